"""The threshold search's method (engine.study.search) on synthetic columns: no cases, no
files, no MPI. Each test drives a :class:`Search` with a known function of the parameter and
checks the threshold against the function's exact boundary, within the search's own
guarantee (|threshold − boundary| ≤ tol = atol + rtol·|x|), never a looser one."""

from __future__ import annotations

import math
import struct

import pytest

from engine.study.search import Search, SearchSpec, SearchStatus, StepFailure, search_tolerance


def drive(search: Search, column, *, limit: int = 500) -> Search:
    """Evaluate every pending value with ``column(x)`` until the search ends."""
    for _ in range(limit):
        pending = search.pending()
        if not pending:
            return search
        for x in pending:
            search.record(x, column(x))
    raise AssertionError("the search did not end")


def numeric(**changes) -> SearchSpec:
    options = dict(parameter="loading.amplitude", low=0.0, high=1.0, column="q", target=0.5)
    options.update(atol=1e-6)
    options.update(changes)
    return SearchSpec(**options)


def bisection_steps(width: float, tol: float) -> int:
    """Cases bisection needs for a bracket of ``width`` to reach 2·tol: both ends, then
    one per halving."""
    return 2 + max(0, math.ceil(math.log2(width / (2.0 * tol))))


MONOTONE = {
    # name: (column(x) on [0, 1], target, exact root)
    "linear": (lambda x: 3.0 * x - 1.0, 0.5, 0.5),
    "cubic": (lambda x: x**3, 0.2, 0.2 ** (1.0 / 3.0)),
    "exponential": (lambda x: math.exp(4.0 * x), 7.0, math.log(7.0) / 4.0),
    # the Cattaneo–Mindlin compliance curve δ(Q) ∝ 1 − (1 − Q/L)^(2/3): infinite slope at L
    "mindlin": (lambda x: 1.0 - (1.0 - x) ** (2.0 / 3.0), 0.9, 1.0 - 0.1**1.5),
    "decreasing": (lambda x: math.cos(1.5 * x), 0.3, math.acos(0.3) / 1.5),
    # regula falsi's bad case: a flat function with a steep end (x^10)
    "steep": (lambda x: x**10, 0.5, 0.5**0.1),
}


@pytest.mark.parametrize("name", sorted(MONOTONE))
def test_illinois_finds_the_root_within_tolerance(name):
    column, target, root = MONOTONE[name]
    spec = numeric(target=target, atol=1e-8)
    result = drive(Search(spec), column).result
    assert result.status == SearchStatus.CONVERGED
    # the search's guarantee: the root is in the final bracket, whose width is ≤ tol
    assert result.lower <= root <= result.upper
    assert abs(result.threshold - root) <= search_tolerance(spec, root)
    # the safeguard keeps it within about twice bisection's cases (plus the bracket check)
    assert result.steps <= 2 * bisection_steps(1.0, 0.5e-8)


def test_illinois_beats_bisection_on_a_smooth_column():
    """Superlinear convergence on a smooth monotone column: fewer than half the cases."""
    column, target, _ = MONOTONE["exponential"]
    illinois = drive(Search(numeric(target=target, atol=1e-8)), column).result
    bisection = drive(Search(numeric(target=target, atol=1e-8, method="bisection")), column)
    assert bisection.result.steps == bisection_steps(1.0, 0.5e-8)
    assert illinois.steps < bisection.result.steps / 2


@pytest.mark.parametrize("boundary", [0.123456, 0.5, 0.987654])
@pytest.mark.parametrize("far_side", ["upper", "lower"])
def test_bisection_on_a_categorical_column(boundary, far_side):
    """A regime that switches at ``boundary``: the midpoint of the final bracket is within
    tol of it, after exactly bisection's number of cases."""

    def regime(x):
        gross = x > boundary if far_side == "upper" else x < boundary
        return "gross" if gross else "partial"

    spec = SearchSpec("loading.amplitude", 0.0, 1.0, "slip_regime", "gross", rtol=1e-4)
    result = drive(Search(spec), regime).result
    assert spec.method == "bisection"
    assert result.status == SearchStatus.CONVERGED
    assert result.lower <= boundary <= result.upper
    assert abs(result.threshold - boundary) <= search_tolerance(spec, result.threshold)
    assert result.upper - result.lower <= 2 * search_tolerance(spec, result.threshold)
    assert {result.lower_value, result.upper_value} == {"gross", "partial"}
    assert result.steps <= bisection_steps(1.0, 1e-4 * boundary)


def test_not_bracketed_reports_both_ends_and_guesses_nothing():
    search = drive(Search(numeric(target=5.0)), lambda x: x)
    result = search.result
    assert result.status == SearchStatus.NOT_BRACKETED
    assert math.isnan(result.threshold)
    assert (result.lower, result.upper) == (0.0, 1.0)
    assert (result.lower_value, result.upper_value) == (0.0, 1.0)
    assert result.steps == 2 and search.pending() == ()
    assert "same side" in result.message


def test_a_failed_case_fails_the_search():
    def column(x):
        return StepFailure("case mu0.3_amplitude0.5 failed: did not converge") if x == 0.5 else x

    result = drive(Search(numeric(target=0.3, method="bisection")), column).result
    assert result.status == SearchStatus.FAILED
    assert math.isnan(result.threshold)
    assert "did not converge" in result.message and "loading.amplitude = 0.5" in result.message
    assert result.steps == 3


@pytest.mark.parametrize("value", [math.nan, None, "partial"])
def test_a_missing_numeric_value_fails_the_search(value):
    result = drive(Search(numeric()), lambda x: value if x == 1.0 else 0.0).result
    assert result.status == SearchStatus.FAILED
    assert "column 'q'" in result.message


def test_max_steps_ends_not_converged_with_the_bracket():
    result = drive(Search(numeric(target=0.3, method="bisection", max_steps=5)), lambda x: x)
    result = result.result
    assert result.status == SearchStatus.NOT_CONVERGED
    assert math.isnan(result.threshold)
    assert result.steps == 5
    assert result.lower <= 0.3 <= result.upper and result.upper - result.lower == 0.125


def test_target_met_exactly_at_an_evaluated_point():
    result = drive(Search(numeric(target=0.0)), lambda x: x).result
    assert result.status == SearchStatus.CONVERGED and result.threshold == 0.0
    result = drive(Search(numeric(target=0.5, method="bisection")), lambda x: x).result
    assert result.status == SearchStatus.CONVERGED and result.threshold == 0.5
    assert result.steps == 3


def test_the_ends_may_arrive_in_either_order():
    forward, backward = Search(numeric(target=0.0)), Search(numeric(target=0.0))
    forward.record(0.0, -1.0)
    forward.record(1.0, 2.0)
    backward.record(1.0, 2.0)
    backward.record(0.0, -1.0)
    assert forward.pending() == backward.pending() == (1.0 / 3.0,)


def test_replay_after_an_interruption_gives_the_same_threshold_bit_for_bit():
    """Stop after every possible number of cases; rebuild the search from the values it had
    (what a results file holds) and finish: same proposals, same threshold, same bits."""
    column, target, _ = MONOTONE["mindlin"]
    spec = numeric(target=target, atol=1e-8)
    reference = drive(Search(spec), column).result
    for done in range(len(reference.evaluations) + 1):
        known = dict(reference.evaluations[:done])
        resumed = Search(spec)
        pending = resumed.replay(known.get)
        assert all(x not in known for x in pending)
        result = drive(resumed, column).result
        assert result.evaluations == reference.evaluations
        assert struct.pack("<d", result.threshold) == struct.pack("<d", reference.threshold)


def test_record_refuses_a_value_it_did_not_ask_for():
    search = Search(numeric())
    with pytest.raises(ValueError, match="did not ask"):
        search.record(0.5, 1.0)


@pytest.mark.parametrize(
    "changes, key",
    [
        ({"low": 1.0, "high": 1.0}, "high"),
        ({"low": 0.0, "high": math.inf}, "high"),
        ({"atol": 0.0}, "rtol"),
        ({"atol": -1.0}, "atol"),
        ({"atol": 2.0}, "atol"),  # wider than the bracket: no step would be taken
        ({"max_steps": 10**15}, "max_steps"),
        ({"method": "newton"}, "method"),
        ({"target": "gross", "method": "illinois"}, "method"),
        ({"max_steps": 2}, "max_steps"),
        ({"target": math.nan}, "target"),
        ({"atol": 1e-9}, "rtol"),  # case ids (10 digits) could not tell the steps apart
    ],
)
def test_bad_specs_name_the_key(changes, key):
    spec = numeric(**changes)
    assert spec.problems()[0][0] == key
    with pytest.raises(ValueError, match=key):
        Search(spec)


# ---------------------------------------------------------------------- many searches as cases
def campaign_plan():
    from engine.study.plan import Case, Plan

    loads = (100.0, 200.0, 400.0)
    no_wear = (("wear1", 0.0), ("wear2", 0.0))  # Archard's coefficients, static cases
    return Plan(
        tuple(
            Case(i, f"mu0.5_w0_b0_load{load:g}", 0.5, 0.5, no_wear, 0.0, (("loading.load", load),))
            for i, load in enumerate(loads)
        )
    )


def regime_row(case):
    """The summary row of a synthetic fretting case: gross slip above δ_slip ∝ P^(2/3)."""
    settings = dict(case.settings)
    boundary = 1e-3 * (settings["loading.load"] / 100.0) ** (2.0 / 3.0)
    regime = "gross" if settings["loading.amplitude"] > boundary else "partial"
    return {**case.parameters(), "status": "completed", "slip_regime": regime}


def run_campaign(campaign, todo, order_seed=None, stop_after=None):
    """Run ``todo`` and what it unlocks; outcomes come back in a shuffled order (as from many
    ranks) when ``order_seed`` is given. Returns the rows by case id."""
    import random

    rows, running = {}, list(todo)
    shuffle = random.Random(order_seed)
    while running:
        if order_seed is not None:
            shuffle.shuffle(running)
        case = running.pop(0)
        rows[case.case_id] = regime_row(case)
        running.extend(campaign.record(case.case_id, rows[case.case_id]))
        if stop_after is not None and len(rows) >= stop_after:
            break
    return rows


def test_a_campaign_is_independent_of_the_order_outcomes_arrive_in_and_resumes():
    from engine.study.search import SearchCampaign

    spec = SearchSpec("loading.amplitude", 1e-4, 1e-2, "slip_regime", "gross", rtol=1e-3)
    plan = campaign_plan()
    reference = SearchCampaign(spec, plan, ("loading.load",))
    rows = run_campaign(reference, reference.start())
    assert reference.finished
    table = reference.table()
    for row in table:
        boundary = 1e-3 * (row["loading.load"] / 100.0) ** (2.0 / 3.0)
        assert row["status"] == "converged"
        assert abs(row["threshold"] - boundary) <= 1e-3 * row["threshold"]
        assert row["lower"] <= boundary <= row["upper"]
    ids = [case.case_id for case in reference.cases()]
    assert ids[0] == "mu0.5_w0_b0_load100_amplitude0.0001" and len(ids) == len(rows)
    for seed in (1, 2, 3):  # outcomes in another order: same cases, same table
        shuffled = SearchCampaign(spec, plan, ("loading.load",))
        run_campaign(shuffled, shuffled.start(), order_seed=seed)
        assert [case.case_id for case in shuffled.cases()] == ids
        assert shuffled.table() == table
    for done in (0, 1, 5, 17, len(rows) - 1):  # killed after `done` cases: replay the file
        first = SearchCampaign(spec, plan, ("loading.load",))
        stored = run_campaign(first, first.start(), order_seed=done, stop_after=done)
        resumed = SearchCampaign(spec, plan, ("loading.load",))
        run_campaign(resumed, resumed.start(stored), order_seed=7)
        assert [case.case_id for case in resumed.cases()] == ids
        assert resumed.table() == table  # thresholds equal as floats: bit for bit
