"""Generated kernels in C where the C extension was built, in numpy elsewhere: :func:`prefer_compiled`.

A model generates numpy kernels (:mod:`contin.modelkit.codegen`) and, from them, the C source of an extension
module (:func:`contin.modelkit.codegen.c_extension_text`) that the package's install compiles when a C compiler
is there (``setup.py``, ``optional=True``).  :func:`prefer_compiled` gives the model one namespace of
kernels to call either way: the compiled function under each name the extension has, the numpy
function under every other name.  The two give the same numbers (the C code runs the numpy code's
operations in the same order; the tests compare them).

The environment variable ``CONTIN_COMPILED=0`` keeps the numpy kernels (to compare or to debug).
"""

from __future__ import annotations

import ast
import importlib
import math
import os
import types
from collections.abc import Callable, Mapping

import numpy as np

__all__ = ["prefer_compiled", "compiled_enabled", "optional_extension"]


def compiled_enabled() -> bool:
    """False when the environment variable ``CONTIN_COMPILED`` is ``0`` (or ``false``, ``no``, ``off``)."""
    return os.environ.get("CONTIN_COMPILED", "1").strip().lower() not in ("0", "false", "no", "off")


def optional_extension(name: str) -> types.ModuleType | None:
    """The C extension module ``name`` (dotted), or None where the install did not build it or ``CONTIN_COMPILED=0``."""
    if not compiled_enabled():
        return None
    try:
        return importlib.import_module(name)
    except ImportError:
        return None


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


def _station_inputs(inputs: tuple, stacked: int) -> tuple[list, tuple[int, ...]] | None:
    """The compiled kernel's inputs for a kernel taking ``stacked`` variables in its first argument
    ``(stacked, *stations)``: each variable, then each array parameter, flattened over the stations
    (array parameters broadcast to them first; numbers stay numbers); and the station shape.  None for
    inputs of another shape (the numpy kernel answers them)."""
    y = inputs[0]
    if np.ndim(y) < 1 or np.shape(y)[0] != stacked:
        return None
    stations = np.shape(y)[1:]
    try:
        params = [np.broadcast_to(p, stations).reshape(-1) if np.ndim(p) else p for p in inputs[1:]]
    except ValueError:
        return None
    return [*np.reshape(y, (stacked, math.prod(stations))), *params], stations


def _returning_kernel(compiled: Callable, fallback: Callable, per_element: bool,
                      shapes: list[tuple[int, ...]], stacked: int = 0) -> Callable:
    def kernel(*inputs):
        args, stations = inputs, ()
        if stacked:
            flat = _station_inputs(inputs, stacked)
            if flat is None:
                return fallback(*inputs)
            args, stations = flat
        m = (math.prod(stations) if stacked else np.shape(inputs[0])[0]) if per_element else None
        outputs = [np.zeros(shape + (m,) if per_element else shape or (1,)) for shape in shapes]
        try:
            compiled(*args, *outputs)
        except TypeError:  # as for the out= kernels: numpy takes what the extension does not
            return fallback(*inputs)
        if stacked:  # back to the station shape; numbers for a single station, as numpy gives
            outputs = [o.reshape(shape + stations)[()] for o, shape in zip(outputs, shapes)]
        if not per_element:  # the numbers of a single element are numbers, as numpy's are
            outputs = [float(o[0]) if not shape else o for o, shape in zip(outputs, shapes)]
        return tuple(outputs) if len(outputs) > 1 else outputs[0]

    kernel.__name__ = kernel.__qualname__ = fallback.__name__
    kernel.__doc__ = fallback.__doc__
    kernel.__wrapped__ = fallback
    return kernel


def prefer_compiled(kernels: types.ModuleType, extension: str,
                    rows: Mapping[str, int] | None = None) -> tuple[types.ModuleType, bool]:
    """The kernels of ``kernels`` with those of the C extension ``extension`` in their place, if it imports.

    Parameters
    ----------
    kernels : module
        The generated numpy module.
    extension : str
        Dotted name of the compiled extension.
    rows : mapping of str to int or None
        Name -> output rows of each kernel the extension carries that fills an ``out`` argument (called
        ``name(*inputs, out)``).  The kernels that return their outputs are those of the extension's
        ``RETURNS`` (see :func:`contin.modelkit.codegen.c_extension_text`).

    Returns
    -------
    namespace : module
        A new module object holding every public name of ``kernels``; each name in ``rows`` is the
        compiled kernel behind the numpy kernel's signature (``name(*inputs, out=None)``), and so is
        each kernel of the extension's ``RETURNS`` (``name(*inputs)``), falling back on the numpy
        kernel for inputs the extension does not take.  A kernel of the extension's ``STACKED``
        (``name -> k``) takes its ``k`` variables stacked, ``(k, *stations)`` with any station shape,
        and its parameters as numbers or arrays that broadcast to the stations: the namespace's
        kernel passes the compiled one each variable and each array parameter flattened over the
        stations (a copy where they are not contiguous, or where a parameter is broadcast) and
        gives the outputs the station shape, as numpy does.
    compiled : bool
        Whether the extension was imported (False also when ``CONTIN_COMPILED=0``).
    """
    namespace = types.ModuleType(kernels.__name__, kernels.__doc__)
    namespace.__dict__.update({k: v for k, v in vars(kernels).items() if not k.startswith("__")})
    module = optional_extension(extension)
    if module is None:
        return namespace, False
    rows = dict(rows or {})
    returns = ast.literal_eval(getattr(module, "RETURNS", "{}"))
    stacked = ast.literal_eval(getattr(module, "STACKED", "{}"))
    if any(not hasattr(module, name) or not hasattr(kernels, name) for name in [*rows, *returns]):
        # an extension built from another version of the generated source: use none of it
        return namespace, False
    for name, n in rows.items():
        setattr(namespace, name, _kernel(getattr(module, name), getattr(kernels, name), n))
    for name, (per_element, shapes) in returns.items():
        setattr(namespace, name, _returning_kernel(getattr(module, name), getattr(kernels, name), per_element,
                                                   [tuple(s) for s in shapes], stacked.get(name, 0)))
    return namespace, True
