"""Mesh convergence of the punch profiles: rounded punch vs sharp flat punch vs
an independent axisymmetric reference, and the sphere vs Hertz.

Rounded punch: flat face b = 1 mm, toroidal edge ρ = 1 mm, E* = 1 MPa (identical materials,
ν = 0.3, so K = 0), P chosen so that the contact radius is a = 1.2 b by the Sneddon integrals
of ``engine.reference.axisymmetric`` (no grid). The grid's half width is 1.3 b, so the edge
zone a − b spans 5, 10 and 20 elements at 64², 128², 256². For each n the table gives the
approach, the peak pressure, the pressure error for r ≤ 0.8 b, all against the reference, and
σ_VM in the surface layer (z = 0.01 of the first graded layer) and below it, with the
differences between successive meshes. The sharp flat punch at the same load is printed
beside it: its edge values grow without bound.

With the paper's numbers (P = 750 N, b = 1.8 mm, E_B = 100 E_A = 20 000 GPa) the edge zone is
far smaller, a fraction of the element at 256², so the 256² solution of the rounded punch is
still that of a flat punch: the third table gives the reference's a − b and edge pressure
for ρ = 0.05 and 0.1 a0 (see docs/explanation/profiles.md).

Sphere: R = 10 mm, P = 750 N, paper materials, half width 1.5 a_Hertz, frictionless; contact
radius (from the contact area), approach, peak pressure and the axis σ_VM maximum (value,
depth) against ``engine.reference.hertz``.

About 3 min here (one core, machine shared). Run:

    . .venv/bin/activate && python benchmarks/profile_convergence.py [--sizes 64 128 256]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from engine.geometry import FlatPunch, RoundedPunch, SphericalPunch
from engine.grid import Grid
from engine.material import MaterialPair
from engine.reference import hertz
from engine.reference.axisymmetric import rounded_punch_contact
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw
from engine.solvers.subsurface import SubsurfaceStress, depth_layers

FACE, EDGE, CONTACT, HALF_WIDTH, NU = 1.0, 1.0, 1.2, 1.3, 0.3
UNIT_CONTACT_MODULUS = MaterialPair(2.0 * (1.0 - NU**2), NU, 2.0 * (1.0 - NU**2), NU)  # E* = 1

REPO = Path(__file__).resolve().parents[1]


def solve(grid, material, profile, load, tol=1e-10):
    solver = ContactSolver(
        grid, material, profile, FrictionLaw(0.0, 0.0, 0.0), tol=tol,
        planner_effort="FFTW_ESTIMATE",
    )  # fmt: skip
    return solver.solve_load(load)


def edge_stress(grid, result, depth):
    """(σ_VM max in the surface layer, σ_VM max below it) in the x–z plane (MPa)."""
    depths = depth_layers(depth, 16)
    plane = SubsurfaceStress(grid, NU, depths).plane(result.pressure)
    return plane.peak().value, plane.peak(depths[1]).value


def emit(lines: list[str], text: str) -> None:
    """Print ``text``; keep the rows of a Markdown table (without the timing suffix)."""
    print(text, flush=True)
    if text.startswith("|"):
        lines.append(text.split("  (", 1)[0])


def rounded_table(sizes) -> str:
    """The rounded punch against its reference at each size; returns the Markdown table."""
    lines: list[str] = []
    reference = rounded_punch_contact(FACE, EDGE, UNIT_CONTACT_MODULUS.contact_modulus)
    load = reference.load(CONTACT * FACE)
    radius = reference.contact_radius(load)
    approach = reference.approach(radius)
    samples = np.linspace(0.95 * FACE, radius, 400)
    pressures = reference.pressures(samples, radius)
    peak = float(pressures.max())
    emit(
        lines,
        f"rounded punch b = {FACE}, rho = {EDGE}, E* = 1, P = {load:.6g}: reference a/b = "
        f"{radius / FACE:.4f}, approach {approach:.6g}, p_max {peak:.6g} at r/b = "
        f"{samples[pressures.argmax()]:.4f}",
    )
    emit(
        lines,
        "| n | approach err | p_max err | p err r<=0.8b (of p(0)) | σ_VM surface | Δ | "
        "σ_VM below | Δ | flat punch σ_VM surface | Δ |",
    )
    emit(lines, "|---|---|---|---|---|---|---|---|---|---|")
    previous = None
    for n in sizes:
        start = time.perf_counter()
        grid = Grid.square(n, HALF_WIDTH * FACE)
        result = solve(grid, UNIT_CONTACT_MODULUS, RoundedPunch(FACE, EDGE), load)
        r = grid.radius()
        inside = r <= 0.8 * FACE
        radii = np.linspace(0.0, 0.8 * FACE, 81)
        exact = np.interp(r[inside], radii, reference.pressures(radii, radius))
        error = np.max(np.abs(result.pressure[inside] - exact)) / reference.pressure(0, radius)
        surface, below = edge_stress(grid, result, 1.5 * FACE)
        flat = solve(grid, UNIT_CONTACT_MODULUS, FlatPunch(FACE), load)
        flat_surface, _ = edge_stress(grid, flat, 1.5 * FACE)
        row = (surface, below, flat_surface)
        deltas = (
            ["–"] * 3
            if previous is None
            else [f"{(value / old - 1.0):+.3f}" for value, old in zip(row, previous, strict=True)]
        )
        previous = row
        emit(
            lines,
            f"| {n} | {result.approach / approach - 1:+.4f} | "
            f"{result.pressure.max() / peak - 1:+.4f} | {error:.4f} | {surface:.4f} | "
            f"{deltas[0]} | {below:.4f} | {deltas[1]} | {flat_surface:.4f} | {deltas[2]} |"
            f"  ({time.perf_counter() - start:.0f} s)",
        )
    return "\n".join(lines) + "\n"


PAPER_FACE, PAPER_LOAD, PAPER_EDGES = 1.8, 750.0, (0.05, 0.1)  # mm, N, ρ/a0


def paper_edge_table(mesh_sizes=(256,)) -> str:
    """The rounded punch at the paper's load (b = a0 = 1.8 mm, P = 750 N, the paper's pair)
    from the axisymmetric reference alone: the contact radius a beyond the face, the edge
    pressure's maximum (p0 = P/(π a0²)), the element width of the study's mesh (half width
    1.05 (a0 + ρ)) at each of ``mesh_sizes`` and the n whose element is a − b wide.
    Returns the Markdown table."""
    lines: list[str] = []
    modulus = MaterialPair(200000.0, NU, 2.0e7, NU).contact_modulus
    p0 = PAPER_LOAD / (math.pi * PAPER_FACE**2)
    elements = " | ".join(f"element at {n}² (µm)" for n in mesh_sizes)
    emit(lines, f"| ρ/a0 | a/b − 1 | a − b (µm) | p_max/p0 | p_max (GPa) | {elements} | "
                "n for one element across a − b |")  # fmt: skip
    emit(lines, "|" + "---|" * (6 + len(mesh_sizes)))
    for fraction in PAPER_EDGES:
        start = time.perf_counter()
        edge = fraction * PAPER_FACE
        reference = rounded_punch_contact(PAPER_FACE, edge, modulus)
        radius = reference.contact_radius(PAPER_LOAD)
        zone = radius - PAPER_FACE
        samples = np.linspace(PAPER_FACE - zone, radius, 400)  # the edge zone, 200 points
        peak = float(reference.pressures(samples, radius).max())
        length = 2.0 * 1.05 * (PAPER_FACE + edge)
        widths = " | ".join(f"{length / n * 1e3:.1f}" for n in mesh_sizes)
        emit(
            lines,
            f"| {fraction:g} | {radius / PAPER_FACE - 1:.5f} | {zone * 1e3:.2f} | "
            f"{peak / p0:.1f} | {peak * 1e-3:.2f} | {widths} | {length / zone:,.0f} |"
            f"  ({time.perf_counter() - start:.0f} s)",
        )
    return "\n".join(lines) + "\n"


def sphere_table(sizes) -> str:
    """The sphere against Hertz at each size; returns the Markdown table."""
    lines: list[str] = []
    material = MaterialPair(200000.0, NU, 2.0e7, NU)
    radius, load = 10.0, 750.0
    modulus = material.contact_modulus
    a = hertz.hertz_contact_radius(load, radius, modulus)
    p_max = hertz.hertz_peak_pressure(load, radius, modulus)
    approach = hertz.hertz_approach(load, radius, modulus)
    vm, depth = hertz.axis_von_mises_peak(NU)
    emit(
        lines,
        f"\nsphere R = {radius} mm, P = {load} N: Hertz a = {a:.5f} mm, p_max = {p_max:.2f} MPa",
    )
    emit(lines, "| n | a err | approach err | p_max err | axis σ_VM max err | its depth err |")
    emit(lines, "|---|---|---|---|---|---|")
    for n in sizes:
        grid = Grid.square(n, 1.5 * a)
        result = solve(grid, material, SphericalPunch(radius), load)
        contact = math.sqrt(result.contact_area(grid.element_area) / math.pi)
        depths = np.linspace(0.3 * a, 0.7 * a, 161)
        plane = SubsurfaceStress(grid, NU, depths).plane(result.pressure)
        column = plane.von_mises[int(np.argmin(np.abs(plane.x[:, 0])))]
        k = int(np.argmax(column))
        emit(
            lines,
            f"| {n} | {contact / a - 1:+.4f} | {result.approach / approach - 1:+.5f} | "
            f"{result.pressure.max() / p_max - 1:+.4f} | {column[k] / p_max / vm - 1:+.5f} | "
            f"{depths[k] / a / depth - 1:+.4f} |",
        )
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256])
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write both tables into docs/explanation/profiles.md (profile-convergence)",
    )  # fmt: skip
    args = parser.parse_args()
    rounded = rounded_table(args.sizes)
    sphere = sphere_table(args.sizes)
    paper = paper_edge_table()
    if args.update_docs:
        from engine.analysis.markdown import measured_on, replace_block

        document = REPO / "docs" / "explanation" / "profiles.md"
        note = "`python benchmarks/profile_convergence.py --update-docs`, one core"
        text = f"{measured_on(note)}\nRounded punch against its reference:\n\n{rounded}\n"
        text += f"Sphere against Hertz:\n\n{sphere}\n"
        text += f"The paper's punch with a rounded edge (reference only, P = 750 N):\n\n{paper}"
        replace_block(document, "profile-convergence", text)
        print(f"{document}: wrote the block profile-convergence")


if __name__ == "__main__":
    main()
