"""A line fretting study with a ``[fatigue]`` section through ``python -m engine``: 1 and 2
ranks give bit-identical results (every dataset, attribute and summary value but run times),
fatigue maps, hot spots and per-cycle histories included. Cylinder on flat, 48 elements, a
bulk stress in phase, two values of σ_d swept; a few seconds per run here. Under the mpio
venv the 2-rank run uses the collective writer (the fatigue datasets go through its
journals: NaN and infinite lives included)."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from engine.study.examples import CYLINDER_ON_STEEL, study_toml
from tests.mpi.test_engine_mpi import run_on_one_and_two_ranks

pytestmark = pytest.mark.mpi

FATIGUE = {
    "criteria": ["crossland", "swt"], "tau_d": 200.0,
    "sigma_f": 1000.0, "b": -0.09, "eps_f": 0.6, "c": -0.6,
    "method": "point", "length": 0.02, "every_cycle": True,
}  # fmt: skip


def write_study(folder: Path) -> Path:
    """The cylinder-on-flat fatigue study of the module docstring, in ``folder``."""
    study = folder / "fatigue.toml"
    loading = {
        "kind": "fretting", "load": 185.0, "steps": 2, "cycles": 12, "record": [1, 12],
        "force_amplitude": 55.0, "bulk_stress_max": 100.0, "bulk_stress_min": -100.0,
    }  # fmt: skip
    study.write_text(
        study_toml(
            "fatigue",
            str(folder / "fatigue.h5"),
            CYLINDER_ON_STEEL,
            mesh={"n": 48, "half_width": 0.2},
            loading=loading,
            subsurface={"depth": 1.0, "layers": 5},
            fatigue=FATIGUE,
            sweep={"mu1": [0.6], "wear1": [1e-8], "fatigue.sigma_d": [300.0, 250.0]},
        )
    )
    return study


def test_fatigue_study_one_and_two_ranks_identical(tmp_path):
    results = run_on_one_and_two_ranks(tmp_path, write_study)
    with h5py.File(results[0], "r") as file:
        for name, group in file["cases"].items():
            risk = group["fatigue/cycle_0000012/crossland_risk"]
            assert risk.shape == group["subsurface/cycle_0000012/z"].shape, name
            assert risk.attrs["units"] == "1"
            assert group["fatigue/cycle_0000012/swt_hot_spot"].attrs["columns"].startswith("value")
            assert len(group["history/swt"]) == len(group["history/cycle"])
            assert np.all(np.isfinite(group["history/crossland_risk"][()]))
