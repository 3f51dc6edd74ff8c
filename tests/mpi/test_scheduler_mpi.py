"""The scheduler itself under ``mpiexec -n 2`` with a trivial ``run_case``: short cases go to
the worker ahead of time (several held at once), and whatever happens every case is accounted
for exactly once — computed, or listed as not started after a stop (the cases a stopped
worker held but had not begun come back)."""

from __future__ import annotations

import json
import subprocess

import pytest

from engine.parallel.scheduler import MOST_AHEAD, SHORT_CASE_S, cases_to_hold
from tests.mpi.test_engine_mpi import MPIEXEC, PYTHON, environment

pytestmark = pytest.mark.mpi

SCRIPT = """
import json, sys, time
from mpi4py import MPI
from engine.parallel.scheduler import Scheduler

comm = MPI.COMM_WORLD
cases, stop_after = int(sys.argv[1]), int(sys.argv[2])


class Case:
    def __init__(self, case_id):
        self.case_id = case_id


class Outcome:
    def __init__(self, case_id, status):
        self.case_id, self.status, self.rank, self.runtime_s = case_id, status, -1, 0.002


done, held = [], []
scheduler = Scheduler(comm, None)


def run_case(case, should_stop):
    time.sleep(0.002 if comm.Get_rank() else 0.02)  # rank 0 slower: the worker runs ahead
    done.append(case.case_id)
    held.append(len(getattr(scheduler, "_tasks", ())))  # received, waiting behind this one
    if comm.Get_rank() == 1 and len(done) == stop_after:
        scheduler.stop_event.set()  # as a signal handler on the worker alone would
    return Outcome(case.case_id, "completed")


scheduler.run_case = run_case
seen = []
if comm.Get_rank() == 0:
    report = scheduler.run([Case(f"c{i}") for i in range(cases)], lambda o: seen.append(o.case_id))
else:
    report = scheduler.run()
everyone = comm.gather(done, root=0)
most_held = comm.gather(max(held, default=0), root=0)
if comm.Get_rank() == 0:
    print(json.dumps({
        "computed": everyone, "most_held": most_held[1], "delivered": seen,
        "statuses": report.statuses,
        "not_started": report.not_started, "stopped": report.stopped,
        "per_rank": {str(rank): count for rank, count in report.cases_per_rank.items()},
    }))
"""


def run_scheduler(cases: int, stop_after: int) -> dict:
    command = [MPIEXEC, "-n", "2", PYTHON, "-c", SCRIPT, str(cases), str(stop_after)]
    run = subprocess.run(command, env=environment(), capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    return json.loads(run.stdout)


def test_every_case_runs_once_and_short_cases_wait_on_the_worker():
    result = run_scheduler(60, stop_after=0)
    on_rank0, on_rank1 = result["computed"]
    assert sorted(on_rank0 + on_rank1) == sorted(f"c{i}" for i in range(60))
    assert sorted(result["delivered"]) == sorted(result["statuses"]) == sorted(on_rank0 + on_rank1)
    assert result["not_started"] == [] and not result["stopped"]
    # the worker's cases are short (2 ms): it held further cases while computing one
    assert result["most_held"] >= 1
    assert result["per_rank"] == {"0": len(on_rank0), "1": len(on_rank1)}


def test_a_worker_stopped_with_cases_held_ahead_returns_them_unstarted():
    result = run_scheduler(60, stop_after=10)
    on_rank0, on_rank1 = result["computed"]
    assert result["stopped"]
    assert len(on_rank1) == 10  # nothing begun after the stop
    computed = on_rank0 + on_rank1
    assert len(set(computed)) == len(computed)  # none twice
    assert sorted(result["statuses"]) == sorted(computed)
    # every case exactly once: computed, or not started (held cases came back)
    assert sorted(computed + result["not_started"]) == sorted(f"c{i}" for i in range(60))
    assert result["not_started"]


def test_short_cases_are_held_ahead_long_ones_one_at_a_time():
    assert cases_to_hold(None) == 1
    assert cases_to_hold(SHORT_CASE_S) == cases_to_hold(60.0) == 1
    assert cases_to_hold(0.001) == MOST_AHEAD
    assert 2 <= cases_to_hold(0.1) < MOST_AHEAD
    assert cases_to_hold(0.5) == 2
