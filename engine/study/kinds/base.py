"""The protocol of a loading kind: what ``[loading] kind = "<name>"`` brings to a study.

A loading kind is one module of :mod:`engine.study.kinds` with one subclass of
:class:`LoadingKind`, registered in the table :data:`engine.study.kinds.KINDS`. The study
layer asks the kind, never branches on its name:

==========================  ==============================================================
what                        member
==========================  ==============================================================
configuration section       :attr:`~LoadingKind.config` (its ``[loading]`` section, a
                            frozen dataclass whose fields are the keys it accepts, each
                            number declaring its :class:`engine.keys.Key`),
                            :meth:`~LoadingKind.parse` (read and check them),
                            :attr:`~LoadingKind.has_cycles` (cycles, wear, cycle jumps),
                            :attr:`~LoadingKind.default_tolerance`
physical checks of a case   :meth:`~LoadingKind.check_case` (refused before anything runs)
case runner                 :meth:`~LoadingKind.run` (one case → :class:`CaseOutcome`)
results datasets            :attr:`~LoadingKind.history` (its ``history/<key>`` tables of
                            :mod:`engine.schema`), :attr:`~LoadingKind.records` (datasets
                            added to each recorded cycle), :meth:`~LoadingKind.layout`
                            (their shapes, for the collective writer),
                            :meth:`~LoadingKind.recorded_cycles`,
                            :meth:`~LoadingKind.plane_angle`
checkpoint state            :meth:`~LoadingKind.save_state`, :meth:`~LoadingKind.load_state`
memory estimate             :meth:`~LoadingKind.increments` (increments per simulated cycle)
scheduling                  :meth:`~LoadingKind.cycle_cost` (relative cost of the cycles)
report and figures          :meth:`~LoadingKind.describe` (the run's one-line summary),
                            :attr:`~LoadingKind.report`, :attr:`~LoadingKind.figures`
                            (``"module:function"`` of the analysis layer, imported when a
                            report or the figures are made; kinds import no analysis),
                            :attr:`~LoadingKind.figures_per_case`
==========================  ==============================================================

The kind receives a :class:`~engine.study.outcome.CaseContext` from the case runner (the
solver and stress builders, the checkpoint path, the progress hook) and builds its outcome
from the shared pieces of :mod:`engine.study.outcome`. A kind module imports no other kind's
module: what two kinds share lives here or in :mod:`engine.study.outcome`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

from engine import schema
from engine.keys import Key, declared_keys
from engine.schema import DatasetSpec
from engine.solvers import defaults
from engine.study.outcome import INTERRUPTED, CaseContext, CaseOutcome
from engine.study.plan import Case
from engine.study.settings.checks import bound_of
from engine.study.settings.sections import (
    LoadingConfig,
    loading_key,
    loading_list,
    steps_key,
)

if TYPE_CHECKING:  # annotations only
    from engine.study.config import StudyConfig
    from engine.study.settings.reader import Section

__all__ = ["LoadingKind", "CycledKind", "CycledLoading", "parse_cycles", "CYCLE_KEYS"]


@dataclass(frozen=True)
class CycledLoading(LoadingConfig):
    """The ``[loading]`` keys of every kind with load cycles (:func:`parse_cycles`), after
    those of every kind (``steps`` counts the increments of a half cycle 0 → P; a kind that
    counts otherwise declares ``steps`` again with its meaning)."""

    steps: int = steps_key("load increments per half cycle")
    cycles: int = loading_key(
        "1",
        "load cycles N to simulate, with cycle jumping",
        label="load cycles N",
        minimum=1,
        maximum=10**9,
        why="fretting tests run 10^7 to 10^8 cycles",
    )
    record: tuple[int, ...] = loading_list(
        "cycles at which the surface fields and stresses are stored (0 = unworn)",
        absent="[cycles]",
    )
    max_wear_fraction: float = loading_key(
        "1",
        "cycle-jump control: the largest wear per jump as a fraction of the peak elastic approach",
        default=defaults.MAX_WEAR_FRACTION,
        label="largest wear per jump / approach",
        minimum=0.0,
        strict=True,
        maximum=1.0,
        why="wear per cycle jump over the peak elastic approach: beyond 1 a jump removes "
        "the whole elastic approach and the jump control no longer holds",
    )


#: [loading] keys of every kind with load cycles (parsed by :func:`parse_cycles`).
CYCLE_KEYS = frozenset(field.name for field in dataclasses.fields(CycledLoading)) - frozenset(
    field.name for field in dataclasses.fields(LoadingConfig)
)


class LoadingKind:
    """One loading kind (module docstring). Subclasses set the class attributes and
    implement :meth:`parse` and :meth:`run`; the other members have working defaults for a
    kind without cycles."""

    #: ``[loading] kind`` value.
    name: ClassVar[str] = ""
    #: One line for the study-file reference.
    summary: ClassVar[str] = ""
    #: Its ``[loading]`` section: a frozen dataclass whose fields are the keys it accepts
    #: (``kind``, ``load`` and ``steps`` of :class:`LoadingConfig` first), each number
    #: declaring its :class:`engine.keys.Key` (unit, meaning, default) in the field's metadata.
    config: ClassVar[type[LoadingConfig]] = LoadingConfig
    #: Load cycles with wear, records and cycle jumps (a wear law applies).
    has_cycles: ClassVar[bool] = False
    #: Increments of one simulated cycle per ``[loading] steps`` (0: no cycles).
    increments_per_step: ClassVar[int] = 0
    #: Default ``[solver] tol`` (relative residual).
    default_tolerance: ClassVar[float] = defaults.STATIC_TOLERANCE
    #: The ``history/<key>`` tables of :mod:`engine.schema` it writes, first match wins.
    history: ClassVar[tuple[Mapping[str, DatasetSpec], ...]] = (schema.STATIC_HISTORY,)
    #: Datasets it adds to every recorded cycle (``fields/cycle_<N>/<name>``).
    records: ClassVar[Mapping[str, DatasetSpec]] = {}

    #: ``"module:function"`` of its report, ``report(study, cycles) -> str`` (Markdown),
    #: and figures, ``figures(study) -> iterator of (file name, figure)``, in the analysis
    #: layer (``study``: engine.analysis.results.Results).
    report: ClassVar[str] = "engine.analysis.report:standard_report"
    figures: ClassVar[str] = "engine.analysis.figures:static_figures"
    #: Its figures are drawn per case, each with its own a0 and p0 (no shared normalisation).
    figures_per_case: ClassVar[bool] = False

    # ------------------------------------------------------------ configuration
    @property
    def keys(self) -> frozenset[str]:
        """The ``[loading]`` keys this kind accepts: the fields of :attr:`config`."""
        return frozenset(field.name for field in dataclasses.fields(self.config))

    @classmethod
    def declared_keys(cls) -> dict[str, Key]:
        """{key: :class:`engine.keys.Key`} of the numbers of its ``[loading]`` section, in
        the order of :attr:`config`'s fields."""
        return declared_keys(cls.config)

    def parse(self, s: Section, load: float, steps: int) -> LoadingConfig:
        """The ``[loading]`` section (``s``, unknown keys already refused) with its checks;
        ``load`` (N) and ``steps`` are read already."""
        raise NotImplementedError

    def check_case(self, case: Case, config: StudyConfig) -> None:
        """Raise ValueError when ``case`` cannot be computed under ``config`` (the plan is
        refused at once, exit code 2). Nothing by default."""

    # ------------------------------------------------------------ the case
    def run(
        self,
        context: CaseContext,
        case: Case,
        config: StudyConfig,
        should_stop: Callable[[], bool],
    ) -> CaseOutcome:
        """Run (or resume) ``case``; an interrupted case saves its state to
        ``context.checkpoint_path(case)`` and comes back ``interrupted``."""
        raise NotImplementedError

    def plane_angle(self, config: StudyConfig) -> float:
        """Angle (degrees from x) of the vertical stress plane through the axis: 0, the x–z
        plane."""
        return 0.0

    # ------------------------------------------------------------ results datasets
    def history_spec(self, key: str) -> DatasetSpec:
        """Units and description of ``history/<key>`` (KeyError for a key it does not
        declare)."""
        for table in self.history:
            if key in table:
                return table[key]
        raise KeyError(f"{key!r} is not a history dataset of the {self.name} kind")

    def record_spec(self, name: str, cycle: int) -> DatasetSpec:
        """``fields/cycle_<N>/<name>`` of the kind's own records (:attr:`records`)."""
        if name not in self.records:
            raise KeyError(f"{name!r} is not a recorded dataset of the {self.name} kind")
        spec = self.records[name]
        return DatasetSpec(spec.units, f"{spec.description}, cycle {cycle}", spec.columns)

    def recorded_cycles(self, config: StudyConfig) -> list[int]:
        """Cycles whose fields a completed case stores (none without cycles)."""
        return []

    def record_shapes(self, config: StudyConfig) -> dict[str, tuple[tuple[int, ...], str]]:
        """{name: (shape, dtype)} of the datasets of :attr:`records` in a recorded cycle."""
        return {}

    # ------------------------------------------------------------ checkpoint state
    def save_state(self, state: Any, path: Path) -> None:
        """Write an interrupted case's solver state to ``path`` (.npz), atomically."""
        raise NotImplementedError(f"the {self.name} kind has no checkpoint")

    def load_state(self, path: Path) -> Any:
        """The state :meth:`save_state` wrote at ``path``."""
        raise NotImplementedError(f"the {self.name} kind has no checkpoint")

    # ------------------------------------------------------------ resources
    def increments(self, steps: int) -> int:
        """Load increments of one simulated cycle (memory estimate; 0 without cycles)."""
        return self.increments_per_step * int(steps)

    def cycle_cost(self, config: StudyConfig) -> float:
        """Relative cost of the cycles of a case (scheduling): 1 without cycles."""
        return 1.0

    # ------------------------------------------------------------ report
    def describe(self, config: StudyConfig, value: Callable[..., str]) -> str:
        """One line on the loading; ``value(name, first, unit)`` gives a ``[loading]`` key's
        value or, when swept, its range over the plan."""
        return f"{self.name}, P = {value('load', config.loading.load, config.punch.load_unit)}"


class CycledKind(LoadingKind):
    """What every kind with load cycles shares: the keys ``cycles``, ``record`` and
    ``max_wear_fraction`` (:func:`parse_cycles`), the recorded cycles (the record list and
    the last), the cyclic solvers' tolerance and a cost growing like the logarithm of the
    cycles (cycle jumps)."""

    config = CycledLoading
    has_cycles = True
    default_tolerance = defaults.CYCLIC_TOLERANCE

    def parse(self, s: Section, load: float, steps: int) -> LoadingConfig:
        s.check_known(self.keys)
        return self.config(**parse_cycles(s, self.name, load, steps))

    def recorded_cycles(self, config: StudyConfig) -> list[int]:
        return sorted({int(c) for c in config.loading.record} | {int(config.loading.cycles)})

    def cycle_cost(self, config: StudyConfig) -> float:
        return math.log10(10.0 + config.loading.cycles)

    def checkpoint(self, context: CaseContext, case: Case):
        """(checkpoint path, the saved state or None) of ``case``."""
        path = context.checkpoint_path(case)
        return path, (self.load_state(path) if path.exists() else None)

    def interrupted(self, case: Case, state: Any, path: Path, extra=None) -> CaseOutcome:
        """Save ``state`` to ``path`` (atomic: temporary file + rename), with the ``extra``
        arrays of the case's analyses where the kind keeps any (fretting: the evaluated
        fatigue cycles); the outcome says where."""
        path.parent.mkdir(parents=True, exist_ok=True)
        if extra is None:
            self.save_state(state, path)
        else:
            self.save_state(state, path, extra)
        message = f"stopped at cycle {state.cycle}; state saved to {path}"
        return CaseOutcome(case, INTERRUPTED, message=message)


def parse_cycles(s: Section, kind: str, load: float, steps: int) -> dict[str, Any]:
    """The keys of every kind with cycles: ``cycles``, ``record`` (cycle numbers, default
    the last) and ``max_wear_fraction`` (cycle-jump bound), with ``kind``, ``load`` and
    ``steps``: the fields of a :class:`CycledLoading` ({field: value})."""
    declared = declared_keys(CycledLoading)
    cycles = s.integer("cycles", **bound_of(declared["cycles"]))
    record_raw = s.raw("record", [cycles])
    record_list = record_raw if isinstance(record_raw, list) else [record_raw]
    record = []
    for item in record_list:
        if isinstance(item, bool) or not isinstance(item, int):
            raise s.error("record", record_raw, "must be a list of integer cycle numbers")
        if not 0 <= item <= cycles:
            raise s.error(
                "record", record_raw, f"cycle {item} is outside 0..cycles (cycles = {cycles})"
            )
        record.append(item)
    if len(set(record)) != len(record):
        raise s.error("record", record_raw, "cycles must not repeat")
    fraction = declared["max_wear_fraction"]
    max_wear_fraction = s.number("max_wear_fraction", fraction.default, **bound_of(fraction))
    return {
        "kind": kind,
        "load": load,
        "steps": steps,
        "cycles": cycles,
        "record": tuple(sorted(record)),
        "max_wear_fraction": max_wear_fraction,
    }
