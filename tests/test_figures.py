"""`python -m engine plot` and `python -m engine report` on tiny studies written here.

Two studies in the shape of the bundled ones (a cyclic sweep like studies/demo.toml with an
orthotropic case, and a static μ sweep like Section 7.1), on a 16 × 16 mesh with few cycles,
so that the engine runs them on one rank in a few seconds. Each is computed with
``python -m engine`` in a subprocess (the real entry point), then plotted with
``python -m engine plot``. Checks: every figure the module documents is written, is a PNG of
more than a few kB, and is not blank (pixel standard deviation well above zero; a blank
white canvas has 0). The numbers are not checked here (tests/test_cyclic.py, test_contact.py).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib import image

from engine.analysis.figures import MAX_WIDTH_PX, case_styles
from engine.analysis.results import ResultCase
from engine.study.examples import study_toml

REPO = Path(__file__).resolve().parents[1]

COMMON = {"subsurface": {"layers": 6}}  # changes to engine.study.examples.BASE (16 x 16)
CYCLIC = study_toml(
    "tiny_cyclic",
    "tiny_cyclic.h5",
    COMMON,
    loading={"kind": "cyclic", "record": [20, 200]},
    # an isotropic and an orthotropic case
    sweep={"mu1": [0.1], "mu2": [0.1, 0.4], "wear1": [1.33e-7], "beta": [30.0]},
)
STATIC = study_toml(
    "tiny_static",
    "tiny_static.h5",
    COMMON,
    loading={"kind": "static", "load": 714.0},
    sweep={"mu1": [0.0, 0.4]},
)

CYCLIC_FIGURES = [
    "wear_history.png",
    "pressure_profiles.png",
    "surface_maps_N200.png",
    "von_mises_N20.png",
    "von_mises_N200.png",
]
STATIC_FIGURES = [
    "pressure_frictionless.png",
    "stiffness_ratio.png",
    "traction_profiles.png",
    "von_mises_final.png",
]
MIN_BYTES = 5_000  # a titled, labelled matplotlib PNG is > 20 kB; an empty canvas ~ 2-5 kB
MIN_PIXEL_STD = 0.02  # RGB in [0, 1]; blank = 0, a line plot on white ~ 0.1, a map ~ 0.3


def _engine(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run(
        [sys.executable, "-m", "engine", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.fixture(scope="module", params=["cyclic", "static"])
def study_results(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp(request.param)
    text = CYCLIC if request.param == "cyclic" else STATIC
    (folder / "study.toml").write_text(text)
    run = _engine("study.toml", "--no-progress-bar", cwd=folder)
    assert run.returncode == 0, run.stdout + run.stderr
    name = "tiny_cyclic" if request.param == "cyclic" else "tiny_static"
    expected = CYCLIC_FIGURES if request.param == "cyclic" else STATIC_FIGURES
    return folder, folder / f"{name}.h5", expected


def test_plot_writes_every_figure_non_blank(study_results, small_text):
    """In process (`python -m engine plot` calls the same main): every figure is written,
    non-blank, at most MAX_WIDTH_PX wide, and has no text below MIN_FONT_SIZE (checked on
    each figure just before it is closed, after it was drawn for saving)."""
    from engine.analysis import figures

    folder, results, expected = study_results
    assert figures.main([str(results), "--out", str(folder / "figures")]) == 0
    assert not small_text, small_text
    written = sorted(path.name for path in (folder / "figures").glob("*.png"))
    assert written == sorted(expected)
    for name in expected:
        path = folder / "figures" / name
        assert path.stat().st_size > MIN_BYTES, name
        pixels = image.imread(path)[..., :3]
        assert pixels.ndim == 3 and min(pixels.shape[:2]) > 200, name
        assert pixels.shape[1] <= MAX_WIDTH_PX, name  # readable at 100 % without scrolling
        assert float(np.std(pixels)) > MIN_PIXEL_STD, name


def test_report_prints_a_row_per_case(study_results):
    folder, results, _ = study_results
    run = _engine("report", str(results), cwd=folder)
    assert run.returncode == 0, run.stdout + run.stderr
    table_rows = [line for line in run.stdout.splitlines() if line.startswith("| μ")]
    is_cyclic = "cyclic" in results.name
    assert len(table_rows) == (2 * 2 if is_cyclic else 2)  # cases × recorded cycles
    assert "Measured:" in run.stdout
    assert "nan" not in "\n".join(table_rows)


def test_plot_missing_file_is_an_error(tmp_path):
    run = _engine("plot", str(tmp_path / "missing.h5"), cwd=tmp_path)
    assert run.returncode == 2
    assert "no such file" in run.stderr


def test_cases_differing_only_in_beta_share_a_colour_but_not_a_line_style():
    # The demo's shape: μ = 0.1, 0.4 at β = 0°, 90°; isotropic, so the β = 0° and 90° curves
    # coincide and must differ in style to stay visible.
    cases = [
        ResultCase.from_values(
            f"c{mu}-{beta}",
            {"mu1": mu, "mu2": mu, "wear1": 1.33e-7, "wear2": 1.33e-7, "beta": beta},
        )
        for mu in (0.1, 0.4)
        for beta in (0.0, 90.0)
    ]
    styles = case_styles(cases)
    for mu in (0.1, 0.4):
        at_0, at_90 = styles[f"c{mu}-0.0"], styles[f"c{mu}-90.0"]
        assert at_0["color"] == at_90["color"]
        assert (at_0["ls"], at_0["marker"], at_0["lw"]) != (
            at_90["ls"],
            at_90["marker"],
            at_90["lw"],
        )
    assert styles["c0.1-0.0"]["color"] != styles["c0.4-0.0"]["color"]
    # a study where only β varies (Section 7.3): colours differ too
    orthotropic = [
        ResultCase.from_values(
            f"o{b}", {"mu1": 0.1, "mu2": 0.4, "wear1": 1e-7, "wear2": 4e-7, "beta": b}
        )
        for b in (0, 45, 90)
    ]
    assert len({style["color"] for style in case_styles(orthotropic).values()}) == 3
