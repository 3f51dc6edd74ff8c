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

import json
import os
import shutil
import struct
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import h5py

from engine.schema import CaseStatus
from engine.study.plan import Plan

from .hdf5 import ResultsMismatch, StudyMetadata, reattach_grid_scales, write_root
from .identity import ExistingResults, check_identity, damaged_path

__all__ = ["scan_damaged", "apply_existing", "readable_copy"]

_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def scan_damaged(path: Path, metadata: StudyMetadata, plan: Plan, problem: str) -> ExistingResults:
    """Find the completed cases of a damaged file that can be read in full."""
    planned = set(plan.case_ids)
    try:
        with readable_copy(path) as file:
            check_identity(path, dict(file.attrs), metadata)
            rescued = [name for name in _names(file) if _complete_and_readable(file, name)]
    except ResultsMismatch:
        raise
    except Exception:  # noqa: BLE001 - root or case list unreadable: nothing to rescue
        rescued = []
    if not rescued:
        return ExistingResults(path, "start-over", problem=problem)
    return ExistingResults(
        path,
        "salvage",
        completed=rescued,
        stale=[case_id for case_id in rescued if case_id not in planned],
        new_cases=len(planned - set(rescued)),
        problem=problem,
    )


def _names(file: h5py.File) -> list[str]:
    return list(file["cases"])


def _complete_and_readable(file: h5py.File, name: str) -> bool:
    """The case is completed, and its attributes and every dataset can be read."""
    try:
        group = file["cases"][name]
        attrs = dict(group.attrs)
        if attrs.get("status") != CaseStatus.COMPLETED:
            return False
        json.loads(attrs["summary"])

        def read(_, item):
            if isinstance(item, h5py.Dataset):
                item[()]
                dict(item.attrs)

        group.visititems(read)
    except Exception:  # noqa: BLE001 - any failure: not rescued
        return False
    return True


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
    existing: ExistingResults, plan: Plan, metadata: StudyMetadata, journal_dir: Path
) -> None:
    """Rank 0, under the output lock, before a writer opens the file: carry out a salvage or a
    start-over. Journals of uncommitted collective writes refer to the damaged file: removed."""
    if existing.kind not in ("salvage", "start-over"):
        return
    path = existing.path
    if existing.kind == "salvage":
        temporary = path.with_name(f".{path.name}.salvaged")
        with readable_copy(path) as source, h5py.File(temporary, "w") as target:
            write_root(target, metadata)
            cases = target.create_group("cases")
            for case_id in list(existing.completed):
                try:
                    source.copy(source["cases"][case_id], cases, name=case_id)
                    reattach_grid_scales(cases[case_id])
                except Exception:  # noqa: BLE001 - could be read but not copied: recompute
                    if case_id in cases:
                        del cases[case_id]
                    existing.completed.remove(case_id)
            target.flush()
        os.replace(path, damaged_path(path))
        os.replace(temporary, path)
    else:
        os.replace(path, damaged_path(path))
    if journal_dir.is_dir():
        for journal in journal_dir.glob("*.written.json"):
            journal.unlink(missing_ok=True)
