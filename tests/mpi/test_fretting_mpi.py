"""A small fretting study through ``python -m engine``: 1 and 2 ranks give bit-identical
results (every dataset, attribute and summary value but run times). Sphere, 16², two
amplitudes (partial and gross slip) under displacement control with the energy wear law
(force control and the Archard law: tests/test_fretting.py); ~25 s for both runs here.
Under the mpio venv (the CI's collective phase) the 2-rank run uses the collective writer."""

from __future__ import annotations

from pathlib import Path

import h5py
import pytest

from engine.study.examples import SPHERE_ON_STEEL, study_toml
from tests.mpi.test_engine_mpi import run_on_one_and_two_ranks

pytestmark = pytest.mark.mpi


def write(tmp_path: Path, name: str, sweep: dict) -> Path:
    """A 16² fretting study of a sphere on the same steel, μ = 0.5, 100 cycles, energy law."""
    path = tmp_path / f"{name}.toml"
    loading = {"steps": 2, "cycles": 100, "record": [1, 100], "max_wear_fraction": 0.05}
    text = study_toml(
        name,
        str(tmp_path / f"{name}.h5"),
        SPHERE_ON_STEEL,
        mesh={"n": 16, "half_width": 0.45},
        loading={"kind": "fretting", **loading},
        wear={"law": "energy"},
        sweep={"mu1": [0.5], **sweep},
    )
    path.write_text(text)
    return path


def test_fretting_study_one_and_two_ranks_identical(tmp_path):
    """Displacement control, partial (1 µm) and gross (4 µm) slip, energy wear law."""
    sweep = {"alpha": [1e-3], "loading.amplitude": [0.001, 0.004]}

    results = run_on_one_and_two_ranks(tmp_path, lambda folder: write(folder, "fretting", sweep))
    with h5py.File(results[0], "r") as file:
        for name, group in file["cases"].items():
            loop = group["fields/cycle_0000100/loop"]
            assert loop.shape == (4 * 2 + 1, 4) and loop.attrs["columns"].startswith("delta_x")
            assert group["history/energy"].attrs["units"] == "mJ", name
