"""The fatigue criteria on textbook histories: fully reversed tension–compression and pure
torsion give each criterion's closed-form value (fast)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine import fatigue
from engine.fatigue import quantities
from engine.fatigue.history import Elasticity, StressHistory
from engine.keys import Key

STEEL = Elasticity(young_modulus=200000.0, poisson_ratio=0.3)
LIMITS = {"sigma_d": 300.0, "tau_d": 200.0}
SWT = {"sigma_f": 1000.0, "b": -0.09, "eps_f": 0.6, "c": -0.6}
FS = {"tau_f": 600.0, "gamma_f": 0.9, "b0": -0.09, "c0": -0.6, "k": 0.6, "sigma_y": 800.0}
CONSTANTS = {**LIMITS, **SWT, **FS}
INSTANTS = 64  # a multiple of 4: the sampled sine reaches ±1 exactly


def _history(mean=0.0, amplitude=0.0, *, component="xx", points=1) -> StressHistory:
    """σ_component = mean + amplitude sin(2πk/n) at ``points`` identical points."""
    phase = 2 * np.pi * np.arange(INSTANTS) / INSTANTS
    values = mean + amplitude * np.round(np.sin(phase), 15)
    components = {component: np.repeat(values[:, None], points, axis=1)}
    if component != "xx":
        components["xx"] = np.zeros((INSTANTS, points))
    return StressHistory.from_components(components, np.arange(points, dtype=float), 0.0)


def _value(name, history, **options):
    criterion = fatigue.build_criteria([name], CONSTANTS, STEEL, fatigue.FatigueOptions(**options))[
        0
    ]
    return criterion.evaluate(history)


@pytest.mark.parametrize("name", ["crossland", "dang_van"])
@pytest.mark.parametrize("method", ["chord", "ball"])
def test_stress_invariant_criteria_are_exact_at_the_two_limits(name, method):
    """Fully reversed tension at σ_d and torsion at τ_d give risk 1, half of them 0.5 (both
    criteria are linear in the amplitude; 1e-9: rounding and the ball's 1e-10 gap)."""
    for amplitude, component, limit in (("sigma_d", "xx", 1.0), ("tau_d", "xz", 1.0)):
        for scale in (1.0, 0.5):
            history = _history(amplitude=scale * LIMITS[amplitude], component=component)
            value = _value(name, history, amplitude_method=method).value[0]
            assert value == pytest.approx(scale * limit, rel=1e-9)


def test_mean_stress_raises_crossland_and_dang_van():
    """R = 0 tension to σ_max: Crossland (σ_max/(2√3) + α σ_max/3)/τ_d and Dang Van
    (σ_max/2·… : σ_a/2 + α_DV σ_max/3)/τ_d (closed forms; 1e-9 rounding)."""
    peak = 360.0
    history = _history(mean=peak / 2, amplitude=peak / 2)
    alpha_c = 3 * 200.0 / 300.0 - math.sqrt(3)
    alpha_dv = 3 * 200.0 / 300.0 - 1.5
    crossland = (peak / (2 * math.sqrt(3)) + alpha_c * peak / 3) / 200.0
    dang_van = (peak / 4 + alpha_dv * peak / 3) / 200.0
    assert _value("crossland", history).value[0] == pytest.approx(crossland, rel=1e-9)
    assert _value("dang_van", history).value[0] == pytest.approx(dang_van, rel=1e-9)
    assert crossland > _value("crossland", _history(amplitude=peak / 2)).value[0]


def test_swt_tension_and_torsion():
    """SWT = σ_a²/E on the plane normal to the load (φ = 90°) in tension and (1 + ν)τ_a²/E
    on a ±45° plane in torsion (1e-12: rounding; planes every 1°, both maxima on the grid)."""
    tension = _value("swt", _history(amplitude=250.0))
    assert tension.value[0] == pytest.approx(250.0**2 / 2e5, rel=1e-12)
    assert tension.angle[0] == 90.0
    torsion = _value("swt", _history(amplitude=150.0, component="xz"))
    assert torsion.value[0] == pytest.approx(1.3 * 150.0**2 / 2e5, rel=1e-12)
    assert torsion.angle[0] in (45.0, 135.0)


def test_fatemi_socie_tension_and_torsion():
    """Torsion: FS = τ_a/G on the shear planes (φ = 0° or 90°; σ_n = 0 there); tension:
    γ_a = σ_a/(2G) at ±45° with σ_n,max = σ_a/2, FS = γ_a(1 + kσ_a/(2σ_y)) (1e-12)."""
    shear_modulus = STEEL.shear_modulus
    torsion = _value("fatemi_socie", _history(amplitude=150.0, component="xz"))
    assert torsion.value[0] == pytest.approx(150.0 / shear_modulus, rel=1e-12)
    assert torsion.angle[0] in (0.0, 90.0)
    tension = _value("fatemi_socie", _history(amplitude=250.0))
    expected = 250.0 / (2 * shear_modulus) * (1 + 0.6 * 125.0 / 800.0)
    assert tension.value[0] == pytest.approx(expected, rel=1e-12)
    assert tension.angle[0] in (45.0, 135.0)


def test_life_inversion_round_trip():
    """SWT and FS lives invert the Basquin–Coffin–Manson curves: a value computed at N gives
    N back (2N to 1e-9 relative: 60 bisections on log 2N)."""
    lives = np.array([1e3, 1e5, 1e7, 3e9])
    reversals = 2 * lives
    swt_curve = SWT["sigma_f"] ** 2 / 2e5 * reversals ** (2 * SWT["b"]) + SWT["sigma_f"] * SWT[
        "eps_f"
    ] * reversals ** (SWT["b"] + SWT["c"])
    criterion = fatigue.build_criteria(["swt"], CONSTANTS, STEEL)[0]
    assert criterion.life(swt_curve) == pytest.approx(lives, rel=1e-9)
    g = STEEL.shear_modulus
    fs_curve = FS["tau_f"] / g * reversals ** FS["b0"] + FS["gamma_f"] * reversals ** FS["c0"]
    criterion = fatigue.build_criteria(["fatemi_socie"], CONSTANTS, STEEL)[0]
    assert criterion.life(fs_curve) == pytest.approx(lives, rel=1e-9)
    assert criterion.life(np.array([0.0, -1.0])).tolist() == [math.inf, math.inf]


def test_shear_amplitude_chord_and_ball_differ_on_a_triangle():
    """Three instants of unit shear σ_yz, σ_xz, σ_xy: an equilateral triangle of side √2 in
    the deviatoric coordinates; half the longest chord is 1/√2, the circumscribed ball's
    radius √(2/3). A circle (σ_xz, σ_xy) = τ(cos, sin) gives τ by both (1e-9: the ball's
    gap; the circle sampled at 64 instants has its chord on a diameter)."""
    eye = np.eye(3)
    triangle = StressHistory.from_components(
        {"xx": np.zeros((3, 1)), "yz": eye[:, :1], "xz": eye[:, 1:2], "xy": eye[:, 2:]}, 0.0, 0.0
    )
    assert quantities.shear_amplitude(triangle, "chord")[0] == pytest.approx(1 / math.sqrt(2))
    assert quantities.shear_amplitude(triangle, "ball")[0] == pytest.approx(
        math.sqrt(2 / 3), rel=1e-9
    )
    phase = 2 * np.pi * np.arange(INSTANTS)[:, None] / INSTANTS
    circle = StressHistory.from_components(
        {"xx": 0 * phase, "xz": 70 * np.cos(phase), "xy": 70 * np.sin(phase)}, 0.0, 0.0
    )
    for method in ("chord", "ball"):
        assert quantities.shear_amplitude(circle, method)[0] == pytest.approx(70.0, rel=1e-9)


def test_missing_or_bad_constants_are_named():
    with pytest.raises(ValueError, match=r"missing \['tau_d'\]"):
        fatigue.build_criteria(["crossland"], {"sigma_d": 300.0}, STEEL)
    with pytest.raises(ValueError, match="'b' must be < 0"):
        fatigue.build_criteria(["swt"], {**SWT, "b": 0.1}, STEEL)
    with pytest.raises(ValueError, match="unknown fatigue criterion 'goodman'"):
        fatigue.build_criteria(["goodman"], CONSTANTS, STEEL)


class MaximumPrincipal(fatigue.FatigueCriterion):
    """A fifth criterion written by a user: the maximum principal stress over the cycle
    divided by a limit (MPa)."""

    name = "max_principal"
    column = "principal_risk"
    unit = "1"
    constants = {"sigma_u": Key("MPa", "ultimate tensile strength")}

    def evaluate(self, history):
        principal = np.linalg.eigvalsh(history.matrices())[..., -1]
        return fatigue.CriterionField(principal.max(axis=0) / self.sigma_u)


def _graded_history(x, z):
    """Fully reversed tension σ_a = 300 (1 − z/4) (MPa) at the points (x, z) (mm)."""
    x, z = np.atleast_1d(x), np.atleast_1d(z)
    amplitude = 300.0 * (1 - z / 4.0) * np.exp(-(x**2))
    phase = 2 * np.pi * np.arange(INSTANTS)[:, None] / INSTANTS
    return StressHistory.from_components({"xx": np.sin(phase) * amplitude[None]}, x, z)


@pytest.mark.parametrize(
    ("method", "depth"),
    [("point", 0.25), ("line", 0.5), ("area", 4 * 1.32 * 0.5 / (3 * math.pi))],
)
def test_critical_distance_methods_and_a_fifth_criterion(method, depth):
    """On a field linear in depth, ℓ = 0.5 mm: the point method reads z = ℓ/2, the line mean
    over 0…2ℓ equals the value at ℓ, the half-disc mean the value at its centroid depth
    4R/(3π) (Gauss quadrature exact for these polynomials in z; x = 0 is the hot spot, the
    area's x-dependence e^{−x²} is not polynomial, so the area row is checked on a field
    constant in x: 1e-12). A user's criterion passed as a class runs through the same driver."""
    x = np.linspace(-1, 1, 21)
    z = np.array([0.0, 0.5, 1.0])
    xs, zs = np.meshgrid(x, z, indexing="ij")

    def flat(x, z):
        return _graded_history(0.0 * x, z) if method == "area" else _graded_history(x, z)

    history = flat(xs.ravel(), zs.ravel())
    criteria = fatigue.build_criteria(
        ["crossland", MaximumPrincipal], {**CONSTANTS, "sigma_u": 600.0}, STEEL
    )
    crossland, principal = fatigue.assess(
        history, criteria, method=method, length=0.5, stress_at=flat
    )
    expected = 300.0 * (1 - depth / 4.0)
    assert principal.critical == pytest.approx(expected / 600.0, rel=1e-12)
    assert crossland.critical == pytest.approx(expected / 300.0, rel=1e-12)
    assert crossland.hot_spot.value == pytest.approx(1.0, rel=1e-12)
    assert crossland.hot_spot.z == 0.0
    assert principal.summary() == {
        "principal_risk": pytest.approx(0.5),
        "principal_risk_x": principal.hot_spot.x,
        "principal_risk_z": 0.0,
        "principal_risk_critical": principal.critical,
    }


def test_two_pass_plane_search_matches_the_exhaustive_search():
    """SWT's 5°-then-1° search against scoring all 180 planes on random non-proportional
    histories (300 points): never above (it visits a subset of the planes), within 1e-3 of
    the exhaustive maximum (the bound of ``search_planes``: the score's variation over
    2.5°) and equal at 97 % of the points or more; Fatemi–Socie (one pass) equal to it."""
    rng = np.random.default_rng(5)
    phase = 2 * np.pi * np.arange(24)[:, None] / 24
    components = {
        key: rng.normal(0, 80, (1, 300))
        + rng.normal(0, 100, (1, 300)) * np.sin(phase + rng.uniform(0, 6, (1, 300)))
        for key in ("xx", "yy", "zz", "xz")
    }
    history = StressHistory.from_components(components, 0.0, 0.0)
    for name in ("swt", "fatemi_socie"):
        criterion = fatigue.build_criteria([name], CONSTANTS, STEEL)[0]
        fast = criterion.evaluate(history).value
        everything = quantities.plane_family(1.0)
        exhaustive = criterion._score(quantities.ResolvedStress(history.tensor, everything))
        best = exhaustive.max(axis=1)
        assert np.all(fast <= best * (1 + 1e-12))
        assert np.all(fast >= best * (1 - 1e-3))
        assert np.mean(np.isclose(fast, best, rtol=1e-12)) >= (0.97 if name == "swt" else 1.0)


def test_minimum_ball_converges_on_a_slow_fretting_path():
    """The two slowest paths of a 3-D fretting cycle (sphere R = 10 mm on steel, 128², 80
    instants, Q* = 0.646 μP; deviatoric coordinates in MPa): near-duplicate instants on both
    sides of each load reversal slow Frank–Wolfe to 7,857 steps. The ball converges to the
    relative gap 1e-10; every instant lies inside it (1e-12: rounding), its radius is at
    least half the longest chord (any enclosing ball's is) and, the paths being nearly a
    segment between the reversals, within 0.1 % of it."""
    from pathlib import Path

    from engine.fatigue.quantities import minimum_ball

    path = np.load(Path(__file__).parent / "data" / "slow_minimum_ball.npy")
    ball = minimum_ball(path)
    assert ball.converged and ball.iterations > 5000
    offsets = path - ball.centre[None]
    assert np.all(np.linalg.norm(offsets, axis=-1) <= ball.radius * (1 + 1e-12))
    chord = 0.5 * np.linalg.norm(path[:, None] - path[None], axis=-1).max(axis=(0, 1))
    assert np.all(ball.radius >= chord * (1 - 1e-12))  # a ball holds its longest chord
    assert np.all(ball.radius <= chord * (1 + 1e-3))  # near a segment: radius ≈ half chord


@pytest.mark.parametrize("mean_shear", [40.0, -40.0])
def test_fatemi_socie_takes_the_larger_value_of_tied_planes(mean_shear):
    """σ_xx = a sin ωt with a constant σ_xz = c: γ_a = a/(2G) on both ±45° planes (tied,
    to round-off), σ_n,max = a/2 + c on one, a/2 − c on the other. The criterion takes the
    larger FS, (a/(2G))(1 + k(a/2 + |c|)/σ_y), whichever sign c has (the mirror image of
    the history, x → −x), so the choice does not depend on the side or on round-off
    (1e-12: rounding)."""
    amplitude = 250.0
    phase = 2 * np.pi * np.arange(INSTANTS) / INSTANTS
    xx = amplitude * np.round(np.sin(phase), 15)
    components = {"xx": xx[:, None], "xz": np.full((INSTANTS, 1), mean_shear)}
    history = StressHistory.from_components(components, np.zeros(1), 0.0)
    result = _value("fatemi_socie", history)
    gamma = amplitude / (2 * STEEL.shear_modulus)
    larger = gamma * (1 + FS["k"] * (amplitude / 2 + abs(mean_shear)) / FS["sigma_y"])
    smaller = gamma * (1 + FS["k"] * (amplitude / 2 - abs(mean_shear)) / FS["sigma_y"])
    assert result.value[0] == pytest.approx(larger, rel=1e-12)
    assert smaller < 0.95 * larger  # the other plane's value: the choice matters
    assert result.angle[0] in (45.0, 135.0)
