"""Collective calls that wait without spinning.

MPICH busy-polls inside a blocking collective: a rank that reaches ``bcast`` while rank 0 is
still busy (reading back the results it wrote, say) burns a core until rank 0 arrives. With
more ranks than cores (an oversubscribed workstation) the waiting ranks then take the cores
from the one rank that has work. :func:`patient_bcast` first meets the other ranks in a
non-blocking barrier polled with short sleeps, then broadcasts (at once: every rank is there);
:func:`patient_gather` likewise.
"""

from __future__ import annotations

import time
from typing import Any

__all__ = ["patient_bcast", "patient_gather", "wait_for_all"]

LONGEST_SLEEP = 0.01  # s between two looks at the barrier, once the wait has lasted


def wait_for_all(comm) -> None:
    """Return when every rank of ``comm`` has called this (a barrier that sleeps)."""
    if comm.Get_size() == 1:
        return
    request = comm.Ibarrier()
    delay = 0.0002
    while not request.Test():
        time.sleep(delay)
        delay = min(2 * delay, LONGEST_SLEEP)


def patient_bcast(comm, value: Any, root: int = 0) -> Any:
    """``comm.bcast(value, root)``, the ranks that arrive early sleeping instead of spinning."""
    wait_for_all(comm)
    return comm.bcast(value, root=root)


def patient_gather(comm, value: Any, root: int = 0) -> list[Any] | None:
    """``comm.gather(value, root)``, the ranks that arrive early sleeping instead of spinning."""
    wait_for_all(comm)
    return comm.gather(value, root=root)
