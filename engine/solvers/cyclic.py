"""Cyclic indentation with orthotropic Archard wear and cycle jumping (Sections 4.3, 7.2, 7.3).

One simulated cycle loads the punch from 0 to P in ``steps`` increments and unloads it back to
0 in ``steps`` increments, each increment solved from the previous one's state. The wear of
the cycle is Σ_k p_k ||Δs_k||_i over its increments (Eq. 14, with Δs the slip increment).

Cycle jumping: the cycle simulated with the wear ω(N) after N real cycles stands for the ΔN
cycles N+1 … N+ΔN, so ω(N+ΔN) = ω(N) + ΔN·Δω_cycle (explicit Euler in the cycle count; the
gap is held fixed within a simulated cycle because one cycle's wear is tiny). ΔN is the
largest integer with ΔN·max(Δω_cycle) ≤ ``max_wear_fraction``·δ(P) (δ: elastic approach at
peak load), at most ``max_jump_growth`` times the previous jump, and cut so that the count
lands exactly on every recorded cycle and on the final one.

Warm start (``CyclicSettings.warm_start = "previous_cycle"``, the default): increment k of a
simulated cycle starts its iteration from the converged increment k of the previous simulated
cycles, which differ from it only by the wear of the jumps, instead of from increment k − 1,
which differs by a whole load step. With two previous cycles x_k(N_1), x_k(N_0) the start is
their linear extrapolation in the cycle count, x_k(N_1) + (N − N_1)/(N_1 − N_0) ·
(x_k(N_1) − x_k(N_0)), projected on p ≥ 0 and the friction ellipses (the wear, hence the
solution, drifts smoothly with N). The history of the increment (the slip reference) is still
increment k − 1; only where the iteration starts changes, so the converged increment is the
same to the solver tolerance. The previous cycles' increments are part of ``CyclicState`` and
of its checkpoint, so a resumed case does the same work bit for bit.
``"previous_increment"`` is the former method (each increment starts from the one before).

Histories hold one row per simulated cycle, describing the state after N real cycles (the
peak-load solution computed with ω(N)). Records hold the peak-load fields at recorded cycles.
With a ``peak_probe`` (e.g. :class:`engine.solvers.peak.PeakTracker`) every row also holds
the probe's values for the peak-load tractions (von Mises peaks, contact radius, peak region);
when the probe returns ``peak_region`` (and ``deep_region``), the peak-load tractions of the
first row and of every row where either differs from the previous row's are kept in
``CyclicState.region_changes``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..schema import CYCLIC_HISTORY_KEYS, HISTORY, RECORDED_FIELDS, contact_units
from ..validation import require_positive
from .contact import SLIP, STICK, ContactSolver, ContactState, IncrementResult
from .defaults import MAX_JUMP_GROWTH, MAX_WEAR_FRACTION
from .friction import WearLaw

# History keys and their units: the results schema (history/<key> of a cyclic case).
HISTORY_KEYS = CYCLIC_HISTORY_KEYS
HISTORY_UNITS = {key: HISTORY[key].units for key in HISTORY_KEYS}
WARM_STARTS = ("previous_cycle", "previous_increment")
WARM_KEYS = ("pressure", "traction_x", "traction_y")
RECORD_KEYS = RECORDED_FIELDS


@dataclass(frozen=True)
class CyclicSettings:
    """``load`` P (N), ``steps`` increments per half cycle, ``cycles`` real cycles to reach,
    ``record``: cycles at which peak-load fields are kept (those beyond ``cycles`` raise),
    ``max_wear_fraction``: wear allowed per jump as a fraction of the peak elastic approach,
    ``max_jump_growth``: largest ratio of consecutive jumps; ``warm_start``: where each
    increment's iteration starts, ``"previous_cycle"`` or ``"previous_increment"`` (see the
    module docstring)."""

    load: float
    steps: int
    cycles: int
    record: tuple[int, ...] = (1000, 10000, 100000)
    max_wear_fraction: float = MAX_WEAR_FRACTION
    max_jump_growth: float = MAX_JUMP_GROWTH
    warm_start: str = "previous_cycle"

    def __post_init__(self) -> None:
        object.__setattr__(self, "load", require_positive("load", self.load))
        object.__setattr__(
            self, "max_wear_fraction", require_positive("max_wear_fraction", self.max_wear_fraction)
        )
        check_schedule(self)


def check_schedule(settings) -> None:
    """Check and normalise (in place, on a frozen dataclass) what cyclic and fretting
    settings share: ``steps`` and ``cycles`` positive integers, ``record`` sorted unique
    cycles in 0 … cycles, ``max_jump_growth`` ≥ 1, ``warm_start`` one of WARM_STARTS."""
    if settings.warm_start not in WARM_STARTS:
        raise ValueError(f"warm_start must be one of {WARM_STARTS}, got {settings.warm_start!r}")
    for name in ("steps", "cycles"):
        value = getattr(settings, name)
        if isinstance(value, bool) or int(value) != value or value < 1:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
        object.__setattr__(settings, name, int(value))
    record = tuple(sorted({int(c) for c in settings.record}))
    for cycle in record:
        if cycle < 0 or cycle > settings.cycles:
            raise ValueError(f"record cycle {cycle} is outside 0 … cycles = {settings.cycles}")
    object.__setattr__(settings, "record", record)
    if not settings.max_jump_growth >= 1.0:
        raise ValueError(f"max_jump_growth must be >= 1, got {settings.max_jump_growth!r}")


@dataclass
class CyclicState:
    """Everything needed to resume a cyclic analysis: wear (mm), the unloaded contact state,
    the real cycle count, the last jump, histories and records so far, and ``warm``: the
    converged increments of the last (at most two) simulated cycles, newest first, with
    ``warm_jump`` real cycles between them (the next cycle's starting points). A plain
    object: checkpoints are written by the study layer (``engine.study.checkpoint``)."""

    wear: np.ndarray
    contact: ContactState
    cycle: int = 0
    jump: int = 0
    history: dict[str, list] = field(default_factory=lambda: {k: [] for k in HISTORY_KEYS})
    records: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)
    region_changes: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)
    matvecs: int = 0
    load_steps: int = 0
    failures: list[str] = field(default_factory=list)
    step_size_estimate: float | None = None
    warm: list[list[ContactState]] = field(default_factory=list)
    warm_jump: int = 0


def _starting_point(state: ContactState, zeros: np.ndarray | None = None) -> ContactState:
    """What a warm start needs of a converged increment: its pressure and tractions (MPa);
    the displacements (unused by a start) are one shared array of zeros."""
    zeros = np.zeros_like(state.pressure) if zeros is None else zeros
    return ContactState(state.pressure, state.traction_x, state.traction_y, zeros, zeros)


@dataclass
class CyclicResult:
    """``completed``: the final cycle was reached (False when stopped early; ``state`` then
    resumes it). ``history``: arrays per simulated cycle (see HISTORY_UNITS); ``records``:
    peak-load fields per recorded cycle; ``final``: peak-load increment of the last simulated
    cycle; ``converged``: every increment reached its tolerance."""

    completed: bool
    state: CyclicState
    history: dict[str, np.ndarray]
    records: dict[int, dict[str, np.ndarray]]
    final: IncrementResult | None
    matvecs: int
    load_steps: int
    converged: bool
    message: str


@dataclass
class _CycleOutcome:
    peak: IncrementResult
    wear_increment: np.ndarray
    end_state: ContactState
    increments: list[ContactState]


class CyclicAnalysis:
    """Runs ``settings.cycles`` real cycles with a contact ``solver`` and a ``wear_law``.

    ``peak_probe(pressure, traction_x, traction_y) -> dict[str, float]``, when given, is called
    with the peak-load tractions (MPa) of every simulated cycle; its values join the history
    row (see :class:`engine.solvers.peak.PeakTracker`).
    """

    def __init__(
        self,
        solver: ContactSolver,
        wear_law: WearLaw,
        settings: CyclicSettings,
        peak_probe: Callable[..., dict[str, float]] | None = None,
    ):
        self.solver = solver
        self.wear_law = wear_law
        self.settings = settings
        self.peak_probe = peak_probe

    def initial_state(self) -> CyclicState:
        grid = self.solver.grid
        return CyclicState(wear=np.zeros(grid.shape), contact=ContactState.unloaded(grid))

    def loads(self) -> np.ndarray:
        """The increment loads of one cycle (N): up in ``steps`` increments, then down."""
        n, load = self.settings.steps, self.settings.load
        up = load * np.arange(1, n + 1) / n
        down = load * np.arange(n - 1, -1, -1) / n
        return np.concatenate([up, down])

    def simulate_cycle(
        self,
        wear: np.ndarray,
        state: ContactState,
        on_increment: Callable[[IncrementResult], None] | None = None,
        guesses: Callable[[int], ContactState] | None = None,
    ) -> _CycleOutcome:
        """One load–unload cycle at fixed wear; returns its peak solution and its wear.
        ``guesses(k)``: where increment k starts (from the previous cycles' increments)."""
        wear_increment = np.zeros_like(wear)
        peak = None
        failures = []
        increments, zeros = [], np.zeros_like(wear)
        load_unit = contact_units("N", self.solver.grid.is_line)
        for index, load in enumerate(self.loads()):
            guess = None if guesses is None else guesses(index)
            result = self.solver.solve_load(load, state, wear=wear, guess=guess)
            increments.append(_starting_point(result.state, zeros))
            if not result.report.converged:
                failures.append(
                    f"increment {index + 1} (P = {load:g} {load_unit}): {result.report.message}"
                )
            wear_increment += self.wear_law.increment(result, state)
            if on_increment is not None:
                on_increment(result)
            if index == self.settings.steps - 1:
                peak = result
            state = result.state
            self._matvecs += result.report.matvecs
            self._steps += 1
        self._failures.extend(failures)
        return _CycleOutcome(
            peak=peak, wear_increment=wear_increment, end_state=state, increments=increments
        )

    def _starting_points(self, state: CyclicState) -> Callable[[int], ContactState] | None:
        """Where increment k of the coming simulated cycle starts: the last simulated cycle's
        increment k, linearly extrapolated in N when there are two (computed when needed, so
        no extra cycle of fields is held)."""
        if not state.warm:
            return None
        warm = state.warm
        if len(warm) == 1 or state.warm_jump <= 0:
            return lambda k: warm[0][k]
        ratio = state.jump / state.warm_jump
        last, before = warm[0], list(warm[1])
        # The state keeps the newest cycle only (the older one is not needed after this
        # cycle), and each increment of the older one is let go once used: the peak holds
        # two cycles of fields, not three. Increment k is asked for once, in order.
        state.warm = warm[:1]

        def start(k: int) -> ContactState:
            previous, before[k] = before[k], None
            return self._extrapolate(last[k], previous, ratio)

        return start

    def _extrapolate(self, last: ContactState, before: ContactState, ratio: float):
        """last + ratio (last − before), pressure ≥ 0, tractions inside its friction ellipse."""
        pressure = np.maximum(last.pressure + ratio * (last.pressure - before.pressure), 0.0)
        tx = last.traction_x + ratio * (last.traction_x - before.traction_x)
        ty = last.traction_y + ratio * (last.traction_y - before.traction_y)
        tx, ty = self.solver.project_tractions(tx, ty, pressure)
        return ContactState(pressure, tx, ty, last.displacement_x, last.displacement_y)

    def _next_stop(self, cycle: int) -> int:
        later = [c for c in self.settings.record if c > cycle]
        return min(later + [self.settings.cycles])

    def _jump(self, cycle: int, previous_jump: int, outcome: _CycleOutcome) -> int:
        settings = self.settings
        largest = float(outcome.wear_increment.max())
        allowed = settings.max_wear_fraction * abs(outcome.peak.approach)
        jump = math.inf if largest <= 0.0 else allowed / largest
        if previous_jump > 0:
            jump = min(jump, settings.max_jump_growth * previous_jump)
        jump = max(1, int(min(jump, self._next_stop(cycle) - cycle)))
        return jump

    def run(
        self,
        state: CyclicState | None = None,
        should_stop: Callable[[], bool] | None = None,
        on_cycle: Callable[[int, int], None] | None = None,
        on_increment: Callable[[IncrementResult, int], None] | None = None,
    ) -> CyclicResult:
        """Advance to ``settings.cycles`` real cycles, or until ``should_stop()`` is true
        (checked between simulated cycles). ``on_cycle(N, cycles)`` reports progress;
        ``on_increment(result, jump_index)`` sees every increment (for audits and tests)."""
        state = state if state is not None else self.initial_state()
        if state.step_size_estimate is not None and self.solver.step_size_estimate is None:
            self.solver.step_size_estimate = state.step_size_estimate
        self._matvecs, self._steps, self._failures = 0, 0, []
        settings, area = self.settings, self.solver.grid.element_area
        final = None
        completed = False
        while True:
            if should_stop is not None and should_stop():
                break
            row_index = len(state.history["cycle"])
            hook = None if on_increment is None else (lambda r, i=row_index: on_increment(r, i))
            warm = self.settings.warm_start == "previous_cycle"
            guesses = self._starting_points(state) if warm else None
            outcome = self.simulate_cycle(state.wear, state.contact, hook, guesses)
            final = outcome.peak
            done = state.cycle >= settings.cycles
            jump = 0 if done else self._jump(state.cycle, state.jump, outcome)
            self._append_history(state, outcome.peak, jump, area)
            if state.cycle in settings.record or done:
                state.records[state.cycle] = self._record(state, outcome)
            self._settle_counts(state)
            if on_cycle is not None:
                on_cycle(state.cycle, settings.cycles)
            if done:
                completed = True
                break
            self._advance(state, outcome, jump, warm)
        return self._result(state, completed, final)

    def _settle_counts(self, state: CyclicState) -> None:
        """Move the simulated cycle's operator applications, increments and failures (and
        the step-size estimate) into the state, which a checkpoint keeps."""
        state.matvecs += self._matvecs
        state.load_steps += self._steps
        state.failures.extend(self._failures)
        state.step_size_estimate = self.solver.step_size_estimate
        self._matvecs, self._steps, self._failures = 0, 0, []

    @staticmethod
    def _advance(state: CyclicState, outcome: _CycleOutcome, jump: int, warm: bool) -> None:
        """Jump ``jump`` real cycles: the simulated cycle's wear increment times the jump,
        its end state, and (warm starts) its increments as the next cycle's starting points."""
        state.wear = state.wear + jump * outcome.wear_increment
        state.contact = outcome.end_state
        if warm:
            state.warm_jump = state.jump if state.warm else 0
            state.warm = [outcome.increments, *state.warm[:1]]
        state.cycle += jump
        state.jump = jump

    def _result(self, state: CyclicState, completed: bool, final) -> CyclicResult:
        """The result of a run that ``completed`` (or was stopped) at ``state``."""
        settings = self.settings
        history = {key: np.asarray(values, dtype=float) for key, values in state.history.items()}
        converged = not state.failures
        if not completed:
            message = f"stopped at cycle {state.cycle} of {settings.cycles}; state saved to resume"
        elif converged:
            message = f"reached {state.cycle} cycles in {len(history['cycle'])} simulated cycles"
        else:
            message = (
                f"{len(state.failures)} increments did not converge; first: {state.failures[0]}"
            )
        return CyclicResult(
            completed=completed,
            state=state,
            history=history,
            records=dict(state.records),
            final=final,
            matvecs=state.matvecs,
            load_steps=state.load_steps,
            converged=converged,
            message=message,
        )

    def _record(self, state: CyclicState, outcome: _CycleOutcome) -> dict[str, np.ndarray]:
        """The fields kept at a recorded cycle: the wear and the peak-load solution."""
        return {
            "wear": state.wear.copy(),
            "pressure": outcome.peak.pressure,
            "traction_x": outcome.peak.traction_x,
            "traction_y": outcome.peak.traction_y,
            "status": outcome.peak.status,
        }

    def _append_history(self, state, peak: IncrementResult, jump: int, area: float) -> None:
        row = {
            "cycle": state.cycle,
            "jump": jump,
            "max_wear_depth": float(state.wear.max()),
            "wear_volume": float(state.wear.sum() * area),
            "peak_pressure": float(peak.pressure.max()),
            "stick_area": float(np.count_nonzero(peak.status == STICK) * area),
            "slip_area": float(np.count_nonzero(peak.status == SLIP) * area),
            "approach": peak.approach,
        }
        if self.peak_probe is not None:
            row.update(self.peak_probe(peak.pressure, peak.traction_x, peak.traction_y))
        rows = len(state.history["cycle"])
        for key, value in row.items():
            # a column the resumed state lacks starts with NaN for the rows before it
            state.history.setdefault(key, [math.nan] * rows).append(value)
        self._keep_region_change(state, peak)

    @staticmethod
    def _keep_region_change(state: CyclicState, peak: IncrementResult) -> None:
        """Keep the peak-load tractions of the first row and of every region change (of the
        overall or of the deep peak)."""
        if not state.history.get("peak_region"):
            return
        columns = [state.history[k] for k in ("peak_region", "deep_region") if k in state.history]
        if len(columns[0]) > 1 and all(_same(c[-1], c[-2]) for c in columns):
            return
        state.region_changes[state.cycle] = {
            "pressure": np.asarray(peak.pressure).copy(),
            "traction_x": np.asarray(peak.traction_x).copy(),
            "traction_y": np.asarray(peak.traction_y).copy(),
        }


def _same(first: float, second: float) -> bool:
    """Equal region codes (NaN equals NaN: no classification in either row)."""
    return first == second or (math.isnan(first) and math.isnan(second))
