"""Fretting-wear contact simulation: FFT boundary elements, cyclic wear, subsurface stress.

Units throughout: mm, N, MPa (= N/mm²); wear coefficients in 1/MPa; angles in degrees at
the user-facing layer and radians inside the numerical code.
"""

__version__ = "0.1.0"

__all__ = ["__version__", "load_summary", "load_thresholds"]


def __getattr__(name: str):
    """``engine.load_summary`` without importing pandas/h5py for every ``import engine``."""
    if name == "load_summary":
        from engine.output.summary import load_summary

        return load_summary
    if name == "load_thresholds":
        from engine.output.thresholds import load_thresholds

        return load_thresholds
    raise AttributeError(f"module 'engine' has no attribute {name!r}")
