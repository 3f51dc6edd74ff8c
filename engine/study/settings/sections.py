"""The configuration's records: one frozen dataclass per section of the study file, the error
every check raises, and the constants the sections share (shapes, kinds, laws, sweepable keys).

Units are those of the paper (Juliá & Rodríguez-Tembleque 2023, Section 7): mm, N, MPa, wear
coefficients in 1/MPa, angles in degrees.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from engine.geometry import DEFAULT_SHAPE, PROFILES, Profile, profile_for
from engine.keys import Key
from engine.solvers.friction import PROPORTIONAL
from engine.solvers.wear_laws import DEFAULT_WEAR_LAW, WEAR_LAWS

# Every name here is public and re-exported by the package (engine.study.config).
__all__ = [
    "StudyConfigError",
    "StudyInfo",
    "MaterialConfig",
    "PunchConfig",
    "MeshConfig",
    "LoadingConfig",
    "loading_key",
    "loading_list",
    "DEFAULT_STEPS",
    "STEPS_BOUNDS",
    "steps_key",
    "WearConfig",
    "SubsurfaceConfig",
    "SweepAxis",
    "SweepConfig",
    "SolverConfig",
    "TestingConfig",
    "contact_modulus",
    "MISSING",
    "PROPORTIONAL",
    "PUNCH_SHAPES",
    "WEAR_LAWS",
]

PUNCH_SHAPES = tuple(PROFILES)  # the contact geometries (engine.geometry.PROFILES)


class StudyConfigError(ValueError):
    """Bad study file: carries the file, the dotted key and the value it refers to (key
    ``""``: the file as a whole, e.g. not found or not TOML)."""

    def __init__(self, source: str, key: str, value: Any, problem: str) -> None:
        self.source = source
        self.key = key
        self.value = value
        self.problem = problem
        section, _, name = key.partition(".")
        where = f"[{section}] {name}" if name else f"[{section}]"
        shown = "" if value is MISSING else f" = {_shown(value)}"
        if not key:
            super().__init__(f"{source}: {problem}")
            return
        super().__init__(f"{source}: {where}{shown}: {problem}")


MOST_SHOWN = 120  # characters of a refused value in a message (a list of 10^5 values is long)


def _shown(value: Any) -> str:
    """``repr(value)``, its start and end only when long (one line whatever the input)."""
    text = repr(value)
    if len(text) <= MOST_SHOWN:
        return text
    size = f", {len(value)} items" if isinstance(value, list | tuple | dict) else ""
    half = MOST_SHOWN // 2
    return f"{text[:half]} … {text[-half // 2 :]} ({len(text)} characters{size})"


MISSING = object()  # "no value given" (distinct from None)


@dataclass(frozen=True)
class StudyInfo:
    name: str
    output: Path
    output_strategy: str = "auto"

    @property
    def summary_path(self) -> Path:
        return self.output.with_suffix(".csv")

    @property
    def checkpoint_dir(self) -> Path:
        return self.output.with_name(self.output.name + ".checkpoints")


@dataclass(frozen=True)
class MaterialConfig:
    E_A: float
    nu_A: float
    E_B: float
    nu_B: float


@dataclass(frozen=True)
class PunchConfig:
    """``[punch]``: the ``shape`` (a name of :data:`engine.geometry.PROFILES`) and the values
    of the keys its profile declares (``keys``: (name, value) pairs in the order of the
    profile's fields; units as the profile declares them)."""

    shape: str
    keys: tuple[tuple[str, float], ...]

    def __getattr__(self, name: str) -> float:
        """A key of the profile by name (``punch.radius``)."""
        for key, value in self.__dict__.get("keys", ()):
            if key == name:
                return value
        raise AttributeError(f"the {self.__dict__.get('shape')!r} punch has no key {name!r}")

    def resolved(self) -> dict[str, object]:
        """The section as the results file stores it: the first key, ``shape`` (left out
        for :data:`engine.geometry.DEFAULT_SHAPE`, so that older results files resume),
        then the other keys (the order studies have always been stored in)."""
        keys = dict(self.keys)
        first = dict(list(keys.items())[:1])
        shape = {} if self.shape == DEFAULT_SHAPE else {"shape": self.shape}
        return first | shape | keys

    @property
    def is_line(self) -> bool:
        """A plane-strain line contact (a cylinder or a rounded pad on a flat)."""
        return PROFILES[self.shape].is_line

    @property
    def load_unit(self) -> str:
        """Unit of the load and the tangential force: N (a line contact's: N/mm)."""
        return PROFILES[self.shape].load_unit

    def profile(self) -> Profile:
        """The :mod:`engine.geometry` profile of this punch (:data:`PROFILES`)."""
        return profile_for(self.shape, **dict(self.keys))


@dataclass(frozen=True)
class MeshConfig:
    n: int
    half_width: float
    reference_distance: float | None = None  # line contacts: the displacement datum (mm)


#: ``[loading] steps`` when absent, whatever the kind, and its bounds (:class:`Key` fields).
DEFAULT_STEPS = 10
STEPS_BOUNDS = {
    "minimum": 1,
    "maximum": 10_000,
    "why": "increments per half cycle (fretting: per quarter), each a full contact solve: "
    "10^4 resolve any loading path",
}


def loading_key(
    unit: str,
    meaning: str,
    *,
    default: Any = None,
    optional: bool = False,
    absent: str = "",
    label: str = "",
    **bounds: Any,
) -> Any:
    """A field of a loading kind's ``[loading]`` dataclass declaring its number
    (:class:`engine.keys.Key` in the field's metadata: ``unit``, ``meaning``, ``default``,
    ``label`` and the ``bounds``); the study-file reference of the manual and its limits
    table are written from it (:func:`engine.study.config.keys.loading_keys`).

    ``bounds`` are the Key's ``minimum``, ``strict`` (an open minimum), ``maximum`` and
    ``why``; the kind's parser reads them (:func:`engine.study.settings.checks.bound_of`).
    ``default`` is the key's value when absent (also the field's default); ``optional``
    gives the field the default None (a key that may stay unset, e.g. one of two controls),
    and ``absent`` says in the reference what holds then ("one of the two"). ``label`` is
    the key's short name on figure axes ("normal load P"). The field is keyword-only, so that
    a kind's dataclass may add required keys after those with defaults, and may declare a
    key of its parent again with its own meaning (the field keeps its place).
    """
    key = Key(unit, meaning, default=default, label=label, **bounds)
    metadata = {"key": key, "absent": absent} if absent else {"key": key}
    if optional:
        return field(default=None, kw_only=True, metadata=metadata)
    if default is not None:
        return field(default=default, kw_only=True, metadata=metadata)
    return field(kw_only=True, metadata=metadata)


def steps_key(meaning: str) -> Any:
    """The field ``steps`` (load increments, default :data:`DEFAULT_STEPS`, bounds
    :data:`STEPS_BOUNDS`) with what it counts for a kind: every kind declares it, each with
    its ``meaning`` ("load increments per half cycle")."""
    return loading_key("1", meaning, default=DEFAULT_STEPS, label="load increments", **STEPS_BOUNDS)


def loading_list(meaning: str, *, absent: str) -> Any:
    """A field of a loading kind's ``[loading]`` dataclass that holds a list, not a sweepable
    number: its ``meaning`` and what holds when it is absent (``absent``, e.g. ``"[cycles]"``),
    for the study-file reference of the manual. The kind's :meth:`parse` fills it in."""
    return field(metadata={"meaning": meaning, "absent": absent})


@dataclass(frozen=True)
class LoadingConfig:
    """The ``[loading]`` keys every kind reads: ``kind`` (the name of the kind), the load and
    the increments of a loading. A kind with more keys extends this dataclass with its own
    fields (:attr:`engine.study.kinds.LoadingKind.config`); the static kind reads just these.
    """

    kind: str
    load: float = loading_key("N", "peak normal load P", label="normal load P")
    steps: int = steps_key("load increments of the loading")


@dataclass(frozen=True)
class WearConfig:
    """``law``: a name of :data:`engine.solvers.wear_laws.WEAR_LAWS`: "archard" (the paper's
    orthotropic law, Eq. 12–14, coefficients wear1/wear2 in 1/MPa), "energy"
    (dissipated-energy law, coefficient alpha in mm³/J) or a registered plug-in's."""

    law: str = DEFAULT_WEAR_LAW
    pad_coefficient: float | None = None  # line contacts: the pad's wear coefficient


@dataclass(frozen=True)
class SubsurfaceConfig:
    depth: float
    layers: int


@dataclass(frozen=True)
class SweepAxis:
    """One axis of the product: a single dotted key, or a zip group of keys varying together.
    ``values[i]`` holds one value per key at list position i."""

    keys: tuple[str, ...]
    values: tuple[tuple[float | int | str, ...], ...]  # str: a text key (SWEEPABLE_TEXT)

    def __len__(self) -> int:
        return len(self.values)


@dataclass(frozen=True)
class SweepConfig:
    """The ``[sweep]`` lists: friction coefficients ``mu1``, ``mu2`` (None: mu2 = mu1), the
    coefficients of the wear law ``law`` as its ``read_sweep`` returns them (``wear``:
    ((coefficient, list or a rule's text or None), ...) in the law's order), the axes angles
    ``beta`` (degrees) and the axes of swept dotted keys."""

    mu1: tuple[float, ...]
    mu2: tuple[float, ...] | None
    beta: tuple[float, ...]
    axes: tuple[SweepAxis, ...] = ()
    law: str = DEFAULT_WEAR_LAW
    wear: tuple[tuple[str, Any], ...] = ()

    @property
    def wear_lists(self) -> dict[str, Any]:
        """{coefficient: its list (or rule)} of the wear law."""
        return dict(self.wear)

    @property
    def swept_keys(self) -> tuple[str, ...]:
        """Dotted keys of the other sections swept here, in axis order."""
        return tuple(key for axis in self.axes for key in axis.keys)

    def resolved(self) -> dict[str, Any]:
        """TOML-able: the friction/wear lists, then every dotted key, then the zip groups."""
        out: dict[str, Any] = {"mu1": list(self.mu1)}
        if self.mu2 is not None:
            out["mu2"] = list(self.mu2)
        # the default law's coefficients before beta, another law's after it (the order of
        # the case parameters)
        coefficients = WEAR_LAWS[self.law].resolved(self.wear_lists)
        if self.law == DEFAULT_WEAR_LAW:
            out.update(coefficients)
        out["beta"] = list(self.beta)
        if self.law != DEFAULT_WEAR_LAW:
            out.update(coefficients)
        for axis in self.axes:
            for position, key in enumerate(axis.keys):
                out[key] = [values[position] for values in axis.values]
        groups = [list(axis.keys) for axis in self.axes if len(axis.keys) > 1]
        if groups:
            out["zip"] = groups
        return out


@dataclass(frozen=True)
class SolverConfig:
    tol: float
    maxiter: int
    threads: int
    fft_planner: str = "estimate"

    @property
    def planner_effort(self) -> str:
        """FFTW planner flag: "estimate" gives the same plan (bit-identical results) in every
        process and run; "measure" times candidate plans (faster, last-digit differences)."""
        return "FFTW_" + self.fft_planner.upper()


@dataclass(frozen=True)
class TestingConfig:
    fail_cases: tuple[str, ...]


def contact_modulus(material: MaterialConfig) -> float:
    """E* = ((1−ν_A²)/E_A + (1−ν_B²)/E_B)⁻¹, MPa (Eq. 6)."""
    return 1.0 / ((1.0 - material.nu_A**2) / material.E_A + (1.0 - material.nu_B**2) / material.E_B)
