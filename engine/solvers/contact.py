"""One load increment of the frictional contact problem (Eqs. 1–3, 7–11).

Unknowns on the candidate elements (where the punch profile exists): pressure p ≥ 0 and
tangential tractions q = (q_x, q_y) acting on the half-space, with

    gap         g  = g_g + ω − δ + u_n,            u = A [q_x, q_y, p]   (Eqs. 1, 3)
    slip        Δs = u_t − u_t^prev                 (Eq. 2 with the rigid slip g_t,o = 0)
    Signorini   p ≥ 0, g ≥ 0, p g = 0               (Eq. 7)
    Coulomb     ||q||_μ ≤ p; Δs = 0 where ||q||_μ < p; −Δs on the outward normal of the
                ellipse where ||q||_μ = p              (Eqs. 8–11, maximal dissipation)

The rigid tangential slip is zero: the punch carries no tangential load and, by the central
symmetry of the friction ellipse, none arises. Without friction the normal problem alone is
solved by the constrained conjugate gradient method of Polonsky & Keer (Wear 231, 1999) with
a spectral preconditioner. With friction (load control) the normal problem with the
tangential tractions frozen and the tangential problem with the friction bounds frozen are
solved in turn (``solve_tangential``: a preconditioned active-set CG), until neither moves;
both inner solvers and the number of alternations are independent of the mesh. Under
displacement control, and as a fallback, the increment is solved as the fixed point of a
projected gradient map on (p, q), whose gradient is (g, Δs) because the block operator is
symmetric (A_xz = A_zxᵀ, Betti), by FISTA with adaptive restart: the pressure is projected
on {p ≥ 0, Σ p ΔA = P} (load control: δ is the multiplier) or {p ≥ 0}, the tractions on the
ellipse of the new pressure (exact Euclidean projection).

Residual (all methods): RMS over the candidate elements of the natural residual
(x − P(x − α∇))/α, i.e. of the gap and slip violations (mm), divided by the approach δ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..geometry import Profile
from ..grid import Grid
from ..kernels.fft import DEFAULT_EFFORT
from ..kernels.operator import HalfSpaceOperator, SpectralPreconditioner
from ..material import MaterialPair
from ..validation import require_finite, require_finite_array, require_non_negative
from .friction import FrictionLaw
from .tangential import ON_BOUND, solve_tangential

NO_CONTACT, STICK, SLIP = 0, 1, 2
POWER_ITERATIONS = 40  # operator applications of the one-time step-size estimate (per solver)
MAX_OUTER = 60  # normal/tangential alternations before the accelerated gradient takes over
INNER_FACTOR = 0.03  # inner tolerance: this fraction of the last outer residual (0.1: 9 % slower)


@dataclass
class ContactState:
    """Converged tractions of an increment (MPa), the relative tangential surface
    displacement they produce (mm) and the approach (mm); the start of the next increment."""

    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    displacement_x: np.ndarray
    displacement_y: np.ndarray
    approach: float = 0.0

    @classmethod
    def unloaded(cls, grid: Grid) -> ContactState:
        zeros = np.zeros(grid.shape)
        return cls(zeros, zeros.copy(), zeros.copy(), zeros.copy(), zeros.copy(), 0.0)

    def copy(self) -> ContactState:
        return ContactState(
            self.pressure.copy(),
            self.traction_x.copy(),
            self.traction_y.copy(),
            self.displacement_x.copy(),
            self.displacement_y.copy(),
            self.approach,
        )

    def arrays(self) -> dict[str, np.ndarray]:
        return {
            "pressure": self.pressure,
            "traction_x": self.traction_x,
            "traction_y": self.traction_y,
            "displacement_x": self.displacement_x,
            "displacement_y": self.displacement_y,
        }


@dataclass
class IncrementResult:
    """Outcome of one increment. Fields (n_x, n_y): pressure, traction_x, traction_y (MPa);
    slip_x, slip_y: slip increment Δs in contact (mm); status: 0 no contact, 1 stick, 2 slip.
    approach δ (mm), load P (N); iterations, operator applications (matvecs), residual
    (relative, see module doc), converged and a message."""

    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray
    status: np.ndarray
    approach: float
    load: float
    iterations: int
    matvecs: int
    residual: float
    converged: bool
    message: str
    state: ContactState = field(repr=False)

    def stick_area(self, element_area: float) -> float:
        return float(np.count_nonzero(self.status == STICK) * element_area)

    def slip_area(self, element_area: float) -> float:
        return float(np.count_nonzero(self.status == SLIP) * element_area)

    def contact_area(self, element_area: float) -> float:
        return float(np.count_nonzero(self.status != NO_CONTACT) * element_area)


def _project_load(values: np.ndarray, total: float) -> tuple[np.ndarray, float]:
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


class ContactSolver:
    """Frictional contact increments of a punch profile on a half-space (Section 6).

    Parameters: ``grid`` (potential contact zone), ``material``, ``profile`` (geometric gap;
    ``inf`` where the punch has no surface), ``friction``; ``tol`` on the relative residual,
    ``maxiter`` iterations per increment, ``threads`` and ``planner_effort`` for FFTW
    (default "FFTW_ESTIMATE": results bit-reproducible across processes, see
    ``engine.kernels.fft``; "FFTW_MEASURE" may be faster, not reproducible).
    """

    def __init__(
        self,
        grid: Grid,
        material: MaterialPair,
        profile: Profile,
        friction: FrictionLaw,
        *,
        tol: float = 1e-8,
        maxiter: int = 20000,
        threads: int = 1,
        planner_effort: str = DEFAULT_EFFORT,
        operator: HalfSpaceOperator | None = None,
    ):
        profile.check_grid(grid)
        self.tol = require_non_negative("tol", tol)
        if self.tol <= 0.0:
            raise ValueError(f"tol must be > 0, got {tol!r}")
        if isinstance(maxiter, bool) or int(maxiter) != maxiter or maxiter < 1:
            raise ValueError(f"maxiter must be a positive integer, got {maxiter!r}")
        self.maxiter = int(maxiter)
        self.grid = grid
        self.material = material
        self.profile = profile
        self.friction = friction
        self.operator = operator or HalfSpaceOperator(
            grid, material, threads=threads, planner_effort=planner_effort
        )
        self.geometric_gap = profile.gap(grid)
        self.candidate = np.isfinite(self.geometric_gap)
        self._lipschitz: float | None = None
        self._symbol: float | None = None
        self._normal_image: np.ndarray | None = None

    # ----------------------------------------------------------------- public API
    def initial_state(self) -> ContactState:
        return ContactState.unloaded(self.grid)

    def solve_load(
        self,
        load: float,
        state: ContactState | None = None,
        wear: np.ndarray | None = None,
        guess: ContactState | None = None,
    ) -> IncrementResult:
        """Load control: find the approach δ such that the total force is ``load`` (N).

        ``state``: the converged previous increment (its displacements define the slip).
        ``guess``: where the iteration starts (pressure and tractions, MPa), e.g. the same
        increment of the previous simulated cycle; default ``state``. With a guess the
        frictional solver first measures the guess's residual (one operator application)
        and sets its first inner tolerances from it, instead of starting coarse.
        """
        load = require_non_negative("load", load)
        return self._solve(load=load, approach=None, state=state, wear=wear, guess=guess)

    def solve_approach(
        self, approach: float, state: ContactState | None = None, wear: np.ndarray | None = None
    ) -> IncrementResult:
        """Displacement control: rigid approach ``approach`` (mm) is given."""
        approach = require_finite("approach", approach)
        return self._solve(load=None, approach=approach, state=state, wear=wear)

    # ----------------------------------------------------------------- internals
    def _solve(self, load, approach, state, wear, guess=None) -> IncrementResult:
        state = state if state is not None else self.initial_state()
        offset = self.geometric_gap.copy()
        if wear is not None:
            wear = require_finite_array("wear", wear)
            if wear.shape != self.grid.shape:
                raise ValueError(f"wear has shape {wear.shape}, expected {self.grid.shape}")
            offset[self.candidate] += wear[self.candidate]
        if load is not None and load == 0.0:
            return self._unloaded(state, offset)
        if load is None:
            return self._fista(load, approach, state, offset)
        if self.friction.frictionless:
            return self._frictionless(load, guess or state, offset, state)
        return self._alternating(load, state, offset, guess)

    @property
    def step_size_estimate(self) -> float | None:
        """The largest eigenvalue estimate behind the FISTA step (mm/MPa), None until the
        first frictional solve; saved with a checkpoint so that a resumed case continues with
        the same step and does not pay the estimate again."""
        return self._lipschitz

    @step_size_estimate.setter
    def step_size_estimate(self, value: float | None) -> None:
        self._lipschitz = None if value is None else require_non_negative("step size", value)

    @property
    def preconditioner(self) -> SpectralPreconditioner:
        """The operator's spectral preconditioner (shared by solvers of one operator)."""
        return self.operator.preconditioner

    def lipschitz(self) -> float:
        """Largest eigenvalue of A restricted to the candidate elements (power iteration)."""
        if self._lipschitz is None:
            rng = np.random.default_rng(12345)
            vector = np.zeros((3, *self.grid.shape))
            vector[:, self.candidate] = rng.standard_normal((3, int(self.candidate.sum())))
            value = 0.0
            for _ in range(POWER_ITERATIONS):
                vector /= np.linalg.norm(vector)
                image = np.array(self.operator.apply(*vector))
                image[:, ~self.candidate] = 0.0
                value = float(np.sum(vector * image))
                vector = image
            # Power iteration approaches from below: keep a safety margin.
            self._lipschitz = 1.05 * value
        return self._lipschitz

    def _unloaded(self, state: ContactState, offset: np.ndarray) -> IncrementResult:
        zeros = np.zeros(self.grid.shape)
        gap_free = offset[self.candidate]
        new_state = ContactState(
            zeros, zeros.copy(), zeros.copy(), zeros.copy(), zeros.copy(), float(gap_free.min())
        )
        return IncrementResult(
            pressure=zeros,
            traction_x=zeros.copy(),
            traction_y=zeros.copy(),
            slip_x=zeros.copy(),
            slip_y=zeros.copy(),
            status=np.zeros(self.grid.shape, dtype=np.int8),
            approach=new_state.approach,
            load=0.0,
            iterations=0,
            matvecs=0,
            residual=0.0,
            converged=True,
            message="zero load: surfaces just touching, no tractions",
            state=new_state,
        )

    def _finish(
        self,
        pressure,
        traction_x,
        traction_y,
        displacement,
        approach,
        state,
        iterations,
        matvecs,
        residual,
        message_kind,
    ) -> IncrementResult:
        converged = residual <= self.tol
        in_contact = pressure > 0.0
        slip_x = np.where(in_contact, displacement[0] - state.displacement_x, 0.0)
        slip_y = np.where(in_contact, displacement[1] - state.displacement_y, 0.0)
        status = np.zeros(self.grid.shape, dtype=np.int8)
        if self.friction.frictionless:
            status[in_contact] = SLIP
        else:
            ratio = np.zeros(self.grid.shape)
            ratio[in_contact] = (
                self.friction.norm(traction_x[in_contact], traction_y[in_contact])
                / pressure[in_contact]
            )
            status[in_contact] = np.where(ratio[in_contact] >= 1.0 - 1e-9, SLIP, STICK)
        load = float(pressure.sum() * self.grid.element_area)
        message = (
            f"{message_kind} converged in {iterations} iterations (residual {residual:.2e})"
            if converged
            else f"{message_kind} did not converge: residual {residual:.2e} > tol {self.tol:.1e} "
            f"after {iterations} iterations"
        )
        new_state = ContactState(
            pressure, traction_x, traction_y, displacement[0], displacement[1], float(approach)
        )
        return IncrementResult(
            pressure=pressure,
            traction_x=traction_x,
            traction_y=traction_y,
            slip_x=slip_x,
            slip_y=slip_y,
            status=status,
            approach=float(approach),
            load=load,
            iterations=iterations,
            matvecs=matvecs,
            residual=float(residual),
            converged=converged,
            message=message,
            state=new_state,
        )

    def _frictionless(self, load, start_from, offset, state) -> IncrementResult:
        """Frictionless load control: the normal problem alone, from ``start_from``."""
        start = self.operator.applications
        pressure, approach, iterations, residual = self._normal_cg(
            load, start_from.pressure, offset, self.tol
        )
        zeros = np.zeros(self.grid.shape)
        tangential = self.operator.coupling_to_tangential(pressure)
        return self._finish(
            pressure,
            zeros,
            zeros.copy(),
            tangential,
            approach,
            state,
            iterations,
            self.operator.applications - start,
            residual,
            "preconditioned CG",
        )

    def _normal_cg(self, load, initial, offset, tol, maxiter=None, image=None):
        """Signorini problem under load control by Polonsky & Keer's constrained CG with the
        spectral preconditioner (Vollebregt 2014): CG on the contact set, projection on
        p >= 0, restart when elements re-enter contact, rescaling to the load each step.

        ``offset`` is the gap with zero pressure and zero approach (mm). ``image``: A_zz
        ``initial`` (mm) when already known, which saves the first operator application.
        Returns (pressure, approach, iterations, relative residual); ``self._normal_image``
        is then A_zz of the returned pressure, or None if not known.
        """
        grid, mask = self.grid, self.candidate
        target = load / grid.element_area
        count = int(mask.sum())
        pressure = np.zeros(grid.shape)
        known = None
        if initial[mask].sum() > 0.0:
            pressure[mask] = np.maximum(initial[mask], 0.0)
            factor = target / pressure.sum()
            pressure *= factor
            proportional = np.all(initial >= 0.0) and np.array_equal(pressure > 0.0, initial > 0.0)
            if image is not None and proportional:
                known = image * factor  # A (c p) = c A p: the start is a multiple of initial
        else:
            pressure[mask] = target / count
        direction = np.zeros(grid.shape)
        previous = 1.0
        conjugate = False
        residual, approach, iterations = math.inf, 0.0, 0
        self._normal_image = None
        for iterations in range(1, (maxiter or self.maxiter) + 1):  # noqa: B007
            raw = known if known is not None else self.operator.apply_normal(pressure)
            known = None
            gap = raw + offset
            contact = mask & (pressure > 0.0)
            approach = float(gap[contact].mean())
            gap -= approach
            violation = np.where(contact, gap, np.minimum(gap, 0.0))
            residual = math.sqrt(np.sum(violation[mask] ** 2) / count) / abs(approach)
            if residual <= tol:
                self._normal_image = raw
                break
            residual_c = np.where(contact, gap, 0.0)
            z = np.where(contact, self.preconditioner.normal(residual_c), 0.0)
            z[contact] -= z[contact].mean()
            product = float(np.sum(residual_c * z))
            beta = product / previous if conjugate else 0.0
            direction = np.where(contact, z + beta * direction, 0.0)
            previous = product
            image = self.operator.apply_normal(direction)
            image -= image[contact].mean()
            step = float(np.sum(residual_c * direction)) / float(np.sum(image * direction))
            pressure = np.where(contact, pressure - step * direction, 0.0)
            pressure = np.maximum(pressure, 0.0)
            overlap = mask & (pressure <= 0.0) & (gap < 0.0)
            conjugate = not np.any(overlap)
            pressure[overlap] -= step * gap[overlap]
            pressure *= target / pressure.sum()
        return pressure, approach, iterations, residual

    def _alternating(self, load, state, offset, guess=None) -> IncrementResult:
        """Frictional load control by alternation (block Gauss–Seidel, Panagiotopoulos):
        the normal problem with the tangential tractions frozen (preconditioned constrained
        CG), then the tangential problem with the friction bounds frozen (``solve_tangential``),
        until neither moves. Each outer pass contracts the coupling error by a factor set by K
        and μ, not by the mesh, and both inner solvers are mesh independent. Inner tolerances
        follow the outer residual; the reported residual is the natural residual of the
        coupled map (the one FISTA reports) at the final iterate. Should the alternation not
        settle within ``MAX_OUTER`` passes, FISTA continues from its iterate.

        From a ``guess`` (a nearby solution: the same increment one cycle jump earlier), the
        first inner tolerance is ``INNER_FACTOR`` times the guess's own coupled residual
        rather than 0.1, so a good guess saves the coarse passes; a guess that already meets
        the tolerance is returned after that one operator application."""
        mask, operator = self.candidate, self.operator
        count = int(mask.sum())
        start = operator.applications
        previous = np.array([state.displacement_x, state.displacement_y])
        first = guess if guess is not None else state
        pressure = first.pressure
        tractions = np.array([first.traction_x, first.traction_y])
        inner_tol, budget, settled, u = 0.1, self.maxiter, False, None
        if guess is not None and pressure.sum() > 0.0:
            x = np.array([*tractions, pressure])
            u = np.array(operator.apply(*x))
            residual, approach = self._natural_residual(x, u, previous, offset, load)
            # The start is the answer if it meets the tolerance and carries the load exactly
            # (to round-off: an extrapolated start clipped at p = 0 does not).
            exact_load = math.isclose(pressure.sum(), load / self.grid.element_area, rel_tol=1e-12)
            if residual <= self.tol and exact_load:
                return self._finish_alternating(x, u, offset, state, 0, start, residual, 0)
            inner_tol = min(inner_tol, INNER_FACTOR * residual)
        coupling = operator.coupling_to_normal(*tractions)
        image = None if u is None else u[2] - coupling  # A_zz p, known from the guess's check
        for outer in range(1, MAX_OUTER + 1):  # noqa: B007 (count kept after loop)
            tol = max(0.3 * self.tol, inner_tol)
            old_bound = pressure
            pressure, approach, normal_its, _ = self._normal_cg(
                load, pressure, offset + coupling, tol, maxiter=budget, image=image
            )
            image = self._normal_image  # A_zz of this pressure: the next pass starts from it
            budget -= normal_its
            tractions = self._follow_bound(tractions, old_bound, pressure)
            u = np.array(operator.apply(*tractions, pressure))
            tangential = solve_tangential(
                operator,
                self.preconditioner,
                self.friction,
                pressure,
                tractions,
                u[:2] - previous,
                tol=tol * abs(approach),
                maxiter=max(budget, 0),
                count=count,
                lipschitz=self._symbol_bound(),
            )
            budget -= tangential.iterations
            if normal_its == 1 and tangential.iterations == 0:
                # Neither block moved: u = A x exactly; measure the coupled residual.
                x = np.array([*tractions, pressure])
                residual, approach = self._natural_residual(x, u, previous, offset, load)
                if residual <= self.tol:
                    settled = True
                    break
                inner_tol = INNER_FACTOR * residual
            else:
                inner_tol = INNER_FACTOR * max(tol, tangential.residual / abs(approach))
            if budget <= 0:
                break
            tractions = tangential.tractions
            coupling = operator.coupling_to_normal(*tractions)
        x = np.array([*tractions, pressure])
        if not settled:
            u = np.array(operator.apply(*x))
            residual, approach = self._natural_residual(x, u, previous, offset, load)
        if not settled and budget > 0 and residual > self.tol:
            spent = operator.applications - start
            label = f" after {outer} alternating passes"
            return self._fista(load, None, state, offset, start=x, spent=spent, label=label)
        iterations = self.maxiter - max(budget, 0)
        return self._finish_alternating(x, u, offset, state, iterations, start, residual, outer)

    def _finish_alternating(self, x, u, offset, state, iterations, start, residual, passes):
        """The increment result of the alternation at ``x`` = (q_x, q_y, p) with u = A x."""
        pressure = x[2]
        contact = pressure > 0.0
        approach = float(np.mean((u[2] + offset)[contact])) if np.any(contact) else 0.0
        return self._finish(
            pressure,
            x[0],
            x[1],
            u[:2],
            approach,
            state,
            iterations,
            self.operator.applications - start,
            residual,
            f"alternating PCG ({passes} passes)",
        )

    def _follow_bound(self, tractions, old_bound, bound):
        """Tractions for a changed pressure: elements that were sliding (on the ellipse of
        ``old_bound``) stay on the ellipse of ``bound`` (scaled with it), the others are
        projected on the new ellipse."""
        sliding = (old_bound > 0.0) & (self.friction.norm(*tractions) >= ON_BOUND * old_bound)
        factor = np.divide(bound, old_bound, out=np.ones_like(bound), where=sliding)
        return np.array(self._project_tractions(*(tractions * factor), bound))

    def _gradient_map(self, x, u, previous, offset, target, delta, alpha):
        """One projected-gradient step from ``x`` (with ``u = A x``) of length ``alpha``:
        the pressure on {p ≥ 0, Σ p = ``target``} (or {p ≥ 0} at the approach ``delta`` when
        ``target`` is None), the tractions on the ellipse of the new pressure. Returns the
        new point, the approach (the multiplier of the load constraint) and the relative
        natural residual |x − new| / (α δ) (RMS over the candidate elements)."""
        mask = self.candidate
        gradient = np.empty_like(u)
        gradient[:2] = u[:2] - previous
        gradient[2] = u[2] + offset if target is not None else u[2] + offset - delta
        gradient[:, ~mask] = 0.0
        trial = x - alpha * gradient
        new = np.zeros_like(x)
        if target is not None:
            new[2, mask], theta = _project_load(trial[2, mask], target)
            delta = theta / alpha
        else:
            new[2, mask] = np.maximum(trial[2, mask], 0.0)
        new[0], new[1] = self._project_tractions(trial[0], trial[1], new[2])
        scale = abs(delta) if delta != 0.0 else 1.0
        residual = math.sqrt(np.sum((x - new)[:, mask] ** 2) / mask.sum()) / (alpha * scale)
        return new, delta, residual

    def _natural_residual(self, x, u, previous, offset, load):
        """The relative natural residual of the load-controlled increment at ``x``, with
        α = 1 / (bound of A's largest eigenvalue); returns it and the approach."""
        target = load / self.grid.element_area
        alpha = 1.0 / self._symbol_bound()
        _, delta, residual = self._gradient_map(x, u, previous, offset, target, 0.0, alpha)
        return residual, delta

    def _symbol_bound(self) -> float:
        if self._symbol is None:
            self._symbol = self.operator.symbol_bound()
        return self._symbol

    def _fista(
        self, load, approach, state, offset, start=None, spent=0, label=""
    ) -> IncrementResult:
        """Accelerated projected gradient on (q_x, q_y, p) with adaptive restart, from
        ``start`` (q_x, q_y, p) when given (``spent`` operator applications already made)."""
        grid = self.grid
        initial = start
        start = self.operator.applications - spent  # the first solve pays the step estimate
        alpha = 1.0 / self.lipschitz()
        target = None if load is None else load / grid.element_area
        previous = np.array([state.displacement_x, state.displacement_y])

        x = np.zeros((3, *grid.shape))
        if initial is not None:
            x[...] = initial
        elif target is not None:
            # Start from the normal solution with the previous tangential tractions frozen
            # (preconditioned CG: ~10 cheap iterations): FISTA then mostly resolves friction.
            coupling = self.operator.coupling_to_normal(state.traction_x, state.traction_y)
            x[2], _, _, _ = self._normal_cg(load, state.pressure, offset + coupling, self.tol)
        else:
            x[2] = state.pressure
        if initial is None:
            x[0], x[1] = self._project_tractions(state.traction_x, state.traction_y, x[2])
        y = x.copy()
        momentum = 1.0
        residual = math.inf
        delta = approach if approach is not None else state.approach
        iterations = 0
        for iterations in range(1, self.maxiter + 1):  # noqa: B007 (count kept after loop)
            u = np.array(self.operator.apply(*y))
            new, delta, residual = self._gradient_map(y, u, previous, offset, target, delta, alpha)
            step = y - new
            if residual <= self.tol:
                x = new
                break
            # Adaptive restart (O'Donoghue & Candès 2015): drop momentum when it goes uphill.
            if np.sum(step * (new - x)) > 0.0:
                momentum = 1.0
            next_momentum = 0.5 * (1.0 + math.sqrt(1.0 + 4.0 * momentum**2))
            y = new + ((momentum - 1.0) / next_momentum) * (new - x)
            x, momentum = new, next_momentum
        pressure, traction_x, traction_y = x[2], x[0], x[1]
        u_final = self.operator.apply(traction_x, traction_y, pressure)
        displacement = np.array(u_final[:2])
        contact = pressure > 0.0
        if np.any(contact):
            delta = float(np.mean((u_final[2] + offset)[contact]))
        return self._finish(
            pressure,
            traction_x,
            traction_y,
            displacement,
            delta,
            state,
            iterations,
            self.operator.applications - start,
            residual,
            "accelerated projected gradient" + label,
        )

    def project_tractions(self, tx, ty, pressure):
        """Closest tractions (MPa) inside the friction ellipses of ``pressure`` (MPa)."""
        return self._project_tractions(tx, ty, pressure)

    def _project_tractions(self, tx, ty, pressure):
        if self.friction.frictionless:
            return np.zeros_like(tx), np.zeros_like(ty)
        return self.friction.project(tx, ty, pressure)


def with_friction(solver: ContactSolver, friction: FrictionLaw) -> ContactSolver:
    """A solver for another friction law sharing the same operator (plans, kernels)."""
    clone = ContactSolver.__new__(ContactSolver)
    clone.__dict__.update(solver.__dict__)
    clone.friction = friction
    return clone
