"""The pieces issue 18 added to the engine: the bracketed root finder, the banded inertia counts and
the optional chord corrector updates."""

import math

import numpy as np
import pytest
import scipy.sparse as sp

from contin import continuation
from contin.numerics.linalg import SymmetricBand
from contin.numerics.stability import leading_inertias
from contin.path.segment import bracketed_root
from contin_models.benchmarks.bratu import Bratu


def test_bracketed_root_finds_the_root_to_its_tolerance_with_few_evaluations():
    calls = []

    def f(x):
        calls.append(x)
        return math.cos(x) - x  # root 0.7390851332151607 (the Dottie number)

    root = bracketed_root(f, 0.0, 1.0, f(0.0), f(1.0), xtol=1e-12)
    assert abs(root - 0.7390851332151607) < 1e-12
    assert len(calls) - 2 <= 8  # superlinear: not the ~40 of bisection


def test_bracketed_root_refuses_a_bracket_without_sign_change():
    with pytest.raises(ValueError, match="no sign change"):
        bracketed_root(lambda x: x * x + 1.0, -1.0, 1.0, 2.0, 2.0, xtol=1e-12)


def _random_band(n, kd, shift, seed):
    rng = np.random.default_rng(seed)
    A = np.zeros((n, n))
    for k in range(kd + 1):
        d = rng.standard_normal(n - k)
        A += np.diag(d, k) + (np.diag(d, -k) if k else 0)
    return A + shift * np.eye(n)


@pytest.mark.parametrize("seed", range(5))
def test_negative_pivots_count_every_leading_block_like_eigvalsh(seed):
    A = _random_band(120, 4, 2.0, seed)
    out = SymmetricBand.from_sparse(sp.csr_matrix(A)).negative_pivots(max_negative=120)
    assert out is not None
    columns, _ = out
    for m in (30, 60, 119, 120):
        expected = int(np.sum(np.linalg.eigvalsh(A[:m, :m]) < 0))
        assert sum(1 for j in columns if j < m) == expected
    assert leading_inertias(sp.csr_matrix(A), (60, 120)) == [int(np.sum(np.linalg.eigvalsh(A[:m, :m]) < 0))
                                                             for m in (60, 120)]


def test_negative_pivots_decline_a_tiny_positive_pivot():
    # [[e, 1], [1, 1]] with e -> 0+: Cholesky goes on, but its multiplier 1/e cannot be trusted
    n = 80
    A = np.eye(n)
    A[10, 10], A[10, 11], A[11, 10] = 1e-12, 1.0, 1.0
    assert SymmetricBand.from_sparse(sp.csr_matrix(A)).negative_pivots() is None


def test_chord_updates_find_the_same_fold_with_fewer_factorizations():
    runs = {rate: continuation(Bratu(200), np.zeros(200), 0.0, ds=0.1, ds_max=1.0, bounds={"max_u": (None, 4.0)},
                               max_chord_rate=rate) for rate in (0.0, 0.2)}
    folds = {rate: br.folds()[0] for rate, br in runs.items()}
    assert all(f.located for f in folds.values())
    assert abs(folds[0.2].p - folds[0.0].p) < 1e-10 * folds[0.0].p
    assert runs[0.2].meta["n_factorizations"] < runs[0.0].meta["n_factorizations"]
