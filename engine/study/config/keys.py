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
never written in ``keys.toml``; a profile another package registers describes its keys the
same way (:func:`punch_keys`).

Units are those of the paper: mm, N, MPa, wear coefficients in 1/MPa, angles in degrees; "1"
is dimensionless and "–" marks a text or a list that has no unit.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from importlib.resources import files

from engine.geometry import DEFAULT_SHAPE, PROFILES

__all__ = ["REQUIRED", "SECTIONS", "StudyKey", "STUDY_KEYS"]

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
    keys = tuple(
        key
        for section, entries in table.items()
        for key in (
            punch_keys(PROFILES.builtins)
            if section == "punch"
            else [StudyKey(section, name, **fields) for name, fields in entries["keys"].items()]
        )
    )
    return sections, keys


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


#: Sections in the order of the reference, each with what it describes; and every key of a
#: study file, section by section in the order of the reference.
SECTIONS, STUDY_KEYS = _read_table()
