"""The driver: criteria evaluated on a stress history, their hot spots and critical values.

``assess(history, criteria, method=…, length=…, stress_at=…)`` evaluates every criterion (any
object with the protocol of ``engine.fatigue.base``) on every point of the history, finds the
hot spot (maximum value; its x, z, critical-plane angle and life) and reads the critical
distance value (``engine.fatigue.distance``) through ``stress_at``. It never branches on a
criterion's name: a fifth criterion needs only its module and its line in ``CRITERIA``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .base import CriterionField, FatigueCriterion, FatigueOptions
from .criteria import CRITERIA
from .distance import METHODS, StressEvaluator, critical_points
from .history import Elasticity, StressHistory

__all__ = ["HotSpot", "CriterionAssessment", "assess", "build_criteria"]


@dataclass(frozen=True)
class HotSpot:
    """The maximum of a criterion: ``value`` (criterion unit), ``x``, ``z`` (mm), ``angle`` of
    the critical plane (deg; nan for invariant criteria) and ``life`` (cycles; nan if none)."""

    value: float
    x: float
    z: float
    angle: float = math.nan
    life: float = math.nan


@dataclass(frozen=True)
class CriterionAssessment:
    """One criterion on one stress history: the ``field`` at every point (shape of the
    history's points via ``map``), the ``hot_spot``, and the ``critical`` value by ``method``
    at ``length`` ℓ (mm) with the surface hot spot it was read below (``surface``)."""

    name: str
    column: str
    unit: str
    field: CriterionField
    shape: tuple[int, ...]
    hot_spot: HotSpot
    surface: HotSpot
    critical: float
    method: str
    length: float | None

    @property
    def map(self) -> np.ndarray:
        """The criterion's values on the plane, shape of the history's points."""
        return self.field.value.reshape(self.shape)

    def summary(self) -> dict[str, float]:
        """The summary columns: ``<column>``, ``_x``, ``_z``, ``_critical`` and, where the
        criterion gives them, ``_angle`` (deg) and ``_life`` (cycles)."""
        spot, column = self.hot_spot, self.column
        row = {column: spot.value, f"{column}_x": spot.x, f"{column}_z": spot.z}
        if self.field.angle is not None:
            row[f"{column}_angle"] = spot.angle
        row[f"{column}_critical"] = self.critical
        if self.field.life is not None:
            row[f"{column}_life"] = spot.life
        return row


def build_criteria(
    names: Sequence[str | type],
    constants: Mapping[str, float],
    elasticity: Elasticity,
    options: FatigueOptions | None = None,
    registry: Mapping[str, type] | None = None,
) -> list[FatigueCriterion]:
    """Criteria by name (keys of ``registry``, default ``engine.fatigue.CRITERIA``) or class,
    each given the constants it names from ``constants`` (MPa; a flat mapping)."""
    if registry is None:
        registry = CRITERIA
    built = []
    for name in names:
        cls = registry.get(name) if isinstance(name, str) else name
        if cls is None:
            raise ValueError(f"unknown fatigue criterion {name!r}; known: {sorted(registry)}")
        built.append(
            cls(
                {key: constants[key] for key in cls.constants if key in constants},
                elasticity,
                options,
            )
        )
    return built


def _spot(field: CriterionField, history: StressHistory, index: int) -> HotSpot:
    return HotSpot(
        value=float(field.value[index]),
        x=float(history.x[index]),
        z=float(history.z[index]),
        angle=math.nan if field.angle is None else float(field.angle[index]),
        life=math.nan if field.life is None else float(field.life[index]),
    )


def _surface_spot(field: CriterionField, history: StressHistory) -> HotSpot:
    """The maximum over the shallowest evaluated points (the surface row)."""
    surface = np.flatnonzero(history.z == history.z.min())
    return _spot(field, history, int(surface[np.argmax(field.value[surface])]))


def _critical(criterion, method, length, stress_at, surface: HotSpot) -> float:
    points = critical_points(method, length, surface.x)
    values = criterion.evaluate(stress_at(points.x, points.z)).value
    return float(np.dot(points.weights, values))


def assess(
    history: StressHistory,
    criteria: Sequence[FatigueCriterion],
    *,
    method: str = "hotspot",
    length: float | None = None,
    stress_at: StressEvaluator | None = None,
) -> list[CriterionAssessment]:
    """Evaluate ``criteria`` on ``history`` (module docstring). ``method`` other than
    "hotspot" needs ``length`` ℓ (mm) and ``stress_at``, the evaluator of the same stress
    history at any points (x, z) (mm)."""
    if method not in METHODS:
        raise ValueError(f"fatigue method must be one of {METHODS}, got {method!r}")
    if method != "hotspot" and (length is None or stress_at is None):
        raise ValueError(f"fatigue method {method!r} needs a length (mm) and a stress evaluator")
    results = []
    for criterion in criteria:
        field = criterion.evaluate(history)
        hot = _spot(field, history, int(np.argmax(field.value)))
        surface = _surface_spot(field, history)
        critical = hot.value
        if method != "hotspot":
            critical = _critical(criterion, method, length, stress_at, surface)
        results.append(
            CriterionAssessment(
                criterion.name,
                criterion.column,
                criterion.unit,
                field,
                history.shape,
                hot,
                surface,
                critical,
                method,
                length,
            )
        )
    return results
