"""Threshold searches at scale: 200 concurrent searches on 2, 4 and 8 ranks — do the ranks
stay busy while each search waits for its previous step?

Each rank count runs under ``mpiexec -n R`` (oversubscribed beyond the cores is fine: the
cases sleep, so the question is the scheduling alone): the engine's own machinery — the
scheduler with its open case queue, the searches (:class:`engine.searching.SearchRun`), the
single writer creating every step's group and writing its summary row to a real HDF5 file —
with synthetic cases in place of the solver: search ``i`` looks for the load at which a
Hertzian approach ``c_i P^(2/3)`` reaches a target (numeric column, Illinois, rtol 1e-4), and
a case sleeps 100–300 ms (``--case-ms``: the mean, 200 by default; deterministic per case)
before returning its row. Printed per rank count: cases, wall time, the end of the first
round (the 400 bracket ends), and the busy fraction (time holding a case / time) of every rank
after the first round — the target is ≥ 90 % on every rank — and over the whole run.
``--compare`` also runs, at each rank count, a plain sweep of about as many cases (nine loads
per combination, all known at the start): what the scheduler's own dispatch costs, which the
searches cannot beat.

    python benchmarks/bench_search_scale.py --compare              # 2, 4, 8 ranks; ~12 min
    python benchmarks/bench_search_scale.py --ranks 8 --searches 50

Other processes on the machine distort the figures (a sleeping case gives its core away, so
the load shows as dispatch latency, not as longer cases).
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

from _single_core import single_core_env

REPO = Path(__file__).resolve().parents[1]
LOW, HIGH, TARGET = 100.0, 2000.0, 1.0  # N, N, mm
CASE_SECONDS = 0.2  # mean duration of a synthetic case (--case-ms)


def spec():
    from engine.study.search import SearchSpec

    return SearchSpec("loading.load", LOW, HIGH, "approach", TARGET, rtol=1e-4)


def base_plan(searches: int):
    """One combination per search: mu1 distinct; the search's root spread over the bracket."""
    from engine.study.plan import Case, Plan

    cases = []
    for i in range(searches):
        mu = round(0.1 + 0.4 * i / searches, 8)
        cases.append(Case(i, f"mu{mu:.8g}_w0_b0", mu, mu, (("wear1", 0.0), ("wear2", 0.0)), 0.0))
    return Plan(tuple(cases))


def root_of(case) -> float:
    """The load (N) at which search ``case``'s approach reaches TARGET: spread over the
    bracket by mu1."""
    share = (case.mu1 - 0.1) / 0.4
    return LOW + (HIGH - LOW) * (0.05 + 0.9 * share)


def run_case(case, should_stop):
    """A synthetic step: sleep 0.5–1.5 × CASE_SECONDS, then the approach c P^(2/3) at the
    case's load."""
    from engine.study.case import CaseOutcome

    load = dict(case.settings)["loading.load"]
    start = time.time()
    phase = (zlib.crc32(case.case_id.encode()) % 1000) / 1000.0
    time.sleep(CASE_SECONDS * (0.5 + phase))
    coefficient = TARGET / root_of(case) ** (2.0 / 3.0)
    row = {**case.parameters(), "status": "completed", "approach": coefficient * load ** (2 / 3)}
    end = time.time()
    return CaseOutcome(
        case, "completed", row=row, attrs={"start": start, "end": end}, runtime_s=end - start
    )


class _Progress:
    def add(self, case) -> None:
        pass

    def count_searches(self, ended: int, searches: int) -> None:
        pass


def plain_cases(searches: int, per_search: int = 9) -> list:
    """The comparison without searches: ``per_search`` fixed loads for each combination, all
    known at the start (a closed queue), about as many cases as the searches take."""
    from engine.study.search import SearchCampaign

    campaign = SearchCampaign(spec(), base_plan(searches), ())
    loads = [LOW + (HIGH - LOW) * k / (per_search - 1) for k in range(per_search)]
    return [campaign.case_for(i, load) for i in range(searches) for load in loads]


def child(directory: Path, searches: int, plain: bool) -> None:
    """One run under mpiexec (every rank): rank 0 prints one JSON line."""
    from mpi4py import MPI

    from engine.output.hdf5 import SingleWriter, StudyMetadata
    from engine.parallel.scheduler import Scheduler
    from engine.searching import SearchRun
    from engine.study.search import SearchCampaign

    comm = MPI.COMM_WORLD
    scheduler = Scheduler(comm, run_case)
    if comm.Get_rank() != 0:
        scheduler.run()
        return
    campaign = SearchCampaign(spec(), base_plan(searches), ())
    todo = campaign.start()
    searches_run = SearchRun(campaign, None, todo)
    writer = SingleWriter(directory / f"scale_r{comm.Get_size()}_{int(plain)}.h5")
    metadata = StudyMetadata(
        name="scale",
        source="bench",
        study_toml="",
        study_json="{}",
        fingerprint="bench",
        command_line="bench",
        version="bench",
        grid_x=None,
        grid_y=None,
    )
    from engine.study.plan import Plan

    cases = plain_cases(searches) if plain else campaign.cases()
    writer.prepare(Plan(tuple(cases)), metadata, fresh=True)
    intervals = []

    def on_outcome(outcome) -> None:
        writer.write(outcome)
        first = len(intervals) < 2 * searches  # plain: as many cases as the bracket ends
        if not plain:
            first = dict(outcome.case.settings)["loading.load"] in (LOW, HIGH)
        intervals.append((outcome.rank, outcome.attrs["start"], outcome.attrs["end"], first))

    start = time.time()
    with writer:
        if plain:
            scheduler.run(cases, on_outcome)
        else:
            searches_run.run(scheduler, writer, _Progress(), on_outcome)
            searches_run.finish(writer)
    end = time.time()
    statuses = [row["status"] for row in campaign.table()]
    print(json.dumps({"intervals": intervals, "start": start, "end": end, "statuses": statuses}))


def busy_fractions(intervals, ranks: int, since: float, until: float) -> list[float]:
    """Per rank: the share of [since, until] it spent holding a case."""
    busy = [0.0] * ranks
    for rank, start, end, _ in intervals:
        busy[rank] += max(0.0, min(end, until) - max(start, since))
    return [value / (until - since) for value in busy]


def measure(ranks: int, searches: int, directory: Path, plain: bool = False) -> dict:
    mpiexec = shutil.which("mpiexec", path=str(Path(sys.executable).parent)) or "mpiexec"
    command = [mpiexec, "-n", str(ranks), sys.executable, __file__, "--child", str(directory)]
    command += ["--searches", str(searches), "--case-ms", str(1000 * CASE_SECONDS)]
    command += ["--plain"] if plain else []
    result = subprocess.run(
        command, capture_output=True, text=True, env=single_core_env(REPO), check=True
    )
    data = json.loads(result.stdout.strip().splitlines()[-1])
    intervals = data["intervals"]
    first_round = max(end for _, _, end, first in intervals if first)
    until = max(end for _, _, end, _ in intervals)
    return {
        "cases": len(intervals),
        "converged": data["statuses"].count("converged"),
        "wall": data["end"] - data["start"],
        "first_round": first_round - data["start"],
        "after": busy_fractions(intervals, ranks, first_round, until),
        "whole": busy_fractions(intervals, ranks, data["start"], until),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ranks", type=int, nargs="+", default=[2, 4, 8])
    parser.add_argument("--searches", type=int, default=200)
    parser.add_argument("--case-ms", type=float, default=200.0, help="mean case duration")
    parser.add_argument(
        "--compare", action="store_true", help="also run the same cases as a plain sweep"
    )
    parser.add_argument(
        "--update-docs", action="store_true",
        help="write the table into docs/explanation/searches.md (block bench-search-scale)",
    )  # fmt: skip
    parser.add_argument("--plain", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--child", type=Path, default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    global CASE_SECONDS
    CASE_SECONDS = args.case_ms / 1000.0
    if args.child is not None:
        child(args.child, args.searches, args.plain)
        return
    started = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    print(
        f"{started}, {platform.node()} ({platform.machine()}, {os.cpu_count()} cores, "
        f"load average {os.getloadavg()[0]:.1f})"
    )
    print(
        f"{args.searches} concurrent searches (rtol 1e-4, Illinois), synthetic cases of "
        f"{0.5 * args.case_ms:g}–{1.5 * args.case_ms:g} ms"
    )
    print(
        f"{'ranks':>5s} {'cases':>6s} {'conv.':>5s} {'wall s':>7s} {'1st round s':>11s} "
        f"{'busy after 1st round: min / mean':>33s} {'whole run: min':>15s}"
    )
    load = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for ranks, plain in [(r, p) for r in args.ranks for p in (False, True)[: 1 + args.compare]]:
            figures = measure(ranks, args.searches, Path(folder), plain)
            after, whole = figures["after"], figures["whole"]
            converged = "plain" if plain else f"{figures['converged']:5d}"
            print(
                f"{ranks:5d} {figures['cases']:6d} {converged:>5s} "
                f"{figures['wall']:7.2f} {figures['first_round']:11.2f} "
                f"{100 * min(after):26.1f} % / {100 * sum(after) / len(after):4.1f} % "
                f"{100 * min(whole):13.1f} %"
            )
            assert math.isfinite(figures["wall"])
            rows.append((
                ranks, "plain sweep" if plain else f"{args.searches} searches", figures["cases"],
                "–" if plain else figures["converged"], f"{figures['wall']:.1f}",
                f"{figures['first_round']:.1f}",
                f"{100 * min(after):.1f} % / {100 * sum(after) / len(after):.1f} %",
            ))  # fmt: skip
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    if args.update_docs:
        write_docs(rows, args, load)


def write_docs(rows, args, load: float) -> None:
    """The table, with the date, machine and load, into the how-to's generated block."""
    sys.path.insert(0, str(REPO))
    from engine.analysis.markdown import markdown_table, measured_on, replace_block

    header = (
        "ranks", "run", "cases", "converged", "wall (s)", "first round ends (s)",
        "busy after the first round, min / mean over ranks",
    )  # fmt: skip
    note = (
        f"load average {load:.1f} at the start; `python benchmarks/bench_search_scale.py "
        f"--update-docs`, synthetic cases of {0.5 * args.case_ms:g}–{1.5 * args.case_ms:g} ms"
    )
    text = measured_on(note) + "\n\n" + markdown_table(header, rows)
    replace_block(REPO / "docs" / "explanation" / "searches.md", "bench-search-scale", text)


if __name__ == "__main__":
    main()
