"""Augusti-type models: a rigid strut on a ball joint, held by four springs at its top, under a vertical load.

A rigid strut of length ``L`` stands on a ball joint; its top moves horizontally by ``L q``,
``q = (q1, q2)``, and drops by ``L (1 - sqrt(1 - |q|^2))``, through which the vertical dead load
``P`` works.  Four linear springs of stiffness ``K/2`` hold the top, one along each of ``+-x`` and
``+-y``, anchored at the distance ``a`` from it and unstressed when ``q = epsilon e`` (the
imperfection: an initial tilt ``epsilon`` in the direction ``e``, at angle ``omega`` to ``x``).  In
units of ``K L^2`` and with ``lambda = P / (K L)``, ``beta = L / a``::

    V(q, lambda) = 1/4 sum_i (|A_i - q| - 1/beta)^2 - lambda (1 - sqrt(1 - |q|^2)),
    A_i = (1/beta) d_i + epsilon e,   d_i = +-e_x, +-e_y.

Rigid struts held by springs in two perpendicular planes go back to Augusti (1964) as models of
compound branching (Thompson & Hunt, *A General Theory of Elastic Stability*, Wiley 1973); here the
springs are translational springs at the top, and their geometry sets the symmetry.  Two models:

- ``spring_length=None`` (``beta -> 0``): springs that stay parallel to their axes,
  ``V = 1/2 |q - epsilon e|^2 - lambda (1 - sqrt(1 - |q|^2))``, invariant under every rotation and
  reflection of the plane when ``epsilon = 0``: the **O(2)-symmetric** model;
- a finite ``spring_length = a/L``: the springs turn as the top moves sideways, which couples the two
  directions; the perfect model keeps only the symmetry of the square (``D4``): the **two-mode**
  model.

Closed forms
------------
*Perfect (``epsilon = 0``).*  ``q = 0`` for every ``lambda``; the Hessian there is ``(1 - lambda) I``
(each pair of springs has the stiffness 1 along its axis and none across it to first order), so
``lambda_c = 1`` (``P_c = K L``) is a double branch point.  Expanding to fourth order,
``V = (1 - lambda) |q|^2 / 2 + c4(q) + ...`` with ``c4 = (beta^2 - 1)/8 (q1^4 + q2^4) - (beta^2 + 1/4) q1^2 q2^2``
at ``lambda = 1`` (a spring along ``x`` lengthens by ``beta q2^2 / 2`` when the top moves by ``q2``
across it).  For ``beta = 0`` it is ``-|q|^4 / 8``: a circle of unstable symmetric branches
``lambda = sqrt(1 - |q|^2)`` (exact: ``q (1 - lambda / sqrt(1 - |q|^2)) = 0``).  For ``beta > 0`` two
kinds of branches, each a line of ``D4``: along an axis (``q2 = 0``, exact)
``lambda = sqrt(1 - xi^2) (2 - 1 / sqrt(1 + beta^2 xi^2))`` (``lambda = 1 + (beta^2 - 1) xi^2 / 2 + ...``,
unstable for ``beta < 1``) and along a diagonal, ``lambda = 1 - (3 beta^2 + 2) rho^2 / 4 + ...``
(more unstable).  :meth:`AugustiStrut.path_load` gives every branch on a line of symmetry exactly.

*Imperfect.*  An imperfection along an axis or a diagonal keeps that line invariant (a reflection of
the square fixes it), and on it ``lambda(xi) = S'(xi - epsilon) sqrt(1 - xi^2) / xi`` with ``S`` the
springs' energy along the line.  With ``V = (1 - lambda) xi^2 / 2 + c xi^4 - epsilon xi`` to leading
order, ``c = c4`` along the line (``c < 0``), the limit load is (Koiter 1945; Thompson & Hunt 1973)

    lambda_s = 1 - 3 A^(1/3) (epsilon / 2)^(2/3),   A = -4 c,

Koiter's two-thirds power law: ``A = 1/2`` for ``beta = 0``, ``(1 - beta^2)/2`` along an axis and
``(3 beta^2 + 2)/4`` along a diagonal.  For ``beta = 0`` it is exact in closed form:
``lambda(xi) = (1 - epsilon / xi) sqrt(1 - xi^2)`` has its maximum at ``xi = epsilon^(1/3)``, so
``lambda_s = (1 - epsilon^(2/3))^(3/2) = 1 - (3/2) epsilon^(2/3) + ...``.
:meth:`AugustiStrut.limit_load` gives the exact maximum of ``lambda(xi)`` on the line (a scalar
maximisation), :meth:`AugustiStrut.koiter_limit_load` the leading order.

Symmetry
--------
``symmetry_generators``: the quarter turn ``(q1, q2) -> (-q2, q1)`` and the reflection
``q2 -> -q2`` (``D4``) for the perfect models; the reflection that fixes the imperfection's line for
an imperfect one (``omega`` a multiple of ``pi/4``, or any ``omega`` for ``beta = 0``).  For ``beta = 0`` every rotation is a
symmetry of the perfect model; the quarter turn and the reflection are given (``O(2)`` is not
finitely generated).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq, minimize_scalar

from contin import Problem

__all__ = ["AugustiStrut"]

_DIRECTIONS = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])


class AugustiStrut(Problem):
    """The strut of the module docstring; state ``q = (q1, q2)``, parameter ``lambda = P / (K L)``.

    Parameters
    ----------
    spring_length : float or None
        ``a / L``; None: springs that stay parallel to their axes (the O(2)-symmetric model).
    imperfection : float
        ``epsilon``, the initial tilt (``>= 0``, below 0.5).
    direction : float
        ``omega``, the angle of the imperfection to the ``x`` axis (radians).
    """

    def __init__(self, spring_length: float | None = None, imperfection: float = 0.0, direction: float = 0.0) -> None:
        if spring_length is not None and not spring_length > 1.0:
            raise ValueError(f"AugustiStrut: spring_length = {spring_length!r} must be None or > 1 "
                             f"(springs longer than the strut)")
        if not 0.0 <= imperfection < 0.5:
            raise ValueError(f"AugustiStrut: imperfection = {imperfection!r} must lie in [0, 0.5)")
        self.spring_length = None if spring_length is None else float(spring_length)
        self.beta = 0.0 if spring_length is None else 1.0 / float(spring_length)
        self.epsilon, self.omega = float(imperfection), float(direction)
        self.e = np.array([math.cos(self.omega), math.sin(self.omega)])
        kind = "o2" if spring_length is None else f"two_mode(a/L={spring_length:g})"
        super().__init__(symmetric=True, name=f"augusti_{kind}(eps={imperfection:g})", parameter_name="lambda")
        self._obs = {"q1": lambda q, lam: float(q[0]), "q2": lambda q, lam: float(q[1]),
                     "tilt": lambda q, lam: float(np.hypot(q[0], q[1]))}
        self.symmetry_generators = self._generators()

    @property
    def observables(self):
        return self._obs

    # ---- the model ---------------------------------------------------------------------------------
    def _spring_terms(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per spring: the vector from the top to the anchor, its length and the extension."""
        q = np.asarray(q, dtype=float)
        reach = _DIRECTIONS / self.beta + self.epsilon * self.e - q
        length = np.hypot(reach[:, 0], reach[:, 1])
        # the extension as (|A - q|^2 - a^2) / (|A - q| + a): no cancellation between two lengths near a
        d = self.epsilon * self.e - q
        extension = (2.0 / self.beta * (_DIRECTIONS @ d) + d @ d) / (length + 1.0 / self.beta)
        return reach, length, extension

    def _drop(self, q: np.ndarray) -> tuple[float, float]:
        """``(1 - sqrt(1 - |q|^2), sqrt(1 - |q|^2))``."""
        r2 = float(np.dot(q, q))
        root = math.sqrt(1.0 - r2)
        return r2 / (1.0 + root), root

    def energy(self, q, lam):
        q = np.asarray(q, dtype=float)
        drop, _ = self._drop(q)
        if self.beta == 0.0:
            springs = 0.5 * float(np.sum((q - self.epsilon * self.e) ** 2))
        else:
            springs = 0.25 * float(np.sum(self._spring_terms(q)[2] ** 2))
        return springs - lam * drop

    def residual(self, q, lam):
        q = np.asarray(q, dtype=float)
        _, root = self._drop(q)
        if self.beta == 0.0:
            springs = q - self.epsilon * self.e
        else:
            reach, length, extension = self._spring_terms(q)
            springs = -0.5 * np.sum((extension / length)[:, None] * reach, axis=0)
        return springs - lam * q / root

    def jacobian(self, q, lam):
        q = np.asarray(q, dtype=float)
        _, root = self._drop(q)
        load = lam * (np.eye(2) / root + np.outer(q, q) / root ** 3)
        if self.beta == 0.0:
            return np.eye(2) - load
        reach, length, extension = self._spring_terms(q)
        H = np.zeros((2, 2))
        for r, ell, ext in zip(reach, length, extension):
            n = r / ell
            H += 0.5 * (np.outer(n, n) + ext / ell * (np.eye(2) - np.outer(n, n)))
        return H - load

    def dresidual_dp(self, q, lam):
        q = np.asarray(q, dtype=float)
        return -q / self._drop(q)[1]

    # ---- symmetry ----------------------------------------------------------------------------------
    def _generators(self) -> tuple[sp.csr_matrix, ...]:
        quarter = sp.csr_matrix(np.array([[0.0, -1.0], [1.0, 0.0]]))
        if self.epsilon == 0.0:
            return quarter, sp.csr_matrix(np.diag([1.0, -1.0]))
        if not self.imperfection_on_a_mirror_line:
            return ()
        c, s = math.cos(2 * self.omega), math.sin(2 * self.omega)
        return (sp.csr_matrix(np.array([[c, s], [s, -c]])),)  # the reflection across the line of e

    @property
    def imperfection_on_a_mirror_line(self) -> bool:
        """Whether a reflection of the perfect model fixes the imperfection's line (any line for ``beta = 0``)."""
        multiple = self.omega / (math.pi / 4)
        return self.beta == 0.0 or abs(multiple - round(multiple)) <= 1e-12

    # ---- closed forms ------------------------------------------------------------------------------
    def quartic_coefficient(self, angle: float) -> float:
        """``c4`` of the perfect model at ``lambda = 1`` along the unit direction at ``angle``."""
        c, s = math.cos(angle), math.sin(angle)
        b2 = self.beta ** 2
        return (b2 - 1.0) / 8.0 * (c ** 4 + s ** 4) - (b2 + 0.25) * c ** 2 * s ** 2

    def _line_spring_slope(self, t: float) -> float:
        """``S'(t)``: the springs' force along the imperfection's line at the relative displacement ``t``."""
        if self.beta == 0.0:
            return t
        d = -t * self.e  # q - epsilon e = t e; the springs see only the relative displacement
        reach = _DIRECTIONS / self.beta + d
        length = np.hypot(reach[:, 0], reach[:, 1])
        extension = (2.0 / self.beta * (_DIRECTIONS @ d) + d @ d) / (length + 1.0 / self.beta)
        return float(-0.5 * np.sum((extension / length) * (reach @ self.e)))

    def path_load(self, xi: float | np.ndarray) -> float | np.ndarray:
        """``lambda(xi)`` on the line of ``e`` (``q = xi e``), exact: ``S'(xi - epsilon) sqrt(1 - xi^2) / xi``."""
        xi_arr = np.atleast_1d(np.asarray(xi, dtype=float))
        out = np.array([self._line_spring_slope(x - self.epsilon) * math.sqrt(1.0 - x * x) / x for x in xi_arr])
        return out if np.ndim(xi) else float(out[0])

    def path_state(self, xi: float) -> np.ndarray:
        """The state ``q = xi e`` on the line of the imperfection."""
        return float(xi) * self.e

    def limit_load(self) -> tuple[float, float]:
        """``(xi_s, lambda_s)``: the maximum of ``lambda(xi)`` on the line, ``xi`` in ``(epsilon, 1)``, exactly.

        For ``beta = 0`` it is ``(epsilon^(1/3), (1 - epsilon^(2/3))^(3/2))``.
        """
        if self.epsilon == 0.0:
            raise ValueError("AugustiStrut.limit_load: the perfect model has a branch point, not a limit load")
        if not self.imperfection_on_a_mirror_line:
            raise ValueError("AugustiStrut.limit_load: the path leaves the imperfection's line unless omega is a "
                             "multiple of pi/4")
        if self.beta == 0.0:
            return self.epsilon ** (1.0 / 3.0), (1.0 - self.epsilon ** (2.0 / 3.0)) ** 1.5
        guess = (self.epsilon / (2.0 * -4.0 * self.quartic_coefficient(self.omega))) ** (1.0 / 3.0)
        found = minimize_scalar(lambda x: -self.path_load(x), bounds=(0.2 * guess, min(5.0 * guess, 0.9)),
                                method="bounded", options={"xatol": 1e-14 * guess})
        return float(found.x), float(-found.fun)

    def transverse_stiffness(self, xi: float) -> float:
        """``d2V/dq_perp^2`` on the line's equilibrium at ``xi`` (``lambda = lambda(xi)``), ``q_perp`` across the line.

        Each spring adds ``1/2 [(n . e_perp)^2 + (x / l) (1 - (n . e_perp)^2)]`` (``n`` its unit vector,
        ``l`` its length, ``x`` its extension), the load ``-lambda / sqrt(1 - xi^2)``.  For ``beta = 0``
        it is ``epsilon / xi > 0``.
        """
        across = np.array([-self.e[1], self.e[0]])
        lam = self.path_load(xi)
        if self.beta == 0.0:
            springs = 1.0
        else:
            d = self.epsilon * self.e - self.path_state(xi)
            reach = _DIRECTIONS / self.beta + d
            length = np.hypot(reach[:, 0], reach[:, 1])
            extension = (2.0 / self.beta * (_DIRECTIONS @ d) + d @ d) / (length + 1.0 / self.beta)
            c2 = ((reach @ across) / length) ** 2
            springs = float(0.5 * np.sum(c2 + extension / length * (1.0 - c2)))
        return springs - lam / math.sqrt(1.0 - xi * xi)

    def secondary_branch_point(self) -> tuple[float, float] | None:
        """``(xi_b, lambda_b)`` where the path along the imperfection's line first loses its stability across it.

        The first root of :meth:`transverse_stiffness` for ``xi`` from ``epsilon`` to the limit point's
        ``xi_s``; None when there is none (the limit point comes first).
        """
        xi_s, _ = self.limit_load()
        grid = np.linspace(self.epsilon, xi_s, 401)[1:]
        values = [self.transverse_stiffness(x) for x in grid]
        for a, b, xa, xb in zip(values, values[1:], grid, grid[1:]):
            if a > 0 >= b:
                xi_b = brentq(self.transverse_stiffness, xa, xb, xtol=1e-15)
                return float(xi_b), float(self.path_load(xi_b))
        return None

    def koiter_limit_load(self) -> float:
        """``1 - 3 A^(1/3) (epsilon/2)^(2/3)`` with ``A = -4 c4`` along the imperfection (leading order)."""
        A = -4.0 * self.quartic_coefficient(self.omega)
        if not A > 0:
            raise ValueError("AugustiStrut.koiter_limit_load: the branch along the imperfection is stable (no limit load)")
        return 1.0 - 3.0 * A ** (1.0 / 3.0) * (self.epsilon / 2.0) ** (2.0 / 3.0)
