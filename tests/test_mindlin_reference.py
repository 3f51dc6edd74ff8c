"""Analytic identities of the Cattaneo–Mindlin / Mindlin–Deresiewicz references (fast)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from engine.material import MaterialPair
from engine.reference import masing, mindlin
from engine.reference.hertz import hertz_contact_radius

STEEL = MaterialPair(E_A=210000.0, nu_A=0.3, E_B=210000.0, nu_B=0.3)
MIXED = MaterialPair(E_A=210000.0, nu_A=0.3, E_B=110000.0, nu_B=0.34)
LOAD, RADIUS, MU = 100.0, 10.0, 0.6
ARGS = (LOAD, RADIUS, STEEL, MU)


def test_compliance_sum_is_eq6_combination():
    """S = Σ(2 − ν_i)/G_i equals 2(2 − ν)/G with the paper's Eq. 6 combinations (1e-14:
    rounding only)."""
    for pair in (STEEL, MIXED):
        combined = 2.0 * (2.0 - pair.poisson_ratio) / pair.shear_modulus
        assert mindlin.compliance_sum(pair) == pytest.approx(combined, rel=1e-14)


def test_slip_displacement_closed_form_and_load_scaling():
    """δ_slip = 3μP S/(16a), and ∝ P^{2/3} since a ∝ P^{1/3} (1e-12: rounding)."""
    a = hertz_contact_radius(LOAD, RADIUS, STEEL.contact_modulus)
    expected = 3 * MU * LOAD * mindlin.compliance_sum(STEEL) / (16 * a)
    assert mindlin.slip_displacement(*ARGS) == pytest.approx(expected, rel=1e-12)
    loads = np.array([10.0, 80.0, 640.0])
    slips = mindlin.slip_displacement(loads, RADIUS, STEEL, MU)
    assert slips[1:] / slips[:-1] == pytest.approx([4.0, 4.0], rel=1e-12)


def test_monotone_curve_limits_and_inverse():
    """δ(0) = 0, δ(μP) = δ_slip, initial stiffness 8a/S (1e-6: finite difference), Q(δ(Q)) = Q."""
    slip = mindlin.slip_displacement(*ARGS)
    limit = MU * LOAD
    assert mindlin.tangential_displacement(0.0, *ARGS) == 0.0
    assert mindlin.tangential_displacement(limit, *ARGS) == pytest.approx(slip, rel=1e-14)
    # initial stiffness dQ/dδ = 3μP/(2δ_slip) = 8a/S (Mindlin's 8Ga/(2−ν) per body)
    small = 1e-7 * limit
    stiffness = small / mindlin.tangential_displacement(small, *ARGS)
    a = hertz_contact_radius(LOAD, RADIUS, STEEL.contact_modulus)
    assert stiffness == pytest.approx(8 * a / mindlin.compliance_sum(STEEL), rel=1e-6)
    forces = np.linspace(0.0, limit, 11)
    back = mindlin.tangential_force(mindlin.tangential_displacement(forces, *ARGS), *ARGS)
    assert back == pytest.approx(forces, rel=1e-12, abs=1e-12 * limit)
    assert mindlin.tangential_force(3 * slip, *ARGS) == limit


def test_stick_radius():
    """c/a = (1 − Q/μP)^{1/3}: 1 unloaded, 0 at sliding, 0.5 at Q = 7μP/8."""
    ratios = mindlin.stick_radius_ratio(np.array([0.0, 7 / 8, 1.0]) * MU * LOAD, LOAD, MU)
    assert ratios == pytest.approx([1.0, 0.5, 0.0], abs=1e-12)
    with pytest.raises(ValueError):
        mindlin.stick_radius_ratio(1.1 * MU * LOAD, LOAD, MU)


def _numerical_loop_energy(amplitude):
    """∫_{−Q*}^{Q*} (δ_unload(Q) − δ_reload(Q)) dQ, δ_reload(Q) = −δ_unload(−Q) (Masing)."""

    def width(force):
        unload = mindlin.unloading_displacement(force, amplitude, *ARGS)
        reload = -mindlin.unloading_displacement(-force, amplitude, *ARGS)
        return float(unload - reload)

    value, _ = quad(width, -amplitude, amplitude, epsabs=0.0, epsrel=1e-12, limit=200)
    return value


@pytest.mark.parametrize("q", [0.05, 0.3, 0.7, 0.95, 1.0])
def test_closed_form_energy_matches_integrated_masing_loop(q):
    """The closed form W(Q*) against adaptive quadrature of the branches (1e-9: quadrature)."""
    amplitude = q * MU * LOAD
    closed = mindlin.partial_slip_energy(amplitude, *ARGS)
    assert closed == pytest.approx(_numerical_loop_energy(amplitude), rel=1e-9)


def test_energy_small_amplitude_limit_is_cubic():
    """W → S Q*³/(36 a μP) as Q*/μP → 0: relative error O(q), 1.5e-3 at q = 1e-3."""
    for q in (1e-3, 1e-2):
        amplitude = q * MU * LOAD
        exact = mindlin.partial_slip_energy(amplitude, *ARGS)
        approx = mindlin.partial_slip_energy_small_amplitude(amplitude, *ARGS)
        assert exact == pytest.approx(approx, rel=1.5 * q)


def test_energy_ratio_at_gross_slip_onset_is_one_fifth():
    """At Q* = μP the loop area is 0.8 μP δ_slip: W/(4δ*Q*) = 0.2 (Fouvry's transition)."""
    slip = mindlin.slip_displacement(*ARGS)
    energy = mindlin.partial_slip_energy(MU * LOAD, *ARGS)
    assert energy / (4 * slip * MU * LOAD) == pytest.approx(0.2, rel=1e-12)


def test_energy_continuous_at_slip_boundary_and_linear_beyond():
    """W(δ*) is continuous at δ_slip (1e-9: the 1 ± 1e-10 offsets) and grows by 4μP per mm."""
    slip = mindlin.slip_displacement(*ARGS)
    below = mindlin.energy_per_cycle(slip * (1 - 1e-10), *ARGS)
    above = mindlin.energy_per_cycle(slip * (1 + 1e-10), *ARGS)
    assert below == pytest.approx(above, rel=1e-9)
    slope = (
        mindlin.energy_per_cycle(3 * slip, *ARGS) - mindlin.energy_per_cycle(2 * slip, *ARGS)
    ) / slip
    assert slope == pytest.approx(4 * MU * LOAD, rel=1e-12)
    with pytest.raises(ValueError):
        mindlin.gross_slip_energy(0.5 * slip, *ARGS)


def _shoelace(displacement, force):
    """|∮ Q dδ| of a closed polygon (mJ)."""
    return 0.5 * abs(np.sum(displacement[:-1] * force[1:] - displacement[1:] * force[:-1]))


@pytest.mark.parametrize("factor", [0.3, 0.8, 1.0, 2.5])
def test_loop_polygon_area_matches_energy(factor):
    """The drawn loop encloses W (5e-5 at 2001 points per branch: polygon of a smooth curve)
    and passes through (±δ*, ±Q*)."""
    slip = mindlin.slip_displacement(*ARGS)
    amplitude = factor * slip
    displacement, force = mindlin.fretting_loop(
        *ARGS, displacement_amplitude=amplitude, points=2001
    )
    assert displacement[0] == pytest.approx(amplitude, rel=1e-12)
    assert displacement.min() == pytest.approx(-amplitude, rel=1e-12)
    assert force[0] == pytest.approx(mindlin.force_amplitude(amplitude, *ARGS), rel=1e-12)
    assert (displacement[-1], force[-1]) == (displacement[0], force[0])
    expected = mindlin.energy_per_cycle(amplitude, *ARGS)
    assert _shoelace(displacement, force) == pytest.approx(expected, rel=5e-5)


def test_force_controlled_loop_and_argument_check():
    """A force-amplitude loop peaks at δ(Q*); one of the two amplitudes must be given."""
    amplitude = 0.5 * MU * LOAD
    displacement, force = mindlin.fretting_loop(*ARGS, force_amplitude=amplitude)
    assert force.max() == pytest.approx(amplitude)
    assert displacement.max() == pytest.approx(
        mindlin.tangential_displacement(amplitude, *ARGS), rel=1e-12
    )
    with pytest.raises(ValueError):
        mindlin.fretting_loop(*ARGS)


def test_loop_by_numerical_inverse_matches_the_closed_form_inverse():
    """masing.fretting_loop without the closed-form Q(δ) (Brent's root of δ(Q) = δ*) draws
    the sphere's loop to 1e-12 of μP and δ_slip (Brent's xtol, 2e-12 N on μP = 60 N, and
    rounding; measured: identical); at δ* ≥ δ_slip both give Q* = μP."""
    limit = MU * LOAD
    slip = mindlin.slip_displacement(*ARGS)

    def virgin(force):
        return mindlin.tangential_displacement(force, *ARGS)

    for amplitude in (0.4 * slip, 1.7 * slip):
        exact = mindlin.fretting_loop(*ARGS, displacement_amplitude=amplitude)
        numerical = masing.fretting_loop(virgin, limit, displacement_amplitude=amplitude)
        np.testing.assert_allclose(numerical[0], exact[0], rtol=0, atol=1e-12 * slip)
        np.testing.assert_allclose(numerical[1], exact[1], rtol=0, atol=1e-12 * limit)
    assert exact[1][0] == numerical[1][0] == limit


def test_energy_ratio_master_curve():
    """A(δ*/δ_slip) = W/(4δ*Q*) agrees with the dimensional functions at two loads (1e-12:
    rounding), is 0.2 at the boundary from both sides, rises monotonically, tends to 1."""
    x = np.array([0.05, 0.3, 0.7, 1.0, 1.5, 4.0, 50.0])
    for load in (20.0, 400.0):
        args = (load, RADIUS, MIXED, MU)
        amplitude = x * mindlin.slip_displacement(*args)
        energy = mindlin.energy_per_cycle(amplitude, *args)
        force = mindlin.force_amplitude(amplitude, *args)
        assert mindlin.energy_ratio(x) == pytest.approx(energy / (4 * amplitude * force), rel=1e-12)
    assert mindlin.energy_ratio([1 - 1e-9, 1.0, 1 + 1e-9]) == pytest.approx([0.2] * 3, rel=1e-6)
    assert np.all(np.diff(mindlin.energy_ratio(np.geomspace(1e-3, 1e3, 200))) > 0)
    assert mindlin.energy_ratio(1e6) == pytest.approx(1.0, abs=1e-6)
