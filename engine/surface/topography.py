"""Random self-affine topographies and their statistics (numerical kernel: no files, no TOML).

A surface is a height map h (mm) on the element centres of a grid, shape ``(n_x, n_y)`` with
``ij`` indexing (``n_y = 1``: a line contact's profile along x), asperity tops positive.

Power spectrum (Persson et al., J. Phys.: Condens. Matter 17 (2005) R1; Jacobs, Junge &
Pastewka, Surf. Topogr.: Metrol. Prop. 5 (2017) 013001, Eq. 3 and 11). With the wavevector
q = 2π/λ (rad/mm), the isotropic spectrum of a self-affine surface of Hurst exponent H is

    C(q) = C0                       for q < q_L = 2π/long_cutoff   (the roll-off)
    C(q) = C0 (q/q_L)^(−2(1+H))     for q_L ≤ q ≤ q_S = 2π/short_cutoff
    C(q) = 0                        for q > q_S

for a map (a profile's exponent is −(1+2H)). The spectrum is normalised as in
SurfaceTopography: C(q) = |h̃(q)|²/A with h̃ the continuous Fourier transform over the map
of area A (a profile: length L), so that h_rms² = (2π)⁻² ∫ C d²q (a profile: (2π)⁻¹ ∫ C dq).

Generation (:func:`self_affine`): Gaussian white noise drawn with NumPy's
``Generator(PCG64(seed)).standard_normal`` in C order over the grid's shape, filtered in
Fourier space by √C(q) and transformed back (``numpy.fft``, no FFTW plans: the same bits on
every machine and with any number of ranks), its mean removed and scaled so that the
realisation's rms height (or rms slope) is exactly the one asked for. The map is periodic over
the grid; the contact solver is not, so only the statistics, not the periodicity, matter.

The rms slope is the spectral one, h'_rms² = ⟨|∇h|²⟩ = (2π)⁻² ∫ q² C d²q: the gradient of the
trigonometric interpolant of the samples (SurfaceTopography's ``rms_gradient`` uses finite
differences, which read a few per cent lower at the short cutoff of 4 elements).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "spectrum",
    "self_affine",
    "wavevectors",
    "rms_height",
    "rms_slope",
    "radial_psd",
    "spectrum_exponent",
]


def wavevectors(shape: tuple[int, int], spacing: tuple[float, float]) -> np.ndarray:
    """|q| (rad/mm) of the Fourier modes of a map of ``shape`` and element ``spacing`` (mm),
    in ``numpy.fft.fftn``'s order, shape ``shape``; a line (``shape[1] == 1``) has q_y = 0."""
    n_x, n_y = shape
    q_x = 2.0 * math.pi * np.fft.fftfreq(n_x, spacing[0])
    q_y = 2.0 * math.pi * np.fft.fftfreq(n_y, spacing[1]) if n_y > 1 else np.zeros(1)
    return np.hypot(q_x[:, None], q_y[None, :])


def spectrum(
    q: np.ndarray, hurst: float, long_cutoff: float, short_cutoff: float, line: bool = False
) -> np.ndarray:
    """C(q)/C0 of the module docstring (1 on the roll-off, 0 beyond q_S), any shape of ``q``
    (rad/mm); ``line``: a profile's exponent −(1+2H); the mode q = 0 (the mean) gets 0."""
    q = np.asarray(q, dtype=float)
    q_long = 2.0 * math.pi / long_cutoff
    q_short = 2.0 * math.pi / short_cutoff
    exponent = -(1.0 + 2.0 * hurst) if line else -2.0 * (1.0 + hurst)
    ratio = np.maximum(q, q_long) / q_long
    out = ratio**exponent
    out[(q > q_short * (1.0 + 1e-12)) | (q == 0.0)] = 0.0
    return out


def self_affine(
    shape: tuple[int, int],
    spacing: tuple[float, float],
    *,
    hurst: float,
    long_cutoff: float,
    short_cutoff: float,
    seed: int,
    rms_height: float | None = None,
    rms_slope: float | None = None,
) -> np.ndarray:
    """A Gaussian self-affine height map (mm), shape ``shape``, element ``spacing`` (mm):
    module docstring; exactly one of ``rms_height`` (mm) and ``rms_slope`` (1) sets its
    amplitude (a value 0 gives a flat map). Deterministic in ``seed`` (an integer ≥ 0)."""
    if (rms_height is None) == (rms_slope is None):
        raise ValueError("give exactly one of rms_height and rms_slope")
    line = shape[1] == 1
    generator = np.random.Generator(np.random.PCG64(int(seed)))
    noise = generator.standard_normal(shape)
    filtered = np.fft.fftn(noise, axes=(0,) if line else (0, 1))
    q = wavevectors(shape, spacing)
    filtered *= np.sqrt(spectrum(q, hurst, long_cutoff, short_cutoff, line))
    height = np.real(np.fft.ifftn(filtered, axes=(0,) if line else (0, 1)))
    height -= height.mean()
    if rms_height is not None:
        scale = rms_height / max(globals()["rms_height"](height), np.finfo(float).tiny)
    else:
        scale = rms_slope / max(globals()["rms_slope"](height, spacing), np.finfo(float).tiny)
    return np.ascontiguousarray(height * scale)


def rms_height(height: np.ndarray) -> float:
    """√⟨(h − ⟨h⟩)²⟩ (mm) over the map."""
    height = np.asarray(height, dtype=float)
    return float(np.sqrt(np.mean((height - height.mean()) ** 2)))


def rms_slope(height: np.ndarray, spacing: tuple[float, float]) -> float:
    """Spectral rms slope √⟨|∇h|²⟩ (1) of the map (module docstring): Parseval over the
    discrete Fourier modes, Σ q² |ĥ|² / N² with ĥ = ``fftn(h)``, N the number of samples
    (the Nyquist modes counted with their q)."""
    height = np.asarray(height, dtype=float)
    line = height.shape[1] == 1
    transform = np.fft.fftn(height - height.mean(), axes=(0,) if line else (0, 1))
    q = wavevectors(height.shape, spacing)
    return float(np.sqrt(np.sum(q**2 * np.abs(transform) ** 2)) / height.size)


def radial_psd(height: np.ndarray, spacing: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """The radially averaged power spectrum of a map: (q, C) with q (rad/mm) the centres of
    annuli of width 2π/L (L the map's shorter side) up to the Nyquist wavevector π/Δ, and
    C (mm⁴; a profile: mm³) the mean of |h̃|²/A over each annulus (module docstring), NaN for
    an empty annulus. A profile's spectrum is one-sided over q > 0 (each q once)."""
    height = np.asarray(height, dtype=float)
    line = height.shape[1] == 1
    transform = np.fft.fftn(height - height.mean(), axes=(0,) if line else (0, 1))
    n_x, n_y = height.shape
    if line:
        length = n_x * spacing[0]
        power = (np.abs(transform[:, 0]) * spacing[0]) ** 2 / length  # |h̃|²/L, mm³
        q = 2.0 * math.pi * np.fft.fftfreq(n_x, spacing[0])
        keep = q > 0.0
        order = np.argsort(q[keep])
        return q[keep][order], power[keep][order]
    area = n_x * spacing[0] * n_y * spacing[1]
    power = (np.abs(transform) * spacing[0] * spacing[1]) ** 2 / area  # |h̃|²/A, mm⁴
    q = wavevectors(height.shape, spacing)
    step = 2.0 * math.pi / max(n_x * spacing[0], n_y * spacing[1])
    nyquist = math.pi / max(spacing)
    edges = np.arange(0.5 * step, nyquist + step, step)
    index = np.digitize(q.ravel(), edges)
    sums = np.bincount(index, weights=power.ravel(), minlength=len(edges) + 1)
    counts = np.bincount(index, minlength=len(edges) + 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = sums / counts
    centres = 0.5 * (edges[:-1] + edges[1:])
    return centres, mean[1 : len(edges)]


def spectrum_exponent(q: np.ndarray, psd: np.ndarray, q_min: float, q_max: float) -> float:
    """Least-squares slope of log C against log q over q_min ≤ q ≤ q_max (rad/mm): −2(1+H)
    for a self-affine map, −(1+2H) for a profile."""
    q, psd = np.asarray(q), np.asarray(psd)
    keep = (q >= q_min) & (q <= q_max) & np.isfinite(psd) & (psd > 0.0)
    slope, _ = np.polyfit(np.log(q[keep]), np.log(psd[keep]), 1)
    return float(slope)
