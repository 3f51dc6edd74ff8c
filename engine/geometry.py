"""Punch profiles: the geometric gap g_g of Eq. (1) over the grid (mm).

A profile returns the initial separation between the undeformed surfaces at each element
centre when the rigid approach is zero; ``numpy.inf`` marks elements the punch cannot touch
(outside the face of a cylindrical punch). New profiles only need ``gap``, ``check_grid`` and
``extent``.

Profiles (r = distance from the punch axis, mm):

- :class:`FlatPunch` (the paper's): g = 0 for r ≤ a, no surface beyond (sharp edge);
- :class:`RoundedPunch` (a machined punch): flat face of radius b joined to the cylinder by a
  toroidal edge of radius ρ: g = 0 for r ≤ b, g = ρ − √(ρ² − (r − b)²) for b < r < b + ρ,
  no surface beyond; ρ = 0 is the flat punch;
- :class:`SphericalPunch`: sphere of radius R in the parabolic (Hertz) approximation
  g = r²/(2R), a surface everywhere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .grid import Grid
from .validation import require_non_negative, require_positive

__all__ = [
    "Profile",
    "FlatPunch",
    "RoundedPunch",
    "SphericalPunch",
    "ContactReachesBorder",
    "border_contact",
    "may_reach_border",
]


class Profile(Protocol):
    def gap(self, grid: Grid) -> np.ndarray: ...

    def check_grid(self, grid: Grid) -> None: ...

    @property
    def extent(self) -> float:
        """Largest distance from the axis at which the punch has a surface (mm; inf: none)."""
        ...


def _check_covers(grid: Grid, radius: float, what: str) -> None:
    """The grid must cover the disc of ``radius`` (mm) and put 4 elements across it."""
    for name, half_width in (
        ("half_width_x", grid.half_width_x),
        ("half_width_y", grid.half_width_y),
    ):
        if half_width < radius:
            raise ValueError(
                f"grid {name} = {half_width:g} mm does not cover the {what} = {radius:g} mm"
            )
    elements = min(grid.n_x * radius / grid.half_width_x, grid.n_y * radius / grid.half_width_y)
    if elements < 4:
        raise ValueError(
            f"grid of {grid.n_x} x {grid.n_y} elements is too coarse for the {what} = "
            f"{radius:g} mm (fewer than 4 elements across it)"
        )


@dataclass(frozen=True)
class FlatPunch:
    """Flat-ended cylindrical punch of radius ``radius`` (mm), axis at x = y = 0."""

    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", require_positive("radius", self.radius))

    @property
    def extent(self) -> float:
        return self.radius

    def check_grid(self, grid: Grid) -> None:
        """The grid must cover the whole punch face, and resolve it with a few elements."""
        _check_covers(grid, self.radius, "punch radius")

    def gap(self, grid: Grid) -> np.ndarray:
        gap = np.zeros(grid.shape)
        gap[grid.radius() > self.radius] = np.inf
        return gap


@dataclass(frozen=True)
class RoundedPunch:
    """Cylindrical punch whose flat face of radius ``radius`` (b, mm) meets the cylinder
    through a toroidal edge of radius ``edge_radius`` (ρ, mm); outer radius b + ρ.

    g(r) = 0 (r ≤ b), ρ − √(ρ² − (r − b)²) (b < r < b + ρ), no surface for r ≥ b + ρ.
    The gap is sampled at the element centres, like every profile; the edge is resolved when
    ρ spans a few elements (see docs/study_sweeps_and_profiles.md).
    """

    radius: float
    edge_radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", require_positive("radius", self.radius))
        object.__setattr__(
            self, "edge_radius", require_non_negative("edge_radius", self.edge_radius)
        )

    @property
    def extent(self) -> float:
        return self.radius + self.edge_radius

    def check_grid(self, grid: Grid) -> None:
        """The grid must cover the flat face (the toroidal edge may be cut: contact there is
        checked at run time, see :func:`border_contact`)."""
        _check_covers(grid, self.radius, "flat face radius")

    def gap(self, grid: Grid) -> np.ndarray:
        r = grid.radius()
        outside = r - self.radius
        gap = np.zeros(grid.shape)
        edge = (outside > 0.0) & (outside < self.edge_radius)
        gap[edge] = self.edge_radius - np.sqrt(self.edge_radius**2 - outside[edge] ** 2)
        gap[(outside > 0.0) & ~edge] = np.inf  # beyond the torus: no surface
        return gap


@dataclass(frozen=True)
class SphericalPunch:
    """Sphere of radius ``radius`` (mm), parabolic (Hertz) approximation g = r²/(2R)."""

    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", require_positive("radius", self.radius))

    @property
    def extent(self) -> float:
        return math.inf

    def check_grid(self, grid: Grid) -> None:
        """Any grid is accepted here: whether it covers the contact depends on the load, and
        is checked after every increment (:func:`border_contact`)."""
        return None

    def gap(self, grid: Grid) -> np.ndarray:
        return grid.radius() ** 2 / (2.0 * self.radius)


class ContactReachesBorder(RuntimeError):
    """The contact area touches the edge of the grid: the solution would be truncated."""


def may_reach_border(profile: Profile, grid: Grid) -> bool:
    """True when the punch has a surface beyond the grid's edge, so the contact could be
    truncated by it (never for a flat punch on a grid covering its face)."""
    half_width = grid.half_width_x if grid.is_line else min(grid.half_width_x, grid.half_width_y)
    return profile.extent > half_width


def border_contact(pressure: np.ndarray) -> int:
    """Number of elements of the outermost ring of the grid carrying pressure (> 0); on a
    line grid (one element along y) the ring is the two end elements along x."""
    pressure = np.asarray(pressure)
    ring = np.zeros(pressure.shape, dtype=bool)
    ring[0, :] = ring[-1, :] = True
    if pressure.shape[1] > 1:
        ring[:, 0] = ring[:, -1] = True
    return int(np.count_nonzero(pressure[ring] > 0.0))
