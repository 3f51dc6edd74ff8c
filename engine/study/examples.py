"""Small study files built in code: one base study, sections overridden per use.

Tests, benchmarks and scripts need many small studies that differ in a few keys (a mesh size,
the loading kind, a sweep). Instead of pasting the same TOML block into each file, they call
:func:`study_toml` with the sections they change::

    text = study_toml(
        name="tiny",
        output="out/tiny.h5",
        mesh={"n": 16},
        loading={"kind": "static", "load": 750.0, "steps": 2},
        sweep={"mu1": [0.1, 0.4]},
    )

Each keyword names a section of the study file; its dict is merged into the base section
(:data:`BASE`), a value ``None`` removes the key, and a section given as ``None`` is left out.
The ``loading`` section starts from :data:`CYCLIC_LOADING` or :data:`STATIC_LOADING` by its
``kind``. The text is written by the study layer's TOML writer, so it parses to exactly the
values given (floats by ``repr``). It lives in the package, not in tests/, so that tests,
benchmarks and users import it the same way.

Base values: the paper's materials (steel on a nearly rigid indenter, Section 7), a flat punch
of radius a0 = 1.8 mm, a 16 x 16 mesh, subsurface depth 1.0 a0 in 4 layers.
"""

from __future__ import annotations

import copy
from typing import Any

from .config import dump_toml

__all__ = ["BASE", "CYCLIC_LOADING", "STATIC_LOADING", "study_sections", "study_toml"]

BASE: dict[str, dict[str, Any]] = {
    "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e5, "nu_B": 0.3},  # MPa, 1
    "punch": {"radius": 1.8},  # mm
    "mesh": {"n": 16},
    "subsurface": {"depth": 1.0, "layers": 4},  # depth in units of a0
    "sweep": {"mu1": [0.3]},
}
CYCLIC_LOADING: dict[str, Any] = {
    "kind": "cyclic",
    "load": 750.0,
    "steps": 2,
    "cycles": 200,
    "record": [200],
}  # N, increments per half cycle, cycles
STATIC_LOADING: dict[str, Any] = {"kind": "static", "load": 750.0, "steps": 2}  # N, increments

_ORDER = ("study", "material", "punch", "mesh", "loading", "subsurface", "solver", "sweep")


def _merged(base: dict[str, Any], changes: dict[str, Any]) -> dict[str, Any]:
    merged = copy.deepcopy(base)
    for key, value in changes.items():
        if value is None:
            merged.pop(key, None)
        else:
            merged[key] = value
    return merged


def study_sections(
    name: str, output: str, **sections: dict[str, Any] | None
) -> dict[str, dict[str, Any]]:
    """The study as nested dicts (section -> key -> value); see the module docstring."""
    loading = sections.pop("loading", None) or {}
    start = STATIC_LOADING if loading.get("kind") == "static" else CYCLIC_LOADING
    study = _merged({"name": name, "output": output}, sections.pop("study", None) or {})
    result: dict[str, dict[str, Any]] = {"study": study, "loading": _merged(start, loading)}
    for section, base in BASE.items():
        changes = sections.pop(section, {})
        if changes is not None:
            result[section] = _merged(base, changes)
    for section, changes in sections.items():  # sections without a base ([solver], ...)
        if changes is not None:
            result[section] = dict(changes)
    ranked = sorted(result, key=lambda s: _ORDER.index(s) if s in _ORDER else len(_ORDER))
    return {section: result[section] for section in ranked}


def study_toml(name: str, output: str, **sections: dict[str, Any] | None) -> str:
    """Text of a study file: :data:`BASE` with ``sections`` merged in (module docstring)."""
    return dump_toml(study_sections(name, output, **sections))
