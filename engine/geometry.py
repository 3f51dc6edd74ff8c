"""Punch profiles: the geometric gap g_g of Eq. (1) over the grid (mm).

A profile returns the initial separation between the undeformed surfaces at each element
centre when the rigid approach is zero; ``numpy.inf`` marks elements the punch cannot touch
(outside the flat face of a cylindrical punch). New profiles only need ``gap`` and
``check_grid``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .grid import Grid
from .validation import require_positive


class Profile(Protocol):
    def gap(self, grid: Grid) -> np.ndarray: ...

    def check_grid(self, grid: Grid) -> None: ...


@dataclass(frozen=True)
class FlatPunch:
    """Flat-ended cylindrical punch of radius ``radius`` (mm), axis at x = y = 0."""

    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", require_positive("radius", self.radius))

    def check_grid(self, grid: Grid) -> None:
        """The grid must cover the whole punch face, and resolve it with a few elements."""
        for name, half_width in (
            ("half_width_x", grid.half_width_x),
            ("half_width_y", grid.half_width_y),
        ):
            if half_width < self.radius:
                raise ValueError(
                    f"grid {name} = {half_width:g} mm does not cover the punch "
                    f"radius = {self.radius:g} mm"
                )
        if (
            min(
                grid.n_x * self.radius / grid.half_width_x,
                grid.n_y * self.radius / grid.half_width_y,
            )
            < 4
        ):
            raise ValueError(
                f"grid of {grid.n_x} x {grid.n_y} elements is too coarse for radius = "
                f"{self.radius:g} mm (fewer than 4 elements across the punch)"
            )

    def gap(self, grid: Grid) -> np.ndarray:
        gap = np.zeros(grid.shape)
        gap[grid.radius() > self.radius] = np.inf
        return gap


@dataclass(frozen=True)
class SphericalPunch:
    """Sphere of radius ``radius`` (mm), parabolic (Hertz) approximation g = r²/(2R)."""

    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", require_positive("radius", self.radius))

    def check_grid(self, grid: Grid) -> None:
        return None

    def gap(self, grid: Grid) -> np.ndarray:
        return grid.radius() ** 2 / (2.0 * self.radius)
