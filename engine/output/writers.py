"""The writer of a rank for an output strategy: ``single`` (:mod:`engine.output.hdf5`) or
``mpio`` (:mod:`engine.output.collective`). It sits above both writer modules, so neither
imports the other back."""

from __future__ import annotations

from pathlib import Path

from .collective import CollectiveWriter  # mpio only: imported when chosen
from .hdf5 import Bystander, ResultsWriter, SingleWriter

__all__ = ["open_writer"]


def open_writer(
    strategy: str,
    path: str | Path,
    *,
    comm=None,
    layout=None,
    summary_path: str | Path | None = None,
    journal_dir: str | Path | None = None,
    drop_stale: bool = False,
    should_stop=None,
) -> ResultsWriter:
    """The writer of this rank for ``strategy`` (``single`` or ``mpio``, see
    :func:`engine.output.collective.choose_strategy`).

    ``single``: a :class:`SingleWriter` on rank 0, a :class:`Bystander` elsewhere. ``mpio``: a
    :class:`engine.output.collective.CollectiveWriter` on every rank of ``comm``, with
    ``layout`` (datasets pre-created per case, :func:`engine.study.layout.plan_layout`) and
    its write journals in ``journal_dir``."""
    options = dict(summary_path=summary_path, drop_stale=drop_stale, should_stop=should_stop)
    if strategy == "mpio":
        return CollectiveWriter(path, comm, layout, journal_dir=journal_dir, **options)
    if strategy != "single":
        raise ValueError(f"output strategy must be 'single' or 'mpio', not {strategy!r}")
    if comm is not None and comm.Get_rank() != 0:
        return Bystander(path, **options)
    return SingleWriter(path, **options)
