"""Fretting results against the closed forms of their geometry, without plotting:
shared by the report (:mod:`engine.analysis.report`), the figures
(:mod:`engine.analysis.fretting_figures`) and ``scripts/check_fretting_map.py``.

A case of a fretting study (``[loading] kind = "fretting"``) is compared with the closed
forms its punch profile hands out (``engine.geometry.Profile.fretting_reference``, an
:class:`engine.reference.masing.FrettingReference`: Mindlin–Deresiewicz for a sphere, the
cylinder's Cattaneo–Masing loop for a line contact; none for the flat, rounded and pad
profiles) where they apply: isotropic friction μ1 = μ2 = μ > 0 and, for exactness, K = 0
(identical materials). Then

- the slip regime of the first simulated cycle (unworn surfaces) must lie on the side of
  the closed form's δ_slip(P) its amplitude δ* lies on (displacement control) or be partial
  (force control, Q* < μP);
- the energy per cycle of the loop recorded at N = 1 is compared with the closed form's
  (the Masing loop's energy in partial slip, W(μP) + 4μP (δ* − δ_slip) in gross slip), and
  in gross slip (displacement control) and under force control also with the analytic loop
  sampled at the solver's own increments (``FrettingReference.sampled_loop_energy``,
  ``sampled_force_loop_energy``: the load-step error removed);
- Fouvry's energy ratio A = W/(4δ*Q*) with the closed form's;
- under the energy wear law, the wear volume over α times the cumulated dissipated energy
  (1 for Fouvry's linear law).

Units: mm, N, mJ (per cycle), J (cumulated), mm³/J (α); a line contact's loads and
energies are per mm of length (N/mm, mJ/mm).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import h5py
import numpy as np

from engine.geometry import profile_from_table
from engine.material import MaterialPair
from engine.schema import CASES_GROUP

from .results import ResultCase, Results

__all__ = [
    "FrettingCheck",
    "amplitude",
    "case_reference",
    "check_case",
    "cumulated_energy",
    "direction",
    "energy_coefficient",
    "read_loops",
    "regime",
    "setting",
    "slip_boundary",
    "unchecked_reason",
]

K_EXACT = 1e-12  # |K| below which the closed forms are exact (uncoupled materials)
_CYCLE = re.compile(r"cycle_(\d+)$")


def setting(study: Results, case: ResultCase, dotted: str, default=None):
    """A case's value of a dotted key: its swept setting, else the study file's value."""
    if dotted in case.settings:
        return case.settings[dotted]
    section, key = dotted.split(".", 1)
    return study.study.get(section, {}).get(key, default)


def direction(study: Results, case: ResultCase) -> float:
    """The sliding direction θ (rad from x)."""
    return float(np.radians(float(setting(study, case, "loading.direction", 0.0) or 0.0)))


def amplitude(study: Results, case: ResultCase) -> float:
    """The displacement amplitude δ* (mm): prescribed, else the last measured one."""
    prescribed = setting(study, case, "loading.amplitude")
    if prescribed is not None:
        return float(prescribed)
    measured = case.history.get("displacement_amplitude")
    return float(measured[-1]) if measured is not None and len(measured) else float("nan")


def regime(case: ResultCase) -> str:
    """ "partial", "gross" or "mixed" (the per-cycle history holds both regimes)."""
    history = case.history.get("slip_regime")
    if history is not None and len(history):
        values = set(np.asarray(history).astype(int).tolist())
        if values == {0, 1}:
            return "mixed"
        return "gross" if values == {1} else "partial"
    return str(case.summary.get("slip_regime", "partial"))


def slip_boundary(study: Results, case: ResultCase):
    """δ_slip(P) (mm) of the case's geometry as a function of the load P, or None where no
    closed form applies (it needs isotropic friction μ1 = μ2 = μ > 0): Mindlin's
    3μP S/(16a) for a sphere (P in N), the cylinder's (μ p0 a/E*)(ln(2d/a) + 1/2) with the
    study's displacement datum d for a line contact (P in N/mm,
    ``engine.reference.line_contact.line_slip_displacement``)."""
    if case.mu1 != case.mu2 or not case.mu1 > 0:
        return None
    profile, pair, datum = case_profile(study, case), material(study, case), _datum(study, case)
    if profile.slip_displacement(1.0, pair, case.mu1, datum) is None:
        return None  # no closed form for this geometry
    return lambda load: profile.slip_displacement(load, pair, case.mu1, datum)


def case_profile(study: Results, case: ResultCase):
    """The punch profile (engine.geometry) of a case, with its swept values."""
    punch = dict(study.study.get("punch", {}))
    punch.update({key[6:]: v for key, v in case.settings.items() if key.startswith("punch.")})
    return profile_from_table(punch)


def material(study: Results, case: ResultCase) -> MaterialPair:
    return MaterialPair(
        *(float(setting(study, case, f"material.{key}")) for key in ("E_A", "nu_A", "E_B", "nu_B"))
    )


def read_loops(path, case_id: str) -> dict[int, np.ndarray]:
    """Every ``loop`` dataset (rows, 4: δ_x, δ_y in mm, Q_x, Q_y in N, a line contact's
    N/mm) of a case, by cycle N (the nearest enclosing ``cycle_N`` group)."""
    loops: dict[int, np.ndarray] = {}

    def visit(name, item):
        if isinstance(item, h5py.Dataset) and name.rsplit("/", 1)[-1] == "loop":
            cycles = [_CYCLE.match(part) for part in name.split("/")]
            numbers = [int(match.group(1)) for match in cycles if match]
            if numbers:
                loops[numbers[-1]] = np.asarray(item)

    with h5py.File(path, "r") as file:
        group = file[CASES_GROUP][case_id]
        group.visititems(visit)
    return loops


def cumulated_energy(case: ResultCase) -> np.ndarray:
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


def energy_coefficient(study: Results, case: ResultCase) -> float | None:
    """The energy law's α (mm³/J) of a case; None under Archard's law."""
    if study.study.get("wear", {}).get("law", "archard") != "energy":
        return None
    for source in (case.settings, case.summary):
        for key in ("alpha", "sweep.alpha", "wear.alpha"):
            if key in source:
                return float(source[key])
    sweep = study.study.get("sweep", {}).get("alpha")
    if isinstance(sweep, list):
        return float(sweep[0]) if len(sweep) == 1 else None
    return None if sweep is None else float(sweep)


def _datum(study: Results, case: ResultCase) -> float | None:
    """A line contact's displacement datum d (mm, ``[mesh] reference_distance``); None in 3-D."""
    datum = setting(study, case, "mesh.reference_distance")
    return None if datum is None else float(datum)


def case_reference(study: Results, case: ResultCase):
    """(the case's closed forms, "") or (None, why there are none): its profile's
    :class:`~engine.reference.masing.FrettingReference` at the case's load and μ, which needs
    a fretting history, isotropic friction μ1 = μ2 = μ > 0, a profile with closed forms and,
    under force control, Q* < μP."""
    if "energy" not in case.history:
        return None, "no fretting history"
    if case.mu1 != case.mu2:
        return None, "orthotropic friction"
    if not case.mu1 > 0:
        return None, "μ = 0"
    profile, load = case_profile(study, case), float(setting(study, case, "loading.load"))
    reference = profile.fretting_reference(
        load, material(study, case), case.mu1, _datum(study, case)
    )
    if reference is None:
        return None, f"no closed form for the {profile.name} profile"
    force = setting(study, case, "loading.force_amplitude")
    if force is not None and float(force) >= reference.limit:
        return None, "Q* ≥ μP"
    return reference, ""


def unchecked_reason(study: Results, case: ResultCase) -> str:
    """Why :func:`check_case` has no check for the case ("" when it has one)."""
    return case_reference(study, case)[1]


@dataclass
class FrettingCheck:
    """One case against its closed forms (module docstring). ``reference``: whose
    (``FrettingReference.name``); ``expected``/``computed``: regime of the first simulated
    cycle; ``energy``: the computed energy per cycle (mJ, mJ/mm for a line contact) at N = 1
    (the first history row without a cycle-1 row), ``exact`` the closed form's, ``sampled``
    the analytic loop at the solver's increments (its displacements in gross slip under
    displacement control, its forces under force control; NaN otherwise); ``ratio``:
    δ*/δ_slip (displacement control) or Q*/μP (force control); ``exact_coupling``: K = 0;
    ``energy_ratio``: Fouvry's A = W/(4δ*Q*) at N = 1 with the prescribed δ*, and
    ``exact_energy_ratio`` the closed form's (displacement control; NaN otherwise)."""

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
    exact_energy_ratio: float = math.nan  # the closed form's at δ*
    reference: str = ""  # whose closed forms

    @property
    def regime_holds(self) -> bool:
        return self.expected == self.computed

    @property
    def energy_error(self) -> float:
        return self.energy / self.exact - 1.0 if self.exact > 0 else math.nan

    @property
    def sampled_error(self) -> float:
        return self.energy / self.sampled - 1.0 if self.sampled > 0 else math.nan


def _first_row(case: ResultCase) -> int:
    """History row of the loop recorded at N = 1 (row 0 when there is no cycle-1 row)."""
    cycles = np.asarray(case.history.get("cycle", []))
    hits = np.flatnonzero(cycles == 1)
    return int(hits[0]) if hits.size else 0


def check_case(study: Results, case: ResultCase) -> FrettingCheck | None:
    """The case against its profile's closed forms, or None where there are none
    (:func:`unchecked_reason` says why: not a profile with closed forms, orthotropic
    friction, μ = 0, Q* ≥ μP, no history)."""
    reference, _ = case_reference(study, case)
    if reference is None:
        return None
    row = _first_row(case)
    energy = float(case.history["energy"][row])
    computed = "gross" if int(case.history["slip_regime"][row]) == 1 else "partial"
    exact_coupling = abs(material(study, case).coupling) < K_EXACT
    force = setting(study, case, "loading.force_amplitude")
    loop = case.fields.get(int(case.history["cycle"][row]), {}).get("loop")
    if loop is not None:  # δ and Q along the sliding direction
        theta = direction(study, case)
        rows = np.asarray(loop)
        delta = rows[:, 0] * np.cos(theta) + rows[:, 1] * np.sin(theta)
        forces = rows[:, 2] * np.cos(theta) + rows[:, 3] * np.sin(theta)
    if force is not None:
        exact = reference.partial_slip_energy(float(force))
        sampled = math.nan
        if loop is not None:
            sampled = reference.sampled_force_loop_energy(forces, float(force))
        return FrettingCheck(
            case.case_id, "force", float(force) / reference.limit, "partial", computed, energy,
            exact, sampled, exact_coupling, reference=reference.name,
        )  # fmt: skip
    delta_star = amplitude(study, case)
    ratio = delta_star / reference.slip_displacement
    expected = "gross" if ratio > 1.0 else "partial"
    check = FrettingCheck(
        case.case_id, "displacement", ratio, expected, computed, energy,
        reference.energy_per_cycle(delta_star), math.nan, exact_coupling,
        reference=reference.name,
    )  # fmt: skip
    denominator = 4.0 * delta_star * float(case.history["q_amplitude"][row])
    if denominator > 0:
        check.energy_ratio = energy / denominator
        check.exact_energy_ratio = reference.energy_ratio(delta_star)
    if expected == "gross" and loop is not None:
        check.sampled = reference.sampled_loop_energy(delta, delta_star)
    return check


def wear_energy_ratios(study: Results, case: ResultCase) -> np.ndarray:
    """V/(α E_d) over the history rows after the first (energy law; empty otherwise)."""
    alpha = energy_coefficient(study, case)
    if not alpha or "wear_volume" not in case.history:
        return np.zeros(0)
    cumulated = cumulated_energy(case)[1:]
    volume = np.asarray(case.history["wear_volume"], dtype=float)[1:]
    keep = cumulated > 0
    return volume[keep] / (alpha * cumulated[keep])
