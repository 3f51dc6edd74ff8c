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


def _log_x_plus_r(x, y, r, out: np.ndarray, scratch: np.ndarray) -> np.ndarray:
    """``out`` ← ln(x + r), r = √(x²+y²), without cancellation for x < 0: x + r = y²/(r − x)
    (``x``, ``y`` broadcast to ``r``'s shape; ``scratch``: a work array of that shape).

    ln(x + r) is taken everywhere first (one pass, no gather of the x ≥ 0 entries) and the
    entries with x < 0 are replaced (the same values, element by element, as evaluating each
    branch on its own entries)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        np.log(np.add(x, r, out=scratch), out=out)
    negative = np.asarray(x) < 0
    if negative.any():
        shape = out.shape
        negative = np.broadcast_to(negative, shape)
        xn, yn = np.broadcast_to(x, shape)[negative], np.broadcast_to(y, shape)[negative]
        out[negative] = np.log(yn * yn) - np.log(r[negative] - xn)
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

#: Corners evaluated at once by ``kernel_quadrants`` (rows of corners, at least
#: ``BLOCK_ROWS``): bounds its work arrays (about ten of this size, 32 kB each on small grids,
#: reused from block to block, so they stay in cache) whatever the grid; the values do not
#: depend on it.
BLOCK_ELEMENTS = 1 << 12
BLOCK_ROWS = 16  # fewer, longer blocks on large grids: the per-block calls stay negligible


class _Work:
    """Named work arrays of up to ``shape``, allocated on first use and handed out as views of
    their first ``rows`` rows (contiguous): the blocks of corners reuse the memory of the
    first block (fresh pages cost more than the arithmetic on small grids)."""

    def __init__(self, shape: tuple[int, ...]):
        self.shape, self.rows = shape, shape[0] if shape else None
        self._arrays: dict[str, np.ndarray] = {}

    def __call__(self, name: str) -> np.ndarray:
        if name not in self._arrays:
            self._arrays[name] = np.empty(self.shape)
        array = self._arrays[name]
        return array if not self.shape else array[: self.rows]


def _antiderivatives(x, y, keys=INTEGRALS, work: _Work | None = None) -> dict[str, np.ndarray]:
    """The corner functions F of NOTES.md at (X, Y) (broadcast against each other), those
    named in ``keys`` only, written into ``work``'s arrays (fresh ones by default); never
    evaluated at X = 0 or Y = 0."""
    if work is None:
        work = _Work(np.broadcast_shapes(np.shape(x), np.shape(y)))
    r = np.hypot(x, y, out=work("r"))
    scratch = work("scratch")
    needs = set(keys)
    log_xr = (
        _log_x_plus_r(x, y, r, work("log_xr"), scratch) if needs & {"one_over_r", "xx"} else None
    )
    log_yr = (
        _log_x_plus_r(y, x, r, work("log_yr"), scratch) if needs & {"one_over_r", "yy"} else None
    )
    log_r = np.log(r, out=work("log_r")) if needs & {"x", "y"} else None
    values = {}
    for key in keys:
        out = work(key)
        if key == "one_over_r":  # x ln(y + r) + y ln(x + r)
            np.multiply(x, log_yr, out=out)
            np.add(out, np.multiply(y, log_xr, out=scratch), out=out)
        elif key == "xx":
            np.multiply(y, log_xr, out=out)
        elif key == "yy":
            np.multiply(x, log_yr, out=out)
        elif key == "xy":
            np.negative(r, out=out)
        elif key == "x":
            _arctan_term(x, y, log_r, out, scratch)
        else:
            _arctan_term(y, x, log_r, out, scratch)
        values[key] = out
    return values


def _arctan_term(a, b, log_r, out: np.ndarray, scratch: np.ndarray) -> np.ndarray:
    """``out`` ← a·atan(b/a) + b·ln r (the corner functions of X/R² and Y/R²)."""
    np.divide(b, a, out=scratch)
    np.arctan(scratch, out=scratch)
    np.multiply(a, scratch, out=scratch)
    np.multiply(b, log_r, out=out)
    return np.add(scratch, out, out=out)


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


def _combine(key: str, f: dict[str, np.ndarray], material: MaterialPair, work=None) -> np.ndarray:
    """Kernel ``key`` (mm/MPa) from the element integrals ``f`` (Eq. 5, material of Eq. 6);
    into ``work``'s arrays "kernel" and "scratch" when given, else a new array."""
    nu, K = material.poisson_ratio, material.coupling
    scale = 1.0 / (np.pi * material.shear_modulus)
    out, scratch = (work("kernel"), work("scratch")) if work is not None else (None, None)
    if key == "zz":
        return np.multiply(scale * (1.0 - nu), f["one_over_r"], out=out)
    if key in ("xx", "yy"):  # scale ((1 − ν) f_1/r + ν f_key)
        total = np.multiply(1.0 - nu, f["one_over_r"], out=out)
        total += np.multiply(nu, f[key], out=scratch)
        total *= scale
        return total
    if key == "xy":
        return np.multiply(scale * nu, f["xy"], out=out)
    if key == "zx":
        return np.multiply(scale * K, f["x"], out=out)
    if key == "zy":
        return np.multiply(scale * K, f["y"], out=out)
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
    counts[1]: the quadrant from which ``KERNEL_PARITY`` gives every other offset
    (``kernel_quadrants``)."""
    return kernel_quadrants(grid, material, (key,), counts)[key]


def kernel_quadrants(
    grid: Grid, material: MaterialPair, keys: tuple[str, ...], counts: tuple[int, int]
) -> dict[str, np.ndarray]:
    """Kernels ``keys`` (mm/MPa) at the offsets (iΔx, jΔy), 0 ≤ i < counts[0], 0 ≤ j <
    counts[1]: the quadrants from which ``KERNEL_PARITY`` gives every other offset.

    Each element integral is the alternating sum of a corner function F over the element's
    four corners (NOTES.md). Neighbouring offsets share corners, so F is evaluated once on
    the lattice of corners ((i − ½)Δx, (j − ½)Δy), 0 ≤ i ≤ counts[0], 0 ≤ j ≤ counts[1],
    combined into the kernel (Eq. 5 is linear in the integrals), and differenced: one
    evaluation per offset instead of four per offset and quadrant (16 times fewer than all
    four quadrants corner by corner). The kernels share what their corner functions share
    (R, the logarithms). Blocks of ``BLOCK_ELEMENTS`` corners bound the work arrays at any
    grid size; each value is computed element by element, the same whatever the blocks.
    """
    for key in keys:
        if key not in KERNEL_INTEGRALS:
            raise ValueError(f"kernel must be one of {tuple(KERNEL_INTEGRALS)}, got {key!r}")
    count_x, count_y = (int(count) for count in counts)
    corners_x = grid.dx * (np.arange(count_x + 1) - 0.5)
    corners_y = (grid.dy * (np.arange(count_y + 1) - 0.5))[None, :]
    quadrants = {key: np.empty((count_x, count_y)) for key in keys}
    integrals = tuple(dict.fromkeys(name for key in keys for name in KERNEL_INTEGRALS[key]))
    rows = max(BLOCK_ROWS, BLOCK_ELEMENTS // (count_y + 1))
    work = _Work((min(rows, count_x) + 1, count_y + 1))
    for start in range(0, count_x, rows):
        stop = min(start + rows, count_x)
        work.rows = stop - start + 1
        f = _antiderivatives(corners_x[start : stop + 1, None], corners_y, integrals, work)
        for key in keys:
            kernel = _combine(key, f, material, work)
            block = quadrants[key][start:stop]  # F(1,1) − F(1,0) − F(0,1) + F(0,0)
            np.subtract(kernel[1:, 1:], kernel[1:, :-1], out=block)
            block -= kernel[:-1, 1:]
            block += kernel[:-1, :-1]
    # An odd kernel integrates to exactly 0 over an element centred on its axis of symmetry.
    for key, quadrant in quadrants.items():
        parity_x, parity_y = KERNEL_PARITY[key]
        if parity_x < 0:
            quadrant[0] = 0.0
        if parity_y < 0:
            quadrant[:, 0] = 0.0
    return quadrants


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
