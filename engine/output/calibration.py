"""The calibration table: ``NAME_calibration.csv`` beside the summary and the group
``/calibration`` of the results file, and :func:`load_calibration` to read either.

One row per test (the tests file's order): ``id``, the test's keys (their units), then

========== ============================ =====================================================
column     units                        meaning
========== ============================ =====================================================
measured   the searched parameter's     the measured threshold (tests file)
predicted  the searched parameter's     the engine's threshold at the fitted values
error      1                            predicted / measured − 1
role       –                            ``calibrate`` (used by the fit) or ``predict``
lower      the searched parameter's     the final bracket of the test's search (its
upper      the searched parameter's     ends when the search was not bracketed)
lower_v…   the column's                 ``lower_value``, ``upper_value``: the threshold
                                        column at ``lower`` and ``upper``
steps      –                            values of the parameter the final search took
status     –                            how the final search ended (``converged`` …)
message    –                            why it did not converge
========== ============================ =====================================================

The group's attributes: ``fitted`` (JSON: key → value), ``fitted_units`` (JSON), ``fit_status``
(``converged``, ``at-bound``, ``not-converged``, ``failed``, ``predict-only``),
``fit_message``, ``fit_evaluations``, ``fit_residual`` (√Σ r² of the calibration tests),
``calibrate`` and ``search`` (JSON: the sections); subgroup ``evaluations`` (one row per
evaluation of the fit: the values tried, the calibration tests' thresholds, Σ r²) and
``contact`` (the kept contact solutions: test, x, the evaluation that solved it, converged).
The CSV starts with ``#`` lines holding the fit and its status.
"""

from __future__ import annotations

import csv
import io
import json
import math
import numbers
import os
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from engine.output.space import MARGIN, OutputFull, free_bytes, is_no_space
from engine.output.summary import column_unit
from engine.output.thresholds import read_table_group, split_header_units

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "calibration_csv_path",
    "write_calibration",
    "load_calibration",
    "CALIBRATION_GROUP",
    "TABLE_COLUMNS",
    "COLUMNS",
    "GROUP_ATTRIBUTES",
    "SUBGROUPS",
]

CALIBRATION_GROUP = "calibration"
TABLE_COLUMNS = ("measured", "predicted", "error", "role", "lower", "upper", "lower_value",
                 "upper_value", "steps", "status", "message")  # fmt: skip
#: The unit of a column that holds values of the searched parameter, or of the searched column.
PARAMETER_UNIT = "the searched parameter's unit"
COLUMN_UNIT = "the searched column's unit"
#: Every column of the table after the tests' own keys: (unit, description). The units stored
#: are the searched parameter's and column's (``[search]``); "1" dimensionless, "–" text.
COLUMNS = {
    "id": ("–", "the test's id (tests file)"),
    "measured": (PARAMETER_UNIT, "measured threshold (tests file)"),
    "predicted": (PARAMETER_UNIT, "threshold the engine predicts at the fitted values"),
    "error": ("1", "predicted / measured - 1"),
    "role": ("–", "calibrate: used by the fit; predict: predicted with the fitted values"),
    "lower": (PARAMETER_UNIT, "final bracket of the test's search, lower end"),
    "upper": (PARAMETER_UNIT, "final bracket of the test's search, upper end"),
    "lower_value": (COLUMN_UNIT, "the threshold column at lower"),
    "upper_value": (COLUMN_UNIT, "the threshold column at upper"),
    "steps": ("1", "values of the searched parameter the final search took"),
    "status": ("–", "how the final search ended"),
    "message": ("–", "why the search did not converge"),
}
_DESCRIPTIONS = {name: description for name, (_, description) in COLUMNS.items()}
#: The attributes of the group ``/calibration`` and its subgroups.
GROUP_ATTRIBUTES = {
    "column_order": "the table's columns in order: the test's id and keys, then the columns",
    "fitted": "JSON: each fitted key and its value",
    "fitted_units": "JSON: each fitted key and its unit",
    "fit_status": "how the fit ended: converged, at-bound, not-converged, failed or predict-only",
    "fit_message": "why the fit ended so",
    "fit_evaluations": "evaluations of the fit (each: one threshold search per calibration test)",
    "fit_residual": "√Σ r² over the calibration tests, r = predicted / measured − 1",
    "column": "the searched summary column ([search] column)",
    "target": "the column's value at the threshold ([search] target, or its fitted value)",
    "calibrate": "JSON: the [calibrate] section",
    "search": "JSON: the [search] section",
}
#: The subgroups of ``/calibration``: one row per evaluation, and the kept contact solutions.
SUBGROUPS = {
    "evaluations": "one row per evaluation of the fit: the values tried, the calibration "
    "tests' thresholds, Σ r²",
    "contact": "the kept contact solutions: test, x (the searched value), the evaluation "
    "that solved it, converged (1 or 0)",
}


def _units(config, rows) -> dict[str, str]:
    line = config.punch.is_line
    declared = {
        PARAMETER_UNIT: column_unit(config.search.parameter, line),
        COLUMN_UNIT: column_unit(config.search.column, line),
        "1": "",
        "–": "",
    }
    units = {}
    for name in _columns(rows):
        if name in COLUMNS:
            unit = declared[COLUMNS[name][0]]
        else:
            unit = column_unit(name, line)
        units[name] = "" if unit == "1" else unit
    return units


def _columns(rows) -> list[str]:
    names: dict[str, None] = {}
    for row in rows:
        names.update((key, None) for key in row if key not in TABLE_COLUMNS)
    return [*names, *TABLE_COLUMNS]


def _fitted_units(config, fitted) -> dict[str, str]:
    line = config.punch.is_line
    return {
        key: column_unit(config.search.column if key == "search.target" else key, line)
        for key in fitted
    }


def _array(values: list[Any]) -> np.ndarray:
    if any(isinstance(value, str) for value in values):
        return np.array([str(v) for v in values], dtype=h5py.string_dtype())
    if values and all(isinstance(v, numbers.Integral) for v in values):
        return np.array(values, dtype=np.int64)
    return np.array(values, dtype=np.float64)


def _cell(value: Any) -> str:
    if value is None or (isinstance(value, numbers.Real) and math.isnan(value)):
        return ""
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value) + 0.0)
    return str(value)


def _write_table(group: h5py.Group, rows, units, descriptions) -> None:
    columns = _columns(rows) if rows and "id" in rows[0] else list(rows[0]) if rows else []
    group.attrs["column_order"] = columns
    for name in columns:
        dataset = group.create_dataset(
            name, data=_array([row.get(name, math.nan) for row in rows]), track_times=False
        )
        dataset.attrs["units"] = units.get(name, "") or "1"
        dataset.attrs["description"] = descriptions.get(name, name)


def calibration_csv_path(summary_path) -> Path:
    """``NAME_calibration.csv`` beside the summary ``NAME.csv``."""
    summary_path = Path(summary_path)
    return summary_path.with_name(f"{summary_path.stem}_calibration.csv")


def write_calibration(config, outcome, store, store_name) -> tuple[Path, Path]:
    """Write the results file (the group ``/calibration``) and ``NAME_calibration.csv``,
    each to a temporary file renamed into place; returns both paths. ``store``: the kept
    contact solutions (``engine.calibration.search.ContactStore``); ``store_name(test)``
    the name under which this study keeps a test's (solutions of another study left out)."""
    output = Path(config.study.output)
    temporary = output.with_name(f".{output.name}.tmp")
    csv_path = calibration_csv_path(config.study.summary_path)
    try:
        _write_file(config, outcome, store, store_name, output, temporary)
        _write_csv(csv_path, outcome.rows, _units(config, outcome.rows), outcome.fit, config)
    except Exception as error:
        temporary.unlink(missing_ok=True)
        if not is_no_space(error):
            raise
        raise OutputFull(output, MARGIN, free_bytes(output)) from None
    return output, csv_path


def _write_file(config, outcome, store, store_name, output: Path, temporary: Path) -> None:
    """The results file: written to ``temporary``, renamed to ``output`` once whole."""
    rows, fit = outcome.rows, outcome.fit
    units = _units(config, rows)
    output.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(temporary, "w", track_order=True) as file:
        file.attrs["study_toml"] = config.to_toml()
        file.attrs["name"] = config.study.name
        group = file.create_group(CALIBRATION_GROUP, track_order=True)
        descriptions = dict(_DESCRIPTIONS)
        descriptions.update(
            {key: f"{key} of the test (tests file)" for key in config.calibrate.keys}
        )
        _write_table(group, rows, units, descriptions)
        group.attrs["fitted"] = json.dumps(fit.values)
        group.attrs["fitted_units"] = json.dumps(_fitted_units(config, fit.values))
        group.attrs["fit_status"] = fit.status
        group.attrs["fit_message"] = fit.message
        group.attrs["fit_evaluations"] = fit.evaluations
        group.attrs["fit_residual"] = fit.residual
        group.attrs["column"] = config.search.column
        group.attrs["target"] = _target(config, fit)
        group.attrs["calibrate"] = json.dumps(config.calibrate.resolved())
        group.attrs["search"] = json.dumps(
            {k: getattr(config.search, k) for k in ("parameter", "low", "high", "column",
                                                     "target", "rtol", "atol", "method")}
        )  # fmt: skip
        evaluations = group.create_group("evaluations", track_order=True)
        if outcome.evaluations:
            _write_table(evaluations, outcome.evaluations, {}, {})
        contact = group.create_group("contact", track_order=True)
        order = {test.id: number for number, test in enumerate(config.calibrate.tests)}
        names = {store_name(test) for test in config.calibrate.tests}
        entries = sorted(
            store.entries.values(),
            key=lambda e: (e.evaluation, order.get(e.test.split("@")[0], -1), e.x),
        )
        table = [
            {
                "test": e.test.split("@")[0],
                "x": e.x,
                "evaluation": e.evaluation,
                "converged": int(e.converged),
            }
            for e in entries
            if e.test in names
        ]
        if table:
            _write_table(contact, table, {"x": units.get("measured", "")}, {
                "test": "the test's id", "x": "the searched parameter's value",
                "evaluation": "the fit's evaluation that solved it (the last: the predictions)",
                "converged": "1: every contact solve of the case converged",
            })  # fmt: skip
    os.replace(temporary, output)


def _target(config, fit) -> float:
    """The column's value at the threshold: fitted (``search.target``) or the study's."""
    return float(fit.values.get("search.target", config.search.target))


def _write_csv(path: Path, rows, units, fit, config) -> None:
    text = io.StringIO()
    text.write(f"# calibration of {config.study.name}: fit {fit.status}")
    text.write(f" ({fit.message})\n" if fit.message else "\n")
    text.write(f"# threshold: {config.search.column} = {_target(config, fit)!r}\n")
    for key, value in fit.values.items():
        unit = _fitted_units(config, fit.values)[key]
        text.write(f"# fitted {key} = {value!r}" + (f" [{unit}]" if unit and unit != "1" else "")
                   + "\n")  # fmt: skip
    writer = csv.writer(text, lineterminator="\n")
    columns = _columns(rows)
    writer.writerow([f"{name} [{units[name]}]" if units[name] else name for name in columns])
    writer.writerows([_cell(row.get(name)) for name in columns] for row in rows)
    temporary = path.with_name(f".{path.name}.tmp")
    try:
        temporary.write_text(text.getvalue(), encoding="utf-8")
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


_FITTED = re.compile(r"^# fitted (?P<key>\S+) = (?P<value>\S+)")
_THRESHOLD = re.compile(r"^# threshold: (?P<column>\S+) = (?P<value>\S+)")


def load_calibration(path: str | Path) -> pd.DataFrame:
    """The calibration table of a study with a ``[calibrate]`` section, as a DataFrame.

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) or ``NAME_calibration.csv``.

    Returns
    -------
    pandas.DataFrame
        One row per test: its id and keys, ``measured``, ``predicted`` (the searched
        parameter's units), ``error`` (predicted/measured − 1), ``role`` (``calibrate`` or
        ``predict``), the final bracket, ``steps``, ``status``; ``frame.attrs["fitted"]``
        maps each fitted key to its value, ``frame.attrs["units"]`` each column to its unit,
        ``frame.attrs["fit_status"]`` says how the fit ended, ``frame.attrs["column"]`` and
        ``["target"]`` define the threshold.

    Examples
    --------
    >>> frame = engine.load_calibration("results/fouvry_crack_nucleation.h5")  # doctest: +SKIP
    >>> frame.attrs["fitted"]                                                  # doctest: +SKIP
    {'fatigue.length': 0.0312...}
    """
    import pandas as pd

    path = Path(path)
    if path.suffix.lower() not in (".h5", ".hdf5"):
        lines = path.read_text(encoding="utf-8").splitlines()
        fitted, status, threshold = {}, "", {}
        for line in lines:
            match = _FITTED.match(line)
            if match:
                fitted[match["key"]] = float(match["value"])
            elif _THRESHOLD.match(line):
                found = _THRESHOLD.match(line)
                threshold = {"column": found["column"], "target": float(found["value"])}
            elif line.startswith("# calibration of") and ": fit " in line:
                status = line.split(": fit ", 1)[1].split(" ", 1)[0]
        body = "\n".join(line for line in lines if not line.startswith("#"))
        frame = pd.read_csv(io.StringIO(body), dtype={"id": str, "role": str, "status": str,
                                                      "message": str})  # fmt: skip
        units = split_header_units(frame)
        frame.attrs.update(units=units, fitted=fitted, fit_status=status, **threshold)
        return frame
    with h5py.File(path, "r") as file:
        group = file.get(CALIBRATION_GROUP)
        if group is None:
            raise KeyError(f"{path}: no calibration table (the study has no [calibrate] section)")
        data, units = read_table_group(group, [str(n) for n in group.attrs["column_order"]])
        attrs = {
            "units": units,
            "fitted": json.loads(group.attrs["fitted"]),
            "fitted_units": json.loads(group.attrs["fitted_units"]),
            "fit_status": str(group.attrs["fit_status"]),
            "fit_message": str(group.attrs["fit_message"]),
            "fit_evaluations": int(group.attrs["fit_evaluations"]),
            "column": str(group.attrs["column"]),
            "target": float(group.attrs["target"]),
        }
    frame = pd.DataFrame(data)
    frame.attrs.update(attrs)
    return frame
