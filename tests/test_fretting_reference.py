"""The closed forms a profile hands out for fretting (``Profile.fretting_reference``, an
``engine.reference.masing.FrettingReference``): the sphere's equal Mindlin's functions to
round-off (1e-12); the numerical defaults (the area of the Masing loop, the bisection
inverse) equal the closed forms to 5e-6 (trapezoidal rule over ENERGY_POINTS per branch:
measured ≤ 1.5e-6, at the slip boundary) and 1e-12; a profile without closed forms hands
out None."""

from __future__ import annotations

import numpy as np
import pytest

from engine.geometry import profile_for
from engine.material import MaterialPair
from engine.reference import line_contact, masing, mindlin

STEEL = MaterialPair(210e3, 0.3, 210e3, 0.3)
SPHERE = (100.0, 12.7, STEEL, 0.6)  # N, mm, materials, μ
CYLINDER = (185.0, 6.0, STEEL.contact_modulus, 0.5, 10.0)  # N/mm, mm, MPa, μ, datum mm


def test_the_sphere_reference_is_mindlin():
    reference = profile_for("sphere", radius=12.7).fretting_reference(100.0, STEEL, 0.6, None)
    slip = float(mindlin.slip_displacement(*SPHERE))
    assert reference.slip_displacement == pytest.approx(slip, rel=1e-12)
    for ratio in (0.3, 0.9, 1.5):
        amplitude = ratio * slip
        exact = float(mindlin.energy_per_cycle(amplitude, *SPHERE))
        assert reference.energy_per_cycle(amplitude) == pytest.approx(exact, rel=1e-12)
        assert reference.energy_ratio(amplitude) == pytest.approx(
            float(mindlin.energy_ratio(ratio)), rel=1e-12
        )


@pytest.mark.parametrize("name", ["sphere", "cylinder"])
def test_numerical_defaults_equal_the_closed_forms(name):
    if name == "sphere":
        closed = mindlin.fretting_reference(*SPHERE)
    else:
        closed = line_contact.line_fretting_reference(*CYLINDER)
    numerical = masing.FrettingReference("numerical", closed.virgin, closed.limit)
    for ratio in (0.3, 0.9, 1.0, 1.5):
        amplitude = ratio * closed.slip_displacement
        assert numerical.force_amplitude(amplitude) == pytest.approx(
            closed.force_amplitude(amplitude), rel=1e-12
        )
        assert numerical.energy_per_cycle(amplitude) == pytest.approx(
            closed.energy_per_cycle(amplitude), rel=5e-6
        )


def test_the_sampled_loops_converge_to_the_closed_form():
    """Sampled at many increments, the analytic loop's area is the closed-form energy (1e-5:
    the trapezoidal rule over 2,001 points per branch)."""
    reference = line_contact.line_fretting_reference(*CYLINDER)
    gross = 2.0 * reference.slip_displacement
    delta, _ = reference.loop(displacement_amplitude=gross, points=2001)
    assert reference.sampled_loop_energy(delta, gross) == pytest.approx(
        reference.energy_per_cycle(gross), rel=1e-5
    )
    amplitude = 0.5 * reference.limit
    _, force = reference.loop(force_amplitude=amplitude, points=2001)
    assert reference.sampled_force_loop_energy(force, amplitude) == pytest.approx(
        reference.partial_slip_energy(amplitude), rel=1e-5
    )


def test_the_cylinder_slip_boundary_is_its_closed_form():
    loads = np.array([100.0, 200.0])
    boundary = profile_for("cylinder", radius=6.0).slip_displacement(loads, STEEL, 0.5, 10.0)
    expected = line_contact.line_slip_displacement(loads, 6.0, STEEL.contact_modulus, 0.5, 10.0)
    np.testing.assert_allclose(boundary, expected, rtol=1e-12)
