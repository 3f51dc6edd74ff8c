"""A stop flag that a signal handler may set at any moment.

A Python signal handler runs in the main thread between two bytecodes, also while that thread
is inside ``threading.Event.set()`` and holds the event's lock (a run sets its stop event
itself, when the disk fills, say). A handler that then called ``Event.set()`` would wait for
that lock forever: the rank hangs, and every other rank with it (seen when SIGTERM reached
the ranks twice, from the sender and forwarded by ``mpiexec``, while a full disk stopped the
run). Setting a :class:`StopFlag` takes no lock. This module imports nothing else of the
engine (``python -m engine`` creates its flag before anything else loads).
"""

from __future__ import annotations

import time

__all__ = ["StopFlag"]


class StopFlag:
    """What :class:`threading.Event` offers a run (``is_set``, ``set``, ``clear``, ``wait``),
    without a lock: safe to set from a signal handler at any moment.

    ``wait`` polls (every 10 ms at most): a flag is read far more often than waited on."""

    def __init__(self) -> None:
        self._set = False

    def is_set(self) -> bool:
        return self._set

    def set(self) -> None:
        self._set = True  # one store: nothing a signal handler can interrupt half-way

    def clear(self) -> None:
        self._set = False

    def wait(self, timeout: float | None = None) -> bool:
        deadline = None if timeout is None else time.monotonic() + timeout
        delay = 0.0005
        while not self._set:
            if deadline is not None and time.monotonic() >= deadline:
                break
            time.sleep(delay)
            delay = min(2 * delay, 0.01)
        return self._set
