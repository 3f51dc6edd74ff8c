"""Two-body wear of a line contact and the scar measures (engine.solvers.scar)."""

import math

import numpy as np
import pytest

from engine.grid import Grid
from engine.solvers.friction import EnergyWearLaw, WearLaw
from engine.solvers.scar import scar_measures, two_body_wear_law


def test_two_body_law_scales_the_flat_law():
    law = two_body_wear_law(WearLaw(2e-8, 1e-8, 0.3), 0.5)
    assert (law.i1, law.i2, law.beta) == pytest.approx((3e-8, 1.5e-8, 0.3), rel=1e-15)
    assert two_body_wear_law(EnergyWearLaw(4.0), 1.0).alpha == 8.0
    with pytest.raises(ValueError, match="pad_ratio"):
        two_body_wear_law(WearLaw(1e-8, 1e-8), -1.0)


def test_scar_measures_of_a_parabolic_scar():
    """h_flat = d (1 − x²/w²) on |x| < w sampled on 200 elements over ±1 mm: exact depth at
    the centre element pair, width to one element, area 4dw/3 to the midpoint rule."""
    grid = Grid.line(200, 1.0)
    depth, half = 10e-3, 0.5
    flat = np.clip(depth * (1 - (grid.x / half) ** 2), 0, None)
    ratio = 0.25
    measures = scar_measures(grid, (1 + ratio) * flat[:, None], ratio)
    assert measures.scar_depth == pytest.approx(flat.max(), rel=1e-14)
    # 1 % of the depth is reached at |x| = w √0.99: the width to one element.
    assert abs(measures.scar_width - 2 * half * np.sqrt(0.99)) <= grid.dx
    assert measures.scar_area == pytest.approx(4 * depth * half / 3, rel=1e-3)
    assert measures.pad_wear_depth == pytest.approx(ratio * flat.max(), rel=1e-14)
    assert set(measures.row()) == {"scar_depth", "scar_width", "scar_area", "pad_wear_depth"}


def test_no_wear_no_scar():
    measures = scar_measures(Grid.line(8, 1.0), np.zeros((8, 1)), 1.0)
    assert measures.row() == dict.fromkeys(measures.row(), 0.0)


def test_line_contact_of_a_study():
    """The study layer's line contact: nominal half-width (Hertz, Ciavarella) and p0 = P/(2a0)."""
    from engine.geometry import profile_for
    from engine.material import MaterialPair
    from engine.reference import line_contact as ref
    from engine.solvers.scar import pad_ratio
    from engine.study.line_contact import LineContact

    steel = MaterialPair(200e3, 0.3, 200e3, 0.3)
    e_star = steel.contact_modulus
    cylinder = LineContact(profile_for("cylinder", radius=6.0), 185.0)
    a = ref.hertz_line_half_width(185.0, 6.0, e_star)
    assert cylinder.nominal_half_width(e_star) == a
    assert cylinder.nominal_pressure(e_star) == pytest.approx(185.0 / (2 * a), rel=1e-15)
    pad = LineContact(profile_for("pad", radius=0.1, edge_radius=5.0), 200.0)
    assert pad.nominal_half_width(e_star) == ref.pad_half_width(200.0, 0.1, 5.0, e_star)
    assert pad_ratio(2.75e-8, 2.75e-8) == 1.0 and pad_ratio(None, 1e-8) == 0.0
    with pytest.raises(ValueError, match="pad_coefficient"):
        pad_ratio(1e-8, 0.0)


def test_a_sphere_that_wears_too(tmp_path):
    """A 3-D punch with ``[wear] pad_coefficient``: the gap carries both bodies' wear, so
    with k_pad = k_flat the case equals a one-body case of twice the coefficient bit for bit
    (the law is scaled by 1 + r = 2, exactly); the summary splits the depth (exact)."""
    from engine.output.summary import load_summary
    from engine.run import run_study
    from engine.study.examples import SPHERE_ON_STEEL, study_toml

    loading = {"kind": "fretting", "amplitude": 0.002, "cycles": 10, "record": [10]}
    rows = {}
    for name, wear, coefficient in (("two", {"pad_coefficient": 1e-7}, 1e-7), ("one", {}, 2e-7)):
        output = tmp_path / f"{name}.h5"
        text = study_toml(
            name, str(output), SPHERE_ON_STEEL, mesh={"n": 16}, loading=loading, wear=wear,
            sweep={"mu1": [0.5], "wear1": [coefficient]},
        )  # fmt: skip
        assert run_study(text, progress=False).status == "completed"
        (rows[name],) = load_summary(output).to_dict("records")
    two, one = rows["two"], rows["one"]
    assert two["max_wear_depth"] == one["max_wear_depth"] > 0
    assert two["wear_volume"] == one["wear_volume"]
    assert two["scar_depth"] == 0.5 * two["max_wear_depth"]
    assert two["pad_wear_depth"] == two["scar_depth"]
    assert "scar_depth" not in one or math.isnan(one["scar_depth"])
