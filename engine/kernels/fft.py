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

import numpy as np
import pyfftw

DEFAULT_EFFORT = "FFTW_ESTIMATE"
EFFORTS = ("FFTW_ESTIMATE", "FFTW_MEASURE", "FFTW_PATIENT", "FFTW_EXHAUSTIVE")


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
