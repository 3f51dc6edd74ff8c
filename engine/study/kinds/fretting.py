"""``kind = "fretting"``: a held normal load and an oscillating tangential motion, with wear
(:mod:`engine.solvers.fretting`): the settings from the study file, the run (with its
checkpoint), and the fretting datasets and summary values.

Datasets of a completed fretting case, besides those of a cyclic case:

- ``history/q_amplitude`` (N), ``history/displacement_amplitude`` (mm), ``history/energy``
  (mJ, ∮ Q·dδ), ``history/slip_regime`` (0 partial, 1 gross), ``history/stick_area`` (mm², at
  the increment of the largest |Q|), ``history/evaluations`` (increment solves per cycle)
  (``engine.schema.FRETTING_HISTORY``);
- ``fields/cycle_NNNNNNN/loop``: the fretting loop of every recorded cycle, shape
  (4·steps + 1, 4), columns delta_x, delta_y (mm), Q_x, Q_y (N; a line contact's N/mm)
  (attribute ``columns`` = "delta_x, delta_y, Q_x, Q_y", ``units`` = "mm, mm, N, N");
- ``fields/cycle_NNNNNNN/vm_cycle``: (σ_VM max over the cycle's increments in the x–z plane
  (MPa), its x, y, z (mm)) (``engine.schema.FRETTING_RECORDS``).

The subsurface plane (``subsurface/*``, the σ_VM history and summary values, ``vm_cycle``) is
the vertical plane through the axis that contains the sliding direction ``direction``: the
x–z plane at 0°; at φ ≠ 0 its datasets carry the attribute ``plane_angle`` (degrees) and say
so in their description, and the history and summary gain the y of the tracked peaks
(``vm_max_y``, ``vm_sub_max_y``, ``vm_deep_max_y``; summary ``vm_deep_max_y``).

With a ``[fatigue]`` section, the criteria are evaluated on the increments of every recorded
cycle (of every simulated cycle with ``every_cycle``) on the same plane, from the planes the
σ_VM probe evaluates (``engine.study.fatigue``): datasets ``fatigue/cycle_NNNNNNN/*``,
``history/<column>`` with ``every_cycle``, the criteria's summary columns
(``crossland_risk`` …); an interrupted case's checkpoint keeps the evaluated cycles.

The recorded surface fields of a fretting cycle are those of its increment of largest |Q|
(+Q*), and ``fields/cycle_NNNNNNN/status_minus_q`` the element states at −Q*.
Summary columns: ``q_amplitude`` (N), ``displacement_amplitude`` (mm), ``energy_per_cycle``
(mJ), ``slip_regime`` ("partial" | "gross") of the last simulated cycle, and ``vm_cycle_max``
(MPa) with ``vm_cycle_max_x/_y/_z`` (mm), the largest σ_VM over the increments of the last
cycle; ``vm_max`` and the other stress columns are at the increment of the largest |Q|.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from engine import schema
from engine.schema import cycle_group
from engine.solvers.fretting import FrettingAnalysis, FrettingSettings, slip_regime_name
from engine.study import outcome
from engine.study.checkpoint import load_extra, load_fretting_state, save_fretting_state
from engine.study.fatigue import FatigueAnalysis
from engine.study.outcome import COMPLETED, FAILED, CaseOutcome
from engine.study.settings.checks import ANGLE_REASON, MAX_FRICTION, bound_of
from engine.study.settings.sections import MISSING, loading_key, steps_key

from .base import CycledKind, CycledLoading, parse_cycles

# In magnitude (MPa): a bulk stress of a line contact's flat.
_BULK_STRESS_BOUNDS = {
    "minimum": -1e4,
    "maximum": 1e4,
    "why": "in magnitude: 10 GPa is above the strength of any steel, and the flat stays "
    "linear elastic",
}


@dataclass(frozen=True)
class FrettingLoading(CycledLoading):
    """The ``[loading]`` section of a fretting study: the cycles (``steps`` per quarter
    tangential cycle), then the tangential signal (exactly one of ``amplitude`` and
    ``force_amplitude``; the other None) and a line contact's bulk stresses (None: none
    given)."""

    steps: int = steps_key("load increments per quarter tangential cycle and of the normal loading")
    amplitude: float | None = loading_key(
        "mm",
        "rigid tangential displacement amplitude δ* (displacement control)",
        optional=True,
        absent="one of the two",
        label="displacement amplitude δ*",
        minimum=0.0,
        strict=True,
        maximum=10.0,
        why="fretting amplitudes lie below ~0.3 mm; beyond 10 mm the motion is "
        "reciprocating sliding, which moves the contact over the flat, and this model holds "
        "it in place",
    )
    force_amplitude: float | None = loading_key(
        "N",
        "tangential force amplitude Q* (force control); must be below μP",
        optional=True,
        absent="one of the two",
        label="force amplitude Q*",
        minimum=0.0,
        strict=True,
        why="a force (the load's unit), also below the friction bound μP of every case",
    )
    direction: float = loading_key(
        "degree",
        "sliding direction, from x",
        default=0.0,
        label="sliding direction",
        minimum=-360.0,
        maximum=360.0,
        why=ANGLE_REASON,
    )
    bulk_stress_max: float | None = loading_key(
        "MPa",
        "line contacts: bulk stress along x in the flat at +Q* (or +δ*), in phase with the signal",
        optional=True,
        absent="0 if the other is given, else no bulk stress",
        label="bulk stress at +Q*",
        **_BULK_STRESS_BOUNDS,
    )
    bulk_stress_min: float | None = loading_key(
        "MPa",
        "line contacts: bulk stress along x in the flat at −Q* (or −δ*)",
        optional=True,
        absent="0 if the other is given, else no bulk stress",
        label="bulk stress at −Q*",
        **_BULK_STRESS_BOUNDS,
    )


#: [loading] keys of the tangential signal, and a line contact's bulk stresses (MPa).
FRETTING_KEYS = frozenset({"amplitude", "force_amplitude", "direction"})
BULK_STRESS_KEYS = frozenset({"bulk_stress_max", "bulk_stress_min"})


class FrettingKind(CycledKind):
    """Tangential fretting cycles under a held normal load
    (engine.solvers.fretting.FrettingAnalysis)."""

    name = "fretting"
    summary = "tangential fretting: a held load, an oscillating tangential motion, wear"
    config = FrettingLoading
    increments_per_step = 4  # four quarter cycles
    history = (schema.FRETTING_HISTORY, schema.HISTORY)
    records = schema.FRETTING_RECORDS
    report = "engine.analysis.fretting_report:fretting_report"
    figures = "engine.analysis.fretting_figures:fretting_figures"
    figures_per_case = True

    # ------------------------------------------------------------ configuration
    def parse(self, s, load, steps):
        """The cycles, then the tangential signal: ``amplitude`` (mm, rigid displacement)
        XOR ``force_amplitude`` (N, tangential force), ``direction`` [0] (degrees from x),
        and a line contact's bulk stresses (MPa)."""
        s.check_known(self.keys)
        cycled = parse_cycles(s, self.name, load, steps)
        given = [key for key in ("amplitude", "force_amplitude") if key in s.table]
        if len(given) != 1:
            shown = {key: s.table[key] for key in given} if given else MISSING
            raise s.error(
                "amplitude" if not given else given[-1],
                shown,
                'kind = "fretting" needs exactly one of amplitude (mm, displacement control) '
                "and force_amplitude (N, a line contact's N/mm; force control)",
            )
        unit = "mm" if given[0] == "amplitude" else ""  # a force's bound is 0: no unit
        declared = self.declared_keys()
        value = s.number(given[0], unit=unit, **bound_of(declared[given[0]]))
        if given[0] == "force_amplitude" and not value < load * MAX_FRICTION:
            raise s.error(given[0], value, "must be below the friction bound μP (the load's unit)")
        direction = declared["direction"]
        direction = s.number("direction", direction.default, unit="degrees", **bound_of(direction))
        bulk = {
            key: s.number(key, unit="MPa", **bound_of(declared[key]))
            for key in sorted(BULK_STRESS_KEYS)
            if key in s.table
        }
        if bulk:
            bulk = {key: bulk.get(key, 0.0) for key in BULK_STRESS_KEYS}
        return self.config(**cycled, **{given[0]: value}, direction=direction, **bulk)

    def check_case(self, case, config):
        fretting = settings(config)
        if config.punch.is_line and fretting.direction % 360.0 != 0.0:
            raise ValueError(
                f"[loading] direction = {fretting.direction:g}°: a line contact "
                f"({config.punch.shape}, plane strain in x–z) slides along x only (direction = 0)"
            )
        check_force_bound(case, fretting, config.punch.load_unit)

    def describe(self, config, value):
        loading, unit = config.loading, config.punch.load_unit
        cycles = f"{value('cycles', loading.cycles, '', ',')} cycles"
        control = (
            f"displacement control, amplitude {value('amplitude', loading.amplitude, 'mm')}"
            if loading.amplitude is not None
            else "force control, force_amplitude "
            + value("force_amplitude", loading.force_amplitude, unit)
        )
        return (
            f"fretting, P = {value('load', loading.load, unit)} held, {control} along "
            f"{value('direction', loading.direction or 0.0, '')}° from x, {cycles}"
        )

    # ------------------------------------------------------------ datasets
    def plane_angle(self, config):
        """The subsurface plane's angle φ (degrees from x): the sliding direction, so that
        the vertical plane through the axis contains it."""
        return plane_angle(config)

    def record_shapes(self, config):
        rows = self.increments(config.loading.steps) + 1  # the cycle's start, then each
        grid = config.punch.profile().grid(config.mesh.n, config.mesh.half_width)
        return {
            "loop": ((rows, 4), "float64"),
            "vm_cycle": ((4,), "float64"),
            "status_minus_q": (grid.shape, "int8"),
        }

    # ------------------------------------------------------------ checkpoint
    def save_state(self, state, path, extra=None):
        save_fretting_state(state, path, extra)

    def load_state(self, path):
        return load_fretting_state(path)

    # ------------------------------------------------------------ the case
    def run(self, context, case, config, should_stop):
        """The cyclic case's solver, stresses, checkpoints and outputs, plus the loops, the
        fretting history and summary columns."""
        angle_deg = self.plane_angle(config)
        angle = math.radians(angle_deg)  # the plane contains the sliding direction
        solver, grid, material = context.solver(case, config)
        stress, depths = context.subsurface(grid, material, config, angle_deg)
        fretting = settings(config)
        check_force_bound(case, fretting, config.punch.load_unit)
        tracker = outcome.peak_tracker(stress, config.contact_length, angle)
        fatigue = fatigue_analysis(config, stress, grid, angle)

        def increment_probe(pressure, traction_x, traction_y):
            plane = stress.plane(pressure, traction_x, traction_y, angle=angle)
            if fatigue is not None:  # the criteria read the same planes
                fatigue.increment_probe(pressure, traction_x, traction_y, plane)
            peak = plane.peak()
            return (peak.value, peak.x, peak.y, peak.z)

        analysis = FrettingAnalysis(
            solver,
            outcome.case_wear_law(case, config),
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
        checkpoint, state = self.checkpoint(context, case)
        on_cycle = context.on_cycle(case)
        if fatigue is not None:
            analysis.probe_every_cycle = config.fatigue.every_cycle
            if state is not None:
                fatigue.restore(load_extra(checkpoint))
            on_cycle = _both(fatigue.on_cycle, on_cycle)
        result = analysis.run(state=state, should_stop=should_stop, on_cycle=on_cycle)
        if fretting.has_bulk_stress:  # the stored planes: σ_B of the last cycle's peak
            stress.bulk_stress = analysis.peak_bulk_stress
        if not result.completed:
            extra = None if fatigue is None else fatigue.arrays()
            return self.interrupted(case, result.state, checkpoint, extra)
        if not result.converged:
            return CaseOutcome(
                case, FAILED, message=f"fretting analysis did not converge: {result.message}"
            )
        final = result.final
        datasets = outcome.history_datasets(result.history, self.history_spec)
        datasets.update(outcome.grid_datasets(grid))
        records = {cycle: dict(fields) for cycle, fields in result.records.items()}
        for cycle, fields in records.items():  # the loop and vm_cycle leave ``fields``
            datasets.update(self._record_datasets(fields, cycle))
        datasets.update(outcome.recorded_datasets(records, stress, angle, "largest |Q|"))
        datasets.update(outcome.final_fields(final))
        row = outcome.final_row(case, config, final, stress, depths, datasets, angle)
        row.update(outcome.peak_row(tracker, final, result.history))
        row.update(summary_values(result))
        if fatigue is not None:
            datasets.update(fatigue.datasets())
            if fatigue.config.every_cycle:
                datasets.update(fatigue.history_datasets(result.history["cycle"]))
            row.update(fatigue.summary_row())
        label_plane(datasets, angle_deg)
        row.update(outcome.totals_row(result, config))
        row.update(outcome.scar_row(case, config, grid, result))
        return CaseOutcome(case, COMPLETED, row=row, datasets=datasets)

    def _record_datasets(self, fields: dict, cycle: int) -> dict:
        """The loop and the cycle's σ_VM maximum of a recorded cycle (taken out of
        ``fields``)."""
        group = cycle_group(cycle)
        return {
            schema.case_group_path("fields", group, name): self.record_spec(name, cycle).record(
                fields.pop(name)
            )
            for name in self.records
            if name in fields
        }


def fatigue_analysis(config, stress, grid, angle: float):
    """The case's fatigue analysis (``[fatigue]``, ``engine.study.fatigue``; None without):
    the flat's E and ν, the case's plane at ``angle`` (rad), its recorded cycles."""
    if config.fatigue is None:
        return None

    loading = config.loading
    recorded = set(loading.record) | {loading.cycles}
    return FatigueAnalysis(
        config.fatigue, stress, grid, config.material.E_A, config.material.nu_A, angle, recorded
    )


def _both(first, second):
    """An ``on_cycle`` calling ``first`` then ``second`` (None: only ``first``)."""
    if second is None:
        return first

    def on_cycle(cycle, cycles):
        first(cycle, cycles)
        second(cycle, cycles)

    return on_cycle


def plane_angle(config) -> float:
    """The subsurface plane's angle φ (degrees from x): the sliding direction."""
    return float(config.loading.direction or 0.0)


def label_plane(datasets: dict, angle: float) -> None:
    """In place, for φ = ``angle`` ≠ 0 (degrees): the plane's datasets (``subsurface/*``, the
    σ_VM peaks of ``history/`` and ``vm_cycle``) say which plane they are on, in their
    description (:func:`engine.schema.on_plane`) and in the attribute ``plane_angle``
    (degrees from x). Nothing changes at φ = 0, so x–z results stay as they were."""
    for path, record in datasets.items():
        description = schema.on_plane(record.description, angle, path.startswith("subsurface/"))
        if description != record.description:
            record.description = description
            record.attrs["plane_angle"] = angle


def settings(config):
    """The solver settings (engine.solvers.fretting.FrettingSettings) of a fretting study
    configuration."""
    loading = config.loading
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


def check_force_bound(case, fretting, unit: str = "N") -> None:
    """Force control needs Q* below the largest force the friction ellipse can carry along d,
    h(d)·P with h(d) = √((μ1 d₁)² + (μ2 d₂)²) (d in the tribological axes); ``unit``: the
    load's (N, a line contact's N/mm)."""
    if fretting.force_amplitude is None:
        return
    angle = math.radians(fretting.direction - case.beta)
    bound = math.hypot(case.mu1 * math.cos(angle), case.mu2 * math.sin(angle)) * fretting.load
    if not fretting.force_amplitude < bound:
        raise ValueError(
            f"[loading] force_amplitude = {fretting.force_amplitude:g} {unit} is not below the "
            f"friction bound {bound:g} {unit} along direction {fretting.direction:g}° (μ = "
            f"{case.mu1:g}/{case.mu2:g}, P = {fretting.load:g} {unit}): the punch would slide "
            "away"
        )


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
