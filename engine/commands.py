"""What the commands on results files share (``plot``, ``report``, ``verify``).

Each reads one or more results files named on its command line; :func:`results_parser`
starts its parser with that argument and :func:`refuse_file` gives the bad-input verdict
(exit 2) for a path that is not a file or not a results file: :func:`wrong_file` says what
the file is and what to pass instead ("studies/demo.toml is a study file; its results:
results/demo.h5"). :func:`engine.load_summary` and :func:`engine.load_thresholds` raise the
same sentence (:class:`WrongFileError`). The study command itself is :mod:`engine.cli`.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from collections.abc import Iterable
from pathlib import Path

__all__ = [
    "results_parser",
    "missing_file",
    "refuse_file",
    "wrong_file",
    "WrongFileError",
    "RESULTS_FORMAT",
]

# The root attribute ``format`` of a results file of this engine (engine.output.hdf5 writes it).
RESULTS_FORMAT = "fretting-engine-results/1"
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"  # at byte 0, 512, 1024, … (HDF5 format spec, superblock)
_RESULTS_SUFFIXES = (".h5", ".hdf5")
_PASS = "pass the results file (.h5) a study run wrote"


class WrongFileError(ValueError):
    """A file that is not what was asked for (a study file, a CSV, another program's HDF5
    file …); the message says what it is and what to pass instead."""


def results_parser(
    prog: str | None, description: str, results_help: str, *, several: bool = False
) -> argparse.ArgumentParser:
    """A parser whose first argument is the results file (``several``: one or more)."""
    parser = argparse.ArgumentParser(prog=prog, description=description)
    nargs = "+" if several else None
    parser.add_argument("results", type=Path, nargs=nargs, help=results_help)
    return parser


def missing_file(paths: Path | Iterable[Path]) -> bool:
    """Whether one of ``paths`` is not a file; says so on stderr (``error: PATH: no such
    file``) for the first such path."""
    for path in [paths] if isinstance(paths, Path) else paths:
        if not path.is_file():
            what = "a directory, not a results file" if path.is_dir() else "no such file"
            print(f"error: {path}: {what}", file=sys.stderr)
            return True
    return False


def refuse_file(paths: Path | Iterable[Path]) -> bool:
    """Whether one of ``paths`` is not a file or not a results file (:func:`wrong_file`);
    says so in one line on stderr for the first such path. A results file that cannot be
    read (damaged) is not refused here: the command reports the damage."""
    paths = [paths] if isinstance(paths, Path) else list(paths)
    if missing_file(paths):
        return True
    for path in paths:
        problem = wrong_file(path)
        if problem is not None:
            print(f"error: {problem}", file=sys.stderr)
            return True
    return False


def wrong_file(path: str | Path, *, accept_csv: bool = False) -> str | None:
    """None when ``path`` is, or may be, a results file of this engine (an HDF5 file with
    this engine's ``format``, or a file named ``*.h5`` / ``*.hdf5`` that HDF5 cannot read: a
    damaged results file); otherwise one line saying what the file is and what to pass:
    a study file (its ``[study] output``), a summary or thresholds CSV (the ``.h5`` beside
    it; ``accept_csv``: a CSV is fine), another program's HDF5 file, or another file.
    ``path`` must exist."""
    path = Path(path)
    head = _head(path)
    if _is_hdf5(path, head):
        return _other_hdf5(path)
    text = _text(head)
    if text is not None:
        study = _study_output(path)
        if study is not None:
            return f"{path} is a study file; its results: {study}"
        table = _csv_table(path, text)
        if table is not None:
            if accept_csv:
                return None
            return f"{path} is {table}; its results file: {_results_beside(path)}"
    if path.suffix.lower() in _RESULTS_SUFFIXES:
        return None  # a results file HDF5 cannot read: damaged, the command says so
    if text is None:
        kind = "not an HDF5 file"
    elif path.suffix.lower() == ".csv":
        kind = "a CSV file but no table of a study"
    elif path.suffix.lower() == ".toml":
        kind = "a TOML file but no study file (no [study] table)"
    else:
        kind = "a text file"
    return f"{path} is {kind}, not a results file: {_PASS}"


def _head(path: Path) -> bytes:
    with open(path, "rb") as handle:
        return handle.read(4096)


def _is_hdf5(path: Path, head: bytes) -> bool:
    """The HDF5 signature at byte 0 or a power of two ≥ 512 (a user block before it)."""
    if head.startswith(_HDF5_SIGNATURE):
        return True
    size = path.stat().st_size
    offset = 512
    with open(path, "rb") as handle:
        while offset + 8 <= size:
            handle.seek(offset)
            if handle.read(8) == _HDF5_SIGNATURE:
                return True
            offset *= 2
    return False


def _other_hdf5(path: Path) -> str | None:
    """None for a results file of this engine (or one HDF5 cannot open: damaged); a
    sentence for another program's HDF5 file."""
    import h5py

    try:
        with h5py.File(path, "r") as file:
            found = file.attrs.get("format")
            names = sorted(file)[:4]
            ours = "cases" in file and "study_name" in file.attrs  # written without a format
    except Exception:  # noqa: BLE001 - unreadable HDF5: a damaged results file
        return None
    if isinstance(found, bytes):
        found = found.decode("utf-8", "replace")
    if found == RESULTS_FORMAT or (found is None and ours):
        return None
    if found is not None:
        what = f"format {str(found)!r}, not {RESULTS_FORMAT!r}"
    else:
        listed = ", ".join(names) if names else "nothing"
        what = f"no 'format' attribute; top level: {listed}"
    return f"{path} is an HDF5 file of another program ({what}): {_PASS}"


def _text(head: bytes) -> str | None:
    """The start of the file as text, or None for binary data."""
    if b"\x00" in head:
        return None
    try:
        return head.decode("utf-8")
    except UnicodeDecodeError as error:  # the 4096 bytes may cut a character
        if error.start < len(head) - 4:
            return None
        return head[: error.start].decode("utf-8")


def _study_output(path: Path) -> str | None:
    """``[study] output`` of a study file (TOML with a ``[study]`` table), or None."""
    try:
        with open(path, "rb") as handle:
            document = tomllib.load(handle)
    except (tomllib.TOMLDecodeError, UnicodeDecodeError, OSError):
        return None
    study = document.get("study")
    if not isinstance(study, dict):
        return None
    output = study.get("output")
    if not isinstance(output, str):
        return f"the file its [study] output names (none given here): {_PASS}"
    exists = "" if Path(output).is_file() else " (not written yet: run the study first)"
    return f"{output}{exists}"


def _csv_table(path: Path, text: str) -> str | None:
    """ "the summary table (CSV)" or "the thresholds table (CSV)" of a study, else None."""
    first = text.splitlines()[0] if text else ""
    columns = [column.strip() for column in first.split(",")]
    if "case_id" not in columns:
        return None
    if path.stem.endswith("_thresholds"):
        return "the thresholds table (CSV) of a study"
    return "the summary table (CSV) of a study"


def _results_beside(path: Path) -> str:
    stem = path.stem.removesuffix("_thresholds") if path.stem.endswith("_thresholds") else path.stem
    results = path.with_name(f"{stem}.h5")
    return str(results) + ("" if results.is_file() else " (not beside it)")
