"""Figures of the fatigue results of a fretting study (``[fatigue]``; the verdicts:
``engine.analysis.fatigue``).

- ``fatigue_maps.png``: each criterion's map on the stress plane at the last recorded cycle
  (rows: up to ``MAX_MAP_CASES`` cases spread over the sweep; columns: criteria), depth z
  downwards, with the contact and the stick zone of the increment of the largest |Q| marked
  on the surface, the hot spot (×), the point the critical distance is read below (▼) and,
  for a risk criterion, the contour risk = 1;
- ``fatigue_history.png``: each criterion's hot spot against the cycles (per simulated cycle
  with ``every_cycle``, else per recorded cycle), the critical value where the history has it
  (dashed), risk = 1 marked;
- on the fretting map (``engine.analysis.fretting_figures``): :func:`draw_crack_boundary`
  rings the cases where a crack is predicted and draws the crack-nucleation boundary (crack
  ratio = 1) over the slip regimes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.tri import Triangulation

from .fatigue import case_verdicts, crack_ratio, has_fatigue, hot_spot_history
from .fretting import direction
from .results import ResultCase, Results

__all__ = ["fatigue_figures", "draw_crack_boundary", "MAX_MAP_CASES"]

MAX_MAP_CASES = 4
STICK, CONTACT_COLOUR, STICK_COLOUR = 1, "0.15", "gold"


def _last_cycle(case: ResultCase) -> int:
    return max(case.fatigue)


def _along_plane(study: Results, case: ResultCase, values: np.ndarray, s: np.ndarray):
    """A surface field (grid shape) at the plane's points s (mm) along the sliding direction:
    the nearest element's value."""
    theta = direction(study, case)
    grid_x, grid_y = study.grid_x, study.grid_y
    if values.shape != (grid_x.size, grid_y.size):  # a case with its own grid
        grid_x = np.linspace(grid_x.min(), grid_x.max(), values.shape[0])
        grid_y = np.linspace(grid_y.min(), grid_y.max(), values.shape[1])
    i = np.abs(grid_x[None, :] - (s * np.cos(theta))[:, None]).argmin(axis=1)
    j = np.abs(grid_y[None, :] - (s * np.sin(theta))[:, None]).argmin(axis=1)
    return values[i, j]


def _zone(axis, s: np.ndarray, mask: np.ndarray, colour: str, width: float, label: str, top):
    """A bar on the surface over the extent of ``mask`` along s."""
    if not np.any(mask):
        return
    axis.plot(
        [s[mask].min(), s[mask].max()], [top, top], color=colour, lw=width,
        solid_capstyle="butt", label=label, clip_on=False,
    )  # fmt: skip


def _map_panel(axis, study: Results, case: ResultCase, verdict, figure) -> None:
    cycle = verdict.cycle
    plane = case.planes[cycle]
    values = case.fatigue[cycle][verdict.column]
    s, z = plane.s, plane.z
    image = axis.pcolormesh(s, z, values, shading="nearest", cmap="magma_r")
    unit = "" if verdict.unit == "1" else f" ({verdict.unit})"
    figure.colorbar(image, ax=axis, label=verdict.name + unit)
    if verdict.unit == "1" and math.isnan(verdict.life) and values.max() >= 1.0 > values.min():
        axis.contour(s, z, values, levels=[1.0], colors="c", linewidths=1.2)
        axis.plot([], [], color="c", lw=1.2, label="risk = 1")  # the contour's legend entry
    depth = float(z.max())
    top = -0.04 * depth
    fields = case.fields.get(cycle, {})
    along = s[:, 0]
    if "pressure" in fields:
        pressure = _along_plane(study, case, np.asarray(fields["pressure"]), along)
        _zone(axis, along, pressure > 0, CONTACT_COLOUR, 6, "contact", top)
    if "status" in fields:
        status = _along_plane(study, case, np.asarray(fields["status"]), along)
        _zone(axis, along, status == STICK, STICK_COLOUR, 3, "stick zone", top)
    axis.plot(verdict.x, verdict.z, "x", color="c", ms=9, mew=2, label="hot spot")
    axis.plot(
        verdict.critical_x, top, "v", color="c", ms=7, clip_on=False,
        label="critical distance read below",
    )  # fmt: skip
    axis.set_ylim(depth, top)
    axis.set_xlabel("s along the sliding direction (mm)")
    axis.set_ylabel("depth z (mm)")
    crack = "crack predicted" if verdict.crack else "no crack"
    axis.set_title(f"{case.label}, N = {cycle:,}\n{verdict.name}: {crack}", fontsize=9)


def _maps_figure(study: Results):
    every = [case for case in study.completed if case.fatigue]
    picks = np.linspace(0, len(every) - 1, min(MAX_MAP_CASES, len(every))).round()
    cases = [every[int(i)] for i in sorted(set(picks.tolist()))]  # spread over the sweep
    verdicts = [case_verdicts(study, case) for case in cases]
    columns = max(len(v) for v in verdicts)
    figure, axes = plt.subplots(
        len(cases), columns, figsize=(4.6 * columns, 3.4 * len(cases)), squeeze=False,
        layout="constrained",
    )  # fmt: skip
    for row, (case, found) in enumerate(zip(cases, verdicts, strict=True)):
        for column, verdict in enumerate(found):
            _map_panel(axes[row, column], study, case, verdict, figure)
        for axis in axes[row, len(found) :]:
            axis.set_visible(False)
    entries = {}  # every panel's entries, once each (the risk = 1 contour is not in all)
    for axis in axes.flat:
        for handle, label in zip(*axis.get_legend_handles_labels(), strict=True):
            entries.setdefault(label, handle)
    figure.legend(
        list(entries.values()), list(entries), loc="outside lower center", ncols=len(entries)
    )
    more = len(every) - len(cases)
    note = f" ({len(cases)} cases of {len(every)}, spread over the sweep)" if more > 0 else ""
    figure.suptitle(f"{study.name}: fatigue criteria on the stress plane{note}")
    return figure


def _history_figure(study: Results):
    cases = [case for case in study.completed if case.fatigue]
    columns = [(v.column, v.name, v.unit) for v in case_verdicts(study, cases[0])]
    figure, axes = plt.subplots(
        1, len(columns), figsize=(5.0 * len(columns), 3.8), squeeze=False, layout="constrained"
    )
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.9, len(cases)))
    for axis, (column, name, unit) in zip(axes[0], columns, strict=True):
        for colour, case in zip(colours, cases, strict=True):
            cycles, values = hot_spot_history(case, column)
            axis.plot(cycles, values, "o-", color=colour, ms=3, label=case.label)
            critical = case.history.get(f"{column}_critical")
            if critical is not None and len(critical) == len(cycles):
                axis.plot(cycles, critical, "--", color=colour, lw=1)
        if unit == "1" and column.endswith("_risk"):
            axis.axhline(1.0, color="k", lw=0.8, ls=":")
        axis.set_xscale("symlog", linthresh=1.0)
        axis.set_xlim(left=0.0)
        axis.set_xlabel("cycle N")
        axis.set_ylabel(name + ("" if unit == "1" else f" ({unit})"))
        axis.grid(alpha=0.3)
        axis.set_title(f"{name}: hot spot (solid), critical distance (dashed)", fontsize=9)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="outside right upper", fontsize=8)
    figure.suptitle(f"{study.name}: fatigue hot spots as wear evolves")
    return figure


def draw_crack_boundary(axis, points: Sequence[tuple[float, float, float]]) -> None:
    """On a fretting map's ``axis``: rings around the points (x, y, crack ratio) where a
    crack is predicted (ratio ≥ 1), and the boundary ratio = 1 — linear interpolation between
    the cases (a contour over their triangulation; on a one-parameter sweep, the crossing
    along it)."""
    points = [p for p in points if math.isfinite(p[2])]
    if not points:
        return
    x, y, ratio = (np.array(values, dtype=float) for values in zip(*points, strict=True))
    limits = axis.get_xlim(), axis.get_ylim()
    try:
        _draw_boundary(axis, x, y, ratio)
    finally:  # the map keeps its own margins around the cases
        axis.set_xlim(*limits[0])
        axis.set_ylim(*limits[1])


def _draw_boundary(axis, x: np.ndarray, y: np.ndarray, ratio: np.ndarray) -> None:
    cracked = ratio >= 1.0
    axis.scatter(
        x[cracked], y[cracked], s=220, facecolors="none", edgecolors="m", linewidths=1.6,
        label="crack predicted (crack ratio ≥ 1)", zorder=4,
    )  # fmt: skip
    if cracked.all() or not cracked.any():
        return
    if np.unique(x).size > 1 and np.unique(y).size > 1:
        try:
            triangulation = Triangulation(np.log10(x), y)
        except (ValueError, RuntimeError):  # collinear points: no triangle
            return
        # triangles chosen on log δ* (the map's axis), the ratio linear between the cases
        linear = Triangulation(x, y, triangulation.triangles)
        axis.tricontour(linear, ratio, levels=[1.0], colors="m", linewidths=1.4)
        axis.plot([], [], color="m", lw=1.4, label="crack-nucleation boundary (ratio = 1)")
        return
    along, other = (x, y) if np.unique(y).size == 1 else (y, x)
    order = np.argsort(along)
    along, values = along[order], ratio[order]
    for k in range(along.size - 1):
        if (values[k] - 1.0) * (values[k + 1] - 1.0) < 0.0:
            t = (1.0 - values[k]) / (values[k + 1] - values[k])
            crossing = along[k] + t * (along[k + 1] - along[k])
            draw = axis.axvline if np.unique(y).size == 1 else axis.axhline
            draw(crossing, color="m", lw=1.4, label="crack-nucleation boundary (ratio = 1)")


def fatigue_figures(study: Results) -> list[tuple[str, object]]:
    """(file name, figure) of the fatigue figures (none without fatigue results)."""
    if not has_fatigue(study):
        return []
    return [
        ("fatigue_maps.png", _maps_figure(study)),
        ("fatigue_history.png", _history_figure(study)),
    ]


def crack_points(study: Results, x_of, y_of) -> list[tuple[float, float, float]]:
    """(x, y, crack ratio) of every case with fatigue results, for :func:`draw_crack_boundary`."""
    return [(x_of(case), y_of(case), crack_ratio(study, case)) for case in study.completed]
