"""Cost of the subsurface stress evaluation against the surface operator and a solve.

Computes, on the paper's 128² grid over the square of half width 1.05 a0 (a0 = 1.8 mm,
P = 714 N, ν = 0.3) with 40 graded depth layers down to 2 a0:

* one surface operator application: ``HalfSpaceOperator.apply`` (full 3×3 block, three
  forward and three inverse 256² FFTs) and ``apply_normal`` (pressure only); if
  ``engine.kernels.operator`` is missing, a zero-padded 256² FFT convolution stands in;
* the x–z plane through the axis and the full 3-D block, (a) "cold": first call on a new
  ``SubsurfaceStress`` (FFTW planning + kernel generation + evaluation) and (b) "warm":
  kernel spectra cached, i.e. the cost of every later call, for the frictionless tractions
  (pressure only) and for frictional ones (pressure + both shear tractions);
* one static frictional solve (μ = 0.3, load control) with ``ContactSolver`` when available,
  whose tractions are then the frictional input above (otherwise q = 0.3 p stands in).

Ratios are printed against one full operator application, measured in the same run. Warm
figures are the best of three runs; cold ones are single runs (FFTW wisdom gathered by the
first lattice makes later plans cheaper, so cold figures are upper bounds for a session).
About 30 s here (2 cores). Run:

    . .venv/bin/activate && python benchmarks/bench_subsurface.py [--threads N] [--no-solve]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from engine.grid import Grid
from engine.reference.flat_punch import sneddon_element_pressure
from engine.solvers.subsurface import SubsurfaceStress, depth_layers

A0, LOAD, NU = 1.8, 714.0, 0.3
LAYERS = 40


def best_time(function, repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def surface_operator(grid: Grid, threads: int):
    """(label, full application, normal application) closures on the padded grid."""
    try:
        from engine.kernels.operator import HalfSpaceOperator
        from engine.material import paper_material
    except ImportError:
        return stand_in_operator(grid, threads)
    operator = HalfSpaceOperator(grid, paper_material(), threads=threads)
    field = np.random.default_rng(0).random(grid.shape)
    return (
        "HalfSpaceOperator",
        lambda: operator.apply(field, field, field),
        lambda: operator.apply_normal(field),
    )


def stand_in_operator(grid: Grid, threads: int):
    import pyfftw

    shape = (2 * grid.n_x, 2 * grid.n_y)
    real = pyfftw.empty_aligned(shape, dtype="float64")
    spectrum = pyfftw.empty_aligned((shape[0], shape[1] // 2 + 1), dtype="complex128")
    forward = pyfftw.FFTW(real, spectrum, axes=(0, 1), threads=threads)
    inverse = pyfftw.FFTW(spectrum, real, axes=(0, 1), direction="FFTW_BACKWARD", threads=threads)
    kernel = spectrum.copy()
    field = np.random.default_rng(0).random(grid.shape)

    def convolve(count):
        for _ in range(count):
            real[...] = 0.0
            real[: grid.n_x, : grid.n_y] = field
            forward()
            spectrum[...] *= kernel
            inverse()

    return "padded 256² FFT convolution (stand-in)", lambda: convolve(3), lambda: convolve(1)


def frictional_solve(grid: Grid, threads: int, pressure: np.ndarray, maxiter: int):
    try:
        from engine.geometry import FlatPunch
        from engine.material import paper_material
        from engine.solvers.contact import ContactSolver
        from engine.solvers.friction import FrictionLaw
    except ImportError:
        return None, (pressure, 0.3 * pressure, 0.3 * pressure)
    solver = ContactSolver(
        grid,
        paper_material(),
        FlatPunch(A0),
        FrictionLaw(0.3, 0.3, 0.0),
        threads=threads,
        maxiter=maxiter,
    )
    start = time.perf_counter()
    result = solver.solve_load(LOAD)
    elapsed = time.perf_counter() - start
    report = result.report
    label = (
        f"{elapsed:.3f} s ({report.matvecs} operator applications, converged={report.converged})"
    )
    return (elapsed, label), (result.pressure, result.traction_x, result.traction_y)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument(
        "--no-solve", action="store_true", help="skip the frictional solve (q = 0.3 p instead)"
    )
    parser.add_argument(
        "--maxiter", type=int, default=3000, help="iteration cap of the frictional solve"
    )
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/performance.md (block bench-subsurface)",
    )  # fmt: skip
    arguments = parser.parse_args()
    threads = arguments.threads

    grid = Grid.square(128, 1.05 * A0)
    edges = -grid.half_width_x + grid.dx * np.arange(grid.n_x + 1)
    pressure = sneddon_element_pressure(edges, edges, LOAD, A0)
    depths = depth_layers(2.0 * A0, LAYERS)

    name, apply_full, apply_normal = surface_operator(grid, threads)
    apply_full()
    apply_normal()
    t_full = best_time(apply_full, 20)
    t_normal = best_time(apply_normal, 20)
    print(
        f"grid 128² (Δ = {grid.dx * 1e3:.1f} µm), {LAYERS} graded layers to 2 a0, "
        f"threads = {threads}"
    )
    print(
        f"surface operator [{name}]: full 3×3 {t_full * 1e3:.2f} ms, "
        f"normal only {t_normal * 1e3:.2f} ms"
    )

    if arguments.no_solve:
        solve, frictional = None, (pressure, 0.3 * pressure, 0.3 * pressure)
    else:
        solve, frictional = frictional_solve(grid, threads, pressure, arguments.maxiter)
    if solve is not None:
        print(f"static frictional solve (μ = 0.3): {solve[1]}")
    cases = {"frictionless": (pressure, None, None), "frictional": frictional}

    print(f"\n{'what':38s} {'cold (s)':>9s} {'warm (s)':>9s} {'warm/op':>8s} {'cache MB':>9s}")
    rows, table = {}, []
    for what in ("plane", "block"):
        for case, tractions in cases.items():
            start = time.perf_counter()
            stress = SubsurfaceStress(grid, NU, depths, threads=threads)
            getattr(stress, what)(*tractions)
            cold = time.perf_counter() - start
            warm = best_time(lambda s=stress, w=what, t=tractions: getattr(s, w)(*t))
            label = f"{'x–z plane' if what == 'plane' else '3-D block'}, {case}"
            rows[(what, case)] = warm
            megabytes = stress.kernel_cache_bytes / 1e6
            table.append(
                (label, f"{cold:.3f}", f"{warm:.3f}", f"{warm / t_full:.1f}", f"{megabytes:.0f}")
            )
            print(
                f"{label:38s} {cold:9.3f} {warm:9.3f} {warm / t_full:8.1f} "
                f"{stress.kernel_cache_bytes / 1e6:9.1f}"
            )
    if solve is not None:
        for case in cases:
            start = time.perf_counter()
            SubsurfaceStress(grid, NU, depths, threads=threads).plane(*cases[case])
            cold = time.perf_counter() - start
            print(
                f"x–z plane {case}: cold/solve = {cold / solve[0]:.2f}, "
                f"warm/solve = {rows[('plane', case)] / solve[0]:.3f} "
                f"(target: < 1)"
            )

    if arguments.update_docs:
        write_doc_table(table, t_full, solve, threads)


def write_doc_table(table, t_full: float, solve, threads: int) -> None:
    """The subsurface table of the manual's performance page (block ``bench-subsurface``)."""
    from pathlib import Path

    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    document = Path(__file__).resolve().parents[1] / "docs" / "explanation" / "performance.md"
    header = ("evaluation", "first call (s)", "kernels cached (s)",
              "cached ÷ one operator application", "kernel cache (MB)")  # fmt: skip
    note = f"`python benchmarks/bench_subsurface.py --update-docs`, {threads} thread(s); "
    note += f"one operator application {t_full * 1e3:.2f} ms"
    if solve is not None:
        note += f"; a static frictional solve (μ = 0.3) {solve[1]}"
    replace_block(
        document, "bench-subsurface", measured_on(note) + "\n" + markdown_table(header, table)
    )
    print(f"{document}: wrote the block bench-subsurface")


if __name__ == "__main__":
    main()
