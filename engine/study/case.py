"""Case runner: one case of the plan → its loading kind → :class:`CaseOutcome`.

The runner knows the study configuration and the table of loading kinds
(:data:`engine.study.kinds.KINDS`), nothing of MPI or HDF5, and never branches on the kind:
``kind.run(context, case, config, should_stop)`` computes the case with the solver and
stress builders of a :class:`~engine.study.outcome.CaseContext`. Whatever happens inside a
case — an exception, a solve that does not converge, a stop request — comes back as a
:class:`CaseOutcome` with a status, so one bad case never stops the study (statuses:
:mod:`engine.study.outcome`). Around the kind's run the runner keeps the run time of an
interrupted case (``<output>.checkpoints/<case_id>.json``, summed over resumed runs), removes
the checkpoint of a case that ended, injects the failures of ``[testing] fail_cases`` and
gives a line contact's datasets their units per unit length
(:meth:`engine.schema.DatasetRecord.per_unit_length`).
"""

from __future__ import annotations

import errno
import json
import os
import time
import traceback as traceback_module
from collections.abc import Callable
from pathlib import Path
from typing import Any

from engine.schema import DatasetRecord
from engine.surface import surface_outcome

from .config import StudyConfig
from .kinds import kind_of
from .operators import OperatorCache
from .outcome import (
    COMPLETED,
    FAILED,
    INTERRUPTED,
    BorderCheckedSolver,
    CaseContext,
    CaseOutcome,
    InjectedFailure,
    case_wear_law,
    nominal_mean_pressure,
    parameters_row,
    peak_tracker,
)
from .plan import Case

__all__ = [
    "COMPLETED",
    "FAILED",
    "INTERRUPTED",
    "peak_tracker",
    "DatasetRecord",
    "CaseOutcome",
    "CaseRunner",
    "InjectedFailure",
    "BorderCheckedSolver",
    "nominal_mean_pressure",
    "case_wear_law",
]


def _without_negative_zeros(row: dict[str, Any]) -> dict[str, Any]:
    """-0.0 → 0.0 in a summary row (a coordinate on the plane y = 0 can come out as -0.0;
    adding +0.0 maps only -0.0 to 0.0 in IEEE arithmetic and leaves NaN as it is)."""
    return {key: value + 0.0 if isinstance(value, float) else value for key, value in row.items()}


class CaseRunner:
    """Callable ``runner(case, should_stop) -> CaseOutcome`` for one study configuration."""

    def __init__(self, config: StudyConfig) -> None:
        self.config = config
        self.checkpoint_dir = config.study.checkpoint_dir
        # Operators, plans and stress kernels shared by the cases of this rank.
        self.context = CaseContext(OperatorCache(), self.checkpoint_dir)
        self._case_configs: dict[tuple, StudyConfig] = {}

    def release(self) -> None:
        """Let go of what this rank keeps for its later cases (operators with their kernel
        spectra and FFT plans, the stress evaluators with their kernels): for when it has no
        case left, so that the read-back of the results file runs beside none of it."""
        self.context.operators = OperatorCache()

    @property
    def operators(self):
        """The operator cache shared by the cases of this rank."""
        return self.context.operators

    @operators.setter
    def operators(self, cache) -> None:
        self.context.operators = cache

    @property
    def on_progress(self) -> Callable[..., None] | None:
        """Progress hook: ``on_progress(case)`` when a case starts, ``on_progress(case, N,
        cycles)`` after each simulated cycle (engine.output.progress; None: no reports)."""
        return self.context.on_progress

    @on_progress.setter
    def on_progress(self, hook: Callable[..., None] | None) -> None:
        self.context.on_progress = hook

    def config_for(self, case: Case) -> StudyConfig:
        """The case's configuration: the study with its swept values (cached per settings)."""
        if case.settings not in self._case_configs:
            self._case_configs[case.settings] = self.config.for_case(case.settings)
        return self._case_configs[case.settings]

    def __call__(self, case: Case, should_stop: Callable[[], bool] | None = None) -> CaseOutcome:
        should_stop = should_stop or (lambda: False)
        start = time.perf_counter()
        cpu_start = time.thread_time()  # CPU of the computing thread (rank 0 computes in one)
        previous = self._load_progress(case)
        if self.on_progress is not None:
            self.on_progress(case)
        try:
            if case.case_id in self.config.testing.fail_cases:
                raise InjectedFailure(f"case {case.case_id} fails on purpose ([testing])")
            config = self.config_for(case)
            outcome = kind_of(config).run(self.context, case, config, should_stop)
        except Exception as error:  # noqa: BLE001 - every failure becomes an outcome
            outcome = CaseOutcome(
                case,
                FAILED,
                message=f"{type(error).__name__}: {error}",
                traceback=traceback_module.format_exc(),
            )
        outcome.runtime_s = previous.get("runtime_s", 0.0) + time.perf_counter() - start
        if self.config.punch.is_line:  # per unit length (engine.schema.contact_units)
            outcome.datasets = {
                path: record.per_unit_length(True) for path, record in outcome.datasets.items()
            }
        outcome = self._with_surface(case, outcome)  # [surface]: its columns and datasets
        if outcome.status == INTERRUPTED:
            self._save_progress(case, {"runtime_s": outcome.runtime_s})
        else:
            self._remove_checkpoint(case)
        if outcome.status != COMPLETED:
            outcome.row = parameters_row(case, outcome.status)
        outcome.attrs["cpu_s"] = time.thread_time() - cpu_start  # this run only
        outcome.row["runtime_s"] = outcome.runtime_s
        outcome.row["status"] = outcome.status
        outcome.row = _without_negative_zeros(outcome.row)
        return outcome

    def _with_surface(self, case: Case, outcome: CaseOutcome) -> CaseOutcome:
        """A completed case of a study with ``[surface]`` gets the surface's columns and
        datasets (engine.surface.outputs; after the line-contact units: a profile's spectrum
        is in mm^3, no per-unit-length quantity); a failure there fails the case."""
        if self.config.surface is None or outcome.status != COMPLETED:
            return outcome
        try:
            return surface_outcome(self.config_for(case), outcome)
        except Exception as error:  # noqa: BLE001 - every failure becomes an outcome
            return CaseOutcome(
                case,
                FAILED,
                message=f"{type(error).__name__}: {error}",
                traceback=traceback_module.format_exc(),
                runtime_s=outcome.runtime_s,
            )

    # ---------------------------------------------------------------- checkpoints
    def _checkpoint_path(self, case: Case) -> Path:
        return self.context.checkpoint_path(case)

    def _progress_path(self, case: Case) -> Path:
        return self.checkpoint_dir / f"{case.case_id}.json"

    def _load_progress(self, case: Case) -> dict:
        path = self._progress_path(case)
        if path.exists() and self._checkpoint_path(case).exists():
            return json.loads(path.read_text())
        return {}

    def _save_progress(self, case: Case, progress: dict) -> None:
        path = self._progress_path(case)
        temporary = path.with_name(f".{path.name}.tmp")
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            temporary.write_text(json.dumps(progress))
            os.replace(temporary, path)
        except OSError as error:  # a full disk: no record of the time spent, the case runs on
            temporary.unlink(missing_ok=True)
            if error.errno not in (errno.ENOSPC, errno.EDQUOT):
                raise

    def _remove_checkpoint(self, case: Case) -> None:
        for path in (self._checkpoint_path(case), self._progress_path(case)):
            path.unlink(missing_ok=True)
