"""The [fatigue] section and the fatigue analysis of a line fretting case's recorded cycles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine.study.config.reader import Section
from engine.study.config.sections import StudyConfigError
from engine.study.fatigue import (
    FatigueAnalysis,
    fatigue_columns,
    fatigue_sweepable,
    parse_fatigue,
)

TABLE = {
    "criteria": ["crossland", "swt"],
    "sigma_d": 300.0, "tau_d": 200.0,
    "sigma_f": 1000.0, "b": -0.09, "eps_f": 0.6, "c": -0.6,
    "method": "point", "length": 0.02,
}  # fmt: skip


def _parse(**changes):
    table = {**TABLE, **changes}
    return parse_fatigue(
        Section("study.toml", "fatigue", {k: v for k, v in table.items() if v is not None})
    )


def test_section_reads_criteria_constants_and_method():
    config = _parse()
    assert config.criteria == ("crossland", "swt")
    assert config.constants["sigma_f"] == 1000.0 and config.length == 0.02
    assert fatigue_columns(config) == [
        "crossland_risk", "crossland_risk_x", "crossland_risk_z", "crossland_risk_critical",
        "swt", "swt_x", "swt_z", "swt_angle", "swt_critical", "swt_life",
    ]  # fmt: skip
    assert fatigue_sweepable()["fatigue.sigma_d"] == "MPa"
    assert fatigue_sweepable()["fatigue.length"] == "mm"


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"tau_d": None}, r"\[fatigue\] tau_d: required key is missing"),
        ({"k": 0.5}, r"\[fatigue\] k = 0.5: unknown key"),
        ({"length": None}, r"\[fatigue\] length: required key is missing"),
        ({"criteria": ["goodman"]}, r"unknown criterion 'goodman'"),
        ({"b": 0.1}, r"\[fatigue\] b = 0.1: .*must be < 0"),
        ({"method": "volume"}, r"\[fatigue\] method = 'volume': must be one of"),
        ({"plane_step": 7.0}, r"\[fatigue\] plane_step = 7.0: must divide 180"),
    ],
)
def test_section_errors_name_the_key_and_value(changes, message):
    with pytest.raises(StudyConfigError, match=message):
        _parse(**changes)


def test_analysis_of_a_line_fretting_case_records_each_recorded_cycle():
    """A 64-element cylinder fretting case (2 increments per quarter) with wear, recorded at
    cycles 1 and 3: the analysis evaluates exactly those cycles (their increments through
    the case's increment probe), on the case's plane, with finite hot spots at the contact
    edge region, a point-method value below the surface hot spot and lives for SWT."""
    from engine.geometry import CylinderProfile
    from engine.grid import Grid
    from engine.kernels.line import line_operator
    from engine.material import MaterialPair
    from engine.solvers.contact import ContactSolver
    from engine.solvers.fretting import FrettingAnalysis, FrettingSettings
    from engine.solvers.friction import FrictionLaw, WearLaw
    from engine.solvers.line_subsurface import LineSubsurfaceStress

    pair = MaterialPair(2e5, 0.3, 2e5, 0.3)
    grid = Grid.line(64, 0.2)
    solver = ContactSolver(
        grid, pair, CylinderProfile(6.0), FrictionLaw(0.6, 0.6),
        operator=line_operator(grid, pair, 10.0), tol=1e-8,
    )  # fmt: skip
    settings = FrettingSettings(
        load=185.0, steps=2, cycles=3, force_amplitude=0.5 * 0.6 * 185.0, record=(1, 3),
        bulk_stress_max=80.0, bulk_stress_min=-80.0,
    )  # fmt: skip
    stress = LineSubsurfaceStress(grid, 0.3, np.array([0.002, 0.01, 0.03]))
    analysis = FatigueAnalysis(_parse(), stress, grid, 2e5, 0.3)

    def probe(pressure, traction_x, traction_y):
        analysis.increment_probe(pressure, traction_x, traction_y)
        return (0.0,)

    fretting = FrettingAnalysis(solver, WearLaw(1e-8, 1e-8), settings, increment_probe=probe)
    fretting.bulk_stress_listener = analysis.set_bulk_stress
    result = fretting.run(on_cycle=analysis.on_cycle)
    assert result.converged, result.message
    assert [c.cycle for c in analysis.cycles] == [1, 3]
    row = analysis.summary_row()
    assert set(row) == set(fatigue_columns(analysis.config))
    half_width = 0.5 * np.count_nonzero(result.final.pressure > 0) * grid.dx
    assert abs(abs(row["crossland_risk_x"]) - half_width) <= 3 * grid.dx
    assert row["crossland_risk_critical"] < row["crossland_risk"]
    assert math.isfinite(row["swt_life"]) and row["swt_life"] > 0
    history = analysis.history()
    assert history["cycle"].tolist() == [1.0, 3.0]
    assert analysis.cycles[-1].assessments[0].map.shape == (64, 3)
