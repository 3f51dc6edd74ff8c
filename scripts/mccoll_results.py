"""The McColl, Ding & Leen (2004) line-contact study at two loads, into the docs.

Runs, with ``mpiexec -n RANKS python -m engine`` (a results file is resumed when it exists):

- ``studies/mccoll_2004_convergence.toml``: the bundled ``studies/mccoll_2004.toml`` case
  (P = 185 N/mm) on 128, 256 and 512 elements over ±1 mm, each with the bundled wear per
  cycle jump, half and a quarter of it;
- ``studies/mccoll_2004_test_load_convergence.toml``: the bundled
  ``studies/mccoll_2004_test_load.toml`` case (P = 18.5 N/mm, the paper's 185 N over a 10 mm
  long contact) on 128, 256 and 512 elements over ±0.5 mm;

reads the wear fields recorded at 1,000, 5,000, 10,000 and 18,000 cycles and writes these
blocks of docs/explanation/results.md, each headed by the date, machine and load:

- ``mccoll-2004`` and ``mccoll-2004-test-load``: the flat's scar depth, width (where its wear
  exceeds 1 % of the depth) and worn area, and the cylinder's wear depth, of each bundled
  study's settings (256 elements, max_wear_fraction 0.004), with the energy-law cross-check:
  under gross slip the worn area of the flat equals k/μ × the dissipated energy (Archard's
  k p s = (k/μ) q s, q = μp on every slipping point).
- ``mccoll-2004-measured``: both loads' numbers beside the scar measured at 18,000 cycles
  (``MEASURED``), with the ratio computed / measured.
- ``mccoll-2004-convergence`` and ``mccoll-2004-test-load-convergence``: per case the
  solver's work and accuracy (simulated cycles, median cycle jump, operator applications per
  simulated cycle, the largest relative residual of any increment, CPU time) and the
  element-scale ripple of the worn profile at 18,000 cycles; then the relative change of the
  scar numbers with the mesh and the wear per cycle jump against the bundled settings.

    python scripts/mccoll_results.py            # 2 ranks
    python scripts/mccoll_results.py --ranks 1 --fresh
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np
from scipy.signal import savgol_filter

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from engine.analysis.markdown import markdown_table, measured_on, replace_block  # noqa: E402
from engine.grid import Grid  # noqa: E402
from engine.solvers.scar import scar_measures  # noqa: E402

DOCUMENT = REPO / "docs" / "explanation" / "results.md"
CYCLES = (1000, 5000, 10000, 18000)
BUNDLED = (256, 0.004)  # elements, max_wear_fraction of both bundled studies
PAD_RATIO = 1.0  # k_pad / k_flat: both 2.75e-8 1/MPa
WEAR_COEFFICIENT = 2.75e-8  # 1/MPa
FRICTION = 0.9
#: The flat's scar at 18,000 cycles read off the profile of the paper's Fig. 11a as digitised
#: in the LevelSetWear repository (figures/fig16_fretting_mccoll/measured_mccoll2004.csv):
#: depth (mm), width (mm, where the trace leaves the unworn line) and worn area (mm²/mm).
MEASURED = {"scar_depth": 2.9e-3, "scar_width": 0.60, "scar_area": 1.0e-3}
MEASURED_CYCLES = 18000


@dataclass(frozen=True)
class Load:
    """One load of the test: its convergence study (whose case with the ``BUNDLED`` settings
    is the bundled study's), the half-width of its mesh (mm) and its blocks."""

    load: float  # N/mm
    bundled_study: str
    study: str
    half_width: float
    block: str

    @property
    def study_path(self) -> Path:
        return REPO / "studies" / f"{self.study}.toml"

    @property
    def results(self) -> Path:
        return REPO / "results" / f"{self.study}.h5"


LOADS = (
    Load(18.5, "mccoll_2004_test_load", "mccoll_2004_test_load_convergence", 0.5,
         "mccoll-2004-test-load"),
    Load(185.0, "mccoll_2004", "mccoll_2004_convergence", 1.0, "mccoll-2004"),
)  # fmt: skip
RIPPLE_WINDOW = 9  # elements of the local cubic fit that the ripple is measured against


def completed_cases(results: Path) -> int:
    """How many cases of a results file are complete (0 without the file)."""
    if not results.exists():
        return 0
    with h5py.File(results, "r") as file:
        return sum(group.attrs["status"] == "completed" for group in file["cases"].values())


def run_study(load: Load, ranks: int, fresh: bool) -> float | None:
    """Run (or resume) a load's study; returns the wall time (s) of the command, or None when
    the results file already held every case complete (nothing was computed, so no time)."""
    import time

    study = load.study_path
    sweep = tomllib.loads(study.read_text())["sweep"]
    cases = math.prod(len(values) for values in sweep.values())
    already_complete = not fresh and completed_cases(load.results) == cases
    mpiexec = Path(sys.executable).parent / "mpiexec"
    command = [str(mpiexec), "-n", str(ranks), sys.executable, "-m", "engine", str(study)]
    command += ["--no-progress-bar", "--progress-interval", "60"] + (["--fresh"] if fresh else [])
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    start = time.perf_counter()
    completed = subprocess.run(command, cwd=REPO, env=env)
    if completed.returncode not in (0, 1):  # 1: a case failed, reported in the table
        raise SystemExit(f"the study stopped with exit code {completed.returncode}")
    return None if already_complete else time.perf_counter() - start


def element_ripple(wear: np.ndarray) -> float:
    """The element-scale roughness of a worn profile (mm): the largest deviation, where the
    wear exceeds 30 % of its depth, from a local cubic least-squares fit over
    ``RIPPLE_WINDOW`` elements (Savitzky–Golay). A smooth scar leaves ~0 (the fit is exact
    to the profile's fourth derivative); an oscillation from element to element stays."""
    inside = wear > 0.3 * wear.max()
    return float(np.abs(wear - savgol_filter(wear, RIPPLE_WINDOW, 3))[inside].max())


def solver_measures(group) -> dict:
    """Per case: simulated cycles, median cycle jump, operator applications per simulated
    cycle (mean and largest), the largest relative residual of any increment of the
    simulated cycles, and the element-scale ripple of the total wear at the last cycle."""
    history = group["history"]
    matvecs = history["matvecs"][...]
    final = group[f"fields/cycle_{CYCLES[-1]:07d}/wear"][...][:, 0]
    return {
        "median_jump": float(np.median(history["jump"][...])),
        "matvecs_mean": float(matvecs.mean()),
        "matvecs_max": float(matvecs.max()),
        "residual": float(history["residual"][...].max()),
        "ripple": element_ripple(final),
    }


def case_measures(results: Path, half_width: float) -> dict[tuple[int, float], dict]:
    """Per case (elements, wear fraction): the scar measures at each recorded cycle, the
    cumulated dissipated energy (N·mm/mm), the solver's measures (``solver_measures``) and
    the case's CPU time (s)."""
    measures = {}
    with h5py.File(results, "r") as file:
        for group in file["cases"].values():
            n = int(group.attrs["mesh.n"])  # the swept keys are attributes of the case
            fraction = float(group.attrs["loading.max_wear_fraction"])
            if group.attrs["status"] != "completed":
                measures[(n, fraction)] = {"failed": str(group.attrs["message"])}
                continue
            grid = Grid.line(n, half_width)
            by_cycle = {
                cycle: scar_measures(
                    grid, group[f"fields/cycle_{cycle:07d}/wear"][...], PAD_RATIO
                ).row()
                for cycle in CYCLES
            }
            history = group["history"]
            cycles = history["cycle"][...]
            energy = np.cumsum(history["jump"][...] * history["energy"][...])
            for cycle in CYCLES:
                by_cycle[cycle]["energy"] = float(np.interp(cycle, cycles, energy))
            measures[(n, fraction)] = {
                "cycles": by_cycle,
                "cpu_s": float(group.attrs.get("cpu_s", float("nan"))),
                "simulated": int(cycles.size),
                **solver_measures(group),
            }
    return measures


def column_table(columns, items, failed=None) -> str:
    """A markdown table of ``columns`` ((header, format of an item), …) over ``items``;
    ``failed(item)``: the row of an item that has no values (None: every item has them)."""
    header = tuple(name for name, _ in columns)
    rows = []
    for item in items:
        row = failed(item) if failed is not None else None
        rows.append(row or tuple(f(item) for _, f in columns))
    return markdown_table(header, rows)


# A recorded cycle of a case: (cycle, its scar measures and dissipated energy).
RESULT_COLUMNS = (
    ("cycles", lambda item: f"{item[0]:,}"),
    ("scar_depth (µm)", lambda item: f"{item[1]['scar_depth'] * 1e3:.3f}"),
    ("scar_width (mm)", lambda item: f"{item[1]['scar_width']:.3f}"),
    ("scar_area (mm²/mm)", lambda item: f"{item[1]['scar_area']:.4e}"),
    ("pad_wear_depth (µm)", lambda item: f"{item[1]['pad_wear_depth'] * 1e3:.3f}"),
    (
        "k/μ × dissipated energy (mm²/mm)",
        lambda item: f"{WEAR_COEFFICIENT / FRICTION * item[1]['energy']:.4e}",
    ),
)

# A case of the convergence study: ((elements, max_wear_fraction), how it ran).
SOLVER_COLUMNS = (
    ("elements", lambda item: item[0][0]),
    ("max_wear_fraction", lambda item: f"{item[0][1]:g}"),
    ("simulated cycles", lambda item: f"{item[1]['simulated']:,}"),
    ("median jump", lambda item: f"{item[1]['median_jump']:g}"),
    (
        "operator applications per cycle (mean / max)",
        lambda item: f"{item[1]['matvecs_mean']:.0f} / {item[1]['matvecs_max']:.0f}",
    ),
    ("largest residual", lambda item: f"{item[1]['residual']:.1e}"),
    ("CPU (s)", lambda item: f"{item[1]['cpu_s']:.1f}"),
    ("ripple at 18,000 cycles (nm)", lambda item: f"{item[1]['ripple'] * 1e6:.1f}"),
)


def results_table(case: dict) -> str:
    return column_table(RESULT_COLUMNS, case["cycles"].items())


def solver_table(measures: dict) -> str:
    """Per case: how it ran (or the message of a failed case)."""

    def failed(item):
        (n, fraction), case = item
        if "failed" in case:
            return (n, f"{fraction:g}", f"failed: {case['failed']}", "", "", "", "", "")
        return None

    return column_table(SOLVER_COLUMNS, sorted(measures.items()), failed)


def convergence_table(measures: dict) -> str:
    """Relative change of each measure against the bundled case, per variant and cycle."""
    reference = measures[BUNDLED]["cycles"]
    header = ("variant", "cycles", "scar_depth", "scar_width", "scar_area", "pad_wear_depth")
    rows = []
    for key in sorted(measures):
        if key == BUNDLED:
            continue
        n, fraction = key
        label = f"{n} elements, max_wear_fraction {fraction:g}"
        if "failed" in measures[key]:
            rows.append((label, "–", "failed (above)", "", "", ""))
            continue
        for cycle in CYCLES:
            values = measures[key]["cycles"][cycle]
            changes = [
                f"{values[name] / reference[cycle][name] - 1:+.2%}"
                for name in ("scar_depth", "scar_width", "scar_area", "pad_wear_depth")
            ]
            rows.append((label, f"{cycle:,}", *changes))
    return markdown_table(header, rows)


def measured_table(bundled: dict[float, dict]) -> str:
    """Per load (N/mm) the bundled settings' scar at each recorded cycle, the measured scar,
    and at the measured cycle count the ratio computed / measured of each load."""
    names = ("scar_depth", "scar_width", "scar_area")
    header = (
        "source", "cycles", "scar depth (µm)", "scar width (mm)", "worn area (mm²/mm)",
        "cylinder wear depth (µm)",
    )  # fmt: skip

    def row(source: str, cycle: int, values: dict) -> tuple:
        return (
            source,
            f"{cycle:,}",
            f"{values['scar_depth'] * 1e3:.2f}",
            f"{values['scar_width']:.3f}",
            f"{values['scar_area']:.2e}",
            f"{values['pad_wear_depth'] * 1e3:.2f}",
        )

    rows = []
    for load, case in bundled.items():
        rows += [row(f"computed, {load:g} N/mm", c, v) for c, v in case["cycles"].items()]
    rows.append(
        (
            "measured (Fig. 11a, digitised)",
            f"{MEASURED_CYCLES:,}",
            f"{MEASURED['scar_depth'] * 1e3:.1f}",
            f"{MEASURED['scar_width']:.2f}",
            f"{MEASURED['scar_area']:.1e}",
            "not in the source",
        )
    )
    for load, case in bundled.items():
        values = case["cycles"][MEASURED_CYCLES]
        ratios = [f"{values[name] / MEASURED[name]:.2f}" for name in names]
        rows.append((f"computed / measured, {load:g} N/mm", f"{MEASURED_CYCLES:,}", *ratios, "–"))
    return markdown_table(header, rows)


def write_blocks(load: Load, measures: dict, timing: str) -> None:
    """The bundled settings' table and the convergence tables of one load."""
    bundled = measures[BUNDLED]
    note = (
        f"`python scripts/mccoll_results.py`: P = {load.load:g} N/mm, 256 elements over "
        f"±{load.half_width:g} mm, max_wear_fraction 0.004 (studies/{load.bundled_study}.toml), "
        f"{bundled['simulated']} simulated cycles, {bundled['cpu_s']:.1f} s of CPU{timing}"
    )
    replace_block(DOCUMENT, load.block, measured_on(note) + "\n" + results_table(bundled))
    note = (
        f"`python scripts/mccoll_results.py`{timing}; every increment to the relative "
        "residual 1e-6 ([solver] tol), the changes against 256 elements, 0.004"
    )
    block = "\n".join((measured_on(note), solver_table(measures), "", convergence_table(measures)))
    replace_block(DOCUMENT, f"{load.block}-convergence", block)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--fresh", action="store_true", help="recompute the study")
    parser.add_argument("--no-run", action="store_true", help="only read existing results")
    args = parser.parse_args()
    bundled = {}
    for load in LOADS:
        wall = None if args.no_run else run_study(load, args.ranks, args.fresh)
        measures = case_measures(load.results, load.half_width)
        count = len(measures)
        timing = (
            f"; the study {load.study} ({count} cases) took {wall:.0f} s on {args.ranks} ranks"
            if wall is not None
            else f"; read from the complete results/{load.study}.h5 (CPU times of its run)"
        )
        write_blocks(load, measures, timing)
        bundled[load.load] = measures[BUNDLED]
    note = (
        "`python scripts/mccoll_results.py`: the bundled settings of both loads (tables "
        f"above) beside the flat's scar measured at {MEASURED_CYCLES:,} cycles"
    )
    replace_block(
        DOCUMENT, "mccoll-2004-measured", measured_on(note) + "\n" + measured_table(bundled)
    )
    blocks = ", ".join(f"{load.block}, {load.block}-convergence" for load in LOADS)
    print(f"{DOCUMENT}: wrote the blocks {blocks}, mccoll-2004-measured")


if __name__ == "__main__":
    main()
