"""Pseudo-arclength continuation (PALC) with fold, branch-point and event detection and location.

The core traces the solution curve of ``f(u, p) = 0`` in the augmented space ``X = (u, p)``.
Each step predicts along the unit tangent and corrects with Newton on the bordered system

    [ J      f_p    ] [du]     [ f                      ]
    [ w t_u  w_p t_p] [dp] = - [ <t, X - X0>_W - ds     ]

solved by block elimination on the model's factorization of ``J`` (see :mod:`contin.linalg`).
The arclength norm is ``||X||_W^2 = w_u^2 |u|^2 / n + w_p^2 p^2``: the state enters through its
root-mean-square, so the number of steps does not grow with the number of unknowns.

Test functions evaluated at every accepted point:

* fold: the parameter component of the tangent changes sign; located by Newton on the minimally
  augmented system ``f = 0, g = 0`` (``g`` from the bordered Jacobian);
* simple branch point: the determinant of the bordered Jacobian changes sign (sign and log-modulus
  come from the factorization, so nothing overflows); located as a root of a continuous bordered
  test function on the curve;
* events: a user observable crossing a value, or its derivative along the path changing sign.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from .branch import Branch, SpecialPoint
from .events import Event
from .linalg import BorderedSolver, SingularMatrixError
from .problem import NonFiniteError, Problem
from .stability import stability_info

__all__ = ["Settings", "continuation", "locate_fold", "switch_branch", "CorrectorFailure", "Curve", "Point"]


@dataclass
class Settings:
    """Options of :func:`continuation` (every field can also be passed as a keyword).

    Attributes
    ----------
    ds, ds_min, ds_max : float
        Initial, minimum and maximum step in the weighted arclength norm.
    max_steps : int
        Maximum number of accepted steps.
    direction : int
        +1 to start with increasing parameter, -1 decreasing.
    p_min, p_max : float
        Parameter bounds; the run stops exactly on a bound (located like an event).
    bounds : dict
        Observable bounds ``{name: (low, high)}`` (either may be None); the run stops exactly on them.
    tol : float
        Relative residual tolerance: a stored point has ``max|f| <= tol * problem.residual_scale``.
    xtol : float
        Newton-update tolerance: a point is accepted only once its estimated error (the last
        corrector update, times the observed contraction rate once there is one) is below
        ``xtol * (1 + ||X||)`` in the arclength norm.  Both tests must hold: in ill-conditioned
        discretizations a small residual alone does not pin the solution down.
    max_newton : int
        Corrector iterations before a step is declared failed.
    fast_newton : int
        The step grows when the corrector needed at most this many iterations.
    target_contraction : float
        Step-size control by the corrector's first contraction rate ``theta = |dX_2| / |dX_1|``:
        the next step is scaled by ``sqrt(target_contraction / theta)`` (within ``shrink`` and
        ``grow``), since ``theta`` grows like the step for a Newton corrector.  Steps that sit at
        the rate where the corrector starts to fail are avoided instead of repeatedly retried.
    grow, shrink : float
        Step-size factors after an easy step and after a failed one.
    state_weight, param_weight : float
        Weights of the state (RMS) and parameter parts of the arclength norm.
    max_correction : float
        Guard against branch jumping: the corrector may move at most this multiple of the step away
        from the predicted point.
    max_contraction : float
        Guard against branch jumping: from the second corrector iteration on, each Newton update
        must be at most this fraction of the previous one; a slowly contracting corrector started
        between branches and may end on the wrong one, so the step is retried smaller.
    min_tangent_cos : float
        Guard against branch jumping: consecutive unit tangents must have at least this cosine.
    target_angle : float
        Curvature control: the next step is scaled so that the tangent turns by about this angle
        (radians) per step, keeping the predictor error small compared with the local curvature.
    detect_folds, detect_branch_points, locate : bool
        Which test functions run, and whether special points are located (else only bracketed).
    stability : bool
        Compute the stability operator's inertia and smallest eigenvalues at every point.
    n_eigs : int
        Number of smallest eigenvalues stored per point.  0 stores only the Morse index, which for
        a sparse (banded) operator costs one pivot-free factorization per point, O(n), instead of
        a banded eigensolve, O(n^2 b).
    locate_tol : float
        Relative tolerance of the arclength root-finding that locates events and branch points.
    store_states : bool
        Keep every state vector (False keeps only the special points' states and the last one).
    stop_at : tuple of str
        Special point kinds (``"fold"``, ``"branch_point"``) that end the run; the run then ends
        exactly on the first located one (e.g. load until the structure snaps).
    progress : bool
        Print a progress line every ``progress_every`` steps to stderr.
    """

    ds: float = 0.02
    ds_min: float = 1e-9
    ds_max: float = 0.2
    max_steps: int = 1000
    direction: int = 1
    p_min: float = -math.inf
    p_max: float = math.inf
    bounds: dict[str, tuple[float | None, float | None]] = field(default_factory=dict)
    tol: float = 1e-10
    xtol: float = 1e-10
    max_newton: int = 10
    fast_newton: int = 4
    target_contraction: float = 0.1
    grow: float = 1.5
    shrink: float = 0.5
    state_weight: float = 1.0
    param_weight: float = 1.0
    max_correction: float = 0.5
    max_contraction: float = 0.5
    min_tangent_cos: float = 0.9
    target_angle: float = 0.15
    detect_folds: bool = True
    detect_branch_points: bool = True
    locate: bool = True
    stability: bool = False
    n_eigs: int = 3
    locate_tol: float = 1e-10
    store_states: bool = True
    stop_at: tuple[str, ...] = ()
    progress: bool = False
    progress_every: int = 25

    def validate(self) -> None:
        """Raise ``ValueError`` naming the field when a setting is out of range."""
        def need(cond: bool, name: str, rule: str) -> None:
            if not cond:
                raise ValueError(f"continuation setting {name!r} = {getattr(self, name)!r} is invalid: {rule}")
        need(self.ds_min > 0, "ds_min", "must be > 0")
        need(self.ds_max >= self.ds_min, "ds_max", "must be >= ds_min")
        need(self.ds_min <= self.ds <= self.ds_max, "ds", "must lie in [ds_min, ds_max]")
        need(self.max_steps >= 1, "max_steps", "must be >= 1")
        need(self.direction in (-1, 1), "direction", "must be +1 or -1")
        need(self.p_min < self.p_max, "p_min", "must be < p_max")
        need(self.tol > 0, "tol", "must be > 0")
        need(self.xtol > 0, "xtol", "must be > 0")
        need(self.max_newton >= 1, "max_newton", "must be >= 1")
        need(self.grow >= 1, "grow", "must be >= 1")
        need(0 < self.shrink < 1, "shrink", "must lie in (0, 1)")
        need(self.state_weight >= 0 and self.param_weight >= 0 and self.state_weight + self.param_weight > 0,
             "state_weight", "weights must be >= 0 and not both 0")
        need(0 < self.max_correction, "max_correction", "must be > 0")
        need(-1 <= self.min_tangent_cos < 1, "min_tangent_cos", "must lie in [-1, 1)")
        need(0 < self.max_contraction < 1, "max_contraction", "must lie in (0, 1)")
        need(0 < self.target_contraction <= self.max_contraction, "target_contraction",
             "must lie in (0, max_contraction]")
        need(0 < self.target_angle < math.pi / 2, "target_angle", "must lie in (0, pi/2)")
        need(self.n_eigs >= 0, "n_eigs", "must be >= 0")


class CorrectorFailure(RuntimeError):
    """The corrector did not converge (the message says why)."""


@dataclass
class Point:
    """A converged point with its tangent and the data of its linearization."""

    u: np.ndarray
    p: float
    t_u: np.ndarray
    t_p: float
    residual: float
    iterations: int
    det_sign: float = 0.0
    s: float = 0.0


class Curve:
    """The equilibrium curve of a problem, with the operations PALC needs.

    Parameters
    ----------
    problem : Problem
    settings : Settings
    """

    def __init__(self, problem: Problem, settings: Settings) -> None:
        self.problem = problem
        self.settings = settings
        self.n_evals = 0
        self.n_factorizations = 0
        self.last_linearization = None
        #: absolute residual tolerance: the relative tolerance times the model's residual scale
        self.tol = settings.tol * getattr(problem, "residual_scale", 1.0)

    # ---- norms -----------------------------------------------------------------------------------
    def weights(self, n: int) -> tuple[float, float]:
        st = self.settings
        return st.state_weight ** 2 / max(n, 1), st.param_weight ** 2

    def inner(self, au, ap, bu, bp) -> float:
        wu, wp = self.weights(au.size)
        return float(wu * np.dot(au, bu) + wp * ap * bp)

    def norm(self, au, ap) -> float:
        return math.sqrt(max(self.inner(au, ap, au, ap), 0.0))

    # ---- linearization ---------------------------------------------------------------------------
    def residual(self, u, p) -> np.ndarray:
        self.n_evals += 1
        return self.problem.checked_residual(u, p)

    def linearize(self, u, p):
        J = self.problem.checked_jacobian(u, p)
        fp = self.problem.dresidual_dp(u, p)
        if not np.all(np.isfinite(fp)):
            raise NonFiniteError(f"df/dp of {self.problem.name!r} is not finite at p = {p!r}")
        try:
            F = self.problem.factorize(J)
        except (SingularMatrixError, np.linalg.LinAlgError, RuntimeError):
            F = None  # the bordered solver factorizes the full matrix instead
        self.n_factorizations += 1
        return J, fp, F

    def bordered(self, J, F, fp, row_u, row_p, extra_cols=None, extra_rows=None, extra_D=None) -> BorderedSolver:
        """Bordered solver for ``[[J, fp, extra_cols], [row, D]]``."""
        n = J.shape[0]
        B = fp.reshape(n, 1)
        C = np.asarray(row_u, dtype=float).reshape(1, n)
        D = np.array([[row_p]], dtype=float)
        if extra_cols is not None:
            B = np.hstack([B, extra_cols.reshape(n, -1)])
            C = np.vstack([C, extra_rows.reshape(-1, n)])
            D = np.asarray(extra_D, dtype=float)
        return BorderedSolver(J, F, B, C, D, refactor=self.problem.factorize)

    def tangent(self, u, p, t_u_prev, t_p_prev, lin=None):
        """Unit tangent at ``(u, p)`` oriented like the previous one, and det sign of the bordered Jacobian."""
        J, fp, F = lin if lin is not None else self.linearize(u, p)
        wu, wp = self.weights(u.size)
        solver = self.bordered(J, F, fp, wu * t_u_prev, wp * t_p_prev)
        x, z = solver.solve(np.zeros(u.size), np.array([1.0]))
        t_u, t_p = x, float(z[0])
        nrm = self.norm(t_u, t_p)
        if not np.isfinite(nrm) or nrm == 0.0:
            raise CorrectorFailure("tangent computation failed (singular bordered Jacobian)")
        sign, _ = solver.det_sign_log()
        return t_u / nrm, t_p / nrm, sign

    # ---- Newton at fixed parameter ---------------------------------------------------------------
    def newton_fixed_p(self, u, p, max_iter: int = 30):
        """Newton's method on ``f(u, p) = 0`` at fixed ``p`` (used to converge a starting point)."""
        tol = self.tol
        u = np.array(u, dtype=float)
        r = self.residual(u, p)
        res = float(np.max(np.abs(r), initial=0.0))
        du_norm = math.inf
        for it in range(max_iter + 1):
            if res <= tol and (du_norm <= self.settings.xtol * (1.0 + self.norm(u, 0.0)) or res <= 1e-6 * tol):
                return u, res, it
            if it == max_iter:
                break
            J = self.problem.checked_jacobian(u, p)
            F = self.problem.factorize(J)
            du = -F.solve(r)
            du_norm = self.norm(du, 0.0)
            # damped Newton: halve until the residual decreases, never past the model's domain
            lam = min(1.0, self.problem.max_step_fraction(u, p, du, 0.0))
            if not lam > 1e-12:
                break
            while True:
                try:
                    r_new = self.residual(u + lam * du, p)
                    res_new = float(np.max(np.abs(r_new), initial=0.0))
                except NonFiniteError:
                    res_new = math.inf
                if res_new < res or lam < 1e-4:
                    break
                lam *= 0.5
            if not np.isfinite(res_new):
                break
            u, r, res = u + lam * du, r_new, res_new
            du_norm *= lam
        raise CorrectorFailure(f"Newton at fixed p = {p:.6g} did not converge (residual {res:.3e} > tol {tol:.1e})")

    # ---- the pseudo-arclength corrector ----------------------------------------------------------
    def correct(self, u0, p0, t_u, t_p, ds, max_iter=None, start=None):
        """Newton on ``f = 0`` and ``<t, X - X0>_W = ds`` from the predictor ``X0 + ds t``.

        ``start = (u, p)`` replaces the linear predictor as the first iterate (e.g. a point of an
        interpolant through the segment being searched).
        Returns ``(u, p, residual, iterations)``; raises :class:`CorrectorFailure`.
        """
        st = self.settings
        max_iter = st.max_newton if max_iter is None else max_iter
        wu, wp = self.weights(u0.size)
        if start is None:
            u_pred, p_pred = u0 + ds * t_u, p0 + ds * t_p
        else:
            u_pred, p_pred = np.asarray(start[0], dtype=float), float(start[1])
        if self.problem.max_step_fraction(u0, p0, u_pred - u0, p_pred - p0) < 1.0:
            raise CorrectorFailure("the predicted point lies outside the model's domain (step filter)")
        u, p = u_pred.copy(), p_pred
        self.last_linearization = None
        self.last_contraction = None
        try:
            r = self.residual(u, p)
        except NonFiniteError as exc:
            raise CorrectorFailure(f"residual not finite at the predicted point ({exc})") from None
        res = float(np.max(np.abs(r), initial=0.0))
        if res <= 1e-6 * self.tol:
            return u, p, res, 0  # the predictor is on the curve to roundoff (e.g. a linear branch)
        history = [res]
        prev_step = math.inf
        for it in range(1, max_iter + 1):
            try:
                J, fp, F = self.linearize(u, p)
                solver = self.bordered(J, F, fp, wu * t_u, wp * t_p)
                arc = self.inner(t_u, t_p, u - u0, p - p0) - ds
                du, dp = solver.solve(-r, np.array([-arc]))
            except (NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
                raise CorrectorFailure(f"linear solve failed in the corrector ({exc})") from None
            dp = float(dp[0])
            frac = self.problem.max_step_fraction(u, p, du, dp)
            if frac < 1.0:  # damped: the full update would leave the model's domain
                if not frac > 1e-8:
                    raise CorrectorFailure(f"the step filter stops the corrector (safe fraction {frac:.1e})")
                du, dp = frac * du, frac * dp
            u, p = u + du, p + dp
            step_norm = self.norm(du, dp)
            x_tol = st.xtol * (1.0 + self.norm(u, p))
            if it >= 2 and step_norm > st.max_contraction * prev_step and step_norm > x_tol:
                raise CorrectorFailure(f"corrector contracts too slowly (update ratio {step_norm / prev_step:.2f}); "
                                       "possible jump to another branch")
            # error of the new iterate: the update itself, or (once a contraction rate theta is
            # known) theta times the update, which bounds it while Newton converges quadratically
            error_estimate = step_norm if it == 1 else step_norm * min(1.0, step_norm / prev_step)
            if it == 2 and step_norm > x_tol:
                # a second update already inside x_tol is rounding noise of a converged point, not a
                # contraction rate: it says nothing about how far the step could go
                self.last_contraction = step_norm / prev_step if prev_step > 0 else 0.0
            prev_step = step_norm
            if self.norm(u - u_pred, p - p_pred) > st.max_correction * abs(ds):
                raise CorrectorFailure("corrector moved too far from the predictor (possible jump to another branch)")
            try:
                r = self.residual(u, p)
            except NonFiniteError as exc:
                raise CorrectorFailure(f"residual not finite during correction ({exc})") from None
            res = float(np.max(np.abs(r), initial=0.0))
            history.append(res)
            if res <= self.tol and error_estimate <= x_tol:
                # the last linearization was taken one (small) update away from the point: good
                # enough for the tangent and the determinant sign, and it saves a factorization
                self.last_linearization = (J, fp, F)
                return u, p, res, it
            if it >= 3 and res > history[-2] and res > self.tol:  # below tol it is roundoff noise
                raise CorrectorFailure(f"corrector diverging (residuals {', '.join(f'{h:.1e}' for h in history)})")
        raise CorrectorFailure(f"corrector did not converge in {max_iter} iterations (residual {res:.3e})")


def _event_value(curve: Curve, event: Event, u, p, t_u, t_p) -> float:
    """Value of an event's test function at a point (with the unit tangent for extrema)."""
    fun = _observable_function(curve.problem, event.observable)
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


def _observable_function(problem: Problem, observable):
    if callable(observable):
        return observable
    if observable in ("p", problem.parameter_name):
        return lambda u, p: p
    try:
        return problem.observables[observable]
    except KeyError:
        raise ValueError(f"unknown observable {observable!r}; the problem has "
                         f"{sorted(problem.observables) + ['p']}") from None


def _bound_names(st: Settings) -> set[str]:
    names = {"p_min", "p_max"}
    for name in st.bounds:
        names |= {f"{name}_min", f"{name}_max"}
    return names


def _bound_events(problem: Problem, st: Settings) -> list[Event]:
    evs = []
    if math.isfinite(st.p_min):
        evs.append(Event("p", st.p_min, -1, True, "p_min"))
    if math.isfinite(st.p_max):
        evs.append(Event("p", st.p_max, +1, True, "p_max"))
    for name, (lo, hi) in st.bounds.items():
        _observable_function(problem, name)
        if lo is not None:
            evs.append(Event(name, float(lo), -1, True, f"{name}_min"))
        if hi is not None:
            evs.append(Event(name, float(hi), +1, True, f"{name}_max"))
    return evs


# ---------------------------------------------------------------------------------------------------
# location of special points on the segment between two accepted points
# ---------------------------------------------------------------------------------------------------
class _Segment:
    """Points on the curve between A and B parametrised by the hyperplane coordinate sigma of A."""

    def __init__(self, curve: Curve, A: Point, B: Point) -> None:
        self.curve, self.A, self.B = curve, A, B
        self.sigma_B = curve.inner(A.t_u, A.t_p, B.u - A.u, B.p - A.p)
        self._cache: dict[float, tuple] = {}
        self._linearization: dict[int, Any] = {}

    def interpolate(self, sigma: float) -> tuple[np.ndarray, float]:
        """Cubic Hermite interpolant through A and B (values and tangents) at hyperplane distance ``sigma``.

        Its error is O(ds^4), so a correction started from it converges in one or two Newton steps.
        """
        A, B, h = self.A, self.B, self.sigma_B
        if h == 0.0:
            return A.u.copy(), A.p
        # dX/dsigma at B: the tangent scaled so that its component along t_A is one
        c = self.curve.inner(A.t_u, A.t_p, B.t_u, B.t_p)
        scale_B = 1.0 / c if abs(c) > 1e-3 else 1.0
        x = sigma / h
        h00, h10 = 2 * x**3 - 3 * x**2 + 1, x**3 - 2 * x**2 + x
        h01, h11 = -2 * x**3 + 3 * x**2, x**3 - x**2
        u = h00 * A.u + h10 * h * A.t_u + h01 * B.u + h11 * h * scale_B * B.t_u
        p = h00 * A.p + h10 * h * A.t_p + h01 * B.p + h11 * h * scale_B * B.t_p
        return u, float(p)

    def point(self, sigma: float):
        """Converged point at hyperplane distance ``sigma`` from A: ``(u, p, residual)``."""
        if sigma in self._cache:
            return self._cache[sigma]
        A = self.A
        if sigma == 0.0:
            out = (A.u, A.p, A.residual)
        else:
            try:
                # correct() refuses a start outside the model's domain; the linear predictor is the fallback
                u, p, res, _ = self.curve.correct(A.u, A.p, A.t_u, A.t_p, sigma, max_iter=20,
                                                  start=self.interpolate(sigma))
            except CorrectorFailure:
                u, p, res, _ = self.curve.correct(A.u, A.p, A.t_u, A.t_p, sigma, max_iter=20)
            out = (u, p, res)
            # the corrector's last linearization is one small update from the point: reuse it for the tangent
            self._linearization[id(u)] = self.curve.last_linearization
        self._cache[sigma] = out
        return out

    def tangent(self, u, p):
        lin = self._linearization.get(id(u))
        t_u, t_p, _ = self.curve.tangent(u, p, self.A.t_u, self.A.t_p, lin=lin)
        return t_u, t_p

    def root(self, fun, f_A: float, f_B: float, rtol: float, ftol: float = 0.0) -> float:
        """Root of ``fun(sigma)`` in (0, sigma_B) given its end values.

        Brent's method to a bracket of ``rtol * sigma_B``, or until ``|fun| <= ftol * max(|f_A|, |f_B|)``:
        below that the test function's value is noise from the converged points' own tolerance, and
        bisecting on noise only costs corrections.
        """
        a, b = 0.0, self.sigma_B
        if f_A == 0.0:
            return a
        if f_B == 0.0:
            return b
        f_small = ftol * max(abs(f_A), abs(f_B))

        def g(s):
            if s == a:
                return f_A
            if s == b:
                return f_B
            v = fun(s)
            if abs(v) <= f_small:
                raise _RootFound(s)
            return v
        from scipy.optimize import brentq  # imported here: scipy.optimize is slow to import

        try:
            return brentq(g, a, b, xtol=rtol * abs(b) + 1e-300, rtol=4 * np.finfo(float).eps, maxiter=100)
        except _RootFound as found:
            return found.sigma


class _RootFound(Exception):
    """Raised inside a root search when the test function is zero to within its noise."""

    def __init__(self, sigma: float) -> None:
        super().__init__(sigma)
        self.sigma = sigma


def _locate_event(curve: Curve, seg: _Segment, event: Event, vA: float, vB: float) -> SpecialPoint:
    def g(sigma):
        u, p, _ = seg.point(sigma)
        if event.kind == "crossing":
            return _event_value(curve, event, u, p, None, None)
        t_u, t_p = seg.tangent(u, p)
        return _event_value(curve, event, u, p, t_u, t_p)

    # an extremum's test function is a derivative along the curve: its noise floor is about the
    # corrector tolerance relative to its size on the bracket
    ftol = max(curve.settings.tol, 1e-12) if event.kind == "extremum" else 0.0
    sigma = seg.root(g, vA, vB, curve.settings.locate_tol, ftol=ftol)
    u, p, res = seg.point(sigma)
    value = g(sigma)
    info = {"event_value": float(value), "bracket_p": [seg.A.p, seg.B.p]}
    if event.kind == "extremum":
        fun = _observable_function(curve.problem, event.observable)
        info["extremum_value"] = float(fun(u, p))
    return SpecialPoint("event", p, u.copy(), curve.problem.evaluate_observables(u, p), residual=res,
                        located=True, s=seg.A.s + sigma, label=event.name, info=info)


def _fold_extended_residual(problem: Problem, F_bord: BorderedSolver):
    """Minimally augmented fold function ``g`` and the null vectors ``v`` (right) and ``w`` (left)."""
    n = F_bord.A.shape[0]
    v, g = F_bord.solve(np.zeros(n), np.array([1.0]))
    if problem.symmetric:
        return float(g[0]), v, v  # b = c and J = J^T make the left null vector equal the right one
    w, _ = F_bord.solve(np.zeros(n), np.array([1.0]), trans=True)
    return float(g[0]), v, w


def locate_fold(problem: Problem, u, p, v0=None, *, tol: float = 1e-10, max_iter: int = 20,
                p_tol: float = 1e-10) -> SpecialPoint:
    """Locate a fold (limit point) by Newton on the minimally augmented system.

    Solves ``f(u, p) = 0``, ``g(u, p) = 0`` where ``g`` is defined by the bordered system
    ``[[J, b], [c^T, 0]] [v; g] = [0; 1]``, with ``b`` and ``c`` approximate right and left null
    vectors of ``J`` at the starting point.  ``g_u = -w^T J_u v`` and ``g_p = -w^T J_p v`` use the
    model's second derivatives along ``v`` (finite differences of the Jacobian by default; they only
    affect the convergence rate, not the located point).

    Parameters
    ----------
    problem : Problem
    u, p : starting point, close to the fold (e.g. on the branch where the tangent's p-component is small).
    v0 : ndarray, optional
        Approximate null vector of the Jacobian (e.g. the state part of the tangent).
    tol : float
        Relative tolerance: ``max|f| <= tol * problem.residual_scale`` and
        ``|g| <= tol * max(1, max|J|)``.
    p_tol : float
        Relative tolerance on the last parameter update; Newton converges quadratically, so the
        located parameter is far more accurate than this (about ``p_tol^2``).

    Returns
    -------
    SpecialPoint
        ``kind="fold"``, ``located`` True on convergence, ``residual`` the max-norm of ``(f, g)``.
    """
    u = np.array(u, dtype=float)
    p = float(p)
    n = u.size
    J = problem.checked_jacobian(u, p)
    F = _safe_factorize(problem, J)
    if v0 is None or not np.any(v0):
        v0 = _inverse_iteration(J, F, n)
    # border [[J, b], [c^T, 0]]: b must stay out of range(J) (a left null vector does), c out of
    # range(J^T) (a right null vector does); for a symmetric J they coincide
    c = np.asarray(v0, dtype=float) / np.linalg.norm(v0)
    b = c.copy() if problem.symmetric else _inverse_iteration(J, F, n, start=c, trans=True)
    status, res, g, dp = "max_iter", math.inf, math.inf, math.inf
    history = []
    for it in range(max_iter + 1):
        r = problem.checked_residual(u, p)
        J = problem.checked_jacobian(u, p)
        F = _safe_factorize(problem, J)
        M = BorderedSolver(J, F, b.reshape(n, 1), c.reshape(1, n), np.zeros((1, 1)), refactor=problem.factorize)
        g, v, w = _fold_extended_residual(problem, M)
        f_res = float(np.max(np.abs(r), initial=0.0))
        res = max(f_res, abs(g))
        history.append(res)
        J_scale = max(1.0, float(np.max(np.abs(J.data if hasattr(J, "data") else J), initial=1.0)))
        if f_res <= tol * getattr(problem, "residual_scale", 1.0) and abs(g) <= tol * J_scale and abs(dp) <= p_tol * max(1.0, abs(p)):
            status = "converged"
            break
        if it == max_iter:
            break
        Jv = problem.jacobian_directional_derivative(u, p, v)
        g_u = -(Jv.T @ w)
        g_p = -float(w @ (problem.jacobian_dp(u, p) @ v))
        fp = problem.dresidual_dp(u, p)
        N = BorderedSolver(J, F, fp.reshape(n, 1), np.asarray(g_u).reshape(1, n), np.array([[g_p]]),
                           refactor=problem.factorize)
        du, dpv = N.solve(-r, np.array([-g]))
        dp = float(dpv[0])
        frac = problem.max_step_fraction(u, p, du, dp)
        if frac < 1.0:
            du, dp = frac * du, frac * dp
        u, p = u + du, p + dp
    return SpecialPoint("fold", p, u, problem.evaluate_observables(u, p), residual=res,
                        located=status == "converged",
                        info={"method": "minimally augmented Newton", "iterations": it, "g": float(g),
                              "history": history})


def _safe_factorize(problem: Problem, J):
    try:
        return problem.factorize(J)
    except (SingularMatrixError, np.linalg.LinAlgError, RuntimeError):
        return None


def _inverse_iteration(J, F, n, start=None, trans=False, iters: int = 3):
    rng = np.random.default_rng(12345)
    x = rng.standard_normal(n) if start is None else np.array(start, dtype=float)
    M = BorderedSolver(J, F, np.zeros((n, 0)), np.zeros((0, n)), np.zeros((0, 0)))
    for _ in range(iters):
        try:
            y, _ = M.solve(x, trans=trans)
        except (SingularMatrixError, np.linalg.LinAlgError):
            break
        if not np.all(np.isfinite(y)) or not np.any(y):
            break
        x = y / np.linalg.norm(y)
    return x / np.linalg.norm(x)


def _locate_fold_on_segment(curve: Curve, seg: _Segment) -> SpecialPoint:
    A, B = seg.A, seg.B
    # secant estimate of the zero of t_p, corrected onto the curve, then the extended system
    frac = A.t_p / (A.t_p - B.t_p) if A.t_p != B.t_p else 0.5
    sigma0 = float(np.clip(frac, 0.05, 0.95)) * seg.sigma_B
    try:
        u0, p0, _ = seg.point(sigma0)
        t_u0, _ = seg.tangent(u0, p0)
    except CorrectorFailure:
        u0, p0, t_u0 = (A.u, A.p, A.t_u) if abs(A.t_p) < abs(B.t_p) else (B.u, B.p, B.t_u)
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
        def tp(sigma):
            u, p, _ = seg.point(sigma)
            return seg.tangent(u, p)[1]
        try:
            sigma = seg.root(tp, A.t_p, B.t_p, curve.settings.locate_tol)
            u, p, res = seg.point(sigma)
            fold = SpecialPoint("fold", p, u.copy(), {}, residual=res, located=True,
                                info={"method": "root of the tangent's parameter component"})
        except (CorrectorFailure, ValueError, RuntimeError) as exc:
            fold.info["error2"] = str(exc)
    fold.observables = curve.problem.evaluate_observables(fold.u, fold.p)
    fold.s = A.s + curve.norm(fold.u - A.u, fold.p - A.p)
    fold.info["bracket_p"] = [A.p, B.p]
    return fold


def _bp_test_solver(curve: Curve, u, p, t_u_row, t_p_row, b_u, b_p, c_u, c_p):
    """Bordered solver of ``[[J, fp, b_u], [t_row, b_p], [c_u, c_p, 0]]``."""
    J, fp, F = curve.linearize(u, p)
    wu, wp = curve.weights(u.size)
    n = u.size
    cols = b_u.reshape(n, 1)
    rows = c_u.reshape(1, n)
    D = np.array([[wp * t_p_row, b_p], [c_p, 0.0]])
    return curve.bordered(J, F, fp, wu * t_u_row, wp * t_p_row, extra_cols=cols, extra_rows=rows, extra_D=D)


def _augmented_null_vectors(curve: Curve, u, p, t_u, t_p):
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


def _locate_branch_point(curve: Curve, seg: _Segment) -> SpecialPoint:
    A, B = seg.A, seg.B
    n = A.u.size
    sigma_mid = 0.5 * seg.sigma_B
    um, pm, _ = seg.point(sigma_mid)
    right, left = _augmented_null_vectors(curve, um, pm, A.t_u, A.t_p)

    def psi(sigma):
        u, p, _ = seg.point(sigma)
        solver = _bp_test_solver(curve, u, p, A.t_u, A.t_p, right[:n], right[n], left[:n], left[n])
        _, z = solver.solve(np.zeros(n), np.array([0.0, 1.0]))
        return float(z[1])

    psi_A, psi_B = psi(0.0), psi(seg.sigma_B)
    info: dict[str, Any] = {"bracket_p": [A.p, B.p]}
    if psi_A * psi_B > 0:
        # the bordered test function does not bracket: report the bracket, unlocated
        u, p, res = seg.point(sigma_mid)
        info["error"] = "bordered test function did not change sign on the bracket"
        bp = SpecialPoint("branch_point", p, u.copy(), {}, residual=res, located=False, info=info)
    else:
        sigma = seg.root(psi, psi_A, psi_B, curve.settings.locate_tol)
        u, p, res = seg.point(sigma)
        val = psi(sigma)
        info["test_function"] = val
        bp = SpecialPoint("branch_point", p, u.copy(), {}, residual=max(res, abs(val)), located=True, info=info)
        # the second null direction, W-orthogonal to the branch tangent: the bifurcating direction
        solver = _bp_test_solver(curve, u, p, A.t_u, A.t_p, right[:n], right[n], left[:n], left[n])
        x, z = solver.solve(np.zeros(n), np.array([0.0, 1.0]))
        phi = np.concatenate([x, z[:1]])
        bp.info["bifurcation_direction"] = (phi / curve.norm(phi[:n], phi[n])).tolist()
        # the tangent is not unique at a branch point: record the direction of the traced branch
        sec_u, sec_p = B.u - A.u, B.p - A.p
        nrm = curve.norm(sec_u, sec_p)
        bp.info["branch_tangent"] = (np.concatenate([sec_u, [sec_p]]) / nrm).tolist()
    bp.observables = curve.problem.evaluate_observables(bp.u, bp.p)
    bp.s = A.s + curve.norm(bp.u - A.u, bp.p - A.p)
    return bp


# ---------------------------------------------------------------------------------------------------
# the driver
# ---------------------------------------------------------------------------------------------------
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
    st = replace(settings or Settings(), **{k: v for k, v in overrides.items() if k in {f.name for f in fields(Settings)}})
    unknown = set(overrides) - {f.name for f in fields(Settings)}
    if unknown:
        raise TypeError(f"unknown continuation option(s): {', '.join(sorted(unknown))}")
    st.validate()
    t_start = time.perf_counter()
    curve = Curve(problem, st)
    all_events = list(events) + _bound_events(problem, st)
    for ev in all_events:
        _observable_function(problem, ev.observable)  # fail early on unknown observables

    u0 = np.array(u0, dtype=float).ravel()
    p0 = float(p0)
    recorder = _Recorder(problem, st, curve)
    try:
        if correct_start:
            u0, res0, it0 = curve.newton_fixed_p(u0, p0)
        else:
            res0 = float(np.max(np.abs(curve.residual(u0, p0)), initial=0.0))
            it0 = 0
            if res0 > curve.tol:
                raise CorrectorFailure(f"starting point is not converged (residual {res0:.3e} > tol {curve.tol:.1e})")
        lin = curve.linearize(u0, p0)
        if tangent is None:
            J, fp, F = lin
            n = u0.size
            if F is not None:
                try:
                    t_u_guess = -F.solve(fp)
                    t_p_guess = 1.0
                except SingularMatrixError:
                    t_u_guess, t_p_guess = np.zeros(n), 1.0
            else:
                t_u_guess, t_p_guess = np.zeros(n), 1.0
            t_u_guess, t_p_guess = st.direction * t_u_guess, float(st.direction) * t_p_guess
        else:
            t_u_guess, t_p_guess = np.asarray(tangent[0], dtype=float), float(tangent[1])
        t_u, t_p, det_sign = curve.tangent(u0, p0, t_u_guess, t_p_guess, lin=lin)
    except (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        return recorder.finish("failed", f"could not start: {exc}", t_start)

    current = Point(u0, p0, t_u, t_p, res0, it0, det_sign, 0.0)
    recorder.add(current)
    if origin is not None:
        landing = origin.special_points(problem)[1]
        landing.u, landing.p, landing.s, landing.index = u0.copy(), p0, 0.0, 0
        landing.residual = res0
        landing.info["energy_released"] = float(origin.energy_from - origin.energy_to)
        landing.info["jumped_from_observables"] = problem.evaluate_observables(origin.u_from, origin.p)
        recorder.special(landing)
    ev_values = [_event_value(curve, ev, u0, p0, t_u, t_p) for ev in all_events]
    ds = st.ds
    previous: Point | None = None
    rejections: dict[str, int] = {}
    status, message = "completed", f"reached max_steps = {st.max_steps}"
    steps = 0
    while steps < st.max_steps:
        try:
            start = _quadratic_predictor(previous, current, ds) if previous is not None else None
            u, p, res, iters = curve.correct(current.u, current.p, current.t_u, current.t_p, ds, start=start)
            theta = curve.last_contraction  # read now: locating special points runs the corrector too
            t_u, t_p, det_sign = curve.tangent(u, p, current.t_u, current.t_p, lin=curve.last_linearization)
            cos = curve.inner(t_u, t_p, current.t_u, current.t_p)
            if cos < st.min_tangent_cos:
                raise CorrectorFailure(f"tangent turned too sharply (cos = {cos:.3f}); possible branch jump")
            if previous is not None:
                _check_curvature_consistency(curve, previous, current, u, p, ds)
        except (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
            reason = str(exc).split(" (")[0].split(";")[0]
            rejections[reason] = rejections.get(reason, 0) + 1
            if ds * st.shrink < st.ds_min:
                status, message = "min_step", f"step size fell below ds_min = {st.ds_min:g} at p = {current.p:.8g}: {exc}"
                break
            ds *= st.shrink
            continue
        steps += 1
        new = Point(u, p, t_u, t_p, res, iters, det_sign, current.s + ds)
        seg = _Segment(curve, current, new)
        specials: list[SpecialPoint] = []
        # ---- folds
        if st.detect_folds and current.t_p * new.t_p < 0:
            specials.append(_locate_fold_on_segment(curve, seg) if st.locate else
                            _bracketed("fold", current, new))
        # ---- branch points
        if st.detect_branch_points and current.det_sign * new.det_sign < 0:
            try:
                specials.append(_locate_branch_point(curve, seg) if st.locate else
                                _bracketed("branch_point", current, new))
            except (CorrectorFailure, ValueError, RuntimeError, SingularMatrixError) as exc:
                sp_ = _bracketed("branch_point", current, new)
                sp_.info["error"] = str(exc)
                specials.append(sp_)
        # ---- events (user events and bounds)
        new_values = [_event_value(curve, ev, u, p, t_u, t_p) for ev in all_events]
        terminal_hit: SpecialPoint | None = None
        terminal_event: Event | None = None
        for ev, va, vb in zip(all_events, ev_values, new_values):
            if ev.triggered(va, vb):
                try:
                    spe = _locate_event(curve, seg, ev, va, vb) if st.locate else _bracketed("event", current, new, ev.name)
                except (CorrectorFailure, ValueError, RuntimeError) as exc:
                    spe = _bracketed("event", current, new, ev.name)
                    spe.info["error"] = str(exc)
                if ev.terminal:
                    if terminal_hit is None or spe.s < terminal_hit.s:
                        terminal_hit, terminal_event = spe, ev
                else:
                    specials.append(spe)
        ev_values = new_values
        for spt in specials:
            if spt.kind in st.stop_at and spt.located and (terminal_hit is None or spt.s < terminal_hit.s):
                terminal_hit, terminal_event = spt, None
        if terminal_hit is not None:
            # keep only what lies before the terminal point; end exactly on it
            specials = [s for s in specials if s.s <= terminal_hit.s and s is not terminal_hit]
            for s in sorted(specials, key=lambda s: s.s):
                recorder.special(s)
            is_bound = terminal_event is not None and terminal_event.name in _bound_names(st)
            label = terminal_event.name if terminal_event is not None else terminal_hit.kind
            if not is_bound:
                recorder.special(terminal_hit)  # before the end point is stored: "before" is the last point
                terminal_hit.info["ends_branch"] = True
            recorder.add(_point_from_special(curve, terminal_hit, current))
            terminal_hit.index = len(recorder.p) - 1
            status = "bound" if is_bound else "event"
            message = f"stopped at {label} ({problem.parameter_name} = {terminal_hit.p:.10g})"
            break
        for s in sorted(specials, key=lambda s: s.s):
            recorder.special(s)
        recorder.add(new)
        previous, current = current, new
        if st.progress and steps % st.progress_every == 0:
            print(f"[contin] step {steps}: p = {p:.6g}, ds = {ds:.3g}, newton = {iters}", file=sys.stderr)
        # ---- step-size control: Newton effort and curvature (turning angle of the tangent)
        angle = math.acos(min(1.0, max(-1.0, cos)))
        if theta is not None and iters <= st.max_newton - 3:
            factor = math.sqrt(st.target_contraction / theta) if theta > 0 else st.grow
            ds = min(max(ds * min(max(factor, st.shrink), st.grow), st.ds_min), st.ds_max)
        elif iters <= st.fast_newton:
            ds = min(ds * st.grow, st.ds_max)
        elif iters >= st.max_newton - 2:
            ds = max(ds * st.shrink, st.ds_min)
        if angle > st.target_angle:
            ds = max(ds * max(st.target_angle / angle, st.shrink), st.ds_min)
    branch = recorder.finish(status, message, t_start)
    branch.meta["n_factorizations"] = curve.n_factorizations
    branch.meta["rejected_steps"] = rejections
    return branch


def _quadratic_predictor(previous: Point, current: Point, ds: float) -> tuple[np.ndarray, float] | None:
    """Second-order predictor ``X + ds t + ds^2/2 k`` with the curvature ``k`` from the last tangent change.

    Its error is O(ds^3) instead of the tangent predictor's O(ds^2), which saves a corrector
    iteration per step on a curved branch.
    """
    h = current.s - previous.s
    if h <= 0:
        return None
    c = 0.5 * ds * ds / h
    return (current.u + ds * current.t_u + c * (current.t_u - previous.t_u),
            current.p + ds * current.t_p + c * (current.t_p - previous.t_p))


def _check_curvature_consistency(curve: Curve, previous: Point, current: Point, u, p, ds: float) -> None:
    """Reject a step whose end point disagrees with the second-order predictor.

    The change of the unit tangent over the previous step estimates the curvature vector; the
    quadratic predictor ``X + ds t + ds^2/2 k`` is then much closer to the true next point than the
    linear one.  A corrector that converged onto a neighbouring branch (parallel to this one, so the
    tangent test cannot see it) lands about the branch gap away from both predictors.
    """
    h = current.s - previous.s
    if h <= 0:
        return
    k_u = (current.t_u - previous.t_u) / h
    k_p = (current.t_p - previous.t_p) / h
    lin_u, lin_p = current.u + ds * current.t_u, current.p + ds * current.t_p
    q_u, q_p = lin_u + 0.5 * ds * ds * k_u, lin_p + 0.5 * ds * ds * k_p
    d_quad = curve.norm(u - q_u, p - q_p)
    d_lin = curve.norm(u - lin_u, p - lin_p)
    d_curv = curve.norm(q_u - lin_u, q_p - lin_p)
    # distances below the corrector's own resolution (xtol) are noise, not a jump
    noise = 10.0 * curve.settings.xtol * (1.0 + curve.norm(u, p))
    if d_quad > 0.5 * max(d_lin, d_curv) + 0.01 * abs(ds) + noise:
        raise CorrectorFailure(f"converged point is {d_quad:.2e} from the curvature predictor "
                               f"(linear predictor error {d_lin:.2e}); possible jump to another branch")


def _bracketed(kind: str, A: Point, B: Point, label: str = "") -> SpecialPoint:
    return SpecialPoint(kind, B.p, B.u.copy(), {}, residual=B.residual, located=False, s=B.s, label=label,
                        info={"bracket_p": [A.p, B.p]})


def _point_from_special(curve: Curve, spt: SpecialPoint, previous: Point) -> Point:
    res = float(np.max(np.abs(curve.residual(spt.u, spt.p)), initial=0.0))
    try:
        t_u, t_p, det_sign = curve.tangent(spt.u, spt.p, previous.t_u, previous.t_p)
    except (CorrectorFailure, SingularMatrixError, np.linalg.LinAlgError):
        # at a branch point the tangent is not unique: keep the previous one
        t_u, t_p, det_sign = previous.t_u, previous.t_p, 0.0
    return Point(spt.u, spt.p, t_u, t_p, res, 0, det_sign, spt.s)


class _Recorder:
    """Accumulates accepted points and special points into a :class:`Branch`."""

    def __init__(self, problem: Problem, st: Settings, curve: Curve) -> None:
        self.problem, self.st, self.curve = problem, st, curve
        self.p: list[float] = []
        self.u: list[np.ndarray] = []
        self.s: list[float] = []
        self.t_p: list[float] = []
        self.res: list[float] = []
        self.iters: list[int] = []
        self.obs: dict[str, list[float]] = {name: [] for name in problem.observables}
        self.n_neg: list[int] = []
        self.eigs: list[np.ndarray] = []
        self.labels: list[str] = []
        self.n_neg_by: dict[str, list[int]] = {}
        self.eigs_by: dict[str, list[np.ndarray]] = {}
        self.specials: list[SpecialPoint] = []

    def add(self, pt: Point) -> None:
        if not (pt.residual <= self.curve.tol):
            raise AssertionError("internal error: attempted to store an unconverged point")
        self.p.append(pt.p)
        if self.st.store_states or not self.u:
            self.u.append(pt.u.copy())
        else:
            self.u[-1] = pt.u.copy()
        self.s.append(pt.s)
        self.t_p.append(pt.t_p)
        self.res.append(pt.residual)
        self.iters.append(pt.iterations)
        for name, fun in self.problem.observables.items():
            self.obs[name].append(float(fun(pt.u, pt.p)))
        if self.st.stability:
            # a model may count all its labels at once (e.g. from one factorization); only the
            # Morse index is then known, so this shortcut is taken when no eigenvalues are asked for
            counts = self.problem.stability_counts(pt.u, pt.p) if self.st.n_eigs == 0 else None
            if counts is not None and (not self.labels or set(counts) == set(self.labels)):
                if not self.labels:
                    self._start_labels(list(counts))
                for label in self.labels:
                    self.n_neg_by[label].append(int(counts[label]))
                    self.eigs_by[label].append(np.zeros(0))
            else:
                ops = self.problem.stability_operators(pt.u, pt.p)
                if not ops:
                    raise ValueError(f"stability requested but problem {self.problem.name!r} has no stability operator")
                if not self.labels:
                    self._start_labels(list(ops))
                for label in self.labels:
                    info = stability_info(ops[label], self.st.n_eigs)
                    e = np.full(self.st.n_eigs, np.nan)
                    m = min(info.eigenvalues.size, self.st.n_eigs)
                    e[:m] = info.eigenvalues[:m]
                    self.n_neg_by[label].append(info.n_negative)
                    self.eigs_by[label].append(e)
            self.n_neg.append(self.n_neg_by[self.labels[0]][-1])
            self.eigs.append(self.eigs_by[self.labels[0]][-1])

    def _start_labels(self, labels: list[str]) -> None:
        self.labels = labels
        self.n_neg_by = {label: [] for label in labels}
        self.eigs_by = {label: [] for label in labels}

    def special(self, spt: SpecialPoint) -> None:
        if spt.index < 0:
            spt.index = len(self.p) - 1
        if self.st.stability and spt.kind in ("fold", "branch_point") and self.n_neg:
            spt.info.setdefault("n_negative_before", int(self.n_neg[-1]))
        self.specials.append(spt)

    def finish(self, status: str, message: str, t_start: float) -> Branch:
        n = self.u[0].size if self.u else 0
        u = np.array(self.u) if self.u else np.zeros((0, n))
        stab = self.st.stability and bool(self.n_neg)
        n_neg = np.array(self.n_neg, dtype=int) if stab else None
        for spt in self.specials:
            if not (stab and spt.kind in ("fold", "branch_point")):
                continue
            if spt.info.get("ends_branch"):
                # the run stopped on this point: only the side it came from is known
                spt.info["stable_before"] = bool(spt.info["n_negative_before"] == 0)
            elif spt.index + 1 < len(self.n_neg):
                spt.info["n_negative_after"] = int(self.n_neg[spt.index + 1])
                spt.info["stable_before"] = bool(self.n_neg[spt.index] == 0)
                spt.info["stable_after"] = bool(self.n_neg[spt.index + 1] == 0)
        return Branch(
            p=np.array(self.p), u=u, s=np.array(self.s), tangent_p=np.array(self.t_p),
            residual=np.array(self.res), newton_iterations=np.array(self.iters, dtype=int),
            observables={k: np.array(v) for k, v in self.obs.items()},
            n_negative=n_neg, eigenvalues=np.array(self.eigs) if stab else None,
            stability_by={label: (np.array(self.n_neg_by[label], dtype=int), np.array(self.eigs_by[label]))
                          for label in self.labels} if stab else {},
            special_points=self.specials, status=status, message=message,
            meta={"problem": self.problem.name, "parameter_name": self.problem.parameter_name,
                  "wall_time_s": time.perf_counter() - t_start, "n_steps": max(len(self.p) - 1, 0),
                  "tol": self.st.tol, "abs_tol": self.curve.tol, "state_weight": self.st.state_weight, "param_weight": self.st.param_weight},
        )


def switch_branch(problem: Problem, branch_point: SpecialPoint, settings: Settings | None = None, *,
                  direction: int = 1, ds: float | None = None, events=(), **overrides: Any) -> Branch:
    """Continue the branch that bifurcates at a located simple branch point.

    The bifurcating direction is the null vector of the augmented Jacobian at the branch point
    that is orthogonal (in the arclength metric) to the traced branch; it was stored by the
    location as ``info["bifurcation_direction"]``.  The first point is found by the corrector on
    the hyperplane ``<phi, X - X*> = ds``, which the original branch does not cross near ``X*``;
    from there ordinary continuation proceeds.  This is exact for pitchfork (symmetry-breaking)
    bifurcations; for a transcritical one it finds the second branch when the step is small.

    Parameters
    ----------
    problem : Problem
    branch_point : SpecialPoint
        A located ``"branch_point"`` from :func:`continuation`.
    direction : int
        +1 or -1: which half of the bifurcating branch.
    ds : float, optional
        First step (defaults to ``settings.ds``).

    Returns
    -------
    Branch
        The bifurcating branch; its first special point is the branch point it came from.
    """
    if branch_point.kind != "branch_point" or "bifurcation_direction" not in branch_point.info:
        raise ValueError("switch_branch needs a located branch point (kind 'branch_point' with a bifurcation direction)")
    if direction not in (-1, 1):
        raise ValueError(f"switch_branch: direction must be +1 or -1, got {direction!r}")
    st = replace(settings or Settings(), **{k: v for k, v in overrides.items() if k in {f.name for f in fields(Settings)}})
    step = st.ds if ds is None else float(ds)
    curve = Curve(problem, st)
    phi = direction * np.asarray(branch_point.info["bifurcation_direction"], dtype=float)
    n = branch_point.u.size
    phi_u, phi_p = phi[:n], float(phi[n])
    last: Exception | None = None
    for _ in range(12):
        try:
            u1, p1, _, _ = curve.correct(np.asarray(branch_point.u, dtype=float), branch_point.p, phi_u, phi_p, step)
            break
        except CorrectorFailure as exc:
            last, step = exc, step * 0.5
    else:
        raise CorrectorFailure(f"could not step onto the bifurcating branch: {last}")
    br = continuation(problem, u1, p1, st, events=events, tangent=(phi_u, phi_p), correct_start=False,
                      **{k: v for k, v in overrides.items() if k not in {f.name for f in fields(Settings)}})
    origin = SpecialPoint("branch_point", branch_point.p, np.asarray(branch_point.u, dtype=float),
                          dict(branch_point.observables), residual=branch_point.residual,
                          located=branch_point.located, s=0.0, index=0, label="origin",
                          info={"bracket_p": branch_point.info.get("bracket_p")})
    br.special_points.insert(0, origin)
    br.meta["origin"] = {"kind": "branch_point", "p": float(branch_point.p)}
    return br
