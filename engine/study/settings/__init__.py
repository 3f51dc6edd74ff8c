"""What a study file's sections become, below the parser and what it dispatches to.

- :mod:`.sections` the frozen records of the sections, the error every check raises and
  the constants they share;
- :mod:`.reader` one TOML table read with typed, range-checked values;
- :mod:`.checks` physical checks and the bounds of the engine's own keys;
- :mod:`.compat` results files of earlier versions (defaults they left out).

The loading kinds (:mod:`engine.study.kinds`) read their ``[loading]`` keys with these; the
units of every sweepable key (:mod:`engine.study.units`, which reads the kinds' declarations)
and the study-file parser (:mod:`engine.study.config`) sit above both, so no package imports
one that imports it back.
"""
