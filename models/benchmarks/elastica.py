"""Discrete Euler column: a planar elastica of rigid links and rotational springs, in compression.

A pinned-pinned column of length ``L`` buckles first in a mode symmetric about mid-span, where the
tangent is parallel to the axis.  Its half is a cantilever of length ``l = L / 2`` clamped at
mid-span and loaded at the pin, which we discretize: ``n`` rigid links of length ``h = l / n`` with
angles ``theta_i`` to the axis, joined by springs of stiffness ``EI / h``.  The half model is exactly
the symmetric half of a column of ``2 n`` links: the mid-span joint turns by ``2 theta_1``, and half
of its spring energy, ``EI / (2 h) * 2 theta_1^2``, belongs to each half.  With a compressive dead
load ``P`` at the free end:

    E(theta; P) = EI / (2 h) [2 theta_1^2 + sum_{i=2}^{n} (theta_i - theta_{i-1})^2] + P h sum_i cos(theta_i).

The Hessian is tridiagonal.  On the straight branch ``theta = 0`` it is ``(EI/h) K - P h I`` with
``K = tridiag(-1, 2, -1)`` except ``K_11 = 3`` and ``K_nn = 1``, so the discrete buckling load is
``P_1 = 4 EI / h^2 sin^2(pi / (4 n))``, which tends to ``pi^2 EI / (4 l^2) = pi^2 EI / L^2`` at second
order in ``1 / n``.
The buckled branch follows the elastica: ``sqrt(P / EI) l = K(sin^2(alpha / 2))`` (complete elliptic
integral with parameter m) with ``alpha`` the end rotation.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from contin import Problem

__all__ = ["EulerColumn"]


class EulerColumn(Problem):
    """Half of a pinned-pinned Euler column with ``n`` links; parameter ``P`` (compression)."""

    def __init__(self, n: int = 50, length: float = 1.0, EI: float = 1.0) -> None:
        if int(n) != n or n < 2:
            raise ValueError(f"EulerColumn: n = {n!r} must be an integer >= 2")
        if not (length > 0 and EI > 0):
            raise ValueError(f"EulerColumn: length and EI must be > 0 (got {length}, {EI})")
        self.n, self.L, self.EI = int(n), float(length), float(EI)
        self.h = 0.5 * self.L / self.n
        # residual terms are of size EI theta / h and P h theta: scale by EI / h
        super().__init__(symmetric=True, name=f"euler_column(n={n})", parameter_name="P",
                         residual_scale=self.EI / self.h)
        self._obs = {"end_rotation": lambda th, P: float(th[-1]),
                     "deflection": lambda th, P: float(self.h * np.sum(np.sin(th)))}

    @property
    def observables(self):
        return self._obs

    def _stiffness(self) -> sp.dia_matrix:
        main = np.full(self.n, 2.0)
        main[0] = 3.0
        main[-1] = 1.0
        off = np.full(self.n, -1.0)
        return sp.dia_matrix((np.vstack([off, main, off]) * (self.EI / self.h), [-1, 0, 1]),
                             shape=(self.n, self.n))

    def energy(self, th, P):
        d = np.diff(th)
        bending = 2 * th[0] ** 2 + np.sum(d ** 2)
        return float(self.EI / (2 * self.h) * bending + P * self.h * np.sum(np.cos(th)))

    def residual(self, th, P):
        return self._stiffness() @ th - P * self.h * np.sin(th)

    def jacobian(self, th, P):
        K = self._stiffness()
        K.data[1] -= P * self.h * np.cos(th)
        return K

    def dresidual_dp(self, th, P):
        return -self.h * np.sin(th)

    def buckling_load_closed_form(self) -> float:
        """First buckling load of this discrete column (closed form of the tridiagonal eigenproblem)."""
        return 4 * self.EI / self.h ** 2 * np.sin(np.pi / (4 * self.n)) ** 2

    def euler_load(self) -> float:
        """Continuum Euler load ``pi^2 EI / L^2``."""
        return np.pi ** 2 * self.EI / self.L ** 2
