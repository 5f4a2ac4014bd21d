"""The engine's lift: a located branch point carried into another problem and located there again."""

import numpy as np
import pytest

from contin import Lift, LiftError, Problem, SpecialPoint, continuation, lift_branch_point, switch_branch, \
    switch_branch_along
from contin_models.benchmarks.elastica import EulerColumn
from contin_models.benchmarks.pitchfork import Pitchfork

#: Where the three-unknown model's pitchfork sits: the two-unknown one's at p = 0, moved.
SHIFT = 0.25


class Pitchfork3(Problem):
    """``E = -(p - SHIFT) u1^2 / 2 + u1^4 / 4 + u2^2 / 2 + (u3 - u1^2)^2 / 2 - e u1``: the pitchfork of
    :class:`Pitchfork` at ``p = SHIFT``, its branches ``u1^2 = p - SHIFT``, ``u3 = u1^2`` (worked out by hand);
    with the imperfection ``e != 0`` no branch point at all."""

    def __init__(self, imperfection: float = 0.0) -> None:
        super().__init__(symmetric=True, name="pitchfork3", parameter_name="p")
        self.e = imperfection

    def residual(self, u, p):
        u1, u2, u3 = u
        return np.array([-(p - SHIFT) * u1 + u1 ** 3 - 2 * u1 * (u3 - u1 ** 2) - self.e, u2, u3 - u1 ** 2])

    def jacobian(self, u, p):
        u1, _, u3 = u
        return np.array([[-(p - SHIFT) + 3 * u1 ** 2 - 2 * u3 + 6 * u1 ** 2, 0.0, -2 * u1],
                         [0.0, 1.0, 0.0],
                         [-2 * u1, 0.0, 1.0]])

    def dresidual_dp(self, u, p):
        return np.array([-u[0], 0.0, 0.0])


def into_three(u, p):
    return np.array([u[0], u[1], 0.0])


LIFT = Lift(state=into_three, mode=lambda v: np.array([v[0], v[1], 0.0]), name="two into three")


@pytest.fixture(scope="module")
def pitchfork_point():
    trivial = continuation(Pitchfork(), [0.0, 0.0], -1.0, ds=0.1, p_max=1.0, stability=True)
    (bp,) = trivial.branch_points()
    return trivial, bp


def test_a_two_unknown_branch_point_relocated_in_three_unknowns(pitchfork_point) -> None:
    _, bp = pitchfork_point
    lifted = lift_branch_point(bp, Pitchfork(), Pitchfork3(), LIFT)
    assert lifted.kind == "branch_point" and lifted.located and lifted.label == "lifted"
    assert lifted.p == pytest.approx(SHIFT, abs=1e-12)
    assert lifted.info["moved_p"] == pytest.approx(SHIFT - bp.p, abs=1e-12)
    assert lifted.info["mode_angle"] < 1e-10          # the kernel (1, 0, 0) is the lifted one
    assert lifted.bifurcation.kind == "pitchfork"
    branch = switch_branch(Pitchfork3(), lifted, ds=0.05, p_max=1.0)
    assert branch.status == "bound"
    u1, u3 = branch.u[1:, 0], branch.u[1:, 2]
    np.testing.assert_allclose(u1 ** 2, branch.p[1:] - SHIFT, atol=1e-9)
    np.testing.assert_allclose(u3, u1 ** 2, atol=1e-9)


def column_lift(coarse: EulerColumn, fine: EulerColumn) -> Lift:
    """Link angles of the coarse column interpolated at the fine column's link midpoints."""
    xc = (np.arange(coarse.n) + 0.5) * coarse.h
    xf = (np.arange(fine.n) + 0.5) * fine.h

    def interpolate(v):
        return np.interp(xf, xc, np.asarray(v, dtype=float))

    return Lift(state=lambda u, p: interpolate(u), mode=interpolate, name="coarse column into fine")


def discrete_buckling_load(col: EulerColumn) -> float:
    """``P_1 = 4 EI / h^2 sin^2(pi / (4 n))`` (the model's docstring)."""
    return 4 * col.EI / col.h ** 2 * np.sin(np.pi / (4 * col.n)) ** 2


def test_a_coarse_column_branch_point_relocated_on_a_finer_mesh() -> None:
    coarse, fine = EulerColumn(10), EulerColumn(25)
    (bp,) = continuation(coarse, np.zeros(coarse.n), 0.0, ds=0.5, ds_max=2.0, p_max=10.5).branch_points()
    lifted = lift_branch_point(bp, coarse, fine, column_lift(coarse, fine))
    assert lifted.p == pytest.approx(discrete_buckling_load(fine), rel=1e-10)
    assert lifted.info["moved_p"] == pytest.approx(discrete_buckling_load(fine) - bp.p, rel=1e-6)
    # the interpolated mode is near the fine mesh's, not equal to it
    assert 0.0 < lifted.info["mode_angle"] < 0.05
    # the buckled branch from the lifted point is the one from the fine column's own branch point
    (own,) = continuation(fine, np.zeros(fine.n), 0.0, ds=0.5, ds_max=2.0, p_max=10.5).branch_points()
    ends = [switch_branch(fine, b, ds=0.05, ds_max=0.2, p_max=10.3).u[-1] for b in (lifted, own)]
    assert abs(ends[0][-1]) > 0.1
    np.testing.assert_allclose(ends[0], ends[1], atol=1e-8)


def test_switch_along_an_explicit_direction() -> None:
    branch = switch_branch_along(Pitchfork(), [0.0, 0.0], 0.0, np.array([1.0, 0.0, 0.0]),
                                 traced=np.array([0.0, 0.0, 1.0]), direction=-1, ds=0.1, p_max=1.0)
    assert branch.status == "bound" and branch.special_points[0].label == "origin"
    u1 = branch.u[1:, 0]
    assert np.all(u1 < 0)
    np.testing.assert_allclose(u1 ** 2, branch.p[1:], atol=1e-9)
    with pytest.raises(ValueError, match="along must be a finite direction"):
        switch_branch_along(Pitchfork(), [0.0, 0.0], 0.0, np.array([0.0, 0.0, 1.0]))


def test_a_point_that_is_not_a_bifurcation_is_refused(pitchfork_point) -> None:
    trivial, bp = pitchfork_point
    start = SpecialPoint("event", float(trivial.p[0]), trivial.u[0], located=True)
    with pytest.raises(LiftError, match="not a bifurcation"):
        lift_branch_point(start, Pitchfork(), Pitchfork3(), LIFT)
    family_lift = Lift(state=into_three, mode=LIFT.mode, family="n", key=3)
    with pytest.raises(LiftError, match="branch point of the source itself"):
        lift_branch_point(bp, Pitchfork(), Pitchfork3(), family_lift)
    wrong_key = SpecialPoint("bifurcation", 0.0, np.zeros(2), located=True,
                             info={"family": "n", "key": 2, "mode": np.array([1.0, 0.0])})
    with pytest.raises(LiftError, match="into n = 2"):
        lift_branch_point(wrong_key, Pitchfork(), Pitchfork3(), family_lift)
    # an imperfect pitchfork has no branch point: the extended system's root unfolds it (mu = e)
    with pytest.raises(LiftError, match="no branch point of the target near the lifted point"):
        lift_branch_point(bp, Pitchfork(), Pitchfork3(imperfection=1e-3), LIFT)
