"""Phase boundaries of the point-loaded cap, traced as curves in the ``(phi_hat, h/R)`` plane.

``docs/model.md#classes``: a cap is monotonous, monostable or bistable according to the limit
points (folds) of its force ``F`` along the equilibrium path.

* **Bistable / monostable**: the lower limit load ``F_min`` crosses zero.  A fold in ``F`` at
  ``F = 0`` is a fold of the unloaded cap in any other parameter, so at fixed ``phi_hat`` it is a fold
  in ``h`` of the family at ``F = 0`` (:class:`contin.FamilyProblem`), and continuing that fold in
  ``phi_hat`` (:class:`contin.FoldCurveProblem`) traces the boundary.
* **Monostable / monotonous**: the two folds ``F_max`` and ``F_min`` meet at a cusp, a fold of the
  fold curve in ``h``; continuing the cusp in ``phi_hat`` (:func:`contin.cusp_curve_problem`) traces
  the boundary.

The members of the families are :class:`ShellPointLoad` under force control with two changes that
do not alter any normalized result (which depends only on ``phi_hat``, ``h/R`` and ``nu``):

* ``h`` enters as ``ln(h/R)``, so that steps are relative and the thin, shallow end of a boundary
  (``h/R ~ 1e-3`` at ``phi_hat = 1.45``) is resolved as well as the thick, deep end;
* ``E`` is set so that ``E h`` stays fixed, which keeps the residual's scale (``E h R``) the same
  for every member;
* the unknowns are the displacements from the member's own reference state, not the absolute
  node positions: changing ``phi_hat`` moves every reference node, and at fixed absolute positions
  that change would be a huge, strongly nonlinear load (a derivative ~1e9 ``E h``), whereas at
  fixed displacements it is mild.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import contin
from contin.numerics.stability import StabilityInfo
from contin.problem import Problem

from .geometry import POLE_RATIO
from .problem import ShellPointLoad

__all__ = ["DisplacementForm", "thickness_member", "force_folds", "BoundaryCurve", "bistable_boundary",
           "monotonous_boundary", "depth_parameter"]

#: Step of the central differences in ``phi_hat`` and ``ln h``.  The engine's default (1e-6) leaves
#: rounding noise of ~5 % in the cusp system's derivative in ``phi_hat`` at N = 200 (its fold function
#: is itself built from differences), which makes the tangent, and the curvature predictor that
#: guards against branch jumping, noisy; at 1e-4 the truncation error is ~1e-8 (measured by halving).
DIFFERENCE_STEP = 1e-4

#: ``E h`` of every member (``R = 1``): the default scene's ``1 MPa x 0.02 R``.
E_TIMES_H = 1e6 * 0.02


def depth_parameter(phi_hat: Any, h_over_R: Any, nu: float = 0.5) -> Any:
    """``lambda = (12 (1 - nu^2))^(1/4) (pi/2 - phi_hat) sqrt(R/h)`` (``docs/model.md#geometry``)."""
    return (12.0 * (1.0 - nu * nu)) ** 0.25 * (math.pi / 2 - np.asarray(phi_hat)) / np.sqrt(np.asarray(h_over_R))


class DisplacementForm(Problem):
    """A :class:`ShellPointLoad` whose unknowns are displacements from its reference state.

    Parameters
    ----------
    shell : ShellPointLoad
        The wrapped problem; ``u_shell = u + shell.reference_unknowns()``.
    """

    def __init__(self, shell: ShellPointLoad) -> None:
        self.shell = shell
        self.origin = shell.reference_unknowns()
        self.D = shell.D
        obs = {name: self._wrap(fun) for name, fun in shell.observables.items()}
        super().__init__(observables=obs, symmetric=True, name=f"{shell.name}_displacements",
                         parameter_name=shell.parameter_name, residual_scale=shell.residual_scale)

    def _wrap(self, fun: Callable) -> Callable:
        return lambda u, p: fun(u + self.origin, p)

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        return self.shell.residual(u + self.origin, p)

    def jacobian(self, u: np.ndarray, p: float) -> Any:
        return self.shell.jacobian(u + self.origin, p)

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        return self.shell.dresidual_dp(u + self.origin, p)

    def energy(self, u: np.ndarray, p: float) -> float:
        return self.shell.energy(u + self.origin, p)

    @property
    def has_energy(self) -> bool:
        return True

    def stability_operators(self, u: np.ndarray, p: float) -> dict[str, Any]:
        return self.shell.stability_operators(u + self.origin, p)

    def stability_operator(self, u: np.ndarray, p: float) -> Any:
        return self.shell.stability_operator(u + self.origin, p)

    def stability(self, u: np.ndarray, p: float, n_eigs: int = 0) -> dict[str, StabilityInfo]:
        return self.shell.stability(u + self.origin, p, n_eigs)

    def factorize(self, J: Any) -> Any:
        return self.shell.factorize(J)

    def full_state(self, u: np.ndarray, p: float) -> np.ndarray:
        """Interleaved node positions ``[r_0, z_0, ...]`` (see :meth:`ShellPointLoad.full_state`)."""
        return self.shell.full_state(u + self.origin, p)


def thickness_member(phi_hat: float, ln_h: float, N: int, nu: float = 0.5,
                     pole_ratio: float = POLE_RATIO) -> DisplacementForm:
    """The force-controlled cap at ``(phi_hat, h/R = exp(ln_h))``, ``R = 1``, ``E h = E_TIMES_H``."""
    h = math.exp(ln_h)
    return DisplacementForm(ShellPointLoad(R=1.0, E=E_TIMES_H / h, nu=nu, h=h, phi_hat=phi_hat, N=N,
                                           control="force", pole_ratio=pole_ratio))


def force_folds(problem: DisplacementForm, max_folds: int = 2, max_steps: int = 3000) -> list[contin.SpecialPoint]:
    """The first ``max_folds`` located limit points in ``F`` along the force-controlled path from rest.

    Raises
    ------
    RuntimeError
        When the path ends before that many folds (the cap may have fewer).
    """
    unit = 2 * math.pi * problem.D
    br = contin.continuation(problem, np.zeros(problem.shell.n), 0.0, ds=0.05, ds_max=0.5, stability=False, max_steps=max_steps,
                             param_weight=1.0 / (10 * unit), p_max=500 * unit, p_min=-500 * unit)
    folds = [s for s in br.special_points if s.kind == "fold"][:max_folds]
    if len(folds) < max_folds:
        raise RuntimeError(f"force_folds: the path has {len(folds)} limit points in F before it ended "
                           f"({br.status}: {br.message}); {max_folds} were asked for")
    return folds


@dataclass
class BoundaryCurve:
    """A phase boundary traced in ``(phi_hat, h/R)``.

    Attributes
    ----------
    kind : str
        ``"bistable"`` (``F_min = 0``) or ``"monotonous"`` (cusp: ``F_max`` and ``F_min`` merge).
    phi_hat, h_over_R, lam : ndarray
        The traced points, sorted by ``phi_hat``; ``lam`` is the depth parameter there.
    F_norm : ndarray
        ``F R / (2 pi D)`` at the boundary (0 for the bistable one; the merged limit load at a cusp).
    branches : list of contin.Branch
        The two continuation runs (towards small and large ``phi_hat``) in the problem's unknowns.
    problem : FoldCurveProblem
        The problem traced (its ``split`` gives the state and ``ln(h/R)``).
    start : dict
        How the curve was started (``phi_hat``, ``h_over_R``, seconds).
    wall_time_s : float
        Time of the whole construction, start included.
    """

    kind: str
    phi_hat: np.ndarray
    h_over_R: np.ndarray
    lam: np.ndarray
    F_norm: np.ndarray
    branches: list[contin.Branch] = field(default_factory=list)
    problem: Any = None
    start: dict[str, Any] = field(default_factory=dict)
    wall_time_s: float = 0.0

    def h_at(self, phi_hat: float) -> float:
        """``h/R`` on the boundary at ``phi_hat`` (interpolated in ``ln h`` between traced points)."""
        return float(np.exp(np.interp(phi_hat, self.phi_hat, np.log(self.h_over_R))))

    def phi_at(self, h_over_R: float) -> float:
        """``phi_hat`` where the boundary crosses ``h/R`` (it is monotone in ``phi_hat``)."""
        order = np.argsort(self.h_over_R)
        return float(np.interp(math.log(h_over_R), np.log(self.h_over_R[order]), self.phi_hat[order]))


def _both_ways(problem: contin.FoldCurveProblem, phi0: float, phi_range: tuple[float, float], ds: float,
               ds_max: float, events: list[contin.Event], max_steps: int, xtol: float = 1e-10) -> list[contin.Branch]:
    if not phi_range[0] < phi0 < phi_range[1]:
        raise ValueError(f"the starting phi_hat = {phi0} must lie inside phi_range = {phi_range}")
    runs = []
    for direction, bound in ((-1, {"p_min": phi_range[0]}), (1, {"p_max": phi_range[1]})):
        br = contin.continuation(problem, problem.start, phi0, ds=ds, ds_max=ds_max, direction=direction,
                                 stability=False, max_steps=max_steps, events=events, xtol=xtol, **bound)
        if br.status != "bound":
            raise RuntimeError(f"boundary continuation towards phi_hat = {bound.popitem()[1]} stopped at "
                               f"phi_hat = {br.p[-1]:.6g}: {br.status}: {br.message}")
        runs.append(br)
    return runs


def _curve(kind: str, problem: contin.FoldCurveProblem, runs: list[contin.Branch], F_of: Callable,
           start: dict[str, Any], t0: float, nu: float) -> BoundaryCurve:
    phi = np.concatenate([runs[0].p[::-1], runs[1].p[1:]])
    U = np.concatenate([runs[0].u[::-1], runs[1].u[1:]])
    ln_h = np.array([problem.split(x)[1] for x in U])
    F = np.array([F_of(x) for x in U])
    h = np.exp(ln_h)
    return BoundaryCurve(kind=kind, phi_hat=phi, h_over_R=h, lam=depth_parameter(phi, h, nu), F_norm=F,
                         branches=runs, problem=problem, start=start, wall_time_s=time.perf_counter() - t0)


def bistable_boundary(N: int, phi_range: tuple[float, float] = (0.5, 1.45), phi0: float = 1.0,
                      h_guess: float = 0.02, nu: float = 0.5, ds_max: float = 0.05, max_steps: int = 1000,
                      events: list[contin.Event] | None = None) -> BoundaryCurve:
    """Trace the bistable/monostable boundary (``F_min = 0``) over ``phi_range``.

    Start: at ``phi0`` and ``h_guess`` (a bistable cap), the lower limit load ``F_min`` is located on
    the force-controlled path, then followed in ``h`` until it reaches ``F = 0`` (an event on that
    fold curve); from there the fold of the unloaded cap is continued in ``phi_hat`` both ways.

    Parameters
    ----------
    N : int
        Nodes on the meridian.
    phi_range : (float, float)
        Range of ``phi_hat`` to trace.
    phi0, h_guess : float
        Starting ``phi_hat`` and a thickness at which that cap is bistable.
    nu : float
        Poisson's ratio.
    ds_max : float
        Largest continuation step (in ``(u, ln h, phi_hat)``).
    max_steps : int
        Step limit of each direction.
    events : list of contin.Event, optional
        Extra events on the boundary (e.g. ``contin.crossing("h_over_R", 0.02)``).

    Returns
    -------
    BoundaryCurve
    """
    t0 = time.perf_counter()
    s0 = math.log(h_guess)
    P = thickness_member(phi0, s0, N, nu)
    _, f_min = force_folds(P, 2)
    unit = 2 * math.pi * P.D
    if f_min.p >= 0:
        raise RuntimeError(f"bistable_boundary: the cap at phi_hat = {phi0}, h/R = {h_guess} is not bistable "
                           f"(F_min R/(2 pi D) = {f_min.p / unit:.4g}); pass a smaller h_guess")
    in_h = contin.FoldCurveProblem(lambda s: thickness_member(phi0, s, N, nu), f_min, s0, q_name="ln_h",
                                   p_scale=10 * unit)
    br = contin.continuation(in_h, in_h.start, s0, ds=0.02, ds_max=0.1, stability=False, max_steps=500,
                             p_max=math.log(0.5), events=[contin.crossing("F", 0.0, terminal=True, name="F = 0")])
    hits = br.events("F = 0")
    if not hits:
        raise RuntimeError(f"bistable_boundary: F_min did not reach 0 as h grew from {h_guess} ({br.status}: {br.message})")
    u_star, _ = in_h.split(hits[0].u)
    s_star = float(hits[0].p)
    start = {"phi_hat": phi0, "h_over_R": math.exp(s_star), "seconds": time.perf_counter() - t0}

    # every phi_hat the fold curve visits makes its family anew: they all take their names, symmetry
    # and residual scale from this one member, and build only the members they evaluate
    base = thickness_member(phi0, s_star, N, nu)

    def family(phi: float) -> contin.FamilyProblem:
        return contin.FamilyProblem(lambda s: thickness_member(phi, s, N, nu), 0.0, s_star, q_name="ln_h",
                                    q_step=DIFFERENCE_STEP, base=base)

    problem = contin.FoldCurveProblem(family, (u_star, s_star), phi0, q_name="phi_hat", q_step=DIFFERENCE_STEP)
    problem.observables["h_over_R"] = lambda U, q: math.exp(problem.split(U)[1])
    runs = _both_ways(problem, phi0, phi_range, 0.01, ds_max, list(events or []), max_steps)
    return _curve("bistable", problem, runs, lambda U: 0.0, start, t0, nu)


def monotonous_boundary(N: int, phi_range: tuple[float, float] = (0.5, 1.45), phi0: float = 1.0,
                        h_guess: float = 0.04, nu: float = 0.5, ds_max: float = 0.05, max_steps: int = 1000,
                        events: list[contin.Event] | None = None, xtol_cusp: float = 1e-6) -> BoundaryCurve:
    """Trace the monostable/monotonous boundary (the cusp where ``F_max`` and ``F_min`` merge).

    Start: at ``phi0`` and ``h_guess`` (a cap with both limit points), ``F_max`` is located on the
    force-controlled path and followed in ``h`` to its cusp (the fold curve's own fold); the cusp is
    then continued in ``phi_hat`` both ways.  Parameters as :func:`bistable_boundary`, and

    xtol_cusp : float
        Newton-update tolerance of the cusp continuation (see the comment in the code: the cusp
        system's rounding floor is ~1e-6 at N = 200).
    """
    t0 = time.perf_counter()
    s0 = math.log(h_guess)
    P = thickness_member(phi0, s0, N, nu)
    f_max = force_folds(P, 1)[0]
    p_scale = 10 * 2 * math.pi * P.D
    in_h = contin.FoldCurveProblem(lambda s: thickness_member(phi0, s, N, nu), f_max, s0, q_name="ln_h",
                                   p_scale=p_scale, q_step=DIFFERENCE_STEP)
    br = contin.continuation(in_h, in_h.start, s0, ds=0.02, ds_max=0.1, stability=False, max_steps=500,
                             p_max=math.log(0.5), stop_at=("fold",))
    cusps = [s for s in br.special_points if s.kind == "fold"]
    if br.status != "event" or not cusps:
        raise RuntimeError(f"monotonous_boundary: F_max followed in h from h/R = {h_guess} met no cusp "
                           f"({br.status}: {br.message})")
    cusp = cusps[-1]
    start = {"phi_hat": phi0, "h_over_R": math.exp(cusp.p), "seconds": time.perf_counter() - t0}
    problem = contin.cusp_curve_problem(lambda phi, s: thickness_member(phi, s, N, nu), in_h, cusp, phi0,
                                        r_name="phi_hat", r_step=DIFFERENCE_STEP)
    problem.observables["h_over_R"] = lambda U, q: math.exp(problem.split(U)[1])

    def F_norm(U: np.ndarray) -> float:
        inner, s = problem.split(U)
        D = E_TIMES_H * math.exp(s) ** 2 / (12 * (1 - nu * nu))  # E h^3 / (12 (1 - nu^2)) with E h fixed
        return in_h.split(inner)[1] / (2 * math.pi * D)

    # The cusp is pinned down to ~1e-7 in (phi_hat, ln h), not to the default xtol = 1e-10: its system
    # holds second derivatives of the fold function, built by differences of differences, and the
    # shell's residual has a rounding floor ~3e-17 |H| R that grows like N^3 (ShellPointLoad Notes).
    # At N = 200 the Newton updates stall at ~1e-6 in the arclength norm while the residual stays
    # below tol; xtol_cusp accepts points there.
    runs = _both_ways(problem, phi0, phi_range, 0.01, ds_max, list(events or []), max_steps, xtol=xtol_cusp)
    return _curve("monotonous", problem, runs, F_norm, start, t0, nu)
