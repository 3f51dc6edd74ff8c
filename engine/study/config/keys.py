"""What every key of a study file means: type, default, unit and meaning, as data.

The parser (:mod:`engine.study.config`) decides which keys exist and checks their values; the
table ``keys.toml`` beside this module describes them for people, and this module reads it
into :data:`SECTIONS` and :data:`STUDY_KEYS`. ``scripts/reference.py`` turns them into the
study-file reference of the manual (``docs/reference/study-file.md``), and
``tests/test_docs.py`` checks them against the parser: every key the parser accepts is
described and nothing else, every constant default is the one the parser resolves, and every
sweepable key has the unit of ``SWEEPABLE``. A new key is one table in ``keys.toml``, in its
section, next to its line in the parser.

The keys a plug-in owns are described by the plug-in: the ``[punch]`` keys are derived from
the built-in profiles' declarations (:data:`engine.geometry.PROFILES`, :meth:`Profile.keys`),
``[wear] law`` and the wear coefficients of ``[sweep]`` from the built-in wear laws'
(:data:`engine.solvers.wear_laws.WEAR_LAWS`, ``coefficients``), ``[fatigue] criteria`` and
the criteria's constants from the built-in criteria's (:data:`engine.fatigue.CRITERIA`,
``constants``), and the ``[loading]`` keys from the built-in loading kinds' sections
(:data:`engine.study.kinds.KINDS`, ``config``: a field's :class:`engine.keys.Key` and type),
never written in ``keys.toml``; a profile, a law, a criterion or a kind another package
registers describes its keys the same way (:func:`punch_keys`, :func:`loading_keys`,
:func:`wear_keys`, :func:`fatigue_keys`).

Units are those of the paper: mm, N, MPa, wear coefficients in 1/MPa, angles in degrees; "1"
is dimensionless and "–" marks a text or a list that has no unit.
"""

from __future__ import annotations

import dataclasses
import tomllib
import types
import typing
from dataclasses import dataclass
from importlib.resources import files

from engine.fatigue import CRITERIA
from engine.geometry import DEFAULT_SHAPE, PROFILES
from engine.solvers.wear_laws import DEFAULT_WEAR_LAW, WEAR_LAWS
from engine.study.kinds import KINDS

__all__ = [
    "REQUIRED",
    "SECTIONS",
    "StudyKey",
    "STUDY_KEYS",
    "punch_keys",
    "loading_keys",
    "wear_keys",
    "fatigue_keys",
]

REQUIRED = "required"


@dataclass(frozen=True)
class StudyKey:
    """One key of a study file as the manual describes it.

    Parameters
    ----------
    section : str
        The TOML table, e.g. ``"loading"``.
    name : str
        The key inside the table, e.g. ``"load"``.
    type : str
        The TOML type a value must have ("number", "integer", "text", "list of numbers" …).
    default : str
        The value used when the key is absent, as text, or :data:`REQUIRED`.
    unit : str
        The unit of the value ("1" dimensionless, "–" none).
    meaning : str
        What the key sets, in one or two sentences (Markdown).
    label : str
        A short name for figure axes and tables ("" when the meaning is one already;
        :attr:`title` gives either).
    """

    section: str
    name: str
    type: str
    default: str
    unit: str
    meaning: str
    label: str = ""

    @property
    def title(self) -> str:
        """The name figures and tables give the key: ``label``, or the meaning up to its
        first parenthesis, comma or semicolon ("Young's modulus of the half-space")."""
        if self.label:
            return self.label
        text = self.meaning.replace("`", "")
        for stop in (" (", ", ", "; "):
            text = text.split(stop)[0]
        return text


def _read_table() -> tuple[dict[str, str], tuple[StudyKey, ...]]:
    """The sections (name: what they describe) and the keys of ``keys.toml``, in its order."""
    table = tomllib.loads(files(__package__).joinpath("keys.toml").read_text(encoding="utf-8"))
    sections = {section: entries["about"] for section, entries in table.items()}
    keys: list[StudyKey] = []
    for section, entries in table.items():
        if section == "punch":
            keys += punch_keys(PROFILES.builtins)
            continue
        if section == "loading":
            keys += loading_keys(KINDS.builtins)
            continue
        described = [StudyKey(section, name, **fields) for name, fields in entries["keys"].items()]
        if section == "wear":  # the law first, then the pad's coefficient in the law's unit
            law, sweep = wear_keys(WEAR_LAWS.builtins)
            units = {
                next(iter(cls.coefficients.values())).unit for cls in WEAR_LAWS.builtins.values()
            }
            described = [law] + [
                dataclasses.replace(key, unit=" or ".join(sorted(units)))
                if key.name == "pad_coefficient" else key
                for key in described
            ]  # fmt: skip
        if section == "fatigue":  # the criteria, then their constants, then the options
            criteria, constants = fatigue_keys(CRITERIA.builtins)
            described = [criteria, *constants] + [k for k in described if k.name != "criteria"]
        if section == "sweep":  # the wear coefficients after the friction coefficients
            at = [key.name for key in described].index("mu2") + 1
            described[at:at] = sweep
        keys += described
    return sections, tuple(keys)


def _quoted(names) -> str:
    return ", ".join(f'`"{name}"`' for name in names)


def punch_keys(profiles=None) -> list[StudyKey]:
    """The ``[punch]`` keys: ``shape`` (one of the profiles, each with its summary), then
    every key a profile declares, with the shapes that take it and what it means for each."""
    profiles = PROFILES if profiles is None else profiles
    shapes = "; ".join(f'`"{name}"`: {cls.description}' for name, cls in profiles.items())
    keys = [StudyKey("punch", "shape", "text", f'"{DEFAULT_SHAPE}"', "–", shapes)]
    owners: dict[str, list] = {}
    for name, cls in profiles.items():
        for key, declared in cls.keys().items():
            owners.setdefault(key, []).append((name, declared))
    for key, declared in owners.items():
        names = [name for name, _ in declared]
        required = all(item.required for _, item in declared)
        if len(names) == len(profiles):
            default = "required" if required else "–"
        else:
            default = f"required for {_quoted(names)}" if required else "–"
        meaning = "; ".join(
            f"{name}: {item.meaning}" + (f" ({item.bounds})" if item.bounds else "")
            for name, item in declared
        )
        label = f"punch {key.replace('_', ' ')}"  # figure axes and tables
        unit = declared[0][1].unit
        keys.append(StudyKey("punch", key, "number", default, unit, meaning, label))
    return keys


def loading_keys(kinds=None) -> list[StudyKey]:
    """The ``[loading]`` keys: ``kind`` (one of ``kinds``, default the registered ones, each
    with its summary), then every other field of the kinds' sections
    (:attr:`engine.study.kinds.LoadingKind.config`) in the order they first appear: its type
    (from the field's annotation), unit and label (from its :class:`engine.keys.Key`), its
    default (required, the default value, or what the kind declares holds when it is
    absent) with the kinds that read it when not all do, and what it means, per kind where
    the kinds' meanings differ (``steps``)."""
    kinds = KINDS if kinds is None else kinds
    summaries = "; ".join(f'`"{name}"`: {kind.summary}' for name, kind in kinds.items())
    keys = [StudyKey("loading", "kind", "text", REQUIRED, "–", summaries)]
    owners: dict[str, list[tuple[str, StudyKey]]] = {}
    for name, kind in kinds.items():
        hints = _annotations(kind.config)
        for field in dataclasses.fields(kind.config):
            if field.name != "kind":
                described = _loading_field(field, hints[field.name])
                owners.setdefault(field.name, []).append((name, described))
    for declared in owners.values():
        first = declared[0][1]
        default = _per_kind([(name, item.default) for name, item in declared])
        if len(declared) < len(kinds) and len({item.default for _, item in declared}) == 1:
            default += f" ({', '.join(name for name, _ in declared)})"
        meaning = _per_kind([(name, item.meaning) for name, item in declared])
        label = next((item.label for _, item in declared if item.label), "")
        keys.append(dataclasses.replace(first, default=default, meaning=meaning, label=label))
    return keys


def _loading_field(field: dataclasses.Field, hint) -> StudyKey:
    """One field of a kind's ``[loading]`` dataclass as that kind describes it: a number's
    :class:`engine.keys.Key` (``"key"`` in the field's metadata), or a list's meaning
    (``"meaning"``); the default is the field's, or what ``"absent"`` says holds without it."""
    declared = field.metadata.get("key")
    unit, label = (declared.unit, declared.label) if declared else ("–", "")
    meaning = declared.meaning if declared else field.metadata.get("meaning", "")
    if "absent" in field.metadata:
        default = field.metadata["absent"]
    elif field.default is dataclasses.MISSING:
        default = REQUIRED
    elif field.default is None:
        default = "none"
    else:
        default = f"{field.default:g}" if isinstance(field.default, float) else str(field.default)
    return StudyKey("loading", field.name, _type_name(hint), default, unit, meaning, label)


def _annotations(cls) -> dict:
    """{field: its type} of the dataclass ``cls``: the evaluated annotations, or their text
    where a name in them cannot be resolved (a plug-in's annotation under TYPE_CHECKING)."""
    try:
        return typing.get_type_hints(cls)
    except (NameError, TypeError):
        return {field.name: field.type for field in dataclasses.fields(cls)}


def _type_name(hint) -> str:
    """The TOML type of a field's annotation: "number", "integer", "list of integers" …"""
    if isinstance(hint, str):  # unresolved: its text ("int", "float | None", "tuple[int, ...]")
        text = hint.removesuffix(" | None")
        item = text.removeprefix("tuple[").removeprefix("list[").split(",")[0].rstrip("]")
        hint = {"bool": bool, "int": int, "float": float, "str": str}.get(item, float)
        return _type_name(tuple[hint, ...] if text != item else hint)
    if typing.get_origin(hint) in (typing.Union, types.UnionType):  # X | None: optional
        hint = next(arg for arg in typing.get_args(hint) if arg is not type(None))
    names = {bool: "boolean", int: "integer", float: "number", str: "text"}
    if typing.get_origin(hint) in (tuple, list):
        item = names.get(typing.get_args(hint)[0], "value")
        return f"list of {'integers' if item == 'integer' else item + 's'}"
    return names.get(hint, "number")


def _per_kind(texts: list[tuple[str, str]]) -> str:
    """One text when every kind of ``texts`` ((kind, text) pairs) says the same, else each
    text after the kinds that say it: "static: …; cyclic: …"."""
    groups: dict[str, list[str]] = {}
    for kind, text in texts:
        groups.setdefault(text, []).append(kind)
    if len(groups) == 1:
        return texts[0][1]
    return "; ".join(f"{', '.join(kinds)}: {text}" for text, kinds in groups.items())


def wear_keys(laws=None) -> tuple[StudyKey, list[StudyKey]]:
    """``[wear] law`` (one of ``laws``, default the registered ones, each with its summary
    and coefficients) and the ``[sweep]`` keys of every law's coefficients, with their
    units, the law that takes each, and its default (required with the law, or the
    coefficient it follows)."""
    laws = WEAR_LAWS if laws is None else laws
    summaries = "; ".join(
        f'`"{name}"`: {cls.description}, `[sweep]` '
        + ", ".join(f"`{key}` in {declared.unit}" for key, declared in cls.coefficients.items())
        for name, cls in laws.items()
    )
    law = StudyKey("wear", "law", "text", f'"{DEFAULT_WEAR_LAW}"', "–", summaries)
    keys: dict[str, StudyKey] = {}
    for name, cls in laws.items():
        follows = cls.followers(dict.fromkeys(cls.coefficients))
        for key, declared in cls.coefficients.items():
            if key in keys:
                continue
            if key in follows:
                default = follows[key][0]
            elif name == DEFAULT_WEAR_LAW:
                default = "required (cyclic, fretting); [0] static"
            else:
                default = f'required with `law = "{name}"`'
            meaning = declared.meaning + (f" (`{name}` law)" if name != DEFAULT_WEAR_LAW else "")
            if key in cls.rules:  # the text it takes instead of a list, and what it means
                rule = cls.followers({**dict.fromkeys(cls.coefficients), key: cls.rules[key]})
                meaning += f', or `"{cls.rules[key]}"`: {rule[key][1]}'

            kind = "list of numbers" + (" or text" if key in cls.rules else "")
            keys[key] = StudyKey("sweep", key, kind, default, declared.unit, meaning)
    return law, list(keys.values())


def fatigue_keys(criteria=None) -> tuple[StudyKey, list[StudyKey]]:
    """``[fatigue] criteria`` (names of ``criteria``, default the registered ones, with what
    each evaluates) and one key per constant: the criteria that need it, its unit and
    meaning (the first criterion's that declares it)."""
    criteria = CRITERIA if criteria is None else criteria
    names = "; ".join(f'`"{name}"`: {cls.description}' for name, cls in criteria.items())
    meaning = f"{names}. Each needs its constants below, which have no defaults"
    listed = StudyKey("fatigue", "criteria", "list of texts", REQUIRED, "–", meaning)
    needed: dict[str, list[str]] = {}
    for name, cls in criteria.items():
        for constant in cls.constants:
            needed.setdefault(constant, []).append(name)
    constants = []
    for constant, users in needed.items():
        first = criteria[users[0]]
        constants.append(
            StudyKey(
                "fatigue",
                constant,
                "number",
                f"required ({', '.join(users)})",
                first.constants[constant].unit,
                first.constants[constant].meaning,
            )
        )
    return listed, constants


#: Sections in the order of the reference, each with what it describes; and every key of a
#: study file, section by section in the order of the reference.
SECTIONS, STUDY_KEYS = _read_table()
