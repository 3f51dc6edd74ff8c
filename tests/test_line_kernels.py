"""Plane-strain (line contact) influence coefficients and their DC-FFT operator.

Tiers: round-off (1e-12) for the FFT operator against the dense product; the 3-D kernels
integrated along y (the definition of plane strain) to the truncation of that integral; the
solvers on a line grid against Hertz and Cattaneo in ``tests/test_line_validation.py``.
"""

import numpy as np
import pytest

from engine.geometry import CylinderProfile, RoundedPadProfile
from engine.grid import Grid
from engine.kernels.influence import SurfaceInfluence
from engine.kernels.line import LineInfluence, line_operator, log_strip_integral
from engine.material import MaterialPair, paper_material
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw

REFERENCE_DISTANCE = 10.0  # mm


def test_line_grid_has_one_unit_element_along_y():
    grid = Grid.line(8, 1.0)
    assert grid.shape == (8, 1) and grid.is_line
    assert grid.dy == 1.0 and grid.element_area == grid.dx  # N/mm loads are N on the slice
    np.testing.assert_array_equal(grid.y, [0.0])
    with pytest.raises(ValueError, match="n_y must be an integer >= 2, got 1"):
        Grid(8, 1, 1.0, 1.0)  # one element along y is a line grid only with Δy = 1 mm


def test_log_strip_integral_matches_quadrature():
    from scipy import integrate

    for offset in (0.0, 0.3, -1.7, 2.55):
        exact = float(log_strip_integral(np.array(offset), 0.4, 3.0))
        value, _ = integrate.quad(
            lambda u: np.log(abs(u) / 3.0), offset - 0.2, offset + 0.2, points=[0.0], limit=200
        )
        # Smooth integrand with an integrable log singularity: round-off level.
        assert exact == pytest.approx(value, rel=1e-10, abs=1e-12)


def test_line_operator_equals_dense_matrix_product():
    grid = Grid.line(9, 1.0)
    operator = line_operator(grid, paper_material(), REFERENCE_DISTANCE)
    tractions = np.random.default_rng(1).standard_normal((3, 9, 1))
    fft = np.array(operator.apply(*tractions))
    dense = operator.influence.dense_matrix() @ tractions.reshape(-1)
    # FFT round-off only: 1e-12 relative.
    np.testing.assert_allclose(fft.reshape(-1), dense, rtol=0, atol=1e-12 * np.abs(dense).max())


def test_line_operator_equals_the_block_operator_on_the_line_kernels():
    """The 1-D operator and its preconditioner are the 3-D block machinery
    (``HalfSpaceOperator``, ``SpectralPreconditioner``) reduced to one axis: the same products
    on a dissimilar pair (K ≠ 0), to FFT round-off (1e-12 of the largest value)."""
    from engine.kernels.operator import HalfSpaceOperator, SpectralPreconditioner

    material = MaterialPair(200e3, 0.3, 70e3, 0.33)
    grid = Grid.line(12, 1.0)
    line = line_operator(grid, material, REFERENCE_DISTANCE)
    block = HalfSpaceOperator(grid, material, influence=line.influence)
    fields = np.random.default_rng(2).standard_normal((3, 12, 1))

    def close(actual, expected):
        actual, expected = np.asarray(actual), np.asarray(expected)
        assert actual.shape == expected.shape
        np.testing.assert_allclose(actual, expected, atol=1e-12 * np.abs(expected).max())

    close(line.apply(*fields), block.apply(*fields))
    close(line.apply_normal(fields[2]), block.apply_normal(fields[2]))
    close(line.apply_tangential(*fields[:2]), block.apply_tangential(*fields[:2]))
    close(line.coupling_to_normal(*fields[:2]), block.coupling_to_normal(*fields[:2]))
    close(line.coupling_to_tangential(fields[2]), block.coupling_to_tangential(fields[2]))
    assert line.symbol_bound() == pytest.approx(block.symbol_bound(), rel=1e-12)
    assert line.self_coefficient("xx") == block.self_coefficient("xx")
    spectral = SpectralPreconditioner(block)
    close(line.preconditioner.normal(fields[2]), spectral.normal(fields[2]))
    close(line.preconditioner.tangential(*fields[:2]), spectral.tangential(*fields[:2]))
    # Plane strain proper (q_y = 0): the y transforms are skipped, u_y = 0 exactly.
    plane = (fields[0], np.zeros_like(fields[1]), fields[2])
    close(line.apply(*plane), block.apply(*plane))
    close(line.apply_tangential(*plane[:2]), block.apply_tangential(*plane[:2]))
    close(line.preconditioner.tangential(*plane[:2]), spectral.tangential(*plane[:2]))
    assert not np.any(line.apply(*plane)[1]) and not np.any(line.apply_tangential(*plane[:2])[1])
    assert line.applications == 9


def test_line_operator_is_symmetric_positive_definite():
    """Betti (A_xz = A_zx^T) and a positive energy with the datum at the grid's length."""
    grid = Grid.line(16, 1.0)
    dense = LineInfluence.build(grid, paper_material(), 2.0).dense_matrix()
    np.testing.assert_allclose(dense, dense.T, atol=1e-14 * np.abs(dense).max())
    assert np.linalg.eigvalsh(dense).min() > 0


def test_reference_distance_must_exceed_the_grid_length():
    with pytest.raises(ValueError, match="reference_distance = 1 mm must be at least"):
        LineInfluence.build(Grid.line(8, 1.0), paper_material(), 1.0)


def test_kernels_are_the_three_dimensional_kernels_integrated_along_y():
    """Plane strain is the 3-D half-space loaded uniformly along y: summing the 3-D element
    kernels over a strip of length L = 2·4000 Δx along y gives the 2-D coefficients. The
    coupling converges as Δx/L (relative 1e-3 here); the normal and tangential kernels
    diverge like ln L, so their *differences* between two offsets are compared (truncation
    O((X/L)²), 1e-6 relative here)."""
    material = paper_material()
    n, dx = 5, 0.2
    long_strip = Grid(n, 8001, n * dx / 2, 8001 * dx / 2)
    three_d = SurfaceInfluence.build(long_strip, material).kernels
    line = LineInfluence.build(Grid.line(n, n * dx / 2), material, REFERENCE_DISTANCE).kernels
    summed = {key: three_d[key].sum(axis=1) for key in ("zz", "xx", "zx")}
    coupling = line["zx"][:, 0]
    np.testing.assert_allclose(summed["zx"], coupling, rtol=1e-3, atol=1e-12 * coupling.max())
    for key in ("zz", "xx"):
        difference_3d = summed[key] - summed[key][n - 1]
        difference_2d = line[key][:, 0] - line[key][n - 1, 0]
        scale = np.abs(difference_2d).max()
        np.testing.assert_allclose(difference_3d, difference_2d, atol=1e-6 * scale)


def test_pressure_does_not_depend_on_the_datum_under_load_control():
    """The datum d shifts every displacement by a constant that the approach takes up; the
    pressure is the same to the solver's tolerance."""
    material = MaterialPair(200e3, 0.3, 70e3, 0.33)  # dissimilar: K ≠ 0
    grid = Grid.line(128, 0.25)
    pressures = []
    for distance in (1.0, 100.0):
        operator = line_operator(grid, material, distance)
        solver = ContactSolver(
            grid, material, CylinderProfile(6.0), FrictionLaw(0.0, 0.0), operator=operator
        )
        result = solver.solve_load(100.0)
        assert result.report.converged, result.report.message
        pressures.append(result.pressure)
    np.testing.assert_allclose(pressures[0], pressures[1], atol=1e-6 * pressures[0].max())


def test_profiles_need_a_line_grid():
    with pytest.raises(ValueError, match="needs a line grid"):
        CylinderProfile(6.0).check_grid(Grid.square(8, 1.0))
    with pytest.raises(ValueError, match="does not cover the pad's flat half-width"):
        RoundedPadProfile(2.0, 5.0).check_grid(Grid.line(64, 1.0))
    gap = RoundedPadProfile(0.5, 4.0).gap(Grid.line(4, 1.0))[:, 0]
    np.testing.assert_allclose(gap, [0.25**2 / 8, 0.0, 0.0, 0.25**2 / 8])


def test_border_of_a_line_grid_is_its_two_ends():
    from engine.geometry import border_contact, may_reach_border

    pressure = np.zeros((8, 1))
    pressure[1:7] = 1.0
    assert border_contact(pressure) == 0
    pressure[7] = 1.0
    assert border_contact(pressure) == 1
    assert may_reach_border(CylinderProfile(6.0), Grid.line(8, 1.0))
