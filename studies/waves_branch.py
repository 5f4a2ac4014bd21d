"""The n-wave branches of clamped shallow caps, from their bifurcation on the axisymmetric path (issue 36).

Run ``python -m studies.waves_branch [--out DIR] [--full]``.  ``docs/asymmetric.md`` (last section) states
the numbers and the conclusions; this docstring says what is computed.

(a) **Apex point load.**  A clamped shallow spherical cap (``nu = 0.3``, ``R/t = 1000``; ``--full`` also
``R/t = 10^4`` at lambda = 12), ``lambda = 2 (3 (1 - nu^2))^(1/4) sqrt(H/t)`` with the exact rise (the cap of
:func:`studies.classical.clamped_cap`: ``t = 1``, ``R = R/t``), loaded by a point force at the apex under
displacement control (the apex deflection ``w`` prescribed), is traced from the unloaded state with the
harmonic blocks ``n = 1 .. default_harmonics`` watched.  From its first bifurcation (into ``n`` waves) the
``n``-wave branch is followed in the 3-D view restricted to ``D_n``
(:func:`contin_models.shell.lift.follow_waves`, ``K`` harmonics: waves ``0, n, ..., K n``) under the same
control, counted against every representation of ``D_n`` (``every_mode``), to ``w/t = W_END`` or until it
returns to the axisymmetric path.  The load is reported as ``P R / (E t^3)`` (shallow-shell theory's
load parameter: the linear stiffness of the shallow sphere is ``4 / sqrt(3 (1 - nu^2))`` in it) against
``w/t``, on both branches, at ``w/t = 20, 25, 30, 35`` (linear interpolation between the stored points,
on the first pass of the branch through that deflection), with the Morse index per representation.

(b) **Koiter's b** at each bifurcation: :func:`contin.koiter_coefficients` on the ``D_n`` view at the
re-located branch point, against the coefficient read off a short trace of the branch with small steps:
``(p / p_c - 1) / xi^2`` fitted linearly in ``xi^2``, its intercept.  ``xi = phi^T u``: the amplitude of
the unit (2-norm) null vector ``phi`` in the view's unknowns (the Fourier coefficients of the rings, in
units of the thickness); ``phi`` carries the wave ``n`` alone and the axisymmetric path none, so
``phi^T u_0(p) = 0``.  ``p`` is the control: the apex deflection under the point load, the pressure below.
The unit 2-norm spreads the mode over every unknown, so this ``b`` depends on the mesh; ``b_w`` is the same
coefficient in the amplitude ``xi_w`` of the mode's largest axial wave ``Z cos n theta`` (over the thickness):
``p / p_c = 1 + b_w xi_w^2`` (:func:`mode_height`).

(c) **Huang's clamped cap under pressure** (lambda = 8, ``nu = 1/3``, ``R/h = 100``; ``--full`` also 1000;
:func:`studies.asymmetric.cap_problem`): the first bifurcation (``n = 4``) and the branch followed under
pressure control to ``P_RETURN`` times its pressure (through the fold of the pressure), its ``b`` and its
stability.

The rotation of the wave pattern about the axis
-----------------------------------------------
Turning an ``n``-wave state about the axis costs no energy: a zero eigenvalue of the ``A2`` block up to the
quadrature, whose sign is noise.  :class:`~contin_models.shell.problem3d.Shell3D` leaves it out of its ``A2`` block
(the view's counts are those of the circle of turned states, ``docs/model.md``, "The turning of a wavy state"), and
the tables and the figure use the engine's counts as they are.

Units: ``t = 1``, ``R = R/t``, ``E`` such that the classical buckling pressure ``p_c = 1``.

Writes ``axisymmetric.csv`` and ``waves.csv`` (the paths), ``table.csv`` (the loads at the four
deflections), ``convergence.csv``, ``koiter.csv``, ``pressure.csv``, ``summary.json`` and the figure
``waves_branch`` (PNG and PDF).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin_models.shell.lift import WavesBranch, follow_waves  # noqa: E402
from contin_models.shell.structure import ShellOfRevolution, default_harmonics  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.asymmetric import cap_problem  # noqa: E402
from studies.classical import clamped_cap  # noqa: E402

NU = 0.3
R_OVER_T = 1000.0
LAMBDAS = (10.0, 12.0)
#: The traces stop at this apex deflection over the thickness (beyond the axisymmetric limit point).
W_END = 40.0
#: The deflections of the tables.
W_TABLE = (20.0, 25.0, 30.0, 35.0)
#: Huang's cap under pressure: lambda, nu, R/h; the branch is followed until the pressure is this times
#: the bifurcation's again (after its fold).
HUANG_LAMBDA, HUANG_NU, HUANG_DEPTHS = 8.0, 1.0 / 3.0, (100.0, 1000.0)
P_RETURN = 1.05
#: The difference step of Koiter's coefficients.  The view's unknowns are the rings' coordinates, whose
#: largest entry is the cap's size (``R`` = 1000 t), and the default step moves it by 1e-2 of that: 10 t
#: along the mode, where the branch bends on the scale of t.
KOITER_STEP = 1e-3


def _branch_settings(ds_max: float) -> contin.Settings:
    return contin.Settings(ds=0.02, ds_max=ds_max, max_steps=4000, stability=True)


# ---- the caps ----------------------------------------------------------------------------------
def point_cap(lam: float, N: int, r_over_t: float = R_OVER_T, nu: float = NU) -> ShellOfRevolution:
    """The clamped cap of :func:`studies.classical.clamped_cap` under an apex point load, its deflection
    prescribed, watching the harmonic blocks ``1 .. default_harmonics``."""
    st = clamped_cap(lam, N, r_over_t, nu=nu).structure
    return ShellOfRevolution(st, "point", "displacement", harmonics=default_harmonics(st))


def load_scale(problem: Any) -> float:
    """``R / (E t^3)``: the factor from the force ``F`` to the load parameter ``P R / (E t^3)`` (``t = 1``)."""
    st = problem.structure
    return float(st.meridian.R) / float(st.E)


def axisymmetric_path(problem: ShellOfRevolution, w_end: float = W_END) -> contin.Branch:
    """The displacement-controlled path from the unloaded cap to ``w/t = w_end``, every bifurcation located."""
    br = contin.continuation(problem, problem.reference_unknowns(), 0.0, contin.Settings(
        ds=0.05, ds_max=0.25, max_steps=4000, stability=True), p_max=w_end)
    if br.status != "bound":
        raise RuntimeError(f"axisymmetric path: {br.message}")
    return br


def first_bifurcation(branch: contin.Branch) -> contin.SpecialPoint:
    """The first located bifurcation into waves on a traced path."""
    for spt in branch.special_points:
        if spt.kind == "bifurcation" and spt.info.get("family") == "n" and spt.located:
            return spt
    raise RuntimeError("no located bifurcation into waves on the path")


def n_wave_branch(problem: Any, point: contin.SpecialPoint, K: int, p_max: float, ds_max: float = 0.25,
                  max_steps: int = 4000, strict: bool = True) -> WavesBranch:
    """The ``n``-wave branch from ``point`` in the ``D_n`` view with ``K`` harmonics, counted against every
    representation, to ``p_max`` or to the axisymmetric path (the branch point where it meets it again).  A trace
    that fails raises unless ``strict`` is False: then it is returned as far as it went (``branch.success`` False,
    ``branch.message`` says where and why)."""
    # stop where it meets the axisymmetric path again: beyond, it retraces its image turned by pi / n
    wb = follow_waves(problem, point, K, every_mode=True, settings=_branch_settings(ds_max), p_max=p_max,
                      max_steps=max_steps, stop_at=("branch_point",))
    if strict and not wb.branch.success:
        raise RuntimeError(f"n-wave branch (K = {K}): {wb.branch.message}")
    return wb


# ---- stability per representation ----------------------------------------------------------------
def morse_counts(wb: WavesBranch, i: int, label: str | None = "displacement") -> dict[str, Any]:
    """The negative eigenvalues at stored point ``i`` of the branch per representation of ``D_n`` under the
    stability label ``label`` (None: the primary one; ``A1``: the traced class, the rest of the total) and their
    total over every perturbation (two-dimensional classes twice)."""
    b = wb.branch
    modes = b.meta["modes"]["representation"]
    counts = {k: int(c) for k, c in zip(modes["keys"], modes["n_negative"][i])}
    total = int(b.n_negative_under(label)[i])
    weight = {k: 2 if k.startswith("E") else 1 for k in counts}
    a1 = total - sum(weight[k] * c for k, c in counts.items())
    return {"A1": a1, **counts, "total": total}


def physical_stability(wb: WavesBranch, label: str = "displacement") -> np.ndarray:
    """Stable (True) at each stored point against every perturbation."""
    return np.array([morse_counts(wb, i, label)["total"] == 0 for i in range(len(wb.branch.p))])


# ---- reading the branches ------------------------------------------------------------------------
def first_pass(w: np.ndarray, y: np.ndarray, target: float) -> tuple[float, int] | None:
    """``y`` at ``w = target`` on the first segment of the path that crosses it (linear between the two
    stored points), and the index of the segment's first point; None where the path does not reach it."""
    for i in range(len(w) - 1):
        a, b = w[i] - target, w[i + 1] - target
        if a == 0.0:
            return float(y[i]), i
        if a * b < 0.0:
            t = a / (a - b)
            return float(y[i] + t * (y[i + 1] - y[i])), i
    return None


def extrema(x: np.ndarray) -> list[int]:
    """Stored points where ``x`` turns (a local maximum or minimum between its neighbours)."""
    d = np.diff(np.asarray(x, dtype=float))
    return [i + 1 for i in range(len(d) - 1) if d[i] * d[i + 1] < 0.0]


def first_half(b: contin.Branch) -> int:
    """The stored points of the branch up to the first branch point it meets after the one it left (all of them
    if none): past it the engine may go on along the image of the same branch, turned by ``pi / n``."""
    met = [s for s in b.special_points[1:] if s.kind == "branch_point"]
    return min(len(b.p), met[0].index + 1) if met else len(b.p)


def wave_amplitude(wb: WavesBranch, u: np.ndarray, p: float) -> float:
    """The largest coefficient of the waves ``n, 2n, ...`` over the rings at the state ``u`` of the view (over the
    thickness): zero on the axisymmetric path only (a branch may also meet a branch of the waves ``2n``, ...)."""
    prob = wb.problem
    c = prob.full_state(u, p)
    return max(float(np.max(np.abs(c[prob.view.dofs_of_wave(int(k))])))
               for k in prob.basis.wave_numbers.tolist() if k > 0)


def loss_of_stability(wb: WavesBranch, w: np.ndarray, stop: int, label: str | None = "displacement"
                      ) -> dict[str, Any] | None:
    """The first stored points of the branch (of the first ``stop``) between which it loses its stability: their
    ``w`` and the representations that gained a negative eigenvalue."""
    before = morse_counts(wb, 0, label)
    for i in range(1, stop):
        now = morse_counts(wb, i, label)
        if now["total"] > 0:
            return {"w_from": float(w[i - 1]), "w_to": float(w[i]),
                    "representations": [k for k in now if k != "total" and now[k] > before[k]]}
        before = now
    return None


def point_load_case(lam: float, N: int, K: int, r_over_t: float = R_OVER_T,
                    w_end: float = W_END) -> dict[str, Any]:
    """One cap under the apex load: the axisymmetric path, its first bifurcation and the ``n``-wave branch."""
    t0 = time.perf_counter()
    pr = point_cap(lam, N, r_over_t)
    path = axisymmetric_path(pr, w_end)
    point = first_bifurcation(path)
    wb = n_wave_branch(pr, point, K, w_end)
    scale = load_scale(pr)
    b = wb.branch
    stop = first_half(b)
    w, P = np.asarray(b.observable("w"))[:stop], np.asarray(b.observable("F"))[:stop] * scale
    w0, P0 = np.asarray(path.observable("w")), np.asarray(path.observable("F")) * scale
    rows = []
    for target in W_TABLE:
        row: dict[str, Any] = {"lambda": lam, "R_over_t": r_over_t, "N": N, "K": K, "w_over_t": target,
                               "P_axisymmetric": float(np.interp(target, w0, P0))}
        hit = first_pass(w, P, target)
        if hit is not None:
            value, i = hit
            before, after = morse_counts(wb, i), morse_counts(wb, i + 1)
            row.update(P_waves=value, ratio=value / row["P_axisymmetric"],
                       **{f"n_{k}": (str(before[k]) if before[k] == after[k] else f"{before[k]}/{after[k]}")
                          for k in before})
        rows.append(row)
    back = return_point(b)
    # the branch meets the path with w turning back: not a fold of the branch
    folds_w = [float(s.p) for s in b.special_points if s.kind == "fold" and s.index < stop - 1
               and (back is None or abs(float(s.p) - back) > 1e-6 * back)]
    largest = max(wave_amplitude(wb, u, q) for u, q in zip(b.u[:stop], b.p[:stop]))
    met = [s for s in b.special_points[1:] if s.kind == "branch_point"]
    turns_P = [(float(w[i]), float(P[i])) for i in extrema(P)]
    axis_turns = [(float(w0[i]), float(P0[i])) for i in extrema(P0)]
    others = [s for s in path.special_points if s.kind == "bifurcation" and s.located]
    return {"lambda": lam, "R_over_t": r_over_t, "N": N, "K": K, "n": int(point.info["key"]),
            "w_bif": float(point.p), "P_bif": float(point.observables["F"]) * scale,
            "moved_w": float(wb.branch_point.info["moved_p"]), "status": b.status, "message": b.message,
            "w_max": float(np.max(w)), "folds_in_w": folds_w, "turns_in_P": turns_P,
            "axisymmetric_turns_in_P": axis_turns,
            "returns_at_w": back, "end_amplitude_over_max": (wave_amplitude(wb, met[0].u, met[0].p) / largest if met else None),
            "loses_stability": loss_of_stability(wb, w, stop), "rows": rows,
            "path_bifurcations": [(int(s.info["key"]), float(s.p)) for s in others],
            "seconds": time.perf_counter() - t0, "_problem": pr, "_path": path, "_waves": wb}


def return_point(b: contin.Branch) -> float | None:
    """Where the branch met a branch point after the one it left (the axisymmetric path again where the wave's
    amplitude vanishes there), or None."""
    met = [float(s.p) for s in b.special_points[1:] if s.kind == "branch_point"]
    return met[0] if met else None


def convergence_rows(cases: Sequence[dict[str, Any]], references: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per case and deflection of the tables, the loads and their changes from a reference of the same lambda and
    ``R/t``: the main case of ``references`` for another ``K``, the case of the main ``N`` and the same ``K`` for
    another ``N`` (None where either branch does not reach the deflection)."""
    out = []
    for case in cases:
        main = next((r for r in references if r["lambda"] == case["lambda"] and r["R_over_t"] == case["R_over_t"]),
                    None)
        if main is None or main is case:
            continue
        # a finer meridian against the main one's at the same K; other K against the main case
        ref = main if case["N"] == main["N"] else next(
            (r for r in cases if r["lambda"] == case["lambda"] and r["R_over_t"] == case["R_over_t"]
             and r["K"] == case["K"] and r["N"] == main["N"]), None)
        if ref is None:
            continue
        for row, base in zip(case["rows"], ref["rows"]):
            entry = {k: row[k] for k in ("lambda", "R_over_t", "N", "K", "w_over_t", "P_axisymmetric")}
            entry["P_waves"] = row.get("P_waves")
            entry["reference"] = f"N = {ref['N']}, K = {ref['K']}"
            entry["change_P_axisymmetric"] = row["P_axisymmetric"] - base["P_axisymmetric"]
            entry["change_P_waves"] = (row["P_waves"] - base["P_waves"]
                                       if row.get("P_waves") is not None and base.get("P_waves") is not None else None)
            out.append(entry)
    return out


# ---- Koiter's b --------------------------------------------------------------------------------
def mode_height(wb: WavesBranch, phi: np.ndarray) -> float:
    """The largest ``Z cos n theta`` coefficient of the view's unit vector ``phi`` over the rings: with it
    ``b_w = b / height^2`` is Koiter's ``b`` in the amplitude ``xi_w`` of the mode's largest axial wave, in units of
    the thickness (independent of the mesh, which the unit 2-norm of the unknowns is not)."""
    prob = wb.problem
    n = prob.basis.n
    direction = prob.full_state(phi, wb.branch_point.p) - prob.full_state(np.zeros_like(phi), wb.branch_point.p)
    waves = direction[prob.view.dofs_of_wave(n)].reshape(-1, 3)
    return float(np.max(np.abs(waves[:, 1])))


def koiter_check(wb: WavesBranch, ds: float, steps: int = 40, window: float = 2e-3) -> dict[str, Any]:
    """Koiter's ``a`` and ``b`` at the re-located branch point against ``b`` read off a short trace.

    The branch is traced again from its point with steps of ``ds``; on its stored points with
    ``0 < |p / p_c - 1| <= window`` the ratio ``(p / p_c - 1) / xi^2``, ``xi = phi^T u``, is fitted by
    ``b + c xi^2`` (module docstring).  The coefficients are differenced with :data:`KOITER_STEP` (``b_koiter``)
    and with :func:`contin.koiter_coefficients`' default step (``b_koiter_default_step``).
    """
    bp = wb.branch_point
    k = contin.koiter_coefficients(wb.problem, bp.u, bp.p, null_vector=bp.bifurcation.null_vector, step=KOITER_STEP)
    coarse = contin.koiter_coefficients(wb.problem, bp.u, bp.p, null_vector=bp.bifurcation.null_vector)
    short = contin.switch_branch(wb.problem, bp, contin.Settings(ds=ds, ds_max=ds), direction=1, max_steps=steps)
    U, p = np.asarray(short.u), np.asarray(short.p)
    xi = U @ k.null_vector
    rel = p / bp.p - 1.0
    use = (np.abs(rel) > 0.0) & (np.abs(rel) <= window) & (np.abs(xi) > 0.0)
    if use.sum() < 4:
        raise RuntimeError(f"koiter_check: {int(use.sum())} points within {window} of p_c; take a smaller ds")
    fit = np.polyfit(xi[use] ** 2, rel[use] / xi[use] ** 2, 1)
    m = mode_height(wb, k.null_vector)
    return {"p_c": float(bp.p), "a": float(k.a), "b_koiter": float(k.b), "b_traced": float(fit[1]),
            "b_koiter_default_step": float(coarse.b), "mode_height": m, "b_w_koiter": float(k.b) / m ** 2,
            "b_w_traced": float(fit[1]) / m ** 2,
            "rel_diff": float(fit[1]) / float(k.b) - 1.0, "points": int(use.sum()),
            "xi_max": float(np.max(np.abs(xi[use]))), "symmetric": bool(k.symmetric)}


# ---- Huang's cap under pressure -------------------------------------------------------------------
def pressure_case(N: int, K: int, r_over_h: float = 100.0) -> dict[str, Any]:
    """Huang's lambda = 8 cap: its first bifurcation, the ``n``-wave branch under pressure through its fold,
    Koiter's ``b`` against the traced branch and the stability along it."""
    t0 = time.perf_counter()
    pr = cap_problem(HUANG_LAMBDA, N, r_over_h, HUANG_NU)
    # traced on to the axisymmetric snap, for the figure
    path = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(
        ds=0.02, ds_max=0.05, max_steps=4000, stability=True, stop_at=("fold",)), p_max=3.0)
    point = next(s for s in path.special_points if s.kind in ("bifurcation", "fold"))
    if point.kind != "bifurcation":
        raise RuntimeError(f"Huang's cap, R/h = {r_over_h}: the first instability is a {point.kind}")
    wb = n_wave_branch(pr, point, K, P_RETURN * float(point.p), ds_max=0.05, max_steps=400)
    b = wb.branch
    p, w = np.asarray(b.p), np.asarray(b.observable("w_over_h"))
    turns = extrema(p)
    counts = [morse_counts(wb, i, None) for i in range(len(p))]
    koiter = koiter_check(wb, ds=2e-3, window=5e-3)
    return {"lambda": HUANG_LAMBDA, "R_over_h": r_over_h, "N": N, "K": K, "n": int(point.info["key"]),
            "p_bif": float(point.p), "w_bif": float(point.observables["w_over_h"]),
            "p_snap": float(path.special_points[-1].p) if path.special_points[-1].kind == "fold" else None,
            "p_min": float(p[turns[0]]) if turns else float(np.min(p)),
            "w_at_p_min": float(w[turns[0]]) if turns else None, "status": b.status,
            "counts": counts, "koiter": koiter, "seconds": time.perf_counter() - t0,
            "_path": path, "_waves": wb}


# ---- the figure --------------------------------------------------------------------------------
@dataclass
class Curve:
    """A path to draw: its abscissae, ordinates and stability at each stored point."""

    x: np.ndarray
    y: np.ndarray
    stable: np.ndarray


def draw_path(ax: Any, c: Curve, color: str, label: str) -> None:
    """A path, solid where stable and dashed where not (each piece includes its end point)."""
    first = True
    start = 0
    for i in range(1, len(c.x) + 1):
        if i == len(c.x) or c.stable[i] != c.stable[start]:
            stop = min(i + 1, len(c.x))
            ax.plot(c.x[start:stop], c.y[start:stop], color=color, lw=1.2,
                    ls="-" if c.stable[start] else "--", label=label if first else None)
            first = False
            start = i


def plot(cases: Sequence[dict[str, Any]], pressure: dict[str, Any] | None) -> Any:
    """``P R / (E t^3)`` against ``w/t``: the axisymmetric paths (grey) and the ``n``-wave branches; a second panel
    for the pressure branch of Huang's cap."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.style import COLORS, WIDTH

    panels = 2 if pressure is not None else 1
    fig, axes = plt.subplots(1, panels, figsize=(WIDTH * (1.6 if panels == 2 else 1.0), 3.8), layout="constrained",
                             squeeze=False)
    ax = axes[0, 0]
    for k, case in enumerate(cases):
        color = COLORS[k % len(COLORS)]
        pr, path, wb = case["_problem"], case["_path"], case["_waves"]
        s = load_scale(pr)
        draw_path(ax, Curve(np.asarray(path.observable("w")), np.asarray(path.observable("F")) * s,
                         np.asarray(path.stable_under("displacement"))), matplotlib.colors.to_hex(
                  0.4 * np.asarray(matplotlib.colors.to_rgb(color)) + 0.6), f"$\\lambda = {case['lambda']:g}$: axisymmetric")
        b = wb.branch
        stop = first_half(b)
        draw_path(ax, Curve(np.asarray(b.observable("w"))[:stop], np.asarray(b.observable("F"))[:stop] * s,
                         physical_stability(wb)[:stop]), color, f"$\\lambda = {case['lambda']:g}$: {case['n']} waves")
        ax.plot([case["w_bif"]], [case["P_bif"]], "o", color=color, mfc="white", ms=5,
                label="bifurcation" if k == 0 else None)
        if case["end_amplitude_over_max"] is not None and case["end_amplitude_over_max"] < 1e-3:
            ax.plot([b.observable("w")[stop - 1]], [b.observable("F")[stop - 1] * s], "o", color=color, ms=4,
                    label="back on the axisymmetric path")
    ax.set_xlabel(r"apex deflection $w/t$")
    ax.set_ylabel(r"apex load $P R / (E t^3)$")
    ax.set_xlim(0, W_END)
    # beyond its inversion (w > 2 H) a cap stretches and the load rises by orders of magnitude: not the subject
    ax.set_ylim(0, 1.3 * max(max(c["P_bif"] for c in cases), max(
        float(np.max(np.asarray(c["_waves"].branch.observable("F")) * load_scale(c["_problem"]))) for c in cases)))
    ax.set_title(f"clamped caps, apex load, $R/t = {cases[0]['R_over_t']:g}$, $\\nu = {NU:g}$ "
                 "(solid stable, dashed unstable)", fontsize="small")
    ax.legend(loc="upper left", fontsize="small")
    if pressure is not None:
        ax = axes[0, 1]
        path, wb = pressure["_path"], pressure["_waves"]
        draw_path(ax, Curve(np.asarray(path.observable("w_over_h")), np.asarray(path.p),
                         np.asarray(path.stable)), "0.55", "axisymmetric")
        b = wb.branch
        stable = np.array([c["total"] == 0 for c in pressure["counts"]])
        draw_path(ax, Curve(np.asarray(b.observable("w_over_h")), np.asarray(b.p), stable), COLORS[2],
              f"{pressure['n']} waves")
        ax.plot([pressure["w_bif"]], [pressure["p_bif"]], "o", color=COLORS[2], mfc="white", ms=5)
        ax.set_xlabel(r"apex deflection $w/h$")
        ax.set_ylabel(r"pressure $p / p_c$")
        ax.set_title(f"Huang's cap under pressure, $\\lambda = {HUANG_LAMBDA:g}$, $R/h = {pressure['R_over_h']:g}$, "
                     "$\\nu = 1/3$",
                     fontsize="small")
        ax.legend(loc="lower right", fontsize="small")
    return fig


# ---- the command line ----------------------------------------------------------------------------
def _public(case: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in case.items() if not k.startswith("_") and k not in ("rows", "counts")}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("waves_branch", "n-wave branches of clamped caps: apex load and pressure, Koiter's b")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    if args.full:
        main_runs = [(lam, 200, 4, R_OVER_T) for lam in LAMBDAS]
        checks = ([(lam, 200, K, R_OVER_T) for lam in LAMBDAS for K in (2, 3)] + [(12.0, 200, 6, R_OVER_T)]
                  + [(lam, 400, 3, R_OVER_T) for lam in LAMBDAS] + [(12.0, 200, 3, 1e4)])
        pressure_runs = [(200, 3, 100.0), (200, 2, 100.0), (400, 2, 100.0), (200, 3, 1000.0)]
    else:
        main_runs, checks, pressure_runs = [(12.0, 120, 2, R_OVER_T)], [], [(100, 2, 100.0)]
    cases = []
    for lam, N, K, rt in main_runs + checks:
        say(args.quiet, f"apex load, lambda = {lam:g}, R/t = {rt:g}, N = {N}, K = {K} ...")
        cases.append(point_load_case(lam, N, K, rt))
    main_cases = cases[:len(main_runs)]
    koiter_rows = []
    for case in main_cases:
        say(args.quiet, f"Koiter's b, lambda = {case['lambda']:g} ...")
        koiter_rows.append({"case": f"apex load, lambda = {case['lambda']:g}", "n": case["n"], "N": case["N"],
                            "K": case["K"], **koiter_check(case["_waves"], ds=0.02)})
    pressures = []
    for N, K, rh in pressure_runs:
        say(args.quiet, f"Huang's cap under pressure, R/h = {rh:g}, N = {N}, K = {K} ...")
        pressures.append(pressure_case(N, K, rh))
    for pc in pressures:
        koiter_rows.append({"case": f"pressure, lambda = 8, R/h = {pc['R_over_h']:g}", "n": pc["n"], "N": pc["N"],
                            "K": pc["K"], **pc["koiter"]})
    elapsed = time.perf_counter() - t0
    table = [r for c in cases for r in c["rows"]]
    convergence = convergence_rows(cases, main_cases)
    write_csv(out / "table.csv", table)
    write_csv(out / "koiter.csv", koiter_rows)
    write_csv(out / "convergence.csv", convergence)
    write_csv(out / "axisymmetric.csv", [
        {"lambda": c["lambda"], "R_over_t": c["R_over_t"], "N": c["N"], "w_over_t": w, "P": P,
         "stable": int(s)}
        for c in main_cases for w, P, s in zip(c["_path"].observable("w"),
                                               np.asarray(c["_path"].observable("F")) * load_scale(c["_problem"]),
                                               c["_path"].stable_under("displacement"))])
    write_csv(out / "waves.csv", [
        {"lambda": c["lambda"], "R_over_t": c["R_over_t"], "N": c["N"], "K": c["K"], "n": c["n"], "w_over_t": w,
         "P": P, **{f"n_{k}": v for k, v in morse_counts(c["_waves"], i).items()}}
        for c in main_cases for i, (w, P) in enumerate(zip(
            c["_waves"].branch.observable("w")[:first_half(c["_waves"].branch)],
            np.asarray(c["_waves"].branch.observable("F")) * load_scale(c["_problem"])))])
    write_csv(out / "pressure.csv", [
        {"R_over_h": pc["R_over_h"], "N": pc["N"], "K": pc["K"], "p_over_p_c": p, "w_over_h": w,
         **{f"n_{k}": v for k, v in cnt.items()}}
        for pc in pressures for p, w, cnt in zip(pc["_waves"].branch.p, pc["_waves"].branch.observable("w_over_h"),
                                                 pc["counts"])])
    write_json(out / "summary.json", {"full": bool(args.full), "seconds": elapsed, "nu": NU,
                                      "load": "P R / (E t^3)", "cases": [_public(c) for c in cases],
                                      "pressure": [_public(p) for p in pressures], "koiter": koiter_rows,
                                      "table": table, "convergence": convergence})
    save_figure(plot(main_cases, pressures[0] if pressures else None), out, "waves_branch")
    if not args.quiet:
        print_table(table, ["lambda", "R_over_t", "N", "K", "w_over_t", "P_axisymmetric", "P_waves", "ratio", "n_A1",
                            "n_A2", "n_E1", "n_B1", "n_B2", "n_total"], digits=5)
        print()
        print_table([_public(c) for c in cases], ["lambda", "R_over_t", "N", "K", "n", "w_bif", "P_bif", "w_max",
                                                  "folds_in_w", "returns_at_w", "end_amplitude_over_max",
                                                  "loses_stability", "status", "seconds"], digits=6)
        print()
        print_table(convergence, ["lambda", "R_over_t", "N", "K", "w_over_t", "P_waves", "change_P_waves",
                                  "P_axisymmetric", "change_P_axisymmetric"], digits=5)
        print()
        print_table(koiter_rows, ["case", "n", "N", "K", "p_c", "a", "b_koiter", "b_traced", "rel_diff",
                                  "b_koiter_default_step", "b_w_koiter", "b_w_traced", "points"], digits=6)
        print()
        print_table([_public(p) for p in pressures], ["R_over_h", "N", "K", "n", "p_bif", "p_min", "w_at_p_min",
                                                       "status", "seconds"], digits=6)
        print(f"\n{elapsed:.1f} s; written to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
