"""No code of ``models``, ``studies`` or ``contin`` reads or writes another object's private state.

An object's private attributes (one leading underscore, not a dunder) are its class's business: the class
may change them, and what other code needs from it is a public, documented accessor.  The scan reads
every module with :mod:`ast` and flags

* an attribute ``X._name`` where ``X`` is not ``self``, ``cls``, ``super()``, or (inside the body of class
  ``C``) the name ``C`` itself;
* ``getattr``, ``hasattr``, ``setattr`` or ``delattr`` of such an ``X`` with a literal private name.

A few reads of the standard library's internals have no public form; they are listed in :data:`ALLOWED`
with the reason.  Private *imports* across packages are ``tests/test_imports.py``'s.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("contin", "models", "studies")

#: ``(file, accessed expression)`` -> why it is allowed.
ALLOWED: dict[tuple[str, str], str] = {
    ("contin/app/cli.py", "argparse._SubParsersAction"):
        "argparse offers no public name for the type of its subcommand action (help formatting finds it)",
    ("contin/app/executors.py", "pool._processes"):
        "multiprocessing's pool offers no public list of its worker processes (a pool that lost one is stopped)",
}

_ACCESSORS = ("getattr", "hasattr", "setattr", "delattr")


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _own(owner: ast.expr, classes: list[str]) -> bool:
    """Whether ``owner`` is the object itself: ``self``, ``cls``, ``super()`` or the enclosing class's name."""
    if isinstance(owner, ast.Name):
        return owner.id in ("self", "cls") or (bool(classes) and owner.id == classes[-1])
    return (isinstance(owner, ast.Call) and isinstance(owner.func, ast.Name) and owner.func.id == "super"
            and not owner.args)


class _Scan(ast.NodeVisitor):
    def __init__(self) -> None:
        self.classes: list[str] = []
        self.found: list[tuple[int, str]] = []

    def visit_ClassDef(self, node: ast.ClassDef) -> None:
        self.classes.append(node.name)
        self.generic_visit(node)
        self.classes.pop()

    def visit_Attribute(self, node: ast.Attribute) -> None:
        if _private(node.attr) and not _own(node.value, self.classes):
            self.found.append((node.lineno, f"{ast.unparse(node.value)}.{node.attr}"))
        self.generic_visit(node)

    def visit_Call(self, node: ast.Call) -> None:
        if (isinstance(node.func, ast.Name) and node.func.id in _ACCESSORS and len(node.args) >= 2
                and isinstance(node.args[1], ast.Constant) and isinstance(node.args[1].value, str)
                and _private(node.args[1].value) and not _own(node.args[0], self.classes)):
            self.found.append((node.lineno, f"{ast.unparse(node.args[0])}.{node.args[1].value}"))
        self.generic_visit(node)


def private_state_accesses(source: str) -> list[tuple[int, str]]:
    """``(line, "owner._name")`` for every access of another object's private attribute in ``source``."""
    scan = _Scan()
    scan.visit(ast.parse(source))
    return sorted(scan.found)


@functools.lru_cache(maxsize=1)
def _accesses() -> dict[str, list[tuple[int, str]]]:
    """Every module's accesses, by path relative to the root (scanned once for all the tests).

    The generated kernels (``_generated.py``, ``_harmonic_generated.py``) are left out: they are straight-line
    arithmetic emitted by the codegen modules, which are scanned.
    """
    return {path.relative_to(ROOT).as_posix(): private_state_accesses(path.read_text())
            for folder in FOLDERS for path in sorted((ROOT / folder).rglob("*.py"))
            if not path.name.endswith("_generated.py")}


def test_the_scan_finds_private_accesses_and_allows_the_objects_own() -> None:
    source = ("class Cache:\n"
              "    _LIMIT = 3\n"
              "    def __init__(self, other):\n"
              "        self._items = []\n"
              "        self._n = Cache._LIMIT + len(super()._hidden)\n"
              "        self.size = other._items\n"
              "        self.__dict__.clear()\n"
              "    @classmethod\n"
              "    def make(cls):\n"
              "        return cls._LIMIT\n"
              "def peek(cache):\n"
              "    return cache._items, getattr(cache, '_n', 0), Cache._LIMIT, cache.store()._data\n")
    assert private_state_accesses(source) == [(6, "other._items"), (12, "Cache._LIMIT"), (12, "cache._items"),
                                              (12, "cache._n"), (12, "cache.store()._data")]


def test_every_allowed_access_is_still_there() -> None:
    """An entry of :data:`ALLOWED` whose access is gone is removed from the list, not left to excuse a new one."""
    found = {(rel, what) for rel, accesses in _accesses().items() for _, what in accesses}
    assert set(ALLOWED) <= found, sorted(set(ALLOWED) - found)


@pytest.mark.parametrize("folder", FOLDERS)
def test_no_module_reads_another_objects_private_state(folder: str) -> None:
    bad = [f"{rel}:{line}: {what}" for rel, accesses in _accesses().items() if rel.startswith(f"{folder}/")
           for line, what in accesses if (rel, what) not in ALLOWED]
    assert not bad, "\n".join(bad)
