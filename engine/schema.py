"""The results schema: what a case produces, where it is stored, in which units.

One table for everything the other layers must agree on: the case status values,
the dataset paths of a case group with their units and descriptions, the peak-region codes
stored in the histories, the summary columns and the row of a case without results. The
loading kinds (:mod:`engine.study.kinds`), the layout (:mod:`engine.study.layout`), the solvers'
histories (:mod:`engine.solvers.cyclic`, :mod:`engine.solvers.peak`), the writers
(:mod:`engine.output.hdf5`, :mod:`engine.output.collective`), the summary, the scheduler, the
CLI and the results reader (:mod:`engine.analysis.results`) all take them from here. This
module sits below every layer and imports nothing of the engine.

Layout of a case group ``/cases/<case_id>/`` (units as UDUNITS strings, "1" dimensionless)::

    grid/x, grid/y                    element-centre coordinates of the case (mm), shape (n,)
    history/<key>                     cyclic: one entry per simulated cycle (HISTORY);
                                      static: one entry per load increment (STATIC_HISTORY)
    fields/final/<name>               surface fields at peak load of the last cycle
                                      (FINAL_FIELDS), shape (n_x, n_y), ij indexing
    fields/cycle_NNNNNNN/<name>       the same at each recorded cycle (RECORDED_FIELDS)
    subsurface/final/<name>,          the x-z plane through the punch axis (PLANE), shape
    subsurface/cycle_NNNNNNN/<name>   (n_s, n_z): x, y, z (mm), von_mises, sigma_<ij> (MPa)
    peak_changes/cycle_NNNNNNN/<name> the plane and PEAK_CHANGE_FIELDS at the first cycle and
                                      each change of the peak region (cyclic)
    fatigue/cycle_NNNNNNN/<name>      fretting with [fatigue]: each criterion's map on the
                                      stress plane, its angles, lives and hot spot
                                      (fatigue_maps)

and at the root ``/grid/x``, ``/grid/y`` (ROOT_GRID) when every case shares the grid. Every
dataset carries ``units`` and ``description`` attributes; :func:`case_dataset` gives both for
any path of a case group, so a test can check a written file against this table.

The units of the tables are a 3-D contact's. A line (plane-strain) contact is computed per
unit length along y: its forces, energies, areas and volumes are per mm of contact length
(N → N/mm, mJ → mJ/mm, mm^2 → mm^2/mm, and a volume mm^3 → mm^2/mm, the worn area per mm
of length as ``scar_area``, :data:`PER_UNIT_LENGTH`);
:func:`contact_units` turns a table's unit into the contact's, :func:`unit_of` takes the
geometry, and :meth:`DatasetRecord.per_unit_length` gives a
line contact's record. Lengths, pressures, stresses and counts are the same in both.
"""

from __future__ import annotations

import dataclasses
import enum
import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "CaseStatus",
    "DatasetRecord",
    "DatasetSpec",
    "FIELDS",
    "FIELD_DTYPES",
    "FINAL_FIELDS",
    "RECORDED_FIELDS",
    "PEAK_CHANGE_FIELDS",
    "HISTORY",
    "CYCLIC_HISTORY_KEYS",
    "STATIC_HISTORY",
    "PEAK_HISTORY_UNITS",
    "PEAK_HISTORY_DESCRIPTIONS",
    "PLANE",
    "STRESS_COMPONENTS",
    "CASE_GRID",
    "ROOT_GRID",
    "REGIONS",
    "AXIS_RADIUS_FRACTION",
    "SURFACE_DEPTH_FRACTION",
    "DEEP_DEPTH_FRACTION",
    "PARAMETER_UNITS",
    "PARAMETERS",
    "SWEPT_KEY_UNITS",
    "SWEPT_TEXT_KEYS",
    "UNITS",
    "PER_UNIT_LENGTH",
    "contact_units",
    "unit_of",
    "SUMMARY_COLUMNS",
    "SURFACE_COLUMNS",
    "SURFACE_DATASETS",
    "FRETTING_HISTORY",
    "FRETTING_RECORDS",
    "FATIGUE_HOT_SPOT_COLUMNS",
    "fatigue_specs",
    "fatigue_maps",
    "LOOP_COLUMNS",
    "fretting_record",
    "COLUMN_UNITS",
    "COLUMN_DESCRIPTIONS",
    "INTEGER_COLUMNS",
    "TEXT_COLUMNS",
    "CASES_GROUP",
    "GRID_GROUP",
    "CYCLE_GROUP",
    "cycle_group",
    "CASE_SECTIONS",
    "case_group_path",
    "cycle_of_group",
    "field_dataset",
    "on_plane",
    "history_dataset",
    "plane_dataset",
    "grid_dataset",
    "case_dataset",
    "pending_row",
    "THRESHOLDS_GROUP",
    "threshold_columns",
]


class CaseStatus(enum.StrEnum):
    """Status of a case, as stored in the ``status`` attribute and the summary column.

    A ``str`` enum: ``CaseStatus.COMPLETED == "completed"`` and it is written as that text."""

    PENDING = "pending"  # created from the plan, nothing computed yet
    COMPLETED = "completed"  # every dataset and the summary row written
    FAILED = "failed"  # message and traceback say why (non-convergence included)
    INTERRUPTED = "interrupted"  # stopped on request; the cyclic state is checkpointed


@dataclass
class DatasetRecord:
    """An array with its units (UDUNITS-style string, "1" = dimensionless) and a description."""

    data: np.ndarray
    units: str
    description: str = ""
    attrs: dict[str, Any] = field(default_factory=dict)  # further attributes (e.g. columns)

    def per_unit_length(self, line: bool) -> DatasetRecord:
        """This record for a line contact (``line``: its units per unit length,
        :func:`contact_units`) or a 3-D one (itself); the data is the same array."""
        units = contact_units(self.units, line)
        return self if units == self.units else dataclasses.replace(self, units=units)


@dataclass(frozen=True)
class DatasetSpec:
    """Units and description of a dataset (the ``units`` and ``description`` attributes)."""

    units: str
    description: str
    columns: str = ""  # a table's column names (the ``columns`` attribute), "" for arrays

    def record(self, data) -> DatasetRecord:
        """``data`` as a :class:`DatasetRecord` carrying this spec's attributes."""
        attrs = {"columns": self.columns} if self.columns else {}
        return DatasetRecord(np.asarray(data), self.units, self.description, attrs)


# ------------------------------------------------------------------ surface fields
FIELDS = {
    "wear": DatasetSpec("mm", "accumulated wear depth, shape (n_x, n_y), ij indexing"),
    "pressure": DatasetSpec(
        "MPa", "normal contact pressure, positive in compression, shape (n_x, n_y)"
    ),
    "traction_x": DatasetSpec("MPa", "tangential traction x, shape (n_x, n_y)"),
    "traction_y": DatasetSpec("MPa", "tangential traction y, shape (n_x, n_y)"),
    "slip_x": DatasetSpec("mm", "slip increment x of the last load step, shape (n_x, n_y)"),
    "slip_y": DatasetSpec("mm", "slip increment y of the last load step, shape (n_x, n_y)"),
    "status": DatasetSpec("1", "contact status: 0 no contact, 1 stick, 2 slip"),
}
FINAL_FIELDS = ("pressure", "traction_x", "traction_y", "slip_x", "slip_y", "status")
RECORDED_FIELDS = ("wear", "pressure", "traction_x", "traction_y", "status")  # CyclicAnalysis
PEAK_CHANGE_FIELDS = ("pressure", "traction_x", "traction_y")
FIELD_DTYPES = {"status": "int8"}  # every other field is float64

# ------------------------------------------------------------------ peak regions
REGIONS = ("edge-surface", "edge-subsurface", "axis-subsurface", "axis-surface")
AXIS_RADIUS_FRACTION = 0.5  # r/a below which a peak is "axis"
SURFACE_DEPTH_FRACTION = 0.1  # z/a below which a peak is "surface"
DEEP_DEPTH_FRACTION = 0.1  # z/a0 from which a peak is "deep" (vm_deep_max)

# ------------------------------------------------------------------ histories
_CYCLIC_HISTORY_UNITS = {
    "cycle": "1",
    "jump": "1",
    "max_wear_depth": "mm",
    "wear_volume": "mm^3",
    "peak_pressure": "MPa",
    "stick_area": "mm^2",
    "slip_area": "mm^2",
    "approach": "mm",
}
CYCLIC_HISTORY_KEYS = tuple(_CYCLIC_HISTORY_UNITS)  # engine.solvers.cyclic, in this order

PEAK_HISTORY_UNITS = {
    "vm_max": "MPa",
    "vm_max_x": "mm",
    "vm_max_z": "mm",
    "vm_sub_max": "MPa",
    "vm_sub_max_x": "mm",
    "vm_sub_max_z": "mm",
    "vm_deep_max": "MPa",
    "vm_deep_max_x": "mm",
    "vm_deep_max_z": "mm",
    "vm_axis_max": "MPa",
    "vm_axis_max_z": "mm",
    "contact_radius": "mm",
    "centre_pressure": "MPa",
    "peak_region": "1",
    "deep_region": "1",
}

_PLANE_PEAK = "von Mises stress (Eq. 21) on the x-z plane through the axis at peak load"
PEAK_HISTORY_DESCRIPTIONS = {
    "vm_max": f"maximum {_PLANE_PEAK}, surface layer included",
    "vm_max_x": "x of vm_max",
    "vm_max_z": "depth z of vm_max (into the half-space)",
    "vm_sub_max": f"maximum {_PLANE_PEAK}, below the surface layer (z >= depths[1])",
    "vm_sub_max_x": "x of vm_sub_max",
    "vm_sub_max_z": "depth z of vm_sub_max",
    "vm_deep_max": f"maximum {_PLANE_PEAK} at depth z >= {DEEP_DEPTH_FRACTION:g} a0",
    "vm_deep_max_x": "x of vm_deep_max",
    "vm_deep_max_z": "depth z of vm_deep_max",
    "vm_axis_max": f"maximum {_PLANE_PEAK} on the punch axis r = 0",
    "vm_axis_max_z": "depth z of vm_axis_max",
    "contact_radius": "area-equivalent contact radius sqrt(A_c/pi), A_c: elements with p > 0 "
    "(a line contact: the half-width, half the length in contact)",
    "centre_pressure": "contact pressure at the punch axis (elements nearest to r = 0)",
    "peak_region": (
        "where vm_max sits: "
        + ", ".join(f"{code} {name}" for code, name in enumerate(REGIONS))
        + f" (axis: r/a < {AXIS_RADIUS_FRACTION:g}; surface: z/a < {SURFACE_DEPTH_FRACTION:g};"
        " a = contact_radius)"
    ),
    "deep_region": "where vm_deep_max sits, same codes and thresholds as peak_region",
}

_PER_CYCLE = ", per simulated cycle (after N = cycle)"
#: history/<key> of a cyclic case: the solver's keys (units only: the description is the key)
#: and the peak tracker's (engine.solvers.peak).
HISTORY = {
    key: DatasetSpec(units, key + _PER_CYCLE) for key, units in _CYCLIC_HISTORY_UNITS.items()
} | {
    key: DatasetSpec(units, PEAK_HISTORY_DESCRIPTIONS[key] + _PER_CYCLE)
    for key, units in PEAK_HISTORY_UNITS.items()
}
#: history/<key> of a static case (one entry per load increment).
STATIC_HISTORY = {
    "load": DatasetSpec("N", "load per increment"),
    "approach": DatasetSpec("mm", "rigid approach per increment"),
}

# ------------------------------------------------------------------ x-z plane, grids
STRESS_COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")
PLANE = {
    "x": DatasetSpec("mm", "x coordinates of the plane"),
    "y": DatasetSpec("mm", "y coordinates of the plane"),
    "z": DatasetSpec("mm", "depth below the surface (into the half-space)"),
    "von_mises": DatasetSpec("MPa", "von Mises stress, Eq. (21)"),
} | {
    f"sigma_{name}": DatasetSpec("MPa", f"stress component {name}, compression negative")
    for name in STRESS_COMPONENTS
}
CASE_GRID = {
    axis: DatasetSpec("mm", f"element-centre {axis} coordinates of this case") for axis in "xy"
}
ROOT_GRID = {axis: DatasetSpec("mm", f"element-centre {axis} coordinates") for axis in "xy"}

# ------------------------------------------------------------------ cycle groups
CYCLE_GROUP = re.compile(r"cycle_(\d+)$")


#: The groups at the root of a results file: every case's group (``/cases/<case_id>``) and
#: the study-wide grid (``/grid/{x, y}``, :data:`ROOT_GRID`; a case with a grid of its own
#: holds it in its group, under the same name, :data:`CASE_GRID`). The threshold tables of a
#: search study are :data:`THRESHOLDS_GROUP`.
CASES_GROUP = "cases"
GRID_GROUP = "grid"

#: The groups of a case group (``/cases/<case_id>/<section>/...``).
CASE_SECTIONS = (
    GRID_GROUP, "history", "fields", "subsurface", "peak_changes", "fatigue", "surface"
)  # fmt: skip

#: ``surface/<name>`` of a case of a study with ``[surface]`` (engine.surface.outputs); a
#: line contact's spectra are in mm^3 (a profile's).
SURFACE_DATASETS = {
    "height": DatasetSpec(
        "mm",
        "surface heights h on the case's grid, shape (n_x, n_y), asperity tops positive: the "
        "gap is the profile's gap minus h",
    ),
    "wavevector": DatasetSpec("rad/mm", "wavevector q = 2π/λ at the centres of the PSD's annuli"),
    "psd": DatasetSpec(
        "mm^4", "radially averaged power spectrum C(q) = |h̃(q)|²/A of h, before wear"
    ),
    "psd_worn": DatasetSpec(
        "mm^4", "radially averaged power spectrum of h − w after the last recorded cycle's wear"
    ),
}


def case_group_path(section: str, *names: str) -> str:
    """Path of a dataset relative to its case group, e.g. ``case_group_path("fields",
    cycle_group(10), "wear")`` → ``"fields/cycle_0000010/wear"``; ``section`` must be one of
    :data:`CASE_SECTIONS`."""
    if section not in CASE_SECTIONS:
        raise KeyError(f"{section!r} is not a section of a case group {CASE_SECTIONS}")
    return "/".join((section, *names))


def cycle_group(cycle: int) -> str:
    """Name of the group of a recorded cycle: ``cycle_0001000`` (seven digits)."""
    return f"cycle_{int(cycle):07d}"


def cycle_of_group(name: str) -> int | None:
    """The cycle N of a group named ``cycle_<N>``, None for any other name (``final``)."""
    match = CYCLE_GROUP.match(name)
    return int(match.group(1)) if match else None


#: history/<key> of a fretting case beyond HISTORY (engine.solvers.fretting); ``stick_area``
#: is taken at the increment of the largest |Q| there.
FRETTING_HISTORY = {
    key: DatasetSpec(units, description + _PER_CYCLE)
    for key, units, description in (
        ("q_amplitude", "N", "tangential force amplitude max_k |Q_k| over the cycle's increments"),
        (
            "displacement_amplitude",
            "mm",
            "rigid tangential displacement amplitude (max δ·d − min δ·d)/2 over the cycle's "
            "increments",
        ),
        ("energy", "mJ", "energy dissipated per cycle ∮ Q·dδ (trapezoidal rule, area of the loop)"),
        (
            "slip_regime",
            "1",
            "slip regime: 0 = partial slip (some element sticks at the increment of the largest "
            "|Q|), 1 = gross slip (none sticks)",
        ),
        ("stick_area", "mm^2", "stick area at the increment of the largest |Q|"),
        ("evaluations", "1", "increment solves of the cycle (force control: secant evaluations)"),
        ("matvecs", "1", "operator applications of the cycle's increment solves"),
        (
            "residual",
            "1",
            "largest relative residual of the cycle's increment solves (≤ [solver] tol unless "
            "the case failed)",
        ),
        # only when [loading] direction != 0 (the plane then contains the sliding direction)
        ("vm_max_y", "mm", "y of vm_max"),
        ("vm_sub_max_y", "mm", "y of vm_sub_max"),
        ("vm_deep_max_y", "mm", "y of vm_deep_max"),
    )
}
LOOP_COLUMNS = ("delta_x", "delta_y", "Q_x", "Q_y")
#: fields/cycle_<N>/<name> of a fretting case beyond the surface fields.
FRETTING_RECORDS = {
    "loop": DatasetSpec(
        "mm, mm, N, N",
        "fretting loop: columns delta_x, delta_y (rigid tangential displacement of the punch), "
        "Q_x, Q_y (total tangential force on the half-space), units per column in `units`; "
        "row 0 is the start of the cycle (the end of the previous one), then one row per "
        "increment (4·steps)",
        ", ".join(LOOP_COLUMNS),
    ),
    "vm_cycle": DatasetSpec(
        "MPa, mm, mm, mm",
        "largest von Mises stress over the increments of the cycle in the x–z plane and its "
        "location: value, x, y, z",
        "vm, x, y, z",
    ),
    "status_minus_q": DatasetSpec(
        "1",
        "contact status at −Q*, the increment of the largest |Q| on the negative half of the "
        "loop (the other fields are at +Q*): 0 no contact, 1 stick, 2 slip; shape (n_x, n_y)",
    ),
}


# ------------------------------------------------------------------ fatigue criteria
#: The columns of a fatigue criterion's hot spot (``fatigue/cycle_<N>/<column>_hot_spot``).
#: A criterion's columns and datasets are named from its own column, unit and description
#: (:func:`fatigue_specs`, :func:`fatigue_maps`; the criteria declare them,
#: :mod:`engine.fatigue`).
FATIGUE_HOT_SPOT_COLUMNS = ("value", "x", "z", "angle", "life", "critical", "critical_x")


def fatigue_specs(column: str, unit: str, what: str, angle: bool, life: bool):
    """The columns of one criterion (summary and, per simulated cycle, history): name →
    :class:`DatasetSpec`, in the summary's order: ``<column>``, ``_x``, ``_z``, ``_angle``
    (critical-plane criteria), ``_critical``, ``_life`` (criteria with a life curve)."""
    specs = {
        column: DatasetSpec(unit, f"{what}, its largest value over the stress plane (hot spot)"),
        f"{column}_x": DatasetSpec("mm", f"x of the {column} hot spot (along the plane)"),
        f"{column}_z": DatasetSpec("mm", f"depth z of the {column} hot spot"),
    }
    if angle:
        specs[f"{column}_angle"] = DatasetSpec(
            "degree", f"critical plane at the {column} hot spot, from +x towards +z"
        )
    specs[f"{column}_critical"] = DatasetSpec(
        unit, f"{column} read at the critical distance ([fatigue] method and length)"
    )
    if life:
        specs[f"{column}_life"] = DatasetSpec(
            "1", f"cycles to crack nucleation at the {column} hot spot (inf: below the curve)"
        )
    return specs


def fatigue_maps(column: str, unit: str, what: str, angle: bool, life: bool, cycle: int):
    """``fatigue/cycle_<N>/<name>`` of one criterion: its map on the stress plane, its plane
    angles and lives where it has them, and its hot spot (name → :class:`DatasetSpec`)."""
    where = f"on the stress plane (the points of subsurface/cycle_NNNNNNN/x, z), cycle {cycle}"
    specs = {column: DatasetSpec(unit, f"{what} {where}")}
    if angle:
        specs[f"{column}_angle"] = DatasetSpec("degree", f"critical plane of {column} {where}")
    if life:
        specs[f"{column}_life"] = DatasetSpec("1", f"cycles to crack nucleation, {column}, {where}")
    specs[f"{column}_hot_spot"] = DatasetSpec(
        f"{unit}, mm, mm, degree, 1, {unit}, mm",
        f"{column} hot spot of cycle {cycle}: value, x, z, critical-plane angle (NaN: none), "
        "life (NaN: none); the value at the critical distance and the x of the surface hot "
        "spot it is read below",
        ", ".join(FATIGUE_HOT_SPOT_COLUMNS),
    )
    return specs


def fretting_record(name: str, cycle: int) -> DatasetSpec:
    """``fields/cycle_<N>/<name>`` of a fretting case: the loop or the cycle's σ_VM maximum."""
    spec = _known(FRETTING_RECORDS, name, "FRETTING_RECORDS")
    return DatasetSpec(spec.units, f"{spec.description}, cycle {cycle}", spec.columns)


def _moment(group: str) -> str:
    cycle = cycle_of_group(group)
    if cycle is None:
        return "the last simulated cycle"
    return f"cycle {cycle}"


def _known(table: dict[str, DatasetSpec], key: str, name: str) -> DatasetSpec:
    """``table[key]``; a key the schema lacks raises a KeyError that says where to add it."""
    if key not in table:
        raise KeyError(f"{key!r} is not in the results schema (add it to engine.schema.{name})")
    return table[key]


def field_dataset(name: str, group: str = "final", at: str = "peak load") -> DatasetSpec:
    """Surface field ``name`` at the instant ``at`` ("peak load"; a fretting cycle's
    "largest |Q|") of ``group`` ("final" or ``cycle_group(N)``)."""
    spec = _known(FIELDS, name, "FIELDS")
    return DatasetSpec(spec.units, f"{spec.description}, {at} of {_moment(group)}")


_XZ_PLANE = re.compile(r"x[-–]z plane( through the axis)?")


def on_plane(description: str, angle: float, plane_group: bool = False) -> str:
    """``description`` of a dataset on the stress plane turned to ``angle`` (degrees from x,
    ≠ 0): "the x–z plane" becomes the vertical plane through the axis at that angle; a
    dataset of a plane group (``subsurface/*``, ``plane_group``) also says how its x, y
    follow from the distance s along the plane. At 0 the description is unchanged."""
    if angle == 0.0:
        return description
    plane = f"vertical plane through the axis at {angle:g}° from x (the sliding direction)"
    description = _XZ_PLANE.sub(plane, description)
    if plane_group:
        description += f"; on the {plane}, x = s cos φ, y = s sin φ, φ = {angle:g}°"
    return description


def history_dataset(key: str, cyclic: bool = True, fretting: bool = False) -> DatasetSpec:
    """``history/<key>`` of a cyclic or fretting (per simulated cycle) or static (per
    increment) case."""
    if fretting and key in FRETTING_HISTORY:
        return FRETTING_HISTORY[key]
    if cyclic:
        return _known(HISTORY, key, "HISTORY")
    return _known(STATIC_HISTORY, key, "STATIC_HISTORY")


def plane_dataset(name: str) -> DatasetSpec:
    """Dataset ``name`` of an x-z plane group (``subsurface/*``, ``peak_changes/*``)."""
    return _known(PLANE, name, "PLANE")


def grid_dataset(axis: str, per_case: bool = True) -> DatasetSpec:
    """``grid/<axis>`` of a case group (``per_case``) or of the file's root."""
    return _known(CASE_GRID if per_case else ROOT_GRID, axis, "CASE_GRID")


def case_dataset(path: str, cyclic: bool = True, criteria=()) -> DatasetSpec:
    """Units and description of the dataset at ``path`` relative to a case group;
    ``criteria``: the (column, unit, what, angle, life) of the fatigue criteria the case
    evaluates (``engine.study.fatigue.criterion_schema``).

    Raises KeyError for a path the schema does not know."""
    parts = path.split("/")
    if len(parts) == 2 and parts[0] == "grid":
        return grid_dataset(parts[1])
    if len(parts) == 2 and parts[0] == "history":
        for described in criteria if cyclic else ():
            specs = fatigue_specs(*described)
            if parts[1] in specs:
                return DatasetSpec(specs[parts[1]].units, specs[parts[1]].description + _PER_CYCLE)
        return history_dataset(parts[1], cyclic)
    if len(parts) == 3 and parts[0] == "fields":
        allowed = FINAL_FIELDS if parts[1] == "final" else RECORDED_FIELDS
        if (parts[1] == "final" or cycle_of_group(parts[1]) is not None) and parts[2] in allowed:
            return field_dataset(parts[2], parts[1])
    if len(parts) == 3 and parts[0] == "subsurface":
        if parts[1] == "final" or cycle_of_group(parts[1]) is not None:
            return plane_dataset(parts[2])
    if len(parts) == 3 and parts[0] == "peak_changes" and cycle_of_group(parts[1]) is not None:
        if parts[2] in PEAK_CHANGE_FIELDS:
            return field_dataset(parts[2], parts[1])
        return plane_dataset(parts[2])
    if len(parts) == 2 and parts[0] == "surface":
        return _known(SURFACE_DATASETS, parts[1], "SURFACE_DATASETS")
    if len(parts) == 3 and parts[0] == "fatigue" and cycle_of_group(parts[1]) is not None:
        for described in criteria:
            specs = fatigue_maps(*described, cycle_of_group(parts[1]))
            if parts[2] in specs:
                return specs[parts[2]]
    raise KeyError(f"no dataset {path!r} in the results schema")


# ------------------------------------------------------------------ summary table
#: Units of the study-file keys of the engine's own sections that ``[sweep]`` may vary
#: (dotted), as parameters and summary columns of each case. The plug-ins' keys (a loading
#: kind's ``[loading]`` numbers, a profile's ``[punch]`` keys, the ``[fatigue]`` constants)
#: come from their declarations, and the study
#: layer's ``SWEEPABLE`` is the union (:mod:`engine.study.units`).
SWEPT_KEY_UNITS = {
    "material.E_A": "MPa",
    "material.nu_A": "1",
    "material.E_B": "MPa",
    "material.nu_B": "1",
    "mesh.n": "1",
    "mesh.half_width": "mm",
    "mesh.reference_distance": "mm",
    "subsurface.depth": "punch radii",
    "subsurface.layers": "1",
    "solver.tol": "1",
    "solver.maxiter": "1",
    # [surface] (engine.surface.config)
    "surface.seed": "1",
    "surface.hurst": "1",
    "surface.long_cutoff": "mm",
    "surface.short_cutoff": "mm",
    "surface.rms_height": "mm",
    "surface.rms_slope": "1",
    "surface.pixel_size": "mm",
}
#: Text keys ``[sweep]`` may vary, as lists of strings (``"surface.path" = ["a.npy",
#: "b.npy"]``): their summary columns and case parameters hold the text, without a unit; the
#: section's parser checks every value (engine.surface.config).
SWEPT_TEXT_KEYS = ("surface.kind", "surface.path", "surface.units", "surface.detrend")
#: The parameters every case stores as attributes, the first columns of every summary:
#: friction, the default wear law's (Archard's) coefficients, 0 under another law, and the
#: axes angle. A study's wear law adds its own coefficients after them (their units and
#: meanings are the law's declaration, ``engine.solvers.wear_laws``).
PARAMETERS = ("mu1", "mu2", "wear1", "wear2", "beta")
PARAMETER_UNITS = {"mu1": "1", "mu2": "1", "wear1": "1/MPa", "wear2": "1/MPa", "beta": "degree"}

SUMMARY_COLUMNS = [
    "case_id", *PARAMETERS, "status", "cycles", "load",
    "approach", "p0", "max_wear_depth", "wear_volume",
    "vm_max", "vm_max_x", "vm_max_y", "vm_max_z",
    "vm_sub_max", "vm_sub_max_x", "vm_sub_max_y", "vm_sub_max_z",
    "stick_fraction", "load_steps", "matvecs", "runtime_s",
    "vm_deep_max", "vm_deep_max_x", "vm_deep_max_z", "vm_axis_max", "vm_axis_max_z",
    "contact_radius", "centre_pressure", "elastic_approach", "wear_severity",
    "peak_region", "peak_region_change_cycle", "deep_region",
    "vm_max_on_edge", "vm_sub_max_on_edge",
]  # fmt: skip

COLUMN_UNITS = {
    "wear1": "1/MPa", "wear2": "1/MPa", "beta": "degree", "load": "N", "approach": "mm",
    "p0": "MPa", "max_wear_depth": "mm", "wear_volume": "mm^3",
    "vm_max": "MPa", "vm_max_x": "mm", "vm_max_y": "mm", "vm_max_z": "mm",
    "vm_sub_max": "MPa", "vm_sub_max_x": "mm", "vm_sub_max_y": "mm", "vm_sub_max_z": "mm",
    "runtime_s": "s",
    "vm_deep_max": "MPa", "vm_deep_max_x": "mm", "vm_deep_max_z": "mm",
    "vm_axis_max": "MPa", "vm_axis_max_z": "mm", "contact_radius": "mm",
    "centre_pressure": "MPa", "elastic_approach": "mm",
    # dimensionless ("1"): friction coefficients, counts and ratios
    "mu1": "1", "mu2": "1", "cycles": "1", "stick_fraction": "1", "load_steps": "1",
    "matvecs": "1", "wear_severity": "1", "peak_region_change_cycle": "1",
    # fretting cases only (extra columns, engine.solvers.fretting)
    "q_amplitude": "N", "displacement_amplitude": "mm", "energy_per_cycle": "mJ",
    "vm_cycle_max": "MPa", "vm_cycle_max_x": "mm", "vm_cycle_max_y": "mm",
    "vm_cycle_max_z": "mm", "vm_deep_max_y": "mm",
    # line contacts with wear, and 3-D punches that wear too (engine.solvers.scar)
    "scar_depth": "mm", "scar_width": "mm", "scar_area": "mm^2/mm", "pad_wear_depth": "mm",
}  # fmt: skip

#: The summary columns of a study with ``[surface]`` (engine.surface.outputs): unit, meaning.
SURFACE_COLUMNS = {
    "real_area_fraction": ("1", "rough surface: real contact area (elements with p > 0) over "
                           "the nominal π a0² (line contacts: 2 a0)"),
    "contact_spots": ("1", "rough surface: contact spots (connected components of the contact, "
                      "elements sharing an edge)"),
    "largest_spot_area": ("mm^2", "rough surface: area of the largest contact spot"),
    "real_mean_pressure": ("MPa", "rough surface: mean pressure over the real contact area"),
    "real_peak_pressure": ("MPa", "rough surface: largest contact pressure"),
    "rms_height": ("mm", "rough surface: rms height of the surface before wear"),
    "rms_slope": ("1", "rough surface: rms slope (spectral) of the surface before wear"),
    "rms_height_worn": ("mm", "rough surface: rms height of h − w after the last recorded "
                        "cycle's wear (the scar's form included)"),
    "rms_slope_worn": ("1", "rough surface: rms slope of h − w after the wear"),
}  # fmt: skip
COLUMN_UNITS.update({column: unit for column, (unit, _) in SURFACE_COLUMNS.items()})


#: A line (plane-strain) contact's unit of each extensive unit of the tables: per mm of
#: contact length along y (loads and forces, energies, areas; a volume becomes the worn area
#: per mm of length, mm²/mm as ``scar_area``; the reports' mm², mm³ and J too).
PER_UNIT_LENGTH = {
    "N": "N/mm", "mJ": "mJ/mm", "J": "J/mm", "mm^2": "mm^2/mm", "mm^3": "mm^2/mm",
    "mm²": "mm²/mm", "mm³": "mm²/mm",
}  # fmt: skip


def contact_units(units: str, line: bool) -> str:
    """``units`` (a unit of the tables, or a table's "mm, mm, N, N", one per column) in a line
    contact (``line``: :data:`PER_UNIT_LENGTH`) or a 3-D one (unchanged)."""
    if not line:
        return units
    return ", ".join(PER_UNIT_LENGTH.get(unit, unit) for unit in units.split(", "))


def unit_of(name: str, line: bool = False) -> str:
    """Units of a parameter, summary column or swept dotted key (:data:`UNITS`) in a 3-D or,
    ``line``, a line contact (:func:`contact_units`); "" for the text columns and names the
    table does not know."""
    return contact_units(UNITS.get(name, ""), line)


#: What each summary column holds (the manual's outputs reference is generated from these,
#: COLUMN_UNITS and PARAMETER_UNITS by scripts/reference.py; not stored in the files).
COLUMN_DESCRIPTIONS = {
    "case_id": "id built from the parameters, e.g. `mu0.1-0.4_w1.33e-07-5.32e-07_b45`; "
    "stable when the sweep grows",
    "mu1": "friction coefficient along e1",
    "mu2": "friction coefficient along e2",
    "wear1": "Archard wear coefficient i1 along e1",
    "wear2": "Archard wear coefficient i2 along e2",
    "beta": "angle of the tribological axes e1, e2 from x",
    "status": "`completed`, `failed`, `interrupted` or `pending`",
    "cycles": "load cycles reached (0 for static cases)",
    "load": "peak normal load P",
    "approach": "rigid approach at peak load of the last simulated cycle",
    "p0": "mean pressure of the nominal contact, not Hertz's peak: P/(π a0²) in 3-D (Eq. "
    "19; a sphere's Hertz peak is 1.5 p0), P/(2 a0) per unit length for a line contact (a "
    "cylinder's Hertz peak is (4/π) p0); a0: punch radius, Hertz radius or half-width",
    "max_wear_depth": "largest wear depth after the last cycle (0 for static cases)",
    "wear_volume": "worn volume after the last cycle (0 for static cases)",
    "vm_max": "largest von Mises stress on the stress plane, every layer (the surface layer "
    "holds the grid-dependent edge singularity of a sharp punch)",
    "vm_max_x": "x of vm_max",
    "vm_max_y": "y of vm_max",
    "vm_max_z": "depth z of vm_max (into the half-space)",
    "vm_sub_max": "largest von Mises stress below the surface layer (z ≥ the second layer)",
    "vm_sub_max_x": "x of vm_sub_max",
    "vm_sub_max_y": "y of vm_sub_max",
    "vm_sub_max_z": "depth z of vm_sub_max",
    "vm_max_on_edge": "where vm_max touches the computed plane's boundary: `inside` (it does "
    "not), `side` (the plane's end, the mesh's edge), `bottom` (its deepest layer) or `side "
    "and bottom`; on the boundary the maximum may lie beyond the domain (widen `[mesh] "
    "half_width` or deepen `[subsurface] depth`)",
    "vm_sub_max_on_edge": "the same for vm_sub_max",
    "stick_fraction": "stick area / contact area at peak load of the last simulated cycle",
    "load_steps": "load increments solved, over resumed runs too",
    "matvecs": "influence-operator applications",
    "runtime_s": "wall time of the case, summed over resumed runs",
    "vm_deep_max": f"largest von Mises stress at depth z ≥ {DEEP_DEPTH_FRACTION:g} a0 (cyclic)",
    "vm_deep_max_x": "x of vm_deep_max",
    "vm_deep_max_y": "y of vm_deep_max (fretting along a direction ≠ 0)",
    "vm_deep_max_z": "depth z of vm_deep_max",
    "vm_axis_max": "largest von Mises stress on the punch axis r = 0 (cyclic)",
    "vm_axis_max_z": "depth z of vm_axis_max",
    "contact_radius": "area-equivalent contact radius √(A_c/π) (cyclic; a line contact: its "
    "half-width)",
    "centre_pressure": "contact pressure at the punch axis (cyclic)",
    "elastic_approach": "elastic approach of the unworn surface",
    "wear_severity": "largest wear depth / elastic approach",
    "peak_region": "where vm_max sits: " + ", ".join(f"`{name}`" for name in REGIONS),
    "peak_region_change_cycle": "first cycle N at which peak_region changed",
    "deep_region": "where vm_deep_max sits, the same regions",
    "q_amplitude": "fretting: tangential force amplitude of the last simulated cycle",
    "displacement_amplitude": "fretting: rigid tangential displacement amplitude of the last "
    "simulated cycle",
    "energy_per_cycle": "fretting: energy dissipated in the last simulated cycle, ∮Q·dδ",
    "slip_regime": "fretting: `partial` (some element sticks at the largest |Q|) or `gross`",
    "vm_cycle_max": "fretting: largest von Mises stress over the last recorded cycle's "
    "increments (vm_max is at the increment of the largest |Q|)",
    "vm_cycle_max_x": "x of vm_cycle_max",
    "vm_cycle_max_y": "y of vm_cycle_max",
    "vm_cycle_max_z": "depth z of vm_cycle_max",
    "scar_depth": "largest wear depth of the flat (line contacts with wear; 3-D punches with "
    "`[wear] pad_coefficient`)",
    "scar_width": "line contacts: extent of the flat's scar (wear above 1 % of its depth)",
    "scar_area": "line contacts: worn area of the flat per unit length, Σ h Δx",
    "pad_wear_depth": "largest wear depth of the pad or punch (line contacts with wear; 3-D "
    "punches with `[wear] pad_coefficient`)",
}

COLUMN_DESCRIPTIONS.update({column: what for column, (_, what) in SURFACE_COLUMNS.items()})

#: The one units table of the results: case parameters, summary columns and swept keys.
UNITS = {**PARAMETER_UNITS, **COLUMN_UNITS, **SWEPT_KEY_UNITS}

INTEGER_COLUMNS = ("cycles", "load_steps", "matvecs", "peak_region_change_cycle")
TEXT_COLUMNS = (
    "case_id", "status", "peak_region", "deep_region", "slip_regime",
    "vm_max_on_edge", "vm_sub_max_on_edge",
)  # fmt: skip


def pending_row(parameters: dict[str, Any], status: str = CaseStatus.PENDING) -> dict[str, Any]:
    """Row of a case without results: its parameters (swept dotted keys included), the
    status (as plain text) and NaN elsewhere."""
    row = {column: math.nan for column in SUMMARY_COLUMNS}
    row.update({k: v for k, v in parameters.items() if k in row or "." in k})
    row["status"] = str(status)
    return row


# ------------------------------------------------------------------ thresholds table
#: Group of the thresholds table of a study with a ``[search]`` section: one 1-D dataset per
#: column (one entry per search, i.e. per combination of the sweep), the search's settings as
#: attributes (parameter, column, target, rtol, atol, method, max_steps).
THRESHOLDS_GROUP = "thresholds"


def threshold_columns(parameter: str, parameter_units: str, column: str, column_units: str):
    """Units and description of the search columns of the thresholds table (the sweep's
    parameter columns come before them, in the units of the summary)."""
    where = f"{parameter} ({parameter_units})"
    value = f"{column} ({column_units})" if column_units else column
    return {
        "threshold": DatasetSpec(parameter_units, f"{where} at which {column} crosses the target"),
        "lower": DatasetSpec(parameter_units, f"lower end of the final bracket, {where}"),
        "upper": DatasetSpec(parameter_units, f"upper end of the final bracket, {where}"),
        "lower_value": DatasetSpec(column_units or "1", f"{value} at the lower end"),
        "upper_value": DatasetSpec(column_units or "1", f"{value} at the upper end"),
        "steps": DatasetSpec("1", "cases the search took, both ends included"),
        "status": DatasetSpec(
            "1", "converged | not-bracketed | not-converged | failed | unfinished"
        ),
        "message": DatasetSpec("1", "why a search did not converge (empty otherwise)"),
    }
