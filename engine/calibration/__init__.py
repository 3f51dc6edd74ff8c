"""Calibration of crack-nucleation thresholds: fit study keys (a critical distance, fatigue
limits …) on measured thresholds, then predict the other tests.

A study with ``[search]`` and ``[calibrate]`` sections (:mod:`engine.calibration.spec`) runs
through :func:`engine.run_study` like any study; :mod:`engine.calibration.run` holds the
method, :mod:`engine.calibration.output` the table (:func:`load_calibration`),
:mod:`engine.calibration.report` the text report and the figure. Submodules load on first
use (PEP 562), so that reading a study file stays light.
"""

from importlib import import_module

__all__ = ["CalibrateSpec", "CalibrationInputError", "parse_calibrate", "load_calibration"]

_HOMES = {
    "CalibrateSpec": "spec",
    "CalibrationInputError": "spec",
    "parse_calibrate": "spec",
    "load_calibration": "output",
}


def __getattr__(name: str):
    if name in _HOMES:
        return getattr(import_module(f"{__name__}.{_HOMES[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
