"""Study file validation: every error names the file, the key and the value."""

from __future__ import annotations

from pathlib import Path

import pytest

from engine.solvers import defaults
from engine.solvers.contact import ContactSolver
from engine.solvers.cyclic import CyclicSettings
from engine.study.config import StudyConfigError, load_study, parse_study, same_fingerprint
from engine.study.config.keys import STUDY_KEYS
from engine.study.examples import CYLINDER_ON_STEEL, SPHERE_ON_STEEL, study_toml

# The study every test here starts from (text manipulations below rely on its lines).
VALID = study_toml(
    "t",
    "out/t.h5",
    mesh={"n": 32},
    loading={"kind": "cyclic", "load": 750, "steps": 4, "cycles": 100, "record": [10, 100]},
    subsurface={"depth": 1.0, "layers": 8},
    sweep={"mu1": [0.1, 0.4], "wear1": [1.33e-7], "beta": [0, 45]},
)


def with_line(section: str, line: str, text: str = VALID) -> str:
    """Insert ``line`` into ``[section]`` (a later duplicate key would be a TOML error)."""
    return text.replace(f"[{section}]\n", f"[{section}]\n{line}\n", 1)


def replace_key(section_key: str, value: str, text: str = VALID) -> str:
    lines = text.splitlines()
    section, key = section_key.split(".")
    inside = False
    for i, line in enumerate(lines):
        if line.startswith("["):
            inside = line == f"[{section}]"
        elif inside and line.split("=")[0].strip() == key:
            lines[i] = f"{key} = {value}"
            return "\n".join(lines)
    raise KeyError(section_key)


def test_valid_study_resolves_defaults():
    config = parse_study(VALID, source="t.toml")
    assert config.mesh.half_width == pytest.approx(1.5 * 1.8)  # flat punch: 1.5 a0
    assert config.sweep.mu2 is None and config.sweep.wear_lists["wear2"] is None
    assert config.loading.record == (10, 100)
    assert config.is_cyclic
    # the resolved TOML reads back to the same configuration
    again = parse_study(config.to_toml(), source="t.toml")
    assert again.resolved() == config.resolved()
    assert again.fingerprint() == config.fingerprint()


def test_every_solver_default_is_resolved_and_stored():
    """The resolved TOML and the fingerprint name the iteration cap and the
    cycle-jump control that ran (no "None means the solver's default"); the solvers' own
    keyword defaults are the same values."""
    config = parse_study(VALID)
    assert config.solver.maxiter == defaults.MAX_ITERATIONS
    assert config.loading.max_wear_fraction == defaults.MAX_WEAR_FRACTION
    assert config.solver.tol == defaults.CYCLIC_TOLERANCE
    text = config.to_toml()
    assert "maxiter = 20000" in text and "max_wear_fraction = 0.004" in text
    assert '"maxiter": 20000' in config.fingerprint()
    assert (
        CyclicSettings(750.0, 4, 100, record=(100,)).max_wear_fraction == defaults.MAX_WEAR_FRACTION
    )
    keywords = ContactSolver.__init__.__kwdefaults__
    assert keywords["maxiter"] == defaults.MAX_ITERATIONS
    assert keywords["tol"] == defaults.STATIC_TOLERANCE
    static_text = VALID.replace('kind = "cyclic"', 'kind = "static"')
    static = parse_study(static_text.replace("cycles = 100\nrecord = [10, 100]\n", ""))
    # no cycle jumps: the static kind's section has no such key, nor one stored
    assert not hasattr(static.loading, "max_wear_fraction")
    assert "max_wear_fraction" not in static.resolved()["loading"]
    assert static.solver.tol == defaults.STATIC_TOLERANCE


def test_files_written_before_the_defaults_were_resolved_still_resume():
    """A fingerprint without maxiter and max_wear_fraction (earlier versions left the
    solver's defaults out) matches the study that sets today's values, not another one."""
    import json

    config = parse_study(VALID)
    former = json.loads(config.fingerprint())
    del former["solver"]["maxiter"], former["loading"]["max_wear_fraction"]
    assert same_fingerprint(json.dumps(former, sort_keys=True), config.fingerprint())
    other = parse_study(with_line("solver", "maxiter = 500", VALID + "[solver]\n"))
    assert not same_fingerprint(json.dumps(former, sort_keys=True), other.fingerprint())
    assert not same_fingerprint(None, config.fingerprint())


def test_config_is_frozen():
    config = parse_study(VALID)
    with pytest.raises(AttributeError):
        config.loading.load = 1.0


def test_fingerprint_ignores_output_and_sweep_but_not_physics():
    base = parse_study(VALID)
    assert parse_study(replace_key("study.output", '"x.h5"')).fingerprint() == base.fingerprint()
    assert parse_study(replace_key("sweep.mu1", "[0.2]")).fingerprint() == base.fingerprint()
    assert parse_study(replace_key("loading.load", "700")).fingerprint() != base.fingerprint()


@pytest.mark.parametrize(
    "text, key, fragment",
    [
        (replace_key("loading.load", "-750"), "[loading] load = -750", "must be > 0"),
        (replace_key("sweep.mu1", "[0.1, -0.2]"), "[sweep] mu1", "must be >= 0"),
        (replace_key("material.nu_A", "0.5"), "[material] nu_A = 0.5", "(-1, 0.5)"),
        (replace_key("material.nu_B", "0.7"), "[material] nu_B = 0.7", "(-1, 0.5)"),
        (replace_key("loading.record", "[10, 200]"), "[loading] record", "outside 0..cycles"),
        (replace_key("loading.kind", '"quasi"'), "[loading] kind", "static"),
        (replace_key("mesh.n", "32.5"), "[mesh] n = 32.5", "integer"),
        (replace_key("mesh.n", "4"), "[mesh] n = 4", ">= 8"),
        (replace_key("punch.radius", '"big"'), "[punch] radius", "must be a number"),
        (replace_key("loading.steps", "true"), "[loading] steps = True", "integer"),
        (replace_key("sweep.wear1", "[]"), "[sweep] wear1", "at least one"),
        (replace_key("sweep.beta", "[0, 0]"), "[sweep] beta", "must not repeat"),
        (replace_key("subsurface.layers", "1"), "[subsurface] layers", ">= 2"),
        (with_line("mesh", "half_width = 1.0"), "[mesh] half_width = 1.0", ">= 1.8"),
        (with_line("sweep", 'wear2 = "double"'), "[sweep] wear2", "proportional"),
        (with_line("loading", "colour = 3"), "[loading] colour = 3", "unknown key"),
        (VALID + "\n[extras]\nx = 1\n", "[extras]", "unknown section"),
        (VALID.replace("[punch]\nradius = 1.8\n", ""), "[punch]", "required section"),
        (VALID.replace("load = 750\n", ""), "[loading] load", "required key is missing"),
        (VALID.replace('output = "out/t.h5"', 'output = "out/t.txt"'), "[study] output", ".h5"),
        (VALID + "\n[sweep]\nmu1 = 1\n", "[sweep]", "malformed TOML"),
        (VALID.replace("E_A = 200000.0", "E_A = "), "[material] E_A", "malformed TOML"),
        (VALID.replace("[mesh]\n", "[mesh]\nn = 4\n"), "[mesh] n", "given twice"),
    ],
)
def test_bad_input_names_file_key_and_value(text, key, fragment):
    with pytest.raises(StudyConfigError) as info:
        parse_study(text, source="bad.toml")
    message = str(info.value)
    assert message.startswith("bad.toml: ")
    assert key in message
    assert fragment in message


def test_static_rejects_cyclic_keys_and_defaults_wear():
    static = VALID.replace('kind = "cyclic"', 'kind = "static"')
    with pytest.raises(StudyConfigError, match=r"\[loading\] cycles = 100: unknown key"):
        parse_study(static)
    static = static.replace("cycles = 100\n", "").replace("record = [10, 100]\n", "")
    config = parse_study(static.replace("wear1 = [1.33e-07]\n", ""))
    assert config.sweep.wear_lists["wear1"] == (0.0,)
    assert not hasattr(config.loading, "cycles")  # a static section has no cycles


def test_proportional_wear_needs_positive_friction():
    text = with_line("sweep", 'wear2 = "proportional"', replace_key("sweep.mu1", "[0.0, 0.1]"))
    with pytest.raises(StudyConfigError, match="mu1 > 0"):
        parse_study(text)


def test_load_study_reports_missing_file(tmp_path: Path):
    with pytest.raises(StudyConfigError, match="nope.toml: no such study file"):
        load_study(tmp_path / "nope.toml")


@pytest.mark.parametrize("path", sorted(Path(__file__).parents[1].glob("studies/*.toml")))
def test_bundled_studies_are_valid(path: Path):
    config = load_study(path)
    assert config.study.name
    assert path.read_text().startswith("#"), "studies start with a comment header"


# ------------------------------------------------------------------ every numeric key bounded
# The sections a key needs to be read at all (a fretting signal, a line contact, a search).
_SPHERE_FRETTING = {**SPHERE_ON_STEEL, "loading": {"kind": "fretting", "amplitude": 0.001}}
_LINE_FRETTING = {**CYLINDER_ON_STEEL, "loading": {"kind": "fretting", "amplitude": 0.001}}
_SEARCH = {
    "search": {
        "parameter": "loading.amplitude",
        "low": 1e-4,
        "high": 1e-2,
        "column": "slip_regime",
        "target": "gross",
        "rtol": 0.05,
    },
    "loading": {"amplitude": None},
}
_FATIGUE = {
    "fatigue": {
        "criteria": ["crossland", "dang_van", "swt", "fatemi_socie"],
        "sigma_d": 300.0, "tau_d": 200.0, "sigma_f": 1000.0, "b": -0.09, "eps_f": 0.6,
        "c": -0.6, "tau_f": 600.0, "gamma_f": 0.9, "b0": -0.09, "c0": -0.6, "k": 0.6,
        "sigma_y": 800.0, "method": "point", "length": 0.02,
    }
}  # fmt: skip
DATA = Path(__file__).parent / "data"
# The surfaces below (cut-offs of 0.5 mm, a 5 mm map) fit a 16² mesh of half-width 1.89 mm.
_SURFACE_MESH = {"mesh": {"half_width": 1.89}}
_CONTEXT = {
    "punch.edge_radius": [{"punch": {"shape": "rounded", "edge_radius": 0.1}}],
    "mesh.reference_distance": [_LINE_FRETTING],
    "loading.amplitude": [_SPHERE_FRETTING],
    "loading.force_amplitude": [
        SPHERE_ON_STEEL,
        {"loading": {"kind": "fretting", "force_amplitude": 10.0}},
    ],
    "loading.direction": [_SPHERE_FRETTING],
    "loading.bulk_stress_max": [_LINE_FRETTING],
    "loading.bulk_stress_min": [_LINE_FRETTING],
    "wear.pad_coefficient": [
        _LINE_FRETTING,
        {"punch": {"shape": "pad", "radius": 0.5, "edge_radius": 2.0}, "mesh": {"half_width": 1}},
    ],
    "sweep.alpha": [{"wear": {"law": "energy"}, "sweep": {"wear1": None, "alpha": [1e-5]}}],
    **{
        f"surface.{name}": [_SURFACE_MESH, {"surface": {"kind": "self_affine", "long_cutoff": 1.0,
                                                        "short_cutoff": 0.5, "rms_height": 1e-3}}]
        for name in ("seed", "hurst", "long_cutoff", "short_cutoff", "rms_height")
    },
    "surface.rms_slope": [_SURFACE_MESH, {"surface": {"kind": "self_affine", "long_cutoff": 1.0,
                                                      "short_cutoff": 0.5, "rms_slope": 0.1}}],
    "surface.pixel_size": [_SURFACE_MESH, {"surface": {"kind": "file", "pixel_size": 0.5,
                                                       "path": str(DATA / "flat_map.txt")}}],
}  # fmt: skip
# A calibration: a force-controlled line fretting search of Crossland's risk over two tests.
_CALIBRATION = [
    {**CYLINDER_ON_STEEL, "sweep": {"mu1": [0.5], "wear1": [0.0]},
     "loading": {"kind": "fretting", "load": 185.0},
     "fatigue": {"criteria": ["crossland"], "sigma_d": 300.0, "tau_d": 200.0}},
    {"search": {"parameter": "loading.force_amplitude", "relative_to": "mu_load", "low": 0.2,
                "high": 0.95, "column": "crossland_risk_critical", "target": 1.0,
                "rtol": 2e-3},
     "calibrate": {"tests": str(DATA / "calibration_tests.csv"), "id": "test",
                   "measured": "Q"}},
]  # fmt: skip
_CONTEXT |= {
    f"calibrate.{name}": _CALIBRATION for name in ("fit_rtol", "max_evaluations", "low", "high")
}
_NUMERIC = sorted(
    f"{key.section}.{key.name}"
    for key in STUDY_KEYS
    if key.type in ("number", "integer", "list of numbers", "list of numbers or text")
)


@pytest.mark.parametrize("key", _NUMERIC)
@pytest.mark.parametrize("value", [1e300, -1e300, 10**15])
def test_every_numeric_key_is_bounded_and_the_refusal_names_it(key, value):
    """No number of the study file is accepted at any size: 1e300, -1e300 and 10^15 are
    refused (exit 2 from the command line) by an error that names that key, not a key
    computed from it (a radius of 1e300 once overflowed, a half-width of 1e300 blamed n)."""
    section, name = key.split(".")
    layers = [{"sweep": {"wear1": [1e-7]}}, *_CONTEXT.get(key, [])]
    if section == "search":
        layers += [_SPHERE_FRETTING, _SEARCH]
    if section == "fatigue":  # the criteria that read every constant, on a fretting case
        layers += [_SPHERE_FRETTING, _FATIGUE]
    parse_study(study_toml("b", "b.h5", *layers), source="b.toml")  # the context is valid
    given = [value] if section == "sweep" else value
    with pytest.raises(StudyConfigError) as info:
        parse_study(study_toml("b", "b.h5", *layers, {section: {name: given}}), source="b.toml")
    if key in ("search.low", "search.high") and value * (1 if name == "low" else -1) > 0:
        # an end beyond the other one: the inverted bracket is named with both its ends
        assert info.value.key in ("search.low", "search.high") and repr(value) in str(info.value)
    else:
        assert info.value.key == key, str(info.value)


@pytest.mark.parametrize(
    ("punch", "load", "accepted"),
    [
        # a pad of flat half-width 0.05 mm at 185 N/mm: p0 = P/(2 a0) ≈ 1.4 GPa ≈ 0.013 E*
        ({"shape": "pad", "radius": 0.05, "edge_radius": 3.0}, 185.0, True),
        # a cylinder R = 6 mm at 185 N/mm: Hertz p0 = P/(2a) ≈ 0.8 GPa ≈ 0.007 E*
        ({"shape": "cylinder", "radius": 6.0}, 185.0, True),
        # a sphere R = 10 mm at 20 N: Hertz p0 = P/(π a²) ≈ 0.82 GPa ≈ 0.007 E*
        ({"shape": "sphere", "radius": 10.0}, 20.0, True),
        # a flat punch a = 0.5 mm at 1e5 N: P/(π a²) ≈ 127 GPa > 0.1 E*
        ({"shape": "flat", "radius": 0.5}, 1e5, False),
    ],
)
def test_the_load_is_judged_by_the_mean_pressure_over_the_profiles_own_contact(
    punch, load, accepted
):
    """p0/E* ≤ 0.1 with p0 the mean pressure over the profile's nominal contact (P/(π a0²),
    or P/(2 a0) per unit length for a line contact), not P/(π radius²) for every shape (which
    refused a valid pad at 185 N/mm as 0.21 E*)."""
    text = study_toml(
        "p", "p.h5", SPHERE_ON_STEEL, {"punch": punch, "mesh": {"n": 64, "half_width": 1.0}},
        {"loading": {"kind": "static", "load": load}},
    )  # fmt: skip
    if accepted:
        parse_study(text, source="p.toml")
        return
    with pytest.raises(StudyConfigError) as info:
        parse_study(text, source="p.toml")
    assert info.value.key == "loading.load" and "P/(π a0²)" in str(info.value)
