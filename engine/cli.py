"""Entry point: ``python -m engine STUDY.toml`` (also under ``mpiexec -n N`` or ``srun``).

Post-processing (serial, no MPI): ``python -m engine plot RESULTS.h5 [--out DIR]`` writes the
figures (:mod:`engine.analysis.figures`), ``python -m engine report RESULTS.h5`` prints the
results tables in Markdown (:mod:`engine.analysis.report`), ``python -m engine verify
RESULTS.h5`` reads every case back and compares its checksums (:mod:`engine.output.verify`).

This is the only module that touches ``MPI.COMM_WORLD``; every layer below receives a
communicator. It parses the command line and hands the run to :func:`engine.run.run_study`,
mapping the run's status to the exit code. The flow:

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
   (exit 70, ``engine.parallel.scheduler.PeerWatch``). See docs/how-to/resume-and-requeue.md.

Exit codes: :mod:`engine.exit_codes` defines them and what each means (the ``--help`` epilog
and docs/reference/exit-codes.md are generated from it).
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import importlib
import logging
import os
import shlex
import signal
import sys
import textwrap
import threading
import time
import traceback
from pathlib import Path

from engine._stop_flag import StopFlag
from engine._version import __version__
from engine.exit_codes import RUN_STATUSES, ExitCode, epilog_text, status_epilog
from engine.interpreter import check_interpreter, launcher_mismatch

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = ExitCode.OK, ExitCode.FAILED, ExitCode.BAD_INPUT
EXIT_INTERRUPTED, EXIT_INTERNAL = ExitCode.INTERRUPTED, ExitCode.INTERNAL
EXIT_DAMAGED, EXIT_OUTPUT_FULL = ExitCode.DAMAGED, ExitCode.OUTPUT_FULL
_STOP_SIGNALS = ("SIGTERM", "SIGUSR1", "SIGINT")
_QUIET_EXIT_DELAY = 2.0  # s: ranks other than 0 wait this long before exiting on a bad launch


_USAGE = """\
%(prog)s STUDY.toml [--dry-run] [--resume | --fresh] [--drop-stale] [--output PATH]
            [--output-strategy {auto,single,mpio}] [--no-progress-bar] [--progress-interval S]
       %(prog)s plot RESULTS.h5 [--out DIR]
       %(prog)s report RESULTS.h5 [--cycles N ...] [--update DOC.md]
       %(prog)s verify RESULTS.h5 [--summary CSV | --no-summary]"""

_DESCRIPTION = """\
Run a fretting-wear parameter study (FFT boundary elements) across all MPI ranks and gather
the results in one HDF5 file with a CSV summary. Launch it with
`.venv/bin/mpiexec -n N .venv/bin/python -m engine STUDY.toml` (or, the environment
activated, `mpiexec -n N python -m engine STUDY.toml`; `srun python -m engine …` under SLURM).

{vocabulary}

subcommands (serial, no MPI):
  plot RESULTS.h5     draw the figures of a results file (PNG); `plot --help` for options
  report RESULTS.h5   print its results tables in Markdown; `report --help` for options
  verify RESULTS.h5   read every case back, compare checksums and the summary CSV with the
                      file (exit 0 whole, 4 damaged; `verify --help` for all)"""

_EPILOG = "\n".join(
    (
        textwrap.fill(
            "Relative paths: the results file ([study] output, --output) is written from the "
            "working directory; the files a study reads ([surface] path, [calibrate] tests) "
            "are found from the folder of the study file. " + epilog_text() + " " + status_epilog(),
            width=95,
        ),
        "Example: .venv/bin/mpiexec -n 2 .venv/bin/python -m engine studies/demo.toml --dry-run",
    )
)


def vocabulary() -> str:
    """The loading kinds and punch shapes a study file may name, one line each, from their
    registries (``engine.study.kinds.KINDS``, ``engine.geometry.PROFILES``)."""
    from engine.geometry import PROFILES
    from engine.study.kinds import KINDS

    lines = ["[loading] kind:"]
    lines += [f"  {name:<10s}  {kind.summary}" for name, kind in KINDS.items()]
    lines.append("[punch] shape:")
    lines += [f"  {name:<10s}  {profile.description}" for name, profile in PROFILES.items()]
    return "\n".join(lines)


class _Parser(argparse.ArgumentParser):
    """The command's parser: its description names the registered loading kinds and punch
    shapes (:func:`vocabulary`), which are imported only when the help is printed, so that
    ``--version`` and a run's parsing load none of them."""

    def format_help(self) -> str:
        self.description = _DESCRIPTION.format(vocabulary=vocabulary())
        return super().format_help()


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = _Parser(
        prog=prog,
        usage=_USAGE,
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
        type=_seconds,
        default=30.0,
        metavar="S",
        help="seconds between progress lines on stderr (cases completed, cycles of the running "
        "cases, elapsed time, ETA) when there is no bar; one also follows each finished case; "
        "0 turns them off (default 30)",
    )


MAX_PROGRESS_INTERVAL = 86400.0  # s: a progress line at least once a day


def _seconds(text: str) -> float:
    """--progress-interval: a finite number of seconds in [0, 86400] (0: no progress lines)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not 0.0 <= value <= MAX_PROGRESS_INTERVAL:  # also refuses nan and inf
        raise argparse.ArgumentTypeError(
            f"{text} must lie in [0, {MAX_PROGRESS_INTERVAL:g}] s (0 turns the lines off)"
        )
    return value


def main(
    argv: list[str] | None = None,
    prog: str | None = None,
    stop_event: threading.Event | None = None,
) -> int:
    """The command line; ``stop_event``: one that early stop-signal handlers already set
    (``python -m engine`` installs them before importing this module)."""
    argv = sys.argv[1:] if argv is None else list(argv)

    if code := check_interpreter(argv):  # a Python without the engine's packages: exit 2
        return code
    if argv and argv[0] in _OUTPUT_COMMANDS:
        signal.signal(signal.SIGINT, signal.default_int_handler)  # Ctrl-C ends them at once
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        signal.signal(signal.SIGUSR1, signal.SIG_DFL)
        return _output_command(argv, prog)
    stop_event = stop_event if stop_event is not None else StopFlag()
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


def _world():
    """``MPI.COMM_WORLD``; without an MPI launcher (:func:`engine.interpreter.launcher_seen`),
    a :class:`engine.parallel.serial.SerialComm`, which neither loads mpi4py nor initialises
    MPI: the world of a process started alone has one rank either way."""
    from engine.interpreter import launcher_seen

    if not launcher_seen():
        from engine.parallel.serial import SerialComm

        return SerialComm()
    from mpi4py import rc

    rc.thread_level = "funneled"  # only the main thread calls MPI (see engine.parallel.scheduler)
    from mpi4py import MPI

    return MPI.COMM_WORLD


def _main_mpi(argv: list[str], prog: str | None, stop_event: threading.Event) -> int:
    comm = _world()
    mismatch = launcher_mismatch(comm.Get_size())  # another MPI's mpiexec, srun without PMI
    if mismatch is not None:
        if mismatch:
            print(mismatch, file=sys.stderr, flush=True)
        else:  # let the task numbered 0 say why: `srun --kill-on-bad-exit` ends the step
            time.sleep(_QUIET_EXIT_DELAY)  # as soon as one task exits non-zero
        return EXIT_BAD_INPUT
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
    except Exception as error:  # noqa: BLE001 - never leave other ranks waiting
        if not _no_space(error):
            return _internal_error(comm, rank)
        # a write the writers do not guard met a full disk (a file system that cannot claim
        # space, a collective call that failed on this rank): one line, every rank ended
        sys.stderr.write(f"error: {_short_no_space(error)}\n")
        sys.stderr.flush()
        if comm.Get_size() > 1:
            comm.Abort(EXIT_OUTPUT_FULL)
        return EXIT_OUTPUT_FULL
    except BaseException:  # noqa: BLE001 - never leave other ranks waiting
        return _internal_error(comm, rank)


def _internal_error(comm, rank: int) -> int:
    """The traceback on stderr, every other rank ended (exit code 70)."""
    sys.stderr.write(f"rank {rank}: internal error\n{traceback.format_exc()}")
    sys.stderr.flush()
    if comm.Get_size() > 1:
        comm.Abort(EXIT_INTERNAL)
    return EXIT_INTERNAL


def _no_space(error: BaseException) -> bool:
    """Whether ``error`` says the disk (or the quota) is full: an errno, or HDF5's message
    (as :func:`engine.output.space.is_no_space`, which the start-up does not import)."""
    if isinstance(error, OSError) and error.errno in (errno.ENOSPC, errno.EDQUOT):
        return True
    text = str(error)
    return "errno = 28" in text or "No space left" in text or "Disk quota exceeded" in text


def _short_no_space(error: BaseException) -> str:
    """The message of :class:`engine.output.space.OutputFull` (it says what to do), or the
    first line of another error saying the disk is full (HDF5's runs over many lines)."""
    text = str(error)
    if "rerun to resume" in text:
        return text
    filename = getattr(error, "filename", None)
    where = f"{filename}: " if filename else ""
    first = (text.splitlines() or [""])[0][:200]
    return (
        f"{where}no space left on its file system ({first}); completed cases are kept: free "
        "space or choose another output, then rerun to resume"
    )


#: The commands on a results file (serial, no MPI) and the modules whose ``main`` they run,
#: imported when the command is asked for.
_OUTPUT_COMMANDS = {
    "plot": "engine.analysis.figures",
    "report": "engine.analysis.report",
    "verify": "engine.output.verify",
}


def _output_command(argv: list[str], prog: str | None) -> int:
    """``plot RESULTS.h5 [--out DIR]`` (engine.analysis.figures), ``report RESULTS.h5 …``
    (engine.analysis.report)."""
    command = importlib.import_module(_OUTPUT_COMMANDS[argv[0]]).main
    try:
        return command(argv[1:], prog=f"{prog or 'python -m engine'} {argv[0]}")
    except SystemExit as exit_:  # --help, usage errors
        return int(exit_.code or 0)


# StudyRun.status -> exit code (the module docstring lists what each means)
EXIT_CODES = {status.name: status.code for status in RUN_STATUSES}


class _ConsoleHandler(logging.Handler):
    """The run's log as the command line shows it: INFO on stdout (a record marked
    ``stream="stderr"``, a progress status line, on stderr), WARNING and above on stderr, the
    message alone, flushed line by line (the streams are looked up at each record, so a
    redirection in force is followed)."""

    def emit(self, record: logging.LogRecord) -> None:
        to_stderr = record.levelno >= logging.WARNING or getattr(record, "stream", "") == "stderr"
        stream = sys.stderr if to_stderr else sys.stdout
        try:
            stream.write(self.format(record) + "\n")
            stream.flush()
        except BrokenPipeError:
            raise
        except Exception:  # noqa: BLE001 - logging must not end the run
            self.handleError(record)


@contextlib.contextmanager
def _console_log(name: str = "engine"):
    """Show the records of the logger ``name`` (INFO and above) on the console meanwhile."""
    logger, handler = logging.getLogger(name), _ConsoleHandler(logging.INFO)
    previous = logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    try:
        yield
    finally:
        logger.removeHandler(handler)
        logger.setLevel(previous)


def _run(comm, args, command_line: str, stop_event: threading.Event) -> int:
    """The study run through :func:`engine.run.run_study`, its log on the console; its
    status as the exit code."""
    from engine.run import run_study

    with _console_log():
        run = _run_study(run_study, comm, args, command_line, stop_event)
    if comm.Get_rank() == 0 and run.status in ("invalid", "output-full"):
        print(f"error: {run.message}", file=sys.stderr, flush=True)
    return EXIT_CODES[run.status]


def _run_study(run_study, comm, args, command_line: str, stop_event: threading.Event):
    return run_study(
        args.study,
        comm=comm,
        output=args.output,
        fresh=args.fresh,
        progress=False if args.no_progress_bar else None,
        progress_interval=args.progress_interval,
        output_strategy=args.output_strategy,
        drop_stale=args.drop_stale,
        dry_run=args.dry_run,
        stop_event=stop_event,
        command_line=command_line,
        check=False,
    )


# the rank, once MPI is initialised (for the message of the stop handler)
_STOP_STATE: dict = {"rank": None}


def _install_stop_handlers(stop_event: threading.Event) -> None:
    """SIGTERM / SIGUSR1 / SIGINT only set ``stop_event`` (never interrupt a write); rank 0
    says what happens next. A second signal changes nothing: the stop is already under way."""

    def handler(signum, frame):
        # runs between two bytecodes of the main thread, which may hold any lock then: no
        # lock is taken here (a StopFlag's set, an unbuffered write to the descriptor)
        if stop_event.is_set():
            return  # a second signal (mpiexec forwards its own): the stop is under way
        stop_event.set()
        if _STOP_STATE["rank"] == 0:
            name = signal.Signals(signum).name
            line = (
                f"{name} received: no new cases; saving running cases and "
                "closing the results file (rerun to resume)\n"
            )
            with contextlib.suppress(OSError):  # stderr on a full disk, or closed
                os.write(sys.stderr.fileno(), line.encode())

    for name in _STOP_SIGNALS:
        signal.signal(getattr(signal, name), handler)
