"""What a case on a rough surface adds to its results: summary columns and datasets.

Summary columns (:data:`SURFACE_COLUMNS`, units in the results schema), from the final state
(``fields/final/pressure``: peak load of the last simulated cycle; fretting: the increment of
the largest |Q|):

- ``real_area_fraction``: real contact area A_r (elements with p > 0) over the nominal one,
  π a0² (a line contact: 2 a0 per unit length), a0 the profile's contact length;
- ``contact_spots``: connected components of the contact (``scipy.ndimage.label``, elements
  sharing an edge are connected), ``largest_spot_area`` the area of the largest (mm²);
- ``real_mean_pressure`` = Σ p ΔA / A_r and ``real_peak_pressure`` = max p (MPa);
- ``rms_height``, ``rms_slope`` of the surface h before wear and ``rms_height_worn``,
  ``rms_slope_worn`` of h − w after it (w: the wear of the last recorded cycle; the scar's
  form is part of it; without wear the same as before). Spectral slope, mean removed
  (:mod:`.topography`).

Datasets, under the case group's ``surface/``: ``height`` (mm, the case's grid, asperity tops
positive: the gap is the profile's gap minus it), ``wavevector`` (rad/mm) and ``psd`` (mm⁴; a
line contact's profile mm³), the radially averaged spectrum of :func:`.topography.radial_psd`,
and ``psd_worn`` of h − w.
"""

from __future__ import annotations

import math

import numpy as np

from engine.schema import SURFACE_DATASETS, CaseStatus, cycle_of_group

from .profile import surface_height
from .topography import radial_psd, rms_height, rms_slope

__all__ = ["surface_datasets", "surface_row", "surface_outcome", "surface_layout"]

GROUP = "surface"


def _specs(line: bool):
    return {
        name: spec
        if not line or name not in ("psd", "psd_worn")
        else type(spec)("mm^3", spec.description.replace("mm^4", "mm^3"))
        for name, spec in SURFACE_DATASETS.items()
    }


def surface_datasets(height: np.ndarray, worn: np.ndarray | None, grid) -> dict:
    """``surface/height``, ``surface/wavevector``, ``surface/psd`` and, with wear (``worn``
    = h − w, mm), ``surface/psd_worn``: path → :class:`engine.schema.DatasetRecord`."""
    spacing = (grid.dx, grid.dy)
    specs = _specs(grid.is_line)
    q, psd = radial_psd(height, spacing)
    out = {
        f"{GROUP}/height": specs["height"].record(np.asarray(height, dtype=float)),
        f"{GROUP}/wavevector": specs["wavevector"].record(q),
        f"{GROUP}/psd": specs["psd"].record(psd),
    }
    if worn is not None:
        out[f"{GROUP}/psd_worn"] = specs["psd_worn"].record(radial_psd(worn, spacing)[1])
    return out


def surface_row(
    height: np.ndarray, worn: np.ndarray | None, pressure: np.ndarray, grid, contact_length
) -> dict[str, float | int]:
    """The summary columns of the module docstring (``pressure`` in MPa on ``grid``)."""
    from scipy import ndimage

    spacing = (grid.dx, grid.dy)
    element = grid.dx * grid.dy
    contact = np.asarray(pressure) > 0.0
    area = float(np.count_nonzero(contact)) * element
    nominal = 2.0 * contact_length if grid.is_line else math.pi * contact_length**2
    labels, spots = ndimage.label(contact)
    largest = float(np.bincount(labels.ravel())[1:].max()) * element if spots else 0.0
    worn = height if worn is None else worn
    return {
        "real_area_fraction": area / nominal,
        "contact_spots": int(spots),
        "largest_spot_area": largest,
        "real_mean_pressure": float(np.sum(pressure) * element / area) if area else math.nan,
        "real_peak_pressure": float(np.max(pressure)),
        "rms_height": rms_height(height),
        "rms_slope": rms_slope(height, spacing),
        "rms_height_worn": rms_height(worn),
        "rms_slope_worn": rms_slope(worn, spacing),
    }


def _last_wear(datasets: dict) -> np.ndarray | None:
    """The wear field of the last recorded cycle among a case's datasets (None: none)."""
    cycles = {
        cycle_of_group(path.split("/")[1]): record
        for path, record in datasets.items()
        if path.startswith("fields/cycle_") and path.endswith("/wear")
    }
    return np.asarray(cycles[max(cycles)].data) if cycles else None


def surface_outcome(config, outcome):
    """Add the surface's columns and datasets to a completed case's ``outcome`` (the case
    runner's hook; any other outcome, or a study without ``[surface]``, is returned as is)."""
    if config.surface is None or outcome.status != CaseStatus.COMPLETED:
        return outcome

    grid = config.punch.profile().grid(config.mesh.n, config.mesh.half_width)
    height = np.asarray(surface_height(config.surface, grid))
    wear = _last_wear(outcome.datasets)
    worn = None if wear is None else height - wear
    pressure = np.asarray(outcome.datasets["fields/final/pressure"].data)
    outcome.row.update(surface_row(height, worn, pressure, grid, config.contact_length))
    outcome.datasets.update(surface_datasets(height, worn, grid))
    return outcome


def surface_layout(config) -> dict[str, tuple[tuple[int, ...], str]]:
    """Path → (shape, dtype) of the ``surface/*`` datasets of a case (the collective writer
    creates them before the case runs); empty without ``[surface]``."""
    if config.surface is None:
        return {}
    grid = config.punch.profile().grid(config.mesh.n, config.mesh.half_width)
    bins = len(radial_psd(np.zeros(grid.shape), (grid.dx, grid.dy))[0])
    layout = {
        f"{GROUP}/height": (grid.shape, "float64"),
        f"{GROUP}/wavevector": ((bins,), "float64"),
        f"{GROUP}/psd": ((bins,), "float64"),
    }
    if config.is_cyclic:
        layout[f"{GROUP}/psd_worn"] = ((bins,), "float64")
    return layout
