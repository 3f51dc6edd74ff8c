"""Measure how long the bundled studies take and write it into their headers.

Every study of ``studies/`` says in its header how long it takes. That line is written only
by this script, from a run it timed: the study runs from scratch in a temporary folder with
``mpiexec -n 2`` (the header's own command), and the line gives the wall time with the date,
the machine and the load average at the run's start. On a loaded machine the figure would
overstate the time, so the script measures but does not write when that load average exceeds
``--max-load`` (2).

    python scripts/study_times.py studies/demo.toml [more.toml …]   # measure, write headers
    python scripts/study_times.py --all                             # every bundled study
    python scripts/study_times.py --check                           # exit 1 if a header's
                                                                    # time line is not one
                                                                    # this script writes

A header without a measurement says so (``UNMEASURED``); ``docs/reference/study-file.md``
lists each study's line (``python scripts/reference.py``).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
STUDIES = REPO / "studies"
PREFIX = "# Time: "
UNMEASURED = (
    PREFIX + "not measured on a quiet machine yet (python scripts/study_times.py measures it)."
)
MEASURED = re.compile(
    r"^# Time: [\d.,]+ (?:s|min|h) with `mpiexec -n 2` \(measured \d{4}-\d{2}-\d{2} on .+, "
    r"load average [\d.]+\)\.$"
)
REFERRED = re.compile(r"^# Time: in the blocks \S+ writes in \S+\.$")


def header_lines(path: Path) -> tuple[list[str], list[str]]:
    """The study's comment header and the rest of its lines."""
    lines = path.read_text().splitlines()
    end = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    return lines[:end], lines[end:]


def time_line(header: list[str]) -> str | None:
    return next((line for line in header if line.startswith(PREFIX)), None)


def write_time(path: Path, line: str) -> None:
    """Put ``line`` in place of the header's time line (or after its description)."""
    header, rest = header_lines(path)
    if time_line(header) is not None:
        header = [line if old.startswith(PREFIX) else old for old in header]
    else:
        at = next((i for i, old in enumerate(header) if old.startswith("# Run")), len(header))
        header.insert(at, line)
    path.write_text("\n".join(header + rest) + "\n")


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s" if seconds >= 10 else f"{seconds:.1f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def measure(path: Path) -> tuple[float, float]:
    """Wall time (s) of a fresh run of the study with ``mpiexec -n 2``, and the one-minute
    load average at its start: the machine's other work (the run's own two ranks add up to 2
    while it runs, so a load read at its end cannot tell a quiet machine from a busy one)."""
    python = REPO / ".venv" / "bin" / "python"
    mpiexec = REPO / ".venv" / "bin" / "mpiexec"
    with tempfile.TemporaryDirectory() as folder:
        # the study's folder whole: its input files (a calibration's tests, a surface map)
        # are found beside it
        copy = Path(folder) / "studies" / path.name
        shutil.copytree(path.resolve().parent, copy.parent, ignore=_results)
        load = os.getloadavg()[0]
        start = time.perf_counter()
        done = subprocess.run(
            [str(mpiexec), "-n", "2", str(python), "-m", "engine", copy.name, "--no-progress-bar"],
            cwd=copy.parent, capture_output=True, text=True,
        )  # fmt: skip
        wall = time.perf_counter() - start
    # exit 1: the run ended with a failed case or search, which the study may show on purpose
    # (the Fouvry calibration's test whose threshold lies below its bracket); it ran whole
    if done.returncode not in (0, 1):
        raise SystemExit(f"{path}: exit {done.returncode}: {done.stderr.strip()[-500:]}")
    return wall, load


def _results(folder, names):
    """Leave results out of the copy of a study's folder."""
    return [name for name in names if name == "results" or name.endswith((".h5", ".hdf5"))]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("studies", nargs="*", type=Path)
    parser.add_argument("--all", action="store_true", help="every study of studies/")
    parser.add_argument("--check", action="store_true", help="check the headers' time lines")
    parser.add_argument("--max-load", type=float, default=2.0)
    args = parser.parse_args(argv)
    if args.check:
        bad = []
        for path in sorted(STUDIES.glob("*.toml")):
            line = time_line(header_lines(path)[0])
            if line != UNMEASURED and not (line and (MEASURED.match(line) or REFERRED.match(line))):
                bad.append(f"{path.name}: {line!r}")
        print("\n".join(bad) or "every study header's time line is measured or says it is not")
        return 1 if bad else 0
    sys.path.insert(0, str(REPO))
    from engine.analysis.markdown import measured_on

    paths = sorted(STUDIES.glob("*.toml")) if args.all else args.studies
    for path in paths:
        wall, load = measure(path)
        where = measured_on().strip("*\n").removeprefix("Measured ").split(", load average")[0]
        line = f"{PREFIX}{_duration(wall)} with `mpiexec -n 2` (measured {where}, "
        line += f"load average {load:.1f})."
        if load > args.max_load:
            print(f"{path.name}: {wall:.1f} s at load average {load:.1f} > {args.max_load}: "
                  "not written")  # fmt: skip
            continue
        write_time(path, line)
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
