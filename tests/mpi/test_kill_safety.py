"""Kill-safety under ``mpiexec -n 2``: kills at the first writes, a signal to one rank alone,
two runs on one output, output-path errors, a signal during start-up.

Tiny static studies (n = 8, 16 cases of ~0.1 s) keep the many trials cheap; trials run four
at a time (each in its own directory: they share nothing but the two cores). What is asserted
does not depend on where a kill or signal lands (that is random on purpose): the rerun always
completes every case, and a signalled job always ends within its deadline.
"""

from __future__ import annotations

import concurrent.futures
import os
import random
import re
import signal
import subprocess
import time
from pathlib import Path

import h5py
import pytest

import engine
from engine.study.examples import study_toml
from tests.mpi.test_engine_mpi import engine_command, environment, run_engine

pytestmark = pytest.mark.mpi

# n = 8, mu = 0.1: one case of 3e6 cycles takes ~6 s here
CYCLIC = {"cycles": 3000000, "record": None, "max_wear_fraction": 0.02}
TRIALS = 20  # kills, and signals to one rank alone: 20 of each
PARALLEL = 4


def tiny_study(
    directory: Path,
    name: str = "tiny",
    *,
    cyclic=False,
    mu1=(0.1, 0.2, 0.3, 0.4),
    beta=(0.0, 30.0, 60.0, 90.0),
    n=8,
    steps=2,
):
    """A static (or, ``cyclic``, a long cyclic) study of small cases in ``directory``."""
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"{name}.toml"
    loading = {"kind": "cyclic", **CYCLIC} if cyclic else {"kind": "static"}
    sweep = {"mu1": list(mu1), "beta": list(beta)}
    if cyclic:
        sweep["wear1"] = [1.33e-7]
    loading["steps"] = steps
    text = study_toml(name, directory / f"{name}.h5", mesh={"n": n}, loading=loading, sweep=sweep)
    path.write_text(text)
    return path


def start(study: Path, *options: str) -> subprocess.Popen:
    return subprocess.Popen(
        engine_command(study, *options),
        cwd=study.parent,
        env=environment(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def rank_pids(study: Path) -> dict[int, int]:
    """rank -> pid of the engine's rank processes on ``study`` (PMI_RANK of their environment)."""
    found = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            words = [w.decode() for w in (entry / "cmdline").read_bytes().split(b"\0") if w]
            if not (len(words) >= 4 and words[1:3] == ["-m", "engine"] and str(study) in words):
                continue
            env = (entry / "environ").read_bytes().split(b"\0")
        except (OSError, UnicodeDecodeError):
            continue
        for item in env:
            if item.startswith(b"PMI_RANK="):
                found[int(item.split(b"=")[1])] = int(entry.name)
    return found


def catches_sigterm(pid: int) -> bool:
    """Whether ``pid`` has a SIGTERM handler installed (SigCgt of /proc/PID/status)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    line = next(line for line in status.splitlines() if line.startswith("SigCgt:"))
    mask = int(line.split()[1], 16)
    return bool(mask & (1 << (signal.SIGTERM - 1)))


def wait_for(condition, timeout: float, interval: float = 0.001) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(interval)
    return False


def kill_ranks(study: Path, signum: int, ranks=(0, 1)) -> int:
    count = 0
    for rank, pid in rank_pids(study).items():
        if rank in ranks:
            try:
                os.kill(pid, signum)
                count += 1
            except ProcessLookupError:
                pass
    return count


def completed_cases(output: Path) -> list[str]:
    summary = engine.load_summary(output)
    return sorted(summary.loc[summary.status == "completed", "case_id"])


# -------------------------------------------------------------- kills at the first writes
def _kill_at_first_writes(directory: Path, delay: float, watch_final: bool):
    study = tiny_study(directory)
    output = directory / "tiny.h5"
    first_write = [output.with_name(f".{output.name}.creating"), output]
    watched = [output] if watch_final else first_write
    process = start(study)
    assert wait_for(lambda: any(p.exists() for p in watched), 60), "no file appeared"
    time.sleep(delay)
    kill_ranks(study, signal.SIGKILL)  # as the OOM killer or a node loss would
    process.communicate(timeout=60)
    left = "+".join(p.name for p in first_write if p.exists()) or "nothing"
    rerun = run_engine(study, "--resume", timeout=120)
    return rerun.returncode, rerun.stderr + rerun.stdout, left


def test_kill_at_the_first_writes_then_plain_resume_completes(tmp_path):
    """SIGKILL both ranks 0, 5, 10, 20, 40 ms after the file's temporary appears
    (creation) or after the file itself appears (the first cases' writes), 20 times; a plain
    ``--resume`` completes all 16 cases every time."""
    delays = [0.0, 0.005, 0.010, 0.020, 0.040] * (TRIALS // 5)
    with concurrent.futures.ThreadPoolExecutor(PARALLEL) as pool:
        futures = [
            pool.submit(_kill_at_first_writes, tmp_path / f"trial{i}", delay, i % 2 == 1)
            for i, delay in enumerate(delays)
        ]
        results = [future.result() for future in futures]
    failures = [(i, text) for i, (code, text, _) in enumerate(results) if code != 0]
    assert not failures, failures[:2]
    left = [state for *_, state in results]
    print("kill trials, files left:", {state: left.count(state) for state in sorted(set(left))})
    for i in range(len(delays)):
        assert len(completed_cases(tmp_path / f"trial{i}" / "tiny.h5")) == 16
        assert "Traceback" not in results[i][1]


# ------------------------------------------------------------------- a signal to one rank
def _signal_study(directory: Path) -> Path:
    """Six static cases of ~0.3 s (n = 32): the hang this guards against needed rank 1
    stopped while it still had a case to start after rank 0's computing thread had finished —
    a window of one case at the end of the run, which short cases would make too narrow to
    hit."""
    return tiny_study(directory, mu1=(0.1, 0.2, 0.3), beta=(0.0, 90.0), n=32, steps=4)


def _signal_rank_one(directory: Path, delay: float) -> tuple[int, float, bool, str]:
    study = _signal_study(directory)
    process = start(study)
    assert wait_for(lambda: 1 in rank_pids(study), 60)
    pid = rank_pids(study)[1]
    wait_for(lambda: catches_sigterm(pid), 30)
    time.sleep(delay)
    sent = kill_ranks(study, signal.SIGTERM, ranks=(1,)) == 1
    signalled = time.monotonic()
    try:
        out, err = process.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        process.kill()
        out, err = process.communicate()
        return -1, time.monotonic() - signalled, sent, err
    elapsed = time.monotonic() - signalled
    return process.returncode, elapsed, sent, err + out


def test_sigterm_to_rank_one_alone_ends_the_job(tmp_path):
    """SIGTERM to rank 1 only, at a random time (start-up, computing, shutdown),
    20 trials: every job ends within 30 s with exit code 3 (or 0 when the signal came after
    the last case and found nothing to stop), and a rerun completes every case."""
    rng = random.Random(16)
    delays = [rng.uniform(0.0, 3.0) for _ in range(TRIALS)]
    with concurrent.futures.ThreadPoolExecutor(PARALLEL) as pool:
        futures = [
            pool.submit(_signal_rank_one, tmp_path / f"trial{i}", delay)
            for i, delay in enumerate(delays)
        ]
        results = [future.result() for future in futures]
    hung = [(i, r) for i, r in enumerate(results) if r[0] == -1]
    assert not hung, hung
    for i, (code, elapsed, _sent, text) in enumerate(results):
        assert code in (0, 3), (i, code, text)
        assert elapsed < 30, (i, elapsed)
        assert "Traceback" not in text, text
        if code == 0:
            assert len(completed_cases(tmp_path / f"trial{i}" / "tiny.h5")) == 6
    assert sum(code == 3 for code, *_ in results) >= TRIALS // 2, "most signals must stop a job"
    for i in (0, 1):  # resume after a stop
        rerun = run_engine(tmp_path / f"trial{i}" / "tiny.toml", timeout=120)
        assert rerun.returncode == 0, rerun.stderr
        assert len(completed_cases(tmp_path / f"trial{i}" / "tiny.h5")) == 6


def _signal_rank_zero(directory: Path, delay: float) -> tuple[int, float, str]:
    """Two cases that run for minutes, one on each rank, nothing held ahead; SIGTERM to
    rank 0 alone ``delay`` s after the cases are handed out. (exit code, s from the signal to the
    end, stdout and stderr); -1: still running 30 s after the signal."""
    directory.mkdir(parents=True, exist_ok=True)
    study = directory / "long.toml"
    loading = {"kind": "cyclic", "steps": 2, "cycles": 300000000, "record": None}
    loading["max_wear_fraction"] = 0.0005  # small jumps: minutes of cycles
    sweep = {"mu1": [0.1, 0.2], "beta": [0.0], "wear1": [1.33e-7]}
    text = study_toml("long", directory / "long.h5", mesh={"n": 8}, loading=loading, sweep=sweep)
    study.write_text(text)
    process = start(study)
    announced = ""
    for line in process.stdout:  # the cases are handed out once the start line is printed
        announced += line
        if " to run on 2 ranks" in line:
            break
    time.sleep(delay)
    assert kill_ranks(study, signal.SIGTERM, ranks=(0,)) == 1
    signalled = time.monotonic()
    try:
        out, err = process.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        kill_ranks(study, signal.SIGKILL)
        out, err = process.communicate()
        return -1, time.monotonic() - signalled, announced + out + err
    return process.returncode, time.monotonic() - signalled, announced + out + err


def test_sigterm_to_rank_zero_alone_stops_rank_one_in_its_case(tmp_path):
    """SIGTERM to rank 0 only while each rank computes a long case with no other case
    held: rank 0 tells rank 1 to stop (as when rank 0's signal, or a full disk, comes first).
    6 trials: every job ends within 10 s with exit 3, rank 1's case saved as interrupted
    (a rank told to stop mid-case once waited for another instruction while rank 0 waited
    for its outcome: both ranks idle for good)."""
    rng = random.Random(0)
    delays = [rng.uniform(0.3, 1.5) for _ in range(6)]
    with concurrent.futures.ThreadPoolExecutor(3) as pool:
        futures = [
            pool.submit(_signal_rank_zero, tmp_path / f"trial{i}", delay)
            for i, delay in enumerate(delays)
        ]
        results = [future.result() for future in futures]
    print("seconds from the signal to the end", [round(elapsed, 2) for _, elapsed, _ in results])
    for i, (code, elapsed, text) in enumerate(results):
        assert code == 3 and elapsed < 10, (i, delays[i], code, elapsed, text)
        assert "Traceback" not in text, text
    interrupted = [re.search(r"rank 1 .* interrupted", text) for *_, text in results]
    assert sum(bool(found) for found in interrupted) >= 3, [text for *_, text in results]


def _signal_process_group(directory: Path, delay: float, idle_rank: bool):
    """SIGTERM to the process group of ``mpiexec`` (as Ctrl-C, ``kill -- -PGID`` or a batch
    system send it: ``mpiexec`` forwards it to the ranks, which Hydra starts outside its
    process group) ``delay`` s after both ranks catch it. (exit code, s from the signal to the
    end, stderr); a job still running 30 s after the signal: exit code -1."""
    if idle_rank:  # one long case: rank 1 waits for work, rank 0 dispatches and computes
        study = tiny_study(directory, cyclic=True, mu1=(0.1,), beta=(0.0,))
    else:
        study = tiny_study(directory)
    process = subprocess.Popen(
        engine_command(study), cwd=study.parent, env=environment(), stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True, start_new_session=True,
    )  # fmt: skip

    # Hydra's mpiexec drops a signal that reaches it before its proxy has started the ranks
    # (`mpiexec -n 2 sleep 8` runs on through a SIGTERM in its first ~40 ms): the moment is
    # drawn from when the engine can catch it
    def ready() -> bool:
        pids = rank_pids(study)
        return len(pids) == 2 and all(catches_sigterm(pid) for pid in pids.values())

    assert wait_for(ready, 60), "the ranks did not start"
    time.sleep(delay)
    os.killpg(process.pid, signal.SIGTERM)
    signalled = time.monotonic()
    try:
        out, err = process.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        out, err = process.communicate()
        return -1, time.monotonic() - signalled, err
    return process.returncode, time.monotonic() - signalled, err


def test_sigterm_to_the_process_group_ends_the_job_with_exit_3(tmp_path):
    """SIGTERM to mpiexec's process group at a random moment 0-2.5 s after the ranks catch
    it (start-up, computing, shutdown), 20 trials, half of them with one long case (rank 1
    idle, waiting for work): every job ends within 10 s with exit 3, or 0 when the signal
    came after the last case."""
    rng = random.Random(40)
    delays = [rng.uniform(0.0, 2.5) for _ in range(20)]
    with concurrent.futures.ThreadPoolExecutor(PARALLEL) as pool:
        futures = [
            pool.submit(_signal_process_group, tmp_path / f"trial{i}", delay, i % 2 == 1)
            for i, delay in enumerate(delays)
        ]
        results = [future.result() for future in futures]
    print("exit codes", [code for code, *_ in results])
    print("seconds from the signal to the end", [round(elapsed, 2) for _, elapsed, _ in results])
    for i, (code, elapsed, err) in enumerate(results):
        assert code in (0, 3), (i, delays[i], code, elapsed, err)
        assert elapsed < 10, (i, delays[i], elapsed)  # a few s on a loaded machine
        assert "Traceback" not in err, err
    assert sum(code == 3 for code, *_ in results) >= 10, "most signals must stop a job"


def test_sigterm_during_start_up_exits_3_within_5_seconds(tmp_path):
    """A stop signal as soon as the ranks can catch it, and a second one
    50 ms later: exit 3 (not a signal death), within 5 s."""
    study = tiny_study(tmp_path)
    process = start(study)
    assert wait_for(lambda: len(rank_pids(study)) == 2, 60)
    pids = rank_pids(study)
    assert wait_for(lambda: all(catches_sigterm(pid) for pid in pids.values()), 30)
    signalled = time.monotonic()
    kill_ranks(study, signal.SIGTERM)
    time.sleep(0.05)
    kill_ranks(study, signal.SIGTERM)
    out, err = process.communicate(timeout=30)
    assert process.returncode == 3, err
    assert time.monotonic() - signalled < 5
    assert "Traceback" not in err


def test_sigterm_during_shutdown_is_not_a_signal_death(tmp_path):
    """SIGTERM to both ranks once the last line is printed (file closing, MPI and
    the interpreter shutting down): exit code 3 or 0, never the signal's 143/15."""
    study = tiny_study(tmp_path)
    process = start(study)
    for line in process.stdout:
        if "completed, 0 failed" in line:
            kill_ranks(study, signal.SIGTERM)
            break
    out, err = process.communicate(timeout=30)
    assert process.returncode in (0, 3), err
    assert "Traceback" not in err
    assert len(completed_cases(tmp_path / "tiny.h5")) == 16


# ----------------------------------------------------------------- two runs on one output
def test_second_run_and_fresh_run_on_a_busy_output_exit_2(tmp_path):
    """While a run computes, a second run and a ``--fresh`` run on the same output exit 2
    naming the first run; the first run's results are intact.

    Deterministic whatever the machine's speed: of the first run's two cases one is short and
    one runs for hours (10⁸ cycles), so the run still holds the output while the contenders
    start; it is then stopped by SIGTERM (exit 3) and its completed case must be there."""
    study = tiny_study(tmp_path, cyclic=True, mu1=(0.1,), beta=(0.0,), n=16)
    text = study.read_text().replace("cycles = 3000000\n", "")
    study.write_text(text + '"loading.cycles" = [1000, 100000000]\n')
    first = start(study)
    lines = []
    for line in first.stdout:
        lines.append(line)
        if line.startswith("[1/2]"):  # the short case is complete, the long one computes
            break
    assert "completed" in lines[-1], "".join(lines)
    lock_owner = rank_pids(study)[0]
    contenders = [start(study), start(study, "--fresh")]
    results = [process.communicate(timeout=120) for process in contenders]
    for process, (_, contender_err) in zip(contenders, results, strict=True):
        assert process.returncode == 2, contender_err
        assert f"in use by another run (pid {lock_owner}, host " in contender_err
        assert "Traceback" not in contender_err
    assert first.poll() is None, "the long case must still be running"
    kill_ranks(study, signal.SIGTERM)
    out, err = first.communicate(timeout=120)
    assert first.returncode == 3, err
    output = tmp_path / "tiny.h5"
    assert len(completed_cases(output)) == 1  # the --fresh contender deleted nothing
    with h5py.File(output, "r") as file:
        assert sorted(int(g.attrs["index"]) for g in file["cases"].values()) == [0, 1]
    assert not (tmp_path / "tiny.h5.lock").exists()


# --------------------------------------------------------------------- output-path errors
@pytest.mark.parametrize("where", ["under /proc", "parent is a file"])
def test_unwritable_output_path_exits_2_naming_path_and_error(where, tmp_path):
    study = tiny_study(tmp_path)
    (tmp_path / "plain").write_text("a regular file")
    output = "/proc/engine-test/out.h5" if where == "under /proc" else str(tmp_path / "plain/o.h5")
    result = run_engine(study, "--output", output, timeout=60)
    assert result.returncode == 2, result.stderr
    assert output in result.stderr and "Traceback" not in result.stderr
    reason = "No such file or directory" if where == "under /proc" else "is not a directory"
    assert reason in result.stderr
