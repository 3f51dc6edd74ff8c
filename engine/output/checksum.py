"""Checksums of the results: a SHA-256 per dataset, and one per case over its datasets.

Every dataset of a completed case carries the attribute ``sha256``: the SHA-256 (hex) of its
dtype, shape and bytes (C order, as stored). The case group carries ``checksum``: the SHA-256
of its *manifest*, one line ``path dtype shape sha256`` per dataset in sorted order, so a
dataset that vanished, was renamed or reshaped is noticed as well as a changed byte.

The root carries ``metadata_checksum`` over the attributes that say which study it holds
(format, name, identity, fingerprint), so a damaged root is not taken for another study.

All are functions of the data alone (no time, rank or host goes in), so equal results give
equal files whichever writer strategy and rank count wrote them. They are computed where the
data is in memory — by the writing rank, before the write — and checked by reading the stored
data back (:func:`verify_case`): before a resumed run trusts a completed case, and by
``python -m engine verify``.

Why SHA-256 attributes rather than HDF5's Fletcher-32 filter: the filter needs chunked
datasets, which the collective (mpio) writer cannot fill independently (parallel HDF5 writes
filtered datasets collectively only), and it would change the layout of every file.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass

import h5py
import numpy as np
from h5py import h5a, h5d, h5o, h5s, h5t

from engine.schema import CaseStatus

from .isolated import report_datasets

__all__ = [
    "ROOT_CHECKSUM",
    "DamagedRoot",
    "root_checksum",
    "check_root",
    "DATASET_CHECKSUM",
    "CASE_CHECKSUM",
    "data_checksum",
    "case_checksum",
    "CaseCheck",
    "verify_case",
]

DATASET_CHECKSUM = "sha256"  # attribute of every dataset of a completed case
CASE_CHECKSUM = "checksum"  # attribute of a completed case group (over its manifest)
ROOT_CHECKSUM = "metadata_checksum"  # root attribute, over the other root attributes


class DamagedRoot(ValueError):
    """The root attributes (the study the file holds) fail their checksum."""


# the root attributes that say which study a file holds (compared by the identity check);
# the command line, output path and version may differ between equal files
IDENTITY_ATTRIBUTES = ("format", "study_name", "study_identity", "study_fingerprint")


def root_checksum(attrs: dict) -> str:
    """SHA-256 (hex) of the root attributes that say which study the file holds (present
    ones of ``IDENTITY_ATTRIBUTES``): a damaged root is told apart from another study."""
    values = {name: _text(attrs[name]) for name in IDENTITY_ATTRIBUTES if name in attrs}
    return hashlib.sha256(json.dumps(values, sort_keys=True).encode()).hexdigest()


def check_root(attrs: dict) -> None:
    """Raise :class:`DamagedRoot` when the stored root checksum differs (files written before
    it existed carry none and pass)."""
    stored = attrs.get(ROOT_CHECKSUM)
    if stored is not None and _text(stored) != root_checksum(attrs):
        raise DamagedRoot("root attributes damaged (metadata checksum mismatch)")


def data_checksum(data) -> str:
    """SHA-256 (hex) of an array's dtype, shape and bytes in C order.

    Text arrays (variable-length strings) are hashed as their UTF-8 items, each followed by a
    NUL byte, so the checksum of the data written and of the data read back agree."""
    array = np.asarray(data)
    digest = hashlib.sha256(f"{_dtype_name(array)} {array.shape}\n".encode())
    if array.dtype.kind in "OSU":
        for item in array.flat:
            text = item.encode() if isinstance(item, str) else bytes(item)
            digest.update(text + b"\0")
    else:
        bytes_ = np.ascontiguousarray(array).reshape(-1).view(np.uint8)
        digest.update(bytes_)  # the array's own buffer: no copy of its bytes
    return digest.hexdigest()


def _dtype_name(array: np.ndarray) -> str:
    """The dtype as stored: numbers by their NumPy code, all text as ``text``."""
    return "text" if array.dtype.kind in "OSU" else array.dtype.str


def case_checksum(manifest: dict[str, tuple[str, tuple[int, ...], str]]) -> str:
    """SHA-256 (hex) of a case's manifest: path -> (dtype name, shape, dataset checksum)."""
    lines = [
        f"{path} {dtype} {tuple(shape)} {checksum}\n"
        for path, (dtype, shape, checksum) in sorted(manifest.items())
    ]
    return hashlib.sha256("".join(lines).encode()).hexdigest()


def manifest_entry(data) -> tuple[str, tuple[int, ...], str]:
    """(dtype name, shape, checksum) of an array for :func:`case_checksum`."""
    array = np.asarray(data)
    return _dtype_name(array), tuple(array.shape), data_checksum(array)


@dataclass
class CaseCheck:
    """What :func:`verify_case` found for one case group.

    ``problem`` is empty for a sound case; ``verified`` is False for a completed case written
    before checksums existed (read in full, but nothing to compare with)."""

    case_id: str
    status: str
    problem: str = ""
    verified: bool = True
    datasets: int = 0  # datasets read
    bytes_read: int = 0

    @property
    def sound(self) -> bool:
        return not self.problem


def verify_case(group: h5py.Group, *, each_dataset: bool = True) -> CaseCheck:
    """Read a completed case back in full and compare its checksums.

    Every dataset is read and hashed (:func:`data_checksum`) and compared with its
    ``sha256`` attribute; the manifest of what was read is compared with the group's
    ``checksum``. Any failure to read (a torn object header, a broken B-tree) is a problem
    too. A case without ``checksum`` (an older file) is read in full and reported as not
    verified. Groups that are not completed are not read (``problem`` empty).

    ``each_dataset=False`` (the read-back right after a run wrote the case): the data read
    is compared with the case checksum alone, which covers the bytes of every dataset; the
    datasets' own ``sha256`` attributes are read only when it differs, to name the bad
    ones."""
    case_id = group.name.rsplit("/", 1)[-1]
    try:
        status = str(group.attrs.get("status", ""))
    except Exception as error:  # noqa: BLE001 - an unreadable attribute is damage
        return CaseCheck(case_id, "", problem=f"attributes unreadable ({_short(error)})")
    check = CaseCheck(case_id, status)
    if status != CaseStatus.COMPLETED:
        return check
    try:
        _read_and_compare(group, check, each_dataset)
    except Exception as error:  # noqa: BLE001 - any failure to read is damage
        check.problem = f"unreadable ({_short(error)})"
    report_datasets(max(check.datasets, 1))  # a time limit that grows with the work done
    return check


def _read_and_compare(group: h5py.Group, check: CaseCheck, each_dataset: bool) -> None:
    json.loads(group.attrs["summary"])
    manifest: dict[str, tuple[str, tuple[int, ...], str]] = {}
    stored: dict[str, str | None] = {}
    for path, dataset in _datasets(group):
        data = _read(dataset)
        manifest[path] = manifest_entry(data)
        check.datasets += 1
        check.bytes_read += int(np.asarray(data).nbytes)
        if each_dataset:
            stored[path] = _text_attribute(dataset, DATASET_CHECKSUM)
    stored_case = _text_attribute(group.id, CASE_CHECKSUM)
    if not each_dataset:
        if stored_case is not None and stored_case == case_checksum(manifest):
            return  # the bytes of every dataset are the ones hashed before the write
        stored = {
            path: _text_attribute(h5o.open(group.id, path.encode()), DATASET_CHECKSUM)
            for path in manifest
        }
    mismatched = [path for path, entry in manifest.items() if stored[path] not in (None, entry[2])]
    missing = [path for path in manifest if stored[path] is None]
    if stored_case is None:
        check.verified = False
        return
    if mismatched:
        check.problem = "checksum mismatch in " + _listed(mismatched)
    elif missing:
        check.problem = "no checksum on " + _listed(missing)
    elif stored_case != case_checksum(manifest):
        check.problem = "datasets missing, added or reshaped (case checksum mismatch)"


# Reading through h5py's low-level API: a case of a small study is ~80 datasets, and the
# high-level objects (wrappers, attribute managers) cost about half the time of reading it.
def _datasets(group: h5py.Group) -> list[tuple[str, h5d.DatasetID]]:
    """(path, opened dataset) of every dataset below ``group``, in HDF5's visiting order."""
    paths: list[bytes] = []

    def collect(name: bytes, info) -> None:
        if info.type == h5o.TYPE_DATASET:
            paths.append(name)

    h5o.visit(group.id, collect, info=True)
    return [(path.decode(), h5o.open(group.id, path)) for path in paths]


def _read(dataset: h5d.DatasetID) -> np.ndarray:
    """The whole dataset as an array (text datasets through h5py's high-level reader)."""
    if dataset.dtype.kind not in "biuf":
        return np.asarray(h5py.Dataset(dataset)[()])
    array = np.empty(dataset.shape, dtype=dataset.dtype)
    if array.size:
        dataset.read(h5s.ALL, h5s.ALL, array)
    return array


def _text_attribute(object_id, name: str) -> str | None:
    """The text attribute ``name`` of an object (its low-level identifier), or None."""
    key = name.encode()
    if not h5a.exists(object_id, key):
        return None
    attribute = h5a.open(object_id, key)
    value = np.empty((), dtype=attribute.dtype)
    attribute.read(value, mtype=h5t.py_create(attribute.dtype))
    return _text(value[()])


def _text(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def _listed(paths: list[str]) -> str:
    return ", ".join(paths[:3]) + (f" and {len(paths) - 3} more" if len(paths) > 3 else "")


def _short(error: BaseException) -> str:
    text = str(error).splitlines()[0] if str(error) else type(error).__name__
    return text[:200]
