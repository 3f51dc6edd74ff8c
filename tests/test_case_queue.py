"""The scheduler with an open case queue (cases created as outcomes arrive, as threshold
searches do), on one rank (COMM_SELF); the multi-rank run is in tests/mpi/test_search_mpi.py."""

from __future__ import annotations

import threading

import pytest

from engine.parallel.scheduler import CaseQueue, Scheduler
from tests.test_output import _Case, _Outcome


def chains(queue: CaseQueue, length: int):
    """An outcome handler: each finished ``s<i>-<k>`` puts ``s<i>-<k+1>`` up to ``length``
    steps; the queue closes when every chain has ended."""
    unfinished = {case.case_id.split("-")[0] for case in queue.cases}
    seen = []

    def on_outcome(outcome):
        seen.append(outcome.case_id)
        chain, step = outcome.case_id.split("-")
        if int(step) + 1 < length:
            queue.put(_Case(f"{chain}-{int(step) + 1}"))
        else:
            unfinished.discard(chain)
            if not unfinished:
                queue.close()

    return on_outcome, seen


def test_an_open_queue_runs_the_cases_put_while_it_runs():
    from mpi4py import MPI

    queue = CaseQueue([_Case(f"s{i}-0") for i in range(3)], open=True)
    on_outcome, seen = chains(queue, 4)
    report = Scheduler(MPI.COMM_SELF, lambda case, stop: _Outcome(case.case_id, "completed")).run(
        queue, on_outcome
    )
    assert sorted(seen) == sorted(f"s{i}-{k}" for i in range(3) for k in range(4))
    for i in range(3):  # each chain's steps in order
        steps = [case_id for case_id in seen if case_id.startswith(f"s{i}-")]
        assert steps == [f"s{i}-{k}" for k in range(4)]
    assert report.cases_per_rank == {0: 12} and not report.stopped


def test_a_queue_left_open_with_nothing_running_is_an_error_not_a_hang():
    from mpi4py import MPI

    queue = CaseQueue([_Case("s0-0")], open=True)
    scheduler = Scheduler(MPI.COMM_SELF, lambda case, stop: _Outcome(case.case_id, "completed"))
    with pytest.raises(RuntimeError, match="queue is open"):
        scheduler.run(queue, lambda outcome: None)


def test_a_stop_ends_an_open_queue():
    from mpi4py import MPI

    stop = threading.Event()
    queue = CaseQueue([_Case("s0-0")], open=True)
    on_outcome, seen = chains(queue, 10)

    def run_case(case, should_stop):
        if case.case_id == "s0-2":
            stop.set()  # as a signal handler would
        return _Outcome(case.case_id, "completed")

    report = Scheduler(MPI.COMM_SELF, run_case, stop_event=stop).run(queue, on_outcome)
    assert report.stopped
    assert seen == ["s0-0", "s0-1", "s0-2"]
    assert report.not_started == ["s0-3"]
