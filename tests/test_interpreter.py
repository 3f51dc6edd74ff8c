"""The wrong Python gets one paragraph and exit code 2, never a traceback.

For real: a bare virtual environment (no pip, no packages) with only the engine's source on
PYTHONPATH runs ``python -m engine`` as the system's Python does when the environment was not
activated — directly, and started by ``mpiexec -n 2`` (one paragraph, not one per rank). About
5 s (creating the environment takes most of it).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from engine.interpreter import REQUIRED, launcher_mismatch, launcher_seen, missing_modules
from engine.study.examples import study_toml
from tests.mpi.test_engine_mpi import MPIEXEC

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def bare_python(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("bare")
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(folder)], check=True)
    return folder / "bin" / "python"


def _run(command: list[str], cwd: Path) -> subprocess.CompletedProcess:
    env = {key: value for key, value in os.environ.items() if key != "VIRTUAL_ENV"}
    env["PYTHONPATH"] = str(REPO)
    return subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, timeout=120)


def _assert_one_paragraph(result: subprocess.CompletedProcess, python: Path, missing: list[str]):
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr  # one paragraph, once
    text = lines[0]
    assert text.startswith(f"error: this Python cannot run the engine: {python} (Python ")
    assert f"has no {', '.join(missing)}." in text
    return text


def test_a_python_without_the_dependencies_is_told_what_to_run(bare_python, tmp_path):
    (tmp_path / "study.toml").write_text(study_toml("s", "s.h5"))
    result = _run([str(bare_python), "-m", "engine", "study.toml"], tmp_path)
    text = _assert_one_paragraph(result, bare_python, list(REQUIRED))
    if (REPO / ".venv" / "bin" / "python").exists():  # a development checkout
        venv = REPO / ".venv" / "bin"
        assert f"Use: {venv}/mpiexec -n 2 {venv}/python -m engine study.toml" in text
    assert not (tmp_path / "s.h5").exists()


def test_the_same_from_the_source_tree_shows_relative_commands(bare_python):
    result = _run([str(bare_python), "-m", "engine", "studies/demo.toml", "--dry-run"], REPO)
    text = _assert_one_paragraph(result, bare_python, list(REQUIRED))
    if (REPO / ".venv" / "bin" / "python").exists():
        expected = "Use: .venv/bin/mpiexec -n 2 .venv/bin/python -m engine studies/demo.toml"
        assert expected in text


def test_plot_needs_only_the_analysis_dependencies(bare_python, tmp_path):
    result = _run([str(bare_python), "-m", "engine", "plot", "r.h5"], tmp_path)
    _assert_one_paragraph(result, bare_python, ["numpy", "h5py", "pandas", "matplotlib"])


@pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec")
def test_under_mpiexec_the_paragraph_comes_once(bare_python, tmp_path):
    (tmp_path / "study.toml").write_text(study_toml("s", "s.h5"))
    result = _run([MPIEXEC, "-n", "2", str(bare_python), "-m", "engine", "study.toml"], tmp_path)
    _assert_one_paragraph(result, bare_python, list(REQUIRED))


def test_this_python_has_everything():
    assert missing_modules(list(REQUIRED)) == []


def test_a_launcher_of_another_mpi_is_recognised():
    # Open MPI's mpiexec starting ranks whose mpi4py uses MPICH: each sees a world of 1
    text = launcher_mismatch(1, {"OMPI_COMM_WORLD_SIZE": "2", "OMPI_COMM_WORLD_RANK": "0"})
    assert text.startswith("error: the launcher started 2 ranks (OMPI_COMM_WORLD_SIZE=2)")
    assert "-m engine" in text
    assert launcher_mismatch(1, {"PMI_SIZE": "2", "PMI_RANK": "1"}) == ""  # rank 1: quiet
    assert launcher_mismatch(2, {"PMI_SIZE": "2", "PMI_RANK": "0"}) is None  # agree
    assert launcher_mismatch(1, {}) is None  # no launcher: a serial run
    assert launcher_mismatch(1, {"PMI_SIZE": "1"}) is None


def test_srun_without_the_pmi_plugin_is_recognised():
    """srun at MpiDefault=none: every task of the step a world of 1, no PMI variables."""
    step = {"SLURM_STEP_NUM_TASKS": "2", "SLURM_NTASKS": "2", "SLURM_STEP_ID": "0"}
    text = launcher_mismatch(1, {**step, "SLURM_PROCID": "0"})
    assert text.startswith("error: srun started 2 tasks (SLURM_STEP_NUM_TASKS=2) but MPI sees")
    assert "`srun --mpi=pmi2` (MPICH, Intel MPI)" in text and "`srun --mpi=pmix`" in text
    assert "\n" not in text  # one line
    assert launcher_mismatch(1, {**step, "SLURM_PROCID": "1"}) == ""  # task 1: quiet
    assert launcher_mismatch(2, {**step, "SLURM_PROCID": "0"}) is None  # connected
    # a world smaller than the step, not only a world of 1
    assert launcher_mismatch(2, {"SLURM_STEP_NUM_TASKS": "4", "SLURM_STEP_ID": "0"})
    # SLURM_NTASKS counts inside a step only (older SLURMs without SLURM_STEP_NUM_TASKS)
    assert launcher_mismatch(1, {"SLURM_NTASKS": "2", "SLURM_STEPID": "0"}).startswith(
        "error: srun started 2 tasks (SLURM_NTASKS=2)"
    )


def test_a_serial_run_in_a_batch_script_or_salloc_shell_is_allowed():
    """The batch shell and an salloc shell hold the allocation's SLURM_NTASKS but are no
    step: a serial run there, or an mpiexec of fewer ranks, is legitimate."""
    batch = {"SLURM_NTASKS": "32", "SLURM_PROCID": "0", "SLURM_JOB_ID": "7"}
    assert launcher_mismatch(1, batch) is None
    assert launcher_mismatch(2, {**batch, "PMI_SIZE": "2", "PMI_RANK": "0"}) is None


def test_a_process_typed_alone_is_told_from_a_launched_one():
    """Alone (no MPI is initialised: engine.parallel.serial) only without any launcher's
    variable; a batch or salloc shell is no launcher, an srun step is one."""
    assert not launcher_seen({})
    assert not launcher_seen({"SLURM_NTASKS": "32", "SLURM_JOB_ID": "7", "HOME": "/h"})
    for launched in (
        {"PMI_SIZE": "1", "PMI_RANK": "0"},  # MPICH's Hydra, Intel MPI
        {"OMPI_COMM_WORLD_SIZE": "1"},  # Open MPI's mpirun
        {"PMIX_RANK": "0"},  # a PMIx launcher (prterun, srun --mpi=pmix)
        {"MPI_LOCALNRANKS": "1"},  # Hydra
        {"SLURM_STEP_ID": "0"},  # an srun step, whatever its --mpi plug-in
    ):
        assert launcher_seen(launched), launched


def test_srun_with_a_plugin_of_another_mpi_is_recognised():
    """srun --mpi=pmi2 set PMI_SIZE, but mpi4py's MPI did not take it up."""
    env = {"SLURM_STEP_NUM_TASKS": "2", "SLURM_STEP_ID": "0", "PMI_SIZE": "2", "PMI_RANK": "0"}
    text = launcher_mismatch(1, env)
    assert text.startswith("error: srun started 2 tasks (PMI_SIZE=2) but MPI sees a world of 1")
    assert "mpi4py" in text and "another MPI" in text


def test_the_readme_writes_every_command_with_the_environments_programs():
    """One form throughout: the environment's own programs (``.venv/bin/…``)."""
    readme = " ".join((REPO / "README.md").read_text().split())  # line breaks as spaces
    for command in ("python -m engine", "mpiexec -n"):
        starts = [i for i in range(len(readme)) if readme.startswith(command, i)]
        assert starts, command
        for start in starts:
            context = readme[max(0, start - 40) : start + 40]
            assert readme[max(0, start - 10) : start] == ".venv/bin/", context
