"""Run studies under two source trees of the engine and compare their results bit for bit.

Usage::

    python scripts/compare_trees.py --before TREE_A --after TREE_B --out DIR STUDY.toml ...
        [--before-python PY] [--after-python PY] [--nice N] [--ignore NAME ...]

Each tree is a checkout (or ``git archive``) of the project with its own environment: by
default ``TREE/.venv/bin/python``, with the tree installed in it (``pip install -e TREE``);
``--before-python`` and ``--after-python`` name other interpreters. Before any run, each
interpreter must import ``engine`` from its own tree (an environment that picks up another
checkout compares a tree with itself): else exit 2.

Every study file is run as given (the same file for both trees), one process at a time, from
the tree's directory, under ``nice`` (19 by default), with ``--fresh`` and ``--output
DIR/<study>.before.h5`` or ``.after.h5``. Then ``scripts/compare_results.py`` compares the two
results files and every summary CSV written beside them (``<study>.<side>.csv`` and the
study's other tables, ``<study>.<side>_<table>.csv``). The stored study file, its resolved
JSON and the command line name the output path, so they are ignored by default
(``--ignore`` adds names; compare them by hand when the study file differs).

Prints one line per run (exit code, wall time, load average at start and end) and per
comparison (the tool's count line), the differences themselves in ``DIR/<file>.txt``.
Exits 0 when every run succeeded alike and every file agrees, 1 otherwise, 2 on bad input.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

COMPARE = Path(__file__).resolve().parent / "compare_results.py"
OUTPUT_PATH_NAMES = ("study_toml", "study_json", "command_line")


def _load() -> str:
    """The 1, 5 and 15 min load averages, as ``uptime`` shows them."""
    return " ".join(f"{value:.2f}" for value in os.getloadavg())


def _engine_source(python: Path) -> Path:
    """The directory that ``python`` imports the engine package from (run outside any tree)."""
    code = "import engine, pathlib; print(pathlib.Path(engine.__file__).resolve().parents[1])"
    done = subprocess.run([str(python), "-c", code], capture_output=True, text=True, cwd="/")
    if done.returncode != 0:
        raise SystemExit(f"error: {python} cannot import engine: {done.stderr.strip()[-200:]}")
    return Path(done.stdout.strip())


def _run(python: Path, tree: Path, study: Path, output: Path, nice: int) -> int:
    """Run ``study`` with the engine of ``tree`` into ``output``; print and return its code."""
    command = ["nice", "-n", str(nice), str(python), "-m", "engine", str(study), "--fresh"]
    command += ["--no-progress-bar", "--progress-interval", "0", "--output", str(output)]
    load, start = _load(), time.perf_counter()
    with open(output.with_suffix(".log"), "w") as log:
        code = subprocess.run(command, cwd=tree, stdout=log, stderr=subprocess.STDOUT).returncode
    seconds = time.perf_counter() - start
    print(f"  {output.name}: exit {code}, {seconds:.1f} s, load {load} -> {_load()}", flush=True)
    return code


def _compare(first: Path, second: Path, ignore: list[str], report: Path) -> bool:
    """Compare two results files or CSVs with compare_results.py; True when they agree."""
    command = [sys.executable, str(COMPARE), str(first), str(second)]
    command += [item for name in ignore for item in ("--ignore", name)]
    done = subprocess.run(command, capture_output=True, text=True)
    report.write_text(done.stdout + done.stderr)
    lines = (done.stdout + done.stderr).strip().splitlines()
    print(f"  {first.name} vs {second.name}: {lines[-1] if lines else 'no output'}", flush=True)
    return done.returncode == 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("studies", nargs="+", type=Path, help="study files (TOML)")
    parser.add_argument("--before", type=Path, required=True, help="source tree A")
    parser.add_argument("--after", type=Path, required=True, help="source tree B")
    parser.add_argument("--before-python", type=Path, help="A's interpreter (TREE/.venv)")
    parser.add_argument("--after-python", type=Path, help="B's interpreter (TREE/.venv)")
    parser.add_argument("--out", type=Path, required=True, help="directory for the results")
    parser.add_argument("--nice", type=int, default=19, help="niceness of the runs (19)")
    parser.add_argument("--ignore", action="append", default=[], help="also ignore NAME")
    args = parser.parse_args(argv)
    sides = {}
    for side, tree, python in (
        ("before", args.before, args.before_python),
        ("after", args.after, args.after_python),
    ):
        tree = tree.resolve()
        python = (python or tree / ".venv" / "bin" / "python").absolute()
        if _engine_source(python) != tree:
            print(f"error: {python} imports engine from elsewhere, not from {tree}")
            return 2
        sides[side] = (python, tree)
    missing = [str(study) for study in args.studies if not study.is_file()]
    if missing:
        print(f"error: no study file {missing[0]}")
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    ignore = [*OUTPUT_PATH_NAMES, *args.ignore]
    agree = True
    for study in args.studies:
        print(f"{study.stem}:", flush=True)
        outputs, codes = {}, {}
        for side, (python, tree) in sides.items():
            outputs[side] = (args.out / f"{study.stem}.{side}.h5").absolute()
            codes[side] = _run(python, tree, study.absolute(), outputs[side], args.nice)
        agree &= codes["before"] == codes["after"]
        before, after = outputs["before"], outputs["after"]
        pairs = [(before, after)]
        for table in sorted(args.out.glob(f"{study.stem}.before*.csv")):
            twin = table.with_name(table.name.replace(".before", ".after", 1))
            pairs.append((table, twin))
        for first, second in pairs:
            if not second.exists():
                print(f"  {second.name}: missing")
                agree = False
                continue
            report = args.out / (first.name.replace(".before", "", 1) + ".txt")
            agree &= _compare(first, second, ignore, report)
    return 0 if agree else 1


if __name__ == "__main__":
    sys.exit(main())
