"""Peak memory of a large frictional static solve, measured within a time limit.

A frictional static solve at 2048² takes tens of minutes on one core, but its memory is
settled within the first normal and tangential passes: every kernel spectrum, FFT buffer
and work array is allocated by then, and later passes reuse them. This script runs the
solve of ``bench_anchors.py --frictional`` (flat punch, a0 = 1.8 mm, P = 714 N, the coupled
material, μ = 0.2, tolerance 1e-8, one core) in a child process, samples the child's peak
resident memory (``VmHWM``) every 0.2 s, and ends it after ``--seconds`` (or when it
finishes), printing the peak, the time of the last rise of the peak and whether the solve
finished. A peak that stopped rising long before the limit is the solve's peak.

The study's estimate for the whole case (``engine.study.resources``: solver plus the
subsurface x–z plane of ``--layers`` layers) is printed beside it.

    python benchmarks/bench_memory.py --n 2048 --seconds 240      # ~4 minutes
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

from _single_core import single_core_env

REPO = Path(__file__).resolve().parents[1]
RADIUS, LOAD, HALF_WIDTH_FACTOR, TOL, FRICTION = 1.8, 714.0, 1.05, 1e-8, 0.2

CHILD = """
import sys
from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw

n, radius, load, factor, tol, mu = sys.argv[1:]
grid = Grid.square(int(n), float(factor) * float(radius))
law = FrictionLaw(float(mu), float(mu))
solver = ContactSolver(grid, paper_material(), FlatPunch(float(radius)), law, tol=float(tol))
print("built", flush=True)
result = solver.solve_load(float(load))
report = result.report
print(f"finished converged={report.converged} iterations={report.iterations}", flush=True)
"""


def peak_kb(pid: int) -> int:
    """The process's peak resident memory (kB), from /proc; 0 once it is gone."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def measure(n: int, seconds: float) -> dict:
    arguments = [str(v) for v in (n, RADIUS, LOAD, HALF_WIDTH_FACTOR, TOL, FRICTION)]
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, *arguments],
        env=single_core_env(REPO),
        stdout=subprocess.PIPE,
        text=True,
    )
    start, peak, last_rise = time.perf_counter(), 0, 0.0
    while child.poll() is None and time.perf_counter() - start < seconds:
        current = peak_kb(child.pid)
        if current > peak:
            peak, last_rise = current, time.perf_counter() - start
        time.sleep(0.2)
    finished = child.poll() is not None
    if not finished:
        child.kill()
    output, _ = child.communicate()
    return {
        "n": n,
        "peak_mb": peak / 1024.0,
        "last_rise_s": last_rise,
        "elapsed_s": time.perf_counter() - start,
        "finished": finished,
        "output": output.strip().splitlines()[-1] if output.strip() else "",
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[2048])
    parser.add_argument("--seconds", type=float, default=240.0)
    parser.add_argument("--layers", type=int, default=16, help="for the study's estimate")
    args = parser.parse_args()
    sys.path.insert(0, str(REPO))
    from engine.study.resources import case_memory_bytes

    for n in args.n:
        row = measure(n, args.seconds)
        estimate = case_memory_bytes(n, args.layers) / 1e6
        print(
            f"n = {n}: solver peak {row['peak_mb']:.0f} MB (last rise at "
            f"{row['last_rise_s']:.0f} s of {row['elapsed_s']:.0f} s; "
            f"{'finished: ' + row['output'] if row['finished'] else 'stopped at the limit'}); "
            f"the study's estimate of the whole case with {args.layers} layers: "
            f"{estimate:.0f} MB",
            flush=True,
        )


if __name__ == "__main__":
    main()
