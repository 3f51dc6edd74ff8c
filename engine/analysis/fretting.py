"""Fretting results against Mindlin, without plotting (issue 13): shared by the report
(:mod:`engine.analysis.report`), the figures (:mod:`engine.analysis.fretting_figures`) and
``scripts/check_fretting_map.py``.

A case of a fretting study (``[loading] kind = "fretting"``) is compared with the analytic
references of :mod:`engine.reference.mindlin` where they apply: a sphere, isotropic friction
μ1 = μ2 = μ > 0 and, for exactness, K = 0 (identical materials). Then

- the slip regime of the first simulated cycle (unworn surfaces) must lie on the side of
  Mindlin's δ_slip(P) = 3μP S/(16a) its amplitude δ* lies on (displacement control) or be
  partial (force control, Q* < μP);
- the energy per cycle of the loop recorded at N = 1 is compared with the exact
  Mindlin–Deresiewicz energy (partial slip) or the gross-slip energy 0.8 μP δ_slip +
  4μP (δ* − δ_slip), and in gross slip also with the analytic loop sampled at the solver's own
  increments (:func:`sampled_loop_energy`: the load-step error removed);
- under the energy wear law, the wear volume over α times the cumulated dissipated energy
  (1 for Fouvry's linear law).

Units: mm, N, mJ (per cycle), J (cumulated), mm³/J (α).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import h5py
import numpy as np

from engine.material import MaterialPair
from engine.reference import mindlin

from .reader import CaseResults, StudyResults

__all__ = [
    "MindlinCheck",
    "amplitude",
    "check_case",
    "cumulated_energy",
    "direction",
    "energy_coefficient",
    "read_loops",
    "regime",
    "sampled_loop_energy",
    "setting",
    "slip_boundary",
]

K_EXACT = 1e-12  # |K| below which Mindlin's references are exact (uncoupled materials)
_CYCLE = re.compile(r"cycle_(\d+)$")


def setting(study: StudyResults, case: CaseResults, dotted: str, default=None):
    """A case's value of a dotted key: its swept setting, else the study file's value."""
    if dotted in case.settings:
        return case.settings[dotted]
    section, key = dotted.split(".", 1)
    return study.config.get(section, {}).get(key, default)


def direction(study: StudyResults, case: CaseResults) -> float:
    """The sliding direction θ (rad from x)."""
    return float(np.radians(float(setting(study, case, "loading.direction", 0.0) or 0.0)))


def amplitude(study: StudyResults, case: CaseResults) -> float:
    """The displacement amplitude δ* (mm): prescribed, else the last measured one."""
    prescribed = setting(study, case, "loading.amplitude")
    if prescribed is not None:
        return float(prescribed)
    measured = case.history.get("displacement_amplitude")
    return float(measured[-1]) if measured is not None and len(measured) else float("nan")


def regime(case: CaseResults) -> str:
    """ "partial", "gross" or "mixed" (the per-cycle history holds both regimes)."""
    history = case.history.get("slip_regime")
    if history is not None and len(history):
        values = set(np.asarray(history).astype(int).tolist())
        if values == {0, 1}:
            return "mixed"
        return "gross" if values == {1} else "partial"
    return str(case.summary.get("slip_regime", "partial"))


def sphere_radius(study: StudyResults, case: CaseResults) -> float | None:
    """The sphere's radius R (mm) for the Hertz–Mindlin references, None for other shapes."""
    from engine.geometry import PROFILES, SphericalPunch

    if PROFILES.get(setting(study, case, "punch.shape")) is not SphericalPunch:
        return None
    return float(setting(study, case, "punch.radius"))


def slip_boundary(study: StudyResults, case: CaseResults):
    """δ_slip(P) (mm) of the case's geometry as a function of the load P, or None where no
    closed form applies (it needs isotropic friction μ1 = μ2 = μ > 0): Mindlin's
    3μP S/(16a) for a sphere (P in N), the cylinder's (μ p0 a/E*)(ln(2d/a) + 1/2) with the
    study's displacement datum d for a line contact (P in N/mm,
    ``engine.reference.line_contact.line_slip_displacement``)."""
    if case.mu1 != case.mu2 or not case.mu1 > 0:
        return None
    profile, pair = case_profile(study, case), material(study, case)
    datum = setting(study, case, "mesh.reference_distance")
    datum = None if datum is None else float(datum)
    if profile.slip_displacement(1.0, pair, case.mu1, datum) is None:
        return None  # no closed form for this geometry
    return lambda load: profile.slip_displacement(load, pair, case.mu1, datum)


def case_profile(study: StudyResults, case: CaseResults):
    """The punch profile (engine.geometry) of a case, with its swept values."""
    from engine.geometry import profile_for

    edge = setting(study, case, "punch.edge_radius")
    return profile_for(
        setting(study, case, "punch.shape", "flat"),
        float(setting(study, case, "punch.radius")),
        None if edge is None else float(edge),
    )


def material(study: StudyResults, case: CaseResults) -> MaterialPair:
    return MaterialPair(
        *(float(setting(study, case, f"material.{key}")) for key in ("E_A", "nu_A", "E_B", "nu_B"))
    )


def read_loops(path, case_id: str) -> dict[int, np.ndarray]:
    """Every ``loop`` dataset (rows, 4: δ_x, δ_y in mm, Q_x, Q_y in N) of a case, by cycle N
    (the nearest enclosing ``cycle_N`` group)."""
    loops: dict[int, np.ndarray] = {}

    def visit(name, item):
        if isinstance(item, h5py.Dataset) and name.rsplit("/", 1)[-1] == "loop":
            cycles = [_CYCLE.match(part) for part in name.split("/")]
            numbers = [int(match.group(1)) for match in cycles if match]
            if numbers:
                loops[numbers[-1]] = np.asarray(item)

    with h5py.File(path, "r") as file:
        group = file["cases"][case_id]
        group.visititems(visit)
    return loops


def cumulated_energy(case: CaseResults) -> np.ndarray:
    """Cumulated dissipated energy E_d (J) at each history row, the companion of the row's
    ``wear_volume``.

    Row k holds the wear after N_k real cycles and the loop simulated from there, which the
    cycle jump applies to the cycles N_k + 1 … N_(k+1) (engine.solvers.cyclic): so
    E_d(N_k) = Σ_(j<k) e_j (N_(j+1) − N_j) with the per-cycle energy e_j (mJ) of row j.
    ``history/cumulated_energy`` (mJ) is used instead if the solver wrote it.
    """
    history = case.history
    if "cumulated_energy" in history:
        return np.asarray(history["cumulated_energy"], dtype=float) / 1e3
    cycles = np.asarray(history["cycle"], dtype=float)
    energy = np.asarray(history["energy"], dtype=float)
    steps = energy[:-1] * np.diff(cycles)
    return np.concatenate([[0.0], np.cumsum(steps)]) / 1e3


def energy_coefficient(study: StudyResults, case: CaseResults) -> float | None:
    """The energy law's α (mm³/J) of a case; None under Archard's law."""
    if study.config.get("wear", {}).get("law", "archard") != "energy":
        return None
    for source in (case.settings, case.summary):
        for key in ("alpha", "sweep.alpha", "wear.alpha"):
            if key in source:
                return float(source[key])
    sweep = study.config.get("sweep", {}).get("alpha")
    if isinstance(sweep, list):
        return float(sweep[0]) if len(sweep) == 1 else None
    return None if sweep is None else float(sweep)


def sampled_loop_energy(delta, amplitude, reference_args) -> float:
    """∮ Q dδ (mJ) of the analytic loop sampled at the solver's displacements ``delta`` (mm),
    unloading on the first half of the rows, reloading on the second (trapezoidal rule).

    ``reference_args`` = (P in N, R in mm, material, μ) as for engine.reference.mindlin."""
    limit = reference_args[-1] * reference_args[0]
    peak = float(mindlin.force_amplitude(amplitude, *reference_args))

    def unloading(x):
        return np.maximum(
            peak - 2 * mindlin.tangential_force((amplitude - x) / 2, *reference_args), -limit
        )

    half = len(delta) // 2
    force = np.concatenate([unloading(delta[: half + 1]), -unloading(-delta[half + 1 :])])
    return float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(delta)))


@dataclass
class MindlinCheck:
    """One case against Mindlin (module docstring). ``expected``/``computed``: regime of the
    first simulated cycle; ``energy``: the computed energy per cycle (mJ) at N = 1 (the first
    history row without a cycle-1 row), ``exact`` Mindlin's, ``sampled`` the analytic loop at
    the solver's increments (gross slip, displacement control; NaN otherwise); ``ratio``:
    δ*/δ_slip (displacement control) or Q*/μP (force control); ``exact_coupling``: K = 0;
    ``energy_ratio``: Fouvry's A = W/(4δ*Q*) at N = 1 with the prescribed δ*, and
    ``exact_energy_ratio`` Mindlin's (displacement control; NaN otherwise)."""

    case_id: str
    control: str  # "displacement" | "force"
    ratio: float
    expected: str
    computed: str
    energy: float
    exact: float
    sampled: float = math.nan
    exact_coupling: bool = True
    energy_ratio: float = math.nan  # Fouvry's A = W/(4δ*Q*) at N = 1 (displacement control)
    exact_energy_ratio: float = math.nan  # Mindlin's master curve at δ*/δ_slip

    @property
    def regime_holds(self) -> bool:
        return self.expected == self.computed

    @property
    def energy_error(self) -> float:
        return self.energy / self.exact - 1.0 if self.exact > 0 else math.nan

    @property
    def sampled_error(self) -> float:
        return self.energy / self.sampled - 1.0 if self.sampled > 0 else math.nan


def _first_row(case: CaseResults) -> int:
    """History row of the loop recorded at N = 1 (row 0 when there is no cycle-1 row)."""
    cycles = np.asarray(case.history.get("cycle", []))
    hits = np.flatnonzero(cycles == 1)
    return int(hits[0]) if hits.size else 0


def check_case(study: StudyResults, case: CaseResults) -> MindlinCheck | None:
    """The case against Mindlin, or None where Mindlin does not apply (not a sphere,
    orthotropic friction, μ = 0, Q* ≥ μP, no history)."""
    radius = sphere_radius(study, case)
    if radius is None or case.mu1 != case.mu2 or case.mu1 <= 0 or "energy" not in case.history:
        return None
    load, pair = float(setting(study, case, "loading.load")), material(study, case)
    arguments = (load, radius, pair, case.mu1)
    row = _first_row(case)
    energy = float(case.history["energy"][row])
    computed = "gross" if int(case.history["slip_regime"][row]) == 1 else "partial"
    exact_coupling = abs(pair.coupling) < K_EXACT
    force = setting(study, case, "loading.force_amplitude")
    if force is not None:
        ratio = float(force) / (case.mu1 * load)
        if ratio >= 1.0:
            return None
        exact = float(mindlin.partial_slip_energy(float(force), *arguments))
        return MindlinCheck(
            case.case_id, "force", ratio, "partial", computed, energy, exact, math.nan,
            exact_coupling,
        )  # fmt: skip
    delta_star = amplitude(study, case)
    ratio = delta_star / float(mindlin.slip_displacement(*arguments))
    expected = "gross" if ratio > 1.0 else "partial"
    exact = float(mindlin.energy_per_cycle(delta_star, *arguments))
    check = MindlinCheck(
        case.case_id, "displacement", ratio, expected, computed, energy, exact, math.nan,
        exact_coupling,
    )  # fmt: skip
    denominator = 4.0 * delta_star * float(case.history["q_amplitude"][row])
    if denominator > 0:
        check.energy_ratio = energy / denominator
        check.exact_energy_ratio = float(mindlin.energy_ratio(ratio))
    loop = case.fields.get(int(case.history["cycle"][row]), {}).get("loop")
    if expected == "gross" and loop is not None:
        theta = direction(study, case)  # δ along the sliding direction
        delta = np.asarray(loop)[:, 0] * np.cos(theta) + np.asarray(loop)[:, 1] * np.sin(theta)
        check.sampled = sampled_loop_energy(delta, delta_star, arguments)
    return check


def wear_energy_ratios(study: StudyResults, case: CaseResults) -> np.ndarray:
    """V/(α E_d) over the history rows after the first (energy law; empty otherwise)."""
    alpha = energy_coefficient(study, case)
    if not alpha or "wear_volume" not in case.history:
        return np.zeros(0)
    cumulated = cumulated_energy(case)[1:]
    volume = np.asarray(case.history["wear_volume"], dtype=float)[1:]
    keep = cumulated > 0
    return volume[keep] / (alpha * cumulated[keep])
