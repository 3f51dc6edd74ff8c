"""Sweep expansion and case ids (every combination is a case; ids are stable)."""

from __future__ import annotations

import pytest

from engine.study.config import StudyConfigError, parse_study
from engine.study.plan import case_id_for, make_plan
from tests.test_config import VALID, replace_key, with_line


def test_every_combination_is_a_case_isotropic_by_default():
    plan = make_plan(parse_study(VALID))
    assert len(plan) == 2 * 1 * 2
    for case in plan:
        assert case.mu2 == case.mu1
        assert case.coefficients["wear2"] == case.coefficients["wear1"]
    assert [case.index for case in plan] == list(range(len(plan)))


def test_orthotropic_product_and_proportional_wear():
    text = with_line(
        "sweep", 'mu2 = [0.4]\nwear2 = "proportional"', replace_key("sweep.mu1", "[0.1]")
    )
    text = replace_key("sweep.beta", "[0, 45, 90]", text)
    plan = make_plan(parse_study(text))
    assert len(plan) == 3
    for case in plan:
        assert (case.mu1, case.mu2) == (0.1, 0.4)
        assert case.coefficients["wear2"] == pytest.approx(1.33e-7 * 0.4 / 0.1, rel=1e-14)
    assert [case.beta for case in plan] == [0.0, 45.0, 90.0]


def test_case_ids_are_stable_when_the_sweep_grows():
    small = make_plan(parse_study(VALID))
    grown = make_plan(parse_study(replace_key("sweep.mu1", "[0.05, 0.1, 0.4]")))
    assert set(small.case_ids) <= set(grown.case_ids)
    assert len(set(grown.case_ids)) == len(grown)
    assert (
        case_id_for(0.1, 0.1, {"wear1": 1.33e-7, "wear2": 1.33e-7}, 45.0) == "mu0.1_w1.33e-07_b45"
    )
    assert case_id_for(0.1, 0.4, {"wear1": 1e-7, "wear2": 4e-7}, 0.0) == "mu0.1-0.4_w1e-07-4e-07_b0"


def test_dispatch_order_puts_low_friction_first_and_skips_done():
    plan = make_plan(parse_study(replace_key("sweep.mu1", "[0.4, 0.1, 0.2]")))
    order = plan.dispatch_order()
    assert [case.mu1 for case in order][:2] == [0.1, 0.1]
    done = {order[0].case_id}
    assert order[0] not in plan.dispatch_order(skip=done)
    assert len(plan.dispatch_order(skip=done)) == len(plan) - 1


def test_unknown_fail_case_is_rejected():
    text = VALID + '\n[testing]\nfail_cases = ["mu9_w0_b0"]\n'
    with pytest.raises(StudyConfigError, match=r"\[testing\] fail_cases"):
        make_plan(parse_study(text))
