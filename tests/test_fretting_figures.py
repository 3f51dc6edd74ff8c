"""Fretting figures (engine.analysis.fretting_figures) on a synthetic results file.

The file is written here in the layout of a fretting study (root ``study_json``, one group per
case with its attributes, ``history/`` and ``fields/cycle_N/loop``), filled with the analytic
Mindlin loops and energies of engine.reference.mindlin, so the figures are tested without
running the solver. Checks, as in tests/test_figures.py: each figure is written, non-blank,
at most MAX_WIDTH_PX wide, without text below MIN_FONT_SIZE; plus the adapter's regime
classification and cumulated energy.
"""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest
from matplotlib import image

from engine.analysis import figures
from engine.analysis.figures import MAX_WIDTH_PX
from engine.analysis.fretting_figures import _regime, cumulated_energy, read_loops
from engine.analysis.results import ResultCase, open_results
from engine.material import MaterialPair
from engine.reference import mindlin
from engine.study.examples import study_toml

RADIUS, MU, ALPHA = 10.0, 0.6, 2e-5  # mm, –, mm³/J
MATERIAL = MaterialPair(210000.0, 0.3, 210000.0, 0.3)
LOADS = (50.0, 100.0, 200.0)
CYCLES = np.array([0, 1, 2, 10, 100, 1000, 10000])
RECORD = (1, 10000)
FIGURES = ["fretting_map.png", "fretting_loops.png", "wear_energy.png"]


def _config(law: str) -> dict:
    return {
        "study": {"name": "synthetic_map", "output": "synthetic.h5"},
        "material": {"E_A": 210000.0, "nu_A": 0.3, "E_B": 210000.0, "nu_B": 0.3},
        "punch": {"shape": "sphere", "radius": RADIUS},
        "mesh": {"n": 32},
        "loading": {"kind": "fretting", "load": 100.0, "steps": 4, "cycles": 10000},
        "wear": {"law": law},
        "sweep": {"mu1": [MU], "alpha": [ALPHA], "loading.load": list(LOADS)},
    }


def _write_case(file, index, load, amplitude):
    group = file.create_group(f"cases/case_{index:03d}")
    energy = float(mindlin.energy_per_cycle(amplitude, load, RADIUS, MATERIAL, MU))
    regime = (
        "gross" if amplitude > mindlin.slip_displacement(load, RADIUS, MATERIAL, MU) else "partial"
    )
    summary = {"q_amplitude": 1.0, "energy_per_cycle": energy, "slip_regime": regime}
    attrs = {"status": "completed", "index": index, "mu1": MU, "mu2": MU, "wear1": 0.0,
             "wear2": 0.0, "beta": 0.0, "summary": json.dumps(summary),
             "loading.load": load, "loading.amplitude": amplitude}  # fmt: skip
    group.attrs.update(attrs)
    cumulated = energy * CYCLES  # mJ (rows from N = 0, as the solver writes them)
    peak_force = float(mindlin.force_amplitude(amplitude, load, RADIUS, MATERIAL, MU))
    history = {"cycle": CYCLES, "energy": np.full(CYCLES.shape, energy),
               "slip_regime": np.full(CYCLES.shape, int(regime == "gross")),
               "wear_volume": ALPHA * cumulated / 1e3,
               "q_amplitude": np.full(CYCLES.shape, peak_force),
               "displacement_amplitude": np.full(CYCLES.shape, amplitude)}  # fmt: skip
    for name, values in history.items():
        group.create_dataset(f"history/{name}", data=values)
    delta, force = mindlin.fretting_loop(
        load, RADIUS, MATERIAL, MU, displacement_amplitude=amplitude, points=9
    )
    rows = np.column_stack([delta, np.zeros_like(delta), force, np.zeros_like(force)])
    for cycle in RECORD:
        group.create_dataset(f"fields/cycle_{cycle}/loop", data=rows * (1 + 0.02 * (cycle > 1)))


@pytest.fixture(scope="module")
def synthetic_results(tmp_path_factory):
    path = tmp_path_factory.mktemp("energy") / "synthetic.h5"
    with h5py.File(path, "w") as file:
        file.attrs["study_json"] = json.dumps(_config("energy"))
        file.attrs["study_name"] = "synthetic_map"
        index = 0
        for load in LOADS:
            slip = mindlin.slip_displacement(load, RADIUS, MATERIAL, MU)
            for factor in (0.2, 0.5, 0.9, 1.5, 3.0):
                _write_case(file, index, load, factor * slip)
                index += 1
    return path


def test_plot_draws_the_fretting_figures(synthetic_results, small_text, tmp_path):
    """`plot` on a fretting file (which sweeps the load) writes the three figures, legibly."""
    out = tmp_path / "figures"
    assert figures.main([str(synthetic_results), "--out", str(out)]) == 0
    assert not small_text, small_text
    assert sorted(path.name for path in out.glob("*.png")) == sorted(FIGURES)
    for name in FIGURES:
        pixels = image.imread(out / name)[..., :3]
        assert min(pixels.shape[:2]) > 200 and pixels.shape[1] <= MAX_WIDTH_PX, name
        assert float(np.std(pixels)) > 0.02, name  # not blank


def test_adapter_reads_loops_and_cumulates_energy(synthetic_results):
    """Loops by cycle from fields/cycle_N/loop; cumulated energy Σ_(j<k) e_j (N_(j+1) − N_j)
    in J (1e-12: rounding), equal to e·(N − N_0) for a constant e."""
    study = open_results(synthetic_results)
    case = study.completed[0]
    assert sorted(read_loops(synthetic_results, case.case_id)) == list(RECORD)
    energy = float(case.history["energy"][0])
    expected = energy * (CYCLES - CYCLES[0]) / 1e3
    assert cumulated_energy(case) == pytest.approx(expected, rel=1e-12)


def test_map_energy_ratio_of_analytic_cases_lies_on_the_master_curve(synthetic_results):
    """The adapter's A = W/(4δ*Q*) and δ*/δ_slip of the synthetic (analytic) cases reproduce
    mindlin.energy_ratio (1e-12: rounding), so the right panel's markers sit on its curve."""
    from engine.analysis.fretting_figures import _computed_energy_ratio

    study = open_results(synthetic_results)
    for case in study.completed:
        load, amplitude = case.settings["loading.load"], case.settings["loading.amplitude"]
        ratio = amplitude / mindlin.slip_displacement(load, RADIUS, MATERIAL, MU)
        expected = float(mindlin.energy_ratio(ratio))
        assert _computed_energy_ratio(case) == pytest.approx(expected, rel=1e-12)


def test_wear_energy_without_coefficient_fits_the_line_through_the_origin():
    """Archard's law (no α): the drawn line is the least-squares fit through the origin,
    V = s E_d with s = Σ E V / Σ E² (here exactly 3e-5 mm³/J, the data's own slope)."""
    import matplotlib.pyplot as plt

    from engine.analysis.fretting_figures import WearSeries, draw_wear_energy

    energy = np.array([0.0, 0.5, 2.0, 8.0])
    series = [WearSeries("P = 1 N", energy, 3e-5 * energy, None, "gross")]
    figure = draw_wear_energy(series, "archard")
    labels = (
        figure.axes[0].get_legend_handles_labels()[1]
        + figure.axes[1].get_legend_handles_labels()[1]
    )
    plt.close(figure)
    assert any("fit through the origin: V = 3e-05 mm³/J" in label for label in labels), labels


def test_regime_mixed_when_the_history_changes():
    def case(history):
        parameters = {"mu1": MU, "mu2": MU, "wear1": 0.0, "wear2": 0.0, "beta": 0.0}
        return ResultCase.from_values("c", parameters, history={"slip_regime": np.array(history)})

    assert _regime(case([0, 0])) == "partial"
    assert _regime(case([1, 1])) == "gross"
    assert _regime(case([1, 0, 0])) == "mixed"


TINY_FRETTING = study_toml(
    "tiny_fretting",
    "tiny_fretting.h5",
    material={"E_A": 210e3, "nu_A": 0.3, "E_B": 210e3, "nu_B": 0.3},
    punch={"shape": "sphere", "radius": 12.7},
    loading={"kind": "fretting", "load": None, "cycles": 4, "record": [1, 4]},
    wear={"law": "energy"},
    sweep={
        "mu1": [0.6],
        "alpha": [5e-6],
        "loading.load": [25.0, 100.0],
        "loading.amplitude": [0.0006, 0.003],
    },
)


def test_plot_reads_a_real_fretting_results_file(tmp_path):
    """End to end on the engine's own file layout: a 16² study of 2 loads × 2 amplitudes
    (partial and gross slip at both loads), computed by `python -m engine`, then plotted; the
    adapter finds the loops of both recorded cycles and the regimes Mindlin predicts."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    repository = Path(__file__).resolve().parents[1]
    (tmp_path / "study.toml").write_text(TINY_FRETTING)
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(repository), env.get("PYTHONPATH")]))
    command = [sys.executable, "-m", "engine", "study.toml", "--no-progress-bar"]
    run = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    results = tmp_path / "tiny_fretting.h5"
    assert figures.main([str(results), "--out", str(tmp_path / "figures")]) == 0
    sweeps = ["sweep_loading.amplitude.png", "sweep_loading.load.png"]  # the swept keys'
    assert sorted(p.name for p in (tmp_path / "figures").glob("*.png")) == sorted(FIGURES + sweeps)
    study = open_results(results)
    for case in study.completed:
        assert sorted(read_loops(results, case.case_id)) == [1, 4]
        load, amplitude = case.settings["loading.load"], case.settings["loading.amplitude"]
        slip = mindlin.slip_displacement(load, 12.7, MATERIAL, 0.6)
        assert _regime(case) == ("gross" if amplitude > slip else "partial"), case.case_id
