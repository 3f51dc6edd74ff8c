"""FFTW plans whose results do not depend on the history of the process.

Every pyfftw plan of the package is made here. Two facts about FFTW decide whether a
result is bit-reproducible:

- **Wisdom.** FFTW keeps, per process, the best plan found so far for every (sub)problem,
  and a plan requested with ``FFTW_ESTIMATE`` *reuses* what a more patient planner
  (``FFTW_MEASURE``, ``FFTW_PATIENT``) chose earlier for the same problem. The measured
  choice depends on timings, so an ``FFTW_ESTIMATE`` plan made after any measured plan of
  the same size may add in another order (a few ulps), and differently in another process.
  This made an interrupted + resumed study differ by 1 ulp from an uninterrupted one
  (issue 15): the mpio writer's layout had planned the subsurface lattice with
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

import sys

import numpy as np


def _import_pyfftw():
    """``pyfftw`` without its SciPy interfaces: ``pyfftw.interfaces`` imports
    ``scipy.fftpack`` and ``scipy.fft`` when SciPy is installed (0.2 s of CPU at every start,
    most of pyfftw's import), and the engine uses only ``pyfftw.FFTW`` and aligned buffers.
    A ``None`` entry in ``sys.modules`` makes that optional import fail, as if SciPy were
    absent; it is removed again at once (an explicit ``import scipy.fftpack`` later works)."""
    if "pyfftw" in sys.modules:
        return sys.modules["pyfftw"]
    blocked = "scipy.fftpack" not in sys.modules
    if blocked:
        sys.modules["scipy.fftpack"] = None
    try:
        import pyfftw
    finally:
        if blocked:
            del sys.modules["scipy.fftpack"]
    return pyfftw


pyfftw = _import_pyfftw()

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


def plan(source, target, axes, *, direction="FFTW_FORWARD", threads=1, effort=DEFAULT_EFFORT):
    """A pyfftw plan from ``source`` to ``target`` over ``axes`` (unnormalised when executed
    with ``execute()``); estimate plans are made with the wisdom forgotten (module doc)."""
    if effort not in EFFORTS:
        raise ValueError(f"planner effort must be one of {EFFORTS}, got {effort!r}")
    if effort == "FFTW_ESTIMATE":
        pyfftw.forget_wisdom()
    return pyfftw.FFTW(
        source, target, axes=axes, direction=direction, threads=threads, flags=(effort,)
    )


class PaddedBuffers:
    """The aligned buffers of ``PaddedRealFFT`` plans for up to ``capacity`` fields of shape
    ``(n_x, n_y)``: plans of any batch ≤ ``capacity`` run on their leading part, so one
    operator keeps one set of buffers for its one-, two- and three-field transforms.

    Forward: ``rows`` (capacity, n_x, 2n_y) float64, ``half`` and ``spectrum`` (capacity,
    2n_x, n_y + 1) complex128, 21·capacity·n_x·n_y·8 bytes. Inverse: ``spectrum`` and
    ``output`` (capacity, n_x, 2n_y) float64, 12·capacity·n_x·n_y·8 bytes. All zero at
    first; the forward plans never write the padding of ``rows`` and ``half``, so it stays
    zero.
    """

    def __init__(self, capacity: int, shape: tuple[int, int], direction: str):
        if direction not in ("forward", "inverse"):
            raise ValueError(f"direction must be 'forward' or 'inverse', got {direction!r}")
        nx, ny = (int(n) for n in shape)
        self.capacity, self.shape, self.direction = int(capacity), (nx, ny), direction
        self.spectrum = _zeros((capacity, 2 * nx, ny + 1), "complex128")
        if direction == "forward":
            self.rows = _zeros((capacity, nx, 2 * ny), "float64")
            self.half = _zeros((capacity, 2 * nx, ny + 1), "complex128")
        else:
            self.output = _zeros((capacity, nx, 2 * ny), "float64")


def _zeros(shape: tuple[int, ...], dtype: str) -> np.ndarray:
    array = pyfftw.empty_aligned(shape, dtype=dtype)
    array[...] = 0
    return array


class PaddedRealFFT:
    """Real FFTs of ``batch`` fields of shape ``(n_x, n_y)`` zero-padded to ``(2n_x, 2n_y)``
    (``direction="forward"``), or the inverse restricted to the first ``(n_x, n_y)`` block
    (``"inverse"``) (DC-FFT, Liu et al. 2000).

    Pruned: the forward transform runs the row FFTs (last axis) on the ``n_x`` rows that hold
    data only (the others are zero) and then the column FFTs; the inverse runs all column
    FFTs (in place) and the row FFTs of the ``n_x`` rows that are kept. This saves a quarter
    of the work of each full 2-D transform. Unnormalised: fold 1/(4 n_x n_y) into the
    kernel. Forward: write into ``fields`` (batch, n_x, n_y), ``forward()`` returns the
    ``spectrum`` buffer (batch, 2n_x, n_y + 1). Inverse: write into ``spectrum``,
    ``inverse()`` returns a view (batch, n_x, n_y) of the result (valid until the next call;
    the spectrum is overwritten).

    ``buffers``: a ``PaddedBuffers`` of this direction and shape with capacity ≥ ``batch``
    whose leading part the plans use (default: buffers of their own). The plans are the
    same either way (same shape, strides and alignment), so are the results, bit for bit.
    """

    def __init__(
        self,
        batch: int,
        shape: tuple[int, int],
        direction: str = "forward",
        *,
        threads=1,
        effort=DEFAULT_EFFORT,
        buffers: PaddedBuffers | None = None,
    ):
        buffers = buffers or PaddedBuffers(batch, shape, direction)
        if buffers.direction != direction or buffers.shape != tuple(shape):
            raise ValueError("buffers of another direction or shape")
        if buffers.capacity < batch:
            raise ValueError(f"buffers for {buffers.capacity} fields, {batch} asked")
        nx, ny = buffers.shape
        self.shape = (nx, ny)
        options = dict(threads=threads, effort=effort)
        self.spectrum = buffers.spectrum[:batch]
        if direction == "forward":
            self._rows, half = buffers.rows[:batch], buffers.half[:batch]
            self._row_plan = plan(self._rows, half[:, :nx, :], (2,), **options)
            self._column_plan = plan(half, self.spectrum, (1,), **options)
            self.fields = self._rows[:, :, :ny]
            self._rows[...] = 0.0  # timed planners write into the buffers: the padding of
            half[...] = 0.0  # rows and half is zero again, and stays zero from now on
        else:
            self._output = buffers.output[:batch]
            backward = dict(direction="FFTW_BACKWARD", **options)
            self._column_plan = plan(self.spectrum, self.spectrum, (1,), **backward)
            self._row_plan = plan(self.spectrum[:, :nx, :], self._output, (2,), **backward)
        self.spectrum[...] = 0.0

    def forward(self) -> np.ndarray:
        """``spectrum`` ← unnormalised FFT of the zero-padded ``fields``."""
        self._row_plan.execute()
        self._column_plan.execute()
        return self.spectrum

    def inverse(self) -> np.ndarray:
        """First (n_x, n_y) block of the unnormalised inverse FFT of ``spectrum``."""
        self._column_plan.execute()
        self._row_plan.execute()
        return self._output[:, :, : self.shape[1]]


class RealFFTPair:
    """Forward (real → half spectrum) and inverse (normalised) real FFTs over the last two
    axes of ``shape`` (leading axes: a batch of independent fields), on aligned buffers
    ``real`` (float64, ``shape``) and ``spectrum`` (complex128, last axis ``n // 2 + 1``).

    ``forward()`` transforms ``real`` into ``spectrum``; ``inverse()`` transforms
    ``spectrum`` into ``real`` (divided by the number of points, as ``numpy.fft.irfft2``).
    Both may overwrite their input (``FFTW_DESTROY_INPUT``).
    """

    def __init__(self, shape: tuple[int, ...], *, threads: int = 1, effort: str = DEFAULT_EFFORT):
        if effort not in EFFORTS:
            raise ValueError(f"planner effort must be one of {EFFORTS}, got {effort!r}")
        shape = tuple(int(n) for n in shape)
        self.real = pyfftw.empty_aligned(shape, dtype="float64")
        self.spectrum = pyfftw.empty_aligned((*shape[:-1], shape[-1] // 2 + 1), dtype="complex128")
        axes = (len(shape) - 2, len(shape) - 1)
        flags = (effort, "FFTW_DESTROY_INPUT")
        if effort == "FFTW_ESTIMATE":
            # Wisdom left by timed planners would be reused by the estimate: forget it.
            pyfftw.forget_wisdom()
        self._forward = pyfftw.FFTW(
            self.real, self.spectrum, axes=axes, threads=threads, flags=flags
        )
        if effort == "FFTW_ESTIMATE":
            pyfftw.forget_wisdom()
        self._inverse = pyfftw.FFTW(
            self.spectrum,
            self.real,
            axes=axes,
            direction="FFTW_BACKWARD",
            threads=threads,
            flags=flags,
        )
        self.scale = 1.0 / float(self._inverse.N)  # what pyfftw's normalised call applies
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
