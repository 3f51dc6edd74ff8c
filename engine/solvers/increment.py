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
A_yz p: zero on an uncoupled material) nor the slip it makes: both are ``Deferred``,
computed on their first read (the reported slip, the next increment's slip reference, a
checkpoint) by the same operations as an eager computation, so with the same bits.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Generic, TypeVar

import numpy as np

from ..grid import Grid
from ..kernels.operator import HalfSpaceOperator, SpectralPreconditioner
from .friction import FrictionLaw

NO_CONTACT, STICK, SLIP = 0, 1, 2  # status codes of an element

Values = TypeVar("Values")


class Deferred(Generic[Values]):
    """Values computed on their first read (``get``) and kept; ``Deferred.known``: values
    at hand. The computation is dropped once done (what it held is released)."""

    __slots__ = ("_compute", "_values")

    def __init__(self, compute: Callable[[], Values]):
        self._compute: Callable[[], Values] | None = compute
        self._values: Values | None = None

    @classmethod
    def known(cls, values: Values) -> Deferred[Values]:
        deferred = cls(None)
        deferred._values = values
        return deferred

    @property
    def done(self) -> bool:
        """Whether the values exist (given, or computed by a read)."""
        return self._compute is None

    def get(self) -> Values:
        if self._compute is not None:
            self._values = self._compute()
            self._compute = None
        return self._values

    def __reduce__(self):
        """Pickled as its values (computed first: the computation holds an operator)."""
        return Deferred.known, (self.get(),)


def _component(deferred: str, index: int, doc: str) -> property:
    """A read-only attribute: component ``index`` of the ``Deferred`` named ``deferred``."""
    return property(lambda self: getattr(self, deferred).get()[index], doc=doc)


class ContactState:
    """Converged tractions of an increment (MPa), the relative tangential surface
    displacement they produce (mm) and the approach (mm); the start of the next increment.

    ``ContactState.deferred``: the displacement computed on its first read (that of a
    frictionless solve's pressure, which the solve does not need)."""

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
        self._displacement = Deferred.known((displacement_x, displacement_y))
        self.approach = approach

    @classmethod
    def deferred(
        cls,
        pressure: np.ndarray,
        traction_x: np.ndarray,
        traction_y: np.ndarray,
        displacement: Deferred,
        approach: float,
    ) -> ContactState:
        """A state whose displacement ``displacement.get()`` (u_x, u_y) is read when needed."""
        state = cls(pressure, traction_x, traction_y, None, None, approach)
        state._displacement = displacement
        return state

    displacement_x = _component("_displacement", 0, "u_x (mm), made on the first read")
    displacement_y = _component("_displacement", 1, "u_y (mm), made on the first read")

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
    applications, residual, converged, message); ``state``: the start of the next increment."""

    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    _slip: Deferred = field(repr=False)  # (slip_x, slip_y), computed on the first read
    status: np.ndarray
    approach: float
    load: float
    report: SolveReport
    state: ContactState = field(repr=False)

    slip_x = _component("_slip", 0, "Δs_x (mm), made on the first read")
    slip_y = _component("_slip", 1, "Δs_y (mm), made on the first read")

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
    tractions and zero approach; ``slip_reference`` (2, n_x, n_y) mm: u_t^ref of the module
    docstring; ``tol`` on the relative natural residual; ``maxiter`` iterations of the
    increment; ``largest_eigenvalue``: the solver's cached power-iteration estimate of A's
    largest eigenvalue on the candidate elements (mm/MPa; the projected-gradient step)."""

    operator: HalfSpaceOperator
    friction: FrictionLaw
    candidate: np.ndarray
    offset: np.ndarray
    slip_reference: np.ndarray
    tol: float
    maxiter: int
    largest_eigenvalue: Callable[[], float]

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
    of these tractions, or a ``Deferred`` of them (a frictionless solve's); ``approach``
    δ (mm); ``iterations``; ``residual`` (relative natural residual); ``method``: the name
    of the method that finished the increment (it begins the message)."""

    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    displacement: np.ndarray | Deferred
    approach: float
    iterations: int
    residual: float
    method: str
