"""The user manual is checked like code: its tables render, its links resolve, the snippets of
its tutorials run, the API reference builds with warnings as errors, and the generated blocks
(reference tables, measured tables) carry their provenance.

Markdown tables are checked the way GitHub renders them: a table is a run of lines starting
with ``|`` whose second line is the delimiter row; every row has the header's number of cells
(cells are split at unescaped pipes). A table split by a stray line renders as plain text, so
a run of ``|`` lines without a delimiter row is an error too.

A tutorial snippet is runnable when the line before its fence is ``<!-- runnable -->``
(``bash`` and ``python`` blocks; the shell ones run with the package's interpreter first on
the PATH) or ``<!-- runnable: NAME -->`` (any block: its text is written to the file NAME
first). The snippets of one page run in order in one fresh folder, the Python ones in one
shared namespace, as a reader would type them.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
DOCS = REPO / "docs"
MARKDOWN = sorted(DOCS.rglob("*.md")) + [
    REPO / name
    for name in ("README.md", "CHANGELOG.md", "CONTRIBUTING.md", "benchmarks/HISTORY.md")
    if (REPO / name).exists()
]
TUTORIALS = sorted((DOCS / "tutorials").glob("*.md"))
FENCE = re.compile(r"^(```+|~~~+)")
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
HTML_SOURCE = re.compile(r"<(?:img|a)\s[^>]*?(?:src|href)=\"([^\"]+)\"")
RUNNABLE = re.compile(r"^<!-- runnable(?::\s*(\S+))? -->$")


def _relative(path: Path) -> str:
    return str(path.relative_to(REPO))


def _prose_lines(text: str) -> list[tuple[int, str]]:
    """(line number, line) outside fenced code blocks."""
    lines, fence = [], None
    for number, line in enumerate(text.splitlines(), 1):
        match = FENCE.match(line.strip())
        if fence is None and match:
            fence = match.group(1)[0]
        elif fence is not None and match and match.group(1)[0] == fence:
            fence = None
        elif fence is None:
            lines.append((number, line))
    return lines


def _cells(row: str) -> int:
    """Cells of a table row, split at pipes not escaped by a backslash."""
    row = row.strip()
    pipes = [i for i, char in enumerate(row) if char == "|" and (i == 0 or row[i - 1] != "\\")]
    count = len(pipes) + 1
    if row.startswith("|"):
        count -= 1
    if row.endswith("|") and not row.endswith("\\|"):
        count -= 1
    return count


def _tables(text: str) -> list[list[tuple[int, str]]]:
    """Runs of consecutive prose lines that start with a pipe."""
    tables, run, previous = [], [], None
    for number, line in _prose_lines(text):
        if line.lstrip().startswith("|") and (previous is None or number == previous + 1):
            run.append((number, line))
        else:
            if run:
                tables.append(run)
            run = [(number, line)] if line.lstrip().startswith("|") else []
        previous = number
    if run:
        tables.append(run)
    return tables


DELIMITER = re.compile(r"^\|?\s*:?-{3,}:?\s*(\|\s*:?-{3,}:?\s*)*\|?$")


@pytest.mark.parametrize("path", MARKDOWN, ids=_relative)
def test_every_markdown_table_renders(path):
    problems = []
    for table in _tables(path.read_text()):
        (first, header), rest = table[0], table[1:]
        if not rest or not DELIMITER.match(rest[0][1].strip()):
            problems.append(f"line {first}: a table without a delimiter row under its header")
            continue
        width = _cells(header)
        for number, row in table[1:]:
            if _cells(row) != width:
                problems.append(f"line {number}: {_cells(row)} cells, the header has {width}")
    assert not problems, f"{_relative(path)}:\n" + "\n".join(problems)


def _targets(text: str) -> list[tuple[int, str]]:
    targets = []
    for number, line in _prose_lines(text):
        line = re.sub(r"`[^`]*`", "", line)  # code spans are not links
        targets += [(number, target) for target in LINK.findall(line)]
        targets += [(number, target) for target in HTML_SOURCE.findall(line)]
    return targets


@pytest.mark.parametrize("path", MARKDOWN, ids=_relative)
def test_every_relative_link_and_image_resolves(path):
    missing = []
    for number, target in _targets(path.read_text()):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue  # an absolute URL (not fetched: no network in tests) or an anchor
        file = (path.parent / target.split("#", 1)[0]).resolve()
        if not file.exists():
            missing.append(f"line {number}: {target}")
        elif REPO not in file.parents:
            missing.append(f"line {number}: {target} leaves the repository")
    assert not missing, f"{_relative(path)}: links that do not resolve:\n" + "\n".join(missing)


# ------------------------------------------------------------------ the tutorials' snippets
def runnable_snippets(text: str) -> list[tuple[str, str | None, str]]:
    """(language, file name or None, code) of every block marked runnable, in page order."""
    snippets, lines = [], text.splitlines()
    for index, line in enumerate(lines):
        marker = RUNNABLE.match(line.strip())
        if not marker:
            continue
        fence = lines[index + 1].strip()
        if not FENCE.match(fence):
            raise AssertionError(f"line {index + 1}: a runnable marker not followed by a fence")
        body = []
        for code in lines[index + 2 :]:
            if code.strip() == fence[: len(fence) - len(fence.lstrip("`~"))]:
                break
            body.append(code)
        language = fence.lstrip("`~").strip().split(" ")[0]
        snippets.append((language, marker.group(1), "\n".join(body) + "\n"))
    return snippets


def _environment() -> dict[str, str]:
    environment = dict(os.environ)
    environment["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{environment['PATH']}"
    environment["MPLBACKEND"] = "Agg"
    environment.pop("ENGINE_MPIEXEC", None)
    return environment


@pytest.mark.parametrize("path", TUTORIALS, ids=_relative)
def test_the_runnable_snippets_of_every_tutorial_run(path, tmp_path, monkeypatch):
    snippets = runnable_snippets(path.read_text())
    assert snippets, f"{_relative(path)}: no snippet marked runnable"
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for language, name, code in snippets:
        if name is not None:
            (tmp_path / name).write_text(code)
        elif language in ("bash", "sh", "shell"):
            done = subprocess.run(
                ["bash", "-euo", "pipefail", "-c", code], cwd=tmp_path, env=_environment(),
                capture_output=True, text=True, timeout=300,
            )  # fmt: skip
            assert done.returncode == 0, f"{_relative(path)}:\n{code}\n{done.stdout}{done.stderr}"
        elif language == "python":
            exec(compile(code, f"{_relative(path)} snippet", "exec"), namespace)
        else:
            raise AssertionError(f"{_relative(path)}: cannot run a {language!r} block")


def test_the_snippet_reader_keeps_page_order_and_file_names():
    page = "\n".join(
        [
            "<!-- runnable: a.toml -->", "```toml", "x = 1", "```", "text",
            "<!-- runnable -->", "```bash", "cat a.toml", "```",
            "```python", "not marked", "```",
        ]
    )  # fmt: skip
    assert runnable_snippets(page) == [
        ("toml", "a.toml", "x = 1\n"),
        ("bash", None, "cat a.toml\n"),
    ]


def test_the_table_checker_finds_a_split_table_and_a_short_row():
    good = "| a | b |\n| --- | --- |\n| 1 | `x \\| y` |\n"
    assert [len(table) for table in _tables(good)] == [3]
    assert _cells("| 1 | `x \\| y` |") == 2
    split = good + "\n| 2 | 3 |\n"
    second = _tables(split)[1]
    assert len(second) == 1 and not DELIMITER.match(second[0][1])
    assert _cells("| 1 |") == 1


# ------------------------------------------------------------------------------ the site
def test_the_site_builds_with_warnings_as_errors_and_every_reference_resolved(tmp_path):
    """The whole manual through Sphinx (MyST for the pages, numpydoc for the API), nitpicky:
    a link to a page or a heading that does not exist, an unresolved cross-reference in a
    docstring, or a docstring that fails numpydoc's validation (summary line, every parameter
    and the return value documented) is an error. The command of docs/conf.py, with the
    builder that resolves every reference without writing pages."""
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-q", "-b", "dummy",
         str(DOCS), str(tmp_path / "site")],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_stored_inventories_hold_what_the_manual_links_to():
    """docs/_inventories: written by scripts/inventories.py, read by the build (no network)."""
    done = subprocess.run(
        [sys.executable, str(REPO / "scripts" / "inventories.py"), "--check"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_build_command_is_the_one_the_readme_and_the_test_script_give():
    command = "python -m sphinx -W --keep-going -n -b html docs build/site"
    assert command in " ".join((REPO / "README.md").read_text().split())
    assert command in (REPO / "scripts" / "test.sh").read_text()
    assert command in (DOCS / "conf.py").read_text()


def test_every_public_name_of_engine_is_in_the_api_reference():
    import engine

    index = (DOCS / "reference" / "api" / "index.rst").read_text()
    pattern = r"^\.\. auto(?:function|class|data):: engine\.(\w+)$"
    documented = set(re.findall(pattern, index, re.M))
    assert set(engine.__all__) - {"__version__"} == documented


# ---------------------------------------------------------------- the generated reference
def test_the_committed_reference_equals_the_generated_one():
    """docs/reference/{study-file,outputs,cli}.md: the blocks scripts/reference.py writes
    from the key table, the results schema and the command line's help."""
    done = subprocess.run(
        [sys.executable, str(REPO / "scripts" / "reference.py"), "--check"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr


def _known_keys(section: str) -> set[str]:
    """The keys the parser accepts in ``section``, from its error for an unknown key."""
    from engine.study.config import StudyConfigError, parse_study
    from engine.study.examples import study_toml

    loading = {"kind": "fretting", "amplitude": 0.001} if section == "loading" else {}
    layers = [{"sweep": {"wear1": [1.33e-7]}}]
    if section in ("mesh", "loading"):  # a line contact: the keys only line contacts take
        layers.append({"punch": {"shape": "cylinder", "radius": 6.0}})
        loading["load"] = 185.0  # N/mm
    if section == "calibrate":  # [calibrate] is read after the [search] it needs
        layers += _calibration_layers()
    layers.append({section: {"not_a_key": 1}})
    text = study_toml("keys", "keys.h5", *layers, loading=loading)
    with pytest.raises(StudyConfigError) as error:
        parse_study(text)
    assert "unknown key (known: " in str(error.value), str(error.value)
    return set(str(error.value).split("(known: ", 1)[1].rstrip(")").split(", "))


def test_the_key_table_describes_exactly_the_keys_the_parser_accepts():
    """The manual's table describes the engine's keys with those of its own profiles; the
    keys of a profile another package registers (installed here: examples/plugins) are the
    parser's too, and described by that package."""
    from engine.fatigue import CRITERIA
    from engine.geometry import PROFILES
    from engine.solvers.wear_laws import WEAR_LAWS
    from engine.study.config import StudyConfigError, parse_study
    from engine.study.config.keys import SECTIONS, STUDY_KEYS
    from engine.study.examples import study_toml
    from engine.study.units import sweepable_keys

    def foreign(registry, keys_of):
        """Keys only the plug-ins of other packages in ``registry`` declare."""
        installed = {key for cls in registry.values() for key in keys_of(cls)}
        return installed - {key for cls in registry.builtins.values() for key in keys_of(cls)}

    foreign_keys = {
        "punch": foreign(PROFILES, lambda cls: cls.keys()),
        "fatigue": foreign(CRITERIA, lambda cls: cls.constants),
        "sweep": foreign(WEAR_LAWS, lambda cls: cls.coefficients),
    }
    text = study_toml("keys", "keys.h5", {"sweep": {"wear1": [1.33e-7]}, "not_a_section": {}})
    with pytest.raises(StudyConfigError) as error:
        parse_study(text)
    known = re.findall(r"\[(\w+)\]", str(error.value).split("(known: ", 1)[1])
    # [search] and [calibrate] are read by engine.study.search and engine.study.calibrate
    assert set(SECTIONS) == set(known) | {"search", "calibrate"}
    for section in SECTIONS:
        described = {key.name for key in STUDY_KEYS if key.section == section}
        known = _known_keys(section)
        if section == "sweep":
            known |= {"zip"}  # the zip groups are read before the section's own keys
        if section == "search":
            known |= {"relative_to"}  # read with [calibrate], before the search's own keys
        known -= foreign_keys.get(section, set())
        assert described == known, section
    units = {f"{key.section}.{key.name}": key.unit for key in STUDY_KEYS}
    for dotted, unit in sweepable_keys(PROFILES.builtins, CRITERIA.builtins).items():
        assert units[dotted] == unit, dotted


_SELF_AFFINE = {"kind": "self_affine", "long_cutoff": 0.4, "short_cutoff": 0.15, "rms_height": 3e-4}
_FILE_SURFACE_KEYS = {"path", "pixel_size", "units", "detrend"}


def _height_map_surface() -> dict:
    """A [surface] of kind "file": a flat 16 × 16 height map (.npy) in a folder of its own."""
    import tempfile

    import numpy as np

    path = Path(tempfile.mkdtemp(prefix="heights")) / "heights.npy"
    np.save(path, np.zeros((16, 16)))
    return {"kind": "file", "path": str(path), "pixel_size": 0.1}


def _calibration_layers() -> list[dict]:
    """A fretting-fatigue threshold search with a [calibrate] section over two tests (the
    tests file written in a folder of its own, named by its absolute path)."""
    import tempfile

    from engine.study.examples import CYLINDER_ON_STEEL

    tests = Path(tempfile.mkdtemp(prefix="tests")) / "tests.csv"
    tests.write_text("test,punch.radius,Q\nA,6,40\nB,10,45\n")
    search = {
        "parameter": "loading.force_amplitude", "relative_to": "mu_load", "low": 0.2,
        "high": 0.95, "column": "crossland_risk_critical", "target": 1.0, "rtol": 2e-3,
    }  # fmt: skip
    fatigue = {"criteria": ["crossland"], "sigma_d": 300.0, "tau_d": 200.0}
    return [
        {"sweep": {"mu1": [0.5], "wear1": [0.0]}},
        CYLINDER_ON_STEEL,
        {"loading": {"kind": "fretting", "load": 185.0}, "mesh": {"n": 48}},
        {"fatigue": fatigue, "search": search},
        {"calibrate": {"tests": str(tests), "id": "test", "measured": "Q"}},
    ]


def _default_study(section: str, name: str) -> str:
    """A valid study in which ``[section] name`` is absent: the kind of study the key belongs
    to (a line fretting case for the bulk stress, a search for [search], …)."""
    from engine.study.examples import CYLINDER_ON_STEEL, SPHERE_ON_STEEL, study_toml

    wear = {"sweep": {"mu1": [0.3], "wear1": [1.33e-7]}}
    fretting = {"loading": {"kind": "fretting", "amplitude": 0.001}}
    drop = {section: {name: None}}
    if (section, name) in {("loading", "bulk_stress_max"), ("loading", "bulk_stress_min"),
                           ("mesh", "reference_distance")}:  # fmt: skip
        layers = [wear, CYLINDER_ON_STEEL, fretting, {"loading": {"load": 185.0}}]
    elif section == "calibrate" or (section, name) == ("search", "relative_to"):
        layers = _calibration_layers()
    elif section == "search":
        search = {
            "parameter": "loading.amplitude", "low": 1e-4, "high": 1e-2,
            "column": "slip_regime", "target": "gross", "rtol": 1e-3,
        }  # fmt: skip
        if name == "rtol":
            search.update(rtol=None, atol=1e-6)
        layers = [wear, SPHERE_ON_STEEL, {"loading": {"kind": "fretting"}}, {"search": search}]
    elif section == "fatigue":  # every criterion, so every constant is needed
        fatigue = dict(_FATIGUE, length=None) if name == "method" else _FATIGUE
        layers = [wear, SPHERE_ON_STEEL, fretting, {"fatigue": fatigue}]
    elif (section, name) == ("punch", "edge_radius"):
        layers = [wear, {"punch": {"shape": "rounded", "radius": 1.0, "edge_radius": 0.2}}]
    elif (section, name) == ("sweep", "alpha"):
        layers = [{"wear": {"law": "energy"}, "sweep": {"mu1": [0.3], "alpha": [1e-5]}}]
    elif section == "loading" and name == "direction":
        layers = [wear, SPHERE_ON_STEEL, fretting]
    elif section == "surface":
        surface = _height_map_surface() if name in _FILE_SURFACE_KEYS else dict(_SELF_AFFINE)
        layers = [wear, SPHERE_ON_STEEL, {"mesh": {"n": 32}, "surface": surface}]
    elif (section, name) == ("sweep", "zip"):
        layers = [wear, {"loading": {"load": None}, "sweep": {"loading.load": [100.0, 200.0]}}]
    else:
        layers = [wear]
    return study_toml("defaults", "defaults.h5", *layers, drop)


def test_every_constant_default_of_the_key_table_is_the_parsers():
    """Every default the study-file reference writes as a plain number, text or list is the
    value a study without the key resolves to, each in a study of the kind the key belongs to
    (the defaults stated in words depend on other keys: they are checked by the tests of the
    sections that compute them)."""
    import json

    from engine.study.config import parse_study
    from engine.study.config.keys import STUDY_KEYS

    unchecked = []
    for key in STUDY_KEYS:
        try:
            default = json.loads(_stated_default(key))
        except json.JSONDecodeError:
            continue  # a default that depends on other keys, stated in words
        config = parse_study(_default_study(key.section, key.name))
        resolved = config.resolved().get(key.section) or {}
        if (key.section, key.name) == ("sweep", "zip"):
            value = [list(axis.keys) for axis in config.sweep.axes if len(axis.keys) > 1]
        elif key.name in resolved:
            value = resolved[key.name]
        elif hasattr(getattr(config, key.section, None), key.name):
            value = getattr(getattr(config, key.section), key.name)
        else:
            unchecked.append(f"[{key.section}] {key.name}")
            continue
        value = list(value) if isinstance(value, tuple) else value
        if key.section == "sweep" and key.name == "beta":
            value = list(value)
        assert value == default, f"[{key.section}] {key.name}: {value!r}, the table: {default!r}"
    assert not unchecked, "defaults no study resolves: " + ", ".join(unchecked)


# ------------------------------------------------------------ measured numbers carry their run
BLOCK = re.compile(r"<!-- BEGIN (generated|report) ([\w-]+) -->\n(.*?)<!-- END \1 \2 -->", re.S)
MEASURED_PAGES = ("explanation/performance.md", "explanation/validation.md")


def _blocks() -> list[tuple[Path, str, str, str]]:
    return [
        (path, kind, name, body)
        for path in MARKDOWN
        for kind, name, body in BLOCK.findall(path.read_text())
    ]


def test_every_generated_block_is_filled_and_measured_ones_say_when_and_where():
    """A generated block is never left empty; a block of measured figures (every one but the
    reference blocks, which scripts/reference.py derives from the code) starts with the date
    and the machine of its run."""
    sys.path.insert(0, str(REPO / "scripts"))
    try:
        from reference import BLOCKS
    finally:
        sys.path.remove(str(REPO / "scripts"))
    derived = {name for _, name in BLOCKS}
    for path, kind, name, body in _blocks():
        assert body.strip(), f"{_relative(path)}: block {name} is empty"
        if kind == "generated" and name not in derived:
            assert re.match(r"\*Measured \d{4}-\d{2}-\d{2} on .+\*", body), (
                f"{_relative(path)}: block {name} does not start with its date and machine"
            )


@pytest.mark.parametrize("page", MEASURED_PAGES)
def test_every_table_of_the_performance_and_validation_pages_is_generated(page):
    """Their figures cannot go stale: each table sits inside a block written by the script or
    benchmark that measured it."""
    text = (DOCS / page).read_text()
    outside = BLOCK.sub("", text)
    tables = _tables(outside)
    assert not tables, f"docs/{page}: tables typed by hand at lines " + ", ".join(
        str(table[0][0]) for table in tables
    )


def test_one_command_takes_every_measured_block_again():
    """scripts/remeasure.py runs the producer of every measured block of the manual (or names
    the command of one whose figures are not times), so that one command on a quiet machine
    takes them all again."""
    sys.path.insert(0, str(REPO / "scripts"))
    try:
        import remeasure
    finally:
        sys.path.remove(str(REPO / "scripts"))
    run = {part for step in remeasure.steps(long=True) for part in step.command}
    producer = re.compile(r"(?:benchmarks|scripts)/\w+\.py|engine\.analysis\.\w+|tests/slurm")
    for path, _, name, body in _blocks():
        header = body.splitlines()[0] if body.strip() else ""
        if "load average" not in header:
            continue
        found = producer.search(header)
        assert found, f"{_relative(path)}, block {name}: no producer named in {header!r}"
        assert found.group(0) in run | set(remeasure.ELSEWHERE), (
            f"{_relative(path)}, block {name}: {found.group(0)} is not run by remeasure.py"
        )


def test_every_page_of_the_manual_is_linked_from_its_index():
    """No orphan pages: docs/index.md links every Markdown page under docs/."""
    index = DOCS / "index.md"
    linked = {
        (index.parent / target.split("#", 1)[0]).resolve()
        for _, target in _targets(index.read_text())
        if not re.match(r"^[a-z][a-z0-9+.-]*:", target)
    }
    pages = {path.resolve() for path in DOCS.rglob("*.md")} - {index.resolve()}
    orphans = sorted(_relative(path) for path in pages - linked)
    assert not orphans, "pages missing from docs/index.md: " + ", ".join(orphans)


# A measured figure in the README: a number with a unit of time, memory or a ratio.
_FIGURE = re.compile(r"(?<![\w.])(\d[\d,]*(?:\.\d+)?) ?(s|ms|min|h|MB|GB|kB|%|×)(?![\w])")


def test_the_readme_quotes_only_numbers_of_the_measured_tables():
    """Every time, memory or ratio the README gives is a cell of a table the benchmarks or
    the results script wrote (a generated or report block of the manual), so it cannot go
    stale apart from them; the one exception is the progress interval, the command line's
    own default."""
    from engine.cli import build_parser

    interval = build_parser().get_default("progress_interval")
    cells = {
        cell.strip()
        for _, _, _, body in _blocks()
        for line in body.splitlines()
        if line.startswith("|")
        for cell in line.strip("|").split("|")
    }
    readme = " ".join((REPO / "README.md").read_text().split())
    found = _FIGURE.findall(readme)
    for number, unit in found:
        if unit == "s" and float(number) == interval and f"every {number} s" in readme:
            continue
        assert number in cells or f"{number} {unit}" in cells, (
            f"README.md quotes {number} {unit}, which no measured table of docs/ holds"
        )


# --------------------------------------------------------------- words for users, figures shown
PROCESS_WORDS = re.compile(
    r"\b(?:verified here|measured here|the old advice|(?:bit-identical|identical) to before"
    r"|per (?:CI|MPI) phase|left open|not done|issues? \d+|sessions?|helpers?|our own"
    r"|development machine|this machine|while other jobs ran|(?:second|third) round"
    r"|the previous (?:scheduler|solver|tree|code|version)|before the performance work"
    r"|work in progress|TODO|wip)\b",
    re.IGNORECASE,
)


@pytest.mark.parametrize("path", sorted(DOCS.rglob("*.md")), ids=_relative)
def test_the_manual_speaks_to_users_not_of_its_making(path):
    """No issue numbers, development history, or notes about the machine a page was written
    on: the manual describes the engine as it is (CHANGELOG.md holds what changed)."""
    found = [
        f"line {number}: {match.group(0)!r}"
        for number, line in _prose_lines(path.read_text())
        for match in PROCESS_WORDS.finditer(line)
    ]
    assert not found, f"{_relative(path)}: words about the making of the manual:\n" + "\n".join(
        found
    )


def test_the_process_words_are_found():
    assert PROCESS_WORDS.search("Verified here (2026-11-23) with MPICH")
    assert PROCESS_WORDS.search("20 per CI phase")
    assert PROCESS_WORDS.search("## Left open")
    assert not PROCESS_WORDS.search("a round-off error on a rounded punch, helpful")


#: Where the code, tests, benchmarks, scripts and bundled studies live; their Python, TOML and
#: Markdown files are read for references to the project's tracker.
SOURCE_DIRECTORIES = ("engine", "tests", "benchmarks", "scripts", "studies", "slurm", "examples")
SOURCE_SUFFIXES = {".py", ".toml", ".md"}
#: A reference to the tracker instead of a statement of what is checked: "issue" or "issues"
#: and a number, "acceptance" and a number or "point", the issue with a possessive, or a
#: section banner that carries nothing but tracker numbers (examples in the test below).
ISSUE_REFERENCES = re.compile(
    r"\bissues? \d+|\bacceptance (?:points?\b|\d+)|\bthe issue's\b"
    r"|^\s*#\s*-{3,}\s*\d+(?:\.\d+)?(?: / \d+(?:\.\d+)?)*\s*$",
    re.IGNORECASE,
)


def _source_files() -> list[Path]:
    return sorted(
        path
        for directory in SOURCE_DIRECTORIES
        for path in (REPO / directory).rglob("*")
        if path.suffix in SOURCE_SUFFIXES
        and path.is_file()
        and not {".venv", "__pycache__", "node_modules"} & set(path.relative_to(REPO).parts)
    )


def test_the_code_tests_and_studies_cite_no_issue_numbers():
    """Comments, docstrings, test names, benchmarks, scripts and study files say what they
    check or do in the reader's words, not by the tracker's numbering."""
    found = [
        f"{_relative(path)}:{number}: {line.strip()}"
        for path in _source_files()
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), start=1)
        if ISSUE_REFERENCES.search(line)
    ]
    assert not found, "references to the tracker:\n" + "\n".join(found)


def test_the_issue_references_are_found():
    # Built from pieces so that this file holds none of them.
    for line in (
        '"""Kill-safety (issue' + "s 16 and 18): kills at the first writes",
        "Cyclic-wear benchmark (issue" + "s 3, 17)",
        '    """Accept' + "ance 2, Fig. 3b: the stiffness ratio grows with μ",
        "    # the 1e-4 relative bound of the iss" + "ue's requirement",
        "# ----------------- " + "16.5 / 18.2",
        "#  ------------ " + "16.1",
        "the accept" + "ance point holds",
    ):
        assert ISSUE_REFERENCES.search(line), line
    for line in (
        "Section 7.2 settings: flat punch a0 = 1.8 mm, P = 750 N",
        "# --- DC-FFT against the direct sum ------------------------------------",
        "# ------------------------------------------------------ output-path errors",
        "see h5py's GitHub issues/1234; a known issue of HDF5 1.14",
        "accepted within 1 % (the acceptance bound of the test)",
        "start_new_session=True, scope='session', a helper thread",
    ):
        assert not ISSUE_REFERENCES.search(line), line


def test_every_figure_of_the_manual_is_shown_on_a_page():
    """A figure under docs/figures that no page shows is stale weight: show it or remove it
    (and stop the script that draws it from writing it)."""
    shown = {
        (path.parent / target.split("#", 1)[0]).resolve()
        for path in MARKDOWN
        for _, target in _targets(path.read_text())
    }
    unused = sorted(
        _relative(figure)
        for figure in (DOCS / "figures").rglob("*.png")
        if figure.resolve() not in shown
    )
    assert not unused, "figures no page shows: " + ", ".join(unused)


def test_every_study_header_gives_a_measured_time_or_says_it_has_none(tmp_path):
    """The time line of a study header is written by scripts/study_times.py from a run it
    timed (with date, machine and load average), or says it was not measured."""
    sys.path.insert(0, str(REPO / "scripts"))
    try:
        import study_times
    finally:
        sys.path.remove(str(REPO / "scripts"))
    assert study_times.main(["--check"]) == 0
    study = tmp_path / "s.toml"
    study.write_text(f"# A study.\n{study_times.UNMEASURED}\n# Run:  x\n\n[study]\n")
    line = (
        "# Time: 4.1 s with `mpiexec -n 2` (measured 2026-11-28 on X (2 cores), load average 0.5)."
    )
    assert study_times.MEASURED.match(line)
    study_times.write_time(study, line)
    assert study.read_text().splitlines()[:3] == ["# A study.", line, "# Run:  x"]


# How-to guides and tutorials answer a user's task: the code's inside is for the architecture
# page and CONTRIBUTING.md.
INTERNALS = re.compile(r"tests/\S+\.py|::test_\w+|`_\w+|\._[a-z]\w*|engine/[\w/]+\.py")


USER_PAGES = sorted((DOCS / "how-to").glob("*.md")) + TUTORIALS
USER_PAGES += [DOCS / "explanation" / name for name in ("validation.md", "rough-surfaces.md")]
USER_PAGES += [DOCS / "explanation" / "performance.md"]


@pytest.mark.parametrize("path", USER_PAGES, ids=_relative)
def test_how_to_guides_and_tutorials_send_no_reader_into_the_code(path):
    """Nor do the validation, rough-surface and performance pages: they say what is compared
    with what and how the engine spends its time, not which test or source file does it (the
    benchmarks they name are commands a reader runs)."""
    found = [
        f"line {number}: {match.group(0)}"
        for number, line in _prose_lines(path.read_text())
        for match in INTERNALS.finditer(line)
    ]
    assert not found, f"{_relative(path)}: test ids, private names or source paths:\n" + "\n".join(
        found
    )


# ------------------------------------------------------------- the limits of the study file
def _limit_rows():
    sys.path.insert(0, str(REPO / "scripts"))
    try:
        from reference import limit_rows
    finally:
        sys.path.remove(str(REPO / "scripts"))
    return limit_rows()


_WEAR = {"sweep": {"mu1": [0.3], "wear1": [1.33e-7]}}
_LINE = {
    "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e3, "nu_B": 0.3},
    "punch": {"shape": "cylinder", "radius": 6.0},
}
_SPHERE = {
    "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e3, "nu_B": 0.3},
    "punch": {"shape": "sphere", "radius": 10.0},
}
_FATIGUE = {
    "criteria": ["crossland", "dang_van", "swt", "fatemi_socie"],
    "sigma_d": 500.0, "tau_d": 320.0, "sigma_f": 1200.0, "b": -0.09, "eps_f": 0.6,
    "c": -0.6, "tau_f": 700.0, "gamma_f": 0.9, "b0": -0.09, "c0": -0.6, "k": 0.5,
    "sigma_y": 900.0, "method": "point", "length": 0.02,
}  # fmt: skip


_INTEGER_KEYS = {"steps", "cycles", "n", "layers", "maxiter", "threads", "max_steps"}
_INTEGER_KEYS |= {"max_evaluations", "seed"}
_NUMBER = r"-?\d+(?:\.\d+)?(?:e-?\d+)?"


def _outside(key: str, accepted: str) -> list[tuple[str, float]]:
    """("below" or "above", a value just outside) for each end of the range ``accepted``
    (``[a, b]``, ``(a, b]``, ``[a, b)``, ``≥ a``, ``> a``, ``≤ b``, or ``a ≤ p0/E* ≤ b``
    for the load): the bound itself at an open end, the nearest value beyond a closed one
    (the next integer, or 0.1 % of the bound's size beyond it)."""
    integer = key.split(".")[-1] in _INTEGER_KEYS
    numbers = [float(x) for x in re.findall(_NUMBER, accepted)]

    def beyond(bound: float, sign: int, is_open: bool) -> float:
        if is_open:
            return bound
        return bound + sign * (1 if integer else 1e-3 * max(abs(bound), 1e-3))

    if key == "loading.load":  # p0/E* on the base flat punch: 1e-20 N and 1e9 N
        return [("below", 1e-20), ("above", 1e9)]
    if "half_width" in accepted.split(",")[0]:  # both ends on the mesh: _MESH_BOUNDS below
        return []
    if "half_width" in accepted:  # a maximum relative to the mesh (_MESH_BOUNDS): the lower end
        return [("below", beyond(numbers[0], -1, accepted.startswith("(")))]
    if accepted.startswith(("≥", ">")):
        return [("below", beyond(numbers[0], -1, accepted.startswith(">")))]
    if accepted.startswith(("≤", "<")):
        return [("above", beyond(numbers[0], +1, accepted.startswith("<")))]
    low, high = numbers
    return [
        ("below", beyond(low, -1, accepted.startswith("("))),
        ("above", beyond(high, +1, accepted.endswith(")"))),
    ]


def _study_with(key: str, value: float, unit: str) -> list[dict]:
    """Study layers of the kind ``key`` belongs to, with ``key`` set to ``value``."""
    section, name = key.split(".", 1)
    fretting = {"loading": {"kind": "fretting", "amplitude": 0.001}}
    if name in _INTEGER_KEYS:
        value = int(value)
    if key == "loading.load":
        return [_WEAR, {"loading": {"load": value}}]
    if section == "fatigue":
        return [_WEAR, _SPHERE, fretting, {"fatigue": dict(_FATIGUE, **{name: value})}]
    if key.startswith("loading.bulk_stress"):
        return [_LINE, fretting, {"loading": {"load": 185.0, "bulk_stress_max": value}}]
    if key == "wear.pad_coefficient":
        energy = "mm³/J" in unit
        layers = [_LINE, {"loading": {"load": 185.0}}, {"wear": {"pad_coefficient": value}}]
        if energy:
            layers += [{"wear": {"law": "energy"}, "sweep": {"mu1": [0.3], "alpha": [1e-5]}}]
        return [_WEAR] + layers
    if key == "mesh.reference_distance":
        return [_WEAR, _LINE, {"loading": {"load": 185.0}, "mesh": {name: value}}]
    if key.startswith("punch."):
        return [_WEAR, {"punch": {"shape": "rounded", "radius": 1.0, "edge_radius": 0.2}},
                {"punch": {name: value}}]  # fmt: skip
    if key in ("loading.amplitude", "loading.direction"):
        return [_SPHERE, fretting, {"loading": {name: value}}]
    if key == "loading.force_amplitude":
        return [_SPHERE, {"loading": {"kind": "fretting", "force_amplitude": value}}]
    if key == "sweep.alpha":
        return [{"wear": {"law": "energy"}, "sweep": {"mu1": [0.3], "alpha": [value]}}]
    if section == "sweep":
        return [_WEAR, {"sweep": {name: [value]}}]
    if section == "search":
        search = {"parameter": "loading.amplitude", "low": 1e-4, "high": 1e-2,
                  "column": "slip_regime", "target": "gross", "rtol": 1e-3}  # fmt: skip
        return [_WEAR, _SPHERE, fretting, {"search": dict(search, **{name: value})}]
    if section == "calibrate":
        return _calibration_layers() + [{"calibrate": {name: value}}]
    if section == "surface":
        surface = _height_map_surface() if name == "pixel_size" else dict(_SELF_AFFINE)
        if name == "rms_slope":
            surface["rms_height"] = None
        return [_WEAR, _SPHERE, {"mesh": {"n": 32}, "surface": dict(surface, **{name: value})}]
    return [_WEAR, {section: {name: value}}]


def _limit_cases():
    return [
        pytest.param(key, side, value, unit, id=f"{key}_{unit}_{side}".replace(" ", "_"))
        for key, accepted, unit, _ in _limit_rows()
        for side, value in _outside(key.split(",")[0], accepted)
    ]


@pytest.mark.parametrize(("key", "side", "value", "unit"), _limit_cases())
def test_every_limit_of_the_reference_is_enforced_and_named(key, side, value, unit):
    """A value just outside each end of each range of the generated limits table (the bound
    itself at an open end) is refused by the study checks, with the key in the message: the
    table states what the code enforces, lower bounds and upper bounds."""
    from engine.study.config import StudyConfigError, parse_study
    from engine.study.examples import study_toml

    first = key.split(",")[0]
    text = study_toml("limits", "limits.h5", *_study_with(first, value, unit))
    with pytest.raises(StudyConfigError) as error:
        parse_study(text)
    section, name = first.split(".", 1)
    assert f"[{section}] {name}" in str(error.value), str(error.value)


def test_every_limit_is_tested_at_both_ends_and_inside():
    """The values the limits test takes lie just outside the ranges the checks declare (the
    host's and the built-in loading kinds'), and the bounds themselves are accepted at closed
    ends (``Limit.holds``)."""
    from engine.study.kinds import KINDS
    from engine.study.settings.checks import LIMITS, Limit

    cases = {(p.values[0], p.values[1]) for p in _limit_cases()}
    ranges = dict(LIMITS)
    for kind in KINDS.builtins.values():
        for name, declared in kind.declared_keys().items():
            if declared.minimum is not None or declared.maximum is not None:
                ranges.setdefault(f"loading.{name}", Limit.of(declared))
    for dotted, limit in ranges.items():
        key = dotted.removesuffix(".energy")
        if key.startswith("loading.bulk_stress"):  # one row for the two
            key = "loading.bulk_stress_max, bulk_stress_min"
        if limit.minimum is not None:
            assert (key, "below") in cases, dotted
            assert limit.holds(limit.minimum) != limit.open_minimum, dotted
        if limit.maximum is not None:
            assert (key, "above") in cases, dotted
            assert limit.holds(limit.maximum) != limit.open_maximum, dotted


# The bounds that depend on the mesh or the contact. [surface] on a 32² mesh of half-width
# 0.5 mm: an element of 1/32 mm, a mesh 1 mm long; [mesh] under a flat punch of radius 1 mm
# (a0 = 1 mm exactly). Each: (key, the bound as the limits table states it, the value at the
# bound, accepted, and the value just beyond it, refused; the other keys of the section).
_ELEMENT, _LENGTH = 2 * 0.5 / 32, 1.0
_MESH_BOUNDS = [
    ("mesh.half_width", "at least the contact length a0", 1.0, 1.0 * (1 - 1e-3), {"n": 32}),
    ("mesh.n", "at least 4 elements across the contact", 16, 15, {"half_width": 4.0}),
    ("surface.short_cutoff", "[4·half_width/n,", 2 * _ELEMENT, 2 * _ELEMENT * (1 - 1e-3), {}),
    ("surface.short_cutoff", ", 2·half_width]", _LENGTH, _LENGTH * (1 + 1e-3),
     {"long_cutoff": 2.0}),
    ("surface.long_cutoff", "at least short_cutoff", 0.15, 0.15 * (1 - 1e-3), {}),
    ("surface.long_cutoff", "100 × 2·half_width]", 100 * _LENGTH, 100 * _LENGTH * (1 + 1e-3), {}),
    ("surface.rms_height", ", 2·half_width]", _LENGTH, _LENGTH * (1 + 1e-3), {}),
    ("surface.pixel_size", ", 2·half_width]", _LENGTH, _LENGTH * (1 + 1e-3), {}),
    ("surface.pixel_size", "samples × pixel_size", _LENGTH / 16, _LENGTH / 16 * (1 - 1e-3), {}),
]  # fmt: skip


def _bound_study(dotted: str, value: float, others: dict, mesh_folder: Path) -> str:
    from engine.study.examples import study_toml

    section, key = dotted.split(".")
    if section == "mesh":
        flat = {"punch": {"shape": "flat", "radius": 1.0}, "mesh": dict(others, **{key: value})}
        return study_toml("bounds", "bounds.h5", _WEAR, flat)
    if key == "pixel_size":  # a flat 16 × 16 map: it spans 16 pixel sizes
        import numpy as np

        np.save(mesh_folder / "heights.npy", np.zeros((16, 16)))
        surface = {"kind": "file", "path": str(mesh_folder / "heights.npy"), key: value}
    else:
        surface = dict(_SELF_AFFINE, **others, **{key: value})
    layers = [_WEAR, _SPHERE, {"mesh": {"n": 32, "half_width": 0.5}, "surface": surface}]
    return study_toml("bounds", "bounds.h5", *layers)


@pytest.mark.parametrize(
    ("key", "stated", "bound", "beyond", "others"),
    _MESH_BOUNDS,
    ids=[f"{row[0]}-{index}" for index, row in enumerate(_MESH_BOUNDS)],
)
def test_every_bound_on_the_mesh_or_contact_is_stated_and_holds_at_both_sides(
    key, stated, bound, beyond, others, tmp_path
):
    """The limits table states the bound; a study at the bound is accepted; just beyond it,
    ``python -m engine`` exits 2 with one line naming the key and the value, and writes
    nothing (the map's folder holds only the map)."""
    from engine.study.config import parse_study

    rows = {row[0]: row for row in _limit_rows()}
    assert stated in " ".join(rows[key][1:]), rows[key]
    parse_study(_bound_study(key, bound, others, tmp_path))
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "bounds.toml").write_text(_bound_study(key, beyond, others, tmp_path))
    done = subprocess.run(
        [sys.executable, "-m", "engine", "bounds.toml"], cwd=folder, capture_output=True,
        text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 2, done.stdout + done.stderr
    lines = done.stderr.strip().splitlines()
    section, name = key.split(".")
    assert len(lines) == 1 and f"[{section}] {name} = {beyond!r}" in lines[0], done.stderr
    assert [path.name for path in folder.iterdir()] == ["bounds.toml"]


def test_every_default_stated_in_words_is_what_the_parser_does():
    """The defaults the study-file reference states in words (they depend on other keys),
    one assert each, so that every default of the table is tested by one of the two tests."""
    from engine.study.config import parse_study
    from engine.study.config.keys import STUDY_KEYS
    from engine.study.examples import CYLINDER_ON_STEEL, SPHERE_ON_STEEL, study_toml
    from engine.study.plan import make_plan

    wear = {"sweep": {"mu1": [0.3, 0.5], "wear1": [1.33e-7]}}

    def parsed(*layers, **sections):
        return parse_study(study_toml("words", "words.h5", wear, *layers, **sections))

    worded = {
        f"{key.section}.{key.name}"
        for key in STUDY_KEYS
        if not key.default.startswith("required") and not _is_json(_stated_default(key))
    }
    checked = set()
    # half_width: flat 1.5·radius; rounded 1.05·(radius + edge_radius); sphere 1.5 Hertz radii
    assert parsed(mesh={"half_width": None}).mesh.half_width == pytest.approx(1.5 * 1.8)
    rounded = parsed(punch={"shape": "rounded", "radius": 1.0, "edge_radius": 0.2})
    assert rounded.mesh.half_width == pytest.approx(1.05 * 1.2)
    for shape in (SPHERE_ON_STEEL, CYLINDER_ON_STEEL, {"punch": {"shape": "pad", "radius": 0.1,
                                                                "edge_radius": 5.0}}):  # fmt: skip
        load = 100.0 if shape is SPHERE_ON_STEEL else 185.0
        contact = parsed(shape, loading={"kind": "static", "load": load}, mesh={"half_width": None})
        assert contact.mesh.half_width == pytest.approx(1.5 * contact.contact_length)
    checked.add("mesh.half_width")
    # record: [cycles]
    assert parsed(loading={"record": None, "cycles": 300}).loading.record == (300,)
    checked.add("loading.record")
    # amplitude, force_amplitude: one of the two
    fretting = {"kind": "fretting"}
    with pytest.raises(Exception, match="amplitude"):
        parsed(SPHERE_ON_STEEL, loading=fretting)
    with pytest.raises(Exception, match="amplitude"):
        parsed(SPHERE_ON_STEEL, loading=dict(fretting, amplitude=1e-3, force_amplitude=1.0))
    checked |= {"loading.amplitude", "loading.force_amplitude"}
    # bulk stresses: none; pad_coefficient: none
    line = parsed(CYLINDER_ON_STEEL, loading=dict(fretting, amplitude=1e-3, load=185.0))
    assert line.loading.bulk_stress_max is None and line.loading.bulk_stress_min is None
    assert line.wear.pad_coefficient is None
    checked |= {"loading.bulk_stress_max", "loading.bulk_stress_min", "wear.pad_coefficient"}
    # mu2 = mu1, wear2 = wear1 in every case
    for case in make_plan(parsed()).cases:
        coefficients = case.coefficients
        assert (case.mu2, coefficients["wear2"]) == (case.mu1, coefficients["wear1"])
    checked |= {"sweep.mu2", "sweep.wear2"}
    # search.method: bisection for a text column, illinois for a number
    search = {"parameter": "loading.amplitude", "low": 1e-4, "high": 1e-2, "rtol": 1e-3}
    for column, target, method in (("slip_regime", "gross", "bisection"),
                                   ("q_amplitude", 10.0, "illinois")):  # fmt: skip
        config = parsed(SPHERE_ON_STEEL, loading=fretting,
                        search=dict(search, column=column, target=target))  # fmt: skip
        assert config.resolved()["search"]["method"] == method
    checked.add("search.method")
    # search.relative_to: absolute (low and high in the parameter's unit)
    calibrated = parse_study(
        study_toml("words", "words.h5", *_calibration_layers(), {"search": {"relative_to": None}})
    )
    assert calibrated.calibrate.relative_to == ""
    checked.add("search.relative_to")
    # solver.tol: 1e-8 static, 1e-6 cyclic and fretting
    assert parsed(loading={"kind": "static"}).solver.tol == 1e-8
    assert parsed().solver.tol == 1e-6
    assert parsed(SPHERE_ON_STEEL, loading=dict(fretting, amplitude=1e-3)).solver.tol == 1e-6
    checked.add("solver.tol")
    # rms_height, rms_slope: one of the two (self_affine)
    surface = {"surface": dict(_SELF_AFFINE, rms_height=None), "mesh": {"n": 32}}
    with pytest.raises(Exception, match="rms_height"):
        parsed(SPHERE_ON_STEEL, surface)
    checked |= {"surface.rms_height", "surface.rms_slope"}
    assert worded == checked, f"worded defaults without a check: {sorted(worded - checked)}"


def _stated_default(key) -> str:
    """A key's default without the loading kinds it applies to, which the reference adds
    when not every kind reads the key ("0.004 (cyclic, fretting)": "0.004")."""
    from engine.study.kinds import KINDS

    value, _, kinds = key.default.rpartition(" (")
    if value and kinds.endswith(")") and set(kinds[:-1].split(", ")) <= set(KINDS):
        return value
    return key.default


def _is_json(text: str) -> bool:
    import json

    try:
        json.loads(text)
    except json.JSONDecodeError:
        return False
    return True


def test_every_required_key_is_required():
    """A key the reference marks required (for the kind, shape, law or criterion it names)
    is refused when missing from a study that needs it, with its name in the message."""
    from engine.study.config import StudyConfigError, parse_study
    from engine.study.config.keys import STUDY_KEYS

    required = [key for key in STUDY_KEYS if key.default.startswith("required")]
    assert len(required) > 30
    for key in required:
        with pytest.raises(StudyConfigError) as error:
            parse_study(_default_study(key.section, key.name))
        assert f"[{key.section}] {key.name}" in str(error.value), str(error.value)


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    return {
        _slug(line.lstrip("#"))
        for _, line in _prose_lines(path.read_text())
        if re.match(r"^#{1,6} ", line)
    }


@pytest.mark.parametrize("path", MARKDOWN, ids=_relative)
def test_every_link_to_a_heading_finds_it(path):
    """Anchors as GitHub renders them (the site's build checks them the same way)."""
    missing = []
    for number, target in _targets(path.read_text()):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or "#" not in target:
            continue
        name, anchor = target.split("#", 1)
        page = (path.parent / name).resolve() if name else path
        if page.suffix == ".md" and page.exists() and anchor not in _anchors(page):
            missing.append(f"line {number}: {target}")
    assert not missing, f"{_relative(path)}: links to headings that do not exist:\n" + "\n".join(
        missing
    )


def test_the_heading_anchors_are_githubs():
    assert _slug("Convergence (`studies/mesh_convergence.toml`)") == (
        "convergence-studiesmesh_convergencetoml"
    )
    assert _slug("Friction: the orthotropic Coulomb cone rotated by β") == (
        "friction-the-orthotropic-coulomb-cone-rotated-by-β"
    )


# Paths of the repository and dotted names of the engine that a page quotes in code spans.
_QUOTED_PATH = re.compile(r"`((?:engine|scripts|benchmarks|tests|studies|slurm)/[\w./-]+)`")
_QUOTED_NAME = re.compile(r"`(engine(?:\.\w+)+)")


def _exists(dotted: str) -> bool:
    import importlib

    parts = dotted.split(".")
    for split in range(len(parts), 0, -1):
        try:
            target = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        for part in parts[split:]:
            if not hasattr(target, part):
                return False
            target = getattr(target, part)
        return True
    return False


@pytest.mark.parametrize("path", MARKDOWN, ids=_relative)
def test_every_path_and_name_a_page_quotes_exists(path):
    text = path.read_text()
    missing = [
        quoted
        for quoted in _QUOTED_PATH.findall(text)
        if not (REPO / quoted.split("::")[0]).exists()
    ]
    missing += [name for name in _QUOTED_NAME.findall(text) if not _exists(name)]
    assert not missing, f"{_relative(path)}: quotes what does not exist: " + ", ".join(missing)
