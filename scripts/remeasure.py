"""Take every load-sensitive measurement of the manual again, in one sequence, on a quiet machine.

    python scripts/remeasure.py --list        # what it runs, in order, with the time each takes
    python scripts/remeasure.py               # run them all (refused above load average 2)
    python scripts/remeasure.py --from bench-rough   # resume the sequence at a step
    python scripts/remeasure.py --long        # also the long studies and results (below)

Each step is a benchmark or script that writes a measured block of the manual (its table
with the date, the machine and the load average), run with its own update option, or
``scripts/study_times.py``, which times the bundled studies and writes their headers. The
figures depend on the machine's load, so the sequence starts only when the one-minute load
average is at most ``--max-load`` (2), checks it again before each step, and stops (naming the
step to resume from) when it has risen above; a step that fails stops the sequence too. Each
step's time is the one its last recorded run took (a block's own figures, a study header's
time, or the script's docstring): those runs were taken on a loaded machine, so the sums are
upper bounds.

The main sequence takes about half an hour: ``bench-rough`` includes the memory of a 2048²
rough solve (several minutes alone), and ``bench-solver`` takes the
sizes its table shows (64² to 256², not 512²). ``--long`` adds the studies that take several
minutes each (``peak_regime*``, ``mesh_convergence``, ``rough_fretting``, ``rounded_punch``,
``fouvry_crack_nucleation``), the McColl results, the three benchmarks whose blocks were
already taken at load 2 or below (``bench-line``, ``bench-scheduler``, ``bench-search-scale``)
and the peak memory of a 2048² frictional case (``bench-memory``, ten minutes and about 4 GB):
over two hours more. Left to their own
commands, because their figures are not times: the Fouvry calibration table
(``python scripts/fouvry_calibration.py --ranks 2``), the cycle-jump comparison of the peak
regime study (``python scripts/peak_regime_states.py halving --update-docs``, ``final`` for its
tables, and ``scripts/peak_paper_state.py`` for the worn state of the paper's peak), the
rough-surface ensemble and the SLURM transcripts (``SLURM_TEST_UPDATE_DOCS=1 pytest
tests/slurm``, root and slurm-wlm).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
PYTHON = sys.executable
#: The scratch environment holding ASPHER and Tamaas 2.9.0 for the side-by-side benchmarks
#: (bench_anchors.py's --anchors-python, bench_rough.py's --tamaas-python).
ANCHORS_PYTHON = Path("/tmp/anchors-venv/bin/python")


@dataclass(frozen=True)
class Step:
    """One measurement: ``name``, the command (run from the repository), what it writes,
    the seconds its last recorded run took and where that figure comes from."""

    name: str
    command: tuple[str, ...]
    writes: str
    seconds: float
    source: str
    environment: tuple[tuple[str, str], ...] = ()


def _python(*arguments: str) -> tuple[str, ...]:
    return (PYTHON, *arguments)


#: Producers of measured blocks left to their own commands: their figures are not times.
ELSEWHERE = {
    "scripts/fouvry_calibration.py": "python scripts/fouvry_calibration.py --ranks 2",
    "engine.analysis.surface_report": "python -m engine.analysis.surface_report "
    "results/rough_fretting.h5 --update docs/explanation/rough-surfaces.md",
    "tests/slurm": "SLURM_TEST_UPDATE_DOCS=1 pytest tests/slurm (root, slurm-wlm)",
    "scripts/peak_regime_states.py": "python scripts/peak_regime_states.py halving --update-docs; "
    "after the regime studies, python scripts/peak_regime_states.py final results/peak_regime.h5 "
    "--update-docs (and results/peak_regime_32.h5)",
    "scripts/peak_paper_state.py": "python scripts/peak_paper_state.py --n 64 --update-docs "
    "(and --n 32)",
}

# Quick studies: the last recorded time of each (s, with `mpiexec -n 2`, on a loaded machine)
# until study_times.py writes a measured one in its header.
QUICK_STUDIES = {
    "demo": 10, "section_7_1_static": 4, "section_7_2_cyclic": 77, "section_7_2_cyclic_32": 15,
    "section_7_3_orthotropic": 141, "section_7_3_orthotropic_32": 45, "fretting_map": 23,
    "fretting_threshold": 68, "fretting_fatigue": 50, "line_fretting_map": 45,
    "load_sweep": 67, "mccoll_2004": 25, "mccoll_2004_test_load": 62,
    "sphere_normal_fretting": 120,
}  # fmt: skip
LONG_STUDIES = {
    "fouvry_crack_nucleation": 285, "mesh_convergence": 450, "rounded_punch": 342,
    "rough_fretting": 502, "peak_regime": 2220, "peak_regime_32": 1400,
    "peak_regime_halving_32": 1000,
}  # fmt: skip


def _study_seconds(name: str, recorded: float) -> float:
    """The study header's measured time when it has one, else ``recorded``."""
    sys.path.insert(0, str(REPO / "scripts"))
    try:
        import study_times
    finally:
        sys.path.remove(str(REPO / "scripts"))
    header, _ = study_times.header_lines(REPO / "studies" / f"{name}.toml")
    line = study_times.time_line(header) or ""
    if study_times.MEASURED.match(line):
        value, unit = line.removeprefix(study_times.PREFIX).split()[:2]
        return float(value.replace(",", "")) * {"s": 1, "min": 60, "h": 3600}[unit]
    return recorded


def _studies_step(name: str, studies: dict[str, float]) -> Step:
    paths = tuple(f"studies/{study}.toml" for study in studies)
    seconds = sum(_study_seconds(study, recorded) for study, recorded in studies.items())
    return Step(
        name, _python("scripts/study_times.py", *paths), "the time line of each study's header",
        seconds, "each header's measured time, else its last recorded run",
    )  # fmt: skip


def steps(long: bool = False) -> list[Step]:
    """The sequence, the quick measurements first."""
    sequence = [
        Step("bench-solver",
             _python("benchmarks/bench_solver.py", "--sizes", "64", "128", "256",
                     "--update-docs"),
             "docs/explanation/performance.md (bench-solver)", 60,
             "its table: 3 s frictionless + 38 s at μ = 0.2, plus start-up",
             (("OMP_NUM_THREADS", "1"),)),
        Step("bench-cyclic", _python("benchmarks/bench_cyclic.py", "--methods", "new",
                                     "--update-docs"),
             "docs/explanation/performance.md (bench-cyclic)", 140,
             "its table: 15 s + 123 s of solve wall time"),
        Step("bench-subsurface", _python("benchmarks/bench_subsurface.py", "--update-docs"),
             "docs/explanation/performance.md (bench-subsurface)", 30, "its docstring"),
        Step("bench-parallel", _python("benchmarks/bench_parallel.py", "--update-docs"),
             "docs/explanation/performance.md (bench-parallel)", 90,
             "its table: 25 s on 1 rank + 19 s on 2, twice"),
        Step("bench-fatigue", _python("benchmarks/bench_fatigue.py", "--repeat", "3",
                                      "--update-docs"),
             "docs/explanation/fatigue.md (bench-fatigue)", 190,
             "its table: 62 s of CPU per repeat"),
        Step("bench-anchors", _python("benchmarks/bench_anchors.py", "--sizes", "128", "256",
                                      "512", "1024", "--repeats", "3",
                                      "--anchors-python", str(ANCHORS_PYTHON), "--update-docs"),
             "docs/explanation/memory-and-setup.md (bench-anchors)", 90,
             "its table: about 17 s of CPU per round, plus the processes' start-up"),
        Step("bench-anchors-frictional",
             _python("benchmarks/bench_anchors.py", "--sizes", "256", "512", "--repeats", "2",
                     "--frictional", "--anchors-python", str(ANCHORS_PYTHON), "--update-docs"),
             "docs/explanation/memory-and-setup.md (bench-anchors-frictional)", 45,
             "its table: about 17 s of CPU per round"),
        Step("bench-cli-overhead",
             _python("benchmarks/bench_cli_overhead.py", "--repeats", "3", "--update-docs"),
             "docs/explanation/performance.md (bench-cli-overhead)", 60,
             "its docstring"),
        Step("bench-rough",
             _python("benchmarks/bench_rough.py", "--only", "tamaas", "speed", "memory",
                     "--tamaas-n", "256", "--speed-n", "512", "--memory-n", "2048",
                     "--rounds", "2", "--tamaas-python", str(ANCHORS_PYTHON), "--update-docs"),
             "docs/explanation/performance.md (bench-rough)", 620,
             "its table: 5 s + 2 × 16 s, and the 2048² memory run's 584 s"),
        Step("bench-rough-loads",
             _python("benchmarks/bench_rough.py", "--only", "loads", "--loads-n", "512",
                     "--update-docs"),
             "docs/explanation/performance.md (bench-rough-loads)", 30, "its table: 17 s of CPU"),
        Step("profile-convergence",
             _python("benchmarks/profile_convergence.py", "--update-docs"),
             "docs/explanation/profiles.md (profile-convergence)", 120,
             "no recorded time: the solver block's 64² to 256² solves, twice"),
        Step("bench-calibration", _python("benchmarks/bench_calibration.py", "--update-docs"),
             "docs/how-to/calibration.md (bench-calibration)", 285, "its table: 285 s wall"),
        Step("validation", _python("scripts/validation.py"),
             "docs/explanation/validation.md (validation)", 120, "its docstring"),
        _studies_step("study-times", QUICK_STUDIES),
    ]  # fmt: skip
    if long:
        sequence += [
            Step("bench-line", _python("benchmarks/bench_line.py", "--all", "--update-docs"),
                 "docs/explanation/performance.md (bench-line)", 170,
                 "its table: 8 + 2 + 20 + 96 + 38 s"),
            Step("bench-scheduler",
                 _python("benchmarks/bench_scheduler.py", "--cases", "2000", "--ranks", "1", "2",
                         "4", "--update-docs"),
                 "docs/explanation/performance.md (bench-scheduler)", 180, "its docstring"),
            Step("bench-search-scale",
                 _python("benchmarks/bench_search_scale.py", "--update-docs"),
                 "docs/explanation/searches.md (bench-search-scale)", 330,
                 "its table: 187 + 95 + 48 s"),
            Step("bench-memory",
                 _python("benchmarks/bench_memory.py", "--n", "2048", "--seconds", "600",
                         "--update-docs"),
                 "docs/explanation/memory-and-setup.md (bench-memory)", 565,
                 "its block: 298 s for the solve, 263 s for the command"),
            Step("mccoll-results", _python("scripts/mccoll_results.py", "--fresh"),
                 "docs/explanation/results.md (mccoll-2004 blocks)", 560,
                 "its blocks: 197 s + 308 s for the convergence studies, 60 s of single cases"),
            _studies_step("study-times-long", LONG_STUDIES),
        ]  # fmt: skip
    return sequence


def load_average() -> float:
    return os.getloadavg()[0]


def _duration(seconds: float) -> str:
    return f"{seconds / 60:.1f} min" if seconds >= 90 else f"{seconds:.0f} s"


def describe(sequence: list[Step]) -> str:
    """The sequence as ``--list`` prints it: each step, its command and time, the total."""
    lines = []
    for number, step in enumerate(sequence, 1):
        environment = " ".join(f"{key}={value}" for key, value in step.environment)
        command = " ".join((environment, *step.command)).strip().replace(PYTHON, "python")
        lines.append(f"{number:2d}. {step.name} (about {_duration(step.seconds)}: {step.source})")
        lines.append(f"    {command}")
        lines.append(f"    writes {step.writes}")
    lines.append("left to their own commands (figures that are not times):")
    lines += [f"    {command}" for command in ELSEWHERE.values()]
    total = sum(step.seconds for step in sequence)
    lines.append(f"total: about {_duration(total)} (from runs on a loaded machine: at most)")
    return "\n".join(lines)


def missing_prerequisites(sequence: list[Step]) -> list[str]:
    """What a step needs that is not here (ASPHER and Tamaas for the side-by-side comparisons)."""
    names = {step.name for step in sequence}
    needs = {"bench-anchors", "bench-anchors-frictional", "bench-rough"} & names
    if needs and not ANCHORS_PYTHON.exists():
        return [
            f"{', '.join(sorted(needs))} compare with ASPHER and Tamaas 2.9.0 from "
            f"{ANCHORS_PYTHON}: python3 -m venv /tmp/anchors-venv && "
            "/tmp/anchors-venv/bin/pip install tamaas==2.9.0 aspher"
        ]
    return []


def run(sequence: list[Step], max_load: float) -> int:
    """Run ``sequence``; 0 when every step ran, 1 when one failed, 3 when the load rose."""
    started = time.monotonic()
    for step in sequence:
        load = load_average()
        if load > max_load:
            print(f"load average {load:.1f} > {max_load:g}: stopped before {step.name}; "
                  f"resume with --from {step.name}", flush=True)  # fmt: skip
            return 3
        print(f"== {step.name} (load average {load:.1f})", flush=True)
        environment = dict(os.environ, **dict(step.environment))
        begun = time.monotonic()
        done = subprocess.run(step.command, cwd=REPO, env=environment)
        print(f"== {step.name}: {time.monotonic() - begun:.0f} s, exit {done.returncode}",
              flush=True)  # fmt: skip
        if done.returncode != 0:
            print(f"{step.name} failed; resume with --from {step.name}", flush=True)
            return 1
    print(f"every step ran in {_duration(time.monotonic() - started)}; "
          "now: python scripts/reference.py (the studies' times in the reference)")  # fmt: skip
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", action="store_true", help="print the steps; run nothing")
    parser.add_argument("--long", action="store_true", help="add the long studies and results")
    parser.add_argument("--from", dest="start", metavar="STEP", help="start at this step")
    parser.add_argument("--max-load", type=float, default=2.0)
    args = parser.parse_args(argv)
    sequence = steps(args.long)
    if args.start:
        names = [step.name for step in sequence]
        if args.start not in names:
            parser.error(f"--from {args.start}: no such step (steps: {', '.join(names)})")
        sequence = sequence[names.index(args.start) :]
    if args.list:
        print(describe(sequence))
        return 0
    load = load_average()
    if load > args.max_load:
        print(f"load average {load:.1f} > {args.max_load:g}: the figures would overstate the "
              "times; run this on a quiet machine", file=sys.stderr)  # fmt: skip
        return 2
    missing = missing_prerequisites(sequence)
    if missing:
        print("missing:\n" + "\n".join(missing), file=sys.stderr)
        return 2
    return run(sequence, args.max_load)


if __name__ == "__main__":
    sys.exit(main())
