"""The engine's step filter (``Problem.max_step_fraction``): a model defined only on part of space.

A spring pulled by the load ``p`` pushes ``u0`` towards negative values; a log barrier (docs/model.md#contact,
eq. 3.16 in one dimension) keeps ``u0 > 0`` and is undefined beyond.  With the filter no residual
is ever evaluated at ``u0 <= 0``; without it the same runs do evaluate there (so the tests can fail).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import contin
from contin.palc import Curve

K, DHAT, SPRING = 1.0, 0.2, 10.0


class Wall(contin.Problem):
    def __init__(self, filtered: bool = True) -> None:
        super().__init__(symmetric=True, name="wall")
        self.filtered = filtered
        self.evaluated: list[float] = []

    @staticmethod
    def barrier(x: float) -> tuple[float, float, float]:
        if x >= DHAT:
            return 0.0, 0.0, 0.0
        if x <= 0:
            return math.nan, math.nan, math.nan
        L = math.log(x / DHAT)
        return (-K * (x - DHAT) ** 2 * L, -K * (2 * (x - DHAT) * L + (x - DHAT) ** 2 / x),
                -K * (2 * L + 4 * (x - DHAT) / x - (x - DHAT) ** 2 / x ** 2))

    def energy(self, u, p):
        return 0.5 * SPRING * (u[0] - (1 - p)) ** 2 + 0.5 * (u[1] - u[0]) ** 2 + self.barrier(u[0])[0]

    def residual(self, u, p):
        self.evaluated.append(float(u[0]))
        return np.array([SPRING * (u[0] - (1 - p)) - (u[1] - u[0]) + self.barrier(u[0])[1], u[1] - u[0]])

    def jacobian(self, u, p):
        return np.array([[SPRING + 1 + self.barrier(u[0])[2], -1.0], [-1.0, 1.0]])

    def dresidual_dp(self, u, p):
        return np.array([SPRING, 0.0])

    def max_step_fraction(self, u, p, du, dp):
        if not self.filtered or du[0] >= 0:
            return 1.0
        t = -u[0] / du[0]  # where u0 would reach the wall
        return 1.0 if t > 1.0 else 0.9 * t


def equilibrium_u0(p: float) -> float:
    """Closed form check: SPRING (u0 - (1 - p)) + W'(u0) = 0 by bisection on (0, 1 - p] or (0, DHAT)."""
    f = lambda x: SPRING * (x - (1 - p)) + Wall.barrier(x)[1]  # noqa: E731
    lo, hi = 1e-300, max(1 - p, DHAT) + 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("filtered", [True, False])
def test_continuation_never_evaluates_outside_the_domain(filtered):
    P = Wall(filtered)
    br = contin.continuation(P, np.array([1.0, 1.0]), 0.0, ds=0.8, ds_max=2.0, p_max=3.0, max_steps=100)
    assert br.status == "bound" and br.p[-1] == pytest.approx(3.0)
    crossings = sum(1 for x in P.evaluated if x <= 0)
    if filtered:
        assert crossings == 0
        assert br.u[-1][0] == pytest.approx(equilibrium_u0(3.0), rel=1e-8)
    else:
        assert crossings > 0  # the unfiltered run probes beyond the wall


@pytest.mark.parametrize("filtered", [True, False])
def test_newton_at_fixed_load_is_damped_to_the_domain(filtered):
    P = Wall(filtered)
    curve = Curve(P, contin.Settings())
    # far from the wall, a full Newton step on the spring alone would overshoot deep into u0 < 0
    u, res, _ = curve.newton_fixed_p(np.array([1.0, 1.0]), 2.5)
    assert u[0] == pytest.approx(equilibrium_u0(2.5), rel=1e-8)
    # unfiltered, the damped Newton still gets there, but only after probing beyond the wall
    assert (min(P.evaluated) > 0) == filtered
