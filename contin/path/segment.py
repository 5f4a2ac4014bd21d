"""The stretch of curve between two accepted points, where special points are located.

A test function that changes sign between accepted points ``A`` and ``B`` is located on the curve
itself: points between them are parametrised by their distance ``sigma`` from ``A`` along ``A``'s
tangent, each converged by the corrector (started from a cubic Hermite interpolant), and the root in
``sigma`` is found by Brent's method.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .corrector import correct
from .curve import CorrectorFailure, Curve, Point

__all__ = ["Segment", "bracketed_root"]


class Segment:
    """Points on the curve between A and B parametrised by the hyperplane coordinate sigma of A."""

    def __init__(self, curve: Curve, A: Point, B: Point) -> None:
        self.curve, self.A, self.B = curve, A, B
        self.sigma_B = curve.inner(A.t_u, A.t_p, B.u - A.u, B.p - A.p)
        self._cache: dict[float, tuple[np.ndarray, float, float]] = {}

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

    def point(self, sigma: float) -> tuple[np.ndarray, float, float]:
        """Converged point at hyperplane distance ``sigma`` from A: ``(u, p, residual)``."""
        if sigma in self._cache:
            return self._cache[sigma]
        A = self.A
        if sigma == 0.0:
            out = (A.u, A.p, A.residual)
        elif sigma == self.sigma_B:
            out = (self.B.u, self.B.p, self.B.residual)  # the step's own end, converged already
        else:
            try:
                # correct() refuses a start outside the model's domain; the linear predictor is the fallback
                c = correct(self.curve, A, sigma, max_iter=20, start=self.interpolate(sigma))
            except CorrectorFailure:
                c = correct(self.curve, A, sigma, max_iter=20)
            out = (c.u, c.p, c.residual)
        self._cache[sigma] = out
        return out

    def tangent(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        """Unit tangent at a point returned by :meth:`point`, oriented like A's."""
        # linearized at the point itself, not taken from the corrector's last linearization (an update
        # away): a test function built on the tangent (an observable's rate along the curve) must not
        # carry that update as an error, which moved located extrema by up to 1e-7 of the length
        # scale (tests/test_located_extrema.py); the model's Jacobian there is mostly cached
        t_u, t_p, _ = self.curve.tangent(u, p, self.A.t_u, self.A.t_p)
        return t_u, t_p

    def root(self, fun: Callable[[float], float], f_A: float, f_B: float, rtol: float, ftol: float = 0.0) -> float:
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

        def g(s: float) -> float:
            if s == a:
                return f_A
            if s == b:
                return f_B
            v = fun(s)
            if abs(v) <= f_small:
                raise _RootFound(s)
            return v
        try:
            return bracketed_root(g, a, b, f_A, f_B, xtol=rtol * abs(b))
        except _RootFound as found:
            return found.sigma


def bracketed_root(fun: Callable[[float], float], a: float, b: float, f_a: float, f_b: float, xtol: float,
                   max_evaluations: int = 100) -> float:
    """Root of ``fun`` in the bracket ``[a, b]`` (``f_a``, ``f_b`` of opposite signs) by Brent's method.

    Brent's safeguarded mix of inverse quadratic interpolation, secant and bisection, with one change
    for expensive functions: when an interpolation step is already shorter than the tolerance, its
    end is returned without evaluating it.  Interpolation converges superlinearly there, so the end's
    error is far below the step; the classical algorithm spends one or two more evaluations (each a
    corrected point here) confirming the bracket at the tolerance's width.

    Parameters
    ----------
    fun : callable
        The function (each call may be costly).
    a, b : float
        The bracket.
    f_a, f_b : float
        ``fun(a)`` and ``fun(b)``, of opposite signs (or one of them zero).
    xtol : float
        Absolute tolerance on the root.
    max_evaluations : int
        Evaluations of ``fun`` allowed.

    Raises
    ------
    ValueError
        If ``f_a`` and ``f_b`` have the same sign.
    RuntimeError
        If the tolerance is not reached within ``max_evaluations``.
    """
    if f_a == 0.0:
        return a
    if f_b == 0.0:
        return b
    if (f_a > 0) == (f_b > 0):
        raise ValueError(f"bracketed_root: no sign change on [{a}, {b}] (values {f_a}, {f_b})")
    eps = np.finfo(float).eps
    c, f_c = a, f_a  # the contrapoint: fun(b) and fun(c) have opposite signs
    step = previous_step = b - a
    for _ in range(max_evaluations):
        if (f_b > 0) == (f_c > 0):
            c, f_c = a, f_a
            step = previous_step = b - a
        if abs(f_c) < abs(f_b):  # b is the best estimate so far
            a, b, c = b, c, b
            f_a, f_b, f_c = f_b, f_c, f_b
        tol = 2.0 * eps * abs(b) + 0.5 * xtol
        half = 0.5 * (c - b)
        if abs(half) <= tol or f_b == 0.0:
            return b
        interpolated = False
        if abs(previous_step) >= tol and abs(f_a) > abs(f_b):
            s = f_b / f_a
            if a == c:  # two points: secant
                num, den = 2.0 * half * s, 1.0 - s
            else:  # three points: inverse quadratic interpolation
                q, r = f_a / f_c, f_b / f_c
                num = s * (2.0 * half * q * (q - r) - (b - a) * (r - 1.0))
                den = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if num > 0:
                den = -den
            else:
                num = -num
            # accept the interpolation only if it stays well inside the bracket and shrinks fast enough
            if 2.0 * num < min(3.0 * half * den - abs(tol * den), abs(previous_step * den)):
                previous_step, step = step, num / den
                interpolated = True
        if not interpolated:
            previous_step = step = half
        if interpolated and abs(step) <= tol:
            return b + step
        a, f_a = b, f_b
        b += step if abs(step) > tol else math.copysign(tol, half)
        f_b = fun(b)
    raise RuntimeError(f"bracketed_root: no convergence in {max_evaluations} evaluations")


class _RootFound(Exception):
    """Raised inside a root search when the test function is zero to within its noise."""

    def __init__(self, sigma: float) -> None:
        super().__init__(sigma)
        self.sigma = sigma
