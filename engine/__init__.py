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

__version__ = "0.1.0"

import sys as _sys  # noqa: E402

if _sys.orig_argv[1:3] == ["-m", "engine"]:  # `python -m engine`: stop signals caught first
    from engine import _early_stop  # noqa: F401

from engine.commands import WrongFileError  # noqa: E402
from engine.run import RUN_STATUSES, StudyError, StudyRun, run_study  # noqa: E402 (needs __version__)

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


def open_results(path):
    """Open a study's results file as objects (:class:`engine.analysis.results.Results`).

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) a study run wrote.

    Returns
    -------
    engine.analysis.results.Results
        A mapping case id → case, in plan order, with ``study`` (the resolved study),
        ``summary`` (a pandas DataFrame); each case with its ``parameters``, ``status``,
        ``summary`` row, ``history``, ``fields`` and ``planes`` (values with units and
        coordinates; ``.to_xarray()`` when xarray is installed).

    Raises
    ------
    OSError
        ``ResultsBeingWritten`` (an ``OSError``, errno EBUSY) while a run writes the file:
        one line naming the run's pid and host; meanwhile ``engine.load_summary`` on the
        summary CSV reads the completed cases. The run is not disturbed.

    Examples
    --------
    >>> results = engine.open_results("results/demo.h5")               # doctest: +SKIP
    >>> case = results["mu0.1_w1.33e-07_b0"]                            # doctest: +SKIP
    >>> case.planes["final"].to_xarray()["von_mises"].max()             # doctest: +SKIP
    """
    from engine.analysis.results import open_results as open_file

    return open_file(path)


def load_summary(path):
    """Summary of a study as a :class:`pandas.DataFrame`, from the results ``.h5`` file or the
    ``.csv`` beside it (``engine.output.summary.load_summary``).

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``; the ``.csv`` beside it is read when the ``.h5`` is gone) or
        the summary ``.csv`` itself.

    Returns
    -------
    pandas.DataFrame
        One row per case, in plan order: the case id, its parameters, its status and the
        summary columns (mm, N, MPa, mm³, s; every column with its unit in
        ``docs/reference/outputs.md``).

    Examples
    --------
    >>> frame = engine.load_summary("results/demo.h5")      # doctest: +SKIP
    >>> frame.pivot(index="mu1", columns="beta", values="max_wear_depth")   # doctest: +SKIP
    """
    from engine.output.summary import load_summary as load

    return load(path)


def load_thresholds(path):
    """Thresholds table of a study with a ``[search]`` section as a :class:`pandas.DataFrame`
    (one row per search), from the results ``.h5`` file or ``NAME_thresholds.csv``; the units
    in ``frame.attrs["units"]`` (``engine.output.thresholds.load_thresholds``).

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) or the ``NAME_thresholds.csv`` beside it.

    Returns
    -------
    pandas.DataFrame
        One row per search: the threshold found, its bracket and the search's settings, with
        the unit of each column in ``frame.attrs["units"]``.

    Examples
    --------
    >>> frame = engine.load_thresholds("results/fretting_threshold.h5")   # doctest: +SKIP
    >>> frame.plot(x="loading.load", y="threshold")                      # doctest: +SKIP
    """
    from engine.output.thresholds import load_thresholds as load

    return load(path)


def load_calibration(path):
    """The calibration table of a study with a ``[calibrate]`` section, as a
    :class:`pandas.DataFrame` (``engine.output.calibration.load_calibration``).

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) or ``NAME_calibration.csv``.

    Returns
    -------
    pandas.DataFrame
        One row per test: its id and keys, ``measured``, ``predicted`` (the searched
        parameter's units), ``error`` (predicted/measured − 1), ``role`` (``calibrate`` or
        ``predict``), the final bracket, ``steps``, ``status``; ``frame.attrs["fitted"]`` the
        fitted values, ``frame.attrs["units"]`` the units, ``frame.attrs["fit_status"]`` how
        the fit ended.

    Examples
    --------
    >>> frame = engine.load_calibration("results/fouvry_crack_nucleation.h5")  # doctest: +SKIP
    >>> frame.attrs["fitted"]["fatigue.length"]                                # doctest: +SKIP
    """
    from engine.output.calibration import load_calibration as load

    return load(path)


def load_ensemble(path):
    """Statistics over the realisations of a study sweeping ``surface.seed`` as a
    :class:`pandas.DataFrame` (``engine.output.ensemble.load_ensemble``), computed from
    the summary (the same table as ``NAME_ensemble.csv``).

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) or its summary ``.csv``.

    Returns
    -------
    pandas.DataFrame
        One row per combination of the other swept keys: ``realisations`` (completed cases)
        and, for every numeric summary column c, ``c_mean``, ``c_std`` and the 95 %
        confidence interval of the mean ``c_ci_low``, ``c_ci_high`` (units: the column's).

    Examples
    --------
    >>> frame = engine.load_ensemble("results/rough_fretting.h5")         # doctest: +SKIP
    >>> frame[["loading.amplitude", "real_area_fraction_mean"]]           # doctest: +SKIP
    """
    from engine.output.ensemble import load_ensemble as load

    return load(path)
