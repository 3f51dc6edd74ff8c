"""Rough surfaces: the engine beside Tamaas on the same height map, speed and memory.

Four measurements, each in fresh child processes on one core (``OMP_NUM_THREADS=1``):

``tamaas``  A rigid flat punch (a0 = 1 mm, grid ±1.05 mm, n²) carrying a self-affine
            roughness (H = 0.8, λ_L = 0.25 mm, λ_S = 8 elements, h'_rms = 0.1) pressed
            frictionless on steel (E* = 115 GPa) at p̄ = 0.04 E* h'_rms: the engine's
            solver and Tamaas 2.9's PKR on Tamaas's non-periodic DC-FFT operator, on the
            same height map (written to a .npy file and read by both). Printed: real contact
            area fraction, approach δ = mean(u − h) over the contact, the contact sets'
            symmetric difference, the pressures' relative L2 distance, solve times. Tamaas runs
            from its own environment (``--tamaas-python``, default
            /tmp/tamaas-venv/bin/python: ``python3 -m venv /tmp/tamaas-venv &&
            /tmp/tamaas-venv/bin/pip install tamaas==2.9.0``).
``speed``   A 512² static frictional solve (μ = 0.3, five load increments to 100 N) of a
            steel sphere (R = 12.7 mm, mesh ±2 a_Hertz) smooth and with a self-affine
            roughness (h_rms = 0.3 µm ≈ 0.1 δ_Hertz, λ_L = 0.2 mm, λ_S = 4 elements), in
            alternating rounds; CPU time of the solves, the ratio rough/smooth.
``loads``   The rough flat punch (λ_S = 4 elements) from first touch to full contact,
            p̄/(E* h'_rms) = 1e-6 … 3, frictionless and at μ = 0.3: convergence, iterations.
``memory``  A 2048² frictionless rough solve of the same sphere (h_rms = 0.3 µm): the child's
            peak resident memory (``VmHWM``) against 2 GB.
``study``   The bundled study ``studies/rough_fretting.toml`` run from scratch in a temporary
            folder with ``mpiexec -n 2`` (its header's command), the wall time against 15
            minutes; ``--study-seeds K`` keeps the first K of its 10 realisations (6 K cases)
            and prints the time scaled to the 60 cases beside the measured one.

    python benchmarks/bench_rough.py                      # all five, small sizes by default
    python benchmarks/bench_rough.py --tamaas-n 256 --speed-n 512 --loads-n 512 \\
        --memory-n 2048 --study-seeds 10 --update-docs    # the figures of the manual
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _single_core import single_core_env

REPO = Path(__file__).resolve().parents[1]
MODULUS = 210e3 / (2 * (1 - 0.3**2))  # E* of steel on steel (MPa)
SPHERE_RADIUS, SPHERE_LOAD = 12.7, 100.0  # mm, N
PUNCH_RADIUS, PUNCH_HALF_WIDTH = 1.0, 1.05  # mm
STUDY = REPO / "studies" / "rough_fretting.toml"
STUDY_SEEDS = 10  # the realisations of the bundled study
SPEED_LIMIT, MEMORY_LIMIT_MB, STUDY_LIMIT_S = 1.5, 2048.0, 900.0  # the targets of the manual


# ------------------------------------------------------------------ children
def _peak_mb() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024
    return math.nan


def _punch_height(n: int) -> np.ndarray:
    from engine.grid import Grid
    from engine.surface.topography import self_affine

    grid = Grid.square(n, PUNCH_HALF_WIDTH)
    return self_affine(
        grid.shape, (grid.dx, grid.dy), hurst=0.8, long_cutoff=0.25, short_cutoff=8 * grid.dx,
        seed=1, rms_slope=0.1,
    )  # fmt: skip


def _punch_load(n: int) -> float:
    from engine.geometry import FlatPunch
    from engine.grid import Grid

    grid = Grid.square(n, PUNCH_HALF_WIDTH)
    nominal = np.count_nonzero(np.isfinite(FlatPunch(PUNCH_RADIUS).gap(grid))) * grid.dx**2
    return 0.04 * MODULUS * 0.1 * nominal


def child_engine_punch(n: int, height_file: str) -> dict:
    from engine.geometry import FlatPunch
    from engine.grid import Grid
    from engine.material import MaterialPair
    from engine.solvers.contact import ContactSolver
    from engine.solvers.friction import FrictionLaw
    from engine.surface.profile import RoughProfile

    grid = Grid.square(n, PUNCH_HALF_WIDTH)
    height = np.load(height_file)
    material = MaterialPair(210e3, 0.3, 210e3, 0.3)
    profile = RoughProfile(FlatPunch(PUNCH_RADIUS), height, grid)
    solver = ContactSolver(grid, material, profile, FrictionLaw(0.0, 0.0), tol=1e-10)
    start = time.perf_counter()
    result = solver.solve_load(_punch_load(n))
    elapsed = time.perf_counter() - start
    np.save(height_file.replace(".npy", "_engine_p.npy"), result.pressure)
    return dict(
        approach=float(result.approach), solve_s=elapsed, converged=bool(result.report.converged),
        iterations=result.report.iterations, residual=result.report.residual,
    )  # fmt: skip


def child_tamaas_punch(n: int, height_file: str) -> dict:
    sys.path.insert(0, str(Path(__file__).parent))
    from tamaas_reference import solve_rough_punch_tamaas

    load = float(os.environ["ROUGH_LOAD"])
    result = solve_rough_punch_tamaas(
        np.load(height_file), PUNCH_RADIUS, PUNCH_HALF_WIDTH, load, MODULUS, tol=1e-10
    )
    np.save(height_file.replace(".npy", "_tamaas_p.npy"), result.pop("pressure"))
    result.pop("contact")
    return result


def _sphere(n: int, rms: float, mu: float):
    from engine.geometry import SphericalPunch
    from engine.grid import Grid
    from engine.material import MaterialPair
    from engine.reference.hertz import hertz_contact_radius
    from engine.solvers.contact import ContactSolver
    from engine.solvers.friction import FrictionLaw
    from engine.surface.profile import RoughProfile
    from engine.surface.topography import self_affine

    a = hertz_contact_radius(SPHERE_LOAD, SPHERE_RADIUS, MODULUS)
    grid = Grid.square(n, 2.0 * a)
    profile = SphericalPunch(SPHERE_RADIUS)
    if rms > 0.0:
        height = self_affine(
            grid.shape, (grid.dx, grid.dy), hurst=0.8, long_cutoff=0.2,
            short_cutoff=4 * grid.dx, seed=1, rms_height=rms,
        )  # fmt: skip
        profile = RoughProfile(profile, height, grid)
    material = MaterialPair(210e3, 0.3, 210e3, 0.3)
    return ContactSolver(grid, material, profile, FrictionLaw(mu, mu), tol=1e-8)


def child_speed(n: int, rms: float) -> dict:
    solver = _sphere(n, rms, 0.3)
    cpu, wall = time.process_time(), time.perf_counter()
    state, matvecs, converged = None, 0, True
    for step in range(1, 6):
        result = solver.solve_load(SPHERE_LOAD * step / 5, state)
        state, matvecs = result.state, matvecs + result.report.matvecs
        converged &= result.report.converged
    contact = int(np.count_nonzero(result.pressure > 0))
    return dict(
        cpu_s=time.process_time() - cpu, wall_s=time.perf_counter() - wall, matvecs=matvecs,
        converged=bool(converged), contact_elements=contact, approach=float(result.approach),
    )  # fmt: skip


def child_memory(n: int) -> dict:
    base = _peak_mb()
    solver = _sphere(n, 3e-4, 0.0)
    start = time.perf_counter()
    result = solver.solve_load(SPHERE_LOAD)
    return dict(
        peak_mb=_peak_mb(), import_mb=base, solve_s=time.perf_counter() - start,
        converged=bool(result.report.converged), iterations=int(result.report.iterations),
    )  # fmt: skip


def child_loads(n: int, mu: float) -> dict:
    """The rough flat punch of ``tamaas`` (λ_S = 4 elements) from first touch to full
    contact: p̄/(E* h'_rms) = 1e-6 … 3, each load solved from the unloaded state."""
    from engine.geometry import FlatPunch
    from engine.grid import Grid
    from engine.material import MaterialPair
    from engine.solvers.contact import ContactSolver
    from engine.solvers.friction import FrictionLaw
    from engine.surface.profile import RoughProfile
    from engine.surface.topography import self_affine

    grid = Grid.square(n, PUNCH_HALF_WIDTH)
    height = self_affine(
        grid.shape, (grid.dx, grid.dy), hurst=0.8, long_cutoff=0.25, short_cutoff=4 * grid.dx,
        seed=2, rms_slope=0.1,
    )  # fmt: skip
    material = MaterialPair(210e3, 0.3, 210e3, 0.3)
    profile = RoughProfile(FlatPunch(PUNCH_RADIUS), height, grid)
    solver = ContactSolver(grid, material, profile, FrictionLaw(mu, mu), tol=1e-8)
    face = np.count_nonzero(np.isfinite(FlatPunch(PUNCH_RADIUS).gap(grid)))
    rows = []
    for pressure in (1e-6, 1e-4, 1e-2, 0.1, 1.0, 3.0):
        start = time.process_time()
        result = solver.solve_load(pressure * MODULUS * 0.1 * face * grid.dx**2)
        rows.append(dict(
            pressure=pressure, converged=bool(result.report.converged),
            iterations=int(result.report.iterations), residual=float(result.report.residual),
            area=int(np.count_nonzero(result.pressure > 0)) / face,
            cpu_s=time.process_time() - start,
        ))  # fmt: skip
    return {"rows": rows}


CHILDREN = {
    "loads": child_loads,
    "engine_punch": child_engine_punch,
    "tamaas_punch": child_tamaas_punch,
    "speed": child_speed,
    "memory": child_memory,
}


def _child(name: str, *args: str, python: str = sys.executable, env_extra=None) -> dict:
    env = single_core_env(REPO)
    env.update(env_extra or {})
    command = [python, __file__, "--child", name, *args]
    done = subprocess.run(command, env=env, capture_output=True, text=True, cwd=REPO)
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode != 0 or not lines:
        raise RuntimeError(f"{name} failed: {done.stderr.strip()[-2000:]}")
    return json.loads(lines[-1])


# ------------------------------------------------------------------ measurements
def measure_tamaas(n: int, tamaas_python: str) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        path = str(Path(folder) / "height.npy")
        np.save(path, _punch_height(n))
        load = _punch_load(n)
        ours = _child("engine_punch", str(n), path)
        theirs = _child(
            "tamaas_punch", str(n), path, python=tamaas_python,
            env_extra={"ROUGH_LOAD": repr(float(load)), "PYTHONPATH": ""},
        )  # fmt: skip
        p_ours = np.load(path.replace(".npy", "_engine_p.npy"))
        p_theirs = np.load(path.replace(".npy", "_tamaas_p.npy"))
    from engine.geometry import FlatPunch
    from engine.grid import Grid

    grid = Grid.square(n, PUNCH_HALF_WIDTH)
    face = np.count_nonzero(np.isfinite(FlatPunch(PUNCH_RADIUS).gap(grid)))
    c_ours, c_theirs = p_ours > 0, p_theirs > 0
    row = dict(
        n=n, load=load,
        area_engine=c_ours.sum() / face, area_tamaas=c_theirs.sum() / face,
        approach_engine=ours["approach"], approach_tamaas=theirs["approach"],
        contact_difference=int(np.count_nonzero(c_ours ^ c_theirs)),
        contact_elements=int(c_ours.sum()),
        pressure_l2=float(np.linalg.norm(p_ours - p_theirs) / np.linalg.norm(p_theirs)),
        engine_s=ours["solve_s"], tamaas_s=theirs["solve_time_s"],
        engine_iterations=ours["iterations"], tamaas_iterations=theirs["iterations"],
        engine_converged=ours["converged"], tamaas_converged=theirs["converged"],
        tamaas_residual=theirs["face_residual"], tamaas_version=theirs["tamaas_version"],
    )  # fmt: skip
    print(
        f"Tamaas side by side, n = {n}, P = {load:.1f} N: real area fraction engine "
        f"{row['area_engine']:.5f}, Tamaas {row['area_tamaas']:.5f}; approach engine "
        f"{row['approach_engine'] * 1e3:.5f} µm, Tamaas {row['approach_tamaas'] * 1e3:.5f} µm"
        f" (relative difference {row['approach_engine'] / row['approach_tamaas'] - 1:.2e}); "
        f"contact sets differ in {row['contact_difference']} of {row['contact_elements']} "
        f"elements; pressure L2 distance {row['pressure_l2']:.2e}; solve {row['engine_s']:.2f} s "
        f"({row['engine_iterations']} it.) vs Tamaas {row['tamaas_s']:.2f} s "
        f"({row['tamaas_iterations']} it.)",
        flush=True,
    )
    return row


def measure_speed(n: int, rounds: int) -> dict:
    runs = {"smooth": [], "rough": []}
    for _ in range(rounds):
        for label, rms in (("smooth", 0.0), ("rough", 3e-4)):
            result = _child("speed", str(n), repr(rms))
            runs[label].append(result)
            print(f"  {label:6s} n = {n}: {result}", flush=True)
    best = {label: min(r["cpu_s"] for r in values) for label, values in runs.items()}
    row = dict(
        n=n, smooth_cpu_s=best["smooth"], rough_cpu_s=best["rough"],
        ratio=best["rough"] / best["smooth"], smooth_matvecs=runs["smooth"][0]["matvecs"],
        rough_matvecs=runs["rough"][0]["matvecs"],
        converged=all(r["converged"] for v in runs.values() for r in v),
    )  # fmt: skip
    print(
        f"Static frictional solve n = {n} (best of {rounds}, CPU): smooth "
        f"{best['smooth']:.1f} s, rough {best['rough']:.1f} s, ratio {row['ratio']:.2f} "
        f"(target ≤ {SPEED_LIMIT:g}: {'met' if row['ratio'] <= SPEED_LIMIT else 'NOT met'})",
        flush=True,
    )
    return row


def measure_loads(n: int) -> dict:
    row = {"n": n}
    for mu in (0.0, 0.3):
        rows = _child("loads", str(n), repr(mu))["rows"]
        row[mu] = rows
        for item in rows:
            print(f"  loads n = {n}, μ = {mu}: {item}", flush=True)
    converged = all(item["converged"] for mu in (0.0, 0.3) for item in row[mu])
    row["converged"] = converged
    row["iterations"] = max(item["iterations"] for mu in (0.0, 0.3) for item in row[mu])
    row["areas"] = (row[0.0][0]["area"], row[0.0][-1]["area"])
    print(
        f"Rough flat punch n = {n}, p̄/(E* h'_rms) from 1e-6 to 3, μ = 0 and 0.3: all "
        f"converged {converged}, at most {row['iterations']} iterations, contact fraction "
        f"{row['areas'][0]:.2e} to {row['areas'][1]:.5f}",
        flush=True,
    )
    return row


def measure_memory(n: int) -> dict:
    row = _child("memory", str(n)) | {"n": n}
    met = "met" if row["peak_mb"] <= MEMORY_LIMIT_MB else "NOT met"
    print(
        f"Frictionless rough solve n = {n}: peak resident memory {row['peak_mb']:.0f} MB "
        f"(after imports {row['import_mb']:.0f} MB; target ≤ {MEMORY_LIMIT_MB:.0f} MB: {met}), "
        f"{row['solve_s']:.0f} s, converged {row['converged']}",
        flush=True,
    )
    return row


def _mpiexec() -> str:
    """The launcher beside this Python (a venv's mpiexec), else the one on the PATH."""
    beside = Path(sys.executable).with_name("mpiexec")
    return str(beside) if beside.exists() else (shutil.which("mpiexec") or "mpiexec")


def measure_study(seeds: int) -> dict:
    """The bundled study with its first ``seeds`` realisations, from scratch on 2 ranks."""
    text = STUDY.read_text()
    kept = ", ".join(str(seed) for seed in range(1, seeds + 1))
    text, count = re.subn(r'^"surface\.seed" = \[.*\]$', f'"surface.seed" = [{kept}]', text,
                          flags=re.M)  # fmt: skip
    if count != 1:
        raise RuntimeError(f"{STUDY}: no surface.seed list to trim")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / STUDY.name
        path.write_text(text)
        command = [_mpiexec(), "-n", "2", sys.executable, "-m", "engine", str(path)]
        environment = dict(os.environ, OMP_NUM_THREADS="1")
        environment["PYTHONPATH"] = os.pathsep.join(
            filter(None, [str(REPO), environment.get("PYTHONPATH")])
        )
        start = time.perf_counter()
        done = subprocess.run(command, cwd=folder, env=environment, capture_output=True, text=True)
        wall = time.perf_counter() - start
        if done.returncode != 0:
            raise RuntimeError(f"study failed: {done.stderr.strip()[-2000:]}")
        last = [line for line in done.stdout.splitlines() if line.startswith("study ")][-1:]
    cases = 6 * seeds
    scaled = wall * STUDY_SEEDS / seeds
    met = "met" if scaled <= STUDY_LIMIT_S else "NOT met"
    row = dict(seeds=seeds, cases=cases, wall_s=wall, scaled_s=scaled, summary=last)
    what = "" if seeds == STUDY_SEEDS else f"; scaled to the 60 cases {scaled / 60:.1f} min"
    print(
        f"Bundled study {STUDY.name} on 2 ranks, {cases} cases ({seeds} of {STUDY_SEEDS} "
        f"realisations): wall {wall / 60:.1f} min{what} (target < {STUDY_LIMIT_S / 60:.0f} min: "
        f"{met}); {last[0] if last else ''}",
        flush=True,
    )
    return row


def write_doc_block(tamaas, speed, memory, loads=None, study=None) -> None:
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    document = REPO / "docs" / "explanation" / "performance.md"
    rows = []
    if tamaas:
        rows.append((
            f"rough flat punch beside Tamaas {tamaas['tamaas_version']}, {tamaas['n']}²",
            f"area {tamaas['area_engine']:.4f} vs {tamaas['area_tamaas']:.4f}; approach "
            f"{tamaas['approach_engine'] / tamaas['approach_tamaas'] - 1:+.1e} relative; "
            f"{tamaas['contact_difference']} of {tamaas['contact_elements']} contact "
            f"elements differ; pressure L2 {tamaas['pressure_l2']:.1e}",
            f"{tamaas['engine_s']:.2f} s vs {tamaas['tamaas_s']:.2f} s",
        ))  # fmt: skip
    if speed:
        rows.append((
            f"static frictional sphere, {speed['n']}², 5 increments",
            f"rough / smooth CPU time {speed['ratio']:.2f} (operator applications "
            f"{speed['rough_matvecs']} / {speed['smooth_matvecs']})",
            f"{speed['rough_cpu_s']:.1f} s vs {speed['smooth_cpu_s']:.1f} s",
        ))  # fmt: skip
    if memory:
        rows.append((
            f"frictionless rough sphere, {memory['n']}²",
            f"peak resident memory {memory['peak_mb']:.0f} MB (limit 2048 MB)",
            f"{memory['solve_s']:.0f} s",
        ))  # fmt: skip
    if study:
        scaled = "" if study["seeds"] == STUDY_SEEDS else (
            f" (scaled to 60 cases: {study['scaled_s'] / 60:.1f} min)"
        )  # fmt: skip
        rows.append((
            f"studies/{STUDY.name} on 2 ranks, {study['cases']} cases",
            f"wall time against 15 min{scaled}",
            f"{study['wall_s'] / 60:.1f} min",
        ))  # fmt: skip
    command = " ".join(["python benchmarks/bench_rough.py", *sys.argv[1:]])
    note = f"`{command}`, one core per process"
    if rows:  # the loads have their own block: each block is what one run measured
        text = measured_on(note) + "\n" + markdown_table(("case", "result", "time"), rows)
        replace_block(document, "bench-rough", text)
        print(f"{document}: wrote the block bench-rough")
    rows = []
    if loads:
        cpu = sum(item["cpu_s"] for mu in (0.0, 0.3) for item in loads[mu])
        rows.append((
            f"rough flat punch, {loads['n']}², first touch to full contact, μ = 0 and 0.3",
            f"6 loads each (p̄/(E* h'_rms) = 1e-6 … 3): converged {loads['converged']}, at most "
            f"{loads['iterations']} iterations, contact fraction {loads['areas'][0]:.1e} to "
            f"{loads['areas'][1]:.5f}",
            f"{cpu:.0f} s",
        ))  # fmt: skip
        text = measured_on(note) + "\n" + markdown_table(("case", "result", "CPU"), rows)
        replace_block(document, "bench-rough-loads", text)
        print(f"{document}: wrote the block bench-rough-loads")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--child", choices=CHILDREN)
    parser.add_argument("--tamaas-n", type=int, default=128)
    parser.add_argument("--speed-n", type=int, default=128)
    parser.add_argument("--memory-n", type=int, default=256)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--loads-n", type=int, default=128)
    parser.add_argument("--study-seeds", type=int, default=1, choices=range(1, STUDY_SEEDS + 1))
    parser.add_argument(
        "--only", choices=("tamaas", "speed", "loads", "memory", "study"), nargs="+"
    )
    parser.add_argument("--tamaas-python", default="/tmp/tamaas-venv/bin/python")
    parser.add_argument("--update-docs", action="store_true")
    args, rest = parser.parse_known_args()
    if args.child:
        n, *others = rest
        converted = [float(v) if args.child in ("speed", "loads") else v for v in others]
        print(json.dumps(CHILDREN[args.child](int(n), *converted)))
        return
    print(f"load average {os.getloadavg()[0]:.1f}", flush=True)
    parts = args.only or ("tamaas", "speed", "loads", "memory", "study")
    tamaas = speed = memory = loads = study = None
    if "tamaas" in parts:
        if Path(args.tamaas_python).exists():
            tamaas = measure_tamaas(args.tamaas_n, args.tamaas_python)
        else:
            print(f"tamaas: skipped ({args.tamaas_python} not found)")
    if "speed" in parts:
        speed = measure_speed(args.speed_n, args.rounds)
    if "loads" in parts:
        loads = measure_loads(args.loads_n)
    if "memory" in parts:
        memory = measure_memory(args.memory_n)
    if "study" in parts:
        study = measure_study(args.study_seeds)
    print(f"load average {os.getloadavg()[0]:.1f}", flush=True)
    if args.update_docs:
        write_doc_block(tamaas, speed, memory, loads, study)


if __name__ == "__main__":
    main()
