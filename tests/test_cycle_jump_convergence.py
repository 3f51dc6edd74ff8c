"""Cycle-jump convergence for μ = 0.2.

The default settings (10 increments per half cycle, wear per jump ≤ 0.004 of the elastic
approach) are checked against halving the wear allowed per jump and against doubling the
increments, with the default solve path (each increment starts from the extrapolated
increments of the previous simulated cycles, ``CyclicSettings.warm_start``):

- 64², i = 1.33e-7 1/MPa, N = 10⁴. Measured: max wear depth 1.1 % and 1.0 %, wear volume
  0.25 % and 0.4 % (the former path, every increment from the previous one: 1.2 %, 1.2 %,
  0.25 %, 0.4 %).
- 32², i = 30 × 1.33e-7 1/MPa (the regime study's large wear coefficients), N = 3000:
  the same check with about 9× the wear of the first case, so the gap changes much more
  over the run (32² to keep the test short). Measured: depth 0.5 % and 1.5 %, volume
  0.2 % and 0.2 %; at 64² with the new path: N = 3000,
  depth 0.5 % and 1.4 %, volume 0.2 % and 0.5 %; N = 10⁴, depth 0.3 % and 1.6 %, volume
  0.15 % and 1.6 %.

Tolerance 2 %: the first-order error of the explicit cycle jump at these settings.
"""

import numpy as np
import pytest

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.solvers.contact import ContactSolver
from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
from engine.solvers.friction import FrictionLaw, WearLaw
from tests.conftest import RADIUS

WEAR = 1.33e-7
# wear coefficient (1/MPa), real cycles, elements per side
CASES = {"wear x1": (WEAR, 10000, 64), "wear x30": (30 * WEAR, 3000, 32)}


def settings(cycles, **options):
    steps = options.pop("steps", 10)
    return CyclicSettings(750.0, steps, cycles, record=(1000, cycles), **options)


def final_wear(material, wear, n, settings):
    grid = Grid.square(n, 1.05 * RADIUS)
    solver = ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(0.2, 0.2), tol=1e-6)
    result = CyclicAnalysis(solver, WearLaw(wear, wear), settings).run()
    assert result.completed and result.converged, result.message
    history = result.history
    return history["max_wear_depth"][-1], history["wear_volume"][-1], len(history["cycle"])


_REFERENCES: dict[str, tuple] = {}


def reference(material, case):
    if case not in _REFERENCES:
        wear, cycles, n = CASES[case]
        _REFERENCES[case] = final_wear(material, wear, n, settings(cycles))
    return _REFERENCES[case]


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize(
    "refinement",
    [{"max_wear_fraction": 0.002}, {"steps": 20}],
    ids=["half-wear-per-jump", "double-increments"],
)
@pytest.mark.validation
def test_cycle_jumping_converges(material, case, refinement, validation):
    depth, volume, simulated = reference(material, case)
    wear, cycles, n = CASES[case]
    fine_depth, fine_volume, fine_simulated = final_wear(
        material, wear, n, settings(cycles, **refinement)
    )
    print(
        f"{case}: depth {depth:.4e} -> {fine_depth:.4e}, volume {volume:.4e} -> "
        f"{fine_volume:.4e}, simulated cycles {simulated} -> {fine_simulated}"
    )
    # The wear criterion binds: the halved fraction needs more simulated cycles.
    if "max_wear_fraction" in refinement:
        assert fine_simulated > simulated
    assert abs(fine_depth / depth - 1) < 0.02
    assert abs(fine_volume / volume - 1) < 0.02
    assert np.isfinite(depth) and depth > 0
    change = (
        "halve the wear per jump" if "max_wear_fraction" in refinement else "double the increments"
    )
    validation.record(
        f"cycle jumping, {case}: {change}", "2 % on depth and volume",
        f"depth {fine_depth / depth - 1:+.2%}, volume {fine_volume / volume - 1:+.2%}",
    )  # fmt: skip
