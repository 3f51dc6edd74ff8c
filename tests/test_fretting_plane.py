"""The subsurface plane of a fretting case contains its sliding direction.

A 16² steel sphere on steel (K = 0, isotropic μ = 0.5, Archard wear, 4 cycles, partial slip)
is run through engine.cli.main with ``direction = 0°`` and ``90°`` (~0.5 s). On the square
grid the 90° case is the 0° case turned by a quarter turn, so its σ_VM peaks on the plane at
90° must equal those on the x–z plane to round-off (measured 1e-15 relative; tolerance 1e-12)
with x and y swapped; the 90° datasets carry ``plane_angle`` = 90 and say so, the 0° ones are
unchanged (no attribute: x–z results stay bit-identical, checked with
scripts/compare_results.py on the 0° studies before and after).
"""

from __future__ import annotations

import h5py
import pandas as pd
import pytest

from engine.analysis.results import open_results
from engine.cli import main
from engine.study.examples import SPHERE_ON_STEEL, study_toml

STEEL = {"E_A": 210e3, "nu_A": 0.3, "E_B": 210e3, "nu_B": 0.3}  # MPa, 1


def study(direction: int, output) -> str:
    """A 16² sphere (R = 10 mm, P = 100 N) fretted 1.5 µm along ``direction``, 4 cycles."""
    return study_toml(
        f"plane{direction}",
        str(output),
        SPHERE_ON_STEEL,
        material=STEEL,
        loading={
            "kind": "fretting",
            "cycles": 4,
            "record": [1, 4],
            "amplitude": 0.0015,
            "direction": float(direction),
        },
        sweep={"mu1": [0.5], "wear1": [1e-6]},
    )


PEAKS = ["vm_max", "vm_sub_max", "vm_deep_max", "vm_axis_max", "vm_cycle_max"]
ROUND_OFF = 1e-12  # relative (values) and mm (locations): the turned problem is the same one


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plane")
    paths = {}
    for direction in (0, 90):
        output = folder / f"plane{direction}.h5"
        text = study(direction, output)
        (folder / f"plane{direction}.toml").write_text(text)
        assert main([str(folder / f"plane{direction}.toml"), "--no-progress-bar"]) == 0
        paths[direction] = output
    return paths


def _row(path) -> pd.Series:
    return pd.read_csv(path.with_suffix(".csv")).iloc[0]


def test_peaks_at_90_degrees_equal_the_turned_peaks_at_0(studies):
    along_x, along_y = _row(studies[0]), _row(studies[90])
    for name in PEAKS:
        assert along_y[name] == pytest.approx(along_x[name], rel=ROUND_OFF), name
    for name in ("vm_max", "vm_sub_max", "vm_cycle_max"):
        assert along_y[f"{name}_y"] == pytest.approx(along_x[f"{name}_x"], abs=ROUND_OFF), name
        assert abs(along_y[f"{name}_x"]) < ROUND_OFF and along_x[f"{name}_y"] == 0.0, name
        assert along_y[f"{name}_z"] == along_x[f"{name}_z"], name
    assert along_y["vm_deep_max_y"] == pytest.approx(along_x["vm_deep_max_x"], abs=ROUND_OFF)
    assert "vm_deep_max_y" not in along_x  # the x–z summary keeps its columns
    assert along_y["peak_region"] == along_x["peak_region"]  # regions from |s|, not |x|
    assert along_y["deep_region"] == along_x["deep_region"]


def test_the_plane_angle_is_recorded(studies):
    with h5py.File(studies[90]) as file:
        (case,) = file["cases"].values()
        for path in ("subsurface/final/von_mises", "subsurface/cycle_0000004/x",
                     "history/vm_max", "fields/cycle_0000004/vm_cycle"):  # fmt: skip
            assert case[path].attrs["plane_angle"] == 90.0, path
            assert "90° from x (the sliding direction)" in case[path].attrs["description"], path
        assert "history/vm_max_y" in case
    with h5py.File(studies[0]) as file:
        (case,) = file["cases"].values()
        assert "plane_angle" not in case["subsurface/final/von_mises"].attrs
        assert "history/vm_max_y" not in case


def test_reader_measures_along_the_plane(studies):
    """engine.analysis.results: the 90° plane's peak at s = the 0° peak's x (the report's r)."""
    planes = {d: open_results(path).completed[0].planes[4] for d, path in studies.items()}
    assert planes[90].angle == 90.0 and planes[0].angle == 0.0
    value, s, z = planes[90].peak()
    assert (value, s, z) == pytest.approx(planes[0].peak(), rel=ROUND_OFF, abs=ROUND_OFF)
    assert planes[90].peak_point()[2] == pytest.approx(s, abs=ROUND_OFF)  # y = s at 90°


def test_a_rank_builds_the_kernels_of_the_plane_its_cases_evaluate():
    # The per-rank cache builds, as set-up, the kernels of the plane a case evaluates (the
    # sliding direction of a fretting case), not those of an x–z plane nobody asks for.
    import math

    import numpy as np

    from engine.grid import Grid
    from engine.kernels.lattice import LatticeConvolution, LineConvolution
    from engine.study.operators import OperatorCache

    cache, grid, depths = OperatorCache(), Grid.square(16, 1.0), np.array([0.1, 0.3])
    options = dict(threads=1, planner_effort="FFTW_ESTIMATE")
    stress = cache.stress(grid, 0.3, depths, angle=math.radians(30.0), **options)
    (oblique,) = stress._lattices.values()
    assert isinstance(oblique, LatticeConvolution) and oblique.cache_bytes > 0
    built = cache.setup_s
    assert cache.stress(grid, 0.3, depths, angle=math.radians(30.0), **options) is stress
    assert cache.setup_s == built  # nothing built again
    assert cache.stress(grid, 0.3, depths, angle=0.0, **options) is stress
    assert len(stress._lattices) == 2 and cache.setup_s > built
    assert any(isinstance(lattice, LineConvolution) for lattice in stress._lattices.values())
