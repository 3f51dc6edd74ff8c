"""Fatigue criteria benchmark: what a ``[fatigue]`` section adds to a case's run time, the
same case run with and without it side by side in one process, one core.

1. 3-D: sphere R = 10 mm on steel (E = 200 GPa, ν = 0.3 both bodies), P = 100 N, μ = 0.5,
   force-controlled partial slip Q* = 0.646 μP, 20 increments per quarter cycle (80
   instants per cycle), 128² elements over ±1.5 a, ``--cycles-3d`` load cycles (default 1:
   two simulated, the worst case for the ratio), the last recorded; stress plane along x
   through the axis, 129 points × 40 depth layers to 1.5 a.
2. 2-D: cylinder R = 6 mm on a steel flat, P = 185 N/mm, μ = 0.9, 512 elements over
   ±0.4 mm, displacement amplitude ±8 µm (gross slip), 4 increments per quarter cycle (16
   instants), ``--cycles`` cycles (default 10⁴, cycle jumping) with wear, the last cycle
   recorded; its whole x–z plane, 512 × 40 depths to 1.5 a0.

Fatigue: all four criteria (Crossland, Dang Van, SWT, Fatemi–Socie, 1° planes) with the
point method, on the recorded cycle. The case runs through the study layer
(``engine.study.case.CaseRunner``), so the fatigue analysis reads the planes the case
evaluates anyway (its σ_VM probe of the recorded cycle) and adds only the criteria and the
critical-distance points. Prints the CPU times (``process_time``) of the case without and
with ``[fatigue]`` (side by side: on a shared machine the two runs differ by more than the
fatigue analysis costs) and the CPU spent inside the fatigue analysis's methods during the
run, over the rest of the case: its share, the figure (median of ``--repeat`` runs; the
bound asked is 15 %).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_fatigue.py [--repeat 3] [--update-docs]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import tempfile
import time
from datetime import UTC, datetime
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

FATIGUE = {
    "criteria": ["crossland", "dang_van", "swt", "fatemi_socie"],
    "sigma_d": 300.0, "tau_d": 200.0,
    "sigma_f": 1000.0, "b": -0.09, "eps_f": 0.6, "c": -0.6,
    "tau_f": 600.0, "gamma_f": 0.9, "b0": -0.09, "c0": -0.6, "k": 0.6, "sigma_y": 800.0,
    "method": "point",
}  # fmt: skip


def three_dimensional(folder: Path, fatigue: bool, cycles: int) -> str:
    from engine.study.examples import SPHERE_ON_STEEL, study_toml

    sections = {"fatigue": {**FATIGUE, "length": 0.01}} if fatigue else {}
    return study_toml(
        "bench_3d", str(folder / "bench_3d.h5"), SPHERE_ON_STEEL,
        mesh={"n": 128},  # half_width: 1.5 Hertz radii
        loading={"kind": "fretting", "load": 100.0, "steps": 20, "cycles": cycles,
                 "record": [cycles], "force_amplitude": 0.646 * 0.5 * 100.0},
        subsurface={"depth": 1.5, "layers": 40},
        sweep={"mu1": [0.5], "wear1": [1e-7]}, **sections,
    )  # fmt: skip


def two_dimensional(folder: Path, fatigue: bool, cycles: int) -> str:
    from engine.study.examples import CYLINDER_ON_STEEL, study_toml

    sections = {"fatigue": {**FATIGUE, "length": 0.01}} if fatigue else {}
    return study_toml(
        "bench_2d", str(folder / "bench_2d.h5"), CYLINDER_ON_STEEL,
        mesh={"n": 512, "half_width": 0.4},
        loading={"kind": "fretting", "load": 185.0, "steps": 4, "cycles": cycles,
                 "record": [cycles], "amplitude": 0.008},
        subsurface={"depth": 1.5, "layers": 40},
        sweep={"mu1": [0.9], "wear1": [2.75e-8]}, **sections,
    )  # fmt: skip


class FatigueClock:
    """CPU seconds spent inside the fatigue analysis's methods during a run (wrapped while
    the clock is in use)."""

    METHODS = ("increment_probe", "set_bulk_stress", "finish_cycle")

    def __init__(self):
        self.seconds = 0.0

    def __enter__(self):
        from engine.study.fatigue import FatigueAnalysis

        self.saved = {name: getattr(FatigueAnalysis, name) for name in self.METHODS}
        for name, method in self.saved.items():
            setattr(FatigueAnalysis, name, self._timed(method))
        return self

    def _timed(self, method):
        def timed(*args, **kwargs):
            start = time.process_time()
            try:
                return method(*args, **kwargs)
            finally:
                self.seconds += time.process_time() - start

        return timed

    def __exit__(self, *exc):
        from engine.study.fatigue import FatigueAnalysis

        for name, method in self.saved.items():
            setattr(FatigueAnalysis, name, method)


def case_time(text: str) -> tuple[float, float, dict]:
    """CPU seconds of the study's one case, of its fatigue analysis in it, and its row."""
    from engine.study.case import CaseRunner
    from engine.study.config import parse_study
    from engine.study.plan import make_plan

    config = parse_study(text)
    runner = CaseRunner(config)
    (case,) = make_plan(config)
    with FatigueClock() as clock:
        start = time.process_time()
        outcome = runner(case)
        spent = time.process_time() - start
    if outcome.status != "completed":
        raise RuntimeError(f"{case.case_id}: {outcome.status}: {outcome.message}")
    return spent, clock.seconds, outcome.row


DOC = Path(__file__).resolve().parents[1] / "docs" / "explanation" / "fatigue.md"


def measure(args) -> list[tuple]:
    """Per case: (label, load cycles, CPU without, CPU with, side-by-side overhead, the
    fatigue analysis's own CPU, its share (fatigue / (with − fatigue)), the runs' shares)."""
    results = []
    with tempfile.TemporaryDirectory() as folder:
        cases = (("3-D", three_dimensional, args.cycles_3d), ("2-D", two_dimensional, args.cycles))
        for label, build, cycles in cases:
            without, with_fatigue, inside, shares = [], [], [], []
            for _ in range(args.repeat):
                base, _, _row = case_time(build(Path(folder), False, cycles))
                full, fatigue, row = case_time(build(Path(folder), True, cycles))
                without.append(base)
                with_fatigue.append(full)
                inside.append(fatigue)
                shares.append(fatigue / (full - fatigue))
            base, full = statistics.median(without), statistics.median(with_fatigue)
            result = (
                label, cycles, base, full, (full - base) / base, statistics.median(inside),
                statistics.median(shares), shares,
            )  # fmt: skip
            print(
                f"{label}: {cycles:,} cycles, case {base:.2f} s CPU without [fatigue], "
                f"{full:.2f} s with (side by side {100 * result[4]:+.1f} %); the fatigue "
                f"analysis {result[5]:.2f} s CPU inside, {100 * result[6]:.1f} % of the rest "
                "(runs: "
                + ", ".join(f"{100 * x:.1f} %" for x in shares)
                + f"); crossland_risk {row['crossland_risk']:.4g}",
                flush=True,
            )
            results.append(result)
    return results


def write_doc_table(results: list[tuple], repeat: int) -> None:
    """The block ``bench-fatigue`` of docs/explanation/fatigue.md."""
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    planes = {"3-D": "sphere, 128², plane 129 × 40, 80 instants",
              "2-D": "cylinder, 512 elements, plane 512 × 40, 16 instants"}  # fmt: skip
    rows = [
        (f"{label} ({planes[label]})", f"{cycles:,}", f"{without:.1f}", f"{full:.1f}",
         f"{100 * side:+.1f} %", f"{fatigue:.2f}", f"{100 * share:.1f} %",
         ", ".join(f"{100 * x:.1f} %" for x in runs))
        for label, cycles, without, full, side, fatigue, share, runs in results
    ]  # fmt: skip
    header = ("case", "load cycles", "CPU without [fatigue] (s)", "CPU with (s)",
              "side by side", "fatigue analysis CPU (s)", "its share (median)",
              "runs")  # fmt: skip
    note = f"`python benchmarks/bench_fatigue.py --repeat {repeat} --update-docs`, one core"
    replace_block(DOC, "bench-fatigue", measured_on(note) + "\n" + markdown_table(header, rows))
    print(f"{DOC}: wrote the block bench-fatigue", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cycles", type=int, default=10_000, help="2-D case's load cycles")
    parser.add_argument("--cycles-3d", type=int, default=1, help="3-D case's load cycles")
    parser.add_argument(
        "--update-docs", action="store_true", help="write the table of docs/explanation/fatigue.md"
    )
    args = parser.parse_args()
    print(
        f"{datetime.now(UTC):%Y-%m-%d %H:%M} UTC, {platform.node()}, "
        f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}",
        flush=True,
    )
    results = measure(args)
    if args.update_docs:
        write_doc_table(results, args.repeat)


if __name__ == "__main__":
    main()
