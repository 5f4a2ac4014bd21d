"""Generated numpy kernels from sympy element energies: emission, text and the byte-for-byte check.

The generation half of the energy-first tools (:mod:`contin.modelkit.energy` assembles the kernels).  sympy
is imported inside the functions that need it only, so ``import contin.modelkit.codegen`` (and ``import
contin``) never loads it; a model that ships a committed generated file never needs sympy at all.

Declaring elements
------------------
An :class:`Element` is a sympy energy of a few *local dofs* (symbols), per-element *parameters*
(symbols whose values differ between elements: stiffness, rest length, ...) and optionally the
continuation *parameter* ``p`` (a load potential such as ``-p * y``)::

    import sympy as sp
    from contin.modelkit.codegen import Element, generate_kernels

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

Writing your own generator
--------------------------
A model whose kernels need more than :class:`Element` (derivatives through a chain of changes of
variables, closed forms written by hand) writes its own generator from the same parts, which every
generator of the project uses: :func:`kernel_printer`; :func:`cse_lines` (one elimination, with an
optional prelude) or :class:`KernelBody` (temporaries accumulated over several steps, reused up to
sign, dead ones dropped, rows filled by :meth:`KernelBody.row_lines`); :func:`upper_pairs` (the
packed Hessian order) and :func:`emitted_helpers` (``_prepare``, ``_upper``, ``_unpack`` for the
generated module); :func:`function_header`, :func:`row_targets`, :func:`count_operations`;
:func:`module_text` to join the parts and :func:`generator_main` for the command line
(``--output PATH``, ``--check``)::

    if __name__ == "__main__":
        raise SystemExit(generator_main(None, generate_source, OUTPUT, "python -m my_model.codegen",
                                        "Generate my_model/_generated.py."))

Reproducibility: the text depends only on the elements (their order, names and expressions), the
title and generator strings and the sympy version; nothing time- or machine-dependent is written, so
regenerating a committed file gives the same bytes (pin sympy's minor version: its
common-subexpression order may change between versions).
"""

from __future__ import annotations

import functools
import keyword
import math
import re
import sys
import types
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["Element", "kernel_printer", "cse_lines", "module_text", "generate_kernels", "compile_kernels",
           "write_generated", "check_generated", "GeneratedFileOutOfDate", "upper_pairs", "emitted_helpers",
           "assignment_lines", "needed_assignments", "KernelBody", "row_targets", "count_operations",
           "function_header", "generator_main", "c_extension_text"]

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
        return upper_pairs(len(self.dofs))


def upper_pairs(n: int) -> tuple[tuple[int, int], ...]:
    """The packed upper-triangle order of a symmetric ``n x n`` matrix: ``(a, b)``, ``a <= b``, row by row.

    Every generated packed Hessian (``P = n (n + 1) / 2`` rows) lists its entries in this order; a
    generated module that needs it at run time embeds the same rule as ``_upper`` (:func:`emitted_helpers`).

    Parameters
    ----------
    n : int
        Size of the matrix (number of local variables).

    Returns
    -------
    tuple of (int, int)
        ``((0, 0), (0, 1), ..., (0, n-1), (1, 1), ..., (n-1, n-1))``.
    """
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
              skip_zeros: bool = False, prelude: Sequence[tuple[Any, Any]] = (),
              float_constants: bool = False) -> list[str]:
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
    prelude : sequence of (sympy.Symbol, sympy.Expr)
        Named quantities the results may use, in order; those needed are printed first
        (:func:`needed_assignments`).
    float_constants : bool
        Print a result that is a number as a float (``-1.0``: the row is filled by broadcasting).

    Returns
    -------
    list of str
        Source lines; temporaries are named ``_c0, _c1, ...`` in sympy's canonical order, so the
        text is deterministic.
    """
    import sympy

    repl, reduced = sympy.cse(list(exprs), symbols=sympy.numbered_symbols("_c"), order="canonical")
    lines = assignment_lines(needed_assignments(list(prelude) + list(repl), reduced), printer, indent)
    for target, e in zip(targets, reduced):
        if skip_zeros and e == 0:
            continue
        if float_constants and e.is_Number:
            e = sympy.Float(e)
        lines.append(f"{indent}{target} = {printer.doprint(e)}")
    return lines


def assignment_lines(assignments: Sequence[tuple[Any, Any]], printer: Any, indent: str = "    ") -> list[str]:
    """``name = value`` source lines, one per assignment.

    Parameters
    ----------
    assignments : sequence of (sympy.Symbol, sympy.Expr)
        In order.
    printer : NumPyPrinter
        From :func:`kernel_printer`.
    indent : str
        Prefix of every line.

    Returns
    -------
    list of str
    """
    return [f"{indent}{printer.doprint(lhs)} = {printer.doprint(rhs)}" for lhs, rhs in assignments]


def needed_assignments(assignments: Sequence[tuple[Any, Any]], results: Sequence[Any]) -> list[tuple[Any, Any]]:
    """The assignments that ``results`` need, directly or through other assignments, in their order.

    Parameters
    ----------
    assignments : sequence of (sympy.Symbol, sympy.Expr)
        Candidate definitions in order (a prelude, then temporaries); each may use the earlier ones.
    results : sequence of sympy.Expr
        What the kernel returns.

    Returns
    -------
    list of (sympy.Symbol, sympy.Expr)
        The needed assignments (dead ones dropped), in the order given.
    """
    import sympy

    need = set().union(*(sympy.sympify(e).free_symbols for e in results))
    keep = []
    for sym, rhs in reversed(list(assignments)):
        if sym in need:
            keep.append((sym, rhs))
            need |= rhs.free_symbols
    keep.reverse()
    return keep


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


# ---- kernel bodies built in steps ----------------------------------------------------------------
def _natural(name: str) -> tuple[str, int]:
    """Sort key: ``_c2`` before ``_c10``."""
    head = name.rstrip("0123456789")
    return (head, int(name[len(head):]) if len(head) < len(name) else -1)


def _trivial(e: Any) -> bool:
    """An atom or minus an atom (free to substitute: any other factor costs an operation per use)."""
    coeff, core = e.as_coeff_Mul()
    return core.is_Atom and (coeff == 1 or coeff == -1 or core.is_Number)


class KernelBody:
    """Assignments of one kernel body built in several steps, common subexpressions named ``_c0, _c1, ...``.

    Where :func:`cse_lines` eliminates one list of results at once, a body accumulates the
    temporaries of successive steps (a chain rule through several changes of variables, say):
    :meth:`reduce` and :meth:`name` eliminate common subexpressions within a step and against all
    earlier ones, also up to sign, and :meth:`lines` prints the prelude definitions and temporaries
    the final results need (dead assignments dropped), deleting each local array after its last use.
    Temporaries are numbered in the order they are created, so the text is deterministic.
    """

    def __init__(self) -> None:
        import sympy

        self.assignments: list[tuple[Any, Any]] = []
        self.names = sympy.numbered_symbols("_c")
        self.known: dict = {}  # right-hand side -> the symbol it is assigned to

    def _assign(self, rhs: Any, sym: Any = None) -> Any:
        """A symbol (or minus a symbol) holding ``rhs``, reusing an earlier assignment if any."""
        if rhs in self.known:
            return self.known[rhs]
        if -rhs in self.known:
            return -self.known[-rhs]
        sym = next(self.names) if sym is None else sym
        self.assignments.append((sym, rhs))
        self.known[rhs] = sym
        return sym

    def reduce(self, exprs: Sequence[Any]) -> list[Any]:
        """Record the common subexpressions of ``exprs``; return the reduced expressions.

        Subexpressions that are a symbol or minus a symbol are substituted instead of assigned (a
        negation costs as much as any other array operation), and so are repeats of earlier
        assignments up to the sign (which ``sympy.cse`` does not detect across calls or signs).

        Parameters
        ----------
        exprs : sequence of sympy.Expr

        Returns
        -------
        list of sympy.Expr
            ``exprs`` in terms of the body's temporaries.
        """
        import sympy

        repl, red = sympy.cse(list(exprs), symbols=self.names, order="canonical")
        subs: dict = {}
        for lhs, rhs in repl:
            rhs = rhs.xreplace(subs)
            if _trivial(rhs):
                subs[lhs] = rhs
            else:
                sym = self._assign(rhs, lhs)
                if sym != lhs:
                    subs[lhs] = sym
        return [e.xreplace(subs) for e in red]

    def name(self, exprs: Sequence[Any]) -> list[Any]:
        """Like :meth:`reduce`, but every result is a symbol or minus a symbol (named if needed).

        The returned list holds, for each of ``exprs`` (sympy expressions), a temporary, a negated
        temporary or an atom: what the next step of a chain rule is written in.
        """
        out = []
        for e in self.reduce(exprs):
            coeff, core = e.as_coeff_Mul()
            if _trivial(e):
                out.append(e)
            elif coeff == -1:
                out.append(-self._assign(core))
            else:
                out.append(self._assign(e))
        return out

    def lines(self, prelude: Sequence[tuple[Any, Any]], results: Sequence[Any], printer: Any,
              targets: Sequence[str] | None = None) -> list[str]:
        """The prelude definitions and assignments that ``results`` need, in order, printed.

        With ``targets`` (one per result) the results are printed as ``target = result`` lines,
        and every local array is deleted right after its last use: its memory is reused by the
        next temporaries instead of piling up (which keeps the working set in cache and the heap
        small).

        Parameters
        ----------
        prelude : sequence of (sympy.Symbol, sympy.Expr)
            Named quantities computed first, in order (kernel inputs are free symbols).
        results : sequence of sympy.Expr
            Reduced results (from :meth:`reduce` or :meth:`name`).
        printer : NumPyPrinter
            From :func:`kernel_printer`.
        targets : sequence of str, optional
            Where each result is assigned.

        Returns
        -------
        list of str
            Source lines indented by four spaces.
        """
        import sympy

        keep = needed_assignments(list(prelude) + self.assignments, results)
        out = assignment_lines(keep, printer)
        if targets is None:
            return out
        statements = [rhs.free_symbols for _, rhs in keep] + [sympy.sympify(e).free_symbols for e in results]
        out += [f"    {t} = {printer.doprint(e)}" for t, e in zip(targets, results)]
        local = {sym for sym, _ in keep}
        last = {}
        for k, used in enumerate(statements):
            for sym in used & local:
                last[sym] = k
        dead: dict = {}
        for sym, k in last.items():
            dead.setdefault(k, []).append(sym)
        lines = []
        for k, line in enumerate(out):
            lines.append(line)
            if k in dead and k < len(out) - 1:  # the last ones go at the return anyway
                lines.append("    del " + ", ".join(sorted((str(sym) for sym in dead[k]), key=_natural)))
        return lines

    def row_lines(self, prelude: Sequence[tuple[Any, Any]], rows: Sequence[Any], printer: Any, like: str,
                  out: str = "out") -> list[str]:
        """Body of a kernel returning its results as the rows of one ``(len(rows), m)`` array.

        The array is the optional argument ``out`` (allocated when ``None``, with the shape of the
        argument ``like`` after the row count); row ``k`` is ``rows[k]``.

        Parameters
        ----------
        prelude : sequence of (sympy.Symbol, sympy.Expr)
            As for :meth:`lines`.
        rows : sequence of sympy.Expr
            Reduced results, one per row.
        printer : NumPyPrinter
            From :func:`kernel_printer`.
        like : str
            Name of a kernel argument of shape ``(m,)``.
        out : str
            Name of the output argument.

        Returns
        -------
        list of str
            Allocation, body and ``return out``, indented by four spaces.
        """
        return ([f"    if {out} is None:", f"        {out} = numpy.empty(({len(rows)},) + numpy.shape({like}))"]
                + self.lines(prelude, rows, printer, row_targets(out, len(rows))) + [f"    return {out}"])


def row_targets(array: str, n: int) -> list[str]:
    """``["array[0]", ..., "array[n-1]"]``: the targets of the rows of a generated ``(n, m)`` output.

    Parameters
    ----------
    array : str
        Name of the output array in the generated code.
    n : int
        Number of rows.

    Returns
    -------
    list of str
    """
    return [f"{array}[{k}]" for k in range(n)]


def count_operations(lines: Sequence[str]) -> int:
    """Array operations in printed code: arithmetic (constant folding excepted) and calls.

    What a vectorised kernel pays per element batch; a generator compares variants of a kernel by it.

    Parameters
    ----------
    lines : sequence of str
        Printed statements (indentation is ignored).

    Returns
    -------
    int
    """
    import ast

    count = 0
    for node in ast.walk(ast.parse("\n".join(line.strip() for line in lines))):
        if isinstance(node, ast.BinOp):
            count += not (isinstance(node.left, ast.Constant) and isinstance(node.right, ast.Constant))
        elif isinstance(node, ast.UnaryOp):
            count += not isinstance(node.operand, ast.Constant)
        elif isinstance(node, ast.Call):
            count += 1
    return count


def function_header(name: str, arguments: Sequence[str], doc: Sequence[str]) -> list[str]:
    """``def name(arguments):`` and its docstring, as source lines.

    Parameters
    ----------
    name : str
        The function's name.
    arguments : sequence of str
        Its parameters (``"out=None"`` for a default).
    doc : sequence of str
        Docstring lines without indentation (the first is the summary; empty strings are blank lines).

    Returns
    -------
    list of str
    """
    lines = [f"def {name}({', '.join(arguments)}):", '    """' + doc[0]]
    lines += [("    " + d) if d else "" for d in doc[1:]]
    lines.append('    """')
    return lines


#: Source of the helpers a generated module may embed (it imports numpy only); see :func:`emitted_helpers`.
_HELPERS = {
    "_prepare": ("def _prepare(*args):\n"
                 "    arrays = [numpy.asarray(a, dtype=float) for a in args]\n"
                 "    return (*arrays, numpy.broadcast_shapes(*(a.shape for a in arrays)))\n"),
    "_upper": ("def _upper(n):\n"
               "    return tuple((a, b) for a in range(n) for b in range(a, n))\n"),
    "_unpack": ("def _unpack(packed, n):\n"
                "    idx = numpy.empty((n, n), dtype=numpy.intp)\n"
                "    for k, (a, b) in enumerate(_upper(n)):\n"
                "        idx[a, b] = idx[b, a] = k\n"
                "    return numpy.moveaxis(packed[idx], (0, 1), (-2, -1)).copy()\n"),
}
_HELPER_NEEDS = {"_unpack": ("_upper",)}


def emitted_helpers(*names: str) -> str:
    """Source of run-time helpers for a generated module (plain numpy, no import of contin).

    ``_prepare(*args)``
        The arguments as float arrays and their broadcast shape (``(*arrays, shape)``).
    ``_upper(n)``
        The packed upper-triangle pair order, :func:`upper_pairs`.
    ``_unpack(packed, n)``
        A packed ``(P, ...)`` array to the symmetric ``(..., n, n)`` one.

    Parameters
    ----------
    *names : str
        Helpers to emit; those they use are added (``_unpack`` needs ``_upper``).

    Returns
    -------
    str
        Their definitions in the order above, separated by two blank lines, ending with a newline.
    """
    unknown = set(names) - set(_HELPERS)
    if unknown:
        raise ValueError(f"unknown helpers {sorted(unknown)} (known: {list(_HELPERS)})")
    wanted = set(names) | {dep for nm in names for dep in _HELPER_NEEDS.get(nm, ())}
    return "\n\n".join(src for nm, src in _HELPERS.items() if nm in wanted)


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
    body = cse_lines(exprs, row_targets("_out", len(exprs)), printer, skip_zeros=True)
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
                     generator: str = "contin.generate_kernels") -> str:
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
    preamble = (f'"""{title}\n\nGENERATED by ``{generator}`` with :func:`contin.generate_kernels`.  Do not '
                f"edit by hand:\nchange the element energies and regenerate.  Plain numpy, vectorised over "
                f"elements (see\n:mod:`contin.modelkit.codegen` for the kernels' signatures and "
                f':class:`contin.EnergyProblem` to assemble them).\n\nElements:\n\n{listing}\n"""\n\nimport numpy\n')
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


def generator_main(argv: list[str] | None, generate_source: Callable[[], str], default_output: Path, prog: str,
                   description: str, companions: Sequence[tuple[Callable[[], str], Path]] = ()) -> int:
    """Command line of a generator: write the module, or with ``--check`` exit 1 if it is out of date.

    A generator script ends with ``raise SystemExit(generator_main(None, generate_source, OUTPUT,
    "python -m my.codegen", "..."))``: ``--output PATH`` writes elsewhere than the committed file,
    ``--check`` writes nothing and fails when the committed file differs (:func:`check_generated`).

    Parameters
    ----------
    argv : list of str or None
        Arguments (``None``: ``sys.argv[1:]``).
    generate_source : callable
        Returns the full text of the generated module.
    default_output : Path
        The committed generated file.
    prog, description : str
        For the help text (``prog`` is also the command the out-of-date message suggests).
    companions : sequence of (callable, Path)
        Files generated from the committed module (e.g. its C extension's source,
        :func:`c_extension_text`): without ``--output``, each is written (or checked) after it.

    Returns
    -------
    int
        The exit status.
    """
    import argparse

    parser = argparse.ArgumentParser(prog=prog, description=description)
    parser.add_argument("--output", type=Path, default=default_output, help="file to write")
    parser.add_argument("--check", action="store_true",
                        help="do not write; exit 1 if the file differs from what would be generated")
    args = parser.parse_args(argv)
    files = [(generate_source, args.output)]
    if args.output == default_output:
        files += list(companions)
    for source, path in files:
        if args.check:
            try:
                check_generated(source, path, prog)
            except GeneratedFileOutOfDate as exc:
                print(exc, file=sys.stderr)
                return 1
        else:
            write_generated(source, path)
    return 0


# ---- the same kernels in C -------------------------------------------------------------------------
#: numpy functions of one argument a generated kernel may call, and their C names (math.h)
_C_FUNCTIONS = {"sqrt": "sqrt", "sign": "sign_of", "abs": "fabs", "absolute": "fabs", "sin": "sin", "cos": "cos", "tan": "tan",
                "exp": "exp", "log": "log", "arctan": "atan", "arcsin": "asin", "arccos": "acos"}
_C_OPERATORS = {"Add": "+", "Sub": "-", "Mult": "*", "Div": "/"}

_C_PRELUDE = r"""#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

/* An input of a kernel: a float64 buffer (1-D with any whole stride, or C-contiguous) or a number
   (stride 0). */
typedef struct {
    Py_buffer view;
    int held;
    const double *data;
    Py_ssize_t stride;
    double scalar;
} Input;

/* An output: a writable C-contiguous float64 buffer of rows x m values (row r of element i at r m + i). */
typedef struct {
    Py_buffer view;
    int held;
    double *data;
} Output;

static void release(Input *in, Py_ssize_t nin, Output *out, Py_ssize_t nout) {
    for (Py_ssize_t k = 0; k < nin; k++) {
        if (in[k].held) PyBuffer_Release(&in[k].view);
    }
    for (Py_ssize_t k = 0; k < nout; k++) {
        if (out[k].held) PyBuffer_Release(&out[k].view);
    }
}

/* numpy.sign of a float: -1, 0 (for either zero) or 1, and NaN for NaN */
static inline double sign_of(double x) {
    return x > 0.0 ? 1.0 : x < 0.0 ? -1.0 : x == 0.0 ? 0.0 : x;
}

static int is_float64(const Py_buffer *view) {
    const char *f = view->format;
    if (f == NULL) return 0;
    if (f[0] == '<' || f[0] == '=' || f[0] == '@') f++;
    return view->itemsize == 8 && strcmp(f, "d") == 0;
}

/* A buffer the kernel cannot use (strided in two dimensions, read-only output, ...) raises
   ValueError or BufferError in CPython and numpy: the wrapper answers TypeError only. */
static int as_type_error(void) {
    PyObject *type, *value, *traceback;
    PyErr_Fetch(&type, &value, &traceback);
    PyErr_Format(PyExc_TypeError, "buffer not usable by the compiled kernel (%S)", value ? value : Py_None);
    Py_XDECREF(type);
    Py_XDECREF(value);
    Py_XDECREF(traceback);
    return -1;
}

/* Reads the inputs args[0..nin) and the outputs args[nin..nin+nout) (rows[k] x m values each); 0, or
   -1 with TypeError set (the Python wrapper then calls the numpy kernel, which takes any array-like). */
static int prepare(const char *name, PyObject *const *args, Py_ssize_t nargs, Input *in, Py_ssize_t nin,
                   Output *out, Py_ssize_t nout, const Py_ssize_t *rows, Py_ssize_t *m) {
    *m = 1;
    for (Py_ssize_t k = 0; k < nin; k++) in[k].held = 0;
    for (Py_ssize_t k = 0; k < nout; k++) out[k].held = 0;
    if (nargs != nin + nout) {
        PyErr_Format(PyExc_TypeError, "%s takes %zd arguments (the inputs, then the outputs), got %zd", name,
                     nin + nout, nargs);
        return -1;
    }
    for (Py_ssize_t k = 0; k < nin; k++) {
        if (PyObject_CheckBuffer(args[k])) {
            if (PyObject_GetBuffer(args[k], &in[k].view, PyBUF_RECORDS_RO) < 0) return as_type_error();
            in[k].held = 1;
            const Py_buffer *v = &in[k].view;
            if (!is_float64(v)) {
                PyErr_Format(PyExc_TypeError, "%s: argument %zd is not float64", name, k);
                return -1;
            }
            Py_ssize_t size = v->len / 8, stride = 1;
            if (v->ndim == 1 && v->strides != NULL) {
                stride = v->strides[0] / 8;
                if (stride * 8 != v->strides[0]) {
                    PyErr_Format(PyExc_TypeError, "%s: argument %zd has a stride of %zd bytes", name, k,
                                 v->strides[0]);
                    return -1;
                }
            } else if (v->ndim > 1 && !PyBuffer_IsContiguous(v, 'C')) {
                PyErr_Format(PyExc_TypeError, "%s: argument %zd is neither 1-D nor C-contiguous", name, k);
                return -1;
            }
            if (size == 1) {
                in[k].scalar = *(const double *)v->buf;
                in[k].data = &in[k].scalar;
                in[k].stride = 0;
                continue;
            }
            if (*m != 1 && size != *m) {
                PyErr_Format(PyExc_TypeError, "%s: argument %zd has %zd elements, expected %zd", name, k, size, *m);
                return -1;
            }
            *m = size;
            in[k].data = (const double *)v->buf;
            in[k].stride = stride;
        } else {
            in[k].scalar = PyFloat_AsDouble(args[k]);
            if (in[k].scalar == -1.0 && PyErr_Occurred()) {
                PyErr_Clear();
                PyErr_Format(PyExc_TypeError, "%s: argument %zd is neither a float64 array nor a number", name, k);
                return -1;
            }
            in[k].data = &in[k].scalar;
            in[k].stride = 0;
        }
    }
    for (Py_ssize_t k = 0; k < nout; k++) {
        if (PyObject_GetBuffer(args[nin + k], &out[k].view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) < 0) {
            return as_type_error();
        }
        out[k].held = 1;
        if (!is_float64(&out[k].view) || out[k].view.len / 8 != rows[k] * *m) {
            PyErr_Format(PyExc_TypeError, "%s: output %zd must be a float64 array of %zd x %zd values", name, k,
                         rows[k], *m);
            return -1;
        }
        out[k].data = (double *)out[k].view.buf;
    }
    return 0;
}
"""


#: Emitted after the prelude by an extension computing elements two or four at once (``simd=True``):
#: a pair of doubles in one SIMD register (a GCC/Clang vector type) and, on x86-64, a quad in one AVX
#: register (its functions compiled for AVX2, called where the processor has it); their loads, stores
#: and numbers made vectors, and each math function lane by lane (the scalar C function on each lane).
#: Every lane runs the scalar code's operations in the same order, so it gets the scalar code's bits
#: (no multiply-add is contracted: AVX2 does not include FMA).
_C_VECTORS = r"""
#if defined(__GNUC__)
#define CONTIN_PAIRS 1
typedef double pair __attribute__((vector_size(16)));

static inline pair pair_of(double a, double b) {
    pair r = {a, b};
    return r;
}

static inline pair pair_splat(double a) {
    return pair_of(a, a);
}

static inline pair pair_load(const double *p) {
    pair r;
    memcpy(&r, p, sizeof r);
    return r;
}

static inline void pair_store(double *p, pair v) {
    memcpy(p, &v, sizeof v);
}

#define PAIR_FUNCTION(name, f) static inline pair name(pair x) { return pair_of(f(x[0]), f(x[1])); }
%(pair_functions)s
static inline pair pair_pow(pair x, double e) {
    return pair_of(pow(x[0], e), pow(x[1], e));
}
#endif

#if defined(__GNUC__) && defined(__x86_64__)
#define CONTIN_QUADS 1
#define QUADS __attribute__((target("avx2")))
typedef double quad __attribute__((vector_size(32)));

QUADS static inline quad quad_of(double a, double b, double c, double d) {
    quad r = {a, b, c, d};
    return r;
}

QUADS static inline quad quad_splat(double a) {
    return quad_of(a, a, a, a);
}

QUADS static inline quad quad_load(const double *p) {
    quad r;
    memcpy(&r, p, sizeof r);
    return r;
}

QUADS static inline void quad_store(double *p, quad v) {
    memcpy(p, &v, sizeof v);
}

#define QUAD_FUNCTION(name, f) \
    QUADS static inline quad name(quad x) { return quad_of(f(x[0]), f(x[1]), f(x[2]), f(x[3])); }
%(quad_functions)s
QUADS static inline quad quad_pow(quad x, double e) {
    return quad_of(pow(x[0], e), pow(x[1], e), pow(x[2], e), pow(x[3], e));
}
#endif
"""

#: The vector kinds of :data:`_C_VECTORS`: name -> lanes.
_LANES = {"pair": 2, "quad": 4}


def _vectors_prelude() -> str:
    """:data:`_C_VECTORS` with a vector version of every function of :data:`_C_FUNCTIONS`."""
    functions = dict.fromkeys(_C_FUNCTIONS.values())
    return _C_VECTORS % {f"{kind}_functions": "\n".join(f"{kind.upper()}_FUNCTION({kind}_{c}, {c})" for c in functions)
                         for kind in _LANES}


class _CExpression:
    """Prints a numpy kernel's expression (a Python ``ast`` node) as a fully parenthesised C expression.

    ``outputs`` maps the kernel's output arrays to their C names and shapes: reading one of their
    entries (``_h[0, 10]``) reads the element's value in the output buffer.
    """

    def __init__(self, function: str, outputs: dict[str, tuple[str, tuple[int, ...]]]) -> None:
        self.function = function
        self.outputs = outputs

    def entry(self, node: Any) -> str:
        """C lvalue of an output entry ``name[i, j, ...]`` (constant indices) for the element ``_i``."""
        import ast

        name = node.value.id if isinstance(node.value, ast.Name) else None
        index = node.slice.elts if isinstance(node.slice, ast.Tuple) else [node.slice]
        if name not in self.outputs or not all(isinstance(k, ast.Constant) and isinstance(k.value, int)
                                               for k in index):
            raise ValueError(f"{self.function}: no C translation for {ast.unparse(node)!r}")
        c_name, shape = self.outputs[name]
        if len(index) != len(shape) or not all(0 <= k.value < d for k, d in zip(index, shape)):
            raise ValueError(f"{self.function}: index {ast.unparse(node)!r} outside the shape {shape}")
        flat = 0
        for k, d in zip(index, shape):
            flat = flat * d + k.value
        return f"{c_name}[{flat} * _m + _i]"

    def __call__(self, node: Any) -> str:
        import ast

        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return repr(float(node.value))
        if isinstance(node, ast.Name):
            return node.id
        if isinstance(node, ast.Subscript):
            return self.entry(node)
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "numpy" \
                and node.attr == "pi":
            return repr(math.pi)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            return f"({'-' if isinstance(node.op, ast.USub) else '+'}{self(node.operand)})"
        if isinstance(node, ast.BinOp) and type(node.op).__name__ in _C_OPERATORS:
            return f"({self(node.left)} {_C_OPERATORS[type(node.op).__name__]} {self(node.right)})"
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            return self._power(node)
        if isinstance(node, ast.Call) and len(node.args) == 1 and not node.keywords:
            f = node.func
            name = (f.attr if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id == "numpy"
                    else f.id if isinstance(f, ast.Name) and f.id == "abs" else None)
            if name in _C_FUNCTIONS:
                return f"{_C_FUNCTIONS[name]}({self(node.args[0])})"
        raise ValueError(f"{self.function}: no C translation for {ast.unparse(node)!r}")

    def _power(self, node: Any) -> str:
        return _power_text(self(node.left), _exponent(node.right), lambda: self(node.right))


def _power_text(base: str, value: float | None, exponent: Callable[[], str], prefix: str = "") -> str:
    """C text of ``base ** exponent`` (``value`` the exponent's if it is a constant; ``prefix`` of the
    functions called: ``pair_`` for pairs, ``quad_`` for quads)."""
    # numpy's own shortcuts for these exponents (square, reciprocal, sqrt), so that C gives its bits
    if value == 2:
        return f"({base} * {base})"
    if value == 1:
        return base
    if value == -1:
        return f"(1.0 / {base})"
    if value == 0.5:
        return f"{prefix}sqrt({base})"
    return f"{prefix}pow({base}, {exponent()})"


class _CVectorExpression(_CExpression):
    """:class:`_CExpression` for several elements at once (``_i``, ``_i + 1``, ...): variables are vectors of
    the ``kind`` of :data:`_C_VECTORS` (``pair``, ``quad``), numbers stay numbers (a vector times a number
    is a vector), output entries are read as vectors."""

    def __init__(self, function: str, outputs: dict[str, tuple[str, tuple[int, ...]]], kind: str) -> None:
        super().__init__(function, outputs)
        self.kind = kind

    def typed(self, node: Any) -> tuple[str, bool]:
        """The C text of ``node`` and whether it is a vector (else a number)."""
        import ast

        if isinstance(node, ast.Name):
            return node.id, True
        if isinstance(node, ast.Subscript):
            return f"{self.kind}_load(&{self.entry(node)})", True
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            text, vector = self.typed(node.operand)
            return f"({'-' if isinstance(node.op, ast.USub) else '+'}{text})", vector
        if isinstance(node, ast.BinOp) and type(node.op).__name__ in _C_OPERATORS:
            (left, lv), (right, rv) = self.typed(node.left), self.typed(node.right)
            return f"({left} {_C_OPERATORS[type(node.op).__name__]} {right})", lv or rv
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            base, vector = self.typed(node.left)

            def exponent() -> str:
                text, exponent_vector = self.typed(node.right)
                if exponent_vector:
                    raise ValueError(f"{self.function}: no C translation for a variable exponent in vectors")
                return text

            return _power_text(base, _exponent(node.right), exponent, f"{self.kind}_" if vector else ""), vector
        if isinstance(node, ast.Call) and len(node.args) == 1 and not node.keywords:
            _CExpression.__call__(self, node)  # the scalar printer's checks (a known numpy function)
            f = node.func
            name = _C_FUNCTIONS[f.attr if isinstance(f, ast.Attribute) else f.id]
            text, vector = self.typed(node.args[0])
            return (f"{self.kind}_{name}({text})" if vector else f"{name}({text})"), vector
        return _CExpression.__call__(self, node), False

    def __call__(self, node: Any) -> str:
        return self.typed(node)[0]

    def value(self, node: Any) -> str:
        """C text of ``node`` as a vector (a number repeated on every lane)."""
        text, vector = self.typed(node)
        return text if vector else f"{self.kind}_splat({text})"


def _exponent(node: Any) -> float | None:
    """A constant exponent's value (``2``, ``-1``, ``0.5``, ...), or None."""
    import ast

    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub) and isinstance(node.operand, ast.Constant):
        return -node.operand.value
    return None


def _c_output_name(name: str) -> str:
    """C name of the pointer to an output's values (``_h`` -> ``out_h``)."""
    return f"out{name}" if name.startswith("_") else f"out_{name}"


def _zeros_shape(value: Any) -> tuple[tuple[int, ...], bool] | None:
    """``(shape, per_element)`` of ``numpy.zeros(shape)`` (per element when its last extent is ``_m``, or when
    the station shape ``_shape`` is appended: ``numpy.zeros((15,) + _shape)``), or None."""
    import ast

    if not (isinstance(value, ast.Call) and ast.unparse(value.func) == "numpy.zeros" and len(value.args) == 1):
        return None
    arg = value.args[0]
    if (isinstance(arg, ast.BinOp) and isinstance(arg.op, ast.Add) and isinstance(arg.left, ast.Tuple)
            and isinstance(arg.right, ast.Name) and arg.right.id == "_shape"):
        dims = arg.left.elts
        if not all(isinstance(d, ast.Constant) and isinstance(d.value, int) for d in dims):
            return None
        return tuple(d.value for d in dims), True
    extents = arg.elts if isinstance(arg, ast.Tuple) else [arg]
    per_element = isinstance(extents[-1], ast.Name) and extents[-1].id == "_m"
    dims = extents[:-1] if per_element else extents
    if not all(isinstance(d, ast.Constant) and isinstance(d.value, int) for d in dims):
        return None
    return tuple(d.value for d in dims), per_element


def _stacked_variables(function: Any) -> tuple[list[str], Any]:
    """The names a kernel unpacks its first argument into (``y0, y1, y2 = y`` as its first statement after
    the docstring) and that statement, or ``([], None)``."""
    import ast

    first = next((s for s in function.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))),
                 None)
    args = function.args.args
    if (isinstance(first, ast.Assign) and len(first.targets) == 1 and isinstance(first.targets[0], ast.Tuple)
            and all(isinstance(t, ast.Name) for t in first.targets[0].elts)
            and isinstance(first.value, ast.Name) and args and first.value.id == args[0].arg):
        return [t.id for t in first.targets[0].elts], first
    return [], None


def _c_kernel(function: Any, rows: int | None,
              simd: bool = False) -> tuple[str, str, tuple[bool, list[tuple[int, ...]]] | None, int]:
    """``(C function text, method-table entry, returns, stacked)`` of one generated numpy kernel.

    ``rows``: the kernel fills an ``out`` argument of ``rows`` rows (``returns`` is None).  None: the
    kernel allocates its outputs with ``numpy.zeros`` and returns them (or scalars per element);
    ``returns`` is then ``(per_element, [shape of each returned value])``.  ``stacked``: the number of
    variables the kernel unpacks its first argument into (0 if it does not), each of them an input of
    the C function in its place.  ``simd`` (a returning kernel): the elements are computed four at a
    time where the processor has AVX2 and two at a time where the compiler has vector types
    (:data:`_C_VECTORS`), the last ones alone.
    """
    import ast

    name = function.name
    inputs = [a.arg for a in function.args.args if a.arg != "out"]
    stacked, unpacking = _stacked_variables(function) if rows is None else ([], None)
    if stacked:
        inputs = stacked + inputs[1:]
    body, declared = [], set(inputs)
    # the body again for each vector kind of _C_VECTORS (a returning kernel with simd)
    vectors: dict[str, list[str]] = {kind: [] for kind in _LANES} if simd and rows is None else {}
    outputs: dict[str, tuple[str, tuple[int, ...]]] = {}
    returned: list[str] = []
    per_element = True
    if rows is not None:
        outputs["out"] = ("out", (rows,))
    statements = function.body
    for statement in statements:
        if isinstance(statement, ast.Return) and rows is None:
            value = statement.value
            returned = [e.id for e in value.elts] if isinstance(value, ast.Tuple) else [value.id]
    for statement in statements:
        if isinstance(statement, (ast.Delete, ast.Return)) or (
                isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant)):
            continue
        if isinstance(statement, ast.If) and ast.unparse(statement.test) == "out is None" and rows is not None:
            continue
        if stacked and statement is unpacking:
            continue
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1):
            raise ValueError(f"{name}: no C translation for statement {ast.unparse(statement)!r}")
        target = statement.targets[0]
        if rows is None and isinstance(target, ast.Name):
            if target.id == "_m" and ast.unparse(statement.value) == f"numpy.shape({inputs[0]})[0]":
                continue
            if stacked and target.id == "_shape" and ast.unparse(statement.value) == f"numpy.shape({inputs[0]})":
                continue
            zeros = _zeros_shape(statement.value)
            if zeros is not None:
                outputs[target.id] = (_c_output_name(target.id), zeros[0])
                per_element = zeros[1]
                continue
        expression = _CExpression(name, outputs)
        value = expression(statement.value)
        vector_values = {kind: _CVectorExpression(name, outputs, kind).value(statement.value) for kind in vectors}
        if isinstance(target, ast.Name):
            for kind, text in vector_values.items():
                vectors[kind].append(f"{'' if target.id in declared else kind + ' '}{target.id} = {text};")
            body.append(f"{'' if target.id in declared else 'double '}{target.id} = {value};")
            declared.add(target.id)
        elif isinstance(target, ast.Subscript):
            for kind, text in vector_values.items():
                vectors[kind].append(f"{kind}_store(&{expression.entry(target)}, {text});")
            body.append(f"{expression.entry(target)} = {value};")
        else:
            raise ValueError(f"{name}: no C translation for target {ast.unparse(target)!r}")
    if rows is None:
        # returned numbers (one per element) get an output of their own, written after the body
        for r in returned:
            if r not in outputs:
                outputs[r] = (_c_output_name(r), ())
                body.append(f"{outputs[r][0]}[_i] = {r};")
                for kind, lines in vectors.items():
                    lines.append(f"{kind}_store(&{outputs[r][0]}[_i], {r});")
        order = returned
    else:
        order = ["out"]
    shapes = [outputs[r][1] for r in order]
    sizes = [math.prod(shape) for shape in shapes]
    n, nout = len(inputs), len(order)
    lines = [f"static PyObject *c_{name}(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {{",
             f"    static const Py_ssize_t rows[{nout}] = {{{', '.join(map(str, sizes))}}};",
             f"    Input in[{n}];",
             f"    Output outputs[{nout}];",
             "    Py_ssize_t _m;",
             f"    if (prepare(\"{name}\", args, nargs, in, {n}, outputs, {nout}, rows, &_m) < 0) {{",
             f"        release(in, {n}, outputs, {nout});",
             "        return NULL;",
             "    }"]
    lines += [f"    double *{outputs[r][0]} = outputs[{k}].data;" for k, r in enumerate(order)]
    used = set(re.findall(r"\b\w+\b", "\n".join(body)))  # an input the kernel ignores is not read

    def loads(kind: str) -> list[str]:
        lanes = ", ".join("in[{k}].data[" + ("_i" if j == 0 else f"(_i + {j})") + " * in[{k}].stride]"
                          for j in range(_LANES[kind]))
        return [f"        const {kind} {a} = {kind}_of({lanes.format(k=k)});"
                for k, a in enumerate(inputs) if a in used]

    if vectors:
        pointers = ", ".join(f"double *{outputs[r][0]}" for r in order)
        quads = [f"static Py_ssize_t c_{name}_quads(const Input *in, {pointers}, Py_ssize_t _m) {{",
                 "    Py_ssize_t _i = 0;", "    for (; _i + 3 < _m; _i += 4) {"]
        quads += loads("quad") + ["        " + line for line in vectors["quad"]]
        quads += ["    }", "    return _i;", "}"]
        lines[:0] = ["#ifdef CONTIN_QUADS", "QUADS " + quads[0], *quads[1:], "#endif", ""]
        lines += ["    Py_ssize_t _i = 0;", "#ifdef CONTIN_QUADS",
                  "    if (__builtin_cpu_supports(\"avx2\")) {",
                  f"        _i = c_{name}_quads(in, {', '.join(outputs[r][0] for r in order)}, _m);", "    }",
                  "#endif", "#ifdef CONTIN_PAIRS", "    for (; _i + 1 < _m; _i += 2) {"]
        lines += loads("pair") + ["        " + line for line in vectors["pair"]]
        lines += ["    }", "#endif", "    for (; _i < _m; _i++) {"]
    else:
        lines += ["    for (Py_ssize_t _i = 0; _i < _m; _i++) {"]
    lines += [f"        const double {a} = in[{k}].data[_i * in[{k}].stride];" for k, a in enumerate(inputs) if a in used]
    lines += ["        " + line for line in body]
    lines += ["    }", f"    release(in, {n}, outputs, {nout});", "    Py_RETURN_NONE;", "}"]
    arguments = "*inputs, out" if rows is not None else "*inputs, *outputs"
    entry = f'    {{"{name}", (PyCFunction)(void (*)(void))c_{name}, METH_FASTCALL, "{name}({arguments})"}},'
    return "\n".join(lines), entry, (None if rows is not None else (per_element, shapes)), len(stacked)


def c_extension_text(python_source: str, rows: dict[str, int], module: str, title: str,
                     returning: Sequence[str] = (), simd: bool = False) -> str:
    """C source of a Python extension module computing generated numpy kernels element by element.

    Each kernel must be a function of the generated module ``python_source`` whose body is
    straight-line code: assignments of arithmetic, powers and the one-argument numpy functions of
    :data:`_C_FUNCTIONS` to temporaries and to entries of its outputs (with constant indices).  The
    C function runs the same operations in the same order for every element, so its results agree
    with the numpy kernel's to rounding (numpy's shortcuts for the exponents 2, -1 and 1/2 are
    kept).  Two forms of kernel:

    * named in ``rows`` (name -> number of rows): the kernel's last argument is ``out``, which it
      fills row by row (``out[k] = ...``; its ``if out is None`` allocation, ``del`` and ``return``
      are skipped); the C function is ``name(*inputs, out)``;
    * named in ``returning``: the kernel allocates its outputs with ``numpy.zeros(shape)`` (per
      element when the last extent is ``_m = numpy.shape(first input)[0]``), fills their entries
      (``_h[0, 10] = ...``, ``_h[10, 0] = _h[0, 10]``) and returns a tuple of them and of numbers
      per element; the C function is ``name(*inputs, *outputs)``, the outputs zero-filled arrays in
      the returned order, and the module's string ``RETURNS`` (a Python literal,
      :func:`contin.numerics.compiled.prefer_compiled` reads it) gives each such kernel's
      ``(per_element, [shape of each returned value])``.  A returning kernel may instead take its
      variables stacked in its first argument, which its first statement unpacks (``y0, y1, y2 = y``;
      then ``_shape = numpy.shape(y0)`` and ``numpy.zeros((3,) + _shape)`` for outputs per station, of
      any station shape in numpy): the C function takes each of those variables as an input of its
      own in the argument's place, and the module's string ``STACKED`` (a Python literal) gives each
      such kernel's number of variables.

    Inputs are float64 arrays of one size ``m`` (1-D with any stride, or C-contiguous) or numbers;
    outputs writable C-contiguous float64 arrays of ``rows x m`` values.  Anything else raises
    ``TypeError``, which a caller answers by calling the numpy kernel.

    Parameters
    ----------
    python_source : str
        Text of the generated numpy module.
    rows : dict of str to int
        The ``out`` kernels and their numbers of output rows.
    module : str
        The extension's module name (the last part of its dotted name).
    title : str
        First line of the C file's comment.
    returning : sequence of str
        The kernels that return their outputs.
    simd : bool
        The returning kernels compute four elements at once in one AVX register where the processor
        has AVX2 (x86-64), then two at once in one SIMD register where the compiler offers GCC's vector
        types, the last ones alone (each lane the same operations in the same order, so the same bits;
        math functions lane by lane) (:data:`_C_VECTORS`).  For kernels with many operations per element;
        the text without ``simd`` does not change.

    Returns
    -------
    str
    """
    import ast

    functions = {f.name: f for f in ast.parse(python_source).body if isinstance(f, ast.FunctionDef)}
    missing = sorted((set(rows) | set(returning)) - set(functions))
    if missing:
        raise ValueError(f"c_extension_text: no kernel named {', '.join(missing)} in the source")
    kernels = [_c_kernel(functions[name], n) for name, n in rows.items()]
    kernels += [_c_kernel(functions[name], None, simd) for name in returning]
    table = "\n".join(entry for _, entry, _, _ in kernels)
    names = [*rows, *returning]
    returns = {name: spec for name, (_, _, spec, _) in zip(names, kernels) if spec is not None}
    stacked = {name: n for name, (_, _, _, n) in zip(names, kernels) if n}
    init = [f"PyMODINIT_FUNC PyInit_{module}(void) {{",
            "    PyObject *module = PyModule_Create(&moduledef);"]
    for constant, value in (("RETURNS", returns), ("STACKED", stacked)):
        if value:
            init += [f"    if (module != NULL && PyModule_AddStringConstant(module, \"{constant}\", \"{value!r}\") < 0) {{",
                     "        Py_DECREF(module);",
                     "        return NULL;",
                     "    }"]
    init += ["    return module;", "}"]
    return "\n".join([
        f"/* {title}",
        "   Generated from the numpy kernels by contin.modelkit.codegen.c_extension_text: do not edit. */",
        _C_PRELUDE + (_vectors_prelude() if simd else ""),
        "\n\n".join(text for text, _, _, _ in kernels),
        "",
        f"static PyMethodDef methods[] = {{\n{table}\n    {{NULL, NULL, 0, NULL}}\n}};",
        "",
        f'static struct PyModuleDef moduledef = {{PyModuleDef_HEAD_INIT, "{module}", NULL, -1, methods, NULL, NULL, NULL,'
        " NULL};",
        "",
        *init,
        ""])
