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
from .fft import DEFAULT_EFFORT, PaddedTransforms, RealFFTPair, aligned_zeros, wrap_kernel
from .influence import (
    KERNEL_PARITY,
    SurfaceInfluence,
    kernel_quadrants,
    kernel_values,
    quadrant_values,
)

__all__ = ["HalfSpaceOperator", "SpectralPreconditioner", "fold_periodic", "wrap_kernel"]

# Component order of the block operator: 0 = x, 1 = y, 2 = n (normal); each block is the
# spectrum of a kernel of SurfaceInfluence with a sign (A_xz = −A_zx, A_yz = −A_zy).
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

#: Kernel spectra built together, each group on its first use: the normal one, the
#: coupling ones (frictional cases on a coupled material, and the slip reported for a
#: frictionless one: the tangential displacement of its pressure), the tangential block.
_SPECTRUM_GROUPS = (("zz",), ("zx", "zy"), ("xx", "xy", "yy"))

#: The coupling kernels: zero on an uncoupled material (K = 0), whose products are skipped.
_COUPLING = ("zx", "zy")

#: Kernels whose values on the periodic cell the spectral preconditioner folds.
_PRECONDITIONED = ("zz", "xx", "yy", "xy")

#: Rows of frequencies whose 3 × 3 symbols ``symbol_bound`` diagonalises at once.
_SYMBOL_ROWS = 64
# rows of 0 + ik made at a time for a product by an imaginary spectrum (about 1 MB at 1024²)
_IMAGINARY_ROWS = 64


class HalfSpaceOperator:
    """Relative surface displacements of two half-spaces from surface tractions.

    ``apply(p_x, p_y, p_n) -> (u_x, u_y, u_n)`` for the full 3×3 block of Eq. (4);
    ``apply_normal(p_n) -> u_n`` for the frictionless case (A_zz only).

    Memory: a kernel's spectrum (the half spectrum of the real, wrapped kernel on the padded
    ``(2n_x, 2n_y)`` grid: 2n_x (n_y + 1) values, 1/(4 n_x n_y) folded in) is kept: real
    values for an even kernel, complex ones 0 + ik for an odd one (A_zx, A_zy: twice the
    memory, one complex product instead of three passes); the kernel itself is written
    from its quadrant (``kernel_quadrants``) straight into the padded transforms' buffer
    (its first n_x rows; the others mirror them) and not kept. A_zz is built with the
    operator; A_zx and A_zy the first time a product needs them (a frictional case on a
    coupled material, K ≠ 0, or the slip of a frictionless one when it is read: the
    tangential displacement its pressure produces); the tangential block likewise
    (frictional cases). ``influence``: kernels given whole instead (default: the 3-D
    half-space kernels of ``grid`` and ``material``, evaluated as needed;
    ``engine.kernels.line`` passes the plane-strain kernels of a line grid). The FFT
    buffers (``PaddedTransforms``) are shared by the plans of every batch size and by the
    kernel spectra, grown to the largest batch asked.
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
        self._effort = planner_effort
        self.planner_effort = planner_effort
        # The block of Eq. (4) in Fourier space, with the 1/(4 n_x n_y) of the inverse FFT
        # folded in (the pruned transforms of PaddedRealFFT are unnormalised).
        self._scale = 1.0 / (self.padded_shape[0] * self.padded_shape[1])
        self._spectra: dict[str, tuple[np.ndarray, str]] = {}  # key -> (values, kind)
        self._influence = influence
        self._given = influence is not None  # kernels given whole (line grids)
        self._self_coefficients: dict[str, float] = {}
        # Kernel values of the preconditioner's periodic cell, kept from the quadrants the
        # spectra are built from (the same values: kernel_quadrants is element by element).
        self._cells: dict[str, np.ndarray] = {}
        self._transforms: PaddedTransforms | None = None
        self._targets: np.ndarray | None = None  # products of multi-field blocks
        self._product: np.ndarray | None = None
        self._imaginary: np.ndarray | None = None  # rows of 0 + ik (multiply_by_imaginary)
        self.applications = 0
        self._row_cache: dict[tuple, tuple] = {}  # blocks of an apply (_rows)
        self._symbol_bound: float | None = None
        self._preconditioner: SpectralPreconditioner | None = None
        self._build_spectra(("zz",))  # the others on first use (_stored)

    @property
    def influence(self) -> SurfaceInfluence:
        """All six kernels on the offset grid (built on first use, for tests and small
        grids: the operator itself never needs them at once)."""
        if self._influence is None:
            self._influence = SurfaceInfluence.build(self.grid, self.material)
        return self._influence

    @property
    def spectra_bytes(self) -> int:
        """Memory held by the kernel spectra built so far (bytes)."""
        return sum(values.nbytes for values, _ in self._spectra.values())

    def kernel(self, key: str, index_x: np.ndarray, index_y: np.ndarray) -> np.ndarray:
        """Kernel ``key`` (mm/MPa) at the offsets (i Δx, j Δy), i in ``index_x``, j in
        ``index_y`` (``engine.kernels.influence.kernel_values``, or the given kernels)."""
        if self._given:
            nx, ny = self.grid.shape
            rows, columns = np.asarray(index_x) + nx - 1, np.asarray(index_y) + ny - 1
            return self._influence.kernels[key][np.ix_(rows, columns)]
        cell = self._cells.get(key)
        if cell is not None and _within(cell, index_x, index_y):
            return quadrant_values(cell, key, index_x, index_y)
        return kernel_values(self.grid, self.material, key, index_x, index_y)

    def self_coefficient(self, key: str) -> float:
        """An element's own coefficient of kernel ``key`` (offset 0; mm/MPa)."""
        if key not in self._self_coefficients:
            value = self.kernel(key, np.array([0]), np.array([0]))[0, 0]
            self._self_coefficients[key] = float(value)
        return self._self_coefficients[key]

    def spectrum(self, key: str) -> np.ndarray:
        """The spectrum of kernel ``key`` on the padded grid, 1/(4 n_x n_y) folded in
        (complex, (2n_x, n_y + 1)), built on first use with the others of its group
        (``_SPECTRUM_GROUPS``). Kept as its real part (kernels even in both directions) or its
        imaginary part (odd in one, k of ik): the other part is zero up to rounding."""
        values, kind = self._stored(key)
        if kind == "real":
            return values.astype(complex)
        return 1j * _imaginary_part(values) if kind == "imaginary" else values.copy()

    def _stored(self, key: str) -> tuple[np.ndarray, str]:
        if key not in self._spectra:
            group = next(keys for keys in _SPECTRUM_GROUPS if key in keys)
            self._build_spectra(group)
        return self._spectra[key]

    def _build_spectra(self, keys: tuple[str, ...]) -> None:
        """Spectra of ``keys`` through the padded transforms (their plans and buffers, no
        others): each kernel's quadrant (``kernel_quadrants``, the group's together) is
        written in circulant order (``wrap_kernel``'s layout: offset k at index k mod 2n),
        mirrored with its parity in y here and in x by ``PaddedTransforms.forward_mirrored``."""
        if self._given:
            transform = RealFFTPair(
                (1, *self.padded_shape), threads=self.threads, effort=self._effort, inverse=False
            )
            for key in keys:
                transform.real[0] = wrap_kernel(self._influence.kernels[key], self.padded_shape)
                self._spectra[key] = (transform.forward()[0] * self._scale, "complex")
            return
        nx, ny = self.grid.shape
        transform = self._transform(1)
        real = transform.real[0]  # rows 0 … n_x − 1 of the circulant kernel (2n_y columns)
        quadrants = kernel_quadrants(self.grid, self.material, keys, (nx, ny))
        for key in keys:
            quadrant = quadrants.pop(key)
            if key in _PRECONDITIONED:  # the preconditioner's periodic cell (kernel())
                self._cells[key] = quadrant[: nx // 2 + 1, : ny // 2 + 1].copy()
            parity_x, parity_y = KERNEL_PARITY[key]
            real[:, :ny] = quadrant
            real[:, ny] = 0.0  # offset ±n_y: outside the kernel
            np.multiply(quadrant[:, :0:-1], parity_y, out=real[:, ny + 1 :])
            spectrum = transform.forward_mirrored(parity_x)
            if parity_x * parity_y > 0:  # even circulant: a real spectrum
                self._spectra[key] = (spectrum.real * self._scale, "real")
            else:  # odd along one axis: an imaginary spectrum ik, kept as k (half of 0 + ik)
                self._spectra[key] = (spectrum.imag * self._scale, "imaginary")
        if "xx" in self._spectra:  # a frictional solve: its products by A_zx, A_zy in one step
            self._imaginary_whole()

    def _imaginary_whole(self) -> None:
        """Keep the imaginary spectra whole, as 0 + ik (twice the memory of k, a product in
        one complex multiplication): for the frictional solves, which apply them at every
        iteration; a frictionless case reads them once per increment (its slip)."""
        for key, (values, kind) in list(self._spectra.items()):
            if kind == "imaginary" and not np.iscomplexobj(values):
                whole = np.zeros(values.shape, complex)
                whole.imag = values
                self._spectra[key] = (whole, kind)

    @property
    def preconditioner(self) -> SpectralPreconditioner:
        """The spectral preconditioner of this operator (built once, then shared)."""
        if self._preconditioner is None:
            self._preconditioner = SpectralPreconditioner(self)
        return self._preconditioner

    def _transform(self, batch: int) -> PaddedTransforms:
        """The padded transforms, with room for ``batch`` fields: replaced by larger ones
        (the old ones released first) when asked for more."""
        if self._transforms is None or self._transforms.capacity < batch:
            self._transforms = None
            self._transforms = PaddedTransforms(
                batch, self.grid.shape, threads=self.threads, effort=self._effort
            )
        return self._transforms

    def release_buffers(self) -> None:
        """Let go of the padded transforms (their plans and buffers: about 48 B per padded
        element, 48 MB at 1024²) and the products' scratch; the kernel spectra stay. The next
        product makes them again, with the same plans (estimate plans depend only on shapes,
        strides and alignment), so with the same bits. For a caller about to need memory
        elsewhere while no product is due, e.g. a case's stress plane after its last solve."""
        self._transforms = self._targets = self._product = None

    def _target_buffer(self, rows: int) -> np.ndarray:
        """Aligned (rows, 2n_x, n_y + 1) buffer for the products of a multi-field block."""
        if self._targets is None or self._targets.shape[0] < rows:
            self._targets = None
            shape = (rows, self.padded_shape[0], self.grid.n_y + 1)
            self._targets = aligned_zeros(shape, "complex128")
        return self._targets[:rows]

    def _imaginary_rows(self) -> np.ndarray:
        """Scratch of ``_IMAGINARY_ROWS`` rows of 0 + ik (``multiply_by_imaginary``)."""
        if self._imaginary is None:
            rows = min(_IMAGINARY_ROWS, self.padded_shape[0])
            self._imaginary = np.zeros((rows, self.grid.n_y + 1), complex)
        return self._imaginary

    def _product_buffer(self) -> np.ndarray:
        if self._product is None:
            self._product = np.empty((self.padded_shape[0], self.grid.n_y + 1), complex)
        return self._product

    def _multiply(
        self, spectrum: np.ndarray, key: str, out: np.ndarray, sign: float = 1.0
    ) -> np.ndarray:
        """``out`` ← ``sign`` · (spectrum of kernel ``key``) · ``spectrum``; ``out`` may be
        ``spectrum``. A real kernel spectrum k multiplies the real and imaginary parts:
        (a + ib)k = ak + ibk (``multiply_by_real``); an imaginary one (kept as k, or whole as
        0 + ik for frictional solves) in one complex product by 0 + ik (``multiply_by_imaginary``
        for k): (a + ib)(0 + ik) =
        (a·0 − bk) + i(ak + b·0) = −bk + iak, exactly (the same values as turning ak + ibk
        by i; a zero may differ in sign, which no sum with a nonzero keeps)."""
        values, kind = self._stored(key)
        if kind == "imaginary" and sign < 0:  # turned by −i instead (numpy's complex
            multiply_by_real(spectrum, _imaginary_part(values), out)  # negation is slow)
            return np.multiply(out, 1j * sign, out=out)  # bk − iak
        if kind == "real":
            multiply_by_real(spectrum, values, out)
        elif kind == "imaginary" and not np.iscomplexobj(values):
            multiply_by_imaginary(spectrum, values, out, self._imaginary_rows())
        else:
            np.multiply(spectrum, values, out=out)
        if sign < 0:
            np.negative(out, out=out)
        return out

    def _convolve(
        self, rows: tuple, fields: list[np.ndarray], out=None, *, count: bool = True
    ) -> np.ndarray:
        """Apply a block of kernel spectra to ``fields`` (columns): ``rows[a]`` lists the
        (field index b, kernel, sign) of output a (``_rows``). One field: each output is its
        own transform pair, the product taken in place (no further buffer). Outputs whose
        row is empty (the coupling blocks of an uncoupled material) are zero, and a call
        whose rows are all empty transforms nothing; each call counts as one application
        (``count``: False for the rest of an application already counted)."""
        nx, ny = self.grid.shape
        for row in rows:  # spectra first: building one uses the transforms' buffers
            for _, key, _ in row:
                self._stored(key)
        result = np.empty((len(rows), nx, ny)) if out is None else out
        if not any(rows):
            result[...] = 0.0
        elif len(fields) == 1:
            transform = self._transform(1)
            for a, ((_, key, sign),) in enumerate(rows):
                transform.fields(1)[0] = fields[0]
                spectrum = transform.forward(1)
                self._multiply(spectrum[0], key, out=spectrum[0], sign=sign)
                result[a] = transform.inverse(spectrum)[0]
        else:
            transform = self._transform(max(len(fields), len(rows)))
            destination = transform.fields(len(fields))
            for index, field in enumerate(fields):
                destination[index] = field
            spectra = transform.forward(len(fields))
            targets = self._target_buffer(len(rows))
            for a, row in enumerate(rows):
                self._accumulate(targets[a], row, spectra)
            result[...] = transform.inverse(targets)
        self.applications += int(count)
        return result

    def _accumulate(self, target: np.ndarray, row: tuple, spectra: np.ndarray) -> None:
        """``target`` ← Σ_b sign_b · (kernel_b spectrum) · ``spectra[b]`` (0 for no terms)."""
        if not row:
            target[...] = 0.0
        for position, (b, key, sign) in enumerate(row):
            if position == 0:
                self._multiply(spectra[b], key, out=target, sign=sign)
                continue
            product = self._multiply(spectra[b], key, out=self._product_buffer())
            if sign > 0:
                target += product
            else:
                target -= product

    def _rows(self, outputs: range, inputs: range) -> tuple:
        """Per output a, the blocks (field index, kernel, sign) of ``_BLOCKS`` that act on
        it, in the order of ``inputs``. On an uncoupled material (K = 0) the coupling
        kernels A_zx, A_zy are zero (Eq. 6: proportional to K), and their blocks are left
        out: a sum without its zero terms has the same value. Made once per block."""
        key = (outputs.start, outputs.stop, inputs.start, inputs.stop)
        rows = self._row_cache.get(key)
        if rows is None:
            uncoupled = self.material.coupling == 0.0
            rows = tuple(
                tuple(
                    (index, *_BLOCKS[(a, b)])
                    for index, b in enumerate(inputs)
                    if not (uncoupled and _BLOCKS[(a, b)][0] in _COUPLING)
                )
                for a in outputs
            )
            self._row_cache[key] = rows
        return rows

    def apply(self, p_x: np.ndarray, p_y: np.ndarray, p_n: np.ndarray):
        """Full 3×3 block: tractions (MPa) → relative displacements ``(u_x, u_y, u_n)`` (mm)."""
        u = self._convolve(self._rows(range(3), range(3)), [p_x, p_y, p_n])
        return u[0], u[1], u[2]

    def apply_normal_later(self, p_x: np.ndarray, p_y: np.ndarray, p_n: np.ndarray):
        """The full 3×3 block as :meth:`apply`, in one application, for a caller that may not
        need u_n: ``(u_x, u_y, normal)``, ``normal()`` giving u_n (mm). On an uncoupled
        material (K = 0) u_t = A_tt p_t and u_n = A_zz p_n are apart, so u_t is made now and
        u_n only when ``normal()`` is called (on the ``p_n`` given, which the caller keeps
        unchanged until then); each has the bits of :meth:`apply`'s (the same products in the
        same order, the transforms of one field the same in any batch). Otherwise all three
        are made now. Zero tangential tractions give u_t = 0 without a transform (the
        transform of zeros is zero; only the sign of a zero could differ, and the slip it
        makes is added to the previous displacement)."""
        if self.material.coupling != 0.0:
            u = self.apply(p_x, p_y, p_n)
            return u[0], u[1], lambda: u[2]
        if p_x.any() or p_y.any():
            u_x, u_y = self.apply_tangential(p_x, p_y)
        else:  # no tangential tractions (a frictional normal loading): u_t = 0
            u_x, u_y = np.zeros(self.grid.shape), np.zeros(self.grid.shape)
            self.applications += 1
        rows = self._rows(range(2, 3), range(2, 3))
        return u_x, u_y, lambda: self._convolve(rows, [p_n], count=False)[0]

    def apply_normal(self, p_n: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """A_zz only: pressure (MPa) → relative normal displacement (mm), into ``out`` (an
        array of the grid's shape) when given (an iteration's work array: no fresh memory)."""
        rows = self._rows(range(2, 3), range(2, 3))
        if out is None:
            return self._convolve(rows, [p_n])[0]
        self._convolve(rows, [p_n], out[None])
        return out

    def apply_tangential(self, p_x: np.ndarray, p_y: np.ndarray):
        """The 2×2 tangential block: (p_x, p_y) (MPa) → (u_x, u_y) (mm)."""
        u = self._convolve(self._rows(range(2), range(2)), [p_x, p_y])
        return u[0], u[1]

    def coupling_to_normal(self, p_x: np.ndarray, p_y: np.ndarray) -> np.ndarray:
        """A_zx p_x + A_zy p_y (mm): normal displacement due to tangential tractions (zero
        on an uncoupled material, K = 0: no transform, no coupling spectra)."""
        return self._convolve(self._rows(range(2, 3), range(2)), [p_x, p_y])[0]

    def coupling_to_tangential(self, p_n: np.ndarray):
        """(A_xz p_n, A_yz p_n) (mm): tangential displacement due to pressure (zero on an
        uncoupled material, K = 0, without building the coupling spectra)."""
        if self.material.coupling == 0.0:
            return np.zeros(self.grid.shape), np.zeros(self.grid.shape)
        u = self._convolve(self._rows(range(2), range(2, 3)), [p_n])
        return u[0], u[1]

    def symbol_bound(self) -> float:
        """An upper bound of the largest eigenvalue of A (mm/MPa): max over frequencies of
        the largest eigenvalue of the Hermitian 3×3 circulant symbol (A is symmetric);
        computed once, ``_SYMBOL_ROWS`` rows of frequencies at a time."""
        if self._symbol_bound is None:
            uncoupled = self.material.coupling == 0.0
            rows = self.padded_shape[0]
            largest = -np.inf
            for start in range(0, rows, _SYMBOL_ROWS):
                part = slice(start, min(start + _SYMBOL_ROWS, rows))
                symbol = np.zeros((part.stop - start, self.grid.n_y + 1, 3, 3), dtype=complex)
                for (a, b), (key, sign) in _BLOCKS.items():
                    if uncoupled and key in _COUPLING:  # zero (K = 0): not built
                        continue
                    values, kind = self._stored(key)
                    factor = {"real": 1.0, "imaginary": 1j, "complex": 1.0}[kind] * sign
                    values = _imaginary_part(values) if kind == "imaginary" else values
                    np.multiply(values[part], factor, out=symbol[..., a, b])
                hermitian = (0.5 / self._scale) * (symbol + np.conj(np.swapaxes(symbol, -1, -2)))
                largest = max(largest, float(np.linalg.eigvalsh(hermitian).max()))
            self._symbol_bound = largest
        return self._symbol_bound


def multiply_by_real(spectrum: np.ndarray, values: np.ndarray, out: np.ndarray) -> None:
    """``out`` ← ``spectrum`` · ``values`` (complex by real, element by element; ``out`` may be
    ``spectrum``): the real and imaginary parts multiplied in place. ``np.multiply`` of a
    complex and a real array would cast the real one to complex through a buffer allocated
    at each call (fresh pages: more time than the product on small grids)."""
    np.multiply(spectrum.real, values, out=out.real)
    np.multiply(spectrum.imag, values, out=out.imag)


def _imaginary_part(values: np.ndarray) -> np.ndarray:
    """k of an imaginary spectrum kept as k or as 0 + ik."""
    return values.imag if np.iscomplexobj(values) else values


def multiply_by_imaginary(
    spectrum: np.ndarray, values: np.ndarray, out: np.ndarray, scratch: np.ndarray
) -> None:
    """``out`` ← ``spectrum`` · (0 + i ``values``) (``out`` may be ``spectrum``): the complex
    product of numpy, a block of ``scratch.shape[0]`` rows at a time, each block's 0 + ik
    written into ``scratch`` (complex, its real part zero), so the imaginary spectrum is kept
    as k alone (half the memory of 0 + ik) with the same products, bit for bit."""
    rows = scratch.shape[0]
    for start in range(0, spectrum.shape[0], rows):
        block = slice(start, min(start + rows, spectrum.shape[0]))
        factor = scratch[: block.stop - start]
        factor.imag = values[block]
        np.multiply(spectrum[block], factor, out=out[block])


def _within(quadrant: np.ndarray, index_x, index_y) -> bool:
    """Whether ``quadrant`` holds every offset |i| of ``index_x`` and |j| of ``index_y``."""
    return (
        int(np.abs(index_x).max()) < quadrant.shape[0]
        and int(np.abs(index_y).max()) < quadrant.shape[1]
    )


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
    The normal part (A_zz) is built with the preconditioner, the tangential part (A_xx,
    A_xy, A_yy) on its first use; each folded kernel is evaluated on the cell's offsets only.
    """

    def __init__(self, operator: HalfSpaceOperator):
        self._operator = operator
        self.shape = operator.grid.shape
        self._normal = 1.0 / self._periodic_spectrum("zz")
        self._tangential: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self._scratch: np.ndarray | None = None  # three tangential spectra (tangential)
        # pyfftw plans of the operator's kind (estimate by default: reproducible bits).
        self._one = self._transform(1)
        self._two: RealFFTPair | None = None

    def _transform(self, batch: int) -> RealFFTPair:
        operator = self._operator
        return RealFFTPair(
            (batch, *self.shape), threads=operator.threads, effort=operator.planner_effort
        )

    def _periodic_spectrum(self, key: str) -> np.ndarray:
        """Real part of the spectrum of kernel ``key`` folded into the periodic cell
        (``fold_periodic``: offsets −n/2 … n/2 − 1 on each axis, evaluated only there)."""
        nx, ny = self.shape
        ia = np.arange(-(nx // 2), nx - nx // 2)
        ib = np.arange(-(ny // 2), ny - ny // 2)
        folded = np.zeros(self.shape)
        folded[np.ix_(ia % nx, ib % ny)] = self._operator.kernel(key, ia, ib)
        return np.fft.rfft2(folded).real

    def _tangential_symbols(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if self._tangential is None:
            spectrum = {key: self._periodic_spectrum(key) for key in ("xx", "yy", "xy")}
            determinant = spectrum["xx"] * spectrum["yy"] - spectrum["xy"] ** 2
            self._tangential = (
                spectrum["yy"] / determinant,
                -spectrum["xy"] / determinant,
                spectrum["xx"] / determinant,
            )
            self._two = self._transform(2)
        return self._tangential

    def normal(self, residual: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """M r (MPa) of a normal residual r (mm), into ``out`` when given."""
        fft = self._one
        fft.real[0] = residual
        spectrum = fft.forward()
        multiply_by_real(spectrum, self._normal, spectrum)
        result = fft.inverse()[0]
        if out is None:
            return result.copy()
        out[...] = result
        return out

    def tangential(self, rx: np.ndarray, ry: np.ndarray):
        ixx, ixy, iyy = self._tangential_symbols()
        fft = self._two
        fft.real[0] = rx
        fft.real[1] = ry
        spectrum = fft.forward()
        if self._scratch is None:
            self._scratch = np.empty((3, *spectrum.shape[1:]), complex)
        fx, first, second = self._scratch
        fx[...] = spectrum[0]
        fy = spectrum[1]
        # (a + ib) r by parts (multiply_by_real): no complex copy of the real symbols
        multiply_by_real(fx, ixx, first)
        multiply_by_real(fy, ixy, second)
        np.add(first, second, out=spectrum[0])
        multiply_by_real(fx, ixy, first)
        multiply_by_real(fy, iyy, second)
        np.add(first, second, out=spectrum[1])
        real = fft.inverse()
        return real[0].copy(), real[1].copy()
