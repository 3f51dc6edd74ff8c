"""``python _rank_cpu.py ARGS`` runs ``python -m engine ARGS`` and, when the process ends,
writes its CPU time (user + system, every thread) to ``$BENCH_CPU_DIR/rank<R>.txt`` (R: the
MPI rank from the launcher's ``PMI_RANK``): what each rank consumed, whatever the load of the
machine, for the benchmarks' load-independent figures."""

from __future__ import annotations

import atexit
import os
import runpy
import sys
from pathlib import Path


def _write_cpu() -> None:
    rank = os.environ.get("PMI_RANK", "0")
    times = os.times()
    path = Path(os.environ["BENCH_CPU_DIR"]) / f"rank{rank}.txt"
    path.write_text(f"{times.user + times.system}\n")


atexit.register(_write_cpu)
sys.argv = ["engine", *sys.argv[1:]]
runpy.run_module("engine", run_name="__main__", alter_sys=True)
