"""A line (plane-strain) contact's results are per unit length; a 3-D contact's keep theirs.

The same tiny fretting study (force control, wear, a swept force amplitude) and a static one
run on a cylinder (line contact, 32 elements; the fretting one through ``python -m engine`` in
a subprocess, the others through the same command line in this process) and on a sphere
(3-D, 16 x 16): every dataset of the line contact's file carries the 3-D file's unit of the
same path turned per unit length (:func:`engine.schema.contact_units`), the extensive ones
(N, mJ, mm², mm³) change, and the 3-D file holds the tables' units unchanged. The dry run,
the force-bound message and the report say N/mm for the line contact. ~8 s in all.
"""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import pytest

from engine.cli import main
from engine.schema import PER_UNIT_LENGTH, contact_units
from engine.study.examples import CYLINDER_ON_STEEL, SPHERE_ON_STEEL, study_toml
from engine.study.units import parameter_units, unit_of
from tests.test_cli import _engine  # python -m engine in a subprocess (this worktree's engine)

FRETTING = {"kind": "fretting", "load": 185.0, "steps": 2, "cycles": 4, "record": [2, 4]}
STATIC = {"kind": "static", "load": 185.0, "steps": 2}
SWEEP = {"mu1": [0.5], "wear1": [2e-8], "loading.force_amplitude": [20.0, 40.0]}
GEOMETRIES = {
    "line": {**CYLINDER_ON_STEEL, "mesh": {"n": 32, "half_width": 0.25}},
    "sphere": {**SPHERE_ON_STEEL, "mesh": {"n": 16}},
}
#: Datasets whose units a line contact must divide by the length (their 3-D unit, per case).
EXTENSIVE = {
    "history/q_amplitude": "N",
    "history/energy": "mJ",
    "history/wear_volume": "mm^3",
    "history/stick_area": "mm^2",
    "history/slip_area": "mm^2",
    "fields/cycle_0000002/loop": "mm, mm, N, N",
    "fields/cycle_0000004/loop": "mm, mm, N, N",
}


def _units(path: Path) -> dict[str, dict[str, str]]:
    """case id -> (path in the case group -> ``units``), and its ``parameter_units`` under
    the key ``@parameter_units``."""
    found: dict[str, dict[str, str]] = {}
    with h5py.File(path, "r") as file:
        for case_id, group in file["cases"].items():
            units = {"@parameter_units": group.attrs["parameter_units"]}

            def collect(name: str, item, units=units) -> None:
                if isinstance(item, h5py.Dataset):
                    units[name] = str(item.attrs["units"])

            group.visititems(collect)
            found[case_id] = units
    return found


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    """(geometry, kind) -> the results file of the tiny study, written by python -m engine."""
    folder = tmp_path_factory.mktemp("line_units")
    written = {}
    for geometry, layer in GEOMETRIES.items():
        for kind, loading in (("fretting", FRETTING), ("static", STATIC)):
            name = f"{geometry}_{kind}"
            sweep = SWEEP if kind == "fretting" else {"mu1": [0.5]}
            output = str(folder / f"{name}.h5")
            text = study_toml(name, output, layer, loading=loading, sweep=sweep)
            (folder / f"{name}.toml").write_text(text)
            if name == "line_fretting":
                run = _engine(f"{name}.toml", "--no-progress-bar", cwd=folder)
                assert run.returncode == 0, run.stderr
            else:
                assert main([str(folder / f"{name}.toml"), "--no-progress-bar"]) == 0
            written[geometry, kind] = folder / f"{name}.h5"
    return written


def test_contact_units_turn_the_extensive_units_per_unit_length():
    """The table of the conversion, column by column for a table's units; a 3-D contact's
    and the intensive units (lengths, pressures, coefficients) stay as they are."""
    assert contact_units("mm, mm, N, N", line=True) == "mm, mm, N/mm, N/mm"
    assert contact_units("mm, mm, N, N", line=False) == "mm, mm, N, N"
    for unit in ("mm", "MPa", "1", "degree", "1/MPa", "mm^3/J", "s"):
        assert contact_units(unit, line=True) == unit
    assert unit_of("energy_per_cycle", line=True) == "mJ/mm"
    assert unit_of("loading.load", line=True) == "N/mm"
    assert unit_of("loading.load") == "N"
    assert unit_of("wear_volume", line=True) == "mm^2/mm"  # the worn area per mm (scar_area)
    assert parameter_units(["loading.force_amplitude"], line=True)["loading.force_amplitude"] == (
        "N/mm"
    )


@pytest.mark.parametrize("kind", ["fretting", "static"])
def test_line_contact_datasets_are_the_3d_units_per_unit_length(studies, kind):
    """Path by path, the line contact's unit is the sphere's per unit length; the extensive
    datasets are among the paths compared and changed; no line dataset keeps a bare N, mJ,
    mm² or mm³ and the sphere's keep the tables' units."""
    line, sphere = _units(studies["line", kind]), _units(studies["sphere", kind])
    assert line.keys() == sphere.keys() and line
    for case_id, units in line.items():
        common = units.keys() & sphere[case_id].keys()
        assert len(common) > 20  # histories, fields, planes, grid
        for path in sorted(common - {"@parameter_units"}):
            assert units[path] == contact_units(sphere[case_id][path], line=True), path
            assert not set(units[path].split(", ")) & PER_UNIT_LENGTH.keys(), path
        parameters = json.loads(units["@parameter_units"])
        assert parameters == {
            name: contact_units(unit, True)
            for name, unit in json.loads(sphere[case_id]["@parameter_units"]).items()
        }
        if kind == "fretting":
            assert parameters["loading.force_amplitude"] == "N/mm"
            for path, unit in EXTENSIVE.items():
                assert sphere[case_id][path] == unit
                assert units[path] == contact_units(unit, True) != unit
            assert units["fields/cycle_0000004/loop"] == "mm, mm, N/mm, N/mm"
            assert units["history/wear_volume"] == "mm^2/mm"
        else:
            assert (sphere[case_id]["history/load"], units["history/load"]) == ("N", "N/mm")


def _output(capsys, *argv: str) -> str:
    """What ``python -m engine *argv`` prints (in this process), exit code 0 checked."""
    capsys.readouterr()
    assert main(list(argv)) == 0
    return capsys.readouterr().out


def test_dry_run_report_and_messages_say_n_per_mm(studies, tmp_path, capsys):
    """The dry-run header, the fretting report's table and a refused force amplitude name
    the line contact's N/mm; the sphere's say N."""
    line, sphere = studies["line", "fretting"], studies["sphere", "fretting"]
    dry = _output(capsys, str(line.with_suffix(".toml")), "--dry-run")
    assert "fretting, P = 185 N/mm held, force control, force_amplitude 20, 40 N/mm" in dry
    assert "swept: loading.force_amplitude = 20, 40 N/mm" in dry
    dry = _output(capsys, str(sphere.with_suffix(".toml")), "--dry-run")
    assert "fretting, P = 185 N held, force control, force_amplitude 20, 40 N along" in dry
    report = _output(capsys, "report", str(line))
    assert "q_amplitude (N/mm)" in report
    assert "energy_per_cycle (mJ/mm)" in report
    assert "wear volume (mm²/mm)" in report
    assert "P = 185 N/mm (held)" in report
    assert "q_amplitude (N) |" in _output(capsys, "report", str(sphere))
    too_large = study_toml(
        "bound", "bound.h5", GEOMETRIES["line"], loading={**FRETTING, "force_amplitude": 95.0},
        sweep={"mu1": [0.5], "wear1": [2e-8]},
    )  # fmt: skip
    (tmp_path / "bound.toml").write_text(too_large)
    refused = _engine("bound.toml", cwd=tmp_path)
    assert refused.returncode == 2
    assert "force_amplitude = 95 N/mm is not below the friction bound 92.5 N/mm" in (refused.stderr)


def test_thresholds_table_units_follow_the_contact():
    """A search along the load for a tangential force: the table's parameter and value
    columns in N/mm for a line contact, N for a 3-D one; lengths and counts unchanged."""
    from engine.output.thresholds import table_units
    from engine.study.search import SearchSpec

    spec = SearchSpec("loading.load", 50.0, 500.0, "q_amplitude", 40.0, rtol=1e-3)
    rows = [{"case_id": "mu0.5", "mu1": 0.5, "loading.amplitude": 0.002}]
    line, sphere = table_units(rows, spec, line=True), table_units(rows, spec)
    for name in ("threshold", "lower", "upper", "lower_value", "upper_value"):
        assert (sphere[name], line[name]) == ("N", "N/mm"), name
    assert line["loading.amplitude"] == sphere["loading.amplitude"] == "mm"
    assert line["steps"] == sphere["steps"] == ""
