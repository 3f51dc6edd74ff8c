"""Contact solver against analytic solutions.

Tiers: equilibrium and symmetry hold to round-off or solver tolerance; comparisons with
analytic solutions hold to the discretisation error at the stated resolution.
"""

import pickle

import numpy as np
import pytest

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import MaterialPair
from engine.reference.flat_punch import (
    mossakovskii_ratio,
    mossakovskii_ratio_rigid,
    sneddon_approach,
    sneddon_pressure,
)
from engine.solvers.contact import SLIP, STICK, ContactSolver, with_friction
from engine.solvers.friction import FrictionLaw
from engine.solvers.static import static_analysis
from tests.conftest import LOAD, RADIUS


@pytest.mark.validation
def test_frictionless_punch_matches_sneddon(frictionless_64, material, validation):
    """Eq. (18) within 1 % and Eq. (17) within 3 % for r <= 0.8 a0 at 64²."""
    result = frictionless_64.solve_load(LOAD)
    assert result.report.converged, result.report.message
    expected = sneddon_approach(LOAD, RADIUS, material.contact_modulus)
    assert result.approach == pytest.approx(expected, rel=0.01)
    r = frictionless_64.grid.radius()
    inside = r <= 0.8 * RADIUS
    error = np.abs(result.pressure[inside] / sneddon_pressure(r[inside], LOAD, RADIUS) - 1)
    assert error.max() < 0.03
    # The whole punch face is in contact and nothing outside it carries load.
    assert np.all(result.pressure[r <= RADIUS] > 0)
    assert np.all(result.pressure[r > RADIUS] == 0)
    validation.record(
        "frictionless punch, 64²: approach vs Eq. 18", "1 % (discretisation)",
        f"{result.approach / expected - 1:+.2%}",
    )  # fmt: skip
    validation.record(
        "frictionless punch, 64²: pressure vs Eq. 17, r ≤ 0.8 a0", "3 % (discretisation)",
        f"{error.max():.2%}",
    )  # fmt: skip


def test_displacement_control_reproduces_load_control(frictionless_64):
    """The two controls are inverse to each other (within the solver tolerance)."""
    by_load = frictionless_64.solve_load(LOAD)
    by_approach = frictionless_64.solve_approach(by_load.approach)
    assert by_approach.report.converged, by_approach.report.message
    assert by_approach.load == pytest.approx(LOAD, rel=1e-6)


@pytest.mark.validation
def test_equilibrium_is_exact(frictionless_64, validation):
    """Σ p ΔA = P to 1e-8 relative, with and without friction."""
    area = frictionless_64.grid.element_area
    for mu in (0.0, 0.2):
        solver = with_friction(frictionless_64, FrictionLaw(mu, mu))
        result = solver.solve_load(LOAD)
        assert result.pressure.sum() * area == pytest.approx(LOAD, rel=1e-8)
        assert result.load == pytest.approx(LOAD, rel=1e-8)
        validation.record(
            f"equilibrium Σ p ΔA = P, μ = {mu:g}, 64²", "1e-8 rel. (round-off)",
            f"{abs(result.pressure.sum() * area / LOAD - 1):.0e} rel.",
        )  # fmt: skip


@pytest.mark.validation
def test_full_stick_stiffness_matches_mossakovskii(frictionless_64, material, validation):
    """μ = 1 sticks everywhere; k(stick)/k(frictionless) within 0.5 % of Eq. 20 (artanh(β)/β with
    Dundurs' β for E_B = 100 E_A, 1.02745; 1.02863 for a rigid punch)."""
    frictionless = frictionless_64.solve_load(LOAD)
    stuck = with_friction(frictionless_64, FrictionLaw(1.0, 1.0)).solve_load(LOAD)
    assert stuck.report.converged, stuck.report.message
    in_contact = stuck.status != 0
    assert np.all(stuck.status[in_contact] == STICK)
    ratio = frictionless.approach / stuck.approach  # same load: k ∝ 1/approach
    assert ratio == pytest.approx(mossakovskii_ratio(material.dundurs_beta), rel=0.005)
    assert mossakovskii_ratio_rigid(0.3) == pytest.approx(1.02863, rel=1e-5)
    expected = mossakovskii_ratio(material.dundurs_beta)
    validation.record(
        f"full stick (μ = 1), 64²: stiffness ratio vs Mossakovskii artanh(β)/β = {expected:.5f}",
        "0.5 % (discretisation)", f"{ratio:.5f} ({ratio / expected - 1:+.2%})",
    )  # fmt: skip


@pytest.mark.validation
def test_stiffness_rises_monotonically_with_friction(frictionless_64, validation):
    """Fig. 3b: the stiffness ratio grows with μ on 0 … 0.4 (static analysis in two
    increments, path dependent), and the stick zone grows with it."""
    ratios, stick = [], []
    reference = static_analysis(frictionless_64, LOAD, 2).stiffness
    for mu in (0.0, 0.1, 0.2, 0.3, 0.4):
        result = static_analysis(with_friction(frictionless_64, FrictionLaw(mu, mu)), LOAD, 2)
        assert result.converged, result.message
        ratios.append(result.stiffness / reference)
        stick.append(np.count_nonzero(result.final.status == STICK))
    assert np.all(np.diff(ratios) > 0), ratios
    assert np.all(np.diff(stick) >= 0), stick
    assert ratios[0] == pytest.approx(1.0, abs=1e-9)
    validation.record(
        "stiffness ratio rises with μ = 0, 0.1, 0.2, 0.3, 0.4 (Fig. 3b)", "strictly monotone",
        ", ".join(f"{ratio:.4f}" for ratio in ratios),
    )  # fmt: skip


def test_slip_is_outward_for_soft_half_space(frictionless_64):
    """Radial fretting: the half-space surface slides toward the axis under the punch, so
    friction on the half-space points outward in the slip annulus."""
    result = with_friction(frictionless_64, FrictionLaw(0.1, 0.1)).solve_load(LOAD)
    X, Y = frictionless_64.grid.coordinates()
    slip = result.status == SLIP
    radial_traction = (result.traction_x * X + result.traction_y * Y)[slip]
    radial_slip = (result.slip_x * X + result.slip_y * Y)[slip]
    assert np.all(radial_traction > 0)
    assert np.all(radial_slip <= 0)


def test_frictionless_slip_is_computed_when_read_with_the_same_bits(material):
    """A frictionless solve does not compute the tangential displacement of its pressure
    (A_xz p, A_yz p on a coupled material): the slip and the state's displacement are made
    on their first read (the next increment's slip reference reads the state's), from the
    same operations as an eager computation (exact)."""
    grid = Grid.square(24, 1.05 * RADIUS)
    solver = ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(0.0, 0.0))
    operator = solver.operator
    first = solver.solve_load(0.5 * LOAD)
    assert set(operator._spectra) == {"zz"}  # no coupling spectra built by the solve
    second = solver.solve_load(LOAD, first.state)  # reads the first's displacement
    # Reported: the applications of the CG and the one the displacement takes when read.
    assert second.report.matvecs == second.report.iterations + 1
    applications = operator.applications
    slip_x, slip_y = second.slip_x, second.slip_y  # u_t(second) − u_t(first)
    assert operator.applications == applications + 1
    u_first = operator.coupling_to_tangential(first.pressure)
    u_second = operator.coupling_to_tangential(second.pressure)
    contact = second.pressure > 0.0
    assert np.array_equal(slip_x, np.where(contact, u_second[0] - u_first[0], 0.0))
    assert np.array_equal(slip_y, np.where(contact, u_second[1] - u_first[1], 0.0))
    assert np.array_equal(second.state.displacement_x, u_second[0])
    assert np.array_equal(first.state.displacement_y, u_first[1])
    assert np.abs(slip_x).max() > 0.0  # K ≠ 0: the pressure does slide the surfaces
    # A result not read yet travels pickled (to another rank) with its values.
    copied = pickle.loads(pickle.dumps(solver.solve_load(LOAD, first.state)))
    assert np.array_equal(copied.slip_x, slip_x)
    assert np.array_equal(copied.state.displacement_x, u_second[0])


def _rotate_scalar(field):
    """Field of the configuration rotated by +90° about z on a square grid."""
    return np.rot90(field, 1)


def _rotate_vector(fx, fy):
    return -_rotate_scalar(fy), _rotate_scalar(fx)


def test_orthotropic_beta_90_is_rotated_beta_0(material):
    """(μ1, μ2, β = 90°) is the (μ1, μ2, β = 0) law rotated by 90°, which is also the
    (μ2, μ1, β = 0) law; their solutions agree to the solver tolerance (1e-6 relative bounds the
    difference of two solves at residual 1e-9)."""
    grid = Grid.square(32, 1.05 * RADIUS)
    base = ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(0.1, 0.4, 0.0), tol=1e-9)
    at_0 = base.solve_load(LOAD)
    at_90 = with_friction(base, FrictionLaw(0.1, 0.4, np.pi / 2)).solve_load(LOAD)
    swapped = with_friction(base, FrictionLaw(0.4, 0.1, 0.0)).solve_load(LOAD)
    for result in (at_0, at_90, swapped):
        assert result.report.converged, result.report.message
    scale = at_0.pressure.max()
    np.testing.assert_allclose(at_90.pressure, _rotate_scalar(at_0.pressure), atol=1e-6 * scale)
    rx, ry = _rotate_vector(at_0.traction_x, at_0.traction_y)
    np.testing.assert_allclose(at_90.traction_x, rx, atol=1e-6 * scale)
    np.testing.assert_allclose(at_90.traction_y, ry, atol=1e-6 * scale)
    np.testing.assert_allclose(at_90.traction_x, swapped.traction_x, atol=1e-6 * scale)
    np.testing.assert_allclose(at_90.traction_y, swapped.traction_y, atol=1e-6 * scale)
    np.testing.assert_array_equal(at_90.status, _rotate_scalar(at_0.status))
    # And the law really is orthotropic: tractions differ between the x and y axes.
    assert not np.allclose(
        at_0.traction_x, _rotate_vector(at_0.traction_x, at_0.traction_y)[0], atol=1e-3 * scale
    )


def test_non_convergence_is_reported(frictionless_64):
    """An iteration budget too small for the tolerance gives converged = False, not a result
    dressed as converged."""
    solver = with_friction(frictionless_64, FrictionLaw(0.2, 0.2))
    solver.maxiter = 5
    result = solver.solve_load(LOAD)
    assert not result.report.converged
    assert "did not converge" in result.report.message
    assert result.report.residual > solver.tol


@pytest.mark.parametrize(
    ("build", "name"),
    [
        (lambda s: s.solve_load(-1.0), "load"),
        (lambda s: s.solve_load(float("nan")), "load"),
        (lambda s: s.solve_approach(float("inf")), "approach"),
        (lambda s: MaterialPair(200e3, 0.5, 200e5, 0.3), "nu_A"),
        (lambda s: MaterialPair(200e3, 0.3, -1.0, 0.3), "E_B"),
        (lambda s: FrictionLaw(-0.1, -0.1), "mu1"),
        (lambda s: FlatPunch(float("nan")), "radius"),
        (lambda s: static_analysis(s, 100.0, 0), "steps"),
        (lambda s: s.solve_load(100.0, wear=np.full(s.grid.shape, np.nan)), "wear"),
    ],
)
def test_bad_input_raises_value_error_naming_parameter(frictionless_64, build, name):
    """Nothing is silently clipped."""
    with pytest.raises(ValueError, match=name):
        build(frictionless_64)


def test_grid_not_covering_punch_is_rejected(material):
    with pytest.raises(ValueError, match="does not cover the punch radius"):
        ContactSolver(Grid.square(32, 1.5), material, FlatPunch(RADIUS), FrictionLaw(0.0, 0.0))
