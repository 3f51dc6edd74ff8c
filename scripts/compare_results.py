"""Compare two results files (or two summary CSVs) bit for bit, run times aside.

Usage::

    python scripts/compare_results.py A.h5 B.h5 [--ignore NAME ...]
    python scripts/compare_results.py A.csv B.csv [--ignore NAME ...]

For HDF5 files every group and dataset of either file must exist in the other, with the same
kind (group or dataset); every dataset must have the same dtype, the same shape and the same
bytes (NaN payloads included: no tolerance); every attribute of the file, of each group and of
each dataset must be equal (same type, same value). Attributes that hold a JSON object (the
case ``summary``) are compared key by key, so a run time inside them is ignored too.

Ignored everywhere, and only these (names of attributes, JSON keys and CSV columns): the run
times, wall clocks, hosts and dates listed in ``RUN_DEPENDENT`` below, plus any ``--ignore``.

For CSV files (the study summary) the header must match and every row must match cell by
cell as text, the ``RUN_DEPENDENT`` columns aside.

Prints every difference, one a line, then a count; exits 0 when the files agree, 1 when they
differ, 2 when a file cannot be read.
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path

import h5py
import numpy as np

#: Names that depend on the run, not on the results: wall and CPU times of a case, the wall
#: time of a study, and the host/date fields a file may carry. Nothing else is ignored.
RUN_DEPENDENT = frozenset(
    {
        "runtime_s",  # wall time of a case, s (case attribute, summary JSON key, CSV column)
        "cpu_s",  # CPU time of a case, s (case attribute)
        "wall_time_s",  # wall time of a study, s
        "host",  # machine name
        "hostname",
        "date",  # calendar date/time of a run
        "created",
        "timestamp",
        "rank",  # which MPI rank computed a case (depends on the rank count and scheduling)
    }
)


def _attribute_value(value, handle=None):
    """An attribute value in a comparable form: text as str, arrays as (dtype, shape, bytes),
    object references (HDF5 dimension scales) as the path of the object they point to in
    ``handle``'s file (their bytes are file addresses, which differ between equal files)."""
    if isinstance(value, h5py.Reference):
        return ("reference", handle.file[value].name if value else None)
    if isinstance(value, bytes):
        return ("bytes", value)
    if isinstance(value, np.ndarray) and value.dtype.names:  # compound, e.g. REFERENCE_LIST
        rows = [tuple(_field_value(item, handle) for item in row) for row in value.flat]
        return ("compound", value.dtype.names, value.shape, rows)
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "O":
            items = [_attribute_value(item, handle) for item in value.flat]
            return ("object-array", value.shape, items)
        return ("array", value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, np.void) and value.dtype.names:
        return ("record", tuple(_attribute_value(item, handle) for item in value))
    if isinstance(value, np.generic):
        return ("scalar", value.dtype.str, value.tobytes())
    return (type(value).__name__, value)


def _field_value(item, handle):
    """A field of a compound attribute: integers by value (REFERENCE_LIST's dimension index
    is u4 or i4 by the HDF5 library's version; its value is the data), others as above."""
    if isinstance(item, np.integer):
        return ("integer", int(item))
    return _attribute_value(item, handle)


def _json_object(value):
    """The dict a JSON-object attribute holds, or None if the value is no JSON object."""
    if not isinstance(value, str) or not value.startswith("{"):
        return None
    try:
        parsed = json.loads(value)
    except ValueError:
        return None
    return parsed if isinstance(parsed, dict) else None


def _compare_json(where: str, first: dict, second: dict, ignored: frozenset) -> list[str]:
    differences = []
    for key in sorted(set(first) | set(second)):
        if key in ignored:
            continue
        if key not in second:
            differences.append(f"{where}: JSON key {key!r} only in A")
        elif key not in first:
            differences.append(f"{where}: JSON key {key!r} only in B")
        elif json.dumps(first[key], sort_keys=True) != json.dumps(second[key], sort_keys=True):
            differences.append(f"{where}: JSON key {key!r}: A={first[key]!r} B={second[key]!r}")
    return differences


def _compare_attributes(path: str, first, second, ignored: frozenset) -> list[str]:
    """Differences between the attributes of two HDF5 objects at ``path``."""
    differences = []
    for name in sorted(set(first.attrs) | set(second.attrs)):
        if name in ignored:
            continue
        where = f"{path} @{name}"
        if name not in second.attrs:
            differences.append(f"{where}: attribute only in A")
            continue
        if name not in first.attrs:
            differences.append(f"{where}: attribute only in B")
            continue
        value_a, value_b = first.attrs[name], second.attrs[name]
        json_a, json_b = _json_object(value_a), _json_object(value_b)
        if json_a is not None and json_b is not None:
            differences += _compare_json(where, json_a, json_b, ignored)
        elif _attribute_value(value_a, first) != _attribute_value(value_b, second):
            differences.append(f"{where}: A={_short(value_a)} B={_short(value_b)}")
    return differences


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 160 else text[:157] + "..."


def _dataset_bytes(dataset: h5py.Dataset):
    data = dataset[()]
    if isinstance(data, np.ndarray) and data.dtype.kind == "O":
        return [_attribute_value(item) for item in data.flat]
    return np.asarray(data).tobytes()


def _compare_dataset(path: str, first: h5py.Dataset, second: h5py.Dataset) -> list[str]:
    if first.dtype != second.dtype:
        return [f"{path}: dtype A={first.dtype} B={second.dtype}"]
    if first.shape != second.shape:
        return [f"{path}: shape A={first.shape} B={second.shape}"]
    if _dataset_bytes(first) != _dataset_bytes(second):
        count = ""
        if first.dtype.kind in "fiub" and first.shape is not None:
            values_a, values_b = np.asarray(first[()]), np.asarray(second[()])
            unequal = values_a.view(np.uint8).reshape(values_a.size, -1) != values_b.view(
                np.uint8
            ).reshape(values_b.size, -1)
            count = f" ({int(unequal.any(axis=1).sum())} of {values_a.size} elements differ)"
        return [f"{path}: data differ{count}"]
    return []


def _objects(handle: h5py.File) -> dict[str, object]:
    """Every group and dataset below the root, by path, with its kind."""
    found: dict[str, object] = {}

    def collect(name: str, item) -> None:  # returning None keeps visititems going
        found[name] = item

    handle.visititems(collect)
    return found


def compare_hdf5(path_a: Path, path_b: Path, ignored: frozenset) -> list[str]:
    """Every difference between two results files, one line each (empty when they agree)."""
    with h5py.File(path_a, "r") as first, h5py.File(path_b, "r") as second:
        differences = _compare_attributes("/", first, second, ignored)
        objects_a, objects_b = _objects(first), _objects(second)
        for name in sorted(set(objects_a) | set(objects_b)):
            path = "/" + name
            if name not in objects_b:
                differences.append(f"{path}: only in A")
                continue
            if name not in objects_a:
                differences.append(f"{path}: only in B")
                continue
            item_a, item_b = objects_a[name], objects_b[name]
            kind_a, kind_b = type(item_a).__name__, type(item_b).__name__
            if kind_a != kind_b:
                differences.append(f"{path}: kind A={kind_a} B={kind_b}")
                continue
            if isinstance(item_a, h5py.Dataset):
                differences += _compare_dataset(path, item_a, item_b)
            differences += _compare_attributes(path, item_a, item_b, ignored)
    return differences


def _read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with open(path, newline="", encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    return (rows[0] if rows else []), rows[1:]


def compare_csv(path_a: Path, path_b: Path, ignored: frozenset) -> list[str]:
    """Every difference between two summary CSVs, cell by cell as text."""
    header_a, rows_a = _read_csv(path_a)
    header_b, rows_b = _read_csv(path_b)
    if header_a != header_b:
        return [f"header: A={header_a} B={header_b}"]
    differences = []
    if len(rows_a) != len(rows_b):
        differences.append(f"rows: A has {len(rows_a)}, B has {len(rows_b)}")
    for number, (row_a, row_b) in enumerate(zip(rows_a, rows_b, strict=False), start=2):
        if len(row_a) != len(row_b):
            differences.append(f"line {number}: A has {len(row_a)} cells, B has {len(row_b)}")
        for column, cell_a, cell_b in zip(header_a, row_a, row_b, strict=False):
            if column not in ignored and cell_a != cell_b:
                differences.append(f"line {number} column {column}: A={cell_a!r} B={cell_b!r}")
    return differences


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("first", type=Path, help="results file A (.h5) or summary A (.csv)")
    parser.add_argument("second", type=Path, help="results file B (.h5) or summary B (.csv)")
    parser.add_argument(
        "--ignore",
        action="append",
        default=[],
        metavar="NAME",
        help="also ignore this attribute / JSON key / CSV column (repeatable)",
    )
    arguments = parser.parse_args(argv)
    ignored = RUN_DEPENDENT | frozenset(arguments.ignore)
    compare = compare_csv if arguments.first.suffix == ".csv" else compare_hdf5
    try:
        differences = compare(arguments.first, arguments.second, ignored)
    except (OSError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    for line in differences:
        print(line)
    print(
        f"{len(differences)} difference(s) between {arguments.first} and {arguments.second}"
        f" (ignored: {', '.join(sorted(ignored))})"
    )
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
