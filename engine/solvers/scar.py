"""Two-body wear (the flat and the punch or pad) and the measures of the flat's scar.

Both bodies wear (``[wear] pad_coefficient``: line contacts and the 3-D punches alike). The
pad's (punch's) wear law is the flat's law with its coefficient scaled by ``pad_ratio``
r = k_pad / k_flat (the same law and anisotropy), so in every increment the pad loses r times
the depth the flat loses at the same point, and the gap carries both:

    h = h_flat + h_pad = (1 + r) h_flat      (the wear the contact solver sees, mm)

:func:`two_body_wear_law` builds the law of h (the flat's law scaled by 1 + r); the two
surfaces are recovered exactly as h_flat = h/(1 + r), h_pad = r h/(1 + r). As everywhere in
the engine's fretting model, the slip is small against the contact (the profile is not
translated with the punch's rigid displacement), so the pad's wear is accumulated at the
flat's coordinates; with a stroke comparable to the contact width this smears the pad's scar
over the stroke, which this model does not represent.

Scar measures of a line contact (per unit length): ``scar_depth`` max h_flat (mm),
``scar_width`` the extent along x of the elements where h_flat exceeds 1 % of the depth (mm,
counting whole elements), ``scar_area`` Σ h_flat Δx (the worn area of the cross-section,
mm² per mm of length), ``pad_wear_depth`` max h_pad (mm). A 3-D punch reports the two
depths (:func:`two_body_depths`); its wear volume and largest wear depth in the summary are
those of h, both bodies together.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..grid import Grid
from ..validation import require_non_negative
from .wear import WearModel

__all__ = [
    "ScarMeasures",
    "pad_ratio",
    "scar_measures",
    "two_body_depths",
    "two_body_wear_law",
    "SCAR_THRESHOLD",
]

SCAR_THRESHOLD = 0.01  # the scar is where the flat's wear exceeds 1 % of its depth


def two_body_wear_law(flat_law, pad_ratio: float):
    """The law of the total wear h = h_flat + h_pad: ``flat_law`` (a
    :class:`engine.solvers.wear.WearModel`) wearing 1 + ``pad_ratio`` times as fast
    (:meth:`~engine.solvers.wear.WearModel.scaled`: its coefficients times 1 + ``pad_ratio``)."""
    pad_ratio = require_non_negative("pad_ratio", pad_ratio)
    if not isinstance(flat_law, WearModel):
        raise TypeError(f"two-body wear needs a wear law (WearModel), got {flat_law!r}")
    return flat_law.scaled(1.0 + pad_ratio)


@dataclass(frozen=True)
class ScarMeasures:
    """``scar_depth``, ``scar_width``, ``pad_wear_depth`` (mm) and ``scar_area`` (mm²/mm)
    (module docstring)."""

    scar_depth: float
    scar_width: float
    scar_area: float
    pad_wear_depth: float

    def row(self) -> dict[str, float]:
        """The four measures as summary columns, named as the fields, in their order."""
        return asdict(self)


def scar_measures(grid: Grid, total_wear: np.ndarray, pad_ratio: float) -> ScarMeasures:
    """The scar of the flat and the pad's wear depth from the total wear h (mm, (n, 1) on a
    line grid) and r = k_pad / k_flat."""
    if not grid.is_line:
        raise ValueError(f"scar measures are defined for line grids, got {grid.shape}")
    pad_ratio = require_non_negative("pad_ratio", pad_ratio)
    flat = np.asarray(total_wear, dtype=float).reshape(grid.n_x) / (1.0 + pad_ratio)
    depth = float(flat.max(initial=0.0))
    if depth <= 0.0:
        return ScarMeasures(0.0, 0.0, 0.0, 0.0)
    scarred = np.flatnonzero(flat > SCAR_THRESHOLD * depth)
    width = float((scarred[-1] - scarred[0] + 1) * grid.dx)
    area = float(flat.sum() * grid.dx)
    return ScarMeasures(depth, width, area, pad_ratio * depth)


def two_body_depths(total_wear: np.ndarray, pad_ratio: float) -> dict[str, float]:
    """``scar_depth`` (max h_flat) and ``pad_wear_depth`` (max h_pad), mm, from the total
    wear h of any grid and r = k_pad / k_flat."""
    pad_ratio = require_non_negative("pad_ratio", pad_ratio)
    depth = float(np.max(total_wear, initial=0.0)) / (1.0 + pad_ratio)
    return {"scar_depth": depth, "pad_wear_depth": pad_ratio * depth}


def pad_ratio(pad_coefficient: float | None, flat_coefficient: float) -> float:
    """r = k_pad / k_flat (0 without pad wear); a pad coefficient needs a flat one."""
    if pad_coefficient is None or pad_coefficient == 0.0:
        return 0.0
    if not flat_coefficient > 0.0:
        raise ValueError(
            f"[wear] pad_coefficient = {pad_coefficient:g} needs a positive wear coefficient "
            "of the flat (the pad's law is the flat's, scaled)"
        )
    if not math.isfinite(pad_coefficient) or pad_coefficient < 0.0:
        raise ValueError(f"[wear] pad_coefficient must be >= 0, got {pad_coefficient!r}")
    return pad_coefficient / flat_coefficient
