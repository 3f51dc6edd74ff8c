"""Dang Van's criterion (Dang Van, Griveau & Message, in *Biaxial and Multiaxial Fatigue*,
EGF 3, 1989, 479).

    risk = max_t [τ(t) + α σ_H(t)] / β,   α = 3τ_d/σ_d − 3/2,   β = τ_d,

where τ(t) = (s₁ − s₃)/2 is the Tresca shear of the mesoscopic deviator s(t) − s*, s* the
centre of the minimum ball circumscribing the deviatoric path (always the ball, whatever
``amplitude_method``: it defines the stabilised residual stress of the grains), and σ_H(t) the
hydrostatic stress at the same instant. σ_d, τ_d (MPa): fully reversed tension and torsion
limits; both are exact: tension σ_d peaks at τ = σ_d/2, σ_H = σ_d/3; torsion τ_d at τ = τ_d,
σ_H = 0. The critical ``angle`` is not reported (the criterion is plane-free as evaluated here).
"""

from __future__ import annotations

import numpy as np

from .base import CriterionField, FatigueLimitCriterion
from .history import StressHistory
from .quantities import deviatoric_coordinates, hydrostatic, minimum_ball, point_chunks


def _mesoscopic_deviator(history: StressHistory) -> StressHistory:
    """s(t) − s* as a history (components order of ``COMPONENTS``)."""
    coordinates = deviatoric_coordinates(history)
    ball = minimum_ball(coordinates)
    if not ball.converged:
        raise RuntimeError(
            f"Dang Van: the minimum ball of the deviatoric path did not converge in "
            f"{ball.iterations} iterations"
        )
    relative = coordinates - ball.centre[None]
    root2 = np.sqrt(2.0)
    tensor = np.concatenate([root2 * relative[..., :3], relative[..., 3:]], axis=-1)
    return StressHistory(tensor, history.x, history.z, history.shape)


class DangVan(FatigueLimitCriterion):
    name = "dang_van"
    column = "dang_van_risk"
    description = "Dang Van risk max_t (τ(t) + α σ_H(t))/τ_d"

    def evaluate(self, history: StressHistory) -> CriterionField:
        alpha = 3.0 * self.tau_d / self.sigma_d - 1.5
        mesoscopic, pressure = _mesoscopic_deviator(history), hydrostatic(history)
        value = np.empty(history.n_points)
        for chunk in point_chunks(history, 9):  # the 3 × 3 matrices and their eigenvalues
            principal = np.linalg.eigvalsh(mesoscopic.take(chunk).matrices())
            tresca = 0.5 * (principal[..., -1] - principal[..., 0])
            value[chunk] = (tresca + alpha * pressure[:, chunk]).max(axis=0)
        return CriterionField(value / self.tau_d)
