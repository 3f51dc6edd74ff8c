"""Plan of a study: the sweep of ``[sweep]`` expanded into cases with stable ids.

Every combination of ``mu1 × mu2 × <wear coefficients> × beta`` is a case (``mu2`` defaults
to ``mu1``; the wear law combines its own coefficients,
:meth:`engine.solvers.wear.WearModel.combinations`: Archard's ``wear2`` defaults to ``wear1``
element-wise, i.e. isotropic laws, and ``wear2 = "proportional"`` gives ``wear1·mu2/mu1``,
paper Section 7.3).

Dotted keys swept in ``[sweep]`` (``"loading.load" = [...]``, ``"mesh.n" = [...]``, any key of
:data:`~engine.study.config.SWEEPABLE`) add axes: the plan is the product of the friction/wear
combinations above with every axis (a ``zip`` group of keys is one axis whose keys vary
together). Axes are the outer loops, in the order of the file.

The case id is built from the parameter values only (never from the position in the sweep), so
adding a value to a list keeps the ids — and the completed results — of every other case::

    mu0.1-0.4_w1.33e-07-5.32e-07_b45
    mu0.1_w1.33e-07_b0_load750_n64        # with "loading.load" and "mesh.n" swept

Each swept key appends ``_<name><value>``, ``name`` being the last part of the dotted key
(the whole key with ``-`` for ``.`` should two swept keys share it); a text value (a swept
``surface.path``, ``surface.detrend`` …) appears as its file name without folder and suffix
(``_pathground`` for ``"maps/ground.npy"``).

Friction coefficients are dimensionless, wear coefficients in 1/MPa, ``beta`` in degrees.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import re
from dataclasses import dataclass
from pathlib import PurePath
from typing import TYPE_CHECKING, Any

from engine.solvers.wear_laws import WEAR_LAWS, fixed_coefficients

from .settings.sections import MISSING as _MISSING
from .settings.sections import StudyConfigError

if TYPE_CHECKING:  # annotations only: the configuration package parses the kinds' sections
    from .config import StudyConfig

__all__ = ["Case", "Plan", "make_plan", "case_id_for", "cost_scale", "setting_names"]


def _format(value: float | int | str) -> str:
    """A value in a case id: an integer as is, a number to 10 significant digits, a text as
    its last path component without its suffix, with every character other than a letter,
    digit, ``_``, ``+`` or ``-`` made ``-`` (``"maps/ground.npy"`` → ``ground``)."""
    if isinstance(value, str):
        return re.sub(r"[^A-Za-z0-9_+-]", "-", PurePath(value).stem) or "-"
    if isinstance(value, int):
        return str(value)
    return format(value, ".10g")


def setting_names(keys: tuple[str, ...]) -> dict[str, str]:
    """Short names of swept dotted keys in case ids: the last part, unless two share it."""
    last = [key.rsplit(".", 1)[-1] for key in keys]
    return {
        key: name if last.count(name) == 1 else key.replace(".", "-")
        for key, name in zip(keys, last, strict=True)
    }


def case_id_for(
    mu1: float, mu2: float, wear: dict[str, float], beta: float, law: str = "archard"
) -> str:
    """Readable id from the parameters: ``mu<mu1>-<mu2>_<wear>_b<beta>``, ``<wear>`` the
    law's part (:meth:`engine.solvers.wear.WearModel.case_id_part`: ``w<wear1>-<wear2>`` for
    Archard, ``a<alpha>`` for the energy law)."""
    mu = f"mu{_format(mu1)}" if mu1 == mu2 else f"mu{_format(mu1)}-{_format(mu2)}"
    part = WEAR_LAWS[law].case_id_part([_format(value) for value in wear.values()])
    return f"{mu}_{part}_b{_format(beta)}"


@dataclass(frozen=True)
class Case:
    """One simulation: friction (μ1, μ2), the wear law's coefficients (``wear``, in the law's
    units: Archard's i1, i2 in 1/MPa), axes angle β (°)."""

    index: int
    case_id: str
    mu1: float
    mu2: float
    wear: tuple[tuple[str, float], ...]
    beta: float
    settings: tuple[tuple[str, Any], ...] = ()  # swept dotted keys and their values
    cost_scale: float = 1.0  # size of the case relative to the study's first values
    mesh: tuple[int, float] | None = None  # (n, half_width mm) of the case's grid
    law: str = "archard"  # the wear law (engine.solvers.wear_laws.WEAR_LAWS)
    line: bool = False  # a line contact: loads, energies, areas, volumes per unit length

    @property
    def coefficients(self) -> dict[str, float]:
        """{coefficient: value} of the case's wear law."""
        return dict(self.wear)

    def parameters(self) -> dict[str, float | int | str]:
        """Case attributes and the parameter columns of its summary row: mu1, mu2, the
        default law's coefficients (0 under another law: every results file has the same
        first columns), beta, then another law's coefficients and the swept keys."""
        wear = self.coefficients
        parameters: dict[str, Any] = {"case_id": self.case_id, "index": self.index}
        parameters.update(mu1=self.mu1, mu2=self.mu2)
        for name in fixed_coefficients():
            parameters[name] = wear.pop(name, 0.0)
        parameters["beta"] = self.beta
        parameters.update(wear)
        parameters.update(self.settings)
        return parameters

    @property
    def expected_cost(self) -> float:
        """Relative cost guess for scheduling: low friction slips more and takes longer
        (more slip, more wear, more simulated cycles); frictionless cases are a single
        normal solve per increment and the cheapest. Times ``cost_scale`` (mesh, steps,
        cycles, layers of swept keys, see :func:`cost_scale`)."""
        friction = min(self.mu1, self.mu2)
        return (0.5 if friction == 0.0 else 1.0 / (0.05 + friction)) * self.cost_scale


@dataclass(frozen=True)
class Plan:
    cases: tuple[Case, ...]

    def __len__(self) -> int:
        return len(self.cases)

    def __iter__(self):
        return iter(self.cases)

    @property
    def case_ids(self) -> tuple[str, ...]:
        return tuple(case.case_id for case in self.cases)

    @property
    def line(self) -> bool:
        """A line contact's plan (results per unit length, :attr:`Case.line`)."""
        return any(case.line for case in self.cases)

    def by_id(self, case_id: str) -> Case:
        for case in self.cases:
            if case.case_id == case_id:
                return case
        raise KeyError(case_id)

    def shared_mesh(self) -> tuple[int, float] | None:
        """(n, half_width) when every case has the same grid, else None."""
        meshes = {case.mesh for case in self.cases}
        return meshes.pop() if len(meshes) == 1 else None

    def dispatch_order(self, skip: set[str] | frozenset[str] = frozenset()) -> list[Case]:
        """Cases still to run, most expensive first (longest-processing-time-first).

        Handing the slow, low-friction cases out first keeps the cheap ones for the end, where
        they fill the gaps; the scheduler is dynamic anyway, this only shortens the tail.
        Ties keep the plan order.
        """
        pending = [case for case in self.cases if case.case_id not in skip]
        return sorted(pending, key=lambda case: (-case.expected_cost, case.index))


def cost_scale(case: StudyConfig, study: StudyConfig) -> float:
    """Cost of a case's configuration relative to the study's (first swept values): an FFT
    operator application grows as n² log n, every increment costs a few of them, the number
    of simulated cycles grows like the logarithm of the real ones (cycle jumps), and each
    subsurface layer costs an FFT pair."""

    def size(config: StudyConfig) -> float:
        n = config.mesh.n
        cycles = config.kind.cycle_cost(config)
        work = n * n * math.log2(n * n) * config.loading.steps * cycles
        return work * (1.0 + 0.05 * config.subsurface.layers)

    return size(case) / size(study)


def _friction_combinations(config: StudyConfig) -> list[tuple]:
    """(mu1, mu2, {wear coefficient: value}, beta) in plan order (nested loops), the wear
    coefficients combined by the study's law."""
    sweep = config.sweep
    law = WEAR_LAWS[sweep.law]
    if sweep.mu2 is None:
        mu_pairs = [(mu, mu) for mu in sweep.mu1]
    else:
        mu_pairs = list(itertools.product(sweep.mu1, sweep.mu2))
    combos = []
    for mu1, mu2 in mu_pairs:
        laws = law.combinations(sweep.wear_lists, mu1, mu2)
        for wear, beta in itertools.product(laws, sweep.beta):
            combos.append((mu1, mu2, wear, beta))
    return combos


def _settings_combinations(config: StudyConfig) -> list[tuple[tuple[str, Any], ...]]:
    """Every combination of the swept axes as ((key, value), ...), first axis outermost."""
    axes = config.sweep.axes
    combos = []
    for positions in itertools.product(*(axis.values for axis in axes)):
        settings = []
        for axis, values in zip(axes, positions, strict=True):
            settings.extend(zip(axis.keys, values, strict=True))
        combos.append(tuple(settings))
    return combos


def make_plan(config: StudyConfig) -> Plan:
    """Expand the sweep into cases (plan order: swept axes, then mu1, mu2, wear1, wear2,
    beta, as nested loops). Every combination of swept values is validated here (exit 2
    before anything is computed), naming the case and its values."""
    names = setting_names(config.sweep.swept_keys)
    cases = []
    seen: dict[str, tuple] = {}
    index = 0
    for settings in _settings_combinations(config):
        try:
            case_config = config.for_case(config.at_search_end(settings))
        except StudyConfigError as error:
            shown = ", ".join(f"{key} = {value!r}" for key, value in settings)
            raise StudyConfigError(
                config.source,
                "sweep",
                _MISSING,
                f"the combination {shown} is invalid: {str(error)[len(error.source) + 2 :]}",
            ) from None
        scale = cost_scale(case_config, config) if settings else 1.0
        mesh = (case_config.mesh.n, case_config.mesh.half_width)
        suffix = "".join(f"_{names[key]}{_format(value)}" for key, value in settings)
        for combo in _friction_combinations(config):
            case_id = case_id_for(*combo, law=config.sweep.law) + suffix
            if case_id in seen:
                first_combo, first_settings = seen[case_id]
                if first_combo != combo:
                    raise _collision(config.source, case_id, first_combo, combo)
                raise _setting_collision(config.source, case_id, first_settings, settings)
            seen[case_id] = (combo, settings)
            mu1, mu2, wear, beta = combo
            line = config.punch.is_line
            case = Case(index, case_id, mu1, mu2, tuple(wear.items()), beta, settings, scale, mesh)
            cases.append(dataclasses.replace(case, law=config.sweep.law, line=line))
            index += 1
    unknown = set(config.testing.fail_cases) - set(seen)
    if unknown:
        raise StudyConfigError(
            config.source, "testing.fail_cases", sorted(unknown), "not a case id of this plan"
        )
    return Plan(tuple(cases))


def _setting_collision(source: str, case_id: str, first: tuple, second: tuple) -> StudyConfigError:
    """Two combinations of swept settings with the same id: name the swept key whose values
    differ only beyond the 10 significant digits of the id."""
    differing = [(key, a, b) for (key, a), (_, b) in zip(first, second, strict=True) if a != b]
    key, a, b = differing[0] if differing else (first[0][0], first[0][1], second[0][1])
    why = (
        "the texts differ only in their folder, suffix or characters other than letters, "
        "digits, _, + and -"
        if isinstance(a, str)
        else "the values differ only beyond 10 significant digits"
    )
    return StudyConfigError(
        source, f"sweep.{key}", [a, b], f"two cases get the same id {case_id!r}: {why}"
    )


def _collision(source: str, case_id: str, first: tuple, second: tuple) -> StudyConfigError:
    """Two combinations with the same id: name the sweep key whose values differ only beyond
    the 10 significant digits of the id."""
    flat = [_flat(combo) for combo in (first, second)]
    keys = [key for key in flat[0] if flat[0][key] != flat[1][key]]
    key = keys[0] if keys else "mu1"
    return StudyConfigError(
        source,
        f"sweep.{key}",
        [flat[0][key], flat[1][key]],
        f"two cases get the same id {case_id!r}: the values differ only beyond 10 "
        "significant digits",
    )


def _flat(combo: tuple) -> dict[str, float]:
    mu1, mu2, wear, beta = combo
    return {"mu1": mu1, "mu2": mu2, **wear, "beta": beta}
