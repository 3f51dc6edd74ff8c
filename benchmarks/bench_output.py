"""Output strategies side by side: single writer (rank 0) vs collective mpio, 2 ranks.

Each case is a real static flat-punch solve at ``--n``² (default 128², P = 750 N) with its
x–z plane stresses, plus the full 3-D stress block ``(n, n, n_z)`` at the final load (seven
float64 arrays: six components and von Mises, Eq. 21) — the large-field case where output
matters. Both strategies run the same cases through the engine's scheduler and writers
(engine.output.hdf5.SingleWriter, engine.output.collective.CollectiveWriter) in one session,
alternating, ``--repeat`` times; the best run of each is reported: wall time of the run, time
spent writing (sum over ranks of the time inside the writers: for the single writer rank 0's
``write`` — the transfer of the arrays to rank 0 is in the wall time only; for mpio the
independent writes of each rank plus the collective prepare/commit), and its share of the run.

    mpiexec.mpich -n 2 .venv-mpio/bin/python benchmarks/bench_output.py      # both strategies
    mpiexec -n 2 .venv/bin/python benchmarks/bench_output.py                 # single only

About 2–3 minutes here at the defaults (4 cases, 16 layers, 2 repeats). The figures depend on
the file system and on other processes on the machine.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))


def study_text(output: str, n: int, layers: int, mu1: list[float]) -> str:
    """Static cases (P = 750 N, 2 increments) on an n x n mesh with ``layers`` depth layers."""
    from engine.study.examples import study_toml

    return study_toml(
        "bench_output",
        output,
        mesh={"n": n},
        loading={"kind": "static"},
        subsurface={"layers": layers},
        sweep={"mu1": mu1},
    )


BLOCK = ("xx", "yy", "zz", "xy", "xz", "yz")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=128)
    parser.add_argument("--layers", type=int, default=16)
    parser.add_argument("--cases", type=int, default=4)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()

    from mpi4py import rc

    rc.thread_level = "funneled"
    from mpi4py import MPI

    from engine.output.collective import h5py_is_mpi_enabled
    from engine.study.config import parse_study

    comm = MPI.COMM_WORLD
    directory = comm.bcast(tempfile.mkdtemp(prefix="bench_output_") if comm.rank == 0 else None)
    mu1 = [float(f"{0.1 + 0.1 * k:.1f}") for k in range(args.cases)]
    text = study_text(f"{directory}/out.h5", args.n, args.layers, mu1)
    config = parse_study(text, source="bench_output")
    strategies = ["single"] + (["mpio"] if h5py_is_mpi_enabled() else [])
    best: dict[str, dict[str, float]] = {}
    for _ in range(args.repeat):
        for strategy in strategies:
            result = run(comm, config, strategy, Path(directory) / f"{strategy}.h5")
            if strategy not in best or result["wall"] < best[strategy]["wall"]:
                best[strategy] = result
    if comm.rank == 0:
        report(args, best, comm.size)
        shutil.rmtree(directory, ignore_errors=True)


def run(comm, config, strategy: str, path: Path) -> dict[str, float]:
    """One study run with ``strategy``; returns wall time, writing time, bytes written."""
    from engine.output.collective import CollectiveWriter
    from engine.output.hdf5 import SingleWriter, remove_outputs
    from engine.parallel.scheduler import Scheduler
    from engine.study.plan import make_plan

    plan = make_plan(config)
    metadata = _metadata(config)
    run_case, layout = block_runner(config)
    if comm.rank == 0:
        remove_outputs(path, path.with_name(path.name + ".checkpoints"))
    comm.Barrier()
    start = time.perf_counter()
    if strategy == "single":
        scheduler = Scheduler(comm, run_case)
        written = 0.0
        if comm.rank == 0:
            with SingleWriter(path) as writer:
                writer.prepare(plan, metadata, fresh=True)

                def on_outcome(outcome):
                    nonlocal written
                    t = time.perf_counter()
                    writer.write(outcome)
                    written += time.perf_counter() - t

                scheduler.run(plan.dispatch_order(), on_outcome)
        else:
            scheduler.run()
        writing = comm.allreduce(written)
        structure = 0.0
    else:
        writer = CollectiveWriter(path, comm, layout, journal_dir=path.parent / "journal")
        writer.prepare(plan, metadata, fresh=True)
        scheduler = Scheduler(comm, run_case if comm.rank == 0 else writer.owner(run_case))
        if comm.rank == 0:
            scheduler.run(plan.dispatch_order(), writer.write)
        else:
            scheduler.run()
        writer.close()
        structure = comm.allreduce(writer.commit_seconds)
        writing = writer.write_seconds_total + structure
    comm.Barrier()
    wall = time.perf_counter() - start
    size = path.stat().st_size if comm.rank == 0 else 0
    return {"wall": wall, "writing": writing, "structure": structure, "bytes": size}


def block_runner(config):
    """The engine's case runner plus the 3-D stress block of the final state."""
    from engine.study.case import COMPLETED, CaseRunner, DatasetRecord
    from engine.study.layout import DatasetShape, case_layout

    runner = CaseRunner(config)
    layout = case_layout(config)
    n_z = config.subsurface.layers
    for name in (*BLOCK, "von_mises"):
        key = f"subsurface/block/{name if name == 'von_mises' else 'sigma_' + name}"
        layout[key] = DatasetShape((config.mesh.n, config.mesh.n, n_z), "float64")

    def run_case(case, should_stop):
        outcome = runner(case, should_stop)
        if outcome.status != COMPLETED:
            return outcome
        from engine.grid import Grid
        from engine.solvers.subsurface import SubsurfaceStress, depth_layers

        grid = Grid.square(config.mesh.n, config.mesh.half_width)
        depths = depth_layers(config.subsurface.depth * config.punch.radius, n_z)
        stress = SubsurfaceStress(grid, config.material.nu_A, np.asarray(depths, dtype=float))
        final = [outcome.datasets[f"fields/final/{k}"].data for k in ("pressure", "traction_x")]
        final.append(outcome.datasets["fields/final/traction_y"].data)
        block = stress.block(*final)
        for name in BLOCK:
            outcome.datasets[f"subsurface/block/sigma_{name}"] = DatasetRecord(
                np.ascontiguousarray(block.components[name]), "MPa", f"stress {name}, 3-D block"
            )
        outcome.datasets["subsurface/block/von_mises"] = DatasetRecord(
            np.ascontiguousarray(block.von_mises), "MPa", "von Mises stress, 3-D block"
        )
        return outcome

    return run_case, layout


def _metadata(config):
    from engine.grid import Grid
    from engine.output.hdf5 import StudyMetadata

    grid = Grid.square(config.mesh.n, config.mesh.half_width)
    return StudyMetadata(
        name=config.study.name,
        source=config.source,
        study_toml=config.to_toml(),
        study_json=config.to_json(),
        fingerprint=config.fingerprint(),
        command_line="benchmarks/bench_output.py",
        version="bench",
        grid_x=grid.x,
        grid_y=grid.y,
    )


def report(args, best: dict[str, dict[str, float]], ranks: int) -> None:
    import h5py

    print(
        f"bench_output: {ranks} ranks, {args.cases} static cases at {args.n}², 3-D stress "
        f"blocks ({args.n}×{args.n}×{args.layers}, 7 arrays), best of {args.repeat}; "
        f"h5py {h5py.__version__}, HDF5 {h5py.version.hdf5_version}, mpi={h5py.get_config().mpi}"
    )
    print("writing s: summed over ranks; share: of the run's rank-seconds (ranks × wall)")
    print("collective s: the part of writing s in the collective prepare + commit (mpio)")
    header = f"{'strategy':<10s} {'wall s':>8s} {'writing s':>10s} {'collective s':>13s}"
    print(f"{header} {'share':>7s} {'file MB':>8s}")
    for strategy, result in best.items():
        share = result["writing"] / (ranks * result["wall"])  # of the run's rank-seconds
        print(
            f"{strategy:<10s} {result['wall']:8.2f} {result['writing']:10.2f} "
            f"{result['structure']:13.2f} {100 * share:6.1f}% {result['bytes'] / 1e6:8.1f}"
        )
    if len(best) == 2:
        ratio = best["mpio"]["wall"] / best["single"]["wall"]
        print(f"wall time mpio / single = {ratio:.2f}")
    else:
        print("mpio not measured: h5py is not MPI-enabled (scripts/build_parallel_h5py.sh)")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
