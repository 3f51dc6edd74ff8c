"""``shape = "rounded"`` (a machined punch): a flat face of radius b joined to the cylinder
by a toroidal edge of radius ρ: g = 0 for r ≤ b, g = ρ − √(ρ² − (r − b)²) for
b < r < b + ρ, no surface beyond; ρ = 0 is the flat punch. a0 = b."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from engine.grid import Grid
from engine.keys import length

from .base import Profile, check_covers

#: Default mesh half-width / outer radius b + ρ of the rounded punch.
FACE_MARGIN = 1.05


@dataclass(frozen=True)
class RoundedPunch(Profile):
    """Cylindrical punch whose flat face of radius ``radius`` (b, mm) meets the cylinder
    through a toroidal edge of radius ``edge_radius`` (ρ, mm); outer radius b + ρ.

    g(r) = 0 (r ≤ b), ρ − √(ρ² − (r − b)²) (b < r < b + ρ), no surface for r ≥ b + ρ.
    The gap is sampled at the element centres, like every profile; the edge is resolved when
    ρ spans a few elements (see docs/how-to/sweeps-and-profiles.md).
    """

    name = "rounded"
    description = "flat punch with a rounded (toroidal) edge"
    radius: float = length("radius b of the flat face", example=1.8)
    edge_radius: float = length(
        "radius ρ of the toroidal edge (0 is the sharp flat punch)", strict=False, example=0.2
    )

    @property
    def extent(self) -> float:
        return self.radius + self.edge_radius

    def default_half_width(self, load: float, contact_modulus: float) -> float:
        """1.05 (b + ρ): the whole punch and a margin."""
        return FACE_MARGIN * (self.radius + self.edge_radius)

    def check_grid(self, grid: Grid) -> None:
        """The grid must cover the flat face (the toroidal edge may be cut: contact there is
        checked at run time, see :func:`~engine.geometry.border_contact`)."""
        check_covers(grid, self.radius, "flat face radius")

    def gap(self, grid: Grid) -> np.ndarray:
        r = grid.radius()
        outside = r - self.radius
        gap = np.zeros(grid.shape)
        edge = (outside > 0.0) & (outside < self.edge_radius)
        gap[edge] = self.edge_radius - np.sqrt(self.edge_radius**2 - outside[edge] ** 2)
        gap[(outside > 0.0) & ~edge] = np.inf  # beyond the torus: no surface
        return gap
