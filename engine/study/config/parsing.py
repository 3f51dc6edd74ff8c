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
``[punch]``       shape ["flat"] (a name of engine.geometry.PROFILES) and the keys its
                  profile declares as dataclass fields (radius, edge_radius …)         mm
``[mesh]``        n* (elements per side), half_width [flat: 1.5·radius; rounded:
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
                  key (SWEEPABLE), e.g. "loading.load" = [500.0, 750.0], and the text keys
                  of SWEEPABLE_TEXT take lists of strings, e.g. "surface.path" =
                  ["a.npy", "b.npy"]; swept keys must not also be set in their own
                  section. zip = [["loading.load", "mesh.n"], ...] makes the keys of each
                  group vary together (equal list lengths) instead of forming their
                  product. See engine.study.plan.
``[solver]``      tol [1e-8 static, 1e-6 cyclic], maxiter [20000] (iterations per
                  increment), threads [1]
                  (FFT threads per rank), fft_planner ["estimate"] ("estimate": the same FFTW
                  plans in every process, so runs and rank counts give bit-identical results;
                  "measure": timed plans, faster, may differ in the last digits)
``[testing]``     fail_cases [[]]: case ids that raise on purpose (fault-injection tests)
``[surface]``     kind* ("self_affine" | "file") and its keys: roughness added to the
                  profile's gap (engine.surface.config)
``[fatigue]``     criteria*, their constants*, method ["hotspot"], length (mm), amplitude_method
                  ["chord"], plane_step [1], every_cycle [false]: multiaxial fatigue
                  criteria on the fretting cycles (fretting only; engine.study.fatigue)
"""

from __future__ import annotations

import dataclasses
import json
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from engine.geometry import DEFAULT_SHAPE, PROFILES
from engine.solvers import defaults
from engine.solvers.wear_laws import DEFAULT_WEAR_LAW, WEAR_LAWS, wear_coefficients
from engine.study.kinds import KINDS
from engine.study.line_contact import DEFAULT_REFERENCE_DISTANCE
from engine.study.settings.checks import LIMITS, bound, bound_of, check_physical_ranges
from engine.study.settings.reader import Section, compared_path, input_path, toml_error
from engine.study.settings.sections import (
    MISSING,
    LoadingConfig,
    MaterialConfig,
    MeshConfig,
    PunchConfig,
    SolverConfig,
    StudyConfigError,
    StudyInfo,
    SubsurfaceConfig,
    SweepConfig,
    TestingConfig,
    WearConfig,
    contact_modulus,
)
from engine.surface.config import parse_surface

from ..calibrate import check_fit_bounds, parse_calibrate
from ..fatigue import parse_fatigue
from ..search import parse_search
from .sweep import SECTIONS_OPTIONAL, SECTIONS_REQUIRED, axis_error, split_sweep, substituted
from .toml_writer import dump_toml


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
    fatigue: Any = None  # the [fatigue] section (engine.study.fatigue.FatigueConfig) or None
    calibrate: Any = None  # the [calibrate] section (engine.calibration.CalibrateSpec) or None
    surface: Any = None  # the [surface] section (engine.surface.SurfaceConfig) or None
    # The parsed TOML tables (swept keys absent; read, never changed) from which for_case()
    # derives a case's configuration, and the dotted keys whose default derives from others.
    tables: dict[str, Any] = dataclasses.field(default_factory=dict, repr=False, compare=False)
    derived_defaults: tuple[str, ...] = ()

    @property
    def kind(self):
        """The loading kind (:class:`engine.study.kinds.LoadingKind`) of ``[loading] kind``."""
        return _kind(self.loading)

    @property
    def is_cyclic(self) -> bool:
        """True for the kinds with load cycles, wear and cycle jumping (cyclic, fretting)."""
        return self.kind.has_cycles

    @property
    def is_fretting(self) -> bool:
        return self.loading.kind == "fretting"

    @property
    def contact_length(self) -> float:
        """a0 (mm), the length unit of ``[subsurface] depth`` and of the summary's p0: the
        punch radius (rounded: of the flat face) or, for a sphere, Hertz's contact radius
        at the peak load; for a line contact the nominal contact half-width (Hertz's for a
        cylinder, Ciavarella's for a pad)."""
        modulus = contact_modulus(self.material)
        return self.punch.profile().contact_length(self.loading.load, modulus)

    def at_search_end(
        self, settings: tuple[tuple[str, Any], ...], end: str = "low"
    ) -> tuple[tuple[str, Any], ...]:
        """A plan combination's ``settings`` with the searched parameter at the ``end``
        (``"low"`` or ``"high"``) of the ``[search]`` bracket: how a search study's
        combination is validated, laid out and checked before its steps exist. Unchanged
        without a search or when the settings already hold the parameter (a step)."""
        if self.search is None or self.search.parameter in dict(settings):
            return settings
        return settings + ((self.search.parameter, getattr(self.search, end)),)

    def for_case(self, settings: tuple[tuple[str, Any], ...] | dict[str, Any]) -> StudyConfig:
        """The configuration of one case: the swept ``settings`` ({dotted key: value})
        substituted into the study file and validated again (derived defaults such as
        ``mesh.half_width`` follow the swept values). Without settings: ``self``."""
        settings = dict(settings)
        if not settings:
            return self
        case = _parse_tables(substituted(self.tables, settings), self.source, set(settings))
        return dataclasses.replace(
            case,
            study=self.study,
            sweep=self.sweep,
            tables=self.tables,
            search=self.search,
            calibrate=self.calibrate,
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
            if field.name in ("source", "tables", "derived_defaults"):
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
            if field.name == "surface":
                if self.surface is not None:
                    resolved = self.surface.resolved()
                    if "surface.kind" in swept:  # the other kind's keys too, as given
                        resolved = {**self.tables.get("surface", {}), **resolved}
                        if "path" in resolved:  # the file, found as the cases find it
                            resolved["path"] = str(input_path(self.source, resolved["path"]))
                    if "path" in resolved:  # recorded as compared (compared_path)
                        resolved["path"] = compared_path(self.source, resolved["path"])
                    out["surface"] = {
                        k: v for k, v in resolved.items() if f"surface.{k}" not in swept
                    }
                continue
            if field.name == "calibrate":
                if self.calibrate is not None:
                    out["calibrate"] = self.calibrate.resolved()
                continue
            if field.name == "fatigue":
                if self.fatigue is not None:
                    resolved = self.fatigue.resolved()
                    out["fatigue"] = {
                        k: v for k, v in resolved.items() if f"fatigue.{k}" not in swept
                    }
                continue
            section = {}
            record = getattr(self, field.name)
            items = record.resolved() if field.name == "punch" else dataclasses.asdict(record)
            for key, value in items.items():
                if value is None or f"{field.name}.{key}" in swept:
                    continue  # TOML has no null: None is "not given" (fretting's other control)
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
        identities = self._surface_identities()
        if identities:  # a measured map's bytes: the first case's, or every swept path's
            resolved["surface_file_sha256"] = (
                identities if len(identities) > 1 else next(iter(identities.values()))
            )
        return json.dumps(resolved, sort_keys=True)

    def _surface_identities(self) -> dict[str, str]:
        """{path: SHA-256} of the measured height maps the cases read (none without one)."""
        if self.surface is None:
            return {}
        given = set()
        if "path" in self.tables.get("surface", {}):  # the file cases of a swept kind
            given.add(self.tables["surface"]["path"])
        for axis in self.sweep.axes:
            if "surface.path" in axis.keys:
                given.update(values[axis.keys.index("surface.path")] for values in axis.values)
        paths = {str(input_path(self.source, value)) for value in given}
        if self.surface.kind == "file":
            paths.add(self.surface.path)
        template = dataclasses.replace(self.surface, kind="file")
        return {
            compared_path(self.source, path): dataclasses.replace(template, path=path).identity()
            for path in sorted(paths)
        }


# A study file is a few kB (a sweep of thousands of values, a few hundred kB); its tables
# nest three or four levels deep. Beyond these it is not a study, and reading on would only
# exhaust memory or the parser's recursion.
MAX_STUDY_BYTES = 16 << 20
MAX_NESTING = 16


def load_study(path: str | Path) -> StudyConfig:
    """Read and validate the study file ``path``; raises :class:`StudyConfigError`."""
    path = Path(path)
    source = str(path)
    try:
        size = path.stat().st_size
        if path.is_file() and size > MAX_STUDY_BYTES:
            raise StudyConfigError(
                source, "", MISSING,
                f"file of {size} bytes: a study file is at most {MAX_STUDY_BYTES >> 20} MiB",
            )  # fmt: skip
        text = path.read_bytes().decode("utf-8-sig")  # a byte-order mark is not TOML
    except FileNotFoundError:
        where = "" if path.is_absolute() else f" (looked for {path.absolute()})"
        raise StudyConfigError(source, "", MISSING, f"no such study file{where}") from None
    except (OSError, UnicodeDecodeError) as error:
        raise StudyConfigError(source, "", MISSING, f"cannot read: {error}") from None
    return parse_study(text, source=source)


def _depth(value) -> int:
    """How deeply tables and arrays nest in ``value`` (a scalar: 0), without recursion."""
    deepest, stack = 0, [(value, 0)]
    while stack:
        item, depth = stack.pop()
        deepest = max(deepest, depth)
        if depth > MAX_NESTING:
            break
        if isinstance(item, dict):
            stack.extend((child, depth + 1) for child in item.values())
        elif isinstance(item, list):
            stack.extend((child, depth + 1) for child in item)
    return deepest


def _too_deep(source: str) -> StudyConfigError:
    return StudyConfigError(
        source, "", MISSING,
        f"tables or arrays nested more than {MAX_NESTING} levels deep: not a study file",
    )  # fmt: skip


def parse_study(text: str, *, source: str = "<string>") -> StudyConfig:
    """Validate study TOML ``text``; ``source`` names the file in error messages.

    Every value of every swept key is validated on its own (with the other axes at their
    first value) before anything else happens; a bad one raises a :class:`StudyConfigError`
    naming the key, its list position and the value. Combinations are validated by
    :func:`engine.study.plan.make_plan`.
    """
    if len(text) > MAX_STUDY_BYTES:
        raise StudyConfigError(
            source, "", MISSING,
            f"text of {len(text)} characters: a study is at most {MAX_STUDY_BYTES >> 20} MiB",
        )  # fmt: skip
    try:
        data = tomllib.loads(text.removeprefix("\ufeff"))  # a byte-order mark is not TOML
    except tomllib.TOMLDecodeError as error:
        raise toml_error(source, text, error) from None
    except RecursionError:
        raise _too_deep(source) from None
    if _depth(data) > MAX_NESTING:
        raise _too_deep(source)
    search_table = data.pop("search", None)
    calibrate_table = data.pop("calibrate", None)
    relative_to = ""
    if calibrate_table is not None and isinstance(search_table, dict):  # the tests' bracket
        search_table = dict(search_table)
        relative_to = search_table.pop("relative_to", "")
    axes, tables = split_sweep(source, data)
    first = {key: axis.values[0][i] for axis in axes for i, key in enumerate(axis.keys)}
    search = _search_spec(source, search_table, tables, tuple(first))
    calibrate = None
    if calibrate_table is not None:  # engine.calibration: its own section and tests file
        calibrate = parse_calibrate(source, calibrate_table, search, relative_to, tuple(first))
    if search is not None:  # the base study at the bracket's low end
        first[search.parameter] = search.low
    swept = set(first)
    try:
        config = _parse_tables(substituted(tables, first), source, swept)
    except StudyConfigError as error:
        if search is not None and error.key == search.parameter:
            problem = f"invalid: {error.problem}"
            raise StudyConfigError(source, "search.low", search.low, problem) from None
        if error.key not in swept:
            raise
        axis = next(axis for axis in axes if error.key in axis.keys)
        raise axis_error(source, axis, 0, error) from None
    for axis in axes:
        for position in range(1, len(axis)):
            settings = dict(first)
            settings.update(zip(axis.keys, axis.values[position], strict=True))
            try:
                _parse_tables(substituted(tables, settings), source, swept)
            except StudyConfigError as error:
                raise axis_error(source, axis, position, error) from None
    if search is not None:
        _check_search_end(source, search, tables, first)
    sweep = dataclasses.replace(config.sweep, axes=axes)
    config = dataclasses.replace(
        config, sweep=sweep, tables=tables, search=search, calibrate=calibrate
    )
    if calibrate is not None:
        check_fit_bounds(config)
    return config


def _search_spec(source: str, table: Any, tables: dict[str, Any], swept: tuple[str, ...]):
    """The ``[search]`` section (None without one; :func:`engine.study.search.parse_search`);
    its parameter must be left out of its own section: the search sets it case by case."""
    if table is None:
        return None

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
        _parse_tables(substituted(tables, settings), source, set(settings))
    except StudyConfigError as error:
        problem = f"invalid: {error.problem}"
        raise StudyConfigError(source, "search.high", search.high, problem) from None


def _parse_tables(data: dict[str, Any], source: str, swept=frozenset()) -> StudyConfig:
    """Validate the TOML tables (``[sweep]`` without dotted keys, ``swept`` the dotted keys
    written into them) into a StudyConfig."""
    for name in data:
        if name not in SECTIONS_REQUIRED + SECTIONS_OPTIONAL:
            raise StudyConfigError(
                source,
                name,
                MISSING,
                "unknown section (known: "
                + ", ".join(f"[{s}]" for s in SECTIONS_REQUIRED + SECTIONS_OPTIONAL)
                + ")",
            )
    for name in SECTIONS_REQUIRED:
        if name not in data:
            raise StudyConfigError(source, name, MISSING, "required section is missing")

    def section(name: str) -> Section:
        return Section(source, name, data.get(name, {}))

    study = _parse_study_info(section("study"))
    material = _parse_material(section("material"))
    punch = _parse_punch(section("punch"))
    loading = _parse_loading(section("loading"), punch.load_unit)
    wear = _parse_wear(section("wear"), loading)
    mesh = _parse_mesh(section("mesh"), punch, material, loading)
    subsurface = _parse_subsurface(section("subsurface"))
    sweep = _parse_sweep(section("sweep"), loading, wear)
    solver = _parse_solver(section("solver"), loading)
    testing = _parse_testing(section("testing"))
    fatigue = _parse_fatigue(section("fatigue"), loading) if "fatigue" in data else None
    surface = None
    if "surface" in data:
        surface = _parse_surface(section("surface"), mesh, punch, "surface.kind" in swept)
    check_physical_ranges(source, material, punch, loading, sweep)
    _check_line_keys(source, punch, loading, wear)
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
        fatigue=fatigue,
        surface=surface,
        derived_defaults=derived,
    )


def _parse_study_info(s: Section) -> StudyInfo:
    s.check_known({"name", "output", "output_strategy"})
    name = s.string("name")
    output = s.string("output")
    if not output.endswith((".h5", ".hdf5")):
        raise s.error("output", output, "must be a path ending in .h5 or .hdf5")
    strategy = s.string("output_strategy", "auto")
    if strategy not in ("auto", "single", "mpio"):
        raise s.error("output_strategy", strategy, 'must be "auto", "single" or "mpio"')
    return StudyInfo(name=name, output=Path(output), output_strategy=strategy)


def _parse_material(s: Section) -> MaterialConfig:
    s.check_known({"E_A", "nu_A", "E_B", "nu_B"})
    return MaterialConfig(
        E_A=s.number("E_A", minimum=0.0, strict=True, unit="MPa"),
        nu_A=s.poisson("nu_A", LIMITS["material.nu_A"]),
        E_B=s.number("E_B", minimum=0.0, strict=True, unit="MPa"),
        nu_B=s.poisson("nu_B", LIMITS["material.nu_B"]),
    )


def _parse_punch(s: Section) -> PunchConfig:
    """``shape`` names a profile of :data:`engine.geometry.PROFILES`, whose dataclass fields
    are the other keys of the section, each read through its declaration (unit, bounds,
    required or default; :meth:`engine.geometry.Profile.keys`)."""
    declared = {name: cls.keys() for name, cls in PROFILES.items()}
    s.check_known({"shape"}.union(*declared.values()))
    shape = s.string("shape", DEFAULT_SHAPE)
    if shape not in PROFILES:
        raise s.error("shape", shape, "must be " + ", ".join(f'"{x}"' for x in PROFILES))
    for key in s.table:
        if key != "shape" and key not in declared[shape]:
            shapes = [f'"{name}"' for name, keys in declared.items() if key in keys]
            raise s.error(key, s.table[key], f"only for shape = {' or '.join(shapes)}")
    keys = tuple((name, key.read(s, name)) for name, key in declared[shape].items())
    return PunchConfig(shape=shape, keys=keys)


def _parse_mesh(
    s: Section, punch: PunchConfig, material: MaterialConfig, loading: LoadingConfig
) -> MeshConfig:
    """The mesh must cover the profile's contact length a0 (the punch face of a flat or
    rounded punch, Hertz's contact radius of a sphere at the peak load, a line contact's
    nominal half-width) with 4 elements across it; the default half-width is the profile's
    (:meth:`engine.geometry.Profile.default_half_width`). A line contact also takes the
    datum of its displacements ``reference_distance`` (mm, at least the mesh's length
    2·half_width). A contact reaching the mesh border at run time fails the case
    (engine.geometry)."""
    profile = punch.profile()
    s.check_known({"n", "half_width"} | ({"reference_distance"} if profile.is_line else set()))
    n = s.integer("n", **bound("mesh.n"))
    modulus = contact_modulus(material)
    contact = profile.contact_length(loading.load, modulus)
    what = profile.covered
    if "half_width" in s.table and s.number("half_width", unit="mm") < contact:
        raise s.error(
            "half_width", s.table["half_width"], f"must be >= {contact:.6g} mm (the {what})"
        )
    default = profile.default_half_width(loading.load, modulus)
    half_width = s.number("half_width", default, unit="mm", **bound("mesh.half_width"))
    if n * contact / half_width < 4:
        raise s.error(
            "n",
            n,
            f"fewer than 4 elements across the {what} ({contact:.6g} mm) on a grid of "
            f"half-width {half_width:.6g} mm; increase n",
        )
    if not profile.is_line:
        return MeshConfig(n=n, half_width=half_width)

    distance = s.number(
        "reference_distance",
        DEFAULT_REFERENCE_DISTANCE,
        unit="mm",
        **bound("mesh.reference_distance"),
    )
    if distance < 2.0 * half_width:
        raise s.error(
            "reference_distance",
            distance,
            f"must be at least the mesh's length 2·half_width = {2.0 * half_width:g} mm",
        )
    return MeshConfig(n=n, half_width=half_width, reference_distance=distance)


def _check_line_keys(source, punch: PunchConfig, loading: LoadingConfig, wear: WearConfig):
    """The keys of line contacts only (the bulk stress) name themselves elsewhere."""
    if punch.is_line:
        return
    for key, value in (
        ("loading.bulk_stress_max", getattr(loading, "bulk_stress_max", None)),
        ("loading.bulk_stress_min", getattr(loading, "bulk_stress_min", None)),
    ):
        if value is not None:
            raise StudyConfigError(
                source, key, value, f"only for line contacts ([punch] shape = {_line_shapes()})"
            )


def _line_shapes() -> str:
    """``"cylinder" or "pad"``: the line-contact shapes of engine.geometry.PROFILES."""
    return " or ".join(f'"{name}"' for name, profile in PROFILES.items() if profile.is_line)


def _parse_loading(s: Section, load_unit: str = "N") -> LoadingConfig:
    """``[loading]``: ``kind`` names a loading kind of :data:`engine.study.kinds.KINDS`,
    which reads the rest of the section after ``load`` (``load_unit``: N, a line contact's
    N/mm) and ``steps``."""
    kind = s.string("kind")
    if kind not in KINDS:
        names = [f'"{name}"' for name in KINDS]
        raise s.error("kind", kind, f"must be {', '.join(names[:-1])} or {names[-1]}")
    load = s.number("load", minimum=0.0, strict=True, unit=load_unit)
    declared = KINDS[kind].declared_keys()["steps"]  # the kind's: default and bounds
    steps = s.integer("steps", declared.default, **bound_of(declared))
    return KINDS[kind].parse(s, load, steps)


def _kinds():
    """The table of loading kinds (imported when first needed: the kinds' modules read
    their sections with this package's reader)."""
    return KINDS


def _kind(loading: LoadingConfig):
    return _kinds()[loading.kind]


def _parse_wear(s: Section, loading: LoadingConfig) -> WearConfig:
    s.check_known({"law", "pad_coefficient"})
    law = s.string("law", DEFAULT_WEAR_LAW)
    if law not in WEAR_LAWS:
        raise s.error("law", law, "must be one of " + ", ".join(f'"{n}"' for n in WEAR_LAWS))
    if law != DEFAULT_WEAR_LAW and not _kind(loading).has_cycles:
        with_wear = " or ".join(f'"{k.name}"' for k in _kinds().values() if k.has_cycles)
        raise s.error("law", law, f"a wear law needs kind = {with_wear}")
    pad = None
    if "pad_coefficient" in s.table:  # the pad's coefficient, in the unit of the flat's law
        first = next(iter(WEAR_LAWS[law].coefficients.values()))
        dotted = "wear.pad_coefficient" + ("" if law == DEFAULT_WEAR_LAW else f".{law}")
        given = {"maximum": first.maximum, "why": first.why, "minimum": first.minimum}
        limit = bound(dotted) if dotted in LIMITS else given
        pad = s.number("pad_coefficient", unit=first.unit, **limit)
    return WearConfig(law=law, pad_coefficient=pad)


def _parse_fatigue(s: Section, loading: LoadingConfig):
    """The ``[fatigue]`` section (``engine.study.fatigue``): the criteria read the increments
    of a fretting cycle, so it needs ``[loading] kind = "fretting"``."""
    config = parse_fatigue(s)
    if loading.kind != "fretting":
        raise StudyConfigError(
            s.source,
            "loading.kind",
            loading.kind,
            '[fatigue] evaluates the increments of fretting cycles: needs kind = "fretting"',
        )
    return config


def _parse_surface(s: Section, mesh: MeshConfig, punch: PunchConfig, kind_swept: bool):
    """The ``[surface]`` section (``engine.surface.config``): roughness on any profile."""
    return parse_surface(s, mesh, punch.is_line, kind_swept=kind_swept)


def _parse_subsurface(s: Section) -> SubsurfaceConfig:
    s.check_known({"depth", "layers"})
    return SubsurfaceConfig(
        depth=s.number("depth", 1.5, unit="punch radii", **bound("subsurface.depth")),
        layers=s.integer("layers", 16, **bound("subsurface.layers")),
    )


def _parse_sweep(s: Section, loading: LoadingConfig, wear: WearConfig) -> SweepConfig:
    """``mu1``, ``mu2``, ``beta`` and the coefficients the wear law declares (read by the
    law, :meth:`engine.solvers.wear.WearModel.read_sweep`); another law's coefficient is
    refused naming the law that takes it."""
    law = WEAR_LAWS[wear.law]
    s.check_known({"mu1", "mu2", "beta", *wear_coefficients()})
    for name in s.table:
        if name in wear_coefficients() and name not in law.coefficients:
            takes = ", ".join(law.coefficients)
            raise s.error(name, s.table[name], f'[wear] law = "{wear.law}" takes {takes}')
    mu1 = s.number_list("mu1", minimum=LIMITS["sweep.mu1"].minimum)
    mu2 = s.number_list("mu2", minimum=LIMITS["sweep.mu2"].minimum) if "mu2" in s.table else None
    lists = law.read_sweep(s, required=_kind(loading).has_cycles)
    beta = _axes_angles(s, s.number_list("beta", [0.0], unit="degrees"))
    return SweepConfig(mu1=mu1, mu2=mu2, beta=beta, law=wear.law, wear=tuple(lists.items()))


def _parse_solver(s: Section, loading: LoadingConfig) -> SolverConfig:
    s.check_known({"tol", "maxiter", "threads", "fft_planner"})
    # Static solves are cheap and feed the stiffness comparisons: 1e-8. A cyclic case solves
    # thousands of increments; 1e-6 (gap/slip violation ~1e-6 of the approach) is far below
    # the wear-jump and discretisation errors (see tests/test_cycle_jump_convergence.py).
    default_tol = _kind(loading).default_tolerance
    tol = _tolerance(s, s.number("tol", default_tol, minimum=0.0, strict=True))
    maxiter = s.integer("maxiter", defaults.MAX_ITERATIONS, **bound("solver.maxiter"))
    threads = s.integer("threads", 1, **bound("solver.threads"))
    fft_planner = s.string("fft_planner", "estimate")
    if fft_planner not in ("estimate", "measure"):
        raise s.error("fft_planner", fft_planner, 'must be "estimate" or "measure"')
    return SolverConfig(tol=tol, maxiter=maxiter, threads=threads, fft_planner=fft_planner)


def _parse_testing(s: Section) -> TestingConfig:
    s.check_known({"fail_cases"})
    raw = s.raw("fail_cases", [])
    if not isinstance(raw, list) or not all(isinstance(item, str) for item in raw):
        raise s.error("fail_cases", raw, "must be a list of case ids (strings)")
    return TestingConfig(fail_cases=tuple(raw))


def _tolerance(s: Section, tol: float) -> float:
    """Relative residual of the solvers: above 1e-2 a solve stops before it has done anything
    meaningful (tol = 1e300 "completed" every case with the same wrong wear)."""
    limit = LIMITS["solver.tol"]
    if not limit.holds(tol):
        raise s.error("tol", s.table["tol"], f"must lie in {limit.accepted} (relative residual)")
    return tol


def _axes_angles(s: Section, angles: tuple[float, ...]) -> tuple[float, ...]:
    """β normalised to [0°, 180°): the friction and wear ellipses are centrally symmetric, so
    β and β ± 180° are the same physics; two values that coincide are rejected."""
    normalised = []
    for value in angles:
        if not LIMITS["sweep.beta"].holds(value):
            angles = LIMITS["sweep.beta"].accepted
            raise s.error("beta", s.table["beta"], f"angles must lie in {angles} degrees")
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
