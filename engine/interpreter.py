"""Can this Python run the engine? One paragraph instead of a traceback when it cannot.

``python -m engine`` checks, before anything else is imported, that the interpreter it runs
in has the engine's dependencies (:data:`REQUIRED`; a run needs all of them, ``plot`` and
``report`` those of :data:`OUTPUT_REQUIRED`), and, once MPI is up, that the launcher is the
one mpi4py was built for and connected the ranks (:func:`launcher_mismatch`). The usual
causes:

- a Python other than the environment's: the system ``python`` or ``python3``, or the
  system's ``mpiexec`` (Debian's ``mpich`` package) starting the system Python;
- an ``mpiexec`` of another MPI than mpi4py's: each rank then starts alone (a world of one
  rank), and every rank would run the whole study;
- ``srun`` without the PMI plug-in the MPI needs (``--mpi=pmi2`` for MPICH and Intel MPI,
  ``--mpi=pmix`` for Open MPI; a cluster's default is often ``none``): the same, every task a
  world of its own.

The error names the interpreter, what is missing and the command to use,
``.venv/bin/mpiexec -n 2 .venv/bin/python -m engine …`` (the environment's own launcher and
Python; or activate it first), and the process exits with code 2 (bad input or setup).
Standard library only: this module must import in a Python that has nothing else.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path

__all__ = [
    "REQUIRED",
    "OUTPUT_REQUIRED",
    "missing_modules",
    "environment_error",
    "launched_sizes",
    "launcher_mismatch",
    "announced_rank",
    "check_interpreter",
]

# import name -> distribution name (pyproject.toml's dependencies)
REQUIRED = {
    "numpy": "numpy",
    "scipy": "scipy",
    "pyfftw": "pyfftw",
    "h5py": "h5py",
    "pandas": "pandas",
    "mpi4py": "mpi4py",
    "tqdm": "tqdm",
    "matplotlib": "matplotlib",
}
OUTPUT_REQUIRED = ("numpy", "h5py", "pandas", "matplotlib")  # plot, report: no MPI
_OUTPUT_COMMANDS = ("plot", "report")
# world size a launcher gives each rank it starts: MPICH's Hydra and srun's PMI plug-ins,
# Open MPI's mpirun.
_LAUNCHER_SIZE = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE")
# tasks of the srun step this process belongs to, whatever the step's --mpi plug-in (none
# included). SLURM_NTASKS counts only inside a step (SLURM_STEP_ID set): in the batch
# script or an salloc shell it is the allocation's, and a serial run, or an mpiexec of fewer
# ranks, is legitimate there.
_SLURM_STEP_SIZE = "SLURM_STEP_NUM_TASKS"
_SLURM_STEP_MARK = ("SLURM_STEP_ID", "SLURM_STEPID")


def missing_modules(names: Sequence[str]) -> list[str]:
    """The modules of ``names`` this interpreter cannot find (nothing is imported)."""
    missing = []
    for name in names:
        try:
            found = importlib.util.find_spec(name) is not None
        except (ImportError, ValueError):  # a broken parent package, or a bad spec
            found = False
        if not found:
            missing.append(name)
    return missing


def _environment_python() -> Path | None:
    """The ``.venv/bin/python`` beside the engine's source tree, if there is one."""
    candidate = Path(__file__).resolve().parents[1] / ".venv" / "bin" / "python"
    return candidate if candidate.exists() else None


def _shown(path: Path) -> str:
    """``path`` relative to the working directory when below it, else absolute."""
    try:
        return str(path.relative_to(Path.cwd()))
    except ValueError:
        return str(path)


def usage_command(arguments: Sequence[str]) -> str:
    """The command to use: the environment's mpiexec and Python when they are found."""
    python = _environment_python()
    rest = " ".join(arguments) or "STUDY.toml"
    if python is None:
        return f"mpiexec -n 2 python -m engine {rest} (with the Python the engine is installed in)"
    bin_dir = python.parent
    if arguments and arguments[0] in _OUTPUT_COMMANDS:
        return f"{_shown(bin_dir / 'python')} -m engine {rest}"
    return f"{_shown(bin_dir / 'mpiexec')} -n 2 {_shown(bin_dir / 'python')} -m engine {rest}"


def environment_error(missing: Sequence[str], arguments: Sequence[str], detail: str = "") -> str:
    """The one-paragraph error for an interpreter that lacks the modules ``missing``
    (``detail``: the import error, when a module is there but cannot be imported)."""
    python = _environment_python()
    where = (
        f"the engine's environment is {_shown(python.parents[1])}/ (its own Python and mpiexec)"
        if python is not None and Path(sys.prefix).resolve() != python.parents[1].resolve()
        else "install the engine into it with `python -m pip install -e .` from the source tree"
    )
    names = ", ".join(REQUIRED.get(name, name) for name in missing)
    return (
        f"error: this Python cannot run the engine: {sys.executable} (Python "
        f"{sys.version.split()[0]}) "
        + (f"cannot import {names} ({detail})" if detail else f"has no {names}")
        + ". It is not the Python the engine is "
        f"installed in — typically the system's `python3`, or the system's `mpiexec` starting "
        f"it; {where}. Use: {usage_command(arguments)} (or activate the environment first, "
        "`source .venv/bin/activate`, and type the same without `.venv/bin/`)."
    )


def announced_rank(environ: Mapping[str, str] = os.environ) -> int:
    """The rank a launcher gave this process (MPICH/Hydra, Open MPI, srun), 0 without one."""
    for name in ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "PMIX_RANK", "SLURM_PROCID"):
        if environ.get(name, "").isdigit():
            return int(environ[name])
    return 0


def launched_sizes(environ: Mapping[str, str] = os.environ) -> dict[str, int]:
    """The number of ranks each launcher variable of ``environ`` announces, by name: the MPI
    launchers' (``PMI_SIZE``, ``OMPI_COMM_WORLD_SIZE``) and, inside an srun step, SLURM's
    (``SLURM_STEP_NUM_TASKS``, else ``SLURM_NTASKS``)."""
    names = list(_LAUNCHER_SIZE)
    if _SLURM_STEP_SIZE in environ:
        names.append(_SLURM_STEP_SIZE)
    elif any(name in environ for name in _SLURM_STEP_MARK):
        names.append("SLURM_NTASKS")
    return {name: int(environ[name]) for name in names if environ.get(name, "").isdigit()}


# prefixes of the variables an MPI launcher (Hydra, Open MPI's mpirun/prterun, PMIx, MVAPICH,
# Intel MPI, srun's PMI plug-ins) sets in the environment of the processes it starts
_LAUNCHER_PREFIXES = ("PMI_", "PMIX_", "OMPI_", "PRTE_", "HYDI_", "HYDRA_", "MPI_LOCAL",
                      "MV2_", "MPIR_", "I_MPI_HYDRA", "SLURM_STEP")  # fmt: skip


def launcher_seen(environ: Mapping[str, str] = os.environ) -> bool:
    """Whether an MPI launcher (or an srun step) may have started this process: any of its
    variables in ``environ`` (:func:`launched_sizes`, or a name with one of the launchers'
    prefixes). False only for a process typed alone, which is then a world of one rank
    without MPI being initialised; when in doubt, True (MPI decides)."""
    if launched_sizes(environ) or any(key in environ for key in _SLURM_STEP_MARK):
        return True
    return any(name.startswith(_LAUNCHER_PREFIXES) for name in environ)


def launcher_mismatch(world_size: int, environ: Mapping[str, str] = os.environ) -> str | None:
    """The error when the launcher started more ranks than MPI sees in its world
    (``world_size``); None when they agree.

    Two causes: an ``mpiexec`` of another MPI than mpi4py's, and an ``srun`` without the PMI
    plug-in of mpi4py's MPI (``--mpi=pmi2`` or ``pmix``). Either way each rank would run the
    whole study alone, so the run must stop before it touches the output. Only the rank the
    launcher numbers 0 gets the text; the others get "" (exit quietly)."""
    sizes = launched_sizes(environ)
    if not sizes or max(sizes.values()) <= world_size:
        return None
    if announced_rank(environ) != 0:
        return ""
    name, size = max(sizes.items(), key=lambda item: item[1])
    seen = f"MPI sees a world of {world_size}" + (" in each" if world_size == 1 else "")
    if name.startswith("SLURM_") and "PMI_SIZE" not in sizes:
        return (
            f"error: srun started {size} tasks ({name}={size}) but {seen}: srun did not connect "
            "them through the PMI plug-in mpi4py's MPI needs, so every task would run the "
            "whole study alone. Launch with `srun --mpi=pmi2` (MPICH, Intel MPI) or "
            "`srun --mpi=pmix` (Open MPI); `srun --mpi=list` shows this cluster's plug-ins "
            "(slurm/run_study.sbatch passes one: SRUN_MPI=… overrides it). How to check a "
            "launch: docs/how-to/slurm.md."
        )
    if name.startswith("SLURM_") or any(key in environ for key in _SLURM_STEP_MARK):
        return (
            f"error: srun started {size} tasks (PMI_SIZE={sizes.get('PMI_SIZE')}) but {seen}: "
            f"mpi4py ({sys.executable}) uses another MPI than the one srun's PMI plug-in serves "
            "(e.g. the `mpich` wheel from PyPI instead of the cluster's MPI), so every task "
            "would run the whole study alone. Build mpi4py against the cluster's MPI, or pass "
            "the plug-in its MPI needs (`srun --mpi=list`): docs/how-to/slurm.md."
        )
    return (
        f"error: the launcher started {size} ranks ({name}={size}) but {seen}: this `mpiexec` "
        f"belongs to another MPI than the one mpi4py uses ({sys.executable}), so every rank "
        f"would run the whole study alone. Use the environment's own launcher: "
        f"{usage_command(sys.argv[1:])}."
    )


def check_interpreter(arguments: Sequence[str]) -> int:
    """0 when this Python has what the command ``arguments`` needs; else print the error on
    stderr and return 2."""
    output = bool(arguments) and arguments[0] in _OUTPUT_COMMANDS
    missing = missing_modules(OUTPUT_REQUIRED if output else list(REQUIRED))
    if not missing:
        return 0
    if announced_rank() == 0:  # under mpiexec: one copy of the paragraph, not one per rank
        print(environment_error(missing, arguments), file=sys.stderr, flush=True)
    return 2
