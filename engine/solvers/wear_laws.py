"""The table of wear laws: ``[wear] law = "<name>"`` picks one.

Built in: ``"archard"`` (:class:`engine.solvers.friction.WearLaw`, the default) and
``"energy"`` (:class:`engine.solvers.friction.EnergyWearLaw`); another package adds a law
through the ``fretting_engine.wear_laws`` entry-point group (:mod:`engine.plugins`), a
:class:`engine.solvers.wear.WearModel` subclass. Every table of the coefficients (the
``[sweep]`` keys, their units, the case parameters and summary columns) is derived from the
laws' ``coefficients`` here.
"""

from __future__ import annotations

from engine.keys import Key, merge_units
from engine.plugins import GROUPS, Registry, subclass_of

from .friction import EnergyWearLaw, WearLaw
from .wear import WearModel

__all__ = [
    "WEAR_LAWS",
    "DEFAULT_WEAR_LAW",
    "wear_coefficients",
    "fixed_coefficients",
    "coefficient_units",
]

WEAR_LAWS: Registry[type[WearModel]] = Registry(
    GROUPS["wear_laws"],
    {law.name: law for law in (WearLaw, EnergyWearLaw)},
    what="wear law",
    check=subclass_of(WearModel),
)
#: The law of a study without ``[wear] law``.
DEFAULT_WEAR_LAW = WearLaw.name


def fixed_coefficients() -> tuple[str, ...]:
    """The default law's coefficients: every case stores them (0 under another law), before
    ``beta``, so that every results file has the same first parameter columns."""
    return tuple(WEAR_LAWS.builtins[DEFAULT_WEAR_LAW].coefficients)


def wear_coefficients(laws=None) -> dict[str, Key]:
    """{coefficient: :class:`Key`} of every law of ``laws`` (default: the registered ones),
    the default law's first; a name two laws declare with different units is an error
    naming both."""
    laws = WEAR_LAWS if laws is None else laws
    coefficient_units(laws)
    keys: dict[str, Key] = {}
    for name in (DEFAULT_WEAR_LAW, *(law for law in laws if law != DEFAULT_WEAR_LAW)):
        for coefficient, key in laws[name].coefficients.items():
            keys.setdefault(coefficient, key)
    return keys


def coefficient_units(laws=None) -> dict[str, str]:
    """{coefficient: unit} of every law of ``laws`` (default: the registered ones)."""
    laws = WEAR_LAWS if laws is None else laws
    return merge_units(
        (
            (f"the {name!r} wear law ({law.__module__})", {
                coefficient: key.unit for coefficient, key in law.coefficients.items()
            })
            for name, law in laws.items()
        ),
        "wear coefficient",
    )  # fmt: skip
