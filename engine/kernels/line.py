"""Plane-strain influence coefficients of two elastic bodies in line contact (the x–z plane).

The 2-D counterpart of ``engine.kernels.influence``: a uniform traction over the strip
|x − x_j| ≤ Δx/2 (infinitely long along y) on two half-planes, the relative surface
displacement u = u^(A) − u^(B) at x (z into body A, tractions acting on A, the conventions
of the 3-D kernels). Integrating the 3-D point kernels of Eq. (5) along y gives the
classical line-load (Flamant) surface displacements (Johnson 1985, Eqs. 2.19–2.20):

    A_zz(X) = A_xx(X) = −(2/(π E*)) ln(|X| / d)       (E* the contact modulus; 2/E* =
                                                       Σ 2(1−ν_i²)/E_i = 2(1−ν)/G of Eq. 6)
    A_zx(X) = −A_xz(X) = (K/G) sgn(X) = β (1−ν)/G sgn(X)     (β: Dundurs' second constant)

with X = x − x'. The normal–tangential coupling K/G is the same constant as in 3-D: the
y-integral of K X/(π G s²) is (K/G) sgn X.

**The rigid-body constant.** A 2-D surface displacement grows like ln|X| and is defined
only up to a constant. The kernels here are *displacement differences*: ``A(X)`` is the
displacement at distance |X| from the load minus that at the distance ``d``
(``reference_distance``, mm), i.e. the displacement relative to a datum at distance d.
The constant does not change the pressure or the tractions under load control (it is taken
up by the approach δ, and by the rigid tangential displacement under force control), nor the
energy dissipated per fretting cycle (a linear compliance encloses no area); it does set the
rigid tangential displacement under *displacement* control, where d plays the role of the
size of the bodies (the far-field compliance (2/(πE*)) ln(d/a) per unit load). The
coupling kernel needs no datum: its two sides are antisymmetric.

Element integration (exact): ∫ ln(|u|/d) du over the element = F(X + Δx/2) − F(X − Δx/2),
F(u) = u ln(|u|/d) − u; ∫ sgn(X − t) dt over the element = Δx sgn(X) at element centres.

Plane strain has no y-traction; the fields keep the ``(n, 1)`` shape of a line grid
(``Grid.line``) and carry a y-component that nothing drives (A_xy = A_zy = 0). Its kernel is
set to A_yy = A_xx so that the block operator and its spectral preconditioner stay
invertible; q_y stays zero.

**The operator** (``LineOperator``): the DC-FFT of ``engine.kernels.operator`` reduced to one
dimension. The Toeplitz product with the ``2n − 1`` offsets equals the first n entries of a
circular convolution of length 2n once the field is zero-padded and the kernel wrapped; the
two distinct kernels have exact parities on that circle (the log kernel even, the coupling
odd), so their spectra are kept as real and imaginary parts. One application is one batch of
real 1-D transforms of length 2n (``FFTW_ESTIMATE`` plans on aligned buffers, made through
``engine.kernels.fft.plan``: reproducible bits), which is what makes a line case cheap: the
2-D machinery of the 3-D operator would transform a padded (2n, 2) array in two passes for
every product.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import Grid
from ..material import MaterialPair
from ..validation import require_positive
from .fft import DEFAULT_EFFORT, aligned_zeros, plan, wrap_kernel
from .influence import SurfaceInfluence
from .operator import fold_periodic

__all__ = [
    "LineInfluence",
    "LineOperator",
    "LinePreconditioner",
    "line_operator",
    "log_strip_integral",
    "minimum_reference_distance",
]

# The log kernel ln(d/|X|) is positive definite on a segment of length L only when d exceeds
# the segment's logarithmic capacity L/4; a datum beyond the grid's whole length keeps every
# contact matrix comfortably positive definite.
REFERENCE_DISTANCE_FACTOR = 1.0


def minimum_reference_distance(grid: Grid) -> float:
    """The smallest accepted ``reference_distance`` for ``grid`` (mm): its length 2·half_width."""
    return REFERENCE_DISTANCE_FACTOR * 2.0 * grid.half_width_x


def log_strip_integral(offset: np.ndarray, width: float, reference_distance: float):
    """∫ ln(|u| / d) du over |u − offset| ≤ width/2 (mm), exact, for any offset (mm)."""

    def antiderivative(u):
        magnitude = np.abs(u)
        safe = np.where(magnitude > 0.0, magnitude, 1.0)
        return np.where(magnitude > 0.0, u * np.log(safe / reference_distance), 0.0) - u

    offset = np.asarray(offset, dtype=float)
    return antiderivative(offset + 0.5 * width) - antiderivative(offset - 0.5 * width)


@dataclass(frozen=True)
class LineInfluence(SurfaceInfluence):
    """Plane-strain kernels on the offset grid of a line grid (mm/MPa), shape ``(2n − 1, 1)``
    (entry ``[a, 0]``: offset (a − n + 1) Δx, observation minus source), keys as
    ``SurfaceInfluence`` (``xx, yy, xy, zz, zx, zy``); ``reference_distance`` d (mm) is the
    datum of the displacements (module docstring)."""

    reference_distance: float = 0.0

    @classmethod
    def build(
        cls, grid: Grid, material: MaterialPair, reference_distance: float | None = None
    ) -> LineInfluence:
        if not grid.is_line:
            raise ValueError(f"a line contact needs a line grid (n_y = 1), got {grid.shape}")
        if reference_distance is None:
            raise ValueError("reference_distance (mm) is required for a line contact")
        reference_distance = require_positive("reference_distance", reference_distance)
        minimum = minimum_reference_distance(grid)
        if reference_distance < minimum:
            raise ValueError(
                f"reference_distance = {reference_distance:g} mm must be at least the grid's "
                f"length {minimum:g} mm (the log kernel is not positive definite otherwise)"
            )
        offsets = grid.dx * np.arange(-(grid.n_x - 1), grid.n_x)
        compliance = 2.0 / (np.pi * material.contact_modulus)
        normal = -compliance * log_strip_integral(offsets, grid.dx, reference_distance)
        coupling = material.coupling / material.shear_modulus * grid.dx * np.sign(offsets)
        zeros = np.zeros_like(normal)
        line_kernels = {"zz": normal, "xx": normal, "yy": normal, "xy": zeros, "zx": coupling}
        line_kernels["zy"] = zeros
        kernels = {key: values[:, None].copy() for key, values in line_kernels.items()}
        return cls(grid, kernels, reference_distance)


class _Transforms:
    """Real 1-D FFTs of length ``length`` for batches of 1 … ``capacity`` rows, on aligned
    buffers of their own (``real`` (capacity, length), ``spectra`` (capacity, length//2 + 1));
    unnormalised both ways (callers fold 1/length into their spectra). The inverse overwrites
    the whole of ``real`` for its rows."""

    def __init__(self, length: int, capacity: int, *, threads: int, effort: str):
        self.length = length
        self.real = aligned_zeros((capacity, length), "float64")
        self.spectra = aligned_zeros((capacity, length // 2 + 1), "complex128")
        options = dict(threads=threads, effort=effort)
        self._forward = [
            plan(self.real[:batch], self.spectra[:batch], (1,), **options)
            for batch in range(1, capacity + 1)
        ]
        self._inverse = [
            plan(
                self.spectra[:batch],
                self.real[:batch],
                (1,),
                direction="FFTW_BACKWARD",
                flags=("FFTW_DESTROY_INPUT",),
                **options,
            )
            for batch in range(1, capacity + 1)
        ]

    def forward(self, fields: tuple[np.ndarray, ...], width: int) -> np.ndarray:
        """Spectra (len(fields), length//2 + 1) of the fields (each (width, 1)) zero-padded
        to ``length``; a view of ``spectra``."""
        batch = len(fields)
        real = self.real[:batch]
        for row, field in zip(real, fields, strict=True):
            row[:width] = field[:, 0]
        real[:, width:] = 0.0
        self._forward[batch - 1].execute()
        return self.spectra[:batch]

    def inverse(self, batch: int, width: int) -> np.ndarray:
        """The first ``width`` entries of the inverse transforms of ``spectra[:batch]``, as
        new fields (batch, width, 1)."""
        self._inverse[batch - 1].execute()
        return self.real[:batch, :width, None].copy()


class LineOperator:
    """Relative surface displacements of two half-planes from strip tractions (plane strain).

    The interface of ``engine.kernels.operator.HalfSpaceOperator`` on a line grid (fields of
    shape ``(n, 1)``: tractions in MPa, displacements in mm): ``apply(p_x, p_y, p_n)`` the
    block of Eq. (4) with the plane-strain kernels of ``LineInfluence``,

        u_x = A_xx p_x − A_zx p_n,   u_y = A_yy p_y,   u_n = A_zx p_x + A_zz p_n

    (A_xx = A_yy = A_zz the log kernel, A_zx the odd coupling kernel, A_xz = −A_zx),
    ``apply_normal``, ``apply_tangential``, ``apply_normal_later``, the two couplings,
    ``symbol_bound`` and the spectral ``preconditioner``. ``applications`` counts calls.
    Spectra: real 1-D transforms
    of length 2n, the log kernel's real (even circulant), the coupling's imaginary (odd), with
    the 1/(2n) of the inverse transform folded in.
    """

    def __init__(
        self,
        grid: Grid,
        material: MaterialPair,
        reference_distance: float,
        *,
        threads: int = 1,
        planner_effort: str = DEFAULT_EFFORT,
    ):
        self.influence = LineInfluence.build(grid, material, reference_distance)
        self.grid, self.material = grid, material
        self.threads, self.planner_effort = threads, planner_effort
        self.reference_distance = reference_distance
        self.padded_length = 2 * grid.n_x
        self.applications = 0
        self._transforms = _Transforms(
            self.padded_length, 3, threads=threads, effort=planner_effort
        )
        scale = 1.0 / self.padded_length
        self._log = scale * self._spectrum("zz").real  # even circulant: real spectrum
        self._coupled = material.coupling != 0.0
        self._coupling = 1j * (scale * self._spectrum("zx").imag)  # odd: imaginary spectrum
        self._symbol_bound: float | None = None
        self._preconditioner: LinePreconditioner | None = None

    def _spectrum(self, key: str) -> np.ndarray:
        wrapped = wrap_kernel(self.influence.kernels[key], (self.padded_length, 1))[:, 0]
        return np.fft.rfft(wrapped)

    @property
    def spectra_bytes(self) -> int:
        """Memory held by the kernel spectra (bytes)."""
        return self._log.nbytes + self._coupling.nbytes

    def kernel(self, key: str, index_x: np.ndarray, index_y: np.ndarray) -> np.ndarray:
        """Kernel ``key`` (mm/MPa) at the offsets i Δx, i in ``index_x`` (``index_y``: 0)."""
        rows = np.asarray(index_x) + self.grid.n_x - 1
        return self.influence.kernels[key][np.ix_(rows, np.asarray(index_y))]

    def self_coefficient(self, key: str) -> float:
        """An element's own coefficient of kernel ``key`` (offset 0; mm/MPa)."""
        return float(self.influence.kernels[key][self.grid.n_x - 1, 0])

    def release_buffers(self) -> None:
        """The half-space operator's way to let go of its transforms before a case's stress
        plane (:meth:`engine.kernels.operator.HalfSpaceOperator.release_buffers`). A line's
        transforms are three rows of 2n values, a few kB even at 2,048 elements: nothing
        worth freeing, so they are kept."""

    @property
    def preconditioner(self) -> LinePreconditioner:
        if self._preconditioner is None:
            self._preconditioner = LinePreconditioner(self)
        return self._preconditioner

    def _forward(self, *fields: np.ndarray) -> np.ndarray:
        """Spectra (len(fields), n + 1) of the zero-padded fields (each (n, 1)): a view of
        the transforms' buffer, which the products overwrite in place."""
        return self._transforms.forward(fields, self.grid.n_x)

    def _inverse(self, batch: int) -> np.ndarray:
        """The first n entries of the inverse transforms of the buffer's first ``batch``
        spectra, as fields (batch, n, 1)."""
        self.applications += 1
        return self._transforms.inverse(batch, self.grid.n_x)

    def apply(self, p_x: np.ndarray, p_y: np.ndarray, p_n: np.ndarray):
        """Full block: tractions (MPa) → relative displacements ``(u_x, u_y, u_n)`` (mm)."""
        if not p_y.any():  # plane strain: q_y = 0, so u_y = 0 without its transforms
            spectra = self._forward(p_x, p_n)
            rows = (0, 1)
        else:
            spectra = self._forward(p_x, p_n, p_y)
            spectra[2] *= self._log
            rows = (0, 1, 2)
        log, coupling = self._log, self._coupling
        tangential, normal = spectra[0].copy(), spectra[1].copy()
        spectra[0] = log * tangential - coupling * normal
        spectra[1] = coupling * tangential + log * normal
        u = self._inverse(len(rows))
        return u[0], u[2] if len(rows) == 3 else np.zeros(self.grid.shape), u[1]

    def apply_normal_later(self, p_x: np.ndarray, p_y: np.ndarray, p_n: np.ndarray):
        """:meth:`apply` in the form of ``HalfSpaceOperator.apply_normal_later``: ``(u_x,
        u_y, normal)`` with ``normal()`` giving u_n (mm); all three are made now (one set of
        transforms)."""
        u_x, u_y, u_n = self.apply(p_x, p_y, p_n)
        return u_x, u_y, lambda: u_n

    def apply_normal(self, p_n: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """A_zz only: pressure (MPa) → relative normal displacement (mm), into ``out`` when
        given."""
        spectra = self._forward(p_n)
        spectra *= self._log
        result = self._inverse(1)[0]
        if out is None:
            return result
        out[...] = result
        return out

    def apply_tangential(self, p_x: np.ndarray, p_y: np.ndarray):
        """The tangential block: (p_x, p_y) (MPa) → (u_x, u_y) (mm); u_y = 0 for q_y = 0."""
        fields = (p_x, p_y) if p_y.any() else (p_x,)
        spectra = self._forward(*fields)
        spectra *= self._log
        u = self._inverse(len(fields))
        return u[0], u[1] if len(fields) == 2 else np.zeros(self.grid.shape)

    def coupling_to_normal(self, p_x: np.ndarray, p_y: np.ndarray) -> np.ndarray:
        """A_zx p_x (mm): normal displacement due to tangential tractions (A_zy = 0)."""
        if not self._coupled:
            return np.zeros(self.grid.shape)
        spectra = self._forward(p_x)
        spectra *= self._coupling
        return self._inverse(1)[0]

    def coupling_to_tangential(self, p_n: np.ndarray):
        """(A_xz p_n, 0) (mm): tangential displacement due to pressure (zero when K = 0)."""
        if not self._coupled:
            return np.zeros(self.grid.shape), np.zeros(self.grid.shape)
        spectra = self._forward(p_n)
        spectra *= -self._coupling
        return self._inverse(1)[0], np.zeros(self.grid.shape)

    def symbol_bound(self) -> float:
        """The largest eigenvalue of A's circulant symbol (mm/MPa): per frequency the x–n
        block [[L, −C], [C, L]] (C imaginary: Hermitian) has eigenvalues L ± |C|, the y
        entry L."""
        if self._symbol_bound is None:
            largest = np.max(self._log + np.abs(self._coupling))  # 1/(2n) folded in
            self._symbol_bound = float(self.padded_length * largest)
        return self._symbol_bound


class LinePreconditioner:
    """Inverse of the periodic (n-element) circulant of the log kernel (mm → MPa): the 1-D
    form of ``engine.kernels.operator.SpectralPreconditioner`` (A_xx = A_yy = A_zz, no
    A_xy, so the tangential block is the normal inverse applied to each component)."""

    def __init__(self, operator: LineOperator):
        n = operator.grid.n_x
        self._n = n
        folded = fold_periodic(operator.influence.kernels["zz"], (n, 1))[:, 0]
        # Even: a real spectrum; the 1/n of the inverse transform folded in.
        self._inverse = 1.0 / (n * np.fft.rfft(folded).real)
        self._transforms = _Transforms(
            n, 2, threads=operator.threads, effort=operator.planner_effort
        )

    def _apply(self, *residuals: np.ndarray) -> np.ndarray:
        spectra = self._transforms.forward(residuals, self._n)
        spectra *= self._inverse
        return self._transforms.inverse(len(residuals), self._n)

    def normal(self, residual: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        result = self._apply(residual)[0]
        if out is None:
            return result
        out[...] = result
        return out

    def tangential(self, rx: np.ndarray, ry: np.ndarray):
        if not ry.any():  # plane strain: no y residual, no y correction
            return self._apply(rx)[0], np.zeros(rx.shape)
        values = self._apply(rx, ry)
        return values[0], values[1]


def line_operator(
    grid: Grid,
    material: MaterialPair,
    reference_distance: float,
    *,
    threads: int = 1,
    planner_effort: str = DEFAULT_EFFORT,
) -> LineOperator:
    """The influence operator of a line contact (``LineOperator``)."""
    return LineOperator(
        grid, material, reference_distance, threads=threads, planner_effort=planner_effort
    )
