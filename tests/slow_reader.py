"""A child's work for the time-limit tests of :mod:`engine.output.isolated`, in a module of
its own: the child imports it in a fraction of a second (the test modules import the whole
engine, which takes seconds on a loaded machine)."""

from __future__ import annotations

import time

from engine.output.isolated import report_datasets


def read_datasets_slowly(seconds: float, then_hang: bool = False) -> int:
    """Stands for reading a file of many small datasets: one reported every 5 ms for
    ``seconds`` (``then_hang``: then stuck, reporting nothing more)."""
    count, end = 0, time.monotonic() + seconds
    while time.monotonic() < end:
        time.sleep(0.005)
        report_datasets(1)
        count += 1
    while then_hang:
        time.sleep(1)
    return count
