"""The table of fatigue criteria: name → criterion class (one module each)."""

from __future__ import annotations

from engine.plugins import GROUPS, Registry, subclass_of

from .base import FatigueCriterion
from .crossland import Crossland
from .dang_van import DangVan
from .fatemi_socie import FatemiSocie
from .swt import SmithWatsonTopper

__all__ = ["CRITERIA"]

#: name → criterion class: the bundled ones, then those other packages register (entry-point
#: group ``fretting_engine.criteria``, :mod:`engine.plugins`).
CRITERIA: Registry[type[FatigueCriterion]] = Registry(
    GROUPS["criteria"],
    {cls.name: cls for cls in (Crossland, DangVan, SmithWatsonTopper, FatemiSocie)},
    what="fatigue criterion",
    check=subclass_of(FatigueCriterion),
)
