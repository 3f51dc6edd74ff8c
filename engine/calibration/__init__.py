"""Calibration of crack-nucleation thresholds: fit study keys (a critical distance, fatigue
limits …) on measured thresholds, then predict the other tests.

A study with ``[search]`` and ``[calibrate]`` sections runs through :func:`engine.run_study`
like any study. The section and its tests file: :mod:`engine.study.calibrate`; the method:
:mod:`engine.calibration.run` (the outer fit, :mod:`~engine.calibration.fit`, over the
tests' searches, :mod:`~engine.calibration.search`, on kept contact solutions,
:mod:`~engine.calibration.contact`); the table: :mod:`engine.output.calibration`
(``engine.load_calibration``); the report and figure: :mod:`engine.analysis.calibration_report`.
"""
