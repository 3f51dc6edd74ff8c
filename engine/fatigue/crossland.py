"""Crossland's criterion (Crossland, Proc. Int. Conf. Fatigue of Metals, 1956, 138).

    risk = (√J2,a + α σ_H,max) / β,   α = 3τ_d/σ_d − √3,   β = τ_d,

with σ_d, τ_d (MPa) the fully reversed tension–compression and torsion fatigue limits, √J2,a the
shear stress amplitude (``FatigueOptions.amplitude_method``) and σ_H,max the maximum hydrostatic
stress over the cycle. risk ≥ 1: crack nucleation predicted (infinite-life design fails). α
makes both limits exact: fully reversed tension σ_d gives √J2,a = σ_d/√3, σ_H,max = σ_d/3;
torsion τ_d gives √J2,a = τ_d, σ_H,max = 0.
"""

from __future__ import annotations

import math

from .base import CriterionField, FatigueLimitCriterion
from .history import StressHistory
from .quantities import hydrostatic, shear_amplitude


class Crossland(FatigueLimitCriterion):
    name = "crossland"
    column = "crossland_risk"
    description = "Crossland risk (√J2,a + α σ_H,max)/τ_d"

    def evaluate(self, history: StressHistory) -> CriterionField:
        alpha = 3.0 * self.tau_d / self.sigma_d - math.sqrt(3.0)
        amplitude = shear_amplitude(history, self.options.amplitude_method)
        peak_hydrostatic = hydrostatic(history).max(axis=0)
        return CriterionField((amplitude + alpha * peak_hydrostatic) / self.tau_d)
