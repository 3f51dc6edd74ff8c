"""Figures of studies that sweep dotted keys (load, modulus, mesh, punch radius, amplitude …).

``python -m engine plot RESULTS.h5`` draws, for every swept dotted key ``K`` (a text key's
values as categories), the figure ``sweep_<K>.png``: each summary quantity of the completed
cases against the values of ``K``, one line per combination of the other swept parameters
(μ, wear coefficient, β and the other dotted keys), in the summary's units
(engine/output/summary.py) except wear depth and approach, drawn in µm. A study sweeping
``surface.seed`` gets none: its seeds are realisations, and :mod:`.surface_figures` draws
the means over them with their 95 % bands against the other keys. The quantities (those the
study has values for):

cyclic and static studies
    maximum wear depth, wear volume, σ_VM maximum over the x–z plane and below its surface
    layer, the depth of the latter, stick fraction at peak load, approach g_n;
fretting studies
    the same, and the tangential force amplitude Q*, the energy dissipated per cycle and the
    slip regime (partial or gross slip).

The same numbers as the tables of ``python -m engine report`` (:mod:`.sweep_report`, which
groups the cases the same way). The per-case field figures of such a study use that case's
own a0, p0 and grid: ``python -m engine plot RESULTS.h5 --case ID``.
"""

from __future__ import annotations

from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from engine.output.ensemble import SEED
from engine.output.summary import column_unit, load_summary

from .names import key_label, key_title
from .results import Results
from .sweep_report import _completed, _groups

__all__ = [
    "SWEEP_QUANTITIES",
    "SweepQuantity",
    "sweep_figures",
    "key_title",
    "key_label",
    "readable_log_axis",
    "key_positions",
    "text_categories",
]

_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">")


@dataclass(frozen=True)
class SweepQuantity:
    """A summary column drawn against a swept key: its name, scale to the drawn unit, the
    drawn unit and (slip regime) the names of its codes."""

    column: str
    name: str
    scale: float = 1.0
    unit: str | None = None  # None: the summary's unit of the column
    categories: tuple[str, ...] = ()

    def label(self, line: bool = False) -> str:
        """ "name (unit)"; ``line``: a line contact's unit (per unit length)."""
        unit = column_unit(self.column, line) if self.unit is None else self.unit
        unit = unit.replace("^3", "³").replace("^2", "²")
        return f"{self.name} ({unit})" if unit else self.name


SWEEP_QUANTITIES = (
    SweepQuantity("max_wear_depth", "maximum wear depth", 1e3, "µm"),
    SweepQuantity("wear_volume", "wear volume"),
    SweepQuantity("vm_max", "σ_VM max, x–z plane"),
    SweepQuantity("vm_sub_max", "σ_VM max below the surface layer"),
    SweepQuantity("vm_sub_max_z", "its depth z"),
    SweepQuantity("stick_fraction", "stick fraction at peak load", unit=""),
    SweepQuantity("approach", "approach g_n", 1e3, "µm"),
    SweepQuantity("q_amplitude", "tangential force amplitude Q*"),
    SweepQuantity("energy_per_cycle", "energy dissipated per cycle"),
    SweepQuantity("slip_regime", "slip regime", unit="", categories=("partial", "gross")),
)


def _present(rows: pd.DataFrame) -> list[SweepQuantity]:
    """The quantities with at least one finite non-zero value in ``rows`` (a static study
    has no wear: its wear panels would be flat lines at zero)."""
    present = []
    for quantity in SWEEP_QUANTITIES:
        if quantity.column not in rows:
            continue
        values = pd.to_numeric(rows[quantity.column], errors="coerce").to_numpy(float)
        if quantity.categories or np.any(np.isfinite(values) & (values != 0.0)):
            present.append(quantity)
    return present


def _plotted(column: pd.Series, quantity: SweepQuantity) -> np.ndarray:
    """The values drawn for ``quantity``: categories as their index on the axis (an unknown
    category as a gap), numbers in the quantity's display unit."""
    if quantity.categories:
        index = {category: number for number, category in enumerate(quantity.categories)}
        return np.array([index.get(value, np.nan) for value in column], dtype=float)
    return pd.to_numeric(column, errors="coerce").to_numpy(float) * quantity.scale


def readable_log_axis(axis, which: str = "x") -> None:
    """Major ticks at 1, 2, 5 × 10^k labelled as plain numbers ("0.002", not "2×10⁻³"),
    minor ticks unlabelled: matplotlib's default labels every minor tick on a short log
    range, and the labels run together."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    target = axis.xaxis if which == "x" else axis.yaxis
    target.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    target.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
    target.set_minor_formatter(NullFormatter())


def _same_as(groups, drawn: dict[int, np.ndarray], data: np.ndarray, x: np.ndarray) -> int | None:
    """The index of an earlier group drawn with the same x and values (to 1e-9 relative:
    round-off), or None."""
    for number, (earlier_x, earlier) in drawn.items():
        if earlier_x.shape == x.shape and np.allclose(earlier_x, x, rtol=1e-12, atol=0.0):
            if np.allclose(earlier, data, rtol=1e-9, atol=0.0, equal_nan=True):
                return number
    return None


def key_positions(values: pd.Series, categories: list | None = None) -> np.ndarray:
    """Where the values of a swept key sit on an x axis: the numbers themselves, or a text
    key's values (a swept ``surface.path`` …) at 0, 1, 2 … in the order of ``categories``
    (:func:`text_categories`)."""
    if categories is None:
        return values.astype(float).to_numpy()
    return values.map({value: number for number, value in enumerate(categories)}).to_numpy(float)


def text_categories(values: pd.Series) -> list | None:
    """The sorted distinct values of a text key's column, None for a numeric one."""
    if pd.api.types.is_numeric_dtype(values):
        return None
    return sorted(values.dropna().unique())


def sweep_figure(summary: pd.DataFrame, key: str, swept: list[str], title: str, line: bool = False):
    """One panel per quantity against ``key`` (a text key's values as categories); one line
    per combination of the others (``line``: a line contact's study, its units per unit
    length)."""
    rows = _completed(summary)
    quantities = _present(rows)
    columns = min(3, max(len(quantities), 1))
    count = -(-len(quantities) // columns)
    figure, axes = plt.subplots(
        count, columns, figsize=(4.4 * columns + 2.6, 3.3 * count), squeeze=False,
        layout="constrained",
    )  # fmt: skip
    categories = text_categories(rows[key])
    values = pd.Series(key_positions(rows[key], categories))
    logarithmic = categories is None and bool(
        (values > 0).all() and values.max() >= 10.0 * values.min()
    )
    groups = list(_groups(rows, key, swept))
    hidden = set()  # groups whose curve lies on an earlier one in some panel
    for axis, quantity in zip(axes.flat, quantities, strict=False):
        drawn: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        for number, (label, group) in enumerate(groups):
            data = _plotted(group[quantity.column], quantity)
            x = key_positions(group[key], categories)
            style = {"marker": _MARKERS[number % len(_MARKERS)], "ms": 5, "lw": 1.4}
            same = _same_as(groups, drawn, data, x)
            if same is not None:  # on top of an earlier curve: dashed, hollow, larger
                hidden.add(number)
                style.update(ls="--", mfc="none", ms=9, lw=1.2)
            axis.plot(x, data, color=f"C{number % 10}", label=label or "all cases", **style)
            drawn[number] = (x, data)
        if quantity.categories:
            axis.set_yticks(range(len(quantity.categories)), quantity.categories)
            axis.set_ylim(-0.5, len(quantity.categories) - 0.5)
        if logarithmic and axis.has_data():
            axis.set_xscale("log")
            readable_log_axis(axis, "x")
        if categories is not None:
            axis.set_xticks(range(len(categories)), categories, rotation=20, ha="right")
        axis.set_xlabel(key_label(key, line))
        axis.set_ylabel(quantity.label(line))
        axis.grid(alpha=0.3, which="both")
    for axis in axes.flat[len(quantities) :]:
        axis.set_visible(False)
    if len(groups) > 1 or groups[0][0]:
        handles, labels = axes.flat[0].get_legend_handles_labels()
        figure.legend(handles, labels, loc="outside right upper", title="other parameters")
    name = key_title(key)
    suptitle = f"{title}: summary against {name} ({len(rows)} completed cases)"
    if hidden:
        suptitle += "\ndashed hollow markers: a curve equal to an earlier one, drawn on top of it"
    figure.suptitle(suptitle)
    return figure


def sweep_figures(study: Results):
    """(file name, figure) of ``sweep_<key>.png`` for every swept dotted key, one at a time.
    None for a study sweeping ``surface.seed``: its seeds are realisations, not a parameter,
    and :mod:`.surface_figures` draws the means over them with their bands against the
    other keys instead."""
    keys = study.swept_keys
    if not keys or SEED in keys:
        return
    summary = load_summary(study.path)
    if _completed(summary).empty:
        return
    for key in keys:
        if _completed(summary)[key].nunique() < 2:
            continue  # one value among the completed cases: nothing to draw against
        figure = sweep_figure(summary, key, keys, study.name, study.profile.is_line)
        yield f"sweep_{key}.png", figure
