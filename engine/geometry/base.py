"""The protocol of a contact geometry (a punch profile) and what the profiles share.

A profile is the geometric gap g_g of Eq. (1) over the grid (mm) and what a study needs to
know of the shape before anything is solved. Each shape is one module of
:mod:`engine.geometry` with one :class:`Profile` subclass, registered in the table
:data:`engine.geometry.PROFILES` under its ``[punch] shape`` name; the study layer asks the
profile and never branches on the shape:

=============================  ===========================================================
what                           member
=============================  ===========================================================
the study file's ``[punch]``   :attr:`~Profile.name`, :attr:`~Profile.description`, its
                               dataclass fields (:meth:`~Profile.keys`: unit, meaning and
                               bounds of each key, :mod:`engine.keys`)
contact length a0              :meth:`~Profile.contact_length` (the length unit of
                               ``[subsurface] depth`` and of the summary's p0)
default mesh                   :meth:`~Profile.grid` (square or line), :meth:`~Profile.
                               default_half_width`, :attr:`~Profile.covered` (what the mesh
                               must cover, in messages)
gap                            :meth:`~Profile.gap` (``numpy.inf``: no surface there)
border check                   :meth:`~Profile.check_grid`, :attr:`~Profile.extent`
                               (:func:`may_reach_border`, :func:`border_contact`)
summary parameters             :meth:`~Profile.mean_pressure` (the summary's p0),
                               :meth:`~Profile.nominal` (a0 and p0), :attr:`~Profile.
                               load_unit` (N, or N/mm for a line contact)
fretting references            :meth:`~Profile.fretting_reference` (the closed forms
                               where they exist, None otherwise), and from it
                               :meth:`~Profile.slip_displacement`,
                               :meth:`~Profile.fretting_loop`
=============================  ===========================================================

Units: lengths in mm, loads in N (line contacts: N/mm), moduli and pressures in MPa.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from engine.grid import Grid
from engine.keys import Key, declared_keys
from engine.reference.flat_punch import mean_pressure

__all__ = [
    "Profile",
    "LineProfile",
    "HERTZ_MARGIN",
    "ContactReachesBorder",
    "border_contact",
    "may_reach_border",
    "check_covers",
]

#: Default mesh half-width / contact length a0 of the flat punch and of the shapes whose
#: contact grows with the load (sphere, cylinder, pad): the contact and half of a0 beyond
#: its edge, where the stresses that start fretting cracks are.
HERTZ_MARGIN = 1.5


class Profile:
    """A punch profile (module docstring). Subclasses are frozen dataclasses whose fields
    are the shape's ``[punch]`` keys, each declared with its unit, meaning and bounds in the
    field's metadata (:func:`engine.keys.length`, :func:`engine.keys.parameter`); they set
    ``name`` and implement :meth:`gap` and, unless the contact length is the field
    ``radius``, :meth:`contact_length`. The other members have a 3-D punch's defaults."""

    #: ``[punch] shape`` value.
    name: ClassVar[str] = ""
    #: One line for the help texts (what the shape is).
    description: ClassVar[str] = ""
    #: A plane-strain line contact (grid of one element along y, loads per unit length).
    is_line: ClassVar[bool] = False
    #: What the mesh must cover, with 4 elements across it (the contact length a0).
    covered: ClassVar[str] = "punch face radius"
    #: Unit of the load: N (a line contact's: N/mm, per unit length).
    load_unit: ClassVar[str] = "N"

    def __post_init__(self) -> None:
        """Each declared key checked against its bounds (ValueError naming it) and kept as
        a float."""
        for name, key in self.keys().items():
            object.__setattr__(self, name, key.check(name, getattr(self, name)))

    @classmethod
    def keys(cls) -> dict[str, Key]:
        """The ``[punch]`` keys of this shape besides ``shape``.

        Returns
        -------
        dict of str to engine.keys.Key
            Name → declaration (unit, meaning, bounds), in the order of the dataclass fields.
        """
        return declared_keys(cls)

    # ------------------------------------------------------------ gap and grid
    def gap(self, grid: Grid) -> np.ndarray:
        """The geometric gap g_g of Eq. (1) at the element centres.

        Parameters
        ----------
        grid : engine.grid.Grid
            The surface grid; ``grid.coordinates()`` gives the element centres x, y (mm).

        Returns
        -------
        numpy.ndarray
            g_g (mm), shape ``grid.shape``, ``numpy.inf`` where the punch has no surface.
        """
        raise NotImplementedError

    def check_grid(self, grid: Grid) -> None:
        """Raise ValueError when ``grid`` cannot hold the contact (checked before solving;
        a contact that grows beyond the grid is caught at run time, :func:`border_contact`)."""

    @property
    def extent(self) -> float:
        """Largest distance from the axis at which the punch has a surface (mm; inf: none)."""
        return math.inf

    def grid(self, n: int, half_width: float) -> Grid:
        """The case's grid: n × n elements over [−half_width, half_width]² (mm)."""
        return Grid.square(n, half_width)

    # ------------------------------------------------------------ nominal contact
    def contact_length(self, load: float, contact_modulus: float) -> float:
        """The nominal contact length a0: the length unit of ``[subsurface] depth``, the
        default mesh and the summary's p0.

        Parameters
        ----------
        load : float
            Peak normal load P (N; a line contact's N/mm).
        contact_modulus : float
            E* (MPa, Eq. 6).

        Returns
        -------
        float
            a0 (mm); by default the field ``radius``.
        """
        return self.radius

    def default_half_width(self, load: float, contact_modulus: float) -> float:
        """Default ``[mesh] half_width`` (mm)."""
        return HERTZ_MARGIN * self.contact_length(load, contact_modulus)

    def mean_pressure(self, load: float, contact_length: float) -> float:
        """The summary's p0 (MPa): P/(π a0²) (Eq. 19)."""
        return mean_pressure(load, contact_length)

    def unworn_pressure(self, r, load: float, contact_length: float):
        """The closed-form frictionless pressure (MPa) at distances ``r`` (mm) from the axis of
        the unworn profile at ``load``, drawn beside the computed profiles, or None where the
        figures draw none (the default)."""
        return None

    def fretting_reference(self, load: float, material, mu: float, reference_distance):
        """The closed forms of this profile under fretting at ``load`` (N, or N/mm for a line
        contact) with isotropic friction ``mu``
        (:class:`engine.reference.masing.FrettingReference`: δ_slip, the force amplitude,
        the energy per cycle, the loop), or None where there are none (the default).
        ``reference_distance`` is a line contact's displacement datum (mm; None in 3-D)."""
        return None

    def slip_displacement(self, load, material, mu: float, reference_distance):
        """The partial/gross-slip transition amplitude δ_slip (mm) at ``load`` (a number or
        an array: the boundary of a fretting map), or None without closed forms."""
        loads = np.asarray(load, dtype=float)
        references = [
            self.fretting_reference(float(value), material, mu, reference_distance)
            for value in loads.ravel()
        ]
        if not references or references[0] is None:
            return None
        return np.reshape([item.slip_displacement for item in references], loads.shape)

    def fretting_loop(self, load: float, material, mu: float, reference_distance, **amplitude):
        """The analytic stabilised Q–δ loop at ``load`` under one of
        ``displacement_amplitude`` (mm) or ``force_amplitude`` (N, N/mm), or None without
        closed forms (:meth:`fretting_reference`)."""
        reference = self.fretting_reference(load, material, mu, reference_distance)
        return None if reference is None else reference.loop(**amplitude)

    def nominal(self, load: float, contact_modulus: float) -> dict[str, float]:
        """The nominal contact: ``a0`` (mm) and ``p0`` (MPa) at the load."""
        a0 = self.contact_length(load, contact_modulus)
        return {"a0": a0, "p0": self.mean_pressure(load, a0)}


class LineProfile(Profile):
    """A plane-strain line contact: the bodies are infinitely long along y, the profile
    depends on x only and is sampled on a line grid (``Grid.line``); loads per unit length
    (N/mm). A surface everywhere: whether the grid covers the contact depends on the load
    and is checked after every increment."""

    is_line = True
    covered = "contact half-width"
    load_unit = "N/mm"

    def grid(self, n: int, half_width: float) -> Grid:
        """n elements along x over [−half_width, half_width] (mm), unit length along y."""
        return Grid.line(n, half_width)

    def mean_pressure(self, load: float, contact_length: float) -> float:
        """p0 = P/(2 a0) (MPa), the mean pressure over the nominal contact."""
        return load / (2.0 * contact_length)

    def check_grid(self, grid: Grid) -> None:
        if not grid.is_line:
            raise ValueError(
                f"a {self.name} is a line (plane-strain) contact: it needs a line grid with "
                f"one element along y, got a grid of {grid.n_x} x {grid.n_y} elements"
            )


def check_covers(grid: Grid, radius: float, what: str) -> None:
    """The grid must cover the disc of ``radius`` (mm) and put 4 elements across it."""
    for name, half_width in (
        ("half_width_x", grid.half_width_x),
        ("half_width_y", grid.half_width_y),
    ):
        if half_width < radius:
            raise ValueError(
                f"grid {name} = {half_width:g} mm does not cover the {what} = {radius:g} mm"
            )
    elements = min(grid.n_x * radius / grid.half_width_x, grid.n_y * radius / grid.half_width_y)
    if elements < 4:
        raise ValueError(
            f"grid of {grid.n_x} x {grid.n_y} elements is too coarse for the {what} = "
            f"{radius:g} mm (fewer than 4 elements across it)"
        )


class ContactReachesBorder(RuntimeError):
    """The contact area touches the edge of the grid: the solution would be truncated."""


def may_reach_border(profile: Profile, grid: Grid) -> bool:
    """True when the punch has a surface beyond the grid's edge, so the contact could be
    truncated by it (never for a flat punch on a grid covering its face)."""
    half_width = grid.half_width_x if grid.is_line else min(grid.half_width_x, grid.half_width_y)
    return profile.extent > half_width


def border_contact(pressure: np.ndarray) -> int:
    """Number of elements of the outermost ring of the grid carrying pressure (> 0); on a
    line grid (one element along y) the ring is the two end elements along x."""
    pressure = np.asarray(pressure)
    ring = np.zeros(pressure.shape, dtype=bool)
    ring[0, :] = ring[-1, :] = True
    if pressure.shape[1] > 1:
        ring[:, 0] = ring[:, -1] = True
    return int(np.count_nonzero(pressure[ring] > 0.0))
