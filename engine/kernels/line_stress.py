"""Plane-strain stresses in a half-plane under uniform strip tractions (the x–z plane).

The 2-D counterpart of ``engine.kernels.stress``. A line load on the surface of the half-plane
z > 0 (Flamant; Johnson 1985, Eqs. 2.15 and 2.21), with X = x − s, r² = X² + z²:

    normal load P (compressive):   σ_xx = −(2P/π) X² z/r⁴,  σ_zz = −(2P/π) z³/r⁴,
                                   σ_xz = −(2P/π) X z²/r⁴
    tangential load Q (along +x):  σ_xx = −(2Q/π) X³/r⁴,    σ_zz = −(2Q/π) X z²/r⁴,
                                   σ_xz = −(2Q/π) X² z/r⁴

A uniform traction over the element s1 ≤ s ≤ s2 integrates exactly with X = z tan φ
(φ = arctan(X/z) ∈ (−π/2, π/2)): the antiderivatives in X are

    z³/r⁴ → φ/2 + sin 2φ/4,   X² z/r⁴ → φ/2 − sin 2φ/4,   X z²/r⁴ → sin² φ/2,
    X³/r⁴ → ln(r/z) − sin² φ/2,

taken between X1 = x − s1 and X2 = x − s2. Conventions as the package's: tension positive,
``pressure`` ≥ 0 pushes into the half-plane (σ_zz → −p at the surface), ``traction_x`` acts on
its surface along +x (σ_xz → −q at the surface). Plane strain adds σ_yy = ν(σ_xx + σ_zz)
(ν of the half-plane, the flat); σ_xy = σ_yz = 0. The stresses do not depend on the elastic
constants otherwise. Depths must be > 0 (the surface values of piecewise constant tractions
jump at element edges; the ln(r/z) term is singular there).
"""

from __future__ import annotations

import numpy as np

__all__ = ["strip_stress_coefficients"]


def _antiderivatives(offset: np.ndarray, depth: np.ndarray) -> dict[str, np.ndarray]:
    """The four antiderivatives of the module docstring at X = ``offset``, z = ``depth``."""
    phi = np.arctan2(offset, depth)
    sin2 = np.sin(2.0 * phi)
    sin_squared = np.sin(phi) ** 2
    return {
        "zzz": 0.5 * phi + 0.25 * sin2,
        "xxz": 0.5 * phi - 0.25 * sin2,
        "xzz": 0.5 * sin_squared,
        "xxx": 0.5 * np.log1p((offset / depth) ** 2) - 0.5 * sin_squared,
    }


def strip_stress_coefficients(offset, depth, width: float) -> dict[str, dict[str, np.ndarray]]:
    """Stress (MPa) at a point at horizontal ``offset`` X (mm, point minus element centre) and
    ``depth`` z > 0 (mm) per unit traction (1 MPa) on an element of ``width`` Δx (mm).

    Returns ``{"pressure": {"xx", "zz", "xz"}, "traction_x": {"xx", "zz", "xz"}}`` arrays of
    the broadcast shape of ``offset`` and ``depth``; σ_yy follows from plane strain.
    """
    offset, depth = np.broadcast_arrays(np.asarray(offset, float), np.asarray(depth, float))
    if np.any(depth <= 0.0):
        raise ValueError("depths must be > 0 (mm) for the strip stress coefficients")
    near = _antiderivatives(offset + 0.5 * width, depth)  # X1 = x − s1
    far = _antiderivatives(offset - 0.5 * width, depth)  # X2 = x − s2
    integral = {key: near[key] - far[key] for key in near}
    scale = -2.0 / np.pi
    return {
        "pressure": {
            "xx": scale * integral["xxz"],
            "zz": scale * integral["zzz"],
            "xz": scale * integral["xzz"],
        },
        "traction_x": {
            "xx": scale * integral["xxx"],
            "zz": scale * integral["xzz"],
            "xz": scale * integral["xxz"],
        },
    }
