"""The [fatigue] section and the fatigue analysis of a line fretting case's recorded cycles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine.schema import FATIGUE_HOT_SPOT_COLUMNS
from engine.study.fatigue import (
    FatigueAnalysis,
    fatigue_columns,
    fatigue_sweepable,
    parse_fatigue,
)
from engine.study.settings.reader import Section
from engine.study.settings.sections import StudyConfigError

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
        ({"k": 0.5}, r"\[fatigue\] k = 0.5: not a constant of the criteria"),
        ({"kappa": 0.5}, r"\[fatigue\] kappa = 0.5: unknown key"),
        ({"every_cycle": 1}, r"\[fatigue\] every_cycle = 1: must be true or false"),
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
    analysis = FatigueAnalysis(_parse(), stress, grid, 2e5, 0.3, recorded=(1, 3))

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
    assert analysis.cycles[-1].maps["crossland_risk"].shape == (64, 3)


# ------------------------------------------------------------------ the section in a study
def test_the_sweepable_constants_are_the_criteria_constants():
    """SWEEPABLE lists the [fatigue] keys with the units the criteria declare."""
    from engine.study.config import SWEEPABLE

    listed = {key: unit for key, unit in SWEEPABLE.items() if key.startswith("fatigue.")}
    assert listed == fatigue_sweepable()


LINE_STUDY = {
    "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e3, "nu_B": 0.3},
    "punch": {"shape": "cylinder", "radius": 6.0},
    "mesh": {"n": 48, "half_width": 0.2},
    "loading": {
        "kind": "fretting", "load": 185.0, "steps": 2, "cycles": 12, "record": [1, 12],
        "force_amplitude": 55.0, "bulk_stress_max": 100.0, "bulk_stress_min": -100.0,
    },
    "subsurface": {"depth": 1.0, "layers": 5},
    "sweep": {"mu1": [0.6], "wear1": [1e-8]},
    "fatigue": {**{k: v for k, v in TABLE.items()}, "every_cycle": True},
}  # fmt: skip


SWEPT_SIGMA_D = {"sweep": {"fatigue.sigma_d": [300.0, 250.0]}, "fatigue": {"sigma_d": None}}


def _line_config(tmp_path, *layers):
    from engine.study.config import parse_study
    from engine.study.examples import study_toml

    return parse_study(study_toml("fatigue", str(tmp_path / "fatigue.h5"), LINE_STUDY, *layers))


def test_study_sections_errors_name_the_key_and_value(tmp_path):
    """[fatigue] needs the fretting kind; an unused constant and a swept constant no listed
    criterion uses are refused, naming the key and the value."""
    with pytest.raises(StudyConfigError, match=r"\[loading\] kind = 'cyclic': \[fatigue\]"):
        cyclic = {"kind": "cyclic", "force_amplitude": None, "bulk_stress_max": None}
        _line_config(tmp_path, {"loading": {**cyclic, "bulk_stress_min": None}})
    with pytest.raises(StudyConfigError, match=r"\[fatigue\] tau_f = 600.0: not a constant"):
        _line_config(tmp_path, {"fatigue": {"tau_f": 600.0}})
    with pytest.raises(StudyConfigError, match=r"\[sweep\] fatigue.tau_f = 600.0: list position"):
        _line_config(tmp_path, {"sweep": {"fatigue.tau_f": [600.0]}})
    config = _line_config(tmp_path, SWEPT_SIGMA_D)
    assert "sigma_d" not in config.resolved()["fatigue"]  # swept: each case's own value
    assert config.for_case({"fatigue.sigma_d": 250.0}).fatigue.constants["sigma_d"] == 250.0


def _run(config, should_stop=None):
    from engine.study.case import CaseRunner
    from engine.study.plan import make_plan

    runner = CaseRunner(config)
    return [runner(case, should_stop) for case in make_plan(config)]


def test_a_line_fretting_study_stores_maps_hot_spots_and_history(tmp_path):
    """The case's outcome: per recorded cycle each criterion's map on the case's plane (the
    shape of subsurface/*), angles and lives for SWT, the hot spot (the map's maximum and
    where it is, the summary's values at the last recorded cycle); with every_cycle the hot
    spots per simulated cycle in history/ (the last equal to the summary). A sweep of
    sigma_d changes Crossland only."""
    config = _line_config(tmp_path, SWEPT_SIGMA_D)
    outcomes = _run(config)
    assert [o.status for o in outcomes] == ["completed"] * 2, outcomes[0].message
    first, second = outcomes
    data = first.datasets
    for cycle in ("cycle_0000001", "cycle_0000012"):
        plane = data[f"subsurface/{cycle}/z"].data
        for name in ("crossland_risk", "swt", "swt_angle", "swt_life"):
            assert data[f"fatigue/{cycle}/{name}"].data.shape == plane.shape
    risk = data["fatigue/cycle_0000012/crossland_risk"].data
    spot = data["fatigue/cycle_0000012/crossland_risk_hot_spot"].data
    index = np.unravel_index(np.argmax(risk), risk.shape)
    x, z = data["subsurface/cycle_0000012/x"].data, data["subsurface/cycle_0000012/z"].data
    assert spot[0] == risk.max() == first.row["crossland_risk"]
    assert (spot[1], spot[2]) == (x[index], z[index])
    assert spot[5] == first.row["crossland_risk_critical"]
    assert first.row["swt_angle"] == data["fatigue/cycle_0000012/swt_hot_spot"].data[3]
    cycles = data["history/cycle"].data
    assert data["history/swt"].data.shape == cycles.shape and cycles[-1] == 12
    assert data["history/crossland_risk"].data[-1] == first.row["crossland_risk"]
    assert first.row["crossland_risk"] < second.row["crossland_risk"]  # σ_d 300 → 250 MPa
    assert first.row["swt"] == second.row["swt"]


def test_an_interrupted_case_resumes_to_the_same_fatigue_results(tmp_path):
    """Stopped after the first recorded cycle and resumed from its checkpoint, a case gives
    the same fatigue datasets and columns, bit for bit, as a run without a stop."""
    config = _line_config(tmp_path)
    (whole,) = _run(config)
    calls = iter(range(100))
    (stopped,) = _run(config, lambda: next(calls) >= 3)
    assert stopped.status == "interrupted"
    (resumed,) = _run(config)
    assert resumed.status == "completed"
    names = [n for n in whole.datasets if n.startswith(("fatigue/", "history/"))]
    assert names and sorted(names) == sorted(
        n for n in resumed.datasets if n.startswith(("fatigue/", "history/"))
    )
    for name in names:
        same = np.array_equal(
            whole.datasets[name].data, resumed.datasets[name].data, equal_nan=True
        )
        assert same, name
    for column in fatigue_columns(config.fatigue):
        assert whole.row[column] == resumed.row[column], column


def test_a_sphere_fretting_case_evaluates_its_sliding_plane(tmp_path):
    """A 3-D case (sphere, 16², force control, sliding at 90°): the criteria on the vertical
    plane through the axis along y, the hot spot on the surface near the contact edge and a
    line-method value (ℓ = 0.05 mm, exact points below the surface hot spot)."""
    from engine.study.config import parse_study
    from engine.study.examples import SPHERE_ON_STEEL, study_toml

    fatigue = {
        "criteria": ["crossland", "fatemi_socie"], "sigma_d": 300.0, "tau_d": 200.0,
        "tau_f": 600.0, "gamma_f": 0.9, "b0": -0.09, "c0": -0.6, "k": 0.6, "sigma_y": 800.0,
        "method": "line", "length": 0.05,
    }  # fmt: skip
    text = study_toml(
        "sphere", str(tmp_path / "sphere.h5"), SPHERE_ON_STEEL,
        loading={"kind": "fretting", "cycles": 2, "record": [2], "force_amplitude": 25.0,
                 "direction": 90.0},
        sweep={"mu1": [0.5], "wear1": [0.0]}, fatigue=fatigue,
    )  # fmt: skip
    (outcome,) = _run(parse_study(text))
    assert outcome.status == "completed", outcome.message
    row = outcome.row
    assert row["crossland_risk_z"] == outcome.datasets["subsurface/final/z"].data.min()
    assert 0.5 * row["contact_radius"] < abs(row["crossland_risk_x"]) < 1.5 * row["contact_radius"]
    assert 0.0 < row["crossland_risk_critical"] < row["crossland_risk"]
    assert math.isfinite(row["fs"]) and 0.0 <= row["fs_angle"] < 180.0
    assert "history/crossland_risk" not in outcome.datasets  # every_cycle is off


def test_report_and_figures_say_whether_and_where_a_crack_is_predicted(tmp_path):
    """Through the results file: the report's fatigue table has a row per case and criterion
    whose verdict follows the stored critical values (Crossland: risk ≥ 1; SWT: the life of
    its critical value within the simulated cycles, recomputed from the constants), and the
    facts name the cracking criteria and the place; ``plot`` draws the maps and the hot-spot
    history besides the fretting figures, and the crack boundary on the fretting map."""
    import engine
    from engine.analysis.fatigue import case_verdicts
    from engine.analysis.figures import plot_study
    from engine.analysis.report import study_report
    from engine.analysis.results import open_results
    from engine.fatigue import Elasticity, SmithWatsonTopper

    config = _line_config(tmp_path, SWEPT_SIGMA_D)
    run = engine.run_study(config, progress=False)
    assert run.status == "completed", run
    study = open_results(tmp_path / "fatigue.h5")
    report = study_report(study)
    swt = SmithWatsonTopper(
        {k: TABLE[k] for k in ("sigma_f", "b", "eps_f", "c")}, Elasticity(2e5, 0.3)
    )
    for case in study.completed:
        verdicts = {v.name: v for v in case_verdicts(study, case)}
        crossland, smith = verdicts["crossland"], verdicts["swt"]
        assert crossland.critical == case.summary["crossland_risk_critical"]
        assert crossland.crack == (case.summary["crossland_risk_critical"] >= 1.0)
        life = float(swt.life(np.array([case.summary["swt_critical"]]))[0])
        assert smith.critical_life == life and smith.crack == (life <= 12)
        assert f"| {case.label} | 12 | crossland |" in report
        if crossland.crack:
            assert f"{case.label}: crack predicted by crossland" in report
    names = [path.name for path in plot_study(study, tmp_path / "figures")]
    assert {"fretting_map.png", "fatigue_maps.png", "fatigue_history.png"} <= set(names)
    # The public reading layer gives the same maps, on the stress plane's dimensions.
    results = engine.open_results(tmp_path / "fatigue.h5")
    for case in study.completed:
        maps = results[case.case_id].fatigue
        assert list(maps) == list(case.fatigue) and maps.cycles
        for cycle, group in maps.items():
            assert list(group) == list(case.fatigue[cycle])
            plane_x = results[case.case_id].planes[cycle]["x"].values
            for name, variable in group.items():
                assert np.array_equal(variable.values, case.fatigue[cycle][name], equal_nan=True)
                if name.endswith("_hot_spot"):
                    columns = list(variable.coords[f"{name}_column"][1])
                    assert columns == list(FATIGUE_HOT_SPOT_COLUMNS)
                else:
                    assert variable.dims == ("s", "depth")
                    assert np.array_equal(variable.coords["x"][1], plane_x)


def test_a_search_finds_the_bulk_stress_at_which_a_crack_is_predicted(tmp_path):
    """``[search]`` on a fatigue column: the bulk stress amplitude at which Crossland at the
    critical distance reaches 1.3 (it grows with the bulk stress); the final bracket holds
    the target between its ends' values, within the relative tolerance."""
    import engine

    config = _line_config(
        tmp_path,
        {"loading": {"bulk_stress_max": None, "bulk_stress_min": -50.0}},
        {"search": {"parameter": "loading.bulk_stress_max", "low": 0.0, "high": 100.0,
                    "column": "crossland_risk_critical", "target": 1.3, "rtol": 0.05}},
    )  # fmt: skip
    run = engine.run_study(config, progress=False)
    assert run.status == "completed", run
    (row,) = engine.load_thresholds(tmp_path / "fatigue.h5").to_dict("records")
    assert row["status"] == "converged", row
    assert row["lower_value"] < 1.3 <= row["upper_value"]
    assert row["upper"] - row["lower"] <= 0.05 * row["upper"]


def test_the_memory_estimate_counts_the_fatigue_analysis():
    """A [fatigue] section adds to a case's memory estimate what it keeps per increment: at
    n = 128, 40 layers, 80 increments 199 MB against 191 MB measured (473 → 664 MB peak,
    2026-11-27; engine.study.resources), within 10 % of the measurement."""
    from engine.study.resources import case_memory_bytes

    added = case_memory_bytes(128, 40, 80, fatigue=True) - case_memory_bytes(128, 40, 80)
    assert abs(added - 191e6) < 0.1 * 191e6
