"""The tangential subproblem of one increment: friction bounds frozen (Tresca-like).

Given the pressure p (so the elliptic bound ||q||_μ ≤ p of every element is fixed) and the
slip Δs(q) = A_tt q + A_tn p − u_t^prev of the current tractions, find the tractions q that
minimise the elastic energy ½ qᵀA_tt q − cᵀq over the product of ellipses; its optimality
conditions are the Coulomb law of Eqs. (8)–(11) with that bound: no slip where ||q||_μ < p,
slip along the inward normal of the ellipse where ||q||_μ = p.

Method: an active-set (face) conjugate gradient, in the spirit of Polonsky & Keer's normal
solver and Vollebregt's TangCG, made mesh independent by two ingredients:
- stick elements are preconditioned by the spectral preconditioner (the |ξ| symbol that
  cancels the 1/|ξ| smoothing of A_tt), restricted to the stick set;
- slip elements move only along the tangent of their ellipse; the energy along the ellipse
  has the curvature term λκ (λ = slip magnitude along the normal, mm; κ = curvature of the
  ellipse, 1/MPa). It enters the step length and the preconditioner: where it exceeds the
  elastic self-stiffness A_ii the slip direction is turned by a Newton step
  r_t / (A_ii + λκ); elsewhere the element stays in the spectral block, scaled by its
  elastic share A_ii / (A_ii + λκ) (symmetrically, D^½ M⁻¹ D^½).
Search directions are combined by Polak–Ribière (restarted when β < 0); each step is
projected on the ellipses and accepted by an Armijo test on the energy (backtracking; after
a few failures a plain projected-gradient step, which always descends), so the energy
decreases monotonically and the active set cannot cycle. Slip elements whose
slip points outward of the ellipse are released to stick. Two operator applications per
iteration (A_tt d for the step, A_tt Δq for the new slip); the energy change is computed
from them, so the solver works with differences and needs no explicit c.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kernels.operator import HalfSpaceOperator, SpectralPreconditioner
from .friction import FrictionLaw, from_tribological, to_tribological

ON_BOUND = 1.0 - 1e-10  # ||q||_μ ≥ ON_BOUND · p counts as on the ellipse (slip)
ARMIJO = 1e-4
MAX_BACKTRACKS = 30
PRECONDITIONED_ATTEMPTS = 6  # halvings along the CG direction before a gradient step


@dataclass
class TangentialResult:
    """``tractions`` (2, n_x, n_y) MPa and the ``slip`` Δs they produce (2, n_x, n_y) mm;
    ``residual``: RMS over ``count`` elements of the face residual (mm); ``iterations``,
    ``backtracks``, ``converged``; ``stalled`` if no step decreased the energy."""

    tractions: np.ndarray
    slip: np.ndarray
    residual: float
    iterations: int
    backtracks: int
    converged: bool
    stalled: bool = False


def ellipse_frame(friction: FrictionLaw, qx: np.ndarray, qy: np.ndarray, rho=None):
    """Unit outward normal (n_x, n_y) and unit tangent (t_x, t_y) of the friction ellipse
    through q, and its curvature κ (1/MPa); zero tractions get an arbitrary frame. ``rho``:
    ||q||_μ when already known."""
    if friction.isotropic:
        return _circle_frame(qx, qy)
    q1, q2 = to_tribological(friction.beta, qx, qy)
    g1, g2 = q1 / friction.mu1**2, q2 / friction.mu2**2  # gradient of ||q||_μ² / 2
    length = np.hypot(g1, g2)
    safe = np.where(length > 0.0, length, 1.0)
    nx, ny = from_tribological(friction.beta, g1 / safe, g2 / safe)
    # Curvature of q1²/a² + q2²/b² = 1 with a = μ1 ρ, b = μ2 ρ (ρ = ||q||_μ):
    # κ = 1 / (a² b² (q1²/a⁴ + q2²/b⁴)^{3/2}).
    rho = friction.norm(qx, qy) if rho is None else rho
    a2, b2 = (friction.mu1 * rho) ** 2, (friction.mu2 * rho) ** 2
    denominator = (
        a2
        * b2
        * (q1**2 / np.where(a2 > 0, a2, 1.0) ** 2 + q2**2 / np.where(b2 > 0, b2, 1.0) ** 2) ** 1.5
    )
    kappa = np.where(denominator > 0.0, 1.0 / np.where(denominator > 0.0, denominator, 1.0), 0.0)
    return nx, ny, -ny, nx, kappa


def _circle_frame(qx: np.ndarray, qy: np.ndarray):
    """``ellipse_frame`` of an isotropic law (μ1 = μ2, any β): the circle through q has the
    normal q/|q| and the curvature 1/|q| (the general formula with a = b = |q|); zero
    tractions get a zero frame and zero curvature, as in the general formula."""
    length = np.hypot(qx, qy)
    inverse = np.divide(1.0, length, out=np.zeros_like(length), where=length > 0.0)
    nx = qx * inverse
    ny = qy * inverse
    return nx, ny, -ny, nx, inverse


def _dot(ax, ay, bx, by) -> float:
    """Σ (a_x b_x + a_y b_y) over the grid (BLAS dot products: no temporary arrays)."""
    return float(np.vdot(ax, bx) + np.vdot(ay, by))


@dataclass
class _Faces:
    """The face of every element at the current tractions: ``sticking`` and ``sliding``
    (on the ellipse with the slip along its inward normal), the ellipse tangent
    (``tx``, ``ty``), the slip along it (``along``, mm) and the curvature stiffness λκ of the
    sliding elements (``curvature``, mm/MPa; 0 elsewhere)."""

    free: np.ndarray
    sticking: np.ndarray
    sliding: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    along: np.ndarray
    curvature: np.ndarray

    def restrict(self, vx: np.ndarray, vy: np.ndarray, v_along: np.ndarray | None = None):
        """``v`` on the faces: as is on stick elements, its component along the tangent
        (``v_along``, default v·t) on slip elements, zero elsewhere."""
        if v_along is None:
            v_along = vx * self.tx + vy * self.ty
        rx = np.where(self.sticking, vx, np.where(self.sliding, v_along * self.tx, 0.0))
        ry = np.where(self.sticking, vy, np.where(self.sliding, v_along * self.ty, 0.0))
        return rx, ry


def _faces(friction: FrictionLaw, bound, free, qx, qy, gx, gy) -> _Faces:
    """Classify the elements at tractions q with slip g (see :class:`_Faces`)."""
    norm = friction.norm(qx, qy)
    nx, ny, tx, ty, kappa = ellipse_frame(friction, qx, qy, norm)
    on_bound = free & (norm >= ON_BOUND * bound)
    multiplier = -(gx * nx + gy * ny)  # λ ≥ 0: slip along the inward normal
    sliding = on_bound & (multiplier > 0.0)
    along = gx * tx + gy * ty
    curvature = np.where(sliding, multiplier * kappa, 0.0)
    return _Faces(free, free & ~sliding, sliding, tx, ty, along, curvature)


def _precondition(preconditioner, self_xx, self_yy, faces: _Faces, rx, ry):
    """The preconditioned residual z = M⁻¹ r. Where the curvature stiffness λκ of a slip
    element exceeds its elastic self-stiffness A_ii, its direction is turned by the Newton
    step r_t / (A_ii + λκ); the other slip elements stay in the spectral block scaled by
    D^½ M⁻¹ D^½, D = A_ii / (A_ii + λκ) their elastic share (1 on stick elements)."""
    tx, ty, along, sliding, curvature = (
        faces.tx,
        faces.ty,
        faces.along,
        faces.sliding,
        faces.curvature,
    )
    stiffness = self_xx * tx**2 + self_yy * ty**2
    newton = sliding & (curvature > stiffness)
    share = np.divide(stiffness, stiffness + curvature, out=np.ones_like(along), where=sliding)
    scale = np.where(faces.free & ~newton, np.sqrt(share), 0.0)
    zx, zy = preconditioner.tangential(scale * rx, scale * ry)
    zx, zy = scale * zx, scale * zy
    newton_step = np.divide(along, stiffness + curvature, out=np.zeros_like(along), where=newton)
    return faces.restrict(zx, zy, np.where(newton, newton_step, zx * tx + zy * ty))


@dataclass
class _Step:
    """An accepted step: the traction change (MPa), the slip change A_tt Δq it makes (mm),
    the halvings it took, and whether it fell back to a gradient step (the conjugate
    directions restart)."""

    change_x: np.ndarray
    change_y: np.ndarray
    image_x: np.ndarray
    image_y: np.ndarray
    backtracks: int
    restarted: bool


def _line_search(operator, friction, bound, free, q, g, d, step, lipschitz) -> _Step | None:
    """Backtracking along ``d`` from the tractions ``q`` (slip ``g``), each trial projected
    on the ellipses and accepted by the Armijo test on the energy; after
    ``PRECONDITIONED_ATTEMPTS`` halvings a plain projected-gradient step (which descends for
    any step ≤ 1/L). None when no step decreases the energy measurably."""
    (qx, qy), (gx, gy), (dx, dy) = q, g, d
    restarted = False
    for attempt in range(MAX_BACKTRACKS):
        if attempt == PRECONDITIONED_ATTEMPTS:
            # The preconditioned path keeps failing (far from the solution, the metric and
            # the projection disagree): take a plain projected-gradient step.
            dx, dy = np.where(free, gx, 0.0), np.where(free, gy, 0.0)
            step, restarted = 1.0 / lipschitz, True
        new_x, new_y = friction.project(qx - step * dx, qy - step * dy, bound)
        change_x = np.where(free, new_x, 0.0) - qx
        change_y = np.where(free, new_y, 0.0) - qy
        image_x, image_y = operator.apply_tangential(change_x, change_y)
        first = _dot(gx, gy, change_x, change_y)
        energy_change = first + 0.5 * _dot(image_x, image_y, change_x, change_y)
        if energy_change <= ARMIJO * first:
            return _Step(change_x, change_y, image_x, image_y, attempt, restarted)
        step *= 0.5
    return None


def _self_stiffness(operator: HalfSpaceOperator) -> tuple[float, float]:
    """A_ii of the x and y tangential blocks (mm/MPa): an element's own compliance."""
    return operator.self_coefficient("xx"), operator.self_coefficient("yy")


def solve_tangential(
    operator: HalfSpaceOperator,
    preconditioner: SpectralPreconditioner,
    friction: FrictionLaw,
    bound: np.ndarray,
    tractions: np.ndarray,
    slip: np.ndarray,
    *,
    tol: float,
    maxiter: int,
    count: int,
    lipschitz: float,
) -> TangentialResult:
    """Minimise the tangential energy over ||q||_μ ≤ ``bound`` (MPa) starting from
    ``tractions`` (already inside the ellipses) whose slip is ``slip`` (mm); stop when the
    RMS face residual over ``count`` elements is ≤ ``tol`` (mm) or after ``maxiter``
    iterations. ``lipschitz`` bounds the largest eigenvalue of A_tt (mm/MPa)."""
    self_xx, self_yy = _self_stiffness(operator)
    free = bound > 0.0
    qx, qy = tractions[0].copy(), tractions[1].copy()
    gx, gy = slip[0].copy(), slip[1].copy()
    dx = dy = rx_old = ry_old = None
    rz_old = 0.0
    residual, backtracks, iterations, stalled = math.inf, 0, 0, False
    for iterations in range(maxiter + 1):  # noqa: B007 (count kept after loop)
        faces = _faces(friction, bound, free, qx, qy, gx, gy)
        rx, ry = faces.restrict(gx, gy, faces.along)
        residual = math.sqrt(_dot(rx, ry, rx, ry) / count)
        if residual <= tol or iterations == maxiter:
            break
        zx, zy = _precondition(preconditioner, self_xx, self_yy, faces, rx, ry)
        rz = _dot(rx, ry, zx, zy)
        if rx_old is None:
            dx, dy = zx, zy
        else:  # Polak–Ribière, restarted when β < 0
            beta = max(0.0, (rz - _dot(rx_old, ry_old, zx, zy)) / rz_old)
            dx, dy = faces.restrict(zx + beta * dx, zy + beta * dy)
        rx_old, ry_old, rz_old = rx, ry, rz
        wx, wy = operator.apply_tangential(dx, dy)
        d_along = dx * faces.tx + dy * faces.ty
        bending = float(np.vdot(faces.curvature, d_along * d_along))
        step = _dot(rx, ry, dx, dy) / (_dot(wx, wy, dx, dy) + bending)
        found = _line_search(
            operator, friction, bound, free, (qx, qy), (gx, gy), (dx, dy), step, lipschitz
        )
        if found is None:
            backtracks += MAX_BACKTRACKS
            stalled = True  # no decrease measurable: the energy is at round-off level
            break
        backtracks += found.backtracks
        if found.restarted:
            rx_old = None
        qx, qy = qx + found.change_x, qy + found.change_y
        gx, gy = gx + found.image_x, gy + found.image_y
    return TangentialResult(
        tractions=np.array([qx, qy]),
        slip=np.array([gx, gy]),
        residual=residual,
        iterations=iterations,
        backtracks=backtracks,
        converged=residual <= tol,
        stalled=stalled,
    )
