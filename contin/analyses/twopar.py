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

from ..problem import Problem
from ..results.branch import SpecialPoint
from ..watch.fold import fold_borders, fold_function

__all__ = ["FoldCurveProblem", "FamilyProblem", "cusp_curve_problem"]

#: Members of the family kept alive (the current ``q`` and its finite-difference neighbours).
_CACHE = 6
#: Relative step of the central differences for second derivatives.  Central differences (error
#: ~ step^2) rather than the engine's forward ones (error ~ step), because a fold curve's own fold
#: (a cusp) is located with derivatives of these derivatives: their noise must stay small.
_SECOND_STEP = 1e-4


def central_jacobian_derivative(P: Problem, u: np.ndarray, p: float, v: np.ndarray) -> Any:
    """``d/de J(u + e v, p)`` at ``e = 0`` by a central difference (error ~1e-10 relative)."""
    vnorm = float(np.max(np.abs(v), initial=0.0))
    if vnorm == 0.0:
        return sp.csr_matrix((u.size, u.size))
    eps = _SECOND_STEP * max(1.0, float(np.max(np.abs(u), initial=0.0))) / vnorm
    return (P.jacobian(u + eps * v, p) - P.jacobian(u - eps * v, p)) / (2.0 * eps)


def central_jacobian_dp(P: Problem, u: np.ndarray, p: float) -> Any:
    """``d/dp J(u, p)`` by a central difference."""
    eps = _SECOND_STEP * (1.0 + abs(p))
    return (P.jacobian(u, p + eps) - P.jacobian(u, p - eps)) / (2.0 * eps)


class _Members:
    """The members ``family(q)`` last used, so that finite differences in ``q`` build each once."""

    def __init__(self, family: Callable[[float], Problem]) -> None:
        self.family = family
        self._cache: OrderedDict[float, Problem] = OrderedDict()

    def __call__(self, q: float) -> Problem:
        q = float(q)
        if q in self._cache:
            self._cache.move_to_end(q)
            return self._cache[q]
        P = self.family(q)
        self._cache[q] = P
        while len(self._cache) > _CACHE:
            self._cache.popitem(last=False)
        return P


def _filters_steps(member: Problem) -> bool:
    """Whether the members of a family (of ``member``'s class) restrict steps to a domain; without a
    filter of their own no member need be built to ask (:meth:`Problem.max_step_fraction` is 1)."""
    return type(member).max_step_fraction is not Problem.max_step_fraction


def _jacobian_derivative(P: Problem, u: np.ndarray, p: float, v: np.ndarray) -> Any:
    # a model's own (exact) second derivative when it has one, a central difference otherwise
    if type(P).jacobian_directional_derivative is not Problem.jacobian_directional_derivative:
        return P.jacobian_directional_derivative(u, p, v)
    return central_jacobian_derivative(P, u, p, v)


def _jacobian_dp(P: Problem, u: np.ndarray, p: float) -> Any:
    if type(P).jacobian_dp is not Problem.jacobian_dp:
        return P.jacobian_dp(u, p)
    return central_jacobian_dp(P, u, p)


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
    borders : (b, c), optional
        Fixed borders of the fold function.  By default they are the approximate left and right
        null vectors at ``fold``; pass them to make several fold-curve problems share one fold
        function ``g`` (as the members of a family of fold curves must, for their own folds, the
        cusps, to be continued: :func:`cusp_curve_family`).

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
                 q_name: str = "q", q_step: float | None = None, p_scale: float = 1.0,
                 borders: tuple[np.ndarray, np.ndarray] | None = None) -> None:
        self.family = family
        self.member = _Members(family)
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
        if borders is not None:
            self.b, self.c = (np.array(x, dtype=float).reshape(-1) for x in borders)
            if self.b.size != self.n or self.c.size != self.n:
                raise ValueError(f"FoldCurveProblem: borders must have {self.n} entries each")
        else:
            self.b, self.c = fold_borders(base, u0, float(p0))
        self.start = np.append(u0, float(p0) / self.p_scale)
        # g is measured against the Jacobian's scale, as contin.locate_fold does, not the residual's:
        # convergence then asks |g| <= tol * |J|, which stays above the rounding floor of g even
        # when g itself is built from finite differences (a cusp curve's fold function)
        J_start = base.checked_jacobian(u0, float(p0))
        J_data = J_start.data if sp.issparse(J_start) else np.asarray(J_start)
        J_scale = max(1.0, float(np.max(np.abs(J_data), initial=1.0)))
        self.g_weight = getattr(base, "residual_scale", 1.0) / J_scale
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
    def split(self, U: np.ndarray) -> tuple[np.ndarray, float]:
        """``(u, p)`` of the unknowns ``U``."""
        return U[:-1], float(U[-1]) * self.p_scale

    def _member_observable(self, name: str) -> Callable:
        def fun(U: np.ndarray, q: float) -> float:
            return float(self.member(q).observables[name](*self.split(U)))
        return fun

    # ---- the extended system -------------------------------------------------------------------
    def _fold_function(self, P: Problem, u: np.ndarray, p: float) -> tuple[float, np.ndarray, np.ndarray, Any, Any]:
        return fold_function(P, u, p, self.b, self.c)

    def residual(self, U: np.ndarray, q: float) -> np.ndarray:
        u, p = self.split(U)
        P = self.member(q)
        g = self._fold_function(P, u, p)[0]
        return np.append(P.residual(u, p), self.g_weight * g)

    def jacobian(self, U: np.ndarray, q: float) -> sp.csr_matrix:
        u, p = self.split(U)
        P = self.member(q)
        _, v, w, J, _ = self._fold_function(P, u, p)
        g_u = -np.asarray(_jacobian_derivative(P, u, p, v).T @ w).ravel()
        g_p = -float(w @ (_jacobian_dp(P, u, p) @ v)) * self.p_scale
        f_p = P.dresidual_dp(u, p).reshape(-1, 1) * self.p_scale
        gw = self.g_weight
        return sp.bmat([[sp.csr_matrix(J), sp.csr_matrix(f_p)],
                        [sp.csr_matrix(gw * g_u.reshape(1, -1)), np.array([[gw * g_p]])]], format="csr")

    def dresidual_dp(self, U: np.ndarray, q: float) -> np.ndarray:
        h = self.q_step
        return (self.residual(U, q + h) - self.residual(U, q - h)) / (2.0 * h)

    def max_step_fraction(self, U: np.ndarray, q: float, dU: np.ndarray, dq: float) -> float:
        # the member's own domain filter, for the state and first-parameter part of the step
        if not _filters_steps(self.base):
            return 1.0
        u, p = self.split(U)
        return self.member(q).max_step_fraction(u, p, dU[:-1], float(dU[-1]) * self.p_scale)

    def null_vector(self, U: np.ndarray, q: float) -> np.ndarray:
        """The right null vector ``v`` of ``J`` at a point of the fold curve (scaled by the border)."""
        return self._fold_function(self.member(q), *self.split(U))[1]


class FamilyProblem(Problem):
    """A family ``family(q)`` at a fixed first parameter ``p``, as a one-parameter problem in ``q``.

    Folds and fold curves live in any parameter: the folds of ``f(u, p; q)`` in ``q`` at fixed
    ``p = p_fixed`` are the points of the fold curves (in ``p``) where ``p = p_fixed``.  Continuing
    such a fold in a third parameter traces, for instance, where a limit load equals a given value
    (e.g. a lower limit load at zero force: where a structure becomes bistable).

    Parameters
    ----------
    family : callable
        ``family(q)`` returns the member :class:`contin.Problem` at ``q`` (all with the same unknowns).
    p_fixed : float
        The value of the members' own parameter.
    q0 : float
        A value of ``q`` (the member built first; its properties, such as symmetry, apply to all).
    q_name : str
        Name of ``q`` (parameter name and observable).
    q_step : float, optional
        Step of the central differences in ``q`` (default ``1e-6 * max(1, |q0|)``).
    base : Problem, optional
        A member already built (of this family or of one that differs from it in another parameter
        only): its observables' names, symmetry, factorization and residual scale serve instead of
        building ``family(q0)`` for them.  A family made anew at every value of another parameter
        (the fold curve of a :class:`FoldCurveProblem` over it) then builds only the members it uses.

    Notes
    -----
    ``df/dq`` and ``dJ/dq`` are central differences between members.  Observables are the
    members' at ``(u, p_fixed)`` plus ``q_name``.  The stability operators are the member's.
    """

    def __init__(self, family: Callable[[float], Problem], p_fixed: float, q0: float, q_name: str = "q",
                 q_step: float | None = None, base: Problem | None = None) -> None:
        self.member = _Members(family)
        self.p_fixed = float(p_fixed)
        self.q_step = float(q_step) if q_step is not None else 1e-6 * max(1.0, abs(float(q0)))
        if base is None:
            base = self.member(float(q0))
        self.base = base
        obs: dict[str, Callable] = {name: self._member_observable(name) for name in base.observables}
        obs[q_name] = lambda u, q: float(q)
        super().__init__(observables=obs, symmetric=base.symmetric, name=f"family({base.name})",
                         parameter_name=q_name, residual_scale=getattr(base, "residual_scale", 1.0))

    def _member_observable(self, name: str) -> Callable:
        def fun(u: np.ndarray, q: float) -> float:
            return float(self.member(q).observables[name](u, self.p_fixed))
        return fun

    def residual(self, u: np.ndarray, q: float) -> np.ndarray:
        return self.member(q).residual(u, self.p_fixed)

    def jacobian(self, u: np.ndarray, q: float) -> Any:
        return self.member(q).jacobian(u, self.p_fixed)

    def dresidual_dp(self, u: np.ndarray, q: float) -> np.ndarray:
        h = self.q_step
        return (self.residual(u, q + h) - self.residual(u, q - h)) / (2.0 * h)

    def jacobian_dp(self, u: np.ndarray, q: float) -> Any:
        h = self.q_step
        return (self.jacobian(u, q + h) - self.jacobian(u, q - h)) / (2.0 * h)

    def jacobian_directional_derivative(self, u: np.ndarray, q: float, v: np.ndarray) -> Any:
        return _jacobian_derivative(self.member(q), u, self.p_fixed, v)

    @property
    def has_energy(self) -> bool:
        return self.base.has_energy

    def energy(self, u: np.ndarray, q: float) -> float:
        return self.member(q).energy(u, self.p_fixed)

    def stability_operators(self, u: np.ndarray, q: float) -> dict[str, Any]:
        return self.member(q).stability_operators(u, self.p_fixed)

    def stability_operator(self, u: np.ndarray, q: float) -> Any:
        return self.member(q).stability_operator(u, self.p_fixed)

    def factorize(self, J: Any) -> Any:
        return self.base.factorize(J)

    def max_step_fraction(self, u: np.ndarray, q: float, du: np.ndarray, dq: float) -> float:
        if not _filters_steps(self.base):
            return 1.0
        return self.member(q).max_step_fraction(u, self.p_fixed, du, 0.0)


def cusp_curve_problem(family2: Callable[[float, float], Problem], fold_curve: FoldCurveProblem,
                       cusp: SpecialPoint, r0: float, r_name: str = "r", r_step: float | None = None,
                       q_scale: float = 1.0) -> FoldCurveProblem:
    """Cusps of a two-parameter family, continued in a third parameter ``r``.

    A cusp is a fold of a fold curve in its second parameter ``q`` (``fold_curve`` at ``r = r0``
    located it: ``cusp``).  The fold curves at other ``r`` form a family of problems in ``q`` that
    share ``fold_curve``'s borders, so their fold functions agree; the cusp's own fold curve in ``r``
    is then a :class:`FoldCurveProblem` of that family: unknowns ``[u, p / p_scale, q / q_scale]``,
    parameter ``r``.

    Parameters
    ----------
    family2 : callable
        ``family2(r, q)`` returns the one-parameter problem (parameter ``p``) at ``(q, r)``.
    fold_curve : FoldCurveProblem
        The fold curve at ``r0`` (``fold_curve.family(q) == family2(r0, q)``) on which ``cusp`` lies.
    cusp : SpecialPoint
        The located fold of ``fold_curve`` (``cusp.u`` its unknowns ``[u, p / p_scale]``, ``cusp.p`` = q).
    r0 : float
        The third parameter at the cusp.
    r_name : str
        Name of ``r``.
    r_step : float, optional
        Central-difference step in ``r``.
    q_scale : float
        Unit of ``q`` inside the unknowns.

    Returns
    -------
    FoldCurveProblem
        Its ``start`` is the cusp; ``split(U)`` gives ``([u, p / p_scale], q)``.
    """
    inner_b, inner_c = fold_curve.b, fold_curve.c
    U_c = np.array(cusp.u, dtype=float)

    def fold_curve_at(r: float) -> FoldCurveProblem:
        return FoldCurveProblem(lambda q: family2(r, q), (U_c[:-1], float(U_c[-1]) * fold_curve.p_scale),
                                float(cusp.p), q_name=fold_curve.parameter_name, q_step=fold_curve.q_step,
                                p_scale=fold_curve.p_scale, borders=(inner_b, inner_c))

    return FoldCurveProblem(fold_curve_at, (U_c, float(cusp.p)), r0, q_name=r_name, q_step=r_step, p_scale=q_scale)
