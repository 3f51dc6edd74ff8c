"""The ranges a study file's numbers must lie in, declared once (:data:`LIMITS`, read by the
parser through :func:`bound` and written into the manual's limits table), and the physical
checks: values the model cannot represent are input errors (moduli, the load as mean pressure
over the contact modulus, friction and wear coefficients, solver tolerance)."""

from __future__ import annotations

from dataclasses import dataclass

from engine.keys import LENGTH_REASON, MAX_LENGTH, Key
from engine.solvers.friction import MAX_ENERGY_WEAR_COEFFICIENT, MAX_WEAR_COEFFICIENT
from engine.solvers.wear_laws import WEAR_LAWS

from .sections import StudyConfigError, contact_modulus

MAX_TOLERANCE = 1e-2
# Below the rounding of float64 (ε = 2.2e-16) no solve can show its relative residual is that
# small: tol = 1e-20 ran 35 s on a 32 × 32 static case and failed, 1e-16 converged (2.5 s).
MIN_TOLERANCE = 1e-16
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
# The wear coefficients' ranges are declared by the wear laws (engine.solvers.friction, the
# [sweep] keys they read); MAX_WEAR_COEFFICIENT (Archard, 1/MPa) and
# MAX_ENERGY_WEAR_COEFFICIENT (energy, mm³/J) also bound [wear] pad_coefficient.
# Lengths (mm): MAX_LENGTH (engine.keys, where the punch profiles declare their lengths).


@dataclass(frozen=True)
class Limit:
    """The range a value of the study file must lie in, as the checks read it and the
    manual states it (``scripts/reference.py`` writes the limits table from :data:`LIMITS`).

    ``minimum``/``maximum``: the bounds (None: none), in the key's unit; ``open_minimum`` /
    ``open_maximum``: the bound itself is refused; ``why``: the reason, printed when a value
    passes the maximum and written in the manual's table.
    """

    minimum: float | None = None
    maximum: float | None = None
    why: str = ""
    open_minimum: bool = False
    open_maximum: bool = False

    def holds(self, value: float) -> bool:
        """True when ``value`` lies in the range."""
        low, high = self.minimum, self.maximum
        above = low is None or (value > low if self.open_minimum else value >= low)
        below = high is None or (value < high if self.open_maximum else value <= high)
        return above and below

    @classmethod
    def of(cls, key: Key) -> Limit:
        """The range a plug-in declares for one of its keys (:class:`engine.keys.Key`)."""
        return cls(key.minimum, key.maximum, key.why, open_minimum=key.strict)

    @property
    def accepted(self) -> str:
        """The range in the manual's notation: ``[8, 16384]``, ``(0, 10]``, ``≥ 0``, ``> 0``."""
        low, high = self.minimum, self.maximum
        if low is None:
            return f"{'<' if self.open_maximum else '≤'} {_number(high)}"
        if high is None:
            return f"{'>' if self.open_minimum else '≥'} {_number(low)}"
        left, right = "(" if self.open_minimum else "[", ")" if self.open_maximum else "]"
        return f"{left}{_number(low)}, {_number(high)}{right}"


def _number(value: float) -> str:
    """``1e-12``, ``10000``, ``1e9``: a bound as the manual and the messages write it."""
    text = f"{value:g}"
    if isinstance(value, int) and float(text) != value:
        return str(value)  # an integer :g would round (2^32 − 1)
    return text.replace("e+0", "e").replace("e+", "e")


_LENGTH = LENGTH_REASON
ANGLE_REASON = "angles in degrees, one turn either way"

#: Every range a number of the host's sections must lie in ("section.key": Limit), read by the
#: checks (:func:`bound`) and written in the manual's limits table. A key beyond the maximum
#: is a typo or a unit slip, and would otherwise run for days or fail late. The plug-ins
#: declare their own keys' ranges (``engine.keys.Key``, read through :func:`bound_of`): the
#: profiles' [punch] keys, the loading kinds' [loading] numbers, the wear laws' coefficients,
#: the fatigue criteria's constants.
LIMITS = {
    "material.E_A": Limit(*MODULUS_RANGE, "from gels to a rigid punch modelled as 10⁶ × steel"),
    "material.E_B": Limit(*MODULUS_RANGE, "from gels to a rigid punch modelled as 10⁶ × steel"),
    "material.nu_A": Limit(-1.0, 0.5, "Poisson's ratio of a stable isotropic solid", True, True),
    "material.nu_B": Limit(-1.0, 0.5, "Poisson's ratio of a stable isotropic solid", True, True),
    "mesh.n": Limit(
        8,
        16384,
        "elements per side: a 16384² grid needs about 0.8 TB of memory per rank; "
        "and at least 4 elements across the contact",
    ),
    "mesh.half_width": Limit(
        0.0, MAX_LENGTH, f"{_LENGTH}; and at least the contact length a0", open_minimum=True
    ),
    "mesh.reference_distance": Limit(
        0.0, MAX_LENGTH, f"{_LENGTH}; and at least the mesh's length 2·half_width"
    ),
    "wear.pad_coefficient": Limit(
        0.0,
        MAX_WEAR_COEFFICIENT,
        "the Archard bound of [sweep] wear1 (fretting tests: 1e-9 … 1e-6 1/MPa)",
    ),
    "wear.pad_coefficient.energy": Limit(
        0.0,
        MAX_ENERGY_WEAR_COEFFICIENT,
        "the energy-law bound of [sweep] alpha (fretting tests: 1e-6 … 1e-4 mm³/J)",
    ),
    "subsurface.depth": Limit(
        0.0,
        100.0,
        "stresses 100 radii deep are below 1e-4 of the mean pressure",
        open_minimum=True,
    ),
    "subsurface.layers": Limit(
        2, 1024, "depth layers of the stress plane: 1024 resolve it to 0.1 %"
    ),
    "sweep.mu1": Limit(0.0, MAX_FRICTION, "real contacts lie below ~2"),
    "sweep.mu2": Limit(0.0, MAX_FRICTION, "real contacts lie below ~2"),
    "sweep.beta": Limit(-360.0, 360.0, f"{ANGLE_REASON}; taken modulo 180°"),
    "solver.tol": Limit(
        MIN_TOLERANCE,
        MAX_TOLERANCE,
        "relative residual: a looser solve stops before doing anything meaningful; a finer "
        "one float64 cannot reach",
    ),
    "solver.maxiter": Limit(
        1, 10**7, "iterations per increment: a solve not converged in 10^7 will not"
    ),
    "solver.threads": Limit(
        1, 1024, "FFT threads per rank: more than the cores of a node only slow"
    ),
    "search.rtol": Limit(0.0, 0.5, "a relative tolerance on the searched value", open_maximum=True),
    "search.atol": Limit(0.0, None, "and below the bracket's width high − low"),
    "search.max_steps": Limit(
        3,
        1000,
        "cases per search: a bound on typos, far above the 27 halvings a tolerance of 1e-8 "
        "of the bracket takes",
    ),
    "calibrate.fit_rtol": Limit(
        0.0, 0.5, "relative tolerance on the fitted values", open_minimum=True, open_maximum=True
    ),
    "calibrate.max_evaluations": Limit(
        3, 10_000, "searches run per fit: each evaluation is one threshold search per test"
    ),
}


def bound(key: str) -> dict:
    """Keyword arguments ``minimum``, ``maximum``, ``why`` (and ``strict`` for an open
    minimum) of :meth:`reader.Section.number` and ``integer`` for ``key`` of :data:`LIMITS`."""
    limit = LIMITS[key]
    strict = {"strict": True} if limit.open_minimum else {}
    return {"minimum": limit.minimum, "maximum": limit.maximum, "why": limit.why} | strict


def bound_of(key: Key) -> dict:
    """:func:`bound` for a key a plug-in declares (:class:`engine.keys.Key`: a loading kind's
    ``[loading]`` number)."""
    strict = {"strict": True} if key.strict else {}
    return {"minimum": key.minimum, "maximum": key.maximum, "why": key.why} | strict


_MEAN_PRESSURE = {False: "p0 = P/(π a0²)", True: "p0 = P/(2 a0), P per unit length"}


def check_physical_ranges(source, material, punch, loading, sweep) -> None:
    """Moduli, load (as mean pressure over contact modulus), friction and wear coefficients
    inside what the model represents (see the constants above for the ranges and why)."""
    for key in ("E_A", "E_B"):
        value, limit = getattr(material, key), LIMITS[f"material.{key}"]
        if not limit.holds(value):
            raise StudyConfigError(
                source,
                f"material.{key}",
                value,
                f"must lie in {limit.accepted} MPa (from gels to a rigid punch modelled as "
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
        limit = LIMITS[f"sweep.{key}"]
        for value in getattr(sweep, key, None) or ():
            if not limit.holds(value):
                raise StudyConfigError(
                    source,
                    f"sweep.{key}",
                    value,
                    f"friction coefficient must lie in {limit.accepted} (real contacts: below ~2)",
                )
    law = WEAR_LAWS[sweep.law]
    for name, values in sweep.wear:
        key = law.coefficients[name]
        limit = Limit.of(key)
        for value in values if isinstance(values, tuple) else ():
            if not limit.holds(value):
                raise StudyConfigError(
                    source,
                    f"sweep.{name}",
                    value,
                    f"wear coefficient must lie in {limit.accepted} {key.unit} ({key.why})",
                )
