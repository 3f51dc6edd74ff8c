"""Worn states of the peak regime study: a test fixture, and the cycle-jump convergence table.

``fixture``: the states of ``studies/peak_regime_32.toml`` for μ = 0.1 at N = 10⁵ that the
region test (tests/test_peak_regions.py) classifies: i = 1.33e-6 1/MPa (ω_max/δ0 ≈ 0.5, just
past the transition, where the plane's surface layer on the axis is inflated by the traction
jump) and i = 1.33e-5 1/MPa (ω_max/δ0 ≈ 2.7, the long-wear limit: the unworn centre carries
the load), saved as peak-load pressure and tractions. Each is one case of that study run alone
(same settings, ``record = [100000]``).

``halving``: the case that wears most (μ = 0.1, i = 1.33e-5 1/MPa, 32²) with the default wear
allowed per cycle jump (``max_wear_fraction`` 0.004, as in ``peak_regime_32.toml``) and with
half of it (0.002, ``studies/peak_regime_halving_32.toml``): the wear, the σ_VM peaks and the
pressures of the two runs at the recorded cycles 10³, 10⁴ and 10⁵ (``history/``), their
relative differences, and the cycles at which the peak regions change. Without results files
it runs both cases from ``studies/peak_regime_halving_32.toml`` (one core, in a temporary
folder); with ``--default`` and ``--halved`` it reads them (the case of ``--default`` with
μ = 0.1, i = 1.33e-5 is taken, so ``results/peak_regime_32.h5`` serves). The figures are
differences of deterministic results, not times: the machine's load does not change them.

``final``: the final state of every case of a regime study's results file (wear severity,
wear depth, the region of the overall σ_VM peak and the cycle of its first change, the peaks
over p0 and where they are, the centre pressure), from the cases' summaries.

Run:  python scripts/peak_regime_states.py fixture WORN.h5 HEAVY.h5 \\
          tests/data/peak_regime_32_worn.npz
      python scripts/peak_regime_states.py halving --update-docs            # the two runs
      python scripts/peak_regime_states.py halving --default results/peak_regime_32.h5 \\
          --halved results/peak_regime_halving_32.h5 --update-docs
      python scripts/peak_regime_states.py final results/peak_regime_32.h5 --update-docs
"""

from __future__ import annotations

import argparse
import json
import math
import re
import tempfile
from pathlib import Path

import h5py
import numpy as np

REPO = Path(__file__).resolve().parent.parent
HALVING_STUDY = REPO / "studies" / "peak_regime_halving_32.toml"
DOCUMENT = REPO / "docs" / "explanation" / "peak-regime.md"
BLOCK = "peak-regime-halving"
MU, WEAR = 0.1, 1.33e-5  # the case compared (1, 1/MPa)
RECORDED = (1000, 10000, 100000)
#: (history column, title): the quantities compared at each recorded cycle.
QUANTITIES = (
    ("max_wear_depth", "max wear depth"),
    ("wear_volume", "wear volume"),
    ("vm_max", "σ_VM plane max"),
    ("vm_sub_max", "σ_VM below surface layer"),
    ("vm_deep_max", "σ_VM deep"),
    ("centre_pressure", "p(0)"),
    ("peak_pressure", "peak pressure"),
)


def peak_load_state(path: str, cycle: int = 100000) -> dict[str, np.ndarray]:
    """The recorded peak-load pressure and tractions (MPa) of the single case of ``path``,
    with its wear coefficient, maximum wear depth (mm) and unworn approach δ0 (mm)."""
    with h5py.File(path, "r") as file:
        (case,) = file["cases"].values()
        fields = case["fields"][f"cycle_{cycle:07d}"]
        summary = json.loads(case.attrs["summary"])
        return {
            "pressure": np.asarray(fields["pressure"]),
            "traction_x": np.asarray(fields["traction_x"]),
            "traction_y": np.asarray(fields["traction_y"]),
            "wear": np.asarray(float(case.attrs["wear1"])),
            "max_wear_depth": np.asarray(summary["max_wear_depth"]),
            "elastic_approach": np.asarray(summary["elastic_approach"]),
        }


def fixture(worn: str, heavy: str, out: str) -> None:
    arrays = {}
    for name, path in (("worn", worn), ("heavy", heavy)):
        arrays |= {f"{name}_{key}": value for key, value in peak_load_state(path).items()}
    np.savez_compressed(out, **arrays)
    print(f"{out}: {', '.join(sorted(arrays))}")


# ------------------------------------------------------------------------ cycle-jump halving
def case_history(path: str | Path) -> dict[str, np.ndarray]:
    """``history/`` of the case μ = 0.1, i = 1.33e-5 1/MPa of results file ``path`` (every
    column, one row per simulated cycle), with the case's ``elastic_approach`` δ0 (mm)."""
    with h5py.File(path, "r") as file:
        for case in file["cases"].values():
            summary = json.loads(case.attrs["summary"])
            if summary.get("status") != "completed":
                continue
            if np.isclose(summary["mu1"], MU) and np.isclose(summary["wear1"], WEAR):
                history = {name: np.asarray(column) for name, column in case["history"].items()}
                history["elastic_approach"] = np.asarray(summary["elastic_approach"])
                return history
    raise SystemExit(f"{path}: no completed case with mu1 = {MU}, wear1 = {WEAR}")


def first_change(history: dict[str, np.ndarray], column: str) -> int | None:
    """The real cycle N of the first simulated cycle whose region ``column`` differs from
    cycle 0's (None: it never changes)."""
    codes = history[column]
    changed = np.flatnonzero(codes != codes[0])
    return int(history["cycle"][changed[0]]) if changed.size else None


def first_on_axis(history: dict[str, np.ndarray]) -> int | None:
    """The real cycle N at which the deep peak (z ≥ 0.1 a0) is first classified on the axis."""
    from engine.solvers.peak import region_name

    for cycle, code in zip(history["cycle"], history["deep_region"], strict=True):
        if region_name(float(code)).startswith("axis"):
            return int(cycle)
    return None


def _row(history: dict[str, np.ndarray], cycle: int) -> int:
    rows = np.flatnonzero(history["cycle"] == cycle)
    if not rows.size:
        raise SystemExit(f"no simulated cycle at N = {cycle} (a recorded cycle of the study)")
    return int(rows[0])


def _percent(new: float, old: float) -> str:
    return f"{100.0 * (new / old - 1.0):+.2f} %".replace("-", "−")


def _cycles(value: int | None) -> str:
    return "never" if value is None else f"{value:,}"


def halving_table(default: dict[str, np.ndarray], halved: dict[str, np.ndarray]) -> str:
    """The Markdown of the comparison: one row per recorded cycle, then the region changes."""
    from engine.analysis.markdown import markdown_table

    rows = []
    for cycle in RECORDED:
        old, new = _row(default, cycle), _row(halved, cycle)
        severity = default["max_wear_depth"][old] / default["elastic_approach"]
        rows.append(
            [f"{cycle:,}", f"{severity:.2f}"]
            + [_percent(halved[name][new], default[name][old]) for name, _ in QUANTITIES]
        )
    header = ["at N", "ω_max/δ0 (default)"] + [title for _, title in QUANTITIES]
    lines = [markdown_table(header, rows)]
    changes = [
        ("first change of the peak region", first_change(default, "peak_region"),
         first_change(halved, "peak_region")),
        ("the deep peak first on the axis", first_on_axis(default), first_on_axis(halved)),
    ]  # fmt: skip
    lines.append("| event | N, default | N, halved | halved − default |")
    lines.append("| --- | --- | --- | --- |")
    for title, old, new in changes:
        difference = "–" if old is None or new is None else _percent(new, old)
        lines.append(f"| {title} | {_cycles(old)} | {_cycles(new)} | {difference} |")
    simulated = (len(default["cycle"]), len(halved["cycle"]))
    lines.append(f"\nSimulated cycles: {simulated[0]} (default) and {simulated[1]} (halved).")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------ final states
def final_table(path: str | Path) -> tuple[str, str]:
    """(block name, Markdown) of the final states of a peak regime study's results ``path``:
    one row per completed case (μ, i), from its summary. a0 is ``[punch] radius``."""
    from engine.analysis.markdown import markdown_table
    from engine.solvers.peak import REGIONS

    with h5py.File(path, "r") as file:
        study = json.loads(file.attrs["study_json"])
        summaries = [json.loads(case.attrs["summary"]) for case in file["cases"].values()]
    done = sorted(
        (row for row in summaries if row.get("status") == "completed"),
        key=lambda row: (row["mu1"], row["wear1"]),
    )
    if not done:
        raise SystemExit(f"{path}: no completed case")
    radius, name = float(study["punch"]["radius"]), study["study"]["name"]
    rows = []
    for row in done:
        p0, change = row["p0"], row.get("peak_region_change_cycle")
        region = row["peak_region"] if row["peak_region"] in REGIONS else "–"
        when = f" ({int(change):,})" if change not in (None, -1) and math.isfinite(change) else ""
        rows.append([
            f"{row['mu1']:g}", f"{row['wear1']:.3g}", f"{row['wear_severity']:.3f}",
            f"{row['max_wear_depth'] * 1e3:.3f}", f"{region}{when}",
            f"{row['vm_max'] / p0:.2f} ({row['vm_max_x'] / radius:+.2f})",
            f"{row['vm_deep_max'] / p0:.2f} ({row['vm_deep_max_x'] / radius:+.2f}, "
            f"{row['vm_deep_max_z'] / radius:.2f})",
            f"{row['centre_pressure'] / p0:.2f}",
        ])  # fmt: skip
    header = [
        "μ", "i (1/MPa)", "ω_max/δ0", "ω_max (µm)", "overall peak: region (first change N)",
        "σ_VM/p0 there (x/a0)", "deep peak σ_VM/p0 (x/a0, z/a0)", "p(0)/p0",
    ]  # fmt: skip
    approaches = {}
    for row in done:
        approaches.setdefault(row["mu1"], row["elastic_approach"])
    unworn = ", ".join(f"{value * 1e3:.3f} µm for μ = {mu:g}" for mu, value in approaches.items())
    cycles, n = int(done[0]["cycles"]), int(study["mesh"]["n"])
    text = (
        f"Final states at N = {cycles:,}, {n}² (`{path}`): ω_max/δ0 is the maximum wear depth "
        f"over the unworn approach δ0 ({unworn}); σ_VM over p0 = {done[0]['p0']:.1f} MPa.\n\n"
        + markdown_table(header, rows)
    )
    return f"{name.replace('_', '-')}-final", text


def final(path: str, update_docs: bool) -> None:
    from engine import __version__

    block, table = final_table(path)
    note = (
        f"`python scripts/peak_regime_states.py final {path} --update-docs`, engine "
        f"{__version__}: the summary of every case (deterministic results: the load does "
        "not change them)"
    )
    _publish(block, table, note, update_docs)


def _publish(block: str, table: str, note: str, update_docs: bool) -> None:
    """Print ``table``; with ``update_docs``, write it into the block ``block`` of the
    peak-regime page under ``note`` (how it was obtained)."""
    print(table)
    if update_docs:
        from engine.analysis.markdown import measured_on, replace_block

        replace_block(DOCUMENT, block, f"{measured_on(note)}\n{table}")
        print(f"{DOCUMENT}: wrote the block {block}")


# ------------------------------------------------------------------------ the path
PATH_FRICTION = (0.1, 0.2)  # the μ whose cases pass the transition
PATH_WEAR = 1.33e-6  # 1/MPa: the case whose history the track table follows
TRACK = (0.35, 0.56)  # ω_max/δ0: the rows of the track table


def _histories(path: str | Path) -> tuple[dict, list[tuple[dict, dict]]]:
    """(resolved study, [(summary, history columns)]) of the completed cases of ``path``."""
    with h5py.File(path, "r") as file:
        study = json.loads(file.attrs["study_json"])
        cases = []
        for case in file["cases"].values():
            summary = json.loads(case.attrs["summary"])
            if summary.get("status") == "completed":
                history = {name: np.asarray(column) for name, column in case["history"].items()}
                cases.append((summary, history))
    return study, sorted(cases, key=lambda item: (item[0]["mu1"], item[0]["wear1"]))


def path_table(path: str | Path) -> tuple[str, str]:
    """(block name, Markdown) of the path in ω_max/δ0 of a regime study's results ``path``:
    for each case of μ ∈ PATH_FRICTION that changes region, the severity at the first
    simulated cycle of each region of the overall peak; then the track of the deep peak of
    the case μ = 0.1, i = PATH_WEAR over the transition (every simulated cycle with
    ω_max/δ0 in TRACK)."""
    from engine.analysis.markdown import markdown_table
    from engine.solvers.peak import region_name

    study, cases = _histories(path)
    radius, name, n = float(study["punch"]["radius"]), study["study"]["name"], study["mesh"]["n"]
    rows, track = [], []
    for summary, history in cases:
        severity = history["max_wear_depth"] / summary["elastic_approach"]
        codes = history["peak_region"]
        starts = [0, *np.flatnonzero(codes[1:] != codes[:-1]) + 1]
        if summary["mu1"] in PATH_FRICTION and len(starts) > 1:
            steps = [region_name(float(codes[0]))] + [
                f"{region_name(float(codes[k]))} at {severity[k]:.3f}" for k in starts[1:]
            ]
            rows.append([f"{summary['mu1']:g}", f"{summary['wear1']:.3g}", " → ".join(steps)])
        if np.isclose(summary["mu1"], 0.1) and np.isclose(summary["wear1"], PATH_WEAR):
            p0 = summary["p0"]
            inside = np.flatnonzero((severity >= TRACK[0]) & (severity <= TRACK[1]))
            where = np.stack([np.abs(history["vm_deep_max_x"]), history["vm_deep_max_z"],
                              history["deep_region"], codes])  # fmt: skip
            for k in inside:  # the first and last rows, and those where the peak moves
                if k not in (inside[0], inside[-1]) and np.array_equal(
                    where[:, k], where[:, k - 1]
                ):
                    continue
                track.append([
                    f"{int(history['cycle'][k]):,}", f"{severity[k]:.3f}",
                    f"{history['vm_deep_max'][k] / p0:.3f}",
                    f"{abs(history['vm_deep_max_x'][k]) / radius:.2f}",
                    f"{history['vm_deep_max_z'][k] / radius:.3f}",
                    region_name(float(history["deep_region"][k])),
                    region_name(float(codes[k])),
                    f"{history['centre_pressure'][k] / p0:.2f}",
                ])  # fmt: skip
    text = (
        f"{n}² (`{path}`): the overall peak's region from cycle 0 and the wear severity "
        "ω_max/δ0 at the first simulated cycle of each later region:\n\n"
        + markdown_table(["μ", "i (1/MPa)", "regions along the history"], rows)
    )
    if track:
        text += (
            f"\nThe deep peak (z ≥ 0.1 a0) of μ = 0.1, i = {PATH_WEAR:g} 1/MPa over "
            f"ω_max/δ0 ∈ [{TRACK[0]}, {TRACK[1]}]: the first and last simulated cycles and "
            "each at which the peak or a region moves (σ_VM over p0):\n\n"
            + markdown_table(
                [
                    "N",
                    "ω_max/δ0",
                    "deep σ_VM/p0",
                    "its |x|/a0",
                    "its z/a0",
                    "deep region",
                    "overall region",
                    "p(0)/p0",
                ],
                track,
            )  # fmt: skip
        )
    return f"{name.replace('_', '-')}-path", text


def path_block(path: str, update_docs: bool) -> None:
    from engine import __version__

    block, table = path_table(path)
    note = (
        f"`python scripts/peak_regime_states.py path {path} --update-docs`, engine "
        f"{__version__}: the peak history of the cases (deterministic results: the load "
        "does not change them)"
    )
    _publish(block, table, note, update_docs)


def _run_both(folder: Path) -> tuple[Path, Path]:
    """Run the compared case with the default and with half the wear per jump; the results
    files, in ``folder``."""
    import engine

    text = HALVING_STUDY.read_text()
    outputs = []
    for name, fraction in (("default", None), ("halved", "0.002")):
        output = folder / f"{name}.h5"
        study = re.sub(r'(?m)^output = ".*"$', f'output = "{output}"', text)
        study = re.sub(r"(?m)^max_wear_fraction = .*$", "", study)
        if fraction is not None:
            study = study.replace("[subsurface]", f"max_wear_fraction = {fraction}\n\n[subsurface]")
        run = engine.run_study(study, progress=False)
        if not run.ok:
            raise SystemExit(f"the {name} run did not complete: {run.status} {run.message}")
        outputs.append(output)
    return outputs[0], outputs[1]


def halving(default: str | None, halved: str | None, update_docs: bool) -> None:
    from engine import __version__

    if (default is None) != (halved is None):
        raise SystemExit("give both --default and --halved, or neither (to run both cases)")
    with tempfile.TemporaryDirectory() as scratch:
        if default is None:
            paths = _run_both(Path(scratch))
            how = (
                f"the case μ = {MU}, i = {WEAR:g} 1/MPa of `studies/peak_regime_halving_32.toml` "
                "run twice, with `max_wear_fraction` 0.004 (the default, as in "
                "`peak_regime_32.toml`) and 0.002"
            )
        else:
            paths = (Path(default), Path(halved))
            how = f"the case μ = {MU}, i = {WEAR:g} 1/MPa of `{default}` and of `{halved}`"
        table = halving_table(case_history(paths[0]), case_history(paths[1]))
    arguments = "" if default is None else f" --default {default} --halved {halved}"
    command = f"`python scripts/peak_regime_states.py halving{arguments} --update-docs`"
    note = (
        f"{command}, engine {__version__}: {how}; relative differences halved − default "
        "(deterministic results: the load does not change them)"
    )
    _publish(BLOCK, table, note, update_docs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    states = commands.add_parser("fixture", help="save the two worn states (.npz)")
    states.add_argument("worn", help="results of μ = 0.1, i = 1.33e-6 (32², 10⁵ cycles)")
    states.add_argument("heavy", help="results of μ = 0.1, i = 1.33e-5 (32², 10⁵ cycles)")
    states.add_argument("out", help="the .npz to write")
    table = commands.add_parser("halving", help="the cycle-jump convergence table")
    table.add_argument("--default", help="results holding the case with the default jumps")
    table.add_argument("--halved", help="results of studies/peak_regime_halving_32.toml")
    table.add_argument(
        "--update-docs", action="store_true",
        help=f"write the table into docs/explanation/peak-regime.md ({BLOCK})",
    )  # fmt: skip
    states = commands.add_parser("final", help="the final-state table of a regime study")
    states.add_argument("results", help="results/peak_regime.h5 or results/peak_regime_32.h5")
    states.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/peak-regime.md (<study>-final)",
    )  # fmt: skip
    states = commands.add_parser("path", help="the regions along the histories, the track")
    states.add_argument("results", help="results/peak_regime.h5 or results/peak_regime_32.h5")
    states.add_argument(
        "--update-docs", action="store_true",
        help="write the tables into docs/explanation/peak-regime.md (<study>-path)",
    )  # fmt: skip
    args = parser.parse_args()
    if args.command == "path":
        path_block(args.results, args.update_docs)
        return
    if args.command == "fixture":
        fixture(args.worn, args.heavy, args.out)
    elif args.command == "final":
        final(args.results, args.update_docs)
    else:
        halving(args.default, args.halved, args.update_docs)


if __name__ == "__main__":
    main()
