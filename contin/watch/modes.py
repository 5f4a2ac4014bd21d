"""Families of stability operators watched along a branch: bifurcations into other modes, detected and located.

A problem whose state space splits by a symmetry (a structure invariant under rotation about an axis,
whose Hessian at a symmetric state splits by wave number) traces one invariant subspace, but its
stability depends on every other one too.  An :class:`OperatorFamily` declares those operators, one per
key (e.g. a wave number ``n``): ``operator(key, u, p)``, symmetric, of any size.  A problem lists its
families in ``operator_families``; :func:`contin.continuation` then watches each like a fold
(:class:`ModeTest`, a test function of :mod:`contin.watch.testfunctions`):

* at every accepted point the Morse index of every key's operator is counted (a banded operator --
  a :class:`~contin.numerics.linalg.SymmetricBand`, or a sparse matrix of narrow band -- by its pivot-free
  ``L D L^T`` run as banded Cholesky factorizations, :meth:`contin.numerics.linalg.SymmetricBand.inertia`;
  others by :func:`contin.numerics.stability.stability_info`), and its eigenvalue nearest zero estimated;
* a change of a key's count between two points is a bifurcation into that mode;
* it is located on the curve between them as the root of the bordered function
  ``g = 1 / (b^T K^-1 b)`` (``b`` the key's eigenvector estimate), which vanishes exactly where the
  operator ``K`` is singular and is smooth through it when one eigenvalue crosses: Brent's method on
  corrected points, as events are located, to the location tolerance or ``g``'s noise floor
  (:data:`BORDERED_NOISE`); the root is accepted where the Jacobi-scaled operator's eigenvalue
  nearest zero is below :data:`SINGULAR_RATIO` of the next, else (and when the count changes by more
  than one) the crossing eigenvalue itself (number ``m`` in ascending order when the count goes from
  ``m`` to ``m + 1``) is bisected.  It is recorded as a special point of kind ``"bifurcation"`` with
  ``info["family"]``, ``info["key"]``, ``info["eigenvalue"]`` and ``info["next_eigenvalue"]`` (the
  eigenvalues nearest zero of the Jacobi-scaled operator at the located point: their ratio says how
  sharply it is located), the keys whose counts changed on the same step (``changed_keys``, the counts
  before and after) and, with ``vectors``, the mode (the operator's null vector, unit norm, in the
  operator's own variables) in ``info["mode"]``.  When
  several keys change on one step, the first crossing along the curve is reported (the first
  instability) and the other located keys are listed in ``info["also"]``; an eigenvalue with the same
  sign at both ends (it crossed twice on one step) is listed in ``info["unlocated_keys"]``.
  ``Settings.stop_at = ("bifurcation",)`` ends the run on the first located one.

The counts per point are stored in ``Branch.meta["modes"][family.name]``: ``keys``, ``multiplicity``,
``n_negative`` (one list of counts per stored point, in the order of ``keys``) and ``lowest`` (each
key's eigenvalue nearest zero, estimated by a few warm-started inverse-iteration steps on the same
factorization, :func:`count_and_lowest`; NaN where not estimated).  They are also added,
each with its multiplicity, to the Morse index the branch records under every stability label: a
point is stable only when it is stable against every mode (the families' operators are shared by
every control).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..numerics.linalg import (BandedLU, SingularMatrixError, SymmetricBand, bandwidths, cholesky_band_solver, factorize,
                               upper_band)
from ..numerics.stability import BANDED_MIN, LDL_GROWTH_LIMIT, lanczos_start, pivot_free_ldlt, stability_info
from ..path.curve import Curve, Point
from ..path.segment import Segment
from ..results.branch import SpecialPoint
from .testfunctions import TestFunction

__all__ = ["OperatorFamily", "ModeTest", "family_counts", "count_and_lowest", "eigenvalues_near_zero", "ordered_eigenvalue",
           "ordered_eigenpairs"]


@dataclass(frozen=True)
class OperatorFamily:
    """Symmetric operators, one per key, whose definiteness decides stability besides the problem's own.

    Attributes
    ----------
    name : str
        What the key is (e.g. ``"n"``, a wave number); the special points' ``info["family"]``.
    keys : sequence
        The keys watched, in order.
    operator : callable ``(key, u, p) -> matrix``
        The symmetric operator of a key at a state (sparse, dense or a
        :class:`~contin.numerics.linalg.SymmetricBand`).
    multiplicity : callable ``key -> int``, optional
        How many copies of the key's operator the whole Hessian holds (e.g. 2 for a wave number
        ``n >= 1``: its ``cos`` and ``sin`` modes); the total Morse index weighs counts with it.
        Default 1.
    vectors : bool
        Store the located mode (the operator's null vector) in ``info["mode"]``.
    all_operators : callable ``(u, p) -> list``, optional
        Every key's operator at a state, in the order of ``keys``: where the operators share work
        per state, the cheaper way for the per-point counts (default: ``operator`` per key).
    mode_shape : callable ``(key, mode) -> array``, optional
        The model's own description of a located mode (``info["mode"]``, in the operator's
        variables), e.g. per-node amplitudes, for the outputs.
    """

    name: str
    keys: Sequence[Any]
    operator: Callable[[Any, np.ndarray, float], Any]
    multiplicity: Callable[[Any], int] | None = None
    vectors: bool = True
    all_operators: Callable[[np.ndarray, float], Sequence[Any]] | None = None
    mode_shape: Callable[[Any, np.ndarray], np.ndarray] | None = None

    def copies(self, key: Any) -> int:
        """The key's multiplicity (default 1)."""
        return 1 if self.multiplicity is None else int(self.multiplicity(key))

    def operators(self, u: np.ndarray, p: float) -> Sequence[Any]:
        """Every key's operator at ``(u, p)``, in the order of :attr:`keys`."""
        if self.all_operators is not None:
            return self.all_operators(u, p)
        return [self.operator(key, u, p) for key in self.keys]


def _band(H: Any) -> SymmetricBand | None:
    """``H`` as a :class:`~contin.numerics.linalg.SymmetricBand` when it is one, or a sparse matrix narrow enough
    for LAPACK's band routines; None otherwise."""
    if isinstance(H, SymmetricBand):
        return H
    if sp.issparse(H) and H.shape[0] > BANDED_MIN:
        b = max(bandwidths(H))
        if b + 1 <= 0.1 * H.shape[0]:
            # a family's operators of one read-only pattern (a FixedPattern's) find their band positions once
            return SymmetricBand(upper_band(H, b))
    return None


def _general(H: Any) -> Any:
    """``H`` as a CSR or dense matrix for the general routines."""
    if isinstance(H, SymmetricBand):
        return H.tocsr()
    return sp.csr_matrix(H) if sp.issparse(H) else np.asarray(H, dtype=float)


def _factor_and_count(H: Any) -> tuple[int, Callable[[np.ndarray], np.ndarray] | None]:
    """The Morse index of the symmetric ``H`` and a solver with ``H`` (None when it is exactly singular).

    A banded ``H`` is counted by its pivot-free ``L D L^T`` run as banded Cholesky factorizations
    (:meth:`contin.numerics.linalg.SymmetricBand.inertia`, O(n b^2)): most operators of a family are positive
    definite at most points, and one Cholesky factorization then counts (0) and solves; an indefinite
    one is solved with a banded LU.  When that cannot be trusted, the general pivot-free ``L D L^T``
    (:func:`contin.numerics.stability.pivot_free_ldlt`); for other matrices
    :func:`contin.numerics.stability.stability_info` counts and a general LU solves.
    """
    B = _band(H)
    if B is not None:
        out = B.inertia(LDL_GROWTH_LIMIT)
        if out is not None:
            count, cholesky = out
            if cholesky is not None:
                return 0, cholesky_band_solver(cholesky)  # r may have several columns
            lu = BandedLU(B)
            return count, (None if lu.exactly_singular else lu.solve)
        ldlt = pivot_free_ldlt(B)
        if ldlt is not None:
            d, lu = ldlt
            return int(np.count_nonzero(d < 0.0)), lambda r: lu.solve(np.asarray(r, dtype=float))
        count = int(stability_info(B.tocsr(), 0).n_negative)
        lu = BandedLU(B)
        return count, (None if lu.exactly_singular else lu.solve)
    G = _general(H)
    count = int(stability_info(G, 0).n_negative)
    try:
        F = factorize(sp.csc_matrix(G) if sp.issparse(G) else G)
    except (SingularMatrixError, np.linalg.LinAlgError):
        return count, None
    return count, F.solve


def _solver(H: Any) -> Callable[[np.ndarray], np.ndarray] | None:
    """A solver with the symmetric ``H`` (None when it is exactly singular), without its Morse index: a
    banded Cholesky factorization when ``H`` is positive definite, else a banded LU (other matrices:
    :func:`_factor_and_count`'s)."""
    B = _band(H)
    if B is None:
        return _factor_and_count(H)[1]
    from scipy.linalg import lapack

    cb, info = lapack.dpbtrf(B.ab, lower=0)
    if info == 0:
        return cholesky_band_solver(cb)
    lu = BandedLU(B)
    return None if lu.exactly_singular else lu.solve


def _count(H: Any) -> int:
    """Morse index of a symmetric matrix (:func:`_factor_and_count`)."""
    return _factor_and_count(H)[0]


def _scaled_near_zero(K: Any, vectors: bool, start: np.ndarray | None = None,
                      solve: Callable[[np.ndarray], np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray | None]:
    """The two eigenvalues nearest zero of the Jacobi-scaled ``K`` (:func:`_jacobi_scaled`), nearest first, and
    with ``vectors`` the null vector of ``K`` itself they give (the scaled eigenvector mapped back, unit norm).
    ``start``: a guess of ``K``'s null vector; ``solve``: a solver with ``K`` already at hand (a banded
    ``K``'s scaled operator is then solved through it instead of being factorized again)."""
    scale = _jacobi_scaling(K)
    guess = None if start is None else start / scale
    w, V = eigenvalues_near_zero(_jacobi_scaled(K, scale), 2, vectors=vectors, start=guess,
                                 solve=None if solve is None else _scaled_solver(solve, scale))
    if not vectors or V is None:
        return w, None
    mode = scale * V[:, 0]
    return w, mode / np.linalg.norm(mode)


def _scaled_solver(solve: Callable[[np.ndarray], np.ndarray], scale: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """A solver with ``S K S`` (``S = diag(scale)``) from one with ``K``: ``(S K S)^-1 r = S^-1 K^-1 S^-1 r``."""
    inverse = 1.0 / scale

    def scaled(r: np.ndarray) -> np.ndarray:
        factor = inverse if np.ndim(r) == 1 else inverse[:, None]
        return factor * solve(factor * r)
    return scaled


def _jacobi_scaling(K: Any) -> np.ndarray:
    """``|diag K|^-1/2``, the diagonal floored at 1e-6 of its largest entry (a diagonal entry that itself goes
    to zero is a mode, not a scale)."""
    if sp.issparse(K) or isinstance(K, SymmetricBand):
        d = np.abs(K.diagonal())
    else:
        d = np.abs(np.diag(np.asarray(K, dtype=float)))
    top = float(np.max(d, initial=0.0))
    return 1.0 / np.sqrt(np.maximum(d, 1e-6 * top)) if top > 0.0 else np.ones_like(d)


def _jacobi_scaled(K: Any, scale: np.ndarray | None = None) -> Any:
    """``D^-1/2 K D^-1/2`` with the scaling of :func:`_jacobi_scaling` (or the given ``scale``)."""
    s = _jacobi_scaling(K) if scale is None else scale
    if isinstance(K, SymmetricBand):
        return K.scaled(s)
    if sp.issparse(K):
        Ds = sp.diags(s)
        return (Ds @ K @ Ds).tocsr()
    return np.asarray(K, dtype=float) * s[:, None] * s[None, :]


def family_counts(family: OperatorFamily, u: np.ndarray, p: float) -> tuple[int, ...]:
    """The Morse index of every key's operator at ``(u, p)``, in the order of ``family.keys``."""
    return tuple(_count(K) for K in family.operators(u, p))


#: A located root of the bordered function is accepted as a singular point when the operator's eigenvalue
#: nearest zero is below this fraction of the next (Jacobi-scaled); otherwise the eigenvalue is bisected.
SINGULAR_RATIO = 1e-6

#: Inverse-iteration steps of the per-point eigenvalue estimate (warm-started from the previous point).
LOWEST_ITERATIONS = 3


def count_and_lowest(H: Any, start: np.ndarray | None = None) -> tuple[int, float, np.ndarray]:
    """The Morse index of the symmetric ``H`` and its eigenvalue nearest zero, with that eigenvector.

    The count and the factorization are :func:`_factor_and_count`'s (a banded Cholesky factorization
    when ``H`` is positive definite, a banded LU otherwise).  The eigenvalue is the Rayleigh quotient
    after :data:`LOWEST_ITERATIONS` steps of inverse iteration on that factorization from ``start``:
    along a branch the previous point's eigenvector, so that the estimate converges as the path
    advances.  It is an estimate: of the smallest eigenvalue of a positive definite ``H`` (to 1e-5
    relative in a few points when the next eigenvalue is twice as large, ``tests/test_modes.py``);
    once another eigenvalue comes nearer zero the warm start follows the old one for a few points.
    """
    return _count_lowest_solver(H, start)[:3]


def _count_lowest_solver(H: Any, start: np.ndarray | None) -> tuple[int, float, np.ndarray,
                                                                    Callable[[np.ndarray], np.ndarray] | None]:
    """:func:`count_and_lowest` and the solver with ``H`` it factorized (None when ``H`` is exactly singular)."""
    n = H.shape[0]
    v = np.ones(n) if start is None or start.shape != (n,) else np.array(start, dtype=float)
    count, solve = _factor_and_count(H)
    if solve is None:
        return count, 0.0, v / np.linalg.norm(v), None
    quotient = 0.0
    for _ in range(LOWEST_ITERATIONS):
        try:
            y = solve(v)
        except (SingularMatrixError, np.linalg.LinAlgError):
            return count, 0.0, v / np.linalg.norm(v), solve
        norm = math.sqrt(float(y @ y))
        if not math.isfinite(norm) or norm == 0.0:
            return count, 0.0, v / np.linalg.norm(v), solve
        # the Rayleigh quotient of y / |y| without a product with H: H y = v makes y^T H y = y^T v
        quotient = float(y @ v) / (norm * norm)
        v = y / norm
    return count, quotient, v, solve


def ordered_eigenpairs(H: Any, lo: int, hi: int, vectors: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """Eigenvalues number ``lo .. hi`` (ascending, 0-based) of the symmetric ``H``, with their vectors.

    LAPACK's banded solver for a banded matrix (the cost of the few asked for, not of all); dense
    ``eigh`` otherwise.
    """
    n = H.shape[0]
    lo, hi = max(0, int(lo)), min(n - 1, int(hi))
    B = _band(H)
    if B is not None:
        import scipy.linalg as sla

        if vectors:
            w, V = sla.eig_banded(B.ab, lower=False, select="i", select_range=(lo, hi))
            return np.asarray(w), V
        return np.asarray(sla.eig_banded(B.ab, lower=False, eigvals_only=True, select="i", select_range=(lo, hi))), None
    A = _general(H)
    A = A.toarray() if sp.issparse(A) else A
    A = 0.5 * (A + A.T)
    if vectors:
        w, V = np.linalg.eigh(A)
        return w[lo:hi + 1], V[:, lo:hi + 1]
    return np.linalg.eigvalsh(A)[lo:hi + 1], None


def ordered_eigenvalue(H: Any, index: int) -> float:
    """The ``index``-th smallest eigenvalue (0: the smallest) of the symmetric ``H``.

    Eigenvalues in ascending order are continuous functions of the matrix, so along a curve the one
    that crosses zero where the Morse index goes from ``m`` to ``m + 1`` (or back) is number ``m``.
    LAPACK's banded solver for a banded matrix; dense up to 3000 rows otherwise; Lanczos for the
    smallest ``index + 1`` beyond.
    """
    n = H.shape[0]
    if _band(H) is not None or n <= 3000:
        return float(ordered_eigenpairs(H, index, index)[0][0])
    from scipy.sparse.linalg import eigsh

    w = eigsh(sp.csc_matrix(H), k=index + 1, which="SA", return_eigenvectors=False, v0=lanczos_start(n))
    return float(np.sort(w)[index])


def eigenvalues_near_zero(H: Any, k: int = 2, vectors: bool = False, start: np.ndarray | None = None,
                          solve: Callable[[np.ndarray], np.ndarray] | None = None
                          ) -> tuple[np.ndarray, np.ndarray | None]:
    """The ``k`` eigenvalues of the symmetric ``H`` nearest zero, nearest first (with their vectors).

    A banded ``H``: subspace inverse iteration on its factorization (:func:`_subspace_near_zero`, from
    ``start`` if given; ``solve``: a solver with ``H`` already at hand instead of a new factorization).
    Otherwise shift-invert Lanczos about zero for a sparse matrix of more than a few dozen rows; dense
    ``eigh`` for the rest, or when either fails (an exactly singular matrix).
    """
    n = H.shape[0]
    k = min(k, n)
    w = V = None
    if _band(H) is not None:
        w, V = _subspace_near_zero(_band(H), k, start, solve)
    elif sp.issparse(H) and n > BANDED_MIN and k < n - 1:
        from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, eigsh

        try:
            w, V = eigsh(sp.csc_matrix(H), k=k, sigma=0.0, which="LM", v0=lanczos_start(n))
        except (ArpackError, ArpackNoConvergence, RuntimeError):
            w = None
    if w is None:
        A = _general(H)
        A = A.toarray() if sp.issparse(A) else A
        w, V = np.linalg.eigh(0.5 * (A + A.T))
    order = np.argsort(np.abs(w))[:k]
    return w[order], (V[:, order] if vectors and V is not None else None)


#: Subspace inverse iteration of :func:`_subspace_near_zero`: extra vectors beyond those asked for, the
#: largest number of sweeps, and the residuals relative to the Ritz values that end it (the nearest zero,
#: the others).
SUBSPACE_EXTRA = 3
SUBSPACE_SWEEPS = 40
SUBSPACE_TOL = 1e-10
SUBSPACE_TOL_OTHERS = 1e-4


def _subspace_near_zero(H: Any, k: int, start: np.ndarray | None = None,
                        solve: Callable[[np.ndarray], np.ndarray] | None = None
                        ) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The ``k`` eigenpairs of the symmetric ``H`` nearest zero by subspace inverse iteration.

    ``k + SUBSPACE_EXTRA`` vectors (``start`` and random ones of a fixed seed: the result is
    reproducible) are multiplied by ``H^-1`` (``solve``, or one factorization, :func:`_factor_and_count`),
    orthonormalized, and rotated to the Ritz vectors of ``H`` on their span, until each Ritz pair's
    residual ``|H x - theta x|`` (which bounds its eigenvalue's error) is below :data:`SUBSPACE_TOL`
    of ``|theta|`` for the nearest and :data:`SUBSPACE_TOL_OTHERS` for the next ``k - 1``, or below
    the roundoff floor (a thousand times machine epsilon times the largest diagonal entry).
    Eigenvalue ``i`` converges like ``(lambda_i / lambda_{k+extra})^sweeps``; O(n b^2) per sweep for a
    band, where LAPACK's banded eigensolver spends O(n^2) on the eigenvectors.  ``(None, None)`` when
    ``H`` is exactly singular to the factorization.
    """
    n = H.shape[0]
    m = min(n, k + SUBSPACE_EXTRA)
    if solve is None:
        solve = _factor_and_count(H)[1]
    if solve is None:
        return None, None
    X = np.random.default_rng(12345).standard_normal((n, m))
    if start is not None and start.shape == (n,):
        X[:, 0] = start  # a guess of the nearest eigenvector (e.g. a bordered solve's)
    floor = 1e3 * np.finfo(float).eps * float(np.max(np.abs(H.diagonal()), initial=0.0))
    tol = np.full(k, SUBSPACE_TOL_OTHERS)
    tol[0] = SUBSPACE_TOL
    theta = None
    for _ in range(SUBSPACE_SWEEPS):
        try:
            Y = np.asarray(solve(X))
        except (SingularMatrixError, np.linalg.LinAlgError):
            return None, None
        if not np.isfinite(Y).all():
            return None, None
        Q, _ = np.linalg.qr(Y)
        HQ = H @ Q
        theta, S = np.linalg.eigh(0.5 * (Q.T @ HQ + (Q.T @ HQ).T))
        order = np.argsort(np.abs(theta))
        theta, S = theta[order], S[:, order]
        X = Q @ S
        residual = np.linalg.norm(HQ @ S[:, :k] - X[:, :k] * theta[:k], axis=0)
        if np.all(residual <= tol * np.abs(theta[:k]) + floor):
            break
    return theta[:k], X[:, :k]


class ModeTest(TestFunction):
    """Watches an :class:`OperatorFamily` along a branch (a test function of :mod:`contin.watch.testfunctions`).

    Its value at a point is the tuple of the keys' Morse indices (also kept on the point, for the
    recorder); a change is a bifurcation, located on the key whose eigenvalue crosses zero first.
    """

    kind = "bifurcation"

    def __init__(self, curve: Curve, family: OperatorFamily) -> None:
        super().__init__(curve)
        self.family = family
        self.name = f"bifurcation({family.name})"
        self._info: dict[str, Any] = {}
        self._vectors: dict[Any, np.ndarray] = {}  # each key's last eigenvector: the next estimate's start
        # the operators and solvers of the last two points counted: a located bifurcation's bracket ends
        self._factored: list[tuple[Point, dict[Any, tuple[Any, Callable[[np.ndarray], np.ndarray] | None]]]] = []

    @property
    def label(self) -> str:
        return self.name

    def value(self, pt: Point) -> tuple[int, ...]:  # type: ignore[override]
        if pt.modes is None:
            pt.modes = {}
        name = self.family.name
        if name not in pt.modes:
            counts, lowest, factored = [], [], {}
            for key, K in zip(self.family.keys, self.family.operators(pt.u, pt.p)):
                c, lam, vec, solve = _count_lowest_solver(K, self._vectors.get(key))
                self._vectors[key] = vec
                factored[key] = (K, solve)
                counts.append(c)
                lowest.append(lam)
            self._factored = [*self._factored[-1:], (pt, factored)]
            pt.modes[name] = tuple(counts)
            pt.modes[f"{name}.lowest"] = tuple(lowest)  # the eigenvalue nearest zero per key, for the records
        return pt.modes[name]

    def detect(self, before: tuple[int, ...], after: tuple[int, ...]) -> bool:  # type: ignore[override]
        return before != after

    def annotate(self, spt: SpecialPoint) -> SpecialPoint:
        spt.info = {**self._info, **spt.info}
        return spt

    def _eigenvalue(self, key: Any, index: int, u: np.ndarray, p: float) -> float:
        return ordered_eigenvalue(self.family.operator(key, u, p), index)

    def _kept(self, key: Any, pt: Point) -> tuple[Any, Callable[[np.ndarray], np.ndarray] | None] | None:
        """The key's operator at the point ``pt`` and its solver as :meth:`value` made them there (kept for the
        last two points counted: a located bifurcation's bracket ends), or None."""
        for counted, factored in self._factored:
            if counted is pt and key in factored:
                return factored[key]
        return None

    def _bordered_root(self, seg: Segment, key: Any, index: int, nodes: dict, negative_at_B: bool = True,
                       rank: int | None = None) -> tuple[float, np.ndarray, np.ndarray | None] | None:
        """The key's bifurcation on the segment (its eigenvalue number ``index`` crosses zero), or None.

        The root of the bordered function ``g = 1 / (b^T K^-1 b)`` of the key's operator ``K`` along the
        curve, ``b`` the key's eigenvector estimate at the segment's end ``B`` (kept by :meth:`value`):
        ``g`` vanishes exactly where ``K`` is singular and is smooth through it when one eigenvalue
        crosses (one factorization per converged point).  Brent's method, ended at the location
        tolerance or where ``|g|`` falls to its noise floor (:data:`BORDERED_NOISE` of its size at the
        ends: the converged points carry the corrector's tolerance).  Converged points are kept in
        ``nodes`` (``sigma -> (u, p)``).  Returns ``(sigma, w, mode)``, ``w`` the two eigenvalues of the
        Jacobi-scaled operator nearest zero at the root and ``mode`` the operator's null vector there
        (None without ``vectors``); None when ``g`` does not
        change sign, or its root is a pole of ``b^T K^-1 b`` rather than a singular ``K`` (the eigenvalue
        nearest zero not below :data:`SINGULAR_RATIO` of the next): the caller then bisects on the
        eigenvalue itself.

        The estimate follows, from point to point, the eigenvalue that was nearest zero; when another one
        crosses, it can still be the old one's vector, and ``g`` then keeps its sign.  ``g`` is tried once
        more with the border the crossing eigenvalue's own vector at ``B``: of the :data:`CROSSING_PAIRS`
        eigenpairs nearest zero there, the nearest on the side the eigenvalue crossed to
        (``negative_at_B``: the count grew on the step).  Where several eigenvalues crossed on the step,
        ``rank`` says which one this is among those on that side, counted from zero (0 the nearest), and
        the border is that one's vector from the start.
        """
        fam, tol = self.family, self.curve.settings.locate_tol
        ops: dict[float, Any] = {}
        solvers: dict[float, Callable[[np.ndarray], np.ndarray] | None] = {}
        for sigma, pt in ((0.0, seg.A), (seg.sigma_B, seg.B)):  # the ends' operators as value() factorized them
            kept = self._kept(key, pt)
            if kept is not None:
                ops[sigma], solvers[sigma] = kept
        K_B = ops.get(seg.sigma_B)
        if K_B is None:
            K_B = ops[seg.sigma_B] = fam.operator(key, seg.B.u, seg.B.p)
        border = self._vectors.get(key)
        if border is None or border.shape != (K_B.shape[0],):
            _, V = eigenvalues_near_zero(K_B, 1, vectors=True)
            border = V[:, 0]
        border = border / np.linalg.norm(border)

        def operator(sigma: float) -> Any:
            if sigma not in ops:
                if sigma not in nodes:
                    u, p, _ = seg.point(sigma)
                    nodes[sigma] = (u, p)
                ops[sigma] = fam.operator(key, *nodes[sigma])
            return ops[sigma]

        def g(sigma: float) -> float:
            if sigma not in solvers:
                solvers[sigma] = _solver(operator(sigma))
            solve = solvers[sigma]
            if solve is None:
                return 0.0  # exactly singular: the root itself
            try:
                q = float(border @ solve(border))
            except (SingularMatrixError, np.linalg.LinAlgError):
                return 0.0
            return 1.0 / q if q != 0.0 else np.inf

        if rank is not None:  # several crossed: this one's own vector at B
            if seg.sigma_B not in solvers:
                solvers[seg.sigma_B] = _solver(K_B)
            border = _nearest_on_side(K_B, negative_at_B, border, solvers[seg.sigma_B], rank)
            if border is None:
                return None
        g_A, g_B = g(0.0), g(seg.sigma_B)
        if rank is None and not (np.isfinite(g_A) and np.isfinite(g_B) and g_A * g_B < 0.0):
            crossing = _nearest_on_side(K_B, negative_at_B, border, solvers.get(seg.sigma_B))
            if crossing is None:
                return None
            border = crossing  # g reads it: the bordered function of the crossing eigenvalue's vector
            g_A, g_B = g(0.0), g(seg.sigma_B)
        if not (np.isfinite(g_A) and np.isfinite(g_B) and g_A * g_B < 0.0):
            return None
        sigma = seg.root(g, g_A, g_B, tol, ftol=BORDERED_NOISE)
        w, mode = _scaled_near_zero(operator(sigma), fam.vectors, start=border, solve=solvers.get(sigma))
        if w.size > 1 and abs(w[0]) > SINGULAR_RATIO * abs(w[1]):
            return None
        return sigma, w, mode

    def locate(self, seg: Segment, before: tuple[int, ...], after: tuple[int, ...]) -> SpecialPoint:  # type: ignore[override]
        fam = self.family
        changed = [key for key, a, b in zip(fam.keys, before, after) if a != b]
        self._info = {"family": fam.name, "key": _plain(changed[0]), "changed_keys": [_plain(k) for k in changed],
                      "counts_before": list(before), "counts_after": list(after)}
        located: list[tuple[float, Any, Any]] = []
        failures: dict[str, str] = {}
        nodes: dict[float, tuple[np.ndarray, float]] = {0.0: (seg.A.u, seg.A.p), seg.sigma_B: (seg.B.u, seg.B.p)}
        for key, a, b in zip(fam.keys, before, after):
            if a == b:
                continue
            if abs(b - a) == 1:  # one eigenvalue crossed: the bordered function, no eigenvalues needed
                found = self._bordered_root(seg, key, min(a, b), nodes, b > a)
                if found is not None:
                    located.append((found[0], key, found[1:]))
                    continue
                indices = [min(a, b)]
            else:
                # the eigenvalues number min(a, b) .. max(a, b) - 1 (ascending) cross zero on the step, each
                # by the bordered function of its own vector at B (at B the crossed ones lie on one side of
                # zero, number b - 1 the nearest of them when the count grew, number b when it fell)
                indices = []
                for index in range(min(a, b), max(a, b)):
                    found = self._bordered_root(seg, key, index, nodes, b > a, b - 1 - index if b > a else index - b)
                    if found is not None:
                        located.append((found[0], key, found[1:]))
                    else:
                        indices.append(index)
            # the rest bisected on the eigenvalue itself: the first crossing along the curve is where the
            # key bifurcates
            for index in indices:
                g_A, g_B = (ordered_eigenvalue(kept[0], index) if kept is not None else
                            self._eigenvalue(key, index, pt.u, pt.p)
                            for pt, kept in ((seg.A, self._kept(key, seg.A)), (seg.B, self._kept(key, seg.B))))
                if g_A * g_B > 0.0:  # crossed twice on the step: no sign change to bracket
                    failures[f"{key}[{index}]"] = f"eigenvalue {index} has the same sign at both ends ({g_A:.3g}, {g_B:.3g})"
                    continue

                def g(sigma: float, key: Any = key, index: int = index) -> float:
                    u, p, _ = seg.point(sigma)
                    return self._eigenvalue(key, index, u, p)
                located.append((seg.root(g, g_A, g_B, self.curve.settings.locate_tol), key, None))
        if failures:
            self._info["unlocated_keys"] = failures
        if not located:
            raise RuntimeError("; ".join(f"key {k}: {v}" for k, v in failures.items()))
        located.sort(key=lambda t: t[0])
        sigma, key, eig = located[0]
        others = []
        for _, k, _ in located[1:]:
            if k != key and k not in others:
                others.append(k)
        u, p, res = seg.point(sigma)
        # at the located point the crossing eigenvalue is the one nearest zero; the next nearest says how
        # sharply it is located.  Both are of the Jacobi-scaled operator D^-1/2 K D^-1/2 (the same
        # inertia and singular points): a thin structure's operator spans many decades, and the rounding
        # error of its raw eigenvalues near zero (machine epsilon times its norm) would hide the location
        if eig is None:
            eig = _scaled_near_zero(fam.operator(key, u, p), fam.vectors)
        w, mode = eig
        info: dict[str, Any] = {"key": _plain(key), "eigenvalue": float(w[0]),
                                "next_eigenvalue": float(w[1]) if w.size > 1 else None,
                                "also": [_plain(k) for k in others], "bracket_p": [seg.A.p, seg.B.p]}
        if fam.vectors and mode is not None:
            info["mode"] = mode
        return SpecialPoint("bifurcation", p, u.copy(), self.curve.problem.evaluate_observables(u, p), residual=res,
                            located=True, s=seg.A.s + sigma, label=self.name, info=info)


#: Eigenpairs nearest zero among which a location looks for the crossing eigenvalue's vector.
CROSSING_PAIRS = 3


def _nearest_on_side(K: Any, negative: bool, start: np.ndarray | None,
                     solve: Callable[[np.ndarray], np.ndarray] | None, rank: int = 0) -> np.ndarray | None:
    """The unit eigenvector of the symmetric ``K``'s eigenvalue number ``rank`` (0: the nearest zero) among the
    negative ones (``negative``) or the others, looked for among the :data:`CROSSING_PAIRS` ``+ rank``
    eigenpairs nearest zero (:func:`eigenvalues_near_zero`, from ``start``, with ``solve`` a solver with
    ``K`` at hand); None when fewer of them lie on that side."""
    w, V = eigenvalues_near_zero(K, CROSSING_PAIRS + rank, vectors=True, start=start, solve=solve)
    if V is None:
        return None
    side = np.flatnonzero((w < 0.0) == negative)
    if side.size <= rank:
        return None
    v = V[:, side[rank]]
    return v / np.linalg.norm(v)


#: The bordered function's noise floor, relative to its size at the segment's ends: below it a converged
#: point is the root to within the corrector's own tolerance (the located points' eigenvalue nearest
#: zero is then about 1e-10 of the next, ``tests/test_modes.py``).
BORDERED_NOISE = 1e-8


def _plain(key: Any) -> Any:
    """A key as a plain Python value (JSON-ready)."""
    return key.item() if isinstance(key, np.generic) else key
