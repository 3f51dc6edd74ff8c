"""Figures of a study, as PNG files: ``python -m engine plot RESULTS.h5 [--out DIR]``.

Matplotlib with the Agg backend (no display needed); no MPI. Which figures, and the paper's
figure each corresponds to (Juliá & Rodríguez-Tembleque 2023, Section 7):

static study (Section 7.1)
    ``pressure_frictionless.png``     p/p0 along x at y ≈ 0 vs Sneddon, Eq. (17)    Fig. 3a
    ``stiffness_ratio.png``           k_μ/k_0 vs μ with Mossakovskii's limit, Eq. (20) Fig. 3b
    ``traction_profiles.png``         p/p0 and q_x/p0 along x per μ                 Fig. 4
    ``von_mises_final.png``           σ_VM/p0 in the x–z plane, Appendix A panel    Fig. 5
cyclic study (Sections 7.2, 7.3)
    ``wear_history.png``              max wear depth and wear volume vs N (log)     Figs. 6a–b, 9
    ``pressure_profiles.png``         p/p0 along x (and y) at each recorded N       Fig. 6c–e
    ``surface_maps_N<N>.png``         wear depth and p/p0 in the x–y plane, last N   Figs. 7, 10
    ``von_mises_N<N>.png``            σ_VM/p0 in the x–z plane at each recorded N   Figs. 8, 11
    ``peak_regime_*.png``             peak region vs wear severity (studies sweeping
                                      wear; :mod:`engine.analysis.regime`)
fretting study (:mod:`engine.analysis.fretting_figures`)
    ``fretting_map.png``, ``fretting_loops.png``, ``wear_energy.png``

Conventions: lengths normalised by a0 (punch radius), stresses by p0 = P/(π a0²) (Eq. 19),
z into the half-space (drawn downwards), wear depth in µm. In the σ_VM maps the black line is
σ_VM/p0 = 1; ★ marks the peak over the whole plane (the surface layer carries the grid-
dependent edge singularity of the flat punch) and ○ the peak below the surface layer, each
at its own signed position (x/a0, z/a0), which the panel title repeats; the figure's legend
names the line and both markers. The colour levels are 0.1 p0 apart up to ``VM_LEVEL_MAX``
and geometric above it (:func:`von_mises_levels`), up to the largest titled peak: every
marked peak lies inside the colour scale, and the singular edge does not wash out the rest
of the plane (each level band has one colour, whatever its width).

Studies that sweep dotted keys (load, mesh, modulus …) get ``sweep_<key>.png``
(:mod:`engine.analysis.sweep_figures`); when a swept key changes a0, p0 or the grid from
case to case, the per-case figures are drawn for one case chosen with ``--case ID``.

Legibility rules: no text below ``MIN_FONT_SIZE`` points (at ``DPI``, as the PNG
is seen at 100 %); no figure wider than ``MAX_WIDTH_PX``; cases that differ only in β get the
same colour and differ in line style, width and marker (``case_styles``), so curves that
coincide — an isotropic law at β = 0° and 90° — stay visible; surface maps use one colour
scale per wear panel (wear magnitudes differ by decades between friction coefficients); the
x–z panels are sized from the aspect ratio of the plane, so no blank band is left.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import BoundaryNorm  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

from engine.commands import refuse_file, results_parser  # noqa: E402
from engine.output.owner import being_written_file  # noqa: E402
from engine.reference.flat_punch import (  # noqa: E402
    flat_punch_stress,
    von_mises_cylindrical,
)

from .calibration_report import calibration_figures, has_calibration  # noqa: E402
from .levels import VM_LEVEL_MAX, von_mises_levels  # noqa: E402
from .report import _STUDY_WIDE, stiffness_ratios  # noqa: E402
from .results import ResultCase, Results, open_results  # noqa: E402
from .surface_figures import surface_figures  # noqa: E402
from .sweep_figures import sweep_figures  # noqa: E402
from .threshold_figures import has_thresholds, threshold_figures

__all__ = [
    "plot_study",
    "main",
    "VM_LEVEL_MAX",
    "von_mises_levels",
    "study_figures",
    "von_mises_plane_figure",
]

DPI = 95
MIN_FONT_SIZE = 9.0  # points
MAX_WIDTH_PX = 1600
MAX_COLUMNS = 3  # panels (cases) per row in the multi-case figures
# in: a figure of one or two panels is at least this wide, so that its title (study name,
# case, mesh and load) and the legend row below fit on it (the figures of one case)
MIN_FIGURE_WIDTH = 8.5
MIN_PANEL_HEIGHT = 3.2  # inches: a σ_VM plane panel with its titles and axis labels

_STYLE = {
    "font.size": 10.0,
    "axes.titlesize": 10.0,
    "axes.labelsize": 10.0,
    "xtick.labelsize": 9.0,
    "ytick.labelsize": 9.0,
    "legend.fontsize": 9.0,
    "figure.titlesize": 11.0,
}
# Per β (in the order met): line style, width, marker, marker size, filled, opacity. The first
# is a wide pale band, the later ones thinner and dashed on top of it, with other markers.
_BETA_STYLES = (
    {"ls": "-", "lw": 3.2, "marker": "o", "ms": 7, "mfc": "none", "alpha": 0.45},
    {"ls": "--", "lw": 1.6, "marker": "^", "ms": 5, "alpha": 1.0},
    {"ls": ":", "lw": 1.6, "marker": "x", "ms": 6, "alpha": 1.0},
    {"ls": "-.", "lw": 1.2, "marker": "s", "ms": 4, "alpha": 1.0},
)
_MARKERS = ("s", "o", "^", "D", "v", "P", "X", "<", ">")


# ----------------------------------------------------------------------------- entry points
def varies_normalisation(study: Results) -> bool:
    """True when a swept key changes a0, P, the grid or the material from case to case, so
    that the per-case figures cannot share one normalisation (fretting studies excepted:
    their figures are per case)."""
    return bool(set(study.swept_keys) & _STUDY_WIDE) and not study.loading_kind.figures_per_case


def study_figures(study: Results) -> Iterator[tuple[str, object]]:
    """(file name, figure) of every figure of ``study``, drawn one at a time."""
    yield from sweep_figures(study)
    yield from surface_figures(study)  # [surface]: topography, spots, spectra, ensemble
    if varies_normalisation(study):
        return  # per-case figures: --case ID (plot_study)
    yield from study.kind_hook("figures")(study)  # the loading kind's figures


def plot_study(
    results: str | Path | Results,
    out_dir: str | Path,
    *,
    case: str | None = None,
    on_figure: Callable[[Path], None] | None = None,
) -> list[Path]:
    """Write the figures of the study to ``out_dir`` (created); return the PNG paths.

    ``case``: only the per-case figures of that case id, normalised by its own a0, p0 and grid
    (for studies whose swept keys change them). ``on_figure(path)`` is called after each file.
    """
    study = results if isinstance(results, Results) else open_results(results)
    if case is not None:
        study = study.for_case(case)
    if not study.completed:
        raise ValueError(f"{study.path}: no completed case to plot")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    with plt.rc_context(_STYLE):
        for name, figure in study_figures(study):
            path = out / name
            figure.savefig(path, dpi=DPI)
            plt.close(figure)
            written.append(path)
            if on_figure is not None:
                on_figure(path)
    return written


def case_styles(cases: Sequence[ResultCase]) -> dict[str, dict]:
    """Line style of each case (by case id) for the curves of several cases in one axis.

    Cases that differ only in β share a colour and get the β style of ``_BETA_STYLES`` (wide
    pale solid line, dashed, dotted …, each with its own marker), so identical curves remain
    distinguishable. When all cases belong to one group (Section 7.3: β alone varies), the
    colour follows β as well.
    """
    betas = sorted({case.beta for case in cases})
    groups: list[tuple] = []
    for case in cases:
        key = (case.mu1, case.mu2, case.wear1, case.wear2)
        if key not in groups:
            groups.append(key)
    styles = {}
    for case in cases:
        beta_index = betas.index(case.beta)
        group_index = groups.index((case.mu1, case.mu2, case.wear1, case.wear2))
        colour = f"C{(beta_index if len(groups) == 1 else group_index) % 10}"
        style = dict(_BETA_STYLES[beta_index % len(_BETA_STYLES)]) if len(betas) > 1 else {
            "ls": "-", "lw": 1.6, "marker": _MARKERS[group_index % len(_MARKERS)], "ms": 4,
        }  # fmt: skip
        style["color"] = colour
        styles[case.case_id] = style
    return styles


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = results_parser(
        prog,
        "Draw the figures of a study (PNG) from its results file.",
        "results file (.h5) written by the engine",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="directory for the PNG files (default: <results>_figures beside the file)",
    )
    parser.add_argument(
        "--case",
        default=None,
        metavar="ID",
        help="draw the field figures (pressure, wear, σ_VM …) of this case alone, normalised "
        "by its own a0, p0 and grid (case ids: the summary's case_id column)",
    )
    return parser


def main(argv: Sequence[str] | None = None, prog: str | None = None) -> int:
    args = build_parser(prog).parse_args(argv)
    if being_written_file(args.results) or refuse_file(args.results):
        return 2

    if args.case is None and has_calibration(args.results):  # a [calibrate] study
        out = args.out or args.results.with_name(f"{args.results.stem}_figures")
        for number, path in enumerate(calibration_figures(args.results, out), start=1):
            print(f"plot: [{number}] {path}", flush=True)
        return 0
    if args.case is None and has_thresholds(args.results):  # a [search] study: its boundaries
        out = args.out or args.results.with_name(f"{args.results.stem}_figures")
        for number, path in enumerate(threshold_figures(args.results, out), start=1):
            print(f"plot: [{number}] {path}", flush=True)
        return 0
    study = open_results(args.results)
    try:
        if args.case is not None:
            study = study.for_case(args.case)
        if not study.completed:
            raise ValueError(f"{args.results}: no completed case to plot")
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    out = args.out or args.results.with_name(
        f"{args.results.stem}_figures" + (f"_{args.case}" if args.case else "")
    )
    count = len(study.completed)
    completed = f"{count} completed case{'s' if count != 1 else ''}"
    print(f"plot: {study.name}, {completed} -> {out}/", flush=True)
    count = 0

    def announce(path: Path) -> None:
        nonlocal count
        count += 1
        print(f"plot: [{count}] {path}", flush=True)

    plot_study(study, out, on_figure=announce)
    if varies_normalisation(study):
        first = study.completed[0].case_id
        keys = sorted(set(study.swept_keys) & _STUDY_WIDE)
        print(
            f"plot: swept {', '.join(keys)} {'changes' if len(keys) == 1 else 'change'} a0, "
            "p0, the grid or the material from case to case; the field figures of one case: "
            f"`python -m engine plot {args.results} --case {first}` (or another case_id)",
            flush=True,
        )
    return 0


# ----------------------------------------------------------------------------- helpers
def _title(study: Results, what: str) -> str:
    return f"{study.name}: {what} ({study.mesh_label}, P = {study.load:g} {study.load_unit})"


def _central_row(values: np.ndarray, study: Results, axis: str) -> tuple[np.ndarray, float]:
    """Profile along ``axis`` ('x' or 'y') on the grid line nearest to the other axis = 0.

    Returns (profile, offset in mm of that grid line from the axis).
    """
    if axis == "x":
        j = int(np.argmin(np.abs(study.grid_y)))
        return values[:, j], float(study.grid_y[j])
    i = int(np.argmin(np.abs(study.grid_x)))
    return values[i, :], float(study.grid_x[i])


def _sneddon_curve(study: Results, offset: float) -> tuple[np.ndarray, np.ndarray] | None:
    """The profile's unworn pressure p/p0 along a line at distance ``offset`` (mm) from the
    axis (a flat punch: Sneddon, Eq. 17), or None when the profile has no closed form."""
    a = study.radius
    s = np.linspace(-1.0, 1.0, 801) * min(a, float(np.max(study.grid_x)))
    r = np.hypot(s, offset)
    pressure = study.profile.unworn_pressure(r, study.load, a)
    return None if pressure is None else (s / a, pressure / study.p0)


def _panel_grid(count: int, width: float = 4.2, height: float = 3.4, max_columns: int = 3):
    """``count`` panels in rows of at most ``max_columns``, each ``width`` × ``height`` in."""
    columns = min(count, max_columns)
    rows = -(-count // columns)
    figure, axes = plt.subplots(
        rows,
        columns,
        figsize=(max(width * columns, MIN_FIGURE_WIDTH), height * rows),
        squeeze=False,
        layout="constrained",
    )
    for axis in axes.flat[count:]:
        axis.set_visible(False)
    return figure, list(axes.flat[:count])


def _von_mises_peaks(study: Results, plane) -> list[tuple[str, str, tuple]]:
    """(marker, what, (σ_VM/p0, x/a0, z/a0)) of the overall peak and the peak below the
    surface layer, at their own signed positions (as the summary's vm_max_x, vm_sub_max_x)."""
    a, p0 = study.radius, study.p0
    peaks = [("★", "max", plane.peak_point())]
    if len(plane.depths) > 1:
        peaks.append(("○", "below surface", plane.peak_point(float(plane.depths[1]))))
    return [(mark, what, (v / p0, x / a, z / a)) for mark, what, (v, x, _, z) in peaks]


_PEAK_MARKERS = {
    "★": {"marker": "*", "ms": 14, "mfc": "w", "mec": "k", "ls": "none"},
    # black edge: the peaks sit in the red and yellow of the scale, where white vanishes
    "○": {"marker": "o", "ms": 8, "mfc": "none", "mec": "k", "mew": 2, "ls": "none"},
}


def _draw_von_mises(axis, study: Results, plane_xz, title: str, levels, peaks=None):
    """Filled σ_VM/p0 contours in the x–z plane (``plane_xz``: x, z, σ_VM in mm, mm, MPa),
    the σ_VM/p0 = 1 line and, with ``peaks`` (:func:`_von_mises_peaks`), the peaks."""
    x, z, von_mises = plane_xz
    a, p0 = study.radius, study.p0
    norm = BoundaryNorm(levels, ncolors=plt.get_cmap("turbo").N, extend="max")
    filled = axis.contourf(
        x / a, z / a, von_mises / p0, levels=levels, cmap="turbo", norm=norm, extend="max"
    )
    axis.contour(x / a, z / a, von_mises / p0, levels=[1.0], colors="k", linewidths=1.2)
    for mark, what, (value, xa, za) in peaks or []:  # values in the title: no box on the plane
        axis.plot(xa, za, **_PEAK_MARKERS[mark], clip_on=False)
        title += f"\n{mark} {what} {value:.2f} at ({xa:+.2f}, {za:.3f})"
    axis.set_ylim(float(np.max(z)) / a, 0.0)
    reach = int(np.floor(float(np.max(np.abs(x))) / a / 0.5 + 1e-9))  # ticks 0.5 a0 apart
    axis.set_xticks(0.5 * np.arange(-reach, reach + 1))
    axis.set_xlabel("x/a0")
    axis.set_ylabel("z/a0 (depth)")
    axis.set_title(title, fontsize=MIN_FONT_SIZE)
    axis.set_aspect("equal")
    return filled


def _von_mises_legend(figure) -> None:
    """What the black line and the two markers of the σ_VM panels are."""
    handles = [
        Line2D([], [], color="k", lw=1.2, label="σ_VM/p0 = 1"),
        Line2D([], [], **_PEAK_MARKERS["★"], label="★ peak over the plane"),
        Line2D([], [], **_PEAK_MARKERS["○"], label="○ below the surface layer"),
    ]
    figure.legend(handles=handles, loc="outside lower center", ncols=3)


def _analytic_plane(study: Results, plane) -> tuple[np.ndarray, np.ndarray]:
    """A fine (x, z) grid (mm) over the extent of a computed plane, for Appendix A.

    Same depth of the surface layer as the computed plane, so that the peaks compare.
    """
    x = np.linspace(float(np.min(plane.x)), float(np.max(plane.x)), 421)
    top = float(plane.depths[0])
    z = np.concatenate([[top], np.geomspace(max(top, 1e-4 * study.radius), plane.z.max(), 240)])
    return np.meshgrid(x, np.unique(z), indexing="ij")


def von_mises_plane_figure(study: Results, key, suptitle: str):
    """σ_VM/p0 on the x–z plane ``key`` (a recorded cycle N or "final") of every case that
    has it, the peaks marked (the figure of ``von_mises_N<N>.png``)."""
    return _von_mises_figure(study, key, suptitle)


def _von_mises_figure(study: Results, key, suptitle: str, analytic: bool = False):
    panels = [case for case in study.completed if key in case.planes]
    count = len(panels) + int(analytic)
    plane = panels[0].planes[key]
    span = float(np.ptp(plane.x)) / max(float(np.max(plane.z)), 1e-300)  # width / depth
    width = 4.6 if count > 1 else MIN_FIGURE_WIDTH - 1.5  # one panel: as wide as the title
    # the height of an equal-aspect plane and its titles; a wide, shallow plane still gets
    # room for the axis labels beside it
    height = max((width - 1.1) / span + 1.6, MIN_PANEL_HEIGHT)
    figure, axes = _panel_grid(count, width=width, height=height)
    peaks = {case.case_id: _von_mises_peaks(study, case.planes[key]) for case in panels}
    top = max(value for marked in peaks.values() for _, _, (value, _, _) in marked)
    levels = von_mises_levels(top)
    filled = None
    axes_iter = iter(axes)
    if analytic:  # no peak marked: the analytic edge is singular (values above: top colour)
        x, z = _analytic_plane(study, panels[0].planes[key])
        nu = study.study["material"]["nu_A"]
        stress = flat_punch_stress(np.abs(x), z, study.load, study.radius, nu)
        filled = _draw_von_mises(
            next(axes_iter), study, (x, z, von_mises_cylindrical(stress)),
            "Appendix A, μ = 0 (analytic)", levels,
        )  # fmt: skip
    for case in panels:
        plane = case.planes[key]
        filled = _draw_von_mises(
            next(axes_iter), study, (plane.x, plane.z, plane.von_mises), case.label, levels,
            peaks[case.case_id],
        )  # fmt: skip
    ticks = [0.0, 0.5, 1.0, 1.5, VM_LEVEL_MAX] + ([levels[-1]] if len(levels) > 21 else [])
    bar = figure.colorbar(filled, ax=axes, label="σ_VM / p0", shrink=0.9, fraction=0.03, aspect=30)
    bar.set_ticks(ticks, labels=[f"{tick:.3g}" for tick in ticks])
    _von_mises_legend(figure)
    figure.suptitle(
        suptitle + "\npeak positions at (x/a0, z/a0); colour levels 0.1 apart up to "
        f"{VM_LEVEL_MAX:g}, geometric above"
    )
    return figure


# ----------------------------------------------------------------------------- static study
def static_figures(study: Results):
    frictionless = [case for case in study.completed if case.mu1 == 0.0 and case.mu2 == 0.0]
    if frictionless:
        yield "pressure_frictionless.png", _pressure_frictionless(study, frictionless[0])
    yield "stiffness_ratio.png", _stiffness_ratio(study)
    yield "traction_profiles.png", _traction_profiles(study)
    title = _title(study, "σ_VM/p0 in the x–z plane (y = 0)")
    yield "von_mises_final.png", _von_mises_figure(study, "final", title, analytic=True)


def _pressure_frictionless(study: Results, case: ResultCase):
    a, p0 = study.radius, study.p0
    pressure, offset = _central_row(case.fields["final"]["pressure"], study, "x")
    figure, axis = plt.subplots(figsize=(MIN_FIGURE_WIDTH, 4.6), layout="constrained")
    unworn = _sneddon_curve(study, offset)
    if unworn is not None:  # a profile with a closed form (the flat punch: Sneddon)
        axis.plot(*unworn, "-", color="C0", label="Sneddon, Eq. (17)")
    axis.plot(study.grid_x / a, pressure / p0, "s", ms=4, mfc="none", color="C3", label="computed")
    axis.set_xlabel("x/a0")
    axis.set_ylabel("p / p0")
    axis.set_ylim(0.0, max(3.0, 1.1 * float(np.max(pressure / p0))))
    axis.legend()
    axis.grid(alpha=0.3)
    axis.set_title(
        _title(study, f"frictionless pressure, {case.case_id}")
        + f"\nalong x at y/a0 = {offset / a:.3f} (grid line nearest the axis)",
    )
    return figure


def _stiffness_ratio(study: Results):
    mu, ratio, limit, what = stiffness_ratios(study)
    figure, axis = plt.subplots(figsize=(MIN_FIGURE_WIDTH, 4.6), layout="constrained")
    axis.plot(mu, ratio, "s-", color="C3", label=f"computed, k = P/g_n (k_0: {what})")
    axis.axhline(
        limit, color="C0", ls="--",
        label=f"Mossakovskii (full stick) artanh(β)/β = {limit:.5f}",
    )  # fmt: skip
    axis.axhline(1.0, color="0.5", lw=0.8)
    axis.set_xlabel("friction coefficient μ")
    axis.set_ylabel("k_n|μ / k_n|frictionless")
    span = max(limit - 1.0, float(np.max(ratio)) - 1.0, 1e-3)
    axis.set_ylim(1.0 - 0.15 * span, 1.0 + 1.25 * span)
    axis.legend(loc="lower right")
    axis.grid(alpha=0.3)
    nu = study.material.poisson_ratio
    axis.set_title(
        _title(study, "normal stiffness vs friction")
        + f"\nν = {nu:.3f}, Dundurs β = {study.material.dundurs_beta:.5f}",
    )
    return figure


def _traction_profiles(study: Results):
    a, p0 = study.radius, study.p0
    cases = sorted(study.completed, key=lambda case: case.mu1)
    figure, axes = _panel_grid(len(cases), width=4.3, height=3.3)
    for axis, case in zip(axes, cases, strict=True):
        fields = case.fields["final"]
        pressure, offset = _central_row(fields["pressure"], study, "x")
        traction, _ = _central_row(fields["traction_x"], study, "x")
        unworn = _sneddon_curve(study, offset)
        xa = study.grid_x / a
        if unworn is not None:  # a profile with a closed form (the flat punch: Sneddon)
            axis.plot(*unworn, "-", color="0.6", lw=1, label="Sneddon (μ = 0)")
        axis.plot(xa, pressure / p0, "s", ms=3, mfc="none", color="C3", label="p/p0")
        axis.plot(xa, traction / p0, "o", ms=3, mfc="none", color="C0", label="q_x/p0")
        if case.mu1 > 0:
            bound = case.mu1 * pressure / p0
            axis.plot(xa, bound, ":", color="C0", lw=1, label="±μ p/p0")
            axis.plot(xa, -bound, ":", color="C0", lw=1)
        axis.set_ylim(-1.2, 3.0)
        axis.set_xlabel("x/a0")
        axis.set_ylabel("traction / p0")
        stick = case.summary.get("stick_fraction", float("nan"))
        axis.set_title(f"{case.label}  (stick fraction {stick:.2f})")
        axis.grid(alpha=0.3)
    axes[0].legend(loc="upper center")
    figure.suptitle(_title(study, f"tractions along x at y/a0 = {offset / a:.3f}"))
    return figure


# ----------------------------------------------------------------------------- cyclic study
def cyclic_figures(study: Results):
    yield "wear_history.png", _wear_history(study)
    yield "pressure_profiles.png", _pressure_profiles(study)
    cycles = sorted({n for case in study.completed for n in case.recorded_cycles})
    if cycles and study.profile.is_line:  # a map of one row of elements shows nothing
        last = cycles[-1]
        yield f"surface_N{last}.png", _line_surface(study, last)
    elif cycles:
        last = cycles[-1]
        yield f"surface_maps_N{last}.png", _surface_maps(study, last)
    for cycle in cycles:
        title = _title(study, f"σ_VM/p0 in the x–z plane after N = {cycle:,}")
        yield f"von_mises_N{cycle}.png", _von_mises_figure(study, cycle, title)
    from .regime import regime_figures  # peak regime: studies that sweep wear

    yield from regime_figures(study)


def _wear_history(study: Results):
    figure, (depth_axis, volume_axis) = plt.subplots(
        1, 2, figsize=(13.0, 4.6), layout="constrained"
    )
    styles = case_styles(study.completed)
    for case in study.completed:
        cycles = np.asarray(case.history["cycle"], dtype=float)
        depth = np.asarray(case.history["max_wear_depth"]) * 1e3  # mm -> µm
        volume = np.asarray(case.history["wear_volume"])
        keep = (cycles > 0) & (depth > 0) & (volume > 0)
        style = {**styles[case.case_id], "label": case.label}
        depth_axis.loglog(cycles[keep], depth[keep], **style)
        volume_axis.loglog(cycles[keep], volume[keep], **style)
    depth_axis.set_ylabel("maximum wear depth (µm)")
    volume_axis.set_ylabel(f"wear volume ({study.per_contact('mm³')})")
    for axis in (depth_axis, volume_axis):
        axis.set_xlabel("load cycles N")
        axis.grid(alpha=0.3, which="both")
    _legend_beside(figure, volume_axis, len(study.completed))
    figure.suptitle(_title(study, "wear history (markers: simulated cycles, cycle jumping)"))
    return figure


def _profile_axes(study: Results) -> list[str]:
    """Along x only for isotropic studies; along x and y when the axes β matter."""
    return ["x"] if study.isotropic else ["x", "y"]


def _pressure_profiles(study: Results):
    a, p0 = study.radius, study.p0
    cycles = sorted({n for case in study.completed for n in case.recorded_cycles})
    directions = _profile_axes(study)
    columns = max(len(cycles), 1)
    width = min(4.4, (MAX_WIDTH_PX / DPI - 3.0) / columns)  # room for the legend beside
    figure, axes = plt.subplots(
        len(directions), columns,
        figsize=(max(width * columns + 3.0, MIN_FIGURE_WIDTH + 1.5), 3.6 * len(directions)),
        squeeze=False, layout="constrained", sharey=True,
    )  # fmt: skip
    styles = case_styles(study.completed)
    for row, direction in enumerate(directions):
        coordinate = study.grid_x if direction == "x" else study.grid_y
        for column, cycle in enumerate(cycles):
            axis = axes[row, column]
            offset = 0.0
            for case in study.completed:
                if cycle not in case.fields:
                    continue
                pressure, offset = _central_row(case.fields[cycle]["pressure"], study, direction)
                style = {**styles[case.case_id], "label": case.label}
                style["ms"] = style["ms"] * 0.6  # 64 points per curve
                axis.plot(coordinate / a, pressure / p0, **style)
            unworn = _sneddon_curve(study, offset)
            if unworn is not None:
                axis.plot(*unworn, "--", color="0.5", lw=1, label="Sneddon, unworn")
            other = "y" if direction == "x" else "x"
            axis.set_title(f"N = {cycle:,}, along {direction} ({other}/a0 = {offset / a:.3f})")
            axis.set_xlabel(f"{direction}/a0")
            axis.set_ylabel("p / p0")
            axis.set_ylim(0.0, 4.0)
            axis.grid(alpha=0.3)
    _legend_beside(figure, axes[0, -1], len(study.completed) + 1)
    figure.suptitle(_title(study, "pressure at peak load of recorded cycles"))
    return figure


def _draw_axes_of_anisotropy(axis, case: ResultCase) -> None:
    """Tribological axes e1 (solid) and e2 (dashed) at angle β, through the punch centre."""
    beta = np.radians(case.beta)
    for angle, style, name in ((beta, "-", "e1"), (beta + np.pi / 2, "--", "e2")):
        dx, dy = np.cos(angle), np.sin(angle)
        axis.plot([-dx, dx], [-dy, dy], style, color="w", lw=0.9)
        axis.text(
            0.72 * dx, 0.72 * dy, name, color="w", fontsize=MIN_FONT_SIZE, ha="center",
            va="center", bbox={"facecolor": "k", "alpha": 0.5, "pad": 1, "edgecolor": "none"},
        )  # fmt: skip


def _legend_beside(figure, axis, entries: int) -> None:
    """The legend to the right of ``axis`` (outside the data), one column."""
    handles, labels = axis.get_legend_handles_labels()
    axis.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)


def _columns_for(count: int, max_columns: int = MAX_COLUMNS) -> int:
    """Columns (max_columns − 1 or max_columns, fewer only for fewer panels) leaving the
    fewest empty cells in the last row; ties go to more columns."""
    if count <= max_columns:
        return max(count, 1)
    return min(
        range(max_columns - 1, max_columns + 1),
        key=lambda columns: (-(-count // columns) * columns - count, -columns),
    )


def _line_surface(study: Results, cycle: int):
    """A line contact's surface after N = ``cycle``: wear depth (µm) and p/p0 along x/a0,
    one line per case."""
    a, p0 = study.radius, study.p0
    figure, (wear_axis, pressure_axis) = plt.subplots(
        2, 1, figsize=(MIN_FIGURE_WIDTH + 1.5, 6.4), sharex=True, layout="constrained"
    )
    styles = case_styles(study.completed)
    for case in study.completed:
        if cycle not in case.fields:
            continue
        style = {**styles[case.case_id], "label": case.label}
        style["ms"] = style["ms"] * 0.6
        fields = case.fields[cycle]
        wear_axis.plot(study.grid_x / a, fields["wear"][:, 0] * 1e3, **style)
        pressure_axis.plot(study.grid_x / a, fields["pressure"][:, 0] / p0, **style)
    wear_axis.set_ylabel("wear depth (µm)")
    pressure_axis.set_ylabel("p / p0")
    pressure_axis.set_xlabel("x/a0")
    for axis in (wear_axis, pressure_axis):
        axis.grid(alpha=0.3)
    _legend_beside(figure, wear_axis, len(study.completed))
    figure.suptitle(_title(study, f"surface after N = {cycle:,} cycles"))
    return figure


def _surface_maps(study: Results, cycle: int):
    """Wear depth and p/p0 of every case, in blocks of two rows (wear above pressure) of up
    to ``MAX_COLUMNS`` cases. Each wear panel has its own colour scale (between μ = 0.1 and
    0.4 the wear differs by an order of magnitude, and a shared scale hides the small one);
    the pressure panels share one scale (same magnitude; the edge elements set its top)."""
    a, p0 = study.radius, study.p0
    cases = [case for case in study.completed if cycle in case.fields]
    extent = study.grid_x / a, study.grid_y / a
    pressure = [case.fields[cycle]["pressure"] / p0 for case in cases]
    pressure_max = max(float(np.max(p)) for p in pressure) or 1.0
    if len(cases) == 1:  # one case: wear beside pressure (stacked, half the page was empty)
        figure, row = plt.subplots(
            1, 2, figsize=(MIN_FIGURE_WIDTH + 1.5, 4.6), squeeze=False, layout="constrained"
        )
        axes, columns, blocks = row.reshape(2, 1), 1, 1
    else:
        columns = _columns_for(len(cases))
        blocks = -(-len(cases) // columns)
        figure, axes = plt.subplots(
            2 * blocks, columns, figsize=(max(4.1 * columns, MIN_FIGURE_WIDTH), 3.15 * 2 * blocks),
            squeeze=False, layout="constrained",
        )  # fmt: skip
    for number, case in enumerate(cases):
        block, column = divmod(number, columns)
        wear = case.fields[cycle]["wear"] * 1e3  # µm
        rows = (
            (wear, "viridis", float(np.max(wear)) or 1.0, "wear depth (µm)"),
            (pressure[number], "magma", pressure_max, "p / p0"),
        )
        for row, (values, cmap, top, what) in enumerate(rows):
            axis = axes[2 * block + row, column]
            mesh = axis.pcolormesh(
                *extent, values.T, cmap=cmap, vmin=0.0, vmax=top, shading="nearest"
            )
            axis.add_patch(Circle((0.0, 0.0), 1.0, fill=False, color="w", lw=0.8, ls=":"))
            if not study.isotropic:
                _draw_axes_of_anisotropy(axis, case)
            axis.set_aspect("equal")
            axis.set_xlabel("x/a0")
            axis.set_ylabel("y/a0")
            axis.set_title(f"{'wear' if row == 0 else 'p/p0'}, {case.label}")
            figure.colorbar(mesh, ax=axis, label=what, shrink=0.9)
    for number in range(len(cases), blocks * columns):
        block, column = divmod(number, columns)
        axes[2 * block, column].set_visible(False)
        axes[2 * block + 1, column].set_visible(False)
    figure.suptitle(
        _title(study, f"surface after N = {cycle:,} cycles")
        + "\ndotted: r = a0; wear: colour scale per panel"
    )
    return figure


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(prog="python -m engine.analysis.figures"))
