"""The 1-D Bratu problem ``u'' + lam exp(u) = 0`` on (0, 1), ``u(0) = u(1) = 0``.

Second-order central differences on ``n`` interior points (``h = 1 / (n + 1)``).  The discrete
problem is the gradient of the energy

    E(u, lam) = sum_{i=0}^{n} (u_{i+1} - u_i)^2 / (2 h) - lam h sum_{i=1}^{n} exp(u_i),

so the residual is ``-h (u'' + lam exp(u))`` in finite differences and the Jacobian is the symmetric
tridiagonal Hessian.  The branch from ``lam = 0`` has a fold at ``lam ~= 3.513830719`` (continuum
value) and continues on the upper, unstable branch where ``max(u)`` grows without bound as
``lam -> 0``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from contin import Problem

__all__ = ["Bratu", "LAMBDA_CRITICAL", "continuum_solution"]

#: Fold of the continuum problem, lam_c = max over theta of theta^2 / (2 cosh(theta/4)^2).
LAMBDA_CRITICAL = 3.513830719125162


class Bratu(Problem):
    """Finite-difference Bratu problem with ``n`` interior points; the parameter is ``lam``."""

    def __init__(self, n: int = 200) -> None:
        if int(n) != n or n < 2:
            raise ValueError(f"Bratu: n = {n!r} must be an integer >= 2")
        # the residual's terms are of size |u| / h: tolerances are relative to 1 / h
        super().__init__(symmetric=True, name=f"bratu(n={n})", parameter_name="lam",
                         residual_scale=float(n + 1))
        self.n = int(n)
        self.h = 1.0 / (n + 1)
        self.x = np.linspace(self.h, 1 - self.h, self.n)
        self._obs = {"max_u": lambda u, lam: float(np.max(u)),
                     "u_mid": lambda u, lam: float(np.interp(0.5, self.x, u))}

    @property
    def observables(self):
        return self._obs

    def _laplacian_times(self, u: np.ndarray) -> np.ndarray:
        out = -2.0 * u
        out[1:] += u[:-1]
        out[:-1] += u[1:]
        return out

    def residual(self, u, lam):
        return -self._laplacian_times(u) / self.h - lam * self.h * np.exp(u)

    def jacobian(self, u, lam):
        n, h = self.n, self.h
        main = 2.0 / h - lam * h * np.exp(u)
        off = np.full(n, -1.0 / h)
        return sp.dia_matrix((np.vstack([off, main, off]), [-1, 0, 1]), shape=(n, n))

    def dresidual_dp(self, u, lam):
        return -self.h * np.exp(u)

    def energy(self, u, lam):
        du = np.diff(np.concatenate([[0.0], u, [0.0]]))
        return float(np.sum(du ** 2) / (2 * self.h) - lam * self.h * np.sum(np.exp(u)))

    def jacobian_directional_derivative(self, u, lam, v):
        return sp.diags(-lam * self.h * np.exp(u) * v)

    def jacobian_dp(self, u, lam):
        return sp.diags(-self.h * np.exp(u))


def continuum_solution(x: np.ndarray, theta: float) -> np.ndarray:
    """Exact continuum solution ``u = -2 log(cosh((x - 1/2) theta / 2) / cosh(theta / 4))``.

    It solves the continuum problem with ``lam = theta^2 / (2 cosh(theta / 4)^2)``.
    """
    return -2.0 * np.log(np.cosh((x - 0.5) * theta / 2) / np.cosh(theta / 4))
