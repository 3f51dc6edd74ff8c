"""How long the bundled calibration takes: ``studies/fouvry_crack_nucleation.toml`` (16
tests, Crossland at the critical distance, ℓ, σ_d and τ_d fitted on the 8 plain-fretting
tests, the 8 fretting-fatigue tests predicted) from scratch under ``mpiexec -n RANKS``.

Printed: the wall time, the contact solutions it took (the cases: one fretting case per
test and value of the force searched), the fit's evaluations and status, the load average
before and after. ``--tests N`` runs the first N tests of each role only (a quick look that
the benchmark works); ``--update-docs`` writes the block ``bench-calibration`` of
docs/how-to/calibration.md (the full study only).

    python benchmarks/bench_calibration.py                  # 2 ranks, the whole study
    python benchmarks/bench_calibration.py --tests 2        # 2 + 2 tests, a few minutes

Other processes on the machine lengthen the wall time (the load average says how much).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
STUDY = REPO / "studies" / "fouvry_crack_nucleation.toml"
DOCS = REPO / "docs" / "how-to" / "calibration.md"


def study_copy(directory: Path, tests: int | None) -> Path:
    """The bundled study writing into ``directory`` (its tests file by absolute path; with
    ``tests``: the first ``tests`` calibration and predicted tests only)."""
    sys.path.insert(0, str(REPO))
    from engine.study.config.toml_writer import dump_toml

    data = tomllib.loads(STUDY.read_text())
    source = STUDY.with_name(data["calibrate"]["tests"])
    data["study"]["output"] = str(directory / "calibration.h5")
    if tests is None:
        data["calibrate"]["tests"] = str(source)
    else:
        lines = source.read_text().splitlines()
        header = [line for line in lines if not line.startswith("#")][0]
        rows = [line for line in lines if not line.startswith("#")][1:]
        calibrate = set(data["calibrate"]["calibrate_on"])
        chosen_calibrate = [row for row in rows if row.split(",")[0] in calibrate][:tests]
        chosen_predict = [row for row in rows if row.split(",")[0] not in calibrate][:tests]
        subset = directory / "tests.csv"
        subset.write_text("\n".join([header, *chosen_calibrate, *chosen_predict]) + "\n")
        data["calibrate"]["tests"] = str(subset)
        data["calibrate"]["calibrate_on"] = [row.split(",")[0] for row in chosen_calibrate]
    path = directory / "calibration.toml"
    path.write_text(dump_toml(data))
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--tests", type=int, default=None, help="N tests of each role")
    parser.add_argument("--update-docs", action="store_true")
    args = parser.parse_args()
    if args.update_docs and args.tests is not None:
        raise SystemExit("--update-docs measures the whole study: leave out --tests")
    load_start = os.getloadavg()[0]
    print(f"load average at the start: {load_start:.1f}", flush=True)
    with tempfile.TemporaryDirectory() as folder:
        study = study_copy(Path(folder), args.tests)
        mpiexec = str(REPO / ".venv" / "bin" / "mpiexec")
        command = [mpiexec, "-n", str(args.ranks), sys.executable, "-m", "engine", str(study),
                   "--no-progress-bar"]  # fmt: skip
        start = time.perf_counter()
        result = subprocess.run(command, cwd=REPO, capture_output=True, text=True)
        wall = time.perf_counter() - start
        if result.returncode not in (0, 1):
            raise SystemExit(f"exit {result.returncode}\n{result.stdout}\n{result.stderr}")
        import engine

        frame = engine.load_calibration(Path(folder) / "calibration.h5")
    solved = int(re.search(r"(\d+) contact solutions computed", result.stdout)[1])
    load_end = os.getloadavg()[0]
    line = (
        f"{len(frame)} tests on {args.ranks} ranks: {wall:.0f} s, {solved} contact solutions "
        f"(cases), fit {frame.attrs['fit_status']} after {frame.attrs['fit_evaluations']} "
        f"evaluations; load average {load_start:.1f} at the start, {load_end:.1f} at the end"
    )
    print(line)
    if args.update_docs:
        write_docs(len(frame), args.ranks, wall, solved, frame, load_start, load_end)


def write_docs(tests, ranks, wall, solved, frame, load_start, load_end) -> None:
    sys.path.insert(0, str(REPO))
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    note = (
        f"load average {load_start:.1f} at the start, {load_end:.1f} at the end; "
        "`python benchmarks/bench_calibration.py --update-docs`"
    )
    row = (tests, ranks, f"{wall:.0f}", solved, frame.attrs["fit_evaluations"],
           frame.attrs["fit_status"])  # fmt: skip
    header = ("tests", "ranks", "wall (s)", "contact solutions (cases)", "fit evaluations", "fit")
    text = measured_on(note) + "\n\n" + markdown_table(header, [row])
    replace_block(DOCS, "bench-calibration", text)


if __name__ == "__main__":
    main()
