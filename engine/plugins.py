"""The plug-in tables: built-in entries merged with those other packages register.

A package adds a punch profile, a fatigue criterion, a loading kind or a wear law without
touching the engine by declaring an entry point in its ``pyproject.toml``::

    [project.entry-points."fretting_engine.profiles"]
    cone = "my_package.cone:ConePunch"

- ``fretting_engine.profiles``: a :class:`engine.geometry.Profile` subclass, in
  ``engine.geometry.PROFILES``;
- ``fretting_engine.criteria``: a :class:`engine.fatigue.FatigueCriterion` subclass, in
  ``engine.fatigue.CRITERIA``;
- ``fretting_engine.kinds``: a ``engine.study.kinds.LoadingKind`` subclass, in
  ``engine.study.kinds.KINDS``;
- ``fretting_engine.wear_laws``: a :class:`engine.solvers.wear.WearModel` subclass, in
  ``engine.solvers.wear_laws.WEAR_LAWS``.

The entry point's name is the name a study file uses (``[punch] shape = "cone"``) and must
be the class's ``name``. A ``Registry`` is a read-only mapping that imports the
registered objects the first time it is read (pluggy-style discovery through
``importlib.metadata.entry_points``, nothing imported at ``import engine``); a name
registered twice, by the engine and a package or by two packages, is an error naming both
distributions (``PluginError``).

Discovery is cheap when nothing is registered: the ``entry_points.txt`` files of the
distributions on ``sys.path`` are read once, and ``importlib.metadata`` (with the email
and zip modules it loads: about 20 ms and 1.5 MB at every start) is imported only when one
of them declares a group of the engine (``entry_points``).

This module sits below every table and imports nothing of the engine.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import os
import sys
from collections.abc import Callable, Iterator, Mapping
from typing import Any, TypeVar

__all__ = [
    "Registry",
    "PluginError",
    "GROUPS",
    "ENGINE_DISTRIBUTION",
    "BUILT_IN_ONLY",
    "subclass_of",
    "declared_groups",
    "entry_points",
]

T = TypeVar("T")

#: The entry-point group of each table.
GROUPS = {
    "profiles": "fretting_engine.profiles",
    "criteria": "fretting_engine.criteria",
    "kinds": "fretting_engine.kinds",
    "wear_laws": "fretting_engine.wear_laws",
}
#: The distribution of the built-in entries (named in a clash).
ENGINE_DISTRIBUTION = "fretting-engine"
#: Set (to anything but "") in the environment, the tables hold the built-in entries only
#: (the manual's generated reference, a check without the installed plug-ins).
BUILT_IN_ONLY = "FRETTING_ENGINE_BUILT_IN_ONLY"


#: Where a distribution on a folder of ``sys.path`` keeps its entry points (what
#: importlib.metadata's path finder reads): ``NAME.dist-info/``, ``NAME.egg-info/``.
_METADATA_FOLDERS = (".dist-info", ".egg-info")
_declared: frozenset[str] | None = None
_scanned = False


def declared_groups() -> frozenset[str] | None:
    """The entry-point groups of the engine (``fretting_engine.*``) that some distribution
    on ``sys.path`` declares, read once from the ``entry_points.txt`` of every
    ``*.dist-info`` and ``*.egg-info`` folder in the folders of ``sys.path`` (and of every
    ``*.egg`` folder there); None when this scan cannot answer: a ``sys.path`` entry that is
    a file (a zip archive) or a finder other than the path finder that lists distributions.
    """
    global _declared, _scanned
    if not _scanned:
        _declared, _scanned = _scan_groups(), True
    return _declared


def _scan_groups() -> frozenset[str] | None:
    others = [
        finder
        for finder in sys.meta_path
        if hasattr(finder, "find_distributions") and finder is not importlib.machinery.PathFinder
    ]
    if others:
        return None
    groups: set[str] = set()
    for entry in sys.path:
        folder = entry or os.curdir
        if os.path.isfile(folder):
            return None
        texts = [os.path.join(folder, "EGG-INFO", "entry_points.txt")]
        try:
            names = os.listdir(folder)
        except OSError:
            continue
        texts += [
            os.path.join(folder, name, "entry_points.txt")
            for name in names
            if name.lower().endswith(_METADATA_FOLDERS)
        ]
        for path in texts:
            try:
                with open(path, encoding="utf-8") as file:
                    lines = file.read().splitlines()
            except OSError:
                continue
            groups.update(
                line.strip()[1:-1]
                for line in lines
                if line.strip().startswith("[fretting_engine.") and line.strip().endswith("]")
            )
    return frozenset(groups)


def entry_points(group: str) -> tuple | Any:
    """``importlib.metadata.entry_points(group=group)``; nothing (and importlib.metadata
    not imported) when no distribution declares ``group`` (:func:`declared_groups`)."""
    declared = declared_groups()
    if declared is not None and group not in declared:
        return ()
    return importlib.import_module("importlib.metadata").entry_points(group=group)


class PluginError(ValueError):
    """A plug-in that cannot be registered: a name two distributions register, or an entry
    point whose object is not of the table's kind or is not named after it."""


class Registry(Mapping[str, T]):
    """A read-only table name → object: the built-in entries, then those of the entry-point
    ``group`` in the order :func:`importlib.metadata.entry_points` gives them, loaded on
    first use.

    Parameters
    ----------
    group : str
        Entry-point group, e.g. ``"fretting_engine.profiles"``.
    builtins : mapping
        The engine's own entries, name → object.
    what : str
        What an entry is, in messages ("punch profile").
    check : callable
        ``check(obj)`` raises TypeError when a loaded object is not of the table's kind.
    adapt : callable
        Turns a loaded object into the table's entry (a loading kind's class → an instance).
    """

    def __init__(
        self,
        group: str,
        builtins: Mapping[str, T],
        *,
        what: str,
        check: Callable[[Any], None] = lambda obj: None,
        adapt: Callable[[Any], T] = lambda obj: obj,
    ) -> None:
        self.group, self.what = group, what
        self._builtins = dict(builtins)
        self._check, self._adapt = check, adapt
        self._table: dict[str, T] | None = None
        self._owners: dict[str, str] = {}

    def _loaded(self) -> dict[str, T]:
        if self._table is None:
            table = dict(self._builtins)
            owners = dict.fromkeys(table, ENGINE_DISTRIBUTION)
            points = () if os.environ.get(BUILT_IN_ONLY) else entry_points(group=self.group)
            for point in points:
                owner = point.dist.name if point.dist is not None else point.value
                if point.name in owners:
                    raise PluginError(
                        f"{self.what} {point.name!r} is registered twice, by {owners[point.name]} "
                        f"and by {owner} (entry-point group {self.group}): uninstall one"
                    )
                table[point.name] = self._entry(point, owner)
                owners[point.name] = owner
            self._table, self._owners = table, owners
        return self._table

    def _entry(self, point, owner: str) -> T:
        obj = point.load()
        try:
            self._check(obj)
        except TypeError as error:
            raise PluginError(
                f"{owner}: entry point {point.name!r} = {point.value!r} of {self.group}: {error}"
            ) from None
        entry = self._adapt(obj)
        if getattr(entry, "name", point.name) != point.name:
            raise PluginError(
                f"{owner}: entry point {point.name!r} of {self.group} loads a {self.what} "
                f"named {entry.name!r}: the two names must be the same"
            )
        return entry

    @property
    def builtins(self) -> dict[str, T]:
        """The engine's own entries (what the manual's generated reference describes),
        without looking at entry points."""
        return dict(self._builtins)

    def owner(self, name: str) -> str:
        """The distribution that registers ``name`` (:data:`ENGINE_DISTRIBUTION` for the
        built-in entries)."""
        self._loaded()
        return self._owners[name]

    def reload(self) -> None:
        """Forget the loaded entries: the next read looks the entry points up again."""
        self._table, self._owners = None, {}

    def __getitem__(self, name: str) -> T:
        return self._loaded()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._loaded())

    def __len__(self) -> int:
        return len(self._loaded())

    def __repr__(self) -> str:
        return f"Registry({self.group!r}, {list(self._loaded())})"


def subclass_of(base: type) -> Callable[[Any], None]:
    """A ``check`` for :class:`Registry`: the object must be a subclass of ``base``."""

    def check(obj: Any) -> None:
        if not (isinstance(obj, type) and issubclass(obj, base)):
            raise TypeError(f"{obj!r} is not a subclass of {base.__module__}.{base.__name__}")

    return check
