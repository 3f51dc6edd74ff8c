"""Physical checks: values the model cannot represent are input errors (moduli, the load as
mean pressure over the contact modulus, friction and wear coefficients, solver tolerance)."""

from __future__ import annotations

from engine.keys import LENGTH_REASON, MAX_LENGTH

from .sections import StudyConfigError, contact_modulus

MAX_TOLERANCE = 1e-2
# Moduli from soft gels (1 kPa) to a "rigid" punch modelled as 10^6 × steel: outside, the
# compliance 1/E* is so large or small that a case fails slowly (E_A = 1e-300 took 100 s per
# case before failing) or the displacements vanish in float64 round-off of the approach.
MODULUS_RANGE = (1e-3, 1e12)  # MPa
# The half-space model is linear elastic, i.e. small strains: the mean pressure p0 over the
# profile's nominal contact (P/(π a0²), or P/(2 a0) for a line contact) must stay below 10 %
# of the contact modulus E* (strain ~ p0/E*), and above 1e-12 of it (displacements below
# float64 resolution of the approach).
MAX_PRESSURE_OVER_MODULUS = 0.1
MIN_PRESSURE_OVER_MODULUS = 1e-12
# Friction coefficients of real contacts lie below ~2 (clean metals in vacuum up to ~5); far
# above, the contact sticks everywhere and μ·p overflows nothing but the user's intent.
MAX_FRICTION = 10.0
# Archard-type wear coefficients (1/MPa) of fretting tests are 1e-9 … 1e-6 (Section 7: 1.33e-7);
# at 1e-3 a contact at 100 MPa slipping 1 µm wears 0.1 µm per cycle, 10^4 × the severest
# measured, and the cycle jump degenerates into single cycles.
MAX_WEAR_COEFFICIENT = 1e-3  # 1/MPa
# The energy law's α (mm³/J) wears α·τ·s·1e-3 mm per cycle where Archard's wears k·p·s: at
# μ = 1, α = 1 mm³/J wears as fast as the Archard bound above (fretting tests: 1e-6 … 1e-4).
MAX_ENERGY_WEAR_COEFFICIENT = 1.0  # mm^3/J
# Lengths (mm): MAX_LENGTH (engine.keys, where the punch profiles declare their lengths).

# Upper bounds of the count and control keys, each with the reason printed when it is passed
# (a key beyond them is a typo or a unit slip, and would otherwise run for days or fail late).
BOUNDS = {
    "loading.steps": (
        10_000,
        "increments per half cycle, each a full contact solve: 10^4 resolve any loading path",
    ),
    "loading.cycles": (10**9, "fretting tests run 10^7 to 10^8 cycles"),
    "loading.max_wear_fraction": (
        1.0,
        "wear per cycle jump over the peak elastic approach: beyond 1 a jump removes the "
        "whole elastic approach and the jump control no longer holds",
    ),
    "mesh.n": (16384, "elements per side: a 16384² grid needs about 0.8 TB of memory per rank"),
    "mesh.half_width": (MAX_LENGTH, LENGTH_REASON),
    "mesh.reference_distance": (MAX_LENGTH, LENGTH_REASON),
    "loading.amplitude": (
        10.0,
        "fretting amplitudes lie below ~0.3 mm; beyond 10 mm the motion is reciprocating "
        "sliding, which moves the contact over the flat, and this model holds it in place",
    ),
    "loading.bulk_stress": (
        1e4,
        "in magnitude: 10 GPa is above the strength of any steel, and the flat stays linear "
        "elastic",
    ),
    "wear.pad_coefficient": (
        MAX_WEAR_COEFFICIENT,
        "the Archard bound of [sweep] wear1 (fretting tests: 1e-9 … 1e-6 1/MPa)",
    ),
    "wear.pad_coefficient.energy": (
        MAX_ENERGY_WEAR_COEFFICIENT,
        "the energy-law bound of [sweep] alpha (fretting tests: 1e-6 … 1e-4 mm³/J)",
    ),
    "subsurface.layers": (1024, "depth layers of the stress plane: 1024 resolve it to 0.1 %"),
    "subsurface.depth": (100.0, "stresses 100 radii deep are below 1e-4 of the mean pressure"),
    "solver.maxiter": (10**7, "iterations per increment: a solve not converged in 10^7 will not"),
    "solver.threads": (1024, "FFT threads per rank: more than the cores of a node only slow"),
}


def bound(key: str) -> dict:
    """Keyword arguments ``maximum`` and ``why`` of :class:`reader.Section` for ``key``."""
    maximum, why = BOUNDS[key]
    return {"maximum": maximum, "why": why}


_MEAN_PRESSURE = {False: "p0 = P/(π a0²)", True: "p0 = P/(2 a0), P per unit length"}


def check_physical_ranges(source, material, punch, loading, sweep) -> None:
    """Moduli, load (as mean pressure over contact modulus), friction and wear coefficients
    inside what the model represents (see the constants above for the ranges and why)."""
    low, high = MODULUS_RANGE
    for key in ("E_A", "E_B"):
        value = getattr(material, key)
        if not low <= value <= high:
            raise StudyConfigError(
                source,
                f"material.{key}",
                value,
                f"must lie in [{low:g}, {high:g}] MPa (from gels to a rigid punch modelled as "
                "10^6 × steel; outside, the compliance leaves float64's useful range)",
            )
    modulus = contact_modulus(material)
    profile = punch.profile()
    a0 = profile.contact_length(loading.load, modulus)
    mean_pressure = profile.mean_pressure(loading.load, a0)
    ratio = mean_pressure / modulus
    if not MIN_PRESSURE_OVER_MODULUS <= ratio <= MAX_PRESSURE_OVER_MODULUS:
        raise StudyConfigError(
            source,
            "loading.load",
            loading.load,
            f"mean pressure p0 = {mean_pressure:.3g} MPa over the nominal contact of the "
            f"{punch.shape} (a0 = {a0:.3g} mm; {_MEAN_PRESSURE[profile.is_line]}) is "
            f"{ratio:.3g} × the contact modulus E* = {modulus:.3g} MPa; the linear-elastic "
            f"half-space needs {MIN_PRESSURE_OVER_MODULUS:g} ≤ p0/E* ≤ "
            f"{MAX_PRESSURE_OVER_MODULUS:g} (small strains)",
        )
    for key in ("mu1", "mu2"):
        for value in getattr(sweep, key, None) or ():
            if value > MAX_FRICTION:
                raise StudyConfigError(
                    source,
                    f"sweep.{key}",
                    value,
                    f"friction coefficient must lie in [0, {MAX_FRICTION:g}] (real contacts: "
                    "below ~2)",
                )
    for key in ("wear1", "wear2"):
        values = getattr(sweep, key, None)
        for value in values if isinstance(values, tuple) else ():
            if value > MAX_WEAR_COEFFICIENT:
                raise StudyConfigError(
                    source,
                    f"sweep.{key}",
                    value,
                    f"wear coefficient must lie in [0, {MAX_WEAR_COEFFICIENT:g}] 1/MPa "
                    "(fretting tests: 1e-9 … 1e-6)",
                )
    for value in getattr(sweep, "alpha", None) or ():
        if value > MAX_ENERGY_WEAR_COEFFICIENT:
            raise StudyConfigError(
                source,
                "sweep.alpha",
                value,
                f"energy wear coefficient must lie in [0, {MAX_ENERGY_WEAR_COEFFICIENT:g}] "
                "mm^3/J (fretting tests: 1e-6 … 1e-4; 1 mm^3/J at μ = 1 wears as fast as "
                f"Archard's {MAX_WEAR_COEFFICIENT:g} 1/MPa)",
            )
