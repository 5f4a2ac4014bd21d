"""Contact with a rigid indenter in the shell's 3-D view: the log barrier over the whole surface.

The traced model's barrier (:class:`contin_models.contact.barrier.ContactBarrier`) integrates
``W(d)`` along the meridian's contact cells, each the quadratic B-spline through three nodes, over the
pieces of each cell within ``dhat`` of the indenter.  In the 3-D view every angle ``theta`` of the
quadrature has its own meridian curve: the cell through the rings' material points at ``theta`` (the
pole's cell through the neighbour at ``theta`` and at ``theta + pi``, where the traced model mirrors the
neighbour), with all three components.  The barrier is that integral averaged over the angle::

    E = (1 / 2 pi) sum_q w_q [ a_0 W(d(P_0(theta_q))) + sum_cells a_i int_{pieces} W(d(X_i(t, theta_q))) dt ],

with the traced model's cell weights ``a_i``, Gauss rule per piece and pieces
(:func:`contin_models.contact.barrier.support_pieces`).  The distance is the 3-D one: ``c - X_z`` to a
plate at height ``c``, ``|X - (0, 0, c)| - rho`` to a sphere centred on the axis.  On an axisymmetric
state every angle sees the traced model's curve, so the term is the traced barrier (to rounding); its
derivatives are the pointwise ones at the same points (the integrand and its first derivative vanish at
the pieces' ends).  A ``D_n`` state's integrand has the state's symmetry (the indenters are
axisymmetric), so the view's quadrature on half a period serves.
"""

from __future__ import annotations

import math
import numpy as np
import scipy.sparse as sp

from contin_models.contact.barrier import CELL_MONOMIALS, ContactBarrier, Plate, barrier_jet, support_pieces

from .fourier import FourierShell

__all__ = ["Contact3D"]


class Contact3D:
    """The barrier between a :class:`~contin_models.shell.fourier.FourierShell` and a rigid indenter.

    Parameters
    ----------
    view : FourierShell
        The shell's 3-D view (its structure's meridian sets the contact cells).
    barrier : ContactBarrier
        The traced model's barrier (indenter, ``K``, ``dhat``, cell weights, Gauss rule per piece); it must
        integrate over the support (``support_points > 0`` and more than one fixed point per cell).
    """

    def __init__(self, view: FourierShell, barrier: ContactBarrier) -> None:
        if barrier.support_rule is None:
            raise ValueError("Contact3D: the barrier must integrate over its support (support_points > 0, "
                             "quadrature > 1)")
        self.view, self.barrier = view, barrier
        N = view.N
        self.cells = cells = barrier.cells(N)
        maps = view.basis.ring_maps()
        self._P, self._Q = maps["P"], maps["Q"]                      # (Q, 3, m)
        # the unknowns' map of each stencil point: the ring's P, or Q for the pole cell's mirrored neighbour
        self._mirror = cells.sign_r[:, 2] < 0                         # (N,)
        self.weights = view.basis.weights / (2.0 * math.pi)

    # ---- the points of the integral ------------------------------------------------------------------
    def _stencil_points(self, c: np.ndarray) -> np.ndarray:
        """``(Q, N, 3, 3)``: per angle and cell, its three stencil points' frame components."""
        view = self.view
        coef = np.asarray(c, dtype=float).reshape(view.N, view.m)
        P = np.einsum("qcj,ij->qic", self._P, coef)                  # (Q, N, 3)
        Qm = np.einsum("qcj,ij->qic", self._Q, coef)
        st = self.cells.stencil                                        # (N, 3)
        pts = P[:, st, :]                                              # (Q, N, 3 slots, 3 comps)
        if np.any(self._mirror):
            k = np.flatnonzero(self._mirror)
            pts[:, k, 2, :] = Qm[:, st[k, 2], :]
        return pts

    def points(self, c: np.ndarray, position: float) -> dict[str, np.ndarray]:
        """The integral's points at the state ``c`` and indenter position: angle index, cell, stencil
        coefficients ``(S, 3)``, weight (the angle's included) and coordinates ``(S, 3)``."""
        cells, barrier = self.cells, self.barrier
        pts = self._stencil_points(c)                                  # (Q, N, 3, 3)
        N = pts.shape[1]
        inner = np.arange(1, N)
        curves = np.einsum("kj,qijc->qick", CELL_MONOMIALS, pts[:, inner])  # (Q, N-1, 3 comps, 3 powers)
        flat = curves.reshape(-1, 3, 3)
        gap = barrier.gap_polynomial(flat[:, 0], flat[:, 2], float(position), T=flat[:, 1])
        rows, a, b = support_pieces(gap)
        xi, wq = barrier.support_rule
        t = (0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * xi).ravel()
        row = np.repeat(rows, xi.size)
        q, cell = np.divmod(row, N - 1)
        cell = cell + 1
        coef = np.stack([np.polynomial.polynomial.polyval(t, CELL_MONOMIALS[:, j]) for j in range(3)], axis=1)
        weight = (0.5 * (b - a)[:, None] * wq).ravel() * cells.cell_weight[cell] * self.weights[q]
        X = np.einsum("sj,sjc->sc", coef, pts[q, cell])
        # the base node's own term where it is within dhat
        base = pts[:, 0, 1, :]                                         # (Q, 3): node 0 at every angle
        d0 = self._distance(base, float(position))["d"]
        near = np.flatnonzero(d0 < barrier.dhat)
        q0 = near
        coef0 = np.tile([0.0, 1.0, 0.0], (near.size, 1))
        w0 = cells.weight[0] * self.weights[q0]
        return {"q": np.concatenate([q0, q]), "cell": np.concatenate([np.zeros(near.size, dtype=int), cell]),
                "coef": np.concatenate([coef0, coef]), "weight": np.concatenate([w0, weight]),
                "X": np.concatenate([base[near], X])}

    def _distance(self, X: np.ndarray, position: float) -> dict[str, np.ndarray]:
        """The distance ``d`` of the points ``X`` ``(S, 3)`` to the indenter at ``position`` and its derivatives:
        ``dX`` ``(S, 3)``, ``dXX`` ``(S, 3, 3)``, ``dc``, ``dcX`` ``(S, 3)``, ``dcc`` (``c`` the position)."""
        S = X.shape[0]
        if isinstance(self.barrier.indenter, Plate):
            dX = np.zeros_like(X)
            dX[:, 2] = -1.0
            return {"d": position - X[:, 2], "dX": dX, "dXX": np.zeros((S, 3, 3)), "dc": np.ones(S),
                    "dcX": np.zeros_like(X), "dcc": np.zeros(S)}
        D = X - np.array([0.0, 0.0, position])
        q = np.sqrt(np.sum(D * D, axis=1))
        dX = D / q[:, None]
        dcX = D * (D[:, 2] / q ** 3)[:, None]
        dcX[:, 2] -= 1.0 / q
        return {"d": q - self.barrier.indenter.radius, "dX": dX,
                "dXX": (np.eye(3)[None] - dX[:, :, None] * dX[:, None, :]) / q[:, None, None],
                "dc": -D[:, 2] / q, "dcX": dcX, "dcc": (q * q - D[:, 2] ** 2) / q ** 3}

    def _barrier(self, X: np.ndarray, position: float) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray,
                                                                np.ndarray]:
        """The distance's derivatives (:meth:`_distance`) and ``W``, ``W'``, ``W''`` at the points."""
        g = self._distance(X, position)
        if np.any(g["d"] <= 0):
            raise ValueError("Contact3D: a point of the barrier integral lies on or inside the indenter "
                             f"(d = {float(g['d'].min()):.6g} <= 0); the barrier is infinite there")
        return (g, *barrier_jet(g["d"], self.barrier.K, self.barrier.dhat))

    def _point_jets(self, X: np.ndarray, position: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``W``, its gradient ``(S, 3)`` and Hessian ``(S, 3, 3)`` in the points' coordinates."""
        g, W, W1, W2 = self._barrier(X, position)
        gd = g["dX"]
        return W, W1[:, None] * gd, W2[:, None, None] * gd[:, :, None] * gd[:, None, :] + W1[:, None, None] * g["dXX"]

    # ---- energy and derivatives in the view's unknowns ---------------------------------------------------
    def _maps(self, pts: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Each point's ``(3, 3 m)`` map from its cell's three rings' unknowns, and those rings' nodes."""
        view, cells = self.view, self.cells
        q, cell, coef = pts["q"], pts["cell"], pts["coef"]
        m = view.m
        S = q.size
        Bmap = np.zeros((S, 3, 3 * m))
        for j in range(3):
            ring = self._P[q]                                          # (S, 3, m)
            if j == 2:
                mirrored = self._mirror[cell]
                ring = np.where(mirrored[:, None, None], self._Q[q], ring)
            Bmap[:, :, j * m:(j + 1) * m] = coef[:, j, None, None] * ring
        return Bmap, cells.stencil[cell]

    def energy(self, c: np.ndarray, position: float) -> float:
        """The barrier's energy at the state ``c`` and the indenter position."""
        pts = self.points(c, position)
        if pts["q"].size == 0:
            return 0.0
        W, _, _ = self._point_jets(pts["X"], float(position))
        return float(np.sum(pts["weight"] * W))

    def gradient(self, c: np.ndarray, position: float) -> np.ndarray:
        """The barrier's gradient in the view's unknowns."""
        view = self.view
        g = np.zeros(view.size)
        pts = self.points(c, position)
        if pts["q"].size == 0:
            return g
        _, G, _ = self._point_jets(pts["X"], float(position))
        Bmap, nodes = self._maps(pts)
        ge = np.einsum("s,sc,sca->sa", pts["weight"], G, Bmap)
        np.add.at(g, view.element_dofs(nodes).ravel(), ge.ravel())
        return g

    def hessian(self, c: np.ndarray, position: float) -> sp.csr_matrix:
        """The barrier's Hessian in the view's unknowns, on the view's pattern (:meth:`FourierShell.pattern`)."""
        view = self.view
        P = view.pattern(False)
        data = np.zeros(P.nnz)
        pts = self.points(c, position)
        if pts["q"].size:
            _, _, H = self._point_jets(pts["X"], float(position))
            Bmap, nodes = self._maps(pts)
            He = np.einsum("s,sca,scd,sdb->sab", pts["weight"], Bmap, H, Bmap, optimize=True)
            data = np.bincount(view.hessian_slots(view.element_dofs(nodes), False, transient=True), He.ravel(),
                               minlength=P.nnz)
        return sp.csr_matrix((data, P.indices, P.indptr), shape=P.shape)

    def _position_jets(self, X: np.ndarray, position: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per point ``dW/dc``, ``d2W/dc dX`` ``(S, 3)`` and ``d2W/dc2`` (the indenter's position ``c``)."""
        g, _, W1, W2 = self._barrier(X, position)
        d_c = g["dc"]
        return W1 * d_c, (W2 * d_c)[:, None] * g["dX"] + W1[:, None] * g["dcX"], W2 * d_c * d_c + W1 * g["dcc"]

    def position_derivatives(self, c: np.ndarray, position: float) -> tuple[float, np.ndarray, float]:
        """``dE/dc``, ``d2E/dc du`` (in the view's unknowns) and ``d2E/dc2`` at the state ``c`` and the indenter
        position: the contact force is ``-dE/dc``."""
        view = self.view
        mixed = np.zeros(view.size)
        pts = self.points(c, position)
        if pts["q"].size == 0:
            return 0.0, mixed, 0.0
        Ec, EcX, Ecc = self._position_jets(pts["X"], float(position))
        w = pts["weight"]
        Bmap, nodes = self._maps(pts)
        np.add.at(mixed, view.element_dofs(nodes).ravel(), np.einsum("s,sc,sca->sa", w, EcX, Bmap).ravel())
        return float(w @ Ec), mixed, float(w @ Ecc)

    def max_safe_fraction(self, c: np.ndarray, position: float, dc: np.ndarray, dposition: float,
                          safety: float = 0.9) -> float:
        """The largest safe fraction of the step ``(dc, dposition)`` times ``safety``, or 1 when the whole step
        is safe: no fixed sample point of any cell, at any angle of the quadrature, reaches the indenter
        (:meth:`contin_models.contact.barrier.ContactBarrier.max_safe_fraction` in three dimensions: each point
        moves along a straight segment)."""
        X, V = self._samples(c), self._samples(np.asarray(dc, dtype=float))  # the points are linear in c
        if isinstance(self.barrier.indenter, Plate):
            gap = position - X[:, 2]
            closing = V[:, 2] - dposition
            hit = closing > 0
            s = np.full(X.shape[0], np.inf)
            s[hit] = gap[hit] / closing[hit]
        else:
            U = X - np.array([0.0, 0.0, position])
            V = V - np.array([0.0, 0.0, dposition])
            rho = self.barrier.indenter.radius
            c0 = np.sum(U * U, axis=1) - rho * rho
            b = np.sum(U * V, axis=1)
            a = np.sum(V * V, axis=1)
            disc = b * b - a * c0
            hit = (disc >= 0) & (b < 0)
            s = np.full(X.shape[0], np.inf)
            s[hit] = c0[hit] / (-b[hit] + np.sqrt(disc[hit]))
        first = float(np.min(s)) if s.size else np.inf
        return 1.0 if first > 1.0 else safety * max(first, 0.0)

    def _samples(self, c: np.ndarray) -> np.ndarray:
        """The fixed sample points of every cell at every angle, ``(Q (1 + (N-1) q), 3)``, linear in ``c``."""
        pts = self._stencil_points(c)                                  # (Q, N, 3, 3)
        inner = np.einsum("jk,qijc->qikc", self.cells.basis, pts[:, 1:])  # (Q, N-1, quadrature, 3)
        base = pts[:, 0, 1, :][:, None, :]
        return np.concatenate([base, inner.reshape(pts.shape[0], -1, 3)], axis=1).reshape(-1, 3)

    def __repr__(self) -> str:
        return f"Contact3D({self.barrier.indenter.name}, K={self.barrier.K}, dhat={self.barrier.dhat})"
