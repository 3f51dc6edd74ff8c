"""Multiaxial fatigue criteria on a contact's stress history, with critical distances.

A criterion is a plug-in: one module with one class implementing the small protocol of
``engine.fatigue.base`` (``name``, ``column``, ``unit``, ``constants``, ``evaluate``), and one
line in ``CRITERIA`` (``criteria``). The driver (``assess``) never branches on a criterion's
name; a user may also pass a class instead of a name (``build_criteria``). Shared quantities
(√J2,a, σ_H, the critical planes, the life inversion) live in ``quantities``; the
critical-distance methods in ``distance``.
"""

from .assessment import CriterionAssessment, HotSpot, assess, build_criteria
from .base import CriterionField, FatigueCriterion, FatigueOptions
from .criteria import CRITERIA
from .crossland import Crossland
from .dang_van import DangVan
from .distance import METHODS, critical_points
from .fatemi_socie import FatemiSocie
from .history import Elasticity, StressHistory
from .swt import SmithWatsonTopper

__all__ = [
    "CRITERIA",
    "Crossland",
    "DangVan",
    "FatemiSocie",
    "SmithWatsonTopper",
    "METHODS",
    "CriterionAssessment",
    "CriterionField",
    "Elasticity",
    "FatigueCriterion",
    "FatigueOptions",
    "HotSpot",
    "StressHistory",
    "assess",
    "build_criteria",
    "critical_points",
]
