import pytest

from engine.geometry import FlatPunch
from engine.grid import Grid
from engine.material import paper_material
from engine.solvers.contact import ContactSolver
from engine.solvers.friction import FrictionLaw

RADIUS = 1.8  # mm, a0 of Section 7
LOAD = 714.0  # N, Section 7.1


@pytest.fixture(scope="session")
def material():
    return paper_material()


@pytest.fixture(scope="session")
def frictionless_64(material):
    """64 x 64 elements over the square of half-width 1.05 a0 (the paper's mesh zone)."""
    grid = Grid.square(64, 1.05 * RADIUS)
    return ContactSolver(grid, material, FlatPunch(RADIUS), FrictionLaw(0.0, 0.0))
