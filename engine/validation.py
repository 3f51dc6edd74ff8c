"""Small input checks shared by every layer: each error names the parameter and its value."""

from __future__ import annotations

import math

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
