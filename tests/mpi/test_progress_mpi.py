"""Progress under ``mpiexec -n 2`` with stderr captured (a file, not a terminal, as on SLURM).

Rank 0 prints plain progress lines that name the cases running on *both* ranks (rank 1
reports by MPI message, rank 0's computing thread through a queue) with an ETA; a run or a
dry run with more ranks than cases warns. Same interpreter/launcher selection as
test_engine_mpi.py (ENGINE_PYTHON, ENGINE_MPIEXEC), so the mpio phase of scripts/test.sh runs
it through the collective writer too. About 10 s on two cores.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from engine.study.examples import study_toml
from tests.mpi.test_engine_mpi import MPIEXEC, PYTHON, environment

pytestmark = pytest.mark.mpi


def run(tmp_path: Path, mu1: list[float], *options: str) -> subprocess.CompletedProcess:
    """Run a cyclic study (24 x 24, 10⁴ cycles, coarse jumps) of the frictions ``mu1``."""
    text = study_toml(
        "progress",
        "progress.h5",
        mesh={"n": 24},
        loading={"cycles": 10000, "record": [10000], "max_wear_fraction": 0.02},
        sweep={"mu1": mu1, "wear1": [1.33e-7]},
    )
    (tmp_path / "study.toml").write_text(text)
    return subprocess.run(
        [MPIEXEC, "-n", "2", PYTHON, "-m", "engine", "study.toml", *options],
        cwd=tmp_path, env=environment(), capture_output=True, text=True, timeout=180,
    )  # fmt: skip


def test_progress_lines_of_a_real_run(tmp_path):
    """End to end, what holds whatever the timing: a status line after every finished case,
    with an ETA while cases remain, and the last one says all are done."""
    result = run(tmp_path, [0.1, 0.2, 0.4], "--progress-interval", "0.2")
    assert result.returncode == 0, result.stdout + result.stderr
    lines = [line for line in result.stderr.splitlines() if line.startswith("progress: ")]
    first = [line for line in lines if line.startswith("progress: 1/3 cases completed")]
    assert any("ETA " in line for line in first)
    assert lines[-1].startswith("progress: 3/3 cases completed")
    assert "warning" not in result.stderr


CHANNEL_SCRIPT = """
import io, sys, time
from types import SimpleNamespace
from mpi4py import MPI
from engine.output.progress import ProgressChannel, ProgressReporter, WorkerProgress

comm = MPI.COMM_WORLD
case = SimpleNamespace(case_id=f"case_of_rank_{comm.Get_rank()}", expected_cost=1.0)
if comm.Get_rank() == 1:
    report = WorkerProgress(comm, min_interval=0.0)
    report(case)
    report(case, 7, 10)
    comm.Barrier()
else:
    status = io.StringIO()
    todo = [case, SimpleNamespace(case_id="case_of_rank_1", expected_cost=1.0)]
    reporter = ProgressReporter(2, todo=todo, ranks=2, stream=io.StringIO(),
                                status_stream=status, bar=False, interval=1e-9)
    channel = ProgressChannel(comm, reporter)
    channel.local(case)
    channel.local(case, 3, 10)
    comm.Barrier()
    deadline = time.monotonic() + 30
    while "cycle 7" not in reporter.status_text() and time.monotonic() < deadline:
        channel.drain()
        time.sleep(0.01)
    text = reporter.status_text()
    print(text)
    sys.exit(0 if "(rank 1," in text and "(rank 0," in text else 1)
"""


def test_progress_channel_names_the_cases_of_both_ranks(tmp_path):
    """Rank 1's reports travel by MPI message, rank 0's computing thread's through a queue;
    one status text names both running cases with their cycles (deterministic: the reports
    are sent before a barrier and drained until they have arrived)."""
    script = tmp_path / "channel.py"
    script.write_text(CHANNEL_SCRIPT)
    result = subprocess.run(
        [MPIEXEC, "-n", "2", PYTHON, str(script)],
        cwd=tmp_path, env=environment(), capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr
    assert "cycle 7" in result.stdout and "cycle 3" in result.stdout, result.stdout


def test_more_ranks_than_cases_warns(tmp_path):
    dry = run(tmp_path, [0.4], "--dry-run")
    assert dry.returncode == 0, dry.stderr
    assert "warning: 2 ranks for 1 case to run: 1 rank will stay idle" in dry.stderr
    assert "would run 1 case on 2 ranks" in dry.stdout
