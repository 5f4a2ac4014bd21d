"""Locating the snap where the last contact node is about to leave the barrier (a *release fold*).

Why the engine's fold location is not enough here.  With one node ``i`` in contact at a gap
``x = dhat - d_i`` (``0 < x << dhat``) the barrier is ``W ~ K x^3 / dhat``: its force on the node is
``~3 K x^2 / dhat`` and its stiffness ``~6 K x / dhat``.  Under displacement control the path loses
stability where that stiffness falls to ``1 / |c|``, ``c`` being the (negative) compliance of the
free shell at the node along the contact normal: ``x_f ~ dhat / (6 K |c|)``.  When the node is the
pole, ``|c|`` is large and ``x_f`` is a sizeable fraction of ``dhat``; the continuation goes round
the fold and the engine locates it.  When the node is off the axis (spheres with ``r/R >= 0.9`` and
the plate after the pole has detached), ``|c| ~ 1e-3`` for the default cap and ``x_f ~ 1.7e-6 dhat``:
the fold's radius of curvature in ``(u, w_b)`` is ~1e-9, below any sensible step, and the
finite-difference second derivatives of the minimally augmented system straddle ``d = dhat``.

The remedy is a parameter in which the fold is not small: the gap ``x`` itself.  For fixed ``x`` the
equilibrium equations plus the constraint ``d_i(u, w_b) = dhat - x`` determine ``(u, w_b)``; the
Jacobian is the shell's band bordered by one row and column, factorized in O(N) by
:class:`contin_models.contact.indentation.BorderedBandedLU`.  Along this curve ``dw_b/dx`` is smooth,
negative on the stable side and ``+1`` as ``x -> 0`` (the barrier's force and stiffness vanish and
the shell is left at a free equilibrium), so the fold ``dw_b/dx = 0`` is bracketed by halving ``x``
and found by Brent's method in ``x``.  At the root the displacement-control Jacobian is singular:
the located point is a fold in ``w_b`` in the engine's sense, obtained in a coordinate that resolves
it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq

from contin.numerics.linalg import SingularMatrixError
from contin.problem import NonFiniteError
from contin_models.shell.energy import HALF_BANDWIDTH

from .indentation import BorderedBandedLU, ShellIndentation

__all__ = ["ReleaseFold", "ReleaseFoldError", "locate_release_fold"]


#: How many times the gap may be doubled from a start that lies past the fold.
_MAX_DOUBLINGS = 8


class ReleaseFoldError(RuntimeError):
    """The release fold could not be bracketed or a gap-constrained solve did not converge."""


@dataclass
class ReleaseFold:
    """A located release fold.

    Attributes
    ----------
    u, w_b : the state and the indenter travel at the fold.
    node : int
        The contact node whose gap parameterizes the search (base = 0, pole = N-1).
    gap : float
        ``x = dhat - d_node`` at the fold.
    residual : float
        Max-norm of the equilibrium residual at the fold.
    dw_dx : float
        ``dw_b / dx`` at the returned point (zero at an exact fold; the root search stops at
        ``|x - x_f| <= xtol``).
    evaluations : int
        Gap-constrained solves made.
    """

    u: np.ndarray
    w_b: float
    node: int
    gap: float
    residual: float
    dw_dx: float
    evaluations: int


class _GapCurve:
    """Equilibria with one barrier sample point's gap prescribed: solutions ``(u, w_b)`` and ``dw_b/dx`` by ``x``."""

    def __init__(self, problem: ShellIndentation, sample: int | None, tol: float, max_iter: int) -> None:
        self.P, self.sample = problem, sample
        self.tol = tol * problem.residual_scale
        self.max_iter = max_iter
        # the gap is a difference of coordinates of order R: its rounding floor
        self.gap_floor = 64 * np.finfo(float).eps * problem.R
        self.solutions: dict[float, tuple[np.ndarray, float, np.ndarray, float]] = {}
        self.evaluations = 0

    def gap_and_gradient(self, u: np.ndarray, w_b: float) -> tuple[float, np.ndarray, float]:
        """``x = dhat - d``, ``dx/du`` (on the unknowns) and ``dx/dw_b``: ``d`` the distance of the fixed
        sample point, or (``sample`` None) of the meridian's point nearest to the indenter."""
        P = self.P
        if self.sample is None:
            d, dd_dx, dd_dc = P.barrier.closest_point(P.full_state(u), P.position(w_b))[:3]
        else:
            d, dd_dx, dd_dc = P.barrier.sample_gap(P.full_state(u), P.position(w_b), self.sample)
        return P.dhat - d, -dd_dx[P.idx], dd_dc  # dx/dw_b = -dd/dw_b = +dd/dc (c = c0 - w_b)

    def _system(self, u: np.ndarray, w_b: float) -> tuple[BorderedBandedLU, np.ndarray, float]:
        P = self.P
        J = P.jacobian(u, w_b)
        Gp = P.dresidual_dp(u, w_b).reshape(-1, 1)
        _, gu, gw = self.gap_and_gradient(u, w_b)
        A = sp.bmat([[J, sp.csr_matrix(Gp)], [sp.csr_matrix(gu.reshape(1, -1)), np.array([[gw]])]], format="csr")
        return BorderedBandedLU(A, HALF_BANDWIDTH, HALF_BANDWIDTH), gu, gw

    def solve(self, x: float, u: np.ndarray, w_b: float) -> tuple[np.ndarray, float, np.ndarray, float]:
        """Newton on ``G(u, w_b) = 0``, ``gap(u, w_b) = x`` from ``(u, w_b)``; returns ``(u, w_b, tangent, dw/dx)``."""
        P = self.P
        self.evaluations += 1
        u = np.array(u, dtype=float)
        for _ in range(self.max_iter + 1):
            res = float(np.max(np.abs(P.residual(u, w_b))))
            gap = self.gap_and_gradient(u, w_b)[0]
            if res <= self.tol and abs(gap - x) <= 1e-6 * x + self.gap_floor:
                break
            lu, _, _ = self._system(u, w_b)
            step = lu.solve(-np.append(P.residual(u, w_b), gap - x))
            if not np.isfinite(step).all():
                raise ReleaseFoldError(f"gap-constrained Newton at x = {x:.6g}: non-finite step")
            du, dw = step[:-1], float(step[-1])
            # the barrier's filter: no node may reach the indenter along the step
            frac = min(1.0, P.max_step_fraction(u, w_b, du, dw))
            u, w_b = u + frac * du, w_b + frac * dw
        else:
            raise ReleaseFoldError(f"gap-constrained Newton at x = {x:.6g} did not converge in {self.max_iter} "
                                   f"iterations (residual {res:.3g}, gap {gap:.6g})")
        lu, _, _ = self._system(u, w_b)
        rhs = np.zeros(u.size + 1)
        rhs[-1] = 1.0  # d/dx of gap(u(x), w_b(x)) = x
        t = lu.solve(rhs)
        self.solutions[x] = (u, w_b, t, float(t[-1]))
        return self.solutions[x]

    def dw_dx(self, x: float) -> float:
        """``dw_b/dx`` on the gap curve at ``x``, solved from the nearest stored solution by its tangent."""
        if x in self.solutions:
            return self.solutions[x][3]
        x0 = min(self.solutions, key=lambda s: abs(math.log(s / x)))
        u0, w0, t0, _ = self.solutions[x0]
        guess_u, guess_w = u0 + (x - x0) * t0[:-1], w0 + (x - x0) * t0[-1]
        try:
            self.P.energy(guess_u, guess_w)
        except NonFiniteError:  # the linear guess crosses the indenter: start from the solution itself
            guess_u, guess_w = u0, w0
        return self.solve(x, guess_u, guess_w)[3]


def locate_release_fold(problem: ShellIndentation, u: np.ndarray, w_b: float, *, tol: float = 1e-10,
                        max_halvings: int = 60, max_iter: int = 30) -> ReleaseFold:
    """Locate the fold in ``w_b`` where the last contact node is about to leave the barrier.

    Parameters
    ----------
    problem : ShellIndentation
    u, w_b : a converged equilibrium near the fold, with at least one node in contact (e.g. where
        ``F`` has fallen to nearly zero); on its stable side, or past it (then the gap is doubled
        until ``dw_b/dx < 0``).
    tol : float
        Relative residual tolerance of every gap-constrained solve (times ``problem.residual_scale``).
    max_halvings : int
        How many times the gap may be halved while bracketing the fold.
    max_iter : int
        Newton iterations per gap-constrained solve.

    Returns
    -------
    ReleaseFold

    Raises
    ------
    ReleaseFoldError
        No node in contact, ``dw_b/dx >= 0`` at the start and at every larger gap below ``dhat``, no
        sign change of ``dw_b/dx`` within ``max_halvings`` halvings, or a solve failed.
    """
    st = problem.contact(u, w_b, hessian=False)
    if st.n_active == 0:
        raise ReleaseFoldError("locate_release_fold: no node is in contact at the start")
    # the point nearest to the indenter is the last to leave its range: on the meridian's curve when
    # the barrier integrates over its support, else the nearest fixed sample point
    barrier, x_full, c = problem.barrier, problem.full_state(u), problem.position(w_b)
    if barrier.support_points and barrier.quadrature > 1:
        sample = None
        d_near, _, _, node, _ = barrier.closest_point(x_full, c)
    else:
        sample, d_near = barrier.nearest_sample(x_full, c)
        node = int(barrier.cells(problem.N).cell[sample])
    curve = _GapCurve(problem, sample, tol, max_iter)
    x_hi = problem.dhat - d_near
    try:
        _, _, _, s_hi = curve.solve(x_hi, u, w_b)
        x_start, s_start = x_hi, s_hi
        x_lo, s_lo = x_hi, s_hi
        # the barrier spread over a cell's sample points softens each of them, so the fold can sit at
        # a somewhat larger gap than the F -> 0 event's: a start just past it is bracketed by doubling
        # the gap (a few times: far from a fold, e.g. at the first touch, there is none to find)
        for _ in range(_MAX_DOUBLINGS):
            if s_hi < 0 or not 0.0 < x_hi < 0.5 * problem.dhat:
                break
            x_lo, s_lo = x_hi, s_hi
            try:
                s_hi = curve.dw_dx(2.0 * x_hi)
            except ReleaseFoldError:
                break
            x_hi = 2.0 * x_hi
        if s_hi >= 0:
            raise ReleaseFoldError(f"locate_release_fold: dw_b/dx = {s_start:.3g} >= 0 at the start (node {node}, "
                                   f"gap {x_start:.3g}): the start is not on the stable side of a release fold "
                                   "(nor just past one)")
        if x_hi == x_start:  # the start is on the stable side: halve the gap until dw_b/dx turns positive
            for _ in range(max_halvings):
                x_lo = 0.5 * x_lo
                s_lo = curve.dw_dx(x_lo)
                if s_lo > 0:
                    break
                x_hi = x_lo
            else:
                raise ReleaseFoldError(f"locate_release_fold: dw_b/dx stayed negative down to gap {x_lo:.3g} "
                                       f"(node {node}): no release fold")
        x_f = brentq(curve.dw_dx, x_lo, x_hi, xtol=1e-14 * x_hi, rtol=1e-12)
        curve.dw_dx(x_f)
    except (NonFiniteError, SingularMatrixError) as exc:
        raise ReleaseFoldError(f"locate_release_fold: {exc}") from None
    u_f, w_f, _, s_f = curve.solutions[x_f]
    res = float(np.max(np.abs(problem.residual(u_f, w_f))))
    return ReleaseFold(u=u_f, w_b=w_f, node=node, gap=x_f, residual=res, dw_dx=s_f, evaluations=curve.evaluations)
