"""Subsurface stresses under the contact by DC-FFT (paper Section 5, Eq. 16; Liu & Wang 2002).

The stress in the half-space (body A) at depth z is the sum over surface elements of the
element-integrated influence coefficients of ``engine.kernels.stress`` times the element
tractions (Eq. 16). On a regular lattice of field points this sum is a 2-D Toeplitz
convolution, evaluated per depth layer by zero-padded FFT (discrete convolution FFT, Liu &
Wang, J. Tribol. 124 (2002) 36–45): the traction fields are padded to ``(N_x, N_y) >=
(n_x + m_x − 1, n_y + m_y − 1)`` for ``m_x × m_y`` field points, the kernel is wrapped in the
same circulant layout, and the first ``m_x × m_y`` entries of the circular convolution are
exact (no periodic images). The convolution lives in ``engine.kernels.lattice``
(``LatticeConvolution``, on the FFT plans of ``engine.kernels.fft``); this module chooses the
lattices (block, vertical planes), checks the tractions and assembles the fields.

Cost and memory. The three traction fields are transformed once per call and reused for all
layers; each layer then costs one inverse real FFT per stress component (six) plus the
spectral products. pyfftw plans are built once per lattice and reused. Kernel spectra are
computed once per (lattice, layer, load) and cached when ``cache_kernels=True`` (a line
through the axis: from its second call on, within the limit below); six per layer and load
type. For the block, field points coincide with the sources, the kernels are
even or odd and their spectra real or imaginary, so only that half is stored:
``N_x · (N_y/2 + 1) · 8`` bytes, 0.26 MB per spectrum at 128² (N = 256). Other lattices
(oblique planes, blocks with a margin) store complex spectra. The x–z and y–z planes
through the axis are single lines of field points on a grid symmetric about them: they fold
the grid across the line (``LineConvolution``: pairs of mirror rows, 1-D transforms along the
line) and store ``ceil(n/2) · (N/2 + 1) · 16`` bytes per spectrum, 0.13 MB at 128², half the
2-D lattice's; a plane then costs six 1-D inverse FFTs per layer (7 ms for 16 layers and three
loads at 128², against 20 ms for the 2-D lattice). Measured at 128² with 16 layers and three
loads: 38 MB for the x–z plane (77 MB before the fold). The line streams its rows in blocks
(``ROW_BLOCK``) and keeps its kernel spectra only when all of them fit in what is left of
``kernel_cache_limit`` (64 MiB by default: the x–z plane at 128² with up to 28 layers);
otherwise it keeps none and computes them at each call, with the same values. A part kept
would save only that part of the time (measured at 256² with 16 layers: 0.29 s a call with
the 44 % that fit, 0.36 s with none), and it holds memory beside the solver's at the case's
peak: a plane costs the line's memory plus one block's, not a field of the grid per layer.
``kernel_cache_bytes`` reports the current size; ``cache_kernels=False`` recomputes the
kernels at every call (about 0.1 s for 16 layers and three loads on the x–z plane at 128²).

Conventions (package wide): lengths mm, stresses MPa, tension positive. z > 0 points into the
half-space. ``pressure`` >= 0 pushes into the half-space (σzz → −p at the surface);
``traction_x``/``traction_y`` act on the half-space surface in +x/+y (σxz → −q_x at the
surface). Surface fields have the grid shape ``(n_x, n_y)``, "ij" indexing. The stresses are
those of the half-space alone and depend on its Poisson ratio only (``material.nu_A``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..grid import Grid
from ..kernels.fft import DEFAULT_EFFORT
from ..kernels.lattice import LatticeConvolution, LineConvolution, line_axis
from ..kernels.stress import COMPONENTS, LOADS, kernel_parity
from ..validation import require_poisson, require_positive

DEFAULT_KERNEL_CACHE_LIMIT = 64 * 2**20
"""Bytes of subsurface kernel spectra a ``SubsurfaceStress`` keeps for its planes through the
axis (64 MiB: every layer of the x–z plane at 128² with 16 layers and three loads, 38 MB);
a plane whose spectra do not all fit keeps none and computes them at each call instead
(module docstring)."""

# --- depth layers ------------------------------------------------------------------------------


def depth_layers(
    max_depth: float, layers: int, graded: bool = True, *, surface_fraction: float = 0.01
) -> np.ndarray:
    """Depths (mm, increasing, all > 0) of ``layers`` evaluation planes down to ``max_depth``.

    The first depth is the *surface layer*: z = 0 itself is excluded (the stress of piecewise
    constant tractions is discontinuous at element edges there), so it sits at
    ``surface_fraction`` (default 1 %) of the first regular depth. The other ``layers − 1``
    depths are z_k = max_depth · (k/(layers − 1))^q, k = 1 … layers − 1, with q = 2 when
    ``graded`` (spacing refined toward the surface, where the edge singularity of a flat
    punch lives) and q = 1 for uniform spacing. Example: 40 graded layers to 2 a0 = 3.6 mm
    give z_1 = 2.4 µm, i.e. 8 % of the element size of the 128² grid over 1.05 a0
    (Δ = 29.5 µm), and a surface layer at 0.024 µm. The surface layer therefore approximates
    the surface stress of the discretised tractions at the element centres, which is grid
    dependent near the punch edge: report peaks with and without it (``StressField.peaks``).
    """
    max_depth = require_positive("max_depth", max_depth)
    if isinstance(layers, bool) or not isinstance(layers, (int, np.integer)) or layers < 2:
        raise ValueError(f"layers must be an integer >= 2, got {layers!r}")
    if not 0.0 < surface_fraction < 1.0:
        raise ValueError(f"surface_fraction must lie in (0, 1), got {surface_fraction!r}")
    fractions = np.arange(1, layers) / (layers - 1)
    regular = max_depth * (fractions**2 if graded else fractions)
    return np.concatenate([[surface_fraction * regular[0]], regular])


# --- results -----------------------------------------------------------------------------------


def von_mises(components: dict[str, np.ndarray]) -> np.ndarray:
    """Equivalent stress (MPa) from the six Cartesian components.

    σ_VM = √(½[(σxx − σyy)² + (σyy − σzz)² + (σzz − σxx)²] + 3(σxy² + σyz² + σxz²)),
    the invariant form of the corrected Eq. (21) of NOTES.md (in cylindrical components with
    τrφ = τφz = 0 it is exactly Eq. 21).
    """
    xx, yy, zz = components["xx"], components["yy"], components["zz"]
    xy, xz, yz = components["xy"], components["xz"], components["yz"]
    return np.sqrt(
        0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2)
        + 3.0 * (xy * xy + xz * xz + yz * yz)
    )


@dataclass(frozen=True)
class Peak:
    """Largest von Mises stress (MPa) of a field and where it is (mm)."""

    value: float
    x: float
    y: float
    z: float
    label: str = ""


@dataclass
class StressField:
    """Stresses on a set of points in the half-space.

    ``x, y, z``: coordinates (mm), arrays of the field's shape — ``(n_x, n_y, n_z)`` for a
    block, ``(n_s, n_z)`` for a vertical plane. ``components``: Cartesian stresses (MPa), keys
    ``'xx','yy','zz','xy','xz','yz'``. ``von_mises`` (MPa). For a plane, ``s`` is the signed
    along-plane coordinate (x = s cos φ, y = s sin φ) and ``angle`` the plane angle φ (rad).
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    components: dict[str, np.ndarray]
    von_mises: np.ndarray
    s: np.ndarray | None = None
    angle: float | None = None
    depths: np.ndarray = field(default_factory=lambda: np.empty(0))

    @classmethod
    def from_components(cls, x, y, z, components, **kwargs) -> StressField:
        return cls(x=x, y=y, z=z, components=components, von_mises=von_mises(components), **kwargs)

    def peak(self, min_depth: float = 0.0) -> Peak:
        """Maximum von Mises stress over the points with z >= ``min_depth`` (mm)."""
        candidates = np.where(self.z >= min_depth, self.von_mises, -np.inf)
        index = np.unravel_index(np.argmax(candidates), candidates.shape)
        if not np.isfinite(candidates[index]):
            raise ValueError(f"no evaluated point at depth >= {min_depth!r} mm")
        return Peak(
            value=float(self.von_mises[index]),
            x=float(self.x[index]),
            y=float(self.y[index]),
            z=float(self.z[index]),
            label=f"z >= {min_depth:g} mm",
        )

    def on_edge(self, min_depth: float = 0.0) -> str:
        """Where the largest σ_VM over z >= ``min_depth`` (mm) of a vertical plane (shape
        ``(n_s, n_z)``) touches the computed domain's boundary: ``"side"`` (an outermost
        column, |s| at the plane's end: the mesh's edge), ``"bottom"`` (the deepest layer),
        ``"side and bottom"``, or ``"inside"``. On the boundary, the maximum of the field may
        lie beyond the domain: widen ``[mesh] half_width`` or deepen ``[subsurface] depth``.
        """
        if self.von_mises.ndim != 2:
            raise ValueError(f"on_edge needs a vertical plane (n_s, n_z), got {self.z.shape}")
        candidates = np.where(self.z >= min_depth, self.von_mises, -np.inf)
        column, layer = np.unravel_index(np.argmax(candidates), candidates.shape)
        places = []
        if column in (0, candidates.shape[0] - 1):
            places.append("side")
        if layer == candidates.shape[1] - 1:
            places.append("bottom")
        return " and ".join(places) or "inside"

    def peaks(self) -> dict[str, Peak]:
        """Peak over all layers and peak below the surface layer, labelled.

        The surface layer (the shallowest depth) carries the edge singularity of a flat punch,
        so its value depends on the grid; the peak below it is the grid-converging figure.
        """
        layers = np.unique(self.z)
        overall = self.peak(0.0)
        result = {
            "overall": Peak(
                overall.value,
                overall.x,
                overall.y,
                overall.z,
                f"all layers (surface layer z = {layers[0]:.3g} mm included)",
            ),
        }
        if layers.size > 1:
            below = self.peak(layers[1])
            result["below_surface_layer"] = Peak(
                below.value, below.x, below.y, below.z, f"z >= {layers[1]:.3g} mm"
            )
        return result

    @property
    def r(self) -> np.ndarray:
        """Distance from the punch axis (mm)."""
        return np.hypot(self.x, self.y)

    def cylindrical(self) -> dict[str, np.ndarray]:
        """Cylindrical components about the punch axis (MPa): 'rr', 'phiphi', 'zz', 'rz', 'rphi',
        'phiz'. φ = atan2(y, x); on the axis the plane angle (or 0) is used."""
        fallback = 0.0 if self.angle is None else self.angle
        phi = np.where(self.r > 0.0, np.arctan2(self.y, self.x), fallback)
        c, s = np.cos(phi), np.sin(phi)
        xx, yy, zz = (self.components[k] for k in ("xx", "yy", "zz"))
        xy, xz, yz = (self.components[k] for k in ("xy", "xz", "yz"))
        return {
            "rr": xx * c * c + yy * s * s + 2.0 * xy * s * c,
            "phiphi": xx * s * s + yy * c * c - 2.0 * xy * s * c,
            "zz": zz,
            "rz": xz * c + yz * s,
            "rphi": (yy - xx) * s * c + xy * (c * c - s * s),
            "phiz": -xz * s + yz * c,
        }


# --- public API --------------------------------------------------------------------------------


class PlaneStresses:
    """The stress field on a vertical plane through the punch axis, as the peak tracking
    (:mod:`engine.solvers.peak`), the fatigue fields and a case's outcome ask for it, whatever
    the contact: :class:`SubsurfaceStress` (3-D) and
    :class:`~engine.solvers.line_subsurface.LineSubsurfaceStress` (plane strain) implement
    ``_plane``."""

    def plane(
        self,
        pressure,
        traction_x=None,
        traction_y=None,
        angle: float = 0.0,
        half_length: float | None = None,
        *,
        bulk_stress: float | None = None,
    ) -> StressField:
        """Stresses on the vertical plane through the punch axis at angle φ = ``angle`` (rad).

        Tractions (MPa) on the grid, None for zero; ``half_length`` (mm) the extent of the
        plane on either side of the axis (default: the grid's); ``bulk_stress`` σ_B (MPa)
        along x, for line contacts only. Returns a ``StressField`` of shape ``(n_s, n_z)``
        with ``s`` and ``angle`` set; what each contact supports is said by its ``_plane``.
        """
        return self._plane(pressure, traction_x, traction_y, angle, half_length, bulk_stress)

    def _plane(self, pressure, traction_x, traction_y, angle, half_length, bulk_stress):
        raise NotImplementedError

    def prepare_plane(self, angle: float = 0.0, kernels: bool = True) -> None:
        """Build what ``plane`` at ``angle`` (rad) keeps between calls (its kernels), so that
        it counts as set-up: here by one evaluation of unit tractions, whatever ``kernels``
        (which a contact may use to defer its kernels to the evaluations)."""
        ones = np.ones(self.grid.shape)
        self.plane(ones, ones, None if self.grid.is_line else ones, angle=float(angle))


class SubsurfaceStress(PlaneStresses):
    """Subsurface stress fields of surface tractions on ``grid`` (Eq. 16 by DC-FFT).

    Parameters
    ----------
    grid : the surface grid of the tractions (element centres = source points).
    poisson_ratio : ν of the half-space (``material.nu_A``).
    depths : evaluation depths (mm, all > 0), e.g. from ``depth_layers``.
    threads : FFTW threads.
    cache_kernels : keep kernel spectra between calls (memory: see the module docstring).
    kernel_cache_limit : bytes of kernel spectra the x–z and y–z planes keep between calls
        (default ``DEFAULT_KERNEL_CACHE_LIMIT``; None: no limit): a plane keeps all of its
        spectra if they fit in what the planes built before left of it, else none, and
        computes them at each call, block by block, with the same values
        (``LineConvolution``).
    planner_effort : FFTW planner flag, ``"FFTW_ESTIMATE"`` (default: bit-reproducible across
        processes, see ``engine.kernels.fft``) or ``"FFTW_MEASURE"``.
    """

    def __init__(
        self,
        grid: Grid,
        poisson_ratio: float,
        depths: np.ndarray,
        threads: int = 1,
        *,
        cache_kernels: bool = True,
        kernel_cache_limit: int | None = DEFAULT_KERNEL_CACHE_LIMIT,
        planner_effort: str = DEFAULT_EFFORT,
    ):
        self.grid = grid
        self.poisson_ratio = require_poisson("poisson_ratio", poisson_ratio)
        depths = np.asarray(depths, dtype=float).ravel()
        if depths.size == 0 or not np.all(np.isfinite(depths)) or np.any(depths <= 0.0):
            raise ValueError("depths must be a non-empty array of finite depths > 0 mm")
        self.depths = depths
        self.threads = int(threads)
        self.cache_kernels = bool(cache_kernels)
        self.kernel_cache_limit = None if kernel_cache_limit is None else int(kernel_cache_limit)
        self.planner_effort = planner_effort
        self._lattices: dict[tuple, LatticeConvolution | LineConvolution] = {}

    @property
    def kernel_cache_bytes(self) -> int:
        """Memory held by cached kernel spectra (bytes)."""
        return sum(lattice.cache_bytes for lattice in self._lattices.values())

    def _lattice(self, origin: tuple[float, float], counts: tuple[int, int]):
        """The convolution for field points origin + (iΔx, jΔy), (i, j) < counts: a line
        through the middle of a grid symmetric about it (the x–z or y–z plane) folds the
        grid across the line (``LineConvolution``); any other lattice is 2-D."""
        key = (origin, counts)
        if key not in self._lattices:
            grid, nu = self.grid, self.poisson_ratio
            options = (self.threads, self.planner_effort, self.cache_kernels)
            axis = line_axis(grid, origin, counts)
            if axis is not None:
                line = (axis, origin[axis], counts[axis])
                convolution = LineConvolution(grid, nu, *line, *options, None)
                limit = self.kernel_cache_limit
                if limit is not None:  # what the lattices built before left of it: all or none
                    left = max(limit - self.kernel_cache_bytes, 0)
                    whole = convolution.kernel_bytes(self.depths.size)
                    convolution.cache_limit = whole if whole <= left else 0
                self._lattices[key] = convolution
            else:
                self._lattices[key] = LatticeConvolution(grid, nu, origin, counts, *options)
        return self._lattices[key]

    def _tractions(self, pressure, traction_x, traction_y) -> dict[str, np.ndarray]:
        tractions = {}
        for load, values in zip(LOADS, (pressure, traction_x, traction_y), strict=True):
            if values is None:
                continue
            values = np.asarray(values, dtype=float)
            if values.shape != self.grid.shape:
                raise ValueError(f"{load} has shape {values.shape}, grid is {self.grid.shape}")
            if not np.all(np.isfinite(values)):
                raise ValueError(f"{load} contains NaN or infinite values")
            if np.any(values):
                tractions[load] = values
        return tractions

    def block(
        self,
        pressure,
        traction_x=None,
        traction_y=None,
        *,
        margin: float = 0.0,
        window: tuple[slice, slice] | None = None,
    ) -> StressField:
        """Stresses at every element centre of the grid and every depth.

        Tractions: arrays of the grid shape (MPa) or None for zero. Returns a ``StressField``
        of shape ``(n_x, n_y, n_z)``. With ``margin`` > 0 (mm) the block is extended on every
        side by ceil(margin/Δ) element pitches beyond the grid (zero traction there), e.g. to
        see the field outside a contact grid that barely covers the punch; the shape grows
        accordingly. ``window`` = (rows, columns), slices of element indices (step 1): only
        those element centres (e.g. the two rows beside the x–z plane), at the cost of a
        lattice that size; not combined with ``margin``.
        """
        grid = self.grid
        margin = float(margin)
        if not (math.isfinite(margin) and margin >= 0.0):
            raise ValueError(f"margin must be a finite length >= 0 mm, got {margin!r}")
        extra = [int(math.ceil(margin / step - 1e-9)) for step in (grid.dx, grid.dy)]
        origin = (grid.x[0] - extra[0] * grid.dx, grid.y[0] - extra[1] * grid.dy)
        counts = (grid.n_x + 2 * extra[0], grid.n_y + 2 * extra[1])
        if window is not None:
            if margin > 0.0:
                raise ValueError("block: give either margin or window, not both")
            ranges = [range(n)[part] for n, part in zip(grid.shape, window, strict=True)]
            if any(len(r) == 0 or r.step != 1 for r in ranges):
                raise ValueError(f"window must be two non-empty slices of step 1, got {window!r}")
            origin = (grid.x[ranges[0].start], grid.y[ranges[1].start])
            counts = (len(ranges[0]), len(ranges[1]))
        lattice = self._lattice((float(origin[0]), float(origin[1])), counts)
        components = lattice.evaluate(
            self.depths, self._tractions(pressure, traction_x, traction_y)
        )
        x = origin[0] + grid.dx * np.arange(counts[0])
        y = origin[1] + grid.dy * np.arange(counts[1])
        X, Y, Z = np.meshgrid(x, y, self.depths, indexing="ij")
        return StressField.from_components(X, Y, Z, components, depths=self.depths.copy())

    def rows_beside_axis(self, pressure, traction_x=None, traction_y=None) -> StressField | None:
        """Stresses at the element centres of the two rows beside the x–z plane (y = ±Δy/2,
        every x and depth) of a grid with an even number of rows; None for any other grid.

        The same points as ``block(window=…)`` on those rows, computed another way: a grid
        shifted by −Δy/2 and padded by one row of zero traction is symmetric about the row
        y = +Δy/2, which is then a line through its middle (``LineConvolution``, 1-D
        transforms along x, no 2-D field per layer); the row y = −Δy/2 is its mirror: the
        same line of the tractions reflected across y = 0 (τ_y changes sign), with σxy and
        σyz changing sign. The sums are those of the block in another order, equal to
        rounding (``ROWS_TOLERANCE``), in half the block's kernel memory. Returns a
        ``StressField`` of shape ``(n_x, 2, n_z)``, rows y = −Δy/2 and +Δy/2.
        """
        grid = self.grid
        if grid.is_line or grid.n_y % 2:
            return None
        tractions = self._tractions(pressure, traction_x, traction_y)
        padded = {}
        mirrored = {}
        for load, values in tractions.items():
            sign = kernel_parity(load, "xx")[1]  # τ_y is odd across y = 0
            padded[load] = np.zeros((grid.n_x, grid.n_y + 1))
            padded[load][:, : grid.n_y] = values
            mirrored[load] = np.zeros((grid.n_x, grid.n_y + 1))
            mirrored[load][:, : grid.n_y] = sign * values[:, ::-1]
        above, below = self._rows_line().evaluate_sets(self.depths, [padded, mirrored])
        components = {}
        for component in COMPONENTS:
            sign = kernel_parity("pressure", component)[1]  # σxy, σyz odd across y = 0
            rows = (sign * below[component][:, 0], above[component][:, 0])
            components[component] = np.stack(rows, axis=1)
        # the coordinates of block(window=…) on these rows, to the bit
        x = grid.x[0] + grid.dx * np.arange(grid.n_x)
        y = grid.y[grid.n_y // 2 - 1] + grid.dy * np.arange(2)
        X, Y, Z = np.meshgrid(x, y, self.depths, indexing="ij")
        return StressField.from_components(X, Y, Z, components, depths=self.depths.copy())

    def _rows_line(self) -> LineConvolution:
        """The line of ``rows_beside_axis``: y = +Δy/2 through the middle of the grid shifted
        by −Δy/2 and padded by one row. Its kernels are kept without limit, like the 2-D
        lattice of those rows (``block``), whose memory they halve."""
        key = ("rows beside the x–z plane",)
        if key not in self._lattices:
            grid = self.grid
            shifted = Grid(
                grid.n_x, grid.n_y + 1, grid.half_width_x, grid.half_width_y + grid.dy / 2
            )
            options = (self.threads, self.planner_effort, self.cache_kernels)
            self._lattices[key] = LineConvolution(
                shifted, self.poisson_ratio, 0, float(grid.x[0]), grid.n_x, *options, None
            )
        return self._lattices[key]

    def _plane(
        self, pressure, traction_x, traction_y, angle: float, half_length, bulk_stress
    ) -> StressField:
        """Stresses on the vertical plane through the punch axis at angle φ = ``angle`` (rad).

        The plane is sampled at s = kh, |s| <= ``half_length`` (default: to the edge of the
        grid), with h = 1/max(|cos φ|/Δx, |sin φ|/Δy), so that every sample sits on the
        lattice x = iΔx, y = jΔy through the axis whenever φ is a multiple of π/2 (or π/4 on
        a square grid); these lattice values are exact DC-FFT sums. Other samples are
        bilinear interpolations between the four neighbouring lattice points. The plane may
        extend beyond the grid (``half_length`` > half width): outside the grid the tractions
        are zero and the stresses are still exact there.

        Returns a ``StressField`` of shape ``(n_s, n_z)`` with ``s`` and ``angle`` set. No bulk
        stress (``bulk_stress`` must be None): that is a line contact's.
        """
        if bulk_stress is not None:
            raise ValueError("a bulk stress applies to line contacts only")
        s, fractional, half_counts, lattice = self._plane_lattice(angle, half_length)
        on_lattice = lattice.evaluate(
            self.depths, self._tractions(pressure, traction_x, traction_y)
        )
        indices = [f + h for f, h in zip(fractional, half_counts, strict=True)]
        components = {c: _bilinear(on_lattice[c], *indices) for c in COMPONENTS}
        cos, sin = math.cos(angle), math.sin(angle)
        S, Z = np.meshgrid(s, self.depths, indexing="ij")
        return StressField.from_components(
            S * cos, S * sin, Z, components, s=S, angle=float(angle), depths=self.depths.copy()
        )

    def _plane_lattice(self, angle: float, half_length):
        """The samples s (mm) of the plane at ``angle``, their fractional lattice indices
        about the axis, the lattice's half counts and its convolution (``_plane``)."""
        grid = self.grid
        cos, sin = math.cos(angle), math.sin(angle)
        step = 1.0 / max(abs(cos) / grid.dx, abs(sin) / grid.dy)
        if half_length is None:
            limits = [
                w / abs(c)
                for w, c in ((grid.half_width_x, cos), (grid.half_width_y, sin))
                if abs(c) > 1e-12
            ]
            half_length = min(limits)
        half_length = require_positive("half_length", half_length)
        count = int(math.floor(half_length / step + 1e-9))
        s = step * np.arange(-count, count + 1)
        fractional = [_snap(s * cos / grid.dx), _snap(s * sin / grid.dy)]
        half_counts = [int(math.ceil(np.max(np.abs(f)))) for f in fractional]
        origin = (-half_counts[0] * grid.dx, -half_counts[1] * grid.dy)
        counts = (2 * half_counts[0] + 1, 2 * half_counts[1] + 1)
        return s, fractional, half_counts, self._lattice(origin, counts)

    def prepare_plane(self, angle: float = 0.0, kernels: bool = True) -> None:
        """Build the plane's lattice and the kernel spectra its cache keeps: those of a
        line through the axis if all fit in ``kernel_cache_limit``, all of any other
        lattice. ``kernels=False``: a line's lattice and FFT plans only; it keeps its
        kernels from its second evaluation on (``LineConvolution``), so a plane evaluated
        once holds none."""
        lattice = self._plane_lattice(angle, None)[3]
        if isinstance(lattice, LineConvolution):
            if kernels:
                lattice.prepare(self.depths)
        else:
            ones = np.ones(self.grid.shape)
            self.plane(ones, ones, ones, angle=angle)


def _snap(values: np.ndarray) -> np.ndarray:
    """Round lattice coordinates that are integers up to rounding error."""
    nearest = np.round(values)
    return np.where(np.abs(values - nearest) < 1e-9, nearest, values)


def _bilinear(values: np.ndarray, fx: np.ndarray, fy: np.ndarray) -> np.ndarray:
    """Bilinear interpolation of ``values[i, j, :]`` at fractional indices (fx, fy) -> (n, n_z).

    Exact (no blending) at integer indices.
    """
    m_x, m_y = values.shape[:2]
    i0 = np.clip(np.floor(fx).astype(int), 0, max(m_x - 2, 0))
    j0 = np.clip(np.floor(fy).astype(int), 0, max(m_y - 2, 0))
    wx = (fx - i0)[:, None]
    wy = (fy - j0)[:, None]
    i1 = np.minimum(i0 + 1, m_x - 1)
    j1 = np.minimum(j0 + 1, m_y - 1)
    return (
        (1 - wx) * (1 - wy) * values[i0, j0]
        + wx * (1 - wy) * values[i1, j0]
        + (1 - wx) * wy * values[i0, j1]
        + wx * wy * values[i1, j1]
    )
