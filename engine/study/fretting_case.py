"""The fretting case of the study layer: settings from the study file, the run (with its
checkpoint), and the fretting datasets and summary values (engine.solvers.fretting).

Datasets of a completed fretting case, besides those of a cyclic case:

- ``history/q_amplitude`` (N), ``history/displacement_amplitude`` (mm), ``history/energy``
  (mJ, ∮ Q·dδ), ``history/slip_regime`` (0 partial, 1 gross), ``history/stick_area`` (mm², at
  the increment of the largest |Q|), ``history/evaluations`` (increment solves per cycle);
- ``fields/cycle_NNNNNNN/loop``: the fretting loop of every recorded cycle, shape
  (4·steps + 1, 4), columns delta_x, delta_y (mm), Q_x, Q_y (N) (attribute ``columns`` =
  "delta_x, delta_y, Q_x, Q_y", ``units`` = "mm, mm, N, N");
- ``fields/cycle_NNNNNNN/vm_cycle``: (σ_VM max over the cycle's increments in the x–z plane
  (MPa), its x, y, z (mm)).

The subsurface plane (``subsurface/*``, the σ_VM history and summary values, ``vm_cycle``) is
the vertical plane through the axis that contains the sliding direction ``direction``: the
x–z plane at 0°; at φ ≠ 0 its datasets carry the attribute ``plane_angle`` (degrees) and say
so in their description, and the history and summary gain the y of the tracked peaks
(``vm_max_y``, ``vm_sub_max_y``, ``vm_deep_max_y``; summary ``vm_deep_max_y``).

With a ``[fatigue]`` section, the criteria are evaluated on the increments of every recorded
cycle (of every simulated cycle with ``every_cycle``) on the same plane
(``engine.study.fatigue``): datasets ``fatigue/cycle_NNNNNNN/*``, ``history/<column>`` with
``every_cycle``, and the criteria's summary columns (``crossland_risk`` …).

The recorded surface fields of a fretting cycle are those of its increment of largest |Q|.
Summary columns: ``q_amplitude`` (N), ``displacement_amplitude`` (mm), ``energy_per_cycle``
(mJ), ``slip_regime`` ("partial" | "gross") of the last simulated cycle, and ``vm_cycle_max``
(MPa) with ``vm_cycle_max_x/_y/_z`` (mm), the largest σ_VM over the increments of the last
cycle; ``vm_max`` and the other stress columns are at the increment of the largest |Q|.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from engine.schema import FRETTING_RECORDS, fretting_record
from engine.solvers.fretting import (
    FrettingAnalysis,
    FrettingSettings,
    slip_regime_name,
)


@dataclass
class FrettingRun:
    result: Any
    tracker: Any
    message: str
    fatigue: Any = None  # engine.study.fatigue.FatigueAnalysis with [fatigue], else None


def plane_angle(cfg) -> float:
    """The subsurface plane's angle φ (degrees from x): the sliding direction, so that the
    vertical plane through the axis contains it (0: the x–z plane of the other kinds)."""
    return float(cfg.loading.direction or 0.0)


def label_plane(datasets: dict, angle: float) -> None:
    """In place, for φ = ``angle`` ≠ 0 (degrees): the plane's datasets (``subsurface/*``, the
    σ_VM peaks of ``history/`` and ``vm_cycle``) say which plane they are on, in their
    description and in the attribute ``plane_angle`` (degrees from x). Nothing changes at
    φ = 0, so x–z results stay as they were."""
    if angle == 0.0:
        return
    plane = f"vertical plane through the axis at {angle:g}° from x (the sliding direction)"
    for path, record in datasets.items():
        description = _XZ_PLANE.sub(plane, record.description)
        if path.startswith("subsurface/"):
            description += f"; on the {plane}, x = s cos φ, y = s sin φ, φ = {angle:g}°"
        if description != record.description:
            record.description = description
            record.attrs["plane_angle"] = angle


_XZ_PLANE = re.compile(r"x[-–]z plane( through the axis)?")


def settings(cfg) -> FrettingSettings:
    """The solver settings of a fretting study configuration."""
    loading = cfg.loading
    options: dict[str, Any] = {}
    if loading.max_wear_fraction is not None:
        options["max_wear_fraction"] = loading.max_wear_fraction
    return FrettingSettings(
        loading.load,
        loading.steps,
        loading.cycles,
        amplitude=loading.amplitude,
        force_amplitude=loading.force_amplitude,
        direction=loading.direction or 0.0,
        record=loading.record,
        bulk_stress_max=loading.bulk_stress_max or 0.0,
        bulk_stress_min=loading.bulk_stress_min or 0.0,
        **options,
    )


def check_force_bound(case, fretting: FrettingSettings) -> None:
    """Force control needs Q* below the largest force the friction ellipse can carry along d,
    h(d)·P with h(d) = √((μ1 d₁)² + (μ2 d₂)²) (d in the tribological axes)."""
    if fretting.force_amplitude is None:
        return
    angle = math.radians(fretting.direction - case.beta)
    bound = math.hypot(case.mu1 * math.cos(angle), case.mu2 * math.sin(angle)) * fretting.load
    if not fretting.force_amplitude < bound:
        raise ValueError(
            f"[loading] force_amplitude = {fretting.force_amplitude:g} N is not below the "
            f"friction bound {bound:g} N along direction {fretting.direction:g}° (μ = "
            f"{case.mu1:g}/{case.mu2:g}, P = {fretting.load:g} N): the punch would slide away"
        )


def run(case, cfg, solver, stress, checkpoint: Path, should_stop, on_cycle) -> FrettingRun:
    """Run (or resume from ``checkpoint``) a fretting case; save the state when stopped."""
    from .case import case_wear_law, peak_tracker
    from .checkpoint import load_extra, load_fretting_state, save_fretting_state

    fretting = settings(cfg)
    check_force_bound(case, fretting)
    angle = math.radians(plane_angle(cfg))  # the plane contains the sliding direction
    tracker = peak_tracker(stress, cfg.contact_length, angle)
    fatigue = _fatigue(cfg, stress, solver.grid, angle)

    def increment_probe(pressure, traction_x, traction_y):
        plane = stress.plane(pressure, traction_x, traction_y, angle=angle)
        if fatigue is not None:  # the criteria read the same planes
            fatigue.increment_probe(pressure, traction_x, traction_y, plane)
        peak = plane.peak()
        return (peak.value, peak.x, peak.y, peak.z)

    analysis = FrettingAnalysis(
        solver,
        case_wear_law(case, cfg),
        fretting,
        peak_probe=tracker,
        increment_probe=increment_probe,
    )
    if fretting.has_bulk_stress:  # the probes see the σ_B of the increment they evaluate

        def listener(value):
            stress.bulk_stress = value
            if fatigue is not None:
                fatigue.set_bulk_stress(value)

        analysis.bulk_stress_listener = listener
    state = load_fretting_state(checkpoint) if checkpoint.exists() else None
    if fatigue is not None:
        analysis.probe_every_cycle = cfg.fatigue.every_cycle
        if state is not None:
            fatigue.restore(load_extra(checkpoint))
        on_cycle = _both(fatigue.on_cycle, on_cycle)
    result = analysis.run(state=state, should_stop=should_stop, on_cycle=on_cycle)
    if fretting.has_bulk_stress:  # the stored planes: σ_B of the last cycle's peak
        stress.bulk_stress = analysis.peak_bulk_stress
    message = result.message
    if not result.completed:
        checkpoint.parent.mkdir(parents=True, exist_ok=True)
        extra = None if fatigue is None else fatigue.arrays()
        save_fretting_state(result.state, checkpoint, extra)  # atomic (temporary + rename)
        message = f"stopped at cycle {result.state.cycle}; state saved to {checkpoint}"
    return FrettingRun(result, tracker, message, fatigue)


def _fatigue(cfg, stress, grid, angle: float):
    """The case's fatigue analysis (``[fatigue]``; None without): the flat's E and ν, the
    case's plane, its recorded cycles."""
    if cfg.fatigue is None:
        return None
    from .fatigue import FatigueAnalysis

    recorded = set(cfg.loading.record) | {cfg.loading.cycles}
    return FatigueAnalysis(
        cfg.fatigue, stress, grid, cfg.material.E_A, cfg.material.nu_A, angle, recorded
    )


def _both(first, second):
    """``on_cycle`` calling ``first`` then ``second`` (None: only ``first``)."""
    if second is None:
        return first

    def on_cycle(cycle, cycles):
        first(cycle, cycles)
        second(cycle, cycles)

    return on_cycle


def fatigue_outputs(run: FrettingRun, history) -> tuple[dict, dict]:
    """(datasets, summary columns) of a case's fatigue analysis: ``fatigue/cycle_N/*`` of
    every recorded cycle and, with ``every_cycle``, ``history/<column>``; nothing without
    ``[fatigue]``."""
    fatigue = run.fatigue
    if fatigue is None:
        return {}, {}
    datasets = fatigue.datasets()
    if fatigue.config.every_cycle:
        datasets.update(fatigue.history_datasets(history["cycle"]))
    return datasets, fatigue.summary_row()


def record_datasets(fields: dict, group: str, cycle: int) -> dict:
    """The loop and the cycle's σ_VM maximum of a recorded cycle (taken out of ``fields``)."""
    return {
        f"fields/{group}/{name}": fretting_record(name, cycle).record(fields.pop(name))
        for name in FRETTING_RECORDS
        if name in fields
    }


def summary_values(result) -> dict[str, Any]:
    """Summary columns of the last simulated cycle (see the module docstring)."""
    history = result.history
    row: dict[str, Any] = {
        "q_amplitude": float(history["q_amplitude"][-1]),
        "displacement_amplitude": float(history["displacement_amplitude"][-1]),
        "energy_per_cycle": float(history["energy"][-1]),
        "slip_regime": slip_regime_name(float(history["slip_regime"][-1])),
    }
    last = result.records[max(result.records)]
    values = last.get("vm_cycle", [math.nan] * 4)
    for key, value in zip(
        ("vm_cycle_max", "vm_cycle_max_x", "vm_cycle_max_y", "vm_cycle_max_z"), values, strict=True
    ):
        row[key] = float(value)
    return row
