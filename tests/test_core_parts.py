"""The named parts of the continuation core: corrector result, step controller, test-function protocol."""

from __future__ import annotations

import math

import numpy as np
import pytest

import contin
from contin.path.corrector import Correction, correct
from contin.path.curve import CorrectorFailure, Curve, Point
from contin.path.segment import Segment
from contin.path.stepsize import StepController
from contin.settings import Settings
from contin.watch.testfunctions import BranchPointTest, EventTest, FoldTest
from contin.watch.watchlist import test_functions


def _parabola() -> contin.Problem:
    """``u^2 + p = 0``: a fold at ``(0, 0)``."""
    return contin.Problem(residual=lambda u, p: u ** 2 + p, jacobian=lambda u, p: np.diag(2 * u),
                          dresidual_dp=lambda u, p: np.ones(1), symmetric=True, observables={"u": lambda u, p: u[0]})


def _point(curve: Curve, u: float) -> Point:
    uu, p = np.array([u]), -u * u
    t_u, t_p, det = curve.tangent(uu, p, np.array([1.0]), 0.0)
    return Point(uu, p, t_u, t_p, 0.0, 0, det, 0.0)


def test_corrector_returns_what_happened() -> None:
    curve = Curve(_parabola(), Settings())
    start = _point(curve, -1.0)
    c = correct(curve, start, 0.1)
    assert isinstance(c, Correction) and c.iterations >= 1
    assert abs(c.u[0] ** 2 + c.p) <= curve.tol and c.residual <= curve.tol
    J, fp, F = c.linearization
    assert J.shape == (1, 1) and fp.shape == (1,)
    assert c.contraction is None or 0 <= c.contraction < Settings().max_contraction
    # nothing is left on the curve for the caller to read
    assert not hasattr(curve, "last_linearization") and not hasattr(curve, "last_contraction")
    with pytest.raises(CorrectorFailure):
        correct(curve, start, 0.1, max_iter=0)


def test_step_controller_rules() -> None:
    st = Settings(ds=0.1, ds_min=0.02, ds_max=0.5)
    ctl = StepController(st)
    ctl.accept(iterations=2, contraction=None, cos_turn=1.0)  # easy step: grow
    assert ctl.ds == pytest.approx(0.1 * st.grow)
    ctl.ds = 0.1
    ctl.accept(iterations=2, contraction=st.target_contraction * 4, cos_turn=1.0)  # too slow a contraction
    assert ctl.ds == pytest.approx(0.05)
    ctl.ds = 0.1
    ctl.accept(iterations=st.max_newton - 1, contraction=None, cos_turn=1.0)  # hard step: shrink
    assert ctl.ds == pytest.approx(0.1 * st.shrink)
    ctl.ds = 0.1
    angle = 0.25
    ctl.accept(iterations=6, contraction=None, cos_turn=math.cos(angle))  # turned too much
    assert ctl.ds == pytest.approx(0.1 * st.target_angle / angle)
    ctl.ds = 0.05
    assert ctl.reject(CorrectorFailure("corrector diverging (residuals 1, 2)")) and ctl.ds == pytest.approx(0.025)
    assert not ctl.reject("corrector diverging") and ctl.ds == pytest.approx(0.025)  # below ds_min: stop
    assert ctl.rejections == {"corrector diverging": 2}


def test_every_watched_quantity_speaks_the_same_protocol() -> None:
    curve = Curve(_parabola(), Settings(p_max=0.5, stop_at=("fold",)))
    tests = test_functions(curve, [contin.crossing("u", 0.5, name="u=0.5")])
    assert [type(t) for t in tests] == [FoldTest, BranchPointTest, EventTest, EventTest]
    fold, bp, event, bound = tests
    assert bound.bound and bound.terminal and bound.name == "p_max" and not event.terminal
    A, B = _point(curve, -0.1), _point(curve, 0.1)
    B.s = curve.norm(B.u - A.u, B.p - A.p)
    seg = Segment(curve, A, B)
    for test in tests:
        a, b = test.value(A), test.value(B)
        if test is fold:
            assert test.detect(a, b)
            spt = test.find(seg, a, b)
            assert spt.kind == "fold" and spt.located and abs(spt.p) < 1e-12 and spt.info["folds"] == "p"
            assert test.stop_rank(spt) == 1
            unlocated = test.find(seg, a, b, locate=False)
            assert not unlocated.located and unlocated.info["bracket_p"] == [A.p, B.p]
        else:
            assert not test.detect(a, b)


def test_residuals_stagnating_inside_the_roundoff_floor_raise_the_tolerance_within_a_limit():
    # the floor at (u, p): eps (||J|| max|u| + |f_p| |p|) = eps * 1e13 = 2.2e-3 with this linearization
    curve = Curve(_parabola(), Settings(tol=1e-10))
    start = curve.tol
    J, fp = np.array([[1e13]]), np.array([0.0])
    u, p = np.array([1.0]), 0.0
    lin = (J, fp, None)
    # decreasing residuals are Newton at work, not noise: no raise
    assert not curve.converged_to_roundoff([1e-2, 1e-4, 1e-6], lin, u, p)
    # stagnating residuals above the floor are not noise either
    assert not curve.converged_to_roundoff([1e-2, 2e-2, 1.5e-2], lin, u, p)
    # stagnating inside the floor, but a raise beyond ROUNDOFF_RAISE_LIMIT times the start's tolerance
    # would trust the floor estimate too far
    assert not curve.converged_to_roundoff([2e-4, 3e-4, 2.5e-4], lin, u, p)
    # stagnating inside the floor and within the limit: raised to ten times the stagnation level
    noise = 20 * start
    assert curve.converged_to_roundoff([noise, 1.2 * noise, 0.9 * noise], lin, u, p)
    assert curve.tol == pytest.approx(12 * noise) and curve.tol_raised == [(0.0, start, curve.tol)]
