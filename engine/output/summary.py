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
rounded punch a0 is the radius of its flat face.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pandas as pd

__all__ = [
    "SUMMARY_COLUMNS",
    "COLUMN_UNITS",
    "summary_frame",
    "write_summary_csv",
    "load_summary",
    "pending_row",
    "column_unit",
]

SUMMARY_COLUMNS = [
    "case_id", "mu1", "mu2", "wear1", "wear2", "beta", "status", "cycles", "load",
    "approach", "p0", "max_wear_depth", "wear_volume",
    "vm_max", "vm_max_x", "vm_max_y", "vm_max_z",
    "vm_sub_max", "vm_sub_max_x", "vm_sub_max_y", "vm_sub_max_z",
    "stick_fraction", "load_steps", "matvecs", "runtime_s",
    "vm_deep_max", "vm_deep_max_x", "vm_deep_max_z", "vm_axis_max", "vm_axis_max_z",
    "contact_radius", "centre_pressure", "elastic_approach", "wear_severity",
    "peak_region", "peak_region_change_cycle", "deep_region",
]  # fmt: skip

COLUMN_UNITS = {
    "wear1": "1/MPa", "wear2": "1/MPa", "beta": "degree", "load": "N", "approach": "mm",
    "p0": "MPa", "max_wear_depth": "mm", "wear_volume": "mm^3",
    "vm_max": "MPa", "vm_max_x": "mm", "vm_max_y": "mm", "vm_max_z": "mm",
    "vm_sub_max": "MPa", "vm_sub_max_x": "mm", "vm_sub_max_y": "mm", "vm_sub_max_z": "mm",
    "runtime_s": "s",
    "vm_deep_max": "MPa", "vm_deep_max_x": "mm", "vm_deep_max_z": "mm",
    "vm_axis_max": "MPa", "vm_axis_max_z": "mm", "contact_radius": "mm",
    "centre_pressure": "MPa", "elastic_approach": "mm",
}  # fmt: skip

_INTEGER_COLUMNS = ("cycles", "load_steps", "matvecs", "peak_region_change_cycle")
_TEXT_COLUMNS = ("case_id", "status", "peak_region", "deep_region")


def column_unit(column: str) -> str:
    """Unit of a summary column ("" when dimensionless or text), swept dotted keys included."""
    from engine.study.config import SWEEPABLE
    from engine.study.fretting_case import FRETTING_SUMMARY_UNITS

    unit = (
        COLUMN_UNITS.get(column) or FRETTING_SUMMARY_UNITS.get(column) or SWEEPABLE.get(column, "")
    )
    return "" if unit == "1" else unit


def pending_row(parameters: dict[str, Any], status: str = "pending") -> dict[str, Any]:
    """Row of a case without results: its parameters (swept dotted keys included), the
    status and NaN elsewhere."""
    row = {column: math.nan for column in SUMMARY_COLUMNS}
    row.update({k: v for k, v in parameters.items() if k in row or "." in k})
    row["status"] = status
    return row


def summary_frame(rows: list[dict[str, Any]]) -> pd.DataFrame:
    """DataFrame with the summary columns first (in order), extra keys after them."""
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


def write_summary_csv(frame: pd.DataFrame, path: str | Path) -> None:
    """Write atomically (temporary file + rename) so a kill never leaves half a table."""
    path = Path(path)
    temporary = path.with_name(f".{path.name}.tmp")
    frame.to_csv(temporary, index=False)  # shortest repr: round-trips exactly
    os.replace(temporary, path)


def _rows_from_h5(path: Path) -> list[dict[str, Any]]:
    with h5py.File(path, "r") as file:
        cases = file.get("cases")
        if cases is None:
            return []
        rows = []
        for name in cases:
            attrs = cases[name].attrs
            rows.append((int(attrs.get("index", 0)), json.loads(attrs["summary"])))
    return [row for _, row in sorted(rows, key=lambda item: item[0])]


def load_summary(path: str | Path) -> pd.DataFrame:
    """Summary of a study as a DataFrame, from the results ``.h5`` file or the ``.csv`` beside it.

    >>> frame = engine.load_summary("results/demo.h5")      # doctest: +SKIP
    >>> frame.pivot(index="mu1", columns="beta", values="max_wear_depth")   # doctest: +SKIP
    """
    path = Path(path)
    if path.suffix.lower() in (".h5", ".hdf5"):
        if not path.exists() and path.with_suffix(".csv").exists():
            path = path.with_suffix(".csv")
        else:
            return summary_frame(_rows_from_h5(path))
    frame = pd.read_csv(path, dtype={"case_id": str, "status": str})
    return summary_frame(frame.to_dict("records"))
