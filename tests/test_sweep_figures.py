"""`python -m engine plot` for a study that sweeps the load, and the σ_VM figure's promises.

One static study on a 16 × 16 mesh, μ ∈ {0, 0.4} × P ∈ {300, 714} N (four cases, a few
seconds on one rank), computed with ``python -m engine`` (the real entry point). Checked on
the figure objects: one line per μ against the load with the summary's numbers and units;
the per-case figures of ``--case``; in the σ_VM figure the colour scale contains every
titled peak, the ★ sits at the summary's own peak location (signed x, not mirrored), and the
black σ_VM/p0 = 1 line and both markers are named in the legend.
"""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
import pytest

from engine import load_summary
from engine.analysis import figures
from engine.analysis.results import open_results
from engine.analysis.sweep_figures import sweep_figure
from engine.study.examples import study_toml
from tests.test_figures import _engine

LOADS = [300.0, 714.0]
STUDY = study_toml(
    "load_sweep_static",
    "sweep.h5",
    {"subsurface": {"layers": 6}},
    loading={"kind": "static", "load": None},
    sweep={"mu1": [0.0, 0.4], "loading.load": LOADS},
)


CASES = ["mu0_w0_b0_load300", "mu0_w0_b0_load714", "mu0.4_w0_b0_load300", "mu0.4_w0_b0_load714"]


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    (folder / "study.toml").write_text(STUDY)
    run = _engine("study.toml", "--no-progress-bar", cwd=folder)
    assert run.returncode == 0, run.stdout + run.stderr
    return folder / "sweep.h5"


def test_plot_draws_the_sweep_figure_and_says_each_file(results):
    """The command no longer refuses a load sweep: a progress line per figure, and the hint
    for the per-case figures."""
    run = _engine("plot", str(results), "--out", "figures", cwd=results.parent)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].startswith("plot: load_sweep_static, 4 completed cases -> figures/")
    assert lines[1] == "plot: [1] figures/sweep_loading.load.png"
    assert lines[-1].endswith(f"plot {results} --case {CASES[0]}` (or another case_id)")
    assert sorted(p.name for p in (results.parent / "figures").iterdir()) == [
        "sweep_loading.load.png"
    ]


def test_sweep_figure_has_one_line_per_friction_with_the_summary_values(results):
    summary = load_summary(results)
    figure = sweep_figure(summary, "loading.load", ["loading.load"], "t")
    axes = {axis.get_ylabel(): axis for axis in figure.axes if axis.get_visible()}
    assert set(axes) >= {
        "approach g_n (µm)",
        "σ_VM max, x–z plane (MPa)",
        "σ_VM max below the surface layer (MPa)",
        "its depth z (mm)",
        "stick fraction at peak load",
    }
    axis = axes["approach g_n (µm)"]
    assert axis.get_xlabel() == "normal load P (N)"  # the schema's name, never the dotted key
    lines = axis.get_lines()
    assert [line.get_label() for line in lines] == ["mu1 = 0, mu2 = 0", "mu1 = 0.4, mu2 = 0.4"]
    for line, mu in zip(lines, (0.0, 0.4), strict=True):
        rows = summary[summary.mu1 == mu].sort_values("loading.load")
        np.testing.assert_array_equal(line.get_xdata(), LOADS)
        np.testing.assert_allclose(line.get_ydata(), rows["approach"] * 1e3, rtol=1e-15)
    assert [t.get_text() for t in figure.legends[0].get_texts()] == [
        "mu1 = 0, mu2 = 0",
        "mu1 = 0.4, mu2 = 0.4",
    ]
    plt.close(figure)


def test_case_option_draws_the_field_figures_with_the_cases_own_load(results, tmp_path, small_text):
    """One case's figures: its own load, and nothing cut by the edge of a one-panel figure
    (its title and the legend row once reached beyond it)."""
    assert figures.main([str(results), "--case", "nope", "--out", str(tmp_path)]) == 2
    study = open_results(results).for_case(CASES[2])
    assert study.load == 300.0 and [c.case_id for c in study.completed] == [CASES[2]]
    out = tmp_path / "one"
    assert (
        figures.main([str(results), "--case", study.completed[0].case_id, "--out", str(out)]) == 0
    )
    assert {p.name for p in out.iterdir()} == {
        "stiffness_ratio.png",
        "traction_profiles.png",
        "von_mises_final.png",
    }
    assert not small_text, small_text


PEAK = re.compile(r"([★○]) .*? ([\d.]+) at \(([+-][\d.]+), ([\d.]+)\)")


def test_von_mises_figure_scale_markers_and_legend(results):
    """The colour levels reach above every titled peak; each ★/○ is drawn where its title
    says, the ★ at the summary's own vm_max location (signed x/a0); the black line and both
    markers are named in the legend."""
    full = open_results(results)
    for case_id in (CASES[1], CASES[2]):
        study = full.for_case(case_id)
        case = study.completed[0]
        figure = figures._von_mises_figure(study, "final", "t", analytic=True)
        top = max(figure.axes[-1].get_ylim()[1], 0.0)  # the colour bar's axis: its top level
        marked = 0
        for axis in figure.axes[:-1]:
            markers = {line.get_marker(): line for line in axis.get_lines()}
            for symbol, value, x, z in PEAK.findall(axis.get_title()):
                line = markers["*" if symbol == "★" else "o"]
                assert float(value) <= top  # inside the colour scale
                assert line.get_xdata()[0] == pytest.approx(float(x), abs=0.006)
                assert line.get_ydata()[0] == pytest.approx(float(z), abs=6e-4)
                marked += 1
            if "*" in markers:
                a, p0 = study.radius, study.p0
                assert markers["*"].get_xdata()[0] == pytest.approx(case.summary["vm_max_x"] / a)
                assert markers["*"].get_ydata()[0] == pytest.approx(case.summary["vm_max_z"] / a)
                assert top >= case.summary["vm_max"] / p0
        assert marked == 2
        legend = [text.get_text() for text in figure.legends[0].get_texts()]
        assert legend == ["σ_VM/p0 = 1", "★ peak over the plane", "○ below the surface layer"]
        contours = [c for c in figure.axes[1].collections if hasattr(c, "levels")]
        assert [list(c.levels) for c in contours if not c.filled] == [[1.0]]
        plt.close(figure)
