"""Tamaas reference for the frictionless flat-punch solver benchmark.

Runs Tamaas's Polonsky–Keer–Rey (PKR) solver on the same problem our solver solves:
a rigid flat-ended cylindrical punch (radius a0) pressed with load P onto an elastic
half-space of contact modulus E*, over a *non-periodic* square potential contact zone
[-hw, hw]² (hw = half_width_factor·a0) discretised with n × n uniform elements.

Tamaas is an optional, benchmark-only dependency (not a project dependency). Tamaas 2.9
requires numpy >= 2 and ships a manylinux wheel for CPython 3.11 / x86_64::

    pip install tamaas==2.9.0

It installs cleanly into the project venv (no numpy/scipy change), or into a scratch venv::

    python3 -m venv /tmp/tamaas-venv && /tmp/tamaas-venv/bin/pip install tamaas==2.9.0
    /tmp/tamaas-venv/bin/python benchmarks/tamaas_reference.py

How the problem is expressed in Tamaas (API of Tamaas 2.9):

* ``tm.ModelFactory.createModel(tm.model_type.basic_2d, [L, L], [n, n])`` with L = 2·hw:
  a boundary-only model whose n × n grid covers exactly the potential contact zone.
  ``model.E``/``model.nu`` are set (before registering operators) so that
  ``model.E_star == E / (1 - nu²) == contact_modulus``.
* ``tm.ModelFactory.registerNonPeriodic(model, "dcfft")`` registers Tamaas's non-periodic
  Boussinesq operator (DC-FFT with uniform-pressure-per-element influence coefficients:
  its self-influence equals Love's centre deflection of a uniformly loaded square, and the
  far field decays as 1/r without periodic images), and
  ``solver.setIntegralOperator("dcfft")`` makes PKR use it instead of the default
  periodic Westergaard operator.
* Tamaas has no "element outside the punch" notion: its surface is a height field h and
  contact is where the deformed surface reaches h. The flat face is h = 0 for element
  centres with r <= a0, and elements with r > a0 get h = -depth (recessed, never touched).
* ``tm.PolonskyKeerRey(model, h, tol, PolonskyKeerRey.pressure, PolonskyKeerRey.pressure)``
  and ``solver.solve(P / L²)``: load control, the argument being the mean pressure over the
  *whole* grid. ``model.traction`` is then the pressure (positive in compression) and
  ``model.displacement`` the surface displacement shifted by the rigid approach.

Caveat on "the same tolerance": Tamaas's PKR error is normalised by the height scale of the
surface, so for a flat punch it depends on the artificial recess depth of the excluded
region (measured: with depth = 1e3 mm a "1e-8" solve stops after 9 iterations at n = 256
with a 5 % pressure error; with depth = 1e6 mm it stops at once on a uniform pressure). The
default ``depth`` here is 2·δ_Sneddon = P/(E* a0) ≈ 1.8e-3 mm, i.e. the normalisation
length is the punch's own approach; the achieved accuracy is then reported independently
of Tamaas's error measure as ``face_residual`` = (max − min of the elastic displacement over
the contact elements) / approach, which is solver-agnostic (a converged rigid flat face has
0), so our solver can be held to the same figure.

Threads: the PyPI build of Tamaas 2.9 has the sequential "cpp" backend
(``tm.TamaasInfo.backend == 'cpp'``; the extension links neither OpenMP nor threaded FFTW),
so it always runs on one core; ``threads`` only sets OMP_NUM_THREADS / FFTW env for the
record and is reported back, it cannot make Tamaas parallel.

Measured on the 2-core project machine (Tamaas 2.9.0, tol 1e-8, default depth, best of 3,
solve time only; OMP_NUM_THREADS=2 gives the same times):

    n    solve s  iters  force err  approach/Sneddon-1  face resid  Sneddon dev (r<=0.8a0)
    64    0.055     36    2e-15         4.9e-3            1.6e-8        2.38 %
   128    0.37      51    4e-15         1.7e-3            1.3e-8        0.70 %
   256    2.3       72    7e-16         9.2e-4            8.5e-9        0.36 %
   512   14.6       98    6e-15         4.8e-4            1.5e-8        0.18 %
"""

from __future__ import annotations

import math
import os
import re
import tempfile
import time
from typing import Any

import numpy as np

INSTALL_HINT = (
    "Tamaas is needed for this benchmark reference: `pip install tamaas==2.9.0` "
    "(CPython 3.11 x86_64 manylinux wheel on PyPI; requires numpy>=2), e.g. in a scratch "
    "venv: python3 -m venv /tmp/tamaas-venv && /tmp/tamaas-venv/bin/pip install tamaas==2.9.0"
)


def _import_tamaas(threads: int):
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, str(threads))
    try:
        import tamaas as tm  # noqa: PLC0415 - optional benchmark-only dependency
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(INSTALL_HINT) from exc
    return tm


class _CaptureStderrFD:
    """Capture what C++ code writes to file descriptor 2 (Tamaas logs its solver there)."""

    def __enter__(self):
        self._tmp = tempfile.TemporaryFile(mode="w+b")
        self._saved = os.dup(2)
        os.dup2(self._tmp.fileno(), 2)
        return self

    def __exit__(self, *exc_info):
        os.dup2(self._saved, 2)
        os.close(self._saved)
        self._tmp.seek(0)
        self.text = self._tmp.read().decode(errors="replace")
        self._tmp.close()
        return False


_ITER_LINE = re.compile(r"^\s*(\d+)\s+[-+0-9.eE]+\s+[-+0-9.eE]+\s*$")


def _iterations_from_log(log: str, converged: bool) -> int | None:
    """Tamaas prints 'Iter Cost_f Error' lines, the last one after the loop ends.

    Iterations are numbered from 0; the closing line repeats the last index when the
    tolerance was met, and is one past it when max_iter stopped the loop.
    """
    indices = [int(m.group(1)) for line in log.splitlines() if (m := _ITER_LINE.match(line))]
    if not indices:
        return None
    return indices[-1] + 1 if converged else indices[-1]


def sneddon_pressure(r: np.ndarray, load: float, radius: float) -> np.ndarray:
    """p = P / (2π a0 √(a0² − r²)) for r < a0 (MPa), NaN elsewhere."""
    r = np.asarray(r, dtype=float)
    out = np.full_like(r, np.nan)
    inside = r < radius
    out[inside] = load / (2.0 * np.pi * radius * np.sqrt(radius**2 - r[inside] ** 2))
    return out


def solve_flat_punch_tamaas(
    n: int,
    radius: float = 1.8,
    half_width_factor: float = 1.05,
    load: float = 714.0,
    contact_modulus: float = 217604.0,
    tol: float = 1e-8,
    threads: int = 1,
    *,
    poisson_ratio: float = 0.3,
    depth: float | None = None,
    max_iter: int = 10000,
) -> dict[str, Any]:
    """Solve the frictionless flat punch with Tamaas's PKR on a non-periodic n × n grid.

    Units: mm, N, MPa. ``depth`` is the recess (mm) given to elements outside the punch
    face (default 2·P/(2 E* a0), see module docstring). Returns a dict with

    - ``solve_time_s``: wall time of ``solver.solve`` only; ``setup_time_s``: model,
      operator and solver construction (+ geometry);
    - ``iterations`` (from Tamaas's log), ``error`` (Tamaas's own final error),
      ``converged``;
    - ``pressure``: (n, n) array [i, j] at (x_i, y_j), x_i = -hw + dx (i + 0.5), MPa;
      ``x`` (= y) centres, ``dx``, ``element_area``;
    - ``force`` = Σ p ΔA (N) and ``force_rel_error`` = force / P − 1;
    - ``approach``: rigid approach δ (mm) = mean elastic displacement over the contact
      elements, ``approach_sneddon`` = P / (2 E* a0);
    - ``face_residual``: (max − min of elastic displacement over contact) / δ;
    - ``n_contact`` and ``n_face`` (elements with r <= a0), ``outside_contact``
      (contact elements off the face; must be 0);
    - ``sneddon_max_rel_dev``: max |p − p_Sneddon| / p_Sneddon over centres r <= 0.8 a0;
    - ``threads``, ``tamaas_version``, ``tamaas_backend``, ``depth``.
    """
    if isinstance(n, bool) or int(n) != n or n < 4:
        raise ValueError(f"n must be an integer >= 4, got {n!r}")
    n = int(n)
    tm = _import_tamaas(threads)

    half_width = half_width_factor * radius
    side = 2.0 * half_width
    dx = side / n
    approach_sneddon = load / (2.0 * contact_modulus * radius)
    if depth is None:
        depth = 2.0 * approach_sneddon
    nu = poisson_ratio
    young = contact_modulus * (1.0 - nu**2)

    t0 = time.perf_counter()
    x = -half_width + dx * (np.arange(n) + 0.5)
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    face = r <= radius
    surface = np.where(face, 0.0, -float(depth))

    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [side, side], [n, n])
    model.E = young  # set elastic constants before registering the operator
    model.nu = nu
    tm.ModelFactory.registerNonPeriodic(model, "dcfft")
    solver = tm.PolonskyKeerRey(
        model, surface, tol, tm.PolonskyKeerRey.pressure, tm.PolonskyKeerRey.pressure
    )
    solver.setIntegralOperator("dcfft")
    solver.max_iter = max_iter
    solver.dump_freq = 2**31 - 1  # log only the first and the closing line
    setup_time = time.perf_counter() - t0
    if not math.isclose(model.E_star, contact_modulus, rel_tol=1e-12):
        raise RuntimeError(f"Tamaas E* = {model.E_star} != {contact_modulus}")

    with _CaptureStderrFD() as cap:
        t0 = time.perf_counter()
        error = solver.solve(load / side**2)
        solve_time = time.perf_counter() - t0
    converged = error <= tol
    iterations = _iterations_from_log(cap.text, converged)

    pressure = np.array(model.traction, dtype=float, copy=True).reshape(n, n)
    elastic = np.zeros_like(pressure)
    model.operators["dcfft"](pressure, elastic)  # K p, displacement without rigid shift
    contact = pressure > 0.0
    approach = float(elastic[contact].mean()) if contact.any() else float("nan")
    face_residual = float(np.ptp(elastic[contact]) / approach) if contact.any() else float("nan")

    element_area = dx * dx
    force = float(pressure.sum() * element_area)
    inner = r <= 0.8 * radius
    p_ref = sneddon_pressure(r[inner], load, radius)
    dev = float(np.max(np.abs(pressure[inner] - p_ref) / p_ref))

    return {
        "n": n,
        "solve_time_s": solve_time,
        "setup_time_s": setup_time,
        "iterations": iterations,
        "error": float(error),
        "converged": bool(converged),
        "tol": tol,
        "pressure": pressure,
        "x": x,
        "dx": dx,
        "element_area": element_area,
        "force": force,
        "force_rel_error": force / load - 1.0,
        "approach": approach,
        "approach_sneddon": approach_sneddon,
        "face_residual": face_residual,
        "n_contact": int(contact.sum()),
        "n_face": int(face.sum()),
        "outside_contact": int((contact & ~face).sum()),
        "sneddon_max_rel_dev": dev,
        "depth": float(depth),
        "threads": threads,
        "tamaas_version": tm.__version__,
        "tamaas_backend": tm.TamaasInfo.backend,
        "log": cap.text,
    }


def solve_rough_punch_tamaas(
    height: np.ndarray,
    radius: float,
    half_width: float,
    load: float,
    contact_modulus: float,
    tol: float = 1e-10,
    *,
    poisson_ratio: float = 0.3,
    max_iter: int = 10000,
) -> dict[str, Any]:
    """A rigid flat punch of ``radius`` (mm) with the roughness ``height`` (mm, (n, n) on the
    element centres of [−half_width, half_width]², asperity tops positive) pressed with
    ``load`` (N) on the non-periodic half-space (DC-FFT), with Tamaas's PKR.

    The Tamaas surface is ``height`` on the face and a recess of 4 × (ptp(height) + P/(E* a0))
    outside it (never touched). Returns the pressure (MPa), the contact elements, the approach
    δ = mean(u − h) over the contact (the rigid shift of the engine's convention g = g_g − h,
    u = δ + h in contact) and its spread ``face_residual`` = ptp(u − h)/δ, the solve time,
    Tamaas's error and iterations."""
    tm = _import_tamaas(1)
    n = height.shape[0]
    side = 2.0 * half_width
    dx = side / n
    x = -half_width + dx * (np.arange(n) + 0.5)
    face = np.hypot(x[:, None], x[None, :]) <= radius
    depth = 4.0 * (float(np.ptp(height)) + load / (contact_modulus * radius))
    surface = np.where(face, height, -depth)
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [side, side], [n, n])
    model.E = contact_modulus * (1.0 - poisson_ratio**2)
    model.nu = poisson_ratio
    tm.ModelFactory.registerNonPeriodic(model, "dcfft")
    solver = tm.PolonskyKeerRey(
        model, surface, tol, tm.PolonskyKeerRey.pressure, tm.PolonskyKeerRey.pressure
    )
    solver.setIntegralOperator("dcfft")
    solver.max_iter = max_iter
    solver.dump_freq = 2**31 - 1
    with _CaptureStderrFD() as cap:
        start = time.perf_counter()
        error = solver.solve(load / side**2)
        solve_time = time.perf_counter() - start
    pressure = np.array(model.traction, dtype=float, copy=True).reshape(n, n)
    elastic = np.zeros_like(pressure)
    model.operators["dcfft"](pressure, elastic)
    contact = pressure > 0.0
    shift = elastic[contact] - height[contact]
    return {
        "pressure": pressure,
        "contact": contact,
        "approach": float(shift.mean()),
        "face_residual": float(np.ptp(shift) / shift.mean()),
        "force": float(pressure.sum() * dx * dx),
        "solve_time_s": solve_time,
        "error": float(error),
        "converged": bool(error <= tol),
        "iterations": _iterations_from_log(cap.text, error <= tol),
        "tamaas_version": tm.__version__,
    }


def _main() -> None:  # pragma: no cover - benchmark driver
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 512])
    parser.add_argument(
        "--repeats", type=int, default=3, help="fresh solves per size; the table shows the fastest"
    )
    parser.add_argument("--tol", type=float, default=1e-8)
    parser.add_argument("--depth", type=float, default=None)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument(
        "--budget",
        type=float,
        default=120.0,
        help="skip n = 512 unless n = 256 predicts a solve under this (s)",
    )
    args = parser.parse_args()

    print(
        f"{'n':>5} {'setup s':>8} {'solve s':>9} {'iters':>6} {'tamaas err':>10} "
        f"{'force err':>10} {'approach/Sn-1':>13} {'face resid':>10} {'Sneddon dev':>11} "
        f"{'contact':>8}"
    )
    last = None
    for n in args.sizes:
        if n >= 512 and last is not None:
            # PKR iterations grow ~ n^0.5 and each costs ~ n² log n: predict conservatively
            predicted = last["solve_time_s"] * (n / last["n"]) ** 3
            if predicted > args.budget:
                print(f"{n:>5} skipped: predicted {predicted:.0f} s > budget {args.budget:.0f} s")
                continue
        runs = [
            solve_flat_punch_tamaas(n, tol=args.tol, depth=args.depth, threads=args.threads)
            for _ in range(max(1, args.repeats))
        ]
        res = min(runs, key=lambda d: d["solve_time_s"])
        last = res
        print(
            f"{n:>5} {res['setup_time_s']:>8.3f} {res['solve_time_s']:>9.4f} "
            f"{res['iterations']!s:>6} {res['error']:>10.2e} {res['force_rel_error']:>10.1e} "
            f"{res['approach'] / res['approach_sneddon'] - 1:>13.2e} "
            f"{res['face_residual']:>10.1e} {res['sneddon_max_rel_dev']:>11.4f} "
            f"{res['n_contact']:>8d}{'' if res['outside_contact'] == 0 else ' OUTSIDE!'}",
            flush=True,
        )
    if last is not None:
        print(
            f"tamaas {last['tamaas_version']} backend={last['tamaas_backend']} "
            f"threads={last['threads']} tol={args.tol:g} depth={last['depth']:.3e} mm "
            f"repeats={args.repeats} (min solve time shown)"
        )


if __name__ == "__main__":
    _main()
