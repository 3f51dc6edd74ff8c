"""Fatigue results of a fretting study with a ``[fatigue]`` section: per case, whether and
where a crack is predicted (no matplotlib here; the figures are ``fatigue_figures``).

A criterion predicts crack nucleation at the value read at the critical distance (the
``[fatigue]`` ``method`` and ``length``; the hot spot itself for ``"hotspot"``):

- a risk criterion (no life curve: Crossland, Dang Van) when that value is ≥ 1;
- a criterion with a life curve (SWT, Fatemi–Socie) when the life of that value (its
  Basquin–Coffin–Manson inversion, ``engine.fatigue``) is at most the case's simulated cycles
  N: a crack would have nucleated within the cycles the case ran.

Both are expressed as one *crack ratio* (≥ 1: crack predicted): the risk itself, or N over
the life. The location is the surface hot spot below which the critical distance is read
(the hot spot of the map for ``"hotspot"``), given in mm and over the contact half-width a
(summary ``contact_radius``: the area-equivalent radius of a 3-D contact, the half-width of
a line contact): x/a = −1 is the trailing edge of a case whose bulk stress is in phase with
the tangential force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from engine.fatigue import CRITERIA, Elasticity, FatigueOptions, build_criteria

from .fretting import setting
from .results import ResultCase, Results

__all__ = [
    "CriterionVerdict",
    "has_fatigue",
    "case_verdicts",
    "crack_ratio",
    "hot_spot_history",
    "fatigue_table",
    "fatigue_facts",
]


@dataclass(frozen=True)
class CriterionVerdict:
    """One criterion of one case at one recorded cycle: the hot spot (``value`` in ``unit``,
    ``x``, ``z`` mm, ``angle`` deg, ``life`` cycles; NaN where none), the ``critical`` value
    read below the surface hot spot at ``critical_x`` (mm), its life ``critical_life`` (NaN:
    no life curve), and the case's simulated ``cycles``."""

    name: str
    column: str
    unit: str
    cycle: int
    value: float
    x: float
    z: float
    angle: float
    life: float
    critical: float
    critical_x: float
    critical_life: float
    cycles: int

    @property
    def ratio(self) -> float:
        """≥ 1: crack predicted (module docstring)."""
        if math.isnan(self.critical_life):
            return self.critical
        if self.critical_life == 0.0:
            return math.inf
        return self.cycles / self.critical_life

    @property
    def crack(self) -> bool:
        return self.ratio >= 1.0


def has_fatigue(study: Results) -> bool:
    """True when the study has a ``[fatigue]`` section and some case stored its results."""
    return "fatigue" in study.study and any(case.fatigue for case in study.completed)


def _criteria(study: Results, case: ResultCase) -> list:
    """The case's criteria: the study's ``[fatigue]`` with the case's swept constants, on
    the flat's E and ν (its swept values too)."""
    table = dict(study.study["fatigue"])
    for key, value in case.settings.items():
        if key.startswith("fatigue."):
            table[key.split(".", 1)[1]] = value
    constants = {
        name: float(table[name])
        for criterion in table["criteria"]
        for name in CRITERIA[criterion].constants
    }
    options = FatigueOptions(
        table.get("amplitude_method", "chord"), float(table.get("plane_step", 1.0))
    )
    young = float(setting(study, case, "material.E_A"))
    poisson = float(setting(study, case, "material.nu_A"))
    return build_criteria(table["criteria"], constants, Elasticity(young, poisson), options)


def case_verdicts(
    study: Results, case: ResultCase, cycle: int | None = None
) -> list[CriterionVerdict]:
    """The verdict of every criterion of ``case`` at recorded cycle ``cycle`` (default: the
    last one with fatigue results); empty without any."""
    if not case.fatigue:
        return []
    cycle = max(case.fatigue) if cycle is None else cycle
    stored = case.fatigue.get(cycle, {})
    verdicts = []
    for criterion in _criteria(study, case):
        spot = stored.get(f"{criterion.column}_hot_spot")
        if spot is None:
            continue
        value, x, z, angle, life, critical, critical_x = (float(v) for v in spot)
        critical_life = math.nan
        if criterion.reports_life:
            critical_life = float(criterion.life(np.array([critical]))[0])
        cycles = int(case.summary.get("cycles") or cycle)
        verdicts.append(
            CriterionVerdict(
                criterion.name,
                criterion.column,
                criterion.unit,
                int(cycle),
                value,
                x,
                z,
                angle,
                life,
                critical,
                critical_x,
                critical_life,
                cycles,
            )  # fmt: skip
        )
    return verdicts


def crack_ratio(study: Results, case: ResultCase) -> float:
    """The largest crack ratio of the case's criteria at its last recorded cycle (NaN
    without fatigue results)."""
    ratios = [verdict.ratio for verdict in case_verdicts(study, case)]
    return max(ratios) if ratios else math.nan


def hot_spot_history(case: ResultCase, column: str) -> tuple[np.ndarray, np.ndarray]:
    """(cycles, hot-spot values) of a criterion's value column: per simulated cycle
    (``history/<column>``, ``every_cycle``) or else per recorded cycle."""
    if column in case.history and "cycle" in case.history:
        return np.asarray(case.history["cycle"], float), np.asarray(case.history[column], float)
    cycles = sorted(c for c, maps in case.fatigue.items() if f"{column}_hot_spot" in maps)
    values = [float(case.fatigue[c][f"{column}_hot_spot"][0]) for c in cycles]
    return np.asarray(cycles, dtype=float), np.asarray(values, dtype=float)


def _edge(case: ResultCase, x: float) -> str:
    """x over the contact half-width a (summary ``contact_radius``), "" without it."""
    half = float(case.summary.get("contact_radius") or math.nan)
    return f"{x / half:+.2f}" if math.isfinite(half) and half > 0 else ""


def _life(value: float) -> str:
    return "–" if math.isnan(value) else ("∞" if math.isinf(value) else f"{value:.3g}")


def fatigue_table(study: Results) -> list[str]:
    """Markdown rows: per case and criterion, the last recorded cycle's hot spot (value, x, z,
    plane angle, life), the critical value and its life, and the verdict."""
    config = study.study["fatigue"]
    length = f", ℓ = {config['length']:g} mm" if "length" in config else ""
    header = [
        "case", "N", "criterion", "hot spot", "at (x, z) (mm)", "x/a", "plane (°)",
        "life (cycles)", f"critical ({config.get('method', 'hotspot')}{length})",
        "below x (mm)", "critical life (cycles)", "crack",
    ]  # fmt: skip
    lines = ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    for case in study.completed:
        for v in case_verdicts(study, case):
            unit = "" if v.unit == "1" else f" {v.unit}"
            angle = "–" if math.isnan(v.angle) else f"{v.angle:g}"
            cells = [
                case.label, f"{v.cycle:,}", v.name, f"{v.value:.4g}{unit}",
                f"({v.x:.4g}, {v.z:.3g})", _edge(case, v.x) or "–", angle, _life(v.life),
                f"{v.critical:.4g}{unit}", f"{v.critical_x:.4g}", _life(v.critical_life),
                "yes" if v.crack else "no",
            ]  # fmt: skip
            lines.append("| " + " | ".join(cells) + " |")
    return lines


def fatigue_facts(study: Results) -> list[str]:
    """Per case, in words: whether a crack is predicted, by which criteria, and where."""
    facts = []
    for case in study.completed:
        verdicts = case_verdicts(study, case)
        if not verdicts:
            continue
        cracking = [v for v in verdicts if v.crack]
        if not cracking:
            worst = max(verdicts, key=lambda v: v.ratio)
            facts.append(
                f"{case.label}: no crack predicted at cycle {worst.cycle:,} (largest crack "
                f"ratio {worst.ratio:.3g}, {worst.name})"
            )
            continue
        where = cracking[0]
        edge = _edge(case, where.critical_x)
        names = ", ".join(f"{v.name} ({_ratio_words(v)})" for v in cracking)
        facts.append(
            f"{case.label}: crack predicted by {names}; at the surface at x = "
            f"{where.critical_x:.4g} mm"
            + (f" (x/a = {edge})" if edge else "")
            + ("" if math.isnan(where.angle) else f", critical plane {where.angle:g}°")
        )
    return facts


def _ratio_words(verdict: CriterionVerdict) -> str:
    if math.isnan(verdict.critical_life):
        return f"risk {verdict.critical:.3g}"
    return f"life {_life(verdict.critical_life)} ≤ {verdict.cycles:,} cycles"
