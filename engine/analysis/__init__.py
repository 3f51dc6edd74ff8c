"""Analysis layer: what runs after a study, on its results file (results, report, figures).

Nothing here writes a results file or knows MPI; :mod:`.results` (the one model of a results
file, :func:`engine.open_results`) and :mod:`.report` do not import matplotlib (only
:mod:`.figures` and :mod:`.regime` draw).
"""
