"""Write the generated reference of the manual from the engine's own definitions.

    python scripts/reference.py           # rewrite the generated blocks of docs/reference/
    python scripts/reference.py --check   # exit 1 when a committed block differs (tests do this)

Blocks (between ``<!-- BEGIN generated NAME -->`` and ``<!-- END generated NAME -->``):

- ``docs/reference/study-file.md``, ``study-keys``: every key of every section, with its type,
  default, unit and meaning (``engine/study/config/keys.toml`` and the built-in plug-ins'
  declarations, :mod:`engine.study.config.keys`), and ``sweepable-keys``: the
  dotted keys ``[sweep]`` accepts (``sweepable_keys`` of the study configuration, over the
  built-in profiles and criteria: the manual describes the engine, not what else is
  installed), ``limits``: every range the checks enforce, from the declarations they use, and
  ``bundled-studies``: every study of ``studies/`` with the title and time of its header;
- ``docs/reference/outputs.md``, ``summary-columns``: every summary column with its unit and
  meaning, and ``datasets``: every dataset of a case group with its units and description
  (:mod:`engine.schema`, the table the writers and the reader share), and ``calibration``:
  the columns, attributes and subgroups of ``/calibration`` (:mod:`engine.output.calibration`);
- ``docs/reference/exit-codes.md``, ``exit-codes-run`` and ``exit-codes-verify``: what each
  exit code of a study run and of ``verify`` means, and ``run-statuses``: what a run can end
  as and the code of each (:mod:`engine.exit_codes`); ``docs/how-to/slurm.md``,
  ``slurm-exit-codes``: what the batch script does with each code;
- ``docs/reference/cli.md``, ``cli-run``, ``cli-plot``, ``cli-report``, ``cli-verify``: the
  help of each command as ``python -m engine`` prints it.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

from engine import exit_codes, schema
from engine.analysis.markdown import markdown_table, read_block, replace_block
from engine.fatigue import CRITERIA
from engine.geometry import PROFILES
from engine.solvers.wear_laws import WEAR_LAWS, wear_coefficients
from engine.study.config.keys import SECTIONS, STUDY_KEYS
from engine.study.fatigue import fatigue_history, fatigue_map_specs
from engine.study.units import summary_columns as described_columns
from engine.study.units import sweepable_keys as swept_key_units

# The manual describes the engine: its own profiles and criteria, whatever else is installed.
BUILT_IN = {
    "profiles": PROFILES.builtins,
    "criteria": CRITERIA.builtins,
    "wear_laws": WEAR_LAWS.builtins,
}

REPO = Path(__file__).resolve().parents[1]
STUDY_FILE = REPO / "docs" / "reference" / "study-file.md"
OUTPUTS = REPO / "docs" / "reference" / "outputs.md"
CLI = REPO / "docs" / "reference" / "cli.md"
EXIT_CODES = REPO / "docs" / "reference" / "exit-codes.md"
SLURM = REPO / "docs" / "how-to" / "slurm.md"


def _code(text: str) -> str:
    return f"`{text}`"


def _units(units: str) -> str:
    """A 3-D contact's ``units``, and a line contact's (per unit length) where they differ."""
    line = schema.contact_units(units, line=True)
    return units if line == units else f"{units} (line contact: {line})"


def study_keys() -> str:
    """One table per section: key, type, default, unit, meaning."""
    parts = []
    for section, what in SECTIONS.items():
        keys = [key for key in STUDY_KEYS if key.section == section]
        parts.append(f"### `[{section}]`: {what}\n")
        rows = [(_code(k.name), k.type, k.default, _units(k.unit), k.meaning) for k in keys]
        parts.append(markdown_table(("key", "type", "default", "unit", "meaning"), rows))
    return "\n".join(parts)


def sweepable_keys() -> str:
    """The dotted keys of ``[sweep]`` with their units, then the text keys (lists of strings)."""
    rows = [
        (_code(f'"{key}"'), _units(unit))
        for key, unit in swept_key_units(BUILT_IN["profiles"], BUILT_IN["criteria"]).items()
    ]
    rows += [(_code(f'"{key}"'), "– (a list of texts)") for key in schema.SWEPT_TEXT_KEYS]
    return markdown_table(("dotted key", "unit"), rows)


def summary_columns() -> str:
    """Every summary column: the common ones, then the fretting, energy-law and fatigue
    criteria's ones (the criteria's from their declarations)."""
    described = described_columns(BUILT_IN["criteria"], BUILT_IN["wear_laws"])
    common = list(schema.SUMMARY_COLUMNS)
    extra = [column for column in described if column not in common]
    rows = [
        (
            _code(column),
            "–" if column in schema.TEXT_COLUMNS else _units(described[column][0] or "1"),
            described[column][1],
        )
        for column in common + extra
    ]
    return markdown_table(("column", "unit", "meaning"), rows)


def _dataset_rows(prefix: str, table: dict[str, schema.DatasetSpec], names=None):
    names = table if names is None else names
    return [
        (_code(f"{prefix}/{name}"), _units(table[name].units), table[name].description)
        for name in names
    ]


def datasets() -> str:
    """Every dataset of a case group ``/cases/<case_id>/``, with units and description."""
    cycle = "cycle_NNNNNNN"
    rows = _dataset_rows("grid", schema.CASE_GRID)
    rows += _dataset_rows("history", schema.HISTORY)
    rows += _dataset_rows("history", schema.FRETTING_HISTORY)
    rows += _dataset_rows("history", schema.STATIC_HISTORY)
    rows += _dataset_rows("fields/final", schema.FIELDS, schema.FINAL_FIELDS)
    rows += _dataset_rows(f"fields/{cycle}", schema.FIELDS, schema.RECORDED_FIELDS)
    rows += _dataset_rows(f"fields/{cycle}", schema.FRETTING_RECORDS)
    rows += _dataset_rows("subsurface/final", schema.PLANE)
    rows += _dataset_rows(f"peak_changes/{cycle}", schema.FIELDS, schema.PEAK_CHANGE_FIELDS)
    rows += _dataset_rows("history", fatigue_history(BUILT_IN["criteria"]))  # every_cycle
    rows += _dataset_rows(f"fatigue/{cycle}", fatigue_map_specs("N", BUILT_IN["criteria"]))
    rows += _dataset_rows("surface", schema.SURFACE_DATASETS)  # [surface]
    return markdown_table(("path in the case group", "units", "description"), rows)


def calibration() -> str:
    """The group ``/calibration`` of a calibration's results file: its columns (after the
    tests' own keys), attributes and subgroups (:mod:`engine.output.calibration`)."""
    from engine.output import calibration as table

    rows = [(_code(name), unit, meaning) for name, (unit, meaning) in table.COLUMNS.items()]
    columns = markdown_table(("dataset", "unit", "meaning"), rows)
    rows = [(_code(name), meaning) for name, meaning in table.GROUP_ATTRIBUTES.items()]
    rows += [
        (_code(f"{name}/"), f"subgroup: {meaning}") for name, meaning in table.SUBGROUPS.items()
    ]
    return columns + "\n" + markdown_table(("attribute or subgroup", "meaning"), rows)


def _header_title(line: str) -> str:
    """The study's first header line up to its first colon, semicolon or parenthesis."""
    title = line.removeprefix("#").strip()
    for mark in (":", ";", " ("):
        title = title.split(mark, 1)[0]
    return title.strip()


def _header_time(lines: list[str]) -> str:
    """What the header's ``# Time: …`` line says (written by scripts/study_times.py from a
    run it timed, with the date, machine and load average), or that it is not measured."""
    for line in lines:
        if line.startswith("# Time: "):
            text = line.removeprefix("# Time: ").strip().rstrip(".")
            if text.startswith("not measured"):
                return "not measured"
            return text.replace("`", "").replace("|", "\\|")
    return "–"


def bundled_studies() -> str:
    """Every study of ``studies/``: what it computes and how long it takes, from its header."""
    rows = []
    for path in sorted((REPO / "studies").glob("*.toml")):
        header = [line for line in path.read_text().splitlines() if line.startswith("#")]
        title = _header_title(header[0]) if header else "–"
        rows.append((f"`studies/{path.name}`", title, _header_time(header)))
    return markdown_table(("file", "what it computes", "time (from its header)"), rows)


def _number(value: float) -> str:
    return f"{value:g}".replace("e+0", "e").replace("e+", "e")


def limit_rows() -> list[tuple[str, str, str, str]]:
    """(dotted key, accepted values, unit, why) of every range the study checks enforce, read
    from the declarations the checks themselves use: ``LIMITS`` of
    ``engine.study.settings.checks``, the bounds the built-in loading kinds declare for their
    ``[loading]`` numbers and the profiles for their ``[punch]`` keys, and the constants'
    ranges the built-in criteria declare."""
    from engine.fatigue import CRITERIA
    from engine.geometry import PROFILES
    from engine.keys import declared_keys
    from engine.study import fatigue
    from engine.study.settings import checks

    units = {f"{key.section}.{key.name}": key.unit for key in STUDY_KEYS}
    units |= {"search.rtol": "1", "search.atol": "unit of the parameter", "search.max_steps": "1"}
    units |= {"calibrate.fit_rtol": "1", "calibrate.max_evaluations": "1"}
    rows = [(
        "loading.load",
        f"{_number(checks.MIN_PRESSURE_OVER_MODULUS)} ≤ p0/E* ≤ "
        f"{_number(checks.MAX_PRESSURE_OVER_MODULUS)}",
        "N (N/mm for line contacts)",
        "p0 the mean pressure over the nominal contact: the half-space is linear elastic "
        "(small strains)",
    )]  # fmt: skip
    host = list(checks.LIMITS.items())
    after_material = next(i for i, (key, _) in enumerate(host) if not key.startswith("material."))
    for index, (dotted, limit) in enumerate(host):
        key = dotted.removesuffix(".energy")
        if index == after_material:  # the loading kinds' declared ranges after the material's
            rows += loading_limit_rows()
        if key == "sweep.beta":  # the wear laws' coefficients before: their declared ranges
            for name, declared in wear_coefficients(BUILT_IN["wear_laws"]).items():
                rows.append((f"sweep.{name}", checks.Limit.of(declared).accepted, declared.unit,
                             declared.why))  # fmt: skip
        unit = "mm³/J" if dotted.endswith(".energy") else units[key]
        if key == "wear.pad_coefficient":
            unit = "mm³/J (energy law)" if dotted.endswith(".energy") else "1/MPa (Archard)"
        rows.append((key, limit.accepted, unit, limit.why))
    punch_keys: dict[str, object] = {}
    for profile in PROFILES.builtins.values():  # the [punch] keys each shape declares
        for name, key in declared_keys(profile).items():
            punch_keys.setdefault(f"punch.{name}", key)
    for dotted, key in punch_keys.items():
        if key.minimum is not None or key.maximum is not None:
            limit = checks.Limit(key.minimum, key.maximum, key.why, open_minimum=key.strict)
            rows.append((dotted, limit.accepted, key.unit, key.why or "–"))
    from engine.surface import config as surface

    for name, (low, high, why) in surface.RANGES.items():
        open_low = (name, "minimum") in surface.OPEN_ENDS
        open_high = (name, "maximum") in surface.OPEN_ENDS
        if isinstance(high, str):  # relative to the mesh
            low = low if isinstance(low, str) else _number(low)
            accepted = f"{'(' if open_low else '['}{low}, {high}]"
        else:
            accepted = checks.Limit(low, high, why, open_low, open_high).accepted
        rows.append((f"surface.{name}", accepted, units[f"surface.{name}"], why))
    for name, key in fatigue.constant_ranges(CRITERIA.builtins).items():
        rows.append((f"fatigue.{name}", checks.Limit.of(key).accepted, key.unit, key.why))
    rows.append(("fatigue.length", f"(0, {_number(fatigue.MAX_LENGTH)}]", "mm",
                 "the critical distance"))  # fmt: skip
    rows.append(("fatigue.plane_step", f"(0, {_number(fatigue.MAX_PLANE_STEP)}]", "degree",
                 "the step of the critical-plane search; it must divide 180"))  # fmt: skip
    return rows


def loading_limit_rows(kinds=None) -> list[tuple[str, str, str, str]]:
    """(dotted key, accepted values, unit, why) of every ``[loading]`` number whose range the
    kinds of ``kinds`` (default: the built-in ones) declare, in the order of their sections;
    keys declared alike one after the other share a row (the two bulk stresses)."""
    from engine.study.kinds import KINDS
    from engine.study.settings.checks import Limit

    declared: dict = {}
    for kind in (KINDS.builtins if kinds is None else kinds).values():
        for name, key in kind.declared_keys().items():
            declared.setdefault(name, key)
    rows: list[tuple[str, str, str, str]] = []
    for name, key in declared.items():
        if key.minimum is None and key.maximum is None:
            continue
        row = (f"loading.{name}", Limit.of(key).accepted, key.unit, key.why)
        if rows and rows[-1][1:] == row[1:]:
            rows[-1] = (f"{rows[-1][0]}, {name}", *row[1:])
        else:
            rows.append(row)
    return rows


def limits() -> str:
    """Every range a value of a study file must lie in, with its unit and why."""
    rows = [(f"`{key}`", accepted, unit, why) for key, accepted, unit, why in limit_rows()]
    return markdown_table(("key", "accepted", "unit", "why"), rows)


def _help(*command: str) -> str:
    """``python -m engine ... --help`` at a fixed width, in a text block."""
    environment = dict(os.environ, COLUMNS="100", FRETTING_ENGINE_BUILT_IN_ONLY="1")
    done = subprocess.run(
        [sys.executable, "-m", "engine", *command, "--help"],
        capture_output=True, text=True, check=True, env=environment, cwd=REPO,
    )  # fmt: skip
    title = " ".join(("python -m engine", *command, "--help"))
    return f"`{title}`:\n\n```text\n{done.stdout.rstrip()}\n```\n"


def exit_code_table(meanings, launcher=None) -> str:
    """The exit codes of a command and what each means."""
    return markdown_table(("code", "meaning"), exit_codes.markdown_rows(meanings, launcher))


def run_statuses() -> str:
    """What a study run can end as (``StudyRun.status``) and the exit code of each."""
    rows = [
        (_code(status.name), str(status.code.value), status.meaning)
        for status in exit_codes.RUN_STATUSES
    ]
    return markdown_table(("status", "exit code", "meaning"), rows)


def slurm_exit_codes() -> str:
    """What the batch script does with each exit code of the engine: 3 (interrupted) is the
    only one it requeues on; every other code ends the job."""
    rows = []
    for meaning in exit_codes.STUDY_RUN:
        statuses = [s.name for s in exit_codes.RUN_STATUSES if s.code == meaning.code]
        then = (
            "the pre-timeout signal: requeued (or chained) and resumed, up to `MAX_RESTARTS`; "
            "`scancel`: CANCELLED, resubmit to resume (the table above)"
            if meaning.code == exit_codes.ExitCode.INTERRUPTED
            else "ends COMPLETED" if meaning.code == exit_codes.ExitCode.OK
            else "ends FAILED, never requeued"
        )  # fmt: skip
        status = ", ".join(_code(name) for name in statuses) or "–"
        rows.append((str(meaning.code.value), status, meaning.short, then))
    return markdown_table(("exit code", "run status", "meaning", "the job"), rows)


BLOCKS = {
    (STUDY_FILE, "study-keys"): study_keys,
    (STUDY_FILE, "sweepable-keys"): sweepable_keys,
    (STUDY_FILE, "bundled-studies"): bundled_studies,
    (STUDY_FILE, "limits"): limits,
    (OUTPUTS, "summary-columns"): summary_columns,
    (OUTPUTS, "datasets"): datasets,
    (OUTPUTS, "calibration"): calibration,
    (EXIT_CODES, "exit-codes-run"): lambda: exit_code_table(
        exit_codes.STUDY_RUN, exit_codes.LAUNCHER
    ),
    (EXIT_CODES, "exit-codes-verify"): lambda: exit_code_table(exit_codes.VERIFY),
    (EXIT_CODES, "run-statuses"): run_statuses,
    (SLURM, "slurm-exit-codes"): slurm_exit_codes,
    (CLI, "cli-run"): lambda: _help(),
    (CLI, "cli-plot"): lambda: _help("plot"),
    (CLI, "cli-report"): lambda: _help("report"),
    (CLI, "cli-verify"): lambda: _help("verify"),
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare, do not write")
    args = parser.parse_args(argv)
    stale = []
    for (document, name), generate in BLOCKS.items():
        text = generate()
        if args.check:
            if read_block(document, name).rstrip("\n") != text.rstrip("\n"):
                stale.append(f"{document.relative_to(REPO)}: block {name}")
        elif replace_block(document, name, text):
            print(f"{document.relative_to(REPO)}: rewrote the block {name}")
    if stale:
        print("out of date (run python scripts/reference.py):\n" + "\n".join(stale))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
