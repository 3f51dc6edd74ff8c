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
  ``plane_step`` [1] (degrees between the critical planes searched; divides 180);
- ``every_cycle`` [false]: evaluate every simulated cycle too (hot spots per simulated cycle
  in ``history/<column>``; one full evaluation per simulated cycle), not only the recorded
  ones.

Only ``[loading] kind = "fretting"`` has the increments of a cycle to evaluate.

``FatigueAnalysis`` takes the increments of every evaluated cycle (``increment_probe`` with
the plane the case has evaluated already, and the bulk stress through ``set_bulk_stress``),
evaluates the criteria on the case's subsurface plane (at its depths) and at the
critical-distance points (exact direct sums, ``engine.fatigue.fields``), and keeps per
recorded cycle the map of each criterion, its hot spot (value, x, z, plane angle, life) and
its critical value (``datasets``: ``fatigue/cycle_NNNNNNN/*``); its summary columns are
``CriterionAssessment.summary()`` of the last recorded cycle. A checkpoint keeps the
evaluated cycles (``arrays``, ``restore``), so a resumed case loses none.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from engine.fatigue import CRITERIA, METHODS, FatigueOptions, assess, build_criteria
from engine.fatigue.fields import (
    CycleRecorder,
    LinePointStress,
    PlanePointStress,
    plane_history,
    planes_history,
)
from engine.fatigue.history import Elasticity
from engine.fatigue.quantities import AMPLITUDE_METHODS
from engine.keys import Key
from engine.schema import (
    FATIGUE_HOT_SPOT_COLUMNS,
    DatasetRecord,
    DatasetSpec,
    case_group_path,
    cycle_group,
    fatigue_maps,
    fatigue_specs,
)
from engine.study.settings.checks import Limit

_PER_CYCLE = ", per simulated cycle (after N = cycle)"

__all__ = [
    "FatigueConfig",
    "parse_fatigue",
    "fatigue_keys",
    "fatigue_sweepable",
    "fatigue_columns",
    "fatigue_column_specs",
    "fatigue_history",
    "fatigue_map_specs",
    "constant_ranges",
    "criterion_schema",
    "FatigueAnalysis",
    "FatigueCycle",
    "fatigue_layout",
]

_OPTIONS = {"criteria", "method", "length", "amplitude_method", "plane_step", "every_cycle"}


@dataclass(frozen=True)
class FatigueConfig:
    """The ``[fatigue]`` section, validated (module docstring)."""

    criteria: tuple[str, ...]
    constants: dict[str, float]
    method: str = "hotspot"
    length: float | None = None
    amplitude_method: str = "chord"
    plane_step: float = 1.0
    every_cycle: bool = False

    @property
    def options(self) -> FatigueOptions:
        return FatigueOptions(self.amplitude_method, self.plane_step)

    def resolved(self) -> dict[str, Any]:
        """The section as TOML-able data, the constants as keys of the section (every
        default filled in; ``length`` only where the method has one)."""
        out: dict[str, Any] = {"criteria": list(self.criteria)}
        out.update(self.constants)
        out.update(
            method=self.method,
            amplitude_method=self.amplitude_method,
            plane_step=self.plane_step,
            every_cycle=self.every_cycle,
        )
        if self.length is not None:
            out["length"] = self.length
        return out


def fatigue_sweepable(registry=CRITERIA) -> dict[str, str]:
    """Dotted sweep keys of the section with their units: every constant, ``length``."""
    keys = {
        f"fatigue.{name}": key.unit
        for cls in registry.values()
        for name, key in cls.constants.items()
    }
    keys["fatigue.length"] = "mm"
    return keys


def fatigue_keys(registry=CRITERIA) -> set[str]:
    """Every key the section accepts: the options and every registered criterion's constants."""
    return _OPTIONS | {name for cls in registry.values() for name in cls.constants}


MAX_LENGTH = 100.0  # mm, the critical distance
MAX_PLANE_STEP = 90.0  # degrees, the step of the critical-plane search (it must divide 180)


def constant_ranges(registry=CRITERIA) -> dict[str, Key]:
    """{constant: :class:`engine.keys.Key`} of the constants whose criteria of ``registry``
    declare bounds (the first criterion's that declares the constant; a constant without
    bounds is taken as given)."""
    ranges: dict[str, Key] = {}
    for cls in registry.values():
        for name, key in cls.constants.items():
            if key.minimum is not None or key.maximum is not None:
                ranges.setdefault(name, key)
    return ranges


def _check_range(section, name: str, value: float, criteria) -> None:
    """Refuse a constant outside the range a listed criterion declares for it, naming the
    key and why."""
    key = constant_ranges({c: CRITERIA[c] for c in criteria}).get(name)
    if key is None:
        return
    limit = Limit.of(key)
    if not limit.holds(value):
        accepted = limit.accepted
        verb = "lie in" if accepted[0] in "[(" else "be"
        raise section.error(name, value, f"must {verb} {accepted} ({key.why})")


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
    """Read the ``[fatigue]`` table (``engine.study.settings.reader.Section``): errors name the
    key and the value (a constant a listed criterion needs, a constant no listed criterion
    uses, a length missing for a critical-distance method …)."""
    section.check_known(fatigue_keys())
    criteria = _criteria(section)
    needed = {name: key.unit for c in criteria for name, key in CRITERIA[c].constants.items()}
    for key in section.table:
        if key not in _OPTIONS and key not in needed:
            raise section.error(
                key, section.table[key], f"not a constant of the criteria {list(criteria)}"
            )
    constants = {
        name: section.number(name, unit="" if unit == "1" else unit)
        for name, unit in needed.items()
    }
    method = section.string("method", "hotspot")
    if method not in METHODS:
        raise section.error("method", method, f"must be one of {', '.join(METHODS)}")
    length = None
    if method != "hotspot":
        length = section.number(
            "length", minimum=0.0, strict=True, unit="mm", maximum=MAX_LENGTH,
            why="critical distances of metals lie in 0.01 … 1 mm",
        )  # fmt: skip
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
    if step > MAX_PLANE_STEP or not float(180.0 / step).is_integer():
        raise section.error(
            "plane_step", step, f"must divide 180 degrees and be <= {MAX_PLANE_STEP:g}"
        )
    every_cycle = section.raw("every_cycle", False)
    if not isinstance(every_cycle, bool):
        raise section.error("every_cycle", every_cycle, "must be true or false")
    config = FatigueConfig(criteria, constants, method, length, amplitude, step, every_cycle)
    elasticity = Elasticity(1.0, 0.0)  # the constants' own checks (signs), any elasticity
    try:
        build_criteria(criteria, constants, elasticity, config.options)
    except ValueError as error:
        key = next((k for k in constants if f"'{k}'" in str(error)), "criteria")
        raise section.error(key, constants.get(key, list(criteria)), str(error)) from None
    for name, value in constants.items():  # signs checked above, magnitudes here
        _check_range(section, name, value, criteria)
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
    """The criteria on one evaluated cycle: its summary ``row`` (``fatigue_columns``) and,
    for a recorded cycle, its ``maps`` (name → array of the plane's shape: ``<column>``,
    ``<column>_angle``, ``<column>_life``)."""

    cycle: int
    row: dict[str, float]
    maps: dict[str, np.ndarray] = field(default_factory=dict)


def fatigue_layout(config: FatigueConfig, plane_shape) -> dict[str, tuple[int, ...]]:
    """Shapes of ``fatigue/cycle_NNNNNNN/<name>`` of one recorded cycle (float64): the maps
    have the stress plane's shape ``plane_shape``, the hot spots
    ``len(FATIGUE_HOT_SPOT_COLUMNS)`` values (``engine.study.layout``)."""
    shapes = {}
    for name in config.criteria:
        column, *described = criterion_schema(CRITERIA[name])
        for dataset in fatigue_maps(column, *described, 0):
            hot_spot = dataset == f"{column}_hot_spot"
            shapes[dataset] = (len(FATIGUE_HOT_SPOT_COLUMNS),) if hot_spot else tuple(plane_shape)
    return shapes


def criterion_schema(criterion) -> tuple[str, str, str, bool, bool]:
    """(column, unit, what, angle, life) of a criterion (class or instance) for the results
    schema (:func:`engine.schema.fatigue_specs`, :func:`engine.schema.fatigue_maps`): its
    declared ``description``, else its name."""
    what = criterion.description or criterion.name
    return criterion.column, criterion.unit, what, criterion.reports_angle, criterion.reports_life


def fatigue_column_specs(registry=CRITERIA) -> dict[str, DatasetSpec]:
    """Summary (and ``history/<column>``) columns of every registered criterion:
    name → :class:`DatasetSpec` (:func:`engine.schema.fatigue_specs`)."""
    specs: dict[str, DatasetSpec] = {}
    for cls in registry.values():
        specs.update(fatigue_specs(*criterion_schema(cls)))
    return specs


def fatigue_history(registry=CRITERIA) -> dict[str, DatasetSpec]:
    """``history/<key>`` of a fretting case with ``[fatigue] every_cycle = true``: every
    registered criterion's hot spots per simulated cycle."""
    return {
        key: DatasetSpec(spec.units, spec.description + _PER_CYCLE)
        for key, spec in fatigue_column_specs(registry).items()
    }


def fatigue_map_specs(cycle, registry=CRITERIA) -> dict[str, DatasetSpec]:
    """``fatigue/cycle_<N>/<name>`` of every registered criterion at ``cycle``."""
    specs: dict[str, DatasetSpec] = {}
    for cls in registry.values():
        specs.update(fatigue_maps(*criterion_schema(cls), cycle))
    return specs


class FatigueAnalysis:
    """Collects a fretting case's cycles and evaluates the criteria on them (module
    docstring). ``stress``: the case's plane evaluator (``SubsurfaceStress`` or
    ``LineSubsurfaceStress``; used where an increment comes without its plane); ``grid``;
    the flat's ``young_modulus`` (MPa) and ``poisson_ratio``; ``angle`` (rad) of a 3-D
    case's plane; ``recorded``: the cycles whose maps are kept (the others, evaluated with
    ``every_cycle``, keep their hot spots only)."""

    def __init__(
        self,
        config: FatigueConfig,
        stress,
        grid,
        young_modulus,
        poisson_ratio,
        angle=0.0,
        recorded=(),
    ):
        self.config, self.stress, self.grid, self.angle = config, stress, grid, angle
        self.poisson_ratio = poisson_ratio
        self.recorded = frozenset(int(c) for c in recorded)
        elasticity = Elasticity(young_modulus, poisson_ratio)
        self.criteria = build_criteria(
            config.criteria, config.constants, elasticity, config.options
        )
        self.recorder = CycleRecorder()
        self.planes: list = []
        self.cycles: list[FatigueCycle] = []

    @property
    def columns(self) -> list[str]:
        return fatigue_columns(self.config)

    @property
    def _row_keys(self) -> list[str]:
        """The summary columns and, per criterion, the x of the surface hot spot below which
        the critical distance is read (``<column>_critical_x``, in the hot-spot datasets)."""
        return self.columns + [f"{c.column}_critical_x" for c in self.criteria]

    def set_bulk_stress(self, value: float) -> None:
        self.recorder.set_bulk_stress(value)

    def increment_probe(self, pressure, traction_x, traction_y, plane=None) -> None:
        """One increment of the current cycle: its tractions (MPa) and, when the caller has
        evaluated it already, its stress plane (``StressField``, with the bulk stress)."""
        self.recorder.add(pressure, traction_x, traction_y)
        self.planes.append(plane)

    def _point_stress(self, increments):
        if self.grid.is_line:
            return LinePointStress(self.grid, self.poisson_ratio, increments)
        return PlanePointStress(self.grid, self.poisson_ratio, increments, self.angle)

    def finish_cycle(self, cycle: int) -> FatigueCycle:
        """Evaluate the increments collected since the last call as cycle ``cycle``."""
        increments, planes = self.recorder.take(), self.planes
        self.planes = []
        if all(plane is not None for plane in planes):
            history = planes_history(planes)
        else:
            history = plane_history(self.stress, increments, self.angle)
        config = self.config
        assessments = assess(
            history,
            self.criteria,
            method=config.method,
            length=config.length,
            stress_at=None if config.method == "hotspot" else self._point_stress(increments),
        )
        row: dict[str, float] = {}
        maps: dict[str, np.ndarray] = {}
        for assessment in assessments:
            row.update(assessment.summary())
            row[f"{assessment.column}_critical_x"] = assessment.surface.x
            if cycle in self.recorded:
                column, field_ = assessment.column, assessment.field
                maps[column] = assessment.map
                for suffix, values in (("angle", field_.angle), ("life", field_.life)):
                    if values is not None:
                        maps[f"{column}_{suffix}"] = values.reshape(assessment.shape)
        result = FatigueCycle(int(cycle), row, maps)
        self.cycles.append(result)
        return result

    def on_cycle(self, cycle: int, cycles: int) -> None:
        """After each simulated cycle (``CyclicAnalysis.run``'s ``on_cycle``): the increments
        collected, if any, are evaluated as cycle ``cycle``."""
        if self.recorder.increments:
            self.finish_cycle(cycle)

    # ------------------------------------------------------------------ results
    def summary_row(self) -> dict[str, Any]:
        """The last recorded cycle's columns (NaN before any)."""
        recorded = [c for c in self.cycles if c.cycle in self.recorded]
        if not recorded:
            return {column: math.nan for column in self.columns}
        return {column: recorded[-1].row[column] for column in self.columns}

    def history(self) -> dict[str, np.ndarray]:
        """Per evaluated cycle: ``cycle`` and every summary column (arrays)."""
        table = {"cycle": np.array([c.cycle for c in self.cycles], dtype=float)}
        for column in self.columns:
            table[column] = np.array([c.row[column] for c in self.cycles], dtype=float)
        return table

    def history_datasets(self, cycles) -> dict[str, DatasetRecord]:
        """``history/<column>`` per simulated cycle (``[fatigue] every_cycle``): the hot
        spots of every simulated cycle, aligned with the run's ``history/cycle``."""
        table = self.history()
        if not np.array_equal(table["cycle"], np.asarray(cycles, dtype=float)):
            raise RuntimeError(
                f"fatigue evaluated cycles {table['cycle'].tolist()} but the run simulated "
                f"{np.asarray(cycles).tolist()}"
            )
        specs = self._column_specs()
        return {
            case_group_path("history", column): DatasetRecord(
                table[column], specs[column].units, specs[column].description + _PER_CYCLE
            )
            for column in self.columns
        }

    def _column_specs(self) -> dict[str, DatasetSpec]:
        specs = {}
        for criterion in self.criteria:
            specs.update(fatigue_specs(*criterion_schema(criterion)))
        return specs

    def datasets(self) -> dict[str, DatasetRecord]:
        """``fatigue/cycle_NNNNNNN/*`` of every recorded cycle (``engine.schema.fatigue_maps``):
        each criterion's map, angles, lives and hot spot."""
        datasets = {}
        for result in self.cycles:
            if result.cycle not in self.recorded:
                continue
            group = cycle_group(result.cycle)
            for criterion in self.criteria:
                column, *described = criterion_schema(criterion)
                specs = fatigue_maps(column, *described, result.cycle)
                for name, spec in specs.items():
                    if name == f"{column}_hot_spot":
                        data = _hot_spot(result.row, column)
                    else:
                        data = result.maps[name]
                    datasets[case_group_path("fatigue", group, name)] = spec.record(data)
        return datasets

    # ------------------------------------------------------------------ checkpoints
    def arrays(self) -> dict[str, np.ndarray]:
        """The evaluated cycles as arrays (a checkpoint's ``fatigue_*`` entries)."""
        arrays = {
            "fatigue_cycles": np.array([c.cycle for c in self.cycles], dtype=np.int64),
            "fatigue_rows": np.array(
                [[c.row[k] for k in self._row_keys] for c in self.cycles], dtype=float
            ).reshape(len(self.cycles), len(self._row_keys)),
        }
        for result in self.cycles:
            for name, values in result.maps.items():
                arrays[f"fatigue_map_{result.cycle}_{name}"] = values
        return arrays

    def restore(self, arrays) -> None:
        """Take back the cycles of :meth:`arrays` (a resumed case)."""
        if "fatigue_cycles" not in arrays:
            return
        rows = np.asarray(arrays["fatigue_rows"], dtype=float)
        self.cycles = []
        for index, cycle in enumerate(np.asarray(arrays["fatigue_cycles"]).tolist()):
            prefix = f"fatigue_map_{cycle}_"
            maps = {
                name[len(prefix) :]: np.asarray(arrays[name])
                for name in arrays
                if name.startswith(prefix)
            }
            row = {k: float(v) for k, v in zip(self._row_keys, rows[index], strict=True)}
            self.cycles.append(FatigueCycle(int(cycle), row, maps))


def _hot_spot(row: dict[str, float], column: str) -> np.ndarray:
    """value, x, z, angle, life, critical of a criterion's hot spot (NaN where none)."""
    names = {"value": column, "critical": f"{column}_critical"}
    return np.array(
        [row.get(names.get(key, f"{column}_{key}"), math.nan) for key in FATIGUE_HOT_SPOT_COLUMNS],
        dtype=float,
    )
