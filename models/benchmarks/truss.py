"""Two-bar von Mises truss under a vertical dead load at the apex (force control).

Two elastic bars of axial stiffness ``k`` join the supports ``(-a, 0)`` and ``(a, 0)`` to the apex
``(x, y)``, initially at ``(0, b)``.  A downward load ``P`` acts on the apex.  The energy is

    E(x, y; P) = sum_bars k/2 (L_i - L0)^2 + P y,      L0 = sqrt(a^2 + b^2),

and its Hessian is the 2 x 2 stiffness matrix (unknowns ``u = (x, y)``, parameter ``P``).

Closed form on the symmetric path ``x = 0``:  ``P(y) = 2 k y (L0 / L - 1)`` with ``L = sqrt(a^2 + y^2)``.
Its limit points satisfy ``L^3 = L0 a^2``, so ``P_max = 2 k y* (L0 / L* - 1)``, ``y* = sqrt(L*^2 - a^2)``
and ``P_min = -P_max`` at ``-y*``.  Between them the path is unstable with one negative eigenvalue.
For ``b / a < 2.4`` the sway stiffness ``2 k (1 - y^2 L0 / L^3)`` stays positive, so the symmetric
path has no branch point and the S-curve is the whole story.
"""

from __future__ import annotations

import math

import numpy as np

from contin import Problem

__all__ = ["VonMisesTruss", "TrussDisplacementControl"]


class VonMisesTruss(Problem):
    """Shallow two-bar truss; state ``u = (x, y)`` of the apex, parameter ``P`` (downward load)."""

    def __init__(self, a: float = 1.0, b: float = 0.5, k: float = 1.0) -> None:
        if not (a > 0 and b > 0 and k > 0):
            raise ValueError(f"VonMisesTruss: a, b, k must be > 0 (got a={a}, b={b}, k={k})")
        super().__init__(symmetric=True, name="von_mises_truss", parameter_name="P")
        self.a, self.b, self.k = float(a), float(b), float(k)
        self.L0 = math.hypot(a, b)
        self._obs = {"y": lambda u, P: float(u[1]), "x": lambda u, P: float(u[0]),
                     "deflection": lambda u, P: float(self.b - u[1])}

    @property
    def observables(self):
        return self._obs

    def _bars(self, u):
        x, y = u
        return [np.array([x + self.a, y]), np.array([x - self.a, y])]

    def energy(self, u, P):
        return float(sum(0.5 * self.k * (np.linalg.norm(d) - self.L0) ** 2 for d in self._bars(u)) + P * u[1])

    def residual(self, u, P):
        g = np.array([0.0, P])
        for d in self._bars(u):
            L = np.linalg.norm(d)
            g += self.k * (L - self.L0) * d / L
        return g

    def jacobian(self, u, P):
        H = np.zeros((2, 2))
        for d in self._bars(u):
            L = np.linalg.norm(d)
            dd = np.outer(d, d) / L ** 2
            H += self.k * (dd + (1 - self.L0 / L) * (np.eye(2) - dd))
        return H

    def dresidual_dp(self, u, P):
        return np.array([0.0, 1.0])

    # ---- closed form ---------------------------------------------------------------------------
    def load_on_symmetric_path(self, y: np.ndarray | float) -> np.ndarray | float:
        """``P(y)`` on the symmetric equilibrium path."""
        L = np.sqrt(self.a ** 2 + np.asarray(y) ** 2)
        return 2 * self.k * np.asarray(y) * (self.L0 / L - 1)

    def limit_points(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """``((y_upper, P_max), (y_lower, P_min))`` in closed form."""
        L_star = (self.L0 * self.a ** 2) ** (1.0 / 3.0)
        y_star = math.sqrt(L_star ** 2 - self.a ** 2)
        P_max = 2 * self.k * y_star * (self.L0 / L_star - 1)
        return (y_star, P_max), (-y_star, -P_max)

    def eigenvalues_on_symmetric_path(self, y: float) -> np.ndarray:
        """Closed-form eigenvalues of the Hessian at ``(0, y)`` (the matrix is diagonal there)."""
        L2 = self.a ** 2 + y ** 2
        c = 1 - self.L0 / math.sqrt(L2)
        return np.sort(2 * self.k * np.array([(self.a ** 2 + c * y ** 2) / L2, (y ** 2 + c * self.a ** 2) / L2]))


class TrussDisplacementControl(Problem):
    """The same truss with the apex height ``y`` prescribed (parameter) and ``x`` free.

    The reaction force ``P = -dE_elastic/dy`` is the observable ``"P"``; its maximum along this
    path is the force-controlled fold ``P_max`` of :class:`VonMisesTruss`.
    """

    def __init__(self, a: float = 1.0, b: float = 0.5, k: float = 1.0) -> None:
        super().__init__(symmetric=True, name="von_mises_truss_displacement", parameter_name="y")
        self.truss = VonMisesTruss(a, b, k)
        self._obs = {"P": lambda u, y: float(-self.truss.residual(np.array([u[0], y]), 0.0)[1])}

    @property
    def observables(self):
        return self._obs

    def energy(self, u, y):
        return self.truss.energy(np.array([u[0], y]), 0.0)

    def residual(self, u, y):
        return self.truss.residual(np.array([u[0], y]), 0.0)[:1]

    def jacobian(self, u, y):
        return self.truss.jacobian(np.array([u[0], y]), 0.0)[:1, :1]

    def dresidual_dp(self, u, y):
        return self.truss.jacobian(np.array([u[0], y]), 0.0)[:1, 1]


def trace_scene():
    """Command-line scene of the truss (see :mod:`contin_models.benchmarks.scenes`)."""
    from .scenes import TRUSS_SCENE
    return TRUSS_SCENE
