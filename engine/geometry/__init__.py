"""Contact geometries: the punch profiles, one module each, one protocol
(:class:`~.base.Profile`), one table.

:data:`PROFILES` maps ``[punch] shape`` to its profile class; :func:`profile_for` builds the
profile of a study's ``[punch]`` section. Each profile supplies the geometric gap g_g of
Eq. (1) (mm; ``numpy.inf`` marks elements the punch cannot touch), its contact length a0,
its default mesh, its border check and the summary's nominal values:

- :class:`FlatPunch` (``"flat"``, the paper's): g = 0 for r ≤ a, no surface beyond;
- :class:`RoundedPunch` (``"rounded"``): a flat face of radius b and a toroidal edge ρ;
- :class:`SphericalPunch` (``"sphere"``): g = r²/(2R), Hertz's a0;
- :class:`CylinderProfile` (``"cylinder"``): a line contact, g = x²/(2R);
- :class:`RoundedPadProfile` (``"pad"``): a line contact, a flat of half-width b with rounds.

Adding a geometry: one module with a :class:`~.base.Profile` subclass, one line in
:data:`PROFILES`, its docs (docs/explanation/architecture.md, "Add a contact geometry").
"""

from __future__ import annotations

from .base import (
    HERTZ_MARGIN,
    ContactReachesBorder,
    LineProfile,
    Profile,
    border_contact,
    may_reach_border,
)
from .cylinder import CylinderProfile
from .flat import FlatPunch
from .pad import RoundedPadProfile
from .rounded import RoundedPunch
from .sphere import SphericalPunch

__all__ = [
    "PROFILES",
    "profile_for",
    "Profile",
    "LineProfile",
    "HERTZ_MARGIN",
    "FlatPunch",
    "RoundedPunch",
    "SphericalPunch",
    "CylinderProfile",
    "RoundedPadProfile",
    "ContactReachesBorder",
    "border_contact",
    "may_reach_border",
]

#: ``[punch] shape`` → its profile class, in the order the manual lists them.
PROFILES: dict[str, type[Profile]] = {
    profile.name: profile
    for profile in (FlatPunch, RoundedPunch, SphericalPunch, CylinderProfile, RoundedPadProfile)
}


def profile_for(shape: str, radius: float, edge_radius: float | None = None) -> Profile:
    """The profile of ``[punch] shape``, ``radius`` and ``edge_radius`` (mm)."""
    if shape not in PROFILES:
        raise ValueError(f"unknown punch shape {shape!r}: one of {', '.join(PROFILES)}")
    return PROFILES[shape].from_settings(radius, edge_radius)
