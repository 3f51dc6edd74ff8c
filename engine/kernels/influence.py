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


#: The corner functions of ``element_integrals`` (keys of ``_antiderivatives``).
INTEGRALS = ("one_over_r", "xx", "yy", "xy", "x", "y")

#: The element integrals each kernel of ``SurfaceInfluence`` combines (``kernel_values``).
KERNEL_INTEGRALS = {
    "zz": ("one_over_r",),
    "xx": ("one_over_r", "xx"),
    "yy": ("one_over_r", "yy"),
    "xy": ("xy",),
    "zx": ("x",),
    "zy": ("y",),
}

#: Rows of offsets evaluated at once by ``kernel_values``: bounds its temporaries (a dozen
#: arrays of this many rows) whatever the grid; the values do not depend on it.
BLOCK_ELEMENTS = 1 << 16


def _antiderivatives(x: np.ndarray, y: np.ndarray, keys=INTEGRALS) -> dict[str, np.ndarray]:
    """The corner functions F of NOTES.md at (X, Y), those named in ``keys`` only; never
    evaluated at X = 0 or Y = 0."""
    r = np.hypot(x, y)
    needs = set(keys)
    log_xr = _log_x_plus_r(x, y, r) if needs & {"one_over_r", "xx"} else None
    log_yr = _log_x_plus_r(y, x, r) if needs & {"one_over_r", "yy"} else None
    log_r = np.log(r) if needs & {"x", "y"} else None
    formulas = {
        "one_over_r": lambda: x * log_yr + y * log_xr,
        "xx": lambda: y * log_xr,
        "yy": lambda: x * log_yr,
        "xy": lambda: -r,
        "x": lambda: x * np.arctan(y / x) + y * log_r,
        "y": lambda: y * np.arctan(x / y) + x * log_r,
    }
    return {key: formulas[key]() for key in keys}


def element_integrals(
    offset_x: np.ndarray, offset_y: np.ndarray, dx: float, dy: float, keys=INTEGRALS
):
    """∬ over an element of the point kernels 1/R, X²/R³, Y²/R³, XY/R³, X/R², Y/R².

    ``offset_x``, ``offset_y`` are the observation point minus the element centre (mm),
    broadcast against each other; the element is ``dx × dy`` (mm). Returns a dict of arrays
    with keys ``one_over_r, xx, yy, xy, x, y`` (units mm, 1, 1, 1, mm⁰·ln… see NOTES.md), or
    those of ``keys`` only (each value is computed the same way whatever the others).
    """
    ox, oy = np.broadcast_arrays(np.asarray(offset_x, float), np.asarray(offset_y, float))
    total = None
    for sx, sy, sign in ((1, 1, 1.0), (1, -1, -1.0), (-1, 1, -1.0), (-1, -1, 1.0)):
        corner = _antiderivatives(ox + sx * 0.5 * dx, oy + sy * 0.5 * dy, keys)
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
        """All six kernels (6 · (2n_x − 1)(2n_y − 1) values; ``kernel_values`` computes one
        kernel, or a part of one, with bounded temporaries)."""
        index_x = np.arange(-(grid.n_x - 1), grid.n_x)
        index_y = np.arange(-(grid.n_y - 1), grid.n_y)
        kernels = {
            key: kernel_values(grid, material, key, index_x, index_y) for key in KERNEL_INTEGRALS
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


def _combine(key: str, f: dict[str, np.ndarray], material: MaterialPair) -> np.ndarray:
    """Kernel ``key`` (mm/MPa) from the element integrals ``f`` (Eq. 5, material of Eq. 6)."""
    nu, K = material.poisson_ratio, material.coupling
    scale = 1.0 / (np.pi * material.shear_modulus)
    if key == "zz":
        return scale * (1.0 - nu) * f["one_over_r"]
    if key == "xx":
        return scale * ((1.0 - nu) * f["one_over_r"] + nu * f["xx"])
    if key == "yy":
        return scale * ((1.0 - nu) * f["one_over_r"] + nu * f["yy"])
    if key == "xy":
        return scale * nu * f["xy"]
    if key == "zx":
        return scale * K * f["x"]
    if key == "zy":
        return scale * K * f["y"]
    raise ValueError(f"kernel must be one of {tuple(KERNEL_INTEGRALS)}, got {key!r}")


def kernel_values(
    grid: Grid, material: MaterialPair, key: str, index_x: np.ndarray, index_y: np.ndarray
) -> np.ndarray:
    """Kernel ``key`` (mm/MPa) at the offsets (i Δx, j Δy), i in ``index_x``, j in
    ``index_y`` (integers, observation minus source): shape ``(index_x.size,
    index_y.size)``.

    The values are those of ``SurfaceInfluence.build`` bit for bit (the same operations on
    the same offsets, element by element); they are computed ``BLOCK_ELEMENTS`` at a time,
    so the temporaries stay a few MB at any grid size, and only the integrals the kernel
    needs are evaluated (``KERNEL_INTEGRALS``).
    """
    if key not in KERNEL_INTEGRALS:
        raise ValueError(f"kernel must be one of {tuple(KERNEL_INTEGRALS)}, got {key!r}")
    offsets_x = grid.dx * np.asarray(index_x)
    offsets_y = grid.dy * np.asarray(index_y)
    values = np.empty((offsets_x.size, offsets_y.size))
    rows = max(1, BLOCK_ELEMENTS // max(1, offsets_y.size))
    for start in range(0, offsets_x.size, rows):
        ox, oy = np.meshgrid(offsets_x[start : start + rows], offsets_y, indexing="ij")
        f = element_integrals(ox, oy, grid.dx, grid.dy, KERNEL_INTEGRALS[key])
        values[start : start + rows] = _combine(key, f, material)
    return values
