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

The counts per point are stored in ``Branch.meta["modes"][family.name]``: ``keys``, ``multiplicity`` and
``n_negative`` (one list of counts per stored point, in the order of ``keys``).  They are also added,
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

__all__ = ["OperatorFamily", "ModeTest", "family_counts", "eigenvalues_near_zero", "ordered_eigenvalue",
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
    """Morse index of a symmetric matrix (:func:`contin.stability.stability_info`: a pivot-free
    ``L D L^T`` when it can be trusted, banded or dense eigenvalues otherwise)."""
    return int(stability_info(sp.csr_matrix(H) if sp.issparse(H) else np.asarray(H, dtype=float), 0).n_negative)


def family_counts(family: OperatorFamily, u: np.ndarray, p: float) -> tuple[int, ...]:
    """The Morse index of every key's operator at ``(u, p)``, in the order of ``family.keys``."""
    return tuple(_count(family.operator(key, u, p)) for key in family.keys)


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
    if n <= 3000:
        A = H.toarray() if sp.issparse(H) else np.asarray(H, dtype=float)
        return float(np.linalg.eigvalsh(0.5 * (A + A.T))[index])
    from scipy.sparse.linalg import eigsh

    w = eigsh(sp.csc_matrix(H), k=index + 1, which="SA", return_eigenvectors=False)
    return float(np.sort(w)[index])


def eigenvalues_near_zero(H: Any, k: int = 2, vectors: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """The ``k`` eigenvalues of the symmetric ``H`` nearest zero, nearest first (with their vectors).

    Dense for matrices up to 2000 rows; shift-invert Lanczos about zero beyond.
    """
    n = H.shape[0]
    k = min(k, n)
    if n <= 2000 or k >= n - 1:
        A = H.toarray() if sp.issparse(H) else np.asarray(H, dtype=float)
        w, V = np.linalg.eigh(0.5 * (A + A.T))
    else:
        from scipy.sparse.linalg import eigsh

        w, V = eigsh(sp.csc_matrix(H), k=k, sigma=0.0, which="LM")
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

    @property
    def label(self) -> str:
        return self.name

    def value(self, pt: Point) -> tuple[int, ...]:  # type: ignore[override]
        if pt.modes is None:
            pt.modes = {}
        if self.family.name not in pt.modes:
            pt.modes[self.family.name] = family_counts(self.family, pt.u, pt.p)
        return pt.modes[self.family.name]

    def detect(self, before: tuple[int, ...], after: tuple[int, ...]) -> bool:  # type: ignore[override]
        return before != after

    def annotate(self, spt: SpecialPoint) -> SpecialPoint:
        spt.info = {**self._info, **spt.info}
        return spt

    def _eigenvalue(self, key: Any, index: int, u: np.ndarray, p: float) -> float:
        return ordered_eigenvalue(self.family.operator(key, u, p), index)

    def _root(self, seg: Segment, key: Any, index: int, before: int, after: int, g_A: float, g_B: float) -> float:
        """Where eigenvalue ``index`` of the key's operator crosses zero on the segment.

        When it is the only one crossing (``|after - before| == 1``) the root is that of the bordered
        function ``g = 1 / (b^T K^-1 b)`` (``b`` the crossing eigenvector at the end of the segment
        nearer zero), which vanishes exactly where ``K`` is singular, is smooth through it, and
        costs one factorization per evaluation; the eigenvalue itself is the fallback.
        """
        fam, tol = self.family, self.curve.settings.locate_tol
        if abs(after - before) == 1:
            end = seg.A if abs(g_A) < abs(g_B) else seg.B
            _, V = ordered_eigenpairs(fam.operator(key, end.u, end.p), index, index, vectors=True)
            border = V[:, 0]

            def g(sigma: float) -> float:
                u, p, _ = seg.point(sigma)
                K = fam.operator(key, u, p)
                y = factorize(sp.csc_matrix(K) if sp.issparse(K) else np.asarray(K, dtype=float)).solve(border)
                return 1.0 / float(border @ y)

            try:
                f_A, f_B = g(0.0), g(seg.sigma_B)
                if f_A * f_B < 0.0:
                    return seg.root(g, f_A, f_B, tol)
            except (SingularMatrixError, np.linalg.LinAlgError, ZeroDivisionError):
                pass  # an end on the singularity itself: the eigenvalue's root below

        def eig(sigma: float) -> float:
            u, p, _ = seg.point(sigma)
            return self._eigenvalue(key, index, u, p)
        return seg.root(eig, g_A, g_B, tol)

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
            # the eigenvalues number min(a, b) .. max(a, b) - 1 (ascending) cross zero on the step: the
            # first crossing along the curve is where the key bifurcates
            for index in range(min(a, b), max(a, b)):
                g_A = self._eigenvalue(key, index, seg.A.u, seg.A.p)
                g_B = self._eigenvalue(key, index, seg.B.u, seg.B.p)
                if g_A * g_B > 0.0:  # crossed twice on the step: no sign change to bracket
                    failures[f"{key}[{index}]"] = f"eigenvalue {index} has the same sign at both ends ({g_A:.3g}, {g_B:.3g})"
                    continue
                located.append((self._root(seg, key, index, a, b, g_A, g_B), key, index))
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
        # the crossing eigenvalue (number ``index``) and its neighbours: the nearest zero is the located
        # one, the next nearest says how sharply it is located
        lo = max(0, index - 1)
        w, V = ordered_eigenpairs(fam.operator(key, u, p), lo, index + 1, vectors=fam.vectors)
        order = np.argsort(np.abs(w))
        w = w[order]
        V = None if V is None else V[:, order]
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
