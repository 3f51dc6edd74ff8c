"""Entry point: ``python -m engine STUDY.toml`` (also under ``mpiexec -n N`` or ``srun``).

Post-processing (serial, no MPI): ``python -m engine plot RESULTS.h5 [--out DIR]`` writes the
figures (:mod:`engine.analysis.figures`), ``python -m engine report RESULTS.h5`` prints the
results tables in Markdown (:mod:`engine.analysis.report`).

This is the only module that touches ``MPI.COMM_WORLD``; every layer below receives a
communicator. The flow:

1. every rank installs the stop-signal handlers (first thing) and parses the command line;
   rank 0 validates the study file, expands the plan, checks the memory a case needs, the
   output path, takes the lock on the output (``engine.output.lock``: a second run, also a
   ``--fresh`` one, exits 2 naming the first run's pid and host) and inspects an existing
   results file (same study? damaged? see ``engine.output.identity``) — before any file is
   created or changed — and broadcasts the verdict (bad input: exit code 2 on every rank);
2. the output strategy is chosen (``--output-strategy`` / ``[study] output_strategy``): the
   single writer (rank 0 owns the file; default with the PyPI h5py wheel) or collective mpio
   (every rank writes its own cases; automatic when h5py is MPI-enabled and ranks > 1, see
   ``engine.output.collective``); the writer prepares the file and learns which cases are
   complete;
3. the scheduler hands the remaining cases out dynamically; rank 0 computes as well;
4. SIGTERM / SIGUSR1 / SIGINT — on any rank, at any time from start-up to shutdown — set a
   stop flag: no new cases, running cyclic cases save their state, the file is closed
   cleanly, exit code 3; the next run resumes. A dead peer on the same host ends the job
   (exit 70, ``engine.parallel.scheduler.PeerWatch``). See docs/reliability.md.

Exit codes: 0 all cases completed; 1 at least one case failed; 2 bad input, unusable output
path, output in use by another run or holding another study (nothing computed, no output of
another run created or changed); 3 interrupted by a signal (rerun to resume); 70 internal
error or a dead peer (the communicator is aborted so no rank waits forever).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import os
import shlex
import signal
import socket
import sys
import threading
import traceback
from pathlib import Path

from engine import __version__
from engine.schema import CaseStatus

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_INTERNAL = 0, 1, 2, 3, 70
_STOP_SIGNALS = ("SIGTERM", "SIGUSR1", "SIGINT")


_USAGE = """\
%(prog)s STUDY.toml [--dry-run] [--resume | --fresh] [--drop-stale] [--output PATH]
            [--output-strategy {auto,single,mpio}] [--no-progress-bar] [--progress-interval S]
       %(prog)s plot RESULTS.h5 [--out DIR]
       %(prog)s report RESULTS.h5 [--cycles N ...] [--update DOC.md]"""

_DESCRIPTION = """\
Run a fretting-wear parameter study (flat, rounded or spherical punch; FFT boundary elements)
across all MPI ranks and gather the results in one HDF5 file with a CSV summary. Launch it with
`mpiexec -n N python -m engine STUDY.toml` or `srun python -m engine STUDY.toml`.

subcommands (serial, no MPI):
  plot RESULTS.h5     draw the figures of a results file (PNG); `plot --help` for options
  report RESULTS.h5   print its results tables in Markdown; `report --help` for options"""

_EPILOG = """\
Relative paths ([study] output, --output) are taken from the working directory, not from the
folder of the study file. Exit codes: 0 every case completed, 1 a case failed, 2 bad input,
unusable output path, or output in use by another run or holding another study (nothing
computed or changed), 3 interrupted by a signal (rerun to resume), 70 internal error or a
dead rank.
Example: mpiexec -n 2 python -m engine studies/demo.toml --dry-run"""


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog,
        usage=_USAGE,
        description=_DESCRIPTION,
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("study", type=Path, help="study file (TOML), see studies/*.toml")
    _add_run_options(parser)
    _add_output_options(parser)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    return parser


def _add_run_options(parser: argparse.ArgumentParser) -> None:
    """--dry-run, --resume / --fresh."""
    parser.add_argument(
        "--dry-run",
        action="store_true",
        help="show what a run would do (with --resume: which cases are complete and skipped, "
        "which resume from a checkpoint; with --fresh: what would be deleted) and stop; "
        "changes nothing",
    )
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument(
        "--resume",
        dest="fresh",
        action="store_false",
        default=False,
        help="keep completed cases of an existing results file and skip them (default)",
    )
    mode.add_argument(
        "--fresh",
        dest="fresh",
        action="store_true",
        help="delete existing results, summary and checkpoints and start over",
    )


def _add_output_options(parser: argparse.ArgumentParser) -> None:
    """Where and how results are written, and what a run prints."""
    parser.add_argument(
        "--output",
        type=Path,
        default=None,
        metavar="PATH",
        help="results file to write instead of [study] output",
    )
    parser.add_argument(
        "--output-strategy",
        choices=("auto", "single", "mpio"),
        default=None,
        help="who writes the HDF5 file: rank 0 only (single), every rank through parallel "
        "HDF5 (mpio, needs an MPI-enabled h5py: scripts/build_parallel_h5py.sh), or mpio when "
        "possible (auto); overrides [study] output_strategy (default auto)",
    )
    parser.add_argument(
        "--drop-stale",
        action="store_true",
        help="delete cases of an existing results file that are no longer in the study "
        "(after the sweep shrank); by default they are kept and listed",
    )
    parser.add_argument(
        "--no-progress-bar",
        action="store_true",
        help="never draw the tqdm bar, even on a terminal (the lines per case and the "
        "progress lines are printed anyway)",
    )
    parser.add_argument(
        "--progress-interval",
        type=float,
        default=30.0,
        metavar="S",
        help="seconds between progress lines on stderr (cases completed, cycles of the running "
        "cases, elapsed time, ETA) when there is no bar; one also follows each finished case; "
        "0 turns them off (default 30)",
    )


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] in _OUTPUT_COMMANDS:
        return _output_command(argv, prog)
    stop_event = threading.Event()
    _install_stop_handlers(stop_event)  # first: a signal during start-up is a stop, too
    code = _main_mpi(argv, prog, stop_event)
    return _quiet_shutdown(code, stop_event)


def _quiet_shutdown(code: int, stop_event: threading.Event) -> int:
    """Exit code 3 if this rank saw a stop signal at any time; then ignore further stop
    signals, so one arriving while the interpreter and MPI shut down cannot turn the exit
    code into a signal death (Python restores the default handlers as it finalises, but
    leaves ignored signals ignored)."""
    for name in _STOP_SIGNALS:
        signal.signal(getattr(signal, name), signal.SIG_IGN)
    if stop_event.is_set() and code in (EXIT_OK, EXIT_FAILED):
        return EXIT_INTERRUPTED
    return code


def _main_mpi(argv: list[str], prog: str | None, stop_event: threading.Event) -> int:
    from mpi4py import rc

    rc.thread_level = "funneled"  # only the main thread calls MPI (see engine.parallel.scheduler)
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    rank = comm.Get_rank()
    quiet = contextlib.redirect_stdout(open(os.devnull, "w")) if rank else contextlib.nullcontext()
    quiet_err = (
        contextlib.redirect_stderr(open(os.devnull, "w")) if rank else contextlib.nullcontext()
    )
    try:
        with quiet, quiet_err:
            args = build_parser(prog).parse_args(argv)
    except SystemExit as exit_:  # --help, --version, usage errors: same code on every rank
        return int(exit_.code or 0)
    command_line = " ".join([prog or "python -m engine", shlex.join(argv)])
    _STOP_STATE["rank"] = rank
    from engine.parallel.scheduler import PeerDied

    try:
        return _run(comm, args, command_line, stop_event)
    except PeerDied as error:  # a rank is gone: nothing can continue, end every rank
        sys.stderr.write(f"rank {rank}: {error}\n")
        sys.stderr.flush()
        comm.Abort(EXIT_INTERNAL)
        return EXIT_INTERNAL
    except BrokenPipeError:  # e.g. `--dry-run | head`: stop writing quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except BaseException:  # noqa: BLE001 - never leave other ranks waiting
        sys.stderr.write(f"rank {rank}: internal error\n{traceback.format_exc()}")
        sys.stderr.flush()
        if comm.Get_size() > 1:
            comm.Abort(EXIT_INTERNAL)
        return EXIT_INTERNAL


_OUTPUT_COMMANDS = ("plot", "report")  # post-processing of a results file: serial, no MPI


def _output_command(argv: list[str], prog: str | None) -> int:
    """``plot RESULTS.h5 [--out DIR]`` (engine.analysis.figures), ``report RESULTS.h5 …``
    (engine.analysis.report)."""
    if argv[0] == "plot":
        from engine.analysis.figures import main as command
    else:
        from engine.analysis.report import main as command
    try:
        return command(argv[1:], prog=f"{prog or 'python -m engine'} {argv[0]}")
    except SystemExit as exit_:  # --help, usage errors
        return int(exit_.code or 0)


def _prepare_on_root(args, ranks: int, ranks_on_node: int, lock_holder: list):
    """Validate everything that can be wrong with the input, in this order, before any file is
    created or changed: the study file and its plan (incl. the memory a case needs), the
    output path, the lock on the output (taken here, appended to ``lock_holder``), then the
    existing results file (same study? damaged?).

    Returns (config, plan, strategy, layout, existing) or raises; ``layout`` (datasets to
    pre-create per case) only for the mpio strategy; ``existing`` is the verdict on the
    existing results file (:class:`engine.output.identity.ExistingResults`).
    """
    from engine.output.collective import choose_strategy
    from engine.output.identity import inspect_existing
    from engine.output.lock import OutputLock, check_output_path, check_summary_path
    from engine.study.config import load_study
    from engine.study.layout import plan_layout
    from engine.study.plan import make_plan
    from engine.study.resources import check_memory

    config = load_study(args.study)
    study = config.study
    if args.output is not None:
        study = dataclasses.replace(study, output=args.output)
    if args.output_strategy is not None:
        study = dataclasses.replace(study, output_strategy=args.output_strategy)
    config = dataclasses.replace(config, study=study)
    plan = make_plan(config)
    check_memory(config, ranks_on_node, plan=plan)
    strategy = choose_strategy(config.study.output_strategy, ranks)
    if args.dry_run:  # read-only; a dry run reports the same mismatch a run would
        existing = None
        if not args.fresh:
            existing = inspect_existing(config.study.output, _metadata(config, "", plan), plan)
        return config, plan, strategy, None, existing
    output = config.study.output
    check_output_path(output)
    lock = OutputLock(output)
    lock.acquire()  # before anything else touches the output, --fresh included
    lock_holder.append(lock)
    if lock.replaced is not None:
        print(
            f"note: removed the stale lock of a run that no longer exists (pid "
            f"{lock.replaced.pid}, host {lock.replaced.host})",
            file=sys.stderr,
            flush=True,
        )
    check_summary_path(output, config.study.summary_path)
    existing = None
    if not args.fresh:
        existing = inspect_existing(output, _metadata(config, "", plan), plan)
    layout = plan_layout(config, plan) if strategy == "mpio" else None
    return config, plan, strategy, layout, existing


def _metadata(config, command_line: str, plan):
    """Root metadata; the root grid only when every case of the plan shares it (otherwise
    each case's own grid is in its group, ``/cases/<case_id>/grid``)."""
    from engine.grid import Grid
    from engine.output.hdf5 import StudyMetadata
    from engine.output.identity import study_identity

    mesh = plan.shared_mesh()
    grid = Grid.square(*mesh) if mesh is not None else None
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


def _run(comm, args, command_line: str, stop_event: threading.Event) -> int:
    from mpi4py import MPI

    from engine.output.collective import ParallelH5pyMissing
    from engine.output.hdf5 import ResultsMismatch
    from engine.output.lock import OutputInUse, OutputPathError
    from engine.study.config import StudyConfigError

    rank = comm.Get_rank()
    ranks_on_node = comm.Split_type(MPI.COMM_TYPE_SHARED).Get_size()
    _STOP_STATE["peers"] = comm.allgather((os.getpid(), socket.gethostname()))
    verdict = None
    lock_holder: list = []  # rank 0: the output lock, once taken
    try:
        if rank == 0:
            try:
                verdict = (
                    "ok",
                    *_prepare_on_root(args, comm.Get_size(), ranks_on_node, lock_holder),
                )
            except (
                StudyConfigError,
                ResultsMismatch,
                ParallelH5pyMissing,
                OutputInUse,
                OutputPathError,
            ) as error:
                print(f"error: {error}", file=sys.stderr, flush=True)
                verdict = ("bad-input", None, None, None, None, None)
        kind, config, plan, strategy, layout, existing = comm.bcast(verdict, root=0)
        if kind != "ok":
            return EXIT_BAD_INPUT
        if args.dry_run:
            if rank == 0:
                _print_plan(config, plan, args, comm.Get_size(), strategy, existing)
            return EXIT_OK
        if comm.allreduce(stop_event.is_set(), op=MPI.LOR):  # a signal during start-up
            if rank == 0:
                print(
                    "stop signal received during start-up: nothing computed, no file "
                    "changed (rerun to start)",
                    file=sys.stderr,
                    flush=True,
                )
            return EXIT_INTERRUPTED
        if rank == 0 and existing is not None:
            existing.report(sys.stdout)
        code = _compute(
            comm, config, plan, strategy, layout, args, command_line, stop_event, existing
        )
        return comm.bcast(code, root=0)
    finally:
        for lock in lock_holder:
            lock.release()


# the rank, once MPI is initialised (for the message); (pid, host) of every rank (PeerWatch)
_STOP_STATE: dict = {"rank": None, "peers": None}


def _install_stop_handlers(stop_event: threading.Event) -> None:
    """SIGTERM / SIGUSR1 / SIGINT only set ``stop_event`` (never interrupt a write); rank 0
    says what happens next. A second signal changes nothing: the stop is already under way."""

    def handler(signum, frame):
        if not stop_event.is_set() and _STOP_STATE["rank"] == 0:
            name = signal.Signals(signum).name
            sys.stderr.write(
                f"{name} received: no new cases; saving running cases and "
                "closing the results file (rerun to resume)\n"
            )
        stop_event.set()

    for name in _STOP_SIGNALS:
        signal.signal(getattr(signal, name), handler)


def _settle_existing(config, plan, args, existing, command_line) -> None:
    """Rank 0, under the lock: --fresh removes the old outputs; a damaged file is salvaged or
    moved aside (engine.output.salvage)."""
    from engine.output.hdf5 import remove_outputs
    from engine.output.salvage import apply_existing

    if args.fresh:
        remove_outputs(config.study.output, config.study.checkpoint_dir)
    elif existing is not None:
        apply_existing(
            existing, plan, _metadata(config, command_line, plan), config.study.checkpoint_dir
        )


def _compute(comm, config, plan, strategy, layout, args, command_line, stop_event, existing) -> int:
    """Every rank: open this rank's writer for the strategy (engine.output.hdf5.open_writer),
    prepare the file (rank 0 alone, or every rank for mpio), run the scheduler, close.

    Rank 0 returns the run's exit code; the others' is replaced by it in the final bcast."""
    from engine.output.hdf5 import StoppedDuringSetUp, open_writer
    from engine.output.progress import WorkerProgress
    from engine.parallel.scheduler import Scheduler
    from engine.study.case import CaseRunner

    rank = comm.Get_rank()
    runner = CaseRunner(config)
    if rank != 0:
        runner.on_progress = WorkerProgress(comm)
    writer = open_writer(
        strategy,
        config.study.output,
        comm=comm,
        layout=layout,
        summary_path=config.study.summary_path,
        journal_dir=config.study.checkpoint_dir,
        drop_stale=args.drop_stale,
        should_stop=stop_event.is_set,
    )
    scheduler = Scheduler(
        comm, writer.computing(runner), stop_event=stop_event, peers=_STOP_STATE["peers"]
    )
    if rank == 0:
        _settle_existing(config, plan, args, existing, command_line)
    try:
        completed = writer.prepare(plan, _metadata(config, command_line, plan), fresh=args.fresh)
    except StoppedDuringSetUp as stopped:  # on rank 0, or on every rank at once (mpio)
        if rank == 0:
            print(f"{stopped} (rerun to start)", file=sys.stderr, flush=True)
            if not writer.collective:
                scheduler.run([], lambda outcome: None)  # tell the waiting workers to exit
        return EXIT_INTERRUPTED
    with writer:
        if rank != 0:
            scheduler.run()
            return EXIT_OK  # replaced by rank 0's code in the final bcast
        todo = plan.dispatch_order(skip=completed)
        _announce(config, plan, completed, todo, comm.Get_size(), writer.announce_suffix)
        report = _run_with_progress(scheduler, writer, plan, completed, todo, args, comm, runner)
    _remove_empty_checkpoint_dir(config)
    if writer.closing_note() is not None:
        print(writer.closing_note(), flush=True)
    return _report(config, [row["status"] for row in writer.rows()], report)


def _announce(config, plan, completed, todo, ranks: int, suffix: str = "") -> None:
    """The start line on stdout, and a warning on stderr when ranks would stay idle."""
    from engine.output.progress import plural

    print(
        f"study {config.study.name!r}: {plural(len(plan), 'case')}, {len(completed)} already "
        f"complete, {len(todo)} to run on {plural(ranks, 'rank')} -> {config.study.output}"
        + suffix,
        flush=True,
    )
    warning = _idle_ranks_warning(len(todo), ranks)
    if warning:
        print(warning, file=sys.stderr, flush=True)


def _idle_ranks_warning(cases: int, ranks: int) -> str | None:
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


def _run_with_progress(scheduler, writer, plan, completed, todo, args, comm, runner):
    """Hand out ``todo``; every outcome goes to the writer, then to the progress display.

    Rank 0's own cases report their progress through a queue, the workers' by MPI
    (``engine.output.progress``); the dispatcher drains both at every pass of its loop.
    """
    from engine.output.progress import ProgressChannel, ProgressReporter

    measured = [
        (float(row.get("runtime_s") or 0.0), plan.by_id(row["case_id"]).expected_cost)
        for row in writer.rows()
        if row.get("status") == CaseStatus.COMPLETED
    ]
    progress = ProgressReporter(
        len(plan),
        len(completed),
        todo=todo,
        ranks=comm.Get_size(),
        measured=measured,
        bar=False if args.no_progress_bar else None,
        interval=args.progress_interval,
    )
    channel = ProgressChannel(comm, progress)
    runner.on_progress = channel.local

    def on_outcome(outcome):
        writer.write(outcome)
        progress.update(outcome)

    try:
        return scheduler.run(todo, on_outcome, on_poll=channel.drain)
    finally:
        channel.drain()  # reports that arrived with the last results
        progress.close()


def _remove_empty_checkpoint_dir(config) -> None:
    """``<output>.checkpoints/`` holds the state of interrupted cases (and, with mpio, the
    write journals); once the run leaves it empty it goes too."""
    with contextlib.suppress(OSError):  # not there, or not empty: keep it
        config.study.checkpoint_dir.rmdir()


def _report(config, statuses: list[str], report) -> int:
    failed = statuses.count(CaseStatus.FAILED)
    done = statuses.count(CaseStatus.COMPLETED)
    print(
        f"study {config.study.name!r}: {done} completed, {failed} failed, "
        f"{len(statuses) - done - failed} not completed; wall time "
        f"{report.wall_time_s:.1f} s; summary {config.study.summary_path}",
        flush=True,
    )
    if report.stopped:
        return EXIT_INTERRUPTED
    return EXIT_FAILED if failed else EXIT_OK


def _print_plan(config, plan, args, ranks: int, strategy: str, existing) -> None:
    """--dry-run: what a run with the same options would do; reads, never writes."""
    from engine.output.progress import plural

    loading = config.loading
    what = (
        f"cyclic, P = {loading.load:g} N, {loading.cycles:,} cycles"
        if config.is_cyclic
        else f"static, P = {loading.load:g} N"
    )
    if config.is_fretting:
        control = (
            f"displacement control, amplitude {loading.amplitude:g} mm"
            if loading.amplitude is not None
            else f"force control, force_amplitude {loading.force_amplitude:g} N"
        )
        what = (
            f"fretting, P = {loading.load:g} N held, {control} along "
            f"{loading.direction or 0.0:g}° from x, {loading.cycles:,} cycles"
        )
    if config.sweep.swept_keys:  # the values above are the first of each swept key
        what += "; swept: " + ", ".join(config.sweep.swept_keys)
    output = config.study.output
    print(f"study {config.study.name!r} ({config.source}): {plural(len(plan), 'case')}, {what}")
    print(
        f"output {output} = {output.resolve()} (summary {config.study.summary_path}), "
        f"{strategy} writer"
    )
    if existing is not None and existing.kind != "resume":
        existing.report(sys.stdout)  # damaged: what a run would do with it
    states = _planned_states(config, plan, existing, args.fresh)
    if args.fresh:
        existing = [
            str(path)
            for path in (output, config.study.summary_path, config.study.checkpoint_dir)
            if path.exists()
        ]
        deleted = ", ".join(existing) if existing else "nothing (none exists)"
        print(f"--fresh would delete: {deleted}")
    todo = [case for case in plan.dispatch_order() if states[case.case_id] != "complete: skip"]
    print(
        f"would run {plural(len(todo), 'case')} on {plural(ranks, 'rank')}; "
        f"{len(plan) - len(todo)} complete and skipped"
    )
    warning = _idle_ranks_warning(len(todo), ranks)
    if warning:
        print(warning, file=sys.stderr, flush=True)
    order = {case.case_id: number for number, case in enumerate(todo, start=1)}
    print(
        f"{'case_id':<40s} {'mu1':>6s} {'mu2':>6s} {'wear1':>10s} {'wear2':>10s} {'beta':>6s}"
        "  order  action"
    )
    for case in plan:
        number = order.get(case.case_id)
        print(
            f"{case.case_id:<40s} {case.mu1:6g} {case.mu2:6g} {case.wear1:10.4g} "
            f"{case.wear2:10.4g} {case.beta:6g}  {number if number else '-':>5}  "
            f"{states[case.case_id]}"
        )


def _planned_states(config, plan, existing, fresh: bool) -> dict[str, str]:
    """Per case: "run", "resume from its checkpoint", "complete: skip", from the look at the
    existing file already taken (``existing``: None without a file); --fresh runs all."""
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
