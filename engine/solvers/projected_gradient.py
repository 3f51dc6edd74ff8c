"""The increment as the fixed point of a projected gradient map, solved by FISTA.

The block operator is symmetric (A_xz = A_zxᵀ, Betti), so the increment of Eqs. (1–3, 7–11)
is the minimum of the energy ½ xᵀA x + (offset − δ)ᵀp − u_t^refᵀ q over the admissible
x = (q_x, q_y, p), whose gradient is (Δs, g) = (u_t − u_t^ref, u_n + offset − δ). One step
of length α moves x against the gradient and projects: the pressure on {p ≥ 0, Σ p ΔA = P}
(load control: δ is the multiplier of the load constraint, exact projection by Michelot's
iteration) or on {p ≥ 0} (displacement control, δ given), the tractions on the friction
ellipses of the new pressure (exact Euclidean projection). FISTA (Beck & Teboulle 2009)
accelerates the steps, with adaptive restart (O'Donoghue & Candès 2015); α = 1/L with L the
power-iteration estimate of A's largest eigenvalue on the candidate elements.

Residual (all methods of the package): RMS over the candidate elements of the natural
residual (x − P(x − α∇))/α, i.e. of the gap and slip violations (mm), divided by |δ|.
Used under displacement control, and as the fallback of the alternation.
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels.operator import HalfSpaceOperator
from .increment import ContactState, CoupledSolution, IncrementProblem
from .normal import solve_normal

POWER_ITERATIONS = 40  # operator applications of the one-time step-size estimate (per solver)


def largest_eigenvalue(operator: HalfSpaceOperator, candidate: np.ndarray) -> float:
    """Largest eigenvalue of A restricted to the candidate elements (mm/MPa), by power
    iteration from a fixed random start, times 1.05 (power iteration approaches from
    below: a safety margin)."""
    rng = np.random.default_rng(12345)
    vector = np.zeros((3, *operator.grid.shape))
    vector[:, candidate] = rng.standard_normal((3, int(candidate.sum())))
    value = 0.0
    for _ in range(POWER_ITERATIONS):
        vector /= np.linalg.norm(vector)
        image = np.array(operator.apply(*vector))
        image[:, ~candidate] = 0.0
        value = float(np.sum(vector * image))
        vector = image
    return 1.05 * value


def project_load(values: np.ndarray, total: float) -> tuple[np.ndarray, float]:
    """Euclidean projection of ``values`` on {p ≥ 0, Σ p = total}: p = max(v − θ, 0).

    Michelot's finite iteration: θ increases monotonically to the exact value.
    """
    active = np.ones(values.shape, dtype=bool)
    theta = (values.sum() - total) / values.size
    for _ in range(values.size + 1):
        new_active = values > theta
        if np.array_equal(new_active, active):
            break
        active = new_active
        theta = (values[active].sum() - total) / np.count_nonzero(active)
    return np.maximum(values - theta, 0.0), float(theta)


def gradient_map(problem: IncrementProblem, x, u, target, delta, alpha):
    """One projected-gradient step from ``x`` (with ``u = A x``) of length ``alpha``:
    the pressure on {p ≥ 0, Σ p = ``target``} (or {p ≥ 0} at the approach ``delta`` when
    ``target`` is None), the tractions on the ellipse of the new pressure. Returns the
    new point, the approach (the multiplier of the load constraint) and the relative
    natural residual |x − new| / (α δ) (RMS over the candidate elements)."""
    mask, offset = problem.candidate, problem.offset
    gradient = np.empty_like(u)
    gradient[:2] = u[:2] - problem.slip_reference
    gradient[2] = u[2] + offset if target is not None else u[2] + offset - delta
    gradient[:, ~mask] = 0.0
    trial = x - alpha * gradient
    new = np.zeros_like(x)
    if target is not None:
        new[2, mask], theta = project_load(trial[2, mask], target)
        delta = theta / alpha
    else:
        new[2, mask] = np.maximum(trial[2, mask], 0.0)
    new[0], new[1] = problem.project_tractions(trial[0], trial[1], new[2])
    scale = abs(delta) if delta != 0.0 else 1.0
    change = (x - new)[:, mask]
    residual = math.sqrt(np.vdot(change, change) / mask.sum()) / (alpha * scale)
    return new, delta, residual


def natural_residual(problem: IncrementProblem, x, u, load: float) -> tuple[float, float]:
    """The relative natural residual of the load-controlled increment at ``x`` (u = A x),
    with α = 1 / (the symbol bound of A's largest eigenvalue); returns it and the approach."""
    target = load / problem.element_area
    alpha = 1.0 / problem.symbol_bound()
    _, delta, residual = gradient_map(problem, x, u, target, 0.0, alpha)
    return residual, delta


def _starting_point(problem: IncrementProblem, load, state: ContactState) -> np.ndarray:
    """(q_x, q_y, p) to start from without a given iterate: under load control the normal
    solution with the previous tractions frozen (preconditioned CG, ~10 cheap iterations:
    FISTA then mostly resolves friction), else the previous pressure; the previous
    tractions projected on the ellipses of that pressure."""
    operator = problem.operator
    x = np.zeros((3, *operator.grid.shape))
    if load is not None:
        coupling = operator.coupling_to_normal(state.traction_x, state.traction_y)
        offset = problem.offset + coupling
        x[2] = solve_normal(
            operator,
            problem.candidate,
            load,
            state.pressure,
            offset,
            tol=problem.tol,
            maxiter=problem.maxiter,
        ).pressure
    else:
        x[2] = state.pressure
    x[0], x[1] = problem.project_tractions(state.traction_x, state.traction_y, x[2])
    return x


def solve_projected_gradient(
    problem: IncrementProblem,
    load: float | None,
    approach: float | None,
    state: ContactState,
    start: np.ndarray | None = None,
    label: str = "",
) -> CoupledSolution:
    """FISTA with adaptive restart on (q_x, q_y, p): load control (``load`` N, ``approach``
    None) or displacement control (``approach`` mm); from ``start`` (3, n_x, n_y) when
    given (the alternation's iterate), else from ``_starting_point``. ``state``: the
    previous increment (its approach starts the multiplier). ``label`` ends the method name
    (e.g. " after 60 alternating passes")."""
    operator = problem.operator
    alpha = 1.0 / problem.largest_eigenvalue()
    target = None if load is None else load / problem.element_area
    x = np.zeros((3, *operator.grid.shape))
    if start is not None:
        x[...] = start
    else:
        x = _starting_point(problem, load, state)
    y = x.copy()
    momentum = 1.0
    residual = math.inf
    delta = approach if approach is not None else state.approach
    iterations = 0
    for iterations in range(1, problem.maxiter + 1):  # noqa: B007 (count kept after loop)
        u = np.array(operator.apply(*y))
        new, delta, residual = gradient_map(problem, y, u, target, delta, alpha)
        step = y - new
        if residual <= problem.tol:
            x = new
            break
        # Adaptive restart: drop the momentum when it goes uphill.
        if np.sum(step * (new - x)) > 0.0:
            momentum = 1.0
        next_momentum = 0.5 * (1.0 + math.sqrt(1.0 + 4.0 * momentum**2))
        y = new + ((momentum - 1.0) / next_momentum) * (new - x)
        x, momentum = new, next_momentum
    u_final = operator.apply(x[0], x[1], x[2])
    contact = x[2] > 0.0
    if np.any(contact):
        delta = float(np.mean((u_final[2] + problem.offset)[contact]))
    return CoupledSolution(
        pressure=x[2],
        traction_x=x[0],
        traction_y=x[1],
        displacement=np.array(u_final[:2]),
        approach=delta,
        iterations=iterations,
        residual=residual,
        method="accelerated projected gradient" + label,
    )
