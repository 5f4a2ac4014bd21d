"""The equilibrium curve ``f(u, p) = 0`` as the continuation engine sees it.

:class:`Curve` holds the arclength metric, the linearization (Jacobian, ``df/dp`` and the model's
factorization), the bordered solves, the unit tangent and Newton at a fixed parameter.  A converged
point with its tangent is a :class:`Point`.

The arclength norm is ``||X||_W^2 = w_u^2 |u|^2 / n + w_p^2 p^2``: the state enters through its
root-mean-square, so the number of steps does not grow with the number of unknowns.  Weights the
settings leave open (None) are ``1 / U`` and ``1 / P``, the start point's own scales
(:func:`contin.path.scales.start_scales`), and a problem without a residual scale gets
``||df/dp|| P`` (``||J|| U`` where ``df/dp = 0``, :meth:`Curve.calibrate`): a model traced in other
units takes the same steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..numerics.linalg import BorderedSolver, SingularMatrixError
from ..problem import NonFiniteError, Problem
from ..settings import Settings
from .scales import critical_mode, start_scales, stiffness_scales

__all__ = ["Curve", "Point", "CorrectorFailure", "Linearization", "roundoff_floor", "stagnation_message"]

#: ``(J, df/dp, factorization of J or None)`` at one point
Linearization = tuple[Any, np.ndarray, Any]


class CorrectorFailure(RuntimeError):
    """The corrector did not converge (the message says why)."""


def max_abs(r: np.ndarray) -> float:
    """Max-norm of a residual vector (0 for an empty one)."""
    return float(np.max(np.abs(r), initial=0.0))


def _matrix_max_row_sum(J: Any) -> float:
    """``||J||_inf`` of a sparse or dense matrix."""
    if hasattr(J, "tocsr"):
        return float(np.max(np.asarray(abs(J).sum(axis=1)), initial=0.0))
    return float(np.max(np.sum(np.abs(np.asarray(J)), axis=1), initial=0.0))


def roundoff_floor(J: Any, fp: np.ndarray, u: np.ndarray, p: float) -> float:
    """Residual level below which ``f(u, p)`` is rounding noise: ``eps (||J|| ||u|| + ||f_p|| |p|)``.

    A residual is a sum of terms of about the size of ``J u`` and ``f_p p`` (for a linear model
    exactly those), each rounded to a relative ``eps``; a corrector asked for less iterates on noise.
    """
    eps = float(np.finfo(float).eps)
    return eps * (_matrix_max_row_sum(J) * max_abs(u) + max_abs(fp) * abs(p))


def stagnation_message(history: list[float], floor: float, tol: float, residual_scale: float) -> str | None:
    """The diagnosis of a corrector whose residuals stopped decreasing near the roundoff floor, or None.

    Residuals that stay within a factor 10 of each other over the last three iterations at less than
    1000 times :func:`roundoff_floor` are rounding noise: the tolerance asked for is below what the
    problem's arithmetic resolves.  The advice is a relative ``tol`` ten times the stagnation level.
    """
    last = history[-3:]
    if len(last) < 2 or not tol < min(last) <= 1e3 * max(floor, 1e-300) or max(last) > 10 * min(last):
        return None
    level = float(np.median(last))
    return (f"tolerance below the roundoff floor of this problem (residual stagnates at {level:.1e}, "
            f"roundoff level {floor:.1e}, asked for {tol:.1e}; raise tol to {10 * level / residual_scale:.0e})")


@dataclass
class Point:
    """A converged point with its unit tangent.

    Attributes
    ----------
    u, p : state and parameter.
    t_u, t_p : unit tangent (in the arclength metric), oriented along the path.
    residual : max-norm of ``f(u, p)``.
    iterations : corrector iterations it took.
    det_sign : sign of the determinant of the bordered Jacobian (0 when unknown).
    s : arclength from the start of the branch.
    stability : the problem's stability by label at the point, once computed (the step guard
        computes it before the point is accepted; the recorder stores it without recomputing).
    modes : the Morse indices of the problem's operator families by family name, once computed
        (:mod:`contin.watch.modes`).
    observed : ``(value, d/ds, d/du, d/dp)`` of each observable with a declared derivative, once
        evaluated (:func:`contin.recorder.observed_rates`: the step guard and the recorder share it).
    inertia : the Jacobian's Morse index read off the corrector's last factorization (one small
        update from the point) where its pivots give it exactly, else None
        (:meth:`contin.numerics.linalg.Factorization.symmetric_inertia`).
    """

    u: np.ndarray
    p: float
    t_u: np.ndarray
    t_p: float
    residual: float
    iterations: int
    det_sign: float = 0.0
    s: float = 0.0
    stability: dict[str, Any] | None = None
    modes: dict[str, tuple[int, ...]] | None = None
    observed: dict[str, tuple[float, float, Any, float]] | None = None
    inertia: int | None = None


#: How far the run's tolerance may be raised to the roundoff floor (:meth:`Curve.converged_to_roundoff`):
#: beyond this the floor estimate, not the arithmetic, is in doubt (a barrier's Jacobian blowing up)
ROUNDOFF_RAISE_LIMIT = 1e4

#: A start's load terms below this fraction of its internal terms are roundoff: its residual scale is
#: then the internal terms' (:meth:`Curve.calibrate`).
ROUNDOFF_LOAD = 1e-12


class Curve:
    """The equilibrium curve of a problem, with the operations PALC needs.

    Parameters
    ----------
    problem : Problem
    settings : Settings

    Attributes
    ----------
    tol : float
        Absolute residual tolerance: ``settings.tol`` times the model's ``residual_scale``.
    n_evals, n_factorizations : int
        Counters of residual evaluations and linearizations.
    """

    def __init__(self, problem: Problem, settings: Settings) -> None:
        self.problem = problem
        self.settings = settings
        self.n_evals = 0
        self.n_factorizations = 0
        # weights left open are 1 until :meth:`calibrate` measures the start point
        self.state_weight = 1.0 if settings.state_weight is None else float(settings.state_weight)
        self.param_weight = 1.0 if settings.param_weight is None else float(settings.param_weight)
        self.tol = settings.tol * getattr(problem, "residual_scale", 1.0)
        self.start_tol = self.tol
        # (p, tolerance before, after) each time the run's tolerance was raised to the roundoff floor
        self.tol_raised: list[tuple[float, float, float]] = []

    def needs_calibration(self) -> bool:
        """Whether the weights and the problem's residual scale are left to the start point.

        Only for a problem that gives no ``residual_scale``: a model that gives one has chosen its
        units (its sizes are of order one in them, as the models of this project are), and
        its open weights stay 1.  Measuring such a model at its start point can also mislead: an
        indenter that does not touch the structure yet moves nothing, so the load that would move the
        state by its own size is unbounded.
        """
        st = self.settings
        own_units = getattr(self.problem, "gives_residual_scale", True)
        return (st.state_weight is None or st.param_weight is None) and not own_units

    def calibrate(self, u: np.ndarray, p: float) -> tuple[float, float]:
        """Set the open weights and residual scale from the start point's scales; return ``(U, P)``.

        The scales are the start's sizes (:func:`contin.path.scales.start_scales`) corrected by its
        stiffness (:func:`contin.path.scales.stiffness_scales`: a load scale no larger than the
        distance to the first critical load, a state scale no smaller than the amplitude the state
        reaches leaving it).  Costs two linearizations, a linearized buckling eigenvalue and a few
        residuals.  The residual scale is the size of the terms that cancel in the residual as the
        path moves: ``||df/dp||_inf P``, with ``P`` the load that moves the state by its own size
        (before the stiffness caps it: the internal terms of that state change are what the load
        terms balance, ``J du/dp = -df/dp``, and what rounding acts on); when the parameter does not
        act at the start (``df/dp = 0``, or at roundoff of the internal terms: :data:`ROUNDOFF_LOAD`) it is
        ``||J||_inf U``.  The norm of the whole Jacobian would
        overstate it wherever stiff directions take no part in the motion (a shallow frame of bars,
        whose axial stiffness is a million times its snap stiffness).  The scale is kept on the
        problem (:meth:`Problem.calibrate_residual_scale`) so that fold location and jumps use the
        same one.
        """
        J, fp, F = self.linearize(u, p)
        U, P = start_scales(u, p, fp, F, getattr(self.problem, "reference_scales", None))
        calibrate = getattr(self.problem, "calibrate_residual_scale", None)
        if calibrate is not None:
            load, internal = max_abs(fp) * P, _matrix_max_row_sum(J) * U
            # a load term at roundoff of the internal ones (df/dp of a symmetric state that should be
            # zero, 1e-33 next to 1) is df/dp = 0
            scale = load if load > ROUNDOFF_LOAD * internal else internal
            if math.isfinite(scale) and scale > 0:
                calibrate(scale)
        critical = critical_mode(self.problem, u, p, J, fp, F, P)
        if critical is not None:
            U, P = stiffness_scales(U, P, p, critical)
        adopt = getattr(self.problem, "adopt_reference_scales", None)
        if adopt is not None:
            adopt(U, P)
        st = self.settings
        if st.state_weight is None:
            self.state_weight = 1.0 / U
        if st.param_weight is None:
            self.param_weight = 1.0 / P
        self.tol = self.start_tol = st.tol * getattr(self.problem, "residual_scale", 1.0)
        return U, P

    # ---- norms -----------------------------------------------------------------------------------
    def weights(self, n: int) -> tuple[float, float]:
        """Weights ``(w_u^2 / n, w_p^2)`` of the arclength inner product for ``n`` unknowns."""
        return self.state_weight ** 2 / max(n, 1), self.param_weight ** 2

    def inner(self, au: np.ndarray, ap: float, bu: np.ndarray, bp: float) -> float:
        """Arclength inner product of ``(au, ap)`` and ``(bu, bp)``."""
        wu, wp = self.weights(au.size)
        return float(wu * np.dot(au, bu) + wp * ap * bp)

    def norm(self, au: np.ndarray, ap: float) -> float:
        """Arclength norm of ``(au, ap)``."""
        return math.sqrt(max(self.inner(au, ap, au, ap), 0.0))

    # ---- linearization ---------------------------------------------------------------------------
    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        """``f(u, p)``; raises :class:`NonFiniteError` on NaN or inf."""
        self.n_evals += 1
        return self.problem.checked_residual(u, p)

    def linearize(self, u: np.ndarray, p: float) -> Linearization:
        """``(J, df/dp, F)`` at ``(u, p)``; ``F`` is None when the model's factorization fails."""
        J = self.problem.checked_jacobian(u, p)
        fp = self.problem.dresidual_dp(u, p)
        if not np.isfinite(fp).all():
            raise NonFiniteError(f"df/dp of {self.problem.name!r} is not finite at p = {p!r}")
        try:
            F = self.problem.factorize(J)
        except (SingularMatrixError, np.linalg.LinAlgError, RuntimeError):
            F = None  # the bordered solver factorizes the full matrix instead
        self.n_factorizations += 1
        return J, fp, F

    def bordered(self, J: Any, F: Any, fp: np.ndarray, row_u: np.ndarray, row_p: float,
                 extra_cols: np.ndarray | None = None, extra_rows: np.ndarray | None = None,
                 extra_D: np.ndarray | None = None) -> BorderedSolver:
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

    def tangent(self, u: np.ndarray, p: float, t_u_prev: np.ndarray, t_p_prev: float,
                lin: Linearization | None = None) -> tuple[np.ndarray, float, float]:
        """Unit tangent at ``(u, p)`` oriented like the previous one, and det sign of the bordered Jacobian.

        ``lin`` reuses a linearization taken at (or one small corrector update from) the point.
        """
        J, fp, F = lin if lin is not None else self.linearize(u, p)
        wu, wp = self.weights(u.size)
        solver = self.bordered(J, F, fp, wu * t_u_prev, wp * t_p_prev)
        x, z = solver.solve(np.zeros(u.size), np.array([1.0]))
        t_u, t_p = x, float(z[0])
        nrm = self.norm(t_u, t_p)
        if not np.isfinite(nrm) or nrm == 0.0:
            raise CorrectorFailure("tangent computation failed (singular bordered Jacobian)")
        return t_u / nrm, t_p / nrm, solver.det_sign()

    # ---- Newton at fixed parameter ---------------------------------------------------------------
    def newton_fixed_p(self, u: np.ndarray, p: float, max_iter: int = 30) -> tuple[np.ndarray, float, int]:
        """Damped Newton on ``f(u, p) = 0`` at fixed ``p`` (used to converge a starting point).

        Returns
        -------
        (u, residual, iterations)

        Raises
        ------
        CorrectorFailure
            No convergence within ``max_iter`` iterations.
        """
        tol = self.tol
        u = np.array(u, dtype=float)
        r = self.residual(u, p)
        res = max_abs(r)
        history = [res]
        du_norm = math.inf
        J = None
        for it in range(max_iter + 1):
            if self.converged_at_fixed_p(u, res, du_norm):
                return u, res, it
            if it == max_iter:
                break
            J = self.problem.checked_jacobian(u, p)
            factors = self.problem.factorize(J)
            du = -factors.solve(r)
            du_norm = self.norm(du, 0.0)
            lam, r_new, res_new = self._damped(u, p, du, res, factors)
            if not np.isfinite(res_new):
                break
            u, r, res = u + lam * du, r_new, res_new
            history.append(res)
            du_norm *= lam
        why = None if J is None else stagnation_message(
            history, roundoff_floor(J, np.zeros(0), u, p), tol, tol / self.settings.tol)
        state = (f"residual {res:.3e} > tol {tol:.1e}" if res > tol else
                 f"residual {res:.3e} within tol {tol:.1e} but the update {du_norm:.3e} does not shrink below xtol")
        raise CorrectorFailure(f"Newton at fixed p = {p:.6g} did not converge ({state})" + (f": {why}" if why else ""))

    def converged_to_roundoff(self, history: list[float], lin: Linearization, u: np.ndarray, p: float) -> bool:
        """Whether a corrector whose updates have converged stands at residuals that are rounding noise.

        The state is converged (the caller checked the error estimate against ``xtol``) but the
        residual is above :attr:`tol`.  When the last three residuals stagnate (within a factor 10 of
        each other) inside the roundoff floor at the point (:func:`roundoff_floor`), the tolerance
        asks for digits the arithmetic does not have (a stiff penalty, ``EA R^2 / EI = 1e6``, computes
        its forces from differences of lengths).  The run's tolerance is then raised to ten times the
        stagnation level (at most the floor, and at most :data:`ROUNDOFF_RAISE_LIMIT` times the
        tolerance the run started with) for the rest of the run, so that every later test (storing,
        locating) uses the same one; the raise is recorded in :attr:`tol_raised` (the branch's
        ``meta["tol_raised"]`` and its message say so).

        Parameters
        ----------
        history : the corrector's residual max-norms so far.
        lin : the corrector's last linearization ``(J, df/dp, F)``.
        u, p : the converged iterate.
        """
        last = history[-3:]
        if len(last) < 3 or max(last) > 10.0 * min(last):
            return False
        J, fp, _ = lin
        floor = roundoff_floor(J, fp, u, p)
        raised = min(floor, 10.0 * max(last))
        if not (max(last) <= floor and self.tol < raised <= ROUNDOFF_RAISE_LIMIT * self.start_tol):
            return False
        self.tol_raised.append((float(p), self.tol, raised))
        self.tol = raised
        return True

    def converged_at_fixed_p(self, u: np.ndarray, res: float, du_norm: float) -> bool:
        """Whether Newton at a fixed parameter has converged at ``u``.

        The residual's max-norm ``res`` must be within :attr:`tol` and the last update taken,
        ``du_norm`` in the state metric, within ``xtol (1 + ||u||)``, unless the residual is a
        millionth of the tolerance already (a start that was converged to begin with takes no update).

        Parameters
        ----------
        u : the iterate.
        res : max-norm of ``f(u, p)``.
        du_norm : size of the update that led to ``u`` (inf before the first one).
        """
        return res <= self.tol and (du_norm <= self.settings.xtol * (1.0 + self.norm(u, 0.0))
                                    or res <= 1e-6 * self.tol)

    def _damped(self, u: np.ndarray, p: float, du: np.ndarray, res: float,
                factors: Any = None) -> tuple[float, np.ndarray | None, float]:
        """Fraction of the Newton update ``du`` to take: halved until the iterate improves.

        An iterate improves when its residual decreases, or when the simplified Newton update
        there, ``J^{-1} f(u + lam du)`` with the Jacobian ``factors`` at ``u``, is shorter than
        ``(1 - lam/4) |du|`` (the natural monotonicity test, which does not depend on how the
        equations are scaled).  Near a soft mode the residual alone is a poor guide: a full step
        that lands within the quadratic convergence region may raise the residual's max-norm
        several orders while the update shrinks, and halving until the residual falls leaves the
        iterate where it started.  Never past the model's domain (:meth:`Problem.max_step_fraction`).
        Returns the fraction, the residual there and its max-norm (inf when no fraction is usable).
        """
        lam = min(1.0, self.problem.max_step_fraction(u, p, du, 0.0))
        if not lam > 1e-12:
            return lam, None, math.inf
        du_norm = self.norm(du, 0.0) if factors is not None else 0.0
        while True:
            try:
                r_new = self.residual(u + lam * du, p)
                res_new = max_abs(r_new)
            except NonFiniteError:
                r_new, res_new = None, math.inf
            if res_new < res or lam < 1e-4:
                return lam, r_new, res_new
            if factors is not None and r_new is not None and \
                    self.norm(factors.solve(r_new), 0.0) <= (1.0 - 0.25 * lam) * du_norm:
                return lam, r_new, res_new
            lam *= 0.5
