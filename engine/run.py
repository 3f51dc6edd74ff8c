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
touches ``MPI.COMM_WORLD``. ``import engine`` does not import it until :func:`run_study` is
first used (``engine.__getattr__``).

A quiet library: rank 0 reports through :mod:`logging` (the logger ``engine.run``: the start
and closing lines, notes on an existing file and a dry run's table at INFO, what went wrong
at WARNING and ERROR) and through the returned :class:`StudyRun`; nothing is printed unless
the caller configures logging. The command line (:mod:`engine.cli`) shows INFO on stdout and
WARNING and above on stderr, the lines it has always printed.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import os
import socket
import threading
from pathlib import Path
from typing import Any

import engine.calibration
from engine.dry_run import idle_ranks_warning, plan_report, resumed_cases_line
from engine.output.ensemble import write_ensemble
from engine.output.hdf5 import StoppedDuringSetUp, remove_outputs
from engine.output.isolated import IsolatedCallStopped
from engine.output.progress import ProgressChannel, ProgressReporter, WorkerProgress, plural
from engine.output.salvage import apply_existing
from engine.output.space import OutputFull
from engine.output.verify import check_after_run
from engine.output.writers import open_writer
from engine.parallel.scheduler import Scheduler
from engine.parallel.serial import any_rank
from engine.parallel.waiting import patient_bcast, patient_gather
from engine.preparation import Prepared, RunOptions, Verdict, decide, study_metadata
from engine.run_outcome import RUN_STATUSES, StudyError, StudyRun
from engine.schema import CaseStatus
from engine.searching import prepare_searches
from engine.study.case import CaseRunner

__all__ = ["StudyError", "StudyRun", "RUN_STATUSES", "run_study", "LOGGER"]

#: Where a run reports (rank 0): INFO the lines of a run, WARNING and ERROR what went wrong.
LOGGER = logging.getLogger(__name__)
logging.getLogger("engine").addHandler(logging.NullHandler())  # quiet unless configured


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
    options = RunOptions(
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


def _communicator(comm):
    """``comm``, or this process alone."""
    if comm is not None:
        return comm
    from mpi4py import MPI

    return MPI.COMM_SELF


def _run(comm, study, options: RunOptions, command_line: str, stop_event) -> StudyRun:
    rank = comm.Get_rank()
    peers = comm.allgather((os.getpid(), socket.gethostname()))
    locks: list = []  # rank 0: the output lock, once taken
    try:
        verdict = decide(comm, study, options, locks, stop_event)
        if verdict.status == "stopped":
            return _stopped_at_start_up(comm, StudyRun("interrupted"))
        if not verdict.ok:
            return StudyRun(verdict.status, message=verdict.message)
        prepared = verdict.prepared
        config, plan = prepared.config, prepared.plan
        run = StudyRun("planned", config.study.output, config.study.name, cases=len(plan))
        if prepared.strategy == "calibrate":
            return engine.calibration.calibrate(comm, config, run, options, stop_event)
        if options.dry_run:
            return patient_bcast(comm, _dry_run(prepared, options, comm) if rank == 0 else None)
        if any_rank(comm, stop_event.is_set()):  # a stop during start-up
            return _stopped_at_start_up(comm, run)
        if rank == 0 and prepared.existing is not None:
            for note in prepared.existing.notes(drop_stale=options.drop_stale):
                LOGGER.info(note)
        return patient_bcast(
            comm, _compute(comm, prepared, options, command_line, stop_event, peers, run)
        )
    finally:
        for lock in locks:
            lock.release()


def _stopped_at_start_up(comm, run: StudyRun) -> StudyRun:
    message = (
        "stop signal received during start-up: nothing computed, no file changed (rerun to start)"
    )
    if comm.Get_rank() == 0:
        LOGGER.warning(message)
    return dataclasses.replace(run, status="interrupted", message=message)


def _dry_run(prepared: Prepared, options: RunOptions, comm) -> StudyRun:
    """Rank 0: what a run with the same options would do (:mod:`engine.dry_run`), logged
    and returned; reads, never writes."""
    config, plan = prepared.config, prepared.plan
    report = plan_report(
        config, plan, prepared.strategy, prepared.existing, options.fresh, comm.Get_size()
    )
    for line in report.summary:
        LOGGER.info(line)
    if report.warning:
        LOGGER.warning(report.warning)
    for line in report.table:
        LOGGER.info(line)
    run = StudyRun("planned", config.study.output, config.study.name, cases=len(plan))
    return dataclasses.replace(run, plan=report.lines)


def _settle_existing(
    prepared: Prepared, options: RunOptions, command_line: str, stop_event
) -> Verdict:
    """Rank 0, under the lock: fresh removes the old outputs; a damaged file is salvaged or
    moved aside (engine.output.salvage, the copy in a child process that ``stop_event``
    ends). The verdict "ok"; "stopped" when a stop ended the salvage (nothing was changed);
    "output-full" (the message of :class:`engine.output.space.OutputFull`) when the disk has
    no room for the salvage."""
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
            return Verdict("stopped")
        except OutputFull as full:
            return Verdict("output-full", message=str(full))
    return Verdict("ok")


def _compute(
    comm, prepared: Prepared, options: RunOptions, command_line, stop_event, peers, run: StudyRun
) -> StudyRun | None:
    """Every rank: open this rank's writer for the strategy (engine.output.writers.open_writer),
    prepare the file (rank 0 alone, or every rank for mpio), run the scheduler, close.

    Rank 0 returns the fields of the run's :class:`StudyRun` that the computation decides;
    the other ranks return None (rank 0's answer is broadcast)."""
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
    searches, settled = None, None
    if rank == 0:
        settled = _settle_existing(prepared, options, command_line, stop_event)
    settled = patient_bcast(comm, settled)  # every rank, before the writer's first collective
    if settled.status == "output-full":  # no room to salvage the damaged file: nothing changed
        return _ended(run, "output-full", settled.message)
    if settled.status == "stopped":
        if rank == 0:
            LOGGER.warning("stopped while salvaging the damaged file; nothing changed")
        return _ended(run, "interrupted", "stopped while salvaging")
    if rank == 0:
        if config.search is not None:  # engine.searching: the cases known so far
            searches = prepare_searches(config, plan, fresh=options.fresh)
    try:
        metadata = study_metadata(config, command_line, plan)
        known = plan if searches is None else searches.plan
        completed = writer.prepare(known, metadata, fresh=options.fresh)
    except StoppedDuringSetUp as stopped:  # on rank 0, or on every rank at once (mpio)
        if rank == 0:
            LOGGER.warning("%s (rerun to start)", stopped)
            if not writer.collective:
                scheduler.run([], lambda outcome: None)  # tell the waiting workers to exit
                _check_shares(comm, config, None)  # nothing written: nothing to read back
        return _ended(run, "interrupted", str(stopped))
    except OutputFull as full:  # the single writer's rank 0 (mpio raises on every rank)
        if not writer.collective:
            scheduler.run([], lambda outcome: None)  # tell the waiting workers to exit
            _check_shares(comm, config, None)
        return _ended(run, "output-full", str(full))
    with writer:
        if rank == 0:
            todo = plan.dispatch_order(skip=completed) if searches is None else searches.todo
            _announce(config, known, completed, todo, comm.Get_size(), writer.announce_suffix)
            report = _run_with_progress(
                scheduler, writer, known, completed, todo, options, comm, runner, searches,
                stop_event,
            )  # fmt: skip
            if searches is not None:
                LOGGER.info(searches.finish(writer))
        else:
            scheduler.run()
    runner.release()  # no case left on this rank: the read-back runs without its operators
    if rank != 0:
        _check_shares(comm, config)
        return None
    _remove_empty_checkpoint_dir(config)
    try:
        write_ensemble(config, writer.rows())  # [surface] sweeping surface.seed: NAME_ensemble.csv
    except OutputFull as full:  # the cases are kept; the next run writes the table
        writer.full = writer.full or full
    if writer.closing_note() is not None:
        LOGGER.info(writer.closing_note())
    ended = _report(config, [row["status"] for row in writer.rows()], report, run)
    return _check_results(comm, config, writer, todo, ended)


def _check_shares(comm, config, written: list[str] | None = None) -> list:
    """Every rank: the cases rank 0 names (``written``, sorted; None: no read-back) are read
    back in shares, rank r the r-th of every ``size`` (the file is closed: several processes
    may read it); rank 0 alone also reads the status of every other case. Rank 0 returns the
    bad checks of all ranks, the others an empty list."""
    rank, size = comm.Get_rank(), comm.Get_size()
    written = patient_bcast(comm, written)
    if written is None:
        return []
    share = set(written[rank::size])
    bad = check_after_run(config.study.output, share, others=rank == 0)
    everyone = patient_gather(comm, bad)
    return [check for checks in everyone for check in checks] if rank == 0 else []


def _check_results(comm, config, writer, todo, run: StudyRun) -> StudyRun:
    """A run never reports success while a case it counts as complete cannot be read: the
    cases it wrote are read back by every rank (:func:`_check_shares`; the others were
    verified when it began). A full disk ends the run as ``"output-full"``."""
    if writer.full is not None:  # the command line prints the message
        _check_shares(comm, config, None)  # the workers wait for the list
        return _ended(run, "output-full", str(writer.full))
    ran = {case.case_id for case in todo}
    written = {
        row["case_id"]
        for row in writer.rows()
        if row["case_id"] in ran and row["status"] == CaseStatus.COMPLETED
    }
    bad = _check_shares(comm, config, sorted(written))
    if not bad:
        return run
    shown = "; ".join(f"{check.case_id}: {check.problem}" for check in bad[:5])
    message = (
        f"{config.study.output} cannot be read back after writing ({shown}); rerun to "
        "recompute those cases"
    )
    LOGGER.error("error: %s", message)
    return _ended(run, "damaged", message)


def _announce(config, plan, completed, todo, ranks: int, suffix: str = "") -> None:
    """The start line and the cases that continue from a checkpoint (INFO), and a warning
    when ranks would stay idle."""
    LOGGER.info(
        f"study {config.study.name!r}: {plural(len(plan), 'case')}, {len(completed)} already "
        f"complete, {len(todo)} to run on {plural(ranks, 'rank')} -> {config.study.output}" + suffix
    )
    resumed = resumed_cases_line(config.study.checkpoint_dir, [case.case_id for case in todo])
    if resumed:  # a requeued or resubmitted run: which cases are not started over
        LOGGER.info(resumed)
    warning = idle_ranks_warning(len(todo), ranks)
    if warning:
        LOGGER.warning(warning)


def _run_with_progress(
    scheduler, writer, plan, completed, todo, options, comm, runner, searches, stop_event
):
    """Hand out ``todo``; every outcome goes to the writer, then to the progress display
    (with ``searches``, a :class:`engine.searching.SearchRun`, then to its search).

    Rank 0's own cases report their progress through a queue, the workers' by MPI
    (``engine.output.progress``); the dispatcher drains both at every pass of its loop.
    """
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
        searches=None if searches is None else searches.counts,
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


def _report(config, statuses: list[str], report, run: StudyRun) -> StudyRun:
    """The closing line (INFO); ``run`` with what the computation decided."""
    failed = statuses.count(CaseStatus.FAILED)
    done = statuses.count(CaseStatus.COMPLETED)
    LOGGER.info(
        f"study {config.study.name!r}: {done} completed, {failed} failed, "
        f"{len(statuses) - done - failed} not completed; wall time "
        f"{report.wall_time_s:.1f} s; summary {config.study.summary_path}"
    )
    status = "interrupted" if report.stopped else ("failed" if failed else "completed")
    return dataclasses.replace(
        run, status=status, completed=done, failed=failed, wall_time_s=float(report.wall_time_s)
    )


def _ended(run: StudyRun, status: str, message: str) -> StudyRun:
    """``run`` ended as ``status`` (a member of ``RUN_STATUSES``), ``message`` saying why."""
    return dataclasses.replace(run, status=status, message=message)
