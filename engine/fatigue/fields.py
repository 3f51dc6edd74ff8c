"""Stress histories from the contact solvers: a recorded cycle's surface tractions, increment
by increment, turned into the history of the evaluated plane and into an evaluator at any
point (the critical distances).

``CycleRecorder`` collects the increments of one cycle (pressure, tractions in MPa on the
surface grid, and the bulk stress σ_B of the increment, MPa, line contacts). Then

- ``plane_history(stress, increments, angle)``: the history on the plane the stress evaluator
  computes (``SubsurfaceStress.plane`` of a 3-D case at the sliding direction's angle, or
  ``LineSubsurfaceStress.plane``, the whole x–z plane of a line contact), one DC-FFT
  evaluation per increment (``planes_history``: from planes the caller already has);
- ``LinePointStress`` and ``PlanePointStress``: the same history at arbitrary points
  (x along the plane, z > 0, mm) by direct sums of the element-integrated influence
  coefficients (``engine.kernels.line_stress``, ``engine.kernels.stress``) over the surface
  elements: the exact field of the discretised tractions there, not an interpolation between
  layers or samples.

Conventions of ``engine.solvers.subsurface``: mm, MPa, tension positive, z > 0 into the flat.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..grid import Grid
from ..kernels.line_stress import strip_stress_coefficients
from ..kernels.stress import COMPONENTS, LOADS, element_stress
from .history import StressHistory

__all__ = [
    "Increment",
    "CycleRecorder",
    "plane_history",
    "planes_history",
    "LinePointStress",
    "PlanePointStress",
]


@dataclass(frozen=True)
class Increment:
    """Surface loads of one increment on the grid: ``pressure``, ``traction_x``,
    ``traction_y`` (MPa, grid shape) and the bulk stress ``bulk_stress`` σ_B (MPa)."""

    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    bulk_stress: float = 0.0


@dataclass
class CycleRecorder:
    """Collects a cycle's increments: ``bulk_stress`` is set by the analysis before each
    increment (``FrettingAnalysis.bulk_stress_listener``), ``add`` takes its tractions."""

    increments: list[Increment] = field(default_factory=list)
    bulk_stress: float = 0.0

    def set_bulk_stress(self, value: float) -> None:
        self.bulk_stress = float(value)

    def add(self, pressure, traction_x, traction_y) -> None:
        copy = [np.array(value, dtype=float) for value in (pressure, traction_x, traction_y)]
        self.increments.append(Increment(*copy, self.bulk_stress))

    def take(self) -> list[Increment]:
        """The increments so far, and start a new cycle."""
        increments, self.increments = self.increments, []
        return increments


def _plane(stress, increment: Increment, angle: float):
    if hasattr(stress, "bulk_stress"):  # line contacts carry σ_B
        return stress.plane(
            increment.pressure, increment.traction_x, bulk_stress=increment.bulk_stress
        )
    if increment.bulk_stress != 0.0:
        raise ValueError("a bulk stress needs a line (plane-strain) contact")
    return stress.plane(increment.pressure, increment.traction_x, increment.traction_y, angle=angle)


def plane_history(stress, increments: list[Increment], angle: float = 0.0) -> StressHistory:
    """The history (n_increments instants) on the evaluator's plane (module docstring);
    ``angle`` (rad) the plane's direction for a 3-D case."""
    if not increments:
        raise ValueError("a stress history needs at least one increment")
    return planes_history([_plane(stress, increment, angle) for increment in increments])


def planes_history(planes) -> StressHistory:
    """The history of stress planes already evaluated, one per instant (``StressField`` of
    ``engine.solvers.subsurface``, all of one shape (n_s, n_z)): points at (s, z), s the
    along-plane coordinate (x on a line contact)."""
    if not planes:
        raise ValueError("a stress history needs at least one instant")
    components = {key: np.stack([p.components[key] for p in planes]) for key in COMPONENTS}
    s = planes[0].s if planes[0].s is not None else planes[0].x
    return StressHistory.from_components(_renamed(components), s, planes[0].z)


def _renamed(components: dict) -> dict:
    """Solver components (keys of ``engine.kernels.stress.COMPONENTS``) for a history."""
    return {key: components[key] for key in ("xx", "yy", "zz", "yz", "xz", "xy")}


def _points(x, z) -> tuple[np.ndarray, np.ndarray]:
    x, z = (np.atleast_1d(np.asarray(v, dtype=float)) for v in np.broadcast_arrays(x, z))
    if np.any(z <= 0.0):
        raise ValueError("critical-distance points need depths z > 0 mm")
    return x.ravel(), z.ravel()


class LinePointStress:
    """The history of a line contact's ``increments`` at any points (x, z) of the x–z plane,
    by direct sums of the strip coefficients; σ_yy = ν(σ_xx + σ_zz) with σ_B in σ_xx."""

    def __init__(self, grid: Grid, poisson_ratio: float, increments: list[Increment]):
        self.grid, self.poisson_ratio = grid, poisson_ratio
        self.loads = {
            "pressure": np.stack([np.ravel(i.pressure) for i in increments]),
            "traction_x": np.stack([np.ravel(i.traction_x) for i in increments]),
        }
        self.bulk = np.array([i.bulk_stress for i in increments])

    def __call__(self, x, z) -> StressHistory:
        x, z = _points(x, z)
        offsets = x[:, None] - self.grid.x[None, :]
        coefficients = strip_stress_coefficients(offsets, z[:, None], self.grid.dx)
        sums = {
            key: sum(
                np.einsum("pj,tj->tp", coefficients[load][key], self.loads[load])
                for load in self.loads
            )
            for key in ("xx", "zz", "xz")
        }
        sums["xx"] = sums["xx"] + self.bulk[:, None]
        sums["yy"] = self.poisson_ratio * (sums["xx"] + sums["zz"])
        return StressHistory.from_components(sums, x, z)


class PlanePointStress:
    """The history of a 3-D case's ``increments`` at any points (s, z) of the vertical plane
    at ``angle`` (rad) through the axis (x = s cos φ, y = s sin φ), by direct sums of the
    element-integrated coefficients of ``engine.kernels.stress`` over all elements (one
    coefficient table per point, depth and load)."""

    def __init__(self, grid: Grid, poisson_ratio: float, increments, angle: float = 0.0):
        self.grid, self.poisson_ratio, self.angle = grid, poisson_ratio, angle
        if any(i.bulk_stress != 0.0 for i in increments):
            raise ValueError("a bulk stress needs a line (plane-strain) contact")
        self.loads = {
            load: np.stack([np.ravel(getattr(i, load)) for i in increments]) for load in LOADS
        }

    def __call__(self, s, z) -> StressHistory:
        s, z = _points(s, z)
        grid = self.grid
        cos, sin = math.cos(self.angle), math.sin(self.angle)
        sums = {
            key: np.zeros((next(iter(self.loads.values())).shape[0], s.size)) for key in COMPONENTS
        }
        for index, (along, depth) in enumerate(zip(s, z, strict=True)):
            offsets_x = along * cos - grid.x
            offsets_y = along * sin - grid.y
            for load, values in self.loads.items():
                table = element_stress(
                    offsets_x, offsets_y, depth, grid.dx, grid.dy, self.poisson_ratio, load
                )
                for key in COMPONENTS:
                    sums[key][:, index] += values @ table[key].ravel()
        return StressHistory.from_components(_renamed(sums), s, z)
