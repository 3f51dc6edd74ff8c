"""Salvage of a damaged results file: read what can be read, copy its completed cases into a
new file, recompute the rest — or start over, saying so — never a dead end.

A results file is damaged when a kill (SIGKILL, OOM killer, node loss) struck while HDF5 was
writing metadata, when a full disk truncated it, or when its header was torn. Two kinds of
damage are repaired:

- *truncated*: HDF5 refuses to open a file shorter than the end-of-file address stored in
  its superblock. The scan opens a private copy whose stored end-of-file address is patched
  to the real size (superblock versions 0 and 1, the ones h5py writes by default); every
  object that lies wholly before the cut can then be read;
- *torn objects*: a case group or dataset whose header cannot be read is left behind; the
  other cases are copied.

Every rescued case is read in full (attributes and every dataset) before it counts, and is
copied with ``H5Ocopy`` into a new file that gets the study's root attributes; the damaged
file is kept beside the output as ``<output>.damaged`` (for inspection; delete it at will).
"""

from __future__ import annotations

import logging
import os
import shutil
import struct
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import h5py

from engine.schema import CASES_GROUP
from engine.study.plan import Plan

from .checksum import CaseCheck, check_root, verify_case
from .hdf5 import ResultsMismatch, StudyMetadata, reattach_grid_scales, write_root
from .identity import ExistingResults, check_identity, damaged_path, verdict
from .isolated import IsolatedCallStopped, IsolatedCallTimedOut, call_isolated, time_limit_for
from .space import MARGIN, OutputFull, ensure_space, free_bytes, is_no_space

#: Where the salvage reports (INFO): a salvage abandoned for a fresh start.
LOGGER = logging.getLogger(__name__)

__all__ = ["scan_damaged", "apply_existing", "readable_copy"]

_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def scan_damaged(path: Path, metadata: StudyMetadata, plan: Plan, problem: str) -> ExistingResults:
    """Find the completed cases of a damaged file that can be read in full and pass their
    checksums (:func:`engine.output.checksum.verify_case`)."""
    try:
        with readable_copy(path) as file:
            attrs = dict(file.attrs)
            check_root(attrs)  # a damaged root: whose study it holds is unknown, start over
            check_identity(path, attrs, metadata)
            names = list(file[CASES_GROUP])
            checks = [_checked(file, name) for name in names]
    except ResultsMismatch:
        raise
    except Exception:  # noqa: BLE001 - root or case list unreadable: nothing to rescue
        names, checks = [], []
    return verdict(path, plan, checks, in_file=names, problem=problem)


def _checked(file: h5py.File, name: str) -> CaseCheck:
    try:
        return verify_case(file[CASES_GROUP][name])
    except Exception as error:  # noqa: BLE001 - the group itself cannot be opened
        return CaseCheck(name, "", problem=f"unreadable ({str(error)[:200]})")


@contextmanager
def readable_copy(path: Path) -> Iterator[h5py.File]:
    """Open ``path`` read-only; if HDF5 refuses it as truncated, open a copy whose stored
    end-of-file address is the real file size."""
    try:
        file = h5py.File(path, "r")
    except OSError as error:
        if "truncated" not in str(error):
            raise
        copy = path.with_name(f".{path.name}.salvage")
        shutil.copyfile(path, copy)
        try:
            _patch_end_of_file(copy)
            with h5py.File(copy, "r") as file:
                yield file
        finally:
            copy.unlink(missing_ok=True)
        return
    with file:
        yield file


def _patch_end_of_file(path: Path) -> None:
    """Set the superblock's end-of-file address (versions 0 and 1) to the file size.

    Superblock v0/v1 layout (HDF5 file format specification, "Superblock"): signature (8
    bytes), five version/size bytes, reserved, sizes of offsets (byte 13) and lengths, group
    K values, consistency flags (bytes 20–23), [v1: indexed-storage K + reserved, 4 bytes],
    then base address, free-space address, end-of-file address, each ``size of offsets``
    bytes, little-endian.
    """
    size = path.stat().st_size
    with open(path, "r+b") as handle:
        head = handle.read(64)
        if head[:8] != _SIGNATURE or head[8] not in (0, 1):
            raise OSError("not a version 0/1 HDF5 superblock; cannot patch")
        offset_size = head[13]
        if offset_size not in (4, 8):
            raise OSError(f"unsupported size of offsets {offset_size}")
        start = (24 if head[8] == 0 else 28) + 2 * offset_size
        handle.seek(start)
        handle.write(struct.pack("<Q" if offset_size == 8 else "<I", size))


def apply_existing(
    existing: ExistingResults,
    plan: Plan,
    metadata: StudyMetadata,
    journal_dir: Path,
    *,
    should_stop=lambda: False,
) -> None:
    """Rank 0, under the output lock, before a writer opens the file: carry out a salvage or a
    start-over. The sound cases are copied in a child process (:mod:`engine.output.isolated`:
    a stop signal or the time limit ends it, the existing file untouched); then the damaged
    file is moved to ``existing.kept_as`` and the new one into place. Journals of uncommitted
    collective writes refer to the damaged file: removed."""
    if existing.kind not in ("salvage", "start-over"):
        return
    path = existing.path
    kept_as = existing.kept_as or damaged_path(path)
    if existing.kind == "salvage":
        temporary = path.with_name(f".{path.name}.salvaged")
        size = path.stat().st_size  # the copy, and a readable copy of a truncated file
        ensure_space(path, size)
        try:
            copied = call_isolated(
                copy_sound_cases,
                path,
                temporary,
                metadata,
                list(existing.completed),
                should_stop=should_stop,
                time_limit=time_limit_for(path),
            )
        except IsolatedCallTimedOut as error:  # HDF5 stuck while copying: start over
            temporary.unlink(missing_ok=True)
            copied = []
            existing.kind, existing.problem = "start-over", f"{existing.problem}; copying: {error}"
            LOGGER.info(f"note: salvage abandoned ({error}); the study starts over")
        except IsolatedCallStopped:
            temporary.unlink(missing_ok=True)
            raise
        except Exception as error:
            temporary.unlink(missing_ok=True)
            path.with_name(f".{path.name}.salvage").unlink(missing_ok=True)
            if is_no_space(error) or free_bytes(path) < MARGIN:  # HDF5 may hide the errno
                raise OutputFull(path, size, free_bytes(path)) from None
            raise
        existing.completed[:] = copied
    if existing.kind == "salvage":
        os.replace(path, kept_as)
        os.replace(temporary, path)
    else:
        os.replace(path, kept_as)
    if journal_dir.is_dir():
        for journal in journal_dir.glob("*.written.json"):
            journal.unlink(missing_ok=True)


def copy_sound_cases(
    path: Path, temporary: Path, metadata: StudyMetadata, case_ids: list[str]
) -> list[str]:
    """Build ``temporary``: the study's root and the cases ``case_ids`` of ``path`` (copied
    with ``H5Ocopy``, their grid scales attached anew). Returns the ids copied (a case that
    could be read but not copied is left out: it is recomputed)."""
    copied = []
    with readable_copy(path) as source, h5py.File(temporary, "w") as target:
        write_root(target, metadata)
        cases = target.create_group(CASES_GROUP)
        for case_id in case_ids:
            try:
                source.copy(source[CASES_GROUP][case_id], cases, name=case_id)
                reattach_grid_scales(cases[case_id], source[CASES_GROUP][case_id])
                copied.append(case_id)
            except Exception:  # noqa: BLE001 - could be read but not copied: recompute
                if case_id in cases:
                    del cases[case_id]
        target.flush()
    return copied
