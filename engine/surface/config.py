"""The ``[surface]`` section of a study: roughness added to any punch profile.

Keys (``*`` required; units mm unless said):

``kind``*            ``"self_affine"`` (a random Gaussian surface, :mod:`.topography`) or
                     ``"file"`` (a measured height map, :mod:`.measured`)
self_affine:
``seed``             integer ≥ 0 [0]: the realisation (sweep it for statistics)
``hurst``            Hurst exponent H in (0, 1) [0.8]
``long_cutoff``*     roll-off wavelength λ_L (mm): the spectrum is flat above it
``short_cutoff``*    shortest wavelength λ_S (mm): nothing shorter; at least 2 elements
``rms_height``       rms height h_rms (mm, ≥ 0) — or ``rms_slope`` (1, ≥ 0): exactly one
file:
``path``*            ``.npy``, whitespace text (``.txt``, ``.dat``, ``.asc``, ``.csv``), or any
                     instrument format SurfaceTopography reads (``pip install -e
                     '.[topography]'``); a relative path is taken from the folder of
                     the study file (and recorded relative to it)
``pixel_size``*      spacing of the map's samples (mm), the same along x and y
``units``            unit of the heights: "m", "mm" ["mm"], "um", "nm"
``detrend``          "none", "mean" or "plane" ["plane"]: what is removed before resampling

Every key is sweepable: the numbers (``"surface.seed"``, ``"surface.rms_height"`` …) as lists
of numbers, the texts (``"surface.path"``, ``"surface.units"``, ``"surface.detrend"``,
``"surface.kind"``) as lists of strings, each value checked here as if it were written in the
section. A study sweeping ``surface.kind`` gives the keys of both kinds in ``[surface]``; each
case reads those of its kind. The checks
that need the mesh (a short cutoff below two elements, a map smaller than the mesh) and the
file's contents (missing, unreadable, NaN) are made here, while the study is parsed, so a bad
surface exits with status 2 before anything is written.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .measured import read_height_map

KINDS = ("self_affine", "file")
HEIGHT_UNITS = {"m": 1e3, "mm": 1.0, "um": 1e-3, "µm": 1e-3, "nm": 1e-6}
DETREND = ("none", "mean", "plane")
DEFAULT_HURST = 0.8
MAX_SEED = 2**32 - 1
MAX_SLOPE = 2.0  # rms slope: the half-space (Boussinesq) model assumes small slopes
MAX_LONG_CUTOFF = 100.0  # × the mesh's length: beyond it the spectrum on the mesh is flat
#: The ranges of the section's numbers, as the checks below read them and the manual's limits
#: table states them: key: (minimum, maximum, why), each end included unless named in
#: ``OPEN_ENDS``. A bound relative to the mesh is text: "2·half_width" (the mesh's length),
#: "4·half_width/n" (two elements of 2·half_width/n).
RANGES = {
    "seed": (0, MAX_SEED, "a 32-bit seed"),
    "hurst": (0.0, 1.0, "a self-affine surface's Hurst exponent"),
    "short_cutoff": (
        "4·half_width/n", "2·half_width",
        "two elements, the shortest wavelength the mesh carries; at most the mesh's length",
    ),
    "long_cutoff": (
        0.0, f"{MAX_LONG_CUTOFF:g} × 2·half_width",
        "beyond, the spectrum on the mesh is flat; and at least short_cutoff",
    ),
    "rms_height": (0.0, "2·half_width", "the mesh's length"),
    "rms_slope": (0.0, MAX_SLOPE, "a small-slope surface: the half-space model's assumption"),
    "pixel_size": (
        0.0, "2·half_width",
        "the mesh's length; and the map, samples × pixel_size along its shorter side, at least "
        "2·half_width: it covers the mesh",
    ),
}  # fmt: skip
OPEN_ENDS = {("hurst", "minimum"), ("hurst", "maximum"), ("long_cutoff", "minimum"),
             ("pixel_size", "minimum")}  # fmt: skip
SELF_AFFINE_KEYS = (
    "kind", "seed", "hurst", "long_cutoff", "short_cutoff", "rms_height", "rms_slope"
)  # fmt: skip
FILE_KEYS = ("kind", "path", "pixel_size", "units", "detrend")

__all__ = ["SurfaceConfig", "parse_surface", "KINDS"]


@dataclass(frozen=True)
class SurfaceConfig:
    """The ``[surface]`` section, validated (module docstring). Unused keys are None."""

    kind: str
    seed: int | None = None
    hurst: float | None = None
    long_cutoff: float | None = None
    short_cutoff: float | None = None
    rms_height: float | None = None
    rms_slope: float | None = None
    path: str | None = None  # absolute (engine.study.settings.reader.input_path)
    pixel_size: float | None = None
    units: str | None = None
    detrend: str | None = None

    def resolved(self) -> dict:
        """TOML-able: the keys that apply (None left out)."""
        return {k: v for k, v in self.__dict__.items() if v is not None}

    def identity(self) -> str | None:
        """SHA-256 of a measured map's file (None for a random surface): part of the study's
        fingerprint, so that a run does not resume on a map changed under the same name."""
        if self.kind != "file":
            return None

        return hashlib.sha256(Path(self.path).read_bytes()).hexdigest()


def parse_surface(s, mesh, is_line: bool, *, kind_swept: bool = False) -> SurfaceConfig:
    """Read ``[surface]`` (``s``: an ``engine.study.config.reader.Section``) for a study
    whose mesh is ``mesh`` (``n``, ``half_width``, mm) and whose contact is a line one or not
    (``kind_swept``: ``[sweep]`` varies ``surface.kind``, so the keys of the other kind are
    allowed and left for the cases of that kind); raises the reader's ``StudyConfigError``
    naming the key and the value."""
    s.check_known(set(SELF_AFFINE_KEYS) | set(FILE_KEYS))
    kind = s.string("kind")
    if kind not in KINDS:
        raise s.error("kind", kind, 'must be "self_affine" or "file"')
    element = 2.0 * mesh.half_width / mesh.n
    if not kind_swept:
        _only(s, kind, SELF_AFFINE_KEYS if kind == "self_affine" else FILE_KEYS)
    if kind == "self_affine":
        return _self_affine(s, element, mesh)
    return _file(s, mesh, is_line)


def _only(s, kind: str, keys: tuple[str, ...]) -> None:
    """Keys of the other kind name themselves."""
    for key in s.table:
        if key not in keys:
            raise s.error(key, s.table[key], f'not a key of kind = "{kind}"')


def _self_affine(s, element: float, mesh) -> SurfaceConfig:
    length = 2.0 * mesh.half_width
    low, high, why = RANGES["seed"]
    seed = s.integer("seed", 0, minimum=low, maximum=high, why=why)
    low, high, _ = RANGES["hurst"]
    hurst = s.number("hurst", DEFAULT_HURST, minimum=low, strict=True, maximum=high)
    if hurst >= high:
        raise s.error("hurst", s.table["hurst"], f"must lie in ({low:g}, {high:g})")
    short = s.number(
        "short_cutoff", minimum=0.0, strict=True, unit="mm", maximum=length,
        why="the mesh's length 2·half_width",
    )  # fmt: skip
    if short < 2.0 * element * (1.0 - 1e-12):
        raise s.error(
            "short_cutoff",
            s.table["short_cutoff"],
            f"must be at least two elements, 2 × {element:.6g} = {2 * element:.6g} mm "
            f"([mesh] n = {mesh.n}, half_width = {mesh.half_width:.6g} mm)",
        )
    long = s.number(
        "long_cutoff", minimum=0.0, strict=True, unit="mm", maximum=MAX_LONG_CUTOFF * length,
        why=f"{MAX_LONG_CUTOFF:g} × the mesh's length: beyond it the spectrum on the mesh is flat",
    )  # fmt: skip
    if long < short:
        raise s.error("long_cutoff", long, f"must be >= short_cutoff = {short:g} mm")
    given = [key for key in ("rms_height", "rms_slope") if key in s.table]
    if len(given) != 1:
        key = given[-1] if given else "rms_height"
        problem = "give exactly one of rms_height (mm) and rms_slope"
        if not given:
            s.raw(key)  # the reader's "required key is missing", naming rms_height
        raise s.error(key, s.table[key], problem)
    key = given[0]
    if key == "rms_height":
        value = s.number(key, minimum=0.0, unit="mm", maximum=length, why="the mesh's length")
    else:  # the half-space model is one of small slopes
        low, high, _ = RANGES["rms_slope"]
        value = s.number(key, minimum=low, maximum=high, why="a small-slope surface")
    return SurfaceConfig(
        kind="self_affine",
        seed=seed,
        hurst=hurst,
        long_cutoff=long,
        short_cutoff=short,
        **{key: value},
    )


def _file(s, mesh, is_line: bool) -> SurfaceConfig:
    given, path = s.input_file("path")  # relative to the study file's folder
    pixel = s.number(
        "pixel_size", minimum=0.0, strict=True, unit="mm", maximum=2.0 * mesh.half_width,
        why="the mesh's length 2·half_width",
    )  # fmt: skip
    units = s.string("units", "mm")
    if units not in HEIGHT_UNITS:
        raise s.error("units", units, "must be " + ", ".join(f'"{u}"' for u in HEIGHT_UNITS))
    detrend = s.string("detrend", "plane")
    if detrend not in DETREND:
        raise s.error("detrend", detrend, 'must be "none", "mean" or "plane"')
    try:
        heights = read_height_map(path)
    except (OSError, ValueError) as error:
        raise s.error("path", given, f"cannot read the height map {path}: {error}") from None
    if not np.isfinite(heights).all():
        bad = _first_bad(heights)
        raise s.error("path", given, f"the height map holds a NaN or inf at row, column {bad}")
    line_map = heights.ndim == 1 or 1 in heights.shape
    if is_line != line_map:
        what = "a profile (one row or column)" if is_line else "a 2-D map"
        raise s.error(
            "path",
            given,
            f"a {'line' if is_line else '3-D'} contact takes {what}, "
            f"got an array of shape {heights.shape}",
        )
    extent = (heights.size if line_map else min(heights.shape)) * pixel
    if extent < 2.0 * mesh.half_width * (1.0 - 1e-12):
        raise s.error(
            "pixel_size",
            s.table["pixel_size"],
            f"the map spans {extent:.6g} mm (shape {heights.shape}), less than the mesh "
            f"2·half_width = {2 * mesh.half_width:.6g} mm",
        )
    return SurfaceConfig(
        kind="file", path=str(path), pixel_size=pixel, units=units, detrend=detrend
    )


def _first_bad(heights):
    index = np.argwhere(~np.isfinite(np.atleast_2d(heights)))[0]
    return f"{int(index[0]) + 1}, {int(index[1]) + 1}"
