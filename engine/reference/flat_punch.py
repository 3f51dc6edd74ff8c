"""Analytic solutions for the rigid flat-ended cylindrical punch on an elastic half-space.

Surface results (Sneddon 1946; paper Eqs. 17–20):
- ``sneddon_pressure``: p(r) = P / (2π a0 √(a0² − r²)) for r < a0 (Eq. 17), MPa.
- ``sneddon_load``: P = 2 E* a0 g (Eq. 18), N.
- ``mossakovskii_ratio``: full-stick / frictionless stiffness = artanh(β)/β with Dundurs' β
  (Eq. 20 for a rigid punch: (1−ν) ln(3−4ν)/(1−2ν)); NOTES.md.
Sign convention: pressure positive in compression; lengths mm, loads N, stresses MPa.
"""

from __future__ import annotations

import numpy as np


def sneddon_pressure(r: np.ndarray, load: float, radius: float) -> np.ndarray:
    """Frictionless contact pressure (MPa) at radius ``r`` (mm); zero outside the punch."""
    r = np.asarray(r, dtype=float)
    inside = r < radius
    pressure = np.zeros_like(r)
    pressure[inside] = load / (2.0 * np.pi * radius * np.sqrt(radius**2 - r[inside] ** 2))
    return pressure


def sneddon_load(approach: float, radius: float, contact_modulus: float) -> float:
    """Frictionless punch load (N) for a rigid approach ``approach`` (mm), Eq. (18)."""
    return 2.0 * contact_modulus * radius * approach


def sneddon_approach(load: float, radius: float, contact_modulus: float) -> float:
    """Frictionless rigid approach (mm) under ``load`` (N): g = P / (2 E* a0)."""
    return load / (2.0 * contact_modulus * radius)


def mean_pressure(load: float, radius: float) -> float:
    """p0 = P / (π a0²), MPa (Eq. 19)."""
    return load / (np.pi * radius**2)


def mossakovskii_ratio(dundurs_beta: float) -> float:
    """Full-stick to frictionless normal stiffness ratio, artanh(β)/β (Eq. 20 for β=(1−2ν)/(2−2ν))."""
    if dundurs_beta == 0.0:
        return 1.0
    return float(np.arctanh(dundurs_beta) / dundurs_beta)


def mossakovskii_ratio_rigid(poisson_ratio: float) -> float:
    """Eq. (20) as printed, for a rigid punch: (1−ν) ln(3−4ν) / (1−2ν)."""
    nu = poisson_ratio
    return (1.0 - nu) * np.log(3.0 - 4.0 * nu) / (1.0 - 2.0 * nu)
