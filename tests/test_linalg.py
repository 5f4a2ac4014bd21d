"""Factorizations and bordered solves against dense numpy references."""

import numpy as np
import pytest
import scipy.sparse as sp

from contin.numerics.linalg import BandedLU, BorderedSolver, DenseLU, SparseLU, factorize


def _random_banded(n, rng, kl=1, ku=2):
    diags = [rng.standard_normal(n) for _ in range(kl + ku + 1)]
    diags[kl] += 4.0
    return sp.diags([d[: n - abs(o)] for d, o in zip(diags, range(-kl, ku + 1))], list(range(-kl, ku + 1)),
                    format="csr")


@pytest.mark.parametrize("cls", [DenseLU, BandedLU, SparseLU])
def test_factorizations_solve_and_determinant(cls):
    rng = np.random.default_rng(1)
    A = _random_banded(60, rng)
    F = cls(A)
    b = rng.standard_normal((60, 2))
    dense = A.toarray()
    np.testing.assert_allclose(dense @ F.solve(b), b, atol=1e-12)
    np.testing.assert_allclose(dense.T @ F.solve(b, trans=True), b, atol=1e-12)
    sign, logdet = np.linalg.slogdet(dense)
    s, l = F.det_sign_log()
    assert s == sign
    assert l == pytest.approx(logdet, rel=1e-12)


def test_sparse_lu_pivots_are_indexed_by_the_columns_of_the_matrix():
    """An arrow matrix: SuperLU eliminates the dense first column last, so the order of its factor's
    columns is not the matrix's; each pivot is at its column's index (the Schur complement of the
    diagonal at column 0)."""
    n = 12
    d = np.arange(1.0, n + 1)
    arrow = np.diag(d)
    arrow[0, 1:] = arrow[1:, 0] = 0.1
    pivots = SparseLU(sp.csc_matrix(arrow)).pivots()
    np.testing.assert_array_equal(pivots[1:], d[1:])
    assert pivots[0] == pytest.approx(1.0 - np.sum(0.01 / d[1:]), rel=1e-14)


def test_determinant_sign_without_overflow():
    # det = 3^5000 overflows a float; its sign and log must still come out right, with a flipped sign
    n = 5000
    d = np.full(n, 3.0)
    d[17] = -3.0
    F = factorize(sp.diags(d, format="csr"))
    s, l = F.det_sign_log()
    assert s == -1.0
    assert l == pytest.approx(n * np.log(3.0), rel=1e-13)


def test_auto_method_choice():
    rng = np.random.default_rng(2)
    assert isinstance(factorize(_random_banded(30, rng)), DenseLU)
    assert isinstance(factorize(_random_banded(3000, rng)), BandedLU)


@pytest.mark.parametrize("k", [1, 2])
def test_bordered_solve_matches_dense(k):
    rng = np.random.default_rng(3)
    n = 300
    A = _random_banded(n, rng)
    B, C, D = rng.standard_normal((n, k)), rng.standard_normal((k, n)), rng.standard_normal((k, k))
    S = BorderedSolver(A, factorize(A), B, C, D)
    M = S.full_matrix().toarray()
    f, g = rng.standard_normal(n), rng.standard_normal(k)
    x, z = S.solve(f, g)
    np.testing.assert_allclose(M @ np.concatenate([x, z]), np.concatenate([f, g]), atol=1e-10)
    xt, zt = S.solve(f, g, trans=True)
    np.testing.assert_allclose(M.T @ np.concatenate([xt, zt]), np.concatenate([f, g]), atol=1e-10)
    sign, logdet = np.linalg.slogdet(M)
    s, l = S.det_sign_log()
    assert s == sign and l == pytest.approx(logdet, rel=1e-10)


def test_bordered_solve_with_singular_main_block():
    # A exactly singular (as at a fold) but the bordered matrix regular: falls back, still exact
    n = 200
    main = np.full(n, 2.0)
    A = sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1], format="lil")
    A[0, 0] = 1.0
    A[n - 1, n - 1] = 1.0  # Neumann Laplacian: null vector = ones
    A = A.tocsr()
    ones = np.ones((n, 1)) / np.sqrt(n)
    S = BorderedSolver(A, factorize(A), ones, ones.T, np.zeros((1, 1)))
    rng = np.random.default_rng(4)
    f, g = rng.standard_normal(n), rng.standard_normal(1)
    x, z = S.solve(f, g)
    M = S.full_matrix().toarray()
    np.testing.assert_allclose(M @ np.concatenate([x, z]), np.concatenate([f, g]), atol=1e-9)


def test_bordered_solve_deflates_a_large_singular_main_block():
    # n above the dense limit: the singular block is deflated (band kept), never factorized densely
    n = 1500
    A = sp.diags([-np.ones(n - 1), np.r_[1.0, np.full(n - 2, 2.0), 1.0], -np.ones(n - 1)], [-1, 0, 1], format="csr")
    rng = np.random.default_rng(5)
    b = rng.standard_normal((n, 1))
    c = rng.standard_normal((1, n))
    S = BorderedSolver(A, factorize(A), b, c, np.zeros((1, 1)))
    f, g = rng.standard_normal(n), rng.standard_normal(1)
    x, z = S.solve(f, g)
    assert S._deflated is not None and S._full is None
    M = S.full_matrix()
    res = M @ np.concatenate([x, z]) - np.concatenate([f, g])
    assert np.max(np.abs(res)) < 1e-9 * (np.max(np.abs(x)) + 1)
    # determinant sign and log through the deflation, against a dense reference
    sign, logdet = np.linalg.slogdet(M.toarray())
    s, l = S.det_sign_log()
    assert s == sign and l == pytest.approx(logdet, rel=1e-9)


@pytest.mark.parametrize("shift", [0.0, 0.7, 1.9, 3.5])
def test_inertia_by_pivot_free_ldlt_matches_eigenvalues(shift):
    # banded symmetric indefinite matrices: Sylvester's law against a dense eigen-decomposition
    from contin.numerics.stability import inertia, stability_info

    n = 300
    rng = np.random.default_rng(11)
    offs = [rng.standard_normal(n - k) * 0.3 for k in (1, 2, 3)]
    A = sp.diags([offs[2], offs[1], offs[0], 2.0 + rng.standard_normal(n) * 0.2 - shift, offs[0], offs[1], offs[2]],
                 [-3, -2, -1, 0, 1, 2, 3], format="csr")
    expected = int(np.count_nonzero(np.linalg.eigvalsh(A.toarray()) < 0))
    assert inertia(A) == expected
    info = stability_info(A, k=0)
    assert info.n_negative == expected and info.eigenvalues.size == 0
    assert stability_info(A, k=2).n_negative == expected


def test_inertia_refuses_a_factorization_it_cannot_trust():
    # a zero leading pivot needs a row exchange: the pivot-free count is not available
    from contin.numerics.stability import inertia, stability_info

    n = 100
    A = sp.diags([np.ones(n - 1), np.r_[0.0, np.full(n - 1, 3.0)], np.ones(n - 1)], [-1, 0, 1], format="csr")
    assert inertia(A) is None
    expected = int(np.count_nonzero(np.linalg.eigvalsh(A.toarray()) < 0))
    assert expected == 1
    assert stability_info(A, k=0).n_negative == expected  # falls back to an eigensolver


def test_stability_falls_back_to_dense_when_arpack_does_not_converge(monkeypatch):
    """ARPACK can stall on the smallest eigenvalues of a stiff Hessian (a shell at a fold, n ~ 450):
    the count and the eigenvalues then come from a dense solve, not from an internal error."""
    import scipy.sparse.linalg as spla

    import contin.numerics.stability as stability

    rng = np.random.default_rng(3)
    A = sp.random(500, 500, density=0.01, random_state=rng)
    A = (A + A.T + sp.eye(500)).tocsr()

    def no_convergence(*args, **kwargs):
        raise spla.ArpackNoConvergence("no convergence", np.zeros(0), np.zeros((500, 0)))

    monkeypatch.setattr(stability.spla, "eigsh", no_convergence)
    info = stability.stability_info(A, 2, vectors=True)
    w = np.linalg.eigvalsh(A.toarray())
    assert info.n_negative == int(np.sum(w < 0))
    np.testing.assert_allclose(info.eigenvalues, w[:2], rtol=1e-10)
    assert info.eigenvectors.shape[1] >= info.n_negative


def _random_band(rng: np.random.Generator, n: int, kd: int, shift: float) -> tuple[np.ndarray, np.ndarray]:
    """A random symmetric band matrix (dense) and its LAPACK upper band storage."""
    A = np.zeros((n, n))
    for k in range(kd + 1):
        v = rng.standard_normal(n - k)
        A += np.diag(v, k) + (np.diag(v, -k) if k else 0.0)
    A += shift * np.eye(n)
    ab = np.zeros((kd + 1, n))
    for k in range(kd + 1):
        ab[kd - k, k:] = np.diag(A, k)
    return A, ab


def test_symmetric_band_agrees_with_its_dense_matrix() -> None:
    from contin.numerics.linalg import SymmetricBand

    rng = np.random.default_rng(3)
    A, ab = _random_band(rng, 40, 3, 2.0)
    B = SymmetricBand(ab)
    x, X = rng.standard_normal(40), rng.standard_normal((40, 3))
    s = rng.uniform(0.5, 2.0, 40)
    assert B.shape == (40, 40) and B.kd == 3
    assert np.array_equal(B.toarray(), A) and np.array_equal(B.tocsc().toarray(), A)
    assert np.allclose(B @ x, A @ x, rtol=0, atol=1e-13) and np.allclose(B @ X, A @ X, rtol=0, atol=1e-13)
    assert np.allclose(B.scaled(s).toarray(), A * s[:, None] * s[None, :], rtol=0, atol=1e-14)
    assert np.allclose(factorize(B).solve(x), np.linalg.solve(A, x), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("shift", [-1.5, 0.0, 1.0, 4.0])
def test_band_inertia_by_restarted_cholesky_matches_eigenvalues(shift: float, banded_path) -> None:
    """The pivot-free L D L^T run as banded Cholesky pieces counts like the eigenvalues (or declines)."""
    from contin.numerics.linalg import SymmetricBand

    rng = np.random.default_rng(int(10 * shift) + 50)
    counted = 0
    for _ in range(60):
        n, kd = int(rng.integers(5, 60)), int(rng.integers(1, 6))
        A, ab = _random_band(rng, n, kd, shift)
        out = SymmetricBand(ab).inertia()
        if out is None:
            continue
        counted += 1
        expected = int(np.count_nonzero(np.linalg.eigvalsh(A) < 0.0))
        assert out[0] == expected
        assert (out[1] is not None) == (expected == 0)  # the Cholesky factor only of a definite matrix
    assert counted >= 45


def test_band_inertia_declines_a_zero_pivot(banded_path) -> None:
    from contin.numerics.linalg import SymmetricBand

    ab = np.array([[0.0, 1.0, 0.5], [1.0, 1.0, 2.0]])  # [[1, 1, 0], [1, 1, .5], [0, .5, 2]]: pivot 2 is 0
    assert SymmetricBand(ab).inertia() is None
    ab[1, 1] = 0.0  # pivot 2 is -1: counted, and the rest resumes
    A = SymmetricBand(ab).toarray()
    assert SymmetricBand(ab).inertia()[0] == int(np.count_nonzero(np.linalg.eigvalsh(A) < 0)) == 1


def test_compiled_band_ldlt_is_the_lapack_pieces_factorization(monkeypatch) -> None:
    """The C pivot-free L D L^T lists the same negative pivots and, for a definite matrix, gives the
    Cholesky factor that LAPACK's pieces give (to rounding), which dpbtrs then solves with."""
    from scipy.linalg import lapack

    from contin.numerics import linalg
    from contin.numerics.linalg import SymmetricBand

    extension = linalg.banded_extension()
    if extension is None:
        pytest.skip("the C extension contin.numerics._banded is not built")
    rng = np.random.default_rng(12)
    compared = definite = 0
    for shift in (-1.0, 0.5, 2.0, 5.0):
        for _ in range(40):
            n = int(rng.integers(2, 50))
            A, ab = _random_band(rng, n, min(int(rng.integers(0, 6)), n - 1), shift)
            monkeypatch.setattr(linalg, "_BANDED", [extension])
            fast = SymmetricBand(ab).negative_pivots()
            monkeypatch.setattr(linalg, "_BANDED", [None])
            pieces = SymmetricBand(ab).negative_pivots()
            assert (fast is None) == (pieces is None)
            if fast is None:
                continue
            compared += 1
            assert fast[0] == pieces[0]
            assert (fast[1] is None) == (pieces[1] is None)
            if fast[1] is not None:
                definite += 1
                np.testing.assert_allclose(fast[1], pieces[1], rtol=1e-10, atol=1e-12 * np.abs(pieces[1]).max())
                b = rng.standard_normal(n)
                np.testing.assert_allclose(A @ lapack.dpbtrs(fast[1], b, lower=0)[0], b, atol=1e-8)
    assert compared >= 120 and definite >= 25
    with pytest.raises(ValueError, match="Fortran"):
        extension.ldlt_negative(np.ones((3, 4)), 1e8, 32, 0.0)  # C order: numpy refuses the buffer


def test_fixed_pattern_matrices_equal_scipy_ones_and_keep_their_pattern():
    from contin.numerics.linalg import FixedPattern

    rng = np.random.default_rng(5)
    A = sp.random(30, 30, density=0.2, format="csr", random_state=5)
    A.sum_duplicates()
    pattern = FixedPattern(A.indices, A.indptr, A.shape)
    x = rng.standard_normal(30)
    for _ in range(2):
        data = rng.standard_normal(A.nnz)
        M = pattern.matrix(data)
        ref = sp.csr_matrix((data, A.indices.copy(), A.indptr.copy()), shape=A.shape)
        assert np.array_equal(M.toarray(), ref.toarray())
        assert np.allclose(M @ x, ref @ x) and np.allclose(M.T @ x, ref.T @ x)
    # a structural change in place would corrupt every matrix of the pattern: it raises instead
    M = pattern.matrix(np.zeros(A.nnz))
    with pytest.raises(ValueError):
        M.eliminate_zeros()
    assert pattern.matrix(np.ones(A.nnz)).nnz == A.nnz
    with pytest.raises(ValueError, match="shape"):
        pattern.matrix(np.ones(A.nnz + 1))
    unsorted = A.indices.copy()
    unsorted[A.indptr[0]:A.indptr[1]] = unsorted[A.indptr[0]:A.indptr[1]][::-1]
    if A.indptr[1] - A.indptr[0] > 1:
        with pytest.raises(ValueError, match="canonical"):
            FixedPattern(unsorted, A.indptr, A.shape)


def test_to_banded_of_fixed_pattern_matrices_uses_the_right_positions():
    """The band positions cached for a fixed pattern give the band of each new matrix, not an old one."""
    from contin.numerics.linalg import FixedPattern, to_banded

    n = 40
    A = sp.diags([np.ones(n - 2), np.ones(n - 1), np.ones(n), np.ones(n - 1)], [-2, -1, 0, 1], format="csr")
    pattern = FixedPattern(A.indices, A.indptr, A.shape)
    rng = np.random.default_rng(1)
    for _ in range(3):
        data = rng.standard_normal(A.nnz)
        ref = sp.csr_matrix((data, A.indices.copy(), A.indptr.copy()), shape=A.shape)
        for extra in (0, 2):
            assert np.array_equal(to_banded(pattern.matrix(data), 2, 1, extra), to_banded(ref, 2, 1, extra))


@pytest.fixture(params=["compiled", "lapack"])
def banded_path(request, monkeypatch):
    """Runs a test with the C extension contin.numerics._banded and again with scipy's LAPACK (and numpy)."""
    from contin.numerics import linalg

    extension = linalg.banded_extension()
    if request.param == "compiled" and extension is None:
        pytest.skip("the C extension contin.numerics._banded is not built")
    monkeypatch.setattr(linalg, "_BANDED", [extension if request.param == "compiled" else None])
    return request.param


@pytest.mark.parametrize("n", [3, 5, 70, 300])
def test_tridiagonal_lu_solves_and_determinant_sign(n, banded_path):
    """gttrf/gttrs against a dense solve and numpy's slogdet (the sign decides fold detection)."""
    from contin.numerics.linalg import TridiagonalLU

    rng = np.random.default_rng(n)
    for _ in range(10):
        A = sp.diags([rng.standard_normal(n - 1), 0.3 * rng.standard_normal(n), rng.standard_normal(n - 1)],
                     [-1, 0, 1], format="csr")
        F = TridiagonalLU(A)
        b = rng.standard_normal(n)
        assert np.allclose(A @ F.solve(b), b) and np.allclose(A.T @ F.solve(b, trans=True), b)
        B = np.column_stack([b, -2 * b])
        assert np.allclose(A @ F.solve(B), B)
        sign, log = F.det_sign_log()
        ref_sign, ref_log = np.linalg.slogdet(A.toarray())
        assert sign == ref_sign and log == pytest.approx(ref_log, abs=1e-9)


def test_factorize_picks_the_tridiagonal_lu_and_flags_exact_singularity(banded_path):
    from contin.numerics.linalg import TridiagonalLU

    n = 200
    A = sp.diags([np.ones(n - 1), -2.0 * np.ones(n), np.ones(n - 1)], [-1, 0, 1], format="csr")
    assert isinstance(factorize(A), TridiagonalLU)
    singular = sp.diags([np.zeros(n - 1), np.r_[0.0, np.ones(n - 1)], np.zeros(n - 1)], [-1, 0, 1], format="csr")
    assert TridiagonalLU(singular).exactly_singular
    with pytest.raises(ValueError, match="at least 3"):
        TridiagonalLU(sp.eye(2, format="csr"))
    assert not isinstance(factorize(sp.eye(2, format="csr"), method="banded"), TridiagonalLU)


def test_tridiagonal_lu_with_no_right_hand_side(banded_path):
    """A bordered system with no border solves for zero columns (gttrs must not be called on them)."""
    from contin.numerics.linalg import TridiagonalLU

    n = 80
    F = TridiagonalLU(sp.diags([np.ones(n - 1), 3.0 * np.ones(n), np.ones(n - 1)], [-1, 0, 1], format="csr"))
    for _ in range(50):
        assert F.solve(np.zeros((n, 0))).shape == (n, 0)
        assert F.solve(np.zeros((n, 0)), trans=True).shape == (n, 0)
    with pytest.raises(ValueError, match="rows"):
        F.solve(np.ones(n + 1))


def test_compiled_tridiagonal_lu_is_lapacks_factorization(monkeypatch):
    """The C factorization is gttrf's (the same factors and pivots); the solves agree to rounding."""
    from contin.numerics import linalg

    extension = linalg.banded_extension()
    if extension is None:
        pytest.skip("the C extension contin.numerics._banded is not built")
    rng = np.random.default_rng(11)
    for n in (3, 4, 9, 200):
        # off-diagonals as large as the diagonal: rows are interchanged at about half the columns
        A = sp.diags([rng.standard_normal(n - 1), rng.standard_normal(n), rng.standard_normal(n - 1)], [-1, 0, 1],
                     format="dia")
        compiled = linalg.TridiagonalLU(A)
        monkeypatch.setattr(linalg, "_BANDED", [None])
        lapack = linalg.TridiagonalLU(A.tocsr())
        monkeypatch.setattr(linalg, "_BANDED", [extension])
        for name in ("_dl", "_d", "_du", "_du2", "_piv"):
            assert np.array_equal(getattr(compiled, name), getattr(lapack, name)), name
        assert 0 < np.count_nonzero(compiled._piv[:-1] != np.arange(n - 1)) or n < 9
        B = rng.standard_normal((n, 3))
        for trans in (False, True):
            x, y = compiled.solve(B, trans=trans), lapack.solve(B, trans=trans)
            np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * np.abs(y).max())
        assert compiled.det_sign_log() == lapack.det_sign_log()
    b = rng.standard_normal(5)
    kept = b.copy()
    linalg.TridiagonalLU(sp.diags([np.ones(4), 3 * np.ones(5), np.ones(4)], [-1, 0, 1])).solve(b)
    assert np.array_equal(b, kept)  # the right-hand side is not overwritten


@pytest.mark.parametrize("fmt", ["dia", "csr"])
def test_tridiagonal_lu_residual_and_norm_are_the_matrix_own(fmt, banded_path):
    """The residual f - A x a factorization gives, and the norm the bordered solver takes from it, are
    A's, on both paths; a matrix other than the factored one, or several columns, get the product."""
    from contin.numerics import linalg

    rng = np.random.default_rng(5)
    n = 60
    A = sp.diags([rng.standard_normal(n - 1), rng.standard_normal(n), rng.standard_normal(n - 1)], [-1, 0, 1],
                 format=fmt)
    dense = A.toarray()
    F = linalg.TridiagonalLU(A)
    x, f = rng.standard_normal(n), rng.standard_normal(n)
    for trans in (False, True):
        ref = f - (dense.T if trans else dense) @ x
        np.testing.assert_allclose(F.residual(A, f, x, trans), ref, rtol=0, atol=1e-13 * np.abs(ref).max())
    other = A * 2.0
    np.testing.assert_allclose(F.residual(other, f, x), f - 2.0 * dense @ x, atol=1e-12)
    X = rng.standard_normal((n, 2))
    np.testing.assert_allclose(F.residual(A, X, X), X - dense @ X, atol=1e-12)
    # strided vectors (columns of an array) are read as vectors, not refused
    np.testing.assert_allclose(F.residual(A, X[:, 0], X[:, 1]), X[:, 0] - dense @ X[:, 1], atol=1e-12)
    norm = linalg._inf_norm_of(A, F)
    assert norm == pytest.approx(np.abs(dense).sum(axis=1).max(), rel=1e-15)
    if banded_path == "compiled":  # the norm came with the factorization: not recomputed from the matrix
        assert F._inf_norm_memo[0] is A
    broken = A.copy()
    broken.data[broken.data.shape[0] // 2] = np.nan  # a diagonal (dia) or a few entries (csr) of NaN
    assert np.isnan(linalg._inf_norm_of(broken, linalg.TridiagonalLU(broken)))


@pytest.mark.parametrize("kd", [0, 1, 4])
def test_cholesky_band_solver_solves(kd, banded_path):
    """Solves with a band Cholesky factor (C for one right-hand side, LAPACK's pbtrs otherwise) against a
    dense solve, for the factor LAPACK's pbtrf and the band L D L^T leave."""
    from scipy.linalg import lapack

    from contin.numerics.linalg import SymmetricBand, cholesky_band_solver

    rng = np.random.default_rng(kd)
    n = 40
    M = rng.standard_normal((n, n))
    dense = M @ M.T + n * np.eye(n)
    dense[np.abs(np.subtract.outer(np.arange(n), np.arange(n))) > kd] = 0.0
    band = SymmetricBand.from_sparse(sp.csr_matrix(dense), kd)
    u, info = lapack.dpbtrf(band.ab, lower=0)
    assert info == 0
    columns, factor = band.negative_pivots()
    assert columns == [] and factor is not None
    for cholesky in (u, factor):
        solve = cholesky_band_solver(cholesky)
        b = rng.standard_normal(n)
        kept = b.copy()
        np.testing.assert_allclose(solve(b), np.linalg.solve(dense, b), rtol=1e-12, atol=1e-14)
        assert np.array_equal(b, kept)  # the right-hand side is not overwritten
        B = rng.standard_normal((n, 3))
        np.testing.assert_allclose(solve(B), np.linalg.solve(dense, B), rtol=1e-12, atol=1e-14)


def test_compiled_max_abs_is_numpys(monkeypatch):
    """The largest modulus over arrays, with and without the C pass: the same value, NaN kept."""
    from contin.numerics import linalg

    if linalg.banded_extension() is None:
        pytest.skip("the C extension contin.numerics._banded is not built")
    rng = np.random.default_rng(3)
    arrays = [rng.standard_normal(50), rng.standard_normal((7, 3)), np.arange(5), rng.standard_normal(40)[::2],
              np.zeros(0), np.array([-4.5])]
    for k in range(1, len(arrays) + 1):
        expected = max(float(np.abs(a).max()) for a in arrays[:k] if a.size)
        assert linalg._max_abs(*arrays[:k]) == expected
    with_nan = rng.standard_normal(30)
    with_nan[17] = np.nan
    assert np.isnan(linalg._max_abs(np.ones(3), with_nan))
    assert np.isnan(linalg.banded_extension().max_abs(with_nan))
    assert linalg.banded_extension().max_abs(np.full(9, -np.inf)) == np.inf


def test_symmetric_column_with_and_without_duplicate_entries():
    from contin.numerics.linalg import symmetric_column

    rng = np.random.default_rng(2)
    M = rng.standard_normal((12, 12))
    S = sp.csr_matrix(M + M.T)
    for j in (0, 5, 11):
        assert np.array_equal(symmetric_column(S, j), (M + M.T)[:, j])
    # duplicates (not canonical: row 3 stores column 4 twice) are summed, as the matrix means
    dup = sp.csr_matrix((np.array([1.0, 2.0, 3.0]), np.array([4, 4, 3]), np.array([0, 0, 0, 0, 2, 3, 3])),
                        shape=(6, 6))
    assert not dup.has_canonical_format
    assert symmetric_column(dup, 3)[4] == 3.0


# ---- arrow matrices: a band with a few dense border rows (an indenter's travel under a dead load) ----

def _arrow(n: int, m: int, negative: int, stiffness: float, seed: int = 0) -> sp.csr_matrix:
    """A stiff pentadiagonal operator (eigenvalues over decades) shifted to ``negative`` negative
    eigenvalues, with ``m`` border rows coupled to 40 random unknowns each."""
    rng = np.random.default_rng(seed)
    fourth = sp.diags([1.0, -4.0, 6.0, -4.0, 1.0], [-2, -1, 0, 1, 2], shape=(n, n)).toarray()
    second = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n)).toarray()
    A = stiffness * fourth + second
    if negative:
        A -= np.linalg.eigvalsh(A)[negative] * np.eye(n)
    for j in range(1, m + 1):
        row = np.zeros(n - m)
        row[rng.integers(0, n - m, size=40)] = rng.normal(size=40)
        A[-j, :n - m], A[:n - m, -j] = row, row
        A[-j, -j] = 10.0 * stiffness * (1.0 + rng.random())
    return sp.csr_matrix(A)


def test_arrow_structure_finds_the_border() -> None:
    from contin.numerics.linalg import arrow_structure

    assert arrow_structure(_arrow(300, 1, 0, 1e3)) == (2, 1)
    assert arrow_structure(_arrow(300, 2, 0, 1e3)) == (2, 2)
    band = sp.diags([1.0, 2.0, 1.0], [-1, 0, 1], shape=(300, 300), format="csr")
    assert arrow_structure(band) is None  # a band already
    assert arrow_structure(sp.csr_matrix(np.ones((300, 300)))) is None
    assert arrow_structure(np.eye(300)) is None  # dense storage


@pytest.mark.parametrize("m", [1, 2])
def test_arrow_cholesky_solves_and_refuses_an_indefinite_shift(m: int) -> None:
    from contin.numerics.linalg import ArrowCholesky, ArrowParts, arrow_structure

    H = _arrow(300, m, 2, 1e3)
    dense = H.toarray()
    lowest = np.linalg.eigvalsh(dense)[0]
    parts = ArrowParts(H, *arrow_structure(H))
    mu = -lowest * 1.001
    rhs = np.random.default_rng(1).normal(size=(300, 3))
    x = ArrowCholesky(parts, mu).solve(rhs)
    shifted = dense + mu * np.eye(300)
    # backward stable: the residual is rounding of |H| |x| (the shift puts H + mu I near singular)
    residual = np.abs(shifted @ x - rhs).max()
    assert residual <= 1e-12 * np.abs(shifted).sum(axis=1).max() * np.abs(x).max()
    np.testing.assert_allclose(x, np.linalg.solve(shifted, rhs), rtol=1e-6, atol=1e-9 * np.abs(x).max())
    assert ArrowCholesky(parts, mu).solve(rhs[:, 0]).shape == (300,)
    with pytest.raises(np.linalg.LinAlgError):
        ArrowCholesky(parts, -lowest * 0.999)


@pytest.mark.parametrize("m, negative, stiffness", [(1, 0, 1e4), (1, 1, 1e4), (2, 2, 1e6), (1, 3, 1e2), (2, 0, 1.0)])
def test_arrow_eigenpairs_agree_with_dense(m: int, negative: int, stiffness: float) -> None:
    from contin.numerics.linalg import arrow_structure
    from contin.numerics.stability import _arrow_info, stability_info

    H = _arrow(401, m, negative, stiffness, seed=m + negative)
    w, V = np.linalg.eigh(H.toarray())
    size = np.abs(H.data).max()
    info = _arrow_info(H, *arrow_structure(H), 2, True)
    assert info is not None  # the arrow route itself, not a fallback
    assert info.n_negative == int(np.count_nonzero(w < 0))
    np.testing.assert_allclose(info.eigenvalues, w[:2], rtol=0, atol=1e-12 * size)
    for i in range(max(2, info.n_negative)):
        assert abs(info.eigenvectors[:, i] @ V[:, i]) == pytest.approx(1.0, abs=1e-9)
    # stability_info takes that route for such a matrix, and gives the count alone as well
    assert stability_info(H, k=0).n_negative == info.n_negative
    np.testing.assert_allclose(stability_info(H, k=1).eigenvalues, w[:1], rtol=0, atol=1e-12 * size)


@pytest.mark.parametrize("m", [1, 2])
@pytest.mark.parametrize("corner", ["stiff", "soft"])
def test_inertias_of_an_arrow_matrix_come_from_its_band_and_schur_complement(m: int, corner: str, monkeypatch) -> None:
    """An arrow matrix with a positive definite band (a shell under an indenter's dead load before its
    limit load) is counted from the band's factorization and the border's Schur complement, not by the
    general sparse factorization; a soft corner makes the complement, and the whole matrix, indefinite."""
    from contin.numerics import stability

    H = _arrow(401, m, 0, 1e3, seed=m).toarray()
    if corner == "soft":
        H[-1, -1] = 1e-3
    sizes = (401 - m, 400, 401)
    expected = [int(np.count_nonzero(np.linalg.eigvalsh(H[:k, :k]) < 0)) for k in sizes]
    assert expected[-1] == (1 if corner == "soft" else 0)

    def general(_):
        raise AssertionError("the general sparse factorization was used")

    monkeypatch.setattr(stability, "_ldlt_pivots", general)
    assert stability.leading_inertias(sp.csr_matrix(H), sizes) == expected


def test_inertias_of_an_arrow_matrix_with_an_indefinite_band_are_counted_as_before() -> None:
    from contin.numerics.stability import leading_inertias

    H = _arrow(401, 1, 2, 1e3, seed=4).toarray()
    sizes = (200, 400, 401)
    assert leading_inertias(sp.csr_matrix(H), sizes) == [int(np.count_nonzero(np.linalg.eigvalsh(H[:k, :k]) < 0))
                                                         for k in sizes]


def test_inf_norm_of_every_storage_is_the_largest_absolute_row_sum() -> None:
    from contin.numerics.linalg import inf_norm

    rng = np.random.default_rng(5)
    dense = rng.standard_normal((30, 30)) * (rng.random((30, 30)) < 0.2)
    dense[7] = 0.0  # an empty row
    expected = float(np.abs(dense).sum(axis=1).max())
    for matrix in (dense, sp.csr_matrix(dense), sp.dia_matrix(dense), sp.csc_matrix(dense)):
        assert inf_norm(matrix) == pytest.approx(expected, rel=1e-14)
    assert inf_norm(sp.csr_matrix((0, 0))) == 0.0



@pytest.mark.parametrize("kd", [1, 4])
def test_upper_band_of_fixed_pattern_matrices_is_the_dense_upper_band(kd):
    """The cached positions of a fixed pattern give each new matrix's own upper band (Fortran-ordered, as
    pbtrf factorizes it in place), the same as the band of a plain CSR matrix; a band wider than kd is refused."""
    from contin.numerics.linalg import FixedPattern, SymmetricBand, upper_band

    rng = np.random.default_rng(kd)
    n = 30
    A, _ = _random_band(rng, n, kd, 0.0)
    S = sp.csr_matrix(A)
    pattern = FixedPattern(S.indices, S.indptr, S.shape)
    for _ in range(3):
        A, ab = _random_band(rng, n, kd, 0.0)
        data = sp.csr_matrix(A).data
        got = upper_band(pattern.matrix(data), kd)
        assert got.flags.f_contiguous
        inside = np.add.outer(np.arange(kd + 1), np.arange(n)) >= kd  # entries of the band inside the matrix
        assert np.array_equal(got[inside], ab[inside])
        assert np.array_equal(got[inside], upper_band(sp.csr_matrix(A), kd)[inside])
        assert np.array_equal(SymmetricBand(got).toarray(), A)
    with pytest.raises(ValueError, match="half-bandwidth"):
        upper_band(pattern.matrix(data), kd - 1)


def test_symmetric_band_factorization_solves_counts_and_signs_like_dense(banded_path):
    """Cholesky where the matrix is positive definite (index 0 read off the factorization), the banded LU
    otherwise: solves, determinant sign and log against a dense reference, and the Morse index the
    factorization reports (where it reports one) equals the count of negative eigenvalues."""
    from contin.numerics.linalg import BandedCholesky, BandedLU, symmetric_band_factorization

    rng = np.random.default_rng(7)
    kinds = set()
    for shift in (-1.5, 0.0, 4.0):
        for _ in range(30):
            n, kd = int(rng.integers(5, 50)), int(rng.integers(1, 6))
            A, _ = _random_band(rng, n, kd, shift)
            F = symmetric_band_factorization(sp.csr_matrix(A), kd)
            negative = int(np.count_nonzero(np.linalg.eigvalsh(A) < 0.0))
            assert isinstance(F, BandedCholesky if negative == 0 else BandedLU)
            kinds.add(type(F).__name__)
            index = F.symmetric_inertia()
            assert index is None or index == negative
            b, B = rng.standard_normal(n), rng.standard_normal((n, 2))
            np.testing.assert_allclose(F.solve(b), np.linalg.solve(A, b), rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(F.solve(B, trans=True), np.linalg.solve(A.T, B), rtol=1e-9, atol=1e-9)
            sign, log = np.linalg.slogdet(A)
            assert F.det_sign() == F.det_sign_log()[0] == sign
            assert F.det_sign_log()[1] == pytest.approx(log, rel=1e-10, abs=1e-10)
    assert kinds == {"BandedCholesky", "BandedLU"}


def test_banded_cholesky_refuses_a_matrix_that_is_not_positive_definite():
    from contin.numerics.linalg import BandedCholesky, NotPositiveDefiniteError, SymmetricBand

    ab = np.array([[0.0, 1.0, 0.5], [1.0, 1.0, 2.0]])  # [[1, 1, 0], [1, 1, .5], [0, .5, 2]]: singular leading block
    with pytest.raises(NotPositiveDefiniteError):
        BandedCholesky(SymmetricBand(ab))
    ab[1, 1] = 3.0
    F = BandedCholesky(SymmetricBand(ab))
    assert F.symmetric_inertia() == 0
    np.testing.assert_allclose(F.pivots(), np.linalg.cholesky(SymmetricBand(ab).toarray()).diagonal() ** 2)
