"""The McColl, Ding & Leen (2004) line-contact study and its convergence check, into the docs.

Runs ``studies/mccoll_2004_convergence.toml`` (the bundled ``studies/mccoll_2004.toml`` case
on 128, 256 and 512 elements, each with the bundled wear per cycle jump and half of it; the
results file is resumed when it exists) with ``mpiexec -n RANKS python -m engine``, reads the
wear fields recorded at 1,000, 5,000, 10,000 and 18,000 cycles and writes two blocks of
docs/explanation/results.md, each headed by the date, machine and load:

- ``mccoll-2004``: the flat's scar depth, width (where its wear exceeds 1 % of the depth) and
  worn area, and the cylinder's wear depth, of the bundled settings (256 elements, 0.004),
  with the energy-law cross-check: under gross slip the worn area of the flat equals
  k/μ × the dissipated energy (Archard's k p s = (k/μ) q s, q = μp on every slipping point).
- ``mccoll-2004-convergence``: the relative change of those numbers with the mesh
  (128 and 512 against 256 elements) and with half the wear per cycle jump.

    python scripts/mccoll_results.py            # 2 ranks
    python scripts/mccoll_results.py --ranks 1 --fresh
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from engine.analysis.markdown import markdown_table, measured_on, replace_block  # noqa: E402
from engine.grid import Grid  # noqa: E402
from engine.solvers.scar import scar_measures  # noqa: E402

STUDY = REPO / "studies" / "mccoll_2004_convergence.toml"
RESULTS = REPO / "results" / "mccoll_2004_convergence.h5"
DOCUMENT = REPO / "docs" / "explanation" / "results.md"
CYCLES = (1000, 5000, 10000, 18000)
BUNDLED = (256, 0.004)  # elements, max_wear_fraction of studies/mccoll_2004.toml
PAD_RATIO = 1.0  # k_pad / k_flat: both 2.75e-8 1/MPa
WEAR_COEFFICIENT = 2.75e-8  # 1/MPa
FRICTION = 0.9
HALF_WIDTH = 1.0  # mm


def run_study(ranks: int, fresh: bool) -> float:
    """Run (or resume) the convergence study; returns the wall time (s) of the command."""
    import time

    mpiexec = Path(sys.executable).parent / "mpiexec"
    command = [str(mpiexec), "-n", str(ranks), sys.executable, "-m", "engine", str(STUDY)]
    command += ["--no-progress-bar", "--progress-interval", "60"] + (["--fresh"] if fresh else [])
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    start = time.perf_counter()
    completed = subprocess.run(command, cwd=REPO, env=env)
    if completed.returncode not in (0, 1):  # 1: a case failed, reported in the table
        raise SystemExit(f"the study stopped with exit code {completed.returncode}")
    return time.perf_counter() - start


def case_measures(results: Path) -> dict[tuple[int, float], dict]:
    """Per case (elements, wear fraction): the scar measures at each recorded cycle, the
    cumulated dissipated energy (N·mm/mm) and the case's CPU time (s)."""
    measures = {}
    with h5py.File(results, "r") as file:
        for group in file["cases"].values():
            n = int(group.attrs["mesh.n"])  # the swept keys are attributes of the case
            fraction = float(group.attrs["loading.max_wear_fraction"])
            if group.attrs["status"] != "completed":
                measures[(n, fraction)] = {"failed": str(group.attrs["message"])}
                continue
            grid = Grid.line(n, HALF_WIDTH)
            by_cycle = {
                cycle: scar_measures(
                    grid, group[f"fields/cycle_{cycle:07d}/wear"][...], PAD_RATIO
                ).row()
                for cycle in CYCLES
            }
            history = group["history"]
            cycles = history["cycle"][...]
            energy = np.cumsum(history["jump"][...] * history["energy"][...])
            for cycle in CYCLES:
                by_cycle[cycle]["energy"] = float(np.interp(cycle, cycles, energy))
            measures[(n, fraction)] = {
                "cycles": by_cycle,
                "cpu_s": float(group.attrs.get("cpu_s", float("nan"))),
                "simulated": int(cycles.size),
            }
    return measures


def results_table(case: dict) -> str:
    header = (
        "cycles", "scar_depth (µm)", "scar_width (mm)", "scar_area (mm²/mm)",
        "pad_wear_depth (µm)", "k/μ × dissipated energy (mm²/mm)",
    )  # fmt: skip
    rows = []
    for cycle, values in case["cycles"].items():
        energy_area = WEAR_COEFFICIENT / FRICTION * values["energy"]
        rows.append(
            (
                f"{cycle:,}",
                f"{values['scar_depth'] * 1e3:.3f}",
                f"{values['scar_width']:.3f}",
                f"{values['scar_area']:.4e}",
                f"{values['pad_wear_depth'] * 1e3:.3f}",
                f"{energy_area:.4e}",
            )
        )
    return markdown_table(header, rows)


def convergence_table(measures: dict) -> str:
    """Relative change of each measure against the bundled case, per variant and cycle."""
    reference = measures[BUNDLED]["cycles"]
    header = ("variant", "cycles", "scar_depth", "scar_width", "scar_area", "pad_wear_depth")
    rows = []
    for key in sorted(measures):
        if key == BUNDLED:
            continue
        n, fraction = key
        label = f"{n} elements, max_wear_fraction {fraction:g}"
        if "failed" in measures[key]:
            rows.append((label, "–", f"failed: {measures[key]['failed']}", "", "", ""))
            continue
        for cycle in CYCLES:
            values = measures[key]["cycles"][cycle]
            changes = [
                f"{values[name] / reference[cycle][name] - 1:+.2%}"
                for name in ("scar_depth", "scar_width", "scar_area", "pad_wear_depth")
            ]
            rows.append((label, f"{cycle:,}", *changes))
    return markdown_table(header, rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--fresh", action="store_true", help="recompute the study")
    parser.add_argument("--no-run", action="store_true", help="only read existing results")
    args = parser.parse_args()
    wall = None if args.no_run else run_study(args.ranks, args.fresh)
    measures = case_measures(RESULTS)
    bundled = measures[BUNDLED]
    timing = f"; the study (6 cases) took {wall:.0f} s on {args.ranks} ranks" if wall else ""
    note = (
        f"`python scripts/mccoll_results.py`: 256 elements, max_wear_fraction 0.004 "
        f"(studies/mccoll_2004.toml), {bundled['simulated']} simulated cycles, "
        f"{bundled['cpu_s']:.1f} s of CPU{timing}"
    )
    replace_block(DOCUMENT, "mccoll-2004", measured_on(note) + "\n" + results_table(bundled))
    cpu = ", ".join(
        f"{n} el./{fraction:g}: {value['cpu_s']:.1f} s"
        for (n, fraction), value in sorted(measures.items())
        if "failed" not in value
    )
    note = f"`python scripts/mccoll_results.py`: change against 256 elements, 0.004; CPU {cpu}"
    replace_block(
        DOCUMENT, "mccoll-2004-convergence", measured_on(note) + "\n" + convergence_table(measures)
    )
    print(f"{DOCUMENT}: wrote the blocks mccoll-2004 and mccoll-2004-convergence")


if __name__ == "__main__":
    main()
