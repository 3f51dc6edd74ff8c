"""The table of fatigue criteria: name → criterion class (one module each)."""

from __future__ import annotations

from .base import FatigueCriterion
from .crossland import Crossland
from .dang_van import DangVan
from .fatemi_socie import FatemiSocie
from .swt import SmithWatsonTopper

__all__ = ["CRITERIA"]

CRITERIA: dict[str, type[FatigueCriterion]] = {
    "crossland": Crossland,
    "dang_van": DangVan,
    "swt": SmithWatsonTopper,
    "fatemi_socie": FatemiSocie,
}
