"""The engine beside its anchors, ASPHER and Tamaas: solve, set-up and peak memory in one run.

The problem (one core, non-periodic): a rigid flat-ended cylindrical punch of radius
a0 = 1.8 mm pressed with P = 714 N onto the paper's half-space (E* of ``paper_material``),
over the square of half-width 1.05 a0 with n × n elements, tolerance 1e-8 in each code's own
measure. Each code runs in a process of its own, so that its peak resident memory
(``ru_maxrss``, imports included) is its own:

- ``engine``: ``ContactSolver`` of this tree (set-up: the solver with its influence operator
  and preconditioner; solve: ``solve_load``);
- ``aspher``: ``aspher.ContactSolver(backend="fft")`` (exact zero-padded FFT convolution,
  ``precond="fourier"``), the punch as gap 0 on the face and 1 mm outside;
- ``tamaas``: Tamaas's Polonsky–Keer–Rey on its non-periodic ``dcfft`` operator
  (``tamaas_reference.py``), slow: only for n ≤ ``--tamaas-max``.

``--frictional`` runs the frictional variant instead: the engine's static solve with
μ = 0.2 on the coupled material (K = 0.196: the tangential tractions come from the
coupling), and ASPHER's ``FrictionSolver`` (Coulomb μ = 0.2, uncoupled Cerruti kernels) with
the same normal load followed by a tangential force of 0.5 μP (partial slip): not the same
problem, the same class (normal and tangential unknowns on every element).

``--baseline DIR`` also runs the engine of another source tree (e.g. ``git archive <rev> |
tar -x -C /tmp/old``) in each round, for before/after figures.

Every engine process starts with an empty cache directory (``XDG_CACHE_HOME``, no
``ENGINE_FFTW_WISDOM``): each run is the first run on a fresh machine as far as the engine's
caches go. (The default planner effort keeps no FFTW wisdom, so later runs cost the same.)

Nothing is installed: a code that cannot be imported is skipped and said so. The anchors are
imported by ``--anchors-python`` (default: this interpreter), e.g. a scratch environment::

    python3 -m venv /tmp/anchors-venv
    /tmp/anchors-venv/bin/pip install tamaas==2.9.0 aspher   # ASPHER builds from source:
    # it needs Eigen 3.4 (Debian: apt-get install libeigen3-dev), else its build downloads it
    python benchmarks/bench_anchors.py --anchors-python /tmp/anchors-venv/bin/python

Printed per size and round (codes alternate within a round, so they share the load): set-up,
solve and whole (set-up + solve) wall time, the CPU time of the whole, peak RSS, the approach
error against Sneddon's δ = P/(2 a0 E*) (equal accuracy check), then the ratios engine / anchor:
of the best (smallest) CPU times over the rounds, which the load of a shared machine inflates
least (its interference only adds time), and the median over the rounds of the ratios. The
load average is printed at the start and at the end.

    python benchmarks/bench_anchors.py --sizes 128 256 512 1024 --repeats 5  # ~3 min here
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _single_core import single_core_env

REPO = Path(__file__).resolve().parents[1]
RADIUS, LOAD, HALF_WIDTH_FACTOR, TOL, FRICTION = 1.8, 714.0, 1.05, 1e-8, 0.2
CODES = ("engine", "aspher", "tamaas", "baseline")  # baseline: the engine of --baseline DIR


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _contact_modulus() -> float:
    """E* of the paper's pair (E_A = 200 GPa, E_B = 100 E_A, ν = 0.3), MPa; written out so
    the anchors' processes need not import the engine."""
    return 1.0 / ((1 - 0.3**2) / 200000.0 + (1 - 0.3**2) / (100 * 200000.0))


def _punch_gap(n: int):
    """Gap (mm) of the flat punch with zero approach: 0 on the face, 1 mm outside."""
    import numpy as np

    half_width = HALF_WIDTH_FACTOR * RADIUS
    x = (np.arange(n) + 0.5) * 2 * half_width / n - half_width
    radius = np.hypot(*np.meshgrid(x, x, indexing="ij"))
    return np.where(radius <= RADIUS, 0.0, 1.0)


def _timed(build, solve) -> dict:
    """Run ``build()`` then ``solve(built)``; wall and CPU times, the approach (mm)."""
    wall, cpu = time.perf_counter(), time.process_time()
    built = build()
    setup_wall, setup_cpu = time.perf_counter() - wall, time.process_time() - cpu
    wall, cpu = time.perf_counter(), time.process_time()
    approach, converged, iterations = solve(built)
    return dict(
        setup_s=setup_wall,
        solve_s=time.perf_counter() - wall,
        setup_cpu_s=setup_cpu,
        cpu_s=setup_cpu + time.process_time() - cpu,
        approach=approach,
        converged=bool(converged),
        iterations=int(iterations),
    )


def child_engine(n: int, frictional: bool) -> dict:
    from engine.geometry import FlatPunch
    from engine.grid import Grid
    from engine.material import paper_material
    from engine.solvers.contact import ContactSolver
    from engine.solvers.friction import FrictionLaw

    mu = FRICTION if frictional else 0.0

    def build():
        grid = Grid.square(n, HALF_WIDTH_FACTOR * RADIUS)
        law = FrictionLaw(mu, mu)
        solver = ContactSolver(grid, paper_material(), FlatPunch(RADIUS), law, tol=TOL)
        solver.preconditioner  # noqa: B018 (set-up, as in a study's operator cache)
        return solver

    def solve(solver):
        result = solver.solve_load(LOAD)
        report = getattr(result, "report", result)  # a --baseline tree from before SolveReport
        return result.approach, report.converged, report.iterations

    return _timed(build, solve)


def child_aspher(n: int, frictional: bool) -> dict:
    import aspher

    side = 2 * HALF_WIDTH_FACTOR * RADIUS
    mean_pressure = LOAD / side**2
    gap = _punch_gap(n).ravel()

    if not frictional:

        def build():
            return aspher.ContactSolver(
                grid_size=n, domain_size=side, E_star=_contact_modulus(), backend="fft"
            )

        def solve(solver):
            result = solver.solve(gap, p_nominal=mean_pressure, tol=TOL, precond="fourier")
            return result.approach, result.converged, result.iterations

        return _timed(build, solve)

    def build_frictional():
        law = aspher.CoulombFriction(FRICTION)
        solver = aspher.FrictionSolver(
            grid_size=n, domain_size=side, E_star=_contact_modulus(), nu=0.3, model=law
        )
        solver.set_gap(gap)
        return solver

    def solve_frictional(solver):
        normal = solver.step(p_bar=mean_pressure, tol_normal=TOL)
        tangential = solver.step(q_bar=(0.5 * FRICTION * mean_pressure, 0.0), dt=1.0)
        iterations = normal.normal_iters + tangential.tangential_iters
        return normal.approach, normal.converged and tangential.converged, iterations

    return _timed(build_frictional, solve_frictional)


def child_tamaas(n: int, frictional: bool) -> dict:
    if frictional:
        raise ImportError("no frictional Tamaas variant in this benchmark")
    sys.path.insert(0, str(Path(__file__).parent))
    import tamaas  # noqa: F401 (ImportError: skipped)
    from tamaas_reference import solve_flat_punch_tamaas

    cpu = time.process_time()
    modulus = _contact_modulus()
    result = solve_flat_punch_tamaas(n, radius=RADIUS, load=LOAD, contact_modulus=modulus, tol=TOL)
    return dict(
        setup_s=result["setup_time_s"],
        solve_s=result["solve_time_s"],
        setup_cpu_s=result["setup_time_s"],  # wall: Tamaas runs its set-up in C++, on one core
        cpu_s=time.process_time() - cpu,
        approach=result["approach"],
        converged=True,
        iterations=result["iterations"],
    )


def run_child(code: str, n: int, frictional: bool, python: str, tree: Path = REPO):
    """One measurement in a fresh process, with the engine of ``tree``; the result dict,
    or why the code was skipped."""
    child = "engine" if code == "baseline" else code
    command = [python, __file__, "--child", child, "--sizes", str(n)]
    command += ["--frictional"] if frictional else []
    env = single_core_env(tree)
    with tempfile.TemporaryDirectory() as cache:
        if child == "engine":  # a fresh machine: no cache of the engine's (module doc)
            env.pop("ENGINE_FFTW_WISDOM", None)
            env["XDG_CACHE_HOME"] = cache
        done = subprocess.run(command, env=env, capture_output=True, text=True, cwd=tree)
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode != 0 or not lines:
        return (done.stderr.strip().splitlines() or ["no output"])[-1]
    return json.loads(lines[-1])


def child_main(code: str, n: int, frictional: bool) -> None:
    base = _peak_mb()
    try:
        row = {"engine": child_engine, "aspher": child_aspher, "tamaas": child_tamaas}[code](
            n, frictional
        )
    except ImportError as error:
        raise SystemExit(f"skipped: {error}") from None
    sneddon = LOAD / (2 * RADIUS * _contact_modulus())
    row.update(peak_mb=_peak_mb(), import_mb=base, approach_error=row["approach"] / sneddon - 1)
    print(json.dumps(row))


def measure(sizes, repeats, frictional, anchors_python, tamaas_max, baseline=None) -> dict:
    """rows[(n, code)] = list of results over the rounds (codes alternate in each round)."""
    rows, skipped = {}, {} if baseline is not None else {"baseline": "no --baseline"}
    for round_ in range(repeats):
        for n in sizes:
            for code in CODES:
                if code in skipped or (code == "tamaas" and n > tamaas_max):
                    continue
                python = anchors_python if code in ("aspher", "tamaas") else sys.executable
                tree = baseline if code == "baseline" else REPO
                result = run_child(code, n, frictional, python, tree)
                if isinstance(result, str):
                    if code in ("engine", "baseline"):
                        raise SystemExit(f"engine failed at n = {n}: {result}")
                    skipped[code] = result
                    print(f"{code}: skipped ({result})", flush=True)
                    continue
                rows.setdefault((n, code), []).append(result)
                print(_line(n, code, round_, result), flush=True)
    return rows


def _line(n, code, round_, r) -> str:
    return (
        f"{n:>5} {code:>7} {round_:>5} {r['setup_s']:8.3f} {r['solve_s']:8.3f} "
        f"{r['setup_s'] + r['solve_s']:8.3f} {r['setup_cpu_s']:9.3f} {r['cpu_s']:8.3f} "
        f"{r['peak_mb']:8.0f} "
        f"{r['iterations']:6d} {r['approach_error']:11.3e} {str(r['converged']):>9}"
    )


def print_ratios(rows: dict, sizes) -> None:
    """Engine / anchor per quantity (< 1: the engine needs less): the median over the rounds
    of the ratios, and the ratio of the best CPU times (the least inflated by the load)."""
    print("\nengine / anchor, median over rounds (< 1: the engine needs less)")
    print(
        f"{'n':>5} {'anchor':>7} {'set-up':>10} {'solve':>10} {'whole':>10} {'set-up CPU':>10} "
        f"{'CPU':>10} {'peak RSS':>10} {'best CPU':>10}"
    )
    keys = ("setup_s", "solve_s", "whole_s", "setup_cpu_s", "cpu_s", "peak_mb")
    for n in sizes:
        engine = rows.get((n, "engine"), [])
        for anchor in CODES[1:]:
            others = rows.get((n, anchor), [])
            if not engine or not others:
                continue
            ratios = [_ratio(engine, others, key) for key in keys]
            ratios.append(_best_ratio(engine, others, "cpu_s"))
            print(f"{n:>5} {anchor:>7} " + " ".join(f"{value:10.3f}" for value in ratios))


def doc_rows(rows: dict, sizes) -> list[tuple]:
    """Per size and anchor: the best (smallest) set-up and whole CPU times over the rounds
    for the engine and the anchor, their ratio with the median of the ratios over the rounds
    in brackets, the median peak RSS and its ratio, and the approach errors."""
    table = []
    for n in sizes:
        engine = rows.get((n, "engine"), [])
        for anchor in ("aspher", "tamaas"):
            others = rows.get((n, anchor), [])
            if not engine or not others:
                continue

            e, o = _bests(engine), _bests(others)
            best, median = _best_ratio(engine, others, "cpu_s"), _ratio(engine, others, "cpu_s")
            table.append((
                f"{n}²", anchor, f"{e['setup_cpu_s']:.4f} / {e['cpu_s']:.4f}",
                f"{o['setup_cpu_s']:.4f} / {o['cpu_s']:.4f}",
                f"{best:.2f} ({median:.2f})",
                f"{e['peak_mb']:.0f} / {o['peak_mb']:.0f}",
                f"{_ratio(engine, others, 'peak_mb'):.2f}",
                f"{e['approach_error']:.1e} / {o['approach_error']:.1e}",
            ))  # fmt: skip
    return table


def _bests(runs: list[dict]) -> dict[str, float]:
    """The smallest CPU times over the rounds; the medians of peak RSS and approach error."""
    best = {key: min(run[key] for run in runs) for key in ("setup_cpu_s", "cpu_s")}
    typical = {
        key: statistics.median(run[key] for run in runs) for key in ("peak_mb", "approach_error")
    }
    return best | typical


def _ratio(engine: list[dict], others: list[dict], key: str) -> float:
    """Median over the rounds of engine / anchor (the codes alternate within a round)."""
    pairs = zip(engine, others, strict=False)
    return statistics.median(_value(e, key) / _value(o, key) for e, o in pairs)


def _best_ratio(engine: list[dict], others: list[dict], key: str) -> float:
    """Best (smallest) engine value over the rounds / best anchor value."""
    return min(_value(e, key) for e in engine) / min(_value(o, key) for o in others)


DOC_HEADER = ("n", "anchor", "engine: set-up CPU / whole CPU, best (s)",
              "anchor: set-up CPU / whole CPU, best (s)",
              "ratio of whole CPU, best (median)", "peak RSS engine / anchor (MB)",
              "ratio of peak RSS", "approach error engine / anchor")  # fmt: skip


def write_doc_table(rows: dict, args) -> None:
    """The table of the manual's memory and set-up page (block ``bench-anchors`` or
    ``bench-anchors-frictional``), with the date, the machine and its load."""
    sys.path.insert(0, str(REPO))
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    block = "bench-anchors-frictional" if args.frictional else "bench-anchors"
    note = "`python benchmarks/bench_anchors.py --sizes " + " ".join(map(str, args.sizes))
    note += f" --repeats {args.repeats}" + " --frictional" * args.frictional
    note += " --update-docs`, one core per process, codes alternating in each round; CPU"
    note += " times: the best of the rounds; peak RSS: median"
    document = REPO / "docs" / "explanation" / "memory-and-setup.md"
    table = markdown_table(DOC_HEADER, doc_rows(rows, args.sizes))
    replace_block(document, block, measured_on(note) + "\n" + table)
    print(f"{document}: wrote the block {block}")


def _value(row: dict, key: str) -> float:
    return row["setup_s"] + row["solve_s"] if key == "whole_s" else row[key]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[128, 256, 512, 1024])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--frictional", action="store_true")
    parser.add_argument("--anchors-python", default=sys.executable)
    parser.add_argument("--tamaas-max", type=int, default=256)
    parser.add_argument(
        "--baseline", type=Path, help="another source tree of the engine, run alongside"
    )
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/memory-and-setup.md",
    )  # fmt: skip
    parser.add_argument("--child", choices=CODES, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child_main(args.child, args.sizes[0], args.frictional)
        return
    kind = "frictional (engine: mu = 0.2, K = 0.196)" if args.frictional else "frictionless"
    print(f"flat punch, {kind}, tol {TOL:g}, one core per process; sizes {args.sizes}")
    print(f"load average at the start: {os.getloadavg()[0]:.1f}")
    print(
        f"{'n':>5} {'code':>7} {'round':>5} {'set-up s':>8} {'solve s':>8} {'whole s':>8} "
        f"{'set-up CPU':>9} {'CPU s':>8} {'peak MB':>8} {'iter':>6} {'approach err':>11} "
        f"{'converged':>9}"
    )
    rows = measure(
        args.sizes,
        args.repeats,
        args.frictional,
        args.anchors_python,
        args.tamaas_max,
        args.baseline,
    )
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    print_ratios(rows, args.sizes)
    if args.update_docs:
        write_doc_table(rows, args)


if __name__ == "__main__":
    main()
