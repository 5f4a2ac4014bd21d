"""Indenter size: where a rigid sphere snaps the cap, against its radius (paper figures 6-8).

Run ``python -m studies.indenter_size [--out DIR] [--full] [--workers K | --scheduler ADDRESS] [--quiet]``.

The cap is the paper's (``phi_hat = 0.8``, ``h/R = 0.02``, ``nu = 0.5``, ``N = 200``, the default barrier
``K_c = 100 E R``, ``dhat = 1e-3 R``), indented by a rigid sphere of radius ``r`` whose travel ``w_b`` is
prescribed.  Every radius is the runner's first loading stretch
(:func:`studies.bench_contact.run_to_snap`, the settings of ``contin trace``), from the first touch of
the barrier to the located snap: a fold in ``w_b`` while the pole is in contact, or the release fold
beyond ``F -> 0`` once the last contact node is off the axis (``models/shell_scene/contact.py``).

What it computes
----------------
* For ``r/R`` in [0.1, 2.0] (8 radii by default, 20 with ``--full``): the snap travel ``w_b^c``, the
  pole-indenter gap ``Delta H`` at the snap, the pole curvature ``kappa_p R`` and pole travel ``w_s`` at
  the snap, and the contact mode on the way (figure 6; ``contact_mode`` as the runner defines it: a gap
  counts once it exceeds ``dhat``; ``contact_mode_strict`` counts any gap).
* The transition radius ``r_c``: the smallest ``r`` whose snap has the pole detached, located by
  bisection in ``r`` on ``Delta_H_at_snap > GAP_TOL_FACTOR * dhat`` (1e-4 ``dhat`` = 1e-7 R): to 1e-3 in
  ``r/R`` with ``--full``, to 0.025 by default.  Below ``r_c`` the pole is inside the barrier at the
  snap and ``Delta H`` is exactly 0; above it ``Delta H`` is the gap of a converged state (to ~1e-9 R),
  so any tolerance between separates the two sides.  A tolerance ``t`` moves the located ``r_c`` up by
  about ``t / (dDelta_H/dr)``: ``dDelta_H/dr ~ 0.17`` at ``r_c`` for this cap (6e-7 for 1e-7 R, 6e-3 for
  ``t = dhat``), but where the ring the sphere rests on lies close to the pole (``h/R = 0.05`` or
  ``phi_hat = 1.1`` in :mod:`studies.geometric_model`) the gap opens slowly and a tolerance of
  0.01 ``dhat`` would already move ``r_c`` by 2e-3 to 5e-3; hence the small one.  With ``--full`` the
  two contact-mode boundaries are bisected as well: detach (``Delta_H_at_snap > dhat``, the runner's
  convention) and continuous -> detach-recontact (the largest pole gap on the stored points before
  the snap exceeds ``dhat``; a sampled maximum, so that boundary is an upper estimate, to 0.01).
* Universality of the snap state: the shape at each snap against the free shell's state at the first
  falling ``F = 0`` of the bilateral point load (:func:`free_snap_state`; ``w_c_one_sided`` of the point
  scene), and a prediction of ``Delta H`` and ``w_b^c`` that needs no contact run: lower a rigid sphere
  of radius ``r + dhat`` along the axis onto the nodes of that free snap shape (the last contact node
  leaves at gap ``dhat``); it rests on the pole (``Delta H = 0``, ``w_b^c = w_s``) or on a ring, with
  the pole ``Delta H`` below it and ``w_b^c = w_s - Delta H`` (:func:`resting_sphere`).
* Figure 8: ``kappa_p R`` and ``Delta H / R`` along the loading paths against ``w_b`` and ``w_s`` for
  ``r/R`` in :data:`FIG8_RADII`, with the point load's path for reference.

Outputs (in ``--out``, default ``out/indenter_size``): ``fig6_snap_vs_radius``, ``fig7_snap_configurations``,
``fig8_pole_curvature`` (PNG and PDF), ``cases.csv`` (one row per radius), ``paths.csv`` (the loading
paths), ``bisection.csv`` (every run of the bisections) and ``summary.json`` (``r_c_over_R``, ``cases``
and the checks).  The default run takes about 15 s on one core; ``--full`` about a minute on two.

The contact runs (the radii, then each round of a bisection) go through an executor
(:mod:`contin.app.executors`): ``--workers K`` local processes (default 1, 2 with ``--full``) or a Dask
cluster (``--scheduler ADDRESS``).  How many radii a bisection round runs is fixed by the mode
(:data:`PER_ROUND_FAST`, :data:`PER_ROUND_FULL`), not by the executor, so the outputs (but the wall
times) are the same whatever runs them.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from typing import Any  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin.app.executors import Executor, make_executor  # noqa: E402
from contin.app.scene import load_scene  # noqa: E402
from contin.plot.style import WIDTH  # noqa: E402
from contin_models.contact.barrier import ContactCells  # noqa: E402
from contin_models.shell_scene.contact import contact_mode  # noqa: E402
from contin_models.shell.problem import ShellPointLoad  # noqa: E402
from contin_models.shell_scene import SHELL_SCHEMA, eversion_displacement, point_problem, point_settings  # noqa: E402
from studies._common import (executor_from_args, output_dir, print_table, run_study, save_figures, say,  # noqa: E402
                             study_parser, write_csv, write_json)
from studies.bench_contact import run_to_snap, snap_settings  # noqa: E402

__all__ = ["PHI_HAT", "H_OVER_R", "GAP_TOL_FACTOR", "RADII_FAST", "RADII_FULL", "FIG8_RADII", "PER_ROUND_FAST",
           "PER_ROUND_FULL", "free_snap_state", "resting_sphere", "snap_case", "locate_transition", "run", "main"]

#: The cap of the paper's contact study (figures 6-8).
PHI_HAT = 0.8
H_OVER_R = 0.02
#: Bisection on ``Delta_H_at_snap > GAP_TOL_FACTOR * dhat``.
GAP_TOL_FACTOR = 1e-4
#: Radii (r/R) of the default run and of ``--full``.
RADII_FAST = (0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 2.0)
RADII_FULL = tuple(round(0.1 * k, 1) for k in range(1, 21))
#: Radii whose loading paths figure 8 shows (the paper: r/R = 0.3 to 1.1).
FIG8_RADII = (0.3, 0.5, 0.7, 0.9, 1.1)
#: Resolution in r/R of the bisection for r_c.
TOL_FAST, TOL_FULL = 0.025, 1e-3
#: Resolution in r/R of the continuous -> detach-recontact boundary (--full only).
TOL_MODE = 0.01
#: Radii per bisection round, by mode (the runs of a round are parallel; fixed so that the bisection,
#: hence the outputs, do not depend on the executor).
PER_ROUND_FAST, PER_ROUND_FULL = 1, 2

_PATH_OBS = ("w_b_over_R", "w_s_over_R", "F_norm", "kappa_p_R", "Delta_H_over_R", "n_contact")


# ---------------------------------------------------------------------------------------------------
# the free shell at the snap (bilateral point load)
# ---------------------------------------------------------------------------------------------------
def _pole_curvature_R(P: ShellPointLoad, x: np.ndarray) -> float:
    """Pole curvature times R of a full state, by the model's own pole element."""
    return P.pole_curvature(x) * P.R


def free_snap_state(phi_hat: float = PHI_HAT, h_over_R: float = H_OVER_R, N: int = 200, R: float = 1.0,
                    path: bool = False) -> dict[str, Any]:
    """The free shell's snap state: the bilateral point load's path at its first falling ``F = 0``.

    The pole displacement ``w`` is prescribed (``contin trace``'s settings for the point scene) from the
    reference state; the path runs through any fold in ``w`` and stops at the first falling zero of
    the force, or at eversion ``2 R (1 - sin phi_hat)`` plus 5 %.  A cap that reaches eversion without
    ``F = 0`` is not bistable: no state is force free on the way, so a unilateral indenter never
    loses it (``"bistable": False``, no shape).

    Parameters
    ----------
    phi_hat, h_over_R : float
        The cap (``R = 1`` units; ``E = 1e6``, ``nu = 0.5``).
    N : int
        Nodes on the meridian.
    R : float
        Sphere radius (the results in units of R do not depend on it).
    path : bool
        Also return the loading path (``w/R``, ``F R / (2 pi D)``, ``kappa_p R`` per stored point).

    Returns
    -------
    dict
        ``bistable``; ``r``, ``z`` (node coordinates, base first, pole last), ``w_s_over_R`` (pole
        travel), ``kappa_p_R`` and ``F_norm`` at ``F = 0``; ``folds_in_w_before``: the folds of the path
        in ``w`` before ``F = 0`` as ``(w/R, F_norm)`` (when there is one, a unilateral point indenter
        snaps there, at a finite force, before the force-free state); ``status``; optional ``path``.
    """
    scene = load_scene(SHELL_SCHEMA, None, [f"shell.N={N}", f"shell.phi_hat={phi_hat}", f"shell.h={h_over_R * R}",
                                            f"shell.R={R}"])
    P = point_problem(scene, "displacement")
    w_end = eversion_displacement(R, phi_hat) * (1.0 + scene["continuation"]["overshoot"])
    st = point_settings(scene, P)
    st.stability = False
    br = contin.continuation(P, P.reference_unknowns(), 0.0, st, p_max=w_end,
                             events=[contin.crossing("F", 0.0, direction=-1, terminal=True, name="F = 0")])
    f_scale = R / (2.0 * math.pi * P.D)
    folds = [(float(sp.p) / R, float(sp.observables["F"]) * f_scale) for sp in br.special_points if sp.kind == "fold"]
    out: dict[str, Any] = {"phi_hat": phi_hat, "h_over_R": h_over_R, "N": N, "status": br.status,
                           "message": br.message, "folds_in_w_before": folds}
    zero = br.events("F = 0")
    if br.status != "event" or not zero:
        out.update({"bistable": False, "r": None, "z": None, "w_s_over_R": None, "kappa_p_R": None, "F_norm": None})
    else:
        sp = zero[-1]
        x = P.full_state(sp.u, sp.p)
        out.update({"bistable": True, "r": x[0::2].copy() / R, "z": x[1::2].copy() / R,
                    "w_s_over_R": float(sp.p) / R, "kappa_p_R": _pole_curvature_R(P, x),
                    "F_norm": float(sp.observables["F"]) * f_scale})
    if path:
        kap = [_pole_curvature_R(P, P.full_state(u, p)) for u, p in zip(br.u, br.p)]
        out["path"] = {"w_over_R": br.p / R, "F_norm": br.observable("F") * f_scale, "kappa_p_R": np.array(kap)}
    return out


def resting_sphere(r: np.ndarray, z: np.ndarray, radius: float) -> dict[str, float]:
    """A rigid sphere centred on the axis, lowered from above onto the points ``(r, z)`` until it touches.

    The points are the nodes, or the meridian as the barrier sees it (:func:`barrier_curve`).

    The centre comes to rest at ``c = max_i (z_i + sqrt(radius^2 - r_i^2))`` over the nodes with
    ``r_i < radius`` (the pole, ``r = 0``, always among them).

    Parameters
    ----------
    r, z : ndarray
        Node coordinates, pole last (``r[-1] = 0``).
    radius : float
        Sphere radius.

    Returns
    -------
    dict
        ``gap``: the pole's distance below the sphere (``c - radius - z_pole``, 0 when the sphere rests
        on the pole), ``node``: index of the node it rests on, ``centre``: ``c``.
    """
    r = np.asarray(r, dtype=float)
    z = np.asarray(z, dtype=float)
    inside = np.nonzero(r < radius)[0]
    heights = z[inside] + np.sqrt(radius * radius - r[inside] ** 2)
    k = int(np.argmax(heights))
    c = float(heights[k])
    gap = c - radius - float(z[-1])
    return {"gap": gap if gap > 1e-12 * radius else 0.0, "node": int(inside[k]), "centre": c}


def barrier_curve(r: np.ndarray, z: np.ndarray, per_cell: int = 64) -> tuple[np.ndarray, np.ndarray]:
    """Points of the meridian as the contact barrier sees it, pole last (at ``r = 0``).

    The base node itself, then each cell's curve (:meth:`contin_models.contact.ContactCells.curve`,
    the quadratic B-spline of the nodes) sampled at ``per_cell`` intervals of ``t`` in
    ``[-1/2, 1/2]``; the pole's cell only up to ``t = 0``, where it crosses the axis.
    """
    r = np.asarray(r, dtype=float)
    z = np.asarray(z, dtype=float)
    cells = np.arange(1, r.size)
    R, Z = ContactCells(r.size, 1).curve(r, z, cells)
    t = np.linspace(-0.5, 0.5, per_cell + 1)
    powers = np.stack([np.ones_like(t), t, t * t])
    rc, zc = (R @ powers).ravel(), (Z @ powers).ravel()
    keep = np.ones(rc.size, dtype=bool)
    keep[-(per_cell // 2):] = False  # the pole's cell beyond the axis: the mirror image
    rc, zc = np.concatenate([r[:1], rc[keep]]), np.concatenate([z[:1], zc[keep]])
    rc[-1] = 0.0  # on the axis (rounding)
    return rc, zc


# ---------------------------------------------------------------------------------------------------
# one radius to its snap
# ---------------------------------------------------------------------------------------------------
def snap_case(r: float, N: int = 200, extra: Sequence[str] = (), keep_path: bool = False,
              keep_shape: bool = False) -> dict[str, Any]:
    """A sphere of radius ``r`` (units of R = 1) to its snap: the snap's observables and the contact mode.

    Parameters
    ----------
    r : float
        Sphere radius.
    N : int
        Nodes on the meridian.
    extra : sequence of str
        Further scene overrides (``"shell.h=0.03"``, ``"shell.phi_hat=1.0"``, ...).
    keep_path, keep_shape : bool
        Also return the loading path (the observables of :data:`_PATH_OBS` per stored point, the snap
        appended, and ``path_tangents``: the arclength ``s`` and ``d/ds`` of ``w_b_over_R`` and
        ``F_norm`` where the branch stores them, NaN at the snap) and the node coordinates at the snap.

    Returns
    -------
    dict
        ``r_over_R``, ``w_b_c_over_R``, ``Delta_H_over_R``, ``kappa_p_R_at_snap``, ``w_s_over_R``,
        ``F_norm_at_snap``, ``snap_label`` (``"release"`` for the release fold), ``contact_mode`` (gap
        counted beyond ``dhat``, as the runner), ``contact_mode_strict`` (any gap),
        ``max_gap_before_snap_over_R``, ``n_contact_at_snap``, ``dhat``, ``points``, ``time_s``.
    """
    t0 = time.perf_counter()
    P, st, w_end = snap_settings(r, N, tuple(extra), stability=False)
    br, sp = run_to_snap(P, st, w_end)
    if sp is None:
        raise RuntimeError(f"r/R = {r} ({', '.join(extra)}): no snap ({br.status}: {br.message})")
    obs = sp.observables
    R = P.R
    gaps = np.append(br.observable("Delta_H"), obs["Delta_H"])
    mode, max_gap = contact_mode(gaps, P.dhat)
    strict, _ = contact_mode(gaps, 0.0)
    rec: dict[str, Any] = {
        "r_over_R": float(r) / R, "extra": " ".join(extra), "N": N, "snap_kind": sp.kind, "snap_label": sp.label,
        "w_b_c_over_R": float(sp.p) / R, "Delta_H_over_R": float(obs["Delta_H"]) / R,
        "kappa_p_R_at_snap": float(obs["kappa_p_R"]), "w_s_over_R": float(obs["w_s"]) / R,
        "F_norm_at_snap": float(obs["F_norm"]), "n_contact_at_snap": int(obs["n_contact"]),
        "contact_mode": mode, "contact_mode_strict": strict, "max_gap_before_snap_over_R": max_gap / R,
        "dhat": P.dhat, "points": len(br.p), "status": br.status, "time_s": time.perf_counter() - t0}
    if keep_path:
        rec["path"] = {name: np.append(br.observable(name), obs[name]) for name in _PATH_OBS}
        # d/ds along the path where the branch stores them (NaN at the appended snap): the figures draw
        # the path smooth between stored points with them (contin.plot.branches.smooth_path)
        d_F = br.tangent("F_norm")
        rec["path_tangents"] = {
            "s": np.append(br.s, sp.s), "w_b_over_R": np.append(br.tangent_p / R, np.nan),
            "F_norm": np.append(d_F if d_F is not None else np.full(len(br.p), np.nan), np.nan)}
    if keep_shape:
        x = P.full_state(sp.u)
        rec["r"], rec["z"] = x[0::2] / R, x[1::2] / R
    return rec


def _case_job(args: tuple) -> dict[str, Any]:
    r, N, extra, keep_path, keep_shape = args
    return snap_case(r, N, extra, keep_path, keep_shape)


def _map(jobs: list[tuple], executor: Executor | None) -> list[dict[str, Any]]:
    """:func:`snap_case` of every job, in order, on ``executor`` (None: in this process)."""
    if executor is None:
        return [_case_job(j) for j in jobs]
    return executor.map(_case_job, jobs)


def _detached(gap_tol_factor: float) -> Callable[[dict[str, Any]], bool]:
    return lambda rec: rec["Delta_H_over_R"] > gap_tol_factor * rec["dhat"]


def locate_transition(lo: float, hi: float, *, N: int = 200, extra: Sequence[str] = (), tol: float = TOL_FULL,
                      gap_tol_factor: float = GAP_TOL_FACTOR, predicate: Callable[[dict[str, Any]], bool] | None = None,
                      executor: Executor | None = None, workers: int = 1,
                      known: dict[float, dict[str, Any]] | None = None,
                      max_expand: int = 6, r_min: float = 0.02, keep_shape: bool = False) -> dict[str, Any]:
    """Bisection in the sphere radius for the transition of the snap (by default: the pole detaches).

    ``predicate(record)`` is False below the transition and True above it; by default it is
    ``Delta_H_at_snap > gap_tol_factor * dhat``.  The bracket ``[lo, hi]`` is checked first (runs at its
    ends unless ``known`` has them) and widened by its own width, up to ``max_expand`` times, until
    ``predicate`` is False at ``lo`` and True at ``hi``.  Each round then runs ``workers`` radii spaced
    evenly inside the bracket (in parallel on ``executor``) and keeps the sub-bracket where the predicate
    changes, until the bracket is at most ``tol`` wide.  The result depends on ``workers`` (the
    points of each round), not on ``executor``.

    Parameters
    ----------
    lo, hi : float
        Initial bracket in r/R.
    N, extra
        The scene, as for :func:`snap_case`.
    tol : float
        Width of the final bracket in r/R.
    gap_tol_factor : float
        Gap tolerance of the default predicate in units of ``dhat``.
    predicate : callable, optional
        Replaces the default predicate.
    executor : contin.app.executors.Executor, optional
        Where the runs go (default: this process).
    workers : int
        Radii per round.
    known : dict, optional
        Records of :func:`snap_case` already computed, keyed by r/R.
    max_expand : int
        How often the bracket may be widened.
    r_min : float
        Smallest radius tried.
    keep_shape : bool
        Keep the node coordinates at each run's snap in its record.

    Returns
    -------
    dict
        ``r_c`` (the bracket's midpoint), ``lo``, ``hi``, ``tol``, ``gap_tol_over_R`` (None with a custom
        predicate), ``runs`` (number of contact runs made) and ``evaluations`` (every record, sorted by r).
    """
    pred = predicate or _detached(gap_tol_factor)
    seen: dict[float, dict[str, Any]] = dict(known or {})
    runs = 0

    def evaluate(radii: list[float]) -> list[bool]:
        nonlocal runs
        todo = [r for r in radii if r not in seen]
        recs = _map([(r, N, tuple(extra), False, keep_shape) for r in todo], executor)
        runs += len(todo)
        for r, rec in zip(todo, recs):
            seen[r] = rec
        return [pred(seen[r]) for r in radii]

    for _ in range(max_expand + 1):
        below, above = evaluate([lo, hi])
        if not below and above:
            break
        if below and not above:
            raise RuntimeError(f"the transition is not monotone in r/R on [{lo:.4g}, {hi:.4g}]")
        width = hi - lo
        if below:  # already past the transition at lo: look below
            if lo <= r_min:
                raise RuntimeError(f"the transition lies below r/R = {r_min:g}")
            lo, hi = max(lo - width, r_min), lo
        else:  # not yet at hi: look above
            lo, hi = hi, hi + width
    else:
        raise RuntimeError(f"no transition bracketed in r/R = [{lo:.4g}, {hi:.4g}] ({', '.join(extra) or 'default'})")
    k = max(int(workers), 1)
    while hi - lo > tol * (1.0 + 1e-9):
        inner = [lo + (hi - lo) * (j + 1) / (k + 1) for j in range(k)]
        flags = evaluate(inner)
        pts = [lo, *inner, hi]
        vals = [False, *flags, True]
        j = next(i for i in range(1, len(vals)) if vals[i])
        lo, hi = pts[j - 1], pts[j]
    dhat = next(iter(seen.values()))["dhat"]
    return {"r_c": 0.5 * (lo + hi), "lo": lo, "hi": hi, "tol": tol,
            "gap_tol_over_R": None if predicate else gap_tol_factor * dhat, "runs": runs,
            "evaluations": [seen[r] for r in sorted(seen)]}


# ---------------------------------------------------------------------------------------------------
# the study
# ---------------------------------------------------------------------------------------------------
def _spread(values: Sequence[float]) -> float:
    v = np.asarray(values, dtype=float)
    return float((v.max() - v.min()) / abs(v.mean()))


def run(full: bool = False, workers: int = 1, quiet: bool = True, N: int = 200,
        executor: Executor | None = None) -> dict[str, Any]:
    """Run the study (no files written): the cases, the transition, the free snap state, the checks.

    Parameters
    ----------
    full : bool
        20 radii and ``r_c`` to 1e-3 (and the mode boundaries) instead of 8 radii and ``r_c`` to 0.025.
    workers : int
        Processes for the contact runs (1: all in this process), when no ``executor`` is given.
    quiet : bool
        No progress lines on stderr.
    N : int
        Nodes on the meridian.
    executor : contin.app.executors.Executor, optional
        Where the contact runs go (not closed here); the results do not depend on it.

    Returns
    -------
    dict
        ``summary`` (what summary.json holds), ``cases`` (records with paths and shapes), ``free`` (the
        point load's snap state and path), ``bisection`` (every run of the bisections).
    """
    t0 = time.perf_counter()
    radii = RADII_FULL if full else RADII_FAST
    free = free_snap_state(PHI_HAT, H_OVER_R, N, path=True)
    if not free["bistable"]:
        raise RuntimeError("the default cap is not bistable?")
    own = executor is None
    ex = make_executor(workers) if executor is None else executor
    per_round = PER_ROUND_FULL if full else PER_ROUND_FAST
    try:
        say(quiet, f"indenter_size: {len(radii)} radii to the snap (N = {N}, {ex.where(len(radii))})")
        # largest radii (the slowest) first, so that the workers end evenly
        jobs = [(r, N, (), True, True) for r in sorted(radii, reverse=True)]
        cases = sorted(_map(jobs, ex), key=lambda d: d["r_over_R"])
        by_r = {d["r_over_R"]: d for d in cases}
        dhat = cases[0]["dhat"]
        detached = _detached(GAP_TOL_FACTOR)
        flags = [detached(d) for d in cases]
        if not any(flags) or all(flags) or flags != sorted(flags):
            raise RuntimeError(f"the pole gap at the snap does not open once along the radii: {flags}")
        i = flags.index(True)
        lo, hi = cases[i - 1]["r_over_R"], cases[i]["r_over_R"]
        say(quiet, f"indenter_size: bisection for r_c in [{lo}, {hi}] to {TOL_FULL if full else TOL_FAST}")
        rc = locate_transition(lo, hi, N=N, tol=TOL_FULL if full else TOL_FAST, executor=ex, workers=per_round,
                               known=dict(by_r))
        boundaries: dict[str, Any] = {}
        if full:
            # the runner's "detach": the gap at the snap beyond dhat
            known = {d["r_over_R"]: d for d in rc["evaluations"]}
            up = [r for r, d in sorted(known.items()) if d["Delta_H_over_R"] > dhat]
            down = [r for r, d in sorted(known.items()) if d["Delta_H_over_R"] <= dhat]
            say(quiet, "indenter_size: bisection for the detach boundary (gap at the snap > dhat)")
            det = locate_transition(max(down), min(up), N=N, tol=TOL_FULL, gap_tol_factor=1.0, executor=ex,
                                    workers=per_round, known=known)
            boundaries["detach"] = {k: det[k] for k in ("r_c", "lo", "hi", "tol", "gap_tol_over_R", "runs")}
            # continuous -> detach-recontact: the largest gap before the snap passes dhat
            cont = [d["r_over_R"] for d in cases if d["contact_mode"] == "continuous"]
            recon = [d["r_over_R"] for d in cases if d["contact_mode"] == "detach-recontact"]
            if cont and recon:
                say(quiet, "indenter_size: bisection for the continuous -> detach-recontact boundary")
                mb = locate_transition(max(cont), min(recon), N=N, tol=TOL_MODE, executor=ex, workers=per_round,
                                       known=dict(by_r),
                                       predicate=lambda d: d["max_gap_before_snap_over_R"] > d["dhat"])
                boundaries["recontact"] = {k: mb[k] for k in ("r_c", "lo", "hi", "tol", "runs")}
                known.update({d["r_over_R"]: d for d in mb["evaluations"]})
            known.update({d["r_over_R"]: d for d in det["evaluations"]})
            rc["evaluations"] = [known[r] for r in sorted(known)]
    finally:
        if own:
            ex.close()

    # universality and the rigid-sphere prediction on the free snap shape
    rf, zf = free["r"], free["z"]
    curve = barrier_curve(rf, zf)
    for d in cases:
        d["shape_deviation_over_R"] = float(max(np.abs(d["r"] - rf).max(), np.abs(d["z"] - zf).max()))
        rest = resting_sphere(*curve, d["r_over_R"] + dhat)
        d["Delta_H_predicted_over_R"] = rest["gap"]
        d["w_b_c_predicted_over_R"] = free["w_s_over_R"] - rest["gap"]
    # the same prediction of r_c: the smallest r whose resting sphere misses the pole by more than the
    # gap tolerance (the gap is 0 up to the transition and grows after it)
    a, b = 1e-3, 10.0
    for _ in range(60):
        m = 0.5 * (a + b)
        a, b = (a, m) if resting_sphere(*curve, m + dhat)["gap"] > GAP_TOL_FACTOR * dhat else (m, b)
    sim_rc_geo = 0.5 * (a + b)

    small = [d for d in cases if d["r_over_R"] < rc["lo"]]
    large = [d for d in cases if d["r_over_R"] > rc["hi"]]
    modes = {d["r_over_R"]: d["contact_mode"] for d in cases}

    def mode_range(name: str) -> list[float] | None:
        rr = [r for r, m in modes.items() if m == name]
        return [min(rr), max(rr)] if rr else None

    checks = {
        "w_b_c_spread_below_r_c": _spread([d["w_b_c_over_R"] for d in small]) if small else None,
        "w_b_c_strictly_decreasing_above_r_c": all(b["w_b_c_over_R"] < a["w_b_c_over_R"]
                                                   for a, b in zip(large, large[1:])),
        "Delta_H_zero_below_r_c": all(d["Delta_H_over_R"] == 0.0 for d in small),
        "kappa_p_R_spread_all_r": _spread([d["kappa_p_R_at_snap"] for d in cases]),
        "w_s_spread_all_r": _spread([d["w_s_over_R"] for d in cases]),
        "max_shape_deviation_from_free_snap_state_over_R": max(d["shape_deviation_over_R"] for d in cases),
        "max_abs_Delta_H_minus_prediction_over_R": max(abs(d["Delta_H_over_R"] - d["Delta_H_predicted_over_R"])
                                                       for d in cases),
        "max_abs_w_b_c_minus_prediction_over_R": max(abs(d["w_b_c_over_R"] - d["w_b_c_predicted_over_R"])
                                                     for d in cases),
        "r_c_of_the_resting_sphere_prediction": sim_rc_geo,
    }
    keep = ("r_over_R", "w_b_c_over_R", "Delta_H_over_R", "contact_mode", "contact_mode_strict", "kappa_p_R_at_snap",
            "w_s_over_R", "F_norm_at_snap", "snap_label", "n_contact_at_snap", "max_gap_before_snap_over_R",
            "Delta_H_predicted_over_R", "w_b_c_predicted_over_R", "shape_deviation_over_R", "points", "time_s")
    summary: dict[str, Any] = {
        "study": "indenter_size", "paper_figures": [6, 7, 8], "mode": "full" if full else "fast",
        "scene": {"phi_hat": PHI_HAT, "h_over_R": H_OVER_R, "nu": 0.5, "R": 1.0, "E": 1e6, "N": N, "dhat_over_R": dhat,
                  "K_c": "100 E R (default barrier)"},
        "r_c_over_R": rc["r_c"],
        "r_c_bracket": [rc["lo"], rc["hi"]],
        "r_c_definition": (f"smallest r/R whose snap has Delta_H_at_snap > {GAP_TOL_FACTOR:g} dhat "
                           f"(= {GAP_TOL_FACTOR * dhat:.3g} R), bisection to {rc['tol']:g} in r/R"),
        "r_c_gap_tol_over_R": rc["gap_tol_over_R"],
        "r_c_runs": rc["runs"],
        "mode_boundaries": boundaries,
        "modes_by_radius": {"continuous": mode_range("continuous"), "detach-recontact": mode_range("detach-recontact"),
                            "detach": mode_range("detach")},
        "free_snap_state": {"w_s_over_R": free["w_s_over_R"], "kappa_p_R": free["kappa_p_R"], "F_norm": free["F_norm"],
                            "folds_in_w_before": free["folds_in_w_before"],
                            "note": "bilateral point load, first falling F = 0 (w_c_one_sided of the point scene)"},
        "checks": checks,
        "cases": [{k: d[k] for k in keep} for d in cases],
        "wall_time_s": time.perf_counter() - t0,
        "executor": ex.name,
        "workers": ex.workers,
    }
    return {"summary": summary, "cases": cases, "free": free, "bisection": rc["evaluations"]}


# ---------------------------------------------------------------------------------------------------
# figures
# ---------------------------------------------------------------------------------------------------
def _smooth_path_of(d: dict[str, Any], y: str) -> tuple[np.ndarray, np.ndarray]:
    """A case's loading path ``(w_b/R, y)``, each piece between stored points a cubic through both with the
    path's stored direction (:func:`contin.plot.branches.smooth_path`); straight where no tangent is stored."""
    from contin.plot.branches import smooth_path

    p, t = d["path"], d.get("path_tangents")
    if t is None or y not in t:
        return p["w_b_over_R"], p[y]
    return smooth_path(p["w_b_over_R"], p[y], t["w_b_over_R"], t[y], t["s"])


def _fig6(res: dict[str, Any]) -> Any:
    import matplotlib.pyplot as plt

    cases, free, S = res["cases"], res["free"], res["summary"]
    # a page wide (contin.plot.style.WIDTH), the panels one above the other: side by side, each would be too
    # narrow for its colour bar or its second axis (tight_layout: the colour bar takes its room from (a)
    # alone, next to it, where the constrained layout would align it with the second axis of (b))
    fig, (a, b) = plt.subplots(2, 1, figsize=(WIDTH, 7.4))
    r_all = [d["r_over_R"] for d in cases]
    norm = matplotlib.colors.Normalize(min(r_all), max(r_all))
    for d in cases:
        a.plot(*_smooth_path_of(d, "F_norm"), "-", lw=1.0, color=plt.cm.viridis(norm(d["r_over_R"])))
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=a, label="indenter radius $r/R$", pad=0.01)
    fp = free["path"]
    a.plot(fp["w_over_R"][::2], fp["F_norm"][::2], "o", mfc="none", ms=3.5, color="k", label="point load (bilateral)")
    a.axhline(0, color="0.7", lw=0.6)
    a.set_xlabel("$w_b/R$")
    a.set_ylabel("$F R / 2\\pi D$")
    a.set_title("(a) loading paths to the snap")
    # the paths start together at the origin and end on the axis: the top right is the free corner
    a.legend(loc="upper right")
    r = np.array([d["r_over_R"] for d in cases])
    rr = np.linspace(0.05, max(r.max(), 2.0), 400)
    dhat = S["scene"]["dhat_over_R"]
    curve = barrier_curve(free["r"], free["z"])
    pred = np.array([resting_sphere(*curve, x + dhat)["gap"] for x in rr])
    # one run a radius: markers at the runs, thin lines between them only to guide the eye
    b.plot(r, [d["w_b_c_over_R"] for d in cases], "o-", color="C0", ms=5, lw=0.7, zorder=3,
           label="$w_b^c/R$ (contact runs)")
    b.plot(rr, free["w_s_over_R"] - pred, ":", color="C0", lw=1.2,
           label="$w_s^*/R - \\Delta H/R$ (sphere on free snap shape)")
    b.set_xlabel("indenter radius $r/R$")
    b.set_ylabel("$w_b^c/R$", color="C0")
    b2 = b.twinx()
    b2.plot(r, [d["Delta_H_over_R"] for d in cases], "s-", color="C3", ms=4.5, lw=0.7, zorder=3,
            label="$\\Delta H/R$ (contact runs)")
    b2.plot(rr, pred, ":", color="C3", lw=1.2, label="$\\Delta H/R$ (sphere on free snap shape)")
    b2.set_ylabel("$\\Delta H/R$ at the snap", color="C3")
    # r_c is known to its bisection bracket only: the bracket shaded, its midpoint dashed
    lo, hi = S["r_c_bracket"]
    b.axvspan(lo, hi, color="0.88", lw=0, zorder=0)
    b.axvline(S["r_c_over_R"], color="k", ls="--", lw=0.8, label=f"$r_c/R \\in [{lo:.3f}, {hi:.3f}]$ (bisection)")
    h1, l1 = b.get_legend_handles_labels()
    h2, l2 = b2.get_legend_handles_labels()
    b.legend(h1 + h2, l1 + l2, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)
    b.set_title("(b) snap travel and pole gap against the indenter size")
    fig.suptitle(f"Sphere indentation, $\\hat\\phi$ = {PHI_HAT}, $h/R$ = {H_OVER_R}, $N$ = {S['scene']['N']}")
    fig.tight_layout(h_pad=1.2)
    return fig


def _fig7(res: dict[str, Any]) -> Any:
    import matplotlib.pyplot as plt

    cases, free, S = res["cases"], res["free"], res["summary"]
    nearest = lambda rw: min(cases, key=lambda c: abs(c["r_over_R"] - rw))  # noqa: E731
    # no run keeps its shape at r_c itself (the bisection's runs keep none): the first sampled radius past
    # its bracket stands for the transition, and its title says so
    above = [c for c in cases if c["r_over_R"] > S["r_c_bracket"][1]]
    middle = ((min(above, key=lambda c: c["r_over_R"]), ", the first sample above $r_c/R$") if above
              else (nearest(S["r_c_over_R"]), ", the sample nearest $r_c/R$"))
    picks = [(nearest(0.5), ""), middle, (nearest(1.1), "")]
    # a page wide (contin.plot.style.WIDTH): three panels side by side would be too narrow, so a 2 x 2 grid,
    # the legend in the fourth cell
    fig, grid = plt.subplots(2, 2, figsize=(WIDTH, 4.6), sharey=True, layout="constrained",
                             gridspec_kw={"wspace": 0.06})
    axes = grid.ravel()[:3]
    dhat = S["scene"]["dhat_over_R"]
    for ax, (d, what) in zip(axes, picks):
        ax.plot(free["r"], free["z"], "-", color="0.6", lw=3, label="free snap state (point load at $F = 0$)")
        ax.plot(-free["r"], free["z"], "-", color="0.6", lw=3)
        ax.plot(d["r"], d["z"], "-", color="C0", lw=1.2, label="contact run at its snap")
        ax.plot(-d["r"], d["z"], "-", color="C0", lw=1.2)
        rest = resting_sphere(*barrier_curve(free["r"], free["z"]), d["r_over_R"] + dhat)
        t = np.linspace(0, 2 * np.pi, 400)
        rad = d["r_over_R"]
        ax.plot(rad * np.cos(t), rest["centre"] + rad * np.sin(t), "-", color="C3", lw=1.0,
                label="indenter (sphere of radius $r$)")
        ax.set_aspect("equal")
        ax.set_xlim(-1.0, 1.0)
        ax.set_ylim(0.5, 1.65)
        ax.set_title(f"$r/R$ = {rad:g}{what}\n{d['contact_mode']}, $\\Delta H/R$ = {d['Delta_H_over_R']:.3g}",
                     fontsize="small")
        # the section's horizontal coordinate: r is the indenter's radius here
        ax.set_xlabel("$x/R$")
    for ax in grid[:, 0]:
        ax.set_ylabel("$z/R$")
    # in the fourth cell (every corner of the panels holds a shape or the indenter)
    grid[1, 1].axis("off")
    grid[1, 1].legend(*axes[0].get_legend_handles_labels(), loc="center", frameon=False)
    return fig


def _fig8(res: dict[str, Any]) -> Any:
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    cases, free = res["cases"], res["free"]
    sel = [d for d in cases if any(abs(d["r_over_R"] - r) < 1e-9 for r in FIG8_RADII)]
    # a page wide (contin.plot.style.WIDTH): each row shares its y axis (the same quantity and range), so the
    # panels keep their width, and the legends go under the panels, where they hide no curve
    fig, axes = plt.subplots(2, 2, figsize=(WIDTH, 6.6), sharex="col", sharey="row", layout="constrained")
    fp = free["path"]
    n = len(sel)
    for k, d in enumerate(sel):
        p = d["path"]
        c = plt.cm.plasma(k / max(n, 1))
        lab = f"$r/R$ = {d['r_over_R']:g} ({d['contact_mode']})"
        axes[0, 0].plot(p["w_b_over_R"], p["kappa_p_R"], "-", color=c, label=lab)
        axes[0, 1].plot(p["w_s_over_R"], p["kappa_p_R"], "-", color=c, label=lab)
        axes[1, 0].plot(p["w_b_over_R"], p["Delta_H_over_R"], "-", color=c, label=lab)
        axes[1, 1].plot(p["w_s_over_R"], p["Delta_H_over_R"], "-", color=c, label=lab)
        # the snaps coincide (the universal snap state): rings shrinking from the first radius to the
        # last nest there instead of covering each other
        for ax, x in ((axes[0, 0], "w_b_over_R"), (axes[0, 1], "w_s_over_R")):
            ax.plot(p[x][-1], p["kappa_p_R"][-1], "o", mfc="none", mec=c, mew=0.9, ms=3.5 + 2.8 * (n - 1 - k),
                    zorder=4 + k)
    kmin = min(float(np.min(d["path"]["kappa_p_R"])) for d in sel)
    kmax = max(float(np.max(d["path"]["kappa_p_R"])) for d in sel)
    for ax in (axes[0, 0], axes[0, 1]):
        ax.plot(fp["w_over_R"], fp["kappa_p_R"], ":", color="k", lw=1,
                label=f"point load (min ${np.min(fp['kappa_p_R']):.3g}$, off scale)")
        ax.set_ylim(kmin - 0.4, kmax + 0.4)
        ax.axhline(free["kappa_p_R"], color="0.6", lw=0.6,
                   label=f"free snap state ($F = 0$): $\\kappa_p R = {free['kappa_p_R']:.3g}$")
    axes[0, 0].set_ylabel("$\\kappa_p R$")
    axes[1, 0].set_ylabel("$\\Delta H/R$")
    for ax in (axes[1, 0], axes[1, 1]):
        dh = res["summary"]["scene"]["dhat_over_R"]
        ax.axhline(dh, color="0.6", lw=0.6, ls="--")
        # right end, above the line: the paths there are flat at 0 or far above it
        ax.annotate("$\\Delta H = \\hat d$", (1.0, dh), xycoords=("axes fraction", "data"), xytext=(-3, 2),
                    textcoords="offset points", ha="right", va="bottom", fontsize="small", color="0.4")
    axes[1, 0].set_xlabel("$w_b/R$ (indenter)")
    axes[1, 1].set_xlabel("$w_s/R$ (pole)")
    axes[0, 0].set_title("(a) pole curvature against indenter travel", fontsize="small")
    axes[0, 1].set_title("(b) pole curvature against pole travel", fontsize="small")
    axes[1, 0].set_title("(c) pole gap against indenter travel", fontsize="small")
    axes[1, 1].set_title("(d) pole gap against pole travel", fontsize="small")
    # under the panels, one legend for the figure: the radii (every panel), then the reference lines and
    # the snap rings (the top row)
    refs = axes[0, 1].get_legend_handles_labels()[0][n:]
    refs.append(Line2D([], [], ls="none", marker="o", mfc="none", mec="0.25", mew=0.9, ms=6,
                       label="snap (rings nest where snaps coincide)"))
    fig.legend(handles=axes[0, 0].get_legend_handles_labels()[0][:n] + refs, loc="outside lower center", ncol=2)
    return fig


def write_outputs(res: dict[str, Any], out: Any) -> None:
    """Write figures 6-8 and the tables of a :func:`run` result to ``out``.

    Tables: ``cases.csv`` (one row a radius), ``paths.csv`` (the traced paths, the free shell at ``r/R = 0``),
    ``bisection.csv`` (the critical-size bisection) and ``summary.json``.
    """
    save_figures(out, res, {"fig6_snap_vs_radius": _fig6, "fig7_snap_configurations": _fig7,
                            "fig8_pole_curvature": _fig8})
    write_csv(out / "cases.csv", res["summary"]["cases"])
    rows = []
    for d in res["cases"]:
        p = d["path"]
        for i in range(len(p["w_b_over_R"])):
            rows.append({"r_over_R": d["r_over_R"], **{k: p[k][i] for k in _PATH_OBS}})
    fp = res["free"]["path"]
    for i in range(len(fp["w_over_R"])):
        rows.append({"r_over_R": 0.0, "w_b_over_R": fp["w_over_R"][i], "w_s_over_R": fp["w_over_R"][i],
                     "F_norm": fp["F_norm"][i], "kappa_p_R": fp["kappa_p_R"][i]})
    write_csv(out / "paths.csv", rows, ["r_over_R", *_PATH_OBS])
    bis_cols = ("r_over_R", "w_b_c_over_R", "Delta_H_over_R", "contact_mode", "max_gap_before_snap_over_R",
                "snap_label", "kappa_p_R_at_snap", "time_s")
    write_csv(out / "bisection.csv", [{k: d[k] for k in bis_cols} for d in res["bisection"]], bis_cols)
    write_json(out / "summary.json", res["summary"])


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m studies.indenter_size [--out DIR] [--full] [--workers K | --scheduler ADDRESS]
    [--quiet]``."""
    ap = study_parser("indenter_size", __doc__.split("\n")[0], executor_options=True,
                      workers_default="1, or 2 with --full")
    args = ap.parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    with executor_from_args(args, default_workers=2 if args.full else 1) as executor:
        res = run(full=args.full, quiet=args.quiet, executor=executor)
    res["summary"]["command"] = "python -m studies.indenter_size " + " ".join(
        argv if argv is not None else sys.argv[1:])
    write_outputs(res, out)
    S = res["summary"]
    rows = [{"r/R": d["r_over_R"], "w_b^c/R": d["w_b_c_over_R"], "Delta_H/R": d["Delta_H_over_R"],
             "pred Delta_H/R": d["Delta_H_predicted_over_R"], "kappa_p R": d["kappa_p_R_at_snap"],
             "w_s/R": d["w_s_over_R"], "mode": d["contact_mode"], "snap": d["snap_label"] or "fold",
             "time [s]": d["time_s"]} for d in S["cases"]]
    print_table(rows, list(rows[0]), digits=6)
    print(f"r_c/R = {S['r_c_over_R']:.5f} (bracket {S['r_c_bracket'][0]:.5f} .. {S['r_c_bracket'][1]:.5f}; "
          f"{S['r_c_definition']})")
    for name, b in S["mode_boundaries"].items():
        print(f"mode boundary {name}: r/R = {b['r_c']:.4f} (bracket {b['lo']:.4f} .. {b['hi']:.4f})")
    c = S["checks"]
    print(f"kappa_p R spread over r: {c['kappa_p_R_spread_all_r']:.2e}; snap shape vs free F = 0 state: "
          f"{c['max_shape_deviation_from_free_snap_state_over_R']:.2e} R; |Delta_H - sphere on free shape|: "
          f"{c['max_abs_Delta_H_minus_prediction_over_R']:.2e} R")
    print(f"wall time {time.perf_counter() - t0:.1f} s; outputs in {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
