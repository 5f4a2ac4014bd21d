"""Pseudo-arclength continuation (PALC): the driver :func:`continuation` and :func:`switch_branch`.

The core traces the solution curve of ``f(u, p) = 0`` in the augmented space ``X = (u, p)``.  One
step is a short sequence of named parts, each in its own module:

* predictor and corrector (:mod:`contin.path.corrector`): predict along the tangent (quadratic with the
  curvature seen over the last step), correct by Newton on the bordered PALC system; the corrector
  returns a :class:`~contin.path.corrector.Correction`;
* step control (:mod:`contin.path.stepsize`): Newton effort, contraction rate, turning angle, rejections;
* test functions (:mod:`contin.watch.testfunctions`): folds, branch points, user events and bounds share
  one protocol (value at a point, detect between two points, locate on the segment);
* record (:mod:`contin.recorder`): accepted points, their stability, the special points.

The curve itself (arclength metric, linearization, tangent) is :class:`contin.path.curve.Curve`; the
options are :class:`contin.settings.Settings`.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from .numerics.linalg import SingularMatrixError
from .numerics.stability import inertia
from .path.corrector import Correction, check_curvature_consistency, correct, quadratic_predictor
from .path.curve import CorrectorFailure, Curve, Point, max_abs
from .path.scales import ZERO_SCALE, emanating_load_change, scales_from_sensitivity
from .path.segment import Segment
from .path.stepsize import StepController
from .problem import NonFiniteError, Problem
from .recorder import Recorder, observed_rates
from .results.branch import SUCCESSES, Bifurcation, Branch, SpecialPoint
from .settings import Settings, resolve_settings
from .watch.events import Event
from .watch.fold import locate_fold
from .watch.branching import FixedSpaceProblem, full_space_stability, isotropy_basis
from .watch.koiter import attach_koiter
from .watch.multiple import IndexWatch, primary_index
from .watch.testfunctions import KnownBranchPoints, TestFunction
from .watch.watchlist import test_functions

__all__ = ["Settings", "continuation", "locate_fold", "switch_branch", "switch_branch_along", "CorrectorFailure", "Curve",
           "Point", "Correction"]

#: failures of one continuation step: the step is retried smaller
STEP_FAILURES = (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError)

Found = tuple[TestFunction, SpecialPoint]

#: how a branch's message says that its tolerance was raised to the roundoff floor
ROUNDOFF_CLAUSE = "; residuals at the roundoff floor:"

#: smaller steps tried when the Morse index jumps by two or more in one step (see :func:`_skipped_folds`)
MAX_SKIP_RETRIES = 4


def continuation(problem: Problem, u0, p0: float, settings: Settings | None = None, *,
                 events: list[Event] | tuple[Event, ...] = (), tangent: tuple[np.ndarray, float] | None = None,
                 correct_start: bool = True, origin: Any = None, **overrides: Any) -> Branch:
    """Trace the solution branch of ``problem`` through ``(u0, p0)`` by pseudo-arclength continuation.

    Parameters
    ----------
    problem : Problem
        The model.
    u0 : array_like
        Initial state (corrected by Newton at fixed ``p0`` unless ``correct_start`` is False).
    p0 : float
        Initial parameter.
    settings : Settings, optional
        Options; any field may also be given as a keyword argument (``ds=0.1, p_max=4``).
    events : sequence of Event
        User events (see :func:`contin.crossing` and :func:`contin.extremum`).
    tangent : (t_u, t_p), optional
        Initial direction (e.g. after branch switching); otherwise ``J t_u = -f_p t_p`` with the
        sign of ``t_p`` given by ``settings.direction``.
    correct_start : bool
        Converge the starting point at fixed parameter first.
    origin : JumpResult, optional
        The snap that landed on the starting point; it is recorded as the branch's first special
        point (``kind="jump"``, ``label="jump_to"``, with the energy released).

    Returns
    -------
    Branch
        Converged points, located special points, and the reason the run stopped.
    """
    st = resolve_settings(settings, overrides)
    t_start = time.perf_counter()
    curve = Curve(problem, st)
    tests = test_functions(curve, events)
    recorder = Recorder(problem, st, curve)
    u0, p0 = np.array(u0, dtype=float).ravel(), float(p0)
    try:
        if curve.needs_calibration():
            curve.calibrate(u0, p0)
        current, lin = _first_point(curve, u0, p0, tangent, correct_start)
    except STEP_FAILURES as exc:
        hint = ""
        if isinstance(exc, np.linalg.LinAlgError):  # SingularMatrixError among them
            hint = ("; the Jacobian is singular at the start: a branch point (start next to it, or use "
                    "switch_branch), or a state on a branch that breaks a continuous symmetry, where a whole "
                    "orbit of equilibria passes through the start and only its fixed-point space (as "
                    "switch_branch traces it) or a phase condition makes the solutions a curve")
        return recorder.finish("failed", f"could not start: {exc}{hint}", t_start)
    if st.check_model:
        failure = _check_start(problem, current, lin)
        if failure:
            return recorder.finish("failed", failure, t_start)
    recorder.add(current)
    if origin is not None:
        recorder.special(_landing(problem, origin, current))
    control = StepController(st)
    watch = IndexWatch()
    status, message = _trace(curve, tests, recorder, control, current, watch)
    late = watch.finish(curve)
    for spt in late.points:
        recorder.special_late(spt)
    recorder.doubts += late.doubts
    if recorder.doubts:
        # the run's own end is kept when it failed; a success becomes a doubt
        status = "unexplained" if status in SUCCESSES else status
        message = f"{message}; the stability count changed where no point could be located: " + "; ".join(
            recorder.doubts)
    if recorder.bridged:
        where = ", ".join(f"{p:.8g}" for p in recorder.bridged)
        message = (f"{message}; crossed {len(recorder.bridged)} bend(s) sharper than ds_min by Newton at a fixed "
                   f"{problem.parameter_name} (from {problem.parameter_name} = {where})")
    branch = recorder.finish(status, message, t_start)
    branch.meta["bridged"] = list(recorder.bridged)
    _note_raised_tolerance(branch, curve, problem.parameter_name)
    branch.meta["n_factorizations"] = curve.n_factorizations
    branch.meta["rejected_steps"] = control.rejections
    return branch


def _note_raised_tolerance(branch: Branch, curve: Curve, parameter_name: str) -> None:
    """Record on ``branch`` (message and ``meta["tol_raised"]``) where ``curve`` raised its tolerance to the roundoff floor."""
    if not curve.tol_raised:
        return
    earlier = branch.meta.get("tol_raised", [])
    branch.meta["tol_raised"] = [{"p": p, "from": a, "to": b} for p, a, b in curve.tol_raised] + earlier
    raised = branch.meta["tol_raised"]
    # one clause for the whole branch: the step off a branch point may have raised it before the run did
    kept = branch.message.split(ROUNDOFF_CLAUSE)[0]
    branch.message = (f"{kept}{ROUNDOFF_CLAUSE} the tolerance was raised from {raised[0]['from']:.1e} to "
                      f"{raised[-1]['to']:.1e} from {parameter_name} = {raised[0]['p']:.8g} on (points converged to rounding)")


def _trace(curve: Curve, tests: list[TestFunction], recorder: Recorder, control: StepController,
           current: Point, watch: IndexWatch) -> tuple[str, str]:
    """The continuation loop from the first point: predict and correct, watch, record, adapt the step.

    Returns the status and message the branch ends with.
    """
    st = curve.settings
    values = [test.value(current) for test in tests]
    previous: Point | None = None
    steps = 0
    crossed: list[tuple[np.ndarray, float]] = []  # folds crossed by _turn_at_fold (each once)
    headway = Headway(tests, values)
    index = _index(recorder, current)

    while steps < st.max_steps:
        try:
            new, contraction, cos_turn = _step(curve, previous, current, control.ds)
        except STEP_FAILURES as exc:
            if control.reject(exc):
                continue
            turned = _turn_at_fold(curve, current, recorder.u, crossed)
            if turned is None and len(recorder.bridged) < MAX_BRIDGES:
                turned = _bridge_bend(curve, current)
                recorder.bridged += [] if turned is None else [current.p]
            if turned is None:
                return "min_step", f"step size fell below ds_min = {st.ds_min:g} at p = {current.p:.8g}: {exc}"
            new, contraction, cos_turn = turned, None, 1.0
            control.ds = max(control.ds, curve.norm(new.u - current.u, new.p - current.p))
        skipped = ""
        if control.retries < MAX_SKIP_RETRIES:
            skipped = ("" if index is not None else _skipped_folds(recorder, current, new)) \
                or _observable_jump(curve, current, new, cos_turn)
        if skipped and control.reject(skipped):
            continue
        seg = Segment(curve, current, new)
        found, new_values = _watch(tests, seg, values, st.locate)
        explained = _explain_index(recorder, tests, seg, found, index, watch)
        if explained.branch_jump and control.reject(explained.branch_jump):
            continue
        steps += 1
        values, index = new_values, explained.index
        found = [f for f in found if not any(f[1] is r for r in explained.replaced)] + explained.found
        for _, spt in found:
            attach_koiter(curve.problem, spt)
        recorder.doubts += explained.doubts
        stop = _first_stop(found)
        if stop is not None:
            return _end_on(recorder, curve, found, stop, current)
        _record(recorder, [spt for _, spt in found], new)
        headway.update(steps, bool(found), values)
        if st.stall_steps and headway.idle(steps) >= st.stall_steps:
            return "stalled", headway.explain(steps, curve.problem.parameter_name, new.p)
        if st.progress and steps % st.progress_every == 0:
            _progress(steps, new, control.ds)
        control.accept(new.iterations, contraction, cos_turn)
        previous, current = current, new
    # the step budget ran out before the path's end, a bound or a stopping event: not a success
    return "max_steps", (f"reached max_steps = {st.max_steps} at {curve.problem.parameter_name} = {current.p:.8g} "
                         "before any bound or stopping event")


class Headway:
    """When a path last made progress: a special point found, or a bound approached closer than ever since the last one.

    The measure behind :attr:`contin.Settings.stall_steps`.  The parameter alone does not show
    progress: a path winding through many folds on its way to its end goes back and forth in it
    for thousands of steps, but it finds a fold every few dozen.  A path with no feature and no bound
    coming nearer (running away from every end) has stopped progressing.  The closest approach counts
    from the last special point, not from the start: a path that came near a bound, turned back at a
    fold and now heads for its end again makes progress with every step nearer, long before it passes
    its earlier approach.

    Parameters
    ----------
    tests : list of TestFunction
        The run's test functions; those that are bounds (:func:`contin.watch.testfunctions.bound_events`)
        give the distance to each bound as the size of their value.
    values : list of float
        Their values at the first point.
    """

    def __init__(self, tests: Sequence[TestFunction], values: Sequence[float]) -> None:
        self._bounds = [i for i, test in enumerate(tests) if getattr(test, "bound", False)]
        self._names = [tests[i].label for i in self._bounds]
        self._nearest = [abs(float(values[i])) for i in self._bounds]
        self.last_step = 0
        self.last_kind = "the start"
        self._since = "the start"

    def update(self, step: int, found_special: bool, values: Sequence[float]) -> None:
        """Take the accepted step ``step`` (whether it found a special point, and the test values at its end)."""
        if found_special:
            self.last_step, self.last_kind = step, "a special point"
            self._since = f"the special point at step {step}"
        for k, i in enumerate(self._bounds):
            gap = abs(float(values[i]))
            if found_special:
                self._nearest[k] = gap
            elif gap < self._nearest[k]:
                self._nearest[k] = gap
                self.last_step, self.last_kind = step, f"a closest approach to {self._names[k]}"

    def idle(self, step: int) -> int:
        """Accepted steps since the last progress."""
        return step - self.last_step

    def explain(self, step: int, parameter: str, p: float) -> str:
        """Why a run stalled: the message of status ``"stalled"``."""
        nearest = ", ".join(f"{name} at {gap:.6g}" for name, gap in zip(self._names, self._nearest))
        approach = (f"; since {self._since} its bounds came no closer than {nearest}" if nearest
                    else "; it has no bound")
        return (f"stalled at {parameter} = {p:.8g}: {self.idle(step)} steps without progress (no fold, branch point "
                f"or event found and no bound approached; the last progress was {self.last_kind} at step "
                f"{self.last_step}){approach}: the path is not heading for an end")


#: How far (in smallest steps ``ds_min`` of the run's metric) a fold may lie from the point whose step
#: collapsed for :func:`_turn_at_fold` to cross it: the collapse must be at that fold.
FOLD_TURN_REACH = 1e3


def _same_point(u: np.ndarray, p: float, v: np.ndarray, q: float, rtol: float = 1e-6) -> bool:
    scale = max(float(np.max(np.abs(v), initial=0.0)), 1e-300)
    return abs(p - q) <= rtol * max(abs(q), 1e-300) and float(np.max(np.abs(u - v), initial=0.0)) <= rtol * scale


def _turn_at_fold(curve: Curve, current: Point, history: list[np.ndarray],
                  crossed: list[tuple[np.ndarray, float]]) -> Point | None:
    """A point past a fold that the arclength steps cannot turn, or None.

    In a metric that weights the parameter far above the state (or a fold far sharper than the
    step-size floor), the curve turns at a fold within less than ``ds_min``: every hyperplane step
    from the near side misses it, and the step collapses.  At the fold itself the tangent is the
    Jacobian's null vector ``(phi, 0)``, and near the fold the curve is a graph over ``phi``, so a
    step from the located fold along ``(phi, 0)`` (oriented as the path was going) lands on the far
    side for any step length up to the fold's own scale (the near side's tangent is that null vector
    to first order).  The fold is then found and located on the segment as usual.

    The way through is the way the path came: from the last recorded state (``history``) that lies
    clearly on one side of the fold, at least half the turn's step away along ``phi``, to the fold.
    Neither the current point's tangent nor its predecessor can tell it: within the corrector's
    noise of the fold, the sign of the tangent's state part relative to its load part is the sign
    of an eigenvalue at roundoff, and in a metric dominated by the load the tangent keeps the load's
    sign, so its state part may point back (and the last step may have gone back with it).
    """
    try:
        fold = locate_fold(curve.problem, current.u, current.p, v0=current.t_u, tol=curve.settings.tol)
    except STEP_FAILURES:
        return None
    # a fold crossed once is not crossed again: from its far side the turn would go back; and only a
    # fold next to the point (the step collapsed on it), never one Newton found elsewhere on the curve
    if not fold.located or any(_same_point(fold.u, fold.p, u, p) for u, p in crossed):
        return None
    if curve.norm(np.asarray(fold.u) - current.u, fold.p - current.p) > FOLD_TURN_REACH * curve.settings.ds_min:
        return None
    crossed.append((np.asarray(fold.u, dtype=float), float(fold.p)))
    # next to the fold the tangent's state part is the null vector to first order in the distance,
    # which is all the hyperplane's normal needs (the curve is a graph over any direction close to it);
    # the step is measured in the state alone (a metric in which the fold is not a corner), and
    # its length is a fraction of the state's size along that direction
    phi = np.asarray(current.t_u, dtype=float)
    size = float(np.sqrt(np.mean(phi * phi)))
    if not size > 0.0:
        return None
    phi = phi / size
    flat = Curve(curve.problem, replace(curve.settings, state_weight=1.0, param_weight=1.0))
    step = 1e-3 * max(float(np.sqrt(np.mean(np.square(fold.u)))), 1e-300)
    if _approach_side(history, np.asarray(fold.u, dtype=float), phi, 0.5 * step) > 0.0:
        phi = -phi  # came from the +phi side: go on towards -phi
    origin = Point(np.asarray(fold.u, dtype=float), float(fold.p), phi, 0.0, fold.residual, 0)
    for _ in range(12):
        try:
            c = correct(flat, origin, step, start=(origin.u + step * phi, origin.p))
            t_u, t_p, det_sign = curve.tangent(c.u, c.p, phi, 0.0, lin=c.linearization)
        except STEP_FAILURES:
            step *= 0.5
            continue
        return Point(c.u, c.p, t_u, t_p, c.residual, c.iterations, det_sign,
                     current.s + curve.norm(c.u - current.u, c.p - current.p))
    return None


#: A step whose tangent keeps less than this fraction of the parameter's part of the tangent before it is
#: approaching a fold: its tangent is taken from the Jacobian at the point itself (see :func:`_step`).  At
#: the stored points next to the folds that hid this way the part fell 9 to 60 times in one step.
FRESH_TANGENT_DROP = 0.5
#: Bends of one run that :func:`_bridge_bend` may cross: each is found only after the step has
#: collapsed, so a path that needs many is better served by a smaller ``ds_min`` or another control.
MAX_BRIDGES = 8
#: The smallest share of the parameter in the unit tangent at which :func:`_bridge_bend` steps in the
#: parameter (below it the path is near a fold, where it is no graph over the parameter).
BRIDGE_MIN_SHARE = 1e-3


def _bridge_bend(curve: Curve, current: Point) -> Point | None:
    """A point past a bend of the path that the arclength steps cannot cross, away from any fold; or None.

    A path may bend over a length below what its corrector resolves: where a contact region leaves
    the barrier's range while another holds the load, the stiffness the region gave vanishes over an
    indenter travel of 1e-9 R.  Every arclength step into the bend then lands farther from its
    predictor than the step is long (the state there is fixed only to the residual's rounding over
    the smallest eigenvalue), and the step collapses although the path goes on.  Away from a fold the
    Jacobian in the state is regular and the path is a graph over the parameter: Newton's method at
    a fixed parameter a little ahead (:meth:`Curve.newton_fixed_p`, from the current state) finds the
    path beyond the bend.  The step grows tenfold from 100 ``ds_min``; its landing counts only if the
    same Newton back at the current parameter returns to the current state, to half the step (the
    same branch both ways), and if the bordered Jacobian's determinant keeps its sign (no fold or
    branch point between).  The watch then checks the step as any other.
    """
    _, wp = curve.weights(current.u.size)
    share = math.sqrt(wp) * abs(current.t_p)  # the parameter's part of the unit tangent
    if not share > BRIDGE_MIN_SHARE:
        return None
    st = curve.settings
    ds = 100.0 * st.ds_min
    while ds <= st.ds_max:
        p = current.p + math.copysign(ds * share, current.t_p) / math.sqrt(wp)
        try:
            u, residual, iterations = curve.newton_fixed_p(current.u, p)
            u_back, _, _ = curve.newton_fixed_p(u, current.p)
            if curve.norm(u_back - current.u, 0.0) <= st.max_correction * ds:
                t_u, t_p, det_sign = curve.tangent(u, p, current.t_u, current.t_p)
                if det_sign * current.det_sign < 0:
                    return None  # a fold or a branch point between: not a bend for this bridge
                return Point(u, p, t_u, t_p, residual, iterations, det_sign,
                             current.s + curve.norm(u - current.u, p - current.p))
        except STEP_FAILURES:
            pass
        ds *= 10.0
    return None


#: How many recorded states back :func:`_approach_side` looks for one clearly on one side of a fold.
APPROACH_LOOKBACK = 50


def _approach_side(history: list[np.ndarray], fold_u: np.ndarray, phi: np.ndarray, reach: float) -> float:
    """Where the path came from, along ``phi`` (scaled to unit rms): the coordinate ``(u - fold_u) . phi / n``
    of the last recorded state at least ``reach`` from the fold (0.0 if none is that far)."""
    for u in reversed(history[-APPROACH_LOOKBACK:]):
        side = float(np.dot(u - fold_u, phi)) / phi.size
        if abs(side) >= reach:
            return side
    return 0.0


def _skipped_folds(recorder: Recorder, current: Point, new: Point) -> str:
    """Why the step from ``current`` to ``new`` may have stepped over several folds ("" when not).

    One fold or simple branch point changes the Morse index by one; a change by two or more in one
    step means the step crossed several of them (e.g. both folds of an S-curve), where the test
    functions see an even number of sign changes, i.e. none.  Only with ``stability`` on (the index
    is then computed for every point anyway, and kept for the recorder).  A double eigenvalue
    crossing zero at once (a symmetric problem's double branch point) also changes the index by
    two; the guard gives up after :data:`MAX_SKIP_RETRIES` smaller steps.
    """
    if not recorder.st.stability:
        return ""
    before, after = recorder.stability_of(current), recorder.stability_of(new)
    label = next(iter(before), None)
    if label is None or label not in after:
        return ""
    n0, n1 = before[label].n_negative, after[label].n_negative
    if abs(n1 - n0) < 2:
        return ""
    return f"Morse index changed from {n0} to {n1} in one step (several folds stepped over)"


#: How many times the slopes at a step's ends (plus the turn of the tangent) an observable's change
#: may be before :func:`_observable_jump` calls the step a jump.
OBSERVABLE_JUMP = 2.0


def _observable_jump(curve: Curve, current: Point, new: Point, cos_turn: float) -> str:
    """Why the step from ``current`` to ``new`` may have jumped over part of the curve ("" when not).

    Along an arc of length ``ds`` over which the unit tangent turns by ``theta``, an observable
    ``y`` with slopes ``y'_0``, ``y'_1`` at the ends changes by at most about
    ``ds (max(|y'_0|, |y'_1|) + theta G)``, ``G`` the size of its gradient in the arclength metric
    (its slope cannot leave the ends' by more than the tangent turns).  A step that skipped a pair
    of folds (both ends on the outer arms of an S, with parallel tangents) moves the state, and the
    observables that see it, by far more than that, while the Morse index and the determinant
    sign come back to where they were.  Checked for the parameter itself and every observable
    with a declared derivative (:attr:`contin.Problem.observable_derivatives`), with
    :data:`OBSERVABLE_JUMP` as the margin and the corrector's resolution as the noise floor.
    """
    ds = new.s - current.s
    if not ds > 0 or current.t_u is None or new.t_u is None:
        return ""
    theta = math.acos(min(1.0, max(-1.0, cos_turn)))
    wu2, wp2 = curve.weights(new.u.size)
    noise = 10.0 * curve.settings.xtol * (1.0 + curve.norm(new.u, new.p))

    def jumped(name: str, change: float, slopes: tuple[float, float], size: float) -> str:
        bound = OBSERVABLE_JUMP * ds * (max(abs(slopes[0]), abs(slopes[1])) + theta * size) + noise * size
        if abs(change) > bound:
            return (f"{name} changed by {change:.3g} in one step where the slopes at its ends allow {bound:.3g} "
                    "(part of the curve stepped over)")
        return ""

    reason = jumped(curve.problem.parameter_name, new.p - current.p, (current.t_p, new.t_p), 1.0 / math.sqrt(wp2))
    if reason or not curve.problem.observable_derivatives:
        return reason
    before, after = observed_rates(curve.problem, current), observed_rates(curve.problem, new)
    for name, (y1, rate1, d_u, d_p) in after.items():
        if name not in before or d_u is None:
            continue
        y0, rate0 = before[name][0], before[name][1]
        d_u = np.asarray(d_u, dtype=float)
        size = math.sqrt(float(np.dot(d_u, d_u)) / wu2 + d_p**2 / wp2)
        if all(math.isfinite(v) for v in (y0, y1, size, rate0, rate1)):
            reason = jumped(name, y1 - y0, (rate0, rate1), size)
            if reason:
                return reason
    return ""


def _progress(steps: int, new: Point, ds: float) -> None:
    print(f"[contin] step {steps}: p = {new.p:.6g}, ds = {ds:.3g}, newton = {new.iterations}", file=sys.stderr)


def _first_point(curve: Curve, u0: np.ndarray, p0: float, tangent: tuple[np.ndarray, float] | None,
                 correct_start: bool) -> tuple[Point, tuple]:
    """The converged starting point with its unit tangent, and the linearization there."""
    if correct_start:
        u0, res0, it0 = curve.newton_fixed_p(u0, p0)
    else:
        res0, it0 = max_abs(curve.residual(u0, p0)), 0
        if res0 > curve.tol:
            raise CorrectorFailure(f"starting point is not converged (residual {res0:.3e} > tol {curve.tol:.1e})")
    lin = curve.linearize(u0, p0)
    if tangent is None:
        guess_u, guess_p = _initial_direction(lin, u0.size, curve.settings.direction)
    else:
        guess_u, guess_p = np.asarray(tangent[0], dtype=float), float(tangent[1])
    t_u, t_p, det_sign = curve.tangent(u0, p0, guess_u, guess_p, lin=lin)
    return Point(u0, p0, t_u, t_p, res0, it0, det_sign, 0.0), lin


def _check_start(problem: Problem, start: Point, lin: tuple) -> str:
    """The model check of :mod:`contin.modelkit.check` at the first point: "" when it passes, else why the run stops."""
    from .modelkit.check import quick_check  # imported here: only runs that check need it
    from .path.scales import start_scales

    J, fp, F = lin
    U, P = start_scales(start.u, start.p, fp, F, getattr(problem, "reference_scales", None))
    report = quick_check(problem, start.u, start.p, J, fp, start.t_u, start.t_p, U, P)
    if report.ok:
        return ""
    return (f"{report.summary()} (see contin.check_problem; Settings.check_model = False skips this check)")


def _initial_direction(lin: tuple, n: int, direction: int) -> tuple[np.ndarray, float]:
    """Guess of the first tangent, ``J t_u = -f_p`` with ``t_p = direction`` (zero ``t_u`` without a factorization)."""
    _, fp, F = lin
    t_u = np.zeros(n)
    if F is not None:
        try:
            t_u = -F.solve(fp)
        except SingularMatrixError:
            t_u = np.zeros(n)
    return direction * t_u, float(direction) * 1.0


def _landing(problem: Problem, origin: Any, start: Point) -> SpecialPoint:
    """The special point ``jump_to`` of the snap that landed on the starting point."""
    landing = origin.special_points(problem)[1]
    landing.u, landing.p, landing.s, landing.index = start.u.copy(), start.p, 0.0, 0
    landing.residual = start.residual
    landing.info["energy_released"] = float(origin.energy_from - origin.energy_to)
    landing.info["jumped_from_observables"] = problem.evaluate_observables(origin.u_from, origin.p)
    return landing


def _step(curve: Curve, previous: Point | None, current: Point, ds: float) -> tuple[Point, float | None, float]:
    """Predict, correct and check one step of arclength ``ds``.

    Returns the new point, the corrector's contraction rate and the cosine of the tangent's turn;
    raises one of :data:`STEP_FAILURES` when the step is to be retried smaller.
    """
    start = quadratic_predictor(previous, current, ds) if previous is not None else None
    c = correct(curve, current, ds, start=start)
    # The corrector's last linearization, one small update from the point, is good enough for the
    # path's own tangent (predictor, orientation, the signs that detect special points); locating
    # them takes tangents linearized at the points themselves (Segment.tangent).  Fresh tangents here
    # too were measured: no faster, and the arch under a load-dominated metric
    # (tests/test_branch_point_weights.py, param_weight 1e3 with ds_max 5e2) then turned back at its
    # near-coincident fold and branch point, 3e-8 apart in the load.
    t_u, t_p, det_sign = curve.tangent(c.u, c.p, current.t_u, current.t_p, lin=c.linearization)
    if abs(t_p) < FRESH_TANGENT_DROP * abs(current.t_p):
        # next to a fold the parameter's part of the tangent is the smallest eigenvalue's doing, and the
        # corrector's last update moves that eigenvalue: a tangent from one update before the point may
        # still point ahead where the point's own Jacobian already has the fold behind it (a contact
        # node leaving the barrier at a limit load); there the fold test reads the point's own tangent
        t_u, t_p, det_sign = curve.tangent(c.u, c.p, current.t_u, current.t_p)
    cos_turn = curve.inner(t_u, t_p, current.t_u, current.t_p)
    if cos_turn < curve.settings.min_tangent_cos:
        raise CorrectorFailure(f"tangent turned too sharply (cos = {cos_turn:.3f}); possible branch jump")
    if previous is not None:
        check_curvature_consistency(curve, previous, current, c.u, c.p, ds)
    new = Point(c.u, c.p, t_u, t_p, c.residual, c.iterations, det_sign, current.s + ds)
    st = curve.settings
    if curve.problem.symmetric and st.watch_index and not st.stability and c.linearization is not None:
        # the Morse index of the Jacobian the corrector last factorized (one converged update from the
        # point): from its pivots where they give it exactly (no interchanges), else one pivot-free
        # L D L^T of that same matrix; the model's Jacobian is not evaluated again.  It is the primary
        # index only where the primary operator is that Jacobian (or it bordered by constraints);
        # otherwise the index is counted from the operator itself (None here)
        J, _, F = c.linearization
        new.inertia = F.symmetric_inertia() if F is not None else None
        if new.inertia is None:
            new.inertia = inertia(J)
        if new.inertia is not None:
            new.inertia = curve.problem.index_from_jacobian(new.inertia)
    return new, c.contraction, cos_turn


@dataclass
class _Explained:
    """:func:`contin.watch.multiple.explain_index_change` on a step, with its points paired with the test of their kind."""

    index: int | None = None
    found: list[Found] = field(default_factory=list)
    replaced: list[SpecialPoint] = field(default_factory=list)
    branch_jump: str = ""
    doubts: list[str] = field(default_factory=list)


def _index(recorder: Recorder, pt: Point) -> int | None:
    """The primary Morse index at ``pt`` when the run watches it (a symmetric problem), else None.

    With ``stability`` on it is the recorder's own count (computed once per point); otherwise the
    count the corrector's factorization gives for free (:attr:`Point.inertia`), or the index alone (a
    pivot-free factorization, no eigenvalues).
    """
    st, problem = recorder.st, recorder.problem
    if not (st.watch_index and st.locate and problem.symmetric and st.detect_folds and st.detect_branch_points):
        return None
    if st.stability:
        infos = recorder.stability_of(pt)
        return None if not infos else int(next(iter(infos.values())).n_negative)
    if pt.inertia is not None:
        return pt.inertia
    return primary_index(problem, pt.u, pt.p)


def _explain_index(recorder: Recorder, tests: list[TestFunction], seg: Segment, found: list[Found],
                   n_A: int | None, watch: IndexWatch) -> _Explained:
    """Account for the step's change of the primary Morse index (from ``n_A``) by what was found on it
    (see :mod:`contin.watch.multiple`); the index at the step's end comes back with the explanation."""
    if n_A is None:
        return _Explained()
    n_B = _index(recorder, seg.B)
    if n_B is None:
        return _Explained()
    result = watch.step(seg.curve, seg, n_A, n_B, [spt for _, spt in found], len(recorder.p) - 1)
    by_kind = {test.kind: test for test in tests}
    pairs = [(by_kind[spt.kind], spt) for spt in result.points]
    return _Explained(n_B, pairs, result.replaced, result.branch_jump, result.doubts)


def _watch(tests: list[TestFunction], seg: Segment, values: list[float],
           locate: bool) -> tuple[list[Found], list[float]]:
    """Test functions at the segment's end; the special points of those that changed sign on it."""
    new_values = [test.value(seg.B) for test in tests]
    found = [(test, test.find(seg, a, b, locate))
             for test, a, b in zip(tests, values, new_values) if test.detect(a, b)]
    return found, new_values


def _first_stop(found: list[Found]) -> Found | None:
    """The special point the run ends on: the first along the path (terminal events win ties)."""
    stops = [(f, rank) for f in found if (rank := f[0].stop_rank(f[1])) is not None]
    if not stops:
        return None
    return min(stops, key=lambda item: (item[0][1].s, item[1]))[0]


def _record(recorder: Recorder, specials: list[SpecialPoint], new: Point | None) -> None:
    """Record special points in path order, then the accepted point after them."""
    for spt in sorted(specials, key=lambda s: s.s):
        recorder.special(spt)
    if new is not None:
        recorder.add(new)


def _end_on(recorder: Recorder, curve: Curve, found: list[Found], stop: Found, current: Point) -> tuple[str, str]:
    """End the branch exactly on ``stop``: record what lies before it, and it; return (status, message)."""
    test, hit = stop
    _record(recorder, [spt for t, spt in found if not t.terminal and spt.s <= hit.s and spt is not hit], None)
    if not test.bound:
        recorder.special(hit)  # before the end point is stored: "before" is the last point
        hit.info["ends_branch"] = True
    recorder.add(_point_from_special(curve, hit, current))
    hit.index = len(recorder.p) - 1
    label = test.name if test.terminal else hit.kind
    message = f"stopped at {label} ({curve.problem.parameter_name} = {hit.p:.10g})"
    return ("bound" if test.bound else "event"), message


def _point_from_special(curve: Curve, spt: SpecialPoint, previous: Point) -> Point:
    """The special point as an accepted point (residual and tangent evaluated there)."""
    res = max_abs(curve.residual(spt.u, spt.p))
    try:
        t_u, t_p, det_sign = curve.tangent(spt.u, spt.p, previous.t_u, previous.t_p)
    except (CorrectorFailure, SingularMatrixError, np.linalg.LinAlgError):
        # at a branch point the tangent is not unique: keep the previous one
        t_u, t_p, det_sign = previous.t_u, previous.t_p, 0.0
    return Point(spt.u, spt.p, t_u, t_p, res, 0, det_sign, spt.s)


def switch_branch(problem: Problem, branch_point: SpecialPoint, settings: Settings | None = None, *,
                  direction: int = 1, branch: int = 0, ds: float | None = None, events: Sequence[Event] = (),
                  known: Sequence[SpecialPoint] = (), **overrides: Any) -> Branch:
    """Continue the branch that bifurcates at a located simple branch point.

    The location stored the bifurcating direction ``d`` without any arclength weight
    (``branch_point.bifurcation.directions[0]``; for symmetric problems from the algebraic bifurcation
    equation, see :func:`contin.watch.testfunctions.bifurcation_directions`), so any settings may be used
    here.  ``d`` is normalised in this run's norm; the first point is found by the corrector on the
    hyperplane through ``X* + ds d`` whose normal is ``d`` made orthogonal (in this run's metric) to
    the traced branch's tangent ``branch_point.bifurcation.traced``, which the traced branch therefore does
    not cross near ``X*``.  From there ordinary continuation proceeds.

    The run ends where the new branch meets a branch point again: the one it started from (status
    ``"closed_loop"``: it went round a closed loop) or one of ``known`` (status
    ``"reached_branch_point"``), instead of going round until ``max_steps``.

    Parameters
    ----------
    problem : Problem
    branch_point : SpecialPoint
        A located ``"branch_point"`` from :func:`continuation`.
    direction : int
        +1 or -1: which half of the bifurcating branch.
    branch : int
        Which of the record's directions (``branch_point.bifurcation.directions``): at a multiple
        point one per branch the symmetry or the reduced equation resolved (``labels`` says which).
    ds : float, optional
        First step (defaults to ``settings.ds``).
    events : sequence of Event
        User events of the new branch.
    known : sequence of SpecialPoint
        Branch points already known (e.g. ``branch.branch_points()`` of the traced branch); the run
        ends on reaching one of them.

    Returns
    -------
    Branch
        The bifurcating branch; its first special point is the branch point it came from.
    """
    bif = branch_point.bifurcation
    if branch_point.kind != "branch_point" or bif is None or not len(bif.directions):
        raise ValueError("switch_branch needs a located branch point (kind 'branch_point' whose bifurcation record "
                         "has a direction to switch to)")
    if direction not in (-1, 1):
        raise ValueError(f"switch_branch: direction must be +1 or -1, got {direction!r}")
    if not 0 <= int(branch) < len(bif.directions):
        raise ValueError(f"switch_branch: branch must be 0 .. {len(bif.directions) - 1} (the point's resolved "
                         f"directions), got {branch!r}")
    if bif.multiplicity > 1 and bif.kind == "symmetric":
        restricted = _in_fixed_space(problem, branch_point, branch, known)
        if restricted is not None:
            sub, bp_z, known_z = restricted
            br = switch_branch(sub, bp_z, settings, direction=direction, branch=0, ds=ds, events=events, known=known_z,
                               **overrides)
            return _to_full_space(problem, sub, br, settings, overrides)
    names = {f.name for f in fields(Settings)}
    st = resolve_settings(settings, {k: v for k, v in overrides.items() if k in names})
    # the model was checked where the branch that bifurcates here was traced; next to a branch point
    # its Jacobian is nearly singular along the new tangent, and finite differences there measure the
    # curvature of the residual rather than the slope the start check compares with
    st = replace(st, check_model=False)
    u_bp = np.asarray(branch_point.u, dtype=float)
    n = u_bp.size
    if Curve(problem, st).needs_calibration():
        # open weights from the branch point's own scales, for the step off and the whole new branch
        # (calibrating at the first point instead would measure a nearly singular Jacobian)
        U, P = branch_point_scales(u_bp, float(branch_point.p), bif.traced, bif.directions[branch],
                                   reference=getattr(problem, "reference_scales", None), koiter=bif.koiter,
                                   bracket=branch_point.info.get("bracket_p"))
        st = replace(st, state_weight=1.0 / U if st.state_weight is None else st.state_weight,
                     param_weight=1.0 / P if st.param_weight is None else st.param_weight)
    curve = Curve(problem, st)
    d = _unit(curve, direction * bif.directions[branch], n)
    normal = _off_branch_normal(curve, d, bif.traced, n)
    step = st.ds if ds is None else float(ds)
    first = _step_off(curve, u_bp, branch_point.p, d, normal, step)
    if curve.tol_raised:
        # the step off converged to rounding: the new branch starts with the tolerance it was raised to
        st = replace(st, tol=max(st.tol, curve.tol / getattr(problem, "residual_scale", 1.0)))
    watch = KnownBranchPoints(tuple([("origin", u_bp, float(branch_point.p))] + [
        (f"branch point {k} ({problem.parameter_name} = {kp.p:.10g})", np.asarray(kp.u, dtype=float), float(kp.p))
        for k, kp in enumerate(known) if kp.kind == "branch_point"]))
    br = continuation(problem, first.u, first.p, st, events=[*events, watch], tangent=(d[:n], float(d[n])),
                      correct_start=False, **{k: v for k, v in overrides.items() if k not in names})
    _name_the_meeting(br, problem)
    _note_raised_tolerance(br, curve, problem.parameter_name)
    origin = SpecialPoint("branch_point", branch_point.p, u_bp, dict(branch_point.observables),
                          residual=branch_point.residual, located=branch_point.located, s=0.0, index=0,
                          label="origin", info={"bracket_p": branch_point.info.get("bracket_p")})
    br.special_points.insert(0, origin)
    br.meta["origin"] = {"kind": "branch_point", "p": float(branch_point.p)}
    return br


def switch_branch_along(problem: Problem, u: np.ndarray, p: float, along: np.ndarray, settings: Settings | None = None,
                        *, traced: np.ndarray | None = None, direction: int = 1, ds: float | None = None,
                        events: Sequence[Event] = (), known: Sequence[SpecialPoint] = (),
                        **overrides: Any) -> Branch:
    """Continue the branch that leaves ``(u, p)`` along an explicit direction, for callers that know it.

    As :func:`switch_branch` from a branch point whose record holds the one direction ``along`` (and the traced
    branch's tangent ``traced``, which the step off keeps clear of); nothing is located or checked at
    ``(u, p)`` beyond what the first corrected point needs.

    Parameters
    ----------
    problem : Problem
    u, p : ndarray, float
        The point the branch leaves (a branch point, or wherever the caller knows a branch passes).
    along : ndarray, shape (n + 1,)
        The direction ``(du, dp)`` of the new branch (any length; a mode is ``(mode, 0)``).
    traced : ndarray, shape (n + 1,), optional
        The tangent of the branch already traced through the point.
    direction, ds, events, known, overrides
        As :func:`switch_branch`.

    Returns
    -------
    Branch
        The new branch; its first special point is ``(u, p)``, a ``"branch_point"`` labelled ``"origin"``.
    """
    u = np.asarray(u, dtype=float)
    along = np.asarray(along, dtype=float)
    if along.shape != (u.size + 1,) or not np.all(np.isfinite(along)) or not np.any(along[:-1]):
        raise ValueError(f"switch_branch_along: along must be a finite direction (du, dp) of shape ({u.size + 1},) "
                         f"with du not zero, got shape {along.shape}")
    kernel = along[:-1] / float(np.linalg.norm(along[:-1]))
    record = Bifurcation(multiplicity=1, kernel=kernel[None, :], directions=along[None, :], traced=traced,
                         kind="unresolved", labels=["given by the caller"])
    point = SpecialPoint("branch_point", float(p), u, problem.evaluate_observables(u, float(p)),
                         residual=max_abs(problem.residual(u, float(p))), located=True, bifurcation=record)
    return switch_branch(problem, point, settings, direction=direction, ds=ds, events=events, known=known, **overrides)


def _in_fixed_space(problem: Problem, bp: SpecialPoint, branch: int,
                    known: Sequence[SpecialPoint]) -> tuple[FixedSpaceProblem, SpecialPoint, list[SpecialPoint]] | None:
    """The branch point and the problem restricted to the fixed-point space of the chosen branch's symmetry.

    At a multiple point the other branches (and, for a nearly continuous symmetry such as a ring's,
    the turned copies of this one) lie next to the chosen branch in every hyperplane that crosses
    it, and the corrector drifts along them; in the fixed-point space of the branch's isotropy
    group the point is simple (:func:`contin.watch.branching.isotropy_basis`).  None when the
    problem declares no symmetry that fixes the branch.
    """
    bif = bp.bifurcation
    u = np.asarray(bp.u, dtype=float)
    d = np.asarray(bif.directions[branch], dtype=float)
    found = isotropy_basis(problem, u, d[:-1])
    if found is None:
        return None
    B, order = found
    sub = FixedSpaceProblem(problem, B)
    d_z = np.concatenate([B.T @ d[:-1], d[-1:]])
    traced = None if bif.traced is None else np.concatenate([B.T @ bif.traced[:-1], bif.traced[-1:]])
    kernel = (B.T @ d[:-1]) / max(float(np.linalg.norm(B.T @ d[:-1])), 1e-300)
    record = Bifurcation(multiplicity=1, kernel=kernel[None, :], directions=d_z[None, :], traced=traced,
                         kind="pitchfork", labels=[f"{bif.labels[branch] if bif.labels else ''}; traced in the "
                                                  f"fixed space of {order} symmetries ({B.shape[1]} unknowns)"])
    bp_z = SpecialPoint("branch_point", bp.p, B.T @ u, dict(bp.observables), residual=bp.residual, located=True,
                        info={"bracket_p": bp.info.get("bracket_p")}, bifurcation=record)
    known_z = [SpecialPoint("branch_point", k.p, B.T @ np.asarray(k.u, dtype=float), located=True)
               for k in known if k.kind == "branch_point"]
    return sub, bp_z, known_z


def _to_full_space(problem: Problem, sub: FixedSpaceProblem, br: Branch, settings: Settings | None,
                   overrides: dict[str, Any]) -> Branch:
    """A branch traced in a fixed-point space, in the full problem's unknowns (and stability, when asked)."""
    B = sub.B
    br.u = np.asarray(br.u) @ B.T if len(br.u) else np.zeros((0, B.shape[0]))
    for spt in br.special_points:
        spt.u = B @ np.asarray(spt.u, dtype=float)
        if spt.bifurcation is not None:
            rec = spt.bifurcation
            rec.kernel = rec.kernel @ B.T
            rec.directions = np.column_stack([rec.directions[:, :-1] @ B.T, rec.directions[:, -1]]) \
                if len(rec.directions) else np.zeros((0, B.shape[0] + 1))
            if rec.traced is not None:
                rec.traced = np.concatenate([B @ rec.traced[:-1], rec.traced[-1:]])
    names = {f.name for f in fields(Settings)}
    st = resolve_settings(settings, {k: v for k, v in overrides.items() if k in names})
    if st.stability and len(br.p):
        # the stability the structure has: against every mode, not only those of the branch's symmetry
        full = full_space_stability(problem, br.u, br.p, st.n_eigs)
        br.stability_by = full.by_label
        br.n_negative, br.eigenvalues = next(iter(full.by_label.values()))
        if full.neutral.any():
            br.meta["neutral_modes"] = int(full.neutral.max())
        _report_symmetry_breaking(br, problem)
    br.meta["fixed_space"] = {"unknowns": int(B.shape[1]), "of": int(B.shape[0]), "problem": sub.name}
    return br


def _report_symmetry_breaking(br: Branch, problem: Problem) -> None:
    """Bracket every change of the full space's Morse index that no point found in the fixed space explains.

    In its fixed-point space a branch cannot see the bifurcations that break its own symmetry; they
    change the index against the other modes.  Each such change is reported as an unlocated branch
    point between the two stored points (``info["breaks_symmetry"]``), never passed in silence.
    """
    n = np.asarray(br.n_negative)
    explained = {spt.index for spt in br.special_points if spt.kind in ("fold", "branch_point")}
    added = []
    for i in np.nonzero(np.diff(n))[0]:
        if int(i) in explained:
            continue
        added.append(SpecialPoint(
            "branch_point", float(br.p[i + 1]), np.asarray(br.u[i + 1], dtype=float).copy(),
            {name: float(values[i + 1]) for name, values in br.observables.items()}, located=False,
            s=float(br.s[i + 1]), index=int(i), label="breaks the branch's symmetry",
            info={"bracket_p": [float(br.p[i]), float(br.p[i + 1])], "breaks_symmetry": True,
                  "n_negative_before": int(n[i]), "n_negative_after": int(n[i + 1])}))
    if added:
        br.special_points = sorted([*br.special_points, *added], key=lambda spt: (spt.index, spt.s))
        where = ", ".join(f"{problem.parameter_name} = {spt.info['bracket_p'][0]:.8g} .. {spt.p:.8g}" for spt in added)
        br.message = (f"{br.message}; the index against modes outside the branch's symmetry changes at {where} "
                      "(bifurcations that break its symmetry, bracketed, not located)")


def branch_point_scales(u: np.ndarray, p: float, *directions: Any,
                        reference: tuple[float, float] | None = None,
                        koiter: Mapping[str, float] | None = None,
                        bracket: Sequence[float] | None = None) -> tuple[float, float]:
    """State and parameter scales ``(U, P)`` at a branch point, as :func:`contin.path.scales.start_scales` at a start.

    The Jacobian is singular there, so the sensitivity ``S = rms(x_u) / |x_p|`` comes from the
    branches' own directions ``x = (x_u, x_p)`` (the traced branch's tangent and the bifurcating
    direction; None and those with ``x_p = 0`` say nothing), the largest of them; the rest is
    :func:`contin.path.scales.start_scales` (``reference``: the problem's scales from an earlier run).
    Without a reference, a load below ``1e-8`` of the ``bracket`` (the loads of the step that found
    the point) is zero, as it is below ``1e-8`` of a reference.  A pitchfork's branch leaves with
    ``x_p = 0`` and changes the load only at second order: with the point's ``koiter`` coefficients
    (:attr:`contin.Bifurcation.koiter`) ``P`` is at least the load change of the emanating branch
    over the state scale ``U`` (:func:`contin.path.scales.emanating_load_change`).  Either keeps a
    point located at a roundoff-small load from making every step of the new branch as small.
    """
    n = u.size
    sens = 0.0
    for x in directions:
        if x is None:
            continue
        x = np.asarray(x, dtype=float)
        if x.size == n + 1 and np.isfinite(x).all() and x[n] != 0.0:
            sens = max(sens, float(np.sqrt(np.mean(x[:n] ** 2))) / abs(float(x[n])))
    if reference is None and bracket is not None and abs(p) <= ZERO_SCALE * abs(float(bracket[1]) - float(bracket[0])):
        p = 0.0
    U, P = scales_from_sensitivity(u, p, sens, reference)
    return U, max(P, emanating_load_change(koiter or {}, U, n))


def _unit(curve: Curve, x: np.ndarray, n: int) -> np.ndarray:
    """``x = (x_u, x_p)`` normalised in the curve's arclength norm."""
    nrm = curve.norm(x[:n], float(x[n]))
    if not (np.isfinite(nrm) and nrm > 0):
        raise ValueError("switch_branch: the stored bifurcation direction is zero or not finite")
    return x / nrm


def _off_branch_normal(curve: Curve, d: np.ndarray, traced: Any, n: int) -> np.ndarray:
    """Unit normal of the step-off hyperplane: ``d`` without its component along the traced branch."""
    if traced is None:
        return d
    t = _unit(curve, np.asarray(traced, dtype=float), n)
    normal = d - curve.inner(d[:n], d[n], t[:n], t[n]) * t
    nrm = curve.norm(normal[:n], normal[n])
    # d (nearly) along the traced branch: the hyperplane normal to d itself is the best left
    return normal / nrm if nrm > 1e-3 else d


def _step_off(curve: Curve, u: np.ndarray, p: float, d: np.ndarray, normal: np.ndarray, step: float,
              attempts: int = 40) -> Correction:
    """First point of the new branch, on ``<normal, X - X*> = step`` from ``X* + step d / <normal, d>``.

    The step is halved on failure, as often as it takes: in a norm that weights one direction
    heavily the new branch is strongly curved, and only a short first step stays near the predictor.
    """
    n = u.size
    origin = Point(u, p, normal[:n], float(normal[n]), 0.0, 0)
    along = curve.inner(normal[:n], normal[n], d[:n], d[n])
    last: Exception | None = None
    for _ in range(attempts):
        reach = step / along
        try:
            return correct(curve, origin, step, start=(u + reach * d[:n], p + reach * float(d[n])))
        except CorrectorFailure as exc:
            last, step = exc, step * 0.5
    raise CorrectorFailure(f"could not step onto the bifurcating branch: {last}")


def _name_the_meeting(br: Branch, problem: Problem) -> None:
    """Status and message of a switched branch that ended on a branch point it already knew."""
    if br.status != "event" or not br.special_points:
        return
    last = br.special_points[-1]
    label = last.info.get("known_as") if last.kind == "branch_point" else None
    if label is None:
        return
    found = f"found on this branch at {problem.parameter_name} = {last.info.get('met_at_p', last.p):.10g}"
    if label == "origin":
        br.status = "closed_loop"
        br.message = (f"closed loop: returned to the branch point it started from "
                      f"({problem.parameter_name} = {last.p:.10g}; {found})")
    else:
        br.status = "reached_branch_point"
        br.message = f"reached the known {label} ({found})"
