"""Subsurface stresses of a line (plane-strain) contact on the whole x–z plane, by DC-FFT.

The stress in the flat (body A) at the element centres x_i and depth z is the sum over the
surface elements j of the strip coefficients of ``engine.kernels.line_stress`` times the
element tractions: a Toeplitz convolution in i − j per depth, evaluated by a zero-padded 1-D
FFT of length 2n (DC-FFT, Liu & Wang 2002; no periodic images). Kernel spectra are computed
once per depth and kept (3 loads·components × (n + 1) complex values per depth).

A bulk stress σ_B along x in the flat (fretting fatigue) adds σ_xx = σ_B and, in plane
strain, σ_yy = ν σ_B; the tractions add σ_yy = ν(σ_xx + σ_zz). So everywhere
σ_yy = ν(σ_xx + σ_zz) with σ_xx including σ_B.

Conventions of ``engine.solvers.subsurface``: mm, MPa, tension positive, z > 0 into the flat;
fields of shape (n_x, n_z); the returned ``StressField`` has y = 0 and σ_xy = σ_yz = 0.
"""

from __future__ import annotations

import numpy as np

from ..grid import Grid
from ..kernels.line_stress import strip_stress_coefficients
from ..validation import require_finite, require_poisson
from .peak import PeakTracker
from .subsurface import PlaneStresses, StressField

__all__ = ["LineSubsurfaceStress", "LinePeakTracker"]

_TERMS = (  # (stress component, load) pairs of the sum
    ("xx", "pressure"),
    ("zz", "pressure"),
    ("xz", "pressure"),
    ("xx", "traction_x"),
    ("zz", "traction_x"),
    ("xz", "traction_x"),
)


class LineSubsurfaceStress(PlaneStresses):
    """Stresses under the surface tractions of a line grid at ``depths`` (mm, all > 0) for a
    flat of Poisson ratio ``poisson_ratio``; its ``plane`` is that of every contact
    (:class:`~engine.solvers.subsurface.PlaneStresses`), so the peak tracking of
    ``engine.solvers.peak`` applies."""

    def __init__(self, grid: Grid, poisson_ratio: float, depths):
        if not grid.is_line:
            raise ValueError(f"line subsurface stresses need a line grid, got {grid.shape}")
        self.grid = grid
        self.poisson_ratio = require_poisson("poisson_ratio", poisson_ratio)
        self.depths = np.asarray(depths, dtype=float)
        if self.depths.ndim != 1 or self.depths.size == 0 or np.any(self.depths <= 0.0):
            raise ValueError(f"depths must be a non-empty list of values > 0 mm, got {depths!r}")
        self._length = 2 * grid.n_x
        self._spectra = self._kernel_spectra()
        self.bulk_stress = 0.0  # σ_B (MPa) used by ``plane`` when none is passed

    def _kernel_spectra(self) -> dict[tuple[str, str], np.ndarray]:
        """rfft of the wrapped kernels, shape (n_z, n + 1) per (component, load)."""
        grid, length = self.grid, self._length
        offsets = grid.dx * np.arange(-(grid.n_x - 1), grid.n_x)
        index = np.arange(-(grid.n_x - 1), grid.n_x) % length
        coefficients = strip_stress_coefficients(offsets[None, :], self.depths[:, None], grid.dx)
        spectra = {}
        for component, load in _TERMS:
            wrapped = np.zeros((self.depths.size, length))
            wrapped[:, index] = coefficients[load][component]
            spectra[component, load] = np.fft.rfft(wrapped, axis=1)
        return spectra

    def _plane(
        self, pressure, traction_x, traction_y, angle: float, half_length, bulk_stress
    ) -> StressField:
        """The x–z field (n_x, n_z) of ``pressure`` and ``traction_x`` (MPa, (n_x, 1) or
        (n_x,); None: zero) and a bulk stress σ_B (MPa) along x (default: the attribute
        ``bulk_stress``, 0 unless set). ``traction_y`` must be zero (plane strain), ``angle``
        0 (the plane is the x–z plane) and ``half_length`` None (the grid)."""
        if angle != 0.0 or half_length is not None:
            raise ValueError("a line contact's stresses are on the x–z plane over its grid")
        if traction_y is not None and np.any(np.asarray(traction_y) != 0.0):
            raise ValueError("a line contact has no traction along y (plane strain)")
        bulk_stress = self.bulk_stress if bulk_stress is None else bulk_stress
        zeros = np.zeros(self.grid.n_x)
        pressure = zeros if pressure is None else pressure
        traction_x = zeros if traction_x is None else traction_x
        bulk_stress = require_finite("bulk_stress", bulk_stress)
        n, length = self.grid.n_x, self._length
        loads = {
            "pressure": np.fft.rfft(np.asarray(pressure, float).reshape(n), n=length),
            "traction_x": np.fft.rfft(np.asarray(traction_x, float).reshape(n), n=length),
        }
        components = {"xx": 0.0, "zz": 0.0, "xz": 0.0}
        for component, load in _TERMS:
            components[component] = (
                components[component] + self._spectra[component, load] * (loads[load][None, :])
            )
        fields = {
            key: np.fft.irfft(value, n=length, axis=1)[:, :n].T for key, value in components.items()
        }
        fields["xx"] = fields["xx"] + bulk_stress
        fields["yy"] = self.poisson_ratio * (fields["xx"] + fields["zz"])
        zeros = np.zeros_like(fields["xx"])
        fields["xy"], fields["yz"] = zeros, zeros.copy()
        x, z = np.meshgrid(self.grid.x, self.depths, indexing="ij")
        return StressField.from_components(
            x, np.zeros_like(x), z, fields, s=x, angle=0.0, depths=self.depths.copy()
        )


class LinePeakTracker(PeakTracker):
    """:class:`~engine.solvers.peak.PeakTracker` on a line contact's x–z plane: its
    ``contact_radius`` is the contact half-width (half the length of the elements with
    p > 0, mm), and ``punch_radius`` the nominal contact half-width a0 (mm)."""

    def contact_radius(self, pressure: np.ndarray) -> float:
        grid = self.stress.grid
        return 0.5 * np.count_nonzero(np.asarray(pressure) > 0.0) * grid.dx
