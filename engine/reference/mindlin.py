"""Cattaneo–Mindlin tangential loading of a Hertzian sphere and the Mindlin–Deresiewicz loop.

A sphere of radius R (mm) is pressed with a constant normal load P (N) on a half-space; the
two bodies are elastic (Young's moduli E_A, E_B in MPa, Poisson ratios ν_A, ν_B, shear moduli
G_i = E_i / (2(1 + ν_i))) with Coulomb friction μ. The contact radius a (mm) is Hertz's
(:mod:`engine.reference.hertz`). The formulas assume that the normal and the tangential
problems are uncoupled (K = 0, e.g. identical bodies); with K ≠ 0 they are approximations.
Sources: Johnson, *Contact Mechanics* (1985), §7.2 (Eqs. 7.37–7.42) and §7.4 (Eqs. 7.52–7.54);
Mindlin & Deresiewicz, *J. Appl. Mech.* 20 (1953) 327.

Convention for δ (mm): the rigid tangential displacement of one body relative to the other,
measured between points far from the contact (the "rigid slip" the engine prescribes).
Forces Q (N), energies in N·mm = mJ. With the compliance sum

    S = (2 − ν_A)/G_A + (2 − ν_B)/G_B          (1/MPa; = 2(2 − ν)/G with Eq. 6's ν, G)

and the limiting force L = μP:

- monotone loading 0 → Q < L (Cattaneo–Mindlin, Johnson 7.40 and 7.42):
  stick radius        c/a = (1 − Q/L)^{1/3},
  compliance curve    δ(Q) = (3 L S / (16 a)) [1 − (1 − Q/L)^{2/3}];
- the partial/gross-slip boundary: δ_slip = δ(L) = 3 L S / (16 a) ∝ P^{2/3};
- cyclic loading between ±Q* (Mindlin–Deresiewicz), by the Masing construction:
  unloading from (δ*, Q*)   δ = δ* − 2 δ((Q* − Q)/2),
  reloading from (−δ*, −Q*) δ = −δ* + 2 δ((Q* + Q)/2),
  with δ* = δ(Q*). The dissipated energy per cycle is the area of the loop,

      W = ∫_{−Q*}^{Q*} (δ_unload − δ_reload) dQ = 4 Q* δ* − 8 ∫₀^{Q*} δ(u) du
        = (9 L² S / (10 a)) [1 − (1 − q)^{5/3} − (5q/6)(1 + (1 − q)^{2/3})],  q = Q*/L,

  (derived here; compare Johnson 7.53, whose prefactor 9μ²P²/(10a)·(2 − ν)/G is this one
  with (2 − ν)/G standing for the sum S; the bracket is checked in
  tests/test_mindlin_reference.py against quadrature of the Masing branches and against the
  Q*³ limit, which fixes the sign of its last term); small amplitudes: W ≈ S Q*³ / (36 a L)
  (Johnson 7.54), at q = 1: W = 0.8 L δ_slip (Fouvry's energy ratio W / (4 δ* Q*) = 0.2);
- gross slip under a displacement amplitude δ* > δ_slip: Q* = L and the loop is the
  partial loop at Q* = L opened by two sliding stretches of length 2(δ* − δ_slip):
  W = W(q = 1) + 4 L (δ* − δ_slip).
"""

from __future__ import annotations

import numpy as np

from ..material import MaterialPair
from . import masing
from .docstrings import documented
from .hertz import hertz_contact_radius

__all__ = [
    "compliance_sum",
    "stick_radius_ratio",
    "tangential_displacement",
    "tangential_force",
    "slip_displacement",
    "unloading_displacement",
    "partial_slip_energy",
    "partial_slip_energy_small_amplitude",
    "gross_slip_energy",
    "energy_per_cycle",
    "energy_ratio",
    "force_amplitude",
    "fretting_loop",
    "fretting_reference",
]


# The parameters several functions share, written once (numpydoc entries): the displacement
# amplitude and the contact (load, radius, materials, friction) that close every signature.
_DISPLACEMENT_AMPLITUDE = "displacement_amplitude : float or array_like\n    δ* (mm)."
_CONTACT = (
    "load : float or array_like\n    Normal load P (N), held constant.",
    "radius : float\n    Sphere radius R (mm).",
    "materials : engine.material.MaterialPair\n"
    "    The two elastic bodies (Young's moduli in MPa, Poisson's ratios).",
    "friction : float\n    Coulomb friction coefficient μ.",
)


def _contact(returns: str, *first: str):
    """Decorator: complete a docstring with the Parameters section (``first``, the entries
    before the shared ones, then load, radius, materials, friction) and the Returns section
    ``returns`` ("type\n    description")."""
    return documented(returns, *first, *_CONTACT)


def compliance_sum(materials: MaterialPair) -> float:
    """The compliance sum S = (2 − ν_A)/G_A + (2 − ν_B)/G_B of the tangential problem.

    Parameters
    ----------
    materials : engine.material.MaterialPair
        The two elastic bodies (moduli in MPa).

    Returns
    -------
    float
        S (1/MPa).
    """
    return (2.0 - materials.nu_A) / materials.shear_modulus_A + (
        2.0 - materials.nu_B
    ) / materials.shear_modulus_B


def _scale(load, radius, materials, friction) -> tuple[float, float]:
    """(δ_slip in mm, L = μP in N)."""
    limit = friction * load
    a = hertz_contact_radius(load, radius, materials.contact_modulus)
    return 3.0 * limit * compliance_sum(materials) / (16.0 * a), limit


def _ratio(force, limit) -> np.ndarray:
    """q = Q/L, checked to lie in [0, 1]."""
    q = np.asarray(force, dtype=float) / limit
    if np.any(q < 0.0) or np.any(q > 1.0 + 1e-12):
        raise ValueError(f"tangential force must lie in [0, μP] = [0, {limit:g}] N")
    return np.clip(q, 0.0, 1.0)


def stick_radius_ratio(force, load: float, friction: float) -> np.ndarray:
    """Radius of the stick zone under a monotone tangential force: c/a = (1 − Q/μP)^{1/3}.

    Cattaneo–Mindlin, Johnson Eq. 7.40.

    Parameters
    ----------
    force : float or array_like
        Tangential force Q (N), 0 ≤ Q ≤ μP.
    load : float
        Normal load P (N).
    friction : float
        Coulomb friction coefficient μ.

    Returns
    -------
    numpy.ndarray
        c/a (dimensionless).
    """
    return (1.0 - _ratio(force, friction * load)) ** (1.0 / 3.0)


@_contact("numpy.ndarray\n    δ_slip (mm), shaped like ``load``.")
def slip_displacement(load, radius, materials: MaterialPair, friction: float) -> np.ndarray:
    """δ_slip = 3 μP S / (16 a): the displacement amplitude at the onset of gross slip.

    With ``load`` an array, δ_slip(P) ∝ P^{2/3} is the partial/gross boundary line of the
    running-condition fretting map.
    """
    load = np.asarray(load, dtype=float)
    a = hertz_contact_radius(load, radius, materials.contact_modulus)
    return 3.0 * friction * load * compliance_sum(materials) / (16.0 * a)


@_contact(
    "numpy.ndarray\n    Rigid tangential displacement δ (mm).",
    "force : float or array_like\n    Tangential force Q (N) of a monotone loading 0 → Q ≤ μP.",
)
def tangential_displacement(force, load, radius, materials, friction) -> np.ndarray:
    """The Cattaneo–Mindlin compliance curve δ(Q) = δ_slip [1 − (1 − Q/μP)^{2/3}].

    Johnson Eq. 7.42.
    """
    slip, limit = _scale(load, radius, materials, friction)
    return slip * (1.0 - (1.0 - _ratio(force, limit)) ** (2.0 / 3.0))


@_contact(
    "numpy.ndarray\n    Tangential force Q (N); μP where the sphere slides.",
    "displacement : float or array_like\n"
    "    Rigid tangential displacement δ (mm); for δ ≥ δ_slip the sphere slides.",
)
def tangential_force(displacement, load, radius, materials, friction) -> np.ndarray:
    """The inverse of the compliance curve: Q(δ) = μP [1 − (1 − δ/δ_slip)^{3/2}]."""
    slip, limit = _scale(load, radius, materials, friction)
    d = np.clip(np.asarray(displacement, dtype=float) / slip, 0.0, 1.0)
    return limit * (1.0 - (1.0 - d) ** 1.5)


@_contact(
    "numpy.ndarray\n    Rigid tangential displacement δ (mm).",
    "force : float or array_like\n    Tangential force Q (N), −Q* ≤ Q ≤ Q*.",
    "amplitude : float\n    Force amplitude Q* ≤ μP (N).",
)
def unloading_displacement(force, amplitude, load, radius, materials, friction):
    """δ on the unloading branch from (δ*, Q*) down to Q (Masing construction).

    δ = δ* − 2 δ_mono((Q* − Q)/2); the reloading branch is its point reflection,
    δ_reload(Q) = −δ_unload(−Q).
    """
    peak = tangential_displacement(amplitude, load, radius, materials, friction)
    half = (amplitude - np.asarray(force, dtype=float)) / 2.0
    return peak - 2.0 * tangential_displacement(half, load, radius, materials, friction)


@_contact(
    "numpy.ndarray\n    Energy per cycle W (mJ = N·mm).",
    "amplitude : float or array_like\n    Force amplitude Q* ≤ μP (N).",
)
def partial_slip_energy(amplitude, load, radius, materials, friction) -> np.ndarray:
    """Energy dissipated per cycle between ±Q* < μP, Mindlin–Deresiewicz (Johnson Eq. 7.53).

    W = (9 (μP)² S / (10 a)) [1 − (1 − q)^{5/3} − (5q/6)(1 + (1 − q)^{2/3})], q = Q*/μP,
    from W = 4 Q* δ* − 8 ∫₀^{Q*} δ_mono(u) du (the module docstring derives it).
    """
    slip, limit = _scale(load, radius, materials, friction)
    # 9 L² S / (10 a) = (24/5) L δ_slip
    return 4.8 * limit * slip * _energy_bracket(_ratio(amplitude, limit))


def _energy_bracket(q) -> np.ndarray:
    """1 − (1 − q)^{5/3} − (5q/6)(1 + (1 − q)^{2/3}), q = Q*/μP in [0, 1]."""
    return 1.0 - (1.0 - q) ** (5.0 / 3.0) - (5.0 * q / 6.0) * (1.0 + (1.0 - q) ** (2.0 / 3.0))


def energy_ratio(displacement_ratio) -> np.ndarray:
    """Fouvry's energy ratio A = W / (4 δ* Q*) against x = δ*/δ_slip.

    One curve for every load, radius, material pair and μ (K = 0): with q = 1 − (1 − x)^{3/2},
    A = 1.2 [1 − (1 − q)^{5/3} − (5q/6)(1 + (1 − q)^{2/3})] / (x q) in partial slip (x ≤ 1),
    A = (0.8 + 4 (x − 1)) / (4x) in gross slip. The partial/gross boundary of a measured loop
    is where A crosses 0.2.

    Parameters
    ----------
    displacement_ratio : float or array_like
        x = δ*/δ_slip (dimensionless, > 0).

    Returns
    -------
    numpy.ndarray
        A (dimensionless): 0.2 at x = 1, → 1 as x → ∞.
    """
    x = np.asarray(displacement_ratio, dtype=float)
    if np.any(x <= 0.0):
        raise ValueError("displacement_ratio δ*/δ_slip must be > 0")
    partial_x = np.minimum(x, 1.0)
    q = 1.0 - (1.0 - partial_x) ** 1.5
    partial = 1.2 * _energy_bracket(q) / (partial_x * q)
    gross = (0.8 + 4.0 * (np.maximum(x, 1.0) - 1.0)) / (4.0 * np.maximum(x, 1.0))
    return np.where(x <= 1.0, partial, gross)


@_contact(
    "numpy.ndarray\n    Energy per cycle W (mJ).",
    "amplitude : float or array_like\n    Force amplitude Q* (N).",
)
def partial_slip_energy_small_amplitude(amplitude, load, radius, materials, friction):
    """W ≈ S Q*³ / (36 a μP), the leading term for Q* ≪ μP (Johnson Eq. 7.54)."""
    a = hertz_contact_radius(load, radius, materials.contact_modulus)
    amplitude = np.asarray(amplitude, dtype=float)
    return compliance_sum(materials) * amplitude**3 / (36.0 * a * friction * load)


@_contact(
    "numpy.ndarray\n    Energy per cycle W (mJ).",
    "displacement_amplitude : float or array_like\n    δ* ≥ δ_slip (mm).",
)
def gross_slip_energy(displacement_amplitude, load, radius, materials, friction):
    """Energy per cycle under a displacement amplitude δ* ≥ δ_slip (gross slip).

    W = W_MD(Q* = μP) + 4 μP (δ* − δ_slip), with W_MD(μP) = 0.8 μP δ_slip.
    """
    slip, limit = _scale(load, radius, materials, friction)
    excess = np.asarray(displacement_amplitude, dtype=float) - slip
    if np.any(excess < -1e-12 * slip):
        raise ValueError(f"gross slip needs δ* ≥ δ_slip = {slip:g} mm")
    return 0.8 * limit * slip + 4.0 * limit * np.maximum(excess, 0.0)


@_contact("numpy.ndarray\n    Q* (N).", _DISPLACEMENT_AMPLITUDE)
def force_amplitude(displacement_amplitude, load, radius, materials, friction):
    """The force amplitude Q* reached under a displacement amplitude δ*: Q(δ*) or μP."""
    return tangential_force(displacement_amplitude, load, radius, materials, friction)


@_contact(
    "numpy.ndarray\n"
    "    Energy per cycle W (mJ): Mindlin–Deresiewicz below δ_slip, gross slip above.",
    _DISPLACEMENT_AMPLITUDE,
)
def energy_per_cycle(displacement_amplitude, load, radius, materials, friction):
    """Energy per stabilised cycle under a displacement amplitude δ*, in either regime."""
    slip, _ = _scale(load, radius, materials, friction)
    d = np.asarray(displacement_amplitude, dtype=float)
    partial = partial_slip_energy(
        force_amplitude(np.minimum(d, slip), load, radius, materials, friction),
        load,
        radius,
        materials,
        friction,
    )
    gross = gross_slip_energy(np.maximum(d, slip), load, radius, materials, friction)
    return np.where(d < slip, partial, gross)


@documented(
    "(numpy.ndarray, numpy.ndarray)\n    δ (mm) and Q (N) around the loop.",
    *_CONTACT,
    masing.LOOP_OPTIONS,
)
def fretting_loop(load, radius, materials, friction, **loop):
    """The sphere's stabilised fretting loop (δ, Q), closed, starting and ending at (δ*, Q*).

    :func:`engine.reference.masing.fretting_loop` on the Cattaneo–Mindlin curve
    (:func:`tangential_displacement`, inverted by :func:`tangential_force`): the unloading
    branch runs from (δ*, Q*) to (−δ*, −Q*) (Masing curve, then sliding at Q = −μP in gross
    slip); the reloading branch is its point reflection.
    """
    contact = (load, radius, materials, friction)
    _, limit = _scale(*contact)
    return masing.fretting_loop(
        lambda force: tangential_displacement(force, *contact),
        limit,
        inverse=lambda displacement: tangential_force(displacement, *contact),
        **loop,
    )


@documented(
    "engine.reference.masing.FrettingReference\n"
    "    δ_slip, Q*(δ*), the energy per cycle (Mindlin–Deresiewicz, gross slip), the loop.",
    *_CONTACT,
)
def fretting_reference(load, radius, materials, friction):
    """The sphere's closed forms under fretting at the load P, as one object: the
    Cattaneo–Mindlin curve, its inverse and the Mindlin–Deresiewicz energy
    (:func:`partial_slip_energy`), Fouvry's master curve (:func:`energy_ratio`)."""
    contact = (load, radius, materials, friction)
    _, limit = _scale(*contact)
    return masing.FrettingReference(
        "Mindlin–Deresiewicz",
        lambda force: tangential_displacement(force, *contact),
        limit,
        inverse=lambda displacement: tangential_force(displacement, *contact),
        loop_energy=lambda amplitude: float(partial_slip_energy(amplitude, *contact)),
        master_curve=energy_ratio,
    )
