"""The command line as a newcomer meets it: help, dry runs, progress with an ETA, output paths.

The progress display is tested with a fake clock (no waiting); one tiny study (16 × 16 mesh,
two cyclic cases, ~3 s) is run for real on one rank through ``python -m engine`` with stderr
captured (not a terminal, as under ``mpiexec``/``srun``). tests/mpi/test_progress_mpi.py runs
the two-rank version.
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
import pytest

import engine
from engine.cli import build_parser
from engine.dry_run import idle_ranks_warning as _idle_ranks_warning
from engine.dry_run import resumed_cases_line
from engine.output.progress import ProgressReporter, format_duration, plural
from engine.study.examples import study_toml

REPO = Path(__file__).resolve().parents[1]

# Cyclic, 16 x 16, two cases; the output is relative: taken from the working directory.
TINY = study_toml("tiny", "out/tiny.h5", sweep={"mu1": [0.1, 0.4], "wear1": [1.33e-7]})


def _engine(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run(
        [sys.executable, "-m", "engine", *args],
        cwd=cwd, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip


# ----------------------------------------------------------------------------- help, words
def test_help_lists_the_subcommands_and_the_path_rule():
    text = build_parser("python -m engine").format_help()
    assert "python -m engine plot RESULTS.h5" in text
    assert "python -m engine report RESULTS.h5" in text
    words = " ".join(text.split())  # the epilog is wrapped
    assert "is written from the working directory" in words
    assert "are found from the folder of the study file" in words


def test_the_version_loads_neither_numpy_nor_the_plug_ins():
    # the help names the registered kinds and shapes; --version needs none of them
    done = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "engine", "--version"],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert done.returncode == 0 and engine.__version__ in done.stdout, done.stderr
    imported = {line.split("|")[-1].strip() for line in done.stderr.splitlines() if "|" in line}
    assert "engine.cli" in imported
    assert not {"numpy", "engine.study.kinds", "engine.geometry"} & imported
    assert "[loading] kind:" in build_parser("python -m engine").format_help()


def test_dry_run_combines_with_fresh_and_resume():
    parser = build_parser()
    assert parser.parse_args(["s.toml", "--dry-run", "--fresh"]).fresh is True
    assert parser.parse_args(["s.toml", "--dry-run", "--resume"]).fresh is False
    with pytest.raises(SystemExit):
        parser.parse_args(["s.toml", "--fresh", "--resume"])


def test_plural_and_durations():
    assert (plural(1, "case"), plural(0, "case"), plural(2, "rank")) == (
        "1 case", "0 cases", "2 ranks",
    )  # fmt: skip
    assert format_duration(42.4) == "42 s"
    assert format_duration(185) == "3 min 05 s"
    assert format_duration(7625) == "2 h 07 min"


def test_idle_ranks_warning():
    assert _idle_ranks_warning(cases=3, ranks=2) is None
    assert _idle_ranks_warning(cases=0, ranks=4) is None  # nothing to run: said elsewhere
    text = _idle_ranks_warning(cases=1, ranks=4)
    assert text.startswith("warning: 4 ranks for 1 case to run: 3 ranks will stay idle")


def test_a_resumed_run_names_the_cases_that_continue_from_their_checkpoints(tmp_path):
    """A requeued or resubmitted run says which cases are not started over."""
    ids = [f"c{index}" for index in range(12)]
    assert resumed_cases_line(tmp_path, ids) is None  # none saved: no line
    (tmp_path / "c3.npz").touch()
    (tmp_path / "c3.json").touch()  # the time spent, not a state
    assert resumed_cases_line(tmp_path, ids) == (
        f"1 case continues from its checkpoint ({tmp_path}): c3"
    )
    for index in range(10):
        (tmp_path / f"c{index}.npz").touch()
    assert resumed_cases_line(tmp_path, ids) == (
        f"10 cases continue from their checkpoints ({tmp_path}): c0, c1, c2, c3, c4, c5, c6, c7 …"
    )
    assert resumed_cases_line(tmp_path, ["c11"]) is None  # only the cases to run now


# ----------------------------------------------------------------------------- progress
@dataclass
class Case:
    case_id: str
    expected_cost: float


@dataclass
class Outcome:
    case_id: str
    status: str = "completed"
    runtime_s: float = 0.0
    rank: int = 0
    message: str = ""


class Clock:
    def __init__(self):
        self.now = 1000.0

    def __call__(self):
        return self.now


def _reporter(todo, ranks=2, interval=30.0, measured=()):
    clock, out, err = Clock(), io.StringIO(), io.StringIO()
    reporter = ProgressReporter(
        len(todo), 0, todo=todo, ranks=ranks, measured=measured, stream=out,
        status_stream=err, bar=False, interval=interval, clock=clock,
    )  # fmt: skip
    return reporter, clock, out, err


def test_status_lines_every_interval_and_after_each_case():
    todo = [Case("a", 1.0), Case("b", 1.0), Case("c", 1.0)]
    reporter, clock, out, err = _reporter(todo)
    reporter.started("a", 0)
    reporter.started("b", 1)
    reporter.cycle("b", 1, 3000, 100000)
    clock.now += 29.0
    reporter.tick()
    assert err.getvalue() == ""  # not yet 30 s
    clock.now += 1.0
    reporter.tick()
    line = err.getvalue().strip()
    assert line.startswith("progress: 0/3 cases completed; running: a (rank 0, 30 s), ")
    assert "b cycle 3,000/100,000 (rank 1, 30 s)" in line
    assert line.endswith("elapsed 30 s; ETA after the first completed case")
    clock.now += 10.0
    reporter.tick()  # 10 s after the last line: nothing
    assert err.getvalue().count("\n") == 1
    reporter.update(Outcome("a", runtime_s=40.0, rank=0))
    assert out.getvalue().startswith("[1/3] a ")
    assert err.getvalue().count("\n") == 2  # a status line after each finished case


def test_eta_from_measured_costs_and_free_ranks():
    # Two ranks. "a" (cost 1) took 40 s: 40 s per unit of cost. "b" (cost 2, 80 s predicted)
    # has run 40 s on rank 1; rank 0 is free and takes "c" (cost 1, 40 s) then "d" (cost 0.5,
    # 20 s): rank 0 is done in 60 s, rank 1 in 40 s -> ETA 60 s.
    todo = [Case("a", 1.0), Case("b", 2.0), Case("c", 1.0), Case("d", 0.5)]
    reporter, clock, _, _ = _reporter(todo)
    reporter.started("a", 0)
    reporter.started("b", 1)
    clock.now += 40.0
    reporter.update(Outcome("a", runtime_s=40.0))
    assert reporter.seconds_per_cost() == pytest.approx(40.0)
    assert reporter.eta_seconds() == pytest.approx(60.0)
    # 100 s later "b" has outrun its prediction: it counts as about to finish (never as a
    # negative time), so "d" (20 s) goes to rank 1 while "c", just started, needs 40 s.
    clock.now += 100.0
    reporter.started("c", 0)
    assert reporter.eta_seconds() == pytest.approx(40.0)


def test_eta_of_a_long_queue_is_the_balanced_load_within_one_case():
    # Beyond EXACT_QUEUE waiting cases the ETA shares the queue out as divisible work (O(1)
    # per finished case instead of O(queue)); greedy dispatch finishes at most one case later.
    import heapq

    from engine.output.progress import EXACT_QUEUE

    costs = [1.0 + (k % 7) / 7 for k in range(EXACT_QUEUE + 50)]
    todo = [Case(f"c{k}", cost) for k, cost in enumerate(costs)]
    reporter, clock, _, _ = _reporter(todo, ranks=3)
    for k in range(3):
        reporter.started(f"c{k}", k)
    clock.now += 2.0
    reporter.update(Outcome("c0", runtime_s=2.0))  # 2 s per unit of cost
    reporter.started("c3", 0)
    free_at = [max(2.0 * costs[k] - elapsed, 0.0) for k, elapsed in ((1, 2.0), (2, 2.0), (3, 0))]
    heapq.heapify(free_at)
    for cost in costs[4:]:
        heapq.heappush(free_at, heapq.heappop(free_at) + 2.0 * cost)
    eta = reporter.eta_seconds()
    assert max(free_at) - 2.0 * max(costs) <= eta <= max(free_at)


def test_earlier_runs_measure_the_cost_before_any_case_of_this_run():
    reporter, *_ = _reporter([Case("b", 1.0)], ranks=1, measured=[(30.0, 1.0)])
    assert reporter.eta_seconds() == pytest.approx(30.0)


def test_late_reports_of_a_finished_case_are_ignored():
    reporter, *_ = _reporter([Case("a", 1.0), Case("b", 1.0)])
    reporter.started("a", 1)
    reporter.update(Outcome("a", runtime_s=5.0, rank=1))
    reporter.cycle("a", 1, 100, 200)  # sent before the result, received after it
    assert "running" not in reporter.status_text()


# ----------------------------------------------------------------------------- a real run
@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """The tiny study run from a working directory other than the study file's folder."""
    root = tmp_path_factory.mktemp("cli")
    (root / "studies").mkdir()
    (root / "studies" / "tiny.toml").write_text(TINY)
    (root / "out" / "tiny.h5.checkpoints").mkdir(parents=True)  # left over by an earlier run
    run = _engine("studies/tiny.toml", "--progress-interval", "1", cwd=root)
    assert run.returncode == 0, run.stdout + run.stderr
    return root, run


def test_relative_output_is_taken_from_the_working_directory(tiny_run):
    root, _ = tiny_run
    assert (root / "out" / "tiny.h5").exists()
    assert not (root / "studies" / "out").exists()


def test_progress_lines_without_a_terminal(tiny_run):
    _, run = tiny_run
    assert "2 cases, 0 already complete, 2 to run on 1 rank ->" in run.stdout
    lines = [line for line in run.stderr.splitlines() if line.startswith("progress: ")]
    assert lines, run.stderr
    assert lines[-1].startswith("progress: 2/2 cases completed;") and lines[-1].endswith("finished")
    assert any("1/2 cases completed" in line and "ETA " in line for line in lines)
    assert "\r" not in run.stderr  # no bar drawn into a file


def test_csv_equals_load_summary_and_has_no_negative_zero(tiny_run):
    root, _ = tiny_run
    from_h5 = engine.load_summary(root / "out" / "tiny.h5")
    from_csv = engine.load_summary(root / "out" / "tiny.csv")
    pd.testing.assert_frame_equal(from_h5, from_csv, check_exact=True)
    assert len(from_h5) == 2
    assert "-0.0," not in (root / "out" / "tiny.csv").read_text()


def test_empty_checkpoint_folder_is_removed(tiny_run):
    root, _ = tiny_run
    assert not (root / "out" / "tiny.h5.checkpoints").exists()


def test_dry_run_shows_what_resume_and_fresh_would_do(tiny_run):
    root, _ = tiny_run
    before = (root / "out" / "tiny.h5").read_bytes()
    resume = _engine("studies/tiny.toml", "--dry-run", cwd=root)
    assert resume.returncode == 0, resume.stderr
    assert "would run 0 cases on 1 rank; 2 complete and skipped" in resume.stdout
    assert resume.stdout.count("complete: skip") == 2
    assert f"= {root / 'out' / 'tiny.h5'}" in resume.stdout  # the resolved path
    fresh = _engine("studies/tiny.toml", "--dry-run", "--fresh", cwd=root)
    assert fresh.returncode == 0, fresh.stderr
    assert "--fresh would delete: out/tiny.h5, out/tiny.csv" in fresh.stdout
    assert "would run 2 cases on 1 rank; 0 complete and skipped" in fresh.stdout
    assert (root / "out" / "tiny.h5").read_bytes() == before  # a dry run changes nothing


def test_a_static_study_stored_in_its_results_runs_again(tmp_path):
    # The study stored in a results file is a study file: a static one once held cycles = 0
    # and record = [], which the parser refuses for static loading. Files written that way
    # still resume (the placeholders are taken out before the comparison).
    import json

    import h5py

    from engine.study.config import parse_study

    text = study_toml("static", "s.h5", loading={"kind": "static", "steps": 1})
    (tmp_path / "s.toml").write_text(text)
    assert _engine("s.toml", cwd=tmp_path).returncode == 0
    with h5py.File(tmp_path / "s.h5", "r") as file:
        stored = str(file.attrs["study_toml"])
    assert "cycles" not in stored and "record" not in stored
    assert parse_study(stored).fingerprint() == parse_study(text).fingerprint()
    former = stored.replace("[loading]\n", "[loading]\ncycles = 0\nrecord = []\n")
    assert parse_study(former).fingerprint() == parse_study(text).fingerprint()
    with pytest.raises(ValueError, match=r"\[loading\] cycles = 5: unknown key"):
        parse_study(former.replace("cycles = 0", "cycles = 5"))
    with h5py.File(tmp_path / "s.h5", "r+") as file:  # as earlier versions wrote it
        for name in ("study_json", "study_identity", "study_fingerprint"):
            data = json.loads(file.attrs[name])
            data["loading"].update(cycles=0, record=[])
            file.attrs[name] = json.dumps(data, sort_keys=True)
        del file.attrs["metadata_checksum"]  # earlier versions wrote none
    again = _engine("s.toml", cwd=tmp_path)
    assert again.returncode == 0, again.stdout + again.stderr
    assert "1 case, 1 already complete, 0 to run" in again.stdout


# ----------------------------------------------------------------------------- the README
def test_readme_study_is_valid_and_the_readme_fits_on_a_screen():
    from engine.study.config import parse_study
    from engine.study.plan import make_plan

    readme = (REPO / "README.md").read_text()
    assert len(readme.splitlines()) <= 200
    block = readme.split("```toml\n", 1)[1].split("```", 1)[0]
    assert len(block.strip().splitlines()) <= 10
    config = parse_study(block, source="README.md")
    assert len(make_plan(config)) == 6
    for link in ("index", "tutorials/first-study", "reference/study-file", "reference/outputs",
                 "explanation/validation", "explanation/performance", "how-to/slurm"):  # fmt: skip
        assert f"(docs/{link}.md)" in readme
        assert (REPO / "docs" / f"{link}.md").exists()


def test_results_doc_has_a_block_for_every_study_of_the_results_script():
    script = (REPO / "scripts" / "results.sh").read_text()
    results = (REPO / "docs" / "explanation" / "results.md").read_text()
    studies = script.split('studies=${STUDIES:-"', 1)[1].split('"}', 1)[0].replace("\\\n", " ")
    assert len(studies.split()) == 5
    for study in studies.split():
        assert (REPO / "studies" / f"{study}.toml").exists()
        assert f"<!-- BEGIN report {study} -->" in results
        assert f"<!-- END report {study} -->" in results
    assert "--update docs/explanation/results.md" in script


def test_every_run_status_exits_with_a_code_the_manual_describes():
    """engine.exit_codes is the one definition: each status of a run maps to one of its
    codes, each code of a study run is reachable, and the help's epilog says them all."""
    from engine import exit_codes
    from engine.cli import EXIT_CODES
    from engine.run import RUN_STATUSES

    described = {meaning.code for meaning in exit_codes.STUDY_RUN}
    assert set(EXIT_CODES) == set(RUN_STATUSES)
    assert set(EXIT_CODES.values()) | {exit_codes.ExitCode.INTERNAL} == described
    epilog = " ".join(build_parser().epilog.split())
    for meaning in exit_codes.STUDY_RUN:
        assert f"{meaning.code.value} {meaning.short}" in epilog


SECOND_SIGNAL = """
import os, signal, sys
from engine import cli
from engine._stop_flag import StopFlag
import engine._early_stop as early

class SecondSignalInside(StopFlag):
    sent = False

    def set(self):  # a second SIGTERM arrives while the flag is being set
        if not SecondSignalInside.sent:
            SecondSignalInside.sent = True
            os.kill(os.getpid(), signal.SIGTERM)
            sum(range(10000))  # bytecodes: the nested handler runs among them
        super().set()

flag = SecondSignalInside()
cli._install_stop_handlers(flag)
cli._STOP_STATE["rank"] = 0
os.kill(os.getpid(), signal.SIGTERM)
assert flag.is_set() and SecondSignalInside.sent
assert isinstance(early.STOP, StopFlag)  # the flag python -m engine starts with
print("stopped")
"""


def test_a_second_stop_signal_inside_the_first_never_hangs():
    """The stop handler runs between two bytecodes of the main thread, also inside the
    flag's own ``set`` (a second SIGTERM, e.g. forwarded by mpiexec): it takes no lock, so
    it cannot wait for one its own thread holds (a ``threading.Event`` hangs here)."""
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    done = subprocess.run(
        [sys.executable, "-c", SECOND_SIGNAL], capture_output=True, text=True, timeout=60,
        env=env,
    )  # fmt: skip
    assert done.returncode == 0 and done.stdout.strip() == "stopped", done.stderr
    assert "SIGTERM received" in done.stderr
