"""Axisymmetric ring boundary elements for normal contact with Coulomb friction and coupling.

An independent reference for the frictional Hertz problem between dissimilar bodies
(Dundurs' β ≠ 0, Spence, *J. Elasticity* 5, 1975): no grid of squares, no FFT, no influence
matrix of the engine. The surface tractions are axisymmetric, p(r) (pressure, MPa) and q(r)
(radial shear on the half-space, MPa), piecewise constant on N rings of width h. The relative
surface displacements of the two bodies, normal w(r) and radial u(r) (mm), follow from the
Hankel-transform form of the half-space solution (Boussinesq–Cerruti, both bodies added):

    w(r) = C [ ∫₀^∞ p̄(ξ) J₀(ξr) dξ + β ∫₀^∞ q̄(ξ) J₀(ξr) dξ ]
    u(r) = C [ ∫₀^∞ q̄(ξ) J₁(ξr) dξ + β ∫₀^∞ p̄(ξ) J₁(ξr) dξ ]
    p̄(ξ) = ∫₀^∞ p(s) J₀(ξs) s ds,   q̄(ξ) = ∫₀^∞ q(s) J₁(ξs) s ds,   C = 2/E*

(C is the compliance 2(1−ν)/G of the paper's Eq. 6 combination, β = K/(1−ν); the sign of β
only flips the direction of slip). Exchanging the order of integration, with the
Weber–Schafheitlin integrals

    ∫₀^∞ J₀(ξr) J₀(ξs) dξ = 2 K(k) / (π (r + s)),       k² = 4rs / (r + s)²
    ∫₀^∞ J₁(ξr) J₁(ξs) dξ = [χ k K(k) − √(2(1 + χ)) E(k)] / (π √(rs)),   χ = (r² + s²)/(2rs),
                                                          (the same k: k² = 2/(1 + χ))
    ∫₀^∞ J₁(ξs) J₀(ξr) dξ = 1/s for s > r, 0 for s < r
    ∫₀^∞ J₀(ξs) J₁(ξr) dξ = 1/r for s < r, 0 for s > r

(K, E complete elliptic integrals; the second is the Legendre function Q_{1/2}(χ)/(π√(rs))):

    w(r) = C [ ∫ p(s) s M₀(r, s) ds + β ∫_r^∞ q(s) ds ]
    u(r) = C [ ∫ q(s) s M₁(r, s) ds + (β / r) ∫₀^r p(s) s ds ]

The ring integrals of the logarithmically singular M₀, M₁ are done by 12-point Gauss–Legendre
on far rings and, on the ring of the collocation point r and two either side, by 48-point
Gauss–Legendre after s = x₀ + (end − x₀) t² from the point x₀ of the ring nearest r (the log
becomes a smooth t log t).

Loading is monotonic, in increments of the approach δ: in contact w = δ − f(r) and p ≥ 0;
a contact ring sticks (its radial displacement u does not change during the increment) while
|q| ≤ μp, else it slips with q = ∓μp opposing the slip increment. A ring entering contact
sticks at the u it had just before. The active sets are found by iteration in each increment.

Checks (tests/test_frictional_sphere_reference.py): the kernels against their Bessel
integrals; frictionless Hertz (a² = Rδ, P, p(0) to 2e-5 at 120 rings); the rigid flat punch
in full stick gives Mossakovskii's stiffness ratio artanh(β)/β
(:func:`engine.reference.flat_punch.mossakovskii_ratio`; −3.5e-5 at 200 rings); under
monotonic loading of a sphere the stick radius c/a is constant (Spence's self-similarity).
β = 0.280 (the paper's pair): c/a = 0.2111 (μ = 0.1; 0.2130 at 480 rings) and 0.7085
(μ = 0.2).

Range: the active sets settle for β/μ ≥ 1.4 (μ ≤ 0.2 at β = 0.28). For larger μ the stick
zone reaches the contact edge, where the piecewise-constant shear of the stuck rings
oscillates from ring to ring (the bonded edge's oscillatory singularity) and a ring entering
contact flips in and out with the slip front: RuntimeError, no silent answer. Spence's
closed-form c/a(β/μ) was not found in the sources available here, so it is not used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.special import ellipe, ellipk

__all__ = [
    "RingContactResult",
    "flat_punch_full_stick",
    "frictional_sphere_loading",
    "ring_influence",
    "spence_stick_ratio",
]

HERTZ_LOAD = 8.0 / 3.0  # Hertz's load at δ = R = 1, per unit C = 2/E*
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(12)
_NEAR_NODES, _NEAR_WEIGHTS = (
    0.5 * (x + 1.0) if k == 0 else 0.5 * x
    for k, x in enumerate(np.polynomial.legendre.leggauss(48))
)  # on [0, 1]


def _kernel_normal(r, s):
    """M₀(r, s) = ∫₀^∞ J₀(ξr) J₀(ξs) dξ (1/mm)."""
    r, s = np.broadcast_arrays(np.asarray(r, float), np.asarray(s, float))
    m = np.clip(4.0 * r * s / (r + s) ** 2, 0.0, 1.0 - 1e-16)
    return 2.0 * ellipk(m) / (math.pi * (r + s))


def _kernel_radial(r, s):
    """M₁(r, s) = ∫₀^∞ J₁(ξr) J₁(ξs) dξ (1/mm); 0 where r or s is 0."""
    r, s = np.broadcast_arrays(np.asarray(r, float), np.asarray(s, float))
    out = np.zeros(r.shape)
    ok = (r > 0) & (s > 0)
    rr, ss = r[ok], s[ok]
    chi = (rr**2 + ss**2) / (2.0 * rr * ss)
    m = np.clip(2.0 / (1.0 + chi), 0.0, 1.0 - 1e-16)
    k = np.sqrt(m)
    out[ok] = (chi * k * ellipk(m) - np.sqrt(2.0 * (1.0 + chi)) * ellipe(m)) / (
        math.pi * np.sqrt(rr * ss)
    )
    return out


@lru_cache(maxsize=8)
def ring_influence(rings: int, width: float) -> tuple[np.ndarray, ...]:
    """Influence matrices (per unit C) of ``rings`` rings of ``width`` (mm), collocated at
    the ring midpoints r_i = (i + ½) h: returns (r, A_pw, A_qu, B_qw, B_pu) with
    w = C (A_pw p + β B_qw q), u = C (A_qu q + β B_pu p). A_pw, A_qu in mm; B_qw, B_pu in mm."""
    h = width
    r = (np.arange(rings) + 0.5) * h
    lower = np.arange(rings) * h
    # far rings: Gauss–Legendre over each ring
    s = lower[None, :, None] + 0.5 * h * (_GAUSS_NODES + 1.0)[None, None, :]
    weights = 0.5 * h * _GAUSS_WEIGHTS
    rr = r[:, None, None]
    normal = np.sum(weights * s * _kernel_normal(rr, s), axis=2)
    radial = np.sum(weights * s * _kernel_radial(rr, s), axis=2)
    # near rings (log singularity at s = r_i): Gauss–Legendre after s = x0 + (end − x0) t²,
    # x0 the point of the ring nearest to r_i, which turns the log into a smooth t log t
    for offset in range(-2, 3):
        i = np.arange(max(0, -offset), min(rings, rings - offset))
        j = i + offset
        lo, hi = lower[j], lower[j] + h
        x0 = np.clip(r[i], lo, hi)
        normal[i, j] = 0.0
        radial[i, j] = 0.0
        for end, direction in ((lo, -1.0), (hi, 1.0)):  # ∫_lo^hi = ∫_x0^hi − ∫_x0^lo
            span = (end - x0)[:, None]
            s = x0[:, None] + span * _NEAR_NODES**2
            jacobian = direction * 2.0 * span * _NEAR_NODES * _NEAR_WEIGHTS
            normal[i, j] += np.sum(jacobian * s * _kernel_normal(r[i][:, None], s), axis=1)
            radial[i, j] += np.sum(jacobian * s * _kernel_radial(r[i][:, None], s), axis=1)
    index = np.arange(rings)
    above = (index[None, :] > index[:, None]).astype(float) * h
    coupling_qw = above + np.eye(rings) * 0.5 * h  # ∫_r^∞ q ds
    upper = lower + h
    below = np.where(index[None, :] < index[:, None], 0.5 * (upper**2 - lower**2)[None, :], 0.0)
    below = below + np.diag(0.5 * (r**2 - lower**2))
    coupling_pu = below / r[:, None]  # (1/r) ∫_0^r p s ds
    return r, normal, radial, coupling_qw, coupling_pu


@dataclass(frozen=True)
class RingContactResult:
    """End state of a loading history. Lengths in the unit of the profile (R = 1 for
    :func:`frictional_sphere_loading`); tractions and load per unit compliance C = 2/E*
    (times E*/2 for MPa, times E*/2 × length² for N)."""

    radius: np.ndarray  # ring midpoints
    width: float  # ring width
    pressure: np.ndarray  # p
    shear: np.ndarray  # q, radial, on the half-space
    stick: np.ndarray  # bool, in contact and sticking
    approach: float  # δ
    load: float  # P = 2π ∫ p r dr
    contact_radius: float  # outer edge of the outermost loaded ring
    stick_radius: float  # outer edge of the central stick disc
    stick_area_radius: float  # √(stick area / π), as the engine measures it
    history: tuple  # the five scalars above, from approach on, per increment


def _solve_increment(mats, gap, u_prev, friction, beta, contact, stick, sign):
    """One increment with given active sets (contact, stick, slip direction): returns p, q
    (per unit C). Unknowns are the contact rings' p and q only; outside contact both are 0.

    Contact rows: w = gap. Stick rows: u = u at the end of the previous increment.
    Slip rows: q + sign μ p = 0."""
    _, a_pw, a_qu, b_qw, b_pu = mats
    rings = np.flatnonzero(contact)
    n = rings.size
    stuck = stick[rings]
    matrix = np.zeros((2 * n, 2 * n))
    rhs = np.zeros(2 * n)
    grid = np.ix_(rings, rings)
    matrix[:n, :n] = a_pw[grid]
    matrix[:n, n:] = beta * b_qw[grid]
    rhs[:n] = gap[rings]
    tangential = np.zeros((n, 2 * n))
    tangential[:, :n] = beta * b_pu[grid]
    tangential[:, n:] = a_qu[grid]
    slipping = np.flatnonzero(~stuck)
    tangential[slipping] = 0.0
    tangential[slipping, n + slipping] = 1.0
    if slipping.size:
        tangential[slipping, slipping] = sign[rings[slipping]] * friction
    matrix[n:] = tangential
    rhs[n:] = np.where(stuck, u_prev[rings], 0.0)
    solution = np.linalg.solve(matrix, rhs)
    p = np.zeros(gap.size)
    q = np.zeros(gap.size)
    p[rings] = solution[:n]
    q[rings] = solution[n:]
    return p, q


def _loading(profile, approaches, rings, width, friction, beta, max_iterations=100):
    """Monotonic loading through ``approaches`` (mm) of a punch of profile f(r) (mm);
    ``friction`` = μ (math.inf: full stick). Tractions are per unit C (the callers divide
    by C = 2/E*)."""
    mats = ring_influence(rings, width)
    r, a_pw, a_qu, b_qw, b_pu = mats
    f = profile(r)
    p, q, u, w = (np.zeros(rings) for _ in range(4))
    contact = np.zeros(rings, bool)
    stick = np.zeros(rings, bool)
    sign = np.zeros(rings)  # direction of the slip increment of slipping rings (±1)
    full_stick = math.isinf(friction)
    history = []
    for delta in approaches:
        gap = delta - f
        u_prev = u.copy()
        entering = ~contact & (w < gap)
        contact = contact | entering
        stick = stick | entering
        visited, cycling = set(), False
        for _ in range(max_iterations):
            p, q = _solve_increment(mats, gap, u_prev, friction, beta, contact, stick, sign)
            w = a_pw @ p + beta * (b_qw @ q)
            u = a_qu @ q + beta * (b_pu @ p)
            new_contact = np.where(contact, p > 0.0, w < gap)
            new_stick = stick & new_contact | (new_contact & ~contact)
            new_sign = np.where(new_contact & ~new_stick, sign, 0.0)
            if not full_stick:
                over = stick & contact & new_contact & (np.abs(q) > friction * p)
                new_stick[over] = False
                new_sign[over] = -np.sign(q[over])
                back = ~stick & contact & new_contact & ((u - u_prev) * sign < 0.0)
                new_stick[back] = True
                new_sign[back] = 0.0
            changed = np.flatnonzero(
                (new_contact != contact) | (new_stick != stick) | (new_sign != sign)
            )
            settled = changed.size == 0
            if cycling and changed.size > 1:
                # changing several rings at once can cycle (a ring entering at the edge as
                # the slip front moves): once a state has repeated, one ring at a time,
                # the innermost first
                keep = np.ones(contact.size, bool)
                keep[changed[0]] = False
                new_contact = np.where(keep, contact, new_contact)
                new_stick = np.where(keep, stick, new_stick)
                new_sign = np.where(keep, sign, new_sign)
            contact, stick, sign = new_contact, new_stick, new_sign
            if settled:
                break
            state = (contact.tobytes(), stick.tobytes(), sign.tobytes())
            cycling = cycling or state in visited
            visited.add(state)
        else:
            raise RuntimeError(f"ring contact: active sets did not settle at approach {delta}")
        history.append(_measure(r, width, p, contact, stick, delta))
    return RingContactResult(r, width, p, q, stick & contact, *history[-1], tuple(history))


def _measure(r, width, pressure, contact, stick, delta):
    """(approach, load, contact radius, central stick radius, area-equivalent stick radius)."""
    load = 2.0 * math.pi * float(np.sum(pressure * r)) * width
    loaded = np.flatnonzero(contact)
    contact_radius = (loaded.max() + 1) * width if loaded.size else 0.0
    not_stick = np.flatnonzero(~(stick & contact))
    central = not_stick.min() * width if not_stick.size else contact_radius
    area = float(np.sum((stick & contact) * 2.0 * math.pi * r * width))
    return float(delta), load, contact_radius, central, math.sqrt(area / math.pi)


def frictional_sphere_loading(
    dundurs_beta: float, friction: float, rings: int = 240, increments: int = 60,
    extent: float = 1.2,
) -> RingContactResult:  # fmt: skip
    """Sphere f(r) = r²/2 (R = 1) loaded monotonically to the approach δ = 1 (Hertz: a = 1),
    in ``increments`` steps δ_k = (k/increments)², so that the contact radius grows by about
    one ring per step when ``rings`` = increments × extent. Units: lengths in R, tractions
    and load per unit compliance C = 2/E* (multiply p, q by E*/2 and P by E* R²/2 for MPa
    and N). ``friction`` = μ, or math.inf for full stick; β = μ = 0 gives Hertz."""
    width = extent / rings
    approaches = (np.arange(1, increments + 1) / increments) ** 2
    return _loading(lambda r: 0.5 * r**2, approaches, rings, width, friction, dundurs_beta)


def flat_punch_full_stick(dundurs_beta: float, rings: int = 200) -> float:
    """Load of a flat punch of radius 1 pressed by δ = 1 in full stick, relative to the
    frictionless one (Mossakovskii's ratio artanh(β)/β for a fine enough ring mesh)."""
    width = 1.0 / rings
    flat = lambda r: np.where(r < 1.0, 0.0, np.inf)  # noqa: E731 - the punch face only
    bonded = _loading(flat, np.array([1.0]), rings, width, math.inf, dundurs_beta)
    smooth = _loading(flat, np.array([1.0]), rings, width, 0.0, 0.0)
    return bonded.load / smooth.load


def spence_stick_ratio(dundurs_beta: float, friction: float, **mesh) -> dict:
    """Stick radius c/a and stiffness ratio k_μ/k_0 of the frictional Hertz problem under
    monotonic loading, from :func:`frictional_sphere_loading` (Spence 1975: c/a is constant
    during the loading and depends on β/μ only). ``k_μ/k_0`` = δ_0/δ_μ at equal load
    = (P_μ/P_0)^(2/3) at equal approach (P ∝ δ^(3/2) for both), P_0 = Hertz's
    (4/3) E* R^½ δ^(3/2) = 8/3 in these units (the rings reproduce it to 2e-5).

    Returns arrays over the increments: approach δ, contact radius a, c/a for the central
    stick disc and for √(stick area/π) (as the engine measures c); the final k_μ/k_0; and
    the final RingContactResult. Lengths in units of R, a ≈ 1 at the end."""
    frictional = frictional_sphere_loading(dundurs_beta, friction, **mesh)
    history = np.array(frictional.history)
    return {
        "approach": history[:, 0],
        "contact_radius": history[:, 2],
        "stick_ratio": history[:, 3] / history[:, 2],
        "stick_area_ratio": history[:, 4] / history[:, 2],
        "stiffness_ratio": (frictional.load / HERTZ_LOAD) ** (2.0 / 3.0),
        "result": frictional,
    }
