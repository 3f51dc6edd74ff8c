"""Influence coefficients and the DC-FFT operator (self-consistency tier: round-off)."""

import numpy as np
import pytest
from scipy import integrate

from engine.grid import Grid
from engine.kernels.influence import SurfaceInfluence, element_integrals
from engine.kernels.operator import HalfSpaceOperator
from engine.material import MaterialPair, paper_material


@pytest.mark.validation
def test_self_term_of_normal_kernel_matches_closed_form(validation):
    material = paper_material()
    h = 0.1
    influence = SurfaceInfluence.build(Grid.square(4, 2 * h), material)
    centre = influence.kernels["zz"][3, 3]
    expected = (
        (1 - material.poisson_ratio)
        * 4
        * h
        * np.log(1 + np.sqrt(2))
        / (np.pi * material.shear_modulus)
    )
    assert centre == pytest.approx(expected, rel=1e-13)
    validation.record(
        "self term of A_zz = (1−ν)·4h·ln(1+√2)/(πG)", "1e-13 rel. (round-off)",
        f"{abs(centre / expected - 1):.0e} rel.",
    )  # fmt: skip


@pytest.mark.parametrize(("x", "y"), [(2.3, -1.7), (0.9, 0.05), (-0.6, 3.1)])
@pytest.mark.validation
def test_element_integrals_match_quadrature_of_point_kernels(x, y, validation):
    dx, dy = 0.7, 0.4
    exact = element_integrals(np.array(x), np.array(y), dx, dy)
    kernels = {
        "one_over_r": lambda a, b: 1 / np.hypot(a, b),
        "xx": lambda a, b: a * a / np.hypot(a, b) ** 3,
        "yy": lambda a, b: b * b / np.hypot(a, b) ** 3,
        "xy": lambda a, b: a * b / np.hypot(a, b) ** 3,
        "x": lambda a, b: a / np.hypot(a, b) ** 2,
        "y": lambda a, b: b / np.hypot(a, b) ** 2,
    }
    worst = 0.0
    for key, kernel in kernels.items():
        value, _ = integrate.dblquad(
            lambda yy, xx, k=kernel: k(x - xx, y - yy),
            -dx / 2,
            dx / 2,
            -dy / 2,
            dy / 2,
            epsabs=1e-13,
            epsrel=1e-12,
        )
        # Quadrature of a smooth integrand: agreement to ~1e-11 is round-off level.
        assert float(exact[key]) == pytest.approx(value, rel=1e-10, abs=1e-13), key
        worst = max(worst, abs(float(exact[key]) - value) / max(abs(value), 1e-3))
    validation.record(
        f"element integrals of the Eq. 5 kernels vs 2-D quadrature at ({x:g}, {y:g})",
        "1e-10 rel. (quadrature round-off)", f"{worst:.0e}",
    )  # fmt: skip


@pytest.mark.validation
def test_operator_equals_dense_matrix_product(validation):
    grid = Grid(7, 5, 1.0, 0.8)
    operator = HalfSpaceOperator(grid, paper_material())
    tractions = np.random.default_rng(0).standard_normal((3, 7, 5))
    fft = np.array(operator.apply(*tractions))
    dense = operator.influence.dense_matrix() @ tractions.reshape(-1)
    # FFT round-off only: 1e-12 relative.
    np.testing.assert_allclose(fft.reshape(-1), dense, rtol=0, atol=1e-12 * np.abs(dense).max())
    normal = operator.apply_normal(tractions[2])
    dense_normal = operator.influence.dense_matrix()[70:, 70:] @ tractions[2].reshape(-1)
    np.testing.assert_allclose(normal.reshape(-1), dense_normal, atol=1e-12 * abs(dense).max())
    error = np.abs(fft.reshape(-1) - dense).max() / np.abs(dense).max()
    validation.record(
        "DC-FFT operator vs dense matrix product, full 3×3 block", "1e-12 (FFT round-off)",
        f"{error:.0e}",
    )  # fmt: skip


def test_block_operator_is_symmetric_positive_definite():
    """Betti: A_xz = A_zx^T, so the block matrix is symmetric; the energy is positive."""
    dense = HalfSpaceOperator(Grid(6, 6, 1.0, 1.0), paper_material()).influence.dense_matrix()
    np.testing.assert_allclose(dense, dense.T, atol=1e-14 * np.abs(dense).max())
    assert np.linalg.eigvalsh(dense).min() > 0


def test_soft_half_space_moves_toward_compressed_region():
    """K > 0 (soft half-space, stiff punch): under a central pressure patch, the surface
    of the half-space moves toward the punch axis: u_x < 0 for x > 0 and u_x > 0 for x < 0."""
    material = paper_material()
    assert material.coupling > 0
    grid = Grid.square(16, 1.0)
    operator = HalfSpaceOperator(grid, material)
    pressure = (grid.radius() < 0.5).astype(float)
    u_x, u_y, u_n = operator.apply(np.zeros(grid.shape), np.zeros(grid.shape), pressure)
    X, Y = grid.coordinates()
    assert np.all(u_x[X > 0] < 0) and np.all(u_x[X < 0] > 0)
    assert np.all(u_y[Y > 0] < 0) and np.all(u_y[Y < 0] > 0)
    assert np.all(u_n > 0)  # compression deflects both surfaces away from each other


def test_identical_materials_have_no_coupling():
    pair = MaterialPair(E_A=210e3, nu_A=0.3, E_B=210e3, nu_B=0.3)
    assert pair.coupling == 0.0


def test_paper_material_constants_match_notes():
    pair = paper_material()
    assert pair.shear_modulus == pytest.approx(152323, rel=1e-5)
    assert pair.coupling == pytest.approx(0.19604, rel=1e-4)
    assert pair.dundurs_beta == pytest.approx(0.28006, rel=1e-4)
    assert pair.contact_modulus == pytest.approx(217604, rel=1e-5)
