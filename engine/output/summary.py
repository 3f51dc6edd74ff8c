"""Summary table: one row per case, as a pandas DataFrame, a CSV file and inside the HDF5 file.

Columns and units (static cases have ``cycles = 0`` and zero wear):

=================  ======  ===========================================================
case_id            –       stable id from the parameters (see ``engine.study.plan``)
mu1, mu2           –       principal friction coefficients
wear1, wear2       1/MPa   principal wear coefficients i1, i2
beta               degree  angle of the tribological axes
status             –       completed | failed | interrupted | pending
cycles             –       load cycles simulated (0 for static cases)
load               N       peak normal load P
approach           mm      rigid approach at peak load of the last simulated cycle
p0                 MPa     mean pressure P/(π a0²), Eq. (19)
max_wear_depth     mm      maximum wear depth after the last cycle
wear_volume        mm³     worn volume after the last cycle
vm_max             MPa     maximum von Mises stress in the x–z plane (surface included)
vm_max_x/_y/_z     mm      its location (z into the half-space)
vm_sub_max         MPa     maximum von Mises stress below the surface layer
vm_sub_max_x/_y/_z mm      its location
vm_max_on_edge     –       inside | side | bottom | side and bottom: where vm_max touches the
                           plane's boundary (side: the mesh's edge; the maximum may lie beyond)
vm_sub_max_on_edge –       the same for vm_sub_max
stick_fraction     –       stick area / contact area at peak load of the last cycle
vm_deep_max        MPa     maximum von Mises stress at depth z >= 0.1 a0 (cyclic cases)
vm_deep_max_x/_z   mm      its location
vm_axis_max        MPa     maximum von Mises stress on the punch axis r = 0 (cyclic)
vm_axis_max_z      mm      its depth
contact_radius     mm      area-equivalent contact radius √(A_c/π) at peak load (cyclic)
centre_pressure    MPa     pressure at the punch axis at peak load (cyclic)
elastic_approach   mm      approach at peak load of the unworn punch (cycle 0, cyclic)
wear_severity      –       max_wear_depth / elastic_approach (cyclic)
peak_region        –       where vm_max sits: edge-surface | edge-subsurface |
                           axis-subsurface | axis-surface (``engine.solvers.peak``)
peak_region_change_cycle – real cycle N of the first simulated cycle whose region differs
                           from cycle 0's (empty if it never changes)
deep_region        –       where vm_deep_max sits (same words)
load_steps         –       load increments solved
matvecs            –       influence-operator applications in the case
runtime_s          s       wall time of the case (summed over resumed runs)
=================  ======  ===========================================================

Every dotted key swept in ``[sweep]`` (``"loading.load"``, ``"mesh.n"``, …) adds a column of
that name after these, in the units of its study-file key (:func:`column_unit`).
For a sphere, p0 is Hertz's mean pressure P/(π a²) (a: Hertz's contact radius); for a
rounded punch a0 is the radius of its flat face. A line contact's loads, forces, energies and
volumes are per unit length (N/mm, mJ/mm, mm²/mm: ``column_unit(column, line=True)``,
:func:`engine.schema.contact_units`).
"""

from __future__ import annotations

import csv
import io
import json
import math
import numbers
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

if TYPE_CHECKING:  # pandas is imported where a DataFrame is built (never while computing)
    import pandas as pd

from engine.commands import WrongFileError, wrong_file
from engine.schema import (
    CASES_GROUP,
    COLUMN_UNITS,
    INTEGER_COLUMNS,
    SUMMARY_COLUMNS,
    TEXT_COLUMNS,
    pending_row,
)
from engine.study.units import unit_of

__all__ = [
    "SUMMARY_COLUMNS",
    "COLUMN_UNITS",
    "summary_frame",
    "summary_csv",
    "write_summary_csv",
    "load_summary",
    "pending_row",
    "column_unit",
]

# Columns, units, the integer/text columns and the pending row: the results schema.
_INTEGER_COLUMNS, _TEXT_COLUMNS = INTEGER_COLUMNS, TEXT_COLUMNS
_KNOWN = frozenset(SUMMARY_COLUMNS)


def column_unit(column: str, line: bool = False) -> str:
    """Unit of a summary column ("" when dimensionless or text), swept dotted keys included,
    in a 3-D or (``line``) a line contact (the results schema's units table with the
    plug-ins' keys, :func:`engine.study.units.unit_of`)."""
    unit = unit_of(column, line)
    return "" if unit == "1" else unit


def summary_frame(rows: list[dict[str, Any]]) -> pd.DataFrame:
    """DataFrame with the summary columns first (in order), extra keys after them."""
    import pandas as pd

    frame = pd.DataFrame.from_records(rows)
    for column in SUMMARY_COLUMNS:
        if column not in frame:
            frame[column] = np.nan
    extra = [c for c in frame.columns if c not in SUMMARY_COLUMNS]
    frame = frame[SUMMARY_COLUMNS + extra]
    for column in SUMMARY_COLUMNS:
        if column in _INTEGER_COLUMNS:
            frame[column] = frame[column].astype("Float64").round().astype("Int64")
        elif column not in _TEXT_COLUMNS:
            frame[column] = frame[column].astype(float) + 0.0  # -0.0 -> 0.0 (IEEE: -0 + 0 = +0)
    return frame


def summary_csv(rows: list[dict[str, Any]]) -> str:
    """The summary table as CSV text, built without pandas (0.2 s of import on the writing
    rank at the start and the end of every run): the same bytes as
    ``summary_frame(rows).to_csv(index=False)`` (``tests/test_output.py`` checks it): the
    summary columns first, extra keys after them in the order met; shortest round-trip repr
    for floats (−0.0 written as 0.0 in the summary columns), integers for the integer
    columns, an empty field for a missing value; extra columns typed as pandas infers them."""
    extra: dict[str, None] = {}
    for row in rows:
        extra.update((key, None) for key in row if key not in _KNOWN)
    columns = [*SUMMARY_COLUMNS, *extra]
    cells = [_cells(column, [row.get(column) for row in rows]) for column in columns]
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(columns)
    writer.writerows(zip(*cells, strict=True))
    return text.getvalue()


def _missing(value: Any) -> bool:
    return value is None or (isinstance(value, numbers.Real) and math.isnan(value))


def _cells(column: str, values: list[Any]) -> list[str]:
    """One column's CSV fields, formatted as pandas formats the column of ``summary_frame``."""
    if column in _INTEGER_COLUMNS:
        return ["" if _missing(v) else str(int(round(float(v)))) for v in values]
    if column in _TEXT_COLUMNS:
        return ["" if _missing(v) else str(v) for v in values]
    if column in _KNOWN:
        return ["" if _missing(v) else repr(float(v) + 0.0) for v in values]
    present = [v for v in values if not _missing(v)]  # an extra column: pandas' inference
    if present and all(isinstance(v, bool | np.bool_) for v in present):
        return ["" if _missing(v) else str(bool(v)) for v in values]
    if present and all(isinstance(v, numbers.Real) for v in present):
        if len(present) == len(values) and all(isinstance(v, numbers.Integral) for v in values):
            return [str(int(v)) for v in values]
        return ["" if _missing(v) else repr(float(v)) for v in values]
    return ["" if _missing(v) else str(v) for v in values]


def write_summary_csv(rows: list[dict[str, Any]], path: str | Path) -> None:
    """Write ``summary_csv(rows)`` atomically (temporary file + rename) so a kill never leaves
    half a table."""
    write_text_atomically(Path(path), summary_csv(rows))


def write_text_atomically(path: Path, text: str) -> None:
    """``text`` (UTF-8) to ``path`` through a temporary file and a rename, so a kill never
    leaves half a file; a temporary that could not be written whole (a full disk) is
    removed."""
    temporary = path.with_name(f".{path.name}.tmp")
    try:
        temporary.write_text(text, encoding="utf-8")
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def _rows_from_h5(path: Path) -> list[dict[str, Any]]:
    with h5py.File(path, "r") as file:
        cases = file.get(CASES_GROUP)
        if cases is None:
            return []
        rows = []
        for name in cases:
            attrs = cases[name].attrs
            rows.append((int(attrs.get("index", 0)), json.loads(attrs["summary"])))
    return [row for _, row in sorted(rows, key=lambda item: item[0])]


def load_summary(path: str | Path) -> pd.DataFrame:
    """Summary of a study as a DataFrame, from the results ``.h5`` file or the ``.csv`` beside it.

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``; its ``.csv`` beside it is read when the ``.h5`` is gone)
        or the summary ``.csv`` itself.

    Raises
    ------
    FileNotFoundError
        No such file (nor a ``.csv`` beside a missing ``.h5``).
    engine.commands.WrongFileError
        A study file, another program's HDF5 file or another file; the message says what
        it is and what to pass.

    Returns
    -------
    pandas.DataFrame
        One row per case, in plan order: the case id, its swept parameters, its status and
        the summary columns (units: mm, N, MPa, mm³, s; every column and its unit is listed
        in ``docs/reference/outputs.md``). The same table from either file.

    Examples
    --------
    >>> frame = engine.load_summary("results/demo.h5")      # doctest: +SKIP
    >>> frame.pivot(index="mu1", columns="beta", values="max_wear_depth")   # doctest: +SKIP
    """
    path = Path(path)
    if path.suffix.lower() in (".h5", ".hdf5") and not path.exists():
        if path.with_suffix(".csv").exists():
            path = path.with_suffix(".csv")
    check_readable(path)
    if path.suffix.lower() in (".h5", ".hdf5"):
        return summary_frame(_rows_from_h5(path))
    import pandas as pd

    frame = pd.read_csv(path, dtype={"case_id": str, "status": str})
    return summary_frame(frame.to_dict("records"))


def check_readable(path: Path) -> None:
    """Raise a one-line :class:`FileNotFoundError` when ``path`` is not a file, a
    :class:`engine.commands.WrongFileError` when it is not a results file or a CSV table of
    a study (:func:`engine.commands.wrong_file`: what it is and what to pass)."""
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    problem = wrong_file(path, accept_csv=True)
    if problem is not None:
        raise WrongFileError(problem)
