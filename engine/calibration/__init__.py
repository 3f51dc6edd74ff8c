"""Calibration of crack-nucleation thresholds: fit study keys (a critical distance, fatigue
limits …) on measured thresholds, then predict the other tests.

A study with ``[search]`` and ``[calibrate]`` sections (:mod:`engine.calibration.spec`) runs
through :func:`engine.run_study` like any study; :mod:`engine.calibration.run` holds the
method, :mod:`engine.calibration.output` the table (:func:`load_calibration`),
:mod:`engine.calibration.report` the text report and the figure.
"""

from .output import load_calibration
from .spec import CalibrateSpec, CalibrationInputError, parse_calibrate

__all__ = ["CalibrateSpec", "CalibrationInputError", "parse_calibrate", "load_calibration"]
