"""``criteria = ["shear_amplitude"]``: the shear stress amplitude over a fatigue limit,

    risk = √J2,a / τ_a,

with √J2,a the amplitude of the second invariant of the deviatoric stress over the cycle
(MPa, the engine's ``amplitude_method``) and ``tau_a`` τ_a (MPa) the material's torsion
fatigue limit. risk ≥ 1: crack nucleation predicted. It is Crossland's criterion without the
hydrostatic term (α = 0), a plain example of the protocol of ``engine.fatigue.base``.
"""

from __future__ import annotations

from engine.fatigue import CriterionField, FatigueCriterion, StressHistory
from engine.fatigue.base import STRENGTH
from engine.fatigue.quantities import shear_amplitude
from engine.keys import Key

__all__ = ["ShearAmplitude"]


class ShearAmplitude(FatigueCriterion):
    name = "shear_amplitude"
    column = "shear_amplitude_risk"
    unit = "1"
    description = "shear amplitude risk √J2,a/τ_a"
    constants = {"tau_a": Key("MPa", "fully reversed torsion fatigue limit τ_a", **STRENGTH)}

    def check(self) -> None:
        self._require_positive("tau_a")

    def evaluate(self, history: StressHistory) -> CriterionField:
        amplitude = shear_amplitude(history, self.options.amplitude_method)
        return CriterionField(amplitude / self.tau_a)
