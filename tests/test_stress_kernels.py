"""Element-integrated subsurface stress coefficients (engine.kernels.stress).

References used here are independent of the corner functions: the classical displacement
fields of the Boussinesq and Cerruti point loads (Johnson 1985, Eqs. 3.19 and 3.22 forms),
differentiated by the complex-step method, and the explicit Cerruti stresses; both are
integrated over the element by adaptive quadrature.
"""

from __future__ import annotations

import numpy as np
import pytest

from engine.kernels.stress import (
    COMPONENTS,
    cerruti_point_stress,
    element_stress,
    kernel_parity,
)

NU = 0.3
HALF_X, HALF_Y = 0.2, 0.15  # element 0.4 mm × 0.3 mm
# (x, y, z) of field points, mm: shallow inside the element, over a corner, over an edge,
# far away, deep.
POINTS = [
    (0.05, -0.03, 0.08),
    (0.2, 0.15, 0.1),
    (-0.2, 0.07, 0.05),
    (1.3, -0.7, 0.5),
    (-0.4, 0.9, 2.0),
]


def _displacement_boussinesq(x, y, z, nu=NU):
    """Unit normal point force into the half-space, G = 1 (Johnson Eq. 3.19b)."""
    rho = np.sqrt(x * x + y * y + z * z)
    c = 1.0 / (4.0 * np.pi)
    return c * np.array(
        [
            x * z / rho**3 - (1 - 2 * nu) * x / (rho * (rho + z)),
            y * z / rho**3 - (1 - 2 * nu) * y / (rho * (rho + z)),
            2 * (1 - nu) / rho + z * z / rho**3,
        ]
    )


def _displacement_cerruti(x, y, z, nu=NU):
    """Unit tangential point force in +x on the half-space, G = 1 (Johnson Eq. 3.19a)."""
    rho = np.sqrt(x * x + y * y + z * z)
    c = 1.0 / (4.0 * np.pi)
    return c * np.array(
        [
            1 / rho
            + x * x / rho**3
            + (1 - 2 * nu) * (1 / (rho + z) - x * x / (rho * (rho + z) ** 2)),
            x * y / rho**3 - (1 - 2 * nu) * x * y / (rho * (rho + z) ** 2),
            x * z / rho**3 + (1 - 2 * nu) * x / (rho * (rho + z)),
        ]
    )


def _stress_from_displacement(displacement, x, y, z, nu=NU):
    """Hooke's law (G = 1) on the complex-step gradient of ``displacement``: exact to rounding."""
    h = 1e-30
    point = [np.asarray(v, dtype=complex) for v in (x, y, z)]
    gradient = []
    for j in range(3):
        shifted = list(point)
        shifted[j] = shifted[j] + 1j * h
        gradient.append(np.imag(displacement(*shifted)) / h)  # d u_i / d x_j
    du = np.stack(gradient, axis=1)
    strain = 0.5 * (du + np.swapaxes(du, 0, 1))
    trace = strain[0, 0] + strain[1, 1] + strain[2, 2]
    lame = 2 * nu / (1 - 2 * nu)
    index = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
    return {c: 2 * strain[i, j] + (lame * trace if i == j else 0.0) for c, (i, j) in index.items()}


def _graded_nodes(lower, upper, peak, width, order=24):
    """Gauss–Legendre nodes and weights on [lower, upper], panels graded geometrically (ratio 2)
    away from ``peak``, the projection of the field point, down to ``width`` (its depth)."""
    peak = min(max(peak, lower), upper)
    breaks = {lower, upper, peak}
    for sign in (-1.0, 1.0):
        step = 0.25 * width
        while step < upper - lower:
            edge = peak + sign * step
            if lower < edge < upper:
                breaks.add(edge)
            step *= 2.0
    breaks = np.array(sorted(breaks))
    t, w = np.polynomial.legendre.leggauss(order)
    half = 0.5 * np.diff(breaks)[:, None]
    nodes = (0.5 * (breaks[1:] + breaks[:-1]))[:, None] + half * t
    return nodes.ravel(), (half * w).ravel()


def _integrate_over_element(point_stress, x, y, z):
    """∫∫ over the element of the point-load stress at (x − ξ, y − η, z): vector of COMPONENTS.

    Composite Gauss–Legendre graded toward the field point's projection: converged to ~1e-9
    relative at the depths used here (checked against adaptive quadrature while writing).
    """
    xi, wx = _graded_nodes(-HALF_X, HALF_X, x, z)
    eta, wy = _graded_nodes(-HALF_Y, HALF_Y, y, z)
    XI, ETA = np.meshgrid(xi, eta, indexing="ij")
    values = point_stress(x - XI, y - ETA, np.full_like(XI, z))
    weights = wx[:, None] * wy[None, :]
    return np.array([np.sum(np.real(values[c]) * weights) for c in COMPONENTS])


def _coefficients(load, x, y, z):
    values = element_stress([x], [y], z, 2 * HALF_X, 2 * HALF_Y, NU, load)
    return np.array([values[c][0, 0] for c in COMPONENTS])


def _cerruti_y(x, y, z):
    """Point force in +y: the +x solution with x ↔ y (components relabelled)."""
    swapped = cerruti_point_stress(y, x, z, NU)
    relabel = {"xx": "yy", "yy": "xx", "zz": "zz", "xy": "xy", "xz": "yz", "yz": "xz"}
    return {c: swapped[relabel[c]] for c in COMPONENTS}


def test_cerruti_point_stress_is_the_derivative_of_the_cerruti_displacement():
    # Two independent textbook forms of the same solution; agreement to rounding (1e-12).
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-2, 2, (2, 50))
    z = rng.uniform(0.01, 2, 50)
    explicit = cerruti_point_stress(x, y, z, NU)
    derived = _stress_from_displacement(_displacement_cerruti, x, y, z)
    for c in COMPONENTS:
        np.testing.assert_allclose(explicit[c], derived[c], rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("point", POINTS)
@pytest.mark.parametrize("load", ["traction_x", "traction_y"])
@pytest.mark.validation
def test_tangential_coefficients_match_integrated_cerruti_solution(load, point, validation):
    # Quadrature is converged to ~1e-9; the required 1e-4 relative bound
    # (with an absolute floor 1e-6 of the largest component for components that vanish by
    # symmetry at a point) leaves that margin untouched.
    point_stress = (
        (lambda x, y, z: cerruti_point_stress(x, y, z, NU)) if load == "traction_x" else _cerruti_y
    )
    reference = _integrate_over_element(point_stress, *point)
    computed = _coefficients(load, *point)
    floor = 1e-6 * np.abs(reference).max()
    np.testing.assert_allclose(computed, reference, rtol=1e-4, atol=floor)
    error = np.max(np.abs(computed - reference) / np.maximum(np.abs(reference), floor))
    validation.record(
        f"{load} stress kernels vs quadrature of Cerruti's point-load solution at {point}",
        "1e-4 rel. (quadrature converged to ~1e-9)", f"{error:.0e}",
    )  # fmt: skip


@pytest.mark.parametrize("point", POINTS)
def test_pressure_coefficients_match_integrated_boussinesq_solution(point):
    # Love (1929) closed forms vs quadrature of the Boussinesq field; same tolerances.
    def point_stress(x, y, z):
        return _stress_from_displacement(_displacement_boussinesq, x, y, z)

    reference = _integrate_over_element(point_stress, *point)
    computed = _coefficients("pressure", *point)
    np.testing.assert_allclose(computed, reference, rtol=1e-4, atol=1e-6 * np.abs(reference).max())


def test_surface_limits_under_the_element_centre():
    # At z → 0 under the centre: σzz = −1 (pressure), σxz = −1 (traction_x), σyz = −1
    # (traction_y), and σxx + σyy = −(1 + 2ν) for pressure (Johnson §3.2). The depth 1e-7 mm
    # sets the O(z/size) departure, hence 1e-5.
    z = 1e-7
    pressure = element_stress([0.0], [0.0], z, 0.4, 0.3, NU, "pressure")
    shear_x = element_stress([0.0], [0.0], z, 0.4, 0.3, NU, "traction_x")
    shear_y = element_stress([0.0], [0.0], z, 0.4, 0.3, NU, "traction_y")
    assert pressure["zz"][0, 0] == pytest.approx(-1.0, abs=1e-5)
    assert pressure["xx"][0, 0] + pressure["yy"][0, 0] == pytest.approx(-(1 + 2 * NU), abs=1e-5)
    assert shear_x["xz"][0, 0] == pytest.approx(-1.0, abs=1e-5)
    assert shear_y["yz"][0, 0] == pytest.approx(-1.0, abs=1e-5)
    assert shear_x["zz"][0, 0] == pytest.approx(0.0, abs=1e-5)
    assert pressure["xz"][0, 0] == pytest.approx(0.0, abs=1e-5)


@pytest.mark.parametrize("load", ["pressure", "traction_x", "traction_y"])
def test_lattice_evaluation_matches_direct_evaluation(load):
    # Self-consistency (rounding only, 1e-12): shared, mirrored corners on a symmetric
    # lattice (including field points exactly above element corners, X = Y = 0) vs. four
    # independent corner evaluations per point.
    d = 0.03
    for x in (np.arange(-20, 21) * d, np.arange(-20, 22) * d - d / 2):
        for y in (np.arange(-15, 16) * d, np.arange(-3, 9) * d + 0.3 * d):
            lattice = element_stress(x, y, 0.004, d, d, NU, load)
            direct = element_stress(x[::-1], y[::-1], 0.004, d, d, NU, load)
            for c in COMPONENTS:
                scale = np.abs(lattice[c]).max()
                np.testing.assert_allclose(
                    lattice[c], direct[c][::-1, ::-1], rtol=0, atol=1e-12 * scale
                )


@pytest.mark.parametrize("load", ["pressure", "traction_x", "traction_y"])
def test_kernel_parity(load):
    # The DC-FFT stores real or imaginary spectra based on these parities: check them on
    # the coefficients themselves (exact symmetry up to rounding).
    x = np.arange(-6, 7) * 0.1
    values = element_stress(x, x, 0.05, 0.1, 0.1, NU, load)
    for c in COMPONENTS:
        parity_x, parity_y = kernel_parity(load, c)
        np.testing.assert_allclose(values[c][::-1, :], parity_x * values[c], atol=1e-14)
        np.testing.assert_allclose(values[c][:, ::-1], parity_y * values[c], atol=1e-14)


def test_depth_must_be_positive():
    with pytest.raises(ValueError, match="depth"):
        element_stress([0.0], [0.0], 0.0, 0.1, 0.1, NU, "pressure")
    with pytest.raises(ValueError, match="load"):
        element_stress([0.0], [0.0], 0.1, 0.1, 0.1, NU, "shear")
