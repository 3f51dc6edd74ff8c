"""The units of every key a study may sweep, derived from the engine's own sections and the
plug-in registries.

The results schema (:data:`engine.schema.SWEPT_KEY_UNITS`) holds the keys of the sections
the engine owns (``[material]``, ``[mesh]``, ``[subsurface]``, ``[solver]``); the keys of a
plug-in come from its declaration: a loading kind's ``[loading]`` numbers from its
dataclass's fields (:meth:`engine.study.kinds.LoadingKind.declared_keys`), a punch
profile's ``[punch]`` keys from its dataclass fields (:meth:`engine.geometry.Profile.keys`),
the ``[fatigue]`` constants from the criteria
(:func:`engine.study.fatigue.fatigue_sweepable`). :data:`SWEEPABLE` is their union, section
by section; :func:`unit_of` and :func:`parameter_units` read it for the summary
columns and the case attributes. A key two plug-ins declare with different units is an
error naming both (:func:`engine.keys.merge_units`).
"""

from __future__ import annotations

from engine import schema
from engine.geometry import PROFILES
from engine.keys import merge_units
from engine.solvers.wear_laws import WEAR_LAWS, fixed_coefficients, wear_coefficients
from engine.study.fatigue import fatigue_column_specs, fatigue_sweepable
from engine.study.kinds import KINDS

__all__ = [
    "SWEEPABLE",
    "SWEEPABLE_TEXT",
    "case_parameters",
    "loading_units",
    "sweepable_keys",
    "summary_columns",
    "unit_of",
    "parameter_units",
]

#: Sections in the order of the study-file reference.
_ORDER = (
    "material", "punch", "mesh", "loading", "subsurface", "solver", "wear", "fatigue", "surface",
)  # fmt: skip


def loading_units(kinds=None) -> dict[str, str]:
    """{``loading.<key>``: unit} of the numbers every loading kind of ``kinds`` (default: the
    registered ones) declares in its ``[loading]`` dataclass
    (:meth:`engine.study.kinds.LoadingKind.declared_keys`), in the order of the kinds."""
    kinds = KINDS if kinds is None else kinds
    return merge_units(
        (
            (f"the {name!r} loading kind ({type(kind).__module__})", {
                f"loading.{key}": declared.unit
                for key, declared in kind.declared_keys().items()
            })
            for name, kind in kinds.items()
        ),
        "[loading] key",
    )  # fmt: skip


def sweepable_keys(profiles=None, criteria=None, kinds=None) -> dict[str, str]:
    """{dotted key: unit} of every scalar ``[sweep]`` accepts: the engine's sections
    (:data:`engine.schema.SWEPT_KEY_UNITS`), the numbers each loading kind declares
    (:func:`loading_units`), each profile's ``[punch]`` keys and every criterion's constants
    with ``fatigue.length``, ordered by section."""
    profiles = PROFILES if profiles is None else profiles
    punch = merge_units(
        (
            (f"the {name!r} profile ({cls.__module__})", {
                f"punch.{key}": declared.unit for key, declared in cls.keys().items()
            })
            for name, cls in profiles.items()
        ),
        "[punch] key",
    )  # fmt: skip
    fatigue = fatigue_sweepable() if criteria is None else fatigue_sweepable(criteria)
    table = {**schema.SWEPT_KEY_UNITS, **loading_units(kinds), **punch, **fatigue}
    return {
        key: table[key] for section in _ORDER for key in table if key.split(".", 1)[0] == section
    }


#: Scalars that ``[sweep]`` accepts under their dotted key, with their units (the summary
#: columns and case parameters of a swept key carry these).
SWEEPABLE = sweepable_keys()
#: Text keys that ``[sweep]`` accepts as lists of strings (no unit; the section's parser
#: checks each value): :data:`engine.schema.SWEPT_TEXT_KEYS`.
SWEEPABLE_TEXT = schema.SWEPT_TEXT_KEYS


def case_parameters(laws=None) -> tuple[str, ...]:
    """Every parameter a case may store, in the order of its attributes: mu1, mu2, the
    default wear law's coefficients, beta, then every other law's of ``laws`` (default: the
    registered ones)."""
    fixed = fixed_coefficients()
    others = [name for name in wear_coefficients(laws) if name not in fixed]
    return ("mu1", "mu2", *fixed, "beta", *others)


def summary_columns(criteria=None, laws=None) -> dict[str, tuple[str, str]]:
    """{column: (unit, meaning)} of every summary column: the results schema's
    (:data:`engine.schema.COLUMN_DESCRIPTIONS`) with the wear coefficients of every law of
    ``laws`` (default: the registered ones; the default law's before ``beta``, the others'
    after the schema's columns), then every fatigue criterion's of ``criteria`` (default: the
    registered ones; :func:`engine.study.fatigue.fatigue_column_specs`)."""
    laws = WEAR_LAWS if laws is None else laws
    coefficients = {
        name: (key.unit, f"{_law_of(name, laws)}: {key.meaning}")
        for name, key in wear_coefficients(laws).items()
    }
    columns: dict[str, tuple[str, str]] = {}
    for column, meaning in schema.COLUMN_DESCRIPTIONS.items():
        if column == "beta":
            columns.update({name: coefficients[name] for name in fixed_coefficients()})
        columns[column] = (schema.unit_of(column), meaning)
    columns.update(coefficients)
    specs = fatigue_column_specs() if criteria is None else fatigue_column_specs(criteria)
    for column, spec in specs.items():
        columns[column] = (spec.units, f"fatigue: {spec.description} (last recorded cycle)")
    return columns


def _law_of(coefficient: str, laws) -> str:
    """ "the <name> wear law" for the laws that declare ``coefficient``."""
    names = [name for name, law in laws.items() if coefficient in law.coefficients]
    return " and ".join(f"`{name}`" for name in names) + " wear law"


_FATIGUE_COLUMN_UNITS = {column: spec.units for column, spec in fatigue_column_specs().items()}


def unit_of(name: str, line: bool = False) -> str:
    """Units of a case parameter, summary column or swept dotted key in a 3-D or (``line``)
    a line contact; "" for text columns and names no table knows
    (:func:`engine.schema.unit_of` with the plug-ins' keys and columns)."""
    if name in SWEEPABLE:
        return schema.contact_units(SWEEPABLE[name], line)
    if name in _FATIGUE_COLUMN_UNITS:
        return schema.contact_units(_FATIGUE_COLUMN_UNITS[name], line)
    coefficients = wear_coefficients()
    if name in coefficients:
        return coefficients[name].unit
    return schema.unit_of(name, line)


def parameter_units(parameters, line: bool = False) -> dict[str, str]:
    """Units of a case's parameter attributes: :data:`engine.schema.PARAMETER_UNITS` and those
    of the swept dotted keys among ``parameters`` (names), in a 3-D or a line contact."""
    units = dict(schema.PARAMETER_UNITS)
    units.update({name: SWEEPABLE.get(name, "") for name in parameters if "." in name})
    return {name: schema.contact_units(unit, line) for name, unit in units.items()}
