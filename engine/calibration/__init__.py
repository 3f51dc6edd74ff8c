"""Calibration of crack-nucleation thresholds: fit study keys (a critical distance, fatigue
limits …) on measured thresholds, then predict the other tests.

A study with ``[search]`` and ``[calibrate]`` sections runs through :func:`engine.run_study`
like any study. The section and its tests file: :mod:`engine.study.calibrate`; the method:
:mod:`engine.calibration.run` (the outer fit, :mod:`~engine.calibration.fit`, over the
tests' searches, :mod:`~engine.calibration.search`, on kept contact solutions,
:mod:`~engine.calibration.contact`); the table: :mod:`engine.output.calibration`
(``engine.load_calibration``); the report and figure: :mod:`engine.analysis.calibration_report`.
"""

import importlib as _importlib

__all__ = ["calibrate"]


def __getattr__(name: str):
    """``calibrate`` (:func:`engine.calibration.run.calibrate`), imported on first use
    (PEP 562): a study without ``[calibrate]`` loads none of the calibration modules."""
    if name == "calibrate":
        return _importlib.import_module("engine.calibration.run").calibrate
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
