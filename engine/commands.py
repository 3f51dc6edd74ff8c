"""What the commands on results files share (``plot``, ``report``, ``verify``).

Each reads one or more results files named on its command line; :func:`results_parser`
starts its parser with that argument and :func:`missing_file` gives the bad-input verdict
(exit 2) for a path that is not a file. The study command itself is :mod:`engine.cli`.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable
from pathlib import Path

__all__ = ["results_parser", "missing_file"]


def results_parser(
    prog: str | None, description: str, results_help: str, *, several: bool = False
) -> argparse.ArgumentParser:
    """A parser whose first argument is the results file (``several``: one or more)."""
    parser = argparse.ArgumentParser(prog=prog, description=description)
    nargs = "+" if several else None
    parser.add_argument("results", type=Path, nargs=nargs, help=results_help)
    return parser


def missing_file(paths: Path | Iterable[Path]) -> bool:
    """Whether one of ``paths`` is not a file; says so on stderr (``error: PATH: no such
    file``) for the first such path."""
    for path in [paths] if isinstance(paths, Path) else paths:
        if not path.is_file():
            print(f"error: {path}: no such file", file=sys.stderr)
            return True
    return False
