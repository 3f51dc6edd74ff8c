"""Loading kinds: one module each, one protocol (:class:`~.base.LoadingKind`), one table.

:data:`KINDS` maps ``[loading] kind`` to its kind; the study layer (configuration, plan,
case runner, layout, memory estimate, feasibility) asks the kind and never branches on its
name. Adding a kind: one module with a :class:`~.base.LoadingKind` subclass, one line below,
its docs (docs/explanation/architecture.md, "Add a loading kind").
"""

from __future__ import annotations

from engine.plugins import GROUPS, Registry, subclass_of

from .base import LoadingKind
from .cyclic import CyclicKind
from .fretting import FrettingKind
from .static import StaticKind

__all__ = ["KINDS", "LoadingKind", "kind_of"]

#: ``[loading] kind`` → its :class:`LoadingKind`: the built-in ones in the order the manual
#: lists them, then those other packages register (entry-point group
#: ``fretting_engine.kinds``, a subclass of :class:`LoadingKind`, :mod:`engine.plugins`).
KINDS: Registry[LoadingKind] = Registry(
    GROUPS["kinds"],
    {kind.name: kind for kind in (StaticKind(), CyclicKind(), FrettingKind())},
    what="loading kind",
    check=subclass_of(LoadingKind),
    adapt=lambda cls: cls(),
)


def kind_of(config) -> LoadingKind:
    """The loading kind of a study configuration (``config.loading.kind``)."""
    return KINDS[config.loading.kind]
