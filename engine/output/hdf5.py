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
    every dataset carries ``units`` and ``description`` attributes (paths, units and descriptions:
    :mod:`engine.schema`); grid/x and grid/y are HDF5
    dimension scales, a case's own attached to dimensions 0 and 1 of its surface fields
    (fields/*, peak_changes/*), see :func:`attach_grid_scales`.

Every case group is created from the plan when the file is prepared (status ``pending``), so
the structure is known before any computation — the shape a collective (mpio) strategy needs,
where structural calls must be identical on all ranks.

Completion flag and kill safety: a case's datasets are written first, then its attributes, and
its ``status`` attribute last, followed by a flush. A group whose status is not ``completed``
(or ``failed``) is incomplete and is emptied and recomputed on resume. The signal handlers of
the CLI only set a flag, so SIGTERM/SIGUSR1/SIGINT never interrupt a write; the file is
consistent after every flush.

Strategies (the writer family)
------------------------------
:class:`ResultsWriter` owns what every strategy shares: ``prepare`` (check an existing file,
build a new one under a temporary name, reset incomplete cases, settle stale ones), the
pending group of a case and the structural write of a finished one. Its strategies:

:class:`SingleWriter` (default): rank 0 owns the file; workers send their outcomes to it (a
    :class:`Bystander` on the other ranks).
:class:`engine.output.collective.CollectiveWriter` (mpio): every rank writes its own cases into
    the shared file through parallel HDF5; same layout (see that module).

``engine.output.writers.open_writer`` picks the strategy's writer for a rank; the one compute
path uses it.
"""

from __future__ import annotations

import contextlib
import gc
import json
import math
import os
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from engine.commands import RESULTS_FORMAT
from engine.schema import CASES_GROUP, GRID_GROUP, CaseStatus
from engine.study.case import COMPLETED, CaseOutcome
from engine.study.config import same_fingerprint
from engine.study.plan import Case, Plan
from engine.study.units import parameter_units

from .checksum import (
    CASE_CHECKSUM,
    DATASET_CHECKSUM,
    ROOT_CHECKSUM,
    case_checksum,
    manifest_entry,
    root_checksum,
)
from .ensemble import ensemble_path
from .lowlevel import attach_scales, create_dataset, make_scale, set_attribute
from .packed import PackedOutcome, pack, unpack
from .space import (
    CLAIM_SLACK,
    MARGIN,
    OutputFull,
    SpareFile,
    case_bytes,
    claim,
    claimed,
    ensure_space,
    is_no_space,
    unclaim,
)
from .summary import pending_row, write_summary_csv
from .thresholds import thresholds_path, write_thresholds, write_thresholds_csv

__all__ = [
    "FORMAT",
    "StudyMetadata",
    "ResultsWriter",
    "SingleWriter",
    "Bystander",
    "case_record",
    "ResultsMismatch",
    "read_root_metadata",
    "write_root",
    "remove_outputs",
]

FORMAT = RESULTS_FORMAT  # the root attribute "format" (engine.commands tells files apart)


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
    if not same_fingerprint(attrs.get("study_fingerprint"), metadata.fingerprint):
        raise ResultsMismatch(
            f"{path}: existing results were computed with different material, punch, mesh, "
            "loading, subsurface or solver settings; use --fresh to start over or choose "
            "another [study] output"
        )


def remove_outputs(output: Path, checkpoint_dir: Path) -> None:
    """--fresh: delete the results file, its summary (and thresholds) and the checkpoints of a
    previous run
    (under the output lock: never while another run holds it, see engine.output.lock)."""
    output.unlink(missing_ok=True)
    creating_path(output).unlink(missing_ok=True)
    output.with_suffix(".csv").unlink(missing_ok=True)
    thresholds_path(output.with_suffix(".csv")).unlink(missing_ok=True)  # a [search] study's
    ensemble_path(output.with_suffix(".csv")).unlink(missing_ok=True)  # a [surface] study's
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
    file.attrs[ROOT_CHECKSUM] = root_checksum(metadata.attrs)
    if metadata.grid_x is None:
        return  # the grid differs between cases: each case group holds its own
    grid = file.require_group(GRID_GROUP)
    for name, values in (("x", metadata.grid_x), ("y", metadata.grid_y)):
        if name not in grid:
            dataset = grid.create_dataset(name, data=values)
            dataset.attrs["units"] = "mm"
            dataset.attrs["description"] = f"element-centre {name} coordinates"
            dataset.make_scale(name)  # the shared grid as a dimension scale (not attached)


SURFACE_FIELD_GROUPS = ("fields/", "peak_changes/")  # surface fields (n_x, n_y), ij indexing


def attach_grid_scales(group: h5py.Group, datasets: dict[str, h5py.Dataset]) -> None:
    """The case's ``grid/x`` and ``grid/y`` become HDF5 dimension scales (named ``x`` and
    ``y``), attached to dimensions 0 and 1 of every surface field of shape (n_x, n_y) among
    ``datasets`` (path -> h5py dataset or its ``DatasetID``; ``fields/*``, ``peak_changes/*``;
    ij indexing: axis 0 is x). Readers that know dimension scales (h5py ``dataset.dims``,
    HDFView) then find each field's coordinates; the data is unchanged. Subsurface planes
    carry their own 2-D x, z arrays."""
    x, y = datasets.get("grid/x"), datasets.get("grid/y")
    if x is None or y is None:
        return
    shape = (x.shape[0], y.shape[0])
    fields = [
        dataset
        for path, dataset in datasets.items()
        if path.startswith(SURFACE_FIELD_GROUPS) and dataset.shape == shape
    ]
    if not fields:
        return
    make_scale(x, "x")
    make_scale(y, "y")
    for field in fields:
        attach_scales(field, (x, y))


def _scaled(path: str) -> bool:
    """Whether :func:`attach_grid_scales` may use the dataset at ``path`` (a case's grid or a
    surface field)."""
    return path in ("grid/x", "grid/y") or path.startswith(SURFACE_FIELD_GROUPS)


_SCALE_ATTRIBUTES = ("DIMENSION_LIST", "REFERENCE_LIST", "CLASS", "NAME")


def reattach_grid_scales(group: h5py.Group, source: h5py.Group | None = None) -> None:
    """After ``H5Ocopy`` into another file (salvage) the object references of dimension
    scales point nowhere (HDF5 does not rewrite them): drop them and attach the copy's own,
    in the order the fields were attached in ``source`` (the original group), so the copy's
    scale attributes equal the original's."""
    paths: list[str] = []
    group.visit(paths.append)
    datasets = [path for path in paths if isinstance(group[path], h5py.Dataset)]
    for path in datasets:
        attrs = group[path].attrs
        for name in _SCALE_ATTRIBUTES:
            if name in attrs:
                del attrs[name]
    first = attached_fields(source) if source is not None else []
    ordered = [path for path in first if path in datasets]
    ordered += [path for path in datasets if path not in ordered]
    attach_grid_scales(group, {path: group[path] for path in ordered})


def attached_fields(group: h5py.Group) -> list[str]:
    """Paths (relative to ``group``) of the fields attached to its ``grid/x`` scale, in the
    order they were attached; [] when it cannot be read."""
    try:
        references = group["grid/x"].attrs["REFERENCE_LIST"]
        paths: list[str] = []
        group.visit(paths.append)
        objects = {path: group[path] for path in paths}
        order = []
        for entry in references:  # a path of an object opened by reference may be unknown
            target = group.file[entry[0]]
            order += [path for path, item in objects.items() if item == target]
        return order
    except Exception:  # noqa: BLE001 - a damaged list: the default order
        return []


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


class ResultsWriter:
    """Base of the writer family: what every strategy does the same way.

    It owns the life of the file up to the first case — :meth:`prepare` (look at an existing
    file, build a new one under a temporary name with a pending group per case, or reopen it,
    reset the incomplete cases, settle stale ones, renumber) — the pending group of a case
    (:meth:`_reset_group`), the structural write of a finished case (:meth:`_store_case`:
    datasets with ``units`` and ``description``, then the case attributes; the ``status``
    flag is set by the strategy, after a flush), and the summary rows. A strategy supplies how
    the file is opened (:meth:`_open`), how the ranks agree (:meth:`_look_at_existing`,
    :meth:`_stop_agreed`, :meth:`_publish`, :meth:`_discard`), what a pending group holds
    beyond its attributes (:meth:`_pending_group`), and ``write`` / ``close``.

    Every call of ``prepare`` and ``close`` is made on the ranks the strategy names (rank 0
    alone for :class:`SingleWriter`, every rank for the collective writer), which is why the
    CLI has one compute path for all of them (``engine.output.writers.open_writer``).
    """

    collective = False  # True: prepare/close are collective calls on every rank
    announce_suffix = ""  # appended to the CLI's start line

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
        self.is_root = True  # the rank that keeps the summary CSV
        self.full: OutputFull | None = None  # set when the file system filled up
        self._file: h5py.File | None = None
        self._plan: Plan | None = None
        self._rows: dict[str, dict[str, Any]] = {}
        self._order: list[str] = []
        self._summary = SummaryTable(self.summary_path)

    # ------------------------------------------------------------------ prepare
    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool = False) -> set[str]:
        """Create or reopen the file; return the ids of completed cases (skipped on resume).

        A new file is built under a temporary name and renamed once its structure is complete
        (:meth:`_create`); an existing one (same study, checked first) keeps its completed
        cases, and every other case of the plan gets a pristine pending group."""
        exists = self._look_at_existing(metadata, fresh)
        if not exists:
            self._create(plan, metadata)
        self._file = self._open(self.path, "a")
        resumed = self._file.get(CASES_GROUP) if exists else None
        self._claim_for(self._file, self._pending_bytes(plan, resumed), self.path)
        cases = self._file.require_group(CASES_GROUP)
        completed: set[str] = set()
        stale: list[str] = []
        if exists:
            write_root(self._file, metadata)
            self._settle_leftovers(cases)
            completed = self._reset_incomplete(cases, plan)
            stale = settle_stale_cases(cases, plan, self._rows, drop_stale=self.drop_stale)
            renumber_cases(cases, plan, stale)
        else:
            self._rows = {case.case_id: pending_row(case.parameters()) for case in plan}
        self._plan = plan
        self._order = list(plan.case_ids) + stale
        self._file.flush()
        self._prepared()
        return completed

    def _look_at_existing(self, metadata: StudyMetadata, fresh: bool) -> bool:
        """Whether an existing file is resumed (checked to hold this study; raises
        :class:`ResultsMismatch` otherwise); a new file's folder is created."""
        exists = self.path.exists() and not fresh
        if exists:
            check_resumable(self.path, metadata)
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        return exists

    def _create(self, plan: Plan, metadata: StudyMetadata) -> None:
        """New file: built under a temporary name, renamed when its structure is complete.
        A stop signal is looked at every 64 cases (thousands of cases take seconds): the
        temporary is removed and :class:`StoppedDuringSetUp` raised."""
        temporary = creating_path(self.path)
        stopped = False
        with self._open(temporary, "w") as file:
            self._claim_for(file, self._pending_bytes(plan), temporary)
            write_root(file, metadata)
            cases = file.create_group(CASES_GROUP)
            for number, case in enumerate(plan):
                if number % 64 == 0 and self._stop_agreed():
                    stopped = True
                    break
                self._pending_group(cases, case)
        if stopped or self._stop_agreed():
            self._discard(temporary)
            raise StoppedDuringSetUp(f"stopped while creating {self.path}; nothing written")
        self._publish()

    def _reset_incomplete(self, cases: h5py.Group, plan: Plan) -> set[str]:
        """Resume: completed cases keep their group and stored summary row; every other case
        of the plan gets a pristine pending group."""
        completed = set()
        for case in plan:
            group = cases.get(case.case_id)
            status = group.attrs.get("status", "") if group is not None else ""
            if status == COMPLETED:
                completed.add(case.case_id)
                self._rows[case.case_id] = json.loads(group.attrs["summary"])
                continue
            self._pending_group(cases, case)
            self._rows[case.case_id] = pending_row(case.parameters())
        return completed

    def _prepared(self) -> None:
        """The file is ready: the summary CSV lists every case."""
        if self.is_root:
            self._summary.update(self.rows, force=True)

    # ------------------------------------------------------------------ strategy hooks
    def _open(self, path: Path, mode: str) -> h5py.File:
        return h5py.File(path, mode)

    def _stop_agreed(self) -> bool:
        return bool(self.should_stop())

    def _pending_bytes(self, plan: Plan, resumed: h5py.Group | None = None) -> int:
        """Bytes the pending groups of ``plan``'s cases add to the file (``resumed``: the
        cases group of the file being resumed; its completed cases keep their groups)."""
        return PENDING_GROUP_BYTES * len(plan)

    def _claim_for(self, file: h5py.File, needed: int, path: Path) -> None:
        """Claim ``needed`` bytes past the end of the open ``file`` before the structural
        writes of :meth:`prepare` (:func:`claim_for`)."""
        claim_for(file, needed, path)

    def _discard(self, temporary: Path) -> None:
        temporary.unlink(missing_ok=True)

    def _publish(self) -> None:
        publish_created(self.path)

    def _settle_leftovers(self, cases: h5py.Group) -> None:
        """Resume: what a killed run of this strategy left to finish (nothing here)."""

    def _pending_group(self, cases: h5py.Group, case: Case) -> h5py.Group:
        return self._reset_group(cases, case)

    # ------------------------------------------------------------------ cases
    @staticmethod
    def _reset_group(cases: h5py.Group, case: Case) -> h5py.Group:
        """Empty (or create) the group of ``case`` and give it its parameters, status pending."""
        if case.case_id in cases:
            del cases[case.case_id]
        group = cases.create_group(case.case_id)
        set_attribute(group, "status", str(CaseStatus.PENDING))
        parameters = case.parameters()
        for name, value in parameters.items():
            set_attribute(group, name, value)
        set_attribute(group, "parameter_units", json.dumps(_parameter_units(case)))
        set_attribute(group, "summary", json.dumps(_json_safe(pending_row(parameters))))
        return group

    @staticmethod
    def _store_case(group: h5py.Group, record: dict[str, Any]) -> None:
        """The structural write of a finished case (:func:`case_record`), status aside:
        datasets (created, or already written into a pre-created one) with their units and
        description and the grid's dimension scales, then the case attributes and its summary
        row. Through :mod:`engine.output.lowlevel`: the same objects as h5py's high-level
        calls, in about a third of the time."""
        datasets, parents = {}, {}
        packed = [path for path, item in record["datasets"].items() if item.get("packed")]
        # of the copies, only the grid and the surface fields are opened (for their scales)
        unpacked = unpack(group, record["image"], packed, opened=_scaled) if packed else {}
        for path, item in record["datasets"].items():
            if item.get("packed"):  # copied with its attributes from the computing rank's image
                if path in unpacked:
                    datasets[path] = unpacked[path]
                continue
            new = not item.get("written")
            if new:  # a DatasetID: no high-level wrapper per dataset
                dataset = create_dataset(group, path, item["data"], parents, wrap=False)
            else:
                dataset = group[path].id
            set_attribute(dataset, "units", item["units"], new=new)
            set_attribute(dataset, "description", item["description"], new=new)
            for name, value in item.get("attrs", {}).items():
                set_attribute(dataset, name, value, new=new)
            datasets[path] = dataset
        attach_grid_scales(group, datasets)
        for name, value in record["attrs"].items():
            set_attribute(group, name, value)
        set_attribute(group, "message", record["message"])
        set_attribute(group, "traceback", record["traceback"])
        set_attribute(group, "rank", record["rank"])
        set_attribute(group, "runtime_s", record["runtime_s"])
        set_attribute(group, "summary", json.dumps(_json_safe(record["row"])))
        set_attribute(group, CASE_CHECKSUM, record["checksum"])

    def rows(self) -> list[dict[str, Any]]:
        return [self._rows[case_id] for case_id in self._order]

    def committed(self, outcome: CaseOutcome) -> list[CaseOutcome]:
        """The outcomes whose completion flags are on disk since the last call, after
        ``write(outcome)``: what the run may announce. Here: ``outcome`` (written whole at
        once); a strategy that commits flags in batches returns them as they are committed."""
        return [outcome]

    def commit(self) -> list[CaseOutcome]:
        """Commit every flag written so far (the scheduling has ended); the outcomes
        committed since the last call."""
        return []

    def computing(self, run_case):
        """What a rank > 0 runs per case: ``run_case`` itself unless the strategy writes there."""
        return run_case

    def closing_note(self) -> str | None:
        """A line for the end of the run (rank 0), or None."""
        return None

    # ------------------------------------------------------------------ interface
    def write(self, outcome: CaseOutcome) -> None:
        """Store one case (rank 0, every outcome)."""
        raise NotImplementedError

    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self) -> ResultsWriter:
        return self

    def __exit__(self, exc_type, *exc_info) -> None:
        # a collective close after an exception on one rank would wait forever: the entry
        # point aborts the communicator instead
        if exc_type is None or not self.collective:
            self.close()


SUMMARY_ROW_BYTES = 512  # bytes of a summary row (about 300 at most; for the spare file)


def file_descriptor(file: h5py.File) -> int | None:
    """The operating-system descriptor of an open file (HDF5's default driver), or None."""
    if file.driver != "sec2":
        return None
    try:
        return int(file.id.get_vfd_handle())
    except Exception:  # noqa: BLE001 - no descriptor to be had: no claims
        return None


PENDING_GROUP_BYTES = 4096  # bytes a pending case group takes in the file (attributes)


def claim_for(file: h5py.File, needed: int, path: Path) -> None:
    """Claim ``needed`` bytes (and the slack) past the end of the open ``file`` before writing
    them (:func:`engine.output.space.claim`; nothing for a driver without a descriptor)."""
    descriptor = file_descriptor(file)
    if descriptor is not None:
        claim(descriptor, needed + CLAIM_SLACK, path)


class SingleWriter(ResultsWriter):
    """Rank 0 is the only writer: it owns the open file; outcomes of other ranks reach it by MPI.

    Completion flags are committed in batches when cases arrive fast (:meth:`_commit_flags`);
    the summary CSV beside the file is rewritten atomically after a commit (:class:`SummaryTable`).
    """

    def __init__(self, path, summary_path=None, *, drop_stale=False, should_stop=None) -> None:
        super().__init__(path, summary_path, drop_stale=drop_stale, should_stop=should_stop)
        self._unflagged: list[tuple[h5py.Group, CaseOutcome]] = []  # status not yet set
        self._announce: list[CaseOutcome] = []  # flags committed, not yet announced
        self._descriptor: int | None = None  # the open file's descriptor (space claims)
        self._broken = False  # a write failed inside HDF5: the open file is unusable
        self._spare = SpareFile(self.path)
        self._pristine: set[str] = set()  # cases whose pending group nothing has touched yet
        self._cases: h5py.Group | None = None  # the open file's /cases (set by prepare)
        self.flag_spacing = 10.0
        self._last_commit_end = -math.inf
        self._commit_cost = 0.0

    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool = False) -> set[str]:
        """:meth:`ResultsWriter.prepare`; a full disk meanwhile raises
        :class:`engine.output.space.OutputFull` (a new file is not left behind; a resumed
        one is as its last run left it or, where HDF5 failed half-way, salvaged by the next
        run)."""
        try:
            completed = super().prepare(plan, metadata, fresh=fresh)
        except Exception as error:
            if not is_no_space(error):
                raise
            self._broken = not isinstance(error, OutputFull)
            if self._file is not None:
                self._close_file()
            creating_path(self.path).unlink(missing_ok=True)
            if isinstance(error, OutputFull):
                raise
            raise OutputFull(self.path, PENDING_GROUP_BYTES * len(plan)) from None
        self._cases = self._file[CASES_GROUP]
        self._descriptor = file_descriptor(self._file)
        self._spare.hold(SUMMARY_ROW_BYTES * len(self._order) + CLAIM_SLACK)
        # every case of the plan not completed has a pristine pending group now
        self._pristine = set(plan.case_ids) - completed
        return completed

    def close(self) -> None:
        """Commit the last flags, close the file, write the summary. On a full disk what can
        still be committed is (the spare blocks are given back for it), the summary is
        written if it fits; the file is closed whatever happens."""
        if self._file is None:
            return
        if not self._broken:
            try:
                self._claim(0)
                self._commit_flags(force=True)
                self._file.flush()
            except Exception as error:
                if not is_no_space(error):
                    raise
                self._became_full(error, MARGIN)
        self._close_file()
        if self.full is not None:
            self._spare.release()  # room for the summary
        try:
            self._write_summary(force=True)
        except OSError as error:  # the next run rewrites the summary from the file
            if not is_no_space(error):
                raise
            self.full = self.full or OutputFull(self.path, MARGIN)
        self._spare.release()

    def _close_file(self) -> None:
        """Close the HDF5 file, then give back the blocks claimed past its end. A file whose
        library state a failed write broke is closed quietly (HDF5 cannot flush it again;
        the file on disk is as the last successful flush left it)."""
        file, self._file = self._file, None
        if self._broken:
            with _quiet_unraisable(), contextlib.suppress(Exception):
                file.close()
        else:
            file.close()
        unclaim(self.path)

    def write(self, outcome: CaseOutcome) -> None:
        """Write one case: datasets and attributes now; its ``status`` (the completion flag) at
        the next commit of flags (:meth:`_commit_flags`): flush, statuses, flush.

        The space a case takes is claimed before it is begun
        (:func:`engine.output.space.claim`); a case that does not fit is not begun, and the
        writer is then ``full`` (:class:`engine.output.space.OutputFull`) and writes nothing
        more: the cases committed so far stay complete, the rest is computed by the next
        run."""
        if self._file is None:
            raise RuntimeError("prepare() the writer before writing")
        if self.full is not None:
            return
        record = case_record(outcome)
        needed = _record_bytes(record)
        try:
            held = claimed(self._descriptor) + self._spare.held * self._spare.size
            ensure_space(self.path, needed, remaining_cases=self._remaining, held=held)
            self._claim(2 * needed)
            self._write_record(outcome, record)
        except Exception as error:
            if not is_no_space(error):
                raise
            self._became_full(error, needed * max(self._remaining(), 1))

    def committed(self, outcome: CaseOutcome) -> list[CaseOutcome]:
        """The outcomes whose completion flags reached the file since the last call (after
        writing ``outcome``): only these are announced, so what the run prints as completed
        is on disk."""
        done, self._announce = self._announce, []
        return done

    def commit(self) -> list[CaseOutcome]:
        """Commit every written flag now; the outcomes committed since the last call."""
        if self._file is not None and not self._broken and self.full is None:
            try:
                self._claim(0)
                self._commit_flags(force=True)
            except Exception as error:
                if not is_no_space(error):
                    raise
                self._became_full(error, MARGIN)
        done, self._announce = self._announce, []
        return done

    def _remaining(self) -> int:
        return sum(1 for row in self._rows.values() if row.get("status") == CaseStatus.PENDING)

    def _claim(self, needed: int) -> None:
        """Claim ``needed`` bytes and :data:`engine.output.space.CLAIM_SLACK` past the end of
        the file before writing them: a write that could not be finished is never begun."""
        if self._descriptor is not None:
            claim(self._descriptor, needed + CLAIM_SLACK, self.path)

    def _became_full(self, error: BaseException, needed: int) -> None:
        """No more cases. An error of HDF5 itself (a write that failed half-way, where no
        space could be claimed) leaves its open file unusable: nothing more is written to it.
        Otherwise the written cases are committed, with the spare blocks given back for it;
        cases whose flags could not be committed are pending again (never announced)."""
        if self.full is None:  # the first fault names what the run needed
            self.full = error if isinstance(error, OutputFull) else OutputFull(self.path, needed)
        if not isinstance(error, OutputFull) and not isinstance(error, _SummaryFull):
            self._broken = True
        if not self._broken:
            self._spare.release()
            try:
                self._claim(0)
                self._commit_flags(force=True)
            except Exception as failure:  # noqa: BLE001 - a failed flush: the handle is gone
                if not isinstance(failure, OutputFull):
                    self._broken = True
        for _, outcome in self._unflagged:  # never flagged: computed again by the next run
            self._rows[outcome.case_id] = pending_row(outcome.case.parameters())
        self._unflagged = []

    def _write_record(self, outcome: CaseOutcome, record: dict[str, Any]) -> None:
        cases = self._cases
        if outcome.case_id in self._pristine:  # prepared and untouched since: no checks
            self._pristine.discard(outcome.case_id)
            group = cases[outcome.case_id]
        else:
            group = cases[outcome.case_id] if outcome.case_id in cases else None
            if group is None or len(group) or group.attrs.get("status") != CaseStatus.PENDING:
                group = self._reset_group(cases, outcome.case)  # a pristine group is reused
        self._store_case(group, record)
        self._rows[outcome.case_id] = dict(outcome.row)
        self._unflagged.append((group, outcome))
        if self._commit_flags():
            self._write_summary()

    def add_case(self, case: Case) -> None:
        """A case created while the study runs (a step of a threshold search): its summary
        row (pending), listed after the cases known so far. Its group is created when its
        outcome is written (one structural change per case on the dispatching thread); a
        case a stop leaves unstarted has none, and the next run proposes it again."""
        if case.case_id in self._rows:
            return
        self._rows[case.case_id] = pending_row(case.parameters())
        self._order.append(case.case_id)

    def arrange(self, plan: Plan) -> None:
        """The final order of the cases (``index`` = position in ``plan``; others after it),
        for a study whose cases were created in the order their outcomes arrived."""
        planned = set(plan.case_ids)
        others = [case_id for case_id in self._order if case_id not in planned]
        self._order = [case_id for case_id in plan.case_ids if case_id in self._rows] + others
        self._plan = plan
        if self._broken:
            return
        try:
            self._claim(0)
            for index, case_id in enumerate(self._order):
                group = self._cases.get(case_id)
                if group is not None and group.attrs.get("index") != index:
                    group.attrs["index"] = index
        except Exception as error:
            if not is_no_space(error):
                raise
            self._became_full(error, MARGIN)

    def write_thresholds(self, rows: list[dict[str, Any]], spec) -> None:
        """The thresholds table of a ``[search]`` study (:mod:`engine.output.thresholds`),
        in the file and as ``NAME_thresholds.csv`` beside the summary; not on a full disk
        (the next run writes it)."""
        if self.full is not None:
            return
        line = self._plan is not None and self._plan.line
        try:
            self._claim(SUMMARY_ROW_BYTES * len(rows))
            write_thresholds(self._file, None, rows, spec, line)
            self._file.flush()
        except Exception as error:
            if not is_no_space(error):
                raise
            self._became_full(error, SUMMARY_ROW_BYTES * len(rows))
            return
        try:
            write_thresholds_csv(thresholds_path(self.summary_path), rows, spec, line)
        except OSError as error:
            if not is_no_space(error):
                raise
            self._became_full(_SummaryFull(self.path, MARGIN), MARGIN)

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
        for group, outcome in self._unflagged:
            set_attribute(group, "status", outcome.status)
        self._file.flush()
        self._announce += [outcome for _, outcome in self._unflagged]
        self._unflagged = []
        self._last_commit_end = time.perf_counter()
        self._commit_cost = self._last_commit_end - now
        return True

    def _write_summary(self, force: bool = False) -> None:
        try:
            self._summary.update(self.rows, force=force)
        except OSError as error:
            if not is_no_space(error):
                raise
            raise _SummaryFull(self.path, MARGIN) from None


class _SummaryFull(OutputFull):
    """The summary CSV did not fit (the HDF5 file is unharmed)."""


@contextlib.contextmanager
def _quiet_unraisable():
    """h5py reports errors of objects it frees (a file HDF5 can no longer close) through
    ``sys.unraisablehook``: silence them while a broken file is let go."""
    hook = sys.unraisablehook
    sys.unraisablehook = lambda _: None
    try:
        yield
        gc.collect()
    finally:
        sys.unraisablehook = hook


class Bystander(ResultsWriter):
    """The single strategy on ranks > 0: nothing to prepare, write or close; the rank only
    computes and sends its outcomes to rank 0 (through the scheduler)."""

    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool = False) -> set[str]:
        return set()

    def computing(self, run_case):
        """``run_case``, then the outcome's datasets packed into an HDF5 image on this rank
        (:mod:`engine.output.packed`): rank 0 copies it instead of creating every object."""

        def run_and_pack(case: Case, should_stop) -> CaseOutcome:
            return pack(run_case(case, should_stop))

        return run_and_pack

    def write(self, outcome: CaseOutcome) -> None:
        raise RuntimeError("only rank 0 writes with the single strategy")

    def close(self) -> None:
        pass


def case_record(outcome: CaseOutcome) -> dict[str, Any]:
    """What :meth:`ResultsWriter._store_case` writes for ``outcome``: datasets (arrays, or
    ``written`` for a dataset its rank has already filled), attributes, summary row."""
    datasets, manifest = {}, {}
    for path, record in outcome.datasets.items():
        item: dict[str, Any] = {"units": record.units, "description": record.description}
        item["attrs"] = dict(getattr(record, "attrs", None) or {})
        if getattr(record, "packed", False):  # in the outcome's image (engine.output.packed)
            item["packed"] = True
            entry = tuple(record.manifest)
        elif getattr(record, "written", False):
            item["written"] = True
            entry = tuple(record.manifest)  # computed by the rank that wrote the data
        else:
            item["data"] = np.asarray(record.data)
            entry = manifest_entry(item["data"])
        item["attrs"][DATASET_CHECKSUM] = entry[2]
        manifest[path] = entry
        datasets[path] = item
    record = {
        "checksum": case_checksum(manifest),
        "case_id": outcome.case_id,
        "status": outcome.status,
        "row": _json_safe(dict(outcome.row)),
        "attrs": _attribute_safe(outcome.attrs),
        "message": outcome.message,
        "traceback": outcome.traceback,
        "rank": int(outcome.rank),
        "runtime_s": float(outcome.runtime_s),
        "datasets": datasets,
    }
    if isinstance(outcome, PackedOutcome):
        record["image"] = outcome.image
    return record


def _record_bytes(record: dict[str, Any]) -> int:
    """Bytes a :func:`case_record` takes in the file (:func:`engine.output.space.case_bytes`)."""
    image = len(record.get("image") or b"")
    return image + case_bytes(item.get("data") for item in record["datasets"].values())


def stale_row(group: h5py.Group) -> dict[str, Any]:
    """Summary row of a stored case no longer in the plan (its stored row, current status)."""
    case_id = group.name.rsplit("/", 1)[-1]
    row = json.loads(group.attrs.get("summary", "{}")) or pending_row({"case_id": case_id})
    row["status"] = str(group.attrs.get("status", row.get("status", CaseStatus.PENDING)))
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
        write_summary_csv(rows(), self.path)
        self._last_end = time.perf_counter()
        self._last_cost = self._last_end - now
        self.dirty = False


def _parameter_units(case: Case) -> dict[str, str]:
    """Units of the case's parameter attributes, swept dotted keys included (a line
    contact's per unit length)."""
    return parameter_units((key for key, _ in case.settings), case.line)


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
