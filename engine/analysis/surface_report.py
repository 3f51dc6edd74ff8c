"""The ensemble table of a study sweeping ``surface.seed``, in Markdown (``python -m engine
report``): for every combination of the other swept keys, the realisations and the mean ± the
half-width of the 95 % confidence interval of the mean of the columns that say what the
roughness changes (:mod:`.ensemble`)."""

from __future__ import annotations

import argparse
import math

from engine.output.ensemble import SEED, ensemble_frame
from engine.output.summary import load_summary

from .markdown import measured_on, replace_block
from .names import value_text
from .results import open_results

__all__ = ["surface_report"]

COLUMNS = (
    ("real_area_fraction", "A_r / A_0", 1.0, "{:.3f}"),
    ("contact_spots", "spots", 1.0, "{:.1f}"),
    ("real_peak_pressure", "p_max (MPa)", 1.0, "{:.0f}"),
    ("q_amplitude", "Q* (N)", 1.0, "{:.2f}"),
    ("energy_per_cycle", "E_d (mJ)", 1.0, "{:.4f}"),
    ("wear_volume", "V (10⁻³ mm³)", 1e3, "{:.4f}"),
    ("max_wear_depth", "h_max (µm)", 1e3, "{:.3f}"),
    ("vm_max", "σ_VM max (MPa)", 1.0, "{:.0f}"),
    ("rms_height_worn", "h_rms worn (µm)", 1e3, "{:.3f}"),
)


def _cell(row, column: str, scale: float, form: str) -> str:
    mean = row[f"{column}_mean"] * scale
    half = (row[f"{column}_ci_high"] - row[f"{column}_mean"]) * scale
    if not math.isfinite(mean):
        return "–"
    if not math.isfinite(half):
        return form.format(mean)
    return f"{form.format(mean)} ± {form.format(half)}"


def surface_report(study) -> str:
    """The Markdown table (empty text when the study does not sweep ``surface.seed``)."""
    if "surface" not in study.study or SEED not in study.swept_keys:
        return ""

    ensemble = ensemble_frame(load_summary(study.path))
    keys = [key for key in study.swept_keys if key != SEED]
    columns = [c for c in COLUMNS if f"{c[0]}_mean" in ensemble]
    header = [*keys, "realisations", *(name for _, name, _, _ in columns)]
    lines = [
        "",
        f"Over the realisations ({SEED}): mean ± half-width of the 95 % confidence interval "
        "of the mean (Student's t).",
        "",
        "| " + " | ".join(header) + " |",
        "|" + "---|" * len(header),
    ]
    for _, row in ensemble.sort_values(keys).iterrows():
        cells = [value_text(row[key]) for key in keys] + [str(int(row["realisations"]))]
        cells += [_cell(row, column, scale, form) for column, _, scale, form in columns]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    """``python -m engine.analysis.surface_report RESULTS.h5 [--update DOC.md]``: print the ensemble
    table, or write it into the block ``<!-- BEGIN report NAME-ensemble -->`` of DOC.md."""
    parser = argparse.ArgumentParser(prog="python -m engine.analysis.surface_report")
    parser.add_argument("results")
    parser.add_argument("--update", metavar="DOC.md")
    args = parser.parse_args(argv)
    study = open_results(args.results)
    text = surface_report(study)
    if not text:
        parser.error(f"{args.results}: the study does not sweep {SEED}")
    if args.update is None:
        print(text)
        return 0
    note = f"`python -m engine.analysis.surface_report {args.results} --update {args.update}`"
    replace_block(args.update, f"{study.name}-ensemble", measured_on(note) + text, kind="report")
    print(f"{args.update}: wrote the block {study.name}-ensemble")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
