"""Plan of a study: the sweep of ``[sweep]`` expanded into cases with stable ids.

Every combination of ``mu1 × mu2 × wear1 × wear2 × beta`` is a case (``mu2`` defaults to
``mu1`` and ``wear2`` to ``wear1`` element-wise, i.e. isotropic laws; ``wear2 =
"proportional"`` gives ``wear1·mu2/mu1``, paper Section 7.3).

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

import itertools
import math
import re
from dataclasses import dataclass
from pathlib import PurePath
from typing import TYPE_CHECKING, Any

from engine.schema import CASE_PARAMETERS

from .settings.sections import MISSING as _MISSING
from .settings.sections import PROPORTIONAL, StudyConfigError

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
    mu1: float, mu2: float, wear1: float, wear2: float, beta: float, alpha: float | None = None
) -> str:
    """Readable id from the parameters: ``mu<mu1>-<mu2>_w<wear1>-<wear2>_b<beta>`` (Archard
    law) or ``mu<mu1>-<mu2>_a<alpha>_b<beta>`` (energy law, ``alpha`` given)."""
    mu = f"mu{_format(mu1)}" if mu1 == mu2 else f"mu{_format(mu1)}-{_format(mu2)}"
    if alpha is not None:
        wear = f"a{_format(alpha)}"
    elif wear1 == wear2:
        wear = f"w{_format(wear1)}"
    else:
        wear = f"w{_format(wear1)}-{_format(wear2)}"
    return f"{mu}_{wear}_b{_format(beta)}"


@dataclass(frozen=True)
class Case:
    """One simulation: friction (μ1, μ2), wear coefficients (i1, i2, 1/MPa), axes angle β (°)."""

    index: int
    case_id: str
    mu1: float
    mu2: float
    wear1: float
    wear2: float
    beta: float
    settings: tuple[tuple[str, Any], ...] = ()  # swept dotted keys and their values
    cost_scale: float = 1.0  # size of the case relative to the study's first values
    mesh: tuple[int, float] | None = None  # (n, half_width mm) of the case's grid
    alpha: float | None = None  # energy wear law (mm³/J), its own parameter; wear1 = wear2 = 0
    line: bool = False  # a line contact: loads, energies, areas, volumes per unit length

    def parameters(self) -> dict[str, float | int | str]:
        """Case attributes and the parameter columns of its summary row."""
        parameters: dict[str, Any] = {
            "case_id": self.case_id,
            "index": self.index,
            "mu1": self.mu1,
            "mu2": self.mu2,
            "wear1": self.wear1,
            "wear2": self.wear2,
            "beta": self.beta,
        }
        if self.alpha is not None:
            parameters["alpha"] = self.alpha
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
    """(mu1, mu2, wear1, wear2, beta, alpha) in plan order (nested loops): the Archard law's
    coefficients with alpha None, or the energy law's alpha (mm³/J) with wear1 = wear2 = 0."""
    sweep = config.sweep
    if sweep.mu2 is None:
        mu_pairs = [(mu, mu) for mu in sweep.mu1]
    else:
        mu_pairs = list(itertools.product(sweep.mu1, sweep.mu2))
    combos = []
    for mu1, mu2 in mu_pairs:
        if sweep.alpha is not None:  # the energy law: one coefficient, Archard's i1 = i2 = 0
            laws = [(0.0, 0.0, alpha) for alpha in sweep.alpha]
        elif sweep.wear2 is None:
            laws = [(w, w, None) for w in sweep.wear1]
        elif sweep.wear2 == PROPORTIONAL:
            laws = [(w, w * mu2 / mu1, None) for w in sweep.wear1]
        else:
            laws = [(w1, w2, None) for w1, w2 in itertools.product(sweep.wear1, sweep.wear2)]
        for (wear1, wear2, alpha), beta in itertools.product(laws, sweep.beta):
            combos.append((mu1, mu2, wear1, wear2, beta, alpha))
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
            case_id = case_id_for(*combo) + suffix
            if case_id in seen:
                first_combo, first_settings = seen[case_id]
                if first_combo != combo:
                    raise _collision(config.source, case_id, first_combo, combo)
                raise _setting_collision(config.source, case_id, first_settings, settings)
            seen[case_id] = (combo, settings)
            *friction, alpha = combo
            line = config.punch.is_line
            cases.append(Case(index, case_id, *friction, settings, scale, mesh, alpha, line))
            index += 1
    unknown = set(config.testing.fail_cases) - set(seen)
    if unknown:
        raise StudyConfigError(
            config.source, "testing.fail_cases", sorted(unknown), "not a case id of this plan"
        )
    return Plan(tuple(cases))


_PARAMETERS = CASE_PARAMETERS


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
    keys = [key for key, a, b in zip(_PARAMETERS, first, second, strict=True) if a != b]
    key = keys[0] if keys else "mu1"
    values = [a for k, a, b in zip(_PARAMETERS, first, second, strict=True) if k == key]
    values += [b for k, a, b in zip(_PARAMETERS, first, second, strict=True) if k == key]
    return StudyConfigError(
        source,
        f"sweep.{key}",
        values,
        f"two cases get the same id {case_id!r}: the values differ only beyond 10 "
        "significant digits",
    )
