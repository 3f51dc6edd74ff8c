"""Closed forms of plane-strain line contact: a cylinder, or a rounded flat pad, on a flat.

Everything is per unit length along the axis y: loads P, Q in N/mm, energies in N·mm/mm,
pressures and tractions in MPa, lengths in mm. E* = ((1−ν_A²)/E_A + (1−ν_B²)/E_B)⁻¹ (MPa) is
the contact modulus. The tangential formulas assume uncoupled normal and tangential problems
(K = 0, e.g. identical elastic bodies); with K ≠ 0 they are approximations.

- **Hertz** (Johnson 1985, Eqs. 4.43–4.45), cylinder of radius R, profile x²/(2R):
  a = √(4PR/(πE*)), p0 = 2P/(πa) = aE*/(2R), p(x) = p0 √(1 − x²/a²).
- **Cattaneo–Mindlin for the cylinder** (Johnson §7.1; Hills & Nowell 1994, Ch. 4): a
  tangential force 0 → Q < μP leaves a central stick zone of half-width
  c = a √(1 − Q/(μP)) and the traction
  q(x) = μp0 √(1 − x²/a²) − μp0 (c/a) √(1 − x²/c²) (the second term only for |x| < c).
- **Mindlin–Deresiewicz loop for the cylinder** (derived here by the Masing construction, as
  for the sphere in ``engine.reference.mindlin``): in the stick zone the relative tangential
  displacement of an elliptic traction q0 √(1 − x²/b²) is (q0 b/E*)(ln(2d/b) + 1/2) relative
  to a datum at distance d (``engine.kernels.line``), so the rigid displacement under Q = μP t
  is δ(t) = (μ p0 a/E*) [t (ln(2d/a) + 1/2) + (1/2)(1 − t) ln(1 − t)]. Its linear part
  encloses no area, and the loop between ±Q* = ±μP T dissipates per cycle

      W = 4 Q* δ(T) − 8 ∫₀^{Q*} δ dQ = (2 μ² P² / (π E*)) [2(1 − T) ln(1 − T) + 2T − T²],

  independent of the datum; small amplitudes W ≈ (2μ²P²/(πE*)) T³/3; at T = 1, 2μ²P²/(πE*).
- **Nowell & Hills' stick-zone shift** (Nowell & Hills, Wear 118 (1987) 211; Hills & Nowell
  1994, §5.3): a bulk stress σ_B along x in the flat (body A), applied with Q, strains the
  flat's surface by ε = (1 − ν_A²) σ_B / E_A (plane strain, σ_yy = ν_A σ_B). The stick zone
  keeps its half-width c and its centre moves to x = e,
  e = sgn(Q) ε E* a / (2 μ p0)  (= σ_B a / (4 μ p0) for identical bodies),
  valid while |e| + c ≤ a; the traction is the Cattaneo one with the stick term centred at e.
  Sign convention of the engine: Q > 0 is the force the pad exerts on the flat, and a
  tension moves the stick zone towards +x when Q > 0.
- **Ciavarella's rounded flat pad** (Ciavarella, Hills & Monno, Proc. IMechE C 212 (1998)
  319): flat of half-width b with parabolic edges (|x| − b)²/(2R). With sin φ0 = b/a,
  P = (E* a² / (4R)) (π − 2φ0 − sin 2φ0), and the pressure, from the inversion of the
  Cauchy integral with bounded ends (Johnson Eq. 2.49 / Muskhelishvili),
  p(x) = (E*/(2πR)) √(a² − x²) [π − 2φ0 + (x − b) J(x; b, a) + (x + b) J(x; −a, −b)],
  J(x; t1, t2) = PV∫_{t1}^{t2} dt / (√(a² − t²)(t − x)), in closed form by t = a sin θ,
  w = tan(θ/2): J = −(1/s) [ln|x w − a − s| − ln|w − x/(a + s)|]_{w1}^{w2}, s = √(a² − x²).
  b → 0 gives Hertz.
"""

from __future__ import annotations

import math

import numpy as np

from . import masing
from .docstrings import documented

__all__ = [
    "hertz_line_half_width",
    "hertz_line_peak_pressure",
    "hertz_line_pressure",
    "cattaneo_line_stick_half_width",
    "cattaneo_line_traction",
    "nowell_hills_traction",
    "line_loop_energy",
    "line_tangential_displacement",
    "line_slip_displacement",
    "line_fretting_loop",
    "line_fretting_reference",
    "bulk_surface_strain",
    "nowell_hills_stick_offset",
    "pad_load",
    "pad_half_width",
    "pad_pressure",
]


def hertz_line_half_width(load: float, radius: float, contact_modulus: float) -> float:
    """a = √(4PR/(πE*)) (mm) for ``load`` P (N/mm), ``radius`` R (mm), E* (MPa)."""
    return math.sqrt(4.0 * load * radius / (math.pi * contact_modulus))


def hertz_line_peak_pressure(load: float, radius: float, contact_modulus: float) -> float:
    """p0 = 2P/(πa) (MPa)."""
    return 2.0 * load / (math.pi * hertz_line_half_width(load, radius, contact_modulus))


def _elliptic(x: np.ndarray, half_width: float) -> np.ndarray:
    """√(1 − x²/b²) inside |x| < b, 0 outside."""
    x = np.asarray(x, dtype=float)
    return np.sqrt(np.clip(1.0 - (x / half_width) ** 2, 0.0, None))


def hertz_line_pressure(x, load: float, radius: float, contact_modulus: float) -> np.ndarray:
    """p(x) = p0 √(1 − x²/a²) inside the contact, 0 outside (MPa); ``x`` in mm."""
    a = hertz_line_half_width(load, radius, contact_modulus)
    return hertz_line_peak_pressure(load, radius, contact_modulus) * _elliptic(x, a)


def _force_ratio(force: float, load: float, friction_coefficient: float) -> float:
    ratio = abs(force) / (friction_coefficient * load)
    if not 0.0 <= ratio <= 1.0:
        raise ValueError(
            f"tangential force |Q| = {abs(force):g} N/mm exceeds the limit μP = "
            f"{friction_coefficient * load:g} N/mm (gross slip)"
        )
    return ratio


def cattaneo_line_stick_half_width(half_width: float, force, load, friction_coefficient):
    """c = a √(1 − |Q|/(μP)) (mm)."""
    return half_width * math.sqrt(1.0 - _force_ratio(force, load, friction_coefficient))


def cattaneo_line_traction(
    x, force: float, load: float, radius: float, contact_modulus: float, friction_coefficient
) -> np.ndarray:
    """Cattaneo–Mindlin traction q(x) (MPa) of a cylinder under 0 → Q (sign of Q), x in mm."""
    return nowell_hills_traction(x, force, load, radius, contact_modulus, friction_coefficient)


def nowell_hills_traction(
    x,
    force: float,
    load: float,
    radius: float,
    contact_modulus: float,
    friction_coefficient: float,
    offset: float = 0.0,
) -> np.ndarray:
    """The partial-slip traction (MPa) with the stick zone centred at ``offset`` e (mm):
    sgn(Q) μp0 [√(1 − x²/a²) − (c/a) √(1 − (x − e)²/c²)]."""
    a = hertz_line_half_width(load, radius, contact_modulus)
    p0 = hertz_line_peak_pressure(load, radius, contact_modulus)
    c = cattaneo_line_stick_half_width(a, force, load, friction_coefficient)
    if abs(offset) + c > a:
        raise ValueError(
            f"stick zone offset |e| = {abs(offset):g} mm plus its half-width {c:g} mm exceeds "
            f"the contact half-width {a:g} mm (Nowell & Hills' solution does not apply)"
        )
    x = np.asarray(x, dtype=float)
    stick = (c / a) * _elliptic(x - offset, c) if c > 0.0 else np.zeros_like(x)
    return math.copysign(friction_coefficient * p0, force) * (_elliptic(x, a) - stick)


def line_loop_energy(
    force_amplitude: float, load: float, contact_modulus: float, friction_coefficient: float
) -> float:
    """Energy dissipated per cycle ±Q* (N·mm per mm of length) of a cylinder in partial
    slip: (2μ²P²/(πE*)) [2(1 − T) ln(1 − T) + 2T − T²], T = Q*/(μP) (module docstring)."""
    t = _force_ratio(force_amplitude, load, friction_coefficient)
    log_term = 0.0 if t == 1.0 else 2.0 * (1.0 - t) * math.log1p(-t)
    scale = 2.0 * (friction_coefficient * load) ** 2 / (math.pi * contact_modulus)
    return scale * (log_term + 2.0 * t - t * t)


def line_tangential_displacement(
    force,
    load: float,
    radius: float,
    contact_modulus: float,
    friction_coefficient: float,
    reference_distance: float,
) -> np.ndarray:
    """The rigid tangential displacement δ (mm) of a cylinder under 0 → Q < μP (N/mm),
    relative to the datum at ``reference_distance`` d (mm; ``engine.kernels.line``):
    δ = (μ p0 a/E*) [t (ln(2d/a) + 1/2) + (1/2)(1 − t) ln(1 − t)], t = |Q|/(μP), with the
    sign of Q (module docstring: the stick zone's displacement under the Cattaneo traction)."""
    force = np.asarray(force, dtype=float)
    t = np.abs(force) / (friction_coefficient * load)
    if np.any(t > 1.0 + 1e-12):
        raise ValueError(
            f"tangential force must lie in [−μP, μP], μP = {friction_coefficient * load:g} N/mm"
        )
    t = np.minimum(t, 1.0)
    a = hertz_line_half_width(load, radius, contact_modulus)
    scale = friction_coefficient * hertz_line_peak_pressure(load, radius, contact_modulus) * a
    complement = 1.0 - t
    log_part = np.where(
        complement > 0.0, complement * np.log(np.where(complement > 0.0, complement, 1.0)), 0.0
    )
    linear = t * (math.log(2.0 * reference_distance / a) + 0.5)
    return np.sign(force) * (scale / contact_modulus) * (linear + 0.5 * log_part)


def line_slip_displacement(
    load,
    radius: float,
    contact_modulus: float,
    friction_coefficient: float,
    reference_distance: float,
):
    """δ_slip (mm): the displacement amplitude at which a cylinder under ``load`` P (N/mm)
    reaches gross slip (Q = μP), (μ p0 a/E*)(ln(2d/a) + 1/2) with p0 = 2P/(πa); the
    partial/gross boundary of a displacement-controlled fretting map. It grows with the
    datum d: under displacement control d sets how much of the stroke is elastic."""
    load = np.asarray(load, dtype=float)
    a = np.sqrt(4.0 * load * radius / (math.pi * contact_modulus))
    p0 = 2.0 * load / (math.pi * a)
    log_term = np.log(2.0 * reference_distance / a) + 0.5
    return friction_coefficient * p0 * a / contact_modulus * log_term


@documented(
    "(numpy.ndarray, numpy.ndarray)\n    δ (mm) and Q (N/mm) around the loop.",
    "load : float\n    Normal load P (N/mm), held constant.",
    "radius : float\n    Cylinder radius R (mm).",
    "contact_modulus : float\n    E* (MPa).",
    "friction_coefficient : float\n    Coulomb friction coefficient μ.",
    "reference_distance : float\n    The displacement datum d (mm; ``engine.kernels.line``).",
    masing.LOOP_OPTIONS,
)
def line_fretting_loop(
    load, radius, contact_modulus, friction_coefficient, reference_distance, **loop
):
    """The cylinder's stabilised fretting loop (δ in mm, Q in N/mm), closed, from (δ*, Q*).

    :func:`engine.reference.masing.fretting_loop` on the virgin curve
    :func:`line_tangential_displacement` (inverted numerically): the unloading branch
    δ = δ* − 2 δ((Q* − Q)/2) to (−δ*, −Q*), sliding at Q = −μP in gross slip (δ* beyond
    :func:`line_slip_displacement`); the reloading branch is its point reflection.
    """
    contact = (load, radius, contact_modulus, friction_coefficient, reference_distance)
    return masing.fretting_loop(
        lambda force: line_tangential_displacement(force, *contact),
        friction_coefficient * load,
        **loop,
    )


def line_fretting_reference(
    load, radius, contact_modulus, friction_coefficient, reference_distance
) -> masing.FrettingReference:
    """The cylinder's closed forms under fretting at the load P (N/mm) as one object
    (:class:`engine.reference.masing.FrettingReference`): the virgin curve
    :func:`line_tangential_displacement` relative to the datum ``reference_distance`` d (mm),
    inverted numerically, and the loop energy :func:`line_loop_energy` (N·mm per mm)."""
    contact = (load, radius, contact_modulus, friction_coefficient, reference_distance)
    return masing.FrettingReference(
        "Cattaneo–Masing (cylinder)",
        lambda force: line_tangential_displacement(force, *contact),
        friction_coefficient * load,
        loop_energy=lambda amplitude: line_loop_energy(
            amplitude, load, contact_modulus, friction_coefficient
        ),
    )


def bulk_surface_strain(bulk_stress: float, young_modulus: float, poisson_ratio: float):
    """ε = (1 − ν²) σ_B / E: the flat's surface strain along x under the bulk stress σ_B
    (MPa) in plane strain (σ_yy = ν σ_B)."""
    return (1.0 - poisson_ratio**2) * bulk_stress / young_modulus


def nowell_hills_stick_offset(
    bulk_strain: float,
    force: float,
    half_width: float,
    peak_pressure: float,
    contact_modulus: float,
    friction_coefficient: float,
) -> float:
    """e = sgn(Q) ε E* a / (2 μ p0) (mm): the stick zone's centre under a bulk strain ε of
    the flat (``bulk_surface_strain``) applied together with Q (module docstring)."""
    magnitude = bulk_strain * contact_modulus * half_width
    return math.copysign(magnitude / (2.0 * friction_coefficient * peak_pressure), force)


def _pad_angle(flat_half_width: float, half_width: float) -> float:
    if not 0.0 <= flat_half_width < half_width:
        raise ValueError(
            f"contact half-width a = {half_width:g} mm must exceed the flat half-width "
            f"b = {flat_half_width:g} mm"
        )
    return math.asin(flat_half_width / half_width)


def pad_load(half_width: float, flat_half_width: float, edge_radius: float, contact_modulus):
    """P = (E* a²/(4R)) (π − 2φ0 − sin 2φ0) (N/mm), sin φ0 = b/a."""
    phi = _pad_angle(flat_half_width, half_width)
    return (
        contact_modulus
        * half_width**2
        / (4.0 * edge_radius)
        * (math.pi - 2.0 * phi - math.sin(2.0 * phi))
    )


def pad_half_width(load: float, flat_half_width: float, edge_radius: float, contact_modulus):
    """The contact half-width a (mm) of the rounded pad under ``load`` P (N/mm): the root of
    ``pad_load`` (monotonic in a), between b and b + the cylinder's a."""
    from scipy.optimize import brentq  # here: a run of a cylinder imports no SciPy

    hertz = hertz_line_half_width(load, edge_radius, contact_modulus)
    low, high = flat_half_width * (1.0 + 1e-15), flat_half_width + hertz
    return brentq(
        lambda a: pad_load(a, flat_half_width, edge_radius, contact_modulus) - load,
        low,
        high,
        xtol=1e-15,
        rtol=1e-14,
    )


def _log_terms(x, w, a, s):
    """ln|x w − a − s| − ln|w − x/(a + s)| (the antiderivative of J up to −1/s)."""
    return np.log(np.abs(x * w - a - s)) - np.log(np.abs(w - x / (a + s)))


def _cauchy_segment(x, a, first, last):
    """J(x; a sin θ1, a sin θ2) for |x| < a (module docstring), θ in [−π/2, π/2]."""
    s = np.sqrt(a * a - x * x)
    w1, w2 = math.tan(0.5 * first), math.tan(0.5 * last)
    return -(_log_terms(x, w2, a, s) - _log_terms(x, w1, a, s)) / s


def pad_pressure(x, load, flat_half_width, edge_radius, contact_modulus) -> np.ndarray:
    """Ciavarella's pressure (MPa) of the rounded flat pad under ``load`` P (N/mm) at ``x``
    (mm); 0 outside the contact. At x = ±b exactly, where J is singular, the limit of
    (x ∓ b) J (zero) is used."""
    a = pad_half_width(load, flat_half_width, edge_radius, contact_modulus)
    phi = _pad_angle(flat_half_width, a)
    x = np.asarray(x, dtype=float)
    inside = np.abs(x) < a
    xi = np.where(inside, x, 0.0)
    bracket = np.full(xi.shape, math.pi - 2.0 * phi)
    for centre, first, last in (
        (flat_half_width, phi, 0.5 * math.pi),
        (-flat_half_width, -0.5 * math.pi, -phi),
    ):
        with np.errstate(divide="ignore", invalid="ignore"):
            term = (xi - centre) * _cauchy_segment(xi, a, first, last)
        bracket += np.where(xi == centre, 0.0, term)
    root = np.sqrt(np.clip(a * a - xi * xi, 0.0, None))
    pressure = contact_modulus / (2.0 * math.pi * edge_radius) * root * bracket
    return np.where(inside, pressure, 0.0)
