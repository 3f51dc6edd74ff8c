"""``kind = "static"``: one loading to the load P in ``steps`` increments, no wear.

Datasets of a completed case: ``history/load`` (N) and ``history/approach`` (mm) per
increment (``engine.schema.STATIC_HISTORY``), the final surface fields, the case's grid and
the stress plane through the axis at the final state (:mod:`engine.study.outcome`).
"""

from __future__ import annotations

from engine.solvers.static import static_analysis
from engine.study.outcome import (
    COMPLETED,
    FAILED,
    CaseOutcome,
    final_fields,
    final_row,
    grid_datasets,
    history_datasets,
)
from engine.study.settings.compat import STATIC_PLACEHOLDERS

from .base import LoadingKind


class StaticKind(LoadingKind):
    """One loading (engine.solvers.static.static_analysis)."""

    name = "static"
    summary = "one loading to P in `steps` increments, no wear"

    def parse(self, s, load, steps):
        # the placeholders that results files of earlier versions stored: they parse back
        former = {key for key, value in STATIC_PLACEHOLDERS.items() if s.table.get(key) == value}
        s.check_known(self.keys | former)
        return self.config(self.name, load=load, steps=steps)

    def run(self, context, case, config, should_stop):
        solver, grid, material = context.solver(case, config)
        result = static_analysis(solver, config.loading.load, config.loading.steps)
        if not result.converged:
            return CaseOutcome(
                case, FAILED, message=f"static analysis did not converge: {result.message}"
            )
        history = {"load": result.loads, "approach": result.approaches}
        datasets = history_datasets(history, self.history_spec)
        datasets.update(final_fields(result.final))
        datasets.update(grid_datasets(grid))
        solver.operator.release_buffers()  # the plane's memory, not beside the transforms'
        stress, depths = context.subsurface(grid, material, config)
        row = final_row(case, config, result.final, stress, depths, datasets)
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
