"""``python -m engine STUDY.toml`` — see :mod:`engine.cli`.

.venv/bin/mpiexec -n 2 .venv/bin/python -m engine studies/demo.toml

Stop signals are caught from the first moment (:mod:`engine._early_stop`). A Python without
the engine's dependencies (the system's, say) gets one paragraph saying which interpreter
ran, what it lacks and what to type instead (:mod:`engine.interpreter`, checked first thing
by :func:`engine.cli.main`).
"""

import sys

from engine._early_stop import STOP
from engine._streams import tolerate_full_console
from engine.interpreter import environment_error

tolerate_full_console()  # a console on a full disk loses lines, never the exit code

try:
    from engine.cli import main

    code = main(prog="python -m engine", stop_event=STOP)
except ImportError as error:  # present but broken, e.g. mpi4py without its MPI library
    print(environment_error([error.name or "?"], sys.argv[1:], str(error)), file=sys.stderr)
    code = 2
sys.exit(code)
