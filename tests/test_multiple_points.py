"""Multiple branch points: a change of the Morse index by more than one is located and reported."""

from __future__ import annotations

import numpy as np
import pytest

import contin


class RadialModes(contin.Problem):
    """``E = sum (k_i - p) u_i^2 / 2 + (sum u_i^2)^2 / 4``: the trivial branch ``u = 0`` has the Hessian
    ``diag(k - p)``, so a branch point of multiplicity ``#{i: k_i = k}`` at each distinct ``p = k``."""

    def __init__(self, k=(1.0, 1.0, 2.0, 3.0, 3.0, 3.0)) -> None:
        super().__init__(symmetric=True, name="radial_modes", parameter_name="p")
        self.k = np.array(k, dtype=float)

    def residual(self, u, p):
        return (self.k - p) * u + np.dot(u, u) * u

    def jacobian(self, u, p):
        return np.diag(self.k - p) + np.dot(u, u) * np.eye(u.size) + 2.0 * np.outer(u, u)

    def dresidual_dp(self, u, p):
        return -u


@pytest.mark.parametrize("stability", [False, True])
def test_every_branch_point_of_the_trivial_branch_with_its_multiplicity(stability):
    model = RadialModes()
    br = contin.continuation(model, np.zeros(6), 0.0, p_max=4.0, stability=stability)
    assert br.success, br.message
    bps = br.branch_points()
    assert [round(b.p, 12) for b in bps] == [1.0, 2.0, 3.0]
    assert [b.bifurcation.multiplicity for b in bps] == [2, 1, 3]
    for bp, dims in zip(bps, ([0, 1], None, [3, 4, 5])):
        assert bp.located
        if dims is None:
            continue
        kernel = bp.bifurcation.kernel
        assert kernel.shape == (len(dims), 6)
        # the kernel spans the unit vectors of the equal stiffnesses (compare projectors)
        expected = np.zeros((6, 6))
        expected[dims, dims] = 1.0
        assert np.allclose(kernel.T @ kernel, expected, atol=1e-10)


def test_a_double_point_is_not_passed_when_the_step_is_large():
    # one step from p = 0.5 to 1.5 crosses the double point: still located, not skipped
    br = contin.continuation(RadialModes(k=(1.0, 1.0, 5.0)), np.zeros(3), 0.5, p_max=3.0, ds=1.0, ds_max=1.0)
    (bp,) = br.branch_points()
    assert bp.p == pytest.approx(1.0, abs=1e-12)
    assert bp.bifurcation.multiplicity == 2


def test_a_branch_saved_before_records_still_switches():
    # written by contin 17f51ba, whose branch points kept their directions as keys of ``info``
    from pathlib import Path

    from contin_models.benchmarks.pitchfork import Pitchfork

    saved = contin.Branch.load(Path(__file__).parent / "data" / "pitchfork_branch_saved_before_records.npz")
    (bp,) = saved.branch_points()
    assert bp.bifurcation is not None and bp.bifurcation.kind == "pitchfork"
    # unit weights: the automatic ones are degenerate at this point (u = 0, p = 0)
    new = contin.switch_branch(Pitchfork(), bp, p_max=0.25, ds=0.05, state_weight=1.0, param_weight=1.0)
    assert new.success
    # the supercritical branch u1^2 = p
    assert np.allclose(np.asarray(new.u)[1:, 0] ** 2, np.asarray(new.p)[1:], atol=1e-8)


@pytest.mark.parametrize("n", [3, 50, 400])
def test_the_inertia_read_off_a_factorization_is_the_eigenvalue_count(n):
    import scipy.sparse as sp

    from contin.numerics.linalg import BandedLU, DenseLU, TridiagonalLU, banded_extension

    rng = np.random.default_rng(n)
    d, e = rng.normal(1.0, 2.0, n), rng.normal(0.0, 0.5, n - 1)
    A = sp.diags([e, d, e], [-1, 0, 1], format="dia")
    negative = int(np.count_nonzero(np.linalg.eigvalsh(A.toarray()) < 0))
    for F in (TridiagonalLU(A), BandedLU(A, 1, 1), DenseLU(A)):
        counted = F.symmetric_inertia()
        # None only where the factors cannot tell (row interchanges, and no compiled count on the diagonals)
        exact = isinstance(F, TridiagonalLU) and banded_extension() is not None
        assert counted == negative or (counted is None and not exact)


class ImperfectPitchfork(contin.Problem):
    """``f = (-p u1 + u1^3 - eps, u2)``: its primary branch ``u1 > 0`` is stable and has no singular
    point; the other branches (``u1 < 0``, with a fold at ``p = 3 (eps / 2)^(2/3)``) lie close to it."""

    def __init__(self, eps: float) -> None:
        super().__init__(symmetric=True, name="imperfect_pitchfork", parameter_name="p")
        self.eps = eps

    def residual(self, u, p):
        return np.array([-p * u[0] + u[0] ** 3 - self.eps, u[1]])

    def jacobian(self, u, p):
        return np.array([[-p + 3.0 * u[0] ** 2, 0.0], [0.0, 1.0]])

    def dresidual_dp(self, u, p):
        return np.array([-u[0], 0.0])


@pytest.mark.parametrize("stability", [False, True])
def test_a_step_onto_another_branch_is_rejected_not_accepted(stability):
    # one step of 1 from p = -0.5 lands on the unstable middle root at p = 0.5 (u1 = -2e-4, index 1):
    # the index changes with no singular point between, so the step is retried smaller
    model = ImperfectPitchfork(1e-4)
    u0 = np.array([2e-4 / (1.0 + 3.2e-7), 0.0])
    br = contin.continuation(model, u0, -0.5, p_max=0.5, ds=1.0, ds_max=1.0, state_weight=1.0, param_weight=1.0,
                             stability=stability)
    assert br.success, br.message
    u1 = np.asarray(br.u)[:, 0]
    assert np.all(u1 > 0) and u1[-1] == pytest.approx(np.sqrt(0.5), rel=1e-3)
    assert [s.kind for s in br.special_points if s.kind in ("fold", "branch_point")] == []
