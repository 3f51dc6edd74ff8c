"""Frictional load control by alternation (block Gauss–Seidel, Panagiotopoulos).

Each pass solves the normal problem with the tangential tractions frozen (the constrained
CG of ``engine.solvers.normal``, the coupling A_zx q_x + A_zy q_y added to the gap), then
the tangential problem with the friction bounds frozen (``solve_tangential``, a
preconditioned active-set CG), until neither moves. Each pass contracts the coupling error
by a factor set by K and μ, not by the mesh, and both inner solvers are mesh independent.
Inner tolerances follow the outer residual (``INNER_FACTOR`` of it); the reported residual
is the natural residual of the coupled map (``engine.solvers.projected_gradient``) at the
final iterate. Once the inner tolerances are at least as tight as the outer one, every pass
ends with that residual, from displacements the blocks already know (u_t: the slip the
tangential solver updates with A_tt Δq; u_n: A_zz p of the normal solve plus the coupling of
the new tractions, which the next pass needs anyway), so an increment stops as soon as it is
certified, without a further pass to show that nothing moves (3.3 → 2.1 passes per
increment at 64², μ = 0.1). Should the alternation not settle within ``MAX_OUTER`` passes,
or the normal CG stall (``engine.solvers.normal``), FISTA continues from its iterate.

From a ``guess`` (a nearby solution: the same increment one cycle jump earlier), the first
inner tolerance is ``INNER_FACTOR`` times the guess's own coupled residual rather than 0.1,
so a good guess saves the coarse passes; a guess that already meets the tolerance is
returned after that one operator application.

The slip of the tangential block is u_t − ``problem.slip_reference`` (formed once per
increment, see ``engine.solvers.increment``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .increment import ContactState, CoupledSolution, IncrementProblem
from .normal import solve_normal
from .projected_gradient import natural_residual, solve_projected_gradient
from .tangential import ON_BOUND, solve_tangential

MAX_OUTER = 60  # normal/tangential alternations before the accelerated gradient takes over
INNER_FACTOR = 0.03  # inner tolerance: this fraction of the last outer residual (0.1: 9 % slower)
FIRST_INNER = 0.1  # inner tolerance of the first pass without a guess


@dataclass
class _Iterate:
    """The alternation's iterate: tractions (2, n_x, n_y) and pressure (MPa); ``image``:
    A_zz pressure (mm) when known; ``budget``: iterations left; ``inner_tol``."""

    tractions: np.ndarray
    pressure: np.ndarray
    image: np.ndarray | None
    budget: int
    inner_tol: float

    def point(self) -> np.ndarray:
        """x = (q_x, q_y, p), shape (3, n_x, n_y)."""
        return np.array([*self.tractions, self.pressure])


def follow_bound(problem: IncrementProblem, tractions, old_bound, bound) -> np.ndarray:
    """Tractions for a changed pressure: elements that were sliding (on the ellipse of
    ``old_bound``) stay on the ellipse of ``bound`` (scaled with it), the others are
    projected on the new ellipse."""
    sliding = (old_bound > 0.0) & (problem.friction.norm(*tractions) >= ON_BOUND * old_bound)
    factor = np.divide(bound, old_bound, out=np.ones_like(bound), where=sliding)
    return np.array(problem.project_tractions(*(tractions * factor), bound))


def _solution(problem, x, u, iterations, residual, passes) -> CoupledSolution:
    """The alternation's answer at ``x`` = (q_x, q_y, p) with u = A x."""
    pressure = x[2]
    contact = pressure > 0.0
    approach = float(np.mean((u[2] + problem.offset)[contact])) if np.any(contact) else 0.0
    return CoupledSolution(
        pressure=pressure,
        traction_x=x[0],
        traction_y=x[1],
        displacement=u[:2],
        approach=approach,
        iterations=iterations,
        residual=residual,
        method=f"alternating PCG ({passes} passes)",
    )


def _known_displacement(problem, normal_image, coupling, slip) -> np.ndarray:
    """u = A x (3, n_x, n_y) of the pass's iterate from what the blocks computed: u_t =
    slip + slip reference (the tangential solver updates the slip with A_tt Δq at every
    step), u_n = A_zz p + A_zx q_x + A_zy q_y."""
    return np.array([*(slip + problem.slip_reference), normal_image + coupling])


def _start(problem, load, state, guess):
    """The first iterate, and the answer itself when the guess already meets the tolerance
    and carries the load exactly (to round-off: an extrapolated start clipped at p = 0 does
    not). The guess's residual check costs one operator application and gives A_zz p."""
    first = guess if guess is not None else state
    iterate = _Iterate(
        np.array([first.traction_x, first.traction_y]),
        first.pressure,
        None,
        problem.maxiter,
        FIRST_INNER,
    )
    if guess is None or not iterate.pressure.sum() > 0.0:
        return iterate, None
    x = iterate.point()
    u = np.array(problem.operator.apply(*x))
    residual, _ = natural_residual(problem, x, u, load)
    target = load / problem.element_area
    exact_load = math.isclose(iterate.pressure.sum(), target, rel_tol=1e-12)
    if residual <= problem.tol and exact_load:
        return iterate, _solution(problem, x, u, 0, residual, 0)
    iterate.inner_tol = min(iterate.inner_tol, INNER_FACTOR * residual)
    iterate.image = u[2]  # A_zz p + coupling: the coupling is removed by the caller
    return iterate, None


def _normal_pass(problem, load, iterate: _Iterate, coupling, tol):
    """The normal block with the tangential tractions frozen; the tractions follow the new
    pressure (``follow_bound``). Returns the normal solution."""
    old_bound = iterate.pressure
    normal = solve_normal(
        problem.operator,
        problem.candidate,
        load,
        iterate.pressure,
        problem.offset + coupling,
        tol=tol,
        maxiter=iterate.budget,
        image=iterate.image,
    )
    iterate.pressure, iterate.image = normal.pressure, normal.image
    iterate.budget -= normal.iterations
    iterate.tractions = follow_bound(problem, iterate.tractions, old_bound, normal.pressure)
    return normal


def _tangential_pass(problem, iterate: _Iterate, u, tol):
    """The tangential block with the friction bounds frozen, from the iterate's tractions
    whose tangential displacements are ``u[:2]`` (= (A x)_t); slip = u_t − slip_reference."""
    tangential = solve_tangential(
        problem.operator,
        problem.preconditioner,
        problem.friction,
        iterate.pressure,
        iterate.tractions,
        u[:2] - problem.slip_reference,
        tol=tol,
        maxiter=max(iterate.budget, 0),
        count=problem.count,
        lipschitz=problem.symbol_bound(),
    )
    iterate.budget -= tangential.iterations
    return tangential


def solve_alternating(
    problem: IncrementProblem, load: float, state: ContactState, guess: ContactState | None
) -> CoupledSolution:
    """The increment under load control ``load`` (N) from ``guess`` (or from ``state``, the
    previous increment); the projected gradient finishes it if the passes do not settle."""
    operator = problem.operator
    iterate, done = _start(problem, load, state, guess)
    if done is not None:
        return done
    coupling = operator.coupling_to_normal(*iterate.tractions)
    if iterate.image is not None:
        iterate.image = iterate.image - coupling  # A_zz p, known from the guess's check
    settled = False
    for outer in range(1, MAX_OUTER + 1):  # noqa: B007 (count kept after loop)
        tol = max(0.3 * problem.tol, iterate.inner_tol)
        normal = _normal_pass(problem, load, iterate, coupling, tol)
        if normal.stalled:  # the projected gradient below takes the increment over
            break
        u_x, u_y, u_normal = operator.apply_normal_later(*iterate.tractions, iterate.pressure)
        u_t = np.array([u_x, u_y])
        tangential = _tangential_pass(problem, iterate, u_t, tol * abs(normal.approach))
        if normal.iterations == 1 and tangential.iterations == 0:
            # Neither block moved: u = A x exactly; measure the coupled residual.
            u = np.array([u_x, u_y, u_normal()])
            residual, _ = natural_residual(problem, iterate.point(), u, load)
            if residual <= problem.tol:
                settled = True
                break
            iterate.inner_tol = INNER_FACTOR * residual
        else:
            iterate.inner_tol = INNER_FACTOR * max(tol, tangential.residual / abs(normal.approach))
        if iterate.budget <= 0:
            break
        iterate.tractions = tangential.tractions
        coupling = operator.coupling_to_normal(*iterate.tractions)
        if tol <= problem.tol and normal.image is not None:
            # Certify without another pass: u = A x is known from the blocks (the slip the
            # tangential solver tracked, A_zz p of the normal solve and the new coupling).
            u = _known_displacement(problem, normal.image, coupling, tangential.slip)
            residual, _ = natural_residual(problem, iterate.point(), u, load)
            if residual <= problem.tol:
                settled = True
                break
    x = iterate.point()
    if not settled:
        u = np.array(operator.apply(*x))
        residual, _ = natural_residual(problem, x, u, load)
    if not settled and iterate.budget > 0 and residual > problem.tol:
        label = f" after {outer} alternating passes"
        label += " (the normal CG stalled)" if normal.stalled else ""
        return solve_projected_gradient(problem, load, None, state, start=x, label=label)
    iterations = problem.maxiter - max(iterate.budget, 0)
    return _solution(problem, x, u, iterations, residual, outer)
