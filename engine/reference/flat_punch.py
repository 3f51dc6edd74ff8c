"""Analytic solutions for the rigid flat-ended cylindrical punch on an elastic half-space.

Surface results (Sneddon 1946; paper Eqs. 17–20):

- ``sneddon_pressure``: p(r) = P / (2π a0 √(a0² − r²)) for r < a0 (Eq. 17), MPa.
- ``sneddon_load``: P = 2 E* a0 g (Eq. 18), N.
- ``mossakovskii_ratio``: full-stick / frictionless stiffness = artanh(β)/β with Dundurs' β
  (Eq. 20 for a rigid punch: (1−ν) ln(3−4ν)/(1−2ν)).

Sign convention: pressure positive in compression; lengths mm, loads N, stresses MPa.
"""

from __future__ import annotations

import numpy as np

from .docstrings import documented

# The parameters several functions share, written once (numpydoc entries).
_R = "r : array_like\n    Distance from the punch axis (mm)."
_LOAD = "load : float\n    Normal load P (N)."
_RADIUS = "radius : float\n    Punch radius a0 (mm)."
_CONTACT_MODULUS = (
    "contact_modulus : float\n    Contact modulus E* = ((1 − ν_A²)/E_A + (1 − ν_B²)/E_B)⁻¹ (MPa)."
)
_POISSON = "poisson_ratio : float\n    Poisson's ratio of the half-space."


@documented(
    "numpy.ndarray\n"
    "    p(r) = P / (2π a0 √(a0² − r²)) for r < a0, 0 outside (MPa), shaped like ``r``.",
    _R,
    _LOAD,
    _RADIUS,
)
def sneddon_pressure(r: np.ndarray, load: float, radius: float) -> np.ndarray:
    """Frictionless contact pressure under a rigid flat punch (Sneddon; paper Eq. 17)."""
    r = np.asarray(r, dtype=float)
    inside = r < radius
    pressure = np.zeros_like(r)
    pressure[inside] = load / (2.0 * np.pi * radius * np.sqrt(radius**2 - r[inside] ** 2))
    return pressure


@documented(
    "float\n    Load P (N).",
    "approach : float\n    Rigid approach g (mm).",
    _RADIUS,
    _CONTACT_MODULUS,
)
def sneddon_load(approach: float, radius: float, contact_modulus: float) -> float:
    """Load of a frictionless rigid flat punch at a given approach: P = 2 E* a0 g (Eq. 18)."""
    return 2.0 * contact_modulus * radius * approach


@documented("float\n    Rigid approach g (mm).", _LOAD, _RADIUS, _CONTACT_MODULUS)
def sneddon_approach(load: float, radius: float, contact_modulus: float) -> float:
    """Approach of a frictionless rigid flat punch under a load: g = P / (2 E* a0)."""
    return load / (2.0 * contact_modulus * radius)


@documented("float\n    p0 (MPa).", _LOAD, _RADIUS)
def mean_pressure(load: float, radius: float) -> float:
    """Mean pressure p0 = P / (π a0²) (Eq. 19), the paper's stress scale."""
    return load / (np.pi * radius**2)


def mossakovskii_ratio(dundurs_beta: float) -> float:
    """Full-stick to frictionless normal stiffness ratio artanh(β)/β (Mossakovskii).

    For a rigid punch β = (1 − 2ν)/(2 − 2ν) and this equals Eq. (20).

    Parameters
    ----------
    dundurs_beta : float
        Dundurs' second parameter β of the material pair.

    Returns
    -------
    float
        The stiffness ratio (dimensionless), 1 at β = 0.
    """
    if dundurs_beta == 0.0:
        return 1.0
    return float(np.arctanh(dundurs_beta) / dundurs_beta)


def mossakovskii_ratio_rigid(poisson_ratio: float) -> float:
    """Eq. (20) as printed, for a rigid punch: (1 − ν) ln(3 − 4ν) / (1 − 2ν).

    Parameters
    ----------
    poisson_ratio : float
        Poisson's ratio ν of the half-space.

    Returns
    -------
    float
        The full-stick to frictionless stiffness ratio (dimensionless).
    """
    nu = poisson_ratio
    return (1.0 - nu) * np.log(3.0 - 4.0 * nu) / (1.0 - 2.0 * nu)


# --- Subsurface stresses of the frictionless punch (paper Appendix A) ---------------------------


@documented(
    "dict of str to numpy.ndarray\n"
    "    ``'rr', 'phiphi', 'zz', 'rz'``: the cylindrical stress components (MPa), compression\n"
    "    negative.",
    _R,
    "z : array_like\n    Depth into the half-space (mm, ≥ 0), broadcast with ``r``.",
    _LOAD,
    _RADIUS,
    _POISSON,
)
def flat_punch_stress(r, z, load: float, radius: float, poisson_ratio: float) -> dict:
    """Stresses under a frictionless rigid flat punch: paper Appendix A, Eqs. (A1)–(A7).

    With the corrections of the reference notes: in (A3) the square root covers only
    (a0² − l1²); in (A5) the term a0 z √(l2² − a0²)(2l1⁴ + r²(l1² + 3l2² − 6a0²)) /
    (l2²(l2² − l1²)³) is inside the bracket of σ2 with a plus sign. Verified against quadrature
    of the Boussinesq solution over the Sneddon pressure.

    Evaluation stays finite and accurate everywhere except the edge r = a0 at z = 0 (the
    singularity): with A = √((r + a0)² + z²), B = √((r − a0)² + z²), l1 = 2a0 r/(A + B),
    l2 = (A + B)/2, l2² − l1² = AB, and a0² − l1², l2² − a0² formed without cancellation; the
    (a0 − √(a0² − l1²))/r² term of (A5) is rewritten as (l1/r)²/(a0 + √(a0² − l1²)), finite on
    the axis r = 0. At z = 0 the z-terms take their limit 0.
    """
    a = float(radius)
    nu = float(poisson_ratio)
    r, z = np.broadcast_arrays(np.abs(np.asarray(r, dtype=float)), np.asarray(z, dtype=float))
    A = np.hypot(r + a, z)
    B = np.hypot(r - a, z)
    total = A + B
    l1 = 2.0 * a * r / total
    l2 = 0.5 * total
    l1_over_r_squared = (2.0 * a / total) ** 2
    # A − (r + a) + B − |r − a|, without cancellation
    excess = z * z / (A + r + a) + z * z / (B + np.abs(r - a))
    inner = a * a * (excess + 2.0 * np.maximum(a - r, 0.0)) * (total + 2.0 * r) / total**2
    outer = 0.5 * (excess + 2.0 * np.maximum(r - a, 0.0)) * (l2 + a)
    root_inner = np.sqrt(inner)  # √(a0² − l1²)
    root_outer = np.sqrt(outer)  # √(l2² − a0²)
    spread = A * B  # l2² − l1²
    c = load / (2.0 * np.pi * a)
    with np.errstate(divide="ignore", invalid="ignore"):
        z_term = np.where(
            z > 0.0,
            z
            * z
            * (l1**4 + a * a * (r * r - 2.0 * a * a - 2.0 * z * z))
            / (root_inner * spread**3),
            0.0,
        )
    sigma_zz = c * (-root_inner / spread + z_term)  # (A2)
    tau_rz = -c * z * r * root_inner * (3.0 * l2**2 + l1**2 - 4.0 * a * a) / spread**3  # (A3)
    sigma_1 = -c * ((1.0 + 2.0 * nu) * root_inner / spread + z_term)  # (A4)
    sigma_2 = -c * (  # (A5), corrected
        (1.0 - 2.0 * nu) * (root_inner / spread - 2.0 * l1_over_r_squared / (a + root_inner))
        + a
        * z
        * root_outer
        * (2.0 * l1**4 + r * r * (l1**2 + 3.0 * l2**2 - 6.0 * a * a))
        / (l2**2 * spread**3)
    )
    return {
        "rr": 0.5 * (sigma_1 + sigma_2),  # (A1)
        "phiphi": 0.5 * (sigma_1 - sigma_2),
        "zz": sigma_zz,
        "rz": tau_rz,
    }


def von_mises_cylindrical(stress: dict) -> np.ndarray:
    """Von Mises stress of an axisymmetric field, Eq. (21) as corrected in the notes.

    Parameters
    ----------
    stress : dict of str to numpy.ndarray
        ``'rr', 'phiphi', 'zz', 'rz'`` components (MPa), e.g. from :func:`flat_punch_stress`.

    Returns
    -------
    numpy.ndarray
        σ_VM = √(½[(σrr − σφφ)² + (σφφ − σzz)² + (σzz − σrr)² + 6τrz²]) (MPa).
    """
    rr, pp, zz, rz = stress["rr"], stress["phiphi"], stress["zz"], stress["rz"]
    return np.sqrt(0.5 * ((rr - pp) ** 2 + (pp - zz) ** 2 + (zz - rr) ** 2 + 6.0 * rz**2))


def sneddon_element_pressure(
    x_edges: np.ndarray, y_edges: np.ndarray, load: float, radius: float, order: int = 48
) -> np.ndarray:
    """Element-averaged Sneddon pressure (Eq. 17) on the rectangles between the given edges.

    The exact integral of p over each element divided by its area. The y-integral is done in
    closed form (arcsine), the x-integral by ``order``-point Gauss–Legendre in θ with
    x = a0 sin θ, which removes the square-root behaviour at x = ±a0.

    Parameters
    ----------
    x_edges : array_like
        Element edges along x (mm), increasing, n_x + 1 values.
    y_edges : array_like
        Element edges along y (mm), increasing, n_y + 1 values.
    load : float
        Normal load P (N).
    radius : float
        Punch radius a0 (mm).
    order : int
        Gauss–Legendre points of the x-integral.

    Returns
    -------
    numpy.ndarray
        Mean pressure of each element (MPa), shape (n_x, n_y); the total force equals ``load``
        when the elements cover the punch.
    """
    a = float(radius)
    x_edges = np.asarray(x_edges, dtype=float)
    y_edges = np.asarray(y_edges, dtype=float)
    nodes, weights = np.polynomial.legendre.leggauss(order)
    theta_edges = np.arcsin(np.clip(x_edges / a, -1.0, 1.0))
    lower, upper = theta_edges[:-1, None], theta_edges[1:, None]
    theta = 0.5 * (upper + lower) + 0.5 * (upper - lower) * nodes  # (n_x, order)
    dtheta = 0.5 * (upper - lower) * weights
    chord = a * np.cos(theta)  # half chord √(a0² − x²) at x = a0 sin θ
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.clip(y_edges[None, None, :] / chord[..., None], -1.0, 1.0)
    angle = np.where(chord[..., None] > 0.0, np.arcsin(ratio), 0.0)
    strip = np.diff(angle, axis=-1)  # ∫ dy / √(a0² − x² − y²) over each y-interval
    # dx = a0 cos θ dθ
    integral = np.einsum("ik,ikj->ij", dtheta * a * np.cos(theta), strip)
    area = np.diff(x_edges)[:, None] * np.diff(y_edges)[None, :]
    return load / (2.0 * np.pi * a) * integral / area
