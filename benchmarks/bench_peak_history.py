"""Peak-history cost benchmark: what tracking the σ_VM peak adds to a simulated cycle.

Section 7.2 settings (flat punch a0 = 1.8 mm, P = 750 N, μ = 0.1, i = 1.33e-7 1/MPa, 10
increments per half cycle, default cycle jumping, tol 1e-6), subsurface as in the studies
(31 graded layers to 1.5 a0). One cyclic run with the :class:`PeakTracker` as ``peak_probe``;
the probe calls are timed inside the same run, so the two figures share the machine's load:

- the cycle's own cost: wall time of the run minus the probe time, per simulated cycle;
- the probe's cost per cycle, first call (fills the kernel cache: one-off) and the others
  (cached kernels: six inverse FFTs per layer of the x–z plane lattice, the peak searches).

Target: the added cost per simulated cycle <= 15 % of the cycle's own cost.

Run:  OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_peak_history.py [--sizes 32 64]
Takes ~1 minute for 32² and 64² with --cycles 10000 here.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.solvers.contact import ContactSolver
from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
from engine.solvers.friction import FrictionLaw, WearLaw
from engine.solvers.peak import PeakTracker
from engine.solvers.subsurface import SubsurfaceStress, depth_layers

RADIUS, LOAD, WEAR, LAYERS, DEPTH = 1.8, 750.0, 1.33e-7, 31, 1.5


class TimedProbe:
    """A PeakTracker whose calls are timed (s)."""

    def __init__(self, tracker: PeakTracker):
        self.tracker = tracker
        self.seconds: list[float] = []

    def __call__(self, *tractions):
        start = time.perf_counter()
        values = self.tracker(*tractions)
        self.seconds.append(time.perf_counter() - start)
        return values


def run(n: int, mu: float, cycles: int) -> dict:
    material = paper_material()
    grid = Grid.square(n, 1.05 * RADIUS)
    solver = ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(mu, mu), tol=1e-6)
    stress = SubsurfaceStress(grid, material.nu_A, depth_layers(DEPTH * RADIUS, LAYERS))
    probe = TimedProbe(PeakTracker(stress, RADIUS))
    settings = CyclicSettings(LOAD, 10, cycles, record=())
    start = time.perf_counter()
    result = CyclicAnalysis(solver, WearLaw(WEAR, WEAR), settings, peak_probe=probe).run()
    elapsed = time.perf_counter() - start
    simulated = len(result.history["cycle"])
    probe_total = float(np.sum(probe.seconds))
    cycle_cost = (elapsed - probe_total) / simulated
    steady = float(np.mean(probe.seconds[1:])) if simulated > 1 else float("nan")
    return dict(
        n=n,
        simulated=simulated,
        cycle=cycle_cost,
        first=probe.seconds[0],
        steady=steady,
        ratio=steady / cycle_cost,
        amortised=probe_total / simulated / cycle_cost,
        cache_mb=stress.kernel_cache_bytes / 1e6,
        converged=result.converged,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[32, 64])
    parser.add_argument("--mu", type=float, default=0.1)
    parser.add_argument("--cycles", type=int, default=10000)
    args = parser.parse_args()
    print(
        f"{'n':>4} {'sim cycles':>10} {'cycle s':>8} {'probe 1st s':>11} {'probe s':>8} "
        f"{'probe/cycle':>11} {'incl. 1st':>9} {'cache MB':>8} converged"
    )
    for n in args.sizes:
        row = run(n, args.mu, args.cycles)
        print(
            f"{row['n']:>4} {row['simulated']:>10} {row['cycle']:8.3f} {row['first']:11.3f} "
            f"{row['steady']:8.4f} {row['ratio']:11.1%} {row['amortised']:9.1%} "
            f"{row['cache_mb']:8.1f} {row['converged']}",
            flush=True,
        )
    print("target: probe/cycle <= 15 %")


if __name__ == "__main__":
    main()
