"""Study file (TOML) -> frozen, validated configuration.

The study file is parsed once with :mod:`tomllib` and checked once; every later layer receives
the frozen :class:`StudyConfig` and never looks at the TOML again. Every error is a
:class:`StudyConfigError` whose message names the file, the key and the offending value, e.g.::

    studies/demo.toml: [loading] load = -750: must be > 0 (N)

Units are those of the paper (Juliá & Rodríguez-Tembleque 2023, Section 7): mm, N, MPa,
wear coefficients in 1/MPa, angles in degrees.

Sections and keys (``*`` = required; defaults in brackets):

``[study]``       name*, output* (path of the .h5 file, relative to the working directory;
                  the summary is written beside it as .csv), output_strategy ["auto"]
                  ("single": rank 0 writes; "mpio": every rank writes its cases through
                  parallel HDF5; "auto": mpio when h5py is MPI-enabled and ranks > 1)
``[material]``    E_A*, nu_A* (half-space), E_B*, nu_B* (punch)                          MPa
``[punch]``       shape ["flat"] ("flat" | "rounded" | "sphere"), radius* (flat: punch radius;
                  rounded: radius of the flat face; sphere: sphere radius), edge_radius*
                  (rounded only: toroidal edge radius, >= 0; 0 is the sharp flat punch)  mm
``[mesh]``        n* (elements per side), half_width [flat: 1.05·radius; rounded:
                  1.05·(radius + edge_radius); sphere: HERTZ_MARGIN·a_Hertz at the load] mm
``[loading]``     kind* ("static" | "cyclic" | "fretting"), load* (N), steps [10] (increments
                  per half cycle; for static: load increments; fretting: per quarter
                  tangential cycle and of the normal loading), cycles* (cyclic, fretting),
                  record [[cycles]] (cycles at which fields and stresses are stored, 0 =
                  unworn; cyclic, fretting),
                  max_wear_fraction [0.004] (cycle-jump control: wear per jump over the
                  peak elastic approach; cyclic, fretting);
                  fretting only: amplitude (mm, rigid tangential displacement) XOR
                  force_amplitude (N, tangential force), direction [0] (degrees from x)
                  (engine.solvers.fretting)
``[wear]``        law ["archard"] ("archard": Eq. 12–14 with [sweep] wear1/wear2 in 1/MPa;
                  "energy": depth = alpha × local frictional work, [sweep] alpha in mm³/J)
``[subsurface]``  depth [1.5] (in punch radii; sphere: in Hertz contact radii), layers [16]
``[sweep]``       mu1*, mu2 [mu1], wear1* (cyclic; [0] for static), wear2 [wear1] or
                  "proportional" (wear1·mu2/mu1, Section 7.3), beta [0] (degrees);
                  alpha* (mm³/J) instead of wear1/wear2 with [wear] law = "energy".
                  Each is a list (a single number is accepted); every combination is a case.
                  Any scalar of the other sections is a sweep axis under its quoted dotted
                  key (SWEEPABLE), e.g. "loading.load" = [500.0, 750.0]; swept keys must
                  not also be set in their own section. zip = [["loading.load",
                  "mesh.n"], ...] makes the keys of each group vary together (equal list
                  lengths) instead of forming their product. See engine.study.plan.
``[solver]``      tol [1e-8 static, 1e-6 cyclic], maxiter [20000] (iterations per
                  increment), threads [1]
                  (FFT threads per rank), fft_planner ["estimate"] ("estimate": the same FFTW
                  plans in every process, so runs and rank counts give bit-identical results;
                  "measure": timed plans, faster, may differ in the last digits)
``[testing]``     fail_cases [[]]: case ids that raise on purpose (fault-injection tests)
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from engine.solvers import defaults

__all__ = [
    "StudyConfigError",
    "StudyConfig",
    "StudyInfo",
    "MaterialConfig",
    "PunchConfig",
    "MeshConfig",
    "LoadingConfig",
    "SubsurfaceConfig",
    "SweepConfig",
    "SolverConfig",
    "TestingConfig",
    "load_study",
    "parse_study",
    "PROPORTIONAL",
    "PUNCH_SHAPES",
    "SWEEPABLE",
    "SweepAxis",
]

PROPORTIONAL = "proportional"
PUNCH_SHAPES = ("flat", "rounded", "sphere")
HERTZ_MARGIN = 1.5  # default sphere mesh half-width / Hertz contact radius at the load

# Scalars that [sweep] accepts under their dotted key, with their units (summary columns).
SWEEPABLE = {
    "material.E_A": "MPa",
    "material.nu_A": "1",
    "material.E_B": "MPa",
    "material.nu_B": "1",
    "punch.radius": "mm",
    "punch.edge_radius": "mm",
    "mesh.n": "1",
    "mesh.half_width": "mm",
    "loading.load": "N",
    "loading.steps": "1",
    "loading.cycles": "1",
    "loading.max_wear_fraction": "1",
    "loading.amplitude": "mm",
    "loading.force_amplitude": "N",
    "loading.direction": "degree",
    "subsurface.depth": "punch radii",
    "subsurface.layers": "1",
    "solver.tol": "1",
    "solver.maxiter": "1",
}


class StudyConfigError(ValueError):
    """Bad study file: carries the file, the dotted key and the value it refers to."""

    def __init__(self, source: str, key: str, value: Any, problem: str) -> None:
        self.source = source
        self.key = key
        self.value = value
        self.problem = problem
        section, _, name = key.partition(".")
        where = f"[{section}] {name}" if name else f"[{section}]"
        shown = "" if value is _MISSING else f" = {value!r}"
        super().__init__(f"{source}: {where}{shown}: {problem}")


_MISSING = object()


@dataclass(frozen=True)
class StudyInfo:
    name: str
    output: Path
    output_strategy: str = "auto"

    @property
    def summary_path(self) -> Path:
        return self.output.with_suffix(".csv")

    @property
    def checkpoint_dir(self) -> Path:
        return self.output.with_name(self.output.name + ".checkpoints")


@dataclass(frozen=True)
class MaterialConfig:
    E_A: float
    nu_A: float
    E_B: float
    nu_B: float


@dataclass(frozen=True)
class PunchConfig:
    radius: float
    shape: str = "flat"
    edge_radius: float | None = None  # rounded only

    def profile(self):
        """The :mod:`engine.geometry` profile of this punch."""
        from engine.geometry import FlatPunch, RoundedPunch, SphericalPunch

        if self.shape == "rounded":
            return RoundedPunch(self.radius, self.edge_radius or 0.0)
        if self.shape == "sphere":
            return SphericalPunch(self.radius)
        return FlatPunch(self.radius)


@dataclass(frozen=True)
class MeshConfig:
    n: int
    half_width: float


@dataclass(frozen=True)
class LoadingConfig:
    kind: str
    load: float
    steps: int
    cycles: int
    record: tuple[int, ...]
    max_wear_fraction: float | None  # None for static loading (no cycle jumps)
    # fretting only (None otherwise): exactly one of amplitude (mm) and force_amplitude (N);
    # direction in degrees from x (engine.solvers.fretting)
    amplitude: float | None = None
    force_amplitude: float | None = None
    direction: float | None = None


@dataclass(frozen=True)
class WearConfig:
    """``law``: "archard" (the paper's orthotropic law, Eq. 12–14, coefficients wear1/wear2
    in 1/MPa) or "energy" (dissipated-energy law, coefficient alpha in mm³/J)."""

    law: str = "archard"


@dataclass(frozen=True)
class SubsurfaceConfig:
    depth: float
    layers: int


@dataclass(frozen=True)
class SweepAxis:
    """One axis of the product: a single dotted key, or a zip group of keys varying together.
    ``values[i]`` holds one value per key at list position i."""

    keys: tuple[str, ...]
    values: tuple[tuple[float | int, ...], ...]

    def __len__(self) -> int:
        return len(self.values)


@dataclass(frozen=True)
class SweepConfig:
    mu1: tuple[float, ...]
    mu2: tuple[float, ...] | None
    wear1: tuple[float, ...]
    wear2: tuple[float, ...] | str | None
    beta: tuple[float, ...]
    axes: tuple[SweepAxis, ...] = ()
    alpha: tuple[float, ...] | None = None  # energy wear law only (mm³/J)

    @property
    def swept_keys(self) -> tuple[str, ...]:
        """Dotted keys of the other sections swept here, in axis order."""
        return tuple(key for axis in self.axes for key in axis.keys)

    def resolved(self) -> dict[str, Any]:
        """TOML-able: the friction/wear lists, then every dotted key, then the zip groups."""
        out: dict[str, Any] = {}
        for name in ("mu1", "mu2", "wear1", "wear2", "beta", "alpha"):
            value = getattr(self, name)
            if value is not None:
                out[name] = list(value) if isinstance(value, tuple) else value
        for axis in self.axes:
            for position, key in enumerate(axis.keys):
                out[key] = [values[position] for values in axis.values]
        groups = [list(axis.keys) for axis in self.axes if len(axis.keys) > 1]
        if groups:
            out["zip"] = groups
        return out


@dataclass(frozen=True)
class SolverConfig:
    tol: float
    maxiter: int
    threads: int
    fft_planner: str = "estimate"

    @property
    def planner_effort(self) -> str:
        """FFTW planner flag: "estimate" gives the same plan (bit-identical results) in every
        process and run; "measure" times candidate plans (faster, last-digit differences)."""
        return "FFTW_" + self.fft_planner.upper()


@dataclass(frozen=True)
class TestingConfig:
    fail_cases: tuple[str, ...]


@dataclass(frozen=True)
class StudyConfig:
    """The whole study, validated. ``source`` is the study file it came from."""

    source: str
    study: StudyInfo
    material: MaterialConfig
    punch: PunchConfig
    mesh: MeshConfig
    loading: LoadingConfig
    subsurface: SubsurfaceConfig
    sweep: SweepConfig
    solver: SolverConfig
    testing: TestingConfig
    wear: WearConfig = WearConfig()
    search: Any = None  # the [search] section (engine.study.search.SearchSpec) or None
    # The parsed TOML tables (JSON text, swept keys absent) from which for_case() derives a
    # case's configuration, and the dotted keys whose default derives from other keys.
    raw: str = dataclasses.field(default="", repr=False, compare=False)
    derived_defaults: tuple[str, ...] = ()

    @property
    def is_cyclic(self) -> bool:
        """True for the kinds with load cycles, wear and cycle jumping (cyclic, fretting)."""
        return self.loading.kind in ("cyclic", "fretting")

    @property
    def is_fretting(self) -> bool:
        return self.loading.kind == "fretting"

    @property
    def contact_length(self) -> float:
        """a0 (mm), the length unit of ``[subsurface] depth`` and of the summary's p0: the
        punch radius (rounded: of the flat face) or, for a sphere, Hertz's contact radius
        at the peak load."""
        if self.punch.shape == "sphere":
            from engine.reference.hertz import hertz_contact_radius

            return hertz_contact_radius(
                self.loading.load, self.punch.radius, _contact_modulus(self.material)
            )
        return self.punch.radius

    def for_case(self, settings: tuple[tuple[str, Any], ...] | dict[str, Any]) -> StudyConfig:
        """The configuration of one case: the swept ``settings`` ({dotted key: value})
        substituted into the study file and validated again (derived defaults such as
        ``mesh.half_width`` follow the swept values). Without settings: ``self``."""
        settings = dict(settings)
        if not settings:
            return self
        data = json.loads(self.raw)
        for key, value in settings.items():
            section, name = key.split(".", 1)
            data.setdefault(section, {})[name] = value
        case = _parse_tables(data, self.source)
        return dataclasses.replace(
            case, study=self.study, sweep=self.sweep, raw=self.raw, search=self.search
        )

    def resolved(self) -> dict[str, dict[str, Any]]:
        """The configuration with every default filled in, as plain TOML-able data."""
        out: dict[str, dict[str, Any]] = {}
        swept = set(self.sweep.swept_keys)
        if self.search is not None:  # searched like a swept key: its value is each case's
            swept.add(self.search.parameter)
        if swept:  # defaults computed from swept keys belong to each case, not to the study
            swept |= set(self.derived_defaults)
        for field in dataclasses.fields(self):
            if field.name in ("source", "raw", "derived_defaults"):
                continue
            if field.name == "sweep":
                out["sweep"] = self.sweep.resolved()
                continue
            if field.name == "wear" and self.wear == WearConfig():
                continue  # the default law, left out so that older results files resume
            if field.name == "search":
                if self.search is not None:
                    out["search"] = dataclasses.asdict(self.search)
                continue
            section = {}
            for key, value in dataclasses.asdict(getattr(self, field.name)).items():
                if value is None or f"{field.name}.{key}" in swept:
                    continue  # TOML has no null: None is "not applicable" (static loading)
                if field.name == "punch" and key == "shape" and value == "flat":
                    continue  # the default, left out so that older results files resume
                if field.name == "loading" and key in STATIC_PLACEHOLDERS and not self.is_cyclic:
                    continue  # no cycles in a static study (older files: fill_former_defaults)
                if isinstance(value, Path):
                    value = str(value)
                if isinstance(value, tuple):
                    value = list(value)
                section[key] = value
            out[field.name] = section
        return out

    def to_toml(self) -> str:
        """Resolved study as TOML text (stored in the results file)."""
        return dump_toml(self.resolved())

    def to_json(self) -> str:
        return json.dumps(self.resolved(), sort_keys=True)

    def fingerprint(self) -> str:
        """Everything that changes the result of a case (not the output path, not testing).

        A results file made with a different fingerprint cannot be resumed.
        """
        resolved = self.resolved()
        resolved.pop("study")
        resolved.pop("testing")
        resolved.pop("sweep")
        resolved["solver"].pop("threads", None)
        if self.sweep.swept_keys:  # which keys vary is part of the study's identity
            resolved["swept_keys"] = sorted(self.sweep.swept_keys)
        return json.dumps(resolved, sort_keys=True)


# Settings that results files written before every default was resolved (issue 14.4) left out
# when they held the solver's default then: such a file ran with exactly these values (they
# are history, not today's defaults).
FORMER_DEFAULTS = {("solver", "maxiter"): 20000, ("loading", "max_wear_fraction"): 0.004}


# What results files of static studies stored for the cyclic keys before they were left out
# (a stored static study then did not parse back: the parser refuses cycles in static loading).
STATIC_PLACEHOLDERS = {"cycles": 0, "record": []}


def fill_former_defaults(stored: dict[str, Any], current: dict[str, Any]) -> None:
    """Give a stored resolved study (or fingerprint data) the former defaults it left out,
    and take out the static placeholders it held (``STATIC_PLACEHOLDERS``), in place, where
    ``current`` does the same: results files of earlier versions resume."""
    for (section, key), value in FORMER_DEFAULTS.items():
        table = stored.get(section)
        if isinstance(table, dict) and key not in table and key in current.get(section, {}):
            table[key] = value
    loading, now = stored.get("loading"), current.get("loading", {})
    if isinstance(loading, dict) and loading.get("kind") == "static":
        for key, value in STATIC_PLACEHOLDERS.items():
            if key in loading and loading[key] == value and key not in now:
                del loading[key]


def same_fingerprint(stored: str | None, current: str) -> bool:
    """Whether a results file's ``stored`` fingerprint is the study's ``current`` one, the
    former defaults filled in (``fill_former_defaults``)."""
    if stored == current:
        return True
    try:
        old, new = json.loads(stored), json.loads(current)
    except (TypeError, ValueError):
        return False
    fill_former_defaults(old, new)
    return json.dumps(old, sort_keys=True) == json.dumps(new, sort_keys=True)


# --------------------------------------------------------------------------------------------
# Parsing helpers: each takes the section dict, the key and the source for error messages.


class _Section:
    """Reads keys of one TOML table and remembers which ones were used."""

    def __init__(self, source: str, name: str, table: Any) -> None:
        if not isinstance(table, dict):
            raise StudyConfigError(source, name, table, "must be a table ([section])")
        self.source, self.name, self.table = source, name, table

    def error(self, key: str, value: Any, problem: str) -> StudyConfigError:
        return StudyConfigError(self.source, f"{self.name}.{key}", value, problem)

    def raw(self, key: str, default: Any = _MISSING) -> Any:
        if key in self.table:
            return self.table[key]
        if default is _MISSING:
            raise self.error(key, _MISSING, "required key is missing")
        return default

    def check_known(self, keys: set[str]) -> None:
        for key in self.table:
            if key not in keys:
                raise self.error(
                    key, self.table[key], f"unknown key (known: {', '.join(sorted(keys))})"
                )

    def number(
        self,
        key: str,
        default: Any = _MISSING,
        *,
        minimum: float | None = None,
        strict: bool = False,
        unit: str = "",
    ) -> float:
        value = self.raw(key, default)
        return self._check_number(key, value, minimum=minimum, strict=strict, unit=unit)

    def _check_number(
        self, key: str, value: Any, *, minimum: float | None, strict: bool, unit: str
    ) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(key, value, "must be a number")
        if not math.isfinite(value):
            raise self.error(key, value, "must be finite")
        suffix = f" ({unit})" if unit else ""
        if minimum is not None:
            if strict and not value > minimum:
                raise self.error(key, value, f"must be > {minimum:g}{suffix}")
            if not strict and not value >= minimum:
                raise self.error(key, value, f"must be >= {minimum:g}{suffix}")
        return float(value)

    def integer(self, key: str, default: Any = _MISSING, *, minimum: int) -> int:
        value = self.raw(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, value, "must be an integer")
        if value < minimum:
            raise self.error(key, value, f"must be >= {minimum}")
        return int(value)

    def string(self, key: str, default: Any = _MISSING) -> str:
        value = self.raw(key, default)
        if not isinstance(value, str) or not value.strip():
            raise self.error(key, value, "must be a non-empty string")
        return value

    def poisson(self, key: str) -> float:
        value = self.number(key)
        if not -1.0 < value < 0.5:
            raise self.error(key, self.table[key], "Poisson ratio must lie in (-1, 0.5)")
        return value

    def number_list(
        self, key: str, default: Any = _MISSING, *, minimum: float | None = None, unit: str = ""
    ) -> tuple[float, ...]:
        value = self.raw(key, default)
        values = value if isinstance(value, list) else [value]
        if not values:
            raise self.error(key, value, "must list at least one value")
        numbers = []
        for item in values:
            if isinstance(item, list):
                raise self.error(key, value, "must be a flat list of numbers")
            numbers.append(self._check_number(key, item, minimum=minimum, strict=False, unit=unit))
        if len(set(numbers)) != len(numbers):
            raise self.error(key, value, "values must not repeat")
        return tuple(numbers)


# --------------------------------------------------------------------------------------------

_SECTIONS_REQUIRED = ("study", "material", "punch", "mesh", "loading", "sweep")
_SECTIONS_OPTIONAL = ("subsurface", "solver", "testing", "wear")


def load_study(path: str | Path) -> StudyConfig:
    """Read and validate the study file ``path``; raises :class:`StudyConfigError`."""
    path = Path(path)
    source = str(path)
    try:
        text = path.read_bytes().decode("utf-8")
    except FileNotFoundError:
        raise StudyConfigError(source, "study", _MISSING, "study file not found") from None
    except (OSError, UnicodeDecodeError) as error:
        raise StudyConfigError(source, "study", _MISSING, f"cannot read: {error}") from None
    return parse_study(text, source=source)


def parse_study(text: str, *, source: str = "<string>") -> StudyConfig:
    """Validate study TOML ``text``; ``source`` names the file in error messages.

    Every value of every swept key is validated on its own (with the other axes at their
    first value) before anything else happens; a bad one raises a :class:`StudyConfigError`
    naming the key, its list position and the value. Combinations are validated by
    :func:`engine.study.plan.make_plan`.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise _toml_error(source, text, error) from None
    search_table = data.pop("search", None)
    axes, tables = _split_sweep(source, data)
    raw = json.dumps(tables, default=str)
    first = {key: axis.values[0][i] for axis in axes for i, key in enumerate(axis.keys)}
    search = _search_spec(source, search_table, tables, tuple(first))
    if search is not None:  # the base study at the bracket's low end
        first[search.parameter] = search.low
    swept = set(first)
    try:
        config = _parse_tables(_substituted(tables, first), source)
    except StudyConfigError as error:
        if search is not None and error.key == search.parameter:
            problem = f"invalid: {error.problem}"
            raise StudyConfigError(source, "search.low", search.low, problem) from None
        if error.key not in swept:
            raise
        axis = next(axis for axis in axes if error.key in axis.keys)
        raise _axis_error(source, axis, 0, error) from None
    for axis in axes:
        for position in range(1, len(axis)):
            settings = dict(first)
            settings.update(zip(axis.keys, axis.values[position], strict=True))
            try:
                _parse_tables(_substituted(tables, settings), source)
            except StudyConfigError as error:
                raise _axis_error(source, axis, position, error) from None
    if search is not None:
        _check_search_end(source, search, tables, first)
    sweep = dataclasses.replace(config.sweep, axes=axes)
    return dataclasses.replace(config, sweep=sweep, raw=raw, search=search)


def _search_spec(source: str, table: Any, tables: dict[str, Any], swept: tuple[str, ...]):
    """The ``[search]`` section (None without one); its parameter must be left out of its
    own section: the search sets it case by case."""
    if table is None:
        return None
    from .search import parse_search

    search = parse_search(source, table, swept)
    section, name = search.parameter.split(".", 1)
    if name in (tables.get(section) or {}):
        raise StudyConfigError(
            source,
            search.parameter,
            tables[section][name],
            "is set by [search] case by case: leave it out here",
        )
    return search


def _check_search_end(source: str, search, tables: dict[str, Any], first: dict) -> None:
    """The study at the bracket's high end must be valid too (the low end is the base)."""
    settings = dict(first)
    settings[search.parameter] = search.high
    try:
        _parse_tables(_substituted(tables, settings), source)
    except StudyConfigError as error:
        raise StudyConfigError(
            source, "search.high", search.high, f"invalid: {error.problem}"
        ) from None


def _axis_error(source: str, axis: SweepAxis, position: int, error: StudyConfigError):
    """Re-word a section's error for the swept value that caused it."""
    key = error.key if error.key in axis.keys else axis.keys[0]
    value = axis.values[position][axis.keys.index(key)]
    section, _, name = error.key.partition(".")
    shown = "" if error.value is _MISSING else f" = {error.value!r}"
    where = "" if error.key == key else f" (then [{section}] {name}{shown}: {error.problem})"
    problem = error.problem if error.key == key else "invalid"
    return StudyConfigError(
        source,
        f"sweep.{key}",
        value,
        f"list position {position + 1} of {len(axis)}: {problem}{where}",
    )


def _substituted(tables: dict[str, Any], settings: dict[str, Any]) -> dict[str, Any]:
    """A copy of the TOML tables with the dotted ``settings`` written into their sections."""
    data = {name: dict(t) if isinstance(t, dict) else t for name, t in tables.items()}
    for key, value in settings.items():
        section, name = key.split(".", 1)
        data.setdefault(section, {})[name] = value
    return data


def _split_sweep(source: str, data: dict[str, Any]) -> tuple[tuple[SweepAxis, ...], dict]:
    """Take the dotted keys and ``zip`` out of ``[sweep]``: (axes, tables without them).

    ``"loading.load" = [...]`` and the unquoted ``loading.load = [...]`` (a TOML sub-table)
    are the same key.
    """
    table = data.get("sweep")
    if not isinstance(table, dict):
        return (), data
    friction: dict[str, Any] = {}
    lists: dict[str, list] = {}
    zip_raw: Any = None
    for name, value in table.items():
        if name == "zip":
            zip_raw = value
        elif isinstance(value, dict) and name in _SECTIONS_REQUIRED + _SECTIONS_OPTIONAL:
            for inner, inner_value in value.items():
                lists[f"{name}.{inner}"] = inner_value
        elif "." in name:
            lists[name] = value
        else:
            friction[name] = value
    for key, value in lists.items():
        _check_sweep_list(source, key, value, data)
        lists[key] = value if isinstance(value, list) else [value]
    groups = _zip_groups(source, zip_raw, lists)
    axes = []
    placed: set[str] = set()
    for key in lists:
        if key in placed:
            continue
        group = next((g for g in groups if key in g), (key,))
        placed.update(group)
        values = tuple(zip(*(lists[k] for k in group), strict=True))
        axes.append(SweepAxis(tuple(group), values))
    tables = dict(data)
    tables["sweep"] = friction
    return tuple(axes), tables


def _check_sweep_list(source: str, key: str, value: Any, data: dict[str, Any]) -> None:
    error_key = f"sweep.{key}"
    if key not in SWEEPABLE:
        raise StudyConfigError(
            source, error_key, value, "not a sweepable key (known: " + ", ".join(SWEEPABLE) + ")"
        )
    section, name = key.split(".", 1)
    if isinstance(data.get(section), dict) and name in data[section]:
        raise StudyConfigError(
            source, error_key, value, f"also set in [{section}]: give it in one place only"
        )
    values = value if isinstance(value, list) else [value]
    if not values:
        raise StudyConfigError(source, error_key, value, "must list at least one value")
    for position, item in enumerate(values):
        if isinstance(item, bool) or not isinstance(item, (int, float)):
            raise StudyConfigError(
                source,
                error_key,
                item,
                f"list position {position + 1} of {len(values)}: must be a number",
            )
    if len(set(values)) != len(values):
        raise StudyConfigError(source, error_key, value, "values must not repeat")


def _zip_groups(source: str, raw: Any, lists: dict[str, list]) -> list[tuple[str, ...]]:
    """Validate ``zip = [["a.b", "c.d"], ...]``: swept keys, each in one group, equal lengths."""
    if raw is None:
        return []
    if not isinstance(raw, list) or not all(
        isinstance(group, list) and all(isinstance(key, str) for key in group) for group in raw
    ):
        raise StudyConfigError(source, "sweep.zip", raw, "must be a list of lists of keys")
    groups, seen = [], set()
    for group in raw:
        if len(group) < 2:
            raise StudyConfigError(source, "sweep.zip", raw, "each group needs two keys or more")
        for key in group:
            if key not in lists:
                raise StudyConfigError(
                    source, "sweep.zip", raw, f"{key!r} is not a dotted key swept in [sweep]"
                )
            if key in seen:
                raise StudyConfigError(source, "sweep.zip", raw, f"{key!r} is in two groups")
            seen.add(key)
        lengths = {key: len(lists[key]) for key in group}
        if len(set(lengths.values())) != 1:
            raise StudyConfigError(
                source, "sweep.zip", raw, f"zipped lists must have equal lengths, got {lengths}"
            )
        groups.append(tuple(group))
    return groups


def _parse_tables(data: dict[str, Any], source: str) -> StudyConfig:
    """Validate the TOML tables (``[sweep]`` without dotted keys) into a StudyConfig."""
    for name in data:
        if name not in _SECTIONS_REQUIRED + _SECTIONS_OPTIONAL:
            raise StudyConfigError(
                source,
                name,
                _MISSING,
                "unknown section (known: "
                + ", ".join(f"[{s}]" for s in _SECTIONS_REQUIRED + _SECTIONS_OPTIONAL)
                + ")",
            )
    for name in _SECTIONS_REQUIRED:
        if name not in data:
            raise StudyConfigError(source, name, _MISSING, "required section is missing")

    def section(name: str) -> _Section:
        return _Section(source, name, data.get(name, {}))

    study = _parse_study_info(section("study"))
    material = _parse_material(section("material"))
    punch = _parse_punch(section("punch"))
    loading = _parse_loading(section("loading"))
    wear = _parse_wear(section("wear"), loading)
    mesh = _parse_mesh(section("mesh"), punch, material, loading)
    subsurface = _parse_subsurface(section("subsurface"))
    sweep = _parse_sweep(section("sweep"), loading, wear)
    solver = _parse_solver(section("solver"), loading)
    testing = _parse_testing(section("testing"))
    check_physical_ranges(source, material, punch, loading, sweep)
    derived = tuple(
        key
        for key, section_name, name in (
            ("mesh.half_width", "mesh", "half_width"),
            ("loading.record", "loading", "record"),
        )
        if name not in data.get(section_name, {})
    )
    return StudyConfig(
        source,
        study,
        material,
        punch,
        mesh,
        loading,
        subsurface,
        sweep,
        solver,
        testing,
        wear=wear,
        derived_defaults=derived,
    )


def _parse_study_info(s: _Section) -> StudyInfo:
    s.check_known({"name", "output", "output_strategy"})
    name = s.string("name")
    output = s.string("output")
    if not output.endswith((".h5", ".hdf5")):
        raise s.error("output", output, "must be a path ending in .h5 or .hdf5")
    strategy = s.string("output_strategy", "auto")
    if strategy not in ("auto", "single", "mpio"):
        raise s.error("output_strategy", strategy, 'must be "auto", "single" or "mpio"')
    return StudyInfo(name=name, output=Path(output), output_strategy=strategy)


def _parse_material(s: _Section) -> MaterialConfig:
    s.check_known({"E_A", "nu_A", "E_B", "nu_B"})
    return MaterialConfig(
        E_A=s.number("E_A", minimum=0.0, strict=True, unit="MPa"),
        nu_A=s.poisson("nu_A"),
        E_B=s.number("E_B", minimum=0.0, strict=True, unit="MPa"),
        nu_B=s.poisson("nu_B"),
    )


def _parse_punch(s: _Section) -> PunchConfig:
    s.check_known({"shape", "radius", "edge_radius"})
    shape = s.string("shape", "flat")
    if shape not in PUNCH_SHAPES:
        raise s.error("shape", shape, "must be " + ", ".join(f'"{x}"' for x in PUNCH_SHAPES))
    radius = s.number("radius", minimum=0.0, strict=True, unit="mm")
    edge_radius = None
    if shape == "rounded":
        edge_radius = s.number("edge_radius", minimum=0.0, unit="mm")
    elif "edge_radius" in s.table:
        raise s.error("edge_radius", s.table["edge_radius"], 'only for shape = "rounded"')
    return PunchConfig(radius=radius, shape=shape, edge_radius=edge_radius)


def _parse_mesh(
    s: _Section, punch: PunchConfig, material: MaterialConfig, loading: LoadingConfig
) -> MeshConfig:
    """The mesh must cover the contact: the punch face (flat, rounded) or, for a sphere,
    Hertz's contact radius at the peak load (a default half-width of HERTZ_MARGIN times it).
    A contact reaching the mesh border at run time fails the case (engine.geometry)."""
    s.check_known({"n", "half_width"})
    n = s.integer("n", minimum=8)
    if punch.shape == "sphere":
        from engine.reference.hertz import hertz_contact_radius

        contact = hertz_contact_radius(loading.load, punch.radius, _contact_modulus(material))
        default, what = HERTZ_MARGIN * contact, "Hertz contact radius"
    else:
        contact = punch.radius
        default = 1.05 * (punch.radius + (punch.edge_radius or 0.0))
        what = "punch face radius"
    if "half_width" in s.table and s.number("half_width", unit="mm") < contact:
        raise s.error(
            "half_width", s.table["half_width"], f"must be >= {contact:.6g} mm (the {what})"
        )
    half_width = s.number("half_width", default, minimum=0.0, strict=True, unit="mm")
    if n * contact / half_width < 4:
        raise s.error("n", n, f"fewer than 4 elements across the {what}; increase n")
    return MeshConfig(n=n, half_width=half_width)


def _contact_modulus(material: MaterialConfig) -> float:
    """E* = ((1−ν_A²)/E_A + (1−ν_B²)/E_B)⁻¹, MPa."""
    return 1.0 / ((1.0 - material.nu_A**2) / material.E_A + (1.0 - material.nu_B**2) / material.E_B)


LOADING_KINDS = ("static", "cyclic", "fretting")
FRETTING_KEYS = {"amplitude", "force_amplitude", "direction"}
WEAR_LAWS = ("archard", "energy")


def _parse_loading(s: _Section) -> LoadingConfig:
    kind = s.string("kind")
    if kind not in LOADING_KINDS:
        raise s.error("kind", kind, 'must be "static", "cyclic" or "fretting"')
    if kind == "static":
        # the placeholders that results files of earlier versions stored: they parse back
        former = {key for key, value in STATIC_PLACEHOLDERS.items() if s.table.get(key) == value}
        s.check_known({"kind", "load", "steps"} | former)
    elif kind == "cyclic":
        s.check_known({"kind", "load", "steps", "cycles", "record", "max_wear_fraction"})
    else:
        s.check_known(
            {"kind", "load", "steps", "cycles", "record", "max_wear_fraction"} | FRETTING_KEYS
        )
    load = s.number("load", minimum=0.0, strict=True, unit="N")
    steps = s.integer("steps", 10, minimum=1)
    if kind == "static":
        return LoadingConfig(kind, load, steps, 0, (), None)
    cycles = s.integer("cycles", minimum=1)
    record_raw = s.raw("record", [cycles])
    record_list = record_raw if isinstance(record_raw, list) else [record_raw]
    record = []
    for item in record_list:
        if isinstance(item, bool) or not isinstance(item, int):
            raise s.error("record", record_raw, "must be a list of integer cycle numbers")
        if not 0 <= item <= cycles:
            raise s.error(
                "record", record_raw, f"cycle {item} is outside 0..cycles (cycles = {cycles})"
            )
        record.append(item)
    if len(set(record)) != len(record):
        raise s.error("record", record_raw, "cycles must not repeat")
    max_wear_fraction = s.number(
        "max_wear_fraction", defaults.MAX_WEAR_FRACTION, minimum=0.0, strict=True
    )
    loading = LoadingConfig(kind, load, steps, cycles, tuple(sorted(record)), max_wear_fraction)
    if kind == "fretting":
        loading = _parse_fretting(s, loading)
    return loading


def _parse_fretting(s: _Section, loading: LoadingConfig) -> LoadingConfig:
    """The tangential signal of the fretting kind: ``amplitude`` (mm, rigid displacement)
    XOR ``force_amplitude`` (N, tangential force), ``direction`` [0] (degrees from x)."""
    given = [key for key in ("amplitude", "force_amplitude") if key in s.table]
    if len(given) != 1:
        shown = {key: s.table[key] for key in given} if given else _MISSING
        raise s.error(
            "amplitude" if not given else given[-1],
            shown,
            'kind = "fretting" needs exactly one of amplitude (mm, displacement control) '
            "and force_amplitude (N, force control)",
        )
    unit = "mm" if given[0] == "amplitude" else "N"
    value = s.number(given[0], minimum=0.0, strict=True, unit=unit)
    if given[0] == "force_amplitude" and not value < loading.load * MAX_FRICTION:
        raise s.error(given[0], value, "must be below the friction bound μP (N)")
    direction = s.number("direction", 0.0, unit="degrees")
    if not -360.0 <= direction <= 360.0:
        raise s.error("direction", direction, "must lie in [-360, 360] degrees")
    return dataclasses.replace(loading, **{given[0]: value}, direction=direction)


def _parse_wear(s: _Section, loading: LoadingConfig) -> WearConfig:
    s.check_known({"law"})
    law = s.string("law", "archard")
    if law not in WEAR_LAWS:
        raise s.error("law", law, 'must be "archard" or "energy"')
    if law == "energy" and loading.kind == "static":
        raise s.error("law", law, 'a wear law needs kind = "cyclic" or "fretting"')
    return WearConfig(law=law)


def _parse_subsurface(s: _Section) -> SubsurfaceConfig:
    s.check_known({"depth", "layers"})
    return SubsurfaceConfig(
        depth=s.number("depth", 1.5, minimum=0.0, strict=True, unit="punch radii"),
        layers=s.integer("layers", 16, minimum=2),
    )


def _parse_sweep(s: _Section, loading: LoadingConfig, wear: WearConfig) -> SweepConfig:
    s.check_known({"mu1", "mu2", "wear1", "wear2", "beta", "alpha"})
    mu1 = s.number_list("mu1", minimum=0.0)
    mu2 = s.number_list("mu2", minimum=0.0) if "mu2" in s.table else None
    if wear.law == "energy":
        for key in ("wear1", "wear2"):
            if key in s.table:
                raise s.error(key, s.table[key], '[wear] law = "energy" takes alpha (mm³/J)')
        alpha = s.number_list("alpha", minimum=0.0, unit="mm^3/J")
        beta = _axes_angles(s, s.number_list("beta", [0.0], unit="degrees"))
        return SweepConfig(mu1=mu1, mu2=mu2, wear1=(), wear2=None, beta=beta, alpha=alpha)
    if "alpha" in s.table:
        raise s.error("alpha", s.table["alpha"], 'only with [wear] law = "energy"')
    wear_default = [0.0] if loading.kind == "static" else _MISSING
    wear1 = s.number_list("wear1", wear_default, minimum=0.0, unit="1/MPa")
    wear2: tuple[float, ...] | str | None = None
    if "wear2" in s.table:
        if s.table["wear2"] == PROPORTIONAL:
            if any(mu == 0.0 for mu in mu1):
                raise s.error("wear2", PROPORTIONAL, "needs every mu1 > 0 (wear1·mu2/mu1)")
            wear2 = PROPORTIONAL
        elif isinstance(s.table["wear2"], str):
            raise s.error(
                "wear2", s.table["wear2"], f'must be a list of numbers or "{PROPORTIONAL}"'
            )
        else:
            wear2 = s.number_list("wear2", minimum=0.0, unit="1/MPa")
    beta = _axes_angles(s, s.number_list("beta", [0.0], unit="degrees"))
    return SweepConfig(mu1=mu1, mu2=mu2, wear1=wear1, wear2=wear2, beta=beta)


def _parse_solver(s: _Section, loading: LoadingConfig) -> SolverConfig:
    s.check_known({"tol", "maxiter", "threads", "fft_planner"})
    # Static solves are cheap and feed the stiffness comparisons: 1e-8. A cyclic case solves
    # thousands of increments; 1e-6 (gap/slip violation ~1e-6 of the approach) is far below
    # the wear-jump and discretisation errors (see tests/test_cycle_jump_convergence.py).
    default_tol = (
        defaults.CYCLIC_TOLERANCE
        if loading.kind in ("cyclic", "fretting")
        else defaults.STATIC_TOLERANCE
    )
    tol = _tolerance(s, s.number("tol", default_tol, minimum=0.0, strict=True))
    maxiter = s.integer("maxiter", defaults.MAX_ITERATIONS, minimum=1)
    threads = s.integer("threads", 1, minimum=1)
    fft_planner = s.string("fft_planner", "estimate")
    if fft_planner not in ("estimate", "measure"):
        raise s.error("fft_planner", fft_planner, 'must be "estimate" or "measure"')
    return SolverConfig(tol=tol, maxiter=maxiter, threads=threads, fft_planner=fft_planner)


def _parse_testing(s: _Section) -> TestingConfig:
    s.check_known({"fail_cases"})
    raw = s.raw("fail_cases", [])
    if not isinstance(raw, list) or not all(isinstance(item, str) for item in raw):
        raise s.error("fail_cases", raw, "must be a list of case ids (strings)")
    return TestingConfig(fail_cases=tuple(raw))


# --------------------------------------------------------------------------------------------
# Range checks (issues 16 and 18): values the model cannot represent are input errors.

MAX_TOLERANCE = 1e-2
# Moduli from soft gels (1 kPa) to a "rigid" punch modelled as 10^6 × steel: outside, the
# compliance 1/E* is so large or small that a case fails slowly (E_A = 1e-300 took 100 s per
# case before failing) or the displacements vanish in float64 round-off of the approach.
MODULUS_RANGE = (1e-3, 1e12)  # MPa
# The half-space model is linear elastic, i.e. small strains: the mean pressure P/(π a²) of
# the flat punch must stay below 10 % of the contact modulus E* (strain ~ p0/E*), and above
# 1e-12 of it (displacements below float64 resolution of the approach).
MAX_PRESSURE_OVER_MODULUS = 0.1
MIN_PRESSURE_OVER_MODULUS = 1e-12
# Friction coefficients of real contacts lie below ~2 (clean metals in vacuum up to ~5); far
# above, the contact sticks everywhere and μ·p overflows nothing but the user's intent.
MAX_FRICTION = 10.0
# Archard-type wear coefficients (1/MPa) of fretting tests are 1e-9 … 1e-6 (Section 7: 1.33e-7);
# at 1e-3 a contact at 100 MPa slipping 1 µm wears 0.1 µm per cycle, 10^4 × the severest
# measured, and the cycle jump degenerates into single cycles.
MAX_WEAR_COEFFICIENT = 1e-3  # 1/MPa


def _toml_error(source: str, text: str, error: Exception) -> StudyConfigError:
    """Malformed TOML, located: the section and key of the offending line when known
    (``[mesh] n: malformed TOML: Cannot overwrite a value (at line 14, column 4)``)."""
    message = str(error)
    line_number = None
    if "(at line " in message:
        try:
            line_number = int(message.split("(at line ")[1].split(",")[0])
        except ValueError:
            line_number = None
    key = "study"
    if line_number is not None:
        lines = text.splitlines()
        section = ""
        for line in lines[: line_number - 1]:
            stripped = line.strip()
            if stripped.startswith("[") and "]" in stripped:
                section = stripped.strip("[]").strip()
        offending = lines[line_number - 1] if line_number <= len(lines) else ""
        name = offending.split("=")[0].strip() if "=" in offending else ""
        if section:
            key = f"{section}.{name}" if name and " " not in name else section
    problem = f"malformed TOML: {message}"
    if "Cannot overwrite a value" in message:
        problem += " (the key is given twice)"
    return StudyConfigError(source, key, _MISSING, problem)


def _tolerance(s: _Section, tol: float) -> float:
    """Relative residual of the solvers: above 1e-2 a solve stops before it has done anything
    meaningful (tol = 1e300 "completed" every case with the same wrong wear)."""
    if tol > MAX_TOLERANCE:
        raise s.error(
            "tol", s.table["tol"], f"must lie in (0, {MAX_TOLERANCE:g}] (relative residual)"
        )
    return tol


def _axes_angles(s: _Section, angles: tuple[float, ...]) -> tuple[float, ...]:
    """β normalised to [0°, 180°): the friction and wear ellipses are centrally symmetric, so
    β and β ± 180° are the same physics; two values that coincide are rejected."""
    normalised = []
    for value in angles:
        if not -360.0 <= value <= 360.0:
            raise s.error("beta", s.table["beta"], "angles must lie in [-360, 360] degrees")
        normalised.append(value % 180.0)
    for index, value in enumerate(normalised):
        first = normalised.index(value)
        if first != index:
            raise s.error(
                "beta",
                s.table["beta"],
                f"{angles[first]:g} and {angles[index]:g} degrees are the same axes "
                "(β is taken modulo 180°: the friction and wear ellipses are centrally "
                "symmetric); list each angle once",
            )
    return tuple(normalised)


def check_physical_ranges(source, material, punch, loading, sweep) -> None:
    """Moduli, load (as mean pressure over contact modulus), friction and wear coefficients
    inside what the model represents (see the constants above for the ranges and why)."""
    low, high = MODULUS_RANGE
    for key in ("E_A", "E_B"):
        value = getattr(material, key)
        if not low <= value <= high:
            raise StudyConfigError(
                source,
                f"material.{key}",
                value,
                f"must lie in [{low:g}, {high:g}] MPa (from gels to a rigid punch modelled as "
                "10^6 × steel; outside, the compliance leaves float64's useful range)",
            )
    contact_modulus = 1.0 / (
        (1.0 - material.nu_A**2) / material.E_A + (1.0 - material.nu_B**2) / material.E_B
    )
    mean_pressure = loading.load / (math.pi * punch.radius**2)
    ratio = mean_pressure / contact_modulus
    if not MIN_PRESSURE_OVER_MODULUS <= ratio <= MAX_PRESSURE_OVER_MODULUS:
        raise StudyConfigError(
            source,
            "loading.load",
            loading.load,
            f"mean pressure P/(π a²) = {mean_pressure:.3g} MPa is {ratio:.3g} × the contact "
            f"modulus E* = {contact_modulus:.3g} MPa; the linear-elastic half-space needs "
            f"{MIN_PRESSURE_OVER_MODULUS:g} ≤ p0/E* ≤ {MAX_PRESSURE_OVER_MODULUS:g} "
            "(small strains)",
        )
    for key in ("mu1", "mu2"):
        for value in getattr(sweep, key, None) or ():
            if value > MAX_FRICTION:
                raise StudyConfigError(
                    source,
                    f"sweep.{key}",
                    value,
                    f"friction coefficient must lie in [0, {MAX_FRICTION:g}] (real contacts: "
                    "below ~2)",
                )
    for key in ("wear1", "wear2"):
        values = getattr(sweep, key, None)
        for value in values if isinstance(values, tuple) else ():
            if value > MAX_WEAR_COEFFICIENT:
                raise StudyConfigError(
                    source,
                    f"sweep.{key}",
                    value,
                    f"wear coefficient must lie in [0, {MAX_WEAR_COEFFICIENT:g}] 1/MPa "
                    "(fretting tests: 1e-9 … 1e-6)",
                )


# --------------------------------------------------------------------------------------------
# A minimal TOML writer for the resolved study (tomllib reads only).


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, str):
        return json.dumps(value)  # JSON string escapes are valid TOML basic strings
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(item) for item in value) + "]"
    raise TypeError(f"cannot write {value!r} as TOML")


def _toml_key(key: str) -> str:
    """Bare key when possible, else a quoted one (dotted sweep keys)."""
    bare = key.replace("_", "").replace("-", "").isalnum()
    return key if bare else json.dumps(key)


def dump_toml(data: dict[str, dict[str, Any]]) -> str:
    lines = []
    for section, table in data.items():
        lines.append(f"[{section}]")
        lines.extend(f"{_toml_key(key)} = {_toml_value(value)}" for key, value in table.items())
        lines.append("")
    return "\n".join(lines)
