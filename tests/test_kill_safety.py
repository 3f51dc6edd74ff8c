"""Serial parts of kill-safety and study identity: the output lock, output paths, the identity
check, extended and shrunk sweeps, salvage of damaged files, input ranges.
The same behaviour under ``mpiexec -n 2`` with real kills: tests/mpi/test_kill_safety.py.
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import sys

import h5py
import numpy as np
import pandas as pd
import pytest

from engine import load_summary
from engine.output.existing import inspect_existing
from engine.output.hdf5 import ResultsMismatch, SingleWriter, SummaryTable
from engine.output.identity import study_identity
from engine.output.lock import (
    OutputInUse,
    OutputLock,
    OutputPathError,
    check_output_path,
    check_summary_path,
    lock_path_for,
)
from engine.output.salvage import apply_existing
from engine.study.config import StudyConfigError, parse_study
from engine.study.examples import study_toml
from engine.study.plan import make_plan
from engine.study.resources import case_memory_bytes, check_memory
from tests.test_config import VALID
from tests.test_output import fake_outcome
from tests.test_output import metadata as base_metadata


def metadata(config):
    data = base_metadata(config)
    data.attrs["study_identity"] = study_identity(config.resolved())
    return data


def study(text=VALID):
    config = parse_study(text)
    return config, make_plan(config)


def completed_file(path, text=VALID):
    """A results file whose cases are all completed (fake outcomes)."""
    config, plan = study(text)
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        for case in plan:
            writer.write(fake_outcome(case))
    return config, plan


# ------------------------------------------------------------------------------ lock
def test_lock_refuses_a_second_owner_and_is_released(tmp_path):
    output = tmp_path / "r.h5"
    first = OutputLock(output)
    first.acquire()
    owner = lock_path_for(output).read_text().split()
    assert owner[:2] == [str(os.getpid()), socket.gethostname()]
    with pytest.raises(OutputInUse, match=rf"in use by another run \(pid {os.getpid()}, host "):
        OutputLock(output).acquire()
    first.release()
    assert not lock_path_for(output).exists()
    with OutputLock(output):
        assert lock_path_for(output).exists()


def test_stale_lock_of_a_dead_process_is_replaced(tmp_path):
    output = tmp_path / "r.h5"
    lock_path_for(output).write_text(f"999999999 {socket.gethostname()} 1\n")
    lock = OutputLock(output)
    lock.acquire()
    assert lock.replaced is not None and lock.replaced.pid == 999999999
    lock.release()


def test_lock_of_another_host_names_the_file_to_delete(tmp_path):
    output = tmp_path / "r.h5"
    lock_path_for(output).write_text("1234 some-other-node 1\n")
    with pytest.raises(OutputInUse, match="host some-other-node.*delete .*r.h5.lock"):
        OutputLock(output).acquire()


def test_output_path_errors_name_the_path(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputPathError, match="is not a directory"):
        check_output_path(tmp_path / "file" / "r.h5")
    (tmp_path / "dir.h5").mkdir()
    with pytest.raises(OutputPathError, match="not a regular file"):
        check_output_path(tmp_path / "dir.h5")
    with pytest.raises(OutputPathError, match="/proc/no-such"):
        check_output_path(__import__("pathlib").Path("/proc/no-such/r.h5"))


def test_an_unrelated_csv_with_the_summary_name_is_not_overwritten(tmp_path):
    (tmp_path / "r.csv").write_text("date,temperature\n2024-01-01,3\n")
    with pytest.raises(OutputPathError, match="not a summary of this engine"):
        check_summary_path(tmp_path / "r.h5", tmp_path / "r.csv")
    (tmp_path / "r.csv").write_text("case_id,mu1,mu2,wear1\n")
    check_summary_path(tmp_path / "r.h5", tmp_path / "r.csv")  # a summary: fine


# ------------------------------------------------------------------------------ identity
def test_another_study_is_refused_naming_every_difference(tmp_path):
    path = tmp_path / "r.h5"
    completed_file(path)
    before = path.read_bytes()
    other_text = VALID.replace('name = "t"', 'name = "other"').replace("load = 750", "load = 700")
    config, plan = study(other_text)
    with pytest.raises(ResultsMismatch) as info:
        inspect_existing(path, metadata(config), plan)
    message = str(info.value)
    assert "study name 't' in the file, 'other' in the study" in message
    assert "[loading] load: 750.0 in the file, 700.0 in the study" in message
    assert path.read_bytes() == before


def test_extended_sweep_adds_cases_and_keeps_completed_ones(tmp_path):
    path = tmp_path / "r.h5"
    completed_file(path)
    config, plan = study(VALID.replace("mu1 = [0.1, 0.4]", "mu1 = [0.1, 0.2, 0.4]"))
    existing = inspect_existing(path, metadata(config), plan)
    assert existing.kind == "resume" and existing.new_cases == 2 and not existing.stale
    with SingleWriter(path) as writer:
        assert len(writer.prepare(plan, metadata(config))) == 4
    with h5py.File(path, "r") as file:  # indices follow the new plan: no two cases share one
        indices = {name: int(group.attrs["index"]) for name, group in file["cases"].items()}
    assert sorted(indices.values()) == list(range(6))
    assert [indices[case_id] for case_id in plan.case_ids] == list(range(6))


@pytest.mark.parametrize("drop_stale", [False, True])
def test_shrunk_sweep_reports_stale_cases_and_csv_equals_h5(tmp_path, drop_stale):
    path = tmp_path / "r.h5"
    completed_file(path)
    config, plan = study(VALID.replace("mu1 = [0.1, 0.4]", "mu1 = [0.1]"))
    existing = inspect_existing(path, metadata(config), plan)
    assert existing.stale == ["mu0.4_w1.33e-07_b0", "mu0.4_w1.33e-07_b45"]
    with SingleWriter(path, drop_stale=drop_stale) as writer:
        writer.prepare(plan, metadata(config))
    from_h5, from_csv = load_summary(path), load_summary(path.with_suffix(".csv"))
    pd.testing.assert_frame_equal(from_h5, from_csv, check_exact=True)
    expected = list(plan.case_ids) + ([] if drop_stale else existing.stale)
    assert list(from_h5.case_id) == expected
    assert (from_h5.status == "completed").all()


# ------------------------------------------------------------------------------ salvage
def _truncate(path, fraction):
    size = path.stat().st_size
    with open(path, "r+b") as handle:
        handle.truncate(int(size * fraction))


def test_truncated_file_is_salvaged_and_the_rest_recomputed(tmp_path):
    """A file cut at 95 %: HDF5 refuses it ('truncated file'); the salvage reads the cases that
    lie wholly before the cut, copies them into a new file and keeps the damaged one."""
    path = tmp_path / "r.h5"
    config, plan = completed_file(path)
    with h5py.File(path, "r") as file:
        reference = {n: file["cases"][n]["fields/final/pressure"][()] for n in plan.case_ids}
    _truncate(path, 0.95)
    with pytest.raises(OSError, match="truncated"):
        h5py.File(path, "r")
    existing = inspect_existing(path, metadata(config), plan)
    assert existing.kind == "salvage", existing
    assert 1 <= len(existing.completed) < len(plan)
    apply_existing(existing, plan, metadata(config), tmp_path / "r.h5.checkpoints")
    assert (tmp_path / "r.h5.damaged.1").exists()
    with SingleWriter(path) as writer:
        completed = writer.prepare(plan, metadata(config))
    assert completed == set(existing.completed)
    with h5py.File(path, "r") as file:
        for name in completed:
            np.testing.assert_array_equal(
                file["cases"][name]["fields/final/pressure"][()], reference[name]
            )
            pressure = file["cases"][name]["fields/final/pressure"]  # scales re-attached
            assert pressure.dims[0][0] == file["cases"][name]["grid/x"]
        assert set(file["cases"]) == set(plan.case_ids)


def test_file_with_a_torn_header_starts_over_with_a_message(tmp_path, capsys):
    path = tmp_path / "r.h5"
    config, plan = completed_file(path)
    with open(path, "r+b") as handle:  # tear the superblock and root object header
        handle.seek(0)
        handle.write(b"\0" * 2048)
    existing = inspect_existing(path, metadata(config), plan)
    assert existing.kind == "start-over"
    existing.report(__import__("sys").stdout)
    assert "starts over" in capsys.readouterr().out
    apply_existing(existing, plan, metadata(config), tmp_path / "r.h5.checkpoints")
    assert not path.exists() and (tmp_path / "r.h5.damaged.1").exists()


def test_file_killed_before_any_case_completed_starts_over(tmp_path):
    """A half-built file (e.g. left by an engine without the temporary-name creation)."""
    path = tmp_path / "r.h5"
    config, plan = study()
    with h5py.File(path, "w") as file:
        file.attrs["format"] = "fretting-engine-results/1"
    shutil.copyfile(path, tmp_path / "copy.h5")
    _truncate(path, 0.3)
    existing = inspect_existing(path, metadata(config), plan)
    assert existing.kind == "start-over"


# ------------------------------------------------------------------------------ summary
def test_summary_table_spaces_rewrites_but_always_writes_when_forced(tmp_path):
    table = SummaryTable(tmp_path / "s.csv", spacing=1e9)
    rows = [{"case_id": "a", "status": "pending"}]
    table.update(lambda: rows, force=True)
    rows[0]["status"] = "completed"
    table.update(lambda: rows)  # within the spacing: skipped
    assert "pending" in (tmp_path / "s.csv").read_text() and table.dirty
    table.update(lambda: rows, force=True)
    assert "completed" in (tmp_path / "s.csv").read_text() and not table.dirty


# ------------------------------------------------------------------------------ input ranges
def replace_in(section_key_value: tuple[str, str]) -> str:
    old, new = section_key_value
    assert old in VALID
    return VALID.replace(old, new)


SOLVER = "beta = [0, 45]\n[solver]\n"
RANGE_ERRORS = {
    "tol 1e300": (("beta = [0, 45]\n", SOLVER + "tol = 1e300\n"), "[solver] tol", "[1e-16, 0.01]"),
    "tol 0.1": (("beta = [0, 45]\n", SOLVER + "tol = 0.1\n"), "[solver] tol", "[1e-16, 0.01]"),
    "maxiter 0": (("beta = [0, 45]\n", SOLVER + "maxiter = 0\n"), "[solver] maxiter", ">= 1"),
    "beta 0 and 180": (("beta = [0, 45]", "beta = [0, 180]"), "[sweep] beta", "same axes"),
    "beta 45 and -135": (("beta = [0, 45]", "beta = [45, -135]"), "[sweep] beta", "same axes"),
    "E_A tiny": (("E_A = 200000.0", "E_A = 1e-300"), "[material] E_A", "[0.001, 1e12] MPa"),
    "E_B huge": (("E_B = 20000000.0", "E_B = 1e300"), "[material] E_B", "MPa"),
    "load huge": (("load = 750", "load = 1e300"), "[loading] load", "small strains"),
    "load tiny": (("load = 750", "load = 1e-300"), "[loading] load", "small strains"),
    "mu huge": (("mu1 = [0.1, 0.4]", "mu1 = [0.1, 1e300]"), "[sweep] mu1", "[0, 10]"),
    "wear huge": (("wear1 = [1.33e-07]", "wear1 = [1e300]"), "[sweep] wear1", "1/MPa"),
    # every count and control key bounded, the refusal naming the key at fault and why
    "steps 1e9": (("steps = 4", "steps = 1e9"), "[loading] steps", "write 1000000000"),
    "steps 10^9": (("steps = 4", "steps = 1000000000"), "[loading] steps", "<= 10000"),
    "cycles 10^15": (
        ("cycles = 100\n", "cycles = 1000000000000000\n"),
        "[loading] cycles",
        "<= 1e+09",
    ),
    "max_wear_fraction 1e300": (
        ("[loading]\n", "[loading]\nmax_wear_fraction = 1e300\n"),
        "[loading] max_wear_fraction",
        "<= 1 (wear per cycle jump",
    ),
    "layers 10^6": (("layers = 8", "layers = 1000000"), "[subsurface] layers", "<= 1024"),
    "depth 1e300": (("depth = 1.0", "depth = 1e300"), "[subsurface] depth", "<= 100"),
    "maxiter 10^12": (
        ("beta = [0, 45]\n", SOLVER + "maxiter = 1000000000000\n"),
        "[solver] maxiter",
        "<= 1e+07",
    ),
    "threads 10^6": (
        ("beta = [0, 45]\n", SOLVER + "threads = 1000000\n"),
        "[solver] threads",
        "<= 1024",
    ),
}


@pytest.mark.parametrize("kind", sorted(RANGE_ERRORS))
def test_values_outside_the_model_are_input_errors(kind):
    edit, key, fragment = RANGE_ERRORS[kind]
    with pytest.raises(StudyConfigError) as info:
        parse_study(replace_in(edit), source="s.toml")
    message = str(info.value)
    assert message.startswith("s.toml: ") and key in message and fragment in message, message


def test_beta_is_normalised_to_0_180():
    config, plan = study(VALID.replace("beta = [0, 45]", "beta = [-30, 270, 45]"))
    assert config.sweep.beta == (150.0, 90.0, 45.0)
    assert {case.beta for case in plan} == {150.0, 90.0, 45.0}


def test_memory_estimate_refuses_a_mesh_the_machine_cannot_hold():
    config, _ = study(VALID.replace("n = 32", "n = 4000"))
    with pytest.raises(StudyConfigError) as info:
        check_memory(config, ranks_on_node=2, limit=16 * 2**30)
    message = str(info.value)
    assert "[mesh] n = 4000" in message and "GiB" in message and "16.0 GiB" in message
    small, _ = study()
    check_memory(small, ranks_on_node=2, limit=16 * 2**30)  # n = 32: ~0.1 GB, fine
    # the 2048² frictional case's peak (benchmarks/bench_memory.py, the memory page's block
    # bench-memory: 4070 MB the solve alone, 4115 MB the command), within 5 % above it
    assert 4115e6 < case_memory_bytes(2048, 16) < 1.05 * 4115e6
    # the largest case of the plan decides: a swept mesh, and the steps of a cyclic study
    swept_n = VALID.replace("[mesh]\nn = 32\n", "[mesh]\n")
    swept, plan = study(swept_n.replace("mu1 = [0.1, 0.4]", 'mu1 = [0.1]\n"mesh.n" = [32, 4000]'))
    with pytest.raises(StudyConfigError, match=r"\[mesh\] n = 4000"):
        check_memory(swept, ranks_on_node=2, limit=16 * 2**30, plan=plan)
    steps = VALID.replace("steps = 4", "steps = 400").replace("n = 32", "n = 1000")
    many, plan = study(steps)
    with pytest.raises(StudyConfigError, match="800 increments per cycle"):
        check_memory(many, ranks_on_node=2, limit=16 * 2**30, plan=plan)
    check_memory(*study(steps.replace("steps = 400", "steps = 4"))[:1], 2, 16 * 2**30)


def test_a_frictionless_study_the_machine_holds_is_not_refused():
    # μ = 0 on every case: the normal problem's 200 B per element, not the frictional 960
    # (the cyclic study of VALID at n = 4000: 17.9 GiB frictionless, 29.3 GiB frictional)
    text = VALID.replace("n = 32", "n = 4000")
    frictional, plan = study(text)
    with pytest.raises(StudyConfigError, match=r"\[mesh\] n = 4000"):
        check_memory(frictional, ranks_on_node=1, limit=24 * 2**30, plan=plan)
    frictionless, plan = study(text.replace("mu1 = [0.1, 0.4]", "mu1 = [0.0]"))
    check_memory(frictionless, ranks_on_node=1, limit=24 * 2**30, plan=plan)
    mixed, plan = study(text.replace("mu1 = [0.1, 0.4]", "mu1 = [0.0, 0.1]"))
    with pytest.raises(StudyConfigError, match=r"\[mesh\] n = 4000"):  # one case has friction
        check_memory(mixed, ranks_on_node=1, limit=24 * 2**30, plan=plan)


LAUNCHER = """
import os, subprocess, sys
child = subprocess.Popen(sys.argv[1:], stdout=subprocess.DEVNULL)
_, status, usage = os.wait4(child.pid, 0)
code = os.waitstatus_to_exitcode(status)
print(usage.ru_maxrss)
sys.exit(code)
"""


@pytest.mark.parametrize("mu", [0.0, 0.2])
def test_the_estimate_bounds_the_measured_peak(tmp_path, mu):
    # the command's peak (ru_maxrss of the ended process: the interpreter, the imports, the
    # solve, the default 16 layers of the x-z plane, the file and its read-back) against the
    # estimate: never above it (the estimate guards the machine), and not more than 1.6 times
    # below it (an estimate that errs that high refuses studies the machine can hold; the
    # imports' part of BASE_BYTES varies with the versions of NumPy and h5py)
    # A first, unmeasured run compiles the modules' bytecode, which the measured run reads,
    # as an installed package does (compiling them raises the peak by about 30 MB). A small
    # launcher starts the command and reports its peak: the peak of a process forked from
    # this one would start from this process's own (pytest's, with pandas and h5py loaded).
    study = study_toml(
        "static_256", "out.h5",
        mesh={"n": 256, "half_width": 1.89}, subsurface=None, solver=None,
        loading={"kind": "static", "load": 714.0, "steps": 1}, sweep={"mu1": [mu]},
    )  # fmt: skip
    (tmp_path / "s.toml").write_text(study)  # the default 16 layers of the x-z plane
    env = {key: value for key, value in os.environ.items() if not key.startswith("OMPI_")}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = str(tmp_path / "bytecode")
    command = [sys.executable, "-m", "engine", "s.toml", "--fresh", "--no-progress-bar"]
    for _ in range(2):
        launched = subprocess.run(
            [sys.executable, "-c", LAUNCHER, *command],
            cwd=tmp_path, env=env, capture_output=True, text=True, check=False,
        )  # fmt: skip
        assert launched.returncode == 0, launched.stderr
    measured = float(launched.stdout.split()[-1]) * 1024.0
    estimate = case_memory_bytes(256, 16, frictional=mu > 0.0)
    assert measured <= estimate <= 1.6 * measured, (measured, estimate)


def test_identity_ignores_threads_and_output_but_not_physics():
    config, _ = study()
    same = parse_study(VALID.replace('output = "out/t.h5"', 'output = "elsewhere/t.h5"'))
    assert study_identity(config.resolved()) == study_identity(same.resolved())
    other = parse_study(VALID.replace("radius = 1.8", "radius = 1.7"))
    assert json.loads(study_identity(other.resolved()))["punch"]["radius"] == 1.7


def test_case_id_collision_names_the_sweep_key():
    text = VALID.replace("mu1 = [0.1, 0.4]", "mu1 = [0.1, 0.10000000000001]")
    with pytest.raises(StudyConfigError, match=r"\[sweep\] mu1 = .*same id"):
        make_plan(parse_study(text, source="s.toml"))


def test_peer_watch_notices_a_dead_rank_of_this_host():
    """A launcher that does not clean up would leave rank 0 waiting for a dead worker forever;
    the watch (about once a second while waiting) turns that into an error (exit code 70)."""
    import subprocess
    import sys

    from engine.parallel.scheduler import PeerDied, PeerWatch

    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()  # gone: its pid no longer exists
    host = socket.gethostname()
    alive = PeerWatch(0, [(os.getpid(), host), (os.getppid(), host)], interval=0.0)
    alive.check({1})  # a live peer: nothing happens
    watch = PeerWatch(0, [(os.getpid(), host), (child.pid, host)], interval=0.0)
    with pytest.raises(PeerDied, match=rf"rank 1 \(pid {child.pid}\) died"):
        watch.check({1})
    remote = PeerWatch(0, [(os.getpid(), host), (child.pid, "another-node")], interval=0.0)
    remote.check({1})  # another host: left to the launcher


def test_lock_of_a_killed_but_unreaped_process_is_stale(tmp_path):
    """A rank killed with SIGKILL stays a zombie until reaped (in a container, PID 1 may never
    reap it); its lock is stale all the same."""
    import signal
    import subprocess
    import sys
    import time

    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    output = tmp_path / "r.h5"
    ticks = open(f"/proc/{child.pid}/stat").read().rpartition(")")[2].split()[19]
    lock_path_for(output).write_text(f"{child.pid} {socket.gethostname()} {ticks}\n")
    with pytest.raises(OutputInUse):
        OutputLock(output).acquire()  # alive: in use
    os.kill(child.pid, signal.SIGKILL)
    time.sleep(0.2)  # dead, not reaped (no wait()): a zombie
    lock = OutputLock(output)
    lock.acquire()
    assert lock.replaced is not None and lock.replaced.pid == child.pid
    lock.release()
    child.wait()


def test_a_lock_path_that_is_a_directory_is_an_input_error_and_garbage_is_stale(tmp_path):
    output = tmp_path / "r.h5"
    lock_path_for(output).mkdir()
    with pytest.raises(OutputPathError, match=r"r\.h5\.lock exists and is not a regular file"):
        OutputLock(output).acquire()
    lock_path_for(output).rmdir()
    lock_path_for(output).write_bytes(b"\xff\xfe not text")  # garbage: a crashed writer's
    with OutputLock(output) as lock:
        assert lock.replaced is not None


def test_a_study_file_with_a_byte_order_mark_is_read(tmp_path):
    from engine.study.config import load_study

    path = tmp_path / "s.toml"
    path.write_bytes(b"\xef\xbb\xbf" + VALID.encode())  # what some Windows editors write
    assert load_study(path).resolved() == parse_study(VALID).resolved()


@pytest.mark.parametrize("value", ["-5", "nan", "inf", "1e9", "soon"])
def test_progress_interval_outside_0_to_a_day_is_refused(value, capsys):
    from engine.cli import build_parser

    with pytest.raises(SystemExit):
        build_parser().parse_args(["s.toml", "--progress-interval", value])
    assert "--progress-interval" in capsys.readouterr().err
