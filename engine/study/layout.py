"""Datasets of a completed case, known from the study before anything is computed.

Paths, units and descriptions are the results schema's (:mod:`engine.schema`); this module
adds the shapes and dtypes that follow from a case's configuration.

A collective (mpio) writer must create every dataset with identical arguments on all ranks
before any rank writes into it, so it needs, per case, the path, shape and dtype of what
:class:`~engine.study.case.CaseRunner` will produce. The layout of a case follows from its own
configuration (:meth:`StudyConfig.for_case`): sweeping ``mesh.n``, ``loading.cycles`` or
``subsurface.layers`` changes shapes from case to case (:func:`plan_layout`):

- ``grid/x``, ``grid/y``: the case's element centres, shape ``(n,)``, float64;

- ``fields/final/<name>`` (pressure, tractions, slip increments, status) and, for cyclic
  studies, ``fields/cycle_NNNNNNN/<name>`` (wear, pressure, tractions, status) for every
  recorded cycle (the solver also records the last cycle): surface fields, shape ``(n, n)``
  (ij indexing), float64; ``status`` is int8; the loading kind adds its own records to every
  recorded cycle (:meth:`~engine.study.kinds.LoadingKind.record_shapes`, e.g. a fretting
  cycle's ``loop`` and ``vm_cycle``);
- ``subsurface/final/*`` and ``subsurface/cycle_NNNNNNN/*``: the x–z plane through the punch
  axis, shape ``(n_s, n_z)``, float64. Its shape is taken from
  :meth:`~engine.solvers.subsurface.SubsurfaceStress.plane` evaluated once for zero tractions,
  so it cannot drift from the solver's sampling rule.

- ``fatigue/cycle_NNNNNNN/*`` (``[fatigue]``): every criterion's maps on the plane's shape
  and its hot spot (``engine.study.fatigue.fatigue_layout``).

Not in the layout: ``history/*`` (one entry per *simulated* cycle, whose number the adaptive
cycle jump decides at run time) and ``peak_changes/cycle_NNNNNNN/*`` (the x–z plane at each
change of the peak region, engine.solvers.peak: how many is known only at run time). They are
small and are written at the collective commit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from engine.schema import FIELD_DTYPES, FINAL_FIELDS, RECORDED_FIELDS, case_group_path, cycle_group
from engine.solvers.line_subsurface import LineSubsurfaceStress
from engine.solvers.subsurface import SubsurfaceStress, depth_layers
from engine.surface import surface_layout

from .config import StudyConfig
from .fatigue import fatigue_layout

__all__ = ["DatasetShape", "case_layout", "plan_layout", "recorded_cycles"]


@dataclass(frozen=True)
class DatasetShape:
    shape: tuple[int, ...]
    dtype: str


def recorded_cycles(config: StudyConfig) -> list[int]:
    """Cycles whose fields a completed case stores (kinds with cycles: the record list and
    the last)."""
    return config.kind.recorded_cycles(config)


def plan_layout(config: StudyConfig, plan) -> dict[str, dict[str, DatasetShape]]:
    """case_id -> :func:`case_layout` of the case's configuration (shared between cases
    with equal swept values). A search's combinations are laid out at the bracket's low end,
    as the plan validates them (a step's layout depends on the swept keys, not on the searched
    value)."""
    layouts: dict[tuple, dict[str, DatasetShape]] = {}
    result = {}
    for case in plan:
        if case.settings not in layouts:
            settings = config.at_search_end(case.settings)
            layouts[case.settings] = case_layout(config.for_case(settings))
        result[case.case_id] = layouts[case.settings]
    return result


def case_layout(config: StudyConfig) -> dict[str, DatasetShape]:
    """Path (relative to the case group) -> shape and dtype of every pre-creatable dataset
    of a case whose configuration is ``config``."""
    n_x, n_y = _grid(config).shape
    plane = _plane_layout(config)
    groups = {"final": FINAL_FIELDS}
    groups.update({cycle_group(c): RECORDED_FIELDS for c in recorded_cycles(config)})
    layout: dict[str, DatasetShape] = {
        case_group_path("grid", "x"): DatasetShape((n_x,), "float64"),
        case_group_path("grid", "y"): DatasetShape((n_y,), "float64"),
    }
    records = config.kind.record_shapes(config)  # the kind's own datasets of a recorded cycle
    for cycle in recorded_cycles(config):
        for name, (shape, dtype) in records.items():
            layout[case_group_path("fields", cycle_group(cycle), name)] = DatasetShape(shape, dtype)
    for group, names in groups.items():
        for name in names:
            dtype = FIELD_DTYPES.get(name, "float64")
            layout[case_group_path("fields", group, name)] = DatasetShape((n_x, n_y), dtype)
        for name, shape in plane.items():
            layout[case_group_path("subsurface", group, name)] = shape
    for path, (shape, dtype) in surface_layout(config).items():  # [surface]
        layout[path] = DatasetShape(shape, dtype)
    if config.fatigue is not None:  # the criteria's maps and hot spots of a recorded cycle
        for cycle in recorded_cycles(config):
            for name, shape in fatigue_layout(config.fatigue, plane["z"].shape).items():
                path = case_group_path("fatigue", cycle_group(cycle), name)
                layout[path] = DatasetShape(shape, "float64")
    return layout


def _grid(config: StudyConfig):
    return config.punch.profile().grid(config.mesh.n, config.mesh.half_width)


def _plane_layout(config: StudyConfig) -> dict[str, DatasetShape]:
    """Names and shapes of the x–z plane datasets (zero tractions: only shapes matter)."""
    grid = _grid(config)
    depths = np.asarray(
        depth_layers(config.subsurface.depth * config.contact_length, config.subsurface.layers),
        dtype=float,
    )
    # The study's planner effort: a timed plan here would leave FFTW wisdom that the cases'
    # estimate plans of the same lattice reuse, on this rank only.
    zero = np.zeros(grid.shape)
    if grid.is_line:
        plane = LineSubsurfaceStress(grid, config.material.nu_A, depths).plane(zero, zero)
    else:
        stress = SubsurfaceStress(
            grid, config.material.nu_A, depths, planner_effort=config.solver.planner_effort
        )
        plane = stress.plane(zero, zero, zero, angle=0.0)
    arrays = {"x": plane.x, "y": plane.y, "z": plane.z, "von_mises": plane.von_mises}
    arrays.update({f"sigma_{name}": values for name, values in plane.components.items()})
    return {
        name: DatasetShape(tuple(np.shape(values)), np.asarray(values).dtype.str.lstrip("<>="))
        for name, values in arrays.items()
    }


def layout_bytes(layout: dict[str, DatasetShape]) -> int:
    """Size of one case's pre-created data (bytes)."""
    return sum(math.prod(s.shape) * np.dtype(s.dtype).itemsize for s in layout.values())
