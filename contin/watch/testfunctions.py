"""Test functions: everything a branch watches, behind one protocol (COCO's monitor functions).

A :class:`TestFunction` has

* ``value(point)``: its value at an accepted point;
* ``detect(before, after)``: whether it changed sign (in the wanted direction) over a step;
* ``locate(segment, before, after)``: the special point on the curve between the two points.

Four kinds implement it:

* :class:`FoldTest`: the parameter component of the unit tangent; a sign change is a fold, located
  by Newton on the minimally augmented system (:func:`contin.watch.fold.locate_fold`), with the root of the
  tangent component on the segment as the fallback;
* :class:`BranchPointTest`: the sign of the determinant of the bordered Jacobian (from the
  factorization, so nothing overflows); located as a root of a continuous bordered test function.
  For a symmetric problem that function borders the Hessian alone by its own near-null eigenvector,
  so the located point does not depend on the arclength weights, and the branch directions come from
  the algebraic bifurcation equation (:func:`bifurcation_directions`), stored without any weight;
  :class:`KnownBranchPoints` makes a run end where it meets a branch point it was told of;
* :class:`EventTest`: a user event (:mod:`contin.watch.events`): an observable minus a value, or the
  derivative of an observable along the unit tangent (extremum);
* bounds of the parameter and of observables are :class:`EventTest` s of terminal crossings
  (``bound=True``): the run ends exactly on them and they are not recorded as special points.

:meth:`TestFunction.find` wraps ``locate``: it returns the located point, or the bracket (an
unlocated special point with the reason) when location is off or fails.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..numerics.linalg import BorderedSolver, SingularMatrixError
from ..numerics.stability import lanczos_start
from ..path.curve import CorrectorFailure, Curve, Point, max_abs
from ..path.segment import Segment
from ..problem import NonFiniteError, Problem
from ..results.branch import Bifurcation, SpecialPoint
from ..settings import Settings
from .events import Event
from .fold import fold_function, inverse_iteration, locate_fold, safe_factorize

__all__ = ["TestFunction", "FoldTest", "BranchPointTest", "EventTest", "event_value", "observable_function",
           "bracketed", "KnownBranchPoints", "bound_events", "smallest_eigenvector", "second_derivative",
           "bifurcation_directions", "nudged", "root_near_singular"]

#: failures of a location that leave the special point bracketed instead of ending the run
LOCATE_FAILURES = (CorrectorFailure, ValueError, RuntimeError, SingularMatrixError)


def bracketed(kind: str, A: Point, B: Point, label: str = "") -> SpecialPoint:
    """An unlocated special point: the bracket ``[A, B]``, reported at ``B``."""
    return SpecialPoint(kind, B.p, B.u.copy(), {}, residual=B.residual, located=False, s=B.s, label=label,
                        info={"bracket_p": [A.p, B.p]})


class TestFunction:
    """The protocol (and the shared part) of everything a branch watches.

    Attributes
    ----------
    kind : str
        Kind of the special points it produces (``"fold"``, ``"branch_point"``, ``"event"``).
    name : str
        Their label.
    terminal : bool
        Every detection ends the run (a terminal event or a bound).
    bound : bool
        A bound: the run ends on it with status ``"bound"`` and it is not recorded.
    stop_on_located : bool
        A located detection ends the run (``Settings.stop_at`` names the kind).

    Parameters
    ----------
    curve : Curve
        The curve the branch is traced on (its settings say which kinds stop the run).
    """

    kind = "event"
    name = ""
    terminal = False
    bound = False

    def __init__(self, curve: Curve) -> None:
        self.curve = curve
        self.stop_on_located = self.kind in curve.settings.stop_at

    def value(self, pt: Point) -> float:
        """The test function at an accepted point."""
        raise NotImplementedError

    def detect(self, before: float, after: float) -> bool:
        """Whether the values at two consecutive points bracket a special point (default: a sign change)."""
        return before * after < 0

    def locate(self, seg: Segment, before: float, after: float) -> SpecialPoint:
        """The special point on ``seg`` (raises one of :data:`LOCATE_FAILURES` when it cannot)."""
        raise NotImplementedError

    def find(self, seg: Segment, before: float, after: float, locate: bool = True) -> SpecialPoint:
        """:meth:`locate`, or the bracket when ``locate`` is False or the location fails.

        A bracket is reported at its end ``seg.B``, with the observables there: whoever reads a special
        point's observables finds them whether or not it was located.
        """
        error = None
        if locate:
            try:
                return self.annotate(self.locate(seg, before, after))
            except LOCATE_FAILURES as exc:
                error = str(exc)
        spt = bracketed(self.kind, seg.A, seg.B, self.label)
        spt.observables = self.curve.problem.evaluate_observables(spt.u, spt.p)
        if error is not None:
            spt.info["error"] = error
        return self.annotate(spt)

    @property
    def label(self) -> str:
        """Label given to bracketed special points."""
        return ""

    def annotate(self, spt: SpecialPoint) -> SpecialPoint:
        """Add what the test function knows about its special points (default: nothing)."""
        return spt

    def stop_rank(self, spt: SpecialPoint) -> int | None:
        """None when ``spt`` does not end the run; else its rank among stops at the same place.

        Terminal events (0) win a tie with kinds listed in ``stop_at`` (1).
        """
        if self.terminal:
            return 0
        if self.stop_on_located and spt.located:
            return 1
        return None


class FoldTest(TestFunction):
    """Folds in the continuation parameter: sign changes of the tangent's parameter component."""

    kind = name = "fold"

    def value(self, pt: Point) -> float:
        return pt.t_p

    def annotate(self, spt: SpecialPoint) -> SpecialPoint:
        spt.info["folds"] = self.curve.problem.parameter_name
        return spt

    def locate(self, seg: Segment, before: float, after: float) -> SpecialPoint:
        curve, A, B = self.curve, seg.A, seg.B
        u0, p0, t_u0 = _fold_start(seg)
        try:
            fold = locate_fold(curve.problem, u0, p0, v0=t_u0, tol=curve.settings.tol)
        except (NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
            fold = SpecialPoint("fold", p0, u0, {}, located=False, info={"error": str(exc)})
        # the extended-system root must lie on this segment; otherwise fall back to a root of t_p
        if fold.located:
            d_total = curve.norm(B.u - A.u, B.p - A.p)
            d_fold = min(curve.norm(fold.u - A.u, fold.p - A.p), curve.norm(fold.u - B.u, fold.p - B.p))
            if d_fold > 2 * d_total:
                fold.located = False
                fold.info["error"] = "extended-system Newton converged away from the bracketing segment"
        if not fold.located:
            fold = _fold_by_tangent_root(seg, fold)
        fold.observables = curve.problem.evaluate_observables(fold.u, fold.p)
        fold.s = A.s + curve.norm(fold.u - A.u, fold.p - A.p)
        fold.info["bracket_p"] = [A.p, B.p]
        return fold


def _fold_start(seg: Segment) -> tuple[np.ndarray, float, np.ndarray]:
    """Start of the fold Newton: the secant zero of ``t_p`` corrected onto the curve, with its tangent."""
    A, B = seg.A, seg.B
    frac = A.t_p / (A.t_p - B.t_p) if A.t_p != B.t_p else 0.5
    sigma0 = float(np.clip(frac, 0.05, 0.95)) * seg.sigma_B
    try:
        u0, p0, _ = seg.point(sigma0)
        t_u0, _ = seg.tangent(u0, p0)
    except CorrectorFailure:
        u0, p0, t_u0 = (A.u, A.p, A.t_u) if abs(A.t_p) < abs(B.t_p) else (B.u, B.p, B.t_u)
    return u0, p0, t_u0


def _fold_by_tangent_root(seg: Segment, failed: SpecialPoint) -> SpecialPoint:
    """The fold as the root of the tangent's parameter component on the segment (``failed`` if none)."""
    def tp(sigma: float) -> float:
        u, p, _ = seg.point(sigma)
        return seg.tangent(u, p)[1]
    try:
        sigma = seg.root(tp, seg.A.t_p, seg.B.t_p, seg.curve.settings.locate_tol)
        u, p, res = seg.point(sigma)
        return SpecialPoint("fold", p, u.copy(), {}, residual=res, located=True,
                            info={"method": "root of the tangent's parameter component"})
    except (CorrectorFailure, ValueError, RuntimeError) as exc:
        failed.info["error2"] = str(exc)
        return failed


class BranchPointTest(TestFunction):
    """Simple branch points: sign changes of the determinant of the bordered Jacobian.

    Detection uses the augmented Jacobian's determinant sign (free from the tangent's
    factorization).  Location depends on the problem:

    * symmetric (``problem.symmetric``): a root on the curve of the Hessian's own bordered test
      function (:class:`_HessianBranchTest`); nothing in it depends on the arclength weights, and
      the bifurcating direction comes from the algebraic bifurcation equation
      (:func:`bifurcation_directions`);
    * otherwise: a root of the doubly bordered augmented Jacobian (:class:`_BorderedBranchTest`).

    Parameters
    ----------
    curve : Curve
    known : KnownBranchPoints, optional
        Branch points that end the run when one is located again (see :func:`contin.switch_branch`).
    """

    kind = name = "branch_point"

    def __init__(self, curve: Curve, known: KnownBranchPoints | None = None) -> None:
        super().__init__(curve)
        self.known = known

    def value(self, pt: Point) -> float:
        return pt.det_sign

    def locate(self, seg: Segment, before: float, after: float) -> SpecialPoint:
        curve, A = self.curve, seg.A
        info: dict[str, Any] = {"bracket_p": [A.p, seg.B.p]}
        if curve.problem.symmetric:
            hess = _HessianBranchTest(seg)
            if hess.ends[0] * hess.ends[1] > 0:
                bp = self._unbracketed(seg, hess.sigma_mid, info)
            else:
                u, p = hess.root()
                res = max_abs(curve.residual(u, p))
                info["test_function"] = fold_function(curve.problem, u, p, hess.b, hess.b)[0]
                info["method"] = "root of the Hessian's bordered test function"
                bp = SpecialPoint("branch_point", p, u, {}, residual=res, located=True, info=info)
                bp.bifurcation = hess.directions(u, p)
                _reject_a_fold(curve.problem, bp, seg)
        else:
            psi = _BorderedBranchTest(seg)
            psi_A, psi_B = psi(0.0), psi(seg.sigma_B)
            if psi_A * psi_B > 0:
                bp = self._unbracketed(seg, psi.sigma_mid, info)
            else:
                sigma = seg.root(psi, psi_A, psi_B, curve.settings.locate_tol)
                u, p, res = seg.point(sigma)
                info["test_function"] = val = psi(sigma)
                bp = SpecialPoint("branch_point", p, u.copy(), {}, residual=max(res, abs(val)), located=True,
                                  info=info)
                bp.bifurcation = psi.directions(u, p)
        bp.observables = curve.problem.evaluate_observables(bp.u, bp.p)
        bp.s = A.s + curve.norm(bp.u - A.u, bp.p - A.p)
        return bp

    @staticmethod
    def _unbracketed(seg: Segment, sigma: float, info: dict[str, Any]) -> SpecialPoint:
        """The bordered test function does not bracket: the bracket, reported unlocated."""
        u, p, res = seg.point(sigma)
        info["error"] = "bordered test function did not change sign on the bracket"
        return SpecialPoint("branch_point", p, u.copy(), {}, residual=res, located=False, info=info)

    def find(self, seg: Segment, before: float, after: float, locate: bool = True) -> SpecialPoint:
        spt = super().find(seg, before, after, locate)
        if self.known is not None:
            match = self.known.match(spt, seg)
            if match is not None:
                # the run ends on the known point itself, not on this run's estimate of it
                label, u, p = match
                spt.info["known_as"] = label
                spt.info["met_at_p"] = float(spt.p)
                spt.u, spt.p = np.array(u, dtype=float), float(p)
                spt.residual = max_abs(self.curve.residual(spt.u, spt.p))
                spt.observables = self.curve.problem.evaluate_observables(spt.u, spt.p)
        return spt

    def stop_rank(self, spt: SpecialPoint) -> int | None:
        if "known_as" in spt.info:
            return 1
        return super().stop_rank(spt)


@dataclass(frozen=True)
class KnownBranchPoints:
    """Branch points a run ends on when it meets one of them again.

    :func:`contin.switch_branch` passes one among the events of its continuation run (so the driver
    needs no extra argument): the branch point it starts from, and those the caller already knows.

    Attributes
    ----------
    points : tuple of (label, u, p)
        The known points; ``label`` names the point in the branch's status message.
    rtol : float
        Relative distance (max-norm in ``u``, absolute in ``p``, both relative to the point's size)
        below which a located branch point is the same point.
    """

    points: tuple[tuple[str, np.ndarray, float], ...]
    rtol: float = 1e-6

    def match(self, spt: SpecialPoint, seg: Segment) -> tuple[str, np.ndarray, float] | None:
        """The known point ``(label, u, p)`` that ``spt`` (found on ``seg``) is, or None.

        Either the located point coincides with it (``rtol``), or it lies on the bracket: within a
        tenth of the segment's length of the chord from ``A`` to ``B``.  The second test matters on
        the branch that crosses a pitchfork: there the Hessian's eigenvalue only touches zero (the
        crossing is a fold in the parameter too), so the point is bracketed but not located.
        """
        curve, A, B = seg.curve, seg.A, seg.B
        chord_u, chord_p = B.u - A.u, B.p - A.p
        length2 = curve.inner(chord_u, chord_p, chord_u, chord_p)
        for label, u, p in self.points:
            u_scale = 1.0 + float(np.max(np.abs(u), initial=0.0))
            if spt.located and (abs(spt.p - p) <= self.rtol * (1.0 + abs(p))
                                and float(np.max(np.abs(spt.u - u), initial=0.0)) <= self.rtol * u_scale):
                return label, u, p
            t = float(np.clip(curve.inner(u - A.u, p - A.p, chord_u, chord_p) / length2, 0.0, 1.0)) \
                if length2 > 0 else 0.0
            if curve.norm(u - A.u - t * chord_u, p - A.p - t * chord_p) <= 0.1 * math.sqrt(length2):
                return label, u, p
        return None


#: At a branch point ``df/dp`` lies in the range of ``J``, i.e. is orthogonal to its null vector; a
#: root of the Hessian's test function where the cosine of their angle exceeds this is a fold.
FOLD_COSINE = 1e-6


def _reject_a_fold(problem: Any, bp: SpecialPoint, seg: Segment) -> None:
    """Mark ``bp`` unlocated when its null vector is not orthogonal to ``df/dp`` (it is a fold).

    The detection (the determinant sign of the bordered Jacobian) does not change at a fold, but a
    step that ends on the fold itself, where that sign is decided by roundoff, can trigger it, and
    the Hessian's eigenvalue does cross zero there.

    ``phi^T df/dp`` is compared with the size ``df/dp`` has on the step (the larger of its norms at
    the step's ends and at the point), not with its size at the point alone: at a fold ``df/dp`` is
    what it is on either side, while where ``df/dp`` itself vanishes (two identical springs in series
    under a prescribed elongation, at the peak of their force) it is roundoff at the point, its
    direction says nothing, and the point is a branch point.
    """
    if bp.bifurcation is None:
        return
    phi = bp.bifurcation.null_vector
    fp = np.asarray(problem.dresidual_dp(bp.u, bp.p), dtype=float)
    size = max(float(np.linalg.norm(fp)), *(float(np.linalg.norm(problem.dresidual_dp(pt.u, pt.p)))
                                            for pt in (seg.A, seg.B)))
    norm = size * float(np.linalg.norm(phi))
    cosine = abs(float(np.dot(fp, phi))) / norm if norm > 0 else 0.0
    bp.info["null_vector_cosine_to_dfdp"] = cosine
    if cosine > FOLD_COSINE:
        bp.located = False
        bp.info["error"] = (f"the test function's root is a fold, not a branch point: df/dp is not orthogonal "
                            f"to the null vector (cosine {cosine:.1e} > {FOLD_COSINE:g})")


class _HessianBranchTest:
    """Weight-free branch-point test function of a symmetric problem on a segment.

    ``J`` (the Hessian) is bordered by one of its eigenvectors ``b`` of small |eigenvalue| at the
    segment's midpoint: the fold function ``g`` of ``[[J, b], [b^T, 0]] [v; g] = [0; 1]``
    (:func:`contin.watch.fold.fold_function`) is ``-1 / (b^T J^{-1} b)``, which changes sign exactly where
    that eigenvalue crosses zero.  Only ``J`` and ``df/dp`` enter, never the arclength weights.

    Of the eigenvectors whose test function changes sign on the segment, ``b`` is the one most
    nearly orthogonal to ``df/dp``: at a branch point ``df/dp`` lies in the range of ``J``, at a
    fold it does not, and a fold can share the segment (it does on a shallow arch).

    The candidates are the eigenvectors of smallest |eigenvalue| at the midpoint, then, if none of
    them changes sign, at the segment's ends: on a long segment the crossing eigenvalue may have
    moved far from zero by the midpoint, behind others that stay near it (on a trivial branch
    ``K - p a a^T`` it is at -1.26 there, behind three near +1), while at the end nearer the
    crossing it is the smallest.
    """

    def __init__(self, seg: Segment, candidates: int = 3) -> None:
        self.seg, self.curve = seg, seg.curve
        problem = self.curve.problem
        self.sigma_mid = 0.5 * seg.sigma_B
        best = None
        for sigma in (self.sigma_mid, 0.0, seg.sigma_B):
            u, p, _ = seg.point(sigma)
            fp = problem.dresidual_dp(u, p)
            fp = fp / max(float(np.linalg.norm(fp)), 1e-300)
            for b in smallest_eigenvectors(problem, u, p, candidates):
                ends = [self._g(b, 0.0), self._g(b, seg.sigma_B)]
                score = abs(float(b @ fp))
                if ends[0] * ends[1] <= 0 and (best is None or score < best[0]):
                    best = (score, b, ends)
            if best is not None:
                break
        if best is None:
            um, pm, _ = seg.point(self.sigma_mid)
            b = smallest_eigenvectors(problem, um, pm, 1)[0]
            best = (0.0, b, [self._g(b, 0.0), self._g(b, seg.sigma_B)])
        self.b, self.ends = best[1], best[2]

    def _g(self, b: np.ndarray, sigma: float) -> float:
        u, p, _ = self.seg.point(sigma)
        return fold_function(self.curve.problem, u, p, b, b)[0]

    def root(self, width: float = 1e-4, attempts: int = 6) -> tuple[np.ndarray, float]:
        """The branch point ``(u, p)``: where the test function vanishes on the curve (:func:`root_near_singular`)."""
        seg = self.seg
        return root_near_singular(seg, lambda u, p: fold_function(self.curve.problem, u, p, self.b, self.b)[0],
                                  0.0, seg.sigma_B, self.ends[0], width * abs(seg.sigma_B), attempts,
                                  g_hi=self.ends[1])

    def directions(self, u: np.ndarray, p: float) -> Bifurcation:
        """Null vector, the branch's tangents and the bifurcation equation at the located point."""
        A, B = self.seg.A, self.seg.B
        return bifurcation_directions(self.curve.problem, u, p, B.u - A.u, B.p - A.p, start=self.b)


#: Where :func:`nudged` tries a function, in fractions of its room: the point first, then either side.
NUDGES = (0.0, 0.1, -0.1, 0.3, -0.3)


def nudged(fun: Callable[[float], Any], sigma: float, room: float) -> tuple[float, Any]:
    """``(s, fun(s))`` at ``s = sigma``, or nudged along the segment by up to ``room`` where the corrector
    fails at it (next to a singular point a few points do not converge); raises the last failure."""
    last: CorrectorFailure | None = None
    for shift in NUDGES:
        s = sigma + shift * room
        try:
            return s, fun(s)
        except CorrectorFailure as exc:
            last = exc
    assert last is not None
    raise last


def root_near_singular(seg: Segment, g_at: Callable[[np.ndarray, float], float], lo: float, hi: float, g_lo: float,
                       width: float, attempts: int = 6, g_hi: float | None = None) -> tuple[np.ndarray, float]:
    """The point ``(u, p)`` of ``seg`` in ``[lo, hi]`` where ``g_at`` changes sign, next to a singular point.

    At a branch point the corrector's bordered system is itself singular (two branches cross the
    hyperplane there), so points closer to it than roundoff allows do not converge.  Hence the
    bracket is narrowed down to ``width`` (a point that fails is nudged along the segment), then the
    root of the cubic through ``g`` at four points ``w / 2`` to ``2 w`` from the bracket's centre, and
    the state by the same cubic (Lagrange) interpolation of those four converged points: its error is
    ``O(w^4)``, far below the corrector's tolerance.  ``w`` doubles when a point fails to converge.

    The bracket narrows by bisection, or, given ``g_hi`` (the value at ``hi``) for a ``g`` that is smooth
    on the segment, by false position (:func:`_false_position`): each value costs a corrected point, and
    a smooth ``g`` is bracketed to ``width`` in a few of them where bisection takes ``log2(|hi - lo| / width)``.
    """
    def value(sigma: float) -> float:
        u, p, _ = seg.point(sigma)
        return g_at(u, p)

    if g_hi is not None and g_lo * g_hi < 0:
        lo, hi = _false_position(value, lo, hi, g_lo, g_hi, width)
    while abs(hi - lo) > width:
        mid = 0.5 * (lo + hi)
        g_mid = nudged(value, mid, 0.25 * abs(hi - lo))[1]
        if g_mid * g_lo > 0:
            lo, g_lo = mid, g_mid
        else:
            hi = mid
    centre = 0.5 * (lo + hi)
    w = width
    last: Exception | None = None
    for _ in range(attempts):
        nodes = centre + np.sign(seg.sigma_B) * w * np.array([-2.0, -1.0, 1.0, 2.0])
        try:
            pts = [seg.point(float(s)) for s in nodes]
        except CorrectorFailure as exc:
            last, w = exc, 2 * w
            continue
        g = np.array([g_at(u, p) for u, p, _ in pts])
        x = (nodes - centre) / w
        coef = np.polyfit(x, g, 3)
        t = _cubic_root(coef, x[1], x[2], g[1], g[2])
        weights = _lagrange_weights(x, t)
        u = sum(wi * pt[0] for wi, pt in zip(weights, pts))
        p = float(sum(wi * pt[1] for wi, pt in zip(weights, pts)))
        return np.asarray(u, dtype=float), p
    raise CorrectorFailure(f"no converged points around the singular point: {last}")


#: False-position steps :func:`_false_position` takes before it leaves the rest to bisection.
FALSE_POSITION_STEPS = 12


def _false_position(value: Callable[[float], float], lo: float, hi: float, g_lo: float, g_hi: float,
                    width: float) -> tuple[float, float]:
    """A bracket ``(lo, hi)`` of the sign change of ``value``, narrowed towards ``width`` by false position.

    The Illinois variant: an end that stays twice has its value halved, so that both ends move.  Once an
    estimate is within ``width / 2`` of the last (it has converged to the root), the next point is placed
    ``width / 2`` beyond it towards the far end, which then brackets the root to about ``width``.  A point
    that fails to converge is nudged (:func:`nudged`).  Returns the bracket it reached after at most
    :data:`FALSE_POSITION_STEPS` values (bisection finishes what is left).
    """
    stale = 0  # +1: lo stayed last time, -1: hi stayed
    previous = None
    for _ in range(FALSE_POSITION_STEPS):
        if abs(hi - lo) <= width:
            break
        s = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
        if previous is not None and abs(s - previous) <= 0.5 * width:
            # converged from one side: step past the root so that the far end comes next to it
            s += 0.5 * width * (1.0 if stale == -1 else -1.0) * np.sign(hi - lo)
        margin = 0.25 * width * np.sign(hi - lo)
        s = float(np.clip(s, min(lo + margin, hi - margin), max(lo + margin, hi - margin)))
        previous = s
        s, g = nudged(value, s, 0.25 * abs(hi - lo))
        if g * g_lo > 0:
            lo, g_lo = s, g
            if stale == -1:
                g_hi *= 0.5
            stale = -1
        else:
            hi, g_hi = s, g
            if stale == 1:
                g_lo *= 0.5
            stale = 1
    return lo, hi


def _cubic_root(coef: np.ndarray, x0: float, x1: float, g0: float, g1: float) -> float:
    """Root in ``[x0, x1]`` of the cubic ``coef`` (numpy order) that changes sign there: Newton from the secant root."""
    t = x0 - g0 * (x1 - x0) / (g1 - g0) if g1 != g0 else 0.5 * (x0 + x1)
    d = np.polyder(coef)
    for _ in range(20):
        step = np.polyval(coef, t) / np.polyval(d, t)
        t = float(np.clip(t - step, x0, x1))
        if abs(step) < 1e-15:
            break
    return t


def _lagrange_weights(x: np.ndarray, t: float) -> np.ndarray:
    """Weights of the Lagrange interpolant through the nodes ``x`` at ``t``."""
    return np.array([np.prod([(t - x[k]) / (x[j] - x[k]) for k in range(x.size) if k != j]) for j in range(x.size)])


def smallest_eigenvectors(problem: Problem, u: np.ndarray, p: float, k: int = 1) -> list[np.ndarray]:
    """Unit eigenvectors of the symmetric ``J(u, p)`` for its ``k`` smallest |eigenvalues|, smallest first.

    Dense for small systems; otherwise Lanczos in shift-invert mode about zero on the model's own
    (banded or sparse) factorization.
    """
    J = problem.checked_jacobian(u, p)
    n = u.size
    k = min(k, n)
    if n <= 400:
        w, V = np.linalg.eigh(J.toarray() if hasattr(J, "toarray") else np.asarray(J))
        order = np.argsort(np.abs(w))[:k]
        return [V[:, i] for i in order]
    from scipy.sparse.linalg import LinearOperator, eigsh  # imported here: slow to import

    F = safe_factorize(problem, J)
    if F is None:
        # exactly singular: shift off zero by a roundoff-sized amount
        shift = 1e-12 * _max_abs_entry(J)
        F = problem.factorize(J - shift * sp.identity(n, format="csr"))
    op = LinearOperator((n, n), matvec=lambda x: F.solve(np.ravel(x)), dtype=float)
    w, V = eigsh(J, k=k, sigma=0.0, OPinv=op, which="LM", v0=lanczos_start(n))
    order = np.argsort(np.abs(w))
    return [V[:, i] for i in order]


def smallest_eigenvector(problem: Problem, u: np.ndarray, p: float, start: np.ndarray | None = None,
                         iters: int = 30) -> np.ndarray:
    """Unit eigenvector of the symmetric ``J(u, p)`` for its smallest |eigenvalue|, near ``start``.

    Inverse iteration on the model's own (banded or sparse) factorization from ``start`` (a
    candidate found nearby): at a branch point that eigenvalue is roundoff-small, so one or two
    iterations converge.  They stop once the Rayleigh residual ``|J x - (x^T J x) x|`` is at
    roundoff level relative to ``|J|``.  Without a factorization (exactly singular) or a start,
    :func:`smallest_eigenvectors`.
    """
    J = problem.checked_jacobian(u, p)
    n = u.size
    F = safe_factorize(problem, J)
    if F is None or start is None:
        return smallest_eigenvectors(problem, u, p, 1)[0]
    x = inverse_iteration(J, F, n, start=start, iters=1)
    J_scale = _max_abs_entry(J)
    for _ in range(iters):
        Jx = J @ x
        lam = float(x @ Jx)
        if np.linalg.norm(Jx - lam * x) <= 1e-13 * J_scale * math.sqrt(n):
            break
        x = inverse_iteration(J, F, n, start=x, iters=1)
    return x


def _max_abs_entry(J: Any) -> float:
    data = J.data if hasattr(J, "data") else np.asarray(J)
    return max(float(np.max(np.abs(data), initial=0.0)), 1e-300)


def second_derivative(problem: Problem, u: np.ndarray, p: float, y_u: np.ndarray, y_p: float,
                      z_u: np.ndarray, z_p: float) -> np.ndarray:
    """``f_XX[Y, Z]`` with ``X = (u, p)``: central difference of ``f_X Z = J z_u + f_p z_p`` along ``Y``.

    The step makes ``Y`` move the state by ``1e-4`` of its size (truncation ``~1e-8`` relative,
    roundoff ``~1e-12``), which is ample for the bifurcation equation's coefficients.
    """
    size = max(float(np.max(np.abs(y_u), initial=0.0)), abs(y_p) / (1.0 + abs(p)), 1e-300)
    scale = 1.0 + float(np.max(np.abs(u), initial=0.0))
    h = 1e-4 * scale / size

    def fx_z(sign: float) -> np.ndarray:
        uu, pp = u + sign * h * y_u, p + sign * h * y_p
        return problem.checked_jacobian(uu, pp) @ z_u + problem.dresidual_dp(uu, pp) * z_p
    return (fx_z(1.0) - fx_z(-1.0)) / (2 * h)


def bifurcation_directions(problem: Problem, u: np.ndarray, p: float, sec_u: np.ndarray, sec_p: float,
                           start: np.ndarray | None = None) -> dict[str, Any]:
    """Directions at a simple branch point of a symmetric problem, free of any arclength weight.

    With ``phi`` the unit null vector of ``J`` and ``T`` the unit vector along ``(v, 1)``,
    ``J v = -f_p``, ``phi^T v = 0``,
    the branches leave ``X*`` along ``alpha (phi, 0) + beta T`` where ``(alpha, beta)`` solves the
    algebraic bifurcation equation ``a alpha^2 + 2 b alpha beta + c beta^2 = 0`` with
    ``a = phi^T f_XX[phi, phi]``, ``b = phi^T f_XX[phi, T]``, ``c = phi^T f_XX[T, T]``.  One root is
    the traced branch (the one nearer the secant ``(sec_u, sec_p)`` of the bracket); the other is
    the bifurcating branch.  At a pitchfork (``a = c = 0`` by symmetry) that is ``phi`` itself.

    Returns
    -------
    Bifurcation
        ``kernel`` ``[phi]`` (unit 2-norm), ``equation`` ``{"a", "b", "c"}``, ``traced`` and the one
        entry of ``directions`` (each ``alpha (phi, 0) + beta T`` with ``alpha^2 + beta^2 = 1``),
        ``kind`` (``"pitchfork"`` or ``"transcritical"``) and ``eigenvalues`` ``[phi^T J phi]``.
    """
    n = u.size
    phi = smallest_eigenvector(problem, u, p, start=start)
    # a reproducible orientation: direction=+1 of switch_branch goes where phi's largest entry grows
    phi = phi if phi[int(np.argmax(np.abs(phi)))] > 0 else -phi
    J = problem.checked_jacobian(u, p)
    fp = problem.dresidual_dp(u, p)
    lam = float(phi @ (J @ phi))
    # T's state part: J v = -f_p on phi's complement (f_p is orthogonal to phi at a branch point)
    M = BorderedSolver(J, safe_factorize(problem, J), phi.reshape(n, 1), phi.reshape(1, n), np.zeros((1, 1)),
                       refactor=problem.factorize)
    v, _ = M.solve(-fp, np.zeros(1))
    # T = (v, 1) at unit Euclidean length: the three coefficients are then in the same units (and a
    # nearby fold, where v is huge, does not swamp a and b)
    t_len = math.sqrt(float(v @ v) + 1.0)
    v, t_p = v / t_len, 1.0 / t_len
    a = float(phi @ second_derivative(problem, u, p, phi, 0.0, phi, 0.0))
    b = float(phi @ second_derivative(problem, u, p, phi, 0.0, v, t_p))
    c = float(phi @ second_derivative(problem, u, p, v, t_p, v, t_p))
    traced = np.array([float(phi @ sec_u), float(sec_p) / t_p])
    traced /= max(np.linalg.norm(traced), 1e-300)
    roots = _abe_roots(a, b, c)
    # the bifurcating root is the one least parallel to the traced branch
    cross = [abs(r[0] * traced[1] - r[1] * traced[0]) for r in roots]
    other = roots[int(np.argmax(cross))]
    scale = abs(a) + abs(b) + abs(c)
    pitchfork = scale > 0 and abs(a) <= 1e-3 * scale and abs(other[1]) <= 1e-3
    if pitchfork:
        other = np.array([1.0, 0.0])
    if other[0] < 0:
        other = -other  # orientation: positive along phi (direction=+1 of switch_branch)

    def along(ab: np.ndarray) -> np.ndarray:
        return np.concatenate([ab[0] * phi + ab[1] * v, [ab[1] * t_p]])
    return Bifurcation(multiplicity=1, kernel=phi[None, :], directions=along(other)[None, :], traced=along(traced),
                       equation={"a": a, "b": b, "c": c}, kind="pitchfork" if pitchfork else "transcritical",
                       eigenvalues=np.array([lam]))


def _abe_roots(a: float, b: float, c: float) -> list[np.ndarray]:
    """The two unit root directions ``(alpha, beta)`` of ``a alpha^2 + 2 b alpha beta + c beta^2 = 0``.

    With ``(alpha, beta) = (cos t, sin t)`` the form is ``A + B cos 2t + C sin 2t`` with
    ``A = (a + c) / 2``, ``B = (a - c) / 2``, ``C = b``, so ``2t = delta +- arccos(-A / R)``; a
    negative discriminant (no real branch) is clipped to the double root nearest to one.
    """
    A, B, C = 0.5 * (a + c), 0.5 * (a - c), b
    R = math.hypot(B, C)
    if R == 0.0:
        raise ValueError("degenerate algebraic bifurcation equation (all second derivatives vanish)")
    delta = math.atan2(C, B)
    gamma = math.acos(float(np.clip(-A / R, -1.0, 1.0)))
    return [np.array([math.cos(t), math.sin(t)]) for t in (0.5 * (delta + gamma), 0.5 * (delta - gamma))]


class _BorderedBranchTest:
    """Continuous branch-point test function ``psi(sigma)`` on a segment.

    The augmented Jacobian ``[[J, fp], [t^T W]]`` is bordered once more by approximate right and left
    null vectors (from the segment's midpoint); the last component of the solution of
    ``[[J, fp, b], [t^T W, b_p], [c^T, c_p, 0]] x = e_last`` changes sign where the augmented
    Jacobian is singular.
    """

    def __init__(self, seg: Segment) -> None:
        self.seg, self.curve, self.A = seg, seg.curve, seg.A
        self.sigma_mid = 0.5 * seg.sigma_B
        um, pm, _ = seg.point(self.sigma_mid)
        self.right, self.left = _augmented_null_vectors(self.curve, um, pm, self.A.t_u, self.A.t_p)

    def solver(self, u: np.ndarray, p: float) -> BorderedSolver:
        """Bordered solver of ``[[J, fp, b_u], [t_row, b_p], [c_u, c_p, 0]]`` at ``(u, p)``."""
        J, fp, F = self.curve.linearize(u, p)
        wu, wp = self.curve.weights(u.size)
        n, A, b, c = u.size, self.A, self.right, self.left
        D = np.array([[wp * A.t_p, b[n]], [c[n], 0.0]])
        return self.curve.bordered(J, F, fp, wu * A.t_u, wp * A.t_p, extra_cols=b[:n].reshape(n, 1),
                                   extra_rows=c[:n].reshape(1, n), extra_D=D)

    def __call__(self, sigma: float) -> float:
        u, p, _ = self.seg.point(sigma)
        _, z = self.solver(u, p).solve(np.zeros(u.size), np.array([0.0, 1.0]))
        return float(z[1])

    def directions(self, u: np.ndarray, p: float) -> Bifurcation:
        """The bifurcating direction (W-orthogonal to the branch) and the traced branch's direction.

        Without symmetry the Jacobian's kernel is not computed: ``kernel`` holds the bifurcating
        direction's state part (unit 2-norm) and ``kind`` is ``"unresolved"``.
        """
        n, curve, A, B = u.size, self.curve, self.A, self.seg.B
        x, z = self.solver(u, p).solve(np.zeros(n), np.array([0.0, 1.0]))
        phi = np.concatenate([x, z[:1]])
        # the tangent is not unique at a branch point: record the direction of the traced branch
        sec_u, sec_p = B.u - A.u, B.p - A.p
        state = phi[:n] / max(float(np.linalg.norm(phi[:n])), 1e-300)
        return Bifurcation(multiplicity=1, kernel=state[None, :],
                           directions=(phi / curve.norm(phi[:n], phi[n]))[None, :],
                           traced=np.concatenate([sec_u, [sec_p]]) / curve.norm(sec_u, sec_p))


def _augmented_null_vectors(curve: Curve, u: np.ndarray, p: float, t_u: np.ndarray,
                            t_p: float) -> list[np.ndarray]:
    """Approximate right and left null vectors of the augmented Jacobian [[J, fp], [t^T W]]."""
    J, fp, F = curve.linearize(u, p)
    wu, wp = curve.weights(u.size)
    n = u.size
    solver = curve.bordered(J, F, fp, wu * t_u, wp * t_p)
    rng = np.random.default_rng(2024)
    vecs = []
    for trans in (False, True):
        x = rng.standard_normal(n + 1)
        for _ in range(3):
            y_u, y_p = solver.solve(x[:n], x[n:], trans=trans)
            y = np.concatenate([y_u, y_p])
            x = y / np.linalg.norm(y)
        vecs.append(x)
    return vecs


#: Noise of an extremum's test function (a derivative along the curve at corrected points), in units
#: of the corrector tolerance times the function's size on the bracket.  Measured on the command line's
#: default trace (tol = 1e-10): values 1e-7 to 4e-7 scattered around the root of a function of size
#: 40 to 120 on its bracket, i.e. 25 to 100 tolerances; the location stops there instead of
#: bisecting noise.  The root is then known to about 1e-8 of the step, far below any use made of it.
EXTREMUM_NOISE = 100.0


class EventTest(TestFunction):
    """A user event or a bound (:class:`contin.watch.events.Event`)."""

    kind = "event"

    def __init__(self, curve: Curve, event: Event, bound: bool = False) -> None:
        super().__init__(curve)
        self.event, self.bound = event, bound
        self.name = event.name
        self.terminal = bool(event.terminal)
        observable_function(curve.problem, event.observable)  # fail early on unknown observables

    @property
    def label(self) -> str:
        return self.event.name

    def value(self, pt: Point) -> float:
        return event_value(self.curve, self.event, pt.u, pt.p, pt.t_u, pt.t_p)

    def detect(self, before: float, after: float) -> bool:
        return self.event.triggered(before, after)

    def annotate(self, spt: SpecialPoint) -> SpecialPoint:
        ev = self.event
        if ev.kind == "extremum":
            spt.info["extremum_of"] = ev.observable if isinstance(ev.observable, str) else ev.name
            if ev.folds is not None:
                spt.info["folds"] = ev.folds
            if ev.stability_label is not None:
                spt.info["stability_label"] = ev.stability_label
        return spt

    def locate(self, seg: Segment, before: float, after: float) -> SpecialPoint:
        curve, event = self.curve, self.event

        def g(sigma: float) -> float:
            u, p, _ = seg.point(sigma)
            if event.kind == "crossing":
                return event_value(curve, event, u, p, None, None)
            t_u, t_p = seg.tangent(u, p)
            return event_value(curve, event, u, p, t_u, t_p)

        # an extremum's test function is a derivative along the curve, taken at points converged to
        # the corrector's tolerance: its noise is EXTREMUM_NOISE times its size on the bracket
        ftol = EXTREMUM_NOISE * max(curve.settings.tol, 1e-12) if event.kind == "extremum" else 0.0
        sigma = seg.root(g, before, after, curve.settings.locate_tol, ftol=ftol)
        u, p, res = seg.point(sigma)
        info = {"event_value": float(g(sigma)), "bracket_p": [seg.A.p, seg.B.p]}
        if event.kind == "extremum":
            info["extremum_value"] = float(observable_function(curve.problem, event.observable)(u, p))
        return SpecialPoint("event", p, u.copy(), curve.problem.evaluate_observables(u, p), residual=res,
                            located=True, s=seg.A.s + sigma, label=event.name, info=info)


def observable_function(problem: Problem, observable: str | Callable) -> Callable[[np.ndarray, float], float]:
    """The callable behind an event's observable: a callable, ``"p"``/the parameter name, or a name."""
    if callable(observable):
        return observable
    if observable in ("p", problem.parameter_name):
        return lambda u, p: p
    try:
        return problem.observables[observable]
    except KeyError:
        raise ValueError(f"unknown observable {observable!r}; the problem has "
                         f"{sorted(problem.observables) + ['p']}") from None


def event_value(curve: Curve, event: Event, u: np.ndarray, p: float, t_u: np.ndarray | None,
                t_p: float | None) -> float:
    """Value of an event's test function at a point (with the unit tangent for extrema)."""
    fun = observable_function(curve.problem, event.observable)
    if event.kind == "crossing":
        return float(fun(u, p)) - event.value
    exact = curve.problem.observable_derivatives.get(event.observable) if isinstance(event.observable, str) else None
    if exact is not None:
        d_u, d_p = exact(u, p)
        return float(np.dot(d_u, t_u) + d_p * t_p)
    if isinstance(event.observable, str) and event.observable in ("p", curve.problem.parameter_name):
        return float(t_p)
    # derivative along the tangent by central differences (second-order accurate); the step
    # balances truncation (h^2) against roundoff (eps / h)
    h = 1e-5 * max(1.0, curve.norm(u, p))
    return (float(fun(u + h * t_u, p + h * t_p)) - float(fun(u - h * t_u, p - h * t_p))) / (2 * h)


def bound_events(st: Settings) -> list[Event]:
    """Terminal crossings for the parameter bounds and the observable bounds of the settings."""
    evs = []
    if math.isfinite(st.p_min):
        evs.append(Event("p", st.p_min, -1, True, "p_min"))
    if math.isfinite(st.p_max):
        evs.append(Event("p", st.p_max, +1, True, "p_max"))
    for name, (lo, hi) in st.bounds.items():
        if lo is not None:
            evs.append(Event(name, float(lo), -1, True, f"{name}_min"))
        if hi is not None:
            evs.append(Event(name, float(hi), +1, True, f"{name}_max"))
    return evs


# pytest would otherwise collect the names starting with "Test" when a test module imports them
for _cls in (TestFunction, FoldTest, BranchPointTest, EventTest):
    _cls.__test__ = False
