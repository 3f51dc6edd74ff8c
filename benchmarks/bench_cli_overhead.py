"""What ``python -m engine`` adds to the solver on a cyclic case: the whole command against the
cyclic analysis alone, side by side in one run.

The case: one case of ``studies/section_7_2_cyclic.toml`` (μ = 0.1: flat punch a0 = 1.8 mm,
P = 750 N, 64², 10 increments per half cycle, 10⁵ cycles with cycle jumping, records at
10³, 10⁴ and 10⁵ cycles, the x–z plane in 31 layers to 1.5 a0), the study file itself with
the other two values of μ left out. Two things are measured, each in a process of its own,
alternating in each round (so that they share the load), on one core:

- **solver**: the case's contact solver and wear law, built by the study's own case runner
  (``CaseContext.solver``, ``case_wear_law``), and ``CyclicAnalysis.run`` without a peak
  probe: the set-up and the cycles, CPU time (``time.process_time``) inside the process;
- **command**: ``python -m engine STUDY.toml --fresh --no-progress-bar`` on that study, CPU
  time (user + system) of the whole process (``os.wait4``): the interpreter, the imports,
  the parsing, the same analysis with the peak tracker of every simulated cycle (the σ_VM
  maxima on the x–z plane and the regions at the element centres beside it), the stress
  planes of the records, the results file, its summary and the read-back.

Printed per round: both CPU times; then the overhead of the command over the solver,
best/best − 1 (CPU times: the load of a shared machine only adds to them, so the best of
the rounds is the least inflated), and a check that both ran the same analysis (the same
maximum wear depth, bit for bit, and the same operator applications). Every process reuses
the bytecode that a first, unrecorded command compiled (``bench_anchors.use_bytecode_cache``),
as an installed package does. The load average is printed at the start and at the end.

``--baseline DIR`` measures the engine of another source tree alike in every round (before
and after a change, in one run). ``--update-docs`` writes the figures of this tree into the
block ``bench-cli-overhead`` of docs/explanation/performance.md, with the date, the machine
and the load average.

    python benchmarks/bench_cli_overhead.py --repeats 3 --update-docs
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _single_core import single_core_env
from bench_anchors import use_bytecode_cache

REPO = Path(__file__).resolve().parents[1]
STUDY = REPO / "studies" / "section_7_2_cyclic.toml"
FRICTION = 0.1


def study_text(output: Path) -> str:
    """The bundled study with one value of μ and its results written to ``output``."""
    lines = []
    for line in STUDY.read_text().splitlines():
        if line.startswith("output ="):
            line = f'output = "{output}"'
        elif line.startswith("mu1 ="):
            line = f"mu1 = [{FRICTION}]"
        lines.append(line)
    return "\n".join(lines) + "\n"


def child_solver(study: Path) -> dict:
    """The cyclic analysis of the study's one case, without the peak probe (module doc)."""
    cpu = time.process_time()
    from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
    from engine.study import outcome
    from engine.study.case import CaseRunner
    from engine.study.config import parse_study
    from engine.study.plan import make_plan

    imports = time.process_time() - cpu
    config = parse_study(study.read_text(), source=str(study))
    (case,) = make_plan(config)
    config = CaseRunner(config).config_for(case)
    cpu = time.process_time()
    solver, _, _ = CaseRunner(config).context.solver(case, config)
    loading = config.loading
    settings = CyclicSettings(
        loading.load,
        loading.steps,
        loading.cycles,
        record=loading.record,
        max_wear_fraction=loading.max_wear_fraction,
    )
    analysis = CyclicAnalysis(solver, outcome.case_wear_law(case, config), settings)
    result = analysis.run()
    return dict(
        cpu_s=time.process_time() - cpu,
        imports_cpu_s=imports,
        max_wear_depth=float(result.state.wear.max()),
        matvecs=int(result.state.matvecs),
    )


def run_solver(study: Path, tree: Path = REPO) -> dict:
    """``child_solver`` in a process of its own, with the engine of ``tree``."""
    env = single_core_env(tree)
    command = [sys.executable, __file__, "--child", str(study)]
    output = subprocess.run(command, env=env, capture_output=True, text=True, check=True)
    return json.loads(output.stdout.strip().splitlines()[-1])


def run_command(study: Path, folder: Path, tree: Path = REPO) -> dict:
    """The whole command's CPU time (s), with the engine of ``tree``, and the case's summary
    row."""
    env = single_core_env(tree)
    env["XDG_CACHE_HOME"] = str(folder)
    command = [sys.executable, "-m", "engine", str(study), "--fresh", "--no-progress-bar"]
    with open(folder / "log", "w") as log:
        process = subprocess.Popen(command, cwd=folder, env=env, stdout=log, stderr=log)
        _, status, usage = os.wait4(process.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"python -m engine failed: {(folder / 'log').read_text()[-2000:]}")
    with open(study.with_suffix(".csv")) as handle:
        (row,) = list(csv.DictReader(handle))
    return dict(cpu_s=usage.ru_utime + usage.ru_stime, row=row)


def measure(repeats: int, trees: dict[str, Path]) -> dict:
    """rows[(code, what)]: the figures of every round, ``what`` = solver or command, for each
    engine tree of ``trees`` (this one, and a baseline), alternating within a round."""
    rows = {(code, what): [] for code in trees for what in ("solver", "command")}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        study = folder / "cyclic_64.toml"
        study.write_text(study_text(study.with_suffix(".h5")))
        # A first, unrecorded command compiles the bytecode that every later process reuses,
        # as an installed package has it (bench_anchors.use_bytecode_cache).
        use_bytecode_cache(str(folder / "bytecode"))
        for tree in trees.values():
            run_command(study, folder, tree)
        for index in range(repeats):
            order = list(rows) if index % 2 == 0 else list(rows)[::-1]
            for code, what in order:
                tree = trees[code]
                if what == "solver":
                    figures = run_solver(study, tree)
                else:
                    figures = run_command(study, folder, tree)
                rows[(code, what)].append(figures)
                print(
                    f"round {index}  {code:8s} {what:8s} CPU {figures['cpu_s']:8.3f} s", flush=True
                )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument(
        "--baseline",
        type=Path,
        help="another source tree of the engine (e.g. git archive <rev> | tar -x -C /tmp/old), "
        "measured alike in every round",
    )
    parser.add_argument(
        "--update-docs",
        action="store_true",
        help="write this tree's figures into docs/explanation/performance.md",
    )
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child_solver(Path(args.child))))
        return
    start = os.getloadavg()[0]
    print(f"load average at the start: {start:.1f}", flush=True)
    trees = {"engine": REPO} | ({"baseline": args.baseline.resolve()} if args.baseline else {})
    rows = measure(args.repeats, trees)
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    figures = {}
    for code in trees:
        solver = min(r["cpu_s"] for r in rows[(code, "solver")])
        command = min(r["cpu_s"] for r in rows[(code, "command")])
        summary = rows[(code, "command")][-1]["row"]
        solved = rows[(code, "solver")]
        same = all(
            float(summary["max_wear_depth"]) == r["max_wear_depth"]
            and int(summary["matvecs"]) == r["matvecs"]
            for r in solved
        )
        figures[code] = (solver, command, same)
        print(
            f"{code}: cyclic 64² case (31 layers, records at 10³, 10⁴, 10⁵ cycles): solver "
            f"{solver:.3f} s, python -m engine {command:.3f} s (CPU, best of {args.repeats}); "
            f"the command adds {100 * (command / solver - 1):.1f} % to the solver's time; same "
            f"analysis (maximum wear depth, operator applications): {same}"
        )
    if args.update_docs:
        write_doc_block(*figures["engine"], repeats=args.repeats, load=start)


def write_doc_block(solver: float, command: float, same: bool, repeats: int, load: float):
    """The block ``bench-cli-overhead`` of the manual's performance page."""
    sys.path.insert(0, str(REPO))
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    note = (
        f"`python benchmarks/bench_cli_overhead.py --repeats {repeats} --update-docs`, one "
        f"core per process, solver and command alternating in each round; CPU times: the best "
        f"of the rounds; load average at the start {load:.1f}"
    )
    header = ("measured", "CPU, best (s)", "added to the solver")
    rows = [
        ("cyclic analysis alone (solver, in-process)", f"{solver:.3f}", "–"),
        ("whole `python -m engine`", f"{command:.3f}", f"{100 * (command / solver - 1):.1f} %"),
    ]
    text = measured_on(note) + "\n" + markdown_table(header, rows)
    text += f"\nSame analysis in both (maximum wear depth and operator applications): {same}.\n"
    document = REPO / "docs" / "explanation" / "performance.md"
    replace_block(document, "bench-cli-overhead", text)
    print(f"{document}: wrote the block bench-cli-overhead")


if __name__ == "__main__":
    main()
