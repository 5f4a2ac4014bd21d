"""Changes of the Morse index that no test function explains: multiple points, missed points, jumps.

The test functions watch signs: the parameter component of the tangent (folds) and the determinant
of the bordered Jacobian (simple branch points).  A symmetric problem's Hessian can lose two or more
positive eigenvalues at one parameter value (a double branch point of a symmetric structure, or
identical cells that fold together); no sign changes then, and the step passes it in silence.  The
Morse index of the primary stability label (the operator of the continuation problem itself, by the
convention of :meth:`contin.Problem.stability_operators`) counts them all.

After every accepted step of a branch traced with stability, :func:`explain_index_change` compares
the change of that index with the folds and branch points found on the step.  Where they do not
account for it, the index is bisected along the segment to the narrow brackets where it jumps, and
each jump not already found is located as the root of the trace of the Hessian on the eigenvectors
that cross zero there (``trace(V^T J V)``: all of them cross together at a multiple point).  At the
located point the Hessian must have that many eigenvalues near zero, well apart from the next: then
it is a point of that multiplicity, reported with its kernel's basis.  Without such a kernel the
index jumped with no singular state between: the step moved to another branch, and the caller
rejects it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..path.curve import CorrectorFailure, Curve, max_abs
from ..path.segment import Segment
from ..problem import NonFiniteError, Problem
from ..results.branch import Bifurcation, SpecialPoint
from .branching import reduced_directions, symmetric_directions
from .testfunctions import FOLD_COSINE, nudged, root_near_singular, smallest_eigenvectors

__all__ = ["IndexExplanation", "IndexWatch", "explain_index_change", "primary_index", "kernel_at"]

#: Bracket width (relative to the step) to which the index is bisected before the root is located.
BISECT_WIDTH = 1e-4
#: Brackets of index changes the same way closer than this (relative to the step) are one point.
MERGE_WIDTH = 1e-2
#: Largest ratio of the kernel's eigenvalues to the next one for the kernel to be taken as exact.
KERNEL_GAP = 1e-3
#: Largest residual, in corrector tolerances, of a point taken on the secant of its bracket (where no
#: point next to it converges) for its kernel to count: the chord of a short bracket on one branch
#: stays that close to the curve; a chord between two branches does not.
SECANT_RESIDUAL = 1e3
#: Failures of a corrected point on the segment that leave a jump unlocated.
_FAILURES = (CorrectorFailure, NonFiniteError, ValueError, RuntimeError, np.linalg.LinAlgError)


def primary_index(problem: Problem, u: np.ndarray, p: float) -> int | None:
    """Morse index of the problem's primary stability operator at ``(u, p)`` (None without one)."""
    infos = problem.stability(u, p)
    return None if not infos else int(next(iter(infos.values())).n_negative)


@dataclass
class IndexExplanation:
    """What :func:`explain_index_change` made of a step.

    Attributes
    ----------
    points : list of SpecialPoint
        Points the test functions missed: multiple points (``info["multiplicity"]`` > 1, with the
        kernel's basis) and simple folds or branch points.
    branch_jump : str
        Non-empty when the index jumped where the Hessian has no kernel: the step left the branch.
    doubts : list of str
        Jumps that could not be located (the branch's result is then in doubt).
    replaced : list of SpecialPoint
        Found points that are one of the multiple points (the determinant's sign changes at a point of
        odd multiplicity, so the simple branch-point test sees it too): left out in its favour.
    """

    points: list[SpecialPoint] = field(default_factory=list)
    replaced: list[SpecialPoint] = field(default_factory=list)
    branch_jump: str = ""
    doubts: list[str] = field(default_factory=list)


def _accounted(found: Sequence[SpecialPoint]) -> int:
    """The index changes the found points explain: located folds and branch points by their multiplicity,
    and folds that are only bracketed (the tangent's sign change shows them); a branch point that could
    not be located explains nothing (a step onto another branch flips the determinant's sign too)."""
    return sum(s.bifurcation.multiplicity if s.bifurcation is not None else 1
               for s in found if s.kind == "fold" or (s.kind == "branch_point" and s.located))


def _unlocated_branch_points(found: Sequence[SpecialPoint]) -> bool:
    return any(s.kind == "branch_point" and not s.located for s in found)


class IndexWatch:
    """The primary Morse index along a run, reconciled step by step with the points found.

    Within the corrector's noise of a fold, the eigenvalue that crosses zero and the tangent's
    parameter component can change sign on neighbouring steps: the index then changes one step
    before (or after) the fold is found.  A discrepancy of one is therefore held for up to
    :data:`LAG` steps and dropped when a later step's surplus cancels it; one that stays is located
    on its own step.  A discrepancy of two or more (a multiple point, or a jump to another branch) is
    explained on the step at once, so that a jump can still be rejected; so is one on a step whose
    branch point could not be located.
    """

    #: Steps a discrepancy of one waits for its fold or branch point.
    LAG = 2

    def __init__(self) -> None:
        self._pending: list[tuple[Segment, int, int, list[SpecialPoint], int, int]] = []

    def step(self, curve: Curve, seg: Segment, n_A: int, n_B: int, found: Sequence[SpecialPoint],
             index: int) -> IndexExplanation:
        """Reconcile an accepted step (``index``: the stored point its start is) and return what was located."""
        excess = abs(n_B - n_A) - _accounted(found)
        if excess >= 2 or (excess >= 1 and _unlocated_branch_points(found)):
            out = explain_index_change(curve, seg, n_A, n_B, found)
        else:
            out = IndexExplanation()
            if excess % 2:
                if self._pending:
                    self._pending.pop()  # a lag: the point and its index change fell on neighbouring steps
                else:
                    self._pending.append((seg, n_A, n_B, list(found), index, 0))
                    return out
        aged = [(s, a, b, f, i, age + 1) for s, a, b, f, i, age in self._pending]
        self._pending = [item for item in aged if item[-1] <= self.LAG]
        for item in aged:
            if item[-1] > self.LAG:
                _merge(out, self._late(curve, *item[:5]))
        return out

    def finish(self, curve: Curve) -> IndexExplanation:
        """Locate what is still held at the end of the run."""
        out = IndexExplanation()
        for item in self._pending:
            _merge(out, self._late(curve, *item[:5]))
        self._pending = []
        return out

    @staticmethod
    def _late(curve: Curve, seg: Segment, n_A: int, n_B: int, found: list[SpecialPoint],
              index: int) -> IndexExplanation:
        """A discrepancy of one that no neighbouring step made up: located on its own step."""
        late = explain_index_change(curve, seg, n_A, n_B, found)
        for spt in late.points:
            spt.index = index
        if late.branch_jump:  # the step is behind us: it can no longer be rejected
            late.doubts.append(f"between {curve.problem.parameter_name} = {seg.A.p:.10g} and {seg.B.p:.10g} "
                               f"{late.branch_jump}")
            late.branch_jump = ""
        return late


def _merge(out: IndexExplanation, more: IndexExplanation) -> None:
    out.points += more.points
    out.replaced += more.replaced
    out.doubts += more.doubts
    out.branch_jump = out.branch_jump or more.branch_jump


def explain_index_change(curve: Curve, seg: Segment, n_A: int, n_B: int, found: Sequence[SpecialPoint]
                         ) -> IndexExplanation:
    """Account for the change of the primary Morse index from ``n_A`` to ``n_B`` over the segment.

    Parameters
    ----------
    curve : Curve
    seg : Segment
        The accepted step.
    n_A, n_B : int
        The primary index at its ends.
    found : sequence of SpecialPoint
        What the test functions found on it: each fold and simple branch point changes the index by one.
    """
    out = IndexExplanation()
    change, accounted = abs(n_B - n_A), _accounted(found)
    if change <= accounted and (change - accounted) % 2 == 0:
        return out
    problem = curve.problem

    def index_of(sigma: float) -> int:
        u, p, _ = seg.point(sigma)
        n = primary_index(problem, u, p)
        if n is None:
            raise ValueError("no stability operator")
        return n

    try:
        jumps = _index_jumps(index_of, seg.sigma_B, n_A, n_B, BISECT_WIDTH * abs(seg.sigma_B))
    except _FAILURES as exc:
        out.doubts.append(f"the index changed from {n_A} to {n_B} between {problem.parameter_name} = "
                          f"{seg.A.p:.10g} and {seg.B.p:.10g} and could not be followed along the step: {exc}")
        return out
    jumps = _merged(jumps, MERGE_WIDTH * abs(seg.sigma_B))
    known = [s for s in found if s.kind == "fold" or (s.kind == "branch_point" and s.located)]
    for lo, hi, m_lo, m_hi in jumps:
        m = abs(m_hi - m_lo)
        try:
            if m == 1 and _claim(known, seg, lo, hi):
                continue
            spt, kernel = _locate_jump(curve, seg, lo, hi, m)
        except _FAILURES as exc:
            out.doubts.append(f"the index changed from {m_lo} to {m_hi} near {problem.parameter_name} = "
                              f"{seg.point(lo)[1]:.10g} and the point could not be located: {exc}")
            continue
        if kernel is None:
            out.branch_jump = (f"the Morse index changed from {m_lo} to {m_hi} where the Hessian has no "
                               f"{m}-dimensional kernel (a jump to another branch)")
            return out
        out.points.append(spt)
        if m > 1:
            p_lo, p_hi = sorted(spt.info["bracket_p"])
            slack = 1e-9 * (1.0 + abs(spt.p))
            same = [s for s in found if s.kind == "branch_point" and not any(s is r for r in out.replaced)
                    and (not s.located or p_lo - slack <= s.p <= p_hi + slack)]
            out.replaced += same
            known[:] = [s for s in known if not any(s is r for r in same)]
    return out


def _claim(known: list[SpecialPoint], seg: Segment, lo: float, hi: float) -> bool:
    """Whether a simple jump in ``[lo, hi]`` is one of the found points (which is then used up)."""
    A = seg.A
    p_lo, p_hi = seg.point(lo)[1], seg.point(hi)[1]
    for s in known:
        sigma = seg.curve.inner(A.t_u, A.t_p, s.u - A.u, s.p - A.p)
        near = min(p_lo, p_hi) - 1e-9 * (1 + abs(s.p)) <= s.p <= max(p_lo, p_hi) + 1e-9 * (1 + abs(s.p))
        if (lo - BISECT_WIDTH * abs(seg.sigma_B) <= sigma <= hi + BISECT_WIDTH * abs(seg.sigma_B)) or near:
            known.remove(s)
            return True
    # a simple point found by a test function but bracketed elsewhere on the step still accounts for one
    if known:
        known.pop(0)
        return True
    return False


def _index_jumps(index_of: Callable[[float], int], sigma_B: float, n_A: int, n_B: int,
                 width: float) -> list[tuple[float, float, int, int]]:
    """Brackets ``(lo, hi, n_lo, n_hi)`` no wider than ``width`` where the index changes, in path order.

    Bisection of every interval whose ends differ; a pair of opposite changes inside one interval of
    the first subdivisions cancels and is not seen (the test functions see those).
    """
    out = []
    stack = [(0.0, float(sigma_B), n_A, n_B)]
    while stack:
        lo, hi, n_lo, n_hi = stack.pop()
        if n_lo == n_hi:
            continue
        if abs(hi - lo) <= width:
            out.append((lo, hi, n_lo, n_hi))
            continue
        mid, n_mid = _index_near(index_of, lo, hi)
        if n_mid is None:
            # no point converges inside (the corrector's system is singular next to the point itself):
            # the bracket is as narrow as the curve allows; the location takes it from here
            out.append((lo, hi, n_lo, n_hi))
            continue
        stack.append((mid, hi, n_mid, n_hi))
        stack.append((lo, mid, n_lo, n_mid))
    return sorted(out, key=lambda j: abs(j[0]))


def _resolve(problem: Problem, u: np.ndarray, p: float, V: np.ndarray, record: Bifurcation,
             info: dict[str, Any]) -> None:
    """The directions of the branches through a multiple point, into its record (one per orbit of copies).

    By the declared symmetry (:func:`contin.watch.branching.symmetric_directions`), else by the
    reduced equation (:func:`contin.watch.branching.reduced_directions`); what could not be resolved
    is ``info["unresolved"]``.  A half-line whose opposite is not a copy of it under the symmetry is
    a branch of its own and gets its own entry.
    """
    found = symmetric_directions(problem, u, V)
    if found is None:
        found = reduced_directions(problem, u, p, V)
    if found.note:
        info["unresolved"] = found.note
    if not found.directions:
        return
    rows, labels = [], []
    for c, label, copies in zip(found.directions, found.labels, found.copies):
        d = np.concatenate([V @ c, [0.0]])
        rows.append(d)
        labels.append(f"{label}; {copies} copies")
    record.directions = np.array(rows)
    record.labels = labels
    record.kind = "symmetric" if found.method == "symmetry" else "reduced"


def _merged(jumps: list[tuple[float, float, int, int]], width: float) -> list[tuple[float, float, int, int]]:
    """Neighbouring brackets whose index changes the same way, closer than ``width``: one jump of their sum.

    Eigenvalues that cross zero together (a double point) are told apart by the bisection down to
    the roundoff of the corrected points; the crossing is one point of the step's resolution.
    """
    out: list[tuple[float, float, int, int]] = []
    for lo, hi, n_lo, n_hi in jumps:
        if out:
            lo0, hi0, n_lo0, n_hi0 = out[-1]
            same_way = (n_hi0 - n_lo0) * (n_hi - n_lo) > 0 and n_hi0 == n_lo
            if same_way and abs(lo - hi0) <= width:
                out[-1] = (lo0, hi, n_lo0, n_hi)
                continue
        out.append((lo, hi, n_lo, n_hi))
    return out


def _index_near(index_of: Callable[[float], int], lo: float, hi: float) -> tuple[float, int | None]:
    """The index at the middle of ``[lo, hi]``, or at a point nudged from it when the middle does not converge."""
    try:
        return nudged(index_of, 0.5 * (lo + hi), 0.5 * (hi - lo))
    except CorrectorFailure:
        return 0.5 * (lo + hi), None


def kernel_at(problem: Problem, u: np.ndarray, p: float, m: int) -> tuple[np.ndarray, np.ndarray, float]:
    """The ``m + 1`` eigenpairs of the Hessian nearest zero at ``(u, p)``: ``(values, vectors, gap)``.

    ``gap`` is the largest of the first ``m`` |eigenvalues| over the next one: small at a point with an
    ``m``-dimensional kernel.
    """
    J = problem.checked_jacobian(u, p)
    vectors = np.column_stack(smallest_eigenvectors(problem, u, p, m + 1))
    values = np.einsum("ij,ij->j", vectors, J @ vectors)
    order = np.argsort(np.abs(values))
    values, vectors = values[order], vectors[:, order]
    nxt = abs(values[m]) if values.size > m else math.inf
    gap = float(np.max(np.abs(values[:m]))) / max(nxt, 1e-300)
    return values, vectors, gap


def _locate_jump(curve: Curve, seg: Segment, lo: float, hi: float, m: int
                 ) -> tuple[SpecialPoint, np.ndarray | None]:
    """The point in ``[lo, hi]`` where ``m`` eigenvalues cross zero, and its kernel (None if it has none)."""
    problem = curve.problem
    # the crossing eigenvectors at an end of the bracket (its ends converged when the index was taken)
    um, pm, _ = seg.point(lo)
    _, V, _ = kernel_at(problem, um, pm, m)
    V = V[:, :m]

    def trace(u: np.ndarray, p: float) -> float:
        return float(np.trace(V.T @ (problem.checked_jacobian(u, p) @ V)))

    u_lo, p_lo, _ = seg.point(lo)
    u_hi, p_hi, _ = seg.point(hi)
    t_lo, t_hi = trace(u_lo, p_lo), trace(u_hi, p_hi)
    try:
        # a step that ends next to the point is short, and its inside is all within the singular zone:
        # the nodes may spread to a few steps' length around it
        u, p = root_near_singular(seg, trace, lo, hi, t_lo, BISECT_WIDTH * abs(seg.sigma_B), attempts=16)
    except CorrectorFailure:
        # no converged point near it: the secant between the bracket's converged ends (its error is
        # the curve's deviation from a chord of the bracket; the residual below says how good it is)
        t = t_lo / (t_lo - t_hi) if t_lo != t_hi else 0.5
        u, p = u_lo + t * (u_hi - u_lo), p_lo + t * (p_hi - p_lo)
    values, vectors, gap = kernel_at(problem, u, p, m)
    info: dict[str, Any] = {"bracket_p": [seg.point(lo)[1], seg.point(hi)[1]],
                            "next_eigenvalue": float(values[m]) if values.size > m else math.nan,
                            "method": "bisection of the Morse index, then the root of the trace of the Hessian "
                                      "on the crossing eigenvectors"}
    kind = "branch_point"
    if m == 1:
        f_p = problem.dresidual_dp(u, p)
        cosine = abs(float(vectors[:, 0] @ f_p)) / max(float(np.linalg.norm(f_p)), 1e-300)
        kind = "fold" if cosine > FOLD_COSINE else "branch_point"
    record = None
    if kind == "branch_point":
        secant = np.concatenate([seg.B.u - seg.A.u, [seg.B.p - seg.A.p]])
        record = Bifurcation(multiplicity=m, kernel=vectors[:, :m].T, directions=np.zeros((0, u.size + 1)),
                             traced=secant / max(float(np.linalg.norm(secant)), 1e-300),
                             kind="multiple" if m > 1 else "unresolved", eigenvalues=values[:m])
        if m > 1 and gap <= KERNEL_GAP:
            _resolve(problem, u, p, vectors[:, :m], record, info)
    res = max_abs(curve.residual(u, p))
    spt = SpecialPoint(kind, float(p), np.array(u, dtype=float), problem.evaluate_observables(u, p),
                       residual=res, located=bool(res <= curve.tol), info=info, bifurcation=record)
    spt.s = seg.A.s + curve.norm(spt.u - seg.A.u, spt.p - seg.A.p)
    # a kernel is only a kernel on the curve: a bracket whose ends lie on two branches gives a point
    # between them, off every branch, whatever its eigenvalues
    on_curve = res <= SECANT_RESIDUAL * curve.tol
    return spt, (vectors[:, :m] if gap <= KERNEL_GAP and on_curve else None)

