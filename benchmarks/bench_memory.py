"""Peak memory of a large frictional static case, the solve alone and the whole command, each
measured within a time limit.

A frictional static case at 2048² takes several minutes on one core, more on a loaded
machine, and some 4 GB. The problem is the one of ``bench_anchors.py --frictional``'s coupled
row: a flat punch, a0 = 1.8 mm, P = 714 N in one step, the paper's coupled pair (K = 0.196),
Coulomb μ = 0.2, tolerance 1e-8, one core. Two things are measured, each in a process of its
own, one after the other:

- **solver**: ``ContactSolver(...).solve_load(P)`` in a child that imports only the solver;
- **command**: ``python -m engine STUDY.toml --fresh --no-progress-bar`` on a one-case
  static study of the same problem (``mu1 = [0.2]``, one load step, the default 16 layers of
  the x–z stress plane), with an empty cache directory, as a user runs it.

Each process's peak resident memory (``VmHWM``) is sampled every 0.2 s, and the process is
ended after ``--seconds`` if it has not finished; its peak is the larger of the last sample
and the ``ru_maxrss`` of the ended process (``os.wait4``), which also holds a rise after the
last sample. Printed per process: the peak (MB = 10⁶ bytes), the time from which the sampled
peak stayed within 1 % of it and the time of its last rise, the time the process ran and
whether it finished within the limit (the solver's convergence and iterations, or the
command's exit code). A process that finished has shown its whole peak; one stopped at the
limit, only its peak until then: the solver's memory is not all allocated in its first
passes (the resident memory swings by hundreds of MB as its temporaries come and go, and
the peak can rise late in the solve), and a command stopped at the limit has not reached
its stress plane and output.

Beside each peak, the study's estimate of the whole case (``engine.study.resources``: the
solver plus the x–z plane of the default 16 layers, what the command checks against the node
before it starts) and the ratio of the peak to it.

``--update-docs`` writes the figures into the block ``bench-memory`` of
docs/explanation/memory-and-setup.md, with the date, the machine and the load average
(memory does not depend on the load; the times do).

    python benchmarks/bench_memory.py --n 2048 --seconds 600 --update-docs   # ~10 minutes
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _single_core import single_core_env
from bench_anchors import study_text

REPO = Path(__file__).resolve().parents[1]
RADIUS, LOAD, HALF_WIDTH_FACTOR, TOL, FRICTION = 1.8, 714.0, 1.05, 1e-8, 0.2
SAMPLE_S = 0.2  # the interval between two samples of VmHWM
SETTLED = 0.01  # a peak within this fraction of the last one has settled
WHAT = {
    "solver": "solver alone (`ContactSolver.solve_load`)",
    "command": "whole `python -m engine`, one-case static study",
}

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
state = "converged" if report.converged else "did not converge"
print(f"solve {state} in {report.iterations} iterations", flush=True)
"""


def peak_kb(pid: int) -> int:
    """The process's peak resident memory (kB = 1024 bytes), from /proc; 0 once it is gone."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def sample(command: list[str], env: dict, cwd: Path, seconds: float) -> dict:
    """Run ``command`` for at most ``seconds``, sampling its peak memory (module doc): the
    peak (MB), the time of its last rise and the time it ran (s), whether it finished, its
    exit code and the last line it printed."""
    with tempfile.TemporaryFile("w+") as log:
        start = time.perf_counter()
        child = subprocess.Popen(
            command, env=env, cwd=cwd, stdout=log, stderr=log, start_new_session=True
        )
        pid = child.pid
        rises, finished = [(0.0, 0)], False  # (time, peak) at each rise of the peak
        while time.perf_counter() - start < seconds:
            done, status, usage = os.wait4(pid, os.WNOHANG)
            if done:
                finished = True
                break
            current = peak_kb(pid)
            if current > rises[-1][1]:
                rises.append((time.perf_counter() - start, current))
            time.sleep(SAMPLE_S)
        if not finished:
            os.killpg(pid, signal.SIGKILL)  # the command and anything it started
            _, status, usage = os.wait4(pid, 0)
        child.returncode = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
        elapsed = time.perf_counter() - start
        if usage.ru_maxrss > rises[-1][1]:  # a rise after the last sample
            rises.append((elapsed, usage.ru_maxrss))
        log.seek(0)
        lines = log.read().strip().splitlines()
    return {
        "peak_mb": rises[-1][1] * 1024 / 1e6,
        "last_rise_s": rises[-1][0],
        "settled_s": next(t for t, kb in rises if kb >= (1 - SETTLED) * rises[-1][1]),
        "elapsed_s": elapsed,
        "finished": finished,
        "exit": child.returncode,
        "output": lines[-1] if lines else "",
    }


def measure_solver(n: int, seconds: float, cwd: Path) -> dict:
    arguments = [str(v) for v in (n, RADIUS, LOAD, HALF_WIDTH_FACTOR, TOL, FRICTION)]
    command = [sys.executable, "-c", CHILD, *arguments]
    return sample(command, single_core_env(REPO), cwd, seconds)


def measure_command(n: int, seconds: float, folder: Path) -> dict:
    """``python -m engine`` on the one-case frictional study of ``bench_anchors.study_text``
    (the paper's pair, μ = ``FRICTION``) in ``folder``, with an empty cache directory
    there (the first run on a fresh machine)."""
    study = folder / f"memory_{n}.toml"
    study.write_text(study_text(n, folder / f"memory_{n}.h5", mu=FRICTION, name="memory"))
    env = single_core_env(REPO)
    env.pop("ENGINE_FFTW_WISDOM", None)
    env["XDG_CACHE_HOME"] = str(folder / "cache")
    command = [sys.executable, "-m", "engine", str(study), "--fresh", "--no-progress-bar"]
    return sample(command, env, folder, seconds)


def outcome(row: dict) -> str:
    """Whether the process finished within the limit, in words."""
    if not row["finished"]:
        return "no: stopped at the limit"
    if row["exit"] != 0:
        return f"yes, failed (exit {row['exit']}: {row['output']})"
    solved = row["output"].startswith("solve ")
    return f"yes: {row['output'].removeprefix('solve ')}" if solved else "yes: exit 0"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[2048])
    parser.add_argument("--seconds", type=float, default=600.0, help="the time limit of each")
    parser.add_argument(
        "--what", nargs="+", choices=tuple(WHAT), default=list(WHAT), help="what to measure"
    )
    parser.add_argument(
        "--update-docs",
        action="store_true",
        help="write the figures into docs/explanation/memory-and-setup.md",
    )
    args = parser.parse_args()
    sys.path.insert(0, str(REPO))
    from engine.study.resources import case_memory_bytes

    layers = 16  # the default of [subsurface] layers, the study's
    load = os.getloadavg()[0]
    print(f"load average at the start: {load:.1f}", flush=True)
    rows = []
    with tempfile.TemporaryDirectory() as name:
        for n in args.n:
            estimate = case_memory_bytes(n, layers, frictional=True) / 1e6
            for what in args.what:
                if what == "solver":
                    row = measure_solver(n, args.seconds, Path(name))
                else:
                    row = measure_command(n, args.seconds, Path(name))
                row |= {"n": n, "what": what, "estimate_mb": estimate}
                rows.append(row)
                print(
                    f"n = {n}, {what}: peak {row['peak_mb']:.0f} MB (within 1 % of it from "
                    f"{row['settled_s']:.0f} s, last rise at {row['last_rise_s']:.0f} s of "
                    f"{row['elapsed_s']:.0f} s); finished "
                    f"within {args.seconds:g} s: {outcome(row)}; the study's estimate of the "
                    f"whole case with {layers} layers: {estimate:.0f} MB (peak / estimate "
                    f"{row['peak_mb'] / estimate:.2f})",
                    flush=True,
                )
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    if args.update_docs:
        write_doc_block(rows, args, load)


def write_doc_block(rows: list[dict], args, load: float) -> None:
    """The block ``bench-memory`` of the manual's memory and set-up page."""
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    command = f"python benchmarks/bench_memory.py --n {' '.join(map(str, args.n))}"
    command += f" --seconds {args.seconds:g}"
    command += f" --what {' '.join(args.what)}" if args.what != list(WHAT) else ""
    note = (
        f"`{command} --update-docs`, one core per process, one process after the other, "
        f"VmHWM sampled every {SAMPLE_S:g} s; MB = 10⁶ bytes; load average at the start "
        f"{load:.1f}"
    )
    header = (
        "n", "measured (one process)", "peak (MB)",
        f"within {100 * SETTLED:g} % of the peak from (s)", "last rise of the peak (s)",
        "ran (s)", f"finished within {args.seconds:g} s", "study's estimate of the case (MB)",
        "peak / estimate",
    )  # fmt: skip
    table = [
        (
            f"{row['n']}²", WHAT[row["what"]], f"{row['peak_mb']:.0f}",
            f"{row['settled_s']:.0f}", f"{row['last_rise_s']:.0f}", f"{row['elapsed_s']:.0f}",
            outcome(row),
            f"{row['estimate_mb']:.0f}", f"{row['peak_mb'] / row['estimate_mb']:.2f}",
        )
        for row in rows
    ]  # fmt: skip
    document = REPO / "docs" / "explanation" / "memory-and-setup.md"
    replace_block(
        document, "bench-memory", measured_on(note) + "\n" + markdown_table(header, table)
    )
    print(f"{document}: wrote the block bench-memory")


if __name__ == "__main__":
    main()
