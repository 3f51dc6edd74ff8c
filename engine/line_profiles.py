"""Profiles of a line (plane-strain) contact: the geometric gap g_g(x) of Eq. (1), in mm.

The bodies are infinitely long along y; the profile depends on x only and is sampled at the
element centres of a line grid (``Grid.line``). Both profiles use the parabolic (Hertz)
approximation of their curved parts, the one the closed forms of ``engine.reference.line``
assume:

- :class:`CylinderProfile`: cylinder of radius R on a flat, g = x²/(2R);
- :class:`RoundedPadProfile`: flat pad of half-width b whose edges are rounded with radius R,
  g = 0 for |x| ≤ b, (|x| − b)²/(2R) beyond (Ciavarella, Hills & Monno 1998).

Both have a surface everywhere; whether the grid covers the contact depends on the load and
is checked after every increment (``engine.geometry.border_contact``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .grid import Grid
from .validation import require_positive

__all__ = ["CylinderProfile", "RoundedPadProfile"]


def _require_line_grid(grid: Grid, what: str) -> None:
    if not grid.is_line:
        raise ValueError(
            f"a {what} is a line (plane-strain) contact: it needs a line grid with one "
            f"element along y, got a grid of {grid.n_x} x {grid.n_y} elements"
        )


@dataclass(frozen=True)
class CylinderProfile:
    """Cylinder of radius ``radius`` (R, mm), axis along y at x = 0: g = x²/(2R)."""

    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", require_positive("radius", self.radius))

    @property
    def extent(self) -> float:
        return math.inf

    def check_grid(self, grid: Grid) -> None:
        _require_line_grid(grid, "cylinder")

    def gap(self, grid: Grid) -> np.ndarray:
        x, _ = grid.coordinates()
        return x**2 / (2.0 * self.radius)


@dataclass(frozen=True)
class RoundedPadProfile:
    """Flat pad of half-width ``flat_half_width`` (b, mm) with edges rounded to
    ``edge_radius`` (R, mm): g = 0 for |x| ≤ b, (|x| − b)²/(2R) for |x| > b."""

    flat_half_width: float
    edge_radius: float

    def __post_init__(self) -> None:
        for name in ("flat_half_width", "edge_radius"):
            object.__setattr__(self, name, require_positive(name, getattr(self, name)))

    @property
    def extent(self) -> float:
        return math.inf

    def check_grid(self, grid: Grid) -> None:
        """A line grid covering the flat with at least 4 elements across it."""
        _require_line_grid(grid, "rounded pad")
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
