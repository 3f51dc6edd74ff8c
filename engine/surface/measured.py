"""Measured height maps: read, detrended, resampled to a case's grid (no TOML, no MPI).

Formats: ``.npy`` (NumPy), whitespace- or comma-separated text (``.txt``, ``.dat``,
``.asc``, ``.csv``; one row of the map per line, ``#`` comments), and any instrument format
that SurfaceTopography reads (``SurfaceTopography.read_topography``; the optional extra
``pip install -e '.[topography]'``). Rows run along x, columns along y (``ij`` indexing, as
the grid's fields); a profile is one row or one column.

Resampling: the map, of spacing ``pixel_size`` (mm), is centred on the punch axis and read at
the element centres by bilinear interpolation (linear for a profile) of its samples; a map that
does not cover the mesh is refused when the study is parsed. Interpolation does not add
roughness below the map's pixel; where the mesh is coarser than the map, wavelengths shorter
than two elements are aliased, so choose the mesh no coarser than the map where that matters.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

TEXT_SUFFIXES = (".txt", ".dat", ".asc", ".csv", ".xyz")

__all__ = ["read_height_map", "detrended", "resampled"]


def read_height_map(path: str | Path) -> np.ndarray:
    """The heights of the file ``path`` in its own unit, float64; 1-D for a profile.
    Raises OSError (missing, unreadable) or ValueError (not a height map)."""
    path = Path(path)
    stat = path.stat()  # FileNotFoundError names the file
    return _read(str(path), stat.st_mtime_ns, stat.st_size).copy()


@lru_cache(maxsize=8)
def _read(path: str, mtime: int, size: int) -> np.ndarray:
    suffix = Path(path).suffix.lower()
    if suffix == ".npy":
        heights = np.load(path, allow_pickle=False)
    elif suffix in TEXT_SUFFIXES:
        text = Path(path).read_text(encoding="utf-8", errors="strict")
        heights = np.loadtxt(text.replace(",", " ").splitlines(), dtype=float, ndmin=2)
    else:
        heights = _read_with_surface_topography(path)
    heights = np.asarray(heights, dtype=float)
    if heights.ndim == 2 and 1 in heights.shape:
        heights = heights.ravel()
    if heights.ndim not in (1, 2) or heights.size < 2:
        raise ValueError(f"expected a 2-D map or a profile, got an array of shape {heights.shape}")
    return heights


def _read_with_surface_topography(path: str) -> np.ndarray:
    try:
        from SurfaceTopography import read_topography
    except ImportError:
        raise ValueError(
            f"{Path(path).suffix!r} files are read through SurfaceTopography: "
            "pip install -e '.[topography]' (or give .npy or text)"
        ) from None
    return np.asarray(read_topography(path).heights(), dtype=float)


def detrended(heights: np.ndarray, mode: str) -> np.ndarray:
    """``heights`` with nothing (``"none"``), the mean (``"mean"``) or the least-squares plane
    (a profile: line) (``"plane"``) removed."""
    heights = np.asarray(heights, dtype=float)
    if mode == "none":
        return heights.copy()
    if mode == "mean":
        return heights - heights.mean()
    axes = np.meshgrid(*(np.arange(n, dtype=float) for n in heights.shape), indexing="ij")
    design = np.column_stack([np.ones(heights.size), *(a.ravel() for a in axes)])
    coefficients, *_ = np.linalg.lstsq(design, heights.ravel(), rcond=None)
    return heights - (design @ coefficients).reshape(heights.shape)


def resampled(heights: np.ndarray, pixel_size: float, grid) -> np.ndarray:
    """The map (centred on the axis, spacing ``pixel_size`` mm) read at the element centres of
    ``grid`` (module docstring): shape ``grid.shape``."""
    from scipy.ndimage import map_coordinates

    if heights.ndim == 1:
        positions = (np.arange(heights.size) - 0.5 * (heights.size - 1)) * pixel_size
        return np.interp(grid.x, positions, heights)[:, None]
    rows = grid.x / pixel_size + 0.5 * (heights.shape[0] - 1)
    columns = grid.y / pixel_size + 0.5 * (heights.shape[1] - 1)
    coordinates = np.meshgrid(rows, columns, indexing="ij")
    return map_coordinates(heights, coordinates, order=1, mode="nearest")
