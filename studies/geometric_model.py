"""Geometric model of the contact snap: the critical indenter size from the universal snap shape (paper figures 9-11).

Run ``python -m studies.geometric_model [--out DIR] [--full] [--workers K] [--quiet]``.

The snap shape.  Under a unilateral indenter a bistable cap snaps where the contact force falls to
zero, so its shape there is a force-free equilibrium: the free shell's state at the first falling
``F = 0`` of the bilateral point load (:func:`studies.indenter_size.free_snap_state`, ``N = 200``).
The study checks that the contact runs end on that state (their snap shapes against it, node by node).
A cap without a falling ``F = 0`` before eversion is not bistable: a unilateral indenter never loses it,
so it has no such snap and no ``r_c``; those cases are listed and skipped.  Where the point-load path
folds in ``w`` before ``F = 0`` (deep or thin caps: ``phi_hat = 0.6`` or ``h/R = 0.01``) a small
indenter snaps at that fold, at a finite force, before the force-free state; the cases are marked
(``fold_first``) and the model is still applied to the force-free state, which is where the large
indenters release the shell.

The model (``docs/model.md#what-the-paper-reports``).  The normal to the snap shape at arc length ``s`` (from the pole)
meets the axis at a centre; ``r~(s)`` is the distance from the shell point to it and ``h~(s)`` its
height above the pole.  A sphere with that centre and radius ``r~`` touches the shape at ``s``; it also
passes through the pole where ``r~ - h~ = 0``.  ``r~ - h~ > 0`` near the pole (a sphere resting on the
pole clears the shape there) and changes sign at ``s*``: ``r_c = r~(s*)`` is the largest sphere that
rests on the pole without touching the shape elsewhere (when there are several sign changes, the
smallest ``r~`` at a change from + to -; and never more than the pole's own radius of curvature, the
limit of ``r~`` at the pole, which bounds it when ``r~ - h~ < 0`` from the pole on).  The shape is a cubic spline through the nodes and their
mirror images across the axis, parametrised by arc length (:func:`normal_centres`).  The same number
follows from the nodes alone as ``min_i (r_i^2 + dz_i^2) / (2 dz_i)`` (the radius of the sphere through
the pole and node ``i``); both are reported.

The simulation.  The transition radius of the contact runs is located by bisection in ``r`` on
``Delta_H_at_snap > 1e-4 dhat`` (:func:`studies.indenter_size.locate_transition`), starting from a
bracket around the node-based prediction minus ``dhat`` (the last contact node leaves the barrier at gap
``dhat``, so a sphere of radius ``r`` acts like a sphere of radius ``r + dhat``), placed off-centre
(from 0.9 half-widths below to 1.1 above, so that the prediction is not a bisection point): half-width
0.005 by default (the default run only checks that the transition lies inside), 0.03 with ``--full``,
refined to 1e-3 in r/R.  A bracket that does not hold is widened.  Beside the geometric ``r_c`` (the
limit of a vanishing gap) each case reports the prediction at the simulation's own gap tolerance: a
rigid sphere of radius ``r + dhat`` lowered onto the nodes of the snap shape
(:func:`studies.indenter_size.resting_sphere`) first misses the pole by more than the tolerance.

Figures: ``fig9_geometric_model`` (``r~ - h~`` against ``s``, the predicted and the simulated ``r_c``, and
the spheres touching the snap shape at a few ``s``), ``fig10_thickness`` (snap shapes and ``r_c/R``
against ``h/R`` at ``phi_hat = 0.8``, with a linear fit over ``h/R <= 0.035``), ``fig11_angle`` (snap
shapes, ``r_c/R`` against ``phi_hat`` at ``h/R = 0.02``, the shapes with ``r`` scaled by ``R cos phi_hat``
and ``z - z_pole`` by ``R (1 - sin phi_hat)``, and ``r_c / (R (1 - sin phi_hat))`` against ``phi_hat`` with a
linear fit).  Data: ``geometric_cases.csv`` (every cap), ``simulated_cases.csv``, ``r_tilde_h_tilde.csv``
(the curves of figure 9), ``scaled_shapes.csv``, ``summary.json``.  The default run takes about 12 s on
one core (3 simulated transitions); ``--full`` about 75 s on two (13).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from concurrent.futures import ProcessPoolExecutor  # noqa: E402
from typing import Any  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from scipy.interpolate import CubicSpline  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

from contin.plot.style import WIDTH  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figures, say, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.indenter_size import GAP_TOL_FACTOR, free_snap_state, locate_transition, resting_sphere  # noqa: E402

__all__ = ["normal_centres", "predict_rc", "node_rc", "linear_fit", "collapse", "run", "main"]

PHI_HAT, H_OVER_R = 0.8, 0.02
#: caps of figure 10 (h/R at phi_hat = 0.8) and figure 11 (phi_hat at h/R = 0.02), geometric model
H_FAST = tuple(np.round(np.arange(0.01, 0.05001, 0.005), 4))
H_FULL = tuple(np.round(np.arange(0.01, 0.05001, 0.0025), 4))
PHI_FAST = tuple(np.round(np.arange(0.6, 1.2001, 0.05), 3))
PHI_FULL = tuple(np.round(np.arange(0.6, 1.2001, 0.025), 3))
#: caps whose transition is also simulated, as (phi_hat, h/R)
SIM_FAST = ((0.8, 0.02), (0.8, 0.035), (1.0, 0.02))
SIM_FULL = ((0.8, 0.01), (0.8, 0.015), (0.8, 0.02), (0.8, 0.025), (0.8, 0.03), (0.8, 0.035), (0.8, 0.04),
            (0.8, 0.05), (0.6, 0.02), (0.7, 0.02), (0.9, 0.02), (1.0, 0.02), (1.1, 0.02))
#: bracket half-width around the prediction and final resolution of the simulated r_c (r/R)
HALF_FAST, TOL_FAST = 0.005, 0.01
HALF_FULL, TOL_FULL = 0.03, 1e-3
#: the near-linear range of figure 10 and the paper's range of figure 11
H_LINEAR_MAX = 0.035
PHI_PAPER = (0.6, 1.0)


# ---------------------------------------------------------------------------------------------------
# the geometric model
# ---------------------------------------------------------------------------------------------------
def normal_centres(r: np.ndarray, z: np.ndarray, n: int = 20001) -> dict[str, Any]:
    """Where the normals of a meridian meet the axis: ``r~(s)`` and ``h~(s)`` on a fine grid of arc length.

    Parameters
    ----------
    r, z : ndarray
        Node coordinates, base first and pole last (``r[-1] = 0``).
    n : int
        Grid points in ``s`` between the first node off the pole and the base.

    Returns
    -------
    dict
        ``s`` (arc length from the pole), ``r_tilde``, ``h_tilde``, ``g = r_tilde - h_tilde``, the splines
        ``spline_r``, ``spline_z`` of the meridian (functions of ``s``, the mirror image at ``s < 0``),
        ``s_nodes`` (the nodes' arc lengths, pole first), ``z_pole`` and ``s_crest`` (where the meridian
        stops rising from the pole: beyond it the normals meet the axis below the shell).
    """
    r = np.asarray(r, dtype=float)
    z = np.asarray(z, dtype=float)
    # the meridian continued across the axis by its mirror image: a smooth curve through the pole
    rr = np.concatenate([-r, r[-2::-1]])
    zz = np.concatenate([z, z[-2::-1]])
    chord = np.hypot(np.diff(rr), np.diff(zz))
    s_all = np.concatenate([[0.0], np.cumsum(chord)])
    s_all -= s_all[r.size - 1]
    cr, cz = CubicSpline(s_all, rr), CubicSpline(s_all, zz)
    s_nodes = s_all[r.size - 1:]
    s = np.linspace(s_nodes[1], s_nodes[-1], n)
    out = _centres(cr, cz, s, float(z[-1]))
    # an indenter from above touches only where the normal's centre lies above the shell point, i.e.
    # up to the crest of the meridian (dz/ds = 0), where the centre leaves for infinity
    falling = np.nonzero(cz(s, 1) <= 0)[0]
    s_crest = float(s[falling[0]]) if falling.size else float(s[-1])
    out.update({"s": s, "spline_r": cr, "spline_z": cz, "s_nodes": s_nodes, "z_pole": float(z[-1]),
                "s_crest": s_crest})
    return out


def _centres(cr: CubicSpline, cz: CubicSpline, s: np.ndarray, z_pole: float) -> dict[str, np.ndarray]:
    x, y, dx, dy = cr(s), cz(s), cr(s, 1), cz(s, 1)
    # the normal (-dy, dx) through (x, y) meets r = 0 at t = x / dy
    t = x / dy
    zc = y + t * dx
    r_t = np.abs(t) * np.hypot(dx, dy)
    h_t = zc - z_pole
    return {"r_tilde": r_t, "h_tilde": h_t, "g": r_t - h_t, "z_centre": zc}


def predict_rc(r: np.ndarray, z: np.ndarray) -> dict[str, Any]:
    """The geometric model's critical indenter radius on a snap shape (see the module docstring).

    Parameters
    ----------
    r, z : ndarray
        Node coordinates of the snap shape, base first and pole last.

    Returns
    -------
    dict
        ``r_c`` (units of the coordinates), ``s_star`` (arc length of the contact point), ``z_centre``,
        ``kind`` (``"tangent"``: a sign change of ``r~ - h~`` from + to -, the smallest ``r~`` among
        them; ``"pole"``: the pole's own radius of curvature ``r_pole``, the limit of ``r~`` at
        ``s -> 0``, is smaller, e.g. when ``r~ - h~ < 0`` right next to the pole), ``roots`` (every
        sign change from + to - before the crest, with its ``r~``), ``r_pole`` and ``curves``
        (:func:`normal_centres`).
    """
    nc = normal_centres(r, z)
    s, g = nc["s"], nc["g"]
    cr, cz, zp = nc["spline_r"], nc["spline_z"], nc["z_pole"]

    def gfun(x: float) -> float:
        return float(_centres(cr, cz, np.array([x]), zp)["g"][0])

    roots = []
    for i in np.nonzero((g[:-1] > 0) & (g[1:] <= 0) & (s[1:] < nc["s_crest"]))[0]:
        x = brentq(gfun, s[i], s[i + 1], xtol=1e-14)
        c = _centres(cr, cz, np.array([x]), zp)
        roots.append({"s": x, "r_tilde": float(c["r_tilde"][0]), "z_centre": float(c["z_centre"][0])})
    # the sphere on the pole is also limited by the pole's own curvature: r~ at s -> 0 (extrapolated)
    r_pole = float(np.polyval(np.polyfit(s[:50], nc["r_tilde"][:50], 2), 0.0))
    best = min(roots, key=lambda d: d["r_tilde"]) if roots else None
    if best is None or r_pole < best["r_tilde"]:
        return {"r_c": r_pole, "s_star": 0.0, "z_centre": zp + r_pole, "kind": "pole", "roots": roots,
                "r_pole": r_pole, "curves": nc}
    return {"r_c": best["r_tilde"], "s_star": best["s"], "z_centre": best["z_centre"], "kind": "tangent",
            "roots": roots, "r_pole": r_pole, "curves": nc}


def node_rc(r: np.ndarray, z: np.ndarray) -> float:
    """``min_i (r_i^2 + dz_i^2) / (2 dz_i)`` over the nodes above the pole: the largest sphere through the
    pole, centred on the axis, that holds no node inside (``dz_i = z_i - z_pole``)."""
    r = np.asarray(r, dtype=float)[:-1]
    dz = np.asarray(z, dtype=float)[:-1] - float(z[-1])
    up = dz > 0
    return float(np.min((r[up] ** 2 + dz[up] ** 2) / (2.0 * dz[up])))


def linear_fit(x: Sequence[float], y: Sequence[float]) -> dict[str, Any]:
    """Least-squares line ``y = slope x + intercept`` with ``R^2`` and the largest residual.

    Parameters
    ----------
    x, y : sequence of float
        The points; with fewer than three, every entry but ``n`` is None.

    Returns
    -------
    dict
        ``slope``, ``intercept``, ``r2``, ``n``, ``max_abs_residual``, ``x_range``.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.size < 3:  # a line through two points says nothing about linearity
        return {"slope": None, "intercept": None, "r2": None, "n": int(x.size), "max_abs_residual": None,
                "x_range": None}
    A = np.vstack([x, np.ones_like(x)]).T
    (m, c), *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - (m * x + c)
    ss = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum(res ** 2)) / ss if ss > 0 else 1.0
    return {"slope": float(m), "intercept": float(c), "r2": r2, "n": int(x.size),
            "max_abs_residual": float(np.max(np.abs(res))), "x_range": [float(x.min()), float(x.max())]}


def _scaled(case: dict[str, Any], scale_z: bool = True) -> tuple[np.ndarray, np.ndarray]:
    phi = case["phi_hat"]
    X = case["r"] / math.cos(phi)
    Z = (case["z"] - case["z"][-1]) / ((1.0 - math.sin(phi)) if scale_z else 1.0)
    return X[::-1], Z[::-1]  # pole first


def collapse(cases: Sequence[dict[str, Any]], scale_z: bool = True, n: int = 401) -> dict[str, Any]:
    """How well snap shapes collapse with ``r -> r / (R cos phi_hat)``, ``z - z_pole -> (z - z_pole) / (R (1 - sin phi_hat))``.

    The scaled curves are sampled on a common grid of scaled ``r`` from the pole to the smallest scaled
    base radius (the base slides).  ``scale_z = False`` leaves ``z - z_pole`` unscaled (the baseline).

    Returns
    -------
    dict
        ``max_spread`` (largest difference between the curves at one scaled ``r``), ``range`` (of the
        scaled ``z`` over all curves), ``relative_max_spread``, ``rms_from_mean``, ``relative_rms``,
        ``phi_hat`` (the cases used), ``grid`` and ``curves`` (the resampled curves).
    """
    curves = [_scaled(c, scale_z) for c in cases]
    top = min(float(X.max()) for X, _ in curves)
    grid = np.linspace(0.0, top, n)
    vals = np.array([np.interp(grid, X, Z) for X, Z in curves])
    spread = vals.max(axis=0) - vals.min(axis=0)
    rng = float(vals.max() - vals.min())
    rms = float(np.sqrt(np.mean((vals - vals.mean(axis=0)) ** 2)))
    return {"max_spread": float(spread.max()), "at_scaled_r": float(grid[int(np.argmax(spread))]), "range": rng,
            "relative_max_spread": float(spread.max()) / rng, "rms_from_mean": rms, "relative_rms": rms / rng,
            "phi_hat": [c["phi_hat"] for c in cases], "grid": grid, "curves": vals}


# ---------------------------------------------------------------------------------------------------
# cases
# ---------------------------------------------------------------------------------------------------
def geometric_case(phi_hat: float, h_over_R: float, N: int = 200) -> dict[str, Any]:
    """Snap shape of one cap and its geometric ``r_c`` (no contact run).

    Returns
    -------
    dict
        ``phi_hat``, ``h_over_R``, ``bistable``, ``fold_first`` (the point-load path folds in ``w`` before
        ``F = 0``) with ``F_norm_at_fold``, ``w_s_over_R``, ``kappa_p_R``, ``r_c_geometric`` (spline normals),
        ``s_star``, ``r_c_kind``, ``r_c_nodes`` (node-based), ``r`` and ``z`` (the shape), ``model`` (the
        :func:`predict_rc` result); None entries when the cap is not bistable.
    """
    fs = free_snap_state(phi_hat, h_over_R, N)
    folds = fs["folds_in_w_before"]
    case: dict[str, Any] = {"phi_hat": float(phi_hat), "h_over_R": float(h_over_R), "bistable": fs["bistable"],
                            "fold_first": bool(folds), "F_norm_at_fold": folds[0][1] if folds else None,
                            "w_s_over_R": fs["w_s_over_R"], "kappa_p_R": fs["kappa_p_R"], "r": fs["r"], "z": fs["z"],
                            "r_c_geometric": None, "s_star": None, "r_c_kind": None, "r_c_nodes": None, "model": None,
                            "note": "" if fs["bistable"] else "not bistable: no falling F = 0 before eversion (skipped)"}
    if fs["bistable"]:
        m = predict_rc(fs["r"], fs["z"])
        case.update({"r_c_geometric": m["r_c"], "s_star": m["s_star"], "r_c_kind": m["kind"], "r_c_nodes": node_rc(fs["r"], fs["z"]), "model": m})
        if folds:
            case["note"] = (f"the point-load path folds in w at F R/(2 pi D) = {folds[0][1]:.4g} before F = 0: "
                            "small indenters snap there (finite force, not the universal state)")
    return case


def _resting_transition(r: np.ndarray, z: np.ndarray, dhat: float, gap_tol: float) -> float:
    """Smallest sphere radius ``x`` whose sphere of radius ``x + dhat``, lowered onto the nodes, misses the
    pole by more than ``gap_tol`` (bisection; the gap is 0 up to the transition and grows after it)."""
    a, b = 1e-3, 10.0
    for _ in range(60):
        m = 0.5 * (a + b)
        a, b = (a, m) if resting_sphere(r, z, m + dhat)["gap"] > gap_tol else (m, b)
    return 0.5 * (a + b)


def _sim_job(args: tuple) -> dict[str, Any]:
    phi, h, lo, hi, tol, N = args
    extra = (f"shell.phi_hat={phi}", f"shell.h={h}")
    t0 = time.perf_counter()
    res = locate_transition(lo, hi, N=N, extra=extra, tol=tol, keep_shape=True)
    res["time_s"] = time.perf_counter() - t0
    res["phi_hat"], res["h_over_R"] = phi, h
    return res


def run(full: bool = False, workers: int = 1, quiet: bool = True, N: int = 200) -> dict[str, Any]:
    """Run the study (no files written).

    Parameters
    ----------
    full : bool
        Finer grids of caps and 13 simulated transitions to 1e-3 instead of 3 checked to +-0.01.
    workers : int
        Processes for the simulated transitions (one cap per process).
    quiet : bool
        No progress lines on stderr.
    N : int
        Nodes on the meridian.

    Returns
    -------
    dict
        ``summary`` (summary.json), ``base``, ``h_cases``, ``phi_cases``, ``sim`` (simulated transitions),
        ``collapse`` and ``collapse_baseline``.
    """
    t0 = time.perf_counter()
    hs, phis = (H_FULL, PHI_FULL) if full else (H_FAST, PHI_FAST)
    say(quiet, f"geometric_model: snap shapes of {len(hs) + len(phis)} caps (N = {N})")
    cache: dict[tuple[float, float], dict[str, Any]] = {}

    def case(phi: float, h: float) -> dict[str, Any]:
        key = (round(float(phi), 6), round(float(h), 6))
        if key not in cache:
            cache[key] = geometric_case(key[0], key[1], N)
        return cache[key]

    base = case(PHI_HAT, H_OVER_R)
    h_cases = [case(PHI_HAT, h) for h in hs]
    phi_cases = [case(p, H_OVER_R) for p in phis]

    # simulated transitions, bracketed around the node-based prediction for an effective radius r + dhat
    sims_wanted = SIM_FULL if full else SIM_FAST
    half, tol = (HALF_FULL, TOL_FULL) if full else (HALF_FAST, TOL_FAST)
    dhat = 1e-3  # the default barrier range, in units of R (contin_models.contact.barrier.default_barrier)
    jobs = []
    for phi, h in sims_wanted:
        c = case(phi, h)
        if not c["bistable"]:
            continue
        centre = c["r_c_nodes"] - dhat
        jobs.append((phi, h, round(centre - 0.9 * half, 6), round(centre + 1.1 * half, 6), tol, N))
    say(quiet, f"geometric_model: {len(jobs)} simulated transitions ({workers} process(es))")
    if workers > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            sims = list(pool.map(_sim_job, jobs))
    else:
        sims = [_sim_job(j) for j in jobs]

    sim_rows = []
    for s in sims:
        c = case(s["phi_hat"], s["h_over_R"])
        # the contact runs end on the free snap state: compare every run's snap shape with it (those that
        # release the shell, and those that snap with the pole in contact, separately: a cap whose path
        # folds in w first snaps there while the pole touches, at a finite force)
        dev = {True: 0.0, False: 0.0}
        for e in s["evaluations"]:
            d = max(float(np.abs(e["r"] - c["r"]).max()), float(np.abs(e["z"] - c["z"]).max()))
            dev[e["Delta_H_over_R"] > 0.0] = max(dev[e["Delta_H_over_R"] > 0.0], d)
        at_tol = _resting_transition(c["r"], c["z"], dhat, s["gap_tol_over_R"])
        sim_rows.append({"phi_hat": s["phi_hat"], "h_over_R": s["h_over_R"], "r_c_simulated": s["r_c"],
                         "lo": s["lo"], "hi": s["hi"], "tol": s["tol"], "runs": s["runs"],
                         "r_c_geometric": c["r_c_geometric"], "r_c_nodes": c["r_c_nodes"],
                         "geometric_minus_dhat": c["r_c_geometric"] - dhat,
                         "geometric_minus_dhat_within_bracket": bool(s["lo"] <= c["r_c_geometric"] - dhat <= s["hi"]),
                         "simulated_minus_geometric_plus_dhat": s["r_c"] - (c["r_c_geometric"] - dhat),
                         "resting_sphere_at_gap_tol": at_tol,
                         "resting_sphere_at_gap_tol_within_bracket": bool(s["lo"] <= at_tol <= s["hi"]),
                         "fold_first": c["fold_first"],
                         "max_F_norm_at_pole_contact_snaps": max([e["F_norm_at_snap"] for e in s["evaluations"]
                                                                  if e["Delta_H_over_R"] == 0.0], default=None),
                         "kappa_p_R_at_pole_contact_snaps": sorted(e["kappa_p_R_at_snap"] for e in s["evaluations"]
                                                                   if e["Delta_H_over_R"] == 0.0),
                         "max_release_snap_shape_deviation_over_R": dev[True],
                         "max_contact_snap_shape_deviation_over_R": dev[False], "time_s": s["time_s"]})
        c["r_c_simulated"] = s["r_c"]
        c["r_c_simulated_bracket"] = [s["lo"], s["hi"]]
    for c in cache.values():
        c.setdefault("r_c_simulated", None)
        c.setdefault("r_c_simulated_bracket", None)

    # fits: r_c against h/R (figure 10), r_c / (1 - sin phi) against phi (figure 11)
    def fit_h(rows: list[dict[str, Any]], key: str, hmax: float = H_LINEAR_MAX) -> dict[str, Any]:
        rows = [c for c in rows if c.get(key) is not None and c["h_over_R"] <= hmax + 1e-12]
        return linear_fit([c["h_over_R"] for c in rows], [c[key] for c in rows])

    def fit_phi(rows: list[dict[str, Any]], key: str, rng: tuple[float, float] | None = None,
                normalized: bool = True) -> dict[str, Any]:
        rows = [c for c in rows if c.get(key) is not None and
                (rng is None or rng[0] - 1e-9 <= c["phi_hat"] <= rng[1] + 1e-9)]
        y = [c[key] / ((1.0 - math.sin(c["phi_hat"])) if normalized else 1.0) for c in rows]
        return linear_fit([c["phi_hat"] for c in rows], y)

    sim_h = [case(p, h) for p, h in sims_wanted if p == PHI_HAT and case(p, h)["bistable"]]
    sim_phi = [case(p, h) for p, h in sims_wanted if h == H_OVER_R and case(p, h)["bistable"]]
    fits = {
        "r_c_vs_h_geometric_h_le_0.035": fit_h(h_cases, "r_c_geometric"),
        "r_c_vs_h_geometric_all_h": fit_h(h_cases, "r_c_geometric", hmax=1.0),
        "r_c_vs_h_simulated_h_le_0.035": fit_h(sim_h, "r_c_simulated"),
        "r_c_vs_h_simulated_all_h": fit_h(sim_h, "r_c_simulated", hmax=1.0),
        "r_c_over_1_minus_sin_vs_phi_geometric_paper_range": fit_phi(phi_cases, "r_c_geometric", PHI_PAPER),
        "r_c_over_1_minus_sin_vs_phi_geometric_all_bistable": fit_phi(phi_cases, "r_c_geometric"),
        "r_c_vs_phi_geometric_paper_range_unnormalized": fit_phi(phi_cases, "r_c_geometric", PHI_PAPER, False),
        "r_c_over_1_minus_sin_vs_phi_simulated_paper_range": fit_phi(sim_phi, "r_c_simulated", PHI_PAPER),
        "r_c_over_1_minus_sin_vs_phi_simulated": fit_phi(sim_phi, "r_c_simulated"),
    }
    bist_phi = [c for c in phi_cases if c["bistable"]]
    paper_phi = [c for c in bist_phi if PHI_PAPER[0] - 1e-9 <= c["phi_hat"] <= PHI_PAPER[1] + 1e-9]
    col_all, col_paper = collapse(bist_phi), collapse(paper_phi)
    base_all, base_paper = collapse(bist_phi, scale_z=False), collapse(paper_phi, scale_z=False)
    ws = np.array([c["w_s_over_R"] / (1.0 - math.sin(c["phi_hat"])) for c in bist_phi])

    def slim(d: dict[str, Any]) -> dict[str, Any]:
        return {k: v for k, v in d.items() if k not in ("grid", "curves")}

    def row(c: dict[str, Any]) -> dict[str, Any]:
        keys = ("phi_hat", "h_over_R", "bistable", "fold_first", "F_norm_at_fold", "w_s_over_R", "kappa_p_R",
                "r_c_geometric", "r_c_nodes", "r_c_kind", "s_star", "r_c_simulated", "r_c_simulated_bracket", "note")
        return {k: c.get(k) for k in keys}

    base_sim = next((r for r in sim_rows if r["phi_hat"] == PHI_HAT and r["h_over_R"] == H_OVER_R), None)
    summary: dict[str, Any] = {
        "study": "geometric_model", "paper_figures": [9, 10, 11], "mode": "full" if full else "fast", "N": N,
        "snap_state": "free shell at the first falling F = 0 of the bilateral point load (w_c_one_sided)",
        "base": {"phi_hat": PHI_HAT, "h_over_R": H_OVER_R, "r_c_geometric_over_R": base["r_c_geometric"],
                 "r_c_nodes_over_R": base["r_c_nodes"], "s_star_over_R": base["s_star"], "kind": base["r_c_kind"],
                 "r_c_simulated_over_R": base_sim["r_c_simulated"] if base_sim else None,
                 "r_c_simulated_bracket": [base_sim["lo"], base_sim["hi"]] if base_sim else None,
                 "w_s_over_R": base["w_s_over_R"], "kappa_p_R": base["kappa_p_R"],
                 "max_release_snap_shape_deviation_over_R":
                     base_sim["max_release_snap_shape_deviation_over_R"] if base_sim else None,
                 "max_contact_snap_shape_deviation_over_R":
                     base_sim["max_contact_snap_shape_deviation_over_R"] if base_sim else None},
        "simulated_r_c_definition": (f"bisection in r/R on Delta_H_at_snap > {GAP_TOL_FACTOR:g} dhat "
                                     f"(studies.indenter_size.locate_transition), to {tol:g}; expected: "
                                     "geometric r_c minus dhat (the last contact node leaves at gap dhat) in the "
                                     "limit of a vanishing tolerance, resting_sphere_at_gap_tol at this one"),
        "simulated": sim_rows,
        "h_cases": [row(c) for c in h_cases],
        "phi_cases": [row(c) for c in phi_cases],
        "not_bistable": [{"phi_hat": c["phi_hat"], "h_over_R": c["h_over_R"]} for c in cache.values() if not c["bistable"]],
        "fold_first": [{"phi_hat": c["phi_hat"], "h_over_R": c["h_over_R"], "F_norm_at_fold": c["F_norm_at_fold"]}
                       for c in cache.values() if c["fold_first"]],
        "fits": fits,
        "collapse": {"scaling": "r / (R cos phi_hat), (z - z_pole) / (R (1 - sin phi_hat))",
                     "all_bistable": slim(col_all), "paper_range": slim(col_paper),
                     "baseline_r_scaled_z_unscaled_all_bistable": slim(base_all),
                     "baseline_r_scaled_z_unscaled_paper_range": slim(base_paper),
                     "w_s_over_R_1_minus_sin": {"mean": float(ws.mean()), "min": float(ws.min()), "max": float(ws.max()),
                                                "relative_spread": float((ws.max() - ws.min()) / ws.mean())}},
        "wall_time_s": time.perf_counter() - t0, "workers": workers,
    }
    return {"summary": summary, "base": base, "h_cases": h_cases, "phi_cases": phi_cases, "sims": sims,
            "collapse": col_all, "collapse_baseline": base_all}


# ---------------------------------------------------------------------------------------------------
# figures
# ---------------------------------------------------------------------------------------------------
def _circle(ax: Any, zc: float, rad: float, **kw: Any) -> None:
    t = np.linspace(0, 2 * np.pi, 400)
    ax.plot(rad * np.cos(t), zc + rad * np.sin(t), **kw)


#: The barrier range dhat of the simulated runs, in units of R (as in :func:`run`).
_DHAT = 1e-3


def _fig9(res: dict[str, Any]) -> Any:
    import matplotlib.pyplot as plt

    base, S = res["base"], res["summary"]
    m = base["model"]
    nc = m["curves"]
    # a page wide (contin.plot.style.WIDTH), (a) above (b): side by side, (a) would be too narrow for its note
    fig, (a, b) = plt.subplots(2, 1, figsize=(WIDTH, 8.0), layout="constrained",
                               gridspec_kw={"height_ratios": (1.0, 1.45)})
    keep = nc["s"] < 0.98 * nc["s_crest"]
    a.plot(nc["s"][keep], nc["g"][keep], "-", color="C0", label="$\\tilde r - \\tilde h$ (left axis)")
    a.axhline(0, color="0.6", lw=0.6)
    a.axvline(m["s_star"], color="k", ls="--", lw=0.8, label=f"$s^*/R$ = {m['s_star']:.3f}: $\\tilde r = \\tilde h$")
    a.axvline(nc["s_crest"], color="0.6", ls=":", lw=0.8, label="crest of the snap shape")
    a.set_xlabel("arc length from the pole $s/R$")
    a.set_ylabel("$(\\tilde r - \\tilde h)/R$")
    a2 = a.twinx()
    a2.plot(nc["s"][keep], nc["r_tilde"][keep], ":", color="C2", label="$\\tilde r$ (right axis)")
    a2.set_ylim(0, 3.0)
    a2.set_ylabel("$\\tilde r / R$", color="C2")
    sim = S["base"]["r_c_simulated_over_R"]
    txt = f"geometric model: $r_c/R$ = {m['r_c']:.3f} at $s^*$"
    if sim is not None:
        lo, hi = S["base"]["r_c_simulated_bracket"]
        txt += (f"\ncontact runs: $r_c/R \\in [{lo:.3f}, {hi:.3f}]$,"
                f" $r_c/R + \\hat d \\in [{lo + _DHAT:.3f}, {hi + _DHAT:.3f}]$")
    a.set_title("(a) $\\tilde r - \\tilde h$ along the universal snap shape", fontsize="small")
    a.text(0.02, 0.04, txt, transform=a.transAxes, fontsize="small")
    # between the curve near 0 and the dotted r~ below it, where the band is empty
    h1, l1 = a.get_legend_handles_labels()
    h2, l2 = a2.get_legend_handles_labels()
    a.legend(h1[:1] + h2 + h1[1:], l1[:1] + l2 + l1[1:], loc="center left", bbox_to_anchor=(0.01, 0.62))
    # (b) spheres tangent to the shape at a few s, centred on the axis
    r, z = base["r"], base["z"]
    b.plot(r, z, "-", color="k", lw=2, label="snap shape (free, $F = 0$)")
    b.plot(-r, z, "-", color="k", lw=2)
    picks = [0.5 * m["s_star"], m["s_star"], 0.5 * (m["s_star"] + nc["s_crest"])]
    for k, sv in enumerate(picks):
        c = _centres(nc["spline_r"], nc["spline_z"], np.array([sv]), nc["z_pole"])
        rad, zc = float(c["r_tilde"][0]), float(c["z_centre"][0])
        lab = ["$\\tilde r > \\tilde h$: crosses the pole", "$\\tilde r = \\tilde h$: $r = r_c$",
               "$\\tilde r < \\tilde h$: pole detached"][k]
        _circle(b, zc, rad, color=f"C{k + 1}", lw=1, label=f"$s/R$ = {sv:.3f}, $\\tilde r/R$ = {rad:.3f} ({lab})")
        b.plot([float(nc["spline_r"](sv))], [float(nc["spline_z"](sv))], "o", color=f"C{k + 1}", ms=4)
        b.plot([0], [zc], "+", color=f"C{k + 1}")
    b.set_aspect("equal")
    b.set_xlim(-0.9, 0.9)
    b.set_ylim(0.4, 1.9)
    b.set_xlabel("$x/R$")
    b.set_ylabel("$z/R$")
    # inside the spheres, above the shape and below their centres: the only place no curve crosses
    b.legend(loc="center", bbox_to_anchor=(0.0, 1.12), bbox_transform=b.transData)
    b.set_title("(b) spheres centred on the axis (+), tangent to the snap shape (dots)", fontsize="small")
    return fig


def _plot_r_c(ax: Any, cases: list[dict[str, Any]], x_key: str, scale: Any = None) -> list[dict[str, Any]]:
    """Plot the critical indenter size of ``cases`` against ``c[x_key]`` on ``ax`` (divided by ``scale(case)``
    when given); return the simulated cases.

    The geometric model (one value a cap: markers, a thin line to guide the eye; a larger open circle
    where the fold in w comes before F = 0) and the contact simulations with their bisection brackets.
    """
    f = scale or (lambda c: 1.0)
    ax.plot([c[x_key] for c in cases], [c["r_c_geometric"] / f(c) for c in cases], "o-", color="C0", ms=4, lw=0.8,
            label="geometric model")
    ff = [c for c in cases if c["fold_first"]]
    if ff:
        ax.plot([c[x_key] for c in ff], [c["r_c_geometric"] / f(c) for c in ff], "o", mfc="none", color="C0", ms=8,
                label="fold in $w$ before $F = 0$")
    sims = [c for c in cases if c["r_c_simulated"] is not None]
    if sims:
        # the bracket is the result, and about as tall as a marker: drawn alone, its caps wider than the
        # model's dot (the two agree to about dhat), so that neither hides the other
        ax.errorbar([c[x_key] for c in sims], [c["r_c_simulated"] / f(c) for c in sims],
                    yerr=[[(c["r_c_simulated"] - c["r_c_simulated_bracket"][0]) / f(c) for c in sims],
                          [(c["r_c_simulated_bracket"][1] - c["r_c_simulated"]) / f(c) for c in sims]],
                    fmt="none", ecolor="C3", elinewidth=1.0, capsize=4.5, capthick=1.3, zorder=3,
                    label="contact simulation (bisection bracket)")
    return sims


def _fig10(res: dict[str, Any]) -> Any:
    import matplotlib.pyplot as plt

    cases = [c for c in res["h_cases"] if c["bistable"]]
    fits = res["summary"]["fits"]
    # a page wide (contin.plot.style.WIDTH), (a) above (b): side by side, the legends would cover the curves
    fig, (a, b) = plt.subplots(2, 1, figsize=(WIDTH, 6.6), layout="constrained")
    for k, c in enumerate(cases):
        col = plt.cm.viridis(k / max(len(cases) - 1, 1))
        a.plot(c["r"], c["z"], "-", color=col, lw=1, label=f"{c['h_over_R']:g}")
        a.plot(-c["r"], c["z"], "-", color=col, lw=1)
    a.set_xlabel("$x/R$")
    a.set_ylabel("$z/R$")
    a.set_title(f"(a) snap shapes, $\\hat\\phi$ = {PHI_HAT} ($z$ exaggerated)", fontsize="small")
    # above the dips, between the crests
    a.legend(ncol=3, title="$h/R$", loc="upper center")
    h = np.array([c["h_over_R"] for c in cases])
    _plot_r_c(b, cases, "h_over_R")
    f = fits["r_c_vs_h_geometric_h_le_0.035"]
    if f["slope"] is not None:
        hh = np.linspace(h.min(), H_LINEAR_MAX, 50)
        b.plot(hh, f["slope"] * hh + f["intercept"], "--", color="k", lw=0.8,
               label=f"linear fit, $h/R \\leq {H_LINEAR_MAX:g}$: slope ${f['slope']:.3g}$, $R^2$ = {f['r2']:.3f}")
    b.set_xlabel("$h/R$")
    b.set_ylabel("$r_c/R$")
    b.set_title(f"(b) critical indenter size against thickness, $\\hat\\phi$ = {PHI_HAT}", fontsize="small")
    b.legend(loc="upper right")
    return fig


def _fig11(res: dict[str, Any]) -> Any:
    import matplotlib.pyplot as plt

    cases = [c for c in res["phi_cases"] if c["bistable"]]
    S = res["summary"]
    # a page wide (contin.plot.style.WIDTH): the shapes in the left column, the critical sizes in the right one,
    # each column's legend (the same for both its panels) under it, where it hides no curve
    fig, axes = plt.subplots(2, 2, figsize=(WIDTH, 7.9), layout="constrained")
    (a, b), (c_, d) = axes
    for k, c in enumerate(cases):
        col = plt.cm.plasma(k / max(len(cases), 1))
        a.plot(c["r"], c["z"], "-", color=col, lw=1, label=f"{c['phi_hat']:g}")
        a.plot(-c["r"], c["z"], "-", color=col, lw=1)
        X, Z = _scaled(c)
        c_.plot(X, Z, "-", color=col, lw=1, label=f"{c['phi_hat']:g}")
    a.set_xlabel("$x/R$")
    a.set_ylabel("$z/R$")
    a.set_title(f"(a) snap shapes, $h/R$ = {H_OVER_R} ($z$ exaggerated)", fontsize="small")
    col = S["collapse"]
    c_.set_xlabel("$r / (R\\cos\\hat\\phi)$")
    c_.set_ylabel("$(z - z_\\mathrm{pole}) / (R(1 - \\sin\\hat\\phi))$")
    c_.set_title(f"(c) scaled snap shapes: max spread {col['all_bistable']['max_spread']:.3f}\n"
                 f"({100 * col['all_bistable']['relative_max_spread']:.0f} % of the range; unscaled $z$: "
                 f"{100 * col['baseline_r_scaled_z_unscaled_all_bistable']['relative_max_spread']:.0f} %)", fontsize="small")
    c_.legend(ncol=4, title="$\\hat\\phi$", loc="upper center", bbox_to_anchor=(0.5, -0.2), handlelength=1.8,
              columnspacing=1.2)
    _plot_r_c(b, cases, "phi_hat")
    nb = S["not_bistable"]
    nbp = [x["phi_hat"] for x in nb if x["h_over_R"] == H_OVER_R]
    if nbp:
        b.axvspan(min(nbp) - 0.0125, max(nbp) + 0.0125, color="0.9", label="not bistable (no snap at $F = 0$)")
    b.set_xlabel("$\\hat\\phi$")
    b.set_ylabel("$r_c/R$")
    b.set_title(f"(b) $r_c$ against the base angle, $h/R$ = {H_OVER_R}", fontsize="small")
    _plot_r_c(d, cases, "phi_hat", scale=lambda c: 1.0 - math.sin(c["phi_hat"]))
    f = S["fits"]["r_c_over_1_minus_sin_vs_phi_geometric_paper_range"]
    if f["slope"] is not None:
        pp = np.linspace(*PHI_PAPER, 50)
        d.plot(pp, f["slope"] * pp + f["intercept"], "--", color="k", lw=0.8,
               label=f"linear fit, ${PHI_PAPER[0]:g} \\leq \\hat\\phi \\leq {PHI_PAPER[1]:g}$:\n"
                     f"slope ${f['slope']:.3g}$, $R^2$ = {f['r2']:.3f}")
    d.set_xlabel("$\\hat\\phi$")
    d.set_ylabel("$r_c / (R(1 - \\sin\\hat\\phi))$")
    d.set_title("(d) normalized critical indenter size", fontsize="small")
    # one legend for (b) and (d): what both draw, then the fit of (d) and the band of (b)
    handles: dict[str, Any] = {}
    for ax in (d, b):
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    d.legend(list(handles.values()), list(handles), loc="upper center", bbox_to_anchor=(0.5, -0.2))
    return fig


def write_outputs(res: dict[str, Any], out: Any) -> None:
    """Write figures 9-11 and the tables of a :func:`run` result to ``out``.

    Tables: ``geometric_cases.csv``, ``simulated_cases.csv``, ``r_tilde_h_tilde.csv``, ``scaled_shapes.csv`` and
    ``summary.json``.
    """
    save_figures(out, res, {"fig9_geometric_model": _fig9, "fig10_thickness": _fig10, "fig11_angle": _fig11})
    S = res["summary"]
    seen = set()
    rows = []
    for c in S["h_cases"] + S["phi_cases"]:
        key = (c["phi_hat"], c["h_over_R"])
        if key not in seen:
            seen.add(key)
            rows.append({k: v for k, v in c.items() if k != "r_c_simulated_bracket"})
    write_csv(out / "geometric_cases.csv", rows)
    write_csv(out / "simulated_cases.csv", S["simulated"])
    nc = res["base"]["model"]["curves"]
    step = max(len(nc["s"]) // 2000, 1)
    write_csv(out / "r_tilde_h_tilde.csv",
              [{"s_over_R": s, "r_tilde_over_R": a, "h_tilde_over_R": b, "r_tilde_minus_h_tilde": a - b}
               for s, a, b in zip(nc["s"][::step], nc["r_tilde"][::step], nc["h_tilde"][::step])])
    col = res["collapse"]
    write_csv(out / "scaled_shapes.csv",
              [{"scaled_r": g, **{f"phi_{p:g}": col["curves"][i][j] for i, p in enumerate(col["phi_hat"])}}
               for j, g in enumerate(col["grid"])])
    write_json(out / "summary.json", S)


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m studies.geometric_model [--out DIR] [--full] [--workers K] [--quiet]``."""
    ap = study_parser("geometric_model", __doc__.split("\n")[0])
    ap.add_argument("--workers", type=int, default=None,
                    help="processes for the simulated transitions (default: 2 with --full, else 1)")
    args = ap.parse_args(argv)
    out = output_dir(args.out)
    workers = args.workers if args.workers is not None else (2 if args.full else 1)
    t0 = time.perf_counter()
    res = run(full=args.full, workers=workers, quiet=args.quiet)
    S = res["summary"]
    S["command"] = "python -m studies.geometric_model " + " ".join(argv if argv is not None else sys.argv[1:])
    write_outputs(res, out)
    rows = [{"phi_hat": r["phi_hat"], "h/R": r["h_over_R"], "r_c geometric": r["r_c_geometric"],
             "geo - dhat": r["geometric_minus_dhat"], "sphere at tol": r["resting_sphere_at_gap_tol"],
             "simulated bracket": f"{r['lo']:.5f}..{r['hi']:.5f}",
             "geo-dhat in": "yes" if r["geometric_minus_dhat_within_bracket"] else "no",
             "at tol in": "yes" if r["resting_sphere_at_gap_tol_within_bracket"] else "no",
             "fold first": r["fold_first"], "release shape dev/R": r["max_release_snap_shape_deviation_over_R"]}
            for r in S["simulated"]]
    print_table(rows, list(rows[0]), digits=5)
    for name, f in S["fits"].items():
        if f["slope"] is not None:
            print(f"fit {name}: slope {f['slope']:.4f}, intercept {f['intercept']:.4f}, R^2 {f['r2']:.6f} (n = {f['n']})")
    c = S["collapse"]
    print(f"collapse (all bistable phi_hat): max spread {c['all_bistable']['max_spread']:.4f} = "
          f"{100 * c['all_bistable']['relative_max_spread']:.1f} % of the range (z unscaled: "
          f"{100 * c['baseline_r_scaled_z_unscaled_all_bistable']['relative_max_spread']:.1f} %); "
          f"w_s/(R(1 - sin phi_hat)) = {c['w_s_over_R_1_minus_sin']['min']:.4f} .. {c['w_s_over_R_1_minus_sin']['max']:.4f}")
    if S["not_bistable"]:
        print("not bistable (skipped): " + ", ".join(f"phi_hat = {d['phi_hat']:g}, h/R = {d['h_over_R']:g}"
                                                     for d in S["not_bistable"]))
    print(f"wall time {time.perf_counter() - t0:.1f} s; outputs in {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
