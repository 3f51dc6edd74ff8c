"""Frictionless axisymmetric contact of any smooth punch profile (Sneddon's integrals).

For a rigid-equivalent punch of profile f(r) (f(0) = 0, mm) on a half-space of contact modulus
E* (MPa) whose contact is a disc of radius a with bounded pressure at its edge (Sneddon,
*Int. J. Eng. Sci.* 3, 1965; the same route Ciavarella, Hills & Monno, *Proc. IMechE C* 212,
1998, take for the rounded flat punch):

    h(t) = t ∫₀^{π/2} f'(t sin θ) dθ                       (Abel transform of f')
    δ    = h(a)                                            (approach, bounded-edge condition)
    P    = 2 E* (a δ − ∫₀^a h(t) dt)                        (load, N)
    p(r) = (E*/π) ∫_r^a h'(t) / √(t² − r²) dt,   h'(t) = ∫₀^{π/2} [f'(t s) + t s f''(t s)] dθ,
                                                              s = sin θ

All integrals are done by Gauss–Legendre quadrature on panels split where f' has a kink, and
the 1/√(t − r) singularity of p is removed by t = r + u². Checks: the Hertz sphere (f = r²/2R)
gives a, δ, p of :mod:`engine.reference.hertz` to ~1e-12; the rounded punch tends to the flat
punch as ρ → 0 (tests/test_profiles.py).

This is an independent check of the FFT boundary-element solver: no grid, no influence matrix.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["AxisymmetricContact", "rounded_punch_contact", "sphere_contact"]

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(96)


def _gauss(function: Callable[[np.ndarray], np.ndarray], lower, upper, panels: int = 8):
    """∫ function over [lower, upper] by composite 96-point Gauss–Legendre; ``lower`` and
    ``upper`` may be arrays (one integral per entry, evaluated in one vectorised call)."""
    lower, upper = np.broadcast_arrays(np.asarray(lower, float), np.asarray(upper, float))
    width = np.clip(upper - lower, 0.0, None)
    total = np.zeros(lower.shape)
    for panel in range(panels):
        left = lower + width * panel / panels
        half = 0.5 * width / panels
        points = left[..., None] + half[..., None] * (_NODES + 1.0)
        total += half * (function(points) @ _WEIGHTS)
    return total


@dataclass(frozen=True)
class AxisymmetricContact:
    """Profile slope ``slope(r)`` = f'(r) and curvature ``curvature(r)`` = f''(r) (vectorised,
    r in mm); ``flat_radius`` b: f' = 0 for r ≤ b (a kink of f' at b is then handled exactly);
    ``outer_radius``: where the profile ends; ``contact_modulus`` E* (MPa)."""

    slope: Callable[[np.ndarray], np.ndarray]
    curvature: Callable[[np.ndarray], np.ndarray]
    contact_modulus: float
    flat_radius: float = 0.0
    outer_radius: float = math.inf

    def _theta_start(self, t: np.ndarray) -> np.ndarray:
        """θ below which t sin θ ≤ b (where f' = 0): arcsin(b/t), π/2 for t ≤ b."""
        ratio = np.where(t > self.flat_radius, self.flat_radius / np.maximum(t, 1e-300), 1.0)
        return np.arcsin(np.clip(ratio, 0.0, 1.0))

    def h(self, t):
        """h(t) = t ∫ f'(t sin θ) dθ (mm); ``t`` scalar or array."""
        t = np.asarray(t, dtype=float)
        scale = t[..., None] if t.ndim else t
        integral = _gauss(
            lambda th: self.slope(scale * np.sin(th)), self._theta_start(t), math.pi / 2
        )
        return t * integral

    def h_prime(self, t):
        """dh/dt (dimensionless); ``t`` scalar or array."""
        t = np.asarray(t, dtype=float)

        def integrand(th):
            x = (t[..., None] if t.ndim else t) * np.sin(th)
            return self.slope(x) + x * self.curvature(x)

        return _gauss(integrand, self._theta_start(t), math.pi / 2)

    def approach(self, a: float) -> float:
        """δ(a) = h(a), mm."""
        return float(self.h(a))

    def load(self, a: float) -> float:
        """P(a) = 2 E* (a h(a) − ∫₀^a h dt), N (h = 0 below the flat radius)."""
        start = min(self.flat_radius, a)
        integral = float(_gauss(self.h, start, a, panels=8))
        return 2.0 * self.contact_modulus * (a * float(self.h(a)) - integral)

    def contact_radius(self, load: float) -> float:
        """a such that P(a) = ``load`` (Brent's root bracketing), mm."""
        lower = self.flat_radius * (1.0 + 1e-12) if self.flat_radius > 0 else 1e-9
        upper = min(self.outer_radius * (1.0 - 1e-9), 1e3 * max(self.flat_radius, 1.0))
        from scipy.optimize import brentq  # here: SciPy's import costs 0.4 s

        return brentq(lambda a: self.load(a) - load, lower, upper, xtol=1e-14, rtol=1e-13)

    def pressure(self, r: float, a: float) -> float:
        """p(r) for contact radius a (MPa); 0 for r ≥ a."""
        if r >= a:
            return 0.0
        start = math.sqrt(max(self.flat_radius - r, 0.0))  # h' = 0 below the flat radius
        end = math.sqrt(a - r)

        def integrand(u):
            return self.h_prime(r + u**2) * 2.0 / np.sqrt(2.0 * r + u**2)

        return self.contact_modulus / math.pi * float(_gauss(integrand, start, end, panels=4))

    def pressures(self, radii, a: float) -> np.ndarray:
        """p at each of ``radii`` (MPa)."""
        return np.array([self.pressure(float(r), a) for r in np.ravel(radii)]).reshape(
            np.shape(radii)
        )


def rounded_punch_contact(
    radius: float, edge_radius: float, contact_modulus: float
) -> AxisymmetricContact:
    """Flat face of radius b = ``radius`` with a toroidal edge of radius ρ = ``edge_radius``."""
    b, rho = radius, edge_radius

    def slope(x):
        s = np.clip(np.asarray(x, dtype=float) - b, 0.0, None)
        return s / np.sqrt(rho**2 - s**2)

    def curvature(x):
        s = np.asarray(x, dtype=float) - b
        return np.where(s > 0.0, rho**2 / (rho**2 - np.clip(s, 0.0, None) ** 2) ** 1.5, 0.0)

    return AxisymmetricContact(slope, curvature, contact_modulus, b, b + rho)


def sphere_contact(radius: float, contact_modulus: float) -> AxisymmetricContact:
    """Parabolic sphere f = r²/(2R): reproduces Hertz (a self-check of the quadrature)."""
    return AxisymmetricContact(
        lambda x: np.asarray(x, dtype=float) / radius,
        lambda x: np.full(np.shape(x), 1.0 / radius),
        contact_modulus,
    )
