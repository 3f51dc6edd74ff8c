"""Orthotropic Coulomb friction (Eqs. 8–11) and orthotropic Archard wear (Eqs. 12–14).

Tribological axes {e1, e2} are the x, y axes rotated by β (Eq. 11):
    t_e1 =  cos β t_x + sin β t_y,   t_e2 = −sin β t_x + cos β t_y.
The friction cone is the ellipse ||t||_μ = √((t_e1/μ1)² + (t_e2/μ2)²) ≤ p (Eq. 10), the
wear norm ||Δg||_i = √((i1 Δg_e1)² + (i2 Δg_e2)²) (Eq. 13). Angles are in radians here.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..keys import Key
from ..validation import CheckedRecord, require_finite, require_non_negative, under_key
from .wear import WearModel

#: ``[sweep] wear2 = "proportional"``: i2 = i1·μ2/μ1 (paper Section 7.3).
PROPORTIONAL = "proportional"
# Archard-type wear coefficients (1/MPa) of fretting tests are 1e-9 … 1e-6 (Section 7: 1.33e-7);
# at 1e-3 a contact at 100 MPa slipping 1 µm wears 0.1 µm per cycle, 10^4 × the severest
# measured, and the cycle jump degenerates into single cycles.
MAX_WEAR_COEFFICIENT = 1e-3  # 1/MPa
# The energy law's α (mm³/J) wears α·τ·s·1e-3 mm per cycle where Archard's wears k·p·s: at
# μ = 1, α = 1 mm³/J wears as fast as the Archard bound above (fretting tests: 1e-6 … 1e-4).
MAX_ENERGY_WEAR_COEFFICIENT = 1.0  # mm^3/J
_ARCHARD_WHY = "fretting tests: 1e-9 … 1e-6"


def _rotation(beta: float) -> tuple[float, float]:
    return math.cos(beta), math.sin(beta)


def to_tribological(beta: float, vx: np.ndarray, vy: np.ndarray):
    """Components along (e1, e2) of a vector given along (x, y), Eq. (11)."""
    c, s = _rotation(beta)
    return c * vx + s * vy, -s * vx + c * vy


def from_tribological(beta: float, v1: np.ndarray, v2: np.ndarray):
    """Inverse of ``to_tribological``."""
    c, s = _rotation(beta)
    return c * v1 - s * v2, s * v1 + c * v2


@dataclass(frozen=True)
class FrictionLaw(CheckedRecord):
    """Principal friction coefficients μ1 (along e1), μ2 (along e2) and the angle β (rad)."""

    mu1: float
    mu2: float
    beta: float = 0.0

    checks = {"mu1": require_non_negative, "mu2": require_non_negative, "beta": require_finite}

    def __post_init__(self) -> None:
        super().__post_init__()
        if (self.mu1 == 0.0) != (self.mu2 == 0.0):
            raise ValueError(
                f"mu1 and mu2 must both be zero (frictionless) or both > 0, "
                f"got mu1={self.mu1!r}, mu2={self.mu2!r}"
            )

    @property
    def frictionless(self) -> bool:
        return self.mu1 == 0.0

    @property
    def isotropic(self) -> bool:
        return self.mu1 == self.mu2

    def norm(self, tx: np.ndarray, ty: np.ndarray) -> np.ndarray:
        """||t||_μ of Eq. (10) (MPa for tractions in MPa)."""
        if self.isotropic:  # rotation invariant: |t| / μ (tractions never near overflow)
            return np.sqrt(tx * tx + ty * ty) / self.mu1
        t1, t2 = to_tribological(self.beta, tx, ty)
        return np.hypot(t1 / self.mu1, t2 / self.mu2)

    def radial_return(self, tx: np.ndarray, ty: np.ndarray, bound: np.ndarray):
        """Eq. (9) as corrected in NOTES.md: t if ||t||_μ < ρ, else ρ t / ||t||_μ.

        ``bound`` is ρ ≥ 0 (the contact pressure). Keeps the direction of t.
        """
        norm = self.norm(tx, ty)
        scale = np.divide(bound, norm, out=np.ones_like(norm), where=norm > bound)
        return tx * scale, ty * scale

    def project(self, tx: np.ndarray, ty: np.ndarray, bound: np.ndarray, iterations: int = 60):
        """Euclidean closest point of t on the ellipse ||t||_μ ≤ ρ (componentwise).

        Solves for the multiplier λ ≥ 0 of min |q − t|² s.t. (q1/a)² + (q2/b)² ≤ 1 with
        a = μ1 ρ, b = μ2 ρ: q_k = a_k² t_k / (a_k² + λ), by Newton's method on the convex,
        decreasing secular function (monotone from a lower bound of the root; stops when the
        ellipse equation holds to 1e-14). Isotropic: the radial return.
        """
        if self.isotropic:
            return self.radial_return(tx, ty, bound)
        qx, qy = np.array(tx, dtype=float), np.array(ty, dtype=float)
        norm = self.norm(tx, ty)
        outside = norm > bound
        if not np.any(outside):
            return qx, qy
        t1, t2 = to_tribological(self.beta, qx[outside], qy[outside])
        rho = bound[outside]
        q1, q2 = np.zeros_like(rho), np.zeros_like(rho)  # zero bound: the cone is a point
        positive = rho > 0.0
        t1p, t2p = t1[positive], t2[positive]
        a2 = (self.mu1 * rho[positive]) ** 2
        b2 = (self.mu2 * rho[positive]) ** 2
        # Start left of the root (f ≥ 0 there, so Newton increases monotonically to it):
        # f(λ) ≥ a_min² |t|² / (a_max² + λ)² − 1 gives λ0 = a_min |t| − a_max², within the
        # axis ratio of the root however far outside t lies (exact when a = b).
        a_min, a2_max = np.sqrt(np.minimum(a2, b2)), np.maximum(a2, b2)
        lam = np.maximum(a_min * np.hypot(t1p, t2p) - a2_max, 0.0)
        for _ in range(iterations):
            d1, d2 = a2 + lam, b2 + lam
            f = a2 * t1p**2 / d1**2 + b2 * t2p**2 / d2**2 - 1.0
            if np.all(np.abs(f) <= 1e-14):
                break
            df = -2.0 * (a2 * t1p**2 / d1**3 + b2 * t2p**2 / d2**3)
            lam = lam - f / df
        q1[positive] = a2 * t1p / (a2 + lam)
        q2[positive] = b2 * t2p / (b2 + lam)
        px, py = from_tribological(self.beta, q1, q2)
        qx[outside], qy[outside] = px, py
        return qx, qy


@dataclass(frozen=True)
class WearLaw(CheckedRecord, WearModel):
    """Principal wear coefficients i1, i2 (1/MPa) along e1, e2 rotated by β (rad): the
    ``"archard"`` wear law, ``[sweep] wear1, wear2``."""

    i1: float
    i2: float
    beta: float = 0.0

    checks = {
        "i1": under_key("wear1", require_non_negative),
        "i2": under_key("wear2", require_non_negative),
        "beta": require_finite,
    }
    name: ClassVar[str] = "archard"
    description: ClassVar[str] = (
        "Archard's orthotropic law (Eqs. 12–14): depth increment = p ||Δg||_i"
    )
    id_prefix: ClassVar[str] = "w"
    rules: ClassVar[dict[str, str]] = {"wear2": PROPORTIONAL}
    coefficients: ClassVar[dict[str, Key]] = {
        "wear1": Key(
            "1/MPa", "Archard wear coefficient i1 along e1", minimum=0.0,
            maximum=MAX_WEAR_COEFFICIENT, why=_ARCHARD_WHY, example=1.33e-7,
        ),
        "wear2": Key(
            "1/MPa", "Archard wear coefficient i2 along e2", minimum=0.0,
            maximum=MAX_WEAR_COEFFICIENT, why=_ARCHARD_WHY, example=1.33e-7,
        ),
    }  # fmt: skip

    @classmethod
    def from_coefficients(cls, values: Mapping[str, float], beta: float) -> WearLaw:
        return cls(values["wear1"], values["wear2"], beta)

    def scaled(self, factor: float) -> WearLaw:
        return WearLaw(self.i1 * factor, self.i2 * factor, self.beta)

    @classmethod
    def read_sweep(cls, section, required: bool) -> dict[str, Any]:
        """``wear1`` (required with wear, else [0]) and ``wear2``: a list, ``"proportional"``
        (every ``mu1`` > 0) or absent (None: wear2 = wear1 element-wise)."""
        default = {} if required else {"default": [0.0]}
        wear1 = section.number_list("wear1", **default, minimum=0.0, unit="1/MPa")
        wear2: tuple[float, ...] | str | None = None
        if "wear2" in section.table:
            given = section.table["wear2"]
            if given == PROPORTIONAL:
                if any(mu == 0.0 for mu in section.number_list("mu1", minimum=0.0)):
                    raise section.error(
                        "wear2", PROPORTIONAL, "needs every mu1 > 0 (wear1·mu2/mu1)"
                    )
                wear2 = PROPORTIONAL
            elif isinstance(given, str):
                raise section.error(
                    "wear2", given, f'must be a list of numbers or "{PROPORTIONAL}"'
                )
            else:
                wear2 = section.number_list("wear2", minimum=0.0, unit="1/MPa")
        return {"wear1": wear1, "wear2": wear2}

    @classmethod
    def combinations(cls, lists, mu1: float, mu2: float) -> list[dict[str, float]]:
        """wear2 absent: (w, w) for w in wear1; ``"proportional"``: (w, w·μ2/μ1); else the
        product wear1 × wear2."""
        wear1, wear2 = lists["wear1"], lists["wear2"]
        if wear2 is None:
            pairs = [(w, w) for w in wear1]
        elif wear2 == PROPORTIONAL:
            pairs = [(w, w * mu2 / mu1) for w in wear1]
        else:
            pairs = list(itertools.product(wear1, wear2))
        return [{"wear1": w1, "wear2": w2} for w1, w2 in pairs]

    @classmethod
    def followers(cls, lists) -> dict[str, tuple[str, str]]:
        if lists["wear2"] is None:
            return {"wear2": ("wear1", "wear1")}
        if lists["wear2"] == PROPORTIONAL:
            return {"wear2": ("wear1", "wear1·mu2/mu1")}
        return {}

    def norm(self, gx: np.ndarray, gy: np.ndarray) -> np.ndarray:
        """||Δg||_i of Eq. (13): mm/MPa for slips in mm."""
        g1, g2 = to_tribological(self.beta, gx, gy)
        return np.hypot(self.i1 * g1, self.i2 * g2)

    def depth_increment(self, pressure: np.ndarray, slip_x: np.ndarray, slip_y: np.ndarray):
        """Δω = p_n ||Δg_t||_i (Eq. 14), mm."""
        return pressure * self.norm(slip_x, slip_y)

    def increment(self, result, previous) -> np.ndarray:
        """Δω of one increment (mm) from its ``result`` (pressure, slip increments); the
        interface every wear law offers (``previous``: the state before it, unused here)."""
        return self.depth_increment(result.pressure, result.slip_x, result.slip_y)


def frictional_work(result, previous) -> np.ndarray:
    """Local frictional work of one increment per area (mJ/mm² = N/mm, shape (n_x, n_y)):
    w = −½ (q_k + q_{k−1}) · Δs_k, the trapezoidal rule on the slip increment Δs_k (mm) with
    the tractions (MPa) of the increment (``result``) and of the previous one
    (``previous``). Its sum times ΔA over a cycle is ∮ Q·dδ minus the change of elastic
    energy (engine.solvers.fretting), exactly, so it is not clipped: on a sliding element
    w ≥ ½ λ h(n) (p_k − p_{k−1}) ≥ 0 while the pressure does not fall (held load, K = 0); in a
    stick zone it is ± the solver tolerance; it can be slightly negative only where a slip
    reverses under a falling pressure (cyclic unloading), and sums to ≥ 0 over a cycle."""
    mean_x = 0.5 * (result.traction_x + previous.traction_x)
    mean_y = 0.5 * (result.traction_y + previous.traction_y)
    return -(mean_x * result.slip_x + mean_y * result.slip_y)


@dataclass(frozen=True)
class EnergyWearLaw(CheckedRecord, WearModel):
    """Dissipated-energy wear law (Fouvry, Kapsa & Vincent, Wear 1996; Fouvry et al. 2003):
    the local wear depth increment is α times the local frictional work per area,
    Δω = α w (mm = mm³/J · J/mm² with w in mJ/mm² → α in mm³/J is scaled by 10⁻³).
    ``alpha`` α in mm³/J (≥ 0). Isotropic by construction: the orthotropy of friction
    enters through the work itself."""

    alpha: float

    checks = {"alpha": require_non_negative}
    name: ClassVar[str] = "energy"
    description: ClassVar[str] = "depth increment = α × local frictional work (Fouvry)"
    id_prefix: ClassVar[str] = "a"
    coefficients: ClassVar[dict[str, Key]] = {
        "alpha": Key(
            "mm^3/J", "dissipated-energy wear coefficient α", minimum=0.0,
            maximum=MAX_ENERGY_WEAR_COEFFICIENT, why="fretting tests: 1e-6 … 1e-4", example=5e-6,
        ),
    }  # fmt: skip

    @classmethod
    def from_coefficients(cls, values: Mapping[str, float], beta: float) -> EnergyWearLaw:
        return cls(values["alpha"])

    def scaled(self, factor: float) -> EnergyWearLaw:
        return EnergyWearLaw(self.alpha * factor)

    def increment(self, result, previous) -> np.ndarray:
        """Δω = α·10⁻³·w (mm), w from :func:`frictional_work` (mJ/mm²)."""
        return self.alpha * 1e-3 * frictional_work(result, previous)
