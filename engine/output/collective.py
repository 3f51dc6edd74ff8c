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

from engine.schema import CASES_GROUP, CaseStatus, DatasetRecord
from engine.study.case import COMPLETED, FAILED, CaseOutcome
from engine.study.layout import DatasetShape
from engine.study.plan import Case, Plan

from .checksum import manifest_entry
from .hdf5 import ResultsWriter, StudyMetadata, case_record, publish_created
from .lowlevel import set_attribute

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

    written = True

    def __init__(self, record: DatasetRecord) -> None:
        self.units, self.description = record.units, record.description
        self.attrs = dict(record.attrs or {})
        self.manifest = manifest_entry(record.data)  # dtype, shape, SHA-256 of the data


class CollectiveWriter(ResultsWriter):
    """All ranks share the file (``driver="mpio"``); each writes the cases it computed.

    ``layout``: case_id -> (path -> :class:`DatasetShape`) of the datasets pre-created in each
    incomplete case group (:func:`engine.study.layout.plan_layout`; identical on all ranks),
    or one path -> :class:`DatasetShape` mapping shared by every case. ``prepare`` and
    ``close`` are collective; ``write`` (rank 0, outcomes of all ranks) and ``write_own``
    (any rank, its own outcome) are not. What differs from the base class: the file is opened
    with the mpio driver, rank 0 looks at the existing file and reads the journals of a killed
    run (then broadcasts), the ranks agree on a stop signal by an allreduce, and a pending
    group holds its pre-created datasets.
    """

    collective = True
    announce_suffix = " (collective mpio output)"

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
        super().__init__(path, summary_path, drop_stale=drop_stale, should_stop=should_stop)
        self.comm = comm
        self.rank = comm.Get_rank()
        self.is_root = self.rank == 0
        self.layout = dict(layout)
        self._per_case = any(isinstance(spec, dict) for spec in self.layout.values())
        self.journal_dir = (
            Path(journal_dir)
            if journal_dir
            else self.path.with_name(self.path.name + ".checkpoints")
        )
        self._leftovers: list[dict[str, Any]] = []  # journals of a killed run (prepare)
        self._journals: list[dict[str, Any]] = []  # rank 0: written this run, not committed
        self.write_seconds = 0.0  # time in independent writes on this rank (benchmark)
        self.commit_seconds = 0.0  # time in prepare + close (collective)
        self.write_seconds_total = 0.0  # sum over ranks, known after close
        self._close_seconds = 0.0

    # ------------------------------------------------------------------ collective
    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool = False) -> set[str]:
        """Collective: open, commit leftover journals, reset and pre-create incomplete cases
        (:meth:`ResultsWriter.prepare`; every rank takes part in building a new file)."""
        start = _now()
        completed = super().prepare(plan, metadata, fresh=fresh)
        self.commit_seconds += _now() - start
        return completed

    def _look_at_existing(self, metadata: StudyMetadata, fresh: bool) -> bool:
        """Rank 0 checks the existing file and reads the journals of a killed run; every rank
        learns the verdict."""
        exists, leftovers = None, []
        if self.rank == 0:
            exists = super()._look_at_existing(metadata, fresh)
            if exists:
                leftovers = self._read_journals()
        exists, self._leftovers = self.comm.bcast((exists, leftovers), root=0)
        return exists

    def _open(self, path: Path, mode: str) -> h5py.File:
        comm = self.comm
        if not hasattr(comm, "py2f"):  # a world of one without MPI (engine.parallel.serial)
            from mpi4py import MPI

            comm = MPI.COMM_SELF
        return h5py.File(path, mode, driver="mpio", comm=comm)

    def _stop_agreed(self) -> bool:
        """Collective: whether any rank has seen a stop signal (the same answer everywhere, so
        every rank leaves the structural writes at the same point)."""
        from mpi4py import MPI

        return bool(self.comm.allreduce(bool(self.should_stop()), op=MPI.LOR))

    def _discard(self, temporary: Path) -> None:
        if self.rank == 0:
            temporary.unlink(missing_ok=True)
        self.comm.Barrier()

    def _publish(self) -> None:
        if self.rank == 0:
            publish_created(self.path)
        self.comm.Barrier()

    def _settle_leftovers(self, cases: h5py.Group) -> None:
        """Commit the journals of a killed run: their data is already in the file."""
        self._commit_all(cases, [r for r in self._leftovers if r["case_id"] in cases])

    def _pending_group(self, cases: h5py.Group, case) -> h5py.Group:
        group = self._reset_group(cases, case)
        for path, spec in self.layout_of(case.case_id).items():
            group.create_dataset(path, shape=spec.shape, dtype=spec.dtype, fill_time="never")
        return group

    def _prepared(self) -> None:
        if self.rank == 0:
            self._remove_journals(self._leftovers)
        self._leftovers = []
        super()._prepared()

    def close(self) -> None:
        """Collective: commit the cases written this run, empty incomplete groups, close."""
        if self._file is None:
            return
        start = _now()
        journals = self.comm.bcast(self._journals if self.rank == 0 else None, root=0)
        cases = self._file[CASES_GROUP]
        self._commit_all(cases, journals)
        for case in self._plan or []:
            if cases[case.case_id].attrs.get("status", "") in (CaseStatus.PENDING, ""):
                self._reset_group(cases, case)  # drop the unwritten pre-created data
        self._file.flush()
        self._file.close()
        self._file = None
        self.write_seconds_total = self.comm.allreduce(self.write_seconds)
        if self.rank == 0:
            self._remove_journals(journals)
            self._journals = []
            if self._summary.dirty:
                self._summary.update(self.rows, force=True)
        self._close_seconds = _now() - start
        self.commit_seconds += self._close_seconds

    def closing_note(self) -> str:
        return (
            f"output (mpio): {self.write_seconds_total:.2f} s writing data over all ranks, "
            f"{self.commit_seconds:.2f} s collective prepare/commit "
            f"(close {self._close_seconds:.2f} s)"
        )

    # ------------------------------------------------------------------ independent
    def write_own(self, outcome: CaseOutcome) -> CaseOutcome:
        """On the computing rank: write the pre-created datasets of ``outcome`` into the file,
        then its journal. Returns the outcome without the written arrays (what rank 0 gets)."""
        if self._file is None:
            raise RuntimeError("prepare() the writer before writing")
        start = _now()
        group = self._file[CASES_GROUP][outcome.case_id]
        light = dict(outcome.datasets)
        if outcome.status == COMPLETED:
            for path, record in outcome.datasets.items():
                if isinstance(record, _Written) or not self._fits_layout(
                    outcome.case_id, path, record
                ):
                    continue  # not pre-created: created and written at the commit
                group[path].write_direct(np.ascontiguousarray(record.data))
                light[path] = _Written(record)
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

    def computing(self, run_case):
        """On ranks > 0, ``run_case`` followed by :meth:`write_own`: the rank writes its case
        and sends rank 0 the light outcome. Rank 0's own cases are written in :meth:`write`."""
        return run_case if self.rank == 0 else self.owner(run_case)

    def owner(self, run_case):
        """Wrap ``run_case`` for ranks > 0: run the case, write it, return the light outcome."""

        def run_and_write(case: Case, should_stop) -> CaseOutcome:
            outcome = run_case(case, should_stop)
            outcome.rank = self.rank
            return self.write_own(outcome)

        return run_and_write

    # ------------------------------------------------------------------ commit
    def _commit_all(self, cases: h5py.Group, journals: list[dict[str, Any]]) -> None:
        for record in journals:
            group = cases[record["case_id"]]
            if group.attrs.get("status", "") in (COMPLETED, FAILED):
                continue  # committed before the journal could be removed
            self._commit(cases, group, record)
            self._rows[record["case_id"]] = record["row"]

    def _commit(self, cases: h5py.Group, group: h5py.Group, record: dict[str, Any]) -> None:
        """Collective, identical on all ranks: :meth:`ResultsWriter._store_case` of the
        journal (pre-created datasets the case did not fill are dropped first), flush, then
        the ``status`` flag, flush."""
        written = {path for path, item in record["datasets"].items() if item["written"]}
        if record["status"] != COMPLETED or set(self.layout_of(record["case_id"])) - written:
            group = _drop_unwritten(cases, group, written, record)
        self._store_case(group, _with_arrays(record))
        self._file.flush()
        set_attribute(group, "status", record["status"])  # the completion flag, written last
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
    """JSON-able :func:`case_record` of an outcome whose pre-created datasets have been
    written: the other arrays as dtype, shape and nested lists."""
    record = case_record(outcome)
    for item in record["datasets"].values():
        if "data" in item:
            data = item.pop("data")
            item.update(
                written=False, dtype=data.dtype.str, shape=list(data.shape), data=data.tolist()
            )
    return record


def _with_arrays(record: dict[str, Any]) -> dict[str, Any]:
    """A journal with its listed datasets back as arrays (for the structural write)."""
    datasets = {}
    for path, item in record["datasets"].items():
        if not item["written"]:
            data = np.asarray(item["data"], dtype=item["dtype"]).reshape(item["shape"])
            item = dict(item, data=data)
        datasets[path] = item
    return dict(record, datasets=datasets)


_now = time.perf_counter
