"""The normal (Signorini) problem under load control: Polonsky & Keer's constrained CG.

Find p ≥ 0 on the candidate elements with Σ p ΔA = P and the gap

    g = A_zz p + offset − δ ≥ 0,  p g = 0          (Eqs. 1, 7)

where ``offset`` (mm) holds the geometric gap, the wear and, in the alternation, the normal
displacement A_zx q_x + A_zy q_y of frozen tangential tractions. Method: conjugate gradient
on the contact set, projection on p ≥ 0, restart when elements re-enter contact, rescaling
to the load each step (Polonsky & Keer, Wear 231, 1999), with the spectral preconditioner
(Vollebregt 2014) restricted to the contact set. The approach δ is the mean gap over the
contact set. Residual: RMS over the candidate elements of the gap violation (g on the
contact set, min(g, 0) elsewhere), divided by |δ|.

**Re-entry.** An element out of contact whose gap is negative (an overlap) re-enters with
the pressure of a gradient step of the same length as the CG step. Without a preconditioner
that is Polonsky & Keer's p = −α g (α in MPa/mm). With it, α is dimensionless (the
direction M r is already a pressure, MPa) and the step along the gap must be preconditioned
too: p = −α (M v) at the overlapping elements, v the gap violation of the residual. The
unpreconditioned expression −α g (mm) hands a re-entering element a pressure of round-off
size (10⁻⁵ MPa against a mean of 260 MPa on the worn line contact that exposed it): it drops
out again at the next step, and on a conforming (worn) contact with many elements of nearly
zero gap the contact set cycles for ever (period 4, 165–195 elements, the residual stuck
near 10⁻³; ``tests/test_normal_reentry.py``). The preconditioned value may be ≥ 0 at an
overlapping element (M is not local); the element then waits for a later step.

**Stagnation.** Should the residual still not reach a new minimum for ``STALL_ITERATIONS``
iterations, the solve stops and says so (``stalled``); the alternation then hands the
increment to the projected gradient instead of spending its whole budget here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kernels.operator import HalfSpaceOperator

STALL_ITERATIONS = 200  # iterations without a new smallest residual before giving up


@dataclass
class NormalSolution:
    """``pressure`` (MPa), ``approach`` δ (mm), ``iterations`` (operator applications of
    the loop), ``residual`` (relative, module doc), ``converged`` (residual ≤ tol);
    ``image``: A_zz ``pressure`` (mm) when the last iteration computed it (converged), else
    None — the next solve from this pressure can start from it; ``stalled``: stopped
    because the residual made no progress for ``STALL_ITERATIONS`` iterations."""

    pressure: np.ndarray
    approach: float
    iterations: int
    residual: float
    converged: bool
    image: np.ndarray | None
    stalled: bool = False


def _scaled_start(operator, candidate, target, initial, image):
    """The starting pressure: ``initial`` clipped at 0 and scaled to the load (uniform if it
    carries none), and A_zz of it when it is a multiple of ``initial`` whose image is known
    (A (c p) = c A p)."""
    pressure = np.zeros(operator.grid.shape)
    known = None
    if initial[candidate].sum() > 0.0:
        pressure[candidate] = np.maximum(initial[candidate], 0.0)
        factor = target / pressure.sum()
        pressure *= factor
        proportional = np.all(initial >= 0.0) and np.array_equal(pressure > 0.0, initial > 0.0)
        if image is not None and proportional:
            known = image * factor
    else:
        pressure[candidate] = target / int(candidate.sum())
    return pressure, known


class _ContactMean:
    """Means over the contact set, its number of elements counted once per iteration
    (``update``): the gathered values ``values[contact]`` summed as ``ndarray.mean`` sums
    them (``np.add.reduce`` of the contiguous gathered values), then divided by their number
    (without ``mean``'s own checks and calls, which cost more than the sum at 128²)."""

    def __init__(self, contact: np.ndarray):
        self._contact = contact.reshape(-1)  # a view: follows the contact array
        self._count = 0

    def update(self) -> None:
        """After the contact array changed: its number of elements."""
        self._count = int(np.count_nonzero(self._contact))

    def __call__(self, values: np.ndarray) -> float:
        return float(np.add.reduce(values.reshape(-1)[self._contact])) / self._count


def _violation(gap, contact, off_candidates, out) -> np.ndarray:
    """The gap violation (mm) into ``out`` (an array of the grid's shape): the gap in
    contact, the negative gap (an overlap) elsewhere on the candidate elements, 0 off them
    (``off_candidates``: None to leave those entries as they come)."""
    violation = np.minimum(gap, 0.0, out=out)  # np.where(contact, gap, min(gap, 0))
    np.copyto(violation, gap, where=contact)
    if off_candidates is not None:
        violation[off_candidates] = 0.0
    return violation


def _violation_rms(gap, contact, mask, count, work) -> float:
    """RMS over the candidate elements of the gap violation (mm); ``work``: an array of the
    grid's shape, overwritten."""
    violation = _violation(gap, contact, None, work)  # summed over the candidates only
    return math.sqrt(np.sum(np.square(violation, out=violation)[mask]) / count)


def solve_normal(
    operator: HalfSpaceOperator,
    candidate: np.ndarray,
    load: float,
    initial: np.ndarray,
    offset: np.ndarray,
    *,
    tol: float,
    maxiter: int,
    image: np.ndarray | None = None,
) -> NormalSolution:
    """Pressure (MPa) carrying ``load`` (N) on the ``candidate`` elements, from ``initial``
    (MPa); ``offset`` (mm) as in the module docstring; ``image``: A_zz ``initial`` (mm) when
    already known, which saves the first operator application."""
    grid, mask = operator.grid, candidate
    preconditioner = operator.preconditioner
    target = load / grid.element_area
    count = int(mask.sum())
    pressure, known = _scaled_start(operator, mask, target, initial, image)
    direction = np.zeros(grid.shape)
    # Work arrays, reused by every iteration (fresh pages at each iteration cost more than
    # the arithmetic on small grids).
    gap, residual_c, work, pressure_image, step_image, z = (np.empty(grid.shape) for _ in range(6))
    contact, outside, overlap, negative = (np.empty(grid.shape, bool) for _ in range(4))
    contact_mean = _ContactMean(contact)
    previous = 1.0
    conjugate = False
    residual, approach, iterations, converged_image = math.inf, 0.0, 0, None
    best, since_best, stalled = math.inf, 0, False
    for iterations in range(1, maxiter + 1):  # noqa: B007
        raw = known if known is not None else operator.apply_normal(pressure, out=pressure_image)
        known = None
        np.add(raw, offset, out=gap)
        np.logical_and(mask, np.greater(pressure, 0.0, out=contact), out=contact)
        np.logical_not(contact, out=outside)
        contact_mean.update()
        approach = contact_mean(gap)
        gap -= approach
        residual = _violation_rms(gap, contact, mask, count, work) / abs(approach)
        if residual <= tol:
            converged_image = raw
            break
        best, since_best = (residual, 0) if residual < best else (best, since_best + 1)
        if since_best >= STALL_ITERATIONS:
            stalled = True
            break
        # Work arrays are updated in place where the old values are not needed again (the
        # same operations, element by element, as the textbook expressions in the comments).
        np.copyto(residual_c, gap)  # np.where(contact, gap, 0)
        residual_c[outside] = 0.0
        preconditioner.normal(residual_c, out=z)  # np.where(contact, M r, 0)
        z -= contact_mean(z)
        z[outside] = 0.0
        product = float(np.sum(np.multiply(residual_c, z, out=work)))
        beta = product / previous if conjugate and previous > 0.0 else 0.0
        direction *= beta  # np.where(contact, z + beta d, 0)
        direction += z
        direction[outside] = 0.0
        previous = product
        operator.apply_normal(direction, out=step_image)
        step_image -= contact_mean(step_image)
        numerator = float(np.sum(np.multiply(residual_c, direction, out=work)))
        curvature = float(np.sum(np.multiply(step_image, direction, out=step_image)))
        # No direction (a contact set of one element, or a preconditioned residual that
        # vanishes there): nothing to move on the set; re-entries take the full step (M ≈ A⁻¹).
        step = numerator / curvature if curvature > 0.0 else 1.0
        change = np.multiply(direction, step, out=work)  # max(where(contact, p − step d, 0), 0)
        np.subtract(pressure, change, out=pressure)
        pressure[outside] = 0.0
        np.maximum(pressure, 0.0, out=pressure)
        np.less_equal(pressure, 0.0, out=overlap)  # mask & (pressure <= 0) & (gap < 0)
        np.logical_and(overlap, mask, out=overlap)
        np.logical_and(overlap, np.less(gap, 0.0, out=negative), out=overlap)
        conjugate = not np.any(overlap)
        if not conjugate:
            # Re-entry along the preconditioned violation (module docstring); never below
            # zero (a step of round-off size and the wrong sign near convergence would
            # otherwise leave a negative pressure, whose friction bound has no meaning).
            violation = _violation(gap, contact, ~mask, work)
            entry = preconditioner.normal(violation, out=z)[overlap]
            pressure[overlap] = np.maximum(pressure[overlap] - step * entry, 0.0)
        pressure *= target / pressure.sum()
    return NormalSolution(
        pressure, approach, iterations, residual, residual <= tol, converged_image, stalled
    )
