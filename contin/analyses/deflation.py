"""Deflation: solutions at one parameter value that no traced branch leads to.

Continuation follows the branch it starts on.  A branch that no traced branch meets (an isola, or a
branch whose connection lies outside the traced range) is found by solving ``f(u, p) = 0`` at a fixed
``p`` once more, with the solutions already known *deflated*: Newton's method runs on

    g(u) = M(u) f(u),        M(u) = prod_r m(u; r),        m(u; r) = 1 / d(u, r)^q + sigma,

one factor per known solution ``r``.  Where ``f`` has a simple root at ``r`` it vanishes like
``d(u, r)``, while ``m`` grows like ``d^-q``: for ``q > 1`` the known root is no root of ``g``, and every
other root of ``f`` still is (Farrell, Birkisson & Funke, "Deflation techniques for finding distinct
solutions of nonlinear partial differential equations", SIAM J. Sci. Comput. 37 (2015); its use
beside continuation: Farrell, Beentjes & Birkisson, "The computation of disconnected bifurcation
diagrams", arXiv:1603.00809 (2016)).

The Newton step of ``g`` needs nothing but the model's own factorization of ``J = df/du``.  ``g``'s
Jacobian ``M J + f (grad M)^T`` is ``M`` times ``J`` plus a rank-one term, so by the Sherman-Morrison
formula its step is the undeflated Newton step ``delta = -J^{-1} f`` scaled,

    step = delta / (1 - w . delta),        w = grad log M = sum_r grad log m(u; r),

one solve with the factorization the model gives (banded, sparse), never a dense matrix.

The distance ``d`` is the continuation's own state metric (:meth:`contin.path.curve.Curve.norm`: the
root-mean-square of the state over its scale ``U``), so a model in other units deflates alike.
The defaults of :class:`DeflationSettings`:

* ``q = 2``: near a known root ``|g|`` grows like ``1 / d``.  With ``q = 1`` it would stay bounded
  there, and a line search on ``|g|`` could still creep towards the known root.  Next to it the
  deflated step is Newton's reversed (``delta / (1 - q)``): the pull of the known root becomes a
  push away from it of the same size.
* ``sigma = 1``: without a shift ``M`` tends to zero far from every known root, and ``|g|`` can be
  made small by running away; Newton would "converge" to infinity.  With the shift ``M >= sigma``
  there, and the step tends to Newton's own.  In the state metric ``d = 1`` is the state's own
  scale, so ``sigma = 1`` puts the change from "pushed away" (``d^-q > sigma``) to "plain Newton" at
  one state scale from each known solution, in any units.

An attempt converges when the *undeflated* residual meets the continuation's tolerance, with the
same test Newton at a fixed parameter uses (:meth:`~contin.path.curve.Curve.converged_at_fixed_p`:
``max|f| <= tol * residual_scale`` and a last update below ``xtol``); the solution found must lie
farther than ``rtol`` from every known one.  Each attempt is reported: converged, diverged (with
why), or returned to a known solution.  :func:`deflated_branches` traces what deflation finds with
:func:`contin.continuation`, in both directions, and recognises a solution that lies on a branch it
already has.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..numerics.linalg import SingularMatrixError
from ..palc import continuation
from ..path.curve import CorrectorFailure, Curve, max_abs
from ..problem import NonFiniteError, Problem
from ..results.branch import Branch
from ..settings import Settings, SettingsError, resolve_settings
from ..watch.events import Event
from ..watch.testfunctions import smallest_eigenvectors

__all__ = ["DeflationSettings", "DeflationOperator", "DeflationAttempt", "DeflationResult", "DeflatedBranches",
           "deflate", "deflated_branches", "deflation_curve", "default_starts", "branch_states_at"]

#: What makes a linearization or an evaluation unusable: the attempt ends as diverged, never raises.
EVALUATION_FAILURES = (NonFiniteError, SingularMatrixError, np.linalg.LinAlgError, CorrectorFailure)

#: Sufficient decrease of the deflated residual asked of a damped step (Armijo's constant).
ARMIJO = 1e-4

#: Half-opening of the cone ahead of a traced branch's start, as a slope: the path has come back
#: round to its start when it enters the cone ``a > CONE * b`` (``a`` the distance along the start
#: tangent, ``b`` the distance from the tangent's line).  A step that turns the tangent by less than
#: ``2 / CONE`` radians ends inside it, and the continuation's guard refuses turns above
#: ``acos(min_tangent_cos)`` (0.45 rad by default).
CONE = 4.0


@dataclass(frozen=True)
class DeflationSettings:
    """Options of :func:`deflate` (the continuation's tolerances come from :class:`contin.Settings`).

    Attributes
    ----------
    power : float
        ``q`` of the deflation factor ``1 / d^q + sigma``; > 1 (at 1 a known root keeps ``|g|``
        bounded, see :mod:`contin.analyses.deflation`).
    shift : float
        ``sigma``; >= 0 (0 lets the deflated residual vanish at infinity).
    max_iter : int
        Deflated Newton iterations per attempt.
    min_damping : float
        Smallest fraction of a deflated Newton step the line search tries, in (0, 1].
    rtol : float
        Two states at the same parameter are one solution when their distance in the continuation's
        state metric (relative to the state's scale) is at most ``rtol``; a new solution must lie
        farther than that from every known one.
    push : float
        Distance (state metric) of the default starts from the known solution they leave.
    modes : int
        Default starts leave each known solution of a symmetric problem along this many softest
        modes of its Hessian (besides ``du/dp``), both ways.
    max_solutions : int
        Stop once this many new solutions have been found.
    """

    power: float = 2.0
    shift: float = 1.0
    max_iter: int = 100
    min_damping: float = 1e-4
    rtol: float = 1e-6
    push: float = 0.1
    modes: int = 2
    max_solutions: int = 20

    def validate(self) -> None:
        """Raise :class:`contin.SettingsError` naming the field and its range if one is out of range."""
        def need(cond: bool, name: str, rule: str) -> None:
            if not cond:
                raise SettingsError(f"deflation setting {name!r} = {getattr(self, name)!r} is invalid: {rule}")
        need(self.power > 1, "power", "must be > 1 (at 1 or below a known root is not removed)")
        need(self.shift >= 0, "shift", "must be >= 0")
        need(self.max_iter >= 1, "max_iter", "must be >= 1")
        need(0 < self.min_damping <= 1, "min_damping", "must lie in (0, 1]")
        need(0 < self.rtol < 1, "rtol", "must lie in (0, 1)")
        need(self.push > 0, "push", "must be > 0")
        need(self.modes >= 0, "modes", "must be >= 0")
        need(self.max_solutions >= 1, "max_solutions", "must be >= 1")


@dataclass
class DeflationAttempt:
    """One run of deflated Newton from one start.

    Attributes
    ----------
    start : int
        Index of the start in :attr:`DeflationResult.starts`.
    status : str
        ``"converged"`` (a new solution), ``"diverged"`` (no solution; :attr:`message` says why) or
        ``"known"`` (it came back to within ``rtol`` of a known solution).
    u : ndarray or None
        The solution (``"converged"``) or the state that met the known one (``"known"``); None otherwise.
    residual : float
        Max-norm of the undeflated residual at the last iterate (inf where it was not finite).
    iterations : int
        Deflated Newton iterations.
    factorizations : int
        Factorizations of the Jacobian: one per iteration, and one more for an attempt that ends
        where its line search fails.
    evaluations : int
        Residual evaluations (the line search's included).
    nearest : int or None
        Index, among the solutions deflated during the attempt (:attr:`DeflationResult.known`, then
        the new ones in the order found), of the one nearest the last iterate.
    distance : float
        Its distance in the state metric.
    message : str
    """

    start: int
    status: str
    u: np.ndarray | None
    residual: float
    iterations: int
    factorizations: int
    evaluations: int
    nearest: int | None
    distance: float
    message: str

    def __repr__(self) -> str:
        return (f"DeflationAttempt(start {self.start}: {self.status}, {self.iterations} iterations, "
                f"residual {self.residual:.2e}: {self.message})")


@dataclass
class DeflationResult:
    """What :func:`deflate` found at one parameter value.

    Attributes
    ----------
    p : float
    known : list of ndarray
        The solutions deflated from the start.
    solutions : list of ndarray
        The new solutions, in the order found; each meets the tolerance and lies farther than
        ``rtol`` from every known one and from the others.
    starts : list of ndarray
    attempts : list of DeflationAttempt
        Every attempt in order: a start is tried again, with the new solution deflated too, after
        each success, and left after its first failure.
    """

    p: float
    known: list[np.ndarray]
    solutions: list[np.ndarray]
    starts: list[np.ndarray]
    attempts: list[DeflationAttempt]

    @property
    def iterations(self) -> int:
        """Deflated Newton iterations over all attempts."""
        return sum(a.iterations for a in self.attempts)

    @property
    def factorizations(self) -> int:
        """Factorizations of the Jacobian over all attempts."""
        return sum(a.factorizations for a in self.attempts)

    @property
    def evaluations(self) -> int:
        """Residual evaluations over all attempts."""
        return sum(a.evaluations for a in self.attempts)

    def summary(self) -> str:
        """One line per attempt."""
        lines = [f"deflation at p = {self.p:.10g}: {len(self.solutions)} new solution(s) from {len(self.starts)} "
                 f"start(s), {self.iterations} iterations, {self.factorizations} factorizations, {self.evaluations} "
                 "residual evaluations"]
        lines += [f"  {attempt!r}" for attempt in self.attempts]
        return "\n".join(lines)


def deflation_curve(problem: Problem, p: float, reference: np.ndarray, settings: Settings) -> Curve:
    """The curve whose tolerance and state metric deflation uses, calibrated as a run from ``reference`` would be.

    Open arclength weights are measured at ``(reference, p)`` exactly as :func:`contin.continuation`
    measures them at its start (:meth:`contin.path.curve.Curve.calibrate`): the state metric and the
    absolute tolerance are then the continuation's own.
    """
    curve = Curve(problem, settings)
    if curve.needs_calibration():
        curve.calibrate(np.asarray(reference, dtype=float), float(p))
    return curve


def deflate(problem: Problem, p: float, known_states: Sequence[Any], *, starts: Sequence[Any] | None = None,
            settings: Settings | None = None, deflation: DeflationSettings | None = None,
            **overrides: Any) -> DeflationResult:
    """Solutions of ``f(u, p) = 0`` at a fixed ``p`` other than ``known_states``, by deflated Newton.

    Parameters
    ----------
    problem : Problem
    p : float
        The parameter value.
    known_states : sequence of array_like
        Solutions already known at ``p`` (e.g. where traced branches cross it, see
        :func:`branch_states_at`); they are deflated, and so is every solution found.
    starts : sequence of array_like, optional
        Initial guesses.  By default each known state pushed by ``push`` (state metric) both ways
        along ``du/dp`` (where ``df/dp`` is not zero) and, for a symmetric problem, along the
        ``modes`` eigenvectors of the Jacobian of smallest ``|eigenvalue|``.
    settings : Settings, optional
        The continuation's settings: ``tol``, ``xtol`` and the arclength weights (fields may also be
        given as keywords).
    deflation : DeflationSettings, optional

    Returns
    -------
    DeflationResult
        The new solutions and a record of every attempt; nothing raises for an attempt that fails.

    Raises
    ------
    ValueError
        A state of the wrong size or not finite, or no start to try.
    contin.SettingsError
        A setting out of its range.
    """
    st = resolve_settings(settings, overrides)
    dst = deflation or DeflationSettings()
    dst.validate()
    p = float(p)
    known = _states(problem, known_states, "deflate", "known_states")
    given = None if starts is None else _states(problem, starts, "deflate", "starts", size=_size(known))
    reference = known[0] if known else (given[0] if given else None)
    if reference is None:
        raise ValueError("deflate: nothing to start from: give known_states (the default starts leave them) "
                         "or starts")
    return _deflate(deflation_curve(problem, p, reference, st), p, known, given, dst)


def _deflate(curve: Curve, p: float, known: list[np.ndarray], starts: list[np.ndarray] | None,
             dst: DeflationSettings) -> DeflationResult:
    """:func:`deflate` on a curve already calibrated (its metric and tolerance are the ones used)."""
    start_list = starts if starts is not None else default_starts(curve, p, known, dst)
    if not start_list and not known:
        raise ValueError("deflate: no known state at this parameter to push the default starts off: give starts")
    if not start_list:
        raise ValueError("deflate: the known states give no default start (df/dp = 0 there and the problem is "
                         "not symmetric, or modes = 0): give starts")
    deflated = [u.copy() for u in known]
    solutions: list[np.ndarray] = []
    attempts: list[DeflationAttempt] = []
    for index, start in enumerate(start_list):
        while len(solutions) < dst.max_solutions:
            attempt = _deflated_newton(curve, p, start, deflated, dst, index)
            attempts.append(attempt)
            if attempt.status != "converged":
                break
            solutions.append(attempt.u)
            deflated.append(attempt.u)
    return DeflationResult(p, known, solutions, start_list, attempts)


def _size(known: list[np.ndarray]) -> int | None:
    return known[0].size if known else None


def _states(problem: Problem, states: Sequence[Any], caller: str, name: str,
            size: int | None = None) -> list[np.ndarray]:
    """The states as float vectors of one size, each finite (ValueError naming ``caller`` and ``name`` otherwise)."""
    out = [np.array(u, dtype=float).ravel() for u in states]
    for k, u in enumerate(out):
        expected = size if size is not None else out[0].size
        if u.size != expected:
            raise ValueError(f"{caller}: {name}[{k}] has {u.size} entries, the states of {problem.name!r} here "
                             f"have {expected}")
        if not np.isfinite(u).all():
            raise ValueError(f"{caller}: {name}[{k}] is not finite")
    return out


def default_starts(curve: Curve, p: float, known: list[np.ndarray], dst: DeflationSettings) -> list[np.ndarray]:
    """Each known state pushed ``dst.push`` (state metric) both ways along ``du/dp`` and its softest modes.

    ``du/dp = -J^{-1} df/dp`` leads along the branch the state lies on, towards where it may fold
    back (the other half of Bratu's branch); a soft mode of a symmetric problem leads towards the
    solutions a symmetry-breaking branch would carry (the pitchfork's).  Directions that are zero or
    cannot be computed (a singular Jacobian) are left out.
    """
    problem = curve.problem
    starts = []
    for r in known:
        directions = []
        try:
            J, fp, F = curve.linearize(r, p)
            if F is not None and max_abs(fp) > 0:
                directions.append(-F.solve(fp))
            if problem.symmetric and dst.modes:
                directions += smallest_eigenvectors(problem, r, p, dst.modes)
        except EVALUATION_FAILURES + (ValueError, RuntimeError):
            pass
        for v in directions:
            size = curve.norm(v, 0.0)
            if np.isfinite(size) and size > 0:
                starts += [r + dst.push / size * v, r - dst.push / size * v]
    return starts


class DeflationOperator:
    """The deflation factor ``M(u) = prod_r (1 / d(u, r)^q + sigma)`` of known states, and its Newton step.

    Parameters
    ----------
    curve : Curve
        Its state metric measures ``d`` (:meth:`contin.path.curve.Curve.norm` of ``u - r``).
    known : list of ndarray
        The known states ``r``.
    power, shift : float
        ``q`` and ``sigma`` (see :class:`DeflationSettings`).
    """

    def __init__(self, curve: Curve, known: list[np.ndarray], power: float = 2.0, shift: float = 1.0) -> None:
        self.curve, self.known, self.q, self.sigma = curve, known, float(power), float(shift)

    def distances(self, u: np.ndarray) -> np.ndarray:
        """Distances of ``u`` from every known state, in the state metric."""
        return np.array([self.curve.norm(u - r, 0.0) for r in self.known])

    def log_factor(self, d: np.ndarray) -> float:
        """``log M`` from the distances :meth:`distances` gives (inf at a known state)."""
        with np.errstate(divide="ignore"):
            return float(np.sum(np.log(d ** -self.q + self.sigma)))

    def gradient(self, u: np.ndarray, d: np.ndarray) -> np.ndarray:
        """``grad log M = -q sum_r w (u - r) / (d^2 (1 + sigma d^q))`` (``w`` the metric's weight of ``|u|^2``)."""
        w = self.curve.weights(u.size)[0]
        g = np.zeros_like(u)
        for r, dr in zip(self.known, d):
            g -= self.q * w * (u - r) / (dr * dr * (1.0 + self.sigma * dr ** self.q))
        return g

    def step(self, u: np.ndarray, f: np.ndarray, factorization: Any) -> np.ndarray:
        """Newton's step for ``M f = 0`` at ``u`` from a factorization of ``J(u)``: one solve.

        ``(M J + f grad M^T) x = -M f`` is, divided by ``M``, ``(J + f w^T) x = -f`` with
        ``w = grad log M``; by Sherman-Morrison ``x = delta / (1 - w . delta)``, ``delta = -J^{-1} f``.
        Not finite where ``w . delta = 1`` (the deflated residual has a critical point there).
        """
        delta = -factorization.solve(f)
        if not self.known:
            return delta
        with np.errstate(divide="ignore", invalid="ignore"):
            return delta / (1.0 - float(self.gradient(u, self.distances(u)) @ delta))


def _deflated_newton(curve: Curve, p: float, start: np.ndarray, known: list[np.ndarray],
                     dst: DeflationSettings, index: int) -> DeflationAttempt:
    """Deflated Newton from ``start`` at ``p`` with ``known`` deflated (see the module's docstring)."""
    problem = curve.problem
    deflator = DeflationOperator(curve, known, dst.power, dst.shift)
    u = start.copy()
    factorizations, evaluations_before = 0, curve.n_evals

    def attempt(status: str, message: str, res: float, it: int, state: np.ndarray | None = None) -> DeflationAttempt:
        d = deflator.distances(u) if known and np.isfinite(u).all() else np.zeros(0)
        nearest = int(np.argmin(d)) if d.size else None
        return DeflationAttempt(index, status, state, res, it, factorizations, curve.n_evals - evaluations_before,
                                nearest,
                                float(d[nearest]) if nearest is not None else math.inf, message)

    try:
        f = curve.residual(u, p)
    except NonFiniteError as exc:
        return attempt("diverged", f"the residual is not finite at the start ({exc})", math.inf, 0)
    d = deflator.distances(u)
    if d.size and d.min() <= dst.rtol:
        return attempt("known", "the start is a known solution", max_abs(f), 0, u.copy())
    res, step_norm = max_abs(f), math.inf
    for it in range(dst.max_iter + 1):
        if curve.converged_at_fixed_p(u, res, step_norm):
            return attempt("converged", f"converged in {it} iterations (residual {res:.2e})", res, it, u.copy())
        if it == dst.max_iter:
            break
        try:
            J = problem.checked_jacobian(u, p)
            factorizations += 1
            step = deflator.step(u, f, problem.factorize(J))
        except EVALUATION_FAILURES + (RuntimeError,) as exc:
            return attempt("diverged", f"no Newton step at iteration {it} ({type(exc).__name__}: {exc})", res, it)
        if not np.isfinite(step).all():
            return attempt("diverged", f"the deflated Newton step is not finite at iteration {it}", res, it)
        if curve.converged_at_fixed_p(u, res, curve.norm(step, 0.0)):
            # the update left is below xtol and the residual near its rounding noise, which the line
            # search could not lower: the full update is the last one, as it is for Newton at fixed p
            last = _evaluate(curve, u + step, p)
            if last is not None and max_abs(last) <= curve.tol:
                u, res = u + step, max_abs(last)
            return attempt("converged", f"converged in {it + 1} iterations (residual {res:.2e})", res, it + 1,
                           u.copy())
        taken = _line_search(curve, deflator, u, p, f, d, step, dst.min_damping)
        if taken is None:
            return attempt("diverged", f"no fraction of the deflated Newton step down to {dst.min_damping:g} lowers "
                           f"|M f| at iteration {it}", res, it)
        lam, u, f, d = taken
        res, step_norm = max_abs(f), lam * curve.norm(step, 0.0)
        if d.size and d.min() <= dst.rtol:
            return attempt("known", f"returned to known solution {int(np.argmin(d))} at iteration {it + 1}",
                           res, it + 1, u.copy())
    return attempt("diverged", f"no convergence in {dst.max_iter} iterations (residual {res:.2e}, tol "
                   f"{curve.tol:.1e})", res, dst.max_iter)


def _line_search(curve: Curve, deflator: DeflationOperator, u: np.ndarray, p: float, f: np.ndarray, d: np.ndarray,
                 step: np.ndarray, min_damping: float) -> tuple[float, np.ndarray, np.ndarray, np.ndarray] | None:
    """Halve the fraction of ``step`` until ``|M f|`` (2-norm) falls by Armijo's measure: ``(lam, u, f, d)``.

    The deflated step is a Newton step of ``g = M f`` (Sherman-Morrison is exact), so it descends
    ``|g|`` and a small enough fraction lowers it.  The comparison is in logarithms (``M`` overflows
    next to a known state), never outside the model's domain (:meth:`contin.Problem.max_step_fraction`).
    A fraction whose residual is not finite counts as no decrease.  None when no fraction down to
    ``min_damping`` lowers ``|g|``.
    """
    log_g = deflator.log_factor(d) + _log_norm(f)
    lam = min(1.0, curve.problem.max_step_fraction(u, p, step, 0.0))
    while lam >= min_damping:
        trial = u + lam * step
        f_trial = _evaluate(curve, trial, p)
        if f_trial is None:
            lam *= 0.5
            continue
        d_trial = deflator.distances(trial)
        if deflator.log_factor(d_trial) + _log_norm(f_trial) <= log_g + math.log1p(-ARMIJO * lam):
            return lam, trial, f_trial, d_trial
        lam *= 0.5
    return None


def _evaluate(curve: Curve, u: np.ndarray, p: float) -> np.ndarray | None:
    """The residual at ``u``, or None where it is not finite."""
    try:
        return curve.residual(u, p)
    except NonFiniteError:
        return None


def _log_norm(f: np.ndarray) -> float:
    """``log |f|`` (2-norm) without overflow: a residual far from its roots may have entries near the largest float."""
    size = max_abs(f)
    if size == 0.0:
        return -math.inf
    return math.log(size) + math.log(float(np.linalg.norm(f / size)))


# ---- branches through what deflation finds ------------------------------------------------------------

def branch_states_at(curve: Curve, branch: Branch, p: float) -> list[np.ndarray]:
    """The states of a traced branch at the parameter ``p``: one per stored step across ``p``, converged there.

    Each is Newton at fixed ``p`` (:meth:`contin.path.curve.Curve.newton_fixed_p`) from the linear
    interpolant of the step's two stored states; states within the curve's ``xtol`` of one already
    listed, and steps whose correction fails, are left out.

    Raises
    ------
    ValueError
        The branch kept no states (traced with ``store_states=False``).
    """
    if branch.u.shape[0] != len(branch):
        raise ValueError("branch_states_at: the branch kept no states (traced with store_states=False)")
    states: list[np.ndarray] = []
    P = np.asarray(branch.p, dtype=float)
    for i in range(len(branch) - 1):
        a, b = P[i] - p, P[i + 1] - p
        if a * b > 0 or (a == 0.0 and i > 0):  # a stored point at p is met once, by the step it starts
            continue
        t = 0.0 if a == b else a / (a - b)
        guess = (1.0 - t) * branch.u[i] + t * branch.u[i + 1]
        try:
            u, _, _ = curve.newton_fixed_p(guess, p)
        except EVALUATION_FAILURES:
            continue
        if not any(curve.norm(u - v, 0.0) <= curve.settings.xtol * (1.0 + curve.norm(v, 0.0)) for v in states):
            states.append(u)
    return states


@dataclass
class DeflatedBranches:
    """What :func:`deflated_branches` found and traced.

    Attributes
    ----------
    p : float
    deflation : DeflationResult
        The deflated Newton attempts; its ``known`` are the given states and those of the given
        branches at ``p``.
    branches : list of Branch
        The new branches: from each traced solution the run along its tangent (oriented like
        ``J t_u = -df/dp t_p`` with ``t_p > 0``), then the run the other way, or the first run alone
        when it closed on itself (status ``"closed_loop"``).  ``meta["deflation"]`` names the solution each started from.
    traced : list of int
        The indices (in ``deflation.solutions``) of the solutions traced.
    same_as : dict of int to int
        Solutions not traced because they lie on the branch of an earlier one: solution -> that one.
    """

    p: float
    deflation: DeflationResult
    branches: list[Branch] = field(default_factory=list)
    traced: list[int] = field(default_factory=list)
    same_as: dict[int, int] = field(default_factory=dict)


def deflated_branches(problem: Problem, p: float, branches: Sequence[Branch] = (),
                      known_states: Sequence[Any] = (), *, starts: Sequence[Any] | None = None,
                      settings: Settings | None = None, deflation: DeflationSettings | None = None,
                      events: Sequence[Event] = (), **overrides: Any) -> DeflatedBranches:
    """Branches through the solutions at ``p`` that the given branches do not reach, traced both ways.

    The states of ``branches`` at ``p`` (:func:`branch_states_at`) and ``known_states`` are deflated
    (:func:`deflate`); each new solution is traced with :func:`contin.continuation` from its tangent,
    then the other way, unless the first run came back round to its start: that run ends there
    with status ``"closed_loop"`` (a success).  A solution that lies on a branch traced here before
    it (the same state at ``p`` within ``rtol``: the second point where an isola crosses ``p``) is
    not traced again.  The branches returned go to :func:`contin.diagram` with the others.

    Parameters
    ----------
    problem : Problem
    p : float
    branches : sequence of Branch
        Branches already traced (with their states stored).
    known_states : sequence of array_like
        Further known solutions at ``p``.
    starts : sequence of array_like, optional
        Initial guesses of the deflated Newton (see :func:`deflate`).
    settings : Settings, optional
        Settings of the deflation's tolerances and of every run (fields may also be keywords: give
        the runs their bounds, ``p_min``, ``p_max``).
    deflation : DeflationSettings, optional
    events : sequence of Event
        User events of every run.

    Returns
    -------
    DeflatedBranches
    """
    st = resolve_settings(settings, overrides)
    dst = deflation or DeflationSettings()
    dst.validate()
    p = float(p)
    given = _states(problem, known_states, "deflated_branches", "known_states")
    trial = None if starts is None else _states(problem, starts, "deflated_branches", "starts",
                                                size=_size(given))
    reference = given[0] if given else _nearest_stored(branches, p)
    if reference is None and trial:
        reference = trial[0]
    if reference is None:
        raise ValueError("deflated_branches: nothing to start from: give branches that store states, "
                         "known_states or starts")
    curve = deflation_curve(problem, p, reference, st)
    known: list[np.ndarray] = []
    for u in given + [v for br in branches for v in branch_states_at(curve, br, p)]:
        if all(curve.norm(u - v, 0.0) > dst.rtol for v in known):  # a state two branches share, once
            known.append(u)
    if known:  # measured where deflate would measure it: the first known state
        curve = deflation_curve(problem, p, known[0], st)
    result = DeflatedBranches(p, _deflate(curve, p, known, trial, dst))
    found = result.deflation
    for k, u in enumerate(found.solutions):
        owner = _owner(curve, result, p, u, dst.rtol)
        if owner is not None:
            result.same_as[k] = owner
            continue
        result.traced.append(k)
        for br in _trace_both_ways(problem, p, u, st, events, dst.rtol):
            br.meta["deflation"] = {"p": p, "solution": k}
            result.branches.append(br)
    return result


def _nearest_stored(branches: Sequence[Branch], p: float) -> np.ndarray | None:
    """The stored state of the branches whose parameter is nearest ``p`` (None without stored states)."""
    best = None
    for br in branches:
        if len(br) and br.u.shape[0] == len(br):
            i = int(np.argmin(np.abs(np.asarray(br.p) - p)))
            if best is None or abs(br.p[i] - p) < best[0]:
                best = (abs(br.p[i] - p), np.array(br.u[i], dtype=float))
    return None if best is None else best[1]


def _owner(curve: Curve, result: DeflatedBranches, p: float, u: np.ndarray, rtol: float) -> int | None:
    """The traced solution on whose branches ``u`` lies at ``p`` (within ``rtol``), or None."""
    for br in result.branches:
        if any(curve.norm(u - v, 0.0) <= rtol for v in branch_states_at(curve, br, p)):
            return int(br.meta["deflation"]["solution"])
    return None


def _trace_both_ways(problem: Problem, p: float, u: np.ndarray, st: Settings, events: Sequence[Event],
                     rtol: float) -> list[Branch]:
    """The branch through the solution ``(u, p)``: along its tangent, then back unless the first run closed."""
    # the run's own metric: a fresh curve calibrated at its start, as continuation calibrates it
    curve = deflation_curve(problem, p, u, st)
    lin = curve.linearize(u, p)
    _, fp, F = lin
    guess = -F.solve(fp) if F is not None else np.zeros(u.size)
    t_u, t_p, _ = curve.tangent(u, p, guess, 1.0, lin=lin)
    out = []
    for sign in (1.0, -1.0):
        back = _return_to_start(curve, u, p, sign * t_u, sign * t_p)
        # the start is deflation's converged solution, in this run's tolerance: correcting it again
        # would move it off the point the return test is measured from
        br = continuation(problem, u, p, st, events=[*events, back], tangent=(sign * t_u, sign * t_p),
                          correct_start=False)
        out.append(br)
        if _closed(curve, br, back, u, p, rtol):
            break
    return out


def _return_to_start(curve: Curve, u0: np.ndarray, p0: float, t_u: np.ndarray, t_p: float) -> Event:
    """A terminal event where the path comes back through its start ``(u0, p0)`` along the unit tangent ``t``.

    Its function is ``a - CONE * b``: ``a`` the distance along ``t`` from the start, ``b`` the
    distance from the tangent's line (the run's own metric).  It is zero at the start, positive in a
    narrow cone ahead of it, negative elsewhere; the path leaves the start into the cone and out of
    it (a fall, which does not trigger), and crosses upwards only where it passes through the start
    again, coming from behind.
    """
    def ahead(u: np.ndarray, p: float) -> float:
        du, dp = u - u0, p - p0
        a = curve.inner(t_u, t_p, du, dp)
        return a - CONE * curve.norm(du - a * t_u, dp - a * t_p)
    return Event(ahead, 0.0, direction=+1, terminal=True, name="return to start")


def _closed(curve: Curve, br: Branch, back: Event, u0: np.ndarray, p0: float, rtol: float) -> bool:
    """Whether ``br`` ended on its return to its start; names it ``"closed_loop"`` if so."""
    last = br.special_points[-1] if br.special_points else None
    if br.status != "event" or last is None or last.label != back.name:
        return False
    gap = curve.norm(np.asarray(last.u) - u0, last.p - p0)
    if gap > rtol * (1.0 + curve.norm(u0, p0)):
        br.message += (f"; it entered the cone ahead of its start {gap:.2e} away from the start without "
                       "passing through it: not a closed loop")
        return False
    br.status = "closed_loop"
    br.message = (f"closed loop: came back round to its start ({curve.problem.parameter_name} = {p0:.10g}) "
                  f"after arclength {float(br.s[-1]):.6g}")
    return True
