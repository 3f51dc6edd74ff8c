"""`engine.analysis.report`: the "Measured" facts group comparable cases and agree with the table.

Synthetic studies in memory (no solver): each case gets a wear history and a pressure field, so
the facts are computed exactly as for a results file. The case that motivated this test is the
demo study: every μ appears twice (β = 0° and 90°), and a check over all cases at once said
"not decreasing with μ" while the table, read per β, decreases.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from engine.analysis.report import cyclic_facts, cyclic_table, study_report
from engine.analysis.results import ResultCase, Results

CYCLES = (1000, 10000)


def _case(index, mu1, beta, depth_um, volume, mu2=None, wear2=1.33e-7) -> ResultCase:
    """A completed case whose wear at N = 1,000 and 10,000 is depth·(1, 5) and volume·(1, 5)."""
    mu2 = mu1 if mu2 is None else mu2
    grid = np.zeros((8, 8))
    grid[6, 4] = 100.0  # pressure maximum off the axis, so its polar angle is defined
    parameters = {"mu1": mu1, "mu2": mu2, "wear1": 1.33e-7, "wear2": wear2, "beta": beta}
    history = {
        "cycle": np.array(CYCLES, dtype=float),
        "max_wear_depth": np.array([1.0, 5.0]) * depth_um * 1e-3,  # mm
        "wear_volume": np.array([1.0, 5.0]) * volume,
        "peak_pressure": np.array([300.0, 200.0]),
    }
    fields = {cycle: {"pressure": grid, "wear": grid * 0.0} for cycle in CYCLES}
    return ResultCase.from_values(
        f"case{index}", parameters, index=index, history=history, fields=fields
    )


def _study(cases) -> Results:
    config = {
        "loading": {"kind": "cyclic", "load": 750.0, "cycles": 10000},
        "punch": {"radius": 1.8},
        "mesh": {"n": 8},
        "subsurface": {"depth": 1.0, "layers": 4},
        "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e5, "nu_B": 0.3},
    }
    x = np.linspace(-1.8, 1.8, 8)
    return Results.from_values("synthetic", config, list(cases), x, x, Path("synthetic.h5"))


def test_duplicated_mu_at_two_angles_is_checked_per_angle():
    # The demo's shape: μ = 0.1, 0.2, 0.4 at β = 0° and 90°; wear decreases with μ at each β,
    # but the β = 90° cases wear slightly more than the β = 0° ones (so a check over all six
    # cases sorted by μ alone would see an increase between the two μ = 0.1 cases).
    cases = []
    for index, (mu, depth, volume) in enumerate(((0.1, 0.15, 3e-4), (0.2, 0.09, 1e-4),
                                                 (0.4, 0.02, 1e-5))):  # fmt: skip
        cases.append(_case(2 * index, mu, 0.0, depth, volume))
        cases.append(_case(2 * index + 1, mu, 90.0, depth * 1.001, volume * 1.001))
    facts = cyclic_facts(_study(cases))
    trends = [fact for fact in facts if "with μ" in fact]
    assert len(trends) == 2 * len(CYCLES)  # one per β and recorded N
    assert all("wear depth and volume strictly decreasing with μ = 0.1, 0.2, 0.4" in fact
               for fact in trends)  # fmt: skip
    assert {fact.split(":")[0] for fact in trends} == {
        f"N = {n:,}, β = {b}°" for n in CYCLES for b in (0, 90)
    }
    assert not any("not monotone" in fact for fact in facts)
    # β changes nothing for an isotropic law: its spread is reported per μ, not over all cases
    spreads = [fact for fact in facts if "spread over β" in fact]
    assert len(spreads) == 3 * len(CYCLES)
    assert all("wear depth 0.10 %" in fact for fact in spreads)


def test_a_real_increase_is_reported_with_its_values():
    cases = [_case(0, 0.1, 0.0, 0.15, 3e-4), _case(1, 0.2, 0.0, 0.09, 4e-4)]
    facts = cyclic_facts(_study(cases))
    trend = next(fact for fact in facts if fact.startswith("N = 1,000") and "μ = 0.1, 0.2" in fact)
    assert "wear depth strictly decreasing (0.15, 0.09 µm)" in trend
    assert "wear volume strictly increasing (3.000e-04, 4.000e-04 mm³)" in trend
    assert "β =" not in trend.split(":")[0]  # a single β: nothing to tell apart


def test_orthotropic_cases_are_compared_over_beta_and_mu2_separately():
    # Section 7.3's shape, plus a second μ2: spread over β per (μ1, μ2), trend in μ2 per β.
    cases = []
    for index, beta in enumerate((0.0, 45.0, 90.0)):
        cases.append(_case(index, 0.1, beta, 0.145, 2.15e-4, mu2=0.4, wear2=5.32e-7))
        cases.append(_case(10 + index, 0.1, beta, 0.12, 1.5e-4, mu2=0.8, wear2=1.064e-6))
    facts = cyclic_facts(_study(cases))
    spreads = [fact for fact in facts if "spread over β = 0, 45, 90°" in fact]
    assert len(spreads) == 2 * len(CYCLES)
    assert all("wear depth 0.00 %, wear volume 0.00 %" in fact for fact in spreads)
    assert any(fact.startswith("N = 10,000, μ2 = 0.4") for fact in spreads)
    trends = [fact for fact in facts if "with μ2 = 0.4, 0.8" in fact]
    assert len(trends) == 3 * len(CYCLES)
    assert all("strictly decreasing" in fact for fact in trends)


def test_facts_agree_with_the_table_rows():
    cases = [_case(i, mu, beta, d, v) for i, (mu, beta, d, v) in enumerate(
        ((0.1, 0.0, 0.15, 3e-4), (0.1, 90.0, 0.16, 3.1e-4), (0.4, 0.0, 0.02, 1e-5),
         (0.4, 90.0, 0.021, 1.1e-5)))]  # fmt: skip
    study = _study(cases)
    table = cyclic_table(study)
    rows = [line for line in table if line.startswith("| μ")]
    assert len(rows) == len(cases) * len(CYCLES)
    for beta in (0.0, 90.0):
        label = "μ = {:g}" + (f", β = {beta:g}°" if beta else "")
        depths = [float(next(r for r in rows if r.startswith(f"| {label.format(mu)} | 10,000"))
                        .split("|")[3]) for mu in (0.1, 0.4)]  # fmt: skip
        assert depths[1] < depths[0]
    report = study_report(study)
    assert "not monotone" not in report and "increasing" not in report


def test_update_replaces_only_its_block_and_names_a_missing_one(tmp_path):
    from engine.analysis.report import update_markdown

    document = tmp_path / "results.md"
    document.write_text(
        "intro\n<!-- BEGIN report a -->\nold a\n<!-- END report a -->\n"
        "<!-- BEGIN report b -->\nold b\n<!-- END report b -->\n"
    )
    update_markdown(document, "a", "new a\n")
    assert document.read_text() == (
        "intro\n<!-- BEGIN report a -->\nnew a\n<!-- END report a -->\n"
        "<!-- BEGIN report b -->\nold b\n<!-- END report b -->\n"
    )
    try:
        update_markdown(document, "c", "x\n")
    except ValueError as error:
        assert "BEGIN report c" in str(error)
    else:
        raise AssertionError("a missing block must be an error")


def test_a_swept_punch_key_gives_the_profile_its_first_value():
    """A study sweeping ``punch.edge_radius`` stores no edge radius in ``[punch]``: the
    study-wide profile (a0, the report's normalisation) takes the sweep's first value."""
    from engine.geometry import RoundedPunch

    config = {
        "punch": {"radius": 1.8, "shape": "rounded"},
        "sweep": {"mu1": [0.1], "punch.edge_radius": [0.09, 0.18]},
    }
    x = np.linspace(-1.8, 1.8, 8)
    study = Results.from_values("swept", config, [], x, x, Path("swept.h5"))
    profile = study.profile
    assert isinstance(profile, RoundedPunch)
    assert (profile.radius, profile.edge_radius) == (1.8, 0.09)
