"""Sphinx configuration of the manual: the Markdown pages (MyST) and the API reference
(numpydoc docstrings of the public API), one site.

Build it from the repository root with

    python -m sphinx -W --keep-going -n -b html docs build/site

(``-W`` turns every warning into an error, ``-n`` makes every cross-reference one that must
resolve). ``tests/test_docs.py`` runs the same build. The build needs no network: the
inventories of the projects the API reference links to are stored in ``docs/_inventories``
(``python scripts/inventories.py`` writes them from the installed packages).
"""

import re
from pathlib import Path

import engine

DOCS = Path(__file__).resolve().parent

project = "fretting-engine"
author = "fretting-engine contributors"
release = version = engine.__version__

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.intersphinx", "numpydoc"]
root_doc = "index"
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "_inventories"]
html_theme = "alabaster"
nitpicky = True

# Markdown: GitHub-style anchors for every heading, so that page.md#a-heading links resolve
# (and a link to a heading that does not exist is a warning, hence an error).
myst_heading_anchors = 6
myst_enable_extensions = ["html_image"]

# The API reference: numpydoc docstrings. Every public function and class has a summary line,
# every parameter and the return value documented (numpydoc's validation codes; a failure is
# a warning, made an error by -W).
autodoc_typehints = "none"  # the numpydoc "Parameters" sections carry the types and units
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validate = True
numpydoc_validation_checks = {"GL08", "SS01", "PR01", "PR02", "PR10", "RT01"}

# Links into the documentation of the projects the API uses, from stored inventories (no
# network at build time). The URLs are where each project publishes its documentation.
intersphinx_mapping = {
    name: (url, str(DOCS / "_inventories" / f"{name}.inv"))
    for name, url in {
        "numpy": "https://numpy.org/doc/stable",
        "pandas": "https://pandas.pydata.org/docs",
        "xarray": "https://docs.xarray.dev/en/stable",
        "h5py": "https://docs.h5py.org/en/stable",
    }.items()
}

# The pages of the site in the order the manual's index links them; index.md itself keeps
# plain links, readable on GitHub, and the table of contents is added here for the site only.
PAGE_LINK = re.compile(
    r"\]\(((?:tutorials|how-to|reference|explanation)/[\w/.-]+?)(?:\.md|\.rst)\)"
)


def _toctree(index_text: str) -> str:
    pages = list(dict.fromkeys(PAGE_LINK.findall(index_text)))
    return "\n\n```{toctree}\n:hidden:\n\n" + "\n".join(pages) + "\n```\n"


# A link from a page to a Markdown file outside docs/ (the README, the changelog, the
# performance history) is a plain link on GitHub; on the site it becomes a download of that
# file, since the site holds the pages under docs/ only.
OUTSIDE = re.compile(r"(?<!!)\[([^\]]+)\]\(((?:\.\./)+[^)#\s]+\.md)(#[^)\s]*)?\)")


def _outside_links_as_downloads(text: str, page: Path) -> str:
    def replace(match):
        target = (page.parent / match.group(2)).resolve()
        if DOCS in target.parents or not target.exists():
            return match.group(0)
        return f"{{download}}`{match.group(1)} <{match.group(2)}>`"

    return OUTSIDE.sub(replace, text)


def _read(app, docname, source):
    page = Path(app.env.doc2path(docname))
    if page.suffix == ".md":
        source[0] = _outside_links_as_downloads(source[0], page)
    if docname == root_doc:
        source[0] += _toctree(source[0])


def setup(app):
    app.connect("source-read", _read)
