"""Memory a case needs, checked against the machine before anything is created.

Peak resident memory of one case, measured with ``ru_maxrss`` through ``python -m engine``
(one process, the engine's imports included) on one-case static studies of the paper's
coupled pair (16 subsurface layers, one load step) at n = 128 … 2048, and cyclic ones at
n = 128 and 256::

    memory ≈ 80 MB + n² · (solver + cycled) + plane bytes
    solver = 960 frictional, 200 when every case of the plan is frictionless (μ1 = μ2 = 0)
    plane  = kept + 60 kB · n,   kept = 145 · n² · layers if that is <= 64 MiB, else 0
    cycled = 600 + 48 · increments per simulated cycle   (cyclic, fretting; 0 for static)

The solver's share is the frictional contact solver: the kernel spectra it needs (the real
half of an even kernel's, 8 B per padded frequency, ~16 B per element; the imaginary half of
the two odd ones, as much; one to three frictionless and six frictional), padded FFT buffers
(~48 B per element and field, up to three fields), the solver's work arrays and their
temporaries, which come and go during the solve (at 2048² its resident memory swings by
about 0.9 GB, and its peak comes late). With μ = 0.2 the command's peak grows by 920–950 B
per element from 256² to 2048² (``benchmarks/bench_memory.py`` states the 2048² peak beside
this estimate, in the memory page); the estimate takes 960 so as to stay above it, and
errs high on small grids, where the imports weigh more. A frictionless solve keeps the normal
problem's spectra and buffers alone: its peaks grow by 160–180 B per element from 1024² to
2048², and the estimate takes 200. ``test_the_estimate_bounds_the_measured_peak`` measures
both at 256².

The plane term is the x–z plane's subsurface kernel spectra kept between calls (six
components and three loads per layer on the folded line lattice, all of them if they fit in
the evaluator's ``DEFAULT_KERNEL_CACHE_LIMIT`` of 64 MiB, else none) and one block of rows
streamed through it (``engine.kernels.lattice.ROW_BLOCK`` rows × 2n offsets: corner
functions, coefficients and their spectra, ~60 kB per element along the line); the cycled
term the histories, records and the warm start, which keeps the pressure and both tractions
of every increment of two simulated cycles (2 · 3 · 8 B per element and increment; a
simulated cycle has 2·steps increments when cyclic, 4·steps when fretting).

A line contact (plane strain, ``[punch] shape`` cylinder or pad) has n elements, not n²,
and its memory grows linearly in n::

    memory ≈ 80 MB + n · (1000 + 600 · layers + 48 · increments per simulated cycle) bytes

fitted on fretting cases of a cylinder (``python -m engine``, ``ru_maxrss``, 2026-11-28, the
2-core machine at load ~12) with n = 1,024 … 16,384, 8 and 32 layers, 16 and 64 increments
per cycle: n = 16,384 with 32 layers 397 MB measured, 423 MB estimated; with 8 layers 172 MB,
188 MB; n = 4,096 with 8 layers 103 MB, 107 MB (the fit errs high by 4–9 %). The layer term
is the line lattice's stress-kernel spectra; a 2,048-element case with 8 layers needs ~93 MB.

A ``[fatigue]`` section adds, per increment of a simulated cycle, 48 B per element and
330 B per point of the stress plane (``FATIGUE_BYTES_PER_*``: the arrays it keeps and its
temporaries); measured: a 3-D fretting case at n = 128, 40 layers, 80 increments peaks at
473 MB without and 664 MB with all four criteria (2026-11-27), the estimate adds 199 MB.

Every rank of a node runs a case at the same time, so ``ranks on the node × estimate`` of the
largest case of the plan (mesh, layers and steps may be swept) must fit in the node's memory:
physical memory, or the cgroup limit of the job when it is smaller (SLURM and containers set
one).
"""

from __future__ import annotations

import os
from pathlib import Path

from engine.solvers.subsurface import DEFAULT_KERNEL_CACHE_LIMIT

from .config import StudyConfig, StudyConfigError
from .plan import Plan

__all__ = ["case_memory_bytes", "largest_case", "memory_limit_bytes", "check_memory"]

BASE_BYTES = 80e6
BYTES_PER_ELEMENT = 960.0  # frictional (module docstring)
BYTES_PER_ELEMENT_FRICTIONLESS = 200.0  # every case μ1 = μ2 = 0: the normal problem alone
BYTES_PER_ELEMENT_AND_LAYER = 145.0  # kernel spectra of the plane, if all fit the cache
STREAM_BYTES_PER_COLUMN = 60e3  # one block of the plane's rows, per element along the line
BYTES_PER_ELEMENT_CYCLED = 600.0
BYTES_PER_ELEMENT_AND_INCREMENT = 48.0  # warm start: 2 cycles × 3 fields × 8 B
# [fatigue], per increment of the evaluated cycle: its tractions twice (the recorder and the
# critical-distance evaluator: 2 × 3 fields × 8 B per element) and, per point of the stress
# plane, the plane kept (11 arrays), the history (6 components) and the criteria's
# temporaries (about four histories): 8 B × (11 + 6 + 4 · 6) ≈ 330 B.
FATIGUE_BYTES_PER_ELEMENT = 48.0
FATIGUE_BYTES_PER_POINT = 330.0
# A line contact's n elements (module docstring): the solver and its spectra, the line
# lattice's stress kernels per layer; the warm start per increment as in 3-D.
LINE_BYTES_PER_ELEMENT = 1000.0
LINE_BYTES_PER_ELEMENT_AND_LAYER = 600.0


def case_memory_bytes(
    n: int,
    layers: int,
    increments: int = 0,
    fatigue: bool = False,
    *,
    line: bool = False,
    frictional: bool = True,
) -> float:
    """Estimated peak memory (bytes) of one case on an n × n mesh (``line``: n elements of a
    line contact) with ``layers`` layers and ``increments`` load increments per simulated
    cycle (0: a static case); ``fatigue``: with a ``[fatigue]`` section; ``frictional``:
    False when μ1 = μ2 = 0 (module docstring)."""
    if line:
        elements = float(n)
        per_element = LINE_BYTES_PER_ELEMENT + LINE_BYTES_PER_ELEMENT_AND_LAYER * layers
        memory = BASE_BYTES + elements * (
            per_element + BYTES_PER_ELEMENT_AND_INCREMENT * increments
        )
    else:
        elements = float(n) ** 2
        per_element = BYTES_PER_ELEMENT if frictional else BYTES_PER_ELEMENT_FRICTIONLESS
        if increments:
            per_element += BYTES_PER_ELEMENT_CYCLED + BYTES_PER_ELEMENT_AND_INCREMENT * increments
        kept = BYTES_PER_ELEMENT_AND_LAYER * elements * layers
        kept = kept if kept <= DEFAULT_KERNEL_CACHE_LIMIT else 0.0  # all of them or none
        plane = kept + STREAM_BYTES_PER_COLUMN * n
        memory = BASE_BYTES + elements * per_element + plane
    if fatigue:
        plane = (n + 1) * layers  # points of the stress plane
        per_increment = FATIGUE_BYTES_PER_ELEMENT * elements + FATIGUE_BYTES_PER_POINT * plane
        memory += increments * per_increment
    return memory


def largest_case(config: StudyConfig, plan: Plan | None = None) -> tuple[int, int, int, bool]:
    """(n, layers, increments per simulated cycle, frictional) of the plan's case that needs
    the most memory (the study's own values without a plan, taken as frictional; a
    ``[fatigue]`` section counts in :func:`check_memory`)."""
    increments = config.kind.increments  # per simulated cycle, from [loading] steps
    sizes = set()
    for case in plan.cases if plan is not None else ():
        settings, n = dict(case.settings), case.mesh[0]  # the plan gives every case its mesh
        layers = settings.get("subsurface.layers", config.subsurface.layers)
        steps = settings.get("loading.steps", config.loading.steps)
        frictional = case.mu1 != 0.0 or case.mu2 != 0.0
        sizes.add((int(n), int(layers), increments(int(steps)), frictional))
    if not sizes:
        sizes.add((config.mesh.n, config.subsurface.layers, increments(config.loading.steps), True))
    fatigue, line = config.fatigue is not None, config.punch.is_line

    def memory(size) -> float:
        n, layers, cycled, frictional = size
        return case_memory_bytes(n, layers, cycled, fatigue, line=line, frictional=frictional)

    return max(sizes, key=memory)


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


def check_memory(
    config: StudyConfig,
    ranks_on_node: int = 1,
    limit: float | None = None,
    plan: Plan | None = None,
) -> None:
    """Raise :class:`StudyConfigError` (exit code 2) when the cases of one node cannot fit:
    ``ranks_on_node`` times the largest case of ``plan``."""
    limit = memory_limit_bytes() if limit is None else limit
    n, layers, increments, frictional = largest_case(config, plan)
    per_case = case_memory_bytes(
        n,
        layers,
        increments,
        fatigue=config.fatigue is not None,
        line=config.punch.is_line,
        frictional=frictional,
    )
    needed = per_case * max(1, ranks_on_node)
    if needed > limit:
        ranks = f" × {ranks_on_node} ranks on this node" if ranks_on_node > 1 else ""
        cycled = f", {increments} increments per cycle" if increments else ""
        raise StudyConfigError(
            config.source,
            "mesh.n",
            n,
            f"a case needs about {_gib(per_case)} (n = {n}, {layers} subsurface layers"
            f"{cycled}{'' if frictional else ', frictionless'}){ranks} = {_gib(needed)}, "
            f"more than the {_gib(limit)} of memory of "
            "this machine; reduce n, [subsurface] layers or [loading] steps, or run fewer "
            "ranks per node",
        )


def _gib(value: float) -> str:
    return f"{value / 2**30:.1f} GiB"
