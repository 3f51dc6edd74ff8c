"""Progress on rank 0: one line per finished case, and a tqdm bar with ETA on a terminal."""

from __future__ import annotations

import sys
import time
from typing import TextIO


class ProgressReporter:
    """``update(outcome)`` after each case; lines go to ``stream``, the bar to stderr (tty only)."""

    def __init__(
        self, total: int, done: int = 0, *, stream: TextIO | None = None, bar: bool | None = None
    ) -> None:
        self.total = total
        self.done = done
        self.stream = stream or sys.stdout
        self.start = time.perf_counter()
        use_bar = sys.stderr.isatty() if bar is None else bar
        self._bar = None
        if use_bar and total > done:
            from tqdm import tqdm

            self._bar = tqdm(
                total=total, initial=done, unit="case", dynamic_ncols=True, file=sys.stderr
            )

    def line(self, text: str) -> None:
        if self._bar is not None:
            self._bar.write(text, file=self.stream)
        else:
            print(text, file=self.stream, flush=True)

    def update(self, outcome) -> None:
        self.done += 1
        width = len(str(self.total))
        text = (
            f"[{self.done:{width}d}/{self.total}] {outcome.case_id:<40s} "
            f"rank {outcome.rank:<3d} {outcome.runtime_s:9.2f} s  {outcome.status}"
        )
        if outcome.status == "failed" and outcome.message:
            text += f": {outcome.message.splitlines()[0]}"
        self.line(text)
        if self._bar is not None:
            self._bar.update(1)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
