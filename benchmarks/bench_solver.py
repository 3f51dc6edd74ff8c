"""Contact-solver benchmark: flat punch, tolerance 1e-8, one core.

For 64², 128², 256², 512² elements over the square of half-width 1.05 a0 (a0 = 1.8 mm,
P = 714 N, paper materials E_B = 100 E_A, ν = 0.3, K = 0.196), prints for the frictionless
solve (Polonsky–Keer CG) and for μ = 0.2 (alternating normal / tangential preconditioned CG):
wall time, iterations, operator applications, time / one operator application, and for
μ = 0.2 the operator applications of a warm-started increment (second half of a
two-increment static analysis), with those of FISTA on the same increment (the previous
method, kept for displacement control and as fallback) measured in the same run. At 256² Tamaas
2.9's PolonskyKeerRey (non-periodic "dcfft" operator, same grid and tolerance) is timed in
the same run when installed (`pip install tamaas==2.9.0`); accuracy is compared with the
solver-agnostic face residual (max − min of the face displacement) / approach.

Run:  OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_solver.py [--sizes 64 128 256 512]
Takes about 6 minutes here with 512² (the μ = 0.2 solves dominate).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.reference.flat_punch import sneddon_approach
from engine.solvers.contact import ContactSolver, with_friction
from engine.solvers.friction import FrictionLaw

RADIUS, LOAD, TOL = 1.8, 714.0, 1e-8


def time_operator(solver: ContactSolver, normal: bool, repeats: int = 20) -> float:
    field = np.ones(solver.grid.shape)
    apply = (
        (lambda: solver.operator.apply_normal(field))
        if normal
        else (lambda: solver.operator.apply(field, field, field))
    )
    apply()
    start = time.perf_counter()
    for _ in range(repeats):
        apply()
    solver.operator.applications -= repeats + 1
    return (time.perf_counter() - start) / repeats


def face_residual(solver: ContactSolver, result) -> float:
    """(max − min of the normal displacement over the contact) / approach: 0 when the face is
    exactly flat; the solver-agnostic accuracy figure also computed for Tamaas."""
    u = solver.operator.apply(result.traction_x, result.traction_y, result.pressure)[2]
    contact = result.pressure > 0
    return float(np.ptp(u[contact]) / result.approach)


def frictionless_solve(n: int, tol: float) -> dict:
    grid = Grid.square(n, 1.05 * RADIUS)
    solver = ContactSolver(
        grid, paper_material(), FlatPunch(RADIUS), FrictionLaw(0.0, 0.0), tol=tol
    )
    start = time.perf_counter()
    result = solver.solve_load(LOAD)
    elapsed = time.perf_counter() - start
    return dict(
        time=elapsed,
        iterations=result.report.iterations,
        face=face_residual(solver, result),
        tol=tol,
    )


def run_size(n: int) -> dict:
    material = paper_material()
    grid = Grid.square(n, 1.05 * RADIUS)
    solver = ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(0.0, 0.0), tol=TOL)
    row = {"n": n}
    t_normal = time_operator(solver, normal=True)
    start = time.perf_counter()
    result = solver.solve_load(LOAD)
    elapsed = time.perf_counter() - start
    row["frictionless"] = dict(
        tol=TOL,
        time=elapsed,
        iterations=result.report.iterations,
        matvecs=result.report.matvecs,
        ratio=elapsed / t_normal,
        converged=result.report.converged,
        approach_error=result.approach / sneddon_approach(LOAD, RADIUS, material.contact_modulus)
        - 1,
        face=face_residual(solver, result),
        op=t_normal,
    )
    frictional = with_friction(solver, FrictionLaw(0.2, 0.2))
    t_full = time_operator(frictional, normal=False)
    start = time.perf_counter()
    cold = frictional.solve_load(LOAD)
    elapsed = time.perf_counter() - start
    start = time.perf_counter()
    half = frictional.solve_load(0.5 * LOAD)
    warm = frictional.solve_load(LOAD, half.state)
    warm_time = time.perf_counter() - start
    fista = with_friction(solver, FrictionLaw(0.2, 0.2))
    fista.load_control_method = "projected_gradient"
    fista.lipschitz()  # FISTA's step estimate: once per grid, reused by every increment
    fista_warm = fista.solve_load(LOAD, fista.solve_load(0.5 * LOAD).state)
    row["mu=0.2"] = dict(
        fista_warm_matvecs=fista_warm.report.matvecs,
        time=elapsed,
        iterations=cold.report.iterations,
        matvecs=cold.report.matvecs,
        ratio=elapsed / t_full,
        converged=cold.report.converged and warm.report.converged,
        warm_matvecs=warm.report.matvecs,
        warm_time=warm_time,
        op=t_full,
    )
    return row


def run_tamaas(n: int) -> dict | None:
    sys.path.insert(0, str(Path(__file__).parent))
    try:
        from tamaas_reference import solve_flat_punch_tamaas
    except ImportError:
        return None
    try:
        best = None
        for _ in range(2):
            result = solve_flat_punch_tamaas(n, radius=RADIUS, load=LOAD, tol=TOL)
            if best is None or result["solve_time_s"] < best["solve_time_s"]:
                best = result
        return best
    except ImportError as error:
        print(f"(Tamaas not available: {error})")
        return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 512])
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/performance.md (block bench-solver)",
    )  # fmt: skip
    args = parser.parse_args()
    rows = [run_size(n) for n in args.sizes]
    if args.update_docs:
        write_doc_table(rows)
    print("\nfrictionless (Polonsky-Keer CG with spectral preconditioner), tol 1e-8")
    print(
        f"{'n':>5} {'time s':>8} {'iter':>5} {'matvecs':>8} {'t/op':>7} {'op ms':>7} "
        f"{'approach err':>12} {'face resid':>10}"
    )
    for row in rows:
        f = row["frictionless"]
        print(
            f"{row['n']:>5} {f['time']:8.3f} {f['iterations']:5d} {f['matvecs']:8d} "
            f"{f['ratio']:7.1f} {f['op'] * 1e3:7.2f} {f['approach_error']:12.2e} {f['face']:10.1e}"
        )
    print("\nmu = 0.2, K = 0.196 (alternating preconditioned CG), tol 1e-8")
    print(
        f"{'n':>5} {'time s':>8} {'iter':>5} {'matvecs':>8} {'t/op':>7} {'op ms':>7} "
        f"{'warm matvecs':>12} {'FISTA warm':>10}"
    )
    for row in rows:
        f = row["mu=0.2"]
        print(
            f"{row['n']:>5} {f['time']:8.3f} {f['iterations']:5d} {f['matvecs']:8d} "
            f"{f['ratio']:7.1f} {f['op'] * 1e3:7.2f} {f['warm_matvecs']:12d} "
            f"{f['fista_warm_matvecs']:10d}"
        )
    warm = {row["n"]: row["mu=0.2"]["warm_matvecs"] for row in rows}
    if 64 in warm and 512 in warm:
        print(
            f"\nwarm-started matvecs growth 64² -> 512²: {warm[512] / warm[64]:.2f}x "
            "(target <= 1.5x)"
        )
        fista = {row["n"]: row["mu=0.2"]["fista_warm_matvecs"] for row in rows}
        print(f"FISTA on the same increments: {fista[512] / fista[64]:.2f}x")
    if 256 in args.sizes:
        tamaas = run_tamaas(256)
        ours = next(r for r in rows if r["n"] == 256)["frictionless"]
        if tamaas is None:
            print("\nTamaas not installed: pip install tamaas==2.9.0 for the side-by-side figure")
        else:
            # Like for like: tighten our tolerance until our face residual is at most Tamaas's.
            tight = ours
            for tol in (1e-9, 1e-10, 1e-11):
                if tight["face"] <= tamaas["face_residual"]:
                    break
                tight = frictionless_solve(256, tol)
            print(
                f"\n256² frictionless, same run: Tamaas {tamaas['solve_time_s']:.3f} s "
                f"({tamaas['iterations']} iterations, face residual "
                f"{tamaas['face_residual']:.1e})"
            )
            for label, row in (("tol 1e-8", ours), (f"tol {tight['tol']:.0e}", tight)):
                print(
                    f"  ours at {label}: {row['time']:.3f} s ({row['iterations']} iterations, "
                    f"face residual {row['face']:.1e}); ratio ours/Tamaas = "
                    f"{row['time'] / tamaas['solve_time_s']:.3f}"
                )


def write_doc_table(rows: list[dict]) -> None:
    """The contact-solver table of the manual's performance page (block ``bench-solver``)."""
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    document = Path(__file__).resolve().parents[1] / "docs" / "explanation" / "performance.md"
    header = ("n", "frictionless: time (s)", "iterations", "operator applications", "t/op",
              "μ = 0.2: time (s)", "iterations", "operator applications",
              "warm-started", "FISTA warm-started")  # fmt: skip
    table = []
    for row in rows:
        free, friction = row["frictionless"], row["mu=0.2"]
        table.append((
            row["n"], f"{free['time']:.3f}", free["iterations"], free["matvecs"],
            f"{free['ratio']:.0f}", f"{friction['time']:.3f}", friction["iterations"],
            friction["matvecs"], friction["warm_matvecs"], friction["fista_warm_matvecs"],
        ))  # fmt: skip
    note = "`OMP_NUM_THREADS=1 python benchmarks/bench_solver.py --update-docs`, one core"
    text = measured_on(note) + "\n" + markdown_table(header, table)
    replace_block(document, "bench-solver", text)
    print(f"{document}: wrote the block bench-solver")


if __name__ == "__main__":
    main()
