"""Results file: one HDF5 file per study, written through one writer with a strategy per situation.

Layout (``format = "fretting-engine-results/1"``)::

    /                       attrs: format, engine_version, command_line, study_name,
                                   study_toml (resolved study, defaults filled in), study_json,
                                   study_fingerprint, source (study file), grid_location
    /grid/x, /grid/y        element-centre coordinates (mm), when every case shares the grid
                            (grid_location = "/grid"); absent when a swept key (mesh.n,
                            mesh.half_width, punch.radius, …) changes it from case to case
    /cases/<case_id>/       attrs: case_id, index, mu1, mu2, wear1, wear2, beta (degree),
                                   every swept dotted key (e.g. "loading.load", N),
                                   parameter_units (JSON), status, message, traceback,
                                   rank, runtime_s, cpu_s (CPU s of this run's computing
                                   thread), summary (JSON row of the summary table)
        grid/x, grid/y      the case's own element-centre coordinates (mm)
        history/<name>      per simulated cycle (cyclic) or per load increment (static)
        fields/cycle_NNNNNNN/<name>   surface fields at peak load of a recorded cycle
        fields/final/<name>           surface fields at peak load of the last cycle
        subsurface/cycle_NNNNNNN/ and subsurface/final/
                            x, y, z (mm), von_mises and sigma_<ij> (MPa) in the x–z plane
    every dataset carries ``units`` and ``description`` attributes.

Every case group is created from the plan when the file is prepared (status ``pending``), so
the structure is known before any computation — the shape a collective (mpio) strategy needs,
where structural calls must be identical on all ranks.

Completion flag and kill safety: a case's datasets are written first, then its attributes, and
its ``status`` attribute last, followed by a flush. A group whose status is not ``completed``
(or ``failed``) is incomplete and is emptied and recomputed on resume. The signal handlers of
the CLI only set a flag, so SIGTERM/SIGUSR1/SIGINT never interrupt a write; the file is
consistent after every flush.

Strategies
----------
:class:`SingleWriter` (default): rank 0 owns the file; workers send their outcomes to it.
:class:`engine.output.collective.CollectiveWriter` (mpio): every rank writes its own cases into
the shared file through parallel HDF5; same layout (see that module).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import time
from pathlib import Path
from typing import Any, Protocol

import h5py
import numpy as np

from engine.study.case import COMPLETED, CaseOutcome
from engine.study.plan import Case, Plan

from .summary import pending_row, summary_frame, write_summary_csv

__all__ = [
    "FORMAT",
    "StudyMetadata",
    "ResultsWriter",
    "SingleWriter",
    "ResultsMismatch",
    "read_root_metadata",
    "write_root",
    "remove_outputs",
]

FORMAT = "fretting-engine-results/1"
_PARAMETER_UNITS = {"mu1": "1", "mu2": "1", "wear1": "1/MPa", "wear2": "1/MPa", "beta": "degree"}


class StoppedDuringSetUp(RuntimeError):
    """A stop signal arrived while the new results file was being built (no file left)."""


class ResultsMismatch(ValueError):
    """The existing results file belongs to another study; resuming it would mix results."""


class StudyMetadata:
    """What goes to the root of the file: resolved study, version, command line, grid."""

    def __init__(
        self,
        *,
        name: str,
        source: str,
        study_toml: str,
        study_json: str,
        fingerprint: str,
        command_line: str,
        version: str,
        grid_x: np.ndarray | None,
        grid_y: np.ndarray | None,
    ) -> None:
        self.attrs = {
            "format": FORMAT,
            "engine_version": version,
            "command_line": command_line,
            "study_name": name,
            "source": source,
            "study_toml": study_toml,
            "study_json": study_json,
            "study_fingerprint": fingerprint,
            "grid_location": "/grid" if grid_x is not None else "/cases/<case_id>/grid",
        }
        self.grid_x = None if grid_x is None else np.asarray(grid_x, dtype=float)
        self.grid_y = None if grid_y is None else np.asarray(grid_y, dtype=float)

    @property
    def fingerprint(self) -> str:
        return self.attrs["study_fingerprint"]


class ResultsWriter(Protocol):
    """Interface of every writer strategy."""

    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool) -> set[str]:
        """Create or reopen the file; return the ids of completed cases (skipped on resume)."""

    def write(self, outcome: CaseOutcome) -> None:
        """Store one case atomically (datasets, attributes, status last, flush)."""

    def close(self) -> None: ...


def read_root_metadata(path: str | Path) -> dict[str, Any]:
    with h5py.File(path, "r") as file:
        return dict(file.attrs)


def check_resumable(path: Path, metadata: StudyMetadata) -> None:
    """Raise :class:`ResultsMismatch` when ``path`` exists and holds another study (read-only)."""
    if not path.exists():
        return
    try:
        attrs = read_root_metadata(path)
    except OSError as error:
        raise ResultsMismatch(
            f"{path}: existing file is not readable HDF5 ({error}); use --fresh to start over"
        ) from None
    if attrs.get("format") != FORMAT:
        raise ResultsMismatch(
            f"{path}: existing file is not a results file of this engine; "
            "use --fresh to overwrite it or choose another [study] output"
        )
    if attrs.get("study_fingerprint") != metadata.fingerprint:
        raise ResultsMismatch(
            f"{path}: existing results were computed with different material, punch, mesh, "
            "loading, subsurface or solver settings; use --fresh to start over or choose "
            "another [study] output"
        )


def remove_outputs(output: Path, checkpoint_dir: Path) -> None:
    """--fresh: delete the results file, its summary and the checkpoints of a previous run
    (under the output lock: never while another run holds it, see engine.output.lock)."""
    output.unlink(missing_ok=True)
    creating_path(output).unlink(missing_ok=True)
    output.with_suffix(".csv").unlink(missing_ok=True)
    if checkpoint_dir.exists():
        shutil.rmtree(checkpoint_dir)


def creating_path(output: Path) -> Path:
    """Where a new results file is built: renamed to ``output`` once its structure (root
    attributes, grid, a pending group per case) is complete, so a kill during creation never
    leaves a file that the next run cannot read (the rename is atomic)."""
    return output.with_name(f".{output.name}.creating")


def publish_created(output: Path) -> None:
    """Rename the completed new file into place (atomic on one file system)."""
    os.replace(creating_path(output), output)


def renumber_cases(cases: h5py.Group, plan: Plan, stale: list[str]) -> None:
    """``index`` of every case = its position in the current plan (stale cases after it), so
    an extended or shrunk sweep never leaves two cases with the same index."""
    for index, case_id in enumerate(list(plan.case_ids) + stale):
        group = cases[case_id]
        if group.attrs.get("index") != index:
            group.attrs["index"] = index


def write_root(file: h5py.File, metadata: StudyMetadata) -> None:
    """Root attributes and the grid coordinates; identical calls in every strategy (in mpio
    mode they are collective, so every rank makes them with the same arguments)."""
    file.attrs.update(metadata.attrs)
    if metadata.grid_x is None:
        return  # the grid differs between cases: each case group holds its own
    grid = file.require_group("grid")
    for name, values in (("x", metadata.grid_x), ("y", metadata.grid_y)):
        if name not in grid:
            dataset = grid.create_dataset(name, data=values)
            dataset.attrs["units"] = "mm"
            dataset.attrs["description"] = f"element-centre {name} coordinates"


def settle_stale_cases(
    cases: h5py.Group, plan: Plan, rows: dict[str, dict], *, drop_stale: bool
) -> list[str]:
    """Groups of cases no longer in the plan (a shrunk sweep), for both writers: deleted
    (``drop_stale``) or kept, their stored summary rows put in ``rows``, and listed after the
    plan's cases. Names in sorted order, so every rank of the collective writer agrees."""
    planned = set(plan.case_ids)
    stale = sorted(name for name in cases if name not in planned)
    if drop_stale:
        for name in stale:
            del cases[name]
        return []
    for name in stale:
        rows[name] = stale_row(cases[name])
    return stale


class SingleWriter:
    """Rank 0 is the only writer: it owns the open file; outcomes of other ranks reach it by MPI.

    The summary CSV beside the file is rewritten (atomically) after every case, so it is always
    in step with the HDF5 file.
    """

    def __init__(
        self,
        path: str | Path,
        summary_path: str | Path | None = None,
        *,
        drop_stale: bool = False,
        should_stop=None,
    ) -> None:
        self.path = Path(path)
        self.should_stop = should_stop or (lambda: False)  # a stop signal during creation
        self.summary_path = Path(summary_path) if summary_path else self.path.with_suffix(".csv")
        self.drop_stale = drop_stale
        self._file: h5py.File | None = None
        self._rows: dict[str, dict[str, Any]] = {}
        self._order: list[str] = []
        self._summary = SummaryTable(self.summary_path)
        self._unflagged: list[tuple[h5py.Group, str]] = []  # written, status not yet set
        self.flag_spacing = 10.0
        self._last_commit_end = -math.inf
        self._commit_cost = 0.0

    # ------------------------------------------------------------------ lifecycle
    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool = False) -> set[str]:
        if fresh or not self.path.exists():
            self._create(plan, metadata)
            self._file = h5py.File(self.path, "a")
            self._rows = {case.case_id: pending_row(case.parameters()) for case in plan}
            self._order = list(plan.case_ids)
            self._write_summary(force=True)
            return set()
        check_resumable(self.path, metadata)
        self._file = h5py.File(self.path, "a")
        file = self._file
        write_root(file, metadata)
        cases = file.require_group("cases")
        completed = set()
        for case in plan:
            group = cases.get(case.case_id)
            status = group.attrs.get("status", "") if group is not None else ""
            if status == COMPLETED:
                completed.add(case.case_id)
                self._rows[case.case_id] = json.loads(group.attrs["summary"])
                continue
            self._reset_group(cases, case)
            self._rows[case.case_id] = pending_row(case.parameters())
        stale = settle_stale_cases(cases, plan, self._rows, drop_stale=self.drop_stale)
        renumber_cases(cases, plan, stale)
        self._order = list(plan.case_ids) + stale
        file.flush()
        self._write_summary(force=True)
        return completed

    def _create(self, plan: Plan, metadata: StudyMetadata) -> None:
        """New file: built under a temporary name, renamed when its structure is complete."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        temporary = creating_path(self.path)
        with h5py.File(temporary, "w") as file:
            write_root(file, metadata)
            cases = file.create_group("cases")
            for number, case in enumerate(plan):
                if number % 64 == 0 and self.should_stop():
                    break
                self._reset_group(cases, case)
        if self.should_stop():  # thousands of cases take seconds: stop without the file
            temporary.unlink(missing_ok=True)
            raise StoppedDuringSetUp(f"stopped while creating {self.path}; nothing written")
        publish_created(self.path)

    def close(self) -> None:
        if self._file is not None:
            self._commit_flags(force=True)
            self._file.flush()
            self._file.close()
            self._file = None
            self._write_summary(force=True)

    def __enter__(self) -> SingleWriter:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    # ------------------------------------------------------------------ writing
    def write(self, outcome: CaseOutcome) -> None:
        """Write one case: datasets and attributes now; its ``status`` (the completion flag) at
        the next commit of flags (:meth:`_commit_flags`): flush, statuses, flush."""
        if self._file is None:
            raise RuntimeError("prepare() the writer before writing")
        cases = self._file["cases"]
        group = cases[outcome.case_id] if outcome.case_id in cases else None
        if group is None or len(group) or group.attrs.get("status") != "pending":
            group = self._reset_group(cases, outcome.case)  # a pristine group is reused
        for path, record in outcome.datasets.items():
            dataset = group.create_dataset(path, data=np.asarray(record.data))
            dataset.attrs["units"] = record.units
            dataset.attrs["description"] = record.description
            dataset.attrs.update(getattr(record, "attrs", {}))
        row = dict(outcome.row)
        group.attrs.update(_attribute_safe(outcome.attrs))
        group.attrs["message"] = outcome.message
        group.attrs["traceback"] = outcome.traceback
        group.attrs["rank"] = outcome.rank
        group.attrs["runtime_s"] = outcome.runtime_s
        group.attrs["summary"] = json.dumps(_json_safe(row))
        self._rows[outcome.case_id] = row
        self._unflagged.append((group, outcome.status))
        if self._commit_flags():
            self._write_summary()

    def _commit_flags(self, force: bool = False) -> bool:
        """Flush the written cases, then set their ``status`` and flush again — the completion
        flag reaches the file only after the data. Done after every case while that costs
        little; when cases arrive faster (thousands of small cases), at most every
        ``flag_spacing`` × the cost of the last commit, so flushing stays a small share of the
        run. A kill loses at most the cases of one uncommitted batch (they are recomputed);
        SIGTERM and the end of the run commit everything (``close``)."""
        if not self._unflagged:
            return False
        now = time.perf_counter()
        if not force and now - self._last_commit_end < self.flag_spacing * self._commit_cost:
            return False
        self._file.flush()
        for group, status in self._unflagged:
            group.attrs["status"] = status
        self._file.flush()
        self._unflagged = []
        self._last_commit_end = time.perf_counter()
        self._commit_cost = self._last_commit_end - now
        return True

    # ------------------------------------------------------------------ helpers
    @staticmethod
    def _reset_group(cases: h5py.Group, case: Case) -> h5py.Group:
        """Empty (or create) the group of ``case`` and give it its parameters, status pending."""
        if case.case_id in cases:
            del cases[case.case_id]
        group = cases.create_group(case.case_id)
        group.attrs["status"] = "pending"
        group.attrs.update(case.parameters())
        group.attrs["parameter_units"] = json.dumps(_parameter_units(case))
        group.attrs["summary"] = json.dumps(_json_safe(pending_row(case.parameters())))
        return group

    def rows(self) -> list[dict[str, Any]]:
        return [self._rows[case_id] for case_id in self._order]

    def _write_summary(self, force: bool = False) -> None:
        self._summary.update(self.rows, force=force)


def stale_row(group: h5py.Group) -> dict[str, Any]:
    """Summary row of a stored case no longer in the plan (its stored row, current status)."""
    case_id = group.name.rsplit("/", 1)[-1]
    row = json.loads(group.attrs.get("summary", "{}")) or pending_row({"case_id": case_id})
    row["status"] = str(group.attrs.get("status", row.get("status", "pending")))
    return row


class SummaryTable:
    """The summary CSV beside the results file, rewritten atomically (always a whole table
    listing every case of the file) but not after every case of a large study.

    Rewriting is O(cases), so rewriting after each case costs O(cases²) over a study (36 ms
    per rewrite at 1000 rows). A rewrite is skipped while less than ``spacing`` × the time of
    the last rewrite has passed since it (default 20: at most ~5 % of the wall time goes to
    the summary, and a small study is still rewritten after every case). ``force`` (file
    prepared, run ending) always writes. After a SIGKILL the CSV can lag the HDF5 file by a
    few seconds of cases; the next run rewrites it from the HDF5 file.
    """

    def __init__(self, path: Path, spacing: float = 20.0) -> None:
        self.path = path
        self.spacing = spacing
        self._last_end = -math.inf
        self._last_cost = 0.0
        self.dirty = False

    def update(self, rows, *, force: bool = False) -> None:
        """``rows``: a callable returning the rows (only called when writing)."""
        self.dirty = True
        now = time.perf_counter()
        if not force and now - self._last_end < self.spacing * self._last_cost:
            return
        write_summary_csv(summary_frame(rows()), self.path)
        self._last_end = time.perf_counter()
        self._last_cost = self._last_end - now
        self.dirty = False


def _parameter_units(case: Case) -> dict[str, str]:
    """Units of the case's parameter attributes, swept dotted keys included."""
    from engine.study.config import SWEEPABLE

    units = dict(_PARAMETER_UNITS)
    units.update({key: SWEEPABLE[key] for key, _ in case.settings})
    return units


def _json_safe(row: dict[str, Any]) -> dict[str, Any]:
    """NaN is not JSON: store it as null (pandas reads it back as NaN)."""
    safe = {}
    for key, value in row.items():
        if isinstance(value, np.generic):
            value = value.item()
        if isinstance(value, float) and value != value:
            value = None
        safe[key] = value
    return safe


def _attribute_safe(attrs: dict[str, Any]) -> dict[str, Any]:
    safe = {}
    for key, value in attrs.items():
        if isinstance(value, dict):
            value = json.dumps(_json_safe(value))
        safe[key] = value
    return safe
