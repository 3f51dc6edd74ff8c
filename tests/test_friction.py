"""Orthotropic friction cone (Eqs. 9–11, NOTES.md) and wear norm (Eq. 13): exact identities."""

import numpy as np
import pytest

from engine.solvers.friction import FrictionLaw, WearLaw, from_tribological, to_tribological

RNG = np.random.default_rng(7)


def test_rotation_round_trip_and_axes():
    vx, vy = RNG.standard_normal(50), RNG.standard_normal(50)
    beta = 0.7
    back = from_tribological(beta, *to_tribological(beta, vx, vy))
    np.testing.assert_allclose(back, (vx, vy), atol=1e-15)
    # Eq. (11): e1 is x rotated by beta.
    e1 = to_tribological(beta, np.cos(beta), np.sin(beta))
    np.testing.assert_allclose(e1, (1.0, 0.0), atol=1e-15)


@pytest.mark.parametrize("beta", [0.0, np.pi / 4, 1.1])
def test_radial_return_lands_on_cone_and_keeps_direction(beta):
    law = FrictionLaw(0.1, 0.4, beta)
    tx, ty = 5 * RNG.standard_normal(200), 5 * RNG.standard_normal(200)
    bound = np.abs(RNG.standard_normal(200))
    qx, qy = law.radial_return(tx, ty, bound)
    outside = law.norm(tx, ty) > bound
    # On the cone to round-off where the trial was outside, untouched inside (Eq. 9).
    np.testing.assert_allclose(law.norm(qx, qy)[outside], bound[outside], rtol=1e-14)
    np.testing.assert_array_equal(qx[~outside], tx[~outside])
    # Same direction: the cross product vanishes and the dot product is positive.
    np.testing.assert_allclose(qx * ty - qy * tx, 0.0, atol=1e-12)
    assert np.all(qx * tx + qy * ty >= 0)


@pytest.mark.parametrize("beta", [0.0, 0.3, np.pi / 2])
def test_euclidean_projection_on_ellipse_satisfies_optimality(beta):
    """Closest point q of the ellipse ||q||_μ ≤ ρ to t: q on the boundary and t − q along the
    outward normal M⁻² q (in tribological axes), with a non-negative multiplier."""
    law = FrictionLaw(0.1, 0.4, beta)
    tx, ty = 3 * RNG.standard_normal(300), 3 * RNG.standard_normal(300)
    bound = np.abs(RNG.standard_normal(300)) + 0.1
    qx, qy = law.project(tx, ty, bound)
    outside = law.norm(tx, ty) > bound
    np.testing.assert_allclose(law.norm(qx, qy)[outside], bound[outside], rtol=1e-12)
    q1, q2 = to_tribological(beta, qx, qy)
    d1, d2 = to_tribological(beta, tx - qx, ty - qy)
    n1, n2 = q1 / law.mu1**2, q2 / law.mu2**2
    np.testing.assert_allclose((d1 * n2 - d2 * n1)[outside], 0.0, atol=1e-10)
    assert np.all((d1 * n1 + d2 * n2)[outside] > 0)
    # A brute-force check of minimality on the boundary for a few points.
    angles = np.linspace(0, 2 * np.pi, 20001)
    for k in np.flatnonzero(outside)[:5]:
        p1 = law.mu1 * bound[k] * np.cos(angles)
        p2 = law.mu2 * bound[k] * np.sin(angles)
        px, py = from_tribological(beta, p1, p2)
        best = np.min(np.hypot(px - tx[k], py - ty[k]))
        assert np.hypot(qx[k] - tx[k], qy[k] - ty[k]) <= best + 1e-9


@pytest.mark.parametrize("scale", [1e-9, 1e-4, 1e-2])
def test_projection_is_exact_far_outside_the_ellipse(scale):
    """Trials 1e9 times the bound (tiny bounds, as at the edge of contact): the Newton
    iteration starts from a lower bound of the multiplier and still lands on the ellipse to
    round-off with t − q along the outward normal."""
    law = FrictionLaw(0.1, 0.4, 0.3)
    tx, ty = RNG.standard_normal(300), RNG.standard_normal(300)
    bound = scale * (np.abs(RNG.standard_normal(300)) + 0.1)
    qx, qy = law.project(tx, ty, bound)
    np.testing.assert_allclose(law.norm(qx, qy), bound, rtol=1e-12)
    q1, q2 = to_tribological(0.3, qx, qy)
    d1, d2 = to_tribological(0.3, tx - qx, ty - qy)
    n1, n2 = q1 / law.mu1**2, q2 / law.mu2**2
    sine = (d1 * n2 - d2 * n1) / (np.hypot(d1, d2) * np.hypot(n1, n2))
    np.testing.assert_allclose(sine, 0.0, atol=1e-9)


def test_isotropic_projection_is_radial_return():
    law = FrictionLaw(0.3, 0.3, 0.4)
    tx, ty = RNG.standard_normal(20), RNG.standard_normal(20)
    bound = np.full(20, 0.1)
    np.testing.assert_allclose(law.project(tx, ty, bound), law.radial_return(tx, ty, bound))


def test_wear_norm_is_orthotropic():
    law = WearLaw(1.0e-7, 4.0e-7, np.pi / 2)
    # Along x (= -e2 direction for beta = 90 deg) the wear coefficient is i2.
    assert law.norm(np.array(2.0), np.array(0.0)) == pytest.approx(8.0e-7)
    assert law.norm(np.array(0.0), np.array(2.0)) == pytest.approx(2.0e-7)
    assert law.depth_increment(np.array(10.0), np.array(0.0), np.array(1.0)) == pytest.approx(
        1.0e-6
    )


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"mu1": -0.1, "mu2": 0.1}, "mu1"),
        ({"mu1": 0.1, "mu2": float("nan")}, "mu2"),
        ({"mu1": 0.1, "mu2": 0.0}, "mu2"),
    ],
)
def test_bad_friction_raises_naming_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        FrictionLaw(**kwargs)
