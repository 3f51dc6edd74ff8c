"""Fatigue criteria benchmark: the four criteria on a recorded cycle against the case's own
run time, side by side in one run, one core.

1. 3-D: sphere R = 10 mm on steel (E = 200 GPa, ν = 0.3 both bodies), P = 100 N, μ = 0.5,
   force-controlled partial slip Q* = 0.646 μP, 20 increments per quarter cycle (80 instants
   per cycle), 128² elements over ±1.5 a, one simulated cycle recorded. Fatigue: the x–z
   plane through the axis (129 points along x × 40 depth layers to 1.5 a) for all 80
   increments, then Crossland, Dang Van, SWT and Fatemi–Socie (1° planes) with the point
   method.
2. 2-D: cylinder R = 6 mm on a steel flat, P = 185 N/mm, μ = 0.9, 1,024 elements over
   ±0.3 mm, displacement amplitude ±3 µm, 4 increments per quarter cycle, to ``--cycles``
   cycles (default 10⁵, cycle jumping) with the last cycle recorded; fatigue on its whole
   x–z plane (1,024 × 40 depths to 0.15 mm, 16 instants).

Prints the CPU times (``process_time``) and the ratio fatigue / case for each, repeated
``--repeat`` times (the median is the figure).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_fatigue.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

CONSTANTS = {
    "sigma_d": 300.0, "tau_d": 200.0,
    "sigma_f": 1000.0, "b": -0.09, "eps_f": 0.6, "c": -0.6,
    "tau_f": 600.0, "gamma_f": 0.9, "b0": -0.09, "c0": -0.6, "k": 0.6, "sigma_y": 800.0,
}  # fmt: skip


def _fatigue(stress, grid, increments, poisson, length, point_stress) -> float:
    from engine import fatigue
    from engine.fatigue.fields import plane_history

    start = time.process_time()
    history = plane_history(stress, increments)
    criteria = fatigue.build_criteria(
        list(fatigue.CRITERIA), CONSTANTS, fatigue.Elasticity(200e3, poisson)
    )
    fatigue.assess(history, criteria, method="point", length=length, stress_at=point_stress)
    return time.process_time() - start


def three_dimensional() -> dict:
    from engine.fatigue.fields import CycleRecorder, PlanePointStress
    from engine.geometry import SphericalPunch
    from engine.grid import Grid
    from engine.material import MaterialPair
    from engine.reference.hertz import hertz_contact_radius
    from engine.solvers.contact import ContactSolver
    from engine.solvers.fretting import FrettingAnalysis, FrettingSettings
    from engine.solvers.friction import FrictionLaw, WearLaw
    from engine.solvers.subsurface import SubsurfaceStress

    material = MaterialPair(200e3, 0.3, 200e3, 0.3)
    radius = hertz_contact_radius(100.0, 10.0, material.contact_modulus)
    grid = Grid.square(128, 1.5 * radius)
    solver = ContactSolver(grid, material, SphericalPunch(10.0), FrictionLaw(0.5, 0.5), tol=1e-6)
    settings = FrettingSettings(100.0, 20, 1, record=(1,), force_amplitude=0.646 * 0.5 * 100.0)
    recorder = CycleRecorder()

    def probe(pressure, traction_x, traction_y):
        recorder.add(pressure, traction_x, traction_y)
        return (0.0,)

    start = time.process_time()
    result = FrettingAnalysis(solver, WearLaw(1e-7, 1e-7), settings, increment_probe=probe).run()
    case = time.process_time() - start
    increments = recorder.take()
    stress = SubsurfaceStress(grid, 0.3, np.linspace(1.5 * radius / 40, 1.5 * radius, 40))
    point = PlanePointStress(grid, 0.3, increments)
    spent = _fatigue(stress, grid, increments, 0.3, 0.1 * radius, point)
    return {"case_s": case, "fatigue_s": spent, "instants": len(increments), "ok": result.converged}


def two_dimensional(cycles: int) -> dict:
    from engine.fatigue.fields import CycleRecorder, LinePointStress
    from engine.geometry import CylinderProfile
    from engine.grid import Grid
    from engine.kernels.line import line_operator
    from engine.material import MaterialPair
    from engine.solvers.contact import ContactSolver
    from engine.solvers.fretting import FrettingAnalysis, FrettingSettings
    from engine.solvers.friction import FrictionLaw, WearLaw
    from engine.solvers.line_subsurface import LineSubsurfaceStress

    steel = MaterialPair(200e3, 0.3, 200e3, 0.3)
    grid = Grid.line(1024, 0.3)
    solver = ContactSolver(
        grid, steel, CylinderProfile(6.0), FrictionLaw(0.9, 0.9),
        operator=line_operator(grid, steel, 10.0),
    )  # fmt: skip
    settings = FrettingSettings(load=185.0, steps=4, cycles=cycles, amplitude=3e-3, record=())
    recorder = CycleRecorder()

    def probe(pressure, traction_x, traction_y):
        recorder.add(pressure, traction_x, traction_y)
        return (0.0,)

    start = time.process_time()
    analysis = FrettingAnalysis(solver, WearLaw(2.75e-8, 2.75e-8), settings, increment_probe=probe)
    result = analysis.run()
    case = time.process_time() - start
    increments = recorder.take()[-16:]
    stress = LineSubsurfaceStress(grid, 0.3, np.linspace(0.15 / 40, 0.15, 40))
    point = LinePointStress(grid, 0.3, increments)
    spent = _fatigue(stress, grid, increments, 0.3, 0.01, point)
    return {"case_s": case, "fatigue_s": spent, "instants": len(increments), "ok": result.converged}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cycles", type=int, default=100_000)
    args = parser.parse_args()
    for label, run in (("3-D", three_dimensional), ("2-D", lambda: two_dimensional(args.cycles))):
        runs = [run() for _ in range(args.repeat)]
        ratios = [r["fatigue_s"] / r["case_s"] for r in runs]
        print(
            f"{label}: case {statistics.median(r['case_s'] for r in runs):.2f} s CPU, fatigue "
            f"{statistics.median(r['fatigue_s'] for r in runs):.2f} s CPU ({runs[0]['instants']}"
            f" instants), ratio {statistics.median(ratios):.3f} (runs: "
            + ", ".join(f"{x:.3f}" for x in ratios)
            + f"), converged {all(r['ok'] for r in runs)}"
        )


if __name__ == "__main__":
    main()
