"""A private single-node SLURM for the tests: ``munged``, ``slurmctld`` and ``slurmd`` (Debian's
``munge`` and ``slurm-wlm``) started as children of the test, in a temporary directory of
their own, with a configuration written here and free TCP ports, and stopped by their PIDs.

Nothing is shared with a SLURM or MUNGE of the machine: its own key and socket, state and
spool directories, log files and ports; every client command gets ``SLURM_CONF`` pointing at
the configuration written here. The node offers the machine's CPUs (at most
:data:`NODE_CPUS`) to one partition, ``test``.

The settings that keep the tests short are the ones a cluster tunes too, chosen for
a test here:

- ``AuthInfo=cred_expire=5``: a requeued job may start again after the job credential's
  lifetime, 120 s by default (so at least 2 minutes per requeue on a cluster left at the
  default); 5 s is the minimum SLURM accepts;
- ``SchedulerParameters=sched_interval=1``: the scheduler looks at the pending jobs every
  second (default 60 s), so a requeued job starts as soon as it may;
- ``MinJobAge=3600``: a finished job stays visible to ``scontrol show job`` for an hour (there
  is no accounting database, so no ``sacct``); ``JobCompType=jobcomp/filetxt`` logs every end
  of a job, requeues included (:meth:`Cluster.completions`).
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from pathlib import Path

DAEMONS = ("munged", "slurmctld", "slurmd")
CLIENTS = ("sbatch", "scancel", "scontrol", "sinfo", "squeue", "srun")
NODE = "fretnode"
PARTITION = "test"
NODE_CPUS = 2
START_TIMEOUT = 60.0  # s: slurmctld and slurmd up, the node idle (about 3 s here)
FINAL_STATES = ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY")
CRED_EXPIRE = 5  # s: the job credential's lifetime, the requeue delay (SLURM's minimum)
STOP_TIMEOUT = 20.0  # s: a daemon's exit after SIGTERM, before SIGKILL


def unavailable() -> str | None:
    """Why a private SLURM cannot run here (None: it can)."""
    if os.geteuid() != 0:
        return "needs root (slurmd starts the jobs' processes; munged and slurmctld run as root)"
    missing = [name for name in ("munge", *DAEMONS, *CLIENTS) if shutil.which(name) is None]
    if missing:
        return (
            f"SLURM or MUNGE is not installed (no {', '.join(missing)}): scripts/test.sh "
            "installs slurm-wlm and munge as root"
        )
    return None


def _free_ports(count: int) -> list[int]:
    """``count`` distinct TCP ports free on localhost now."""
    sockets = [socket.socket() for _ in range(count)]
    try:
        for item in sockets:
            item.bind(("127.0.0.1", 0))
        return [item.getsockname()[1] for item in sockets]
    finally:
        for item in sockets:
            item.close()


class Cluster:
    """One controller, one node, one partition, in ``root`` (created, and left for reading
    the logs after a failure; :meth:`stop` ends every daemon started)."""

    def __init__(self, root: Path | None = None, cpus: int | None = None):
        if root is None:  # munged wants every directory above its socket to be searchable
            root = Path(tempfile.mkdtemp(prefix="fretting-slurm-"))
        self.root = root
        self.cpus = cpus or min(NODE_CPUS, os.cpu_count() or 1)
        self.config = root / "slurm.conf"
        self.socket = root / "run" / "munge.socket"
        self.processes: dict[str, subprocess.Popen] = {}

    # ------------------------------------------------------------------ configuration
    def _write_configuration(self) -> None:
        root = self.root
        for name in ("run", "state", "spool", "log"):
            (root / name).mkdir(parents=True, exist_ok=True)
        root.chmod(0o755)
        (root / "run").chmod(0o755)
        keys = root / "munge"
        keys.mkdir(mode=0o700, exist_ok=True)
        key = keys / "munge.key"
        key.write_bytes(os.urandom(1024))
        key.chmod(0o400)
        controller_port, node_port = _free_ports(2)
        host = socket.gethostname()
        self.config.write_text(
            f"""\
ClusterName=fretting-test
SlurmctldHost={host}(127.0.0.1)
SlurmctldPort={controller_port}
SlurmdPort={node_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.socket},cred_expire={CRED_EXPIRE}
StateSaveLocation={root}/state
SlurmdSpoolDir={root}/spool
SlurmctldPidFile={root}/run/slurmctld.pid
SlurmdPidFile={root}/run/slurmd.pid
SlurmctldLogFile={root}/log/slurmctld.log
SlurmdLogFile={root}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc={root}/log/jobcomp.txt
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=3600
NodeName={NODE} NodeHostname={host} NodeAddr=127.0.0.1 CPUs={self.cpus} State=UNKNOWN
PartitionName={PARTITION} Nodes={NODE} Default=YES MaxTime=INFINITE State=UP
"""
        )

    # ------------------------------------------------------------------ daemons
    def start(self) -> None:
        """Write the configuration, start the daemons, wait for the node to be idle."""
        self._write_configuration()
        log = self.root / "log"
        self._spawn(
            "munged",
            [
                "munged", "--foreground", f"--socket={self.socket}",
                f"--key-file={self.root / 'munge' / 'munge.key'}",
                f"--pid-file={self.root / 'run' / 'munged.pid'}",
                f"--seed-file={self.root / 'munge' / 'munged.seed'}",
                f"--log-file={log / 'munged.log'}",
            ],
        )  # fmt: skip
        self._wait(lambda: self.socket.exists(), "munged's socket")
        self._spawn("slurmctld", ["slurmctld", "-D", "-i", "-f", str(self.config)])
        self._spawn("slurmd", ["slurmd", "-D", "-N", NODE, "-f", str(self.config)])
        self._wait(self._node_idle, f"node {NODE} idle")

    def _spawn(self, name: str, command: list[str]) -> None:
        output = open(self.root / "log" / f"{name}.out", "ab")  # noqa: SIM115 - the daemon's
        self.processes[name] = subprocess.Popen(
            command, stdout=output, stderr=subprocess.STDOUT, env=self.environment()
        )

    def _node_idle(self) -> bool:
        result = self.run("sinfo", "-h", "-N", "-o", "%T", check=False)
        return result.returncode == 0 and result.stdout.strip() == "idle"

    def _wait(self, condition, what: str, timeout: float = START_TIMEOUT) -> None:
        deadline = time.monotonic() + timeout
        while not condition():
            dead = [name for name, process in self.processes.items() if process.poll() is not None]
            if dead or time.monotonic() > deadline:
                self.stop()
                logs = self.root / "log"
                raise RuntimeError(
                    f"private SLURM: no {what} after {timeout:g} s (exited: {dead or 'none'}); "
                    f"logs in {logs}"
                )
            time.sleep(0.2)

    def stop(self) -> None:
        """Cancel the jobs left, then end slurmd, slurmctld and munged by their PIDs (SIGTERM,
        SIGKILL after :data:`STOP_TIMEOUT`)."""
        if self.processes.get("slurmctld") and self.processes["slurmctld"].poll() is None:
            self.run("scancel", "--partition", PARTITION, check=False)
            deadline = time.monotonic() + STOP_TIMEOUT
            while self._jobs_alive() and time.monotonic() < deadline:
                time.sleep(0.5)
        for name in ("slurmd", "slurmctld", "munged"):
            process = self.processes.pop(name, None)
            if process is None or process.poll() is not None:
                continue
            os.kill(process.pid, signal.SIGTERM)
            try:
                process.wait(timeout=STOP_TIMEOUT)
            except subprocess.TimeoutExpired:
                os.kill(process.pid, signal.SIGKILL)
                process.wait()

    def _jobs_alive(self) -> bool:
        result = self.run("squeue", "-h", "-o", "%T", check=False)
        return result.returncode == 0 and bool(result.stdout.split())

    # ------------------------------------------------------------------ clients
    def environment(self, **extra: str) -> dict[str, str]:
        """The caller's environment without any SLURM or PMI variables of its own, with
        ``SLURM_CONF`` for this cluster and ``extra``."""
        env = {
            key: value
            for key, value in os.environ.items()
            if not key.startswith(("SLURM_", "SBATCH_", "SRUN_", "SALLOC_", "PMI_", "PMIX_"))
        }
        env["SLURM_CONF"] = str(self.config)
        env.update(extra)
        return env

    def run(self, *command: str, check: bool = True, cwd: Path | None = None, env=None):
        """A client command (``sbatch``, ``scontrol`` …) against this cluster."""
        result = subprocess.run(
            command,
            cwd=cwd,
            env=env or self.environment(),
            capture_output=True,
            text=True,
            timeout=60,
        )
        if check and result.returncode != 0:
            raise RuntimeError(f"{' '.join(command)}: exit {result.returncode}\n{result.stderr}")
        return result

    def job(self, job_id: int) -> dict[str, str]:
        """The fields of ``scontrol show job`` (JobState, ExitCode, Restarts, …)."""
        text = self.run("scontrol", "show", "job", "-o", str(job_id)).stdout
        return dict(field.split("=", 1) for field in text.split() if "=" in field)

    def wait_until_finished(self, job_id: int, timeout: float) -> dict[str, str]:
        """The job's fields once it ended for good (not pending, running or requeued)."""
        deadline = time.monotonic() + timeout
        while True:
            fields = self.job(job_id)
            state = fields.get("JobState", "")
            if state in FINAL_STATES:
                return fields
            if time.monotonic() > deadline:
                raise TimeoutError(f"job {job_id} still {state} after {timeout:g} s")
            time.sleep(0.5)

    def completions(self) -> list[dict[str, str]]:
        """Every end of a job run so far (jobcomp/filetxt), requeued runs included."""
        path = self.root / "log" / "jobcomp.txt"
        if not path.exists():
            return []
        return [
            dict(field.split("=", 1) for field in line.split() if "=" in field)
            for line in path.read_text().splitlines()
        ]
