"""The header of every bundled study (``studies/*.toml``) gives the commands that run it in the
README's form — ``.venv/bin/python -m engine …`` or ``.venv/bin/mpiexec -n 2 .venv/bin/python
-m engine …`` from the repository's root — and each command works as written: the study
command names its own file and passes a dry run, ``plot``/``report`` parse and read the
study's output, scripts exist, ``python -c`` code compiles and names the engine's API."""

from __future__ import annotations

import re
import shlex
import tomllib
from pathlib import Path

import pytest

import engine
from engine import cli
from engine.analysis import figures, report
from engine.output import verify

REPO = Path(__file__).resolve().parents[1]
PYTHON = ".venv/bin/python"
MPIEXEC = [".venv/bin/mpiexec", "-n", "2", PYTHON]
STUDIES = sorted((REPO / "studies").glob("*.toml"))
# A command in a header comment, after an optional label ("Run:", "Then:", "Check:", "or");
# two spaces or more before a parenthesis start a remark.
COMMAND = re.compile(r"^#\s*(?:(?:Run|Then|Check|or):\s*)?((?:\.venv/bin/|python|mpiexec)\S*.*?)$")
OUTPUT_COMMANDS = {"plot": figures, "report": report, "verify": verify}


def _header(path: Path) -> list[str]:
    lines = path.read_text().splitlines()
    return lines[: next(i for i, line in enumerate(lines) if not line.startswith("#"))]


def _commands(path: Path) -> list[list[str]]:
    commands = []
    for line in _header(path):
        match = COMMAND.match(line)
        if match:
            text = re.split(r"\s{2,}\(", match.group(1))[0]
            commands.append(shlex.split(text))
    return commands


def test_the_readme_uses_the_form_the_headers_follow():
    readme = (REPO / "README.md").read_text()
    assert ".venv/bin/mpiexec -n 2 .venv/bin/python -m engine studies/demo.toml" in readme
    assert ".venv/bin/python -m engine plot RESULTS.h5" in readme


@pytest.mark.parametrize("path", STUDIES, ids=lambda path: path.name)
def test_the_header_commands_run_as_written(path, capsys, monkeypatch):
    commands = _commands(path)
    assert any("-m" in argv and path.name in " ".join(argv) for argv in commands), (
        f"{path.name}: no command that runs it"
    )
    output = tomllib.loads(path.read_text())["study"]["output"]
    monkeypatch.chdir(REPO)
    for argv in commands:
        if argv[: len(MPIEXEC)] == MPIEXEC:
            rest = argv[len(MPIEXEC) :]
        else:
            assert argv[0] == PYTHON, f"{path.name}: {shlex.join(argv)} is not in the README's form"
            rest = argv[1:]
        if rest[:2] == ["-m", "engine"] and rest[2] in OUTPUT_COMMANDS:
            args = OUTPUT_COMMANDS[rest[2]].build_parser().parse_args(rest[3:])
            results = args.results if isinstance(args.results, list) else [args.results]
            assert [str(item) for item in results] == [output], shlex.join(argv)
        elif rest[:2] == ["-m", "engine"]:
            args = cli.build_parser().parse_args(rest[2:])
            assert Path(args.study).resolve() == path, shlex.join(argv)
            assert cli.main([*rest[2:], "--dry-run"]) == 0, capsys.readouterr().err
        elif rest[0] == "-c":
            compile(rest[1], path.name, "exec")
            for name in re.findall(r"engine\.(\w+)", rest[1]):
                assert hasattr(engine, name), f"{path.name}: engine.{name}"
            assert output in rest[1], shlex.join(argv)
        else:
            assert (REPO / rest[0]).is_file(), shlex.join(argv)
            assert output in rest[1:], shlex.join(argv)
