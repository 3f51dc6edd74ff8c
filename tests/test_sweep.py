"""Any scalar as a sweep axis: dotted keys, zip groups, ids, validation, order,
per-case configuration, layout and output. Exact checks (no tolerances): these are
bookkeeping, not numerics."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from engine.output.summary import column_unit, load_summary
from engine.study.case import COMPLETED, CaseRunner
from engine.study.config import StudyConfigError, load_study, parse_study
from engine.study.examples import study_toml
from engine.study.layout import plan_layout
from engine.study.plan import make_plan

ROOT = Path(__file__).resolve().parents[1]


def study_text(sweep: str, *, mu1=(0.2, 0.4), output="out.h5", **sections) -> str:
    """A cyclic study (16 x 16, 1000 cycles) whose ``[sweep]`` ends with the TOML lines
    ``sweep`` (kept as text: the sweep syntax itself is under test); ``sections`` change the
    others (a key set to None is left out)."""
    base = {"loading": {"kind": "cyclic", "cycles": 1000, "record": None}}
    sweep_base = {"mu1": list(mu1), "wear1": [1.33e-7]}
    text = study_toml("sweep", output, base, {"sweep": sweep_base}, **sections)
    return text + sweep + "\n"


def study(sweep: str, **sections):
    return parse_study(study_text(sweep, **sections), source="s.toml")


def test_product_of_dotted_keys_with_short_stable_ids():
    config = study(
        '"loading.load" = [500.0, 750.0]\n"mesh.n" = [16, 32]',
        mesh={"n": None},
        loading={"load": None},
    )
    plan = make_plan(config)
    assert len(plan) == 2 * 2 * 2
    assert plan.case_ids[0] == "mu0.2_w1.33e-07_b0_load500_n16"
    assert plan.case_ids[-1] == "mu0.4_w1.33e-07_b0_load750_n32"
    # adding a value keeps every other id
    more = study(
        '"loading.load" = [250.0, 500.0, 750.0]\n"mesh.n" = [16, 32]',
        mesh={"n": None},
        loading={"load": None},
    )
    assert set(plan.case_ids) < set(make_plan(more).case_ids)
    case = plan.by_id("mu0.4_w1.33e-07_b0_load750_n32")
    assert case.parameters()["loading.load"] == 750.0 and case.parameters()["mesh.n"] == 32
    case_config = config.for_case(case.settings)
    assert case_config.loading.load == 750.0 and case_config.mesh.n == 32


def test_zip_groups_vary_together_and_unquoted_keys_are_the_same():
    config = study(
        'loading.load = [500.0, 750.0]\nmesh.n = [16, 32]\nzip = [["loading.load", "mesh.n"]]',
        mesh={"n": None},
        loading={"load": None},
    )
    assert make_plan(config).case_ids == (
        "mu0.2_w1.33e-07_b0_load500_n16",
        "mu0.4_w1.33e-07_b0_load500_n16",
        "mu0.2_w1.33e-07_b0_load750_n32",
        "mu0.4_w1.33e-07_b0_load750_n32",
    )


def test_derived_defaults_follow_the_swept_value():
    config = study('"punch.radius" = [1.0, 1.8]', punch={"radius": None})
    configs = [config.for_case(case.settings) for case in make_plan(config)]
    assert sorted({c.mesh.half_width for c in configs}) == pytest.approx([1.5, 2.7])  # 1.5 a0
    assert make_plan(config).shared_mesh() is None


@pytest.mark.parametrize(
    ("sweep", "expected"),
    [
        ('"loading.load" = [500.0, -5.0]', "[sweep] loading.load = -5.0: list position 2 of 2: "
         "must be > 0"),
        ('"mesh.n" = [16, 4]', "[sweep] mesh.n = 4: list position 2 of 2: must be >= 8"),
        ('"mesh.n" = [16, 32.5]', "[sweep] mesh.n = 32.5: list position 2 of 2: must be an "
         "integer"),
        ('"loading.load" = [500.0, "x"]', "[sweep] loading.load = 'x': list position 2 of 2"),
        ('"punch.colour" = [1.0]', "not a sweepable key"),
        ('"loading.load" = []', "must list at least one value"),
        ('"loading.load" = [1.0, 1.0]', "must not repeat"),
        ('"loading.load" = [1.0]\n"mesh.n" = [16, 32]\nzip = [["loading.load", "mesh.n"]]',
         "equal lengths"),
        ('"loading.steps" = [2, 3]', "also set in [loading]"),
        # fine alone, too coarse in combination with the swept radius: names the combination
        ('"punch.radius" = [1.8, 0.1]', "[sweep] punch.radius = 0.1: list position 2 of 2: "
         "invalid (then [mesh] n = 16: fewer than 4 elements"),
    ],
)  # fmt: skip
def test_bad_swept_value_names_key_position_and_value(sweep, expected):
    punch = {"radius": None} if "punch.radius" in sweep else {}
    loading = {"load": None} if "loading.load" in sweep else {}
    mesh = {"n": None} if "mesh.n" in sweep else {"half_width": 1.89}
    with pytest.raises(StudyConfigError) as error:
        make_plan(study(sweep, punch=punch, loading=loading, mesh=mesh))
    assert expected in str(error.value)
    assert str(error.value).startswith("s.toml: ")


def test_bad_value_exits_2_before_anything_is_computed(tmp_path):
    output = tmp_path / "bad.h5"
    path = tmp_path / "bad.toml"
    path.write_text(
        study_text('"loading.load" = [500.0, 750.0, 0.0]', loading={"load": None}, output=output)
    )
    run = subprocess.run(
        [sys.executable, "-m", "engine", str(path)], capture_output=True, text=True, cwd=ROOT
    )
    assert run.returncode == 2
    assert "[sweep] loading.load = 0.0: list position 3 of 3: must be > 0" in run.stderr
    assert not output.exists()


def test_existing_studies_keep_ids_fingerprint_and_resolved_text():
    config = load_study(ROOT / "studies/section_7_2_cyclic.toml")
    assert make_plan(config).case_ids == (
        "mu0.1_w1.33e-07_b0", "mu0.2_w1.33e-07_b0", "mu0.4_w1.33e-07_b0",
    )  # fmt: skip
    assert "shape" not in config.to_toml() and "swept_keys" not in config.fingerprint()
    assert make_plan(config).shared_mesh() == (64, 1.89)


def test_resolved_study_round_trips_and_fingerprint_ignores_values():
    config = study(
        '"loading.load" = [500.0, 750.0]\n"mesh.n" = [16, 32]',
        mesh={"n": None},
        loading={"load": None},
    )
    again = parse_study(config.to_toml(), source="again")
    assert again.fingerprint() == config.fingerprint()
    assert make_plan(again).case_ids == make_plan(config).case_ids
    more = study(
        '"loading.load" = [100.0, 500.0, 750.0]\n"mesh.n" = [16, 32]',
        mesh={"n": None},
        loading={"load": None},
    )
    assert more.fingerprint() == config.fingerprint()  # adding a value resumes
    other = study('"loading.load" = [500.0, 750.0]', loading={"load": None})
    assert other.fingerprint() != config.fingerprint()  # sweeping another key does not


def test_dispatch_order_runs_bigger_meshes_first():
    config = study('"mesh.n" = [16, 64, 32]', mesh={"n": None})
    order = [case.case_id for case in make_plan(config).dispatch_order()]
    assert [case_id.rsplit("_n", 1)[1] for case_id in order] == ["64", "64", "32", "32", "16", "16"]
    assert order[0].startswith("mu0.2")  # then friction as before (low μ first)


def test_per_case_layout_grid_and_summary_columns(tmp_path):
    """mesh.n swept: every case has its own grid and layout; swept keys are columns and
    attributes; the root has no grid (grid_location says where it is)."""
    from engine.cli import main

    output = tmp_path / "sweep.h5"
    path = tmp_path / "sweep.toml"
    path.write_text(
        study_text(
            '"mesh.n" = [16, 24]\n"loading.load" = [500.0, 750.0]',
            mu1=[0.3],
            mesh={"n": None},
            loading={"load": None},
            output=output,
        )
    )
    assert main([str(path), "--no-progress-bar"]) == 0
    config = load_study(path)
    plan = make_plan(config)
    layouts = plan_layout(config, plan)
    summary = load_summary(output)
    assert list(summary["mesh.n"]) == [16, 16, 24, 24]
    assert list(summary["loading.load"]) == [500.0, 750.0, 500.0, 750.0]
    assert list(summary["load"]) == pytest.approx([500.0, 750.0, 500.0, 750.0])
    assert column_unit("loading.load") == "N"
    with h5py.File(output, "r") as file:
        assert "grid" not in file and file.attrs["grid_location"] == "/cases/<case_id>/grid"
        for case in plan:
            group = file["cases"][case.case_id]
            assert group.attrs["status"] == COMPLETED
            assert group.attrs["mesh.n"] == case.parameters()["mesh.n"]
            n = case.parameters()["mesh.n"]
            assert group["grid/x"].shape == (n,) and group["fields/final/pressure"].shape == (n, n)
            for name, spec in layouts[case.case_id].items():
                assert group[name].shape == spec.shape, name
    # the same case run directly gives the same numbers (per-case configuration is used)
    case = plan.by_id("mu0.3_w1.33e-07_b0_n24_load750")
    outcome = CaseRunner(config)(case)
    row = summary.set_index("case_id").loc[case.case_id]
    assert outcome.row["wear_volume"] == row["wear_volume"]
    assert np.isfinite(row["vm_sub_max"])


def test_sweep_report_power_law_and_convergence_verdicts():
    """Exact: a fitted exponent of y = 3 x² is 2 (round-off); verdicts from made-up columns."""
    import pandas as pd

    from engine.analysis.sweep_report import convergence_table, power_law_exponent, sweep_report

    assert power_law_exponent([250.0, 500.0, 1000.0], [3 * 250.0**2, 3 * 500.0**2, 3e6]) == (
        pytest.approx(2.0, abs=1e-12)
    )
    rows = []
    meshes = ((16, 1.0, 1.0), (32, 1.5, 2.0), (64, 1.6, 3.5), (128, 1.62, 6.0))
    for n, converging, growing in meshes:
        rows.append(
            dict(case_id=f"c{n}", mu1=0.2, mu2=0.2, wear1=1e-7, wear2=1e-7, beta=0.0,
                 status="completed", cycles=10, approach=converging, vm_max=growing,
                 p0=7.0, **{"mesh.n": n})
        )  # fmt: skip
    summary = pd.DataFrame(rows)
    lines = {line.split(" |")[0]: line for line in convergence_table(summary, ["mesh.n"])}
    assert lines["| approach (mm)"].endswith("| converging |")
    assert lines["| vm_max (MPa)"].endswith("| not converging |")
    assert lines["| p0 (MPa)"].endswith("| constant |")
    assert "Convergence with the mesh" in sweep_report(summary, ["mesh.n"], "t")


def test_adding_a_swept_value_resumes_and_keeps_completed_cases(tmp_path):
    """Resume: a second run with one more load keeps the completed case (same fingerprint,
    same id) and computes only the new one."""
    from engine.cli import main

    output = tmp_path / "resume.h5"
    path = tmp_path / "resume.toml"

    def write(loads):
        text = study_text(
            f'"loading.load" = {loads}', mu1=[0.4], loading={"load": None}, output=output
        )
        path.write_text(text)

    write("[500.0]")
    assert main([str(path), "--no-progress-bar"]) == 0
    with h5py.File(output, "r") as file:
        first = file["cases/mu0.4_w1.33e-07_b0_load500"].attrs["runtime_s"]
    write("[500.0, 750.0]")
    assert main([str(path), "--no-progress-bar"]) == 0
    summary = load_summary(output)
    assert list(summary["status"]) == ["completed", "completed"]
    with h5py.File(output, "r") as file:
        assert file["cases/mu0.4_w1.33e-07_b0_load500"].attrs["runtime_s"] == first
