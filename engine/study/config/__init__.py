"""Study file (TOML) -> frozen, validated configuration (:class:`StudyConfig`).

The package is split by role:

- :mod:`.sections` the section records, the error every check raises, shared constants;
- :mod:`.parsing` the study file read and validated into a :class:`StudyConfig` (the keys of
  every section are listed there), and a case's configuration derived from the study's;
- :mod:`.reader` one TOML table read with typed, range-checked values;
- :mod:`.sweep` the ``[sweep]`` table's dotted keys and ``zip`` groups;
- :mod:`.checks` physical checks (values the model cannot represent);
- :mod:`.toml_writer` the resolved study written back as TOML;
- :mod:`.compat` results files of earlier versions (defaults they left out).

Every name below is importable from ``engine.study.config``.
"""

from engine.geometry import HERTZ_MARGIN
from engine.study.settings import sections
from engine.study.settings.checks import (
    MAX_FRICTION,
    MAX_PRESSURE_OVER_MODULUS,
    MAX_TOLERANCE,
    MAX_WEAR_COEFFICIENT,
    MIN_PRESSURE_OVER_MODULUS,
    MODULUS_RANGE,
    check_physical_ranges,
)
from engine.study.settings.compat import (
    FORMER_DEFAULTS,
    STATIC_PLACEHOLDERS,
    fill_former_defaults,
    same_fingerprint,
)
from engine.study.settings.sections import *  # noqa: F403  (the section records; sections.__all__)
from engine.study.units import SWEEPABLE, SWEEPABLE_TEXT

from .parsing import StudyConfig, load_study, parse_study
from .toml_writer import dump_toml

__all__ = [
    "StudyConfig",
    "load_study",
    "parse_study",
    "dump_toml",
    "check_physical_ranges",
    "fill_former_defaults",
    "same_fingerprint",
    "FORMER_DEFAULTS",
    "STATIC_PLACEHOLDERS",
    "SWEEPABLE",
    "SWEEPABLE_TEXT",
    "HERTZ_MARGIN",
    "MAX_FRICTION",
    "MAX_PRESSURE_OVER_MODULUS",
    "MAX_TOLERANCE",
    "MAX_WEAR_COEFFICIENT",
    "MIN_PRESSURE_OVER_MODULUS",
    "MODULUS_RANGE",
    *sections.__all__,
]
