"""Critical distances: a criterion read at a material length ℓ (mm) from the hot spot.

Steep contact-edge gradients make the surface peak of a criterion depend on the mesh and
overestimate the risk; the theory of critical distances (Taylor, *The Theory of Critical
Distances*, Elsevier 2007; for fretting Araújo & Nowell, Int. J. Fatigue 24 (2002) 763,
Fouvry et al., Wear 250 (2001) 1389) reads it at a length ℓ instead. Methods:

- ``"hotspot"``: the maximum over the evaluated points (no length);
- ``"point"``: the value at depth ℓ/2 directly below the surface hot spot;
- ``"line"``: the mean over depth 0 … 2ℓ below the surface hot spot, by 12-point
  Gauss–Legendre quadrature (exact for polynomials of degree 23 in z);
- ``"area"``: the mean over the half-disc of radius 1.32 ℓ centred on the surface hot spot
  (Taylor's area method for plane strain), by 8 × 8-point Gauss quadrature in polar
  coordinates (r, angle from the surface).

The *surface hot spot* is the point of maximum value among the shallowest evaluated points
(the surface row of the plane). The points are evaluated exactly where the method puts them by
the stress evaluator passed in (``StressEvaluator``: any callable (x, z) → StressHistory at
those points), never interpolated between the plane's layers; the criterion's value is
averaged (not the stresses).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .history import StressHistory

__all__ = ["METHODS", "AREA_RADIUS", "StressEvaluator", "CriticalPoints", "critical_points"]

METHODS = ("hotspot", "point", "line", "area")
AREA_RADIUS = 1.32  # half-disc radius in units of ℓ (Taylor 2007, plane strain)
LINE_NODES, AREA_NODES = 12, 8

StressEvaluator = Callable[[np.ndarray, np.ndarray], StressHistory]


@dataclass(frozen=True)
class CriticalPoints:
    """Where a method reads the criterion: points ``x``, ``z`` (mm) and quadrature ``weights``
    (summing to 1) of the mean."""

    x: np.ndarray
    z: np.ndarray
    weights: np.ndarray


def _gauss(nodes: int, start: float, stop: float) -> tuple[np.ndarray, np.ndarray]:
    points, weights = np.polynomial.legendre.leggauss(nodes)
    half = 0.5 * (stop - start)
    return start + half * (points + 1.0), half * weights


def critical_points(method: str, length: float, surface_x: float) -> CriticalPoints:
    """The points of ``method`` ("point", "line", "area") for the length ℓ = ``length`` (mm)
    below the surface hot spot at x = ``surface_x`` (mm); module docstring."""
    if not length > 0.0:
        raise ValueError(f"fatigue length must be > 0 mm, got {length!r}")
    if method == "point":
        return CriticalPoints(np.array([surface_x]), np.array([0.5 * length]), np.ones(1))
    if method == "line":
        depth, weight = _gauss(LINE_NODES, 0.0, 2.0 * length)
        return CriticalPoints(np.full(depth.size, surface_x), depth, weight / weight.sum())
    if method == "area":
        radius, radial_weight = _gauss(AREA_NODES, 0.0, AREA_RADIUS * length)
        angle, angular_weight = _gauss(AREA_NODES, 0.0, np.pi)
        r, psi = np.meshgrid(radius, angle, indexing="ij")
        weight = np.outer(radial_weight * radius, angular_weight).ravel()
        x = surface_x + (r * np.cos(psi)).ravel()
        return CriticalPoints(x, (r * np.sin(psi)).ravel(), weight / weight.sum())
    raise ValueError(f"fatigue method must be one of {METHODS}, got {method!r}")
