"""``engine.open_results``: a results file as objects with units, and ``.to_xarray()``.

Two tiny studies run once per module (8 × 8 mesh, 4 depth layers; ~1 s each): a cyclic one
(two friction coefficients, 20 cycles, cycle 10 recorded) and a fretting one (energy law).
What the objects give is checked against the file read with h5py and against the results
schema (units and descriptions), so the objects cannot drift from what is stored.
"""

from __future__ import annotations

import pickle
from pathlib import Path

import h5py
import numpy as np
import pytest

import engine
from engine.schema import HISTORY, PLANE, field_dataset
from engine.study.examples import study_toml
from tests.test_api import TOML

xarray = pytest.importorskip("xarray")

CYCLIC = TOML  # two friction coefficients, 20 cycles, cycle 10 recorded
FRETTING = study_toml(
    "loops",
    "loops.h5",
    mesh={"n": 8},
    subsurface={"layers": 4},
    loading={"kind": "fretting", "steps": 2, "cycles": 4, "record": [2], "amplitude": 0.001},
    wear={"law": "energy"},
    sweep={"mu1": [0.6], "alpha": [5e-6]},
)


def _run(folder: Path, text: str, name: str, monkeypatch) -> Path:
    folder.mkdir()
    (folder / f"{name}.toml").write_text(text)
    monkeypatch.chdir(folder)
    run = engine.run_study(f"{name}.toml", progress=False)
    assert run.ok, run
    return folder / f"{name}.h5"


@pytest.fixture(scope="module")
def cyclic(tmp_path_factory):
    with pytest.MonkeyPatch.context() as monkeypatch:
        return _run(tmp_path_factory.mktemp("c") / "run", CYCLIC, "api", monkeypatch)


@pytest.fixture(scope="module")
def fretting(tmp_path_factory):
    with pytest.MonkeyPatch.context() as monkeypatch:
        return _run(tmp_path_factory.mktemp("f") / "run", FRETTING, "loops", monkeypatch)


def test_the_study_its_summary_and_its_cases(cyclic):
    results = engine.open_results(cyclic)
    assert results.name == "api" and results.kind == "cyclic"
    assert results.case_ids == ["mu0.2_w1.33e-07_b0", "mu0.4_w1.33e-07_b0"]
    assert list(results) == results.case_ids and len(results) == 2
    assert results.study["loading"]["cycles"] == 20
    assert list(results.summary["case_id"]) == results.case_ids
    assert repr(results).startswith("<Results 'api': cyclic, 2 cases (2 completed)")
    case = results["mu0.4_w1.33e-07_b0"]
    assert case.completed and case.parameters["mu1"] == 0.4 and case.parameters["beta"] == 0.0
    assert case.parameter_units["wear1"] == "1/MPa"
    assert case.summary["max_wear_depth"] == results.summary["max_wear_depth"].iloc[1]
    assert "completed: beta = 0, mu1 = 0.4" in repr(case)
    with pytest.raises(KeyError, match="no case 'mu9'"):
        results["mu9"]


def test_fields_history_and_planes_are_the_stored_values_with_the_schema_units(cyclic):
    case = engine.open_results(cyclic)["mu0.2_w1.33e-07_b0"]
    assert list(case.fields) == [10, 20, "final"] and case.fields.cycles == [10, 20]
    with h5py.File(cyclic) as file:
        group = file["cases/mu0.2_w1.33e-07_b0"]
        grid_x = group["grid/x"][()]
        pressure = case.fields["final"]["pressure"]
        assert np.array_equal(pressure.values, group["fields/final/pressure"][()])
        assert pressure.units == field_dataset("pressure").units == "MPa"
        assert pressure.dims == ("x", "y")
        assert np.array_equal(pressure.coords["x"][1], grid_x)  # from the dimension scale
        wear = case.fields[10]["wear"]
        assert np.array_equal(wear.values, group["fields/cycle_0000010/wear"][()])
        assert np.array_equal(case.history["wear_volume"], group["history/wear_volume"][()])
        von_mises = case.planes["final"]["von_mises"]
        assert np.array_equal(von_mises.values, group["subsurface/final/von_mises"][()])
    assert case.history["max_wear_depth"].units == HISTORY["max_wear_depth"].units == "mm"
    assert von_mises.units == PLANE["von_mises"].units and von_mises.dims == ("s", "depth")
    assert "pressure" in repr(case.fields["final"]) and "[MPa]" in repr(pressure)


def test_the_figures_and_the_report_read_the_same_objects(cyclic):
    """The figures and the report take the objects open_results gives: the study grid as
    arrays, the completed cases in plan order with their index and parameters, every
    Variable standing for its values in NumPy expressions, each stress plane's peak."""
    results = engine.open_results(cyclic)
    with h5py.File(cyclic) as file:
        assert np.array_equal(results.grid_x, file["grid/x"][()])
        assert np.array_equal(results.grid_y, file["grid/y"][()])
        assert [file["cases"][c].attrs["index"] for c in results.case_ids] == [0, 1]
        for case in results.completed:
            group = file["cases"][case.case_id]
            assert case.mu1 == group.attrs["mu1"] and case.beta == group.attrs["beta"]
            assert case.recorded_cycles == [10, 20] and list(case.fields) == [10, 20, "final"]
            wear = case.fields[20]["wear"]
            stored = group["fields/cycle_0000020/wear"][()]
            assert np.array_equal(wear * 1e3, stored * 1e3)  # an array, the same bits
            assert np.array_equal(np.asarray(wear), stored) and wear[3, 4] == stored[3, 4]
            assert float(np.max(wear)) == float(stored.max()) == wear.max()
            assert np.array_equal(wear.T, stored.T) and wear.argmax() == stored.argmax()
            with pytest.raises(AttributeError):
                wear.no_such_attribute  # noqa: B018 - only NumPy's array attributes pass
            plane = case.planes["final"]
            von_mises = group["subsurface/final/von_mises"][()]
            assert plane.angle == 0.0 and np.array_equal(plane.von_mises, von_mises)
            index = np.unravel_index(np.argmax(von_mises), von_mises.shape)
            assert plane.peak()[0] == von_mises[index]
            assert plane.peak()[1:] == (plane.x[index], plane.z[index])
    assert results.skipped == [] and results.is_cyclic and results.loading_kind.name == "cyclic"
    assert results.radius == results.study["punch"]["radius"]  # a flat punch: a0 = R


def test_a_with_block_keeps_the_file_open_for_many_reads(cyclic):
    """Inside ``with`` the cases read from one open file (closed at the end); outside it,
    each read opens and closes the file; the values are the same."""
    results = engine.open_results(cyclic)
    with results as held:
        assert held is results
        inside = [case.fields["final"]["pressure"].values for case in held.completed]
        with h5py.File(cyclic, "r") as other:  # read-only: other readers are welcome
            assert other["cases"]
    again = engine.open_results(cyclic)
    outside = [case.fields["final"]["pressure"].values for case in again.completed]
    assert all(np.array_equal(a, b) for a, b in zip(inside, outside, strict=True))
    assert results.completed[0].planes["final"]["von_mises"].shape  # after the block: reopens


def test_units_and_descriptions_asked_for_after_the_block_are_those_stored(cyclic):
    """A variable's units, description and other attributes are read when first asked
    for: after the ``with`` block (the file closed) they are still the stored ones, equal
    to those read outside any block, and each grid's coordinates are those of its case."""
    with engine.open_results(cyclic) as results:
        held = [(case.fields, case.planes["final"]) for case in results.completed]
    outside = engine.open_results(cyclic)
    for (fields, plane), case in zip(held, outside.completed, strict=True):
        for key, group in fields.items():
            for name, variable in group.items():
                other = case.fields[key][name]
                assert (variable.units, variable.description, variable.attrs) == (
                    other.units,
                    other.description,
                    other.attrs,
                )
                assert variable.units == field_dataset(name).units
                assert np.array_equal(variable.coords["x"][1], case.grid["x"].values)
        von_mises = plane["von_mises"]
        copied = pickle.loads(pickle.dumps(von_mises))  # a copy reads them by the path
        assert (copied.units, copied.description) == (von_mises.units, von_mises.description)
        assert von_mises.units == PLANE["von_mises"].units == "MPa"
        assert von_mises.description == case.planes["final"]["von_mises"].description != ""


def test_a_peak_change_holds_a_plane_and_surface_fields(cyclic):
    """peak_changes/cycle_N: the plane's datasets on (s, depth), the surface fields beside
    it on (x, y) with the grid as coordinates; both in one xarray.Dataset."""
    case = engine.open_results(cyclic)["mu0.2_w1.33e-07_b0"]
    group = case.peak_changes[case.peak_changes.cycles[0]]
    assert group["von_mises"].dims == ("s", "depth") and group["pressure"].dims == ("x", "y")
    assert np.array_equal(group["pressure"].coords["x"][1], case.grid["x"].values)
    dataset = group.to_xarray()
    assert dataset["pressure"].dims == ("x", "y") and dataset["von_mises"].dims == ("s", "depth")


def test_to_xarray_takes_coordinates_from_the_file(cyclic):
    case = engine.open_results(cyclic)["mu0.2_w1.33e-07_b0"]
    final = case.fields["final"].to_xarray()
    assert np.array_equal(final["x"].values, case.grid["x"].values)
    assert final["pressure"].attrs["units"] == "MPa" and final["x"].attrs["units"] == "mm"
    recorded = case.fields.to_xarray()  # the recorded cycles along "cycle"
    assert list(recorded["cycle"].values) == [10, 20]
    assert np.array_equal(recorded["wear"].sel(cycle=10).values, case.fields[10]["wear"].values)
    assert "each recorded cycle" in recorded["wear"].attrs["description"]
    plane = case.planes["final"].to_xarray()
    z = case.planes["final"]["z"].values
    assert np.array_equal(plane["depth"].values, z[0])  # the evaluated depths (mm)
    assert np.array_equal(plane["s"].values, case.planes["final"]["x"].values[:, 0])
    assert plane["von_mises"].dims == ("s", "depth")
    history = case.history.to_xarray()
    assert np.array_equal(history["cycle"].values, case.history["cycle"].values)


def test_a_fretting_loop_has_its_columns_as_a_coordinate(fretting):
    results = engine.open_results(fretting)
    case = results.completed[0]
    assert case.parameters["alpha"] == 5e-6 and case.parameters["wear1"] == 0.0
    assert case.parameter_units["alpha"] == "mm^3/J"
    loop = case.fields[2]["loop"]
    assert loop.dims == ("loop_row", "loop_column") and loop.units == "mm, mm, N, N"
    dataset = case.fields.to_xarray()
    assert list(dataset["loop_column"].values) == ["delta_x", "delta_y", "Q_x", "Q_y"]
    assert dataset["loop"].shape == (2, 4 * 2 + 1, 4)  # two recorded cycles: 2 and the last


def test_a_file_that_is_not_a_results_file_is_refused(tmp_path):
    with pytest.raises(FileNotFoundError):
        engine.open_results(tmp_path / "none.h5")
    with h5py.File(tmp_path / "other.h5", "w") as file:
        file["x"] = [1.0]
    with pytest.raises(ValueError, match="not a results file"):
        engine.open_results(tmp_path / "other.h5")
