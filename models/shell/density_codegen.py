"""Generate :mod:`contin_models.shell._density_generated`: value, gradient and Hessian of the 2-D densities anywhere.

Run as ``python -m contin_models.shell.density_codegen [--output PATH] [--check]`` (about half a
minute).  Only this module imports sympy; the emitted file is plain vectorised numpy and is committed,
and so is the source of its C extension (:data:`C_OUTPUT`, :func:`generate_c_source`), translated from
it by :func:`contin.modelkit.codegen.c_extension_text` with several stations per SIMD register
(``simd=True``: thousands of operations per station); :mod:`contin_models.shell.density_kernels` serves
the compiled kernels where the install built them.

:mod:`contin_models.shell.harmonic_codegen` differentiates the densities at axisymmetric states only
(the harmonic blocks need nothing else).  A view whose states are not axisymmetric (rings of
material points moving in three directions) needs, at every angular station, the value, the
gradient and the Hessian of each density in all of its local variables: that is what is generated
here, from the same functions of :mod:`contin_models.shell.density` evaluated on sympy symbols.

What is generated
-----------------
Every kernel ``<name>_jet(y, *params)`` takes the local variables ``y``, a ``(k, ...)`` array (or a
sequence of ``k`` arrays of one shape, ``(m,)`` for ``m`` stations), in the order of the density's
arguments, each 3-vector as its components ``(r, t, z)`` in the local frame (any orthonormal frame:
the densities are invariant), and the per-element parameters (arrays that broadcast against one
variable, or numbers).  It returns the value ``(...)``, the gradient ``(k, ...)`` and the full
symmetric Hessian ``(k, k, ...)``: the layout of :class:`contin_models.shell.jets.Jet`, so that
``y`` gathered from the unknowns by one index array and the gradient scattered back by the same
index share their shape.

=====================  ====  ===========================================  ===========================================
kernel                 k     ``y``                                        parameters
=====================  ====  ===========================================  ===========================================
``stretch_jet``        6     ``D, Mp``                                    ``lbar, rbar, ks, nu``
``bend_cur_jet``       15    ``e1, e2, Dp, Pp, Ppp``                      ``lbar, rbar, k11bar, k22bar, kb, nu``
``bend_ref_jet``       15    the same (``kappa11`` with ``L = lbar``)     the same
``free_edge_jet``      12    ``e, Dp, Pp, Ppp``                           ``K, kbar, nu``
``volume_jet``         12    ``P_i, P_j, P'_i, P'_j``                     none
``skirt_jet``          6     ``P_0, P'_0``                                ``z_ref``
``pole_<side>_<L>_jet`` 15   ``Pm, Pm', Pc, Pq, Pq'``                     ``lbar`` (unused by ``cur``)
``stretch_general_jet``   6  ``D, Mp``                                    ``lbar, rbar, e12bar, ks, nu``
``bend_<L>_general_jet`` 15  ``e1, e2, Dp, Pp, Ppp``                      ``lbar, rbar, k11bar, k22bar, k12bar, kb, nu``
``free_edge_general_jet`` 12 ``e, Dp, Pp, Ppp``                           ``K, kbar, k12bar, nu``
=====================  ====  ===========================================  ===========================================

(:func:`~contin_models.shell.density.stretch_density`, :func:`~contin_models.shell.density.bend_density`
with ``L`` the current ``(|e1| + |e2|)/2`` or the reference ``lbar``,
:func:`~contin_models.shell.density.free_edge_density`, :func:`~contin_models.shell.density.volume_density`,
:func:`~contin_models.shell.density.skirt_density`; the pole kernels differentiate the directional
curvature :func:`~contin_models.shell.density.pole_curvature`, ``side`` ``north`` or ``south``: the pole's
energy is a function of the curvature's mean and mean square over the angle, which the view forms.  The
``general`` kernels differentiate :func:`~contin_models.shell.density.general_stretch_density`,
:func:`~contin_models.shell.density.general_bend_density` (``L`` as ``bend_cur`` or ``bend_ref``) and
:func:`~contin_models.shell.density.general_free_edge_density`: the same strains against a reference that
need not be axisymmetric, whose shear ``e12bar`` and twist ``k12bar`` are subtracted too.)

How
---
The bending density is a quadratic form in the three curvatures
(:func:`~contin_models.shell.density.bend_curvatures`): the kernel differentiates the curvatures
(value, gradient, Hessian, one common-subexpression elimination) and assembles the density's
derivatives by the chain rule, ``g = sum_a F_a g_a``, ``H = sum_a F_a H_a + sum_a (sum_b F_ab g_b) g_a^T``,
which costs far fewer operations than differentiating the density itself.  The outer quadratic form
is checked against :func:`~contin_models.shell.density.bend_density` at generation time (to 40
digits at a random point).  The other densities are differentiated directly (they are small or
polynomial).
"""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import sympy as sp

from contin.modelkit.codegen import KernelBody, c_extension_text, generator_main, kernel_printer, module_text

from . import density as D

__all__ = ["generate_source", "generate_c_source", "main", "symbolic", "DEFAULT_OUTPUT", "C_OUTPUT", "KERNELS"]

DEFAULT_OUTPUT = Path(__file__).with_name("_density_generated.py")
#: The same kernels as a C extension (``contin_models.shell._density_ckernels``), generated from the
#: committed numpy module by :func:`contin.modelkit.codegen.c_extension_text` and built when the package installs
C_OUTPUT = Path(__file__).with_name("_density_ckernels.c")
BEND_VARIANTS = ("bend_cur", "bend_ref")
POLE_VARIANTS = tuple(f"pole_{side}_{length}" for side in ("north", "south") for length in ("cur", "ref"))
#: The densities against a reference that need not be axisymmetric (a shear and a twist to subtract, the
#: reference numbers given per station).
GENERAL_VARIANTS = ("stretch_general", "bend_cur_general", "bend_ref_general", "free_edge_general")
#: Every generated kernel's name, in the order of the module.
KERNELS = tuple(f"{name}_jet" for name in ("stretch", *BEND_VARIANTS, "free_edge", "volume", "skirt", *POLE_VARIANTS,
                                           *GENERAL_VARIANTS))


def symbolic(function: Callable[..., Any], *args: Any) -> Any:
    """``function(*args)`` on sympy symbols (:func:`contin_models.shell.density.symbolic_sqrt`), each result's
    float constants made exact (``1.0 / 3.0`` is ``1/3``: no ``1.0*x`` left in the kernels)."""
    with D.symbolic_sqrt(sp.sqrt):
        out = function(*args)
    return tuple(_exact(e) for e in out) if isinstance(out, tuple) else _exact(out)


def _exact(e: sp.Expr) -> sp.Expr:
    return e.xreplace({f: sp.nsimplify(f) for f in e.atoms(sp.Float)})


def _vectors(y: Sequence[sp.Symbol]) -> list[tuple]:
    """The local variables as 3-vectors ``(y0, y1, y2), (y3, y4, y5), ...``."""
    return [tuple(y[i:i + 3]) for i in range(0, len(y), 3)]


def _derivatives(f: sp.Expr, y: Sequence[sp.Symbol]) -> tuple[dict[int, sp.Expr], dict[tuple[int, int], sp.Expr]]:
    """The nonzero entries of the gradient and of the upper Hessian of ``f`` in ``y``."""
    grad = {i: sp.diff(f, y[i]) for i in range(len(y))}
    grad = {i: g for i, g in grad.items() if g != 0}
    hess = {}
    for i, g in grad.items():
        for j in range(i, len(y)):
            h = sp.diff(g, y[j])
            if h != 0:
                hess[i, j] = h
    return grad, hess


def _kernel(name: str, doc: str, y: Sequence[sp.Symbol], inner: Sequence[sp.Expr], outer: sp.Expr,
            u: Sequence[sp.Symbol], params: Sequence[str]) -> str:
    """A kernel returning the value, gradient and Hessian of ``outer(inner(y))`` in ``y``.

    ``inner`` are a few functions of ``y`` (differentiated to second order and eliminated together),
    ``outer`` a function of the symbols ``u`` (one per inner function) and the parameters; the chain
    rule is written on the nonzero entries only.
    """
    k = len(y)
    printer = kernel_printer()
    body = KernelBody()
    derivs = [_derivatives(f, y) for f in inner]
    flat = list(inner)
    for grad, hess in derivs:
        flat += [grad[i] for i in sorted(grad)] + [hess[p] for p in sorted(hess)]
    named = iter(body.name(flat))
    values = [next(named) for _ in inner]
    grads, hesses = [], []
    for grad, hess in derivs:
        grads.append({i: next(named) for i in sorted(grad)})
        hesses.append({p: next(named) for p in sorted(hess)})
    at = dict(zip(u, values))
    first = body.name([sp.diff(outer, ua).xreplace(at) for ua in u])
    second = {(a, b): sp.diff(outer, u[a], u[b]).xreplace(at) for a in range(len(u)) for b in range(len(u))}
    # l_a = sum_b F_ab g_b: the second-order chain term is then sum_a l_a g_a^T
    left = []
    for a in range(len(u)):
        entries = {i: sp.Add(*[second[a, b] * grads[b][i] for b in range(len(u)) if i in grads[b]])
                   for i in range(k)}
        entries = {i: e for i, e in entries.items() if e != 0}
        left.append(dict(zip(entries, body.name(list(entries.values())))))
    value = outer.xreplace(at)
    gradient = {i: sp.Add(*[first[a] * grads[a][i] for a in range(len(u)) if i in grads[a]]) for i in range(k)}
    hessian = {}
    for i in range(k):
        for j in range(i, k):
            e = sp.Add(*[first[a] * hesses[a][i, j] for a in range(len(u)) if (i, j) in hesses[a]],
                       *[left[a][i] * grads[a][j] for a in range(len(u)) if i in left[a] and j in grads[a]])
            if e != 0:
                hessian[i, j] = e
    gpos = [i for i in range(k) if gradient[i] != 0]
    pairs = sorted(hessian)
    results = body.reduce([value] + [gradient[i] for i in gpos] + [hessian[p] for p in pairs])
    targets = ["_v"] + [f"_g[{i}]" for i in gpos] + [f"_h[{i}, {j}]" for i, j in pairs]
    unpack = ", ".join(f"y{i}" for i in range(k))
    lines = [f"def {name}({', '.join(['y', *params])}):", f'    """{doc}"""', f"    {unpack} = y",
             "    _shape = numpy.shape(y0)", f"    _g = numpy.zeros(({k},) + _shape)",
             f"    _h = numpy.zeros(({k}, {k}) + _shape)"]
    lines += body.lines([], results, printer, targets)
    lines += [f"    _h[{j}, {i}] = _h[{i}, {j}]" for i, j in pairs if i != j]
    lines.append("    return _v, _g, _h")
    return "\n".join(lines)


def _bend_quadratic(k11: Any, k22: Any, k12: Any, lbar: Any, rbar: Any, k11bar: Any, k22bar: Any, kb: Any,
                    nu: Any, k12bar: Any = 0) -> Any:
    """The bending density as the quadratic form in the curvatures that :func:`density.general_bend_density`
    evaluates (checked against it by :func:`_check_equal`)."""
    b11, b22, b12 = k11 - k11bar, k22 - k22bar, k12 - k12bar
    return (b11 ** 2 + 2 * nu * b11 * b22 + b22 ** 2 + 2 * (1 - nu) * b12 ** 2) * (rbar * lbar * kb / 2)


def _check_equal(a: sp.Expr, b: sp.Expr, symbols: Sequence[sp.Symbol], what: str) -> None:
    """Raise unless ``a`` and ``b`` agree to 40 digits at a random point (every symbol in 0.2 .. 0.9)."""
    rng = random.Random(1)
    point = {s: sp.Rational(rng.randint(200, 900), 1000) for s in symbols}
    da, db = sp.N(a.xreplace(point), 50), sp.N(b.xreplace(point), 50)
    if abs(da - db) > sp.Float(10) ** -40 * (1 + abs(db)):
        raise AssertionError(f"{what}: the chain rule's outer function differs from the density ({da} vs {db})")


def _bend_kernel(variant: str) -> str:
    y = sp.symbols("y0:15", real=True)
    general = variant.endswith("_general")
    names = "lbar rbar k11bar k22bar k12bar kb nu" if general else "lbar rbar k11bar k22bar kb nu"
    params = sp.symbols(names, real=True)
    by = dict(zip(names.split(), params))
    lbar = params[0]
    L = None if variant.startswith("bend_cur") else lbar
    curv = symbolic(D.bend_curvatures, *_vectors(y), L)
    u = sp.symbols("_k11 _k22 _k12", real=True)
    outer = _bend_quadratic(*u, *(by[p] for p in "lbar rbar k11bar k22bar kb nu".split()), by.get("k12bar", 0))
    density = D.general_bend_density if general else D.bend_density
    _check_equal(outer.xreplace(dict(zip(u, curv))), symbolic(density, *_vectors(y), *params, L),
                 (*y, *params), variant)
    length = "the current ``(|e1| + |e2|)/2``" if L is None else "``lbar``"
    against = " against a reference with the twist ``k12bar``" if general else ""
    doc = (f"Value, gradient ``(15, ...)`` and Hessian ``(15, 15, ...)`` of the bending density per radian of an "
           f"interior node in ``(e1, e2, Dp, Pp, Ppp)`` (``L`` {length}){against}.")
    return _kernel(f"{variant}_jet", doc, y, curv, outer, u, [str(p) for p in params])


def _direct_kernel(name: str, what: str, variables: str, density: Callable[..., Any], params: Sequence[str]) -> str:
    """A kernel differentiating ``density(*vectors, *params)`` itself (its own single inner function);
    ``variables`` names its vector arguments, ``what`` says what it is."""
    k = 3 * len(variables.split(", "))
    y = sp.symbols(f"y0:{k}", real=True)
    E = symbolic(density, *_vectors(y), *[sp.Symbol(p, real=True) for p in params])
    u = sp.Symbol("_u0", real=True)
    doc = f"Value, gradient ``({k}, ...)`` and Hessian ``({k}, {k}, ...)`` of {what} in ``({variables})``."
    return _kernel(name, doc, y, [E], u, [u], params)


def _pole_kernel(variant: str) -> str:
    north, current = "_north_" in variant, variant.endswith("_cur")
    return _direct_kernel(f"{variant}_jet", f"the pole's directional curvature ({variant})", "Pm, Pm', Pc, Pq, Pq'",
                          lambda *a: D.pole_curvature(*a[:5], north, None if current else a[5]), ["lbar"])


def _kernels() -> list[str]:
    """Every kernel's source, in the order of :data:`KERNELS`."""
    return ([_direct_kernel("stretch_jet", "the stretching density per radian of an edge", "D, Mp", D.stretch_density,
                            ["lbar", "rbar", "ks", "nu"])]
            + [_bend_kernel(v) for v in BEND_VARIANTS]
            + [_direct_kernel("free_edge_jet", "the bending density per radian of a rotating edge", "e, Dp, Pp, Ppp",
                              D.free_edge_density, ["K", "kbar", "nu"]),
               _direct_kernel("volume_jet", "the volume per radian of the strip between two rings",
                              "P_i, P_j, P'_i, P'_j", D.volume_density, []),
               _direct_kernel("skirt_jet", "the skirt's volume per radian", "P_0, P'_0", D.skirt_density, ["z_ref"])]
            + [_pole_kernel(v) for v in POLE_VARIANTS]
            + [_direct_kernel("stretch_general_jet", "the stretching density per radian of an edge against any "
                              "reference", "D, Mp", D.general_stretch_density, ["lbar", "rbar", "e12bar", "ks", "nu"]),
               _bend_kernel("bend_cur_general"), _bend_kernel("bend_ref_general"),
               _direct_kernel("free_edge_general_jet", "the bending density per radian of a rotating edge against any "
                              "reference", "e, Dp, Pp, Ppp", D.general_free_edge_density, ["K", "kbar", "k12bar", "nu"])])


_PREAMBLE = '''"""Generated by ``python -m contin_models.shell.density_codegen``: do not edit.

Value, gradient and Hessian of the 2-D shell densities per radian (:mod:`contin_models.shell.harmonic`)
in their local variables at any state, vectorised over stations; see the generator's docstring.
"""

import numpy'''


def generate_source() -> str:
    """The full text of the generated module."""
    return module_text(_PREAMBLE, KERNELS, f"KERNELS = {KERNELS!r}", _kernels())


def generate_c_source(python_source: str | None = None) -> str:
    """Text of ``_density_ckernels.c``: every kernel of ``python_source`` in C.

    Each kernel unpacks its stacked variables ``y``; the C function takes them one by one, flattened
    over the stations (:func:`contin.numerics.compiled.prefer_compiled` does that).

    Parameters
    ----------
    python_source : str or None
        Text of the numpy module (``None``: the committed ``_density_generated.py``, which the C
        file is generated from and checked against).
    """
    text = DEFAULT_OUTPUT.read_text(encoding="utf-8") if python_source is None else python_source
    return c_extension_text(text, {}, "_density_ckernels",
                            "Value, gradient and Hessian of the 2-D densities at general states "
                            "(contin_models.shell._density_ckernels).", returning=KERNELS, simd=True)


def main(argv: list[str] | None = None) -> int:
    """The generator's command line (:func:`contin.modelkit.codegen.generator_main`): ``--output PATH``, ``--check``.

    Without ``--output`` the C extension's source :data:`C_OUTPUT` is written (or checked) too.
    """
    return generator_main(argv, generate_source, DEFAULT_OUTPUT, "python -m contin_models.shell.density_codegen",
                          "Generate the 2-D densities' value, gradient and Hessian kernels at general states.",
                          companions=[(generate_c_source, C_OUTPUT)])


if __name__ == "__main__":
    raise SystemExit(main())
