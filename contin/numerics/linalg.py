"""Structure-aware linear algebra for continuation.

Every Newton step of a continuation method solves a *bordered* system

    [ A  B ] [x]   [f]
    [ C  D ] [z] = [g]

where ``A`` is the model's sparse Jacobian (n x n) and the borders ``B`` (n x k), ``C`` (k x n),
``D`` (k x k) are dense and thin (k = 1 for equilibrium continuation with the arclength row, 2 for a
fold extended system, ...).  Factorizing the whole bordered matrix with a general sparse LU destroys
the structure of ``A`` (a dense row and column cause fill), so the bordered system is solved by block
elimination on a factorization of ``A`` alone, followed by iterative refinement on the full system.
When ``A`` is (numerically) singular -- as it is at a fold -- block elimination loses accuracy; the
refinement detects it and the solver falls back to a direct factorization of the full matrix.

Factorizations report the sign and the logarithm of the modulus of their determinant, never the
determinant itself, so that branch-point tests cannot overflow.
"""

from __future__ import annotations

import warnings

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.linalg import lapack

from ..lazy import lazy_module

# imported on first use: the sparse LU and the graph orderings are fallbacks the banded paths never reach
csgraph = lazy_module("scipy.sparse.csgraph")
spla = lazy_module("scipy.sparse.linalg")

__all__ = [
    "Factorization",
    "DenseLU",
    "BandedLU",
    "BandedCholesky",
    "NotPositiveDefiniteError",
    "symmetric_band_factorization",
    "upper_band",
    "TridiagonalLU",
    "SparseLU",
    "SymmetricBand",
    "cholesky_band_solver",
    "factorize",
    "bandwidths",
    "to_banded",
    "FixedPattern",
    "symmetric_column",
    "same_values",
    "banded_extension",
    "BorderedSolver",
    "SingularMatrixError",
    "lower_band",
    "arrow_structure",
    "inf_norm",
    "ArrowParts",
    "ArrowCholesky",
]

#: Below this size a dense LU is cheaper than anything clever.
DENSE_LIMIT = 64
#: Banded storage is used when (kl + ku + 1) is at most this fraction of n.
BANDED_FRACTION = 0.25


class SingularMatrixError(np.linalg.LinAlgError):
    """Raised when a matrix is exactly singular or a solve produces non-finite numbers."""


def _permutation_parity(perm: np.ndarray) -> int:
    """Return +1 for an even permutation and -1 for an odd one (O(n), vectorised)."""
    n = perm.size
    if n == 0:
        return 1
    graph = sp.csr_matrix((np.ones(n), (np.arange(n), perm)), shape=(n, n))
    n_cycles, _ = csgraph.connected_components(graph, directed=True, connection="weak")
    return -1 if (n - n_cycles) % 2 else 1


def _ipiv_parity(ipiv: np.ndarray) -> int:
    """Parity of the row interchanges recorded by LAPACK (0-based ``ipiv`` as returned by scipy)."""
    swaps = np.count_nonzero(ipiv != np.arange(ipiv.size))
    return -1 if swaps % 2 else 1


def _sign_from_diagonal(diag: np.ndarray, parity: int) -> float:
    if not diag.all():
        return 0.0
    return float(parity * (-1 if np.count_nonzero(diag < 0) % 2 else 1))


def _sign_log_from_diagonal(diag: np.ndarray, parity: int) -> tuple[float, float]:
    sign = _sign_from_diagonal(diag, parity)
    if sign == 0.0:
        return 0.0, -np.inf
    return sign, float(np.sum(np.log(np.abs(diag))))


#: Largest multiplier ``|a_jk| / |d_j|`` a pivot-free ``L D L^T`` may meet before its count of negative
#: pivots is no longer trusted (element growth makes the later pivots' signs unreliable).
PIVOT_FREE_GROWTH_LIMIT = 1e8


class Factorization:
    """A factorized square matrix: solves and the sign / log-modulus of the determinant."""

    n: int

    def solve(self, b: np.ndarray, trans: bool = False) -> np.ndarray:  # pragma: no cover - interface
        """Solve ``A x = b`` (or ``A^T x = b`` if ``trans``); ``b`` may have several columns."""
        raise NotImplementedError

    def det_sign_log(self) -> tuple[float, float]:  # pragma: no cover - interface
        """Return ``(sign, log|det|)``; the sign is 0 for an exactly singular matrix."""
        raise NotImplementedError

    def det_sign(self) -> float:
        """The sign of the determinant alone (0 for an exactly singular matrix), without its logarithm."""
        return self.det_sign_log()[0]

    def symmetric_inertia(self) -> int | None:
        """Negative eigenvalues of the factorized matrix, read off the factors when that is exact, else None.

        For a *symmetric* matrix factorized without row interchanges, ``U``'s diagonal is the ``D`` of
        its ``L D L^T`` and Sylvester's law of inertia counts the negative eigenvalues as the negative
        pivots.  The caller vouches for the symmetry; any interchange (or a zero pivot) gives None.
        """
        piv, diag = self._row_interchanges(), None
        if piv is None:
            return None
        diag = self.pivots()
        if np.count_nonzero(piv != np.arange(piv.size)) or not diag.all():
            return None
        return int(np.count_nonzero(diag < 0.0))

    def _row_interchanges(self) -> np.ndarray | None:
        """The 0-based row interchanges of an LU factorization (None for other factorizations)."""
        return None

    def residual(self, A, f: np.ndarray, x: np.ndarray, trans: bool = False) -> np.ndarray:
        """``f - A x`` (``f - A^T x`` if ``trans``) for the matrix ``A`` this factorizes.

        The product is ``A``'s own: a solve is checked against the matrix, not against its factors.
        A factorization that kept ``A``'s entries may compute it faster (:class:`TridiagonalLU`).
        """
        return f - (A.T @ x if trans else A @ x)

    def _check(self, x: np.ndarray) -> np.ndarray:
        if not np.isfinite(x).all():
            raise SingularMatrixError("linear solve produced non-finite values (singular matrix)")
        return x


class DenseLU(Factorization):
    """LU with partial pivoting of a dense matrix (LAPACK getrf)."""

    def __init__(self, A) -> None:
        A = A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)
        self.n = A.shape[0]
        if self.n == 0:
            self._lu, self._piv = A, np.zeros(0, dtype=int)
            return
        self._lu, self._piv, info = lapack.dgetrf(A)
        self.exactly_singular = info > 0

    def solve(self, b, trans=False):
        if self.n == 0:
            return np.asarray(b, dtype=float).copy()
        x, info = lapack.dgetrs(self._lu, self._piv, b, trans=1 if trans else 0)
        return self._check(x)

    def _row_interchanges(self) -> np.ndarray:
        return self._piv

    def pivots(self) -> np.ndarray:
        """Diagonal of the U factor."""
        return np.diag(self._lu)

    def det_sign_log(self):
        if self.n == 0:
            return 1.0, 0.0
        return _sign_log_from_diagonal(self.pivots(), _ipiv_parity(self._piv))

    def det_sign(self):
        return 1.0 if self.n == 0 else _sign_from_diagonal(self.pivots(), _ipiv_parity(self._piv))


def bandwidths(A) -> tuple[int, int]:
    """Return the lower and upper bandwidths ``(kl, ku)`` of a sparse or dense matrix."""
    if sp.issparse(A) and A.format == "dia":
        # a dia matrix has a few diagonals: a Python loop over them costs less than numpy's calls over all
        offs = [off for off, row in zip(A.offsets.tolist(), A.data) if row.any()]
        if not offs:
            return 0, 0
        return max(0, -min(offs)), max(0, max(offs))
    if sp.issparse(A) and A.format == "csr" and A.has_canonical_format:
        return _pattern_memo(A, ("bandwidths",), lambda: _csr_bandwidths(A))
    if sp.issparse(A):
        coo = A.tocoo()
        if coo.nnz == 0:
            return 0, 0
        off = coo.row.astype(np.int64) - coo.col.astype(np.int64)
    else:
        r, c = np.nonzero(np.asarray(A))
        if r.size == 0:
            return 0, 0
        off = r.astype(np.int64) - c
    return int(max(off.max(), 0)), int(max(-off.min(), 0))


class FixedPattern:
    """CSR matrices of one fixed sparsity pattern, made from their values alone.

    A model whose Jacobian keeps its pattern from state to state makes every matrix here instead of
    through ``scipy.sparse.csr_matrix((data, indices, indptr))``: scipy validates the index arrays
    on each construction (about 12 microseconds, as long as the rest of a small Jacobian's assembly
    together), while a matrix of a known pattern needs none of it (about 2 microseconds).  The
    matrices share this pattern's index arrays, which are read-only: an operation that would change
    a matrix's structure in place raises instead of changing every other matrix.

    Parameters
    ----------
    indices, indptr : ndarray
        The pattern in canonical CSR form (sorted column indices, no duplicates).
    shape : (int, int)
    """

    def __init__(self, indices: np.ndarray, indptr: np.ndarray, shape: tuple[int, int]) -> None:
        template = sp.csr_matrix((np.zeros(len(indices)), np.array(indices, copy=True),
                                  np.array(indptr, copy=True)), shape=shape)
        if not template.has_canonical_format:
            raise ValueError("FixedPattern: the pattern must be canonical (sorted indices, no duplicates)")
        template.indices.setflags(write=False)
        template.indptr.setflags(write=False)
        self._template = template
        self.shape = template.shape
        self.nnz = template.nnz

    @property
    def indices(self) -> np.ndarray:
        """Column indices (read-only)."""
        return self._template.indices

    @property
    def indptr(self) -> np.ndarray:
        """Row pointers (read-only)."""
        return self._template.indptr

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        """The matrix of this pattern with values ``data`` (shape ``(nnz,)``, used without a copy)."""
        data = np.asarray(data, dtype=float)
        if data.shape != (self.nnz,):
            raise ValueError(f"FixedPattern.matrix: data must have shape ({self.nnz},), got {data.shape}")
        # a shallow copy of the template without copy.copy's protocol (0.3 against 1.7 us)
        A = object.__new__(type(self._template))
        A.__dict__.update(self._template.__dict__)
        A.data = data
        return A


#: Band positions of the last few patterns seen by :func:`to_banded` and :func:`upper_band`, by the identity
#: of their read-only index arrays (the matrices of a :class:`FixedPattern` share them, and they cannot change).
_BAND_POSITIONS: list[tuple[np.ndarray, np.ndarray, tuple, Any]] = []


def _pattern_memo(A, key: tuple, compute: Callable[[], Any]) -> Any:
    """``compute()`` for the canonical CSR matrix ``A``, remembered for its pattern when the index arrays
    are read-only (a :class:`FixedPattern`'s: they cannot change, so their identity names the pattern)."""
    for indices, indptr, k, value in _BAND_POSITIONS:
        if indices is A.indices and indptr is A.indptr and k == key:
            return value
    value = compute()
    if not (A.indices.flags.writeable or A.indptr.flags.writeable):
        _BAND_POSITIONS.insert(0, (A.indices, A.indptr, key, value))
        del _BAND_POSITIONS[6:]
    return value


def _band_positions(A, kl: int, ku: int, extra_rows: int) -> np.ndarray:
    """Flat positions in band storage of the stored entries of the canonical CSR matrix ``A``."""
    def compute() -> np.ndarray:
        n = A.shape[0]
        rows = np.repeat(np.arange(n), np.diff(A.indptr))
        return (extra_rows + ku + rows - A.indices) * n + A.indices

    return _pattern_memo(A, ("general", kl, ku, extra_rows), compute)


def upper_band(A, kd: int) -> np.ndarray:
    """The upper band of the symmetric sparse ``A`` in LAPACK's storage, ``ab[kd + i - j, j] = A[i, j]`` for
    ``j - kd <= i <= j``, Fortran-ordered (``pbtrf`` factorizes it in place); only the upper triangle is read.

    For a canonical CSR matrix of a :class:`FixedPattern` the entries' positions are computed once per pattern.
    """
    n = A.shape[0]
    ab = np.zeros((kd + 1, n), order="F")
    if sp.issparse(A) and A.format == "csr" and A.has_canonical_format:
        def compute() -> tuple[np.ndarray, np.ndarray]:
            rows = np.repeat(np.arange(n, dtype=np.int64), np.diff(A.indptr))
            cols = A.indices.astype(np.int64)
            upper = np.flatnonzero(cols >= rows)
            if upper.size and int(np.max(cols[upper] - rows[upper])) > kd:
                raise ValueError(f"upper_band: the matrix has entries beyond the half-bandwidth kd = {kd}")
            # Fortran order: entry (r, c) of the (kd + 1, n) array lies at c (kd + 1) + r
            return upper, cols[upper] * (kd + 1) + kd + rows[upper] - cols[upper]

        upper, positions = _pattern_memo(A, ("upper", kd), compute)
        ab.T.reshape(-1)[positions] = A.data[upper]  # ab.T is C-contiguous: a view
        return ab
    return np.asfortranarray(SymmetricBand.from_sparse(A, kd).ab)


def same_values(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two arrays hold the same shape, dtype and bytes: the key test of a state cache.

    Stricter than ``np.array_equal`` (``-0.0`` differs from ``0.0``; equal NaN bits match), which a
    cache only pays for with a recomputation, and about six times faster for a state vector of a few
    hundred entries (0.3 against 1.8 us).
    """
    if a is b:
        return True
    a = a if isinstance(a, np.ndarray) else np.asarray(a)
    b = b if isinstance(b, np.ndarray) else np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def symmetric_column(H: sp.csr_matrix, j: int) -> np.ndarray:
    """Dense column ``j`` of a symmetric CSR matrix, read as its row ``j`` (no transpose, no column slicing)."""
    lo, hi = H.indptr[j], H.indptr[j + 1]
    col = np.zeros(H.shape[0])
    if H.has_canonical_format:  # no duplicate entries: a plain assignment (np.add.at is slow)
        col[H.indices[lo:hi]] = H.data[lo:hi]
    else:
        np.add.at(col, H.indices[lo:hi], H.data[lo:hi])
    return col


def to_banded(A, kl: int, ku: int, extra_rows: int = 0) -> np.ndarray:
    """Copy ``A`` into LAPACK band storage with ``extra_rows`` leading zero rows (``kl`` for gbtrf)."""
    n = A.shape[0]
    ab = np.zeros((extra_rows + kl + ku + 1, n))
    if sp.issparse(A) and A.format == "dia":
        for off, data in zip(A.offsets, A.data):
            # dia data[j] holds A[j - off, j]
            ab[extra_rows + ku - off, :] += data[:n]
        if ab.shape[0]:
            # entries of dia storage that fall outside the matrix must not leak in
            for off in A.offsets:
                row = extra_rows + ku - off
                if off > 0:
                    ab[row, :off] = 0.0
                elif off < 0:
                    ab[row, n + off:] = 0.0
        return ab
    if sp.issparse(A) and A.format == "csr" and A.has_canonical_format:
        # no duplicate entries: a plain scatter (np.add.at is several times slower)
        ab.reshape(-1)[_band_positions(A, kl, ku, extra_rows)] = A.data  # a view: .flat is 6 times slower
        return ab
    coo = A.tocoo() if sp.issparse(A) else sp.coo_matrix(np.asarray(A))
    np.add.at(ab, (extra_rows + ku + coo.row - coo.col, coo.col), coo.data)
    return ab


class BandedLU(Factorization):
    """LU with partial pivoting in LAPACK band storage (gbtrf): O(n (kl + ku)^2) work."""

    def __init__(self, A, kl: int | None = None, ku: int | None = None) -> None:
        if isinstance(A, SymmetricBand):
            kl = ku = A.kd
            ab = A.general_band(extra_rows=kl)
        else:
            if kl is None or ku is None:
                kl, ku = bandwidths(A)
            ab = to_banded(A, kl, ku, extra_rows=kl)
        self.n = A.shape[0]
        self.kl, self.ku = kl, ku
        self._lu, self._piv, info = lapack.dgbtrf(ab, kl, ku)
        self.exactly_singular = info > 0

    def solve(self, b, trans=False):
        x, info = lapack.dgbtrs(self._lu, self.kl, self.ku, b, self._piv, trans=1 if trans else 0)
        return self._check(x)

    def _row_interchanges(self) -> np.ndarray:
        return self._piv

    def pivots(self) -> np.ndarray:
        """Diagonal of the U factor."""
        return self._lu[self.kl + self.ku, :]

    def det_sign_log(self):
        return _sign_log_from_diagonal(self.pivots(), _ipiv_parity(self._piv))

    def det_sign(self):
        return _sign_from_diagonal(self.pivots(), _ipiv_parity(self._piv))


class BandedCholesky(Factorization):
    """Cholesky factorization ``A = U^T U`` of a symmetric positive definite banded matrix (LAPACK ``pbtrf``).

    A fraction of the work of the banded LU of the same matrix (no pivoting, one triangle), and exact
    inertia for free: a factorization that exists says that ``A`` has no negative eigenvalue.  Only the
    upper triangle of ``A`` is read.  Most callers want :func:`symmetric_band_factorization`, which falls
    back to the banded LU where ``A`` is not positive definite.

    Parameters
    ----------
    A : sparse matrix or SymmetricBand
        The symmetric matrix.
    kd : int, optional
        Its half-bandwidth (default: measured).

    Raises
    ------
    NotPositiveDefiniteError
        When a pivot is not positive (``A`` is indefinite, singular, or not a number).
    """

    def __init__(self, A, kd: int | None = None) -> None:
        if isinstance(A, SymmetricBand):
            kd, ab = A.kd, np.array(A.ab, dtype=float, order="F")
        else:
            kd = max(bandwidths(A)) if kd is None else int(kd)
            ab = upper_band(A, kd)
        self.n = A.shape[0]
        self.kd = kd
        self._factor, info = lapack.dpbtrf(ab, lower=0, overwrite_ab=1)
        if info != 0:
            raise NotPositiveDefiniteError(f"banded Cholesky: pivot {info} of {self.n} is not positive")
        self.exactly_singular = False
        self._solve = cholesky_band_solver(self._factor)

    def solve(self, b, trans=False):
        # A is symmetric: A^T x = b is A x = b
        return self._check(self._solve(np.asarray(b, dtype=float)))

    def pivots(self) -> np.ndarray:
        """The pivots ``d`` of ``A = L D L^T``: the squares of ``U``'s diagonal."""
        return self._factor[self.kd] ** 2

    def symmetric_inertia(self) -> int | None:
        """0: a positive definite matrix has no negative eigenvalue."""
        return 0

    def det_sign_log(self):
        return 1.0, 2.0 * float(np.sum(np.log(self._factor[self.kd])))

    def det_sign(self):
        return 1.0


class NotPositiveDefiniteError(np.linalg.LinAlgError):
    """Raised by :class:`BandedCholesky` for a matrix that is not positive definite."""


def symmetric_band_factorization(A, kd: int | None = None) -> Factorization:
    """The cheapest exact factorization of the symmetric banded matrix ``A``: :class:`BandedCholesky` where it
    is positive definite, else the banded LU with partial pivoting (:class:`BandedLU`).

    Along a stable branch every Jacobian is positive definite and costs the Cholesky alone; an
    indefinite one costs the Cholesky up to its first non-positive pivot and the LU.  The caller vouches
    for the symmetry (only the upper triangle decides which factorization is used).  ``A`` and ``kd`` are
    those of :class:`BandedCholesky`.

    Returns
    -------
    Factorization
        A :class:`BandedCholesky` or a :class:`BandedLU`.
    """
    if isinstance(A, SymmetricBand):
        kd = A.kd
    elif kd is None:
        kd = max(bandwidths(A))
    try:
        return BandedCholesky(A, kd)
    except NotPositiveDefiniteError:
        return BandedLU(A, kd, kd)


class TridiagonalLU(Factorization):
    """LU with partial pivoting of a tridiagonal matrix (LAPACK's gttrf): O(n), no band bookkeeping.

    What :class:`BandedLU` computes for ``kl = ku = 1``, faster: with the C extension
    ``contin.numerics._banded`` (built by the install where a compiler is found) the factorization is
    gttrf's and the solves are gttrs's algorithm multiplying by the pivots' reciprocals instead of
    dividing (at n = 2000, :meth:`solve` 13 against 30 us, of which the C call 10 and dgttrs 27); elsewhere
    scipy's LAPACK dgttrf/dgttrs (``CONTIN_COMPILED=0`` keeps them).
    """

    def __init__(self, A) -> None:
        self.n = A.shape[0]
        if self.n < 3:  # scipy's gttrs wrapper needs the second superdiagonal (n - 2 entries) non-empty
            raise ValueError(f"TridiagonalLU: the matrix must be at least 3 x 3, got {A.shape}")
        compiled = banded_extension()
        if compiled is not None:
            # A's entries, kept beside the factors, give the bordered solver (on this factorization)
            # A's norm now and its residuals later in one C pass each, where the dia matrix costs numpy
            # calls per diagonal and scipy's product (see _inf_norm_of)
            self._matrix, self._source = _tridiagonals(A, copy=False), A
            self._inf_norm_memo = (A, compiled.inf_norm(*self._matrix))
            dl, d, du = (a.copy() for a in self._matrix)
            self._du2, self._piv, self._rd = np.empty(self.n - 2), np.empty(self.n, dtype=np.int64), np.empty(self.n)
            info = compiled.factor(dl, d, du, self._du2, self._piv, self._rd)  # rd[k] = inf for a zero pivot
            self._compiled = compiled
        else:
            dl, d, du, self._du2, piv, info = lapack.dgttrf(*_tridiagonals(A))
            self._piv = piv - 1  # scipy returns gttrf's pivots 1-based (getrf's and gbtrf's are made 0-based)
            self._compiled = None
        self._dl, self._d, self._du = dl, d, du
        self.exactly_singular = info > 0

    def solve(self, b, trans=False):
        b = np.asarray(b, dtype=float)
        if b.shape[0] != self.n:
            raise ValueError(f"TridiagonalLU.solve: b has {b.shape[0]} rows, the matrix {self.n}")
        if b.size == 0:  # no right-hand side: scipy's gttrs wrapper would write past an empty array
            return b.copy()
        if self._compiled is not None and b.ndim <= 2:
            x = np.array(b, dtype=float, order="C")
            self._compiled.solve(self._dl, self._rd, self._du, self._du2, self._piv, x, bool(trans))
            return self._check(x)
        x, info = lapack.dgttrs(self._dl, self._d, self._du, self._du2, self._piv + 1, b,
                                trans="T" if trans else "N")
        return self._check(x)

    def residual(self, A, f, x, trans=False):
        if self._compiled is None or A is not self._source or x.ndim != 1 or f.ndim != 1:
            return super().residual(A, f, x, trans)
        out = np.empty(self.n)
        # contiguous copies of strided vectors (a column of a caller's array): the C code reads them flat
        self._compiled.residual(*self._matrix, np.ascontiguousarray(x, dtype=float),
                                np.ascontiguousarray(f, dtype=float), out, bool(trans))
        return out

    def symmetric_inertia(self) -> int | None:
        """As :meth:`Factorization.symmetric_inertia`; after row interchanges, the pivot-free count on the
        matrix's own diagonals (kept beside the factors), without building the matrix again."""
        counted = super().symmetric_inertia()
        if counted is not None or self._compiled is None:
            return counted
        _, d, du = self._matrix
        # the same checks as SymmetricBand.negative_pivots, on the diagonals as they are
        scale = self._compiled.max_abs(d)
        counted = self._compiled.sturm_count(d, du, PIVOT_FREE_GROWTH_LIMIT, 1e-14 * scale)
        return None if counted < 0 else counted

    def _row_interchanges(self) -> np.ndarray:
        return self._piv

    def pivots(self) -> np.ndarray:
        """Diagonal of the U factor."""
        return self._d

    def det_sign_log(self):
        return _sign_log_from_diagonal(self._d, _ipiv_parity(self._piv))

    def det_sign(self):
        return _sign_from_diagonal(self._d, _ipiv_parity(self._piv))


def _tridiagonals(A, copy: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sub-, main and superdiagonal of a tridiagonal ``A`` as contiguous float arrays: new ones, or
    with ``copy=False`` views of a dia matrix's own data where they are such (read, do not write)."""
    n = A.shape[0]
    if sp.issparse(A) and A.format == "dia" and len(A.offsets) == len(set(A.offsets.tolist())) \
            and set(A.offsets.tolist()) <= {-1, 0, 1} and A.data.shape[1] >= n:
        # dia data[k, j] holds A[j - offsets[k], j]: the diagonals without a band copy
        rows = dict(zip(A.offsets.tolist(), A.data))
        zeros = np.zeros(n)
        diagonals = rows.get(-1, zeros)[:n - 1], rows.get(0, zeros)[:n], rows.get(1, zeros)[1:n]
        if copy:
            return tuple(a.astype(float, copy=True) for a in diagonals)
        return tuple(np.ascontiguousarray(a, dtype=float) for a in diagonals)
    ab = to_banded(A, 1, 1)  # rows: super-, main and sub-diagonal
    return ab[2, :-1].copy(), ab[1].copy(), ab[0, 1:].copy()


_BANDED: list = []


def banded_extension() -> Any:
    """The C extension module ``contin.numerics._banded`` (the tridiagonal LU's and the band L D L^T's C code),
    or None when it is not built or ``CONTIN_COMPILED=0``: for tests and for instrumenting its calls
    (``studies.bench_floor``)."""
    if not _BANDED:
        from .compiled import optional_extension

        _BANDED.append(optional_extension("contin.numerics._banded"))
    return _BANDED[0]


def cholesky_band_solver(u: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """Solves with ``U^T U`` for the upper band Cholesky factor ``u`` (LAPACK's storage, as ``pbtrf`` and
    :meth:`SymmetricBand.negative_pivots` leave it): ``solve(r)`` for ``r`` of one or several columns.

    One right-hand side runs in C (``contin.numerics._banded.cholesky_solve``) where it is built: scipy's
    ``dpbtrs`` wrapper costs more per call than the solve itself on a narrow band.
    """
    from scipy.linalg import lapack

    compiled = banded_extension()
    factor = np.asarray(u, dtype=float, order="F")
    reciprocals = 1.0 / factor[-1] if compiled is not None else None

    def solve(r: np.ndarray) -> np.ndarray:
        if compiled is not None and np.ndim(r) == 1:
            x = np.array(r, dtype=float)
            compiled.cholesky_solve(factor, reciprocals, x)
            return x
        return lapack.dpbtrs(factor, r, lower=0)[0]
    return solve


def _csr_bandwidths(A) -> tuple[int, int]:
    """:func:`bandwidths` of a canonical CSR matrix, from its row pointers (no COO copy)."""
    if A.nnz == 0:
        return 0, 0
    off = np.repeat(np.arange(A.shape[0], dtype=np.int64), np.diff(A.indptr)) - A.indices.astype(np.int64)
    return int(max(off.max(), 0)), int(max(-off.min(), 0))


def lower_band(H, b: int) -> np.ndarray:
    """The lower band of the symmetric ``H`` (sparse or dense) in LAPACK storage: ``ab[i - j, j] = H[i, j]``."""
    n = H.shape[0]
    coo = sp.tril(H, format="coo") if sp.issparse(H) else sp.coo_matrix(np.tril(np.asarray(H)))
    ab = np.zeros((b + 1, n))
    np.add.at(ab, (coo.row - coo.col, coo.col), coo.data)
    return ab


#: Most trailing dense rows (and columns) :func:`arrow_structure` looks for.
ARROW_MAX_BORDER = 2


def arrow_structure(H) -> tuple[int, int] | None:
    """``(b, m)`` when the sparse symmetric ``H`` is a narrow band except for its last ``m`` rows and columns.

    Such an *arrow* matrix is a structure's Hessian with a few unknowns coupled to many nodes (the
    travel of an indenter under a dead load touches every node in contact).  ``b`` is the half
    bandwidth of the leading ``n - m`` block, which must be at most a tenth of it (the band pays);
    ``m`` the smallest such border, up to :data:`ARROW_MAX_BORDER`.  None when ``H`` is dense, already
    banded itself, or of no such form.
    """
    if not sp.issparse(H):
        return None
    n = H.shape[0]
    if H.format == "csr":  # the entries' rows straight from the row pointers, without a COO copy
        rows, cols = np.repeat(np.arange(n, dtype=np.int64), np.diff(H.indptr)), H.indices.astype(np.int64)
    else:
        coo = H.tocoo()
        rows, cols = coo.row.astype(np.int64), coo.col.astype(np.int64)
    distance = np.abs(rows - cols)
    if distance.size == 0 or int(distance.max()) + 1 <= 0.1 * n:
        return None
    for m in range(1, ARROW_MAX_BORDER + 1):
        lead = n - m
        inside = (rows < lead) & (cols < lead)
        b = int(distance[inside].max(initial=0))
        if lead > 0 and b + 1 <= 0.1 * lead:
            return b, m
    return None


class ArrowParts:
    """The blocks of a symmetric arrow matrix ``[[A, B], [B^T, C]]`` (:func:`arrow_structure`), taken once.

    ``band`` is ``A``'s lower band in LAPACK storage (``band[i - j, j] = A[i, j]``), ``border`` is
    ``B`` and ``corner`` is ``C``, both dense.  Several shifts of one matrix
    (:class:`ArrowCholesky`) share them.
    """

    def __init__(self, H, b: int, m: int) -> None:
        n = H.shape[0]
        self.lead = lead = n - m
        csr = sp.csr_matrix(H)
        self.band = lower_band(csr[:lead, :lead], b)
        self.border = csr[:lead, lead:].toarray()
        self.corner = csr[lead:, lead:].toarray()


class ArrowCholesky:
    """Cholesky factorization of a symmetric arrow matrix plus a shift, ``H + mu I`` (:func:`arrow_structure`).

    ``H + mu I = [[A, B], [B^T, C]]`` with ``A`` banded: ``A = L L^T`` in band storage, then the
    Schur complement ``S = C - B^T A^-1 B`` (``m x m``) densely.  ``H + mu I`` is positive definite
    exactly when both factorizations succeed, so a failure raises :class:`numpy.linalg.LinAlgError`,
    as ``scipy.linalg.cho_factor`` does for a dense matrix.  O(n b^2 + n b m) work.

    Parameters
    ----------
    parts : ArrowParts
        The matrix's blocks (``ArrowParts(H, b, m)``).
    mu : float
        The shift.
    """

    def __init__(self, parts: ArrowParts, mu: float = 0.0) -> None:
        self.lead = parts.lead
        self._border = parts.border
        band = parts.band.copy()
        band[0] += mu
        self._band = sla.cholesky_banded(band, lower=True)
        self._a_inv_border = sla.cho_solve_banded((self._band, True), parts.border)
        schur = parts.corner + mu * np.eye(parts.corner.shape[0]) - parts.border.T @ self._a_inv_border
        self._schur = sla.cho_factor(0.5 * (schur + schur.T), lower=True)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``(H + mu I)^-1 rhs`` for a vector or the columns of a matrix, by block elimination."""
        rhs = np.asarray(rhs, dtype=float)
        top = sla.cho_solve_banded((self._band, True), rhs[:self.lead])
        tail = sla.cho_solve(self._schur, rhs[self.lead:] - self._border.T @ top)
        return np.concatenate([top - self._a_inv_border @ tail, tail])


class SymmetricBand:
    """A symmetric banded matrix held in LAPACK's upper band storage.

    ``ab[kd + i - j, j] = A[i, j]`` for ``j - kd <= i <= j`` (``kd`` the half-bandwidth): the form
    LAPACK's symmetric band routines (``pbtrf``, ``sbmv``, ``sbevx``) take without a copy into another
    layout.  An operator that is assembled straight into this storage skips the sparse formats
    altogether; :mod:`contin.watch.modes` and :func:`factorize` accept it, and :meth:`tocsr` gives the rest
    of the toolkit a sparse matrix.

    Parameters
    ----------
    ab : ndarray, shape ``(kd + 1, n)``
        The upper band (entries outside the matrix, ``ab[kd - k, :k]``, are ignored).
    """

    def __init__(self, ab: np.ndarray) -> None:
        ab = np.asarray(ab, dtype=float)
        if ab.ndim != 2 or ab.shape[0] < 1:
            raise ValueError(f"SymmetricBand: ab must have shape (kd + 1, n), got {ab.shape}")
        self.ab = ab

    @property
    def shape(self) -> tuple[int, int]:
        """``(n, n)``."""
        return self.ab.shape[1], self.ab.shape[1]

    @property
    def kd(self) -> int:
        """Half-bandwidth."""
        return self.ab.shape[0] - 1

    def diagonal(self) -> np.ndarray:
        """The main diagonal (a copy)."""
        return self.ab[-1].copy()

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.ndim == 1:
            from scipy.linalg import blas

            return blas.dsbmv(self.kd, 1.0, self.ab, x, lower=0)
        return np.column_stack([self @ x[:, j] for j in range(x.shape[1])])

    def scaled(self, s: np.ndarray) -> "SymmetricBand":
        """``diag(s) A diag(s)``."""
        s = np.asarray(s, dtype=float)
        kd, n = self.kd, self.shape[0]
        ab = self.ab.copy()
        for k in range(1, kd + 1):  # row kd - k holds A[j - k, j]
            ab[kd - k, k:] *= s[:n - k] * s[k:]
        ab[kd] *= s * s
        return SymmetricBand(ab)

    @classmethod
    def from_sparse(cls, A, kd: int | None = None) -> "SymmetricBand":
        """The upper band of a symmetric sparse (or dense) matrix; ``kd`` defaults to its bandwidth.

        Only the upper triangle is read: the matrix is taken to be symmetric, not checked.
        """
        n = A.shape[0]
        if sp.issparse(A) and A.format == "dia" and A.shape[1] == n:
            # the diagonals are stored by column (A[j - k, j] = data[., j] for offset k): copied as they are
            offsets = [int(k) for k in A.offsets]
            if kd is None:
                kd = max([k for k in offsets if k >= 0], default=0)
            if len(set(offsets)) == len(offsets) and all(k <= kd for k in offsets):
                ab = np.zeros((kd + 1, n))
                for k, row in zip(offsets, A.data):
                    if k >= 0:
                        ab[kd - k, k:] = row[k:n]
                return cls(ab)
        if sp.issparse(A) and A.format == "csr":
            rows = np.repeat(np.arange(n), np.diff(A.indptr))
            cols, data = A.indices, A.data
        else:
            coo = A.tocoo() if sp.issparse(A) else sp.coo_matrix(np.asarray(A))
            rows, cols, data = coo.row, coo.col, coo.data
        upper = cols >= rows
        rows, cols, data = rows[upper], cols[upper], data[upper]
        if kd is None:
            kd = int(np.max(cols - rows, initial=0))
        ab = np.zeros((kd + 1, n))
        if sp.issparse(A) and A.format == "csr" and A.has_canonical_format:
            ab[kd + rows - cols, cols] = data  # no duplicate entries: a plain scatter
        else:
            np.add.at(ab, (kd + rows - cols, cols), data)
        return cls(ab)

    def inertia(self, growth_limit: float = PIVOT_FREE_GROWTH_LIMIT, max_negative: int = 32,
                overwrite: bool = False) -> tuple[int, object] | None:
        """Negative eigenvalues from the pivot-free ``L D L^T``, run as banded Cholesky factorizations.

        Returns ``(count, cholesky)`` -- ``cholesky`` the factor for ``pbtrs`` when the matrix is
        positive definite, else None -- or None when the pivot-free factorization cannot be trusted
        (see :meth:`negative_pivots`).  ``overwrite`` lets the factorization use the band's own storage.
        """
        out = self.negative_pivots(growth_limit, max_negative, overwrite)
        return None if out is None else (len(out[0]), out[1])

    def negative_pivots(self, growth_limit: float = PIVOT_FREE_GROWTH_LIMIT, max_negative: int = 32,
                        overwrite: bool = False) -> tuple[list[int], object] | None:
        """Columns of the negative pivots of the pivot-free ``L D L^T``, run as banded Cholesky factorizations.

        With the C extension ``contin.numerics._banded`` the same factorization runs column by column in one
        pass (the same pivots to rounding, the same checks and Cholesky factor); what follows
        describes the LAPACK version that runs without it.

        LAPACK's ``pbtrf`` (unblocked for a narrow band) stops at the first pivot ``d_j <= 0`` with the
        rows before it factorized and the rest holding the Schur complement.  A negative pivot is
        recorded and eliminated by hand (a rank-one update of the next ``kd`` rows: Haynsworth's inertia
        additivity), and Cholesky resumes in place on the rest; so the whole costs one banded Cholesky
        factorization plus ``O(kd^2)`` per negative eigenvalue, where a general sparse ``L D L^T`` costs
        several times more.  The pivots of a leading block are the leading pivots of the whole, so the
        columns give the Morse index of every leading principal submatrix.  Returns ``(columns,
        cholesky)`` -- ``cholesky`` the factor for ``pbtrs`` when the matrix is positive definite, else
        None -- or None when the pivot-free factorization cannot be trusted (a zero pivot, a multiplier
        above ``growth_limit``, or more than ``max_negative`` negative pivots).
        """
        from scipy.linalg import lapack

        kd, n = self.kd, self.shape[0]
        diagonal_scale = float(np.max(np.abs(self.ab[kd]), initial=0.0))
        # factorized in place, piece by piece (``overwrite``: in the band itself, when it is Fortran-ordered)
        work = self.ab if overwrite and self.ab.flags.f_contiguous else np.array(self.ab, dtype=float, order="F")
        compiled = banded_extension()
        if compiled is not None:
            # the same factorization in one pass of C (the same pivots up to rounding, the same checks)
            columns = compiled.ldlt_negative(work, float(growth_limit), int(max_negative), 1e-14 * diagonal_scale)
            return None if columns is None else (columns, work if not columns else None)
        columns: list[int] = []
        start = 0
        scale = None
        while True:
            piece = work[:, start:]  # Fortran-contiguous: LAPACK works on it without a copy
            cb, info = lapack.dpbtrf(piece, lower=0, overwrite_ab=1)
            if not np.shares_memory(cb, work):
                piece[...] = cb
            if info == 0:
                if _cholesky_growth(work, columns) > growth_limit:
                    return None  # a tiny positive pivot: the multipliers below it cannot be trusted
                return columns, (work if not columns else None)
            j = info - 1  # column of the non-positive pivot within the piece
            d = piece[kd, j]
            if scale is None:
                scale = diagonal_scale
            if not np.isfinite(d) or d >= 0.0 or abs(d) <= 1e-14 * scale:
                return None  # a zero pivot: singular to working precision, or not a number
            k = min(kd, piece.shape[1] - 1 - j)
            r = np.array([piece[kd - t, j + t] for t in range(1, k + 1)])  # row j's unscaled entries to its right
            if k and float(np.max(np.abs(r))) / abs(d) > growth_limit:
                return None
            columns.append(start + j)
            if len(columns) > max_negative:
                return None
            start += j + 1
            if start >= n:
                if _cholesky_growth(work, columns) > growth_limit:
                    return None
                return columns, None
            for a in range(k):  # S[a, b] -= r_a r_b / d on the next k rows (upper band: row kd + a - b)
                for b in range(a, k):
                    work[kd + a - b, start + b] -= r[a] * r[b] / d

    def tocsc(self) -> sp.csc_matrix:
        """The whole matrix as CSC (both triangles; every entry of the band stored, zeros included)."""
        kd, n = self.kd, self.shape[0]
        vals = np.zeros((n, 2 * kd + 1))  # column j, rows j - kd .. j + kd
        vals[:, :kd + 1] = self.ab.T
        for k in range(1, kd + 1):  # A[j + k, j] = A[j, j + k] = ab[kd - k, j + k]
            vals[:n - k, kd + k] = self.ab[kd - k, k:]
        rows = np.arange(n)[:, None] + np.arange(-kd, kd + 1)[None, :]
        inside = (rows >= 0) & (rows < n)
        indptr = np.concatenate([[0], np.cumsum(inside.sum(axis=1))])
        return sp.csc_matrix((vals[inside], rows[inside], indptr), shape=(n, n))

    def tocsr(self) -> sp.csr_matrix:
        """The whole matrix as CSR (both triangles)."""
        C = self.tocsc()  # symmetric: its CSC arrays are its CSR arrays
        return sp.csr_matrix((C.data, C.indices, C.indptr), shape=C.shape)

    def toarray(self) -> np.ndarray:
        """The whole matrix, dense."""
        return self.tocsr().toarray()

    def general_band(self, extra_rows: int = 0) -> np.ndarray:
        """The matrix in LAPACK's general band storage with ``kl = ku = kd`` (``extra_rows`` leading
        zero rows; ``kd`` of them for ``gbtrf``)."""
        kd, n = self.kd, self.shape[0]
        g = np.zeros((extra_rows + 2 * kd + 1, n))
        g[extra_rows:extra_rows + kd + 1] = self.ab
        for k in range(1, kd + 1):  # A[j + k, j] = A[j, j + k] = ab[kd - k, j + k]
            g[extra_rows + kd + k, :n - k] = self.ab[kd - k, k:]
        return g


def _cholesky_growth(work: np.ndarray, negative: list[int]) -> float:
    """Largest multiplier ``|l_ij| = |u_ij| / u_ii`` of the pivot-free ``L D L^T`` factorized in ``work``.

    ``work`` is the upper band after :meth:`SymmetricBand.negative_pivots`: Cholesky factors ``u`` in the
    rows of positive pivots; the rows of the ``negative`` pivots hold their unscaled entries (checked
    where they were eliminated) and are left out.
    """
    kd = work.shape[0] - 1
    n = work.shape[1]
    if kd == 0 or n < 2:
        return 0.0
    # work[kd - t, j] (row i = j - t of column j) divided by u_ii = diag[j - t], all rows at once: row r
    # of the divisors is diag shifted right by kd - r, with inf where the band leaves the matrix
    padded = np.full(n + kd, np.inf)
    padded[kd:] = work[kd]
    padded[kd + np.asarray(negative, dtype=np.intp)] = np.inf  # their multipliers were checked when eliminated
    step = padded.strides[0]
    divisors = np.lib.stride_tricks.as_strided(padded, shape=(kd, n), strides=(step, step), writeable=False)
    ratio = np.abs(work[:kd]) / divisors
    for r in range(kd):  # entries of the band storage outside the matrix hold anything: not multipliers
        ratio[r, :kd - r] = 0.0
    return float(ratio.max())


class SparseLU(Factorization):
    """General sparse LU (SuperLU) for matrices that are neither small nor banded."""

    def __init__(self, A) -> None:
        A = sp.csc_matrix(A)
        self.n = A.shape[0]
        try:
            self._lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A")
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise SingularMatrixError(str(exc)) from exc
        self.exactly_singular = False

    def solve(self, b, trans=False):
        return self._check(self._lu.solve(np.asarray(b, dtype=float), trans="T" if trans else "N"))

    def pivots(self) -> np.ndarray:
        """Diagonal of the U factor, each pivot at the index of its column of ``A`` (SuperLU orders the
        columns for sparsity: the pivot of factor column ``k`` belongs to column ``perm_c[k]``)."""
        d = np.empty(self.n)
        d[self._lu.perm_c] = self._lu.U.diagonal()
        return d

    def det_sign_log(self):
        parity = _permutation_parity(self._lu.perm_r) * _permutation_parity(self._lu.perm_c)
        return _sign_log_from_diagonal(self._lu.U.diagonal(), parity)


def factorize(A, method: str = "auto") -> Factorization:
    """Factorize a square matrix choosing the cheapest safe method.

    Parameters
    ----------
    A : scipy.sparse matrix or ndarray
        Square matrix.
    method : {"auto", "dense", "banded", "sparse"}
        ``"auto"`` uses dense LU for small matrices, banded LU when the bandwidth is small
        compared with the size, and SuperLU otherwise.
    """
    n = A.shape[0]
    if isinstance(A, SymmetricBand):
        return DenseLU(A.toarray()) if method == "dense" else BandedLU(A)
    if method == "dense" or (method == "auto" and n <= DENSE_LIMIT):
        return DenseLU(A)
    if method in ("auto", "banded"):
        kl, ku = bandwidths(A)
        if method == "banded" or (kl + ku + 1) <= max(BANDED_FRACTION * n, 8):
            return TridiagonalLU(A) if kl == ku == 1 and n >= 3 else BandedLU(A, kl, ku)
    if method == "auto" and n <= 1500:
        return DenseLU(A)
    return SparseLU(A)


def _matvec(A, x):
    return A @ x


def inf_norm(A) -> float:
    """The infinity norm (largest row sum of ``|A|``) of a sparse or dense matrix, 0 without rows.

    CSR and DIA matrices are summed from their arrays: ``abs(A)`` would build a new matrix first.
    """
    if sp.issparse(A) and A.format == "dia":
        # row sums of |A| without building |A|: dia data[k, j] sits in row j - offset_k
        n, m = A.shape
        rows = np.zeros(n)
        for off, d in zip(A.offsets.tolist(), np.abs(A.data)):  # Python ints: cheaper index arithmetic
            lo, hi = max(0, off), min(m, n + off)
            rows[lo - off:hi - off] += d[lo:hi]
        return float(rows.max()) if n else 0.0
    if sp.issparse(A) and A.format == "csr" and A.shape[0] and A.nnz:
        # row sums straight from the CSR arrays: abs(A) would build a new matrix every call
        lengths = np.diff(A.indptr)
        if np.all(lengths):
            sums = np.add.reduceat(np.abs(A.data), A.indptr[:-1])
        else:
            sums = np.bincount(np.repeat(np.arange(A.shape[0]), lengths), weights=np.abs(A.data),
                               minlength=A.shape[0])
        return float(sums.max())
    if sp.issparse(A):
        return float(abs(A).sum(axis=1).max()) if A.shape[0] else 0.0
    A = np.asarray(A)
    return float(np.abs(A).sum(axis=1).max()) if A.size else 0.0


def _remembered(factor: Factorization | None, slot: str, key: Any, same: Callable[[Any, Any], bool],
                compute: Callable[[], Any], keep: Callable[[Any], Any] = lambda key: key) -> Any:
    """``compute()``, remembered on ``factor`` (attribute ``slot``) for the next call with the same ``key``.

    The bordered systems of a Newton step (the correction, the tangent, the test functions) share one
    main block and its factorization: what depends on the block alone is computed once for them.
    ``keep(key)`` is what is stored to compare with (a copy of an array the caller may change).
    """
    memo = getattr(factor, slot, None)
    if memo is not None and same(memo[0], key):
        return memo[1]
    value = compute()
    if factor is not None:
        setattr(factor, slot, (keep(key), value))
    return value


def _inf_norm_of(A, factor) -> float:
    """``inf_norm(A)``, remembered by ``A``'s factorization (while ``A`` is the same object)."""
    return _remembered(factor, "_inf_norm_memo", A, lambda a, b: a is b, lambda: inf_norm(A))


def _border_solution(factor: Factorization, B: np.ndarray) -> np.ndarray:
    """``A^-1 B``, remembered by ``A``'s factorization for the next border column of the same values
    (the tangent after a correction shares the corrector's last Jacobian and its ``df/dp``)."""
    return _remembered(factor, "_border_memo", B, same_values, lambda: factor.solve(B), keep=np.copy)


def _max_abs(*arrays: np.ndarray) -> float:
    """Largest modulus over the arrays (0 when all are empty; NaN when any entry is NaN)."""
    largest = 0.0
    compiled = banded_extension()
    for a in arrays:
        if a.size == 1:  # a border's single value: numpy's call overhead is most of the cost
            value = abs(float(a.flat[0]))
        elif not a.size:
            continue
        elif compiled is not None and a.dtype == np.float64 and a.flags.c_contiguous:
            value = compiled.max_abs(a)  # one pass, without numpy's array of |a|
        else:
            value = float(np.maximum.reduce(np.abs(a), axis=None))
        if not value <= largest:  # larger, or NaN (which then stays)
            largest = value
            if value != value:
                return value
    return largest


def _row_sum_norm(M: np.ndarray) -> float:
    """Largest row sum of ``|M|`` for a 2-D array (0 when it has no rows)."""
    if M.shape[1] == 1:  # one border column: the largest modulus, without the row sums
        return _max_abs(M)
    return float(np.abs(M).sum(axis=1).max(initial=0.0))


@dataclass
class BorderedSolver:
    """Solve ``[[A, B], [C, D]] [x; z] = [f; g]`` by block elimination on a factorization of ``A``.

    Parameters
    ----------
    A : sparse or dense (n, n)
        Main block.
    factor : Factorization
        Factorization of ``A`` (reused across solves; the caller owns its choice).
    B, C, D : ndarray
        Borders of shape (n, k), (k, n), (k, k).
    refine_tol : float
        Relative residual that a solve must reach; otherwise the main block is deflated (see
        ``_deflate``), and as a last resort the full matrix is factorized.
    refactor : callable, optional
        Factorization routine for the deflated main block (default :func:`factorize`).
    """

    A: object
    factor: Factorization | None
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    refine_tol: float = 1e-12
    max_refine: int = 3
    refactor: object = None
    depth: int = 0
    used_fallback: bool = field(default=False, init=False)

    def __post_init__(self) -> None:
        self.B = np.asarray(self.B, dtype=float).reshape(self.A.shape[0], -1)
        k = self.B.shape[1]
        self.C = np.asarray(self.C, dtype=float).reshape(k, self.A.shape[0])
        self.D = np.asarray(self.D, dtype=float).reshape(k, k)
        self.k = k
        self._schur = {}
        self._full: Factorization | None = None
        self._deflated: BorderedSolver | None = None
        self._deflation_sign = 1.0
        if self.refactor is None:
            self.refactor = factorize
        self._scale = _inf_norm_of(self.A, self.factor) + _row_sum_norm(self.B) + (
            _row_sum_norm(self.C) + _row_sum_norm(self.D))
        if self.factor is None or getattr(self.factor, "exactly_singular", False):
            if not self._deflate():
                self._use_full()

    # -- block elimination --------------------------------------------------------------------
    def _schur_parts(self, trans: bool):
        if trans not in self._schur:
            if trans:
                X = self.factor.solve(self.C.T, trans=True)  # A^T X = C^T
                S = self.D.T - self.B.T @ X
            else:
                X = _border_solution(self.factor, self.B)
                S = self.D - self.C @ X
            S_lu = None
            if self.k:
                if not np.isfinite(S).all():
                    raise SingularMatrixError("the Schur complement of the bordered system is not finite")
            if self.k == 1:  # one border (a continuation step): the Schur complement is a number
                if S[0, 0] == 0.0:
                    raise SingularMatrixError("the Schur complement of the bordered system is singular")
            elif self.k:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", sla.LinAlgWarning)
                    S_lu = sla.lu_factor(S, check_finite=False)
                if np.any(np.diag(S_lu[0]) == 0.0):
                    # singular Schur complement: the caller falls back (deflation or the full matrix)
                    raise SingularMatrixError("the Schur complement of the bordered system is singular")
            self._schur[trans] = (X, S_lu, S)
        return self._schur[trans]

    def _be_solve(self, f, g, trans):
        X, S_lu, _ = self._schur_parts(trans)
        y = self.factor.solve(f, trans=trans)
        if self.k == 0:
            return y, np.zeros((0,) + f.shape[1:])
        Cm = self.B.T if trans else self.C
        if self.k == 1:
            _, _, S = self._schur[trans]
            z = (g - Cm @ y) / S[0, 0]
        else:
            z = sla.lu_solve(S_lu, g - Cm @ y, check_finite=False)
        x = y - X @ z
        return x, z

    def _residual(self, x, z, f, g, trans):
        # a factorization of the caller's own type may lack residual(): the product then is A's
        own = type(self.factor).residual if isinstance(self.factor, Factorization) else Factorization.residual
        r1 = own(self.factor, self.A, f, x, trans)
        if trans:
            r1 -= self.C.T @ z
            r2 = g - self.B.T @ x - self.D.T @ z
        else:
            r1 -= self.B @ z
            r2 = g - self.C @ x - self.D @ z
        return r1, r2

    # -- fallbacks ------------------------------------------------------------------------------
    def full_matrix(self):
        """The assembled bordered matrix (sparse)."""
        return sp.bmat([[sp.csr_matrix(self.A), sp.csr_matrix(self.B)],
                        [sp.csr_matrix(self.C), sp.csr_matrix(self.D)]], format="csc")

    def _deflation_index(self) -> int | None:
        """Index where the (near) null vector of ``A`` is largest, or None if it cannot be found."""
        n = self.A.shape[0]
        if self.factor is not None and not getattr(self.factor, "exactly_singular", False):
            rng = np.random.default_rng(7)
            try:
                y = self.factor.solve(rng.standard_normal(n))
                return int(np.argmax(np.abs(y)))
            except (SingularMatrixError, np.linalg.LinAlgError):
                pass
        diag = getattr(self.factor, "pivots", None)
        if diag is not None:
            return int(np.argmin(np.abs(diag())))
        return None

    def _deflate(self) -> bool:
        """Replace ``A`` by ``A + sigma e_j e_j^T`` (same band, regular) and add one border.

        ``[[A, B], [C, D]]`` is equivalent to ``[[A + s e e^T, B, -e], [C, D, 0], [e^T, 0, -1/s]]``
        (eliminate the new unknown ``y = s e^T x``), so block elimination runs on a well-conditioned
        main block.  ``det`` of the original is ``det`` of the extended one times ``-s``.
        """
        if self.depth >= 2 or self.A.shape[0] <= DENSE_LIMIT:
            return False
        j = self._deflation_index()
        if j is None:
            return False
        n = self.A.shape[0]
        sigma = max(inf_norm(self.A), 1e-300)
        e = np.zeros((n, 1))
        e[j] = 1.0
        A2 = sp.csr_matrix(self.A) + sp.csr_matrix(([sigma], ([j], [j])), shape=(n, n))
        try:
            F2 = self.refactor(A2)
        except (SingularMatrixError, np.linalg.LinAlgError, RuntimeError):
            return False
        k = self.k
        B2 = np.hstack([self.B, -e])
        C2 = np.vstack([self.C, e.T])
        D2 = np.zeros((k + 1, k + 1))
        D2[:k, :k] = self.D
        D2[k, k] = -1.0 / sigma
        self._deflated = BorderedSolver(A2, F2, B2, C2, D2, refine_tol=self.refine_tol,
                                        max_refine=self.max_refine, refactor=self.refactor,
                                        depth=self.depth + 1)
        self._deflation_sign = -1.0
        self.used_fallback = True
        return True

    def _use_full(self) -> None:
        if self._full is None:
            M = self.full_matrix()
            n = M.shape[0]
            self._full = DenseLU(M) if n <= 3000 else SparseLU(M)
            self.used_fallback = True

    def _try_block_elimination(self, f, g, trans):
        x, z = self._be_solve(f, g, trans)
        size = _max_abs(x, z)
        rhs = _max_abs(f, g)
        for _ in range(self.max_refine + 1):
            r1, r2 = self._residual(x, z, f, g, trans)
            res = _max_abs(r1, r2)
            if res <= self.refine_tol * (self._scale * size + rhs):
                return x, z
            dx, dz = self._be_solve(r1, r2, trans)
            x, z = x + dx, z + dz
            size = _max_abs(x, z)
        return None

    def solve(self, f, g=None, trans: bool = False):
        """Solve the bordered system (or its transpose); returns ``(x, z)``."""
        n = self.A.shape[0]
        f = np.asarray(f, dtype=float)
        g = np.zeros((self.k,) + f.shape[1:]) if g is None else np.asarray(g, dtype=float)
        if self._full is None and self._deflated is None:
            try:
                out = self._try_block_elimination(f, g, trans)
                if out is not None:
                    return out
            except (SingularMatrixError, np.linalg.LinAlgError, ValueError):
                pass
            if not self._deflate():
                self._use_full()
        if self._deflated is not None:
            extra = np.zeros((1,) + f.shape[1:])
            x, z = self._deflated.solve(f, np.concatenate([g, extra]), trans=trans)
            return x, z[: self.k]
        rhs = np.concatenate([f, g])
        sol = self._full.solve(rhs, trans=trans)
        return sol[:n], sol[n:]

    def det_sign_log(self) -> tuple[float, float]:
        """Sign and log-modulus of the determinant of the bordered matrix."""
        if self._deflated is not None:
            s_, l_ = self._deflated.det_sign_log()
            sigma = max(inf_norm(self.A), 1e-300)
            return s_ * self._deflation_sign, l_ + float(np.log(sigma))
        if self._full is not None:
            return self._full.det_sign_log()
        sa, la = self.factor.det_sign_log()
        if self.k == 0:
            return sa, la
        _, _, S = self._schur_parts(False)
        ss, ls = np.linalg.slogdet(S)
        return float(sa * ss), float(la + ls)

    def det_sign(self) -> float:
        """Sign of the determinant of the bordered matrix (:meth:`det_sign_log` without the logarithm)."""
        if self._deflated is not None:
            return self._deflated.det_sign() * self._deflation_sign
        if self._full is not None:
            return self._full.det_sign()
        sa = self.factor.det_sign()
        if self.k == 0:
            return sa
        _, _, S = self._schur_parts(False)
        ss = float(np.sign(S[0, 0])) if self.k == 1 else float(np.linalg.slogdet(S)[0])
        return float(sa * ss)
