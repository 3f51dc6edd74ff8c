"""Element-integrated surface influence coefficients of two elastic half-spaces (Eqs. 3–6).

The point kernels of the paper's Eq. (5) relate a unit traction at x' to the relative surface
displacement u = u^(A) − u^(B) at x (z into the half-space A, tractions acting on A):

    A_zz = (1−ν)/(πG s)            A_xx = [(1−ν)/s + ν X²/s³]/(πG)     A_xy = ν X Y/(πG s³)
    A_zx = K X/(πG s²) = −A_xz     A_zy = K Y/(πG s²) = −A_yz

with X = x − x', Y = y − y', s = √(X² + Y²) and the combined G, ν, K of Eq. (6)
(``MaterialPair``). A uniform traction over a Δx × Δy element is integrated exactly with the
antiderivatives of NOTES.md (Love 1929; Johnson 1985 §3.2), so the coefficients are finite
everywhere, the element's own included.

With K > 0 (half-space softer than the punch), A_xz(X > 0) < 0: the surface of the
half-space moves toward a compressed region, i.e. toward the punch axis under the punch.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import Grid
from ..material import MaterialPair


def _log_x_plus_r(x: np.ndarray, y: np.ndarray, r: np.ndarray) -> np.ndarray:
    """ln(x + r), r = √(x²+y²), without cancellation for x < 0: x + r = y²/(r − x)."""
    negative = x < 0
    out = np.empty_like(x)
    out[~negative] = np.log(x[~negative] + r[~negative])
    xn, yn, rn = x[negative], y[negative], r[negative]
    out[negative] = np.log(yn * yn) - np.log(rn - xn)
    return out


def _antiderivatives(x: np.ndarray, y: np.ndarray) -> dict[str, np.ndarray]:
    """The corner functions F of NOTES.md at (X, Y); never evaluated at X = 0 or Y = 0."""
    r = np.hypot(x, y)
    log_xr = _log_x_plus_r(x, y, r)
    log_yr = _log_x_plus_r(y, x, r)
    log_r = np.log(r)
    return {
        "one_over_r": x * log_yr + y * log_xr,
        "xx": y * log_xr,
        "yy": x * log_yr,
        "xy": -r,
        "x": x * np.arctan(y / x) + y * log_r,
        "y": y * np.arctan(x / y) + x * log_r,
    }


def element_integrals(offset_x: np.ndarray, offset_y: np.ndarray, dx: float, dy: float):
    """∬ over an element of the point kernels 1/R, X²/R³, Y²/R³, XY/R³, X/R², Y/R².

    ``offset_x``, ``offset_y`` are the observation point minus the element centre (mm),
    broadcast against each other; the element is ``dx × dy`` (mm). Returns a dict of arrays
    with keys ``one_over_r, xx, yy, xy, x, y`` (units mm, 1, 1, 1, mm⁰·ln… see NOTES.md).
    """
    ox, oy = np.broadcast_arrays(np.asarray(offset_x, float), np.asarray(offset_y, float))
    total = None
    for sx, sy, sign in ((1, 1, 1.0), (1, -1, -1.0), (-1, 1, -1.0), (-1, -1, 1.0)):
        corner = _antiderivatives(ox + sx * 0.5 * dx, oy + sy * 0.5 * dy)
        if total is None:
            total = {key: sign * value for key, value in corner.items()}
        else:
            for key, value in corner.items():
                total[key] += sign * value
    return total


@dataclass(frozen=True)
class SurfaceInfluence:
    """Influence-coefficient kernels on the offset grid of a ``Grid`` (mm/MPa).

    Each kernel has shape ``(2 n_x − 1, 2 n_y − 1)``; entry ``[a, b]`` is the displacement at
    an element centre caused by unit traction on the element whose centre lies at offset
    ``((a − n_x + 1) Δx, (b − n_y + 1) Δy)`` *behind* it (observation minus source).
    Keys: ``xx, yy, xy, zz, zx, zy`` (A_yx = A_xy, A_xz = −A_zx, A_yz = −A_zy).
    """

    grid: Grid
    kernels: dict[str, np.ndarray]

    @classmethod
    def build(cls, grid: Grid, material: MaterialPair) -> SurfaceInfluence:
        offsets_x = grid.dx * np.arange(-(grid.n_x - 1), grid.n_x)
        offsets_y = grid.dy * np.arange(-(grid.n_y - 1), grid.n_y)
        ox, oy = np.meshgrid(offsets_x, offsets_y, indexing="ij")
        f = element_integrals(ox, oy, grid.dx, grid.dy)
        nu, K = material.poisson_ratio, material.coupling
        scale = 1.0 / (np.pi * material.shear_modulus)
        kernels = {
            "zz": scale * (1.0 - nu) * f["one_over_r"],
            "xx": scale * ((1.0 - nu) * f["one_over_r"] + nu * f["xx"]),
            "yy": scale * ((1.0 - nu) * f["one_over_r"] + nu * f["yy"]),
            "xy": scale * nu * f["xy"],
            "zx": scale * K * f["x"],
            "zy": scale * K * f["y"],
        }
        return cls(grid, kernels)

    def dense_matrix(self) -> np.ndarray:
        """The full 3N × 3N matrix [[A_xx A_xy A_xz] [A_yx A_yy A_yz] [A_zx A_zy A_zz]].

        For tests and tiny grids only (N = n_x·n_y); unknowns ordered (p_x, p_y, p_n), each
        flattened in C order of the ``(n_x, n_y)`` field.
        """
        nx, ny = self.grid.shape
        i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
        i, j = i.ravel(), j.ravel()
        a = i[:, None] - i[None, :] + nx - 1
        b = j[:, None] - j[None, :] + ny - 1
        k = {key: value[a, b] for key, value in self.kernels.items()}
        return np.block(
            [
                [k["xx"], k["xy"], -k["zx"]],
                [k["xy"], k["yy"], -k["zy"]],
                [k["zx"], k["zy"], k["zz"]],
            ]
        )
