"""Small input checks shared by every layer: each error names the parameter and its value."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np


def require_finite(name: str, value: float) -> float:
    """Return ``value`` as float, or raise ``ValueError`` if it is NaN, infinite or not a number."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(number):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return number


def require_positive(name: str, value: float) -> float:
    number = require_finite(name, value)
    if number <= 0.0:
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return number


def require_non_negative(name: str, value: float) -> float:
    number = require_finite(name, value)
    if number < 0.0:
        raise ValueError(f"{name} must be >= 0, got {value!r}")
    return number


def require_poisson(name: str, value: float) -> float:
    number = require_finite(name, value)
    if not -1.0 < number < 0.5:
        raise ValueError(f"{name} must lie in (-1, 0.5), got {value!r}")
    return number


def require_finite_array(name: str, array: np.ndarray) -> np.ndarray:
    array = np.asarray(array, dtype=float)
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return array


def check_fields(record, check, *names: str) -> None:
    """Replace each named field of the frozen dataclass ``record`` by ``check(name, value)``.

    For ``__post_init__``: ``check`` returns the value converted (float, int …) or raises
    ``ValueError`` naming the field and its value; the fields are checked in order.
    """
    for name in names:
        object.__setattr__(record, name, check(name, getattr(record, name)))


def under_key(key: str, check: Callable[[str, Any], Any]) -> Callable[[str, Any], Any]:
    """``check`` for a :class:`CheckedRecord` field whose errors name the user's ``key`` (the
    study-file name) instead of the field's own name."""
    return lambda _field, value: check(key, value)


class CheckedRecord:
    """Base of frozen dataclasses whose fields are checked and converted on creation.

    A subclass sets ``checks``, a table from field name to ``check(name, value)`` (which
    returns the value converted or raises ``ValueError`` naming the field and its value);
    ``__post_init__`` applies them in the table's order. A subclass with further checks calls
    ``super().__post_init__()`` first.
    """

    checks: ClassVar[dict[str, Callable[[str, Any], Any]]] = {}

    def __post_init__(self) -> None:
        for name, check in self.checks.items():
            object.__setattr__(self, name, check(name, getattr(self, name)))
