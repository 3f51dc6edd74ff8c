"""Tangential fretting: a held normal load and an oscillating rigid tangential motion.

The punch is pressed with the normal load P in ``steps`` load-controlled increments and held;
then it is moved tangentially along the unit vector d = (cos θ, sin θ) (θ = ``direction``)
with the triangle signal 0 → +A → −A → +A …, ``steps`` increments per quarter cycle. A is
either the rigid displacement amplitude (mm, *displacement control*) or the amplitude of the
tangential force component Q·d (N, *force control*).

Slip with a rigid tangential motion (paper Eq. 2, g_t = g_t,o + u_t). Let δ (mm) be the
rigid tangential displacement of the punch and u_t the relative tangential surface
displacement (half-space minus punch, :mod:`.contact`). The half-space slips relative to the
punch by

    Δs = u_t − u_t^prev − (δ − δ^prev),        i.e. g_t,o = −δ,

and the traction q acting on the half-space opposes Δs (maximal dissipation): a punch pushed
towards +x drags the half-space surface along +x, so q_x > 0, Q = Σ q ΔA > 0 and the work
∮ Q·dδ done on the contact is positive. The increment solver needs no new unknown under
displacement control: the rigid increment is a uniform shift of the previous displacement
u_t^prev on every element (:func:`shifted_state`).

Force control: the rig drives the punch along d only (the perpendicular rigid displacement
is held at zero; the force across d is a reaction), and the force component Q·d follows the
prescribed signal. δ·d is the multiplier of that constraint; Q·d(δ) is nondecreasing, so it is
found by a safeguarded secant iteration (regula falsi with the Illinois modification once the
target is bracketed; steps grown by the tangential stiffness until it is), each evaluation an
increment solve warm-started from the previous evaluation (``restart="last"``, the
default) or from the tractions on the secant through the two nearest solutions known on the
line δ = s·d (``restart="secant"``: the increment's start and the evaluations; exact where
every element sticks, since Q and q are then linear in s, so a second evaluation costs one
operator application to certify it). It stops when |Q·d − Q_target| ≤ ``force_tol`` · A.
The first guess is the same increment of the previous simulated cycle (which differs only
by one jump of wear), else the last increment's δ plus ΔQ over the secant stiffness of the
last increment.

Bulk stress (fretting fatigue, line contacts): a stress σ_B along x in the half-space (the
flat specimen) oscillates in phase with the signal, ``bulk_stress_max`` at +A and
``bulk_stress_min`` at −A. Their mean is applied before the normal load and moves no contact
point; after it, every change Δσ_B strains the flat's surface by Δε = (1 − ν_A²) Δσ_B / E_A
(plane strain), a displacement Δε·x measured from the material point under the punch axis
that adds to the slip: Δs = u_t + Δε·x − u_t^prev − Δδ (:func:`shifted_state`). This is
Nowell & Hills' (1987) problem; ``engine.reference.line_contact`` has its stick-zone shift.

One simulated cycle is +A → −A → +A (4·``steps`` increments) starting where the last one
ended; the normal loading and the first quarter 0 → +A are solved once, in
:meth:`FrettingAnalysis.initial_state`. Cycle jumping, warm starts, records and checkpoints
are those of :class:`~engine.solvers.cyclic.CyclicAnalysis`; the wear of a cycle is the sum
over its increments of the wear law's depth increment.

Per simulated cycle (history): ``q_amplitude`` max_k |Q_k| (N); ``displacement_amplitude``
(max_k δ_k·d − min_k δ_k·d)/2 (mm); ``energy`` ∮ Q·dδ by the trapezoidal rule over the cycle's
increments from its starting point (the area of the loop polygon, mJ = N·mm);
``slip_regime`` 0 (partial) or 1 (gross): gross when no element sticks at the increment of
the largest |Q| (status of :mod:`.contact`: an element slips when ||q||_μ ≥ (1 − 10⁻⁹) p);
``stick_area`` at that increment; ``matvecs`` (operator applications) and ``residual`` (the
largest relative residual) of the cycle's increment solves. The "peak" of a cycle (stresses,
the cyclic history's columns, the recorded fields) is the increment of the largest |Q|, taken
on the +Q* half of the loop (signal > 0) whenever that half reaches within ``PEAK_TIE``
(10⁻⁴, relative) of the largest |Q|: a symmetric loop reaches ±Q* equally up to the solver's
tolerance (10⁻⁶), and round-off must not decide which end the fields show. A recorded cycle
also keeps the element states at −Q* (``status_minus_q``: the increment of the largest |Q|
on the −Q* half, signal < 0, the first of equal ones), so that the slip/stick map is known at
both ends of the loop.

Energy consistency (exact to round-off, tested): per increment, with the trapezoidal rule,
½(Q_k + Q_{k−1})·Δδ_k = Σ_e ½(q_k + q_{k−1})·(Δu_k − Δs_k) ΔA, and Σ_e ½(q_k + q_{k−1})·Δu_k ΔA
is the change of the tangential elastic energy ½ Σ q·u_t ΔA when the pressure is unchanged
(K = 0, held load), so ∮ Q·dδ = W_friction + ΔE with W_friction = Σ_k Σ_e −½(q_k + q_{k−1})·Δs_k ΔA,
the local frictional work that the energy wear law (:class:`.friction.EnergyWearLaw`) uses.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .contact import STICK, ContactSolver, ContactState, IncrementResult
from .cyclic import (
    CyclicAnalysis,
    CyclicState,
    _CycleOutcome,
    _starting_point,
    check_schedule,
)
from .defaults import MAX_JUMP_GROWTH, MAX_WEAR_FRACTION
from .friction import WearLaw

DISPLACEMENT, FORCE = "displacement", "force"
LAST, SECANT = "last", "secant"  # where a later force-control evaluation starts
RESTARTS = (LAST, SECANT)
FORCE_TOL = 1e-5  # |Q·d − Q_target| ≤ FORCE_TOL · amplitude (N/N), force control
MAX_EVALUATIONS = 40  # increment solves per force-controlled increment
PEAK_TIE = 1e-4  # |Q| within this (relative) of the cycle's largest: the +Q* increment is the peak
PARTIAL, GROSS = 0, 1
REGIME_NAMES = ("partial", "gross")

# Dataset paths, units and descriptions of the fretting outputs: engine.schema
# (FRETTING_HISTORY, FRETTING_RECORDS).
CYCLE_VM_KEYS = ("vm_cycle_max", "vm_cycle_max_x", "vm_cycle_max_y", "vm_cycle_max_z")


@dataclass(frozen=True)
class FrettingSettings:
    """``load`` P (N, held), ``steps`` increments per quarter tangential cycle (and of the
    normal loading), ``cycles``, ``amplitude`` (mm) XOR ``force_amplitude`` (N),
    ``direction`` θ (degrees from x), ``record``, ``max_wear_fraction``, ``max_jump_growth``,
    ``warm_start`` as :class:`~engine.solvers.cyclic.CyclicSettings`; ``force_tol`` relative
    to the force amplitude. ``bulk_stress_max``/``bulk_stress_min`` (MPa): a bulk stress σ_B
    along x in the half-space (the flat of a fretting-fatigue test), in phase with the signal
    (line contacts only, :meth:`FrettingAnalysis.bulk_strain`)."""

    load: float
    steps: int
    cycles: int
    amplitude: float | None = None
    force_amplitude: float | None = None
    direction: float = 0.0
    record: tuple[int, ...] = ()
    max_wear_fraction: float = MAX_WEAR_FRACTION
    max_jump_growth: float = MAX_JUMP_GROWTH
    warm_start: str = "previous_cycle"
    force_tol: float = FORCE_TOL
    bulk_stress_max: float = 0.0
    bulk_stress_min: float = 0.0

    def __post_init__(self) -> None:
        if (self.amplitude is None) == (self.force_amplitude is None):
            raise ValueError(
                "exactly one of amplitude (mm) and force_amplitude (N) must be given, got "
                f"amplitude={self.amplitude!r}, force_amplitude={self.force_amplitude!r}"
            )
        for name in ("amplitude", "force_amplitude", "load", "max_wear_fraction", "force_tol"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
        for name in ("bulk_stress_max", "bulk_stress_min"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(
                    f"{name} must be a finite number (MPa), got {getattr(self, name)!r}"
                )
        check_schedule(self)

    @property
    def has_bulk_stress(self) -> bool:
        return self.bulk_stress_max != 0.0 or self.bulk_stress_min != 0.0

    def bulk_stress(self, value: float) -> float:
        """σ_B (MPa) at the signal ``value``: in phase with it, ``bulk_stress_max`` at +A and
        ``bulk_stress_min`` at −A, their mean at 0 (applied before the normal load)."""
        mean = 0.5 * (self.bulk_stress_max + self.bulk_stress_min)
        half_range = 0.5 * (self.bulk_stress_max - self.bulk_stress_min)
        return mean + half_range * value / self.signal_amplitude

    @property
    def control(self) -> str:
        return DISPLACEMENT if self.amplitude is not None else FORCE

    @property
    def signal_amplitude(self) -> float:
        """A: mm under displacement control, N under force control."""
        return self.amplitude if self.amplitude is not None else self.force_amplitude

    @property
    def unit_direction(self) -> np.ndarray:
        angle = math.radians(self.direction)
        return np.array([math.cos(angle), math.sin(angle)])

    def quarter(self) -> np.ndarray:
        """Signal values of the first quarter 0 → +A (``steps`` values, the last = A)."""
        return self.signal_amplitude * np.arange(1, self.steps + 1) / self.steps

    def cycle_signal(self) -> np.ndarray:
        """Signal values of one cycle +A → −A → +A (4·steps values, triangle wave)."""
        n, amplitude = self.steps, self.signal_amplitude
        down = amplitude * (1.0 - np.arange(1, 2 * n + 1) / n)
        up = amplitude * (-1.0 + np.arange(1, 2 * n + 1) / n)
        return np.concatenate([down, up])


def shifted_state(
    state: ContactState, rigid_increment: np.ndarray, stretch: np.ndarray | None = None
) -> ContactState:
    """``state`` with its tangential displacements shifted by the rigid increment Δδ (mm):
    the contact solver's slip u_t − u_t^prev then is u_t − u_t^prev − Δδ (Eq. 2, g_t,o = −δ).
    ``stretch`` (mm, (n_x, n_y)): an imposed increment of the half-space's surface
    displacement along x (the bulk strain of :func:`bulk_stretch`), which adds to the slip:
    Δs = u_t + stretch − u_t^prev − Δδ. The arrays are new; ``state`` is unchanged."""
    displacement_x = state.displacement_x + float(rigid_increment[0])
    if stretch is not None:
        displacement_x = displacement_x - stretch
    return ContactState(
        state.pressure,
        state.traction_x,
        state.traction_y,
        displacement_x,
        state.displacement_y + float(rigid_increment[1]),
        state.approach,
    )


def bulk_stretch(grid, strain_increment: float) -> np.ndarray:
    """Δε·x (mm, (n_x, n_y)): the surface displacement along x of the half-space (the flat)
    when its bulk strain along x grows by ``strain_increment`` Δε, measured from the
    material point under the punch axis (x = 0), which the punch's rigid displacement δ
    refers to (fretting fatigue: Nowell & Hills 1987; ``engine.reference.line_contact``)."""
    x, _ = grid.coordinates()
    return strain_increment * x


def total_force(result, element_area: float) -> np.ndarray:
    """Q = Σ q ΔA (N), the tangential force on the half-space, shape (2,)."""
    return np.array(
        [
            float(np.sum(result.traction_x) * element_area),
            float(np.sum(result.traction_y) * element_area),
        ]
    )


@dataclass
class TangentialIncrement:
    """One fretting increment: the contact ``result``, the rigid displacement ``rigid``
    δ (mm, (2,)) and the force ``force`` Q (N, (2,)); ``evaluations`` increment solves,
    ``matvecs`` operator applications; ``force_residual`` |Q·d − Q_target| (N, 0 under
    displacement control); ``converged`` (contact solves and force constraint) and a
    ``message`` naming the method; ``iterations``: the iterations of all its increment
    solves."""

    result: IncrementResult
    rigid: np.ndarray
    force: np.ndarray
    evaluations: int
    matvecs: int
    force_residual: float
    converged: bool
    message: str
    iterations: int = 0


class TangentialDriver:
    """Increments with a prescribed rigid tangential displacement or force (see module doc).

    ``solver``: a :class:`~engine.solvers.contact.ContactSolver` (or a wrapper with the same
    ``solve_load`` and ``project_tractions``); ``load`` P (N) held; ``direction`` d (unit
    (2,)); ``force_tol`` relative to ``force_scale`` (N); ``restart``: where the force
    control's second and later evaluations start, ``"last"`` (the last evaluation's solution)
    or ``"secant"`` (:meth:`secant_guess`; fewer operator applications, other bits)."""

    def __init__(
        self,
        solver: ContactSolver,
        load: float,
        direction,
        force_tol=FORCE_TOL,
        restart: str = LAST,
    ):
        if restart not in RESTARTS:
            raise ValueError(f"restart must be one of {RESTARTS}, got {restart!r}")
        self.solver = solver
        self.load = load
        self.direction = np.asarray(direction, dtype=float)
        self.force_tol = force_tol
        self.restart = restart
        self.area = solver.grid.element_area

    def displacement(self, state, rigid_previous, rigid, wear=None, guess=None, stretch=None):
        """Displacement control: the punch moves from ``rigid_previous`` to ``rigid`` (mm);
        ``stretch``: the half-space's imposed surface displacement increment (mm, field of
        :func:`bulk_stretch`) or None."""
        rigid = np.asarray(rigid, dtype=float)
        increment = rigid - np.asarray(rigid_previous, dtype=float)
        result = self.solver.solve_load(
            self.load, shifted_state(state, increment, stretch), wear=wear, guess=guess
        )
        return TangentialIncrement(
            result,
            rigid,
            total_force(result, self.area),
            1,
            result.report.matvecs,
            0.0,
            result.report.converged,
            f"displacement control: {result.report.message}",
            result.report.iterations,
        )

    def force(self, state, rigid_previous, target, scale, first_guess, stiffness, **options):
        """Force control: find δ = s·d with Q(δ)·d = ``target`` (N) to ``force_tol``·``scale``.

        ``first_guess`` s₀ (mm); ``stiffness`` dQ/ds estimate (N/mm, > 0) for the second
        point and for growing the steps until the target is bracketed. ``options``: ``wear``,
        ``guess`` (the first evaluation's starting point) and ``stretch``. The later
        evaluations start as ``restart`` says (class doc); with ``"secant"`` and no
        ``stretch``, ``state`` is the solution at s = ``rigid_previous``·d."""
        wear, guess, stretch = options.get("wear"), options.get("guess"), options.get("stretch")
        tolerance = self.force_tol * scale
        rigid_previous = np.asarray(rigid_previous, dtype=float)
        evaluations, matvecs, iterations = 0, 0, 0
        low = high = None  # (s, f) with f < 0, f > 0
        points: list[tuple[float, float]] = []
        s, best = float(first_guess), None
        side = 0  # Illinois: the bracket end kept twice in a row
        secant = self.restart == SECANT
        # Solutions known on the line δ = s·d: (s, state); the stretch moves the start off it
        known = [(float(rigid_previous @ self.direction), state)] if stretch is None else []
        while evaluations < MAX_EVALUATIONS:
            step = self.displacement(
                state, rigid_previous, s * self.direction, wear, guess, stretch
            )
            evaluations += 1
            matvecs += step.matvecs
            iterations += step.iterations
            guess = step.result.state
            f = float(step.force @ self.direction) - target
            if best is None or abs(f) < abs(best[1]):
                best = (step, f)
            if abs(f) <= tolerance:
                break
            points.append((s, f))
            if f < 0.0:
                low, side = (s, f), (side - 1 if side <= 0 else -1)
            else:
                high, side = (s, f), (side + 1 if side >= 0 else 1)
            s_next = self._next_point(points, low, high, stiffness, side)
            if secant:
                known = sorted([*known, (s, guess)], key=lambda pair: abs(pair[0] - s_next))[:2]
                if len(known) == 2 and known[0][0] != known[1][0]:
                    guess = self.secant_guess(known, s_next)
            s = s_next
        step, f = best  # the accepted evaluation: its own contact solve must have converged
        solves_converged = step.result.report.converged
        converged = abs(f) <= tolerance and solves_converged
        method = f"force control by safeguarded secant on δ ({evaluations} increment solves)"
        message = (
            f"{method}: |Q·d − Q| = {abs(f):.2e} N"
            if converged
            else f"{method} did not converge: |Q·d − Q| = {abs(f):.2e} N > {tolerance:.1e} N"
            + ("" if solves_converged else f"; {step.result.report.message}")
        )
        return TangentialIncrement(
            step.result,
            step.rigid,
            step.force,
            evaluations,
            matvecs,
            abs(f),
            converged,
            message,
            iterations,
        )

    def secant_guess(self, known, s: float) -> ContactState:
        """The starting point of the evaluation at δ = s·d (mm) from two solutions ``known``
        = ((s_a, state_a), (s_b, state_b)) on that line: x = x_a + t (x_b − x_a) with
        t = (s − s_a)/(s_b − s_a) for x = (p, q_x, q_y) (MPa), then p ≥ 0 and q projected on
        the friction ellipses of p. Exact while the elements stick, where q is linear in s
        (and so is Q: the secant of the force iteration); elsewhere a close start the solve
        corrects. Only its tractions are read (no displacement)."""
        (s_a, a), (s_b, b) = known
        weight = (s - s_a) / (s_b - s_a)

        def between(field: str) -> np.ndarray:
            first, second = getattr(a, field), getattr(b, field)
            return first + weight * (second - first)

        pressure = np.maximum(between("pressure"), 0.0)
        traction_x, traction_y = self.solver.project_tractions(
            between("traction_x"), between("traction_y"), pressure
        )
        approach = a.approach + weight * (b.approach - a.approach)
        return ContactState(pressure, traction_x, traction_y, None, None, approach)

    @staticmethod
    def _next_point(points, low, high, stiffness, side) -> float:
        """The next s: regula falsi (Illinois-weighted) inside a bracket; before one, a secant
        step (slope of the last two points, else ``stiffness``) grown ×2 per evaluation on
        the same side so a flat gross-slip branch cannot stall it."""
        s, f = points[-1]
        if low is not None and high is not None:
            f_low, f_high = low[1], high[1]
            if side <= -2:
                f_high *= 0.5 ** (-side - 1)
            elif side >= 2:
                f_low *= 0.5 ** (side - 1)
            return low[0] - f_low * (high[0] - low[0]) / (f_high - f_low)
        slope = stiffness
        if len(points) >= 2:
            (s0, f0), (s1, f1) = points[-2], points[-1]
            if s1 != s0 and (f1 - f0) / (s1 - s0) > 0.0:
                slope = (f1 - f0) / (s1 - s0)
        growth = 2.0 ** max(len(points) - 2, 0)
        return s - growth * f / slope


@dataclass
class FrettingState(CyclicState):
    """:class:`~engine.solvers.cyclic.CyclicState` plus the rigid tangential displacement δ
    at the start of the next simulated cycle (mm, (2,)), the δ·d of every increment of the
    last simulated cycle (force-control first guesses, mm) and the tangential secant
    stiffness of the last increment (N/mm). Checkpoints: ``engine.study.checkpoint``."""

    rigid: np.ndarray = field(default_factory=lambda: np.zeros(2))
    rigid_warm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stiffness: float = math.nan


@dataclass
class _FrettingCycle:
    """Per-increment data of a simulated cycle (the loop and the force-control guesses)."""

    loop: np.ndarray
    rigid_along: np.ndarray
    evaluations: int
    peak_index: int
    cycle_vm: np.ndarray | None = None
    status_minus_q: np.ndarray | None = None  # element states at −Q* (recorded cycles)
    matvecs: int = 0  # operator applications of the cycle's increment solves
    residual: float = 0.0  # the largest relative residual of the cycle's increment solves


class FrettingAnalysis(CyclicAnalysis):
    """Runs ``settings.cycles`` fretting cycles with a contact ``solver`` and a wear law.

    ``peak_probe`` as for :class:`~engine.solvers.cyclic.CyclicAnalysis`, called with the
    tractions of the increment of the largest |Q| of every simulated cycle.
    ``increment_probe(pressure, tx, ty) -> (value, x, y, z)``, when given, is called on every
    increment of the recorded cycles (of every simulated cycle with ``probe_every_cycle``);
    its largest value over a recorded cycle is kept in the record (``vm_cycle``: value MPa,
    x, y, z mm)."""

    def __init__(
        self,
        solver: ContactSolver,
        wear_law: WearLaw,
        settings: FrettingSettings,
        peak_probe: Callable[..., dict[str, float]] | None = None,
        increment_probe: Callable[..., tuple[float, float, float, float]] | None = None,
    ):
        super().__init__(solver, wear_law, settings, peak_probe)  # type: ignore[arg-type]
        if settings.has_bulk_stress and not solver.grid.is_line:
            raise ValueError(
                "bulk_stress_max/bulk_stress_min apply to line (plane-strain) contacts only"
            )
        self.increment_probe = increment_probe
        # True: the increment probe sees every simulated cycle, not only the recorded ones
        self.probe_every_cycle = False
        self.peak_bulk_stress = 0.0  # σ_B (MPa) at the peak increment of the last cycle
        # Called with σ_B (MPa) before each probe, so that the stresses the probes evaluate
        # include the bulk stress of the increment they look at (line contacts).
        self.bulk_stress_listener: Callable[[float], None] | None = None
        self.driver = TangentialDriver(
            solver, settings.load, settings.unit_direction, settings.force_tol
        )
        self._state: FrettingState | None = None
        self._cycle: _FrettingCycle | None = None

    # ------------------------------------------------------------- start: normal + quarter
    def initial_state(self) -> FrettingState:
        """The normal loading (``steps`` increments, δ = 0) and the first quarter 0 → +A,
        solved once; their operator applications and failures are in the state."""
        grid = self.solver.grid
        state = FrettingState(wear=np.zeros(grid.shape), contact=ContactState.unloaded(grid))
        self._state = state
        contact, approaches, loads = state.contact, [], []
        for index in range(1, self.settings.steps + 1):
            load = self.settings.load * index / self.settings.steps
            result = self.solver.solve_load(load, contact, wear=state.wear)
            self._account(state, result.report, "normal")
            contact = result.state
            approaches.append(result.approach)
            loads.append(load)
        state.stiffness = self._initial_stiffness(loads, approaches)
        rigid, previous = np.zeros(2), 0.0
        for index, value in enumerate(self.settings.quarter()):
            step = self._increment(contact, rigid, (previous, value), state, None, None)
            previous = value
            self._account(state, step, f"first {index}")
            contact, rigid = step.result.state, step.rigid
        state.contact, state.rigid = contact, rigid
        return state

    def _initial_stiffness(self, loads, approaches) -> float:
        """Tangential stiffness guess (N/mm): the normal secant stiffness of the last load
        step times 2(1 − ν)/(2 − ν) (the sphere's ratio, Johnson §7.2; any shape: a guess
        the secant iteration corrects)."""
        nu = self.solver.material.nu_A
        if len(loads) >= 2 and approaches[-1] != approaches[-2]:
            normal = (loads[-1] - loads[-2]) / (approaches[-1] - approaches[-2])
        else:
            normal = loads[-1] / max(abs(approaches[-1]), 1e-300)
        return abs(normal) * 2.0 * (1.0 - nu) / (2.0 - nu)

    def _account(self, state, report, label) -> None:
        """Count a solve's operator applications and keep its failure: ``report`` a
        :class:`~engine.solvers.increment.SolveReport` or a :class:`TangentialIncrement`
        (both carry matvecs, converged and message)."""
        state.matvecs += report.matvecs
        state.load_steps += 1
        if not report.converged:
            state.failures.append(f"{label}: {report.message}")

    def bulk_strain(self, bulk_stress: float) -> float:
        """ε = (1 − ν_A²) σ_B / E_A: the flat's surface strain along x under the bulk stress
        σ_B (MPa) in plane strain (σ_yy = ν_A σ_B; Nowell & Hills 1987)."""
        material = self.solver.material
        return (1.0 - material.nu_A**2) * bulk_stress / material.E_A

    def _stretch(self, previous: float, value: float) -> np.ndarray | None:
        """The flat's surface stretch (mm) when the signal goes from ``previous`` to
        ``value``: the bulk stress's strain increment times x (None without bulk stress)."""
        settings = self.settings
        if not settings.has_bulk_stress:
            return None
        change = settings.bulk_stress(value) - settings.bulk_stress(previous)
        return bulk_stretch(self.solver.grid, self.bulk_strain(change))

    def _increment(self, contact, rigid, values, state, guess, warm):
        """One increment from the signal ``values[0]`` to ``values[1]`` (mm or N) from
        ``contact`` at ``rigid``."""
        settings, direction = self.settings, self.driver.direction
        previous, value = values
        stretch = self._stretch(previous, value)
        if settings.control == DISPLACEMENT:
            return self.driver.displacement(
                contact, rigid, value * direction, state.wear, guess, stretch
            )
        along = float(rigid @ direction)
        now = float(total_force(contact, self.solver.grid.element_area) @ direction)
        first = warm if warm is not None else along + (value - now) / state.stiffness
        step = self.driver.force(
            contact,
            rigid,
            value,
            settings.force_amplitude,
            first,
            state.stiffness,
            wear=state.wear,
            guess=guess,
            stretch=stretch,
        )
        moved = float(step.rigid @ direction) - along
        change = float(step.force @ direction) - now
        if moved != 0.0 and change / moved > 0.0:
            state.stiffness = change / moved
        return step

    # ------------------------------------------------------------- one simulated cycle
    def run(self, state: FrettingState | None = None, **options):
        """As :meth:`CyclicAnalysis.run` (``should_stop``, ``on_cycle``, ``on_increment``)."""
        state = state if state is not None else self.initial_state()
        self._state = state
        return super().run(state=state, **options)

    def simulate_cycle(self, wear, state, on_increment=None, guesses=None) -> _CycleOutcome:
        """One cycle +A → −A → +A from ``state`` (the end of the last one) at fixed wear."""
        fretting, area = self._state, self.solver.grid.element_area
        recorded = self._is_recorded(fretting.cycle)
        rigid = np.asarray(fretting.rigid, dtype=float)
        previous_force = total_force(state, area)
        rows = [[*rigid, *previous_force]]
        wear_increment, increments, zeros = np.zeros_like(wear), [], np.zeros_like(wear)
        along, evaluations, peak, peak_norm, cycle_vm = [], 0, None, -1.0, None
        positive, positive_norm, positive_index = None, -1.0, -1
        negative, negative_norm = None, -1.0  # the −Q* half: its largest |Q|, first if tied
        peak_bulk_stress = positive_bulk_stress = 0.0
        matvecs, largest_residual = 0, 0.0
        warm_rigid = fretting.rigid_warm if len(fretting.rigid_warm) else None
        previous = self.settings.signal_amplitude
        for index, value in enumerate(self.settings.cycle_signal()):
            guess = None if guesses is None else guesses(index)
            warm = None if warm_rigid is None else float(warm_rigid[index])
            step = self._increment(state, rigid, (previous, value), fretting, guess, warm)
            previous = value
            result = step.result
            evaluations += step.evaluations
            self._matvecs += step.matvecs
            matvecs += step.matvecs
            largest_residual = max(largest_residual, float(result.report.residual))
            self._steps += 1
            if not step.converged:
                self._failures.append(f"increment {index + 1} (signal {value:g}): {step.message}")
            wear_increment += self.wear_law.increment(result, state)
            if on_increment is not None:
                on_increment(result)
            norm = float(np.hypot(*step.force))
            if norm > peak_norm:
                peak, peak_norm, peak_index = result, norm, index
                peak_bulk_stress = self.settings.bulk_stress(value)
            if value > 0.0 and norm > positive_norm:  # the +Q* half of the loop
                positive, positive_norm, positive_index = result, norm, index
                positive_bulk_stress = self.settings.bulk_stress(value)
            if value < 0.0 and norm > negative_norm:  # the −Q* half of the loop
                negative, negative_norm = result, norm
            if (recorded or self.probe_every_cycle) and self.increment_probe is not None:
                self._announce_bulk_stress(self.settings.bulk_stress(value))
                probe = np.asarray(self.increment_probe(*_tractions(result)), dtype=float)
                cycle_vm = probe if cycle_vm is None or probe[0] > cycle_vm[0] else cycle_vm
            increments.append(_starting_point(result.state, zeros))
            rows.append([*(step.rigid + 0.0), *step.force])
            along.append(float(step.rigid @ self.driver.direction))
            state, rigid = result.state, step.rigid
        fretting.rigid, fretting.rigid_warm = rigid, np.asarray(along)
        if positive is not None and positive_norm >= (1.0 - PEAK_TIE) * peak_norm:
            peak, peak_index, peak_bulk_stress = positive, positive_index, positive_bulk_stress
        self.peak_bulk_stress = peak_bulk_stress
        self._cycle = _FrettingCycle(np.asarray(rows), np.asarray(along), evaluations, peak_index)
        self._cycle.cycle_vm = cycle_vm
        if recorded and negative is not None:
            self._cycle.status_minus_q = np.array(negative.status, copy=True)
        self._cycle.matvecs, self._cycle.residual = matvecs, largest_residual
        return _CycleOutcome(
            peak=peak, wear_increment=wear_increment, end_state=state, increments=increments
        )

    def _is_recorded(self, cycle: int) -> bool:
        return cycle in self.settings.record or cycle >= self.settings.cycles

    # ------------------------------------------------------------- history and records
    def _announce_bulk_stress(self, bulk_stress: float) -> None:
        if self.bulk_stress_listener is not None:
            self.bulk_stress_listener(bulk_stress)

    def _append_history(self, state, peak: IncrementResult, jump: int, area: float) -> None:
        self._announce_bulk_stress(self.peak_bulk_stress)  # the peak probe sees the peak's σ_B
        super()._append_history(state, peak, jump, area)
        cycle = self._cycle
        loop = cycle.loop
        forces, rigid = loop[:, 2:], loop[:, :2]
        energy = float(
            np.sum(0.5 * (forces[1:] + forces[:-1]) * (rigid[1:] - rigid[:-1]))
        )  # ∮ Q·dδ, N·mm = mJ
        stick = np.count_nonzero(peak.status == STICK)
        row = {
            "q_amplitude": float(np.max(np.hypot(forces[1:, 0], forces[1:, 1]))),
            "displacement_amplitude": 0.5
            * float(cycle.rigid_along.max() - cycle.rigid_along.min()),
            "energy": energy,
            "slip_regime": float(GROSS if stick == 0 else PARTIAL),
            "evaluations": float(cycle.evaluations),
            "matvecs": float(cycle.matvecs),
            "residual": cycle.residual,
        }
        rows = len(state.history["cycle"]) - 1
        for key, value in row.items():
            state.history.setdefault(key, [math.nan] * rows).append(value)

    def _record(self, state, outcome: _CycleOutcome) -> dict[str, np.ndarray]:
        fields = super()._record(state, outcome)
        fields["loop"] = self._cycle.loop
        if self._cycle.cycle_vm is not None:
            fields["vm_cycle"] = self._cycle.cycle_vm
        if self._cycle.status_minus_q is not None:
            fields["status_minus_q"] = self._cycle.status_minus_q
        return fields


def _tractions(result) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return result.pressure, result.traction_x, result.traction_y


def slip_regime_name(code: float) -> str:
    """ "partial" or "gross" from the history's 0/1 code ("" for NaN)."""
    return "" if math.isnan(code) else REGIME_NAMES[int(code)]
