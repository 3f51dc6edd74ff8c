"""The console on a full disk: ``python -m engine … > log 2>&1`` where ``log`` lies on a file
system that fills.

A message that cannot be written to a full disk is lost, but the run goes on and its exit code
stays the run's: the results are on their own file system, and an exit code turned into 1 (an
unhandled ``OSError`` from ``print``) or 120 (Python failing to flush ``stdout`` at exit) would
tell a job script that a completed study failed. :func:`tolerate_full_console` wraps
``sys.stdout`` and ``sys.stderr`` so that writing or flushing them ignores ``ENOSPC`` and
``EDQUOT``; every other error (a closed pipe, say) is raised as before. This module imports
nothing else of the engine.
"""

from __future__ import annotations

import errno
import sys
from typing import Any

__all__ = ["tolerate_full_console", "FullDiskTolerantStream"]

_FULL = (errno.ENOSPC, errno.EDQUOT)


class FullDiskTolerantStream:
    """A text stream whose ``write`` and ``flush`` ignore a full disk (``lost`` says
    whether something was lost); everything else is the wrapped stream's."""

    def __init__(self, stream: Any) -> None:
        self._stream = stream
        self.lost = False

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except OSError as error:
            if error.errno not in _FULL:
                raise
            self.lost = True
            return len(text)

    def flush(self) -> None:
        try:
            self._stream.flush()
        except OSError as error:
            if error.errno not in _FULL:
                raise
            self.lost = True

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def tolerate_full_console() -> None:
    """Wrap ``sys.stdout`` and ``sys.stderr`` (once) in :class:`FullDiskTolerantStream`."""
    for name in ("stdout", "stderr"):
        stream = getattr(sys, name)
        if stream is not None and not isinstance(stream, FullDiskTolerantStream):
            setattr(sys, name, FullDiskTolerantStream(stream))
