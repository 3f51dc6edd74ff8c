"""The ``[fatigue]`` section of a study and the fatigue analysis of a case's recorded cycles.

``[fatigue]`` keys (``*`` required):

- ``criteria``* — a list of names of ``engine.fatigue.CRITERIA`` (``"crossland"``,
  ``"dang_van"``, ``"swt"``, ``"fatemi_socie"``);
- the material constants the listed criteria name, all required (no defaults): Crossland and
  Dang Van ``sigma_d``, ``tau_d`` (MPa); SWT ``sigma_f`` (MPa), ``b``, ``eps_f``, ``c``;
  Fatemi–Socie ``tau_f`` (MPa), ``gamma_f``, ``b0``, ``c0``, ``k``, ``sigma_y`` (MPa). E and ν
  are the flat's (``[material] E_A``, ``nu_A``). Each is sweepable (``"fatigue.sigma_d"``);
- ``method`` [``"hotspot"``] — the critical-distance method (``"hotspot"``, ``"point"``,
  ``"line"``, ``"area"``; ``engine.fatigue.distance``) and ``length`` ℓ (mm, required unless
  hotspot; sweepable);
- ``amplitude_method`` [``"chord"``] (√J2,a: half the longest chord, or ``"ball"``) and
  ``plane_step`` [1] (degrees between the critical planes searched; divides 180).

``FatigueAnalysis`` takes the increments of every recorded cycle (``increment_probe`` and the
bulk stress through ``set_bulk_stress``), evaluates the criteria on the case's subsurface
plane (the stress evaluator the case uses, at its depths) and at the critical-distance points
(exact direct sums, ``engine.fatigue.fields``), and keeps per recorded cycle the map of each
criterion, its hot spot (value, x, z, plane angle, life) and its critical value; its summary
columns are ``CriterionAssessment.summary()`` of the last recorded cycle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from engine.fatigue import CRITERIA, METHODS, FatigueOptions, assess, build_criteria
from engine.fatigue.fields import CycleRecorder, LinePointStress, PlanePointStress, plane_history
from engine.fatigue.history import Elasticity
from engine.fatigue.quantities import AMPLITUDE_METHODS

__all__ = [
    "FatigueConfig",
    "parse_fatigue",
    "fatigue_sweepable",
    "fatigue_columns",
    "FatigueAnalysis",
]

_OPTIONS = {"criteria", "method", "length", "amplitude_method", "plane_step"}


@dataclass(frozen=True)
class FatigueConfig:
    """The ``[fatigue]`` section, validated (module docstring)."""

    criteria: tuple[str, ...]
    constants: dict[str, float]
    method: str = "hotspot"
    length: float | None = None
    amplitude_method: str = "chord"
    plane_step: float = 1.0

    @property
    def options(self) -> FatigueOptions:
        return FatigueOptions(self.amplitude_method, self.plane_step)


def fatigue_sweepable(registry=CRITERIA) -> dict[str, str]:
    """Dotted sweep keys of the section with their units: every constant, ``length``."""
    keys = {
        f"fatigue.{name}": unit
        for cls in registry.values()
        for name, unit in cls.constant_units.items()
    }
    keys["fatigue.length"] = "mm"
    return keys


def _criteria(section) -> tuple[str, ...]:
    value = section.raw("criteria")
    names = value if isinstance(value, list) else [value]
    if not names or any(not isinstance(n, str) for n in names) or len(set(names)) != len(names):
        raise section.error("criteria", value, "must be a non-empty list of distinct names")
    for name in names:
        if name not in CRITERIA:
            known = ", ".join(f'"{k}"' for k in CRITERIA)
            raise section.error("criteria", value, f"unknown criterion {name!r} (known: {known})")
    return tuple(names)


def parse_fatigue(section) -> FatigueConfig:
    """Read the ``[fatigue]`` table (``engine.study.config.reader.Section``): errors name the
    key and the value (a constant a listed criterion needs, a constant no listed criterion
    uses, a length missing for a critical-distance method …)."""
    criteria = _criteria(section)
    needed = {
        name: CRITERIA[c].constant_units[name] for c in criteria for name in CRITERIA[c].constants
    }
    section.check_known(_OPTIONS | set(needed))
    constants = {name: section.number(name) for name in needed}
    method = section.string("method", "hotspot")
    if method not in METHODS:
        raise section.error("method", method, f"must be one of {', '.join(METHODS)}")
    length = None
    if method != "hotspot":
        length = section.number("length", minimum=0.0, strict=True, unit="mm")
    elif "length" in section.table:
        raise section.error(
            "length", section.table["length"], 'applies to a method other than "hotspot"'
        )
    amplitude = section.string("amplitude_method", "chord")
    if amplitude not in AMPLITUDE_METHODS:
        raise section.error(
            "amplitude_method", amplitude, f"must be one of {', '.join(AMPLITUDE_METHODS)}"
        )
    step = section.number("plane_step", 1.0, minimum=0.0, strict=True, unit="degree")
    if step > 90.0 or not float(180.0 / step).is_integer():
        raise section.error("plane_step", step, "must divide 180 degrees and be <= 90")
    config = FatigueConfig(criteria, constants, method, length, amplitude, step)
    elasticity = Elasticity(1.0, 0.0)  # the constants' own checks (signs), any elasticity
    try:
        build_criteria(criteria, constants, elasticity, config.options)
    except ValueError as error:
        key = next((k for k in constants if f"'{k}'" in str(error)), "criteria")
        raise section.error(key, constants.get(key, list(criteria)), str(error)) from None
    return config


def fatigue_columns(config: FatigueConfig) -> list[str]:
    """The summary columns of the section's criteria (``CriterionAssessment.summary``)."""
    columns = []
    for name in config.criteria:
        cls = CRITERIA[name]
        column = cls.column
        columns += [column, f"{column}_x", f"{column}_z"]
        columns += [f"{column}_angle"] if cls.reports_angle else []
        columns += [f"{column}_critical"]
        columns += [f"{column}_life"] if cls.reports_life else []
    return columns


@dataclass
class FatigueCycle:
    """The criteria on one recorded cycle: ``assessments`` (``CriterionAssessment`` each)."""

    cycle: int
    assessments: list = field(default_factory=list)

    def row(self) -> dict[str, float]:
        row: dict[str, float] = {}
        for assessment in self.assessments:
            row.update(assessment.summary())
        return row


class FatigueAnalysis:
    """Collects a case's recorded cycles and evaluates the criteria on them (module
    docstring). ``stress``: the case's plane evaluator (``SubsurfaceStress`` or
    ``LineSubsurfaceStress``); ``grid``; the flat's ``young_modulus`` (MPa) and
    ``poisson_ratio``; ``angle`` (rad) of a 3-D case's plane."""

    def __init__(
        self, config: FatigueConfig, stress, grid, young_modulus, poisson_ratio, angle=0.0
    ):
        self.config, self.stress, self.grid, self.angle = config, stress, grid, angle
        self.poisson_ratio = poisson_ratio
        elasticity = Elasticity(young_modulus, poisson_ratio)
        self.criteria = build_criteria(
            config.criteria, config.constants, elasticity, config.options
        )
        self.recorder = CycleRecorder()
        self.cycles: list[FatigueCycle] = []

    def set_bulk_stress(self, value: float) -> None:
        self.recorder.set_bulk_stress(value)

    def increment_probe(self, pressure, traction_x, traction_y) -> None:
        self.recorder.add(pressure, traction_x, traction_y)

    def _point_stress(self, increments):
        if self.grid.is_line:
            return LinePointStress(self.grid, self.poisson_ratio, increments)
        return PlanePointStress(self.grid, self.poisson_ratio, increments, self.angle)

    def finish_cycle(self, cycle: int) -> FatigueCycle:
        """Evaluate the increments collected since the last call as recorded cycle ``cycle``."""
        increments = self.recorder.take()
        history = plane_history(self.stress, increments, self.angle)
        config = self.config
        assessments = assess(
            history,
            self.criteria,
            method=config.method,
            length=config.length,
            stress_at=None if config.method == "hotspot" else self._point_stress(increments),
        )
        result = FatigueCycle(cycle, assessments)
        self.cycles.append(result)
        return result

    def summary_row(self) -> dict[str, Any]:
        """The last recorded cycle's columns (NaN before any)."""
        if not self.cycles:
            return {column: math.nan for column in fatigue_columns(self.config)}
        return self.cycles[-1].row()

    def history(self) -> dict[str, np.ndarray]:
        """Per recorded cycle: ``cycle`` and every summary column (arrays)."""
        rows = [cycle.row() for cycle in self.cycles]
        columns = fatigue_columns(self.config)
        table = {"cycle": np.array([c.cycle for c in self.cycles], dtype=float)}
        table.update({column: np.array([row[column] for row in rows]) for column in columns})
        return table

    def on_cycle(self, cycle: int, cycles: int) -> None:
        """After each simulated cycle (``CyclicAnalysis.run``'s ``on_cycle``): a recorded
        cycle's increments, if any were collected, are evaluated as cycle ``cycle``."""
        if self.recorder.increments:
            self.finish_cycle(cycle)
