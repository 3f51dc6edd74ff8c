"""The outer fit: values of the fitted keys that minimise the relative errors of the
calibration tests' thresholds.

With residuals r_i(v) = predicted_i(v)/measured_i − 1 over the calibration tests:

- one fitted key: a bounded scalar minimisation of Σ r_i² (Brent's method on [low, high],
  :func:`scipy.optimize.minimize_scalar`, ``method="bounded"``), absolute tolerance
  ``fit_rtol``·(high − low) on the value;
- several: bounded non-linear least squares (:func:`scipy.optimize.least_squares`, trust
  region reflective), tolerance ``fit_rtol`` on the scaled step, finite differences of relative
  step 10·``fit_rtol``.

Each evaluation of r is a threshold search per calibration test; the searches' own tolerance
makes r piecewise smooth at the level of the search's ``rtol``: choose ``fit_rtol`` no finer
than needed. How the fit ended (:class:`FitResult.status`): ``converged``; ``at-bound`` (the
value found lies within the tolerance of a bound: the optimum may lie beyond it);
``not-converged`` (``max_evaluations`` reached); ``failed`` (a calibration test's search
failed); ``predict-only`` (no fitted key).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["FitResult", "FitFailed", "fit_values", "FIT_STATUSES"]

FIT_STATUSES = ("converged", "at-bound", "not-converged", "failed", "predict-only")


class FitFailed(Exception):
    """An evaluation could not give residuals (a calibration test's search failed)."""


@dataclass(frozen=True)
class FitResult:
    """The fitted values (keys' units), how the fit ended, its evaluations and residual norm
    (√Σ r², relative)."""

    values: dict[str, float]
    status: str
    message: str
    evaluations: int
    residual: float = math.nan


def fit_values(
    residuals: Callable[[dict[str, float]], np.ndarray],
    keys: Sequence[str],
    low: Sequence[float],
    high: Sequence[float],
    *,
    rtol: float,
    max_evaluations: int,
) -> FitResult:
    """Fit ``keys`` within [low, high] to minimise ``residuals(values)`` (module docstring)."""
    from scipy.optimize import least_squares, minimize_scalar

    calls = [0]
    best: list = [math.inf, {}]  # the smallest Σ r² so far and its values

    def counted(vector) -> np.ndarray:
        calls[0] += 1
        if calls[0] > max_evaluations:
            raise _Exhausted()
        values = {key: float(v) for key, v in zip(keys, np.atleast_1d(vector), strict=True)}
        found = np.asarray(residuals(values), dtype=float)
        if float(np.sum(found**2)) < best[0]:
            best[:] = [float(np.sum(found**2)), values]
        return found

    if not keys:
        return FitResult({}, "predict-only", "nothing fitted", 0)
    tolerances = [rtol * (h - lo) for lo, h in zip(low, high, strict=True)]
    try:
        if len(keys) == 1:
            result = minimize_scalar(
                lambda v: float(np.sum(counted(v) ** 2)),
                bounds=(low[0], high[0]),
                method="bounded",
                options={"xatol": tolerances[0], "maxiter": max_evaluations},
            )
            vector = np.atleast_1d(result.x)
            success, message = bool(result.success), str(result.message)
            norm = math.sqrt(float(result.fun))
        else:
            start = 0.5 * (np.asarray(low, dtype=float) + np.asarray(high, dtype=float))
            result = least_squares(
                counted,
                start,
                bounds=(np.asarray(low, dtype=float), np.asarray(high, dtype=float)),
                x_scale=np.asarray(high, dtype=float) - np.asarray(low, dtype=float),
                xtol=rtol,
                ftol=rtol,
                gtol=rtol,
                diff_step=10.0 * rtol,
                max_nfev=max_evaluations,
            )
            vector, success = np.asarray(result.x), result.status > 0
            message, norm = str(result.message), float(np.sqrt(2.0 * result.cost))
    except _Exhausted:
        message = f"{max_evaluations} evaluations (max_evaluations): the best values so far"
        return FitResult(best[1], "not-converged", message, max_evaluations, math.sqrt(best[0]))
    except FitFailed as error:
        return FitResult({}, "failed", str(error), calls[0])
    values = {key: float(v) for key, v in zip(keys, vector, strict=True)}
    status = "converged" if success else "not-converged"
    near = [
        key
        for key, lo, h, tol in zip(keys, low, high, tolerances, strict=True)
        if values[key] - lo <= 2.0 * tol or h - values[key] <= 2.0 * tol
    ]
    if success and near:
        status = "at-bound"
        message = f"{', '.join(near)} at a bound of its range: the optimum may lie beyond"
    return FitResult(values, status, message, calls[0], norm)


class _Exhausted(Exception):
    pass
