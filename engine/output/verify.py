"""``python -m engine verify RESULTS.h5``: is a results file whole? (serial, no MPI)

Reads every case group and every dataset of a results file, compares each completed case's
checksums (:mod:`engine.output.checksum`), and compares the summary CSV beside it with the
summary rows stored in the file. Prints one line per bad case (case id, status, what is
wrong), then a verdict. Use it on results copied from a cluster before trusting them.

Exit codes: :data:`engine.exit_codes.VERIFY` (0 whole, 4 damaged, 2 bad input, 3
interrupted; the help and the manual's table are generated from it).

The reading runs in a child process with a time limit (:mod:`engine.output.isolated`): a file
whose damage sends HDF5 into an endless loop is reported as damaged, not waited for forever.
"""

from __future__ import annotations

import argparse
import codecs
import csv
import io
import json
import signal
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import h5py

from engine._stop_flag import StopFlag
from engine.commands import refuse_file, results_parser
from engine.exit_codes import VERIFY, ExitCode, epilog_text
from engine.schema import CASES_GROUP, CaseStatus

from .checksum import CaseCheck, check_root, verify_case
from .hdf5 import FORMAT
from .isolated import IsolatedCallStopped, IsolatedCallTimedOut, call_isolated, time_limit_for
from .owner import being_written_file
from .summary import summary_csv

__all__ = [
    "FileCheck",
    "verify_file",
    "check_after_run",
    "compare_summary",
    "main",
    "EXIT_CLEAN",
    "EXIT_DAMAGED",
]

EXIT_CLEAN, EXIT_BAD_INPUT = ExitCode.OK, ExitCode.BAD_INPUT
EXIT_INTERRUPTED, EXIT_DAMAGED = ExitCode.INTERRUPTED, ExitCode.DAMAGED


class NotResultsFile(ValueError):
    """A readable HDF5 file that is not a results file of this engine."""


@dataclass
class FileCheck:
    """What :func:`verify_file` found: every case's check, and damage of the file itself."""

    path: Path
    cases: list[CaseCheck] = field(default_factory=list)
    problem: str = ""  # the file or its case list cannot be read
    summary_problems: list[tuple[str, str]] = field(default_factory=list)  # (case id, what)
    summary_note: str = ""  # e.g. no CSV beside the file

    @property
    def bad_cases(self) -> list[CaseCheck]:
        return [check for check in self.cases if not check.sound]

    @property
    def damaged(self) -> bool:
        return bool(self.problem or self.bad_cases or self.summary_problems)


def verify_file(path: Path, summary: Path | None) -> FileCheck:
    """Read every case of ``path`` (completed ones in full, checksums compared) and compare
    ``summary`` (a CSV; None: not checked) with the summary rows stored in the file.

    Raises :class:`NotResultsFile` for an HDF5 file without this engine's ``format``."""
    check = FileCheck(path)
    rows: dict[str, tuple[int, dict]] = {}
    if not h5py.is_hdf5(path) and _is_text(path):  # a study file, a CSV: not damage
        raise NotResultsFile(f"{path}: a text file, not a results file (HDF5) of this engine")
    try:
        with h5py.File(path, "r") as file:
            if file.attrs.get("format") != FORMAT:
                raise NotResultsFile(f"{path}: not a results file of this engine")
            check_root(dict(file.attrs))
            cases = file[CASES_GROUP]
            for name in cases:
                check.cases.append(_checked(cases, name))
                row = _stored_row(cases, name)
                if row is not None:
                    rows[name] = row
    except NotResultsFile:
        raise
    except Exception as error:  # noqa: BLE001 - any failure to read is damage
        check.problem = _short(error)
    if summary is None:
        return check
    if not summary.exists():
        check.summary_note = f"no summary CSV at {summary} (not checked)"
    elif not check.problem:
        check.summary_problems = compare_summary(summary, rows)
    return check


def _is_text(path: Path, length: int = 4096) -> bool:
    """Whether the first ``length`` bytes of ``path`` are UTF-8 text (a results file damaged
    in its first block holds binary bytes after it, or zeros)."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(length)
        codecs.getincrementaldecoder("utf-8")().decode(head, final=False)  # may end mid-character
    except (OSError, UnicodeDecodeError):
        return False
    return bool(head) and b"\0" not in head  # an empty file is a truncated results file


def _checked(cases: h5py.Group, name: str, *, each_dataset: bool = True) -> CaseCheck:
    try:
        return verify_case(cases[name], each_dataset=each_dataset)
    except Exception as error:  # noqa: BLE001 - the group itself cannot be opened
        return CaseCheck(name, "", problem=f"unreadable ({_short(error)})")


def _stored_row(cases: h5py.Group, name: str) -> tuple[int, dict] | None:
    """(index, summary row with the case's current status) as the writer lists it in the CSV."""
    try:
        attrs = cases[name].attrs
        row = json.loads(attrs["summary"])
        row["status"] = str(attrs.get("status", row.get("status", CaseStatus.PENDING)))
        return int(attrs.get("index", 0)), row
    except Exception:  # noqa: BLE001 - reported by the case's own check
        return None


def check_after_run(path: Path, written: set[str], *, others: bool = True) -> list[CaseCheck]:
    """The bad cases of a results file a run has just closed: every case group and status
    readable, and the cases ``written`` by the run read back in full and compared with their
    case checksums (the others were verified when the run began). In-process: the file is
    this run's own. ``others=False``: the cases ``written`` only (a rank checking its share
    of them)."""
    bad = []
    try:
        with h5py.File(path, "r") as file:
            check_root(dict(file.attrs))
            cases = file[CASES_GROUP]
            for name in cases:
                if name in written:  # the case checksum proves the bytes of every dataset
                    check = _checked(cases, name, each_dataset=False)
                elif others:
                    check = _status_only(cases, name)
                else:
                    continue
                if not check.sound:
                    bad.append(check)
    except Exception as error:  # noqa: BLE001 - any failure to read is damage
        bad.append(CaseCheck("(file)", "", problem=_short(error)))
    return bad


def _status_only(cases: h5py.Group, name: str) -> CaseCheck:
    try:
        return CaseCheck(name, str(cases[name].attrs.get("status", "")))
    except Exception as error:  # noqa: BLE001 - the group itself cannot be opened
        return CaseCheck(name, "", problem=f"unreadable ({_short(error)})")


def compare_summary(summary: Path, stored: dict[str, tuple[int, dict]]) -> list[tuple[str, str]]:
    """(case id, what differs) between the CSV ``summary`` and the rows stored in the file
    (``stored``: case id -> (index, row)), the CSV written from them as the writer writes it
    (:func:`engine.output.summary.summary_csv`), compared cell by cell."""
    ordered = [row for _, row in sorted(stored.values(), key=lambda item: item[0])]
    expected = _parse_csv(summary_csv(ordered)) if ordered else {}
    try:
        found = _parse_csv(summary.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, csv.Error, KeyError) as error:
        return [("(summary)", f"{summary} cannot be read as a summary CSV ({_short(error)})")]
    problems = []
    for case_id in sorted(set(expected) - set(found)):
        problems.append((case_id, f"missing from {summary.name}"))
    for case_id in sorted(set(found) - set(expected)):
        problems.append((case_id, f"in {summary.name} but not in the results file"))
    for case_id in sorted(set(expected) & set(found)):
        columns = sorted(
            column
            for column in set(expected[case_id]) | set(found[case_id])
            if expected[case_id].get(column, "") != found[case_id].get(column, "")
        )
        if columns:
            shown = ", ".join(columns[:4]) + (" …" if len(columns) > 4 else "")
            problems.append((case_id, f"{summary.name} differs from the file in {shown}"))
    return problems


def _parse_csv(text: str) -> dict[str, dict[str, str]]:
    """case id -> {column: cell} of a summary CSV text."""
    return {row["case_id"]: row for row in csv.DictReader(io.StringIO(text))}


def _short(error: BaseException) -> str:
    text = str(error).splitlines()[0] if str(error) else type(error).__name__
    return text[:200]


# ---------------------------------------------------------------------------- command line
def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = results_parser(
        prog,
        "Check a results file: read every case and dataset, compare the checksums, "
        "compare the summary CSV with the file. " + epilog_text(VERIFY),
        "results file (HDF5)",
    )
    parser.add_argument(
        "--summary",
        type=Path,
        default=None,
        metavar="CSV",
        help="summary CSV to compare with the file (default: RESULTS with the suffix .csv)",
    )
    parser.add_argument(
        "--no-summary", action="store_true", help="do not compare a summary CSV with the file"
    )
    return parser


def main(argv: Sequence[str] | None = None, prog: str | None = None) -> int:
    args = build_parser(prog).parse_args(argv)
    path: Path = args.results
    if being_written_file(path) or refuse_file(path):
        return EXIT_BAD_INPUT
    summary = None if args.no_summary else (args.summary or path.with_suffix(".csv"))
    stop = StopFlag()  # set by the handlers below: takes no lock
    for name in ("SIGTERM", "SIGINT", "SIGUSR1"):
        signal.signal(getattr(signal, name), lambda *_: stop.set())
    try:
        check = call_isolated(
            verify_file, path, summary, should_stop=stop.is_set, time_limit=time_limit_for(path)
        )
    except NotResultsFile as error:
        print(f"error: {error}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except IsolatedCallStopped:
        print(f"{path}: stopped before the check finished", file=sys.stderr)
        return EXIT_INTERRUPTED
    except IsolatedCallTimedOut as error:
        check = FileCheck(path, problem=str(error))
    print_report(check)
    return EXIT_DAMAGED if check.damaged else EXIT_CLEAN


def print_report(check: FileCheck, stream=None) -> None:
    """The table of bad cases and the verdict line."""
    stream = stream or sys.stdout
    lines = [(c.case_id, c.status or "?", c.problem) for c in check.bad_cases]
    lines += [(case_id, "summary", problem) for case_id, problem in check.summary_problems]
    if lines:
        width = max(len("case_id"), *(len(case_id) for case_id, _, _ in lines))
        print(f"{'case_id':<{width}s}  {'status':<10s}  problem", file=stream)
        for case_id, status, problem in lines:
            print(f"{case_id:<{width}s}  {status:<10s}  {problem}", file=stream)
    if check.summary_note:
        print(f"note: {check.summary_note}", file=stream)
    unverified = sum(1 for c in check.cases if c.sound and not c.verified)
    if unverified:
        print(
            f"note: {unverified} completed case(s) carry no checksums (written by an earlier "
            "version): read in full, nothing to compare with",
            file=stream,
        )
    print(_verdict(check), file=stream)


def _verdict(check: FileCheck) -> str:
    if check.problem:
        return f"{check.path}: DAMAGED: {check.problem}"
    completed = sum(1 for c in check.cases if c.status == CaseStatus.COMPLETED)
    read = sum(c.bytes_read for c in check.cases)
    counts = f"{len(check.cases)} cases, {completed} completed, {read / 1e6:.1f} MB of data read"
    if check.damaged:
        return (
            f"{check.path}: DAMAGED: {len(check.bad_cases)} bad case(s), "
            f"{len(check.summary_problems)} summary difference(s) ({counts}); rerunning the "
            "study recomputes the bad cases and rewrites the summary"
        )
    return f"{check.path}: OK ({counts}, checksums equal)"


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(prog="python -m engine.output.verify"))
