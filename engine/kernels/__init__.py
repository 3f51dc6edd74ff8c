"""Numerical kernels: influence coefficients and FFT convolution operators (no MPI, no files)."""
