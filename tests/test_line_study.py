"""Line (plane-strain) contacts through the study layer: a cylinder on a flat, static and
fretting (displacement and force control, bulk stress, two-body wear), run by run_study."""

import csv

import h5py
import numpy as np
import pytest

from engine.reference import line_contact as ref
from engine.run import run_study
from engine.study.config import StudyConfigError, parse_study
from engine.study.examples import CYLINDER_ON_STEEL, study_toml

LOAD = 185.0  # N/mm
E_STAR = 200e3 / (2 * (1 - 0.3**2))
HALF_WIDTH = ref.hertz_line_half_width(LOAD, 6.0, E_STAR)


def _summary(path):
    with open(path.with_suffix(".csv")) as handle:
        return list(csv.DictReader(handle))


def test_static_cylinder_study_gives_hertz(tmp_path):
    """128 elements over ±0.25 mm (58 across the contact): p_max within 1 % of p0, the
    half-width within one element (as the solver's validation), fields of shape (n, 1)."""
    output = tmp_path / "static.h5"
    text = study_toml(
        "line_static",
        str(output),
        CYLINDER_ON_STEEL,
        mesh={"n": 128},
        loading={"kind": "static", "load": LOAD, "steps": 2},
        sweep={"mu1": [0.0]},
    )
    run = run_study(text, progress=False)
    assert run.status == "completed", run
    (row,) = _summary(output)
    assert row["status"] == "completed"
    assert float(row["p0"]) == pytest.approx(LOAD / (2 * HALF_WIDTH), rel=1e-12)
    with h5py.File(output) as results:
        (case,) = results["cases"].values()
        pressure = case["fields/final/pressure"][...]
        assert pressure.shape == (128, 1)
        x = case["grid/x"][...]
        assert case["subsurface/final/von_mises"].shape[0] == 128
    peak = ref.hertz_line_peak_pressure(LOAD, 6.0, E_STAR)
    assert pressure.max() == pytest.approx(peak, rel=1e-2)
    dx = 0.5 / 128
    assert abs(0.5 * np.count_nonzero(pressure > 0) * dx - HALF_WIDTH) <= dx
    np.testing.assert_allclose(x, np.linspace(-0.25, 0.25, 129)[:-1] + 0.25 / 128)


@pytest.mark.parametrize("control", [("amplitude", 0.002), ("force_amplitude", 40.0)])
def test_fretting_cylinder_study_with_bulk_stress_and_pad_wear(tmp_path, control):
    """Displacement and force control with an in-phase bulk stress and wear of both bodies:
    the scar columns are consistent (pad depth = k_pad/k_flat × flat depth; the wear the
    gap carries is their sum)."""
    output = tmp_path / "fretting.h5"
    text = study_toml(
        "line_fretting",
        str(output),
        CYLINDER_ON_STEEL,
        loading={
            "kind": "fretting",
            "load": LOAD,
            "steps": 2,
            "cycles": 20,
            "record": [20],
            "bulk_stress_max": 100.0,
            "bulk_stress_min": -20.0,
        },
        wear={"pad_coefficient": 1e-8},
        sweep={
            "mu1": [0.5],
            "wear1": [2e-8],
            f"loading.{control[0]}": [control[1]],
        },
    )
    run = run_study(text, progress=False)
    assert run.status == "completed", run
    (row,) = _summary(output)
    assert row["status"] == "completed", row
    depth, pad = float(row["scar_depth"]), float(row["pad_wear_depth"])
    assert depth > 0 and pad == pytest.approx(0.5 * depth, rel=1e-12)
    assert float(row["max_wear_depth"]) == pytest.approx(1.5 * depth, rel=1e-12)
    assert 0 < float(row["scar_width"]) <= 0.5
    assert float(row["scar_area"]) > 0
    assert row["slip_regime"] in ("partial", "gross")


def test_line_keys_are_checked():
    base = study_toml(
        "bad",
        "bad.h5",
        CYLINDER_ON_STEEL,
        loading={"kind": "static", "load": LOAD, "steps": 2},
        mesh={"reference_distance": 0.2},
    )
    with pytest.raises(StudyConfigError, match="reference_distance.*at least the mesh's length"):
        parse_study(base)
    flat = study_toml(
        "bad",
        "bad.h5",
        loading={"kind": "fretting", "amplitude": 1e-3, "bulk_stress_max": 5.0},
        sweep={"mu1": [0.3], "wear1": [1e-8]},
    )
    with pytest.raises(StudyConfigError, match="bulk_stress_max.*only for line contacts"):
        parse_study(flat)
