"""The influence operator u = A p applied by zero-padded FFT convolution (DC-FFT).

Liu, Wang & Liu (2000); Liu & Wang (2002): the Toeplitz convolution of an ``(n_x, n_y)``
traction field with the ``(2n_x − 1, 2n_y − 1)`` kernel of ``SurfaceInfluence`` equals the
first ``(n_x, n_y)`` block of a circular convolution of size ``(2n_x, 2n_y)`` once the field
is zero-padded and the kernel wrapped (non-periodic, no aliasing). pyfftw plans are built once
per operator and batch size and reused for every application.

Fields are in real space, shape ``(n_x, n_y)``; tractions in MPa, displacements in mm.
``applications`` counts calls (one call = one operator application, whatever the number of
traction components involved).
"""

from __future__ import annotations

import numpy as np

from ..grid import Grid
from ..material import MaterialPair
from .fft import DEFAULT_EFFORT, PaddedRealFFT, RealFFTPair, wrap_kernel
from .influence import SurfaceInfluence

__all__ = ["HalfSpaceOperator", "SpectralPreconditioner", "fold_periodic", "wrap_kernel"]

# Component order of the block operator: 0 = x, 1 = y, 2 = n (normal).
_BLOCKS = {
    (0, 0): ("xx", 1.0),
    (0, 1): ("xy", 1.0),
    (0, 2): ("zx", -1.0),
    (1, 0): ("xy", 1.0),
    (1, 1): ("yy", 1.0),
    (1, 2): ("zy", -1.0),
    (2, 0): ("zx", 1.0),
    (2, 1): ("zy", 1.0),
    (2, 2): ("zz", 1.0),
}


class HalfSpaceOperator:
    """Relative surface displacements of two half-spaces from surface tractions.

    ``apply(p_x, p_y, p_n) -> (u_x, u_y, u_n)`` for the full 3×3 block of Eq. (4);
    ``apply_normal(p_n) -> u_n`` for the frictionless case (A_zz only).
    ``influence``: the kernels to apply (default: the 3-D half-space kernels of ``grid`` and
    ``material``; ``engine.kernels.line`` passes the plane-strain kernels of a line grid).
    """

    def __init__(
        self,
        grid: Grid,
        material: MaterialPair,
        *,
        threads: int = 1,
        planner_effort: str = DEFAULT_EFFORT,
        influence: SurfaceInfluence | None = None,
    ):
        self.grid = grid
        self.material = material
        self.threads = threads
        self.padded_shape = (2 * grid.n_x, 2 * grid.n_y)
        self.influence = influence or SurfaceInfluence.build(grid, material)
        self._effort = planner_effort
        self.planner_effort = planner_effort
        spectra = {}
        transform = RealFFTPair((1, *self.padded_shape), threads=threads, effort=planner_effort)
        for key, kernel in self.influence.kernels.items():
            transform.real[0] = wrap_kernel(kernel, self.padded_shape)
            spectra[key] = transform.forward()[0].copy()
        self._spectra = spectra
        # The block of Eq. (4) in Fourier space, with the 1/(4 n_x n_y) of the inverse FFT
        # folded in (the pruned transforms of PaddedRealFFT are unnormalised).
        self._scale = 1.0 / (self.padded_shape[0] * self.padded_shape[1])
        self._full = np.empty((3, 3, *spectra["zz"].shape), dtype=complex)
        for (a, b), (key, sign) in _BLOCKS.items():
            np.multiply(spectra[key], sign * self._scale, out=self._full[a, b])
        self._ffts: dict[int, PaddedRealFFT] = {}
        self._inverse_ffts: dict[int, PaddedRealFFT] = {}
        self._product = np.empty_like(spectra["zz"])
        self.applications = 0
        self._symbol_bound: float | None = None
        self._preconditioner: SpectralPreconditioner | None = None

    @property
    def preconditioner(self) -> SpectralPreconditioner:
        """The spectral preconditioner of this operator (built once, then shared)."""
        if self._preconditioner is None:
            self._preconditioner = SpectralPreconditioner(self)
        return self._preconditioner

    def _fft(self, batch: int, store: dict) -> PaddedRealFFT:
        """Plans and buffers per batch size, forward (``_ffts``) or inverse."""
        if batch not in store:
            direction = "forward" if store is self._ffts else "inverse"
            store[batch] = PaddedRealFFT(
                batch, self.grid.shape, direction, threads=self.threads, effort=self._effort
            )
        return store[batch]

    def _convolve(self, block: np.ndarray, fields: list[np.ndarray]) -> np.ndarray:
        """Apply a (rows × columns) block of kernel spectra to ``fields`` (columns)."""
        columns = len(fields)
        fft = self._fft(columns, self._ffts)
        for index, field in enumerate(fields):
            fft.fields[index] = field
        spectrum = fft.forward()
        rows = block.shape[0]
        out_fft = self._fft(rows, self._inverse_ffts)
        product = self._product
        for a in range(rows):
            target = out_fft.spectrum[a]
            np.multiply(block[a, 0], spectrum[0], out=target)
            for b in range(1, columns):
                np.multiply(block[a, b], spectrum[b], out=product)
                target += product
        self.applications += 1
        return out_fft.inverse().copy()

    def apply(self, p_x: np.ndarray, p_y: np.ndarray, p_n: np.ndarray):
        """Full 3×3 block: tractions (MPa) → relative displacements ``(u_x, u_y, u_n)`` (mm)."""
        u = self._convolve(self._full, [p_x, p_y, p_n])
        return u[0], u[1], u[2]

    def apply_normal(self, p_n: np.ndarray) -> np.ndarray:
        """A_zz only: pressure (MPa) → relative normal displacement (mm)."""
        return self._convolve(self._full[2:, 2:], [p_n])[0]

    def apply_tangential(self, p_x: np.ndarray, p_y: np.ndarray):
        """The 2×2 tangential block: (p_x, p_y) (MPa) → (u_x, u_y) (mm)."""
        u = self._convolve(self._full[:2, :2], [p_x, p_y])
        return u[0], u[1]

    def coupling_to_normal(self, p_x: np.ndarray, p_y: np.ndarray) -> np.ndarray:
        """A_zx p_x + A_zy p_y (mm): normal displacement due to tangential tractions."""
        return self._convolve(self._full[2:, :2], [p_x, p_y])[0]

    def coupling_to_tangential(self, p_n: np.ndarray):
        """(A_xz p_n, A_yz p_n) (mm): tangential displacement due to pressure."""
        u = self._convolve(self._full[:2, 2:], [p_n])
        return u[0], u[1]

    def symbol_bound(self) -> float:
        """An upper bound of the largest eigenvalue of A (mm/MPa): max over frequencies of
        the largest eigenvalue of the Hermitian 3×3 circulant symbol (A is symmetric);
        computed once."""
        if self._symbol_bound is None:
            symbol = np.moveaxis(self._full, (0, 1), (-2, -1))
            hermitian = (0.5 / self._scale) * (symbol + np.conj(np.swapaxes(symbol, -1, -2)))
            self._symbol_bound = float(np.linalg.eigvalsh(hermitian).max())
        return self._symbol_bound

    def normal_symbol_bound(self) -> float:
        return float(np.abs(self._spectra["zz"]).max())


def fold_periodic(kernel: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Fold an offset kernel ``(2n_x − 1, 2n_y − 1)`` into an ``(n_x, n_y)`` periodic cell
    (offsets −n/2 … n/2 − 1), the circulant whose inverse serves as a preconditioner."""
    nx, ny = shape
    ia = np.arange(-(nx // 2), nx - nx // 2)
    ib = np.arange(-(ny // 2), ny - ny // 2)
    folded = np.zeros(shape)
    folded[np.ix_(ia % nx, ib % ny)] = kernel[np.ix_(ia + nx - 1, ib + ny - 1)]
    return folded


class SpectralPreconditioner:
    """Inverse of the periodic (n_x × n_y) circulant of the surface kernels (mm → MPa).

    Applied to a residual (gap or slip, mm) it returns a traction-like correction (MPa):
    the discrete analogue of the |ξ| (Dirichlet-to-Neumann) operator that cancels the 1/|ξ|
    smoothing of A, so that CG iterations no longer grow with the number of elements.
    """

    def __init__(self, operator: HalfSpaceOperator):
        grid = operator.grid
        self.shape = grid.shape
        kernels = operator.influence.kernels
        spectrum = {
            key: np.fft.rfft2(fold_periodic(kernels[key], self.shape)).real
            for key in ("zz", "xx", "yy", "xy")
        }
        self._normal = 1.0 / spectrum["zz"]
        determinant = spectrum["xx"] * spectrum["yy"] - spectrum["xy"] ** 2
        self._tangential = (
            spectrum["yy"] / determinant,
            -spectrum["xy"] / determinant,
            spectrum["xx"] / determinant,
        )
        # pyfftw plans of the operator's kind (estimate by default: reproducible bits).
        effort, threads = operator.planner_effort, operator.threads
        self._one = RealFFTPair((1, *self.shape), threads=threads, effort=effort)
        self._two = RealFFTPair((2, *self.shape), threads=threads, effort=effort)

    def normal(self, residual: np.ndarray) -> np.ndarray:
        fft = self._one
        fft.real[0] = residual
        spectrum = fft.forward()
        spectrum *= self._normal
        return fft.inverse()[0].copy()

    def tangential(self, rx: np.ndarray, ry: np.ndarray):
        fft = self._two
        fft.real[0] = rx
        fft.real[1] = ry
        spectrum = fft.forward()
        fx, fy = spectrum[0].copy(), spectrum[1]
        ixx, ixy, iyy = self._tangential
        spectrum[0] = ixx * fx + ixy * fy
        spectrum[1] = ixy * fx + iyy * fy
        real = fft.inverse()
        return real[0].copy(), real[1].copy()
