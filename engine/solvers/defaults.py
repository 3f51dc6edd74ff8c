"""Default solver settings, in one light module (no NumPy, no FFTW).

The study configuration (``engine.study.config``) resolves every default from here when it
is built, so the resolved study stored with the results and its fingerprint name exactly
what ran; the solvers use the same values as their own keyword defaults.
"""

from __future__ import annotations

STATIC_TOLERANCE = 1e-8  # relative residual of static solves (stiffness comparisons)
CYCLIC_TOLERANCE = 1e-6  # relative residual of cyclic solves (tests/test_cycle_jump_convergence)
MAX_ITERATIONS = 20000  # iterations per increment (all methods together)
MAX_WEAR_FRACTION = 0.004  # wear per cycle jump / peak elastic approach
MAX_JUMP_GROWTH = 2.0  # largest ratio of consecutive cycle jumps
