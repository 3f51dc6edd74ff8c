"""Running a study with a ``[search]`` section: threshold searches as cases, over all ranks.

Every combination of the ``[sweep]`` gets its own search (:class:`engine.study.search.
SearchCampaign`); each step of a search is an ordinary case (its own group in the results
file, its summary row, resumable). The searches advance **asynchronously** on rank 0: when a
step's outcome arrives, its search proposes its next case at once and it joins the
scheduler's open queue (:class:`engine.parallel.scheduler.CaseQueue`); a free rank takes
whichever search's step is waiting, so with more searches than ranks no rank waits for a
particular search. Rank 0's main thread does all of this between MPI messages (the searches'
bookkeeping costs microseconds per step).

Output strategy: the **single writer**. The collective mpio writer makes every structural
HDF5 call on every rank with identical arguments and therefore pre-creates every case group
from the plan; a search only knows its next case when the previous one has finished. With the
single writer, rank 0 creates each new case's group as the case is created
(:meth:`engine.output.hdf5.SingleWriter.add_case`). A ``[search]`` study asks for
``output_strategy = "auto"`` or ``"single"``; ``"mpio"`` is refused before anything runs.

Resume: the completed cases of the results file are replayed through the searches
(:meth:`SearchCampaign.start`); each search proposes the same steps as before and takes the
stored values, so the run continues where it stopped and ends with the same thresholds, bit
for bit. At the end of every run the cases are put in their canonical order (search by search,
steps in the order taken; ``index`` renumbered) and the thresholds table is written (in the
file and as ``NAME_thresholds.csv``, :mod:`engine.output.thresholds`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from engine.output.thresholds import completed_rows
from engine.parallel.scheduler import CaseQueue
from engine.schema import CaseStatus
from engine.study.config import StudyConfigError
from engine.study.plan import Case, Plan
from engine.study.search import SearchCampaign, SearchStatus

__all__ = [
    "SearchRun",
    "prepare_searches",
    "search_strategy",
    "describe_search",
    "describe_thresholds",
]


def search_strategy(config) -> str:
    """The output strategy of a ``[search]`` study: the single writer (see the module
    docstring); an explicit ``mpio`` is refused, naming the key."""
    if config.study.output_strategy != "mpio":
        return "single"

    raise StudyConfigError(
        config.source,
        "study.output_strategy",
        "mpio",
        "a [search] study creates its cases as its searches advance, which the collective "
        'mpio writer cannot (it pre-creates every case on every rank): use "single" or '
        '"auto"',
    )


@dataclass
class SearchRun:
    """Rank 0's searches of one run: the campaign, the plan known at the start (completed
    steps and the cases to run now) and those cases, in search order."""

    campaign: SearchCampaign
    plan: Plan
    todo: list[Case]

    @property
    def counts(self) -> tuple[int, int]:
        """(ended, searches): how many searches have ended, of how many."""
        searches = self.campaign.searches
        return sum(search.finished for search in searches), len(searches)

    def run(self, scheduler, writer, progress, on_outcome: Callable[[Any], None], on_poll=None):
        """Hand out the steps until every search has ended (or a stop): each outcome goes to
        its search, then to ``on_outcome`` (the writer, the progress display, which counts
        the searches ended: their number is known from the start, the steps are not); the
        search's next case is then created in the file (``writer.add_case``), counted
        (``progress.add``) and queued. Returns the scheduler's report."""
        campaign = self.campaign
        queue = CaseQueue(self.todo, open=not campaign.finished)

        def handle(outcome) -> None:
            created = []
            if outcome.status in (CaseStatus.COMPLETED, CaseStatus.FAILED):
                created = campaign.record(outcome.case_id, outcome.row)
            progress.count_searches(*self.counts)  # [k/N] counts searches
            on_outcome(outcome)
            for case in created:
                writer.add_case(case)
                progress.add(case)
                queue.put(case)
            if campaign.finished:
                queue.close()

        progress.count_searches(*self.counts)
        return scheduler.run(queue, handle, on_poll=on_poll)

    def finish(self, writer) -> str:
        """Canonical order of the cases, then the thresholds table; returns a line saying
        how the searches ended."""
        writer.arrange(Plan(tuple(self.campaign.cases())))
        table = self.campaign.table()
        writer.write_thresholds(table, self.campaign.spec)
        return describe_thresholds(table, self.campaign.spec)


def prepare_searches(config, base_plan: Plan, *, fresh: bool) -> SearchRun:
    """Rank 0, before the writer prepares the file: replay the completed cases of the
    results file being resumed (none with ``fresh``) through the study's searches."""
    campaign = SearchCampaign(config.search, base_plan, config.sweep.swept_keys)
    rows = {} if fresh else completed_rows(config.study.output)
    todo = campaign.start(rows)
    return SearchRun(campaign, Plan(tuple(campaign.cases())), todo)


def describe_thresholds(table: list[dict[str, Any]], spec) -> str:
    """One line for the end of the run: how many searches converged, and the others."""
    statuses = [row["status"] for row in table]
    converged = statuses.count(SearchStatus.CONVERGED)
    text = f"thresholds of {spec.parameter}: {converged} of {len(table)} searches converged"
    others = sorted(set(statuses) - {SearchStatus.CONVERGED})
    if others:
        text += " (" + ", ".join(f"{statuses.count(s)} {s}" for s in others) + ")"
    return text


def describe_search(searches: SearchRun) -> str:
    """What a dry run says of the searches: how many, what they look for, where they stand."""
    spec = searches.campaign.spec
    ended = sum(search.finished for search in searches.campaign.searches)
    target = (
        f"{spec.column} = {spec.target!r}"
        if spec.categorical
        else (f"{spec.column} reaches {spec.target:g}")
    )
    return (
        f"{len(searches.campaign.searches)} searches (one per combination of the sweep): "
        f"{spec.parameter} from {spec.low:g} to {spec.high:g} until {target} ({spec.method}, "
        f"rtol {spec.rtol:g}, atol {spec.atol:g}); {ended} ended. The cases listed are those "
        "known now (completed steps and each search's next); more follow as the searches "
        "advance"
    )
