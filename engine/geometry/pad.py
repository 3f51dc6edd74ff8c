"""``shape = "pad"``: a flat pad of half-width b whose edges are rounded with radius R,
g = 0 for |x| ≤ b, (|x| − b)²/(2R) beyond (Ciavarella, Hills & Monno 1998), parabolic
approximation of the rounds. A line (plane-strain) contact: ``[punch] radius`` is b,
``edge_radius`` R; a0 is Ciavarella's contact half-width at the load per unit length."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from engine.grid import Grid
from engine.keys import length
from engine.reference.line_contact import pad_half_width

from .base import LineProfile


@dataclass(frozen=True)
class RoundedPadProfile(LineProfile):
    """Flat pad of half-width ``radius`` (b, mm; the key keeps the name of the other
    shapes' face size) with edges rounded to ``edge_radius`` (R, mm): g = 0 for |x| ≤ b,
    (|x| − b)²/(2R) for |x| > b."""

    name = "pad"
    description = "flat pad with rounded edges on a flat, plane strain (line contact)"
    radius: float = length("half-width b of the flat", example=0.1)
    edge_radius: float = length("radius R of the rounded edges", example=5.0)

    @property
    def flat_half_width(self) -> float:
        """b (mm), the half-width of the flat (``[punch] radius``)."""
        return self.radius

    def contact_length(self, load: float, contact_modulus: float) -> float:
        return pad_half_width(load, self.flat_half_width, self.edge_radius, contact_modulus)

    def check_grid(self, grid: Grid) -> None:
        """A line grid covering the flat with at least 4 elements across it."""
        super().check_grid(grid)
        if grid.half_width_x < self.flat_half_width:
            raise ValueError(
                f"grid half_width = {grid.half_width_x:g} mm does not cover the pad's flat "
                f"half-width {self.flat_half_width:g} mm"
            )
        if 2.0 * self.flat_half_width < 4.0 * grid.dx:
            raise ValueError(
                f"grid of {grid.n_x} elements is too coarse for the pad's flat half-width "
                f"{self.flat_half_width:g} mm (fewer than 4 elements across the flat)"
            )

    def gap(self, grid: Grid) -> np.ndarray:
        x, _ = grid.coordinates()
        beyond = np.maximum(np.abs(x) - self.flat_half_width, 0.0)
        return beyond**2 / (2.0 * self.edge_radius)
