"""contin.analyses.deadload.DeadLoad on a small displacement-controlled model, checked against the closed form.

The model: the von Mises truss apex ``y`` (two bars of stiffness k from ``(-a, 0)``, ``(a, 0)``) tied by
a spring ``k_s`` to a point whose height ``p`` is prescribed.  ``E(y, p) = k (L - L0)^2 + k_s (y - p)^2 / 2``
with ``L = sqrt(a^2 + y^2)``.  Under a dead load ``F`` on that point the equilibrium is
``F = dE/dp = k_s (p - y) = V'(y)``, ``V = k (L - L0)^2``, whose limit loads are the extrema of ``V'``:
``-P_max`` at ``y*`` with ``L*^3 = L0 a^2`` and ``P_max = 2 k y* (L0 / L* - 1)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

from contin import Problem, continuation
from contin.analyses.deadload import DeadLoad, bordered_matrix

A, B, K, KS = 1.0, 0.5, 1.0, 50.0
L0 = math.hypot(A, B)


class TiedTruss(Problem):
    """The truss apex tied to a prescribed height ``p`` by a spring (displacement control of ``p``)."""

    def __init__(self) -> None:
        super().__init__(symmetric=True, name="tied_truss", parameter_name="p",
                         observables={"y": lambda u, p: float(u[0]), "p": lambda u, p: float(p)})

    def energy(self, u: np.ndarray, p: float) -> float:
        return K * (math.hypot(A, u[0]) - L0) ** 2 + 0.5 * KS * (u[0] - p) ** 2

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        L = math.hypot(A, u[0])
        return np.array([2 * K * (L - L0) * u[0] / L + KS * (u[0] - p)])

    def jacobian(self, u: np.ndarray, p: float) -> np.ndarray:
        y, L = u[0], math.hypot(A, u[0])
        return np.array([[2 * K * (1 - L0 * A * A / L ** 3) + KS]])

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        return np.array([-KS])

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        return KS * (p - u[0])

    def conjugate_stiffness(self, u: np.ndarray, p: float) -> float:
        return KS


def limit_load() -> tuple[float, float]:
    L = (L0 * A * A) ** (1 / 3)
    y = math.sqrt(L * L - A * A)
    return y, 2 * K * y * (L0 / L - 1)


def test_residual_and_jacobian_are_the_energy_derivatives() -> None:
    P = DeadLoad(TiedTruss(), scaled={"F_half": ("F", 0.5)})
    U, F, h = np.array([0.3, 0.2]), 0.7, 1e-6
    grad = [(P.energy(U + h * e, F) - P.energy(U - h * e, F)) / (2 * h) for e in np.eye(2)]
    np.testing.assert_allclose(P.residual(U, F), grad, atol=1e-8)
    jac = np.column_stack([(P.residual(U + h * e, F) - P.residual(U - h * e, F)) / (2 * h) for e in np.eye(2)])
    np.testing.assert_allclose(P.jacobian(U, F).toarray(), jac, atol=1e-6)
    np.testing.assert_allclose(P.dresidual_dp(U, F), [0.0, -1.0])
    obs = P.evaluate_observables(U, F)
    assert obs["p"] == 0.2 and obs["F"] == 0.7 and obs["F_half"] == 0.35 and obs["y"] == 0.3
    assert P.parameter_name == "F"


def test_dead_load_snaps_at_the_closed_form_limit_load() -> None:
    y_star, p_max = limit_load()
    P = DeadLoad(TiedTruss())
    U0, F0 = P.from_displacement_state(np.array([B]), B)
    assert F0 == 0.0
    br = continuation(P, U0, F0, ds=0.02, ds_max=0.05, direction=-1, stop_at=("fold",), stability=True)
    fold = br.folds()[-1]
    assert fold.p == pytest.approx(-p_max, abs=1e-9)
    assert fold.u[0] == pytest.approx(y_star, abs=1e-5)
    # stable under the dead load up to the fold, and always under the prescribed displacement (stiff spring)
    assert np.all(br.stability_by["force"][0][:-1] == 0)
    assert np.all(br.stability_by["displacement"][0] == 0)


def test_bordered_matrix_matches_the_dense_border() -> None:
    rng = np.random.default_rng(1)
    A_ = rng.standard_normal((5, 5))
    col = np.array([0.0, 1.5, 0.0, -2.0, 0.0])
    dense = np.block([[A_, col[:, None]], [col[None, :], np.array([[3.0]])]])
    np.testing.assert_array_equal(bordered_matrix(A_, col, 3.0).toarray(), dense)


def test_bordered_matrices_of_a_fixed_pattern_are_right_call_after_call() -> None:
    """The bordered layout of a fixed pattern is kept for the next call: each matrix still has its own
    values, and a border with other nonzeros gets its own layout."""
    from contin.numerics.linalg import FixedPattern

    rng = np.random.default_rng(2)
    off = rng.standard_normal(39)
    dense = np.diag(rng.uniform(1.0, 2.0, 40)) + np.diag(off, 1) + np.diag(off, -1)
    base = sp.csr_matrix(dense)
    pattern = FixedPattern(base.indices, base.indptr, base.shape)
    made = []
    for nonzero in ([37, 38, 39], [37, 38, 39], [0, 20], []):
        values = rng.standard_normal(base.nnz)
        col = np.zeros(40)
        col[nonzero] = rng.standard_normal(len(nonzero))
        made.append((bordered_matrix(pattern.matrix(values), col, 5.0), values, col))
    # the repeated border is filled into the first one's pattern, not built anew (the phase boundaries'
    # force-controlled members border a Jacobian of one pattern at every Newton step)
    assert made[1][0].indices is made[0][0].indices and made[1][0].indptr is made[0][0].indptr
    assert made[2][0].indices is not made[0][0].indices
    for M, values, col in made:  # earlier matrices are not overwritten by later ones
        A_ = sp.csr_matrix((values, base.indices, base.indptr), shape=base.shape).toarray()
        expected = np.block([[A_, col[:, None]], [col[None, :], np.array([[5.0]])]])
        np.testing.assert_array_equal(M.toarray(), expected)
        assert M.has_canonical_format and M.nnz == base.nnz + 2 * np.count_nonzero(col) + 1


def test_a_problem_without_a_conjugate_force_is_refused() -> None:
    with pytest.raises(TypeError, match="conjugate_force"):
        DeadLoad(Problem(residual=lambda u, p: u - p, symmetric=True))


def test_dead_load_declares_the_displacement_operator_as_its_leading_block() -> None:
    """No counting of its own: the base's Hessian is the ``LeadingBlock`` of the bordered Jacobian, and the
    engine's counts equal each operator's eigenvalue count."""
    from contin import LeadingBlock

    base = TiedTruss()
    P = DeadLoad(base)
    assert P._stability_operators["displacement"] == LeadingBlock("force", -1)
    for y, p in ((0.3, 0.2), (0.0, 0.1), (-0.2, -0.6)):
        U, F = P.from_displacement_state(np.array([y]), p)
        ops = P.stability_operators(U, F)
        np.testing.assert_array_equal(ops["displacement"], base.jacobian(np.array([y]), p))
        counts = {label: info.n_negative for label, info in P.stability(U, F).items()}
        assert counts == {label: int(np.count_nonzero(np.linalg.eigvalsh(_dense(op)) < 0))
                          for label, op in ops.items()}


def _dense(A: object) -> np.ndarray:
    return A.toarray() if hasattr(A, "toarray") else np.asarray(A)
