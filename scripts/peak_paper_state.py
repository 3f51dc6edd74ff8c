"""The worn state at which the deep σ_VM peak reaches the paper's place.

Runs the Section 7.2 case μ = 0.1 (flat punch a0 = 1.8 mm, P = 750 N, 10 increments per half
cycle, default cycle jumping, subsurface as studies/peak_regime.toml) with a wear coefficient
(default 1.33e-6 1/MPa, ten times the paper's; only i·N matters for the worn shape,
see docs/explanation/peak-regime.md) until the first simulated cycle whose deep peak
(z >= 0.1 a0) is on the
axis (|x| <= one element) at z/a0 in [0.6, 0.8]. Prints that row of the peak history and,
for the same peak-load tractions, the maxima of σ_VM

- on the x–z plane through the axis (the engine's plane; its points lie on element edges of
  an even mesh, where piecewise-constant shear tractions make the surface layer grid
  dependent), and
- on the block of element centres (every depth), which avoids those edge lines;
- on the axis at 141 depths between 0.3 a0 and 1.0 a0 (the studies' layers are 0.06 a0
  apart there), to place the deep peak finer than the layers do.

With ``--update-docs`` the printed lines (and the state's i·N over the paper's,
1.33e-7 1/MPa × 10⁵ cycles) go into the block ``peak-paper-state-<n>`` of
docs/explanation/peak-regime.md. They are figures of a deterministic computation: the load
of the machine does not change them.

Run:  python scripts/peak_paper_state.py [--n 32] [--wear 1.33e-6] [--update-docs]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.reference.flat_punch import mean_pressure
from engine.solvers.contact import ContactSolver
from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
from engine.solvers.friction import FrictionLaw, WearLaw
from engine.solvers.peak import PeakTracker, region_name
from engine.solvers.subsurface import SubsurfaceStress, depth_layers

RADIUS, LOAD, MU, DEPTH, LAYERS = 1.8, 750.0, 0.1, 1.5, 31
BAND = (0.6, 0.8)
PAPER_WEAR, PAPER_CYCLES = 1.33e-7, 100000  # 1/MPa, the paper's coefficient and cycles
REPO = Path(__file__).resolve().parent.parent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=32)
    parser.add_argument("--wear", type=float, default=1.33e-6)
    parser.add_argument("--cycles", type=int, default=100000)
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the lines into docs/explanation/peak-regime.md (peak-paper-state-<n>)",
    )  # fmt: skip
    args = parser.parse_args()
    lines: list[str] = []

    def say(text: str) -> None:
        print(text, flush=True)
        lines.append(text.strip())

    material = paper_material()
    grid = Grid.square(args.n, 1.05 * RADIUS)
    solver = ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(MU, MU))
    stress = SubsurfaceStress(grid, material.nu_A, depth_layers(DEPTH * RADIUS, LAYERS))
    tracker = PeakTracker(stress, RADIUS)
    settings = CyclicSettings(LOAD, 10, args.cycles, record=())
    analysis = CyclicAnalysis(solver, WearLaw(args.wear, args.wear), settings, tracker)
    state = analysis.initial_state()

    def reached() -> bool:
        history = state.history
        if not history.get("vm_deep_max_z"):
            return False
        on_axis = abs(history["vm_deep_max_x"][-1]) <= grid.dx
        depth = history["vm_deep_max_z"][-1] / RADIUS
        return on_axis and BAND[0] <= depth <= BAND[1]

    start = time.perf_counter()
    result = analysis.run(state=state, should_stop=reached)
    elapsed = time.perf_counter() - start
    history, p0 = result.history, mean_pressure(LOAD, RADIUS)
    row = len(history["cycle"]) - 1
    print(f"{args.n}² mesh, μ = {MU}, i = {args.wear:g} 1/MPa, {elapsed:.0f} s")
    say(f"{args.n}² mesh, μ = {MU}, i = {args.wear:g} 1/MPa")
    if not reached():
        say(f"the deep peak never reached the axis at z/a0 in {BAND} by N = {args.cycles}")
        _write(args, lines)
        return
    cycle, wear = history["cycle"][row], history["max_wear_depth"][row]
    first_approach, approach = history["approach"][0], history["approach"][row]
    say(
        f"first row: N = {int(cycle):,} (i·N = {args.wear * cycle:.3g} 1/MPa, "
        f"{args.wear * cycle / (PAPER_WEAR * PAPER_CYCLES):.1f} × the paper's "
        f"{PAPER_WEAR * PAPER_CYCLES:.4g}), max wear "
        f"{wear * 1e3:.4f} µm, δ0 = {first_approach * 1e3:.4f} µm, δ(N) = {approach * 1e3:.4f}"
        f" µm, ω/δ0 = {wear / first_approach:.3f}, ω/δ(N) = {wear / approach:.3f}"
    )
    for key in ("vm_max", "vm_sub_max", "vm_deep_max", "vm_axis_max", "centre_pressure",
                "peak_pressure"):  # fmt: skip
        say(f"  {key} {history[key][row] / p0:.3f} p0")
    say(
        f"  deep peak at x/a0 = {history['vm_deep_max_x'][row] / RADIUS:.3f}, "
        f"z/a0 = {history['vm_deep_max_z'][row] / RADIUS:.3f}; overall peak at x/a0 = "
        f"{history['vm_max_x'][row] / RADIUS:.3f}, z/a0 = {history['vm_max_z'][row] / RADIUS:.4f}"
        f" ({region_name(history['peak_region'][row])})"
    )
    final = result.final
    block = stress.block(final.pressure, final.traction_x, final.traction_y)
    for label, layers in (("all layers", slice(None)), ("below surface layer", slice(1, None))):
        values = block.von_mises[:, :, layers]
        index = np.unravel_index(np.argmax(values), values.shape)
        x, y = block.x[index[0], index[1], 0], block.y[index[0], index[1], 0]
        z = block.depths[layers][index[2]]
        say(
            f"  element-centre block, {label}: {values[index] / p0:.3f} p0 at "
            f"r/a0 = {math.hypot(x, y) / RADIUS:.3f}, z/a0 = {z / RADIUS:.4f}"
        )
    fine = SubsurfaceStress(grid, material.nu_A, np.linspace(0.3, 1.0, 141) * RADIUS)
    plane = fine.plane(final.pressure, final.traction_x, final.traction_y)
    column = int(np.argmin(np.abs(plane.x[:, 0])))
    deepest = int(np.argmax(plane.von_mises[column]))
    value, depth = plane.von_mises[column, deepest] / p0, plane.z[column, deepest] / RADIUS
    say(f"  axis profile, 141 depths z/a0 = 0.30-1.00: max {value:.3f} p0 at z/a0 = {depth:.3f}")
    profile = plane.von_mises[column] / p0
    at = [int(np.argmin(np.abs(plane.z[column] / RADIUS - z))) for z in (0.6, 0.7, 0.8)]
    say(
        "  on the axis at z/a0 = 0.6, 0.7, 0.8: "
        + ", ".join(f"{profile[k]:.3f}" for k in at)
        + f" p0 ({', '.join(f'{100 * (profile[k] / value - 1):+.1f} %' for k in at)} of the max)"
    )
    stick, contact = np.count_nonzero(final.status == 1), np.count_nonzero(final.status)
    say(f"  stick fraction of the contact {stick / contact:.3f}")
    _write(args, lines)


def _write(args, lines: list[str]) -> None:
    """The lines, as a list, into the page's block ``peak-paper-state-<n>``."""
    if not args.update_docs:
        return
    from engine import __version__
    from engine.analysis.markdown import measured_on, replace_block

    note = (
        f"`python scripts/peak_paper_state.py --n {args.n} --wear {args.wear:g} --update-docs`,"
        f" engine {__version__}: the first simulated cycle whose deep peak is on the axis at "
        f"z/a0 in [{BAND[0]}, {BAND[1]}] (deterministic: the load does not change the figures)"
    )
    document = REPO / "docs" / "explanation" / "peak-regime.md"
    block = f"peak-paper-state-{args.n}"
    replace_block(document, block, measured_on(note) + "\n" + "\n".join(f"- {x}" for x in lines))
    print(f"{document}: wrote the block {block}")


if __name__ == "__main__":
    main()
