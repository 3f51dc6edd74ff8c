"""Run a function on an existing results file in a child process, under a stop signal and a
time limit.

A damaged HDF5 file can send the HDF5 library into an endless loop (a zeroed block where a
B-tree or heap was: measured on 2 of 19 zeroed 4 KiB blocks of a small results file). Inside
the process that runs it nothing can stop such a loop — HDF5 holds the interpreter, so even
the stop-signal handlers never run. Every read of an existing file before a run starts
(:func:`engine.output.existing.inspect_existing`, the salvage copy) therefore runs in a
child interpreter (``python -m engine.output.isolated``): the parent waits, polling its stop
flag; a stop signal ends the child at once, and so does the time limit, after which the file
counts as damaged beyond reading.

The function and its arguments travel to the child pickled on its standard input, the result
(or the exception raised) back on its standard output. The child imports only the
function's module (no MPI).

The time limit grows with the work done: a file of 80,000 datasets takes minutes to read on a
loaded machine, however small its bytes. The child counts the datasets it has read
(:func:`report_datasets`, called by the readers of every case) in a shared counter, and the
parent allows :data:`PER_DATASET_S` more for each: a read that keeps going is never cut
short, while HDF5 stuck in a loop stops counting and meets the limit.
"""

from __future__ import annotations

import importlib
import os
import pickle
import struct
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = [
    "IsolatedCallStopped",
    "IsolatedCallTimedOut",
    "call_isolated",
    "time_limit_for",
    "report_datasets",
    "PER_DATASET_S",
]

TIME_LIMIT_VARIABLE = "ENGINE_INSPECTION_TIME_LIMIT"
BASE_TIME_LIMIT = 60.0  # s: interpreter start, imports and a small file on a loaded machine
READ_RATE = 20e6  # bytes/s: a pessimistic read (and SHA-256) rate of a cluster file system
# s allowed per dataset read, beyond the limit: verify took 3 ms per dataset of a small
# results file (20 datasets, opening included) at a load average of 9 on 2 cores; 10 ms
# leaves three times that
PER_DATASET_S = 0.01
POLL_INTERVAL = 0.05  # s between looks at the stop flag
COUNTER_VARIABLE = "ENGINE_ISOLATED_COUNTER"  # the child's counter file (a path)
_COUNTER = struct.Struct("<Q")
_counted = {"datasets": 0, "descriptor": None}


class IsolatedCallStopped(RuntimeError):
    """A stop signal arrived while the child ran: it was ended, nothing was changed."""


class IsolatedCallTimedOut(RuntimeError):
    """The child did not finish within its time limit (HDF5 stuck on a damaged file)."""


def time_limit_for(path: Path) -> float:
    """Seconds allowed to read ``path`` in full: ``ENGINE_INSPECTION_TIME_LIMIT`` if set,
    else 60 s plus the file's size at 20 MB/s."""
    configured = os.environ.get(TIME_LIMIT_VARIABLE)
    if configured:
        return float(configured)
    try:
        size = path.stat().st_size
    except OSError:
        size = 0
    return BASE_TIME_LIMIT + size / READ_RATE


def call_isolated(
    function: Callable[..., Any],
    *args: Any,
    should_stop: Callable[[], bool] = lambda: False,
    time_limit: float = BASE_TIME_LIMIT,
    **kwargs: Any,
) -> Any:
    """``function(*args, **kwargs)`` in a child interpreter; its result, or its exception
    raised here.

    Raises :class:`IsolatedCallStopped` when ``should_stop()`` turns true and
    :class:`IsolatedCallTimedOut` after ``time_limit`` seconds (the child is killed in both
    cases)."""
    request = pickle.dumps((_module_name(function), function.__qualname__, args, kwargs))
    with (
        tempfile.TemporaryFile() as reply,
        tempfile.TemporaryFile() as errors,
        tempfile.NamedTemporaryFile(prefix="engine-isolated-") as counter,
    ):
        child = subprocess.Popen(
            [sys.executable, "-m", "engine.output.isolated"],
            stdin=subprocess.PIPE,
            stdout=reply,
            stderr=errors,
            env={**_child_environment(), COUNTER_VARIABLE: counter.name},
        )
        try:
            child.stdin.write(request)
            child.stdin.close()
            _wait(child, should_stop, time_limit, counter.fileno())
            if should_stop():  # the signal may have reached the child first (Ctrl-C)
                raise IsolatedCallStopped("stopped while reading the existing results file")
        finally:
            if child.poll() is None:
                child.kill()
                child.wait()
        reply.seek(0)
        answer = reply.read()
        errors.seek(0)
        last_error = (errors.read().decode(errors="replace").strip().splitlines() or [""])[-1]
    if not answer:
        raise RuntimeError(
            f"the child process reading the file ended with code {child.returncode}: {last_error}"
        )
    kind, value = pickle.loads(answer)
    if kind == "error":
        raise value
    return value


def _module_name(function: Callable[..., Any]) -> str:
    """The importable name of ``function``'s module (also when it runs as ``__main__``)."""
    name = function.__module__
    if name == "__main__":
        spec = getattr(sys.modules["__main__"], "__spec__", None)
        if spec is None:
            raise ValueError(f"{function.__qualname__}: its module cannot be imported by name")
        name = spec.name
    return name


def _wait(
    child: subprocess.Popen,
    should_stop: Callable[[], bool],
    time_limit: float,
    counter: int | None = None,
) -> None:
    """Wait for ``child``: ``time_limit`` s, plus :data:`PER_DATASET_S` for every dataset it
    has reported read in the file ``counter`` (a descriptor) so far."""
    start = time.monotonic()
    while child.poll() is None:
        if should_stop():
            raise IsolatedCallStopped("stopped while reading the existing results file")
        datasets = datasets_read(counter)
        allowed = time_limit + PER_DATASET_S * datasets
        if time.monotonic() - start > allowed:
            raise IsolatedCallTimedOut(
                f"reading it did not finish within {allowed:.0f} s ({datasets} datasets read; "
                "HDF5 is stuck on damaged metadata; a slow file system may need a longer "
                f"{TIME_LIMIT_VARIABLE})"
            )
        time.sleep(POLL_INTERVAL)


def datasets_read(counter: int | None) -> int:
    """The count the child wrote in the counter file (0 before its first report)."""
    if counter is None:
        return 0
    data = os.pread(counter, _COUNTER.size, 0)
    return _COUNTER.unpack(data)[0] if len(data) == _COUNTER.size else 0


def report_datasets(count: int) -> None:
    """In a child of :func:`call_isolated`: ``count`` more datasets have been read (each
    allows the parent's wait :data:`PER_DATASET_S` more). Nothing elsewhere."""
    if count <= 0:
        return
    if _counted["descriptor"] is None:
        path = os.environ.get(COUNTER_VARIABLE)
        if not path:
            return
        try:
            _counted["descriptor"] = os.open(path, os.O_WRONLY)
        except OSError:
            _counted["descriptor"] = -1
    descriptor = _counted["descriptor"]
    _counted["datasets"] += count
    if descriptor >= 0:
        os.pwrite(descriptor, _COUNTER.pack(_counted["datasets"]), 0)


def _child_environment() -> dict[str, str]:
    """The parent's environment, the package importable, one thread for NumPy."""
    env = dict(os.environ)
    env.pop(COUNTER_VARIABLE, None)
    package_root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [package_root, env.get("PYTHONPATH")]))
    env.setdefault("OMP_NUM_THREADS", "1")
    return env


def _serve() -> None:
    """The child: read the request from stdin, answer on stdout."""
    module_name, qualified_name, args, kwargs = pickle.loads(sys.stdin.buffer.read())
    target: Any = importlib.import_module(module_name)
    for name in qualified_name.split("."):
        target = getattr(target, name)
    try:
        answer = ("ok", target(*args, **kwargs))
    except Exception as error:  # noqa: BLE001 - handed to the parent, raised there
        answer = ("error", error)
    sys.stdout.buffer.write(pickle.dumps(answer))
    sys.stdout.buffer.flush()


if __name__ == "__main__":
    _serve()
