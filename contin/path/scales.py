"""The state and load scales ``(U, P)`` a run measures where it starts, and what the stiffness adds to them.

The open arclength weights are ``1 / U`` and ``1 / P`` (:meth:`contin.path.curve.Curve.calibrate`),
so a step of the default ``ds_max = 0.2`` moves the state by at most a fifth of ``U`` or the load by
a fifth of ``P``.  The sizes of the start point alone can mislead in two ways, and the stiffness tells
both apart:

* a path that is nearly rigid before it buckles (a ring whose membrane is a million times stiffer
  than its bending) moves the state so little per unit load that the load which would move it by its
  own size, ``rms(u) / rms(du/dp)``, lies far beyond the buckling loads; the load scale is then capped
  by the distance to the first critical load estimated from the start's linearization
  (:func:`critical_mode`): ``J(u0, p0) + mu dJ/dp`` singular, ``dJ/dp`` taken along the path;
* a start whose state is tiny (an imperfection of ``1e-5``) gives a state scale that the path outgrows
  by orders of magnitude once it leaves the critical load, and the run crawls; the state scale is
  raised to the amplitude at which the state leaving that critical load, along its mode, has moved the
  load by ``P`` (:meth:`CriticalMode.amplitude_for`).

At a branch point the Jacobian is singular and the same relation is read the other way, from the
emanating branch's Koiter coefficients: the load scale is at least the load change of that branch over
one state scale (:func:`emanating_load_change`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..numerics.linalg import SingularMatrixError
from ..problem import NonFiniteError, Problem

__all__ = ["ZERO_SCALE", "CriticalMode", "critical_mode", "emanating_load_change", "rms", "scales_from_sensitivity",
           "start_scales", "stiffness_scales"]

#: Below this fraction of a reference scale a size is zero up to roundoff (see :func:`start_scales`).
ZERO_SCALE = 1e-8
#: Up to this size the linearized buckling problem is solved densely, above it by Arnoldi iteration.
DENSE_EIGEN_SIZE = 24
#: How many decades above the start's state scale :meth:`CriticalMode.amplitude_for` looks.
AMPLITUDE_DECADES = 12
#: The load step of the difference that gives ``dJ/dp`` along the path, relative to the load scale.
JACOBIAN_RATE_STEP = 1e-6

#: Failures of a model evaluated where it may not be defined (a probe's amplitude past its domain).
_OUTSIDE = (NonFiniteError, ValueError, ArithmeticError, SingularMatrixError, np.linalg.LinAlgError)


def rms(x: np.ndarray) -> float:
    """Root-mean-square of a vector (0 for an empty one)."""
    return float(np.linalg.norm(x) / math.sqrt(max(x.size, 1)))


def start_scales(u: np.ndarray, p: float, fp: np.ndarray, F: Any,
                 reference: tuple[float, float] | None = None) -> tuple[float, float]:
    """State and parameter scales ``(U, P)`` of a start point from its sizes, in the model's units.

    ``U`` is the RMS size of the state and ``P`` the size of the parameter, each at least what the
    other implies through the sensitivity ``S = rms(du/dp) = rms(J^{-1} df/dp)``:
    ``U = max(rms(u), S |p|)`` and ``P = max(|p|, rms(u) / S)`` (so a start at ``p = 0`` gets the
    load that would move the state by its own size, and a start at ``u = 0`` the state change the
    load causes).  Both scale with the units of ``u`` and ``p``.  A scale with no size to measure
    (``u = 0``, ``p = 0``) is taken from ``reference`` (the scales an earlier run of the same
    problem measured, see :attr:`contin.Problem.reference_scales`), else 1: the user's units are
    then all there is.  With a reference, a size below ``1e-8`` of it is zero (a branch point
    located at ``p = 1e-21`` is at ``p = 0``, not at a scale of ``1e-21``).  What the stiffness
    changes in them is :func:`stiffness_scales`.

    Parameters
    ----------
    u, p : the start point.
    fp : ``df/dp`` there.
    F : the factorization of the Jacobian there, or None when it is singular.
    reference : (U, P), optional
    """
    sens = math.nan
    if F is not None:
        try:
            sens = rms(np.asarray(F.solve(fp), dtype=float))
        except (SingularMatrixError, np.linalg.LinAlgError, ValueError):
            pass
    return scales_from_sensitivity(u, p, sens, reference)


def scales_from_sensitivity(u: np.ndarray, p: float, sens: float,
                            reference: tuple[float, float] | None = None) -> tuple[float, float]:
    """``(U, P)`` of :func:`start_scales` from the point and a sensitivity ``S`` found otherwise (NaN or 0: none)."""
    ref_U, ref_P = reference if reference is not None else (1.0, 1.0)
    u_size, p_size = rms(u), abs(float(p))
    if reference is not None:
        u_size = u_size if u_size > ZERO_SCALE * ref_U else 0.0
        p_size = p_size if p_size > ZERO_SCALE * ref_P else 0.0
    if math.isfinite(sens) and sens > 0:
        U, P = max(u_size, sens * p_size), max(p_size, u_size / sens)
    else:
        U, P = u_size, p_size
    if reference is not None:
        # a size that only a roundoff sensitivity implies (df/dp of a symmetric state, 1e-33 where it
        # should be zero, times the load) is no size either
        U = U if U > ZERO_SCALE * ref_U else 0.0
        P = P if P > ZERO_SCALE * ref_P else 0.0
    return (U if U > 0 else ref_U), (P if P > 0 else ref_P)


def stiffness_scales(U: float, P: float, p: float, critical: CriticalMode) -> tuple[float, float]:
    """The scales ``(U, P)`` of :func:`start_scales` corrected by the start's first critical load.

    ``P`` is at most the distance to the critical load (but never below the start's own ``|p|``),
    and then ``U`` at least the amplitude at which the state leaving the critical load along its mode
    has moved the load by ``P`` (:meth:`CriticalMode.amplitude_for`), both to three significant
    digits; the module docstring says why.

    Parameters
    ----------
    U, P : the scales of :func:`start_scales`.
    p : the start's parameter.
    critical : the start's :func:`critical_mode`.
    """
    P = max(abs(float(p)), min(P, _significant(critical.distance)))
    return max(U, _significant(critical.amplitude_for(P, U))), P


def _significant(x: float, digits: int = 3) -> float:
    """``x`` to a few significant digits.

    The stiffness estimates carry the roundoff of a difference of Jacobians in their last digits
    (1e-9 of a stiff ring's load scale differs between BLAS thread counts); a scale is an order of
    magnitude, and rounded it gives the same steps on every machine.
    """
    return float(f"{x:.{digits}g}") if math.isfinite(x) and x != 0 else x


def emanating_load_change(koiter: Mapping[str, float], U: float, n: int) -> float:
    """The load change of the branch leaving a simple branch point over the state scale ``U`` (0 when unknown).

    Koiter's ``p - p_c = a_abs xi + b_abs xi^2`` (:func:`contin.koiter_coefficients`) has ``xi`` the
    amplitude of the unit-2-norm null vector; a state change of RMS size ``U`` in ``n`` unknowns is
    ``xi = U sqrt(n)``.
    """
    xi = U * math.sqrt(max(n, 1))
    change = 0.0
    for key, power in (("a_abs", 1), ("b_abs", 2)):
        coefficient = koiter.get(key, math.nan)
        if math.isfinite(coefficient):
            change += abs(coefficient) * xi ** power
    return change if math.isfinite(change) else 0.0


@dataclass(frozen=True)
class CriticalMode:
    """The first critical load of a start point to first order, and the state's mode there.

    Attributes
    ----------
    problem : Problem
    u, p : the linear prediction of the state at the critical load, ``u0 + mu du/dp``, and that load.
    mode : the critical mode (RMS 1).
    jacobian : the Jacobian at ``(u, p)``.
    load_stiffness : ``||dJ/dp mode||``: the force per unit amplitude a unit change of load puts on the mode.
    distance : ``|mu|``, the distance from the start's load to the critical load.
    """

    problem: Problem
    u: np.ndarray
    p: float
    mode: np.ndarray
    jacobian: Any
    load_stiffness: float
    distance: float

    def load_offset(self, amplitude: float) -> float:
        """How far from the critical load the load must be to hold the state at ``u +- amplitude mode``.

        The nonlinear part of the force, ``f(u + a v, p) - f(u, p) - a J v``, is balanced by the load
        offset times ``a dJ/dp v`` (the larger of the two signs of ``a`` counts).  Inf where the model
        cannot be evaluated (past its domain).
        """
        linear = amplitude * np.asarray(self.jacobian @ self.mode, dtype=float).ravel()
        worst = 0.0
        try:
            base = self.problem.checked_residual(self.u, self.p)
            for a, lin in ((amplitude, linear), (-amplitude, -linear)):
                step = a * self.mode
                if self.problem.max_step_fraction(self.u, self.p, step, 0.0) < 1.0:
                    return math.inf
                force = self.problem.checked_residual(self.u + step, self.p) - base - lin
                worst = max(worst, float(np.linalg.norm(force)))
        except _OUTSIDE:
            return math.inf
        return worst / (amplitude * self.load_stiffness)

    def amplitude_for(self, load: float, start: float) -> float:
        """The amplitude (RMS) at which :meth:`load_offset` reaches ``load``, looked for from ``start`` up.

        Decades up from ``start``, then interpolated in the logarithms.  ``start`` itself when the
        offset is reached there already, or not within :data:`AMPLITUDE_DECADES` decades (a model
        without nonlinearity along the mode sets no state scale); the largest amplitude the model
        could be evaluated at when its domain ends first.
        """
        if not (load > 0 and start > 0 and math.isfinite(load) and math.isfinite(start)):
            return start
        a, offset = start, self.load_offset(start)
        if offset >= load:
            return start
        for _ in range(AMPLITUDE_DECADES):
            a_next = 10.0 * a
            offset_next = self.load_offset(a_next)
            if math.isinf(offset_next):
                return a
            if offset_next >= load:
                if offset > 0:
                    return a * 10.0 ** (math.log(load / offset) / math.log(offset_next / offset))
                return a_next
            a, offset = a_next, offset_next
        return start


def critical_mode(problem: Problem, u: np.ndarray, p: float, J: Any, fp: np.ndarray, F: Any,
                  load_scale: float) -> CriticalMode | None:
    """The start's first critical load to first order: the smallest ``|mu|`` with ``J + mu dJ/dp`` singular.

    ``dJ/dp`` is the Jacobian's rate along the path, ``(J(u + h du/dp, p + h) - J) / h`` with
    ``du/dp = -J^{-1} df/dp`` and ``h`` a millionth of ``load_scale``.  The largest eigenvalue
    ``nu`` of ``J^{-1} dJ/dp`` in modulus gives ``mu = -1 / nu`` (linearized buckling; a complex
    ``nu`` still gives the load over which the stiffness changes by its own size).  Unlike the smallest
    eigenvalue of ``J`` divided by its rate, this sees the mode that softens first even when a mode the
    load does not touch is softer at the start.

    Returns None where there is nothing to measure: no factorization (a singular start), a critical
    load within :data:`ZERO_SCALE` of ``load_scale`` (the start is critical itself, as a resumed
    branch point is), a load that does not change the stiffness, or a failed eigen-solve.
    """
    n = u.size
    if F is None or n == 0 or not (load_scale > 0 and math.isfinite(load_scale)):
        return None
    try:
        du_dp = -np.asarray(F.solve(fp), dtype=float)
        h = JACOBIAN_RATE_STEP * load_scale
        rate = (problem.checked_jacobian(u + h * du_dp, p + h) - J) / h
        nu, mode = _largest_eigenpair(J, F, rate, n)
    except _OUTSIDE:
        return None
    if not (np.isfinite(nu) and abs(nu) > 0):
        return None
    # a complex pair: the stiffness still changes by its own size over 1 / |nu| of load
    mu = -1.0 / nu.real if abs(nu.imag) <= 1e-8 * abs(nu) else -math.copysign(1.0 / abs(nu), nu.real)
    if abs(mu) <= ZERO_SCALE * load_scale:
        return None  # the start is the critical point (a located branch point): its sizes are all there is
    mode = np.real(mode) if np.linalg.norm(np.real(mode)) >= np.linalg.norm(np.imag(mode)) else np.imag(mode)
    size = rms(mode)
    if not size > 0:
        return None
    mode = mode / size
    u_c, p_c = u + mu * du_dp, p + mu
    try:
        J_c = problem.checked_jacobian(u_c, p_c)
    except _OUTSIDE:
        return None
    load_stiffness = float(np.linalg.norm(np.asarray(rate @ mode, dtype=float)))
    if not (load_stiffness > 0 and math.isfinite(load_stiffness)):
        return None
    return CriticalMode(problem, u_c, p_c, mode, J_c, load_stiffness, abs(mu))


def _largest_eigenpair(J: Any, F: Any, rate: Any, n: int) -> tuple[complex, np.ndarray]:
    """The eigenvalue of ``J^{-1} rate`` largest in modulus and its eigenvector."""
    if n <= DENSE_EIGEN_SIZE:
        dense = (lambda A: A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float))
        w, V = np.linalg.eig(np.linalg.solve(dense(J), dense(rate)))
        k = int(np.argmax(np.abs(w)))
        return complex(w[k]), V[:, k]
    from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, LinearOperator, eigs  # slow to import

    operator = LinearOperator((n, n), matvec=lambda x: F.solve(np.asarray(rate @ np.real(x), dtype=float)), dtype=float)
    start = np.random.default_rng(0).standard_normal(n)  # a fixed start: the same scales every run
    try:
        w, V = eigs(operator, k=1, which="LM", v0=start, ncv=min(n - 1, 20), tol=1e-6, maxiter=100)
    except ArpackNoConvergence as exc:
        w, V = exc.eigenvalues, exc.eigenvectors
    except ArpackError:
        return complex(math.nan), np.zeros(n)
    if not len(w):
        return complex(math.nan), np.zeros(n)
    return complex(w[0]), V[:, 0]
