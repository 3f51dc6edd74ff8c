"""Swept mesh under ``mpiexec -n 2``: cases with different grids (mesh.n swept)
give the same file with one rank or two, and with the collective (mpio) writer, whose
datasets are pre-created per case from ``engine.study.layout.plan_layout``."""

from __future__ import annotations

import h5py
import pytest

from engine.study.examples import study_toml
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


def _cases(path):
    with h5py.File(path, "r") as file:
        return {name: group.attrs["status"] for name, group in file["cases"].items()}


def _pressure(path, case_id):
    with h5py.File(path, "r") as file:
        return file["cases"][case_id]["fields/final/pressure"][()]


def test_a_sweep_that_shrinks_or_changes_reruns_exit_0_on_two_ranks(tmp_path):
    """Values removed, then changed, then --drop-stale, each run twice on 2 ranks: every run
    exits 0, runs exactly the cases of the new study not yet complete, leaves a file that
    `verify` reads clean, keeps the stale cases (dropped with --drop-stale) with their
    results untouched, and the CSV lists exactly the file's cases."""
    from engine.output.summary import load_summary
    from engine.output.verify import verify_file

    study = tmp_path / "sweep.toml"
    output = tmp_path / "sweep.h5"

    def run(mu1, *options):
        study.write_text(
            study_toml(
                "sweep",
                str(output),
                mesh={"n": 8},
                loading={"kind": "static", "steps": 2},
                sweep={"mu1": mu1, "beta": [0.0, 45.0]},
            )
        )
        done = run_engine(study, "--no-progress-bar", "--progress-interval", "0", *options)
        assert done.returncode == 0, done.stderr
        check = verify_file(output, output.with_suffix(".csv"))  # checksums, the CSV against them
        assert not check.damaged, check
        assert sorted(load_summary(output)["case_id"]) == sorted(_cases(output))
        return done.stdout

    ids = {mu: {f"mu{mu}_w0_b0", f"mu{mu}_w0_b45"} for mu in (0.1, 0.15, 0.2, 0.3, 0.4)}
    assert "8 to run" in run([0.1, 0.2, 0.3, 0.4])
    reference = tmp_path / "reference.h5"
    reference.write_bytes(output.read_bytes())
    everything = ids[0.1] | ids[0.2] | ids[0.3] | ids[0.4]
    for _ in range(2):  # shrunk: nothing to run, the stale cases kept
        assert "4 cases, 4 already complete, 0 to run" in run([0.1, 0.2])
        assert set(_cases(output)) == everything
    assert "4 cases, 2 already complete, 2 to run" in run([0.15, 0.2])  # changed
    assert "4 cases, 4 already complete, 0 to run" in run([0.15, 0.2])
    assert set(_cases(output)) == everything | ids[0.15]
    assert set(_cases(output).values()) == {"completed"}
    for case_id in sorted(ids[0.3]):  # a stale case's results are untouched
        assert (_pressure(output, case_id) == _pressure(reference, case_id)).all()
    stdout = run([0.15, 0.2], "--drop-stale")
    assert "they are deleted (--drop-stale)" in stdout
    assert set(_cases(output)) == ids[0.15] | ids[0.2]
    assert "4 cases, 4 already complete, 0 to run" in run([0.15, 0.2])
    assert set(_cases(output)) == ids[0.15] | ids[0.2]
