"""What a study run settles before anything is written: the configuration with the run's
overrides, the plan, the output strategy, the lock on the output and the look at an existing
results file; and the verdict every rank receives (:func:`decide`).

Rank 0 checks everything that can be wrong with the input, in this order, before any file is
created or changed (:func:`prepare_on_root`): the study and its plan (incl. the memory a case
needs), the output path, the lock, the existing results file (same study? damaged?), the free
space. Bad input is a :class:`Verdict` "invalid" naming the file, the key and the value.
"""

from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from engine._version import __version__
from engine.output.collective import ParallelH5pyMissing, choose_strategy
from engine.output.existing import inspect_existing_isolated
from engine.output.hdf5 import ResultsMismatch, StudyMetadata
from engine.output.identity import study_identity
from engine.output.isolated import IsolatedCallStopped
from engine.output.lock import (
    OutputInUse,
    OutputLock,
    OutputPathError,
    check_output_name,
    check_output_names,
    check_output_path,
    check_summary_path,
    check_text,
)
from engine.output.space import MARGIN, OutputFull, check_space, planned_bytes
from engine.parallel.serial import ranks_on_node
from engine.parallel.waiting import patient_bcast
from engine.searching import search_strategy
from engine.study.config import StudyConfig, StudyConfigError, load_study, parse_study
from engine.study.feasibility import ImpossibleCases, check_feasible
from engine.study.layout import plan_layout
from engine.study.plan import make_plan
from engine.study.resources import check_memory

__all__ = [
    "RunOptions",
    "Prepared",
    "Verdict",
    "ExistingOutput",
    "read_study",
    "prepare_on_root",
    "study_metadata",
    "decide",
]

LOGGER = logging.getLogger(__name__)


@dataclass(frozen=True)
class RunOptions:
    output: Path | None
    output_strategy: str | None
    resume: bool
    fresh: bool
    dry_run: bool
    drop_stale: bool
    progress_bar: bool | None
    progress_interval: float


@dataclass(frozen=True)
class Prepared:
    """What rank 0 found out before anything was written, broadcast to every rank."""

    config: Any
    plan: Any
    strategy: str
    layout: Any
    existing: Any


def read_study(study):
    """A validated configuration from a path, TOML text or a configuration."""
    if isinstance(study, StudyConfig):
        return study
    if isinstance(study, str) and "\n" in study:
        return parse_study(study)
    return load_study(study)


def _configure(study, options: RunOptions):
    """The configuration with the run's overrides (output path, output strategy)."""
    config = read_study(study)
    info = config.study
    if options.output is not None:
        check_output_name(options.output)
        info = dataclasses.replace(info, output=options.output)
    if options.output_strategy is not None:
        info = dataclasses.replace(info, output_strategy=options.output_strategy)
    return dataclasses.replace(config, study=info)


def prepare_on_root(
    study, options: RunOptions, ranks: int, ranks_on_node: int, locks: list, stop_event
):
    """Validate everything that can be wrong with the input, in this order, before any file is
    created or changed: the study and its plan (incl. the memory a case needs), the output
    path, the lock on the output (taken here, appended to ``locks``), then the existing
    results file (same study? damaged? read back in a child process that ``stop_event``
    ends), then the free space for the cases to run. Returns a :class:`Prepared` or
    raises."""

    def inspect(output, plan):
        metadata = study_metadata(config, "", plan)
        return inspect_existing_isolated(output, metadata, plan, should_stop=stop_event.is_set)

    config = _configure(study, options)
    check_text(f"{config.source}: [study] name", config.study.name)  # stored in the file
    check_output_names(config.study.output)
    plan = make_plan(config)
    if config.calibrate is not None:  # engine.calibration: its own searches and outputs
        return _prepare_calibration(config, plan, options, locks)
    check_feasible(config, plan)
    check_memory(config, ranks_on_node, plan=plan)
    if config.search is not None:  # searches create their cases as they go: single writer
        strategy = search_strategy(config)
    else:
        strategy = choose_strategy(config.study.output_strategy, ranks)
    output = config.study.output
    if options.dry_run:  # read-only; a dry run reports the same mismatch a run would
        existing = None
        if not options.fresh:
            existing = inspect(output, plan)
        return Prepared(config, plan, strategy, None, _for_searches(config, existing))
    lock = _take_output(output, locks, lambda: _all_cases_bytes(config, plan))
    if lock.replaced is not None:
        LOGGER.warning(
            "note: removed the stale lock of a run that no longer exists (pid %s, host %s)",
            lock.replaced.pid,
            lock.replaced.host,
        )
    check_summary_path(output, config.study.summary_path)
    existing = None
    if not options.fresh:
        _check_may_resume(output, options)
        existing = inspect(output, plan)
    layout = plan_layout(config, plan)
    _check_space(output, plan, layout, existing)
    layout = layout if strategy == "mpio" else None
    return Prepared(config, plan, strategy, layout, _for_searches(config, existing))


def _prepare_calibration(config, plan, options: RunOptions, locks: list):
    """A ``[calibrate]`` study: one combination of the sweep (the tests file says what
    differs), the output path checked and locked (engine.calibration keeps its contact
    solutions beside it and resumes from them)."""
    if len(plan) != 1:
        raise StudyConfigError(
            config.source, "sweep", f"{len(plan)} combinations",
            "a calibration takes one combination of the [sweep] (the tests file sets what "
            "differs between tests)",
        )  # fmt: skip

    if not options.dry_run:
        _take_output(config.study.output, locks, lambda: MARGIN)  # what its results write
    return Prepared(config, plan, "calibrate", None, None)


def _take_output(output: Path, locks: list, needed) -> OutputLock:
    """Check the output's path and take its lock (appended to ``locks``), before anything
    else touches the output. A disk too full for the lock file is
    :class:`engine.output.space.OutputFull` naming what the run needs (``needed()``, bytes,
    at most that when a results file exists: its cases are not looked at without the lock),
    not the lock file's few bytes."""
    try:
        check_output_path(output)
        lock = OutputLock(output)
        lock.acquire()
    except OutputFull as full:
        raise OutputFull(output, needed(), full.free, at_most=output.exists()) from None
    locks.append(lock)
    return lock


def _all_cases_bytes(config, plan) -> int:
    """The bytes every case of ``plan`` writes (known from the plan, as the check before a
    run counts them: :func:`engine.output.space.planned_bytes`)."""
    return planned_bytes(plan_layout(config, plan), plan.case_ids)


def _for_searches(config, existing):
    """A ``[search]`` study's cases are its searches' steps, not the plan's combinations:
    the look at the existing file neither counts them stale nor the combinations new (the
    searches replay the file, engine.searching)."""
    if config.search is None or existing is None:
        return existing
    return dataclasses.replace(existing, stale=[], new_cases=0)


def _check_space(output: Path, plan, layout, existing) -> None:
    """Raise :class:`engine.output.space.OutputFull` when the data the cases still to run
    will write (known from the plan: a lower bound) does not fit on the output's file
    system: a rerun on a still-full disk says so at once and changes nothing."""
    completed = set(existing.completed) if existing is not None else set()
    remaining = [case_id for case_id in plan.case_ids if case_id not in completed]
    if not remaining:
        return
    smallest = min(planned_bytes(layout, [case_id]) for case_id in remaining)
    check_space(output, planned_bytes(layout, remaining), smallest_case=smallest)


class ExistingOutput(ValueError):
    """``resume=False`` without ``fresh=True``, and the results file exists."""


def _check_may_resume(output: Path, options: RunOptions) -> None:
    if not options.resume and output.exists():
        raise ExistingOutput(
            f"{output} exists: pass resume=True to continue it or fresh=True to start over"
        )


def study_metadata(config, command_line: str, plan):
    """Root metadata of the results file; the root grid only when every case of the plan
    shares it (otherwise each case's own grid is in its group, ``/cases/<case_id>/grid``)."""
    mesh = plan.shared_mesh()
    grid = None
    if mesh is not None:  # the profile's grid (a line contact's: one element along y)
        grid = config.punch.profile().grid(*mesh)
    metadata = StudyMetadata(
        name=config.study.name,
        source=config.source,
        study_toml=config.to_toml(),
        study_json=config.to_json(),
        fingerprint=config.fingerprint(),
        command_line=command_line,
        version=__version__,
        grid_x=grid.x if grid is not None else None,
        grid_y=grid.y if grid is not None else None,
    )
    metadata.attrs["study_identity"] = study_identity(config.resolved())
    return metadata


def _input_errors() -> tuple[type[Exception], ...]:
    """The errors that mean "bad input": nothing is computed or changed."""
    return (
        StudyConfigError,
        ImpossibleCases,
        ResultsMismatch,
        ParallelH5pyMissing,
        OutputInUse,
        OutputPathError,
        ExistingOutput,
    )


@dataclass(frozen=True)
class Verdict:
    """What rank 0's look at the input decided, the same on every rank: ``status`` "ok"
    (``prepared`` holds what it found), "invalid" or "output-full" (``message`` says why) or
    "stopped" (a stop signal while the existing file was read)."""

    status: str
    prepared: Prepared | None = None
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def decide(comm, study, options: RunOptions, locks: list, stop_event) -> Verdict:
    """Rank 0 prepares (:func:`_prepare_on_root`); every rank receives its :class:`Verdict`."""
    verdict = None
    if comm.Get_rank() == 0:
        node_ranks = ranks_on_node(comm)
        try:
            prepared = prepare_on_root(
                study, options, comm.Get_size(), node_ranks, locks, stop_event
            )
            verdict = Verdict("ok", prepared)
        except _input_errors() as error:
            verdict = Verdict("invalid", message=str(error))
        except OutputFull as error:
            verdict = Verdict("output-full", message=str(error))
        except IsolatedCallStopped:
            verdict = Verdict("stopped")
    else:
        ranks_on_node(comm)  # collective: every rank takes part
    return patient_bcast(comm, verdict)
