"""A full disk stops a run cleanly: completed cases kept, one line naming the path and the
space needed, exit code 5 (free space, rerun to resume).

Two guards:

- before each case is written, the free space of the output's file system is compared with
  what the case will take (its data, twice, plus a margin for HDF5 metadata: a case is never
  begun that cannot be finished, so the file stays consistent);
- an error of the operating system saying "no space left" (``ENOSPC``, or ``EDQUOT`` for a
  quota) while writing becomes :class:`OutputFull` instead of a traceback.

Before anything runs, :func:`check_space` compares the free space with the data the cases
still to run will write (the datasets known from the plan; a lower bound), so a rerun on a
still-full disk says so at once and changes nothing.

Space claimed before it is written (the model: SQLite and PostgreSQL never let the database
see a half-done write). Another process can fill the disk between the check and the write,
and an HDF5 library that meets "no space left" in the middle of a flush leaves its open file
in a state it cannot flush or close again. So the writer claims the blocks first:
:func:`claim` allocates them beyond the end of the results file without changing its size
(``fallocate`` with ``FALLOC_FL_KEEP_SIZE``, Linux: ext4, xfs, btrfs, tmpfs), and the case is
written only once they are held: HDF5's writes then land in blocks that are already the
file's. A claim that fails is the clean stop: nothing of the case has been written yet. Where
the file system cannot claim (NFS, Lustre, macOS), the free-space check is the only guard.
:class:`SpareFile` holds a few blocks beside the output for what must still be written after
the disk filled (the completion flags and the summary CSV).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import math
import os
import shutil
import sys
from pathlib import Path

import numpy as np

__all__ = [
    "OutputFull",
    "is_no_space",
    "free_bytes",
    "case_bytes",
    "ensure_space",
    "check_space",
    "planned_bytes",
    "format_bytes",
    "claim",
    "allocate",
    "SpareFile",
    "CLAIM_SLACK",
    "unclaim",
    "claimed",
]

DATASET_OVERHEAD = 2048  # bytes of HDF5 metadata per dataset (header, units, description, sha256)
MARGIN = 1 << 20  # bytes kept free besides a case's own, for the flags, the summary CSV, …
# Bytes a case writes beyond what the plan knows (histories, whose lengths are decided at run
# time, its attributes) and that opening the file to resume writes: measured 4 kB and 4 kB for
# a small static case; the check before a run adds this to the smallest case still to run.
UNPLANNED = 64 << 10


class OutputFull(OSError):
    """The output's file system has no room for what must be written next."""

    def __init__(
        self, path: Path, needed: int, free: int | None = None, *, at_most: bool = False
    ) -> None:
        """``needed``: bytes the cases still to run write (an estimate); ``at_most``: an
        upper bound (cases already in the file not counted off)."""
        self.path, self.needed, self.free = Path(path), int(needed), free
        have = f"{format_bytes(free)} free; " if free is not None else ""
        bound = "at most" if at_most else "about"
        super().__init__(
            errno.ENOSPC,
            f"{self.path}: no space left on its file system ({have}the cases still to run need "
            f"{bound} {format_bytes(self.needed)}, and {format_bytes(MARGIN)} is kept free); "
            "completed cases are kept: free space or choose another output, then rerun to "
            "resume",
        )

    def __str__(self) -> str:
        return self.strerror


def is_no_space(error: BaseException) -> bool:
    """Whether ``error`` says the file system (or the user's quota) is full; h5py reports the
    operating system's errno only inside its message."""
    if isinstance(error, OutputFull):
        return True
    if isinstance(error, OSError) and error.errno in (errno.ENOSPC, errno.EDQUOT):
        return True
    text = str(error)
    return "errno = 28" in text or "No space left" in text or "Disk quota exceeded" in text


def free_bytes(path: Path) -> int:
    """Bytes available to this user on the file system of ``path`` (or of its folder)."""
    target = Path(path)
    while not target.exists() and target != target.parent:
        target = target.parent
    return shutil.disk_usage(target).free


def case_bytes(arrays) -> int:
    """Bytes a case's datasets take in the file: their data plus HDF5 metadata."""
    arrays = list(arrays)
    return sum(int(getattr(array, "nbytes", 0)) for array in arrays) + DATASET_OVERHEAD * len(
        arrays
    )


def planned_bytes(layout: dict, case_ids) -> int:
    """Bytes the datasets known from the plan take for ``case_ids`` (``layout``: case id ->
    path -> shape and dtype, :func:`engine.study.layout.plan_layout`); a lower bound (the
    histories' lengths are decided at run time)."""
    total = 0
    for case_id in case_ids:
        shapes = layout.get(case_id, {})
        data = sum(math.prod(s.shape) * np.dtype(s.dtype).itemsize for s in shapes.values())
        total += data + DATASET_OVERHEAD * len(shapes)
    return total


def ensure_space(path: Path, needed: int, *, remaining_cases=1, held: int = 0) -> None:
    """Raise :class:`OutputFull` unless ``needed`` bytes (twice, plus a margin) fit on the
    file system of ``path``; the message names what the ``remaining_cases`` need (a count,
    or a callable returning it: counted only when the space is short). ``held``: bytes the
    writer holds already (claimed past the file's end, the spare file), counted as free."""
    free = free_bytes(path) + held
    if free < 2 * needed + MARGIN:
        remaining = remaining_cases() if callable(remaining_cases) else remaining_cases
        raise OutputFull(path, needed * max(remaining, 1), free)


def check_space(path: Path, needed: int, *, smallest_case: int = 0) -> None:
    """Before a run: raise :class:`OutputFull` when less than ``needed`` bytes plus the margin
    are free for ``path``, or when not even the smallest case still to run
    (``smallest_case`` bytes) would pass the writer's own test (:func:`ensure_space`, twice
    its data plus the margin, with :data:`UNPLANNED` for what the plan does not know) — then
    a run could only compute cases it cannot keep, and change the file for nothing."""
    free = free_bytes(path)
    if free < needed + MARGIN or free < 2 * smallest_case + MARGIN + UNPLANNED:
        raise OutputFull(path, needed, free)


# Bytes claimed beyond a case's estimate: HDF5's metadata of a case (object headers, B-tree
# nodes, attributes) and the flags; a static 8 x 8 case writes about 30 kB in all.
CLAIM_SLACK = 64 << 10
_KEEP_SIZE = 0x01  # FALLOC_FL_KEEP_SIZE (linux/falloc.h)
_PUNCH_HOLE = 0x02  # FALLOC_FL_PUNCH_HOLE
_UNSUPPORTED = (errno.EOPNOTSUPP, errno.ENOSYS, errno.EINVAL, errno.ENODEV)


def _libc_fallocate():
    """``fallocate(2)`` of the C library, or None where there is none (not Linux). glibc's
    ``libc.so.6`` is opened by name first: ``ctypes.util.find_library`` runs
    ``ldconfig -p`` in a child process (about 10 ms of every command's start)."""
    if not sys.platform.startswith("linux"):
        return None
    function = None
    for name in ("libc.so.6", None):
        try:
            name = name or ctypes.util.find_library("c")
            function = ctypes.CDLL(name, use_errno=True).fallocate if name else None
        except (OSError, AttributeError):
            continue
        if function is not None:
            break
    if function is None:
        return None
    function.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int64, ctypes.c_int64]
    function.restype = ctypes.c_int
    return function


_FALLOCATE = _libc_fallocate()


def claim(descriptor: int, length: int, path: Path) -> bool:
    """Allocate ``length`` bytes of blocks after the current end of the open file
    ``descriptor`` without changing its size (``FALLOC_FL_KEEP_SIZE``), so that writes of up
    to ``length`` bytes past the end cannot fail for want of space.

    Returns False where the file system or platform cannot do this (then nothing is
    claimed); raises :class:`OutputFull` (naming ``path``) when the space is not there."""
    if _FALLOCATE is None or length <= 0:
        return False
    end = os.fstat(descriptor).st_size
    if _FALLOCATE(descriptor, _KEEP_SIZE, end, length) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.ENOSPC, errno.EDQUOT):
        raise OutputFull(path, length, free_bytes(path))
    if code in _UNSUPPORTED:
        return False
    raise OSError(code, f"{path}: cannot claim space: {os.strerror(code)}")


def allocate(descriptor: int, size: int, path: Path) -> bool:
    """Allocate the blocks of the first ``size`` bytes of the open file ``descriptor`` (its
    holes: datasets created but not yet written), extending it to ``size`` if it is shorter,
    so that writes within them cannot fail for want of space.

    Returns False where the file system or platform cannot do this; raises
    :class:`OutputFull` (naming ``path``) when the space is not there."""
    if _FALLOCATE is None or size <= 0:
        return False
    if _FALLOCATE(descriptor, 0, 0, size) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.ENOSPC, errno.EDQUOT):
        held = os.fstat(descriptor).st_blocks * 512
        raise OutputFull(path, max(size - held, 0), free_bytes(path))
    if code in _UNSUPPORTED:
        return False
    raise OSError(code, f"{path}: cannot allocate space: {os.strerror(code)}")


def claimed(descriptor: int | None) -> int:
    """Bytes allocated to the open file past its end (a claim not used yet)."""
    if descriptor is None:
        return 0
    status = os.fstat(descriptor)
    return max(0, getattr(status, "st_blocks", 0) * 512 - status.st_size)


def unclaim(path: Path) -> None:
    """Give back the blocks claimed past the end of the closed file ``path``: a truncation
    to its own size (ext4, xfs) and a hole punched past the end (tmpfs), whichever the file
    system honours; nothing where claims are not made."""
    if _FALLOCATE is None:
        return
    try:
        descriptor = os.open(path, os.O_WRONLY)
    except OSError:
        return
    try:
        end = os.fstat(descriptor).st_size
        os.ftruncate(descriptor, end)
        _FALLOCATE(descriptor, _KEEP_SIZE | _PUNCH_HOLE, end, 1 << 40)
    except OSError:
        pass
    finally:
        os.close(descriptor)


class SpareFile:
    """A few blocks held beside the output (``.NAME.spare``) and given back when the disk is
    full, so that the completion flags and the summary CSV can still be written.

    ``hold(size)`` allocates them (silently holds nothing when they are not free: the
    writer's checks stop the run before it matters); ``release`` deletes the file."""

    def __init__(self, output: Path) -> None:
        self.path = spare_path(output)
        self.size = 0
        self.held = False

    def hold(self, size: int) -> None:
        self.size = int(size)
        try:
            descriptor = os.open(self.path, os.O_CREAT | os.O_WRONLY | os.O_TRUNC, 0o644)
        except OSError:
            return
        try:
            os.posix_fallocate(descriptor, 0, self.size)
            self.held = True
        except OSError:  # no room (or no fallocate): hold nothing
            os.ftruncate(descriptor, 0)
        finally:
            os.close(descriptor)
        if not self.held:
            self.path.unlink(missing_ok=True)

    def release(self) -> None:
        self.path.unlink(missing_ok=True)
        self.held = False


def spare_path(output: Path) -> Path:
    """The spare file of ``output`` (hidden, beside it)."""
    return output.with_name(f".{output.name}.spare")


def format_bytes(count: int | None) -> str:
    if count is None:
        return "?"
    for unit, size in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if count >= size:
            return f"{count / size:.1f} {unit}"
    return f"{count} B"
