"""Two-parameter continuation of folds: trace a fold (limit point) as a second parameter changes.

A one-parameter family of problems ``f(u, p; q) = 0`` has folds in ``p`` at isolated points; as ``q``
changes they move along *fold curves* in the ``(p, q)`` plane.  :class:`FoldCurveProblem` makes
those curves ordinary branches for :func:`contin.continuation`: its unknowns are ``U = [u, p]``, its
parameter is ``q``, and its residual is the minimally augmented fold system

    f(u, p; q) = 0,    g(u, p; q) = 0,    [[J, b], [c^T, 0]] [v; g] = [0; 1],

with ``J = df/du`` and fixed borders ``b``, ``c`` (approximate left and right null vectors at the
starting fold).  ``g`` vanishes exactly where ``J`` is singular, so the zero set is the fold curve
whatever the borders, as long as they stay away from the range of ``J`` and ``J^T``.

Where two folds meet and annihilate (a *cusp*), the fold curve turns back in ``q``: the cusp is a fold
of this problem in its own parameter, which :func:`contin.continuation` detects and locates like any
other (``stop_at=("fold",)`` ends the trace there).  Events on the fold curve (e.g. the first
parameter crossing a value: ``contin.crossing("p", 0.0)``) are located as usual.

The second parameter enters through ``family(q)``, a callable returning the one-parameter problem at
``q``; ``df/dq`` is a central difference between two members of the family (models are often built
from ``q``, e.g. a geometry, so no analytic derivative is assumed).  The Jacobian of the extended
system is ``[[J, f_p], [g_u, g_p]]`` with ``g_u = -w^T J_u v`` and ``g_p = -w^T J_p v`` from the
member problem's second derivatives along ``v``; it is returned sparse and factorized by the generic
sparse LU (a banded ``J`` bordered by one row and column keeps O(n) fill).
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sp

from .branch import SpecialPoint
from .linalg import BorderedSolver
from .palc import _inverse_iteration, _safe_factorize
from .problem import Problem

__all__ = ["FoldCurveProblem"]

#: Members of the family kept alive (the current ``q`` and its finite-difference neighbours).
_CACHE = 6


class FoldCurveProblem(Problem):
    """Folds of ``family(q)`` in its parameter ``p``, as a problem in ``U = [u, p]`` with parameter ``q``.

    Parameters
    ----------
    family : callable
        ``family(q)`` returns the one-parameter :class:`contin.Problem` at ``q``; every member must
        have the same unknowns (same size and meaning).
    fold : SpecialPoint or tuple
        A fold of ``family(q0)``: a located :class:`contin.SpecialPoint` (``kind = "fold"``) or a
        tuple ``(u, p)`` near one.
    q0 : float
        The second parameter at that fold.
    q_name : str
        Name of ``q`` (the parameter name of this problem, also an observable).
    q_step : float, optional
        Step of the central difference in ``q`` (default ``1e-6 * max(1, |q0|)``).
    p_scale : float
        Unit of ``p`` inside ``U``: the last unknown is ``p / p_scale``, so that arclength steps
        weigh the state and ``p`` alike (e.g. a force unit for a load).  Observables report ``p``.

    Attributes
    ----------
    b, c : ndarray
        The borders (unit vectors).

    Notes
    -----
    Observables are the member problem's, evaluated at ``(u, p)`` of ``family(q)``, plus ``"p"``
    (named after the member's parameter as well) and ``q_name``.  This problem has no stability
    operator: stability along a fold curve is that of the member problem at its fold.
    """

    def __init__(self, family: Callable[[float], Problem], fold: SpecialPoint | tuple[Any, float], q0: float,
                 q_name: str = "q", q_step: float | None = None, p_scale: float = 1.0) -> None:
        self.family = family
        self._members: OrderedDict[float, Problem] = OrderedDict()
        self.q0 = float(q0)
        if not (p_scale > 0 and np.isfinite(p_scale)):
            raise ValueError(f"FoldCurveProblem: p_scale must be a finite number > 0, got {p_scale!r}")
        self.p_scale = float(p_scale)
        base = self.member(self.q0)
        self.base = base
        u0, p0 = (fold.u, fold.p) if isinstance(fold, SpecialPoint) else fold
        u0 = np.array(u0, dtype=float)
        self.n = u0.size
        self.q_step = float(q_step) if q_step is not None else 1e-6 * max(1.0, abs(self.q0))
        J = base.checked_jacobian(u0, float(p0))
        F = _safe_factorize(base, J)
        self.c = _inverse_iteration(J, F, self.n)
        self.b = self.c.copy() if base.symmetric else _inverse_iteration(J, F, self.n, start=self.c, trans=True)
        self.start = np.append(u0, float(p0) / self.p_scale)
        p_name = base.parameter_name or "p"
        obs: dict[str, Callable] = {}
        for name in base.observables:
            obs[name] = self._member_observable(name)
        obs.setdefault("p", lambda U, q: self.split(U)[1])
        obs.setdefault(p_name, lambda U, q: self.split(U)[1])
        obs[q_name] = lambda U, q: float(q)
        super().__init__(observables=obs, symmetric=False, name=f"fold_curve({base.name})", parameter_name=q_name,
                         residual_scale=getattr(base, "residual_scale", 1.0))

    # ---- members -------------------------------------------------------------------------------
    def member(self, q: float) -> Problem:
        """The one-parameter problem at ``q`` (cached)."""
        q = float(q)
        if q in self._members:
            self._members.move_to_end(q)
            return self._members[q]
        P = self.family(q)
        self._members[q] = P
        while len(self._members) > _CACHE:
            self._members.popitem(last=False)
        return P

    def split(self, U: np.ndarray) -> tuple[np.ndarray, float]:
        """``(u, p)`` of the unknowns ``U``."""
        return U[:-1], float(U[-1]) * self.p_scale

    def _member_observable(self, name: str) -> Callable:
        def fun(U: np.ndarray, q: float) -> float:
            return float(self.member(q).observables[name](*self.split(U)))
        return fun

    # ---- the extended system -------------------------------------------------------------------
    def _fold_function(self, P: Problem, u: np.ndarray, p: float) -> tuple[float, np.ndarray, np.ndarray, Any, Any]:
        J = P.checked_jacobian(u, p)
        F = _safe_factorize(P, J)
        M = BorderedSolver(J, F, self.b.reshape(-1, 1), self.c.reshape(1, -1), np.zeros((1, 1)), refactor=P.factorize)
        v, g = M.solve(np.zeros(self.n), np.array([1.0]))
        if P.symmetric:
            w = v
        else:
            w, _ = M.solve(np.zeros(self.n), np.array([1.0]), trans=True)
        return float(g[0]), v, w, J, F

    def residual(self, U: np.ndarray, q: float) -> np.ndarray:
        u, p = self.split(U)
        P = self.member(q)
        g = self._fold_function(P, u, p)[0]
        return np.append(P.residual(u, p), g)

    def jacobian(self, U: np.ndarray, q: float) -> sp.csr_matrix:
        u, p = self.split(U)
        P = self.member(q)
        _, v, w, J, _ = self._fold_function(P, u, p)
        g_u = -np.asarray(P.jacobian_directional_derivative(u, p, v).T @ w).ravel()
        g_p = -float(w @ (P.jacobian_dp(u, p) @ v)) * self.p_scale
        f_p = P.dresidual_dp(u, p).reshape(-1, 1) * self.p_scale
        return sp.bmat([[sp.csr_matrix(J), sp.csr_matrix(f_p)],
                        [sp.csr_matrix(g_u.reshape(1, -1)), np.array([[g_p]])]], format="csr")

    def dresidual_dp(self, U: np.ndarray, q: float) -> np.ndarray:
        h = self.q_step
        return (self.residual(U, q + h) - self.residual(U, q - h)) / (2.0 * h)

    def max_step_fraction(self, U: np.ndarray, q: float, dU: np.ndarray, dq: float) -> float:
        # the member's own domain filter, for the state and first-parameter part of the step
        u, p = self.split(U)
        return self.member(q).max_step_fraction(u, p, dU[:-1], float(dU[-1]) * self.p_scale)

    def null_vector(self, U: np.ndarray, q: float) -> np.ndarray:
        """The right null vector ``v`` of ``J`` at a point of the fold curve (scaled by the border)."""
        return self._fold_function(self.member(q), *self.split(U))[1]
