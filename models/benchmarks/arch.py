"""Shallow circular arch of bars and hinge springs under a central dead load (snap and bifurcation).

Geometry: ``n`` (even) straight bars of equal length ``l`` with their nodes on a circular arc of
chord ``span`` and ``rise``; both supports pinned.  Each bar is an axial spring of stiffness
``EA / l``; each interior node is a hinge with a rotational spring ``EI / l`` resisting the change of
the angle between its two bars (the discrete form of bending stiffness ``EI``).  The radius of
gyration ``r = sqrt(EI / EA)`` is set by the rise parameter ``rise / r`` (default 10).  A vertical
dead load ``P`` (positive downwards) acts at the crown node.  Unknowns: the displacements
``(u_x, u_y)`` of the ``n - 1`` interior nodes, node by node, so the Hessian is banded (bandwidth 5).

Energy, with ``d_i`` the deformed bar vectors, ``l_i = |d_i|``, ``theta_i`` their angles and
``beta_k`` the stress-free hinge angles:

    E = sum_i EA / (2 l) (l_i - l)^2 + sum_{k=1}^{n-1} EI / (2 l) (theta_k - theta_{k-1} - beta_k)^2 + P u_y(crown).

Gradient, Hessian (sparse, assembled from 4 x 4 bar blocks and 6 x 6 hinge blocks), ``df/dP`` and
the energy are written out exactly.

Comparison with theory.  Marguerre's shallow-arch theory predicts, for a pinned shallow arch under a
central point load, a symmetric limit (snap) load and an asymmetric bifurcation load that depend on
the rise parameter ``rise / r``; for a large enough rise the asymmetric bifurcation comes first on
the symmetric path.  We did not find a closed form for the *circular* pinned arch under a *central
point* load that we could check within this work (the classical closed forms, e.g. Fung and Kaplan,
NACA TN 2840 (1952), and Gjelsvik and Bodner, J. Eng. Mech. Div. ASCE 88 (1962), are for the
half-sine arch or for Fourier-truncated models), so the tests compare instead with an independent
dense check: at every located branch point the dense Hessian (from the energy's own formula, not the
sparse assembly) has an eigenvalue at roundoff level whose eigenvector is antisymmetric about the
crown, and the located loads agree across arclength weights.  With ``n = 20`` and ``rise / r = 10``
the symmetric path has four branch points (two before and two after its limit points).
The loads themselves are compared with Marguerre's shallow-arch theory, solved in sine modes by
:class:`contin_models.benchmarks.marguerre.MarguerreArch` (``studies/arch_marguerre.py``,
``tests/test_arch_marguerre.py``); ``shape="sine"`` builds the half-sine arch of that literature.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from contin import Problem

__all__ = ["ShallowArch"]


class ShallowArch(Problem):
    """Pinned shallow circular arch of ``n`` bars with hinge springs; parameter ``P`` (central dead load).

    Parameters
    ----------
    n : int
        Number of bars (even, >= 4): the load acts at the crown node ``n / 2``.
    span, rise : float
        Chord and rise of the circular arc through the nodes.
    EI : float
        Bending stiffness; each hinge spring is ``EI / l``.
    rise_over_gyration : float
        ``rise / r`` with ``r = sqrt(EI / EA)``: sets ``EA = EI (rise_over_gyration / rise)^2``.
    shape : {"circle", "sine"}
        ``circle`` (default): nodes at equal angles on the circular arc, all bars of one length.
        ``sine``: nodes at equally spaced ``x_j`` with ``y_j = rise sin(pi x_j / span)`` (the half-sine
        arch of the classical shallow-arch literature, see :mod:`contin_models.benchmarks.marguerre`);
        its bars differ slightly in length, each axial spring is ``EA / l_i`` with its own rest length
        and each hinge ``EI / l_k`` with ``l_k`` the mean of its two bars.
    """

    def __init__(self, n: int = 20, span: float = 1.0, rise: float = 0.05, EI: float = 1.0,
                 rise_over_gyration: float = 10.0, shape: str = "circle") -> None:
        if int(n) != n or n < 4 or n % 2:
            raise ValueError(f"ShallowArch: n = {n!r} must be an even integer >= 4")
        if not (span > 0 and 0 < rise < 0.5 * span and EI > 0 and rise_over_gyration > 0):
            raise ValueError("ShallowArch: need span > 0, 0 < rise < span / 2, EI > 0, rise_over_gyration > 0")
        self.n, self.span, self.rise, self.EI = int(n), float(span), float(rise), float(EI)
        self.EA = self.EI * (rise_over_gyration / self.rise) ** 2
        self.shape = shape
        if shape == "circle":
            R = (0.25 * span ** 2 + rise ** 2) / (2 * rise)
            half = np.arcsin(0.5 * span / R)
            phi = np.linspace(-half, half, self.n + 1)
            self.X0 = np.column_stack([R * np.sin(phi), R * np.cos(phi) - (R - rise)])
            self.l = float(np.linalg.norm(self.X0[1] - self.X0[0]))
            # one bar length: keep the springs scalar, so the circular arch is exactly what it was
            self.rest = self.l
            self.k_axial, self.k_hinge = self.EA / self.l, self.EI / self.l
        elif shape == "sine":
            x = np.linspace(-0.5 * span, 0.5 * span, self.n + 1)
            self.X0 = np.column_stack([x, rise * np.cos(np.pi * x / span)])
            self.rest = np.linalg.norm(np.diff(self.X0, axis=0), axis=1)
            self.l = float(np.mean(self.rest))
            self.k_axial = self.EA / self.rest
            self.k_hinge = self.EI / (0.5 * (self.rest[:-1] + self.rest[1:]))
        else:
            raise ValueError(f"ShallowArch: shape {shape!r} is not 'circle' or 'sine'")
        self.beta = np.diff(self._angles(self.X0))
        self.crown = 2 * (self.n // 2 - 1) + 1  # index of the crown's u_y among the unknowns
        super().__init__(symmetric=True, name=f"shallow_arch(n={n})", parameter_name="P",
                         residual_scale=self.EI / self.l ** 2)
        q = self.n // 4
        self._obs = {
            "deflection": lambda u, P: float(-u[self.crown]),
            # antisymmetric part of the vertical displacement at the quarter points: zero on the symmetric path
            "asymmetry": lambda u, P: float(self._uy(u)[q] - self._uy(u)[self.n - q]),
        }

    @property
    def observables(self):
        return self._obs

    # ---- kinematics ------------------------------------------------------------------------------
    def _nodes(self, u: np.ndarray) -> np.ndarray:
        X = self.X0.copy()
        X[1:-1] += np.asarray(u, dtype=float).reshape(-1, 2)
        return X

    def _uy(self, u: np.ndarray) -> np.ndarray:
        """Vertical displacement of every node, supports included."""
        return np.concatenate([[0.0], np.asarray(u).reshape(-1, 2)[:, 1], [0.0]])

    @staticmethod
    def _angles(X: np.ndarray) -> np.ndarray:
        d = np.diff(X, axis=0)
        return np.arctan2(d[:, 1], d[:, 0])

    def _bars(self, u: np.ndarray):
        """Bar vectors, lengths, angles and the hinge moments ``m_k`` (k = 1..n-1)."""
        X = self._nodes(u)
        d = np.diff(X, axis=0)
        length = np.hypot(d[:, 0], d[:, 1])
        theta = np.arctan2(d[:, 1], d[:, 0])
        # hinge rotation relative to the stress-free angle, wrapped to (-pi, pi]
        rot = np.angle(np.exp(1j * (np.diff(theta) - self.beta)))
        return d, length, theta, self.k_hinge * rot, rot

    # ---- the interface ---------------------------------------------------------------------------
    def energy(self, u, P):
        _, length, _, _, rot = self._bars(u)
        return float(0.5 * np.sum(self.k_axial * (length - self.rest) ** 2) + 0.5 * np.sum(self.k_hinge * rot ** 2)
                     + P * u[self.crown])

    def _bar_gradients(self, d: np.ndarray, length: np.ndarray, m: np.ndarray):
        """Per bar: the derivative of the energy with respect to ``d_i`` (axial plus hinge parts)."""
        axial = (self.k_axial * (length - self.rest) / length)[:, None] * d
        g_theta = np.column_stack([-d[:, 1], d[:, 0]]) / (length ** 2)[:, None]
        # dE/dtheta_i = m_i - m_{i+1} (hinge i at the bar's start, hinge i + 1 at its end; none at supports)
        mm = np.concatenate([[0.0], m, [0.0]])
        c = mm[:-1] - mm[1:]
        return axial + c[:, None] * g_theta, g_theta, c

    def residual(self, u, P):
        d, length, _, m, _ = self._bars(u)
        g_bar, _, _ = self._bar_gradients(d, length, m)
        G = np.zeros((self.n + 1, 2))
        G[1:] += g_bar
        G[:-1] -= g_bar
        r = G[1:-1].ravel()
        r[self.crown] += P
        return r

    def dresidual_dp(self, u, P):
        e = np.zeros(2 * (self.n - 1))
        e[self.crown] = 1.0
        return e

    def jacobian(self, u, P):
        n = self.n
        d, length, _, m, _ = self._bars(u)
        _, g_theta, c = self._bar_gradients(d, length, m)
        dx, dy, l2 = d[:, 0], d[:, 1], length ** 2
        # bar blocks in d: axial stiffness plus the hinge moments times the angle's Hessian
        nn = np.einsum("ia,ib->iab", d, d) / l2[:, None, None]
        k_axial = np.broadcast_to(self.k_axial, (n,))[:, None, None]
        H = k_axial * (nn + ((length - self.rest) / length)[:, None, None] * (np.eye(2) - nn))
        H_theta = np.empty((n, 2, 2))
        H_theta[:, 0, 0] = 2 * dx * dy
        H_theta[:, 1, 1] = -2 * dx * dy
        H_theta[:, 0, 1] = H_theta[:, 1, 0] = dy ** 2 - dx ** 2
        H += c[:, None, None] * H_theta / (l2 ** 2)[:, None, None]
        # the bar's d is (end node - start node): its block on the two nodes is [[H, -H], [-H, H]]
        bar = np.concatenate([np.concatenate([H, -H], axis=2), np.concatenate([-H, H], axis=2)], axis=1)
        bar_dofs = 2 * np.arange(n)[:, None] + np.arange(4)[None, :]
        # hinge blocks: k_s G G^T with G the gradient of the hinge rotation on nodes k-1, k, k+1
        gl, gr = g_theta[:-1], g_theta[1:]
        G = np.concatenate([gl, -gl - gr, gr], axis=1)
        hinge = np.broadcast_to(self.k_hinge, (n - 1,))[:, None, None] * np.einsum("ia,ib->iab", G, G)
        hinge_dofs = 2 * np.arange(n - 1)[:, None] + np.arange(6)[None, :]
        rows = np.concatenate([np.repeat(bar_dofs, 4, axis=1).ravel(), np.repeat(hinge_dofs, 6, axis=1).ravel()])
        cols = np.concatenate([np.tile(bar_dofs, (1, 4)).ravel(), np.tile(hinge_dofs, (1, 6)).ravel()])
        vals = np.concatenate([bar.ravel(), hinge.ravel()])
        N = 2 * (n + 1)
        K = sp.coo_matrix((vals, (rows, cols)), shape=(N, N)).tocsr()
        return K[2:-2, 2:-2]
