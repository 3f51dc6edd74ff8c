"""The stress history a fatigue criterion reads: Cartesian stresses at points over instants.

Conventions (package wide): stresses MPa, tension positive, lengths mm, z > 0 into the flat.
A history holds the six components of the stress tensor at ``n_points`` points and
``n_instants`` instants as one array of shape (n_instants, n_points, 6) in the order
``COMPONENTS = ("xx", "yy", "zz", "yz", "xz", "xy")``, and the points' coordinates x, z (mm).
Fields of any point shape (a plane (n_x, n_z), a line of points) are flattened; ``shape``
restores it. The flat's elastic constants (``Elasticity``) turn stresses into strains for the
strain-based criteria (isotropic Hooke's law).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..validation import require_poisson, require_positive

__all__ = ["COMPONENTS", "Elasticity", "StressHistory"]

COMPONENTS = ("xx", "yy", "zz", "yz", "xz", "xy")


@dataclass(frozen=True)
class Elasticity:
    """Young's modulus E (MPa) and Poisson ratio ν of the body the criteria assess."""

    young_modulus: float
    poisson_ratio: float

    def __post_init__(self) -> None:
        require_positive("young_modulus", self.young_modulus)
        require_poisson("poisson_ratio", self.poisson_ratio)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2(1 + ν)) (MPa)."""
        return self.young_modulus / (2.0 * (1.0 + self.poisson_ratio))


@dataclass(frozen=True)
class StressHistory:
    """Stresses (MPa) ``tensor`` of shape (n_instants, n_points, 6) (order ``COMPONENTS``) at
    the points ``x``, ``z`` (mm, shape (n_points,)); ``shape`` is the points' original shape."""

    tensor: np.ndarray
    x: np.ndarray
    z: np.ndarray
    shape: tuple[int, ...]

    @classmethod
    def from_components(cls, components, x, z) -> StressHistory:
        """From a mapping of component name → array (n_instants, *shape) (missing shear
        components are zero, as for plane strain) and coordinates broadcastable to ``shape``."""
        xx = np.asarray(components["xx"], dtype=float)
        if xx.ndim < 1 or xx.shape[0] < 1:
            raise ValueError(f"a stress history needs an instants axis, got shape {xx.shape}")
        shape = xx.shape[1:]
        columns = []
        for name in COMPONENTS:
            value = components.get(name)
            value = np.zeros(xx.shape) if value is None else np.asarray(value, dtype=float)
            if value.shape != xx.shape:
                raise ValueError(f"component {name!r} has shape {value.shape}, not {xx.shape}")
            columns.append(value.reshape(xx.shape[0], -1))
        tensor = np.stack(columns, axis=-1)
        if not np.all(np.isfinite(tensor)):
            raise ValueError("the stress history holds non-finite values")
        points = math.prod(shape)
        x = np.broadcast_to(np.asarray(x, dtype=float), shape).reshape(points)
        z = np.broadcast_to(np.asarray(z, dtype=float), shape).reshape(points)
        return cls(tensor=tensor, x=x, z=z, shape=tuple(shape))

    @property
    def n_instants(self) -> int:
        return self.tensor.shape[0]

    @property
    def n_points(self) -> int:
        return self.tensor.shape[1]

    def take(self, points: np.ndarray) -> StressHistory:
        """The history at a subset of the points (a flat index array or slice)."""
        x, z = self.x[points], self.z[points]
        return StressHistory(self.tensor[:, points], x, z, (x.size,))

    def matrices(self) -> np.ndarray:
        """The tensors as symmetric 3 × 3 matrices, shape (n_instants, n_points, 3, 3)."""
        t = self.tensor
        rows = [
            [t[..., 0], t[..., 5], t[..., 4]],
            [t[..., 5], t[..., 1], t[..., 3]],
            [t[..., 4], t[..., 3], t[..., 2]],
        ]
        return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)
