"""Westergaard's frictionless contact of a sinusoidal wave on an elastic half-space.

The periodic profile h(x) = Δ cos(2πx/λ) (amplitude Δ, wavelength λ, mm) pressed onto a flat
elastic half-space in plane strain by the mean pressure p̄ (MPa) (Westergaard, J. Appl. Mech.
6 (1939) A49; Johnson, *Contact Mechanics*, 1985, §13.2, Eqs. 13.6–13.8), with the contact
modulus E* (MPa):

- full contact at p* = π E* Δ / λ                                 (MPa)
- contact half-width a of each spot: p̄ = p* sin²(π a / λ)        (mm)
- contact fraction 2a/λ = (2/π) arcsin √(p̄/p*)
- pressure p(x) = 2 p̄ cos(πx/λ) √(sin²(πa/λ) − sin²(πx/λ)) / sin²(πa/λ), |x| ≤ a
  (x measured from the crest)
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["full_contact_pressure", "contact_fraction", "westergaard_pressure"]


def full_contact_pressure(amplitude: float, wavelength: float, contact_modulus: float) -> float:
    """p* = π E* Δ/λ (MPa): the mean pressure that flattens the wave."""
    return math.pi * contact_modulus * amplitude / wavelength


def contact_fraction(mean_pressure, full_pressure: float):
    """2a/λ = (2/π) arcsin √(p̄/p*) (1), for p̄ ≤ p* (1 beyond)."""
    ratio = np.minimum(np.asarray(mean_pressure, dtype=float) / full_pressure, 1.0)
    return 2.0 / math.pi * np.arcsin(np.sqrt(ratio))


def westergaard_pressure(x, mean_pressure: float, full_pressure: float, wavelength: float):
    """p(x) (MPa) at the distance ``x`` (mm) from a crest, periodic in λ; 0 out of contact."""
    x = np.asarray(x, dtype=float)
    edge = math.sin(math.pi * float(contact_fraction(mean_pressure, full_pressure)) / 2.0) ** 2
    phase = np.sin(math.pi * x / wavelength) ** 2
    inside = phase < edge
    root = np.sqrt(np.where(inside, edge - phase, 0.0))
    return np.where(
        inside, 2.0 * mean_pressure * np.abs(np.cos(math.pi * x / wavelength)) * root / edge, 0.0
    )
