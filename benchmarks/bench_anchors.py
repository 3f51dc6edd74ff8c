"""The engine beside its anchors, ASPHER and Tamaas: the solver, the whole script and the whole
command, each with its time and peak memory, in one run.

The problem (one core, non-periodic): a rigid flat-ended cylindrical punch of radius
a0 = 1.8 mm pressed with P = 714 N onto the paper's half-space (E* of ``paper_material``),
over the square of half-width 1.05 a0 with n × n elements, tolerance 1e-8 in each code's own
measure. Three things are measured per size, each in a process of its own:

- **solver**: the set-up and solve inside the process (``time.process_time``), and the
  memory they add to the process after its imports (peak RSS − RSS after the imports):
  ``engine``: ``ContactSolver`` of this tree (set-up: the solver with its influence operator
  and preconditioner; solve: ``solve_load``); ``aspher``: ``aspher.ContactSolver(backend=
  "fft")`` (exact zero-padded FFT convolution, ``precond="fourier"``), the punch as gap 0 on
  the face and 1 mm outside; ``tamaas``: Tamaas's Polonsky–Keer–Rey on its non-periodic
  ``dcfft`` operator (``tamaas_reference.py``), slow: only for n ≤ ``--tamaas-max``;
- **script**: the same process as a whole, as a user's script of each code runs it: the
  interpreter's start, the imports, set-up and solve; CPU time (user + system) and peak RSS
  of the ended process (``os.wait4``), wall time around it;
- **CLI** (the engine only): ``python -m engine STUDY.toml`` on a one-case static study of
  the same problem (μ = 0 on the paper's coupled material, one load step, the default 16
  layers of the x–z stress plane, the results file, its summary CSV and the read-back
  check), measured like the script and compared with the anchor's whole script;
- **import floor**: a process that only imports what every ``python -m engine`` must before it
  computes anything, NumPy, h5py and pyFFTW's core (``FLOOR_IMPORTS``: pyFFTW as the engine
  loads it, without its SciPy interfaces), measured like the script and compared with the
  anchor's whole script at each size: the part of the CLI's ratios that the mandatory
  dependencies take on their own;
- **imports of the command**: a process that imports every module ``python -m engine``
  imports in a run of the smallest size (the top-level entries of its ``-X importtime``
  list, in their order) and computes nothing, measured like the script: the CLI's figures
  less these are what the run itself costs (parsing, set-up, solve, stress plane, file,
  summary and read-back).

``--frictional`` runs the frictional problem instead, the same one in both codes: the normal
load P, then a tangential force Q = 0.5 μP along x (no slip: the flat punch's Mindlin
traction has the pressure's shape, q/p = Q/P = 0.1 < μ, and every element sticks in the
engine's solution at 256² and 512²), Coulomb μ = 0.2, on an
uncoupled pair (K = 0: ASPHER's ``FrictionSolver`` has no coupling; the engine's pair is
two equal bodies of the same E* and ν = 0.3), tolerance 1e-8 on the normal problem and
1e-5 on the tangential force (ASPHER's ``tol_tangential``; the engine's force control,
``TangentialDriver.force`` with ``restart="secant"``, to 1e-5 Q, each of its increment
solves to 1e-8; ``iter``: the normal solve's iterations plus those of every increment solve
of the force control, ASPHER's normal plus tangential iterations). ``last``: the same with
``restart="last"``, each later evaluation started from the last one's solution, which is
what the fretting analysis does (bit-identical results of the bundled studies). Beside it,
``coupled``: the engine's static solve with μ = 0.2 on the paper's coupled pair (K = 0.196,
the tangential tractions from the coupling, no tangential force), the coupled solve's cost.

``--baseline DIR`` also runs the engine of another source tree (e.g. ``git archive <rev> |
tar -x -C /tmp/old``) in each round, for before/after figures (solver and script only).

Every engine process starts with an empty cache directory (``XDG_CACHE_HOME``, no
``ENGINE_FFTW_WISDOM``): each run is the first run on a fresh machine as far as the engine's
caches go. (The default planner effort keeps no FFTW wisdom, so later runs cost the same.)

Nothing is installed: a code that cannot be imported is skipped and said so. The anchors are
imported by ``--anchors-python`` (default: this interpreter), e.g. a scratch environment::

    python3 -m venv /tmp/anchors-venv
    /tmp/anchors-venv/bin/pip install tamaas==2.9.0 aspher   # ASPHER builds from source:
    # it needs Eigen 3.4 (Debian: apt-get install libeigen3-dev), else its build downloads it
    python benchmarks/bench_anchors.py --anchors-python /tmp/anchors-venv/bin/python

Printed per size and round (codes alternate within a round, so they share the load): the
solver's set-up, solve and CPU times, its memory and the process's peak RSS, the script's
wall and CPU times, the approach error against Sneddon's δ = P/(2 a0 E*) (equal accuracy
check); then per size the engine / anchor ratios of the solver, the script and the CLI: of
the best (smallest) CPU times over the rounds, which the load of a shared machine inflates
least (its interference only adds time), and of the median peak memory; then the CLI's
imports (``python -X importtime``: their total and the largest packages, and whether pandas,
SciPy or matplotlib were imported). Every child reuses the bytecode its modules compiled to
in a first, unrecorded round (``use_bytecode_cache``), as an installed package does. The
load average is printed at the start and at the end.

    python benchmarks/bench_anchors.py --sizes 128 256 512 1024 --repeats 5 \
        --anchors-python /tmp/anchors-venv/bin/python --update-docs    # ~5 min here
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
TANGENTIAL_FRACTION, TANGENTIAL_TOL, NU = 0.5, 1e-5, 0.3  # Q = 0.5 μP; ASPHER's default
CODES = ("engine", "last", "coupled", "aspher", "tamaas", "baseline")  # baseline: --baseline DIR
ANCHORS = ("aspher", "tamaas")
HEAVY_IMPORTS = ("pandas", "scipy", "matplotlib")
#: What every ``python -m engine`` imports before it computes anything (the import floor):
#: NumPy, h5py and pyFFTW's core (``engine.kernels.pyfftw_import``, which the light package
#: ``engine`` holds: its ``__init__`` imports only the version and the stop-signal handlers).
FLOOR_IMPORTS = "import numpy, h5py\nimport engine.kernels.pyfftw_import"


def _rss_mb() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return 0.0


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


def _uncoupled_material():
    """Two equal bodies (K = 0) with the paper's E* and ν = 0.3: E = 2 E* (1 − ν²)."""
    from engine.material import MaterialPair

    modulus = 2.0 * _contact_modulus() * (1.0 - NU**2)
    return MaterialPair(E_A=modulus, nu_A=NU, E_B=modulus, nu_B=NU)


def child_engine(n: int, frictional: bool, coupled: bool = False, restart="secant") -> dict:
    from engine.geometry import FlatPunch
    from engine.grid import Grid
    from engine.material import paper_material
    from engine.solvers.contact import ContactSolver
    from engine.solvers.friction import FrictionLaw

    mu = FRICTION if frictional else 0.0
    material = _uncoupled_material() if frictional and not coupled else paper_material()

    def build():
        grid = Grid.square(n, HALF_WIDTH_FACTOR * RADIUS)
        law = FrictionLaw(mu, mu)
        solver = ContactSolver(grid, material, FlatPunch(RADIUS), law, tol=TOL)
        solver.preconditioner  # noqa: B018 (set-up, as in a study's operator cache)
        return solver

    def solve(solver):
        result = solver.solve_load(LOAD)
        report = getattr(result, "report", result)  # a --baseline tree from before SolveReport
        if not frictional or coupled:
            return result.approach, report.converged, report.iterations
        return _tangential_force(solver, result, report, restart)

    return _timed(build, solve)


def _tangential_force(solver, normal, report, restart="secant"):
    """The tangential force Q = 0.5 μP along x after the normal load, by the engine's force
    control (``TangentialDriver.force``, to 1e-5 Q, its later evaluations started on the
    secant of the known solutions); the guess of the tangential stiffness is the normal
    secant stiffness times 2(1 − ν)/(2 − ν), as the fretting analysis takes it. Iterations:
    the normal solve's plus those of every increment solve of the force control."""
    import numpy as np

    from engine.solvers.fretting import TangentialDriver

    target = TANGENTIAL_FRACTION * FRICTION * LOAD
    try:
        driver = TangentialDriver(solver, LOAD, (1.0, 0.0), TANGENTIAL_TOL, restart=restart)
    except TypeError:  # a --baseline tree from before the secant restart
        driver = TangentialDriver(solver, LOAD, (1.0, 0.0), TANGENTIAL_TOL)
    stiffness = LOAD / normal.approach * 2.0 * (1.0 - NU) / (2.0 - NU)
    step = driver.force(normal.state, np.zeros(2), target, target, target / stiffness, stiffness)
    # such a tree does not count its evaluations' iterations: the last one's per evaluation
    last = step.result.report.iterations * step.evaluations
    iterations = report.iterations + getattr(step, "iterations", last)
    return normal.approach, report.converged and step.converged, iterations


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
            grid_size=n, domain_size=side, E_star=_contact_modulus(), nu=NU, model=law
        )
        solver.set_gap(gap)
        return solver

    def solve_frictional(solver):
        normal = solver.step(p_bar=mean_pressure, tol_normal=TOL)
        force = (TANGENTIAL_FRACTION * FRICTION * mean_pressure, 0.0)
        tangential = solver.step(q_bar=force, dt=1.0, tol_normal=TOL, tol_tangential=TANGENTIAL_TOL)
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


def _run_process(command: list[str], env: dict, cwd: Path) -> tuple[int, str, str, dict]:
    """Run ``command`` to its end; (exit code, stdout, stderr, whole-process figures: wall
    and CPU (user + system) time in s, peak RSS in MB, from ``os.wait4``)."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        wall = time.perf_counter()
        process = subprocess.Popen(command, env=env, cwd=cwd, stdout=out, stderr=err, text=True)
        _, status, usage = os.wait4(process.pid, 0)
        wall = time.perf_counter() - wall
        process.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        whole = dict(
            wall_s=wall, cpu_s=usage.ru_utime + usage.ru_stime, peak_mb=usage.ru_maxrss / 1024.0
        )
        return process.returncode, out.read(), err.read(), whole


def _engine_env(env: dict, cache: str) -> dict:
    """A fresh machine for the engine's caches (module doc)."""
    env.pop("ENGINE_FFTW_WISDOM", None)
    env["XDG_CACHE_HOME"] = cache
    return env


def run_child(code: str, n: int, frictional: bool, python: str, tree: Path = REPO):
    """One solver measurement in a fresh process (the script), with the engine of ``tree``;
    the result dict (``script``: the process's whole figures), or why it was skipped."""
    child = "engine" if code == "baseline" else code
    command = [python, __file__, "--child", child, "--sizes", str(n)]
    command += ["--frictional"] if frictional else []
    with tempfile.TemporaryDirectory() as cache:
        env = single_core_env(tree)
        if child in ("engine", "last", "coupled"):
            env = _engine_env(env, cache)
        code_, stdout, stderr, whole = _run_process(command, env, tree)
    lines = [line for line in stdout.splitlines() if line.startswith("{")]
    if code_ != 0 or not lines:
        return (stderr.strip().splitlines() or ["no output"])[-1]
    return json.loads(lines[-1]) | {"script": whole}


def study_text(n: int, output: Path, mu: float = 0.0, name: str = "anchor") -> str:
    """The one-case static study of the CLI measurement (module doc); ``mu``: its friction
    coefficient (``bench_memory.py`` takes the frictional one), ``name``: its study name."""
    return f"""[study]
name = "{name}_{n}"
output = "{output}"

[material]
E_A = 200e3
nu_A = 0.3
E_B = 200e5
nu_B = 0.3

[punch]
radius = {RADIUS}

[mesh]
n = {n}
half_width = {HALF_WIDTH_FACTOR * RADIUS!r}

[loading]
kind = "static"
load = {LOAD}
steps = 1

[solver]
tol = {TOL}

[sweep]
mu1 = [{mu!r}]
"""


def _cli_command(study: Path, importtime: bool = False) -> list[str]:
    flags = ["-X", "importtime"] if importtime else []
    return [sys.executable, *flags, "-m", "engine", str(study), "--fresh", "--no-progress-bar"]


def run_cli(n: int, importtime: bool = False) -> dict:
    """``python -m engine`` on the one-case study at n²: the whole process's figures (and,
    with ``importtime``, its stderr, which then holds the import times)."""
    with tempfile.TemporaryDirectory() as folder:
        study = Path(folder) / "study.toml"
        study.write_text(study_text(n, Path(folder) / "anchor.h5"))
        env = _engine_env(single_core_env(REPO), folder)
        code, stdout, stderr, whole = _run_process(_cli_command(study, importtime), env, REPO)
    if code != 0:
        raise SystemExit(f"python -m engine failed at n = {n} (exit {code}): {stderr[-2000:]}")
    return whole | ({"importtime": stderr} if importtime else {})


def run_floor() -> dict:
    """A process that imports ``FLOOR_IMPORTS`` and nothing else: its whole figures."""
    env = single_core_env(REPO)
    code, _, stderr, whole = _run_process([sys.executable, "-c", FLOOR_IMPORTS], env, REPO)
    if code != 0:
        raise SystemExit(f"the import floor failed (exit {code}): {stderr[-2000:]}")
    return whole


def imported_modules(stderr: str) -> list[str]:
    """From ``-X importtime`` output: the modules imported at the top level, in their order
    (importing them imports the rest), without ``__main__`` modules (which would run)."""
    modules = []
    for line in stderr.splitlines():
        if not line.startswith("import time:") or "|" not in line or "self [us]" in line:
            continue
        name = line.split("|")[2]
        if not name.startswith("  ") and not name.strip().endswith("__main__"):
            modules.append(name.strip())
    return modules


def run_imports(modules: list[str]) -> dict:
    """A process that imports ``modules`` and computes nothing: its whole figures."""
    env = single_core_env(REPO)
    code_ = "\n".join(f"import {module}" for module in modules)
    code, _, stderr, whole = _run_process([sys.executable, "-c", code_], env, REPO)
    if code != 0:
        raise SystemExit(f"the command's imports failed (exit {code}): {stderr[-2000:]}")
    return whole


def import_budget(stderr: str) -> dict:
    """From ``-X importtime`` output: the total of the imports' own times (s), the largest
    top-level packages by cumulative time (s), and which of ``HEAVY_IMPORTS`` were imported."""
    total, packages, names = 0.0, {}, set()
    for line in stderr.splitlines():
        if not line.startswith("import time:") or "|" not in line or "self [us]" in line:
            continue
        own, cumulative, name = line[len("import time:") :].split("|")
        total += int(own) / 1e6
        names.add(name.strip())  # a package counts when it is itself imported (the engine
        # blocks pyfftw's optional scipy.fftpack by a None entry, which importtime lists)
        if not name.startswith("  "):  # top level: its cumulative time includes its imports
            top = name.strip().split(".")[0]
            packages[top] = packages.get(top, 0.0) + int(cumulative) / 1e6
    largest = sorted(packages.items(), key=lambda item: -item[1])[:6]
    return dict(total_s=total, largest=largest, heavy=[m for m in HEAVY_IMPORTS if m in names])


def child_main(code: str, n: int, frictional: bool) -> None:
    try:
        if code in ("engine", "last", "coupled"):
            import engine.solvers.contact  # noqa: F401 (the imports, before the set-up)
            import engine.solvers.fretting  # noqa: F401

            before = _rss_mb()
            restart = "last" if code == "last" else "secant"
            row = child_engine(n, frictional, coupled=code == "coupled", restart=restart)
        else:
            __import__(code)  # the imports, before the set-up
            if code == "tamaas":
                sys.path.insert(0, str(Path(__file__).parent))
                import tamaas_reference  # noqa: F401

            before = _rss_mb()
            row = {"aspher": child_aspher, "tamaas": child_tamaas}[code](n, frictional)
    except ImportError as error:
        raise SystemExit(f"skipped: {error}") from None
    sneddon = LOAD / (2 * RADIUS * _contact_modulus())
    row.update(
        peak_mb=_peak_mb(),
        import_mb=before,
        solver_mb=_peak_mb() - before,
        approach_error=row["approach"] / sneddon - 1,
    )
    print(json.dumps(row))


def use_bytecode_cache(folder: str) -> None:
    """Let every child process compile a module once and reuse its bytecode, as an installed
    package does (an environment may set ``PYTHONDONTWRITEBYTECODE``: then each process
    compiles the engine's modules again, about a fifth of the command's CPU at 128²); the
    cache lives in ``folder`` (``PYTHONPYCACHEPREFIX``), so the trees stay untouched."""
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
    os.environ["PYTHONPYCACHEPREFIX"] = folder


def measure(sizes, repeats, frictional, anchors_python, tamaas_max, baseline=None) -> dict:
    """rows[(n, code)] = list of results over the rounds (codes alternate in each round);
    ``cli`` the engine's whole command, ``(0, "floor")`` its import floor and
    ``(0, "imports")`` all its imports (frictionless only). A first round at the smallest
    size, not recorded, fills the bytecode cache (``use_bytecode_cache``)."""
    rows, skipped = {}, {} if baseline is not None else {"baseline": "no --baseline"}
    skipped |= {} if frictional else {"coupled": "frictional only", "last": "frictional only"}
    for code in CODES:  # the warm-up round
        if code not in skipped:
            python = anchors_python if code in ANCHORS else sys.executable
            run_child(code, sizes[0], frictional, python, baseline if code == "baseline" else REPO)
    modules = []
    if not frictional:
        modules = imported_modules(run_cli(sizes[0], importtime=True)["importtime"])
        run_floor()
        run_imports(modules)
    for round_ in range(repeats):
        if not frictional:
            result = run_floor()
            rows.setdefault((0, "floor"), []).append(result)
            print(_cli_line("all", round_, result, "floor"), flush=True)
            result = run_imports(modules)
            rows.setdefault((0, "imports"), []).append(result)
            print(_cli_line("all", round_, result, "imports"), flush=True)
        for n in sizes:
            for code in CODES:
                if code in skipped or (code == "tamaas" and n > tamaas_max):
                    continue
                python = anchors_python if code in ANCHORS else sys.executable
                tree = baseline if code == "baseline" else REPO
                result = run_child(code, n, frictional, python, tree)
                if isinstance(result, str):
                    if code not in ANCHORS:
                        raise SystemExit(f"{code} failed at n = {n}: {result}")
                    skipped[code] = result
                    print(f"{code}: skipped ({result})", flush=True)
                    continue
                rows.setdefault((n, code), []).append(result)
                print(_line(n, code, round_, result), flush=True)
            if not frictional:
                result = run_cli(n)
                rows.setdefault((n, "cli"), []).append(result)
                print(_cli_line(n, round_, result), flush=True)
    return rows


HEADER = (
    f"{'n':>5} {'code':>8} {'round':>5} {'set-up s':>8} {'solve s':>8} {'solver CPU':>10} "
    f"{'solver MB':>9} {'peak MB':>8} {'script s':>8} {'script CPU':>10} {'iter':>6} "
    f"{'approach err':>12} {'converged':>9}"
)


def _line(n, code, round_, r) -> str:
    return (
        f"{n:>5} {code:>8} {round_:>5} {r['setup_s']:8.3f} {r['solve_s']:8.3f} "
        f"{r['cpu_s']:10.3f} {r.get('solver_mb', r['peak_mb']):9.0f} {r['peak_mb']:8.0f} "
        f"{r['script']['wall_s']:8.3f} {r['script']['cpu_s']:10.3f} "
        f"{r['iterations']:6d} {r['approach_error']:12.3e} {str(r['converged']):>9}"
    )


def _cli_line(n, round_, r, code: str = "CLI") -> str:
    return (
        f"{n:>5} {code:>8} {round_:>5} {'':>8} {'':>8} {'':>10} {'':>9} {r['peak_mb']:8.0f} "
        f"{r['wall_s']:8.3f} {r['cpu_s']:10.3f}"
    )


# --------------------------------------------------------------------- figures and ratios
def _solver(run: dict) -> dict:
    return {"cpu_s": run["cpu_s"], "peak_mb": run.get("solver_mb", run["peak_mb"])}


def _script(run: dict) -> dict:
    return run["script"]


def _cli(run: dict) -> dict:
    return run


def _best(runs: list[dict], part) -> dict:
    """Best (smallest) CPU and wall times over the rounds, median peak memory."""
    values = [part(run) for run in runs]
    best = {key: min(v[key] for v in values if key in v) for key in ("cpu_s", "wall_s")
            if any(key in v for v in values)}  # fmt: skip
    return best | {"peak_mb": statistics.median(v["peak_mb"] for v in values)}


def comparisons(rows: dict, sizes, frictional: bool) -> list[tuple]:
    """(n, what, engine figures, anchor name, anchor figures) per size: the solver and the
    script against each anchor's, the CLI and its import floor (the same process at every
    size) against each anchor's script; frictional: the coupled solve beside the uncoupled
    one."""
    table = []
    for n in sizes:
        engine = rows.get((n, "engine"), [])
        for anchor in ANCHORS:
            others = rows.get((n, anchor), [])
            if not engine or not others:
                continue
            table.append((n, "solver", _best(engine, _solver), anchor, _best(others, _solver)))
            table.append((n, "script", _best(engine, _script), anchor, _best(others, _script)))
            if rows.get((n, "cli")):
                cli = _best(rows[(n, "cli")], _cli)
                table.append((n, "CLI", cli, f"{anchor} script", _best(others, _script)))
            for part in ("floor", "imports"):
                if rows.get((0, part)):
                    own = _best(rows[(0, part)], _cli)
                    table.append((n, part, own, f"{anchor} script", _best(others, _script)))
        last = rows.get((n, "last"), [])
        for anchor in ANCHORS:
            others = rows.get((n, anchor), [])
            if last and others:
                for what, part in (("solver", _solver), ("script", _script)):
                    table.append((n, f"last {what}", _best(last, part), anchor,
                                  _best(others, part)))  # fmt: skip
        coupled = rows.get((n, "coupled"), [])
        if engine and coupled:
            for what, part in (("solver", _solver), ("script", _script)):
                table.append((n, f"coupled {what}", _best(coupled, part), "engine K = 0",
                              _best(engine, part)))  # fmt: skip
    return table


def print_ratios(rows: dict, sizes, frictional: bool) -> None:
    print(
        "\nper size: best CPU (s) and median peak memory (MB; solver: added to the process"
        " after its imports), engine / anchor"
    )
    print(
        f"{'n':>5} {'what':>15} {'vs':>14} {'engine CPU':>10} {'anchor CPU':>10} {'ratio':>6} "
        f"{'engine MB':>9} {'anchor MB':>9} {'ratio':>6}"
    )
    for n, what, mine, anchor, theirs in comparisons(rows, sizes, frictional):
        print(
            f"{n:>5} {what:>15} {anchor:>14} {mine['cpu_s']:10.4f} {theirs['cpu_s']:10.4f} "
            f"{mine['cpu_s'] / theirs['cpu_s']:6.2f} {mine['peak_mb']:9.0f} "
            f"{theirs['peak_mb']:9.0f} {mine['peak_mb'] / theirs['peak_mb']:6.2f}"
        )


def print_imports(budget: dict) -> None:
    largest = ", ".join(f"{name} {seconds:.3f}" for name, seconds in budget["largest"])
    heavy = ", ".join(budget["heavy"]) or "none"
    print(f"CLI imports (python -X importtime, wall): {budget['total_s']:.3f} s; largest {largest}")
    print(f"  of {', '.join(HEAVY_IMPORTS)} imported: {heavy}")


DOC_HEADER = (
    "n", "measured", "compared with", "engine CPU, best (s)", "anchor CPU, best (s)",
    "ratio of CPU", "engine peak (MB)", "anchor peak (MB)", "ratio of memory",
)  # fmt: skip

WHAT = {
    "solver": "solver in-process (memory: added after the imports)",
    "script": "whole script (process peak)",
    "CLI": "whole `python -m engine` (process peak)",
    "floor": "import floor of the command: NumPy, h5py, pyFFTW core (process peak)",
    "imports": "imports of the command: every module a run imports, nothing computed "
    "(process peak)",
    "last solver": "solver in-process, force control restarting from its last attempt (the "
    "fretting analysis's default)",
    "last script": "whole script, force control restarting from its last attempt",
    "coupled solver": "coupled (K = 0.196) solver in-process",
    "coupled script": "coupled (K = 0.196) whole script",
}


def doc_rows(rows: dict, sizes, frictional: bool) -> list[tuple]:
    return [
        (
            f"{n}²", WHAT[what], anchor, f"{mine['cpu_s']:.4f}", f"{theirs['cpu_s']:.4f}",
            f"{mine['cpu_s'] / theirs['cpu_s']:.2f}", f"{mine['peak_mb']:.0f}",
            f"{theirs['peak_mb']:.0f}", f"{mine['peak_mb'] / theirs['peak_mb']:.2f}",
        )
        for n, what, mine, anchor, theirs in comparisons(rows, sizes, frictional)
    ]  # fmt: skip


def write_doc_table(rows: dict, args, budget: dict | None, loads: tuple[float, float]) -> None:
    """The table of the manual's memory and set-up page (block ``bench-anchors`` or
    ``bench-anchors-frictional``), with the date, the machine and its load."""
    sys.path.insert(0, str(REPO))
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    block = "bench-anchors-frictional" if args.frictional else "bench-anchors"
    note = "`python benchmarks/bench_anchors.py --sizes " + " ".join(map(str, args.sizes))
    note += f" --repeats {args.repeats}" + " --frictional" * args.frictional
    note += " --update-docs`, one core per process, codes alternating in each round; CPU"
    note += " times: the best of the rounds; memory: median; load average at the start"
    note += f" {loads[0]:.1f}"
    text = (
        measured_on(note)
        + "\n"
        + markdown_table(DOC_HEADER, doc_rows(rows, args.sizes, args.frictional))
    )
    if budget is not None:
        largest = ", ".join(f"{name} {seconds:.2f} s" for name, seconds in budget["largest"][:4])
        heavy = ", ".join(budget["heavy"]) or "none"
        text = text.rstrip("\n") + (
            f"\n\nImports of `python -m engine` at {args.sizes[0]}² (`-X importtime`, wall "
            f"times, which the load inflates): {budget['total_s']:.2f} s in all (largest: "
            f"{largest}); of pandas, SciPy and matplotlib imported: {heavy}."
        )
    document = REPO / "docs" / "explanation" / "memory-and-setup.md"
    replace_block(document, block, text)
    print(f"{document}: wrote the block {block}")


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
    kind = (
        f"frictional (mu = {FRICTION}, K = 0, then Q = {TANGENTIAL_FRACTION} mu P; coupled:"
        " the engine's static solve on K = 0.196)"
        if args.frictional
        else "frictionless"
    )
    print(f"flat punch, {kind}, tol {TOL:g}, one core per process; sizes {args.sizes}")
    start_load = os.getloadavg()[0]
    print(f"load average at the start: {start_load:.1f}")
    with tempfile.TemporaryDirectory() as bytecode:
        use_bytecode_cache(bytecode)
        print(HEADER)
        rows = measure(
            args.sizes,
            args.repeats,
            args.frictional,
            args.anchors_python,
            args.tamaas_max,
            args.baseline,
        )
        budget = None
        if not args.frictional:
            budget = import_budget(run_cli(args.sizes[0], importtime=True)["importtime"])
    end_load = os.getloadavg()[0]
    print(f"load average at the end: {end_load:.1f}")
    print_ratios(rows, args.sizes, args.frictional)
    if budget is not None:
        print_imports(budget)
    if args.update_docs:
        write_doc_table(rows, args, budget, (start_load, end_load))


if __name__ == "__main__":
    main()
