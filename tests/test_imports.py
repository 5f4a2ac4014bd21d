"""No module of ``contin``, ``models`` or ``studies`` imports a private name from another package.

A *package* here is the unit that owns its private names:

* each subpackage of ``contin`` (``contin.path``, ``contin.watch``, ...: the engine's layers), and each
  module directly in ``contin/`` on its own (``contin.palc``);
* each top-level subpackage of ``models`` (``contin_models.shell``, ``contin_models.contact``, ``contin_models.benchmarks``,
  ...), and each module directly in ``models/`` on its own (``contin_models.NAME``);
* ``studies`` (one package: the studies share ``studies._common``).

A name is private when it starts with one underscore (dunders such as ``__version__`` are not).  An
import is cross-package and private when any component after the target's package is private
(``from contin_models.shell.scene import _problem``, ``import contin_models.contact._generated``, ``from
contin_models.shell import _generated``).  The scan reads the import statements with :mod:`ast`, including
those inside functions, and resolves relative imports.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Import name -> folder: the folder models/ is installed as contin_models (pyproject.toml).
FOLDERS = {"contin": "contin", "contin_models": "models", "studies": "studies"}
PACKAGES = tuple(FOLDERS)


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    parts[0] = next(name for name, folder in FOLDERS.items() if folder == parts[0])
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def owner(module: str) -> str:
    """The package that owns ``module``'s private names (see the module docstring)."""
    parts = module.split(".")
    if parts[0] in ("contin", "contin_models") and len(parts) > 1:
        return ".".join(parts[:2])
    return parts[0]


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _resolve(importer: str, is_package: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = importer.split(".")
    if not is_package:
        base = base[:-1]
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def cross_package_private_imports(source: str, importer: str, is_package: bool = False) -> list[str]:
    """``"importer (line n): imported.name"`` for every private name ``source`` imports from another package."""
    mine = owner(importer)
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            module = _resolve(importer, is_package, node)
            targets = [f"{module}.{alias.name}" for alias in node.names if alias.name != "*"]
        else:
            continue
        for target in targets:
            if not target.split(".")[0] in PACKAGES or owner(target) == mine:
                continue
            inside = target.split(".")[len(owner(target).split(".")):]
            if any(_private(part) for part in inside):
                found.append(f"{importer} (line {node.lineno}): {target}")
    return found


def _modules() -> list[Path]:
    return sorted(p for folder in FOLDERS.values() for p in (ROOT / folder).rglob("*.py"))


def test_the_scan_sees_every_package() -> None:
    names = {_module_name(p) for p in _modules()}
    assert {"contin.palc", "contin_models.shell.problem", "contin_models.contact.barrier"} <= names
    assert any(n.startswith("studies.") for n in names)


def test_the_scan_flags_what_it_should() -> None:
    assert owner("contin_models.shell.scene") == "contin_models.shell" and owner("contin.app.cli") == "contin.app"
    assert owner("contin.palc") == "contin.palc" and owner("contin") == "contin"
    assert owner("studies._common") == "studies" and owner("contin_models.tools") == "contin_models.tools"
    assert _private("_problem") and not _private("__version__") and not _private("problem")
    bad = ("from contin_models.shell.scene import _problem\n"
           "def f():\n    import contin_models.contact._generated\n"
           "from ..shell import _generated\n"
           "from contin.app.cli import _json_ready as j\n")
    found = cross_package_private_imports(bad, "contin_models.contact.runner")
    # contin_models.contact._generated is the importer's own package
    assert [f.split(": ")[1] for f in found] == ["contin_models.shell.scene._problem", "contin_models.shell._generated",
                                                 "contin.app.cli._json_ready"]
    # the same package's private names are its own; relative imports resolve to the importer's package
    assert cross_package_private_imports("from . import _generated\nfrom ._generated import k\n",
                                         "contin_models.contact.barrier") == []
    assert cross_package_private_imports("from studies._common import x\n", "studies.peers") == []
    # the engine's layers own their private names: a subpackage's are not another's
    assert cross_package_private_imports("from ..results.branch import _helper\n", "contin.analyses.diagram") == \
        ["contin.analyses.diagram (line 1): contin.results.branch._helper"]
    assert cross_package_private_imports("from .deadload import _last\n", "contin.analyses.conjugate") == []


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(ROOT)))
def test_no_cross_package_private_import(path: Path) -> None:
    assert cross_package_private_imports(path.read_text(), _module_name(path), path.name == "__init__.py") == []
