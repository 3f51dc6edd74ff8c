"""Outcomes packed into an HDF5 image by the computing rank (engine.output.packed): the file
rank 0 writes from them equals, object for object and attribute for attribute, the file it
writes from the arrays; the checksums hold; large or empty outcomes travel as they are."""

from __future__ import annotations

import importlib.util
import pickle
from pathlib import Path

import numpy as np

from engine.output.hdf5 import SingleWriter
from engine.output.packed import PackedOutcome, pack
from engine.output.verify import check_after_run
from engine.run import study_metadata
from engine.study.case import CaseOutcome, CaseRunner, DatasetRecord
from engine.study.config import parse_study
from engine.study.examples import study_toml
from engine.study.plan import make_plan

REPO = Path(__file__).resolve().parents[1]
RUN_DEPENDENT = frozenset({"runtime_s", "cpu_s", "rank"})


def _compare_hdf5():
    script = REPO / "scripts" / "compare_results.py"
    spec = importlib.util.spec_from_file_location("compare_results", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.compare_hdf5


def _write(path: Path, config, plan, outcomes) -> None:
    metadata = study_metadata(config, "python -m engine packed.toml", plan)
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata)
        for outcome in outcomes:
            writer.write(outcome)


def _study(tmp_path):
    text = study_toml(
        "packed",
        tmp_path / "unused.h5",
        mesh={"n": 8},
        loading={"kind": "static", "steps": 1},
        subsurface={"layers": 2},
        sweep={"mu1": [0.1, 0.3], "beta": [0.0, 30.0]},
    )
    config = parse_study(text)
    return config, make_plan(config)


def test_a_packed_case_is_written_as_the_same_objects_as_its_arrays(tmp_path):
    config, plan = _study(tmp_path)
    runner = CaseRunner(config)
    outcomes = [runner(case) for case in plan]
    assert all(outcome.status == "completed" for outcome in outcomes)
    # what a worker sends: packed, then pickled and unpickled by MPI
    packed = [pickle.loads(pickle.dumps(pack(outcome))) for outcome in outcomes]
    assert all(isinstance(outcome, PackedOutcome) for outcome in packed)
    assert all(outcome.image for outcome in packed)
    direct, through_images = tmp_path / "direct.h5", tmp_path / "packed.h5"
    _write(direct, config, plan, outcomes)
    _write(through_images, config, plan, packed)
    assert _compare_hdf5()(direct, through_images, RUN_DEPENDENT) == []
    # every case read back in full, its datasets' and its own checksum agreeing
    assert check_after_run(through_images, set(plan.case_ids)) == []


def test_outcomes_without_datasets_or_above_the_limit_travel_as_arrays(tmp_path):
    config, plan = _study(tmp_path)
    case = next(iter(plan))
    failed = CaseOutcome(case, "failed", row={"status": "failed"}, message="boom")
    assert pack(failed) is failed
    large = CaseOutcome(
        case, "completed", datasets={"history/x": DatasetRecord(np.zeros(1000), "mm", "x")}
    )
    assert pack(large, limit=7999) is large  # 8,000 bytes of data
    assert isinstance(pack(large, limit=8000), PackedOutcome)
