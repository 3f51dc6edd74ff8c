"""Memory a case needs, checked against the machine before anything is created.

Peak resident memory of one case (static or cyclic: the same arrays dominate), measured with
``ru_maxrss`` for n = 64, 128, 256 and 4, 16, 32 subsurface layers (one process, the engine's
imports included)::

    memory ≈ 100 MB + n² · (1600 + 340 · layers) bytes

The n² term is the contact solver (FFT operator and work arrays on the 2n × 2n padded grid,
~1600 B per element); the layer term the subsurface stress kernels (six stress components per
layer on the padded grid, ~340 B per element and layer). The fit is within +5 % of the
measured peaks (e.g. n = 256, 32 layers: 918 MB estimated, 889 MB measured) and errs high.

Every rank of a node runs a case at the same time, so ``ranks on the node × estimate`` must
fit in the node's memory: physical memory, or the cgroup limit of the job when it is smaller
(SLURM and containers set one).
"""

from __future__ import annotations

import os
from pathlib import Path

from .config import StudyConfig, StudyConfigError

__all__ = ["case_memory_bytes", "memory_limit_bytes", "check_memory"]

BASE_BYTES = 100e6
BYTES_PER_ELEMENT = 1600.0
BYTES_PER_ELEMENT_AND_LAYER = 340.0


def case_memory_bytes(n: int, layers: int) -> float:
    """Estimated peak memory (bytes) of one case on an n × n mesh with ``layers`` layers."""
    return BASE_BYTES + float(n) ** 2 * (BYTES_PER_ELEMENT + BYTES_PER_ELEMENT_AND_LAYER * layers)


def memory_limit_bytes() -> float:
    """Memory of this machine (bytes): physical memory, or the cgroup limit if smaller."""
    limit = float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            text = Path(path).read_text().strip()
        except OSError:
            continue
        if text.isdigit():
            limit = min(limit, float(text))
    return limit


def check_memory(config: StudyConfig, ranks_on_node: int = 1, limit: float | None = None) -> None:
    """Raise :class:`StudyConfigError` (exit code 2) when the cases of one node cannot fit."""
    limit = memory_limit_bytes() if limit is None else limit
    per_case = case_memory_bytes(config.mesh.n, config.subsurface.layers)
    needed = per_case * max(1, ranks_on_node)
    if needed > limit:
        ranks = f" × {ranks_on_node} ranks on this node" if ranks_on_node > 1 else ""
        raise StudyConfigError(
            config.source,
            "mesh.n",
            config.mesh.n,
            f"a case needs about {_gib(per_case)} (n = {config.mesh.n}, "
            f"{config.subsurface.layers} subsurface layers){ranks} = {_gib(needed)}, more than "
            f"the {_gib(limit)} of memory of this machine; reduce n or [subsurface] layers, "
            "or run fewer ranks per node",
        )


def _gib(value: float) -> str:
    return f"{value / 2**30:.1f} GiB"
