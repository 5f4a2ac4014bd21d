"""Pitchfork normal form as a gradient system.

``E(u, p) = -p u1^2 / 2 + u1^4 / 4 + u2^2 / 2`` with residual ``(-p u1 + u1^3, u2)``.  The trivial
branch ``u = 0`` is stable for ``p < 0`` and has one negative eigenvalue for ``p > 0``; at ``p = 0``
a supercritical pitchfork sends off the stable branches ``u1 = +-sqrt(p)``.  The decoupled ``u2``
makes the system two-dimensional so that the null space is a proper subspace.
"""

from __future__ import annotations

import numpy as np

from contin import Problem

__all__ = ["Pitchfork"]


class Pitchfork(Problem):
    """Normal form of a supercritical pitchfork at ``p = 0``; state ``(u1, u2)``."""

    def __init__(self) -> None:
        super().__init__(symmetric=True, name="pitchfork", parameter_name="p")
        self._obs = {"u1": lambda u, p: float(u[0])}

    @property
    def observables(self):
        return self._obs

    def energy(self, u, p):
        return float(-p * u[0] ** 2 / 2 + u[0] ** 4 / 4 + u[1] ** 2 / 2)

    def residual(self, u, p):
        return np.array([-p * u[0] + u[0] ** 3, u[1]])

    def jacobian(self, u, p):
        return np.array([[-p + 3 * u[0] ** 2, 0.0], [0.0, 1.0]])

    def dresidual_dp(self, u, p):
        return np.array([-u[0], 0.0])
