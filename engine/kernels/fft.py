"""FFTW plans whose results do not depend on the history of the process.

Every pyfftw plan of the package is made here. Two facts about FFTW decide whether a
result is bit-reproducible:

- **Wisdom.** FFTW keeps, per process, the best plan found so far for every (sub)problem,
  and a plan requested with ``FFTW_ESTIMATE`` *reuses* what a more patient planner
  (``FFTW_MEASURE``, ``FFTW_PATIENT``) chose earlier for the same problem. The measured
  choice depends on timings, so an ``FFTW_ESTIMATE`` plan made after any measured plan of
  the same size may add in another order (a few ulps), and differently in another process.
  This made an interrupted + resumed study differ by 1 ulp from an uninterrupted one: the
  mpio writer's layout had planned the subsurface lattice with
  ``FFTW_MEASURE`` on rank 0 only, before the cases were planned with ``FFTW_ESTIMATE``.
  Here, an ``FFTW_ESTIMATE`` plan is made with the wisdom forgotten first, so it is a
  function of the problem (shape, strides, alignment, threads) and of the FFTW build only.
- **Alignment.** FFTW picks SIMD codelets when the arrays it is planned with are aligned.
  Plans are made on aligned buffers of their own (``pyfftw.empty_aligned``) and always
  executed on those buffers (callers copy into ``real``/``spectrum``), never on arrays
  passed at call time, so the codelets cannot change with the alignment of a caller's array.

Planner efforts: ``"FFTW_ESTIMATE"`` (default everywhere in the package: reproducible across
processes, ranks, interruptions) or ``"FFTW_MEASURE"``/``"FFTW_PATIENT"`` (timed: possibly
faster, not reproducible bit for bit between processes).
"""

from __future__ import annotations

import numpy as np

from . import wisdom
from .pyfftw_import import pyfftw

DEFAULT_EFFORT = "FFTW_ESTIMATE"
EFFORTS = ("FFTW_ESTIMATE", "FFTW_MEASURE", "FFTW_PATIENT", "FFTW_EXHAUSTIVE")


def next_fast_length(target: int) -> int:
    """The smallest 5-smooth number (2^a 3^b 5^c) ≥ ``target``: a length whose FFT FFTW
    does fast (the same values as ``scipy.fft.next_fast_len(target, real=True)``)."""
    target = int(target)
    if target <= 6:
        return max(target, 1)
    best = 2 * target
    power5 = 1
    while power5 < best:
        power35 = power5
        while power35 < best:
            value = power35
            while value < target:
                value *= 2
            best = min(best, value)
            power35 *= 3
        power5 *= 5
    return best


def wrap_kernel(
    kernel: np.ndarray, padded_shape: tuple[int, int], negative: tuple[int, int] | None = None
) -> np.ndarray:
    """Place an offset kernel in a circulant array of ``padded_shape`` (DC-FFT): the entry
    of offset k goes to index k mod N on each axis. ``kernel[i, j]`` holds the offsets
    (i − negative[0], j − negative[1]); by default ``negative`` is half the kernel, i.e. a
    ``(2n_x − 1, 2n_y − 1)`` kernel of offsets −(n − 1) … n − 1 (field points = sources).
    The padded shape must hold every offset once (N ≥ kernel size on each axis)."""
    if negative is None:
        negative = tuple((size - 1) // 2 for size in kernel.shape)
    wrapped = np.zeros(padded_shape)
    ix = np.arange(-negative[0], kernel.shape[0] - negative[0]) % padded_shape[0]
    iy = np.arange(-negative[1], kernel.shape[1] - negative[1]) % padded_shape[1]
    wrapped[np.ix_(ix, iy)] = kernel
    return wrapped


def plan(
    source,
    target,
    axes,
    *,
    direction="FFTW_FORWARD",
    threads=1,
    effort=DEFAULT_EFFORT,
    flags=(),
):
    """A pyfftw plan from ``source`` to ``target`` over ``axes`` (unnormalised when executed
    with ``execute()``); estimate plans are made with the wisdom forgotten (module doc),
    timed ones with this machine's wisdom loaded first and saved after
    (``engine.kernels.wisdom``)."""
    if effort not in EFFORTS:
        raise ValueError(f"planner effort must be one of {EFFORTS}, got {effort!r}")
    if effort == "FFTW_ESTIMATE":
        pyfftw.forget_wisdom()
    else:
        wisdom.load()
    made = pyfftw.FFTW(
        source, target, axes=axes, direction=direction, threads=threads, flags=(effort, *flags)
    )
    if effort != "FFTW_ESTIMATE":
        wisdom.save()
    return made


def aligned_zeros(shape: tuple[int, ...], dtype: str) -> np.ndarray:
    """A zero array on an aligned buffer (FFTW's SIMD codelets; module doc)."""
    array = pyfftw.empty_aligned(shape, dtype=dtype)
    array[...] = 0
    return array


class PaddedTransforms:
    """Real FFTs of up to ``capacity`` fields of shape ``(n_x, n_y)`` zero-padded to
    ``(2n_x, 2n_y)``, and the inverse restricted to the first ``(n_x, n_y)`` block (DC-FFT,
    Liu et al. 2000), on two buffers shared by every batch size:

    - ``real`` (capacity, n_x, 2n_y) float64: the fields (their first n_y columns) and the
      inverse's output;
    - ``spectra`` (capacity, 2n_x, n_y + 1) complex128: the forward transform, in place.

    Pruned: the forward transform runs the row FFTs (last axis) on the ``n_x`` rows that hold
    data only and then the column FFTs in place; the inverse runs all column FFTs in place
    and the row FFTs of the ``n_x`` rows that are kept. Unnormalised: fold 1/(4 n_x n_y)
    into the kernel. The padding is zeroed before each forward transform (an inverse
    transform or the in-place column FFT leave data there): 12·capacity·n_x·n_y·8 bytes in
    all, instead of 33·… for separate forward and inverse buffers.

    Plans are ``plan``'s (estimate plans: the same for the same shapes, strides and
    alignment, so the same results whatever the batch sizes asked before).
    """

    def __init__(self, capacity: int, shape: tuple[int, int], *, threads=1, effort=DEFAULT_EFFORT):
        nx, ny = (int(n) for n in shape)
        self.capacity, self.shape = int(capacity), (nx, ny)
        self._options = dict(threads=threads, effort=effort)
        self.real = aligned_zeros((capacity, nx, 2 * ny), "float64")
        self.spectra = aligned_zeros((capacity, 2 * nx, ny + 1), "complex128")
        self._plans: dict[tuple, tuple] = {}
        self._padding_dirty = False

    def fields(self, batch: int) -> np.ndarray:
        """Where to write ``batch`` fields before ``forward(batch)``: (batch, n_x, n_y)."""
        return self.real[:batch, :, : self.shape[1]]

    def forward(self, batch: int) -> np.ndarray:
        """``spectra[:batch]`` ← unnormalised FFT of the zero-padded ``fields(batch)``."""
        nx, ny = self.shape
        rows, columns = self._plan("forward", batch, self.spectra)
        if self._padding_dirty:
            self.real[:, :, ny:] = 0.0
            self._padding_dirty = False
        self.spectra[:batch, nx:, :] = 0.0
        rows.execute()
        columns.execute()
        return self.spectra[:batch]

    def forward_mirrored(self, parity_x: float) -> np.ndarray:
        """``spectra[0]`` ← unnormalised FFT of a whole (2n_x, 2n_y) field, even
        (``parity_x`` = 1) or odd (−1) in its first index: rows 0 … n_x − 1 are ``real[0]``
        (all 2n_y columns, written by the caller), row n_x is zero and row 2n_x − i is
        ``parity_x`` · row i. The row FFTs of the mirrored rows are those of the first rows
        times the parity (exact), so only n_x rows are transformed; the transforms are the
        padded ones (the same FFTW plans, so the same values as a 2-D real FFT of the whole
        field: a circulant kernel's spectrum, ``engine.kernels.operator``). Returns a view."""
        nx = self.shape[0]
        rows, columns = self._plan("forward", 1, self.spectra)
        self._padding_dirty = True  # the caller wrote the padding columns
        rows.execute()
        spectrum = self.spectra[0]
        spectrum[nx] = 0.0
        np.multiply(spectrum[1:nx][::-1], parity_x, out=spectrum[nx + 1 :])
        columns.execute()
        return spectrum

    def inverse(self, spectra: np.ndarray) -> np.ndarray:
        """First (n_x, n_y) block of the unnormalised inverse FFT of ``spectra`` (batch,
        2n_x, n_y + 1): ``self.spectra`` or an aligned buffer of the same layout, overwritten.
        Returns a view of ``real`` (valid until the next transform)."""
        batch = spectra.shape[0]
        columns, rows = self._plan("inverse", batch, spectra)
        columns.execute()
        rows.execute()
        self._padding_dirty = True
        return self.real[:batch, :, : self.shape[1]]

    def _plan(self, direction: str, batch: int, spectra: np.ndarray) -> tuple:
        key = (direction, batch, spectra.ctypes.data)
        if key not in self._plans:
            if batch > self.capacity or batch > spectra.shape[0]:
                raise ValueError(f"{batch} fields asked, buffers for {self.capacity}")
            nx = self.shape[0]
            real, spectrum = self.real[:batch], spectra[:batch]
            # Timed planners run transforms on the buffers they plan on: keep their data.
            kept = (
                None
                if self._options["effort"] == "FFTW_ESTIMATE"
                else (real.copy(), spectrum.copy())
            )
            if direction == "forward":
                first = plan(real, spectrum[:, :nx, :], (2,), **self._options)
                second = plan(spectrum, spectrum, (1,), **self._options)
            else:
                backward = dict(direction="FFTW_BACKWARD", **self._options)
                first = plan(spectrum, spectrum, (1,), **backward)
                second = plan(spectrum[:, :nx, :], real, (2,), **backward)
            self._plans[key] = (first, second)
            if kept is not None:
                real[...], spectrum[...] = kept
        return self._plans[key]


class RealFFTPair:
    """Forward (real → half spectrum) and inverse (normalised) real FFTs over the last two
    axes of ``shape`` (leading axes: a batch of independent fields), on aligned buffers
    ``real`` (float64, ``shape``) and ``spectrum`` (complex128, last axis ``n // 2 + 1``).

    ``forward()`` transforms ``real`` into ``spectrum``; ``inverse()`` transforms
    ``spectrum`` into ``real`` (divided by the number of points, as ``numpy.fft.irfft2``).
    Both may overwrite their input (``FFTW_DESTROY_INPUT``). ``inverse=False``: the
    forward transform only (one plan fewer, e.g. for kernel spectra).
    """

    def __init__(
        self,
        shape: tuple[int, ...],
        *,
        threads: int = 1,
        effort: str = DEFAULT_EFFORT,
        inverse: bool = True,
    ):
        if effort not in EFFORTS:
            raise ValueError(f"planner effort must be one of {EFFORTS}, got {effort!r}")
        shape = tuple(int(n) for n in shape)
        self.real = pyfftw.empty_aligned(shape, dtype="float64")
        self.spectrum = pyfftw.empty_aligned((*shape[:-1], shape[-1] // 2 + 1), dtype="complex128")
        axes = (len(shape) - 2, len(shape) - 1)
        options = dict(threads=threads, effort=effort, flags=("FFTW_DESTROY_INPUT",))
        self._forward = plan(self.real, self.spectrum, axes, **options)
        self._inverse = (
            plan(self.spectrum, self.real, axes, direction="FFTW_BACKWARD", **options)
            if inverse
            else None
        )
        self.scale = 1.0 / float(shape[-2] * shape[-1])  # what pyfftw's normalised call applies
        self.real[...] = 0.0
        self.spectrum[...] = 0.0

    def forward(self) -> np.ndarray:
        """``spectrum`` ← FFT(``real``); returns ``spectrum`` (the buffer, not a copy)."""
        self._forward.execute()
        return self.spectrum

    def inverse(self) -> np.ndarray:
        """``real`` ← IFFT(``spectrum``) / N; returns ``real`` (the buffer, not a copy)."""
        self._inverse.execute()
        real = self.real
        real *= self.scale
        return real

    def inverse_unscaled(self) -> np.ndarray:
        """``real`` ← N · IFFT(``spectrum``) (no division; for callers that fold 1/N into a
        kernel); returns ``real``."""
        self._inverse.execute()
        return self.real
