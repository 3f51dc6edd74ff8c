"""Fretting-wear contact simulation: FFT boundary elements, cyclic wear, subsurface stress.

Units throughout: mm, N, MPa (= N/mm²); wear coefficients in 1/MPa; angles in degrees at
the user-facing layer and radians inside the numerical code.
"""

__version__ = "0.1.0"
