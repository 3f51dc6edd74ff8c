"""Static analysis (Section 7.1): load the punch from 0 to P in equal increments.

Each increment starts from the previous one's tractions and displacements, so friction is
path dependent exactly as in the cyclic analysis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..validation import require_non_negative
from .contact import ContactSolver, IncrementResult


@dataclass
class StaticResult:
    """``final``: the increment at full load; ``loads`` (N) and ``approaches`` (mm) per step;
    totals of iterations and operator applications; converged only if every step did."""

    final: IncrementResult
    loads: np.ndarray
    approaches: np.ndarray
    iterations: int
    matvecs: int
    converged: bool
    message: str

    @property
    def stiffness(self) -> float:
        """k_n = P / g_n,o at full load (N/mm)."""
        return self.final.load / self.final.approach


def static_analysis(solver: ContactSolver, load: float, steps: int) -> StaticResult:
    """Load from 0 to ``load`` (N) in ``steps`` equal increments; returns a ``StaticResult``."""
    load = require_non_negative("load", load)
    if isinstance(steps, bool) or int(steps) != steps or steps < 1:
        raise ValueError(f"steps must be a positive integer, got {steps!r}")
    state = solver.initial_state()
    results = []
    for step in range(1, int(steps) + 1):
        result = solver.solve_load(load * step / steps, state)
        results.append(result)
        state = result.state
    reports = [r.report for r in results]
    failed = [i + 1 for i, report in enumerate(reports) if not report.converged]
    message = (
        f"{steps} increments converged"
        if not failed
        else f"increments {failed} did not converge: {reports[failed[0] - 1].message}"
    )
    return StaticResult(
        final=results[-1],
        loads=np.array([r.load for r in results]),
        approaches=np.array([r.approach for r in results]),
        iterations=sum(report.iterations for report in reports),
        matvecs=sum(report.matvecs for report in reports),
        converged=not failed,
        message=message,
    )
