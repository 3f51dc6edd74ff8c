"""The normal CG (``engine.solvers.normal``) on a worn, conforming line contact, and its
stall guard.

``tests/data/mccoll_512_worn.npz`` holds an input on which the constrained CG used to cycle
for ever: ``wear`` (mm, the sum of both bodies' wear) of the 512-element, max_wear_fraction
0.004 case of ``studies/mccoll_2004_convergence.toml`` after about 9,000 cycles (13.9 µm
deep, an element-scale ripple of a few tens of nm on its bottom), and ``pressure`` (MPa), the
iterate the alternation handed to its third normal pass at the first increment that failed.
With the unpreconditioned re-entry p = −α g the contact set went round a cycle of period 4
(165–195 elements, the relative residual between 4e-4 and 3e-3) until the increment's
20,000 iterations were spent. Cylinder R = 6 mm, P = 185 N/mm, steel on steel (K = 0, so
the frictional increment's normal block is this problem exactly).
"""

from pathlib import Path

import numpy as np
import pytest

from engine.geometry import CylinderProfile
from engine.grid import Grid
from engine.kernels.line import LineOperator
from engine.material import MaterialPair
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw
from engine.solvers.normal import STALL_ITERATIONS, solve_normal

STEEL = MaterialPair(200e3, 0.3, 200e3, 0.3)
RADIUS, LOAD, DATUM = 6.0, 185.0, 10.0  # mm, N/mm, mm
WORN = Path(__file__).parent / "data" / "mccoll_512_worn.npz"


def _worn_problem():
    data = np.load(WORN)
    grid = Grid.line(data["wear"].size, 1.0)
    operator = LineOperator(grid, STEEL, DATUM)
    gap = CylinderProfile(RADIUS).gap(grid)
    return operator, np.isfinite(gap), gap + data["wear"][:, None], data["pressure"][:, None]


def test_worn_conforming_contact_converges_from_the_stalled_start():
    operator, candidate, offset, start = _worn_problem()
    tol = 1e-8
    warm = solve_normal(operator, candidate, LOAD, start, offset, tol=tol, maxiter=1000)
    assert warm.converged and not warm.stalled, (warm.iterations, warm.residual)
    # 28 iterations here; the bound only says "no cycling" (it was 20,000 without an end).
    assert warm.iterations <= 60
    # The answer, checked from its definition rather than from the solver's own residual.
    grid = operator.grid
    assert warm.pressure.sum() * grid.element_area == pytest.approx(LOAD, rel=1e-12)
    gap = operator.apply_normal(warm.pressure) + offset - warm.approach
    contact = warm.pressure > 0.0
    assert np.all(warm.pressure >= 0.0)
    assert np.abs(gap[contact]).max() <= 10 * tol * warm.approach  # RMS ≤ tol: max ≤ 10 tol
    assert gap[candidate & ~contact].min() >= -10 * tol * warm.approach
    # The problem is strictly convex (A positive definite): a cold start reaches the same
    # pressure, to the tolerance (measured 9e-6 of the peak at tol 1e-8).
    cold = solve_normal(
        operator, candidate, LOAD, np.zeros(grid.shape), offset, tol=tol, maxiter=1000
    )
    assert cold.converged
    assert np.array_equal(cold.pressure > 0.0, contact)
    assert np.abs(cold.pressure - warm.pressure).max() <= 1e-4 * warm.pressure.max()


class _NoPreconditioner:
    """A preconditioner that returns nothing: the CG has no direction and cannot move."""

    def normal(self, residual, out=None):
        if out is None:
            return np.zeros_like(residual)
        out[...] = 0.0
        return out

    def tangential(self, rx, ry):
        return np.zeros_like(rx), np.zeros_like(ry)


class _BlindOperator(LineOperator):
    @property
    def preconditioner(self):
        return _NoPreconditioner()


def _blind_hertz(n=128):
    grid = Grid.line(n, 0.25)  # ±2.2 a (Hertz a = 0.113 mm)
    return grid, _BlindOperator(grid, STEEL, DATUM)


def test_a_solve_without_progress_stops_and_says_it_stalled():
    grid, operator = _blind_hertz()
    gap = CylinderProfile(RADIUS).gap(grid)
    start = np.zeros(grid.shape)
    solution = solve_normal(operator, np.isfinite(gap), LOAD, start, gap, tol=1e-8, maxiter=20000)
    assert solution.stalled and not solution.converged
    # The first residual is the best one; STALL_ITERATIONS more without a better one.
    assert solution.iterations == STALL_ITERATIONS + 1


@pytest.mark.parametrize("mu", [0.0, 0.5])
def test_a_stalled_normal_solve_is_finished_by_the_projected_gradient(mu):
    """Frictionless and frictional load control both hand a stalled CG to FISTA, which
    needs no preconditioner; its answer is the Hertz line contact's (the residual is the
    coupled natural residual of every method, checked against the tolerance)."""
    grid, operator = _blind_hertz()
    profile = CylinderProfile(RADIUS)
    solver = ContactSolver(grid, STEEL, profile, FrictionLaw(mu, mu), operator=operator, tol=1e-6)
    result = solver.solve_load(LOAD)
    report = result.report
    assert report.converged, report.message
    assert "stalled" in report.message and "projected gradient" in report.message
    assert result.load == pytest.approx(LOAD, rel=1e-9)
    reference = ContactSolver(
        grid, STEEL, profile, FrictionLaw(mu, mu), operator=LineOperator(grid, STEEL, DATUM)
    ).solve_load(LOAD)
    assert np.abs(result.pressure - reference.pressure).max() <= 1e-3 * reference.pressure.max()
