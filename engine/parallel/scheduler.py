"""Dynamic master–worker scheduling of cases over a communicator; rank 0 computes too.

Who runs which case is decided at run time: a rank that finishes a case receives the next one,
so slow cases (low friction slips more, Section 7.2) never leave the other ranks idle. The plan
is handed out most-expensive-first (see ``Plan.dispatch_order``) to shorten the tail.

How rank 0 computes and dispatches at the same time
---------------------------------------------------
On rank 0 the *main thread* is the dispatcher and a *helper thread* computes cases. Every MPI
call is made by the main thread (MPI initialised with ``MPI_THREAD_FUNNELED`` is enough), and
the helper thread talks to the dispatcher through two ``queue.Queue`` objects only. Why this way
round:

- the dispatcher answers workers within ~10 ms even while rank 0 is in a long solve, so no
  worker waits for rank 0 to reach a "poll point" (a static case has none);
- Python runs signal handlers in the main thread; the dispatcher loop sleeps in short slices,
  so a SIGTERM is seen at once and stop requests go out immediately;
- no rank ever sits in a blocking ``MPI_Recv`` (MPICH busy-polls inside it, which would steal
  the core of the computing thread): every wait is ``Iprobe`` + short sleep;
- the numerical work (NumPy/pyFFTW) releases the GIL, so the dispatcher costs almost nothing.

Workers (ranks > 0) compute in their main thread. Their ``should_stop`` checks the local stop
event (set by a signal handler) and probes for a ``stop`` message from rank 0.

Protocol (pickled tuples; one tag per direction so messages stay in order):
worker → 0: ``("ready", None)``, ``("result", outcome)``, ``("returned", case)`` (stop arrived
before the case started); 0 → worker: ``("task", case)``, ``("stop", None)``, ``("exit", None)``.
A worker computes its tasks in the order they came; rank 0 keeps one task (more for short
cases, see :class:`_Dispatcher`) with each worker and sends ``exit`` once it holds none.

Stopping (SIGTERM/SIGUSR1 on any rank — also on a worker alone, which then interrupts its
case and returns those it holds — or an interrupted case anywhere): rank 0 hands out no more cases,
sends ``stop`` to the busy workers, waits for their (interrupted) outcomes, and tells every
worker to exit. An exception escaping ``run_case`` propagates to the caller; the entry point
aborts the communicator so no rank is left waiting (see ``engine.cli``).
"""

from __future__ import annotations

import math
import os
import queue
import socket
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

from engine.schema import CaseStatus

__all__ = ["Scheduler", "SchedulerReport", "PeerDied", "CaseQueue"]

TAG_TO_MASTER = 71
TAG_TO_WORKER = 72
INTERRUPTED = CaseStatus.INTERRUPTED


@dataclass
class SchedulerReport:
    """What happened on this rank (rank 0 also knows the whole study)."""

    rank: int
    size: int
    stopped: bool = False
    statuses: dict[str, str] = field(default_factory=dict)  # rank 0 only: case_id -> status
    not_started: list[str] = field(default_factory=list)  # rank 0 only
    cases_per_rank: dict[int, int] = field(default_factory=dict)  # rank 0 only
    wall_time_s: float = 0.0


class CaseQueue:
    """The cases still to hand out, for a run whose cases are not all known at the start.

    A threshold search creates its next case when the previous one's outcome arrives: the
    caller keeps the queue ``open``, puts new cases (:meth:`put`) from its outcome handler
    (rank 0, main thread) and closes it (:meth:`close`) when no more will come. Meanwhile a
    rank that asks for a case while the queue is empty waits (it is not told to exit); it
    gets the next case put.
    A plain list passed to :meth:`Scheduler.run` is a closed queue.
    """

    def __init__(self, cases: Iterable[Any] = (), *, open: bool = False) -> None:
        self.cases: deque = deque(cases)
        self.open = open

    def put(self, case: Any) -> None:
        self.cases.append(case)

    def close(self) -> None:
        self.open = False

    def __len__(self) -> int:
        return len(self.cases)


_WAIT = object()  # _Dispatcher._next_case: none now, but the open queue may get one
SHORT_CASE_S = 1.0  # s: a worker whose last case ran shorter gets its next ones ahead
AHEAD_S = 0.1  # s of short cases a worker holds beyond its running one (at least one)
MOST_AHEAD = 8  # cases a worker holds at most


class _LocalWorker(threading.Thread):
    """Rank 0's computing thread: takes cases from ``inbox``, puts outcomes in ``outbox``."""

    def __init__(self, run_case, should_stop, rank: int) -> None:
        super().__init__(name="engine-local-worker", daemon=True)
        self.run_case, self.should_stop, self.rank = run_case, should_stop, rank
        self.inbox: queue.Queue = queue.Queue()
        self.outbox: queue.Queue = queue.Queue()

    def run(self) -> None:
        while (case := self.inbox.get()) is not None:
            if self.should_stop():
                self.outbox.put(("returned", case))
                continue
            try:
                outcome = self.run_case(case, self.should_stop)
                outcome.rank = self.rank
                self.outbox.put(("result", outcome))
            except BaseException as error:  # noqa: BLE001 - re-raised by the dispatcher
                self.outbox.put(("error", (error, traceback.format_exc())))
                return


class PeerDied(RuntimeError):
    """A rank this one waits for no longer exists (SIGKILL, OOM killer): the job must end."""


class PeerWatch:
    """Notices a dead peer on the same host while waiting for it, about once a second.

    ``peers``: (pid, host) of every rank, from one ``allgather`` at start-up. MPI has no
    portable way to see a dead peer, and a launcher that does not clean up (``srun`` without
    ``--kill-on-bad-exit``, ``mpiexec -disable-auto-cleanup``) would leave the job waiting
    forever; a process of the same host can be checked directly (gone, or a zombie). Ranks on
    other hosts are left to the launcher.
    """

    def __init__(self, rank: int, peers: list[tuple[int, str]] | None, interval: float = 1.0):
        self.interval = interval
        self._next = time.monotonic() + interval
        host = socket.gethostname()
        self.local = {
            other: pid
            for other, (pid, peer_host) in enumerate(peers or [])
            if other != rank and peer_host == host and pid != os.getpid()
        }

    def check(self, busy_or_alive: set[int]) -> None:
        if not self.local or time.monotonic() < self._next:
            return
        self._next = time.monotonic() + self.interval
        for rank in busy_or_alive:
            pid = self.local.get(rank)
            if pid is not None and not _process_exists(pid):
                raise PeerDied(f"rank {rank} (pid {pid}) died; ending the job")


def _process_exists(pid: int) -> bool:
    """True while ``pid`` runs (a zombie — dead, not yet reaped — counts as gone)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().rpartition(")")[2].split()[0] not in ("Z", "X")
    except OSError:
        return True


class Scheduler:
    """Run cases over ``comm`` with ``run_case(case, should_stop) -> outcome``.

    ``outcome`` needs a ``status`` (``"interrupted"`` means stopped early) and a writable
    ``rank``; cases need a ``case_id``. ``stop_event`` is set by the caller (e.g. a signal
    handler) to stop handing out cases and interrupt the running ones.
    """

    def __init__(
        self,
        comm,
        run_case: Callable[[Any, Callable[[], bool]], Any],
        *,
        stop_event: threading.Event | None = None,
        poll_interval: float = 0.01,
        peers: list[tuple[int, str]] | None = None,
    ) -> None:
        self.comm = comm
        self.run_case = run_case
        self.stop_event = stop_event or threading.Event()
        self.poll_interval = poll_interval
        self.rank = comm.Get_rank()
        self.size = comm.Get_size()
        self.watch = PeerWatch(self.rank, peers)

    def run(
        self,
        cases: Iterable[Any] | CaseQueue | None = None,
        on_outcome: Callable[[Any], None] | None = None,
        on_poll: Callable[[], None] | None = None,
    ) -> SchedulerReport:
        """Rank 0: pass the cases (dispatch order, or a :class:`CaseQueue` that grows while
        the run goes on) and the outcome handler; others: nothing.

        ``on_poll()`` (rank 0, main thread) is called once per pass of the dispatch loop, i.e.
        about every ``poll_interval`` seconds: the progress display drains its reports there.
        """
        start = time.perf_counter()
        if self.rank == 0:
            queue_ = cases if isinstance(cases, CaseQueue) else CaseQueue(cases or [])
            report = self._dispatch(queue_, on_outcome or (lambda outcome: None), on_poll)
        else:
            report = self._work()
        report.wall_time_s = time.perf_counter() - start
        return report

    # ------------------------------------------------------------------ rank 0
    def _dispatch(
        self,
        cases: CaseQueue,
        on_outcome: Callable[[Any], None],
        on_poll: Callable[[], None] | None = None,
    ) -> SchedulerReport:
        return _Dispatcher(self, cases, on_outcome, on_poll).run()

    # ------------------------------------------------------------------ ranks > 0
    def _work(self) -> SchedulerReport:
        report = SchedulerReport(self.rank, self.size)
        self._tasks: deque = deque()  # cases received, not yet started (in order)
        # Not blocking sends: a result too large to go eagerly waits for rank 0 to take it,
        # and MPICH would spin meanwhile (a core taken from the ranks with work); the next
        # case (sent ahead, see _Dispatcher) is computed in the meantime.
        sends = [self.comm.isend(("ready", None), dest=0, tag=TAG_TO_MASTER)]
        while self._receive_instructions(wait=not self._tasks):
            case = self._tasks.popleft()
            if self.stop_event.is_set():
                message = ("returned", case)
            else:
                outcome = self.run_case(case, self._should_stop)
                outcome.rank = self.rank
                message = ("result", outcome)
            sends = [request for request in sends if not request.Test()]
            sends.append(self.comm.isend(message, dest=0, tag=TAG_TO_MASTER))
        _wait_patiently(sends)
        report.stopped = self.stop_event.is_set()
        return report

    def _receive_instructions(self, *, wait: bool) -> bool:
        """Take every instruction that has arrived: tasks join ``_tasks``, a stop sets the
        stop event. ``wait`` (an idle rank: it holds no task): first wait (Iprobe + sleep,
        never a busy blocking receive) for a task or for exit. False when rank 0 says exit
        (it does so only when this rank holds no case).

        A rank in the middle of a case never waits here: a stop that arrives while it
        holds no task ahead leaves it to end its case and send the outcome, which rank 0
        waits for before it says exit."""
        delay = 0.0005
        while True:
            if self.comm.Iprobe(source=0, tag=TAG_TO_WORKER):
                kind, payload = self.comm.recv(source=0, tag=TAG_TO_WORKER)
                if kind == "exit":
                    return False
                if kind == "stop":
                    self.stop_event.set()
                else:
                    self._tasks.append(payload)
                wait = wait and not self._tasks
                delay = 0.0005
                continue
            if not wait:
                return True
            self.watch.check(busy_or_alive={0})
            time.sleep(delay)
            delay = min(2 * delay, self.poll_interval)

    def _should_stop(self) -> bool:
        """Called by the solver between cycles: local signal, or a stop message from rank 0
        (a task sent ahead meanwhile is kept for later)."""
        if not self.stop_event.is_set() and not self._receive_instructions(wait=False):
            raise RuntimeError(f"rank {self.rank}: told to exit during a case")
        return self.stop_event.is_set()


def cases_to_hold(runtime_s: float | None) -> int:
    """How many cases a worker should hold (running and waiting) when its last case ran
    ``runtime_s`` (None: unknown): one for a long or unknown case; for a short one enough to
    cover :data:`AHEAD_S` beyond the running case, at most :data:`MOST_AHEAD`."""
    if runtime_s is None or not runtime_s < SHORT_CASE_S:
        return 1
    return min(MOST_AHEAD, 1 + math.ceil(AHEAD_S / max(float(runtime_s), 1e-6)))


def _wait_patiently(requests: list) -> None:
    """Wait for ``requests`` (sends) to complete, sleeping between looks (no spinning)."""
    delay = 0.0005
    while requests:
        requests = [request for request in requests if not request.Test()]
        if requests:
            time.sleep(delay)
            delay = min(2 * delay, 0.01)


class _Dispatcher:
    """Rank 0's side of one :meth:`Scheduler.run`: hands ``cases`` out to the worker
    ranks and to rank 0's own computing thread as each becomes free, settles every message
    before handing out the next case, then delivers outcomes to ``on_outcome`` (writing may
    take a while: the rank that computed a case already has its next one). With an open
    :class:`CaseQueue`, a rank asking while it is empty waits in ``parked`` (rank 0's own
    thread in ``local_parked``) until a case is put or the queue closes.

    Short cases (the worker's last one ran less than :data:`SHORT_CASE_S`) go out ahead
    (:func:`cases_to_hold`): such a worker holds its running case and the next ones, so it
    starts the next at once instead of waiting for rank 0's answer, which may come only after
    rank 0 has written other cases or computed one of its own. Long cases go out one at a
    time, so no case waits behind a long one while another rank is free.

    Rank 0 computes only what its writing leaves time for: its computing thread gets its next
    case when no worker's message is waiting. With many short cases the single writer is
    rank 0's main load; a case computed there would delay the answers to every worker, and
    the results sent ahead would pile up unwritten at the end of the run.
    """

    def __init__(self, scheduler: Scheduler, cases, on_outcome, on_poll) -> None:
        self.scheduler, self.comm, self.rank = scheduler, scheduler.comm, scheduler.rank
        self.stop_event = scheduler.stop_event
        self.on_outcome, self.on_poll = on_outcome, on_poll
        self.report = SchedulerReport(scheduler.rank, scheduler.size)
        self.pending = cases
        self.busy: dict[int, deque] = {}  # rank -> its cases handed out, oldest first
        self.holds: dict[int, int] = {}  # worker -> cases it should hold (default 1)
        self.parked: deque[int] = deque()  # workers waiting for the open queue
        self.local_parked = False
        self.local_hungry = False  # rank 0's thread is free; fed once no worker waits
        self.workers_alive = set(range(1, scheduler.size))
        self.stop_sent: set[int] = set()
        self.local = _LocalWorker(scheduler.run_case, self.stop_event.is_set, self.rank)
        self.local_alive = True

    def run(self) -> SchedulerReport:
        self.status = self.any_source = None  # alone (no workers): no message to probe
        if self.workers_alive:
            from mpi4py import MPI

            self.status = MPI.Status()
            self.any_source = MPI.ANY_SOURCE
        self.local.start()
        self._feed_local()
        while self.local_alive or self.rank in self.busy or self.workers_alive:
            if self.on_poll is not None:
                self.on_poll()
            if self.stop_event.is_set():
                self._send_stops()
            self._feed_parked()
            progressed = self._service_local()
            progressed = self._service_workers() or progressed
            if self.local_hungry and not self._worker_waiting():
                self.local_hungry = False
                self._feed_local()
            if not progressed:
                self._idle()
        self.local.join()
        self.report.stopped = self.stop_event.is_set()
        self.report.not_started = [case.case_id for case in self.pending.cases]
        return self.report

    def _next_case(self):
        """The next case; None: none will come (stop, or the queue is empty and closed);
        ``_WAIT``: none now, the open queue may get one."""
        if self.stop_event.is_set():
            return None
        if not self.pending.cases:
            return _WAIT if self.pending.open else None
        return self.pending.cases.popleft()

    def _feed_parked(self) -> None:
        """Hand the cases put since the waiting ranks asked (or exit once none will come)."""
        for source in [source for source in self.parked if self._next_case_ready()]:
            self.parked.remove(source)
            self._top_up(source)
        if self.local_parked and self._next_case_ready():
            self.local_parked = False
            self._feed_local()
        idle = not self.busy and not self.pending.cases and not self.stop_event.is_set()
        if self.pending.open and idle:
            raise RuntimeError("the case queue is open but no case runs that could add one")

    def _next_case_ready(self) -> bool:
        return self.stop_event.is_set() or bool(self.pending.cases) or not self.pending.open

    def _top_up(self, source: int) -> None:
        """Send worker ``source`` cases until it holds as many as it should (one, or two
        for short cases); exit once it holds none and none will come; park it while it
        holds none and the open queue is empty."""
        held = self.busy.get(source, ())
        while len(held) < self.holds.get(source, 1):
            case = self._next_case()
            if case is None or case is _WAIT:
                if not held and case is None:
                    self.comm.send(("exit", None), dest=source, tag=TAG_TO_WORKER)
                    self.workers_alive.discard(source)
                elif not held:
                    self.parked.append(source)
                return
            held = self.busy.setdefault(source, deque())
            held.append(case)
            self.comm.send(("task", case), dest=source, tag=TAG_TO_WORKER)

    def _settle(self, rank: int, kind: str, payload: Any) -> bool:
        """Bookkeeping of a message (cheap, before the next case is handed out); True when
        it carries an outcome to deliver."""
        held = self.busy[rank]
        case = held.popleft()  # a rank computes its cases in the order it received them
        if not held:
            del self.busy[rank]
        if kind == "returned":  # the worker was stopped (its own signal): the job stops
            self.pending.cases.appendleft(case)
            self.stop_event.set()
            return False
        if payload.status == INTERRUPTED:
            self.stop_event.set()
        if rank != self.rank:
            self.holds[rank] = cases_to_hold(getattr(payload, "runtime_s", None))
        return True

    def _deliver(self, rank: int, payload: Any) -> None:
        """Record and hand on an outcome."""
        self.report.statuses[payload.case_id] = payload.status
        self.report.cases_per_rank[rank] = self.report.cases_per_rank.get(rank, 0) + 1
        self.on_outcome(payload)

    def _feed_local(self) -> None:
        case = self._next_case()
        if case is _WAIT:
            self.local_parked = True
        elif case is None:
            self.local.inbox.put(None)
            self.local_alive = False
        else:
            self.busy[self.rank] = deque([case])
            self.local.inbox.put(case)

    def _service_local(self, timeout: float | None = None) -> bool:
        """Collect rank 0's own outcome if there is one (waiting up to ``timeout``), give the
        computing thread its next case at once unless a worker's message waits (then later,
        see ``local_hungry``), then deliver the outcome."""
        try:
            if timeout is None:
                kind, payload = self.local.outbox.get_nowait()
            else:
                kind, payload = self.local.outbox.get(timeout=timeout)
        except queue.Empty:
            return False
        if kind == "error":
            error, text = payload
            raise RuntimeError(f"rank {self.rank}: run_case raised\n{text}") from error
        has_outcome = self._settle(self.rank, kind, payload)
        if self._worker_waiting() and not self.stop_event.is_set():
            self.local_hungry = True
        else:
            self._feed_local()
        if has_outcome:
            self._deliver(self.rank, payload)
        return True

    def _worker_waiting(self) -> bool:
        """A worker's message waits to be answered."""
        return bool(self.workers_alive) and self.comm.Iprobe(
            source=self.any_source, tag=TAG_TO_MASTER
        )

    def _send_stops(self) -> None:
        for rank in [r for r in self.busy if r != self.rank and r not in self.stop_sent]:
            self.comm.send(("stop", None), dest=rank, tag=TAG_TO_WORKER)
            self.stop_sent.add(rank)
        if self.local_hungry:  # a stop: the computing thread is told to end
            self.local_hungry = False
            self._feed_local()

    def _service_workers(self) -> bool:
        """Answer every waiting worker message: settle it, send the worker its next case (or
        exit), then deliver its outcome; True when there was one."""
        progressed = False
        status = self.status
        while self.workers_alive and self.comm.Iprobe(
            source=self.any_source, tag=TAG_TO_MASTER, status=status
        ):
            progressed = True
            source = status.Get_source()
            kind, payload = self.comm.recv(source=source, tag=TAG_TO_MASTER)
            has_outcome = kind in ("result", "returned") and self._settle(source, kind, payload)
            self._top_up(source)
            if has_outcome:
                self._deliver(source, payload)
            self._service_local()  # rank 0's own outcomes are delivered as they come
        return progressed

    def _idle(self) -> None:
        """Nothing happened: check the peers, then wait. A worker waiting for its next case
        idles, so answer within ~2 ms (an Iprobe costs microseconds); with no workers left,
        only rank 0's own case matters, and its completion wakes the wait."""
        scheduler = self.scheduler
        scheduler.watch.check(busy_or_alive=set(self.busy) | self.workers_alive)
        interval = scheduler.poll_interval
        wait = min(interval, 0.002) if self.workers_alive else interval
        if self.rank in self.busy:
            self._service_local(timeout=wait)
        else:
            time.sleep(wait)
