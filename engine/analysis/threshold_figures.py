"""The boundary curves of a study with a ``[search]`` section (``python -m engine plot``).

One figure, ``thresholds.png``: the searched parameter (vertical axis, e.g. the displacement
amplitude in mm) against the first swept key of the sweep (horizontal axis, e.g. the normal
load in N): the threshold of every search as a curve (one per combination of the other swept
values, the friction and wear lists included: μ = 0.3 and 0.5 are two curves), each search's
final bracket as an error bar, and every case the searches computed as a point — filled where
the deciding column is on the target's side (e.g. gross slip), open on the other (partial
slip), crosses for failed cases. Searches that did not converge are marked with their status.
The horizontal axis is the first swept dotted key, else the first friction or wear list with
more than one value; a study with a single search draws it at position 0.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from engine.output.summary import column_unit, load_summary
from engine.output.thresholds import SEARCH_COLUMNS, load_thresholds
from engine.schema import THRESHOLDS_GROUP
from engine.study.units import case_parameters

from .sweep_figures import key_title

__all__ = ["has_thresholds", "threshold_figures", "draw_thresholds", "varying_keys"]

_LISTS = case_parameters()  # the [sweep] lists, in order
FONT_SIZE = 9.0  # points: the figures' smallest text (engine.analysis.figures.MIN_FONT_SIZE)


def has_thresholds(path: str | Path) -> bool:
    """Whether the results file holds a thresholds table (a ``[search]`` study)."""
    with h5py.File(path, "r") as file:
        return THRESHOLDS_GROUP in file


def _label(key: str, units: dict[str, str]) -> str:
    """ "name (unit)": the key's name in the study-file schema, in the unit the table stored
    (a line contact's per unit length)."""
    unit = units.get(key) or column_unit(key)
    unit = "°" if unit == "degree" else unit
    title = key_title(key)
    return f"{title} ({unit})" if unit and unit != "1" else title


def _far_side(values, spec: dict) -> np.ndarray:
    """True where the column is on the target's side (text: equal; numeric: above)."""
    target = spec["target"]
    if isinstance(target, str):
        return np.asarray([value == target for value in values])
    return np.asarray(values, dtype=float) > float(target)


def threshold_figures(path: str | Path, out_dir: str | Path) -> list[Path]:
    """Draw ``thresholds.png`` into ``out_dir``; returns the paths written."""
    figure = draw_thresholds(path)  # selects the Agg backend first
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    target = out_dir / "thresholds.png"
    figure.savefig(target, dpi=120)
    plt.close(figure)
    return [target]


def draw_thresholds(path: str | Path):
    """The figure of ``thresholds.png`` (module docstring): one errorbar curve per
    combination of the keys that tell the searches apart, the steps as points."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    table = load_thresholds(path)
    spec = table.attrs["search"]
    parameter = spec["parameter"]
    summary = load_summary(path)
    across, others = varying_keys(table)
    figure, axis = plt.subplots(figsize=(7.0, 4.8), layout="constrained")
    groups = table.groupby(others, sort=False) if others else [((), table)]
    for number, (key, group) in enumerate(groups):
        if across:
            group = group.sort_values(across, kind="stable")
        x = group[across] if across else group.index.to_numpy(dtype=float)
        values = key if isinstance(key, tuple) else (key,)
        label = (
            ", ".join(f"{name} = {value:g}" for name, value in zip(others, values, strict=True))
            if others
            else "threshold"
        )
        below = group["threshold"] - group["lower"]
        above = group["upper"] - group["threshold"]
        axis.errorbar(
            x, group["threshold"], yerr=[below, above], fmt="-", color=f"C{number}",
            capsize=3, label=label,
        )  # fmt: skip
        _draw_cases(axis, summary, group, across, parameter, spec, f"C{number}")
        for _, row in group[group["status"] != "converged"].iterrows():
            where = row[across] if across else row.name
            axis.annotate(row["status"], (where, row["upper"]), fontsize=FONT_SIZE, color="C3")
    units = table.attrs.get("units", {})
    axis.set_xlabel(_label(across, units) if across else "search")
    axis.set_ylabel(_label(parameter, units))
    axis.grid(alpha=0.3)
    axis.legend(fontsize=FONT_SIZE)
    axis.set_title(
        f"{Path(path).stem}: {key_title(parameter)} at which {spec['column']} reaches "
        f"{spec['target']!r}"
        "\nfilled: target side, open: other side, ×: failed; bars: final bracket"
    )
    return figure


def varying_keys(table) -> tuple[str | None, list[str]]:
    """The horizontal axis of the boundary curves and the keys that tell the curves apart:
    every sweep column of the thresholds table with more than one value (dotted keys first,
    then the [sweep] lists; mu2 and wear2 only where they differ from mu1 and wear1); the
    first of them is the axis (None: nothing varies)."""
    searched = set(SEARCH_COLUMNS) | {"case_id"}
    dotted = [key for key in table.columns if key not in searched and key not in _LISTS]
    lists = [key for key in _LISTS if key in table.columns]
    for second, first in (("mu2", "mu1"), ("wear2", "wear1")):  # isotropic: one of the two
        if second in lists and first in lists and table[second].equals(table[first]):
            lists.remove(second)
    varying = [key for key in dotted + lists if table[key].nunique(dropna=False) > 1]
    if not varying:
        return None, []
    return varying[0], varying[1:]


def _draw_cases(axis, summary, group, across, parameter, spec, colour) -> None:
    """Every step of the group's searches: at (swept value, parameter value)."""
    search_of = summary["case_id"].map(lambda case_id: case_id.rsplit("_", 1)[0])  # its base
    steps = summary[search_of.isin(set(group["case_id"]))]
    if across is None:
        position = dict(zip(group["case_id"], group.index.to_numpy(dtype=float), strict=True))
        x = steps["case_id"].map(lambda case_id: position[case_id.rsplit("_", 1)[0]])
    else:
        x = steps[across]
    completed = (steps["status"] == "completed").to_numpy()
    far = _far_side(steps[spec["column"]], spec) & completed
    near = ~far & completed
    y = steps[parameter]
    axis.plot(x[far], y[far], "o", color=colour, ms=4)
    axis.plot(x[near], y[near], "o", mfc="none", color=colour, ms=4)
    axis.plot(x[~completed], y[~completed], "x", color="C3", ms=5)
