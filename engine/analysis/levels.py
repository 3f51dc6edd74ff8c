"""Contour levels of the von Mises stress figures (σ_VM/p0), shared by every figure module."""

from __future__ import annotations

import numpy as np

__all__ = ["VM_LEVEL_MAX", "von_mises_levels"]

VM_LEVEL_MAX = 2.0  # top of the linear part of the σ_VM/p0 colour scale


def von_mises_levels(top: float, linear_top: float = VM_LEVEL_MAX, steps: int = 20) -> np.ndarray:
    """Contour levels of σ_VM/p0: ``steps`` equal steps up to ``linear_top`` (0.1 apart by
    default), then geometric (four per doubling) up to ``top`` (the largest peak to show), the
    last level just above it, so that every marked peak lies inside the colour scale."""
    levels = np.linspace(0.0, linear_top, steps + 1)
    if not np.isfinite(top) or top <= linear_top:
        return levels
    count = max(int(np.ceil(4.0 * np.log2(top / linear_top))), 1)
    above = linear_top * (top / linear_top) ** (np.arange(1, count + 1) / count)
    above[-1] = np.nextafter(top, np.inf)
    return np.concatenate([levels, above])
