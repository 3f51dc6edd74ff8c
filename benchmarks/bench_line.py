"""Line (plane-strain) fretting: one 1,024-element case, the McColl study and the 2-D map.

**One case** (``--case``, the default part): CPU time of one 1,024-element case to 10⁵
cycles on one core, against the 10 s target.

The case: steel cylinder R = 6 mm on a steel flat (E = 200 GPa, ν = 0.3), P = 185 N/mm,
μ = 0.9, displacement amplitude ±3 µm (partial slip: the slip limit is about 5 µm with the
datum d = 10 mm), Archard 2.75e-8 1/MPa for each body, 4 increments per quarter cycle, the
default cycle jumping and the tolerance a fretting study uses (``CYCLIC_TOLERANCE``);
1,024 elements over ±0.3 mm. It prints the CPU time, the simulated
cycles, the operator applications and the ratio to the 10 s target, and the same for a
256-element case beside it (the mesh ratio).

**The McColl study** (``--mccoll``): ``studies/mccoll_2004.toml`` (one 256-element case,
18,000 cycles) run with ``mpiexec -n 2 python -m engine``, the whole command timed (wall),
against the 60 s target; one case cannot be split, so the second rank idles.

**The 2-D fretting map** (``--map``): ``studies/line_fretting_map.toml`` (504 cases) under
``mpiexec -n 1`` and ``-n 2``, the whole command timed, and the ratio against the 0.55
target, with the CPU time of each rank's process (``_rank_cpu.py``) and the idle-machine
ratio: max(busiest rank, all CPU / cores) on 2 ranks over the CPU of the 1-rank run, the
least time an idle machine would need for the same split of the work (other processes on
the cores inflate the wall ratio).

``--update-docs`` writes the measured table (date, machine, load) into
docs/explanation/performance.md (block ``bench-line``).

    python benchmarks/bench_line.py                      # the one-case part, both meshes
    python benchmarks/bench_line.py --n 1024             # one mesh
    python benchmarks/bench_line.py --all --update-docs  # all three parts, into the docs
"""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
import time
from pathlib import Path

from bench_parallel import case_cpu_per_rank
from bench_parallel import run as run_engine

from engine.geometry import CylinderProfile
from engine.grid import Grid
from engine.kernels.line import line_operator
from engine.material import MaterialPair
from engine.solvers.contact import ContactSolver
from engine.solvers.defaults import CYCLIC_TOLERANCE
from engine.solvers.fretting import FrettingAnalysis, FrettingSettings
from engine.solvers.friction import FrictionLaw, WearLaw
from engine.solvers.scar import scar_measures, two_body_wear_law

REPO = Path(__file__).resolve().parents[1]
TARGET_S = 10.0
MCCOLL_TARGET_S = 60.0
MAP_TARGET_RATIO = 0.55


def run(n: int, cycles: int) -> dict[str, float]:
    steel = MaterialPair(200e3, 0.3, 200e3, 0.3)
    grid = Grid.line(n, 0.3)
    operator = line_operator(grid, steel, 10.0)
    solver = ContactSolver(
        grid,
        steel,
        CylinderProfile(6.0),
        FrictionLaw(0.9, 0.9),
        operator=operator,
        tol=CYCLIC_TOLERANCE,
    )
    settings = FrettingSettings(load=185.0, steps=4, cycles=cycles, amplitude=3e-3, record=())
    law = two_body_wear_law(WearLaw(2.75e-8, 2.75e-8), 1.0)
    start = time.process_time()
    result = FrettingAnalysis(solver, law, settings).run()
    cpu = time.process_time() - start
    scar = scar_measures(grid, result.state.wear, 1.0)
    return {
        "cpu_s": cpu,
        "simulated": len(result.history["cycle"]),
        "matvecs": result.matvecs,
        "converged": result.converged,
        "scar_depth_um": scar.scar_depth * 1e3,
    }


def one_case(meshes: list[int], cycles: int) -> list[tuple]:
    """The one-case part: CPU per mesh, printed side by side with the target."""
    results = {n: run(n, cycles) for n in meshes}
    rows = []
    for n, values in results.items():
        print(
            f"n = {n:5d}: CPU {values['cpu_s']:.2f} s for {cycles} cycles "
            f"({values['simulated']} simulated, {values['matvecs']} operator applications, "
            f"converged {values['converged']}, scar depth {values['scar_depth_um']:.3f} µm); "
            f"ratio to the {TARGET_S:g} s target {values['cpu_s'] / TARGET_S:.2f}",
            flush=True,
        )
        rows.append(
            (
                f"one case, {n} elements, {cycles:,} cycles (CPU, one core)",
                f"{values['cpu_s']:.2f} s",
                f"{TARGET_S:g} s" if n == 1024 else "–",
                f"{values['simulated']} cycles simulated, {values['matvecs']:,} operator "
                "applications",
            )
        )
    if len(results) > 1:
        first, second = meshes[0], meshes[1]
        ratio = results[first]["cpu_s"] / results[second]["cpu_s"]
        print(f"CPU ratio n = {first} / n = {second}: {ratio:.2f}")
    return rows


def _study_copy(name: str, folder: Path) -> Path:
    """The bundled study ``name`` in ``folder``, writing its results there."""
    target = folder / name
    shutil.copy(REPO / "studies" / name, target)
    text = target.read_text().replace('output = "results/', f'output = "{folder}/')
    target.write_text(text)
    return target


def mccoll() -> list[tuple]:
    """The McColl study on 2 ranks, the whole command timed."""
    with tempfile.TemporaryDirectory() as folder:
        study = _study_copy("mccoll_2004.toml", Path(folder))
        wall, cpu = run_engine(2, study)
        case_cpu = sum(case_cpu_per_rank(Path(folder) / "mccoll_2004.h5").values())
    print(
        f"McColl study on 2 ranks: wall {wall:.2f} s (target {MCCOLL_TARGET_S:g} s, ratio "
        f"{wall / MCCOLL_TARGET_S:.2f}); CPU of all processes {cpu:.2f} s, of the case "
        f"{case_cpu:.2f} s",
        flush=True,
    )
    return [
        (
            "studies/mccoll_2004.toml on 2 ranks (wall, whole command)",
            f"{wall:.2f} s",
            f"{MCCOLL_TARGET_S:g} s",
            f"the one case: {case_cpu:.2f} s CPU",
        )
    ]


def run_per_rank(ranks: int, study: Path) -> tuple[float, list[float]]:
    """``python -m engine STUDY --fresh`` under ``mpiexec -n RANKS``: wall time of the whole
    command, and the CPU time of each rank's process (all its threads, start-up and the
    read-back included; ``_rank_cpu.py``)."""
    import subprocess
    import sys

    from _single_core import single_core_env

    mpiexec = shutil.which("mpiexec", path=str(Path(sys.executable).parent)) or "mpiexec"
    launcher = str(Path(__file__).with_name("_rank_cpu.py"))
    with tempfile.TemporaryDirectory() as cpu_dir:
        env = dict(single_core_env(REPO), BENCH_CPU_DIR=cpu_dir)
        command = [mpiexec, "-n", str(ranks), sys.executable, launcher, str(study)]
        start = time.perf_counter()
        result = subprocess.run(
            [*command, "--fresh", "--no-progress-bar"], env=env, capture_output=True, text=True
        )
        wall = time.perf_counter() - start
        if result.returncode != 0:
            raise SystemExit(f"engine failed ({result.returncode}):\n{result.stderr[-2000:]}")
        cpu = [float((Path(cpu_dir) / f"rank{rank}.txt").read_text()) for rank in range(ranks)]
    return wall, cpu


def idle_estimate(rank_cpu: list[float]) -> float:
    """The least time an idle machine needs for the same split of the work: the busiest
    rank's CPU, and at least all the CPU spread over the cores."""
    cores = min(len(rank_cpu), os.cpu_count() or 1)
    return max(max(rank_cpu), sum(rank_cpu) / cores)


def fretting_map() -> list[tuple]:
    """The 504-case map on 1 and 2 ranks, the whole command timed, each rank's CPU measured."""
    with tempfile.TemporaryDirectory() as folder:
        study = _study_copy("line_fretting_map.toml", Path(folder))
        results = Path(folder) / "line_fretting_map.h5"
        one, one_cpu = run_per_rank(1, study)
        serial_cases = sum(case_cpu_per_rank(results).values())
        two, two_cpu = run_per_rank(2, study)
    ratio = idle_estimate(two_cpu) / idle_estimate(one_cpu)
    fixed = max(one_cpu[0] - serial_cases, 0.0)
    print(
        f"2-D map (504 cases): 1 rank {one:.2f} s, 2 ranks {two:.2f} s, wall ratio "
        f"{two / one:.3f} (target <= {MAP_TARGET_RATIO}); CPU per rank: 1 rank "
        f"{one_cpu[0]:.2f} s, 2 ranks {two_cpu[0]:.2f} + {two_cpu[1]:.2f} s; idle-machine "
        f"ratio {ratio:.3f}; case CPU {serial_cases:.2f} s, fixed CPU of a run {fixed:.2f} s; "
        f"load average {os.getloadavg()[0]:.1f}",
        flush=True,
    )
    return [
        (
            "studies/line_fretting_map.toml (504 cases), 1 rank (wall)",
            f"{one:.2f} s",
            "–",
            f"CPU {one_cpu[0]:.2f} s: cases {serial_cases:.2f} s, fixed CPU of a run {fixed:.2f} s",
        ),
        (
            "the same on 2 ranks (wall); ratio to 1 rank",
            f"{two:.2f} s; {two / one:.3f}",
            f"≤ {MAP_TARGET_RATIO}",
            f"CPU rank 0 {two_cpu[0]:.2f} s, rank 1 {two_cpu[1]:.2f} s; idle-machine ratio "
            f"{ratio:.3f}",
        ),
    ]


def write_doc_table(rows: list[tuple], parts: str) -> None:
    """The line-contact table of the manual's performance page (block ``bench-line``)."""
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    document = REPO / "docs" / "explanation" / "performance.md"
    header = ("what", "measured", "target", "detail")
    note = f"`python benchmarks/bench_line.py {parts} --update-docs`"
    replace_block(document, "bench-line", measured_on(note) + "\n" + markdown_table(header, rows))
    print(f"{document}: wrote the block bench-line")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, action="append", help="elements (default 1024, 256)")
    parser.add_argument("--cycles", type=int, default=100_000)
    parser.add_argument("--mccoll", action="store_true", help="the McColl study on 2 ranks")
    parser.add_argument("--map", action="store_true", help="the 2-D map on 1 and 2 ranks")
    parser.add_argument("--all", action="store_true", help="the one case, McColl and the map")
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/performance.md (block bench-line)",
    )  # fmt: skip
    args = parser.parse_args()
    rows: list[tuple] = []
    only_studies = (args.mccoll or args.map) and not args.all
    if not only_studies:
        rows += one_case(args.n or [1024, 256], args.cycles)
    if args.mccoll or args.all:
        rows += mccoll()
    if args.map or args.all:
        rows += fretting_map()
    if args.update_docs:
        parts = (
            "--all"
            if args.all
            else " ".join(
                flag for flag, on in (("--mccoll", args.mccoll), ("--map", args.map)) if on
            )
        )
        write_doc_table(rows, parts)


if __name__ == "__main__":
    main()
