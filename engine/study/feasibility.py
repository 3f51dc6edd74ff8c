"""Cases the plan already knows cannot be computed, refused before anything runs.

A case is physically impossible when its settings ask for a state the contact cannot hold:
under force control a tangential force amplitude Q* at or above the largest force the
friction ellipse carries along the loading direction d, h(d)·P with
h(d) = √((μ1 d₁)² + (μ2 d₂)² ) (d in the tribological axes, Eqs. 8–11), makes the punch
slide away (gross sliding has no steady force-controlled cycle). Such a case would fail at
run time after the cases before it had run; :func:`impossible_cases` finds every one of them
from the plan, so the run is refused at once (exit code 2) naming the case ids.
"""

from __future__ import annotations

from .kinds.base import LoadingKind

__all__ = ["impossible_cases", "ImpossibleCases"]


class ImpossibleCases(ValueError):
    """Cases of the plan that cannot be computed (ids and reasons in the message)."""


def impossible_cases(config, plan) -> list[tuple[str, str]]:
    """(case id, reason) of every case of ``plan`` that cannot be computed."""
    kind = config.kind
    if type(kind).check_case is LoadingKind.check_case:  # a kind without case checks
        return []
    found = []
    ends = ("low", "high") if config.search is not None else ("low",)  # a search: both ends
    for case in plan:
        for end in ends:
            try:
                kind.check_case(case, config.for_case(config.at_search_end(case.settings, end)))
            except ValueError as error:
                found.append((case.case_id, str(error)))
                break
    return found


def check_feasible(config, plan) -> None:
    """Raise :class:`ImpossibleCases` listing the impossible cases of ``plan`` (at most ten
    shown in full; the count of the rest)."""
    found = impossible_cases(config, plan)
    if not found:
        return
    shown = "; ".join(f"{case_id}: {reason}" for case_id, reason in found[:10])
    more = f"; and {len(found) - 10} more" if len(found) > 10 else ""
    raise ImpossibleCases(
        f"{len(found)} case(s) of the study cannot be computed: {shown}{more}. Change the sweep "
        "so that every case can be held (nothing was run)"
    )
