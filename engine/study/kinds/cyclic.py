"""``kind = "cyclic"``: normal load cycles 0 → P → 0 with wear and cycle jumping (the
paper's Section 7.2; :mod:`engine.solvers.cyclic`).

Cyclic cases track the peak at every simulated cycle (:mod:`engine.solvers.peak`): the
history (``engine.schema.HISTORY``) gains the von Mises maxima (overall, below the surface
layer, at z >= 0.1 a0, on the axis), the contact radius, the centre pressure and the peak
region; the x–z plane at the first cycle and at every change of region is written under
``peak_changes/cycle_<N>/``. Every recorded cycle (``[loading] record`` and the last) stores
its surface fields (``fields/cycle_<N>/``) and stress plane (``subsurface/cycle_<N>/``).
"""

from __future__ import annotations

from engine import schema
from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
from engine.study import outcome
from engine.study.checkpoint import load_cyclic_state, save_cyclic_state
from engine.study.outcome import COMPLETED, FAILED, CaseOutcome

from .base import CycledKind


class CyclicKind(CycledKind):
    """Load cycles with wear (engine.solvers.cyclic.CyclicAnalysis)."""

    name = "cyclic"
    summary = (
        "normal (indentation) fretting: load cycles 0 → P → 0 with wear (the paper's Section 7.2)"
    )
    increments_per_step = 2  # loading and unloading half cycles
    history = (schema.HISTORY,)
    figures = "engine.analysis.figures:cyclic_figures"

    def describe(self, config, value):
        cycles = f"{value('cycles', config.loading.cycles, '', ',')} cycles"
        load = value("load", config.loading.load, config.punch.load_unit)
        return f"cyclic, P = {load}, {cycles}"

    def save_state(self, state, path):
        save_cyclic_state(state, path)

    def load_state(self, path):
        return load_cyclic_state(path)

    def run(self, context, case, config, should_stop):
        solver, grid, material = context.solver(case, config)
        wear_law = outcome.case_wear_law(case, config)  # [wear] law: Archard or energy
        settings = CyclicSettings(
            config.loading.load,
            config.loading.steps,
            config.loading.cycles,
            record=config.loading.record,
            max_wear_fraction=config.loading.max_wear_fraction,
        )
        stress, depths = context.subsurface(grid, material, config)
        tracker = outcome.peak_tracker(stress, config.contact_length)
        analysis = CyclicAnalysis(solver, wear_law, settings, peak_probe=tracker)
        checkpoint, state = self.checkpoint(context, case)
        on_cycle = context.on_cycle(case)
        result = analysis.run(state=state, should_stop=should_stop, on_cycle=on_cycle)
        if not result.completed:
            return self.interrupted(case, result.state, checkpoint)
        final = result.final
        if not result.converged:
            message = result.message or final.report.message
            return CaseOutcome(case, FAILED, message=f"cyclic analysis did not converge: {message}")

        datasets = outcome.history_datasets(result.history, self.history_spec)
        datasets.update(outcome.region_change_datasets(stress, result.state.region_changes))
        datasets.update(outcome.grid_datasets(grid))
        records = {cycle: dict(fields) for cycle, fields in result.records.items()}
        datasets.update(outcome.recorded_datasets(records, stress))
        datasets.update(outcome.final_fields(final))
        row = outcome.final_row(case, config, final, stress, depths, datasets)
        row.update(outcome.peak_row(tracker, final, result.history))
        row.update(outcome.totals_row(result, config))
        row.update(outcome.scar_row(case, config, grid, result))
        return CaseOutcome(case, COMPLETED, row=row, datasets=datasets)
