"""Where the von Mises peak sits: per-cycle peak history and its classification.

After every simulated cycle the peak-load tractions give the stresses on the x–z plane
through the punch axis (Eq. 16 by DC-FFT, von Mises Eq. 21; :mod:`.subsurface`). From that
plane :class:`PeakTracker` extracts, per cycle,

- ``vm_max`` — the maximum over the whole plane (surface layer included), at (x, z);
- ``vm_sub_max`` — the maximum below the surface layer, z >= depths[1];
- ``vm_deep_max`` — the maximum at depth z >= ``DEEP_DEPTH_FRACTION``·a0 = 0.1 a0, i.e. away
  from the surface edge singularity of the flat punch (Eq. 17), where the paper's μ = 0.1
  peak (r = 0, z ≈ 0.7 a0, Fig. 8b) would be;
- ``vm_axis_max`` — the maximum on the punch axis r = 0, at depth z;
- ``contact_radius`` a = √(A_c/π), A_c the area of the elements with p > 0 (area-equivalent
  radius; a = a0 for the intact flat punch up to the staircase edge);
- ``centre_pressure`` — the pressure at the axis (mean of the elements nearest to it: four
  for an even mesh);
- ``peak_region`` and ``deep_region`` — where the largest σ_VM sits, over all depths and at
  z >= 0.1 a0 (codes of ``REGIONS``), classified on the element centres beside the plane
  (below).

Which stresses decide the region. The plane's points lie at x = kΔ, y = 0: on an even mesh,
element corners, where the piecewise-constant tractions jump. Just below the surface the
stress there has the logarithmic singularity of that jump (its value grows without bound as
the surface layer approaches z = 0 and depends on the mesh); once the worn centre carries the
load, that artefact on the axis outgrows every real peak (worn 32² state,
docs/explanation/peak-regime.md: 1.46 p0 on the plane's surface layer against 0.74 p0 at the
nearest element centre).
So the regions are classified on the element centres next to the plane — the elements whose
centres lie within half an element of it (the rows y = ±Δ/2 of the x–z plane on an even
mesh, the row y = 0 on an odd one) — at every depth, where the tractions are continuous
around each point and the surface value is finite. The real singularities (the square-root
edge of the intact punch, the step of a worn profile) still show there, at their own
elements. ``vm_max`` and the other peaks stay those of the plane (as before); their
location may therefore differ from the region's. Beside the x–z plane of an even mesh those
centres are taken by 1-D transforms along x (:meth:`SubsurfaceStress.rows_beside_axis`,
half the memory and time of their 2-D lattice), which equal the lattice's values to
rounding; a region stands only when every centre within twice the rounding bound
(``ROWS_TOLERANCE``) of the maximum has it, so it is the word of the lattice's own maximum,
and otherwise the lattice decides: the regions are those of the lattice, bit for bit.

Classification (:func:`classify_peak`), with r the distance of the peak from the punch axis
and a the current contact radius:

- *axis* if r/a < ``AXIS_RADIUS_FRACTION`` = 0.5, else *edge*. The two loci a worn flat
  punch produces are the contact edge (r ≈ a: the square-root pressure singularity of the
  intact punch, Eq. 17, and the slip/stick boundary on the surface) and the axis (r = 0: the
  maximum shear under a uniform or centre-peaked pressure, z ≈ 0.48 a for Hertz and ≈ 0.64 a
  for a uniform disc, Johnson 1985 §3.4). r = a/2 is halfway between; it is 8 elements from
  either at 32² and keeps a load-carrying stick island (radius ≈ 0.22 a0 at μ = 0.1, stick
  fraction 0.05) on the axis side.
- *surface* if z/a < ``SURFACE_DEPTH_FRACTION`` = 0.1, else *subsurface*. The edge
  singularity decays within a few elements of the surface (0.1 a is 1.6 elements at 32², 3.2
  at 64²), while the subsurface maxima of smooth pressures sit at z ≈ 0.5–0.7 a; 0.1 a is far
  from both; the "deep" peak is sought below the same depth (``DEEP_DEPTH_FRACTION``).

Units: lengths mm, stresses MPa (tension positive, z into the half-space).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..grid import Grid
from ..schema import (
    AXIS_RADIUS_FRACTION,
    DEEP_DEPTH_FRACTION,
    PEAK_HISTORY_DESCRIPTIONS,
    PEAK_HISTORY_UNITS,
    REGIONS,
    SURFACE_DEPTH_FRACTION,
)
from .subsurface import StressField, SubsurfaceStress

__all__ = [
    "AXIS_RADIUS_FRACTION",
    "SURFACE_DEPTH_FRACTION",
    "DEEP_DEPTH_FRACTION",
    "REGIONS",
    "PEAK_HISTORY_UNITS",
    "PEAK_HISTORY_DESCRIPTIONS",
    "classify_peak",
    "region_code",
    "region_name",
    "first_region_change",
    "PeakTracker",
]

# The region codes and thresholds are part of the results (the stored ``peak_region`` codes
# mean them), so they and the history units and descriptions live in the schema.


def classify_peak(x: float, z: float, contact_radius: float) -> str:
    """Region word of a peak at horizontal distance |x| (mm) from the axis and depth z (mm).

    ``axis`` when |x|/a < AXIS_RADIUS_FRACTION, else ``edge``; ``surface`` when
    z/a < SURFACE_DEPTH_FRACTION, else ``subsurface``; a = ``contact_radius`` (mm, > 0).
    """
    if not (math.isfinite(contact_radius) and contact_radius > 0.0):
        raise ValueError(f"contact_radius must be a finite length > 0 mm, got {contact_radius!r}")
    side = "axis" if abs(x) / contact_radius < AXIS_RADIUS_FRACTION else "edge"
    depth = "surface" if z / contact_radius < SURFACE_DEPTH_FRACTION else "subsurface"
    return f"{side}-{depth}"


def region_code(name: str) -> int:
    """Integer code of a region word (index in ``REGIONS``), as stored in ``history/``."""
    return REGIONS.index(name)


def region_name(code: float) -> str:
    """Region word of an integer code; '' for NaN (no classification)."""
    if code is None or (isinstance(code, float) and math.isnan(code)):
        return ""
    return REGIONS[int(code)]


def first_region_change(cycles, codes) -> int | None:
    """Real cycle N of the first history row whose region differs from the first row's.

    With cycle jumping the change happened after the previous simulated cycle and by this
    one. ``None`` when the region never changes (or the history is empty).
    """
    codes = np.asarray(codes, dtype=float)
    cycles = np.asarray(cycles)
    if codes.size == 0:
        return None
    changed = np.flatnonzero(codes != codes[0])
    return int(cycles[changed[0]]) if changed.size else None


@dataclass(frozen=True)
class _PlaneMaximum:
    value: float
    x: float
    z: float
    y: float = 0.0
    s: float = 0.0  # signed distance along the plane (= x on the x–z plane)


def _maximum(plane: StressField, mask: np.ndarray) -> _PlaneMaximum:
    candidates = np.where(mask, plane.von_mises, -np.inf)
    index = np.unravel_index(np.argmax(candidates), candidates.shape)
    along = plane.x if plane.s is None else plane.s
    return _PlaneMaximum(
        float(plane.von_mises[index]),
        float(plane.x[index]),
        float(plane.z[index]),
        float(plane.y[index]),
        float(along[index]),
    )


ROWS_TOLERANCE = 1e-8
"""Bound, relative to the largest stress component of the rows, on the difference between
the stresses of the rows beside the x–z plane taken by lines and by the 2-D lattice
(``SubsurfaceStress.rows_beside_axis`` against ``block``): both are exact DC-FFT sums in
another order, measured to differ by at most 3e-15 of it (cyclic 32² and 64² cases), so the
bound holds with a margin of over a million."""

_MAX_CANDIDATES = 64  # more points that close to the maximum: the lattice decides


def _rounding_bound(field: StressField) -> float:
    """Bound (MPa) on |σ_VM − σ_VM'| between the rows taken by lines and by the lattice: σ_VM
    is a seminorm of the stress, and a difference of at most δ in every component moves it
    by at most √15 δ, δ = ``ROWS_TOLERANCE`` · max |σ_ij| (MPa)."""
    largest = max(float(np.max(np.abs(values))) for values in field.components.values())
    return math.sqrt(15.0) * ROWS_TOLERANCE * largest


def _certain_word(field: StressField, mask: np.ndarray, radius: float, bound: float):
    """The region word of the maximum of σ_VM over ``mask`` if every point within 2·``bound``
    (MPa) of it has the same word (then the maximum of values within ``bound`` of these has
    it too); None if not, or if there are more than ``_MAX_CANDIDATES`` such points."""
    values = np.where(mask, field.von_mises, -np.inf)
    top = float(np.max(values))
    if not math.isfinite(top):
        return None
    candidates = np.flatnonzero(values >= top - 2.0 * bound)
    if candidates.size > _MAX_CANDIDATES:
        return None
    x, y, z = (np.ravel(coordinate)[candidates] for coordinate in (field.x, field.y, field.z))
    words = {
        classify_peak(math.hypot(float(a), float(b)), float(c), radius)
        for a, b, c in zip(x, y, z, strict=True)
    }
    return words.pop() if len(words) == 1 else None


def _centre_band(grid: Grid, angle: float) -> tuple[tuple[slice, slice], np.ndarray]:
    """The elements whose centres lie within half an element of the vertical plane through
    the axis at ``angle`` (rad): the (rows, columns) window of the grid holding them, and
    the mask of those elements within the window."""
    sin, cos = math.sin(angle), math.cos(angle)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    reach = 0.5 * (abs(sin) * grid.dx + abs(cos) * grid.dy) * (1.0 + 1e-9)
    band = np.abs(y * cos - x * sin) <= reach
    rows, columns = np.flatnonzero(band.any(axis=1)), np.flatnonzero(band.any(axis=0))
    window = (slice(rows[0], rows[-1] + 1), slice(columns[0], columns[-1] + 1))
    return window, band[window]


class PeakTracker:
    """Peak-load von Mises peaks on the x–z plane, one call per simulated cycle.

    ``stress``: the case's :class:`SubsurfaceStress` (its kernel spectra are cached, so after
    the first call a cycle costs six inverse FFTs per depth layer of the plane lattice);
    ``punch_radius`` a0 (mm). Calling ``tracker(pressure, traction_x, traction_y)`` (MPa, grid
    shape) returns the history values of ``PEAK_HISTORY_UNITS`` (floats; ``peak_region`` as
    its code) and keeps the plane in ``last_plane``.

    ``angle`` (rad, default 0: the x–z plane): the vertical plane through the axis at φ from x
    instead (a fretting case's sliding direction). The axis column then uses the distance
    along the plane |s| (the regions: the element centres within half an element of that
    plane); the ``_x`` values stay Cartesian x, and the values gain ``vm_max_y``,
    ``vm_sub_max_y``, ``vm_deep_max_y`` (mm) — only when φ ≠ 0, so the x–z results are
    unchanged. The element centres beside an oblique plane are a second 2-D lattice (every
    depth), which costs about as much as the plane (11 ms against 12 ms CPU per cycle at
    32², 31 layers); beside the x–z plane they are taken by lines (module docstring).
    """

    def __init__(self, stress: SubsurfaceStress, punch_radius: float, angle: float = 0.0):
        self.stress = stress
        self.punch_radius = float(punch_radius)
        self.angle = float(angle)
        depths = np.sort(stress.depths)
        self.subsurface_depth = float(depths[1]) if depths.size > 1 else float(depths[0])
        self.deep_depth = DEEP_DEPTH_FRACTION * self.punch_radius
        if depths[-1] < self.deep_depth:
            raise ValueError(
                f"the deepest layer ({depths[-1]:g} mm) is above {DEEP_DEPTH_FRACTION:g} a0 "
                f"= {self.deep_depth:g} mm; no deep peak can be found"
            )
        grid: Grid = stress.grid
        distance = np.hypot(*np.meshgrid(grid.x, grid.y, indexing="ij"))
        self._centre = distance <= distance.min() * (1.0 + 1e-9) + 1e-12
        self._element_area = grid.element_area
        # a line contact's plane (LineSubsurfaceStress, no block) is its row of element
        # centres already: the plane itself decides the regions there
        self._centres = _centre_band(grid, self.angle) if hasattr(stress, "block") else None
        if self._centres is not None and self.angle == 0.0:
            # evaluated every cycle: the x–z plane keeps its kernels from the first on
            stress.prepare_plane(0.0)
        # the x–z plane of an even grid: its band is the two whole rows y = ±Δy/2, which
        # the stresses can give by lines (regions)
        self._rows = (
            self._centres is not None
            and self.angle == 0.0
            and hasattr(stress, "rows_beside_axis")
            and grid.n_y % 2 == 0
            and bool(self._centres[1].all())
            and self._centres[0]
            == (slice(0, grid.n_x), slice(grid.n_y // 2 - 1, grid.n_y // 2 + 1))
        )
        self.last_plane: StressField | None = None

    def contact_radius(self, pressure: np.ndarray) -> float:
        """Area-equivalent contact radius √(A_c/π) (mm), A_c = area of elements with p > 0."""
        area = np.count_nonzero(np.asarray(pressure) > 0.0) * self._element_area
        return math.sqrt(area / math.pi)

    def centre_pressure(self, pressure: np.ndarray) -> float:
        """Mean pressure (MPa) of the elements nearest to the punch axis."""
        return float(np.asarray(pressure)[self._centre].mean())

    def regions(self, pressure, traction_x, traction_y, radius: float) -> tuple[str, str]:
        """Region words of the largest σ_VM over all depths and at z >= 0.1 a0, both taken
        at the element centres beside the plane (module docstring), for contact radius
        ``radius`` (mm). A line contact's plane (a stress object without ``block``) is its
        row of element centres: there the last plane decides.

        Beside the x–z plane of an even grid the two rows of centres are first taken by 1-D
        transforms (``SubsurfaceStress.rows_beside_axis``), equal to the 2-D lattice's
        values to rounding; a word stands when every point within twice that rounding
        bound of the maximum (``ROWS_TOLERANCE``) has it, so it is the word of the lattice's
        own maximum; otherwise the lattice decides, as for every other plane."""
        if self._centres is None:
            centres = self.last_plane
            band = np.ones(centres.z.shape, dtype=bool)
            return self._words(centres, band, radius)
        if self._rows:
            rows = self.stress.rows_beside_axis(pressure, traction_x, traction_y)
            bound = _rounding_bound(rows)
            band = np.ones(rows.z.shape, dtype=bool)
            words = [
                _certain_word(rows, mask, radius, bound)
                for mask in (band, rows.z >= self.deep_depth)
            ]
            if None not in words:
                return words[0], words[1]
        window, band = self._centres
        centres = self.stress.block(pressure, traction_x, traction_y, window=window)
        band = np.broadcast_to(band[..., None], centres.z.shape)
        return self._words(centres, band, radius)

    def _words(self, centres: StressField, band: np.ndarray, radius: float) -> tuple[str, str]:
        """Region words of the maxima of ``centres`` over ``band`` and over its part at
        z >= 0.1 a0."""
        words = []
        for mask in (band, band & (centres.z >= self.deep_depth)):
            peak = _maximum(centres, mask)
            words.append(classify_peak(math.hypot(peak.x, peak.y), peak.z, radius))
        return words[0], words[1]

    def __call__(self, pressure, traction_x=None, traction_y=None) -> dict[str, float]:
        plane = self.stress.plane(pressure, traction_x, traction_y, angle=self.angle)
        self.last_plane = plane
        overall = _maximum(plane, np.ones(plane.z.shape, dtype=bool))
        below = _maximum(plane, plane.z >= self.subsurface_depth)
        deep = _maximum(plane, plane.z >= self.deep_depth)
        along = plane.x if plane.s is None else plane.s  # s = x on the x–z plane
        axis_column = np.abs(along) == np.abs(along).min()
        axis = _maximum(plane, axis_column)
        radius = self.contact_radius(pressure)
        region = deep_region = None
        if radius > 0.0:
            region, deep_region = self.regions(pressure, traction_x, traction_y, radius)
        locations = {}
        if self.angle != 0.0:
            locations = {
                "vm_max_y": overall.y,
                "vm_sub_max_y": below.y,
                "vm_deep_max_y": deep.y,
            }
        return {
            "vm_max": overall.value,
            "vm_max_x": overall.x,
            "vm_max_z": overall.z,
            "vm_sub_max": below.value,
            "vm_sub_max_x": below.x,
            "vm_sub_max_z": below.z,
            "vm_deep_max": deep.value,
            "vm_deep_max_x": deep.x,
            "vm_deep_max_z": deep.z,
            "vm_axis_max": axis.value,
            "vm_axis_max_z": axis.z,
            "contact_radius": radius,
            "centre_pressure": self.centre_pressure(pressure),
            "peak_region": math.nan if region is None else float(region_code(region)),
            "deep_region": math.nan if deep_region is None else float(region_code(deep_region)),
        } | locations
