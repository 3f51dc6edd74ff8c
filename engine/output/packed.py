"""A small case's datasets packed into an HDF5 file image by the rank that computed it.

With the single writer, rank 0 stores every case of every rank. Creating a small case's
datasets (~20 for a static case at n = 8, each with its ``units``, ``description`` and
checksum attributes) costs ~10 ms of HDF5 object creation, as long as computing the case:
thousands of tiny cases on several ranks then wait for rank 0's writing, and a second rank
barely speeds a study up. Packing moves that work to the rank that computed the case:

- :func:`pack` (computing rank): the datasets are created, with their attributes, in an
  in-memory HDF5 file (core driver, nothing on disk) by the same low-level calls a direct
  write makes (:mod:`engine.output.lowlevel`); the outcome travels to rank 0 with the file's
  image (bytes) instead of its arrays, and the manifest entries (dtype, shape, SHA-256) of
  its datasets, computed here too;
- :func:`unpack` (rank 0): the image's top-level groups are copied into the case's group
  with ``H5Ocopy``, one C call per group (~1 ms for the whole case). ``H5Ocopy`` does not
  rewrite object references, so the image holds no dimension scales: the writer attaches
  them to the copies, in the order a direct write does.

The copies are the objects a direct write makes: same datatypes, contiguous layout, creation
properties and attributes, so a file written with packing compares equal, dataset for dataset
and attribute for attribute, to one written without (``scripts/compare_results.py``).

Cases with more than :data:`PACK_LIMIT` bytes of data are sent as arrays: their writing is a
small share of their computing, and an image would double their memory on the computing rank.
"""

from __future__ import annotations

import itertools
import os
from dataclasses import dataclass, fields
from typing import Any

import h5py
import numpy as np
from h5py import h5d, h5f, h5o, h5p

from engine.study.case import CaseOutcome

from .checksum import DATASET_CHECKSUM, manifest_entry
from .lowlevel import create_dataset, set_attribute

__all__ = ["PACK_LIMIT", "PackedDataset", "PackedOutcome", "pack", "unpack"]

PACK_LIMIT = 4 << 20  # bytes of data: larger cases travel as arrays
_names = itertools.count()  # core-driver files need a name unique in the process


@dataclass
class PackedDataset:
    """Stands for a dataset that travels inside the outcome's image: what the writer needs
    besides the data (the manifest entry for the case checksum)."""

    units: str
    description: str
    manifest: tuple[str, tuple[int, ...], str]
    packed: bool = True


@dataclass
class PackedOutcome(CaseOutcome):
    """A :class:`engine.study.case.CaseOutcome` whose datasets are :class:`PackedDataset`
    entries, their data and attributes in ``image`` (an HDF5 file image)."""

    image: bytes = b""


def pack(outcome: CaseOutcome, limit: int = PACK_LIMIT) -> CaseOutcome:
    """``outcome`` with its datasets packed into an HDF5 file image; the outcome itself when
    it has no datasets or more than ``limit`` bytes of data."""
    arrays = {path: np.asarray(record.data) for path, record in outcome.datasets.items()}
    if not arrays or sum(array.nbytes for array in arrays.values()) > limit:
        return outcome
    packed: dict[str, PackedDataset] = {}
    with h5py.File(_core_name(), "w", driver="core", backing_store=False) as image:
        parents: dict[str, Any] = {}
        for path, record in outcome.datasets.items():
            entry = manifest_entry(arrays[path])
            dataset = create_dataset(image, path, arrays[path], parents, wrap=False)
            set_attribute(dataset, "units", record.units, new=True)
            set_attribute(dataset, "description", record.description, new=True)
            for name, value in (getattr(record, "attrs", None) or {}).items():
                set_attribute(dataset, name, value, new=True)
            set_attribute(dataset, DATASET_CHECKSUM, entry[2], new=True)
            packed[path] = PackedDataset(record.units, record.description, entry)
        image.flush()
        data = image.id.get_file_image()
    values = {item.name: getattr(outcome, item.name) for item in fields(CaseOutcome)}
    return PackedOutcome(**{**values, "datasets": packed}, image=data)


def unpack(
    group: h5py.Group, image: bytes, paths: list[str], opened=lambda path: True
) -> dict[str, h5d.DatasetID]:
    """Copy the groups and datasets of ``image`` into ``group`` (which holds none of them);
    returns path -> opened dataset for those of ``paths`` that ``opened(path)`` selects."""
    access = h5p.create(h5p.FILE_ACCESS)
    access.set_fapl_core(backing_store=False)
    access.set_file_image(image)
    source = h5f.open(_core_name().encode(), h5f.ACC_RDONLY, fapl=access)
    try:
        for name in dict.fromkeys(path.split("/", 1)[0] for path in paths):
            h5o.copy(source, name.encode(), group.id, name.encode())
    finally:
        source.close()
    return {path: h5d.open(group.id, path.encode()) for path in paths if opened(path)}


def _core_name() -> str:
    return f"packed-case-{os.getpid()}-{next(_names)}.h5"
