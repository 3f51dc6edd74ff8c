"""Stop signals caught from the first moment of ``python -m engine``.

Imported by ``engine/__init__.py`` only when the interpreter runs ``python -m engine``, before
anything else of the package loads: a SIGTERM, SIGUSR1 or SIGINT that arrives while the
modules load (0.3–1 s on a busy node) only sets :data:`STOP`, which the command line then
takes over (:func:`engine.cli.main`): a stop at start-up, exit code 3, nothing changed —
not a death by signal. Library use (``import engine``) installs no handlers.

:data:`STOP` is a :class:`engine._stop_flag.StopFlag`, not a :class:`threading.Event`,
which a signal handler cannot set safely (see there).
"""

import signal

from engine._stop_flag import StopFlag

__all__ = ["STOP"]


STOP = StopFlag()

for _name in ("SIGTERM", "SIGUSR1", "SIGINT"):
    signal.signal(getattr(signal, _name), lambda signum, frame: STOP.set())
