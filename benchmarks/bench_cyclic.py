"""Cyclic-wear benchmark: today's method and the new one side by side.

Section 7.2 settings: flat punch a0 = 1.8 mm, P = 750 N, i = 1.33e-7 1/MPa, μ = 0.1, paper
materials, 10 increments per half cycle, wear per jump <= 0.004 of the elastic approach,
tol 1e-6, 10⁵ cycles. Methods (``CyclicSettings.warm_start``):

- today: ``previous_increment``: every increment starts from the previous increment;
- new:   ``previous_cycle``: every increment starts from the same increment of the previous
  simulated cycles (linearly extrapolated in N), with the first inner tolerance set from the
  start's own residual.

Each (size, method) runs in a fresh process (so the peak RSS is its own), one after the
other, alternating the order per size, on one core (OMP/OpenBLAS threads = 1, FFTW threads =
1). Printed per run: set-up time (operator, spectra, plans, preconditioner), solve time,
simulated cycles, operator applications per increment, max wear depth, wear volume, the
von Mises peak of the final x–z plane (all layers and below the surface layer) and the peak
RSS; then the ratios today/new. The solve's CPU time (``time.process_time``) is printed
beside its wall time: on a shared machine it is the steadier of the two. Targets: 64² ≤ 10 s
and ≥ 2.9× today in the same run, 128² ≤ 45 s, results within 1 %.

``--static-cases K`` also runs a study of K static frictional 128² cases through the case
runner, with the per-rank operator cache and without it (today), and prints set-up vs total.
``--static-512`` reports the peak RSS of one 512² static frictional solve; ``--cli-rss``
that of one 128² cyclic case run as users run it (``python -m engine``, 3000 cycles, the
σ_VM probe of every simulated cycle included), for the baseline and this tree alternating.

Run:  OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_cyclic.py [--sizes 64 128]
      [--static-cases 20] [--static-512] [--cli-rss [LAYERS ...]]
Takes ~1 minute for 64² and ~4 minutes more for 128² on an idle core here.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _single_core import single_core_env

RADIUS, LOAD, WEAR = 1.8, 750.0, 1.33e-7
METHODS = {"base": None, "today": "previous_increment", "new": "previous_cycle"}
REPO = Path(__file__).resolve().parents[1]


def _peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run_cyclic(n: int, mu: float, cycles: int, method: str) -> dict:
    """One cyclic case in this process; returns the figures of the table."""
    from engine.geometry import FlatPunch
    from engine.grid import Grid
    from engine.material import paper_material
    from engine.solvers.contact import ContactSolver
    from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings
    from engine.solvers.friction import FrictionLaw, WearLaw
    from engine.solvers.subsurface import SubsurfaceStress, depth_layers

    grid = Grid.square(n, 1.05 * RADIUS)
    start = time.perf_counter()
    solver = ContactSolver(grid, paper_material(), FlatPunch(RADIUS), FrictionLaw(mu, mu), tol=1e-6)
    solver.preconditioner  # noqa: B018 (set-up: built before the clock of the solve starts)
    solver.operator.symbol_bound()
    if hasattr(solver, "_symbol"):
        solver._symbol = solver.operator.symbol_bound()
    setup = time.perf_counter() - start
    options = {} if METHODS[method] is None else {"warm_start": METHODS[method]}
    settings = CyclicSettings(
        LOAD, 10, cycles, record=tuple(c for c in (1000, 10000, 100000) if c <= cycles), **options
    )
    start, cpu_start = time.perf_counter(), time.process_time()
    result = CyclicAnalysis(solver, WearLaw(WEAR, WEAR), settings).run()
    solve, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    depths = depth_layers(1.5 * RADIUS, 16)
    final = result.final
    plane = SubsurfaceStress(grid, paper_material().nu_A, depths).plane(
        final.pressure, final.traction_x, final.traction_y
    )
    return dict(
        n=n,
        method=method,
        setup=setup,
        solve=solve,
        cpu=cpu,
        simulated=len(result.history["cycle"]),
        per_increment=result.matvecs / result.load_steps,
        converged=bool(result.converged),
        depth=float(result.history["max_wear_depth"][-1]),
        volume=float(result.history["wear_volume"][-1]),
        vm=float(plane.peak().value),
        vm_sub=float(plane.peak(min_depth=float(depths[1])).value),
        rss=_peak_rss_mb(),
    )


def run_static_512() -> dict:
    """Peak RSS (MB) and time of one 512² static frictional solve (μ = 0.3, 3 increments)."""
    from engine.geometry import FlatPunch
    from engine.grid import Grid
    from engine.material import paper_material
    from engine.solvers.contact import ContactSolver
    from engine.solvers.friction import FrictionLaw
    from engine.solvers.static import static_analysis

    grid = Grid.square(512, 1.05 * RADIUS)
    start = time.perf_counter()
    solver = ContactSolver(grid, paper_material(), FlatPunch(RADIUS), FrictionLaw(0.3, 0.3))
    result = static_analysis(solver, LOAD, 3)
    return dict(time=time.perf_counter() - start, rss=_peak_rss_mb(), converged=result.converged)


def static_study(output: Path, n: int, mu: list[float]) -> str:
    """Static cases (P = 750 N, one increment) on an n x n mesh, 16 layers to 1.5 a0."""
    from engine.study.examples import study_toml

    return study_toml(
        "bench_static",
        output,
        mesh={"n": n},
        loading={"kind": "static", "steps": 1},
        subsurface={"depth": 1.5, "layers": 16},
        sweep={"mu1": mu},
    )


def run_static_cases(n: int, count: int, shared: bool) -> dict:
    """``count`` static frictional cases (μ from 0.05 to 0.5) through the case runner, with
    the per-rank operator cache (``shared``) or a fresh build per case (today)."""
    from engine.study.case import CaseRunner
    from engine.study.config import parse_study
    from engine.study.operators import OperatorCache
    from engine.study.plan import make_plan

    mus = [round(0.05 + 0.45 * k / max(count - 1, 1), 4) for k in range(count)]
    with tempfile.TemporaryDirectory() as folder:
        text = static_study(Path(folder) / "s.h5", n, mus)
        config = parse_study(text, source="bench")
        runner = CaseRunner(config)
        setup = 0.0
        start = time.perf_counter()
        for case in make_plan(config):
            if not shared:
                runner.operators = OperatorCache()
            outcome = runner(case)
            assert outcome.status == "completed", outcome.message
            setup += runner.operators.setup_s if not shared else 0.0
        total = time.perf_counter() - start
        if shared:
            setup = runner.operators.setup_s
    return dict(total=total, setup=setup, count=count, rss=_peak_rss_mb())


def cli_case(code: Path, n: int, cycles: int, layers: int) -> dict:
    """Peak RSS (MB) and wall time (s) of one Section 7.2 case (μ = 0.1, 10 steps) run as
    users run it, ``python -m engine`` with the engine of ``code``: the case runner, the
    σ_VM probe of every simulated cycle on the x–z plane (``layers`` layers to 1.5 a0), the
    records and the writer. The peak of that process alone (``os.wait4``)."""
    from engine.study.examples import study_toml

    loading = {"kind": "cyclic", "load": LOAD, "steps": 10, "cycles": cycles, "record": [cycles]}
    with tempfile.TemporaryDirectory() as folder:
        study = Path(folder) / "rss.toml"
        study.write_text(
            study_toml(
                "bench_rss",
                Path(folder) / "rss.h5",
                mesh={"n": n},
                loading=loading,
                subsurface={"depth": 1.5, "layers": layers},
                sweep={"mu1": [0.1], "wear1": [WEAR]},
            )
        )
        env = single_core_env(code)
        with open(Path(folder) / "log", "w") as log:
            start = time.perf_counter()
            process = subprocess.Popen(
                [sys.executable, "-m", "engine", str(study)],
                cwd=folder,  # not this tree: ``-m`` puts the working directory first
                env=env,
                stdout=log,
                stderr=log,
            )
            _, status, usage = os.wait4(process.pid, 0)
            wall = time.perf_counter() - start
        if status != 0:
            raise RuntimeError((Path(folder) / "log").read_text())
    return dict(rss=usage.ru_maxrss / 1024.0, wall=wall)


def compare_cli_cases(baseline: Path | None, n: int, cycles: int, layers, repeat: int) -> None:
    """``cli_case`` for the baseline and this tree, alternating, ``repeat`` times each."""
    codes = {"new": REPO} if baseline is None else {"base": baseline, "new": REPO}
    for count in layers:
        peaks = {name: [] for name in codes}
        for index in range(repeat):
            for name in codes if index % 2 == 0 else list(codes)[::-1]:
                peaks[name].append(cli_case(codes[name], n, cycles, count)["rss"])
        shown = ", ".join(f"{name} {min(v):.0f}–{max(v):.0f} MB" for name, v in peaks.items())
        print(
            f"{n}² cyclic case, {cycles} cycles, {count} layers, python -m engine: peak RSS "
            f"{shown}",
            flush=True,
        )


def in_subprocess(*arguments: str, code: Path = REPO) -> dict:
    """Run this file's ``child`` with the engine of ``code`` (this tree, or the baseline)."""
    env = single_core_env(code)
    output = subprocess.run(
        [sys.executable, __file__, "--child", *arguments],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return json.loads(output.strip().splitlines()[-1])


def _relative(a: float, b: float) -> str:
    return f"{abs(a / b - 1) * 100:.3f} %"


def compare_cyclic(sizes, mu, cycles, baseline: Path | None, methods) -> dict[int, dict]:
    """Run each size with each method; returns {n: {method: row}}."""
    print(
        f"{'n':>4} {'method':>6} {'setup s':>7} {'solve s':>8} {'cpu s':>7} {'sim cyc':>7} "
        f"{'matvec/inc':>10} {'max wear um':>11} {'volume mm3':>11} {'vm MPa':>8} "
        f"{'vm_sub MPa':>10} {'RSS MB':>7} converged",
        flush=True,
    )
    measured = {}
    for index, n in enumerate(sizes):
        order = [m for m in ("base", "today", "new") if m in methods]
        order = [m for m in order if m != "base" or baseline is not None]
        order = order if index % 2 == 0 else order[::-1]
        rows = {}
        for method in order:
            code = baseline if method == "base" else REPO
            row = in_subprocess("cyclic", str(n), str(mu), str(cycles), method, code=code)
            rows[method] = row
            print(
                f"{n:>4} {method:>6} {row['setup']:7.2f} {row['solve']:8.2f} {row['cpu']:7.2f} "
                f"{row['simulated']:>7} {row['per_increment']:10.1f} {row['depth'] * 1e3:11.5f} "
                f"{row['volume']:11.5e} {row['vm']:8.2f} {row['vm_sub']:10.2f} "
                f"{row['rss']:7.0f} {row['converged']}",
                flush=True,
            )
        for name in [m for m in ("base", "today") if m in rows and "new" in rows]:
            _print_ratio(n, name, rows[name], rows["new"])
        measured[n] = rows
    return measured


DOC = REPO / "docs" / "explanation" / "performance.md"


def write_doc_table(measured: dict[int, dict], mu: float, cycles: int) -> None:
    """The cyclic-wear table of the manual's performance page (block ``bench-cyclic``)."""
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    rows = [
        (n, row["simulated"], f"{row['cpu']:.1f}", f"{row['solve']:.1f}",
         f"{row['per_increment']:.1f}", f"{row['depth'] * 1e3:.4f}", f"{row['volume']:.3e}",
         row["converged"])
        for n, rows_of_n in measured.items() if (row := rows_of_n.get("new"))
    ]  # fmt: skip
    header = ("n", "simulated cycles", "CPU (s)", "solve wall (s)", "operator applications "
              "per increment", "max wear depth (µm)", "wear volume (mm³)", "converged")  # fmt: skip
    note = f"`python benchmarks/bench_cyclic.py --methods new --update-docs`, μ = {mu:g}, "
    note += f"{cycles:,} cycles, one core per case"
    replace_block(DOC, "bench-cyclic", measured_on(note) + "\n" + markdown_table(header, rows))
    print(f"{DOC.relative_to(REPO)}: wrote the block bench-cyclic", flush=True)


def _print_ratio(n: int, name: str, today: dict, new: dict) -> None:
    """Speed-up of ``new`` over ``today`` and the relative differences of the results."""
    print(
        f"{n:>4} {name}/new: solve cpu {today['cpu'] / new['cpu']:.2f}x, solve time "
        f"{today['solve'] / new['solve']:.2f}x, total "
        f"{(today['solve'] + today['setup']) / (new['solve'] + new['setup']):.2f}x, "
        f"operator applications {today['per_increment'] / new['per_increment']:.2f}x; "
        f"differences: max wear {_relative(new['depth'], today['depth'])}, volume "
        f"{_relative(new['volume'], today['volume'])}, vm "
        f"{_relative(new['vm'], today['vm'])}, vm_sub "
        f"{_relative(new['vm_sub'], today['vm_sub'])}; RSS new - {name} "
        f"{new['rss'] - today['rss']:+.0f} MB",
        flush=True,
    )


def child(arguments) -> None:
    kind = arguments[0]
    if kind == "cyclic":
        n, mu, cycles, method = arguments[1:]
        row = run_cyclic(int(n), float(mu), int(cycles), method)
    elif kind == "static":
        n, count, shared = arguments[1:]
        row = run_static_cases(int(n), int(count), shared == "shared")
    else:
        row = run_static_512()
    print(json.dumps(row))


def _export(revision: str, folder: Path) -> Path:
    """The ``engine`` package of a git revision, extracted into ``folder``."""
    archive = subprocess.run(
        ["git", "-C", str(REPO), "archive", revision, "engine"], capture_output=True, check=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
    return folder


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child(sys.argv[2:])
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[64, 128])
    parser.add_argument("--mu", type=float, default=0.1)
    parser.add_argument("--cycles", type=int, default=100000)
    parser.add_argument(
        "--methods", nargs="+", default=["base", "today", "new"], choices=sorted(METHODS)
    )
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table of this tree's runs into docs/explanation/performance.md",
    )  # fmt: skip
    parser.add_argument("--static-cases", type=int, default=0, metavar="K")
    parser.add_argument("--static-n", type=int, default=128)
    parser.add_argument("--static-512", action="store_true")
    parser.add_argument(
        "--cli-rss",
        type=int,
        nargs="*",
        metavar="LAYERS",
        help="peak RSS of one 128² cyclic case (3000 cycles) through python -m engine, with "
        "these numbers of subsurface layers (default 16 31), baseline and new alternating",
    )
    parser.add_argument(
        "--baseline-commit",
        metavar="REV",
        help="also run the engine of this git revision (e.g. an earlier commit) as "
        "'base', from a temporary export (git archive)",
    )
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}, cpus: {os.cpu_count()}", flush=True)
    with tempfile.TemporaryDirectory() as folder:
        baseline = _export(args.baseline_commit, Path(folder)) if args.baseline_commit else None
        if args.sizes:
            measured = compare_cyclic(args.sizes, args.mu, args.cycles, baseline, args.methods)
            if args.update_docs:
                write_doc_table(measured, args.mu, args.cycles)
        if args.static_cases:
            for mode in ("today", "shared"):
                row = in_subprocess("static", str(args.static_n), str(args.static_cases), mode)
                print(
                    f"{row['count']} static {args.static_n}² cases ({mode:>6}): total "
                    f"{row['total']:.2f} s, set-up {row['setup']:.2f} s "
                    f"({100 * row['setup'] / row['total']:.1f} %), RSS {row['rss']:.0f} MB",
                    flush=True,
                )
        if args.cli_rss is not None:
            compare_cli_cases(baseline, 128, 3000, args.cli_rss or [16, 31], repeat=2)
        if args.static_512:
            codes = {"new": REPO} if baseline is None else {"base": baseline, "new": REPO}
            for name, code in codes.items():
                row = in_subprocess("static512", code=code)
                print(
                    f"512² static frictional solve (3 increments, {name}): {row['time']:.1f} s, "
                    f"peak RSS {row['rss']:.0f} MB, converged {row['converged']}",
                    flush=True,
                )
    print(f"load average after: {os.getloadavg()}", flush=True)


if __name__ == "__main__":
    main()
