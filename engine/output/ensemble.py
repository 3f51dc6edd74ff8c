"""Statistics over random realisations: the ensemble table of a study sweeping ``surface.seed``.

For every combination of the other swept keys and parameters (mu1, mu2, the wear law's
coefficients, beta and the dotted keys other than ``surface.seed``), over its completed cases:

- ``realisations``: how many completed (failed cases are left out and not counted);
- for every numeric summary column c: ``c_mean``, ``c_std`` (sample standard deviation,
  ddof = 1), ``c_ci_low`` and ``c_ci_high``, the 95 % confidence interval of the mean,
  mean ± t₀.₉₇₅,ₙ₋₁ s/√n (Student's t; NaN with one realisation).

The table is written as ``NAME_ensemble.csv`` beside the summary ``NAME.csv`` at the end of a
run (:func:`write_ensemble`) and computed from the summary by :func:`load_ensemble`; the
surface itself is :mod:`engine.surface`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from engine.study.units import case_parameters

from .space import OutputFull, free_bytes, is_no_space
from .summary import load_summary, summary_frame

SEED = "surface.seed"
STATISTICS = ("mean", "std", "ci_low", "ci_high")
#: Columns that are not statistics of the cases (identity, the wall time).
_SKIPPED = ("case_id", "status", SEED, "runtime_s")  # runtime_s: not reproducible
_PARAMETERS = case_parameters()

__all__ = ["ensemble_path", "ensemble_frame", "write_ensemble", "load_ensemble", "SEED"]


def ensemble_path(summary_path: str | Path) -> Path:
    """``NAME_ensemble.csv`` beside the summary ``NAME.csv``."""
    summary_path = Path(summary_path)
    return summary_path.with_name(f"{summary_path.stem}_ensemble.csv")


def ensemble_frame(summary):
    """The ensemble table (module docstring) of a summary DataFrame with a ``surface.seed``
    column; an empty frame when there is none."""
    import pandas as pd
    from scipy import stats

    if SEED not in summary:
        return pd.DataFrame()
    done = summary[summary["status"] == "completed"]
    keys = [
        c for c in summary.columns
        if c != SEED and (c in _PARAMETERS or "." in c) and summary[c].notna().any()
    ]  # fmt: skip
    numeric = [
        c for c in summary.columns
        if c not in _SKIPPED and c not in keys and pd.api.types.is_numeric_dtype(summary[c])
        and summary[c].notna().any()
    ]  # fmt: skip
    rows = []
    combinations = summary[keys].drop_duplicates() if keys else pd.DataFrame(index=[0])
    for _, combination in combinations.iterrows():
        mask = np.ones(len(done), dtype=bool)
        for key in keys:
            mask &= (done[key] == combination[key]).to_numpy()
        group = done[mask]
        row = {key: combination[key] for key in keys}
        count = len(group)
        row["realisations"] = count
        for column in numeric:
            values = group[column].astype(float).dropna().to_numpy()
            mean = float(values.mean()) if len(values) else np.nan
            std = float(values.std(ddof=1)) if len(values) > 1 else np.nan
            half = (
                float(stats.t.ppf(0.975, len(values) - 1)) * std / np.sqrt(len(values))
                if len(values) > 1
                else np.nan
            )
            row.update(
                {
                    f"{column}_mean": mean,
                    f"{column}_std": std,
                    f"{column}_ci_low": mean - half,
                    f"{column}_ci_high": mean + half,
                }
            )
        rows.append(row)
    return pd.DataFrame.from_records(rows)


def write_ensemble(config, rows) -> Path | None:
    """Write ``NAME_ensemble.csv`` of the summary ``rows`` when the study sweeps
    ``surface.seed`` (atomically); returns its path, None when there is nothing to write.
    Raises :class:`engine.output.space.OutputFull` when the disk has no room for it (the
    next run writes it)."""
    if config.surface is None or SEED not in config.sweep.swept_keys:
        return None

    frame = ensemble_frame(summary_frame(list(rows)))
    path = ensemble_path(config.study.summary_path)
    temporary = path.with_name(f".{path.name}.tmp")
    text = frame.to_csv(index=False)
    try:
        temporary.write_text(text, encoding="utf-8")
        os.replace(temporary, path)
    except OSError as error:  # nothing half-written is left; a full disk is exit code 5
        temporary.unlink(missing_ok=True)
        if not is_no_space(error):
            raise
        raise OutputFull(path, len(text.encode()), free_bytes(path)) from None
    return path


def load_ensemble(path: str | Path):
    """Statistics over the realisations of a study sweeping ``surface.seed``, computed from
    its summary (the same table as ``NAME_ensemble.csv``; module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) or its summary ``.csv``.

    Returns
    -------
    pandas.DataFrame
        One row per combination of the other swept keys: ``realisations`` (completed cases)
        and, for every numeric summary column c, ``c_mean``, ``c_std`` and the 95 %
        confidence interval of the mean ``c_ci_low``, ``c_ci_high`` (units: the column's).

    Examples
    --------
    >>> frame = engine.load_ensemble("results/rough_fretting.h5")         # doctest: +SKIP
    >>> frame[["loading.amplitude", "real_area_fraction_mean"]]           # doctest: +SKIP
    """
    return ensemble_frame(load_summary(path))
