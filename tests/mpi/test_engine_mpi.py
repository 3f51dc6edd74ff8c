"""The product as users meet it: ``mpiexec -n 2 python -m engine STUDY.toml``.

Every test launches real processes — real MPI ranks, real HDF5 files, real signals — with the
``mpiexec`` of the virtualenv (the ``mpich`` wheel). Run with ``python -m pytest tests/mpi``.
The studies are the demo's physics on a coarse mesh, so the whole file runs in about two
minutes on two cores.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest

import engine
from engine.study.examples import study_toml

pytestmark = pytest.mark.mpi

REPO = Path(__file__).resolve().parents[2]
# The engine's interpreter and mpiexec: by default this virtualenv's (the `mpich` wheel).
# ENGINE_PYTHON / ENGINE_MPIEXEC select another environment, e.g. the MPI-enabled h5py of
# scripts/build_parallel_h5py.sh with Debian's `mpiexec.mpich` (scripts/test.sh, second run).
PYTHON = os.environ.get("ENGINE_PYTHON") or sys.executable
MPIEXEC = (
    os.environ.get("ENGINE_MPIEXEC")
    or shutil.which("mpiexec", path=str(Path(PYTHON).parent))
    or shutil.which("mpiexec")
)
VOLATILE_ATTRS = {"rank", "runtime_s", "cpu_s", "command_line", "summary"}


def study_text(name, output, *, cycles=10000, mu1=(0.1, 0.4), beta=(0.0,), **sections) -> str:
    """Cyclic runs, P = 750 N, n = 32: one case takes 2–5 s here. ``sections``: changes
    (engine.study.examples.study_toml)."""
    base = {
        "mesh": {"n": 32},
        # coarse cycle jumping: fast enough for CI (accuracy: tests/test_cyclic*)
        "loading": {
            "steps": 4,
            "cycles": cycles,
            "record": [1000, cycles],
            "max_wear_fraction": 0.02,
        },
        "subsurface": {"layers": 8},
        "sweep": {"mu1": list(mu1), "wear1": [1.33e-7], "beta": list(beta)},
    }
    return study_toml(name, output, base, **sections)


def write_study(tmp_path: Path, name: str, **changes) -> Path:
    """``tmp_path/<name>.toml`` of :func:`study_text` writing ``tmp_path/<name>.h5``."""
    path = tmp_path / f"{name}.toml"
    path.write_text(study_text(name, tmp_path / f"{name}.h5", **changes))
    return path


def engine_command(study: Path, *options: str, ranks: int = 2) -> list[str]:
    return [MPIEXEC, "-n", str(ranks), PYTHON, "-m", "engine", str(study), *options]


def environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    return env


def signal_ranks(study: Path, signum: int) -> int:
    """Send ``signum`` to the engine's rank processes of the run on ``study``, as SLURM does
    with its pre-timeout signal (to the tasks, not to a launcher). Returns how many got it.

    Sending it to mpiexec instead depends on the launcher: PyPI's Hydra 5.0 forwards it and
    returns the ranks' exit code, Debian's Hydra 4.0.2 forwards it but then exits 0.
    """
    count = 0
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            argv = (entry / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        words = [word.decode(errors="replace") for word in argv if word]
        if (
            len(words) >= 4
            and Path(words[0]).name.startswith("python")
            and words[1:3] == ["-m", "engine"]
            and str(study) in words[3:]
        ):
            os.kill(int(entry.name), signum)
            count += 1
    return count


def run_engine(study: Path, *options: str, ranks: int = 2, timeout: float = 180):
    return subprocess.run(
        engine_command(study, *options, ranks=ranks),
        cwd=study.parent,
        env=environment(),
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def run_on_one_and_two_ranks(tmp_path: Path, write_study, timeout: float = 300) -> list[Path]:
    """The study ``write_study(folder)`` writes (its path; results named after it) run in
    ``ranks1/`` on 1 rank and in ``ranks2/`` on 2; both must succeed, and their results are
    the same (:func:`assert_same_results`). Returns the two results files."""
    results = []
    for ranks in (1, 2):
        folder = tmp_path / f"ranks{ranks}"
        folder.mkdir()
        study = write_study(folder)
        run = run_engine(study, ranks=ranks, timeout=timeout)
        assert run.returncode == 0, run.stdout + run.stderr
        results.append(study.with_suffix(".h5"))
    assert_same_results(*results)
    return results


def finished_cases(stdout: str) -> list[str]:
    """Case ids of the per-case progress lines ``[k/N] case_id rank r  t s  status``."""
    return [line.split()[1] for line in stdout.splitlines() if line.startswith("[")]


def comparable_summary(path: Path) -> pd.DataFrame:
    return engine.load_summary(path).drop(columns=["runtime_s"])


def dataset_attrs(dataset: h5py.Dataset) -> dict:
    """A dataset's attributes, its dimension scales (object references, which differ between
    files) by the names of the datasets they refer to."""
    attrs = dict(dataset.attrs)
    if "DIMENSION_LIST" in attrs:
        attrs["DIMENSION_LIST"] = [[scale.name for scale in axis.values()] for axis in dataset.dims]
    if "REFERENCE_LIST" in attrs:
        file = dataset.file
        attrs["REFERENCE_LIST"] = sorted(
            (file[reference].name, int(axis)) for reference, axis in attrs["REFERENCE_LIST"]
        )
    return attrs


def assert_same_results(path_a: Path, path_b: Path) -> None:
    """Same groups and datasets (to round-off), same attributes except run-dependent ones."""
    with h5py.File(path_a, "r") as a, h5py.File(path_b, "r") as b:
        assert sorted(a["cases"]) == sorted(b["cases"])
        for name in a["cases"]:
            group_a, group_b = a["cases"][name], b["cases"][name]
            scales = magnitude_per_unit(group_b)
            names_a, names_b = [], []
            group_a.visit(names_a.append)
            group_b.visit(names_b.append)
            assert sorted(names_a) == sorted(names_b), name
            for item in names_a:
                if isinstance(group_a[item], h5py.Dataset):
                    units = group_b[item].attrs["units"]
                    assert_round_off_equal(
                        group_a[item][()], group_b[item][()], scales[units], f"{name}/{item}"
                    )
                    assert dataset_attrs(group_a[item]) == dataset_attrs(group_b[item])
            for key, value in group_a.attrs.items():
                if key not in VOLATILE_ATTRS:
                    assert group_b.attrs[key] == value, (name, key)
        for key in ("study_toml", "study_fingerprint", "engine_version", "format"):
            assert a.attrs[key] == b.attrs[key] or key == "study_toml"
    pd.testing.assert_frame_equal(
        comparable_summary(path_a), comparable_summary(path_b), check_exact=True
    )


# Bit for bit: the engine plans its FFTs with FFTW_ESTIMATE ([solver] fft_planner default), so
# every process uses the same plans and sums in the same order. (With "measure", plans are
# chosen by timing and two processes differed by ~4e-15 relative.)
RTOL = 0.0


def magnitude_per_unit(group: h5py.Group) -> dict[str, float]:
    """Largest magnitude of each physical quantity (by units) in a case group."""
    scales: dict[str, float] = {}

    def visit(name, item):
        if isinstance(item, h5py.Dataset) and item.size:
            units = item.attrs["units"]
            scales[units] = max(scales.get(units, 0.0), float(np.max(np.abs(item[()]))))

    group.visititems(visit)
    return scales


def assert_round_off_equal(actual, desired, scale: float, message: str) -> None:
    """Relative to the magnitude of the quantity in the case (a shear stress that is zero in
    exact arithmetic is round-off noise of the normal stresses)."""
    actual, desired = np.asarray(actual), np.asarray(desired)
    assert actual.shape == desired.shape, message
    if actual.dtype.kind in "fc":
        np.testing.assert_allclose(actual, desired, rtol=RTOL, atol=RTOL * scale, err_msg=message)
    else:
        np.testing.assert_array_equal(actual, desired, err_msg=message)


@pytest.fixture(scope="module")
def reference_run(tmp_path_factory):
    """The demo-like study, uninterrupted, on two ranks (shared by several tests)."""
    tmp_path = tmp_path_factory.mktemp("reference")
    study = write_study(tmp_path, "ref", cycles=100000, mu1=(0.1, 0.2, 0.4), beta=(0.0, 90.0))
    result = run_engine(study)
    assert result.returncode == 0, result.stderr
    return study, tmp_path / "ref.h5", result


def test_two_ranks_and_one_rank_give_identical_summaries(reference_run, tmp_path):
    """The same study on 2 ranks and on 1 rank; both ranks computed cases."""
    study, two_ranks, result = reference_run
    one_rank = tmp_path / "one.h5"
    serial = run_engine(study, "--output", str(one_rank), ranks=1)
    assert serial.returncode == 0, serial.stderr
    pd.testing.assert_frame_equal(
        comparable_summary(two_ranks), comparable_summary(one_rank), check_exact=True
    )
    assert_same_results(two_ranks, one_rank)
    with h5py.File(two_ranks, "r") as file:
        ranks = {int(group.attrs["rank"]) for group in file["cases"].values()}
        assert ranks == {0, 1}, "rank 0 and rank 1 both compute"
        assert file.attrs["command_line"].startswith("python -m engine")
        assert "[sweep]" in file.attrs["study_toml"]
    summary = engine.load_summary(two_ranks.with_suffix(".csv"))
    assert (summary["status"] == "completed").all() and len(summary) == 6
    assert (summary["cycles"] == 100000).all()


def test_sigterm_then_resume_completes_without_recomputing(reference_run, tmp_path):
    """SIGTERM mid-run, rerun; nothing completed is computed twice, and the final file equals the
    uninterrupted run's."""
    reference_study, reference, _ = reference_run
    study = tmp_path / "ref.toml"
    study.write_text(
        reference_study.read_text().replace(str(reference_study.parent), str(tmp_path))
    )
    output = tmp_path / "ref.h5"
    process = subprocess.Popen(
        engine_command(study),
        cwd=tmp_path,
        env=environment(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    lines = []
    for line in process.stdout:  # wait for the first finished case, then stop the run
        lines.append(line)
        if line.startswith("[1/"):
            assert signal_ranks(study, signal.SIGTERM) == 2
            break
    out, err = process.communicate(timeout=120)
    first = "".join(lines) + out
    assert process.returncode == 3, err  # interrupted: rerun to resume
    assert "SIGTERM received" in err
    done_first = [
        case
        for case, status in zip(finished_cases(first), _statuses(first), strict=True)
        if status == "completed"
    ]
    assert 1 <= len(done_first) < 6
    partial = engine.load_summary(output)  # the interrupted file is readable
    assert set(partial.loc[partial.status == "completed", "case_id"]) == set(done_first)
    assert (partial.status != "completed").any()

    second = run_engine(study)
    assert second.returncode == 0, second.stderr
    redone = finished_cases(second.stdout)
    assert not set(redone) & set(done_first), "a completed case was computed twice"
    assert sorted(redone + done_first) == sorted(engine.load_summary(output).case_id)
    assert not (tmp_path / "ref.h5.checkpoints").exists() or not any(
        (tmp_path / "ref.h5.checkpoints").iterdir()
    )
    assert_same_results(output, reference)


def _statuses(stdout: str) -> list[str]:
    return [line.split()[-1] for line in stdout.splitlines() if line.startswith("[")]


def test_failed_case_is_reported_and_the_rest_complete(tmp_path):
    """A case forced to fail ([testing] fail_cases) -> status failed, message and traceback stored,
    the other cases complete, exit code 1."""
    testing = {"fail_cases": ["mu0.2_w1.33e-07_b0"]}
    study = write_study(tmp_path, "fail", mu1=(0.1, 0.2, 0.4), testing=testing)
    result = run_engine(study)
    assert result.returncode == 1, result.stderr
    assert "failed: InjectedFailure" in result.stdout
    summary = engine.load_summary(tmp_path / "fail.h5")
    statuses = dict(zip(summary.case_id, summary.status, strict=True))
    assert statuses == {
        "mu0.1_w1.33e-07_b0": "completed",
        "mu0.2_w1.33e-07_b0": "failed",
        "mu0.4_w1.33e-07_b0": "completed",
    }
    with h5py.File(tmp_path / "fail.h5", "r") as file:
        failed = file["cases/mu0.2_w1.33e-07_b0"]
        assert "fails on purpose" in failed.attrs["message"]
        assert "Traceback" in failed.attrs["traceback"]


BAD_INPUT = {
    "malformed": (lambda t: t.replace("n = 32", "n = = 32"), "malformed TOML"),
    "unknown key": (lambda t: t.replace("n = 32", "n = 32\ncolour = 1"), "[mesh] colour"),
    "missing section": (lambda t: t.replace("[punch]\nradius = 1.8\n", ""), "[punch]"),
    "negative load": (lambda t: t.replace("load = 750.0", "load = -750.0"), "[loading] load"),
    "negative friction": (
        lambda t: t.replace("mu1 = [0.1, 0.4]", "mu1 = [0.1, -0.4]"),
        "[sweep] mu1",
    ),
    "poisson 0.5": (lambda t: t.replace("nu_A = 0.3", "nu_A = 0.5"), "[material] nu_A"),
    "record beyond cycles": (
        lambda t: t.replace("record = [1000, 10000]", "record = [1000, 20000]"),
        "[loading] record",
    ),
}


@pytest.mark.parametrize("kind", sorted(BAD_INPUT))
def test_bad_input_exits_2_before_touching_any_file(kind, tmp_path):
    """Exit code 2, a message naming the key and the file, no output created; an existing results
    file is left byte-for-byte unchanged."""
    edit, key = BAD_INPUT[kind]
    good = write_study(tmp_path, "good")
    bad = tmp_path / "bad.toml"
    bad.write_text(edit(good.read_text()).replace("good.h5", "bad.h5"))
    result = run_engine(bad, timeout=60)
    assert result.returncode == 2, result.stderr
    assert str(bad) in result.stderr and key in result.stderr, result.stderr
    assert not (tmp_path / "bad.h5").exists() and not (tmp_path / "bad.csv").exists()
    assert "Traceback" not in result.stderr


def test_bad_input_leaves_existing_results_unchanged(reference_run, tmp_path):
    study, reference, _ = reference_run
    before = reference.read_bytes(), reference.with_suffix(".csv").read_bytes()
    bad = tmp_path / "bad.toml"
    bad.write_text(study.read_text().replace("load = 750.0", "load = -1.0"))
    result = run_engine(bad, timeout=60)
    assert result.returncode == 2
    assert (reference.read_bytes(), reference.with_suffix(".csv").read_bytes()) == before
    # a different study pointing at the same file is refused too (would mix results)
    other = tmp_path / "other.toml"
    other.write_text(study.read_text().replace("load = 750.0", "load = 700.0"))
    result = run_engine(other, timeout=60)
    assert result.returncode == 2 and "--fresh" in result.stderr
    assert (reference.read_bytes(), reference.with_suffix(".csv").read_bytes()) == before


def test_dry_run_lists_cases_and_creates_nothing(tmp_path):
    study = write_study(tmp_path, "dry", mu1=(0.1, 0.2), beta=(0.0, 45.0))
    start = time.perf_counter()
    result = run_engine(study, "--dry-run", timeout=60)
    assert result.returncode == 0
    assert result.stdout.count("mu0.") == 4
    assert not (tmp_path / "dry.h5").exists()
    assert time.perf_counter() - start < 30
