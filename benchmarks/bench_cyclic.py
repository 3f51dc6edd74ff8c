"""Cyclic-wear benchmark (issue 3): one core, Section 7.2 settings.

Flat punch a0 = 1.8 mm, P = 750 N, i = 1.33e-7 1/MPa, paper materials; default cycle jumping
(10 increments per half cycle, wear per jump <= 0.004 of the elastic approach), tol 1e-6.
Prints, for μ = 0.1 at 64² and 128²: simulated cycles to reach 10⁵ real cycles, wall time per
simulated cycle, total wall time, operator applications per increment, and the wear reached.
Target: the 64² case under 2 minutes on one core.

Run:  OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_cyclic.py [--sizes 64 128]
Takes ~2 minutes for 64² and ~8 minutes more for 128² here.
"""

from __future__ import annotations

import argparse
import time

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.solvers.contact import ContactSolver
from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
from engine.solvers.friction import FrictionLaw, WearLaw

RADIUS, LOAD, WEAR = 1.8, 750.0, 1.33e-7


def run(n: int, mu: float, cycles: int) -> dict:
    grid = Grid.square(n, 1.05 * RADIUS)
    start = time.perf_counter()
    solver = ContactSolver(grid, paper_material(), FlatPunch(RADIUS), FrictionLaw(mu, mu), tol=1e-6)
    settings = CyclicSettings(LOAD, 10, cycles, record=(1000, 10000, 100000))
    result = CyclicAnalysis(solver, WearLaw(WEAR, WEAR), settings).run()
    elapsed = time.perf_counter() - start
    simulated = len(result.history["cycle"])
    return dict(
        n=n,
        mu=mu,
        time=elapsed,
        simulated=simulated,
        per_cycle=elapsed / simulated,
        per_increment=result.matvecs / result.load_steps,
        converged=result.converged,
        depth=result.history["max_wear_depth"][-1],
        volume=result.history["wear_volume"][-1],
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 128])
    parser.add_argument("--mu", type=float, default=0.1)
    parser.add_argument("--cycles", type=int, default=100000)
    args = parser.parse_args()
    print(
        f"{'n':>5} {'mu':>5} {'sim cycles':>10} {'s/cycle':>8} {'total s':>8} "
        f"{'matvecs/incr':>12} {'max wear um':>11} {'volume mm3':>10} converged"
    )
    for n in args.sizes:
        row = run(n, args.mu, args.cycles)
        print(
            f"{row['n']:>5} {row['mu']:>5} {row['simulated']:>10} {row['per_cycle']:8.2f} "
            f"{row['time']:8.1f} {row['per_increment']:12.0f} {row['depth'] * 1e3:11.4f} "
            f"{row['volume']:10.3e} {row['converged']}",
            flush=True,
        )


if __name__ == "__main__":
    main()
