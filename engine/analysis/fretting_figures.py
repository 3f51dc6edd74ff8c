"""Figures of a tangential fretting study (``[loading] kind = "fretting"``).

``python -m engine plot RESULTS.h5`` draws, for a fretting study (:func:`fretting_figures`):

``fretting_map.png``
    the running-condition fretting map: displacement amplitude δ* (µm) × normal load P (N),
    one marker per case coloured by slip regime (partial slip; gross slip; mixed: the regime
    changed during the run), with Mindlin's partial/gross boundary δ_slip(P) = 3μP S/(16a)
    (:func:`engine.reference.mindlin.slip_displacement`) drawn as a line per friction
    coefficient (sphere only).
``fretting_loops.png``
    the fretting loops Q–δ at the recorded cycles of up to six cases (spread over the
    amplitudes at the middle load), with the stabilised Mindlin–Deresiewicz / gross-slip loop
    (:func:`engine.reference.mindlin.fretting_loop`) dashed where it applies (sphere,
    isotropic friction; exact for K = 0).
``wear_energy.png``
    wear volume (mm³) against the cumulated dissipated energy (J), linear and log–log: for
    the energy wear law (Fouvry) V = α E_d is a line through the origin, drawn with the
    study's α; for Archard's law the line through the origin fitted by least squares is drawn
    and its slope (the energy wear coefficient it implies) given in the legend.

Loop and map quantities are projected on the sliding direction (``direction``, degrees from
x): δ = δ_x cos θ + δ_y sin θ, Q = Q_x cos θ + Q_y sin θ. Units: δ in µm on the axes (mm in
the file), Q in N, energies in mJ per cycle and J cumulated (1 J = 1000 mJ = 1000 N·mm).

The drawing functions (``draw_*``) take plain arrays, so they are usable and testable without
a results file; :func:`fretting_figures` is the thin adapter from the results file.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import NullFormatter, ScalarFormatter

from engine.reference import mindlin
from engine.schema import contact_units

from . import fretting as _shared
from .case_fields import case_field_figures
from .fatigue import has_fatigue
from .fatigue_figures import crack_points, draw_crack_boundary, fatigue_figures
from .figures import MIN_FIGURE_WIDTH
from .fretting import case_profile, cumulated_energy, read_loops
from .results import ResultCase, Results

__all__ = [
    "FrettingCase",
    "LoopPanel",
    "draw_fretting_map",
    "draw_fretting_loops",
    "draw_wear_energy",
    "fretting_figures",
    "read_loops",
    "cumulated_energy",
]

MICRONS_PER_MM = 1e3
REGIME_STYLES = {
    "partial": {"color": "C0", "marker": "o", "label": "partial slip"},
    "mixed": {"color": "C2", "marker": "D", "label": "mixed (regime changed)"},
    "gross": {"color": "C3", "marker": "s", "label": "gross slip"},
}
MAX_LOOP_PANELS = 6


@dataclass
class FrettingCase:
    """One case on the fretting map: amplitude δ* (mm), load P (N), regime, friction μ; and,
    where Mindlin applies (sphere, isotropic friction), δ*/δ_slip(P) and the computed energy
    ratio A = W/(4 δ* Q*) of the first simulated cycle (NaN otherwise)."""

    amplitude: float
    load: float
    regime: str
    friction: float
    displacement_ratio: float = float("nan")
    energy_ratio: float = float("nan")


@dataclass
class LoopPanel:
    """The loops of one case: ``loops[N] = (δ in mm, Q in N)`` along the sliding direction,
    and the analytic stabilised loop (δ, Q) or None."""

    title: str
    loops: dict[int, tuple[np.ndarray, np.ndarray]]
    reference: tuple[np.ndarray, np.ndarray] | None = None
    reference_label: str = "Mindlin–Deresiewicz (K = 0)"


@dataclass
class WearSeries:
    """Cumulated dissipated energy (J) and wear volume (mm³) of one case over its cycles."""

    group: str  # legend entry shared by cases of one colour (e.g. "P = 100 N")
    energy: np.ndarray
    volume: np.ndarray
    coefficient: float | None = None  # the energy law's α (mm³/J); None for Archard's law
    regime: str = "partial"  # markers filled for gross slip, hollow otherwise


# ----------------------------------------------------------------------------- drawing
def draw_fretting_map(
    cases: Sequence[FrettingCase],
    boundaries: dict[float, tuple[np.ndarray, np.ndarray]],
    title: str,
    *,
    load_unit: str = "N",
    boundary_label: str = "Mindlin boundary δ_slip(P)",
):
    """The running-condition fretting map, and Fouvry's energy ratio against δ*/δ_slip.

    ``cases``: the markers (amplitude in mm, load in N, regime "partial"/"gross"/"mixed").
    ``boundaries``: per friction coefficient μ, (δ_slip in mm, P in ``load_unit``) of the
    partial/gross boundary (Mindlin's for a sphere; the cylinder's, N/mm, for a line
    contact). Left: δ* (µm, log axis) × P with the boundaries. Right (when some case has a finite
    ``energy_ratio``): A = W/(4δ*Q*) against δ*/δ_slip(P), where every load falls on
    Mindlin's one master curve (:func:`engine.reference.mindlin.energy_ratio`), A = 0.2 at
    the boundary.
    """
    frictions = sorted({case.friction for case in cases})
    if len(frictions) > 1 and not any(np.isfinite(case.energy_ratio) for case in cases):
        return _map_per_friction(cases, boundaries, title, frictions, load_unit, boundary_label)
    with_ratio = [case for case in cases if np.isfinite(case.energy_ratio)]
    columns = 2 if with_ratio else 1
    figure, axes = plt.subplots(
        1, columns, figsize=(7.0 * columns, 5.0), squeeze=False, layout="constrained"
    )
    axis = axes[0, 0]
    for mu, (slip, loads) in sorted(boundaries.items()):
        axis.plot(
            np.asarray(slip) * MICRONS_PER_MM, loads, "-", lw=1.4, color=_grey(mu, boundaries),
            label=f"{boundary_label}, μ = {mu:g}",
        )  # fmt: skip
    _map_panel(axis, cases, load_unit)
    axis.set_title("slip regime of each case")
    if with_ratio:
        _draw_energy_ratio(axes[0, 1], with_ratio)
    figure.suptitle(title)
    return figure


def _map_panel(axis, cases: Sequence[FrettingCase], load_unit: str, legend: bool = True) -> None:
    """The regime markers on δ* (µm, log axis) × P, with ticks, labels and the legend."""
    _regime_markers(axis, cases, lambda case: case.amplitude * MICRONS_PER_MM, "load")
    axis.set_xscale("log")
    axis.xaxis.set_major_formatter(ScalarFormatter())
    axis.xaxis.set_minor_formatter(NullFormatter())
    axis.set_xticks(_round_ticks([case.amplitude * MICRONS_PER_MM for case in cases]))
    axis.set_xlabel("displacement amplitude δ* (µm)")
    axis.set_ylabel(f"normal load P ({load_unit})")
    axis.grid(alpha=0.3, which="both")
    if legend:
        axis.legend(loc="upper left")


def _map_per_friction(cases, boundaries, title, frictions, load_unit, boundary_label):
    """One map panel per friction coefficient (a study sweeping μ too), each with its own
    boundary: the cases of different μ would otherwise hide one another."""
    figure, axes = _panels(len(frictions), 5.2, 4.2)
    for axis, mu in zip(axes, frictions, strict=True):
        if mu in boundaries:
            slip, loads = boundaries[mu]
            axis.plot(np.asarray(slip) * MICRONS_PER_MM, loads, "k-", lw=1.4, label=boundary_label)
        _map_panel(axis, [case for case in cases if case.friction == mu], load_unit, False)
        axis.set_title(f"μ = {mu:g}")
    _legend_below(figure, axes)
    figure.suptitle(title)
    return figure


def _panels(count: int, width: float, height: float):
    """A figure of ``count`` panels, up to three per row (the rest hidden); the panels."""
    columns = min(3, max(count, 1))
    rows = -(-count // columns)
    figure, axes = plt.subplots(
        rows, columns, figsize=(max(width * columns, MIN_FIGURE_WIDTH), height * rows),
        squeeze=False, layout="constrained",
    )  # fmt: skip
    for axis in axes.flat[count:]:
        axis.set_visible(False)
    return figure, list(axes.flat[:count])


def _legend_below(figure, axes) -> None:
    """One legend for all panels, below them (each label once)."""
    entries: dict[str, object] = {}
    for axis in axes:
        for handle, label in zip(*axis.get_legend_handles_labels(), strict=True):
            entries.setdefault(label, handle)
    if entries:
        figure.legend(
            list(entries.values()), list(entries), loc="outside lower center",
            ncol=min(len(entries), 5),
        )  # fmt: skip


def _grey(mu: float, boundaries: dict) -> str:
    """Black for a single boundary; shades of grey from dark (lowest μ) when several."""
    if len(boundaries) == 1:
        return "k"
    order = sorted(boundaries).index(mu)
    return str(round(0.6 * order / (len(boundaries) - 1), 3))


def _regime_markers(axis, cases, x_of, y_name: str) -> None:
    """One marker style per slip regime (REGIME_STYLES), at (x_of(case), case.<y_name>)."""
    for regime, style in REGIME_STYLES.items():
        chosen = [case for case in cases if case.regime == regime]
        if chosen:
            axis.plot(
                [x_of(case) for case in chosen], [getattr(case, y_name) for case in chosen],
                ls="none", ms=8, mfc=style["color"], mec="k", marker=style["marker"],
                label=style["label"],
            )  # fmt: skip


def _draw_energy_ratio(axis, cases: Sequence[FrettingCase]) -> None:
    """A = W/(4δ*Q*) of each case against δ*/δ_slip, with Mindlin's master curve."""
    ratios = np.array([case.displacement_ratio for case in cases])
    span = np.geomspace(min(0.5, ratios.min() / 1.3), max(2.0, ratios.max() * 1.3), 300)
    axis.plot(span, mindlin.energy_ratio(span), "k-", lw=1.4, label="Mindlin (any P, R, μ)")
    axis.axhline(0.2, color="0.4", ls="--", lw=1.0, label="A = 0.2 (transition)")
    axis.axvline(1.0, color="0.4", ls=":", lw=1.0)
    _regime_markers(axis, cases, lambda case: case.displacement_ratio, "energy_ratio")
    axis.set_xscale("log")
    axis.xaxis.set_major_formatter(ScalarFormatter())
    axis.xaxis.set_minor_formatter(NullFormatter())
    axis.set_xticks(_round_ticks(span))
    axis.set_ylim(0.0, 1.0)
    axis.set_xlabel("δ*/δ_slip(P) (dimensionless)")
    axis.set_ylabel("energy ratio A = W/(4 δ* Q*) (dimensionless)")
    axis.grid(alpha=0.3, which="both")
    axis.legend(loc="upper left")
    axis.set_title("Fouvry's energy ratio, first simulated cycle")


def _round_ticks(values) -> list[float]:
    """1-2-5 ticks (µm) spanning ``values`` on the log axis of the map."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values) & (values > 0)]
    if not values.size:
        return []
    low, high = np.floor(np.log10(values.min())), np.ceil(np.log10(values.max()))
    ticks = [m * 10.0**e for e in np.arange(low, high + 1) for m in (1.0, 2.0, 5.0)]
    return [t for t in ticks if values.min() / 1.5 <= t <= values.max() * 1.5]


def draw_fretting_loops(panels: Sequence[LoopPanel], title: str, force_unit: str = "N"):
    """Q–δ loops (δ in µm, Q in ``force_unit``), one panel per case, one colour per
    recorded cycle."""
    figure, axes = _panels(len(panels), 4.6, 3.7)
    coincide = False
    for axis, panel in zip(axes, panels, strict=True):
        drawn = []
        for number, (cycle, (delta, force)) in enumerate(sorted(panel.loops.items())):
            style = _LOOP_STYLES[min(number, len(_LOOP_STYLES) - 1)]
            axis.plot(
                np.asarray(delta) * MICRONS_PER_MM, force, color=f"C{number % 10}",
                label=f"N = {cycle:,}", **style,
            )  # fmt: skip
            coincide |= any(_same_loop(delta, force, other) for other in drawn)
            drawn.append((np.asarray(delta), np.asarray(force)))
        if panel.reference is not None:
            delta, force = panel.reference
            axis.plot(
                np.asarray(delta) * MICRONS_PER_MM, force, "k--", lw=1.0,
                label=panel.reference_label,
            )  # fmt: skip
        axis.axhline(0.0, color="0.6", lw=0.6)
        axis.axvline(0.0, color="0.6", lw=0.6)
        axis.set_xlabel("tangential displacement δ (µm)")
        axis.set_ylabel(f"tangential force Q ({force_unit})")
        axis.set_title(panel.title)
        axis.grid(alpha=0.3)
    _legend_below(figure, axes)  # loops fill the corners of a gross-slip panel
    if coincide:
        title += (
            "\nlater cycles drawn thinner on top: a loop hidden under a later one is the wide band"
        )
    figure.suptitle(title)
    return figure


# The loops of a panel's recorded cycles, first to last: the first a wide pale band, the later
# ones thinner, dashed or dotted, with their own markers, so that equal loops stay visible.
_LOOP_STYLES = (
    {"ls": "-", "lw": 4.5, "alpha": 0.35},
    {"ls": "--", "lw": 1.6, "marker": "o", "ms": 3.5, "mfc": "none"},
    {"ls": ":", "lw": 1.6, "marker": "x", "ms": 4},
    {"ls": "-.", "lw": 1.2, "marker": "s", "ms": 3},
)


def _same_loop(delta, force, other) -> bool:
    """Whether the loop (δ, Q) lies on ``other`` to 1 % of its force amplitude (what a reader
    cannot tell apart at the figure's scale)."""
    other_delta, other_force = other
    if other_delta.shape != np.shape(delta):
        return False
    scale = max(float(np.max(np.abs(other_force))), 1e-300)
    return bool(
        np.allclose(delta, other_delta, rtol=0.0, atol=1e-2 * float(np.ptp(other_delta)) + 1e-300)
        and np.allclose(force, other_force, rtol=0.0, atol=1e-2 * scale)
    )


def draw_wear_energy(series: Sequence[WearSeries], title: str, line: bool = False):
    """Wear volume (mm³) against cumulated dissipated energy (J), linear and log–log.

    Series with an energy-law coefficient α (mm³/J) get the line V = α E_d (one per distinct
    α); without (Archard's law) the least-squares line through the origin of all points is
    drawn and its slope, the energy wear coefficient Archard's law implies, is given.
    ``line``: a line contact's series, energies and volumes per unit length
    (:func:`engine.schema.contact_units`).
    """
    figure, (linear, logarithmic) = plt.subplots(1, 2, figsize=(13.0, 4.8), layout="constrained")
    energy = np.concatenate([np.asarray(item.energy, dtype=float) for item in series] or [[0.0]])
    volume = np.concatenate([np.asarray(item.volume, dtype=float) for item in series] or [[0.0]])
    groups = list(dict.fromkeys(item.group for item in series))
    for item in series:
        number = groups.index(item.group)
        colour, marker = f"C{number % 10}", "os^Dv"[number % 5]
        for axis in (linear, logarithmic):
            axis.plot(
                item.energy, item.volume, ls="-", lw=0.6, marker=marker, ms=5, color=colour,
                mfc=colour if item.regime == "gross" else "none",
            )  # fmt: skip
    for number, group in enumerate(groups):  # legend: one entry per group, then the fill
        logarithmic.plot([], [], ls="-", lw=0.6, marker="os^Dv"[number % 5],
                         color=f"C{number % 10}", mfc="none", label=group)  # fmt: skip
    logarithmic.plot([], [], ls="none", marker="o", color="0.3", mfc="none", label="partial slip")
    logarithmic.plot([], [], ls="none", marker="o", color="0.3", label="gross slip (filled)")
    coefficients = sorted({item.coefficient for item in series if item.coefficient is not None})
    if coefficients:
        lines = [(alpha, f"energy law V = α E_d, α = {alpha:.3g} mm³/J") for alpha in coefficients]
    else:
        slope = float(energy @ volume / (energy @ energy)) if energy @ energy > 0 else 0.0
        lines = [(slope, f"fit through the origin: V = {slope:.3g} mm³/J · E_d")]
    positive = energy[energy > 0]
    if positive.size:
        span = np.geomspace(positive.min(), positive.max(), 50)
        for number, (slope, label) in enumerate(lines):
            style = {"color": "k", "lw": 1.0, "ls": ("-", "--", ":", "-.")[number % 4]}
            linear.plot(np.concatenate([[0.0], span]), slope * np.concatenate([[0.0], span]),
                        label=label, **style)  # fmt: skip
            if slope > 0:
                logarithmic.plot(span, slope * span, label=label, **style)
        logarithmic.set_xscale("log")
        logarithmic.set_yscale("log")
    for axis in (linear, logarithmic):
        axis.set_xlabel(f"cumulated dissipated energy E_d ({contact_units('J', line)})")
        axis.set_ylabel(f"wear volume V ({contact_units('mm³', line)})")
        axis.grid(alpha=0.3, which="both")
    linear.set_xlim(left=0.0)
    linear.set_ylim(bottom=0.0)
    handles, labels = logarithmic.get_legend_handles_labels()
    logarithmic.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    figure.suptitle(title)
    return figure


# ----------------------------------------------------------------------------- adapter
# The results-file helpers shared with the report and scripts/check_fretting_map.py live in
# engine.analysis.fretting (no matplotlib there); the short names below are this module's.
_setting, _direction, _amplitude = _shared.setting, _shared.direction, _shared.amplitude
_regime, _material = _shared.regime, _shared.material
_energy_coefficient = _shared.energy_coefficient


def _isotropic_friction(case: ResultCase) -> bool:
    """μ1 = μ2 (the wear coefficients do not matter here; they are NaN under the energy law)."""
    return case.mu1 == case.mu2


def _map_figure(study: Results):
    cases, boundaries = [], {}
    for case in study.completed:
        load, amplitude = float(_setting(study, case, "loading.load")), _amplitude(study, case)
        item = FrettingCase(amplitude, load, _regime(case), case.mu1)
        boundary = _shared.slip_boundary(study, case)
        if boundary is not None:
            boundaries.setdefault(case.mu1, boundary)
            reference = _shared.case_reference(study, case)[0]
            if reference is not None and reference.master_curve is not None:  # one curve
                item.displacement_ratio = amplitude / float(boundary(load))
                item.energy_ratio = _computed_energy_ratio(case)
        cases.append(item)
    loads = np.array([item.load for item in cases])
    span = np.linspace(0.6 * loads.min(), 1.15 * loads.max(), 100)
    lines = {mu: (boundary(span), span) for mu, boundary in boundaries.items()}
    title = f"{study.name}: running-condition fretting map\n({study.mesh_label})"
    if study.profile.is_line:
        datum = study.study.get("mesh", {}).get("reference_distance")
        figure = draw_fretting_map(
            cases, lines, title, load_unit=study.load_unit,
            boundary_label=f"cylinder δ_slip(P), datum {datum:g} mm",
        )  # fmt: skip
    else:
        figure = draw_fretting_map(cases, lines, title)
    if has_fatigue(study):  # where a crack is predicted, over the slip regimes
        axis = figure.axes[0]
        points = crack_points(
            study,
            lambda case: _amplitude(study, case) * MICRONS_PER_MM,
            lambda case: float(_setting(study, case, "loading.load")),
        )
        draw_crack_boundary(axis, points)
        axis.legend(loc="best")
    return figure


def _computed_energy_ratio(case: ResultCase) -> float:
    """A = W/(4 δ* Q*) of the first simulated cycle (history row 0), NaN without history."""
    history = case.history
    if not all(key in history for key in ("energy", "q_amplitude", "displacement_amplitude")):
        return float("nan")
    denominator = 4.0 * history["displacement_amplitude"][0] * history["q_amplitude"][0]
    return float(history["energy"][0] / denominator) if denominator > 0 else float("nan")


def _loop_cases(study: Results) -> list[ResultCase]:
    """Up to six cases: at the middle load, spread over the amplitudes."""
    loads = sorted({float(_setting(study, case, "loading.load")) for case in study.completed})
    middle = loads[len(loads) // 2]
    chosen = [c for c in study.completed if float(_setting(study, c, "loading.load")) == middle]
    chosen.sort(key=lambda case: _amplitude(study, case))
    if len(chosen) > MAX_LOOP_PANELS:
        picks = np.linspace(0, len(chosen) - 1, MAX_LOOP_PANELS).round().astype(int)
        chosen = [chosen[i] for i in sorted(set(picks.tolist()))]
    return chosen


def _reference_loop(study: Results, case: ResultCase):
    """The analytic stabilised loop of a case, or None where it does not apply: Mindlin's
    for a sphere, the cylinder's (``engine.reference.line_contact.line_fretting_loop``)."""
    if not _isotropic_friction(case) or case.mu1 <= 0:
        return None
    load, material = float(_setting(study, case, "loading.load")), _material(study, case)
    force = _setting(study, case, "loading.force_amplitude")
    if force is not None and float(force) >= case.mu1 * load:
        return None
    amplitudes = (
        {"force_amplitude": float(force)}
        if force is not None
        else {"displacement_amplitude": _amplitude(study, case)}
    )
    datum = _setting(study, case, "mesh.reference_distance")
    datum = None if datum is None else float(datum)
    profile = case_profile(study, case)  # its loop: None without a closed form
    return profile.fretting_loop(load, material, case.mu1, datum, **amplitudes)


def _loops_figure(study: Results):
    panels = []
    for case in _loop_cases(study):
        theta = _direction(study, case)
        cosine, sine = np.cos(theta), np.sin(theta)
        loops = {
            cycle: (
                rows[:, 0] * cosine + rows[:, 1] * sine,
                rows[:, 2] * cosine + rows[:, 3] * sine,
            )
            for cycle, rows in read_loops(study.path, case.case_id).items()
        }
        load = float(_setting(study, case, "loading.load"))
        friction = (
            f"μ = {case.mu1:g}"
            if _isotropic_friction(case)
            else f"μ1, μ2 = {case.mu1:g}, {case.mu2:g}, β = {case.beta:g}°"
        )
        title = (
            f"P = {load:g} {study.load_unit}, δ* = {_amplitude(study, case) * 1e3:.3g} µm"
            f"\n{friction}, {_regime(case)} slip"
        )
        reference = _shared.case_reference(study, case)[0]
        label = f"{reference.name if reference else 'analytic'} / gross slip"
        if abs(_material(study, case).coupling) > 1e-12:
            label += " (K ≠ 0: approximate)"
        panels.append(LoopPanel(title, loops, _reference_loop(study, case), label))
    title = f"{study.name}: fretting loops at recorded cycles"
    if any(panel.reference is not None for panel in panels):
        title += "\n(dashed: analytic, unworn surfaces)"
    return draw_fretting_loops(panels, title, study.load_unit)


def _wear_energy_figure(study: Results):
    series = []
    for case in study.completed:
        if "wear_volume" not in case.history or "energy" not in case.history:
            continue
        load = float(_setting(study, case, "loading.load"))
        volume = np.asarray(case.history["wear_volume"], dtype=float)
        coefficient = _energy_coefficient(study, case)
        series.append(
            WearSeries(
                f"P = {load:g} {study.load_unit}",
                cumulated_energy(case),
                volume,
                coefficient,
                _regime(case),
            )
        )
    law = study.study.get("wear", {}).get("law", "archard")
    title = f"{study.name}: wear volume vs dissipated energy ({law} wear law)"
    return draw_wear_energy(series, title, study.profile.is_line)


def fretting_figures(study: Results) -> list[tuple[str, object]]:
    """(file name, figure) of every fretting figure of ``study`` (for one case, ``--case``,
    its field figures: ``engine.analysis.case_fields``; with ``[fatigue]``, the fatigue
    figures too: ``engine.analysis.fatigue_figures``)."""
    return [
        ("fretting_map.png", _map_figure(study)),
        ("fretting_loops.png", _loops_figure(study)),
        ("wear_energy.png", _wear_energy_figure(study)),
        *case_field_figures(study),
        *fatigue_figures(study),
    ]
