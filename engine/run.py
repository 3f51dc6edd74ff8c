"""Run a study from Python: :func:`run_study` does everything ``python -m engine`` does.

>>> import engine
>>> run = engine.run_study("studies/demo.toml")            # doctest: +SKIP
>>> run.status, run.output                                   # doctest: +SKIP
('completed', PosixPath('results/demo.h5'))
>>> run.summary.pivot(index="mu1", columns="beta", values="max_wear_depth")  # doctest: +SKIP

Under MPI every rank calls it with the same arguments and its communicator
(``run_study(path, comm=MPI.COMM_WORLD)``); without ``comm`` the study runs on this process
alone (``MPI.COMM_SELF``: no ``mpiexec`` needed, in a notebook too). The flow:

1. rank 0 validates the study and its plan (incl. the memory a case needs), the output path,
   takes the lock on the output (``engine.output.lock``) and inspects an existing results
   file (same study? damaged? ``engine.output.identity``) — before any file is created or
   changed — and broadcasts the verdict (bad input: status ``"invalid"`` on every rank);
2. the output strategy is chosen: the single writer (rank 0 owns the file) or collective mpio
   (``engine.output.collective``); the writer prepares the file and learns which cases are
   complete;
3. the scheduler (``engine.parallel.scheduler``) hands the remaining cases out; rank 0
   computes as well;
4. ``stop_event`` (a :class:`threading.Event`; the command line sets it on SIGTERM, SIGUSR1,
   SIGINT) stops the run cleanly: no new cases, running cyclic cases save their state, the
   file is closed; status ``"interrupted"``, the next run resumes.

This module sits above the output and parallel layers (docs/explanation/architecture.md); it never
touches ``MPI.COMM_WORLD`` and imports its heavy modules (mpi4py, h5py, numpy) only when a
study runs, so that ``import engine`` stays light.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import socket
import sys
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from engine import __version__
from engine.parallel.serial import any_rank, ranks_on_node
from engine.parallel.waiting import patient_bcast, patient_gather

__all__ = ["StudyError", "StudyRun", "RUN_STATUSES", "run_study"]

# What a run can end as (StudyRun.status); the command line maps them to its exit codes.
RUN_STATUSES = (
    "completed",
    "failed",
    "invalid",
    "interrupted",
    "planned",
    "damaged",
    "output-full",
)


class StudyError(ValueError):
    """An invalid study or an unusable output: what :func:`run_study` raises unless
    ``check=False``.

    The message is the line the command line prints: the file, the key and the value
    (``demo.toml: [loading] load = -750.0: must be > 0 (N)``).

    Parameters
    ----------
    run : StudyRun
        The run with status ``"invalid"`` (kept as ``error.run``).
    """

    def __init__(self, run: StudyRun) -> None:
        super().__init__(run.message)
        self.run = run


@dataclass(frozen=True)
class StudyRun:
    """The outcome of :func:`run_study`.

    Parameters
    ----------
    status : str
        ``"completed"`` every case completed; ``"failed"`` at least one case failed;
        ``"invalid"`` bad input, unusable output path, output in use by another run or holding
        another study (nothing computed, nothing changed; ``message`` says why);
        ``"interrupted"`` stopped by ``stop_event`` (run again to resume); ``"planned"`` a dry
        run (nothing computed or changed); ``"damaged"`` a case the run wrote cannot be read
        back (run again to recompute it); ``"output-full"`` the output's file system is full
        (completed cases kept; free space and run again to resume; ``message`` names the
        path and the space needed).
    output : pathlib.Path or None
        The results file (None when the study could not be read).
    name : str
        The study's name ("" when the study could not be read).
    cases, completed, failed : int
        Cases of the study; completed and failed ones in the results file after the run.
    wall_time_s : float
        Wall time of the scheduling loop, s (0 when nothing ran).
    message : str
        Why the run is ``"invalid"`` or was interrupted at start-up; "" otherwise.
    """

    status: str
    output: Path | None = None
    name: str = ""
    cases: int = 0
    completed: int = 0
    failed: int = 0
    wall_time_s: float = 0.0
    message: str = ""

    @property
    def summary_path(self) -> Path | None:
        """The summary CSV beside the results file."""
        return None if self.output is None else self.output.with_suffix(".csv")

    @property
    def summary(self):
        """The summary table as a :class:`pandas.DataFrame` (:func:`engine.load_summary`)."""
        from engine.output.summary import load_summary

        if self.output is None:
            raise ValueError(f"no results: the run is {self.status!r} ({self.message})")
        return load_summary(self.output)

    @property
    def ok(self) -> bool:
        """True when every case completed (or, for a dry run, when the study is valid)."""
        return self.status in ("completed", "planned")

    def __str__(self) -> str:
        text = f"StudyRun({self.status}: {self.name!r}, {self.completed}/{self.cases} completed"
        text += f", {self.failed} failed -> {self.output})"
        return text + (f": {self.message}" if self.message else "")


def run_study(
    study: Any,
    *,
    comm: Any = None,
    output: str | Path | None = None,
    resume: bool = True,
    fresh: bool = False,
    progress: bool | None = None,
    progress_interval: float = 30.0,
    output_strategy: str | None = None,
    drop_stale: bool = False,
    dry_run: bool = False,
    stop_event: threading.Event | None = None,
    command_line: str = "",
    check: bool = True,
) -> StudyRun:
    """Run (or resume) a parameter study and write its results file and summary.

    Parameters
    ----------
    study : str, pathlib.Path or StudyConfig
        A study file, study TOML text (a string holding a newline) or a configuration from
        ``engine.study.config.parse_study``.
    comm : mpi4py communicator, optional
        Ranks that share the study, every one calling ``run_study`` with the same arguments.
        Default: this process alone (``MPI.COMM_SELF``).
    output : str or pathlib.Path, optional
        Results file instead of ``[study] output`` (relative to the working directory).
    resume : bool
        Keep the completed cases of an existing results file of the same study and skip them
        (default). With ``resume=False`` an existing results file is an error (status
        ``"invalid"``) unless ``fresh=True``.
    fresh : bool
        Delete the existing results, summary and checkpoints and start over.
    progress : bool, optional
        Draw the tqdm bar: None on a terminal only, False never, True always.
    progress_interval : float
        Seconds between progress lines on stderr when there is no bar; 0 turns them off.
    output_strategy : {"auto", "single", "mpio"}, optional
        Who writes the file; overrides ``[study] output_strategy``.
    drop_stale : bool
        Delete cases of an existing results file that are no longer in the study.
    dry_run : bool
        Print what a run would do and stop (status ``"planned"``); changes nothing.
    stop_event : threading.Event, optional
        Set it (from another thread or a signal handler) to stop the run cleanly.
    command_line : str
        Stored in the results file (the command line that started the run).
    check : bool
        Raise :class:`StudyError` for an invalid study (default); with ``check=False`` it is
        the returned status ``"invalid"`` with the reason in ``message``.

    Returns
    -------
    StudyRun
        The same on every rank. Failed, interrupted, damaged and full-disk runs are
        statuses of it, never exceptions: ``run.ok`` tells whether every case completed.

    Raises
    ------
    StudyError
        (``check=True``) the study is invalid or the output unusable: nothing computed,
        nothing written; the message names the file, the key and the value. Raised on every
        rank alike.
    """
    comm = _communicator(comm)
    stop_event = stop_event if stop_event is not None else threading.Event()
    options = _RunOptions(
        output=None if output is None else Path(output),
        output_strategy=output_strategy,
        resume=resume,
        fresh=fresh,
        dry_run=dry_run,
        drop_stale=drop_stale,
        progress_bar=progress,
        progress_interval=progress_interval,
    )
    run = _run(comm, study, options, command_line, stop_event)
    if check and run.status == "invalid":
        raise StudyError(run)
    return run


@dataclass(frozen=True)
class _RunOptions:
    output: Path | None
    output_strategy: str | None
    resume: bool
    fresh: bool
    dry_run: bool
    drop_stale: bool
    progress_bar: bool | None
    progress_interval: float


def _communicator(comm):
    """``comm``, or this process alone."""
    if comm is not None:
        return comm
    from mpi4py import MPI

    return MPI.COMM_SELF


@dataclass(frozen=True)
class _Prepared:
    """What rank 0 found out before anything was written, broadcast to every rank."""

    config: Any
    plan: Any
    strategy: str
    layout: Any
    existing: Any


def _read_study(study):
    """A validated configuration from a path, TOML text or a configuration."""
    from engine.study.config import StudyConfig, load_study, parse_study

    if isinstance(study, StudyConfig):
        return study
    if isinstance(study, str) and "\n" in study:
        return parse_study(study)
    return load_study(study)


def _configure(study, options: _RunOptions):
    """The configuration with the run's overrides (output path, output strategy)."""
    config = _read_study(study)
    info = config.study
    if options.output is not None:
        from engine.output.lock import check_output_name

        check_output_name(options.output)
        info = dataclasses.replace(info, output=options.output)
    if options.output_strategy is not None:
        info = dataclasses.replace(info, output_strategy=options.output_strategy)
    return dataclasses.replace(config, study=info)


def _prepare_on_root(
    study, options: _RunOptions, ranks: int, ranks_on_node: int, locks: list, stop_event
):
    """Validate everything that can be wrong with the input, in this order, before any file is
    created or changed: the study and its plan (incl. the memory a case needs), the output
    path, the lock on the output (taken here, appended to ``locks``), then the existing
    results file (same study? damaged? read back in a child process that ``stop_event``
    ends), then the free space for the cases to run. Returns a :class:`_Prepared` or
    raises."""
    from engine.output.collective import choose_strategy
    from engine.output.existing import inspect_existing_isolated
    from engine.output.lock import (
        OutputLock,
        check_output_names,
        check_output_path,
        check_summary_path,
        check_text,
    )
    from engine.study.feasibility import check_feasible
    from engine.study.layout import plan_layout
    from engine.study.plan import make_plan
    from engine.study.resources import check_memory

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
        from engine.searching import search_strategy

        strategy = search_strategy(config)
    else:
        strategy = choose_strategy(config.study.output_strategy, ranks)
    output = config.study.output
    if options.dry_run:  # read-only; a dry run reports the same mismatch a run would
        existing = None
        if not options.fresh:
            existing = inspect(output, plan)
        return _Prepared(config, plan, strategy, None, _for_searches(config, existing))
    check_output_path(output)
    lock = OutputLock(output)
    lock.acquire()  # before anything else touches the output, fresh included
    locks.append(lock)
    if lock.replaced is not None:
        print(
            f"note: removed the stale lock of a run that no longer exists (pid "
            f"{lock.replaced.pid}, host {lock.replaced.host})",
            file=sys.stderr,
            flush=True,
        )
    check_summary_path(output, config.study.summary_path)
    existing = None
    if not options.fresh:
        _check_may_resume(output, options)
        existing = inspect(output, plan)
    layout = plan_layout(config, plan)
    _check_space(output, plan, layout, existing)
    layout = layout if strategy == "mpio" else None
    return _Prepared(config, plan, strategy, layout, _for_searches(config, existing))


def _prepare_calibration(config, plan, options: _RunOptions, locks: list):
    """A ``[calibrate]`` study: one combination of the sweep (the tests file says what
    differs), the output path checked and locked (engine.calibration keeps its contact
    solutions beside it and resumes from them)."""
    from engine.output.lock import OutputLock, check_output_path
    from engine.study.config import StudyConfigError

    if len(plan) != 1:
        raise StudyConfigError(
            config.source, "sweep", f"{len(plan)} combinations",
            "a calibration takes one combination of the [sweep] (the tests file sets what "
            "differs between tests)",
        )  # fmt: skip

    if not options.dry_run:
        check_output_path(config.study.output)
        lock = OutputLock(config.study.output)
        lock.acquire()
        locks.append(lock)
    return _Prepared(config, plan, "calibrate", None, None)


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
    from engine.output.space import check_space, planned_bytes

    completed = set(existing.completed) if existing is not None else set()
    remaining = [case_id for case_id in plan.case_ids if case_id not in completed]
    if not remaining:
        return
    smallest = min(planned_bytes(layout, [case_id]) for case_id in remaining)
    check_space(output, planned_bytes(layout, remaining), smallest_case=smallest)


class ExistingOutput(ValueError):
    """``resume=False`` without ``fresh=True``, and the results file exists."""


def _check_may_resume(output: Path, options: _RunOptions) -> None:
    if not options.resume and output.exists():
        raise ExistingOutput(
            f"{output} exists: pass resume=True to continue it or fresh=True to start over"
        )


def study_metadata(config, command_line: str, plan):
    """Root metadata of the results file; the root grid only when every case of the plan
    shares it (otherwise each case's own grid is in its group, ``/cases/<case_id>/grid``)."""
    from engine.output.hdf5 import StudyMetadata
    from engine.output.identity import study_identity

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
    from engine.output.collective import ParallelH5pyMissing
    from engine.output.hdf5 import ResultsMismatch
    from engine.output.lock import OutputInUse, OutputPathError
    from engine.study.config import StudyConfigError
    from engine.study.feasibility import ImpossibleCases

    return (
        StudyConfigError,
        ImpossibleCases,
        ResultsMismatch,
        ParallelH5pyMissing,
        OutputInUse,
        OutputPathError,
        ExistingOutput,
    )


def _verdict(comm, study, options: _RunOptions, locks: list, stop_event):
    """Rank 0 prepares; every rank receives ``("ok", _Prepared)``, ``("invalid", message)``,
    ``("output-full", message)`` or ``("stopped", "")`` (a stop signal while the existing file
    was read)."""
    from engine.output.isolated import IsolatedCallStopped
    from engine.output.space import OutputFull

    verdict = None
    if comm.Get_rank() == 0:
        node_ranks = ranks_on_node(comm)
        try:
            prepared = _prepare_on_root(
                study, options, comm.Get_size(), node_ranks, locks, stop_event
            )
            verdict = ("ok", prepared)
        except _input_errors() as error:
            verdict = ("invalid", str(error))
        except OutputFull as error:
            verdict = ("output-full", str(error))
        except IsolatedCallStopped:
            verdict = ("stopped", "")
    else:
        ranks_on_node(comm)  # collective: every rank takes part
    return patient_bcast(comm, verdict)


def _run(comm, study, options: _RunOptions, command_line: str, stop_event) -> StudyRun:
    rank = comm.Get_rank()
    peers = comm.allgather((os.getpid(), socket.gethostname()))
    locks: list = []  # rank 0: the output lock, once taken
    try:
        kind, prepared = _verdict(comm, study, options, locks, stop_event)
        if kind in ("invalid", "output-full"):
            return StudyRun(kind, message=prepared)
        if kind == "stopped":
            return _stopped_at_start_up(comm, StudyRun("interrupted"))
        config, plan = prepared.config, prepared.plan
        run = StudyRun("planned", config.study.output, config.study.name, cases=len(plan))
        if prepared.strategy == "calibrate":
            from engine.calibration.run import calibrate

            return calibrate(comm, config, run, options, stop_event)
        if options.dry_run:
            if rank == 0:
                print_plan(prepared, options, comm.Get_size())
            return run
        if any_rank(comm, stop_event.is_set()):  # a stop during start-up
            return _stopped_at_start_up(comm, run)
        if rank == 0 and prepared.existing is not None:
            prepared.existing.report(sys.stdout, drop_stale=options.drop_stale)
        outcome = _compute(comm, prepared, options, command_line, stop_event, peers)
        return patient_bcast(comm, dataclasses.replace(run, **outcome) if rank == 0 else None)
    finally:
        for lock in locks:
            lock.release()


def _stopped_at_start_up(comm, run: StudyRun) -> StudyRun:
    message = (
        "stop signal received during start-up: nothing computed, no file changed (rerun to start)"
    )
    if comm.Get_rank() == 0:
        print(message, file=sys.stderr, flush=True)
    return dataclasses.replace(run, status="interrupted", message=message)


def _settle_existing(
    prepared: _Prepared, options: _RunOptions, command_line: str, stop_event
) -> bool:
    """Rank 0, under the lock: fresh removes the old outputs; a damaged file is salvaged or
    moved aside (engine.output.salvage, the copy in a child process that ``stop_event``
    ends). False when a stop ended the salvage (nothing was changed); the message of
    :class:`engine.output.space.OutputFull` when the disk has no room for the salvage."""
    from engine.output.hdf5 import remove_outputs
    from engine.output.isolated import IsolatedCallStopped
    from engine.output.salvage import apply_existing
    from engine.output.space import OutputFull

    config = prepared.config
    if options.fresh:
        remove_outputs(config.study.output, config.study.checkpoint_dir)
    elif prepared.existing is not None:
        try:
            apply_existing(
                prepared.existing,
                prepared.plan,
                study_metadata(config, command_line, prepared.plan),
                config.study.checkpoint_dir,
                should_stop=stop_event.is_set,
            )
        except IsolatedCallStopped:
            return False
        except OutputFull as full:
            return str(full)
    return True


def _compute(comm, prepared: _Prepared, options: _RunOptions, command_line, stop_event, peers):
    """Every rank: open this rank's writer for the strategy (engine.output.writers.open_writer),
    prepare the file (rank 0 alone, or every rank for mpio), run the scheduler, close.

    Rank 0 returns the fields of the run's :class:`StudyRun` that the computation decides;
    the other ranks return None (rank 0's answer is broadcast)."""
    from engine.output.ensemble import write_ensemble
    from engine.output.hdf5 import StoppedDuringSetUp
    from engine.output.progress import WorkerProgress
    from engine.output.space import OutputFull
    from engine.output.writers import open_writer
    from engine.parallel.scheduler import Scheduler
    from engine.study.case import CaseRunner

    rank = comm.Get_rank()
    config, plan = prepared.config, prepared.plan
    runner = CaseRunner(config)
    if rank != 0:
        runner.on_progress = WorkerProgress(comm)
    writer = open_writer(
        prepared.strategy,
        config.study.output,
        comm=comm,
        layout=prepared.layout,
        summary_path=config.study.summary_path,
        journal_dir=config.study.checkpoint_dir,
        drop_stale=options.drop_stale,
        should_stop=stop_event.is_set,
    )
    scheduler = Scheduler(comm, writer.computing(runner), stop_event=stop_event, peers=peers)
    searches, settled = None, True
    if rank == 0:
        settled = _settle_existing(prepared, options, command_line, stop_event)
    settled = patient_bcast(comm, settled)  # every rank, before the writer's first collective
    if isinstance(settled, str):  # no room to salvage the damaged file: nothing changed
        return {"status": "output-full", "message": settled}
    if not settled:
        if rank == 0:
            print("stopped while salvaging the damaged file; nothing changed", file=sys.stderr)
        return {"status": "interrupted", "message": "stopped while salvaging"}
    if rank == 0:
        if config.search is not None:  # engine.searching: the cases known so far
            from engine.searching import prepare_searches

            searches = prepare_searches(config, plan, fresh=options.fresh)
    try:
        metadata = study_metadata(config, command_line, plan)
        known = plan if searches is None else searches.plan
        completed = writer.prepare(known, metadata, fresh=options.fresh)
    except StoppedDuringSetUp as stopped:  # on rank 0, or on every rank at once (mpio)
        if rank == 0:
            print(f"{stopped} (rerun to start)", file=sys.stderr, flush=True)
            if not writer.collective:
                scheduler.run([], lambda outcome: None)  # tell the waiting workers to exit
                _check_shares(comm, config, None)  # nothing written: nothing to read back
        return {"status": "interrupted", "message": str(stopped)}
    except OutputFull as full:  # the single writer's rank 0 (mpio raises on every rank)
        if not writer.collective:
            scheduler.run([], lambda outcome: None)  # tell the waiting workers to exit
            _check_shares(comm, config, None)
        return {"status": "output-full", "message": str(full)}
    with writer:
        if rank == 0:
            todo = plan.dispatch_order(skip=completed) if searches is None else searches.todo
            _announce(config, known, completed, todo, comm.Get_size(), writer.announce_suffix)
            report = _run_with_progress(
                scheduler, writer, known, completed, todo, options, comm, runner, searches,
                stop_event,
            )  # fmt: skip
            if searches is not None:
                print(searches.finish(writer), flush=True)
        else:
            scheduler.run()
    if rank != 0:
        _check_shares(comm, config)
        return None
    _remove_empty_checkpoint_dir(config)
    write_ensemble(config, writer.rows())  # [surface] sweeping surface.seed: NAME_ensemble.csv
    if writer.closing_note() is not None:
        print(writer.closing_note(), flush=True)
    outcome = _report(config, [row["status"] for row in writer.rows()], report)
    return _check_results(comm, config, writer, todo, outcome)


def _check_shares(comm, config, written: list[str] | None = None) -> list:
    """Every rank: the cases rank 0 names (``written``, sorted; None: no read-back) are read
    back in shares, rank r the r-th of every ``size`` (the file is closed: several processes
    may read it); rank 0 alone also reads the status of every other case. Rank 0 returns the
    bad checks of all ranks, the others an empty list."""
    from engine.output.verify import check_after_run

    rank, size = comm.Get_rank(), comm.Get_size()
    written = patient_bcast(comm, written)
    if written is None:
        return []
    share = set(written[rank::size])
    bad = check_after_run(config.study.output, share, others=rank == 0)
    everyone = patient_gather(comm, bad)
    return [check for checks in everyone for check in checks] if rank == 0 else []


def _check_results(comm, config, writer, todo, outcome: dict[str, Any]) -> dict[str, Any]:
    """A run never reports success while a case it counts as complete cannot be read: the
    cases it wrote are read back by every rank (:func:`_check_shares`; the others were
    verified when it began). A full disk ends the run as ``"output-full"``."""
    from engine.schema import CaseStatus

    if writer.full is not None:  # the command line prints the message
        _check_shares(comm, config, None)  # the workers wait for the list
        return {**outcome, "status": "output-full", "message": str(writer.full)}
    ran = {case.case_id for case in todo}
    written = {
        row["case_id"]
        for row in writer.rows()
        if row["case_id"] in ran and row["status"] == CaseStatus.COMPLETED
    }
    bad = _check_shares(comm, config, sorted(written))
    if not bad:
        return outcome
    shown = "; ".join(f"{check.case_id}: {check.problem}" for check in bad[:5])
    message = (
        f"{config.study.output} cannot be read back after writing ({shown}); rerun to "
        "recompute those cases"
    )
    print(f"error: {message}", file=sys.stderr, flush=True)
    return {**outcome, "status": "damaged", "message": message}


def _announce(config, plan, completed, todo, ranks: int, suffix: str = "") -> None:
    """The start line on stdout, the cases that continue from a checkpoint, and a warning on
    stderr when ranks would stay idle."""
    from engine.output.progress import plural

    print(
        f"study {config.study.name!r}: {plural(len(plan), 'case')}, {len(completed)} already "
        f"complete, {len(todo)} to run on {plural(ranks, 'rank')} -> {config.study.output}"
        + suffix,
        flush=True,
    )
    resumed = resumed_cases_line(config.study.checkpoint_dir, [case.case_id for case in todo])
    if resumed:  # a requeued or resubmitted run: which cases are not started over
        print(resumed, flush=True)
    warning = idle_ranks_warning(len(todo), ranks)
    if warning:
        print(warning, file=sys.stderr, flush=True)


_NAMED_CASES = 8  # case ids named in a line; the rest are counted


def resumed_cases_line(checkpoint_dir: Path, case_ids: Sequence[str]) -> str | None:
    """The line naming the cases of ``case_ids`` (to run now) that continue from a saved
    state, ``<checkpoint_dir>/<case_id>.npz``; None when every one starts from the beginning."""
    from engine.output.progress import plural

    resumed = [case_id for case_id in case_ids if (checkpoint_dir / f"{case_id}.npz").exists()]
    if not resumed:
        return None
    shown = ", ".join(resumed[:_NAMED_CASES]) + (" …" if len(resumed) > _NAMED_CASES else "")
    verb = (
        "continues from its checkpoint" if len(resumed) == 1 else "continue from their checkpoints"
    )
    return f"{plural(len(resumed), 'case')} {verb} ({checkpoint_dir}): {shown}"


def idle_ranks_warning(cases: int, ranks: int) -> str | None:
    """Every rank, rank 0 included, computes one case at a time: ranks beyond the number of
    cases to run have nothing to do."""
    from engine.output.progress import plural

    if cases == 0 or ranks <= cases:
        return None
    return (
        f"warning: {plural(ranks, 'rank')} for {plural(cases, 'case')} to run: "
        f"{plural(ranks - cases, 'rank')} will stay idle (each rank computes one case at a "
        f"time; use at most {cases})"
    )


def _run_with_progress(
    scheduler, writer, plan, completed, todo, options, comm, runner, searches, stop_event
):
    """Hand out ``todo``; every outcome goes to the writer, then to the progress display
    (with ``searches``, a :class:`engine.searching.SearchRun`, then to its search).

    Rank 0's own cases report their progress through a queue, the workers' by MPI
    (``engine.output.progress``); the dispatcher drains both at every pass of its loop.
    """
    from engine.output.progress import ProgressChannel, ProgressReporter
    from engine.schema import CaseStatus

    planned = set(plan.case_ids)  # stale cases of a shrunk or changed sweep are not planned
    measured = [
        (float(row.get("runtime_s") or 0.0), plan.by_id(row["case_id"]).expected_cost)
        for row in writer.rows()
        if row.get("status") == CaseStatus.COMPLETED and row["case_id"] in planned
    ]
    progress = ProgressReporter(
        len(plan),
        len(completed),
        todo=todo,
        ranks=comm.Get_size(),
        measured=measured,
        bar=options.progress_bar,
        interval=options.progress_interval,
    )
    channel = ProgressChannel(comm, progress)
    runner.on_progress = channel.local

    def on_outcome(outcome):
        writer.write(outcome)
        for committed in writer.committed(outcome):  # announced once on disk
            progress.update(committed)
        if writer.full is not None:  # no space for more cases: stop handing them out
            stop_event.set()

    try:
        if searches is not None:
            report = searches.run(scheduler, writer, progress, on_outcome, on_poll=channel.drain)
        else:
            report = scheduler.run(todo, on_outcome, on_poll=channel.drain)
        for committed in writer.commit():
            progress.update(committed)
        return report
    finally:
        channel.drain()  # reports that arrived with the last results
        progress.close()


def _remove_empty_checkpoint_dir(config) -> None:
    """``<output>.checkpoints/`` holds the state of interrupted cases (and, with mpio, the
    write journals); once the run leaves it empty it goes too."""
    with contextlib.suppress(OSError):  # not there, or not empty: keep it
        config.study.checkpoint_dir.rmdir()


def _report(config, statuses: list[str], report) -> dict[str, Any]:
    """The closing line on stdout; the computed fields of the StudyRun."""
    from engine.schema import CaseStatus

    failed = statuses.count(CaseStatus.FAILED)
    done = statuses.count(CaseStatus.COMPLETED)
    print(
        f"study {config.study.name!r}: {done} completed, {failed} failed, "
        f"{len(statuses) - done - failed} not completed; wall time "
        f"{report.wall_time_s:.1f} s; summary {config.study.summary_path}",
        flush=True,
    )
    status = "interrupted" if report.stopped else ("failed" if failed else "completed")
    return {
        "status": status,
        "completed": done,
        "failed": failed,
        "wall_time_s": float(report.wall_time_s),
    }


def print_plan(prepared: _Prepared, options: _RunOptions, ranks: int) -> None:
    """Dry run: what a run with the same options would do; reads, never writes."""
    from engine.output.progress import plural

    config, plan, existing = prepared.config, prepared.plan, prepared.existing
    output = config.study.output
    print(
        f"study {config.study.name!r} ({config.source}): {plural(len(plan), 'case')}, "
        + _loading_description(config, plan)
    )
    print(
        f"output {output} = {output.resolve()} (summary {config.study.summary_path}), "
        f"{prepared.strategy} writer"
    )
    if existing is not None and existing.kind != "resume":
        existing.report(sys.stdout)  # damaged: what a run would do with it
    states = _planned_states(config, plan, existing, options.fresh)
    if config.search is not None:  # the cases known now: completed steps, the next ones
        from engine.searching import describe_search, prepare_searches

        searches = prepare_searches(config, plan, fresh=options.fresh)
        print(describe_search(searches))
        plan, waiting = searches.plan, {case.case_id for case in searches.todo}
        fresh_states = _planned_states(config, plan, None, False)  # run, or from a checkpoint
        states = {
            case_id: fresh_states[case_id] if case_id in waiting else "complete: skip"
            for case_id in plan.case_ids
        }
    if options.fresh:
        present = [
            str(path)
            for path in (output, config.study.summary_path, config.study.checkpoint_dir)
            if path.exists()
        ]
        deleted = ", ".join(present) if present else "nothing (none exists)"
        print(f"--fresh would delete: {deleted}")
    todo = [case for case in plan.dispatch_order() if states[case.case_id] != "complete: skip"]
    print(
        f"would run {plural(len(todo), 'case')} on {plural(ranks, 'rank')}; "
        f"{len(plan) - len(todo)} complete and skipped"
    )
    warning = idle_ranks_warning(len(todo), ranks)
    if warning:
        print(warning, file=sys.stderr, flush=True)
    _print_case_table(plan, todo, states, config.sweep.swept_keys)


_PARAMETERS = ("mu1", "mu2", "wear1", "wear2", "beta", "alpha")


def _values(plan, key: str) -> list:
    """The distinct values of parameter ``key`` over the cases of ``plan``, sorted."""
    values = {case.parameters().get(key) for case in plan}
    return sorted(value for value in values if value is not None)


def _range_text(values: Sequence[float], unit: str = "", form: str = "g") -> str:
    """``"750 N"``, ``"250, 500, 750 N"`` (up to four values), ``"250 … 1000 N (7 values)"``
    (``form``: the format of each value)."""
    suffix = f" {unit}" if unit and unit != "1" else ""
    if len(values) > 4:
        first, last = format(values[0], form), format(values[-1], form)
        return f"{first} … {last}{suffix} ({len(values)} values)"
    return ", ".join(format(value, form) for value in values) + suffix


def _loading_description(config, plan) -> str:
    """One line on the loading of a study: each value as swept over the plan (the range of a
    swept key, not only its first value), then the ranges of every swept parameter; one the
    user did not sweep but that follows another (mu2 = mu1) is named beside it."""

    from engine.output.summary import column_unit

    def value(name: str, first, unit: str, form: str = "g") -> str:
        key = f"loading.{name}"
        return _range_text(_values(plan, key) if key in swept else [first], unit, form)

    swept = set(config.sweep.swept_keys)
    line = config.punch.is_line  # a line contact's loads per unit length
    what = config.kind.describe(config, value)
    rules = _followers(config.sweep)
    ranges = []
    for key in (*_PARAMETERS, *config.sweep.swept_keys):
        values = _values(plan, key)
        if len(values) < 2:
            continue
        text = f"{key} = {_range_text(values, column_unit(key, line))}"
        if key in rules:  # not swept: it follows its rule, named beside the key it follows
            leader, rule = rules[key]
            if len(_values(plan, leader)) > 1:
                continue
            text = f"{key} = {rule} = {_range_text(values, column_unit(key, line))}"
        text += "".join(
            f", {follower} = {rule}" for follower, (leader, rule) in rules.items() if leader == key
        )
        ranges.append(text)
    return what + ("; swept: " + "; ".join(ranges) if ranges else "")


def _followers(sweep) -> dict[str, tuple[str, str]]:
    """The parameters the user did not sweep that follow another: (the one followed, the
    rule) by name (``[sweep] mu2`` absent: mu2 = mu1; ``wear2`` absent: wear1,
    ``"proportional"``: wear1·mu2/mu1). The dry run names them beside the parameter they
    follow, not as swept."""
    rules = {}
    if sweep.mu2 is None:
        rules["mu2"] = ("mu1", "mu1")
    if sweep.alpha is None and sweep.wear2 is None:
        rules["wear2"] = ("wear1", "wear1")
    elif sweep.alpha is None and isinstance(sweep.wear2, str):  # "proportional"
        rules["wear2"] = ("wear1", "wear1·mu2/mu1")
    return rules


def _wear_columns(plan) -> list[str]:
    """The wear coefficients the cases' law uses: ``alpha`` (mm³/J) when the cases carry
    one (the energy law; ``wear1``/``wear2`` then only where not all zero), otherwise
    ``wear1``, ``wear2`` (1/MPa)."""
    parameters = [case.parameters() for case in plan]
    if all(row.get("alpha") is None for row in parameters):
        return ["wear1", "wear2"]
    rates = [key for key in ("wear1", "wear2") if any(row.get(key) for row in parameters)]
    return [*rates, "alpha"]


def _print_case_table(plan, todo, states, swept: Sequence[str]) -> None:
    """One row per case: the friction coefficients, the wear coefficients its law uses, β,
    one column per swept dotted key (headed by the key), the dispatch order and the
    action."""
    order = {case.case_id: number for number, case in enumerate(todo, start=1)}
    wear = _wear_columns(plan)
    names = list(swept)
    widths = [
        max(len(name), *(len(f"{case.parameters()[key]:g}") for case in plan))
        for name, key in zip(names, swept, strict=True)
    ]
    extra = "".join(f" {name:>{width}s}" for name, width in zip(names, widths, strict=True))
    heads = "".join(f" {key:>10s}" for key in wear)
    print(f"{'case_id':<40s} {'mu1':>6s} {'mu2':>6s}{heads} {'beta':>6s}{extra}  order  action")
    for case in plan:
        number = order.get(case.case_id)
        parameters = case.parameters()
        settings = "".join(
            f" {parameters[key]:>{width}g}" for key, width in zip(swept, widths, strict=True)
        )
        rates = "".join(f" {parameters[key]:10.4g}" for key in wear)
        print(
            f"{case.case_id:<40s} {case.mu1:6g} {case.mu2:6g}{rates} {case.beta:6g}{settings}"
            f"  {number if number else '-':>5}  {states[case.case_id]}"
        )


def _planned_states(config, plan, existing, fresh: bool) -> dict[str, str]:
    """Per case: "run", "resume from its checkpoint", "complete: skip", from the look at the
    existing file already taken (``existing``: None without a file); fresh runs all."""
    if fresh:
        return dict.fromkeys(plan.case_ids, "run")
    completed = set(existing.completed) if existing is not None else set()
    states = {}
    for case_id in plan.case_ids:
        if case_id in completed:
            states[case_id] = "complete: skip"
        elif (config.study.checkpoint_dir / f"{case_id}.npz").exists():
            states[case_id] = "resume from its checkpoint"
        else:
            states[case_id] = "run"
    return states
