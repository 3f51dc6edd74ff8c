"""A disk that fills to the last byte while a study runs, on 1 and 2 ranks, static and cyclic.

Each trial runs a small study on its own small tmpfs and, at a moment drawn at random, has
another process fill that file system to 0 B free (every other trial also sends SIGTERM to
the ranks 0.3 s later, while the run stops). Whatever the moment, the run must end within
30 s of the fault with exit 0 (it had finished), 5 (one line on stderr, no traceback) or,
after SIGTERM, 3; every case it printed as completed must be completed in the file; and a rerun
once the space is free must complete the study to a file identical to an undisturbed run
(``scripts/compare_results.py``). 8 trials for each of the four combinations: 32 in all.

Needs root to mount a tmpfs; skipped (saying so) where it cannot mount one. The longer soak
(kills, signals, damage as well) is ``benchmarks/soak_integrity.py``.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import importlib.util
import os
import random
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path

import h5py
import pytest

from engine.study.examples import study_toml
from tests.mpi.test_engine_mpi import engine_command, environment
from tests.test_full_disk import fill_to_the_last_byte as fill

pytestmark = pytest.mark.mpi

REPO = Path(__file__).resolve().parents[2]
TRIALS = 8  # per (ranks, kind): 32 trials in all
PARALLEL = 2  # trials at once (each on its own tmpfs)
DEADLINE_S = 30.0  # s from the fault to the end of the run (the required bound)
SIZE = "5m"  # the tmpfs: the study's file (0.6-2 MB) with the 1 MB kept free, twice over
OPTIONS = ("--no-progress-bar", "--progress-interval", "0")
COMPLETED_LINE = re.compile(r"^\[\s*\d+/\d+\] (\S+)\s+rank \d+\s+\S+ s\s+completed$", re.M)


def study_text(kind: str) -> str:
    """Small cases (n = 8): 20 static (about 1 s on one rank) or 12 cyclic of 10 cycles
    (about 2 s)."""
    loading = {"kind": "static", "steps": 2}
    sweep = {"mu1": [0.1, 0.2, 0.3, 0.4, 0.5], "beta": [0.0, 10.0, 20.0, 30.0]}
    if kind == "cyclic":
        loading = {"kind": "cyclic", "cycles": 10, "record": [10]}
        sweep = {"mu1": [0.1, 0.3, 0.5], "beta": [0.0, 10.0, 20.0, 30.0], "wear1": [1.33e-7]}
    return study_toml("disk", "disk.h5", mesh={"n": 8}, loading=loading, sweep=sweep)


def mount_tmpfs(directory: Path, size: str) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("mounting a small tmpfs needs root and mount(8)")
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(directory)],
        capture_output=True,
    )
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.decode().strip()}")


def command(ranks: int) -> list[str]:
    """The study by its relative name (the command line is stored in the file)."""
    return engine_command(Path("disk.toml"), *OPTIONS, ranks=ranks)


def run(directory: Path, ranks: int) -> subprocess.CompletedProcess:
    return subprocess.run(
        command(ranks),
        cwd=directory, env=environment(), capture_output=True, text=True, timeout=300,
    )  # fmt: skip


def differences(first: Path, second: Path) -> list[str]:
    """``scripts/compare_results.py``'s differences (run times ignored), in this process."""
    script = REPO / "scripts" / "compare_results.py"
    spec = importlib.util.spec_from_file_location("compare_results", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.compare_hdf5(first, second, module.RUN_DEPENDENT)


def rank_pids(directory: Path) -> list[int]:
    """Pids of the engine's rank processes running in ``directory`` (not ``mpiexec``: a
    signal goes to the ranks, as SLURM sends it to the tasks)."""
    pids = []
    for entry in Path("/proc").iterdir():
        try:
            words = (entry / "cmdline").read_bytes().split(b"\0")
            rank = words[1:3] == [b"-m", b"engine"]  # python -m engine, not the launcher
            if rank and os.readlink(entry / "cwd") == str(directory):
                pids.append(int(entry.name))
        except (OSError, ValueError):
            continue
    return pids


def faulted_run(directory: Path, ranks: int, delay: float, terminate: bool = False):
    """Start the study, fill the disk after ``delay`` s (``terminate``: and SIGTERM to every
    rank 0.3 s later, while the run stops); (exit code, stdout, stderr, seconds from the
    fault to the end). A run still alive 30 s after the fault is a hang: it gets SIGTERM,
    then SIGKILL, and the exit code None."""
    process = subprocess.Popen(
        command(ranks),
        cwd=directory, env=environment(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, start_new_session=True,
    )  # fmt: skip
    time.sleep(delay)
    filler = fill(directory)
    fault = time.monotonic()
    if terminate:
        time.sleep(0.3)
        for pid in rank_pids(directory):
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGTERM)
    try:
        out, err = process.communicate(timeout=DEADLINE_S)
        code = process.returncode
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGTERM)
        try:
            out, err = process.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            out, err = process.communicate()
        code = None
    elapsed = time.monotonic() - fault
    filler.unlink()
    return code, out, err, elapsed


@pytest.fixture(scope="module")
def undisturbed(tmp_path_factory):
    """The results of each kind, run once on 1 rank with space (the reference), and the
    wall time that run took from its start (s)."""
    results = {}
    for kind in ("static", "cyclic"):
        directory = tmp_path_factory.mktemp(f"reference_{kind}")
        (directory / "disk.toml").write_text(study_text(kind))
        start = time.monotonic()
        done = run(directory, 1)
        assert done.returncode == 0, done.stderr
        results[kind] = (directory / "disk.h5", time.monotonic() - start)
    return results


def trial(directory: Path, ranks: int, kind: str, delay: float, reference: Path):
    """One trial on its own tmpfs at ``directory``: (exit code, the problems found). Every
    other trial also sends SIGTERM while the run stops: then exit 3 is right as well, and
    the line saying that the signal was received comes first."""
    mount_tmpfs(directory, SIZE)
    problems = []
    terminate = int(directory.name.removeprefix("trial")) % 2 == 1
    where = f"{directory.name} (fault at {delay:.2f} s{', SIGTERM' if terminate else ''})"
    try:
        (directory / "disk.toml").write_text(study_text(kind))
        code, out, err, elapsed = faulted_run(directory, ranks, delay, terminate)
        if code not in ((0, 3, 5) if terminate else (0, 5)) or elapsed > DEADLINE_S:
            return code, [f"{where}: exit {code} {elapsed:.1f} s after the fault: {err}"]
        lines = [line for line in err.strip().splitlines() if " received: " not in line]
        if code == 5 and (len(lines) != 1 or not lines[0].startswith("error: disk.h5: no")):
            problems.append(f"{where}: exit 5 with stderr {err!r}")
        if "Traceback" in err:
            problems.append(f"{where}: a traceback: {err}")
        printed = COMPLETED_LINE.findall(out)
        if printed:
            with h5py.File(directory / "disk.h5", "r") as file:
                cases = file["cases"]
                missing = [c for c in printed if cases[c].attrs.get("status") != "completed"]
            if missing:
                problems.append(f"{where}: printed completed, not in the file: {missing}")
        rerun = run(directory, ranks)
        if rerun.returncode != 0:
            return code, [*problems, f"{where}: rerun: exit {rerun.returncode}: {rerun.stderr}"]
        found = differences(reference, directory / "disk.h5")
        if found:
            problems.append(f"{where}: the rerun differs from an undisturbed run: {found[:5]}")
        return code, problems
    finally:
        subprocess.run(["umount", "-l", str(directory)], check=False)


@pytest.mark.parametrize("kind", ["static", "cyclic"])
@pytest.mark.parametrize("ranks", [1, 2])
def test_a_disk_filled_to_the_last_byte_at_any_moment(tmp_path, undisturbed, ranks, kind):
    """8 trials, two at a time (each on its own tmpfs), the fault moments drawn from a
    fixed seed; every problem of every trial is listed. At least two trials must have been
    stopped by the fault (exit 5, or 3 after SIGTERM), else the moments missed the run."""
    rng = random.Random(f"{ranks}-{kind}")  # the same fractions of the run every time
    reference, duration = undisturbed[kind]
    # the fault within the run, however fast this machine runs it: from 0.2 s to 80 % of
    # the undisturbed run's wall time (start-up included)
    delays = [rng.uniform(0.2, max(0.4, 0.8 * duration)) for _ in range(TRIALS)]
    with concurrent.futures.ThreadPoolExecutor(PARALLEL) as pool:
        found = pool.map(
            lambda number: trial(
                tmp_path / f"trial{number}", ranks, kind, delays[number], reference
            ),
            range(TRIALS),
        )
        results = list(found)
    problems = [problem for _, problems in results for problem in problems]
    assert not problems, "\n".join(problems)
    codes = [code for code, _ in results]
    assert sum(code in (3, 5) for code in codes) >= 2, codes


def fill_when(trigger: Path, process: subprocess.Popen) -> None:
    """Fill ``trigger``'s file system to 0 B the moment ``trigger`` appears (polled without
    sleeping): the blocks in one ``fallocate``, then the last pages byte by byte."""
    while not trigger.exists() and process.poll() is None:
        pass
    filler = trigger.parent / "filler"
    with open(filler, "ab", buffering=0) as handle:
        status = os.statvfs(trigger.parent)
        with contextlib.suppress(OSError):
            os.posix_fallocate(handle.fileno(), 0, status.f_bavail * status.f_frsize)
    fill(trigger.parent)


@pytest.mark.skipif(not h5py.get_config().mpi, reason="the collective writer needs mpio h5py")
def test_the_collective_writer_meets_a_full_disk_as_it_creates_its_file(tmp_path):
    """The disk fills (another process) as the mpio writer creates its file: its first
    claim, or HDF5's flush of the new file, finds no space. 6 trials on 2 ranks: each exits
    5 with the one line naming the output and the space needed (no MPI_Abort, no
    traceback), leaves no temporary or spare file, and a rerun with space completes."""
    directory = tmp_path / "disk"
    mount_tmpfs(directory, SIZE)
    try:
        for trial in range(6):
            for path in directory.iterdir():
                shutil.rmtree(path) if path.is_dir() else path.unlink()
            (directory / "disk.toml").write_text(study_text("static"))
            process = subprocess.Popen(
                [*command(2), "--output-strategy", "mpio"], cwd=directory, env=environment(),
                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            )  # fmt: skip
            fill_when(directory / ".disk.h5.creating", process)
            out, err = process.communicate(timeout=DEADLINE_S)
            assert process.returncode == 5, (trial, err)
            lines = err.strip().splitlines()
            assert len(lines) == 1, (trial, err)
            assert re.match(r"error: disk\.h5: no space left .* need about \d", lines[0]), err
            left = {path.name for path in directory.iterdir()}
            assert not left & {".disk.h5.creating", ".disk.h5.spare", "disk.h5.lock"}, left
        (directory / "filler").unlink()
        rerun = subprocess.run(
            [*command(2), "--output-strategy", "mpio"], cwd=directory, env=environment(),
            capture_output=True, text=True, timeout=300,
        )  # fmt: skip
        assert rerun.returncode == 0, rerun.stderr
    finally:
        subprocess.run(["umount", "-l", str(directory)], check=False)
