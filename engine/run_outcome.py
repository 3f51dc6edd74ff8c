"""What a study run ends as: :class:`StudyRun`, the object :func:`engine.run_study` returns
(its status one of :data:`RUN_STATUSES`), and :class:`StudyError`, what it raises for an
invalid study.

The command line (:mod:`engine.cli`) maps the status to its exit code
(:mod:`engine.exit_codes`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from engine import exit_codes
from engine.output.summary import load_summary

__all__ = ["RUN_STATUSES", "StudyError", "StudyRun"]

#: What a run can end as (StudyRun.status), defined with the exit code of each in
#: engine.exit_codes.
RUN_STATUSES = tuple(status.name for status in exit_codes.RUN_STATUSES)


class StudyError(ValueError):
    """An invalid study or an unusable output: what :func:`run_study` raises unless
    ``check=False``.

    The message is the line the command line prints: the file, the key and the value
    (``demo.toml: [loading] load = -750.0: must be > 0 (N)``).

    Parameters
    ----------
    run : StudyRun
        The run with status ``"invalid"`` (kept as ``error.run``).
    """

    def __init__(self, run: StudyRun) -> None:
        super().__init__(run.message)
        self.run = run


@dataclass(frozen=True)
class StudyRun:
    """The outcome of :func:`run_study`.

    Parameters
    ----------
    status : str
        ``"completed"`` every case completed; ``"failed"`` at least one case failed;
        ``"invalid"`` bad input, unusable output path, output in use by another run or holding
        another study (nothing computed, nothing changed; ``message`` says why);
        ``"interrupted"`` stopped by ``stop_event`` (run again to resume); ``"planned"`` a dry
        run (nothing computed or changed); ``"damaged"`` a case the run wrote cannot be read
        back (run again to recompute it); ``"output-full"`` the output's file system is full
        (completed cases kept; free space and run again to resume; ``message`` names the
        path and the space needed).
    output : pathlib.Path or None
        The results file (None when the study could not be read).
    name : str
        The study's name ("" when the study could not be read).
    cases, completed, failed : int
        Cases of the study; completed and failed ones in the results file after the run.
    wall_time_s : float
        Wall time of the scheduling loop, s (0 when nothing ran).
    message : str
        Why the run is ``"invalid"`` or was interrupted at start-up; "" otherwise.
    plan : tuple of str
        A dry run's report, line by line (what a run would do, one row per case); empty
        otherwise.
    """

    status: str
    output: Path | None = None
    name: str = ""
    cases: int = 0
    completed: int = 0
    failed: int = 0
    wall_time_s: float = 0.0
    message: str = ""
    plan: tuple[str, ...] = ()

    @property
    def summary_path(self) -> Path | None:
        """The summary CSV beside the results file."""
        return None if self.output is None else self.output.with_suffix(".csv")

    @property
    def summary(self):
        """The summary table as a :class:`pandas.DataFrame` (:func:`engine.load_summary`)."""
        if self.output is None:
            raise ValueError(f"no results: the run is {self.status!r} ({self.message})")
        return load_summary(self.output)

    @property
    def ok(self) -> bool:
        """True when every case completed (or, for a dry run, when the study is valid)."""
        return self.status in ("completed", "planned")

    def __str__(self) -> str:
        text = f"StudyRun({self.status}: {self.name!r}, {self.completed}/{self.cases} completed"
        text += f", {self.failed} failed -> {self.output})"
        return text + (f": {self.message}" if self.message else "")
