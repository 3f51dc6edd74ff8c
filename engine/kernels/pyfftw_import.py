"""``pyfftw``, imported once for the whole package without its SciPy interfaces (the FFT
plans of :mod:`engine.kernels.fft` and the wisdom file of :mod:`engine.kernels.wisdom`)."""

from __future__ import annotations

import sys

__all__ = ["pyfftw"]


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
