"""scripts/mccoll_results.py: its studies are the bundled ones, and the comparison with the
measured scar divides the right numbers.

- Each bundled McColl study differs from its convergence study's case with the script's
  ``BUNDLED`` settings only in its name and output (so the tables of that case are the bundled
  study's), and the study at the test's load differs from the one at 185 N/mm only in the
  load and the mesh's half-width (nothing else was changed between the two loads).
- The ratio row computed / measured of ``measured_table`` holds each computed measure at
  18,000 cycles divided by the measured one (hand-made numbers, no engine run).
"""

from __future__ import annotations

import importlib.util
import sys
import tomllib
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SPEC = importlib.util.spec_from_file_location(
    "mccoll_results", REPO / "scripts" / "mccoll_results.py"
)
mccoll_results = importlib.util.module_from_spec(SPEC)
sys.modules[SPEC.name] = mccoll_results  # the script's dataclass looks its module up
SPEC.loader.exec_module(mccoll_results)


def _study(name: str) -> dict:
    return tomllib.loads((REPO / "studies" / f"{name}.toml").read_text())


def _without(study: dict, *keys: tuple[str, str]) -> dict:
    stripped = {section: dict(values) for section, values in study.items()}
    for section, key in keys:
        stripped[section].pop(key, None)
    return stripped


@pytest.mark.parametrize("load", mccoll_results.LOADS, ids=lambda load: load.bundled_study)
def test_the_convergence_case_with_the_bundled_settings_is_the_bundled_study(load):
    bundled, convergence = _study(load.bundled_study), _study(load.study)
    n, fraction = mccoll_results.BUNDLED
    sweep = convergence["sweep"]
    assert n in sweep.pop("mesh.n") and fraction in sweep.pop("loading.max_wear_fraction")
    assert bundled["mesh"]["n"] == n and bundled["loading"]["max_wear_fraction"] == fraction
    assert bundled["mesh"]["half_width"] == load.half_width
    assert bundled["loading"]["load"] == load.load
    ignored = [("study", "name"), ("study", "output"), ("mesh", "n")]
    ignored += [("loading", "max_wear_fraction")]
    assert _without(bundled, *ignored) == _without(convergence, *ignored)


def test_the_two_loads_differ_only_in_the_load_and_the_mesh_extent():
    paper, test = _study("mccoll_2004"), _study("mccoll_2004_test_load")
    assert (paper["loading"]["load"], test["loading"]["load"]) == (185.0, 18.5)  # N/mm
    ignored = [("study", "name"), ("study", "output"), ("loading", "load")]
    ignored += [("mesh", "half_width")]
    assert _without(paper, *ignored) == _without(test, *ignored)


def test_the_ratio_row_divides_the_computed_scar_by_the_measured_one():
    measured = mccoll_results.MEASURED
    computed = {"scar_depth": 5.8e-3, "scar_width": 0.15, "scar_area": 3.0e-3}
    values = {**computed, "pad_wear_depth": 5.8e-3}
    cycles = {cycle: values for cycle in mccoll_results.CYCLES}
    table = mccoll_results.measured_table({18.5: {"cycles": cycles}})
    ratio_row = next(line for line in table.splitlines() if "computed / measured" in line)
    cells = [cell.strip() for cell in ratio_row.strip("|").split("|")]
    expected = [computed[name] / measured[name] for name in ("scar_depth", "scar_width")]
    expected.append(computed["scar_area"] / measured["scar_area"])
    # two decimals in the table: 2.00, 0.25, 3.00 exactly for these numbers
    assert [float(cell) for cell in cells[2:5]] == pytest.approx(expected, abs=5e-3)
    assert cells[1] == f"{mccoll_results.MEASURED_CYCLES:,}"
