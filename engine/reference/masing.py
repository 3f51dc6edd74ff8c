"""The stabilised fretting loop of a contact from its virgin tangential curve (Masing).

Under a constant normal load, a contact loaded monotonically 0 → Q follows its virgin
compliance curve δ(Q) (Cattaneo–Mindlin for a sphere, its plane-strain analogue for a
cylinder). Cycling between ±Q*, the unloading branch from (δ*, Q*) is Masing's construction
δ = δ* − 2 δ((Q* − Q)/2) and the reloading branch is its point reflection (Johnson,
*Contact Mechanics*, §7.4; Mindlin & Deresiewicz 1953). In gross slip (δ* beyond the slip
displacement) the contact slides at Q = −μP from the end of the unloading curve to −δ*.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["masing_loop"]


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
    displacement : numpy.ndarray
        δ (mm) around the loop.
    force : numpy.ndarray
        Q around the loop, in the unit of ``peak_force``.
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
