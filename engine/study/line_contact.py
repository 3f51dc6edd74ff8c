"""The line (plane-strain) contact in the study layer: the nominal contact, the peak tracker,
and the scar columns of a study of a cylinder or a rounded pad on a flat
(docs/explanation/line-contact.md). The profile is ``PunchConfig.profile``'s, the line grid,
operator and stresses are built by the case runner and ``engine.study.operators``.

``[punch] shape = "cylinder"`` (``radius`` R) or ``"pad"`` (``radius`` the flat half-width b,
``edge_radius`` R of the rounds); ``[mesh] n`` elements along x over ``half_width`` and the
displacement datum ``reference_distance`` (mm, default ``DEFAULT_REFERENCE_DISTANCE``);
loads per unit length (N/mm). The nominal contact half-width a0 (the length unit of
``[subsurface] depth``) is Hertz's for the cylinder and Ciavarella's for the pad, at the load;
the summary's p0 is the mean pressure P/(2 a0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from engine.geometry import Profile
from engine.grid import Grid
from engine.solvers.line_subsurface import LinePeakTracker, LineSubsurfaceStress
from engine.solvers.scar import scar_measures

__all__ = [
    "DEFAULT_REFERENCE_DISTANCE",
    "LineContact",
]

DEFAULT_REFERENCE_DISTANCE = 10.0  # mm: the datum of 2-D displacements (a specimen's size)


@dataclass(frozen=True)
class LineContact:
    """A line contact's ``profile`` (a cylinder or a pad, :class:`engine.geometry.Profile`)
    and ``load`` (N/mm)."""

    profile: Profile
    load: float

    def nominal_half_width(self, contact_modulus: float) -> float:
        """a0 (mm): the profile's (Hertz's a = √(4PR/(πE*)) or Ciavarella's pad half-width)
        at the load."""
        return self.profile.contact_length(self.load, contact_modulus)

    def nominal_pressure(self, contact_modulus: float) -> float:
        """p0 = P/(2 a0) (MPa), the mean pressure over the nominal contact."""
        return self.profile.mean_pressure(self.load, self.nominal_half_width(contact_modulus))

    @staticmethod
    def peak_tracker(stress: LineSubsurfaceStress, nominal_half_width: float, angle=0.0):
        if angle != 0.0:
            raise ValueError("a line contact slides along x (direction = 0)")
        return LinePeakTracker(stress, nominal_half_width)


def scar_row(grid: Grid, total_wear: np.ndarray, pad_ratio: float) -> dict[str, float]:
    """Summary columns scar_depth, scar_width (mm), scar_area (mm²/mm), pad_wear_depth (mm)."""
    return scar_measures(grid, total_wear, pad_ratio).row()
