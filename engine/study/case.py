"""Case runner: one case of the plan -> solver objects -> run -> :class:`CaseOutcome`.

The runner knows the solvers and the study configuration, nothing of MPI or HDF5. Whatever
happens inside a case — an exception, a solve that does not converge, a stop request — comes
back as a :class:`CaseOutcome` with a status, so one bad case never stops the study:

- ``completed``: summary row, datasets (with units) and attributes are filled in;
- ``failed``: ``message`` and ``traceback`` say why (non-convergence is a failure, never
  reported as converged);
- ``interrupted``: ``should_stop`` returned True; the cyclic state was saved to the case's
  checkpoint (``<output>.checkpoints/<case_id>.npz``) and the next run resumes from it.

Subsurface stresses (paper Section 5, Eq. 16, von Mises Eq. 21) are evaluated in the x–z
plane through the punch axis, at the final state and at every recorded cycle. ``vm_max`` is
the maximum over the whole plane; ``vm_sub_max`` the maximum over the layers strictly below
the surface layer, i.e. ``z >= depths[1]`` (the surface layer itself carries the edge
singularity of the flat punch, Eq. 17, whose value depends on the element size).

Cyclic cases also track the peak at every simulated cycle (:mod:`engine.solvers.peak`): the
history gains the von Mises maxima (overall, below the surface layer, at z >= 0.1 a0, on the
axis), the contact radius, the centre pressure and the peak region; the x–z plane at the
first cycle and at every change of region is written under ``peak_changes/cycle_<N>/``.
"""

from __future__ import annotations

import json
import math
import os
import time
import traceback as traceback_module
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from engine.schema import (
    FINAL_FIELDS,
    PEAK_CHANGE_FIELDS,
    CaseStatus,
    DatasetRecord,
    cycle_group,
    field_dataset,
    grid_dataset,
    history_dataset,
    pending_row,
    plane_dataset,
)

from .config import StudyConfig
from .plan import Case

__all__ = [
    "peak_tracker",
    "DatasetRecord",
    "CaseOutcome",
    "CaseRunner",
    "InjectedFailure",
    "BorderCheckedSolver",
    "nominal_mean_pressure",
    "case_wear_law",
]

# Status values, dataset paths, units and descriptions: the results schema (engine.schema).
COMPLETED, FAILED, INTERRUPTED = (
    CaseStatus.COMPLETED,
    CaseStatus.FAILED,
    CaseStatus.INTERRUPTED,
)


def _without_negative_zeros(row: dict[str, Any]) -> dict[str, Any]:
    """-0.0 → 0.0 in a summary row (a coordinate on the plane y = 0 can come out as -0.0;
    adding +0.0 maps only -0.0 to 0.0 in IEEE arithmetic and leaves NaN as it is)."""
    return {key: value + 0.0 if isinstance(value, float) else value for key, value in row.items()}


def case_wear_law(case: Case, cfg: StudyConfig):
    """The case's wear law (``[wear] law``, cyclic and fretting kinds): the orthotropic
    Archard law (wear1, wear2 in 1/MPa, β) or the dissipated-energy law (α in mm³/J)."""
    from engine.solvers.friction import EnergyWearLaw, WearLaw

    if cfg.wear.law == "energy":
        law = EnergyWearLaw(case.alpha)
    else:
        law = WearLaw(case.wear1, case.wear2, math.radians(case.beta))
    if cfg.punch.is_line:  # the gap carries the flat's and the pad's wear
        from engine.study.line_contact import wear_law

        return wear_law(law, pad_ratio(case, cfg))
    return law


def pad_ratio(case: Case, cfg: StudyConfig) -> float:
    """k_pad / k_flat of a line contact (``[wear] pad_coefficient``; 0 without)."""
    from engine.study.line_contact import pad_ratio as ratio

    flat = case.alpha if cfg.wear.law == "energy" else case.wear1
    return ratio(cfg.wear.pad_coefficient, flat)


def nominal_mean_pressure(cfg: StudyConfig) -> float:
    """The summary's p0 (MPa): P/(π a0²) with a0 the punch radius (flat: Eq. 19; rounded:
    the flat face's radius) or, for a sphere, Hertz's mean pressure P/(π a²), a = Hertz's
    contact radius (engine.reference.hertz); for a line contact P/(2 a0) with a0 the nominal
    half-width (engine.study.line_contact)."""
    from engine.reference.flat_punch import mean_pressure

    if cfg.punch.is_line:  # per unit length: P/(2 a0), a0 the nominal half-width
        return cfg.loading.load / (2.0 * cfg.contact_length)
    return mean_pressure(cfg.loading.load, cfg.contact_length)


def peak_tracker(stress, contact_length: float, angle: float = 0.0):
    """The peak tracker of a case's stresses (engine.solvers.peak): a line contact's tracks
    its contact half-width (engine.solvers.line_subsurface)."""
    if stress.grid.is_line:
        from engine.study.line_contact import LineContact

        return LineContact.peak_tracker(stress, contact_length, angle)
    from engine.solvers.peak import PeakTracker

    return PeakTracker(stress, contact_length, angle=angle)


class BorderCheckedSolver:
    """A contact solver whose every increment is checked for contact on the grid's border.

    Delegates everything (attributes read and set) to the wrapped solver; ``solve_load`` and
    ``solve_approach`` raise :class:`engine.geometry.ContactReachesBorder` when the pressure
    is positive on the outermost ring of elements: the contact would continue beyond the
    grid, so the solution is truncated and wrong (enlarge ``[mesh] half_width``).
    """

    def __init__(self, solver) -> None:
        object.__setattr__(self, "_solver", solver)

    def __getattr__(self, name: str):
        return getattr(self._solver, name)

    def __setattr__(self, name: str, value) -> None:
        setattr(self._solver, name, value)

    def _checked(self, result, what: str):
        from engine.geometry import ContactReachesBorder, border_contact

        touching = border_contact(result.pressure)
        if touching:
            grid = self._solver.grid
            raise ContactReachesBorder(
                f"the contact reaches the mesh border at {what} ({touching} border elements "
                f"loaded, half_width = {grid.half_width_x:g} mm): the solution would be "
                "truncated; increase [mesh] half_width"
            )
        return result

    def solve_load(self, load, state=None, wear=None, guess=None):
        result = self._solver.solve_load(load, state, wear=wear, guess=guess)
        return self._checked(result, f"P = {load:g} N")

    def solve_approach(self, approach, state=None, wear=None):
        result = self._solver.solve_approach(approach, state, wear=wear)
        return self._checked(result, f"approach = {approach:g} mm")


class InjectedFailure(RuntimeError):
    """Raised on purpose for cases listed in ``[testing] fail_cases``."""


@dataclass
class CaseOutcome:
    """What a case produced. Picklable: workers send it to the writing rank."""

    case: Case
    status: str  # a CaseStatus value, kept as plain text (h5py stores str, not str enums)
    row: dict[str, Any] = field(default_factory=dict)
    datasets: dict[str, DatasetRecord] = field(default_factory=dict)
    attrs: dict[str, Any] = field(default_factory=dict)
    message: str = ""
    traceback: str = ""
    runtime_s: float = 0.0
    rank: int = -1

    def __post_init__(self) -> None:
        self.status = str(CaseStatus(self.status))  # an unknown status raises ValueError

    @property
    def case_id(self) -> str:
        return self.case.case_id


class CaseRunner:
    """Callable ``runner(case, should_stop) -> CaseOutcome`` for one study configuration."""

    def __init__(self, config: StudyConfig) -> None:
        from .operators import OperatorCache

        self.config = config
        self.checkpoint_dir = config.study.checkpoint_dir
        # Operators, plans and stress kernels shared by the cases of this rank (issue 17).
        self.operators = OperatorCache()
        # Progress hook: on_progress(case) when a case starts, on_progress(case, N, cycles)
        # after each simulated cycle (engine.output.progress; None: no reports).
        self.on_progress: Callable[..., None] | None = None
        self._case_configs: dict[tuple, StudyConfig] = {}

    def config_for(self, case: Case) -> StudyConfig:
        """The case's configuration: the study with its swept values (cached per settings)."""
        if case.settings not in self._case_configs:
            self._case_configs[case.settings] = self.config.for_case(case.settings)
        return self._case_configs[case.settings]

    # ---------------------------------------------------------------- public entry point
    def __call__(self, case: Case, should_stop: Callable[[], bool] | None = None) -> CaseOutcome:
        should_stop = should_stop or (lambda: False)
        start = time.perf_counter()
        cpu_start = time.thread_time()  # CPU of the computing thread (rank 0 computes in one)
        previous = self._load_progress(case)
        if self.on_progress is not None:
            self.on_progress(case)
        try:
            if case.case_id in self.config.testing.fail_cases:
                raise InjectedFailure(f"case {case.case_id} fails on purpose ([testing])")
            config = self.config_for(case)
            if config.is_fretting:
                outcome = self._run_fretting(case, config, should_stop)
            elif config.is_cyclic:
                outcome = self._run_cyclic(case, config, should_stop)
            else:
                outcome = self._run_static(case, config)
        except Exception as error:  # noqa: BLE001 - every failure becomes an outcome
            outcome = CaseOutcome(
                case,
                FAILED,
                message=f"{type(error).__name__}: {error}",
                traceback=traceback_module.format_exc(),
            )
        outcome.runtime_s = previous.get("runtime_s", 0.0) + time.perf_counter() - start
        if outcome.status == INTERRUPTED:
            self._save_progress(case, {"runtime_s": outcome.runtime_s})
        else:
            self._remove_checkpoint(case)
        if outcome.status != COMPLETED:
            outcome.row = self._parameters_row(case, outcome.status)
        outcome.attrs["cpu_s"] = time.thread_time() - cpu_start  # this run only
        outcome.row["runtime_s"] = outcome.runtime_s
        outcome.row["status"] = outcome.status
        outcome.row = _without_negative_zeros(outcome.row)
        return outcome

    # ---------------------------------------------------------------- solver objects
    def _solver(self, case: Case, cfg: StudyConfig):
        """The one place where a case's contact solver is built (profile, grid, material,
        friction, options). For profiles with a surface beyond the grid (sphere, a rounded
        edge cut by the mesh) it is wrapped so that a contact touching the grid's border
        fails the case (engine.geometry.ContactReachesBorder) instead of being truncated."""
        from engine.geometry import may_reach_border
        from engine.grid import Grid
        from engine.material import MaterialPair
        from engine.solvers.contact import ContactSolver
        from engine.solvers.friction import FrictionLaw

        material = MaterialPair(
            cfg.material.E_A, cfg.material.nu_A, cfg.material.E_B, cfg.material.nu_B
        )
        if cfg.punch.is_line:  # plane strain: n elements along x, unit length along y
            grid = Grid.line(cfg.mesh.n, cfg.mesh.half_width)
        else:
            grid = Grid.square(cfg.mesh.n, cfg.mesh.half_width)
        punch = cfg.punch.profile()
        punch.check_grid(grid)
        friction = FrictionLaw(case.mu1, case.mu2, math.radians(case.beta))
        operator = self.operators.operator(
            grid,
            material,
            threads=cfg.solver.threads,
            planner_effort=cfg.solver.planner_effort,
            reference_distance=cfg.mesh.reference_distance,
        )
        solver = ContactSolver(
            grid,
            material,
            punch,
            friction,
            tol=cfg.solver.tol,
            maxiter=cfg.solver.maxiter,
            threads=cfg.solver.threads,
            planner_effort=cfg.solver.planner_effort,
            operator=operator,
        )
        if may_reach_border(punch, grid):
            solver = BorderCheckedSolver(solver)
        return solver, grid, material

    def _subsurface(self, grid, material, cfg: StudyConfig):
        from engine.solvers.subsurface import depth_layers
        from engine.study import fretting_case

        depths = np.asarray(
            depth_layers(cfg.subsurface.depth * cfg.contact_length, cfg.subsurface.layers),
            dtype=float,
        )
        stress = self.operators.stress(
            grid,
            material.nu_A,
            depths,
            threads=cfg.solver.threads,
            planner_effort=cfg.solver.planner_effort,
            angle=math.radians(fretting_case.plane_angle(cfg)),
        )
        if grid.is_line:
            stress.bulk_stress = 0.0  # shared between cases: each starts without bulk stress
        return stress, depths

    # ---------------------------------------------------------------- static
    def _run_static(self, case: Case, cfg: StudyConfig) -> CaseOutcome:
        from engine.solvers.static import static_analysis

        solver, grid, material = self._solver(case, cfg)
        result = static_analysis(solver, cfg.loading.load, cfg.loading.steps)
        if not result.converged:
            return CaseOutcome(
                case, FAILED, message=f"static analysis did not converge: {result.message}"
            )
        datasets = {
            "history/load": history_dataset("load", cyclic=False).record(result.loads),
            "history/approach": history_dataset("approach", cyclic=False).record(result.approaches),
        }
        datasets.update(self._final_fields(result.final))
        datasets.update(self._grid_datasets(grid))
        stress, depths = self._subsurface(grid, material, cfg)
        row = self._final_row(case, cfg, result.final, stress, depths, datasets, "final")
        row.update(
            cycles=0,
            max_wear_depth=0.0,
            wear_volume=0.0,
            load_steps=int(len(result.loads)),
            matvecs=int(result.matvecs),
        )
        return CaseOutcome(
            case,
            COMPLETED,
            row=row,
            datasets=datasets,
            attrs={"iterations": int(result.iterations)},
        )

    # ---------------------------------------------------------------- cyclic
    def _run_cyclic(self, case: Case, cfg: StudyConfig, should_stop) -> CaseOutcome:
        from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings

        from .checkpoint import load_cyclic_state, save_cyclic_state

        solver, grid, material = self._solver(case, cfg)
        wear_law = case_wear_law(case, cfg)  # [wear] law: Archard (default) or energy
        settings = CyclicSettings(
            cfg.loading.load,
            cfg.loading.steps,
            cfg.loading.cycles,
            record=cfg.loading.record,
            max_wear_fraction=cfg.loading.max_wear_fraction,
        )
        stress, depths = self._subsurface(grid, material, cfg)
        tracker = peak_tracker(stress, cfg.contact_length)
        analysis = CyclicAnalysis(solver, wear_law, settings, peak_probe=tracker)
        checkpoint = self._checkpoint_path(case)
        state = load_cyclic_state(checkpoint) if checkpoint.exists() else None
        on_cycle = None
        if self.on_progress is not None:
            on_cycle = lambda cycle, cycles: self.on_progress(case, cycle, cycles)  # noqa: E731
        result = analysis.run(state=state, should_stop=should_stop, on_cycle=on_cycle)
        if not result.completed:
            checkpoint.parent.mkdir(parents=True, exist_ok=True)
            save_cyclic_state(result.state, checkpoint)  # atomic (temporary file + rename)
            return CaseOutcome(
                case,
                INTERRUPTED,
                message=f"stopped at cycle {result.state.cycle}; state saved to {checkpoint}",
            )
        final = result.final
        converged = getattr(result, "converged", final.converged)
        if not converged:
            message = getattr(result, "message", "") or final.message
            return CaseOutcome(case, FAILED, message=f"cyclic analysis did not converge: {message}")

        datasets = self._history_datasets(result.history)
        datasets.update(self._region_change_datasets(stress, result.state.region_changes))
        datasets.update(self._grid_datasets(grid))
        records = {cycle: dict(fields) for cycle, fields in result.records.items()}
        datasets.update(self._recorded_datasets(records, stress))
        datasets.update(self._final_fields(final))
        row = self._final_row(case, cfg, final, stress, depths, datasets, "final")
        row.update(self._peak_row(tracker, final, result.history))
        row.update(self._totals_row(result, cfg))
        row.update(self._scar_row(case, cfg, grid, result))
        return CaseOutcome(case, COMPLETED, row=row, datasets=datasets)

    def _recorded_datasets(self, records, stress, angle=0.0, moment="peak load of"):
        """The surface fields (``fields/cycle_N/``) and the stress plane through the axis at
        ``angle`` (radians; ``subsurface/cycle_N/``) of every recorded cycle N; ``moment``
        names the instant of the fields in their descriptions."""
        datasets = {}
        for cycle in sorted(records):
            fields, group = records[cycle], cycle_group(cycle)
            for name, values in fields.items():
                spec = field_dataset(name, group)
                description = spec.description.replace("peak load of", moment)
                datasets[f"fields/{group}/{name}"] = DatasetRecord(
                    np.asarray(values), spec.units, description
                )
            plane = stress.plane(
                fields["pressure"], fields["traction_x"], fields["traction_y"], angle=angle
            )
            datasets.update(self._plane_datasets(plane, f"subsurface/{group}"))
        return datasets

    @staticmethod
    def _totals_row(result, cfg: StudyConfig) -> dict[str, Any]:
        """Cycles reached, wear, and the work counts (cumulative over resumed runs: they are
        kept in the state) of a cyclic or fretting run."""
        history = result.history
        cycles = history.get("cycle", [])
        return {
            "cycles": int(cycles[-1]) if len(cycles) else cfg.loading.cycles,
            "max_wear_depth": float(history["max_wear_depth"][-1]),
            "wear_volume": float(history["wear_volume"][-1]),
            "load_steps": int(result.load_steps),
            "matvecs": int(result.matvecs),
        }

    # ---------------------------------------------------------------- fretting
    def _run_fretting(self, case: Case, cfg: StudyConfig, should_stop) -> CaseOutcome:
        """A fretting case (engine.solvers.fretting): the cyclic case's solver, stresses,
        checkpoints and outputs, plus the loops, the fretting history and summary columns."""
        from engine.study import fretting_case

        solver, grid, material = self._solver(case, cfg)
        stress, depths = self._subsurface(grid, material, cfg)
        checkpoint = self._checkpoint_path(case)
        on_cycle = None
        if self.on_progress is not None:
            on_cycle = lambda cycle, cycles: self.on_progress(case, cycle, cycles)  # noqa: E731
        run = fretting_case.run(case, cfg, solver, stress, checkpoint, should_stop, on_cycle)
        if not run.result.completed:
            return CaseOutcome(case, INTERRUPTED, message=run.message)
        if not run.result.converged:
            return CaseOutcome(
                case, FAILED, message=f"fretting analysis did not converge: {run.result.message}"
            )
        result, final = run.result, run.result.final
        angle = math.radians(fretting_case.plane_angle(cfg))  # the plane holds the direction
        datasets = self._history_datasets(result.history, fretting=True)
        datasets.update(self._grid_datasets(grid))
        records = {cycle: dict(fields) for cycle, fields in result.records.items()}
        for cycle, fields in records.items():  # the loop and vm_cycle leave ``fields``
            datasets.update(fretting_case.record_datasets(fields, cycle_group(cycle), cycle))
        datasets.update(self._recorded_datasets(records, stress, angle, "largest |Q| of"))
        datasets.update(self._final_fields(final))
        row = self._final_row(case, cfg, final, stress, depths, datasets, "final", angle)
        row.update(self._peak_row(run.tracker, final, result.history))
        row.update(fretting_case.summary_values(result))
        fatigue_datasets, fatigue_row = fretting_case.fatigue_outputs(run, result.history)
        datasets.update(fatigue_datasets)
        row.update(fatigue_row)
        fretting_case.label_plane(datasets, fretting_case.plane_angle(cfg))
        row.update(self._totals_row(result, cfg))
        row.update(self._scar_row(case, cfg, grid, result))
        return CaseOutcome(case, COMPLETED, row=row, datasets=datasets)

    @staticmethod
    def _scar_row(case, cfg, grid, result) -> dict[str, Any]:
        """Line contacts: scar_depth, scar_width, scar_area of the flat and pad_wear_depth
        (engine.solvers.scar) from the final wear; nothing for the 3-D punches."""
        if not grid.is_line:
            return {}
        from engine.study.line_contact import scar_row

        return scar_row(grid, result.state.wear, pad_ratio(case, cfg))

    # ---------------------------------------------------------------- peak history
    @staticmethod
    def _history_datasets(
        history: dict[str, np.ndarray], fretting: bool = False
    ) -> dict[str, DatasetRecord]:
        """``history/<key>`` of a cyclic or fretting case; a key the schema does not know
        raises."""
        datasets = {}
        for key, values in history.items():
            values = np.asarray(values)
            if key in ("peak_region", "deep_region") and not np.any(np.isnan(values)):
                values = values.astype(np.int8)
            datasets[f"history/{key}"] = history_dataset(key, fretting=fretting).record(values)
        return datasets

    def _region_change_datasets(self, stress, changes) -> dict[str, DatasetRecord]:
        """x–z plane (σ_VM and components) and the peak-load pressure and tractions at the
        first cycle and every change of the peak region, under ``peak_changes/cycle_<N>/``."""
        datasets = {}
        for cycle in sorted(changes):
            fields = changes[cycle]
            group = cycle_group(cycle)
            prefix = f"peak_changes/{group}"
            plane = stress.plane(
                fields["pressure"], fields["traction_x"], fields["traction_y"], angle=0.0
            )
            datasets.update(self._plane_datasets(plane, prefix))
            for name in PEAK_CHANGE_FIELDS:
                datasets[f"{prefix}/{name}"] = field_dataset(name, group).record(fields[name])
        return datasets

    @staticmethod
    def _peak_row(tracker, final, history: dict[str, np.ndarray]) -> dict[str, Any]:
        """Summary values of the peak history: final peaks, region and its first change."""
        from engine.solvers.peak import first_region_change, region_name

        values = tracker(final.pressure, final.traction_x, final.traction_y)
        change = first_region_change(history.get("cycle", []), history.get("peak_region", []))
        return {
            "vm_deep_max": values["vm_deep_max"],
            "vm_deep_max_x": values["vm_deep_max_x"],
            "vm_deep_max_z": values["vm_deep_max_z"],
            "vm_axis_max": values["vm_axis_max"],
            "vm_axis_max_z": values["vm_axis_max_z"],
            "contact_radius": values["contact_radius"],
            "centre_pressure": values["centre_pressure"],
            "elastic_approach": float(history["approach"][0]),
            "wear_severity": float(history["max_wear_depth"][-1] / history["approach"][0]),
            "peak_region": region_name(values["peak_region"]),
            "deep_region": region_name(values["deep_region"]),
            "peak_region_change_cycle": math.nan if change is None else change,
        } | ({"vm_deep_max_y": values["vm_deep_max_y"]} if "vm_deep_max_y" in values else {})

    # ---------------------------------------------------------------- shared pieces
    def _final_fields(self, final) -> dict[str, DatasetRecord]:
        datasets = {}
        for name in FINAL_FIELDS:
            datasets[f"fields/final/{name}"] = field_dataset(name).record(getattr(final, name))
        return datasets

    @staticmethod
    def _plane_datasets(plane, prefix: str) -> dict[str, DatasetRecord]:
        arrays = {"x": plane.x, "y": plane.y, "z": plane.z, "von_mises": plane.von_mises}
        arrays.update({f"sigma_{name}": values for name, values in plane.components.items()})
        return {
            f"{prefix}/{name}": plane_dataset(name).record(values)
            for name, values in arrays.items()
        }

    @staticmethod
    def _grid_datasets(grid) -> dict[str, DatasetRecord]:
        """The case's own grid (cases of a study may differ in mesh.n or half_width)."""
        return {
            f"grid/{axis}": grid_dataset(axis).record(values)
            for axis, values in (("x", grid.x), ("y", grid.y))
        }

    def _final_row(
        self, case, cfg, final, stress, depths, datasets, group, angle: float = 0.0
    ) -> dict[str, Any]:
        """Summary values of the final state; σ_VM on the vertical plane at ``angle`` (rad,
        0: the x–z plane)."""
        plane = stress.plane(final.pressure, final.traction_x, final.traction_y, angle=angle)
        datasets.update(self._plane_datasets(plane, f"subsurface/{group}"))
        peak = plane.peak()
        below_surface = float(depths[1]) if len(depths) > 1 else float(depths[0])
        sub_peak = plane.peak(min_depth=below_surface)
        status = np.asarray(final.status)
        contact = int(np.count_nonzero(status > 0))
        stick = int(np.count_nonzero(status == 1))
        row = self._parameters_row(case, COMPLETED)
        row.update(
            load=float(final.load),
            approach=float(final.approach),
            p0=float(nominal_mean_pressure(cfg)),
            vm_max=float(peak.value),
            vm_max_x=float(peak.x),
            vm_max_y=float(peak.y),
            vm_max_z=float(peak.z),
            vm_sub_max=float(sub_peak.value),
            vm_sub_max_x=float(sub_peak.x),
            vm_sub_max_y=float(sub_peak.y),
            vm_sub_max_z=float(sub_peak.z),
            stick_fraction=stick / contact if contact else math.nan,
        )
        return row

    @staticmethod
    def _parameters_row(case: Case, status: CaseStatus) -> dict[str, Any]:
        row = pending_row(case.parameters(), status)
        if case.alpha is not None:  # energy wear law (not a summary column of the other laws)
            row["alpha"] = case.alpha
        return row

    # ---------------------------------------------------------------- checkpoints
    def _checkpoint_path(self, case: Case) -> Path:
        return self.checkpoint_dir / f"{case.case_id}.npz"

    def _progress_path(self, case: Case) -> Path:
        return self.checkpoint_dir / f"{case.case_id}.json"

    def _load_progress(self, case: Case) -> dict:
        path = self._progress_path(case)
        if path.exists() and self._checkpoint_path(case).exists():
            return json.loads(path.read_text())
        return {}

    def _save_progress(self, case: Case, progress: dict) -> None:
        path = self._progress_path(case)
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary = path.with_name(f".{path.name}.tmp")
        temporary.write_text(json.dumps(progress))
        os.replace(temporary, path)

    def _remove_checkpoint(self, case: Case) -> None:
        for path in (self._checkpoint_path(case), self._progress_path(case)):
            path.unlink(missing_ok=True)
