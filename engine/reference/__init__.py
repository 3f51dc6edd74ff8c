"""Analytic reference solutions, usable by users and tests to validate the solvers."""
