"""One output holds one study: the identity check, and what to do with an existing file.

Before anything is written, rank 0 inspects an existing results file (read-only) and decides:

``resume``       same study: name and every setting that changes a result (material, punch,
                 mesh, loading, subsurface, solver; see ``StudyConfig.fingerprint``) equal.
                 The case list may differ: an *extended* sweep (new values) adds cases and
                 keeps every completed one; a *shrunk* sweep leaves *stale* cases in the file
                 (no longer in the study), reported by id, kept (default: the CSV lists them
                 too, after the study's cases) or deleted with ``--drop-stale``.
mismatch         another study (different name or settings): :class:`ResultsMismatch`, exit
                 code 2 naming every difference, nothing touched.
``salvage``      the file is damaged (killed while HDF5 metadata was being written, truncated
                 by a full disk, a torn header) but its root and some completed cases can be
                 read: they are copied into a new file (:mod:`engine.output.salvage`), the
                 damaged file is kept as ``<output>.damaged``, the rest is recomputed.
``start-over``   nothing can be read (no completed case can be rescued): the file is moved to
                 ``<output>.damaged`` and the study starts over, saying so. Never a dead end
                 that only ``--fresh`` opens.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

import h5py

from engine.schema import CaseStatus
from engine.study.config import fill_former_defaults
from engine.study.plan import Plan

from .hdf5 import FORMAT, ResultsMismatch, StudyMetadata

__all__ = ["ExistingResults", "inspect_existing", "describe_differences", "study_identity"]

# settings whose change does not change any result (never compared)
_NOT_COMPARED = {("solver", "threads")}
_SECTIONS_NOT_COMPARED = ("study", "testing", "sweep")


def study_identity(resolved: dict[str, dict[str, Any]]) -> str:
    """JSON identity of a study: its name and every compared setting (sweep excluded: the case
    list is compared case by case)."""
    identity = {"name": resolved["study"]["name"]}
    for section, table in resolved.items():
        if section in _SECTIONS_NOT_COMPARED:
            continue
        identity[section] = {
            key: value for key, value in table.items() if (section, key) not in _NOT_COMPARED
        }
    return json.dumps(identity, sort_keys=True)


def describe_differences(stored: dict[str, Any], current: dict[str, Any]) -> list[str]:
    """``[section] key: X in the file, Y in the study`` for every compared setting."""
    differences = []
    if stored.get("name") != current.get("name"):
        differences.append(
            f"study name {stored.get('name')!r} in the file, {current.get('name')!r} in the study"
        )
    for section in sorted(set(stored) | set(current)):
        if section == "name":
            continue
        old, new = stored.get(section, {}), current.get(section, {})
        for key in sorted(set(old) | set(new)):
            if old.get(key) != new.get(key):
                differences.append(
                    f"[{section}] {key}: {_shown(old, key)} in the file, "
                    f"{_shown(new, key)} in the study"
                )
    return differences


def _shown(table: dict[str, Any], key: str) -> str:
    return repr(table[key]) if key in table else "(not set)"


@dataclass
class ExistingResults:
    """What rank 0 found at the output path (see the module docstring)."""

    path: Path
    kind: str  # "resume" | "salvage" | "start-over"
    completed: list[str] = field(default_factory=list)  # readable completed cases
    stale: list[str] = field(default_factory=list)  # in the file, not in the study
    new_cases: int = 0  # in the study, not in the file
    problem: str = ""  # why the file is damaged

    def report(self, stream: TextIO) -> None:
        """Say what happens to the existing file (rank 0, before computing)."""
        if self.kind == "start-over":
            print(
                f"note: {self.path} is damaged and nothing in it can be read ({self.problem}); "
                f"it is kept as {damaged_path(self.path)} and the study starts over",
                file=stream,
                flush=True,
            )
        elif self.kind == "salvage":
            print(
                f"note: {self.path} is damaged ({self.problem}); {len(self.completed)} "
                f"completed case(s) are copied into a new file, the rest is recomputed; the "
                f"damaged file is kept as {damaged_path(self.path)}",
                file=stream,
                flush=True,
            )
        if self.new_cases and self.kind == "resume":
            print(
                f"note: the sweep was extended: {self.new_cases} case(s) not yet in "
                f"{self.path} are added",
                file=stream,
                flush=True,
            )
        if self.stale:
            shown = ", ".join(self.stale[:10]) + (" …" if len(self.stale) > 10 else "")
            print(
                f"note: {len(self.stale)} case(s) in {self.path} are no longer in the study "
                f"(the sweep shrank): {shown}; they are kept in the file and the summary "
                "(--drop-stale deletes them)",
                file=stream,
                flush=True,
            )


def damaged_path(path: Path) -> Path:
    return path.with_name(path.name + ".damaged")


def inspect_existing(path: Path, metadata: StudyMetadata, plan: Plan) -> ExistingResults | None:
    """Read-only look at an existing results file; None when there is none.

    Raises :class:`ResultsMismatch` for a file of another study or another program.
    """
    if not path.exists():
        return None
    try:
        with h5py.File(path, "r") as file:
            attrs = dict(file.attrs)
            check_identity(path, attrs, metadata)
            cases = _case_statuses(file)
    except ResultsMismatch:
        raise
    except Exception as error:  # noqa: BLE001 - any failure to read is damage
        from .salvage import scan_damaged

        return scan_damaged(path, metadata, plan, _short(error))
    planned = set(plan.case_ids)
    return ExistingResults(
        path,
        "resume",
        completed=[case_id for case_id, status in cases.items() if status == CaseStatus.COMPLETED],
        stale=[case_id for case_id in cases if case_id not in planned],
        new_cases=len(planned - set(cases)),
    )


def _case_statuses(file: h5py.File) -> dict[str, str]:
    """case_id -> status of every case group, reading what a resume reads (status, summary)."""
    statuses = {}
    cases = file.get("cases")
    if cases is None:
        raise KeyError("no /cases group")
    for name in cases:
        attrs = cases[name].attrs
        statuses[name] = str(attrs.get("status", ""))
        if statuses[name] == CaseStatus.COMPLETED:
            json.loads(attrs["summary"])
    return statuses


def check_identity(path: Path, attrs: dict[str, Any], metadata: StudyMetadata) -> None:
    """Raise :class:`ResultsMismatch` naming every difference between the file's study and
    ``metadata``'s."""
    if attrs.get("format") != FORMAT:
        raise ResultsMismatch(
            f"{path}: existing file is not a results file of this engine; "
            "use --fresh to overwrite it or choose another [study] output"
        )
    current_text = metadata.attrs.get("study_identity") or study_identity(
        json.loads(metadata.attrs["study_json"])
    )
    current = json.loads(current_text)
    stored_text = attrs.get("study_identity")
    if stored_text is not None:
        stored = json.loads(stored_text)
    else:  # files written before the identity existed: rebuild it from the resolved study
        stored = json.loads(study_identity(json.loads(attrs["study_json"])))
    fill_former_defaults(stored, current)
    differences = describe_differences(stored, current)
    if differences:
        raise ResultsMismatch(
            f"{path}: holds another study: "
            + "; ".join(differences)
            + ". Use --fresh to replace it (its results are deleted) or choose another "
            "[study] output"
        )


def _short(error: BaseException) -> str:
    text = str(error).splitlines()[0] if str(error) else type(error).__name__
    return text[:200]
