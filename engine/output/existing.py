"""The read-only look at an existing results file before a run: whose study it holds, which
cases are complete and sound (:mod:`engine.output.identity`), and, for a damaged file, what can
be rescued (:mod:`engine.output.salvage`). It sits above both, so neither imports the other
back."""

from __future__ import annotations

from pathlib import Path

import h5py

from engine.study.plan import Plan

from .checksum import check_root
from .hdf5 import ResultsMismatch, StudyMetadata
from .identity import ExistingResults, check_cases, check_identity, damaged_path, verdict
from .isolated import IsolatedCallTimedOut, call_isolated, time_limit_for
from .salvage import scan_damaged

__all__ = ["inspect_existing", "inspect_existing_isolated"]


def inspect_existing(path: Path, metadata: StudyMetadata, plan: Plan) -> ExistingResults | None:
    """Read-only look at an existing results file; None when there is none.

    Reads the root and every case's status and verifies every completed case
    (:func:`engine.output.checksum.verify_case`); a damaged file goes to
    :func:`engine.output.salvage.scan_damaged`. Raises :class:`ResultsMismatch` for a file of
    another study or another program.
    """
    if not path.exists():
        return None
    try:
        with h5py.File(path, "r") as file:
            attrs = dict(file.attrs)
            check_root(attrs)
            check_identity(path, attrs, metadata)
            checks = check_cases(file)
    except ResultsMismatch:
        raise
    except Exception as error:  # noqa: BLE001 - any failure to read is damage
        return scan_damaged(path, metadata, plan, _short(error))
    return verdict(path, plan, checks, in_file=[check.case_id for check in checks])


def inspect_existing_isolated(
    path: Path, metadata: StudyMetadata, plan: Plan, *, should_stop=lambda: False
) -> ExistingResults | None:
    """:func:`inspect_existing` in a child process (:mod:`engine.output.isolated`).

    A stop signal raises :class:`engine.output.isolated.IsolatedCallStopped` (nothing was
    changed); a read that does not finish within its time limit makes the file one that
    nothing can be read from (``start-over``: kept aside, the study starts over)."""
    if not path.exists():
        return None
    try:
        return call_isolated(
            inspect_existing,
            path,
            metadata,
            plan,
            should_stop=should_stop,
            time_limit=time_limit_for(path),
        )
    except IsolatedCallTimedOut as error:
        return ExistingResults(path, "start-over", problem=str(error), kept_as=damaged_path(path))


def _short(error: BaseException) -> str:
    """The first line of an error's message (at most 200 characters)."""
    text = str(error).splitlines()[0] if str(error) else type(error).__name__
    return text[:200]
