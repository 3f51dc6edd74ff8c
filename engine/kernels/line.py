"""Plane-strain influence coefficients of two elastic bodies in line contact (the x–z plane).

The 2-D counterpart of ``engine.kernels.influence``: a uniform traction over the strip
|x − x_j| ≤ Δx/2 (infinitely long along y) on two half-planes, the relative surface
displacement u = u^(A) − u^(B) at x (z into body A, tractions acting on A, the conventions
of the 3-D kernels). Integrating the 3-D point kernels of Eq. (5) along y gives the
classical line-load (Flamant) surface displacements (Johnson 1985, Eqs. 2.19–2.20):

    A_zz(X) = A_xx(X) = −(2/(π E*)) ln(|X| / d)       (E* the contact modulus; 2/E* =
                                                       Σ 2(1−ν_i²)/E_i = 2(1−ν)/G of Eq. 6)
    A_zx(X) = −A_xz(X) = (K/G) sgn(X) = β (1−ν)/G sgn(X)     (β: Dundurs' second constant)

with X = x − x'. The normal–tangential coupling K/G is the same constant as in 3-D: the
y-integral of K X/(π G s²) is (K/G) sgn X.

**The rigid-body constant.** A 2-D surface displacement grows like ln|X| and is defined
only up to a constant. The kernels here are *displacement differences*: ``A(X)`` is the
displacement at distance |X| from the load minus that at the distance ``d``
(``reference_distance``, mm), i.e. the displacement relative to a datum at distance d.
The constant does not change the pressure or the tractions under load control (it is taken
up by the approach δ, and by the rigid tangential displacement under force control), nor the
energy dissipated per fretting cycle (a linear compliance encloses no area); it does set the
rigid tangential displacement under *displacement* control, where d plays the role of the
size of the bodies (the far-field compliance (2/(πE*)) ln(d/a) per unit load). The
coupling kernel needs no datum: its two sides are antisymmetric.

Element integration (exact): ∫ ln(|u|/d) du over the element = F(X + Δx/2) − F(X − Δx/2),
F(u) = u ln(|u|/d) − u; ∫ sgn(X − t) dt over the element = Δx sgn(X) at element centres.

Plane strain has no y-traction; the fields keep the ``(n, 1)`` shape of a line grid
(``Grid.line``) and carry a y-component that nothing drives (A_xy = A_zy = 0). Its kernel is
set to A_yy = A_xx so that the block operator and its spectral preconditioner stay
invertible; q_y stays zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import Grid
from ..material import MaterialPair
from ..validation import require_positive
from .fft import DEFAULT_EFFORT
from .influence import SurfaceInfluence
from .operator import HalfSpaceOperator

__all__ = ["LineInfluence", "line_operator", "log_strip_integral", "minimum_reference_distance"]

# The log kernel ln(d/|X|) is positive definite on a segment of length L only when d exceeds
# the segment's logarithmic capacity L/4; a datum beyond the grid's whole length keeps every
# contact matrix comfortably positive definite.
REFERENCE_DISTANCE_FACTOR = 1.0


def minimum_reference_distance(grid: Grid) -> float:
    """The smallest accepted ``reference_distance`` for ``grid`` (mm): its length 2·half_width."""
    return REFERENCE_DISTANCE_FACTOR * 2.0 * grid.half_width_x


def log_strip_integral(offset: np.ndarray, width: float, reference_distance: float):
    """∫ ln(|u| / d) du over |u − offset| ≤ width/2 (mm), exact, for any offset (mm)."""

    def antiderivative(u):
        magnitude = np.abs(u)
        safe = np.where(magnitude > 0.0, magnitude, 1.0)
        return np.where(magnitude > 0.0, u * np.log(safe / reference_distance), 0.0) - u

    offset = np.asarray(offset, dtype=float)
    return antiderivative(offset + 0.5 * width) - antiderivative(offset - 0.5 * width)


@dataclass(frozen=True)
class LineInfluence(SurfaceInfluence):
    """Plane-strain kernels on the offset grid of a line grid (mm/MPa), shape ``(2n − 1, 1)``
    (entry ``[a, 0]``: offset (a − n + 1) Δx, observation minus source), keys as
    ``SurfaceInfluence`` (``xx, yy, xy, zz, zx, zy``); ``reference_distance`` d (mm) is the
    datum of the displacements (module docstring)."""

    reference_distance: float = 0.0

    @classmethod
    def build(
        cls, grid: Grid, material: MaterialPair, reference_distance: float | None = None
    ) -> LineInfluence:
        if not grid.is_line:
            raise ValueError(f"a line contact needs a line grid (n_y = 1), got {grid.shape}")
        if reference_distance is None:
            raise ValueError("reference_distance (mm) is required for a line contact")
        reference_distance = require_positive("reference_distance", reference_distance)
        minimum = minimum_reference_distance(grid)
        if reference_distance < minimum:
            raise ValueError(
                f"reference_distance = {reference_distance:g} mm must be at least the grid's "
                f"length {minimum:g} mm (the log kernel is not positive definite otherwise)"
            )
        offsets = grid.dx * np.arange(-(grid.n_x - 1), grid.n_x)
        compliance = 2.0 / (np.pi * material.contact_modulus)
        normal = -compliance * log_strip_integral(offsets, grid.dx, reference_distance)
        coupling = material.coupling / material.shear_modulus * grid.dx * np.sign(offsets)
        zeros = np.zeros_like(normal)
        line_kernels = {"zz": normal, "xx": normal, "yy": normal, "xy": zeros, "zx": coupling}
        line_kernels["zy"] = zeros
        kernels = {key: values[:, None].copy() for key, values in line_kernels.items()}
        return cls(grid, kernels, reference_distance)


def line_operator(
    grid: Grid,
    material: MaterialPair,
    reference_distance: float,
    *,
    threads: int = 1,
    planner_effort: str = DEFAULT_EFFORT,
) -> HalfSpaceOperator:
    """The influence operator of a line contact: ``HalfSpaceOperator``'s DC-FFT applied to
    the plane-strain kernels of a line grid (a transform of length 2n along x; the y axis
    has one element and no offsets, so its transform is trivial)."""
    influence = LineInfluence.build(grid, material, reference_distance)
    return HalfSpaceOperator(
        grid, material, threads=threads, planner_effort=planner_effort, influence=influence
    )
