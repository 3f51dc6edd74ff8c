"""The protocol of a fatigue criterion, and its result on a stress history.

A criterion is a class with four class attributes and one method:

- ``name``: its key in ``engine.fatigue.CRITERIA`` and in a study's ``[fatigue]`` ``criteria``;
- ``column``: the summary column of its hot-spot value (``crossland_risk``, ``swt`` …), from
  which the columns ``<column>_x``, ``<column>_z``, ``<column>_critical`` and, where the
  criterion gives them, ``<column>_angle`` and ``<column>_life`` are named;
- ``unit``: the unit of its value ("1" for a risk, "MPa", …);
- ``constants``: its material constants, all required (no defaults), one
  :class:`engine.keys.Key` each ({name: Key}): the unit ("MPa" or "1"), what the constant
  is in one phrase (the study-file reference of the manual) and, where a real material's
  constant lies in a known range, its bounds and why (``minimum``, ``maximum``, ``why``; a
  study-file value outside is refused, naming the key and why; :data:`STRENGTH`,
  :data:`BASQUIN`, :data:`COFFIN_MANSON` are the common ones, ``Key("MPa", "yield
  strength", **STRENGTH)``);
- ``description`` [its name]: what its value is, one phrase (the results' descriptions of
  its columns and datasets, the reference of the manual);
- ``reports_angle``, ``reports_life`` [False]: whether its field carries a critical-plane
  angle and a life (then the columns ``_angle`` and ``_life`` exist);
- ``evaluate(history) -> CriterionField``: its value at every point of a ``StressHistory``,
  vectorised over points (and planes, instants);
- with ``reports_life``: ``life(value) -> cycles``, the life of values of the criterion (the
  report reads the life of the critical-distance value with it).

``FatigueCriterion`` implements the constructor shared by the four bundled criteria:
``Criterion(constants, elasticity, options)`` checks that ``constants`` holds exactly the
names the class's ``constants`` declares (finite numbers) and keeps them as attributes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from engine.keys import Key

from .history import Elasticity, StressHistory
from .quantities import AMPLITUDE_METHODS, check_plane_step

__all__ = [
    "CriterionField",
    "FatigueCriterion",
    "FatigueLimitCriterion",
    "FatigueOptions",
    "STRENGTH",
    "BASQUIN",
    "COFFIN_MANSON",
]

# The magnitudes a material constant can take (a value outside is a typo or a unit slip: MPa
# given in Pa, a percentage for a fraction): the bounds of its Key and the reason printed when
# a value passes them, ``Key("MPa", meaning, **STRENGTH)``.
STRENGTH = {
    "minimum": 0.0,
    "maximum": 1e5,
    "why": "100 GPa: above the strength of any engineering material",
}
BASQUIN = {
    "minimum": -1.0,
    "maximum": 0.0,
    "why": "Basquin exponents of metals lie in -0.05 … -0.2",
}
COFFIN_MANSON = {
    "minimum": -2.0,
    "maximum": 0.0,
    "why": "Coffin-Manson exponents of metals lie in -0.4 … -0.9",
}


@dataclass(frozen=True)
class FatigueOptions:
    """How the shared quantities are computed: ``amplitude_method`` of √J2,a ("chord": half
    the longest chord, default; "ball": the minimum circumscribed ball) and ``plane_step``
    (deg), the resolution of the critical-plane search (a divisor of 180)."""

    amplitude_method: str = "chord"
    plane_step: float = 1.0

    def __post_init__(self) -> None:
        if self.amplitude_method not in AMPLITUDE_METHODS:
            raise ValueError(
                f"amplitude_method must be one of {AMPLITUDE_METHODS}, "
                f"got {self.amplitude_method!r}"
            )
        check_plane_step(self.plane_step)


@dataclass(frozen=True)
class CriterionField:
    """A criterion's ``value`` at every point (shape (n_points,), in the criterion's unit),
    the critical-plane ``angle`` (deg, module ``quantities``; None for invariant criteria)
    and the predicted ``life`` (cycles; None where the criterion gives none)."""

    value: np.ndarray
    angle: np.ndarray | None = None
    life: np.ndarray | None = None

    def take(self, points) -> CriterionField:
        """The field at a subset of the points."""
        return CriterionField(
            self.value[points],
            None if self.angle is None else self.angle[points],
            None if self.life is None else self.life[points],
        )


class FatigueCriterion:
    """Base class of a fatigue criterion (the protocol: module docstring of
    ``engine.fatigue.base``). A subclass sets the class attributes and implements
    :meth:`evaluate`; a criterion of another package registers under the entry-point group
    ``fretting_engine.criteria`` (``engine.plugins``).

    Parameters
    ----------
    constants : mapping of str to float
        The material constants, exactly the names the class's ``constants`` declares
        (finite numbers, each in its Key's unit); kept as attributes.
    elasticity : engine.fatigue.Elasticity
        E (MPa) and ν of the flat, for the criteria that need strains.
    options : engine.fatigue.FatigueOptions, optional
        How the shared quantities are computed (amplitude method, plane step).
    """

    name: ClassVar[str]
    column: ClassVar[str]
    unit: ClassVar[str]
    constants: ClassVar[Mapping[str, Key]]
    description: ClassVar[str] = ""
    reports_angle: ClassVar[bool] = False
    reports_life: ClassVar[bool] = False

    def __init__(
        self,
        constants: Mapping[str, float],
        elasticity: Elasticity,
        options: FatigueOptions | None = None,
    ):
        missing = [key for key in self.constants if key not in constants]
        if missing:
            raise ValueError(
                f"fatigue criterion {self.name!r} needs the constants {list(self.constants)}; "
                f"missing {missing}"
            )
        for key in self.constants:
            value = constants[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"fatigue constant {key!r} must be a number, got {value!r}")
            if not math.isfinite(value):
                raise ValueError(f"fatigue constant {key!r} must be finite, got {value!r}")
            setattr(self, key, float(value))
        self.elasticity = elasticity
        self.options = options or FatigueOptions()
        self.check()

    def check(self) -> None:
        """Further checks of the constants (a subclass raises ValueError naming the key)."""

    def _require_positive(self, *keys: str) -> None:
        for key in keys:
            if not getattr(self, key) > 0.0:
                raise ValueError(
                    f"fatigue constant {key!r} must be > 0, got {getattr(self, key)!r}"
                )

    def _require_negative(self, *keys: str) -> None:
        for key in keys:
            if not getattr(self, key) < 0.0:
                raise ValueError(
                    f"fatigue constant {key!r} must be < 0, got {getattr(self, key)!r}"
                )

    def evaluate(self, history: StressHistory) -> CriterionField:  # pragma: no cover
        """The criterion at every point of a stress history.

        Parameters
        ----------
        history : engine.fatigue.StressHistory
            Stresses (MPa), shape (n_instants, n_points, 6), at the points x, z (mm).

        Returns
        -------
        engine.fatigue.CriterionField
            Its value at every point (shape (n_points,), in ``unit``), with the
            critical-plane angle and the life where the criterion gives them.
        """
        raise NotImplementedError


class FatigueLimitCriterion(FatigueCriterion):
    """Base of the criteria calibrated on the fully reversed tension and torsion fatigue
    limits ``sigma_d`` and ``tau_d`` (MPa, both > 0): Crossland, Dang Van."""

    unit = "1"
    constants = {
        "sigma_d": Key("MPa", "fully reversed tension–compression fatigue limit", **STRENGTH),
        "tau_d": Key("MPa", "fully reversed torsion fatigue limit", **STRENGTH),
    }

    def check(self) -> None:
        self._require_positive("sigma_d", "tau_d")
