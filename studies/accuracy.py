"""Error against run time: continuation against two baselines, and the mesh convergence of the paper's quantities.

Run ``python -m studies.accuracy [--out DIR] [--full] [--repeat K] [--quiet]``.

The default scene: ``R = 1``, ``h/R = 0.02``, ``phi_hat = 0.8``, ``nu = 0.5``, ``E = 1e6``
(:class:`contin_models.shell.ShellPointLoad`'s defaults, the paper's N = 200).

Quantities and their references
-------------------------------
* ``F_max`` and its ``w`` (the first maximum of F on the displacement-controlled path), over
  N = 25 .. 3200 (fast: 25 .. 1600);
* ``w_b^c`` of a sphere indenter with ``r/R = 0.5`` (:func:`studies.indenter_size.snap_case`), over
  N = 25 .. 3200 (fast: 25 .. 200);
* ``--full`` only: the bistable boundary's ``phi_hat`` at ``h/R = 0.02`` and ``lambda_d`` of both
  boundaries (eq. 4.1 in its squared form, ``lambda = lambda_d`` on the boundary, fitted as
  :func:`studies.phase_diagram.fit_eq41` on 20 points equally spaced in ``phi_hat`` over [1.0, 1.45]),
  over N = 25 .. 800 (bistable) and 25 .. 400 (monotonous: the cusp continuation's rounding floor
  grows like N^3 and it fails at N = 800).  The boundaries are traced over ``phi_hat`` in [0.95, 1.45]
  only (the fit range and the ``h/R = 0.02`` crossing, near 1.10 and 1.26), and ``h/R`` at the 20 fit
  points is located by Newton at fixed ``phi_hat`` on the traced curve, so that the value does not
  depend on where the steps fell; the phase-diagram study's own value (``h/R`` interpolated in
  ``ln h`` between traced points) is recorded beside it with its extra error.

Each reference is the Richardson extrapolation in N from the three finest meshes (with the order
observed there); its error estimate is reported twice: the difference from the Richardson value
of the three meshes before, and the size of the last correction (reference minus finest value).

Methods, side by side for ``F_max`` and its ``w``
---------------------------------------------------
* ours: PALC on the displacement-controlled path with the maximum of F located as an event
  (:func:`studies.shell_mesh_convergence.first_force_maximum`), over N (and the coarse N = 6 .. 16)
  and over the continuation's ``tol``/``xtol``, ``locate_tol`` and ``ds_max``; ours + Richardson
  combines N, 2N, 4N (time: the sum).
* natural-parameter load stepping under force control with bisection of the failed step
  (:func:`studies.baselines.natural_parameter_limit`), over N, the first step and the bracket tolerance.
* implicit dynamic relaxation (:func:`studies.baselines.dr_reaction_maximum`): the pole displacement
  is ramped at constant rate, the F_max estimate is the largest reaction recorded.  Over N, the ramp
  rate and the time step.  Lumped mass ``rho h A_i`` with ``rho = 1000 kg/m^3`` (an elastomer; E = 1 MPa),
  mass-proportional damping critical for the lowest mode at rest (``zeta = 1``).

Every run's wall time includes building the problem (and, for dynamic relaxation, the masses and
the lowest frequency).  Runs shorter than 1 s are repeated up to ``--repeat`` times (default 3) and
the median time is kept; longer ones (boundaries, slow ramps) run once.  Besides the total error
(against the references), the solver error at N = 200 (against ours at N = 200, default settings)
is compared too, and the cost of one Newton step over N.  Baseline / ours time ratios are taken at
equal error on the Pareto fronts (:func:`equal_error_ratios`; a lower bound where the error ranges
do not overlap).

The fast default mode takes about 11 s (single-threaded BLAS, development machine); ``--full``
about 5 minutes.  ``docs/accuracy.md`` reports the ``--full`` run.

Outputs (``--out``, default ``out/accuracy``): ``error_vs_time.png/.pdf``, ``runs.csv`` (every run),
``summary.json`` (references, orders, cost per Newton step, equal-error ratios, target verdicts).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from typing import Any  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin.palc import Curve, Settings  # noqa: E402
from contin.plot.style import WIDTH  # noqa: E402
from contin_models.shell import ShellPointLoad  # noqa: E402
from contin_models.shell.boundaries import BoundaryCurve, bistable_boundary, monotonous_boundary  # noqa: E402
from studies._common import (clearest_offset, output_dir, print_table, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.baselines import (critical_damping, dr_reaction_maximum, lowest_frequency, lumped_masses,  # noqa: E402
                               natural_parameter_limit)
from studies.shell_mesh_convergence import first_force_maximum, observed_orders, orders_against, richardson  # noqa: E402

__all__ = ["reference", "pareto_front", "equal_error_ratios", "ours_force_maximum", "natural_parameter_run",
           "dynamic_relaxation_run", "newton_step_cost", "boundary_quantities", "run", "main"]

# ---- the scene and the grids -------------------------------------------------------------------------
PHI_HAT, H_OVER_R, NU, E_MOD, R = 0.8, 0.02, 0.5, 1e6, 1.0
SPHERE_RADIUS = 0.5
NS_FULL = (25, 50, 100, 200, 400, 800, 1600, 3200)
NS_FAST = (25, 50, 100, 200, 400, 800, 1600)
NS_WB_FULL = NS_FULL
NS_WB_FAST = (25, 50, 100, 200)
NS_BISTABLE = (25, 50, 100, 200, 400, 800)
NS_MONOTONOUS = (25, 50, 100, 200, 400)
#: the meshes of the tolerance and step-size variations of ours
SETTINGS_NS_FULL = (50, 200, 800)
#: coarser meshes for ours (not part of the doubling sequence): the errors the fastest ramps reach
COARSE_NS = (6, 8, 12, 16)
SETTINGS_NS_FAST = (200,)
#: variations of ours (continuation settings), default first
OURS_SETTINGS: tuple[tuple[str, dict[str, float]], ...] = (
    ("default", {}),
    ("tol=xtol=1e-8", {"tol": 1e-8, "xtol": 1e-8}),
    ("tol=xtol=1e-6", {"tol": 1e-6, "xtol": 1e-6}),
    ("tol=xtol=1e-5", {"tol": 1e-5, "xtol": 1e-5}),
    ("tol=xtol=1e-4", {"tol": 1e-4, "xtol": 1e-4}),
    ("tol=xtol=1e-3", {"tol": 1e-3, "xtol": 1e-3}),
    ("locate_tol=1e-3", {"locate_tol": 1e-3}),
    ("locate_tol=1e-6", {"locate_tol": 1e-6}),
    ("ds_max=0.2", {"ds_max": 0.2}),
    ("ds_max=0.01", {"ds_max": 0.01, "ds": 0.01}),
    ("loose: tol=xtol=1e-6, locate_tol=1e-4, ds_max=0.2", {"tol": 1e-6, "xtol": 1e-6, "locate_tol": 1e-4,
                                                           "ds_max": 0.2}),
)
OURS_SETTINGS_FAST = ("default", "tol=xtol=1e-6", "tol=xtol=1e-4", "ds_max=0.2")

#: natural-parameter baseline: first step and bracket tolerance in units of 2 pi D / R (F_max ~ 8.9 of them)
NP_NS_FULL = (50, 200, 800, 3200)
NP_NS_FAST = (50, 200)
NP_DP0 = (1.0, 0.25)
NP_DP0_FAST = (1.0,)
NP_BRACKETS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7)
NP_BRACKETS_FAST = (1e-1, 1e-3, 1e-5)
#: a converged load step whose pole displacement jumps by more than this (in R) landed on the far branch
NP_MAX_JUMP = 0.05

#: dynamic relaxation: density [kg/m^3], damping ratio of the lowest mode, and the (dt omega_1, ramp rate
#: dw/dt / (R omega_1)) pairs.  dt omega_1 <= 1 resolves the dynamics; larger steps approach the
#: quasi-static limit, where inertia no longer matters.
DR_DENSITY = 1000.0
DR_ZETA = 1.0
DR_RESOLVED = ((1.0, 1e-3), (1.0, 1e-4))
DR_LARGE_DT = ((1e2, 1e-5), (1e4, 1e-7), (1e6, 1e-9), (1e4, 1e-8), (1e6, 1e-10))
DR_PLAN_FULL: dict[int, tuple[tuple[float, float], ...]] = {
    50: DR_RESOLVED + DR_LARGE_DT,
    200: DR_RESOLVED + ((1.0, 1e-5),) + DR_LARGE_DT,
    800: DR_RESOLVED[:1] + DR_LARGE_DT,
    3200: ((1e6, 1e-9), (1e6, 1e-10)),
}
DR_PLAN_FAST: dict[int, tuple[tuple[float, float], ...]] = {
    50: ((1.0, 1e-3), (1e4, 1e-7), (1e6, 1e-9)),
    200: ((1e6, 1e-9),),
}
#: the ramp stops once F has fallen this much (relative) below its largest recorded value
DR_DROP = 1e-3

#: meshes of the cost per Newton step
COST_NS = (25, 50, 100, 200, 400, 800, 1600, 3200)

#: the boundaries: traced range, fit range and points (as studies.phase_diagram), the ds_max variations
BOUNDARY_PHI_RANGE = (0.95, 1.45)
FIT_PHI = (1.0, 1.45)
FIT_POINTS = 20
BOUNDARY_DS_MAX = 0.05
BOUNDARY_DS_VARIANTS = (0.1, 0.025)
BOUNDARY_DS_N = 100

#: targets of the issue
TARGET_N = 200
TARGET_FAST = {"rel_error": 1e-3, "time_s": 0.5}
TARGET_RICHARDSON = {"rel_error": 1e-6, "time_s": 5.0, "Ns": (200, 400, 800)}
TARGET_DR_RATIO = 100.0

#: runs shorter than this are repeated (median of up to --repeat)
REPEAT_BELOW_S = 1.0


def _scene_shell(N: int, control: str = "displacement") -> ShellPointLoad:
    return ShellPointLoad(R=R, E=E_MOD, nu=NU, h=H_OVER_R * R, phi_hat=PHI_HAT, N=N, control=control)


def _timed(fn: Callable[[], Any], repeat: int) -> tuple[Any, float, list[float]]:
    """Run ``fn``; repeat while a run takes under :data:`REPEAT_BELOW_S` (up to ``repeat`` runs); median time."""
    times = []
    out = None
    for k in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
        if times[0] >= REPEAT_BELOW_S:
            break
    return out, statistics.median(times), times


# ---------------------------------------------------------------------------------------------------
# references, fronts, ratios
# ---------------------------------------------------------------------------------------------------
def reference(ns: Sequence[int], values: Sequence[float]) -> dict[str, Any]:
    """Richardson reference from the three finest meshes, with two error estimates.

    Parameters
    ----------
    ns : sequence of int
        Meshes, each twice the previous.
    values : sequence of float
        The quantity on them (at least three; four for the first estimate).

    Returns
    -------
    dict
        ``value`` (Richardson from the last three), ``order`` (observed there), ``from_Ns``;
        ``previous`` (Richardson from the three before, None with only three meshes) and
        ``estimate_previous = |value - previous|``; ``last_correction = |value - values[-1]|`` (a
        cruder bound: what the extrapolation added); ``error_estimate``: ``estimate_previous`` (the
        last correction when there are only three meshes).
    """
    if len(values) < 3:
        raise ValueError(f"reference: need at least three meshes, got {len(values)}")
    ns = [int(n) for n in ns]
    if any(b != 2 * a for a, b in zip(ns, ns[1:])):
        raise ValueError(f"reference: meshes must double, got {ns}")
    value, p = richardson(values)
    prev = richardson(values[:-1]) if len(values) >= 4 else None
    est_prev = abs(value - prev[0]) if prev is not None else None
    last = abs(value - float(values[-1]))
    est = est_prev if est_prev is not None else last
    return {"value": value, "order": p, "from_Ns": ns[-3:], "previous": prev[0] if prev else None,
            "previous_order": prev[1] if prev else None, "estimate_previous": est_prev, "last_correction": last,
            "error_estimate": est, "relative_error_estimate": est / abs(value)}


def pareto_front(points: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """The ``(time, error)`` points no other point beats in both (sorted by time, errors falling).

    Points with a zero or non-finite error or time are left out (no logarithm).
    """
    pts = sorted((t, e) for t, e in points if t > 0 and e > 0 and math.isfinite(t) and math.isfinite(e))
    front: list[tuple[float, float]] = []
    for t, e in pts:
        if not front or e < front[-1][1]:
            front.append((t, e))
    return front


def _time_at(front: list[tuple[float, float]], err: float) -> float | None:
    """Time a front needs for ``err``, by linear interpolation of log time against log error."""
    if len(front) == 0:
        return None
    errs = np.array([e for _, e in front])
    if not errs.min() <= err <= errs.max():
        return None
    if len(front) == 1:
        return front[0][0]
    x = -np.log(errs)  # increasing along the front
    y = np.log([t for t, _ in front])
    return float(np.exp(np.interp(-math.log(err), x, y)))


def equal_error_ratios(baseline: Sequence[tuple[float, float]], ours: Sequence[tuple[float, float]]) -> dict[str, Any]:
    """Time of ``baseline`` over time of ``ours`` at equal error, on both Pareto fronts.

    Each front is interpolated (log time against log error) at the error levels of the other front
    that lie inside its own range, and at the decades inside the common range.

    Where the fronts do not overlap, a lower bound still holds for every baseline point that some
    run of ours matches or beats in error: ``t_baseline / t_ours`` with ``t_ours`` the shortest
    time of such a run (ours reached at least that accuracy in that time).

    Returns
    -------
    dict
        ``overlap`` (the common error range, None if empty), ``points`` (``error``, ``t_baseline``,
        ``t_ours``, ``ratio``), ``at_decades`` (``{error: ratio}``), ``min``, ``median``, ``max`` (of
        the interpolated ratios); ``lower_bounds`` (``error``, ``t_baseline``, ``t_ours``,
        ``ours_error``, ``ratio_at_least``) and ``lower_bound_min`` / ``lower_bound_max``.
    """
    fb, fo = pareto_front(baseline), pareto_front(ours)
    empty: dict[str, Any] = {"overlap": None, "points": [], "at_decades": {}, "min": None, "median": None, "max": None,
                             "lower_bounds": [], "lower_bound_min": None, "lower_bound_max": None}
    if not fb or not fo:
        return empty
    bounds = []
    for tb, eb in fb:
        better = [(t, e) for t, e in fo if e <= eb]
        if better:
            to, eo = min(better)
            bounds.append({"error": eb, "t_baseline": tb, "t_ours": to, "ours_error": eo, "ratio_at_least": tb / to})
    lb = [b["ratio_at_least"] for b in bounds]
    empty.update({"lower_bounds": bounds, "lower_bound_min": min(lb) if lb else None,
                  "lower_bound_max": max(lb) if lb else None})
    lo = max(min(e for _, e in fb), min(e for _, e in fo))
    hi = min(max(e for _, e in fb), max(e for _, e in fo))
    if lo > hi:
        empty.update({"baseline_range": [min(e for _, e in fb), max(e for _, e in fb)],
                      "ours_range": [min(e for _, e in fo), max(e for _, e in fo)]})
        return empty
    levels = sorted({e for _, e in fb + fo if lo <= e <= hi})
    pts = []
    for e in levels:
        tb, to = _time_at(fb, e), _time_at(fo, e)
        if tb is not None and to is not None:
            pts.append({"error": e, "t_baseline": tb, "t_ours": to, "ratio": tb / to})
    decades = {}
    for k in range(math.ceil(math.log10(lo)), math.floor(math.log10(hi)) + 1):
        e = 10.0 ** k
        tb, to = _time_at(fb, e), _time_at(fo, e)
        if tb is not None and to is not None:
            decades[f"{e:.0e}"] = tb / to
    ratios = [p["ratio"] for p in pts]
    empty.update({"overlap": [lo, hi], "points": pts, "at_decades": decades,
                  "min": min(ratios) if ratios else None, "median": statistics.median(ratios) if ratios else None,
                  "max": max(ratios) if ratios else None})
    return empty


# ---------------------------------------------------------------------------------------------------
# the methods
# ---------------------------------------------------------------------------------------------------
def ours_force_maximum(N: int, **overrides: float) -> tuple[float, float]:
    """``(F_max, w)`` of the default scene by PALC and event location; ``overrides`` change the settings.

    This is :func:`studies.shell_mesh_convergence.first_force_maximum` (from rest, ``ds = 0.02 R``,
    ``ds_max = 0.05 R``, up to ``w = 0.5 R``, the maximum of F a terminal event) with the given
    :class:`contin.Settings` fields changed.

    Raises
    ------
    RuntimeError
        If no maximum is found.
    """
    shell = _scene_shell(N)
    F, w_over_R = first_force_maximum(shell, **overrides)
    return F, w_over_R * shell.R


def natural_parameter_run(N: int, dp0_units: float, bracket_units: float) -> dict[str, Any]:
    """The natural-parameter baseline on the default scene under force control (units of ``2 pi D / R``)."""
    shell = _scene_shell(N, "force")
    unit = 2.0 * math.pi * shell.D / shell.R
    res = natural_parameter_limit(shell, shell.reference_unknowns(), 0.0, dp0_units * unit, bracket_units * unit,
                                  max_jump=("w", NP_MAX_JUMP * shell.R), p_max=1e3 * unit)
    if res.status != "bracketed":
        raise RuntimeError(f"natural-parameter run N = {N}: {res.status}")
    return {"F_max": res.p_limit, "w": res.observables["w"], "bracket": [res.lo, res.hi], "steps": res.steps,
            "failures": res.failures, "newton_iterations": res.counts.iterations}


def dynamic_relaxation_run(N: int, dt_omega: float, eps: float) -> dict[str, Any]:
    """Implicit dynamic relaxation of the default scene: the pole pushed at ``dw/dt = eps R omega_1``.

    ``dt = dt_omega / omega_1``; ``omega_1`` is the lowest frequency at rest with the pole held, the
    damping ``C = 2 zeta omega_1 M`` with ``zeta = DR_ZETA``, the masses ``rho h A_i``.
    """
    shell = _scene_shell(N)
    m = lumped_masses(shell, DR_DENSITY)
    u0 = shell.reference_unknowns()
    w1 = lowest_frequency(shell, u0, 0.0, m)
    alpha = critical_damping(w1, DR_ZETA)
    out = dr_reaction_maximum(shell, u0, m, alpha, dt_omega / w1, eps * shell.R * w1, p_end=0.5 * shell.R, drop=DR_DROP)
    return {"F_max": out["F_max"], "w": out["p_at_max"], "steps": out["steps"],
            "newton_iterations": out["newton_iterations"], "omega_1": w1, "alpha": alpha, "dt": dt_omega / w1,
            "rate": eps * shell.R * w1, "dw_per_step": eps * dt_omega * shell.R}


def newton_step_cost(N: int, repeats: int) -> float:
    """Median seconds of one residual + Jacobian assembly + banded factorization + solve at ``N``.

    A new state (the pole moved by a different amount) each time, so that no cache is hit.
    """
    shell = _scene_shell(N)
    u = shell.reference_unknowns()
    times = []
    for k in range(repeats):
        p = 1e-4 * shell.R * (k + 1) / repeats
        t0 = time.perf_counter()
        r = shell.residual(u, p)
        fac = shell.factorize(shell.jacobian(u, p))
        fac.solve(r)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _located_heights(curve: BoundaryCurve, phis: np.ndarray) -> np.ndarray:
    """``h/R`` on a traced boundary at each ``phi_hat`` of ``phis``: Newton at fixed ``phi_hat`` from the
    linear interpolant of the neighbouring traced points (the traced ends are taken as they are)."""
    problem = curve.problem
    U = np.concatenate([curve.branches[0].u[::-1], curve.branches[1].u[1:]])
    P = np.asarray(curve.phi_hat, dtype=float)
    newton = Curve(problem, Settings())
    out = []
    for phi in phis:
        k = int(np.argmin(np.abs(P - phi)))
        if abs(P[k] - phi) <= 1e-13:
            u = U[k]
        else:
            j = int(min(max(np.searchsorted(P, phi), 1), len(P) - 1))
            a = (phi - P[j - 1]) / (P[j] - P[j - 1])
            u, _, _ = newton.newton_fixed_p((1 - a) * U[j - 1] + a * U[j], float(phi))
        out.append(math.exp(problem.split(u)[1]))
    h = np.array(out)
    if not np.all(np.isfinite(h)):
        raise RuntimeError("located boundary heights are not finite")
    return h


def boundary_quantities(kind: str, N: int, ds_max: float = BOUNDARY_DS_MAX) -> dict[str, Any]:
    """One boundary at ``N``: ``lambda_d`` (located and as the phase diagram interpolates), ``phi_hat`` at
    ``h/R = 0.02``, and the time (tracing plus location)."""
    from studies.phase_diagram import _uniform, fit_eq41, phi_at_mark

    t0 = time.perf_counter()
    event = [contin.crossing("h_over_R", H_OVER_R, name="h_mark")]
    trace = bistable_boundary if kind == "bistable" else monotonous_boundary
    curve = trace(N, BOUNDARY_PHI_RANGE, nu=NU, ds_max=ds_max, events=event)
    phis = np.linspace(FIT_PHI[0], FIT_PHI[1], FIT_POINTS)
    h = _located_heights(curve, phis)
    lam = fit_eq41(phis, h)["squared"]["value"]
    elapsed = time.perf_counter() - t0
    lam_interp = fit_eq41(*_uniform(curve, FIT_PHI[0], FIT_PHI[1], FIT_POINTS))["squared"]["value"]
    try:
        phi, phi_failure = phi_at_mark(curve), None
    except RuntimeError as exc:  # lambda_d stands on its own located points
        phi, phi_failure = None, str(exc)
    return {"lambda_d": lam, "lambda_d_interpolated": lam_interp, "phi_at_h": phi, "phi_failure": phi_failure,
            "time_s": elapsed,
            "trace_time_s": curve.wall_time_s, "steps": [len(b.p) - 1 for b in curve.branches]}


# ---------------------------------------------------------------------------------------------------
# the study
# ---------------------------------------------------------------------------------------------------
def _row(method: str, quantity: str, N: int | None, setting: str, t: float, value: float | None,
         ref: dict[str, Any] | None, **extra: Any) -> dict[str, Any]:
    row: dict[str, Any] = {"method": method, "quantity": quantity, "N": N, "setting": setting, "wall_time_s": t,
                           "value": value}
    if ref is not None and value is not None:
        row["reference"] = ref["value"]
        row["abs_error"] = abs(value - ref["value"])
        row["rel_error"] = row["abs_error"] / abs(ref["value"])
    row.update(extra)
    return row


def _orders(ns: Sequence[int], values: Sequence[float], ref: dict[str, Any]) -> dict[str, Any]:
    return {"Ns": list(ns), "values": list(values), "successive": observed_orders(values) if len(values) >= 3 else [],
            "against_reference": orders_against(values[:-3] if len(values) > 3 else values, ref["value"])
            if len(values) > 3 else [],
            "against_reference_Ns": list(ns[:-3]) if len(values) > 3 else []}


def _quantity_over_N(name: str, ns: Sequence[int], compute: Callable[[int], tuple[float, float]], quiet: bool,
                     label: str) -> tuple[list[float], list[float]]:
    vals, times = [], []
    for N in ns:
        v, t = compute(N)
        if not math.isfinite(v):
            raise RuntimeError(f"{name} at N = {N} is not finite")
        vals.append(v)
        times.append(t)
        say(quiet, f"  {label} N = {N:5d}: {v:.12g}  ({t:.3f} s)")
    return vals, times


def run(full: bool = False, repeat: int = 3, quiet: bool = False) -> dict[str, Any]:
    """Every section of the study; returns ``{"rows": [...], "summary": {...}}``."""
    t_start = time.perf_counter()
    rows: list[dict[str, Any]] = []
    summary: dict[str, Any] = {"mode": "full" if full else "fast", "repeat": repeat,
                               "scene": {"R": R, "h_over_R": H_OVER_R, "phi_hat": PHI_HAT, "nu": NU, "E": E_MOD},
                               "timing": f"median of up to {repeat} runs for runs under {REPEAT_BELOW_S} s, one run "
                                         "otherwise; OPENBLAS_NUM_THREADS="
                                         f"{os.environ.get('OPENBLAS_NUM_THREADS')}"}
    references: dict[str, Any] = {}
    orders: dict[str, Any] = {}
    ns = NS_FULL if full else NS_FAST

    # ---- 1. ours over N (default settings) ---------------------------------------------------------
    say(quiet, f"accuracy: F_max by continuation over N = {ns} ({summary['mode']} mode)")
    ours: dict[int, dict[str, Any]] = {}
    for N in ns:
        (F, w), t, times = _timed(lambda N=N: ours_force_maximum(N), repeat)
        ours[N] = {"F": F, "w": w, "t": t, "times": times}
        say(quiet, f"  N = {N:5d}: F_max = {F:.10f}, w = {w:.10f}  ({t:.3f} s, runs {', '.join(f'{x:.3f}' for x in times)})")
    Fs = [ours[N]["F"] for N in ns]
    ws = [ours[N]["w"] for N in ns]
    references["F_max"] = reference(ns, Fs)
    references["w_at_F_max"] = reference(ns, ws)
    orders["F_max"] = _orders(ns, Fs, references["F_max"])
    orders["w_at_F_max"] = _orders(ns, ws, references["w_at_F_max"])
    refF, refw = references["F_max"], references["w_at_F_max"]
    for N in ns:
        o = ours[N]
        rows.append(_row("ours", "F_max", N, "default", o["t"], o["F"], refF, runs_s=o["times"]))
        rows.append(_row("ours", "w_at_F_max", N, "default", o["t"], o["w"], refw, runs_s=o["times"]))
    for N in COARSE_NS:
        (F, w), t, times = _timed(lambda N=N: ours_force_maximum(N), repeat)
        rows.append(_row("ours", "F_max", N, "default, coarse mesh", t, F, refF, runs_s=times))
        rows.append(_row("ours", "w_at_F_max", N, "default, coarse mesh", t, w, refw, runs_s=times))
        say(quiet, f"  coarse N = {N:3d}: F_max = {F:.10f}, w = {w:.10f}  ({t:.3f} s)")

    # ---- 2. ours: tolerances and step limits ---------------------------------------------------------
    settings_ns = SETTINGS_NS_FULL if full else SETTINGS_NS_FAST
    chosen = [s for s in OURS_SETTINGS[1:] if full or s[0] in OURS_SETTINGS_FAST]
    say(quiet, f"ours: {len(chosen)} setting variations at N = {settings_ns}")
    for N in settings_ns:
        for label, kw in chosen:
            try:
                (F, w), t, times = _timed(lambda N=N, kw=kw: ours_force_maximum(N, **kw), repeat)
            except RuntimeError as exc:
                rows.append(_row("ours", "F_max", N, label, math.nan, None, None, failure=str(exc)))
                say(quiet, f"  N = {N:4d} {label:48s} failed: {exc}")
                continue
            solver = {"solver_rel_error": abs(F - ours[N]["F"]) / abs(refF["value"])}
            rows.append(_row("ours", "F_max", N, label, t, F, refF, runs_s=times, **solver))
            rows.append(_row("ours", "w_at_F_max", N, label, t, w, refw, runs_s=times,
                             solver_rel_error=abs(w - ours[N]["w"]) / abs(refw["value"])))
            say(quiet, f"  N = {N:4d} {label:48s} F_max = {F:.10f} ({t:.3f} s)")

    # ---- 3. ours + Richardson (N, 2N, 4N) -------------------------------------------------------------
    rich = []
    for i in range(len(ns) - 2):
        trio = ns[i:i + 3]
        if list(trio) == refF["from_Ns"]:
            continue  # that is the reference itself
        t = sum(ours[n]["t"] for n in trio)
        F = richardson([ours[n]["F"] for n in trio])[0]
        w = richardson([ours[n]["w"] for n in trio])[0]
        setting = f"Richardson N = {trio[0]}, {trio[1]}, {trio[2]}"
        rows.append(_row("ours+Richardson", "F_max", trio[0], setting, t, F, refF))
        rows.append(_row("ours+Richardson", "w_at_F_max", trio[0], setting, t, w, refw))
        rich.append({"Ns": list(trio), "F_max": F, "w": w, "time_s": t, "rel_error": abs(F - refF["value"]) / abs(refF["value"])})

    # ---- 4. natural-parameter baseline -------------------------------------------------------------
    np_ns = NP_NS_FULL if full else NP_NS_FAST
    say(quiet, f"natural-parameter stepping with bisection at N = {np_ns}")
    for N in np_ns:
        for dp0 in (NP_DP0 if full else NP_DP0_FAST):
            for bt in (NP_BRACKETS if full else NP_BRACKETS_FAST):
                setting = f"dF0={dp0:g}, bracket={bt:g} (units of 2 pi D/R)"
                try:
                    res, t, times = _timed(lambda N=N, dp0=dp0, bt=bt: natural_parameter_run(N, dp0, bt), repeat)
                except (RuntimeError, ValueError) as exc:
                    rows.append(_row("natural_parameter", "F_max", N, setting, math.nan, None, None, failure=str(exc)))
                    say(quiet, f"  N = {N:4d} {setting}: failed ({exc})")
                    continue
                extra = {"steps": res["steps"], "failures": res["failures"], "newton_iterations": res["newton_iterations"],
                         "bracket_lo": res["bracket"][0], "bracket_hi": res["bracket"][1], "runs_s": times}
                if N in ours:
                    extra["solver_rel_error"] = abs(res["F_max"] - ours[N]["F"]) / abs(refF["value"])
                    extra["discretization_rel_error"] = abs(ours[N]["F"] - refF["value"]) / abs(refF["value"])
                rows.append(_row("natural_parameter", "F_max", N, setting, t, res["F_max"], refF, **extra))
                wx = {k: v for k, v in extra.items() if k not in ("solver_rel_error", "discretization_rel_error")}
                if N in ours:
                    wx["solver_rel_error"] = abs(res["w"] - ours[N]["w"]) / abs(refw["value"])
                    wx["discretization_rel_error"] = abs(ours[N]["w"] - refw["value"]) / abs(refw["value"])
                rows.append(_row("natural_parameter", "w_at_F_max", N, setting, t, res["w"], refw, **wx))
                say(quiet, f"  N = {N:4d} {setting}: F_max = {res['F_max']:.10f} ({t:.3f} s, "
                           f"{res['newton_iterations']} Newton iterations)")

    # ---- 5. dynamic relaxation ---------------------------------------------------------------------
    plan = DR_PLAN_FULL if full else DR_PLAN_FAST
    say(quiet, f"implicit dynamic relaxation (displacement ramp) at N = {tuple(plan)}")
    dr_params: dict[int, dict[str, float]] = {}
    for N, combos in plan.items():
        for dt_omega, eps in combos:
            setting = f"dt*omega_1={dt_omega:g}, rate={eps:g} R*omega_1"
            try:
                res, t, times = _timed(lambda N=N, a=dt_omega, e=eps: dynamic_relaxation_run(N, a, e), repeat)
            except (RuntimeError, ValueError) as exc:
                rows.append(_row("dynamic_relaxation", "F_max", N, setting, math.nan, None, None, failure=str(exc),
                                 dt_omega=dt_omega, rate_eps=eps))
                say(quiet, f"  N = {N:4d} {setting}: failed ({exc})")
                continue
            dr_params[N] = {"omega_1": res["omega_1"], "alpha": res["alpha"]}
            extra = {"steps": res["steps"], "newton_iterations": res["newton_iterations"], "dt_omega": dt_omega,
                     "rate_eps": eps, "dt_s": res["dt"], "dw_per_step": res["dw_per_step"], "runs_s": times,
                     "regime": "resolved" if dt_omega <= 1.0 else "large_dt"}
            fx = dict(extra, solver_rel_error=abs(res["F_max"] - ours[N]["F"]) / abs(refF["value"]),
                      discretization_rel_error=abs(ours[N]["F"] - refF["value"]) / abs(refF["value"])) if N in ours else extra
            wx = dict(extra, solver_rel_error=abs(res["w"] - ours[N]["w"]) / abs(refw["value"]),
                      discretization_rel_error=abs(ours[N]["w"] - refw["value"]) / abs(refw["value"])) if N in ours else extra
            rows.append(_row("dynamic_relaxation", "F_max", N, setting, t, res["F_max"], refF, **fx))
            rows.append(_row("dynamic_relaxation", "w_at_F_max", N, setting, t, res["w"], refw, **wx))
            say(quiet, f"  N = {N:4d} {setting}: F_max = {res['F_max']:.10f} ({t:.2f} s, {res['steps']} steps, "
                       f"{res['newton_iterations']} Newton iterations)")
    summary["dynamic_relaxation"] = {
        "density_kg_m3": DR_DENSITY, "damping": "C = alpha M, alpha = 2 zeta omega_1", "zeta": DR_ZETA,
        "mass": "lumped, rho h A_i (ring 2 pi r_i l_i, pole disc pi (l/2)^2)",
        "omega_1_and_alpha_by_N": dr_params, "ramp": "w(t) = rate t, F_max = largest reaction recorded",
        "stop": f"F fallen {DR_DROP:g} (relative) below its largest value",
        "integrator": "implicit Euler on M u'' + C u' + f(u, w(t)) = 0, Newton each step (tol 1e-10 as ours)",
        "plan": {str(N): [list(c) for c in combos] for N, combos in plan.items()},
        "why_displacement_ramp": "the paper moves the pole (displacement boundary condition, figures 3-5) "
                                 "and records the reaction; the force ramp (studies.baselines.dr_snap_load) "
                                 "adds the delayed-bifurcation lag ~ rate^(2/3) of a dead load driven through a fold"}

    # ---- 6. w_b^c of a sphere indenter ---------------------------------------------------------------
    from studies.indenter_size import snap_case

    wb_ns = NS_WB_FULL if full else NS_WB_FAST
    say(quiet, f"w_b^c (sphere r/R = {SPHERE_RADIUS}) over N = {wb_ns}")

    def wb(N: int, extra: Sequence[str] = ()) -> tuple[float, float]:
        t0 = time.perf_counter()
        rec = snap_case(SPHERE_RADIUS, N, tuple(extra))
        return float(rec["w_b_c_over_R"]), time.perf_counter() - t0

    wb_vals, wb_times = _quantity_over_N("w_b^c", wb_ns, wb, quiet, "w_b^c/R")
    references["w_b_c_over_R"] = reference(wb_ns, wb_vals)
    orders["w_b_c_over_R"] = _orders(wb_ns, wb_vals, references["w_b_c_over_R"])
    for N, v, t in zip(wb_ns, wb_vals, wb_times):
        rows.append(_row("ours", "w_b_c_over_R", N, "default", t, v, references["w_b_c_over_R"]))
    if full:
        for label, extra in (("continuation.tol=1e-8", ["continuation.tol=1e-8"]),
                             ("continuation.ds_max=0.025", ["continuation.ds_max=0.025"])):
            v, t = wb(200, extra)
            rows.append(_row("ours", "w_b_c_over_R", 200, label, t, v, references["w_b_c_over_R"],
                             solver_rel_error=abs(v - wb_vals[wb_ns.index(200)]) / abs(references["w_b_c_over_R"]["value"])))
            say(quiet, f"  N = 200 {label}: {v:.12g} ({t:.2f} s)")

    # ---- 7. the boundaries (--full) ------------------------------------------------------------------
    if full:
        boundary_ns: dict[str, list[int]] = {}
        for kind, bns in (("bistable", NS_BISTABLE), ("monotonous", NS_MONOTONOUS)):
            say(quiet, f"{kind} boundary over N = {bns}")
            recs = {}
            qn = f"lambda_d_{kind}"
            for N in bns:
                try:
                    recs[N] = boundary_quantities(kind, N)
                except RuntimeError as exc:  # a failed trace ends the sequence: the finer meshes are not run
                    rows.append(_row("ours", qn, N, "default", math.nan, None, None, failure=str(exc)))
                    say(quiet, f"  N = {N:4d}: failed ({exc}); the {kind} sequence stops here")
                    break
                phi = recs[N]["phi_at_h"]
                say(quiet, f"  N = {N:4d}: lambda_d = {recs[N]['lambda_d']:.10f} (interpolated "
                           f"{recs[N]['lambda_d_interpolated']:.10f}), phi_hat(h/R=0.02) = "
                           f"{recs[N]['phi_failure'] if phi is None else format(phi, '.10f')} ({recs[N]['time_s']:.1f} s)")
            bns = tuple(recs)
            boundary_ns[kind] = list(bns)
            if len(bns) < 3:
                raise RuntimeError(f"the {kind} boundary was traced on {len(bns)} meshes only: no reference")
            lam = [recs[N]["lambda_d"] for N in bns]
            references[qn] = reference(bns, lam)
            orders[qn] = _orders(bns, lam, references[qn])
            lam_i = [recs[N]["lambda_d_interpolated"] for N in bns]
            orders[qn]["interpolated_values"] = lam_i
            for N in bns:
                r = recs[N]
                rows.append(_row("ours", qn, N, "default", r["time_s"], r["lambda_d"], references[qn], steps=str(r["steps"])))
                rows.append(_row("ours", qn, N, "phase_diagram interpolation, ds_max=0.05", r["time_s"],
                                 r["lambda_d_interpolated"], references[qn],
                                 solver_rel_error=abs(r["lambda_d_interpolated"] - r["lambda_d"]) / references[qn]["value"]))
            if kind == "bistable":
                # the meshes up to the first whose crossing of h/R = 0.02 was not located
                located = []
                for N in bns:
                    if recs[N]["phi_at_h"] is None:
                        rows.append(_row("ours", "phi_hat_bistable_at_h_0.02", N, "default", recs[N]["time_s"], None,
                                         None, failure=recs[N]["phi_failure"]))
                        break
                    located.append(N)
                phis = [recs[N]["phi_at_h"] for N in located]
                references["phi_hat_bistable_at_h_0.02"] = reference(located, phis)
                orders["phi_hat_bistable_at_h_0.02"] = _orders(located, phis, references["phi_hat_bistable_at_h_0.02"])
                for N in located:
                    rows.append(_row("ours", "phi_hat_bistable_at_h_0.02", N, "default", recs[N]["time_s"],
                                     recs[N]["phi_at_h"], references["phi_hat_bistable_at_h_0.02"]))
            for ds in BOUNDARY_DS_VARIANTS:
                try:
                    r = boundary_quantities(kind, BOUNDARY_DS_N, ds_max=ds)
                except RuntimeError as exc:
                    rows.append(_row("ours", qn, BOUNDARY_DS_N, f"ds_max={ds:g}", math.nan, None, None, failure=str(exc)))
                    say(quiet, f"  N = {BOUNDARY_DS_N} ds_max = {ds:g}: failed ({exc})")
                    continue
                base = recs[BOUNDARY_DS_N]
                for label, key in ((f"ds_max={ds:g}", "lambda_d"),
                                   (f"phase_diagram interpolation, ds_max={ds:g}", "lambda_d_interpolated")):
                    rows.append(_row("ours", qn, BOUNDARY_DS_N, label, r["time_s"], r[key], references[qn],
                                     solver_rel_error=abs(r[key] - base["lambda_d"]) / references[qn]["value"],
                                     steps=str(r["steps"])))
                if kind == "bistable" and r["phi_at_h"] is not None and base["phi_at_h"] is not None:
                    rows.append(_row("ours", "phi_hat_bistable_at_h_0.02", BOUNDARY_DS_N, f"ds_max={ds:g}", r["time_s"],
                                     r["phi_at_h"], references["phi_hat_bistable_at_h_0.02"],
                                     solver_rel_error=abs(r["phi_at_h"] - base["phi_at_h"])
                                     / references["phi_hat_bistable_at_h_0.02"]["value"]))
                say(quiet, f"  N = {BOUNDARY_DS_N} ds_max = {ds:g}: lambda_d = {r['lambda_d']:.10f} (interpolated "
                           f"{r['lambda_d_interpolated']:.10f}) ({r['time_s']:.1f} s)")
        summary["boundaries"] = {"traced_phi_range": list(BOUNDARY_PHI_RANGE), "fit_phi_range": list(FIT_PHI),
                                 "fit_points": FIT_POINTS, "form": "squared: lambda = lambda_d on the boundary",
                                 "Ns": boundary_ns,
                                 "why_smaller_N": "monotonous: the cusp continuation fails at N = 800 (rounding floor "
                                                  "~N^3); bistable: N = 1600 would take minutes per run"}
    else:
        summary["boundaries"] = "skipped in fast mode (run with --full)"

    # ---- 8. cost per Newton step ---------------------------------------------------------------------
    say(quiet, f"cost per Newton step at N = {COST_NS}")
    cost = {}
    for N in COST_NS:
        reps = max(5, min(200, int(20000 / N))) if full else max(5, min(40, int(4000 / N)))
        cost[N] = newton_step_cost(N, reps)
        say(quiet, f"  N = {N:5d}: {cost[N] * 1e3:.4f} ms (median of {reps})")
    cn = np.array(COST_NS, dtype=float)
    ct = np.array([cost[N] for N in COST_NS])
    fit_all = float(np.polyfit(np.log(cn), np.log(ct), 1)[0])
    big = cn >= 400
    fit_big = float(np.polyfit(np.log(cn[big]), np.log(ct[big]), 1)[0])
    bigger = cn >= 800
    fit_bigger = float(np.polyfit(np.log(cn[bigger]), np.log(ct[bigger]), 1)[0])
    summary["newton_step_cost"] = {"N": list(COST_NS), "seconds": [cost[N] for N in COST_NS],
                                   "exponent_all": fit_all, "exponent_N_ge_400": fit_big,
                                   "exponent_N_ge_800": fit_bigger,
                                   "what": "one residual + Jacobian assembly + banded LU + solve, displacement control"}

    # ---- 9. fronts, ratios, targets ----------------------------------------------------------------------
    summary["references"] = references
    summary["orders"] = orders
    summary["ours_richardson"] = rich
    summary["ratios"] = _all_ratios(rows)
    summary["targets"] = _targets(rows, ours, refF, summary["ratios"], ns)
    summary["wall_time_s"] = time.perf_counter() - t_start
    return {"rows": rows, "summary": summary}


def _points(rows: list[dict[str, Any]], method: str, quantity: str, key: str = "rel_error",
            where: Callable[[dict[str, Any]], bool] = lambda r: True) -> list[tuple[float, float]]:
    return [(r["wall_time_s"], r[key]) for r in rows if r["method"] == method and r["quantity"] == quantity
            and r.get(key) is not None and r.get("value") is not None and where(r)]


def _all_ratios(rows: list[dict[str, Any]]) -> dict[str, Any]:
    resolved = lambda r: r.get("regime") == "resolved"  # noqa: E731
    out: dict[str, Any] = {}
    for q in ("F_max", "w_at_F_max"):
        ours = _points(rows, "ours", q)
        ours_r = _points(rows, "ours+Richardson", q)
        base = {"natural_parameter": _points(rows, "natural_parameter", q),
                "dynamic_relaxation_resolved": _points(rows, "dynamic_relaxation", q, where=resolved),
                "dynamic_relaxation_any_dt": _points(rows, "dynamic_relaxation", q)}
        out[q] = {f"{b}/ours": equal_error_ratios(pts, ours) for b, pts in base.items()}
        out[q].update({f"{b}/ours+Richardson": equal_error_ratios(pts, ours_r) for b, pts in base.items()})
    # solver error only, at N = 200 (against ours' default N = 200 value)
    at = lambda r: r["N"] == TARGET_N  # noqa: E731
    ours_s = _points(rows, "ours", "F_max", "solver_rel_error", at)
    out["F_max_solver_N200"] = {
        "natural_parameter/ours": equal_error_ratios(_points(rows, "natural_parameter", "F_max", "solver_rel_error", at), ours_s),
        "dynamic_relaxation_resolved/ours": equal_error_ratios(
            _points(rows, "dynamic_relaxation", "F_max", "solver_rel_error", lambda r: at(r) and resolved(r)), ours_s),
        "dynamic_relaxation_any_dt/ours": equal_error_ratios(
            _points(rows, "dynamic_relaxation", "F_max", "solver_rel_error", at), ours_s)}
    return out


def _targets(rows: list[dict[str, Any]], ours: dict[int, dict[str, Any]], refF: dict[str, Any],
             ratios: dict[str, Any], ns: Sequence[int]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    o = ours[TARGET_N]
    err = abs(o["F"] - refF["value"]) / abs(refF["value"])
    out["N200_within_1e-3_under_0.5s"] = {"rel_error": err, "time_s": o["t"], "runs_s": o["times"],
                                          "met": bool(err <= TARGET_FAST["rel_error"] and o["t"] < TARGET_FAST["time_s"])}
    trio = TARGET_RICHARDSON["Ns"]
    if all(n in ours for n in trio):
        F = richardson([ours[n]["F"] for n in trio])[0]
        t = sum(ours[n]["t"] for n in trio)
        e = abs(F - refF["value"]) / abs(refF["value"])
        out["richardson_200_400_800_within_1e-6_under_5s"] = {
            "value": F, "rel_error": e, "time_s": t, "reference_rel_error_estimate": refF["relative_error_estimate"],
            "met": bool(e <= TARGET_RICHARDSON["rel_error"] and t < TARGET_RICHARDSON["time_s"]),
            "resolvable": bool(refF["relative_error_estimate"] < TARGET_RICHARDSON["rel_error"])}
    for scope, group in (("total", "F_max"), ("solver_N200", "F_max_solver_N200")):
        for variant in ("dynamic_relaxation_resolved", "dynamic_relaxation_any_dt"):
            for against in ("ours", "ours+Richardson"):
                name = f"{variant}/{against}"
                if name not in ratios[group]:
                    continue
                r = ratios[group][name]
                key = f"{scope}: {name} >= {TARGET_DR_RATIO:g}"
                if r["min"] is not None:
                    out[key] = {"basis": "interpolated at equal error", "met_everywhere": bool(r["min"] >= TARGET_DR_RATIO),
                                "met_somewhere": bool(r["max"] >= TARGET_DR_RATIO), "min": r["min"],
                                "median": r["median"], "max": r["max"], "overlap": r["overlap"],
                                "at_decades": r["at_decades"]}
                elif r["lower_bound_min"] is not None:
                    out[key] = {"basis": "lower bound (no common error range: ours is at least as accurate)",
                                "met_everywhere": bool(r["lower_bound_min"] >= TARGET_DR_RATIO),
                                "met_somewhere": bool(r["lower_bound_max"] >= TARGET_DR_RATIO),
                                "lower_bound_min": r["lower_bound_min"], "lower_bound_max": r["lower_bound_max"]}
                else:
                    out[key] = {"basis": "none: the baseline is more accurate than every run of ours",
                                "met_everywhere": None, "met_somewhere": None}
    return out


# ---------------------------------------------------------------------------------------------------
# figure and main
# ---------------------------------------------------------------------------------------------------
_STYLE = {"ours": ("C0", "o", "ours (PALC + located maximum)"),
          "ours+Richardson": ("C2", "D", "ours + Richardson ($N$, $2N$, $4N$)"),
          "natural_parameter": ("C1", "s", "natural parameter + bisection (force control)"),
          "dynamic_relaxation": ("C3", "^", "dynamic relaxation (displacement ramp)")}


def _dr_size(dt_omega: float | None) -> float:
    """Marker size of a dynamic-relaxation run with a large step: smaller the larger ``dt omega_1``, so the
    runs that differ only in the step (they end on almost the same point) nest instead of covering each other."""
    # 4.5 points a factor 100 in dt: a triangle's sides only clear the next one's by a quarter of that
    return 4.0 + 4.5 * max(0.0, (6.0 - math.log10(max(dt_omega or 1e6, 1.0))) / 2.0)


def _panel(ax: Any, rows: list[dict[str, Any]], quantity: str, key: str, where: Callable[[dict[str, Any]], bool],
           title: str, band: float | None, handles: dict[str, Any] | None = None) -> None:
    """One panel: every run as a marker, each method's Pareto front as a line.  ``handles`` collects one
    legend handle (marker and line) per kind of thing drawn, by label, for a legend of the figure."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    handles = {} if handles is None else handles

    def entry(label: str, **kw: Any) -> None:
        # a later panel that draws the method's front as a line gives the entry its line
        if label not in handles or (kw.get("ls", "-") != "none" and handles[label].get_linestyle() == "None"):
            handles[label] = Line2D([], [], **kw)

    for method, (col, mk, lab) in _STYLE.items():
        sel = [r for r in rows if r["method"] == method and r["quantity"] == quantity and where(r)
               and r.get(key) is not None and r.get(key, 0) > 0 and r.get("value") is not None]
        if not sel:
            continue
        front = pareto_front([(r["wall_time_s"], r[key]) for r in sel])
        drawn_front = len(front) > 1  # a front of one run is that run's marker: no line to draw or name
        if method == "dynamic_relaxation":
            for regime, lab_r in (("resolved", r", $dt\,\omega_1 \leq 1$"),
                                  ("large_dt", r", $dt\,\omega_1 > 1$ (smaller mark: larger $dt$)")):
                s = sorted((r for r in sel if r.get("regime") == regime), key=lambda r: r.get("dt_omega") or 0.0)
                for r in s:
                    big = regime == "large_dt"
                    ax.plot([r["wall_time_s"]], [r[key]], mk, color=col, mfc="none" if big else col, mew=0.8,
                            ms=_dr_size(r.get("dt_omega")) if big else 5.0, ls="none", zorder=4)
                if s:
                    entry(lab + lab_r, color=col, marker=mk, mfc="none" if regime == "large_dt" else col, mew=0.9,
                          ms=5.0, ls="none")
            if drawn_front:
                ax.plot([t for t, _ in front], [e for _, e in front], "-", color=col, lw=1.2)
                entry("dynamic relaxation, best of any $dt$", color=col, lw=1.2)
            res_front = pareto_front([(r["wall_time_s"], r[key]) for r in sel if r.get("regime") == "resolved"])
            if len(res_front) > 1:
                ax.plot([t for t, _ in res_front], [e for _, e in res_front], "--", color=col, lw=1.0)
                entry(r"dynamic relaxation, best with $dt\,\omega_1 \leq 1$", color=col, lw=1.0, ls="--")
            continue
        if method == "ours":
            # the default settings over N open; other solver settings small and filled, so that one that
            # lands on a default run (same error, similar time) shows inside its circle
            base = [r for r in sel if str(r["setting"]).startswith("default")]
            other = [r for r in sel if not str(r["setting"]).startswith("default")]
            ax.plot([r["wall_time_s"] for r in base], [r[key] for r in base], mk, color=col, ms=5, mfc="none",
                    mew=0.8, ls="none", zorder=3)
            if other:
                ax.plot([r["wall_time_s"] for r in other], [r[key] for r in other], mk, color=col, ms=2.6,
                        ls="none", zorder=4)
            if base or drawn_front:
                entry(lab, color=col, marker=mk, ms=5, mfc="none", mew=0.8, lw=1.2 if drawn_front else 0,
                      ls="-" if drawn_front else "none")
            if other:
                entry("ours, other solver settings", color=col, marker=mk, ms=2.6, ls="none")
        else:
            ax.plot([r["wall_time_s"] for r in sel], [r[key] for r in sel], mk, color=col, ms=4.5, mfc="none",
                    mew=0.8, ls="none", zorder=3)
            entry(lab, color=col, marker=mk, ms=4.5, mfc="none", mew=0.8, lw=1.2 if drawn_front else 0,
                  ls="-" if drawn_front else "none")
        if drawn_front:
            ax.plot([t for t, _ in front], [e for _, e in front], "-", color=col, lw=1.2)
        if method == "ours" and key == "rel_error":
            dflt = sorted((r for r in sel if r["setting"] == "default"), key=lambda r: r["N"])
            for r in dflt:
                ax.annotate(f"{r['N']}", (r["wall_time_s"], r[key]), fontsize=7, color=col, xytext=(3, 3.5),
                            textcoords="offset points")
    if band:
        ax.axhspan(1e-20, band, color="0.85", zorder=0)
        handles.setdefault("below the reference's error estimate", Patch(color="0.85"))
    ax.set_xscale("log")
    ax.set_yscale("log")
    # the runs span about two decades of time: 1-2-5 ticks, labelled plainly, so that times can be read
    ax.xaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("wall time [s]")
    ax.set_title(title, fontsize="small")
    ax.grid(True, which="major", lw=0.3)


def _place_labels(fig: Any, axes: Sequence[Any]) -> None:
    """Put each run's ``N`` label beside its marker where it hides least (:func:`studies._common.clearest_offset`):
    the runs' times vary from one run of the study to the next, so a fixed corner can land on another
    method's marker."""
    from matplotlib.text import Annotation

    fig.canvas.draw()  # the layout first: the panels' final size
    for ax in axes:
        placed: list[np.ndarray] = []
        for ann in [t for t in ax.texts if isinstance(t, Annotation) and t.get_text()]:
            best, place = clearest_offset(ax, ann.xy, _LABEL_OFFSETS, placed)
            ann.set_position(_LABEL_OFFSETS[best])
            ann.set_horizontalalignment("center")
            ann.set_verticalalignment("center")
            placed.append(place)


#: Where a run's ``N`` label may go, in points from its marker to the label's centre (up and right first).
_LABEL_OFFSETS = ((9, 7), (9, -7), (-9, 7), (-9, -7))


def plot(res: dict[str, Any], out: Any) -> None:
    """The error-against-time figure: F_max and w (total error) and F_max at N = 200 (solver error only)."""
    import matplotlib.pyplot as plt

    rows, S = res["rows"], res["summary"]
    # a page wide (contin.plot.style.WIDTH): the three panels one above the other, on one time axis (the panels
    # keep the width of their time axis, where the runs crowd), the legend under them
    fig, axes = plt.subplots(3, 1, figsize=(WIDTH, 8.4), sharex=True, layout="constrained")
    all_rows = lambda r: True  # noqa: E731
    vals = [r["rel_error"] for r in rows if r.get("rel_error")] + [1.0]
    handles: dict[str, Any] = {}
    _panel(axes[0], rows, "F_max", "rel_error", all_rows, "(a) $F_{max}$: relative error against the extrapolated value",
           S["references"]["F_max"]["relative_error_estimate"], handles)
    _panel(axes[1], rows, "w_at_F_max", "rel_error", all_rows, "(b) $w$ at $F_{max}$: relative error against the extrapolated value",
           S["references"]["w_at_F_max"]["relative_error_estimate"], handles)
    _panel(axes[2], rows, "F_max", "solver_rel_error", lambda r: r["N"] == TARGET_N,
           f"(c) $F_{{max}}$ at $N$ = {TARGET_N}: solver error only (against ours, default settings)", None, handles)
    axes[0].set_ylabel("relative error")
    axes[1].set_ylabel("relative error")
    axes[2].set_ylabel("relative solver error")
    lo = max(min(vals) / 3, 1e-13)
    for ax in axes[:2]:
        ax.set_ylim(lo, 2.0)
        ax.set_xlabel("")  # the time axis is shared: labelled under the last panel
    fig.suptitle(f"Error against run time, default scene ($\\hat\\phi$ = {PHI_HAT}, $h/R$ = {H_OVER_R}), {S['mode']} mode\n"
                 "(lines: the best error reached within a time, per method; numbers: $N$)")
    # two columns a page wide: the longest entries on two lines
    labels = [lab.replace("(displacement ramp), ", "(displacement ramp),\n") for lab in handles]
    fig.legend(list(handles.values()), labels, loc="outside lower center", ncol=2, frameon=False)
    _place_labels(fig, axes)
    save_figure(fig, out, "error_vs_time")


_CSV_COLUMNS = ("method", "quantity", "N", "setting", "wall_time_s", "value", "reference", "abs_error", "rel_error",
                "solver_rel_error", "discretization_rel_error", "steps", "failures", "newton_iterations", "bracket_lo", "bracket_hi", "dt_omega",
                "rate_eps", "dt_s", "dw_per_step", "regime", "runs_s", "failure")


def write_outputs(res: dict[str, Any], out: Any) -> None:
    """``error_vs_time.png/.pdf``, ``runs.csv`` and ``summary.json`` in ``out``."""
    plot(res, out)
    rows = [{**r, "runs_s": " ".join(f"{x:.6g}" for x in r["runs_s"]) if "runs_s" in r else None} for r in res["rows"]]
    write_csv(out / "runs.csv", rows, _CSV_COLUMNS)
    write_json(out / "summary.json", res["summary"])


def _report(res: dict[str, Any]) -> None:
    S, rows = res["summary"], res["rows"]
    print("References (Richardson from the three finest meshes):")
    table = []
    for q, r in S["references"].items():
        table.append({"quantity": q, "reference": r["value"], "order": r["order"], "from N": str(r["from_Ns"]),
                      "|R - R_prev|": r["estimate_previous"], "last correction": r["last_correction"],
                      "rel. estimate": r["relative_error_estimate"]})
    print_table(table, list(table[0]), digits=10)
    print("\nObserved orders (successive differences; against the reference):")
    for q, o in S["orders"].items():
        print(f"  {q}: {', '.join(f'{x:.3f}' for x in o['successive'])}; "
              f"{', '.join(f'{x:.3f}' for x in o['against_reference'])}")
    c = S["newton_step_cost"]
    print(f"\nCost per Newton step: {', '.join(f'{n}: {t * 1e3:.3f} ms' for n, t in zip(c['N'], c['seconds']))}; "
          f"exponent {c['exponent_all']:.3f} (all), {c['exponent_N_ge_400']:.3f} (N >= 400), "
          f"{c['exponent_N_ge_800']:.3f} (N >= 800)")
    print("\nEqual-error time ratios, F_max (baseline / ours; min, median, max over the common error range):")
    for q in ("F_max", "w_at_F_max", "F_max_solver_N200"):
        for k, r in S["ratios"][q].items():
            if r["min"] is None:
                lb = (f"; ratio at least {r['lower_bound_min']:.3g} .. {r['lower_bound_max']:.3g} (ours as accurate "
                      "or more)") if r["lower_bound_min"] is not None else ""
                print(f"  {q:18s} {k:45s} no common error range{lb}")
            else:
                dec = ", ".join(f"{e}: {v:.3g}" for e, v in r["at_decades"].items())
                print(f"  {q:18s} {k:45s} {r['min']:.3g} / {r['median']:.3g} / {r['max']:.3g} over "
                      f"[{r['overlap'][0]:.1e}, {r['overlap'][1]:.1e}]  (decades: {dec})")
    print("\nTargets:")
    for k, v in S["targets"].items():
        print(f"  {k}: " + ", ".join(f"{a}={_short(b)}" for a, b in v.items() if a not in ("runs_s", "at_decades")))
    n_fail = sum(1 for r in rows if r.get("failure"))
    print(f"\n{len(rows)} rows ({n_fail} failed runs); wall time {S['wall_time_s']:.1f} s")


def _short(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, list):
        return "[" + ", ".join(_short(x) for x in v) + "]"
    return str(v)


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: ``python -m studies.accuracy [--out DIR] [--full] [--repeat K] [--quiet]``."""
    ap = study_parser("accuracy", __doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3, help="runs per timing for runs under 1 s (median; default 3)")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat must be >= 1")
    out = output_dir(args.out)
    res = run(full=args.full, repeat=args.repeat, quiet=args.quiet)
    res["summary"]["command"] = "python -m studies.accuracy " + " ".join(argv if argv is not None else sys.argv[1:])
    write_outputs(res, out)
    _report(res)
    print(f"outputs in {out}")
    return 0


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
