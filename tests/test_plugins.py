"""Plug-ins from other packages: the example package of ``examples/plugins/`` (installed by
scripts/test.sh) registers a cone profile and a fatigue criterion through entry points; the
engine finds them, reads their keys, sweeps them, and solves the cone as Sneddon did. A name
registered twice is an error naming both distributions."""

from __future__ import annotations

import math
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pytest

import engine
from engine import plugins
from engine.fatigue import CRITERIA
from engine.geometry import PROFILES, Profile, profile_for
from engine.grid import Grid
from engine.material import MaterialPair
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw
from engine.solvers.wear_laws import WEAR_LAWS
from engine.study.config import SWEEPABLE, StudyConfigError, parse_study
from engine.study.examples import study_toml
from engine.study.plan import make_plan
from engine.study.units import unit_of

EXAMPLE = "fretting-engine-cone"
PAPER = MaterialPair(200e3, 0.3, 200e5, 0.3)


def _example():
    """The example package: installed by scripts/test.sh (``pip install -e
    examples/plugins``); without it these tests fail, they do not skip."""
    if "cone" not in PROFILES:
        pytest.fail("the example plug-ins are not installed: pip install -e examples/plugins")
    from fretting_engine_cone import cone

    return cone


def test_the_example_registers_a_profile_and_a_criterion_by_entry_point():
    _example()
    assert PROFILES.owner("cone") == EXAMPLE and issubclass(PROFILES["cone"], Profile)
    assert CRITERIA.owner("shear_amplitude") == EXAMPLE
    assert PROFILES.owner("flat") == plugins.ENGINE_DISTRIBUTION


def test_the_cone_against_sneddon():
    """32² over 1.5 a, frictionless, α = 1°: the approach within 0.1 % of Sneddon's
    δ = (π/2) a tan α (the log-singular pressure at the tip is resolved by the element
    integrals; measured −0.015 %, −0.003 % at 64²) and the area-equivalent contact radius
    within 3 % of a (the edge is located to within one element, 9 % of a here; measured
    +1.5 %, +0.2 % at 64²)."""
    cone = _example()
    load, angle, modulus = 750.0, 1.0, PAPER.contact_modulus
    radius = cone.sneddon_contact_radius(load, angle, modulus)
    grid = Grid.square(32, 1.5 * radius)
    profile = profile_for("cone", angle=angle)
    assert profile.contact_length(load, modulus) == radius
    solver = ContactSolver(
        grid, PAPER, profile, FrictionLaw(0.0, 0.0, 0.0), tol=1e-10, planner_effort="FFTW_ESTIMATE"
    )
    result = solver.solve_load(load)
    assert result.report.converged
    assert result.approach == pytest.approx(cone.sneddon_approach(load, angle, modulus), rel=1e-3)
    contact = math.sqrt(result.contact_area(grid.element_area) / math.pi)
    assert contact == pytest.approx(radius, rel=0.03)


def _cone_study(**sweep):
    return study_toml(
        "cone",
        "cone.h5",
        punch={"shape": "cone", "angle": 1.0, "radius": None},
        loading={"kind": "static", "load": 750.0, "steps": 2},
        mesh={"n": 16},
        sweep={"mu1": [0.0]} | sweep,
    )


def test_the_cone_owns_its_key_which_sweeps_and_is_checked():
    _example()
    assert SWEEPABLE["punch.angle"] == "degree"
    config = parse_study(_cone_study())
    assert config.punch.angle == 1.0 and config.resolved()["punch"] == {
        "angle": 1.0,
        "shape": "cone",
    }
    text = (
        _cone_study()
        .replace("angle = 1.0", "")
        .replace("[sweep]", '[sweep]\n"punch.angle" = [0.5, 2.0]')
    )
    plan = make_plan(parse_study(text))
    assert [case.case_id for case in plan.cases] == ["mu0_w0_b0_angle0.5", "mu0_w0_b0_angle2"]
    with pytest.raises(StudyConfigError, match=r"\[punch\] angle = 45.0: must be <= 30 degree"):
        parse_study(_cone_study().replace("angle = 1.0", "angle = 45.0"))
    with pytest.raises(StudyConfigError, match=r'\[punch\] radius = 1.0: only for shape = "flat"'):
        parse_study(_cone_study().replace("angle = 1.0", "angle = 1.0\nradius = 1.0"))


def test_the_example_criterion_is_a_fatigue_criterion_of_the_study_file():
    _example()
    assert SWEEPABLE["fatigue.tau_a"] == "MPa"
    from engine.study.fatigue import parse_fatigue
    from engine.study.settings.reader import Section

    config = parse_fatigue(
        Section("s.toml", "fatigue", {"criteria": ["shear_amplitude"], "tau_a": 200.0})
    )
    assert config.constants == {"tau_a": 200.0}
    with pytest.raises(StudyConfigError, match=r"\[fatigue\] tau_a = -1.0"):
        parse_fatigue(
            Section("s.toml", "fatigue", {"criteria": ["shear_amplitude"], "tau_a": -1.0})
        )


class _EntryPoint(SimpleNamespace):
    def load(self):
        return self.obj


def _registry(monkeypatch, *points):
    monkeypatch.setattr(plugins, "entry_points", lambda group: list(points))
    return plugins.Registry(
        "fretting_engine.profiles",
        {"flat": PROFILES["flat"]},
        what="punch profile",
        check=plugins.subclass_of(Profile),
    )


def _point(name, obj, distribution):
    return _EntryPoint(
        name=name, value=f"{distribution}:{name}", obj=obj, dist=SimpleNamespace(name=distribution)
    )


def test_a_name_registered_twice_names_both_distributions(monkeypatch):
    table = _registry(monkeypatch, _point("flat", PROFILES["sphere"], "other-flat"))
    with pytest.raises(
        plugins.PluginError,
        match="'flat' is registered twice, by fretting-engine and by other-flat",
    ):
        dict(table)
    sphere = PROFILES["sphere"]
    table = _registry(monkeypatch, _point("sphere", sphere, "one"), _point("sphere", sphere, "two"))
    with pytest.raises(plugins.PluginError, match="by one and by two"):
        list(table)


def test_an_entry_point_of_the_wrong_kind_or_name_is_refused(monkeypatch):
    with pytest.raises(
        plugins.PluginError, match="is not a subclass of engine.geometry.base.Profile"
    ):
        dict(_registry(monkeypatch, _point("nothing", object, "bad")))
    with pytest.raises(plugins.PluginError, match="loads a punch profile named 'sphere'"):
        dict(_registry(monkeypatch, _point("ball", PROFILES["sphere"], "bad")))


def test_entry_points_are_read_when_the_table_is_first_read(monkeypatch):
    calls = []
    monkeypatch.setattr(plugins, "entry_points", lambda group: calls.append(group) or [])
    table = plugins.Registry("fretting_engine.criteria", {}, what="fatigue criterion")
    assert calls == []
    assert list(table) == [] and calls == ["fretting_engine.criteria"]
    assert len(table) == 0 and calls == ["fretting_engine.criteria"]  # loaded once


def test_the_environment_can_leave_the_plug_ins_out(monkeypatch):
    """FRETTING_ENGINE_BUILT_IN_ONLY: the tables hold the engine's own entries (how the
    manual's generated help is written whatever is installed)."""
    monkeypatch.setenv(plugins.BUILT_IN_ONLY, "1")
    table = plugins.Registry("fretting_engine.profiles", PROFILES.builtins, what="punch profile")
    assert dict(table) == PROFILES.builtins


# ---------------------------------------------------------------------- the example wear law
def _threshold_study(output: str, **sweep) -> str:
    return study_toml(
        "threshold",
        output,
        wear={"law": "threshold"},
        sweep={"mu1": [0.3]} | sweep,
    )


def test_the_example_wear_law_is_registered_and_its_coefficients_sweep():
    _example()
    assert WEAR_LAWS.owner("threshold") == EXAMPLE
    assert WEAR_LAWS.owner("archard") == plugins.ENGINE_DISTRIBUTION
    text = _threshold_study("t.h5", wear_rate=[1e-7, 2e-7], threshold_pressure=[50.0])
    plan = make_plan(parse_study(text))
    assert plan.case_ids == ("mu0.3_t1e-07-50_b0", "mu0.3_t2e-07-50_b0")
    parameters = plan.cases[0].parameters()
    assert list(parameters)[2:] == [
        "mu1", "mu2", "wear1", "wear2", "beta", "wear_rate", "threshold_pressure"
    ]  # fmt: skip
    assert (parameters["wear1"], parameters["wear2"]) == (0.0, 0.0)  # not Archard's
    assert unit_of("wear_rate") == "1/MPa" and unit_of("threshold_pressure") == "MPa"
    with pytest.raises(StudyConfigError, match=r"\[sweep\] threshold_pressure = -1.0"):
        parse_study(_threshold_study("t.h5", wear_rate=[1e-7], threshold_pressure=[-1.0]))
    with pytest.raises(StudyConfigError, match=r"\[sweep\] wear_rate = 0.5: wear coefficient"):
        parse_study(_threshold_study("t.h5", wear_rate=[0.5], threshold_pressure=[0.0]))
    with pytest.raises(StudyConfigError, match=r'\[sweep\] wear1 = .*law = "threshold" takes'):
        parse_study(_threshold_study("t.h5", wear1=[1e-7]))


def test_the_example_wear_law_against_a_hand_computed_depth():
    """Δω = k ⟨p − p_th⟩ |Δs| on four elements, k = 2e-7 1/MPa, p_th = 100 MPa, computed by
    hand: (300 − 100)·2e-7·5e-3 = 2e-7 mm (slip 3-4-5 µm), 0 below and at the threshold,
    (150 − 100)·2e-7·1e-3 = 1e-8 mm; to 1e-15 relative (a few roundings of float64)."""
    _example()
    law = WEAR_LAWS["threshold"].from_coefficients(
        {"wear_rate": 2e-7, "threshold_pressure": 100.0}, beta=0.7
    )
    result = SimpleNamespace(
        pressure=np.array([[300.0, 50.0], [100.0, 150.0]]),  # MPa
        slip_x=np.array([[3e-3, 1e-3], [1e-3, 0.0]]),  # mm
        slip_y=np.array([[4e-3, 0.0], [0.0, -1e-3]]),
    )
    expected = np.array([[2e-7, 0.0], [0.0, 1e-8]])  # mm
    np.testing.assert_allclose(law.increment(result, None), expected, rtol=1e-15, atol=0.0)
    twice = law.scaled(2.0).increment(result, None)  # two bodies: the rate doubles
    np.testing.assert_allclose(twice, 2.0 * expected, rtol=1e-15, atol=0.0)


def test_the_example_wear_law_in_a_study_against_archard(tmp_path, monkeypatch):
    """A cyclic study (flat punch, 16², 200 cycles): with p_th = 0 the law is Archard's with
    i1 = i2 = k, the same wear depth to 1e-12 relative (|Δs| computed as hypot(k Δs1, k Δs2)
    by Archard, k hypot(Δs_x, Δs_y) here: the last bits differ and the solver's iterations
    follow them); with p_th above every pressure nothing wears."""
    _example()
    monkeypatch.chdir(tmp_path)
    rate = 1.33e-7
    archard = engine.run_study(
        study_toml("archard", "archard.h5", sweep={"mu1": [0.3], "wear1": [rate]}),
        progress=False,
    )
    threshold = engine.run_study(
        _threshold_study("threshold.h5", wear_rate=[rate], threshold_pressure=[0.0, 1e4]),
        progress=False,
    )
    assert archard.status == threshold.status == "completed"
    depth = archard.summary["max_wear_depth"].iloc[0]
    worn, unworn = threshold.summary["max_wear_depth"]
    assert depth > 0.0
    assert worn == pytest.approx(depth, rel=1e-12)
    assert unworn == 0.0
    assert list(threshold.summary.columns[-2:]) == ["wear_rate", "threshold_pressure"]


# ---------------------------------------------------------------------- a loading kind's keys
def test_a_kind_of_another_package_describes_its_keys_in_the_reference():
    """A kind registered beside the built-in ones gets its [loading] rows from its own
    dataclass, without any table of the engine: its key with unit, meaning and label, its
    meaning of ``steps`` beside the built-in kinds', and itself among the readers of the
    keys it shares."""
    from dataclasses import dataclass

    from engine.study.config.keys import loading_keys
    from engine.study.kinds import KINDS
    from engine.study.kinds.base import CycledKind, CycledLoading
    from engine.study.settings.sections import loading_key
    from engine.study.units import loading_units

    @dataclass(frozen=True)
    class RampedLoading(CycledLoading):
        steps: int = loading_key("1", "load increments per ramp", default=5)
        ramp: float = loading_key("s", "duration of the load ramp", default=1.0, label="ramp")

    class RampedKind(CycledKind):
        name = "ramped"
        summary = "load cycles with a timed ramp"
        config = RampedLoading

    kinds = {**KINDS.builtins, "ramped": RampedKind()}
    rows = {key.name: key for key in loading_keys(kinds)}
    assert '`"ramped"`: load cycles with a timed ramp' in rows["kind"].meaning
    ramp = rows["ramp"]
    assert (ramp.type, ramp.default, ramp.unit) == ("number", "1 (ramped)", "s")
    assert (ramp.meaning, ramp.title) == ("duration of the load ramp", "ramp")
    assert "ramped: load increments per ramp" in rows["steps"].meaning
    assert rows["steps"].default == "static, cyclic, fretting: 10; ramped: 5"
    assert rows["cycles"].default == "required (cyclic, fretting, ramped)"
    assert loading_units(kinds)["loading.ramp"] == "s"


# ---------------------------------------------------------------------- discovery
def test_the_scan_of_sys_path_finds_the_groups_importlib_metadata_finds():
    """The cheap scan (entry_points.txt on sys.path) agrees with importlib.metadata here,
    where the example package declares three of the four groups."""
    import importlib.metadata

    found = {
        group for group in plugins.GROUPS.values() if importlib.metadata.entry_points(group=group)
    }
    assert plugins.declared_groups() == found


def test_a_group_nobody_declares_does_not_import_importlib_metadata():
    """No distribution declares fretting_engine.kinds: the table reads nothing, and the
    metadata machinery (about 20 ms and 1.5 MB at start-up) is not imported."""
    code = (
        "import sys; from engine import plugins; "
        "assert plugins.entry_points('fretting_engine.kinds') == (); "
        "assert 'importlib.metadata' not in sys.modules, 'imported'"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_the_scan_reads_dist_info_folders_and_gives_up_on_archives(tmp_path, monkeypatch):
    info = tmp_path / "cone-1.0.dist-info"
    info.mkdir()
    (info / "entry_points.txt").write_text(
        "[console_scripts]\ncone = cone:main\n\n[fretting_engine.profiles]\ncone = cone:Cone\n"
    )
    monkeypatch.setattr(sys, "path", [str(tmp_path), str(tmp_path / "absent")])
    assert plugins._scan_groups() == {"fretting_engine.profiles"}
    archive = tmp_path / "plugins.zip"
    archive.write_bytes(b"PK\x05\x06" + bytes(18))
    monkeypatch.setattr(sys, "path", [str(tmp_path), str(archive)])
    assert plugins._scan_groups() is None  # left to importlib.metadata
