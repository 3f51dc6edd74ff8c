"""The peak regions of worn states of the regime study are not decided by the surface layer.

Two peak-load states of ``studies/peak_regime_32.toml`` (μ = 0.1, N = 10⁵; saved by
``scripts/peak_regime_states.py fixture`` in tests/data/peak_regime_32_worn.npz):
i = 1.33e-6 1/MPa (ω_max/δ0 = 0.52) and the heavy-wear state i = 1.33e-5 1/MPa (ω_max/δ0 = 2.70).

On the x–z plane (element corners of the even mesh) the surface layer's σ_VM on the axis is
the logarithmic singularity of the traction jump there: moving the surface layer 100 × closer
to the surface raises it by a third (worn) and four fifths (heavy). The regions are taken at
element centres, where that value converges: they must not move with the surface layer, and
they must agree with the largest σ_VM over the whole block of element centres (all elements,
not only those beside the plane). About 2 s.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from engine.grid import Grid
from engine.solvers import peak as peak_module
from engine.solvers.peak import ROWS_TOLERANCE, PeakTracker, classify_peak, region_name
from engine.solvers.subsurface import SubsurfaceStress, depth_layers

STATES = np.load(Path(__file__).parent / "data" / "peak_regime_32_worn.npz")
RADIUS, LOAD = 1.8, 750.0  # mm, N (studies/peak_regime_32.toml)
P0 = LOAD / (math.pi * RADIUS**2)  # MPa, Eq. (19)
GRID = Grid.square(32, 1.89)


@pytest.fixture(scope="module")
def trackers() -> tuple[PeakTracker, PeakTracker]:
    """The study's 31 graded layers to 1.5 a0, the surface layer at 1 % (as the study) and
    0.01 % of the first regular depth; one module-wide pair, so the kernels are built once."""
    return tuple(
        PeakTracker(SubsurfaceStress(GRID, 0.3, depth_layers(1.5 * RADIUS, 31, **f)), RADIUS)
        for f in ({"surface_fraction": 0.01}, {"surface_fraction": 1e-4})
    )


def _state(name: str):
    return [STATES[f"{name}_{key}"] for key in ("pressure", "traction_x", "traction_y")]


@pytest.mark.parametrize(
    ("name", "severity", "artefact_growth"),
    [("worn", 0.522, 1.3), ("heavy", 2.704, 1.8)],
)
def test_regions_do_not_follow_the_surface_layer_artefact(
    trackers, name, severity, artefact_growth
):
    state = _state(name)
    assert STATES[f"{name}_max_wear_depth"] / STATES[f"{name}_elastic_approach"] == (
        pytest.approx(severity, abs=5e-4)
    )
    usual, closer = trackers
    rows = [usual(*state), closer(*state)]
    # the artefact: the plane's maximum sits on the axis in the surface layer and grows as
    # the layer approaches z = 0 (log singularity; the real stress converges)
    for row in rows:
        assert row["vm_max_x"] == 0.0 and row["vm_max_z"] < 1e-3 * RADIUS
    assert rows[1]["vm_max"] > artefact_growth * rows[0]["vm_max"]
    # the regions do not move with it
    assert rows[0]["peak_region"] == rows[1]["peak_region"]
    assert rows[0]["deep_region"] == rows[1]["deep_region"]
    # and agree with the largest σ_VM over every element centre and depth (exact DC-FFT)
    block = usual.stress.block(*state)
    index = np.unravel_index(np.argmax(block.von_mises), block.von_mises.shape)
    radius = rows[0]["contact_radius"]
    where = classify_peak(math.hypot(block.x[index], block.y[index]), block.z[index], radius)
    assert region_name(rows[0]["peak_region"]) == where
    deep = np.where(block.z >= 0.1 * RADIUS, block.von_mises, -np.inf)
    index = np.unravel_index(np.argmax(deep), deep.shape)
    where = classify_peak(math.hypot(block.x[index], block.y[index]), block.z[index], radius)
    assert region_name(rows[0]["deep_region"]) == where
    # the element-centre maximum is well below the plane's surface value (the artefact)
    assert np.max(block.von_mises) < 0.6 * rows[0]["vm_max"]


@pytest.mark.parametrize("name", ["worn", "heavy"])
def test_rows_beside_the_axis_by_lines_equal_the_lattice_to_rounding(trackers, name):
    # The two rows of element centres beside the x–z plane, by 1-D transforms of a shifted,
    # padded grid and its mirror image, against the 2-D lattice of those rows: the same
    # points to the bit and the same exact DC-FFT sums in another order, so equal to
    # rounding: 1e-12 of the largest component (measured 1e-15), far inside the bound
    # ROWS_TOLERANCE = 1e-8 on which the regions rely.
    tracker = trackers[0]
    state = _state(name)
    rows = tracker.stress.rows_beside_axis(*state)
    block = tracker.stress.block(*state, window=tracker._centres[0])
    for coordinate in ("x", "y", "z"):
        assert np.array_equal(getattr(rows, coordinate), getattr(block, coordinate))
    largest = max(np.max(np.abs(values)) for values in block.components.values())
    for component, values in block.components.items():
        difference = np.max(np.abs(rows.components[component] - values))
        assert difference <= 1e-12 * largest, component
    assert 1e-12 < ROWS_TOLERANCE


@pytest.mark.parametrize("name", ["worn", "heavy"])
@pytest.mark.parametrize("tolerance", [ROWS_TOLERANCE, 1.0])
def test_regions_by_lines_are_those_of_the_lattice(trackers, monkeypatch, name, tolerance):
    # The words taken from the rows by lines are those of the lattice's own maxima; with a
    # bound so wide that points of other words come near the maximum (tolerance 1), the
    # lattice decides instead, with the same words.
    tracker = trackers[0]
    state = _state(name)
    radius = tracker.contact_radius(state[0])
    window, band = tracker._centres
    block = tracker.stress.block(*state, window=window)
    expected = tracker._words(block, np.broadcast_to(band[..., None], block.z.shape), radius)
    monkeypatch.setattr(peak_module, "ROWS_TOLERANCE", tolerance)
    lattices = []
    original = tracker.stress.block
    monkeypatch.setattr(
        tracker.stress, "block", lambda *a, **k: lattices.append(1) or original(*a, **k)
    )
    assert tracker.regions(*state, radius) == expected
    assert len(lattices) == (0 if tolerance == ROWS_TOLERANCE else 1)
