"""Output layer (single writer, file layout, summary) and the scheduler with a trivial callable.

These run serially (one rank, ``MPI.COMM_SELF``); tests/mpi runs the real thing on two ranks.
"""

from __future__ import annotations

import json
import threading

import h5py
import numpy as np
import pandas as pd
import pytest

from engine import load_summary
from engine.output.hdf5 import FORMAT, ResultsMismatch, SingleWriter, StudyMetadata
from engine.output.summary import SUMMARY_COLUMNS
from engine.parallel.scheduler import Scheduler
from engine.study.case import CaseOutcome, DatasetRecord
from engine.study.config import parse_study
from engine.study.plan import make_plan
from tests.test_config import VALID


def metadata(config, fingerprint=None):
    return StudyMetadata(
        name="t",
        source="t.toml",
        study_toml=config.to_toml(),
        study_json=config.to_json(),
        fingerprint=fingerprint or config.fingerprint(),
        command_line="python -m engine t.toml",
        version="0",
        grid_x=np.arange(4.0),
        grid_y=np.arange(4.0),
    )


def fake_outcome(case, status="completed"):
    row = {
        **case.parameters(),
        "status": status,
        "cycles": 100,
        "load": 750.0,
        "approach": 1e-3,
        "p0": 73.68,
        "max_wear_depth": case.mu1 * 1e-3,
        "wear_volume": 2e-3,
        "vm_max": 100.0,
        "vm_max_x": 1.7,
        "vm_max_y": 0.0,
        "vm_max_z": 0.0,
        "vm_sub_max": 90.0,
        "vm_sub_max_x": 0.0,
        "vm_sub_max_y": 0.0,
        "vm_sub_max_z": 1.2,
        "stick_fraction": 0.5,
        "load_steps": 40,
        "matvecs": 1234,
        "runtime_s": 1.5,
    }
    datasets = {
        "history/cycle": DatasetRecord(np.arange(1, 11), "1", "cycle"),
        "history/max_wear_depth": DatasetRecord(np.linspace(0, 1e-3, 10), "mm", "depth"),
        "fields/final/pressure": DatasetRecord(np.ones((4, 4)), "MPa", "pressure"),
        "grid/x": DatasetRecord(np.linspace(-1.5, 1.5, 4), "mm", "element-centre x"),
        "grid/y": DatasetRecord(np.linspace(-1.5, 1.5, 4) + 10.0, "mm", "element-centre y"),
    }
    if status != "completed":
        datasets = {}
        row = {**case.parameters(), "status": status}
    return CaseOutcome(
        case,
        status,
        row=row,
        datasets=datasets,
        message="boom" * (status == "failed"),
        traceback="Traceback ..." * (status == "failed"),
        runtime_s=1.5,
        rank=0,
    )


@pytest.fixture
def study(tmp_path):
    config = parse_study(VALID)
    return config, make_plan(config), tmp_path / "r.h5"


def test_layout_units_attributes_and_completion_flag(study):
    config, plan, path = study
    with SingleWriter(path) as writer:
        assert writer.prepare(plan, metadata(config)) == set()
        writer.write(fake_outcome(plan.cases[0]))
        writer.write(fake_outcome(plan.cases[1], "failed"))
    with h5py.File(path, "r") as file:
        assert file.attrs["format"] == FORMAT
        assert "[loading]" in file.attrs["study_toml"]
        assert file.attrs["command_line"].startswith("python -m engine")
        assert file["grid/x"].attrs["units"] == "mm"
        done = file["cases"][plan.cases[0].case_id]
        assert done.attrs["status"] == "completed"
        assert done.attrs["mu1"] == plan.cases[0].mu1
        assert json.loads(done.attrs["parameter_units"])["beta"] == "degree"
        assert done["history/max_wear_depth"].attrs["units"] == "mm"
        failed = file["cases"][plan.cases[1].case_id]
        assert failed.attrs["status"] == "failed"
        assert failed.attrs["message"] == "boom" and failed.attrs["traceback"]
        # every planned case has a group from the start (pre-created from the plan)
        assert set(file["cases"]) == set(plan.case_ids)
        assert file["cases"][plan.cases[2].case_id].attrs["status"] == "pending"


def test_grid_coordinates_are_dimension_scales_of_the_surface_fields(study):
    """A case's grid/x and grid/y are HDF5 dimension scales attached to axes 0 and
    1 of its surface fields (ij indexing), history arrays are left alone, and the shared root
    grid is marked as a scale too."""
    config, plan, path = study
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        writer.write(fake_outcome(plan.cases[0]))
    with h5py.File(path, "r") as file:
        case = file["cases"][plan.cases[0].case_id]
        pressure = case["fields/final/pressure"]
        assert pressure.dims[0][0] == case["grid/x"] and pressure.dims[1][0] == case["grid/y"]
        assert list(pressure.dims[0].keys()) == ["x"] and list(pressure.dims[1].keys()) == ["y"]
        np.testing.assert_array_equal(pressure.dims[1]["y"][()], case["grid/y"][()])
        assert len(case["history/cycle"].dims[0]) == 0
        assert file["grid/x"].is_scale and file["grid/y"].is_scale


def test_summary_from_h5_and_csv_agree(study):
    config, plan, path = study
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        for case in plan:
            writer.write(fake_outcome(case))
    from_h5 = load_summary(path)
    from_csv = load_summary(path.with_suffix(".csv"))
    assert list(from_h5.columns[: len(SUMMARY_COLUMNS)]) == SUMMARY_COLUMNS
    assert len(from_h5) == len(plan)
    assert list(from_h5["case_id"]) == list(plan.case_ids)  # plan order
    pd.testing.assert_frame_equal(from_h5, from_csv, check_exact=True)


def test_resume_keeps_completed_and_resets_the_rest(study):
    config, plan, path = study
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        writer.write(fake_outcome(plan.cases[0]))
        writer.write(fake_outcome(plan.cases[1], "interrupted"))
        writer.write(fake_outcome(plan.cases[2], "failed"))
    with SingleWriter(path) as writer:
        completed = writer.prepare(plan, metadata(config))
    assert completed == {plan.cases[0].case_id}
    with h5py.File(path, "r") as file:
        statuses = [file["cases"][cid].attrs["status"] for cid in plan.case_ids]
        assert statuses == ["completed", "pending", "pending", "pending"]
        assert "history" in file["cases"][plan.cases[0].case_id]


def test_resume_refuses_another_study_without_touching_the_file(study):
    config, plan, path = study
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        writer.write(fake_outcome(plan.cases[0]))
    before = path.read_bytes()
    with pytest.raises(ResultsMismatch, match="--fresh"):
        SingleWriter(path).prepare(plan, metadata(config, fingerprint="other"))
    assert path.read_bytes() == before


class _Outcome:
    def __init__(self, case_id, status):
        self.case_id, self.status, self.rank = case_id, status, -1


class _Case:
    def __init__(self, case_id):
        self.case_id = case_id


def test_scheduler_single_rank_runs_every_case_once():
    from mpi4py import MPI

    calls = []

    def run_case(case, should_stop):
        calls.append(case.case_id)
        return _Outcome(case.case_id, "completed")

    seen = []
    report = Scheduler(MPI.COMM_SELF, run_case).run([_Case(f"c{i}") for i in range(5)], seen.append)
    assert sorted(calls) == [f"c{i}" for i in range(5)]
    assert [outcome.rank for outcome in seen] == [0] * 5
    assert report.cases_per_rank == {0: 5} and not report.stopped


def test_scheduler_stop_interrupts_and_hands_out_nothing_more():
    from mpi4py import MPI

    stop = threading.Event()

    def run_case(case, should_stop):
        if case.case_id == "c1":
            stop.set()  # as a signal handler would
        return _Outcome(case.case_id, "interrupted" if should_stop() else "completed")

    report = Scheduler(MPI.COMM_SELF, run_case, stop_event=stop).run(
        [_Case(f"c{i}") for i in range(5)]
    )
    assert report.stopped
    assert report.statuses == {"c0": "completed", "c1": "interrupted"}
    assert report.not_started == ["c2", "c3", "c4"]


def test_scheduler_surfaces_exceptions_of_run_case():
    from mpi4py import MPI

    def run_case(case, should_stop):
        raise ValueError("bug")

    with pytest.raises(RuntimeError, match="run_case raised"):
        Scheduler(MPI.COMM_SELF, run_case).run([_Case("c0")])


def test_low_level_writes_make_the_objects_h5py_makes(tmp_path):
    """engine.output.lowlevel (the per-case writes) against h5py's high-level calls:
    same datatypes (variable-length UTF-8 for str), shapes, values and creation properties, an
    existing attribute replaced, intermediate groups created."""
    from engine.output.lowlevel import create_dataset, set_attribute

    values = {"s": "text", "i": 3, "f": 2.5, "n": np.float64(1.5), "k": np.int64(4), "b": True}
    values["list"] = [1.0, 2.0]
    arrays = {"a": np.arange(6.0).reshape(2, 3), "s": np.zeros((2, 2), np.int8), "e": np.zeros(0)}
    path = tmp_path / "t.h5"
    with h5py.File(path, "w") as file:
        high, low = file.create_group("high"), file.create_group("low")
        for name, value in values.items():
            high.attrs[name] = value
            set_attribute(low, name, value)
        high.attrs["s"] = "replaced"
        set_attribute(low, "s", "replaced")
        for name, array in arrays.items():
            high.create_dataset(f"g/h/{name}", data=array)
            create_dataset(low, f"g/h/{name}", array)
    with h5py.File(path, "r") as file:
        for name in values:
            a, b = file["high"].attrs.get_id(name), file["low"].attrs.get_id(name)
            assert a.get_type().equal(b.get_type()) and a.shape == b.shape, name
            np.testing.assert_array_equal(file["high"].attrs[name], file["low"].attrs[name])
        assert file["low"].attrs["s"] == "replaced"
        for name in arrays:
            a, b = file["high/g/h"][name], file["low/g/h"][name]
            assert a.id.get_type().equal(b.id.get_type()) and a.shape == b.shape, name
            np.testing.assert_array_equal(a[()], b[()])
            created_a, created_b = a.id.get_create_plist(), b.id.get_create_plist()
            assert created_a.get_layout() == created_b.get_layout()
            assert created_a.get_obj_track_times() == created_b.get_obj_track_times()
            assert created_a.get_fill_time() == created_b.get_fill_time()
        assert isinstance(file["low/g/h"], h5py.Group)


def test_low_level_writes_through_identifiers_make_the_same_objects(tmp_path):
    """The per-case path: ``create_dataset(wrap=False)`` (a DatasetID), attributes of a new
    dataset with ``new=True``, ``make_scale`` and ``attach_scales`` on identifiers — read back
    through h5py's ``dims`` API like ``make_scale``/``attach_scale`` of the high-level API."""
    from engine.output.lowlevel import attach_scales, create_dataset, make_scale, set_attribute

    grid = {"x": np.arange(3.0), "y": np.arange(4.0)}
    path = tmp_path / "t.h5"
    with h5py.File(path, "w") as file:
        high, low = file.create_group("high"), file.create_group("low")
        for name, values in grid.items():
            high.create_dataset(f"grid/{name}", data=values).make_scale(name)
            dataset = create_dataset(low, f"grid/{name}", values, wrap=False)
            assert isinstance(dataset, h5py.h5d.DatasetID)
            make_scale(dataset, name)
        field = high.create_dataset("fields/p", data=np.ones((3, 4)))
        field.attrs["units"] = "MPa"
        field.attrs["flag"] = True  # a value h5py converts itself
        field.dims[0].attach_scale(high["grid/x"])
        field.dims[1].attach_scale(high["grid/y"])
        field_id = create_dataset(low, "fields/p", np.ones((3, 4)), wrap=False)
        set_attribute(field_id, "units", "MPa", new=True)
        set_attribute(field_id, "flag", True, new=True)
        attach_scales(field_id, (low["grid/x"].id, low["grid/y"]))
    with h5py.File(path, "r") as file:
        for side in ("high", "low"):
            field = file[f"{side}/fields/p"]
            assert [dim.label for dim in field.dims] == ["", ""]
            assert [dim[0].name for dim in field.dims] == [f"/{side}/grid/x", f"/{side}/grid/y"]
            assert [dim.keys() for dim in field.dims] == [["x"], ["y"]]
            assert file[f"{side}/grid/x"].is_scale and file[f"{side}/grid/y"].is_scale
            assert field.attrs["units"] == "MPa" and field.attrs["flag"]
        for name in ("CLASS", "NAME"):
            a, b = (file[f"{side}/grid/x"].attrs.get_id(name) for side in ("high", "low"))
            assert a.get_type().equal(b.get_type()) and a.shape == b.shape, name


def test_summary_csv_is_byte_for_byte_what_pandas_writes(study):
    # The engine writes the CSV without pandas (summary_csv); users read it with pandas.
    # The text must be exactly pandas' to_csv of summary_frame, for every kind of value a
    # row can hold: pending and completed rows, NaN and None, −0.0, integers given as
    # floats, tiny and huge floats, text with commas and quotes, and swept extra columns
    # (all integers, integers with a gap, floats, booleans, text, nothing).
    import io

    from engine.output.summary import summary_csv, summary_frame
    from engine.schema import pending_row

    config, plan, _ = study
    completed = [fake_outcome(case).row for case in plan.cases[:2]]
    completed[0].update(approach=-0.0, wear_volume=1e-300, vm_max=1.7976931348623157e308)
    completed[1].update(cycles=100.0, matvecs=1234.0, vm_max_x=float("nan"), load_steps=None)
    completed[1]["status"] = 'failed: "x", y'
    pending = [pending_row(case.parameters()) for case in plan.cases[2:]]
    extras = {
        "mesh.n": [16, 32, 64, 128],
        "loading.load": [500, 750.5, None, 1e-7],
        "subsurface.layers": [4, None, 8, 12],
        "flag": [True, False, None, True],
        "punch.shape": ["flat", "sphere", None, "rounded, r=1"],
        "nothing": [None, None, None, None],
        "zero": [-0.0, 0.0, 1.0, float("nan")],
    }
    rows = completed + pending
    for index, row in enumerate(rows):
        row.update({key: values[index] for key, values in extras.items()})
    for case in (rows, rows[:1], pending, []):
        expected = io.StringIO()
        summary_frame(case).to_csv(expected, index=False)
        assert summary_csv(case) == expected.getvalue()
