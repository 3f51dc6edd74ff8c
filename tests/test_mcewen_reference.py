"""McEwen's closed-form line-contact field: tractions, equilibrium and the known facts (fast)."""

from __future__ import annotations

import numpy as np
import pytest

from engine.reference import line_contact, mcewen

A, P0, MU, NU = 0.5, 600.0, 0.6, 0.3  # half-width mm, peak pressure MPa, friction, Poisson


def _partial_slip(bulk=0.0, ratio=0.6):
    return mcewen.partial_slip_tractions(A, P0, MU, ratio, bulk_stress=bulk)


def test_surface_stresses_equal_the_tractions():
    """At z = 0 inside the contact σ_zz = −p, σ_xz = −q, and outside both vanish (1e-9 p0:
    rounding of the closed forms; the edges are excluded, where m = n = 0)."""
    tractions = _partial_slip(bulk=80.0)
    x = np.linspace(-1.5 * A, 1.5 * A, 301)
    x = x[np.abs(np.abs(x) - A) > 1e-9]
    field = mcewen.line_contact_stress(x, 0.0, tractions, NU)
    assert np.allclose(field.zz, -tractions.pressure_at(x), atol=1e-9 * P0)
    assert np.allclose(field.xz, -tractions.shear_at(x), atol=1e-9 * P0)
    assert np.allclose(field.yy, NU * (field.xx + field.zz), atol=1e-12 * P0)


def test_frictionless_maximum_shear():
    """The principal shear of the frictionless Hertz line contact peaks at 0.300 p0 at
    z = 0.786 a on the axis (Johnson 1985, §4.2: 0.30 p0 at 0.78 a); tolerances are the
    quoted digits (the sampling step is 1e-4 a)."""
    z = np.linspace(1e-4, 2.0, 20000) * A
    field = mcewen.line_contact_stress(0.0, z, mcewen.sliding_tractions(A, P0, 0.0), NU)
    shear = np.hypot(0.5 * (field.xx - field.zz), field.xz)
    peak = int(np.argmax(shear))
    assert shear[peak] / P0 == pytest.approx(0.3003, abs=5e-4)
    assert z[peak] / A == pytest.approx(0.786, abs=2e-3)
    assert field.xx[0] == pytest.approx(-P0, rel=1e-3)  # σ_xx = σ_zz = −p0 at the surface


def test_sliding_trailing_edge_tension():
    """Full sliding (q = μp in +x): σ_xx = +2μp0 of tension at the trailing edge x = −a and
    −2μp0 at the leading edge x = +a (Johnson 1985, Eq. 7.19b; 1e-9: rounding), and
    σ_xx = −p(x) − 2μp0 x/a inside the contact."""
    tractions = mcewen.sliding_tractions(A, P0, MU)
    edges = mcewen.line_contact_stress(np.array([-A, A]), 0.0, tractions, NU)
    assert edges.xx == pytest.approx([2 * MU * P0, -2 * MU * P0], rel=1e-9)
    x = np.linspace(-0.9, 0.9, 7) * A
    inside = mcewen.line_contact_stress(x, 0.0, tractions, NU)
    expected = -tractions.pressure_at(x) - 2 * MU * P0 * x / A
    assert np.allclose(inside.xx, expected, atol=1e-9 * P0)


@pytest.mark.parametrize("bulk", [0.0, 120.0])
def test_equilibrium_by_finite_differences(bulk):
    """∂σ_xx/∂x + ∂σ_xz/∂z = 0 and ∂σ_xz/∂x + ∂σ_zz/∂z = 0 at points in and around the
    contact of a partial-slip traction with a shifted stick zone (central differences with
    h = 1e-5 a: truncation ~h² and rounding ~1e-16/h, both below 1e-5 p0/a)."""
    rng = np.random.default_rng(7)
    x = rng.uniform(-2.0, 2.0, 200) * A
    z = rng.uniform(0.02, 1.5, 200) * A
    tractions = _partial_slip(bulk=bulk)
    h = 1e-5 * A

    def field(dx, dz):
        return mcewen.line_contact_stress(x + dx, z + dz, tractions, NU)

    d_dx = [(p - m) / (2 * h) for p, m in zip(_xz(field(h, 0)), _xz(field(-h, 0)), strict=True)]
    d_dz = [(p - m) / (2 * h) for p, m in zip(_xz(field(0, h)), _xz(field(0, -h)), strict=True)]
    tolerance = 1e-5 * P0 / A
    assert np.max(np.abs(d_dx[0] + d_dz[2])) < tolerance
    assert np.max(np.abs(d_dx[2] + d_dz[1])) < tolerance


def _xz(field):
    return field.xx, field.zz, field.xz


def test_partial_slip_traction_matches_line_reference():
    """The partial-slip shear (with the Nowell & Hills offset) equals the independent
    ``engine.reference.line_contact.nowell_hills_traction`` (1e-10: rounding). Hertz: P in
    N/mm from a and p0 with E* and R chosen so that a = 0.5 mm, p0 = 600 MPa."""
    modulus = 115000.0
    radius = A * modulus / (2 * P0)
    load = np.pi * A * P0 / 2
    x = np.linspace(-A, A, 201)
    for bulk in (0.0, 60.0):
        offset = bulk * A / (4 * MU * P0)
        reference = line_contact.nowell_hills_traction(
            x, 0.6 * MU * load, load, radius, modulus, MU, offset=offset
        )
        ours = _partial_slip(bulk=bulk, ratio=0.6).shear_at(x)
        assert np.allclose(ours, reference, atol=1e-10 * P0)


def test_fretting_cycle_force_and_coulomb_bound():
    """Along the steady cycle the resultant ∫q dx equals Q = (Q/Q*) T μP (each term
    integrates to A π b/2 exactly; 1e-12 relative), |q| ≤ μp everywhere (Coulomb; 1e-9 p0),
    and the branches meet at the reversal points (the cycle closes)."""
    load = np.pi * A * P0 / 2
    ratio = 0.7
    forces, unloading = mcewen.fretting_cycle_forces(16)
    cycle = mcewen.FrettingCycle(A, P0, MU, ratio, bulk_mean=30.0, bulk_amplitude=50.0)
    x = np.linspace(-A, A, 4001)
    for force, unload in zip(forces, unloading, strict=True):
        tractions = cycle.tractions(ratio * force, bool(unload))
        resultant = sum(t.amplitude * np.pi * t.half_width / 2 for t in tractions.shear)
        assert resultant == pytest.approx(ratio * force * MU * load, rel=1e-12, abs=1e-9)
        assert np.all(np.abs(tractions.shear_at(x)) <= MU * tractions.pressure_at(x) + 1e-9 * P0)
        assert tractions.bulk_stress == pytest.approx(30.0 + 50.0 * force)
    bottom = [cycle.tractions(-ratio, unload).shear_at(x) for unload in (True, False)]
    assert np.allclose(bottom[0], bottom[1], atol=1e-9 * P0)


def test_fretting_cycle_stress_shapes_and_stick_slip():
    """The history has shape (instants, points); in the stick zone of the reversal state the
    surface traction is below μp, in the slip zones equal to μp (1e-9 p0)."""
    x = np.linspace(-A, A, 11)
    history = mcewen.FrettingCycle(A, P0, MU, 0.5).stress(x, 0.0, NU, instants=8)
    assert history.xx.shape == (8, 11)
    shear, pressure = -history.xz[0], -history.zz[0]
    stick = np.abs(x) < A * np.sqrt(0.5) - 1e-9
    assert np.all(shear[stick] < MU * pressure[stick])
    assert np.allclose(shear[~stick], MU * pressure[~stick], atol=1e-9 * P0)


def test_bulk_stress_too_large_for_partial_slip_is_refused():
    with pytest.raises(ValueError, match="exceeds the contact half-width"):
        _partial_slip(bulk=4 * MU * P0, ratio=0.1)
