"""Two baselines for locating a limit load without continuation, for :mod:`studies.accuracy`.

Both work on any :class:`contin.Problem` (residual, Jacobian, factorization, observables) and use
nothing of the continuation engine: they are what a user without PALC would write.

Natural-parameter load stepping with bisection (:func:`natural_parameter_limit`)
    The load ``p`` (a dead load under force control) is stepped from a converged state, Newton
    starting from the previous solution at each step.  When Newton fails to converge (no
    equilibrium nearby: the load is past the limit point) the step is halved; the last converged
    load and the smallest failed one bracket the limit load, and the bracket is bisected until it is
    narrower than a tolerance.  The estimate is the midpoint of the bracket.  A Newton that converges
    to a state far from the previous one (``max_jump`` on an observable: the post-snap branch) counts
    as a failure, so the bracket never closes on the far branch.

Implicit dynamic relaxation (:func:`implicit_dynamic_ramp` and its two uses)
    Inertia and damping are added to the discrete equilibrium and the load is ramped in time,
    each time step solved fully implicitly by Newton (as in implicit discrete elastic rods and the
    paper's section 3(c)):

        M (u_{n+1} - u_n - dt v_n) / dt^2 + C (u_{n+1} - u_n) / dt + f(u_{n+1}, p(t_{n+1})) = 0,
        v_{n+1} = (u_{n+1} - u_n) / dt,

    with ``f`` the problem's residual (the gradient of the potential energy), a lumped mass ``M``
    (:func:`lumped_masses`: density times node area times thickness for the shell) and a
    mass-proportional damping ``C = alpha M``; :func:`critical_damping` sets ``alpha = 2 zeta
    omega_1`` from the lowest mode of ``J phi = omega^2 M phi`` at the start (``zeta = 1``: critical
    for that mode).  Under displacement control (:func:`dr_reaction_maximum`) the prescribed
    parameter is ramped and the limit load is the largest reaction recorded; under force control
    (:func:`dr_snap_load`) the load is ramped and the snap is detected when a monitored observable
    moves faster than a threshold, the estimate being the load of the last step before that.
    :func:`dr_relax` holds the load and steps until the motion dies out: the static equilibrium.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from contin.numerics.linalg import SingularMatrixError
from contin.problem import NonFiniteError, Problem

__all__ = ["NewtonFailure", "SolveCounts", "newton", "LimitResult", "natural_parameter_limit",
           "lumped_masses", "lowest_frequency", "critical_damping", "RampResult", "StopRule", "implicit_dynamic_ramp",
           "dr_reaction_maximum", "dr_snap_load", "dr_relax"]


class NewtonFailure(RuntimeError):
    """Newton did not converge (the message says why)."""


@dataclass
class SolveCounts:
    """Work counters: Newton iterations (one residual, Jacobian, factorization and solve each)."""

    iterations: int = 0
    failed_solves: int = 0


def _rms(v: np.ndarray) -> float:
    return float(np.sqrt(np.mean(v * v))) if v.size else 0.0


def _add_diagonal(J: Any, d: np.ndarray) -> Any:
    """``J + diag(d)`` for a dense or sparse ``J`` (in place on a copy of the CSR data when the diagonal is stored)."""
    if not sp.issparse(J):
        return np.asarray(J, dtype=float) + np.diag(d)
    A = J.tocsr() if J.format != "csr" else J
    rows = np.repeat(np.arange(A.shape[0]), np.diff(A.indptr))
    on_diag = A.indices == rows
    if np.count_nonzero(on_diag) != A.shape[0]:  # a diagonal entry is not stored: general addition
        return (A + sp.diags(d, format="csr")).tocsr()
    data = A.data.copy()
    data[on_diag] += d[rows[on_diag]]
    return sp.csr_matrix((data, A.indices, A.indptr), shape=A.shape)


def newton(problem: Problem, u0: np.ndarray, p: float, *, tol: float = 1e-10, xtol: float = 1e-10,
           max_iter: int = 25, counts: SolveCounts | None = None,
           shift: np.ndarray | None = None, rhs_shift: Callable[[np.ndarray], np.ndarray] | None = None
           ) -> tuple[np.ndarray, int, Any]:
    """Plain (undamped) Newton on ``f(u, p) + g(u) = 0`` at fixed ``p`` from ``u0``.

    Parameters
    ----------
    problem : Problem
        The model; its residual scale sets the absolute tolerance.
    u0 : ndarray
        Starting state.
    p : float
        Parameter (held fixed).
    tol : float
        Residual tolerance relative to ``problem.residual_scale`` (max norm), as the engine's.
    xtol : float
        The last Newton update must be below ``xtol (1 + rms(u))`` in the root-mean-square norm.
    max_iter : int
        Iterations before giving up.
    counts : SolveCounts, optional
        Incremented by the iterations made (and a failure).
    shift : ndarray, optional
        Diagonal added to the Jacobian (the ``M / dt^2 + C / dt`` of an implicit time step).
    rhs_shift : callable, optional
        ``g(u)``, added to the residual (the inertial and damping forces of a time step).

    Returns
    -------
    (u, iterations, factorization)
        The converged state, the iterations it took and the factorization of the last Jacobian
        used (None when the start was already converged).

    Raises
    ------
    NewtonFailure
        No convergence in ``max_iter`` iterations, a non-finite residual or Jacobian, a singular
        Jacobian, an update that leaves the model's domain, or a residual grown by 1e8.
    """
    counts = counts if counts is not None else SolveCounts()
    tol_abs = tol * float(getattr(problem, "residual_scale", 1.0))
    u = np.array(u0, dtype=float)

    def resid(x: np.ndarray) -> np.ndarray:
        r = problem.checked_residual(x, p)
        return r + rhs_shift(x) if rhs_shift is not None else r

    try:
        r = resid(u)
    except NonFiniteError as exc:
        counts.failed_solves += 1
        raise NewtonFailure(f"residual not finite at the start ({exc})") from None
    res0 = res = float(np.max(np.abs(r), initial=0.0))
    step = math.inf
    fac = None
    for it in range(max_iter + 1):
        if res <= tol_abs and (step <= xtol * (1.0 + _rms(u)) or res <= 1e-6 * tol_abs):
            counts.iterations += it
            return u, it, fac
        if it == max_iter:
            break
        try:
            J = problem.checked_jacobian(u, p)
            if shift is not None:
                J = _add_diagonal(J, shift)
            fac = problem.factorize(J)
            du = -fac.solve(r)
        except (NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
            counts.iterations += it + 1
            counts.failed_solves += 1
            raise NewtonFailure(f"linear solve failed ({exc})") from None
        if problem.max_step_fraction(u, p, du, 0.0) < 1.0:
            counts.iterations += it + 1
            counts.failed_solves += 1
            raise NewtonFailure("the Newton update leaves the model's domain")
        u = u + du
        step = _rms(du)
        try:
            r = resid(u)
        except NonFiniteError:
            counts.iterations += it + 1
            counts.failed_solves += 1
            raise NewtonFailure("residual not finite") from None
        res = float(np.max(np.abs(r), initial=0.0))
        if res > 1e8 * max(res0, tol_abs):
            counts.iterations += it + 1
            counts.failed_solves += 1
            raise NewtonFailure(f"Newton diverges (residual {res:.2e})")
    counts.iterations += max_iter
    counts.failed_solves += 1
    raise NewtonFailure(f"no convergence in {max_iter} iterations (residual {res:.2e} > {tol_abs:.1e})")


# ---------------------------------------------------------------------------------------------------
# natural-parameter stepping with bisection
# ---------------------------------------------------------------------------------------------------
@dataclass
class LimitResult:
    """A bracketed limit load of :func:`natural_parameter_limit`.

    Attributes
    ----------
    p_limit : float
        Estimate: the midpoint of the final bracket.
    lo, hi : float
        The last converged load and the smallest load where Newton failed.
    u_lo : ndarray
        The state at ``lo``.
    observables : dict
        The problem's observables at ``lo``.
    steps, failures : int
        Converged and failed load steps.
    counts : SolveCounts
        Newton work.
    wall_time_s : float
    status : str
        ``"bracketed"`` or ``"p_max"`` (no failure up to ``p_max``) or ``"max_steps"``.
    """

    p_limit: float
    lo: float
    hi: float
    u_lo: np.ndarray
    observables: dict[str, float]
    steps: int
    failures: int
    counts: SolveCounts
    wall_time_s: float
    status: str


def natural_parameter_limit(problem: Problem, u0: np.ndarray, p0: float, dp0: float, bracket_tol: float, *,
                            tol: float = 1e-10, xtol: float = 1e-10, max_iter: int = 25,
                            max_jump: tuple[str, float] | None = None, p_max: float = math.inf,
                            max_steps: int = 100000) -> LimitResult:
    """The limit load along increasing ``p`` by natural-parameter stepping and bisection.

    Parameters
    ----------
    problem : Problem
        Parameter = the load (force control).
    u0 : ndarray
        A converged (or nearly: it is corrected first) state at ``p0``.
    p0 : float
        Starting load.
    dp0 : float
        Initial load step (> 0).
    bracket_tol : float
        Stop once the bracket ``[lo, hi]`` is at most this wide (> 0).
    tol, xtol, max_iter
        Newton's settings (:func:`newton`).
    max_jump : (str, float), optional
        ``(observable, bound)``: a converged step whose observable changed by more than ``bound``
        from the previous state landed on another branch and counts as a failure.
    p_max : float
        Give up (status ``"p_max"``) once the load would exceed this.
    max_steps : int
        Limit on load steps, converged or failed.

    Returns
    -------
    LimitResult

    Raises
    ------
    NewtonFailure
        If the starting state does not converge.
    """
    if not dp0 > 0 or not bracket_tol > 0:
        raise ValueError(f"natural_parameter_limit: dp0 and bracket_tol must be > 0 (got {dp0}, {bracket_tol})")
    t0 = time.perf_counter()
    counts = SolveCounts()
    u, _, _ = newton(problem, u0, p0, tol=tol, xtol=xtol, max_iter=max_iter, counts=counts)
    watch = problem.observables[max_jump[0]] if max_jump is not None else None
    lo, hi, dp = float(p0), math.inf, float(dp0)
    steps = failures = 0
    status = "max_steps"
    for _ in range(max_steps):
        if hi - lo <= bracket_tol:
            status = "bracketed"
            break
        p = lo + (dp if math.isinf(hi) else min(dp, 0.5 * (hi - lo)))
        if p > p_max:
            status = "p_max"
            break
        try:
            u_new, _, _ = newton(problem, u, p, tol=tol, xtol=xtol, max_iter=max_iter, counts=counts)
            if watch is not None and abs(float(watch(u_new, p)) - float(watch(u, lo))) > max_jump[1]:
                raise NewtonFailure("converged on another branch")
        except NewtonFailure:
            failures += 1
            hi = p
            dp = 0.5 * (hi - lo)
            continue
        steps += 1
        u, lo = u_new, p
    est = 0.5 * (lo + hi) if math.isfinite(hi) else lo
    return LimitResult(p_limit=est, lo=lo, hi=hi, u_lo=u, observables=problem.evaluate_observables(u, lo),
                       steps=steps, failures=failures, counts=counts, wall_time_s=time.perf_counter() - t0,
                       status=status)


# ---------------------------------------------------------------------------------------------------
# implicit dynamic relaxation
# ---------------------------------------------------------------------------------------------------
def lumped_masses(shell: Any, density: float) -> np.ndarray:
    """Lumped mass of every unknown of a :class:`contin_models.shell.ShellPointLoad`: ``density h A_i``.

    ``A_i`` is the reference area of node ``i``'s cell: the ring ``2 pi r_i l_i`` (``l_i`` the Voronoi
    length, half an edge at the base) for every node but the pole, whose cell is the disc
    ``pi (l/2)^2`` of its last edge (the area the model's pole element uses).  The ``r`` and ``z``
    unknowns of a node carry the same mass.

    Parameters
    ----------
    shell : ShellPointLoad
        The model (either control; its ``idx`` maps unknowns to the interleaved dofs).
    density : float
        Mass density (kg/m^3 for SI units).

    Returns
    -------
    ndarray
        One mass per unknown.
    """
    cap = shell.cap
    area = 2.0 * math.pi * np.asarray(cap.r, dtype=float) * np.asarray(cap.voronoi_length, dtype=float)
    area[-1] = math.pi * (0.5 * float(cap.edge_length[-1])) ** 2
    node_mass = density * shell.h * area
    return node_mass[np.asarray(shell.idx) // 2].astype(float)


def lowest_frequency(problem: Problem, u: np.ndarray, p: float, masses: np.ndarray) -> float:
    """Lowest angular frequency ``omega_1`` of ``J phi = omega^2 M phi`` at ``(u, p)``, ``M = diag(masses)``.

    The symmetric Jacobian (stiffness) is scaled to ``M^{-1/2} J M^{-1/2}``; its smallest eigenvalue
    comes from a banded (or dense, for small problems) symmetric eigensolver.

    Raises
    ------
    ValueError
        If the stiffness is not positive definite there (no real lowest frequency).
    """
    J = problem.checked_jacobian(u, p)
    s = 1.0 / np.sqrt(np.asarray(masses, dtype=float))
    if sp.issparse(J):
        A = sp.diags(s) @ J @ sp.diags(s)
        A = sp.dia_matrix(A)
        kd = int(np.max(np.abs(A.offsets)))
        n = A.shape[0]
        band = np.zeros((kd + 1, n))
        Acsr = A.tocsr()
        for k in range(kd + 1):
            diag = Acsr.diagonal(k)
            band[kd - k, k:] = diag
        lam = sla.eig_banded(band, lower=False, select="i", select_range=(0, 0), eigvals_only=True)[0]
    else:
        Jd = np.asarray(J, dtype=float)
        lam = float(np.linalg.eigvalsh(s[:, None] * Jd * s[None, :])[0])
    if not lam > 0:
        raise ValueError(f"lowest_frequency: the stiffness is not positive definite (lambda_min = {lam:.3e})")
    return math.sqrt(float(lam))


def critical_damping(omega_1: float, zeta: float = 1.0) -> float:
    """``alpha`` of the mass-proportional damping ``C = alpha M`` with damping ratio ``zeta`` for ``omega_1``."""
    return 2.0 * zeta * omega_1


@dataclass
class RampResult:
    """Time history of :func:`implicit_dynamic_ramp`.

    Attributes
    ----------
    t, p : ndarray
        Times and parameter values of the stored steps (the start included).
    history : dict of ndarray
        Recorded observables per stored step.
    u, v : ndarray
        State and velocity at the end.
    steps : int
        Time steps taken.
    counts : SolveCounts
        Newton work.
    wall_time_s : float
    status : str
        ``"stopped"`` (the stop rule fired), ``"p_end"``, ``"max_steps"`` or ``"newton_failure"``.
    message : str
    """

    t: np.ndarray
    p: np.ndarray
    history: dict[str, np.ndarray]
    u: np.ndarray
    v: np.ndarray
    steps: int
    counts: SolveCounts
    wall_time_s: float
    status: str
    message: str = ""


#: ``stop(p, values, u, v)``: called after every converged step with the parameter, the recorded
#: observables, the state and the velocity; True ends the run.
StopRule = Callable[[float, dict[str, float], np.ndarray, np.ndarray], bool]


def implicit_dynamic_ramp(problem: Problem, u0: np.ndarray, masses: np.ndarray, alpha: float, dt: float,
                          rate: float, *, p0: float = 0.0, p_end: float = math.inf, record: tuple[str, ...] = (),
                          stop: StopRule | None = None, v0: np.ndarray | None = None, tol: float = 1e-10,
                          xtol: float = 1e-10, max_iter: int = 25, max_steps: int = 1_000_000) -> RampResult:
    """Integrate ``M u'' + alpha M u' + f(u, p(t)) = 0`` with ``p(t) = p0 + rate t`` by implicit Euler.

    Each step solves ``M (u - u_n - dt v_n)/dt^2 + alpha M (u - u_n)/dt + f(u, p_{n+1}) = 0`` by
    Newton.  Its first iterate is the extrapolation ``u_n + dt v_n`` plus the linear response
    ``-(J + M/dt^2 + alpha M/dt)^{-1} f_p delta`` (previous step's last factorization) to the part
    ``delta`` of the parameter increment that the velocity does not already carry (the whole
    increment of the first step from rest, nothing after that on a constant ramp), as
    finite-element codes apply a prescribed-displacement increment: evaluating the residual with
    only the prescribed node moved puts a kink in the mesh that plain Newton cannot always undo
    (measured on the shell: it diverges for a first pole increment of 1e-3 R at N = 200).

    Parameters
    ----------
    problem : Problem
        The model; ``f`` is its residual and ``f_p`` its ``dresidual_dp``.
    u0 : ndarray
        Initial state (at rest unless ``v0``).
    masses : ndarray
        Lumped mass per unknown (> 0).
    alpha : float
        Mass-proportional damping coefficient (``C = alpha M``), >= 0.
    dt : float
        Time step (> 0).
    rate : float
        Load rate ``dp/dt`` (0: the load is held at ``p0``).
    p0, p_end : float
        Start of the ramp, and the value the ramp never passes (status ``"p_end"``).
    record : tuple of str
        Observables stored after every step (besides ``t`` and ``p``).
    stop : StopRule, optional
        True ends the run (status ``"stopped"``).
    v0 : ndarray, optional
        Initial velocity.
    tol, xtol, max_iter
        Newton's settings per step (:func:`newton`).
    max_steps : int
        Step limit.

    Returns
    -------
    RampResult
        A step whose Newton fails ends the run with status ``"newton_failure"``; nothing
        unconverged is stored.
    """
    if not dt > 0 or alpha < 0:
        raise ValueError(f"implicit_dynamic_ramp: need dt > 0 and alpha >= 0 (got dt={dt}, alpha={alpha})")
    m = np.asarray(masses, dtype=float)
    if m.shape != (np.size(u0),) or not np.all(m > 0):
        raise ValueError("implicit_dynamic_ramp: masses must be positive, one per unknown")
    t_start = time.perf_counter()
    counts = SolveCounts()
    u = np.array(u0, dtype=float)
    v = np.zeros_like(u) if v0 is None else np.array(v0, dtype=float)
    shift = m / dt ** 2 + alpha * m / dt
    obs = {name: problem.observables[name] for name in record}
    ts, ps = [0.0], [float(p0)]
    hist: dict[str, list[float]] = {name: [float(f(u, p0))] for name, f in obs.items()}
    status, message, steps = "max_steps", "", 0
    fac = None
    p_prev = float(p0)
    dp_in_v = 0.0  # the parameter increment the velocity v already carries (0 at rest)
    if v0 is not None:
        dp_in_v = rate * dt
    direction = 1.0 if rate >= 0 else -1.0
    for n in range(1, max_steps + 1):
        p = p0 + rate * n * dt
        if (p - p_end) * direction > 0:
            status = "p_end"
            break
        un, vn = u, v

        def inertia(x: np.ndarray, un: np.ndarray = un, vn: np.ndarray = vn) -> np.ndarray:
            return m * (x - un - dt * vn) / dt ** 2 + alpha * m * (x - un) / dt

        start = un + dt * vn
        extra = (p - p_prev) - dp_in_v  # the increment the extrapolation u_n + dt v_n does not carry
        try:
            if abs(extra) > 1e-9 * abs(p - p_prev):  # not just the rounding of p0 + rate n dt
                if fac is None:  # the first step: factorize at the start
                    fac = problem.factorize(_add_diagonal(problem.checked_jacobian(un, p_prev), shift))
                start = start - fac.solve(problem.dresidual_dp(un, p_prev) * extra)
            u, _, fac_new = newton(problem, start, p, tol=tol, xtol=xtol, max_iter=max_iter, counts=counts,
                                   shift=shift, rhs_shift=inertia)
        except (NewtonFailure, SingularMatrixError, NonFiniteError, np.linalg.LinAlgError) as exc:
            u = un
            status, message = "newton_failure", f"step {n} (p = {p:.6g}): {exc}"
            break
        fac = fac_new if fac_new is not None else fac
        v = (u - un) / dt
        dp_in_v = p - p_prev
        p_prev = p
        steps = n
        ts.append(n * dt)
        ps.append(p)
        values = {name: float(f(u, p)) for name, f in obs.items()}
        for name, val in values.items():
            hist[name].append(val)
        if stop is not None and stop(p, values, u, v):
            status = "stopped"
            break
    return RampResult(t=np.array(ts), p=np.array(ps), history={k: np.array(x) for k, x in hist.items()}, u=u, v=v,
                      steps=steps, counts=counts, wall_time_s=time.perf_counter() - t_start, status=status,
                      message=message)


def dr_reaction_maximum(problem: Problem, u0: np.ndarray, masses: np.ndarray, alpha: float, dt: float,
                        rate: float, *, p_end: float, force: str = "F", drop: float = 1e-3,
                        **kw: Any) -> dict[str, Any]:
    """Displacement ramp: the largest reaction force recorded, and the parameter where it was recorded.

    The prescribed parameter (e.g. the pole displacement ``w``) is ramped at ``rate`` (> 0); the run
    stops once the reaction ``force`` has fallen by ``drop`` (relative) below the largest value
    recorded, i.e. once the maximum has clearly been passed.

    Returns
    -------
    dict
        ``F_max`` (largest recorded reaction), ``p_at_max``, ``steps``, ``newton_iterations``,
        ``wall_time_s``, ``status``, and ``result`` (the :class:`RampResult`).

    Raises
    ------
    RuntimeError
        If the run ends before the maximum is passed (a Newton failure or ``p_end``).
    """
    best = [-math.inf]

    def passed(p: float, values: dict[str, float], u: np.ndarray, v: np.ndarray) -> bool:
        f = values[force]
        best[0] = max(best[0], f)
        return best[0] > 0 and f < (1.0 - drop) * best[0]

    r = implicit_dynamic_ramp(problem, u0, masses, alpha, dt, rate, p_end=p_end, record=(force,), stop=passed, **kw)
    if r.status != "stopped":
        raise RuntimeError(f"dr_reaction_maximum: the ramp ended before the maximum was passed ({r.status}: {r.message})")
    k = int(np.argmax(r.history[force]))
    return {"F_max": float(r.history[force][k]), "p_at_max": float(r.p[k]), "steps": r.steps,
            "newton_iterations": r.counts.iterations, "wall_time_s": r.wall_time_s, "status": r.status, "result": r}


def dr_snap_load(problem: Problem, u0: np.ndarray, masses: np.ndarray, alpha: float, dt: float, rate: float, *,
                 monitor: str, jump_rate: float, p_end: float, **kw: Any) -> dict[str, Any]:
    """Load ramp under force control: the load of the last step before the monitored observable jumps.

    The snap is detected at the first step over which ``monitor`` moves faster than ``jump_rate``
    (``|q_{n+1} - q_n| / dt > jump_rate``): on the quasi-static stretch it creeps with the load, in a
    snap it moves at the speed the released energy gives it.

    Returns
    -------
    dict
        ``p_snap`` (load of the last step before the jump), ``monitor_before`` (its value there),
        ``steps``, ``newton_iterations``, ``wall_time_s``, ``status``, ``result``.

    Raises
    ------
    RuntimeError
        If no jump shows before ``p_end`` or a step fails to converge.
    """
    last = [None]

    def jumped(p: float, values: dict[str, float], u: np.ndarray, v: np.ndarray) -> bool:
        q, prev = values[monitor], last[0]
        last[0] = q
        return prev is not None and abs(q - prev) > jump_rate * dt

    r = implicit_dynamic_ramp(problem, u0, masses, alpha, dt, rate, p_end=p_end, record=(monitor,), stop=jumped, **kw)
    if r.status != "stopped":
        raise RuntimeError(f"dr_snap_load: no snap detected ({r.status}: {r.message})")
    return {"p_snap": float(r.p[-2]), "monitor_before": float(r.history[monitor][-2]), "steps": r.steps,
            "newton_iterations": r.counts.iterations, "wall_time_s": r.wall_time_s, "status": r.status,
            "result": r}


def dr_relax(problem: Problem, u0: np.ndarray, p: float, masses: np.ndarray, alpha: float, dt: float, *,
             vtol: float, max_steps: int = 100000, **kw: Any) -> RampResult:
    """Hold the load at ``p`` and step until the root-mean-square velocity is below ``vtol``.

    Returns the :class:`RampResult`; its ``u`` is the relaxed (static) state.

    Raises
    ------
    RuntimeError
        If the motion does not die out within ``max_steps`` or a step fails.
    """
    def still(p_: float, values: dict[str, float], u: np.ndarray, v: np.ndarray) -> bool:
        return _rms(v) < vtol

    r = implicit_dynamic_ramp(problem, u0, masses, alpha, dt, 0.0, p0=p, stop=still, max_steps=max_steps, **kw)
    if r.status != "stopped":
        raise RuntimeError(f"dr_relax: the motion did not die out ({r.status}: {r.message})")
    return r
