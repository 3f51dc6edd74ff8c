"""Report of a tangential fretting study (``[loading] kind = "fretting"``).

``python -m engine report RESULTS.h5`` prints, for a fretting study, per case and recorded
cycle N (or the cycles of ``--cycles``):

- the fretting columns of the history: tangential force amplitude Q* (``q_amplitude``, N),
  displacement amplitude δ* (``displacement_amplitude``, mm), energy per cycle ∮ Q·dδ
  (``energy_per_cycle``, mJ), slip regime (partial / gross), wear volume (mm³), maximum wear
  depth (µm);
- σ_VM (MPa) at the increment of the largest |Q| (= Q*, column "σ_VM at Q*") on the
  vertical plane through the axis that contains the sliding direction, with its location
  (x, y, z in mm), and the largest σ_VM over the cycle's increments (``vm_cycle``) with its
  location;

then, with a ``[fatigue]`` section, per case and criterion the hot spot, the critical value
and whether and where a crack is predicted (``engine.analysis.fatigue``); then the measured
checks against the closed forms of the case's profile where it has some
(engine.analysis.fretting: Mindlin–Deresiewicz for a sphere, the cylinder's Cattaneo–Masing
loop for a line contact; μ1 = μ2 > 0; exact for K = 0): slip regime of the first cycle
against δ_slip(P), energy per cycle at N = 1 against the closed form's (partial or gross
slip), and against the analytic loop sampled at the solver's increments; Fouvry's energy
ratio A = W/(4δ*Q*) against the closed form's; under the energy wear law V/(α E_d). The
cases without a check are listed by reason ("no closed form for the pad profile", …).
No matplotlib here (tests/test_architecture.py).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence

import numpy as np

from .fatigue import fatigue_facts, fatigue_table, has_fatigue
from .fretting import FrettingCheck, check_case, material, unchecked_reason, wear_energy_ratios
from .names import key_title
from .report import edge_facts
from .results import ResultCase, Results

__all__ = ["fretting_report", "fretting_table", "fretting_facts"]

COLUMNS = [
    "case", "N", "q_amplitude (N)", "displacement_amplitude (mm)", "energy_per_cycle (mJ)",
    "slip_regime", "wear volume (mm³)", "max wear depth (µm)", "σ_VM at Q* (MPa)",
    "at (x, y, z) (mm)", "σ_VM cycle max (MPa)", "at (x, y, z) (mm)",
]  # fmt: skip
REGIME_WORDS = {0: "partial", 1: "gross"}
_PER_CONTACT = re.compile(r"\((N|mJ|mm³)\)")  # the units of COLUMNS a line contact divides


def table_columns(study: Results) -> list[str]:
    """:data:`COLUMNS` in the study's units (a line contact's forces, energies, volumes per
    unit length)."""
    return [
        _PER_CONTACT.sub(lambda match: f"({study.per_contact(match.group(1))})", column)
        for column in COLUMNS
    ]


def _row(values: Sequence[str]) -> str:
    return "| " + " | ".join(values) + " |"


ROUND_OFF_LENGTH = 1e-12  # mm: a coordinate of the plane at φ ≠ 0 that is zero up to round-off


def _point(*coordinates: float) -> str:
    """(x, y, z) in mm; |value| < 1e-12 mm shown as 0 (x = s cos 90° is 6e-17 s, not 0)."""
    shown = [0.0 if abs(value) < ROUND_OFF_LENGTH else value for value in coordinates]
    return "(" + ", ".join(f"{value:.4g}" for value in shown) + ")"


def _stress_columns(case: ResultCase, cycle: int) -> list[str]:
    """σ_VM at the largest |Q| (the recorded plane) and the cycle maximum, with locations."""
    columns = ["–", "–", "–", "–"]
    plane = case.planes.get(cycle)
    if plane is not None:
        value, x, y, z = plane.peak_point()
        columns[:2] = [f"{value:.4g}", _point(x, y, z)]
    record = case.fields.get(cycle, {}).get("vm_cycle")
    if record is not None:
        value, x, y, z = (float(v) for v in np.asarray(record).ravel()[:4])
        columns[2:] = [f"{value:.4g}", _point(x, y, z)]
    return columns


def fretting_table(study: Results, cycles: Sequence[int] | None = None) -> list[str]:
    """The fretting columns per case and cycle (module docstring)."""
    if cycles is None:
        cycles = sorted({n for case in study.completed for n in case.recorded_cycles})
    lines = [_row(table_columns(study)), "|" + "|".join("---" for _ in COLUMNS) + "|"]
    for case in study.completed:
        for cycle in cycles:
            energy = case.history_at("energy", cycle)
            if math.isnan(energy):
                continue
            regime = case.history_at("slip_regime", cycle)
            values = [
                case.label,
                f"{cycle:,}",
                f"{case.history_at('q_amplitude', cycle):.5g}",
                f"{case.history_at('displacement_amplitude', cycle):.4g}",
                f"{energy:.4g}",
                REGIME_WORDS.get(int(regime), "?") if math.isfinite(regime) else "–",
                f"{case.history_at('wear_volume', cycle):.3e}",
                f"{case.history_at('max_wear_depth', cycle) * 1e3:.4g}",
                *_stress_columns(case, cycle),
            ]
            lines.append(_row(values))
    return lines


def _reference_fact(study: Results, case: ResultCase, check: FrettingCheck) -> str:
    """One case against its closed forms: regime, energy, energy ratio."""
    if check.control == "displacement":
        where = f"δ*/δ_slip = {check.ratio:.3g}"
    else:
        where = f"Q*/μP = {check.ratio:.3g}"
    verdict = (
        f"as {check.reference}"
        if check.regime_holds
        else f"{check.reference} says {check.expected}"
    )
    unit = study.per_contact("mJ")
    text = (
        f"{case.label}: {where}, first cycle {check.computed} slip ({verdict}); energy at "
        f"N = 1 {check.energy:.4g} {unit} vs {check.exact:.4g} {unit} "
        f"({check.energy_error:+.2%})"
    )
    if math.isfinite(check.sampled_error):
        text += f", vs the analytic loop at the solver's increments {check.sampled_error:+.2%}"
    if math.isfinite(check.energy_ratio):
        text += (
            f"; energy ratio A = W/(4δ*Q*) {check.energy_ratio:.3g} "
            f"({check.reference} {check.exact_energy_ratio:.3g})"
        )
    if not check.exact_coupling:
        coupling = _coupling(study, case)
        text += f" [K = {coupling:.3g} ≠ 0: {check.reference} is only approximate]"
    return text


def _coupling(study: Results, case: ResultCase) -> float:
    return float(material(study, case).coupling)


def _worst(checks: Sequence[FrettingCheck], regime: str | None, error: str) -> str:
    """The largest |error| over the checks of ``regime`` (None: all), "–" without one."""
    errors = [getattr(check, error) for check in checks if regime in (None, check.expected)]
    errors = [abs(value) for value in errors if math.isfinite(value)]
    return f"{max(errors):.2%}" if errors else "–"


def fretting_facts(study: Results) -> list[str]:
    """The checks against the closed forms and the energy wear law (module docstring): the
    totals first (the figures of scripts/check_fretting_map.py), then one line per case, then
    the cases without a check, by reason."""
    checks = [(case, check_case(study, case)) for case in study.completed]
    applicable = [(case, check) for case, check in checks if check is not None]
    facts = []
    if applicable:
        holding = sum(check.regime_holds for _, check in applicable)
        found = [check for _, check in applicable]
        names = ", ".join(dict.fromkeys(check.reference for check in found))
        facts.append(
            f"slip regime of the first cycle on the side of the closed form's δ_slip "
            f"({names}; isotropic friction): {holding} of {len(applicable)} cases; largest "
            f"|energy error| at N = 1: partial slip {_worst(found, 'partial', 'energy_error')}, "
            f"gross slip {_worst(found, 'gross', 'energy_error')} (against the analytic loop "
            f"at the solver's increments {_worst(found, None, 'sampled_error')})"
        )
    ratios = [wear_energy_ratios(study, case) for case in study.completed]
    ratios = np.concatenate(ratios) if ratios else np.zeros(0)
    if ratios.size:
        facts.append(
            f"wear volume / (α E_d) over every case and history row: {ratios.min():.5f} … "
            f"{ratios.max():.5f} (1 for the energy wear law)"
        )
    facts += [_reference_fact(study, case, check) for case, check in applicable]
    unchecked: dict[str, list[str]] = {}
    for case, check in checks:
        if check is None:
            unchecked.setdefault(unchecked_reason(study, case), []).append(case.label)
    facts += [f"not checked, {reason}: {', '.join(labels)}" for reason, labels in unchecked.items()]
    return facts


def _value(study: Results, key: str, unit: str, default=None) -> str:
    """``loading.<key>`` of the study file with its unit, or "swept" when it is swept."""
    if f"loading.{key}" in study.swept_keys:
        return "swept"
    value = study.study["loading"].get(key)
    value = default if value is None else value
    return "–" if value is None else f"{float(value):g}{unit}"


def _signal(study: Results) -> str:
    """The tangential signal: control mode, amplitude and direction."""
    loading = study.study["loading"]
    if loading.get("force_amplitude") is not None or "loading.force_amplitude" in study.swept_keys:
        signal = f"force control, Q* = {_value(study, 'force_amplitude', ' ' + study.load_unit)}"
    else:
        signal = f"displacement control, δ* = {_value(study, 'amplitude', ' mm')}"
    return f"{signal} along {_value(study, 'direction', '°', 0.0)} from x"


def _fatigue_header(study: Results) -> str:
    config = study.study["fatigue"]
    length = f", ℓ = {config['length']:g} mm" if "length" in config else ""
    return (
        f"Fatigue at the last recorded cycle ({', '.join(config['criteria'])}; critical "
        f"distance: {config.get('method', 'hotspot')}{length}). A crack is predicted where "
        "a risk at the critical distance is ≥ 1, or where the life there is at most the "
        "simulated cycles; x/a: the hot spot over the contact half-width (−1: the trailing "
        "edge when the bulk stress is in phase with Q):"
    )


def fretting_report(study: Results, cycles: Sequence[int] | None = None) -> str:
    """The Markdown table and checks of a fretting study."""
    loading, config = study.study["loading"], study.study
    names = ", ".join(key_title(key) for key in study.swept_keys)
    swept = f"; swept: {names}" if study.swept_keys else ""
    law = config.get("wear", {}).get("law", "archard")
    subsurface = config.get("subsurface", {})
    load = _value(study, "load", " " + study.load_unit)
    lines = [
        f"### {study.name}",
        "",
        f"{study.mesh_label}, tangential fretting: P = {load} (held), "
        f"{_signal(study)}, {int(loading['cycles']):,} cycles, {law} wear law{swept} (a "
        "case's label gives its swept values). "
        f"Subsurface: {subsurface.get('layers')} layers to z = "
        f"{subsurface.get('depth')} a0, on the vertical plane through the axis that "
        f"contains the sliding direction. Source: `{study.path}`.",
        "",
    ]
    lines += fretting_table(study, cycles)
    lines += ["", "Measured:", ""]
    lines += [f"- {fact}" for fact in fretting_facts(study) + edge_facts(study)]
    if has_fatigue(study):
        lines += ["", _fatigue_header(study), "", *fatigue_table(study), ""]
        lines += [f"- {fact}" for fact in fatigue_facts(study)]
    if study.skipped:
        lines += ["", "Not completed: " + ", ".join(f"{c} ({s})" for c, s in study.skipped)]
    return "\n".join(lines) + "\n"
