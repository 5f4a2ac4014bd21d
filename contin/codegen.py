"""Generated numpy kernels from sympy element energies: emission, text and the byte-for-byte check.

The generation half of the energy-first tools (:mod:`contin.energy` assembles the kernels).  sympy
is imported inside the functions that need it only, so ``import contin.codegen`` (and ``import
contin``) never loads it; a model that ships a committed generated file never needs sympy at all.

Declaring elements
------------------
An :class:`Element` is a sympy energy of a few *local dofs* (symbols), per-element *parameters*
(symbols whose values differ between elements: stiffness, rest length, ...) and optionally the
continuation *parameter* ``p`` (a load potential such as ``-p * y``)::

    import sympy as sp
    from contin.codegen import Element, generate_kernels

    x1, y1, x2, y2, EA, L0, p = sp.symbols("x1 y1 x2 y2 EA L0 p", real=True)
    L = sp.sqrt((x2 - x1) ** 2 + (y2 - y1) ** 2)
    bar = Element("bar", EA / (2 * L0) * (L - L0) ** 2, dofs=(x1, y1, x2, y2), params=(EA, L0))
    y = sp.Symbol("y", real=True)
    load = Element("load", p * y, dofs=(y,), parameter=p)
    source = generate_kernels([bar, load], title="Bar and load kernels.",
                              generator="python make_kernels.py")

:func:`generate_kernels` returns the text of a plain-numpy module (commit it, and check it with
:func:`check_generated`); :func:`compile_kernels` executes the same text into a module object in
process, for quick work without a committed file.

What is emitted
---------------
For each element ``<name>`` with ``n`` local dofs, ``k`` parameters and ``P = n (n + 1) / 2`` packed
pairs, functions vectorised over ``m`` elements (``x``: ``(n, m)``, ``q``: ``(k, m)``, ``p``: scalar,
``v``: ``(n, m)``):

==============================================  ================  =========================================
``<name>_energy(x, q, p)``                      ``(m,)``          the energy
``<name>_gradient(x, q, p)``                    ``(n, m)``        ``dE/dx_a``
``<name>_hessian(x, q, p)``                     ``(P, m)``        ``d2E/dx_a dx_b``, ``a <= b`` (``pairs``)
``<name>_gradient_dp(x, q, p)``                 ``(n, m)``        ``d2E/dx_a dp``
``<name>_hessian_dp(x, q, p)``                  ``(P, m)``        ``d3E/dx_a dx_b dp``
``<name>_hessian_directional(x, v, q, p)``      ``(P, m)``        ``d/dt H_ab(x + t v)`` at ``t = 0``
==============================================  ================  =========================================

and a dictionary ``ELEMENTS`` describing each element (dof, parameter and pair order).  Each kernel's
rows share one common-subexpression elimination (temporaries ``_c0, _c1, ...``).

Reproducibility: the text depends only on the elements (their order, names and expressions), the
title and generator strings and the sympy version; nothing time- or machine-dependent is written, so
regenerating a committed file gives the same bytes (pin sympy's minor version: its
common-subexpression order may change between versions).
"""

from __future__ import annotations

import functools
import keyword
import types
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["Element", "kernel_printer", "cse_lines", "module_text", "generate_kernels", "compile_kernels",
           "write_generated", "check_generated", "GeneratedFileOutOfDate"]

#: Names a generated kernel uses for itself: user symbols may not take them.
_RESERVED = {"numpy"}


@dataclass(frozen=True)
class Element:
    """One element type: a sympy energy of local dofs, element parameters and the continuation parameter.

    Parameters
    ----------
    name : str
        Prefix of the generated functions (a Python identifier).
    energy : sympy.Expr
        The element energy.  Its free symbols must be among ``dofs``, ``params`` and ``parameter``.
    dofs : sequence of sympy.Symbol
        The local degrees of freedom, in the order of the connectivity columns.
    params : sequence of sympy.Symbol
        Per-element constants, in the order of the parameter columns.
    parameter : sympy.Symbol, optional
        The continuation parameter, when the energy depends on it.
    doc : str
        One line describing the element, copied into the generated docstrings.
    """

    name: str
    energy: Any
    dofs: Sequence[Any]
    params: Sequence[Any] = ()
    parameter: Any = None
    doc: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "dofs", tuple(self.dofs))
        object.__setattr__(self, "params", tuple(self.params))
        symbols = list(self.dofs) + list(self.params) + ([self.parameter] if self.parameter is not None else [])
        names = [self.name] + [str(s) for s in symbols]
        for nm in names:  # they become Python names in the generated source
            if not nm.isidentifier() or keyword.iskeyword(nm) or nm.startswith("_") or nm in _RESERVED:
                raise ValueError(f"element {self.name!r}: {nm!r} is not usable as a generated name (a Python "
                                 f"identifier, not a keyword, not 'numpy', not starting with '_')")
        if len(set(names[1:])) != len(names) - 1:
            raise ValueError(f"element {self.name!r}: dof, parameter and p symbols must have distinct names")
        if not self.dofs:
            raise ValueError(f"element {self.name!r} has no dofs")
        stray = set(getattr(self.energy, "free_symbols", set())) - set(symbols)
        if stray:
            raise ValueError(f"element {self.name!r}: the energy depends on {sorted(map(str, stray))}, which are "
                             f"neither dofs, params nor the parameter")

    @property
    def pairs(self) -> tuple[tuple[int, int], ...]:
        """Local dof pairs ``(a, b)``, ``a <= b``, in the order of the packed Hessian rows."""
        n = len(self.dofs)
        return tuple((a, b) for a in range(n) for b in range(a, n))


@functools.cache
def _printer_class() -> type:
    from sympy.printing.numpy import NumPyPrinter

    class KernelPrinter(NumPyPrinter):
        """NumPy printer with plain reciprocals and square roots instead of float powers, and integer
        powers above 2 as products (``numpy.power`` is slow for them)."""

        def _print_Pow(self, expr: Any, rational: bool = False) -> str:
            base, exp = expr.base, expr.exp
            if exp.is_Integer or (exp.is_Rational and exp.q == 2):
                half = not exp.is_Integer
                k = int(exp * 2) if half else int(exp)  # for half-integer powers k counts halves
                b = f"numpy.sqrt({self._print(base)})" if half else self.parenthesize(base, 60)
                mag = abs(k)
                if half or mag <= 2:
                    core = b if mag == 1 else f"{b}**{mag}"
                else:  # numpy's power is slow for exponents other than 2: multiply, in parentheses since
                    # the product may stand in a denominator (``a/(b**2*b)``, not ``a/b**2*b``)
                    core = "(" + "*".join([f"{b}**2"] * (mag // 2) + [b] * (mag % 2)) + ")"
                return core if k > 0 else f"(1/{core})"
            return super()._print_Pow(expr, rational=rational)

    return KernelPrinter


def kernel_printer() -> Any:
    """The sympy printer of generated kernels: numpy with fully qualified ``numpy.`` names.

    Reciprocals and square roots print as ``1/x`` and ``numpy.sqrt``, integer powers above 2 as
    products (faster than ``numpy.power``).

    Returns
    -------
    sympy.printing.numpy.NumPyPrinter
        A fresh printer (its class is ``KernelPrinter``).
    """
    return _printer_class()(settings={"fully_qualified_modules": True})


def cse_lines(exprs: Sequence[Any], targets: Sequence[str], printer: Any, indent: str = "    ",
              skip_zeros: bool = False) -> list[str]:
    """Common-subexpression elimination of ``exprs`` printed as ``_c<k> = ...`` then ``target = expr``.

    Parameters
    ----------
    exprs : sequence of sympy.Expr
        The results, eliminated together (shared temporaries are computed once).
    targets : sequence of str
        Where each result is assigned (``"_out[3]"``).
    printer : NumPyPrinter
        From :func:`kernel_printer`.
    indent : str
        Prefix of every line.
    skip_zeros : bool
        Omit assignments of an exact zero (the target is pre-zeroed).

    Returns
    -------
    list of str
        Source lines; temporaries are named ``_c0, _c1, ...`` in sympy's canonical order, so the
        text is deterministic.
    """
    import sympy

    repl, reduced = sympy.cse(list(exprs), symbols=sympy.numbered_symbols("_c"), order="canonical")
    lines = [f"{indent}{printer.doprint(lhs)} = {printer.doprint(rhs)}" for lhs, rhs in repl]
    for target, e in zip(targets, reduced):
        if skip_zeros and e == 0:
            continue
        lines.append(f"{indent}{target} = {printer.doprint(e)}")
    return lines


def module_text(preamble: str, exported: Sequence[str], constants: str, chunks: Sequence[str]) -> str:
    """Join the parts of a generated module: preamble, ``__all__``, constants, then the kernels.

    Parameters
    ----------
    preamble : str
        Module docstring and imports.
    exported : sequence of str
        Public names; ``__all__`` lists them sorted.
    constants : str
        Module-level constants with their docstrings.
    chunks : sequence of str
        Source of each generated function.

    Returns
    -------
    str
        The module text: parts separated by two blank lines, ending with one newline.
    """
    exports = "__all__ = [\n" + "".join(f'    "{f}",\n' for f in sorted(exported)) + "]"
    return "\n\n\n".join([preamble.rstrip("\n"), exports, constants, *chunks]) + "\n"


# ---- element kernels -----------------------------------------------------------------------------
def _signature(el: Element, kind: str) -> str:
    args = "_x, _v, _q, _p" if kind == "hessian_directional" else "_x, _q, _p"
    return f"def {el.name}_{kind}({args}):"


def _unpack(el: Element, used: set[str], directional: bool) -> list[str]:
    """``name = _x[a]`` lines for the symbols the kernel uses (in dof, param, parameter order)."""
    lines = [f"    {s} = _x[{a}]" for a, s in enumerate(el.dofs) if str(s) in used]
    if directional:
        lines += [f"    _v{a} = _v[{a}]" for a in range(len(el.dofs)) if f"_v{a}" in used]
    lines += [f"    {s} = _q[{k}]" for k, s in enumerate(el.params) if str(s) in used]
    if el.parameter is not None and str(el.parameter) in used:
        lines.append(f"    {el.parameter} = _p")
    return lines


_KINDS = {
    "energy": ("Energy of each element.", "``(m,)``"),
    "gradient": ("Gradient with respect to the local dofs.", "``(n, m)``, rows in dof order"),
    "hessian": ("Hessian, packed upper triangle.", "``(P, m)``, rows in ``pairs`` order"),
    "gradient_dp": ("Derivative of the gradient with respect to the parameter.", "``(n, m)``"),
    "hessian_dp": ("Derivative of the packed Hessian with respect to the parameter.", "``(P, m)``"),
    "hessian_directional": ("Directional derivative ``d/dt H(x + t v)`` at ``t = 0`` of the packed Hessian.",
                            "``(P, m)``"),
}


def _kernel(el: Element, kind: str, exprs: list[Any], printer: Any) -> str:
    import sympy

    what, shape = _KINDS[kind]
    dofs = ", ".join(map(str, el.dofs))
    params = ", ".join(map(str, el.params)) or "none"
    doc = [f'    """{el.name}: {what}', ""]
    if el.doc:
        doc += [f"    {el.doc}", ""]
    doc += [f"    Dofs ``({dofs})`` (rows of ``_x``{', and of the direction ``_v``' if kind == 'hessian_directional' else ''}); "
            f"parameters ``({params})`` (rows of ``_q``); ``_p`` the continuation parameter.",
            "", "    Returns", "    -------", f"    ndarray, shape {shape}", '    """']
    body = cse_lines(exprs, [f"_out[{k}]" for k in range(len(exprs))], printer, skip_zeros=True)
    used = set().union(*(sympy.sympify(e).free_symbols for e in exprs))
    names = {str(s) for s in used}
    lines = [_signature(el, kind)] + doc + _unpack(el, names, kind == "hessian_directional")
    lines.append(f"    _out = numpy.zeros(({len(exprs)},) + numpy.shape(_x[0]))")
    lines += body
    lines.append("    return _out[0]" if kind == "energy" else "    return _out")
    return "\n".join(lines)


def _derivatives(el: Element) -> dict[str, list[Any]]:
    import sympy

    x = list(el.dofs)
    g = [sympy.diff(el.energy, xa) for xa in x]
    H = [sympy.diff(g[a], x[b]) for a, b in el.pairs]
    v = sympy.symbols(f"_v0:{len(x)}", real=True)
    dH = [sum((sympy.diff(h, xc) * vc for xc, vc in zip(x, v)), sympy.Integer(0)) for h in H]
    p = el.parameter
    zero = sympy.Integer(0)
    return {"energy": [el.energy], "gradient": g, "hessian": H,
            "gradient_dp": [sympy.diff(e, p) if p is not None else zero for e in g],
            "hessian_dp": [sympy.diff(e, p) if p is not None else zero for e in H],
            "hessian_directional": dH}


def generate_kernels(elements: Sequence[Element], title: str = "Element kernels.",
                     generator: str = "contin.codegen.generate_kernels") -> str:
    """The text of a plain-numpy module with the kernels of ``elements`` (see the module docstring).

    Parameters
    ----------
    elements : sequence of Element
        The element types, in the order of the generated file.
    title : str
        First line of the module docstring.
    generator : str
        The command that regenerates the file, named in its docstring.

    Returns
    -------
    str
        The module source (deterministic: the same elements and sympy version give the same bytes).
    """
    import sympy

    names = [el.name for el in elements]
    if len(set(names)) != len(names):
        raise ValueError(f"element names must be distinct (got {names})")
    printer = kernel_printer()
    chunks, exported, described = [], ["ELEMENTS"], []
    for el in elements:
        for kind, exprs in _derivatives(el).items():
            chunks.append(_kernel(el, kind, [sympy.sympify(e) for e in exprs], printer))
            exported.append(f"{el.name}_{kind}")
        described.append(f'    "{el.name}": {{"dofs": {tuple(map(str, el.dofs))!r}, "params": '
                         f'{tuple(map(str, el.params))!r}, "parameter": '
                         f'{(str(el.parameter) if el.parameter is not None else None)!r}, "pairs": {el.pairs!r}}},')
    constants = ("ELEMENTS = {\n" + "\n".join(described) + "\n}\n"
                 '"""Each element\'s local dofs, parameters, continuation parameter and packed Hessian pairs."""')
    listing = "\n".join(f"* ``{el.name}``: {el.doc or sympy.sstr(el.energy)}" for el in elements)
    preamble = (f'"""{title}\n\nGENERATED by ``{generator}`` with :func:`contin.codegen.generate_kernels`.  Do not '
                f"edit by hand:\nchange the element energies and regenerate.  Plain numpy, vectorised over "
                f"elements (see\n:mod:`contin.codegen` for the kernels' signatures and :class:`contin.EnergyProblem` "
                f'to assemble them).\n\nElements:\n\n{listing}\n"""\n\nimport numpy\n')
    return module_text(preamble, exported, constants, chunks)


def compile_kernels(elements: Sequence[Element], name: str = "contin_kernels") -> types.ModuleType:
    """Generate the kernels of ``elements`` and execute the text into a module object (no file written).

    For quick work: the module behaves as an imported generated file (``module.__source__`` holds
    the text).  Generation costs sympy time at every call; commit the file for repeated use.

    Parameters
    ----------
    elements : sequence of Element
        The element types.
    name : str
        ``__name__`` of the module.

    Returns
    -------
    types.ModuleType
        The kernels and ``ELEMENTS``.
    """
    source = generate_kernels(elements, title=f"Kernels of {name}, generated in process.")
    module = types.ModuleType(name)
    exec(compile(source, f"<generated {name}>", "exec"), module.__dict__)  # noqa: S102 - our own text
    module.__source__ = source
    return module


# ---- writing and checking committed files --------------------------------------------------------
class GeneratedFileOutOfDate(AssertionError):
    """A committed generated file differs from what its generator produces now."""


def _text(source: str | Callable[[], str]) -> str:
    return source() if callable(source) else source


def write_generated(source: str | Callable[[], str], path: str | Path | None) -> str:
    """Write a generated module to ``path`` with ``\\n`` line endings (``None``: only return the text).

    Parameters
    ----------
    source : str or callable returning str
        The module text, or the function that generates it.
    path : str or Path or None
        Output file.

    Returns
    -------
    str
        The text.
    """
    text = _text(source)
    if path is not None:
        Path(path).write_text(text, encoding="utf-8", newline="\n")
    return text


def check_generated(source: str | Callable[[], str], path: str | Path, command: str = "") -> None:
    """Raise unless the committed file ``path`` holds exactly the bytes that ``source`` generates.

    Parameters
    ----------
    source : str or callable returning str
        The regenerated text, or the function that generates it.
    path : str or Path
        The committed file.
    command : str
        The command that regenerates it, quoted in the error.

    Raises
    ------
    GeneratedFileOutOfDate
        The file is missing or differs; the message gives the first differing line.
    """
    expected = _text(source).encode("utf-8")
    path = Path(path)
    actual = path.read_bytes() if path.exists() else None
    if actual == expected:
        return
    hint = f": run `{command}`" if command else ""
    if actual is None:
        raise GeneratedFileOutOfDate(f"{path} is missing{hint}")
    old, new = actual.decode("utf-8", "replace").splitlines(), expected.decode("utf-8").splitlines()
    k = next((i for i, (a, b) in enumerate(zip(old, new)) if a != b), min(len(old), len(new)))
    detail = (f"line {k + 1}: committed {old[k]!r} vs generated {new[k]!r}" if k < min(len(old), len(new))
              else f"lengths differ ({len(old)} vs {len(new)} lines)")
    raise GeneratedFileOutOfDate(f"{path} is out of date ({detail}){hint}")
