"""What one case of a study produced, and the pieces every loading kind builds it from.

A case comes back as a :class:`CaseOutcome` with a status, so one bad case never stops the
study:

- ``completed``: summary row, datasets (with units) and attributes are filled in;
- ``failed``: ``message`` and ``traceback`` say why (non-convergence is a failure, never
  reported as converged);
- ``interrupted``: the stop request came; the kind saved its state to the case's checkpoint
  (``<output>.checkpoints/<case_id>.npz``) and the next run resumes from it.

:class:`CaseContext` is what the case runner (:mod:`engine.study.case`) lends a loading kind
(:mod:`engine.study.kinds`): the one place where a case's contact solver and its subsurface
stresses are built, the checkpoint path, the progress hook. The functions below turn solver
results into the datasets (paths, units and descriptions from :mod:`engine.schema`) and the
summary values shared by the kinds.

Subsurface stresses (paper Section 5, Eq. 16, von Mises Eq. 21) are evaluated in the vertical
plane through the punch axis (the x–z plane unless a kind turns it), at the final state and at
every recorded cycle. ``vm_max`` is the maximum over the whole plane; ``vm_sub_max`` the
maximum over the layers strictly below the surface layer, i.e. ``z >= depths[1]`` (the surface
layer itself carries the edge singularity of the flat punch, Eq. 17, whose value depends on
the element size).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from engine.geometry import ContactReachesBorder, border_contact, may_reach_border
from engine.material import MaterialPair
from engine.schema import (
    FINAL_FIELDS,
    PEAK_CHANGE_FIELDS,
    CaseStatus,
    DatasetRecord,
    DatasetSpec,
    case_group_path,
    contact_units,
    cycle_group,
    field_dataset,
    grid_dataset,
    pending_row,
    plane_dataset,
)
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw
from engine.solvers.peak import PeakTracker, first_region_change, region_name
from engine.solvers.scar import pad_ratio as ratio
from engine.solvers.scar import two_body_depths, two_body_wear_law
from engine.solvers.subsurface import depth_layers
from engine.solvers.wear_laws import WEAR_LAWS
from engine.study.line_contact import LineContact
from engine.study.line_contact import scar_row as line_scar_row
from engine.surface import rough_profile

from .plan import Case

if TYPE_CHECKING:  # annotations only: the configuration package parses the kinds' sections
    from .config import StudyConfig

__all__ = [
    "COMPLETED",
    "FAILED",
    "INTERRUPTED",
    "CaseOutcome",
    "CaseContext",
    "DatasetRecord",
    "BorderCheckedSolver",
    "InjectedFailure",
    "case_wear_law",
    "pad_ratio",
    "nominal_mean_pressure",
    "peak_tracker",
]

# Status values, dataset paths, units and descriptions: the results schema (engine.schema).
COMPLETED, FAILED, INTERRUPTED = (
    CaseStatus.COMPLETED,
    CaseStatus.FAILED,
    CaseStatus.INTERRUPTED,
)


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


# ---------------------------------------------------------------- laws and nominal values
def case_wear_law(case: Case, cfg: StudyConfig):
    """The case's wear law (``[wear] law``, kinds with wear): the registered law built from
    the case's coefficients (:meth:`engine.solvers.wear.WearModel.from_coefficients`; the
    orthotropic Archard law with wear1, wear2 in 1/MPa and β, the dissipated-energy law with
    α in mm³/J, …)."""
    law = WEAR_LAWS[cfg.wear.law].from_coefficients(case.coefficients, math.radians(case.beta))
    ratio = pad_ratio(case, cfg)
    if cfg.punch.is_line or ratio > 0.0:  # the gap carries the flat's and the pad's wear
        return two_body_wear_law(law, ratio)
    return law


def pad_ratio(case: Case, cfg: StudyConfig) -> float:
    """k_pad / k_flat (``[wear] pad_coefficient``, in the unit of the law's first
    coefficient; 0 without, the punch does not wear)."""
    flat = next(iter(case.coefficients.values()))
    return ratio(cfg.wear.pad_coefficient, flat)


def nominal_mean_pressure(cfg: StudyConfig) -> float:
    """The summary's p0 (MPa): P/(π a0²) with a0 the punch radius (flat: Eq. 19; rounded:
    the flat face's radius) or, for a sphere, Hertz's mean pressure P/(π a²), a = Hertz's
    contact radius (engine.reference.hertz); for a line contact P/(2 a0) with a0 the nominal
    half-width (engine.study.line_contact)."""
    return cfg.punch.profile().mean_pressure(cfg.loading.load, cfg.contact_length)


def peak_tracker(stress, contact_length: float, angle: float = 0.0):
    """The peak tracker of a case's stresses (engine.solvers.peak): a line contact's tracks
    its contact half-width (engine.solvers.line_subsurface)."""
    if stress.grid.is_line:
        return LineContact.peak_tracker(stress, contact_length, angle)

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

        return self._checked(result, f"P = {load:g} {contact_units('N', self.grid.is_line)}")

    def solve_approach(self, approach, state=None, wear=None):
        result = self._solver.solve_approach(approach, state, wear=wear)
        return self._checked(result, f"approach = {approach:g} mm")


# ---------------------------------------------------------------- what the runner lends
class CaseContext:
    """What the case runner lends a loading kind for one case: the solver and stress
    builders (sharing this rank's operator cache), the checkpoint path and the progress hook.

    Parameters
    ----------
    operators : engine.study.operators.OperatorCache
        Operators, plans and stress kernels shared by the cases of this rank.
    checkpoint_dir : pathlib.Path
        ``<output>.checkpoints``: where an interrupted case leaves its state.
    on_progress : callable or None
        ``on_progress(case, N, cycles)`` after each simulated cycle (None: no reports).
    """

    def __init__(self, operators, checkpoint_dir: Path, on_progress=None) -> None:
        self.operators = operators
        self.checkpoint_dir = Path(checkpoint_dir)
        self.on_progress: Callable[..., None] | None = on_progress

    def checkpoint_path(self, case: Case) -> Path:
        """``<output>.checkpoints/<case_id>.npz``."""
        return self.checkpoint_dir / f"{case.case_id}.npz"

    def on_cycle(self, case: Case) -> Callable[[int, int], None] | None:
        """The per-cycle progress callback ``(cycle, cycles)`` of ``case`` (None: no reports)."""
        if self.on_progress is None:
            return None
        report = self.on_progress
        return lambda cycle, cycles: report(case, cycle, cycles)

    def solver(self, case: Case, cfg: StudyConfig):
        """The one place where a case's contact solver is built (profile, grid, material,
        friction, options): returns (solver, grid, material). For profiles with a surface
        beyond the grid (sphere, a rounded edge cut by the mesh) it is wrapped so that a
        contact touching the grid's border fails the case
        (engine.geometry.ContactReachesBorder) instead of being truncated."""
        material = MaterialPair(
            cfg.material.E_A, cfg.material.nu_A, cfg.material.E_B, cfg.material.nu_B
        )
        punch = cfg.punch.profile()
        grid = punch.grid(cfg.mesh.n, cfg.mesh.half_width)  # square, or a line contact's
        punch.check_grid(grid)
        punch = rough_profile(punch, cfg.surface, grid)  # [surface]: the gap minus h
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

    def subsurface(self, grid, material, cfg: StudyConfig, plane_angle: float = 0.0):
        """(stress evaluator, depths in mm) of a case: ``[subsurface] layers`` depths down to
        ``depth · a0``; the plane through the axis at ``plane_angle`` (degrees from x)."""
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
            angle=math.radians(plane_angle),
        )
        if grid.is_line:
            stress.bulk_stress = 0.0  # shared between cases: each starts without bulk stress
        return stress, depths


# ---------------------------------------------------------------- datasets
def parameters_row(case: Case, status: str) -> dict[str, Any]:
    """The summary row of ``case`` before (or without) results: its parameters."""
    row = pending_row(case.parameters(), status)
    for name, value in case.coefficients.items():  # another law's (not fixed) columns
        row.setdefault(name, value)
    return row


def final_fields(final) -> dict[str, DatasetRecord]:
    """``fields/final/<name>`` of the final state (FINAL_FIELDS)."""
    return {
        case_group_path("fields", "final", name): field_dataset(name).record(getattr(final, name))
        for name in FINAL_FIELDS
    }


def plane_datasets(plane, group: str, prefix: str = "subsurface") -> dict[str, DatasetRecord]:
    """The plane's coordinates, σ_VM and components under ``<prefix>/<group>/``."""
    arrays = {"x": plane.x, "y": plane.y, "z": plane.z, "von_mises": plane.von_mises}
    arrays.update({f"sigma_{name}": values for name, values in plane.components.items()})
    return {
        case_group_path(prefix, group, name): plane_dataset(name).record(values)
        for name, values in arrays.items()
    }


def grid_datasets(grid) -> dict[str, DatasetRecord]:
    """The case's own grid (cases of a study may differ in mesh.n or half_width)."""
    return {
        case_group_path("grid", axis): grid_dataset(axis).record(values)
        for axis, values in (("x", grid.x), ("y", grid.y))
    }


def history_datasets(
    history: dict[str, np.ndarray], spec: Callable[[str], DatasetSpec]
) -> dict[str, DatasetRecord]:
    """``history/<key>`` of every key of ``history``; ``spec(key)`` is the kind's schema entry
    (a key the schema does not know raises)."""
    datasets = {}
    for key, values in history.items():
        values = np.asarray(values)
        if key in ("peak_region", "deep_region") and not np.any(np.isnan(values)):
            values = values.astype(np.int8)
        datasets[case_group_path("history", key)] = spec(key).record(values)
    return datasets


def recorded_datasets(records, stress, angle: float = 0.0, at: str = "peak load"):
    """The surface fields (``fields/cycle_N/``) and the stress plane through the axis at
    ``angle`` (radians; ``subsurface/cycle_N/``) of every recorded cycle N; ``at`` names
    the instant of the fields in their descriptions."""
    datasets = {}
    for cycle in sorted(records):
        fields, group = records[cycle], cycle_group(cycle)
        for name, values in fields.items():
            path = case_group_path("fields", group, name)
            datasets[path] = field_dataset(name, group, at).record(np.asarray(values))
        plane = stress.plane(
            fields["pressure"], fields["traction_x"], fields["traction_y"], angle=angle
        )
        datasets.update(plane_datasets(plane, group))
    return datasets


def region_change_datasets(stress, changes) -> dict[str, DatasetRecord]:
    """x–z plane (σ_VM and components) and the peak-load pressure and tractions at the first
    cycle and every change of the peak region, under ``peak_changes/cycle_<N>/``."""
    datasets = {}
    for cycle in sorted(changes):
        fields = changes[cycle]
        group = cycle_group(cycle)
        plane = stress.plane(
            fields["pressure"], fields["traction_x"], fields["traction_y"], angle=0.0
        )
        datasets.update(plane_datasets(plane, group, "peak_changes"))
        for name in PEAK_CHANGE_FIELDS:
            path = case_group_path("peak_changes", group, name)
            datasets[path] = field_dataset(name, group).record(fields[name])
    return datasets


# ---------------------------------------------------------------- summary values
def final_row(case, cfg, final, stress, depths, datasets, angle: float = 0.0) -> dict[str, Any]:
    """Summary values of the final state; σ_VM on the vertical plane at ``angle`` (rad,
    0: the x–z plane), whose datasets (``subsurface/final/*``) join ``datasets``."""
    plane = stress.plane(final.pressure, final.traction_x, final.traction_y, angle=angle)
    datasets.update(plane_datasets(plane, "final"))
    peak = plane.peak()
    below_surface = float(depths[1]) if len(depths) > 1 else float(depths[0])
    sub_peak = plane.peak(min_depth=below_surface)
    status = np.asarray(final.status)
    contact = int(np.count_nonzero(status > 0))
    stick = int(np.count_nonzero(status == 1))
    row = parameters_row(case, COMPLETED)
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
        vm_max_on_edge=plane.on_edge(),
        vm_sub_max_on_edge=plane.on_edge(below_surface),
        stick_fraction=stick / contact if contact else math.nan,
    )
    return row


def peak_row(tracker, final, history: dict[str, np.ndarray]) -> dict[str, Any]:
    """Summary values of the peak history: final peaks, region and its first change."""
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


def totals_row(result, cfg: StudyConfig) -> dict[str, Any]:
    """Cycles reached, wear, and the work counts (cumulative over resumed runs: they are kept
    in the state) of a run with cycles."""
    history = result.history
    cycles = history.get("cycle", [])
    return {
        "cycles": int(cycles[-1]) if len(cycles) else cfg.loading.cycles,
        "max_wear_depth": float(history["max_wear_depth"][-1]),
        "wear_volume": float(history["wear_volume"][-1]),
        "load_steps": int(result.load_steps),
        "matvecs": int(result.matvecs),
    }


def scar_row(case, cfg, grid, result) -> dict[str, Any]:
    """Line contacts: scar_depth, scar_width, scar_area of the flat and pad_wear_depth
    (engine.solvers.scar) from the final wear; a 3-D punch that wears too
    (``[wear] pad_coefficient``): scar_depth and pad_wear_depth; else nothing."""
    if not grid.is_line:
        ratio = pad_ratio(case, cfg)
        if ratio == 0.0:
            return {}

        return two_body_depths(result.state.wear, ratio)

    return line_scar_row(grid, result.state.wear, pad_ratio(case, cfg))
