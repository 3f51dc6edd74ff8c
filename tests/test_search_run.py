"""Threshold searches run as a study (``python -m engine STUDY.toml`` with a ``[search]``
section), one rank; the multi-rank runs, kills and resumes are in tests/mpi/test_search_mpi.py.

The validation: the partial/gross-slip transition amplitude of a sphere (R = 10 mm, P = 100 N,
steel on steel, K = 0, μ = 0.5) against Mindlin's closed form δ_slip = 3μP S/(16a)
(engine.reference.mindlin.slip_displacement, 2.1146 µm). Measured (searched to rtol 1e-3, one
fretting cycle, 4 increments per quarter, mesh over ±1.5 a): −1.24 % at n = 16, −0.55 % at
n = 32, −0.41 % at n = 48 — the discrete model's own transition (the last sticking element at
the centre vanishes later than the continuum's stick zone), converging with the mesh; the
search's own error is ≤ rtol. Hence 1 % at n = 32. The cylinder (line contact) against
Cattaneo–Mindlin's δ_slip, which depends on the displacement datum d: see its test.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

import engine
from engine.material import MaterialPair
from engine.reference import mindlin
from engine.reference.line_contact import line_slip_displacement
from engine.study.config import StudyConfigError, parse_study
from engine.study.examples import CYLINDER_ON_STEEL, study_toml

REPO = Path(__file__).resolve().parents[1]
STEEL = {"E_A": 210e3, "nu_A": 0.3, "E_B": 210e3, "nu_B": 0.3}  # MPa, 1 (K = 0)
SPHERE = {"shape": "sphere", "radius": 10.0}  # mm
ONE_CYCLE = {"kind": "fretting", "load": 100.0, "cycles": 1, "record": [1], "steps": 4}
SEARCH = {
    "parameter": "loading.amplitude",
    "low": 1e-3,  # mm: partial slip (about δ_slip / 2)
    "high": 4e-3,  # mm: gross slip (about 2 δ_slip)
    "column": "slip_regime",
    "target": "gross",
    "rtol": 1e-3,
}


def sphere_study(tmp_path: Path, name: str, *, n: int = 16, **sections) -> Path:
    changes = {
        "material": STEEL,
        "punch": SPHERE,
        "mesh": {"n": n},
        "loading": dict(ONE_CYCLE),
        "sweep": {"mu1": [0.5], "wear1": [0.0]},
        "search": dict(SEARCH),
    }
    for section, values in sections.items():
        changes[section] = {**changes.get(section, {}), **values}
    path = tmp_path / f"{name}.toml"
    path.write_text(study_toml(name, str(tmp_path / f"{name}.h5"), changes))
    return path


def run(study: Path, *options: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "engine", str(study), "--no-progress-bar", *options],
        cwd=study.parent,
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.mark.validation
def test_sphere_transition_amplitude_against_mindlin(tmp_path, validation):
    """The search finds the partial/gross boundary within 1 % of Mindlin's δ_slip at n = 32
    (see the module docstring) in 12 cases, where a uniform grid of amplitudes reaching the
    same accuracy (spacing 2 tol over the bracket) needs 715."""
    study = sphere_study(tmp_path, "sphere", n=32)
    result = run(study)
    assert result.returncode == 0, result.stderr
    table = engine.load_thresholds(tmp_path / "sphere.h5")
    row = table.iloc[0]
    slip = float(mindlin.slip_displacement(100.0, 10.0, MaterialPair(**STEEL), 0.5))
    assert row.status == "converged"
    assert abs(row.threshold / slip - 1.0) < 0.01
    assert (row.lower_value, row.upper_value) == ("partial", "gross")
    assert row.upper - row.lower <= 2 * 1e-3 * row.threshold  # the search's tolerance
    tolerance = 1e-3 * row.threshold
    grid_cases = math.ceil((SEARCH["high"] - SEARCH["low"]) / (2 * tolerance)) + 1
    print(f"threshold {row.threshold * 1e3:.5f} µm vs δ_slip {slip * 1e3:.5f} µm: ")
    print(f"{row.steps} cases; a uniform grid of the same accuracy: {grid_cases}")
    assert row.steps == 12 and grid_cases > 50 * row.steps
    validation.record(
        "threshold search, sphere (R = 10 mm, P = 100 N, μ = 0.5, K = 0), 32², rtol 1e-3: the "
        "partial/gross-slip amplitude vs Mindlin's δ_slip",
        "1 % (the discrete model's own transition at 32²; the search's error ≤ rtol)",
        f"{row.threshold / slip - 1.0:+.2%}; {row.steps} cases (a uniform grid of the same "
        f"accuracy: {grid_cases})",
    )


@pytest.mark.validation
def test_cylinder_transition_amplitude_against_cattaneo_mindlin(tmp_path, validation):
    """A steel cylinder on a steel flat (R = 6 mm, P = 185 N/mm, a = 0.113 mm, μ = 0.5, line
    contact): the searched partial/gross boundary against the closed form
    δ_slip = (μ p0 a/E*)(ln(2d/a) + 1/2)
    (engine.reference.line_contact.line_slip_displacement), for two displacement
    datums d = 1 and 10 mm (one search each, swept): 1.81 and 3.04 µm. Measured (rtol 1e-3,
    one cycle, 4 increments per quarter, ±0.25 mm): −0.13 % at n = 32, −0.09 % and +0.02 % at
    n = 64, +0.02 % at n = 128; hence 0.5 % at n = 64. Each search takes 12 or 13 cases where
    a uniform grid of amplitudes reaching the same accuracy needs more than 700."""
    datums = [1.0, 10.0]  # mm
    changes = {
        **CYLINDER_ON_STEEL,
        "loading": {**ONE_CYCLE, "load": 185.0},
        "sweep": {"mu1": [0.5], "wear1": [0.0], "mesh.reference_distance": datums},
        "search": {**SEARCH, "low": 1.5e-3, "high": 6e-3},
    }
    study = tmp_path / "cylinder.toml"
    study.write_text(study_toml("cylinder", str(tmp_path / "cylinder.h5"), changes))
    result = run(study)
    assert result.returncode == 0, result.stderr
    table = engine.load_thresholds(tmp_path / "cylinder.h5")
    modulus = 1.0 / (2.0 * (1.0 - 0.3**2) / 200e3)  # MPa, E* of steel on steel
    for datum, row in zip(datums, table.itertuples(), strict=True):
        slip = line_slip_displacement(185.0, 6.0, modulus, 0.5, datum)
        assert row.status == "converged"
        assert abs(row.threshold / slip - 1.0) < 5e-3, (datum, row.threshold, slip)
        assert (row.lower_value, row.upper_value) == ("partial", "gross")
        tolerance = SEARCH["rtol"] * row.threshold
        grid_cases = math.ceil((6e-3 - 1.5e-3) / (2 * tolerance)) + 1
        print(f"d = {datum} mm: {row.threshold * 1e3:.5f} µm vs {slip * 1e3:.5f} µm, ")
        print(f"{row.steps} cases; a uniform grid of the same accuracy: {grid_cases}")
        assert row.steps <= 13 and grid_cases > 50 * row.steps
    assert table["mesh.reference_distance"].tolist() == datums
    for datum, row in zip(datums, table.itertuples(), strict=True):
        slip = line_slip_displacement(185.0, 6.0, modulus, 0.5, datum)
        grid_cases = math.ceil((6e-3 - 1.5e-3) / (2 * SEARCH["rtol"] * row.threshold)) + 1
        validation.record(
            f"threshold search, cylinder (R = 6 mm, P = 185 N/mm, μ = 0.5), 64 elements, datum "
            f"d = {datum:g} mm, rtol 1e-3: the partial/gross-slip amplitude vs "
            "Cattaneo–Mindlin's δ_slip",
            "0.5 % (the discrete transition at 64 elements; the search's error ≤ rtol)",
            f"{row.threshold / slip - 1.0:+.2%}; {row.steps} cases (a uniform grid of the "
            f"same accuracy: {grid_cases})",
        )


def test_a_search_study_stores_every_step_and_the_thresholds_table(tmp_path):
    """Two loads: two searches. Every step is a case of the file and the summary (canonical
    order, index = position); the thresholds table is in the file and in
    NAME_thresholds.csv with units, both read by engine.load_thresholds; the boundary grows
    with the load (δ_slip ∝ P^(2/3))."""
    study = sphere_study(
        tmp_path,
        "loads",
        loading={"load": None},
        sweep={"loading.load": [50.0, 100.0]},
        search={"rtol": 1e-2},
    )
    result = run(study)
    assert result.returncode == 0, result.stderr
    assert "2 of 2 searches converged" in result.stdout
    counters = re.findall(r"^\[(\d+)/(\d+)\] ", result.stdout, flags=re.MULTILINE)
    assert {total for _, total in counters} == {"2"}  # [k/N] counts the two searches
    assert [int(k) for k, _ in counters] == sorted(int(k) for k, _ in counters)
    assert counters[-1] == ("2", "2") and len(counters) > 2  # several steps each
    assert "2/2 searches ended" in result.stderr
    from_h5 = engine.load_thresholds(tmp_path / "loads.h5")
    from_csv = engine.load_thresholds(tmp_path / "loads_thresholds.csv")
    assert list(from_h5.columns) == list(from_csv.columns)
    assert from_h5["threshold"].tolist() == from_csv["threshold"].tolist()  # repr round trip
    assert from_h5.attrs["units"] == from_csv.attrs["units"]
    units = from_h5.attrs["units"]
    assert units["threshold"] == units["lower"] == "mm" and units["loading.load"] == "N"
    assert from_h5.attrs["search"]["column"] == "slip_regime"
    assert list(from_h5["loading.load"]) == [50.0, 100.0]
    ratio = from_h5["threshold"][1] / from_h5["threshold"][0]
    assert ratio == pytest.approx(2.0 ** (2.0 / 3.0), rel=0.03)  # two searches' tolerances
    summary = engine.load_summary(tmp_path / "loads.h5")
    assert len(summary) == from_h5["steps"].sum()
    assert (summary.status == "completed").all()
    with h5py.File(tmp_path / "loads.h5", "r") as file:
        indices = {name: int(group.attrs["index"]) for name, group in file["cases"].items()}
        assert file["thresholds/threshold"].attrs["units"] == "mm"
    assert [indices[case_id] for case_id in summary.case_id] == list(range(len(summary)))
    first = summary.case_id.tolist()[:2]
    assert first == ["mu0.5_w0_b0_load50_amplitude0.001", "mu0.5_w0_b0_load50_amplitude0.004"]
    again = run(study)  # a rerun of a finished search study computes nothing
    assert again.returncode == 0 and "0 to run" in again.stdout
    assert "no longer in the study" not in again.stdout + again.stderr  # steps are not stale
    assert "sweep was extended" not in again.stdout + again.stderr


def test_mpio_is_refused_for_a_search_study(tmp_path):
    study = sphere_study(tmp_path, "mpio")
    result = run(study, "--output-strategy", "mpio")
    assert result.returncode == 2
    assert "output_strategy" in result.stderr and "single" in result.stderr
    assert not (tmp_path / "mpio.h5").exists()


def _parse(**search) -> None:
    text = study_toml(
        "bad",
        "bad.h5",
        {"material": STEEL, "punch": SPHERE, "loading": dict(ONE_CYCLE)},
        sweep={"mu1": [0.5], "wear1": [0.0]},
        search={**SEARCH, **search},
    )
    parse_study(text)


@pytest.mark.parametrize(
    "search, key",
    [
        ({"parameter": "mesh.n"}, "search.parameter"),
        ({"parameter": "loading.nothing"}, "search.parameter"),
        ({"target": 1.0}, "search.target"),
        ({"column": "q_amplitude", "target": "gross"}, "search.target"),
        ({"column": "nothing"}, "search.column"),
        ({"low": 4e-3}, "search.high"),
        ({"rtol": 0.0}, "search.rtol"),
        ({"speed": 1}, "search.speed"),
        ({"low": -1e-3}, "search.low"),
    ],
)
def test_bad_search_sections_name_the_key(search, key):
    with pytest.raises(StudyConfigError) as error:
        _parse(**search)
    assert error.value.key == key


def test_the_searched_parameter_is_neither_swept_nor_set():
    with pytest.raises(StudyConfigError, match="search it or sweep it"):
        parse_study(
            study_toml(
                "bad",
                "bad.h5",
                {"material": STEEL, "punch": SPHERE, "loading": dict(ONE_CYCLE)},
                sweep={"mu1": [0.5], "wear1": [0.0], "loading.amplitude": [1e-3, 2e-3]},
                search=SEARCH,
            )
        )
    with pytest.raises(StudyConfigError, match="set by \\[search\\]"):
        parse_study(
            study_toml(
                "bad",
                "bad.h5",
                {"material": STEEL, "punch": SPHERE},
                loading={**ONE_CYCLE, "amplitude": 1e-3},
                sweep={"mu1": [0.5], "wear1": [0.0]},
                search=SEARCH,
            )
        )


def test_plot_draws_one_boundary_curve_per_friction_with_every_step(tmp_path, small_text):
    """μ ∈ {0.3, 0.5} × P ∈ {50, 100} N: four searches. The boundary figure has one curve per
    μ (the friction list tells the curves apart, not only the dotted keys), each against the
    load in increasing order through its thresholds, with the bracket as error bars, and a
    point for every step the searches computed; the curves grow with μ and with the load
    (δ_slip ∝ μ P^(2/3)); `python -m engine plot` writes it, no text too small or cut."""
    from engine.analysis import figures
    from engine.analysis.threshold_figures import draw_thresholds

    study = sphere_study(
        tmp_path,
        "curves",
        loading={"load": None},
        sweep={"mu1": [0.3, 0.5], "loading.load": [50.0, 100.0]},
        search={"rtol": 5e-2, "low": 5e-4},  # mm: δ_slip(μ = 0.3, 50 N) = 0.8 µm
    )
    result = run(study)
    assert result.returncode == 0, result.stderr
    path = tmp_path / "curves.h5"
    table = engine.load_thresholds(path)
    figure = draw_thresholds(path)
    axis = figure.axes[0]
    legend = [text.get_text() for text in axis.get_legend().get_texts()]
    assert legend == ["mu1 = 0.3", "mu1 = 0.5"]
    assert (table["status"] == "converged").all()
    curves = [line for line in axis.get_lines() if line.get_linestyle() == "-"]
    assert len(curves) == 2
    for mu, curve in zip((0.3, 0.5), curves, strict=True):
        rows = table[table.mu1 == mu].sort_values("loading.load")
        assert list(curve.get_xdata()) == [50.0, 100.0]
        assert list(curve.get_ydata()) == rows["threshold"].tolist()
    assert curves[0].get_ydata()[1] > curves[0].get_ydata()[0]  # with the load
    assert all(curves[1].get_ydata() > curves[0].get_ydata())  # with μ
    points = [line for line in axis.get_lines() if line.get_marker() in ("o", "x")]
    assert sum(len(line.get_xdata()) for line in points) == table["steps"].sum()
    assert figure.axes[0].get_xlabel() == "normal load P (N)"
    assert figure.axes[0].get_ylabel() == "displacement amplitude δ* (mm)"
    figures.plt.close(figure)
    assert figures.main([str(path), "--out", str(tmp_path / "figures")]) == 0
    assert (tmp_path / "figures" / "thresholds.png").exists()
    step = engine.load_summary(path).case_id.iloc[0]  # --case: the figures of one step
    assert figures.main([str(path), "--case", step, "--out", str(tmp_path / "step")]) == 0
    assert "fretting_loops.png" in {p.name for p in (tmp_path / "step").iterdir()}
    assert not small_text, small_text
