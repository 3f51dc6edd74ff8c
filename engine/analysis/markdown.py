"""Generated blocks of the manual: tables written by the code that knows or measures them.

A page of ``docs/`` holds a generated block between two comment lines::

    <!-- BEGIN generated NAME -->
    ...
    <!-- END generated NAME -->

and only the program that owns the block rewrites it (:func:`replace_block`): the reference
generator (``scripts/reference.py``), the benchmarks, ``python -m engine report --update``.
Measured blocks start with :func:`measured_on`, the date and the machine of the measurement,
so that no number in the manual is typed by hand or outlives the run that produced it.
"""

from __future__ import annotations

import datetime
import os
import platform
from collections.abc import Iterable, Sequence
from pathlib import Path

__all__ = ["markdown_table", "measured_on", "read_block", "replace_block"]


def _markers(name: str, kind: str) -> tuple[str, str]:
    return f"<!-- BEGIN {kind} {name} -->", f"<!-- END {kind} {name} -->"


def read_block(document: str | Path, name: str, kind: str = "generated") -> str:
    """The text between the markers of block ``name`` in ``document``.

    Parameters
    ----------
    document : str or pathlib.Path
        The Markdown page.
    name : str
        The block's name, as in ``<!-- BEGIN generated NAME -->``.
    kind : str
        The marker's kind: ``"generated"`` (reference and measured tables) or ``"report"``
        (the tables of ``python -m engine report --update``).

    Returns
    -------
    str
        The block's text, without the marker lines.
    """
    text = Path(document).read_text()
    begin, end = _markers(name, kind)
    if begin not in text or end not in text:
        raise ValueError(f"{document}: no block {begin} … {end}")
    return text.split(begin, 1)[1].split(end, 1)[0].removeprefix("\n")


def replace_block(document: str | Path, name: str, text: str, kind: str = "generated") -> bool:
    """Replace the text between the markers of block ``name`` in ``document`` with ``text``.

    Parameters
    ----------
    document : str or pathlib.Path
        The Markdown page; it must already hold both markers.
    name : str
        The block's name, as in ``<!-- BEGIN generated NAME -->``.
    text : str
        The new content (a final newline is added when missing).
    kind : str
        The marker's kind, ``"generated"`` or ``"report"``.

    Returns
    -------
    bool
        True when the page changed.
    """
    document = Path(document)
    old = document.read_text()
    begin, end = _markers(name, kind)
    if begin not in old or end not in old:
        raise ValueError(f"{document}: no block {begin} … {end}")
    head, rest = old.split(begin, 1)
    _, tail = rest.split(end, 1)
    new = f"{head}{begin}\n{text.rstrip(chr(10))}\n{end}{tail}"
    if new != old:
        document.write_text(new)
    return new != old


def _cell(value: object) -> str:
    return str(value).replace("|", "\\|").replace("\n", " ")


def markdown_table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> str:
    """A Markdown table (GitHub's pipe tables), pipes inside cells escaped.

    Parameters
    ----------
    header : sequence of str
        The column titles.
    rows : iterable of sequences
        One sequence of cells per row, as many as the header; each cell is written with
        ``str``.

    Returns
    -------
    str
        The table's lines, ending with a newline.
    """
    lines = ["| " + " | ".join(_cell(title) for title in header) + " |"]
    lines.append("|" + "|".join(" --- " for _ in header) + "|")
    for row in rows:
        if len(row) != len(header):
            raise ValueError(f"row {row!r} has {len(row)} cells, the header {len(header)}")
        lines.append("| " + " | ".join(_cell(value) for value in row) + " |")
    return "\n".join(lines) + "\n"


def _processor() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def measured_on(note: str = "") -> str:
    """One line that says when and where a measurement ran, for the top of a measured block.

    Parameters
    ----------
    note : str
        Anything else the reader needs, e.g. ``"one core, load 2"``.

    Returns
    -------
    str
        E.g. ``"*Measured 2026-11-25 on Intel Xeon … (2 cores), Linux 6.1, load average 1.9;
        one core.*"``.
    """
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    where = f"{_processor()} ({os.cpu_count()} cores), {platform.system()} {platform.release()}"
    extra = f"; {note}" if note else ""
    return f"*Measured {today} on {where}, load average {load:.1f}{extra}.*\n"
