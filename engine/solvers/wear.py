"""The protocol of a wear law: the coefficients it declares and the depth it removes.

A wear law is one class, registered in :data:`engine.solvers.wear_laws.WEAR_LAWS` under its
``name`` (``[wear] law = "<name>"``), by the engine or by another package through the
``fretting_engine.wear_laws`` entry-point group (:mod:`engine.plugins`). It declares:

- ``coefficients``: {name: :class:`engine.keys.Key`}, the ``[sweep]`` lists the law reads,
  each with its unit, meaning and bounds. Every case stores them as parameters (summary
  columns, case attributes); their names must not clash with another law's unless the unit
  is the same;
- ``id_prefix``: the letter of the case id before the coefficients (``w`` for Archard's
  ``mu0.5_w1e-07_b0``);
- ``rules`` (optional): {coefficient: a text it accepts instead of a list};
- ``from_coefficients(values, beta)``: the law of one case, ``values`` {name: value} in the
  declared units, ``beta`` the angle of the tribological axes (rad);
- ``increment(result, previous)``: the wear depth Δω (mm, shape of the grid) of one load
  increment from its solved ``result`` (``pressure`` MPa, ``slip_x``/``slip_y`` mm,
  ``traction_x``/``traction_y`` MPa) and the state ``previous`` before it.

What the solvers need of a wear law is ``increment`` only. ``scaled(factor)`` (the law
wearing ``factor`` times as fast) serves two-body wear (``[wear] pad_coefficient``);
``combinations`` and ``followers`` let a law derive a coefficient from another one
(Archard's ``wear2`` defaults to ``wear1``). This module imports nothing of the study layer.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

import numpy as np

from engine.keys import Key

__all__ = ["WearModel"]


class WearModel:
    """Base class of a wear law (module docstring). A subclass sets ``name``,
    ``description``, ``coefficients`` and ``id_prefix`` and implements
    :meth:`from_coefficients` and :meth:`increment`."""

    name: ClassVar[str]
    description: ClassVar[str]
    coefficients: ClassVar[dict[str, Key]]
    id_prefix: ClassVar[str]
    #: {coefficient: the text it accepts instead of a list} (a rule, e.g. Archard's
    #: ``wear2 = "proportional"``).
    rules: ClassVar[dict[str, str]] = {}

    @classmethod
    def keys(cls) -> dict[str, Key]:
        """{coefficient: :class:`Key`}, in the order of the ``[sweep]`` lists."""
        return dict(cls.coefficients)

    @classmethod
    def from_coefficients(cls, values: Mapping[str, float], beta: float) -> WearModel:
        """The law of one case.

        Parameters
        ----------
        values : mapping of str to float
            {coefficient: value} in the declared units, every declared coefficient.
        beta : float
            Angle of the tribological axes e1, e2 from x (rad); an isotropic law ignores it.

        Returns
        -------
        WearModel
            The law, ready for :meth:`increment`.
        """
        raise NotImplementedError

    def increment(self, result, previous) -> np.ndarray:
        """The wear depth of one load increment.

        Parameters
        ----------
        result : engine.solvers.increment.IncrementResult
            The solved increment: ``pressure`` (MPa), ``slip_x``, ``slip_y`` (mm, the slip
            increments), ``traction_x``, ``traction_y`` (MPa), each of shape (n_x, n_y).
        previous : engine.solvers.increment.IncrementResult
            The state before it (its tractions; a law of the frictional work needs them).

        Returns
        -------
        numpy.ndarray
            Δω (mm), shape (n_x, n_y).
        """
        raise NotImplementedError

    def scaled(self, factor: float) -> WearModel:
        """The law wearing ``factor`` times as fast (two bodies wearing together,
        ``[wear] pad_coefficient``).

        Parameters
        ----------
        factor : float
            1 + k_pad / k_flat (≥ 1).

        Returns
        -------
        WearModel
            The scaled law; the base class raises NotImplementedError (no pad wear).
        """
        raise NotImplementedError(
            f"the wear law {self.name!r} cannot wear two bodies ([wear] pad_coefficient)"
        )

    @classmethod
    def read_sweep(cls, section, required: bool) -> dict[str, Any]:
        """The law's ``[sweep]`` lists.

        Parameters
        ----------
        section : engine.study.settings.reader.Section
            The ``[sweep]`` table; ``section.number_list`` reads a list, ``section.error``
            makes the error naming a key and its value.
        required : bool
            The loading kind wears (a coefficient without a default must be given);
            otherwise an absent coefficient is [0].

        Returns
        -------
        dict
            {coefficient: tuple of values}, each ≥ its declared minimum, in the declared
            order.
        """
        lists: dict[str, Any] = {}
        for name, key in cls.coefficients.items():
            default: Any = [key.default] if key.default is not None else None
            if default is None and not required:
                default = [0.0]
            given = {} if default is None else {"default": default}
            unit = "" if key.unit == "1" else key.unit
            lists[name] = section.number_list(name, **given, minimum=key.minimum, unit=unit)
        return lists

    @classmethod
    def combinations(
        cls, lists: Mapping[str, Any], mu1: float, mu2: float
    ) -> list[dict[str, float]]:
        """The coefficients of the cases for one pair of friction coefficients.

        Parameters
        ----------
        lists : mapping
            What :meth:`read_sweep` returned.
        mu1, mu2 : float
            The friction coefficients of the cases (for a law deriving a coefficient from
            them).

        Returns
        -------
        list of dict
            {coefficient: value} per case, in plan order: the product of the lists, first
            coefficient outermost.
        """
        names = list(cls.coefficients)
        return [
            dict(zip(names, values, strict=True))
            for values in itertools.product(*(lists[name] for name in names))
        ]

    @classmethod
    def followers(cls, lists: Mapping[str, Any]) -> dict[str, tuple[str, str]]:
        """The coefficients not swept but derived from another.

        Parameters
        ----------
        lists : mapping
            What :meth:`read_sweep` returned (a coefficient's entry None when absent).

        Returns
        -------
        dict
            {coefficient: (the coefficient it follows, the rule in words)}; the dry run
            names them beside the one they follow. None by default.
        """
        return {}

    @classmethod
    def resolved(cls, lists: Mapping[str, Any]) -> dict[str, Any]:
        """The ``[sweep]`` lists as TOML values, in the declared order (absent ones left out)."""
        return {
            name: list(value) if isinstance(value, tuple) else value
            for name, value in lists.items()
            if value is not None
        }

    @classmethod
    def case_id_part(cls, values: Sequence[str]) -> str:
        """The case id's part of the coefficients.

        Parameters
        ----------
        values : sequence of str
            The coefficients' values of one case as the id writes them, in declared order.

        Returns
        -------
        str
            ``id_prefix`` and the values, one value when they are all equal (``w1e-07``),
            else joined by ``-`` (``w1e-07-4e-07``).
        """
        shown = values[:1] if len(set(values)) == 1 else values
        return cls.id_prefix + "-".join(shown)
