"""Progress under ``mpiexec -n 2`` with stderr captured (a file, not a terminal, as on SLURM).

Rank 0 prints plain progress lines that name the cases running on *both* ranks (rank 1
reports by MPI message, rank 0's computing thread through a queue) with an ETA; a run or a
dry run with more ranks than cases warns. Same interpreter/launcher selection as
test_engine_mpi.py (ENGINE_PYTHON, ENGINE_MPIEXEC), so the mpio phase of scripts/test.sh runs
it through the collective writer too. About 10 s on two cores.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.mpi

REPO = Path(__file__).resolve().parents[2]
PYTHON = os.environ.get("ENGINE_PYTHON") or sys.executable
MPIEXEC = (
    os.environ.get("ENGINE_MPIEXEC")
    or shutil.which("mpiexec", path=str(Path(PYTHON).parent))
    or shutil.which("mpiexec")
)

STUDY = """
[study]
name = "progress"
output = "progress.h5"
[material]
E_A = 200e3
nu_A = 0.3
E_B = 200e5
nu_B = 0.3
[punch]
radius = 1.8
[mesh]
n = 24
[loading]
kind = "cyclic"
load = 750.0
steps = 2
cycles = 10000
record = [10000]
max_wear_fraction = 0.02
[subsurface]
depth = 1.0
layers = 4
[sweep]
mu1 = {mu1}
wear1 = [1.33e-7]
"""


def run(tmp_path: Path, mu1: str, *options: str) -> subprocess.CompletedProcess:
    (tmp_path / "study.toml").write_text(STUDY.format(mu1=mu1))
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    return subprocess.run(
        [MPIEXEC, "-n", "2", PYTHON, "-m", "engine", "study.toml", *options],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=180,
    )  # fmt: skip


def test_progress_lines_name_the_cases_of_both_ranks(tmp_path):
    result = run(tmp_path, "[0.1, 0.2, 0.4]", "--progress-interval", "0.2")
    assert result.returncode == 0, result.stdout + result.stderr
    lines = [line for line in result.stderr.splitlines() if line.startswith("progress: ")]
    assert lines, result.stderr
    assert any("(rank 1," in line for line in lines), lines  # reported by MPI message
    assert any("cycle " in line and "(rank 0," in line for line in lines), lines
    assert any(line.startswith("progress: 1/3 cases done") and "ETA " in line for line in lines)
    assert lines[-1].startswith("progress: 3/3 cases done")
    assert "warning" not in result.stderr


def test_more_ranks_than_cases_warns(tmp_path):
    dry = run(tmp_path, "[0.4]", "--dry-run")
    assert dry.returncode == 0, dry.stderr
    assert "warning: 2 ranks for 1 case to run: 1 rank will stay idle" in dry.stderr
    assert "would run 1 case on 2 ranks" in dry.stdout
