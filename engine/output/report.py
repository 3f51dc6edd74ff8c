"""Results tables of a study in Markdown: ``python -m engine report RESULTS.h5 [--cycles N …]``.

The tables of the README's Results section are printed by this command, never typed by hand.
Per case:

cyclic study   at each N (default: the recorded cycles): maximum wear depth (µm), wear volume
               (mm³), peak pressure p_max/p0, peak σ_VM/p0 over the x–z plane and its location
               (r/a0, z/a0), and the peak below the surface layer with its location;
static study   approach g_n (µm), stiffness ratio k_μ/k_0, stick fraction, the same σ_VM peaks.

Then a list of *measured facts* bearing on the paper's findings (Section 7): stick and
stiffness vs Mossakovskii, wear ordering in μ, peak locations, spread over β, where the
pressure peak sits relative to the tribological axes. They are measurements, not verdicts.
p0 = P/(π a0²) (Eq. 19); r = |x| on the plane y = 0; z into the half-space.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .reader import CaseResults, StressPlane, StudyResults, read_results

__all__ = ["study_report", "main", "INTERIOR_DEPTH"]

INTERIOR_DEPTH = 0.1  # z/a0 below which the surface edge singularity dominates the σ_VM peak


def _format_peak(study: StudyResults, peak: tuple[float, float, float]) -> tuple[str, str]:
    value, x, z = peak
    a = study.radius
    return f"{value / study.p0:.2f}", f"({abs(x) / a:.2f}, {z / a:.3f})"


def _plane_columns(study: StudyResults, plane: StressPlane | None) -> list[str]:
    if plane is None:
        return ["–"] * 4
    return [*_format_peak(study, plane.peak()), *_format_peak(study, plane.subsurface_peak())]


def _header(columns: list[str]) -> list[str]:
    return ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]


def _row(values: list[str]) -> str:
    return "| " + " | ".join(values) + " |"


_PEAK_COLUMNS = ["σ_VM/p0 max", "at (r/a0, z/a0)", "σ_VM/p0 below surface", "at (r/a0, z/a0)"]


def cyclic_table(study: StudyResults, cycles: Sequence[int] | None = None) -> list[str]:
    if cycles is None:
        cycles = sorted({n for case in study.cases for n in case.recorded_cycles})
    lines = _header(
        ["case", "N", "max wear depth (µm)", "wear volume (mm³)", "p_max/p0", *_PEAK_COLUMNS]
    )
    for case in study.cases:
        for cycle in cycles:
            depth = case.history_at("max_wear_depth", cycle) * 1e3
            volume = case.history_at("wear_volume", cycle)
            pressure = case.history_at("peak_pressure", cycle) / study.p0
            if math.isnan(depth):
                continue
            lines.append(
                _row(
                    [
                        case.label,
                        f"{cycle:,}",
                        f"{depth:.4g}",
                        f"{volume:.3e}",
                        f"{pressure:.2f}",
                        *_plane_columns(study, case.planes.get(cycle)),
                    ]
                )
            )
    return lines


def static_table(study: StudyResults) -> list[str]:
    from .figures import stiffness_ratios

    mu, ratios, limit, what = stiffness_ratios(study)
    ratio_of = dict(zip(mu.tolist(), ratios.tolist(), strict=True))
    lines = _header(["case", "g_n (µm)", "k_μ/k_0", "stick fraction", *_PEAK_COLUMNS])
    for case in sorted(study.cases, key=lambda case: case.mu1):
        ratio = ratio_of.get(case.mu1, float("nan")) if case.isotropic else float("nan")
        lines.append(
            _row(
                [
                    case.label,
                    f"{case.summary['approach'] * 1e3:.4f}",
                    f"{ratio:.5f}",
                    f"{case.summary['stick_fraction']:.3f}",
                    *_plane_columns(study, case.planes.get("final")),
                ]
            )
        )
    lines += ["", f"k = P/g_n at peak load; k_0: {what}; Mossakovskii artanh(β)/β = {limit:.5f}."]
    return lines


# ----------------------------------------------------------------------------- measured facts
def static_facts(study: StudyResults) -> list[str]:
    from engine.reference.flat_punch import sneddon_approach

    from .figures import stiffness_ratios

    mu, ratios, limit, _ = stiffness_ratios(study)
    facts = [
        f"stiffness ratio k_μ/k_0 = {ratios[-1]:.5f} at μ = {mu[-1]:g} vs Mossakovskii "
        f"{limit:.5f} (reached to {100 * (ratios[-1] - 1) / (limit - 1):.0f} % of the rise)"
    ]
    full = [case for case in study.cases if case.summary["stick_fraction"] >= 0.999]
    first = min((case.mu1 for case in full), default=None)
    facts.append(
        "full stick (stick fraction ≥ 0.999) first at μ = "
        + (f"{first:g}" if first is not None else "none of the cases")
        + "; stick fractions: "
        + ", ".join(
            f"μ={case.mu1:g}: {case.summary['stick_fraction']:.3f}"
            for case in sorted(study.cases, key=lambda case: case.mu1)
        )
    )
    for case in sorted(study.cases, key=lambda case: case.mu1):
        if case.mu1 > 0 and "final" in case.fields:
            facts.append(f"μ = {case.mu1:g}: {_slip_zone(study, case)}")
    frictionless = [case for case in study.cases if case.mu1 == 0.0]
    if frictionless:
        expected = sneddon_approach(study.load, study.radius, study.material.contact_modulus)
        computed = frictionless[0].summary["approach"]
        facts.append(
            f"frictionless approach {computed * 1e3:.4f} µm vs Sneddon P/(2E*a0) = "
            f"{expected * 1e3:.4f} µm ({100 * (computed / expected - 1):+.2f} %)"
        )
    return facts


def _slip_zone(study: StudyResults, case: CaseResults) -> str:
    """Where the slipping elements are (radii of their centres / a0) and how many rings."""
    status = case.fields["final"]["status"]
    X, Y = np.meshgrid(study.grid_x, study.grid_y, indexing="ij")
    radius = np.hypot(X, Y)[status == 2] / study.radius
    if radius.size == 0:
        return "no slipping element"
    element = (study.grid_x[1] - study.grid_x[0]) / study.radius
    width = (radius.max() - radius.min()) / element
    return (
        f"{radius.size} slipping elements at r/a0 = {radius.min():.3f} … {radius.max():.3f} "
        f"(slip annulus ≈ {width + 1:.1f} element widths)"
    )


def _pressure_peak_angle(study: StudyResults, case: CaseResults, cycle) -> tuple[float, float]:
    """(r/a0, polar angle in degrees within [0, 180)) of the pressure maximum."""
    pressure = case.fields[cycle]["pressure"]
    i, j = np.unravel_index(np.argmax(pressure), pressure.shape)
    x, y = study.grid_x[i], study.grid_y[j]
    return float(np.hypot(x, y) / study.radius), float(np.degrees(np.arctan2(y, x)) % 180.0)


def cyclic_facts(study: StudyResults) -> list[str]:
    facts = []
    cycles = sorted({n for case in study.cases for n in case.recorded_cycles})
    for cycle in cycles:
        cases = [case for case in study.cases if cycle in case.fields]
        depths = [case.history_at("max_wear_depth", cycle) for case in cases]
        volumes = [case.history_at("wear_volume", cycle) for case in cases]
        if study.isotropic and len(cases) > 1:
            order = np.argsort([case.mu1 for case in cases])
            decreasing = all(np.diff(np.asarray(depths)[order]) < 0) and all(
                np.diff(np.asarray(volumes)[order]) < 0
            )
            facts.append(
                f"N = {cycle:,}: wear depth and volume strictly decreasing with μ: "
                f"{'yes' if decreasing else 'no'}"
            )
        elif len(cases) > 1:
            spread_depth = (max(depths) - min(depths)) / max(np.mean(depths), 1e-300)
            spread_volume = (max(volumes) - min(volumes)) / max(np.mean(volumes), 1e-300)
            facts.append(
                f"N = {cycle:,}: spread over the cases (max − min)/mean: wear depth "
                f"{100 * spread_depth:.2f} %, wear volume {100 * spread_volume:.2f} %"
            )
    if cycles:
        last = cycles[-1]
        for case in study.cases:
            if last not in case.fields:
                continue
            plane = case.planes.get(last)
            if plane is not None:
                value, x, z = plane.peak(INTERIOR_DEPTH * study.radius)
                facts.append(
                    f"N = {last:,}, {case.label}: σ_VM peak at depth z/a0 >= {INTERIOR_DEPTH:g} "
                    f"(away from the edge singularity) {value / study.p0:.2f} p0 at "
                    f"r/a0 = {abs(x) / study.radius:.2f}, z/a0 = {z / study.radius:.3f}; "
                    "on the axis r = 0: {:.2f} p0 at z/a0 = {:.3f}".format(
                        plane.axis_peak()[0] / study.p0, plane.axis_peak()[2] / study.radius
                    )
                )
            radius, angle = _pressure_peak_angle(study, case, last)
            text = f"N = {last:,}, {case.label}: pressure maximum at r/a0 = {radius:.2f}, "
            text += f"polar angle {angle:.0f}°"
            if not case.isotropic:
                e2 = (case.beta + 90.0) % 180.0
                text += f" (e2 axis at {e2:.0f}°)"
            facts.append(text)
    return facts


def study_report(results: str | Path | StudyResults, cycles: Sequence[int] | None = None) -> str:
    """The Markdown tables and measured facts of a study."""
    study = results if isinstance(results, StudyResults) else read_results(results)
    if study.swept_keys:
        return _swept_report(study, cycles)
    config = study.config
    lines = [
        f"### {study.name}",
        "",
        f"{study.mesh_label}, P = {study.load:g} N, a0 = {study.radius:g} mm, "
        f"p0 = {study.p0:.2f} MPa; subsurface to z = {config['subsurface']['depth']:g} a0 in "
        f"{config['subsurface']['layers']} layers"
        + (f"; {config['loading']['cycles']:,} cycles" if study.is_cyclic else "; static")
        + f". Source: `{study.path}`.",
        "",
    ]
    lines += cyclic_table(study, cycles) if study.is_cyclic else static_table(study)
    lines += ["", "Measured:", ""]
    facts = cyclic_facts(study) if study.is_cyclic else static_facts(study)
    lines += [f"- {fact}" for fact in facts]
    if study.skipped:
        lines += ["", "Not completed: " + ", ".join(f"{c} ({s})" for c, s in study.skipped)]
    return "\n".join(lines) + "\n"


_STUDY_WIDE = {"punch.radius", "loading.load", "mesh.n", "mesh.half_width", "loading.cycles",
               "subsurface.depth", "subsurface.layers", "material.E_A", "material.nu_A",
               "material.E_B", "material.nu_B"}  # fmt: skip


def swept_keys(path: str | Path) -> list[str]:
    """Dotted keys swept in the study of the results file ``path`` (root attributes only)."""
    import json

    import h5py

    with h5py.File(path, "r") as file:
        sweep = json.loads(file.attrs["study_json"]).get("sweep", {})
    return [key for key in sweep if "." in key]


def _swept_report(study: StudyResults, cycles: Sequence[int] | None) -> str:
    """Studies with swept dotted keys (engine.output.sweep_report); the per-case tables too
    when no swept key changes the study-wide normalisation (a0, P, mesh, material)."""
    from .summary import load_summary
    from .sweep_report import sweep_report

    text = sweep_report(load_summary(study.path), study.swept_keys, study.name)
    if set(study.swept_keys) & _STUDY_WIDE:
        return text
    lines = ["", *(cyclic_table(study, cycles) if study.is_cyclic else static_table(study))]
    return text + "\n".join(lines) + "\n"


def update_markdown(document: str | Path, name: str, report: str) -> None:
    """Replace the block between ``<!-- BEGIN report NAME -->`` and ``<!-- END report NAME -->``
    of ``document`` with ``report`` (how the README's Results tables are regenerated)."""
    document = Path(document)
    text = document.read_text()
    begin, end = f"<!-- BEGIN report {name} -->", f"<!-- END report {name} -->"
    if begin not in text or end not in text:
        raise ValueError(f"{document}: no block {begin} … {end}")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    document.write_text(f"{head}{begin}\n{report}{end}{tail}")


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog, description="Print the results tables of a study (Markdown)."
    )
    parser.add_argument("results", type=Path, nargs="+", help="results file(s) (.h5)")
    parser.add_argument(
        "--cycles", type=int, nargs="+", default=None,
        help="cycles N to tabulate (cyclic studies; default: the recorded cycles)",
    )  # fmt: skip
    parser.add_argument(
        "--update", type=Path, default=None, metavar="DOC.md",
        help="instead of printing, replace the block <!-- BEGIN report NAME --> … "
        "<!-- END report NAME --> of DOC.md (NAME: the study name)",
    )  # fmt: skip
    return parser


def main(argv: Sequence[str] | None = None, prog: str | None = None) -> int:
    args = build_parser(prog).parse_args(argv)
    for path in args.results:
        if not path.exists():
            print(f"error: {path}: no such file", file=sys.stderr)
            return 2
    for path in args.results:
        study = read_results(path)
        report = study_report(study, args.cycles)
        if args.update is None:
            print(report)
        else:
            update_markdown(args.update, study.name, report)
            print(f"{args.update}: updated the report of {study.name}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(prog="python -m engine.output.report"))
