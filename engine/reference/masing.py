"""The stabilised fretting loop of a contact from its virgin tangential curve (Masing).

Under a constant normal load, a contact loaded monotonically 0 → Q follows its virgin
compliance curve δ(Q) (Cattaneo–Mindlin for a sphere, its plane-strain analogue for a
cylinder). Cycling between ±Q*, the unloading branch from (δ*, Q*) is Masing's construction
δ = δ* − 2 δ((Q* − Q)/2) and the reloading branch is its point reflection (Johnson,
*Contact Mechanics*, §7.4; Mindlin & Deresiewicz 1953). In gross slip (δ* beyond the slip
displacement) the contact slides at Q = −μP from the end of the unloading curve to −δ*.

:func:`fretting_loop` draws the loop of any contact from its virgin curve and an amplitude
(displacement or force); the sphere (``engine.reference.mindlin.fretting_loop``) and the
cylinder (``engine.reference.line_contact.line_fretting_loop``) hand it their curves.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["masing_loop", "fretting_loop"]

# The numpydoc entry of the keyword options that the closed forms handing their curve to
# fretting_loop pass on (written once).
LOOP_OPTIONS = (
    "**loop\n"
    "    The options of :func:`engine.reference.masing.fretting_loop`: exactly one of\n"
    "    ``displacement_amplitude`` δ* (mm) and ``force_amplitude`` Q* ≤ μP; ``points``\n"
    "    per branch (201)."
)


def fretting_loop(
    virgin: Callable[[np.ndarray], np.ndarray],
    limit: float,
    *,
    displacement_amplitude: float | None = None,
    force_amplitude: float | None = None,
    points: int = 201,
    inverse: Callable[[float], float] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The stabilised fretting loop (δ, Q), closed, starting and ending at (δ*, Q*).

    The unloading branch runs from (δ*, Q*) to (−δ*, −Q*) (Masing curve, then sliding at
    Q = −μP in gross slip); the reloading branch is its point reflection
    (:func:`masing_loop`). Under a displacement amplitude δ* the force amplitude is
    Q* = Q(δ*) below the slip displacement δ(μP) and μP at or beyond it.

    Parameters
    ----------
    virgin : callable
        The virgin compliance curve δ(Q) (mm) on −μP ≤ Q ≤ μP (N or N/mm, array).
    limit : float
        The limiting force μP, in the unit of ``virgin``'s argument.
    displacement_amplitude : float, optional
        δ* (mm), partial or gross slip; give exactly one of the two amplitudes.
    force_amplitude : float, optional
        Q* ≤ μP, in the unit of ``limit``.
    points : int
        Points per branch.
    inverse : callable, optional
        Q(δ) on 0 ≤ δ < δ(μP), where a closed form exists; default: the root of
        ``virgin(Q) = δ`` on [0, μP] (Brent's method, SciPy).

    Returns
    -------
    displacement : numpy.ndarray
        δ (mm) around the loop.
    force : numpy.ndarray
        Q around the loop, in the unit of ``limit``.
    """
    if (displacement_amplitude is None) == (force_amplitude is None):
        raise ValueError("give exactly one of displacement_amplitude and force_amplitude")
    if force_amplitude is not None:
        peak_force = float(force_amplitude)
        return masing_loop(virgin, peak_force, float(virgin(peak_force)), points)
    peak = float(displacement_amplitude)
    if peak >= float(virgin(limit)):  # at or beyond the slip displacement: gross slip
        peak_force = limit
    elif inverse is not None:
        peak_force = float(inverse(peak))
    else:
        from scipy.optimize import brentq  # here: a run of a contact imports no SciPy

        peak_force = brentq(lambda q: float(virgin(q)) - peak, 0.0, limit)
    return masing_loop(virgin, peak_force, peak, points)


def masing_loop(
    virgin: Callable[[np.ndarray], np.ndarray], peak_force: float, peak: float, points: int
) -> tuple[np.ndarray, np.ndarray]:
    """The closed loop (δ, Q) from (δ*, Q*) round to (δ*, Q*).

    Parameters
    ----------
    virgin : callable
        The virgin compliance curve δ(Q): tangential force (N or N/mm, array) to rigid
        tangential displacement (mm).
    peak_force : float
        Force amplitude Q* (μP in gross slip), in the unit of ``virgin``'s argument.
    peak : float
        Displacement amplitude δ* (mm); beyond δ(Q*) the contact slides.
    points : int
        Points per unloading branch (and per sliding stretch).

    Returns
    -------
    tuple of numpy.ndarray
        (δ, Q) around the loop, as :func:`fretting_loop` returns them.
    """
    forces = np.linspace(peak_force, -peak_force, points)
    displacements = float(virgin(peak_force)) - 2.0 * virgin(0.5 * (peak_force - forces))
    if peak > displacements[0] * (1.0 + 1e-12):  # gross slip: slide at Q = −μP to −δ*
        displacements = displacements + (peak - displacements[0])
        sliding = np.linspace(displacements[-1], -peak, points)[1:]
        displacements = np.concatenate([displacements, sliding])
        forces = np.concatenate([forces, np.full(sliding.size, -peak_force)])
    return (
        np.concatenate([displacements, -displacements[1:]]),
        np.concatenate([forces, -forces[1:]]),
    )
