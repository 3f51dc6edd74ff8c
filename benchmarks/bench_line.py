"""Line (plane-strain) fretting: CPU time of one 1,024-element case to 10⁵ cycles, one core.

The case: steel cylinder R = 6 mm on a steel flat (E = 200 GPa, ν = 0.3), P = 185 N/mm,
μ = 0.9, displacement amplitude ±3 µm (partial slip: the slip limit is about 5 µm with the
datum d = 10 mm), Archard 2.75e-8 1/MPa for each body, 4 increments per quarter cycle, the
default cycle jumping and the tolerance a fretting study uses (``CYCLIC_TOLERANCE``);
1,024 elements over ±0.3 mm. It prints the CPU time, the simulated
cycles, the operator applications and the ratio to the 10 s target, and the same for a
256-element case beside it (the mesh ratio).

    python benchmarks/bench_line.py            # both meshes
    python benchmarks/bench_line.py --n 1024   # one mesh
"""

from __future__ import annotations

import argparse
import time

from engine.grid import Grid
from engine.kernels.line import line_operator
from engine.line_profiles import CylinderProfile
from engine.material import MaterialPair
from engine.solvers.contact import ContactSolver
from engine.solvers.defaults import CYCLIC_TOLERANCE
from engine.solvers.fretting import FrettingAnalysis, FrettingSettings
from engine.solvers.friction import FrictionLaw, WearLaw
from engine.solvers.scar import scar_measures, two_body_wear_law

TARGET_S = 10.0


def run(n: int, cycles: int) -> dict[str, float]:
    steel = MaterialPair(200e3, 0.3, 200e3, 0.3)
    grid = Grid.line(n, 0.3)
    operator = line_operator(grid, steel, 10.0)
    solver = ContactSolver(
        grid,
        steel,
        CylinderProfile(6.0),
        FrictionLaw(0.9, 0.9),
        operator=operator,
        tol=CYCLIC_TOLERANCE,
    )
    settings = FrettingSettings(load=185.0, steps=4, cycles=cycles, amplitude=3e-3, record=())
    law = two_body_wear_law(WearLaw(2.75e-8, 2.75e-8), 1.0)
    start = time.process_time()
    result = FrettingAnalysis(solver, law, settings).run()
    cpu = time.process_time() - start
    scar = scar_measures(grid, result.state.wear, 1.0)
    return {
        "cpu_s": cpu,
        "simulated": len(result.history["cycle"]),
        "matvecs": result.matvecs,
        "converged": result.converged,
        "scar_depth_um": scar.scar_depth * 1e3,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, action="append", help="elements (default 1024, 256)")
    parser.add_argument("--cycles", type=int, default=100_000)
    args = parser.parse_args()
    meshes = args.n or [1024, 256]
    results = {n: run(n, args.cycles) for n in meshes}
    for n, values in results.items():
        print(
            f"n = {n:5d}: CPU {values['cpu_s']:.2f} s for {args.cycles} cycles "
            f"({values['simulated']} simulated, {values['matvecs']} operator applications, "
            f"converged {values['converged']}, scar depth {values['scar_depth_um']:.3f} µm); "
            f"ratio to the {TARGET_S:g} s target {values['cpu_s'] / TARGET_S:.2f}"
        )
    if len(results) > 1:
        first, second = meshes[0], meshes[1]
        ratio = results[first]["cpu_s"] / results[second]["cpu_s"]
        print(f"CPU ratio n = {first} / n = {second}: {ratio:.2f}")


if __name__ == "__main__":
    main()
