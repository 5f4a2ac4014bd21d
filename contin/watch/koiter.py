"""Initial post-buckling at a simple branch point of a conservative model: Koiter's coefficients.

At a simple branch point ``(u_c, p_c)`` of ``f(u, p) = grad E`` with the unit null vector ``phi`` of
the Hessian ``J``, write a state near it as ``u = u_0(p) + xi phi + w`` with ``u_0(p)`` the traced
(fundamental) branch and ``w`` orthogonal to ``phi``.  The branch that emanates is

    p / p_c = 1 + a xi + b xi^2 + ...,        xi = phi^T (u - u_0(p)),

so ``xi`` is the amplitude of the buckling mode at unit 2-norm (in the model's own unknowns).  With
the reduced (Lyapunov-Schmidt) equation ``g(xi, mu) = phi^T f(u_0(p_c + mu) + xi phi + w, p_c + mu)``
expanded as ``C1 xi mu + C2 xi^2 / 2 + C3 xi^3 / 6 + ...``:

* ``C1 = phi^T (d/dp J(u_0(p), p)) phi`` (the rate at which the critical eigenvalue crosses zero),
* ``C2 = phi^T f_uu[phi, phi]``,
* ``C3 = phi^T f_uuu[phi, phi, phi] + 3 phi^T f_uu[phi, chi]`` with ``J chi = -(f_uu[phi, phi])``
  on the complement of ``phi`` and ``chi`` orthogonal to it (the second-order field);

and ``a p_c = -C2 / (2 C1)``; where ``C2`` vanishes (a symmetric bifurcation),
``b p_c = -C3 / (6 C1)``.  ``b < 0`` with ``C1 < 0`` is the unstable-symmetric case behind Koiter's
two-thirds-power law of imperfection sensitivity.

The Hessian is the model's own; its derivatives along ``phi`` and along the branch are central
differences of the Hessian, Richardson-extrapolated (error ~h^4 of the state's scale).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..numerics.linalg import BorderedSolver, SingularMatrixError
from ..path.curve import CorrectorFailure
from ..problem import NonFiniteError, Problem
from ..results.branch import SpecialPoint
from .fold import safe_factorize
from .testfunctions import FOLD_COSINE, smallest_eigenvector

__all__ = ["KoiterCoefficients", "koiter_coefficients", "attach_koiter"]

#: ``|C2|`` below this fraction of ``|C3| + |C1|`` counts as zero (a symmetric bifurcation): the
#: second derivative along ``phi`` is then roundoff and truncation of the differences.
SYMMETRIC_TOL = 1e-6


@dataclass(frozen=True)
class KoiterCoefficients:
    """Koiter's coefficients at a simple branch point (see the module's docstring for the definitions).

    Attributes
    ----------
    p_c : float
        The branch point's parameter.
    a, b : float
        ``p / p_c = 1 + a xi + b xi^2`` along the emanating branch (``nan`` where ``p_c = 0``;
        ``b`` is ``nan`` at an asymmetric point, where ``a`` rules).
    a_abs, b_abs : float
        The same without the division by ``p_c``: ``p - p_c = a_abs xi + b_abs xi^2``.
    symmetric : bool
        Whether ``C2`` vanishes (to :data:`SYMMETRIC_TOL`): a symmetric bifurcation.
    null_vector : ndarray
        ``phi`` (unit 2-norm, its largest entry positive): ``xi`` is the amplitude along it.
    C1, C2, C3 : float
        The reduced equation's coefficients.
    """

    p_c: float
    a: float
    b: float
    a_abs: float
    b_abs: float
    symmetric: bool
    null_vector: np.ndarray = field(repr=False)
    C1: float
    C2: float
    C3: float

    def load(self, xi: np.ndarray | float) -> np.ndarray | float:
        """The parameter along the emanating branch to second order in the amplitude ``xi``."""
        b = 0.0 if math.isnan(self.b_abs) else self.b_abs
        return self.p_c + self.a_abs * np.asarray(xi) + b * np.asarray(xi) ** 2


def koiter_coefficients(problem: Problem, u: np.ndarray, p: float, null_vector: np.ndarray | None = None,
                        path_tangent: tuple[np.ndarray, float] | None = None,
                        step: float = 1e-2) -> KoiterCoefficients:
    """Koiter's coefficients of the branch that emanates from the simple branch point ``(u, p)``.

    Parameters
    ----------
    problem : Problem
        A symmetric (conservative) model: ``f`` is the gradient of an energy.
    u, p : array, float
        The located branch point (for example a ``"branch_point"`` of :func:`contin.continuation`).
    null_vector : array, optional
        A start for the Hessian's null vector (the branch point's ``bifurcation.null_vector``); found by
        inverse iteration without it.
    path_tangent : (array, float), optional
        The traced branch's tangent ``(du, dp)`` at the point.  By default the traced branch is the
        one whose tangent is orthogonal to the null vector (a trivial or symmetric fundamental path);
        the choice matters only at an asymmetric point.
    step : float
        The difference step: along each direction the largest state entry moves by ``step`` times the problem's
        :attr:`~contin.Problem.difference_scale` (default ``1 + max|u|``) and the parameter by at most
        ``step (1 + |p|)``.  The third
        derivative is a second difference of the Hessian, so roundoff grows as ``1 / step^2`` while
        the extrapolated truncation error falls as ``step^4``.

    Returns
    -------
    KoiterCoefficients

    Raises
    ------
    ValueError
        If the problem is not symmetric, the point is a fold (``df/dp`` not orthogonal to the null
        vector), or the critical eigenvalue does not cross zero along the
        traced branch (``C1 = 0``: not a simple branch point of this parameter).
    """
    if not problem.symmetric:
        raise ValueError("koiter_coefficients needs a symmetric problem (the residual the gradient of an energy)")
    u = np.asarray(u, dtype=float)
    p = float(p)
    n = u.size
    phi = smallest_eigenvector(problem, u, p, start=None if null_vector is None else np.asarray(null_vector, float))
    phi = phi if phi[int(np.argmax(np.abs(phi)))] > 0 else -phi
    J = problem.checked_jacobian(u, p)
    f_p = problem.dresidual_dp(u, p)
    cosine = abs(float(phi @ f_p)) / max(float(np.linalg.norm(f_p)), 1e-300)
    if cosine > FOLD_COSINE:
        raise ValueError(f"(u, p) is a fold, not a branch point: df/dp is not orthogonal to the null vector "
                         f"(cosine {cosine:.1e} > {FOLD_COSINE:g})")
    solver = BorderedSolver(J, safe_factorize(problem, J), phi.reshape(n, 1), phi.reshape(1, n), np.zeros((1, 1)),
                            refactor=problem.factorize)
    if path_tangent is None:
        v, _ = solver.solve(-f_p, np.zeros(1))
        t_u, t_p = v, 1.0
    else:
        t_u, t_p = np.asarray(path_tangent[0], dtype=float), float(path_tangent[1])
        if t_p == 0.0:
            raise ValueError("the traced branch's tangent has no parameter component: p is not its load")
        t_u, t_p = t_u / t_p, 1.0
    declared = getattr(problem, "difference_scale", None)
    state_scale = float(declared) if declared else 1.0 + float(np.max(np.abs(u), initial=0.0))

    def step_along(d_u: np.ndarray, d_p: float) -> float:
        """The difference step along ``(d_u, d_p)``: its largest state entry moves by ``step`` of the state's
        scale and the parameter by at most ``step (1 + |p|)`` (the traced tangent, scaled to ``d_p = 1``, may
        be long in the parameter where the state's entries are small)."""
        reach = max(float(np.max(np.abs(d_u), initial=0.0)) / state_scale, abs(d_p) / (1.0 + abs(p)))
        return step / reach

    def jac(du: np.ndarray, dp: float) -> Any:
        return problem.checked_jacobian(u + du, p + dp)

    def first(d_u: np.ndarray, d_p: float, x: np.ndarray) -> np.ndarray:
        """``(J_X[d]) x``: the Hessian's derivative along ``d = (d_u, d_p)`` applied to ``x``."""
        h = step_along(d_u, d_p)

        def central(hh: float) -> np.ndarray:
            return (jac(hh * d_u, hh * d_p) @ x - jac(-hh * d_u, -hh * d_p) @ x) / (2.0 * hh)
        return (4.0 * central(0.5 * h) - central(h)) / 3.0

    def second(x: np.ndarray) -> float:
        """``phi^T J_uu[x, x] phi``, i.e. ``phi^T f_uuu[x, x, phi]``."""
        J0 = J @ phi
        h = step_along(x, 0.0)

        def central(hh: float) -> float:
            return float(phi @ (jac(hh * x, 0.0) @ phi - 2.0 * J0 + jac(-hh * x, 0.0) @ phi)) / hh ** 2
        return (4.0 * central(0.5 * h) - central(h)) / 3.0

    C1 = float(phi @ first(t_u, t_p, phi))
    f_uu_phiphi = first(phi, 0.0, phi)
    C2 = float(phi @ f_uu_phiphi)
    rhs = -(f_uu_phiphi - C2 * phi)
    chi, _ = solver.solve(rhs, np.zeros(1))
    C3 = second(phi) + 3.0 * float(phi @ first(phi, 0.0, chi))
    scale = abs(C1) + abs(C3)
    if C1 == 0.0 or not math.isfinite(C1) or abs(C1) <= 1e-12 * max(scale, 1e-300):
        raise ValueError(f"the critical eigenvalue does not cross zero along the traced branch (C1 = {C1:.3e}): "
                         "not a simple branch point in this parameter")
    symmetric = abs(C2) <= SYMMETRIC_TOL * scale
    a_abs = 0.0 if symmetric else -C2 / (2.0 * C1)
    b_abs = -C3 / (6.0 * C1) if symmetric else math.nan
    norm = p if p != 0.0 else math.nan
    return KoiterCoefficients(p_c=p, a=a_abs / norm, b=b_abs / norm, a_abs=a_abs, b_abs=b_abs, symmetric=symmetric,
                              null_vector=phi, C1=C1, C2=C2, C3=C3)


def attach_koiter(problem: Problem, spt: SpecialPoint) -> None:
    """Put Koiter's coefficients into the record of a located simple branch point of a symmetric problem.

    ``spt.bifurcation.koiter`` gets ``a`` and ``b`` (normalised by ``p_c``; NaN where ``p_c = 0``) and
    ``a_abs``, ``b_abs`` (``p - p_c = a_abs xi + b_abs xi^2``); where they cannot be computed the reason
    is ``spt.info["koiter_error"]``.  Other points are left as they are.
    """
    bif = spt.bifurcation
    if (spt.kind != "branch_point" or not spt.located or bif is None or bif.multiplicity != 1
            or bif.kind not in ("pitchfork", "transcritical") or not problem.symmetric):
        return
    traced = None if bif.traced is None or bif.traced[-1] == 0.0 else (bif.traced[:-1], float(bif.traced[-1]))
    try:
        k = koiter_coefficients(problem, spt.u, spt.p, null_vector=bif.null_vector, path_tangent=traced)
    except (ValueError, CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        spt.info["koiter_error"] = str(exc)
        return
    bif.koiter = {"a": k.a, "b": k.b, "a_abs": k.a_abs, "b_abs": k.b_abs}
