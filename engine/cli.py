"""Entry point: ``python -m engine STUDY.toml`` (also under ``mpiexec -n N`` or ``srun``).

Post-processing (serial, no MPI): ``python -m engine plot RESULTS.h5 [--out DIR]`` writes the
figures (:mod:`engine.output.figures`), ``python -m engine report RESULTS.h5`` prints the
results tables in Markdown (:mod:`engine.output.report`).

This is the only module that touches ``MPI.COMM_WORLD``; every layer below receives a
communicator. The flow:

1. every rank parses the command line; rank 0 validates the study file, expands the plan and
   checks that an existing results file belongs to the same study — before any file is created
   or changed — and broadcasts the verdict (bad input: exit code 2 on every rank);
2. the output strategy is chosen (``--output-strategy`` / ``[study] output_strategy``): the
   single writer (rank 0 owns the file; default with the PyPI h5py wheel) or collective mpio
   (every rank writes its own cases; automatic when h5py is MPI-enabled and ranks > 1, see
   ``engine.output.collective``); the writer prepares the file and learns which cases are
   complete;
3. the scheduler hands the remaining cases out dynamically; rank 0 computes as well;
4. SIGTERM / SIGUSR1 / SIGINT set a stop flag: no new cases, running cyclic cases save their
   state, the file is closed cleanly, exit code 3; the next run resumes.

Exit codes: 0 all cases completed; 1 at least one case failed; 2 bad input (nothing computed,
no output created or changed); 3 interrupted by a signal (rerun to resume); 70 internal error
(the communicator is aborted so no rank waits forever).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import os
import shlex
import signal
import sys
import threading
import traceback
from pathlib import Path

from engine import __version__

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_INTERNAL = 0, 1, 2, 3, 70
_STOP_SIGNALS = ("SIGTERM", "SIGUSR1", "SIGINT")


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Run a fretting-wear parameter study (flat punch, FFT boundary elements) "
        "across all MPI ranks and gather the results in one HDF5 file with a CSV summary.",
        epilog="Exit codes: 0 ok, 1 a case failed, 2 bad input, 3 interrupted (rerun to "
        "resume). Example: mpiexec -n 2 python -m engine studies/demo.toml",
    )
    parser.add_argument("study", type=Path, help="study file (TOML), see studies/*.toml")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--dry-run", action="store_true", help="list the cases and stop")
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
    parser.add_argument(
        "--output", type=Path, default=None, help="results file to write instead of [study] output"
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
        "--no-progress-bar",
        action="store_true",
        help="never draw the tqdm bar (lines per case are always printed)",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    return parser


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] in _OUTPUT_COMMANDS:
        return _output_command(argv, prog)
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
    try:
        return _run(comm, args, command_line)
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
    """``plot RESULTS.h5 [--out DIR]`` (engine.output.figures), ``report RESULTS.h5 …``
    (engine.output.report)."""
    if argv[0] == "plot":
        from engine.output.figures import main as command
    else:
        from engine.output.report import main as command
    try:
        return command(argv[1:], prog=f"{prog or 'python -m engine'} {argv[0]}")
    except SystemExit as exit_:  # --help, usage errors
        return int(exit_.code or 0)


def _prepare_on_root(args, ranks: int):
    """Validate everything that can be wrong with the input.

    Returns (config, plan, strategy, layout) or raises; ``layout`` (datasets to pre-create per
    case) only for the mpio strategy.
    """
    from engine.output.collective import choose_strategy
    from engine.output.hdf5 import check_resumable
    from engine.study.config import load_study
    from engine.study.layout import plan_layout
    from engine.study.plan import make_plan

    config = load_study(args.study)
    study = config.study
    if args.output is not None:
        study = dataclasses.replace(study, output=args.output)
    if args.output_strategy is not None:
        study = dataclasses.replace(study, output_strategy=args.output_strategy)
    config = dataclasses.replace(config, study=study)
    plan = make_plan(config)
    strategy = choose_strategy(config.study.output_strategy, ranks)
    if not args.fresh and not args.dry_run:
        check_resumable(config.study.output, _metadata(config, "", plan))
    layout = plan_layout(config, plan) if strategy == "mpio" and not args.dry_run else None
    return config, plan, strategy, layout


def _metadata(config, command_line: str, plan):
    """Root metadata; the root grid only when every case of the plan shares it (otherwise
    each case's own grid is in its group, ``/cases/<case_id>/grid``)."""
    from engine.grid import Grid
    from engine.output.hdf5 import StudyMetadata

    mesh = plan.shared_mesh()
    grid = Grid.square(*mesh) if mesh is not None else None
    return StudyMetadata(
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


def _run(comm, args, command_line: str) -> int:
    from engine.output.collective import ParallelH5pyMissing
    from engine.output.hdf5 import ResultsMismatch
    from engine.study.config import StudyConfigError

    rank = comm.Get_rank()
    verdict = None
    if rank == 0:
        try:
            verdict = ("ok", *_prepare_on_root(args, comm.Get_size()))
        except (StudyConfigError, ResultsMismatch, ParallelH5pyMissing) as error:
            print(f"error: {error}", file=sys.stderr, flush=True)
            verdict = ("bad-input", None, None, None, None)
    kind, config, plan, strategy, layout = comm.bcast(verdict, root=0)
    if kind != "ok":
        return EXIT_BAD_INPUT
    if args.dry_run:
        if rank == 0:
            _print_plan(config, plan)
        return EXIT_OK

    stop_event = threading.Event()
    _install_stop_handlers(stop_event, rank)
    if strategy == "mpio":
        code = _compute_collective(comm, config, plan, layout, args, command_line, stop_event)
    else:
        code = _compute(comm, config, plan, args, command_line, stop_event)
    return comm.bcast(code, root=0)


def _install_stop_handlers(stop_event: threading.Event, rank: int) -> None:
    def handler(signum, frame):
        if not stop_event.is_set() and rank == 0:
            name = signal.Signals(signum).name
            sys.stderr.write(
                f"{name} received: no new cases; saving running cases and "
                "closing the results file (rerun to resume)\n"
            )
        stop_event.set()

    for name in _STOP_SIGNALS:
        signal.signal(getattr(signal, name), handler)


def _compute(comm, config, plan, args, command_line, stop_event) -> int:
    from engine.output.hdf5 import SingleWriter, remove_outputs
    from engine.parallel.scheduler import Scheduler
    from engine.study.case import CaseRunner

    scheduler = Scheduler(comm, CaseRunner(config), stop_event=stop_event)
    if comm.Get_rank() != 0:
        scheduler.run()
        return EXIT_OK  # replaced by rank 0's code in the final bcast

    if args.fresh:
        remove_outputs(config.study.output, config.study.checkpoint_dir)
    with SingleWriter(config.study.output, config.study.summary_path) as writer:
        completed = writer.prepare(plan, _metadata(config, command_line, plan), fresh=args.fresh)
        todo = plan.dispatch_order(skip=completed)
        print(
            f"study {config.study.name!r}: {len(plan)} cases, {len(completed)} already "
            f"complete, {len(todo)} to run on {comm.Get_size()} rank(s) -> "
            f"{config.study.output}",
            flush=True,
        )
        report = _run_with_progress(scheduler, writer, plan, completed, todo, args)
        statuses = [row["status"] for row in writer.rows()]
    return _report(config, statuses, report)


def _compute_collective(comm, config, plan, layout, args, command_line, stop_event) -> int:
    """mpio strategy: every rank opens the file and writes the cases it computes."""
    import time

    from engine.output.collective import CollectiveWriter
    from engine.output.hdf5 import remove_outputs
    from engine.parallel.scheduler import Scheduler
    from engine.study.case import CaseRunner

    rank = comm.Get_rank()
    if args.fresh and rank == 0:
        remove_outputs(config.study.output, config.study.checkpoint_dir)
    comm.Barrier()
    writer = CollectiveWriter(
        config.study.output,
        comm,
        layout,
        summary_path=config.study.summary_path,
        journal_dir=config.study.checkpoint_dir,
    )
    completed = writer.prepare(plan, _metadata(config, command_line, plan), fresh=args.fresh)
    runner = CaseRunner(config)
    scheduler = Scheduler(
        comm, runner if rank == 0 else writer.owner(runner), stop_event=stop_event
    )
    if rank != 0:
        scheduler.run()
        writer.close()
        return EXIT_OK  # replaced by rank 0's code in the final bcast

    todo = plan.dispatch_order(skip=completed)
    print(
        f"study {config.study.name!r}: {len(plan)} cases, {len(completed)} already complete, "
        f"{len(todo)} to run on {comm.Get_size()} rank(s) -> {config.study.output} "
        "(collective mpio output)",
        flush=True,
    )
    report = _run_with_progress(scheduler, writer, plan, completed, todo, args)
    start = time.perf_counter()
    writer.close()
    print(
        f"output (mpio): {writer.write_seconds_total:.2f} s writing data over all ranks, "
        f"{writer.commit_seconds:.2f} s collective prepare/commit "
        f"(close {time.perf_counter() - start:.2f} s)",
        flush=True,
    )
    return _report(config, [row["status"] for row in writer.rows()], report)


def _run_with_progress(scheduler, writer, plan, completed, todo, args):
    """Hand out ``todo``; every outcome goes to the writer, then to the progress display."""
    from engine.output.progress import ProgressReporter

    progress = ProgressReporter(
        len(plan), len(completed), bar=False if args.no_progress_bar else None
    )

    def on_outcome(outcome):
        writer.write(outcome)
        progress.update(outcome)

    try:
        return scheduler.run(todo, on_outcome)
    finally:
        progress.close()


def _report(config, statuses: list[str], report) -> int:
    failed = statuses.count("failed")
    done = statuses.count("completed")
    print(
        f"study {config.study.name!r}: {done} completed, {failed} failed, "
        f"{len(statuses) - done - failed} not completed; wall time "
        f"{report.wall_time_s:.1f} s; summary {config.study.summary_path}",
        flush=True,
    )
    if report.stopped:
        return EXIT_INTERRUPTED
    return EXIT_FAILED if failed else EXIT_OK


def _print_plan(config, plan) -> None:
    loading = config.loading
    what = (
        f"cyclic, P = {loading.load:g} N, {loading.cycles} cycles"
        if config.is_cyclic
        else f"static, P = {loading.load:g} N"
    )
    if config.sweep.swept_keys:  # the values above are the first of each swept key
        what += "; swept: " + ", ".join(config.sweep.swept_keys)
    print(f"study {config.study.name!r} ({config.source}): {len(plan)} cases, {what}")
    print(f"output {config.study.output} (summary {config.study.summary_path})")
    print(f"{'case_id':<40s} {'mu1':>6s} {'mu2':>6s} {'wear1':>10s} {'wear2':>10s} {'beta':>6s}")
    for case in plan:
        print(
            f"{case.case_id:<40s} {case.mu1:6g} {case.mu2:6g} {case.wear1:10.4g} "
            f"{case.wear2:10.4g} {case.beta:6g}"
        )
