"""Physical checks: values the model cannot represent are input errors (moduli, the load as
mean pressure over the contact modulus, friction and wear coefficients, solver tolerance)."""

from __future__ import annotations

import math

from .sections import StudyConfigError, contact_modulus

MAX_TOLERANCE = 1e-2
# Moduli from soft gels (1 kPa) to a "rigid" punch modelled as 10^6 × steel: outside, the
# compliance 1/E* is so large or small that a case fails slowly (E_A = 1e-300 took 100 s per
# case before failing) or the displacements vanish in float64 round-off of the approach.
MODULUS_RANGE = (1e-3, 1e12)  # MPa
# The half-space model is linear elastic, i.e. small strains: the mean pressure P/(π a²) of
# the flat punch must stay below 10 % of the contact modulus E* (strain ~ p0/E*), and above
# 1e-12 of it (displacements below float64 resolution of the approach).
MAX_PRESSURE_OVER_MODULUS = 0.1
MIN_PRESSURE_OVER_MODULUS = 1e-12
# Friction coefficients of real contacts lie below ~2 (clean metals in vacuum up to ~5); far
# above, the contact sticks everywhere and μ·p overflows nothing but the user's intent.
MAX_FRICTION = 10.0
# Archard-type wear coefficients (1/MPa) of fretting tests are 1e-9 … 1e-6 (Section 7: 1.33e-7);
# at 1e-3 a contact at 100 MPa slipping 1 µm wears 0.1 µm per cycle, 10^4 × the severest
# measured, and the cycle jump degenerates into single cycles.
MAX_WEAR_COEFFICIENT = 1e-3  # 1/MPa

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
    "subsurface.layers": (1024, "depth layers of the stress plane: 1024 resolve it to 0.1 %"),
    "subsurface.depth": (100.0, "stresses 100 radii deep are below 1e-4 of the mean pressure"),
    "solver.maxiter": (10**7, "iterations per increment: a solve not converged in 10^7 will not"),
    "solver.threads": (1024, "FFT threads per rank: more than the cores of a node only slow"),
}


def bound(key: str) -> dict:
    """Keyword arguments ``maximum`` and ``why`` of :class:`reader.Section` for ``key``."""
    maximum, why = BOUNDS[key]
    return {"maximum": maximum, "why": why}


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
    mean_pressure = loading.load / (math.pi * punch.radius**2)
    ratio = mean_pressure / modulus
    if not MIN_PRESSURE_OVER_MODULUS <= ratio <= MAX_PRESSURE_OVER_MODULUS:
        raise StudyConfigError(
            source,
            "loading.load",
            loading.load,
            f"mean pressure P/(π a²) = {mean_pressure:.3g} MPa is {ratio:.3g} × the contact "
            f"modulus E* = {modulus:.3g} MPa; the linear-elastic half-space needs "
            f"{MIN_PRESSURE_OVER_MODULUS:g} ≤ p0/E* ≤ {MAX_PRESSURE_OVER_MODULUS:g} "
            "(small strains)",
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
