"""Landings of a snap (``contin.quasistatic``, ``contin.leave_fold``): close to the fold but distinct, and not.

The von Mises truss of ``tests/test_quasistatic.py``: two bars of stiffness k from ``(-a, 0)`` and
``(a, 0)`` to the apex ``(0, y)`` under a downward dead load P.  On the symmetric path
``P(y) = 2 k y (L0 / L - 1)``, ``L = sqrt(a^2 + y^2)``, with the limit point ``P_max`` where
``L^3 = L0 a^2``.  Reference states come from these formulas, never from the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from contin import Problem, SpecialPoint, jump, quasistatic
from contin.analyses.quasistatic import SnapRules, leave_fold
from contin_models.benchmarks.truss import VonMisesTruss

A, B, K = 1.0, 0.5, 1.0
L0 = math.hypot(A, B)
KW = dict(ds=0.02, ds_max=0.05)


def limit_point() -> tuple[float, float]:
    """``(y*, P_max)`` from ``L*^3 = L0 a^2``."""
    L = (L0 * A * A) ** (1 / 3)
    y = math.sqrt(L * L - A * A)
    return y, 2 * K * y * (L0 / L - 1)


Y_STAR, P_MAX = limit_point()


def P_of_y(y: float) -> float:
    return 2 * K * y * (L0 / math.hypot(A, y) - 1)


def y_upper(P: float) -> float:
    """The state on the upper stable branch (``y > y*``) at load ``P < P_max``."""
    return brentq(lambda y: P_of_y(y) - P, Y_STAR + 1e-12, 50.0, xtol=1e-15)


def y_lower(P: float) -> float:
    """The state on the inverted stable branch (``y < -y*``) at load ``P``."""
    return brentq(lambda y: P_of_y(y) - P, -50.0, -Y_STAR - 1e-12, xtol=1e-15)


def test_a_distinct_stable_state_closer_than_min_separation_is_a_landing() -> None:
    # the snap moves the apex by |y_lower - y*| ~ 0.9, far below the threshold: only the check that the
    # landing stays on a stable branch of its own when carried back to the fold's load can accept it
    # (a thin shell's snap moves its pole by a fraction of the thickness, below the shell's threshold)
    res = quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 1.5 * P_MAX, min_separation=100.0, **KW)
    assert res.status == "completed", res.message
    assert len(res.jumps) == 1
    jr = res.jumps[0]
    assert jr.info["restated"] and jr.p == pytest.approx(P_MAX, rel=1e-9)
    assert jr.u_to[1] == pytest.approx(y_lower(P_MAX), rel=1e-8)


def test_a_landing_on_the_folds_own_branch_is_refused() -> None:
    # a "fold" reported below the true limit load: the minimisation a hair past it still finds the
    # upper branch it came from, a stable equilibrium right next to the start; carried back to the
    # reported load it falls onto the start itself, so it is not a snap
    P_f = P_MAX * (1.0 - 1e-3)
    u_f = np.array([0.0, y_upper(P_f)])
    fold = SpecialPoint("fold", P_f, u_f, {}, residual=0.0, located=True)
    rules = SnapRules(attempts=((1e-6, None), (1e-5, None)), min_separation=100.0)
    jr, reasons = leave_fold(VonMisesTruss(A, B, K), fold, +1, rules=rules)
    assert jr is None
    assert len(reasons) == 2 and all("landed back next to the fold" in r for r in reasons), reasons
    assert all("falls back towards the fold" in r for r in reasons), reasons


# ---- a descent along a bent valley -------------------------------------------------------------------
#: Stiffness across the valley y = x^2 (a thin shell's membrane) and the soft energy along it.
VALLEY_STIFFNESS = 1e6


def bent_valley() -> Problem:
    """``E = (x^4/4 - x^2/2) + K/2 (y - x^2)^2 - p x``: a maximum of the soft part at the origin,
    minima near ``x = +-1`` on the parabola ``y = x^2``, which a stiff ``K`` makes a narrow bent valley."""
    K = VALLEY_STIFFNESS

    def energy(u: np.ndarray, p: float) -> float:
        x, y = u
        return x ** 4 / 4 - x ** 2 / 2 + K / 2 * (y - x * x) ** 2 - p * x

    def residual(u: np.ndarray, p: float) -> np.ndarray:
        x, y = u
        return np.array([x ** 3 - x - 2 * K * x * (y - x * x) - p, K * (y - x * x)])

    def jacobian(u: np.ndarray, p: float) -> np.ndarray:
        x, y = u
        return np.array([[3 * x * x - 1 - 2 * K * y + 6 * K * x * x, -2 * K * x], [-2 * K * x, K]])

    return Problem(residual=residual, jacobian=jacobian, dresidual_dp=lambda u, p: np.array([-1.0, 0.0]),
                   energy=energy, symmetric=True, name="bent valley")


def test_the_descent_follows_a_bent_valley() -> None:
    # from the saddle at the origin the valley floor y = x^2 bends away from the straight unstable
    # direction (the x axis): a straight kick of 1e-3 climbs K/2 (1e-3)^4 = 5e-7 up its wall, as much as
    # the soft part gives, and larger ones climb more; the kick and the descent must follow the bend to
    # the minimum at x = +-1 (p = 0: x^3 - x = 0 on the floor, which the stiff term leaves unchanged)
    jr = jump(bent_valley(), [0.0, 0.0], 0.0, scale=1.0)
    assert jr.success, jr.message
    assert abs(jr.u_to[0]) == pytest.approx(1.0, rel=1e-8) and jr.u_to[1] == pytest.approx(1.0, rel=1e-8)
    assert jr.n_negative == 0 and jr.energy_to == pytest.approx(-0.25, rel=1e-10)
