"""``slurm/run_study.sbatch`` under a real SLURM: a private single-node cluster
(:mod:`tests.slurm.cluster`: munged, slurmctld and slurmd of Debian's slurm-wlm, started for
this module and stopped at its end), real ``sbatch``, ``srun --mpi=pmi2`` on two tasks, real
signals delivered by SLURM.

The jobs run the engine with an mpi4py built against Debian's MPICH (``.venv-mpio`` of
``scripts/build_parallel_h5py.sh``; ``ENGINE_PYTHON`` selects another), which is what srun's
PMI-2 plug-in can connect. Skipped, with the reason, without root, without slurm-wlm and
munge, or without that Python. ``scripts/test.sh`` runs this module in its SLURM phase.

Every job is submitted from a directory outside the repository, with the script's path, and
its options as sbatch flags, as a user would. The pre-timeout signal comes from SLURM's own
timer in the ``--no-requeue`` test (``--time=1 --signal=B:USR1@50``); the requeue and chain
tests send it by hand once a case has finished, ``scancel --batch --signal=USR1``: the same
signal by the same route (slurmctld → slurmd → the batch shell), at a known moment.
``SLURM_TEST_UPDATE_DOCS=1`` writes the transcript of the requeue test into
docs/how-to/slurm.md.
"""

from __future__ import annotations

import datetime
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import h5py
import pytest

from engine.study.examples import study_toml
from tests.slurm.cluster import CRED_EXPIRE, Cluster, unavailable

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "slurm" / "run_study.sbatch"
PYTHON = Path(os.environ.get("ENGINE_PYTHON") or REPO / ".venv-mpio" / "bin" / "python")
DOC = REPO / "docs" / "how-to" / "slurm.md"
JOB_TIMEOUT = 300.0  # s: a job of the small study takes 15–30 s here at load 15, requeued ~40 s
MU1, BETA = [0.1, 0.2, 0.4], [0.0, 90.0]
CASES = len(MU1) * len(BETA)


def _python_unavailable() -> str | None:
    """Why PYTHON cannot run the engine under srun --mpi=pmi2 (None: it can)."""
    if not PYTHON.exists():
        return (
            f"no {PYTHON}: an mpi4py built against Debian's MPICH is needed "
            "(bash scripts/build_parallel_h5py.sh builds .venv-mpio)"
        )
    check = (
        "import mpi4py; mpi4py.rc.initialize = False; from mpi4py import MPI; "
        "print(MPI.Get_library_version().splitlines()[0])"
    )
    result = subprocess.run([PYTHON, "-c", check], capture_output=True, text=True)
    if result.returncode != 0 or "MPICH" not in result.stdout:
        return f"{PYTHON} has no mpi4py on an MPICH library: {result.stdout or result.stderr}"
    return None


REASON = unavailable() or _python_unavailable()
pytestmark = [pytest.mark.slurm, pytest.mark.skipif(REASON is not None, reason=str(REASON))]


@pytest.fixture(scope="module")
def cluster():
    cluster = Cluster()
    cluster.start()  # on failure: stops what it started, keeps its logs and says where
    try:
        yield cluster
    finally:
        cluster.stop()
        shutil.rmtree(cluster.root, ignore_errors=True)


class Job:
    """One submission of the script in its own working directory ``directory``."""

    def __init__(
        self, cluster: Cluster, directory: Path, *options: str, cycles=1e5, mu1=MU1, beta=BETA,
        study: str | None = None, relative: bool = False, **variables: str,
    ):  # fmt: skip
        """``study``: the study file's text (default: :func:`small_study` of ``cycles``,
        ``mu1``, ``beta``); ``relative``: give sbatch the script's path relative to the
        working directory (``../../…``); ``variables``: the script's variables."""
        self.cluster, self.directory = cluster, directory
        directory.mkdir(parents=True, exist_ok=True)
        (directory / "study.toml").write_text(study or small_study(int(cycles), mu1, beta))
        script = os.path.relpath(SCRIPT, directory) if relative else str(SCRIPT)
        self.command = [
            "sbatch", "--parsable", "--ntasks=2", "--time=10", "--job-name=slurm-test",
            *options, script, "study.toml",
        ]  # fmt: skip
        self.variables = {"PYTHON": str(PYTHON), **variables}  # exported to the job
        env = cluster.environment(**self.variables)
        result = cluster.run(*self.command, cwd=directory, env=env)
        self.id = int(result.stdout.strip().split(";")[0])
        self.log = directory / f"slurm-slurm-test-{self.id}.out"

    def text(self) -> str:
        return self.log.read_text() if self.log.exists() else ""

    def wait_for(self, pattern: str, timeout: float = JOB_TIMEOUT) -> None:
        """Until the job's log holds a line matching ``pattern``."""
        deadline = time.monotonic() + timeout
        while not re.search(pattern, self.text(), re.M):
            fields = self.cluster.job(self.id)
            if fields["JobState"] not in ("PENDING", "RUNNING", "CONFIGURING"):
                raise AssertionError(f"job ended {fields['JobState']}:\n{self.text()}")
            if time.monotonic() > deadline:
                raise TimeoutError(f"no {pattern!r} in the log after {timeout:g} s:\n{self.text()}")
            time.sleep(0.2)

    def finish(self, timeout: float = JOB_TIMEOUT) -> dict[str, str]:
        return self.cluster.wait_until_finished(self.id, timeout)

    @property
    def results(self) -> Path:
        return self.directory / "results" / "small.h5"


def small_study(cycles: int, mu1: list[float], beta: list[float]) -> str:
    """Cyclic cases (P = 750 N, n = 32, coarse cycle jumps); with 10⁵ cycles 2–5 s each here,
    so a signal after the first finished case finds the other rank inside one."""
    return study_toml(
        "small",
        "results/small.h5",
        {
            "mesh": {"n": 32},
            "loading": {
                "steps": 4,
                "cycles": cycles,
                "record": [1000, cycles],
                "max_wear_fraction": 0.02,
            },
            "subsurface": {"layers": 8},
            "sweep": {"mu1": mu1, "wear1": [1.33e-7], "beta": beta},
        },
    )


def statuses(path: Path) -> list[str]:
    with h5py.File(path, "r") as file:
        return [str(group.attrs["status"]) for group in file["cases"].values()]


def compare(first: Path, second: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(REPO / "scripts" / "compare_results.py"), str(first), str(second)],
        capture_output=True,
        text=True,
    )


@pytest.fixture(scope="module")
def reference(cluster, tmp_path_factory):
    """The study uninterrupted: one job on 2 ranks, submitted from outside the repository."""
    job = Job(cluster, tmp_path_factory.mktemp("reference"))
    fields = job.finish()
    return job, fields


def test_a_study_completes_on_two_ranks(reference):
    job, fields = reference
    log = job.text()
    assert (fields["JobState"], fields["ExitCode"], fields["Restarts"]) == (
        "COMPLETED", "0:0", "0",
    ), log  # fmt: skip
    assert "srun --mpi=pmi2 (for MPICH" in log
    assert f"{CASES} cases, 0 already complete, {CASES} to run on 2 ranks" in log
    assert statuses(job.results) == ["completed"] * CASES
    with h5py.File(job.results, "r") as file:
        ranks = {int(group.attrs["rank"]) for group in file["cases"].values()}
    assert ranks == {0, 1}, "both tasks are ranks of one MPI world, and both computed"


def test_scancel_stops_without_requeue(cluster, tmp_path):
    job = Job(cluster, tmp_path)
    job.wait_for(r"^\[1/")  # a case finished, the other rank is inside one
    cluster.run("scancel", str(job.id))
    fields = job.finish()
    log = job.text()
    assert (fields["JobState"], fields["Restarts"]) == ("CANCELLED", "0"), log
    assert "TERM without a pre-timeout signal" in log
    assert "study incomplete, resubmit to resume: sbatch " in log
    assert "requeued" not in log
    done = statuses(job.results)  # readable, resumable
    assert 1 <= done.count("completed") < CASES, log
    time.sleep(7)  # longer than the requeue delay (cred_expire=5): still not requeued
    assert cluster.job(job.id)["JobState"] == "CANCELLED"


def test_a_pre_timeout_signal_requeues_and_the_result_equals_an_uninterrupted_run(
    cluster, reference, tmp_path
):
    job = Job(cluster, tmp_path)
    job.wait_for(r"^\[1/")
    signalled = time.monotonic()
    cluster.run("scancel", "--batch", "--signal=USR1", str(job.id))
    fields = job.finish()
    elapsed = time.monotonic() - signalled
    log = job.text()
    assert (fields["JobState"], fields["ExitCode"], fields["Restarts"]) == (
        "COMPLETED", "0:0", "1",
    ), log  # fmt: skip
    assert "pre-timeout signal (USR1)" in log
    assert f"requeued: the study continues in a new run of job {job.id}" in log
    assert "(restart 1 of at most 20)" in log
    assert re.search(r"^\d+ cases? continues? from (its|their) checkpoints?", log, re.M), log
    runs = [record for record in cluster.completions() if record["JobId"] == str(job.id)]
    assert len(runs) == 2 and runs[-1]["JobState"] == "COMPLETED", runs  # two runs, one id
    reference_job, _ = reference
    for suffix in (".h5", ".csv"):
        same = compare(reference_job.results.with_suffix(suffix), job.results.with_suffix(suffix))
        assert same.returncode == 0, same.stdout + same.stderr
    delay = requeue_delay(log)
    # SLURM holds a requeued job for the credential's lifetime; the log's stamps are whole
    # seconds and the "requeued" line follows scontrol's return: 2 s of slack
    assert delay >= CRED_EXPIRE - 2, log
    print(f"requeue delay {delay:.0f} s; signal to the end of the requeued run {elapsed:.1f} s")
    if os.environ.get("SLURM_TEST_UPDATE_DOCS") == "1":
        between = [f"$ scancel --batch --signal=USR1 {job.id}    # what --signal=B:USR1@300 sends"]
        write_transcript("slurm-transcript", job, fields, between, f": requeue delay {delay:.0f} s")


def requeue_delay(log: str) -> float:
    """Seconds from the script's "requeued" line to the first line of the next run."""
    stamps = {}
    for line in log.splitlines():
        stamp, _, text = line.partition(" ")
        if text.startswith("requeued:"):
            stamps["requeued"] = datetime.datetime.fromisoformat(stamp)
        elif text.startswith("job ") and "(restart 1 " in text:
            stamps["restarted"] = datetime.datetime.fromisoformat(stamp)
    return (stamps["restarted"] - stamps["requeued"]).total_seconds()


def test_a_requeue_by_slurm_itself_is_not_taken_for_a_cancel(cluster, tmp_path):
    """`scontrol requeue JOBID` from outside (an operator; preemption does the same): SLURM
    sends TERM and requeues the job; the script says so and the next run resumes."""
    job = Job(cluster, tmp_path)
    job.wait_for(r"^\[1/")
    cluster.run("scontrol", "requeue", str(job.id))
    fields = job.finish()
    log = job.text()
    assert (fields["JobState"], fields["ExitCode"], fields["Restarts"]) == (
        "COMPLETED", "0:0", "1",
    ), log  # fmt: skip
    assert "TERM: SLURM is requeueing this job" in log
    assert "TERM without a pre-timeout signal" not in log and "resubmit" not in log
    assert re.search(r"^\d+ cases? continues? from (its|their) checkpoints?", log, re.M), log
    assert statuses(job.results) == ["completed"] * CASES


def test_a_chained_job_continues_the_study(cluster, reference, tmp_path):
    """CHAIN=1: the pre-timeout signal submits a dependent job with the same resources."""
    job = Job(cluster, tmp_path, CHAIN="1")
    job.wait_for(r"^\[1/")
    cluster.run("scancel", "--batch", "--signal=USR1", str(job.id))
    first = job.finish()
    log = job.text()
    assert (first["JobState"], first["ExitCode"], first["Restarts"]) == (
        "COMPLETED", "0:0", "0",
    ), log  # fmt: skip
    successor = int(re.search(r"chained: job (\d+) continues the study", log).group(1))
    fields = cluster.wait_until_finished(successor, JOB_TIMEOUT)
    assert (fields["JobState"], fields["ExitCode"], fields["NumTasks"]) == ("COMPLETED", "0:0", "2")
    assert fields["TimeLimit"] == first["TimeLimit"] and fields["JobName"] == "slurm-test"
    chained = (tmp_path / f"slurm-slurm-test-{successor}.out").read_text()
    assert "(restart 1 of at most 20)" in chained
    assert re.search(r"^\d+ cases? continues? from (its|their) checkpoints?", chained, re.M), (
        chained
    )
    reference_job, _ = reference
    same = compare(reference_job.results, job.results)
    assert same.returncode == 0, same.stdout + same.stderr


def test_a_refused_requeue_ends_failed_with_exit_code_3(cluster, tmp_path):
    """The pre-timeout signal sent by SLURM's own timer: --time=1 with USR1 50 s before the
    limit (SLURM checks about every 30 s, so it comes 10–40 s after the start). The study is
    longer than that (128 cases of 10⁶ cycles: 48 of them once finished within 40 s on 2
    ranks here), and the job is not requeueable."""
    mu1 = [round(0.1 + 0.025 * i, 3) for i in range(16)]
    beta = [0.0, 22.5, 45.0, 67.5, 90.0, 112.5, 135.0, 157.5]
    options = ("--no-requeue", "--time=1", "--signal=B:USR1@50")
    job = Job(cluster, tmp_path, *options, cycles=1e6, mu1=mu1, beta=beta)
    fields = job.finish()
    log = job.text()
    assert (fields["JobState"], fields["ExitCode"], fields["Restarts"]) == (
        "FAILED", "3:0", "0",
    ), log  # fmt: skip
    assert "pre-timeout signal (USR1)" in log
    assert "requeue refused" in log
    assert "study incomplete, resubmit to resume" in log
    if job.results.exists():  # absent when the signal came during start-up (a timer's luck)
        assert statuses(job.results).count("completed") < len(mu1) * len(beta)


def test_the_restart_bound_ends_the_chain_failed_with_exit_code_3(cluster, tmp_path):
    """MAX_RESTARTS bounds requeues and chained jobs: at the bound the job is not requeued."""
    job = Job(cluster, tmp_path, MAX_RESTARTS="0")
    job.wait_for(r"^\[1/")
    cluster.run("scancel", "--batch", "--signal=USR1", str(job.id))
    fields = job.finish()
    log = job.text()
    assert (fields["JobState"], fields["ExitCode"], fields["Restarts"]) == (
        "FAILED", "3:0", "0",
    ), log  # fmt: skip
    assert "MAX_RESTARTS=0 restarts reached" in log
    assert "study incomplete, resubmit to resume" in log


@pytest.mark.parametrize(
    ("testing", "code"),
    [({"fail_cases": ["mu0.2_w0_b0"]}, 1), ({"fail_cases": "not a list"}, 2)],
    ids=["a failed case", "bad input"],
)
def test_exit_codes_1_and_2_end_the_job_without_requeue(cluster, tmp_path, testing, code):
    """Two static cases on a coarse mesh (seconds): one forced to fail, or a bad study."""
    study = study_toml(
        "tiny",
        "results/tiny.h5",
        {"mesh": {"n": 8}, "loading": {"kind": "static"}, "sweep": {"mu1": [0.1, 0.2]}},
        testing=testing,
    )
    job = Job(cluster, tmp_path, study=study, relative=True)  # the repository found from it
    fields = job.finish()
    log = job.text()
    assert (fields["JobState"], fields["ExitCode"], fields["Restarts"]) == (
        "FAILED", f"{code}:0", "0",
    ), log  # fmt: skip
    assert "not requeued" in log and "requeued:" not in log
    assert f"engine {REPO}, " in log


def test_a_launch_without_the_pmi_plugin_is_refused_and_not_requeued(cluster, tmp_path):
    job = Job(cluster, tmp_path, SRUN_MPI="none")
    fields = job.finish()
    log = job.text()
    assert (fields["JobState"], fields["ExitCode"], fields["Restarts"]) == (
        "FAILED", "2:0", "0",
    ), log  # fmt: skip
    errors = [line for line in log.splitlines() if line.startswith("error: srun started 2 tasks")]
    assert len(errors) == 1, log
    assert "--mpi=pmi2" in errors[0] and "SLURM_STEP_NUM_TASKS=2" in errors[0]
    assert not job.results.exists(), "refused before the output was touched"
    assert "not requeued" in log
    time.sleep(7)  # longer than the requeue delay: no second run
    assert cluster.job(job.id)["Restarts"] == "0"
    assert len([r for r in cluster.completions() if r["JobId"] == str(job.id)]) == 1
    if os.environ.get("SLURM_TEST_UPDATE_DOCS") == "1":
        write_transcript("slurm-refused-launch", job, cluster.job(job.id), [])


def write_transcript(
    block: str, job: Job, fields: dict[str, str], between: list[str], measured: str = ""
) -> None:
    """The test's own commands and job log as the generated block ``block`` of the how-to:
    the submission, the commands ``between`` (typed while it ran), the log, the job's end."""
    from engine.analysis.markdown import measured_on, replace_block

    def shown(text: str) -> str:
        return text.replace(str(job.directory), "~/runs").replace(str(REPO), "~/fretting-engine")

    variables = [f"{name}={value}" for name, value in job.variables.items()]
    command = [*variables, "sbatch", *job.command[2:]]  # sbatch exports the environment
    lines = [
        f"$ cd ~/runs && {shown(' '.join(command))}",
        f"Submitted batch job {job.id}",
        *between,
        f"$ cat slurm-slurm-test-{job.id}.out",
        *shown(job.text()).rstrip("\n").splitlines(),
        f"$ scontrol show job {job.id} | grep -o -E '(JobState|Restarts|ExitCode)=[^ ]+'",
        *(f"{key}={fields[key]}" for key in ("JobState", "Restarts", "ExitCode")),
    ]
    note = (
        "written by `SLURM_TEST_UPDATE_DOCS=1 pytest tests/slurm` (the SLURM phase of "
        "scripts/test.sh): a private single-node slurm-wlm 22.05, 2 tasks, Debian's MPICH "
        f"4.0.2, AuthInfo=cred_expire={CRED_EXPIRE}{measured}; paths shortened to ~/runs and "
        "~/fretting-engine"
    )
    text = measured_on(note) + "\n```\n" + "\n".join(lines) + "\n```\n"
    replace_block(DOC, block, text)
