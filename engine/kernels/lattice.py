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
from .fft import RealFFTPair, next_fast_length, plan, pyfftw, wrap_kernel
from .stress import COMPONENTS, LOADS, element_stress, kernel_parity

__all__ = ["LatticeConvolution", "LineConvolution", "ROW_BLOCK", "line_axis"]


def _symmetric_about_zero(coordinates: np.ndarray, step: float) -> bool:
    """True if the element centres ``coordinates`` mirror onto each other about 0."""
    return bool(np.allclose(coordinates[::-1], -coordinates, rtol=0, atol=1e-9 * step))


def line_axis(grid: Grid, origin: tuple[float, float], counts: tuple[int, int]) -> int | None:
    """The axis along which the lattice origin + (iΔx, jΔy), (i, j) < counts, is a line
    through the middle of a grid symmetric about it (0: the x–z plane, 1: the y–z plane),
    i.e. where a ``LineConvolution`` applies; None for any other lattice."""
    for axis, across, step in ((0, grid.y, grid.dy), (1, grid.x, grid.dx)):
        on_line = counts[1 - axis] == 1 and origin[1 - axis] == 0.0
        if on_line and _symmetric_about_zero(across, step):
            return axis
    return None


class _DepthLayers:
    """Every depth layer from the same traction spectra, transformed once per call (the 2-D
    lattice; a line streams its rows instead, ``LineConvolution``)."""

    counts: tuple[int, int]

    def traction_spectra(self, tractions: dict[str, np.ndarray]) -> dict:
        raise NotImplementedError

    def layer(self, layer: int, depth: float, tractions: dict) -> dict:
        raise NotImplementedError

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


class LatticeConvolution(_DepthLayers):
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
        # Other lattices: the six components' spectra of a load in one array, so that a
        # layer takes its products and inverse transforms for all six at once (_stacked).
        self._stacks: dict[tuple[int, str], np.ndarray] = {}
        self._batch: RealFFTPair | None = None
        self._options = (threads, effort)

    @property
    def cache_bytes(self) -> int:
        spectra = sum(a.nbytes for kept in self._kernels.values() for a, _ in kept.values())
        return spectra + sum(stack.nbytes for stack in self._stacks.values())

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
        coefficients = self._coefficients(depth, load)
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

    def _coefficients(self, depth: float, load: str) -> dict[str, np.ndarray]:
        """The element coefficients of ``load`` on the lattice's offsets at ``depth`` (mm)."""
        return element_stress(
            self._offsets[0],
            self._offsets[1],
            depth,
            self.grid.dx,
            self.grid.dy,
            self.poisson_ratio,
            load,
        )

    def _stacked(self, layer: int, depth: float, load: str) -> np.ndarray:
        """The spectra of ``kernel_spectra`` of a lattice that is not the block itself (all
        complex, factor 1), the six components stacked: (6, N_x, N_y // 2 + 1)."""
        key = (layer, load)
        if key in self._stacks:
            return self._stacks[key]
        coefficients = self._coefficients(depth, load)
        stack = np.empty((len(COMPONENTS), *self._spectrum.shape), dtype=complex)
        negative = (self.grid.n_x - 1, self.grid.n_y - 1)
        for index, component in enumerate(COMPONENTS):  # _transform(wrapped=True), in place
            self._real[...] = wrap_kernel(coefficients.pop(component), self.padded, negative)
            stack[index] = self._fft.forward()
        if self.cache:
            self._stacks[key] = stack
        return stack

    def _batched(self) -> bool:
        """Whether a layer takes its six components at once (``_layer_stacked``): a lattice
        that is not the block, whose batch buffers (the six fields, their spectra and one
        product, ``BATCH_LIMIT``) are small; others one component at a time."""
        if self.symmetric:
            return False
        fields = len(COMPONENTS) * self.padded[0] * self.padded[1] * 8
        spectra = len(COMPONENTS) * self._spectrum.size * 16
        return fields + 2 * spectra <= BATCH_LIMIT

    def _layer_stacked(self, layer: int, depth: float, tractions: dict) -> dict:
        """``layer`` for a lattice that is not the block: the same products, summed in the
        same order, for the six components at once, and their six inverse transforms in one
        batch (each with the bits of its own transform)."""
        if self._batch is None:
            threads, effort = self._options
            shape = (len(COMPONENTS), *self.padded)
            self._batch = RealFFTPair(shape, threads=threads, effort=effort)
            self._product = np.empty_like(self._batch.spectrum)
        spectra, product = self._batch.spectrum, self._product
        for index, (load, traction) in enumerate(tractions.items()):
            # the first product is the sum itself (0 + a = a but for the sign of a zero)
            out = spectra if index == 0 else product
            np.multiply(self._stacked(layer, depth, load), traction, out=out)
            if index:
                spectra += product
        real = self._batch.inverse_unscaled()
        m_x, m_y = self.counts
        values = self._scale * real[:, :m_x, :m_y]
        return {component: values[index] for index, component in enumerate(COMPONENTS)}

    def layer(self, layer: int, depth: float, tractions: dict[str, np.ndarray]) -> dict:
        """Stresses on the lattice at one depth: dict component -> (m_x, m_y), MPa.

        ``tractions``: traction spectra from ``traction_spectra``.
        """
        if self._batched():
            return self._layer_stacked(layer, depth, tractions)
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


BATCH_LIMIT = 16 * 2**20
"""Bytes of the buffers with which a lattice that is not the block takes the six stress
components of a layer at once (the element centres beside an oblique plane: 1.4 MB at 64²);
a larger one takes them one at a time, in less memory, with the same values."""

ROW_BLOCK = 64
"""Rows folded across the line that a ``LineConvolution`` transforms and sums together: the
sum over the rows runs block by block, in this fixed order, so a line's values depend on the
grid only, never on how many kernel spectra are kept (grids of up to 128 rows across the
line are one block)."""


class LineConvolution:
    """Eq. (16) on a line of field points through the middle of a grid that is symmetric
    about it: t = (t_0 + iΔx, 0), i < m (``axis`` = 0, the x–z plane), or t = (0, t_0 + jΔy)
    (``axis`` = 1, the y–z plane).

    Across the line the sources pair up: element j and its mirror j' sit at opposite
    offsets, and an element coefficient even (odd) across the line sees them with the same
    (the opposite) sign (``kernel_parity``). So the sum of Eq. (16) on the line is a sum over
    half the rows of 1-D convolutions along it, of the folded tractions τ(j) ± τ(j'): each
    row is zero-padded to N >= n + m − 1 along the line and transformed there only, the
    products are summed over the rows, and one 1-D inverse FFT per component gives the line.
    Exact like the 2-D lattice (no periodic images), with half its kernel memory (rows ·
    (N/2 + 1) complex values per spectrum, rows = ceil(n_across / 2)) and 1-D inverse FFTs.

    Streaming. The rows are taken in blocks of ``ROW_BLOCK``: per block, the folded traction
    spectra, then per layer the kernel spectra of the block's rows and their products,
    summed into the line spectra of every layer (``n_z · 6 · (N/2 + 1)`` complex values);
    so no field of the whole grid is held per layer, and the memory of a call is the line's
    plus one block's. Kernel spectra are kept between calls up to ``cache_limit`` bytes
    (None: all of them; 0: none, every call computes them again), from the second call of
    ``evaluate`` on (a line evaluated once, a one-case static study's, keeps nothing) or
    when ``prepare`` asks for them; the values do not depend on it, since every block is
    computed and summed the same way whether kept or not.
    """

    def __init__(
        self,
        grid: Grid,
        poisson_ratio: float,
        axis: int,
        start,
        count,
        threads,
        effort,
        cache,
        cache_limit: int | None = None,
    ):
        self.grid = grid
        self.poisson_ratio = poisson_ratio
        self.axis = axis
        self.counts = (count, 1) if axis == 0 else (1, count)
        self.cache = cache
        self.cache_limit = None if cache_limit is None else int(cache_limit)
        origin = (start, 0.0) if axis == 0 else (0.0, start)
        if line_axis(grid, origin, self.counts) != axis:
            raise ValueError("a line convolution needs a grid symmetric about the line")
        along, across = (grid.x, grid.y) if axis == 0 else (grid.y, grid.x)
        steps = (grid.dx, grid.dy) if axis == 0 else (grid.dy, grid.dx)
        n, half = along.size, across.size // 2
        self.padded = next_fast_length(n + count - 1)
        self._scale = 1.0 / self.padded
        # Row r pairs the source at +c_r (the upper half, outermost first) with its mirror
        # at −c_r; a middle row (odd count) stands alone. Offsets field − source across the
        # line are −c_r, ascending, so they step by one element (shared corners).
        upper = np.arange(across.size - 1, across.size - 1 - half, -1)
        self._upper, self._lower = upper, across.size - 1 - upper
        self._middle = half if across.size % 2 else None
        across_offsets = -across[upper]
        if self._middle is not None:
            across_offsets = np.append(across_offsets, 0.0)
        rows = across_offsets.size
        block = min(rows, ROW_BLOCK)
        self._blocks = [slice(first, min(first + block, rows)) for first in range(0, rows, block)]
        self._negative = n - 1  # offsets −(n − 1) … count − 1 along the line, circulant order
        along_offsets = start - along[0] + steps[0] * np.arange(-(n - 1), count)
        self._along_offsets, self._across_offsets = along_offsets, across_offsets
        self._rows = pyfftw.empty_aligned((block, self.padded), "float64")
        self._row_spectra = pyfftw.empty_aligned((block, self.padded // 2 + 1), "complex128")
        self._forward = plan(self._rows, self._row_spectra, (1,), threads=threads, effort=effort)
        self._line_spectra = pyfftw.empty_aligned(
            (len(COMPONENTS), self.padded // 2 + 1), "complex128"
        )
        self._lines = pyfftw.empty_aligned((len(COMPONENTS), self.padded), "float64")
        self._inverse = plan(
            self._line_spectra,
            self._lines,
            (1,),
            direction="FFTW_BACKWARD",
            threads=threads,
            effort=effort,
        )
        self._parity_axis = 1 - axis
        self._kernels: dict[tuple[int, str, int], dict[str, np.ndarray]] = {}
        self._cache_bytes = 0
        self._evaluated = False  # kernels are kept from the second evaluation on
        self._dense: tuple[tuple, np.ndarray] | None = None  # evaluate_sets' kernels

    @property
    def cache_bytes(self) -> int:
        dense = 0 if self._dense is None else self._dense[1].nbytes
        return self._cache_bytes + dense

    def kernel_bytes(self, layers: int, loads: int = len(LOADS)) -> int:
        """Bytes of every kernel spectrum of ``layers`` depths and ``loads`` load types: six
        components of (rows, N/2 + 1) complex values per layer and load, rows = ceil(n_across
        / 2) (what a cache without limit keeps once every call has asked for them)."""
        rows = sum(block.stop - block.start for block in self._blocks)
        return rows * (self.padded // 2 + 1) * 16 * len(COMPONENTS) * int(layers) * int(loads)

    def _transform(self, rows: np.ndarray) -> np.ndarray:
        """Forward FFT along the line of ``rows`` (at most one block of rows, length <= N,
        already in padded order): (rows, N/2 + 1)."""
        self._rows[...] = 0.0
        self._rows[: rows.shape[0], : rows.shape[1]] = rows
        self._forward.execute()
        return self._row_spectra[: rows.shape[0]].copy()

    def _transform_kernel(self, rows: np.ndarray) -> np.ndarray:
        """Forward FFT along the line of kernel ``rows`` (rows, offsets −(n − 1) … m − 1 along
        it) in circulant order, offset k at index k mod N (``wrap_kernel``'s layout, written
        straight into the transform's buffer by two slices): (rows, N/2 + 1)."""
        negative, count = self._negative, rows.shape[1] - self._negative
        self._rows[...] = 0.0
        self._rows[: rows.shape[0], :count] = rows[:, negative:]
        if negative:
            self._rows[: rows.shape[0], self.padded - negative :] = rows[:, :negative]
        self._forward.execute()
        return self._row_spectra[: rows.shape[0]].copy()

    def _fold(self, values: np.ndarray, parity: int, block: slice) -> np.ndarray:
        """τ(upper) + parity · τ(lower) for the rows of ``block``, as (rows, n along the line)."""
        rows = values.T if self.axis == 0 else values  # (across, along)
        upper = self._upper[block]
        folded = rows[upper] + parity * rows[self._lower[block]]
        if self._middle is not None and block.stop > self._upper.size:
            middle = rows[self._middle] if parity > 0 else np.zeros_like(rows[self._middle])
            folded = np.vstack([folded, middle])
        return folded

    def traction_spectra(self, tractions: dict[str, np.ndarray], block: slice) -> dict:
        """Spectra of the folded tractions of the rows of ``block``: (load, parity across the
        line) -> (rows, N/2 + 1)."""
        return {
            (load, parity): self._transform(self._fold(values, parity, block))
            for load, values in tractions.items()
            for parity in (1, -1)
        }

    def kernel_spectra(
        self,
        layer: int,
        depth: float,
        load: str,
        index: int = 0,
        keep: bool = True,
        stacked: bool = True,
    ):
        """Spectra along the line of the element coefficients at one depth, for the rows of
        block ``index``, the six components in ``COMPONENTS`` order, each (rows, N/2 + 1):
        stacked in one (6, rows, N/2 + 1) array when ``stacked`` (or kept), else a list of
        the six, which a single evaluation takes one by one without the stacked copy; kept
        for later calls when ``keep`` and the cache has room."""
        key = (layer, load, index)
        if key in self._kernels:
            return self._kernels[key]
        grid = self.grid
        across = self._across_offsets[self._blocks[index]]
        offsets = (self._along_offsets, across) if self.axis == 0 else (across, self._along_offsets)
        coefficients = element_stress(*offsets, depth, grid.dx, grid.dy, self.poisson_ratio, load)
        spectra = []
        for component in COMPONENTS:
            rows = coefficients.pop(component)
            rows = rows.T if self.axis == 0 else rows  # (rows, offsets along the line)
            spectra.append(self._transform_kernel(rows))
            del rows  # the component's coefficients, transformed
        size = sum(spectrum.nbytes for spectrum in spectra)
        limit = self.cache_limit
        if keep and self.cache and (limit is None or self._cache_bytes + size <= limit):
            spectra = np.stack(spectra)
            self._kernels[key] = spectra
            self._cache_bytes += size
        elif stacked:
            spectra = np.stack(spectra)
        return spectra

    def prepare(self, depths: np.ndarray, loads=LOADS) -> None:
        """Compute the kernel spectra that the cache keeps (in the order ``evaluate`` asks
        for them), so that later calls find them; nothing beyond ``cache_limit``."""
        if not self.cache or self.cache_limit == 0:
            return
        for index in range(len(self._blocks)):
            for layer, depth in enumerate(depths):
                for load in loads:
                    if (layer, load, index) not in self._kernels:
                        before = self._cache_bytes
                        self.kernel_spectra(layer, float(depth), load, index)
                        if self._cache_bytes == before:
                            return  # full: the rest is computed when asked for

    def evaluate_sets(self, depths: np.ndarray, sets: list[dict[str, np.ndarray]]) -> list:
        """``evaluate`` for several sets of tractions at once (e.g. a field and its mirror
        image), by one matrix product per component and frequency: the line spectra of
        every layer and set are ``K @ T``, K (layers, loads · rows) the kernel spectra, T
        (loads · rows, sets) the folded traction spectra. BLAS sums the rows and loads in
        its own order, so the values equal ``evaluate``'s to rounding only. The kernels of
        every block, layer and load are kept in that layout from the first call on, unless
        the line keeps no kernels (``cache``), whatever ``cache_limit`` (``cache_bytes``;
        the per-block cache of ``evaluate`` is left alone)."""
        width = self.padded // 2 + 1
        rows = sum(block.stop - block.start for block in self._blocks)
        if self._dense is not None and self._dense[0] == tuple(depths):
            dense = self._dense[1]
        else:
            dense = np.empty((len(COMPONENTS), width, depths.size, len(LOADS) * rows), complex)
            for k, depth in enumerate(depths):
                for j, load in enumerate(LOADS):
                    first = j * rows
                    for index, block in enumerate(self._blocks):
                        kernels = self.kernel_spectra(k, float(depth), load, index, keep=False)
                        span = slice(first + block.start, first + block.stop)
                        dense[:, :, k, span] = kernels.transpose(0, 2, 1)
            if self.cache:
                self._dense = (tuple(depths), dense)
        folded = np.zeros((len(COMPONENTS), width, len(LOADS) * rows, len(sets)), complex)
        for n, tractions in enumerate(sets):
            for block in self._blocks:
                spectra = self.traction_spectra(tractions, block)
                for j, load in enumerate(LOADS):
                    if load not in tractions:
                        continue
                    span = slice(j * rows + block.start, j * rows + block.stop)
                    for c, component in enumerate(COMPONENTS):
                        parity = kernel_parity(load, component)[self._parity_axis]
                        folded[c, :, span, n] = spectra[(load, parity)].T
        lines = np.fft.irfft(np.matmul(dense, folded), n=self.padded, axis=1)
        count = max(self.counts)
        return [
            {
                component: np.ascontiguousarray(lines[c, :count, :, n]).reshape(
                    *self.counts, depths.size
                )
                for c, component in enumerate(COMPONENTS)
            }
            for n in range(len(sets))
        ]

    def evaluate(self, depths: np.ndarray, tractions: dict[str, np.ndarray]) -> dict:
        """All layers: dict component -> (m_x, m_y, n_z), MPa; the rows block by block
        (class docstring), each block's products summed into the line spectra of every layer.

        Per block, layer and load, one ``einsum`` takes the six components at once from the
        second evaluation on (when the kernels are kept: an evaluator called again, e.g. by a
        peak tracker every cycle), on the folded traction spectra stacked per component (6
        per load); the first evaluation, often the only one (a static case), takes one
        ``einsum`` per component on the folded spectra as they are, in less memory. The same
        products, each component's rows summed in the same order either way, so the values do
        not depend on the batching."""
        loads = sorted(tractions, key=LOADS.index)
        width = self.padded // 2 + 1
        sums = np.zeros((depths.size, len(COMPONENTS), width), dtype=complex)
        keep, self._evaluated = self._evaluated, self._evaluated or bool(loads)
        parities = {
            load: [kernel_parity(load, component)[self._parity_axis] for component in COMPONENTS]
            for load in loads
        }
        for index, block in enumerate(self._blocks if loads else ()):
            traction = self.traction_spectra({load: tractions[load] for load in loads}, block)
            # the folded traction spectra each component sees: (rows, N/2 + 1) each, stacked
            # to (6, rows, N/2 + 1) per load when the kernels are kept
            folded = {
                load: [traction[(load, parity)] for parity in parities[load]] for load in loads
            }
            if keep:
                folded = {load: np.stack(folded[load]) for load in loads}
            for k, depth in enumerate(depths):
                kernels = [
                    self.kernel_spectra(k, float(depth), load, index, keep, stacked=keep)
                    for load in loads
                ]
                for load, kernel in zip(loads, kernels, strict=True):
                    if keep:
                        sums[k] += np.einsum("crk,crk->ck", kernel, folded[load])
                        continue
                    for c, spectra in enumerate(folded[load]):
                        sums[k, c] += np.einsum("rk,rk->k", kernel[c], spectra)
        count = max(self.counts)
        lines = np.empty((len(COMPONENTS), count, depths.size))
        for k in range(depths.size):
            self._line_spectra[...] = sums[k]
            self._inverse.execute()
            lines[:, :, k] = self._lines[:, :count]
        lines *= self._scale
        return {
            component: lines[c].reshape(*self.counts, depths.size)
            for c, component in enumerate(COMPONENTS)
        }
