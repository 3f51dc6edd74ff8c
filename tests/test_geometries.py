"""Contact geometries as plug-ins: one profile class per shape (engine.geometry), one table,
and no ``shape == ...`` anywhere else in the engine."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from engine.analysis.results import Results
from engine.geometry import PROFILES, profile_for
from engine.reference.hertz import hertz_contact_radius
from engine.reference.line_contact import hertz_line_half_width, pad_half_width

ENGINE = Path(__file__).resolve().parents[1] / "engine"
E_STAR = 200e3 / (2 * (1 - 0.3**2))  # MPa, two steel bodies


@pytest.mark.parametrize(
    ("shape", "radius", "edge", "load", "a0", "p0", "half_width", "line"),
    [  # a0 (mm), p0 (MPa) and the default mesh half-width (mm) from their closed forms
        ("flat", 1.8, None, 750.0, 1.8, 750.0 / (math.pi * 1.8**2), 1.5 * 1.8, False),
        ("rounded", 1.8, 0.2, 750.0, 1.8, 750.0 / (math.pi * 1.8**2), 1.05 * 2.0, False),
        ("sphere", 10.0, None, 100.0, "hertz", "hertz", "hertz", False),
        ("cylinder", 6.0, None, 185.0, "line", "line", "line", True),
        ("pad", 0.1, 5.0, 200.0, "pad", "pad", "pad", True),
    ],
)
def test_each_profile_supplies_its_contact_length_mesh_and_summary_values(
    shape, radius, edge, load, a0, p0, half_width, line
):
    keys = {"radius": radius} | ({} if edge is None else {"edge_radius": edge})
    profile = profile_for(shape, **keys)
    expected = {
        "hertz": lambda: hertz_contact_radius(load, radius, E_STAR),
        "line": lambda: hertz_line_half_width(load, radius, E_STAR),
        "pad": lambda: pad_half_width(load, radius, edge, E_STAR),
    }
    a0 = expected[a0]() if a0 in expected else a0
    if p0 in expected:  # Hertz's P/(π a²) for the sphere; P/(2 a0) per unit length
        p0 = load / (2 * a0) if line else load / (math.pi * a0**2)
    half_width = 1.5 * a0 if half_width in expected else half_width
    # equal to the last bit: the same expressions the summary has always used
    assert profile.contact_length(load, E_STAR) == a0
    assert profile.nominal(load, E_STAR) == {"a0": a0, "p0": pytest.approx(p0, rel=1e-15)}
    assert profile.default_half_width(load, E_STAR) == pytest.approx(half_width, rel=1e-15)
    grid = profile.grid(16, half_width)
    assert profile.is_line == line == grid.is_line
    profile.check_grid(grid)
    assert profile.gap(grid).shape == grid.shape


def test_the_punch_keys_are_the_profiles_dataclass_fields():
    with_edge = [name for name, profile in PROFILES.items() if "edge_radius" in profile.keys()]
    assert with_edge == ["rounded", "pad"]
    with pytest.raises(ValueError, match="unknown punch shape 'no-such-shape'"):
        profile_for("no-such-shape", radius=1.0)


def test_no_shape_branches_outside_the_geometry_package():
    # a shape compared with a name (not an array's shape with a tuple of sizes)
    pattern = re.compile(r"""shape"?\)?\s*(==|!=)\s*["']|shape"?\)?\s+(not\s+)?in\s*\(?\s*["']""")
    for path in ENGINE.rglob("*.py"):
        if "geometry" in path.relative_to(ENGINE).parts:
            continue
        for number, line in enumerate(path.read_text().splitlines(), start=1):
            assert not pattern.search(line), f"{path.relative_to(ENGINE)}:{number}: {line}"


def test_the_reader_takes_a0_and_p0_from_the_profile_of_a_line_contact():
    """A cylinder's a0 is its Hertz half-width and p0 = P/(2 a0), as in the summary."""
    config = {
        "punch": {"shape": "cylinder", "radius": 6.0},
        "loading": {"kind": "static", "load": 185.0},
        "material": {"E_A": 200e3, "nu_A": 0.3, "E_B": 200e3, "nu_B": 0.3},
        "mesh": {"n": 64},
    }
    study = Results.from_values("x", config, [], np.zeros(1), np.zeros(1))
    a0 = hertz_line_half_width(185.0, 6.0, study.material.contact_modulus)
    assert study.radius == a0
    assert study.p0 == 185.0 / (2.0 * a0)
