"""Conformance suites: one parametrised class per plug-in protocol, run over every registered
plug-in (the built-in ones and those other packages register, such as the example package of
``examples/plugins/``). A new profile, criterion, loading kind or wear law is tested by being
registered; no test here lists their names."""

from __future__ import annotations

import dataclasses
import importlib
import math
from types import SimpleNamespace

import numpy as np
import pytest

from engine.fatigue import CRITERIA, CriterionField, FatigueCriterion, FatigueOptions
from engine.fatigue.history import Elasticity, StressHistory
from engine.geometry import PROFILES, Profile, profile_for, profile_from_table
from engine.keys import Key, examples
from engine.material import MaterialPair
from engine.schema import DatasetSpec, fatigue_specs
from engine.solvers.wear import WearModel
from engine.solvers.wear_laws import WEAR_LAWS
from engine.study.config import SWEEPABLE, dump_toml, parse_study
from engine.study.config.keys import (
    STUDY_KEYS,
    fatigue_keys,
    loading_keys,
    punch_keys,
    wear_keys,
)
from engine.study.examples import study_toml
from engine.study.fatigue import FatigueConfig, criterion_schema, fatigue_columns
from engine.study.kinds import KINDS, LoadingKind
from engine.study.plan import make_plan
from engine.study.settings.checks import Limit
from engine.study.settings.sections import LoadingConfig
from engine.study.units import case_parameters, summary_columns, unit_of

#: The keys the manual describes, by (section, key).
BY_NAME = {(key.section, key.name): key for key in STUDY_KEYS}
E_STAR = 200e3 / (2 * (1 - 0.3**2))  # MPa, two steel bodies


def _load(profile: type[Profile]) -> float:
    """A load of the paper's magnitude in the profile's unit: 750 N, or 200 N/mm along a
    line contact."""
    return 200.0 if profile.is_line else 750.0


@pytest.mark.parametrize("name", list(PROFILES))
class TestProfile:
    """The protocol of :class:`engine.geometry.Profile` (engine/geometry/base.py)."""

    def test_is_a_frozen_dataclass_registered_under_its_name(self, name):
        cls = PROFILES[name]
        assert issubclass(cls, Profile) and cls.name == name and cls.description
        assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen
        assert cls.gap is not Profile.gap

    def test_declares_every_field_as_a_key_with_unit_and_meaning(self, name):
        cls = PROFILES[name]
        keys = cls.keys()
        assert list(keys) == [field.name for field in dataclasses.fields(cls)]
        for key_name, key in keys.items():
            assert isinstance(key, Key) and key.unit and key.meaning, key_name
            assert SWEEPABLE[f"punch.{key_name}"] == key.unit
            described = {k.name: k for k in punch_keys()}[key_name]
            assert f"{name}: {key.meaning}" in described.meaning
            value = examples(cls)[key_name]
            assert key.check(key_name, value) == value
            if key.minimum is not None:
                with pytest.raises(ValueError, match=key_name):
                    cls(**(examples(cls) | {key_name: key.minimum - 1.0}))

    def test_gap_contact_length_and_default_mesh(self, name):
        """The gap (mm) has the grid's shape, is ≥ 0 or inf (no surface) and is smallest at
        the element nearest to the axis; a0 > 0; the default mesh covers the contact and
        passes the grid check; p0 is the load over the nominal area (π a0², or 2 a0 per
        unit length)."""
        cls = PROFILES[name]
        profile = cls(**examples(cls))
        load = _load(cls)
        a0 = profile.contact_length(load, E_STAR)
        assert a0 > 0.0 and math.isfinite(a0)
        half_width = profile.default_half_width(load, E_STAR)
        assert half_width >= a0
        grid = profile.grid(32, half_width)
        assert grid.is_line == cls.is_line
        profile.check_grid(grid)
        gap = profile.gap(grid)
        assert gap.shape == grid.shape
        assert np.all((gap >= 0.0) | np.isinf(gap)) and not np.any(np.isnan(gap))
        x, y = grid.coordinates()
        distance = np.abs(x) if cls.is_line else np.hypot(x, y)
        assert gap[np.unravel_index(np.argmin(distance), grid.shape)] == np.min(gap)
        area = 2.0 * a0 if cls.is_line else math.pi * a0**2
        nominal = profile.nominal(load, E_STAR)
        assert nominal["a0"] == a0
        assert nominal["p0"] == pytest.approx(load / area, rel=1e-12)
        assert cls.load_unit == ("N/mm" if cls.is_line else "N")

    def test_fretting_references_are_all_there_or_all_none(self, name):
        """Closed forms (δ_slip, the loop) where the profile has them, None for each where
        it has none."""
        cls = PROFILES[name]
        profile, load = cls(**examples(cls)), _load(cls)
        material = MaterialPair(200e3, 0.3, 200e3, 0.3)
        distance = 10.0 if cls.is_line else None
        reference = profile.fretting_reference(load, material, 0.5, distance)
        slip = profile.slip_displacement(load, material, 0.5, distance)
        loop = profile.fretting_loop(load, material, 0.5, distance, displacement_amplitude=1e-3)
        assert (reference is None) == (slip is None) == (loop is None)
        if reference is not None:
            assert slip == reference.slip_displacement > 0.0

    def test_a_study_file_reads_it_and_the_results_rebuild_it(self, name):
        """[punch] shape = name with its example keys parses, and the stored [punch] table
        gives the same profile back (the results reader's way)."""
        cls = PROFILES[name]
        keys = examples(cls)
        punch = {"shape": name, "radius": None} | keys
        loading = {"kind": "static", "load": _load(cls), "steps": 1}
        text = study_toml(name, f"{name}.h5", punch=punch, loading=loading, sweep={"mu1": [0.0]})
        config = parse_study(text)
        assert config.punch.profile() == profile_for(name, **keys)
        assert profile_from_table(config.resolved()["punch"]) == config.punch.profile()


def _constants(cls: type[FatigueCriterion]) -> dict[str, float]:
    """Constants inside each declared range (the middle of it); 1 for a constant without one
    (a unit-free coefficient)."""
    return {
        name: 0.5 * (key.minimum + key.maximum)
        if key.minimum is not None and key.maximum is not None
        else 1.0
        for name, key in cls.constants.items()
    }


def _history(points: int = 3) -> StressHistory:
    """Fully reversed tension-torsion at ``points`` points, 9 instants (MPa)."""
    phase = np.linspace(0.0, 2.0 * np.pi, 9)[:, None] * np.ones(points)
    scale = np.arange(1, points + 1, dtype=float)
    components = {"xx": 100.0 * scale * np.sin(phase), "xz": 50.0 * scale * np.sin(phase)}
    return StressHistory.from_components(components, np.arange(points, dtype=float), 0.5)


@pytest.mark.parametrize("name", list(CRITERIA))
class TestCriterion:
    """The protocol of :class:`engine.fatigue.FatigueCriterion` (engine/fatigue/base.py)."""

    def test_declares_its_name_column_unit_and_constants(self, name):
        cls = CRITERIA[name]
        assert issubclass(cls, FatigueCriterion) and cls.name == name
        assert cls.column and cls.unit and cls.description
        assert cls.constants and all(isinstance(key, Key) for key in cls.constants.values())
        for constant, key in cls.constants.items():
            assert key.unit and key.meaning and key.required, constant
            assert SWEEPABLE[f"fatigue.{constant}"] == key.unit
            if key.minimum is not None or key.maximum is not None:  # refused outside, and why
                assert key.why, constant
                assert Limit.of(key).holds(_constants(cls)[constant]), constant
        # the manual's key table: the criterion named, each constant with a unit and meaning
        listed, constants = fatigue_keys()
        assert f'`"{name}"`' in listed.meaning
        described = {key.name: key for key in constants}
        for constant, key in cls.constants.items():
            assert described[constant].unit == key.unit, constant
            assert described[constant].meaning, constant
            assert name in described[constant].default, constant

    def test_evaluates_a_field_per_point_with_its_angle_and_life(self, name):
        cls = CRITERIA[name]
        criterion = cls(_constants(cls), Elasticity(200e3, 0.3), FatigueOptions())
        history = _history()
        field = criterion.evaluate(history)
        assert isinstance(field, CriterionField)
        assert field.value.shape == (3,) and np.all(np.isfinite(field.value))
        assert (field.angle is not None) == cls.reports_angle
        assert (field.life is not None) == cls.reports_life
        if cls.reports_life:
            assert np.shape(criterion.life(field.value)) == (3,)

    def test_is_vectorised_over_points(self, name):
        """A history of many different points gives, point by point, the one-point values
        (1e-12: the same arithmetic)."""
        cls = CRITERIA[name]
        criterion = cls(_constants(cls), Elasticity(200e3, 0.3), FatigueOptions())
        rng = np.random.default_rng(3)
        phase = 2 * np.pi * np.arange(16)[:, None] / 16
        shape = (5, 4)
        components = {
            key: rng.normal(0, 100, (1, *shape))
            + rng.normal(0, 100, (1, *shape)) * np.sin(phase + rng.uniform(0, 6, (1, 1)))[..., None]
            for key in ("xx", "yy", "zz", "xz")
        }
        history = StressHistory.from_components(components, rng.normal(size=shape), 0.0)
        whole = criterion.evaluate(history).value
        for point in (0, 7, 19):
            alone = criterion.evaluate(history.take(np.array([point]))).value[0]
            assert whole[point] == pytest.approx(alone, rel=1e-12)

    def test_missing_constants_are_refused_naming_them(self, name):
        cls = CRITERIA[name]
        constants = _constants(cls)
        missing = next(iter(cls.constants))
        del constants[missing]
        with pytest.raises(ValueError, match=missing):
            cls(constants, Elasticity(200e3, 0.3))

    def test_its_columns_and_datasets_follow_from_its_declaration(self, name):
        cls = CRITERIA[name]
        specs = fatigue_specs(*criterion_schema(cls))
        config = FatigueConfig((name,), _constants(cls))
        assert list(specs) == fatigue_columns(config)
        assert all(isinstance(spec, DatasetSpec) and spec.units for spec in specs.values())


def _function(reference: str):
    module, function = reference.split(":")
    return getattr(importlib.import_module(module), function)


@pytest.mark.parametrize("name", list(KINDS))
class TestLoadingKind:
    """The protocol of :class:`engine.study.kinds.LoadingKind` (engine/study/kinds/base.py)."""

    def test_is_registered_under_its_name_and_describes_itself(self, name):
        kind = KINDS[name]
        assert isinstance(kind, LoadingKind) and kind.name == name and kind.summary
        assert {"kind", "load", "steps"} <= kind.keys
        assert type(kind).parse is not LoadingKind.parse
        assert type(kind).run is not LoadingKind.run
        assert kind.increments(4) == kind.increments_per_step * 4
        assert kind.has_cycles == (kind.increments_per_step > 0)
        if kind.has_cycles:  # a kind with cycles can be stopped and resumed
            assert type(kind).save_state is not LoadingKind.save_state
            assert type(kind).load_state is not LoadingKind.load_state

    def test_its_loading_section_is_a_dataclass_declaring_its_keys(self, name):
        kind = KINDS[name]
        assert dataclasses.is_dataclass(kind.config) and issubclass(kind.config, LoadingConfig)
        assert kind.config.__dataclass_params__.frozen
        assert kind.keys == {field.name for field in dataclasses.fields(kind.config)}
        declared = kind.declared_keys()
        assert {"load", "steps"} <= declared.keys()
        for key, declaration in declared.items():
            assert isinstance(declaration, Key) and declaration.meaning
            # the unit the results files give the swept key is the one the kind declares
            assert SWEEPABLE[f"loading.{key}"] == declaration.unit
            if name in KINDS.builtins:  # the manual describes it with the declared unit
                assert BY_NAME[("loading", key)].unit == declaration.unit
            if declaration.default is not None:  # a default the parser's bounds accept
                assert Limit.of(declaration).holds(declaration.default), key
            if declaration.maximum is not None:  # the reason printed beyond it
                assert declaration.why, key

    def test_every_key_is_declared_and_described_in_the_reference(self, name):
        """Each field of its section (but ``kind``) declares a unit and a meaning (a number's
        Key; a list's meaning and what holds without it), and the study-file reference
        derived from the registered kinds gives it a row: its type, unit and default, its
        meaning for this kind, and this kind among those that read it."""
        kind = KINDS[name]
        rows = {key.name: key for key in loading_keys()}
        assert f'`"{name}"`: {kind.summary}' in rows["kind"].meaning
        readers = {key: [k for k in KINDS.values() if key in k.keys] for key in rows}
        for field in dataclasses.fields(kind.config):
            if field.name == "kind":
                continue
            declared = field.metadata.get("key")
            if declared is None:  # not a number: a list, filled in by the kind's parser
                meaning = field.metadata.get("meaning")
                assert meaning and field.metadata.get("absent"), field.name
            else:
                assert isinstance(declared, Key) and declared.unit and declared.meaning
                meaning = declared.meaning
            row = rows[field.name]
            assert row.type and row.unit and row.default, field.name
            assert row.unit == (declared.unit if declared else "–"), field.name
            assert meaning in row.meaning, field.name
            if len(readers[field.name]) < len(KINDS):  # the default names the kinds
                assert name in row.default, field.name
            if name in KINDS.builtins:  # the manual's table has the row
                assert ("loading", field.name) in BY_NAME, field.name

    def test_its_datasets_are_described_in_the_schema_tables(self, name):
        kind = KINDS[name]
        assert kind.history and all(
            isinstance(spec, DatasetSpec) for table in kind.history for spec in table.values()
        )
        for table in kind.history:
            for key in table:
                assert kind.history_spec(key).units
        for record in kind.records:
            assert kind.record_spec(record, 10).description.endswith("cycle 10")

    def test_its_report_and_figures_name_functions_of_the_analysis_layer(self, name):
        kind = KINDS[name]
        for reference in (kind.report, kind.figures):
            assert reference.startswith("engine.analysis.") or "." in reference
            assert callable(_function(reference))


def _slipping_increment(points: int = 4):
    """A sliding increment on ``points`` elements, and the state before it: pressure p
    (MPa), slips Δs (mm) in several directions, tractions −0.3 p Δs/|Δs| opposing the slip
    at the increment and the one before (positive frictional work everywhere)."""
    angle = np.linspace(0.0, 2.0 * np.pi, points, endpoint=False).reshape(points, 1)
    pressure = np.linspace(100.0, 400.0, points).reshape(points, 1)
    slip_x, slip_y = 1e-3 * np.cos(angle), 1e-3 * np.sin(angle)
    traction_x, traction_y = -0.3 * pressure * np.cos(angle), -0.3 * pressure * np.sin(angle)
    state = {"pressure": pressure, "traction_x": traction_x, "traction_y": traction_y}
    result = SimpleNamespace(**state, slip_x=slip_x, slip_y=slip_y)
    return result, SimpleNamespace(**state)


def _coefficients(cls: type[WearModel]) -> dict[str, float]:
    return {name: key.example for name, key in cls.coefficients.items()}


@pytest.mark.parametrize("name", list(WEAR_LAWS))
class TestWearLaw:
    """The protocol of :class:`engine.solvers.wear.WearModel` (engine/solvers/wear.py)."""

    def test_is_registered_under_its_name_and_declares_its_coefficients(self, name):
        cls = WEAR_LAWS[name]
        assert issubclass(cls, WearModel) and cls.name == name and cls.description
        assert cls.id_prefix.isalpha() and cls.coefficients
        assert cls.increment is not WearModel.increment
        assert cls.from_coefficients is not WearModel.from_coefficients
        for coefficient, key in cls.coefficients.items():
            assert isinstance(key, Key) and key.unit and key.meaning, coefficient
            assert key.minimum is not None and key.example is not None, coefficient
            assert key.check(coefficient, key.example) == key.example
            assert unit_of(coefficient) == key.unit  # summary columns, case attributes
            assert coefficient in case_parameters()
            assert summary_columns()[coefficient][0] == key.unit

    def test_wears_where_it_slips_and_nowhere_else(self, name):
        """Δω ≥ 0, finite, with the grid's shape where the surface slips against friction;
        0 without slip; the law scaled by 2 wears twice as deep (two bodies), when it offers
        scaling."""
        cls = WEAR_LAWS[name]
        law = cls.from_coefficients(_coefficients(cls), beta=math.radians(30.0))
        result, previous = _slipping_increment()
        depth = law.increment(result, previous)
        assert depth.shape == result.pressure.shape
        assert np.all(np.isfinite(depth)) and np.all(depth >= 0.0) and np.any(depth > 0.0)
        still = SimpleNamespace(**{**vars(result), "slip_x": 0.0 * result.slip_x,
                                   "slip_y": 0.0 * result.slip_y})  # fmt: skip
        assert np.all(law.increment(still, previous) == 0.0)
        try:
            doubled = law.scaled(2.0)
        except NotImplementedError:
            return
        # twice the coefficients: the same products times 2, to a few roundings
        np.testing.assert_allclose(doubled.increment(result, previous), 2.0 * depth, rtol=1e-14)

    def test_a_study_file_sweeps_its_coefficients_and_stores_a_readable_study(self, name):
        """``[wear] law = name`` with its coefficients in ``[sweep]`` parses into one case per
        combination, named by the law's id prefix, each storing its coefficients; the
        resolved study (what a results file stores) parses again to the same plan; the
        manual's key table describes every coefficient with its unit."""
        cls = WEAR_LAWS[name]
        sweep = {"mu1": [0.3]} | {c: [value] for c, value in _coefficients(cls).items()}
        text = study_toml(name, f"{name}.h5", wear={"law": name}, sweep=sweep)
        config = parse_study(text)
        plan = make_plan(config)
        assert len(plan) == 1 and plan.case_ids[0].split("_")[1].startswith(cls.id_prefix)
        parameters = plan.cases[0].parameters()
        assert all(parameters[c] == v for c, v in _coefficients(cls).items())
        again = parse_study(dump_toml(config.resolved()))
        assert make_plan(again).case_ids == plan.case_ids
        described = {key.name: key for key in wear_keys()[1]}
        assert all(described[c].unit == key.unit for c, key in cls.coefficients.items())
        assert f'`"{name}"`' in wear_keys()[0].meaning
