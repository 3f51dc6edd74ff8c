"""Subsurface stresses by DC-FFT (engine.solvers.subsurface).

Tiers: DC-FFT against the direct sum of the same coefficients (rounding, 1e-10); the
frictionless flat punch against the analytic field of Appendix A at 128² (2 %, 0.02 p0);
equilibrium of every depth plane with the applied forces (2e-4, set by the far-field model).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine.grid import Grid
from engine.kernels.lattice import LatticeConvolution, LineConvolution
from engine.kernels.stress import COMPONENTS, LOADS, element_stress
from engine.reference.flat_punch import (
    flat_punch_stress,
    mean_pressure,
    sneddon_element_pressure,
    von_mises_cylindrical,
)
from engine.solvers.subsurface import StressField, SubsurfaceStress, depth_layers, von_mises

A0, LOAD, NU = 1.8, 714.0, 0.3  # Section 7.1: a0 (mm), P (N), ν of the half-space
P0 = mean_pressure(LOAD, A0)
PAPER_GRID = Grid.square(128, 1.05 * A0)


def _edges(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    return (
        -grid.half_width_x + grid.dx * np.arange(grid.n_x + 1),
        -grid.half_width_y + grid.dy * np.arange(grid.n_y + 1),
    )


def _sneddon(grid: Grid, load: float = LOAD, radius: float = A0) -> np.ndarray:
    """Element-averaged Sneddon pressure (Eq. 17): exact element integrals, total = load."""
    return sneddon_element_pressure(*_edges(grid), load, radius)


def _solver_pressure() -> np.ndarray:
    """Frictionless pressure of the team's contact solver at 128² (skips if not available)."""
    contact = pytest.importorskip("engine.solvers.contact")
    friction = pytest.importorskip("engine.solvers.friction")
    from engine.geometry import FlatPunch
    from engine.material import paper_material

    solver = contact.ContactSolver(
        PAPER_GRID, paper_material(), FlatPunch(A0), friction.FrictionLaw(0.0, 0.0, 0.0)
    )
    result = solver.solve_load(LOAD)
    assert result.report.converged, result.report.message
    return result.pressure


@pytest.fixture(scope="module")
def paper_stress():
    depths = A0 * np.array([0.1, 0.15, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0])
    return SubsurfaceStress(PAPER_GRID, NU, depths)


def _compare_with_appendix_a(field: StressField) -> dict[str, float]:
    r = field.r
    mask = (r <= 0.8 * A0) | (r >= 1.2 * A0)
    mask &= (field.z >= 0.1 * A0 - 1e-12) & (field.z <= 2.0 * A0 + 1e-12)
    assert np.count_nonzero(mask) >= 20
    reference = flat_punch_stress(r, field.z, LOAD, A0, NU)
    computed = field.cylindrical()
    errors = {
        k: float(np.max(np.abs(computed[k] - reference[k])[mask]) / P0)
        for k in ("rr", "phiphi", "zz", "rz")
    }
    vm_reference = von_mises_cylindrical(reference)
    errors["von_mises"] = float(
        np.max(np.abs(field.von_mises - vm_reference)[mask] / vm_reference[mask])
    )
    return errors


# --- frictionless punch against Appendix A -------------------------------------------------------


@pytest.mark.parametrize("source", ["sneddon", "solver"])
@pytest.mark.validation
def test_frictionless_punch_matches_appendix_a_on_xz_plane(paper_stress, source, validation):
    # 2 % on σ_VM and 0.02 p0 on σrr, σφφ, σzz, τrz away from the edge
    # (r ≤ 0.8 a0 or r ≥ 1.2 a0, 0.1 a0 ≤ z ≤ 2 a0). Measured at 128²: 0.23 % / 0.0008 p0
    # with the element-averaged Sneddon pressure (only the discretisation of the load into
    # elements), 1.2 % / 0.006 p0 with the solver's pressure (its edge error adds).
    pressure = _sneddon(PAPER_GRID) if source == "sneddon" else _solver_pressure()
    # The plane extends beyond the contact grid (half width 1.05 a0) to reach r ≥ 1.2 a0.
    field = paper_stress.plane(pressure, None, None, angle=0.0, half_length=2.2 * A0)
    errors = _compare_with_appendix_a(field)
    assert errors["von_mises"] < 0.02, errors
    for k in ("rr", "phiphi", "zz", "rz"):
        assert errors[k] < 0.02, errors
    worst = max(errors[k] for k in ("rr", "phiphi", "zz", "rz"))
    validation.record(
        f"subsurface σ_VM vs Appendix A, 128², {source} pressure, r ≤ 0.8 a0 or ≥ 1.2 a0, "
        "0.1 ≤ z/a0 ≤ 2", "2 % on σ_VM; 0.02 p0 on the components (discretisation)",
        f"{errors['von_mises']:.2%}; {worst:.4f} p0",
    )  # fmt: skip


def test_oblique_plane_matches_appendix_a(paper_stress):
    # A plane at φ = 0.6 rad is bilinearly interpolated from the lattice; same tolerances as
    # the x–z plane above (measured 0.19 % / 0.0006 p0).
    field = paper_stress.plane(_sneddon(PAPER_GRID), angle=0.6, half_length=2.2 * A0)
    errors = _compare_with_appendix_a(field)
    assert errors["von_mises"] < 0.02, errors
    for k in ("rr", "phiphi", "zz", "rz"):
        assert errors[k] < 0.02, errors


# --- DC-FFT against the direct sum ------------------------------------------------------------


def _direct_sum(grid, tractions, points_x, points_y, depth):
    """Eq. (16) summed element by element at arbitrary points (flattened), MPa."""
    out = {c: np.zeros(points_x.size) for c in COMPONENTS}
    for p, (px, py) in enumerate(zip(points_x, points_y, strict=True)):
        for load, values in tractions.items():
            # offsets from every source centre, in decreasing order: the general corner path
            coefficients = element_stress(
                px - grid.x, py - grid.y, depth, grid.dx, grid.dy, NU, load
            )
            for c in COMPONENTS:
                out[c][p] += np.sum(coefficients[c] * values)
    return out


@pytest.fixture(scope="module")
def small_case():
    grid = Grid(7, 6, 0.7, 0.45)  # odd × even, Δx ≠ Δy
    rng = np.random.default_rng(7)
    tractions = {
        "pressure": rng.uniform(0, 10, grid.shape),
        "traction_x": rng.uniform(-3, 3, grid.shape),
        "traction_y": rng.uniform(-3, 3, grid.shape),
    }
    depths = np.array([0.003, 0.05, 0.4])
    return grid, tractions, SubsurfaceStress(grid, NU, depths, planner_effort="FFTW_ESTIMATE")


def test_block_equals_direct_sum(small_case):
    # Self-consistency: the zero-padded FFT convolution is exact, rounding only (1e-10).
    grid, tractions, stress = small_case
    field = stress.block(tractions["pressure"], tractions["traction_x"], tractions["traction_y"])
    assert field.x.shape == (7, 6, 3)
    for k, depth in enumerate(stress.depths):
        reference = _direct_sum(
            grid, tractions, field.x[:, :, k].ravel(), field.y[:, :, k].ravel(), depth
        )
        for c in COMPONENTS:
            scale = np.abs(reference[c]).max()
            np.testing.assert_allclose(
                field.components[c][:, :, k].ravel(), reference[c], rtol=0, atol=1e-10 * scale
            )


@pytest.mark.parametrize("angle", [0.0, math.pi / 2, 0.7])
def test_plane_equals_direct_sum_on_lattice_points(small_case, angle):
    # On the lattice through the axis (all samples for φ = 0, π/2; the axis for any φ) the
    # plane is an exact DC-FFT value, also beyond the grid (half_length > half width): 1e-10.
    # Off the lattice the bilinear interpolation error is checked against Appendix A above.
    grid, tractions, stress = small_case
    field = stress.plane(**tractions, angle=angle, half_length=1.2)
    if angle == 0.7:
        rows = np.flatnonzero(field.s[:, 0] == 0.0)
    else:
        rows = np.arange(field.s.shape[0])
    for k, depth in enumerate(stress.depths):
        reference = _direct_sum(grid, tractions, field.x[rows, k], field.y[rows, k], depth)
        for c in COMPONENTS:
            scale = np.abs(reference[c]).max()
            np.testing.assert_allclose(
                field.components[c][rows, k], reference[c], rtol=0, atol=1e-10 * scale
            )


@pytest.mark.parametrize("shape", [(7, 6), (6, 7)])
@pytest.mark.parametrize("axis", [0, 1])
def test_line_through_the_axis_folds_the_grid(shape, axis):
    # The x–z (y–z) plane folds the grid across the line (LineConvolution): the same sums
    # as the 2-D lattice it replaces, to rounding (1e-12), with half its kernel memory or
    # less, for an odd and an even number of rows across the line.
    grid = Grid(*shape, 0.7, 0.45)
    rng = np.random.default_rng(11)
    tractions = {load: rng.uniform(-3, 3, grid.shape) for load in LOADS}
    depths = np.array([0.003, 0.05, 0.4])
    stress = SubsurfaceStress(grid, NU, depths)
    field = stress.plane(**tractions, angle=axis * math.pi / 2, half_length=1.2)
    ((origin, counts), line), *others = stress._lattices.items()
    assert isinstance(line, LineConvolution) and not others
    lattice = LatticeConvolution(grid, NU, origin, counts, 1, "FFTW_ESTIMATE", True)
    reference = lattice.evaluate(depths, tractions)
    for c in COMPONENTS:
        scale = np.abs(reference[c]).max()
        np.testing.assert_allclose(
            field.components[c],
            reference[c].reshape(field.components[c].shape),
            rtol=0,
            atol=1e-12 * scale,
        )
    assert line.cache_bytes == 0  # kept from the second evaluation on
    stress.plane(**tractions, angle=axis * math.pi / 2, half_length=1.2)
    assert 0 < line.cache_bytes <= 0.5 * lattice.cache_bytes * (1 + 1 / min(shape))


@pytest.mark.parametrize("axis", [0, 1])
def test_line_streams_its_rows_in_blocks(monkeypatch, axis):
    # Streaming: the rows folded across the line are transformed and summed block by block
    # (ROW_BLOCK), and only the kernel spectra under the cache limit are kept. With blocks of
    # two rows (an odd grid across: the middle row ends the last block) the line is the
    # one-block sum up to the order of the sum over the rows (rounding: 1e-13 of the largest
    # value), and bit for bit the same whatever the cache keeps (all, part, nothing) and
    # on the second call, which reads the kept spectra.
    import engine.kernels.lattice as lattice

    grid = Grid(9, 11, 0.7, 0.45) if axis == 0 else Grid(11, 9, 0.45, 0.7)
    rng = np.random.default_rng(5)
    tractions = {load: rng.uniform(-3, 3, grid.shape) for load in LOADS}
    depths = np.array([0.004, 0.05, 0.3])
    angle = axis * math.pi / 2

    def plane(limit):
        stress = SubsurfaceStress(grid, NU, depths, kernel_cache_limit=limit)
        first = stress.plane(**tractions, angle=angle)
        second = stress.plane(**tractions, angle=angle)
        for c in COMPONENTS:
            np.testing.assert_array_equal(first.components[c], second.components[c])
        return stress, first

    whole = plane(None)[1]  # 6 rows across: one block
    monkeypatch.setattr(lattice, "ROW_BLOCK", 2)
    streamed = {}
    for limit in (None, 0, "part"):
        stress, streamed[limit] = plane(None if limit == "part" else limit)
        (line,) = stress._lattices.values()
        assert len(line._blocks) == 3
        if limit == "part":  # the line itself keeps what a limit allows, block by block
            stress, _ = plane(0)
            (line,) = stress._lattices.values()
            line.cache_limit = line.kernel_bytes(depths.size) // 3
            streamed[limit] = stress.plane(**tractions, angle=angle)
            assert 0 < stress.kernel_cache_bytes <= line.cache_limit
        elif limit is None:
            assert stress.kernel_cache_bytes == line.kernel_bytes(depths.size)
        else:
            assert stress.kernel_cache_bytes == 0
    for c in COMPONENTS:
        scale = np.abs(whole.components[c]).max()
        np.testing.assert_allclose(
            streamed[None].components[c], whole.components[c], rtol=0, atol=1e-13 * scale
        )
        for limit in (0, "part"):
            np.testing.assert_array_equal(
                streamed[limit].components[c], streamed[None].components[c]
            )


def test_prepared_plane_keeps_all_its_kernels_or_none():
    # The set-up of a plane (prepare_plane) builds every kernel spectrum of the plane when
    # they all fit in the limit, and none when they do not (a part would hold memory for a
    # part of the time); a plane evaluated afterwards equals that of a fresh evaluator bit
    # for bit, and keeps no more than the set-up did.
    grid = Grid.square(12, 0.6)
    depths = np.array([0.01, 0.1, 0.2, 0.4])
    pressure = _sneddon(grid, 10.0, 0.4)
    fresh = SubsurfaceStress(grid, NU, depths).plane(pressure, 0.2 * pressure)
    unlimited = SubsurfaceStress(grid, NU, depths, kernel_cache_limit=None)
    unlimited.prepare_plane()
    whole = unlimited.kernel_cache_bytes
    (line,) = unlimited._lattices.values()
    assert whole == line.kernel_bytes(depths.size) > 0
    fits = SubsurfaceStress(grid, NU, depths, kernel_cache_limit=whole)
    fits.prepare_plane()
    assert fits.kernel_cache_bytes == whole
    limited = SubsurfaceStress(grid, NU, depths, kernel_cache_limit=whole - 1)
    limited.prepare_plane()
    assert limited.kernel_cache_bytes == 0
    for stress in (unlimited, fits, limited):
        kept = stress.kernel_cache_bytes
        field = stress.plane(pressure, 0.2 * pressure)
        assert stress.kernel_cache_bytes == kept
        for c in COMPONENTS:
            np.testing.assert_array_equal(field.components[c], fresh.components[c])


def test_block_margin_extends_the_lattice(small_case):
    # Field points beyond the grid edge, exact DC-FFT values again (1e-10).
    grid, tractions, stress = small_case
    field = stress.block(**tractions, margin=0.25)
    assert field.x.shape == (7 + 2 * 2, 6 + 2 * 2, 3)
    k = 1
    reference = _direct_sum(
        grid, tractions, field.x[:, :, k].ravel(), field.y[:, :, k].ravel(), stress.depths[k]
    )
    for c in COMPONENTS:
        scale = np.abs(reference[c]).max()
        np.testing.assert_allclose(
            field.components[c][:, :, k].ravel(), reference[c], rtol=0, atol=1e-10 * scale
        )


def test_rotated_load_on_perpendicular_plane():
    # Sign and angle conventions: rotating every traction by +90° about z and looking at the
    # plane φ = π/2 gives σ' = R σ Rᵀ of the plane φ = 0 (both exact lattice values, 1e-10).
    grid = Grid.square(16, 1.0)
    rng = np.random.default_rng(11)
    p, qx, qy = rng.uniform(0, 1, (3, 16, 16))
    stress = SubsurfaceStress(grid, NU, np.array([0.01, 0.2]), planner_effort="FFTW_ESTIMATE")
    original = stress.plane(p, qx, qy, angle=0.0)

    def rotate(field):  # f'(x, y) = f(y, −x) on the symmetric square grid
        return field.T[::-1, :]

    rotated = stress.plane(rotate(p), -rotate(qy), rotate(qx), angle=math.pi / 2)
    expected = {
        "xx": original.components["yy"],
        "yy": original.components["xx"],
        "zz": original.components["zz"],
        "xy": -original.components["xy"],
        "xz": -original.components["yz"],
        "yz": original.components["xz"],
    }
    for c in COMPONENTS:
        np.testing.assert_allclose(rotated.components[c], expected[c], rtol=0, atol=1e-10)
    np.testing.assert_allclose(rotated.y, original.x, atol=1e-12)


# --- equilibrium -------------------------------------------------------------------------------


def _disk_fraction_normal(radius, z):
    """∫ over the disk r ≤ R of σzz of a unit normal point force (Boussinesq): −(1 − cos³ θ)."""
    return -(1.0 - z**3 / (radius**2 + z**2) ** 1.5)


def _disk_fraction_shear(radius, z):
    """∫ over the disk r ≤ R of σxz of a unit +x point force (Cerruti σxz = −3x²z/2πρ⁵)."""
    rho = math.hypot(radius, z)
    return -1.0 + 1.5 * z / rho - 0.5 * z**3 / rho**3


@pytest.mark.validation
def test_every_depth_plane_carries_the_applied_forces(validation):
    # ∫σzz dA = −P, ∫σxz dA = −Q_x, ∫σyz dA = −Q_y over a plane much wider than
    # the contact (radius 12 mm vs. contact radius 0.5 mm). The lattice sum over the disk is
    # completed by the far field of the resultant forces outside it (point-load fractions
    # above; the Cerruti shear decays only as z/R, 6 % at z = 0.5 mm). What remains — the
    # departure of the real load from a point load in that far field, O((a/R)² · 6 %), and
    # the staircase disk edge — is measured at ≤ 6e-5 of the force (σzz ≤ 3e-7); the
    # tolerance is 2e-4.
    a = 0.5
    grid = Grid.square(32, 0.55)
    pressure = _sneddon(grid, 100.0, a)
    traction_x = 0.25 * pressure
    traction_y = -0.1 * pressure
    forces = {
        "zz": pressure.sum() * grid.element_area,
        "xz": traction_x.sum() * grid.element_area,
        "yz": traction_y.sum() * grid.element_area,
    }
    depths = np.array([1e-4, 0.05, 0.2, 0.5])
    stress = SubsurfaceStress(grid, NU, depths, cache_kernels=False, planner_effort="FFTW_ESTIMATE")
    field = stress.block(pressure, traction_x, traction_y, margin=12.1)
    radius = 12.0
    inside = field.r[:, :, 0] <= radius
    worst = {"zz": 0.0, "shear": 0.0}
    for k, z in enumerate(depths):
        integrals = {
            c: field.components[c][:, :, k][inside].sum() * grid.element_area
            for c in ("zz", "xz", "yz")
        }
        # far field outside the disk, from the resultant forces
        integrals["zz"] += forces["zz"] * (-1.0 - _disk_fraction_normal(radius, z))
        integrals["xz"] += forces["xz"] * (-1.0 - _disk_fraction_shear(radius, z))
        integrals["yz"] += forces["yz"] * (-1.0 - _disk_fraction_shear(radius, z))
        for c, force in forces.items():
            assert integrals[c] == pytest.approx(-force, rel=2e-4, abs=2e-4 * forces["zz"]), (
                c,
                z,
            )
            key = "zz" if c == "zz" else "shear"
            worst[key] = max(worst[key], abs(integrals[c] + force) / forces["zz"])
    validation.record(
        "∫σzz = −P and ∫σxz, σyz = −Q on wide planes at every depth",
        "2e-4 of P (far-field completion)", f"{worst['zz']:.0e}; {worst['shear']:.0e}",
    )  # fmt: skip


# --- location of the peak ----------------------------------------------------------------------


@pytest.mark.validation
def test_frictionless_peak_is_at_the_contact_edge_near_the_surface(validation):
    # Fig. 5b: maximum at x/a0 = 1, z/a0 = 0. Both peaks, with and without the surface layer,
    # must sit within two element pitches of r = a0 and within 5 % of a0 of the surface; the
    # peak value exceeds the mean pressure (σ_VM/p0 ≥ 1 around the edge).
    depths = depth_layers(2.0 * A0, 40)
    stress = SubsurfaceStress(PAPER_GRID, NU, depths)
    field = stress.plane(_sneddon(PAPER_GRID), angle=0.0)
    peaks = field.peaks()
    assert set(peaks) == {"overall", "below_surface_layer"}
    assert peaks["overall"].z == pytest.approx(depths[0])
    assert peaks["below_surface_layer"].z >= depths[1]
    for peak in peaks.values():
        assert abs(math.hypot(peak.x, peak.y) - A0) <= 2.0 * PAPER_GRID.dx, peak
        assert peak.z <= 0.05 * A0, peak
        assert peak.value > P0, peak
    assert peaks["overall"].value >= peaks["below_surface_layer"].value
    peak = peaks["overall"]
    validation.record(
        "frictionless σ_VM peak at the contact edge near the surface (Fig. 5b)",
        "two element pitches of r = a0, z ≤ 0.05 a0",
        f"r = {math.hypot(peak.x, peak.y) / A0:.4f} a0, z = {peak.z / A0:.1e} a0 "
        f"(σ_VM/p0 = {peak.value / P0:.2f})",
    )  # fmt: skip


# --- depths, results, API details --------------------------------------------------------------


@pytest.mark.parametrize("graded", [True, False])
def test_depth_layers(graded):
    depths = depth_layers(3.6, 40, graded=graded)
    assert depths.shape == (40,)
    assert np.all(depths > 0.0) and np.all(np.diff(depths) > 0.0)
    assert depths[-1] == pytest.approx(3.6)
    assert depths[0] == pytest.approx(0.01 * depths[1])
    if graded:
        assert depths[1] == pytest.approx(3.6 / 39**2)
    else:
        np.testing.assert_allclose(np.diff(depths[1:]), 3.6 / 39)
    with pytest.raises(ValueError):
        depth_layers(3.6, 1)
    with pytest.raises(ValueError):
        depth_layers(-1.0, 10)


def test_von_mises_is_eq_21_for_axisymmetric_fields(paper_stress):
    # The cylindrical rotation preserves the invariant: Cartesian σ_VM equals Eq. (21) plus
    # the 6(τrφ² + τφz²) terms (rounding, 1e-9); for the axisymmetric load those terms are
    # discretisation noise, so Eq. (21) alone holds to 1e-4 relative.
    field = paper_stress.plane(_sneddon(PAPER_GRID), angle=0.3)
    cylindrical = field.cylindrical()
    extra = 3.0 * (cylindrical["rphi"] ** 2 + cylindrical["phiz"] ** 2)
    eq_21 = von_mises_cylindrical(cylindrical)
    np.testing.assert_allclose(field.von_mises, np.sqrt(eq_21**2 + extra), rtol=1e-9)
    np.testing.assert_allclose(field.von_mises, eq_21, rtol=1e-4)
    np.testing.assert_allclose(von_mises(field.components), field.von_mises)


def test_kernel_cache_is_reused_and_reported(small_case):
    grid, tractions, stress = small_case
    first = stress.block(tractions["pressure"])
    size = stress.kernel_cache_bytes
    second = stress.block(tractions["pressure"])
    assert stress.kernel_cache_bytes == size > 0
    for c in COMPONENTS:
        np.testing.assert_array_equal(first.components[c], second.components[c])


def test_inputs_are_checked():
    grid = Grid.square(8, 1.0)
    with pytest.raises(ValueError, match="depths"):
        SubsurfaceStress(grid, NU, np.array([0.0, 0.1]))
    stress = SubsurfaceStress(grid, NU, np.array([0.1]), planner_effort="FFTW_ESTIMATE")
    with pytest.raises(ValueError, match="shape"):
        stress.block(np.zeros((8, 7)))
    zero = stress.block(np.zeros((8, 8)))
    assert np.all(zero.von_mises == 0.0)


def test_a_window_gives_the_same_bits_with_its_components_at_once_or_apart(monkeypatch):
    """The element centres beside a plane (a window of the grid) take a layer's six
    components at once (small batch buffers) or one at a time (``BATCH_LIMIT`` 0): the same
    products in the same order, so the same bits."""
    from engine.kernels import lattice

    grid = Grid.square(16, 1.05 * A0)
    rng = np.random.default_rng(7)
    tractions = [rng.random(grid.shape) for _ in LOADS]
    window = (slice(0, 16), slice(7, 9))
    depths = depth_layers(1.5 * A0, 5)
    together = SubsurfaceStress(grid, NU, depths).block(*tractions, window=window)
    monkeypatch.setattr(lattice, "BATCH_LIMIT", 0)
    apart = SubsurfaceStress(grid, NU, depths).block(*tractions, window=window)
    for component in COMPONENTS:
        assert np.array_equal(together.components[component], apart.components[component])


def _line_case(axis: int, along: int, across: int, sets: int, seed: int):
    """A grid of ``along`` × ``across`` elements along ``axis``, the origin of a line through
    it four elements in, and ``sets`` random traction fields (MPa)."""
    sizes, half_widths = (along, across), (0.7, 0.45)
    grid = Grid(*sizes[:: 1 - 2 * axis], *half_widths[:: 1 - 2 * axis])
    origin = (-4 * grid.dx, 0.0) if axis == 0 else (0.0, -4 * grid.dy)
    rng = np.random.default_rng(seed)
    fields = [{load: rng.uniform(-3, 3, grid.shape) for load in LOADS} for _ in range(sets)]
    return grid, origin, fields


@pytest.mark.parametrize("row_block", [64, 2])
@pytest.mark.parametrize("axis", [0, 1])
def test_line_takes_sets_of_tractions_at_once(monkeypatch, row_block, axis):
    # evaluate_sets: several traction fields (here two, one without τ_y) by one matrix product
    # per component and frequency, in one block of rows or in blocks of two; BLAS sums in its
    # own order, so the lines equal evaluate's to rounding (1e-12 of the largest value). The
    # kernels are kept in that layout only when the line keeps kernels.
    import engine.kernels.lattice as lattice

    monkeypatch.setattr(lattice, "ROW_BLOCK", row_block)
    grid, origin, sets = _line_case(axis, 9, 7, sets=2, seed=3)
    del sets[1]["traction_y"]
    depths = np.array([0.004, 0.05, 0.3])
    for cache in (True, False):
        options = (1, "FFTW_ESTIMATE", cache)
        line = LineConvolution(grid, NU, axis, origin[axis], 9, *options)
        together = line.evaluate_sets(depths, sets)
        assert (line.cache_bytes > 0) == cache
        for tractions, values in zip(sets, together, strict=True):
            alone = line.evaluate(depths, tractions)
            for c in COMPONENTS:
                scale = np.abs(alone[c]).max()
                assert values[c].shape == alone[c].shape
                np.testing.assert_allclose(values[c], alone[c], rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("row_block", [64, 2])
@pytest.mark.parametrize("axis", [0, 1])
def test_a_line_gives_the_same_bits_with_and_without_kept_kernels(monkeypatch, axis, row_block):
    # a line's first evaluation (often its only one: a static case) takes a layer's six
    # components one by one, in less memory; later ones take them in one einsum per load, on
    # the kernels kept or not: the same products summed in the same order, so the same bits
    import engine.kernels.lattice as lattice

    monkeypatch.setattr(lattice, "ROW_BLOCK", row_block)
    grid, origin, (tractions,) = _line_case(axis, 20, 16, sets=1, seed=5)
    depths = np.array([0.004, 0.05, 0.3, 1.2])
    values = {}
    for cache in (True, False):
        line = LineConvolution(grid, NU, axis, origin[axis], 20, 1, "FFTW_ESTIMATE", cache)
        values[cache] = [line.evaluate(depths, tractions) for _ in range(2)]
        assert (line.cache_bytes > 0) == cache
    for first in values[True]:
        for second in values[False]:
            for c in COMPONENTS:
                assert np.array_equal(first[c], second[c]), c
