"""The read-back at the end of a run, shared by the ranks (``engine.run._check_shares``):
under ``mpiexec -n 2`` a damaged case is found whichever rank reads it, and the cases that
are not named are only status-checked (by rank 0)."""

from __future__ import annotations

import json
import subprocess

import pytest

from engine.study.case import CaseRunner
from tests.mpi.test_engine_mpi import MPIEXEC, PYTHON, environment
from tests.test_checksums import flip_bit
from tests.test_packed import _study, _write

pytestmark = pytest.mark.mpi

SCRIPT = """
import json, sys
from types import SimpleNamespace
from mpi4py import MPI
from engine.run import _check_shares

config = SimpleNamespace(study=SimpleNamespace(output=sys.argv[1]))
written = json.loads(sys.argv[2]) if MPI.COMM_WORLD.Get_rank() == 0 else None
bad = _check_shares(MPI.COMM_WORLD, config, written)
if MPI.COMM_WORLD.Get_rank() == 0:
    print(json.dumps(sorted(check.case_id for check in bad)))
"""


def test_each_rank_reads_back_its_share_and_rank_0_hears_of_every_damaged_case(tmp_path):
    config, plan = _study(tmp_path)
    runner = CaseRunner(config)
    path = tmp_path / "r.h5"
    _write(path, config, plan, [runner(case) for case in plan])
    names = sorted(plan.case_ids)  # 4 cases: rank 0 reads names[0::2], rank 1 names[1::2]
    for name in (names[0], names[1]):  # one case in the share of each rank
        flip_bit(path, name, "grid/x")
    command = [MPIEXEC, "-n", "2", PYTHON, "-c", SCRIPT, str(path)]
    every = subprocess.run(
        [*command, json.dumps(names)], env=environment(), capture_output=True, text=True
    )
    assert every.returncode == 0, every.stderr
    assert json.loads(every.stdout) == [names[0], names[1]]
    # cases not written by the run: their status only (the damage is not seen)
    others = subprocess.run(
        [*command, json.dumps(names[2:])], env=environment(), capture_output=True, text=True
    )
    assert others.returncode == 0, others.stderr
    assert json.loads(others.stdout) == []
