"""The ``[calibrate]`` section and its tests file, validated.

A calibration study has a ``[search]`` section (the quantity measured at the threshold, e.g.
``loading.force_amplitude``, and the column/target that define the threshold, e.g.
``crossland_risk_critical = 1``) and a ``[calibrate]`` section:

- ``tests`` — a CSV file (a relative path is taken from the study file's folder, an absolute
  one as given; the results record it relative to that folder), one row per test: an id column,
  dotted study keys that differ between tests (any sweepable key, or ``mu1``) and the
  measured threshold (in the searched parameter's units);
- ``id``, ``measured`` — the names of the id and measured columns;
- ``fit`` — the study keys to fit (sweepable keys, e.g. ``fatigue.length``) with ``low`` and
  ``high`` lists of the same length; an empty ``fit`` only predicts. ``"search.target"``
  fits the column's value at the threshold itself (e.g. the SWT parameter at the fatigue
  limit, σ_d²/E in MPa, when σ_d is not known);
- ``calibrate_on`` — the ids of the tests the fit uses; every other test is predicted;
- ``fit_rtol`` [1e-3] — the fit's relative tolerance on each fitted value;
- ``max_evaluations`` [40] — evaluations of the objective (each a threshold search per
  calibration test) the fit may take.

``[search] relative_to = "mu_load"`` gives the bracket ``low``/``high`` as fractions of μP of
each test (μ = ``mu1``, P = the test's ``loading.load``); without it they are absolute.

Errors name the file, the row (1 = the first data row) and the column; nothing is written
before the section and its tests file are valid (:class:`CalibrationInputError`, a
:class:`~engine.study.config.StudyConfigError`: exit code 2).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from engine.study.settings.checks import LIMITS
from engine.study.settings.reader import compared_path, input_path
from engine.study.settings.sections import MISSING, StudyConfigError
from engine.study.units import SWEEPABLE

__all__ = [
    "CalibrationInputError",
    "CalibrateSpec",
    "TestRow",
    "parse_calibrate",
    "check_fit_bounds",
    "read_tests",
    "RELATIVE_TO",
    "TARGET_KEY",
    "test_keys",
]

#: Ways to give the [search] bracket per test: absolute values, or fractions of μP.
RELATIVE_TO = ("", "mu_load")
CALIBRATE_KEYS = (
    "tests", "id", "measured", "fit", "low", "high", "calibrate_on", "fit_rtol",
    "max_evaluations",
)  # fmt: skip
#: The fitted key that stands for the search's target (the column's value at the threshold).
TARGET_KEY = "search.target"
#: Keys a test may set besides the dotted sweepable keys: the friction coefficient.
EXTRA_TEST_KEYS = {"mu1": "1"}


class CalibrationInputError(StudyConfigError):
    """A bad ``[calibrate]`` section or tests file: names the file, and for the tests file
    the row (1-based, data rows) and the column."""

    def __init__(self, source: str, key: str, value: Any, problem: str, *, row=None, column=None):
        self.row, self.column = row, column
        super().__init__(source, key, value, problem)
        if row is not None or column is not None:
            where = ", ".join(
                part
                for part in (
                    f"row {row}" if row is not None else "",
                    f"column {column!r}" if column is not None else "",
                )
                if part
            )
            shown = "" if value is MISSING else f" = {value!r}"
            self.args = (f"{source}: {where}{shown}: {problem}",)


def test_keys() -> dict[str, str]:
    """Keys a tests file's columns may name, with their units."""
    return {**EXTRA_TEST_KEYS, **SWEEPABLE}


@dataclass(frozen=True)
class TestRow:
    """One test: its ``id``, its study ``settings`` ((dotted key, value) in the file's
    column order) and the ``measured`` threshold (the searched parameter's units)."""

    __test__ = False  # not a pytest class

    id: str
    settings: tuple[tuple[str, float], ...]
    measured: float


@dataclass(frozen=True)
class CalibrateSpec:
    """A validated ``[calibrate]`` section (module docstring) with its tests."""

    tests_path: Path
    id_column: str
    measured_column: str
    tests: tuple[TestRow, ...]
    fit: tuple[str, ...] = ()
    low: tuple[float, ...] = ()
    high: tuple[float, ...] = ()
    calibrate_on: tuple[str, ...] = ()
    relative_to: str = ""
    fit_rtol: float = 1e-3
    max_evaluations: int = 40
    keys: tuple[str, ...] = field(default=())  # the tests' setting columns, file order
    tests_file: str = ""  # ``tests`` as recorded (``compared_path``); ``tests_path``: absolute

    def role(self, test_id: str) -> str:
        """``"calibrate"`` for a test the fit uses, ``"predict"`` otherwise."""
        return "calibrate" if test_id in self.calibrate_on else "predict"

    def resolved(self) -> dict[str, Any]:
        """The section as TOML-able data (stored with the results)."""
        return {
            "tests": self.tests_file or str(self.tests_path),
            "id": self.id_column,
            "measured": self.measured_column,
            "fit": list(self.fit),
            "low": list(self.low),
            "high": list(self.high),
            "calibrate_on": list(self.calibrate_on),
            "relative_to": self.relative_to,
            "fit_rtol": self.fit_rtol,
            "max_evaluations": self.max_evaluations,
        }


def _number(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(text)
    return value


def read_tests(
    path: Path, id_column: str, measured_column: str, parameter: str
) -> tuple[tuple[TestRow, ...], tuple[str, ...]]:
    """The tests of ``path`` (CSV, ``#`` lines are comments): rows and setting columns.

    Refuses, naming the file, row and column: a missing file, a column that is neither the
    id, the measured column nor a study key a test may set (or the searched ``parameter``
    itself), a duplicate id, an empty or non-numeric value, a measured threshold ≤ 0.
    """
    source = str(path)
    if not path.is_file():
        raise CalibrationInputError(source, "calibrate.tests", MISSING, "no such file")
    lines = [line for line in path.read_text().splitlines() if not line.lstrip().startswith("#")]
    reader = csv.reader(lines)
    header = [name.strip() for name in next(reader, [])]
    if not header:
        raise CalibrationInputError(source, "calibrate.tests", MISSING, "no header row", row=0)
    known = test_keys()
    for name in (id_column, measured_column):
        if name not in header:
            raise CalibrationInputError(
                source, "calibrate.tests", MISSING, "column is missing", row=0, column=name
            )
    for name in header:
        if name in (id_column, measured_column):
            continue
        if name == parameter:
            raise CalibrationInputError(
                source, "calibrate.tests", MISSING,
                "is the searched parameter: the search sets it", row=0, column=name,
            )  # fmt: skip
        if name not in known:
            raise CalibrationInputError(
                source, "calibrate.tests", MISSING,
                "not a study key a test may set (a sweepable dotted key or mu1)",
                row=0, column=name,
            )  # fmt: skip
    if len(set(header)) != len(header):
        twice = next(name for name in header if header.count(name) > 1)
        raise CalibrationInputError(
            source, "calibrate.tests", MISSING, "column given twice", row=0, column=twice
        )
    keys = tuple(name for name in header if name not in (id_column, measured_column))
    tests, seen = [], set()
    for number, cells in enumerate(reader, start=1):
        if not any(cell.strip() for cell in cells):
            continue
        if len(cells) != len(header):
            raise CalibrationInputError(
                source, "calibrate.tests", cells,
                f"has {len(cells)} cells, the header {len(header)}", row=number,
            )  # fmt: skip
        values = {name: cell.strip() for name, cell in zip(header, cells, strict=True)}
        test_id = values[id_column]
        if not test_id:
            raise CalibrationInputError(
                source, "calibrate.tests", "", "empty id", row=number, column=id_column
            )
        if test_id in seen:
            raise CalibrationInputError(
                source, "calibrate.tests", test_id, "duplicate id", row=number, column=id_column
            )
        seen.add(test_id)
        numbers = {}
        for name in (*keys, measured_column):
            try:
                numbers[name] = _number(values[name])
            except ValueError:
                raise CalibrationInputError(
                    source, "calibrate.tests", values[name], "not a finite number",
                    row=number, column=name,
                ) from None  # fmt: skip
        if not numbers[measured_column] > 0.0:
            raise CalibrationInputError(
                source, "calibrate.tests", numbers[measured_column],
                "a measured threshold must be > 0 (errors are relative to it)",
                row=number, column=measured_column,
            )  # fmt: skip
        settings = tuple((name, numbers[name]) for name in keys)
        tests.append(TestRow(test_id, settings, numbers[measured_column]))
    if not tests:
        raise CalibrationInputError(source, "calibrate.tests", MISSING, "no test rows")
    return tuple(tests), keys


def parse_calibrate(
    source: str, table: Any, search, relative_to: Any = "", swept: tuple[str, ...] = ()
) -> CalibrateSpec:
    """Validate the ``[calibrate]`` table of study file ``source`` (``search``: its
    :class:`~engine.study.search.SearchSpec`; ``relative_to``: ``[search] relative_to``)."""

    def error(key: str, value: Any, problem: str) -> CalibrationInputError:
        return CalibrationInputError(source, f"calibrate.{key}", value, problem)

    if not isinstance(table, dict):
        raise CalibrationInputError(source, "calibrate", table, "must be a table ([calibrate])")
    if search is None:
        raise CalibrationInputError(
            source, "search", MISSING,
            "[calibrate] needs a [search] section: the measured quantity and the threshold",
        )  # fmt: skip
    for key, value in table.items():
        if key not in CALIBRATE_KEYS:
            raise error(key, value, f"unknown key (known: {', '.join(CALIBRATE_KEYS)})")
    for key in ("tests", "id", "measured"):
        if not isinstance(table.get(key, MISSING), str) or not table[key]:
            raise error(key, table.get(key, MISSING), "required: a non-empty text")
    if relative_to not in RELATIVE_TO:
        raise CalibrationInputError(
            source, "search.relative_to", relative_to,
            'must be "mu_load" (low and high as fractions of μP) or left out (absolute)',
        )  # fmt: skip
    if relative_to and not 0.0 < search.low < search.high < 1.0:
        raise CalibrationInputError(
            source, "search.high", search.high,
            "with relative_to = \"mu_load\", low and high are fractions of μP: 0 < low < high < 1",
        )  # fmt: skip
    fit = table.get("fit", [])
    if not isinstance(fit, list) or not all(isinstance(key, str) for key in fit):
        raise error("fit", fit, "must be a list of dotted study keys")
    for key in fit:
        if key == TARGET_KEY:
            if search.categorical:
                raise error("fit", key, "the search's target is a text: nothing to fit")
            continue
        if key not in SWEEPABLE or key in _INTEGER_KEYS:
            raise error("fit", key, "not a continuous sweepable key")
        if key == search.parameter:
            raise error("fit", key, "is the searched parameter")
        if key in swept:
            raise error("fit", key, "is swept in [sweep]: fit it or sweep it")
    if len(set(fit)) != len(fit):
        raise error("fit", fit, "a key is listed twice")
    bounds = {}
    for key in ("low", "high"):
        values = table.get(key, [])
        if (
            not isinstance(values, list)
            or len(values) != len(fit)
            or any(isinstance(v, bool) or not isinstance(v, int | float) for v in values)
            or not all(math.isfinite(v) for v in values)
        ):
            raise error(
                key, values, f"must be a list of {len(fit)} finite numbers (one per fit key)"
            )
        bounds[key] = tuple(float(v) for v in values)
    for key, low, high in zip(fit, bounds["low"], bounds["high"], strict=True):
        if not low < high:
            raise error("high", high, f"must be greater than low = {low} ({key})")
    fit_rtol = table.get("fit_rtol", 1e-3)
    limit = LIMITS["calibrate.fit_rtol"]
    if (
        isinstance(fit_rtol, bool)
        or not isinstance(fit_rtol, int | float)
        or not limit.holds(fit_rtol)
    ):
        raise error("fit_rtol", fit_rtol, f"must be a number in {limit.accepted}")
    evaluations = table.get("max_evaluations", 40)
    limit = LIMITS["calibrate.max_evaluations"]
    if (
        isinstance(evaluations, bool)
        or not isinstance(evaluations, int)
        or not limit.holds(evaluations)
    ):
        raise error("max_evaluations", evaluations, f"must be an integer in {limit.accepted}")
    calibrate_on = table.get("calibrate_on", [])
    if not isinstance(calibrate_on, list) or not all(isinstance(i, str) for i in calibrate_on):
        raise error("calibrate_on", calibrate_on, "must be a list of test ids (text)")
    if fit and not calibrate_on:
        raise error("calibrate_on", calibrate_on, "a fit needs at least one calibration test")
    path = input_path(source, table["tests"])  # relative to the study file's folder
    if not path.is_file():
        raise error(
            "tests", table["tests"],
            f"no such file: {path} (a relative path is taken from the study file's folder)",
        )  # fmt: skip
    tests, keys = read_tests(path, table["id"], table["measured"], search.parameter)
    ids = [test.id for test in tests]
    for test_id in calibrate_on:
        if test_id not in ids:
            raise CalibrationInputError(
                str(path), "calibrate.calibrate_on", test_id,
                f"not an id of the tests file (column {table['id']!r}; {source} [calibrate])",
                column=table["id"],
            )  # fmt: skip
    for key in keys:
        if key in fit:
            raise CalibrationInputError(
                str(path), "calibrate.fit", key, "is fitted: it cannot differ between tests",
                row=0, column=key,
            )  # fmt: skip
    return CalibrateSpec(
        tests_path=path,
        id_column=table["id"],
        measured_column=table["measured"],
        tests=tests,
        fit=tuple(fit),
        low=bounds["low"],
        high=bounds["high"],
        calibrate_on=tuple(calibrate_on),
        relative_to=relative_to,
        fit_rtol=float(fit_rtol),
        max_evaluations=evaluations,
        keys=keys,
        tests_file=compared_path(source, path),
    )


def check_fit_bounds(config) -> None:
    """The study must be valid at both ends of every fitted key's range (a fitted constant
    outside the magnitudes the parser accepts is refused here, not in the middle of a fit),
    naming the key and the end."""
    spec = config.calibrate
    if spec is None:
        return
    for number, key in enumerate(spec.fit):
        if key == TARGET_KEY:
            continue
        for end, values in (("low", spec.low), ("high", spec.high)):
            settings = config.at_search_end(((key, values[number]),), "low")
            try:
                config.for_case(settings)
            except StudyConfigError as error:
                raise CalibrationInputError(
                    config.source, f"calibrate.{end}", values[number],
                    f"{key} = {values[number]!r} makes the study invalid: {error.problem}",
                ) from None  # fmt: skip


_INTEGER_KEYS = ("mesh.n", "loading.steps", "loading.cycles", "subsurface.layers", "solver.maxiter")
