"""Plane-strain subsurface stresses of a line contact (engine.solvers.line_subsurface).

Tiers: the element-integrated strip coefficients against quadrature of Flamant's point
solutions (round-off); the DC-FFT field against the direct sum (round-off); the field of a
Hertz pressure and of a sliding (q = μp) traction against their closed forms (discretisation:
1001 elements over ±2a, pointwise relative errors ≤ 1e-3, measured 1e-4).
"""

import math

import numpy as np
import pytest
from scipy import integrate

from engine.grid import Grid
from engine.kernels.line_stress import strip_stress_coefficients
from engine.solvers.line_subsurface import LineSubsurfaceStress

HALF_WIDTH, PEAK, NU = 0.5, 100.0, 0.3


def _flamant(load, X, z):
    """Stresses per unit line load at offset X, depth z (Johnson 2.15, 2.21)."""
    r4 = (X * X + z * z) ** 2
    if load == "pressure":
        return {"xx": X * X * z / r4, "zz": z**3 / r4, "xz": X * z * z / r4}
    return {"xx": X**3 / r4, "zz": X * z * z / r4, "xz": X * X * z / r4}


@pytest.mark.parametrize(("offset", "depth"), [(0.0, 0.05), (0.31, 0.02), (-1.2, 0.4)])
def test_strip_coefficients_match_quadrature_of_flamant(offset, depth):
    width = 0.1
    exact = strip_stress_coefficients(offset, depth, width)
    for load in ("pressure", "traction_x"):
        for component in ("xx", "zz", "xz"):
            value, _ = integrate.quad(
                lambda s, c=component, q=load: _flamant(q, offset - s, depth)[c],
                -width / 2,
                width / 2,
                epsabs=1e-14,
                epsrel=1e-12,
            )
            # Smooth integrand: round-off level.
            expected = -2.0 / math.pi * value
            assert float(exact[load][component]) == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_fft_field_equals_direct_sum():
    grid = Grid.line(9, 0.45)
    depths = np.array([0.01, 0.2])
    rng = np.random.default_rng(3)
    pressure, traction = rng.random(9), rng.standard_normal(9)
    field = LineSubsurfaceStress(grid, NU, depths).plane(pressure, traction, bulk_stress=7.0)
    offsets = grid.x[:, None] - grid.x[None, :]
    for k, z in enumerate(depths):
        c = strip_stress_coefficients(offsets, z, grid.dx)
        for component in ("xx", "zz", "xz"):
            direct = c["pressure"][component] @ pressure + c["traction_x"][component] @ traction
            direct = direct + (7.0 if component == "xx" else 0.0)
            # FFT round-off.
            np.testing.assert_allclose(field.components[component][:, k], direct, atol=1e-12)
    xx, zz = field.components["xx"], field.components["zz"]
    np.testing.assert_allclose(field.components["yy"], NU * (xx + zz), rtol=1e-15)


@pytest.fixture(scope="module")
def fine_grid():
    return Grid.line(1001, 2 * HALF_WIDTH)  # odd: an element centre on the axis


def test_hertz_pressure_field_on_the_axis(fine_grid):
    """σ_zz = −p0 a/√(a²+z²), σ_xx = −(p0/a)[(a²+2z²)/√(a²+z²) − 2z] (Johnson 4.50)."""
    depths = np.array([0.05, 0.25, 0.5, 1.0])
    a = HALF_WIDTH
    pressure = PEAK * np.sqrt(np.clip(1 - (fine_grid.x / a) ** 2, 0, None))
    field = LineSubsurfaceStress(fine_grid, NU, depths).plane(pressure, np.zeros(1001))
    root = np.sqrt(a * a + depths**2)
    np.testing.assert_allclose(field.components["zz"][500], -PEAK * a / root, rtol=1e-3)
    expected_xx = -(PEAK / a) * ((a * a + 2 * depths**2) / root - 2 * depths)
    np.testing.assert_allclose(field.components["xx"][500], expected_xx, rtol=1e-3)


def test_sliding_traction_gives_the_trailing_edge_tension(fine_grid):
    """Sliding cylinder q = μp (q along +x on the flat): near the surface,
    σ_xx(x) = −p0 √(1 − x²/a²) − 2μ p0 x/a inside the contact (Johnson §7.2 (McEwen)), so
    the tensile peak +2μp0 sits at the trailing edge x = −a."""
    mu, a = 0.5, HALF_WIDTH
    x = fine_grid.x
    pressure = PEAK * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    field = LineSubsurfaceStress(fine_grid, NU, [1e-6]).plane(pressure, mu * pressure)
    inside = np.abs(x) < 0.9 * a
    expected = -pressure - 2 * mu * PEAK * x / a
    # At z → 0 the jumps of the piecewise constant traction between elements leave
    # ln(Δx/z) terms: 0.5 % of p0 (measured 0.2 %, at the ends of |x| < 0.9a).
    xx = field.components["xx"][:, 0]
    np.testing.assert_allclose(xx[inside], expected[inside], atol=5e-3 * PEAK)
    trailing = np.argmax(field.components["xx"][:, 0])
    assert abs(x[trailing] + a) <= fine_grid.dx
    # The surface value next to the edge converges from below like √(Δx/a) (the traction's
    # square-root edge sampled at element centres): measured 0.908, 0.931, 0.965 of 2μp0
    # with 250, 1000 and 4000 elements over ±2a; here between 0.9 and 1.
    assert 0.9 * 2 * mu * PEAK < xx[trailing] <= 2 * mu * PEAK


def test_fretting_probes_see_the_bulk_stress_of_their_increment():
    """The peak tracker's plane carries σ_B of the peak increment (σ_xx gains σ_B,
    σ_yy = ν(σ_xx + σ_zz)); the contact half-width is the line's."""
    from engine.geometry import CylinderProfile
    from engine.kernels.line import line_operator
    from engine.material import MaterialPair
    from engine.solvers.contact import ContactSolver
    from engine.solvers.fretting import FrettingAnalysis, FrettingSettings
    from engine.solvers.friction import FrictionLaw, WearLaw
    from engine.solvers.line_subsurface import LinePeakTracker

    steel = MaterialPair(200e3, 0.3, 200e3, 0.3)
    grid = Grid.line(64, 0.3)
    solver = ContactSolver(
        grid,
        steel,
        CylinderProfile(6.0),
        FrictionLaw(0.5, 0.5),
        operator=line_operator(grid, steel, 10.0),
    )
    stress = LineSubsurfaceStress(grid, 0.3, [0.001, 0.02, 0.05, 0.2])
    tracker = LinePeakTracker(stress, 0.113)
    settings = FrettingSettings(
        load=185.0,
        steps=2,
        cycles=1,
        force_amplitude=40.0,
        bulk_stress_max=150.0,
        bulk_stress_min=-50.0,
    )
    analysis = FrettingAnalysis(solver, WearLaw(0.0, 0.0), settings, peak_probe=tracker)
    analysis.bulk_stress_listener = lambda value: setattr(stress, "bulk_stress", value)
    outcome = analysis.run()
    assert outcome.converged, outcome.message
    assert analysis.peak_bulk_stress in (150.0, -50.0)
    plane = tracker.last_plane
    peak = outcome.final  # the peak increment of the last cycle, which the tracker saw
    without = stress.plane(peak.pressure, peak.traction_x, bulk_stress=0.0)
    difference = plane.components["xx"] - without.components["xx"]
    np.testing.assert_allclose(difference, analysis.peak_bulk_stress, rtol=1e-12)
    xx, zz = plane.components["xx"], plane.components["zz"]
    np.testing.assert_allclose(plane.components["yy"], 0.3 * (xx + zz), rtol=1e-14)
    half_width = 0.5 * np.count_nonzero(outcome.final.pressure > 0) * grid.dx
    assert outcome.history["contact_radius"][-1] == half_width
