"""Figures of a study with ``[surface]`` (``python -m engine plot``; Matplotlib, no MPI).

- ``surface_<case_id>.png``, for the first realisation (smallest ``surface.seed``) of every
  combination of the other swept keys: the topography h (µm), the contact spots at the final
  state over it, and the radially averaged power spectrum before and after wear;
- ``ensemble_<key>.png``, for every swept key other than ``surface.seed`` in a study that
  sweeps it: the mean over the realisations of the rough-surface columns and of the sweep
  figures' quantities (:data:`.sweep_figures.SWEEP_QUANTITIES`, those with a non-zero
  value) against the key (a text key's values as categories), with the 95 % confidence band
  of the mean (:mod:`engine.output.ensemble`), one line per combination of the remaining
  keys. Never a curve against the seed: a seed is a realisation, not a parameter (such a
  study has no ``sweep_*.png``).
"""

from __future__ import annotations

import h5py
import matplotlib.pyplot as plt
import numpy as np

from engine.output.ensemble import SEED, ensemble_frame
from engine.output.summary import column_unit, load_summary

from .names import key_label, value_text
from .sweep_figures import SWEEP_QUANTITIES, key_positions, text_categories

__all__ = ["surface_figures"]

#: Columns drawn by the ensemble figures (those the study has), with their drawn scale/unit.
ENSEMBLE_COLUMNS = (
    ("real_area_fraction", "real contact area / nominal", 1.0, ""),
    ("contact_spots", "contact spots", 1.0, ""),
    ("real_peak_pressure", "peak pressure", 1.0, "MPa"),
    ("energy_per_cycle", "energy per cycle", 1.0, "mJ"),
    ("wear_volume", "wear volume", 1.0, "mm³"),
    ("max_wear_depth", "maximum wear depth", 1e3, "µm"),
    ("vm_max", "σ_VM max", 1.0, "MPa"),
    ("rms_height_worn", "rms height after wear", 1e3, "µm"),
)
_PARAMETERS = ("mu1", "mu2", "wear1", "wear2", "beta", "alpha")  # the ensemble's key columns


def _drawn_columns(ensemble, line: bool) -> list[tuple[str, str, float, str]]:
    """(column, name, scale, unit) of the ensemble figures: the rough-surface columns, then
    the sweep figures' numeric quantities, each where some mean is finite and non-zero."""
    drawn = list(ENSEMBLE_COLUMNS)
    named = {column for column, *_ in drawn}
    for quantity in SWEEP_QUANTITIES:
        if quantity.categories or quantity.column in named:
            continue
        unit = column_unit(quantity.column, line) if quantity.unit is None else quantity.unit
        drawn.append((quantity.column, quantity.name, quantity.scale, unit))
    present = []
    for column, name, scale, unit in drawn:
        means = ensemble.get(f"{column}_mean")
        if means is not None and np.any(np.isfinite(means) & (means.to_numpy(float) != 0.0)):
            present.append((column, name, scale, unit.replace("^3", "³").replace("^2", "²")))
    return present


def surface_figures(study):
    """(file name, figure) of the figures of the module docstring; nothing without
    ``[surface]``."""
    if "surface" not in study.study:
        return

    summary = load_summary(study.path)
    done = summary[summary["status"] == "completed"]
    if done.empty:
        return
    others = [key for key in study.swept_keys if key != SEED]
    firsts = done.sort_values(SEED) if SEED in done else done
    firsts = firsts.drop_duplicates(subset=others or None, keep="first")
    if not others:
        firsts = firsts.iloc[:1]
    with h5py.File(study.path, "r") as file:
        for case_id in firsts["case_id"]:
            yield f"surface_{case_id}.png", _case_figure(file["cases"][case_id], case_id)
    if SEED in study.swept_keys:
        ensemble = ensemble_frame(summary)
        line = study.profile.is_line
        for key in others if _drawn_columns(ensemble, line) else ():
            figure = _ensemble_figure(ensemble, key, study.name, line)
            yield f"ensemble_{key}.png", figure


def _case_figure(group, case_id: str):
    height = group["surface/height"][()] * 1e3  # µm
    x, y = group["grid/x"][()], group["grid/y"][()]
    pressure = group["fields/final/pressure"][()]
    figure, axes = plt.subplots(1, 3, figsize=(13.5, 4.0), layout="constrained")
    figure.suptitle(case_id)
    if height.shape[1] == 1:  # a line contact's profile
        axes[0].plot(x, height[:, 0], color="0.3")
        axes[0].set(xlabel="x (mm)", ylabel="h (µm)", title="surface profile")
        axes[1].plot(x, height[:, 0], color="0.6")
        spots = np.where(pressure[:, 0] > 0, height[:, 0], np.nan)
        axes[1].plot(x, spots, color="C3", lw=2, label="in contact")
        axes[1].set(xlabel="x (mm)", ylabel="h (µm)", title="contact spots (final state)")
        axes[1].legend()
    else:
        extent = (x[0], x[-1], y[0], y[-1])
        image = axes[0].imshow(height.T, origin="lower", extent=extent, cmap="cividis")
        figure.colorbar(image, ax=axes[0], label="h (µm)")
        axes[0].set(xlabel="x (mm)", ylabel="y (mm)", title="topography")
        axes[1].imshow(height.T, origin="lower", extent=extent, cmap="Greys", alpha=0.6)
        contact = np.ma.masked_where(pressure <= 0, pressure)
        image = axes[1].imshow(contact.T, origin="lower", extent=extent, cmap="inferno_r")
        figure.colorbar(image, ax=axes[1], label="pressure (MPa)")
        axes[1].set(xlabel="x (mm)", ylabel="y (mm)", title="contact spots (final state)")
    q = group["surface/wavevector"][()]
    psd = group["surface/psd"][()]
    axes[2].loglog(q, psd, label="before wear")
    axes[2].set_ylim(bottom=1e-8 * np.nanmax(psd))  # the round-off floor beyond q_S left out
    if "psd_worn" in group["surface"]:
        axes[2].loglog(q, group["surface/psd_worn"][()], label="after wear", ls="--")
    unit = group["surface/psd"].attrs["units"].replace("^4", "⁴").replace("^3", "³")
    axes[2].set(xlabel="q (rad/mm)", ylabel=f"C(q) ({unit})", title="power spectrum")
    axes[2].legend()
    return figure


def _ensemble_figure(ensemble, key: str, title: str, line: bool = False):
    columns = _drawn_columns(ensemble, line)
    rest = [
        column for column in ensemble.columns
        if column != key and (column in _PARAMETERS or "." in column)
        and ensemble[column].nunique() > 1
    ]  # fmt: skip
    categories = text_categories(ensemble[key])
    count = len(columns)
    ncols = min(count, 4)
    nrows = -(-count // ncols)
    figure, axes = plt.subplots(
        nrows, ncols, figsize=(3.6 * ncols, 3.0 * nrows), layout="constrained", squeeze=False
    )
    figure.suptitle(f"{title}: mean over realisations, 95 % band of the mean")
    groups = ensemble.groupby(rest, sort=True) if rest else [((), ensemble)]
    for index, (values, rows) in enumerate(groups):
        rows = rows.sort_values(key)
        values = values if isinstance(values, tuple) else (values,)
        label = ", ".join(f"{k} = {value_text(v)}" for k, v in zip(rest, values, strict=True))
        x = key_positions(rows[key], categories)
        for axis, (column, name, scale, unit) in zip(axes.flat, columns, strict=False):
            mean = rows[f"{column}_mean"].to_numpy(float) * scale
            low = rows[f"{column}_ci_low"].to_numpy(float) * scale
            high = rows[f"{column}_ci_high"].to_numpy(float) * scale
            axis.plot(x, mean, marker="o", color=f"C{index}", label=label or None)
            axis.fill_between(x, low, high, color=f"C{index}", alpha=0.25)
            axis.set(xlabel=key_label(key, line), ylabel=f"{name} ({unit})" if unit else name)
            if categories is not None:
                axis.set_xticks(range(len(categories)), categories, rotation=20, ha="right")
    for axis in list(axes.flat)[count:]:
        axis.set_visible(False)
    if rest:
        axes.flat[0].legend(fontsize="small")
    return figure
