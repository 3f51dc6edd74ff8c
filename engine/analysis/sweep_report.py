"""Report tables of studies with swept dotted keys, from the summary table.

``python -m engine report RESULTS.h5`` prints these for a study whose ``[sweep]`` has dotted
keys (``"loading.load"``, ``"mesh.n"``, ``"punch.edge_radius"``, …):

- per swept key, the main summary columns against its values, one block per combination of
  the other parameters (:func:`key_table`);
- ``loading.load`` swept: wear volume and maximum wear depth against the load with the
  exponent of the least-squares power law V ∝ P^m (:func:`load_table`);
- ``mesh.n`` swept: every numeric summary column against n, the relative change between
  successive meshes and the observed order p = log2(|Δ_coarse| / |Δ_fine|) for halved
  elements, with a verdict: "constant", "settled" (the last two changes below 0.5 %),
  "converging" (the absolute changes shrink), "not converging" (the sharp punch's edge values), "–"
  with too few meshes (:func:`convergence_table`).

The columns' units are those of the summary (engine/output/summary.py); lengths in mm,
stresses in MPa, wear volume in mm³.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from engine.output.ensemble import SEED
from engine.output.summary import column_unit
from engine.schema import PARAMETERS, SUMMARY_COLUMNS, CaseStatus, contact_units

from .names import key_label, key_title, value_text

__all__ = ["sweep_report", "key_table", "load_table", "convergence_table", "power_law_exponent"]

# Results only: a case's run time depends on the machine and its load (the summary CSV keeps
# it), and these tables are pasted into the manual (``--update``).
_MAIN_COLUMNS = [
    "approach", "max_wear_depth", "wear_volume", "vm_max", "vm_sub_max", "vm_sub_max_z",
    "stick_fraction",
]  # fmt: skip
_PARAMETERS = list(PARAMETERS)
_NOT_CONVERGENCE = {"case_id", "status", *PARAMETERS, "cycles"}


def _completed(summary: pd.DataFrame) -> pd.DataFrame:
    return summary[summary["status"] == str(CaseStatus.COMPLETED)]


def _groups(summary: pd.DataFrame, key: str, swept: Sequence[str]):
    """(label, rows sorted by ``key``) for each combination of the other parameters."""
    others = [c for c in _PARAMETERS + list(swept) if c != key and summary[c].nunique() > 1]
    if not others:
        yield "", summary.sort_values(key)
        return
    for values, rows in summary.groupby(others, sort=True):
        values = values if isinstance(values, tuple) else (values,)
        label = ", ".join(
            f"{name} = {value_text(value)}" for name, value in zip(others, values, strict=True)
        )
        yield label, rows.sort_values(key)


def _header(columns: list[str]) -> list[str]:
    return ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]


def _named(column: str, line: bool = False) -> str:
    unit = column_unit(column, line)
    return f"{column} ({unit})" if unit else column


def _number(value) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    return value_text(value, ".5g")


def key_table(
    summary: pd.DataFrame, key: str, swept: Sequence[str], line: bool = False
) -> list[str]:
    """The main columns against the values of the swept ``key`` (``line``: a line contact's
    study, its forces, energies and volumes per unit length)."""
    columns = [c for c in _MAIN_COLUMNS if c in summary]
    lines = [f"#### Against {key_title(key)}", ""]
    for label, rows in _groups(_completed(summary), key, swept):
        if label:
            lines += [f"{label}:", ""]
        lines += _header([key_label(key, line)] + [_named(c, line) for c in columns])
        for _, row in rows.iterrows():
            lines.append("| " + " | ".join(_number(row[c]) for c in [key, *columns]) + " |")
        lines.append("")
    return lines


def power_law_exponent(x: Sequence[float], y: Sequence[float]) -> float:
    """m of the least-squares fit log y = m log x + c (NaN with fewer than 2 positive pairs)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    keep = (x > 0) & (y > 0)
    if np.count_nonzero(keep) < 2:
        return math.nan
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def load_table(summary: pd.DataFrame, swept: Sequence[str], line: bool = False) -> list[str]:
    """Wear volume and depth against the load, with the fitted exponents (``line``: a line
    contact's study, per unit length)."""
    load, volume = contact_units("N", line), contact_units("mm³", line)
    key = "loading.load"
    lines = ["#### Wear against the load", ""]
    for label, rows in _groups(_completed(summary), key, swept):
        if label:
            lines += [f"{label}:", ""]
        lines += _header([f"P ({load})", f"wear volume ({volume})", "V/V(P_min)",
                          "max wear depth (µm)", "p0 (MPa)", "stick fraction"])  # fmt: skip
        first = rows["wear_volume"].iloc[0]
        for _, row in rows.iterrows():
            ratio = row["wear_volume"] / first if first else math.nan
            lines.append(
                f"| {row[key]:g} | {row['wear_volume']:.4g} | {ratio:.3g} | "
                f"{row['max_wear_depth'] * 1e3:.4g} | {row['p0']:.4g} | "
                f"{row['stick_fraction']:.3f} |"
            )
        volume = power_law_exponent(rows[key], rows["wear_volume"])
        depth = power_law_exponent(rows[key], rows["max_wear_depth"])
        lines += ["", f"Least-squares power laws: wear volume ∝ P^{volume:.2f}, maximum wear "
                  f"depth ∝ P^{depth:.2f}.", ""]  # fmt: skip
    return lines


SETTLED = 0.005  # relative change below which a column counts as settled


def _verdict(values: list[float]) -> str:
    """constant | settled (last two relative changes < 0.5 %) | converging (the absolute
    changes shrink) | not converging | – (fewer than three finite values)."""
    finite = [v for v in values if math.isfinite(v)]
    if len(finite) < 3:
        return "–"
    steps = [abs(b - a) for a, b in zip(finite[:-1], finite[1:], strict=True)]
    if all(step == 0.0 for step in steps):
        return "constant"
    relative = [step / abs(b) if b else math.inf for step, b in zip(steps, finite[1:], strict=True)]
    if all(change < SETTLED for change in relative[-2:]):
        return "settled (< 0.5 %)"
    shrinking = all(b < a for a, b in zip(steps[:-1], steps[1:], strict=True))
    return "converging" if shrinking else "not converging"


def convergence_table(summary: pd.DataFrame, swept: Sequence[str], line: bool = False) -> list[str]:
    """Every numeric summary column against ``mesh.n``: values, relative changes between
    successive meshes, observed order (for n doubling), verdict (``line``: a line contact's
    study, per unit length)."""
    key = "mesh.n"
    lines = ["#### Convergence with the mesh", ""]
    numeric = [
        c for c in summary.columns
        if c not in _NOT_CONVERGENCE and c != key and c not in swept
        and pd.api.types.is_numeric_dtype(summary[c])
    ]  # fmt: skip
    for label, rows in _groups(_completed(summary), key, swept):
        if label:
            lines += [f"{label}:", ""]
        sizes = [int(n) for n in rows[key]]
        steps = [f"Δ {a}→{b}" for a, b in zip(sizes[:-1], sizes[1:], strict=True)]
        lines += _header(["column"] + [f"n = {n}" for n in sizes] + steps + ["order", "verdict"])
        for column in numeric:
            values = [float(v) for v in rows[column]]
            if column.endswith(("_x", "_y")):  # mirror-symmetric peaks: compare |x|, |y|
                values = [abs(v) for v in values]
            changes = [
                (b - a) / abs(b) if b else math.nan
                for a, b in zip(values[:-1], values[1:], strict=True)
            ]
            order = math.nan
            doubling = all(b == 2 * a for a, b in zip(sizes[:-1], sizes[1:], strict=True))
            if len(changes) >= 2 and doubling:
                absolute = [abs(b - a) for a, b in zip(values[:-1], values[1:], strict=True)]
                if absolute[-1] > 0 and absolute[-2] > 0:
                    order = math.log2(absolute[-2] / absolute[-1])
            cost = column in ("runtime_s", "matvecs", "load_steps")
            lines.append(
                f"| {_named(column, line)} | " + " | ".join(_number(v) for v in values) + " | "
                + " | ".join("–" if not math.isfinite(c) else f"{c:+.2%}" for c in changes)
                + f" | {_number(order)} | {'cost' if cost else _verdict(values)} |"
            )  # fmt: skip
        lines.append("")
    lines += [
        "Δ: relative change from the coarser to the finer mesh; order: log2 of the ratio of "
        "the last two absolute changes (n doubling); peak locations _x, _y compared in "
        "absolute value (the peak may jump between mirror-symmetric points); cost columns "
        "are not expected to converge.",
        "",
    ]
    return lines


def sweep_report(
    summary: pd.DataFrame, swept: Sequence[str], title: str = "", line: bool = False
) -> str:
    """Markdown of all sweep tables of a study's ``summary`` (``line``: a line contact's
    study, its forces, energies and volumes per unit length)."""
    lines = [f"### {title}", ""] if title else []
    done = _completed(summary)
    names = ", ".join(key_title(key) for key in swept)
    lines.append(f"{len(done)} of {len(summary)} cases completed; swept: {names}.")
    lines.append("")
    if "loading.load" in swept:
        lines += load_table(summary, swept, line)
    if "mesh.n" in swept:
        lines += convergence_table(summary, swept, line)
    for key in swept:
        if key != SEED:  # realisations, not a parameter: the ensemble table gives their statistics
            lines += key_table(summary, key, swept, line)
    return "\n".join(lines) + "\n"


assert set(_MAIN_COLUMNS) <= set(SUMMARY_COLUMNS)
