"""Progress of a study on rank 0: a line per finished case, and a status line with an ETA.

What rank 0 reports while a study runs, through :mod:`logging` (the logger
``engine.output.progress``, at INFO; the command line shows the case lines on stdout and the
status lines, marked ``stream="stderr"``, on stderr):

- one line per finished case: ``[k/N] case_id rank r  t s  status``;
- a *status line* every ``interval`` seconds (default 30) and after each finished
  case: cases done/total, the running cases with the cycle they reached, elapsed time, and
  the ETA. Plain lines, so that they work under ``mpiexec``/``srun`` where stderr is a file;
- on a terminal (stderr a tty) a tqdm bar instead of the status lines, with the same
  running cases and ETA in its postfix.

Where the numbers come from. Each rank's case runner reports the start of a case and every
simulated cycle (``CaseRunner.on_progress``): rank 0's computing thread through a queue,
the other ranks by a small MPI message (tag ``TAG_PROGRESS``, at most one per
``WorkerProgress.min_interval`` seconds per rank besides the start). Rank 0's dispatcher
drains both between its other duties (``ProgressChannel.drain``), so no extra thread touches
MPI.

What is counted. A finished case is counted by its status: ``completed``, ``failed`` or
``interrupted`` (stopped by a signal; its state is checkpointed and a rerun resumes it); only
completed cases count towards ``k/N cases completed``. Once a case has been interrupted the
run is stopping: no case starts any more, so the line gives the cases left unstarted instead
of an ETA. The last status line, printed after the last finished case, therefore has the
same counts as the closing summary (completed, failed, and interrupted plus unstarted = not
completed).

The ETA. Each case has a relative cost guess (``Case.expected_cost``: low friction slips
more and takes longer). The measured seconds per unit of that cost, over the cases completed
so far (in this run and in the runs it resumes), give a predicted time per case. A running
case needs its prediction minus the time it has already run; once it has run longer than
predicted, its remaining time is extrapolated from the cycles it has reached (elapsed ×
(cycles − cycle)/cycle: an upper bound with cycle jumping, whose later jumps are longer),
and a case without a cycle report that is past its prediction makes the ETA a lower bound
("more than …"). The cases not yet started are handed, in dispatch order, to whichever
rank frees up first — as the scheduler does. The ETA is when the last rank finishes. Before
the first case completes there is no measurement and the line says so.
"""

from __future__ import annotations

import heapq
import logging
import queue
import sys
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, TextIO

from engine.schema import CaseStatus

LOGGER = logging.getLogger(__name__)

__all__ = [
    "ProgressReporter",
    "ProgressChannel",
    "WorkerProgress",
    "plural",
    "format_duration",
    "TAG_PROGRESS",
]

TAG_PROGRESS = 73  # worker -> rank 0: ("start" | "cycle", case_id, cycle, cycles)
MAX_LISTED = 4  # running cases named in a status line; the rest are counted
# Beyond this many waiting cases the ETA treats the queue as divisible work (water-filling,
# :func:`_balanced_finish`) instead of simulating the greedy dispatch case by case: the
# simulation is O(waiting) per finished case, i.e. O(cases²) over a study (at 10,000 cases,
# several ms per case on the dispatcher). The two differ by at most the longest waiting case.
EXACT_QUEUE = 256


def plural(count: int, singular: str, plural_form: str | None = None) -> str:
    """``"1 case"``, ``"2 cases"``, ``"0 cases"``."""
    word = singular if count == 1 else (plural_form or singular + "s")
    return f"{count} {word}"


def format_duration(seconds: float) -> str:
    """``"42 s"``, ``"3 min 05 s"``, ``"2 h 07 min"`` (rounded down to the unit shown)."""
    seconds = max(0.0, float(seconds))
    if seconds < 60:
        return f"{seconds:.0f} s"
    minutes, rest = divmod(int(seconds), 60)
    if minutes < 60:
        return f"{minutes} min {rest:02d} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes:02d} min"


def _remaining(seconds: float) -> str:
    """An ETA while cases are still running or waiting: never "0 s" (work is left), but
    "under 1 s" below a second."""
    return "under 1 s" if seconds < 1.0 else format_duration(seconds)


def _balanced_finish(free_at: list[float], work: float) -> float:
    """When ranks free at ``free_at`` (s from now, at least one) share ``work`` seconds of
    divisible work: the level T with sum over ranks of max(T - free_at_i, 0) = work
    (water-filling), or the latest ``free_at`` if that is later."""
    ranks = sorted(free_at)
    for count in range(1, len(ranks) + 1):
        level = (work + sum(ranks[:count])) / count
        if count == len(ranks) or level <= ranks[count]:
            return max(level, ranks[-1])
    return 0.0


@dataclass
class _Running:
    case_id: str
    rank: int
    started: float  # clock time when rank 0 learnt of the start
    cost: float
    cycle: int | None = None
    cycles: int | None = None


class ProgressReporter:
    """Rank 0's display. ``started``/``cycle`` as reports arrive, ``update(outcome)`` when a
    case finishes, ``tick()`` often (it prints only every ``interval`` seconds).

    ``todo``: the cases still to run, in dispatch order (objects with ``case_id`` and
    ``expected_cost``); ``measured``: (runtime in s, expected cost) of cases completed by
    earlier runs of the study; ``ranks``: how many ranks compute. ``bar``: None draws a tqdm
    bar when stderr is a terminal; ``interval`` 0 turns the periodic status lines off.
    ``searches``: (ended, searches) of a ``[search]`` study, whose ``[k/N]`` and bar count
    searches (:meth:`count_searches`) from the start.
    """

    def __init__(
        self,
        total: int,
        done: int = 0,
        *,
        todo: Iterable[Any] = (),
        ranks: int = 1,
        measured: Iterable[tuple[float, float]] = (),
        stream: TextIO | None = None,
        status_stream: TextIO | None = None,
        bar: bool | None = None,
        interval: float = 30.0,
        clock: Callable[[], float] = time.monotonic,
        searches: tuple[int, int] | None = None,
    ) -> None:
        self.total = total
        self.done = done  # finished cases, whatever their status (earlier runs: completed)
        self._searches: tuple[int, int] | None = None  # (ended, searches) of a [search] study
        self.counts = {CaseStatus.COMPLETED: done, CaseStatus.FAILED: 0, CaseStatus.INTERRUPTED: 0}
        self.ranks = max(1, ranks)
        self.stream = stream  # None: the case lines are logged
        self.status_stream = status_stream  # None: the status lines are logged
        self.interval = interval
        self.clock = clock
        self.start = clock()
        self._last_status = self.start
        self._costs = {case.case_id: float(case.expected_cost) for case in todo}
        self._waiting = dict.fromkeys(self._costs)  # not started yet, dispatch order
        self._waiting_cost = sum(self._costs.values())  # their expected cost, summed
        self._running: dict[str, _Running] = {}
        self._finished: set[str] = set()
        self._measured_seconds = 0.0
        self._measured_cost = 0.0
        for runtime, cost in measured:
            self._measure(runtime, cost)
        use_bar = sys.stderr.isatty() if bar is None else bar
        self._bar = None
        counted, count, unit = (
            (total, done, "case") if searches is None else (*searches[::-1], "search")
        )
        if use_bar and counted > count:
            from tqdm import tqdm

            self._bar = tqdm(
                total=counted, initial=count, unit=unit, dynamic_ncols=True, file=sys.stderr,
                bar_format="{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}{postfix}]",
            )  # fmt: skip
        if searches is not None:
            self.count_searches(*searches)

    # ------------------------------------------------------------------ reports
    def started(self, case_id: str, rank: int) -> None:
        if case_id in self._finished or case_id in self._running:
            return
        self._leave_queue(case_id)
        cost = self._costs.get(case_id, 1.0)
        self._running[case_id] = _Running(case_id, rank, self.clock(), cost)

    def cycle(self, case_id: str, rank: int, cycle: int, cycles: int) -> None:
        if case_id in self._finished:
            return  # a late report of a case that has finished meanwhile
        if case_id not in self._running:
            self.started(case_id, rank)
        running = self._running[case_id]
        running.cycle, running.cycles = int(cycle), int(cycles)

    def update(self, outcome) -> None:
        """A case finished (any status): its line on ``stream``, then a status line."""
        self.done += 1
        status = CaseStatus(outcome.status)
        self.counts[status] = self.counts.get(status, 0) + 1
        self._finished.add(outcome.case_id)
        self._running.pop(outcome.case_id, None)
        self._leave_queue(outcome.case_id)
        if outcome.status == CaseStatus.COMPLETED:
            self._measure(outcome.runtime_s, self._costs.get(outcome.case_id, 1.0))
        count, total = self._searches or (self.counts[CaseStatus.COMPLETED], self.total)
        width = len(str(total))
        text = (
            f"[{count:{width}d}/{total}] {outcome.case_id:<40s} "
            f"rank {outcome.rank:<3d} {outcome.runtime_s:9.2f} s  {outcome.status}"
        )
        if outcome.status == CaseStatus.FAILED and outcome.message:
            text += f": {outcome.message.splitlines()[0]}"
        self.line(text)
        if self._bar is not None and self._searches is None and status == CaseStatus.COMPLETED:
            self._bar.update(1)  # the bar counts completed cases; the others are in its postfix
        self._show_status(force=True)

    def count_searches(self, ended: int, searches: int) -> None:
        """A ``[search]`` study: ``ended`` of its ``searches`` have ended. The ``[k/N]`` of
        each case line and the status lines then count searches (their number is known from
        the start; the steps each takes are not), and so does the bar."""
        self._searches = (int(ended), int(searches))
        if self._bar is not None:
            self._bar.unit = "search"
            self._bar.total = self._searches[1]
            self._bar.n = self._searches[0]
            self._bar.refresh()

    def add(self, case) -> None:
        """A case created while the run goes on (a step of a threshold search): one more to
        do, waiting at the end of the queue."""
        self.total += 1
        self._costs[case.case_id] = float(case.expected_cost)
        self._waiting[case.case_id] = None
        self._waiting_cost += self._costs[case.case_id]
        if self._bar is not None and self._searches is None:  # a search's bar counts searches
            self._bar.total = self.total
            self._bar.refresh()

    def tick(self) -> None:
        """Print (or refresh the bar with) the status if ``interval`` has passed."""
        self._show_status(force=False)

    # ------------------------------------------------------------------ numbers
    def _leave_queue(self, case_id: str) -> None:
        """``case_id`` is no longer waiting (O(1): thousands of cases stay cheap)."""
        if self._waiting.pop(case_id, False) is None:
            self._waiting_cost -= self._costs[case_id]

    def _measure(self, runtime_s: float, cost: float) -> None:
        if runtime_s > 0 and cost > 0:
            self._measured_seconds += float(runtime_s)
            self._measured_cost += float(cost)

    def seconds_per_cost(self) -> float | None:
        """Measured seconds per unit of ``expected_cost`` (None before any completed case)."""
        if self._measured_cost <= 0:
            return None
        return self._measured_seconds / self._measured_cost

    @property
    def stopping(self) -> bool:
        """A case was interrupted: the run stops, no further case starts."""
        return self.counts[CaseStatus.INTERRUPTED] > 0

    def eta_seconds(self) -> float | None:
        """Seconds until the last case should finish (None without a measured case); a lower
        bound when :meth:`overdue` is not empty."""
        rate = self.seconds_per_cost()
        if rate is None:
            return None if (self._running or self._waiting) else 0.0
        now = self.clock()
        free_at = [self._remaining(running, rate, now) for running in self._running.values()]
        free_at += [0.0] * max(self.ranks - len(free_at), 0)
        if len(self._waiting) > EXACT_QUEUE:
            return _balanced_finish(free_at, max(self._waiting_cost, 0.0) * rate)
        heapq.heapify(free_at)
        for case_id in self._waiting:
            heapq.heappush(free_at, heapq.heappop(free_at) + self._costs[case_id] * rate)
        return max(free_at, default=0.0)

    @staticmethod
    def _remaining(running: _Running, rate: float, now: float) -> float:
        """Seconds a running case still needs: its prediction minus the time it has run or,
        past the prediction, the extrapolation of its cycle reports (0 without one)."""
        elapsed = now - running.started
        predicted = running.cost * rate - elapsed
        if predicted > 0.0:
            return predicted
        if running.cycle and running.cycles:
            return elapsed * max(running.cycles - running.cycle, 0) / running.cycle
        return 0.0

    def overdue(self) -> list[str]:
        """Running cases past their prediction with no cycle report to extrapolate from."""
        rate = self.seconds_per_cost()
        if rate is None:
            return []
        now = self.clock()
        return [
            item.case_id
            for item in self._running.values()
            if not (item.cycle and item.cycles) and item.cost * rate <= now - item.started
        ]

    def counts_text(self) -> str:
        """``"3/9 cases completed, 1 failed, 1 interrupted"`` (zero counts left out)."""
        text = f"{self.counts[CaseStatus.COMPLETED]}/{plural(self.total, 'case')} completed"
        if self._searches is not None:  # the cases so far; more follow as searches advance
            ended, searches = self._searches
            text = (
                f"{ended}/{plural(searches, 'search', 'searches')} ended, "
                f"{plural(self.counts[CaseStatus.COMPLETED], 'case')} completed"
            )
        for status in (CaseStatus.FAILED, CaseStatus.INTERRUPTED):
            if self.counts[status]:
                text += f", {self.counts[status]} {status}"
        return text

    def _eta_text(self) -> str:
        """The ETA part of a status line (or why there is none)."""
        if self.stopping:
            unstarted = len(self._waiting)
            return "stopping" + (f", {unstarted} not started" if unstarted else "")
        if not (self._running or self._waiting):
            return "finished"
        eta = self.eta_seconds()
        if eta is None:
            return "ETA after the first completed case"
        overdue = len(self.overdue())
        if not overdue:
            return f"ETA {_remaining(eta)}"
        past = f"{plural(overdue, 'case')} running past the estimate"
        if eta >= 1.0:
            return f"ETA more than {format_duration(eta)} ({past})"
        return f"ETA unknown ({past})"

    def status_text(self, *, short: bool = False) -> str:
        """``3/9 cases completed, 1 failed; running: …; elapsed 2 min 10 s; ETA 5 min 20 s``
        (``short``: the running cases without rank and time, and the ETA, for the postfix of
        the bar, whose counter shows the completed cases)."""
        now = self.clock()
        parts = [] if short else [self.counts_text()]
        if short and self.done > self.counts[CaseStatus.COMPLETED]:
            parts.append(self.counts_text().split(", ", 1)[1])
        running = sorted(self._running.values(), key=lambda item: item.rank)
        if running:
            listed = [self._describe(item, now, short) for item in running[:MAX_LISTED]]
            if len(running) > MAX_LISTED:
                listed.append(f"+{len(running) - MAX_LISTED} more")
            parts.append("running: " + ", ".join(listed))
        if not short:
            parts.append(f"elapsed {format_duration(now - self.start)}")
        parts.append(self._eta_text())
        return "; ".join(parts)

    @staticmethod
    def _describe(item: _Running, now: float, short: bool) -> str:
        where = "" if short else f" (rank {item.rank}, {format_duration(now - item.started)})"
        if item.cycle is None:
            return f"{item.case_id}{where}"
        return f"{item.case_id} cycle {item.cycle:,}/{item.cycles:,}{where}"

    # ------------------------------------------------------------------ output
    def line(self, text: str) -> None:
        """A finished case's line: through the bar while one is drawn, else logged (INFO,
        the logger ``engine.output.progress``), or written to the ``stream`` given."""
        if self._bar is not None:
            self._bar.write(text, file=self.stream or sys.stdout)
        elif self.stream is None:
            LOGGER.info(text)
        else:
            print(text, file=self.stream, flush=True)

    def _show_status(self, *, force: bool) -> None:
        now = self.clock()
        if self._bar is not None:
            if force or now - self._last_status >= 1.0:
                self._bar.set_postfix_str(self.status_text(short=True), refresh=True)
                self._last_status = now
            return
        if self.interval <= 0 or (not force and now - self._last_status < self.interval):
            return
        self._last_status = now
        text = f"progress: {self.status_text()}"
        if self.status_stream is None:  # a status line: stderr on the command line
            LOGGER.info(text, extra={"stream": "stderr"})
        else:
            print(text, file=self.status_stream, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None


class WorkerProgress:
    """A rank > 0's ``CaseRunner.on_progress``: reports to rank 0 by MPI (main thread only).

    The start of a case always; simulated cycles at most every ``min_interval`` seconds.
    """

    def __init__(self, comm, min_interval: float = 5.0, clock=time.monotonic) -> None:
        self.comm = comm
        self.min_interval = min_interval
        self.clock = clock
        self._last = -float("inf")

    def __call__(self, case, cycle: int | None = None, cycles: int | None = None) -> None:
        now = self.clock()
        if cycle is None:
            message = ("start", case.case_id, None, None)
        elif now - self._last >= self.min_interval:
            message = ("cycle", case.case_id, int(cycle), int(cycles))
        else:
            return
        self._last = now
        self.comm.send(message, dest=0, tag=TAG_PROGRESS)


class ProgressChannel:
    """Rank 0's side: the local computing thread's reports (a queue) and the workers' (MPI),
    delivered to a :class:`ProgressReporter` by ``drain()`` from the main thread."""

    def __init__(self, comm, reporter: ProgressReporter) -> None:
        self.comm = comm
        self.reporter = reporter
        self.rank = comm.Get_rank()
        self._local: queue.SimpleQueue = queue.SimpleQueue()

    def local(self, case, cycle: int | None = None, cycles: int | None = None) -> None:
        """``CaseRunner.on_progress`` of rank 0's computing thread (no MPI here)."""
        self._local.put((case.case_id, cycle, cycles))

    def drain(self) -> None:
        """Deliver every pending report, then let the reporter print if it is time."""
        while True:
            try:
                case_id, cycle, cycles = self._local.get_nowait()
            except queue.Empty:
                break
            self._deliver(case_id, self.rank, cycle, cycles)
        if self.comm.Get_size() > 1:
            from mpi4py import MPI

            status = MPI.Status()
            while self.comm.Iprobe(source=MPI.ANY_SOURCE, tag=TAG_PROGRESS, status=status):
                source = status.Get_source()
                _, case_id, cycle, cycles = self.comm.recv(source=source, tag=TAG_PROGRESS)
                self._deliver(case_id, source, cycle, cycles)
        self.reporter.tick()

    def _deliver(self, case_id: str, rank: int, cycle, cycles) -> None:
        if cycle is None:
            self.reporter.started(case_id, rank)
        else:
            self.reporter.cycle(case_id, rank, cycle, cycles)
