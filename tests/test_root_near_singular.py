"""Locating a branch point's test function on a segment (:func:`contin.watch.testfunctions.root_near_singular`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from contin.path.curve import CorrectorFailure
from contin.watch.testfunctions import root_near_singular


class _Line:
    """A segment whose point at ``sigma`` is ``u = [sigma], p = sigma``; points within ``dead`` of ``root``
    fail to converge, as next to a branch point."""

    def __init__(self, sigma_B: float, root: float, dead: float = 0.0) -> None:
        self.sigma_B, self.root, self.dead = sigma_B, root, dead
        self.calls = 0

    def point(self, sigma: float) -> tuple[np.ndarray, float, float]:
        self.calls += 1
        if abs(sigma - self.root) < self.dead:
            raise CorrectorFailure("too close to the singular point")
        return np.array([sigma]), float(sigma), 0.0


@pytest.mark.parametrize("sigma_B, root, dead", [(0.02, 0.0123, 0.0), (0.02, 0.0071, 0.0), (1.0, 0.7, 1e-5)])
def test_false_position_locates_as_bisection_does_in_fewer_points(sigma_B: float, root: float, dead: float) -> None:
    """Given the value at the far end, a smooth test function is bracketed by false position: the same root
    (the cubic through four points next to it) from fewer corrected points than bisection takes, and points
    next to the root that fail to converge are stepped around."""
    def g(u: np.ndarray, p: float) -> float:
        return math.tanh(30.0 * (p - root) / abs(sigma_B))

    width = 1e-4 * abs(sigma_B)
    found = {}
    for name, g_hi in (("bisection", None), ("false position", g(None, sigma_B))):
        seg = _Line(sigma_B, root, dead)
        u, p = root_near_singular(seg, g, 0.0, sigma_B, g(None, 0.0), width, g_hi=g_hi)
        assert p == pytest.approx(root, abs=1e-9 * abs(sigma_B)) and u[0] == pytest.approx(p, abs=1e-12)
        found[name] = seg.calls
    if not dead:  # next to points that fail, both pay for the nudges
        assert found["false position"] < found["bisection"] - 4
