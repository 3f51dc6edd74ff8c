"""The results schema (engine.schema) is what a real results file holds.

Two tiny studies (16 x 16 mesh, 4 depth layers; one cyclic with a recorded cycle, one static
with two cases) run through the command line in this process (~2 s together). Every dataset of
the written files must be one the schema knows, with exactly its ``units`` and
``description``; every case status and summary status must be a :class:`CaseStatus` value.
"""

from __future__ import annotations

import json

import h5py
import pytest

from engine.cli import main
from engine.schema import (
    ROOT_GRID,
    SUMMARY_COLUMNS,
    CaseStatus,
    case_dataset,
    cycle_group,
    cycle_of_group,
    pending_row,
)
from engine.study.examples import study_toml

STUDIES = {
    "cyclic": dict(
        loading={"kind": "cyclic", "load": 750.0, "steps": 2, "cycles": 200, "record": [100]},
        sweep={"mu1": [0.2], "wear1": [1.33e-7]},
    ),
    "static": dict(
        loading={"kind": "static", "load": 750.0, "steps": 2},
        sweep={"mu1": [0.0, 0.3]},
    ),
}


def _datasets(file: h5py.File) -> dict[str, h5py.Dataset]:
    found: dict[str, h5py.Dataset] = {}

    def collect(name: str, item) -> None:
        if isinstance(item, h5py.Dataset):
            found[name] = item

    file.visititems(collect)
    return found


@pytest.fixture(scope="module", params=sorted(STUDIES))
def results(request, tmp_path_factory):
    """(kind, path) of a completed tiny study of that loading kind."""
    kind = request.param
    folder = tmp_path_factory.mktemp(kind)
    study = folder / f"{kind}.toml"
    study.write_text(
        study_toml(
            name=kind, output=str(folder / f"{kind}.h5"), subsurface={"layers": 4}, **STUDIES[kind]
        )
    )
    assert main([str(study)]) == 0
    return kind, folder / f"{kind}.h5"


def test_every_dataset_has_the_schema_units_and_description(results):
    kind, path = results
    checked = 0
    with h5py.File(path, "r") as file:
        for name, dataset in _datasets(file).items():
            if name.startswith("cases/"):
                relative = name.split("/", 2)[2]
                spec = case_dataset(relative, cyclic=kind == "cyclic")  # KeyError: unknown
            else:
                assert name in ("grid/x", "grid/y"), f"{name}: not in the schema"
                spec = ROOT_GRID[name[-1]]
            assert dataset.attrs["units"] == spec.units, name
            assert dataset.attrs["description"] == spec.description, name
            checked += 1
    assert checked > 30  # the whole case layout, not a handful


def test_the_cyclic_file_has_every_group_of_the_schema(results):
    kind, path = results
    with h5py.File(path, "r") as file:
        case = next(iter(file["cases"].values()))
        groups = set(case) | {f"{top}/{sub}" for top in case for sub in case[top]}
    expected = {"grid", "history", "fields", "subsurface", "fields/final", "subsurface/final"}
    if kind == "cyclic":
        expected |= {"peak_changes", f"fields/{cycle_group(100)}", f"peak_changes/{cycle_group(0)}"}
    assert expected <= groups


def test_statuses_are_schema_values(results):
    _, path = results
    with h5py.File(path, "r") as file:
        for group in file["cases"].values():
            assert group.attrs["status"] == CaseStatus.COMPLETED
            assert type(group.attrs["status"]) is str  # written as plain text
            summary = json.loads(group.attrs["summary"])
            assert summary["status"] == "completed"
            assert list(summary)[: len(SUMMARY_COLUMNS)] == SUMMARY_COLUMNS


def test_unknown_paths_are_rejected_and_groups_round_trip():
    for path in ("history/nonsense", "fields/final/wear", "fields/later/pressure", "extra/x"):
        with pytest.raises(KeyError):
            case_dataset(path)
    assert cycle_of_group(cycle_group(1000)) == 1000
    assert cycle_of_group("final") is None
    assert [status.value for status in CaseStatus] == [
        "pending", "completed", "failed", "interrupted"
    ]  # fmt: skip
    row = pending_row({"case_id": "a", "mu1": 0.1, "loading.load": 5.0}, CaseStatus.FAILED)
    assert type(row["status"]) is str and row["status"] == "failed"
    assert row["loading.load"] == 5.0 and list(row)[: len(SUMMARY_COLUMNS)] == SUMMARY_COLUMNS


def test_one_units_table_for_parameters_columns_and_swept_keys():
    """engine.schema.UNITS: every fixed case parameter, every numeric summary column
    and every key of the engine's own sections a sweep may vary has its unit there; the
    study layer's SWEEPABLE adds the plug-ins' keys from their declarations, and the
    summary's column units read it."""
    from engine import schema
    from engine.geometry import PROFILES
    from engine.output.summary import column_unit
    from engine.study.config import SWEEPABLE
    from engine.study.units import parameter_units, unit_of

    names = [*schema.PARAMETERS, *schema.COLUMN_UNITS, *schema.SWEPT_KEY_UNITS]
    for name in names:
        assert schema.unit_of(name), name
    assert unit_of("alpha") == "mm^3/J"  # a wear law's coefficient: the law declares its unit
    numeric = [c for c in schema.SUMMARY_COLUMNS if c not in schema.TEXT_COLUMNS]
    assert all(schema.unit_of(column) for column in numeric if column != "index")
    assert schema.SWEPT_KEY_UNITS.items() <= SWEEPABLE.items()
    for profile in PROFILES.values():
        for name, key in profile.keys().items():
            assert SWEEPABLE[f"punch.{name}"] == unit_of(f"punch.{name}") == key.unit
    assert all(unit_of(name) for name in SWEEPABLE)
    assert column_unit("loading.load") == "N" and column_unit("alpha") == "mm^3/J"
    assert parameter_units(["loading.amplitude"])["loading.amplitude"] == "mm"
