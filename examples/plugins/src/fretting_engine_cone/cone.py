"""``shape = "cone"``: a rigid-profile cone whose flanks rise at ``angle`` α from the flat,
axis at x = y = 0: g = r tan α, a surface everywhere.

Sneddon's cone (Sneddon, Int. J. Eng. Sci. 3, 1965, 47-57; Johnson, Contact Mechanics,
1985, §5.3) in the contact modulus E* (MPa, Eq. 6 of the engine's paper): the contact radius
a, the load P (N) and the approach δ (mm) are related by

    P = (π/2) E* a² tan α,        δ = (π/2) a tan α,

and the mean pressure P/(π a²) = E* tan α / 2 does not depend on the load. The profile's
contact length a0 is that a at the load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from engine.geometry import Profile
from engine.keys import parameter

__all__ = ["ConePunch", "sneddon_contact_radius", "sneddon_approach"]


def sneddon_contact_radius(load: float, angle: float, contact_modulus: float) -> float:
    """a = √(2P / (π E* tan α)) (mm) of a cone of flank ``angle`` α (degrees) pressed with
    ``load`` P (N) on a half-space of contact modulus E* (MPa)."""
    return math.sqrt(2.0 * load / (math.pi * contact_modulus * math.tan(math.radians(angle))))


def sneddon_approach(load: float, angle: float, contact_modulus: float) -> float:
    """δ = (π/2) a tan α (mm), the rigid approach of Sneddon's cone at ``load`` P (N)."""
    radius = sneddon_contact_radius(load, angle, contact_modulus)
    return 0.5 * math.pi * radius * math.tan(math.radians(angle))


@dataclass(frozen=True)
class ConePunch(Profile):
    """Cone with flanks at ``angle`` α (degrees) from the flat: g = r tan α (mm)."""

    name = "cone"
    description = "cone with flanks at `angle` from the flat (example plug-in)"
    covered = "Sneddon contact radius"
    angle: float = parameter(
        "degree",
        "angle α of the cone's flanks from the flat (Sneddon's cone)",
        minimum=0.0,
        strict=True,
        maximum=30.0,
        why="the half-space model assumes small surface slopes",
        example=1.0,
    )

    def gap(self, grid) -> np.ndarray:
        """g = r tan α (mm) at the element centres, shape ``grid.shape``."""
        x, y = grid.coordinates()
        return np.hypot(x, y) * math.tan(math.radians(self.angle))

    def contact_length(self, load: float, contact_modulus: float) -> float:
        """Sneddon's contact radius a (mm) at the load P (N)."""
        return sneddon_contact_radius(load, self.angle, contact_modulus)

    def check_grid(self, grid) -> None:
        """Any grid: whether it covers the contact depends on the load and is checked after
        every increment (engine.geometry.border_contact)."""
        return None
