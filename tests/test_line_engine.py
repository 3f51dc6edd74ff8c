"""Line (plane-strain) contacts through ``python -m engine``: every loading kind (static,
cyclic, fretting under displacement and under force control), both wear laws, cycle jumping,
peak tracking, the x–z subsurface plane with σ_yy = ν(σ_xx + σ_zz), and a fretting case
interrupted by Ctrl-C and resumed from its checkpoint, bit for bit.

The physics is validated in ``test_line_validation.py`` against closed forms; these tests
check that the command line carries it into the results file. Tolerances: 1e-12 for
identities the engine computes exactly (σ_yy, the pad/flat split), the stated ones otherwise.
"""

import os
import signal
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from engine.output.summary import load_summary
from engine.reference import line_contact as ref
from engine.solvers.fretting import FORCE_TOL
from engine.study.examples import CYLINDER_ON_STEEL, study_toml

REPO = Path(__file__).resolve().parents[1]
LOAD = 185.0  # N/mm
NU = 0.3


def _environment() -> dict[str, str]:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return env


def _engine(folder: Path, *args: str) -> subprocess.CompletedProcess:
    quiet = () if args[0] == "plot" else ("--progress-interval", "0")
    return subprocess.run(
        [sys.executable, "-m", "engine", *args, *quiet],
        cwd=folder, env=_environment(), capture_output=True, text=True, timeout=300,
    )  # fmt: skip


def _write(folder: Path, name: str, **sections) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(study_toml(name, f"{name}.h5", CYLINDER_ON_STEEL, **sections))
    return path


def _rows(folder: Path, name: str) -> dict[str, dict]:
    table = load_summary(folder / f"{name}.csv")
    return {row["case_id"]: row for row in table.to_dict("records")}


def _plane_strain(case: h5py.Group, group: str) -> None:
    """σ_yy = ν(σ_xx + σ_zz) on the whole x–z plane (n, layers), to round-off."""
    stresses = {key: case[f"subsurface/{group}/sigma_{key}"][...] for key in ("xx", "yy", "zz")}
    expected = NU * (stresses["xx"] + stresses["zz"])
    scale = np.abs(expected).max()
    np.testing.assert_allclose(stresses["yy"], expected, rtol=0, atol=1e-12 * scale)
    depth = case[f"subsurface/{group}/z"][...]  # coordinates of each point (mm), z ≥ 0
    assert stresses["yy"].shape == depth.shape == (case["grid/x"].shape[0], 4)
    assert np.all(depth >= 0.0)


def test_static_and_cyclic_line_studies(tmp_path):
    """Static: Hertz's peak pressure (1 %, 128 elements: the interior converges like Δx).
    Cyclic (0 → P → 0 under Archard wear, 2,000 cycles; a softer cylinder, K ≠ 0, so that
    the normal load makes the surfaces slip and wear): cycle jumps, the peak tracker's
    history and changes, the recorded fields of shape (n, 1), the plane-strain stresses."""
    _write(
        tmp_path, "static", mesh={"n": 128},
        loading={"kind": "static", "load": LOAD, "steps": 2}, sweep={"mu1": [0.0]},
    )  # fmt: skip
    softer = {**CYLINDER_ON_STEEL["material"], "E_B": 70e3, "nu_B": 0.33}
    _write(
        tmp_path, "cyclic", mesh={"n": 64}, material=softer,
        loading={"kind": "cyclic", "load": LOAD, "steps": 2, "cycles": 2000,
                 "record": [1, 2000]},
        sweep={"mu1": [0.5], "wear1": [1e-7]},
    )  # fmt: skip
    for name in ("static", "cyclic"):
        result = _engine(tmp_path, f"{name}.toml")
        assert result.returncode == 0, result.stdout + result.stderr
    modulus = 200e3 / (2 * (1 - NU**2))
    with h5py.File(tmp_path / "static.h5") as results:
        (case,) = results["cases"].values()
        peak = ref.hertz_line_peak_pressure(LOAD, 6.0, modulus)
        assert case["fields/final/pressure"][...].max() == pytest.approx(peak, rel=1e-2)
        _plane_strain(case, "final")
    ((case_id, row),) = _rows(tmp_path, "cyclic").items()
    assert row["status"] == "completed" and float(row["scar_depth"]) > 0
    with h5py.File(tmp_path / "cyclic.h5") as results:
        case = results["cases"][case_id]
        jumps = case["history/jump"][...]
        assert jumps.max() > 1 and jumps.sum() == 2000  # cycle jumping covered the cycles
        assert case["history/peak_region"].shape == jumps.shape
        assert "peak_changes" in case
        assert case["fields/cycle_0002000/wear"].shape == (64, 1)
        _plane_strain(case, "final")


def test_fretting_line_studies_both_controls_and_wear_laws(tmp_path):
    """Displacement control under the energy law (V = α ΣE_d: 1 %, the loops drift as the
    surfaces wear between jumps; 7e-5 measured), and force control under Archard's law with
    an in-phase bulk stress and the pad wearing too (pad depth = k_pad/k_flat × flat depth,
    exact): the loops, the scar columns, the slip regime against the cylinder's δ_slip, and
    the figures ``python -m engine plot`` draws.
    (With a bulk stress the loop area ∮Q dδ is not the whole frictional dissipation: the
    bulk strain makes the surfaces slip too; docs/explanation/line-contact.md.)"""
    common = {"kind": "fretting", "load": LOAD, "steps": 3, "cycles": 300, "record": [1, 300]}
    _write(
        tmp_path, "energy", mesh={"n": 64},
        loading=common,
        wear={"law": "energy"},
        sweep={"mu1": [0.5], "alpha": [2e-5], "loading.amplitude": [0.001, 0.006]},
    )  # fmt: skip
    _write(
        tmp_path, "force", mesh={"n": 64},
        loading={**common, "force_amplitude": 50.0, "bulk_stress_max": 80.0,
                 "bulk_stress_min": -40.0},
        wear={"pad_coefficient": 1e-8}, sweep={"mu1": [0.5], "wear1": [2e-8]},
    )  # fmt: skip
    for name in ("energy", "force"):
        result = _engine(tmp_path, f"{name}.toml")
        assert result.returncode == 0, result.stdout + result.stderr
    modulus = 200e3 / (2 * (1 - NU**2))
    slip = ref.line_slip_displacement(LOAD, 6.0, modulus, 0.5, 10.0)  # 3.04 µm
    with h5py.File(tmp_path / "energy.h5") as results:
        for row in _rows(tmp_path, "energy").values():
            assert row["status"] == "completed", row
            amplitude = float(row["loading.amplitude"])
            assert row["slip_regime"] == ("gross" if amplitude > slip else "partial")
            case = results["cases"][row["case_id"]]
            history = case["history"]
            dissipated = float(np.sum(history["jump"][...] * history["energy"][...]))
            # the gap carries the flat's wear only (no pad coefficient): V = α ΣE_d
            assert float(row["wear_volume"]) == pytest.approx(2e-5 * 1e-3 * dissipated, rel=1e-2)
            assert case["fields/cycle_0000300/loop"].shape[1] == 4
            _plane_strain(case, "final")
    # The fretting figures of a line contact: map (with the cylinder's δ_slip), loops, wear
    plot = _engine(tmp_path, "plot", "energy.h5", "--out", "figures")
    assert plot.returncode == 0, plot.stdout + plot.stderr
    for name in ("fretting_map.png", "fretting_loops.png", "wear_energy.png"):
        assert (tmp_path / "figures" / name).stat().st_size > 10_000, name
    ((case_id, row),) = _rows(tmp_path, "force").items()
    assert float(row["q_amplitude"]) == pytest.approx(50.0, rel=2 * FORCE_TOL)
    with h5py.File(tmp_path / "force.h5") as results:
        _plane_strain(results["cases"][case_id], "final")  # with σ_B: σ_yy = ν(σ_xx + σ_zz)
    depth = float(row["scar_depth"])
    assert depth > 0 and float(row["pad_wear_depth"]) == pytest.approx(0.5 * depth, rel=1e-12)


def test_interrupted_fretting_case_resumes_from_its_checkpoint_bit_for_bit(tmp_path):
    """Ctrl-C while the one fretting case runs: exit code 3, its state in the checkpoint
    folder; the rerun resumes it and the results equal an uninterrupted run's, bit for bit
    (``scripts/compare_results.py``). About 10 s."""
    sections = {
        "mesh": {"n": 128},
        "loading": {"kind": "fretting", "load": LOAD, "steps": 4, "cycles": 20000,
                    "record": [20000], "amplitude": 0.002, "max_wear_fraction": 0.001},
        "sweep": {"mu1": [0.6], "wear1": [2.75e-8]},
    }  # fmt: skip
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    for folder in (whole, stopped):
        folder.mkdir()
        _write(folder, "resume", **sections)
    result = _engine(whole, "resume.toml")
    assert result.returncode == 0, result.stdout + result.stderr
    process = subprocess.Popen(
        [sys.executable, "-m", "engine", "resume.toml", "--progress-interval", "0.2"],
        cwd=stopped, env=_environment(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True,
    )  # fmt: skip
    for line in process.stderr:  # the case has simulated a few cycles: Ctrl-C
        if " cycle " in line and " cycle 0/" not in line:
            process.send_signal(signal.SIGINT)
            break
    out, err = process.communicate(timeout=300)
    assert process.returncode == 3, out + err
    saved = {path.suffix for path in (stopped / "resume.h5.checkpoints").iterdir()}
    assert ".npz" in saved, saved  # the case's state (and its progress record)
    result = _engine(stopped, "resume.toml")
    assert result.returncode == 0, result.stdout + result.stderr
    assert not (stopped / "resume.h5.checkpoints").exists()
    compare = subprocess.run(
        [sys.executable, str(REPO / "scripts" / "compare_results.py"),
         str(whole / "resume.h5"), str(stopped / "resume.h5")],
        capture_output=True, text=True, env=_environment(),
    )  # fmt: skip
    assert compare.returncode == 0, compare.stdout + compare.stderr


def test_a_cylinder_run_imports_neither_scipy_nor_pandas(tmp_path):
    """The set-up of a line contact (its nominal half-width, kernels and stresses) keeps the
    start-up of every rank as light as a 3-D study's (SciPy's import: about 1.5 s of CPU)."""
    _write(
        tmp_path, "light", mesh={"n": 16},
        loading={"kind": "static", "load": LOAD, "steps": 1}, sweep={"mu1": [0.0]},
    )  # fmt: skip
    code = (
        "import sys\n"
        "from engine.cli import main\n"
        "status = main(['light.toml', '--no-progress-bar'])\n"
        "print(status, sorted(m for m in ('scipy', 'pandas', 'matplotlib') if m in sys.modules))\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
        env=_environment(),
    )  # fmt: skip
    assert run.stdout.strip().splitlines()[-1] == "0 []", run.stdout + run.stderr
