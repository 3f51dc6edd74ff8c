"""The Smith–Watson–Topper parameter on the critical plane (Smith, Watson & Topper, J. Mater.
6 (1970) 767; critical-plane form of Socie, J. Eng. Mater. Technol. 109 (1987) 293).

    SWT = max over planes of σ_n,max · ε_n,a   (MPa),

σ_n,max the maximum normal stress on the plane over the cycle and ε_n,a the amplitude (half the
range) of the normal strain ε_n = ((1 + ν) σ_n − ν tr σ)/E (isotropic Hooke's law, the flat's
E and ν; elastic stresses). Planes with σ_n,max ≤ 0 score 0 (a crack does not open). Planes:
``engine.fatigue.quantities`` (trace angle φ, step ``plane_step``); ``angle`` is φ of the
maximising plane. Life from the Basquin–Coffin–Manson curve
ε_a = (σ_f/E)(2N)^b + ε_f (2N)^c multiplied by σ_max = σ_f (2N)^b:

    SWT = (σ_f²/E) (2N)^{2b} + σ_f ε_f (2N)^{b+c}

(σ_f MPa, b < 0, ε_f > 0, c < 0). Fully reversed uniaxial σ_a gives SWT = σ_a²/E at φ = 90°
(the plane normal to the load along x); pure torsion τ_a gives (1 + ν) τ_a²/E at 45°.
"""

from __future__ import annotations

import numpy as np

from engine.keys import Key

from .base import BASQUIN, COFFIN_MANSON, STRENGTH, CriterionField, FatigueCriterion
from .history import StressHistory
from .quantities import ResolvedStress, cycle_range, invert_life, search_planes


class SmithWatsonTopper(FatigueCriterion):
    name = "swt"
    column = "swt"
    unit = "MPa"
    description = "Smith–Watson–Topper parameter σ_n,max ε_n,a on the critical plane"
    constants = {
        "sigma_f": Key("MPa", "fatigue strength coefficient σ'_f (Basquin)", **STRENGTH),
        "b": Key("1", "fatigue strength exponent (< 0)", **BASQUIN),
        "eps_f": Key(
            "1",
            "fatigue ductility coefficient ε'_f (Coffin–Manson)",
            minimum=0.0,
            maximum=10.0,
            why="fatigue ductility coefficients of metals lie below about 3",
        ),
        "c": Key("1", "fatigue ductility exponent (< 0)", **COFFIN_MANSON),
    }
    reports_angle = True
    reports_life = True

    def check(self) -> None:
        self._require_positive("sigma_f", "eps_f")
        self._require_negative("b", "c")

    def evaluate(self, history: StressHistory) -> CriterionField:
        value, angle = search_planes(history, self._score, self.options.plane_step)
        return CriterionField(value, angle, self.life(value))

    def _score(self, resolved: ResolvedStress) -> np.ndarray:
        """σ_n,max ε_n,a (MPa) on each plane, 0 where σ_n,max ≤ 0; shape (points, planes)."""
        young, poisson = self.elasticity.young_modulus, self.elasticity.poisson_ratio
        normal = resolved.normal()
        trace = resolved.tensor[..., :3].sum(axis=-1)[..., None]
        strain_amplitude = cycle_range((1.0 + poisson) * normal - poisson * trace) / young
        return np.clip(normal.max(axis=0), 0.0, None) * strain_amplitude

    def life(self, value: np.ndarray) -> np.ndarray:
        """N (cycles) of the SWT values (MPa), module docstring."""
        coefficients = [self.sigma_f**2 / self.elasticity.young_modulus, self.sigma_f * self.eps_f]
        return invert_life(value, coefficients, [2.0 * self.b, self.b + self.c])
