"""Elastic constants of the two contacting bodies and their combinations (paper Eq. 6, 18).

Body A is the elastic half-space, body B the punch. Every quantity is in MPa except the
dimensionless Poisson ratios and the coupling constant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .validation import CheckedRecord, require_poisson, require_positive


@dataclass(frozen=True)
class MaterialPair(CheckedRecord):
    """Young's moduli (MPa) and Poisson ratios of the half-space (A) and the punch (B)."""

    E_A: float
    nu_A: float
    E_B: float
    nu_B: float

    checks = {
        "E_A": require_positive,
        "E_B": require_positive,
        "nu_A": require_poisson,
        "nu_B": require_poisson,
    }

    @property
    def shear_modulus_A(self) -> float:
        return self.E_A / (2.0 * (1.0 + self.nu_A))

    @property
    def shear_modulus_B(self) -> float:
        return self.E_B / (2.0 * (1.0 + self.nu_B))

    @property
    def shear_modulus(self) -> float:
        """Combined G of Eq. (6): 1/G = (1/G_A + 1/G_B)/2, in MPa."""
        return 2.0 / (1.0 / self.shear_modulus_A + 1.0 / self.shear_modulus_B)

    @property
    def poisson_ratio(self) -> float:
        """Combined ν of Eq. (6): ν/G = (ν_A/G_A + ν_B/G_B)/2."""
        return (
            self.shear_modulus
            * 0.5
            * (self.nu_A / self.shear_modulus_A + self.nu_B / self.shear_modulus_B)
        )

    @property
    def coupling(self) -> float:
        """Normal–tangential coupling K of Eq. (6) (dimensionless; 0 for identical bodies)."""
        return (
            0.25
            * self.shear_modulus
            * (
                (1.0 - 2.0 * self.nu_A) / self.shear_modulus_A
                - (1.0 - 2.0 * self.nu_B) / self.shear_modulus_B
            )
        )

    @property
    def dundurs_beta(self) -> float:
        """Dundurs' second constant β = K/(1−ν) (NOTES.md)."""
        return self.coupling / (1.0 - self.poisson_ratio)

    @property
    def contact_modulus(self) -> float:
        """E* = ((1−ν_A²)/E_A + (1−ν_B²)/E_B)⁻¹ in MPa (below Eq. 19)."""
        return 1.0 / ((1.0 - self.nu_A**2) / self.E_A + (1.0 - self.nu_B**2) / self.E_B)

    def describe(self) -> dict[str, float]:
        return {
            "E_A": self.E_A,
            "nu_A": self.nu_A,
            "E_B": self.E_B,
            "nu_B": self.nu_B,
            "G": self.shear_modulus,
            "nu": self.poisson_ratio,
            "K": self.coupling,
            "E_star": self.contact_modulus,
        }


def paper_material() -> MaterialPair:
    """The pair of Section 7: E_A = 200 GPa, E_B = 100 E_A, ν = 0.3 for both."""
    return MaterialPair(E_A=200e3, nu_A=0.3, E_B=200e5, nu_B=0.3)


def _check_notes() -> None:  # pragma: no cover - documentation aid
    pair = paper_material()
    assert math.isclose(pair.coupling, 0.19604, rel_tol=1e-4)
