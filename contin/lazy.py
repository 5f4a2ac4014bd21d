"""Packages whose public names are imported on first use (PEP 562): one mechanism for the engine and the models.

A package lists its public names with the module that defines each and calls :func:`lazy_exports` at the
end of its ``__init__.py``::

    _EXPORTS = {"Branch": "results.branch", "continuation": "palc"}
    __all__ = list(_EXPORTS)
    lazy_exports(__name__, _EXPORTS)

``import package`` then costs nothing until a name is touched, and a light submodule (a scene's schema)
can be imported without the heavy ones beside it: ``contin --help`` and a refused scene load every
registered model's schema, and none of them imports numpy, scipy or matplotlib (``tests/test_startup.py``).
A submodule is also reachable as an attribute (``package.submodule`` after ``import package``); a
subpackage that calls ``lazy_exports(__name__, {})`` has that alone (``contin.app.scene`` after ``import
contin``).

A public function may share its module's name (``contin_models.shell_scene.build`` the function, in
``models/shell_scene/build.py``).  Importing that module binds it to the package under that name, which
would hide the function; the package's binding then takes the function instead, as an eager ``from .build
import build`` would have.
"""

from __future__ import annotations

import sys
import types
from collections.abc import Mapping
from importlib import import_module
from typing import Any

__all__ = ["lazy_exports", "lazy_module", "LazyModule"]


class _LazyPackage(types.ModuleType):
    """A package of :func:`lazy_exports`: a submodule bound under a public function's name binds the function."""

    def __setattr__(self, name: str, value: Any) -> None:
        exports = self.__dict__.get("_lazy_exports", {})
        if isinstance(value, types.ModuleType) and exports.get(name) == name and hasattr(value, name):
            value = getattr(value, name)
        super().__setattr__(name, value)


def lazy_exports(package: str, exports: Mapping[str, str]) -> None:
    """Make the names of ``exports`` (public name -> the submodule of ``package`` that defines it) import on use.

    Parameters
    ----------
    package : str
        The package's ``__name__``; call this from its ``__init__.py``.
    exports : mapping of str to str
        Each public name and the submodule (relative to ``package``) it is imported from.
    """
    module = sys.modules[package]
    exports = dict(exports)

    def __getattr__(name: str) -> Any:
        if name in exports:
            value = getattr(import_module(f".{exports[name]}", package), name)
            module.__dict__[name] = value  # later look-ups skip this function
            return value
        try:  # a submodule used as an attribute (``contin.app.scene.load_scene`` after ``import contin``)
            return import_module(f".{name}", package)
        except ModuleNotFoundError as exc:
            if exc.name != f"{package}.{name}":
                raise  # the submodule exists but needs something missing
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None

    def __dir__() -> list[str]:
        return sorted(set(module.__dict__) | set(exports))

    module.__dict__.update(_lazy_exports=exports, __getattr__=__getattr__, __dir__=__dir__)
    module.__class__ = _LazyPackage


class LazyModule:
    """A module imported when one of its attributes is first read (:func:`lazy_module`)."""

    __slots__ = ("_name", "_module")

    def __init__(self, name: str) -> None:
        object.__setattr__(self, "_name", name)
        object.__setattr__(self, "_module", None)

    def _loaded(self) -> types.ModuleType:
        if self._module is None:
            object.__setattr__(self, "_module", import_module(self._name))
        return self._module

    def __getattr__(self, attr: str) -> Any:
        return getattr(self._loaded(), attr)

    def __setattr__(self, attr: str, value: Any) -> None:  # on the module itself, as on a plain import
        setattr(self._loaded(), attr, value)

    def __delattr__(self, attr: str) -> None:
        delattr(self._loaded(), attr)

    def __repr__(self) -> str:
        return f"<module {self._name!r}, {'imported' if self._module is not None else 'imported on first use'}>"


def lazy_module(name: str) -> LazyModule:
    """The module ``name``, imported on the first read of one of its attributes.

    For a module the engine needs only on some paths (``scipy.linalg`` for dense factorizations and
    ARPACK, never on the default trace): ``sla = lazy_module("scipy.linalg")`` then ``sla.lu_factor(...)``
    imports it there, and a run that never gets there never pays for the import.
    """
    return LazyModule(name)
