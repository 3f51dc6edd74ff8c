"""Threshold searches under ``mpiexec -n 2``: real ranks, real HDF5 files, real signals.

Two searches (a sphere at two loads, the partial/gross-slip boundary in the amplitude,
n = 16, one fretting cycle: ~0.3 s a case, 9 cases a search) run at once over the two ranks.
An uninterrupted run on one rank is the reference; a two-rank run, and two-rank runs killed
(SIGKILL, as the OOM killer would) or stopped (SIGTERM, as a batch system would) in the
middle of the searches and then resumed, must all give the same file — every case, the
thresholds table, the summary — bit for bit (scripts/compare_results.py, which ignores only
run-dependent attributes such as runtimes, ranks and the command line).
"""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import pytest

import engine
from engine.study.examples import study_toml
from tests.mpi.test_engine_mpi import run_engine
from tests.mpi.test_kill_safety import kill_ranks, start

pytestmark = pytest.mark.mpi

REPO = Path(__file__).resolve().parents[2]
STUDY = {
    "material": {"E_A": 210e3, "nu_A": 0.3, "E_B": 210e3, "nu_B": 0.3},
    "punch": {"shape": "sphere", "radius": 10.0},
    "mesh": {"n": 16},
    "loading": {"kind": "fretting", "load": None, "cycles": 1, "record": [1], "steps": 2},
    "sweep": {"mu1": [0.5], "wear1": [0.0], "loading.load": [50.0, 200.0]},
    "search": {
        "parameter": "loading.amplitude",
        "low": 1e-3,
        "high": 6e-3,
        "column": "slip_regime",
        "target": "gross",
        "rtol": 1e-2,
    },
}


def search_study(directory: Path) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / "search.toml"
    path.write_text(study_toml("search", "search.h5", STUDY))
    return path


def same_results(first: Path, second: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [
            sys.executable,
            str(REPO / "scripts" / "compare_results.py"),
            "--ignore",
            "command_line",
            "--ignore",
            "source",
            str(first),
            str(second),
        ],
        capture_output=True,
        text=True,
    )


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    """The study run without interruption on one rank."""
    study = search_study(tmp_path_factory.mktemp("reference"))
    result = run_engine(study, ranks=1, timeout=300)
    assert result.returncode == 0, result.stderr
    table = engine.load_thresholds(study.with_suffix(".h5"))
    assert (table.status == "converged").all()
    return study.with_suffix(".h5")


def _interrupt_and_resume(directory: Path, signum: int, after: int, total: int):
    """Start on two ranks, send ``signum`` to both once ``after`` cases have finished,
    resume on two ranks; (exit code of the interrupted run, output of the rerun)."""
    study = search_study(directory)
    process = start(study, "--no-progress-bar")
    finished = 0
    for line in process.stdout:
        finished += line.startswith("[")
        if finished >= after:
            kill_ranks(study, signum)
            break
    process.communicate(timeout=120)
    summary = engine.load_summary(study.with_suffix(".h5"))
    completed = int((summary.status == "completed").sum())
    assert 0 < completed < total, "the signal must land in the middle of the searches"
    rerun = run_engine(study, timeout=300)
    assert rerun.returncode == 0, rerun.stderr
    return process.returncode, rerun.stdout


def test_two_ranks_give_the_one_rank_results(reference, tmp_path):
    study = search_study(tmp_path)
    result = run_engine(study, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "2 of 2 searches converged" in result.stdout
    comparison = same_results(reference, study.with_suffix(".h5"))
    assert comparison.returncode == 0, comparison.stdout
    csv = same_results(reference.with_suffix(".csv"), study.with_suffix(".csv"))
    assert csv.returncode == 0, csv.stdout
    thresholds = reference.with_name("search_thresholds.csv")
    assert thresholds.read_bytes() == tmp_path.joinpath("search_thresholds.csv").read_bytes()


@pytest.mark.parametrize("signum, after", [(signal.SIGKILL, 5), (signal.SIGTERM, 9)])
def test_a_search_interrupted_midway_resumes_to_the_same_thresholds(
    reference, tmp_path, signum, after
):
    """SIGKILL (nothing saved: the cases without their completion flag are recomputed) or
    SIGTERM (exit 3) after ``after`` of the 18 cases; the rerun replays the completed steps
    and ends with the same file, thresholds included, bit for bit."""
    total = len(engine.load_summary(reference))
    code, rerun = _interrupt_and_resume(tmp_path, signum, after, total)
    if signum == signal.SIGTERM:
        assert code == 3
    assert "already complete" in rerun
    comparison = same_results(reference, tmp_path / "search.h5")
    assert comparison.returncode == 0, comparison.stdout
    thresholds = reference.with_name("search_thresholds.csv")
    assert thresholds.read_bytes() == tmp_path.joinpath("search_thresholds.csv").read_bytes()
