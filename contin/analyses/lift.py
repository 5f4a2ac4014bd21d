"""Carry a located point of one problem into another problem and locate it there again (a lift).

Two problems often describe the same structure at two levels: a traced model restricted to a symmetric
subspace and a larger view that holds the states the symmetry breaking leads to (an axisymmetric shell and
its view in the angle), a coarse and a fine mesh, a reduced model and the full one.  A bifurcation the first
one locates -- a located ``"branch_point"`` of its own, or a ``"bifurcation"`` into a mode of one of its
operator families (:class:`contin.OperatorFamily`) -- is a simple branch point of the second when the second
holds the mode among its unknowns.  A :class:`Lift` says how a state, a parameter and a mode of the first
problem map into the second's unknowns; :func:`lift_branch_point` maps the point, locates it again on the
second problem and returns a located ``"branch_point"`` that :func:`contin.switch_branch` reads as any other.

Re-location
-----------
The discretisations of the two problems need not agree, so the lifted point is a start, not the answer.  It is
corrected by Newton's method on the extended system of a simple branch point of ``F(x) = f(u, p) = 0``,
``x = (u, p)``, with the left null vector ``psi`` and an unfolding scalar ``mu``::

    f(u, p) + mu psi = 0,     F_x(x)^T psi = 0,     psi0^T psi = 1,

``psi0`` the lifted mode.  Its Jacobian is regular at a simple branch point whose algebraic bifurcation
equation is not degenerate (the 2 x 2 matrix ``psi^T F_xx`` on the kernel of ``F_x`` is nonsingular), which a
pitchfork and a transcritical point both are; ``mu`` vanishes at a branch point and measures how far the
solution is from one otherwise.  For a symmetric problem (an energy's Hessian) the second derivatives it
needs are two directional differences of the Jacobian (``J_u[psi]`` and ``f_pu psi``): the third derivatives of
an energy are symmetric, so ``(J_u[du]) psi = (J_u[psi]) du``.  Newton converges to the exact root whatever
the difference step, as the residual is evaluated exactly.

The located point records how far it moved from the lifted one: in the parameter (``info["moved_p"]``), in
the state (``info["moved_u"]``, max norm) and the angle between the lifted mode and the null vector found
(``info["mode_angle"]``, radians).  Its :class:`contin.Bifurcation` comes from the algebraic bifurcation
equation at the located point (:func:`contin.watch.testfunctions.bifurcation_directions`), the traced
branch's direction being the source branch's tangent carried by the lift.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..path.curve import max_abs
from ..problem import Problem
from ..results.branch import SpecialPoint
from ..watch.fold import safe_factorize
from ..watch.testfunctions import bifurcation_directions

__all__ = ["Lift", "LiftError", "lift_branch_point"]

#: Relative Newton steps below which a step that no longer contracts (to half the previous one) is rounding:
#: the iteration ends there.
ROUNDING_FLOOR = 1e-9


class LiftError(ValueError):
    """A point that cannot be lifted (not a bifurcation, a mode the lift does not carry), or one the target
    problem has no branch point near."""


def _same(p: float) -> float:
    return float(p)


@dataclass(frozen=True)
class Lift:
    """How a state, a parameter and a mode of a source problem map into a target problem's unknowns.

    Attributes
    ----------
    state : callable ``(u, p) -> u'``
        The target's unknowns of the source's state ``u`` at its parameter ``p``.
    parameter : callable ``p -> p'``
        The target's parameter of the source's (default: the same value).
    mode : callable ``vector -> vector'``
        A mode of the source as a direction in the target's unknowns: a vector of the operator family's
        key :attr:`key` (``info["mode"]`` of a ``"bifurcation"``), or of the source's own unknowns (the
        kernel of a ``"branch_point"``) when :attr:`family` is None.
    family : str, optional
        The operator family whose modes :attr:`mode` maps (``info["family"]``), None for the source's own
        branch points.
    key : optional
        The family's key whose modes :attr:`mode` maps (``info["key"]``, e.g. a wave number).
    name : str
        What the lift is, for messages.
    """

    state: Callable[[np.ndarray, float], np.ndarray]
    mode: Callable[[np.ndarray], np.ndarray]
    parameter: Callable[[float], float] = _same
    family: str | None = None
    key: Any = None
    name: str = "lift"

    def tangent(self, u: np.ndarray, p: float, t_u: np.ndarray, t_p: float) -> np.ndarray:
        """The direction ``(t_u, t_p)`` of the source at ``(u, p)`` as the target's ``(t_u', t_p')``: the
        derivative of the lift along it, by a central difference (exact for an affine lift)."""
        size = max(float(np.max(np.abs(t_u), initial=0.0)), abs(float(t_p)), 1e-300)
        h = 1e-6 * (1.0 + float(np.max(np.abs(u), initial=0.0)) + abs(float(p))) / size
        up = self.state(u + h * t_u, p + h * t_p), self.parameter(p + h * t_p)
        dn = self.state(u - h * t_u, p - h * t_p), self.parameter(p - h * t_p)
        return np.concatenate([(np.asarray(up[0]) - np.asarray(dn[0])) / (2 * h), [(up[1] - dn[1]) / (2 * h)]])


def lift_branch_point(point: SpecialPoint, source: Problem, target: Problem, lift: Lift, *,
                      tol: float = 1e-12, max_iter: int = 30) -> SpecialPoint:
    """A located bifurcation of ``source`` as a located simple branch point of ``target``.

    The point's state and mode are carried by ``lift``; the branch point is then located again on
    ``target`` by Newton's method on its extended system, started from the lifted state, the lifted
    parameter and the lifted mode as the null vector (module docstring).

    Parameters
    ----------
    point : SpecialPoint
        A located point of ``source``: a ``"bifurcation"`` of the operator family ``lift.family`` into its
        key ``lift.key`` whose ``info["mode"]`` is stored, or (``lift.family`` None) a ``"branch_point"``
        with its :class:`contin.Bifurcation` record.
    source, target : Problem
        The problem ``point`` lies on and the one it is lifted into (symmetric: an energy's Hessian).
    lift : Lift
    tol : float
        Newton ends when its step changes the state and the parameter by less than ``tol`` relative to
        their sizes (and the unfolding scalar by less than ``tol`` relative to the residual's scale), or
        when steps below :data:`ROUNDING_FLOOR` stop contracting (the rounding floor of a fine mesh).
    max_iter : int
        Newton steps at most.

    Returns
    -------
    SpecialPoint
        Kind ``"branch_point"``, located, on ``target``, label ``"lifted"``; its ``bifurcation`` is ready
        for :func:`contin.switch_branch`.  ``info``: ``lifted_from`` (the source point's kind, parameter,
        family and key), ``moved_p`` (located minus lifted parameter), ``moved_u`` (max norm of the state's
        change), ``mode_angle`` (radians, between the lifted mode and the located null vector), ``unfolding``
        (``mu`` at the root, relative to the residual's scale) and ``newton_steps``.

    Raises
    ------
    LiftError
        The point is not a located bifurcation of the lift's kind, the lifted vectors do not fit ``target``,
        ``target`` is not symmetric, or Newton does not converge to a branch point near the lifted one.
    """
    mode, traced = _source_vectors(point, source, lift)
    if not target.symmetric:
        raise LiftError(f"{lift.name}: the target problem {target.name!r} is not symmetric; the branch point's "
                        "extended system is located with the second derivatives of an energy")
    u0 = np.asarray(lift.state(np.asarray(point.u, dtype=float), float(point.p)), dtype=float)
    p0 = float(lift.parameter(float(point.p)))
    psi0 = np.asarray(lift.mode(mode), dtype=float)
    n = np.asarray(target.residual(u0, p0)).size if u0.ndim == 1 else -1
    for what, v in (("state", u0), ("mode", psi0)):
        if v.shape != (n,) or not np.all(np.isfinite(v)):
            raise LiftError(f"{lift.name}: the lifted {what} must be a finite vector of the target's {n} unknowns, "
                            f"got shape {v.shape}")
    nrm = float(np.linalg.norm(psi0))
    if nrm == 0.0:
        raise LiftError(f"{lift.name}: the lifted mode is zero (the target's unknowns do not hold it)")
    psi0 = psi0 / nrm
    u, p, psi, steps, mu = _newton(target, u0, p0, psi0, tol, max_iter, lift.name)
    sec = None if traced is None else lift.tangent(np.asarray(point.u, dtype=float), float(point.p),
                                                   traced[:-1], float(traced[-1]))
    sec_u, sec_p = (np.zeros(n), 1.0) if sec is None else (sec[:n], float(sec[n]))
    record = bifurcation_directions(target, u, p, sec_u, sec_p, start=psi / np.linalg.norm(psi))
    phi = record.kernel[0]
    along = abs(float(phi @ psi0))
    # the angle from its sine and cosine together: acos alone loses half the digits near zero
    angle = math.atan2(float(np.linalg.norm(phi - (phi @ psi0) * psi0)), along)
    info = {"lifted_from": {"kind": point.kind, "p": float(point.p), "family": point.info.get("family"),
                            "key": point.info.get("key"), "lift": lift.name},
            "moved_p": p - p0, "moved_u": float(np.max(np.abs(u - u0), initial=0.0)),
            "mode_angle": angle, "unfolding": mu, "newton_steps": steps,
            "method": "Newton on the branch point's extended system from the lifted point"}
    return SpecialPoint("branch_point", p, u, target.evaluate_observables(u, p),
                        residual=max_abs(target.residual(u, p)), located=True, label="lifted", info=info,
                        bifurcation=record)


def _source_vectors(point: SpecialPoint, source: Problem, lift: Lift) -> tuple[np.ndarray, np.ndarray | None]:
    """The mode to lift and the source branch's tangent ``(t_u, t_p)`` at the point (None if unknown)."""
    if not point.located:
        raise LiftError(f"{lift.name}: the {point.kind} at {source.parameter_name} = {point.p:.10g} is not located; "
                        "only a located point can be lifted")
    if point.kind == "bifurcation":
        fam, key = point.info.get("family"), point.info.get("key")
        if lift.family is None or fam != lift.family or key != lift.key:
            raise LiftError(f"{lift.name}: the point is a bifurcation into {fam} = {key!r}, but the lift carries "
                            + (f"the modes of {lift.family} = {lift.key!r}" if lift.family is not None
                               else "the source's own kernel (a 'branch_point')"))
        mode = point.info.get("mode")
        if mode is None:
            raise LiftError(f"{lift.name}: the bifurcation carries no mode (info['mode']); its operator family must "
                            "store vectors")
        return np.asarray(mode, dtype=float), _tangent(source, np.asarray(point.u, dtype=float), float(point.p))
    if point.kind == "branch_point":
        bif = point.bifurcation
        if lift.family is not None:
            raise LiftError(f"{lift.name}: the lift carries modes of the family {lift.family!r}, but the point is a "
                            "branch point of the source itself")
        if bif is None or bif.multiplicity != 1:
            raise LiftError(f"{lift.name}: only a simple branch point with its bifurcation record can be lifted")
        return np.asarray(bif.kernel[0], dtype=float), bif.traced
    raise LiftError(f"{lift.name}: a {point.kind!r} point is not a bifurcation; only a located 'bifurcation' of an "
                    "operator family or a located 'branch_point' can be lifted")


def _tangent(problem: Problem, u: np.ndarray, p: float) -> np.ndarray | None:
    """``(v, 1)`` with ``J v = -f_p``: the source branch's direction where its own Jacobian is regular (it is
    at a bifurcation into another mode); None where it is singular."""
    J = problem.checked_jacobian(u, p)
    F = safe_factorize(problem, J)
    if F is None:
        return None
    v = -np.asarray(F.solve(np.asarray(problem.dresidual_dp(u, p), dtype=float)), dtype=float)
    return np.concatenate([v, [1.0]]) if np.all(np.isfinite(v)) else None


def _newton(problem: Problem, u: np.ndarray, p: float, psi0: np.ndarray, tol: float, max_iter: int,
            name: str) -> tuple[np.ndarray, float, np.ndarray, int, float]:
    """Root ``(u, p, psi, steps, mu)`` of the extended system (module docstring), ``mu`` relative to the
    residual's scale."""
    n = u.size
    psi, mu = psi0.copy(), 0.0
    previous = math.inf
    scale = float(getattr(problem, "residual_scale", 1.0) or 1.0)
    dp_step = 1e-4 * (abs(p) if p != 0.0 else 1.0)
    for step in range(1, max_iter + 1):
        J = sp.csr_matrix(problem.checked_jacobian(u, p))
        fp = np.asarray(problem.dresidual_dp(u, p), dtype=float)
        f = np.asarray(problem.residual(u, p), dtype=float)
        G = np.concatenate([f + mu * psi, J @ psi, [fp @ psi], [psi0 @ psi - 1.0]])
        # second derivatives by central differences along psi (in u) and in p
        h = 1e-4 * (1.0 + float(np.max(np.abs(u), initial=0.0))) / max(float(np.max(np.abs(psi))), 1e-300)
        S = (sp.csr_matrix(problem.checked_jacobian(u + h * psi, p))
             - sp.csr_matrix(problem.checked_jacobian(u - h * psi, p))) / (2 * h)
        Jp_psi = (np.asarray(problem.dresidual_dp(u + h * psi, p))
                  - np.asarray(problem.dresidual_dp(u - h * psi, p))) / (2 * h)
        fpp_psi = float((np.asarray(problem.dresidual_dp(u, p + dp_step))
                         - np.asarray(problem.dresidual_dp(u, p - dp_step))) @ psi) / (2 * dp_step)
        A = sp.bmat([[J, _column(fp), mu * sp.identity(n) if mu else None, _column(psi)],
                     [S, _column(Jp_psi), J, None],
                     [_column(Jp_psi).T, sp.csr_matrix([[fpp_psi]]), _column(fp).T, None],
                     [None, None, _column(psi0).T, sp.csr_matrix((1, 1))]], format="csc")
        try:
            d = splu(A).solve(-G)
        except RuntimeError as exc:
            raise LiftError(f"{name}: the branch point's extended system is singular near the lifted point "
                            f"({problem.parameter_name} = {p:.10g}): not a simple branch point of the target "
                            f"({exc})") from None
        if not np.all(np.isfinite(d)):
            raise LiftError(f"{name}: Newton on the branch point's extended system gave a non-finite step at "
                            f"{problem.parameter_name} = {p:.10g}")
        u, p, psi, mu = u + d[:n], p + float(d[n]), psi + d[n + 1:2 * n + 1], mu + float(d[-1])
        size = max(float(np.max(np.abs(d[:n]))) / (1.0 + float(np.max(np.abs(u)))), abs(float(d[n])) / (1.0 + abs(p)),
                   abs(float(d[-1])) / scale)
        # converged, or stalled at the rounding floor: once the steps are that small they stop contracting
        # (on a fine mesh the floor lies above tol; the point is then as good as its rounding allows)
        if size <= tol or (size <= ROUNDING_FLOOR and size >= 0.5 * previous):
            if abs(mu) > 1e-6 * scale:
                raise LiftError(f"{name}: no branch point of the target near the lifted point: the extended system's "
                                f"root at {problem.parameter_name} = {p:.10g} has the unfolding mu = {mu:.3g}, not 0 "
                                f"(relative to the residual's scale {scale:.3g})")
            return u, p, psi, step, mu / scale
        previous = size
    raise LiftError(f"{name}: Newton on the branch point's extended system did not converge from the lifted point "
                    f"in {max_iter} steps (last {problem.parameter_name} = {p:.10g}); the target has no simple branch "
                    "point near it")


def _column(v: np.ndarray) -> sp.csr_matrix:
    return sp.csr_matrix(np.asarray(v, dtype=float).reshape(-1, 1))
