"""Folds on the 1-D Bratu problem against an independent dense Moore-Spence solve and the continuum."""

import numpy as np
import pytest

from contin import continuation
from contin_models.benchmarks.bratu import Bratu

LAMBDA_CONTINUUM = 3.513830719  # fold of u'' + lam exp(u) = 0, u(0) = u(1) = 0


def dense_moore_spence(n: int) -> float:
    """Fold of the finite-difference Bratu problem from the Moore-Spence system, dense Newton.

    Written from the equations (u_{i-1} - 2 u_i + u_{i+1}) / h^2 + lam exp(u_i) = 0, independently of
    the model's code and scaling.  Unknowns (u, phi, lam); equations F = 0, J phi = 0, sum(phi) = 1.
    """
    h = 1.0 / (n + 1)
    x = np.linspace(h, 1 - h, n)
    A = (np.diag(-2 * np.ones(n)) + np.diag(np.ones(n - 1), 1) + np.diag(np.ones(n - 1), -1)) / h ** 2
    theta = 4.798714560  # continuum fold, starting guess
    u = -2 * np.log(np.cosh((x - 0.5) * theta / 2) / np.cosh(theta / 4))
    lam = 3.5
    phi = np.sin(np.pi * x)
    phi /= phi.sum()
    for _ in range(50):
        e = np.exp(u)
        J = A + lam * np.diag(e)
        G = np.concatenate([A @ u + lam * e, J @ phi, [phi.sum() - 1]])
        DG = np.zeros((2 * n + 1, 2 * n + 1))
        DG[:n, :n] = J
        DG[:n, 2 * n] = e
        DG[n:2 * n, :n] = lam * np.diag(e * phi)
        DG[n:2 * n, n:2 * n] = J
        DG[n:2 * n, 2 * n] = e * phi
        DG[2 * n, n:2 * n] = 1.0
        d = np.linalg.solve(DG, -G)
        u, phi, lam = u + d[:n], phi + d[n:2 * n], lam + d[2 * n]
        if abs(d[2 * n]) < 1e-15 * lam and np.max(np.abs(G)) < 1e-9:
            break
    return lam


def trace(n, **kw):
    return continuation(Bratu(n), np.zeros(n), 0.0, ds=0.1, ds_max=1.0, bounds={"max_u": (None, 4.0)}, **kw)


def test_fold_matches_dense_extended_system_n200():
    br = trace(200)
    folds = br.folds()
    assert len(folds) == 1 and folds[0].located
    ref = dense_moore_spence(200)
    assert folds[0].p == pytest.approx(ref, rel=1e-10, abs=0)
    assert folds[0].info["method"] == "minimally augmented Newton"


def test_fold_n2000_close_to_continuum_and_trace_reaches_upper_branch():
    br = trace(2000)
    assert br.status == "bound"
    assert br.observables["max_u"][-1] == pytest.approx(4.0, abs=1e-9)
    (fold,) = br.folds()
    assert abs(fold.p - LAMBDA_CONTINUUM) < 1e-5
    # the last point lies on the upper branch: past the fold, lam decreased again
    assert br.p[-1] < fold.p - 1.0


def test_step_count_does_not_grow_with_n():
    steps = [trace(n, store_states=False).meta["n_steps"] for n in (200, 2000, 20000)]
    assert max(steps) - min(steps) <= 2, steps


def test_every_stored_point_is_converged():
    pb = Bratu(300)
    br = trace(300)
    for u, lam in zip(br.u, br.p):
        assert np.max(np.abs(pb.residual(u, lam))) <= br.meta["abs_tol"]
    assert np.all(br.residual <= br.meta["abs_tol"])


def test_stability_on_banded_path_matches_eigvalsh():
    # n = 600 exceeds the dense limit: exercises the banded eigensolver
    pb = Bratu(600)
    br = continuation(pb, np.zeros(600), 0.0, ds=0.2, ds_max=1.0, bounds={"max_u": (None, 3.0)},
                      stability=True, n_eigs=2)
    for i in range(len(br)):
        w = np.linalg.eigvalsh(pb.jacobian(br.u[i], br.p[i]).toarray())
        assert br.n_negative[i] == np.count_nonzero(w < 0)
        np.testing.assert_allclose(br.eigenvalues[i], w[:2], rtol=1e-8, atol=1e-10)
    # lower branch stable, upper branch one unstable direction
    assert br.n_negative[0] == 0 and br.n_negative[-1] == 1
