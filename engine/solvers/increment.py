"""What the increment methods share: the state between increments, the problem of one
increment, the solution a method returns and the result the solver reports.

An increment (Eqs. 1–3, 7–11) is set by the operator A, the friction law, the candidate
elements, the gap with zero tractions and zero approach (``offset``, geometric gap plus
wear, mm) and the slip reference u_t^ref (mm): the slip of tractions q with displacements
u = A x, x = (q_x, q_y, p), is

    Δs = u_t − u_t^ref,    u_t^ref = u_t^prev (tangential displacement of the previous
                                               increment; the punch has no rigid slip)

``IncrementProblem.slip_reference`` is the one place where u_t^ref is formed (by
``ContactSolver._problem``); every method (normal CG, alternation, projected gradient) and
the reported slip read it from there. A rigid tangential displacement of the punch would
enter here and nowhere else.

A frictionless solve does not need the tangential displacement of its pressure (A_xz p,
A_yz p: zero on an uncoupled material) nor the slip it makes: both are cached properties,
computed on their first read (the reported slip, the next increment's slip reference, a
checkpoint) by the same operations as an eager computation, so with the same bits.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..grid import Grid
from ..kernels.operator import HalfSpaceOperator, SpectralPreconditioner
from .friction import FrictionLaw

NO_CONTACT, STICK, SLIP = 0, 1, 2  # status codes of an element


class ContactState:
    """Converged tractions of an increment (MPa), the relative tangential surface
    displacement they produce (mm) and the approach (mm); the start of the next increment.

    ``ContactState.deferred``: the displacement computed on its first read (that of a
    frictionless solve's pressure, which the solve does not need); a pickled state carries
    it computed (the computation holds the operator)."""

    def __init__(
        self,
        pressure: np.ndarray,
        traction_x: np.ndarray,
        traction_y: np.ndarray,
        displacement_x: np.ndarray,
        displacement_y: np.ndarray,
        approach: float = 0.0,
    ):
        self.pressure = pressure
        self.traction_x = traction_x
        self.traction_y = traction_y
        self.displacement = (displacement_x, displacement_y)
        self.approach = approach
        self._compute_displacement: Callable[[], tuple] | None = None

    @classmethod
    def deferred(
        cls,
        pressure: np.ndarray,
        traction_x: np.ndarray,
        traction_y: np.ndarray,
        compute_displacement: Callable[[], tuple],
        approach: float,
    ) -> ContactState:
        """A state whose displacement ``compute_displacement()`` (u_x, u_y) is made when
        first read."""
        state = cls(pressure, traction_x, traction_y, None, None, approach)
        del state.displacement
        state._compute_displacement = compute_displacement
        return state

    @cached_property
    def displacement(self) -> tuple[np.ndarray, np.ndarray]:
        """(u_x, u_y) (mm): given, or made on the first read of a deferred state."""
        compute, self._compute_displacement = self._compute_displacement, None
        return compute()

    @property
    def displacement_known(self) -> bool:
        """Whether the displacement exists (given, or made by a read)."""
        return "displacement" in self.__dict__

    @property
    def displacement_x(self) -> np.ndarray:
        """u_x (mm), made on the first read of a deferred state."""
        return self.displacement[0]

    @property
    def displacement_y(self) -> np.ndarray:
        """u_y (mm), made on the first read of a deferred state."""
        return self.displacement[1]

    def __getstate__(self) -> dict:
        """The state with its displacement made (the computation is not pickled)."""
        return {**self.__dict__, "displacement": self.displacement, "_compute_displacement": None}

    def __repr__(self) -> str:
        return f"ContactState(approach={self.approach!r}, shape={np.shape(self.pressure)})"

    @classmethod
    def unloaded(cls, grid: Grid) -> ContactState:
        # Five np.zeros, not copies of one: untouched zero pages take no memory until written.
        fields = [np.zeros(grid.shape) for _ in range(5)]
        return cls(*fields, 0.0)

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


@dataclass(frozen=True)
class SolveReport:
    """How an increment's solve went (the solver's account, in the manner of
    ``scipy.optimize.OptimizeResult``): ``method`` that finished it, ``iterations``,
    operator applications ``matvecs`` (a frictionless one's on a coupled material include
    the one its tangential displacement takes, made when that is first read), ``residual``
    (relative natural residual, see ``engine.solvers.projected_gradient``), ``converged``
    (residual ≤ tol) and a ``message`` that begins with the method. Built once, by
    :meth:`judge` or :meth:`unloaded`."""

    method: str
    iterations: int
    matvecs: int
    residual: float
    converged: bool
    message: str

    @classmethod
    def judge(cls, method: str, iterations: int, matvecs: int, residual, tol: float):
        """The report of a solve that ended at ``residual``: converged when ≤ ``tol``."""
        residual = float(residual)
        converged = residual <= tol
        message = (
            f"{method} converged in {iterations} iterations (residual {residual:.2e})"
            if converged
            else f"{method} did not converge: residual {residual:.2e} > tol {tol:.1e} "
            f"after {iterations} iterations"
        )
        return cls(method, iterations, matvecs, residual, converged, message)

    @classmethod
    def unloaded(cls) -> SolveReport:
        """Zero load: nothing to solve, exact."""
        message = "zero load: surfaces just touching, no tractions"
        return cls("none", 0, 0, 0.0, True, message)


@dataclass
class IncrementResult:
    """Outcome of one increment. Fields (n_x, n_y): pressure, traction_x, traction_y (MPa);
    slip_x, slip_y: slip increment Δs in contact (mm); status: 0 no contact, 1 stick, 2 slip.
    approach δ (mm), load P (N); ``report``: the :class:`SolveReport` (iterations, operator
    applications, residual, converged, message); ``state``: the start of the next increment.
    The slip Δs = u_t − u_t^ref on the elements ``in_contact`` (u_t: the state's
    displacement, u_t^ref: ``slip_reference``, the previous increment's (u_x, u_y), mm) is
    made on its first read."""

    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    status: np.ndarray
    approach: float
    load: float
    report: SolveReport
    state: ContactState = field(repr=False)
    slip_reference: tuple[np.ndarray, np.ndarray] = field(repr=False)
    in_contact: np.ndarray = field(repr=False)

    @cached_property
    def slip(self) -> tuple[np.ndarray, np.ndarray]:
        """(Δs_x, Δs_y) (mm), zero out of contact; made on the first read."""
        u, u_ref, in_contact = self.state.displacement, self.slip_reference, self.in_contact
        return (
            np.where(in_contact, u[0] - u_ref[0], 0.0),
            np.where(in_contact, u[1] - u_ref[1], 0.0),
        )

    @property
    def slip_x(self) -> np.ndarray:
        """Δs_x (mm), made on the first read."""
        return self.slip[0]

    @property
    def slip_y(self) -> np.ndarray:
        """Δs_y (mm), made on the first read."""
        return self.slip[1]

    def stick_area(self, element_area: float) -> float:
        return float(np.count_nonzero(self.status == STICK) * element_area)

    def slip_area(self, element_area: float) -> float:
        return float(np.count_nonzero(self.status == SLIP) * element_area)

    def contact_area(self, element_area: float) -> float:
        return float(np.count_nonzero(self.status != NO_CONTACT) * element_area)


@dataclass(frozen=True)
class IncrementProblem:
    """One increment's data. ``operator`` A (mm/MPa); ``friction``; ``candidate`` (bool,
    n_x × n_y): elements where the punch has a surface; ``offset`` (mm): gap with zero
    tractions and zero approach; ``reference_displacement`` (u_x, u_y) of the previous
    increment (mm, not copied) and ``slip_reference``, the same stacked (2, n_x, n_y): u_t^ref
    of the module docstring; ``tol`` on the relative natural residual; ``maxiter`` iterations of the
    increment; ``largest_eigenvalue``: the solver's cached power-iteration estimate of A's
    largest eigenvalue on the candidate elements (mm/MPa; the projected-gradient step)."""

    operator: HalfSpaceOperator
    friction: FrictionLaw
    candidate: np.ndarray
    offset: np.ndarray
    reference_displacement: tuple[np.ndarray, np.ndarray]
    tol: float
    maxiter: int
    largest_eigenvalue: Callable[[], float]

    @cached_property
    def slip_reference(self) -> np.ndarray:
        """u_t^ref (2, n_x, n_y) mm, stacked from ``reference_displacement`` (u_x, u_y of the
        previous increment) on its first read: the frictional methods read it at every
        iteration; a frictionless solve never does (its reported slip reads the two fields),
        so it holds no copy of them."""
        return np.array(self.reference_displacement)

    @property
    def preconditioner(self) -> SpectralPreconditioner:
        return self.operator.preconditioner

    @property
    def count(self) -> int:
        """Number of candidate elements (the RMS of the residuals runs over them)."""
        return int(self.candidate.sum())

    @property
    def element_area(self) -> float:
        return self.operator.grid.element_area

    def symbol_bound(self) -> float:
        """Upper bound of A's largest eigenvalue from its Fourier symbol (mm/MPa)."""
        return self.operator.symbol_bound()

    def project_tractions(self, tx, ty, pressure):
        """Closest tractions (MPa) inside the friction ellipses of ``pressure`` (MPa)."""
        if self.friction.frictionless:
            return np.zeros_like(tx), np.zeros_like(ty)
        return self.friction.project(tx, ty, pressure)


@dataclass
class CoupledSolution:
    """What a method found for the increment: ``pressure``, ``traction_x``, ``traction_y``
    (MPa); ``displacement`` (2, n_x, n_y): the tangential displacements u_t = (A x)_t (mm)
    of these tractions, or a function that makes them (a frictionless solve's); ``approach``
    δ (mm); ``iterations``; ``residual`` (relative natural residual); ``method``: the name
    of the method that finished the increment (it begins the message)."""

    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    displacement: np.ndarray | Callable[[], tuple]
    approach: float
    iterations: int
    residual: float
    method: str
