"""Shallow-shell (Marguerre / Donnell-Mushtari-Vlasov) theory of a clamped spherical cap under an apex point load.

An independent check of the shell model's wavy branches (:mod:`contin_models.shell`): the same cap described by the
classical equations of a shallow shell, in polar coordinates, written from the theory and sharing nothing with the
shell model but the engine.

Theory (facts from the literature, written out here in our own notation)
-----------------------------------------------------------------------
* Marguerre (1938) and the Donnell-Mushtari-Vlasov approximation: a shallow shell is a plate with an initial
  height ``z0(x, y)``; its in-plane strains are ``e_ab = (u_a,b + u_b,a + z0,a w,b + z0,b w,a + w,a w,b) / 2`` and
  its curvature changes those of a plate, ``w,ab``; the energy is the plate's (Timoshenko & Woinowsky-Krieger,
  *Theory of plates and shells*, ch. 1 and 15; Brush & Almroth, *Buckling of bars, plates and shells*, ch. 5).
* The shallow sphere: ``z0 = H (1 - r^2 / a^2)``, a paraboloid of base radius ``a`` and rise ``H``, which is the
  sphere of radius ``R = a^2 / (2 H)`` to shallow order (``sqrt(R^2 - r^2) - (R - H) = H - r^2 / (2 R) +
  O(r^4 / R^3)``, and the theory drops terms of that order).  The geometric parameter
  ``lambda = 2 (3 (1 - nu^2))^(1/4) sqrt(H / t) = (12 (1 - nu^2))^(1/4) a / sqrt(R t)`` (Budiansky 1959; Huang
  1964; Fitch 1968).

Equations of this module (derived here)
---------------------------------------
``w`` is the deflection towards the base plane (positive where the apex is pushed in), ``u_r``, ``u_t`` the
in-plane displacements.  In polar coordinates, with ``z0' = -2 H r / a^2``::

    e_rr = u_r,r + (2 H r / a^2) w,r + w,r^2 / 2
    e_tt = (u_r + u_t,t) / r + w,t^2 / (2 r^2)
    g_rt = 2 e_rt = u_t,r - u_t / r + u_r,t / r + (2 H / a^2) w,t + w,r w,t / r
    k_rr = w,rr,   k_tt = w,r / r + w,tt / r^2,   2 k_rt = 2 (w,rt / r - w,t / r^2)

(``z0`` does not depend on ``t``, so ``e_tt`` has no coupling term).  With ``rho = r / a``, ``w = t W``,
``u = (t^2 / a) U`` and the energy over ``D t^2 / a^2`` (``D = E t^3 / (12 (1 - nu^2))``), every strain is
``t^2 / a^2`` times its hatted form, in which ``2 H r / a^2`` becomes ``beta rho`` with
``beta = a^2 / (R t) = 2 H / t = lambda^2 / sqrt(12 (1 - nu^2))``, and the energy is::

    E = int_0^1 int_0^2pi [ k . C k / 2 + 6 e . C e ] rho drho dt,   e . C e = e_rr^2 + e_tt^2 + 2 nu e_rr e_tt
                                                                         + (1 - nu) g_rt^2 / 2

(``k . C k`` likewise with ``2 k_rt``).  The factor 6: the membrane density ``E t / (2 (1 - nu^2)) e . C e`` with
``e ~ t^2 / a^2`` over the bending density's unit ``D (t / a^2)^2`` is ``(E t^3 / (2 (1 - nu^2))) / D = 6``.  It
depends on ``lambda`` (through ``beta``) and ``nu`` only.  The apex load
``P`` (towards the base) does the work ``P w(0)``; under displacement control ``W(0) = delta`` is the parameter
and the apex force is the energy's derivative in it, ``q = P a^2 / (D t) = dE / d delta``.  The load parameter
of the shell's studies is ``P R / (E t^3) = q / (12 (1 - nu^2) beta)``.

Discretisation
--------------
Fourier in the angle, finite elements in the radius.  A :class:`Harmonic` ``(m, "cos")`` carries
``w, u_r ~ cos m t`` and ``u_t ~ sin m t``, ``(m, "sin")`` the same with cos and sin exchanged (its ``m = 0``
member is the twist ``u_t`` alone).  The state of the ``n``-wave branch lies in the space fixed by the
dihedral group ``D_n`` (turns by ``2 pi / n`` and the reflection ``t -> -t``): the harmonics ``(k n, "cos")``,
``k = 0 .. K``.  In the radius, ``w`` is a cubic Hermite interpolant (value and slope at the nodes) and
``u_r``, ``u_t`` quadratic Lagrange (vertices and mid-points), four Gauss points per element.  The angular
integral is a uniform rule exact for the trigonometric polynomials that occur: the energy density of harmonics up
to ``K n`` has degree ``4 K n``, so ``4 K + 1`` points over one period ``2 pi / n``; a Hessian of perturbations up
to harmonic ``m`` about such a state has degree ``2 K n + 2 m``.  The energy, gradient and Hessian are therefore
those of the discrete fields exactly, up to the radial Gauss rule.

The pole (``rho = 0``), for a field regular at the axis: harmonic ``m`` of ``w`` goes as ``rho^m`` and of
``u_r``, ``u_t`` as ``rho^(m - 1)``.  Hence ``w'(0) = 0`` for ``m = 0`` (``w(0)`` is the apex deflection);
``w(0) = 0`` for ``m = 1``, with ``u_t(0) = -u_r(0)`` (``cos``) or ``u_t(0) = u_r(0)`` (``sin``): a translation of
the pole in the plane; and ``w(0) = w'(0) = u_r(0) = u_t(0) = 0`` for ``m >= 2``; ``u_r(0) = 0`` and
``u_t(0) = 0`` for ``m = 0``.  These are imposed by elimination.  The clamped edge: ``w = w' = u_r = u_t = 0`` at
``rho = 1`` for every harmonic.

The unknowns are ordered by radial position (all harmonics of one node together), so the Hessian is banded.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

import contin

__all__ = ["Harmonic", "FourierSpace", "ShallowCap", "beta_of_lambda", "load_factor", "representation_harmonics",
           "point_load_stiffness", "plate_point_load_deflection"]

#: The primitive fields of the energy density: ``U`` = ``u_r``, ``V`` = ``u_t``, ``W`` = ``w``; ``r`` a radial
#: derivative, ``t`` an angular one.  ``w`` itself never enters (only its derivatives).
FIELDS = ("U", "Ur", "Ut", "V", "Vr", "Vt", "Wr", "Wt", "Wrr", "Wrt", "Wtt")
#: Per component: the fields it carries, as (index in FIELDS, radial derivative order, angular derivative order).
_COMPONENT_FIELDS = {
    "u": ((0, 0, 0), (1, 1, 0), (2, 0, 1)),
    "v": ((3, 0, 0), (4, 1, 0), (5, 0, 1)),
    "w": ((6, 1, 0), (7, 0, 1), (8, 2, 0), (9, 1, 1), (10, 0, 2)),
}
COMPONENTS = ("u", "v", "w")
#: Radial unknowns per element per component: Hermite (value, slope at both ends) and quadratic Lagrange.
_LOCAL = {"u": 3, "v": 3, "w": 4}
GAUSS_POINTS = 4
_PATHS: dict[tuple, Any] = {}


def _einsum(spec: str, *operands: np.ndarray) -> np.ndarray:
    """``np.einsum`` with its contraction order found once per subscripts and shapes (the search costs more than
    these small contractions)."""
    key = (spec,) + tuple(o.shape for o in operands)
    path = _PATHS.get(key)
    if path is None:
        path = _PATHS[key] = np.einsum_path(spec, *operands, optimize="optimal")[0]
    return np.einsum(spec, *operands, optimize=path)


def beta_of_lambda(lam: float, nu: float) -> float:
    """``beta = a^2 / (R t) = 2 H / t`` of the shallow cap of geometric parameter ``lam`` (module docstring)."""
    return float(lam) ** 2 / math.sqrt(12.0 * (1.0 - nu ** 2))


def load_factor(lam: float, nu: float) -> float:
    """The factor from ``q = P a^2 / (D t)`` to ``P R / (E t^3)``: ``1 / (12 (1 - nu^2) beta)``."""
    return 1.0 / (12.0 * (1.0 - nu ** 2) * beta_of_lambda(lam, nu))


def point_load_stiffness(nu: float) -> float:
    """Reissner's stiffness of a shallow sphere under a small point load, far from its edge:
    ``P R / (E t^3) = 4 / sqrt(3 (1 - nu^2)) w / t`` (Reissner 1946/47)."""
    return 4.0 / math.sqrt(3.0 * (1.0 - nu ** 2))


def plate_point_load_deflection(q: float) -> float:
    """The central deflection over ``t`` of a clamped circular plate under a central force, ``w = P a^2 / (16 pi D)``
    (Timoshenko & Woinowsky-Krieger, sec. 19), for ``q = P a^2 / (D t)``: ``q / (16 pi)``."""
    return float(q) / (16.0 * math.pi)


@dataclass(frozen=True)
class Harmonic:
    """One angular harmonic of the fields: wave number ``m`` and parity ``"cos"`` (``w, u_r ~ cos m t``,
    ``u_t ~ sin m t``) or ``"sin"`` (the other way round)."""

    m: int
    parity: str = "cos"

    def components(self) -> tuple[str, ...]:
        """The components this harmonic carries (a zero ``sin 0`` is left out)."""
        if self.m == 0:
            return ("u", "w") if self.parity == "cos" else ("v",)
        return COMPONENTS

    def angular(self, component: str, order: int, theta: np.ndarray) -> np.ndarray:
        """The ``order``-th angular derivative of the component's angular function at ``theta``."""
        cosine = (self.parity == "cos") != (component == "v")
        # d^k/dt^k of cos(m t) = m^k cos(m t + k pi / 2); of sin(m t) = m^k sin(m t + k pi / 2)
        arg = self.m * theta + order * np.pi / 2.0
        return (self.m ** order) * (np.cos(arg) if cosine else np.sin(arg))


def representation_harmonics(n: int, K: int) -> dict[str, list[Harmonic]]:
    """The harmonics of each real representation class of ``D_n`` for perturbations of an ``n``-wave state with
    harmonics up to ``K n``: ``A1`` (the state's own space), ``A2`` (its ``sin`` twin, with the twist), ``B1``,
    ``B2`` (``n`` even: wave numbers ``n / 2`` mod ``n``) and ``E1 .. E_{(n-1)//2}`` (wave numbers ``+-j`` mod
    ``n``; the ``cos`` member, the ``sin`` one has the same spectrum).  Wave numbers up to ``K n + n // 2``."""
    top = K * n + n // 2
    out = {"A1": [Harmonic(k * n, "cos") for k in range(K + 1)],
           "A2": [Harmonic(0, "sin")] + [Harmonic(k * n, "sin") for k in range(1, K + 1)]}
    if n % 2 == 0:
        half = [m for m in range(n // 2, top + 1, n)]
        out["B1"] = [Harmonic(m, "cos") for m in half]
        out["B2"] = [Harmonic(m, "sin") for m in half]
    for j in range(1, (n - 1) // 2 + 1):
        ms = sorted(m for m in range(0, top + 1) if m % n in (j, n - j))
        out[f"E{j}"] = [Harmonic(m, "cos") for m in ms]
    return out


def _hermite(xi: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cubic Hermite shape functions on elements of lengths ``h`` at local coordinates ``xi`` in [0, 1]: values,
    first and second derivatives in ``rho``, shape (elements, points, 4)."""
    x = xi[None, :]
    hh = h[:, None]
    one = np.ones_like(hh)
    N0 = np.stack([one * (1 - 3 * x ** 2 + 2 * x ** 3), hh * (x - 2 * x ** 2 + x ** 3),
                   one * (3 * x ** 2 - 2 * x ** 3), hh * (-x ** 2 + x ** 3)], axis=-1)
    N1 = np.stack([(-6 * x + 6 * x ** 2) / hh, one * (1 - 4 * x + 3 * x ** 2),
                   (6 * x - 6 * x ** 2) / hh, one * (-2 * x + 3 * x ** 2)], axis=-1)
    N2 = np.stack([(-6 + 12 * x) / hh ** 2, (-4 + 6 * x) / hh,
                   (6 - 12 * x) / hh ** 2, (-2 + 6 * x) / hh], axis=-1)
    return N0, N1, N2


def _lagrange(xi: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quadratic Lagrange shape functions (start, middle, end): values and ``rho``-derivatives, shape
    (elements, points, 3)."""
    x = xi[None, :]
    hh = h[:, None]
    one = np.ones_like(hh)
    L0 = np.stack([one * 2 * (x - 0.5) * (x - 1), one * -4 * x * (x - 1), one * 2 * x * (x - 0.5)], axis=-1)
    L1 = np.stack([(4 * x - 3) / hh, (-8 * x + 4) / hh, (4 * x - 1) / hh], axis=-1)
    return L0, L1


def radial_mesh(N: int, grading: float = 1.0) -> np.ndarray:
    """``N + 1`` nodes on [0, 1], ``rho_i = (i / N)^grading`` (``grading > 1`` refines at the pole)."""
    if int(N) != N or N < 2:
        raise ValueError(f"ShallowCap: N = {N!r} must be an integer >= 2 (radial elements)")
    if not (math.isfinite(grading) and 1.0 <= grading <= 3.0):
        raise ValueError(f"ShallowCap: grading = {grading!r} must lie in [1, 3]")
    return (np.arange(N + 1) / N) ** float(grading)


class FourierSpace:
    """The discrete fields of a set of harmonics on a radial mesh, their unknowns and their angular rule.

    Parameters
    ----------
    nodes : ndarray
        The radial mesh, from 0 to 1.
    harmonics : sequence of Harmonic
    theta, weights : ndarray
        The angular quadrature points and weights (summing to ``2 pi``).
    apex_parameter : bool
        Whether the apex deflection ``w(0)`` of harmonic ``(0, "cos")`` is the parameter (the state's space) or
        held at zero (a space of perturbations under displacement control).

    Attributes
    ----------
    n_free : int
        The number of unknowns.
    labels : list of tuple
        Each unknown's ``(m, parity, component, position, slot)``: position ``2 i`` is node ``i``, ``2 e + 1`` the
        middle of element ``e``; slot 1 is a slope of ``w``.
    """

    def __init__(self, nodes: np.ndarray, harmonics: Sequence[Harmonic], theta: np.ndarray, weights: np.ndarray,
                 apex_parameter: bool = True) -> None:
        self.nodes = np.asarray(nodes, dtype=float)
        self.harmonics = list(harmonics)
        self.theta = np.asarray(theta, dtype=float)
        self.weights = np.asarray(weights, dtype=float)
        N = self.N = len(self.nodes) - 1
        h = np.diff(self.nodes)
        xi, wg = np.polynomial.legendre.leggauss(GAUSS_POINTS)
        xi = 0.5 * (xi + 1.0)
        wg = 0.5 * wg
        self.rho = self.nodes[:-1, None] + h[:, None] * xi[None, :]          # (N, ng)
        # radial weight times rho (the area element), per Gauss point
        self.radial_weight = h[:, None] * wg[None, :] * self.rho
        N0, N1, N2 = _hermite(xi, h)
        L0, L1 = _lagrange(xi, h)
        radial = {"w": (N0, N1, N2), "u": (L0, L1), "v": (L0, L1)}
        # per component: radial tables (N, ng, fields, local) and angular tables (fields, M, blocks)
        self.blocks = {c: [k for k, hm in enumerate(self.harmonics) if c in hm.components()] for c in COMPONENTS}
        self.rad = {c: np.stack([radial[c][r] for (_, r, _) in _COMPONENT_FIELDS[c]], axis=2) for c in COMPONENTS}
        self.ang = {c: np.stack([np.stack([self.harmonics[k].angular(c, t, self.theta) for k in self.blocks[c]],
                                          axis=-1) if self.blocks[c] else np.zeros((len(self.theta), 0))
                                 for (_, _, t) in _COMPONENT_FIELDS[c]], axis=0) for c in COMPONENTS}
        self._unknowns(apex_parameter)

    # ---- unknowns ----------------------------------------------------------------------------------
    def _unknowns(self, apex_parameter: bool) -> None:
        """Number the raw nodal values, decide which are free, fixed, the parameter or tied to another."""
        N = self.N
        raw: list[tuple] = []      # (position, block, component, slot)
        for k, hm in enumerate(self.harmonics):
            for c in hm.components():
                if c == "w":
                    raw += [(2 * i, k, c, s) for i in range(N + 1) for s in (0, 1)]
                else:
                    raw += [(p, k, c, 0) for p in range(2 * N + 1)]
        comp_order = {c: i for i, c in enumerate(COMPONENTS)}
        raw.sort(key=lambda r: (r[0], r[1], comp_order[r[2]], r[3]))
        index = {r: i for i, r in enumerate(raw)}
        # status: each raw value is sign * free[j], or zero, or the parameter
        free_of = np.full(len(raw), -1, dtype=np.int64)
        sign = np.zeros(len(raw))
        param = np.zeros(len(raw))
        pole_pos, edge_pos_w, edge_pos_uv = 0, 2 * N, 2 * N
        labels = []
        ties = []
        for i, (pos, k, c, s) in enumerate(raw):
            hm = self.harmonics[k]
            fixed = False
            if c == "w" and pos == edge_pos_w:
                fixed = True
            elif c in ("u", "v") and pos == edge_pos_uv:
                fixed = True
            elif pos == pole_pos:
                if c == "w":
                    if hm.m == 0 and s == 0:
                        if apex_parameter and hm.parity == "cos":
                            param[i] = 1.0
                        fixed = True
                    elif hm.m == 0 and s == 1:
                        fixed = True
                    elif hm.m == 1:
                        fixed = s == 0
                    else:
                        fixed = True
                elif hm.m == 1 and c == "v":
                    # a translation of the pole: u_t(0) = -u_r(0) (cos) or u_r(0) (sin)
                    ties.append((i, index[(pos, k, "u", 0)], -1.0 if hm.parity == "cos" else 1.0))
                    continue
                elif hm.m != 1:
                    fixed = True
            if fixed:
                continue
            free_of[i] = len(labels)
            sign[i] = 1.0
            labels.append((hm.m, hm.parity, c, pos, s))
        for i, j, sgn in ties:
            free_of[i] = free_of[j]
            sign[i] = sgn
        self.n_raw = len(raw)
        self.n_free = len(labels)
        self.labels = labels
        self._free_of, self._sign, self._param = free_of, sign, param
        # element-local layout: per component, blocks x local slots; the raw index of each
        loc_raw = []
        for c in COMPONENTS:
            for k in self.blocks[c]:
                if c == "w":
                    cols = [(lambda e, a=a, s=s: (2 * (e + a), k, c, s)) for a in (0, 1) for s in (0, 1)]
                else:
                    cols = [(lambda e, d=d: (2 * e + d, k, c, 0)) for d in (0, 1, 2)]
                loc_raw.append(np.array([[index[f(e)] for f in cols] for e in range(N)], dtype=np.int64))
        self.loc_raw = np.concatenate(loc_raw, axis=1) if loc_raw else np.zeros((N, 0), dtype=np.int64)
        self.n_local = self.loc_raw.shape[1]
        self.loc_free = free_of[self.loc_raw]
        self.loc_sign = sign[self.loc_raw]
        self.loc_param = param[self.loc_raw]
        # COO pattern of the free-free Hessian and the free-parameter column
        ii = np.repeat(self.loc_free[:, :, None], self.n_local, axis=2)
        jj = np.repeat(self.loc_free[:, None, :], self.n_local, axis=1)
        self._hmask = (ii >= 0) & (jj >= 0)
        self._hrows, self._hcols = ii[self._hmask], jj[self._hmask]
        self._hsign = (self.loc_sign[:, :, None] * self.loc_sign[:, None, :])[self._hmask]
        self._gmask = self.loc_free >= 0
        self._pmask = (ii >= 0) & (self.loc_param[:, None, :] != 0.0)
        offsets, start = {}, 0
        for c in COMPONENTS:
            size = len(self.blocks[c]) * _LOCAL[c]
            offsets[c] = (start, start + size)
            start += size
        self._offsets = offsets

    def local(self, x: np.ndarray, p: float) -> np.ndarray:
        """The element-local nodal values (elements, local) of the unknowns ``x`` and the apex deflection ``p``."""
        x = np.asarray(x, dtype=float)
        vals = np.where(self.loc_free >= 0, x[np.maximum(self.loc_free, 0)], 0.0) * self.loc_sign
        return vals + float(p) * self.loc_param

    # ---- fields, gradient, Hessian ------------------------------------------------------------------
    def _present(self):
        """The components this space carries: (component, its blocks, its local slice, its fields' indices)."""
        for c in COMPONENTS:
            if self.blocks[c]:
                a, b = self._offsets[c]
                yield c, len(self.blocks[c]), slice(a, b), [f for (f, _, _) in _COMPONENT_FIELDS[c]]

    def fields(self, loc: np.ndarray) -> np.ndarray:
        """The primitive fields (:data:`FIELDS`) at the quadrature points: (elements, Gauss, angles, 11)."""
        out = np.zeros(self.rho.shape + (len(self.theta), len(FIELDS)))
        for c, nb, cols, idx in self._present():
            d = loc[:, cols].reshape(self.N, nb, _LOCAL[c])
            out[..., idx] += _einsum("egfi,ehi,fjh->egjf", self.rad[c], d, self.ang[c])
        return out

    def gradient(self, psi1: np.ndarray) -> tuple[np.ndarray, float]:
        """The gradient in the unknowns and the derivative in the parameter of ``int psi``, from the density's
        derivatives ``psi1`` (elements, Gauss, angles, 11) in the primitive fields."""
        wq = self.radial_weight[:, :, None] * self.weights[None, None, :]
        glocal = np.zeros((self.N, self.n_local))
        for c, nb, cols, idx in self._present():
            g = _einsum("egj,egjf,egfi,fjh->ehi", wq, psi1[..., idx], self.rad[c], self.ang[c])
            glocal[:, cols] = g.reshape(self.N, -1)
        grad = np.bincount(self.loc_free[self._gmask], weights=(glocal * self.loc_sign)[self._gmask],
                           minlength=self.n_free)
        return grad, float(np.sum(glocal * self.loc_param))

    def hessian(self, psi2: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
        """The Hessian in the unknowns (CSR) and its column in the parameter, from the density's second
        derivatives ``psi2``: (elements, Gauss, angles, 11, 11), or (elements, Gauss, 11, 11) where they do not
        depend on the angle (an axisymmetric state): the angular integrals are then those of the harmonics'
        products alone, summed once."""
        axisymmetric = psi2.ndim == 4
        wq = self.radial_weight[:, :, None] * self.weights[None, None, :]
        H = np.zeros((self.N, self.n_local, self.n_local))
        for c1, n1, cols1, i1 in self._present():
            for c2, n2, cols2, i2 in self._present():
                if axisymmetric:
                    coef = psi2[..., i1, :][..., i2] * self.radial_weight[..., None, None]
                    gram = _einsum("j,ajh,bjk->abhk", self.weights, self.ang[c1], self.ang[c2])
                    T = coef[..., None, None] * gram
                else:
                    coef = psi2[..., i1, :][..., i2] * wq[..., None, None]
                    T = _einsum("egjab,ajh,bjk->egabhk", coef, self.ang[c1], self.ang[c2])
                blk = _einsum("egai,egbl,egabhk->ehikl", self.rad[c1], self.rad[c2], T)
                H[:, cols1, cols2] = blk.reshape(self.N, n1 * _LOCAL[c1], n2 * _LOCAL[c2])
        vals = H[self._hmask] * self._hsign
        Hf = sp.csr_matrix((vals, (self._hrows, self._hcols)), shape=(self.n_free, self.n_free))
        pcol = H * (self.loc_sign[:, :, None] * self.loc_param[:, None, :])
        dfdp = np.bincount(np.broadcast_to(self.loc_free[:, :, None], H.shape)[self._pmask],
                           weights=pcol[self._pmask], minlength=self.n_free)
        return Hf, dfdp

    def index_of(self, labels: Sequence[tuple]) -> np.ndarray:
        """Positions of the given unknowns' labels among this space's unknowns (-1 where it has none)."""
        where = {lab: i for i, lab in enumerate(self.labels)}
        return np.array([where.get(lab, -1) for lab in labels], dtype=np.int64)


class _Density:
    """The energy density of the shallow shell and its derivatives in the primitive fields (module docstring)."""

    def __init__(self, beta: float, nu: float) -> None:
        self.beta, self.nu = float(beta), float(nu)
        self.C = np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 0.5 * (1.0 - nu)]])

    def __call__(self, f: np.ndarray, rho: np.ndarray, order: int) -> tuple[np.ndarray, ...]:
        """``psi`` and, up to ``order``, ``psi1`` (..., 11) and ``psi2`` (..., 11, 11) at the points;
        ``rho`` broadcasts against ``f[..., 0]``."""
        U, Ur, Ut, V, Vr, Vt, Wr, Wt, Wrr, Wrt, Wtt = np.moveaxis(f, -1, 0)
        r = np.broadcast_to(rho, U.shape)
        b = self.beta
        eps = np.stack([Ur + b * r * Wr + 0.5 * Wr ** 2,
                        (U + Vt) / r + 0.5 * Wt ** 2 / r ** 2,
                        Vr - V / r + Ut / r + b * Wt + Wr * Wt / r], axis=-1)
        kap = np.stack([Wrr, Wr / r + Wtt / r ** 2, 2.0 * (Wrt / r - Wt / r ** 2)], axis=-1)
        Ce, Ck = eps @ self.C, kap @ self.C
        psi = 0.5 * np.sum(kap * Ck, axis=-1) + 6.0 * np.sum(eps * Ce, axis=-1)
        if order == 0:
            return (psi,)
        shape = U.shape
        De = np.zeros(shape + (3, len(FIELDS)))
        De[..., 0, 1] = 1.0
        De[..., 0, 6] = b * r + Wr
        De[..., 1, 0] = 1.0 / r
        De[..., 1, 5] = 1.0 / r
        De[..., 1, 7] = Wt / r ** 2
        De[..., 2, 4] = 1.0
        De[..., 2, 3] = -1.0 / r
        De[..., 2, 2] = 1.0 / r
        De[..., 2, 7] = b + Wr / r
        De[..., 2, 6] = Wt / r
        Dk = np.zeros(shape + (3, len(FIELDS)))
        Dk[..., 0, 8] = 1.0
        Dk[..., 1, 6] = 1.0 / r
        Dk[..., 1, 10] = 1.0 / r ** 2
        Dk[..., 2, 9] = 2.0 / r
        Dk[..., 2, 7] = -2.0 / r ** 2
        psi1 = np.einsum("...a,...af->...f", Ck, Dk) + 12.0 * np.einsum("...a,...af->...f", Ce, De)
        if order == 1:
            return psi, psi1
        psi2 = (np.einsum("...af,ab,...bg->...fg", Dk, self.C, Dk, optimize=True)
                + 12.0 * np.einsum("...af,ab,...bg->...fg", De, self.C, De, optimize=True))
        psi2[..., 6, 6] += 12.0 * Ce[..., 0]
        psi2[..., 7, 7] += 12.0 * Ce[..., 1] / r ** 2
        psi2[..., 6, 7] += 12.0 * Ce[..., 2] / r
        psi2[..., 7, 6] += 12.0 * Ce[..., 2] / r
        return psi, psi1, psi2


def _period_rule(n: int, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """A uniform angular rule over one period ``2 pi / n`` (``n = 0``: the circle), exact for the trigonometric
    polynomials of degree ``degree`` in ``n t`` (in ``t`` when ``n = 0``) that are even in ``t``, weights summing to
    ``2 pi``.  Every integrand here is even: the state and each class of perturbations are mapped to themselves by
    the reflection ``t -> -t``, so the points ``t_j`` and ``-t_j`` of the uniform rule are folded into one."""
    M = degree + 1
    period = 2.0 * np.pi / max(n, 1)
    j = np.arange(M // 2 + 1)
    weights = np.where((j == 0) | (2 * j == M), 1.0, 2.0) * (2.0 * np.pi / M)
    return period * j / M, weights


class ShallowCap(contin.Problem):
    """The clamped shallow cap under an apex load, apex deflection prescribed, in the ``D_n``-fixed space.

    Parameters
    ----------
    lam : float
        ``lambda = (12 (1 - nu^2))^(1/4) a / sqrt(R t)`` (0: a flat plate).
    nu : float
        Poisson's ratio, in (-1, 0.5].
    n : int
        The wave number of the state's symmetry (0: axisymmetric, then ``K`` must be 0).
    K : int
        Harmonics ``0, n, .., K n`` of the state.
    N : int
        Radial elements.
    grading : float
        Mesh grading towards the pole (:func:`radial_mesh`).
    watch : sequence of int
        Wave numbers whose Hessians the branch watches (an :class:`contin.OperatorFamily` ``"n"``, multiplicity 2)
        when the state is axisymmetric: at an axisymmetric state the Hessian splits by harmonic.

    Notes
    -----
    Parameter: the apex deflection over the thickness, ``w(0) / t``.  Observables: ``w`` (the same), ``q`` (the
    apex force ``P a^2 / (D t)``) and, for ``lam > 0``, ``P`` (``P R / (E t^3)``).  The stability operator is the
    Hessian at fixed apex deflection in the state's space (class ``A1``); :meth:`representation_hessians` gives
    the others.
    """

    def __init__(self, lam: float, nu: float = 0.3, n: int = 0, K: int = 0, N: int = 60, grading: float = 1.0,
                 watch: Sequence[int] = ()) -> None:
        if not (math.isfinite(lam) and lam >= 0.0):
            raise ValueError(f"ShallowCap: lam = {lam!r} must be a finite number >= 0")
        if not (math.isfinite(nu) and -1.0 < nu <= 0.5):
            raise ValueError(f"ShallowCap: nu = {nu!r} must lie in (-1, 0.5]")
        if int(n) != n or n < 0 or int(K) != K or K < 0 or (n == 0 and K != 0):
            raise ValueError(f"ShallowCap: n = {n!r}, K = {K!r}: integers >= 0, and K = 0 when n = 0")
        if watch and K != 0:
            raise ValueError("ShallowCap: watch the wave numbers of an axisymmetric state only (K = 0)")
        self.lam, self.nu, self.n, self.K, self.grading = float(lam), float(nu), int(n), int(K), float(grading)
        self.beta = beta_of_lambda(lam, nu)
        self.nodes = radial_mesh(N, grading)
        self.N = int(N)
        self.density = _Density(self.beta, nu)
        # the density of harmonics up to K n has degree 4 K in n t
        theta, weights = _period_rule(self.n, 4 * self.K)
        self.space = FourierSpace(self.nodes, [Harmonic(k * self.n, "cos") for k in range(self.K + 1)], theta,
                                  weights)
        self._cache: dict[str, Any] = {}
        observables = {"w": lambda x, p: float(p), "q": lambda x, p: self.apex_force(x, p)}
        if self.lam > 0.0:
            observables["P"] = lambda x, p: self.apex_force(x, p) * load_factor(self.lam, self.nu)
        families = ()
        if watch:
            keys = [int(m) for m in watch]
            if any(m < 1 for m in keys):
                raise ValueError(f"ShallowCap: watch = {watch!r}: wave numbers >= 1")
            families = (contin.OperatorFamily("n", keys, lambda m, x, p: self.wave_hessian(int(m), x, p),
                                              multiplicity=lambda m: 2),)
        # a turn by pi / n maps the state's harmonic k n to (-1)^k times itself
        gens = []
        if self.K > 0:
            flip = np.array([(-1.0) ** (lab[0] // self.n) for lab in self.space.labels])
            gens = [sp.diags(flip).tocsr()]
        super().__init__(symmetric=True, observables=observables,
                         name=f"shallow_cap(lambda={lam:g}, nu={nu:g}, n={n}, K={K}, N={N})",
                         parameter_name="w", operator_families=families, symmetry_generators=gens,
                         difference_scale=1.0)

    # ---- evaluation ------------------------------------------------------------------------------
    def _eval(self, x: np.ndarray, p: float, order: int) -> dict[str, Any]:
        x = np.asarray(x, dtype=float)
        key = (x.tobytes(), float(p))
        if self._cache.get("key") != key:
            self._cache = {"key": key}
        c = self._cache
        if c.get("order", -1) < order:
            if not np.all(np.isfinite(x)) or not math.isfinite(p):
                raise contin.NonFiniteError("ShallowCap: a non-finite state or parameter")
            f = self.space.fields(self.space.local(x, p))
            out = self.density(f, self.space.rho[:, :, None], order)
            wq = self.space.radial_weight[:, :, None] * self.space.weights[None, None, :]
            c["energy"] = float(np.sum(wq * out[0]))
            if order >= 1:
                c["grad"], c["force"] = self.space.gradient(out[1])
            if order >= 2:
                c["hess"], c["dfdp"] = self.space.hessian(out[2])
                c["psi2"] = out[2]
            c["order"] = order
        return c

    def energy(self, x, p):
        return self._eval(x, p, 0)["energy"]

    def residual(self, x, p):
        return self._eval(x, p, 1)["grad"].copy()

    def jacobian(self, x, p):
        return self._eval(x, p, 2)["hess"]

    def dresidual_dp(self, x, p):
        return self._eval(x, p, 2)["dfdp"].copy()

    def apex_force(self, x: np.ndarray, p: float) -> float:
        """``q = P a^2 / (D t)``: the energy's derivative in the apex deflection at equilibrium."""
        return self._eval(x, p, 1)["force"]

    @property
    def wave_unknowns(self) -> np.ndarray:
        """Which unknowns belong to the waves (harmonics ``m > 0``): all zero on the axisymmetric path."""
        return np.array([lab[0] > 0 for lab in self.space.labels], dtype=bool)

    def reference_unknowns(self) -> np.ndarray:
        """The unloaded state (zero)."""
        return np.zeros(self.space.n_free)

    # ---- Hessians of other symmetry classes ----------------------------------------------------------
    def class_hessian(self, harmonics: Sequence[Harmonic], x: np.ndarray, p: float) -> tuple[sp.csr_matrix,
                                                                                            FourierSpace]:
        """The Hessian at ``(x, p)``, at fixed apex deflection, restricted to perturbations in the given
        harmonics (a space the state's symmetry leaves invariant), and that space.  The angular rule is the
        uniform one over the circle exact for the products (degree ``2 K n + 2 max m``)."""
        state, pert = self._class_spaces(tuple(harmonics))
        if self.K == 0:
            # the state does not depend on the angle: its density's derivatives at one angle serve every harmonic
            return pert.hessian(self._eval(x, p, 2)["psi2"][:, :, 0])[0], pert
        f = state.fields(state.local(x, p))
        psi2 = self.density(f, state.rho[:, :, None], 2)[2]
        return pert.hessian(psi2)[0], pert

    def _class_spaces(self, harmonics: tuple[Harmonic, ...]) -> tuple[FourierSpace, FourierSpace]:
        """The state's space and the perturbations' on the angular rule of :meth:`class_hessian` (built once)."""
        spaces = self.__dict__.setdefault("_spaces", {})
        if harmonics not in spaces:
            top = max(h.m for h in harmonics)
            theta, weights = _period_rule(0, 2 * self.K * self.n + 2 * top)
            spaces[harmonics] = (FourierSpace(self.nodes, self.space.harmonics, theta, weights),
                                 FourierSpace(self.nodes, harmonics, theta, weights, apex_parameter=False))
        return spaces[harmonics]

    def wave_hessian(self, m: int, x: np.ndarray, p: float) -> sp.csr_matrix:
        """The Hessian of the perturbations ``(m, "cos")`` at an axisymmetric state (its ``sin`` twin has the same)."""
        return self.class_hessian([Harmonic(m, "cos")], x, p)[0]

    def representation_hessians(self, x: np.ndarray, p: float) -> dict[str, tuple[sp.csr_matrix, FourierSpace]]:
        """The Hessians of every representation class of ``D_n`` (:func:`representation_harmonics`) at an
        ``n``-wave state, with their spaces."""
        if self.n < 1:
            raise ValueError("ShallowCap.representation_hessians: the state is axisymmetric (n = 0)")
        return {label: self.class_hessian(hs, x, p) for label, hs in representation_harmonics(self.n, self.K).items()}

    def turning_mode(self, x: np.ndarray, space: FourierSpace) -> np.ndarray:
        """The derivative of the state ``x`` in a turn about the axis, as a vector of the ``A2`` space ``space``:
        ``d/dalpha`` of ``cos m (t - alpha)`` is ``m sin m t``; of ``sin m (t - alpha)`` (``u_t``) ``-m cos m t``."""
        out = np.zeros(space.n_free)
        where = {lab: i for i, lab in enumerate(space.labels)}
        for value, (m, parity, c, pos, s) in zip(np.asarray(x, dtype=float), self.space.labels):
            j = where.get((m, "sin", c, pos, s))
            if j is not None and m > 0:
                out[j] += (-m if c == "v" else m) * value
        return out

    def embed(self, source: "ShallowCap", x: np.ndarray) -> np.ndarray:
        """The unknowns ``x`` of another cap (same mesh; its harmonics a subset of this one's) as this cap's."""
        idx = self.space.index_of(source.space.labels)
        out = np.zeros(self.space.n_free)
        out[idx[idx >= 0]] = np.asarray(x, dtype=float)[idx >= 0]
        return out

    def embed_mode(self, m: int, mode: np.ndarray) -> np.ndarray:
        """A mode of :meth:`wave_hessian` ``m`` (its space's unknowns) as this cap's unknowns."""
        pert = FourierSpace(self.nodes, [Harmonic(m, "cos")], np.zeros(1), np.ones(1), apex_parameter=False)
        idx = self.space.index_of(pert.labels)
        if np.any(idx < 0):
            raise ValueError(f"ShallowCap.embed_mode: harmonic {m} is not among this cap's "
                             f"({self.n} waves, K = {self.K})")
        out = np.zeros(self.space.n_free)
        out[idx] = np.asarray(mode, dtype=float)
        return out
