"""Shared check near a cusp: the two folds' parameter gap grows as the distance to the cusp to the 3/2."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pytest

import contin


def assert_three_halves_law(problem: contin.FoldCurveProblem, branch: contin.Branch,
                            distances: Sequence[float]) -> None:
    """Assert that the fold-curve gap at each event ``d=<distance>`` scales as ``distance ** 1.5``.

    Parameters
    ----------
    problem : contin.FoldCurveProblem
        The fold-curve problem; ``problem.split(u)[1]`` is the fold's parameter.
    branch : contin.Branch
        The traced fold curve, with two crossing events named ``f"d={d:g}"`` for each distance.
    distances : sequence of float
        Distances from the cusp.

    Raises
    ------
    AssertionError
        The log-log slope of the gap against the distance is not 1.5 within 0.02.
    """
    gap = []
    for d in distances:
        a, b = (problem.split(e.u)[1] for e in branch.events(f"d={d:g}"))
        gap.append(abs(a - b))
    slope = np.polyfit(np.log(distances), np.log(gap), 1)[0]
    assert slope == pytest.approx(1.5, abs=0.02)
