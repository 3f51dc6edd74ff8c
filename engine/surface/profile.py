"""A rough profile: any punch profile with the composite roughness of the two bodies.

The roughness h (mm, asperity tops positive) is put on the half-space's side: the geometric
gap of Eq. (1) becomes g_g − h, so every loading kind, wear law and solver runs unchanged on
it, and the wear (added to the gap) flattens the asperities. ``numpy.inf`` (no surface)
stays inf. The height map of a case is built once per surface and grid (:func:`surface_height`).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from engine.grid import Grid

from .config import HEIGHT_UNITS, SurfaceConfig
from .measured import detrended, read_height_map, resampled
from .topography import self_affine

__all__ = ["RoughProfile", "surface_height", "rough_profile"]


@lru_cache(maxsize=4)
def _height(surface: SurfaceConfig, grid: Grid) -> np.ndarray:
    spacing = (grid.dx, grid.dy)
    if surface.kind == "self_affine":
        height = self_affine(
            grid.shape,
            spacing,
            hurst=surface.hurst,
            long_cutoff=surface.long_cutoff,
            short_cutoff=surface.short_cutoff,
            seed=surface.seed,
            rms_height=surface.rms_height,
            rms_slope=surface.rms_slope,
        )
    else:
        heights = detrended(read_height_map(surface.path), surface.detrend)
        height = resampled(heights * HEIGHT_UNITS[surface.units], surface.pixel_size, grid)
    height.setflags(write=False)
    return height


def surface_height(surface: SurfaceConfig, grid: Grid) -> np.ndarray:
    """h (mm) at the element centres of ``grid``, shape ``grid.shape`` (read-only)."""
    return _height(surface, grid)


class RoughProfile:
    """``base`` (an :class:`engine.geometry.Profile`) with the height map ``height`` (mm,
    shape ``grid.shape``) of ``grid``: gap(grid) = base.gap(grid) − height; everything else
    is the base profile's."""

    def __init__(self, base, height: np.ndarray, grid: Grid) -> None:
        height = np.asarray(height, dtype=float)
        if height.shape != grid.shape:
            raise ValueError(f"height has shape {height.shape}, the grid {grid.shape}")
        self.base, self.height, self.grid = base, height, grid

    def __getattr__(self, name: str):
        if name.startswith("__") or name in ("base", "height", "grid"):  # copies, pickles
            raise AttributeError(name)
        return getattr(self.base, name)

    def __repr__(self) -> str:
        return f"RoughProfile({self.base!r}, rms height {np.std(self.height):.3g} mm)"

    def gap(self, grid: Grid) -> np.ndarray:
        """g_g − h (mm), shape ``grid.shape``; inf where the base profile has no surface."""
        if grid != self.grid:
            raise ValueError(f"the surface was built for {self.grid}, not {grid}")
        return self.base.gap(grid) - self.height


def rough_profile(profile, surface: SurfaceConfig | None, grid: Grid):
    """``profile`` itself without a surface, else its :class:`RoughProfile` on ``grid``."""
    if surface is None:
        return profile
    return RoughProfile(profile, surface_height(surface, grid), grid)
