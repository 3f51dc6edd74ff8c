"""The Python API: ``engine.run_study`` runs a study as ``python -m engine`` does.

A tiny cyclic study (8 x 8 mesh, 4 depth layers, two friction coefficients, 20 cycles with
one recorded; ~1 s a run) runs through both doors in this process, each in its own folder
with the same relative paths: the two results files and summaries must be the same bit for
bit (``scripts/compare_results.py``, run times aside, and the stored command line, which
names the door).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import engine
from engine.cli import main
from engine.study.config import parse_study
from engine.study.examples import study_toml

REPO = Path(__file__).resolve().parents[1]

TOML = study_toml(
    "api",
    "api.h5",
    mesh={"n": 8},
    subsurface={"layers": 4},
    loading={"kind": "cyclic", "load": 750.0, "steps": 2, "cycles": 20, "record": [10]},
    sweep={"mu1": [0.2, 0.4], "wear1": [1.33e-7]},
)


def _compare(first: Path, second: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [
            sys.executable,
            str(REPO / "scripts" / "compare_results.py"),
            str(first),
            str(second),
            "--ignore",
            "command_line",
        ],
        capture_output=True,
        text=True,
    )


def test_the_api_and_the_command_line_write_the_same_files(tmp_path, monkeypatch):
    for door in ("api", "cli"):
        (tmp_path / door).mkdir()
        (tmp_path / door / "api.toml").write_text(TOML)
    monkeypatch.chdir(tmp_path / "api")
    run = engine.run_study("api.toml", progress=False)
    monkeypatch.chdir(tmp_path / "cli")
    assert main(["api.toml", "--no-progress-bar"]) == 0
    assert (run.status, run.cases, run.completed, run.failed) == ("completed", 2, 2, 0)
    assert run.output == Path("api.h5") and run.ok
    for name in ("api.h5", "api.csv"):
        compared = _compare(tmp_path / "api" / name, tmp_path / "cli" / name)
        assert compared.returncode == 0, compared.stdout + compared.stderr
    monkeypatch.chdir(tmp_path / "api")
    assert list(run.summary["status"]) == ["completed", "completed"]


def test_text_or_configuration_in_and_resume(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    first = engine.run_study(TOML, progress=False)
    assert first.status == "completed"
    again = engine.run_study(parse_study(TOML), progress=False)
    assert (again.status, again.completed) == ("completed", 2)  # both skipped, still complete
    with pytest.raises(engine.StudyError, match="fresh=True"):
        engine.run_study(TOML, resume=False, progress=False)
    refused = engine.run_study(TOML, resume=False, progress=False, check=False)
    assert refused.status == "invalid" and "fresh=True" in refused.message
    fresh = engine.run_study(TOML, resume=False, fresh=True, output="other.h5", progress=False)
    assert fresh.status == "completed" and Path("other.h5").exists()


def test_bad_input_raises_naming_the_key_or_is_a_status(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    bad = TOML.replace("load = 750.0", "load = -750.0")
    with pytest.raises(engine.StudyError, match=r"\[loading\] load = -750.0") as raised:
        engine.run_study(bad, progress=False)
    assert raised.value.run.status == "invalid"
    run = engine.run_study(bad, progress=False, check=False)
    assert run.status == "invalid" and not run.ok
    assert "[loading] load = -750.0" in run.message
    assert not Path("api.h5").exists()
    with pytest.raises(ValueError, match="invalid"):
        run.summary  # noqa: B018 - the property raises


def test_a_dry_run_changes_nothing(tmp_path, monkeypatch, capsys, caplog):
    """The library prints nothing: the dry run's report is in the returned run and in the
    log (the logger ``engine.run``, which the command line shows)."""
    monkeypatch.chdir(tmp_path)
    with caplog.at_level("INFO", logger="engine"):
        run = engine.run_study(TOML, dry_run=True)
    assert (run.status, run.cases) == ("planned", 2)
    assert any(line.startswith("would run 2 cases") for line in run.plan)
    assert capsys.readouterr() == ("", "")
    assert [record.getMessage() for record in caplog.records] == list(run.plan)
    assert list(tmp_path.iterdir()) == []


def test_a_run_prints_nothing_and_logs_its_lines(tmp_path, monkeypatch, capsys, caplog):
    monkeypatch.chdir(tmp_path)
    with caplog.at_level("INFO", logger="engine"):
        run = engine.run_study(TOML, progress=False, progress_interval=0)
    assert run.status == "completed"
    assert capsys.readouterr().out == ""
    messages = [record.getMessage() for record in caplog.records]
    assert messages[0].startswith("study 'api': 2 cases, 0 already complete, 2 to run")
    assert messages[-1].startswith("study 'api': 2 completed, 0 failed")


def test_dir_engine_lists_the_public_api():
    """Every public name is listed and reached through the module's PEP 562 ``__getattr__``
    (imported on first use); an unknown name is an AttributeError."""
    for name in engine.__all__:
        assert name in dir(engine) and getattr(engine, name) is not None
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        engine.no_such_name  # noqa: B018


def test_import_engine_loads_no_layer():
    code = "import sys, engine; print(sorted(m for m in sys.modules if m.startswith('engine.')))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "['engine._version']", done.stdout
