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

A full disk (the model: the single writer's, :mod:`engine.output.space`). A structural call
that fails for want of space on one rank leaves the others waiting in the collective call, so
nothing structural may meet a full disk: the space is held before it is needed, rank 0 claims
it and every rank learns the answer from one broadcast. ``prepare`` claims what it writes,
then allocates the blocks of the whole file, the pre-created datasets' included (their data
is then written into blocks that are already the file's); a claim that fails stops the run on
every rank at once, before any case. Rank 0 accepts a case — and announces it completed —
only once the bytes its commit will add (histories, attributes, headers) are claimed past the
end of the file; a case whose journal or data could not be written, or whose commit space
cannot be claimed, is not accepted: the run stops (exit code 5), and the next run computes
the case again. So ``close`` commits what was announced into blocks already held, on every
rank alike.
"""

from __future__ import annotations

import contextlib
import json
import math
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
from .hdf5 import (
    PENDING_GROUP_BYTES,
    SUMMARY_ROW_BYTES,
    ResultsWriter,
    StudyMetadata,
    case_record,
    creating_path,
    publish_created,
)
from .lowlevel import set_attribute
from .space import (
    CLAIM_SLACK,
    DATASET_OVERHEAD,
    MARGIN,
    OutputFull,
    SpareFile,
    allocate,
    case_bytes,
    claim,
    free_bytes,
    is_no_space,
    planned_bytes,
    unclaim,
)

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
        self._kept: CaseOutcome | None = None  # rank 0: the outcome kept by ``write``
        self.write_seconds = 0.0  # time in independent writes on this rank (benchmark)
        self.commit_seconds = 0.0  # time in prepare + close (collective)
        self.write_seconds_total = 0.0  # sum over ranks, known after close
        self._close_seconds = 0.0
        self._descriptor: int | None = None  # rank 0: the file, for claims past its end
        self._spare = SpareFile(self.path)  # rank 0: blocks for the summary on a full disk
        self._commit_bytes = 0  # rank 0: what the accepted journals add to the file
        self._close_bytes = CLAIM_SLACK  # rank 0: what close adds besides the commits

    # ------------------------------------------------------------------ collective
    def prepare(self, plan: Plan, metadata: StudyMetadata, *, fresh: bool = False) -> set[str]:
        """Collective: open, commit leftover journals, reset and pre-create incomplete cases
        (:meth:`ResultsWriter.prepare`; every rank takes part in building a new file), then
        hold the blocks of the whole file. No room: :class:`OutputFull` on every rank, the
        file closed as its last flush left it (a new one removed)."""
        start = _now()
        self._agree(lambda: self._hold_spare(SUMMARY_ROW_BYTES * len(plan) + CLAIM_SLACK))
        try:
            completed = super().prepare(plan, metadata, fresh=fresh)
        except Exception as error:  # noqa: BLE001 - a full disk is told apart below
            # OutputFull is raised on every rank alike (a claim's verdict is broadcast); so
            # is HDF5's error when a collective flush or close finds the disk full (each
            # rank learns the outcome of the write): either way the same clean stop
            if not is_no_space(error):
                raise
            self._stop_preparing()
            if isinstance(error, OutputFull):
                raise
            needed = self._pending_bytes(plan)
            raise OutputFull(self.path, needed, _free_or_none(self.path)) from None
        self.commit_seconds += _now() - start
        return completed

    def _stop_preparing(self) -> None:
        """Collective, after ``prepare`` met a full disk: the file closed as its last flush
        left it (a new one removed), the spare blocks given back."""
        if self._file is not None:
            with contextlib.suppress(Exception):  # its flush may meet the full disk again
                self._file.close()
            self._file = None
        self._close_descriptor()
        if self.is_root:
            creating_path(self.path).unlink(missing_ok=True)
            self._spare.release()
        self.comm.Barrier()

    def _pending_bytes(self, plan: Plan, resumed: h5py.Group | None = None) -> int:
        """The pending groups' attributes and their pre-created datasets (data and headers)
        for every case not completed: the mpio driver gives each dataset its place in the
        file when it is created, so what is written after it (the headers of the next
        groups, the metadata flushed on close) lands beyond all of them."""
        todo = [
            case.case_id
            for case in plan
            if resumed is None
            or case.case_id not in resumed
            or resumed[case.case_id].attrs.get("status", "") != COMPLETED
        ]
        datasets = planned_bytes({case_id: self.layout_of(case_id) for case_id in todo}, todo)
        return super()._pending_bytes(plan) + datasets

    def _claim_for(self, file: h5py.File, needed: int, path: Path) -> None:
        """Rank 0 claims ``needed`` bytes past the end of ``path``; every rank learns whether
        it could (:class:`OutputFull` raised on all of them)."""
        self._agree(lambda: _claim_path(path, needed + CLAIM_SLACK))

    def _hold_spare(self, size: int) -> None:
        """Rank 0, before any HDF5 call: hold the spare blocks, the room to close the file
        cleanly should a claim fail later (:meth:`_agree`). No room for them: the run stops
        here, before a file is opened (closing one writes its metadata)."""
        self._spare.hold(size)
        if not self._spare.held and free_bytes(self.path) < size:
            raise OutputFull(self.path, size, free_bytes(self.path))

    def _agree(self, action) -> None:
        """Run ``action`` on rank 0; raise its :class:`OutputFull` on every rank. The spare
        blocks are given back first: closing the open file still writes its metadata."""
        failure = None
        if self.is_root:
            try:
                action()
            except OutputFull as error:
                failure = (str(self.path), error.needed, error.free)  # the output, by its name
                self._spare.release()
        failure = self.comm.bcast(failure, root=0)
        if failure is not None:
            raise OutputFull(Path(failure[0]), failure[1], failure[2])

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
        """The file is built: rank 0 allocates its blocks (the pre-created datasets' data
        lands in them), keeps a descriptor for the claims of the commit, and removes the
        committed journals of a killed run."""
        self._agree(self._hold_blocks)
        if self.rank == 0:
            self._remove_journals(self._leftovers)
        self._leftovers = []
        super()._prepared()

    def _hold_blocks(self) -> None:
        """Rank 0: the blocks of the whole file allocated (after the flush of ``prepare`` its
        size covers every pre-created dataset, holes where nothing is written yet), and
        room claimed past its end for what ``close`` writes besides the commits (a pending
        group anew for each case not completed, the flags)."""
        self._descriptor = os.open(self.path, os.O_RDWR)
        allocate(self._descriptor, os.fstat(self._descriptor).st_size, self.path)
        self._close_bytes = PENDING_GROUP_BYTES * len(self._order) + CLAIM_SLACK
        claim(self._descriptor, self._close_bytes, self.path)

    def _claim_commit(self) -> None:
        """Rank 0: the room past the end of the file for the commit and the rest of
        ``close``; on a full disk the spare blocks are given back for it first."""
        if self.full is not None:
            self._spare.release()
        claim(self._descriptor, self._close_bytes + self._commit_bytes, self.path)

    def _close_descriptor(self) -> None:
        if self._descriptor is not None:
            os.close(self._descriptor)
            self._descriptor = None

    def close(self) -> None:
        """Collective: commit the cases written this run, empty incomplete groups, close."""
        if self._file is None:
            return
        start = _now()
        journals = self.comm.bcast(self._journals if self.rank == 0 else None, root=0)
        # Each rank opened the groups of the cases it wrote, so the ranks' metadata caches
        # differ; a collective call that reads an object one rank holds and another does not
        # (deleting a case a rank wrote but the run did not keep: a full disk) breaks in the
        # broadcast of that read. Reopened, every rank starts from the same empty cache.
        self._file.close()
        self._file = self._open(self.path, "a")
        cases = self._file[CASES_GROUP]
        try:  # the room claimed for the commit, held again (closing may have trimmed it)
            self._agree(self._claim_commit)
        except OutputFull as full:  # the journals stay: the next run commits them
            self.full = self.full or full
            journals = []
        else:
            self._commit_all(cases, journals)
            for case in self._plan or []:
                if cases[case.case_id].attrs.get("status", "") in (CaseStatus.PENDING, ""):
                    self._reset_group(cases, case)  # drop the unwritten pre-created data
        self._file.flush()
        self._file.close()
        self._file = None
        self.write_seconds_total = self.comm.allreduce(self.write_seconds)
        if self.rank == 0:
            self._close_descriptor()
            unclaim(self.path)
            self._remove_journals(journals)
            self._journals = []
            if self.full is not None:
                self._spare.release()  # room for the summary
            if self._summary.dirty:
                try:
                    self._summary.update(self.rows, force=True)
                except OSError as error:  # the next run rewrites the summary from the file
                    if not is_no_space(error):
                        raise
                    self.full = self.full or OutputFull(self.path, MARGIN)
            self._spare.release()
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
        records = outcome.datasets
        light = dict(records)
        try:
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
        except Exception as error:
            if not is_no_space(error):
                raise
            # the whole case, also what was written before the disk filled: the next run
            # computes and writes it again
            needed = case_bytes(np.asarray(r.data) for r in records.values() if hasattr(r, "data"))
            outcome.datasets = {}  # rank 0 needs none of it: the case is computed again
            outcome.output_full = (needed, _free_or_none(self.path))
        self.write_seconds += _now() - start
        return outcome

    def write(self, outcome: CaseOutcome) -> None:
        """On rank 0 (main thread) for every outcome: write it if it is rank 0's own, claim
        the bytes its commit will add, then keep its journal for the commit and update the
        summary CSV. A case that could not be written or claimed is not kept: the writer is
        ``full`` (its journal removed, the case left pending for the next run)."""
        if self.full is not None:
            if getattr(outcome, "output_full", None) is None:
                self._journal_path(outcome.case_id).unlink(missing_ok=True)
            return
        if outcome.rank == self.rank:  # computed by rank 0's own thread
            outcome = self.write_own(outcome)
        unwritten = getattr(outcome, "output_full", None)
        if unwritten is not None:
            self.full = OutputFull(self.path, unwritten[0], unwritten[1])
            return
        journal = _journal(outcome)
        needed = _commit_bytes(journal)
        try:
            claim(self._descriptor, self._close_bytes + self._commit_bytes + needed, self.path)
        except OutputFull as full:
            self.full = full
            self._journal_path(outcome.case_id).unlink(missing_ok=True)
            return
        self._commit_bytes += needed
        self._journals.append(journal)
        self._kept = outcome
        self._rows[outcome.case_id] = dict(outcome.row)
        try:
            self._write_summary()
        except OSError as error:  # the next run rewrites the summary from the file
            if not is_no_space(error):
                raise
            self.full = OutputFull(self.path, MARGIN, _free_or_none(self.path))

    def committed(self, outcome: CaseOutcome) -> list[CaseOutcome]:
        """``outcome`` once it is kept for the commit (its data and journal written, the
        space of its commit held, see :meth:`write`); nothing on a full disk."""
        kept, self._kept = self._kept, None
        return [kept] if kept is not None else []

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
        """The journal of a written case, whole or not at all (written aside, then renamed;
        a write that fails leaves nothing)."""
        path = self._journal_path(record["case_id"])
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary = path.with_name(f".{path.name}.{self.rank}.tmp")
        try:
            temporary.write_text(json.dumps(record))
            os.replace(temporary, path)
        except BaseException:
            with contextlib.suppress(OSError):
                temporary.unlink()
            raise

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


def _commit_bytes(journal: dict[str, Any]) -> int:
    """Bytes the commit of ``journal`` adds to the file: the datasets it creates, the
    attributes of every dataset and of the case (:func:`engine.output.space.case_bytes`)."""
    data = sum(
        math.prod(item["shape"]) * np.dtype(item["dtype"]).itemsize
        for item in journal["datasets"].values()
        if "data" in item
    )
    overhead = DATASET_OVERHEAD * len(journal["datasets"])
    return data + overhead + len(json.dumps(journal["row"])) + len(journal["traceback"])


def _claim_path(path: Path, length: int) -> None:
    """Claim ``length`` bytes past the end of the file ``path`` (opened for the claim)."""
    descriptor = os.open(path, os.O_RDWR)
    try:
        claim(descriptor, length, path)
    finally:
        os.close(descriptor)


def _free_or_none(path: Path) -> int | None:
    try:
        return free_bytes(path)
    except OSError:
        return None


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
