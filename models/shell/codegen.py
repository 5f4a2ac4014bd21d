"""Generate :mod:`contin_models.shell._generated` from sympy definitions of the local element energies.

Run as ``python -m contin_models.shell.codegen [--output PATH] [--check]``.  This is the only module of
the shell model that imports sympy; the emitted file is plain vectorised numpy and is committed.
Regenerating must reproduce the committed file byte for byte (``tests/test_shell_energy.py`` checks
it): the output is built from a fixed element list in a fixed order, common subexpressions get
stable names ``_c0, _c1, ...`` and nothing time- or machine-dependent is written.

Elements (notation of ``docs/model.md#the-discrete-shell``; a bar means "in the reference configuration")
------------------------------------------------------------------------------------------------
``stretch``
    One edge ``i`` between nodes ``(r0, z0)``, ``(r1, z1)``; 4 local dofs ``[r0, z0, r1, z1]``.
    ``eps11 = l / lbar - 1``, ``eps22 = r_edge / rbar - 1`` with ``r_edge = (r0 + r1) / 2``;
    energy ``pi rbar lbar ks (eps11^2 + 2 nu eps11 eps22 + eps22^2)``, ``ks = E h / (1 - nu^2)``.
``bend`` and ``bend_cur``
    One interior node ``i`` with neighbours ``i-1`` and ``i+1``; 6 local dofs
    ``[r0, z0, r1, z1, r2, z2]`` (node ``i`` is ``(r1, z1)``).  With ``e1 = x1 - x0``,
    ``e2 = x2 - x1``, ``cross = e1 x e2``, ``dot = e1 . e2``:

    * ``kappa11 = 2 tan(xi / 2) / L = 2 cross / ((|e1| |e2| + dot) L)``, ``xi`` the signed
      turning angle (positive when the meridian turns counter-clockwise, as it does on the
      reference cap traversed from base to pole).  ``L = lbar`` (reference Voronoi length, the
      paper's eq. 3.9 read with a bar, ``docs/model.md#the-discrete-shell``) for ``bend``;
      ``L = (|e1| + |e2|) / 2`` (current Voronoi length) for ``bend_cur``.
    * ``kappa22 = n_r / r1`` with the node normal ``n`` = the unit bisector of the two edge
      normals, i.e. ``t = e1/|e1| + e2/|e2|`` rotated clockwise: ``n = (t_z, -t_r) / |t|``.  In
      closed form ``n_r = (e1_z/|e1| + e2_z/|e2|) / sqrt(2 + 2 dot / (|e1| |e2|))``.
      For three nodes equally spaced on a circle centred on the axis the bisector is the radius
      through the middle node, so ``kappa22 = 1/R`` exactly on the uniformly meshed reference
      sphere (and ``1/((1+e) R)`` after a dilation).
    * energy ``pi rbar lbar kb (B11^2 + 2 nu B11 B22 + B22^2)``, ``B = kappa - kappabar``,
      ``kb = E h^3 / (12 (1 - nu^2))``.

    Both curvatures are smooth wherever the two edges do not fold back onto each other
    (``|e1| |e2| + dot > 0``); no ``atan2`` appears.

How the derivatives are generated
---------------------------------
The formulas above are the 2-D densities of :mod:`contin_models.shell.density` at axisymmetric states
(:func:`axisymmetric_restriction`): :attr:`Element.strains` are those restrictions, in the node
coordinates, and the element's energy is ``2 pi`` times the density.  Before an element is emitted,
:func:`check_axisymmetric_restriction` asserts that the strains the kernels compute are the
density's, that the third strain (shear, twist) vanishes and that the weights agree.  The
emitted code evaluates the same functions and their exact derivatives through a chain of changes of
variables in which every step is small, which makes the kernels several times shorter than
differentiating the Cartesian formulas directly (numpy pays per array operation, and for a few
hundred elements that cost is nearly independent of the array length):

1. *Local variables* (the kernel arguments): quantities the element depends on linearly: ``e1``,
   ``e2`` and ``r1`` for bending (5 numbers), ``e`` and ``r0 + r1`` for stretching (3).  The map
   to the node coordinates is a constant matrix ``T``: ``grad_x = T^T grad``,
   ``hess_x = T^T hess T``.
2. *Edge polar variables*: each edge vector is ``l (c, s)`` with ``(c, s) = (cos theta,
   sin theta)``.  Writing ``d theta = d tau / l`` (a diagonal scaling, its own step), the Jacobian
   of ``(l, tau)`` with respect to the edge vector is the rotation ``[[c, s], [-s, c]]``, and the
   second derivatives of ``l`` and ``theta`` are closed forms in ``c``, ``s`` and ``1/l``
   (:func:`_edge_rotation`).  The rotation step is written with double angles
   (:func:`_rotate`) when that takes fewer operations than the generic product (the generator
   emits whichever variant of a kernel is shorter).
3. *Strain variables* for bending: ``|e1|``, ``theta1``, ``|e2|``, ``theta2``, ``r1``:
   ``kappa11 = 2 tan(psi) / L`` with ``psi = (theta2 - theta1) / 2 = xi / 2`` and
   ``kappa22 = sin(phi) / r1`` with ``phi = (theta1 + theta2) / 2`` (the unit bisector normal is
   ``(sin phi, -cos phi)``).  Sympy differentiates these with ``tan psi``, ``sin phi``,
   ``cos phi``, ``1/(|e1| + |e2|)`` and ``1/r1`` as opaque functions (:class:`_TanHalfTurn`,
   :class:`_SinMid`, :class:`_CosMid`, :class:`_Recip`) that are then replaced by quantities the
   kernel computes algebraically from the edge vectors: ``tan psi = cross / (|e1| |e2| + dot)``
   and ``(cos phi, sin phi) = (c1 + c2, s1 + s2) / |t|`` with
   ``1 / |t|^2 = |e1| |e2| / (2 (|e1| |e2| + dot))``.  No angle is ever computed.  For stretching
   the strain variables are ``l`` and ``r0 + r1``, in which the strains are linear.

Each step is the exact chain rule ``g' = A^T g``, ``H' = A^T H A + sum_k g_k hess(v_k)``; the
entries of every intermediate gradient and Hessian get names, common subexpressions are
eliminated within and across steps (also up to sign) and dead assignments dropped
(:class:`contin.modelkit.codegen.KernelBody`, the engine's kernel body).
``tests/test_shell_energy.py`` compares the kernels with a direct sympy differentiation of the
Cartesian definitions evaluated in 30-digit arithmetic (:meth:`Element.cartesian_gradient`,
:meth:`Element.cartesian_hessian_upper`) and with finite differences.

Generated functions
-------------------
For every element (``<name>`` = ``stretch``, ``bend``, ``bend_cur``):

* the fast kernels used by :class:`contin_models.shell.ShellEnergy`, taking the local variables (names in
  ``INPUTS[name]``) and the parameters, arrays of one common shape (scalars for the parameters
  are allowed), no broadcasting of the local variables:
  ``<name>_fast_energy`` (shape ``(m,)``), ``<name>_fast_gradient`` (*packed*: shape
  ``(ndof, m)``, derivatives with respect to the node coordinates), ``<name>_fast_hessian``
  (*packed*: shape ``(ndof (ndof + 1) / 2, m)``, the upper triangle ``a <= b`` row by row, the
  pairs in ``UPPER[name]``), ``<name>_fast_gradient_hessian`` (the gradient's rows, then the
  Hessian's, from one body: the engine asks for both at almost every state) and
  ``<name>_fast_<strains>``;
* convenience versions with the node coordinates as arguments, broadcasting over all arguments
  and with unpacked outputs: ``<name>_energy`` (``(m,)``), ``<name>_gradient`` (``(m, ndof)``),
  ``<name>_hessian`` (``(m, ndof, ndof)``) and the strain helper (``stretch_strains`` /
  ``bend_curvatures`` / ``bend_cur_curvatures``, a tuple of two ``(m,)`` arrays).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
import random
from pathlib import Path

import sympy as sp
from sympy.printing.numpy import NumPyPrinter

from contin.modelkit.codegen import (KernelBody, c_extension_text, count_operations, emitted_helpers, function_header,
                            generator_main, kernel_printer, module_text, upper_pairs)

from . import density
from .density_codegen import symbolic

__all__ = ["Element", "Layer", "build_elements", "axisymmetric_restriction", "check_axisymmetric_restriction",
           "generate_source", "generate_c_source", "main", "DEFAULT_OUTPUT",
           "C_OUTPUT"]

DEFAULT_OUTPUT = Path(__file__).with_name("_generated.py")
#: The same fast kernels as a C extension (``contin_models.shell._ckernels``), generated from the
#: committed numpy module by :func:`contin.modelkit.codegen.c_extension_text` and built when the package installs
C_OUTPUT = Path(__file__).with_name("_ckernels.c")


@dataclass
class Layer:
    """One change of variables ``v = v(u)`` in the chain from the strain variables to the kernel inputs.

    Attributes
    ----------
    outer : list of sympy.Symbol
        The variables ``v`` of the previous step (the strain variables for the first layer).
    inner : list of sympy.Symbol
        The new variables ``u``.
    jacobian : list of list of sympy.Expr
        ``d v_i / d u_j``, shape ``(len(outer), len(inner))``.
    hessians : dict of int to list of list of sympy.Expr
        ``d^2 v_i / d u d u`` for the outer variables that are nonlinear in ``u`` (by index).
    rotations : list of tuple
        Set when the layer maps edge variables ``(l, tau)`` to edge vectors by rotations (see
        :func:`_edge_rotation`): ``(index of l, index of tau or None, index of the edge's first
        inner variable, c, s, 1/l)`` per edge; the other outer variables are copied to the inner
        ones as :attr:`passthrough` says.  The chain rule is then written with the rotation
        structure (fewer operations than the generic ``A^T H A``, same result).
    passthrough : dict of int to int
        Outer index to inner index of the variables a rotation layer copies.
    """

    outer: list
    inner: list
    jacobian: list
    hessians: dict = field(default_factory=dict)
    rotations: list = field(default_factory=list)
    passthrough: dict = field(default_factory=dict)


@dataclass
class Element:
    """A local element whose energy is a quadratic form in two strain measures.

    The energy is ``weight * (s1^2 + 2 nu s1 s2 + s2^2)`` with ``s = strains - reference``.  Its
    derivatives follow by the chain rule through the strains, ``grad = J^T w`` and
    ``hess = J^T C J + sum_c w_c hess(strain_c)`` with ``J`` the strain Jacobian, ``w`` the
    stress-like derivative of the quadratic form and ``C`` its constant matrix, and then through the
    :attr:`layers` down to the kernel inputs and the node coordinates (module docstring).

    Attributes
    ----------
    name : str
        Prefix of the generated functions.
    dofs : list of sympy.Symbol
        Local degrees of freedom (node coordinates), in the order of the gradient and Hessian.
    params : list of sympy.Symbol
        Further (per-element or material) arguments, after the dofs.
    strains : dict of str to sympy.Expr
        The two strain measures as functions of :attr:`dofs` (the definition: the 2-D density's,
        :func:`axisymmetric_restriction`), returned by the helper ``<name>_<strains_name>``.
    reference : tuple of sympy.Expr
        Their reference values (subtracted before the quadratic form).
    weight : sympy.Expr
        Prefactor of the quadratic form (area weight times stiffness).
    nu : sympy.Symbol
        Poisson's ratio, the coupling in the quadratic form.
    inputs : list of (sympy.Symbol, sympy.Expr)
        Arguments of the fast kernels, each a linear function of :attr:`dofs`.
    prelude : list of (sympy.Symbol, sympy.Expr)
        Quantities computed from the inputs and parameters, in order, at the start of every kernel.
    strain_values : tuple of sympy.Symbol
        The prelude symbols holding the two strains.
    variables : list of sympy.Symbol
        Strain variables: the strains are :attr:`strain_formulas` of these.
    strain_formulas : tuple of sympy.Expr
        The strains as functions of :attr:`variables`; they may contain opaque functions with
        known derivatives (``tan psi``, ``sin phi``, ``cos phi``, reciprocals), replaced after
        differentiation through :attr:`trig`.
    trig : dict of sympy.Expr to sympy.Symbol
        Replacement of those functions by prelude symbols.
    rewrite : dict of sympy.Expr to sympy.Symbol
        Products to express through prelude symbols after the replacement (``4 isum tn -> k11``:
        the derivatives then reuse the strains).
    layers : list of Layer
        Changes of variables from :attr:`variables` to the inputs (the last layer's ``inner``).
    strains_name : str
        Suffix of the strain helper.
    doc : str
        One-line description used in the generated docstrings.
    """

    name: str
    dofs: list
    params: list
    strains: dict
    reference: tuple
    weight: sp.Expr
    nu: sp.Symbol
    inputs: list
    prelude: list
    strain_values: tuple
    variables: list
    strain_formulas: tuple
    trig: dict
    layers: list
    rewrite: dict = field(default_factory=dict)
    strains_name: str = "strains"
    doc: str = ""

    # ---- the definition, differentiated directly (reference for the tests) ----------------------
    def _s(self) -> list[sp.Expr]:
        return [e - ref for e, ref in zip(self.strains.values(), self.reference)]

    @property
    def energy(self) -> sp.Expr:
        """The element energy as one sympy expression of :attr:`dofs`."""
        s1, s2 = self._s()
        return self.weight * (s1**2 + 2 * self.nu * s1 * s2 + s2**2)

    def cartesian_gradient(self) -> list[sp.Expr]:
        """Exact gradient with respect to :attr:`dofs` by direct differentiation of :attr:`strains`."""
        s1, s2 = self._s()
        w = (2 * self.weight * (s1 + self.nu * s2), 2 * self.weight * (self.nu * s1 + s2))
        jac = [[sp.diff(e, q) for q in self.dofs] for e in self.strains.values()]
        return [w[0] * jac[0][a] + w[1] * jac[1][a] for a in range(len(self.dofs))]

    def cartesian_hessian_upper(self) -> tuple[list[tuple[int, int]], list[sp.Expr]]:
        """Exact Hessian entries ``(a, b)``, ``a <= b``, by direct differentiation of :attr:`strains`."""
        s1, s2 = self._s()
        n = len(self.dofs)
        w = (2 * self.weight * (s1 + self.nu * s2), 2 * self.weight * (self.nu * s1 + s2))
        c = ((2 * self.weight, 2 * self.weight * self.nu), (2 * self.weight * self.nu, 2 * self.weight))
        jac = [[sp.diff(e, q) for q in self.dofs] for e in self.strains.values()]
        pairs = list(upper_pairs(n))
        entries = []
        for a, b in pairs:
            gauss_newton = sum(jac[i][a] * c[i][j] * jac[j][b] for i in range(2) for j in range(2))
            curvature = sum(w[i] * sp.diff(jac[i][a], self.dofs[b]) for i in range(2))
            entries.append(gauss_newton + curvature)
        return pairs, entries

    # ---- the chain of small steps (what is emitted) ---------------------------------------------
    def input_map(self) -> list[list[sp.Expr]]:
        """``T[i][a] = d input_i / d dof_a`` (constant)."""
        T = [[sp.diff(e, q) for q in self.dofs] for _, e in self.inputs]
        assert all(t.is_Number for row in T for t in row), "inputs must be linear in the dofs"
        return T

    @property
    def moduli(self) -> list[tuple[sp.Symbol, sp.Expr]]:
        """Prelude entries for the constant matrix ``C = [[kq, kqnu], [kqnu, kq]]`` of the quadratic form."""
        c, cnu = sp.symbols("kq kqnu", real=True)
        return [(c, 2 * self.weight), (cnu, c * self.nu)]

    def stress(self) -> tuple[sp.Expr, sp.Expr]:
        """``w = dW/d strain = C s``, in terms of prelude symbols."""
        s1, s2 = (v - ref for v, ref in zip(self.strain_values, self.reference))
        (c, _), (cnu, _) = self.moduli
        return c * s1 + cnu * s2, cnu * s1 + c * s2

    def stiffness(self) -> tuple[tuple[sp.Expr, sp.Expr], tuple[sp.Expr, sp.Expr]]:
        """``C = d^2 W / d strain^2``, in terms of prelude symbols."""
        (c, _), (cnu, _) = self.moduli
        return (c, cnu), (cnu, c)

    def strain_derivatives(self) -> tuple[list[list[sp.Expr]], list[list[list[sp.Expr]]]]:
        """First and second derivatives of the strain formulas with respect to :attr:`variables`."""
        v = self.variables
        jac, hess = [], []
        for f in self.strain_formulas:
            d1 = [sp.diff(f, a) for a in v]
            d2 = [[sp.diff(d1[i], v[j]) for j in range(len(v))] for i in range(len(v))]
            jac.append([self._replace(e) for e in d1])
            hess.append([[self._replace(e) for e in row] for row in d2])
        return jac, hess

    def chain_strains(self) -> list[sp.Expr]:
        """The strains as the kernels compute them: :attr:`strain_formulas` through the prelude and the inputs,
        as functions of :attr:`dofs`."""
        values = {s: e for s, e in self.inputs}
        for s, e in self.prelude:
            values[s] = e.xreplace(values)
        return [self._replace(f).xreplace(values) for f in self.strain_formulas]

    def check_names(self) -> None:
        """Every name the kernels assign or take is distinct."""
        names = ([str(s) for s, _ in self.inputs] + [str(s) for s in self.params]
                 + [str(s) for s, _ in self.prelude + self.moduli])
        assert len(names) == len(set(names)), f"{self.name}: duplicate names in {names}"
        assert not any(n.startswith("_") for n in names), f"{self.name}: names must not start with _"

    def _replace(self, e: sp.Expr) -> sp.Expr:
        e = e.xreplace(self.trig)
        if self.rewrite:
            e = e.subs(self.rewrite)
        leftover = e.atoms(sp.Function)
        assert not leftover, f"{self.name}: functions left after replacement: {leftover}"
        return e


# ---- element definitions -------------------------------------------------------------------------
def _edge_rotation(c: sp.Symbol, s: sp.Symbol, il: sp.Symbol, k: int, n: int):
    """Jacobian rows and Hessians of ``(l, tau)`` of the edge whose components are inputs ``k, k+1``.

    ``tau`` stands for the edge angle ``theta`` scaled by the length, ``d tau = l d theta``: the
    Jacobian of ``(l, tau)`` is the rotation ``[[c, s], [-s, c]]``; the Hessian returned for
    ``tau`` is that of ``theta`` times ``l``, which is what the gradient with respect to ``tau``
    (``1/l`` times the one with respect to ``theta``) multiplies.
    """
    def row(vals):
        out = [sp.Integer(0)] * n
        out[k], out[k + 1] = vals
        return out

    def block(m):
        out = [[sp.Integer(0)] * n for _ in range(n)]
        for i in range(2):
            for j in range(2):
                out[k + i][k + j] = m[i][j]
        return out

    l_row = row((c, s))
    t_row = row((-s, c))
    l_hess = block(((il * s**2, -il * c * s), (-il * c * s, il * c**2)))
    t_hess = block(((2 * il * c * s, il * (s**2 - c**2)), (il * (s**2 - c**2), -2 * il * c * s)))
    return l_row, t_row, l_hess, t_hess


def _unit_row(k: int, n: int) -> list:
    out = [sp.Integer(0)] * n
    out[k] = sp.Integer(1)
    return out


class _TanHalfTurn(sp.Function):
    """``tan((th2 - th1) / 2)`` as a function of the edge angles ``(th1, th2)``."""

    nargs = 2

    def fdiff(self, argindex=1):
        return (1 + self**2) / 2 * (-1 if argindex == 1 else 1)


class _Recip(sp.Function):
    """``1 / x``, replaced by a prelude symbol after differentiation."""

    nargs = 1

    def fdiff(self, argindex=1):
        return -self**2


class _SinMid(sp.Function):
    """``sin((th1 + th2) / 2)`` as a function of the edge angles ``(th1, th2)``."""

    nargs = 2

    def fdiff(self, argindex=1):
        return _CosMid(*self.args) / 2


class _CosMid(sp.Function):
    """``cos((th1 + th2) / 2)`` as a function of the edge angles ``(th1, th2)``."""

    nargs = 2

    def fdiff(self, argindex=1):
        return -_SinMid(*self.args) / 2


def axisymmetric_restriction(name: str, dofs: list[sp.Symbol],
                             params: list[sp.Symbol]) -> tuple[tuple[sp.Expr, sp.Expr, sp.Expr], sp.Expr]:
    """The 2-D density of element ``name`` at the axisymmetric state through its nodes, as sympy expressions.

    At ``theta = 0`` the ring through node ``(r, z)`` has ``P = (r, 0, z)``, ``P' = (0, r, 0)`` and
    ``P'' = (-r, 0, 0)`` in the frame ``(e_r, e_theta, e_z)``.  The radii are positive symbols while the
    density is evaluated (so ``|P'| = r``), then the element's real ``dofs``; the densities' float
    constants become exact (:func:`contin_models.shell.density_codegen.symbolic`).  A negative radius
    (a node across the axis) is outside the definition: there ``|P'| = -r``, the 1-D formulas are
    their continuation.

    Parameters
    ----------
    name : str
        ``stretch`` (:func:`contin_models.shell.density.stretch_strains`), ``bend`` or ``bend_cur``
        (:func:`contin_models.shell.density.bend_curvatures` with ``L = lbar`` or the current length).
    dofs : list of sympy.Symbol
        The node coordinates ``[r0, z0, r1, z1, ...]`` (2 nodes for ``stretch``, 3 for bending).
    params : list of sympy.Symbol
        The element's parameters, in the order of :attr:`Element.params`.

    Returns
    -------
    strains : tuple of sympy.Expr
        ``(eps11, eps22, eps12)`` or ``(kappa11, kappa22, kappa12)``.
    energy : sympy.Expr
        The density (energy per radian).
    """
    radii = [sp.Dummy(str(r), positive=True) for r in dofs[0::2]]
    P = [(r, 0, z) for r, z in zip(radii, dofs[1::2])]
    Pp = [(0, r, 0) for r in radii]
    Ppp = [(-r, 0, 0) for r in radii]
    if name == "stretch":
        D = tuple(b - a for a, b in zip(P[0], P[1]))
        Mp = (0, (radii[0] + radii[1]) / 2, 0)
        lbar, rbar = params[:2]
        strains = symbolic(density.stretch_strains, D, Mp, lbar, rbar)
        energy = symbolic(density.stretch_density, D, Mp, *params)
    else:
        e1 = tuple(b - a for a, b in zip(P[0], P[1]))
        e2 = tuple(b - a for a, b in zip(P[1], P[2]))
        Dp = tuple(b - a for a, b in zip(Pp[0], Pp[2]))
        L = None if name == "bend_cur" else params[0]
        strains = symbolic(density.bend_curvatures, e1, e2, Dp, Pp[1], Ppp[1], L)
        energy = symbolic(density.bend_density, e1, e2, Dp, Pp[1], Ppp[1], *params, L)
    back = dict(zip(radii, dofs[0::2]))
    return tuple(e.xreplace(back) for e in strains), energy.xreplace(back)


def _rational_points(el: Element, count: int) -> list[dict[sp.Symbol, sp.Rational]]:
    """Random states of the element's nodes at which every square root of its strains is rational.

    Each edge has a rational length and the direction ``(cos 2a, sin 2a)`` with ``tan(a / 2)``
    rational, so that ``cos a``, ``sin a`` and with them the half turn between two edges are rational:
    the strains then evaluate exactly (no rounding), and equal strains give an exact zero.  The radii
    stay positive (a node's radius is large next to the edges).
    """
    rng = random.Random(len(el.dofs))

    def fraction(low: int, high: int) -> sp.Rational:
        return sp.Rational(rng.randint(low, high), 100)

    points = []
    for _ in range(count):
        point = {p: fraction(10, 90) for p in el.params}
        edges = []
        for _edge in range(len(el.dofs) // 2 - 1):
            t, length = fraction(-90, 90), fraction(5, 60)
            c, s = (1 - t**2) / (1 + t**2), 2 * t / (1 + t**2)
            edges.append((length * (c * c - s * s), length * 2 * c * s))
        r, z = fraction(500, 900), fraction(-50, 50)
        if len(edges) == 1:
            nodes = [(r, z), (r + edges[0][0], z + edges[0][1])]
        else:  # (r, z) is the middle node
            nodes = [(r - edges[0][0], z - edges[0][1]), (r, z), (r + edges[1][0], z + edges[1][1])]
        point.update(zip(el.dofs, [v for node in nodes for v in node]))
        points.append(point)
    return points


def check_axisymmetric_restriction(el: Element) -> None:
    """Assert that the element is the 2-D density restricted to axisymmetric states, times ``2 pi``.

    With the density of :func:`axisymmetric_restriction`:

    * :attr:`Element.strains` are its first two strains, and each equals the chain form the kernels
      evaluate (:meth:`Element.chain_strains`) exactly at random rational states
      (:func:`_rational_points`; sympy's ``simplify`` does not prove the circumferential curvature's
      identity in reasonable time);
    * its third (shear or twist) strain is zero;
    * ``2 pi`` times the density minus the element's energy simplifies to zero, each strain an opaque
      symbol on both sides: the weights and the quadratic forms agree.

    Raises
    ------
    AssertionError
        Naming the element and the quantity that differs.
    """
    strains, energy = axisymmetric_restriction(el.name, el.dofs, el.params)
    assert list(el.strains.values()) == list(strains[:2]), f"{el.name}: the strains are not the density's"
    for point in _rational_points(el, 4):
        for (key, derived), chain in zip(zip(el.strains, strains), el.chain_strains()):
            difference = (derived - chain).xreplace(point)
            assert difference.is_Rational and difference == 0, (
                f"{el.name}: {key} of the density is not the kernels' {key} at {point}")
    assert strains[2] == 0, f"{el.name}: the density's third strain does not vanish at axisymmetric states"
    opaque = sp.symbols("_s1 _s2", real=True)
    as_symbols = dict(zip(strains[:2], opaque))
    element = el.energy.xreplace(dict(zip(el.strains.values(), opaque)))
    density_of_strains = energy.xreplace(as_symbols)
    assert not density_of_strains.free_symbols & set(el.dofs), (
        f"{el.name}: the density at axisymmetric states is not a function of its strains alone")
    assert sp.simplify(2 * sp.pi * density_of_strains - element) == 0, (
        f"{el.name}: 2 pi times the density is not the element's energy {el.weight} (s1^2 + 2 nu s1 s2 + s2^2)")


def _stretch() -> Element:
    r0, z0, r1, z1 = sp.symbols("r0 z0 r1 z1", real=True)
    lbar, rbar, ks, nu = sp.symbols("lbar rbar ks nu", positive=True)
    eps11, eps22, _ = axisymmetric_restriction("stretch", [r0, z0, r1, z1], [lbar, rbar, ks, nu])[0]
    # local variables, prelude, strain variables
    er, ez, rs = sp.symbols("er ez rs", real=True)
    l, il, c, s, e11, e22 = sp.symbols("l il c s eps11 eps22", real=True)
    prelude = [(l, sp.sqrt(er**2 + ez**2)), (il, 1 / l), (c, er * il), (s, ez * il),
               (e11, l / lbar - 1), (e22, rs / (2 * rbar) - 1)]
    l_row, _, l_hess, _ = _edge_rotation(c, s, il, 0, 3)
    layer = Layer(outer=[l, rs], inner=[er, ez, rs], jacobian=[l_row, _unit_row(2, 3)], hessians={0: l_hess},
                  rotations=[(0, None, 0, c, s, il)], passthrough={1: 2})
    return Element(
        name="stretch",
        dofs=[r0, z0, r1, z1],
        params=[lbar, rbar, ks, nu],
        strains={"eps11": eps11, "eps22": eps22},
        reference=(sp.Integer(0), sp.Integer(0)),
        weight=sp.pi * rbar * lbar * ks,
        nu=nu,
        inputs=[(er, r1 - r0), (ez, z1 - z0), (rs, r0 + r1)],
        prelude=prelude,
        strain_values=(e11, e22),
        variables=[l, rs],
        strain_formulas=(l / lbar - 1, rs / (2 * rbar) - 1),
        trig={},
        layers=[layer],
        strains_name="strains",
        doc="stretching energy of one edge, pi rbar lbar ks (eps11^2 + 2 nu eps11 eps22 + eps22^2)",
    )


def _bend(current_length: bool) -> Element:
    r0, z0, r1, z1, r2, z2 = sp.symbols("r0 z0 r1 z1 r2 z2", real=True)
    lbar, rbar, kb, nu = sp.symbols("lbar rbar kb nu", positive=True)
    k11bar, k22bar = sp.symbols("k11bar k22bar", real=True)
    ar, az = r1 - r0, z1 - z0
    br, bz = r2 - r1, z2 - z1
    name = "bend_cur" if current_length else "bend"
    params = [lbar, rbar, k11bar, k22bar, kb, nu]
    kappa11, kappa22, _ = axisymmetric_restriction(name, [r0, z0, r1, z1, r2, z2], params)[0]
    which = "current Voronoi length (|e1|+|e2|)/2" if current_length else "reference Voronoi length lbar"

    # local variables e1 = (ar, az), e2 = (br, bz), r1; the polar form of the two edges
    ar_, az_, br_, bz_ = sp.symbols("ar az br bz", real=True)
    la_, lb_, ila, ilb, ca, sa, cb, sb = sp.symbols("la lb ila ilb ca sa cb sb", real=True)
    lab, den, tn, it2, it, sphi, cphi, k11, k22 = sp.symbols("lab den tn it2 it sphi cphi k11 k22", real=True)
    isum, ir = sp.symbols("isum ir", real=True)
    th1, th2 = sp.symbols("th1 th2", real=True)
    prelude = [
        (la_, sp.sqrt(ar_**2 + az_**2)), (lb_, sp.sqrt(br_**2 + bz_**2)),
        (ila, 1 / la_), (ilb, 1 / lb_),
        (ca, ar_ * ila), (sa, az_ * ila), (cb, br_ * ilb), (sb, bz_ * ilb),
        # from the edge vectors themselves (not the unit vectors): one rounding less in tan(xi/2)
        (lab, la_ * lb_), (den, lab + ar_ * br_ + az_ * bz_),  # |e1| |e2| (1 + cos xi)
        (tn, (ar_ * bz_ - az_ * br_) / den),  # tan(xi/2)
        (it2, lab / (2 * den)),  # 1 / |t|^2 with t = e1/|e1| + e2/|e2|
        (it, sp.sqrt(it2)),
        (sphi, (sa + sb) * it),  # n_r = sin(phi), phi = (th1 + th2) / 2
        (cphi, (ca + cb) * it),  # t_r / |t| = cos(phi)
        (ir, 1 / r1),
        (k22, sphi * ir),
    ]
    prelude += [(isum, 1 / (la_ + lb_)), (k11, 4 * tn * isum)] if current_length else [(k11, 2 * tn / lbar)]
    half_turn, mid_sin = _TanHalfTurn(th1, th2), _SinMid(th1, th2)
    k11_formula = 4 * half_turn * _Recip(la_ + lb_) if current_length else 2 * half_turn / lbar
    # theta_i = tau_i / l_i (a diagonal scaling), then (l_i, tau_i) -> e_i (a rotation)
    ta, tb = sp.symbols("ta tb", real=True)
    scaling = [sp.Integer(1), ila, sp.Integer(1), ilb, sp.Integer(1)]
    scale = Layer(outer=[la_, th1, lb_, th2, r1], inner=[la_, ta, lb_, tb, r1],
                  jacobian=[[scaling[i] if i == j else sp.Integer(0) for j in range(5)] for i in range(5)])
    la_row, t1_row, la_hess, t1_hess = _edge_rotation(ca, sa, ila, 0, 5)
    lb_row, t2_row, lb_hess, t2_hess = _edge_rotation(cb, sb, ilb, 2, 5)
    edges = Layer(outer=[la_, ta, lb_, tb, r1], inner=[ar_, az_, br_, bz_, r1],
                  jacobian=[la_row, t1_row, lb_row, t2_row, _unit_row(4, 5)],
                  hessians={0: la_hess, 1: t1_hess, 2: lb_hess, 3: t2_hess},
                  rotations=[(0, 1, 0, ca, sa, ila), (2, 3, 2, cb, sb, ilb)], passthrough={4: 4})
    return Element(
        name=name,
        dofs=[r0, z0, r1, z1, r2, z2],
        params=params,
        strains={"kappa11": kappa11, "kappa22": kappa22},
        reference=(k11bar, k22bar),
        weight=sp.pi * rbar * lbar * kb,
        nu=nu,
        inputs=[(ar_, ar), (az_, az), (br_, br), (bz_, bz), (r1, r1)],
        prelude=prelude,
        strain_values=(k11, k22),
        variables=[la_, th1, lb_, th2, r1],
        strain_formulas=(k11_formula, mid_sin * _Recip(r1)),
        trig={half_turn: tn, mid_sin: sphi, _CosMid(th1, th2): cphi, _Recip(r1): ir, _Recip(la_ + lb_): isum},
        layers=[scale, edges],
        rewrite={4 * isum * tn: k11, ir * sphi: k22} if current_length else {ir * sphi: k22},
        strains_name="curvatures",
        doc=f"bending energy of one interior node, kappa11 over the {which}",
    )


def build_elements() -> list[Element]:
    """The element definitions, in the fixed order in which they are emitted.

    Returns
    -------
    list of Element
        ``stretch``, ``bend`` (reference Voronoi length in ``kappa11``) and ``bend_cur`` (current
        Voronoi length).
    """
    return [_stretch(), _bend(False), _bend(True)]


# ---- the chain rule through the layers -----------------------------------------------------------
def _chain(el: Element, body: KernelBody, hessian: bool, structured: bool = True):
    """Chain rule from the strain variables to the dofs: gradient list, packed upper Hessian list.

    Each intermediate gradient and Hessian is named in ``body`` before the next change of
    variables, so that the printed code keeps the small-step structure.  ``structured`` uses the
    rotation form of :func:`_rotate` for rotation layers (else the generic ``A^T H A``).
    """
    jac, shess = el.strain_derivatives()
    nv = len(el.variables)
    pairs = upper_pairs(nv)
    # name the strain derivatives and the stresses, then V = C J: H = sum_i V_i J_i^T + w_i hess_i
    flat = list(el.stress()) + [e for row in jac for e in row]
    if hessian:
        flat += [shess[i][a][b] for i in range(2) for a, b in pairs]
    flat = body.name(flat)
    w, flat = flat[:2], flat[2:]
    jac, flat = [flat[:nv], flat[nv:2 * nv]], flat[2 * nv:]
    g = [w[0] * jac[0][a] + w[1] * jac[1][a] for a in range(nv)]
    H = None
    if hessian:
        hs = [dict(zip(pairs, flat[:len(pairs)])), dict(zip(pairs, flat[len(pairs):]))]
        C = el.stiffness()
        V = body.name([C[i][0] * jac[0][a] + C[i][1] * jac[1][a] for i in range(2) for a in range(nv)])
        V = [V[:nv], V[nv:]]
        H = {(a, b): V[0][a] * jac[0][b] + V[1][a] * jac[1][b] + w[0] * hs[0][a, b] + w[1] * hs[1][a, b]
             for a, b in pairs}
    steps = [(lay.jacobian, lay.hessians, lay) for lay in el.layers] + [(el.input_map(), {}, None)]
    for A, hessians, layer in steps:
        g, H = _named(body, g, H)
        if structured and layer is not None and layer.rotations:
            g, H = _rotate(body, layer, g, H)
            continue
        n_out, n_in = len(A), len(A[0])
        g_new = [sp.Add(*[A[k][j] * g[k] for k in range(n_out) if A[k][j] != 0]) for j in range(n_in)]
        H_new = None
        if H is not None:
            H_new = {}
            for i, j in upper_pairs(n_in):
                e = sp.Add(*[A[k][i] * H[min(k, m), max(k, m)] * A[m][j]
                             for k in range(n_out) for m in range(n_out) if A[k][i] != 0 and A[m][j] != 0])
                H_new[i, j] = e + sp.Add(*[g[k] * hk[i][j] for k, hk in hessians.items()])
        g, H = g_new, H_new
    return g, ([H[k] for k in upper_pairs(len(el.dofs))] if H is not None else None)


def _rotate(body: KernelBody, layer: Layer, g: list, H: dict | None):
    """The chain rule through a rotation layer (:attr:`Layer.rotations`).

    Per edge, with ``R = [[c, s], [-s, c]]`` the Jacobian of ``(l, tau)``: the gradient is
    ``R^T (g_l, g_tau)``; the diagonal block ``R^T [[h_ll, h_lt], [h_lt, h_tt]] R`` plus the
    curvature terms ``g_l hess(l) + g_tau hess(tau)`` is written with the double angle
    (``C2 = c^2 - s^2``, ``S2 = 2 c s``), the blocks between two edges as ``R_i^T (M R_j)`` and
    the ones between an edge and a copied variable as ``R_i^T (h_l, h_tau)``.
    """
    zero = sp.Integer(0)
    n_in = len(layer.inner)

    def h(a, b):
        if a is None or b is None:
            return zero
        return H[min(a, b), max(a, b)]

    def rot(c, s):  # rows: (l, tau), columns: the two edge components
        return ((c, s), (-s, c))

    g_new = [zero] * n_in
    for li, ti, k, c, s, _ in layer.rotations:
        gt = g[ti] if ti is not None else zero
        g_new[k], g_new[k + 1] = c * g[li] - s * gt, s * g[li] + c * gt
    for p, q in layer.passthrough.items():
        g_new[q] = g[p]
    if H is None:
        return g_new, None

    H_new: dict = {}

    def put(i, j, e):
        H_new[min(i, j), max(i, j)] = e

    for li, ti, k, c, s, il in layer.rotations:
        gt = g[ti] if ti is not None else zero
        C2, S2 = body.name([c**2 - s**2, 2 * c * s])
        m = (h(li, li) + h(ti, ti)) / 2
        a0 = g[li] * il / 2
        ma0, p, q = body.name([m + a0, (h(li, li) - h(ti, ti)) / 2 - a0, gt * il - h(li, ti)])
        (u,) = body.name([p * C2 + q * S2])
        put(k, k, ma0 + u)
        put(k + 1, k + 1, ma0 - u)
        put(k, k + 1, p * S2 - q * C2)
    for n, (li, ti, ki, ci, si, _) in enumerate(layer.rotations):
        Ri = rot(ci, si)
        for lj, tj, kj, cj, sj, _ in layer.rotations[n + 1:]:
            Rj = rot(cj, sj)
            M = ((h(li, lj), h(li, tj)), (h(ti, lj), h(ti, tj)))
            X = body.name([M[a][0] * Rj[0][col] + M[a][1] * Rj[1][col] for a in range(2) for col in range(2)])
            X = (X[:2], X[2:])
            for row in range(2):
                for col in range(2):
                    put(ki + row, kj + col, Ri[0][row] * X[0][col] + Ri[1][row] * X[1][col])
        for p, q in layer.passthrough.items():
            for row in range(2):
                put(ki + row, q, Ri[0][row] * h(li, p) + Ri[1][row] * h(ti, p))
    for p1, q1 in layer.passthrough.items():
        for p2, q2 in layer.passthrough.items():
            if q1 <= q2:
                put(q1, q2, h(p1, p2))
    assert tuple(sorted(H_new)) == upper_pairs(n_in)
    return g_new, H_new


def _named(body: KernelBody, g: list, H: dict | None):
    """Name the entries of a gradient (and Hessian) before the next change of variables."""
    keys = sorted(H) if H is not None else []
    vals = body.name(list(g) + [H[k] for k in keys])
    return vals[:len(g)], (dict(zip(keys, vals[len(g):])) if H is not None else None)


# ---- emitting the functions ----------------------------------------------------------------------
def _inputs_doc(el: Element) -> str:
    return ", ".join(f"``{s} = {sp.sstr(e)}``" for s, e in el.inputs)


def _fast_header(el: Element, suffix: str, doc: list[str], out: bool) -> list[str]:
    names = [str(s) for s, _ in el.inputs] + [str(s) for s in el.params] + (["out=None"] if out else [])
    return function_header(f"{el.name}_fast_{suffix}", names, doc)


def _fast_doc(el: Element, what: str) -> list[str]:
    return [what, "", f"Fast kernel: arguments are the local variables {_inputs_doc(el)} and the",
            "parameters, arrays of one shape ``(m,)`` (parameters may be scalars)."]


def _emit_rows(el: Element, name: str, rows: list[sp.Expr], body: KernelBody, doc: list[str],
               printer: NumPyPrinter) -> list[str]:
    return (_fast_header(el, name, doc, True)
            + body.row_lines(el.prelude + el.moduli, rows, printer, like=str(el.inputs[0][0])))


def _emit_fast_energy(el: Element, printer: NumPyPrinter) -> list[str]:
    s1, s2 = (v - ref for v, ref in zip(el.strain_values, el.reference))
    body = KernelBody()
    (red,) = body.reduce([el.weight * (s1**2 + 2 * el.nu * s1 * s2 + s2**2)])
    doc = _fast_doc(el, f"Element {el.doc}.") + ["", "Returns", "-------", "ndarray, shape ``(m,)``"]
    return (_fast_header(el, "energy", doc, False) + body.lines(el.prelude + el.moduli, [red], printer, ["_e"])
            + ["    return _e"])


def _cheapest_chain(el: Element, hessian: bool, printer: NumPyPrinter,
                    with_gradient: bool = False) -> tuple[KernelBody, list[sp.Expr]]:
    """The chain rule with and without the rotation form; the variant with fewer operations.

    The rows are the gradient, or the packed Hessian, or (``with_gradient``) the gradient's rows
    followed by the Hessian's, sharing one body.
    """
    best = None
    for structured in (True, False):
        body = KernelBody()
        g, H = _chain(el, body, hessian=hessian, structured=structured)
        rows = body.reduce((list(g) + H if with_gradient else H) if hessian else g)
        lines = body.lines(el.prelude + el.moduli, rows, printer) + [printer.doprint(e) for e in rows]
        cost = count_operations(lines)
        if best is None or cost < best[0]:
            best = (cost, body, rows)
    return best[1], best[2]


def _emit_fast_gradient(el: Element, printer: NumPyPrinter) -> list[str]:
    n = len(el.dofs)
    body, rows = _cheapest_chain(el, False, printer)
    dofs = ", ".join(str(q) for q in el.dofs)
    doc = _fast_doc(el, f"Gradient of the {el.doc}.") + [
        "", "Returns", "-------", f"ndarray, shape ``({n}, m)``",
        f"    Derivatives with respect to ``[{dofs}]``, one row per dof (written into ``out``",
        "    when given)."]
    return _emit_rows(el, "gradient", rows, body, doc, printer)


def _emit_fast_hessian(el: Element, printer: NumPyPrinter) -> list[str]:
    body, rows = _cheapest_chain(el, True, printer)
    dofs = ", ".join(str(q) for q in el.dofs)
    doc = _fast_doc(el, f"Hessian of the {el.doc}.") + [
        "", "Returns", "-------", f"ndarray, shape ``({len(rows)}, m)``",
        f"    Second derivatives with respect to ``[{dofs}]``, packed: the upper triangle",
        f"    ``(a, b)``, ``a <= b``, row by row (``UPPER[{el.name!r}]``; written into ``out`` when",
        "    given)."]
    return _emit_rows(el, "hessian", rows, body, doc, printer)


def _emit_fast_gradient_hessian(el: Element, printer: NumPyPrinter) -> list[str]:
    n = len(el.dofs)
    body, rows = _cheapest_chain(el, True, printer, with_gradient=True)
    dofs = ", ".join(str(q) for q in el.dofs)
    doc = _fast_doc(el, f"Gradient and Hessian of the {el.doc}, in one pass.") + [
        "", "Returns", "-------", f"ndarray, shape ``({len(rows)}, m)``",
        f"    The {n} rows of ``{el.name}_fast_gradient`` followed by the {len(rows) - n} rows of",
        f"    ``{el.name}_fast_hessian`` (written into ``out`` when given).  The two share their",
        "    intermediate quantities, so this costs about what the Hessian alone costs."]
    return _emit_rows(el, "gradient_hessian", rows, body, doc, printer)


def _emit_fast_strains(el: Element, printer: NumPyPrinter) -> list[str]:
    names = list(el.strains)
    doc = _fast_doc(el, f"Strain measures ``({', '.join(names)})``: {el.doc}.") + [
        "", "Returns", "-------", f"tuple of {len(names)} ndarrays, shape ``(m,)``"]
    body = KernelBody()
    vals = list(el.strain_values)
    return (_fast_header(el, el.strains_name, doc, False) + body.lines(el.prelude, vals, printer)
            + [f"    return {', '.join(printer.doprint(v) for v in vals)}"])


# The convenience functions: node coordinates in, broadcasting, unpacked outputs.
def _header(el: Element, suffix: str, doc: list[str]) -> list[str]:
    names = [str(s) for s in el.dofs + el.params]
    return function_header(f"{el.name}_{suffix}", names, doc) + [
        f"    {', '.join(names)}, _shape = _prepare({', '.join(names)})"]


def _call_fast(el: Element, suffix: str, printer: NumPyPrinter, out: str | None = None) -> str:
    args = [printer.doprint(e) for _, e in el.inputs] + [str(s) for s in el.params]
    if out is not None:
        args.append(f"out={out}")
    return f"{el.name}_fast_{suffix}({', '.join(args)})"


def _emit_energy(el: Element, printer: NumPyPrinter) -> list[str]:
    doc = [f"Element {el.doc}.", "", "Returns", "-------", "ndarray, shape ``(m,)``"]
    return _header(el, "energy", doc) + [
        "    _out = numpy.zeros(_shape)",
        f"    _out[...] = {_call_fast(el, 'energy', printer)}",
        "    return _out"]


def _emit_derivative(el: Element, printer: NumPyPrinter, suffix: str) -> list[str]:
    """The broadcasting ``<name>_gradient`` or ``<name>_hessian`` around its packed fast kernel."""
    n = len(el.dofs)
    dofs = ", ".join(str(q) for q in el.dofs)
    if suffix == "gradient":
        shape, what, packed = f"{n}", "Derivatives", n
        var, ret = "_g", "numpy.moveaxis(_g, 0, -1).copy()"
    else:
        shape, what, packed = f"{n}, {n}", "Symmetric second derivatives", n * (n + 1) // 2
        var, ret = "_h", f"_unpack(_h, {n})"
    doc = [f"{suffix.capitalize()} of the {el.doc}.", "", "Returns", "-------",
           f"ndarray, shape ``(m, {shape})``", f"    {what} with respect to ``[{dofs}]``."]
    return _header(el, suffix, doc) + [
        f"    {var} = {_call_fast(el, suffix, printer, f'numpy.empty(({packed},) + _shape)')}",
        f"    return {ret}"]


def _emit_strains(el: Element, printer: NumPyPrinter) -> list[str]:
    names = list(el.strains)
    doc = [f"Strain measures ``({', '.join(names)})`` of the element: {el.doc}.", "", "Returns",
           "-------", f"tuple of {len(names)} ndarrays, shape ``(m,)``"]
    lines = _header(el, el.strains_name, doc)
    outs = [f"_o{k}" for k in range(len(names))]
    lines.append(f"    {', '.join(outs)} = {_call_fast(el, el.strains_name, printer)}")
    for o in outs:
        lines.append(f"    {o} = numpy.broadcast_to({o}, _shape).copy()")
    lines.append(f"    return {', '.join(outs)}")
    return lines


_PREAMBLE = '''"""Element energies of the discrete axisymmetric shell, with exact gradients and Hessians.

GENERATED by ``python -m contin_models.shell.codegen`` from the sympy definitions in
``models/shell/codegen.py`` (its docstring explains the chain of variables the derivatives are
written in).  Do not edit by hand: change the generator and regenerate.  Plain numpy, vectorised
over a batch of elements.

``<name>_fast_*`` take the element's local variables (``INPUTS[name]``: edge vectors and radii, each
a linear function of the node coordinates) and return packed gradients ``(ndof, m)`` and packed
upper-triangle Hessians ``(ndof (ndof + 1) / 2, m)`` (pairs ``UPPER[name]``); they are what
:class:`contin_models.shell.ShellEnergy` calls.  ``<name>_energy`` / ``_gradient`` / ``_hessian`` and the
strain helpers take the node coordinates, broadcast over all their arguments (every argument is an
array with one entry per element, or a scalar broadcast to all of them) and return ``(m,)``,
``(m, ndof)`` and ``(m, ndof, ndof)`` arrays.
"""

import numpy


''' + emitted_helpers("_prepare", "_upper", "_unpack")


def generate_source() -> str:
    """Check each element's names, then build the text of ``_generated.py``.

    Returns
    -------
    str
        The module: the fast and the broadcasting kernels of every element, with ``NDOF``, ``INPUTS`` and
        ``UPPER`` (deterministic: the same sympy version gives the same bytes).
    """
    printer = kernel_printer()
    elements = build_elements()
    functions: list[str] = []
    chunks: list[str] = []
    for el in elements:
        el.check_names()
        check_axisymmetric_restriction(el)
        emitters = ((_emit_fast_energy, "fast_energy"), (_emit_fast_gradient, "fast_gradient"),
                    (_emit_fast_hessian, "fast_hessian"), (_emit_fast_gradient_hessian, "fast_gradient_hessian"),
                    (_emit_fast_strains, f"fast_{el.strains_name}"),
                    (_emit_energy, "energy"), (partial(_emit_derivative, suffix="gradient"), "gradient"),
                    (partial(_emit_derivative, suffix="hessian"), "hessian"),
                    (_emit_strains, el.strains_name))
        for emit, suffix in emitters:
            chunks.append("\n".join(emit(el, printer)))
            functions.append(f"{el.name}_{suffix}")
    by_name = sorted(elements, key=lambda e: e.name)
    constants = "\n".join([
        "NDOF = {" + ", ".join(f'"{el.name}": {len(el.dofs)}' for el in by_name) + "}",
        '"""Number of local dofs (node coordinates) of each element."""',
        "",
        "INPUTS = {" + ", ".join(f'"{el.name}": (' + ", ".join(f'"{s}"' for s, _ in el.inputs) + ")"
                                 for el in by_name) + "}",
        '"""Local variables (arguments before the parameters) of the ``<name>_fast_*`` kernels."""',
        "",
        "UPPER = {" + ", ".join(f'"{el.name}": _upper({len(el.dofs)})' for el in by_name) + "}",
        '"""Local dof pairs ``(a, b)``, ``a <= b``, of the rows of a packed Hessian."""',
    ])
    return module_text(_PREAMBLE, functions + ["INPUTS", "NDOF", "UPPER"], constants, chunks)


def generate_c_source(python_source: str | None = None) -> str:
    """Text of ``_ckernels.c``: the fast gradient and Hessian kernels of ``python_source`` in C.

    Parameters
    ----------
    python_source : str or None
        Text of the numpy module (``None``: the committed ``_generated.py``, which the C file is
        generated from and checked against, so that neither needs sympy to agree with the other).

    Returns
    -------
    str
    """
    text = DEFAULT_OUTPUT.read_text(encoding="utf-8") if python_source is None else python_source
    namespace: dict = {}
    exec(compile(text, str(DEFAULT_OUTPUT), "exec"), namespace)
    from .energy import compiled_rows

    return c_extension_text(text, compiled_rows(namespace["NDOF"]), "_ckernels",
                            "Fast element kernels of the discrete axisymmetric shell (contin_models.shell._ckernels).")


def main(argv: list[str] | None = None) -> int:
    """The generator's command line (:func:`contin.modelkit.codegen.generator_main`): ``--output PATH``, ``--check``.

    Without ``--output`` the C extension's source :data:`C_OUTPUT` is written (or checked) too, from
    the committed numpy module.
    """
    return generator_main(argv, generate_source, DEFAULT_OUTPUT, "python -m contin_models.shell.codegen",
                          __doc__.split("\n")[0], companions=[(generate_c_source, C_OUTPUT)])


if __name__ == "__main__":
    raise SystemExit(main())
