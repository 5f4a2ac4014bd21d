"""Predictor and corrector of pseudo-arclength continuation.

From an accepted point ``X0 = (u0, p0)`` with unit tangent ``t`` the predictor guesses the next point
at arclength ``ds`` (linear along ``t``, or quadratic with the curvature seen over the last step).
The corrector then runs Newton on the bordered system

    [ J      f_p    ] [du]     [ f                      ]
    [ w t_u  w_p t_p] [dp] = - [ <t, X - X0>_W - ds     ]

solved by block elimination on the model's factorization of ``J`` (see :mod:`contin.numerics.linalg`), and
returns a :class:`Correction`: the converged point, the iterations, the contraction rate and the last
linearization.  Guards against jumping to a neighbouring branch (too long a correction, a slowly
contracting Newton, an end point that disagrees with the curvature) raise :class:`CorrectorFailure`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..numerics.linalg import SingularMatrixError
from ..problem import NonFiniteError
from .curve import CorrectorFailure, Curve, Linearization, Point, max_abs, roundoff_floor, stagnation_message

__all__ = ["Correction", "correct", "quadratic_predictor", "check_curvature_consistency"]


@dataclass
class Correction:
    """What the corrector found.

    Attributes
    ----------
    u, p : the converged point.
    residual : its max-norm residual.
    iterations : Newton iterations (0 when the predictor was already on the curve).
    contraction : ``|dX_2| / |dX_1|``, the first contraction rate, or None when Newton stopped
        before a second update above rounding noise.
    linearization : ``(J, df/dp, F)`` from the last iteration (one small update from the point), or
        None when no iteration ran.
    """

    u: np.ndarray
    p: float
    residual: float
    iterations: int
    contraction: float | None = None
    linearization: Linearization | None = None


class _Contraction:
    """Watches the sizes of successive Newton updates (the guard against slow contraction)."""

    def __init__(self, max_contraction: float) -> None:
        self.max_contraction = max_contraction
        self.previous = math.inf
        self.rate: float | None = None

    def update(self, it: int, step: float, x_tol: float, linear: bool = False) -> float:
        """Record update ``it`` of size ``step``; return the error estimate of the new iterate.

        The estimate is the update itself, or (once a contraction rate is known) the update times
        that rate, which bounds the error while Newton converges quadratically; for a chord update
        (``linear``, a fixed rate ``q``) the bound is the update times ``q / (1 - q)``.
        """
        if it >= 2 and step > self.max_contraction * self.previous and step > x_tol:
            raise CorrectorFailure(f"corrector contracts too slowly (update ratio {step / self.previous:.2f}); "
                                   "possible jump to another branch")
        if it == 1:
            estimate = step
        else:
            q = min(1.0, step / self.previous)
            estimate = step * (q / (1.0 - q) if linear and q < 0.5 else q)
        if it == 2 and step > x_tol:
            # a second update already inside x_tol is rounding noise of a converged point, not a
            # contraction rate: it says nothing about how far the step could go
            self.rate = step / self.previous if self.previous > 0 else 0.0
        self.previous = step
        return estimate


def _residual(curve: Curve, u: np.ndarray, p: float, where: str) -> tuple[np.ndarray, float]:
    try:
        r = curve.residual(u, p)
    except NonFiniteError as exc:
        raise CorrectorFailure(f"residual not finite {where} ({exc})") from None
    return r, max_abs(r)


def _linearized_system(curve: Curve, u: np.ndarray, p: float, origin: Point) -> tuple[Linearization, Any]:
    """The linearization at ``(u, p)`` and the bordered solver of the corrector's system built on it."""
    wu, wp = curve.weights(u.size)
    try:
        lin = curve.linearize(u, p)
        J, fp, F = lin
        return lin, curve.bordered(J, F, fp, wu * origin.t_u, wp * origin.t_p)
    except (NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        raise CorrectorFailure(f"linear solve failed in the corrector ({exc})") from None


def _update(curve: Curve, solver: Any, u: np.ndarray, p: float, r: np.ndarray, origin: Point,
            ds: float) -> tuple[np.ndarray, float]:
    """The corrector's update ``(du, dp)`` from a bordered solver, shortened to the model's domain."""
    try:
        arc = curve.inner(origin.t_u, origin.t_p, u - origin.u, p - origin.p) - ds
        du, dp = solver.solve(-r, np.array([-arc]))
    except (NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        raise CorrectorFailure(f"linear solve failed in the corrector ({exc})") from None
    dp = float(dp[0])
    frac = curve.problem.max_step_fraction(u, p, du, dp)
    if frac < 1.0:  # damped: the full update would leave the model's domain
        if not frac > 1e-8:
            raise CorrectorFailure(f"the step filter stops the corrector (safe fraction {frac:.1e})")
        du, dp = frac * du, frac * dp
    return du, dp


def _predict(curve: Curve, origin: Point, ds: float,
             start: tuple[np.ndarray, float] | None) -> tuple[np.ndarray, float]:
    """The first iterate: ``start``, or the linear predictor; refused outside the model's domain."""
    if start is None:
        u_pred, p_pred = origin.u + ds * origin.t_u, origin.p + ds * origin.t_p
    else:
        u_pred, p_pred = np.asarray(start[0], dtype=float), float(start[1])
    if curve.problem.max_step_fraction(origin.u, origin.p, u_pred - origin.u, p_pred - origin.p) < 1.0:
        raise CorrectorFailure("the predicted point lies outside the model's domain (step filter)")
    return u_pred, p_pred


def correct(curve: Curve, origin: Point, ds: float, max_iter: int | None = None,
            start: tuple[np.ndarray, float] | None = None) -> Correction:
    """Newton on ``f = 0`` and ``<t, X - X0>_W = ds`` from the predictor ``X0 + ds t``.

    Parameters
    ----------
    curve : Curve
    origin : Point
        ``X0`` and the tangent ``t`` that defines the hyperplane (only ``u, p, t_u, t_p`` are read).
    ds : float
        Distance of the hyperplane from ``X0`` along ``t``.
    max_iter : int, optional
        Iterations allowed (default ``settings.max_newton``).
    start : (u, p), optional
        First iterate instead of the linear predictor (e.g. a quadratic predictor or a point of an
        interpolant through the segment being searched).

    Raises
    ------
    CorrectorFailure
        No convergence, divergence, or a guard against branch jumping fired.
    """
    st = curve.settings
    max_iter = st.max_newton if max_iter is None else max_iter
    u_pred, p_pred = _predict(curve, origin, ds, start)
    u, p = u_pred.copy(), p_pred
    r, res = _residual(curve, u, p, "at the predicted point")
    if res <= 1e-6 * curve.tol:
        return Correction(u, p, res, 0)  # the predictor is on the curve to roundoff (e.g. a linear branch)
    history, contraction = [res], _Contraction(st.max_contraction)
    lin: Linearization | None = None
    solver = None
    chord_allowed = st.max_chord_rate > 0.0
    for it in range(1, max_iter + 1):
        # fresh: the update comes from a linearization at the iterate it starts from (a Newton update)
        fresh = solver is None or not chord_allowed
        if not fresh:
            # chord update: the last linearization again, one solve and no new Jacobian; kept while
            # it shrinks the update at least as fast as max_chord_rate
            du, dp = _update(curve, solver, u, p, r, origin, ds)
            fresh = curve.norm(du, dp) > st.max_chord_rate * contraction.previous
        if fresh:
            lin, solver = _linearized_system(curve, u, p, origin)
            du, dp = _update(curve, solver, u, p, r, origin, ds)
        u, p = u + du, p + dp
        x_tol = st.xtol * (1.0 + curve.norm(u, p))
        error_estimate = contraction.update(it, curve.norm(du, dp), x_tol, linear=not fresh)
        if curve.norm(u - u_pred, p - p_pred) > st.max_correction * abs(ds):
            raise CorrectorFailure("corrector moved too far from the predictor (possible jump to another branch)")
        r, res = _residual(curve, u, p, "during correction")
        history.append(res)
        if res <= curve.tol and error_estimate <= x_tol:
            return Correction(u, p, res, it, contraction.rate, lin if fresh else None)
        if it >= 2 and error_estimate <= x_tol and lin is not None and curve.converged_to_roundoff(history, lin, u, p):
            return Correction(u, p, res, it, contraction.rate, lin if fresh else None)
        if not fresh and res > history[-2] and res > curve.tol:
            # a chord update that raised the residual says nothing about Newton: Newton from here on
            chord_allowed = False
            continue
        if it >= 3 and res > history[-2] and res > curve.tol:  # below tol it is roundoff noise
            raise CorrectorFailure(_stalled(curve, history, lin, u, p) or
                                   f"corrector diverging (residuals {', '.join(f'{h:.1e}' for h in history)})")
    raise CorrectorFailure(_stalled(curve, history, lin, u, p) or
                           f"corrector did not converge in {max_iter} iterations (residual {res:.3e})")


def _stalled(curve: Curve, history: list[float], lin: Linearization | None, u: np.ndarray, p: float) -> str | None:
    """The roundoff-floor diagnosis of a failed correction (see :func:`contin.path.curve.stagnation_message`)."""
    if lin is None:
        return None
    J, fp, _ = lin
    scale = curve.tol / curve.settings.tol
    return stagnation_message(history, roundoff_floor(J, fp, u, p), curve.tol, scale)


def quadratic_predictor(previous: Point, current: Point, ds: float) -> tuple[np.ndarray, float] | None:
    """Second-order predictor ``X + ds t + ds^2/2 k`` with the curvature ``k`` from the last tangent change.

    Its error is O(ds^3) instead of the tangent predictor's O(ds^2), which saves a corrector
    iteration per step on a curved branch.  None when the last step has no length.
    """
    h = current.s - previous.s
    if h <= 0:
        return None
    c = 0.5 * ds * ds / h
    return (current.u + ds * current.t_u + c * (current.t_u - previous.t_u),
            current.p + ds * current.t_p + c * (current.t_p - previous.t_p))


def check_curvature_consistency(curve: Curve, previous: Point, current: Point, u: np.ndarray, p: float,
                                ds: float) -> None:
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
