"""The fretting checks of a line contact: a cylinder study run through ``python -m engine``,
then ``python -m engine report``, checked against the cylinder's closed forms
(engine.reference.line_contact via the profile's ``fretting_reference``); a pad study, which
has none, says so by name.

Steel cylinder on steel (K = 0: the closed forms are exact), R = 6 mm, P = 185 N/mm, μ = 0.5,
datum d = 10 mm: a = 0.113 mm, δ_slip = 3.04 µm. 128 elements over ±0.25 mm (58 across the
contact), 2 cycles. Measured (2026-11-27) at 128 elements, and at 64 to show where the error
comes from:

- displacement control, δ* = 1.5 µm (partial slip), 10 steps: energy at N = 1 +0.03 % from
  the closed form (+0.47 % at 64 elements: the mesh's error) → 0.3 %;
- δ* = 6 µm (gross slip), 10 steps: −0.13 % from the closed form, the trapezoidal rule over
  10 steps per quarter cycle (the analytic loop sampled at the solver's increments: 0.00 %)
  → 0.5 %, and 0.05 % against the sampled loop;
- force control, Q* = 0.5 μP, 4 steps: −1.55 % from the closed form (the steps), +0.04 %
  from the loop sampled at the solver's forces (−2.54 % at 64 elements: the mesh) → 3 % and
  0.5 %.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from engine.analysis.fretting import check_case, unchecked_reason
from engine.analysis.results import open_results
from engine.material import MaterialPair
from engine.reference import line_contact
from engine.study.examples import CYLINDER_ON_STEEL, study_toml

REPO = Path(__file__).resolve().parents[1]
LOAD, MU, DATUM = 185.0, 0.5, 10.0  # N/mm, 1, mm
COMMON = {"kind": "fretting", "load": LOAD, "cycles": 2, "record": [1]}
ENERGY_LAW = {"wear": {"law": "energy"}}
STUDIES = {
    "displacement": dict(
        mesh={"n": 128, "reference_distance": DATUM},
        loading={**COMMON, "steps": 10},
        sweep={"mu1": [MU], "alpha": [1e-6], "loading.amplitude": [0.0015, 0.006]},
        **ENERGY_LAW,
    ),
    "force": dict(
        mesh={"n": 128, "reference_distance": DATUM},
        loading={**COMMON, "steps": 4, "force_amplitude": 0.5 * MU * LOAD},
        sweep={"mu1": [MU], "alpha": [1e-6]},
        **ENERGY_LAW,
    ),
    "pad": dict(
        punch={"shape": "pad", "radius": 0.1, "edge_radius": 6.0},
        loading={**COMMON, "steps": 4, "amplitude": 0.002},
        sweep={"mu1": [MU], "alpha": [1e-6]},
        **ENERGY_LAW,
    ),
}


def _engine(folder: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run(
        [sys.executable, "-m", "engine", *args], cwd=folder, env=env, capture_output=True,
        text=True, timeout=300,
    )  # fmt: skip


@pytest.fixture(scope="module")
def reports(tmp_path_factory) -> dict[str, tuple[Path, str]]:
    """Each study run, then reported: (results file, report text) by name."""
    folder = tmp_path_factory.mktemp("line_check")
    out = {}
    for name, sections in STUDIES.items():
        (folder / f"{name}.toml").write_text(
            study_toml(name, f"{name}.h5", CYLINDER_ON_STEEL, **sections)
        )
        run = _engine(folder, f"{name}.toml", "--progress-interval", "0")
        assert run.returncode == 0, run.stdout + run.stderr
        report = _engine(folder, "report", f"{name}.h5")
        assert report.returncode == 0, report.stdout + report.stderr
        out[name] = (folder / f"{name}.h5", report.stdout)
    return out


def _checks(path: Path):
    study = open_results(path)
    return study, [check_case(study, case) for case in study.completed]


def test_displacement_control_against_the_cylinder_closed_forms(reports):
    path, text = reports["displacement"]
    assert "(Cattaneo–Masing (cylinder); isotropic friction): 2 of 2 cases" in text
    assert "no closed form" not in text and "not checked" not in text
    _, (partial, gross) = _checks(path)
    modulus = MaterialPair(200e3, 0.3, 200e3, 0.3).contact_modulus
    slip = float(line_contact.line_slip_displacement(LOAD, 6.0, modulus, MU, DATUM))
    assert partial.ratio == pytest.approx(0.0015 / slip, rel=1e-12)
    assert (partial.expected, partial.computed) == ("partial", "partial")
    assert (gross.expected, gross.computed) == ("gross", "gross")
    assert partial.exact_coupling and gross.exact_coupling
    assert abs(partial.energy_error) < 3e-3  # the mesh (module docstring)
    assert abs(gross.energy_error) < 5e-3  # the load steps' trapezoid
    assert abs(gross.sampled_error) < 5e-4  # the load steps removed
    # Gross slip: the closed form's energy, W(μP) + 4μP(δ* − δ_slip)
    limit = MU * LOAD
    closed = line_contact.line_loop_energy(limit, LOAD, modulus, MU) + 4 * limit * (0.006 - slip)
    assert gross.exact == pytest.approx(closed, rel=1e-12)
    # Q* = μP in gross slip, so A = W/(4δ*Q*) is off by the energy error alone
    assert gross.energy_ratio / gross.exact_energy_ratio - 1 == pytest.approx(
        gross.energy_error, abs=1e-4
    )
    assert f"energy at N = 1 {gross.energy:.4g} mJ/mm vs {gross.exact:.4g} mJ/mm" in text


def test_force_control_against_the_cylinder_closed_forms(reports):
    path, text = reports["force"]
    (check,) = _checks(path)[1]
    assert check.control == "force" and check.ratio == pytest.approx(0.5, rel=1e-12)
    assert check.regime_holds and check.computed == "partial"
    modulus = MaterialPair(200e3, 0.3, 200e3, 0.3).contact_modulus
    closed = line_contact.line_loop_energy(0.5 * MU * LOAD, LOAD, modulus, MU)
    assert check.exact == pytest.approx(closed, rel=1e-12)
    assert abs(check.energy_error) < 3e-2  # 4 load steps (module docstring)
    assert abs(check.sampled_error) < 5e-3  # the mesh
    assert "1 of 1 cases" in text


def test_a_profile_without_closed_forms_says_so_by_name(reports):
    path, text = reports["pad"]
    study, (check,) = _checks(path)
    assert check is None
    assert unchecked_reason(study, study.completed[0]) == "no closed form for the pad profile"
    assert "- not checked, no closed form for the pad profile: " in text
    assert "slip regime of the first cycle" not in text
