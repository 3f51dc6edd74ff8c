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

:class:`FrettingReference` gathers what follows from one virgin curve at one load: the slip
displacement δ_slip = δ(μP), the force amplitude reached under a displacement amplitude,
the energy per cycle in partial and gross slip, Fouvry's energy ratio, the loop and the loop
sampled at given displacements. A geometry with such closed forms hands one out
(``engine.geometry.Profile.fretting_reference``); the checks of a fretting study
(``engine.analysis.fretting``) ask it, whatever the shape.

Energy in gross slip: the Masing loop between ±μP plus the two sliding strokes,
W = W(μP) + 4 μP (δ* − δ_slip).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .docstrings import documented

__all__ = ["masing_loop", "fretting_loop", "FrettingReference"]

#: Bisection steps of the numerical inverse of a virgin curve: 2⁻⁶⁴ μP, below round-off.
BISECTION_STEPS = 64
#: Points per branch of the loop whose area is the energy where no closed form is given:
#: the trapezoidal error of the Masing curve is below 2e-6 of W there
#: (tests/test_fretting_reference.py checks it against the closed forms).
ENERGY_POINTS = 4001

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


@dataclass(frozen=True)
class FrettingReference:
    """The closed forms of one contact under fretting at a held normal load (module
    docstring), from its virgin curve by Masing's construction.

    Parameters
    ----------
    name : str
        Whose closed forms (reports and figure legends), e.g. "Mindlin–Deresiewicz".
    virgin : callable
        The virgin compliance curve δ(Q) (mm) on −μP ≤ Q ≤ μP (array).
    limit : float
        μP (N, or N/mm for a line contact).
    inverse : callable, optional
        Q(δ) on 0 ≤ δ ≤ δ_slip where a closed form exists; default: bisection on ``virgin``.
    loop_energy : callable, optional
        The closed-form energy per cycle W(Q*) (mJ, or mJ/mm) of the loop between ±Q* ≤ μP;
        default: the area of the Masing loop (trapezoidal rule, ``ENERGY_POINTS`` = 4001 points).
    master_curve : callable, optional
        Fouvry's A against δ*/δ_slip where it is one curve for every load, size and μ (the
        sphere's, ``engine.reference.mindlin.energy_ratio``); None where A depends on more
        (the cylinder's, on a/d).
    """

    name: str
    virgin: Callable[[np.ndarray], np.ndarray]
    limit: float
    inverse: Callable[[np.ndarray], np.ndarray] | None = None
    loop_energy: Callable[[float], float] | None = None
    master_curve: Callable[[np.ndarray], np.ndarray] | None = None

    @property
    def slip_displacement(self) -> float:
        """δ_slip = δ(μP) (mm): the displacement amplitude at the onset of gross slip."""
        return float(self.virgin(self.limit))

    @documented(
        "numpy.ndarray\n    Q (N, or N/mm), shaped like ``displacement``.",
        "displacement : float or array_like\n    δ ≥ 0 (mm).",
    )
    def force(self, displacement) -> np.ndarray:
        """Q(δ) of the virgin curve for δ ≥ 0 (mm, array): μP from δ_slip on."""
        target = np.clip(np.asarray(displacement, dtype=float), 0.0, self.slip_displacement)
        if self.inverse is not None:
            return np.minimum(np.asarray(self.inverse(target), dtype=float), self.limit)
        low, high = np.zeros_like(target), np.full_like(target, self.limit)
        for _ in range(BISECTION_STEPS):  # δ(Q) increases on [0, μP]
            middle = 0.5 * (low + high)
            below = self.virgin(middle) < target
            low, high = np.where(below, middle, low), np.where(below, high, middle)
        return 0.5 * (low + high)

    @documented("float\n    Q* (N, or N/mm).", "displacement_amplitude : float\n    δ* (mm), > 0.")
    def force_amplitude(self, displacement_amplitude: float) -> float:
        """Q* reached under the displacement amplitude δ* (mm): Q(δ*), or μP in gross slip."""
        return float(self.force(displacement_amplitude))

    @documented(
        "float\n    W (mJ, or mJ/mm).", "force_amplitude : float\n    Q* ≤ μP (N, or N/mm)."
    )
    def partial_slip_energy(self, force_amplitude: float) -> float:
        """W (mJ, or mJ/mm) of the loop between ±Q* ≤ μP."""
        if self.loop_energy is not None:
            return float(self.loop_energy(force_amplitude))
        peak = float(self.virgin(force_amplitude))
        return _area(*masing_loop(self.virgin, force_amplitude, peak, ENERGY_POINTS))

    @documented("float\n    W (mJ, or mJ/mm).", "displacement_amplitude : float\n    δ* (mm), > 0.")
    def energy_per_cycle(self, displacement_amplitude: float) -> float:
        """W (mJ, or mJ/mm) under the displacement amplitude δ* (mm), in either regime."""
        slip = self.slip_displacement
        partial = self.partial_slip_energy(self.force_amplitude(min(displacement_amplitude, slip)))
        return partial + 4.0 * self.limit * max(displacement_amplitude - slip, 0.0)

    @documented(
        "float\n    A (dimensionless).", "displacement_amplitude : float\n    δ* (mm), > 0."
    )
    def energy_ratio(self, displacement_amplitude: float) -> float:
        """Fouvry's A = W/(4 δ* Q*) under the displacement amplitude δ* (mm); 0.2 at δ_slip
        for a sphere (one master curve), a function of a/d too for a cylinder."""
        force = self.force_amplitude(displacement_amplitude)
        return self.energy_per_cycle(displacement_amplitude) / (
            4.0 * displacement_amplitude * force
        )

    @documented(
        "(numpy.ndarray, numpy.ndarray)\n    δ (mm) and Q (N, or N/mm) around the loop.",
        LOOP_OPTIONS.replace("**loop", "**amplitude"),
    )
    def loop(self, **amplitude) -> tuple[np.ndarray, np.ndarray]:
        """The stabilised loop (δ, Q) of :func:`fretting_loop` (its keyword options)."""
        return fretting_loop(self.virgin, self.limit, inverse=self.inverse, **amplitude)

    @documented(
        "float\n    ∮ Q dδ (mJ, or mJ/mm).",
        "delta : array_like\n    δ (mm) of the computed loop's rows, from (δ*, Q*) round.",
        "displacement_amplitude : float\n    δ* (mm).",
    )
    def sampled_loop_energy(self, delta, displacement_amplitude: float) -> float:
        """∮ Q dδ (mJ, or mJ/mm) of the analytic loop under δ* sampled at the displacements
        ``delta`` (mm) of a computed loop, unloading on the first half of the rows, reloading
        on the second (trapezoidal rule): the computed energy's error with the load-step
        error removed."""
        delta = np.asarray(delta, dtype=float)
        peak = self.force_amplitude(displacement_amplitude)

        def unloading(x):
            return np.maximum(
                peak - 2.0 * self.force((displacement_amplitude - x) / 2.0), -self.limit
            )

        half = len(delta) // 2
        force = np.concatenate([unloading(delta[: half + 1]), -unloading(-delta[half + 1 :])])
        return _area(delta, force)

    @documented(
        "float\n    ∮ Q dδ (mJ, or mJ/mm).",
        "force : array_like\n    Q (N, or N/mm) of the computed loop's rows, from Q* round.",
        "force_amplitude : float\n    Q* < μP (N, or N/mm).",
    )
    def sampled_force_loop_energy(self, force, force_amplitude: float) -> float:
        """∮ Q dδ (mJ, or mJ/mm) of the analytic loop between ±Q* sampled at the forces
        ``force`` of a computed loop (force control; rows as in
        :meth:`sampled_loop_energy`): the computed energy's error with the load-step error
        removed."""
        force = np.asarray(force, dtype=float)
        peak = float(self.virgin(force_amplitude))

        def unloading(q):
            return peak - 2.0 * self.virgin((force_amplitude - q) / 2.0)

        half = len(force) // 2
        delta = np.concatenate([unloading(force[: half + 1]), -unloading(-force[half + 1 :])])
        return _area(delta, force)


def _area(delta: np.ndarray, force: np.ndarray) -> float:
    """∮ Q dδ by the trapezoidal rule over the rows of a loop."""
    return float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(delta)))
