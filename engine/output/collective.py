"""Collective output strategy: every rank writes its own cases into the one shared HDF5 file.

Needs h5py built against parallel HDF5 (``h5py.get_config().mpi``; see
``scripts/build_parallel_h5py.sh``). The file layout is that of :class:`SingleWriter`
(engine.output.hdf5), so readers cannot tell the strategies apart.

Parallel HDF5 rule: every *structural* call — opening/closing the file, creating or deleting
groups and datasets, writing attributes, resizing, flushing — is collective and must be made
with identical arguments on all ranks. Raw data of an existing dataset may be written by one
rank alone (independent I/O). The dynamic scheduler lets ranks finish cases at different times,
so this writer keeps all structural calls at two collective points:

``prepare`` (all ranks, before the scheduler starts)
    Open the file with ``driver="mpio"``, commit cases left by a killed run (see journal
    below), reset every incomplete case group and pre-create its datasets from the plan
    (:func:`engine.study.layout.plan_layout`: shapes known from the study, contiguous, no fill
    values), flush.
between (independent only)
    The rank that computed a case writes its fields and stresses into the pre-created
    datasets, then writes the case's *journal* ``<output>.checkpoints/<case_id>.written.json``
    (atomic rename): status, attributes, summary row, dataset units/descriptions and the small
    ``history/*`` arrays whose length the cycle jump decides at run time. Rank 0 keeps the
    summary CSV in step. No metadata of the file changes, so the file on disk stays as
    consistent as it was after ``prepare`` even if a rank is killed (SIGKILL, node failure).
``close`` (all ranks, after the scheduler returns — also after SIGTERM)
    Rank 0 broadcasts the journals of the run; all ranks *commit* them identically: history
    datasets, attributes, ``summary``, flush, then the ``status`` attribute (the completion
    flag, last), flush. Groups of cases that did not complete lose their pre-created datasets
    (as in the single-writer file); committed journals are deleted.

Resume after a kill: ``prepare`` commits every journal whose case is not yet complete — its
data is already in the file — so no completed case is lost or recomputed.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from engine.study.case import COMPLETED, FAILED, CaseOutcome, DatasetRecord
from engine.study.layout import DatasetShape
from engine.study.plan import Case, Plan

from .hdf5 import (
    SingleWriter,
    StoppedDuringSetUp,
    StudyMetadata,
    SummaryTable,
    _attribute_safe,
    _json_safe,
    check_resumable,
    creating_path,
    publish_created,
    renumber_cases,
    settle_stale_cases,
    write_root,
)
from .summary import pending_row

__all__ = [
    "STRATEGIES",
    "CollectiveWriter",
    "ParallelH5pyMissing",
    "h5py_is_mpi_enabled",
    "choose_strategy",
]

STRATEGIES = ("auto", "single", "mpio")
BUILD_HINT = (
    "build one with `bash scripts/build_parallel_h5py.sh` (Debian parallel HDF5 -> .venv-mpio) "
    "and run `mpiexec.mpich -n N .venv-mpio/bin/python -m engine STUDY.toml`; or use "
    "--output-strategy single"
)


class ParallelH5pyMissing(ValueError):
    """mpio was requested but the installed h5py is not built against parallel HDF5."""


def h5py_is_mpi_enabled() -> bool:
    return bool(h5py.get_config().mpi)


def choose_strategy(requested: str, ranks: int) -> str:
    """``single`` or ``mpio`` for the requested strategy (``auto``: mpio when possible)."""
    if requested not in STRATEGIES:
        raise ValueError(f"output strategy must be one of {STRATEGIES}, not {requested!r}")
    if requested == "mpio" and not h5py_is_mpi_enabled():
        raise ParallelH5pyMissing(
            f"output strategy 'mpio' needs h5py built against parallel HDF5, but h5py "
            f"{h5py.__version__} (HDF5 {h5py.version.hdf5_version}) is not MPI-enabled; "
            + BUILD_HINT
        )
    if requested == "auto":
        return "mpio" if ranks > 1 and h5py_is_mpi_enabled() else "single"
    return requested


class _Written:
    """Stands for a dataset its rank has already written into the shared file."""

    def __init__(self, units: str, description: str, attrs: dict | None = None) -> None:
        self.units, self.description = units, description
        self.attrs = dict(attrs or {})


class CollectiveWriter:
    """All ranks share the file (``driver="mpio"``); each writes the cases it computed.

    ``layout``: case_id -> (path -> :class:`DatasetShape`) of the datasets pre-created in each
    incomplete case group (:func:`engine.study.layout.plan_layout`; identical on all ranks),
    or one path -> :class:`DatasetShape` mapping shared by every case. ``prepare`` and
    ``close`` are collective; ``write`` (rank 0, outcomes of all ranks) and ``write_own``
    (any rank, its own outcome) are not.
    """

    def __init__(
        self,
        path: str | Path,
        comm,
        layout: dict[str, DatasetShape] | dict[str, dict[str, DatasetShape]],
        *,
        summary_path: str | Path | None = None,
        journal_dir: str | Path | None = None,
        drop_stale: bool = False,
        should_stop=None,
    ) -> None:
        self.path = Path(path)
        self.comm = comm
        self.should_stop = should_stop or (lambda: False)  # this rank's stop signal
        self.rank = comm.Get_rank()
        self.layout = dict(layout)
        self._per_case = any(isinstance(spec, dict) for spec in self.layout.values())
        self.summary_path = Path(summary_path) if summary_path else self.path.with_suffix(".csv")
        self.journal_dir = (
            Path(journal_dir)
            if journal_dir
            else self.path.with_name(self.path.name + ".checkpoints")
        )
        self.drop_stale = drop_stale
        self._summary = SummaryTable(self.summary_path)
        self._file: h5py.File | None = None
        self._plan: Plan | None = None
        self._rows: dict[str, dict[str, Any]] = {}
        self._order: list[str] = []
        self._journals: list[dict[str, Any]] = []  # rank 0: written this run, not committed
        self.write_seconds = 0.0  # time in independent writes on this rank (benchmark)
        self.commit_seconds = 0.0  # time in prepare + close (collective)
        self.write_seconds_total = 0.0  # sum over ranks, known after close

    # ------------------------------------------------------------------ collective
    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool = False) -> set[str]:
        """Collective: open, commit leftover journals, reset and pre-create incomplete cases.

        A new file is built under a temporary name (every rank takes part) and renamed by
        rank 0 once its structure is complete, as in the single writer."""
        start = _now()
        exists, leftovers = None, []
        if self.rank == 0:
            exists = self.path.exists() and not fresh
            if exists:
                check_resumable(self.path, metadata)
                leftovers = self._read_journals()
            else:
                self.path.parent.mkdir(parents=True, exist_ok=True)
        exists, leftovers = self.comm.bcast((exists, leftovers), root=0)
        if not exists:
            self._create(plan, metadata)
        self._file = h5py.File(self.path, "a", driver="mpio", comm=self.comm)
        file = self._file
        cases = file["cases"] if not exists else file.require_group("cases")
        completed: set[str] = set()
        stale: list[str] = []
        if exists:
            write_root(file, metadata)
            self._commit_all(cases, [r for r in leftovers if r["case_id"] in cases])
            completed = self._reset_incomplete(cases, plan)
            stale = settle_stale_cases(cases, plan, self._rows, drop_stale=self.drop_stale)
            renumber_cases(cases, plan, stale)
        else:
            self._rows = {case.case_id: pending_row(case.parameters()) for case in plan}
        self._plan = plan
        self._order = list(plan.case_ids) + stale
        file.flush()
        if self.rank == 0:
            self._remove_journals(leftovers)
            self._summary.update(self.rows, force=True)
        self.commit_seconds += _now() - start
        return completed

    def _create(self, plan: Plan, metadata: StudyMetadata) -> None:
        """Collective: structure of a new file under the temporary name, then the rename."""
        temporary = creating_path(self.path)
        stopped = False
        with h5py.File(temporary, "w", driver="mpio", comm=self.comm) as file:
            write_root(file, metadata)
            cases = file.create_group("cases")
            for number, case in enumerate(plan):
                if number % 64 == 0 and self._stop_agreed():
                    stopped = True
                    break
                self._pending_group(cases, case)
        stopped = stopped or self._stop_agreed()
        if stopped:  # thousands of cases take seconds: stop without the file, on every rank
            if self.rank == 0:
                temporary.unlink(missing_ok=True)
            self.comm.Barrier()
            raise StoppedDuringSetUp(f"stopped while creating {self.path}; nothing written")
        if self.rank == 0:
            publish_created(self.path)
        self.comm.Barrier()

    def _stop_agreed(self) -> bool:
        """Collective: whether any rank has seen a stop signal (the same answer everywhere, so
        every rank leaves the structural writes at the same point)."""
        from mpi4py import MPI

        return bool(self.comm.allreduce(bool(self.should_stop()), op=MPI.LOR))

    def _pending_group(self, cases: h5py.Group, case) -> None:
        group = SingleWriter._reset_group(cases, case)
        for path, spec in self.layout_of(case.case_id).items():
            group.create_dataset(path, shape=spec.shape, dtype=spec.dtype, fill_time="never")

    def _reset_incomplete(self, cases: h5py.Group, plan: Plan) -> set[str]:
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

    def close(self) -> None:
        """Collective: commit the cases written this run, empty incomplete groups, close."""
        if self._file is None:
            return
        start = _now()
        journals = self.comm.bcast(self._journals if self.rank == 0 else None, root=0)
        cases = self._file["cases"]
        self._commit_all(cases, journals)
        for case in self._plan or []:
            if cases[case.case_id].attrs.get("status", "") in ("pending", ""):
                SingleWriter._reset_group(cases, case)  # drop the unwritten pre-created data
        self._file.flush()
        self._file.close()
        self._file = None
        self.write_seconds_total = self.comm.allreduce(self.write_seconds)
        if self.rank == 0:
            self._remove_journals(journals)
            self._journals = []
            if self._summary.dirty:
                self._summary.update(self.rows, force=True)
        self.commit_seconds += _now() - start

    def __enter__(self) -> CollectiveWriter:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    # ------------------------------------------------------------------ independent
    def write_own(self, outcome: CaseOutcome) -> CaseOutcome:
        """On the computing rank: write the pre-created datasets of ``outcome`` into the file,
        then its journal. Returns the outcome without the written arrays (what rank 0 gets)."""
        if self._file is None:
            raise RuntimeError("prepare() the writer before writing")
        start = _now()
        group = self._file["cases"][outcome.case_id]
        light = dict(outcome.datasets)
        if outcome.status == COMPLETED:
            for path, record in outcome.datasets.items():
                if isinstance(record, _Written) or not self._fits_layout(
                    outcome.case_id, path, record
                ):
                    continue  # not pre-created: created and written at the commit
                group[path].write_direct(np.ascontiguousarray(record.data))
                light[path] = _Written(record.units, record.description, record.attrs)
        outcome.datasets = light
        self._write_journal(_journal(outcome))
        self.write_seconds += _now() - start
        return outcome

    def write(self, outcome: CaseOutcome) -> None:
        """On rank 0 (main thread) for every outcome: write it if it is rank 0's own, then keep
        its journal for the commit and update the summary CSV."""
        if outcome.rank == self.rank:  # computed by rank 0's own thread
            outcome = self.write_own(outcome)
        self._journals.append(_journal(outcome))
        self._rows[outcome.case_id] = dict(outcome.row)
        self._write_summary()

    def owner(self, run_case):
        """Wrap ``run_case`` for ranks > 0: run the case, write it, return the light outcome."""

        def run_and_write(case: Case, should_stop) -> CaseOutcome:
            outcome = run_case(case, should_stop)
            outcome.rank = self.rank
            return self.write_own(outcome)

        return run_and_write

    def rows(self) -> list[dict[str, Any]]:
        return [self._rows[case_id] for case_id in self._order]

    # ------------------------------------------------------------------ commit
    def _commit_all(self, cases: h5py.Group, journals: list[dict[str, Any]]) -> None:
        for record in journals:
            group = cases[record["case_id"]]
            if group.attrs.get("status", "") in (COMPLETED, FAILED):
                continue  # committed before the journal could be removed
            self._commit(cases, group, record)
            self._rows[record["case_id"]] = record["row"]

    def _commit(self, cases: h5py.Group, group: h5py.Group, record: dict[str, Any]) -> None:
        """Collective, identical on all ranks: the structural part of SingleWriter.write."""
        written = {path for path, item in record["datasets"].items() if item["written"]}
        if record["status"] != COMPLETED or set(self.layout_of(record["case_id"])) - written:
            group = _drop_unwritten(cases, group, written, record)
        for path, item in record["datasets"].items():
            if item["written"]:
                dataset = group[path]
            else:
                data = np.asarray(item["data"], dtype=item["dtype"]).reshape(item["shape"])
                dataset = group.create_dataset(path, data=data)
            dataset.attrs["units"] = item["units"]
            dataset.attrs["description"] = item["description"]
            dataset.attrs.update(item.get("attrs", {}))
        group.attrs.update(record["attrs"])
        group.attrs["message"] = record["message"]
        group.attrs["traceback"] = record["traceback"]
        group.attrs["rank"] = record["rank"]
        group.attrs["runtime_s"] = record["runtime_s"]
        group.attrs["summary"] = json.dumps(_json_safe(record["row"]))
        self._file.flush()
        group.attrs["status"] = record["status"]  # the completion flag, written last
        self._file.flush()

    def layout_of(self, case_id: str) -> dict[str, DatasetShape]:
        """Path -> shape of the datasets pre-created for ``case_id``."""
        return self.layout.get(case_id, {}) if self._per_case else self.layout

    def _fits_layout(self, case_id: str, path: str, record: DatasetRecord) -> bool:
        spec = self.layout_of(case_id).get(path)
        data = np.asarray(record.data)
        return spec is not None and data.shape == spec.shape and data.dtype == np.dtype(spec.dtype)

    # ------------------------------------------------------------------ journal + summary
    def _journal_path(self, case_id: str) -> Path:
        return self.journal_dir / f"{case_id}.written.json"

    def _write_journal(self, record: dict[str, Any]) -> None:
        path = self._journal_path(record["case_id"])
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary = path.with_name(f".{path.name}.{self.rank}.tmp")
        temporary.write_text(json.dumps(record))
        os.replace(temporary, path)

    def _read_journals(self) -> list[dict[str, Any]]:
        if not self.journal_dir.is_dir():
            return []
        paths = sorted(self.journal_dir.glob("*.written.json"))
        return [json.loads(path.read_text()) for path in paths]

    def _remove_journals(self, records: list[dict[str, Any]]) -> None:
        for record in records:
            self._journal_path(record["case_id"]).unlink(missing_ok=True)

    def _write_summary(self) -> None:
        self._summary.update(self.rows)


def _drop_unwritten(cases, group, written: set[str], record) -> h5py.Group:
    """Delete pre-created datasets the case did not write (failed or interrupted cases keep
    none, as in the single-writer file), and subgroups left empty."""
    keep = written if record["status"] == COMPLETED else set()
    names: list[str] = []
    group.visit(names.append)
    for name in sorted(names, key=lambda n: -n.count("/")):
        item = group.get(name)
        if isinstance(item, h5py.Dataset) and name not in keep:
            del group[name]
        elif isinstance(item, h5py.Group) and len(item) == 0:
            del group[name]
    return group


def _journal(outcome: CaseOutcome) -> dict[str, Any]:
    """JSON-able record of an outcome whose pre-created datasets have been written."""
    datasets = {}
    for path, record in outcome.datasets.items():
        item: dict[str, Any] = {"units": record.units, "description": record.description}
        if getattr(record, "attrs", None):
            item["attrs"] = dict(record.attrs)
        if isinstance(record, _Written):
            item["written"] = True
        else:
            data = np.asarray(record.data)
            item.update(
                written=False, dtype=data.dtype.str, shape=list(data.shape), data=data.tolist()
            )
        datasets[path] = item
    return {
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


_now = time.perf_counter
