"""Sphinx configuration of the API reference (numpydoc docstrings of the public API).

Build it with ``python -m sphinx -W -b html docs/reference/api build/api`` from the repository
root; ``tests/test_docs.py`` builds it with warnings as errors in every test run.
"""

import engine

project = "fretting-engine"
author = "fretting-engine contributors"
release = version = engine.__version__

extensions = ["sphinx.ext.autodoc", "numpydoc"]
root_doc = "index"
exclude_patterns = ["_build"]
html_theme = "alabaster"

autodoc_typehints = "none"  # the numpydoc "Parameters" sections carry the types and units
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
# Every public function and class: a summary line, every parameter and the return value
# documented (numpydoc's validation codes; a failure is a warning, made an error by -W).
numpydoc_validate = True
numpydoc_validation_checks = {"GL08", "SS01", "PR01", "PR02", "PR10", "RT01"}
