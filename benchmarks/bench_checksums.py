"""Cost of the results checksums per case, side by side in one run (CPU time).

For every case of the given results files (repeated, the minimum kept):

store    the writer's structural write of the case (``ResultsWriter._store_case``) into a
         file in memory, without checksums;
+sums    what the checksums add to it: the SHA-256 of every dataset from memory
         (:func:`engine.output.checksum.manifest_entry`) and its ``sha256`` attribute;
scan     what a resume read per case before checksums: its status and summary attributes;
verify   what a resume reads now: the whole case read back and every checksum compared
         (:func:`engine.output.checksum.verify_case`).

Printed per file: data per case, the CPU times per case (ms), and the added write cost and
``verify`` as shares of the case's own computing time (``runtime_s``).

Run (after a study, e.g. ``python -m engine studies/demo.toml``)::

    python benchmarks/bench_checksums.py results/demo.h5 [more.h5 ...] [--repeat 5]
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import h5py

from engine.output.checksum import DATASET_CHECKSUM, manifest_entry, verify_case
from engine.output.hdf5 import ResultsWriter


def _cpu(function, repeat: int) -> float:
    """Minimum CPU time (s) of ``function()`` over ``repeat`` calls."""
    best = float("inf")
    for _ in range(repeat):
        start = time.process_time()
        function()
        best = min(best, time.process_time() - start)
    return best


def _datasets(group: h5py.Group) -> dict[str, object]:
    paths: list[str] = []
    group.visit(paths.append)
    return {path: group[path][()] for path in paths if isinstance(group[path], h5py.Dataset)}


def _store(data: dict[str, object], checksums: bool) -> None:
    """The writer's structural write of a case with these datasets, into a file in memory."""
    datasets = {}
    for path, array in data.items():
        attrs = {DATASET_CHECKSUM: manifest_entry(array)[2]} if checksums else {}
        datasets[path] = {"units": "1", "description": "", "data": array, "attrs": attrs}
    record = {
        "datasets": datasets,
        "attrs": {},
        "message": "",
        "traceback": "",
        "rank": 0,
        "runtime_s": 0.0,
        "row": {},
        "checksum": "0" * 64,
    }
    with h5py.File("in-memory.h5", "w", driver="core", backing_store=False) as file:
        ResultsWriter._store_case(file.create_group("case"), record)


def measure(path: Path, repeat: int) -> dict[str, float]:
    """Medians over the completed cases of ``path``."""
    write, plain, scan, verify, size, runtime = [], [], [], [], [], []
    with h5py.File(path, "r") as file:
        for name in file["cases"]:
            group = file["cases"][name]
            if group.attrs.get("status") != "completed":
                continue
            data = _datasets(group)
            size.append(sum(getattr(array, "nbytes", 0) for array in data.values()))
            write.append(_cpu(lambda d=data: _store(d, checksums=True), repeat))
            plain.append(_cpu(lambda d=data: _store(d, checksums=False), repeat))
            scan.append(_cpu(lambda g=group: json.loads(g.attrs["summary"]), repeat))
            verify.append(_cpu(lambda g=group: verify_case(g), repeat))
            runtime.append(float(group.attrs.get("runtime_s", float("nan"))))
    return {
        "cases": len(size),
        "megabytes": statistics.median(size) / 1e6,
        "store_ms": 1e3 * statistics.median(plain),
        "write_ms": 1e3 * (statistics.median(write) - statistics.median(plain)),
        "scan_ms": 1e3 * statistics.median(scan),
        "verify_ms": 1e3 * statistics.median(verify),
        "runtime_s": statistics.median(runtime),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, nargs="+")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(
        f"{'file':<28s} {'cases':>5s} {'MB/case':>8s} {'store ms':>9s} {'+sums ms':>9s} "
        f"{'scan ms':>8s} "
        f"{'verify ms':>10s} {'case s':>7s} {'write/case':>11s} {'verify/case':>12s}"
    )
    for path in args.results:
        m = measure(path, args.repeat)
        print(
            f"{path.name:<28s} {m['cases']:5d} {m['megabytes']:8.3f} {m['store_ms']:9.2f} "
            f"{m['write_ms']:9.2f} "
            f"{m['scan_ms']:8.3f} {m['verify_ms']:10.2f} {m['runtime_s']:7.2f} "
            f"{m['write_ms'] / 1e3 / m['runtime_s']:11.2%} "
            f"{m['verify_ms'] / 1e3 / m['runtime_s']:12.2%}"
        )


if __name__ == "__main__":
    main()
