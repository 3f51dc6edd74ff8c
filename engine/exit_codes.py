"""The exit codes of the commands, defined once.

:class:`ExitCode` holds the numbers; :data:`STUDY_RUN` says what each means for a study run
(``python -m engine STUDY.toml``) and :data:`VERIFY` for ``python -m engine verify``;
:data:`RUN_STATUSES` names what a run can end as (``StudyRun.status`` of ``run_study``) and
the code each exits with. The command line returns these members, its ``--help`` epilog is
:func:`epilog_text` of :data:`STUDY_RUN` and :func:`status_epilog`, and
``scripts/reference.py`` writes the tables of ``docs/reference/exit-codes.md`` and of the
SLURM guide from them (:func:`markdown_rows`).

This module imports nothing of the engine.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

__all__ = [
    "ExitCode",
    "Meaning",
    "RunStatus",
    "STUDY_RUN",
    "RUN_STATUSES",
    "VERIFY",
    "LAUNCHER",
    "epilog_text",
    "status_epilog",
]


class ExitCode(enum.IntEnum):
    """The process exit codes (an ``int``: ``sys.exit(ExitCode.FAILED)`` exits with 1)."""

    OK = 0
    FAILED = 1
    BAD_INPUT = 2
    INTERRUPTED = 3
    DAMAGED = 4
    OUTPUT_FULL = 5
    INTERNAL = 70


@dataclass(frozen=True)
class Meaning:
    """What an exit code means for one command: ``short`` for the ``--help`` epilog,
    ``long`` (Markdown) for the manual's table."""

    code: ExitCode
    short: str
    long: str


#: A study run (``python -m engine STUDY.toml``), on every rank.
STUDY_RUN = (
    Meaning(ExitCode.OK, "every case completed", "every case completed"),
    Meaning(
        ExitCode.FAILED,
        "a case failed",
        "at least one case failed (message and traceback stored in its group)",
    ),
    Meaning(
        ExitCode.BAD_INPUT,
        "bad input, unusable output path, or output in use by another run or holding another "
        "study (nothing computed or changed)",
        "bad input or unusable output, nothing computed, no file of another run touched: a "
        "study-file error (file, key, value), a value outside the model's range, a mesh that "
        "does not fit in memory (estimate and limit), an output path that cannot be written "
        "(path and OS error), an output **in use by another run (pid, host)**, an existing "
        "output holding **another study** (every difference named), an unrelated CSV where "
        "the summary goes, a **launch whose MPI world is smaller than the tasks started** "
        "(`srun` without `--mpi=pmi2`/`pmix`, another MPI's `mpiexec`: "
        "[SLURM](../how-to/slurm.md#2-check-a-launch-the-pmi-plug-in-your-mpi-needs))",
    ),
    Meaning(
        ExitCode.INTERRUPTED,
        "interrupted by a signal (rerun to resume)",
        "stopped by SIGTERM, SIGUSR1 or SIGINT — on any rank, at any time: start-up, "
        "computing, shutdown, a second signal. State saved; rerun (plain or `--resume`) to "
        "continue",
    ),
    Meaning(
        ExitCode.DAMAGED,
        "a case written cannot be read back (rerun)",
        "a case the run wrote cannot be read back: rerun to recompute it (`verify` gives 4 "
        "for a damaged file)",
    ),
    Meaning(
        ExitCode.OUTPUT_FULL,
        "the output's file system is full (free space, rerun to resume)",
        "the output's file system is full: completed cases kept, one line names the path and "
        "the space needed; free space and rerun to resume ([check a results "
        "file](../how-to/results-integrity.md))",
    ),
    Meaning(
        ExitCode.INTERNAL,
        "internal error or a dead rank",
        "internal error: the communicator is aborted, so no rank is left waiting",
    ),
)


@dataclass(frozen=True)
class RunStatus:
    """What a study run can end as (``StudyRun.status``), the code the command line exits
    with, and what it means (Markdown)."""

    name: str
    code: ExitCode
    meaning: str


#: Every status of a run, in the order of the exit codes.
RUN_STATUSES = (
    RunStatus("completed", ExitCode.OK, "every case completed"),
    RunStatus("planned", ExitCode.OK, "a dry run (`--dry-run`): nothing computed or changed"),
    RunStatus("failed", ExitCode.FAILED, "at least one case failed"),
    RunStatus(
        "invalid",
        ExitCode.BAD_INPUT,
        "bad input, an unusable output path, or an output in use by another run or holding "
        "another study: nothing computed, nothing changed; the message says why",
    ),
    RunStatus(
        "interrupted",
        ExitCode.INTERRUPTED,
        "stopped by a signal (or `run_study`'s `stop_event`): run again to resume",
    ),
    RunStatus(
        "damaged",
        ExitCode.DAMAGED,
        "a case the run wrote cannot be read back: run again to recompute it",
    ),
    RunStatus(
        "output-full",
        ExitCode.OUTPUT_FULL,
        "the output's file system is full: completed cases kept; free space and run again",
    ),
)


#: What the launcher returns when a rank dies (not an exit code of the engine's own).
LAUNCHER = (
    "a rank *died* (SIGKILL, OOM killer, node loss): `mpiexec` (Hydra) kills the other ranks "
    "at once and returns the signal number (9); with `srun` use `--kill-on-bad-exit=1` (or "
    "`KillOnBadExit=1`), otherwise SLURM leaves the other tasks running"
)

#: ``python -m engine verify RESULTS.h5``.
VERIFY = (
    Meaning(
        ExitCode.OK,
        "whole",
        "whole: every completed case read in full with equal checksums; the CSV (if present) "
        "agrees",
    ),
    Meaning(
        ExitCode.BAD_INPUT,
        "bad input",
        "bad input: no such file, or not a results file of this engine (a study file, a CSV, "
        "another program's HDF5 file …: the line says what it is and what to pass)",
    ),
    Meaning(ExitCode.INTERRUPTED, "interrupted", "interrupted (Ctrl-C, SIGTERM)"),
    Meaning(
        ExitCode.DAMAGED,
        "damaged",
        "damaged (a results file only): a case or the file cannot be read, a checksum differs, "
        "or the CSV disagrees",
    ),
)


def epilog_text(meanings=STUDY_RUN) -> str:
    """``Exit codes: 0 every case completed, 1 a case failed, …`` for a ``--help`` epilog."""
    return "Exit codes: " + ", ".join(f"{m.code.value} {m.short}" for m in meanings) + "."


def status_epilog() -> str:
    """``Run statuses (exit code): completed 0, planned 0, …`` for a ``--help`` epilog."""
    statuses = ", ".join(f"{status.name} {status.code.value}" for status in RUN_STATUSES)
    return f"Run statuses (exit code): {statuses}."


def markdown_rows(meanings, launcher: str | None = None) -> list[tuple[str, str]]:
    """(code, meaning) rows of the manual's table; ``launcher``: a last row for what the
    launcher returns when a rank dies."""
    rows = [(str(m.code.value), m.long) for m in meanings]
    if launcher:
        rows.append(("launcher's", launcher))
    return rows
