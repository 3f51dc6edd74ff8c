"""Scheduler and output at scale: thousands of tiny cases on 1, 2 and 4 ranks.

A static study at n = 8 (about 10 ms of computing per case) with ``mu1 × beta`` giving
``--cases`` cases is run with ``python -m engine`` under ``mpiexec -n R`` for each ``R`` of
``--ranks`` (oversubscribed beyond the cores is fine: the question is whether rank 0
becomes a bottleneck), side by side in one session. Printed per run:

- wall: the engine's own "wall time" line (scheduling loop: dispatch, computing, writing;
  interpreter and MPI start-up excluded), and the whole command;
- compute: the sum of the cases' ``runtime_s`` (summary CSV);
- overhead per case = (wall × min(R, cores) − compute) / cases: the engine's time per case
  outside the cases' computing (dispatch, HDF5 and CSV writing, progress lines), over all
  the cores in use; and the same from CPU time, (CPU of all ranks − the cases' ``cpu_s``)
  / cases: start-up, file creation, dispatch, writing and the read-back, per case;
- the CPU time of every rank (each rank's process, all threads, start-up and the read-back
  of the results included) and the time the run would take on an idle machine,
  max(busiest rank, all CPU / cores): other processes do not change it. Targets: 2 ranks
  in ≤ 0.6 of one rank's time, 4 ranks (oversubscribed) no slower than 2;
- share of rank 0 (cases it computed) and the speed-up wall(1 rank) / wall(R ranks);
- whether the summaries of all runs are identical (parameters and results, runtime aside).

    python benchmarks/bench_scheduler.py --cases 2000 --ranks 1 2 4   # ~3 minutes here
    python benchmarks/bench_scheduler.py --cases 10000 --ranks 1 4    # ~10 minutes here

``--baseline DIR`` runs every rank count with a second source tree as well (e.g. the commit
before a change: ``git archive 0779412 | tar -x -C /tmp/old``), alternating old and new runs
so both see the same load, and prints the two side by side with the ratio new/old of the
overhead per case. ``--update-docs`` writes the table into the manual's performance page.

Other processes on the machine distort the wall times; ratios measured in one session and
the CPU figures count.
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
    cpu_dir = directory / f"{label}_r{ranks}_cpu"
    cpu_dir.mkdir()
    env = dict(single_core_env(tree), BENCH_CPU_DIR=str(cpu_dir))
    launcher = str(Path(__file__).with_name("_rank_cpu.py"))
    command = [mpiexec(), "-n", str(ranks), sys.executable, launcher, str(study)]
    command += ["--no-progress-bar"]
    start = time.perf_counter()
    result = subprocess.run(command, env=env, capture_output=True, text=True, cwd=directory)
    total = time.perf_counter() - start
    if result.returncode != 0:
        raise SystemExit(f"{ranks} ranks: exit {result.returncode}\n{result.stderr[-2000:]}")
    rank_cpu = [float((cpu_dir / f"rank{rank}.txt").read_text()) for rank in range(ranks)]
    wall = float(re.search(r"wall time ([0-9.]+) s", result.stdout).group(1))
    summary = pd.read_csv(output.with_suffix(".csv"))
    on_rank0 = len(re.findall(r"^\[.*\] \S+ +rank 0 ", result.stdout, flags=re.MULTILINE))
    count = len(summary)
    compute = float(summary["runtime_s"].sum())
    compute_cpu = case_cpu_seconds(output)
    cores = min(ranks, os.cpu_count() or 1)
    # On an idle machine each rank runs about serially (rank 0's threads share one
    # interpreter lock), so the run takes at least its busiest rank's CPU and at least the
    # whole CPU spread over the cores: a figure other processes on the machine do not change.
    idle_estimate = max(max(rank_cpu), sum(rank_cpu) / cores)
    return {
        "tree": label,
        "ranks": ranks,
        "cases": count,
        "wall_s": wall,
        "command_s": total,
        "compute_s": compute,
        "overhead_ms_per_case": 1e3 * (wall * cores - compute) / count,
        "rank_cpu": rank_cpu,
        "cpu_overhead_ms_per_case": 1e3 * (sum(rank_cpu) - compute_cpu) / count,
        "idle_estimate_s": idle_estimate,
        "rank0_share": on_rank0 / count,
        "summary": comparable(summary),
    }


def case_cpu_seconds(output: Path) -> float:
    """The sum of the cases' ``cpu_s`` (CPU time of the thread that computed each case)."""
    import h5py

    with h5py.File(output, "r") as file:
        return float(sum(group.attrs.get("cpu_s", 0.0) for group in file["cases"].values()))


def comparable(summary: pd.DataFrame) -> pd.DataFrame:
    """Results without the run-dependent wall time, in case order."""
    frame = summary.drop(columns=["runtime_s"]).sort_values("case_id")
    return frame.reset_index(drop=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=2000)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4])
    parser.add_argument(
        "--baseline", type=Path, default=None, help="source tree to compare with (old code)"
    )
    parser.add_argument("--keep", action="store_true", help="keep the output directory")
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/performance.md (block bench-scheduler)",
    )  # fmt: skip
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
    if args.update_docs:
        write_doc_table(results, args)
    if args.keep:
        print(f"outputs in {directory}")
    else:
        shutil.rmtree(directory)


def table_rows(results: list[dict]) -> list[tuple]:
    """One row per run: ranks, wall and whole-command times, overhead per case (wall and
    CPU), CPU of rank 0 and of the busiest other rank, the idle-machine estimate and its
    ratio to the same tree's first run, rank 0's share, identical results."""
    first, rows = {}, []
    for r in results:
        base = first.setdefault(r["tree"], r)
        others = max(r["rank_cpu"][1:], default=0.0)
        rows.append((
            r["tree"], r["ranks"], f"{r['wall_s']:.2f}", f"{r['command_s']:.2f}",
            f"{r['overhead_ms_per_case']:.2f}", f"{r['cpu_overhead_ms_per_case']:.2f}",
            f"{r['rank_cpu'][0]:.2f}", f"{others:.2f}" if r["ranks"] > 1 else "",
            f"{r['idle_estimate_s']:.2f}",
            f"{r['idle_estimate_s'] / base['idle_estimate_s']:.3f}",
            f"{r['command_s'] / base['command_s']:.3f}", f"{r['rank0_share']:.3f}",
            str(r["summary"].equals(results[0]["summary"])),
        ))  # fmt: skip
    return rows


HEADER = ("tree", "ranks", "wall s", "command s", "overhead ms/case (wall)",
          "overhead ms/case (CPU)", "rank 0 CPU s", "busiest other rank CPU s",
          "idle-machine estimate s", "estimate ratio", "command ratio", "rank 0 share",
          "same results")  # fmt: skip


def print_table(results: list[dict]) -> None:
    """The rows of :func:`table_rows`, and the ratio new/old of the overhead per case."""
    print(" | ".join(HEADER))
    for row in table_rows(results):
        print(" | ".join(str(value) for value in row))
    old = {r["ranks"]: r for r in results if r["tree"] == "old"}
    for r in results:
        if r["tree"] == "new" and r["ranks"] in old:
            ratio = r["cpu_overhead_ms_per_case"] / old[r["ranks"]]["cpu_overhead_ms_per_case"]
            print(f"{r['ranks']} ranks: CPU overhead per case new/old {ratio:.2f}")


def write_doc_table(results: list[dict], args) -> None:
    """The scheduler table of the manual's performance page (block ``bench-scheduler``)."""
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    document = REPO / "docs" / "explanation" / "performance.md"
    note = f"`python benchmarks/bench_scheduler.py --cases {args.cases} --ranks "
    note += " ".join(str(r) for r in args.ranks) + " --update-docs`: static cases at n = 8"
    rows = [row[1:] for row in table_rows(results) if row[0] == "new"]  # this tree's runs
    text = measured_on(note) + "\n" + markdown_table(HEADER[1:], rows)
    replace_block(document, "bench-scheduler", text)
    print(f"{document}: wrote the block bench-scheduler")


if __name__ == "__main__":
    main()
