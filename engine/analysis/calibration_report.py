"""The calibration's report (text) and figure (predicted against measured thresholds).

``python -m engine report RESULTS.h5`` on a calibration's results file prints
:func:`calibration_report`: the fitted values and how the fit ended, the table of tests
(measured, predicted, error, role, status) and the median and largest |error| of the
predicted tests. ``python -m engine plot RESULTS.h5`` draws ``calibration.png``
(:func:`draw_calibration`): every converged test's predicted threshold against its measured
one, the 1:1 line with ±10 % and ±20 % bands, calibration tests filled, predicted tests open;
a test whose threshold lies outside its search's bracket as an arrow-head at the bracket's
end (▼: below it, ▲: above).
"""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np

from engine.output.calibration import CALIBRATION_GROUP, load_calibration

__all__ = [
    "has_calibration",
    "calibration_report",
    "draw_calibration",
    "calibration_figures",
    "error_summary",
]


def has_calibration(path: str | Path) -> bool:
    """Whether ``path`` is a results file holding a calibration table."""
    path = Path(path)
    if path.suffix.lower() not in (".h5", ".hdf5") or not path.is_file():
        return False
    with h5py.File(path, "r") as file:
        return CALIBRATION_GROUP in file


def outside(frame) -> list[tuple[str, str, float]]:
    """The tests whose threshold lies outside their search's bracket: (id, ``"<"`` or
    ``">"``, the bracket's end), from the column's values at the ends and the target."""
    found = []
    target = frame.attrs.get("target", math.nan)
    for row in frame.itertuples(index=False):
        if row.status != "not-bracketed" or math.isnan(row.lower_value):
            continue
        below = row.lower_value > target  # the column already past the target at the low end
        found.append((row.id, "<" if below else ">", row.lower if below else row.upper))
    return found


def error_summary(frame) -> tuple[float, float, int]:
    """(median |error|, largest |error|, count) over the predicted tests whose search
    converged (NaN, NaN, 0 without any)."""
    predicted = frame[(frame["role"] == "predict") & frame["error"].notna()]
    errors = np.abs(predicted["error"].to_numpy(dtype=float))
    if errors.size == 0:
        return math.nan, math.nan, 0
    return float(np.median(errors)), float(errors.max()), int(errors.size)


def calibration_report(path: str | Path) -> str:
    """The report of a calibration's results file or CSV (module docstring), Markdown."""
    frame = load_calibration(path)
    units = frame.attrs["units"]
    unit = units.get("measured", "")
    lines = [f"# Calibration: {Path(path).name}", ""]
    fitted = frame.attrs.get("fitted", {})
    fitted_units = frame.attrs.get("fitted_units", {})
    status = frame.attrs.get("fit_status", "")
    if fitted:
        shown = ", ".join(
            f"{key} = {value:.6g} {fitted_units.get(key, '')}".rstrip()
            for key, value in fitted.items()
        )
        lines.append(f"Fitted: {shown} (fit {status}).")
    else:
        lines.append(f"Nothing fitted (fit {status}).")
    message = frame.attrs.get("fit_message", "")
    if message and status != "converged":
        lines.append(f"Fit: {message}.")
    lines += [
        "",
        "| id | measured | predicted | error | role | status |",
        "|---|---|---|---|---|---|",
    ]
    bounds = {test: (side, end) for test, side, end in outside(frame)}
    for row in frame.itertuples(index=False):
        predicted = "" if math.isnan(row.predicted) else f"{row.predicted:.4g}"
        error = "" if math.isnan(row.error) else f"{100 * row.error:+.1f} %"
        if row.id in bounds:
            side, end = bounds[row.id]
            predicted, error = (
                f"{side} {end:.4g}",
                f"{side} {100 * (end / row.measured - 1):+.1f} %",
            )
        lines.append(
            f"| {row.id} | {row.measured:.4g} | {predicted} | {error} | {row.role} | {row.status} |"
        )
    lines.append("")
    median, largest, count = error_summary(frame)
    if count:
        lines.append(
            f"Predicted tests ({count}): median |error| {100 * median:.1f} %, largest "
            f"{100 * largest:.1f} % (thresholds in {unit})."
        )
    else:
        lines.append("No predicted test with a converged search.")
    for test, side, end in outside(frame):
        relation = "below" if side == "<" else "above"
        lines.append(
            f"{test}: the threshold lies {relation} the search's bracket ({side} {end:.4g} "
            f"{unit}); not counted above."
        )
    return "\n".join(lines)


def draw_calibration(path: str | Path):
    """The figure of ``calibration.png`` (module docstring)."""
    from matplotlib.figure import Figure  # no pyplot: nothing to close, no backend to set

    frame = load_calibration(path)
    unit = frame.attrs["units"].get("measured", "")
    figure = Figure(figsize=(5.5, 5.0))
    axes = figure.subplots()
    shown = frame[frame["predicted"].notna()]
    values = np.r_[frame["measured"].to_numpy(float), shown["predicted"].to_numpy(float)]
    top = 1.15 * float(np.nanmax(values)) if values.size else 1.0
    line = np.array([0.0, top])
    axes.plot(line, line, color="black", lw=1.0, label="1:1")
    for band, alpha in ((0.2, 0.10), (0.1, 0.18)):
        axes.fill_between(line, line * (1 - band), line * (1 + band), color="tab:blue",
                          alpha=alpha, lw=0, label=f"±{int(100 * band)} %")  # fmt: skip
    for role, face in (("calibrate", "tab:red"), ("predict", "none")):
        part = shown[shown["role"] == role]
        axes.scatter(part["measured"], part["predicted"], s=36, facecolors=face,
                     edgecolors="tab:red", label=f"{role} ({len(part)})", zorder=3)  # fmt: skip
        for row in part.itertuples(index=False):
            axes.annotate(str(row.id), (row.measured, row.predicted), fontsize=7,
                          xytext=(3, 3), textcoords="offset points")  # fmt: skip
    for test, side, end in outside(frame):  # a bound: an arrow-head at the bracket's end
        row = frame[frame["id"] == test].iloc[0]
        marker = "v" if side == "<" else "^"
        axes.scatter([row["measured"]], [end], marker=marker, s=36, facecolors="none",
                     edgecolors="tab:red", zorder=3)  # fmt: skip
        axes.annotate(f"{test} ({side})", (row["measured"], end), fontsize=7, xytext=(3, 3),
                      textcoords="offset points")  # fmt: skip
    suffix = f" ({unit})" if unit else ""
    axes.set(xlim=(0, top), ylim=(0, top), xlabel=f"measured threshold{suffix}",
             ylabel=f"predicted threshold{suffix}", aspect="equal")  # fmt: skip
    fitted = frame.attrs.get("fitted", {})
    title = ", ".join(f"{k.split('.')[-1]} = {v:.4g}" for k, v in fitted.items())
    title = title or "nothing fitted"
    axes.set_title(f"{title}\n(fit {frame.attrs.get('fit_status', '')})", fontsize=9)
    axes.legend(fontsize=8, loc="upper left")
    figure.tight_layout()
    return figure


def calibration_figures(path: str | Path, out_dir: str | Path) -> list[Path]:
    """Draw ``calibration.png`` into ``out_dir``; returns the paths written."""
    figure = draw_calibration(path)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    target = out_dir / "calibration.png"
    figure.savefig(target, dpi=130)
    return [target]
