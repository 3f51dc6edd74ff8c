"""Tangential fretting: engine.solvers.fretting and the fretting study kind.

Sphere R = 10 mm on a half-space of the same material (E = 200 GPa, ν = 0.3, so K = 0),
P = 100 N, μ = 0.5; Hertz radius a = 0.190 mm, mesh half-width 1.5 a. Cattaneo–Mindlin
(Johnson 1985 §7.2) under a monotone tangential force Q < μP:

    c/a = (1 − Q/μP)^{1/3},   δ(Q) = (3μP/16a) Σ_i (2 − ν_i)/G_i [1 − (1 − Q/μP)^{2/3}].
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine.geometry import FlatPunch, SphericalPunch
from engine.grid import Grid
from engine.material import MaterialPair
from engine.reference import mindlin
from engine.reference.hertz import hertz_contact_radius
from engine.solvers.contact import STICK, ContactSolver
from engine.solvers.fretting import FrettingAnalysis, FrettingSettings, TangentialDriver
from engine.solvers.friction import EnergyWearLaw, FrictionLaw, WearLaw, frictional_work
from engine.study.checkpoint import load_fretting_state, save_fretting_state
from engine.study.config import StudyConfigError, parse_study
from engine.study.examples import SPHERE_ON_STEEL, study_toml

E, NU, RADIUS, LOAD, MU = 200e3, 0.3, 10.0, 100.0, 0.5
SHEAR = E / (2.0 * (1.0 + NU))
CONTACT_MODULUS = E / (2.0 * (1.0 - NU**2))
A_HERTZ = hertz_contact_radius(LOAD, RADIUS, CONTACT_MODULUS)


MATERIAL = MaterialPair(E, NU, E, NU)
REFERENCE = (LOAD, RADIUS, MATERIAL, MU)  # engine.reference.mindlin arguments


def mindlin_displacement(force):
    """δ(Q) of Cattaneo–Mindlin (mm), two identical bodies."""
    return mindlin.tangential_displacement(force, *REFERENCE)


def solver(n=32, mu1=MU, mu2=MU, beta=0.0):
    grid = Grid.square(n, 1.5 * A_HERTZ)
    return ContactSolver(grid, MATERIAL, SphericalPunch(RADIUS), FrictionLaw(mu1, mu2, beta))


def ramp(analysis):
    """Every increment of the first quarter: (δ·d, Q·d, stick area)."""
    seen = []
    original = analysis._increment

    def recording(*args, **kwargs):
        step = original(*args, **kwargs)
        area = analysis.solver.grid.element_area
        stick = np.count_nonzero(step.result.status == STICK) * area
        seen.append(
            (step.rigid @ analysis.driver.direction, step.force @ analysis.driver.direction, stick)
        )
        return step

    analysis._increment = recording
    analysis.initial_state()
    return np.array(seen)


@pytest.mark.validation
def test_cattaneo_mindlin_force_ramp(validation):
    """Force control 0 → 0.8 μP in 8 increments at 48² (16 elements per contact radius):
    δ(Q) within 1 % and c/a within 0.03 of the closed forms (c from the stick area √(A/π);
    one element is 0.0625 a, so 0.03 is half an element). Measured: δ 0.29 %, c/a 0.014;
    the force meets its target to 3.5e-4 N (tolerance 1e-5 × 40 N)."""
    settings = FrettingSettings(LOAD, 8, 1, force_amplitude=0.8 * MU * LOAD)
    rows = ramp(FrettingAnalysis(solver(48), WearLaw(0.0, 0.0), settings))
    delta, force, stick = rows.T
    np.testing.assert_allclose(force, settings.quarter(), rtol=0, atol=1e-5 * 40.0)
    np.testing.assert_allclose(delta, mindlin_displacement(force), rtol=0.01)
    ratio = np.sqrt(stick / math.pi) / A_HERTZ
    expected = mindlin.stick_radius_ratio(force, LOAD, MU)
    np.testing.assert_allclose(ratio, expected, atol=0.03)
    validation.record(
        "fretting, sphere, K = 0, μ = 0.5: Cattaneo–Mindlin δ(Q) and stick radius c/a under a "
        "force ramp to 0.8 μP, 48²", "1 % / 0.03 (half an element)",
        f"{np.max(np.abs(delta / mindlin_displacement(force) - 1)):.2%} / "
        f"{np.max(np.abs(ratio - expected)):.3f}",
    )  # fmt: skip


def test_displacement_control_gives_the_force_control_curve():
    """Displacement control to the δ of the force-controlled ramp gives back its Q (same
    mesh: the same discrete problem) to 2e-5 relative (force tolerance 1e-5; measured
    1.2e-6), and Q(δ) follows Cattaneo–Mindlin within 0.5 % at 32² (measured 0.08 %)."""
    force_settings = FrettingSettings(LOAD, 4, 1, force_amplitude=0.6 * MU * LOAD)
    forced = ramp(FrettingAnalysis(solver(), WearLaw(0.0, 0.0), force_settings))
    amplitude = forced[-1, 0]
    settings = FrettingSettings(LOAD, 4, 1, amplitude=amplitude)
    driven = ramp(FrettingAnalysis(solver(), WearLaw(0.0, 0.0), settings))
    np.testing.assert_allclose(driven[-1, 1], forced[-1, 1], rtol=2e-5)
    expected = mindlin.tangential_force(driven[:, 0], *REFERENCE)  # δ(Q) inverted
    np.testing.assert_allclose(driven[:, 1], expected, rtol=0.005)


def force_control(profile, half_width, mu, first_guess_factor, restart):
    """Normal load P, then the force control of Q = 0.5 μP along x to 1e-5 Q at 32² (K = 0),
    from the first guess s₀ = Q/k times ``first_guess_factor``, k the normal secant stiffness
    times 2(1 − ν)/(2 − ν). Returns (driver, normal result, target Q, s₀, increment)."""
    contact = ContactSolver(
        Grid.square(32, half_width), MATERIAL, profile, FrictionLaw(mu, mu), tol=1e-8
    )
    normal = contact.solve_load(LOAD)
    target = 0.5 * mu * LOAD
    stiffness = LOAD / normal.approach * 2.0 * (1.0 - NU) / (2.0 - NU)
    first = first_guess_factor * target / stiffness
    driver = TangentialDriver(contact, LOAD, (1.0, 0.0), 1e-5, restart=restart)
    step = driver.force(normal.state, np.zeros(2), target, target, first, stiffness)
    return driver, normal, target, first, step


def test_secant_restart_certifies_a_sticking_contact_in_one_application():
    """Flat punch (a = 1 mm), K = 0, μ = 0.2, Q = 0.5 μP: Mindlin's traction
    Q/(2πa√(a² − r²)) has the pressure's shape, so q/p = Q/P = 0.1 < μ and every element
    sticks; Q and q are then linear in δ. From a first guess 1 % off, both restarts meet
    |Q·d − Q| ≤ 1e-5 Q in two evaluations; the secant start of the second is its solution,
    certified by one operator application and no iteration (from the last evaluation's
    solution: 64 applications in all against 39)."""
    results = {}
    for restart in ("last", "secant"):
        results[restart] = force_control(FlatPunch(1.0), 1.05, 0.2, 1.01, restart)
    driver, normal, target, first, secant = results["secant"]
    last = results["last"][-1]
    for step in (last, secant):
        assert step.converged, step.message
        assert step.evaluations == 2
        assert step.force_residual <= 1e-5 * target
        assert abs(step.force[0] - target) == pytest.approx(step.force_residual, abs=1e-12)
        assert np.count_nonzero(step.result.status == STICK) == np.count_nonzero(
            step.result.in_contact
        )
    # the first evaluation again, alone: the secant's second costs 1 application, 0 iterations
    alone = driver.displacement(normal.state, np.zeros(2), (first, 0.0))
    assert secant.matvecs == alone.matvecs + 1
    assert secant.iterations == alone.iterations
    assert last.matvecs > secant.matvecs + 10
    assert secant.result.report.iterations == 0 and secant.result.report.converged
    np.testing.assert_array_equal(secant.rigid, last.rigid)  # same force iteration, same δ


def test_secant_restart_in_partial_slip_finds_the_same_increment():
    """Sphere (Hertz a = 0.19 mm), K = 0, μ = 0.5, Q = 0.5 μP: partial slip, Q(δ) not
    linear. Both restarts meet 1e-5 Q in the same number of evaluations (6) and the secant
    costs no more operator applications (measured 156 against 169). Their δ agree to 1e-4
    (each within the force tolerance 1e-5 Q over the tangent stiffness, which slip lowers
    below Q/δ; measured 4.8e-9) and their tractions to 1e-3 of the largest (the force
    tolerance spread over the slip zone's edge; measured 1.8e-7)."""
    steps = {
        restart: force_control(SphericalPunch(RADIUS), 1.5 * A_HERTZ, MU, 1.0, restart)[-1]
        for restart in ("last", "secant")
    }
    last, secant = steps["last"], steps["secant"]
    target = 0.5 * MU * LOAD
    for step in (last, secant):
        assert step.converged, step.message
        assert step.force_residual <= 1e-5 * target
    assert np.count_nonzero(secant.result.status == STICK) > 0  # partial slip
    assert np.count_nonzero(secant.result.status == STICK) < np.count_nonzero(
        secant.result.in_contact
    )
    assert secant.evaluations == last.evaluations
    assert secant.matvecs <= last.matvecs
    assert secant.rigid[0] == pytest.approx(last.rigid[0], rel=1e-4)
    scale = np.abs(last.result.traction_x).max()
    np.testing.assert_allclose(secant.result.traction_x, last.result.traction_x, atol=1e-3 * scale)


def test_unknown_restart_is_refused():
    with pytest.raises(ValueError, match="restart must be one of.*'previous'"):
        TangentialDriver(solver(), LOAD, (1.0, 0.0), restart="previous")


@pytest.mark.validation
def test_beta_invariance_orthotropic(validation):
    """μ1 = 0.6, μ2 = 0.3: the loop for β = 90°, direction 90° is the loop for β = 0,
    direction 0 turned by 90° (an exact symmetry of the square grid): δ exactly, Q to 1e-6
    of its amplitude (measured 1.5e-8: the two runs differ by round-off in the iterations);
    the stick zone exactly and the tractions to 1e-6 of their largest value (measured 2e-9)."""
    loops = {}
    for angle in (0.0, 90.0):
        settings = FrettingSettings(LOAD, 3, 1, amplitude=0.002, direction=angle)
        analysis = FrettingAnalysis(
            solver(24, 0.6, 0.3, math.radians(angle)), WearLaw(0.0, 0.0), settings
        )
        loops[angle] = analysis.run().records[1]
    fields, turned_fields = loops[0.0], loops[90.0]
    # The stick zone and the tractions at the largest |Q| follow the turned cone.
    np.testing.assert_array_equal(np.rot90(fields["status"]), turned_fields["status"])
    traction_scale = np.abs(fields["traction_x"]).max()
    np.testing.assert_allclose(
        np.rot90(fields["traction_x"]), turned_fields["traction_y"], atol=1e-6 * traction_scale
    )
    first, turned = fields["loop"], turned_fields["loop"]
    scale = np.abs(first[:, 2]).max()
    np.testing.assert_array_equal(turned[:, 1], first[:, 0])
    np.testing.assert_allclose(turned[:, 3], first[:, 2], atol=1e-6 * scale)
    np.testing.assert_allclose(turned[:, 2], -first[:, 3], atol=1e-6 * scale)
    error = max(np.abs(turned[:, 3] - first[:, 2]).max(), np.abs(turned[:, 2] + first[:, 3]).max())
    validation.record(
        "fretting, orthotropic μ1 = 0.6, μ2 = 0.3, 24²: β = 90° with the direction turned "
        "gives the turned loop and stick zone", "1e-6 of Q* (solver round-off)",
        f"{error / scale:.0e}",
    )  # fmt: skip


def collect(analysis, **options):
    results = []
    outcome = analysis.run(on_increment=lambda r, row: results.append((row, r)), **options)
    return outcome, results


def test_energy_is_frictional_work_plus_elastic_change():
    """K = 0, held load: ∮ Q·dδ (trapezoid) = Σ_k Σ_e −½(q_k + q_{k−1})·Δs_k ΔA + ΔE_t with
    E_t = ½ Σ q·u_t ΔA, to round-off: 1e-12 of the energy (measured 1e-16; the
    identity only needs A_tt symmetric, which the FFT operator is to round-off)."""
    settings = FrettingSettings(LOAD, 3, 1, amplitude=0.002)
    analysis = FrettingAnalysis(solver(24), WearLaw(0.0, 0.0), settings)
    start = analysis.initial_state()
    before = start.contact.copy()
    result, results = collect(analysis, state=start)
    area = analysis.solver.grid.element_area
    work, previous = 0.0, before
    for row, increment in results:
        if row != 0:  # the first simulated cycle only (history row 0)
            break
        work += float(np.sum(frictional_work(increment, previous)) * area)
        previous = increment.state

    def elastic(state):
        return (
            0.5
            * area
            * float(
                np.sum(
                    state.traction_x * state.displacement_x
                    + state.traction_y * state.displacement_y
                )
            )
        )

    change = elastic(previous) - elastic(before)
    energy = result.history["energy"][0]
    assert energy > 0.0
    assert abs(energy - (work + change)) <= 1e-12 * energy


@pytest.mark.parametrize("law", ["archard", "energy"])
def test_wear_volume_is_the_sum_of_increments(law):
    """Both laws: the wear volume after the run is Σ over simulated cycles of the jump times
    the cycle's Σ Δω ΔA (1e-12 relative), as tests/test_cyclic.py checks the cyclic kind."""
    wear_law = WearLaw(1e-6, 1e-6) if law == "archard" else EnergyWearLaw(1e-2)
    settings = FrettingSettings(LOAD, 2, 40, amplitude=0.003, record=(1,), max_wear_fraction=0.05)
    analysis = FrettingAnalysis(solver(16), wear_law, settings)
    start = analysis.initial_state()
    previous = {"state": start.contact}
    per_row: dict[int, float] = {}
    solves: dict[int, list] = {}
    area = analysis.solver.grid.element_area

    def hook(result, row):
        depth = wear_law.increment(result, previous["state"])
        per_row[row] = per_row.get(row, 0.0) + float(np.sum(depth) * area)
        solves.setdefault(row, []).append(result.report)
        previous["state"] = result.state

    outcome = analysis.run(state=start, on_increment=hook)
    jumps = outcome.history["jump"]
    expected = sum(jumps[row] * volume for row, volume in per_row.items())
    assert outcome.history["wear_volume"][-1] == pytest.approx(expected, rel=1e-12)
    assert expected > 0.0
    # The history's solver columns: each cycle's operator applications and largest residual.
    for row, reports in solves.items():
        assert outcome.history["matvecs"][row] == sum(r.matvecs for r in reports)
        assert outcome.history["residual"][row] == max(r.residual for r in reports)
        assert outcome.history["residual"][row] <= analysis.solver.tol
    if law == "energy":  # V = α Σ jumps × ∮Q·dδ up to the elastic energy change (measured
        # 0.37 %: the loops drift as the wear grows, gross slip at δ* = 3 µm)
        energy = sum(j * e for j, e in zip(jumps, outcome.history["energy"], strict=True))
        assert expected == pytest.approx(1e-2 * 1e-3 * energy, rel=1e-2)


def test_resume_is_bit_identical(tmp_path):
    """Stop after the second simulated cycle, save, load, resume: the same history bit for
    bit as an uninterrupted run (force control, whose guesses live in the state)."""
    settings = FrettingSettings(LOAD, 2, 30, force_amplitude=20.0, record=(1,))
    law = WearLaw(1e-6, 1e-6)
    whole = FrettingAnalysis(solver(16), law, settings).run()
    calls = {"n": 0}

    def stop():
        calls["n"] += 1
        return calls["n"] > 2

    first = FrettingAnalysis(solver(16), law, settings).run(should_stop=stop)
    assert not first.completed
    path = tmp_path / "state.npz"
    save_fretting_state(first.state, path)
    resumed = FrettingAnalysis(solver(16), law, settings).run(state=load_fretting_state(path))
    assert resumed.completed
    for key, values in whole.history.items():
        np.testing.assert_array_equal(resumed.history[key], values, err_msg=key)
    np.testing.assert_array_equal(resumed.records[30]["loop"], whole.records[30]["loop"])


def study(loading=None, wear=None, sweep=None):
    """A 16² fretting study of a sphere on the same steel, μ = 0.5, 10 cycles (P = 100 N)."""
    loading = {"kind": "fretting", "amplitude": 0.002} if loading is None else loading
    sweep = {"wear1": [1e-7]} if sweep is None else sweep
    sweep = {"mu1": [0.5], **sweep}
    text = study_toml(
        "f",
        "f.h5",
        SPHERE_ON_STEEL,
        loading={"kind": "fretting", "record": None, **loading},
        wear=wear,
        sweep=sweep,
    )
    return parse_study(text, source="f.toml")


def test_study_keys_and_sweeps():
    config = study(sweep={"wear1": [1e-7], "loading.amplitude": [0.001, 0.002]}, loading={})
    assert config.is_fretting and config.is_cyclic
    energy = study(wear={"law": "energy"}, sweep={"alpha": [1e-3]})
    assert energy.wear.law == "energy" and energy.sweep.wear_lists == {"alpha": (1e-3,)}
    forced = study(loading={"force_amplitude": 20.0, "direction": 30.0})
    assert forced.loading.force_amplitude == 20.0 and forced.loading.direction == 30.0


A, W = {"amplitude": 0.002}, {"wear1": [1e-7]}  # a valid signal and sweep


@pytest.mark.parametrize(
    ("loading", "wear", "sweep", "words"),
    [
        ({}, None, W, "[loading] amplitude: kind"),
        ({"amplitude": 0.002, "force_amplitude": 5.0}, None, W, "exactly one"),
        ({"amplitude": -0.002}, None, W, "[loading] amplitude = -0.002: must be >"),
        (A, {"law": "energy"}, W, "[sweep] wear1"),
        (A, {"law": "energy"}, {}, "[sweep] alpha: required"),
        (A, None, {**W, "alpha": [1.0]}, "[sweep] alpha"),
        (A, {"law": "paris"}, W, "[wear] law = 'paris'"),
    ],
)
def test_config_errors_name_the_key(loading, wear, sweep, words):
    with pytest.raises(StudyConfigError) as error:
        study(loading, wear, sweep)
    assert str(error.value).startswith("f.toml: ")
    assert words in str(error.value), str(error.value)


def test_force_amplitude_above_the_friction_bound_is_refused():
    """Force control above h(d)·P (the largest force the friction ellipses carry along d)
    fails the case with a message naming the key; orthotropic: h(d) of the rotated ellipse."""
    from engine.study.kinds.fretting import check_force_bound
    from engine.study.plan import make_plan

    config = study(
        loading={"force_amplitude": 49.0, "direction": 90.0},
        sweep={"mu1": [0.6], "mu2": [0.4], "wear1": [0.0]},
    )
    case = make_plan(config).cases[0]
    with pytest.raises(
        ValueError, match="force_amplitude = 49 N is not below the friction bound 40 N"
    ):
        check_force_bound(case, fretting_settings(config))
    below = study(
        loading={"force_amplitude": 39.0, "direction": 90.0},
        sweep={"mu1": [0.6], "mu2": [0.4], "wear1": [0.0]},
    )
    check_force_bound(make_plan(below).cases[0], fretting_settings(below))


def fretting_settings(config):
    from engine.study.kinds.fretting import settings

    return settings(config)


def test_energy_law_in_the_cyclic_kind_conserves_volume(material):
    """The energy law in the normal-indentation (cyclic) kind, flat punch of Section 7.2 at
    16², μ = 0.1: wear volume = Σ jumps × Σ_k α·10⁻³ Σ_e w ΔA (1e-12 relative), and the
    study runner picks the law from [wear] (engine.study.case.case_wear_law)."""
    from engine.geometry import FlatPunch
    from engine.solvers.cyclic import CyclicAnalysis, CyclicSettings

    grid = Grid.square(16, 1.05 * 1.8)
    solver = ContactSolver(grid, material, FlatPunch(1.8), FrictionLaw(0.1, 0.1), tol=1e-6)
    law = EnergyWearLaw(1e-2)
    analysis = CyclicAnalysis(solver, law, CyclicSettings(750.0, 3, 200, record=(200,)))
    previous = {"state": analysis.initial_state().contact}
    per_row: dict[int, float] = {}

    def hook(result, row):
        depth = law.increment(result, previous["state"])
        per_row[row] = per_row.get(row, 0.0) + float(np.sum(depth) * grid.element_area)
        previous["state"] = result.state

    outcome = analysis.run(on_increment=hook)
    jumps = outcome.history["jump"]
    expected = sum(jumps[row] * volume for row, volume in per_row.items())
    assert expected > 0.0
    assert outcome.history["wear_volume"][-1] == pytest.approx(expected, rel=1e-12)


@pytest.mark.validation
def test_coupling_changes_the_loop(validation):
    """K ≠ 0 (steel under a 100× stiffer sphere, K = 0.196): no analytic target; the case
    converges, and the coupling shows as the normal loading's locked-in slip (the first loop
    dissipates more than the second: measured 17 % at 24², 1e-4 at K = 0) and as a loop that
    is no longer odd in Q (|Q+| ≠ |Q−|: measured 0.8 %, 1e-5 at K = 0)."""
    grid = Grid.square(24, 0.3)
    stiff = MaterialPair(E, NU, 100.0 * E, NU)
    coupled = ContactSolver(grid, stiff, SphericalPunch(RADIUS), FrictionLaw(MU, MU), tol=1e-6)
    settings = FrettingSettings(LOAD, 4, 1, amplitude=0.001)
    result = FrettingAnalysis(coupled, WearLaw(0.0, 0.0), settings).run()
    assert result.converged, result.message
    first, second = result.history["energy"]
    assert first > 1.1 * second
    loop = result.records[1]["loop"]
    assert abs(loop[:, 2].min() + loop[:, 2].max()) > 1e-3 * loop[:, 2].max()
    validation.record(
        "fretting, sphere under a 100× stiffer sphere (K = 0.196), μ = 0.5, δ* = 1 µm, 24²: "
        "what the coupling changes (no analytic target): first loop's energy over the "
        "second's; the loop's asymmetry |Q+| − |Q−|",
        "first loop ≥ 1.1 × the second, asymmetry > 1e-3 of Q* (at K = 0 both vanish: 1e-4, 1e-5)",
        f"{first:.4g} then {second:.4g} mJ ({first / second - 1.0:+.0%}); Q = "
        f"{loop[:, 2].max():+.4g} / {loop[:, 2].min():+.4g} N "
        f"({(loop[:, 2].max() + loop[:, 2].min()) / loop[:, 2].max():+.1%})",
    )


@pytest.mark.parametrize("amplitude", [0.0005, 0.004, 0.02])
def test_fields_are_recorded_at_plus_q_star(amplitude):
    """Partial (0.5 µm) and gross slip (4, 20 µm): a symmetric loop reaches ±Q* alike up to
    the solver's tolerance; the recorded fields are those at +Q* in every recorded cycle
    (∫ q_x dA = +Q*, within the 10⁻⁴ of the tie: the loop's own asymmetry), never the
    sign round-off picks."""
    settings = FrettingSettings(LOAD, 2, 3, amplitude=amplitude, record=(1, 2, 3))
    analysis = FrettingAnalysis(solver(16), WearLaw(0.0, 0.0), settings)
    result = analysis.run()
    area = analysis.solver.grid.element_area
    for cycle, fields in result.records.items():
        force = float(np.sum(fields["traction_x"]) * area)
        largest = float(np.max(np.abs(fields["loop"][:, 2])))  # Q along x over the loop
        assert force == pytest.approx(largest, rel=1e-4), cycle
