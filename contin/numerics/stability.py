"""Stability from the inertia of a symmetric operator (usually the Hessian of the energy).

A state is stable when the operator is positive definite.  We report the number of negative
eigenvalues (the Morse index) and, on request, the few smallest eigenvalues.

Morse index of a sparse or banded matrix: Sylvester's law of inertia.  ``H = L D L^T`` (an LU
factorization without pivoting in the natural order, which keeps a band's fill inside the band)
has as many negative pivots in ``D`` as ``H`` has negative eigenvalues, at O(n b^2) cost.  Without
pivoting the factorization can suffer element growth on an indefinite matrix; when the multipliers
grow beyond :data:`LDL_GROWTH_LIMIT` (or a pivot is exactly zero) the count falls back to an
eigensolver.  For an *arrow* matrix (below) whose band is positive definite, the same pivots come from
the band's factorization and the border's Schur complement, without a general sparse factorization.
The eigenvalues themselves come from dense ``eigh`` for small matrices, LAPACK's banded symmetric
eigensolver with index selection for banded ones (its reduction to tridiagonal form
costs O(n^2 b), so it is asked for only when ``k > 0``; above :data:`SHIFT_INVERT_WORK`, Lanczos in
shift-invert mode below the spectrum instead), Lanczos in shift-invert mode just below the
spectrum for an *arrow* matrix (a band with a few dense border rows, :func:`contin.numerics.linalg.arrow_structure`:
an indenter's travel under a dead load couples to every node in contact), and ARPACK for the rest.

Nested operators (an operator and its leading block, e.g. a structure's Hessian under a dead load and
under its prescribed displacement): :func:`nested_inertias` counts both from one pivot-free
``L D L^T``; where that cannot be trusted (the leading block is singular at a fold of the
displacement-controlled path, so the border is divided by a vanishing pivot), from the leading
block's own count plus the inertia of its Schur complement (Sylvester's law of inertia:
``H = [[A, B], [B^T, C]]`` is congruent to ``diag(A, C - B^T A^{-1} B)``).
"""

from __future__ import annotations

from dataclasses import dataclass

from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..lazy import lazy_module
from .linalg import (BANDED_FRACTION, PIVOT_FREE_GROWTH_LIMIT, ArrowCholesky, ArrowParts, BandedLU, Factorization, SymmetricBand, arrow_structure, bandwidths,
                     cholesky_band_solver, factorize, lower_band, upper_band)

__all__ = ["StabilityInfo", "stability_info", "inertia", "leading_inertias", "nested_inertias", "lanczos_start"]

# imported on first use: ARPACK is a fallback the banded inertia counts never reach
spla = lazy_module("scipy.sparse.linalg")


def lanczos_start(n: int) -> np.ndarray:
    """A fixed start vector for ARPACK's Lanczos (``eigsh(..., v0=lanczos_start(n))``).

    Without one ARPACK draws its start from a generator whose state runs on from call to call in
    the process, so the same matrix gives eigenvectors (and everything located with them) that
    depend on what the process computed before.
    """
    return np.random.default_rng(12345).standard_normal(n)

DENSE_LIMIT = 400
#: Largest multiplier |L_ij| accepted in the pivot-free LDL^T before the inertia count is redone
#: with an eigensolver (growth makes the signs of the pivots untrustworthy).
LDL_GROWTH_LIMIT = PIVOT_FREE_GROWTH_LIMIT
#: Banded matrices above this size use the banded eigensolver (4x faster than dense eigh at n = 400).
BANDED_MIN = 64


@dataclass
class StabilityInfo:
    """Inertia summary of a symmetric matrix.

    Attributes
    ----------
    n_negative : int
        Number of negative eigenvalues.
    eigenvalues : ndarray
        The smallest eigenvalues in ascending order (at most ``k`` of them).
    eigenvectors : ndarray or None
        Matching eigenvectors as columns, when requested.
    """

    n_negative: int
    eigenvalues: np.ndarray
    eigenvectors: np.ndarray | None = None

    @property
    def stable(self) -> bool:
        """True when there is no negative eigenvalue."""
        return self.n_negative == 0


def inertia(H) -> int | None:
    """Number of negative eigenvalues of the sparse symmetric ``H`` from a pivot-free ``L D L^T``.

    Returns None when the factorization is not trustworthy (a zero pivot, a row exchange, or
    multipliers above :data:`LDL_GROWTH_LIMIT`); the caller then counts with an eigensolver.
    """
    counts = leading_inertias(H, (H.shape[0],))
    return None if counts is None else counts[0]


def leading_inertias(H, sizes) -> list[int] | None:
    """Negative-eigenvalue counts of the leading principal submatrices ``H[:m, :m]`` for ``m`` in ``sizes``.

    The pivot-free ``L D L^T`` of a leading block is the leading part of the whole one, so one
    factorization gives the Morse index of every nested block (e.g. a structure's Hessian with and
    without its last, load-carrying degree of freedom).  None when the factorization is not
    trustworthy (see :func:`inertia`).
    """
    band = _narrow_band(H)
    if band is not None:
        out = band.negative_pivots(LDL_GROWTH_LIMIT)
        if out is not None:
            return [sum(1 for j in out[0] if j < m) for m in sizes]
    else:
        counts = _arrow_inertias(H, sizes)
        if counts is not None:
            return counts
    d = _ldlt_pivots(H)
    if d is None:
        return None
    negative = np.concatenate([[0], np.cumsum(d < 0.0)])
    return [int(negative[m]) for m in sizes]


def _arrow_inertias(H, sizes) -> list[int] | None:
    """:func:`leading_inertias` of an arrow matrix whose band block is positive definite, by blocks; else None.

    ``H = [[A, B], [B^T, C]]`` with ``A`` banded (:func:`contin.numerics.linalg.arrow_structure`, e.g. a structure's
    Hessian bordered by an indenter's travel): the pivot-free ``L D L^T`` of ``H`` is ``A``'s followed by
    that of the Schur complement ``S = C - B^T A^{-1} B``.  ``A``'s banded factorization
    (:meth:`contin.numerics.linalg.SymmetricBand.negative_pivots`, which leaves its Cholesky factor when ``A`` is
    positive definite) and ``S``'s, a few rows, give every count for a fraction of the general sparse
    factorization's cost.  None when ``H`` is no arrow, ``A`` is not positive definite (the general
    factorization then counts) or a pivot cannot be trusted.
    """
    if not sp.issparse(H) or H.shape[0] <= BANDED_MIN:
        return None
    arrow = arrow_structure(H)
    if arrow is None:
        return None
    b, m = arrow
    csr = H.tocsr()
    if not csr.has_canonical_format:
        csr = csr.copy()
        csr.sum_duplicates()
    n = csr.shape[0]
    lead = n - m
    rows, cols, data = np.repeat(np.arange(n), np.diff(csr.indptr)), csr.indices, csr.data
    upper = (cols >= rows) & (cols < lead)  # A's upper band, as SymmetricBand keeps it
    ab = np.zeros((b + 1, lead))
    ab[b + rows[upper] - cols[upper], cols[upper]] = data[upper]  # canonical: no entry twice
    out = SymmetricBand(ab).negative_pivots(LDL_GROWTH_LIMIT)
    if out is None or out[0]:
        return None
    solve = cholesky_band_solver(out[1])
    border, corner = np.zeros((lead, m)), np.zeros((m, m))
    side, tail = (rows < lead) & (cols >= lead), (rows >= lead) & (cols >= lead)
    border[rows[side], cols[side] - lead] = data[side]
    corner[rows[tail] - lead, cols[tail] - lead] = data[tail]
    schur = corner - border.T @ np.column_stack([solve(border[:, k]) for k in range(m)])
    schur = 0.5 * (schur + schur.T)
    pivots = []
    for k in range(m):  # the pivot-free L D L^T of S, checked as the general factorization is
        d = float(schur[k, k])
        if not np.isfinite(d) or d == 0.0:
            return None
        multipliers = schur[k + 1:, k] / d
        if multipliers.size and float(np.max(np.abs(multipliers))) > LDL_GROWTH_LIMIT:
            return None
        schur[k + 1:, k + 1:] -= np.outer(multipliers, schur[k, k + 1:])
        pivots.append(d)
    negative = np.concatenate([[0], np.cumsum(np.array(pivots) < 0.0)])
    return [0 if size <= lead else int(negative[size - lead]) for size in sizes]


def _narrow_band(H) -> SymmetricBand | None:
    """``H`` in symmetric band storage when it is a sparse matrix of narrow band, else None.

    The pivot-free ``L D L^T`` then runs as banded Cholesky pieces (:meth:`SymmetricBand.negative_pivots`),
    several times cheaper than SuperLU's; when that declines (more negative pivots than it handles, or
    a pivot it cannot trust) the general factorization decides.
    """
    if isinstance(H, SymmetricBand):
        return H
    n = H.shape[0]
    if not sp.issparse(H) or n <= BANDED_MIN:
        return None
    kl, ku = bandwidths(H) if H.format != "csr" else _csr_bandwidths(H)
    kd = max(kl, ku)
    if kd + 1 > 0.1 * n:
        return None
    return SymmetricBand.from_sparse(H if H.format in ("csr", "dia") else H.tocsr(), kd)


def _csr_bandwidths(H: sp.csr_matrix) -> tuple[int, int]:
    """``(kl, ku)`` of a CSR matrix straight from its index arrays."""
    if H.nnz == 0:
        return 0, 0
    off = np.repeat(np.arange(H.shape[0]), np.diff(H.indptr)) - H.indices
    return int(max(off.max(), 0)), int(max(-off.min(), 0))


def nested_inertias(H, m: int) -> tuple[int, int]:
    """Negative-eigenvalue counts of the leading block ``A = H[:m, :m]`` and of the symmetric ``H`` itself.

    One pivot-free ``L D L^T`` of ``H`` gives both (:func:`leading_inertias`).  When it cannot be
    trusted (a leading block singular at a fold divides the border by a vanishing pivot, and a general
    eigensolver need not converge on the bordered matrix either), ``A`` is counted on its own
    (:func:`stability_info`, which takes the banded path for a banded ``A``) and ``H`` adds the negative
    eigenvalues of the Schur complement ``S = C - B^T A^{-1} B`` (``B = H[:m, m:]``, ``C = H[m:, m:]``):
    by Sylvester's law of inertia ``H`` is congruent to ``diag(A, S)``.  An ``A`` singular to working
    precision adds nothing (exactly at a fold the count is decided by roundoff).

    Parameters
    ----------
    H : sparse or dense (n, n) symmetric matrix
    m : int
        Size of the leading block, ``0 < m < n``.

    Returns
    -------
    (int, int)
        Morse index of ``A``, then of ``H``.
    """
    n = H.shape[0]
    if not 0 < m < n:
        raise ValueError(f"nested_inertias: the leading block's size must be in (0, {n}), got {m}")
    counts = leading_inertias(H, (m, n))
    if counts is not None:
        return counts[0], counts[1]
    Hs = sp.csr_matrix(H)
    A = Hs[:m, :m]
    n_lead = stability_info(A, 0).n_negative
    B = Hs[:m, m:].toarray()
    C = Hs[m:, m:].toarray()
    try:
        Y = _leading_factorization(A).solve(B)
        # entry by entry as 1-D dot products: a bordered matrix (n - m = 1) gets s = d - b . A^{-1} b
        S = np.array([[C[i, j] - float(B[:, i] @ Y[:, j]) for j in range(n - m)] for i in range(n - m)])
    except np.linalg.LinAlgError:  # A exactly singular (SingularMatrixError is one)
        return n_lead, n_lead
    return n_lead, n_lead + int(np.count_nonzero(np.linalg.eigvalsh(0.5 * (S + S.T)) < 0.0))


def _leading_factorization(A) -> Factorization:
    """LU of the leading block for its Schur complement: banded (gbtrf on its own band) when it is banded."""
    kl, ku = bandwidths(A)
    if kl + ku + 1 <= max(BANDED_FRACTION * A.shape[0], 8):
        return BandedLU(A, kl, ku)
    return factorize(A)


def pivot_free_ldlt(H) -> tuple[np.ndarray, Any] | None:
    """The pivot-free ``L D L^T`` of the sparse symmetric ``H``: its pivots ``D`` and the factorization
    (SuperLU in natural order, no pivoting; its ``solve`` solves with ``H``), or None when they cannot be
    trusted (a zero pivot, a row exchange, or multipliers above :data:`LDL_GROWTH_LIMIT`)."""
    A = H.tocsc() if hasattr(H, "tocsc") else sp.csc_matrix(H)
    try:
        lu = spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular pivot
        return None
    n = A.shape[0]
    if not np.array_equal(lu.perm_r, np.arange(n)) or not np.array_equal(lu.perm_c, np.arange(n)):
        return None
    if lu.L.nnz and float(np.max(np.abs(lu.L.data))) > LDL_GROWTH_LIMIT:
        return None
    d = lu.U.diagonal()
    if not np.isfinite(d).all() or np.any(d == 0.0):
        return None
    return d, lu


def _ldlt_pivots(H) -> np.ndarray | None:
    """Pivots ``D`` of the pivot-free ``L D L^T`` of ``H``, or None when they cannot be trusted."""
    out = pivot_free_ldlt(H)
    return None if out is None else out[0]


def stability_info(H, k: int = 3, vectors: bool = False) -> StabilityInfo:
    """Count negative eigenvalues of the symmetric matrix ``H`` and return the ``k`` smallest.

    Parameters
    ----------
    H : sparse or dense (n, n) symmetric matrix
    k : int
        Number of smallest eigenvalues to report; 0 reports the Morse index only, which for a
        sparse matrix costs one pivot-free factorization (:func:`inertia`).
    vectors : bool
        Also return the eigenvectors of the reported eigenvalues (needs ``k >= 1``).
    """
    n = H.shape[0]
    if k <= 0 and not vectors and n > BANDED_MIN:
        n_neg = inertia(H)
        if n_neg is not None:
            return StabilityInfo(n_neg, np.zeros(0))
    k = max(1, min(k, n))
    kl, ku = bandwidths(H)
    b = max(kl, ku)
    # a wider band than a tenth still beats ARPACK's iteration on a stiff matrix too large for the dense route
    banded = n > BANDED_MIN and (b + 1 <= 0.1 * n or (n > DENSE_LIMIT and b + 1 <= BANDED_FRACTION * n))
    if not banded and n > BANDED_MIN:
        arrow = arrow_structure(H)
        if arrow is not None:
            info = _arrow_info(H, *arrow, k, vectors)
            if info is not None:
                return info
    if n <= DENSE_LIMIT and not banded:
        return _dense_info(H, k, vectors)
    if banded:
        return _banded_info(H, b, k, vectors)
    return _sparse_info(H, k, vectors)


def _dense_info(H, k: int, vectors: bool) -> StabilityInfo:
    """All eigenvalues of a small matrix (dense ``eigh``)."""
    A = H.toarray() if sp.issparse(H) else np.asarray(H, dtype=float)
    if vectors:
        w, V = np.linalg.eigh(A)
    else:
        w, V = np.linalg.eigvalsh(A), None
    n_neg = int(np.count_nonzero(w < 0))
    m = max(k, n_neg) if vectors else k
    return StabilityInfo(n_neg, w[:k], None if V is None else V[:, :m])


#: Above this ``n^2 b`` a banded matrix's few smallest eigenvalues come from Lanczos in shift-invert mode
#: below the spectrum (:func:`_shifted_lanczos_info`: a few O(n b^2) factorizations) instead of LAPACK's
#: reduction to tridiagonal form, which costs O(n^2 b): 0.7 s at n = 4400, b = 32.
SHIFT_INVERT_WORK = 2.0e8


def _banded_info(H, b: int, k: int, vectors: bool) -> StabilityInfo:
    """The ``k`` smallest eigenvalues by LAPACK's banded solver (large bands: :func:`_shifted_lanczos_info`).

    When all of them are negative the Morse index comes from the inertia (or all negative eigenvalues).
    """
    n = H.shape[0]
    if float(n) * n * b > SHIFT_INVERT_WORK:
        info = _shifted_lanczos_info(H, b, k, vectors)
        if info is not None:
            return info
    ab = lower_band(H, b)
    w = sla.eig_banded(ab, lower=True, eigvals_only=True, select="i", select_range=(0, k - 1))
    if w[-1] < 0:
        counted = inertia(H)
        if counted is None:
            neg = sla.eig_banded(ab, lower=True, eigvals_only=True, select="v", select_range=(-np.inf, 0.0))
            counted = int(np.count_nonzero(neg < 0))
        n_neg = counted
    else:
        n_neg = int(np.count_nonzero(w < 0))
    V = None
    if vectors:
        m = max(k, n_neg)
        _, V = sla.eig_banded(ab, lower=True, select="i", select_range=(0, m - 1))
    return StabilityInfo(n_neg, np.asarray(w), V)


def _shifted_lanczos_info(H, b: int, k: int, vectors: bool = False) -> StabilityInfo | None:
    """The Morse index and the ``k`` smallest eigenvalues of a large symmetric band matrix, in O(n b^2) work
    (with ``vectors``, the eigenvectors of the ``max(k, index)`` smallest, as :func:`stability_info` gives them).

    The index from the pivot-free ``L D L^T`` (:func:`inertia`).  A shift ``sigma`` below the spectrum:
    ``-delta`` (``delta = 1e-8 |H|``) when nothing is negative, else ``-delta 2^m`` with ``m`` the first
    for which ``H - sigma I`` is positive definite (its banded Cholesky factorization succeeds), so that
    ``sigma`` lies within a factor of two below the smallest eigenvalue.  Lanczos on ``(H - sigma I)^-1``
    (ARPACK, a fixed start) then converges to the eigenvalues nearest ``sigma``: the smallest.  None (the
    caller takes LAPACK's route) where the count cannot be trusted or ARPACK does not converge.
    """
    n = H.shape[0]
    n_neg = inertia(H)
    if n_neg is None:
        return None
    want = max(k, n_neg) if vectors else k
    if want >= n - 1 or want > ARROW_MAX_EIGENPAIRS:
        return None
    H = sp.csr_matrix(H)
    band = upper_band(H, b)  # its positions computed once per pattern of a model's Hessians
    size = float(abs(H).sum(axis=1).max()) or 1.0
    delta = 1e-8 * size
    factor = None
    for _ in range(200):
        shifted = band.copy(order="F")
        shifted[b] += delta  # the diagonal of the upper band storage
        try:
            factor = sla.cholesky_banded(shifted, lower=False, check_finite=False)
        except np.linalg.LinAlgError:
            delta *= 2.0
            continue
        break
    if factor is None:
        return None

    def solve(r: np.ndarray) -> np.ndarray:
        return sla.cho_solve_banded((factor, False), r, check_finite=False)

    sigma = -delta
    op = spla.LinearOperator((n, n), matvec=solve, dtype=float)
    try:
        out = spla.eigsh(op, k=want, which="LA", v0=lanczos_start(n), return_eigenvectors=vectors, tol=1e-12)
    except (spla.ArpackNoConvergence, spla.ArpackError):
        return None
    mu, V = out if vectors else (out, None)
    order = np.argsort(sigma + 1.0 / mu)
    w = (sigma + 1.0 / mu)[order]
    if np.count_nonzero(w < 0) > n_neg or (n_neg >= want and np.any(w >= 0)):
        return None  # the eigenvalues disagree with the count: let LAPACK decide
    return StabilityInfo(int(n_neg), w[:k], None if V is None else V[:, order])


#: Most eigenpairs of an arrow matrix computed by Lanczos; more (a state far from stable) go dense.
ARROW_MAX_EIGENPAIRS = 16
#: Restarts of ARPACK on an arrow matrix before the dense route takes over (about 20 solves each).
ARROW_MAX_RESTARTS = 20


def _arrow_info(H, b: int, m: int, k: int, vectors: bool) -> StabilityInfo | None:
    """The ``k`` smallest eigenvalues of an arrow matrix (:func:`contin.numerics.linalg.arrow_structure`), or None.

    The Morse index from the pivot-free ``L D L^T`` (:func:`inertia`); the eigenvalues by Lanczos on
    ``(H - sigma I)^-1`` (ARPACK in shift-invert mode, :class:`contin.numerics.linalg.ArrowCholesky` for the
    solves) with ``sigma`` just below the spectrum.  Cauchy's interlacing places the smallest
    eigenvalue of ``H`` below the band block's smallest, ``lambda_1(A)``, and the ``(m + 1)``-th above
    it; ``sigma = lambda_1(A) - delta``, ``delta`` doubled from ``1e-8 |H|`` until ``H - sigma I`` is
    positive definite, so the smallest eigenvalue lies within ``delta / 2`` of ``sigma`` (within
    ``delta`` when the first ``delta`` serves) and the ``(m + 1)``-th at least ``delta`` away: the
    iteration converges fast.  None (the caller then takes the dense or ARPACK route) when the count
    cannot be trusted, ARPACK does not converge, or its eigenvalues disagree with the count.
    """
    n = H.shape[0]
    n_neg = inertia(H)
    if n_neg is None:
        return None
    want = max(k, n_neg) if vectors else k
    if want > ARROW_MAX_EIGENPAIRS or want >= n - 1:
        return None
    H = sp.csr_matrix(H)
    parts = ArrowParts(H, b, m)
    size = float(np.max(np.abs(H.data), initial=0.0)) or 1.0
    lowest_lead = sla.eig_banded(parts.band, lower=True, eigvals_only=True, select="i", select_range=(0, 0))[0]
    delta = 1e-8 * size
    for _ in range(100):
        try:
            shifted = ArrowCholesky(parts, delta - lowest_lead)
            break
        except np.linalg.LinAlgError:
            delta *= 2.0
    else:
        return None
    sigma = lowest_lead - delta
    inverse = spla.LinearOperator((n, n), matvec=shifted.solve, dtype=float)
    start = lanczos_start(n)
    try:
        # few restarts: the wanted eigenvalues are well apart from the rest unless several are wanted
        # and lie in a cluster, where the dense route is the faster one
        w, V = spla.eigsh(H, k=want, sigma=sigma, which="LM", OPinv=inverse, v0=start, maxiter=ARROW_MAX_RESTARTS)
    except spla.ArpackNoConvergence:
        return None
    order = np.argsort(w)
    w, V = w[order], V[:, order]
    if int(np.count_nonzero(w < 0)) != min(want, n_neg):
        return None  # Lanczos missed an eigenvalue below zero, or found one the L D L^T did not count
    return StabilityInfo(n_neg, w[:k], V if vectors else None)


#: Largest matrix whose eigenvalues are computed densely when ARPACK does not converge (a few
#: seconds of ``eigh`` at most; beyond it the failure is reported).
DENSE_FALLBACK_LIMIT = 4000


def _sparse_info(H, k: int, vectors: bool) -> StabilityInfo:
    """ARPACK for the algebraically smallest, widened until a non-negative one shows.

    The smallest eigenvalues of a stiff matrix (eigenvalues spread over many decades, nearly zero
    ones among them: a thin structure at a fold) can defeat ARPACK's iteration; a matrix up to
    :data:`DENSE_FALLBACK_LIMIT` is then solved densely.
    """
    n = H.shape[0]
    try:
        return _arpack_info(H, k, vectors)
    except spla.ArpackNoConvergence as exc:
        if n > DENSE_FALLBACK_LIMIT:
            raise np.linalg.LinAlgError(f"stability: the smallest eigenvalues of the {n} x {n} Hessian did not "
                                      f"converge ({exc}); it is too large for the dense fallback "
                                      f"(n <= {DENSE_FALLBACK_LIMIT})") from exc
        return _dense_info(H, k, vectors)


def _arpack_info(H, k: int, vectors: bool) -> StabilityInfo:
    n = H.shape[0]
    m = k
    while True:
        w, V = spla.eigsh(sp.csr_matrix(H), k=min(m, n - 1), which="SA", v0=lanczos_start(n))
        order = np.argsort(w)
        w, V = w[order], V[:, order]
        if w[-1] >= 0 or m >= n - 1:
            break
        m *= 2
    n_neg = int(np.count_nonzero(w < 0))
    return StabilityInfo(n_neg, w[:k], V if vectors else None)
