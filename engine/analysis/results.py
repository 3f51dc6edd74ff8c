"""A study's results file as objects: :func:`engine.open_results` → :class:`Results`.

The one model of a results file: what a user reads, and what the figures and the report read
(``python -m engine plot`` and ``report``). Beside the stored values it gives what the
analyses derive from the study: the profile, the material, a0 and p0 (Eq. 19), case labels and
the stress planes' peaks (:class:`Plane`).

The file's layout is ``engine.schema``'s; every dataset comes back as a :class:`Variable`
carrying its values, its units and description (the dataset's ``units`` and ``description``
attributes) and the names and coordinates of its dimensions. Surface fields take their
coordinates from the dimension scales the writer attached (the case's ``grid/x`` and
``grid/y``, mm); a stress plane's from its own ``x``, ``y``, ``z`` datasets. Nothing is read
before it is asked for, and nothing here writes.

With the optional ``xarray`` package (``pip install fretting-engine[xarray]``) a case's fields
and planes become :class:`xarray.Dataset` objects through ``.to_xarray()``.

Examples
--------
>>> results = engine.open_results("results/demo.h5")           # doctest: +SKIP
>>> results                                                     # doctest: +SKIP
<Results 'demo': cyclic, 6 cases (6 completed), results/demo.h5>
>>> case = results["mu0.1_w1.33e-07_b0"]                        # doctest: +SKIP
>>> case.fields["final"]["pressure"].units                      # doctest: +SKIP
'MPa'
>>> case.fields.to_xarray()["wear"].sel(cycle=10000)            # doctest: +SKIP
"""

from __future__ import annotations

import contextlib
import copy
import importlib
import json
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from numpy.lib.mixins import NDArrayOperatorsMixin

from engine.geometry import profile_from_table
from engine.material import MaterialPair
from engine.output.owner import (
    check_not_being_written,
    is_locked_error,
    locked_by_another_program,
)
from engine.output.summary import column_unit, load_summary
from engine.schema import (
    CASES_GROUP,
    GRID_GROUP,
    PLANE,
    CaseStatus,
    contact_units,
    cycle_of_group,
)
from engine.study.kinds import KINDS
from engine.study.units import case_parameters, unit_of

from .names import value_text

__all__ = [
    "open_results",
    "Results",
    "ResultCase",
    "Variable",
    "VariableGroup",
    "Plane",
    "Records",
]


def open_results(path: str | Path) -> Results:
    """Open a study's results file as objects.

    Parameters
    ----------
    path : str or pathlib.Path
        The results file (``.h5``) a study run wrote.

    Returns
    -------
    Results
        A mapping case id → case, in plan order, with ``study`` (the resolved study),
        ``summary`` (a pandas DataFrame); each case with its ``parameters``, ``status``,
        ``summary`` row, ``history``, ``fields`` and ``planes`` (values with units and
        coordinates; ``.to_xarray()`` when xarray is installed).

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        A file without a stored study.
    engine.output.owner.ResultsBeingWritten
        A file a run is writing (an ``OSError``): one line naming the run's pid and host and
        what to read meanwhile (``engine.load_summary`` on the summary CSV); the run is not
        disturbed.

    Examples
    --------
    >>> results = engine.open_results("results/demo.h5")               # doctest: +SKIP
    >>> case = results["mu0.1_w1.33e-07_b0"]                            # doctest: +SKIP
    >>> case.planes["final"].to_xarray()["von_mises"].max()             # doctest: +SKIP
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such results file")
    check_not_being_written(path)
    with _opened(path) as file:
        if "study_json" not in file.attrs or CASES_GROUP not in file:
            raise ValueError(f"{path}: not a results file of this engine (no stored study)")
        study = json.loads(file.attrs["study_json"])
        name = str(file.attrs.get("study_name", path.stem))
        version = str(file.attrs.get("engine_version", ""))
        statuses, order = {}, {}
        for position, (case_id, group) in enumerate(file[CASES_GROUP].items()):
            statuses[case_id] = str(group.attrs.get("status", ""))
            order[case_id] = int(group.attrs.get("index", position))
    case_ids = sorted(statuses, key=lambda case_id: order[case_id])
    return Results(path, name, study, version, {case_id: statuses[case_id] for case_id in case_ids})


def _opened(path: Path) -> h5py.File:
    """``path`` opened for reading; HDF5 refusing it because a process holds it open for
    writing becomes :class:`engine.output.owner.ResultsBeingWritten`."""
    try:
        return h5py.File(path, "r")
    except OSError as error:
        if is_locked_error(error):
            raise locked_by_another_program(path) from None
        raise


#: The files held open by a ``with open_results(path) as results:`` block, by path: the reads
#: made meanwhile (by any object of that file) share them.
_HELD: dict[Path, h5py.File] = {}


def _reading(path: Path):
    """A context giving the file ``path`` open for reading: the one a ``with`` block holds,
    else opened now and closed at its end."""
    held = _HELD.get(Path(path))
    return contextlib.nullcontext(held) if held is not None else _opened(Path(path))


def _text(value: Any) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


@dataclass(frozen=True)
class _Source:
    """Where an object's data are: the results file ``path`` and the ``name`` of the group or
    dataset inside it (a pickled object reads the file by this path)."""

    path: Path
    name: str

    def child(self, name: str) -> _Source:
        return _Source(self.path, f"{self.name}/{name}")


class Variable(NDArrayOperatorsMixin):
    """One dataset of a results file: values with units, a description and named dimensions.

    In NumPy expressions and functions a Variable stands for its values (``variable * 1e3``,
    ``numpy.max(variable)``, ``variable[i, j]`` give arrays and numbers).

    Parameters
    ----------
    name : str
        The dataset's name (``pressure``, ``von_mises``, ``max_wear_depth``, …).
    values : numpy.ndarray
        The stored values.
    units : str, optional
        UDUNITS string ("1": dimensionless; a loop's "mm, mm, N, N" names one unit per column).
        Without it (and without ``description`` and ``attrs``) they are read from the
        dataset ``source`` when first asked for.
    description : str, optional
        What the values are (the schema's description, with the instant they belong to).
    dims : tuple of str
        One name per axis of ``values``.
    coords : dict, optional
        Coordinates: name → (dims, values, units) of each coordinate.
    attrs : dict, optional
        Any other attribute of the dataset (``columns``, ``plane_angle``).
    source : _Source, optional
        The dataset in its file (None: values in memory, units and description "").
    """

    def __init__(
        self,
        name: str,
        values: np.ndarray,
        units: str | None = None,
        description: str | None = None,
        dims: tuple[str, ...] = (),
        coords: dict[str, tuple[tuple[str, ...], np.ndarray, str]] | None = None,
        attrs: dict[str, Any] | None = None,
        *,
        source: _Source | None = None,
    ) -> None:
        self.name = name
        self.values = values
        self.dims = tuple(dims)
        self.coords = dict(coords or {})
        self.source = source
        given = {"units": units, "description": description, "attrs": attrs}
        self.__dict__.update({key: value for key, value in given.items() if value is not None})

    @cached_property
    def _stored(self) -> dict[str, Any]:
        """The dataset's attributes, read all at once on the first need."""
        if self.source is None:
            return {}
        with _reading(self.source.path) as file:
            stored = file[self.source.name].attrs
            return {key: stored[key] for key in stored if key not in _LINKS}

    @cached_property
    def units(self) -> str:
        """UDUNITS string of the values (the dataset's ``units``)."""
        return _text(self._stored.get("units", ""))

    @cached_property
    def description(self) -> str:
        """What the values are (the dataset's ``description``)."""
        return _text(self._stored.get("description", ""))

    @cached_property
    def attrs(self) -> dict[str, Any]:
        """The dataset's other attributes (``columns``, ``plane_angle``)."""
        return {
            key: _attribute(value) for key, value in self._stored.items() if key not in _NOT_ATTRS
        }

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of ``values``."""
        return tuple(np.shape(self.values))

    @property
    def ndim(self) -> int:
        return np.ndim(self.values)

    @property
    def size(self) -> int:
        return np.size(self.values)

    @property
    def dtype(self) -> np.dtype:
        return np.asarray(self.values).dtype

    def __array__(self, dtype=None, copy=None):
        return np.asarray(self.values, dtype=dtype)

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        """A ufunc on the values (the result an array or a number, not a Variable)."""
        inputs = tuple(_plain(value) for value in inputs)
        if "out" in kwargs:
            kwargs["out"] = tuple(_plain(value) for value in kwargs["out"])
        return getattr(ufunc, method)(*inputs, **kwargs)

    def __getattr__(self, name: str):
        """NumPy's array attributes and methods on the values (``variable.T``,
        ``variable.max()``, …); nothing else."""
        values = self.__dict__.get("values")
        if name.startswith("_") or values is None or not hasattr(np.ndarray, name):
            raise AttributeError(f"'Variable' object has no attribute {name!r}")
        return getattr(np.asarray(values), name)

    def __getitem__(self, key):
        return self.values[key]

    def __len__(self) -> int:
        return len(self.values)

    def __iter__(self):
        return iter(self.values)

    def __float__(self) -> float:
        return float(self.values)

    def __int__(self) -> int:
        return int(self.values)

    def __repr__(self) -> str:
        sizes = ", ".join(f"{dim}: {size}" for dim, size in zip(self.dims, self.shape, strict=True))
        return f"<Variable {self.name!r} ({sizes}) [{self.units}]: {self.description}>"

    def _attrs(self) -> dict[str, Any]:
        return {"units": self.units, "description": self.description, **self.attrs}

    def to_xarray(self):
        """The variable as an :class:`xarray.DataArray` (units and description in ``attrs``).

        Returns
        -------
        xarray.DataArray
            ``values`` with ``dims``, ``coords`` and the attributes.
        """
        xarray = _xarray()
        coords = {
            name: xarray.Variable(dims, values, {"units": units})
            for name, (dims, values, units) in self.coords.items()
        }
        return xarray.DataArray(
            self.values, dims=self.dims, coords=coords, name=self.name, attrs=self._attrs()
        )


def _plain(value):
    return value.values if isinstance(value, Variable) else value


class _Table(Mapping):
    """A read-only mapping over the dict ``self._items``."""

    _items: dict

    def __getitem__(self, key):
        return self._items[key]

    def __iter__(self) -> Iterator:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)


class VariableGroup(_Table):
    """The datasets of one group of a case (a history, the fields or the stress plane of one
    instant): name → :class:`Variable`.

    Parameters
    ----------
    name : str
        What the group holds, e.g. ``"fields/final"``.
    variables : dict
        Name → :class:`Variable`.
    attrs : dict, optional
        Attributes of the whole group (the plane's ``plane_angle``).
    """

    def __init__(
        self, name: str, variables: dict[str, Variable], attrs: dict | None = None
    ) -> None:
        self.name = name
        self._items = variables
        self.attrs = dict(attrs or {})

    def __repr__(self) -> str:
        lines = [f"<VariableGroup {self.name!r}: {len(self)} variables>"]
        for variable in self._items.values():
            shape = "×".join(str(size) for size in variable.shape) or "scalar"
            lines.append(f"  {variable.name:<24s} {shape:<12s} [{variable.units}]")
        return "\n".join(lines)

    def to_xarray(self):
        """The group as an :class:`xarray.Dataset`, one data variable per dataset.

        Returns
        -------
        xarray.Dataset
            The variables with their dimensions, coordinates, units and descriptions.
        """
        xarray = _xarray()
        coordinate_names = {name for variable in self.values() for name in variable.coords}
        arrays = {
            name: variable.to_xarray()
            for name, variable in self.items()
            if name not in coordinate_names
        }
        return xarray.Dataset(arrays, attrs={"group": self.name, **self.attrs})


class Plane(VariableGroup):
    """A stored stress plane: the vertical plane through the punch axis at ``angle`` φ
    (degrees from x; 0: the x–z plane y = 0; a fretting case's plane contains its sliding
    direction, attribute ``plane_angle``), its datasets on the dimensions ``s`` and ``depth``.

    ``x``, ``y``, ``z``: coordinates (mm), shape ``(n_s, n_z)``, z into the half-space (``y``
    None when the file holds none: zeros); ``von_mises`` (MPa), same shape. ``s`` =
    x cos φ + y sin φ: the signed distance along the plane (= x on the x–z plane). ``depths``:
    the evaluated depths (mm); ``depths[0]`` is the surface layer (see
    ``engine.solvers.subsurface.depth_layers``).

    Parameters
    ----------
    name : str
        What the group holds, e.g. ``"cases/<case_id>/subsurface/final"``.
    variables : dict
        Name → :class:`Variable`: at least ``x``, ``z`` and ``von_mises``.
    attrs : dict, optional
        ``plane_angle``: φ (degrees).
    """

    @classmethod
    def from_arrays(
        cls,
        x: np.ndarray,
        z: np.ndarray,
        von_mises: np.ndarray,
        y: np.ndarray | None = None,
        angle: float = 0.0,
        name: str = "plane",
    ) -> Plane:
        """A plane of values in memory.

        Parameters
        ----------
        x, z : numpy.ndarray
            Coordinates of the points (mm), shape ``(n_s, n_z)``; z into the half-space.
        von_mises : numpy.ndarray
            σ_VM (MPa), same shape.
        y : numpy.ndarray, optional
            y of the points (mm), same shape (None: the x–z plane).
        angle : float
            φ (degrees from x).
        name : str
            The group's name.

        Returns
        -------
        Plane
            The plane, its values on the dimensions ``s`` and ``depth``.
        """
        arrays = {"x": x, "y": y, "z": z, "von_mises": von_mises}
        variables = {
            key: Variable(key, np.asarray(values), PLANE[key].units, "", ("s", "depth"))
            for key, values in arrays.items()
            if values is not None
        }
        return cls(name, variables, {"plane_angle": float(angle)})

    @property
    def x(self) -> np.ndarray:
        return self["x"].values

    @property
    def y(self) -> np.ndarray | None:
        return self["y"].values if "y" in self else None

    @property
    def z(self) -> np.ndarray:
        return self["z"].values

    @property
    def von_mises(self) -> np.ndarray:
        return self["von_mises"].values

    @property
    def angle(self) -> float:
        """φ (degrees from x): the group's ``plane_angle``."""
        return float(self.attrs.get("plane_angle", 0.0))

    @property
    def depths(self) -> np.ndarray:
        return self.z[0]

    @property
    def s(self) -> np.ndarray:
        """Signed along-plane coordinate (mm); exactly ``x`` on the x–z plane."""
        if self.angle == 0.0 or self.y is None:
            return self.x
        phi = np.radians(self.angle)
        return self.x * np.cos(phi) + self.y * np.sin(phi)

    def _index(self, min_depth: float):
        candidates = np.where(self.z >= min_depth, self.von_mises, -np.inf)
        return np.unravel_index(np.argmax(candidates), candidates.shape)

    def on_edge(self, min_depth: float = 0.0) -> str:
        """Where the largest σ_VM over z >= ``min_depth`` touches the computed domain's
        boundary. A peak there may lie beyond the domain: the real maximum is not known
        (widen ``[mesh] half_width`` or deepen ``[subsurface] depth``).

        Parameters
        ----------
        min_depth : float
            Points with z >= min_depth (mm) only.

        Returns
        -------
        str
            "side" (the plane's outermost column, the mesh's edge), "bottom" (its deepest
            layer), "side and bottom" or "" (inside).
        """
        column, layer = self._index(min_depth)
        places = []
        if column in (0, self.von_mises.shape[0] - 1):
            places.append("side")
        if layer == self.von_mises.shape[1] - 1:
            places.append("bottom")
        return " and ".join(places)

    def peak(self, min_depth: float = 0.0) -> tuple[float, float, float]:
        """The largest von Mises stress over the points with z >= ``min_depth`` and where it is.

        Parameters
        ----------
        min_depth : float
            Points with z >= min_depth (mm) only.

        Returns
        -------
        tuple of float
            (σ_VM in MPa, s in mm, z in mm); s along the plane (= x on the x–z plane).
        """
        index = self._index(min_depth)
        return float(self.von_mises[index]), float(self.s[index]), float(self.z[index])

    def peak_point(self, min_depth: float = 0.0) -> tuple[float, float, float, float]:
        """The largest von Mises stress over the points with z >= ``min_depth`` and its point.

        Parameters
        ----------
        min_depth : float
            Points with z >= min_depth (mm) only.

        Returns
        -------
        tuple of float
            (σ_VM in MPa, x, y, z in mm).
        """
        index = self._index(min_depth)
        y = 0.0 if self.y is None else float(self.y[index])
        return float(self.von_mises[index]), float(self.x[index]), y, float(self.z[index])

    def axis_peak(self) -> tuple[float, float, float]:
        """The largest von Mises stress on the punch axis (the column s ≈ 0).

        Returns
        -------
        tuple of float
            (σ_VM in MPa, s in mm, z in mm).
        """
        along = self.s
        column = int(np.argmin(np.abs(along[:, 0])))
        depth = int(np.argmax(self.von_mises[column]))
        return (
            float(self.von_mises[column, depth]),
            float(along[column, depth]),
            float(self.z[column, depth]),
        )

    def subsurface_peak(self) -> tuple[float, float, float]:
        """The peak over the layers strictly below the surface layer (z >= depths[1]).

        Returns
        -------
        tuple of float
            (σ_VM in MPa, s in mm, z in mm), as :meth:`peak`.
        """
        depths = self.depths
        return self.peak(float(depths[1]) if len(depths) > 1 else 0.0)


class Records(_Table):
    """A case's groups of one kind by instant: ``"final"`` or the recorded cycle N (int) →
    :class:`VariableGroup`.

    Parameters
    ----------
    name : str
        ``"fields"``, ``"planes"`` or ``"peak_changes"``.
    groups : dict
        Instant → :class:`VariableGroup`.
    """

    def __init__(self, name: str, groups: dict[Any, VariableGroup]) -> None:
        self.name = name
        self._items = groups

    @property
    def cycles(self) -> list[int]:
        """The recorded cycles N, ascending."""
        return sorted(key for key in self._items if isinstance(key, int))

    def __repr__(self) -> str:
        keys = ["final"] if "final" in self._items else []
        keys += [f"cycle {cycle}" for cycle in self.cycles]
        return f"<Records {self.name!r}: {', '.join(keys) or 'none'}>"

    def to_xarray(self):
        """The recorded cycles stacked along a dimension ``cycle`` (the datasets every
        recorded cycle holds with the same shape; ``"final"`` stays apart:
        ``records["final"].to_xarray()``).

        Returns
        -------
        xarray.Dataset
            Dimension ``cycle`` (the recorded cycle numbers) before each dataset's own.

        Raises
        ------
        ValueError
            When the case has no recorded cycle.
        """
        xarray = _xarray()
        cycles = self.cycles
        if not cycles:
            raise ValueError(f"no recorded cycle in {self.name!r} (use ['final'])")
        datasets = [self._items[cycle].to_xarray() for cycle in cycles]
        common = set(datasets[0].data_vars)
        for dataset in datasets[1:]:
            common &= {
                name
                for name in dataset.data_vars
                if name in datasets[0] and dataset[name].shape == datasets[0][name].shape
            }
        datasets = [dataset[sorted(common)] for dataset in datasets]
        stacked = xarray.concat(
            datasets, dim="cycle", data_vars="all", coords="minimal", compat="override"
        )
        stacked = stacked.assign_coords(cycle=("cycle", np.asarray(cycles), {"units": "1"}))
        stacked.attrs = {"group": self._items[cycles[0]].name.rsplit("/", 1)[0]}
        first = re.compile(rf"\bcycle {cycles[0]}\b")
        for name in stacked.data_vars:  # the description of every recorded cycle
            attrs = dict(datasets[0][name].attrs)
            attrs["description"] = first.sub("each recorded cycle", attrs["description"])
            stacked[name].attrs = attrs
        return stacked


class ResultCase:
    """One case of a results file: its parameters, status, summary row, histories, surface
    fields, stress planes and fatigue maps (read when first asked for).

    Parameters
    ----------
    results : Results
        The file the case belongs to.
    case_id : str
        The case's id.
    """

    def __init__(self, results: Results, case_id: str) -> None:
        self.results = results
        self.case_id = case_id
        with self._group() as group:
            stored_attrs = group.attrs
            attrs = {key: stored_attrs[key] for key in stored_attrs}  # each read once
            self.status: str = _text(attrs.get("status", ""))
            #: The case's position in the plan (attribute ``index``).
            index = attrs.get("index")
            self.index: int = results.case_ids.index(case_id) if index is None else int(index)
            self.message: str = _text(attrs.get("message", ""))
            summary = attrs.get("summary")
            self.summary: dict[str, Any] = json.loads(summary) if summary is not None else {}
            units = attrs.get("parameter_units")
            stored = json.loads(units) if units is not None else {}
            names = case_parameters()
            self.parameters: dict[str, Any] = {
                key: value.item() if hasattr(value, "item") else value
                for key, value in attrs.items()
                if key in names or "." in key
            }
            # the units table of the schema for a parameter the file left without its unit
            self.parameter_units: dict[str, str] = {
                key: stored.get(key) or unit_of(key) for key in self.parameters
            }

    def _group(self):
        return _CaseGroup(self.results, self.case_id)

    @property
    def _path(self) -> str:
        """The case's group in the file."""
        return f"/{CASES_GROUP}/{self.case_id}"

    @property
    def completed(self) -> bool:
        """Whether the case completed (only completed cases hold datasets)."""
        return self.status == CaseStatus.COMPLETED

    @classmethod
    def from_values(
        cls,
        case_id: str,
        parameters: dict[str, Any],
        *,
        index: int = 0,
        summary: dict[str, Any] | None = None,
        history: dict[str, np.ndarray] | None = None,
        fields: dict[Any, dict[str, np.ndarray]] | None = None,
        planes: dict[Any, Plane] | None = None,
        results: Results | None = None,
    ) -> ResultCase:
        """A completed case of values in memory (no file), as the figures and the report
        take it.

        Parameters
        ----------
        case_id : str
            The case's id.
        parameters : dict
            ``mu1``, ``mu2``, ``wear1`` (1/MPa), ``wear2``, ``beta`` (degrees) and any swept
            dotted key.
        index : int
            Its position in the plan.
        summary : dict, optional
            Its summary row.
        history : dict, optional
            History name → array (one entry per cycle or increment).
        fields : dict, optional
            Instant (``"final"`` or the cycle N) → field name → array ``(n_x, n_y)``.
        planes : dict, optional
            Instant → :class:`Plane` (:meth:`Plane.from_arrays`).
        results : Results, optional
            The results it belongs to.

        Returns
        -------
        ResultCase
            The case, status ``"completed"``.
        """
        case = cls.__new__(cls)
        case.results, case.case_id, case.index = results, case_id, index
        case.status, case.message = CaseStatus.COMPLETED.value, ""
        case.summary = dict(summary or {})
        case.parameters = dict(parameters)
        case.parameter_units = {key: unit_of(key) for key in case.parameters}
        case.history = _in_memory(f"cases/{case_id}/history", history or {})
        case.fields = Records(
            "fields",
            {
                key: _in_memory(f"cases/{case_id}/fields/{key}", group)
                for key, group in (fields or {}).items()
            },
        )
        case.planes = Records("planes", dict(planes or {}))
        case.peak_changes = Records("peak_changes", {})
        case.fatigue = Records("fatigue", {})
        return case

    def _parameter(self, name: str) -> float:
        return float(self.parameters[name])

    @property
    def mu1(self) -> float:
        """Friction coefficient μ1 (along x)."""
        return self._parameter("mu1")

    @property
    def mu2(self) -> float:
        """Friction coefficient μ2 (along y)."""
        return self._parameter("mu2")

    @property
    def wear1(self) -> float:
        """Wear coefficient k1 (1/MPa)."""
        return self._parameter("wear1")

    @property
    def wear2(self) -> float:
        """Wear coefficient k2 (1/MPa)."""
        return self._parameter("wear2")

    @property
    def beta(self) -> float:
        """Angle β of the orthotropic axes (degrees)."""
        return self._parameter("beta")

    @property
    def settings(self) -> dict[str, Any]:
        """The case's values of the swept dotted keys (``loading.load``, ``mesh.n``, …)."""
        return {key: value for key, value in self.parameters.items() if "." in key}

    @property
    def isotropic(self) -> bool:
        return self.mu1 == self.mu2 and self.wear1 == self.wear2

    @property
    def label(self) -> str:
        """Short name of the case for legends and titles (μ, and μ2, β when orthotropic, and
        every other swept key with its unit)."""

        def unit(key: str) -> str:  # the file's unit (a line contact's per unit length)
            stored = self.parameter_units.get(key, "1")
            return column_unit(key) if stored == "1" else stored

        swept = "".join(
            f", {key.rsplit('.', 1)[-1]} = {value_text(value)}"
            + (f" {unit(key)}" if unit(key) else "")
            for key, value in self.settings.items()
        )
        if self.isotropic:
            text = f"μ = {self.mu1:g}"
            return text + (f", β = {self.beta:g}°" if self.beta else "") + swept
        return f"μ1 = {self.mu1:g}, μ2 = {self.mu2:g}, β = {self.beta:g}°" + swept

    @property
    def recorded_cycles(self) -> list[int]:
        """The cycles N whose surface fields are recorded, ascending."""
        return sorted(key for key in self.fields if isinstance(key, int))

    def history_at(self, name: str, cycle: int) -> float:
        """A history's value after exactly ``cycle`` real cycles.

        Parameters
        ----------
        name : str
            The history (``max_wear_depth``, ``energy``, …).
        cycle : int
            The cycle N.

        Returns
        -------
        float
            Its value (NaN when that cycle was not simulated).
        """
        cycles = self.history.get("cycle")
        if cycles is None:
            return float("nan")
        hits = np.flatnonzero(np.asarray(cycles) == cycle)
        return float(self.history[name][hits[-1]]) if len(hits) else float("nan")

    def __repr__(self) -> str:
        parameters = ", ".join(f"{key} = {value:g}" for key, value in self._numbers().items())
        text = f"<ResultCase {self.case_id!r} {self.status}: {parameters}"
        if self.completed:
            text += (
                f"; history {len(self.history)} keys, fields {_instants(self.fields)}, "
                f"planes {_instants(self.planes)}"
            )
        elif self.message:
            text += f"; {self.message}"
        return text + ">"

    def _numbers(self) -> dict[str, float]:
        return {
            key: value
            for key, value in self.parameters.items()
            if isinstance(value, (int, float)) and not isinstance(value, bool)
        }

    @cached_property
    def grid(self) -> VariableGroup:
        """The case's element-centre coordinates ``x`` and ``y`` (mm)."""
        with self._group() as group:
            source = group[GRID_GROUP] if GRID_GROUP in group else group.file.get(GRID_GROUP)
            return _grid_group(f"cases/{self.case_id}/grid", source, self.results.path)

    @cached_property
    def history(self) -> VariableGroup:
        """The case's histories: one entry per simulated cycle (dimension ``step``, with the
        coordinate ``cycle``) or, for a static case, per load increment."""
        with self._group() as group:
            history = group.get("history", {})
            coords = {}
            if "cycle" in history:
                coords["cycle"] = (("step",), _read(history["cycle"]), "1")
            source = _Source(self.results.path, f"{self._path}/history")
            variables = {
                name: _variable(name, dataset, ("step",), coords, source)
                for name, dataset in history.items()
            }
        return VariableGroup(f"cases/{self.case_id}/history", variables)

    @cached_property
    def fields(self) -> Records:
        """Surface fields by instant (``"final"`` or the recorded cycle N), each of shape
        ``(n_x, n_y)`` on the dimensions ``x``, ``y`` (coordinates: the attached dimension
        scales, mm); a fretting cycle's ``loop`` and ``vm_cycle`` on their own dimensions."""
        return self._records("fields", _field_group)

    @cached_property
    def planes(self) -> Records:
        """The stress plane through the axis by instant (``"final"`` or the recorded cycle
        N): σ_VM and the components (MPa) on the dimensions ``s`` (along the plane, mm) and
        ``depth`` (mm), with the points' ``x``, ``y``, ``z`` (mm) as coordinates."""
        return self._records("subsurface", _plane_group)

    @cached_property
    def peak_changes(self) -> Records:
        """The plane and the surface fields at the first cycle and each change of the peak
        region (cyclic cases), by cycle N: the plane's datasets as in :attr:`planes`, the
        fields on ``x``, ``y`` as in :attr:`fields`."""
        return self._records("peak_changes", _plane_group)

    @cached_property
    def fatigue(self) -> Records:
        """The fatigue criteria's maps by recorded cycle N (fretting studies with
        ``[fatigue]``): each map on the dimensions ``s`` and ``depth`` of the stress plane of
        that cycle (its coordinates those of ``planes[N]``), and each criterion's hot spot
        (``<column>_hot_spot``, its columns as a coordinate)."""
        planes = self.planes

        def read(name, group, source, scales):
            plane = planes.get(cycle_of_group(name.rsplit("/", 1)[-1]))
            coords = next(iter(plane.values())).coords if plane else {}
            variables = {
                key: _variable(key, dataset, ("s", "depth"), coords, source)
                if dataset.ndim == 2 and "columns" not in dataset.attrs
                else _field(key, dataset, source, scales)
                for key, dataset in group.items()
            }
            return VariableGroup(name, variables)

        return self._records("fatigue", read)

    def _records(self, section: str, read) -> Records:
        groups = {}
        with self._group() as group:
            for name, sub in group.get(section, {}).items():
                cycle = cycle_of_group(name)
                groups[name if cycle is None else cycle] = read(
                    f"cases/{self.case_id}/{section}/{name}",
                    sub,
                    _Source(self.results.path, f"{self._path}/{section}/{name}"),
                    self.results._scales,
                )
        ordered = {key: groups[key] for key in sorted(groups, key=_instant_order)}
        return Records("planes" if section == "subsurface" else section, ordered)


class _CaseGroup:
    """``with _CaseGroup(results, case_id) as group``: the case's group, the file open
    meanwhile (the file ``results`` holds open inside its ``with`` block, else opened here)."""

    def __init__(self, results: Results, case_id: str) -> None:
        self.results, self.case_id = results, case_id

    def __enter__(self) -> h5py.Group:
        self.opened = self.results._open()
        return self.opened.__enter__()[CASES_GROUP][self.case_id]

    def __exit__(self, *exc) -> None:
        self.opened.__exit__(*exc)


def _in_memory(name: str, arrays: dict[str, np.ndarray], units: str = "") -> VariableGroup:
    """A group of values in memory: name → array (each on dimensions named after it)."""
    variables = {}
    for key, values in arrays.items():
        values = np.asarray(values)
        dims = tuple(f"{key}_{axis}" for axis in range(values.ndim))
        variables[key] = Variable(key, values, units, "", dims)
    return VariableGroup(name, variables)


def _instant_order(key) -> tuple[int, int]:
    return (0, key) if isinstance(key, int) else (1, 0)


def _instants(records: Records) -> str:
    parts = ["final"] if "final" in records else []
    if records.cycles:
        parts.append(f"{len(records.cycles)} recorded cycles")
    return " + ".join(parts) or "none"


# The dimension-scale links (costly to read, never read) and the attributes a Variable
# carries as fields (units, description) or that are bookkeeping (the checksum): left out of
# ``Variable.attrs``.
_LINKS = frozenset(("DIMENSION_LIST", "REFERENCE_LIST", "CLASS", "NAME"))
_NOT_ATTRS = _LINKS | {"units", "description", "sha256"}


def _variable(
    name: str, dataset, dims: tuple[str, ...], coords: dict | None, source: _Source
) -> Variable:
    """The dataset ``name`` of the group ``source`` as a :class:`Variable` (its attributes
    read when first asked for)."""
    values = _read(dataset)
    if len(dims) != values.ndim:
        dims = tuple(f"{name}_{axis}" for axis in range(values.ndim))
    return Variable(name, values, dims=dims, coords=coords, source=source.child(name))


def _read(dataset) -> np.ndarray:
    """The whole dataset as an array (``dataset[()]``: h5py's direct read, quicker than
    ``numpy.asarray(dataset)``)."""
    return np.asarray(dataset[()])


def _attribute(value: Any) -> Any:
    return _text(value) if isinstance(value, (bytes, str)) else value


def _grid_group(name: str, group, path: Path) -> VariableGroup:
    """The coordinates ``x`` and ``y`` (mm) of a grid group (None: none) of the file
    ``path``."""
    axes = [axis for axis in ("x", "y") if group is not None and axis in group]
    source = _Source(path, group.name) if axes else None
    return VariableGroup(
        name, {axis: _variable(axis, group[axis], (axis,), None, source) for axis in axes}
    )


def _basename(dataset) -> str:
    """The last part of the dataset's path (slow for a dataset reached by reference: HDF5
    searches the file for its path)."""
    return dataset.name.rsplit("/", 1)[-1]


def _field(name: str, dataset, source: _Source, scales: dict) -> Variable:
    """A surface field on the dimensions named by its attached scales (x, y), with the
    scales' values as coordinates; a dataset without scales (a fretting loop, vm_cycle) on
    dimensions named after it, its ``columns`` attribute as the last one's coordinate.
    ``scales``: the dimension scales read so far (h5py id → (label, coordinate)), shared by
    the groups read while the file stays open."""
    dims, coords = [], {}
    for dimension in dataset.dims:
        if len(dimension):
            scale = dimension[0]
            if scale.id not in scales:
                label = _text(h5py.h5ds.get_scale_name(scale.id) or b"") or _basename(scale)
                units = _text(scale.attrs.get("units", ""))
                scales[scale.id] = (label, ((label,), _read(scale), units))
            label, coordinate = scales[scale.id]
            dims.append(label)
            coords[label] = coordinate
        else:
            dims.append(None)
    if None in dims:
        columns = dataset.attrs.get("columns")
        dims = [f"{name}_row" if label is None else label for label in dims]
        if columns is not None:
            column = f"{name}_column"
            dims[-1] = column
            names = np.array([part.strip() for part in _text(columns).split(",")])
            coords[column] = ((column,), names, "")
    return _variable(name, dataset, tuple(dims), coords, source)


def _field_group(name: str, group, source: _Source, scales: dict) -> VariableGroup:
    return VariableGroup(
        name, {key: _field(key, data, source, scales) for key, data in group.items()}
    )


def _plane_group(name: str, group, source: _Source, scales: dict) -> Plane:
    """A stored stress plane: the data on (s, depth); x, y, z (mm) as 2-D coordinates; ``s``
    (the signed distance along the plane, x cos φ + y sin φ) and ``depth`` as 1-D ones when
    the points form a grid of columns and layers (as the engine writes them). Datasets the
    schema's PLANE does not name (the surface fields beside a peak change's plane) are
    fields."""
    dims = ("s", "depth")
    variables = {
        key: _variable(key, dataset, dims, None, source)
        if key in PLANE
        else _field(key, dataset, source, scales)
        for key, dataset in group.items()
    }
    x, z = variables["x"].values, variables["z"].values
    y = variables["y"].values if "y" in variables else np.zeros_like(x)
    angle = (
        float(group["von_mises"].attrs.get("plane_angle", 0.0)) if "von_mises" in variables else 0
    )
    coords: dict[str, tuple] = {"x": (dims, x, "mm"), "y": (dims, y, "mm"), "z": (dims, z, "mm")}
    if np.all(z == z[:1, :]):
        coords["depth"] = (("depth",), z[0].copy(), "mm")
        phi = np.radians(angle)
        along = x * np.cos(phi) + y * np.sin(phi) if angle else x
        if np.all(along == along[:, :1]):
            coords["s"] = (("s",), along[:, 0].copy(), "mm")
    for key, variable in variables.items():  # the plane's coordinates, read once
        if key in PLANE:
            variable.coords.update(coords)
    return Plane(name, variables, {"plane_angle": angle})


class Results(_Table):
    """A study's results file: the study, its summary and its cases by id.

    Made by :func:`engine.open_results`; a mapping case id → :class:`ResultCase`, in plan order.
    Each read opens and closes the file; in a ``with`` block (``with open_results(path) as
    results:``) the reads share one open file.

    Parameters
    ----------
    path : pathlib.Path
        The results file.
    name : str
        The study's name.
    study : dict
        The resolved study (every section, every default filled in) stored in the file.
    engine_version : str
        The version of the engine that wrote the file.
    statuses : dict
        Case id → status, in plan order.
    """

    def __init__(
        self, path: Path, name: str, study: dict, engine_version: str, statuses: dict[str, str]
    ) -> None:
        self.path = Path(path)
        self.name = name
        self.study = study
        self.engine_version = engine_version
        self.statuses = statuses
        self._items: dict[str, ResultCase] = {}
        self._file: h5py.File | None = None
        self._scales_read: dict = {}

    def __enter__(self) -> Results:
        """``with open_results(path) as results:`` keeps the file open while reading many
        cases (each read otherwise opens and closes it)."""
        if self._file is None:
            self._file = _opened(self.path)
            _HELD.setdefault(self.path, self._file)
        return self

    def __exit__(self, *exc) -> None:
        if self._file is not None:
            if _HELD.get(self.path) is self._file:
                del _HELD[self.path]
            self._file.close()
            self._file = None
            self._scales_read = {}

    @property
    def _scales(self) -> dict:
        """The dimension scales read while the file stays open (h5py ids hold only then);
        outside ``with``, a new dict."""
        return self._scales_read if self._file is not None else {}

    def _open(self):
        """A context giving the open file: the one held inside ``with``, else opened now
        and closed at its end."""
        if self._file is not None:
            return contextlib.nullcontext(self._file)
        return _reading(self.path)

    @property
    def kind(self) -> str:
        """The study's ``[loading] kind``."""
        return str(self.study["loading"]["kind"])

    @property
    def swept_keys(self) -> list[str]:
        """Dotted keys swept in ``[sweep]``, in file order."""
        return [key for key in self.study.get("sweep", {}) if "." in key]

    @cached_property
    def grid(self) -> VariableGroup:
        """The study's element-centre coordinates ``x`` and ``y`` (mm): the grid every case
        shares or, when the grid changes from case to case, the first case's (by case id)
        that holds one (each case's own: ``results[case_id].grid``); empty without any."""
        with self._open() as file:
            source = file.get(GRID_GROUP)
            if source is None:
                holding = (group for _, group in sorted(file[CASES_GROUP].items()))
                source = next((group[GRID_GROUP] for group in holding if GRID_GROUP in group), None)
            return _grid_group("grid", source, self.path)

    @property
    def case_ids(self) -> list[str]:
        """Every case id, in plan order."""
        return list(self.statuses)

    @property
    def completed(self) -> list[ResultCase]:
        """The completed cases, in plan order."""
        return [self[case_id] for case_id, status in self.statuses.items() if status == "completed"]

    @cached_property
    def summary(self):
        """The summary table (:func:`engine.load_summary`): a :class:`pandas.DataFrame`, one
        row per case, units in ``docs/reference/outputs.md``."""
        return load_summary(self.path)

    @classmethod
    def from_values(
        cls,
        name: str,
        study: dict,
        cases: list[ResultCase],
        grid_x: np.ndarray | None = None,
        grid_y: np.ndarray | None = None,
        path: str | Path = "memory.h5",
    ) -> Results:
        """Results of values in memory (no file), as the figures and the report take them.

        Parameters
        ----------
        name : str
            The study's name.
        study : dict
            The resolved study: section → keys.
        cases : list of ResultCase
            The completed cases (:meth:`ResultCase.from_values`).
        grid_x, grid_y : numpy.ndarray, optional
            The element centres' coordinates (mm).
        path : str or pathlib.Path
            The path it reports as its file.

        Returns
        -------
        Results
            The results, every case completed.
        """
        results = cls(Path(path), name, study, "", {case.case_id: case.status for case in cases})
        results._items = {case.case_id: case for case in cases}
        for case in cases:
            case.results = results
        axes = {"x": grid_x, "y": grid_y}
        results.grid = _in_memory(
            "grid", {axis: values for axis, values in axes.items() if values is not None}, "mm"
        )
        for case in cases:
            case.__dict__.setdefault("grid", results.grid)
        return results

    # ---------------------------------------------------------- what the analyses derive
    @property
    def skipped(self) -> list[tuple[str, str]]:
        """(case id, status) of every case that did not complete, by case id."""
        return sorted(
            (case_id, status)
            for case_id, status in self.statuses.items()
            if status != CaseStatus.COMPLETED
        )

    @property
    def grid_x(self) -> np.ndarray:
        """x of the element centres (mm): ``grid["x"]``'s values (empty without a grid)."""
        return self.grid["x"].values if "x" in self.grid else np.zeros(0)

    @property
    def grid_y(self) -> np.ndarray:
        """y of the element centres (mm): ``grid["y"]``'s values (empty without a grid)."""
        return self.grid["y"].values if "y" in self.grid else np.zeros(0)

    @property
    def loading_kind(self):
        """The study's loading kind (the class ``engine.study.kinds.KINDS`` names)."""
        return KINDS[self.kind]

    def kind_hook(self, name: str):
        """The analysis function the loading kind names for ``name``.

        Parameters
        ----------
        name : str
            ``"report"`` or ``"figures"``: the kind's ``"module:function"`` attribute.

        Returns
        -------
        callable
            That function, imported now.
        """
        module, _, function = getattr(self.loading_kind, name).partition(":")
        return getattr(importlib.import_module(module), function)

    @property
    def is_cyclic(self) -> bool:
        """The radial cyclic kind (``kind = "cyclic"``); fretting studies: :attr:`is_fretting`."""
        return self.kind == "cyclic"

    @property
    def is_fretting(self) -> bool:
        """Tangential fretting (``kind = "fretting"``): load cycles and wear too."""
        return self.kind == "fretting"

    @property
    def load_unit(self) -> str:
        """Unit of the load and the tangential force: N (a line contact's: N/mm)."""
        return self.profile.load_unit

    def per_contact(self, unit: str) -> str:
        """A unit in this study's contact.

        Parameters
        ----------
        unit : str
            N, mJ, mm³, …

        Returns
        -------
        str
            ``unit``, or for a line contact's forces, energies, areas and volumes the unit
            per unit length (``engine.schema.contact_units``).
        """
        return contact_units(unit, self.profile.is_line)

    @property
    def profile(self):
        """The punch profile of the study (one of ``engine.geometry.PROFILES``); a swept
        ``punch`` key at its first value (what the study-wide figures use: the shape, a0)."""
        table = dict(self.study["punch"])
        for key, values in self.study.get("sweep", {}).items():
            section, _, name = key.partition(".")
            if section == "punch" and name not in table and values:
                table[name] = values[0]
        return profile_from_table(table)

    @property
    def radius(self) -> float:
        """a0 (mm), the profile's contact length at the load: the punch radius (rounded: of
        the flat face); for a sphere, Hertz's contact radius; for a line contact the nominal
        half-width (the summary's p0 uses the same a0)."""
        return float(self.profile.contact_length(self.load, self.material.contact_modulus))

    @property
    def load(self) -> float:
        """Peak normal load P (N)."""
        return float(self.study["loading"]["load"])

    @property
    def p0(self) -> float:
        """The summary's mean pressure p0 (MPa): P/(π a0²), Eq. (19); a line contact's
        P/(2 a0)."""
        return float(self.profile.mean_pressure(self.load, self.radius))

    @property
    def material(self) -> MaterialPair:
        """The material pair of ``[material]`` (moduli in MPa)."""
        m = self.study["material"]
        return MaterialPair(m["E_A"], m["nu_A"], m["E_B"], m["nu_B"])

    @property
    def mesh_label(self) -> str:
        n = self.study["mesh"]["n"]
        if self.profile.is_line:
            return f"{n} elements along x"  # a line contact (plane strain)
        return f"{n}×{n} mesh"

    @property
    def isotropic(self) -> bool:
        """Whether every completed case is isotropic (μ1 = μ2, k1 = k2)."""
        return all(case.isotropic for case in self.completed)

    def for_case(self, case_id: str) -> Results:
        """The study reduced to one completed case.

        Parameters
        ----------
        case_id : str
            The case.

        Returns
        -------
        Results
            The case alone, with its values of the swept dotted keys in ``study`` (so a0, P,
            p0 and the mesh are its own) and its grid.

        Raises
        ------
        ValueError
            Naming the case and the completed ones when it is not among them.
        """
        if self.statuses.get(case_id) != CaseStatus.COMPLETED:
            skipped = dict(self.skipped)
            why = f"its status is {skipped[case_id]!r}" if case_id in skipped else "no such case"
            completed = [key for key, status in self.statuses.items() if status == "completed"]
            known = ", ".join(completed[:8])
            more = ", …" if len(completed) > 8 else ""
            raise ValueError(
                f"{self.path}: case {case_id!r} cannot be plotted ({why}); completed cases: "
                f"{known}{more}"
            )
        case = self[case_id]
        study = copy.deepcopy(self.study)
        for key, value in case.settings.items():
            section, name = key.split(".", 1)
            study.setdefault(section, {})[name] = value
            study.get("sweep", {}).pop(key, None)
        view = copy.copy(self)
        view.__dict__.pop("summary", None)
        view.name, view.study, view._file = f"{self.name} {case_id}", study, None
        view.statuses, view._items = {case_id: self.statuses[case_id]}, {case_id: case}
        if case.grid:
            view.grid = case.grid
        return view

    def __getitem__(self, case_id: str) -> ResultCase:
        if case_id not in self.statuses:
            known = ", ".join(self.case_ids[:6]) + (", …" if len(self.statuses) > 6 else "")
            raise KeyError(f"{self.path}: no case {case_id!r} (cases: {known})")
        if case_id not in self._items:
            self._items[case_id] = ResultCase(self, case_id)
        return self._items[case_id]

    def __iter__(self) -> Iterator[str]:
        return iter(self.statuses)

    def __len__(self) -> int:
        return len(self.statuses)

    def __repr__(self) -> str:
        counts: dict[str, int] = {}
        for status in self.statuses.values():
            counts[status] = counts.get(status, 0) + 1
        states = ", ".join(f"{count} {status}" for status, count in sorted(counts.items()))
        swept = f", swept {', '.join(self.swept_keys)}" if self.swept_keys else ""
        return (
            f"<Results {self.name!r}: {self.kind}, {len(self)} cases ({states}){swept}, "
            f"{self.path}>"
        )


def _xarray():
    try:
        import xarray
    except ImportError:  # pragma: no cover - depends on the installation
        raise ImportError(
            "to_xarray() needs the optional package xarray: pip install 'fretting-engine[xarray]'"
        ) from None
    return xarray
