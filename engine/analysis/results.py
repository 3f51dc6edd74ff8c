"""A study's results file as objects: :func:`engine.open_results` → :class:`Results`.

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
import json
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from engine.output.owner import (
    check_not_being_written,
    is_locked_error,
    locked_by_another_program,
)
from engine.output.summary import load_summary
from engine.schema import (
    CASES_GROUP,
    GRID_GROUP,
    PLANE,
    CaseStatus,
    cycle_of_group,
)
from engine.study.settings.units import case_parameters, unit_of

__all__ = ["open_results", "Results", "ResultCase", "Variable", "VariableGroup", "Records"]


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


def _text(value: Any) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


@dataclass
class Variable:
    """One dataset of a results file: values with units, a description and named dimensions.

    Parameters
    ----------
    name : str
        The dataset's name (``pressure``, ``von_mises``, ``max_wear_depth``, …).
    values : numpy.ndarray
        The stored values.
    units : str
        UDUNITS string ("1": dimensionless; a loop's "mm, mm, N, N" names one unit per column).
        Read from the file, as ``description`` and ``attrs``, when first asked for.
    description : str
        What the values are (the schema's description, with the instant they belong to).
    dims : tuple of str
        One name per axis of ``values``.
    coords : dict
        Coordinates: name → (dims, values, units) of each coordinate.
    attrs : dict
        Any other attribute of the dataset (``columns``, ``plane_angle``).
    """

    name: str
    values: np.ndarray
    units: str
    description: str
    dims: tuple[str, ...]
    coords: dict[str, tuple[tuple[str, ...], np.ndarray, str]] = field(default_factory=dict)
    attrs: dict[str, Any] = field(default_factory=dict)

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of ``values``."""
        return tuple(np.shape(self.values))

    def __array__(self, dtype=None, copy=None):
        return np.asarray(self.values, dtype=dtype)

    def __repr__(self) -> str:
        sizes = ", ".join(f"{dim}: {size}" for dim, size in zip(self.dims, self.shape, strict=True))
        return f"<Variable {self.name!r} ({sizes}) [{self.units}]: {self.description}>"

    def __getstate__(self) -> dict[str, Any]:
        """The state with ``units``, ``description`` and ``attrs`` read (copies and pickles
        hold no link to the file)."""
        return {
            **self.__dict__,
            **{
                f"_stored_{name}": getattr(self, name) for name in ("units", "description", "attrs")
            },
        }

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


class _Attributes:
    """The attributes of the dataset at ``path`` of the file ``results`` opens, read all at
    once when a :class:`Variable`'s ``units``, ``description`` or ``attrs`` is first asked
    for (until then the Variable holds this in their place)."""

    __slots__ = ("results", "path", "stored")

    def __init__(self, results: Results, path: str) -> None:
        self.results, self.path = results, path
        self.stored: dict[str, Any] | None = None

    def value(self, name: str) -> Any:
        """The Variable's field ``name`` (``units``, ``description`` or ``attrs``)."""
        if self.stored is None:
            with self.results._open() as file:
                stored = file[self.path].attrs
                self.stored = {key: stored[key] for key in stored if key not in _LINKS}
        if name == "attrs":
            return {
                key: _attribute(value)
                for key, value in self.stored.items()
                if key not in _NOT_ATTRS
            }
        return _text(self.stored.get(name, ""))


class _FromFile:
    """A field of :class:`Variable` that may stand as :class:`_Attributes` until first read."""

    def __init__(self, name: str) -> None:
        self.name, self.slot = name, f"_stored_{name}"

    def __get__(self, variable, owner=None):
        if variable is None:
            raise AttributeError(self.name)
        value = variable.__dict__[self.slot]
        if isinstance(value, _Attributes):
            value = variable.__dict__[self.slot] = value.value(self.name)
        return value

    def __set__(self, variable, value) -> None:
        variable.__dict__[self.slot] = value


for _name in ("units", "description", "attrs"):  # read lazily (the dataclass's fields still)
    setattr(Variable, _name, _FromFile(_name))


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
            return _grid_group(f"cases/{self.case_id}/grid", source, self.results)

    @cached_property
    def history(self) -> VariableGroup:
        """The case's histories: one entry per simulated cycle (dimension ``step``, with the
        coordinate ``cycle``) or, for a static case, per load increment."""
        with self._group() as group:
            history = group.get("history", {})
            coords = {}
            if "cycle" in history:
                coords["cycle"] = (("step",), _read(history["cycle"]), "1")
            source = _Source(self.results, f"{self._path}/history")
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

        def read(name, group, source):
            plane = planes.get(cycle_of_group(name.rsplit("/", 1)[-1]))
            coords = next(iter(plane.values())).coords if plane else {}
            variables = {
                key: _variable(key, dataset, ("s", "depth"), coords, source)
                if dataset.ndim == 2 and "columns" not in dataset.attrs
                else _field(key, dataset, source)
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
                    _Source(self.results, f"{self._path}/{section}/{name}", self.results._scales),
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
    attributes = _Attributes(source.results, f"{source.path}/{name}")
    return Variable(
        name=name,
        values=values,
        units=attributes,  # type: ignore[arg-type]  # read when first asked for
        description=attributes,  # type: ignore[arg-type]
        dims=dims,
        coords=dict(coords or {}),
        attrs=attributes,  # type: ignore[arg-type]
    )


def _read(dataset) -> np.ndarray:
    """The whole dataset as an array (``dataset[()]``: h5py's direct read, quicker than
    ``numpy.asarray(dataset)``)."""
    return np.asarray(dataset[()])


@dataclass(frozen=True)
class _Source:
    """Where a group's datasets are: the file ``results`` opens, the group's ``path``; and
    the dimension scales read so far (h5py id → (label, coordinate)): the group's own, or
    (``results._scales``) those of every group read while the file stays open."""

    results: Results
    path: str
    scales: dict = field(default_factory=dict, compare=False)


def _attribute(value: Any) -> Any:
    return _text(value) if isinstance(value, (bytes, str)) else value


def _grid_group(name: str, group, results: Results) -> VariableGroup:
    """The coordinates ``x`` and ``y`` (mm) of a grid group (None: none) of ``results``."""
    axes = [axis for axis in ("x", "y") if group is not None and axis in group]
    source = _Source(results, group.name) if axes else None
    return VariableGroup(
        name, {axis: _variable(axis, group[axis], (axis,), None, source) for axis in axes}
    )


def _basename(dataset) -> str:
    """The last part of the dataset's path (slow for a dataset reached by reference: HDF5
    searches the file for its path)."""
    return dataset.name.rsplit("/", 1)[-1]


def _field(name: str, dataset, source: _Source) -> Variable:
    """A surface field on the dimensions named by its attached scales (x, y), with the
    scales' values as coordinates; a dataset without scales (a fretting loop, vm_cycle) on
    dimensions named after it, its ``columns`` attribute as the last one's coordinate."""
    dims, coords, scales = [], {}, source.scales
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


def _field_group(name: str, group, source: _Source) -> VariableGroup:
    return VariableGroup(name, {key: _field(key, data, source) for key, data in group.items()})


def _plane_group(name: str, group, source: _Source) -> VariableGroup:
    """A stored stress plane: the data on (s, depth); x, y, z (mm) as 2-D coordinates; ``s``
    (the signed distance along the plane, x cos φ + y sin φ) and ``depth`` as 1-D ones when
    the points form a grid of columns and layers (as the engine writes them). Datasets the
    schema's PLANE does not name (the surface fields beside a peak change's plane) are
    fields."""
    dims = ("s", "depth")
    variables = {
        key: _variable(key, dataset, dims, None, source)
        if key in PLANE
        else _field(key, dataset, source)
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
    return VariableGroup(name, variables, {"plane_angle": angle})


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
        return self

    def __exit__(self, *exc) -> None:
        if self._file is not None:
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
        return _opened(self.path)

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
            return _grid_group("grid", source, self)

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
