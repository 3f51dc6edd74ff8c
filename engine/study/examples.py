"""Small study files built in code: one base study, sections overridden per use.

Tests, benchmarks and scripts need many small studies that differ in a few keys (a mesh size,
the loading kind, a sweep). Instead of pasting the same TOML block into each file, they call
:func:`study_toml` with the sections they change::

    text = study_toml(
        "tiny",
        "out/tiny.h5",
        mesh={"n": 16},
        loading={"kind": "static", "load": 750.0, "steps": 2},
        sweep={"mu1": [0.1, 0.4]},
    )

Each keyword names a section of the study file; its dict is merged into that section of the
base (:data:`BASE`): a value ``None`` removes the key, a section given as ``None`` is left
out, a section the base lacks (``[solver]``, ``[testing]``) is added. Positional dicts of the
same shape (section -> changes) are merged first, in order: a test module keeps the changes
all its studies share in one dict and passes it before its per-test changes. The
``[loading]`` section starts from :data:`CYCLIC_LOADING`, :data:`STATIC_LOADING` or
:data:`FRETTING_LOADING` by the last ``kind`` given. The text is written by the study
layer's TOML writer, so it parses to exactly the values given (floats by ``repr``, ints stay
ints). It lives in the package, not in tests/, so that tests, benchmarks and users import it
the same way (benchmarks run as scripts and cannot import tests/).

Base values: the paper's materials (steel on a nearly rigid indenter, Section 7), a flat punch
of radius a0 = 1.8 mm, a 16 x 16 mesh, subsurface depth 1.0 a0 in 4 layers.
"""

from __future__ import annotations

import copy
from typing import Any

from .config import dump_toml

__all__ = [
    "BASE",
    "CYCLIC_LOADING",
    "STATIC_LOADING",
    "FRETTING_LOADING",
    "SPHERE_ON_STEEL",
    "CYLINDER_ON_STEEL",
    "study_sections",
    "study_toml",
]

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
FRETTING_LOADING: dict[str, Any] = {
    "kind": "fretting",
    "load": 100.0,
    "steps": 2,
    "cycles": 10,
    "record": [10],
}  # N, increments per quarter tangential cycle, cycles; amplitude or force_amplitude to add
#: A layer for tangential fretting tests: a sphere of radius 10 mm on the same steel (K = 0).
SPHERE_ON_STEEL: dict[str, dict[str, Any]] = {
    "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e3, "nu_B": 0.3},  # MPa, 1
    "punch": {"shape": "sphere", "radius": 10.0},  # mm
}

#: A layer for line (plane-strain) contacts: a steel cylinder of radius 6 mm on a steel flat
#: (McColl et al. 2004), loads per unit length (N/mm); Hertz's a = 0.113 mm at 185 N/mm.
CYLINDER_ON_STEEL: dict[str, dict[str, Any]] = {
    "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e3, "nu_B": 0.3},  # MPa, 1
    "punch": {"shape": "cylinder", "radius": 6.0},  # mm
    "mesh": {"n": 64, "half_width": 0.25},  # elements along x, mm
}

_ORDER = ("study", "material", "punch", "mesh", "loading", "subsurface", "solver", "sweep")


def _kind(layers: list[dict[str, Any]]) -> str:
    kinds = [(layer.get("loading") or {}).get("kind") for layer in layers]
    given = [kind for kind in kinds if kind is not None]
    return given[-1] if given else "cyclic"


def _apply(sections: dict[str, dict[str, Any]], layer: dict[str, Any]) -> None:
    """Merge one layer (section -> changes) into ``sections`` in place."""
    for section, changes in layer.items():
        if changes is None:
            sections.pop(section, None)
            continue
        table = sections.setdefault(section, {})
        for key, value in changes.items():
            if value is None:
                table.pop(key, None)
            else:
                table[key] = copy.deepcopy(value)


def study_sections(
    name: str, output: str, *layers: dict[str, Any], **sections: dict[str, Any] | None
) -> dict[str, dict[str, Any]]:
    """The study as nested dicts (section -> key -> value); see the module docstring."""
    layers = (*layers, sections)
    loading = {"static": STATIC_LOADING, "fretting": FRETTING_LOADING}.get(
        _kind(list(layers)), CYCLIC_LOADING
    )
    result = {"study": {"name": name, "output": str(output)}, "loading": dict(loading)}
    result.update(copy.deepcopy(BASE))
    for layer in layers:
        _apply(result, layer)
    rank = {section: index for index, section in enumerate(_ORDER)}
    ordered = sorted(result, key=lambda section: rank.get(section, len(_ORDER)))
    return {section: result[section] for section in ordered}


def study_toml(
    name: str, output: str, *layers: dict[str, Any], **sections: dict[str, Any] | None
) -> str:
    """Text of a study file: :data:`BASE` with ``layers`` and ``sections`` merged in (see the
    module docstring)."""
    return dump_toml(study_sections(name, output, *layers, **sections))
