"""Loading kinds as plug-ins: one protocol, one module each, one table (engine.study.kinds);
the energy wear law's α as a case parameter of its own."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from engine.study.config import parse_study
from engine.study.examples import study_toml
from engine.study.kinds import KINDS
from engine.study.layout import case_layout
from engine.study.plan import case_id_for, make_plan
from engine.study.resources import largest_case

KINDS_DIR = Path(__file__).resolve().parents[1] / "engine" / "study" / "kinds"


def test_no_kind_module_imports_another_kind_module():
    """What two kinds share lives in kinds/base.py or study/outcome.py (function-local
    imports counted)."""
    modules = {path.stem for path in KINDS_DIR.glob("*.py")} - {"__init__", "base"}
    for path in KINDS_DIR.glob("*.py"):
        if path.stem in ("__init__", "base"):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                names = [node.module or ""] + [alias.name for alias in node.names]
                others = {part for name in names for part in name.split(".")} & modules
                assert others <= {path.stem}, f"{path.name} imports {others - {path.stem}}"


def test_the_case_runner_does_not_branch_on_the_kind():
    source = (KINDS_DIR.parent / "case.py").read_text()
    for word in ('"static"', '"cyclic"', '"fretting"', "is_fretting", "is_cyclic"):
        assert word not in source


@pytest.mark.parametrize(
    ("loading", "increments"),
    [
        ({"kind": "static", "load": 750.0, "steps": 3}, 0),
        ({"kind": "cyclic", "load": 750.0, "steps": 3, "cycles": 10, "record": None}, 6),
        (
            {
                "kind": "fretting",
                "load": 750.0,
                "steps": 3,
                "cycles": 10,
                "record": None,
                "amplitude": 1e-3,
            },
            12,
        ),
    ],
)
def test_the_kind_gives_the_memory_estimate_and_the_recorded_datasets(loading, increments):
    """Increments per simulated cycle: static none, cyclic 2·steps (loading, unloading),
    fretting 4·steps (four quarter cycles); a fretting cycle's loop has 4·steps + 1 rows."""
    text = study_toml("k", "k.h5", loading=loading, sweep={"mu1": [0.1], "wear1": [1e-7]})
    config = parse_study(text, source="k.toml")
    assert largest_case(config)[2] == increments
    layout = case_layout(config)
    loops = {path: shape for path, shape in layout.items() if path.endswith("/loop")}
    if loading["kind"] == "fretting":
        assert loops == {"fields/cycle_0000010/loop": loops["fields/cycle_0000010/loop"]}
        assert loops["fields/cycle_0000010/loop"].shape == (4 * 3 + 1, 4)
    else:
        assert not loops
    cycles = [path for path in layout if path.startswith("fields/cycle_")]
    assert bool(cycles) == KINDS[loading["kind"]].has_cycles


def test_energy_law_alpha_is_its_own_case_parameter_and_archard_ids_are_unchanged():
    energy = {"law": "energy"}
    text = study_toml(
        "e",
        "e.h5",
        loading={"kind": "cyclic", "load": 750.0, "steps": 2, "cycles": 10, "record": None},
        wear=energy,
        sweep={"mu1": [0.1, 0.2], "alpha": [1e-6, 2e-6]},
    )
    plan = make_plan(parse_study(text, source="e.toml"))
    assert [case.case_id for case in plan] == [
        "mu0.1_a1e-06_b0",
        "mu0.1_a2e-06_b0",
        "mu0.2_a1e-06_b0",
        "mu0.2_a2e-06_b0",
    ]
    for case in plan:
        assert case.coefficients["alpha"] in (1e-6, 2e-6) and list(case.coefficients) == ["alpha"]
        parameters = case.parameters()
        assert (parameters["wear1"], parameters["wear2"]) == (0.0, 0.0)  # Archard's columns: 0
        assert parameters["alpha"] == case.coefficients["alpha"]
        assert list(parameters)[-1] == "alpha"  # after beta: not one of the fixed columns
    # the Archard ids of existing studies are unchanged
    assert case_id_for(0.1, 0.1, {"wear1": 1.33e-7, "wear2": 1.33e-7}, 0.0) == "mu0.1_w1.33e-07_b0"
    assert case_id_for(0.1, 0.1, {"alpha": 1e-6}, 0.0, law="energy") == "mu0.1_a1e-06_b0"


def test_case_runners_and_the_layout_take_dataset_paths_from_the_schema():
    """No dataset path assembled from f-strings in the study layer's case code: every path
    of a case group comes from engine.schema.case_group_path (its sections listed there)."""
    from engine.schema import CASE_SECTIONS

    study = KINDS_DIR.parent
    files = [*KINDS_DIR.glob("*.py"), study / "outcome.py", study / "layout.py"]
    files += [study / "case.py", study / "fatigue.py"]
    for path in files:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.JoinedStr) and node.values:
                first = node.values[0]
                text = first.value if isinstance(first, ast.Constant) else ""
                assert not text.startswith(tuple(f"{s}/" for s in CASE_SECTIONS)), (
                    f"{path.name}:{node.lineno}: a dataset path from an f-string"
                )
