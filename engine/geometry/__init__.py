"""Contact geometries: the punch profiles, one module each, one protocol
(:class:`~.base.Profile`), one table.

:data:`PROFILES` maps ``[punch] shape`` to its profile class; :func:`profile_for` builds a
profile from its keys and :func:`profile_from_table` from a ``[punch]`` table. A profile's
``[punch]`` keys are its dataclass fields (unit, meaning and bounds in their metadata,
:meth:`Profile.keys`). Each profile supplies the geometric gap g_g of
Eq. (1) (mm; ``numpy.inf`` marks elements the punch cannot touch), its contact length a0,
its default mesh, its border check and the summary's nominal values:

- :class:`FlatPunch` (``"flat"``, the paper's): g = 0 for r ≤ a, no surface beyond;
- :class:`RoundedPunch` (``"rounded"``): a flat face of radius b and a toroidal edge ρ;
- :class:`SphericalPunch` (``"sphere"``): g = r²/(2R), Hertz's a0;
- :class:`CylinderProfile` (``"cylinder"``): a line contact, g = x²/(2R);
- :class:`RoundedPadProfile` (``"pad"``): a line contact, a flat of half-width b with rounds.

Adding a geometry: one module with a :class:`~.base.Profile` subclass and one line in
:data:`PROFILES`, or, from another package, an entry point of the group
``fretting_engine.profiles`` (:mod:`engine.plugins`; the example under ``examples/plugins/``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from engine.plugins import GROUPS, Registry, subclass_of

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
    "DEFAULT_SHAPE",
    "profile_for",
    "profile_from_table",
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

#: ``[punch] shape`` → its profile class: the built-in ones in the order the manual lists
#: them, then those other packages register (entry-point group ``fretting_engine.profiles``,
#: :mod:`engine.plugins`).
PROFILES: Registry[type[Profile]] = Registry(
    GROUPS["profiles"],
    {
        profile.name: profile
        for profile in (FlatPunch, RoundedPunch, SphericalPunch, CylinderProfile, RoundedPadProfile)
    },
    what="punch profile",
    check=subclass_of(Profile),
)


#: ``[punch] shape`` when the section leaves it out (the paper's punch).
DEFAULT_SHAPE = FlatPunch.name


def profile_for(shape: str, **keys: float) -> Profile:
    """The profile of ``[punch] shape`` with its ``keys`` (``radius=1.8`` …, in the units
    the profile declares)."""
    if shape not in PROFILES:
        raise ValueError(f"unknown punch shape {shape!r}: one of {', '.join(PROFILES)}")
    return PROFILES[shape](**keys)


def profile_from_table(table: Mapping[str, Any]) -> Profile:
    """The profile of a ``[punch]`` table as a results file stores it (``shape``, default
    ``"flat"``, and the shape's keys; a swept key written in)."""
    shape = table.get("shape", DEFAULT_SHAPE)
    if shape not in PROFILES:
        raise ValueError(f"unknown punch shape {shape!r}: one of {', '.join(PROFILES)}")
    keys = PROFILES[shape].keys()
    return profile_for(shape, **{name: float(table[name]) for name in keys if name in table})
