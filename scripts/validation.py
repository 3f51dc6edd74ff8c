"""Write the validation table of the manual from the tests that measure it.

    python scripts/validation.py            # run the tests marked `validation`, write the table
    python scripts/validation.py tests/test_contact.py   # only these files (the rest kept)

Every test marked ``@pytest.mark.validation`` compares the engine with an analytic solution
and, after its asserts, records what it compared, the tolerance and why, and the measured
figure (the ``validation`` fixture of ``tests/conftest.py``). This script runs those tests
with ``ENGINE_VALIDATION_RECORD`` set, collects the rows and rewrites the block
``<!-- BEGIN generated validation -->`` of ``docs/explanation/validation.md`` with the date
and the machine. A check that fails writes no row and the script stops with the pytest
output, leaving the page unchanged. About two minutes here.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from engine.analysis.markdown import markdown_table, measured_on, read_block, replace_block

REPO = Path(__file__).resolve().parents[1]
DOCUMENT = REPO / "docs" / "explanation" / "validation.md"
HEADER = ("check", "tolerance and why", "measured")
#: The topic of the rows each test file records, in the page's words (a file not listed is
#: titled by its name).
TOPICS = {
    "test_contact.py": "Flat punch: normal and frictional contact",
    "test_influence.py": "Influence coefficients and the DC-FFT operator",
    "test_profiles.py": "Sphere and rounded punch",
    "test_stress_kernels.py": "Subsurface stress coefficients",
    "test_subsurface.py": "Subsurface stresses",
    "test_cycle_jump_convergence.py": "Cycle jumping",
    "test_cyclic.py": "Wear over cycles",
    "test_fretting.py": "Fretting",
    "test_fretting_validation.py": "Fretting loops against Mindlin–Deresiewicz",
    "test_line_validation.py": "Line contacts (plane strain)",
    "test_search_run.py": "Threshold searches against the slip amplitude",
    "test_fatigue_validation.py": "Fatigue criteria on a line contact against McEwen's field",
    "test_surface.py": "Rough surfaces",
}


def _test_file(node: str) -> str:
    """``tests/test_contact.py::test_x[64]`` -> ``test_contact.py``."""
    return node.split("::", 1)[0].removeprefix("tests/")


def _spaced(text: str) -> str:
    """``+0.49%`` -> ``+0.49 %``: a space before the per cent sign, as in the manual."""
    return re.sub(r"(\d)%", r"\1 %", text)


def run(paths: list[str]) -> list[dict]:
    """Run the validation tests of ``paths`` and return their rows, in the order they ran."""
    with tempfile.TemporaryDirectory() as folder:
        record = Path(folder) / "rows.jsonl"
        environment = dict(os.environ, ENGINE_VALIDATION_RECORD=str(record))
        command = [sys.executable, "-m", "pytest", "-q", "-m", "validation", "-p",
                   "no:cacheprovider", *paths]  # fmt: skip
        done = subprocess.run(command, cwd=REPO, env=environment, capture_output=True, text=True)
        if done.returncode != 0:
            print(done.stdout + done.stderr)
            raise SystemExit(f"validation tests failed (exit {done.returncode}); page unchanged")
        lines = record.read_text().splitlines() if record.exists() else []
    return [json.loads(line) for line in lines]


def _title(file: str) -> str:
    return TOPICS.get(file, file)


def _existing_rows() -> list[tuple[str, ...]]:
    """(test file, check, tolerance, measured) of the committed tables (to keep those of the
    files not rerun): the file is the one whose topic heads the row's table."""
    files = {title: file for file, title in TOPICS.items()}
    rows, file = [], ""
    for line in read_block(DOCUMENT, "validation").splitlines():
        if line.startswith("**") and line.endswith("**"):
            title = line.strip("*")
            file = files.get(title, title)
        elif line.startswith("| ") and not line.startswith(("| check |", "| --- |")):
            cells = [cell.strip().replace("\\|", "|") for cell in line.strip("|").split(" | ")]
            rows.append((file, *cells))
    return rows


def tables(rows: list[tuple[str, ...]]) -> str:
    """One table per topic, in the order of :data:`TOPICS` (a file not listed last)."""
    order = list(TOPICS)
    files = sorted(
        dict.fromkeys(row[0] for row in rows),
        key=lambda file: order.index(file) if file in order else len(order),
    )
    parts = []
    for file in files:
        table = markdown_table(HEADER, [row[1:] for row in rows if row[0] == file])
        parts.append(f"**{_title(file)}**\n\n{table}")
    return "\n".join(parts)


def main(argv: list[str] | None = None) -> int:
    paths = list(sys.argv[1:] if argv is None else argv)
    rows = [
        (
            _test_file(row["test"]),
            row["check"],
            _spaced(row["tolerance"]),
            _spaced(row["measured"]),
        )
        for row in run(paths or ["tests"])
    ]
    if paths:  # keep the rows of the files not rerun
        rerun = {Path(path).name for path in paths}
        rows = [row for row in _existing_rows() if row[0] not in rerun] + rows
    note = "`python scripts/validation.py`"
    header = measured_on(note).rstrip("\n")
    replace_block(DOCUMENT, "validation", header + "\n\n" + tables(rows))
    print(f"{DOCUMENT.relative_to(REPO)}: {len(rows)} rows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
