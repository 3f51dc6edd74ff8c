"""Every test's threshold search for given values of the fitted keys, across the ranks.

For values v of the fitted keys, every test is one threshold search
(:class:`engine.study.search.Search`, the same method and stopping rule as a ``[search]``
study) along the searched parameter x. The searches advance together in rounds: each round
takes the x every unfinished search waits for, solves the contact of those not solved yet
(:func:`~engine.calibration.contact.solve_cycle`; rank r solves the r-th of every ``size``),
reads the threshold column from every kept contact solution with the values v
(:func:`~engine.calibration.contact.criterion_value`, shared the same way) and gives every
search its value. Every rank holds every search and receives every value, so every rank ends
with the same thresholds, bit for bit, whatever the number of ranks.

Contact solutions are kept in a :class:`ContactStore` keyed by (test, x, the fitted keys that
change the contact). A fatigue constant or the critical distance does not change the contact:
a fit over them solves the contact only at values of x not solved before, and an evaluation
starts each search from the tightest bracket among the x solved in *earlier* evaluations
(read again with the new values, no contact solve), so as the fit converges its searches need
fewer and fewer new solutions. Only solutions of earlier evaluations seed a bracket: what an
evaluation does depends on the evaluations before it alone, so a run resumed from the store
repeats the uninterrupted run exactly.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from engine.output.space import OutputFull, free_bytes, is_no_space
from engine.parallel.serial import any_rank
from engine.study.search import Search, SearchSpec, SearchStatus, StepFailure

from .contact import ContactCycle, criterion_value, cycle_arrays, cycle_from_arrays, solve_cycle

__all__ = ["ContactStore", "StoreEntry", "TestSearches", "Stopped"]

_STORED = re.compile(r"^[0-9a-f]{24}\.npz$")


class Stopped(Exception):
    """A stop was requested (every rank agreed): the run ends, the store keeps its work."""


@dataclass(frozen=True)
class StoreEntry:
    """One kept contact solution: its test (``id@digest``: the test's id and a digest of
    everything that sets its contact, :meth:`CalibrationProblem.store_name`), x, the
    contact-changing fitted values, the evaluation that created it, and its file (named by a
    digest of the first three)."""

    test: str
    x: float
    contact: tuple[tuple[str, float], ...]
    evaluation: int
    path: Path
    converged: bool = True


@dataclass
class ContactStore:
    """Contact solutions on disk (``directory/<digest>.npz``, each written atomically; the
    digest of test, x and the contact-changing values, so that a file's name never depends
    on the order in which it was solved) and an in-memory copy of those this rank has read
    or solved."""

    directory: Path
    entries: dict[tuple, StoreEntry] = field(default_factory=dict)
    cycles: dict[tuple, ContactCycle] = field(default_factory=dict)

    @staticmethod
    def key(test: str, x: float, contact) -> tuple:
        return (test, float(x), tuple(contact))

    def load_index(self) -> None:
        """Read the entries already on disk (a resumed run)."""
        if not self.directory.is_dir():
            return
        for path in sorted(self.directory.glob("*.npz")):
            if not _STORED.match(path.name):  # a temporary file a kill left behind
                continue
            with np.load(path, allow_pickle=False) as data:
                names = [str(n) for n in data["contact_names"]]
                values = [float(v) for v in data["contact_values"]]
                entry = StoreEntry(
                    str(data["test"]),
                    float(data["x"]),
                    tuple(zip(names, values, strict=True)),
                    int(data["evaluation"]),
                    path,
                    bool(int(data["converged"][0])),
                )
            self.entries[self.key(entry.test, entry.x, entry.contact)] = entry

    def get(self, test: str, x: float, contact) -> StoreEntry | None:
        return self.entries.get(self.key(test, x, contact))

    def path_for(self, test: str, x: float, contact) -> Path:
        text = repr(self.key(test, x, contact)).encode("utf-8")
        return self.directory / f"{hashlib.sha256(text).hexdigest()[:24]}.npz"

    def save(self, entry: StoreEntry, cycle: ContactCycle) -> None:
        """Keep ``cycle`` in the store, whole or not at all (written aside, then renamed; a
        write that fails, a full disk say, leaves nothing)."""
        self.directory.mkdir(parents=True, exist_ok=True)
        arrays = cycle_arrays(cycle)
        names, values = zip(*entry.contact, strict=True) if entry.contact else ((), ())
        arrays.update(
            test=np.array(entry.test),
            x=np.array(entry.x),
            evaluation=np.array(entry.evaluation),
            contact_names=np.array(list(names), dtype=str),
            contact_values=np.array(list(values), dtype=float),
        )
        temporary = entry.path.with_name(f".{entry.path.name}.tmp.npz")
        try:
            np.savez(temporary, **arrays)
            os.replace(temporary, entry.path)
        except BaseException:
            temporary.unlink(missing_ok=True)
            raise
        self.cycles[self.key(entry.test, entry.x, entry.contact)] = cycle

    def add(self, entry: StoreEntry) -> None:
        self.entries[self.key(entry.test, entry.x, entry.contact)] = entry

    def cycle(self, entry: StoreEntry) -> ContactCycle:
        key = self.key(entry.test, entry.x, entry.contact)
        if key not in self.cycles:
            with np.load(entry.path, allow_pickle=False) as data:
                self.cycles[key] = cycle_from_arrays(data)
        return self.cycles[key]


@dataclass
class TestSearches:
    """The threshold searches of the tests for one evaluation (given fitted values).

    ``problem`` gives, per test and x, the case and configuration (``problem.case(test, x,
    values)``), and the contact-changing part of the fitted values; ``comm`` the ranks.
    """

    __test__ = False

    problem: Any
    store: ContactStore
    comm: Any
    context: Any
    should_stop: Any = None
    solves: int = 0  # contact solves of this run, all ranks
    _read: dict = field(default_factory=dict)

    def run(self, tests, values: dict[str, float], evaluation: int) -> dict[str, Any]:
        """Search every test of ``tests`` at the fitted ``values``; returns per test id the
        :class:`~engine.study.search.SearchResult` (threshold in the parameter's units)."""
        problem = self.problem
        contact = problem.contact_values(values)
        self._read = {}  # (test id, x) -> the column at ``values``: read once per evaluation
        specs = {test.id: problem.search_spec(test, values) for test in tests}
        specs.update(self._seeded(tests, specs, values, contact, evaluation))
        searches = {test.id: Search(specs[test.id]) for test in tests}
        while True:
            self._check_stop()
            wanted = [(test, x) for test in tests for x in searches[test.id].pending()]
            if not wanted:
                break
            found = self._values(wanted, values, contact, evaluation)
            for (test, x), value in zip(wanted, found, strict=True):
                searches[test.id].record(x, value)
        return {test.id: searches[test.id].result for test in tests}

    # ------------------------------------------------------------------ internals
    def _check_stop(self) -> None:
        stop = bool(self.should_stop is not None and self.should_stop())
        if any_rank(self.comm, stop):
            raise Stopped()

    def _seeded(self, tests, specs, values, contact, evaluation) -> dict[str, SearchSpec]:
        """Per test, its bracket narrowed to the tightest pair of neighbouring x solved in
        earlier evaluations on either side of the target (read with ``values``; found by
        bisection over the sorted x, the column taken monotone in the bracket as the search
        does); tests without such a pair keep their bracket."""
        known = {}
        for test in tests:
            spec = specs[test.id]
            xs = sorted(
                entry.x
                for entry in self.store.entries.values()
                if entry.test == self.problem.store_name(test)
                and entry.contact == tuple(contact)
                and entry.evaluation < evaluation
                and entry.converged
                and spec.low <= entry.x <= spec.high
            )
            if len(xs) >= 2:
                known[test.id] = xs
        by_id = {test.id: test for test in tests}
        side: dict[str, dict[int, bool | None]] = {test_id: {} for test_id in known}
        ranges = {test_id: [0, len(xs) - 1] for test_id, xs in known.items()}
        while True:
            wanted = []  # (test id, index) whose side is needed now
            for test_id, (low, high) in ranges.items():
                for index in (low, high) if low not in side[test_id] else ((low + high) // 2,):
                    if index not in side[test_id]:
                        wanted.append((test_id, index))
            if not wanted:
                break
            found = self._values(
                [(by_id[t], known[t][i]) for t, i in wanted], values, contact, evaluation
            )
            for (test_id, index), value in zip(wanted, found, strict=True):
                target = float(specs[test_id].target)
                side[test_id][index] = None if not _usable(value) else float(value) > target
            for test_id in list(ranges):
                low, high = ranges[test_id]
                seen = side[test_id]
                if seen.get(low) is None or seen.get(high) is None or seen[low] == seen[high]:
                    del ranges[test_id]  # unusable or not bracketed: keep the bracket
                    continue
                if high - low == 1:
                    xs = known[test_id]
                    specs[test_id] = dataclasses.replace(specs[test_id], low=xs[low], high=xs[high])
                    del ranges[test_id]
                    continue
                middle = (low + high) // 2
                if middle in seen:
                    if seen[middle] is None:
                        del ranges[test_id]
                    elif seen[middle] == seen[low]:
                        ranges[test_id] = [middle, high]
                    else:
                        ranges[test_id] = [low, middle]
        return specs

    def _values(self, wanted, values, contact, evaluation) -> list[Any]:
        """The column at every (test, x) of ``wanted``: missing contact solutions are solved
        first (shared over the ranks), then the criteria are read (shared too)."""
        rank, size = self.comm.Get_rank(), self.comm.Get_size()
        missing, seen = [], set()
        name = self.problem.store_name
        for test, x in wanted:
            key = ContactStore.key(name(test), x, contact)
            if self.store.get(name(test), x, contact) is None and key not in seen:
                seen.add(key)
                missing.append((test, x))
        entries = [
            StoreEntry(name(test), float(x), tuple(contact), evaluation,
                       self.store.path_for(name(test), x, contact))
            for test, x in missing
        ]  # fmt: skip
        solved, full = [], None  # full: (store, bytes) of a save that found no space
        for k in range(rank, len(missing), size):
            test, x = missing[k]
            case, config = self.problem.case(test, x, values)
            try:
                cycle = solve_cycle(self.context, case, config, self.should_stop)
            except InterruptedError:
                cycle = None
            except Exception as error:  # noqa: BLE001 - a failed solve fails its search
                cycle = ContactCycle((), False, f"{type(error).__name__}: {error}")
            if cycle is not None:
                entry = dataclasses.replace(entries[k], converged=cycle.converged)
                try:
                    self.store.save(entry, cycle)
                except OSError as error:  # a full disk: no more solves on any rank
                    if not is_no_space(error):
                        raise
                    full = (str(self.store.directory), _cycle_bytes(cycle))
                    break
                solved.append((k, cycle.converged))
        everyone = self.comm.allgather((solved, full))
        done = {k: converged for share, _ in everyone for k, converged in share}
        for k, converged in done.items():  # what was saved is kept for the next run
            self.store.add(dataclasses.replace(entries[k], converged=converged))
        stopped = [where for _, where in everyone if where is not None]
        if stopped:
            where, needed = stopped[0]
            raise OutputFull(Path(where), needed, free_bytes(Path(where)))
        if len(done) < len(missing):  # a rank was stopped inside a solve
            raise Stopped()
        self.solves += len(missing)
        unread = []  # the (test, x) not read yet at these values, each once
        for test, x in wanted:
            if (test.id, x) not in self._read and (test, x) not in unread:
                unread.append((test, x))
        mine = {}
        for k in range(rank, len(unread), size):
            test, x = unread[k]
            mine[k] = self._value(test, x, values, contact)
        for share in self.comm.allgather(mine):
            for k, value in share.items():
                test, x = unread[k]
                self._read[(test.id, x)] = value
        return [self._read[(test.id, x)] for test, x in wanted]

    def _value(self, test, x, values, contact):
        entry = self.store.get(self.problem.store_name(test), x, contact)
        cycle = self.store.cycle(entry)
        if not cycle.converged or not cycle.increments:
            return StepFailure(
                f"the contact at {self.problem.parameter} = {x!r} did not converge"
                + (f": {cycle.message}" if cycle.message else "")
            )
        try:
            case, config = self.problem.case(test, x, values)
            return criterion_value(self.context, case, config, cycle, self.problem.column)
        except Exception as error:  # noqa: BLE001 - the search ends failed, naming why
            return StepFailure(f"{type(error).__name__}: {error}")


def _usable(value: Any) -> bool:
    try:
        return math.isfinite(float(value))
    except (TypeError, ValueError):
        return False


CONVERGED = SearchStatus.CONVERGED


def _cycle_bytes(cycle: ContactCycle) -> int:
    """Bytes a contact cycle takes in the store (its arrays)."""
    return sum(int(np.asarray(array).nbytes) for array in cycle_arrays(cycle).values())
