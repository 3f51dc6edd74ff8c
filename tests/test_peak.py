"""Peak history and peak regions: classification, the tracker on synthetic
tractions with analytic references, the history columns of a cyclic run and their checkpoint.

The mini regime study (edge → axis as the wear coefficient grows) runs the real entry point:
tests/test_peak_regime.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.reference.flat_punch import sneddon_pressure
from engine.solvers.contact import ContactSolver
from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
from engine.solvers.friction import FrictionLaw, WearLaw
from engine.solvers.peak import (
    PEAK_HISTORY_DESCRIPTIONS,
    PEAK_HISTORY_UNITS,
    REGIONS,
    PeakTracker,
    classify_peak,
    first_region_change,
    region_code,
    region_name,
)
from engine.solvers.subsurface import SubsurfaceStress, depth_layers
from engine.study.checkpoint import load_cyclic_state, save_cyclic_state

RADIUS, LOAD, NU = 1.8, 750.0, 0.3


@pytest.mark.parametrize(
    ("x", "z", "expected"),
    [
        (1.0, 0.0, "edge-surface"),
        (-0.95, 0.05, "edge-surface"),
        (0.9, 0.2, "edge-subsurface"),
        (0.0, 0.7, "axis-subsurface"),
        (-0.2, 0.1, "axis-subsurface"),  # z/a = 0.1 is subsurface (threshold inclusive below)
        (0.49, 0.0, "axis-surface"),
        (0.5, 0.0, "edge-surface"),  # r/a = 0.5 is edge
        (0.0, 0.099, "axis-surface"),
    ],
)
def test_classify_peak_thresholds(x, z, expected):
    """r/a < 0.5 → axis, z/a < 0.1 → surface; lengths scale with the contact radius a."""
    assert classify_peak(x, z, 1.0) == expected
    assert classify_peak(2.0 * x, 2.0 * z, 2.0) == expected


def test_classify_peak_rejects_no_contact():
    with pytest.raises(ValueError, match="contact_radius"):
        classify_peak(0.0, 0.0, 0.0)


def test_region_codes_round_trip_and_first_change():
    for name in REGIONS:
        assert region_name(float(region_code(name))) == name
    assert region_name(math.nan) == ""
    cycles = [0, 10, 30, 70, 150]
    assert first_region_change(cycles, [0, 0, 3, 3, 2]) == 30
    assert first_region_change(cycles, [0, 0, 0, 0, 0]) is None
    assert first_region_change([], []) is None


def test_every_history_column_has_units_and_a_description():
    assert set(PEAK_HISTORY_UNITS) == set(PEAK_HISTORY_DESCRIPTIONS)
    assert all(PEAK_HISTORY_UNITS.values())
    for key in ("vm_max", "vm_deep_max", "vm_axis_max", "centre_pressure"):
        assert PEAK_HISTORY_UNITS[key] == "MPa"
    for key in ("vm_deep_max_x", "vm_deep_max_z", "vm_axis_max_z", "contact_radius"):
        assert PEAK_HISTORY_UNITS[key] == "mm"


# --------------------------------------------------------------- synthetic tractions
@pytest.fixture(scope="module")
def tracker():
    """32² over 1.05 a0 (the studies' reduced mesh), 31 graded layers to 1.5 a0."""
    grid = Grid.square(32, 1.05 * RADIUS)
    stress = SubsurfaceStress(grid, NU, depth_layers(1.5 * RADIUS, 31))
    return PeakTracker(stress, RADIUS)


def _radius_field(tracker) -> np.ndarray:
    grid = tracker.stress.grid
    return np.hypot(*np.meshgrid(grid.x, grid.y, indexing="ij"))


def uniform_disc_axis_von_mises(z: np.ndarray, pressure: float, a: float) -> np.ndarray:
    """σ_VM = |σ_r − σ_z| on the axis under a uniform pressure p on a disc of radius a
    (Johnson, Contact Mechanics, Eq. 3.39 (a, b), ν = NU)."""
    root = np.sqrt(a * a + z * z)
    sigma_z = -pressure * (1.0 - z**3 / root**3)
    sigma_r = -0.5 * pressure * ((1 + 2 * NU) - 2 * (1 + NU) * z / root + z**3 / root**3)
    return np.abs(sigma_r - sigma_z)


def test_flat_punch_pressure_peaks_at_the_edge_surface(tracker):
    """Sneddon's pressure (Eq. 17) on the elements: overall and deep peaks at the edge."""
    r = _radius_field(tracker)
    pressure = sneddon_pressure(np.minimum(r, 0.985 * RADIUS), LOAD, RADIUS) * (r < RADIUS)
    values = tracker(pressure)
    assert region_name(values["peak_region"]) == "edge-surface"
    assert region_name(values["deep_region"]) == "edge-subsurface"
    # the deep peak sits at the first layers at or below 0.1 a0, under the edge
    assert values["vm_deep_max_z"] >= 0.1 * RADIUS
    assert values["vm_deep_max_z"] < 0.2 * RADIUS
    assert abs(values["vm_deep_max_x"]) > 0.8 * RADIUS
    # the area-equivalent radius of the pixelated disc: within one element width of a0
    assert abs(values["contact_radius"] - RADIUS) < tracker.stress.grid.dx


def test_uniform_pressure_peaks_on_the_axis_at_the_analytic_depth(tracker):
    """Uniform p on the disc: peak on the axis, below the surface, where Johnson's axis
    solution puts it (z ≈ 0.64 a for ν = 0.3). Tolerances: the pixelated disc's area differs
    from π a² by ~1 % (value within 3 %); the depth within one layer spacing there."""
    r = _radius_field(tracker)
    inside = r < RADIUS
    p = 80.0
    values = tracker(np.where(inside, p, 0.0))
    a = values["contact_radius"]  # the disc the elements actually cover
    assert region_name(values["peak_region"]) == "axis-subsurface"
    assert region_name(values["deep_region"]) == "axis-subsurface"
    z = np.linspace(0.01, 1.5, 3001) * a
    analytic = uniform_disc_axis_von_mises(z, p, a)
    depth, peak = z[np.argmax(analytic)], analytic.max()
    assert 0.6 < depth / a < 0.7  # the reference itself: Johnson's 0.64 a
    depths = tracker.stress.depths
    spacing = np.max(np.diff(depths)[np.abs(depths[1:] - depth) < 0.3 * a])
    assert abs(values["vm_axis_max_z"] - depth) <= spacing
    assert values["vm_axis_max"] == pytest.approx(peak, rel=0.03)
    assert values["vm_max"] == pytest.approx(values["vm_axis_max"], rel=1e-12)
    assert values["centre_pressure"] == pytest.approx(p)


def test_load_on_a_central_island_peaks_on_the_axis_surface(tracker):
    """Load carried by a central island (the long-wear limit): the island presses like a
    small flat punch of radius b = 0.3 a0 (Sneddon's pressure, singular at r = b), the worn
    annulus touches with a small uniform pressure. Peak at the island edge on the surface,
    r/a ≈ 0.3: axis-surface; the contact radius is still a0."""
    r = _radius_field(tracker)
    island = 0.3 * RADIUS
    pressure = sneddon_pressure(np.minimum(r, 0.95 * island), 0.9 * LOAD, island) * (r < island)
    pressure = pressure + np.where(r < RADIUS, 1.0, 0.0)
    values = tracker(pressure)
    assert region_name(values["peak_region"]) == "axis-surface"
    assert abs(values["vm_max_x"]) == pytest.approx(island, abs=tracker.stress.grid.dx)
    assert abs(values["contact_radius"] - RADIUS) < tracker.stress.grid.dx


# --------------------------------------------------------------- cyclic history + checkpoint
@pytest.fixture(scope="module")
def short_run():
    """16², μ = 0.1, large wear (1.33e-5 1/MPa) for 300 cycles: a few simulated cycles."""
    grid = Grid.square(16, 1.05 * RADIUS)
    solver = ContactSolver(grid, paper_material(), FlatPunch(RADIUS), FrictionLaw(0.1, 0.1))
    stress = SubsurfaceStress(grid, NU, depth_layers(1.5 * RADIUS, 10))
    tracker = PeakTracker(stress, RADIUS)
    settings = CyclicSettings(LOAD, 2, 300, record=(300,), max_wear_fraction=0.05)
    analysis = CyclicAnalysis(solver, WearLaw(1.33e-5, 1.33e-5), settings, peak_probe=tracker)
    return analysis, analysis.run()


def test_history_rows_hold_the_peak_columns(short_run):
    _, result = short_run
    history = result.history
    rows = len(history["cycle"])
    assert rows >= 3
    for key in PEAK_HISTORY_UNITS:
        assert len(history[key]) == rows, key
        assert np.all(np.isfinite(history[key])), key
    assert np.all(history["vm_max"] >= history["vm_sub_max"])
    assert np.all(history["vm_sub_max"] >= history["vm_deep_max"])
    assert np.all(history["vm_max"] >= history["vm_axis_max"])
    assert np.all(history["vm_deep_max_z"] >= 0.1 * RADIUS)
    # the first row's tractions are always kept, later ones only where a region changes
    changes = result.state.region_changes
    assert 0 in changes
    for cycle in changes:
        if cycle:
            row = int(np.flatnonzero(history["cycle"] == cycle)[0])
            assert (
                history["peak_region"][row] != history["peak_region"][row - 1]
                or history["deep_region"][row] != history["deep_region"][row - 1]
            )


def test_checkpoint_keeps_peak_history_and_region_changes(short_run, tmp_path):
    _, result = short_run
    path = tmp_path / "state.npz"
    save_cyclic_state(result.state, path)
    loaded = load_cyclic_state(path)
    for key in PEAK_HISTORY_UNITS:
        np.testing.assert_array_equal(loaded.history[key], result.state.history[key])
    assert set(loaded.region_changes) == set(result.state.region_changes)
    for cycle, fields in result.state.region_changes.items():
        for name, values in fields.items():
            np.testing.assert_array_equal(loaded.region_changes[cycle][name], values)
