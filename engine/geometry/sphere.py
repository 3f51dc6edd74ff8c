"""``shape = "sphere"``: a sphere of radius R in the parabolic (Hertz) approximation
g = r²/(2R), a surface everywhere. a0 is Hertz's contact radius at the load
(engine.reference.hertz); the summary's p0 Hertz's mean pressure P/(π a²)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from engine.grid import Grid
from engine.keys import length
from engine.reference import mindlin
from engine.reference.hertz import hertz_contact_radius

from .base import Profile


@dataclass(frozen=True)
class SphericalPunch(Profile):
    """Sphere of radius ``radius`` (mm), parabolic (Hertz) approximation g = r²/(2R)."""

    name = "sphere"
    description = "sphere (Hertz)"
    covered = "Hertz contact radius"
    radius: float = length("sphere radius R", example=10.0)

    def contact_length(self, load: float, contact_modulus: float) -> float:
        """Hertz's contact radius a = (3PR/(4E*))^(1/3) (mm)."""
        return hertz_contact_radius(load, self.radius, contact_modulus)

    def check_grid(self, grid: Grid) -> None:
        """Any grid is accepted here: whether it covers the contact depends on the load, and
        is checked after every increment (:func:`~engine.geometry.border_contact`)."""
        return None

    def gap(self, grid: Grid) -> np.ndarray:
        return grid.radius() ** 2 / (2.0 * self.radius)

    def fretting_reference(self, load: float, material, mu: float, reference_distance):
        """Mindlin's closed forms (:func:`engine.reference.mindlin.fretting_reference`)."""
        return mindlin.fretting_reference(load, self.radius, material, mu)
