"""The frictional increment solvers checked against each other and against exact limits.

Two independent methods solve the same increment: the alternation of preconditioned normal
and tangential CG (the default under load control) and FISTA on the coupled map (used under
displacement control and as fallback). They share only the operator, so their agreement to
the solver tolerance checks both. The tangential CG is also checked on its own: the friction
bound frozen, a bound too large to reach gives the linear stick solution, and a tiny one
gives full slip along the slip direction.
"""

import numpy as np
import pytest

import engine.solvers.alternation as alternation
from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.solvers.contact import ContactSolver, with_friction
from engine.solvers.friction import FrictionLaw
from engine.solvers.tangential import ellipse_frame, solve_tangential
from tests.conftest import LOAD, RADIUS


def _solver(material, n, friction, tol=1e-9):
    grid = Grid.square(n, 1.05 * RADIUS)
    return ContactSolver(grid, material, FlatPunch(RADIUS), friction, tol=tol)


def _two_increments(solver):
    half = solver.solve_load(0.5 * LOAD)
    return half, solver.solve_load(LOAD, half.state)


def _fista(solver):
    """The same solver with the alternation replaced by FISTA (the independent method)."""
    clone = with_friction(solver, solver.friction)
    clone.load_control_method = "projected_gradient"
    return clone


@pytest.mark.parametrize(
    "friction",
    [FrictionLaw(0.1, 0.1), FrictionLaw(0.3, 0.3), FrictionLaw(0.1, 0.4, 0.5)],
    ids=["mu0.1", "mu0.3", "ortho"],
)
def test_alternation_agrees_with_fista(material, friction):
    """Both methods at residual 1e-9 on a warm-started increment (32²): tractions agree to
    1e-6 of the peak pressure, the stick/slip map exactly, and each is converged."""
    solver = _solver(material, 32, friction)
    _, ours = _two_increments(solver)
    _, reference = _two_increments(_fista(solver))
    for result in (ours, reference):
        assert result.report.converged, result.report.message
    assert "alternating" in ours.report.message and "accelerated" in reference.report.message
    scale = reference.pressure.max()
    for name in ("pressure", "traction_x", "traction_y"):
        np.testing.assert_allclose(
            getattr(ours, name), getattr(reference, name), atol=1e-6 * scale, err_msg=name
        )
    np.testing.assert_array_equal(ours.status, reference.status)
    assert ours.approach == pytest.approx(reference.approach, rel=1e-7)


@pytest.mark.parametrize(
    "friction", [FrictionLaw(0.1, 0.1), FrictionLaw(0.1, 0.4, 0.5)], ids=["mu0.1", "ortho"]
)
def test_a_guess_changes_where_the_iteration_starts_not_the_answer(material, friction):
    """``solve_load(guess=...)`` (the cyclic warm start): from a perturbed solution of the
    same increment (1 % noise on pressure and tractions) the increment converges to the
    answer of the unguided solve, to 1e-6 of the peak pressure as between the two methods
    above (both at residual 1e-9); from the converged answer itself it returns at once (one
    application: the residual check), unchanged. (A rough guess saves nothing; the smooth
    guesses of the cyclic warm start do: benchmarks/bench_cyclic.py.)"""
    solver = _solver(material, 32, friction)
    half, reference = _two_increments(solver)
    rng = np.random.default_rng(3)
    noisy = reference.state.copy()
    for name in ("pressure", "traction_x", "traction_y"):
        values = getattr(noisy, name)
        values *= 1.0 + 0.01 * rng.standard_normal(values.shape)
    guided = solver.solve_load(LOAD, half.state, guess=noisy)
    assert guided.report.converged, guided.report.message
    scale = reference.pressure.max()
    for name in ("pressure", "traction_x", "traction_y"):
        np.testing.assert_allclose(
            getattr(guided, name), getattr(reference, name), atol=1e-6 * scale, err_msg=name
        )
    again = solver.solve_load(LOAD, half.state, guess=reference.state)
    assert again.report.matvecs == 1 and "0 passes" in again.report.message, again.report.message
    np.testing.assert_array_equal(again.pressure, reference.pressure)


def test_warm_increment_work_does_not_grow_with_the_mesh(material):
    """The scaling target as a deterministic count: operator applications of a
    warm-started μ = 0.2 increment grow by at most 1.5x from 32² to 128² (16x the elements;
    FISTA's grew about 2x over the same range). The benchmark covers 64² to 512²."""
    counts = {}
    for n in (32, 128):
        solver = _solver(material, n, FrictionLaw(0.2, 0.2), tol=1e-8)
        _, warm = _two_increments(solver)
        assert warm.report.converged, warm.report.message
        counts[n] = warm.report.matvecs
    assert counts[128] <= 1.5 * counts[32], counts


def test_fallback_to_fista_when_alternation_does_not_settle(material, monkeypatch):
    """With a single pass allowed the alternation cannot settle; FISTA continues from its
    iterate, converges, and the message says which method finished the increment."""
    monkeypatch.setattr(alternation, "MAX_OUTER", 1)
    solver = _solver(material, 32, FrictionLaw(0.2, 0.2))
    result = solver.solve_load(LOAD)
    assert result.report.converged, result.report.message
    assert "after 1 alternating passes" in result.report.message
    monkeypatch.undo()
    direct = _solver(material, 32, FrictionLaw(0.2, 0.2)).solve_load(LOAD)
    np.testing.assert_allclose(result.pressure, direct.pressure, atol=1e-6 * direct.pressure.max())


def _tangential_setup(material, bound_value):
    """A 32² tangential problem: bound fixed on the punch face, a slip field produced by
    the coupling of the Sneddon-like pressure of a frictionless solve."""
    solver = _solver(material, 32, FrictionLaw(0.3, 0.15, 0.4))
    pressure = with_friction(solver, FrictionLaw(0.0, 0.0)).solve_load(LOAD).pressure
    bound = np.where(pressure > 0, bound_value, 0.0)
    zeros = np.zeros((2, *solver.grid.shape))
    slip = np.array(solver.operator.coupling_to_tangential(pressure))
    slip[:, bound == 0] = 0.0
    return solver, bound, zeros, slip


def _solve_tangential(solver, bound, start, slip):
    """The tangential CG from ``start`` to 1e-12 of the initial RMS slip."""
    count = int(solver.candidate.sum())
    initial = np.sqrt(np.sum(slip**2) / count)
    return solve_tangential(
        solver.operator,
        solver.preconditioner,
        solver.friction,
        bound,
        start,
        slip,
        tol=1e-12 * initial,
        maxiter=500,
        count=count,
        lipschitz=solver.operator.symbol_bound(),
    )


def test_tangential_cg_with_unreachable_bound_is_the_linear_stick_solution(material):
    """Bound 1e6 MPa: nothing slips; the slip A_tt q + c vanishes on the face (1e-12 of
    its initial size, checked with a fresh operator application)."""
    solver, bound, zeros, slip = _tangential_setup(material, 1e6)
    result = _solve_tangential(solver, bound, zeros, slip)
    assert result.converged
    assert result.iterations < 60
    fresh = np.array(solver.operator.apply_tangential(*result.tractions)) + slip
    assert np.abs(fresh[:, bound > 0]).max() < 1e-10 * np.abs(slip).max()
    assert np.all(solver.friction.norm(*result.tractions) < bound + (bound == 0))


def test_tangential_cg_with_tiny_bound_slips_everywhere_along_the_slip(material):
    """Bound 1e-9 MPa: every element slides; the traction sits on its ellipse at the point
    whose outward normal is opposite to the slip (maximal dissipation, Eq. 9–10)."""
    solver, bound, zeros, slip = _tangential_setup(material, 1e-9)
    result = _solve_tangential(solver, bound, zeros, slip)
    assert result.converged
    face = (bound > 0) & (np.hypot(*slip) > 1e-6 * np.abs(slip).max())
    norm = solver.friction.norm(*result.tractions)
    np.testing.assert_allclose(norm[face], bound[face], rtol=1e-9)
    nx, ny, _, _, _ = ellipse_frame(solver.friction, *result.tractions)
    sx, sy = result.slip
    cosine = -(nx * sx + ny * sy) / np.hypot(sx, sy)
    assert np.all(cosine[face] > 1 - 1e-9)
