"""Generated kernels in C where the C extension was built, in numpy elsewhere: :func:`prefer_compiled`.

A model generates numpy kernels (:mod:`contin.codegen`) and, from them, the C source of an extension
module (:func:`contin.codegen.c_extension_text`) that the package's install compiles when a C compiler
is there (``setup.py``, ``optional=True``).  :func:`prefer_compiled` gives the model one namespace of
kernels to call either way: the compiled function under each name the extension has, the numpy
function under every other name.  The two give the same numbers (the C code runs the numpy code's
operations in the same order; the tests compare them).

The environment variable ``CONTIN_COMPILED=0`` keeps the numpy kernels (to compare or to debug).
"""

from __future__ import annotations

import importlib
import os
import types
from collections.abc import Callable, Mapping

import numpy as np

__all__ = ["prefer_compiled", "compiled_enabled"]


def compiled_enabled() -> bool:
    """False when the environment variable ``CONTIN_COMPILED`` is ``0`` (or ``false``, ``no``, ``off``)."""
    return os.environ.get("CONTIN_COMPILED", "1").strip().lower() not in ("0", "false", "no", "off")


def _kernel(compiled: Callable, fallback: Callable, rows: int) -> Callable:
    def kernel(*inputs, out=None):
        if out is None:
            out = np.empty((rows,) + np.shape(inputs[0]))
        try:
            compiled(*inputs, out)
        except TypeError:
            # the extension takes float64 arrays of one size (strided in one dimension) and numbers; numpy
            # takes anything that broadcasts
            return fallback(*inputs, out=out)
        return out

    kernel.__name__ = kernel.__qualname__ = fallback.__name__
    kernel.__doc__ = fallback.__doc__
    kernel.__wrapped__ = fallback
    return kernel


def prefer_compiled(kernels: types.ModuleType, extension: str, rows: Mapping[str, int]) -> tuple[types.ModuleType, bool]:
    """The kernels of ``kernels`` with those of the C extension ``extension`` in their place, if it imports.

    Parameters
    ----------
    kernels : module
        The generated numpy module.
    extension : str
        Dotted name of the compiled extension.
    rows : mapping of str to int
        Name -> output rows of each kernel the extension carries (called ``name(*inputs, out)``).

    Returns
    -------
    namespace : module
        A new module object holding every public name of ``kernels``; each name in ``rows`` is the
        compiled kernel behind the numpy kernel's signature (``name(*inputs, out=None)``), falling
        back on the numpy kernel for inputs the extension does not take.
    compiled : bool
        Whether the extension was imported (False also when ``CONTIN_COMPILED=0``).
    """
    namespace = types.ModuleType(kernels.__name__, kernels.__doc__)
    namespace.__dict__.update({k: v for k, v in vars(kernels).items() if not k.startswith("__")})
    if not compiled_enabled():
        return namespace, False
    try:
        module = importlib.import_module(extension)
    except ImportError:
        return namespace, False
    missing = [name for name in rows if not hasattr(module, name)]
    if missing:
        # an extension built from another version of the generated source: use none of it
        return namespace, False
    for name, n in rows.items():
        setattr(namespace, name, _kernel(getattr(module, name), getattr(kernels, name), n))
    return namespace, True
