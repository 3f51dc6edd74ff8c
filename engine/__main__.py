"""``python -m engine STUDY.toml`` — see :mod:`engine.cli`.

mpiexec -n 2 python -m engine studies/demo.toml
"""

import sys

from engine._early_stop import STOP
from engine.cli import main

sys.exit(main(prog="python -m engine", stop_event=STOP))
