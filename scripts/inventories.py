"""Write the intersphinx inventories of the manual (docs/_inventories/NAME.inv) from the
installed packages, so that the site builds without network access.

An inventory (Sphinx's ``objects.inv``, version 2) lists the objects a project documents and
the page of its documentation that describes each. The published inventories of numpy,
pandas, xarray and h5py are not fetched here: this script lists the public objects of the
installed packages (their top-level classes and functions and the public methods and
attributes of those classes) and gives each the address its project's documentation uses
for it (``reference/generated/numpy.NAME.html`` for numpy, ``reference/api/pandas.NAME.html``
for pandas, ``generated/xarray.NAME.html`` for xarray, the hand-written pages of h5py's
high-level API). A link of the manual therefore lands on the right page of the current
documentation of each project.

    python scripts/inventories.py            # write docs/_inventories/*.inv
    python scripts/inventories.py --check    # exit 1 if a stored inventory lacks an object
                                             # the manual refers to
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import sys
import zlib
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
FOLDER = REPO / "docs" / "_inventories"

# The address of an object's page, from its full name, in each project's documentation.
PROJECTS = {
    "numpy": lambda name: f"reference/generated/{name}.html#{name}",
    "pandas": lambda name: f"reference/api/{name}.html#{name}",
    "xarray": lambda name: f"generated/{name}.html#{name}",
}
# h5py documents its high-level classes on one page each, not one page per object.
H5PY_PAGES = {
    "File": "high/file.html",
    "Group": "high/group.html",
    "Dataset": "high/dataset.html",
    "AttributeManager": "high/attr.html",
}
# Objects the manual refers to: a stored inventory must hold them.
REQUIRED = {
    "numpy": ["numpy.ndarray"],
    "pandas": ["pandas.DataFrame"],
    "xarray": ["xarray.Dataset", "xarray.DataArray"],
    "h5py": ["h5py.File", "h5py.Dataset"],
}


def _members(cls) -> list[tuple[str, str]]:
    """(role, name) of the public methods and attributes of a class."""
    found = []
    for name, value in vars(cls).items():
        if name.startswith("_"):
            continue
        role = "method" if callable(value) or isinstance(value, classmethod) else "attribute"
        found.append((role, name))
    return found


def objects(project: str) -> list[tuple[str, str, str]]:
    """(full name, domain:role, address) of the public objects of an installed package."""
    module = importlib.import_module(project)
    entries = [(project, "py:module", "index.html")]
    for name in sorted(dir(module)):
        if name.startswith("_"):
            continue
        value = getattr(module, name)
        full = f"{project}.{name}"
        if project == "h5py":
            if name not in H5PY_PAGES:
                continue
            page = H5PY_PAGES[name]
            entries.append((full, "py:class", f"{page}#{full}"))
            for role, member in _members(value):
                entries.append((f"{full}.{member}", f"py:{role}", f"{page}#{full}.{member}"))
            continue
        address = PROJECTS[project]
        if inspect.isclass(value):
            entries.append((full, "py:class", address(full)))
            for role, member in _members(value):
                entries.append((f"{full}.{member}", f"py:{role}", address(f"{full}.{member}")))
        elif callable(value):
            entries.append((full, "py:function", address(full)))
    return entries


def inventory(project: str) -> bytes:
    """The bytes of an objects.inv (version 2) of the installed ``project``."""
    version = importlib.import_module(project).__version__
    header = (
        "# Sphinx inventory version 2\n"
        f"# Project: {project}\n"
        f"# Version: {version}\n"
        "# The remainder of this file is compressed using zlib.\n"
    )
    lines = "".join(f"{name} {role} 1 {address} -\n" for name, role, address in objects(project))
    return header.encode() + zlib.compress(lines.encode(), 9)


def stored_names(path: Path) -> set[str]:
    data = path.read_bytes()
    body = data.split(b"\n", 4)[4]
    return {line.split(" ", 1)[0] for line in zlib.decompress(body).decode().splitlines()}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="check the stored inventories")
    args = parser.parse_args(argv)
    if args.check:
        missing = [
            f"{project}: {name}"
            for project, names in REQUIRED.items()
            for name in names
            if not (FOLDER / f"{project}.inv").exists()
            or name not in stored_names(FOLDER / f"{project}.inv")
        ]
        print("\n".join(missing) or "every inventory holds the objects the manual refers to")
        return 1 if missing else 0
    FOLDER.mkdir(parents=True, exist_ok=True)
    for project in REQUIRED:
        data = inventory(project)
        (FOLDER / f"{project}.inv").write_bytes(data)
        print(f"{project}: {len(objects(project))} objects, {len(data):,} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
