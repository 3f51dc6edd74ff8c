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
from pathlib import Path

from .owner import LockOwner, lock_path_for, start_ticks
from .space import OutputFull, free_bytes, is_no_space

__all__ = [
    "OutputLock",
    "OutputInUse",
    "OutputPathError",
    "lock_path_for",
    "check_output_path",
    "check_output_name",
    "check_output_names",
    "check_text",
    "derived_names",
]


class OutputInUse(ValueError):
    """Another live run holds the output (exit code 2, nothing written)."""


class OutputPathError(ValueError):
    """The output cannot be written: names the path and the operating-system error."""


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


PID_DIGITS = 7  # a Linux pid has at most 7 digits (pid_max <= 4194304)
_LONGEST_PID = "9" * PID_DIGITS


def derived_names(output: Path) -> list[str]:
    """Every name the engine may create beside ``output`` (the longest forms: a pid of
    :data:`PID_DIGITS` digits, the 9999th damaged copy): the lock and its private and stale
    names, the file being built, the spare blocks, salvage copies, the checkpoints folder,
    the summary and thresholds CSVs and their temporaries."""
    name, pid = output.name, _LONGEST_PID
    summary = output.with_suffix(".csv").name
    thresholds = f"{output.stem}_thresholds.csv"
    return [
        name,
        f"{name}.lock",
        f".{name}.lock.{pid}",
        f".{name}.lock.stale.{pid}",
        f".{name}.creating",
        f".{name}.spare",
        f".{name}.salvage",
        f".{name}.salvaged",
        f"{name}.damaged.9999",
        f"{name}.checkpoints",
        summary,
        f".{summary}.tmp",
        thresholds,
        f".{thresholds}.tmp",
    ]


def _limit(directory: Path, name: str, default: int) -> int:
    """``pathconf`` limit ``name`` of the nearest existing ancestor of ``directory``."""
    while not directory.exists() and directory != directory.parent:
        directory = directory.parent
    try:
        return int(os.pathconf(directory, name))
    except (OSError, ValueError):
        return default


def check_text(what: str, text: str) -> None:
    """Refuse control characters (NUL, newline, escape …) in a name that becomes a file name
    or an HDF5 attribute: :class:`OutputPathError` naming the character and where."""
    for position, character in enumerate(text):
        if ord(character) < 32 or ord(character) == 127:
            raise OutputPathError(
                f"{what} {text[:60]!r}: contains the control character U+{ord(character):04X} "
                f"at position {position}; use printable characters"
            )


def _shortened(path: Path, most: int = 60) -> str:
    """``path`` for a message: its first and last characters when it is long."""
    text = str(path)
    return text if len(text) <= most else f"{text[: most // 2]}…{text[-most // 2 :]}"


def check_output_names(output: Path) -> None:
    """Before anything is created: no control characters in the output's path, and every
    name the engine derives from it (:func:`derived_names`) within the file system's limits
    (``NAME_MAX`` per name, ``PATH_MAX`` for the whole path). Raises
    :class:`OutputPathError` naming the longest name and the limit."""
    check_text("output", str(output))
    directory = output.parent
    name_max = _limit(directory, "PC_NAME_MAX", 255)
    longest = max(derived_names(output), key=lambda name: len(os.fsencode(name)))
    size = len(os.fsencode(longest))
    if size > name_max:
        room = name_max - (size - len(os.fsencode(output.name)))
        raise OutputPathError(
            f"output {_shortened(output)}: its name is {len(os.fsencode(output.name))} bytes; the "
            f"engine writes {longest[:40]}… beside it, {size} bytes, and the file system "
            f"allows {name_max}: use an output name of at most {room} bytes"
        )
    path_max = _limit(directory, "PC_PATH_MAX", 4096)
    whole = len(os.fsencode(str(output.absolute().with_name(longest))))
    if whole >= path_max:
        raise OutputPathError(
            f"output {_shortened(output)}: the paths the engine writes beside it reach "
            f"{whole} bytes; the file system allows {path_max - 1}: use a shorter folder or name"
        )


def check_output_path(output: Path) -> None:
    """Make the output's directory and check that files can be created in it.

    Raises :class:`OutputPathError` naming the path and the OS error (a parent that is a
    regular file, a read-only or immutable directory, a path under /proc, …), or a name too
    long or with control characters (:func:`check_output_names`).
    """
    check_output_names(output)
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
            raise OutputFull(output, 4096, free_bytes(output)) from None
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
        self.owner = LockOwner(os.getpid(), socket.gethostname(), start_ticks(os.getpid()))
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
                free = free_bytes(self.output)
                raise OutputFull(self.output, len(self.owner.line()), free) from None
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


def sibling_outputs(output: Path) -> list[Path]:
    """The other results files that would share ``output``'s summary CSV (``x.h5`` and
    ``x.hdf5`` both write ``x.csv``)."""
    return [
        output.with_suffix(suffix)
        for suffix in RESULTS_SUFFIXES
        if suffix != output.suffix and output.suffix in RESULTS_SUFFIXES
    ]


def check_summary_path(output: Path, summary: Path) -> None:
    """Refuse to overwrite a CSV beside the output that is not a summary of this engine (an
    unrelated table that happens to have the summary's name), or the summary of another
    results file beside it (``x.hdf5`` when writing ``x.h5``: the file, or the lock of a run
    building it; called once this run's lock is held, so two runs that start at once both
    see the other's lock)."""
    for other in sibling_outputs(output):
        if other.exists() or lock_path_for(other).exists():
            raise OutputPathError(
                f"output {output}: {other} is beside it and both would write the summary "
                f"{summary}; choose another name for one of them"
            )
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
