"""Test functions: everything a branch watches, behind one protocol (COCO's monitor functions).

A :class:`TestFunction` has

* ``value(point)``: its value at an accepted point;
* ``detect(before, after)``: whether it changed sign (in the wanted direction) over a step;
* ``locate(segment, before, after)``: the special point on the curve between the two points.

Four kinds implement it:

* :class:`FoldTest`: the parameter component of the unit tangent; a sign change is a fold, located
  by Newton on the minimally augmented system (:func:`contin.fold.locate_fold`), with the root of the
  tangent component on the segment as the fallback;
* :class:`BranchPointTest`: the sign of the determinant of the bordered Jacobian (from the
  factorization, so nothing overflows); located as a root of a continuous bordered test function;
* :class:`EventTest`: a user event (:mod:`contin.events`): an observable minus a value, or the
  derivative of an observable along the unit tangent (extremum);
* bounds of the parameter and of observables are :class:`EventTest` s of terminal crossings
  (``bound=True``): the run ends exactly on them and they are not recorded as special points.

:meth:`TestFunction.find` wraps ``locate``: it returns the located point, or the bracket (an
unlocated special point with the reason) when location is off or fails.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from .branch import SpecialPoint
from .curve import CorrectorFailure, Curve, Point
from .events import Event
from .fold import locate_fold
from .linalg import BorderedSolver, SingularMatrixError
from .problem import NonFiniteError, Problem
from .segment import Segment
from .settings import Settings

__all__ = ["TestFunction", "FoldTest", "BranchPointTest", "EventTest", "test_functions", "event_value",
           "observable_function", "bracketed"]

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
        """:meth:`locate`, or the bracket when ``locate`` is False or the location fails."""
        if not locate:
            return self.annotate(bracketed(self.kind, seg.A, seg.B, self.label))
        try:
            return self.annotate(self.locate(seg, before, after))
        except LOCATE_FAILURES as exc:
            spt = bracketed(self.kind, seg.A, seg.B, self.label)
            spt.info["error"] = str(exc)
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
    """Simple branch points: sign changes of the determinant of the bordered Jacobian."""

    kind = name = "branch_point"

    def value(self, pt: Point) -> float:
        return pt.det_sign

    def locate(self, seg: Segment, before: float, after: float) -> SpecialPoint:
        curve, A = self.curve, seg.A
        psi = _BorderedBranchTest(seg)
        psi_A, psi_B = psi(0.0), psi(seg.sigma_B)
        info: dict[str, Any] = {"bracket_p": [A.p, seg.B.p]}
        if psi_A * psi_B > 0:
            # the bordered test function does not bracket: report the bracket, unlocated
            u, p, res = seg.point(psi.sigma_mid)
            info["error"] = "bordered test function did not change sign on the bracket"
            bp = SpecialPoint("branch_point", p, u.copy(), {}, residual=res, located=False, info=info)
        else:
            sigma = seg.root(psi, psi_A, psi_B, curve.settings.locate_tol)
            u, p, res = seg.point(sigma)
            info["test_function"] = val = psi(sigma)
            bp = SpecialPoint("branch_point", p, u.copy(), {}, residual=max(res, abs(val)), located=True, info=info)
            bp.info.update(psi.directions(u, p))
        bp.observables = curve.problem.evaluate_observables(bp.u, bp.p)
        bp.s = A.s + curve.norm(bp.u - A.u, bp.p - A.p)
        return bp


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

    def directions(self, u: np.ndarray, p: float) -> dict[str, list[float]]:
        """The bifurcating direction (W-orthogonal to the branch) and the traced branch's direction."""
        n, curve, A, B = u.size, self.curve, self.A, self.seg.B
        x, z = self.solver(u, p).solve(np.zeros(n), np.array([0.0, 1.0]))
        phi = np.concatenate([x, z[:1]])
        # the tangent is not unique at a branch point: record the direction of the traced branch
        sec_u, sec_p = B.u - A.u, B.p - A.p
        return {"bifurcation_direction": (phi / curve.norm(phi[:n], phi[n])).tolist(),
                "branch_tangent": (np.concatenate([sec_u, [sec_p]]) / curve.norm(sec_u, sec_p)).tolist()}


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


class EventTest(TestFunction):
    """A user event or a bound (:class:`contin.events.Event`)."""

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

        # an extremum's test function is a derivative along the curve: its noise floor is about the
        # corrector tolerance relative to its size on the bracket
        ftol = max(curve.settings.tol, 1e-12) if event.kind == "extremum" else 0.0
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


def test_functions(curve: Curve, events: Sequence[Event] = ()) -> list[TestFunction]:
    """Everything a branch watches, in the order special points found on one step are reported."""
    st = curve.settings
    tests: list[TestFunction] = []
    if st.detect_folds:
        tests.append(FoldTest(curve))
    if st.detect_branch_points:
        tests.append(BranchPointTest(curve))
    tests += [EventTest(curve, ev) for ev in events]
    tests += [EventTest(curve, ev, bound=True) for ev in bound_events(st)]
    return tests


# pytest would otherwise collect the names starting with "Test" when a test module imports them
for _cls in (TestFunction, FoldTest, BranchPointTest, EventTest):
    _cls.__test__ = False
test_functions.__test__ = False
