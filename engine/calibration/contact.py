"""One test at one value of the searched parameter: the contact solution, kept, and the
threshold column read from it for any values of the fatigue constants.

A fretting case is solved once (:func:`solve_cycle`: the engine's contact solver, wear law
and fretting analysis, exactly as ``kind = "fretting"`` runs them) and what the fatigue
criteria need of it is kept: the surface tractions (pressure, traction_x, traction_y in MPa
on the grid) and the bulk stress σ_B (MPa) of every increment of the last simulated cycle
(:class:`~engine.fatigue.fields.Increment`). The fatigue constants and the critical distance
do not change the contact solution, so a fit over them evaluates the criteria again on the
kept increments (:func:`criterion_value`: the stress history of the subsurface plane and at
the critical distance recomputed from the tractions, ``engine.study.fatigue.FatigueAnalysis``)
and never solves the contact again.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from engine.fatigue.fields import Increment
from engine.solvers.fretting import FrettingAnalysis
from engine.study.fatigue import FatigueAnalysis
from engine.study.kinds.fretting import check_force_bound, plane_angle, settings
from engine.study.outcome import case_wear_law

__all__ = ["ContactCycle", "solve_cycle", "criterion_value", "cycle_arrays", "cycle_from_arrays"]


@dataclass(frozen=True)
class ContactCycle:
    """The increments of the last simulated cycle of a solved case (tractions MPa on the
    grid, σ_B MPa), whether every solve converged, and why not."""

    increments: tuple[Increment, ...]
    converged: bool
    message: str = ""


def solve_cycle(context, case, config, should_stop=None) -> ContactCycle:
    """Solve the fretting case ``case`` of configuration ``config`` (its own, with the
    case's settings) on this process: the normal load, then ``[loading] cycles`` fretting
    cycles; returns the increments of the last one. ``context``: a
    :class:`~engine.study.outcome.CaseContext` (its operator cache is reused between calls).
    """
    if not config.is_fretting:
        raise ValueError('a calibration searches fretting cases ([loading] kind = "fretting")')
    solver, _, _ = context.solver(case, config)
    fretting = settings(config)
    check_force_bound(case, fretting, config.punch.load_unit)
    kept: list[Increment] = []
    last: list[list[Increment]] = [[]]
    bulk = [0.0]

    def increment_probe(pressure, traction_x, traction_y):
        copy = [np.array(value, dtype=float) for value in (pressure, traction_x, traction_y)]
        kept.append(Increment(*copy, bulk[0]))
        return (math.nan, math.nan, math.nan, math.nan)  # no σ_VM tracking here

    def on_cycle(cycle, cycles):
        if kept:
            last[0] = list(kept)
            kept.clear()

    analysis = FrettingAnalysis(
        solver, case_wear_law(case, config), fretting, increment_probe=increment_probe
    )
    if fretting.has_bulk_stress:

        def listener(value):
            bulk[0] = float(value)

        analysis.bulk_stress_listener = listener
    result = analysis.run(should_stop=should_stop or (lambda: False), on_cycle=on_cycle)
    if not result.completed:
        raise InterruptedError("stopped")
    return ContactCycle(tuple(last[0]), bool(result.converged), str(result.message or ""))


def criterion_value(context, case, config, cycle: ContactCycle, column: str) -> float:
    """The summary ``column`` of the ``[fatigue]`` criteria of ``config`` (its constants and
    critical distance) on the kept ``cycle`` of ``case``: the criteria evaluated as a case
    does on its last recorded cycle (``FatigueAnalysis.finish_cycle``), without solving the
    contact. NaN when the column is not one of the criteria's."""
    solver, grid, material = context.solver(case, config)
    angle_deg = plane_angle(config)
    stress, _ = context.subsurface(grid, material, config, angle_deg)
    analysis = FatigueAnalysis(
        config.fatigue,
        stress,
        grid,
        config.material.E_A,
        config.material.nu_A,
        math.radians(angle_deg),
        recorded=(1,),
    )
    for increment in cycle.increments:
        analysis.set_bulk_stress(increment.bulk_stress)
        analysis.increment_probe(increment.pressure, increment.traction_x, increment.traction_y)
    row = analysis.finish_cycle(1).row
    return float(row.get(column, math.nan))


def cycle_arrays(cycle: ContactCycle) -> dict[str, np.ndarray]:
    """The cycle as arrays (stored in the calibration's contact store): ``pressure``,
    ``traction_x``, ``traction_y`` (increments × grid shape, MPa), ``bulk_stress``
    (increments, MPa), ``converged`` (0/1)."""
    increments = cycle.increments

    def stack(name: str) -> np.ndarray:
        if not increments:  # a solve that failed before its last cycle
            return np.zeros((0,), dtype=float)
        return np.stack([getattr(increment, name) for increment in increments])

    return {
        "pressure": stack("pressure"),
        "traction_x": stack("traction_x"),
        "traction_y": stack("traction_y"),
        "bulk_stress": np.array([i.bulk_stress for i in increments], dtype=float),
        "converged": np.array([1 if cycle.converged else 0], dtype=np.int8),
        "message": np.array(cycle.message),
    }


def cycle_from_arrays(arrays) -> ContactCycle:
    """The inverse of :func:`cycle_arrays`."""
    message = str(arrays["message"]) if "message" in arrays else ""
    increments = tuple(
        Increment(
            np.asarray(arrays["pressure"][k], dtype=float),
            np.asarray(arrays["traction_x"][k], dtype=float),
            np.asarray(arrays["traction_y"][k], dtype=float),
            float(arrays["bulk_stress"][k]),
        )
        for k in range(len(arrays["bulk_stress"]))
    )
    return ContactCycle(increments, bool(int(np.asarray(arrays["converged"])[0])), message)
