"""Families of stability operators watched along a branch: bifurcations into other modes, detected and located.

A problem whose state space splits by a symmetry (a structure invariant under rotation about an axis,
whose Hessian at a symmetric state splits by wave number) traces one invariant subspace, but its
stability depends on every other one too.  An :class:`OperatorFamily` declares those operators, one per
key (e.g. a wave number ``n``): ``operator(key, u, p)``, symmetric, of any size.  A problem lists its
families in ``operator_families``; :func:`contin.continuation` then watches each like a fold
(:class:`ModeTest`, a test function of :mod:`contin.testfunctions`):

* at every accepted point the Morse index of every key's operator is counted (pivot-free ``L D L^T``,
  :func:`contin.stability.inertia`; an eigensolver when that cannot be trusted);
* a change of a key's count between two points is a bifurcation into that mode;
* it is located as the root, along the curve between them, of the operator's eigenvalue that crosses
  zero (number ``m`` in ascending order when the count goes from ``m`` to ``m + 1``: a continuous
  function that changes sign there; Brent's method on corrected points, as events are located), and recorded as a special point of kind ``"bifurcation"`` with ``info["family"]``,
  ``info["key"]``, ``info["eigenvalue"]`` and ``info["next_eigenvalue"]`` (the eigenvalue nearest zero
  and the next one at the located point: their ratio says how sharply it is located), the keys whose
  counts changed on the same step (``changed_keys``, the counts before and after) and, with
  ``vectors``, the mode (the null vector) in ``info["mode"]``.  When several keys change on one step,
  the first crossing along the curve is reported (the first instability) and the other located keys
  are listed in ``info["also"]``; an eigenvalue with the same sign at both ends (it crossed twice on one
  step) is listed in ``info["unlocated_keys"]``.  ``Settings.stop_at =
  ("bifurcation",)`` ends the run on the first located one.

The counts per point are stored in ``Branch.meta["modes"][family.name]``: ``keys``, ``multiplicity``,
``n_negative`` (one list of counts per stored point, in the order of ``keys``) and ``lowest`` (each
key's eigenvalue nearest zero, estimated by a few warm-started inverse-iteration steps on the same
factorization, :func:`count_and_lowest`; NaN where not estimated).  They are also added,
each with its multiplicity, to the Morse index the branch records under every stability label: a
point is stable only when it is stable against every mode (the families' operators are shared by
every control).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from .branch import SpecialPoint
from .curve import Curve, Point
from .segment import Segment
from .linalg import SingularMatrixError, bandwidths, factorize
from .stability import BANDED_MIN, _lower_band, stability_info
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
        The symmetric operator of a key at a state (sparse or dense).
    multiplicity : callable ``key -> int``, optional
        How many copies of the key's operator the whole Hessian holds (e.g. 2 for a wave number
        ``n >= 1``: its ``cos`` and ``sin`` modes); the total Morse index weighs counts with it.
        Default 1.
    vectors : bool
        Store the located mode (the operator's null vector) in ``info["mode"]``.
    """

    name: str
    keys: Sequence[Any]
    operator: Callable[[Any, np.ndarray, float], Any]
    multiplicity: Callable[[Any], int] | None = None
    vectors: bool = True

    def copies(self, key: Any) -> int:
        """The key's multiplicity (default 1)."""
        return 1 if self.multiplicity is None else int(self.multiplicity(key))


def _count(H: Any) -> int:
    """Morse index of a symmetric matrix.

    A banded Cholesky factorization first (LAPACK ``pbtrf``, O(n b^2)): most operators of a family are
    positive definite at most points, and it succeeds exactly then (count 0).  Otherwise
    :func:`contin.stability.stability_info` (a pivot-free ``L D L^T`` when it can be trusted, banded or
    dense eigenvalues otherwise).
    """
    if sp.issparse(H) and H.shape[0] > BANDED_MIN:
        b = max(bandwidths(H))
        if b + 1 <= 0.1 * H.shape[0]:
            from scipy.linalg import lapack

            _, info = lapack.dpbtrf(_upper_band(H, b), lower=0)
            if info == 0:
                return 0
    return int(stability_info(sp.csr_matrix(H) if sp.issparse(H) else np.asarray(H, dtype=float), 0).n_negative)


def _jacobi_scaled(K: Any) -> Any:
    """``D^-1/2 K D^-1/2`` with ``D = |diag K|`` floored at 1e-6 of its largest entry (a diagonal entry that
    itself goes to zero is a mode, not a scale)."""
    d = np.abs(K.diagonal()) if sp.issparse(K) else np.abs(np.diag(np.asarray(K, dtype=float)))
    top = float(np.max(d, initial=0.0))
    s = 1.0 / np.sqrt(np.maximum(d, 1e-6 * top)) if top > 0.0 else np.ones_like(d)
    if sp.issparse(K):
        Ds = sp.diags(s)
        return (Ds @ K @ Ds).tocsr()
    return np.asarray(K, dtype=float) * s[:, None] * s[None, :]


def _upper_band(H: Any, b: int) -> np.ndarray:
    """LAPACK's upper band storage ``ab[b + i - j, j] = H[i, j]`` of a sparse symmetric matrix."""
    C = sp.coo_matrix(H)
    keep = (C.col >= C.row) & (C.col - C.row <= b)
    ab = np.zeros((b + 1, H.shape[0]))
    ab[b + C.row[keep] - C.col[keep], C.col[keep]] = C.data[keep]
    return ab


def family_counts(family: OperatorFamily, u: np.ndarray, p: float) -> tuple[int, ...]:
    """The Morse index of every key's operator at ``(u, p)``, in the order of ``family.keys``."""
    return tuple(_count(family.operator(key, u, p)) for key in family.keys)


#: A located root of the bordered function is accepted as a singular point when the operator's eigenvalue
#: nearest zero is below this fraction of the next (Jacobi-scaled); otherwise the eigenvalue is bisected.
SINGULAR_RATIO = 1e-6

#: Inverse-iteration steps of the per-point eigenvalue estimate (warm-started from the previous point).
LOWEST_ITERATIONS = 4


def count_and_lowest(H: Any, start: np.ndarray | None = None) -> tuple[int, float, np.ndarray]:
    """The Morse index of the symmetric ``H`` and its eigenvalue nearest zero, with that eigenvector.

    The count is :func:`_count`'s (a banded Cholesky factorization when ``H`` is positive definite).
    The eigenvalue is the Rayleigh quotient after :data:`LOWEST_ITERATIONS` steps of inverse iteration
    on the same factorization (Cholesky, or a banded LU when ``H`` is indefinite) from ``start``: along a
    branch the previous point's eigenvector, so that the estimate converges as the path advances.  It
    is an estimate: of the smallest eigenvalue of a positive definite ``H`` (to 1e-5 relative in a
    few points when the next eigenvalue is twice as large, ``tests/test_modes.py``); once another
    eigenvalue comes nearer zero the warm start follows the old one for a few points.
    """
    n = H.shape[0]
    v = np.ones(n) if start is None or start.shape != (n,) else np.array(start, dtype=float)
    solve = None
    count = None
    if sp.issparse(H) and n > BANDED_MIN:
        b = max(bandwidths(H))
        if b + 1 <= 0.1 * n:
            from scipy.linalg import lapack

            cb, info = lapack.dpbtrf(_upper_band(H, b), lower=0)
            if info == 0:
                count = 0

                def solve(r: np.ndarray) -> np.ndarray:
                    return lapack.dpbtrs(cb, r, lower=0)[0]
    if count is None:
        count = int(stability_info(sp.csr_matrix(H) if sp.issparse(H) else np.asarray(H, dtype=float), 0).n_negative)
        try:
            F = factorize(sp.csc_matrix(H) if sp.issparse(H) else np.asarray(H, dtype=float))
            solve = F.solve
        except (SingularMatrixError, np.linalg.LinAlgError):
            return count, 0.0, v / np.linalg.norm(v)
    for _ in range(LOWEST_ITERATIONS):
        try:
            y = solve(v)
        except (SingularMatrixError, np.linalg.LinAlgError):
            return count, 0.0, v / np.linalg.norm(v)
        norm = np.linalg.norm(y)
        if not np.isfinite(norm) or norm == 0.0:
            return count, 0.0, v / np.linalg.norm(v)
        v = y / norm
    return count, float(v @ (H @ v)), v


def ordered_eigenpairs(H: Any, lo: int, hi: int, vectors: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """Eigenvalues number ``lo .. hi`` (ascending, 0-based) of the symmetric ``H``, with their vectors.

    LAPACK's banded solver for a sparse banded matrix (the cost of the few asked for, not of all);
    dense ``eigh`` otherwise.
    """
    n = H.shape[0]
    lo, hi = max(0, int(lo)), min(n - 1, int(hi))
    if sp.issparse(H) and n > BANDED_MIN:
        b = max(bandwidths(H))
        if b + 1 <= 0.1 * n:
            import scipy.linalg as sla

            ab = _lower_band(H, b)
            if vectors:
                w, V = sla.eig_banded(ab, lower=True, select="i", select_range=(lo, hi))
                return np.asarray(w), V
            return np.asarray(sla.eig_banded(ab, lower=True, eigvals_only=True, select="i", select_range=(lo, hi))), None
    A = H.toarray() if sp.issparse(H) else np.asarray(H, dtype=float)
    A = 0.5 * (A + A.T)
    if vectors:
        w, V = np.linalg.eigh(A)
        return w[lo:hi + 1], V[:, lo:hi + 1]
    return np.linalg.eigvalsh(A)[lo:hi + 1], None


def ordered_eigenvalue(H: Any, index: int) -> float:
    """The ``index``-th smallest eigenvalue (0: the smallest) of the symmetric ``H``.

    Eigenvalues in ascending order are continuous functions of the matrix, so along a curve the one
    that crosses zero where the Morse index goes from ``m`` to ``m + 1`` (or back) is number ``m``.
    LAPACK's banded solver for a sparse banded matrix; dense up to 3000 rows otherwise; Lanczos for the
    smallest ``index + 1`` beyond.
    """
    n = H.shape[0]
    if (sp.issparse(H) and n > BANDED_MIN) or n <= 3000:
        return float(ordered_eigenpairs(H, index, index)[0][0])
    from scipy.sparse.linalg import eigsh

    w = eigsh(sp.csc_matrix(H), k=index + 1, which="SA", return_eigenvectors=False)
    return float(np.sort(w)[index])


def eigenvalues_near_zero(H: Any, k: int = 2, vectors: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """The ``k`` eigenvalues of the symmetric ``H`` nearest zero, nearest first (with their vectors).

    Shift-invert Lanczos about zero for a sparse matrix of more than a few dozen rows (one sparse LU
    and a few solves); dense ``eigh`` otherwise, or when Lanczos fails (an exactly singular matrix).
    """
    n = H.shape[0]
    k = min(k, n)
    w = V = None
    if sp.issparse(H) and n > BANDED_MIN and k < n - 1:
        from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, eigsh

        try:
            w, V = eigsh(sp.csc_matrix(H), k=k, sigma=0.0, which="LM")
        except (ArpackError, ArpackNoConvergence, RuntimeError):
            w = None
    if w is None:
        A = H.toarray() if sp.issparse(H) else np.asarray(H, dtype=float)
        w, V = np.linalg.eigh(0.5 * (A + A.T))
    order = np.argsort(np.abs(w))[:k]
    return w[order], (V[:, order] if vectors else None)


class ModeTest(TestFunction):
    """Watches an :class:`OperatorFamily` along a branch (a test function of :mod:`contin.testfunctions`).

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

    @property
    def label(self) -> str:
        return self.name

    def value(self, pt: Point) -> tuple[int, ...]:  # type: ignore[override]
        if pt.modes is None:
            pt.modes = {}
        name = self.family.name
        if name not in pt.modes:
            counts, lowest = [], []
            for key in self.family.keys:
                c, lam, vec = count_and_lowest(self.family.operator(key, pt.u, pt.p), self._vectors.get(key))
                self._vectors[key] = vec
                counts.append(c)
                lowest.append(lam)
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

    def _bordered_root(self, seg: Segment, key: Any) -> float | None:
        """The root on the segment of ``g = 1 / (b^T K^-1 b)`` for the key's operator ``K``, ``b`` its
        eigenvector nearest zero at the segment's end: ``g`` vanishes exactly where ``K`` is singular and is
        smooth through it when one eigenvalue crosses (one factorization per evaluation).  None when ``g``
        does not change sign on the segment (the caller then bisects on the eigenvalue itself)."""
        fam, tol = self.family, self.curve.settings.locate_tol
        _, V = eigenvalues_near_zero(fam.operator(key, seg.B.u, seg.B.p), 1, vectors=True)
        border = V[:, 0]

        def g(sigma: float) -> float:
            u, p, _ = seg.point(sigma)
            K = fam.operator(key, u, p)
            try:
                y = factorize(sp.csc_matrix(K) if sp.issparse(K) else np.asarray(K, dtype=float)).solve(border)
            except (SingularMatrixError, np.linalg.LinAlgError):
                return 0.0  # exactly singular: the root itself
            return 1.0 / float(border @ y)

        try:
            f_A, f_B = g(0.0), g(seg.sigma_B)
        except (SingularMatrixError, np.linalg.LinAlgError, ZeroDivisionError):
            return None
        if not f_A * f_B < 0.0:
            return None
        sigma = seg.root(g, f_A, f_B, tol)
        # g also changes sign across a pole (b^T K^-1 b = 0, possible once K is indefinite): accept the
        # root only where K is singular, i.e. its eigenvalue nearest zero is far below the next
        u, p, _ = seg.point(sigma)
        w, _ = eigenvalues_near_zero(_jacobi_scaled(fam.operator(key, u, p)), 2)
        if w.size > 1 and abs(w[0]) > SINGULAR_RATIO * abs(w[1]):
            return None
        return sigma

    def locate(self, seg: Segment, before: tuple[int, ...], after: tuple[int, ...]) -> SpecialPoint:  # type: ignore[override]
        fam = self.family
        changed = [key for key, a, b in zip(fam.keys, before, after) if a != b]
        self._info = {"family": fam.name, "key": _plain(changed[0]), "changed_keys": [_plain(k) for k in changed],
                      "counts_before": list(before), "counts_after": list(after)}
        located: list[tuple[float, Any]] = []
        failures: dict[str, str] = {}
        for key, a, b in zip(fam.keys, before, after):
            if a == b:
                continue
            if abs(b - a) == 1:  # one eigenvalue crossed: the bordered function, no eigenvalues needed
                sigma = self._bordered_root(seg, key)
                if sigma is not None:
                    located.append((sigma, key, min(a, b)))
                    continue
            # the eigenvalues number min(a, b) .. max(a, b) - 1 (ascending) cross zero on the step: the
            # first crossing along the curve is where the key bifurcates
            for index in range(min(a, b), max(a, b)):
                g_A = self._eigenvalue(key, index, seg.A.u, seg.A.p)
                g_B = self._eigenvalue(key, index, seg.B.u, seg.B.p)
                if g_A * g_B > 0.0:  # crossed twice on the step: no sign change to bracket
                    failures[f"{key}[{index}]"] = f"eigenvalue {index} has the same sign at both ends ({g_A:.3g}, {g_B:.3g})"
                    continue

                def g(sigma: float, key: Any = key, index: int = index) -> float:
                    u, p, _ = seg.point(sigma)
                    return self._eigenvalue(key, index, u, p)
                located.append((seg.root(g, g_A, g_B, self.curve.settings.locate_tol), key, index))
        if failures:
            self._info["unlocated_keys"] = failures
        if not located:
            raise RuntimeError("; ".join(f"key {k}: {v}" for k, v in failures.items()))
        located.sort(key=lambda t: t[0])
        sigma, key, index = located[0]
        others = []
        for _, k, _ in located[1:]:
            if k != key and k not in others:
                others.append(k)
        u, p, res = seg.point(sigma)
        # at the located point the crossing eigenvalue is the one nearest zero; the next nearest says how
        # sharply it is located.  Both are of the Jacobi-scaled operator D^-1/2 K D^-1/2 (the same
        # inertia and singular points): a thin structure's operator spans many decades, and the rounding
        # error of its raw eigenvalues near zero (machine epsilon times its norm) would hide the location
        K = fam.operator(key, u, p)
        w, V = eigenvalues_near_zero(_jacobi_scaled(K), 2, vectors=fam.vectors)
        info: dict[str, Any] = {"key": _plain(key), "eigenvalue": float(w[0]),
                                "next_eigenvalue": float(w[1]) if w.size > 1 else None,
                                "also": [_plain(k) for k in others], "bracket_p": [seg.A.p, seg.B.p]}
        if fam.vectors and V is not None:
            info["mode"] = V[:, 0].copy()
        return SpecialPoint("bifurcation", p, u.copy(), self.curve.problem.evaluate_observables(u, p), residual=res,
                            located=True, s=seg.A.s + sigma, label=self.name, info=info)


def _plain(key: Any) -> Any:
    """A key as a plain Python value (JSON-ready)."""
    return key.item() if isinstance(key, np.generic) else key
