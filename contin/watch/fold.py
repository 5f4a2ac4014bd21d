"""Location of folds (limit points) by Newton on the minimally augmented system.

The fold system is ``f(u, p) = 0``, ``g(u, p) = 0`` where ``g`` is defined by the bordered system
``[[J, b], [c^T, 0]] [v; g] = [0; 1]``, with ``b`` and ``c`` approximate left and right null
vectors of ``J`` at the starting point: ``g`` vanishes exactly where ``J`` is singular.  Its
derivatives ``g_u = -w^T J_u v`` and ``g_p = -w^T J_p v`` use the model's second derivatives along
``v`` (finite differences of the Jacobian by default; they only set the convergence rate, not the
located point).  :mod:`contin.analyses.twopar` continues the same system in a second parameter.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..numerics.linalg import BorderedSolver, SingularMatrixError
from ..path.curve import max_abs
from ..problem import Problem
from ..results.branch import SpecialPoint

__all__ = ["locate_fold", "safe_factorize", "inverse_iteration", "fold_test_function", "fold_function",
           "fold_borders"]


def safe_factorize(problem: Problem, J: Any) -> Any:
    """The model's factorization of ``J``, or None when it fails (a bordered solve then goes dense)."""
    try:
        return problem.factorize(J)
    except (SingularMatrixError, np.linalg.LinAlgError, RuntimeError):
        return None


def inverse_iteration(J: Any, F: Any, n: int, start: np.ndarray | None = None, trans: bool = False,
                      iters: int = 3) -> np.ndarray:
    """Approximate (unit) null vector of ``J`` (of ``J^T`` with ``trans``) by a few inverse iterations."""
    rng = np.random.default_rng(12345)
    x = rng.standard_normal(n) if start is None else np.array(start, dtype=float)
    M = BorderedSolver(J, F, np.zeros((n, 0)), np.zeros((0, n)), np.zeros((0, 0)))
    for _ in range(iters):
        try:
            y, _ = M.solve(x, trans=trans)
        except (SingularMatrixError, np.linalg.LinAlgError):
            break
        if not np.isfinite(y).all() or not np.any(y):
            break
        x = y / np.linalg.norm(y)
    return x / np.linalg.norm(x)


def fold_test_function(problem: Problem, F_bord: BorderedSolver) -> tuple[float, np.ndarray, np.ndarray]:
    """Minimally augmented fold function ``g`` and the null vectors ``v`` (right) and ``w`` (left)."""
    n = F_bord.A.shape[0]
    v, g = F_bord.solve(np.zeros(n), np.array([1.0]))
    if problem.symmetric:
        return float(g[0]), v, v  # b = c and J = J^T make the left null vector equal the right one
    w, _ = F_bord.solve(np.zeros(n), np.array([1.0]), trans=True)
    return float(g[0]), v, w


def fold_function(problem: Problem, u: np.ndarray, p: float, b: np.ndarray,
                  c: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, Any, Any]:
    """``(g, v, w, J, F)``: the fold function with borders ``b``, ``c`` at ``(u, p)``, its null vectors,
    and the Jacobian and factorization they come from."""
    J = problem.checked_jacobian(u, p)
    F = safe_factorize(problem, J)
    M = BorderedSolver(J, F, b.reshape(-1, 1), c.reshape(1, -1), np.zeros((1, 1)), refactor=problem.factorize)
    g, v, w = fold_test_function(problem, M)
    return g, v, w, J, F


def fold_borders(problem: Problem, u: np.ndarray, p: float,
                 v0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Borders ``(b, c)``: ``b`` out of range(J) (a left null vector is), ``c`` out of range(J^T).

    ``c`` is ``v0`` (an approximate right null vector) normalised, or one found by inverse
    iteration; for a symmetric ``J`` they coincide.
    """
    J = problem.checked_jacobian(u, p)
    F = safe_factorize(problem, J)
    if v0 is None or not np.any(v0):
        v0 = inverse_iteration(J, F, u.size)
    c = np.asarray(v0, dtype=float) / np.linalg.norm(v0)
    b = c.copy() if problem.symmetric else inverse_iteration(J, F, u.size, start=c, trans=True)
    return b, c


def _newton_update(problem: Problem, u: np.ndarray, p: float, r: np.ndarray, lin: tuple,
                   g: float, v: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, float]:
    """Newton update of the fold system, shortened to the model's domain."""
    J, F = lin
    n = u.size
    g_u = -(problem.jacobian_directional_derivative(u, p, v).T @ w)
    g_p = -float(w @ (problem.jacobian_dp(u, p) @ v))
    fp = problem.dresidual_dp(u, p)
    N = BorderedSolver(J, F, fp.reshape(n, 1), np.asarray(g_u).reshape(1, n), np.array([[g_p]]),
                       refactor=problem.factorize)
    du, dpv = N.solve(-r, np.array([-g]))
    dp = float(dpv[0])
    frac = problem.max_step_fraction(u, p, du, dp)
    if frac < 1.0:
        du, dp = frac * du, frac * dp
    return du, dp


def locate_fold(problem: Problem, u: np.ndarray, p: float, v0: np.ndarray | None = None, *,
                tol: float = 1e-10, max_iter: int = 20, p_tol: float = 1e-10) -> SpecialPoint:
    """Locate a fold (limit point) by Newton on the minimally augmented system (module docstring).

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
    u, p = np.array(u, dtype=float), float(p)
    b, c = fold_borders(problem, u, p, v0)
    converged, res, g, dp, history = False, math.inf, math.inf, math.inf, []
    for it in range(max_iter + 1):
        r = problem.checked_residual(u, p)
        g, v, w, J, F = fold_function(problem, u, p, b, c)
        f_res = max_abs(r)
        res = max(f_res, abs(g))
        history.append(res)
        J_scale = max(1.0, float(np.max(np.abs(J.data if hasattr(J, "data") else J), initial=1.0)))
        converged = (f_res <= tol * getattr(problem, "residual_scale", 1.0) and abs(g) <= tol * J_scale
                     and abs(dp) <= p_tol * max(1.0, abs(p)))
        if converged or it == max_iter:
            break
        du, dp = _newton_update(problem, u, p, r, (J, F), g, v, w)
        u, p = u + du, p + dp
    return SpecialPoint("fold", p, u, problem.evaluate_observables(u, p), residual=res, located=converged,
                        info={"method": "minimally augmented Newton", "iterations": it, "g": float(g),
                              "history": history})
