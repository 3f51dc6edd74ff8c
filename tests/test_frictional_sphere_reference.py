"""The axisymmetric ring reference for the frictional Hertz problem
(engine.reference.frictional_sphere), checked before it is used against the engine
(tests/test_profiles.py): frictionless Hertz, the bonded flat punch (Mossakovskii) and
Spence's self-similarity under monotonic loading. Units: R = 1, compliance C = 2/E* = 1."""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine.material import MaterialPair
from engine.reference import frictional_sphere as rings
from engine.reference.flat_punch import mossakovskii_ratio

BETA = MaterialPair(200e3, 0.3, 200e5, 0.3).dundurs_beta  # 0.2801 (K = 0.196)


def test_kernels_match_the_bessel_integrals():
    """M₀, M₁ against their defining integrals ∫ J_ν(ξr) J_ν(ξs) dξ, done numerically with
    a convergence factor e^(−εξ), ε = 1e-3 (which shifts them by ~1e-4 relative)."""
    from scipy.integrate import quad
    from scipy.special import j0, j1

    for r, s in ((0.3, 0.7), (1.0, 0.5)):
        for kernel, bessel in ((rings._kernel_normal, j0), (rings._kernel_radial, j1)):

            def integrand(x, bessel=bessel, r=r, s=s):
                return bessel(x * r) * bessel(x * s) * math.exp(-1e-3 * x)

            numeric = quad(integrand, 0.0, 2000.0, limit=4000)[0]
            assert kernel(r, s).item() == pytest.approx(numeric, rel=5e-4)


def test_frictionless_rings_reproduce_hertz():
    """μ = 0: contact radius a = √(Rδ) = 1 to one ring (the edge is located to one ring);
    load 8/3 and p(0) = 4/π (per unit C) within 1e-4 (measured 1.4e-5 and 1.4e-5 at 120
    rings: piecewise-constant p against the square-root edge)."""
    result = rings.frictional_sphere_loading(0.0, 0.0, rings=120, increments=20)
    assert result.contact_radius == pytest.approx(1.0, abs=result.width)
    assert result.load == pytest.approx(rings.HERTZ_LOAD, rel=1e-4)
    assert result.pressure[0] == pytest.approx(4.0 / math.pi, rel=1e-4)


def test_bonded_flat_punch_gives_mossakovskii():
    """Full stick, rigid flat punch of radius 1 pressed in one step: stiffness ratio
    artanh(β)/β (Mossakovskii; 1.02745 for β = 0.2801). The error halves with the ring width
    (−6.9e-5, −3.5e-5, −1.7e-5 at 100, 200, 400 rings): 1e-4 at 200 rings. This checks the
    radial kernel M₁ and both coupling terms, which Hertz does not."""
    ratio = rings.flat_punch_full_stick(BETA, rings=200)
    assert ratio == pytest.approx(mossakovskii_ratio(BETA), abs=1e-4)
    assert ratio > 1.0


def test_stick_ratio_is_constant_under_monotonic_loading():
    """Spence (1975): under monotonic loading the stick radius grows in proportion to a.
    c/a at half and full approach agree to two rings (c is located to one ring, a to one)."""
    out = rings.spence_stick_ratio(BETA, 0.1, rings=240, increments=100)
    half = int(np.searchsorted(out["approach"], 0.25))  # δ = 1/4: a = 1/2
    tolerance = 2 * 1.2 / 240 / 0.5
    assert out["stick_ratio"][half] == pytest.approx(out["stick_ratio"][-1], abs=tolerance)
    # one central stick disc: no stick ring in the slip annulus
    assert out["stick_area_ratio"][-1] == pytest.approx(out["stick_ratio"][-1], rel=1e-12)
    assert 0.0 < out["stick_ratio"][-1] < 1.0
