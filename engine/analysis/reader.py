"""A study's results in memory, as the figures and the report use them.

The file is read through the public reading layer (:func:`engine.open_results`,
:mod:`engine.analysis.results`: the one place that knows the layout of
:mod:`engine.schema`); :func:`read_results` loads every completed case's values into plain
arrays and adds what the analyses need: the normalisations of the paper (a0 = punch radius,
p0 = P/(π a0²), Eq. 19), the study's profile and material, case labels and the stress
planes' peaks. Units as stored: mm, N, MPa. The other cases are listed in
``StudyResults.skipped``. Nothing here writes.
"""

from __future__ import annotations

import copy
import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from engine.geometry import profile_from_table
from engine.material import MaterialPair
from engine.output.summary import column_unit
from engine.schema import CaseStatus, contact_units
from engine.study.kinds import KINDS

from .names import value_text
from .results import Records, ResultCase, VariableGroup, open_results

__all__ = ["CaseResults", "StressPlane", "StudyResults", "read_results"]


@dataclass
class StressPlane:
    """Von Mises stress on the vertical plane through the punch axis at ``angle`` φ (degrees
    from x; 0: the x–z plane y = 0, the default; a fretting case's plane contains its sliding
    direction, attribute ``plane_angle`` of its datasets).

    ``x``, ``y``, ``z``: coordinates (mm), shape ``(n_s, n_z)``, z into the half-space (``y``
    None: zeros); ``von_mises`` (MPa), same shape. ``s`` = x cos φ + y sin φ: the signed
    distance along the plane (= x on the x–z plane). ``depths``: the evaluated depths (mm);
    ``depths[0]`` is the surface layer (see :func:`engine.solvers.subsurface.depth_layers`).
    """

    x: np.ndarray
    z: np.ndarray
    von_mises: np.ndarray
    y: np.ndarray | None = None
    angle: float = 0.0

    @property
    def depths(self) -> np.ndarray:
        return self.z[0]

    @property
    def s(self) -> np.ndarray:
        """Signed along-plane coordinate (mm); exactly ``x`` on the x–z plane."""
        if self.angle == 0.0 or self.y is None:
            return self.x
        phi = np.radians(self.angle)
        return self.x * np.cos(phi) + self.y * np.sin(phi)

    def _index(self, min_depth: float):
        candidates = np.where(self.z >= min_depth, self.von_mises, -np.inf)
        return np.unravel_index(np.argmax(candidates), candidates.shape)

    def on_edge(self, min_depth: float = 0.0) -> str:
        """Where the largest σ_VM over z >= ``min_depth`` touches the computed domain's
        boundary: "side" (the plane's outermost column, the mesh's edge), "bottom" (its
        deepest layer) or "" (inside). A peak there may lie beyond the domain: the real
        maximum is not known (widen ``[mesh] half_width`` or deepen ``[subsurface] depth``)."""
        column, layer = self._index(min_depth)
        places = []
        if column in (0, self.von_mises.shape[0] - 1):
            places.append("side")
        if layer == self.von_mises.shape[1] - 1:
            places.append("bottom")
        return " and ".join(places)

    def peak(self, min_depth: float = 0.0) -> tuple[float, float, float]:
        """(σ_VM, s, z) of the largest von Mises stress over the points with z >= min_depth
        (s: along the plane, = x on the x–z plane)."""
        index = self._index(min_depth)
        return float(self.von_mises[index]), float(self.s[index]), float(self.z[index])

    def peak_point(self, min_depth: float = 0.0) -> tuple[float, float, float, float]:
        """(σ_VM, x, y, z) of the largest von Mises stress over the points with z >= min_depth."""
        index = self._index(min_depth)
        y = 0.0 if self.y is None else float(self.y[index])
        return float(self.von_mises[index]), float(self.x[index]), y, float(self.z[index])

    def axis_peak(self) -> tuple[float, float, float]:
        """(σ_VM, s, z) of the largest von Mises stress on the punch axis (the column s ≈ 0)."""
        along = self.s
        column = int(np.argmin(np.abs(along[:, 0])))
        depth = int(np.argmax(self.von_mises[column]))
        return (
            float(self.von_mises[column, depth]),
            float(along[column, depth]),
            float(self.z[column, depth]),
        )

    def subsurface_peak(self) -> tuple[float, float, float]:
        """Peak over the layers strictly below the surface layer (z >= depths[1])."""
        depths = self.depths
        return self.peak(float(depths[1]) if len(depths) > 1 else 0.0)


@dataclass
class CaseResults:
    """One completed case: parameters, summary row, histories, surface fields, stress planes
    and, with ``[fatigue]``, the criteria's maps and hot spots per recorded cycle
    (``fatigue[N][name]``, names of ``engine.schema.fatigue_maps``).

    ``fields[key][name]`` and ``planes[key]`` use the key ``"final"`` or the recorded cycle
    number N (int). Field arrays have shape ``(n_x, n_y)`` (ij indexing, as ``grid_x, grid_y``).
    """

    case_id: str
    index: int
    mu1: float
    mu2: float
    wear1: float
    wear2: float
    beta: float
    summary: dict[str, Any]
    history: dict[str, np.ndarray] = field(default_factory=dict)
    fields: dict[Any, dict[str, np.ndarray]] = field(default_factory=dict)
    planes: dict[Any, StressPlane] = field(default_factory=dict)
    change_planes: dict[int, StressPlane] = field(default_factory=dict)  # peak_changes/, by N
    fatigue: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)  # fatigue/, by N
    settings: dict[str, Any] = field(default_factory=dict)  # swept dotted keys -> values
    parameter_units: dict[str, str] = field(default_factory=dict)  # as stored in the file

    @property
    def isotropic(self) -> bool:
        return self.mu1 == self.mu2 and self.wear1 == self.wear2

    @property
    def label(self) -> str:
        """Short name of the case for legends and titles (μ, and μ2, β when orthotropic, and
        every other swept key with its unit)."""

        def unit(key: str) -> str:  # the file's unit (a line contact's per unit length)
            stored = self.parameter_units.get(key, "1")
            return column_unit(key) if stored == "1" else stored

        swept = "".join(
            f", {key.rsplit('.', 1)[-1]} = {value_text(value)}"
            + (f" {unit(key)}" if unit(key) else "")
            for key, value in self.settings.items()
        )
        if self.isotropic:
            text = f"μ = {self.mu1:g}"
            return text + (f", β = {self.beta:g}°" if self.beta else "") + swept
        return f"μ1 = {self.mu1:g}, μ2 = {self.mu2:g}, β = {self.beta:g}°" + swept

    @property
    def recorded_cycles(self) -> list[int]:
        return sorted(key for key in self.fields if isinstance(key, int))

    def history_at(self, name: str, cycle: int) -> float:
        """History value ``name`` after exactly ``cycle`` real cycles (NaN if not simulated)."""
        cycles = self.history.get("cycle")
        if cycles is None:
            return float("nan")
        hits = np.flatnonzero(np.asarray(cycles) == cycle)
        return float(self.history[name][hits[-1]]) if len(hits) else float("nan")


@dataclass
class StudyResults:
    """A study's results file in memory."""

    path: Path
    name: str
    config: dict[str, Any]
    grid_x: np.ndarray
    grid_y: np.ndarray
    cases: list[CaseResults]
    skipped: list[tuple[str, str]] = field(default_factory=list)

    @property
    def kind(self):
        """The study's loading kind (:data:`engine.study.kinds.KINDS`)."""
        return KINDS[self.config["loading"]["kind"]]

    def kind_hook(self, name: str):
        """The analysis function the loading kind names for ``name`` ("report",
        "figures"): its ``"module:function"`` attribute, imported now."""
        module, _, function = getattr(self.kind, name).partition(":")
        return getattr(importlib.import_module(module), function)

    @property
    def is_cyclic(self) -> bool:
        """The radial cyclic kind (``kind = "cyclic"``); fretting studies: :attr:`is_fretting`."""
        return self.config["loading"]["kind"] == "cyclic"

    @property
    def is_fretting(self) -> bool:
        """Tangential fretting (``kind = "fretting"``): load cycles and wear too."""
        return self.config["loading"]["kind"] == "fretting"

    @property
    def swept_keys(self) -> list[str]:
        """Dotted keys swept in ``[sweep]`` ("loading.load", "mesh.n", …), file order."""
        return [key for key in self.config.get("sweep", {}) if "." in key]

    @property
    def load_unit(self) -> str:
        """Unit of the load and the tangential force: N (a line contact's: N/mm)."""
        return self.profile.load_unit

    def per_contact(self, unit: str) -> str:
        """``unit`` (N, mJ, mm³ …) in this study's contact: a line contact's forces,
        energies, areas and volumes per unit length (:func:`engine.schema.contact_units`)."""
        return contact_units(unit, self.profile.is_line)

    @property
    def profile(self):
        """The punch profile (:data:`engine.geometry.PROFILES`) of the study."""
        return profile_from_table(self.config["punch"])

    @property
    def radius(self) -> float:
        """a0 (mm), the profile's contact length at the load: the punch radius (rounded: of
        the flat face); for a sphere, Hertz's contact radius; for a line contact the nominal
        half-width (the summary's p0 uses the same a0)."""
        return float(self.profile.contact_length(self.load, self.material.contact_modulus))

    @property
    def load(self) -> float:
        """Peak normal load P (N)."""
        return float(self.config["loading"]["load"])

    @property
    def p0(self) -> float:
        """The summary's mean pressure p0 (MPa): P/(π a0²), Eq. (19); a line contact's
        P/(2 a0)."""
        return float(self.profile.mean_pressure(self.load, self.radius))

    @property
    def material(self) -> MaterialPair:
        m = self.config["material"]
        return MaterialPair(m["E_A"], m["nu_A"], m["E_B"], m["nu_B"])

    @property
    def mesh_label(self) -> str:
        n = self.config["mesh"]["n"]
        if self.profile.is_line:
            return f"{n} elements along x"  # a line contact (plane strain)
        return f"{n}×{n} mesh"

    @property
    def isotropic(self) -> bool:
        return all(case.isotropic for case in self.cases)

    def for_case(self, case_id: str) -> StudyResults:
        """The study reduced to the completed case ``case_id``, with that case's values of the
        swept dotted keys in ``config`` (so a0, P, p0 and the mesh are its own) and its grid.

        Raises ValueError naming the case and the completed ones when it is not among them.
        """
        chosen = [case for case in self.cases if case.case_id == case_id]
        if not chosen:
            skipped = dict(self.skipped)
            why = f"its status is {skipped[case_id]!r}" if case_id in skipped else "no such case"
            known = ", ".join(case.case_id for case in self.cases[:8])
            more = ", …" if len(self.cases) > 8 else ""
            raise ValueError(
                f"{self.path}: case {case_id!r} cannot be plotted ({why}); completed cases: "
                f"{known}{more}"
            )
        config = copy.deepcopy(self.config)
        for key, value in chosen[0].settings.items():
            section, name = key.split(".", 1)
            config.setdefault(section, {})[name] = value
            config.get("sweep", {}).pop(key, None)
        grid = open_results(self.path)[case_id].grid
        grid_x, grid_y = (
            (grid["x"].values, grid["y"].values) if grid else (self.grid_x, self.grid_y)
        )
        return StudyResults(
            path=self.path, name=f"{self.name} {case_id}", config=config, grid_x=grid_x,
            grid_y=grid_y, cases=chosen,
        )  # fmt: skip


def read_results(path: str | Path) -> StudyResults:
    """Load every completed case of the results file ``path`` (read by
    :func:`engine.open_results`); the other cases by id in ``skipped``."""
    with open_results(path) as results:
        grid = results.grid
        cases = [_case(case) for case in results.completed]
    return StudyResults(
        path=results.path,
        name=results.name,
        config=results.study,
        grid_x=grid["x"].values if "x" in grid else np.zeros(0),
        grid_y=grid["y"].values if "y" in grid else np.zeros(0),
        cases=cases,
        skipped=sorted(
            (case_id, status)
            for case_id, status in results.statuses.items()
            if status != CaseStatus.COMPLETED
        ),
    )


def _case(case: ResultCase) -> CaseResults:
    """A completed case's values in memory."""
    parameters = case.parameters
    return CaseResults(
        case_id=case.case_id,
        index=case.index,
        mu1=float(parameters["mu1"]),
        mu2=float(parameters["mu2"]),
        wear1=float(parameters["wear1"]),
        wear2=float(parameters["wear2"]),
        beta=float(parameters["beta"]),
        summary=case.summary,
        history=_values(case.history),
        fields={key: _values(group) for key, group in case.fields.items()},
        planes=_planes(case.planes),
        change_planes=_planes(case.peak_changes),
        fatigue={key: _values(group) for key, group in case.fatigue.items()},
        settings={key: value for key, value in parameters.items() if "." in key},
        parameter_units=dict(case.parameter_units),
    )


def _values(group: VariableGroup) -> dict[str, np.ndarray]:
    return {name: variable.values for name, variable in group.items()}


def _planes(records: Records) -> dict[Any, StressPlane]:
    """The stored planes by instant; each one's angle (degrees) from its ``plane_angle``
    attribute (absent: 0)."""
    return {
        key: StressPlane(
            x=group["x"].values,
            z=group["z"].values,
            von_mises=group["von_mises"].values,
            y=group["y"].values if "y" in group else None,
            angle=float(group.attrs["plane_angle"]),
        )
        for key, group in records.items()
    }
