"""What the benchmarks' child processes share: one core each, and the engine of a given tree."""

from __future__ import annotations

import os
from pathlib import Path


def single_core_env(code: Path) -> dict[str, str]:
    """The environment of a child process that runs the engine of ``code`` (a tree or an
    exported baseline, first on ``PYTHONPATH``) with OpenMP and OpenBLAS on one thread."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(code), env.get("PYTHONPATH")]))
    return env
