"""What a study file's sections become, below the parser and what it dispatches to.

- :mod:`.sections` the frozen records of the sections, the error every check raises and
  the constants they share;
- :mod:`.reader` one TOML table read with typed, range-checked values;
- :mod:`.checks` physical checks and the bounds of the engine's own keys;
- :mod:`.units` the units of every sweepable key, from the engine's sections and the
  plug-in registries;
- :mod:`.compat` results files of earlier versions (defaults they left out).

The loading kinds (:mod:`engine.study.kinds`) read their ``[loading]`` keys with these; the
study-file parser (:mod:`engine.study.config`) sits above both and dispatches to the kinds,
so no package imports one that imports it back.
"""
