"""Reading one TOML table of the study file: typed values, checked ranges, unknown keys, and
errors that name the file, the section, the key and the value."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from .sections import MISSING, StudyConfigError


def input_path(source: str, value: str) -> Path:
    """The file a study names with the text ``value`` (``[surface] path``, ``[calibrate]
    tests``): an absolute path as given, a relative one relative to the folder of the study
    file ``source`` (whatever the working directory; a study given as text, ``source`` not a
    file, has the working directory as its folder). Absolute and normalised (``..`` removed),
    symbolic links not followed."""
    folder = Path(source).parent if Path(source).is_file() else Path()
    return Path(os.path.abspath(folder / Path(value).expanduser()))


def compared_path(source: str, path: str | Path) -> str:
    """The form of an input file's absolute ``path`` that the results record and a resumed
    run compares: relative to the folder of the study file ``source`` when the file lies
    under it (so the same study gives the same results file, and resumes, from any working
    directory and after its folder is moved), else absolute."""
    folder = Path(os.path.abspath(Path(source).parent if Path(source).is_file() else Path()))
    try:
        return Path(path).relative_to(folder).as_posix()
    except ValueError:
        return str(path)


class Section:
    """Reads keys of one TOML table and remembers which ones were used."""

    def __init__(self, source: str, name: str, table: Any) -> None:
        if not isinstance(table, dict):
            raise StudyConfigError(source, name, table, "must be a table ([section])")
        self.source, self.name, self.table = source, name, table

    def error(self, key: str, value: Any, problem: str) -> StudyConfigError:
        return StudyConfigError(self.source, f"{self.name}.{key}", value, problem)

    def raw(self, key: str, default: Any = MISSING) -> Any:
        if key in self.table:
            return self.table[key]
        if default is MISSING:
            raise self.error(key, MISSING, "required key is missing")
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
        default: Any = MISSING,
        *,
        minimum: float | None = None,
        strict: bool = False,
        unit: str = "",
        maximum: float | None = None,
        why: str = "",
    ) -> float:
        """A finite number >= ``minimum`` (> with ``strict``) and <= ``maximum``; ``why`` says
        where the maximum comes from (in the error)."""
        value = self.raw(key, default)
        number = self._check_number(key, value, minimum=minimum, strict=strict, unit=unit)
        self._check_maximum(key, value, maximum, unit, why)
        return number

    def _check_maximum(self, key: str, value, maximum, unit: str, why: str) -> None:
        if maximum is not None and value > maximum:
            suffix = f" {unit}" if unit else ""
            reason = f" ({why})" if why else ""
            raise self.error(key, value, f"must be <= {maximum:g}{suffix}{reason}")

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

    def integer(
        self,
        key: str,
        default: Any = MISSING,
        *,
        minimum: int,
        maximum: int | None = None,
        why: str = "",
    ) -> int:
        """An integer in [``minimum``, ``maximum``]; ``why`` says where the maximum comes from.
        A float with an integer value (``1e9``) is named as such, not as "not a number"."""
        value = self.raw(key, default)
        if isinstance(value, float) and value.is_integer():
            raise self.error(key, value, f"must be an integer (write {int(value)})")
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, value, "must be an integer")
        if value < minimum:
            raise self.error(key, value, f"must be >= {minimum}")
        self._check_maximum(key, value, maximum, "", why)
        return int(value)

    def string(self, key: str, default: Any = MISSING) -> str:
        value = self.raw(key, default)
        if not isinstance(value, str) or not value.strip():
            raise self.error(key, value, "must be a non-empty string")
        return value

    def input_file(self, key: str) -> tuple[str, Path]:
        """``(value, file)``: the text of ``key`` and the existing file it names
        (:func:`input_path`: relative to the study file's folder); a missing file is an error
        naming the key, the value and the absolute path looked for."""
        value = self.string(key)
        path = input_path(self.source, value)
        if not path.is_file():
            raise self.error(key, value, f"no such file: {path} (a relative path is taken "
                             "from the study file's folder)")  # fmt: skip
        return value, path

    def poisson(self, key: str, limit) -> float:
        """Poisson's ratio within ``limit`` (``engine.study.settings.checks.Limit``)."""
        value = self.number(key)
        if not limit.holds(value):
            raise self.error(key, self.table[key], f"Poisson ratio must lie in {limit.accepted}")
        return value

    def number_list(
        self, key: str, default: Any = MISSING, *, minimum: float | None = None, unit: str = ""
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


class TomlSyntaxError(StudyConfigError):
    """Malformed TOML: the file and the line (``line``, 1-based; None when the parser gave
    none); ``key`` is the dotted key of a ``key = value`` line, "" for any other line."""

    def __init__(self, source: str, line: int | None, text: str, key: str, problem: str) -> None:
        self.source, self.key, self.value, self.problem = source, key, MISSING, problem
        self.line = line
        where = f"line {line}" if line is not None else "the file"
        if key:
            section, _, name = key.partition(".")
            where += f", [{section}] {name}"
        elif text.strip():
            where += f" ({text.strip()[:60]!r})"
        ValueError.__init__(self, f"{source}: {where}: {problem}")


def toml_error(source: str, text: str, error: Exception) -> StudyConfigError:
    """Malformed TOML, located by its line: with the section and key when the line is a
    ``key = value`` line (``line 14, [mesh] n: malformed TOML: Cannot overwrite a value (at
    line 14, column 4)``), with the line's text otherwise (a table header: the section
    above it is not to blame)."""
    message = str(error)
    line_number = getattr(error, "lineno", None)
    if line_number is None and "(at line " in message:
        try:
            line_number = int(message.split("(at line ")[1].split(",")[0])
        except ValueError:
            line_number = None
    key, offending = "", ""
    if line_number is not None:
        lines = text.splitlines()
        offending = lines[line_number - 1] if 0 < line_number <= len(lines) else ""
        section = ""
        for line in lines[: line_number - 1]:
            stripped = line.strip()
            if stripped.startswith("[") and "]" in stripped:
                section = stripped.strip("[]").strip()
        name = offending.split("=")[0].strip() if "=" in offending else ""
        is_key_line = name and not offending.lstrip().startswith("[") and " " not in name
        if section and is_key_line:
            key = f"{section}.{name}"
    problem = f"malformed TOML: {message}"
    if "Cannot overwrite a value" in message:
        problem += " (the key is given twice)"
    return TomlSyntaxError(source, line_number, offending, key, problem)
