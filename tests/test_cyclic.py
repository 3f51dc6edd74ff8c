"""Cyclic indentation with wear (the convergence of cycle jumping is in
test_cycle_jump_convergence.py)."""

import numpy as np
import pytest

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.solvers.contact import ContactSolver
from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
from engine.solvers.friction import FrictionLaw, WearLaw
from engine.study.checkpoint import load_cyclic_state, save_cyclic_state
from tests.conftest import RADIUS

LOAD = 750.0  # N, Section 7.2
WEAR = 1.33e-7  # 1/MPa, Section 7.2


def analysis(material, n, mu1, mu2, i1, i2, beta_deg, cycles, record, steps=5, tol=1e-6):
    grid = Grid.square(n, 1.05 * RADIUS)
    beta = np.radians(beta_deg)
    solver = ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(mu1, mu2, beta), tol=tol)
    settings = CyclicSettings(LOAD, steps, cycles, record=record)
    return CyclicAnalysis(solver, WearLaw(i1, i2, beta), settings)


@pytest.mark.validation
def test_wear_volume_is_the_sum_of_archard_increments(material, validation):
    """V = Σ_cycles ΔN Σ_increments Σ_elements i p |Δs| ΔA to round-off."""
    run = analysis(material, 24, 0.2, 0.2, WEAR, WEAR, 0, cycles=300, record=(10, 300))
    per_row: dict[int, float] = {}

    def audit(result, row):
        slip = np.hypot(result.slip_x, result.slip_y)
        volume = np.sum(WEAR * result.pressure * slip) * run.solver.grid.element_area
        per_row[row] = per_row.get(row, 0.0) + volume

    result = run.run(on_increment=audit)
    assert result.completed and result.converged, result.message
    jumps = result.history["jump"]
    expected = sum(jumps[row] * volume for row, volume in per_row.items())
    assert result.history["wear_volume"][-1] == pytest.approx(expected, rel=1e-12)
    assert expected > 0
    # The count lands exactly on the recorded and final cycles.
    assert {10, 300} <= set(result.history["cycle"].astype(int))
    assert sorted(result.records) == [10, 300]
    error = abs(result.history["wear_volume"][-1] / expected - 1)
    validation.record(
        "wear volume = Σ ΔN Σ i p |Δs| ΔA over cycles, increments, elements",
        "1e-12 rel. (round-off)", f"{error:.0e} rel.",
    )  # fmt: skip


@pytest.mark.validation
def test_wear_decreases_with_friction(material, validation):
    """Section 7.2 (P = 750 N, i = 1.33e-7 1/MPa, 32², 10⁵ cycles): maximum wear depth and
    wear volume decrease over μ = 0.1, 0.2, 0.4."""
    depth, volume = [], []
    for mu in (0.1, 0.2, 0.4):
        result = analysis(material, 32, mu, mu, WEAR, WEAR, 0, 100000, (1000, 100000)).run()
        assert result.completed and result.converged, result.message
        depth.append(result.history["max_wear_depth"][-1])
        volume.append(result.history["wear_volume"][-1])
    assert depth[0] > depth[1] > depth[2], depth
    assert volume[0] > volume[1] > volume[2], volume
    validation.record(
        "wear decreases with μ = 0.1, 0.2, 0.4 after 10⁵ cycles, 32²", "strictly",
        "depth " + ", ".join(f"{d * 1e3:.3f}" for d in depth) + " µm; volume "
        + ", ".join(f"{v:.1e}" for v in volume) + " mm³",
    )  # fmt: skip


@pytest.mark.validation
def test_orthotropic_wear_is_invariant_with_beta(material, validation):
    """Section 7.3 (μ1 = 0.1, μ2 = 0.4, i2 = i1 μ2/μ1, 32², 10⁴ cycles): maximum wear depth and wear
    volume agree within 3 % for β = 0, 45, 90°; the β = 90° wear field is the β = 0 field rotated by
    90° (to the solver tolerance)."""
    results = {}
    for beta in (0, 45, 90):
        run = analysis(material, 32, 0.1, 0.4, WEAR, 4 * WEAR, beta, 10000, (10000,))
        results[beta] = run.run()
        assert results[beta].completed and results[beta].converged, results[beta].message
    depth = np.array([results[b].history["max_wear_depth"][-1] for b in (0, 45, 90)])
    volume = np.array([results[b].history["wear_volume"][-1] for b in (0, 45, 90)])
    assert np.ptp(depth) / depth.mean() < 0.03, depth
    assert np.ptp(volume) / volume.mean() < 0.03, volume
    wear_0 = results[0].records[10000]["wear"]
    wear_90 = results[90].records[10000]["wear"]
    np.testing.assert_allclose(wear_90, np.rot90(wear_0, 1), atol=1e-5 * wear_0.max())
    # Not axisymmetric: the wear differs along e1 and e2.
    assert not np.allclose(wear_0, wear_0.T, atol=0.05 * wear_0.max())
    validation.record(
        "orthotropic (μ1 = 0.1, μ2 = 0.4, i2 = 4 i1), 32², 10⁴ cycles: invariance with "
        "β = 0, 45, 90°; β = 90° field = rotated β = 0° field", "3 % (cycle jumping)",
        f"depth spread {np.ptp(depth) / depth.mean():.2%}, volume spread "
        f"{np.ptp(volume) / volume.mean():.2%}",
    )  # fmt: skip


def test_save_interrupt_resume_gives_identical_histories(material, tmp_path):
    """Stop after two simulated cycles, save, load, resume."""
    settings = dict(
        n=24, mu1=0.2, mu2=0.2, i1=WEAR, i2=WEAR, beta_deg=0, cycles=2000, record=(100, 2000)
    )
    uninterrupted = analysis(material, **settings).run()
    calls = iter(range(100))
    first = analysis(material, **settings).run(should_stop=lambda: next(calls) >= 2)
    assert not first.completed
    path = tmp_path / "case.npz"
    save_cyclic_state(first.state, path)
    resumed = analysis(material, **settings).run(state=load_cyclic_state(path))
    assert resumed.completed
    for key, values in uninterrupted.history.items():
        np.testing.assert_array_equal(resumed.history[key], values, err_msg=key)
    for cycle, fields in uninterrupted.records.items():
        for key, value in fields.items():
            np.testing.assert_array_equal(resumed.records[cycle][key], value)
    # The checkpoint carries the step-size estimate: the resumed run does no extra work.
    assert resumed.matvecs == uninterrupted.matvecs


def test_record_beyond_cycles_is_rejected():
    with pytest.raises(ValueError, match="record cycle 2000"):
        CyclicSettings(LOAD, 5, 1000, record=(2000,))
