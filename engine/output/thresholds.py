"""Thresholds table of a study with a ``[search]`` section: one row per search.

Each combination of the ``[sweep]`` gets one search (:class:`engine.study.search.SearchCampaign`)
and one row: its parameters (``case_id`` of the combination, mu1, mu2, wear1, wear2, beta and
every swept dotted key, in the summary's units), then ``threshold``, the final bracket
``lower`` / ``upper`` (the searched parameter's units), the column's values there
``lower_value`` / ``upper_value`` (the column's units), ``steps`` (cases taken) and
``status`` (``converged``, ``not-bracketed``, ``not-converged``, ``failed``, ``unfinished``)
with a ``message`` when it did not converge. ``threshold`` is empty (NaN) unless converged.

Stored twice, both rewritten at the end of every run (an interrupted run lists its open
searches as ``unfinished``):

- in the results file, group ``/thresholds`` (:data:`engine.schema.THRESHOLDS_GROUP`): one
  1-D dataset per column with ``units`` and ``description``; the search's settings as the
  group's attributes (and ``column_order``);
- beside the summary CSV as ``NAME_thresholds.csv``, the units in the header
  (``threshold [mm]``).

``engine.load_thresholds(path)`` reads either into a DataFrame (units in ``frame.attrs``).
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import numbers
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from engine.commands import WrongFileError
from engine.schema import CASES_GROUP, THRESHOLDS_GROUP, CaseStatus, threshold_columns

from .summary import check_readable, column_unit, write_text_atomically

if TYPE_CHECKING:
    import pandas as pd

    from engine.study.search import SearchSpec

__all__ = [
    "thresholds_path",
    "table_units",
    "write_thresholds",
    "write_thresholds_csv",
    "load_thresholds",
    "completed_rows",
]

SEARCH_COLUMNS = (
    "threshold",
    "lower",
    "upper",
    "lower_value",
    "upper_value",
    "steps",
    "status",
    "message",
)
_TEXT = ("case_id", "status", "message")


def thresholds_path(summary_path: str | Path) -> Path:
    """``NAME_thresholds.csv`` beside the summary CSV ``NAME.csv``."""
    summary_path = Path(summary_path)
    return summary_path.with_name(f"{summary_path.stem}_thresholds.csv")


def table_units(rows: list[dict[str, Any]], spec: SearchSpec, line: bool = False) -> dict[str, str]:
    """Unit of every column of the table ("" for text and dimensionless columns) in a 3-D or
    (``line``) a line contact."""
    specs = _search_specs(spec, line)
    units = {}
    for name in _columns(rows):
        if name in specs:
            unit = specs[name].units
            units[name] = "" if unit == "1" or name in _TEXT else unit
        else:
            units[name] = "" if name in _TEXT else column_unit(name, line)
    return units


def _search_specs(spec: SearchSpec, line: bool = False) -> dict:
    parameter_unit = column_unit(spec.parameter, line) or "1"
    column = column_unit(spec.column, line)
    return threshold_columns(spec.parameter, parameter_unit, spec.column, column)


def _columns(rows: list[dict[str, Any]]) -> list[str]:
    names: dict[str, None] = {}
    for row in rows:
        names.update((key, None) for key in row if key not in SEARCH_COLUMNS)
    return [*names, *SEARCH_COLUMNS]


def write_thresholds(
    file: h5py.File,
    csv_path: str | Path,
    rows: list[dict[str, Any]],
    spec: SearchSpec,
    line: bool = False,
) -> None:
    """Write the table into ``file`` (replacing ``/thresholds``) and as CSV (atomically;
    ``csv_path`` None: the file only); ``line``: a line contact's study (units per unit
    length)."""
    if THRESHOLDS_GROUP in file:
        del file[THRESHOLDS_GROUP]
    group = file.create_group(THRESHOLDS_GROUP)
    settings = dataclasses.asdict(spec)
    for name, value in settings.items():
        group.attrs[name] = value
    specs = _search_specs(spec, line)
    units = table_units(rows, spec, line)
    group.attrs["column_order"] = _columns(rows)
    for name in _columns(rows):
        values = [row.get(name, math.nan) for row in rows]
        dataset = group.create_dataset(name, data=_array(values))
        dataset.attrs["units"] = units[name] or "1"
        description = specs[name].description if name in specs else _parameter_text(name)
        dataset.attrs["description"] = description
    if csv_path is not None:
        _write_csv(csv_path, rows, units)


def write_thresholds_csv(
    csv_path: str | Path, rows: list[dict[str, Any]], spec: SearchSpec, line: bool = False
) -> None:
    """The CSV of :func:`write_thresholds` alone."""
    _write_csv(csv_path, rows, table_units(rows, spec, line))


def _parameter_text(name: str) -> str:
    if name == "case_id":
        return "id of the combination of the sweep (the searched parameter left out)"
    return f"{name} of the combination of the sweep"


def _array(values: list[Any]) -> np.ndarray:
    """Text as variable-length UTF-8, numbers as float64 (int64 when all are integers)."""
    if any(isinstance(value, str) for value in values):
        text = ["" if _missing(value) else str(value) for value in values]
        return np.array(text, dtype=h5py.string_dtype())
    if values and all(isinstance(value, numbers.Integral) for value in values):
        return np.array(values, dtype=np.int64)
    return np.array(values, dtype=np.float64)


def _missing(value: Any) -> bool:
    return value is None or (isinstance(value, numbers.Real) and math.isnan(value))


def _cell(value: Any) -> str:
    if _missing(value):
        return ""
    if isinstance(value, bool | np.bool_):
        return str(bool(value))
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value) + 0.0)
    return str(value)


def _write_csv(path: str | Path, rows: list[dict[str, Any]], units: dict[str, str]) -> None:
    path = Path(path)
    columns = _columns(rows)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow([f"{name} [{units[name]}]" if units[name] else name for name in columns])
    writer.writerows([_cell(row.get(name)) for name in columns] for row in rows)
    write_text_atomically(path, text.getvalue())


def completed_rows(path: str | Path) -> dict[str, dict[str, Any]]:
    """Summary rows of the completed cases of a results file (case id -> row), {} without a
    file: what a threshold search replays when it resumes. A case counts as completed when
    its ``status`` attribute (the completion flag, set after its data) says so."""
    path = Path(path)
    if not path.exists():
        return {}
    rows = {}
    with h5py.File(path, "r") as file:
        cases = file.get(CASES_GROUP)
        for name in cases if cases is not None else ():
            attrs = cases[name].attrs
            if attrs.get("status") == CaseStatus.COMPLETED:
                rows[name] = json.loads(attrs["summary"])
    return rows


_HEADER_UNIT = re.compile(r"^(?P<name>.*?) \[(?P<unit>[^\]]*)\]$")


def split_header_units(frame) -> dict[str, str]:
    """Rename the columns of a table read from CSV, whose headers are ``name [unit]``, to
    their names; returns {name: unit} ("" where a header has no unit). A ``message`` column's
    empty cells become ""."""
    units = {}
    for header in frame.columns:
        match = _HEADER_UNIT.match(header)
        name, unit = (match["name"], match["unit"]) if match else (header, "")
        units[name] = unit
    frame.columns = list(units)
    if "message" in frame.columns:
        frame["message"] = frame["message"].fillna("")
    return units


def load_thresholds(path: str | Path) -> pd.DataFrame:
    """Thresholds table of a study with a ``[search]`` section as a DataFrame (one row per
    search), from its results file or ``NAME_thresholds.csv``.

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) or the ``NAME_thresholds.csv`` beside it.

    Returns
    -------
    pandas.DataFrame
        One row per search: the threshold found, its bracket and the search's settings;
        ``frame.attrs["units"]`` maps each column to its unit ("" for text and
        dimensionless columns); from the results file ``frame.attrs["search"]`` holds the
        search's settings.

    Examples
    --------
    >>> frame = engine.load_thresholds("results/fretting_map_search.h5")   # doctest: +SKIP
    >>> frame.plot(x="loading.load", y="threshold")                        # doctest: +SKIP
    """
    import pandas as pd

    path = Path(path)
    check_readable(path)
    if path.suffix.lower() not in (".h5", ".hdf5"):
        frame = pd.read_csv(path, dtype={"case_id": str, "status": str, "message": str})
        units = split_header_units(frame)
        frame.attrs["units"] = units
        return frame
    with h5py.File(path, "r") as file:
        group = file.get(THRESHOLDS_GROUP)
        if group is None:
            raise WrongFileError(
                f"{path}: no thresholds table (the study has no [search] section; "
                "engine.load_summary reads its cases)"
            )
        data, units = read_table_group(group, _ordered(group))
        search = {
            name: _plain(value) for name, value in group.attrs.items() if name != "column_order"
        }
    frame = pd.DataFrame(data)
    frame.attrs["units"] = units
    frame.attrs["search"] = search
    return frame


def read_table_group(group: h5py.Group, names: list[str]) -> tuple[dict, dict[str, str]]:
    """Columns ``names`` of a stored table group, as ``(data, units)``.

    Text columns come back as lists of ``str``, numbers as numpy arrays; a unit of "1"
    (dimensionless) reads back as "".
    """
    data, units = {}, {}
    for name in names:
        values = group[name][()]
        if values.dtype.kind == "O":
            values = [value.decode("utf-8") for value in values]
        data[name] = values
        unit = str(group[name].attrs.get("units", ""))
        units[name] = "" if unit == "1" else unit
    return data, units


def _ordered(group: h5py.Group) -> list[str]:
    """The table's columns in their written order (parameters first, then SEARCH_COLUMNS)."""
    order = group.attrs.get("column_order")
    if order is not None:
        return [str(name) for name in order]
    return sorted(group)


def _plain(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value
