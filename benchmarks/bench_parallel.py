"""Parallel efficiency of the study engine: four equal cases on one rank vs two ranks.

Four cyclic cases of identical cost (isotropic friction, so the axes angle β = 0, 45, 90, 135°
changes nothing but the id) are run with ``python -m engine`` under ``mpiexec -n 1`` and
``mpiexec -n 2``, side by side in one session, alternating, ``--repeat`` times each. The wall
time of the whole command (start-up, MPI init, HDF5 writing included) is measured; the best of
the repeats is compared. Target: t(2 ranks) / t(1 rank) <= 0.55 on a 2-core machine.

    python benchmarks/bench_parallel.py            # short (n = 32) and long (n = 64) cases
    python benchmarks/bench_parallel.py --n 32 --cycles 10000 --repeat 1   # quick look

The fixed CPU of a run (start-up, imports, MPI initialisation, operator set-up, writing) is
printed per study: it is what keeps short cases from scaling.

Other processes on the machine distort the figure; run it on an otherwise idle machine.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _single_core import single_core_env

REPO = Path(__file__).resolve().parents[1]


def study_text(output: Path, n: int, steps: int, cycles: int) -> str:
    """Four equal cyclic cases (μ = 0.2, β = 0, 45, 90, 135°) on an n x n mesh, coarse jumps."""
    from engine.study.examples import study_toml

    loading = {"steps": steps, "cycles": cycles, "record": [cycles], "max_wear_fraction": 0.02}
    return study_toml(
        "bench_parallel",
        output,
        mesh={"n": n},
        loading=loading,
        subsurface={"layers": 12},
        sweep={"mu1": [0.2], "wear1": [1.33e-7], "beta": [0.0, 45.0, 90.0, 135.0]},
    )


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def case_cpu_per_rank(results: Path) -> dict[int, float]:
    """CPU seconds of the cases each rank computed (``cpu_s`` attribute of every case)."""
    import h5py

    per_rank: dict[int, float] = {}
    with h5py.File(results, "r") as file:
        for group in file["cases"].values():
            rank = int(group.attrs["rank"])
            per_rank[rank] = per_rank.get(rank, 0.0) + float(group.attrs["cpu_s"])
    return per_rank


def run(ranks: int, study: Path) -> tuple[float, float]:
    """Wall time of the command and CPU time of all its processes (s)."""
    mpiexec = shutil.which("mpiexec", path=str(Path(sys.executable).parent)) or "mpiexec"
    env = single_core_env(REPO)
    command = [
        mpiexec,
        "-n",
        str(ranks),
        sys.executable,
        "-m",
        "engine",
        str(study),
        "--fresh",
        "--no-progress-bar",
    ]
    cpu = _children_cpu()
    start = time.perf_counter()
    result = subprocess.run(command, env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    cpu = _children_cpu() - cpu
    if result.returncode != 0:
        raise SystemExit(f"engine failed ({result.returncode}):\n{result.stdout}{result.stderr}")
    return elapsed, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--n",
        type=int,
        nargs="+",
        default=[32, 64],
        help="elements per side, one study each (default: 32 = short cases, 64 = long ones)",
    )
    parser.add_argument("--steps", type=int, default=6, help="increments per half cycle")
    parser.add_argument("--cycles", type=int, default=100000)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/performance.md (block bench-parallel)",
    )  # fmt: skip
    args = parser.parse_args()
    rows = [measure(n, args.steps, args.cycles, args.repeat) for n in args.n]
    if args.update_docs:
        write_doc_table(rows, args)


def write_doc_table(rows: list[tuple], args) -> None:
    """The MPI table of the manual's performance page (block ``bench-parallel``)."""
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    document = REPO / "docs" / "explanation" / "performance.md"
    header = ("n", "CPU per case (s)", "1 rank (s)", "2 ranks (s)", "wall ratio",
              "load-independent ratio", "fixed CPU of a run (s)")  # fmt: skip
    note = "`python benchmarks/bench_parallel.py --update-docs`: four equal cyclic cases, "
    note += f"{args.cycles:,} cycles, {args.steps} increments per half cycle, whole command "
    note += f"timed, best of {args.repeat}"
    replace_block(
        document, "bench-parallel", measured_on(note) + "\n" + markdown_table(header, rows)
    )
    print(f"{document}: wrote the block bench-parallel")


def measure(n: int, steps: int, cycles: int, repeat: int) -> tuple:
    """Four equal cases on 1 and 2 ranks, alternating, best of ``repeat``; prints the ratio,
    the per-case CPU and the fixed CPU of a run (start-up, set-up, writing)."""
    with tempfile.TemporaryDirectory() as folder:
        study = Path(folder) / "bench.toml"
        study.write_text(study_text(Path(folder) / "bench.h5", n, steps, cycles))
        times: dict[int, list[float]] = {1: [], 2: []}
        cpu: dict[int, list[float]] = {1: [], 2: []}
        estimates, fixed_cpu, case_cpu = [], [], []
        for _ in range(repeat):
            for ranks in (1, 2):
                wall, used = run(ranks, study)
                times[ranks].append(wall)
                cpu[ranks].append(used)
                per_rank = case_cpu_per_rank(Path(folder) / "bench.h5")
                shares = ", ".join(f"rank {r}: {t:.2f} s" for r, t in sorted(per_rank.items()))
                print(
                    f"n={n} ranks={ranks}: wall {wall:7.2f} s, cpu {used:7.2f} s (cases: {shares})",
                    flush=True,
                )
                if ranks == 1:
                    serial_cases, serial_cpu = sum(per_rank.values()), used
                    fixed_cpu.append(max(serial_cpu - serial_cases, 0.0))
                    case_cpu.append(serial_cases / 4)
                else:
                    # Idle-machine estimate (one free core per process): each rank pays the fixed
                    # CPU of the 1-rank run (start-up, planning, writing) plus its own cases;
                    # the 1-rank run takes its CPU time.
                    fixed = max(serial_cpu - serial_cases, 0.0)
                    estimates.append((fixed + max(per_rank.values())) / serial_cpu)
    one, two = min(times[1]), min(times[2])
    print(
        f"four equal cases (n = {n}, {cycles} cycles, {steps} steps, {min(case_cpu):.2f} s "
        f"cpu per case), best of {repeat}: 1 rank {one:.2f} s, 2 ranks {two:.2f} s, wall ratio "
        f"{two / one:.3f} (target <= 0.55); fixed cpu of a run (start-up, set-up, writing) "
        f"{min(fixed_cpu):.2f} s; cpus = {os.cpu_count()}, load average after: "
        f"{os.getloadavg()[0]:.2f}"
    )
    print(
        f"cpu of all processes: 1 rank {min(cpu[1]):.2f} s, 2 ranks {min(cpu[2]):.2f} s; "
        f"load-independent ratio (fixed cpu + busiest rank's case cpu) / 1-rank cpu: "
        f"{min(estimates):.3f}. Other processes on the cores inflate the wall ratio.",
        flush=True,
    )
    return (
        n, f"{min(case_cpu):.2f}", f"{one:.2f}", f"{two:.2f}", f"{two / one:.3f}",
        f"{min(estimates):.3f}", f"{min(fixed_cpu):.2f}",
    )  # fmt: skip


if __name__ == "__main__":
    main()
