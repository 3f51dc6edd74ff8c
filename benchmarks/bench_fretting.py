"""Fretting benchmark: operator applications per increment and a 10⁵-cycle case.

1. Operator applications (FFT matvecs) per increment at 128², side by side in one run:
   - cyclic: today's frictional cyclic increment (Section 7.2: flat punch a0 = 1.8 mm,
     P = 750 N, μ = 0.1, i = 1.33e-7 1/MPa, paper materials, 10 increments per half cycle,
     tol 1e-6, warm start "previous_cycle"), ``--cycles`` real cycles;
   - fretting: a partial-slip tangential fretting increment (sphere R = 10 mm on steel, same
     materials so K = 0, P = 100 N, μ = 0.5, displacement amplitude 0.5 δ_slip (Mindlin),
     i = 1e-7 1/MPa, 10 increments per quarter cycle, tol 1e-6), the same real cycles.
   Both counts include everything the run did (normal loading and first quarter of the
   fretting case, first load cycle of the cyclic case) divided by the increments solved;
   the fretting count of the cycles alone (after the first quarter) is printed too, and the
   same case under force control (Q* = 0.646 μP, the Mindlin force of 0.5 δ_slip).
2. Wall time of a 64² sphere fretting case to 10⁵ cycles (partial slip as above, 5 increments
   per quarter cycle, cycle jumping with the default max_wear_fraction 0.004) — target
   < 2 minutes.

One core (OMP/OpenBLAS threads = 1, FFTW threads = 1). The CPU time (``process_time``) is
printed beside the wall time of part 2: on a shared machine it is the steadier of the two.
Run:  OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_fretting.py [--cycles 10]
Takes ~2–4 minutes here.
"""

from __future__ import annotations

import argparse
import math
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

E, NU, RADIUS, LOAD, MU = 200e3, 0.3, 10.0, 100.0, 0.5


def cyclic_case(n: int, cycles: int) -> dict:
    from engine.geometry import FlatPunch
    from engine.grid import Grid
    from engine.material import paper_material
    from engine.solvers.contact import ContactSolver
    from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
    from engine.solvers.friction import FrictionLaw, WearLaw

    grid = Grid.square(n, 1.05 * 1.8)
    solver = ContactSolver(grid, paper_material(), FlatPunch(1.8), FrictionLaw(0.1, 0.1), tol=1e-6)
    settings = CyclicSettings(750.0, 10, cycles, record=(cycles,))
    start = time.perf_counter()
    result = CyclicAnalysis(solver, WearLaw(1.33e-7, 1.33e-7), settings).run()
    return {
        "matvecs": result.matvecs,
        "increments": result.load_steps,
        "simulated": len(result.history["cycle"]),
        "seconds": time.perf_counter() - start,
        "converged": result.converged,
    }


def fretting_case(n: int, cycles: int, steps: int, force: bool = False) -> dict:
    from engine.geometry import SphericalPunch
    from engine.grid import Grid
    from engine.material import MaterialPair
    from engine.reference.hertz import hertz_contact_radius
    from engine.solvers.contact import ContactSolver
    from engine.solvers.fretting import FrettingAnalysis, FrettingSettings
    from engine.solvers.friction import FrictionLaw, WearLaw

    contact_modulus = E / (2.0 * (1.0 - NU**2))
    radius = hertz_contact_radius(LOAD, RADIUS, contact_modulus)
    shear = E / (2.0 * (1.0 + NU))
    slip = 3.0 * MU * LOAD / (16.0 * radius) * 2.0 * (2.0 - NU) / shear  # Mindlin δ_slip
    grid = Grid.square(n, 1.5 * radius)
    material = MaterialPair(E, NU, E, NU)
    solver = ContactSolver(grid, material, SphericalPunch(RADIUS), FrictionLaw(MU, MU), tol=1e-6)
    # Partial slip: δ* = 0.5 δ_slip, or under force control its Mindlin force Q* = 0.646 μP.
    signal = {"force_amplitude": 0.646 * MU * LOAD} if force else {"amplitude": 0.5 * slip}
    settings = FrettingSettings(LOAD, steps, cycles, record=(cycles,), **signal)
    analysis = FrettingAnalysis(solver, WearLaw(1e-7, 1e-7), settings)
    start, cpu = time.perf_counter(), time.process_time()
    state = analysis.initial_state()
    before = (state.matvecs, state.load_steps)
    result = analysis.run(state=state)
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    history = result.history
    return {
        "matvecs": result.matvecs,
        "increments": result.load_steps,
        "cycle_matvecs": result.matvecs - before[0],
        "cycle_increments": result.load_steps - before[1],
        "simulated": len(history["cycle"]),
        "seconds": seconds,
        "cpu": cpu,
        "converged": result.converged,
        "regime": history["slip_regime"][-1],
        "energy": history["energy"][-1],
        "wear_volume": history["wear_volume"][-1],
        "max_wear_depth": history["max_wear_depth"][-1],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=10, help="real cycles of part 1")
    parser.add_argument("--size", type=int, default=128, help="mesh of part 1")
    parser.add_argument("--long-size", type=int, default=64, help="mesh of part 2")
    parser.add_argument("--long-cycles", type=int, default=100000, help="cycles of part 2")
    args = parser.parse_args()

    cyclic = cyclic_case(args.size, args.cycles)
    fretting = fretting_case(args.size, args.cycles, 10)
    forced = fretting_case(args.size, args.cycles, 10, force=True)
    per_cyclic = cyclic["matvecs"] / cyclic["increments"]
    per_fretting = fretting["matvecs"] / fretting["increments"]
    per_cycle_only = fretting["cycle_matvecs"] / fretting["cycle_increments"]
    print(f"1. operator applications per increment, {args.size}², {args.cycles} real cycles")
    print(f"{'case':>30} {'increments':>10} {'matvecs':>9} {'per incr.':>9} {'time s':>7}")
    print(
        f"{'cyclic frictional (7.2)':>30} {cyclic['increments']:>10} {cyclic['matvecs']:>9} "
        f"{per_cyclic:>9.1f} {cyclic['seconds']:>7.1f}"
    )
    print(
        f"{'fretting partial slip, all':>30} {fretting['increments']:>10} "
        f"{fretting['matvecs']:>9} {per_fretting:>9.1f} {fretting['seconds']:>7.1f}"
    )
    print(
        f"{'fretting, cycles only':>30} {fretting['cycle_increments']:>10} "
        f"{fretting['cycle_matvecs']:>9} {per_cycle_only:>9.1f}"
    )
    print(
        f"{'fretting, force control, all':>30} {forced['increments']:>10} "
        f"{forced['matvecs']:>9} {forced['matvecs'] / forced['increments']:>9.1f} "
        f"{forced['seconds']:>7.1f}"
    )
    print(
        f"{'force control, cycles only':>30} {forced['cycle_increments']:>10} "
        f"{forced['cycle_matvecs']:>9} {forced['cycle_matvecs'] / forced['cycle_increments']:>9.1f}"
    )
    print(
        f"ratio fretting/cyclic per increment: {per_fretting / per_cyclic:.2f} (all), "
        f"{per_cycle_only / per_cyclic:.2f} (cycles only); target <= 1"
    )
    long = fretting_case(args.long_size, args.long_cycles, 5)
    regime = "gross" if long["regime"] == 1 else "partial"
    print(
        f"2. {args.long_size}² sphere fretting to {args.long_cycles:,} cycles: "
        f"{long['seconds']:.1f} s wall, {long['cpu']:.1f} s CPU "
        f"({long['simulated']} simulated cycles, "
        f"{long['increments']} increments, {long['matvecs']} matvecs, {regime} slip, "
        f"energy {long['energy']:.4g} mJ/cycle, wear volume {long['wear_volume']:.4g} mm³, "
        f"max depth {long['max_wear_depth'] * 1e3:.4g} µm, converged {long['converged']}); "
        f"target < 120 s"
    )
    if not math.isfinite(long["seconds"]):
        raise SystemExit(1)


if __name__ == "__main__":
    main()
