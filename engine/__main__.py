"""``python -m engine STUDY.toml`` — see :mod:`engine.cli`.

.venv/bin/mpiexec -n 2 .venv/bin/python -m engine studies/demo.toml

A Python without the engine's dependencies (the system's, say) gets one paragraph saying
which interpreter ran, what it lacks and what to type instead (:mod:`engine.interpreter`).
"""

import sys

from engine.interpreter import check_interpreter, environment_error

if code := check_interpreter(sys.argv[1:]):
    sys.exit(code)
try:
    from engine.cli import main

    code = main(prog="python -m engine")
except ImportError as error:  # present but broken, e.g. mpi4py without its MPI library
    print(environment_error([error.name or "?"], sys.argv[1:], str(error)), file=sys.stderr)
    code = 2
sys.exit(code)
