"""DC-FFT of surface tractions to a lattice of field points (paper Eq. 16; Liu & Wang 2002).

The stress at field point t of a depth layer is Σ_s K(t − s) τ(s) over the surface elements
s (``engine.kernels.stress`` gives the element-integrated coefficients K). On a regular
lattice of field points t = (t_x0 + iΔx, t_y0 + jΔy), i < m_x, j < m_y, this sum is a 2-D
Toeplitz convolution, evaluated by zero-padded FFT (discrete convolution FFT, Liu & Wang,
J. Tribol. 124 (2002) 36–45): the traction fields are padded to ``(N_x, N_y) >=
(n_x + m_x − 1, n_y + m_y − 1)``, the kernel is wrapped in the same circulant layout
(``engine.kernels.fft.wrap_kernel``), and the first ``m_x × m_y`` entries of the circular
convolution are exact (no periodic images). The FFTs are ``RealFFTPair`` plans of
``engine.kernels.fft`` (reproducible estimate plans by default), built once per lattice.

Fields in real space, tractions in MPa, stresses in MPa, lengths in mm; "ij" indexing.
"""

from __future__ import annotations

import numpy as np

from ..grid import Grid
from .fft import RealFFTPair, next_fast_length, wrap_kernel
from .stress import COMPONENTS, element_stress, kernel_parity

__all__ = ["LatticeConvolution"]


class LatticeConvolution:
    """Eq. (16) on the field-point lattice t = (t_x0 + iΔx, t_y0 + jΔy), i < m_x, j < m_y.

    Offsets field − source run over (t_0 − x_0) + kΔ, k = −(n − 1) … m − 1; they are stored
    in circulant order (k mod N) in an ``(N_x, N_y)`` array, N >= n + m − 1.
    """

    def __init__(self, grid: Grid, poisson_ratio: float, origin, counts, threads, effort, cache):
        self.grid = grid
        self.poisson_ratio = poisson_ratio
        self.counts = counts
        self.cache = cache
        self.padded = tuple(
            next_fast_length(n + m - 1) for n, m in zip(grid.shape, counts, strict=True)
        )
        self._fft = RealFFTPair(self.padded, threads=threads, effort=effort)
        self._real, self._spectrum = self._fft.real, self._fft.spectrum
        self._scale = 1.0 / (self.padded[0] * self.padded[1])
        steps = (grid.dx, grid.dy)
        sources = (grid.x[0], grid.y[0])
        self._offsets = []
        for n, m, start, first, step in zip(
            grid.shape, counts, origin, sources, steps, strict=True
        ):
            k = np.arange(-(n - 1), m)
            self._offsets.append(start - first + step * k)
        # Field points = source points (the block): the circulant kernel is even or odd about
        # index 0 on each axis, so its spectrum is real (parities ee, oo) or imaginary (eo,
        # oe) up to rounding; only that part is stored (half the memory, cheaper products).
        self.symmetric = counts == grid.shape and np.allclose(origin, sources, rtol=0, atol=0)
        self._kernels: dict[tuple[int, str], dict[str, tuple[np.ndarray, complex]]] = {}

    @property
    def cache_bytes(self) -> int:
        return sum(a.nbytes for spectra in self._kernels.values() for a, _ in spectra.values())

    def _transform(self, values: np.ndarray, wrapped: bool = False) -> np.ndarray:
        """Forward FFT of a zero-padded field (corner block) or of a kernel in circulant order.

        A kernel on offsets k = −(n − 1) … m − 1 goes to index k mod N: k >= 0 to the start,
        k < 0 to the end of each axis (``wrap_kernel``).
        """
        real = self._real
        if not wrapped:
            real[...] = 0.0
            real[: values.shape[0], : values.shape[1]] = values
        else:
            negative = (self.grid.n_x - 1, self.grid.n_y - 1)
            real[...] = wrap_kernel(values, self.padded, negative)
        return self._fft.forward().copy()

    def traction_spectra(self, tractions: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Forward transforms of the zero-padded traction fields (once per call)."""
        return {load: self._transform(values) for load, values in tractions.items()}

    def kernel_spectra(self, layer: int, depth: float, load: str) -> dict:
        """Spectra of the element coefficients at one depth: component -> (array, factor),
        the spectrum being ``factor * array``."""
        key = (layer, load)
        if key in self._kernels:
            return self._kernels[key]
        coefficients = element_stress(
            self._offsets[0],
            self._offsets[1],
            depth,
            self.grid.dx,
            self.grid.dy,
            self.poisson_ratio,
            load,
        )
        spectra = {}
        for component in COMPONENTS:
            spectrum = self._transform(coefficients[component], wrapped=True)
            if not self.symmetric:
                spectra[component] = (spectrum, 1.0)
            elif np.prod(kernel_parity(load, component)) > 0:
                spectra[component] = (spectrum.real.copy(), 1.0)
            else:
                spectra[component] = (spectrum.imag.copy(), 1j)
        if self.cache:
            self._kernels[key] = spectra
        return spectra

    def layer(self, layer: int, depth: float, tractions: dict[str, np.ndarray]) -> dict:
        """Stresses on the lattice at one depth: dict component -> (m_x, m_y), MPa.

        ``tractions``: traction spectra from ``traction_spectra``.
        """
        kernels = {load: self.kernel_spectra(layer, depth, load) for load in tractions}
        m_x, m_y = self.counts
        result = {}
        for component in COMPONENTS:
            spectrum = self._spectrum
            spectrum[...] = 0.0
            for load, traction in tractions.items():
                kernel, factor = kernels[load][component]
                if factor == 1.0:
                    spectrum += kernel * traction
                else:
                    spectrum += factor * (kernel * traction)
            self._fft.inverse_unscaled()
            result[component] = self._scale * self._real[:m_x, :m_y]
        return result

    def evaluate(self, depths: np.ndarray, tractions: dict[str, np.ndarray]) -> dict:
        """All layers: dict component -> (m_x, m_y, n_z), MPa."""
        spectra = self.traction_spectra(tractions)
        out = {c: np.empty((*self.counts, depths.size)) for c in COMPONENTS}
        for k, depth in enumerate(depths):
            if spectra:
                values = self.layer(k, float(depth), spectra)
                for c in COMPONENTS:
                    out[c][:, :, k] = values[c]
            else:
                for c in COMPONENTS:
                    out[c][:, :, k] = 0.0
        return out
