"""Damage a finished results file on purpose; the check must see it and a plain rerun repair it.

One small static study (n = 8, six cases of ~0.1 s) is run once; each attack damages a copy
of its finished file:

- 4 KiB overwritten at ten positions (every eleventh of the file; zeros and fixed random
  bytes alternately: zeroed B-tree nodes are what sends HDF5 into an endless loop);
- single bits flipped inside the data of three datasets;
- truncation at five sizes (95 %, 70 %, 40 %, 10 %, 0 bytes).

After each: ``python -m engine verify`` flags the damage (exit 4) — or, where the overwrite
hit bytes the file does not use, the damaged copy still holds exactly the reference's
results — and then the plain rerun ``python -m engine STUDY.toml`` exits 0 with every case of
the study present once and results identical to the reference (scripts/compare_results.py:
bit for bit, run times aside), the summary CSV included (the rerun itself reads back what
it wrote before it exits 0). Attacks run three at a time (each in
its own directory); the read time limit is 4 s so the endless loops cost little.
"""

from __future__ import annotations

import concurrent.futures
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from engine.output.verify import EXIT_DAMAGED
from engine.study.examples import study_toml
from tests.test_checksums import flip_bit as flip_stored_bit

REPO = Path(__file__).resolve().parents[1]
# s for reading a damaged file (ENGINE_INSPECTION_TIME_LIMIT): the endless loops end sooner;
# a read cut short on a loaded machine takes the start-over path, with the same results
TIME_LIMIT = "4"
STUDY = study_toml(
    "attacked",
    "attacked.h5",
    mesh={"n": 8},
    loading={"kind": "static", "steps": 2},
    sweep={"mu1": [0.1, 0.2, 0.4], "beta": [0.0, 45.0]},
)
CASES = 6


def _compare_module():
    script = REPO / "scripts" / "compare_results.py"
    spec = importlib.util.spec_from_file_location("compare_results", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


COMPARE = _compare_module()


def engine(directory: Path, *args: str, timeout: float = 180) -> subprocess.CompletedProcess:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "ENGINE_INSPECTION_TIME_LIMIT": TIME_LIMIT}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run(
        [sys.executable, "-m", "engine", *args],
        cwd=directory, env=env, capture_output=True, text=True, timeout=timeout,
    )  # fmt: skip


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    directory = tmp_path_factory.mktemp("reference")
    (directory / "attacked.toml").write_text(STUDY)
    run = engine(directory, "attacked.toml", "--no-progress-bar", "--progress-interval", "0")
    assert run.returncode == 0, run.stderr
    return directory


def attacked_copy(reference: Path, directory: Path, damage) -> Path:
    directory.mkdir()
    for name in ("attacked.toml", "attacked.h5", "attacked.csv"):
        shutil.copy(reference / name, directory / name)
    damage(directory / "attacked.h5")
    return directory


def holds_the_reference(path: Path, reference: Path) -> bool:
    """Whether a damaged copy still holds exactly the reference's results (read in a child:
    the damage may make HDF5 loop)."""
    code = (
        "import sys, importlib.util as u\n"
        f"s = u.spec_from_file_location('c', {str(REPO / 'scripts' / 'compare_results.py')!r})\n"
        "m = u.module_from_spec(s); s.loader.exec_module(m)\n"
        "sys.exit(1 if m.compare_hdf5(*map(__import__('pathlib').Path, sys.argv[1:3]), "
        "m.RUN_DEPENDENT) else 0)"
    )
    try:
        result = subprocess.run(
            [sys.executable, "-c", code, str(path), str(reference / "attacked.h5")],
            capture_output=True, timeout=float(TIME_LIMIT),
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        return False
    return result.returncode == 0


def attack(reference: Path, directory: Path, damage) -> str:
    """Damage a copy, check it, rerun it; returns "" or what went wrong (for the report)."""
    directory = attacked_copy(reference, directory, damage)
    untouched = directory / "untouched-copy.h5"
    shutil.copy(directory / "attacked.h5", untouched)
    check = engine(directory, "verify", "attacked.h5", "--no-summary")
    if check.returncode != EXIT_DAMAGED and not holds_the_reference(untouched, reference):
        return f"verify exit {check.returncode} on a damaged file: {check.stdout[-300:]}"
    rerun = engine(directory, "attacked.toml", "--no-progress-bar", "--progress-interval", "0")
    if rerun.returncode != 0:
        return f"rerun exit {rerun.returncode}: {rerun.stderr[-600:]}"
    with h5py.File(directory / "attacked.h5", "r") as file:
        cases = sorted(file["cases"])
        statuses = {file["cases"][name].attrs["status"] for name in cases}
    if len(cases) != CASES or statuses != {"completed"}:
        return f"after the rerun: cases {cases}, statuses {statuses}"
    differences = COMPARE.compare_hdf5(
        reference / "attacked.h5", directory / "attacked.h5", COMPARE.RUN_DEPENDENT
    )
    differences += COMPARE.compare_csv(
        reference / "attacked.csv", directory / "attacked.csv", COMPARE.RUN_DEPENDENT
    )
    if differences:
        return "results differ from the reference: " + "; ".join(differences[:3])
    return ""


def run_attacks(reference: Path, tmp_path: Path, damages: dict) -> None:
    with concurrent.futures.ThreadPoolExecutor(max_workers=3) as pool:
        futures = {
            name: pool.submit(attack, reference, tmp_path / name, damage)
            for name, damage in damages.items()
        }
        problems = {name: future.result() for name, future in futures.items()}
    assert not {name: text for name, text in problems.items() if text}


def overwrite(fraction: float, random: bool):
    def damage(path: Path) -> None:
        size = path.stat().st_size
        block = np.random.default_rng(7).bytes(4096) if random else bytes(4096)
        with open(path, "r+b") as handle:
            handle.seek(min(int(size * fraction), size - 4096))
            handle.write(block)

    return damage


def flip_bit(case_index: int, dataset: str, byte: int, bit: int):
    def damage(path: Path) -> None:
        with h5py.File(path, "r") as file:
            case_id = sorted(file["cases"])[case_index]
        flip_stored_bit(path, case_id, dataset, byte=byte, bit=bit)

    return damage


def truncate(fraction: float):
    def damage(path: Path) -> None:
        with open(path, "r+b") as handle:
            handle.truncate(int(path.stat().st_size * fraction))

    return damage


def test_4_kib_overwritten_at_ten_positions(reference, tmp_path):
    damages = {f"overwrite_{k}": overwrite(k / 11, random=k % 2 == 0) for k in range(1, 11)}
    run_attacks(reference, tmp_path, damages)


def test_single_bits_flipped_inside_datasets(reference, tmp_path):
    damages = {
        "flip_pressure": flip_bit(0, "fields/final/pressure", byte=100, bit=0),
        "flip_grid": flip_bit(3, "grid/x", byte=7, bit=6),  # a sign or exponent bit
        "flip_stress": flip_bit(5, "subsurface/final/von_mises", byte=41, bit=3),
    }
    run_attacks(reference, tmp_path, damages)  # a copy with a flipped bit never holds the
    # reference's results, so attack() requires verify's exit 4 for each


def test_truncated_at_five_sizes(reference, tmp_path):
    damages = {f"truncate_{int(f * 100)}": truncate(f) for f in (0.95, 0.7, 0.4, 0.1, 0.0)}
    run_attacks(reference, tmp_path, damages)
