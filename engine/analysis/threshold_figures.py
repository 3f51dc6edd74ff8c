"""The boundary curves of a study with a ``[search]`` section (``python -m engine plot``).

One figure, ``thresholds.png``: the searched parameter (vertical axis, e.g. the displacement
amplitude in mm) against the first swept key of the sweep (horizontal axis, e.g. the normal
load in N): the threshold of every search as a curve (one per combination of the other swept
values), each search's final bracket as an error bar, and every case the searches computed as
a point — filled where the deciding column is on the target's side (e.g. gross slip), open on
the other (partial slip), crosses for failed cases. Searches that did not converge are marked
with their status. A study that sweeps nothing but the friction/wear lists draws the searches
side by side (horizontal axis: the search's position in the table).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from engine.output.summary import column_unit, load_summary
from engine.output.thresholds import SEARCH_COLUMNS, load_thresholds
from engine.schema import THRESHOLDS_GROUP

__all__ = ["has_thresholds", "threshold_figures"]

_NOT_SWEPT = {"case_id", "mu1", "mu2", "wear1", "wear2", "beta", "alpha"}


def has_thresholds(path: str | Path) -> bool:
    """Whether the results file holds a thresholds table (a ``[search]`` study)."""
    with h5py.File(path, "r") as file:
        return THRESHOLDS_GROUP in file


def _label(key: str) -> str:
    unit = column_unit(key)
    return f"{key} ({unit})" if unit else key


def _far_side(values, spec: dict) -> np.ndarray:
    """True where the column is on the target's side (text: equal; numeric: above)."""
    target = spec["target"]
    if isinstance(target, str):
        return np.asarray([value == target for value in values])
    return np.asarray(values, dtype=float) > float(target)


def threshold_figures(path: str | Path, out_dir: str | Path) -> list[Path]:
    """Draw ``thresholds.png`` into ``out_dir``; returns the paths written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    table = load_thresholds(path)
    spec = table.attrs["search"]
    parameter = spec["parameter"]
    summary = load_summary(path)
    swept = [key for key in table.columns if key not in _NOT_SWEPT | set(SEARCH_COLUMNS)]
    across = swept[0] if swept else None
    figure, axis = plt.subplots(figsize=(7.0, 4.8), layout="constrained")
    groups = table.groupby(swept[1:], sort=False) if len(swept) > 1 else [("", table)]
    for number, (key, group) in enumerate(groups):
        x = group[across] if across else group.index.to_numpy(dtype=float)
        label = f"{', '.join(swept[1:])} = {key}" if len(swept) > 1 else "threshold"
        below = group["threshold"] - group["lower"]
        above = group["upper"] - group["threshold"]
        axis.errorbar(
            x, group["threshold"], yerr=[below, above], fmt="-", color=f"C{number}",
            capsize=3, label=label,
        )  # fmt: skip
        _draw_cases(axis, summary, group, across, parameter, spec, f"C{number}")
        for _, row in group[group["status"] != "converged"].iterrows():
            where = row[across] if across else row.name
            axis.annotate(row["status"], (where, row["upper"]), fontsize=8, color="C3")
    axis.set_xlabel(_label(across) if across else "search")
    axis.set_ylabel(_label(parameter))
    axis.grid(alpha=0.3)
    axis.legend(fontsize=8)
    axis.set_title(
        f"{Path(path).stem}: {parameter} at which {spec['column']} reaches {spec['target']!r}"
        "\nfilled: target side, open: other side, ×: failed; bars: final bracket"
    )
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    target = out_dir / "thresholds.png"
    figure.savefig(target, dpi=120)
    plt.close(figure)
    return [target]


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
