"""The line contact's subsurface field against McEwen's closed form (engine.reference.mcewen).

The solver's own tractions (Hertz pressure with a Cattaneo–Mindlin or Nowell & Hills traction,
or full sliding) give the x–z field of engine.solvers.line_subsurface, compared with McEwen's
field of the exact tractions at points on the surface layer and below it. Mesh: 512 elements
over ±1.25a (410 across the contact). Below the surface layer (z ≥ 0.05a, 2.6 Δx) the field
agrees to 1e-3 p0 (measured 1.2e-4 p0). On the surface layer (z = 1e-4 a, far below an
element) the jumps of the piecewise constant tractions at element edges show: 5 % of p0
(measured 3.4 %, σ_xx next to the contact edges).
"""

import numpy as np
import pytest

from engine.geometry import CylinderProfile
from engine.grid import Grid
from engine.kernels.line import line_operator
from engine.material import MaterialPair
from engine.reference import line_contact as ref
from engine.reference import mcewen
from engine.solvers.contact import ContactSolver
from engine.solvers.fretting import TangentialDriver, bulk_stretch, shifted_state
from engine.solvers.friction import FrictionLaw
from engine.solvers.line_subsurface import LineSubsurfaceStress

STEEL = MaterialPair(200e3, 0.3, 200e3, 0.3)
RADIUS, LOAD, MU = 6.0, 185.0, 0.5
E_STAR = STEEL.contact_modulus
A = ref.hertz_line_half_width(LOAD, RADIUS, E_STAR)
P0 = ref.hertz_line_peak_pressure(LOAD, RADIUS, E_STAR)
DEPTHS = np.array([1e-4, 0.05, 0.25, 0.5, 1.0]) * A


def _solved(force_ratio, bulk_stress):
    grid = Grid.line(512, 1.25 * A)
    solver = ContactSolver(
        grid,
        STEEL,
        CylinderProfile(RADIUS),
        FrictionLaw(MU, MU),
        operator=line_operator(grid, STEEL, 10.0),
        tol=1e-10,
    )
    start = solver.solve_load(LOAD).state
    strain = ref.bulk_surface_strain(bulk_stress, STEEL.E_A, STEEL.nu_A)
    state = shifted_state(start, np.zeros(2), bulk_stretch(grid, strain))
    driver = TangentialDriver(solver, LOAD, np.array([1.0, 0.0]), force_tol=1e-9)
    force = force_ratio * MU * LOAD
    step = driver.force(state, np.zeros(2), force, force, 1e-3, 1e5)
    assert step.converged, step.message
    return grid, step.result


@pytest.mark.parametrize(("force_ratio", "bulk_stress"), [(0.6, 0.0), (0.5, 120.0)])
def test_partial_slip_field_against_mcewen(force_ratio, bulk_stress):
    grid, result = _solved(force_ratio, bulk_stress)
    stress = LineSubsurfaceStress(grid, STEEL.nu_A, DEPTHS)
    plane = stress.plane(result.pressure, result.traction_x, bulk_stress=bulk_stress)
    tractions = mcewen.partial_slip_tractions(A, P0, MU, force_ratio, bulk_stress)
    exact = mcewen.line_contact_stress(plane.x, plane.z, tractions, STEEL.nu_A)
    inside = np.abs(plane.x) <= 1.2 * A
    for component in ("xx", "zz", "xz", "yy"):
        error = np.abs(plane.components[component] - exact.components[component])[inside]
        surface = error.reshape(-1, DEPTHS.size)[:, 0]
        below = error.reshape(-1, DEPTHS.size)[:, 1:]
        assert below.max() < 1e-3 * P0, component
        assert surface.max() < 5e-2 * P0, component


def test_sliding_trailing_edge_tension_against_mcewen():
    """Full sliding (q = μp of the solver's pressure): the tensile peak of σ_xx sits at the
    trailing edge x = −a, where McEwen's surface value is 2μp0; the element-centre value next
    to the edge approaches it like √(Δx/a) (test_line_subsurface): within 10 %. Below the
    surface (z ≥ 0.05a) the whole σ_xx field, its tension included, agrees to 1e-3 p0."""
    grid = Grid.line(512, 1.25 * A)
    solver = ContactSolver(
        grid,
        STEEL,
        CylinderProfile(RADIUS),
        FrictionLaw(0.0, 0.0),
        operator=line_operator(grid, STEEL, 10.0),
        tol=1e-10,
    )
    pressure = solver.solve_load(LOAD).pressure
    stress = LineSubsurfaceStress(grid, STEEL.nu_A, DEPTHS)
    plane = stress.plane(pressure, MU * pressure)
    exact = mcewen.line_contact_stress(
        plane.x, plane.z, mcewen.sliding_tractions(A, P0, MU), STEEL.nu_A
    )
    surface_xx = plane.components["xx"][:, 0]
    trailing = np.argmax(surface_xx)
    assert abs(grid.x[trailing] + A) <= grid.dx
    assert 0.9 * 2 * MU * P0 < surface_xx[trailing] <= 2 * MU * P0
    below = np.abs(plane.components["xx"] - exact.components["xx"])[:, 1:]
    assert below.max() < 1e-3 * P0
