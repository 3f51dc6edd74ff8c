"""Calibrations under ``mpiexec``: real ranks, real files, real signals.

The calibration of ``tests/test_calibration.py`` (a critical distance fitted on two line
contact tests, a third predicted; ~100 contact solutions of ~0.1 s) run without
interruption on one rank is the reference. A run on two ranks, and two-rank runs killed
(SIGKILL) or stopped (SIGTERM, exit 3) in the middle of the fit and then resumed from the
kept contact solutions, must write the same results file and the same
``NAME_calibration.csv``, bit for bit — the same fitted value included.
"""

from __future__ import annotations

import signal
from pathlib import Path

import h5py
import numpy as np
import pytest

import engine
from tests.mpi.test_engine_mpi import run_engine
from tests.mpi.test_kill_safety import kill_ranks, start
from tests.test_calibration import write_study

pytestmark = pytest.mark.mpi


def _contents(path: Path) -> dict:
    """Every dataset and attribute of a results file (name → value)."""
    found = {}
    with h5py.File(path, "r") as file:

        def visit(name, item):
            found.update({f"{name}@{key}": value for key, value in item.attrs.items()})
            if isinstance(item, h5py.Dataset):
                found[name] = item[()]

        found.update({f"@{key}": value for key, value in file.attrs.items()})
        file.visititems(visit)
    return found


def assert_same_files(first: Path, second: Path) -> None:
    """The same results file (every dataset and attribute equal, NaN equal to NaN) and the
    same CSV, byte for byte."""
    ours, theirs = _contents(first), _contents(second)
    assert sorted(ours) == sorted(theirs)
    for name, value in ours.items():
        other = theirs[name]
        if isinstance(value, np.ndarray) and value.dtype.kind == "f":
            assert np.array_equal(value, other, equal_nan=True), name
        elif isinstance(value, np.ndarray):
            assert np.array_equal(value, other), name
        elif isinstance(value, float) and np.isnan(value):
            assert np.isnan(other), name
        elif name != "@study_toml":  # the study file names its own folder
            assert value == other, name
    csv = "calibrate_calibration.csv"
    assert first.with_name(csv).read_bytes() == second.with_name(csv).read_bytes()


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    study = write_study(tmp_path_factory.mktemp("reference"))
    result = run_engine(study, ranks=1, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    output = study.parent / "out" / "calibrate.h5"
    assert engine.load_calibration(output).attrs["fit_status"] == "converged"
    return output


def test_two_ranks_give_the_one_rank_files(reference, tmp_path):
    study = write_study(tmp_path)
    result = run_engine(study, ranks=2, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    assert_same_files(reference, tmp_path / "out" / "calibrate.h5")


@pytest.mark.parametrize("signum", [signal.SIGKILL, signal.SIGTERM], ids=["kill", "term"])
def test_an_interrupted_calibration_resumes_to_the_same_fit(reference, tmp_path, signum):
    """The signal lands after the fit's third evaluation; the rerun solves only what the
    store lacks and ends with the reference's files (the fitted value bit for bit)."""
    study = write_study(tmp_path)
    process = start(study, "--no-progress-bar")
    for line in process.stdout:
        if line.startswith("fit evaluation 2:"):
            kill_ranks(study, signum)
            break
    process.communicate(timeout=120)
    if signum == signal.SIGTERM:
        assert process.returncode == 3
    output = tmp_path / "out" / "calibrate.h5"
    assert not output.exists(), "the signal must land before the end"
    assert any((tmp_path / "out" / "calibrate.h5.contact").glob("*.npz"))
    rerun = run_engine(study, ranks=2, timeout=300)
    assert rerun.returncode == 0, rerun.stdout + rerun.stderr
    solved = int(rerun.stdout.rsplit(" contact solutions computed", 1)[0].rsplit("\n", 1)[-1])
    total = len(engine.load_calibration(reference).pipe(lambda f: f))  # the tests
    assert total == 3 and solved < _solutions(reference)
    assert_same_files(reference, output)


def _solutions(path: Path) -> int:
    with h5py.File(path, "r") as file:
        return len(file["calibration/contact/x"])
