"""HDF5 object creation through h5py's low-level API, for the per-case writes.

A case of a small study (n = 8) is ~20 datasets with ``units`` and ``description``, ~10 case
attributes and the dimension scales of its surface fields. Through h5py's high-level API each
object costs Python work beyond HDF5's own (dtype guessing, array conversion, a property list
per dataset, an intermediate-group lookup per path, wrapper objects): about two thirds of the
time of writing such a case. The functions here make the same HDF5 calls that h5py makes —
same datatypes (variable-length UTF-8 strings for ``str``, the NumPy type otherwise), same
creation properties (no time stamps on datasets and groups, attribute creation order not
tracked), same layout (contiguous) — with property lists and datatypes built once and
reused, so the files are the same object for object and attribute for attribute as those
written by ``group.create_dataset`` and ``attrs[name] = value``.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import h5py
import numpy as np
from h5py import h5a, h5d, h5ds, h5g, h5p, h5s, h5t

__all__ = ["set_attribute", "create_dataset", "attach_scales", "make_scale"]

_STRING = h5py.string_dtype()  # variable-length UTF-8, what h5py stores a str as


def _dataset_creation_properties():
    """h5py's defaults for ``create_dataset``: no object time stamps, creation order of
    attributes not tracked."""
    properties = h5p.create(h5p.DATASET_CREATE)
    properties.set_obj_track_times(False)
    properties.set_attr_creation_order(0)
    return properties


_DATASET_CREATION = _dataset_creation_properties()
_GROUP_CREATION = h5p.create(h5p.GROUP_CREATE)
_GROUP_CREATION.set_obj_track_times(False)  # h5py's default for create_group


@cache
def _types(dtype: np.dtype) -> tuple[h5t.TypeID, h5t.TypeID]:
    """(file type, memory type) of ``dtype``, as h5py builds them for an attribute."""
    return h5t.py_create(dtype, logical=True), h5t.py_create(dtype)


def _as_array(value: Any) -> np.ndarray | None:
    """``value`` as the array h5py would store, or None where the high-level API must decide
    (anything but str, int, float and NumPy numbers)."""
    if isinstance(value, str):  # str() also turns a StrEnum member into its value
        return np.array(str(value), dtype=_STRING)
    if isinstance(value, bool | np.bool_):
        return None
    if isinstance(value, int | float | np.integer | np.floating):
        return np.asarray(value)
    return None


_SCALAR_SPACE = h5s.create(h5s.SCALAR)  # dataspaces are copied by H5Acreate/H5Dcreate: reusable


@cache
def _simple_space(shape: tuple[int, ...]) -> h5s.SpaceID:
    """A simple dataspace of ``shape``, built once per shape (a few shapes per study)."""
    return h5s.create_simple(shape)


def _space(shape: tuple[int, ...]) -> h5s.SpaceID:
    return _SCALAR_SPACE if not shape else _simple_space(shape)


def set_attribute(target, name: str, value: Any, *, new: bool = False) -> None:
    """``target.attrs[name] = value`` (replacing an existing attribute), in fewer steps.

    ``target``: an h5py object or its low-level identifier (``.id``); ``new``: the caller
    knows the object has no attribute ``name`` yet (a dataset just created), so the
    existence check is skipped."""
    data = _as_array(value)
    object_id = _identifier(target)
    if data is None:
        h5py.AttributeManager(_high_level(object_id))[name] = value
        return
    key = name.encode()
    if not new and h5a.exists(object_id, key):
        h5a.delete(object_id, key)
    file_type, memory_type = _types(data.dtype)
    attribute = h5a.create(object_id, key, file_type, _space(data.shape))
    try:
        attribute.write(data, mtype=memory_type)
    finally:
        attribute.close()


def _identifier(target):
    """The low-level identifier of an h5py object (``.id``), or ``target`` if it is one."""
    return target.id if isinstance(target, h5py.HLObject) else target


def _high_level(object_id):
    """The h5py object of a low-level identifier (for the rare values h5py must convert)."""
    if isinstance(object_id, h5d.DatasetID):
        return h5py.Dataset(object_id)
    return h5py.Group(object_id)


def create_dataset(
    group: h5py.Group,
    path: str,
    data: Any,
    parents: dict[str, h5g.GroupID] | None = None,
    *,
    wrap: bool = True,
):
    """``group.create_dataset(path, data=data)`` for a NumPy array of numbers (contiguous;
    missing intermediate groups created as h5py creates them). ``parents`` caches the
    groups already looked up or created for ``group`` (one dict per case). Returns the
    :class:`h5py.Dataset`, or with ``wrap=False`` its low-level ``DatasetID`` (no wrapper
    object: the per-case writes need only the identifier)."""
    array = np.ascontiguousarray(data)
    if array.dtype.kind not in "biuf":
        dataset = group.create_dataset(path, data=array)
        return dataset if wrap else dataset.id
    parent_path, _, name = path.rpartition("/")
    parent = _parent(group, parent_path, {} if parents is None else parents)
    file_type, _ = _types(array.dtype)
    space = _space(array.shape)
    dataset = h5d.create(parent, name.encode(), file_type, space, dcpl=_DATASET_CREATION)
    if array.size:
        dataset.write(h5s.ALL, h5s.ALL, array)
    return h5py.Dataset(dataset) if wrap else dataset


def _parent(group: h5py.Group, path: str, known: dict[str, h5g.GroupID]) -> h5g.GroupID:
    """The group at ``path`` below ``group``, created (with each missing ancestor) without
    time stamps, as ``group.create_group`` does: time stamps would make the file depend on
    the moment of writing, and in mpio mode differ between ranks, which HDF5 refuses."""
    if not path:
        return group.id
    if path in known:
        return known[path]
    ancestor, _, _ = path.rpartition("/")
    _parent(group, ancestor, known)
    key = path.encode()
    if group.id.links.exists(key):
        known[path] = h5g.open(group.id, key)
    else:
        known[path] = h5g.create(group.id, key, gcpl=_GROUP_CREATION)
    return known[path]


def attach_scales(field, scales: tuple) -> None:
    """``field.dims[axis].attach_scale(scale)`` for each axis and scale (h5py datasets or
    their ``DatasetID``)."""
    field_id = _identifier(field)
    for axis, scale in enumerate(scales):
        h5ds.attach_scale(field_id, _identifier(scale), axis)


def make_scale(dataset, name: str) -> None:
    """``dataset.make_scale(name)`` (an h5py dataset or its ``DatasetID``)."""
    h5ds.set_scale(_identifier(dataset), name.encode())
