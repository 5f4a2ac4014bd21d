"""Generate :mod:`contin_models.shell._harmonic_generated`: local derivatives of the 2-D densities at axisymmetric states.

Run as ``python -m contin_models.shell.harmonic_codegen [--output PATH] [--check]`` (about half a
minute).  Only this module imports sympy; the emitted file is plain vectorised numpy and is
committed.

What is generated
-----------------
* ``<variant>_hessian(y0, y2, y3, y5, y7, y10, lbar, rbar, k11bar, k22bar, kb, nu)``: the Hessian
  ``(15, 15, m)`` of :func:`contin_models.shell.harmonic.bend_density` in an interior node's 15 local
  variables ``y = (e1, e2, Dp, Pp, Ppp)`` (each a 3-vector ``(r, t, z)`` in the local frame) at an
  axisymmetric state, where ``e1 = (y0, 0, y2)``, ``e2 = (y3, 0, y5)``, ``Dp = (0, y7, 0)``,
  ``Pp = (0, y10, 0)``, ``Ppp = (-y10, 0, 0)``.  The density is quadratic in the curvatures
  (:func:`~contin_models.shell.harmonic.bend_curvatures`), so the kernel differentiates those
  (``kappa11`` and ``kappa22`` to second order, ``kappa12``, which vanishes there, to first) and
  assembles the Hessian by the chain rule on the nonzero entries only: fewer operations than
  differentiating the density itself.  Two variants: ``bend_cur`` (``L`` the current
  ``(|e1| + |e2|)/2``) and ``bend_ref`` (``L = lbar``, the reference Voronoi length; also the clamp's
  element).
* ``stretch_hessian(y0, y2, y4, lbar, rbar, ks, nu)``: the Hessian ``(6, 6, m)`` of
  :func:`~contin_models.shell.harmonic.stretch_density` in ``(D, Mp)`` at ``D = (y0, 0, y2)``,
  ``Mp = (0, y4, 0)``;
* ``pole_<north|south>_<cur|ref>_jet(y0, y2, y4, y6, y8, y9, y11, y13, lbar)``: the value, gradient
  ``(15,)`` and Hessian ``(15, 15)`` of :func:`~contin_models.shell.harmonic.pole_curvature` in
  ``(Pm, Pm', Pc, Pq, Pq')`` at ``Pm = (y0, 0, y2)``, ``Pm' = (0, y4, 0)``, ``Pc = (y6, 0, y8)``,
  ``Pq = (y9, 0, y11)``, ``Pq' = (0, y13, 0)`` (scalars: a pole is one element);
* ``free_edge_hessian(y0, y2, y4, y7, y9, K, kbar, nu)``: the Hessian ``(12, 12)`` of
  :func:`~contin_models.shell.harmonic.free_edge_density` in ``(e, Dp, Pp, Ppp)`` at ``e = (y0, 0, y2)``,
  ``Dp = (0, y4, 0)``, ``Pp = (0, y7, 0)``, ``Ppp = (y9, 0, 0)`` (scalars: a rotating edge is one element).

They evaluate the same expressions as the jets of :class:`contin_models.shell.harmonic.Jet` (the
``method="jets"`` reference), which ``tests/test_harmonic.py`` compares them with.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import sympy as sp

from contin.modelkit.codegen import c_extension_text, cse_lines, generator_main, kernel_printer, module_text

from . import density
from . import harmonic as H

__all__ = ["generate_source", "generate_c_source", "main", "DEFAULT_OUTPUT", "C_OUTPUT", "VARIANTS"]

DEFAULT_OUTPUT = Path(__file__).with_name("_harmonic_generated.py")
#: The same kernels as a C extension (``contin_models.shell._harmonic_ckernels``), generated from the
#: committed numpy module by :func:`contin.modelkit.codegen.c_extension_text` and built when the package installs
C_OUTPUT = Path(__file__).with_name("_harmonic_ckernels.c")
VARIANTS = ("bend_cur", "bend_ref")
_FREE = (0, 2, 3, 5, 7, 10)
_STRETCH_FREE = (0, 2, 4)
POLE_VARIANTS = tuple(f"pole_{side}_{length}" for side in ("north", "south") for length in ("cur", "ref"))


def _bend_kernel(variant: str) -> str:
    """The bending density's Hessian at axisymmetric states: the curvatures' jets, then the chain rule."""
    y = sp.symbols("y0:15", real=True)
    lbar = sp.Symbol("lbar", real=True)
    curv = _symbolic(density.bend_curvatures, tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]),
                     tuple(y[12:15]), None if variant == "bend_cur" else lbar)
    axisym = {y[k]: 0 for k in range(15) if k not in _FREE and k != 12}
    axisym[y[12]] = -y[10]
    exprs, targets = [], []
    grad: dict[str, dict[int, str]] = {}
    hess: dict[str, dict[tuple[int, int], str]] = {}
    for name, kappa, hessian in (("k11", curv[0], True), ("k22", curv[1], True), ("k12", curv[2], False)):
        if name != "k12":  # kappa12 vanishes at axisymmetric states; only its gradient enters
            exprs.append(kappa.subs(axisym))
            targets.append(f"_{name}")
        grads = [sp.diff(kappa, y[i]) for i in range(15)]
        grad[name] = {}
        for i in range(15):
            e = grads[i].subs(axisym)
            if e != 0:
                exprs.append(e)
                targets.append(grad[name].setdefault(i, f"_g{name}_{i}"))
        if hessian:
            hess[name] = {}
            for i in range(15):
                for j in range(i, 15):
                    # every variable but y_j may take its axisymmetric value before the last differentiation
                    keep = {y[j]} | ({y[10], y[12]} if j in (10, 12) else set())
                    pre = {k: v for k, v in axisym.items() if k not in keep}
                    e = sp.diff(grads[i].subs(pre), y[j]).subs(axisym)
                    if e != 0:
                        exprs.append(e)
                        targets.append(hess[name].setdefault((i, j), f"_h{name}_{i}_{j}"))
    args = ", ".join([f"y{k}" for k in _FREE] + ["lbar", "rbar", "k11bar", "k22bar", "kb", "nu"])
    lines = [f"def {variant}_hessian({args}):",
             '    """Hessian ``(15, 15, m)`` of the bending density per radian of an interior node'
             f' ({variant}) at axisymmetric states."""',
             "    _m = numpy.shape(y0)[0]",
             "    _h = numpy.zeros((15, 15, _m))"]
    lines += cse_lines(exprs, targets, kernel_printer())
    # the density c (B11^2 + 2 nu B11 B22 + B22^2 + 2 (1 - nu) kappa12^2), c = rbar lbar kb / 2, B = kappa -
    # kappabar, by the chain rule with kappa12 = 0: 2 c ((B11 + nu B22) H11 + (B22 + nu B11) H22 + g11 (g11 +
    # nu g22)^T + g22 (nu g11 + g22)^T + 2 (1 - nu) g12 g12^T)
    lines += ["    _wt = rbar*lbar*kb", "    _b11 = _k11 - k11bar", "    _b22 = _k22 - k22bar",
              "    _f11 = _wt*(_b11 + nu*_b22)", "    _f22 = _wt*(_b22 + nu*_b11)", "    _f12 = 2.0*_wt*(1.0 - nu)"]
    g11, g22, g12 = grad["k11"], grad["k22"], grad["k12"]
    left: dict[str, dict[int, str]] = {"l11": {}, "l22": {}, "l12": {}}
    for i in range(15):
        for out, parts in (("l11", [(g11, ""), (g22, "nu*")]), ("l22", [(g11, "nu*"), (g22, "")]),
                           ("l12", [(g12, "")])):
            terms = [f"{factor}{g[i]}" for g, factor in parts if i in g]
            if terms:
                weight = "_f12" if out == "l12" else "_wt"
                left[out][i] = f"_{out}_{i}"
                lines.append(f"    _{out}_{i} = {weight}*({' + '.join(terms)})" if len(terms) > 1
                             else f"    _{out}_{i} = {weight}*{terms[0]}")
    pairs = []
    for i in range(15):
        for j in range(i, 15):
            terms = [f"{f}*{hess[k][(i, j)]}" for f, k in (("_f11", "k11"), ("_f22", "k22")) if (i, j) in hess[k]]
            terms += [f"{left[l][i]}*{g[j]}" for l, g in (("l11", g11), ("l22", g22), ("l12", g12))
                      if i in left[l] and j in g]
            if terms:
                pairs.append((i, j))
                lines.append(f"    _h[{i}, {j}] = {' + '.join(terms)}")
    lines += [f"    _h[{j}, {i}] = _h[{i}, {j}]" for i, j in pairs if i != j]
    lines.append("    return _h")
    return "\n".join(lines)


def _symbolic(function: Callable[..., Any], *args: Any) -> Any:
    """``function(*args)`` on sympy symbols (the densities take their square roots by ``density._sqrt``)."""
    with density.symbolic_sqrt(sp.sqrt):
        return function(*args)


def _hessian_kernel(name: str, doc: str, energy: Any, y: Sequence[Any], free: Sequence[int], params: Sequence[str],
                    per_element: bool) -> str:
    """A kernel returning the Hessian ``(k, k[, m])`` of ``energy`` in the ``k`` variables ``y`` at axisymmetric
    states, where every variable but those numbered ``free`` (the kernel's first arguments, then ``params``)
    is zero; ``per_element``: its inputs are arrays of ``m`` elements, else numbers."""
    k = len(y)
    axisym = {y[i]: 0 for i in range(k) if i not in free}
    exprs = {(i, j): sp.diff(energy, y[i], y[j]).subs(axisym) for i in range(k) for j in range(i, k)}
    pairs = [p for p, e in exprs.items() if e != 0]
    args = ", ".join([f"y{i}" for i in free] + list(params))
    lines = [f"def {name}({args}):", f'    """{doc}"""']
    if per_element:
        lines += ["    _m = numpy.shape(y0)[0]", f"    _out = numpy.zeros(({k}, {k}, _m))"]
    else:
        lines += [f"    _out = numpy.zeros(({k}, {k}))"]
    lines += cse_lines([exprs[p] for p in pairs], [f"_out[{i}, {j}]" for i, j in pairs], kernel_printer())
    lines += [f"    _out[{j}, {i}] = _out[{i}, {j}]" for i, j in pairs if i != j]
    lines.append("    return _out")
    return "\n".join(lines)


def _stretch_kernel() -> str:
    y = sp.symbols("y0:6", real=True)
    lbar, rbar, ks, nu = sp.symbols("lbar rbar ks nu", real=True)
    E = _symbolic(density.stretch_density, tuple(y[0:3]), tuple(y[3:6]), lbar, rbar, ks, nu)
    return _hessian_kernel("stretch_hessian",
                           "Hessian ``(6, 6, m)`` of the stretching density per radian at axisymmetric states.",
                           E, y, _STRETCH_FREE, ("lbar", "rbar", "ks", "nu"), per_element=True)


def _pole_kernel(variant: str) -> str:
    y = sp.symbols("y0:15", real=True)
    lbar = sp.Symbol("lbar", real=True)
    north = "_north_" in variant
    kap = _symbolic(density.pole_curvature, tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]),
                    tuple(y[12:15]), north, None if variant.endswith("_cur") else lbar)
    axisym = {y[k]: 0 for k in range(15) if k not in H.POLE_FREE}
    grads = [sp.diff(kap, y[i]) for i in range(15)]
    exprs = [kap.subs(axisym)] + [g.subs(axisym) for g in grads]
    targets = ["_v", *[f"_g[{i}]" for i in range(15)]]
    pairs = []
    for i in range(15):
        for j in range(i, 15):
            e = sp.diff(grads[i], y[j]).subs(axisym)
            if e != 0:
                pairs.append((i, j))
                exprs.append(e)
                targets.append(f"_h[{i}, {j}]")
    keep = [(e, t) for e, t in zip(exprs, targets) if e != 0 or t == "_v"]
    args = ", ".join([f"y{k}" for k in H.POLE_FREE] + ["lbar"])
    lines = [f"def {variant}_jet({args}):",
             f'    """Value, gradient ``(15,)`` and Hessian ``(15, 15)`` of the pole curvature ({variant}) at an axisymmetric state."""',
             "    _g = numpy.zeros(15)",
             "    _h = numpy.zeros((15, 15))"]
    lines += cse_lines([e for e, _ in keep], [t for _, t in keep], kernel_printer())
    lines += [f"    _h[{j}, {i}] = _h[{i}, {j}]" for i, j in pairs if i != j]
    lines.append("    return _v, _g, _h")
    return "\n".join(lines)


def _free_edge_kernel() -> str:
    y = sp.symbols("y0:12", real=True)
    K, kbar, nu = sp.symbols("K kbar nu", real=True)
    E = _symbolic(density.free_edge_density, tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]), K, kbar, nu)
    return _hessian_kernel("free_edge_hessian",
                           "Hessian ``(12, 12)`` of the bending density per radian of a rotating edge at an "
                           "axisymmetric state.", E, y, H.FREE_EDGE_FREE, ("K", "kbar", "nu"), per_element=False)


_PREAMBLE = '''"""Generated by ``python -m contin_models.shell.harmonic_codegen``: do not edit.

The local Hessians of the 2-D bending and stretching densities per radian
(:func:`contin_models.shell.harmonic.bend_density`, :func:`~contin_models.shell.harmonic.stretch_density`,
:func:`~contin_models.shell.harmonic.free_edge_density`) and the pole curvature's jets at axisymmetric
states; see the generator's docstring.
"""

import numpy'''


def generate_source() -> str:
    """The full text of the generated module."""
    names = ([f"{v}_hessian" for v in VARIANTS] + ["stretch_hessian"] + [f"{v}_jet" for v in POLE_VARIANTS]
             + ["free_edge_hessian"])
    return module_text(_PREAMBLE, names, 'VARIANTS = ("bend_cur", "bend_ref")',
                       [_bend_kernel(v) for v in VARIANTS] + [_stretch_kernel()]
                       + [_pole_kernel(v) for v in POLE_VARIANTS] + [_free_edge_kernel()])


def generate_c_source(python_source: str | None = None) -> str:
    """Text of ``_harmonic_ckernels.c``: every kernel of ``python_source`` in C.

    Parameters
    ----------
    python_source : str or None
        Text of the numpy module (``None``: the committed ``_harmonic_generated.py``, which the C
        file is generated from and checked against).
    """
    import ast

    text = DEFAULT_OUTPUT.read_text(encoding="utf-8") if python_source is None else python_source
    names = [f.name for f in ast.parse(text).body if isinstance(f, ast.FunctionDef)]
    return c_extension_text(text, {}, "_harmonic_ckernels",
                            "Local Hessian kernels of the harmonic blocks (contin_models.shell._harmonic_ckernels).",
                            returning=names)


def main(argv: list[str] | None = None) -> int:
    """The generator's command line (:func:`contin.modelkit.codegen.generator_main`): ``--output PATH``, ``--check``.

    Without ``--output`` the C extension's source :data:`C_OUTPUT` is written (or checked) too.
    """
    return generator_main(argv, generate_source, DEFAULT_OUTPUT, "python -m contin_models.shell.harmonic_codegen",
                          "Generate the harmonic blocks' bending Hessian kernels.",
                          companions=[(generate_c_source, C_OUTPUT)])


if __name__ == "__main__":
    raise SystemExit(main())
