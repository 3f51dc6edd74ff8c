"""Peak-regime figures: where the σ_VM peak sits as the surface wears.

Drawn by ``python -m engine plot`` for a cyclic study whose cases carry the peak history
(:mod:`engine.solvers.peak`) and that sweeps the wear coefficient (two values or more):

``peak_regime_map.png``
    (a) the regime map: x the wear severity ω_max/δ0 (maximum wear depth over the elastic
    approach of the unworn punch at peak load; log scale), y μ; a large marker per case at its
    final state, marker and colour the region of the overall σ_VM peak, annotated with the
    depth z/a0 of the deep peak (z >= 0.1 a0) and whether it is on the axis or at the edge;
    small markers behind them: the region along the history of the case of each μ that wears
    most (every simulated cycle). (b) the depth z/a0 of the deep peak along those histories
    (linear severity, where the narrow transition shows),
    filled markers where it is on the axis; the band z/a0 ∈ [0.6, 0.8] is the paper's μ = 0.1
    finding (Fig. 8b). (c) for the lowest μ: the overall, deep and axis σ_VM peaks and the
    centre pressure along the same history, over p0.
``peak_regime_von_mises_mu<μ>.png``
    σ_VM/p0 in the x–z plane at the cycles where the region (overall or deep peak) changes,
    for the lowest μ, case that wears most; each panel its own colour scale (linear up to 1.6 ×
    its deep peak, at most ``VM_LEVEL_MAX``: the whole field falls several-fold with wear, a
    shared scale would hide the worn panels' lobes; geometric above, up to the ★ peak, which
    therefore lies inside the scale), thin contours every 0.1 p0; ★ overall peak, ○ deep
    peak; the regions as stored (classified at the element centres beside the plane).

Wear coefficient and cycle count enter the wear only through their product when the wear
law is linear (Archard, Eq. 14): cases of one μ follow the same path in severity, the more
wear-prone going further. That is why one history per μ suffices for the tracks.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import ticker
from matplotlib.colors import BoundaryNorm

from engine.solvers.peak import AXIS_RADIUS_FRACTION, DEEP_DEPTH_FRACTION, region_name

from .levels import VM_LEVEL_MAX, von_mises_levels
from .results import ResultCase, Results

__all__ = ["regime_figures", "has_peak_history", "wear_severity_history"]

REGION_STYLE = {  # marker, colour (colour-blind safe, Okabe–Ito); keys: REGIONS
    "edge-surface": ("s", "#D55E00"),
    "edge-subsurface": ("D", "#E69F00"),
    "axis-subsurface": ("o", "#0072B2"),
    "axis-surface": ("^", "#009E73"),
}
FRICTION_COLOURS = ("k", "#0072B2", "#D55E00", "#009E73", "#CC79A7")  # per μ in (b)
PAPER_DEPTH_BAND = (0.6, 0.8)  # z/a0 of the paper's μ = 0.1 peak after 10⁵ cycles (Fig. 8b)


def has_peak_history(study: Results) -> bool:
    """True for a cyclic study whose cases hold the peak history and that sweeps wear."""
    if not study.is_cyclic or not study.completed:
        return False
    if not all("peak_region" in case.history for case in study.completed):
        return False
    return len({case.wear1 for case in study.completed}) >= 2


def wear_severity_history(case: ResultCase) -> np.ndarray:
    """ω_max/δ0 per history row: max wear depth over the approach of the unworn punch."""
    return np.asarray(case.history["max_wear_depth"]) / float(case.history["approach"][0])


def regime_figures(study: Results) -> list:
    """(file name, figure) pairs; empty unless :func:`has_peak_history`."""
    if not has_peak_history(study):
        return []
    figures = [("peak_regime_map.png", _regime_map(study))]
    lowest = min(case.mu1 for case in study.completed)
    case = _most_worn(study, lowest)
    if case.peak_changes:
        figures.append((f"peak_regime_von_mises_mu{lowest:g}.png", _change_maps(study, case)))
    return figures


# ----------------------------------------------------------------------------- helpers
def _frictions(study: Results) -> list[float]:
    return sorted({case.mu1 for case in study.completed})


def _most_worn(study: Results, mu: float) -> ResultCase:
    cases = [case for case in study.completed if case.mu1 == mu]
    return max(cases, key=lambda case: wear_severity_history(case)[-1])


def _final_severity(case: ResultCase) -> float:
    return float(wear_severity_history(case)[-1])


def _legend_handles(axis) -> None:
    handles = [
        axis.plot([], [], ls="none", marker=m, color=c, ms=9, label=name)[0]
        for name, (m, c) in REGION_STYLE.items()
    ]
    axis.legend(
        handles=handles, title="overall σ_VM peak", fontsize=9, title_fontsize=9,
        loc="upper right", framealpha=0.9,
    )  # fmt: skip


def _positive_floor(values: np.ndarray) -> np.ndarray:
    """Severities for a log axis: the unworn row (0) is drawn at a tenth of the first."""
    values = np.asarray(values, dtype=float)
    positive = values[values > 0]
    floor = positive.min() / 10.0 if positive.size else 1e-4
    return np.where(values > 0, values, floor)


# ----------------------------------------------------------------------------- the map
def _regime_map(study: Results):
    figure, (map_axis, depth_axis, peak_axis) = plt.subplots(
        1, 3, figsize=(16.4, 5.4), layout="constrained"
    )
    _draw_map(map_axis, study)
    _draw_deep_depth(depth_axis, study)
    _draw_peaks(peak_axis, study, _frictions(study)[0])
    figure.suptitle(
        f"{study.name}: where the σ_VM peak goes as the surface wears "
        f"({study.mesh_label}, P = {study.load:g} {study.load_unit}, "
        f"{int(study.study['loading']['cycles']):,} cycles)",
        fontsize=12,
    )
    return figure


def _draw_map(axis, study: Results) -> None:
    frictions = _frictions(study)
    for mu in frictions:  # tracks: the region along the most worn case's history
        case = _most_worn(study, mu)
        severity = _positive_floor(wear_severity_history(case))
        codes = np.asarray(case.history["peak_region"])
        for code in np.unique(codes[np.isfinite(codes)]):
            marker, colour = REGION_STYLE[region_name(float(code))]
            rows = codes == code
            axis.plot(
                severity[rows], np.full(rows.sum(), mu), ls="none", marker=marker,
                ms=3.5, color=colour, alpha=0.45, zorder=2,
            )  # fmt: skip
    for case in study.completed:  # final states
        marker, colour = REGION_STYLE[str(case.summary["peak_region"])]
        severity = _final_severity(case)
        axis.plot(severity, case.mu1, marker=marker, color=colour, ms=13, mec="k", zorder=3)
        depth = float(case.summary["vm_deep_max_z"]) / study.radius
        side = "axis" if str(case.summary.get("deep_region", "")).startswith("axis") else "edge"
        axis.annotate(
            f"{depth:.2f}\n{side}", (severity, case.mu1), xytext=(0, 11),
            textcoords="offset points", ha="center", va="bottom", fontsize=8,
        )  # fmt: skip
    axis.set_xscale("log")
    finals = [_final_severity(case) for case in study.completed]
    axis.set_xlim(min(finals) / 4.0, max(finals) * 2.0)
    axis.set_yscale("log")
    axis.set_yticks(frictions, [f"{mu:g}" for mu in frictions])
    axis.minorticks_off()
    low, high = frictions[0], frictions[-1]
    axis.set_ylim(low / 1.35, high * 1.6)
    axis.set_xlabel("wear severity ω_max / δ0 (max wear depth / elastic approach)")
    axis.set_ylabel("friction coefficient μ")
    axis.set_title(
        "(a) region of the σ_VM peak; labels: deep peak (z ≥ "
        f"{DEEP_DEPTH_FRACTION:g} a0) depth z/a0 and side",
        fontsize=10,
    )
    axis.grid(True, which="major", alpha=0.3)
    _legend_handles(axis)


def _draw_deep_depth(axis, study: Results) -> None:
    colours = [FRICTION_COLOURS[i % len(FRICTION_COLOURS)] for i in range(len(_frictions(study)))]
    right = _settled_severity(study)
    axis.axhspan(*PAPER_DEPTH_BAND, color="0.85", zorder=0)
    axis.text(
        0.98, np.mean(PAPER_DEPTH_BAND), "paper, μ = 0.1 (Fig. 8b)", ha="right", va="center",
        fontsize=8, transform=axis.get_yaxis_transform(),
    )  # fmt: skip
    for mu, colour in zip(_frictions(study), colours, strict=True):
        case = _most_worn(study, mu)
        severity = wear_severity_history(case)
        depth = np.asarray(case.history["vm_deep_max_z"]) / study.radius
        radius = np.asarray(case.history["contact_radius"])
        on_axis = np.abs(case.history["vm_deep_max_x"]) < AXIS_RADIUS_FRACTION * radius
        axis.plot(severity, depth, "-", color=colour, lw=1.2, label=f"μ = {mu:g}")
        axis.plot(severity[on_axis], depth[on_axis], "o", color=colour, ms=5)
        axis.plot(severity[~on_axis], depth[~on_axis], "o", mfc="none", mec=colour, ms=5)
    axis.set_xlim(0.0, right)
    if right < max(_final_severity(case) for case in study.completed):
        axis.text(
            0.98, 0.03, "beyond the right edge: every deep peak\nstays where it is, to the end",
            transform=axis.transAxes, ha="right", va="bottom", fontsize=8,
        )  # fmt: skip
    axis.set_ylim(1.6, 0.0)
    axis.set_xlabel("wear severity ω_max / δ0 (linear)")
    axis.set_ylabel("depth of the deep peak z/a0 (down)")
    axis.set_title("(b) deep σ_VM peak: ● on the axis, ○ at the edge", fontsize=10)
    axis.grid(True, alpha=0.3)
    axis.legend(fontsize=9, loc="lower left")


def _settled_severity(study: Results) -> float:
    """Right end of panel (b): the whole range, unless every track has long since settled
    (same deep region and depth to its end); then 1.3 × the last severity where any track
    still changes, so that the transition is not squeezed into a corner."""
    last_change, end = 0.0, 0.0
    for mu in _frictions(study):
        case = _most_worn(study, mu)
        severity = wear_severity_history(case)
        state = np.stack([case.history["deep_region"], case.history["vm_deep_max_z"]])
        changes = np.flatnonzero(np.any(state[:, 1:] != state[:, :-1], axis=0))
        if changes.size:
            last_change = max(last_change, float(severity[changes[-1] + 1]))
        end = max(end, float(severity[-1]))
    return end if last_change <= 0.0 else min(end, 1.3 * last_change)


def _draw_peaks(axis, study: Results, mu: float) -> None:
    case = _most_worn(study, mu)
    severity = wear_severity_history(case)
    p0 = study.p0
    curves = (
        ("vm_max", "σ_VM max, whole plane", "k", "-"),
        ("vm_deep_max", f"σ_VM max at z ≥ {DEEP_DEPTH_FRACTION:g} a0", "#0072B2", "-"),
        ("vm_axis_max", "σ_VM max on the axis", "#009E73", "--"),
        ("centre_pressure", "p(r = 0)", "#CC79A7", ":"),
    )
    for key, label, colour, style in curves:
        axis.plot(severity, np.asarray(case.history[key]) / p0, style, color=colour, lw=1.6,
                  label=label)  # fmt: skip
    axis.set_xlim(left=0.0)
    axis.set_yscale("log")
    axis.yaxis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.yaxis.set_major_formatter(ticker.FormatStrFormatter("%g"))
    axis.yaxis.set_minor_formatter(ticker.NullFormatter())
    axis.set_xlabel("wear severity ω_max / δ0 (linear)")
    axis.set_ylabel("stress / p0 (log)")
    axis.set_title(f"(c) μ = {mu:g}, i = {case.wear1:g} 1/MPa: peaks along the history",
                   fontsize=10)  # fmt: skip
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=9, loc="upper left")


# ----------------------------------------------------------------------------- σ_VM maps
def _row_at(case: ResultCase, cycle: int) -> int:
    hits = np.flatnonzero(np.asarray(case.history["cycle"]) == cycle)
    return int(hits[0])


def _change_maps(study: Results, case: ResultCase):
    cycles = sorted(case.peak_changes)
    columns = min(len(cycles), 3)
    rows = -(-len(cycles) // columns)
    figure, axes = plt.subplots(
        rows, columns, figsize=(5.6 * columns, 4.1 * rows), squeeze=False, layout="constrained"
    )
    for axis in axes.flat[len(cycles) :]:
        axis.set_visible(False)
    a, p0 = study.radius, study.p0
    severity = wear_severity_history(case)
    for axis, cycle in zip(axes.flat, cycles, strict=False):
        plane = case.peak_changes[cycle]
        row = _row_at(case, cycle)
        ratio = plane.von_mises / p0
        overall = np.unravel_index(np.argmax(ratio), ratio.shape)
        deep = np.where(plane.z >= DEEP_DEPTH_FRACTION * a, ratio, -np.inf)
        deep_index = np.unravel_index(np.argmax(deep), deep.shape)
        # each panel its own scale, linear up to 1.6 × its deep peak (at most VM_LEVEL_MAX):
        # the lobes stay visible as the whole field falls with wear; geometric above, up to
        # the ★ peak, so that it lies inside the scale; thin contours every 0.1 p0
        top = min(VM_LEVEL_MAX, 1.6 * float(ratio[deep_index]))
        levels = von_mises_levels(float(ratio[overall]), linear_top=top, steps=16)
        norm = BoundaryNorm(levels, ncolors=plt.get_cmap("turbo").N, extend="max")
        filled = axis.contourf(plane.x / a, plane.z / a, ratio, levels=levels, cmap="turbo",
                               norm=norm, extend="max")  # fmt: skip
        lines = np.arange(0.1, top, 0.1)
        axis.contour(plane.x / a, plane.z / a, ratio, levels=lines, colors="k",
                     linewidths=0.4, alpha=0.5)  # fmt: skip
        bar = figure.colorbar(filled, ax=axis, label="σ_VM / p0", shrink=0.8)
        ticks = [levels[0], levels[16] / 2, levels[16], levels[-1]]
        bar.set_ticks(ticks, labels=[f"{tick:.2g}" for tick in ticks])
        axis.plot(plane.x[overall] / a, plane.z[overall] / a, "*", ms=15, mfc="w", mec="k",
                  clip_on=False)  # fmt: skip
        axis.plot(plane.x[deep_index] / a, plane.z[deep_index] / a, "o", ms=9, mfc="none",
                  mec="w", mew=2)  # fmt: skip
        text = (
            f"★ plane max {ratio[overall]:.2f} p0\n"
            f"○ deep max {ratio[deep_index]:.2f} p0 at z/a0 = {plane.z[deep_index] / a:.2f}\n"
            f"regions: {region_name(case.history['peak_region'][row])}, deep "
            f"{region_name(case.history['deep_region'][row])}"
        )
        axis.text(
            0.02, 0.03, text, transform=axis.transAxes, fontsize=8, color="w", va="bottom",
            bbox={"facecolor": "k", "alpha": 0.55, "pad": 2, "edgecolor": "none"},
        )  # fmt: skip
        axis.set_ylim(float(np.max(plane.z)) / a, 0.0)
        axis.set_aspect("equal")
        axis.set_xlabel("x/a0")
        axis.set_ylabel("z/a0 (depth)")
        axis.set_title(f"N = {cycle:,}, ω_max/δ0 = {severity[row]:.3f}", fontsize=10)
    figure.suptitle(
        f"{study.name}: σ_VM/p0 where the peak region changes — μ = {case.mu1:g}, "
        f"i = {case.wear1:g} 1/MPa ({study.mesh_label})\nthin lines: σ_VM/p0 every 0.1; "
        "colour levels linear to 1.6 × the deep peak, geometric above, to the ★ peak; regions "
        "classified at the element centres beside the plane",
        fontsize=12,
    )
    return figure
