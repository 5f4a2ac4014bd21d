"""The few smallest eigenvalues of a large band matrix by Lanczos in shift-invert mode (``contin.numerics.stability``).

LAPACK's banded eigensolver reduces the band to tridiagonal form at O(n^2 b) cost, which dominated a
3-D shell trace from N = 400 on (0.7 s a point).  Above ``SHIFT_INVERT_WORK`` the eigenvalues come from
Lanczos on the inverse of the band shifted just below its spectrum; they must be LAPACK's, and the
Morse index the count's, for positive definite and indefinite bands.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from contin.numerics import stability
from contin.numerics.linalg import lower_band


def band(n: int, b: int, shift: float, seed: int) -> sp.csr_matrix:
    rng = np.random.default_rng(seed)
    A = sp.diags([rng.random(n - abs(k)) for k in range(-b, b + 1)], list(range(-b, b + 1))).tocsr()
    return ((A + A.T) * 0.5 + sp.eye(n) * (b + 1.0 + shift)).tocsr()


@pytest.mark.parametrize("shift, negative", [(0.0, False), (-25.3, True), (-29.0, True)])
def test_shift_invert_gives_lapacks_smallest_eigenvalues(shift: float, negative: bool) -> None:
    n, b = 2600, 32
    assert float(n) * n * b > stability.SHIFT_INVERT_WORK
    H = band(n, b, shift, 1)
    ab = lower_band(H, b)
    reference = sla.eig_banded(ab, lower=True, eigvals_only=True, select="i", select_range=(0, 2))
    count = sla.eig_banded(ab, lower=True, eigvals_only=True, select="v", select_range=(-np.inf, 0.0)).size
    direct = stability._shifted_lanczos_info(H, b, 3)
    assert direct is not None
    info = stability.stability_info(H, 3)
    for got in (direct, info):
        assert np.max(np.abs(got.eigenvalues - reference)) <= 1e-12 * np.max(np.abs(reference))
        assert got.n_negative == count
    assert (reference[0] < 0) == negative


@pytest.mark.parametrize("shift", [-25.3, 0.0])
def test_shift_invert_gives_the_eigenvectors_too(shift: float) -> None:
    """An energy descent asks for the unstable eigenvector of a large band: the same route, not LAPACK's
    reduction, and the vectors are orthonormal eigenvectors of the matrix for LAPACK's eigenvalues."""
    n, b = 2600, 32
    H = band(n, b, shift, 2)
    info = stability.stability_info(H, 1, vectors=True)
    want = max(1, info.n_negative)
    w = sla.eig_banded(lower_band(H, b), lower=True, eigvals_only=True, select="i", select_range=(0, want))
    assert w[want] - w[want - 1] > 1e-6 * np.max(np.abs(w))  # simple: the vectors are determined up to sign
    V = info.eigenvectors
    assert V.shape == (n, want)
    assert np.max(np.abs(info.eigenvalues - w[:1])) <= 1e-12 * np.max(np.abs(w))
    assert np.max(np.abs(V.T @ V - np.eye(want))) < 1e-10
    for j in range(want):
        assert np.linalg.norm(H @ V[:, j] - w[j] * V[:, j]) <= 1e-8 * np.max(np.abs(w))
