"""What a dry run says: the study, its output, what would happen to an existing results file,
and one row per case with its parameters, its place in the dispatch order and its action.

:func:`plan_report` builds the text from what :func:`engine.run.run_study` found out before
anything is written (the configuration, the plan, the look at the existing file); it reads,
never writes. The case table's columns are the friction coefficients, the coefficients the
study's wear law declares (:data:`engine.solvers.wear_laws.WEAR_LAWS`), β, then one per key
the plan sweeps.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from engine.output.progress import plural
from engine.output.summary import column_unit
from engine.searching import describe_search, prepare_searches
from engine.solvers.wear_laws import WEAR_LAWS, fixed_coefficients

__all__ = [
    "DryRun",
    "plan_report",
    "idle_ranks_warning",
    "resumed_cases_line",
    "loading_description",
]

#: The dry run's word for a case the run would skip.
SKIP = "complete: skip"


def idle_ranks_warning(cases: int, ranks: int) -> str | None:
    """Every rank, rank 0 included, computes one case at a time: ranks beyond the number of
    cases to run have nothing to do."""
    if cases == 0 or ranks <= cases:
        return None
    return (
        f"warning: {plural(ranks, 'rank')} for {plural(cases, 'case')} to run: "
        f"{plural(ranks - cases, 'rank')} will stay idle (each rank computes one case at a "
        f"time; use at most {cases})"
    )


@dataclass(frozen=True)
class DryRun:
    """A dry run's report: the ``summary`` lines (the study, its output, what happens to an
    existing file, how many cases would run), the ``warning`` when ranks would stay idle
    (None otherwise) and the case ``table`` (a header and one row per case)."""

    summary: tuple[str, ...]
    warning: str | None
    table: tuple[str, ...]

    @property
    def lines(self) -> tuple[str, ...]:
        """The whole report, in order."""
        return self.summary + ((self.warning,) if self.warning else ()) + self.table


_NAMED_CASES = 8  # case ids named in a line; the rest are counted


def resumed_cases_line(checkpoint_dir: Path, case_ids: Sequence[str]) -> str | None:
    """The line naming the cases of ``case_ids`` (to run now) that continue from a saved
    state, ``<checkpoint_dir>/<case_id>.npz``; None when every one starts from the beginning."""
    resumed = [case_id for case_id in case_ids if (checkpoint_dir / f"{case_id}.npz").exists()]
    if not resumed:
        return None
    shown = ", ".join(resumed[:_NAMED_CASES]) + (" …" if len(resumed) > _NAMED_CASES else "")
    verb = (
        "continues from its checkpoint" if len(resumed) == 1 else "continue from their checkpoints"
    )
    return f"{plural(len(resumed), 'case')} {verb} ({checkpoint_dir}): {shown}"


def plan_report(config, plan, strategy: str, existing, fresh: bool, ranks: int) -> DryRun:
    """What a run with the same options would do (``existing``: the look at the existing
    results file, None without one or with ``fresh``)."""
    output = config.study.output
    lines = [
        f"study {config.study.name!r} ({config.source}): {plural(len(plan), 'case')}, "
        + loading_description(config, plan),
        f"output {output} = {output.resolve()} (summary {config.study.summary_path}), "
        f"{strategy} writer",
    ]
    if existing is not None and existing.kind != "resume":
        lines += existing.notes()  # damaged: what a run would do with it
    states = _planned_states(config, plan, existing, fresh)
    if config.search is not None:  # the cases known now: completed steps, the next ones
        searches = prepare_searches(config, plan, fresh=fresh)
        lines.append(describe_search(searches))
        plan, waiting = searches.plan, {case.case_id for case in searches.todo}
        fresh_states = _planned_states(config, plan, None, False)  # run, or from a checkpoint
        states = {
            case_id: fresh_states[case_id] if case_id in waiting else SKIP
            for case_id in plan.case_ids
        }
    if fresh:
        present = [
            str(path)
            for path in (output, config.study.summary_path, config.study.checkpoint_dir)
            if path.exists()
        ]
        deleted = ", ".join(present) if present else "nothing (none exists)"
        lines.append(f"--fresh would delete: {deleted}")
    todo = [case for case in plan.dispatch_order() if states[case.case_id] != SKIP]
    lines.append(
        f"would run {plural(len(todo), 'case')} on {plural(ranks, 'rank')}; "
        f"{len(plan) - len(todo)} complete and skipped"
    )
    table = case_table(plan, todo, states, config.sweep.swept_keys)
    return DryRun(tuple(lines), idle_ranks_warning(len(todo), ranks), tuple(table))


def _values(plan, key: str) -> list:
    """The distinct values of parameter ``key`` over the cases of ``plan``, sorted."""
    values = {case.parameters().get(key) for case in plan}
    return sorted(value for value in values if value is not None)


def _shown(value, form: str = "g") -> str:
    """A value in ``form`` (a number) or as it is (a text: a swept ``surface.path`` …)."""
    return value if isinstance(value, str) else format(value, form)


def _range_text(values: Sequence[float], unit: str = "", form: str = "g") -> str:
    """``"750 N"``, ``"250, 500, 750 N"`` (up to four values), ``"250 … 1000 N (7 values)"``
    (``form``: the format of each value)."""
    suffix = f" {unit}" if unit and unit != "1" else ""
    if len(values) > 4:
        first, last = _shown(values[0], form), _shown(values[-1], form)
        return f"{first} … {last}{suffix} ({len(values)} values)"
    return ", ".join(_shown(value, form) for value in values) + suffix


def loading_description(config, plan) -> str:
    """One line on the loading of a study: each value as swept over the plan (the range of a
    swept key, not only its first value), then the ranges of every swept parameter; one the
    user did not sweep but that follows another (mu2 = mu1) is named beside it."""

    def value(name: str, first, unit: str, form: str = "g") -> str:
        key = f"loading.{name}"
        return _range_text(_values(plan, key) if key in swept else [first], unit, form)

    swept = set(config.sweep.swept_keys)
    line = config.punch.is_line  # a line contact's loads per unit length
    what = config.kind.describe(config, value)
    rules = _followers(config.sweep)
    ranges = []
    for key in (*_parameter_names(config), *config.sweep.swept_keys):
        values = _values(plan, key)
        if len(values) < 2:
            continue
        text = f"{key} = {_range_text(values, column_unit(key, line))}"
        if key in rules:  # not swept: it follows its rule, named beside the key it follows
            leader, rule = rules[key]
            if len(_values(plan, leader)) > 1:
                continue
            text = f"{key} = {rule} = {_range_text(values, column_unit(key, line))}"
        text += "".join(
            f", {follower} = {rule}" for follower, (leader, rule) in rules.items() if leader == key
        )
        ranges.append(text)
    return what + ("; swept: " + "; ".join(ranges) if ranges else "")


def _followers(sweep) -> dict[str, tuple[str, str]]:
    """The parameters the user did not sweep that follow another: (the one followed, the
    rule) by name (``[sweep] mu2`` absent: mu2 = mu1; a wear law's derived coefficients,
    :meth:`engine.solvers.wear.WearModel.followers`: Archard's ``wear2`` absent: wear1,
    ``"proportional"``: wear1·mu2/mu1). The dry run names them beside the parameter they
    follow, not as swept."""
    rules = {}
    if sweep.mu2 is None:
        rules["mu2"] = ("mu1", "mu1")
    rules.update(WEAR_LAWS[sweep.law].followers(sweep.wear_lists))
    return rules


def _parameter_names(config) -> list[str]:
    """The case parameters in the order of the case attributes: mu1, mu2, the default law's
    coefficients, beta, then the study's law's own."""
    own = [name for name in WEAR_LAWS[config.sweep.law].coefficients]
    fixed = list(fixed_coefficients())
    return ["mu1", "mu2", *fixed, "beta", *(name for name in own if name not in fixed)]


def case_table(plan, todo, states, swept: Sequence[str]) -> list[str]:
    """One row per case: the friction coefficients, the wear coefficients its law uses (four
    significant digits in 10 characters), β, one column per swept dotted key (headed by the
    key), the dispatch order and the action."""
    order = {case.case_id: number for number, case in enumerate(todo, start=1)}
    wear = list(WEAR_LAWS[plan.cases[0].law].coefficients) if len(plan) else []
    columns = [(name, 6, "g") for name in ("mu1", "mu2")]
    columns += [(name, 10, ".4g") for name in wear]
    columns += [("beta", 6, "g")]
    columns += [
        (key, max(len(key), *(len(_shown(case.parameters()[key])) for case in plan)), "g")
        for key in swept
    ]
    header = "".join(f" {name:>{width}s}" for name, width, _ in columns)
    lines = [f"{'case_id':<40s}{header}  order  action"]
    for case in plan:
        number = order.get(case.case_id)
        values = case.parameters()
        cells = "".join(f" {_shown(values[name], form):>{width}}" for name, width, form in columns)
        action = states[case.case_id]
        lines.append(f"{case.case_id:<40s}{cells}  {number if number else '-':>5}  {action}")
    return lines


def _planned_states(config, plan, existing, fresh: bool) -> dict[str, str]:
    """Per case: "run", "resume from its checkpoint", "complete: skip", from the look at the
    existing file already taken (``existing``: None without a file); fresh runs all."""
    if fresh:
        return dict.fromkeys(plan.case_ids, "run")
    completed = set(existing.completed) if existing is not None else set()
    states = {}
    for case_id in plan.case_ids:
        if case_id in completed:
            states[case_id] = SKIP
        elif (config.study.checkpoint_dir / f"{case_id}.npz").exists():
            states[case_id] = "resume from its checkpoint"
        else:
            states[case_id] = "run"
    return states
