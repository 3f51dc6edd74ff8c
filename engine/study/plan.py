"""Plan of a study: the sweep of ``[sweep]`` expanded into cases with stable ids.

Every combination of ``mu1 × mu2 × wear1 × wear2 × beta`` is a case (``mu2`` defaults to
``mu1`` and ``wear2`` to ``wear1`` element-wise, i.e. isotropic laws; ``wear2 =
"proportional"`` gives ``wear1·mu2/mu1``, paper Section 7.3).

The case id is built from the parameter values only (never from the position in the sweep), so
adding a value to a list keeps the ids — and the completed results — of every other case::

    mu0.1-0.4_w1.33e-07-5.32e-07_b45

Friction coefficients are dimensionless, wear coefficients in 1/MPa, ``beta`` in degrees.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

from .config import PROPORTIONAL, StudyConfig, StudyConfigError

__all__ = ["Case", "Plan", "make_plan", "case_id_for"]


def _format(value: float) -> str:
    return format(value, ".10g")


def case_id_for(mu1: float, mu2: float, wear1: float, wear2: float, beta: float) -> str:
    """Readable id from the parameters: ``mu<mu1>-<mu2>_w<wear1>-<wear2>_b<beta>``."""
    mu = f"mu{_format(mu1)}" if mu1 == mu2 else f"mu{_format(mu1)}-{_format(mu2)}"
    wear = f"w{_format(wear1)}" if wear1 == wear2 else f"w{_format(wear1)}-{_format(wear2)}"
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

    def parameters(self) -> dict[str, float | int | str]:
        return {
            "case_id": self.case_id,
            "index": self.index,
            "mu1": self.mu1,
            "mu2": self.mu2,
            "wear1": self.wear1,
            "wear2": self.wear2,
            "beta": self.beta,
        }

    @property
    def expected_cost(self) -> float:
        """Relative cost guess for scheduling: low friction slips more and takes longer
        (more slip, more wear, more simulated cycles); frictionless cases are a single
        normal solve per increment and the cheapest."""
        friction = min(self.mu1, self.mu2)
        return 0.5 if friction == 0.0 else 1.0 / (0.05 + friction)


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

    def by_id(self, case_id: str) -> Case:
        for case in self.cases:
            if case.case_id == case_id:
                return case
        raise KeyError(case_id)

    def dispatch_order(self, skip: set[str] | frozenset[str] = frozenset()) -> list[Case]:
        """Cases still to run, most expensive first (longest-processing-time-first).

        Handing the slow, low-friction cases out first keeps the cheap ones for the end, where
        they fill the gaps; the scheduler is dynamic anyway, this only shortens the tail.
        Ties keep the plan order.
        """
        pending = [case for case in self.cases if case.case_id not in skip]
        return sorted(pending, key=lambda case: (-case.expected_cost, case.index))


def make_plan(config: StudyConfig) -> Plan:
    """Expand the sweep into cases (plan order: mu1, mu2, wear1, wear2, beta, as nested loops)."""
    sweep = config.sweep
    combos = []
    if sweep.mu2 is None:
        mu_pairs = [(mu, mu) for mu in sweep.mu1]
    else:
        mu_pairs = list(itertools.product(sweep.mu1, sweep.mu2))
    for mu1, mu2 in mu_pairs:
        if sweep.wear2 is None:
            wear_pairs = [(w, w) for w in sweep.wear1]
        elif sweep.wear2 == PROPORTIONAL:
            wear_pairs = [(w, w * mu2 / mu1) for w in sweep.wear1]
        else:
            wear_pairs = list(itertools.product(sweep.wear1, sweep.wear2))
        for (wear1, wear2), beta in itertools.product(wear_pairs, sweep.beta):
            combos.append((mu1, mu2, wear1, wear2, beta))

    cases = []
    seen: dict[str, tuple] = {}
    for index, (mu1, mu2, wear1, wear2, beta) in enumerate(combos):
        case_id = case_id_for(mu1, mu2, wear1, wear2, beta)
        if case_id in seen:
            raise _collision(config.source, case_id, seen[case_id], combos[index])
        seen[case_id] = combos[index]
        cases.append(Case(index, case_id, mu1, mu2, wear1, wear2, beta))
    unknown = set(config.testing.fail_cases) - set(seen)
    if unknown:
        raise StudyConfigError(
            config.source, "testing.fail_cases", sorted(unknown), "not a case id of this plan"
        )
    return Plan(tuple(cases))


_PARAMETERS = ("mu1", "mu2", "wear1", "wear2", "beta")


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
