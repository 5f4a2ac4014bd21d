"""Simple branch points: detection, location, branch switching (pitchfork, discrete Euler column)."""

import numpy as np
import pytest
from scipy.special import ellipk

from contin import continuation, switch_branch
from contin_models.benchmarks.elastica import EulerColumn
from contin_models.benchmarks.pitchfork import Pitchfork


def test_pitchfork_branch_point_and_switch():
    pf = Pitchfork()
    trivial = continuation(pf, [0.0, 0.0], -1.0, ds=0.1, p_max=1.0, stability=True)
    (bp,) = trivial.branch_points()
    assert bp.located and abs(bp.p) < 1e-12
    assert bp.info["stable_before"] and not bp.info["stable_after"]
    for direction in (1, -1):
        nb = switch_branch(pf, bp, direction=direction, ds=0.1, p_max=1.0, stability=True)
        assert nb.status == "bound" and nb.p[-1] == pytest.approx(1.0)
        u1 = nb.u[:, 0]
        np.testing.assert_allclose(u1 ** 2, nb.p, atol=1e-9)
        assert np.all(np.sign(u1) == np.sign(u1[0])) and np.all(np.abs(u1) > 0)
        assert np.all(nb.n_negative == 0)  # supercritical: the bifurcating branches are stable
        assert nb.special_points[0].kind == "branch_point"


def discrete_buckling_load(n: int, length: float = 1.0, EI: float = 1.0) -> float:
    """Lowest load making the straight column's Hessian singular: dense eigenvalue problem.

    Built here from the energy EI/(2h) [2 t_1^2 + sum (t_i - t_{i-1})^2] + P h sum cos t_i:
    at t = 0 the Hessian is (EI/h) K - P h I, so P = lambda_min(K) EI / h^2.
    """
    h = 0.5 * length / n
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[0, 0], K[-1, -1] = 3.0, 1.0
    return np.linalg.eigvalsh(K)[0] * EI / h ** 2


def trivial_branch(n):
    col = EulerColumn(n)
    return col, continuation(col, np.zeros(n), 0.0, ds=0.5, ds_max=2.0, p_max=15.0, stability=True)


@pytest.mark.parametrize("n", [20, 80])
def test_column_first_branch_point_matches_dense_eigenvalue_solve(n):
    col, br = trivial_branch(n)
    bps = br.branch_points()
    assert bps and bps[0].located
    assert bps[0].p == pytest.approx(discrete_buckling_load(n), rel=1e-8, abs=0)
    assert br.n_negative[0] == 0 and bps[0].info["n_negative_after"] == 1
    for th, P, n_neg, eigs in zip(br.u, br.p, br.n_negative, br.eigenvalues):
        w = np.linalg.eigvalsh(col.jacobian(th, P).toarray())
        assert n_neg == np.count_nonzero(w < 0)
        np.testing.assert_allclose(eigs, w[:eigs.size], rtol=1e-9, atol=1e-9)


def test_column_branch_point_converges_to_euler_load_at_second_order():
    euler = np.pi ** 2  # pi^2 EI / L^2
    errors = []
    for n in (10, 20, 40):
        _, br = trivial_branch(n)
        errors.append(abs(br.branch_points()[0].p - euler))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert errors[-1] < 2e-3 * euler
    assert np.all(np.abs(orders - 2.0) < 0.1), orders


def test_column_switched_branch_is_the_buckled_elastica():
    n = 100
    col, br = trivial_branch(n)
    bp = br.branch_points()[0]
    buckled = switch_branch(col, bp, ds=0.05, ds_max=0.2, p_max=14.0, stability=True, max_steps=400)
    assert buckled.status == "bound"
    rot = buckled.observables["end_rotation"]
    assert np.all(np.abs(rot[1:]) > 0) and np.all(buckled.p > bp.p)
    assert np.all(buckled.n_negative == 0)  # post-buckling of the elastica is stable
    for th, P, eigs in zip(buckled.u, buckled.p, buckled.eigenvalues):
        np.testing.assert_allclose(eigs, np.linalg.eigvalsh(col.jacobian(th, P).toarray())[:eigs.size],
                                   rtol=1e-9, atol=1e-9)
    # elastica: sqrt(P / EI) l = K(m = sin^2(alpha / 2)), l = L / 2, alpha the end rotation
    l = 0.5
    predicted = ellipk(np.sin(rot / 2) ** 2) ** 2 / l ** 2
    big = np.abs(rot) > 0.3
    assert big.sum() > 5
    np.testing.assert_allclose(buckled.p[big], predicted[big], rtol=2e-3)
