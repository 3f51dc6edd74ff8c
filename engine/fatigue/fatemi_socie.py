"""The Fatemi–Socie parameter on the critical plane (Fatemi & Socie, Fatigue Fract. Eng.
Mater. Struct. 11 (1988) 149).

    FS = γ_a (1 + k σ_n,max / σ_y)   (dimensionless),

on the plane of maximum shear strain amplitude γ_a (engineering shear strain γ = τ/G, G the
flat's shear modulus; elastic stresses), σ_n,max the maximum normal stress on that plane over
the cycle, k and σ_y (MPa) material constants. Per plane, γ_a is the larger of the amplitudes
(half ranges) of the shear along the plane's trace and along y (``engine.fatigue.quantities``);
among planes whose γ_a is within 1e-9 (relative) of the maximum, the largest FS is taken
(uniaxial loading has two such planes, ±45°). Life from

    FS = (τ_f/G) (2N)^{b0} + γ_f (2N)^{c0}

(τ_f MPa, b0 < 0, γ_f > 0, c0 < 0). Pure torsion τ_a gives FS = τ_a/G (σ_n = 0 on the shear
planes); fully reversed uniaxial σ_a gives γ_a = σ_a/(2G) at 45° with σ_n,max = σ_a/2.
"""

from __future__ import annotations

import numpy as np

from engine.keys import Key

from .base import BASQUIN, COFFIN_MANSON, STRENGTH, CriterionField, FatigueCriterion
from .history import StressHistory
from .quantities import ResolvedStress, cycle_range, invert_life, search_planes

_TIE = 1e-9  # relative tolerance of equal shear amplitudes (rounding of the resolution)


class FatemiSocie(FatigueCriterion):
    name = "fatemi_socie"
    column = "fs"
    unit = "1"
    description = "Fatemi–Socie parameter γ_a (1 + k σ_n,max/σ_y) on the critical plane"
    constants = {
        "tau_f": Key("MPa", "shear fatigue strength coefficient τ'_f", **STRENGTH),
        "gamma_f": Key(
            "1",
            "shear fatigue ductility coefficient γ'_f",
            minimum=0.0,
            maximum=10.0,
            why="shear fatigue ductility coefficients of metals lie below about 5",
        ),
        "b0": Key("1", "shear fatigue strength exponent (< 0)", **BASQUIN),
        "c0": Key("1", "shear fatigue ductility exponent (< 0)", **COFFIN_MANSON),
        "k": Key(
            "1",
            "normal-stress sensitivity of Fatemi–Socie",
            minimum=0.0,
            maximum=10.0,
            why="Fatemi-Socie's normal-stress sensitivity lies in 0.3 … 1",
        ),
        "sigma_y": Key("MPa", "yield strength", **STRENGTH),
    }
    reports_angle = True
    reports_life = True

    def check(self) -> None:
        self._require_positive("tau_f", "gamma_f", "sigma_y")
        self._require_negative("b0", "c0")
        if self.k < 0.0:
            raise ValueError(f"fatigue constant 'k' must be >= 0, got {self.k!r}")

    def evaluate(self, history: StressHistory) -> CriterionField:
        value, angle = search_planes(history, self._score, self.options.plane_step, two_pass=False)
        return CriterionField(value, angle, self.life(value))

    def _score(self, resolved: ResolvedStress) -> np.ndarray:
        """FS on the planes whose γ_a is within ``_TIE`` of the maximum at the point, −inf on
        the others (the critical plane is that of maximum shear strain amplitude)."""
        shear = np.maximum(cycle_range(resolved.shear_trace()), cycle_range(resolved.shear_y()))
        strain = shear / self.elasticity.shear_modulus
        opening = 1.0 + self.k * resolved.normal().max(axis=0) / self.sigma_y
        critical = strain >= strain.max(axis=1, keepdims=True) * (1.0 - _TIE)
        return np.where(critical, strain * opening, -np.inf)

    def life(self, value: np.ndarray) -> np.ndarray:
        """N (cycles) of the FS values, module docstring."""
        coefficients = [self.tau_f / self.elasticity.shear_modulus, self.gamma_f]
        return invert_life(value, coefficients, [self.b0, self.c0])
