"""The ``[sweep]`` table's dotted keys and ``zip`` groups: the axes of the plan's product, and
a study's tables with a case's swept values written in."""

from __future__ import annotations

from typing import Any

from engine.study.settings.sections import MISSING, StudyConfigError, SweepAxis
from engine.study.units import SWEEPABLE, SWEEPABLE_TEXT

SECTIONS_REQUIRED = ("study", "material", "punch", "mesh", "loading", "sweep")
SECTIONS_OPTIONAL = ("subsurface", "solver", "testing", "wear", "fatigue", "surface")


def axis_error(source: str, axis: SweepAxis, position: int, error: StudyConfigError):
    """Re-word a section's error for the swept value that caused it."""
    key = error.key if error.key in axis.keys else axis.keys[0]
    value = axis.values[position][axis.keys.index(key)]
    section, _, name = error.key.partition(".")
    shown = "" if error.value is MISSING else f" = {error.value!r}"
    where = "" if error.key == key else f" (then [{section}] {name}{shown}: {error.problem})"
    problem = error.problem if error.key == key else "invalid"
    return StudyConfigError(
        source,
        f"sweep.{key}",
        value,
        f"list position {position + 1} of {len(axis)}: {problem}{where}",
    )


def substituted(tables: dict[str, Any], settings: dict[str, Any]) -> dict[str, Any]:
    """A copy of the TOML tables with the dotted ``settings`` written into their sections."""
    data = {name: dict(t) if isinstance(t, dict) else t for name, t in tables.items()}
    for key, value in settings.items():
        section, name = key.split(".", 1)
        data.setdefault(section, {})[name] = value
    return data


def split_sweep(source: str, data: dict[str, Any]) -> tuple[tuple[SweepAxis, ...], dict]:
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
        elif isinstance(value, dict) and name in SECTIONS_REQUIRED + SECTIONS_OPTIONAL:
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
    if key not in SWEEPABLE and key not in SWEEPABLE_TEXT:
        known = ", ".join((*SWEEPABLE, *SWEEPABLE_TEXT))
        raise StudyConfigError(source, error_key, value, f"not a sweepable key (known: {known})")
    section, name = key.split(".", 1)
    if isinstance(data.get(section), dict) and name in data[section]:
        raise StudyConfigError(
            source, error_key, value, f"also set in [{section}]: give it in one place only"
        )
    values = value if isinstance(value, list) else [value]
    if not values:
        raise StudyConfigError(source, error_key, value, "must list at least one value")
    text = key in SWEEPABLE_TEXT  # a list of strings; the section's parser checks each one
    for position, item in enumerate(values):
        if text and not isinstance(item, str):
            problem = "must be a text (a quoted string)"
        elif not text and (isinstance(item, bool) or not isinstance(item, (int, float))):
            problem = "must be a number"
        else:
            continue
        where = f"list position {position + 1} of {len(values)}"
        raise StudyConfigError(source, error_key, item, f"{where}: {problem}")
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
