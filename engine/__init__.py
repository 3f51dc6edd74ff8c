"""Fretting-wear contact simulation: FFT boundary elements, cyclic wear, subsurface stress.

Units throughout: mm, N, MPa (= N/mm²); wear coefficients in 1/MPa; angles in degrees at
the user-facing layer and radians inside the numerical code.

The public API:

- :func:`run_study` runs (or resumes) a study file, TOML text or configuration, on this process
  or on the ranks of a communicator, and returns a :class:`StudyRun` (an invalid study raises
  :class:`StudyError` with the file, the key and the value);
- :func:`open_results` opens a results file as objects: the study, the summary, each
  case's histories, fields and stress planes with units (``.to_xarray()`` with xarray);
- :func:`load_summary` reads a study's summary table as a pandas DataFrame;
- :func:`load_thresholds` reads the thresholds table of a study with a ``[search]`` section;
- :func:`load_calibration` reads the calibration table of a study with a ``[calibrate]``
  section (measured and predicted thresholds, the fitted values);
- :func:`load_ensemble` gives the statistics over the realisations of a rough-surface study.

``import engine`` stays light: NumPy, h5py, mpi4py and pandas load when a function needs them.
"""

import importlib as _importlib
import sys as _sys

from engine._version import __version__

if _sys.orig_argv[1:3] == ["-m", "engine"]:  # `python -m engine`: stop signals caught first
    from engine import _early_stop  # noqa: F401

__all__ = [
    "__version__",
    "RUN_STATUSES",
    "StudyError",
    "StudyRun",
    "WrongFileError",
    "run_study",
    "open_results",
    "load_summary",
    "load_thresholds",
    "load_calibration",
    "load_ensemble",
]

#: Where each public name lives: imported on first use (PEP 562), so that ``import engine``
#: loads none of the layers a script does not use.
_PUBLIC = {
    "RUN_STATUSES": "engine.run_outcome",
    "StudyRun": "engine.run_outcome",
    "StudyError": "engine.run_outcome",
    "WrongFileError": "engine.commands",
    "run_study": "engine.run",
    "open_results": "engine.analysis.results",
    "load_summary": "engine.output.summary",
    "load_thresholds": "engine.output.thresholds",
    "load_calibration": "engine.output.calibration",
    "load_ensemble": "engine.output.ensemble",
}


def __getattr__(name: str):
    """The public name ``name`` from its module (:data:`_PUBLIC`), imported on first use."""
    if name not in _PUBLIC:
        raise AttributeError(f"module 'engine' has no attribute {name!r}")
    value = getattr(_importlib.import_module(_PUBLIC[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))
