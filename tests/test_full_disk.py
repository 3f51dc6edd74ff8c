"""A full disk stops a run cleanly: completed cases kept, one line naming the path and the
space needed, exit code 5, and a rerun elsewhere completes.

The writer is tested with the free space and the operating system's ENOSPC simulated
(deterministic); the command line on a real 1.2 MB tmpfs when this process may mount one
(root), skipped otherwise.
"""

from __future__ import annotations

import errno
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import h5py
import pytest

from engine.output import space
from engine.output.hdf5 import SingleWriter
from engine.output.space import OutputFull, is_no_space
from engine.study.examples import study_toml
from tests.test_kill_safety import completed_file, metadata, study
from tests.test_output import fake_outcome

REPO = Path(__file__).resolve().parents[1]


def test_a_case_that_does_not_fit_is_not_begun(tmp_path, monkeypatch):
    """Free space for two cases: they complete, the writer is then full and writes nothing
    more; the file holds the two cases whole."""
    config, plan = study()
    path = tmp_path / "r.h5"
    free = {"bytes": 10**9}
    monkeypatch.setattr(space, "free_bytes", lambda _: free["bytes"])
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        for number, case in enumerate(plan):
            if number == 2:
                free["bytes"] = 0  # the disk fills up (the writer still holds its claims)
            writer.write(fake_outcome(case))
        assert isinstance(writer.full, OutputFull)
        assert str(path) in str(writer.full) and "rerun to resume" in str(writer.full)
    with h5py.File(path, "r") as file:
        statuses = [file["cases"][case_id].attrs["status"] for case_id in plan.case_ids]
    assert statuses == ["completed", "completed", "pending", "pending"]


def test_no_space_from_the_operating_system_becomes_output_full(tmp_path, monkeypatch):
    config, plan = study()
    first, second = list(plan)[:2]
    path = tmp_path / "r.h5"
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        writer.write(fake_outcome(first))

        def no_space(*args, **kwargs):
            raise OSError(errno.ENOSPC, "No space left on device")

        monkeypatch.setattr(SingleWriter, "_store_case", staticmethod(no_space))
        writer.write(fake_outcome(second))
        assert isinstance(writer.full, OutputFull)
    with h5py.File(path, "r") as file:
        assert file["cases"][first.case_id].attrs["status"] == "completed"
    assert is_no_space(RuntimeError("... errno = 28, error message = 'No space left on device'"))
    assert not is_no_space(RuntimeError("bad symbol table node signature"))


def test_the_check_before_a_run_refuses_when_no_case_could_be_kept(tmp_path, monkeypatch):
    """The data still to run fits, but the smallest case would fail the writer's own test
    (twice its data, the margin and the unplanned allowance): refused before anything runs,
    where a run would compute the case, fail to keep it and rewrite the file for nothing."""
    case = 40_000  # bytes the plan knows of the smallest case still to run
    writer_needs = 2 * case + space.MARGIN + space.UNPLANNED
    monkeypatch.setattr(space, "free_bytes", lambda _: writer_needs - 1)
    with pytest.raises(OutputFull):
        space.check_space(tmp_path / "r.h5", 2 * case, smallest_case=case)
    monkeypatch.setattr(space, "free_bytes", lambda _: writer_needs)
    space.check_space(tmp_path / "r.h5", 2 * case, smallest_case=case)


@pytest.fixture(params=["tmpfs", "ext2"])
def small_file_system(tmp_path, request):
    """About 1.2 MB free: a tmpfs, or an ext2 image on a loop device — a file system that
    cannot claim space (no ``fallocate``), where the free-space check is the only guard."""
    mount = tmp_path / "small"
    mount.mkdir()
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("needs root to mount a small file system")
    if request.param == "tmpfs":
        command = ["mount", "-t", "tmpfs", "-o", "size=1200k", "tmpfs", str(mount)]
    else:
        image = tmp_path / "ext2.img"
        image.write_bytes(b"")
        os.truncate(image, 1260 * 1024)  # about 1.2 MB free once formatted (no reserve)
        made = subprocess.run(["mkfs.ext2", "-q", "-F", "-m", "0", str(image)])
        if shutil.which("mkfs.ext2") is None or made.returncode != 0:
            pytest.skip("cannot make an ext2 file system here")
        command = ["mount", "-o", "loop", str(image), str(mount)]
    done = subprocess.run(command, capture_output=True)
    if done.returncode != 0:
        pytest.skip(f"cannot mount a {request.param} here: {done.stderr.decode().strip()}")
    if request.param == "ext2":
        probe = os.open(mount / "probe", os.O_CREAT | os.O_RDWR)
        try:
            assert not space.claim(probe, 4096, mount / "probe")  # ext2: no fallocate
        finally:
            os.close(probe)
            (mount / "probe").unlink()
    yield mount
    subprocess.run(["umount", str(mount)], check=False)


def engine(directory: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run(
        [sys.executable, "-m", "engine", *args, "--no-progress-bar", "--progress-interval", "0"],
        cwd=directory, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip


def test_a_full_file_system_stops_the_run_with_exit_5(small_file_system, tmp_path):
    """1.2 MB: room for about three of four cases beside the 1 MB kept free. The run exits 5
    with one line; the rerun on the still-full disk says so again and changes nothing; moved
    to space it completes the cases the first run kept."""
    text = study_toml(
        "full",
        "full.h5",
        mesh={"n": 8},
        loading={"kind": "static", "steps": 2},
        sweep={"mu1": [0.1, 0.2], "beta": [0.0, 30.0]},
    )
    (small_file_system / "full.toml").write_text(text)
    # How many cases fit depends on the HDF5 file's size when the next case is checked. Where
    # the writer claims its space (tmpfs) that size is exact; where it cannot (ext2), HDF5's
    # metadata may reach the disk after the check, and now and then the fourth case passes
    # the check with about 10 kB to spare: then all four fit, the run rightly ends with
    # exit 0, and the study is drawn again on the emptied file system (at most three times).
    for _ in range(3):
        first = engine(small_file_system, "full.toml")
        if first.returncode != 0:
            break
        for path in small_file_system.iterdir():
            if path.is_dir():
                shutil.rmtree(path)
            elif path.name != "full.toml":
                path.unlink()
    assert first.returncode == 5, first.stderr
    lines = first.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: full.h5: no space left")
    assert "Traceback" not in first.stderr
    with h5py.File(small_file_system / "full.h5", "r") as file:
        kept = sum(group.attrs["status"] == "completed" for group in file["cases"].values())
    assert 0 < kept < 4, first.stdout
    before = (small_file_system / "full.h5").read_bytes()
    again = engine(small_file_system, "full.toml")
    assert again.returncode == 5 and "Traceback" not in again.stderr
    assert (small_file_system / "full.h5").read_bytes() == before
    moved = tmp_path / "moved"
    shutil.copytree(small_file_system, moved)
    last = engine(moved, "full.toml")
    assert last.returncode == 0, last.stderr
    assert f"{kept} already complete, {4 - kept} to run" in last.stdout, last.stdout


def fill_to_the_last_byte(directory: Path) -> Path:
    """Grow ``directory/filler`` until its file system has 0 B free (1 MiB, 4 KiB, then
    single bytes); the filler's path."""
    path = directory / "filler"
    with open(path, "ab", buffering=0) as handle:
        for size in (1 << 20, 4096, 1):
            block = b"\0" * size
            while True:
                try:
                    handle.write(block)
                except OSError as error:
                    if error.errno != errno.ENOSPC:
                        raise
                    break
    return path


def test_a_disk_too_full_for_the_lock_names_what_the_run_needs(small_file_system):
    """A disk full to the last byte: not even the lock file can be written. Exit 5 with one
    line, nothing created, and the space named is what the study's cases need — the figure
    the check before a run names on the same disk with a little room left (the lock is
    taken, the cases do not fit beside the 1 MB kept free), not the lock file's 17 B."""
    text = study_toml(
        "lock", "lock.h5", mesh={"n": 8}, loading={"kind": "static", "steps": 2},
        sweep={"mu1": [0.1, 0.2], "beta": [0.0, 30.0]},
    )  # fmt: skip
    (small_file_system / "lock.toml").write_text(text)
    (small_file_system / "filler").write_bytes(bytes(600_000))  # about 0.6 MB left
    figures = []
    for fill in (lambda: None, lambda: fill_to_the_last_byte(small_file_system)):
        fill()
        done = engine(small_file_system, "lock.toml")
        assert done.returncode == 5, done.stderr
        lines = done.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: lock.h5: no space left"), lines
        made = {p.name for p in small_file_system.iterdir()} - {"lost+found"}  # ext2's own
        assert made == {"filler", "lock.toml"}
        figures.append(re.search(r"the cases still to run need about ([^,]+),", lines[0]))
    assert figures[0] and figures[1], figures
    assert figures[1][1] == figures[0][1]
    assert space.free_bytes(small_file_system) == 0  # the second run met a full disk


def test_a_case_is_announced_only_once_its_flag_is_on_disk(tmp_path):
    """Flags are committed in batches: an outcome is handed back for announcing (its
    "completed" line) only after the flush that put its status in the file."""
    config, plan = study()
    path = tmp_path / "r.h5"
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        writer.flag_spacing = 1e9  # after the first commit, none until asked
        announced = []
        for case in plan:
            outcome = fake_outcome(case)
            writer.write(outcome)
            announced += writer.committed(outcome)
            shutil.copyfile(path, tmp_path / "now.h5")  # the bytes a kill now would leave
            with h5py.File(tmp_path / "now.h5", "r") as file:
                for done in announced:
                    assert file["cases"][done.case_id].attrs["status"] == "completed"
        assert len(announced) == 1  # the first case; the other three wait for a commit
        rest = writer.commit()
        assert [o.case_id for o in announced + rest] == list(plan.case_ids)


def test_a_claim_that_fails_stops_before_the_case_is_begun(tmp_path, monkeypatch):
    """Another process took the space: the claim fails, nothing of the case is written, the
    cases written before are committed (their flags fit in the spare blocks given back) and
    announced; those never committed are pending in the summary."""
    from engine.output import hdf5

    config, plan = study()
    first, second, *_ = list(plan)
    path = tmp_path / "r.h5"
    with SingleWriter(path) as writer:
        writer.prepare(plan, metadata(config))
        assert space.spare_path(path).exists() or not writer._spare.held
        writer.flag_spacing = 1e9
        writer.write(fake_outcome(first))
        announced = writer.committed(None)

        def no_room(descriptor, length, where):
            raise OutputFull(where, length, 0)

        monkeypatch.setattr(hdf5, "claim", no_room)
        writer.write(fake_outcome(second))
        assert isinstance(writer.full, OutputFull) and not writer._broken
        announced += writer.commit()
    assert [o.case_id for o in announced] == [first.case_id]
    assert not space.spare_path(path).exists()
    with h5py.File(path, "r") as file:
        assert file["cases"][first.case_id].attrs["status"] == "completed"
        assert file["cases"][second.case_id].attrs["status"] == "pending"
        assert len(file["cases"][second.case_id]) == 0  # not begun


def test_claimed_blocks_are_held_then_given_back(tmp_path):
    """fallocate(KEEP_SIZE) allocates past the end without changing the size; closing the
    file gives the blocks back (where the file system supports it)."""
    path = tmp_path / "f"
    path.write_bytes(b"x" * 5000)
    with open(path, "r+b") as handle:
        if not space.claim(handle.fileno(), 1 << 20, path):
            pytest.skip("this file system cannot claim blocks (fallocate KEEP_SIZE)")
        assert path.stat().st_size == 5000
        assert space.claimed(handle.fileno()) >= (1 << 20) - 4096
    space.unclaim(path)
    assert path.stat().st_size == 5000 and path.stat().st_blocks * 512 < 64 << 10


def test_a_checkpoint_that_does_not_fit_leaves_nothing(tmp_path, monkeypatch):
    """A full disk while a stopped cyclic case saves its state: no checkpoint, not even a
    partial one (the case starts over when rerun), and no error."""
    import numpy as np

    from engine.study import checkpoint

    def no_space(target, **arrays):
        Path(target).write_bytes(b"partial")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", no_space)
    target = tmp_path / "case.npz"
    checkpoint._write(target, {"a": np.zeros(3)})
    assert list(tmp_path.iterdir()) == []


def test_no_room_to_salvage_a_damaged_file_is_a_full_disk(tmp_path, monkeypatch):
    """A salvage copies the sound cases into a new file: without room for it, exit 5 and
    the damaged file untouched."""
    from engine.output.identity import ExistingResults
    from engine.output.salvage import apply_existing

    config, plan = completed_file(tmp_path / "r.h5")
    before = (tmp_path / "r.h5").read_bytes()
    existing = ExistingResults(tmp_path / "r.h5", "salvage", completed=list(plan.case_ids))
    monkeypatch.setattr(space, "free_bytes", lambda _: 0)
    with pytest.raises(OutputFull):
        apply_existing(existing, plan, metadata(config), tmp_path / "r.h5.checkpoints")
    assert (tmp_path / "r.h5").read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.h5"]


# ------------------------------------------------------------------ the other writers
def no_space(*args, **kwargs):
    raise OSError(errno.ENOSPC, "No space left on device")


# a calibration that fits nothing and predicts one test (a few contact solves)
PREDICT_ONLY = {"calibrate": {"fit": [], "low": [], "high": [], "calibrate_on": []}}
ONE_TEST = "test,punch.radius,loading.load,Q\nA,6,185,40\n"


def test_a_calibration_stops_cleanly_when_its_contact_store_fills(tmp_path, monkeypatch):
    """The contact store's third save finds the disk full: the run ends ``output-full``
    naming the store, the two saved solutions kept whole (no temporary left); with space
    the rerun completes, reusing them."""
    import engine
    from engine.calibration import search
    from tests.test_calibration import write_study

    study = write_study(tmp_path, PREDICT_ONLY, tests=ONE_TEST)
    save, calls = search.ContactStore.save, []

    def fills_up(store, entry, cycle):
        calls.append(entry)
        if len(calls) > 2:
            return no_space()
        return save(store, entry, cycle)

    monkeypatch.setattr(search.ContactStore, "save", fills_up)
    run = engine.run_study(study, progress=False)
    assert run.status == "output-full", run
    store = tmp_path / "out" / "calibrate.h5.contact"
    assert str(store) in run.message and "rerun to resume" in run.message
    assert len(list(store.glob("*.npz"))) == 2 and not list(store.glob(".*"))
    monkeypatch.setattr(search.ContactStore, "save", save)
    run = engine.run_study(study, progress=False)
    assert run.status == "completed", run


def test_a_calibration_whose_results_do_not_fit_stops_cleanly(tmp_path, monkeypatch):
    """The results file finds the disk full as it is renamed into place: ``output-full``,
    no temporary left."""
    import engine
    from engine.output import calibration
    from tests.test_calibration import write_study

    study = write_study(tmp_path, PREDICT_ONLY, tests=ONE_TEST)
    monkeypatch.setattr(calibration, "os", SimpleNamespace(replace=no_space))  # this module's
    run = engine.run_study(study, progress=False)
    assert run.status == "output-full", run
    assert "calibrate.h5: no space left" in run.message
    assert not [path.name for path in (tmp_path / "out").glob(".*")]


def test_an_ensemble_table_that_does_not_fit_stops_cleanly(tmp_path, monkeypatch):
    """A ``[surface]`` study sweeping seeds: its ensemble CSV finds the disk full after the
    cases completed: ``output-full`` (exit 5), the results file whole, no temporary left."""
    import engine
    from engine.output import ensemble

    text = study_toml(
        "rough", "rough.h5", mesh={"n": 16}, loading={"kind": "static", "steps": 1},
        surface={"kind": "self_affine", "hurst": 0.8, "short_cutoff": 1.0,
                 "long_cutoff": 4.0, "rms_slope": 0.01},
        sweep={"mu1": [0.3], "surface.seed": [1, 2]},
    )  # fmt: skip
    (tmp_path / "rough.toml").write_text(text)
    monkeypatch.setattr(ensemble, "os", SimpleNamespace(replace=no_space))  # this module's
    monkeypatch.chdir(tmp_path)
    run = engine.run_study(tmp_path / "rough.toml", progress=False)
    assert run.status == "output-full", run
    assert "no space left" in run.message
    assert not [path.name for path in tmp_path.glob(".*")]


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full (Linux)")
def test_a_console_on_a_full_disk_loses_lines_never_the_exit_code(tmp_path):
    """stdout and stderr on a device that is always full (/dev/full: every write ENOSPC):
    a study completes with exit code 0, bad input is still 2, verify of a whole file 0."""
    text = study_toml(
        "console", "console.h5", mesh={"n": 8}, loading={"kind": "static", "steps": 1},
        sweep={"mu1": [0.1]},
    )  # fmt: skip
    (tmp_path / "console.toml").write_text(text)
    (tmp_path / "bad.toml").write_text(text.replace("n = 8", "n = 3"))
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    codes = []
    for args in (["console.toml"], ["bad.toml"], ["verify", "console.h5"]):
        with open("/dev/full", "w") as full:
            done = subprocess.run(
                [sys.executable, "-m", "engine", *args], cwd=tmp_path, env=env,
                stdout=full, stderr=full, timeout=300,
            )  # fmt: skip
        codes.append(done.returncode)
    assert codes == [0, 2, 0]
    with h5py.File(tmp_path / "console.h5", "r") as file:
        assert [group.attrs["status"] for group in file["cases"].values()] == ["completed"]
