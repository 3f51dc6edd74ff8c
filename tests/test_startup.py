"""Start-up of a run: the compute path imports neither SciPy nor pandas, and the
FFT length helper that replaced SciPy's gives SciPy's lengths (so the subsurface lattices,
hence the stresses, keep their bits)."""

import os
import subprocess
import sys
from pathlib import Path

from engine.interpreter import launcher_seen
from engine.kernels.fft import next_fast_length

REPO = Path(__file__).resolve().parents[1]


def test_next_fast_length_is_scipys_real_next_fast_len():
    """Exact equality (integers) over every length a lattice of up to 2500² points needs."""
    from scipy.fft import next_fast_len

    lengths = range(1, 5001)
    assert [next_fast_length(n) for n in lengths] == [next_fast_len(n, real=True) for n in lengths]


def test_compute_path_imports_neither_scipy_nor_pandas():
    """The modules a rank imports to compute and write cases (0.2 s of CPU each saved)."""
    code = (
        "import sys\n"
        "import engine.cli, engine.output.collective, engine.output.hdf5, engine.study.case\n"
        "import engine.solvers.contact, engine.solvers.cyclic, engine.solvers.subsurface\n"
        "import engine.study.operators, engine.study.checkpoint\n"
        "print(sorted(m for m in ('scipy', 'pandas', 'matplotlib') if m in sys.modules))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.strip() == "[]", run.stdout


def test_a_whole_run_imports_neither_scipy_nor_pandas(tmp_path):
    """From the study file to the results file and the summary CSV (written without pandas:
    its import was 0.2 s on the writing rank, before the first case and after the last)."""
    from engine.study.examples import study_toml

    study = tmp_path / "t.toml"
    study.write_text(
        study_toml(
            "t",
            str(tmp_path / "t.h5"),
            mesh={"n": 8},
            loading={"kind": "static", "steps": 1},
            sweep={"mu1": [0.1, 0.3]},
        )
    )
    code = (
        "import sys\n"
        "from engine.cli import main\n"
        "status = main([sys.argv[1], '--no-progress-bar'])\n"
        "print(status, sorted(m for m in ('scipy', 'pandas', 'matplotlib') if m in sys.modules))\n"
        "print(sorted(m for m in sys.modules if m.startswith('engine.calibration.')))\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code, str(study)], capture_output=True, text=True, cwd=tmp_path
    )
    assert run.stdout.strip().splitlines()[-2] == "0 []", run.stdout + run.stderr
    # a study without [calibrate] loads no calibration module (engine.calibration, PEP 562)
    assert run.stdout.strip().splitlines()[-1] == "[]", run.stdout
    assert (tmp_path / "t.csv").read_text().count("\n") == 3  # header and two cases


def test_the_reports_closed_forms_import_scipy_only_when_a_root_is_searched():
    """The fretting report and its analytic references (Mindlin, Hertz, the axisymmetric
    punches) load without SciPy (its import was 0.4 s of a 0.7 s report); SciPy comes in only
    with the bounded searches that need it (Hertz's axis peak, a rounded punch's radius)."""
    code = (
        "import sys\n"
        "import engine.analysis.fretting_report, engine.analysis.report\n"
        "import engine.reference.mindlin, engine.reference.hertz, engine.reference.axisymmetric\n"
        "print(sorted(m for m in ('scipy', 'pandas', 'matplotlib') if m in sys.modules))\n"
        "engine.reference.hertz.axis_von_mises_peak(0.3)\n"
        "print('scipy' in sys.modules)\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.split() == ["[]", "True"], run.stdout


def test_a_process_typed_alone_loads_no_mpi(tmp_path):
    """Without a launcher the command runs on a world of one rank that is not MPI's (17 MB of
    mpi4py saved), and its files are bit-identical to those of the same command on
    ``MPI.COMM_WORLD`` (scripts/compare_results.py, no tolerance)."""
    from engine.study.examples import study_toml

    text = study_toml(
        "t", "t.h5", mesh={"n": 8}, loading={"kind": "static", "steps": 1},
        sweep={"mu1": [0.1, 0.3]},
    )  # fmt: skip
    code = (
        "import sys\n"
        "import engine.cli\n"
        "if sys.argv[2] == 'mpi':\n"
        "    from mpi4py import MPI\n"
        "    engine.cli._world = lambda: MPI.COMM_WORLD\n"
        "status = engine.cli.main(['t.toml', '--no-progress-bar'])\n"
        "print(status, 'mpi4py' in sys.modules)\n"
    )
    environ = {k: v for k, v in os.environ.items() if not launcher_seen({k: v})}
    for world, expected in (("serial", "0 False"), ("mpi", "0 True")):
        (tmp_path / world).mkdir()
        (tmp_path / world / "t.toml").write_text(text)
        run = subprocess.run(
            [sys.executable, "-c", code, "t.toml", world],
            capture_output=True, text=True, cwd=tmp_path / world, env=environ,
        )  # fmt: skip
        assert run.stdout.strip().splitlines()[-1] == expected, run.stdout + run.stderr
    compare = [sys.executable, str(REPO / "scripts" / "compare_results.py")]
    for name in ("t.h5", "t.csv"):
        files = [str(tmp_path / world / name) for world in ("serial", "mpi")]
        check = subprocess.run([*compare, *files], capture_output=True, text=True)
        assert check.returncode == 0, check.stdout + check.stderr
