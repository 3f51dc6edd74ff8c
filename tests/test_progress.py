"""Progress that tells the truth: failed and interrupted cases are counted as such, the ETA
covers the running and waiting cases, and the last status line agrees with the closing
summary — on a clock we drive, and in a real run stopped by a real SIGINT (Ctrl-C).
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys

import pytest

from engine.study.examples import study_toml
from tests.test_cli import REPO, Case, Outcome, _reporter


def test_failed_and_interrupted_cases_are_not_counted_as_completed():
    todo = [Case("a", 1.0), Case("b", 1.0), Case("c", 1.0), Case("d", 1.0)]
    reporter, clock, out, err = _reporter(todo, ranks=2)
    reporter.started("a", 0)
    reporter.started("b", 1)
    clock.now += 10.0
    reporter.update(Outcome("a", status="failed", runtime_s=10.0, message="diverged\nmore"))
    assert out.getvalue().rstrip().endswith("failed: diverged")
    assert err.getvalue().splitlines()[-1].startswith("progress: 0/4 cases completed, 1 failed;")
    reporter.started("c", 0)
    clock.now += 10.0
    reporter.update(Outcome("b", runtime_s=20.0, rank=1))
    line = err.getvalue().splitlines()[-1]
    assert line.startswith("progress: 1/4 cases completed, 1 failed; running: c (rank 0, 10 s)")
    assert "ETA " in line  # c runs, d waits
    clock.now += 1.0
    reporter.update(Outcome("c", status="interrupted", runtime_s=11.0))
    line = err.getvalue().splitlines()[-1]
    # stopped: d never starts, so there is no ETA, and nothing reads "4/4" or "done"
    assert line.startswith("progress: 1/4 cases completed, 1 failed, 1 interrupted;")
    assert line.endswith("; stopping, 1 not started")


def test_eta_counts_the_waiting_cases_when_the_running_ones_are_overdue():
    # One rank, 40 s per unit of cost (from "a"). "b" has run 100 s against 40 s predicted
    # and reported cycle 2,500 of 10,000: 300 s more by extrapolation; "c" and "d" still wait
    # (40 s each): ETA 380 s, never 0 while cases remain.
    todo = [Case("a", 1.0), Case("b", 1.0), Case("c", 1.0), Case("d", 1.0)]
    reporter, clock, _, err = _reporter(todo, ranks=1)
    reporter.started("a", 0)
    clock.now += 40.0
    reporter.update(Outcome("a", runtime_s=40.0))
    reporter.started("b", 0)
    reporter.cycle("b", 0, 2500, 10000)
    clock.now += 100.0
    assert reporter.eta_seconds() == pytest.approx(380.0)
    assert reporter.status_text().endswith("ETA 6 min 20 s")


def test_an_overdue_case_without_cycle_reports_makes_the_eta_a_lower_bound():
    # A static case reports no cycles: past its prediction its remaining time is unknown, so
    # the ETA covers the waiting case (40 s) and says it is a lower bound.
    todo = [Case("a", 1.0), Case("b", 1.0), Case("c", 1.0)]
    reporter, clock, _, _ = _reporter(todo, ranks=1)
    reporter.started("a", 0)
    clock.now += 40.0
    reporter.update(Outcome("a", runtime_s=40.0))
    reporter.started("b", 0)
    clock.now += 90.0
    assert reporter.overdue() == ["b"]
    text = reporter.status_text()
    assert text.endswith("ETA more than 40 s (1 case running past the estimate)"), text


# ----------------------------------------------------------------------------- a real Ctrl-C
STUDY = study_toml(
    "stopped",
    "stopped.h5",
    mesh={"n": 24},
    loading={"cycles": 100000, "record": [100000], "max_wear_fraction": 0.02},
    sweep={"mu1": [0.4, 0.2, 0.1], "wear1": [1.33e-7]},
)


def test_ctrl_c_counts_the_stopped_case_as_interrupted(tmp_path):
    """SIGINT (what Ctrl-C sends) after the first finished case: the last status line counts
    1 completed, 1 interrupted and 1 not started, as the closing summary does (1 completed,
    0 failed, 2 not completed), and the exit code is 3 (rerun to resume). About 10 s."""
    (tmp_path / "study.toml").write_text(STUDY)
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    process = subprocess.Popen(
        [sys.executable, "-m", "engine", "study.toml", "--progress-interval", "0.5"],
        cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    lines = []
    for line in process.stdout:  # the first finished case, then Ctrl-C
        lines.append(line)
        if line.startswith("[1/3]"):
            process.send_signal(signal.SIGINT)
            break
    out, err = process.communicate(timeout=120)
    stdout = "".join(lines) + out
    assert process.returncode == 3, stdout + err
    status = [line for line in err.splitlines() if line.startswith("progress: ")]
    last = status[-1]
    assert last.startswith("progress: 1/3 cases completed, 1 interrupted;"), err
    assert last.endswith("stopping, 1 not started"), err
    assert not any(re.match(r"progress: [23]/3 cases", line) for line in status)
    assert "ETA 0 s" not in err
    assert "1 completed, 0 failed, 2 not completed" in stdout
    assert re.search(r"\[1/3\] mu0\.2_\S+ +rank 0 .* interrupted", stdout), stdout  # k: completed
