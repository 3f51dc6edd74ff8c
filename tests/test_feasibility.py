"""Cases the plan knows cannot be computed are refused before anything runs, by case id."""

from __future__ import annotations

import pytest

from engine.study.feasibility import ImpossibleCases, check_feasible, impossible_cases
from engine.study.plan import make_plan
from tests.test_fretting import study


def test_force_control_at_or_above_the_friction_bound_is_refused_by_case_id():
    """P = 100 N, μ = 0.5 isotropic: the bound is μP = 50 N in every direction; Q* = 50 N (at
    the bound: gross sliding) and 60 N cannot be held, 40 N can."""
    config = study(
        loading={},
        sweep={"wear1": [1e-7], "loading.force_amplitude": [40.0, 50.0, 60.0]},
    )
    plan = make_plan(config)
    found = dict(impossible_cases(config, plan))
    assert len(found) == 2 and len(plan) == 3
    for case_id, reason in found.items():
        assert "not below the friction bound 50 N" in reason, case_id
    with pytest.raises(ImpossibleCases, match="2 case\\(s\\) of the study cannot be computed"):
        check_feasible(config, plan)


def test_displacement_control_and_other_kinds_have_no_impossible_cases():
    config = study()
    assert impossible_cases(config, make_plan(config)) == []
