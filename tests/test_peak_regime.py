"""Mini peak-regime study: the real entry point on a 24² mesh, μ = 0.1, the
paper's wear coefficient and ten times it, 10⁵ cycles (coarse: 4 increments per half cycle,
wear per jump 2 % of the approach; ~15 s on one core).

What it shows: with the paper's i = 1.33e-7 1/MPa the σ_VM peak stays at the contact edge on
the surface; with 1.33e-6 the edge is relieved and the peak moves to the axis, at a real
cycle N the summary reports. Also: every history column the peak tracker adds is in the file
with its units and description, and ``python -m engine plot`` draws the regime figures.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from matplotlib import image

from engine import load_summary
from engine.solvers.peak import PEAK_HISTORY_UNITS, REGIONS
from engine.study.examples import study_toml
from tests.test_figures import MIN_BYTES, MIN_PIXEL_STD, _engine

MINI = study_toml(
    "mini_regime",
    "mini_regime.h5",
    mesh={"n": 24, "half_width": 1.89},
    loading={"steps": 4, "cycles": 100000, "record": [100000], "max_wear_fraction": 0.02},
    subsurface={"depth": 1.5, "layers": 12},
    sweep={"mu1": [0.1], "wear1": [1.33e-7, 1.33e-6]},
)


@pytest.fixture(scope="module")
def mini(tmp_path_factory):
    folder = tmp_path_factory.mktemp("mini_regime")
    (folder / "mini.toml").write_text(MINI)
    run = _engine("mini.toml", "--no-progress-bar", cwd=folder)
    assert run.returncode == 0, run.stdout + run.stderr
    return folder, folder / "mini_regime.h5"


def test_region_moves_from_the_edge_to_the_axis_as_wear_grows(mini):
    _, results = mini
    summary = load_summary(results).sort_values("wear1")
    assert list(summary["status"]) == ["completed", "completed"]
    paper, tenfold = summary.iloc[0], summary.iloc[1]
    assert paper["peak_region"] == "edge-surface"
    assert tenfold["peak_region"].startswith("axis")
    assert tenfold["wear_severity"] > paper["wear_severity"]
    # the change is reported at a real cycle N inside the run, never for the paper's case
    assert 0 < tenfold["peak_region_change_cycle"] < 100000
    assert summary["peak_region_change_cycle"].isna().iloc[0]
    # the summary's location columns agree with the region words
    assert abs(tenfold["vm_max_x"]) < 0.5 * tenfold["contact_radius"]
    assert abs(paper["vm_max_x"]) > 0.5 * paper["contact_radius"]


def test_history_columns_are_in_the_file_with_units(mini):
    _, results = mini
    with h5py.File(results, "r") as file:
        for case in file["cases"].values():
            history = case["history"]
            rows = history["cycle"].shape[0]
            for key, units in PEAK_HISTORY_UNITS.items():
                assert history[key].shape == (rows,), key
                assert history[key].attrs["units"] == units, key
                assert history[key].attrs["description"], key
            codes = history["peak_region"][:]
            assert codes.dtype.kind == "i" and set(codes) <= set(range(len(REGIONS)))
            # the planes at the first cycle and at every change of region
            changes = case["peak_changes"]
            assert "cycle_0000000" in changes
            assert changes["cycle_0000000/von_mises"].attrs["units"] == "MPa"
            change_cycles = sorted(int(name.split("_")[1]) for name in changes)
            cycles = history["cycle"][:]
            for cycle in change_cycles[1:]:
                row = int(np.flatnonzero(cycles == cycle)[0])
                assert (codes[row] != codes[row - 1]) or (
                    history["deep_region"][row] != history["deep_region"][row - 1]
                )


def test_plot_draws_the_regime_figures(mini):
    folder, results = mini
    run = _engine("plot", str(results), "--out", "figures", cwd=folder)
    assert run.returncode == 0, run.stdout + run.stderr
    for name in ("peak_regime_map.png", "peak_regime_von_mises_mu0.1.png"):
        path = folder / "figures" / name
        assert path.stat().st_size > MIN_BYTES, name
        pixels = image.imread(path)[..., :3]
        assert float(np.std(pixels)) > MIN_PIXEL_STD, name
