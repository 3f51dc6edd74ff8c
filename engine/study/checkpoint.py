"""Checkpoints of interrupted cyclic cases: a ``CyclicState`` to and from an .npz file.

The solver (``engine.solvers.cyclic``) keeps a plain state object; reading and writing it is
the study layer's business (the case runner saves it to ``<output>.checkpoints/<case>.npz``
when a case is stopped and resumes from it on the next run). Format (unchanged since the
cycle-jump work, so older checkpoints resume): one array per entry —

- ``wear`` (mm); ``contact_<field>``: the unloaded contact state (pressure, traction_x,
  traction_y in MPa, displacement_x, displacement_y in mm);
- ``history_<column>``: the history rows so far (probe columns included);
- ``record_<cycle>_<field>``, ``change_<cycle>_<field>``: recorded fields and region changes;
- ``scalars``: [cycle, jump, matvecs, load_steps, approach (mm), step-size estimate (mm/MPa,
  NaN when none)]; ``failures``: messages of increments that did not converge;
- ``warm_<field>`` (cycles × increments × n_x × n_y) and ``warm_jump``: the warm-start
  increments of the last simulated cycles, when present.

Writes are atomic (temporary file, then rename): a stop during the write leaves the former
checkpoint or none.
"""

from __future__ import annotations

import errno
from pathlib import Path

import numpy as np

from engine.solvers.contact import ContactState
from engine.solvers.cyclic import HISTORY_KEYS, WARM_KEYS, CyclicState
from engine.solvers.fretting import FrettingState

__all__ = [
    "save_cyclic_state",
    "load_cyclic_state",
    "save_fretting_state",
    "load_fretting_state",
    "load_extra",
]


def _arrays(state: CyclicState) -> dict[str, np.ndarray]:
    """The checkpoint's arrays (module docstring)."""
    arrays = {"wear": state.wear}
    for key, value in state.contact.arrays().items():
        arrays[f"contact_{key}"] = value
    for key, values in state.history.items():
        arrays[f"history_{key}"] = np.asarray(values, dtype=float)
    for cycle, fields in state.records.items():
        for key, value in fields.items():
            arrays[f"record_{cycle}_{key}"] = value
    for cycle, fields in state.region_changes.items():
        for key, value in fields.items():
            arrays[f"change_{cycle}_{key}"] = value
    step = np.nan if state.step_size_estimate is None else state.step_size_estimate
    arrays["scalars"] = np.array(
        [state.cycle, state.jump, state.matvecs, state.load_steps, state.contact.approach, step],
        dtype=float,
    )
    arrays["failures"] = np.array(state.failures, dtype=str)
    if state.warm:
        for key in WARM_KEYS:
            arrays[f"warm_{key}"] = np.array(
                [[getattr(c, key) for c in cycle] for cycle in state.warm]
            )
        arrays["warm_jump"] = np.array(state.warm_jump)
    return arrays


def save_cyclic_state(state: CyclicState, path: str | Path) -> None:
    """Write ``state`` to ``path`` (.npz) atomically (temporary file, then rename)."""
    _write(path, _arrays(state))


def _write(path: str | Path, arrays: dict[str, np.ndarray]) -> None:
    """Atomically; on a full disk (or quota) no checkpoint is left, not even a partial one:
    the interrupted case starts again from its first cycle when the study is rerun."""
    path = Path(path)
    temporary = path.with_name(path.name + ".tmp.npz")
    try:
        np.savez(temporary, **arrays)
        temporary.replace(path)
    except OSError as error:
        temporary.unlink(missing_ok=True)
        if error.errno not in (errno.ENOSPC, errno.EDQUOT):
            raise
        path.unlink(missing_ok=True)


def save_fretting_state(
    state: FrettingState, path: str | Path, extra: dict[str, np.ndarray] | None = None
) -> None:
    """The cyclic checkpoint of ``state`` plus the fretting arrays: ``fretting_rigid`` (the
    rigid tangential displacement δ at the next cycle's start, mm), ``fretting_rigid_warm``
    (δ·d of the last simulated cycle's increments, mm), ``fretting_stiffness`` (N/mm), and
    the ``extra`` arrays of the case's analyses (names starting with ``fatigue_``: the
    evaluated fatigue cycles, ``engine.study.fatigue.FatigueAnalysis.arrays``)."""
    arrays = dict(extra or {})
    if any(not name.startswith("fatigue_") for name in arrays):
        raise ValueError(f"extra checkpoint arrays must start with 'fatigue_': {list(arrays)}")
    arrays.update(_arrays(state))
    arrays["fretting_rigid"] = np.asarray(state.rigid, dtype=float)
    arrays["fretting_rigid_warm"] = np.asarray(state.rigid_warm, dtype=float)
    arrays["fretting_stiffness"] = np.array(state.stiffness)
    _write(path, arrays)


def load_fretting_state(path: str | Path) -> FrettingState:
    """The ``FrettingState`` saved by ``save_fretting_state`` at ``path``."""
    base = load_cyclic_state(path)
    with np.load(path) as data:
        return FrettingState(
            **vars(base),
            rigid=data["fretting_rigid"],
            rigid_warm=data["fretting_rigid_warm"],
            stiffness=float(data["fretting_stiffness"]),
        )


def load_extra(path: str | Path, prefix: str = "fatigue_") -> dict[str, np.ndarray]:
    """The arrays of a checkpoint whose names start with ``prefix`` (``save_fretting_state``'s
    ``extra``; empty for a checkpoint without them)."""
    with np.load(path) as data:
        return {name: data[name] for name in data.files if name.startswith(prefix)}


def _history(data) -> dict[str, list]:
    history = {k: list(data[f"history_{k}"]) for k in HISTORY_KEYS}
    for name in data.files:  # probe columns (peak history), when present
        if name.startswith("history_") and name[8:] not in history:
            history[name[8:]] = list(data[name])
    return history


def _fields_by_cycle(data, prefix: str) -> dict[int, dict[str, np.ndarray]]:
    """``<prefix><cycle>_<field>`` arrays grouped by cycle."""
    grouped: dict[int, dict[str, np.ndarray]] = {}
    for name in data.files:
        if name.startswith(prefix):
            _, cycle_text, key = name.split("_", 2)
            grouped.setdefault(int(cycle_text), {})[key] = data[name]
    return grouped


def _warm(data) -> list[list[ContactState]]:
    """The warm-start increments of a checkpoint, per cycle (empty when it has none)."""
    if "warm_pressure" not in data.files:
        return []
    fields = [data[f"warm_{key}"] for key in WARM_KEYS]
    zeros = np.zeros(fields[0].shape[2:])
    return [
        [ContactState(p, tx, ty, zeros, zeros) for p, tx, ty in zip(*cycle, strict=True)]
        for cycle in zip(*fields, strict=True)
    ]


def load_cyclic_state(path: str | Path) -> CyclicState:
    """The ``CyclicState`` saved by ``save_cyclic_state`` at ``path``."""
    with np.load(path) as data:
        cycle, jump, matvecs, load_steps, approach, step = data["scalars"]
        contact = ContactState(
            data["contact_pressure"],
            data["contact_traction_x"],
            data["contact_traction_y"],
            data["contact_displacement_x"],
            data["contact_displacement_y"],
            float(approach),
        )
        return CyclicState(
            wear=data["wear"],
            contact=contact,
            cycle=int(cycle),
            jump=int(jump),
            history=_history(data),
            records=_fields_by_cycle(data, "record_"),
            region_changes=_fields_by_cycle(data, "change_"),
            matvecs=int(matvecs),
            load_steps=int(load_steps),
            failures=[str(f) for f in data["failures"]],
            step_size_estimate=None if np.isnan(step) else float(step),
            warm=_warm(data),
            warm_jump=int(data["warm_jump"]) if "warm_jump" in data.files else 0,
        )
