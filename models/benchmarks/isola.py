"""A two-dof gradient system whose equilibria include an isola: a closed branch no other branch meets.

In coordinates turned by an angle ``angle`` against the state's axes, ``xi = c u1 + s u2`` and
``eta = -s u1 + c u2`` (``c, s = cos angle, sin angle``), the energy is

    E(u, p) = V(xi, p) + eta^2 / 2,
    V(xi, p) = xi^4 / 4 - 2 a xi^3 / 3 + (a^2 + (p - b)^2 - rho^2) xi^2 / 2,

so that ``dV/dxi = xi ((xi - a)^2 + (p - b)^2 - rho^2)``.  The equilibria are ``eta = 0`` and either
``xi = 0`` (the trivial branch, for every ``p``) or the circle ``(xi - a)^2 + (p - b)^2 = rho^2``
(the isola).  On the circle ``d2V/dxi2 = 2 xi (xi - a)``: its outer half (``xi > a``) is stable, its
inner half unstable, with folds at ``p = b +- rho`` (``xi = a``).  On the trivial branch
``d2V/dxi2 = a^2 + (p - b)^2 - rho^2``, positive for every ``p`` when ``a > rho``: no branch point
there, and no path from it reaches the circle.  The turn makes the Jacobian a full 2 x 2 matrix.
"""

from __future__ import annotations

import math

import numpy as np

from contin import Problem

__all__ = ["Isola"]


class Isola(Problem):
    """An isola ``(xi - a)^2 + (p - b)^2 = rho^2`` beside the trivial branch ``u = 0`` (``a > rho``)."""

    def __init__(self, a: float = 2.0, b: float = 0.5, rho: float = 1.0, angle: float = 0.5) -> None:
        if not (a > rho > 0):
            raise ValueError(f"Isola: need a > rho > 0 (the circle apart from xi = 0), got a = {a!r}, rho = {rho!r}")
        super().__init__(symmetric=True, name="isola", parameter_name="p")
        self.a, self.b, self.rho = float(a), float(b), float(rho)
        self.c, self.s = math.cos(angle), math.sin(angle)
        self._obs = {"xi": lambda u, p: float(self.xi(u))}

    @property
    def observables(self):
        return self._obs

    def xi(self, u: np.ndarray) -> float:
        """The amplitude ``xi`` of a state."""
        return float(self.c * u[0] + self.s * u[1])

    def state(self, xi: float, eta: float = 0.0) -> np.ndarray:
        """The state with amplitudes ``(xi, eta)``."""
        return np.array([self.c * xi - self.s * eta, self.s * xi + self.c * eta])

    def isola_amplitudes(self, p: float) -> tuple[float, ...]:
        """The ``xi`` of the isola's points at ``p`` (closed form): none, one at a fold, or two."""
        gap = self.rho ** 2 - (p - self.b) ** 2
        if gap < 0:
            return ()
        return (self.a,) if gap == 0 else (self.a - math.sqrt(gap), self.a + math.sqrt(gap))

    def _split(self, u: np.ndarray) -> tuple[float, float]:
        return self.c * u[0] + self.s * u[1], -self.s * u[0] + self.c * u[1]

    def energy(self, u, p):
        xi, eta = self._split(u)
        k = self.a ** 2 + (p - self.b) ** 2 - self.rho ** 2
        return float(xi ** 4 / 4 - 2 * self.a * xi ** 3 / 3 + k * xi ** 2 / 2 + eta ** 2 / 2)

    def residual(self, u, p):
        xi, eta = self._split(u)
        dV = xi * ((xi - self.a) ** 2 + (p - self.b) ** 2 - self.rho ** 2)
        return self.state(dV, eta)

    def jacobian(self, u, p):
        xi, _ = self._split(u)
        d2V = 3 * xi ** 2 - 4 * self.a * xi + self.a ** 2 + (p - self.b) ** 2 - self.rho ** 2
        c, s = self.c, self.s
        # R^T diag(d2V, 1) R with R the turn (xi, eta) <- u
        return np.array([[c * c * d2V + s * s, c * s * (d2V - 1.0)],
                         [c * s * (d2V - 1.0), s * s * d2V + c * c]])

    def dresidual_dp(self, u, p):
        xi, _ = self._split(u)
        return self.state(2.0 * (p - self.b) * xi, 0.0)
