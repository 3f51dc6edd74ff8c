"""Rough surfaces under ``mpiexec -n 2``: a study sweeping ``surface.seed`` gives the same
results, surfaces and ensemble table with one rank or two, and with the collective writer
(whose ``surface/*`` datasets are pre-created from the layout)."""

from __future__ import annotations

import pytest

from engine.study.examples import SPHERE_ON_STEEL, study_toml
from tests.mpi.test_engine_mpi import assert_same_results, run_engine, run_on_one_and_two_ranks
from tests.mpi.test_mpio import engine_h5py_is_mpi_enabled, needs_parallel_h5py

__all__ = ["engine_h5py_is_mpi_enabled"]  # evaluated by the skipif condition

pytestmark = pytest.mark.mpi

SURFACE = {"kind": "self_affine", "long_cutoff": 0.3, "short_cutoff": 0.08, "rms_height": 2e-4}


def write_rough_study(folder):
    text = study_toml(
        "rough", "rough.h5", SPHERE_ON_STEEL, mesh={"n": 16, "half_width": 0.3},
        loading={"kind": "fretting", "load": 100.0, "amplitude": 5e-4, "cycles": 10},
        sweep={"mu1": [0.5], "wear1": [1e-7]}, surface=SURFACE,
    )  # fmt: skip
    path = folder / "rough.toml"
    path.write_text(text.replace("[sweep]\n", '[sweep]\n"surface.seed" = [1, 2, 3]\n'))
    return path


def test_realisations_are_the_same_on_one_and_two_ranks(tmp_path):
    one, two = run_on_one_and_two_ranks(tmp_path, write_rough_study)
    ensembles = [path.with_name("rough_ensemble.csv").read_bytes() for path in (one, two)]
    assert ensembles[0] == ensembles[1]


@needs_parallel_h5py
def test_rough_collective_equals_single(tmp_path):
    study = write_rough_study(tmp_path)
    single = run_engine(study, "--output-strategy", "single", "--output", str(tmp_path / "s.h5"))
    assert single.returncode == 0, single.stderr
    collective = run_engine(study, "--output-strategy", "mpio")
    assert collective.returncode == 0, collective.stderr
    assert_same_results(tmp_path / "rough.h5", tmp_path / "s.h5")


def write_measured_study(folder):
    """A measured map swept over two detrend modes: text values under [sweep]."""
    import numpy as np

    heights = np.random.default_rng(5).standard_normal((40, 40)) * 0.2  # µm
    np.save(folder / "map.npy", heights + np.linspace(0.0, 1.0, 40)[:, None])
    # the map beside the study file: found from the study's folder, whatever the cwd
    surface = {"kind": "file", "path": "map.npy", "pixel_size": 0.02, "units": "um"}
    text = study_toml(
        "rough", "rough.h5", SPHERE_ON_STEEL, mesh={"n": 16, "half_width": 0.3},
        loading={"kind": "fretting", "load": 100.0, "amplitude": 5e-4, "cycles": 10},
        sweep={"mu1": [0.5], "wear1": [1e-7]}, surface=surface,
    )  # fmt: skip
    path = folder / "rough.toml"
    path.write_text(text.replace("[sweep]\n", '[sweep]\n"surface.detrend" = ["mean", "plane"]\n'))
    return path


def test_swept_texts_are_the_same_on_one_and_two_ranks(tmp_path):
    run_on_one_and_two_ranks(tmp_path, write_measured_study)
