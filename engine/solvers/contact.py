"""One load increment of the frictional contact problem (Eqs. 1–3, 7–11): the solver front.

Unknowns on the candidate elements (where the punch profile exists): pressure p ≥ 0 and
tangential tractions q = (q_x, q_y) acting on the half-space, with

    gap         g  = g_g + ω − δ + u_n,            u = A [q_x, q_y, p]   (Eqs. 1, 3)
    slip        Δs = u_t − u_t^prev                 (Eq. 2 with the rigid slip g_t,o = 0)
    Signorini   p ≥ 0, g ≥ 0, p g = 0               (Eq. 7)
    Coulomb     ||q||_μ ≤ p; Δs = 0 where ||q||_μ < p; −Δs on the outward normal of the
                ellipse where ||q||_μ = p              (Eqs. 8–11, maximal dissipation)

The rigid tangential slip is zero: the punch carries no tangential load and, by the central
symmetry of the friction ellipse, none arises. ``ContactSolver`` builds the increment's
problem (``engine.solvers.increment``: the gap offset with the wear, the slip reference) and
chooses the method:

- frictionless, load control: the normal problem alone, Polonsky & Keer's constrained CG with
  the spectral preconditioner (``engine.solvers.normal``);
- frictional, load control: the alternation of the normal block and the tangential block
  (``engine.solvers.alternation``), FISTA as its fallback;
- displacement control: the projected gradient map on (p, q) by FISTA
  (``engine.solvers.projected_gradient``), whose module also defines the residual that all
  methods report (RMS natural residual over the candidate elements, divided by δ).
"""

from __future__ import annotations

import numpy as np

from ..geometry import Profile
from ..grid import Grid
from ..kernels.fft import DEFAULT_EFFORT
from ..kernels.operator import HalfSpaceOperator, SpectralPreconditioner
from ..material import MaterialPair
from ..validation import require_finite, require_finite_array, require_non_negative
from .alternation import solve_alternating
from .defaults import MAX_ITERATIONS, STATIC_TOLERANCE
from .friction import FrictionLaw
from .increment import (
    NO_CONTACT,
    SLIP,
    STICK,
    ContactState,
    CoupledSolution,
    IncrementProblem,
    IncrementResult,
    SolveReport,
)
from .normal import solve_normal
from .projected_gradient import largest_eigenvalue, solve_projected_gradient

__all__ = [
    "NO_CONTACT",
    "STICK",
    "SLIP",
    "ContactState",
    "IncrementResult",
    "SolveReport",
    "ContactSolver",
    "with_friction",
]

LOAD_CONTROL_METHODS = ("alternating", "projected_gradient")


class ContactSolver:
    """Frictional contact increments of a punch profile on a half-space (Section 6).

    Parameters: ``grid`` (potential contact zone), ``material``, ``profile`` (geometric gap;
    ``inf`` where the punch has no surface), ``friction``; ``tol`` on the relative residual,
    ``maxiter`` iterations per increment, ``threads`` and ``planner_effort`` for FFTW
    (default "FFTW_ESTIMATE": results bit-reproducible across processes, see
    ``engine.kernels.fft``; "FFTW_MEASURE" may be faster, not reproducible); ``operator``: a
    shared ``HalfSpaceOperator`` of ``grid`` and ``material`` (built when None).
    ``load_control_method``: "alternating" (default) or "projected_gradient" (FISTA from the
    normal solution; the independent method the tests compare with).
    """

    load_control_method = "alternating"

    def __init__(
        self,
        grid: Grid,
        material: MaterialPair,
        profile: Profile,
        friction: FrictionLaw,
        *,
        tol: float = STATIC_TOLERANCE,
        maxiter: int = MAX_ITERATIONS,
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
        """Largest eigenvalue of A restricted to the candidate elements (power iteration,
        ``engine.solvers.projected_gradient.largest_eigenvalue``), computed once."""
        if self._lipschitz is None:
            self._lipschitz = largest_eigenvalue(self.operator, self.candidate)
        return self._lipschitz

    def project_tractions(self, tx, ty, pressure):
        """Closest tractions (MPa) inside the friction ellipses of ``pressure`` (MPa)."""
        if self.friction.frictionless:
            return np.zeros_like(tx), np.zeros_like(ty)
        return self.friction.project(tx, ty, pressure)

    # ----------------------------------------------------------------- internals
    def _problem(self, state: ContactState, wear: np.ndarray | None) -> IncrementProblem:
        """The increment's problem: gap offset with the wear, and the slip reference
        u_t^ref = the previous increment's tangential displacement (the one place where
        it is formed)."""
        offset = self.geometric_gap.copy()
        if wear is not None:
            wear = require_finite_array("wear", wear)
            if wear.shape != self.grid.shape:
                raise ValueError(f"wear has shape {wear.shape}, expected {self.grid.shape}")
            offset[self.candidate] += wear[self.candidate]
        return IncrementProblem(
            operator=self.operator,
            friction=self.friction,
            candidate=self.candidate,
            offset=offset,
            reference_displacement=tuple(state.displacement),
            tol=self.tol,
            maxiter=self.maxiter,
            largest_eigenvalue=self.lipschitz,
        )

    def _solve(self, load, approach, state, wear, guess=None) -> IncrementResult:
        state = state if state is not None else self.initial_state()
        problem = self._problem(state, wear)
        if load is not None and load == 0.0:
            return self._unloaded(problem)
        start = self.operator.applications
        if load is None:
            solution = solve_projected_gradient(problem, None, approach, state)
        elif self.friction.frictionless:
            solution = self._frictionless(problem, load, guess or state)
        elif self.load_control_method == "projected_gradient":
            solution = solve_projected_gradient(problem, load, None, state)
        else:
            solution = solve_alternating(problem, load, state, guess)
        matvecs = self.operator.applications - start
        if callable(solution.displacement) and self.material.coupling != 0.0:
            matvecs += 1  # its tangential displacement's, made when first read
        return self._result(problem, solution, matvecs)

    def _frictionless(self, problem: IncrementProblem, load, start_from) -> CoupledSolution:
        """Frictionless load control: the normal problem alone, from ``start_from``; the
        projected gradient finishes it should the CG stall. The tangential displacement of
        its pressure (A_xz p, A_yz p), which the CG does not need, is computed when first
        read (the slip, the next increment's reference)."""
        normal = solve_normal(
            self.operator,
            self.candidate,
            load,
            start_from.pressure,
            problem.offset,
            tol=self.tol,
            maxiter=self.maxiter,
        )
        zeros = np.zeros(self.grid.shape)  # untouched zero pages take no memory until written
        if normal.stalled:
            start = np.array([zeros, zeros, normal.pressure])
            label = " after the preconditioned CG stalled"
            return solve_projected_gradient(problem, load, None, start_from, start, label)
        # A copy: a caller may change the result's pressure before the slip is first read.
        operator, pressure = self.operator, normal.pressure.copy()
        return CoupledSolution(
            pressure=normal.pressure,
            traction_x=zeros,
            traction_y=np.zeros(self.grid.shape),  # not a copy: a copy writes its pages
            displacement=lambda: operator.coupling_to_tangential(pressure),
            approach=normal.approach,
            iterations=normal.iterations,
            residual=normal.residual,
            method="preconditioned CG",
        )

    def _unloaded(self, problem: IncrementProblem) -> IncrementResult:
        zeros = np.zeros(self.grid.shape)
        gap_free = problem.offset[self.candidate]
        new_state = ContactState(
            zeros, zeros.copy(), zeros.copy(), zeros.copy(), zeros.copy(), float(gap_free.min())
        )
        result = IncrementResult(
            pressure=zeros,
            traction_x=zeros.copy(),
            traction_y=zeros.copy(),
            status=np.zeros(self.grid.shape, dtype=np.int8),
            approach=new_state.approach,
            load=0.0,
            report=SolveReport.unloaded(),
            state=new_state,
            slip_reference=problem.reference_displacement,
            in_contact=np.zeros(self.grid.shape, dtype=bool),
        )
        result.slip = (zeros.copy(), zeros.copy())
        return result

    def _status(self, pressure, traction_x, traction_y) -> np.ndarray:
        """0 no contact, 1 stick (||q||_μ < p), 2 slip (on the ellipse to 1e-9; every
        element in contact slips without friction)."""
        in_contact = pressure > 0.0
        status = np.zeros(self.grid.shape, dtype=np.int8)
        if self.friction.frictionless:
            status[in_contact] = SLIP
            return status
        ratio = np.zeros(self.grid.shape)
        ratio[in_contact] = (
            self.friction.norm(traction_x[in_contact], traction_y[in_contact])
            / pressure[in_contact]
        )
        status[in_contact] = np.where(ratio[in_contact] >= 1.0 - 1e-9, SLIP, STICK)
        return status

    def _result(self, problem, solution: CoupledSolution, matvecs: int) -> IncrementResult:
        """The reported increment: slip Δs = u_t − u_t^ref in contact (computed when first
        read if the displacement is deferred), status, load and the solve's report
        (converged against the solver's tolerance, the method's message)."""
        pressure = solution.pressure
        displacement = solution.displacement
        report = SolveReport.judge(
            solution.method, solution.iterations, matvecs, solution.residual, self.tol
        )
        approach = float(solution.approach)
        tractions = (pressure, solution.traction_x, solution.traction_y)
        if callable(displacement):
            new_state = ContactState.deferred(*tractions, displacement, approach)
        else:
            new_state = ContactState(*tractions, displacement[0], displacement[1], approach)
        result = IncrementResult(
            pressure=pressure,
            traction_x=solution.traction_x,
            traction_y=solution.traction_y,
            status=self._status(pressure, solution.traction_x, solution.traction_y),
            approach=approach,
            load=float(pressure.sum() * self.grid.element_area),
            report=report,
            state=new_state,
            slip_reference=problem.reference_displacement,
            in_contact=pressure > 0.0,
        )
        if new_state.displacement_known:
            result.slip  # noqa: B018 - made now, from the displacement at hand
        return result


def with_friction(solver: ContactSolver, friction: FrictionLaw) -> ContactSolver:
    """A solver for another friction law sharing the same operator (plans, kernels)."""
    clone = ContactSolver.__new__(ContactSolver)
    clone.__dict__.update(solver.__dict__)
    clone.friction = friction
    return clone
