"""Generate :mod:`contin_models.contact._generated` (contact-barrier kernels) from sympy definitions.

Run as ``python -m contin_models.contact.codegen [--output PATH] [--check]``.  This is the only module of
the contact layer that imports sympy; the emitted file is plain vectorised numpy and is committed.
Regenerating reproduces the committed file byte for byte (``tests/test_contact_barrier.py`` checks
it): the output is built from a fixed list of indenters in a fixed order, common subexpressions get
stable names ``_c0, _c1, ...`` and nothing time- or machine-dependent is written.

The barrier (``docs/model.md#contact``, paper eq. 3.16)
-----------------------------------------------------------
Per shell node at distance ``d`` from the indenter surface::

    W(d) = -K (d - dhat)^2 log(d / dhat)      for 0 < d < dhat,      W = 0 for d >= dhat.

With ``s = d - dhat``, ``L = log(d / dhat)`` and ``u = s / d`` its derivatives are::

    W'(d)  = -K s (2 L + u)
    W''(d) = -K (2 L + u (4 - u))

(the generator checks both against ``sympy.diff`` of the definition).  ``W``, ``W'`` and ``W''``
all vanish at ``d = dhat`` (C2 continuation by zero) and ``W -> +inf`` as ``d -> 0+``.

Indenters (the distance ``d`` of a node ``(r, z)``)
---------------------------------------------------
``sphere``
    Rigid sphere of radius ``rho`` centred on the axis at height ``zc``:
    ``d = sqrt(r^2 + (z - zc)^2) - rho``.  With ``q = sqrt(r^2 + (z - zc)^2)`` and the unit vector
    ``n = (r, z - zc) / q`` from the centre to the node, ``grad d = (n_r, n_z, -n_z)`` with respect
    to ``(r, z, zc)`` and ``hess d = (1/q) P`` with ``P`` the projector orthogonal to ``n``,
    ``P_rr = n_z^2``, ``P_rz = -n_r n_z``, ``P_zz = n_r^2`` (and the ``zc`` row/column the negated
    ``z`` one).  ``rho = 0`` is a point indenter.
``plate``
    Flat horizontal plate at height ``zp`` pushing down: ``d = zp - z``, ``grad d = (0, -1, 1)``,
    ``hess d = 0``.

Every kernel is a function of the node's ``(r, z)`` and the indenter position ``c`` (``zc`` or
``zp``): the three variables ``(r, z, c)`` in this order.  The chain rule is
``grad W = W' grad d`` and ``hess W = W'' grad d grad d^T + W' hess d``; the closed forms of
``grad d`` and ``hess d`` above are checked against ``sympy.diff`` of the definition of ``d`` at
generation time.

Generated functions
-------------------
For ``<shape>`` in ``sphere`` (parameters ``rho, K, dhat``) and ``plate`` (``K, dhat``), all
taking ``(r, z, c, *params)``:

* ``<shape>_distance``: ``d``, shape ``(m,)``, valid everywhere;
* ``<shape>_energy``: ``W(d)``, shape ``(m,)``;
* ``<shape>_gradient``: shape ``(3, m)``, rows ``d/dr, d/dz, d/dc``;
* ``<shape>_hessian``: shape ``(6, m)``, the packed upper triangle, rows
  ``(r, r), (r, z), (r, c), (z, z), (z, c), (c, c)`` (:data:`PAIRS`);
* ``<shape>_derivatives``: ``(energy, gradient, hessian)`` from one pass.

The energy and derivative kernels are only valid for ``0 < d < dhat``: the caller evaluates them on
the active set alone (:class:`contin_models.contact.ContactBarrier`).  ``r`` and ``z`` are arrays of one
size ``m``; ``c`` and the parameters are numbers or arrays of that size.

Contact cells: the barrier between the nodes
--------------------------------------------
The barrier does not act on the nodes alone but on the meridian between them
(:mod:`contin_models.contact.barrier`): the cell of node ``i`` is the piece around node ``i`` of the
uniform quadratic B-spline whose control points are the nodes, ``x(t) = sum_j B_j(t) x_j`` over the
nodes ``i-1, i, i+1``::

    B_0(t) = (1/2 - t)^2 / 2,    B_1(t) = 3/4 - t^2,    B_2(t) = (1/2 + t)^2 / 2,

for ``t`` in ``[-1/2, 1/2]``; consecutive cells meet at the midpoints of the segments with a common
tangent, so the meridian the barrier sees is C1.  The cell's energy ``int W(d(x(t))) dt`` is taken
by a Gauss rule, so a cell is a sum of the point kernels above at the points ``x(t_q)``.  The point
``x(t)`` is linear in the nodes, so the exact derivatives of a cell are the point kernels' times the
basis::

    dW/dr_j = B_j dW/dr,    d2W/dr_j dz_k = B_j B_k d2W/dr dz,    d2W/dr_j dc = B_j d2W/dr dc, ...

(the generator checks this chain rule against ``sympy.diff`` of the cell point's distance at 30
digits; the energy follows through ``d``).
``cell_basis`` is emitted alongside the kernels.

The same kernels in C
---------------------
The kernels (not ``cell_basis``) are also written as the C extension ``contin_models.contact._ckernels``
(:data:`C_OUTPUT`, :func:`generate_c_source`, by :func:`contin.modelkit.codegen.c_extension_text` from the
committed numpy module), which the package install compiles where it finds a C compiler; the barrier
calls them through :func:`contin.numerics.compiled.prefer_compiled`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path

import sympy as sp
from sympy.printing.numpy import NumPyPrinter

from contin.modelkit.codegen import (c_extension_text, cse_lines, function_header, generator_main, kernel_printer,
                                     module_text, row_targets, upper_pairs)

__all__ = ["Indenter", "build_indenters", "barrier_definition", "cell_basis", "check_cell_chain_rule",
           "generate_source", "generate_c_source", "main", "DEFAULT_OUTPUT", "C_OUTPUT", "PAIRS"]

DEFAULT_OUTPUT = Path(__file__).with_name("_generated.py")
#: The kernels as a C extension (``contin_models.contact._ckernels``), generated from the committed numpy module.
C_OUTPUT = Path(__file__).with_name("_ckernels.c")

#: Packed upper-triangle pairs of the 3 local variables ``(r, z, c)``.
PAIRS = upper_pairs(3)

_r, _z = sp.symbols("r z", real=True)
_K, _dhat = sp.symbols("K dhat", positive=True)
# prelude symbols shared by both indenters
_d, _s, _logt, _u, _w0, _w1, _w2 = sp.symbols("d s logt u w0 w1 w2", real=True)


def barrier_definition(d: sp.Expr) -> sp.Expr:
    """The barrier ``W(d) = -K (d - dhat)^2 log(d / dhat)`` (eq. 3.16), as a sympy expression."""
    return -_K * (d - _dhat) ** 2 * sp.log(d / _dhat)


def _barrier_prelude() -> list[tuple[sp.Symbol, sp.Expr]]:
    """``s, L, u, W, W', W''`` in terms of the distance symbol ``d`` (checked against the definition)."""
    s, logt, u = _d - _dhat, sp.log(_d / _dhat), (_d - _dhat) / _d
    w0 = -_K * s**2 * logt
    w1 = -_K * s * (2 * logt + u)
    w2 = -_K * (2 * logt + u * (4 - u))
    W = barrier_definition(_d)
    for k, closed in enumerate((w0, w1, w2)):
        assert sp.simplify(sp.diff(W, _d, k) - closed) == 0, f"barrier derivative {k} is wrong"
    return [(_s, _d - _dhat), (_logt, sp.log(_d / _dhat)), (_u, _s / _d),
            (_w0, -_K * _s**2 * _logt), (_w1, -_K * _s * (2 * _logt + _u)),
            (_w2, -_K * (2 * _logt + _u * (4 - _u)))]


@dataclass
class Indenter:
    """One indenter shape: the distance of a node and its exact derivatives.

    Attributes
    ----------
    name : str
        Prefix of the generated functions.
    position : sympy.Symbol
        The indenter's position parameter ``c`` (third local variable).
    params : list of sympy.Symbol
        Geometric parameters (before ``K, dhat``).
    distance : sympy.Expr
        The definition of ``d`` in ``(r, z, c, params)``.
    prelude : list of (sympy.Symbol, sympy.Expr)
        Named quantities computed first, in order; ends with ``d``.
    grad_d : list of sympy.Expr
        ``grad d`` with respect to ``(r, z, c)`` in prelude symbols.
    hess_d : list of sympy.Expr
        ``hess d``, packed as :data:`PAIRS`, in prelude symbols.
    doc : str
        Description used in the generated docstrings.
    """

    name: str
    position: sp.Symbol
    params: list
    distance: sp.Expr
    prelude: list
    grad_d: list
    hess_d: list
    doc: str

    @property
    def variables(self) -> list[sp.Symbol]:
        """The three local variables ``(r, z, c)``."""
        return [_r, _z, self.position]

    @property
    def arguments(self) -> list[sp.Symbol]:
        """Kernel arguments: ``r, z, c``, the geometric parameters, ``K, dhat``."""
        return self.variables + list(self.params) + [_K, _dhat]

    @property
    def energy(self) -> sp.Expr:
        """The node's barrier energy as one sympy expression of :attr:`arguments` (the definition)."""
        return barrier_definition(self.distance)

    def _expand(self, e: sp.Expr) -> sp.Expr:
        for sym, rhs in reversed(self.prelude):
            e = e.subs(sym, rhs)
        return e

    def check(self) -> None:
        """Assert that the closed forms of ``grad d`` and ``hess d`` are the derivatives of ``d``."""
        assert sp.simplify(self._expand(_d) - self.distance) == 0
        for a, v in enumerate(self.variables):
            assert sp.simplify(self._expand(self.grad_d[a]) - sp.diff(self.distance, v)) == 0, (self.name, a)
        for k, (a, b) in enumerate(PAIRS):
            exact = sp.diff(self.distance, self.variables[a], self.variables[b])
            assert sp.simplify(self._expand(self.hess_d[k]) - exact) == 0, (self.name, a, b)

    def outputs(self) -> tuple[sp.Expr, list[sp.Expr], list[sp.Expr]]:
        """Energy, gradient (3) and packed Hessian (6) in prelude symbols (chain rule through ``d``)."""
        g = [_w1 * gd for gd in self.grad_d]
        h = [_w2 * self.grad_d[a] * self.grad_d[b] + _w1 * hd for (a, b), hd in zip(PAIRS, self.hess_d)]
        return _w0, g, h


def _sphere() -> Indenter:
    zc, rho = sp.Symbol("zc", real=True), sp.Symbol("rho", nonnegative=True)
    dz, q, iq, nr, nz = sp.symbols("dz q iq nr nz", real=True)
    prelude = [(dz, _z - zc), (q, sp.sqrt(_r**2 + dz**2)), (iq, 1 / q), (nr, _r * iq), (nz, dz * iq),
               (_d, q - rho)]
    grad_d = [nr, nz, -nz]
    P = {(0, 0): nz**2, (0, 1): -nr * nz, (1, 1): nr**2}
    hess_d = [iq * P[0, 0], iq * P[0, 1], -iq * P[0, 1], iq * P[1, 1], -iq * P[1, 1], iq * P[1, 1]]
    return Indenter("sphere", zc, [rho], sp.sqrt(_r**2 + (_z - zc) ** 2) - rho, prelude, grad_d, hess_d,
                    "sphere of radius ``rho`` centred on the axis at height ``zc``")


def _plate() -> Indenter:
    zp = sp.Symbol("zp", real=True)
    zero = sp.Integer(0)
    return Indenter("plate", zp, [], zp - _z, [(_d, zp - _z)], [zero, sp.Integer(-1), sp.Integer(1)],
                    [zero] * 6, "flat horizontal plate at height ``zp`` pushing down")


_t = sp.Symbol("t", real=True)


def cell_basis() -> list[sp.Expr]:
    """Uniform quadratic B-spline basis ``B_0, B_1, B_2`` of a contact cell in ``t`` on ``[-1/2, 1/2]``.

    Returns
    -------
    list of sympy.Expr
        ``[(1/2 - t)^2 / 2, 3/4 - t^2, (1/2 + t)^2 / 2]``.  Checked: the weights sum to one, and the
        curve of consecutive cells is C1 (cell ``i`` at ``t = 1/2`` and cell ``i + 1`` at
        ``t = -1/2`` give the same point, the midpoint of their shared segment, and the same tangent,
        the segment itself).
    """
    half = sp.Rational(1, 2)
    basis = [(half - _t) ** 2 / 2, sp.Rational(3, 4) - _t**2, (half + _t) ** 2 / 2]
    assert sp.expand(sum(basis)) == 1
    x = sp.symbols("x0:4")  # nodes i-1 .. i+2: cell i on x0..x2, cell i+1 on x1..x3
    for order in (0, 1):
        right = sum(sp.diff(B, _t, order).subs(_t, half) * x[j] for j, B in enumerate(basis))
        left = sum(sp.diff(B, _t, order).subs(_t, -half) * x[j + 1] for j, B in enumerate(basis))
        assert sp.expand(right - left) == 0, order
    return basis


def check_cell_chain_rule(ind: Indenter) -> None:
    """Assert that a cell's exact derivatives are the point kernel's derivatives times the basis.

    The distance ``d(x(t), c)`` of a cell's point ``x(t) = sum_j B_j(t) x_j`` is differentiated by
    sympy with respect to the six nodal coordinates and ``c`` and compared, at a fixed point and 30
    digits, with ``B_j dd/da`` and ``B_j B_k d2d/da db`` of the point's distance; the energy
    ``W(d)`` then follows by the chain rule through ``d`` that :meth:`Indenter.check` verifies for
    the point kernels (checking the distance keeps generation fast).
    """
    basis = cell_basis()
    nodes = sp.symbols("r0 z0 r1 z1 r2 z2", real=True)
    c = ind.position
    point = {_r: sum(L * nodes[2 * j] for j, L in enumerate(basis)),
             _z: sum(L * nodes[2 * j + 1] for j, L in enumerate(basis))}
    cell = ind.distance.subs(point, simultaneous=True)
    local = list(nodes) + [c]
    # where: a cell through three points just under the indenter (the sphere centred 1/2 above)
    values = {nodes[0]: sp.Rational(1, 5), nodes[1]: sp.Rational(-3, 10000), nodes[2]: sp.Rational(-1, 5),
              nodes[3]: sp.Rational(1, 10000), nodes[4]: sp.Rational(-1, 5), nodes[5]: sp.Rational(-7, 10000),
              _t: sp.Rational(1, 7), _K: 10**8, _dhat: sp.Rational(1, 1000)}
    values[c] = sp.Rational(1, 1000) if ind.name == "plate" else sp.Rational(5, 10) + sp.Rational(1, 1000)
    values.update({p: sp.Rational(1, 2) for p in ind.params})

    def role(v: sp.Symbol) -> tuple[sp.Expr, sp.Symbol]:  # (basis weight, point variable) of a local variable
        if v == c:
            return sp.Integer(1), c
        k = nodes.index(v)
        return basis[k // 2], (_r, _z)[k % 2]

    at_point = {**values, **{sym: expr.subs(values) for sym, expr in point.items()}}
    for a in local:
        wa, va = role(a)
        exact = sp.diff(cell, a).evalf(30, subs=values)
        chain = (wa * sp.diff(ind.distance, va)).subs(_t, values[_t]).evalf(30, subs=at_point)
        assert abs(exact - chain) <= sp.Float("1e-20", 30) * (1 + abs(exact)), (ind.name, a)
        for b in local[local.index(a):]:
            wb, vb = role(b)
            exact = sp.diff(cell, a, b).evalf(30, subs=values)
            chain = (wa * wb * sp.diff(ind.distance, va, vb)).subs(_t, values[_t]).evalf(30, subs=at_point)
            assert abs(exact - chain) <= sp.Float("1e-20", 30) * (1 + abs(exact)), (ind.name, a, b)


def build_indenters() -> list[Indenter]:
    """The indenters, in the order of the generated file: ``sphere``, ``plate``."""
    return [_sphere(), _plate()]


# ---- printing ------------------------------------------------------------------------------------
def _body(ind: Indenter, results: list[sp.Expr], printer: NumPyPrinter, targets: list[str]) -> list[str]:
    """Printed prelude and common subexpressions that ``results`` need, then ``target = result``
    (a constant row as a float, filled by broadcasting)."""
    return cse_lines(results, targets, printer, prelude=ind.prelude + _barrier_prelude(), float_constants=True)


def _header(ind: Indenter, suffix: str, doc: list[str]) -> list[str]:
    return function_header(f"{ind.name}_{suffix}", [str(a) for a in ind.arguments], doc)


def _valid_note(ind: Indenter) -> list[str]:
    return ["", f"Indenter: {ind.doc}.", "Valid for ``0 < d < dhat`` only (the caller masks the active set)."]


def _vars(ind: Indenter) -> str:
    return ", ".join(str(v) for v in ind.variables)


def _emit_distance(ind: Indenter, printer: NumPyPrinter) -> list[str]:
    doc = [f"Distance of nodes ``(r, z)`` from the indenter surface: ``d = {sp.sstr(ind.distance)}``.", "",
           f"Indenter: {ind.doc}.", "Valid everywhere (``d <= 0``: the node penetrates); ``K`` and ``dhat`` are unused.",
           "",
           "Returns", "-------", "ndarray, shape ``(m,)``"]
    lines = _header(ind, "distance", doc)
    lines += _body(ind, [_d], printer, ["_d"])
    lines.append("    return _d")
    return lines


def _emit_energy(ind: Indenter, printer: NumPyPrinter) -> list[str]:
    doc = ["Barrier energy ``W(d) = -K (d - dhat)^2 log(d / dhat)`` of each node."] + _valid_note(ind) + [
        "", "Returns", "-------", "ndarray, shape ``(m,)``"]
    e, _, _ = ind.outputs()
    lines = _header(ind, "energy", doc)
    lines += _body(ind, [e], printer, ["_e"])
    lines.append("    return _e")
    return lines


def _size_line(ind: Indenter) -> str:
    return f"    _m = numpy.shape({ind.variables[0]})[0]"


def _hess_doc(ind: Indenter) -> str:
    v = ind.variables
    return ", ".join(f"({v[a]}, {v[b]})" for a, b in PAIRS)


def _emit_derivative(ind: Indenter, printer: NumPyPrinter, suffix: str) -> list[str]:
    """The ``<name>_gradient`` (rows ``d/dr, d/dz, d/dc``) or ``<name>_hessian`` (packed) kernel."""
    _, g, h = ind.outputs()
    if suffix == "gradient":
        what, exprs, var, packed = "Gradient of the node barrier", g, "_g", ""
        rows = "Rows ``" + ", ".join(f"d/d{v}" for v in ind.variables) + "``."
    else:
        what, exprs, var, packed = "Hessian of the node barrier", h, "_h", ", packed"
        rows = f"Upper triangle, rows ``{_hess_doc(ind)}`` (:data:`PAIRS`)."
    doc = [f"{what} with respect to ``({_vars(ind)})``{packed}."] + _valid_note(ind) + [
        "", "Returns", "-------", f"ndarray, shape ``({len(exprs)}, m)``", f"    {rows}"]
    lines = _header(ind, suffix, doc) + [_size_line(ind), f"    {var} = numpy.zeros(({len(exprs)}, _m))"]
    lines += _body(ind, exprs, printer, row_targets(var, len(exprs)))
    lines.append(f"    return {var}")
    return lines


def _emit_derivatives(ind: Indenter, printer: NumPyPrinter) -> list[str]:
    doc = ["Energy, gradient and packed Hessian of the node barrier in one pass."] + _valid_note(ind) + [
        "", "Returns", "-------", "tuple of ndarray",
        "    Energy ``(m,)``; gradient ``(3, m)`` with rows "
        f"``d/d{ind.variables[0]}, d/d{ind.variables[1]}, d/d{ind.variables[2]}``;",
        f"    packed Hessian ``(6, m)`` with rows ``{_hess_doc(ind)}``."]
    e, g, h = ind.outputs()
    lines = _header(ind, "derivatives", doc) + [
        _size_line(ind), "    _g = numpy.zeros((3, _m))", "    _h = numpy.zeros((6, _m))"]
    targets = ["_e"] + row_targets("_g", 3) + row_targets("_h", 6)
    lines += _body(ind, [e] + g + h, printer, targets)
    lines.append("    return _e, _g, _h")
    return lines


def _emit_cell_basis(printer: NumPyPrinter) -> list[str]:
    basis = cell_basis()
    lines = ["def cell_basis(t):",
             '    """Quadratic B-spline basis of a contact cell on the nodes ``i-1, i, i+1``, for ``t`` in ``[-1/2, 1/2]``.',
             "",
             "    The cell's point ``x(t) = B_0 x_{i-1} + B_1 x_i + B_2 x_{i+1}``; consecutive cells join with a",
             "    common tangent at the midpoints of the segments (a C1 curve).",
             "",
             "    Returns",
             "    -------",
             "    ndarray, shape ``(3,) + shape(t)``",
             '    """',
             "    t = numpy.asarray(t, dtype=float)",
             "    _L = numpy.empty((3,) + t.shape)"]
    lines += [f"    _L[{j}] = {printer.doprint(sp.expand(L))}" for j, L in enumerate(basis)]
    lines.append("    return _L")
    return lines


_PREAMBLE = '''"""Contact barrier kernels: a shell node against a sphere or a plate indenter, exact derivatives.

GENERATED by ``python -m contin_models.contact.codegen`` from the sympy definitions in
``models/contact/codegen.py`` (its docstring states the barrier, the distances and the chain rule).
Do not edit by hand: change the generator and regenerate.  Plain numpy, vectorised over nodes.

Every kernel takes ``(r, z, c, *params, K, dhat)``: the node coordinates (arrays of one size ``m``),
the indenter position (``zc``: sphere centre height; ``zp``: plate height), the geometric parameters
(``rho`` for the sphere) and the barrier constants (numbers or arrays of size ``m``).  Local
variables are ``(r, z, c)``; gradients are ``(3, m)`` and packed upper-triangle Hessians ``(6, m)``
with rows :data:`PAIRS`.  Energy and derivative kernels are valid for ``0 < d < dhat`` only.
:func:`cell_basis` is the quadratic B-spline basis of a contact cell (the meridian between the
nodes, see the generator's docstring): a point of a cell is linear in its three nodes, so the
kernels evaluated there give the cell's exact derivatives by the chain rule.
"""

import numpy
'''


def generate_source() -> str:
    """Check each indenter's derivatives and chain rule, then build the text of ``_generated.py``.

    Returns
    -------
    str
        The module: five kernels per indenter, :data:`PAIRS` and ``cell_basis`` (deterministic: the same
        sympy version gives the same bytes).
    """
    printer = kernel_printer()
    _barrier_prelude()  # checks the closed-form barrier derivatives
    chunks, functions = [], []
    for ind in build_indenters():
        ind.check()
        check_cell_chain_rule(ind)
        for emit, suffix in ((_emit_distance, "distance"), (_emit_energy, "energy"),
                             (partial(_emit_derivative, suffix="gradient"), "gradient"),
                             (partial(_emit_derivative, suffix="hessian"), "hessian"),
                             (_emit_derivatives, "derivatives")):
            chunks.append("\n".join(emit(ind, printer)))
            functions.append(f"{ind.name}_{suffix}")
    chunks.append("\n".join(_emit_cell_basis(printer)))
    functions.append("cell_basis")
    pairs = ("PAIRS = " + repr(PAIRS) + "\n"
             '"""Local variable pairs ``(a, b)``, ``a <= b``, of the packed Hessian rows; variables '
             '``(r, z, c)``."""')
    return module_text(_PREAMBLE, functions + ["PAIRS"], pairs, chunks)


def generate_c_source(python_source: str | None = None) -> str:
    """Text of ``_ckernels.c``: every kernel of ``python_source`` but ``cell_basis``, in C.

    Parameters
    ----------
    python_source : str or None
        Text of the numpy module (``None``: the committed ``_generated.py``, which the C file is
        generated from and checked against).
    """
    import ast

    text = DEFAULT_OUTPUT.read_text(encoding="utf-8") if python_source is None else python_source
    names = [f.name for f in ast.parse(text).body if isinstance(f, ast.FunctionDef) and f.name != "cell_basis"]
    return c_extension_text(text, {}, "_ckernels", "Contact barrier kernels (contin_models.contact._ckernels).",
                            returning=names)


def main(argv: list[str] | None = None) -> int:
    """The generator's command line (:func:`contin.modelkit.codegen.generator_main`): ``--output PATH``, ``--check``.

    Without ``--output`` the C extension's source :data:`C_OUTPUT` is written (or checked) too.
    """
    return generator_main(argv, generate_source, DEFAULT_OUTPUT, "python -m contin_models.contact.codegen",
                          __doc__.split("\n")[0], companions=[(generate_c_source, C_OUTPUT)])


if __name__ == "__main__":
    raise SystemExit(main())
