"""Who owns an output: the line of its lock file (``<output>.lock``: ``pid host start``) and
whether that process still runs. Read by the run that takes the lock
(:mod:`engine.output.lock`) and by the readers of a results file, which must not open a file a
run is writing (:func:`being_written`).

A results file being written is not a consistent HDF5 file between two flushes of its
writer: a reader could see half an object header (``KeyError: addr overflow``), and with
HDF5's file locking it is refused outright (``BlockingIOError``). A reader therefore says in
one line who writes the file and what can be read meanwhile: the summary CSV beside it,
rewritten atomically as cases complete, is a consistent snapshot of the completed cases.
"""

from __future__ import annotations

import errno
import os
import socket
import sys
from dataclasses import dataclass
from pathlib import Path

__all__ = [
    "LockOwner",
    "lock_path_for",
    "start_ticks",
    "ResultsBeingWritten",
    "being_written",
    "check_not_being_written",
    "being_written_file",
    "is_locked_error",
    "locked_by_another_program",
]


def lock_path_for(output: Path) -> Path:
    return output.with_name(output.name + ".lock")


@dataclass(frozen=True)
class LockOwner:
    pid: int
    host: str
    start: str  # process start time in clock ticks since boot ("?" where /proc is absent)

    def line(self) -> str:
        return f"{self.pid} {self.host} {self.start}\n"

    @classmethod
    def parse(cls, text: str) -> LockOwner | None:
        words = text.split()
        if len(words) < 2 or not words[0].isdigit():
            return None
        return cls(int(words[0]), words[1], words[2] if len(words) > 2 else "?")

    def is_alive_here(self) -> bool | None:
        """True/False for a process of this host; None when the owner is on another host."""
        if self.host != socket.gethostname():
            return None
        if self.pid <= 0:
            return False
        try:
            os.kill(self.pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:
            pass  # exists, belongs to another user
        if _state(self.pid) in ("Z", "X"):
            return False  # killed, not yet reaped (a container's init may never reap it)
        return self.start in ("?", start_ticks(self.pid))


def _stat_fields(pid: int) -> list[str]:
    """Fields of /proc/PID/stat after the command name (state first), or [] without /proc."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return []
    return stat.rpartition(")")[2].split()


def _state(pid: int) -> str:
    fields = _stat_fields(pid)
    return fields[0] if fields else "?"


def start_ticks(pid: int) -> str:
    """Start time of ``pid`` in clock ticks after boot (field 22 of /proc/PID/stat), or "?"."""
    fields = _stat_fields(pid)
    return fields[19] if len(fields) > 19 else "?"


class ResultsBeingWritten(OSError):
    """The results file is being written by a run: read it when the run has ended (or its
    summary CSV meanwhile)."""

    def __init__(self, message: str) -> None:
        super().__init__(errno.EBUSY, message)

    def __str__(self) -> str:
        return self.strerror


def being_written(path: Path) -> str | None:
    """One line saying that a run is writing the results file ``path`` (its lock names a
    live process of this host, or a process of another host) and how to read it; None when
    no run holds it."""
    path = Path(path)
    lock = lock_path_for(path)
    try:
        owner = LockOwner.parse(lock.read_text(errors="replace"))
    except OSError:
        return None
    if owner is None:
        return None
    alive = owner.is_alive_here()
    if alive is False:
        return None  # a stale lock of a killed run: the file is as that run left it
    who = f"pid {owner.pid}, host {owner.host}"
    if alive is None:
        who += f"; if that run is gone, delete {lock}"
    return _message(path, who)


def _message(path: Path, who: str) -> str:
    summary = path.with_suffix(".csv")
    return (
        f"{path}: being written by a run ({who}); read it once the run has ended, or "
        f"meanwhile the summary of its completed cases: engine.load_summary('{summary}')"
    )


def being_written_file(paths: Path | list[Path]) -> bool:
    """For the commands on results files (exit 2): whether a run writes one of ``paths``;
    says so on stderr in one line (:func:`being_written`) for the first such path."""
    for path in [paths] if isinstance(paths, Path) else paths:
        message = being_written(path)
        if message is not None:
            print(f"error: {message}", file=sys.stderr)
            return True
    return False


def check_not_being_written(path: Path) -> None:
    """Raise :class:`ResultsBeingWritten` when a run holds ``path`` (:func:`being_written`)."""
    message = being_written(path)
    if message is not None:
        raise ResultsBeingWritten(message)


def is_locked_error(error: BaseException) -> bool:
    """Whether ``error`` is HDF5 refusing a file another process holds open for writing."""
    return isinstance(error, BlockingIOError) or (
        isinstance(error, OSError) and "unable to lock file" in str(error)
    )


def locked_by_another_program(path: Path) -> ResultsBeingWritten:
    """The error for a file HDF5 finds locked with no run of this engine holding it."""
    return ResultsBeingWritten(_message(Path(path), "another process holds it open"))
