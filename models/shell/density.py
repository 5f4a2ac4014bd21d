"""The 2-D energy densities of the shell, written once: energy per radian of each element at one ``theta``.

Each density is a function of an element's local vectors (the positions ``P``, ``P'``, ``P''`` of its rings'
material points at one ``theta``, as 3-tuples of components in any orthonormal frame) and of its
reference numbers (:class:`contin_models.shell.reference.ShellReference`).  The same function is
evaluated on floats, on :class:`contin_models.shell.jets.Jet` (an element's local Hessian) and on sympy
symbols (:mod:`contin_models.shell.harmonic_codegen`, which sets :data:`SYMBOLIC_SQRT`), so the
harmonic blocks, the ring mesh and the generated kernels differentiate one definition.  The
definitions and their restriction to axisymmetric states, the traced 1-D energy:
:mod:`contin_models.shell.harmonic` ("The 2-D energy").  The bodies are frozen: the generated kernels
are derived from these expression trees, so a rewritten product or literal changes their bytes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from .jets import Jet

__all__ = ["SYMBOLIC_SQRT", "symbolic_sqrt", "stretch_strains", "stretch_density", "general_stretch_density",
           "stretch_reference", "bend_curvatures", "bend_density", "general_bend_density", "pole_curvature",
           "volume_density", "free_edge_density", "general_free_edge_density", "free_edge_curvatures",
           "vector_length", "skirt_density"]


#: Square root of a symbolic expression (set by :func:`symbolic_sqrt` while the generators evaluate
#: the same densities in sympy; never needed at run time).
SYMBOLIC_SQRT = None


@contextmanager
def symbolic_sqrt(sqrt: Callable[[Any], Any]) -> Iterator[None]:
    """Within the block the densities take the square roots of symbolic arguments by ``sqrt``.

    The code generators (:mod:`contin_models.shell.harmonic_codegen`,
    :mod:`contin_models.shell.density_codegen`) evaluate the densities on sympy symbols with
    ``sqrt = sympy.sqrt``; this module itself never imports sympy.
    """
    global SYMBOLIC_SQRT
    previous, SYMBOLIC_SQRT = SYMBOLIC_SQRT, sqrt
    try:
        yield
    finally:
        SYMBOLIC_SQRT = previous


def _sqrt(x):
    if isinstance(x, Jet):
        return x.sqrt()
    if SYMBOLIC_SQRT is not None and not isinstance(x, (np.ndarray, float, int, np.floating)):
        return SYMBOLIC_SQRT(x)
    return np.sqrt(x)


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _norm(a):
    return _sqrt(_dot(a, a))


def _scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _addv(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


# ---------------------------------------------------------------------------------------------------
# the 2-D energy densities (per radian), as functions of the local vectors at one theta
# ---------------------------------------------------------------------------------------------------
# Every vector is a 3-tuple of components in the local frame (e_r, e_theta, e_z) (or any orthonormal
# frame: the densities are invariant); components are arrays or Jets.

def stretch_strains(D, Mp, lbar, rbar):
    """``(eps11, eps22, eps12)`` of an edge (arguments as :func:`stretch_density`)."""
    g1 = _scale(D, 1.0 / lbar)
    g2 = _scale(Mp, 1.0 / rbar)
    n1, n2 = _norm(g1), _norm(g2)
    return n1 - 1.0, n2 - 1.0, _dot(g1, g2) / (n1 * n2) * 0.5


def stretch_density(D, Mp, lbar, rbar, ks, nu):
    """Stretching energy per radian of an edge.

    ``D = P_j - P_i`` (the chord between the rings at one ``theta``), ``Mp = (P'_i + P'_j) / 2``.
    """
    return general_stretch_density(D, Mp, lbar, rbar, 0.0, ks, nu)


def general_stretch_density(D, Mp, lbar, rbar, e12bar, ks, nu):
    """Stretching energy per radian of an edge against a reference that need not be axisymmetric.

    ``lbar``, ``rbar``: the reference ``|D|`` and ``|Mp|`` at this ``theta``, ``e12bar`` the reference's
    shear (:func:`stretch_reference`; ``0`` for an axisymmetric reference, :func:`stretch_density`).  The
    strains are ``|D| / lbar - 1``, ``|Mp| / rbar - 1`` and ``eps12 - e12bar``, the weight the reference
    lengths' product ``rbar lbar``.
    """
    e11, e22, e12 = stretch_strains(D, Mp, lbar, rbar)
    B12 = e12 - e12bar
    q = e11 * e11 + 2.0 * nu * (e11 * e22) + e22 * e22 + 2.0 * (1.0 - nu) * (B12 * B12)
    return q * (0.5 * rbar * lbar * ks)


def stretch_reference(D, Mp):
    """``(lbar, rbar, e12bar)`` of an edge at one ``theta`` from its reference local vectors
    (:func:`general_stretch_density`): the lengths and the shear of :func:`stretch_strains` there."""
    lbar, rbar = _norm(D), _norm(Mp)
    return lbar, rbar, stretch_strains(D, Mp, lbar, rbar)[2]


def bend_curvatures(e1, e2, Dp, Pp, Ppp, L=None):
    """``(kappa11, kappa22, kappa12)`` of an interior node (module docstring).

    ``e1 = P_i - P_{i-1}``, ``e2 = P_{i+1} - P_i``, ``Dp = P'_{i+1} - P'_{i-1}``, ``Pp = P'_i``,
    ``Ppp = P''_i``; ``L`` the length in ``kappa11`` (``None``: the current ``(|e1| + |e2|) / 2``).
    """
    l1, l2 = _norm(e1), _norm(e2)
    sp_ = _norm(Pp)
    tau = _scale(Pp, 1.0 / sp_)
    cross = -_dot(_cross(e1, e2), tau)
    dot = _dot(e1, e2)
    Lk = (l1 + l2) * 0.5 if L is None else L
    k11 = 2.0 * cross / ((l1 * l2 + dot) * Lk)
    t = _addv(_scale(e1, 1.0 / l1), _scale(e2, 1.0 / l2))
    nv = _cross(tau, t)
    nv = _scale(nv, 1.0 / _norm(nv))
    k22 = -_dot(nv, Ppp) / (sp_ * sp_)
    k12 = _dot(nv, Dp) / ((l1 + l2) * sp_)
    return k11, k22, k12


def bend_density(e1, e2, Dp, Pp, Ppp, lbar, rbar, k11bar, k22bar, kb, nu, L=None):
    """Bending energy per radian of an interior node (arguments as :func:`bend_curvatures`)."""
    return general_bend_density(e1, e2, Dp, Pp, Ppp, lbar, rbar, k11bar, k22bar, 0.0, kb, nu, L)


def general_bend_density(e1, e2, Dp, Pp, Ppp, lbar, rbar, k11bar, k22bar, k12bar, kb, nu, L=None):
    """Bending energy per radian of an interior node against a reference that need not be axisymmetric:
    ``k12bar`` the reference twist (``0`` for an axisymmetric reference, :func:`bend_density`), the
    weight ``rbar lbar`` (the reference ``|P'|`` and Voronoi length at this ``theta``)."""
    k11, k22, k12 = bend_curvatures(e1, e2, Dp, Pp, Ppp, L)
    B11, B22, B12 = k11 - k11bar, k22 - k22bar, k12 - k12bar
    q = B11 * B11 + 2.0 * nu * (B11 * B22) + B22 * B22 + 2.0 * (1.0 - nu) * (B12 * B12)
    return q * (0.5 * rbar * lbar * kb)


def pole_curvature(Pm, Pmp, Pc, Pq, Pqp, north, L=None):
    """Directional curvature ``kappa(theta)`` at a pole.

    ``Pm``, ``Pmp``: the neighbour ring's point and ``P'`` at ``theta``; ``Pc``: the pole;
    ``Pq``, ``Pqp``: the neighbour's point and ``P'`` at ``theta + pi`` (all in one frame).
    ``north``: the pole is the last node (the meridian runs neighbour -> pole), else the first.
    ``L``: ``None`` for the current length ``(|e1| + |e2|) / 2``, else the reference one.
    """
    if north:
        e1, e2 = _sub(Pc, Pm), _sub(Pq, Pc)
    else:
        e1, e2 = _sub(Pc, Pq), _sub(Pm, Pc)
    w = _sub(Pmp, Pqp)
    w = _scale(w, 1.0 / _norm(w))
    l1, l2 = _norm(e1), _norm(e2)
    cross = -_dot(_cross(e1, e2), w)
    Lk = (l1 + l2) * 0.5 if L is None else L
    return 2.0 * cross / ((l1 * l2 + _dot(e1, e2)) * Lk)


def _horizontal_triple(P, A, D):
    """``h(P).(A x D)`` with ``h(P) = (P_r, P_t, 0)``."""
    c = _cross(A, D)
    return P[0] * c[0] + P[1] * c[1]


def volume_density(Pi, Pj, Ppi, Ppj):
    """Volume per radian of the ruled strip between rings ``i`` and ``j`` (flux of ``(x, y, 0)/2``)."""
    D = _sub(Pj, Pi)
    s = (_horizontal_triple(Pi, Ppi, D) * (1.0 / 3.0) + _horizontal_triple(Pj, Ppj, D) * (1.0 / 3.0)
         + (_horizontal_triple(Pi, Ppj, D) + _horizontal_triple(Pj, Ppi, D)) * (1.0 / 6.0))
    return s * 0.5


def free_edge_density(e, Dp, Pp, Ppp, K, kbar, nu):
    """Bending energy per radian of a rotating edge's half cell (:class:`contin_models.shell.structure.MomentFreeEdge`).

    ``e = P_1 - P_0``, ``Dp = P'_1 - P'_0``, ``Pp = P'_0``, ``Ppp = P''_0``; ``K`` the 1-D element's
    ``pi r0bar lbar_0 kb (1 - nu^2) / 2``.  The moment-free edge eliminates ``B11 = -nu B22``: the
    density is ``kb ((1 - nu^2) B22^2 + 2 (1 - nu) kappa12^2)`` over the half cell, with ``kappa22`` the
    circumferential normal curvature about the first edge's normal (``n_r / r_0`` when axisymmetric,
    the 1-D element's) and the twist ``kappa12`` one-sided over the first edge (zero when axisymmetric),
    :func:`free_edge_curvatures`.
    """
    return general_free_edge_density(e, Dp, Pp, Ppp, K, kbar, 0.0, nu)


def general_free_edge_density(e, Dp, Pp, Ppp, K, kbar, k12bar, nu):
    """:func:`free_edge_density` against a reference that need not be axisymmetric: ``kbar``, ``k12bar``
    the reference's :func:`free_edge_curvatures` (the twist ``0`` when axisymmetric), ``K`` the weight
    from the reference's ``|P'_0|`` and ``|e|`` at this ``theta``."""
    k22, k12 = free_edge_curvatures(e, Dp, Pp, Ppp)
    B22, B12 = k22 - kbar, k12 - k12bar
    return (B22 * B22 + (2.0 / (1.0 + nu)) * (B12 * B12)) * (K / (2.0 * math.pi))


def free_edge_curvatures(e, Dp, Pp, Ppp):
    """``(kappa22, kappa12)`` of a rotating edge's half cell (arguments as :func:`free_edge_density`)."""
    l = _norm(e)
    sp_ = _norm(Pp)
    tau = _scale(Pp, 1.0 / sp_)
    nv = _cross(tau, _scale(e, 1.0 / l))
    nv = _scale(nv, 1.0 / _norm(nv))
    return -_dot(nv, Ppp) / (sp_ * sp_), _dot(nv, Dp) / (l * sp_)


def vector_length(a):
    """The length of a local vector ``a`` (a 3-tuple of components in an orthonormal frame)."""
    return _norm(a)


def skirt_density(P0, Pp0, z_ref):
    """Volume per radian of the skirt from the base plane ``z = z_ref`` up to ring 0."""
    return (P0[0] * Pp0[1] - P0[1] * Pp0[0]) * (P0[2] - z_ref) * 0.5
