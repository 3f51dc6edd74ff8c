"""The field figures of one fretting case (``python -m engine plot RESULTS.h5 --case ID``).

A fretting case stores, at every recorded cycle N, its surface fields at the increment of
the largest |Q| on the +Q* side of the loop (``engine.solvers.fretting``): wear depth,
pressure, tractions and each element's state (no contact, stick, slip), and the x–z stress
plane there; and each element's state at −Q* (``status_minus_q``). For one case these
figures show them:

- ``surface_N<N>.png`` — a 3-D contact (punch, sphere): maps over the mesh of the wear depth
  (µm), p/p0 at +Q* and the slip/stick state at +Q* and at −Q*; a line contact (cylinder,
  pad): profiles along x/a of the wear depth, p/p0 and q_x/p0 at +Q* with the stick zone
  shaded, and strips of the state at +Q* and −Q*;
- ``von_mises_N<N>.png`` — σ_VM/p0 on the x–z plane at +Q*
  (:func:`engine.analysis.figures.von_mises_plane_figure`).

The criterion planes of a study with ``[fatigue]`` are drawn by
:mod:`engine.analysis.fatigue_figures`. Lengths are in units of a (the contact radius or
half-width at the case's load, ``study.radius``), stresses in units of p0 (``study.p0``).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.patches import Patch

from .figures import MIN_FIGURE_WIDTH, von_mises_plane_figure
from .results import Results

__all__ = ["case_field_figures", "STATE_NAMES"]

# Element states of the contact solver (engine.solvers.increment: NO_CONTACT, STICK, SLIP).
STATE_NAMES = ("no contact", "stick", "slip")
_STATE_COLOURS = ("#d9d9d9", "#2166ac", "#d6604d")


def case_field_figures(study: Results):
    """(file name, figure) of the field figures of the one case of ``study`` (nothing for a
    study of several cases: their figures compare cases; ``--case`` selects one)."""
    if len(study.completed) != 1:
        return
    case = study.completed[0]
    cycles = case.recorded_cycles
    if not cycles:
        return
    last = cycles[-1]
    fields = case.fields[last]
    if study.profile.is_line:
        yield f"surface_N{last}.png", _line_profiles(study, fields, last)
    else:
        yield f"surface_N{last}.png", _surface_maps(study, fields, last)
    for cycle in cycles:
        if cycle in case.planes:
            title = _title(study, f"σ_VM/p0 in the x–z plane at +Q*, N = {cycle:,}")
            yield f"von_mises_N{cycle}.png", von_mises_plane_figure(study, cycle, title)


def _title(study: Results, what: str) -> str:
    case = study.completed[0]  # the name of a one-case study names the case
    return f"{study.name}: {what}\n{case.label}, {study.mesh_label}"


def _state_map():
    cmap = ListedColormap(_STATE_COLOURS)
    return cmap, BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)


def _state_counts(status: np.ndarray) -> str:
    counts = [int(np.count_nonzero(status == code)) for code in range(3)]
    return f"{counts[1]} stick, {counts[2]} slip elements"


def _state_handles(alpha: float = 1.0) -> list[Patch]:
    return [
        Patch(color=colour, alpha=alpha, label=name)
        for colour, name in zip(_STATE_COLOURS, STATE_NAMES, strict=True)
    ]


def _surface_maps(study: Results, fields: dict, cycle: int):
    """Wear depth and p/p0 (top), the stick/slip state at +Q* and at −Q* (bottom) over the
    mesh; a file without the −Q* state (``status_minus_q``) leaves its panel out."""
    a, p0 = study.radius, study.p0
    x, y = study.grid_x / a, study.grid_y / a
    states = [("+Q*", fields["status"])]
    if "status_minus_q" in fields:
        states.append(("−Q*", fields["status_minus_q"]))
    figure, axes = plt.subplots(
        2, 2, figsize=(MIN_FIGURE_WIDTH + 1.5, 9.0), layout="constrained", squeeze=False
    )
    wear = fields["wear"] * 1e3  # µm
    panels = (
        (wear, "viridis", "wear depth (µm)", "wear depth"),
        (fields["pressure"] / p0, "magma", "p / p0", "pressure at +Q*"),
    )
    for axis, (values, cmap, label, title) in zip(axes[0], panels, strict=True):
        top = float(np.max(values)) or 1.0
        mesh = axis.pcolormesh(x, y, values.T, cmap=cmap, vmin=0.0, vmax=top, shading="nearest")
        figure.colorbar(mesh, ax=axis, label=label, shrink=0.85)
        axis.set_title(title)
    cmap, norm = _state_map()
    for axis, (where, status) in zip(axes[1], states, strict=False):
        axis.pcolormesh(x, y, status.T, cmap=cmap, norm=norm, shading="nearest")
        axis.set_title(f"state at {where}: {_state_counts(status)}")
    if len(states) == 1:
        axes[1, 1].set_visible(False)
    figure.legend(handles=_state_handles(), loc="outside lower center", ncols=3, fontsize=9)
    for axis in axes.ravel():
        axis.set_aspect("equal")
        axis.set_xlabel("x/a")
        axis.set_ylabel("y/a")
    figure.suptitle(
        _title(study, f"surface after N = {cycle:,} cycles: fields at +Q*, state at ±Q*")
    )
    return figure


def _line_profiles(study: Results, fields: dict, cycle: int):
    """Wear depth, p/p0 and q_x/p0 along x/a with the stick zone shaded (a line contact)."""
    a, p0 = study.radius, study.p0
    x = study.grid_x / a
    figure, (wear_axis, stress_axis, state_axis) = plt.subplots(
        3,
        1,
        figsize=(MIN_FIGURE_WIDTH, 7.6),
        sharex=True,
        layout="constrained",
        height_ratios=[3, 3, 1.2],
    )
    wear_axis.plot(x, fields["wear"][:, 0] * 1e3, color="C2", lw=1.6)
    wear_axis.set_ylabel("wear depth (µm)")
    wear_axis.set_title("wear scar of the flat")
    stress_axis.plot(x, fields["pressure"][:, 0] / p0, color="C0", lw=1.6, label="p / p0")
    stress_axis.plot(
        x, fields["traction_x"][:, 0] / p0, color="C3", lw=1.4, ls="--", label="q_x / p0"
    )
    status = fields["status"][:, 0]
    step = float(x[1] - x[0]) if x.size > 1 else 1.0
    for code, colour in ((1, _STATE_COLOURS[1]), (2, _STATE_COLOURS[2])):
        for start, stop in _runs(status == code):
            stress_axis.axvspan(
                x[start] - step / 2, x[stop - 1] + step / 2, color=colour, alpha=0.15, lw=0
            )
    handles, _ = stress_axis.get_legend_handles_labels()
    handles += [
        Patch(color=_STATE_COLOURS[1], alpha=0.3, label="stick"),
        Patch(color=_STATE_COLOURS[2], alpha=0.3, label="slip"),
    ]
    figure.legend(handles=handles, loc="outside lower center", ncols=4, fontsize=9)
    stress_axis.axhline(0.0, color="k", lw=0.6)
    stress_axis.set_ylabel("stress / p0")
    stress_axis.set_title("pressure and shear traction at +Q*; shaded: stick and slip zones")
    _state_strips(state_axis, x, fields)
    state_axis.set_xlabel("x/a")
    for axis in (wear_axis, stress_axis):
        axis.grid(alpha=0.3)
    figure.suptitle(_title(study, f"surface after N = {cycle:,} cycles"))
    return figure


def _state_strips(axis, x: np.ndarray, fields: dict) -> None:
    """The element states along x/a at +Q* and (when stored) −Q*, one strip each."""
    cmap, norm = _state_map()
    rows = [("+Q*", fields["status"][:, 0])]
    if "status_minus_q" in fields:
        rows.append(("−Q*", fields["status_minus_q"][:, 0]))
    states = np.array([status for _, status in rows])
    axis.pcolormesh(x, np.arange(len(rows)), states, cmap=cmap, norm=norm, shading="nearest")
    axis.set_yticks(range(len(rows)), [f"at {where}" for where, _ in rows])
    axis.invert_yaxis()
    counts = "; ".join(f"{where}: {_state_counts(status)}" for where, status in rows)
    axis.set_title(f"state: {counts}", fontsize=10)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, stop) index ranges where ``mask`` is True."""
    edges = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True))
