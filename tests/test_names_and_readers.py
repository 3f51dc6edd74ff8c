"""Hostile names and shapes are refused before anything is created (exit 2), and readers of a
results file that a run is writing get one line saying so instead of an HDF5 error.

Names: an output name too long for the lock, temporary or salvage names the engine derives
from it; control characters in the output path or the study name; study files nested too
deeply or too large; ``x.h5`` beside ``x.hdf5`` (both would write ``x.csv``).
Readers: ``engine.open_results``, ``report``, ``plot`` and ``verify`` on a file whose lock a
live run holds, or that another process holds open for writing; ``verify`` on paths that are
not results files.
"""

from __future__ import annotations

import os
import re
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

import engine
from engine.analysis import figures, report
from engine.output import verify
from engine.output.lock import derived_names, lock_path_for
from engine.output.owner import ResultsBeingWritten, start_ticks
from engine.study.config import parsing
from engine.study.examples import study_toml

REPO = Path(__file__).resolve().parents[1]


def text(name: str = "n", output: str = "n.h5") -> str:
    """A one-case static study (n = 8: a fraction of a second)."""
    loading = {"kind": "static", "steps": 2}
    return study_toml(name, output, mesh={"n": 8}, loading=loading, sweep={"mu1": [0.3]})


def refused(tmp_path, monkeypatch, study: str, **options) -> str:
    """Run ``study`` in an empty folder: it must be refused as bad input with nothing
    created; returns the message."""
    folder = tmp_path / "run"
    folder.mkdir()
    monkeypatch.chdir(folder)
    run = engine.run_study(study, progress=False, check=False, **options)
    assert run.status == "invalid", run
    assert os.listdir(folder) == [], "a refused study created files"
    assert "\n" not in run.message and len(run.message) < 400
    return run.message


def test_an_output_name_too_long_for_its_derived_names(tmp_path, monkeypatch):
    """NAME_MAX is 255 bytes here: the longest derived name (the stale lock with a 7-digit
    pid) adds 20 bytes, so a 236-byte name is the longest accepted."""
    limit = os.pathconf(tmp_path, "PC_NAME_MAX")
    extra = max(len(name) for name in derived_names(Path("x.h5"))) - len("x.h5")
    longest = "a" * (limit - extra - 3) + ".h5"
    message = refused(tmp_path, monkeypatch, text(output=longest[1:] + "a.h5"))
    assert f"use an output name of at most {len(longest)} bytes" in message
    monkeypatch.chdir(tmp_path)
    run = engine.run_study(text(output=longest), progress=False)
    assert run.ok, run


def test_control_characters_in_names(tmp_path, monkeypatch):
    message = refused(tmp_path, monkeypatch, text(name="a\x00b"))
    assert "[study] name 'a\\x00b': contains the control character U+0000" in message
    (tmp_path / "run").rmdir()
    message = refused(tmp_path, monkeypatch, text(output="a\nb.h5"))
    assert "output 'a\\nb.h5': contains the control character U+000A" in message


def test_study_files_nested_too_deeply_or_too_large(tmp_path, monkeypatch):
    deep = text() + "x = " + "[" * 5000 + "]" * 5000 + "\n"  # tomllib: RecursionError
    assert "nested more than 16 levels deep" in refused(tmp_path, monkeypatch, deep)
    (tmp_path / "run").rmdir()
    dotted = text() + "[" + ".".join(["a"] * 40) + "]\nb = 1\n"  # parses, but 40 levels
    assert "nested more than 16 levels deep" in refused(tmp_path, monkeypatch, dotted)
    monkeypatch.setattr(parsing, "MAX_STUDY_BYTES", 1000)
    path = tmp_path / "big.toml"
    path.write_text(text() + "#" * 2000 + "\n")
    with pytest.raises(parsing.StudyConfigError, match=r"bytes: a study file is at most"):
        parsing.load_study(path)


def test_x_h5_and_x_hdf5_never_share_a_summary(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    first = engine.run_study(text(output="x.h5"), progress=False)
    assert first.ok, first
    summary = (tmp_path / "x.csv").read_bytes()
    second = engine.run_study(text(name="other", output="x.hdf5"), progress=False, check=False)
    assert second.status == "invalid"
    assert "x.h5 is beside it and both would write the summary x.csv" in second.message
    assert not (tmp_path / "x.hdf5").exists() and (tmp_path / "x.csv").read_bytes() == summary


# ------------------------------------------------------------------------ live readers
@pytest.fixture(scope="module")
def results(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("results")
    with pytest.MonkeyPatch.context() as monkeypatch:
        monkeypatch.chdir(folder)
        run = engine.run_study(text(), progress=False)
    assert run.ok, run
    return folder / "n.h5"


def test_a_file_whose_run_is_alive_is_named_as_being_written(results, capsys):
    """A live process of this host holds the lock (this test's own process, as a run's rank
    0 would): every reader says so in one line, exit 2 for the commands."""
    lock = lock_path_for(results)
    lock.write_text(f"{os.getpid()} {socket.gethostname()} {start_ticks(os.getpid())}\n")
    try:
        with pytest.raises(ResultsBeingWritten) as error:
            engine.open_results(results)
        line = str(error.value)
        assert line.startswith(f"{results}: being written by a run (pid {os.getpid()}, host ")
        assert "engine.load_summary(" in line and "\n" not in line
        for command in (report.main, figures.main, verify.main):
            assert command([str(results)]) == 2
            err = capsys.readouterr().err
            assert err.count("\n") == 1 and "being written by a run" in err, err
    finally:
        lock.unlink()
    assert engine.open_results(results).statuses  # the lock gone: read as usual


def test_a_file_held_open_for_writing_by_another_process(results, tmp_path):
    """No lock of this engine, but HDF5's own file locking refuses the reader: one line, and
    the writer goes on undisturbed (it writes and closes the file after the reader failed)."""
    copy = tmp_path / "held.h5"
    copy.write_bytes(results.read_bytes())
    holder = subprocess.Popen(
        [sys.executable, "-c",
         "import sys, time, h5py\n"
         f"f = h5py.File({str(copy)!r}, 'a'); print('open', flush=True); sys.stdin.readline()\n"
         "f.attrs['touched'] = 1; f.close(); print('closed', flush=True)"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert holder.stdout.readline().strip() == "open"
        with pytest.raises(ResultsBeingWritten, match="another process holds it open"):
            engine.open_results(copy)
        out, _ = holder.communicate("go\n", timeout=60)
    finally:
        holder.kill()
    assert out.strip() == "closed" and holder.returncode == 0
    time.sleep(0)  # the file is closed: readable again
    assert engine.open_results(copy).statuses


def test_verify_on_paths_that_are_not_results_files(results, tmp_path, capsys):
    """Exit 2 (bad input) for a directory, a study file and a CSV; 4 stays for damage."""
    study = tmp_path / "s.toml"
    study.write_text(text())
    for path, words in (
        (tmp_path, "a directory, not a results file"),
        (study, "is a study file; its results:"),
        (results.with_suffix(".csv"), "the summary table (CSV) of a study"),
        (tmp_path / "none.h5", "no such file"),
    ):
        assert verify.main([str(path)]) == 2
        assert words in capsys.readouterr().err
    damaged = tmp_path / "damaged.h5"
    data = bytearray(results.read_bytes())
    data[:4096] = bytes(4096)  # the superblock zeroed: damage, not a wrong kind of file
    damaged.write_bytes(bytes(data))
    assert verify.main([str(damaged), "--no-summary"]) == 4


# ------------------------------------------------------------------ bounds of the physics
def test_a_refused_long_list_prints_one_short_line():
    """A list of 10^5 values where a number belongs: the message shows its ends and size."""
    study = text().replace("steps = 2", "steps = [" + ", ".join(["1"] * 100_000) + "]")
    with pytest.raises(parsing.StudyConfigError) as error:
        parsing.parse_study(study)
    message = str(error.value)
    assert "\n" not in message and len(message) < 400, len(message)
    assert "100000 items" in message and "[loading] steps" in message


def test_plane_step_is_bounded_by_what_can_run():
    from engine.fatigue.quantities import MIN_PLANE_STEP, check_plane_step

    assert check_plane_step(MIN_PLANE_STEP) == 0.1  # 1800 planes
    for step in (1e-6, 0.05, 0.0, 91.0, 0.7):  # too fine, zero, too coarse, not dividing 180
        with pytest.raises(ValueError, match=r"plane_step must divide 180 degrees"):
            check_plane_step(step)


def test_a_solver_tolerance_float64_cannot_reach_is_refused():
    for tol in (1e-20, 1e-300):
        with pytest.raises(parsing.StudyConfigError, match=r"\[solver\] tol = 1e-\d+: must lie"):
            parsing.parse_study(text() + f"\n[solver]\ntol = {tol}\n")
    parsing.parse_study(text() + "\n[solver]\ntol = 1e-16\n")


def test_search_targets_a_column_never_takes_are_refused():
    from engine.study.search import parse_search

    base = {"parameter": "loading.amplitude", "low": 1e-4, "high": 1e-2, "rtol": 0.01}
    parse_search("s.toml", {**base, "column": "slip_regime", "target": "gross"})
    for column, target, words in (
        ("slip_regime", "sliding", "slip_regime takes only 'partial', 'gross'"),
        ("peak_region", "corner", "peak_region takes only 'edge-surface'"),
        ("matvecs", -3, "matvecs counts (≥ 0)"),
        ("stick_fraction", 1.5, "stick_fraction is a fraction, in [0, 1]: never reached"),
        ("stick_fraction", -0.1, "stick_fraction is a fraction"),
        ("q_amplitude", -1.0, "q_amplitude is a size, never negative"),
        ("vm_max", -5.0, "vm_max is a von Mises stress, never negative"),
        ("vm_sub_max_z", -0.01, "vm_sub_max_z is a depth below the surface"),
    ):
        with pytest.raises(parsing.StudyConfigError, match=re.escape(words)):
            parse_search("s.toml", {**base, "column": column, "target": target})
    for column, target in (("stick_fraction", 0.0), ("stick_fraction", 1.0), ("vm_max_x", -1.0)):
        parse_search("s.toml", {**base, "column": column, "target": target})  # reachable


def test_a_line_contact_slides_along_x_only():
    from engine.study.examples import CYLINDER_ON_STEEL
    from engine.study.feasibility import ImpossibleCases, check_feasible
    from engine.study.plan import make_plan

    def study(direction):
        return parsing.parse_study(
            study_toml(
                "line", "line.h5", CYLINDER_ON_STEEL,
                loading={"kind": "fretting", "load": 185.0, "amplitude": 0.001,
                         "direction": direction},
                sweep={"mu1": [0.6], "alpha": [5e-6]}, wear={"law": "energy"},
            )
        )  # fmt: skip

    config = study(0.0)
    check_feasible(config, make_plan(config))
    config = study(90.0)
    with pytest.raises(ImpossibleCases, match=r"direction = 90°: a line contact \(cylinder"):
        check_feasible(config, make_plan(config))
