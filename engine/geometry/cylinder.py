"""``shape = "cylinder"``: a cylinder of radius R on a flat, axis along y at x = 0, in the
parabolic (Hertz) approximation g = x²/(2R) (the one the closed forms of
``engine.reference.line_contact`` assume). A line (plane-strain) contact: a0 is Hertz's
half-width a = √(4PR/(πE*)) at the load per unit length P (N/mm)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from engine.grid import Grid
from engine.keys import length
from engine.reference import line_contact
from engine.reference.line_contact import hertz_line_half_width

from .base import LineProfile


@dataclass(frozen=True)
class CylinderProfile(LineProfile):
    """Cylinder of radius ``radius`` (R, mm), axis along y at x = 0: g = x²/(2R)."""

    name = "cylinder"
    description = "cylinder on a flat, plane strain (line contact)"
    radius: float = length("cylinder radius R", example=6.0)

    def contact_length(self, load: float, contact_modulus: float) -> float:
        return hertz_line_half_width(load, self.radius, contact_modulus)

    def gap(self, grid: Grid) -> np.ndarray:
        x, _ = grid.coordinates()
        return x**2 / (2.0 * self.radius)

    def fretting_reference(self, load: float, material, mu: float, reference_distance):
        """The cylinder's closed forms relative to the displacement datum
        ``reference_distance`` d (mm): δ_slip = (μ p0 a/E*)(ln(2d/a) + 1/2), the loop energy
        (:func:`engine.reference.line_contact.line_fretting_reference`)."""
        return line_contact.line_fretting_reference(
            load, self.radius, material.contact_modulus, mu, float(reference_distance)
        )
