"""Can this Python run the engine? One paragraph instead of a traceback when it cannot.

``python -m engine`` checks, before anything else is imported, that the interpreter it runs
in has the engine's dependencies (:data:`REQUIRED`; a run needs all of them, ``plot`` and
``report`` those of :data:`OUTPUT_REQUIRED`), and, once MPI is up, that the launcher is the
one mpi4py was built for (:func:`launcher_mismatch`). The usual causes:

- a Python other than the environment's: the system ``python`` or ``python3``, or the
  system's ``mpiexec`` (Debian's ``mpich`` package) starting the system Python;
- an ``mpiexec`` of another MPI than mpi4py's: each rank then starts alone (a world of one
  rank), and every rank would run the whole study.

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
# world size a launcher gives each rank it starts: MPICH's Hydra and srun (PMI), Open MPI.
# Not SLURM_NTASKS: a serial run inside a many-task allocation is legitimate.
_LAUNCHER_SIZE = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE")


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


def launcher_mismatch(world_size: int, environ: Mapping[str, str] = os.environ) -> str | None:
    """The error when the launcher started more ranks than MPI sees in its world, i.e. an
    ``mpiexec`` of another MPI than mpi4py's (each rank alone); None when they agree. Only the
    rank the launcher numbers 0 gets the text; the others get "" (exit quietly)."""
    announced = {name: environ.get(name, "") for name in _LAUNCHER_SIZE}
    sizes = {name: int(value) for name, value in announced.items() if value.isdigit()}
    if world_size != 1 or not sizes or max(sizes.values()) <= 1:
        return None
    name, size = max(sizes.items(), key=lambda item: item[1])
    if announced_rank(environ) != 0:
        return ""
    return (
        f"error: the launcher started {size} ranks ({name}={size}) but MPI sees a world of 1 "
        f"in each: this `mpiexec` belongs to another MPI than the one mpi4py uses "
        f"({sys.executable}), so every rank would run the whole study alone. Use the "
        f"environment's own launcher: {usage_command(sys.argv[1:])}."
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
