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
                 by a full disk, a torn header, overwritten blocks, a flipped bit) but its
                 root and some completed cases can be read and pass their checksums: they are
                 copied into a new file (:mod:`engine.output.salvage`), the damaged file is
                 kept as ``<output>.damaged.N`` (the first free number: no copy is ever
                 overwritten), the rest is recomputed.
``start-over``   nothing can be read (no completed case can be rescued, or reading did not
                 finish within its time limit): the file is moved to ``<output>.damaged.N``
                 and the study starts over, saying so. Never a dead end that only
                 ``--fresh`` opens.

A completed case is trusted only after it has been read back in full and its checksums
compared (:func:`engine.output.checksum.verify_case`), in the same pass that reads the case
statuses. The pass runs in a child process
(``engine.output.existing.inspect_existing_isolated``), where a stop signal and a time limit
reach it even if HDF5 loops on damaged metadata.
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

from .checksum import CaseCheck, verify_case
from .hdf5 import FORMAT, ResultsMismatch, StudyMetadata

__all__ = [
    "ExistingResults",
    "describe_differences",
    "study_identity",
    "damaged_path",
]

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
    completed: list[str] = field(default_factory=list)  # completed cases read and verified
    stale: list[str] = field(default_factory=list)  # in the file, not in the study
    new_cases: int = 0  # in the study, not in the file
    problem: str = ""  # why the file is damaged
    damaged: dict[str, str] = field(default_factory=dict)  # case id -> what is wrong with it
    unverified: int = 0  # completed cases without checksums (older files): read, not compared
    kept_as: Path | None = None  # where a damaged file goes (salvage, start-over)

    def report(self, stream: TextIO, *, drop_stale: bool = False) -> None:
        """Say what happens to the existing file (rank 0, before computing)."""
        for line in self.notes(drop_stale=drop_stale):
            print(line, file=stream, flush=True)

    def notes(self, *, drop_stale: bool = False) -> list[str]:
        """The lines of :meth:`report`; ``drop_stale``: the stale cases are deleted."""
        notes = []
        if self.kind == "start-over":
            notes.append(
                f"note: {self.path} is damaged and nothing in it can be read ({self.problem}); "
                f"it is kept as {self.kept_as} and the study starts over"
            )
        elif self.kind == "salvage":
            notes.append(
                f"note: {self.path} is damaged ({self.problem}); {len(self.completed)} "
                f"completed case(s) passed their checksums and are copied into a new file, "
                f"{len(self.damaged)} damaged case(s) and the rest are recomputed; the damaged "
                f"file is kept as {self.kept_as}"
            )
        if self.unverified:
            notes.append(
                f"note: {self.unverified} completed case(s) in {self.path} carry no checksums "
                "(written by an earlier version): read in full, nothing to compare with"
            )
        if self.new_cases and self.kind == "resume":
            notes.append(
                f"note: the sweep was extended: {self.new_cases} case(s) not yet in "
                f"{self.path} are added"
            )
        if self.stale:
            shown = ", ".join(self.stale[:10]) + (" …" if len(self.stale) > 10 else "")
            notes.append(
                f"note: {len(self.stale)} case(s) in {self.path} are no longer in the study "
                f"(the sweep shrank or changed): {shown}; "
                + (
                    "they are deleted (--drop-stale)"
                    if drop_stale
                    else "they are kept in the file and the summary (--drop-stale deletes them)"
                )
            )
        return notes


def damaged_path(path: Path) -> Path:
    """``<output>.damaged.N`` with the first N (from 1) that does not exist yet."""
    number = 1
    while (candidate := path.with_name(f"{path.name}.damaged.{number}")).exists():
        number += 1
    return candidate


def check_cases(file: h5py.File) -> list[CaseCheck]:
    """:func:`engine.output.checksum.verify_case` of every case group, in file order."""
    cases = file.get("cases")
    if cases is None:
        raise KeyError("no /cases group")
    return [verify_case(cases[name]) for name in cases]


def verdict(
    path: Path, plan: Plan, checks: list[CaseCheck], *, in_file: list[str], problem: str = ""
) -> ExistingResults:
    """What to do with a file whose cases were checked: resume it when every completed case is
    sound; otherwise salvage the sound ones (or start over when there are none)."""
    planned = set(plan.case_ids)
    sound = [check.case_id for check in checks if check.sound]
    trusted = [c for c in checks if c.sound and c.status == CaseStatus.COMPLETED]
    completed = [check.case_id for check in trusted]
    damaged = {check.case_id: check.problem for check in checks if not check.sound}
    unverified = sum(1 for check in trusted if not check.verified)
    if damaged and not problem:
        first = next(iter(damaged.items()))
        problem = f"{len(damaged)} case(s) fail their checks, e.g. {first[0]}: {first[1]}"
    kind = "resume" if not problem else ("salvage" if completed else "start-over")
    kept = [case_id for case_id in in_file if case_id in sound] if kind == "resume" else completed
    return ExistingResults(
        path,
        kind,
        completed=completed,
        stale=[case_id for case_id in kept if case_id not in planned],
        new_cases=len(planned - set(kept)),
        problem=problem,
        damaged=damaged,
        unverified=unverified,
        kept_as=None if kind == "resume" else damaged_path(path),
    )


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
