"""How a plug-in declares the keys it reads from a study file: unit, meaning and bounds.

A plug-in owns its vocabulary. A punch profile's ``[punch]`` keys are the fields of its
dataclass, each carrying a :class:`Key` in the field's metadata (:func:`parameter`,
:func:`length`); a wear law declares its coefficients and a fatigue criterion its constants
as :class:`Key` tables. The study-file parser reads a key through its declaration
(:meth:`Key.read`), and every table of the host (the units of the sweepable keys and of the
case parameters, the study-file reference of the manual) is derived from the declarations,
never copied beside them.

This module sits below every plug-in and imports nothing of the engine.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

__all__ = [
    "Key",
    "parameter",
    "length",
    "declared_keys",
    "examples",
    "merge_units",
    "MAX_LENGTH",
    "LENGTH_REASON",
]

#: Upper bound of every length of the study file (mm): 10 m is beyond any contact the
#: half-space model describes; further out the mean pressure and the influence coefficients
#: leave float64's useful range (1e300 overflowed).
MAX_LENGTH = 1e4  # mm
LENGTH_REASON = "10 m: larger than any contact this half-space model describes"


@dataclass(frozen=True)
class Key:
    """One key a plug-in reads from its section of the study file.

    Parameters
    ----------
    unit : str
        Unit of the value (UDUNITS-style, "1" dimensionless), e.g. ``"mm"``.
    meaning : str
        What the key sets, one sentence for the reference of the manual (Markdown).
    minimum : float or None
        Lower bound (None: none).
    strict : bool
        The value must exceed ``minimum`` (else it may equal it).
    maximum : float or None
        Upper bound (None: none).
    why : str
        Why the maximum is there (printed when a value passes it).
    default : float or None
        Value when the key is absent; None: the key is required.
    example : float or None
        A typical value (the conformance tests build every registered plug-in with its
        examples); None: the default.
    label : str
        A short name for figure axes and tables ("normal load P"); "": the meaning up to its
        first parenthesis, comma or semicolon.
    """

    unit: str
    meaning: str
    minimum: float | None = None
    strict: bool = False
    maximum: float | None = None
    why: str = ""
    default: float | None = None
    example: float | None = None
    label: str = ""

    @property
    def required(self) -> bool:
        return self.default is None

    def read(self, section, name: str) -> float:
        """The value of key ``name`` in ``section`` (an ``engine.study.settings.reader.Section``):
        a finite number within the bounds; a missing required key, or a value out of bounds,
        raises the section's error naming the key and the value."""
        given = {} if self.default is None else {"default": self.default}
        return section.number(
            name,
            **given,
            minimum=self.minimum,
            strict=self.strict,
            unit=self.unit if self.unit != "1" else "",
            maximum=self.maximum,
            why=self.why,
        )

    def check(self, name: str, value: Any) -> float:
        """``value`` as a float within the bounds, or ValueError naming ``name`` and the value
        (what a plug-in's constructor checks when it is built outside a study file)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{name} must be a number, got {value!r}")
        number = float(value)
        if number != number or number in (float("inf"), float("-inf")):
            raise ValueError(f"{name} must be finite, got {value!r}")
        if self.minimum is not None:
            if self.strict and not number > self.minimum:
                raise ValueError(f"{name} must be > {self.minimum:g}, got {value!r}")
            if not self.strict and not number >= self.minimum:
                raise ValueError(f"{name} must be >= {self.minimum:g}, got {value!r}")
        if self.maximum is not None and number > self.maximum:
            raise ValueError(f"{name} must be <= {self.maximum:g}, got {value!r}")
        return number

    @property
    def bounds(self) -> str:
        """The bounds in words for the reference ("> 0, ≤ 10000"), "" without any."""
        parts = []
        if self.minimum is not None:
            parts.append(f"{'>' if self.strict else '≥'} {self.minimum:g}")
        if self.maximum is not None:
            parts.append(f"≤ {self.maximum:g}")
        return ", ".join(parts)


def parameter(unit: str, meaning: str, **bounds: Any) -> Any:
    """A dataclass field declaring a key of the study file in its metadata.

    Parameters
    ----------
    unit : str
        Unit of the value ("1" dimensionless).
    meaning : str
        What the key sets, one sentence for the reference.
    **bounds
        The other fields of :class:`Key`: ``minimum``, ``strict``, ``maximum``, ``why``,
        ``default`` (also the field's default), ``example``, ``label``.

    Returns
    -------
    dataclasses.Field
        For a profile's class body: ``angle: float = parameter("degree", "flank angle",
        minimum=0.0, strict=True, example=1.0)``.
    """
    key = Key(unit, meaning, **bounds)
    if key.default is None:
        return dataclasses.field(metadata={"key": key})
    return dataclasses.field(default=key.default, metadata={"key": key})


def length(
    meaning: str, *, example: float, strict: bool = True, default: float | None = None
) -> Any:
    """A dataclass field declaring a length key (mm), at most ``MAX_LENGTH``.

    Parameters
    ----------
    meaning : str
        What the length is, one sentence for the reference.
    example : float
        A typical value (mm).
    strict : bool, optional
        The length must be > 0 (default), else ≥ 0.
    default : float, optional
        Value when the key is absent; without one the key is required.

    Returns
    -------
    dataclasses.Field
        ``radius: float = length("sphere radius R", example=10.0)``.
    """
    return parameter(
        "mm",
        meaning,
        minimum=0.0,
        strict=strict,
        maximum=MAX_LENGTH,
        why=LENGTH_REASON,
        default=default,
        example=example,
    )


def examples(cls) -> dict[str, float]:
    """{name: typical value} of the keys the dataclass ``cls`` declares (each key's
    ``example``, else its default): a valid instance is ``cls(**examples(cls))``."""
    return {
        name: key.default if key.example is None else key.example
        for name, key in declared_keys(cls).items()
    }


def declared_keys(cls) -> dict[str, Key]:
    """{name: :class:`Key`} of the fields of the dataclass ``cls`` that declare a key, in the
    order of the fields."""
    return {
        field.name: field.metadata["key"]
        for field in dataclasses.fields(cls)
        if "key" in field.metadata
    }


def merge_units(tables, what: str) -> dict[str, str]:
    """One {key: unit} table from ``tables``, an iterable of (owner, {key: unit}): a key two
    owners declare with different units is an error naming both (``what``: the kind of key,
    in the message)."""
    units: dict[str, str] = {}
    owners: dict[str, str] = {}
    for owner, table in tables:
        for key, unit in table.items():
            if key in units and units[key] != unit:
                raise ValueError(
                    f"{what} {key!r} has the unit {units[key]!r} in {owners[key]} and "
                    f"{unit!r} in {owner}: one key, one unit"
                )
            units.setdefault(key, unit)
            owners.setdefault(key, owner)
    return units
