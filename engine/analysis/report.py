"""Results tables of a study in Markdown: ``python -m engine report RESULTS.h5 [--cycles N …]``.

The tables of the manual's results page are printed by this command (``--update``), never typed
by hand.
Per case:

cyclic study   at each N (default: the recorded cycles): maximum wear depth (µm), wear volume
               (mm³), peak pressure p_max/p0, peak σ_VM/p0 over the x–z plane and its location
               (r/a0, z/a0), and the peak below the surface layer with its location;
static study   approach g_n (µm), stiffness ratio k_μ/k_0, stick fraction, the same σ_VM peaks;
fretting study the fretting columns and the checks against Mindlin
               (:mod:`engine.analysis.fretting_report`).

Then a list of *measured facts* bearing on the paper's findings (Section 7): stick and
stiffness vs Mossakovskii, wear ordering in μ, peak locations, spread over β, where the
pressure peak sits relative to the tribological axes. They are measurements, not verdicts.
p0 = P/(π a0²) (Eq. 19); r = |x| on the plane y = 0; z into the half-space.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence
from pathlib import Path

import h5py
import numpy as np

from engine.commands import refuse_file, results_parser
from engine.output.owner import being_written_file
from engine.output.summary import load_summary
from engine.reference.flat_punch import mossakovskii_ratio, sneddon_approach
from engine.schema import PARAMETERS

from .calibration_report import calibration_report, has_calibration
from .markdown import replace_block
from .results import Plane, ResultCase, Results, open_results
from .surface_report import surface_report

__all__ = ["study_report", "main", "INTERIOR_DEPTH"]

INTERIOR_DEPTH = 0.1  # z/a0 below which the surface edge singularity dominates the σ_VM peak


def stiffness_ratios(study: Results) -> tuple[np.ndarray, np.ndarray, float, str]:
    """(μ, k_μ/k_0, Mossakovskii's ratio, what k_0 is) with k = P/g_n at peak load.

    k_0 is the computed frictionless stiffness when the study has a μ = 0 case (so the
    discretisation error of the stiffness cancels), else Sneddon's 2E*a0 (Eq. 18).
    """
    isotropic = [case for case in study.completed if case.isotropic]
    mu = np.array([case.mu1 for case in isotropic])
    stiffness = np.array([case.summary["load"] / case.summary["approach"] for case in isotropic])
    frictionless = [k for m, k in zip(mu, stiffness, strict=True) if m == 0.0]
    if frictionless:
        reference, what = frictionless[0], "computed μ = 0 stiffness"
    else:
        reference = 2.0 * study.material.contact_modulus * study.radius
        what = "Sneddon 2E*a0, Eq. (18)"
    order = np.argsort(mu)
    limit = mossakovskii_ratio(study.material.dundurs_beta)
    return mu[order], stiffness[order] / reference, limit, what


def _format_peak(study: Results, peak: tuple[float, float, float]) -> tuple[str, str]:
    value, x, z = peak
    a = study.radius
    return f"{value / study.p0:.2f}", f"({abs(x) / a:.2f}, {z / a:.3f})"


def _plane_columns(study: Results, plane: Plane | None) -> list[str]:
    if plane is None:
        return ["–"] * 4
    return [*_format_peak(study, plane.peak()), *_format_peak(study, plane.subsurface_peak())]


def edge_facts(study: Results) -> list[str]:
    """One warning per case and stress plane whose σ_VM peak (over the plane, or below its
    surface layer) sits on the edge of the computed domain (:meth:`Plane.on_edge`; the
    final state's are the summary's ``vm_max_on_edge`` and ``vm_sub_max_on_edge``)."""
    facts = []
    for case in study.completed:
        for key, plane in case.planes.items():
            below = float(plane.depths[1]) if len(plane.depths) > 1 else 0.0
            for what, depth in (("peak", 0.0), ("peak below the surface layer", below)):
                edge = plane.on_edge(depth)
                if edge:
                    when = "final state" if key == "final" else f"N = {key:,}"
                    facts.append(
                        f"**peak on the domain's edge**: {case.label}, {when}: the σ_VM {what} "
                        f"lies on the {edge} of the computed plane; the maximum may lie beyond "
                        "it (widen [mesh] half_width or deepen [subsurface] depth)"
                    )
                    break
    return facts


def _header(columns: list[str]) -> list[str]:
    return ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]


def _row(values: list[str]) -> str:
    return "| " + " | ".join(values) + " |"


_PEAK_COLUMNS = ["σ_VM/p0 max", "at (r/a0, z/a0)", "σ_VM/p0 below surface", "at (r/a0, z/a0)"]


def cyclic_table(study: Results, cycles: Sequence[int] | None = None) -> list[str]:
    if cycles is None:
        cycles = sorted({n for case in study.completed for n in case.recorded_cycles})
    lines = _header(
        [
            "case",
            "N",
            "max wear depth (µm)",
            f"wear volume ({study.per_contact('mm³')})",
            "p_max/p0",
            *_PEAK_COLUMNS,
        ]
    )
    for case in study.completed:
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


def static_table(study: Results) -> list[str]:
    mu, ratios, limit, what = stiffness_ratios(study)
    ratio_of = dict(zip(mu.tolist(), ratios.tolist(), strict=True))
    lines = _header(["case", "g_n (µm)", "k_μ/k_0", "stick fraction", *_PEAK_COLUMNS])
    for case in sorted(study.completed, key=lambda case: case.mu1):
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
def static_facts(study: Results) -> list[str]:
    mu, ratios, limit, _ = stiffness_ratios(study)
    facts = [
        f"stiffness ratio k_μ/k_0 = {ratios[-1]:.5f} at μ = {mu[-1]:g} vs Mossakovskii "
        f"{limit:.5f} (reached to {100 * (ratios[-1] - 1) / (limit - 1):.0f} % of the rise)"
    ]
    full = [case for case in study.completed if case.summary["stick_fraction"] >= 0.999]
    first = min((case.mu1 for case in full), default=None)
    facts.append(
        "full stick (stick fraction ≥ 0.999) first at μ = "
        + (f"{first:g}" if first is not None else "none of the cases")
        + "; stick fractions: "
        + ", ".join(
            f"{case.label.replace(' = ', '=')}: {case.summary['stick_fraction']:.3f}"
            for case in sorted(study.completed, key=lambda case: (case.mu1, case.beta))
        )
    )
    for case in sorted(study.completed, key=lambda case: (case.mu1, case.beta)):
        if case.mu1 > 0 and "final" in case.fields:
            facts.append(f"{case.label}: {_slip_zone(study, case)}")
    frictionless = [case for case in study.completed if case.mu1 == 0.0]
    if frictionless:
        expected = sneddon_approach(study.load, study.radius, study.material.contact_modulus)
        computed = frictionless[0].summary["approach"]
        facts.append(
            f"frictionless approach {computed * 1e3:.4f} µm vs Sneddon P/(2E*a0) = "
            f"{expected * 1e3:.4f} µm ({100 * (computed / expected - 1):+.2f} %)"
        )
    return facts


def _slip_zone(study: Results, case: ResultCase) -> str:
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


def _pressure_peak_angle(study: Results, case: ResultCase, cycle) -> tuple[float, float]:
    """(r/a0, polar angle in degrees within [0, 180)) of the pressure maximum."""
    pressure = case.fields[cycle]["pressure"]
    i, j = np.unravel_index(np.argmax(pressure), pressure.shape)
    x, y = study.grid_x[i], study.grid_y[j]
    return float(np.hypot(x, y) / study.radius), float(np.degrees(np.arctan2(y, x)) % 180.0)


def _groups(cases: Sequence[ResultCase], key) -> list[list[ResultCase]]:
    """Cases sharing ``key(case)``, in order of first appearance."""
    groups: dict = {}
    for case in cases:
        groups.setdefault(key(case), []).append(case)
    return list(groups.values())


def _group_label(case: ResultCase, names: Sequence[str], varying: set[str]) -> str:
    """``"β = 90°"``-style label of the parameters ``names`` that take several values in the
    study (``varying``); empty when none does (one group, nothing to tell apart)."""
    units = {"beta": "°", "wear1": " 1/MPa", "wear2": " 1/MPa"}
    symbols = {"mu1": "μ1", "mu2": "μ2", "wear1": "i1", "wear2": "i2", "beta": "β"}
    parts = [
        f"{symbols[name]} = {getattr(case, name):g}{units.get(name, '')}"
        for name in names
        if name in varying
    ]
    return ", ".join(parts)


def _varying_parameters(cases: Sequence[ResultCase]) -> set[str]:
    names = PARAMETERS
    return {name for name in names if len({getattr(case, name) for case in cases}) > 1}


def _trend(values: Sequence[float]) -> str:
    """Strictly decreasing, strictly increasing or not monotone, for values in sweep order."""
    steps = np.diff(np.asarray(values, dtype=float))
    if np.all(steps < 0):
        return "strictly decreasing"
    if np.all(steps > 0):
        return "strictly increasing"
    return "not monotone"


def _trend_fact(
    cycle, cases, parameter: str, symbol: str, label: str, volume_unit: str = "mm³"
) -> str | None:
    """Trend of wear depth and volume at ``cycle`` along ``parameter`` within one group of cases
    that differ only in that parameter (and in what follows from it, e.g. a proportional i2).

    Stated for depth and volume separately, with the values, so it can be checked against the
    table line by line; ``None`` when the group has fewer than two values of the parameter.
    """
    cases = sorted(cases, key=lambda case: getattr(case, parameter))
    values = [getattr(case, parameter) for case in cases]
    if len(set(values)) < 2 or len(set(values)) != len(values):
        return None
    depths = [case.history_at("max_wear_depth", cycle) * 1e3 for case in cases]
    volumes = [case.history_at("wear_volume", cycle) for case in cases]
    depth_trend, volume_trend = _trend(depths), _trend(volumes)
    where = f"N = {cycle:,}" + (f", {label}" if label else "")
    listed = ", ".join(f"{value:g}" for value in values)
    if depth_trend == volume_trend:
        verdict = f"wear depth and volume {depth_trend} with {symbol} = {listed}"
    else:
        verdict = (
            f"with {symbol} = {listed}: wear depth {depth_trend} "
            f"({', '.join(f'{d:.4g}' for d in depths)} µm), wear volume {volume_trend} "
            f"({', '.join(f'{v:.3e}' for v in volumes)} {volume_unit})"
        )
    return f"{where}: {verdict}"


def _spread_fact(cycle, cases, label: str) -> str | None:
    """Spread (max − min)/mean of wear depth and volume over β within one group of cases that
    differ only in β; ``None`` with fewer than two angles."""
    betas = sorted({case.beta for case in cases})
    if len(betas) < 2:
        return None
    depths = [case.history_at("max_wear_depth", cycle) for case in cases]
    volumes = [case.history_at("wear_volume", cycle) for case in cases]
    spread_depth = (max(depths) - min(depths)) / max(float(np.mean(depths)), 1e-300)
    spread_volume = (max(volumes) - min(volumes)) / max(float(np.mean(volumes)), 1e-300)
    where = f"N = {cycle:,}" + (f", {label}" if label else "")
    angles = ", ".join(f"{beta:g}" for beta in betas)
    return (
        f"{where}: spread over β = {angles}° (max − min)/mean: wear depth "
        f"{100 * spread_depth:.2f} %, wear volume {100 * spread_volume:.2f} %"
    )


def wear_trend_facts(study: Results, cycle: int) -> list[str]:
    """The wear facts at one recorded cycle, each within a group of comparable cases.

    - isotropic cases (μ1 = μ2, i1 = i2), grouped by β and i: trend with μ (Section 7.2);
    - orthotropic cases grouped by μ1, i1 and β: trend with μ2 (i2 may follow μ2);
    - all cases grouped by μ1, μ2, i1, i2: spread over β (Section 7.3: invariance with β).

    Duplicates of a μ at other angles β (the demo's β = 0°, 90°) therefore never enter one
    comparison together.
    """
    cases = [case for case in study.completed if cycle in case.fields]
    varying = _varying_parameters(cases)
    volume_unit = study.per_contact("mm³")
    facts: list[str | None] = []
    isotropic = [case for case in cases if case.isotropic]
    for group in _groups(isotropic, lambda case: (case.beta, case.wear1)):
        label = _group_label(group[0], ("beta", "wear1"), varying)
        facts.append(_trend_fact(cycle, group, "mu1", "μ", label, volume_unit))
    orthotropic = [case for case in cases if not case.isotropic]
    for group in _groups(orthotropic, lambda case: (case.mu1, case.wear1, case.beta)):
        label = _group_label(group[0], ("mu1", "wear1", "beta"), varying)
        facts.append(_trend_fact(cycle, group, "mu2", "μ2", label, volume_unit))
    for group in _groups(cases, lambda case: (case.mu1, case.mu2, case.wear1, case.wear2)):
        label = _group_label(group[0], ("mu1", "mu2", "wear1", "wear2"), varying)
        facts.append(_spread_fact(cycle, group, label))
    return [fact for fact in facts if fact is not None]


def cyclic_facts(study: Results) -> list[str]:
    facts = []
    cycles = sorted({n for case in study.completed for n in case.recorded_cycles})
    for cycle in cycles:
        facts += wear_trend_facts(study, cycle)
    if cycles:
        last = cycles[-1]
        for case in study.completed:
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
                off = abs(angle - e2) % 180.0
                text += f" (e2 axis at {e2:.0f}°, {min(off, 180.0 - off):.0f}° from it)"
            facts.append(text)
    return facts


def study_report(results: str | Path | Results, cycles: Sequence[int] | None = None) -> str:
    """The Markdown tables and measured facts of a study."""
    study = results if isinstance(results, Results) else open_results(results)
    return study.kind_hook("report")(study, cycles) + surface_report(study)  # [surface]


def standard_report(study: Results, cycles: Sequence[int] | None = None) -> str:
    """The report of a static or cyclic study (the loading kinds' ``report`` hook): the
    tables of the recorded cycles (or the static tables) and the measured facts, or the
    sweep report when dotted keys are swept."""
    if study.swept_keys:
        return _swept_report(study, cycles)
    config = study.study
    lines = [
        f"### {study.name}",
        "",
        f"{study.mesh_label}, P = {study.load:g} {study.load_unit}, a0 = {study.radius:g} mm, "
        f"p0 = {study.p0:.2f} MPa; subsurface to z = {config['subsurface']['depth']:g} a0 in "
        f"{config['subsurface']['layers']} layers"
        + (f"; {config['loading']['cycles']:,} cycles" if study.is_cyclic else "; static")
        + f". Source: `{study.path}`.",
        "",
    ]
    lines += cyclic_table(study, cycles) if study.is_cyclic else static_table(study)
    lines += ["", "Measured:", ""]
    facts = cyclic_facts(study) if study.is_cyclic else static_facts(study)
    facts += edge_facts(study)
    lines += [f"- {fact}" for fact in facts]
    if study.skipped:
        lines += ["", "Not completed: " + ", ".join(f"{c} ({s})" for c, s in study.skipped)]
    return "\n".join(lines) + "\n"


_STUDY_WIDE = {"punch.radius", "loading.load", "mesh.n", "mesh.half_width", "loading.cycles",
               "subsurface.depth", "subsurface.layers", "material.E_A", "material.nu_A",
               "material.E_B", "material.nu_B"}  # fmt: skip


def study_settings(path: str | Path) -> dict:
    """The resolved study stored in the results file ``path`` (root attributes only: cheap,
    whatever the number of cases)."""
    with h5py.File(path, "r") as file:
        return json.loads(file.attrs["study_json"])


def swept_keys(settings: dict) -> list[str]:
    """Dotted keys swept in a resolved study (:func:`study_settings`)."""
    return [key for key in settings.get("sweep", {}) if "." in key]


def _swept_report(study: Results, cycles: Sequence[int] | None) -> str:
    """Studies with swept dotted keys (engine.analysis.sweep_report); the per-case tables too
    when no swept key changes the study-wide normalisation (a0, P, mesh, material)."""
    line = study.profile.is_line
    from .sweep_report import sweep_report  # pandas: only for a sweep

    text = sweep_report(load_summary(study.path), study.swept_keys, study.name, line)
    edges = [f"- {fact}" for fact in edge_facts(study)]
    if edges:
        text += "\n".join(["", *edges]) + "\n"
    if set(study.swept_keys) & _STUDY_WIDE:
        return text
    lines = ["", *(cyclic_table(study, cycles) if study.is_cyclic else static_table(study))]
    return text + "\n".join(lines) + "\n"


def update_markdown(document: str | Path, name: str, report: str) -> None:
    """Replace the block between ``<!-- BEGIN report NAME -->`` and ``<!-- END report NAME -->``
    of ``document`` with ``report`` (how the tables of the results page are regenerated)."""
    replace_block(document, name, report, kind="report")


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = results_parser(
        prog,
        "Print the results tables of a study (Markdown).",
        "results file(s) (.h5)",
        several=True,
    )
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
    if being_written_file(args.results) or refuse_file(args.results):
        return 2

    for path in args.results:
        if has_calibration(path) and args.update is None:  # a [calibrate] study
            print(calibration_report(path))
            continue
        study = open_results(path)
        report = study_report(study, args.cycles)
        if args.update is None:
            print(report)
        else:
            try:
                update_markdown(args.update, study.name, report)
            except (OSError, ValueError) as error:  # no such document, or no block to replace
                print(f"error: {error}", file=sys.stderr)
                return 2
            print(f"{args.update}: updated the report of {study.name}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(prog="python -m engine.analysis.report"))
