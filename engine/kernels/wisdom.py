"""FFTW wisdom kept between runs, per user and machine, for the timed planner efforts.

FFTW's timed planners (``FFTW_MEASURE``, ``FFTW_PATIENT``, ``FFTW_EXHAUSTIVE``) time
candidate algorithms before choosing one: seconds for a large grid, paid again by every
process. The choices (FFTW's "wisdom") are stored in a file and imported before the next
timed plan, so a later run on the same machine plans at once, and chooses the same
algorithms (its results then repeat the earlier run's bits).

The default effort, ``FFTW_ESTIMATE``, never reads or writes wisdom: every estimate plan is
made with the wisdom forgotten (``engine.kernels.fft``), so its results are the same bits
with or without a wisdom file, on every rank, before and after an interruption.

Location: ``$ENGINE_FFTW_WISDOM`` when set (a file path; empty or ``off``: no file), else
``$XDG_CACHE_HOME/fretting-engine/`` (default ``~/.cache/fretting-engine/``), one file per
machine (host name, architecture and FFTW version in its name). ``clear()`` deletes the
file, as does removing it by hand; a damaged file is ignored and rewritten.
"""

from __future__ import annotations

import os
import pickle
import platform
import socket
import tempfile
from pathlib import Path

from .pyfftw_import import pyfftw

__all__ = ["wisdom_path", "load", "save", "clear"]

_loaded: set[Path] = set()


def wisdom_path() -> Path | None:
    """The wisdom file of this user and machine (None: wisdom is not kept)."""
    chosen = os.environ.get("ENGINE_FFTW_WISDOM")
    if chosen is not None:
        return None if chosen.strip() in ("", "off") else Path(chosen).expanduser()
    cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    machine = f"{socket.gethostname()}-{platform.machine()}-fftw{_fftw_version()}"
    return cache / "fretting-engine" / f"fftw-wisdom-{machine}.pickle"


def _fftw_version() -> str:
    return str(getattr(pyfftw, "__version__", "unknown")).replace(os.sep, "_")


def load() -> None:
    """Import this machine's wisdom into FFTW (once per process and file)."""
    path = wisdom_path()
    if path is None or path in _loaded:
        return
    _loaded.add(path)
    try:
        wisdom = pickle.loads(path.read_bytes())
        pyfftw.import_wisdom(wisdom)
    except (OSError, ValueError, TypeError, EOFError, pickle.UnpicklingError):
        return  # no file yet, or a damaged one: it is rewritten by the next save()


def save() -> None:
    """Write FFTW's current wisdom to this machine's file (atomically: a rank reading it at
    the same time sees the old or the new file, never a part)."""
    path = wisdom_path()
    if path is None:
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=".wisdom-")
        with os.fdopen(handle, "wb") as stream:
            pickle.dump(pyfftw.export_wisdom(), stream)
        os.replace(temporary, path)
    except OSError:
        return  # a read-only or full cache: plans are made, only not kept


def clear() -> Path | None:
    """Delete this machine's wisdom file (the next timed plan measures again); returns the
    path removed, or None if there was none."""
    path = wisdom_path()
    _loaded.clear()
    if path is None or not path.exists():
        return None
    path.unlink()
    return path
