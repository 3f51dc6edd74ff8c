"""Two-body wear of a line contact and the scar measures (engine.solvers.scar)."""

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
    from engine.material import MaterialPair
    from engine.reference import line_contact as ref
    from engine.study.line_contact import LineContact, pad_ratio

    steel = MaterialPair(200e3, 0.3, 200e3, 0.3)
    e_star = steel.contact_modulus
    cylinder = LineContact("cylinder", 6.0, None, 185.0)
    a = ref.hertz_line_half_width(185.0, 6.0, e_star)
    assert cylinder.nominal_half_width(e_star) == a
    assert cylinder.nominal_pressure(e_star) == pytest.approx(185.0 / (2 * a), rel=1e-15)
    pad = LineContact("pad", 0.1, 5.0, 200.0)
    assert pad.nominal_half_width(e_star) == ref.pad_half_width(200.0, 0.1, 5.0, e_star)
    assert pad_ratio(2.75e-8, 2.75e-8) == 1.0 and pad_ratio(None, 1e-8) == 0.0
    with pytest.raises(ValueError, match="pad_coefficient"):
        pad_ratio(1e-8, 0.0)
