"""Operators built once per rank and shared by every case with the same grid and material.

Building a case's numerical machinery costs far more than a short case: the surface influence
kernels and their spectra, the FFTW plans of the operator and of its preconditioner, and the
subsurface stress kernels (six components × three loads × every depth layer). None of it
depends on the friction or wear coefficients that a sweep varies, so the case runner asks this
cache instead of building them again.

Sharing is safe bit for bit: the objects keep no state between applications (every buffer is
overwritten before it is read; plans are ``FFTW_ESTIMATE`` plans, see ``engine.kernels.fft``),
so a case gives the same bits whether it is the first one of its rank or the tenth.
"""

from __future__ import annotations

import time

import numpy as np

from engine.grid import Grid
from engine.kernels.line import line_operator
from engine.kernels.operator import HalfSpaceOperator
from engine.material import MaterialPair
from engine.solvers.line_subsurface import LineSubsurfaceStress
from engine.solvers.subsurface import SubsurfaceStress

__all__ = ["OperatorCache"]


class OperatorCache:
    """Per-rank store of half-space operators and subsurface stress evaluators.

    ``setup_s`` accumulates the wall time (s) spent building what was not cached yet.
    """

    def __init__(self) -> None:
        self._operators: dict[tuple, HalfSpaceOperator] = {}
        self._stresses: dict[tuple, SubsurfaceStress] = {}
        self._planes: set[tuple] = set()  # (stress key, angle) whose kernels are built
        self.setup_s = 0.0

    def operator(
        self,
        grid: Grid,
        material: MaterialPair,
        *,
        threads: int,
        planner_effort: str,
        reference_distance: float | None = None,
    ) -> HalfSpaceOperator:
        """The influence operator of ``grid`` and ``material`` (built on first request); a
        line grid's plane-strain operator takes the displacement datum
        ``reference_distance`` (mm, engine.kernels.line)."""
        key = (grid, material, threads, planner_effort, reference_distance)
        if key not in self._operators:
            start = time.perf_counter()
            if grid.is_line:  # plane strain: the line kernels with their datum
                operator = line_operator(
                    grid,
                    material,
                    reference_distance,
                    threads=threads,
                    planner_effort=planner_effort,
                )
            else:
                operator = HalfSpaceOperator(
                    grid, material, threads=threads, planner_effort=planner_effort
                )
            operator.preconditioner  # noqa: B018 (built now, counted as set-up)
            self._operators[key] = operator
            self.setup_s += time.perf_counter() - start
        return self._operators[key]

    def stress(
        self,
        grid: Grid,
        poisson_ratio: float,
        depths: np.ndarray,
        *,
        threads: int,
        planner_effort: str,
        angle: float = 0.0,
    ) -> SubsurfaceStress:
        """The subsurface stress evaluator (its kernel spectra are kept between cases); the
        lattice of the vertical plane through the axis at ``angle`` (rad; 0: the x–z plane,
        which cyclic and static cases evaluate; a fretting case's sliding direction) is
        built on the first request for that plane and counted as set-up; an oblique plane's
        kernels too, while the plane through the axis keeps its kernels from its second
        evaluation on (``SubsurfaceStress.prepare_plane``): a one-case static study, which
        evaluates it once, never holds them."""
        key = (grid, float(poisson_ratio), tuple(float(d) for d in depths), threads, planner_effort)
        if (key, float(angle)) in self._planes:
            return self._stresses[key]
        start = time.perf_counter()
        if key not in self._stresses and grid.is_line:
            self._stresses[key] = LineSubsurfaceStress(
                grid, poisson_ratio, np.asarray(depths, dtype=float)
            )
        elif key not in self._stresses:
            self._stresses[key] = SubsurfaceStress(
                grid,
                poisson_ratio,
                np.asarray(depths, dtype=float),
                threads,
                planner_effort=planner_effort,
            )
        self._stresses[key].prepare_plane(float(angle), kernels=False)
        self._planes.add((key, float(angle)))
        self.setup_s += time.perf_counter() - start
        return self._stresses[key]
