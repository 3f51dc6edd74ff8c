"""McEwen's closed-form plane-strain stresses under a Hertzian line contact, with friction,
partial slip and a bulk stress: the reference field of fretting fatigue.

A half-space z > 0 (the flat) carries, on its surface z = 0, a pressure and a tangential
traction made of *elliptic terms* A √(1 − (x − e)²/b²) (|x − e| < b). McEwen (Phil. Mag. 40
(1949) 454) gave the stresses of such a term in closed form; in Johnson's notation
(*Contact Mechanics*, 1985, Eqs. 7.18–7.19 with z into the body) with

    s = b² − X² + z²,   m² = ½(√(s² + 4X²z²) + s),   n² = ½(√(s² + 4X²z²) − s),

X = x − e, m ≥ 0 and n of the sign of X, the stresses (MPa) of a pressure term p0 are

    σ_xx = −(p0/b) [m (1 + (z² + n²)/(m² + n²)) − 2z]
    σ_zz = −(p0/b)  m (1 − (z² + n²)/(m² + n²))
    σ_xz = −(p0/b)  n (m² − z²)/(m² + n²)

and those of a shear term q0 (acting on the flat in +x) are

    σ_xx = +(q0/b) [n (2 − (z² − m²)/(m² + n²)) − 2X]
    σ_zz = −(q0/b)  n (m² − z²)/(m² + n²)
    σ_xz = −(q0/b) [m (1 + (z² + n²)/(m² + n²)) − 2z].

The signs are those of this module's convention (below), checked in
tests/test_mcewen_reference.py by the surface tractions, by equilibrium (the divergence of the
stress vanishes, by finite differences) and by the known facts (the frictionless maximum shear
0.30 p0 at z = 0.78 b; σ_xx = 2μp0 of tension at the trailing edge x = −b of a sliding
contact).

Conventions (package wide): lengths mm, stresses MPa, tension positive, z > 0 into the flat.
A pressure ≥ 0 pushes into the flat (σ_zz = −p at the surface); a traction q acts on the flat's
surface in +x (σ_xz = −q at the surface) — the force the pad exerts on the flat, the engine's
Q > 0. Plane strain: σ_yy = ν(σ_xx + σ_zz). A bulk stress σ_B along x in the flat adds
σ_xx = σ_B (and ν σ_B to σ_yy, through the same formula).

Tractions of the cylinder on a flat (Hertz half-width a, peak pressure p0, friction μ; Hills &
Nowell, *Mechanics of Fretting Fatigue*, 1994, Ch. 4–5):

- full sliding: q = μ p(x), one shear term μp0 of half-width a;
- partial slip under 0 → Q (Cattaneo–Mindlin): q = μp0 √(1 − x²/a²) − μp0 (c/a) √(1 − (x − e)²/c²),
  c = a √(1 − Q/(μP)); the second term is the shear term −μp0 c/a of half-width c centred on
  e, the Nowell & Hills offset e = σ_B a/(4μp0) of a bulk stress applied with Q (identical
  elastic bodies, :mod:`engine.reference.line_contact`);
- the steady fretting cycle between ±Q* with σ_B = σ_m + σ_a Q/Q* in phase
  (Mindlin–Deresiewicz by superposition): at Q* the partial-slip traction with c* = a √(1 − Q*/(μP))
  and e* = σ_a a/(4μp0); unloading to Q adds −2 × a partial-slip traction of the change,
  −2μp0 [√(1 − x²/a²) − (c'/a) √(1 − (x − e')²/c'²)] with c' = a √(1 − (Q* − Q)/(2μP)) and
  e' = (σ_a (Q* − Q)/Q*) a/(8μp0); reloading from −Q* is the mirror image. The mean σ_m adds
  to σ_xx only (in the steady state it leaves no mark on the traction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "EllipticTerm",
    "LineTractions",
    "PlaneStrainStress",
    "elliptic_pressure_stress",
    "elliptic_shear_stress",
    "line_contact_stress",
    "sliding_tractions",
    "partial_slip_tractions",
    "FrettingCycle",
    "fretting_cycle_forces",
]


@dataclass(frozen=True)
class PlaneStrainStress:
    """Plane-strain stresses (MPa) at points of the x–z plane, arrays of the points' shape.

    ``xx, yy, zz, xz``; σ_xy = σ_yz = 0. ``components`` gives the six Cartesian components
    under the keys of ``engine.solvers.subsurface.StressField``.
    """

    xx: np.ndarray
    yy: np.ndarray
    zz: np.ndarray
    xz: np.ndarray

    @property
    def components(self) -> dict[str, np.ndarray]:
        zero = np.zeros_like(self.xx)
        return {"xx": self.xx, "yy": self.yy, "zz": self.zz, "xy": zero, "xz": self.xz, "yz": zero}


@dataclass(frozen=True)
class EllipticTerm:
    """A surface load ``amplitude`` √(1 − (x − centre)²/half_width²) (MPa; mm)."""

    amplitude: float
    half_width: float
    centre: float = 0.0


@dataclass(frozen=True)
class LineTractions:
    """Surface loads of one instant: ``pressure`` and ``shear`` terms, and the bulk stress
    σ_B (MPa) along x in the flat."""

    pressure: tuple[EllipticTerm, ...]
    shear: tuple[EllipticTerm, ...] = ()
    bulk_stress: float = 0.0

    def pressure_at(self, x) -> np.ndarray:
        """p(x) (MPa) on the surface points ``x`` (mm)."""
        return _surface_sum(self.pressure, x)

    def shear_at(self, x) -> np.ndarray:
        """q(x) (MPa, on the flat in +x) on the surface points ``x`` (mm)."""
        return _surface_sum(self.shear, x)


def _surface_sum(terms, x) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    total = np.zeros_like(x)
    for term in terms:
        ratio = (x - term.centre) / term.half_width
        total += term.amplitude * np.sqrt(np.clip(1.0 - ratio**2, 0.0, None))
    return total


def _mcewen_mn(offset: np.ndarray, z: np.ndarray, half_width: float):
    """McEwen's m ≥ 0 and n (sign of x − e), computed without cancellation: the larger of the
    two is √(½(r + |s|)), the other |X| z over it (m n = X z)."""
    s = half_width**2 - offset**2 + z**2
    r = np.hypot(s, 2.0 * offset * z)
    large = np.sqrt(0.5 * (r + np.abs(s)))
    small = np.divide(np.abs(offset) * z, large, out=np.zeros_like(large), where=large > 0.0)
    m = np.where(s >= 0.0, large, small)
    n = np.sign(offset) * np.where(s >= 0.0, small, large)
    return m, n


def _ratio(numerator: np.ndarray, denominator: np.ndarray) -> np.ndarray:
    """numerator / denominator, 0 where both vanish (the contact edge on the surface)."""
    return np.divide(numerator, denominator, out=np.zeros_like(numerator), where=denominator > 0.0)


def _points(x, z) -> tuple[np.ndarray, np.ndarray]:
    x, z = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(z, dtype=float))
    if np.any(z < 0.0):
        raise ValueError(f"depth z must be >= 0 mm (into the flat), got min {z.min():g}")
    return x, z


def elliptic_pressure_stress(x, z, term: EllipticTerm) -> tuple[np.ndarray, ...]:
    """(σ_xx, σ_zz, σ_xz) (MPa) of a pressure term (McEwen; module docstring) at the points
    ``x, z`` (mm, broadcast together, z ≥ 0)."""
    x, z = _points(x, z)
    m, n = _mcewen_mn(x - term.centre, z, term.half_width)
    d = m * m + n * n
    scale = term.amplitude / term.half_width
    xx = -scale * (m + _ratio(m * (z * z + n * n), d) - 2.0 * z)
    zz = -scale * (m - _ratio(m * (z * z + n * n), d))
    xz = -scale * _ratio(n * (m * m - z * z), d)
    return xx, zz, xz


def elliptic_shear_stress(x, z, term: EllipticTerm) -> tuple[np.ndarray, ...]:
    """(σ_xx, σ_zz, σ_xz) (MPa) of a shear term acting on the flat in +x (McEwen; module
    docstring) at the points ``x, z`` (mm, broadcast together, z ≥ 0)."""
    x, z = _points(x, z)
    offset = x - term.centre
    m, n = _mcewen_mn(offset, z, term.half_width)
    d = m * m + n * n
    scale = term.amplitude / term.half_width
    xx = scale * (2.0 * n - _ratio(n * (z * z - m * m), d) - 2.0 * offset)
    zz = -scale * _ratio(n * (m * m - z * z), d)
    xz = -scale * (m + _ratio(m * (z * z + n * n), d) - 2.0 * z)
    return xx, zz, xz


def line_contact_stress(x, z, tractions: LineTractions, poisson_ratio: float) -> PlaneStrainStress:
    """The plane-strain stresses (MPa) of ``tractions`` at the points ``x, z`` (mm, any
    broadcastable shapes, z ≥ 0), with σ_yy = ν(σ_xx + σ_zz) for the flat's Poisson ratio."""
    if not 0.0 <= poisson_ratio < 0.5:
        raise ValueError(f"poisson_ratio must lie in [0, 0.5), got {poisson_ratio!r}")
    x, z = _points(x, z)
    xx = np.full(x.shape, float(tractions.bulk_stress))
    zz = np.zeros(x.shape)
    xz = np.zeros(x.shape)
    for term, field in [(t, elliptic_pressure_stress) for t in tractions.pressure] + [
        (t, elliptic_shear_stress) for t in tractions.shear
    ]:
        dxx, dzz, dxz = field(x, z, term)
        xx += dxx
        zz += dzz
        xz += dxz
    return PlaneStrainStress(xx=xx, yy=poisson_ratio * (xx + zz), zz=zz, xz=xz)


# --- the tractions of a cylinder on a flat -----------------------------------------------------


def sliding_tractions(
    half_width: float, peak_pressure: float, friction_coefficient: float, bulk_stress=0.0
) -> LineTractions:
    """Hertz pressure p0 √(1 − x²/a²) and full sliding q = μ p(x) (μ < 0: sliding the other
    way; μ = 0: frictionless)."""
    pressure = (EllipticTerm(peak_pressure, half_width),)
    shear = (EllipticTerm(friction_coefficient * peak_pressure, half_width),)
    return LineTractions(pressure, shear if friction_coefficient else (), float(bulk_stress))


def _stick_term(amplitude, half_width, stick_half_width, offset) -> tuple[EllipticTerm, ...]:
    """The stick correction −amplitude (c/a) √(1 − (x − e)²/c²), checked |e| + c ≤ a."""
    if abs(offset) + stick_half_width > half_width * (1.0 + 1e-12):
        raise ValueError(
            f"stick zone offset |e| = {abs(offset):g} mm plus its half-width "
            f"{stick_half_width:g} mm exceeds the contact half-width {half_width:g} mm "
            "(the bulk stress is too large for partial slip: Nowell & Hills' solution does "
            "not apply)"
        )
    if stick_half_width <= 0.0:
        return ()
    return (EllipticTerm(-amplitude * stick_half_width / half_width, stick_half_width, offset),)


def _force_ratio(name: str, value: float, limit: float = 1.0) -> float:
    if not 0.0 <= value <= limit:
        raise ValueError(f"{name} must lie in [0, {limit:g}], got {value!r}")
    return float(value)


def partial_slip_tractions(
    half_width: float,
    peak_pressure: float,
    friction_coefficient: float,
    force_ratio: float,
    bulk_stress: float = 0.0,
) -> LineTractions:
    """Cattaneo–Mindlin tractions under 0 → Q = ``force_ratio`` μP (0 ≤ Q/(μP) ≤ 1), with
    the Nowell & Hills stick-zone offset e = σ_B a/(4μp0) of a bulk stress σ_B applied with Q
    (identical elastic bodies)."""
    ratio = _force_ratio("force_ratio", force_ratio)
    if not friction_coefficient > 0.0:
        raise ValueError(f"friction_coefficient must be > 0, got {friction_coefficient!r}")
    amplitude = friction_coefficient * peak_pressure
    stick = half_width * math.sqrt(1.0 - ratio)
    offset = bulk_stress * half_width / (4.0 * amplitude)
    shear = (EllipticTerm(amplitude, half_width),)
    shear += _stick_term(amplitude, half_width, stick, offset)
    return LineTractions((EllipticTerm(peak_pressure, half_width),), shear, float(bulk_stress))


@dataclass(frozen=True)
class FrettingCycle:
    """The steady fretting cycle of a cylinder on a flat between ±Q* = ±T μP with an in-phase
    bulk stress σ_B = σ_m + σ_a Q/Q* (module docstring): Hertz ``half_width`` a (mm) and
    ``peak_pressure`` p0 (MPa), ``friction_coefficient`` μ, ``force_amplitude_ratio``
    T = Q*/(μP) in [0, 1], ``bulk_mean`` σ_m and ``bulk_amplitude`` σ_a (MPa)."""

    half_width: float
    peak_pressure: float
    friction_coefficient: float
    force_amplitude_ratio: float
    bulk_mean: float = 0.0
    bulk_amplitude: float = 0.0

    def tractions(self, force_ratio: float, unloading: bool) -> LineTractions:
        """Tractions at Q = ``force_ratio`` μP (−T ≤ Q/(μP) ≤ T) on the ``unloading`` branch
        (from Q* down) or the reloading one (from −Q* up): the reversal state plus −2 (or +2)
        times the partial-slip traction of the change (Mindlin–Deresiewicz)."""
        peak_ratio = _force_ratio("force_amplitude_ratio", self.force_amplitude_ratio)
        if abs(force_ratio) > peak_ratio * (1.0 + 1e-12):
            raise ValueError(f"force_ratio must lie in [−{peak_ratio:g}, {peak_ratio:g}]")
        a, sign = self.half_width, 1.0 if unloading else -1.0
        amplitude = self.friction_coefficient * self.peak_pressure
        reversal = partial_slip_tractions(
            a, self.peak_pressure, self.friction_coefficient, peak_ratio, self.bulk_amplitude
        )
        change = min(max((peak_ratio - sign * force_ratio) / 2.0, 0.0), peak_ratio)
        fraction = change / peak_ratio if peak_ratio > 0.0 else 0.0
        offset = self.bulk_amplitude * fraction * a / (4.0 * amplitude)
        shear = tuple(
            EllipticTerm(sign * t.amplitude, t.half_width, t.centre) for t in reversal.shear
        )
        shear += (EllipticTerm(-sign * 2.0 * amplitude, a),)
        shear += _stick_term(-sign * 2.0 * amplitude, a, a * math.sqrt(1.0 - change), offset)
        signal = force_ratio / peak_ratio if peak_ratio > 0.0 else 0.0
        bulk = self.bulk_mean + self.bulk_amplitude * signal
        return LineTractions((EllipticTerm(self.peak_pressure, a),), shear, float(bulk))

    def stress(self, x, z, poisson_ratio: float, instants: int = 40) -> PlaneStrainStress:
        """The stress history of the cycle sampled by ``fretting_cycle_forces`` at the points
        ``x, z`` (mm): arrays of shape (instants, *points)."""
        forces, unloading = fretting_cycle_forces(instants)
        ratio = self.force_amplitude_ratio
        fields = [
            line_contact_stress(x, z, self.tractions(ratio * force, bool(unload)), poisson_ratio)
            for force, unload in zip(forces, unloading, strict=True)
        ]
        keys = ("xx", "yy", "zz", "xz")
        return PlaneStrainStress(
            **{key: np.stack([getattr(f, key) for f in fields]) for key in keys}
        )


def fretting_cycle_forces(instants: int) -> tuple[np.ndarray, np.ndarray]:
    """The sampled signal of one cycle: Q/Q* = cos(2πk/n), k = 0 … n − 1 (from the maximum,
    unloading to the minimum at k = n/2, reloading), and whether each instant unloads."""
    if instants < 2:
        raise ValueError(f"instants must be >= 2, got {instants!r}")
    phase = 2.0 * np.pi * np.arange(instants) / instants
    return np.cos(phase), phase <= np.pi
