"""Analysis layer: what runs after a study, on its results file (reader, report, figures).

Nothing here writes a results file or knows MPI; :mod:`.report` and :mod:`.reader` do not
import matplotlib (only :mod:`.figures` and :mod:`.regime` draw).
"""
