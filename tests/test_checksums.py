"""Checksums of the results, the verified look at an existing file, and the file check.

Serial, on small files written by the single writer from fake outcomes (four cases); the
damage is made with byte-exact writes at offsets HDF5 reports, so every test is
deterministic. The same checks on real runs through the command line: tests/test_attacks.py.
"""

from __future__ import annotations

import time

import h5py
import numpy as np
import pytest

from engine.output.checksum import (
    CASE_CHECKSUM,
    DATASET_CHECKSUM,
    case_checksum,
    data_checksum,
    manifest_entry,
    verify_case,
)
from engine.output.existing import inspect_existing, inspect_existing_isolated
from engine.output.isolated import (
    PER_DATASET_S,
    IsolatedCallStopped,
    IsolatedCallTimedOut,
    call_isolated,
)
from engine.output.salvage import apply_existing
from engine.output.verify import EXIT_CLEAN, EXIT_DAMAGED, main, verify_file
from tests.slow_reader import read_datasets_slowly
from tests.test_kill_safety import completed_file, metadata, study

PRESSURE = "fields/final/pressure"


def flip_bit(path, case_id, dataset=PRESSURE, byte=3, bit=2):
    """Flip one bit of the stored data of ``dataset`` of ``case_id`` (contiguous layout)."""
    with h5py.File(path, "r") as file:
        offset = file["cases"][case_id][dataset].id.get_offset()
    with open(path, "r+b") as handle:
        handle.seek(offset + byte)
        value = handle.read(1)[0]
        handle.seek(offset + byte)
        handle.write(bytes([value ^ (1 << bit)]))


# ------------------------------------------------------------------------------ checksums
def test_checksum_is_a_function_of_dtype_shape_and_bytes():
    values = np.arange(6.0)
    assert data_checksum(values) == data_checksum(values.copy())
    assert data_checksum(values) != data_checksum(values.reshape(2, 3))  # shape counts
    assert data_checksum(values) != data_checksum(values.astype(np.float32))  # dtype counts
    changed = values.copy()
    changed.view(np.uint8)[5] ^= 1  # one bit
    assert data_checksum(values) != data_checksum(changed)
    # text read back from HDF5 as bytes hashes as the str that was written
    assert data_checksum(np.array(["a", "bc"], dtype=object)) == data_checksum(
        np.array([b"a", b"bc"], dtype=object)
    )


def test_every_dataset_of_a_completed_case_carries_its_checksum(tmp_path):
    path = tmp_path / "r.h5"
    _, plan = completed_file(path)
    with h5py.File(path, "r") as file:
        for case_id in plan.case_ids:
            group = file["cases"][case_id]
            manifest = {}
            for name in ("history/cycle", "history/max_wear_depth", PRESSURE, "grid/x"):
                data = group[name][()]
                assert group[name].attrs[DATASET_CHECKSUM] == data_checksum(data)
            group.visititems(
                lambda name, item, m=manifest: (
                    m.__setitem__(name, manifest_entry(item[()]))
                    if isinstance(item, h5py.Dataset)
                    else None
                )
            )
            assert group.attrs[CASE_CHECKSUM] == case_checksum(manifest)
            assert verify_case(group).sound and verify_case(group).verified


def test_equal_results_give_equal_checksums(tmp_path):
    """Two files written from the same outcomes carry the same checksum attributes (no time,
    rank or host goes in)."""
    first, second = tmp_path / "a.h5", tmp_path / "b.h5"
    _, plan = completed_file(first)
    completed_file(second)
    with h5py.File(first, "r") as a, h5py.File(second, "r") as b:
        for case_id in plan.case_ids:
            assert (
                a["cases"][case_id].attrs[CASE_CHECKSUM] == b["cases"][case_id].attrs[CASE_CHECKSUM]
            )


@pytest.mark.parametrize("each_dataset", [True, False])
def test_a_flipped_bit_and_a_removed_dataset_are_found(tmp_path, each_dataset):
    """Both ways of reading a case back (each dataset against its own checksum, or all of
    them against the case checksum, as after a run) find the damage and name the dataset."""
    path = tmp_path / "r.h5"
    _, plan = completed_file(path)
    flipped, removed, sound = plan.case_ids[:3]
    flip_bit(path, flipped)
    with h5py.File(path, "a") as file:
        del file["cases"][removed]["history/cycle"]
    with h5py.File(path, "r") as file:
        cases = file["cases"]
        problem = verify_case(cases[flipped], each_dataset=each_dataset).problem
        assert problem == f"checksum mismatch in {PRESSURE}"
        problem = verify_case(cases[removed], each_dataset=each_dataset).problem
        assert "case checksum mismatch" in problem
        assert verify_case(cases[sound], each_dataset=each_dataset).sound


def test_the_read_back_after_a_run_needs_no_dataset_checksum(tmp_path):
    """After a run the case checksum alone is compared (it covers every dataset's bytes): a
    damaged ``sha256`` attribute over intact data is left to ``python -m engine verify``,
    which compares each dataset's own checksum too."""
    path = tmp_path / "r.h5"
    _, plan = completed_file(path)
    with h5py.File(path, "a") as file:
        file["cases"][plan.case_ids[0]][PRESSURE].attrs[DATASET_CHECKSUM] = "0" * 64
    with h5py.File(path, "r") as file:
        group = file["cases"][plan.case_ids[0]]
        assert verify_case(group, each_dataset=False).sound
        assert verify_case(group).problem == f"checksum mismatch in {PRESSURE}"


def test_a_case_without_checksums_is_read_but_not_verified(tmp_path):
    """Files written before checksums existed still resume (read in full, not compared)."""
    path = tmp_path / "r.h5"
    _, plan = completed_file(path)
    with h5py.File(path, "a") as file:
        del file["cases"][plan.case_ids[0]].attrs[CASE_CHECKSUM]
    with h5py.File(path, "r") as file:
        check = verify_case(file["cases"][plan.case_ids[0]])
    assert check.sound and not check.verified


# ------------------------------------------------------------------------------ resume
def test_resume_recomputes_a_case_whose_checksum_fails(tmp_path):
    """A bit flipped in one dataset: that case is not trusted; the sound ones are copied, the
    damaged file kept aside under a number that never overwrites an earlier copy."""
    path = tmp_path / "r.h5"
    config, plan = completed_file(path)
    (tmp_path / "r.h5.damaged.1").write_text("an earlier damaged copy")
    flip_bit(path, plan.case_ids[1])
    existing = inspect_existing(path, metadata(config), plan)
    assert existing.kind == "salvage"
    assert existing.damaged == {plan.case_ids[1]: f"checksum mismatch in {PRESSURE}"}
    assert sorted(existing.completed) == sorted(set(plan.case_ids) - {plan.case_ids[1]})
    assert existing.kept_as == tmp_path / "r.h5.damaged.2"
    assert any("1 damaged case(s)" in note for note in existing.notes())
    apply_existing(existing, plan, metadata(config), tmp_path / "r.h5.checkpoints")
    assert (tmp_path / "r.h5.damaged.1").read_text() == "an earlier damaged copy"
    assert (tmp_path / "r.h5.damaged.2").exists()
    again = inspect_existing(path, metadata(config), plan)
    assert again.kind == "resume" and sorted(again.completed) == sorted(existing.completed)


def test_the_isolated_inspection_gives_the_same_verdict(tmp_path):
    path = tmp_path / "r.h5"
    config, plan = completed_file(path)
    flip_bit(path, plan.case_ids[0])
    here = inspect_existing(path, metadata(config), plan)
    there = inspect_existing_isolated(path, metadata(config), plan)
    assert (there.kind, there.damaged, there.completed) == (here.kind, here.damaged, here.completed)


def sleep_forever():
    """Stands for HDF5 looping on damaged metadata (run in the child by the tests below)."""
    while True:
        time.sleep(1)


def test_a_read_that_never_ends_is_stopped_by_the_time_limit_and_by_a_stop_signal():
    start = time.monotonic()
    with pytest.raises(IsolatedCallTimedOut, match="did not finish within 2 s"):
        call_isolated(sleep_forever, time_limit=2.0)
    stop_at = time.monotonic() + 1.0
    with pytest.raises(IsolatedCallStopped):
        call_isolated(sleep_forever, should_stop=lambda: time.monotonic() > stop_at)
    assert time.monotonic() - start < 20  # 2 s + 1 s and two interpreter starts


def test_the_time_limit_grows_with_the_datasets_read():
    """A read of 4 s goes on past a 2 s limit while it reports datasets (each allows
    PER_DATASET_S = 10 ms more, twice what one takes here); stuck after 0.5 s of reading
    (about 100 datasets, 1 s more) it is cut at about 3 s, the count named."""
    assert PER_DATASET_S >= 0.01  # the reads below take 5 ms per dataset
    count = call_isolated(read_datasets_slowly, 4.0, time_limit=2.0)
    assert count > 200  # fewer: the child did not read for 4 s (a sleep of 5 ms or more)
    start = time.monotonic()
    with pytest.raises(IsolatedCallTimedOut, match=r"\(\d+ datasets read"):
        call_isolated(read_datasets_slowly, 0.5, True, time_limit=2.0)
    assert time.monotonic() - start < 2.0 + 0.5 + 100 * PER_DATASET_S + 10  # start-up, load


def test_a_file_that_cannot_be_read_in_time_is_kept_aside(tmp_path, monkeypatch):
    """The verdict after the time limit: start over, the file kept as <output>.damaged.N."""
    path = tmp_path / "r.h5"
    config, plan = completed_file(path)
    monkeypatch.setenv("ENGINE_INSPECTION_TIME_LIMIT", "0.01")  # less than a child's start
    existing = inspect_existing_isolated(path, metadata(config), plan)
    assert existing.kind == "start-over" and "did not finish within" in existing.problem
    assert existing.kept_as == tmp_path / "r.h5.damaged.1"


# ------------------------------------------------------------------------------ verify
def test_verify_passes_a_whole_file_and_its_summary(tmp_path, capsys):
    path = tmp_path / "r.h5"
    completed_file(path)
    assert main([str(path)]) == EXIT_CLEAN
    assert "OK (4 cases, 4 completed" in capsys.readouterr().out


def test_verify_names_the_bad_cases_and_a_summary_that_disagrees(tmp_path, capsys):
    path = tmp_path / "r.h5"
    _, plan = completed_file(path)
    flip_bit(path, plan.case_ids[2])
    summary = path.with_suffix(".csv")
    summary.write_text(summary.read_text().replace(plan.case_ids[3], "somewhere_else", 1))
    assert main([str(path)]) == EXIT_DAMAGED
    out = capsys.readouterr().out
    lines = [line.split() for line in out.splitlines()]
    assert [plan.case_ids[2], "completed", "checksum", "mismatch", "in", PRESSURE] in lines
    assert [plan.case_ids[3], "summary", "missing", "from", "r.csv"] in lines
    assert "DAMAGED: 1 bad case(s), 2 summary difference(s)" in out


def test_verify_reports_an_unreadable_file_as_damaged(tmp_path, capsys):
    path = tmp_path / "r.h5"
    completed_file(path)
    with open(path, "r+b") as handle:
        handle.write(b"\0" * 64)  # the superblock
    assert main([str(path), "--no-summary"]) == EXIT_DAMAGED
    assert "DAMAGED" in capsys.readouterr().out
    assert main([str(tmp_path / "missing.h5")]) == 2


def test_verify_file_reads_every_dataset(tmp_path):
    path = tmp_path / "r.h5"
    completed_file(path)
    check = verify_file(path, None)
    assert not check.damaged and [c.datasets for c in check.cases] == [5, 5, 5, 5]


def test_study_helper_is_four_cases():
    assert len(study()[1]) == 4  # what the counts above assume
