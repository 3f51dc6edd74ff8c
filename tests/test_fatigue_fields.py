"""Stress histories from solver tractions: the point evaluators of the critical distances
equal the DC-FFT planes where both are defined (self-consistency tier, fast)."""

from __future__ import annotations

import numpy as np
import pytest

from engine.fatigue.fields import (
    CycleRecorder,
    LinePointStress,
    PlanePointStress,
    plane_history,
)
from engine.grid import Grid
from engine.solvers.line_subsurface import LineSubsurfaceStress
from engine.solvers.subsurface import SubsurfaceStress

NU = 0.3


def _recorder(shape, instants=3, bulk=(0.0, 0.0, 0.0)):
    rng = np.random.default_rng(11)
    recorder = CycleRecorder()
    for k in range(instants):
        recorder.set_bulk_stress(bulk[k])
        loads = [
            rng.uniform(0, 100, shape),
            rng.uniform(-30, 30, shape),
            rng.uniform(-30, 30, shape),
        ]
        if shape[1] == 1:
            loads[2] = np.zeros(shape)
        recorder.add(*loads)
    return recorder.take()


def test_line_point_stress_equals_the_plane():
    """Direct sums at the plane's points (element centres, its depths) equal the DC-FFT
    plane, bulk stress included (1e-9 of the load scale: FFT rounding)."""
    grid = Grid.line(32, 1.0)
    depths = np.array([0.01, 0.2, 0.5])
    increments = _recorder((32, 1), bulk=(0.0, 50.0, -20.0))
    history = plane_history(LineSubsurfaceStress(grid, NU, depths), increments)
    points = LinePointStress(grid, NU, increments)(history.x, history.z)
    assert np.allclose(points.tensor, history.tensor, atol=1e-9 * 100)


def test_plane_point_stress_equals_the_plane():
    """On a 3-D grid, the direct sums at lattice points of the x–z plane equal
    ``SubsurfaceStress.plane`` (exact DC-FFT sums there; 1e-9 of the load scale)."""
    grid = Grid.square(12, 1.0)
    depths = np.array([0.05, 0.3])
    increments = _recorder((12, 12), instants=2)
    history = plane_history(SubsurfaceStress(grid, NU, depths), increments)
    chosen = np.array([0, 5, 17, 22])
    points = PlanePointStress(grid, NU, increments)(history.x[chosen], history.z[chosen])
    assert np.allclose(points.tensor, history.tensor[:, chosen], atol=1e-9 * 100)


def test_point_evaluators_refuse_the_surface():
    with pytest.raises(ValueError, match="z > 0"):
        LinePointStress(Grid.line(8, 1.0), NU, _recorder((8, 1)))(np.array([0.0]), 0.0)
