"""Regular surface grid of rectangular boundary elements over the potential contact zone.

Convention used everywhere in the package: a surface field is a float array of shape
``(n_x, n_y)`` indexed ``[i, j]`` at the element centre ``(x[i], y[j])`` ("ij" indexing,
axis 0 is x, axis 1 is y). Lengths in mm; the grid is centred on the punch axis.

A *line grid* (:meth:`Grid.line`) is the 1-D grid of a plane-strain (line) contact: ``n``
elements along x and one element of unit length along y (``n_y = 1``, Δy = 1 mm), so that
loads "per unit length" (N/mm) are the loads on this 1 mm slice (N) and every solver written
for ``(n_x, n_y)`` fields runs unchanged on ``(n, 1)`` fields.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .validation import CheckedRecord, require_positive

LINE_HALF_LENGTH = 0.5  # mm: a line grid's one element along y is 1 mm long


def _element_count(name: str, value) -> int:
    """An element count along one axis, as int."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be an integer >= 2, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class Grid(CheckedRecord):
    n_x: int
    n_y: int
    half_width_x: float
    half_width_y: float

    checks = {
        "n_x": _element_count,
        "n_y": _element_count,
        "half_width_x": require_positive,
        "half_width_y": require_positive,
    }

    def __post_init__(self) -> None:
        super().__post_init__()
        line = self.n_y == 1 and self.half_width_y == LINE_HALF_LENGTH
        if self.n_x < 2 or (self.n_y < 2 and not line):
            name, value = ("n_x", self.n_x) if self.n_x < 2 else ("n_y", self.n_y)
            raise ValueError(f"{name} must be an integer >= 2, got {value!r}")

    @classmethod
    def line(cls, n: int, half_width: float) -> Grid:
        """``n`` elements over ``[-half_width, half_width]`` (mm) along x and one element of
        unit length (1 mm) along y: the grid of a plane-strain line contact."""
        return cls(n, 1, half_width, LINE_HALF_LENGTH)

    @property
    def is_line(self) -> bool:
        """True for a line grid (plane strain, one element of unit length along y)."""
        return self.n_y == 1

    @classmethod
    def square(cls, n: int, half_width: float) -> Grid:
        """``n × n`` elements over the square ``[-half_width, half_width]²`` (mm)."""
        return cls(n, n, half_width, half_width)

    @property
    def shape(self) -> tuple[int, int]:
        return (self.n_x, self.n_y)

    @property
    def dx(self) -> float:
        return 2.0 * self.half_width_x / self.n_x

    @property
    def dy(self) -> float:
        return 2.0 * self.half_width_y / self.n_y

    @property
    def element_area(self) -> float:
        """ΔA = Δx·Δy in mm²."""
        return self.dx * self.dy

    @cached_property
    def x(self) -> np.ndarray:
        """Element-centre x coordinates, shape (n_x,), mm."""
        return -self.half_width_x + self.dx * (np.arange(self.n_x) + 0.5)

    @cached_property
    def y(self) -> np.ndarray:
        """Element-centre y coordinates, shape (n_y,), mm."""
        return -self.half_width_y + self.dy * (np.arange(self.n_y) + 0.5)

    def coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """Element centres ``(X, Y)``, each of shape ``(n_x, n_y)``, mm."""
        return np.meshgrid(self.x, self.y, indexing="ij")

    def radius(self) -> np.ndarray:
        """Distance of each element centre from the punch axis, shape ``(n_x, n_y)``, mm."""
        return np.hypot(self.x[:, None], self.y[None, :])  # broadcast: no coordinate arrays
