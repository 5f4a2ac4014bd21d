"""The small elements of the axisymmetric shell that the interior kernels do not cover.

* :class:`PoleMirror`: the bending element of a pole node on the axis, with a mirror node across it
  (:mod:`contin_models.shell.problem`, "Pole treatment").
* :class:`ClampedEdge`: the bending element of a clamped edge node, against a fixed ghost node on the
  reference edge tangent (:func:`edge_tangent`).
* :class:`MomentFreeEdge`: the bending element of an edge node whose rotation is free.

:class:`contin_models.shell.reference.ShellReference` builds them from the reference meridian; the
problems (:class:`contin_models.shell.ShellPointLoad`, :class:`contin_models.shell.structure.ShellStructure`)
add their energies to the interior nodes'.
"""

from __future__ import annotations

import math

import numpy as np

from . import _generated as gen

__all__ = ["PoleMirror", "ClampedEdge", "MomentFreeEdge", "edge_tangent"]


class PoleMirror:
    """Bending element of the pole node with a mirror node across the axis.

    Acts on the local variables ``(r_{N-2}, z_{N-2}, z_{N-1})`` through ``a = r_{N-2}`` and
    ``b = z_{N-1} - z_{N-2}`` (``r_{N-1} = 0``).

    Parameters
    ----------
    lbar : float
        Reference length of the last edge (the pole's Voronoi length with the mirror edge).
    kb : float
        Bending stiffness ``E h^3 / (12 (1 - nu^2))``.
    nu : float
        Poisson's ratio.
    current_length : bool
        Use the current last-edge length ``sqrt(a^2 + b^2)`` in ``kappa11`` instead of ``lbar``.
    a_bar, b_bar : float
        Reference ``a`` and ``b``; the reference curvature ``kappabar`` comes from the same formula,
        so the reference state is stress free.

    Notes
    -----
    The element's area ``pi (lbar/2)^2`` is the exact area of the pole's cell, so that with the
    interior rings the cells tile the cap; the docstring of :mod:`contin_models.shell.problem`
    ("Pole treatment") gives the measured effect of other weights and lengths.
    """

    def __init__(self, lbar: float, kb: float, nu: float, current_length: bool,
                 a_bar: float, b_bar: float) -> None:
        self.lbar = float(lbar)
        self.current_length = bool(current_length)
        self.area = math.pi * (0.5 * self.lbar) ** 2
        self.K = self.area * kb * (1.0 + nu)
        self.kappa_bar = self.curvature(a_bar, b_bar)[0]

    def curvature(self, a: float, b: float) -> tuple[float, np.ndarray, np.ndarray]:
        """Pole curvature ``kappa`` with its gradient and Hessian in ``(a, b)``."""
        if self.current_length:
            s = a * a + b * b
            rs = math.sqrt(s)
            s32 = s * rs
            s52 = s32 * s
            k = 2.0 * b / (a * rs)
            ka = -2.0 * b / (a * a * rs) - 2.0 * b / s32
            kb_ = 2.0 * a / s32
            kaa = 4.0 * b / (a ** 3 * rs) + 2.0 * b / (a * s32) + 6.0 * a * b / s52
            kab = 2.0 / s32 - 6.0 * a * a / s52
            kbb = -6.0 * a * b / s52
        else:
            c = 2.0 / self.lbar
            k = c * b / a
            ka = -c * b / (a * a)
            kb_ = c / a
            kaa = 2.0 * c * b / a ** 3
            kab = -c / (a * a)
            kbb = 0.0
        return k, np.array([ka, kb_]), np.array([[kaa, kab], [kab, kbb]])

    # local (r_{N-2}, z_{N-2}, z_{N-1}) -> (a, b) is linear with this Jacobian
    _T = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 1.0]])

    def energy(self, a: float, b: float) -> float:
        """Element energy ``K (kappa - kappabar)^2``."""
        k = self.curvature(a, b)[0]
        return self.K * (k - self.kappa_bar) ** 2

    def gradient_hessian(self, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
        """Gradient (3,) and Hessian (3, 3) in the local variables ``(r_{N-2}, z_{N-2}, z_{N-1})``."""
        k, g, H = self.curvature(a, b)
        c, B = 2.0 * self.K, k - self.kappa_bar
        (ka, kb_), ((kaa, kab), (_, kbb)) = g.tolist(), H.tolist()
        # T^T g and T^T H T with T = _T (a = r_{N-2}, b = z_{N-1} - z_{N-2}), written out in floats:
        # the pole element is evaluated with every gradient and Hessian, and small-array numpy
        # operations cost more than the arithmetic
        ga, gb = c * B * ka, c * B * kb_
        haa, hab, hbb = c * (ka * ka + B * kaa), c * (ka * kb_ + B * kab), c * (kb_ * kb_ + B * kbb)
        return (np.array([ga, -gb, gb]),
                np.array([[haa, -hab, hab], [-hab, hbb, -hbb], [hab, -hbb, hbb]]))


def edge_tangent(r: np.ndarray, z: np.ndarray) -> tuple[float, float]:
    """Unit tangent at node 0 of a polyline, pointing along it, from the circle through nodes 0, 1, 2.

    Exact for a polyline whose first three nodes lie on a circle or a straight line (spherical caps,
    tori, plates, cones), second-order in the spacing otherwise.
    """
    p0, p1, p2 = (np.array([r[k], z[k]], dtype=float) for k in range(3))
    a, b = p1 - p0, p2 - p0
    cross = a[0] * b[1] - a[1] * b[0]
    if abs(cross) <= 1e-14 * np.linalg.norm(a) * np.linalg.norm(b):  # collinear: a straight edge
        t = a
    else:
        # centre c of the circle through p0, p1, p2 (relative to p0); the tangent at p0 is normal to c
        aa, bb = a @ a, b @ b
        c = np.array([b[1] * aa - a[1] * bb, a[0] * bb - b[0] * aa]) / (2.0 * cross)
        t = np.array([-c[1], c[0]])
        if t @ a < 0:
            t = -t
    t = t / np.linalg.norm(t)
    return float(t[0]), float(t[1])


class ClampedEdge:
    """Bending element of the edge node against a fixed ghost node on the reference edge tangent.

    The interior nodes' bending element (generated ``"bend"`` kernel, ``kappa11`` over the reference
    length given) on the nodes ``(ghost, 0, 1)``, with length and weight the half of the first
    reference edge inside the shell.  The ghost lies one first-edge length behind node 0 along the
    reference tangent (the smooth meridian's, else :func:`edge_tangent`).  Why the tangent and the half cell:
    :mod:`contin_models.shell.pressure`.

    Parameters
    ----------
    r, z : ndarray
        Reference node coordinates (node 0 is the edge).
    kb, nu : float
        Bending stiffness at the edge node and Poisson's ratio.
    tangent : (float, float), optional
        Unit tangent of the smooth reference meridian at node 0, along it; default
        :func:`edge_tangent` of the nodes.
    """

    #: Full-state dofs of the element's real nodes (0 and 1): ``r_0, z_0, r_1, z_1``.
    dofs = np.arange(4)

    def __init__(self, r: np.ndarray, z: np.ndarray, kb: float, nu: float,
                 tangent: tuple[float, float] | None = None) -> None:
        l0 = math.hypot(r[1] - r[0], z[1] - z[0])
        tr, tz = edge_tangent(r, z) if tangent is None else tangent
        self.ghost = (float(r[0]) - l0 * tr, float(z[0]) - l0 * tz)
        self.lbar = 0.5 * l0  # the edge node's cell inside the shell
        self.rbar = float(r[0])
        self.kb, self.nu = float(kb), float(nu)
        k11, k22 = gen.bend_curvatures(*self.ghost, r[0], z[0], r[1], z[1],
                                       self.lbar, self.rbar, 0.0, 0.0, self.kb, self.nu)
        self.kappa_bar = (float(k11), float(k22))

    def _args(self, x: np.ndarray) -> tuple:
        return (*self.ghost, x[0], x[1], x[2], x[3], self.lbar, self.rbar, *self.kappa_bar, self.kb, self.nu)

    def curvatures(self, x: np.ndarray) -> tuple[float, float]:
        """``(kappa11, kappa22)`` at the edge node of a full state."""
        k11, k22 = gen.bend_curvatures(*self._args(x))
        return float(k11), float(k22)

    def energy(self, x: np.ndarray) -> float:
        """Element energy ``pi rbar lbar kb (B11^2 + 2 nu B11 B22 + B22^2)`` of a full state."""
        return float(gen.bend_energy(*self._args(x)))

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """Gradient (4,) in :attr:`dofs` (the ghost is fixed: its entries are dropped)."""
        return gen.bend_gradient(*self._args(x))[2:]

    def hessian(self, x: np.ndarray) -> np.ndarray:
        """Hessian (4, 4) in :attr:`dofs`."""
        return gen.bend_hessian(*self._args(x))[2:, 2:]


class MomentFreeEdge:
    """Bending element of an edge node whose rotation is free: the half cell inside the shell, moment free.

    At an edge that may rotate (sliding, pinned, free) the meridional moment vanishes,
    ``B11 + nu B22 = 0``, so the bending energy density ``kb (B11^2 + 2 nu B11 B22 + B22^2)`` of the
    edge's cell is ``kb (1 - nu^2) B22^2`` with ``B22`` the change of the hoop curvature
    ``kappa22 = n_r / r_0``, ``n`` the first edge's unit normal.  Weighted with the half cell
    ``pi r0bar lbar_0 / 2`` the node owns inside the shell, as for the interior nodes and
    :class:`ClampedEdge`.  Without it the edge's half cell carries no bending energy at all, an
    O(spacing) error: a pinned plate under a central point load then converges at first order
    (errors 5.5e-4, 2.7e-4 at N = 400, 800); with it at order 1.9 (2.0e-5, 5.9e-6;
    ``tests/test_shell_structure.py``).  The paper's base has no such element (``edge_bending="none"``).

    Parameters
    ----------
    r, z : ndarray
        Reference node coordinates (node 0 is the edge, off the axis).
    kb, nu : float
        Bending stiffness at the edge node and Poisson's ratio.
    """

    #: Full-state dofs of the element: ``r_0, z_0, r_1, z_1``.
    dofs = np.arange(4)
    _DR = np.array([-1.0, 0.0, 1.0, 0.0])
    _DZ = np.array([0.0, -1.0, 0.0, 1.0])

    def __init__(self, r: np.ndarray, z: np.ndarray, kb: float, nu: float) -> None:
        l0 = math.hypot(r[1] - r[0], z[1] - z[0])
        self.K = math.pi * float(r[0]) * 0.5 * l0 * float(kb) * (1.0 - nu * nu)
        self.kappa_bar = self.curvature(np.array([r[0], z[0], r[1], z[1]], dtype=float))[0]

    def curvature(self, u: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """``kappa22 = (z_1 - z_0) / (l r_0)`` with its gradient and Hessian in ``(r_0, z_0, r_1, z_1)``."""
        r0, z0, r1, z1 = (float(v) for v in u[:4])
        dr, dz = r1 - r0, z1 - z0
        l = math.hypot(dr, dz)
        a, b, c = dz, 1.0 / l, 1.0 / r0  # kappa22 = a b c
        g = dr * self._DR + dz * self._DZ  # l dl
        da, db, dc = self._DZ, -g / l**3, np.array([-c * c, 0.0, 0.0, 0.0])
        Hb = 3.0 / l**5 * np.outer(g, g) - (np.outer(self._DR, self._DR) + np.outer(self._DZ, self._DZ)) / l**3
        Hc = np.zeros((4, 4))
        Hc[0, 0] = 2.0 * c**3
        t = db * c + b * dc
        k = a * b * c
        dk = da * b * c + a * t
        Hk = a * (Hb * c + np.outer(db, dc) + np.outer(dc, db) + b * Hc) + np.outer(da, t) + np.outer(t, da)
        return k, dk, Hk

    def energy(self, x: np.ndarray) -> float:
        """``K (kappa22 - kappabar22)^2`` of a full state."""
        return self.K * (self.curvature(x)[0] - self.kappa_bar) ** 2

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """Gradient (4,) in :attr:`dofs`."""
        k, dk, _ = self.curvature(x)
        return 2.0 * self.K * (k - self.kappa_bar) * dk

    def hessian(self, x: np.ndarray) -> np.ndarray:
        """Hessian (4, 4) in :attr:`dofs`."""
        k, dk, Hk = self.curvature(x)
        return 2.0 * self.K * (np.outer(dk, dk) + (k - self.kappa_bar) * Hk)
