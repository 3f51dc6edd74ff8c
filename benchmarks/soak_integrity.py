"""Soak: a 2,000-case study on 2 ranks under chaos, then checked against an undisturbed run.

The study (static cases at n = 8, about 10 ms of computing each; ``--cases`` of them) runs
under ``mpiexec -n RANKS`` on its own tmpfs, again and again (each run resumes the last),
while this script, for ``--minutes``, does at random moments one of:

- ``kill``: SIGKILL to one rank (the other must notice and end the job);
- ``term``: SIGTERM to every rank (as SLURM's pre-timeout signal): exit 3 expected;
- ``fill``: another process fills the tmpfs to 0 B free; exit 5 expected (or 0 if it had
  finished), the space freed after the run ended;
- ``damage`` (between two runs): 4 KiB of random bytes over a random block of the results
  file, a flipped bit, or the file truncated: the next run must find it and salvage.

After every faulted run it checks that the run ended within 30 s of the fault (else it
counts a hang and kills the job) and that every case the run printed as completed is
completed in the file (read in a child process with a time limit). A run that completes the
study is checked with ``verify``, and the next starts over with ``--fresh``. When the time
is up: space freed, the study is run to its end, the file verified and compared with the
undisturbed run (every case and its checksum: see :func:`differences`).

    python benchmarks/soak_integrity.py --minutes 10            # ~15 minutes here (root)
    python benchmarks/soak_integrity.py --cases 200 --minutes 1  # a quick look

Needs root (it mounts a tmpfs) and prints the load average with its figures.
"""

from __future__ import annotations

import argparse
import collections
import errno
import importlib.util
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PYTHON = str(Path(sys.executable))
MPIEXEC = str(Path(sys.executable).with_name("mpiexec"))
DEADLINE_S = 30.0  # s from a fault to the end of the run
OPTIONS = ("--no-progress-bar", "--progress-interval", "0")
COMPLETED_LINE = re.compile(r"^\[\s*\d+/\d+\] (\S+)\s+rank \d+\s+\S+ s\s+completed$", re.M)


def study_text(cases: int) -> str:
    """``cases`` static cases at n = 8 (one increment each), ``mu1 × beta``."""
    sys.path.insert(0, str(REPO))
    from engine.study.examples import study_toml

    columns = 40
    rows = max(1, cases // columns)
    mu1 = [round(0.05 + 0.9 * i / rows, 6) for i in range(rows)]
    beta = [round(90.0 * j / columns, 6) for j in range(columns)]
    return study_toml(
        "soak", "soak.h5", mesh={"n": 8}, subsurface={"layers": 2},
        loading={"kind": "static", "steps": 1}, sweep={"mu1": mu1, "beta": beta},
    )  # fmt: skip


# s for reading a results file in full (resume, verify): the engine allows 60 s, 1 s per 20 MB
# and 10 ms per dataset read (engine.output.isolated), about 860 s for a 2,000-case file
# (58 MB, 80,000 datasets); the soak fixes 900 s so that its runs do not depend on that rule.
INSPECTION_TIME_LIMIT = "900"


def environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    env["ENGINE_INSPECTION_TIME_LIMIT"] = INSPECTION_TIME_LIMIT
    return env


def command(ranks: int, *extra: str) -> list[str]:
    return [MPIEXEC, "-n", str(ranks), PYTHON, "-m", "engine", "soak.toml", *OPTIONS, *extra]


def run(directory: Path, ranks: int, *extra: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        command(ranks, *extra), cwd=directory, env=environment(), capture_output=True,
        text=True, timeout=3600,
    )  # fmt: skip


def rank_pids(directory: Path) -> list[int]:
    """Pids of the engine's rank processes running in ``directory`` (not ``mpiexec``: a
    signal goes to the ranks, as SLURM sends it to the tasks)."""
    pids = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            words = (entry / "cmdline").read_bytes().split(b"\0")
            rank = words[1:3] == [b"-m", b"engine"]  # python -m engine, not the launcher
            if rank and os.readlink(entry / "cwd") == str(directory):
                pids.append(int(entry.name))
        except OSError:
            continue
    return pids


def fill(directory: Path) -> Path:
    """A file in ``directory`` grown until the file system has 0 B free."""
    path = directory / "filler"
    with open(path, "ab", buffering=0) as handle:
        for size in (1 << 20, 4096, 1):
            block = b"\0" * size
            while True:
                try:
                    handle.write(block)
                except OSError as error:
                    if error.errno != errno.ENOSPC:
                        raise
                    break
    return path


def damage(path: Path, rng: random.Random) -> str:
    """Overwrite a 4 KiB block, flip a bit, or truncate ``path``; what was done."""
    size = path.stat().st_size
    if size < 8192:
        return "none"
    kind = rng.choice(["block", "bit", "truncate"])
    with open(path, "r+b") as handle:
        if kind == "block":
            handle.seek(rng.randrange(0, size - 4096))
            handle.write(rng.randbytes(4096))
        elif kind == "bit":
            offset = rng.randrange(0, size)
            handle.seek(offset)
            byte = handle.read(1)[0]
            handle.seek(offset)
            handle.write(bytes([byte ^ (1 << rng.randrange(8))]))
        else:
            handle.truncate(rng.randrange(size // 2, size))
    return kind


CHECK = """
import sys, h5py
printed = sys.argv[2:]
with h5py.File(sys.argv[1], "r") as file:
    cases = file["cases"]
    missing = [c for c in printed if cases[c].attrs.get("status") != "completed"]
print(len(missing))
"""


def missing_printed(directory: Path, printed: list[str]) -> int | None:
    """How many cases printed as completed are not completed in the file (None: the file
    cannot be read within 60 s, e.g. after a kill in the middle of a write)."""
    if not printed:
        return 0
    try:
        done = subprocess.run(
            [PYTHON, "-c", CHECK, str(directory / "soak.h5"), *printed],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        return None
    return int(done.stdout) if done.returncode == 0 and done.stdout.strip() else None


def differences(first: Path, second: Path) -> list[str]:
    """What differs between two results files that both pass ``verify``: the cases, and per
    case every attribute — the ``checksum`` (SHA-256 over every dataset's bytes, dtype and
    shape, which ``verify`` proved equal to the data) among them — and the root's attributes;
    run times, hosts and ranks ignored (``scripts/compare_results.py``'s ``RUN_DEPENDENT``).
    The same verdict as ``compare_results.py`` on verified files, in seconds instead of
    the tens of minutes its dataset-by-dataset walk takes for 2,000 cases on a loaded
    machine."""
    import h5py

    spec = importlib.util.spec_from_file_location(
        "compare_results", REPO / "scripts" / "compare_results.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    ignored = module.RUN_DEPENDENT
    found = []
    with h5py.File(first, "r") as a, h5py.File(second, "r") as b:
        found += module._compare_attributes("/", a, b, ignored)
        cases_a, cases_b = a["cases"], b["cases"]
        if set(cases_a) != set(cases_b):
            found.append(f"cases differ: {sorted(set(cases_a) ^ set(cases_b))[:5]}")
        for name in sorted(set(cases_a) & set(cases_b)):
            found += module._compare_attributes(
                f"/cases/{name}", cases_a[name], cases_b[name], ignored
            )
    return found


def verified(directory: Path) -> str:
    """ "" when ``verify`` finds the file whole, else its last lines."""
    done = subprocess.run(
        [PYTHON, "-m", "engine", "verify", "soak.h5"], cwd=directory, env=environment(),
        capture_output=True, text=True,
    )  # fmt: skip
    return "" if done.returncode == 0 else (done.stdout + done.stderr)[-600:]


class Soak:
    def __init__(self, directory: Path, reference: Path, ranks: int, rng: random.Random):
        self.directory, self.reference, self.ranks, self.rng = directory, reference, ranks, rng
        self.counts: collections.Counter = collections.Counter()
        self.exits: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
        self.end_times: dict[str, list[float]] = collections.defaultdict(list)
        self.problems: list[str] = []
        self.fresh = False
        self.longest = 30.0  # s: faults fall anywhere in a run's first half minute

    def one_run(self) -> None:
        """Start a run; a fault at a random moment (or none); wait; check."""
        extra = ("--fresh",) if self.fresh else ()
        self.fresh = False
        process = subprocess.Popen(
            command(self.ranks, *extra), cwd=self.directory, env=environment(),
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
        )  # fmt: skip
        self.counts["runs"] += 1
        action = self.rng.choices(["kill", "term", "fill", "none"], [3, 3, 3, 1])[0]
        delay = self.rng.uniform(0.5, self.longest)
        try:
            out, err = process.communicate(timeout=delay)
            action = "none"  # it ended before the fault
        except subprocess.TimeoutExpired:
            out = err = None
        filler = None
        if out is None:
            fault = time.monotonic()
            if action == "kill":
                pids = rank_pids(self.directory)
                if pids:
                    os.kill(self.rng.choice(pids), signal.SIGKILL)
            elif action == "term":
                for pid in rank_pids(self.directory):
                    os.kill(pid, signal.SIGTERM)
            elif action == "fill":
                filler = fill(self.directory)
            timeout = DEADLINE_S if action != "none" else 3600
            try:
                out, err = process.communicate(timeout=timeout)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                out, err = process.communicate()
                self.problems.append(f"run {self.counts['runs']}: {action}: no end in 30 s")
                self.counts["hangs"] += 1
            if action != "none":
                self.end_times[action].append(time.monotonic() - fault)
        if filler is not None:
            filler.unlink()
        self.counts[action] += 1
        code = process.returncode
        self.exits[action][code] += 1
        if action in ("term", "fill", "none") and "Traceback" in err:
            self.problems.append(f"run {self.counts['runs']}: {action}: traceback: {err[-500:]}")
        missing = missing_printed(self.directory, COMPLETED_LINE.findall(out))
        if missing is None:
            self.counts["unreadable after the run"] += 1
        elif missing:
            self.counts["printed completed, missing"] += missing
            self.problems.append(f"run {self.counts['runs']}: {action}: {missing} printed missing")
        if code == 0:
            self.round_complete()
        elif self.rng.random() < 0.25 and (self.directory / "soak.h5").exists():
            self.counts[f"damage {damage(self.directory / 'soak.h5', self.rng)}"] += 1

    def round_complete(self) -> None:
        """The study completed under chaos: does it verify? Then start over (the comparison
        with the undisturbed run, minutes for a large file, is made at the end)."""
        self.counts["completed rounds"] += 1
        failure = verified(self.directory)
        if failure:
            self.problems.append(f"run {self.counts['runs']}: verify: {failure}")
        self.fresh = True


def mount(directory: Path, size: str) -> None:
    directory.mkdir(parents=True)
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(directory)],
        capture_output=True, text=True,
    )  # fmt: skip
    if done.returncode != 0:
        sys.exit(f"cannot mount a tmpfs (needs root): {done.stderr.strip()}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=2000)
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--minutes", type=float, default=10.0, help="of chaos")
    parser.add_argument("--size", default="256m", help="of the tmpfs")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    work = Path(tempfile.mkdtemp(prefix="soak_"))
    reference, disk = work / "reference", work / "disk"
    reference.mkdir()
    mount(disk, args.size)
    try:
        text = study_text(args.cases)
        for folder in (reference, disk):
            (folder / "soak.toml").write_text(text)
        print(f"load average at the start: {os.getloadavg()[0]:.1f}", flush=True)
        start = time.monotonic()
        done = run(reference, args.ranks)
        if done.returncode != 0:
            sys.exit(f"the undisturbed run failed: {done.stderr}")
        undisturbed = time.monotonic() - start
        size = (reference / "soak.h5").stat().st_size
        print(f"undisturbed run: {args.cases} cases on {args.ranks} ranks in {undisturbed:.0f} s, "
              f"{size / 1e6:.1f} MB", flush=True)  # fmt: skip
        soak = Soak(disk, reference / "soak.h5", args.ranks, rng)
        end = time.monotonic() + 60.0 * args.minutes
        while time.monotonic() < end:
            soak.one_run()
        chaos = time.monotonic() - (end - 60.0 * args.minutes)
        final, tries = None, 0
        while tries < 5 and (final is None or final.returncode != 0):
            final, tries = run(disk, args.ranks), tries + 1
        failure = verified(disk)
        whole = not failure
        found = differences(reference / "soak.h5", disk / "soak.h5")
        same = not found
        print(f"load average at the end: {os.getloadavg()[0]:.1f}")
        print(f"chaos for {chaos / 60:.1f} min: {dict(soak.counts)}")
        for action, codes in sorted(soak.exits.items()):
            times = soak.end_times.get(action, [])
            longest = f"; longest end after the fault {max(times):.1f} s" if times else ""
            print(f"  {action}: exit codes {dict(sorted(codes.items(), key=str))}{longest}")
        verdict = "OK" if whole else "FAILED"
        print(f"final run: exit {final.returncode} after {tries} run(s); verify {verdict}; "
              f"identical to the undisturbed run: {same}")  # fmt: skip
        for problem in soak.problems + found[:10] + ([f"verify: {failure}"] if failure else []):
            print(f"problem: {problem}")
        if not (final.returncode == 0 and whole and same and not soak.problems):
            sys.exit(1)
    finally:
        subprocess.run(["umount", "-l", str(disk)], check=False)
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
