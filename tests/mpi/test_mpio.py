"""Collective (mpio) output strategy under ``mpiexec -n 2``.

The comparison with the single writer's file and the kill-and-resume test need h5py built
against parallel HDF5 in the engine's environment; run them with the environment of
``scripts/build_parallel_h5py.sh``::

    ENGINE_MPIEXEC=mpiexec.mpich .venv-mpio/bin/python -m pytest tests/mpi

(scripts/test.sh does this as its second MPI run). With the plain h5py wheel they are skipped
and the check that asking for mpio gives a clear error runs instead.
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from functools import cache

import h5py
import pytest

import engine
from tests.mpi.test_engine_mpi import (
    MPIEXEC,
    PYTHON,
    assert_same_results,
    engine_command,
    environment,
    finished_cases,
    run_engine,
    signal_ranks,
    write_study,
)
from tests.mpi.test_kill_safety import tiny_study

pytestmark = pytest.mark.mpi


@cache
def engine_h5py_is_mpi_enabled() -> bool:
    """Whether h5py in the *engine's* interpreter (ENGINE_PYTHON) is built with MPI."""
    check = "import h5py; print(bool(h5py.get_config().mpi))"
    result = subprocess.run([PYTHON, "-c", check], capture_output=True, text=True, timeout=60)
    return result.stdout.strip() == "True"


needs_parallel_h5py = pytest.mark.skipif(
    "not engine_h5py_is_mpi_enabled()",
    reason="h5py of the engine's environment is not MPI-enabled; build one with "
    "`bash scripts/build_parallel_h5py.sh` and run with ENGINE_PYTHON=.venv-mpio/bin/python "
    "ENGINE_MPIEXEC=mpiexec.mpich (scripts/test.sh does)",
)
# Four cases of 1.5–3 s each: both ranks compute two, so the kill test finds a case done and
# others still pending.
SWEEP = {"mu1": (0.1, 0.2, 0.4), "beta": (0.0, 90.0)}


@needs_parallel_h5py
def test_collective_file_equals_single_writer_file(tmp_path):
    """Same study, 2 ranks, --output-strategy single vs mpio -> same groups, datasets (to
    round-off), attributes and summary; both ranks computed and wrote cases."""
    study = write_study(tmp_path, "demo", **SWEEP)
    single = run_engine(study, "--output-strategy", "single", "--output", str(tmp_path / "s.h5"))
    assert single.returncode == 0, single.stderr
    collective = run_engine(study, "--output-strategy", "mpio")
    assert collective.returncode == 0, collective.stderr
    assert "collective mpio output" in collective.stdout
    assert_same_results(tmp_path / "demo.h5", tmp_path / "s.h5")
    with h5py.File(tmp_path / "demo.h5", "r") as file:
        ranks = {int(group.attrs["rank"]) for group in file["cases"].values()}
    assert ranks == {0, 1}, "both ranks wrote their own cases"
    assert not any((tmp_path / "demo.h5.checkpoints").glob("*.json")), "journals committed"
    summary = engine.load_summary(tmp_path / "demo.h5")
    assert (summary.status == "completed").all() and len(summary) == 6


@needs_parallel_h5py
@pytest.mark.parametrize("kill", ["SIGKILL", "SIGTERM"])
def test_kill_during_collective_run_then_resume_loses_no_completed_case(kill, tmp_path):
    """Kill the collective run after its first finished case (SIGKILL: no chance to commit, the
    journal of the case is all there is; SIGTERM: orderly stop), then resume: every case finished
    before the kill is kept, not recomputed, and the file equals an uninterrupted single-writer
    run."""
    study = write_study(tmp_path, "killed", **SWEEP)
    process = subprocess.Popen(
        engine_command(study, "--output-strategy", "mpio"),
        cwd=tmp_path,
        env=environment(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group: SIGKILL reaches mpiexec and the ranks
    )
    lines = []
    for line in process.stdout:
        lines.append(line)
        if line.startswith("[1/"):
            if kill == "SIGKILL":
                os.killpg(process.pid, signal.SIGKILL)
            else:
                assert signal_ranks(study, signal.SIGTERM) == 2
            break
    out, err = process.communicate(timeout=120)
    if kill == "SIGKILL":
        _wait_for_ranks_to_die(process.pid)
    else:
        assert process.returncode == 3, err
    first = "".join(lines) + out
    done_first = [line.split()[1] for line in first.splitlines() if _completed_line(line)]
    assert 1 <= len(done_first) < 6

    second = run_engine(study, "--output-strategy", "mpio")
    assert second.returncode == 0, second.stderr
    redone = finished_cases(second.stdout)
    assert not set(redone) & set(done_first), "a completed case was computed twice"
    summary = engine.load_summary(tmp_path / "killed.h5")
    assert (summary.status == "completed").all() and len(summary) == 6
    reference = run_engine(
        study, "--output-strategy", "single", "--output", str(tmp_path / "reference.h5")
    )
    assert reference.returncode == 0, reference.stderr
    assert_same_results(tmp_path / "killed.h5", tmp_path / "reference.h5")


def _completed_line(line: str) -> bool:
    return line.startswith("[") and line.rstrip().endswith("completed")


def _wait_for_ranks_to_die(group: int, timeout: float = 30) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            os.killpg(group, 0)
        except ProcessLookupError:
            return
        time.sleep(0.2)
    raise AssertionError("ranks survived SIGKILL of their process group")


@pytest.mark.skipif(
    "engine_h5py_is_mpi_enabled()", reason="h5py is MPI-enabled here: mpio is available"
)
def test_mpio_without_parallel_h5py_is_a_clear_error(tmp_path):
    """Plain h5py wheel + mpio requested -> exit 2 at once, a message naming the build script, no
    file created (no hang, no corrupt file)."""
    study = write_study(tmp_path, "plain")
    result = run_engine(study, "--output-strategy", "mpio", timeout=60)
    assert result.returncode == 2, result.stderr
    assert "not MPI-enabled" in result.stderr
    assert "scripts/build_parallel_h5py.sh" in result.stderr
    assert not (tmp_path / "plain.h5").exists() and not (tmp_path / "plain.csv").exists()
    # the same through the study file
    study.write_text(study.read_text().replace("[study]\n", '[study]\noutput_strategy = "mpio"\n'))
    result = run_engine(study, timeout=60)
    assert result.returncode == 2 and "build_parallel_h5py.sh" in result.stderr


def run_on_two_ranks(code: str, study) -> subprocess.CompletedProcess:
    """``code`` as a script beside ``study``, run under ``mpiexec -n 2`` with the study's
    path as its argument, from the study's folder."""
    script = study.with_suffix(".py")
    script.write_text(code)
    return subprocess.run(
        [MPIEXEC, "-n", "2", PYTHON, str(script), str(study)],
        cwd=study.parent, env=environment(), capture_output=True, text=True, timeout=120,
    )  # fmt: skip


STOP_DURING_CREATION = """
import sys
from pathlib import Path
from mpi4py import MPI
from engine.run import study_metadata as _metadata
from engine.output.collective import CollectiveWriter
from engine.output.hdf5 import StoppedDuringSetUp, creating_path
from engine.study.config import parse_study
from engine.study.layout import plan_layout
from engine.study.plan import make_plan

comm = MPI.COMM_WORLD
config = parse_study(Path(sys.argv[1]).read_text(), source=sys.argv[1])
output = config.study.output
plan = make_plan(config)
calls = []

def should_stop():  # a stop signal seen by rank 1 only, at its third check (case 128)
    calls.append(1)
    return comm.Get_rank() == 1 and len(calls) > 2

writer = CollectiveWriter(output, comm, plan_layout(config, plan), should_stop=should_stop)
try:
    writer.prepare(plan, _metadata(config, "", plan))
except StoppedDuringSetUp:
    comm.Barrier()
    left = output.exists() or creating_path(output).exists()
    print(f"rank {comm.Get_rank()} stopped; file left: {left}", flush=True)
    sys.exit(0 if not left else 1)
print(f"rank {comm.Get_rank()} was not stopped", flush=True)
sys.exit(1)
"""


@needs_parallel_h5py
def test_stop_signal_on_one_rank_stops_collective_creation_on_every_rank(tmp_path):
    """On the mpio path: a stop seen by one rank while the new file's structure is
    being created (every 64 cases the ranks agree by an allreduce) stops the creation on every
    rank at the same point, and neither the file nor its temporary is left. Deterministic: the
    "signal" is a should_stop() that turns true on rank 1 at its third check."""
    mu1 = [float(f"{0.001 * k:.3f}") for k in range(1, 201)]  # 200 cases
    study = tiny_study(tmp_path, "stop", mu1=mu1, beta=[0.0])
    result = run_on_two_ranks(STOP_DURING_CREATION, study)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.count("stopped; file left: False") == 2, result.stdout


FULL_AT_THE_JOURNAL = """
import errno
import sys
from pathlib import Path
from mpi4py import MPI
from engine.output.collective import CollectiveWriter
from engine.output.space import case_bytes
from engine.run import study_metadata as _metadata
from engine.study.case import CaseRunner
from engine.study.config import parse_study
from engine.study.layout import plan_layout
from engine.study.plan import make_plan

comm = MPI.COMM_WORLD
config = parse_study(Path(sys.argv[1]).read_text(), source=sys.argv[1])
plan = make_plan(config)
writer = CollectiveWriter(config.study.output, comm, plan_layout(config, plan))
writer.prepare(plan, _metadata(config, "", plan))
case = plan.cases[comm.Get_rank()]
outcome = CaseRunner(config)(case)
data = case_bytes(record.data for record in outcome.datasets.values())

def full(journal):  # every dataset is in the file; the disk fills at the journal
    raise OSError(errno.ENOSPC, "No space left on device")

writer._write_journal = full
outcome = writer.write_own(outcome)
print(f"rank {comm.Get_rank()}: needed {outcome.output_full[0]} of {data}", flush=True)
sys.exit(0 if outcome.output_full[0] == data > 0 else 1)
"""


@needs_parallel_h5py
def test_a_case_the_disk_cannot_keep_names_all_its_bytes(tmp_path):
    """A disk that fills at a case's journal, after its datasets went into the file: the run
    stops as full, and what it says the case needs is the case's whole data (the next run
    computes and writes it again), not the nothing left to write."""
    study = tiny_study(tmp_path, "journal", mu1=[0.1, 0.2], beta=[0.0])
    result = run_on_two_ranks(FULL_AT_THE_JOURNAL, study)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.count(": needed ") == 2, result.stdout
