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
    """ln(x + r), r = √(x²+y²), without cancellation for x < 0: x + r = y²/(r − x).

    ln(x + r) is taken everywhere first (one pass, no gather of the x ≥ 0 entries) and the
    entries with x < 0 are replaced (the same values, element by element, as evaluating each
    branch on its own entries)."""
    out = np.empty_like(x)
    with np.errstate(divide="ignore", invalid="ignore"):
        np.log(x + r, out=out)
    negative = x < 0
    if negative.any():
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

#: Corners evaluated at once by ``kernel_quadrant``: bounds its temporaries (a dozen arrays
#: of this size) whatever the grid; the values do not depend on it.
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
        """All six kernels (6 · (2n_x − 1)(2n_y − 1) values; ``kernel_quadrant`` computes the
        quadrant that determines one kernel)."""
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


#: Parity of each kernel in (X, Y), +1 even and −1 odd: 1/R, X²/R³ and Y²/R³ are even in
#: both, XY/R³ odd in both, X/R² odd in X and Y/R² odd in Y (and so are their integrals
#: over an element centred on the offset).
KERNEL_PARITY = {
    "zz": (1, 1),
    "xx": (1, 1),
    "yy": (1, 1),
    "xy": (-1, -1),
    "zx": (-1, 1),
    "zy": (1, -1),
}


def kernel_quadrant(grid: Grid, material: MaterialPair, key: str, counts: tuple[int, int]):
    """Kernel ``key`` (mm/MPa) at the offsets (iΔx, jΔy), 0 ≤ i < counts[0], 0 ≤ j <
    counts[1]: the quadrant from which ``KERNEL_PARITY`` gives every other offset.

    Each element integral is the alternating sum of a corner function F over the element's
    four corners (NOTES.md). Neighbouring offsets share corners, so F is evaluated once on
    the lattice of corners ((i − ½)Δx, (j − ½)Δy), 0 ≤ i ≤ counts[0], 0 ≤ j ≤ counts[1],
    combined into the kernel (Eq. 5 is linear in the integrals), and differenced: one
    evaluation per offset instead of four per offset and quadrant (16 times fewer than all
    four quadrants corner by corner). Blocks of ``BLOCK_ELEMENTS`` corners bound the
    temporaries at any grid size.
    """
    if key not in KERNEL_INTEGRALS:
        raise ValueError(f"kernel must be one of {tuple(KERNEL_INTEGRALS)}, got {key!r}")
    count_x, count_y = (int(count) for count in counts)
    corners_x = grid.dx * (np.arange(count_x + 1) - 0.5)
    corners_y = grid.dy * (np.arange(count_y + 1) - 0.5)
    quadrant = np.empty((count_x, count_y))
    rows = max(1, BLOCK_ELEMENTS // (count_y + 1))
    for start in range(0, count_x, rows):
        stop = min(start + rows, count_x)
        cx, cy = np.meshgrid(corners_x[start : stop + 1], corners_y, indexing="ij")
        f = _combine(key, _antiderivatives(cx, cy, KERNEL_INTEGRALS[key]), material)
        quadrant[start:stop] = f[1:, 1:] - f[1:, :-1] - f[:-1, 1:] + f[:-1, :-1]
    # An odd kernel integrates to exactly 0 over an element centred on its axis of symmetry.
    parity_x, parity_y = KERNEL_PARITY[key]
    if parity_x < 0:
        quadrant[0] = 0.0
    if parity_y < 0:
        quadrant[:, 0] = 0.0
    return quadrant


def kernel_values(
    grid: Grid, material: MaterialPair, key: str, index_x: np.ndarray, index_y: np.ndarray
) -> np.ndarray:
    """Kernel ``key`` (mm/MPa) at the offsets (i Δx, j Δy), i in ``index_x``, j in
    ``index_y`` (integers, observation minus source): shape ``(index_x.size,
    index_y.size)``, from ``kernel_quadrant`` and ``KERNEL_PARITY`` (exactly even or odd)."""
    index_x, index_y = np.asarray(index_x), np.asarray(index_y)
    counts = (int(np.abs(index_x).max()) + 1, int(np.abs(index_y).max()) + 1)
    quadrant = kernel_quadrant(grid, material, key, counts)
    return quadrant_values(quadrant, key, index_x, index_y)


def quadrant_values(
    quadrant: np.ndarray, key: str, index_x: np.ndarray, index_y: np.ndarray
) -> np.ndarray:
    """Kernel ``key`` at the offsets (i Δx, j Δy), i in ``index_x``, j in ``index_y``, from
    its ``quadrant`` (``kernel_quadrant``, covering every |i| and |j|) and its parity."""
    index_x, index_y = np.asarray(index_x), np.asarray(index_y)
    values = quadrant[np.ix_(np.abs(index_x), np.abs(index_y))]
    parity_x, parity_y = KERNEL_PARITY[key]
    if parity_x < 0:
        values[index_x < 0] *= -1.0
    if parity_y < 0:
        values[:, index_y < 0] *= -1.0
    return values
