"""Hertz's frictionless contact of a sphere (parabolic profile g = r²/(2R)) on a half-space.

Closed forms (Johnson, *Contact Mechanics*, 1985, Eqs. 4.22–4.23 and 3.45), with the contact
modulus E* = ((1−ν_A²)/E_A + (1−ν_B²)/E_B)⁻¹ (MPa), load P (N), sphere radius R (mm):

- contact radius a = (3 P R / (4 E*))^(1/3)                     (mm)
- approach       δ = a² / R                                     (mm)
- peak pressure  p_max = 3 P / (2 π a²) = 2 E* a / (π R)         (MPa)
- pressure       p(r) = p_max √(1 − r²/a²)
- stresses on the axis r = 0 at depth z (compression negative):
  σ_z = −p_max / (1 + z²/a²),
  σ_r = σ_θ = p_max [−(1 + ν)(1 − (z/a) arctan(a/z)) + 1 / (2 (1 + z²/a²))],
  σ_VM = abs(σ_r − σ_z) (two equal principal stresses).

For ν = 0.3 the axis σ_VM has its maximum 0.6200 p_max at z = 0.4809 a
(:func:`axis_von_mises_peak` finds it numerically for any ν).
With dissimilar materials (K ≠ 0) and no friction the normal problem is uncoupled from the
tangential one, so these formulas hold unchanged.
"""

from __future__ import annotations

import math

import numpy as np

from .docstrings import documented

__all__ = [
    "hertz_contact_radius",
    "hertz_approach",
    "hertz_peak_pressure",
    "hertz_pressure",
    "axis_stresses",
    "axis_von_mises",
    "axis_von_mises_peak",
]


# The parameters several functions share, written once (numpydoc entries).
_LOAD = "load : float\n    Normal load P (N)."
_RADIUS = "radius : float\n    Sphere radius R (mm)."
_CONTACT_MODULUS = (
    "contact_modulus : float\n    Contact modulus E* = ((1 − ν_A²)/E_A + (1 − ν_B²)/E_B)⁻¹ (MPa)."
)
_DEPTH = "z : array_like\n    Depth below the surface in units of the contact radius a (z > 0)."
_POISSON = "nu : float\n    Poisson's ratio of the half-space."


def _hertz(returns: str, *first: str):
    """Decorator: complete a one-line docstring with the Parameters section (``first``, the
    entries before the shared ones, then load, radius, contact modulus) and the Returns
    section ``returns`` ("type\n    description")."""
    return documented(returns, *first, _LOAD, _RADIUS, _CONTACT_MODULUS)


@_hertz("float\n    Contact radius a (mm).")
def hertz_contact_radius(load: float, radius: float, contact_modulus: float) -> float:
    """Hertz's contact radius a = (3 P R / (4 E*))^(1/3) (Johnson Eq. 4.22)."""
    return (3.0 * load * radius / (4.0 * contact_modulus)) ** (1.0 / 3.0)


@_hertz("float\n    Approach δ (mm).")
def hertz_approach(load: float, radius: float, contact_modulus: float) -> float:
    """Hertz's approach δ = a²/R of the two bodies' distant points (Johnson Eq. 4.23)."""
    return hertz_contact_radius(load, radius, contact_modulus) ** 2 / radius


@_hertz("float\n    Peak pressure p_max (MPa).")
def hertz_peak_pressure(load: float, radius: float, contact_modulus: float) -> float:
    """Hertz's peak pressure p_max = 3 P / (2 π a²) at the centre of the contact."""
    a = hertz_contact_radius(load, radius, contact_modulus)
    return 3.0 * load / (2.0 * math.pi * a**2)


@_hertz(
    "numpy.ndarray\n    Contact pressure (MPa), positive in compression, shaped like ``r``.",
    "r : array_like\n    Radial distance from the contact's centre (mm).",
)
def hertz_pressure(r: np.ndarray, load: float, radius: float, contact_modulus: float):
    """Hertz's pressure p(r) = p_max √(1 − r²/a²) inside the contact, 0 outside."""
    a = hertz_contact_radius(load, radius, contact_modulus)
    p_max = hertz_peak_pressure(load, radius, contact_modulus)
    r = np.asarray(r, dtype=float)
    return p_max * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))


@documented(
    "sigma_r : numpy.ndarray\n    Radial (and hoop) stress σ_r / p_max.\n"
    "sigma_z : numpy.ndarray\n    Normal stress σ_z / p_max.",
    _DEPTH,
    _POISSON,
)
def axis_stresses(z: np.ndarray, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Stresses on the axis r = 0 below a Hertzian contact (Johnson Eq. 3.45).

    σ_z = −1/(1 + z²), σ_r = σ_θ = −(1 + ν)(1 − z arctan(1/z)) + 1/(2(1 + z²)), in units of
    p_max with z in units of a; compression negative.
    """
    z = np.asarray(z, dtype=float)
    sigma_z = -1.0 / (1.0 + z**2)
    sigma_r = -(1.0 + nu) * (1.0 - z * np.arctan(1.0 / z)) + 0.5 / (1.0 + z**2)
    return sigma_r, sigma_z


@documented("numpy.ndarray\n    σ_VM / p_max, shaped like ``z``.", _DEPTH, _POISSON)
def axis_von_mises(z: np.ndarray, nu: float) -> np.ndarray:
    """Von Mises stress on the axis below a Hertzian contact, σ_VM = abs(σ_r − σ_z)."""
    sigma_r, sigma_z = axis_stresses(z, nu)
    return np.abs(sigma_r - sigma_z)


@documented("peak : float\n    max σ_VM / p_max.\ndepth : float\n    Its depth z / a.", _POISSON)
def axis_von_mises_peak(nu: float) -> tuple[float, float]:
    """The largest von Mises stress on the axis and its depth, found to 1e-10 by bounded search.

    For ν = 0.3: 0.6200 p_max at z = 0.4809 a.
    """
    from scipy.optimize import minimize_scalar  # here: SciPy's import costs 0.4 s

    result = minimize_scalar(
        lambda z: -float(axis_von_mises(z, nu)),
        bounds=(0.05, 2.0),
        method="bounded",
        options={"xatol": 1e-10},
    )
    return float(-result.fun), float(result.x)
