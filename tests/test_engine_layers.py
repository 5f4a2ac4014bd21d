"""The engine's layers: ``contin/`` is built bottom up, and every import runs down or sideways, never up.

A *unit* is a subpackage of ``contin`` (``contin.path``) or a module directly in ``contin/`` (``contin.palc``).
:data:`LAYERS` puts every unit in a layer, bottom first, in the order ``contin/__init__.py``'s docstring gives.
Every ``.py`` file under ``contin/`` is parsed with :mod:`ast`; its imports (those inside functions and
under ``if TYPE_CHECKING`` too: a lazy import is still a dependency) make the import graph, and

* no circle runs through the units, nor through the modules;
* no module imports from a layer above its own;
* matplotlib is imported under ``contin/plot/`` only;
* what ``import contin`` and ``import contin.launch`` load before any function runs (their imports at
  module level, and their packages' ``__init__``) reaches no numpy, scipy, matplotlib or networkx.

No exception is needed today; one would be written here, with its reason, as an allowed edge.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ENGINE = Path(__file__).resolve().parents[1] / "contin"

#: The layers, bottom first: each a tuple of units.  ``contin`` is the package's own ``__init__`` (the
#: version and the lazy public names, importing only ``contin.lazy``).
LAYERS: list[tuple[str, ...]] = [
    ("contin", "contin.lazy"),
    ("contin.numerics",),
    ("contin.settings", "contin.problem"),
    ("contin.results",),
    ("contin.path",),
    ("contin.modelkit",),
    ("contin.watch",),
    ("contin.recorder", "contin.palc"),
    ("contin.analyses",),
    ("contin.plot",),
    ("contin.app",),
    ("contin.launch", "contin.__main__"),
]

#: Imports from a higher layer that are allowed, as ``(importer, imported module)``, each with its reason.
ALLOWED_UPWARD: dict[tuple[str, str], str] = {}

HEAVY = ("numpy", "scipy", "matplotlib", "networkx")


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ENGINE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


#: Every engine module by name, and its file.
MODULES: dict[str, Path] = {_module_name(p): p for p in sorted(ENGINE.rglob("*.py"))}


def unit(module: str) -> str:
    """The unit of an engine module: its subpackage of ``contin``, or the module itself."""
    parts = module.split(".")
    return ".".join(parts[:2])


def layer(module: str) -> int:
    """The index in :data:`LAYERS` of ``module``'s unit."""
    return next(i for i, units in enumerate(LAYERS) if unit(module) in units)


def _resolve(importer: str, is_package: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = importer.split(".") if is_package else importer.split(".")[:-1]
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _runs_on_import(tree: ast.Module) -> list[ast.AST]:
    """The nodes of ``tree`` that run when the module is imported: not inside a function, nor under ``if
    TYPE_CHECKING``."""
    found, todo = [], [tree]
    while todo:
        node = todo.pop()
        found.append(node)
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                continue
            if isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
                todo += child.orelse
                continue
            todo.append(child)
    return found


def imports(module: str, on_import_only: bool = False) -> list[tuple[str, int]]:
    """``(imported module, line)`` for every import statement of ``module``: an engine module (the most
    specific one a ``from X import name`` names: the submodule ``X.name`` where it is one) or the top-level
    name of another package.  ``on_import_only``: the statements that run when the module is imported."""
    path = MODULES[module]
    tree = ast.parse(path.read_text())
    found = []
    for node in _runs_on_import(tree) if on_import_only else ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, path.name == "__init__.py", node)
            names = [f"{target}.{a.name}" if f"{target}.{a.name}" in MODULES else target for a in node.names]
        else:
            continue
        for name in names:
            if name.split(".")[0] == "contin":
                while name not in MODULES:  # an attribute of a module: the module
                    name = name.rsplit(".", 1)[0]
            else:
                name = name.split(".")[0]
            if name != module:
                found.append((name, node.lineno))
    return found


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of ``graph`` with more than one node (Tarjan), sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def _engine_graph(by: str) -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for module in MODULES:
        for name, _ in imports(module):
            if name in MODULES:
                a, b = (unit(module), unit(name)) if by == "unit" else (module, name)
                if a != b:
                    graph.setdefault(a, set()).add(b)
    return graph


def test_every_unit_has_one_layer() -> None:
    placed = [u for units in LAYERS for u in units]
    assert len(placed) == len(set(placed))
    assert {unit(m) for m in MODULES} == set(placed)


def test_the_scan_reads_imports_as_python_does() -> None:
    # relative imports, the submodule a ``from package import name`` names, lazy imports inside functions
    assert "contin.results.io" in {n for n, _ in imports("contin.results.branch")}
    assert "contin.plot.style" in {n for n, _ in imports("contin.plot.branches")}
    assert "contin.modelkit.check" in {n for n, _ in imports("contin.palc")}
    assert "contin.modelkit.check" not in {n for n, _ in imports("contin.palc", on_import_only=True)}
    assert "numpy" in {n for n, _ in imports("contin.results.io")}  # inside functions and TYPE_CHECKING
    assert "numpy" not in {n for n, _ in imports("contin.results.io", on_import_only=True)}
    assert "contin" in {n for n, _ in imports("contin.app.cli")}  # the version, from the package itself
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert layer("contin.path.curve") < layer("contin.palc") < layer("contin.app.scene")


def test_no_circle_between_units() -> None:
    assert _cycles(_engine_graph("unit")) == []


def test_no_circle_between_modules() -> None:
    assert _cycles(_engine_graph("module")) == []


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_import_from_a_layer_above(module: str) -> None:
    upward = [f"{module} (line {line}) imports {name}, {LAYERS[layer(name)]} above {LAYERS[layer(module)]}"
              for name, line in imports(module)
              if name in MODULES and layer(name) > layer(module) and (module, name) not in ALLOWED_UPWARD]
    assert upward == []


def test_matplotlib_only_under_plot() -> None:
    found = [f"{module} (line {line})" for module in MODULES for name, line in imports(module)
             if name in ("matplotlib", "mpl_toolkits") and unit(module) != "contin.plot"]
    assert found == []
    assert any(name == "matplotlib" for name, _ in imports("contin.plot.branches"))


def _loaded_on_import(module: str) -> dict[str, list[str]]:
    """Every module ``import module`` runs, with the chain of imports that reaches it (statements at module
    level only; a package's ``__init__`` runs before its submodules)."""
    chains: dict[str, list[str]] = {}
    todo = [(module, [module])]
    while todo:
        name, chain = todo.pop()
        if name in chains:
            continue
        chains[name] = chain
        if name not in MODULES:
            continue
        parents = [".".join(name.split(".")[:k]) for k in range(1, name.count(".") + 1)]
        todo += [(p, chain + [p]) for p in parents]
        todo += [(n, chain + [n]) for n, _ in imports(name, on_import_only=True)]
    return chains


@pytest.mark.parametrize("entry", ["contin", "contin.launch"])
def test_the_package_and_its_launcher_load_nothing_heavy(entry: str) -> None:
    chains = _loaded_on_import(entry)
    assert {" -> ".join(chain) for name, chain in chains.items() if name in HEAVY} == set()
    assert "contin.lazy" in chains
