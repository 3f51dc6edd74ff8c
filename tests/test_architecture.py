"""The import layering of docs/explanation/architecture.md holds in engine/ (parsed with ast,
nothing run).

Each module of engine/ belongs to a unit (a subpackage such as ``solvers`` or a top-level
module such as ``grid``); the table in docs/explanation/architecture.md says which layer each
unit is in and which layers it may import. Every ``import``/``from … import`` of the engine, at
module
level or inside a function, must respect it. Also: only engine/cli.py touches
``MPI.COMM_WORLD``; the analysis layer imports no writer; ``engine.analysis.report`` (and the
results reader) import without matplotlib.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
ENGINE = REPO / "engine"
WRITERS = {"hdf5", "collective", "lock", "salvage", "identity", "progress"}


def _layer_table() -> tuple[dict[str, str], dict[str, set[str]]]:
    """(unit -> layer, layer -> layers it may import) from docs/explanation/architecture.md."""
    text = (REPO / "docs" / "explanation" / "architecture.md").read_text()
    section = text.split("# Architecture", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| ")][1:]
    layer_of, allowed = {}, {}
    for row in rows:
        layer, modules, may_import = (cell.strip() for cell in row.strip("|").split("|"))
        for unit in re.findall(r"`([\w.]+)`", modules):
            layer_of[unit] = layer
        words = [word.strip() for word in may_import.split(",")]
        allowed[layer] = {layer} | {word for word in words if word != "nothing of the engine"}
    return layer_of, allowed


def _unit(module: str) -> str:
    """Unit of a dotted module name: ``engine.solvers.contact`` -> ``solvers``."""
    parts = module.split(".")
    if len(parts) == 1:
        return "__init__"
    return parts[1]


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(REPO).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, runtime: bool = False) -> list[str]:
    """Every engine module that ``path`` imports (absolute names, relative ones resolved);
    ``runtime``: without the imports of ``if TYPE_CHECKING:`` blocks (never executed)."""
    module = _module_name(path)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    tree = ast.parse(path.read_text(), filename=str(path))
    if runtime:
        for node in ast.walk(tree):
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
                node.body = []
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
                names = [f"{target}.{alias.name}" for alias in node.names]
                found += [target] + [name for name in names if _is_module(name)]
            else:
                found.append(node.module or "")
                found += [
                    f"{node.module}.{a.name}"
                    for a in node.names
                    if _is_module(f"{node.module}.{a.name}")
                ]
    return [name for name in found if name == "engine" or name.startswith("engine.")]


def _is_module(name: str) -> bool:
    path = REPO.joinpath(*name.split("."))
    return path.with_suffix(".py").exists() or (path / "__init__.py").exists()


def _engine_files() -> list[Path]:
    return sorted(ENGINE.rglob("*.py"))


def test_the_table_names_every_unit_of_the_engine():
    layer_of, allowed = _layer_table()
    units = {_unit(_module_name(path)) for path in _engine_files()}
    assert units == set(layer_of), "docs/explanation/architecture.md: units missing or unknown"
    assert set().union(*allowed.values()) <= set(allowed), "may import: unknown layer name"


def test_every_import_respects_the_layers():
    layer_of, allowed = _layer_table()
    broken = []
    for path in _engine_files():
        source = layer_of[_unit(_module_name(path))]
        for target in _imports(path):
            if target == "engine":
                continue  # the package itself (engine.__version__)
            if layer_of[_unit(target)] not in allowed[source]:
                broken.append(f"{path.relative_to(REPO)} ({source}) imports {target}")
    assert not broken, "\n".join(broken)


def _import_graph() -> dict[str, set[str]]:
    """module -> the engine modules it imports when it runs, at module level or inside a
    function (``if TYPE_CHECKING:`` imports left out: they never run). The package
    ``engine`` itself is left out as a target: it only gathers the public API, and every
    module of the engine runs it first anyway."""
    graph = {}
    for path in _engine_files():
        module = _module_name(path)
        targets = set(_imports(path, runtime=True)) - {"engine", module}
        graph[module] = {target for target in targets if _is_module(target)}
    return graph


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for target in sorted(graph.get(node, ())):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def test_the_circle_finder_finds_a_circle_through_a_function_local_import():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _circles(graph) == [["a", "b", "c"]]
    assert _circles({"a": {"b"}, "b": set()}) == []


def test_no_import_circles_between_engine_modules():
    """No module imports, directly or through others, a module that imports it back,
    function-local imports counted."""
    circles = _circles(_import_graph())
    assert not circles, "import circles:\n" + "\n".join(" <-> ".join(c) for c in circles)


def test_the_analysis_layer_imports_no_writer():
    for path in sorted((ENGINE / "analysis").glob("*.py")):
        for target in _imports(path):
            assert not (target.startswith("engine.output.") and target.split(".")[2] in WRITERS), (
                f"{path.name} imports the writer {target}"
            )


def test_only_the_entry_point_touches_comm_world():
    for path in _engine_files():
        tree = ast.parse(path.read_text())
        touches = any(
            isinstance(node, ast.Attribute) and node.attr == "COMM_WORLD" for node in ast.walk(tree)
        )
        assert not touches or path == ENGINE / "cli.py", f"{path} uses MPI.COMM_WORLD"


@pytest.mark.parametrize(
    "module",
    [
        "engine.analysis.report",
        "engine.analysis.results",
        "engine.analysis.fretting",
        "engine.analysis.fretting_report",
    ],
)
def test_post_processing_tables_do_not_import_matplotlib(module):
    code = f"import sys, {module}; assert 'matplotlib' not in sys.modules, 'matplotlib'"
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def _package_node(module: str) -> str:
    """The unit of ``module`` in the package graph: its package when that package holds no
    package of its own (``engine.study.kinds.base`` -> ``engine.study.kinds``), else the
    module itself (``engine.study.outcome``, ``engine.run``)."""
    parts = module.split(".")
    package = REPO.joinpath(*parts[:-1])
    if len(parts) > 1 and (package / "__init__.py").exists():
        holds_packages = any((child / "__init__.py").exists() for child in package.iterdir())
        if not holds_packages:
            return ".".join(parts[:-1])
    return module


def test_no_import_circles_between_packages():
    """The study-file parser sits above the loading kinds it dispatches to, and no package
    imports one that imports it back (function-local imports counted)."""
    graph: dict[str, set[str]] = {}
    for module, targets in _import_graph().items():
        node = _package_node(module)
        graph.setdefault(node, set()).update(
            _package_node(target) for target in targets if _package_node(target) != node
        )
    circles = _circles(graph)
    assert not circles, "package circles:\n" + "\n".join(" <-> ".join(c) for c in circles)


#: Function-local imports are for optional or heavy dependencies (matplotlib, xarray, SciPy
#: where a search needs it, pandas, tqdm, pyFFTW, MPI where its initialisation must wait);
#: everything else is imported at the top of the module.
MAX_LOCAL_IMPORTS = 40


def test_imports_inside_functions_are_few():
    local = []
    for path in _engine_files():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                local += [
                    f"{path.relative_to(REPO)}:{inner.lineno}"
                    for inner in ast.walk(node)
                    if isinstance(inner, ast.Import | ast.ImportFrom)
                ]
    assert len(local) <= MAX_LOCAL_IMPORTS, "\n".join(local)
