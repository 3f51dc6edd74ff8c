"""Rough and measured surfaces: the ``[surface]`` section of a study.

- :mod:`.topography` random self-affine height maps and their statistics (rms height and
  slope, radially averaged power spectrum): a numerical kernel;
- :mod:`.measured` measured height maps read, detrended and resampled to a case's grid;
- :mod:`.config` the ``[surface]`` section validated into a :class:`SurfaceConfig`;
- :mod:`.profile` a punch profile with the roughness: gap = g_g − h (:class:`RoughProfile`);
- :mod:`.outputs` the summary columns and ``surface/*`` datasets of a case.

Beside it: :mod:`engine.output.ensemble` (statistics over the realisations of a study
sweeping ``surface.seed``), :mod:`engine.analysis.surface_figures` and
:mod:`engine.analysis.surface_report` (its figures and its table).

The host calls in at four places: the study parser (:func:`parse_surface`), the solver
builder (:func:`rough_profile`), the case runner (:func:`surface_outcome`) and the layout of
the collective writer (:func:`surface_layout`); the run writes the ensemble table
(:func:`engine.output.ensemble.write_ensemble`).
"""

from .config import SurfaceConfig, parse_surface
from .outputs import surface_layout, surface_outcome
from .profile import RoughProfile, rough_profile, surface_height

__all__ = [
    "SurfaceConfig",
    "parse_surface",
    "RoughProfile",
    "rough_profile",
    "surface_height",
    "surface_outcome",
    "surface_layout",
]
