"""Swept mesh (issue 12.1) under ``mpiexec -n 2``: cases with different grids (mesh.n swept)
give the same file with one rank or two, and with the collective (mpio) writer, whose
datasets are pre-created per case from ``engine.study.layout.plan_layout``."""

from __future__ import annotations

import h5py
import pytest

from tests.mpi.test_engine_mpi import assert_same_results, run_engine, write_study
from tests.mpi.test_mpio import engine_h5py_is_mpi_enabled, needs_parallel_h5py

__all__ = ["engine_h5py_is_mpi_enabled"]  # evaluated by the skipif condition

pytestmark = pytest.mark.mpi

SWEPT = {"mesh.n": [16, 24], "loading.load": [500.0, 750.0]}


def write_swept_study(tmp_path, name):
    return write_study(
        tmp_path, name, cycles=2000, mu1=[0.4], beta=[0.0],
        mesh={"n": None}, loading={"load": None}, sweep=SWEPT,
    )  # fmt: skip


def _check_per_case_grids(path):
    with h5py.File(path, "r") as file:
        assert "grid" not in file
        sizes = sorted(group["grid/x"].shape[0] for group in file["cases"].values())
        assert sizes == [16, 16, 24, 24]


def test_swept_mesh_two_ranks_equal_one(tmp_path):
    study = write_swept_study(tmp_path, "swept")
    two = run_engine(study, "--output-strategy", "single")
    assert two.returncode == 0, two.stderr
    one = run_engine(study, "--output-strategy", "single", "--output", str(tmp_path / "one.h5"),
                     ranks=1)  # fmt: skip
    assert one.returncode == 0, one.stderr
    assert_same_results(tmp_path / "swept.h5", tmp_path / "one.h5")
    _check_per_case_grids(tmp_path / "swept.h5")


@needs_parallel_h5py
def test_swept_mesh_collective_equals_single(tmp_path):
    study = write_swept_study(tmp_path, "swept")
    single = run_engine(study, "--output-strategy", "single", "--output", str(tmp_path / "s.h5"))
    assert single.returncode == 0, single.stderr
    collective = run_engine(study, "--output-strategy", "mpio")
    assert collective.returncode == 0, collective.stderr
    assert_same_results(tmp_path / "swept.h5", tmp_path / "s.h5")
    _check_per_case_grids(tmp_path / "swept.h5")
