"""One run per output: a lock file beside the results file, taken before anything else.

``<output>.lock`` (e.g. ``results/demo.h5.lock``) holds one line ``pid host start`` of the
process that owns the output (rank 0 of the run). It is created atomically — written in full
under a private name, then hard-linked to the lock name, which fails if the lock exists — so a
lock file is never seen half written, and the method works on NFS as well as on local disks.

A second run on the same output (also a ``--fresh`` one) finds the lock and stops with exit
code 2: ``in use by another run (pid 1234, host node17)``. It never removes or changes the
other run's files.

Stale locks: a run killed by SIGKILL, the OOM killer or a node loss cannot remove its lock.
On the *same host* a lock is stale when its process no longer exists (or the pid now belongs
to a process started later: the start time, in clock ticks since boot from ``/proc``, is part
of the lock); it is then replaced, with a message. On another host the engine cannot tell
whether the owner is alive: the message names the lock file to delete once the user knows the
other run is gone.
"""

from __future__ import annotations

import errno
import os
import socket
from dataclasses import dataclass
from pathlib import Path

from .space import OutputFull, is_no_space

__all__ = [
    "OutputLock",
    "OutputInUse",
    "OutputPathError",
    "lock_path_for",
    "check_output_path",
    "check_output_name",
]


class OutputInUse(ValueError):
    """Another live run holds the output (exit code 2, nothing written)."""


class OutputPathError(ValueError):
    """The output cannot be written: names the path and the operating-system error."""


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
        return self.start in ("?", _start_ticks(self.pid))


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


def _start_ticks(pid: int) -> str:
    """Start time of ``pid`` in clock ticks after boot (field 22 of /proc/PID/stat), or "?"."""
    fields = _stat_fields(pid)
    return fields[19] if len(fields) > 19 else "?"


def _describe(error: OSError) -> str:
    return error.strerror or str(error)


RESULTS_SUFFIXES = (".h5", ".hdf5")


def check_output_name(output: Path, where: str = "--output") -> None:
    """The rule of ``[study] output`` for an output given elsewhere (``--output``): a path
    ending in .h5 or .hdf5 (the summary CSV is written beside it with the suffix .csv, so any
    other name could make the two one file). Raises :class:`OutputPathError`."""
    if not str(output).endswith(RESULTS_SUFFIXES) or str(output).endswith(("/", os.sep)):
        raise OutputPathError(
            f"{where} {output}: must be a path ending in .h5 or .hdf5 (the results file; the "
            "summary is written beside it as .csv)"
        )


def check_output_path(output: Path) -> None:
    """Make the output's directory and check that files can be created in it.

    Raises :class:`OutputPathError` naming the path and the OS error (a parent that is a
    regular file, a read-only or immutable directory, a path under /proc, …).
    """
    if output.exists() and not output.is_file():
        raise OutputPathError(f"output {output}: exists and is not a regular file")
    for ancestor in output.parents:
        if ancestor.exists():
            if not ancestor.is_dir():
                raise OutputPathError(f"output {output}: {ancestor} is not a directory")
            break
    try:
        output.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        if is_no_space(error):
            raise OutputFull(output, 4096, 0) from None
        raise OutputPathError(
            f"output {output}: cannot create directory {output.parent}: {_describe(error)}"
        ) from None
    if output.exists() and not os.access(output, os.R_OK | os.W_OK):
        raise OutputPathError(f"output {output}: existing file is not readable and writable")


class OutputLock:
    """``acquire()`` on rank 0 before touching the output; ``release()`` when the run ends."""

    def __init__(self, output: Path) -> None:
        self.output = Path(output)
        self.path = lock_path_for(self.output)
        self.owner = LockOwner(os.getpid(), socket.gethostname(), _start_ticks(os.getpid()))
        self.held = False
        self.replaced: LockOwner | None = None  # a stale lock this run replaced

    def acquire(self) -> None:
        """Take the lock or raise :class:`OutputInUse` / :class:`OutputPathError`."""
        if self.path.is_dir() or (self.path.exists() and not self.path.is_file()):
            raise OutputPathError(
                f"output {self.output}: the lock path {self.path} exists and is not a regular "
                "file; move it away"
            )
        private = self.path.with_name(f".{self.path.name}.{self.owner.pid}")
        try:
            private.write_text(self.owner.line())
        except OSError as error:
            private.unlink(missing_ok=True)
            if is_no_space(error):  # a full disk is not bad input: exit 5, like any other
                raise OutputFull(self.output, len(self.owner.line()), 0) from None
            raise OutputPathError(
                f"output {self.output}: cannot create files in {self.output.parent}: "
                f"{_describe(error)}"
            ) from None
        try:
            for _ in range(3):
                if self._link(private):
                    self.held = True
                    return
                other = self._read_owner()
                if other is None:
                    continue  # vanished meanwhile: try again
                alive = other.is_alive_here()
                if alive is False:
                    self._remove_stale(other)
                    continue
                where = "" if alive else f"; if that run is gone, delete {self.path}"
                raise OutputInUse(
                    f"output {self.output} is in use by another run (pid {other.pid}, host "
                    f"{other.host}){where}"
                )
            raise OutputInUse(f"output {self.output}: could not take the lock {self.path}")
        finally:
            private.unlink(missing_ok=True)

    def _link(self, private: Path) -> bool:
        try:
            os.link(private, self.path)
        except FileExistsError:
            return False
        except OSError as error:
            if error.errno in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP):
                return self._create_exclusive()  # file systems without hard links
            raise OutputPathError(
                f"output {self.output}: cannot create {self.path}: {_describe(error)}"
            ) from None
        return True

    def _create_exclusive(self) -> bool:
        try:
            descriptor = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            return False
        with os.fdopen(descriptor, "w") as handle:
            handle.write(self.owner.line())
        return True

    def _read_owner(self) -> LockOwner | None:
        try:
            text = self.path.read_text(errors="replace")
        except FileNotFoundError:
            return None
        except OSError as error:  # not readable by this user, not a file
            raise OutputPathError(
                f"output {self.output}: the lock {self.path} cannot be read: "
                f"{_describe(error)}; move it away"
            ) from None
        owner = LockOwner.parse(text)
        # unreadable content: never written by this engine's link method; treat as the
        # owner's, on this host, dead (a crash while writing through _create_exclusive)
        return owner or LockOwner(0, socket.gethostname(), "?")

    def _remove_stale(self, other: LockOwner) -> None:
        """Move a dead run's lock away (rename is atomic: only one run can win it)."""
        stale = self.path.with_name(f".{self.path.name}.stale.{self.owner.pid}")
        try:
            os.replace(self.path, stale)
        except FileNotFoundError:
            return
        if LockOwner.parse(stale.read_text(errors="replace")) not in (other, None):
            os.replace(stale, self.path)  # someone else took it meanwhile: put it back
            return
        stale.unlink(missing_ok=True)
        self.replaced = other

    def release(self) -> None:
        if not self.held:
            return
        if self._read_owner() == self.owner:
            self.path.unlink(missing_ok=True)
        self.held = False

    def __enter__(self) -> OutputLock:
        self.acquire()
        return self

    def __exit__(self, *exc_info) -> None:
        self.release()


def check_summary_path(output: Path, summary: Path) -> None:
    """Refuse to overwrite a CSV beside the output that is not a summary of this engine (an
    unrelated table that happens to have the summary's name)."""
    if not summary.exists():
        return
    try:
        with open(summary, encoding="utf-8", errors="replace") as handle:
            header = handle.readline()
    except OSError as error:
        raise OutputPathError(f"summary {summary}: cannot be read: {_describe(error)}") from None
    if header and not header.startswith("case_id,mu1,mu2,"):
        raise OutputPathError(
            f"summary {summary} (written beside {output}) exists and is not a summary of this "
            "engine; move it away or choose another [study] output"
        )
