"""The line (plane-strain) contact solvers against the closed forms of
``engine.reference.line_contact`` (meshes and tolerances: docs/explanation/validation.md).

Tolerances are those of the analytic tier: the pressure's square-root edge is sampled at
element centres, so the pointwise error near the edge decays like √(Δx/a) and the contact
half-width is known to one element; interior values and integrals converge like Δx.
"""

import math

import numpy as np
import pytest

from engine.geometry import CylinderProfile, RoundedPadProfile
from engine.grid import Grid
from engine.kernels.line import line_operator
from engine.material import MaterialPair
from engine.reference import line_contact as ref
from engine.solvers.contact import ContactSolver
from engine.solvers.fretting import (
    FrettingAnalysis,
    FrettingSettings,
    TangentialDriver,
    bulk_stretch,
    shifted_state,
)
from engine.solvers.friction import FrictionLaw, WearLaw

STEEL = MaterialPair(200e3, 0.3, 200e3, 0.3)  # identical bodies: K = 0
RADIUS = 6.0  # mm
LOAD = 185.0  # N/mm (McColl et al. 2004)
MU = 0.5
DATUM = 10.0  # mm
E_STAR = STEEL.contact_modulus
HALF_WIDTH = ref.hertz_line_half_width(LOAD, RADIUS, E_STAR)
PEAK = ref.hertz_line_peak_pressure(LOAD, RADIUS, E_STAR)


def _solver(n, half_width, profile, mu=MU, tol=1e-10):
    grid = Grid.line(n, half_width)
    operator = line_operator(grid, STEEL, DATUM)
    return ContactSolver(grid, STEEL, profile, FrictionLaw(mu, mu), operator=operator, tol=tol)


@pytest.fixture(scope="module")
def cylinder():
    """256 elements over ±1.25 a: 205 elements across the contact."""
    solver = _solver(256, 1.25 * HALF_WIDTH, CylinderProfile(RADIUS), mu=0.0)
    return solver, solver.solve_load(LOAD)


@pytest.mark.validation
def test_hertz_line_contact(cylinder, validation):
    solver, result = cylinder
    assert result.report.converged, result.report.message
    grid = solver.grid
    assert result.load == pytest.approx(LOAD, rel=1e-12)  # load control is exact
    half_width = 0.5 * np.count_nonzero(result.pressure > 0.0) * grid.dx
    assert abs(half_width - HALF_WIDTH) <= grid.dx  # the edge is known to one element
    # Peak at the centre (elements at ±Δx/2): the interior converges like Δx; 0.2 %.
    assert result.pressure.max() == pytest.approx(PEAK, rel=2e-3)
    expected = ref.hertz_line_pressure(grid.x, LOAD, RADIUS, E_STAR)
    error = result.pressure[:, 0] - expected
    # RMS over the grid 0.3 % of p0; the worst point (next to the edge) 2 % (√(Δx/a)).
    assert math.sqrt(np.mean(error**2)) < 3e-3 * PEAK
    assert np.abs(error).max() < 2e-2 * PEAK
    validation.record(
        "line contact (plane strain), steel on steel, R = 6 mm, P = 185 N/mm, 256 elements "
        "over ±1.25a: Hertz half-width / p0 / RMS / worst point of p",
        "1 element / 0.2 % / 0.3 % / 2 % of p0 (edge sampled at element centres)",
        f"{(half_width - HALF_WIDTH) / grid.dx:+.2f} element / "
        f"{result.pressure.max() / PEAK - 1:+.1e} / {math.sqrt(np.mean(error**2)) / PEAK:.2%} / "
        f"{np.abs(error).max() / PEAK:.2%}",
    )  # fmt: skip


def _tangential(solver, force, stretch=None):
    start = solver.solve_load(LOAD)
    state = start.state if stretch is None else shifted_state(start.state, np.zeros(2), stretch)
    driver = TangentialDriver(solver, LOAD, np.array([1.0, 0.0]), force_tol=1e-8)
    step = driver.force(state, np.zeros(2), force, abs(force), 1e-3, 1e5)
    assert step.converged, step.message
    return step.result


@pytest.mark.parametrize("ratio", [0.3, -0.7])
@pytest.mark.validation
def test_cattaneo_mindlin_cylinder(ratio, validation):
    """Q = ratio·μP from the normal-loaded state: stick half-width and traction profile."""
    solver = _solver(256, 1.25 * HALF_WIDTH, CylinderProfile(RADIUS))
    force = ratio * MU * LOAD
    result = _tangential(solver, force)
    grid = solver.grid
    stick = 0.5 * np.count_nonzero(result.status == 1) * grid.dx
    expected_stick = ref.cattaneo_line_stick_half_width(HALF_WIDTH, force, LOAD, MU)
    assert abs(stick - expected_stick) <= 1.5 * grid.dx  # both ends known to one element
    traction = ref.cattaneo_line_traction(grid.x, force, LOAD, RADIUS, E_STAR, MU)
    error = result.traction_x[:, 0] - traction
    # Two square-root edges (contact and stick): RMS 0.5 %, worst point 2 % of μp0.
    assert math.sqrt(np.mean(error**2)) < 5e-3 * MU * PEAK
    assert np.abs(error).max() < 2e-2 * MU * PEAK
    np.testing.assert_array_equal(result.traction_y, 0.0)  # plane strain: no q_y
    validation.record(
        f"line contact, Cattaneo–Mindlin at Q = {ratio:g} μP (μ = 0.5), 256 elements: stick "
        "half-width / RMS / worst point of q", "1.5 elements / 0.5 % / 2 % of μp0",
        f"{(stick - expected_stick) / grid.dx:+.2f} element / "
        f"{math.sqrt(np.mean(error**2)) / (MU * PEAK):.2%} / "
        f"{np.abs(error).max() / (MU * PEAK):.2%}",
    )  # fmt: skip


@pytest.mark.validation
def test_nowell_hills_stick_zone_shift_with_bulk_stress(validation):
    """A bulk tension σ_B applied with Q (one proportional increment) moves the stick zone
    by e = σ_B a / (4 μ p0) towards +x for Q > 0; its half-width stays c."""
    solver = _solver(512, 1.25 * HALF_WIDTH, CylinderProfile(RADIUS))
    force, bulk_stress = 0.5 * MU * LOAD, 120.0  # MPa
    strain = ref.bulk_surface_strain(bulk_stress, STEEL.E_A, STEEL.nu_A)
    result = _tangential(solver, force, bulk_stretch(solver.grid, strain))
    offset = ref.nowell_hills_stick_offset(strain, force, HALF_WIDTH, PEAK, E_STAR, MU)
    assert offset == pytest.approx(bulk_stress * HALF_WIDTH / (4 * MU * PEAK), rel=1e-12)
    grid = solver.grid
    stick_x = grid.x[result.status[:, 0] == 1]
    # Centre and half-width of the stick zone to one element each.
    assert abs(0.5 * (stick_x.min() + stick_x.max()) - offset) <= grid.dx
    c = ref.cattaneo_line_stick_half_width(HALF_WIDTH, force, LOAD, MU)
    assert abs(0.5 * (stick_x.max() - stick_x.min() + grid.dx) - c) <= 1.5 * grid.dx
    traction = ref.nowell_hills_traction(grid.x, force, LOAD, RADIUS, E_STAR, MU, offset)
    error = result.traction_x[:, 0] - traction
    assert math.sqrt(np.mean(error**2)) < 5e-3 * MU * PEAK  # as Cattaneo's
    centre = 0.5 * (stick_x.min() + stick_x.max())
    validation.record(
        "line contact, Nowell & Hills stick-zone shift, σ_B = 120 MPa, Q = 0.5 μP, 512 elements: "
        "stick centre / RMS of q", "1 element / 0.5 % of μp0",
        f"{(centre - offset) / grid.dx:+.2f} element / "
        f"{math.sqrt(np.mean(error**2)) / (MU * PEAK):.2%}",
    )  # fmt: skip


@pytest.mark.parametrize("ratio", [0.5, 0.9])
@pytest.mark.validation
def test_mindlin_deresiewicz_loop_energy(ratio, validation):
    """One force-controlled cycle ±Q* without wear: the loop's area ∮ Q dδ against
    (2μ²P²/(πE*))[2(1 − T) ln(1 − T) + 2T − T²]. The loop is a polygon through 16
    increments per quarter (the trapezoidal rule on a curved loop) and 128 elements across
    the contact: 0.5 % (measured 0.11–0.14 %)."""
    solver = _solver(160, 1.25 * HALF_WIDTH, CylinderProfile(RADIUS), tol=1e-9)
    force = ratio * MU * LOAD
    settings = FrettingSettings(load=LOAD, steps=16, cycles=1, force_amplitude=force)
    analysis = FrettingAnalysis(solver, WearLaw(0.0, 0.0), settings)
    outcome = analysis.run()
    assert outcome.converged, outcome.message
    energy = outcome.history["energy"][-1]
    expected = ref.line_loop_energy(force, LOAD, E_STAR, MU)
    assert energy == pytest.approx(expected, rel=5e-3)
    validation.record(
        f"line contact, Mindlin–Deresiewicz loop energy at Q* = {ratio:g} μP, 160 elements, "
        "16 increments per quarter", "0.5 % (trapezoidal rule, mesh)",
        f"{energy / expected - 1:+.2%}",
    )  # fmt: skip
    # The displacement amplitude δ(Q*) relative to the datum d (the fretting map's
    # partial/gross boundary at Q* = μP): mesh error only, 0.1 % (measured 1e-5).
    amplitude = outcome.history["displacement_amplitude"][-1]
    exact = float(ref.line_tangential_displacement(force, LOAD, RADIUS, E_STAR, MU, DATUM))
    assert amplitude == pytest.approx(exact, rel=1e-3)
    validation.record(
        f"line contact, displacement amplitude δ(Q*) at Q* = {ratio:g} μP (datum 10 mm), "
        "160 elements", "0.1 % (mesh)", f"{amplitude / exact - 1:+.4%}",
    )  # fmt: skip


def test_line_slip_displacement_is_the_displacement_at_full_force():
    slip = ref.line_slip_displacement(LOAD, RADIUS, E_STAR, MU, DATUM)
    at_limit = ref.line_tangential_displacement(MU * LOAD, LOAD, RADIUS, E_STAR, MU, DATUM)
    assert float(at_limit) == pytest.approx(float(slip), rel=1e-14)
    # Doubling the datum adds the compliance (2/(πE*)) ln 2 per unit load at Q = μP.
    farther = ref.line_slip_displacement(LOAD, RADIUS, E_STAR, MU, 2 * DATUM)
    expected = 2 * MU * LOAD * math.log(2) / (math.pi * E_STAR)
    assert float(farther - slip) == pytest.approx(expected, rel=1e-12)


def test_line_loop_energy_limits():
    """Small amplitudes: W → (2μ²P²/(πE*)) T³/3 (cubic, as Mindlin's sphere)."""
    scale = 2 * (MU * LOAD) ** 2 / (math.pi * E_STAR)
    small = ref.line_loop_energy(1e-3 * MU * LOAD, LOAD, E_STAR, MU)
    assert small == pytest.approx(scale * 1e-9 / 3, rel=1e-2)
    assert ref.line_loop_energy(MU * LOAD, LOAD, E_STAR, MU) == pytest.approx(scale)


@pytest.mark.parametrize("factor", [0.3, 0.8, 2.5])
def test_line_fretting_loop_encloses_the_energy_per_cycle(factor):
    """The drawn loop (2001 points per branch) passes through (±δ*, ±Q*) and encloses
    line_loop_energy(Q*) in partial slip, that plus 4μP(δ* − δ_slip) in gross slip (2e-5:
    polygon of a smooth curve). Q* under a displacement amplitude comes from the numerical
    inverse of the virgin curve (1e-12: Brent's xtol and rounding; measured 4e-15)."""
    contact = (LOAD, RADIUS, E_STAR, MU, DATUM)
    slip = float(ref.line_slip_displacement(*contact))
    amplitude = factor * slip
    delta, force = ref.line_fretting_loop(*contact, displacement_amplitude=amplitude, points=2001)
    peak_force = force[0]
    assert delta[0] == pytest.approx(amplitude, rel=1e-12)
    assert delta.min() == pytest.approx(-amplitude, rel=1e-12)
    assert (delta[-1], force[-1]) == (delta[0], force[0])
    limit = MU * LOAD
    if factor < 1.0:
        reached = float(ref.line_tangential_displacement(peak_force, *contact))
        assert reached == pytest.approx(amplitude, rel=1e-12)
        expected = ref.line_loop_energy(peak_force, LOAD, E_STAR, MU)
    else:
        assert peak_force == limit
        expected = ref.line_loop_energy(limit, LOAD, E_STAR, MU) + 4 * limit * (amplitude - slip)
    area = 0.5 * abs(np.sum(delta[:-1] * force[1:] - delta[1:] * force[:-1]))
    assert area == pytest.approx(expected, rel=2e-5)


def test_rounded_pad_closed_form_is_consistent():
    """The pressure integrates to P (to the quadrature's 1e-6), reduces to Hertz as b → 0,
    and inside the flat matches direct quadrature of the inversion integral (the integrand
    is regular there after t = a sin θ)."""
    from scipy import integrate

    b, radius, load = 0.1, 5.0, 200.0
    a = ref.pad_half_width(load, b, radius, E_STAR)
    assert ref.pad_load(a, b, radius, E_STAR) == pytest.approx(load, rel=1e-12)
    x = np.linspace(-a, a, 400001)
    total = np.trapezoid(ref.pad_pressure(x, load, b, radius, E_STAR), x)
    assert total == pytest.approx(load, rel=1e-6)
    near_hertz = ref.pad_pressure(np.array([0.03]), load, 1e-9, radius, E_STAR)[0]
    hertz = ref.hertz_line_pressure(0.03, load, radius, E_STAR)
    assert near_hertz == pytest.approx(float(hertz), rel=1e-6)
    phi = math.asin(b / a)

    def slope_over_distance(theta, point, edge):
        """h'(t) / (t − x) at t = a sin θ (the weight 1/√(a² − t²) absorbed by dθ)."""
        t = a * math.sin(theta)
        return (t - edge) / (radius * (t - point))

    for point in (0.0, 0.04, -0.07):
        right, _ = integrate.quad(slope_over_distance, phi, math.pi / 2, (point, b), epsabs=1e-13)
        left, _ = integrate.quad(slope_over_distance, -math.pi / 2, -phi, (point, -b), epsabs=1e-13)
        quadrature = E_STAR / (2 * math.pi) * math.sqrt(a * a - point**2) * (right + left)
        closed = ref.pad_pressure(np.array([point]), load, b, radius, E_STAR)[0]
        assert closed == pytest.approx(quadrature, rel=1e-9)


@pytest.mark.validation
def test_rounded_pad_against_ciavarella(validation):
    """Flat b = 0.1 mm, edges R = 5 mm, P = 200 N/mm: 256 elements over ±1.15 a. The
    pressure peaks near x = ±b where the flat meets the rounds (a kink of the profile, so the
    pressure has a log-like cusp): RMS error 1 % of the mean pressure P/(2a)."""
    b, radius, load = 0.1, 5.0, 200.0
    a = ref.pad_half_width(load, b, radius, E_STAR)
    solver = _solver(256, 1.15 * a, RoundedPadProfile(b, radius), mu=0.0)
    result = solver.solve_load(load)
    assert result.report.converged, result.report.message
    grid = solver.grid
    half_width = 0.5 * np.count_nonzero(result.pressure > 0.0) * grid.dx
    assert abs(half_width - a) <= grid.dx
    expected = ref.pad_pressure(grid.x, load, b, radius, E_STAR)
    error = result.pressure[:, 0] - expected
    mean = load / (2 * a)
    assert math.sqrt(np.mean(error**2)) < 1e-2 * mean  # measured 0.11 %
    validation.record(
        "line contact, Ciavarella's rounded pad (b = 0.1 mm, R = 5 mm, 200 N/mm), 256 elements "
        "over ±1.15a: half-width / RMS of p", "1 element / 1 % of P/(2a)",
        f"{(half_width - a) / grid.dx:+.2f} element / {math.sqrt(np.mean(error**2)) / mean:.2%}",
    )  # fmt: skip


def test_fretting_fatigue_cycle_keeps_the_shifted_stick_zone():
    """Q and σ_B oscillating in phase (±Q*, ±σ_B, force control): at the extremes of the
    cycle the stick zone is Nowell & Hills' (half-width c, centre e = σ_B a/(4μp0)), the same
    at +Q* (σ_B) and −Q* (−σ_B); 8 increments per quarter, 256 elements over ±1.25a."""
    solver = _solver(256, 1.25 * HALF_WIDTH, CylinderProfile(RADIUS), tol=1e-9)
    force, bulk_stress = 0.5 * MU * LOAD, 120.0
    settings = FrettingSettings(
        load=LOAD,
        steps=8,
        cycles=1,
        force_amplitude=force,
        bulk_stress_max=bulk_stress,
        bulk_stress_min=-bulk_stress,
    )
    analysis = FrettingAnalysis(solver, WearLaw(0.0, 0.0), settings)
    outcome = analysis.run()
    assert outcome.converged, outcome.message
    assert abs(analysis.peak_bulk_stress) == bulk_stress
    grid = solver.grid
    stick_x = grid.x[outcome.final.status[:, 0] == 1]
    offset = bulk_stress * HALF_WIDTH / (4 * MU * PEAK)
    assert abs(0.5 * (stick_x.min() + stick_x.max()) - offset) <= grid.dx
    c = ref.cattaneo_line_stick_half_width(HALF_WIDTH, force, LOAD, MU)
    assert abs(0.5 * (stick_x.max() - stick_x.min() + grid.dx) - c) <= 1.5 * grid.dx


def test_bulk_stress_needs_a_line_contact():
    from engine.geometry import SphericalPunch

    grid = Grid.square(16, 1.0)
    solver = ContactSolver(grid, STEEL, SphericalPunch(10.0), FrictionLaw(MU, MU))
    settings = FrettingSettings(load=10.0, steps=2, cycles=1, amplitude=1e-3, bulk_stress_max=5)
    with pytest.raises(ValueError, match="line \\(plane-strain\\) contacts only"):
        FrettingAnalysis(solver, WearLaw(0.0, 0.0), settings)


@pytest.mark.parametrize("datum", [1.0, 10.0, 100.0])  # mm
def test_cylinder_slip_displacement_is_the_stick_point_displacement_at_full_sliding(datum):
    """The closed form δ_slip = (μ p0 a/E*)(ln(2d/a) + 1/2) against the quadrature of its
    definition: the tangential displacement at the centre x = 0 (where the stick zone
    vanishes) of the full-sliding traction μ p(ξ), through the plane-strain kernel
    −(2/(πE*)) ln(|ξ|/d) of both bodies (engine.kernels.line). Self-consistency: 1e-9."""
    from scipy.integrate import quad

    modulus, radius, load, mu = 109_890.0, 6.0, 185.0, 0.5  # MPa, mm, N/mm, 1
    a = ref.hertz_line_half_width(load, radius, modulus)
    p0 = ref.hertz_line_peak_pressure(load, radius, modulus)

    def integrand(t):  # ξ = a t, an even integrand: twice the half [0, 1]
        return mu * p0 * math.sqrt(1.0 - t * t) * math.log(a * t / datum)

    half, _ = quad(integrand, 0.0, 1.0, limit=200)
    quadrature = -(2.0 / (math.pi * modulus)) * 2.0 * a * half
    closed = ref.line_slip_displacement(load, radius, modulus, mu, datum)
    assert closed == pytest.approx(quadrature, rel=1e-9)
