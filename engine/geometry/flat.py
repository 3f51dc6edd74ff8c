"""``shape = "flat"`` (the paper's): a flat-ended cylindrical punch of radius a, axis at
x = y = 0; g = 0 for r ≤ a, no surface beyond (sharp edge). a0 = a."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from engine.grid import Grid
from engine.keys import length
from engine.reference.flat_punch import sneddon_pressure

from .base import HERTZ_MARGIN, Profile, check_covers


@dataclass(frozen=True)
class FlatPunch(Profile):
    """Flat-ended cylindrical punch of radius ``radius`` (mm), axis at x = y = 0."""

    name = "flat"
    description = "flat-ended cylindrical punch (the paper's)"
    radius: float = length("punch radius a0", example=1.8)

    @property
    def extent(self) -> float:
        return self.radius

    def default_half_width(self, load: float, contact_modulus: float) -> float:
        """1.5 a (:data:`HERTZ_MARGIN`, as the Hertz shapes): the face and half a radius
        beyond its edge, where the edge's stress peak and the cracks of fretting start."""
        return HERTZ_MARGIN * self.radius

    def check_grid(self, grid: Grid) -> None:
        """The grid must cover the whole punch face, and resolve it with a few elements."""
        check_covers(grid, self.radius, "punch radius")

    def unworn_pressure(self, r, load: float, contact_length: float):
        """Sneddon's pressure P/(2πa√(a² − r²)) (Eq. 17), MPa."""
        return sneddon_pressure(r, load, contact_length)

    def gap(self, grid: Grid) -> np.ndarray:
        gap = np.zeros(grid.shape)
        gap[grid.radius() > self.radius] = np.inf
        return gap
