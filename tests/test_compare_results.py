"""scripts/compare_results.py finds every kind of difference and ignores only run times.

Two small hand-made results files (no engine run): identical copies agree (exit 0); a changed
bit of a dataset, a changed dtype, a missing dataset, a changed attribute and a changed key of
the JSON summary are each reported (exit 1), while run times (attribute ``runtime_s`` and the
summary's ``runtime_s`` key) are not.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "compare_results.py"


def _results(path: Path) -> Path:
    with h5py.File(path, "w") as file:
        file.attrs["study_name"] = "t"
        case = file.create_group("cases/a")
        case.attrs.update(status="completed", runtime_s=1.5, cpu_s=1.0)
        case.attrs["summary"] = json.dumps({"case_id": "a", "vm_max": 1.25, "runtime_s": 1.5})
        data = case.create_dataset("history/approach", data=np.linspace(0.0, 1.0, 5))
        data.attrs.update(units="mm", description="approach")
        case.create_dataset("fields/final/status", data=np.zeros((2, 2), dtype=np.int8))
    return path


def _compare(first: Path, second: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(SCRIPT), str(first), str(second)], capture_output=True, text=True
    )


def _edit_approach(file):
    values = file["cases/a/history/approach"][()]
    values[2] = np.nextafter(values[2], 2.0)  # one ulp
    file["cases/a/history/approach"][...] = values


def _edit_dtype(file):
    del file["cases/a/fields/final/status"]
    file.create_dataset("cases/a/fields/final/status", data=np.zeros((2, 2), dtype=np.int16))


def _edit_summary(file):
    file["cases/a"].attrs["summary"] = json.dumps({"case_id": "a", "vm_max": 1.5, "runtime_s": 1.5})


EDITS = {
    "one ulp": (_edit_approach, "history/approach: data differ (1 of 5 elements differ)"),
    "dtype": (_edit_dtype, "fields/final/status: dtype A=int8 B=int16"),
    "missing": (lambda f: f["cases/a/history"].pop("approach"), "history/approach: only in A"),
    "units": (
        lambda f: f["cases/a/history/approach"].attrs.__setitem__("units", ""),
        "history/approach @units: A='mm' B=''",
    ),
    "summary": (_edit_summary, "@summary: JSON key 'vm_max': A=1.25 B=1.5"),
}


def test_identical_files_and_run_times_agree(tmp_path):
    first = _results(tmp_path / "a.h5")
    second = tmp_path / "b.h5"
    shutil.copy(first, second)
    with h5py.File(second, "a") as file:
        file["cases/a"].attrs.update(runtime_s=9.0, cpu_s=8.0)
        file["cases/a"].attrs["summary"] = json.dumps(
            {"case_id": "a", "vm_max": 1.25, "runtime_s": 9.0}
        )
    result = _compare(first, second)
    assert result.returncode == 0, result.stdout
    assert result.stdout.startswith("0 difference(s)")


@pytest.mark.parametrize("kind", sorted(EDITS))
def test_each_difference_is_reported(kind, tmp_path):
    edit, expected = EDITS[kind]
    first = _results(tmp_path / "a.h5")
    second = tmp_path / "b.h5"
    shutil.copy(first, second)
    with h5py.File(second, "a") as file:
        edit(file)
    result = _compare(first, second)
    assert result.returncode == 1
    assert expected in result.stdout, result.stdout
