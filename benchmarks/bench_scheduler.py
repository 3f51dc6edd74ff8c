"""Scheduler and output at scale: thousands of tiny cases on 1, 2, 4 and 8 ranks (issue 18.3).

A static study at n = 8 (a few ms to tens of ms of computing per case) with ``mu1 × beta``
giving ``--cases`` cases is run with ``python -m engine`` under ``mpiexec -n R`` for each
``R`` of ``--ranks`` (oversubscribed beyond the cores is fine: the question is whether rank 0
becomes a bottleneck), side by side in one session. Printed per run:

- wall: the engine's own "wall time" line (scheduling loop: dispatch, computing, writing;
  interpreter and MPI start-up excluded), and the whole command;
- compute: the sum of the cases' ``runtime_s`` (summary CSV);
- overhead per case = (wall × min(R, cores) − compute) / cases: the engine's time per case
  outside the cases' computing (dispatch, HDF5 and CSV writing, progress lines), over all
  the cores in use. Target: ≤ 5 ms at 10,000 cases;
- share of rank 0 (cases it computed) and the speed-up wall(1 rank) / wall(R ranks)
  (target: the 8-rank run no slower than the 1-rank run on this 2-core machine);
- whether the summaries of all runs are identical (parameters and results, runtime aside).

    python benchmarks/bench_scheduler.py --cases 1000 --ranks 1 2 4 8     # ~2 minutes here
    python benchmarks/bench_scheduler.py --cases 10000 --ranks 1 8        # ~10 minutes here

``--baseline DIR`` runs every rank count with a second source tree as well (e.g. the commit
before a change: ``git archive 0779412 | tar -x -C /tmp/old``), alternating old and new runs
so both see the same load, and prints the two side by side with the ratio new/old of the
overhead per case.

Other processes on the machine distort the figures; ratios measured in one session count.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd
from _single_core import single_core_env

REPO = Path(__file__).resolve().parents[1]


def study_text(output: Path, mu1: list[float], beta: list[float]) -> str:
    """Tiny static cases (8 x 8, P = 750 N, one increment, 2 layers): scheduling dominates."""
    from engine.study.examples import study_toml

    return study_toml(
        "bench_scheduler",
        output,
        mesh={"n": 8},
        loading={"kind": "static", "steps": 1},
        subsurface={"layers": 2},
        sweep={"mu1": mu1, "beta": beta},
    )


def sweep_values(cases: int) -> tuple[list[float], list[float]]:
    """mu1 × beta lists with ``cases`` combinations (beta in [0, 180) degrees)."""
    betas = min(100, cases)
    mus = math.ceil(cases / betas)
    mu1 = [round(0.05 + 0.5 * i / mus, 6) for i in range(mus)]
    beta = [round(180.0 * j / betas, 6) for j in range(betas)]
    return mu1, beta


def mpiexec() -> str:
    return shutil.which("mpiexec", path=str(Path(sys.executable).parent)) or "mpiexec"


def run(directory: Path, cases: int, ranks: int, tree: Path = REPO, label: str = "new") -> dict:
    mu1, beta = sweep_values(cases)
    output = directory / f"{label}_r{ranks}.h5"
    study = directory / f"{label}_r{ranks}.toml"
    study.write_text(study_text(output, mu1, beta))
    env = single_core_env(tree)
    command = [mpiexec(), "-n", str(ranks), sys.executable, "-m", "engine", str(study)]
    command += ["--no-progress-bar"]
    start = time.perf_counter()
    result = subprocess.run(command, env=env, capture_output=True, text=True, cwd=directory)
    total = time.perf_counter() - start
    if result.returncode != 0:
        raise SystemExit(f"{ranks} ranks: exit {result.returncode}\n{result.stderr[-2000:]}")
    wall = float(re.search(r"wall time ([0-9.]+) s", result.stdout).group(1))
    summary = pd.read_csv(output.with_suffix(".csv"))
    on_rank0 = len(re.findall(r"^\[.*\] \S+ +rank 0 ", result.stdout, flags=re.MULTILINE))
    count = len(summary)
    compute = float(summary["runtime_s"].sum())
    cores = min(ranks, os.cpu_count() or 1)
    return {
        "tree": label,
        "ranks": ranks,
        "cases": count,
        "wall_s": wall,
        "command_s": total,
        "compute_s": compute,
        "overhead_ms_per_case": 1e3 * (wall * cores - compute) / count,
        "rank0_share": on_rank0 / count,
        "summary": comparable(summary),
    }


def comparable(summary: pd.DataFrame) -> pd.DataFrame:
    """Results without the run-dependent wall time, in case order."""
    frame = summary.drop(columns=["runtime_s"]).sort_values("case_id")
    return frame.reset_index(drop=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=1000)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8])
    parser.add_argument(
        "--baseline", type=Path, default=None, help="source tree to compare with (old code)"
    )
    parser.add_argument("--keep", action="store_true", help="keep the output directory")
    args = parser.parse_args()
    directory = Path(tempfile.mkdtemp(prefix="bench_scheduler_"))
    print(f"{args.cases} static cases at n = 8; ranks {args.ranks}; {os.cpu_count()} cores")
    print(f"load average at the start: {os.getloadavg()[0]:.1f}", flush=True)
    results = []
    for ranks in args.ranks:
        if args.baseline is not None:
            results.append(run(directory, args.cases, ranks, args.baseline, "old"))
        results.append(run(directory, args.cases, ranks))
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    print_table(results)
    if args.keep:
        print(f"outputs in {directory}")
    else:
        shutil.rmtree(directory)


def print_table(results: list[dict]) -> None:
    """One line per run; speed-up against the same tree's first rank count, overhead ratio
    new/old for the same rank count, results compared with the first run."""
    first = {}
    old = {r["ranks"]: r for r in results if r["tree"] == "old"}
    print(
        f"{'tree':>4s} {'ranks':>5s} {'wall s':>8s} {'command s':>9s} {'compute s':>9s} "
        f"{'overhead ms/case':>16s} {'new/old':>7s} {'rank 0 share':>12s} {'speed-up':>8s} "
        f"{'same results':>12s}"
    )
    for r in results:
        base = first.setdefault(r["tree"], r)
        same = r["summary"].equals(results[0]["summary"])
        ratio = ""
        if r["tree"] == "new" and r["ranks"] in old:
            ratio = f"{r['overhead_ms_per_case'] / old[r['ranks']]['overhead_ms_per_case']:.2f}"
        print(
            f"{r['tree']:>4s} {r['ranks']:5d} {r['wall_s']:8.2f} {r['command_s']:9.2f} "
            f"{r['compute_s']:9.2f} {r['overhead_ms_per_case']:16.2f} {ratio:>7s} "
            f"{r['rank0_share']:12.3f} {base['wall_s'] / r['wall_s']:8.2f} {str(same):>12s}"
        )


if __name__ == "__main__":
    main()
