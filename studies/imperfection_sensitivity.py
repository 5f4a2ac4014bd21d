"""Imperfection sensitivity of Huang's clamped caps and of the complete sphere under pressure (issue 37, study 5).

Run ``python -m studies.imperfection_sensitivity [--out DIR] [--full]``.  ``docs/three_d.md`` (section 5) states
the numbers and the conclusions; this docstring says what is computed.

(a) **Koiter's b per lambda.**  The clamped caps of :func:`studies.asymmetric.cap_problem` (``R/h = 100``,
``nu = 1/3``, lambda = 6 .. 16, ``p_c = 1``) are traced under pressure to their first bifurcation into ``n``
waves; the point is lifted into the ``D_n`` view with ``K`` harmonics and re-located there
(:func:`contin_models.shell.lift.follow_waves`, a few steps of the branch), and :func:`contin.koiter_coefficients`
gives ``a`` and ``b`` (``p / p_bif = 1 + b xi^2``, ``xi`` the amplitude of the unit 2-norm null vector ``phi`` in the
view's unknowns) and ``b_w = b / m^2`` in the amplitude of the mode's largest ``Z cos n theta`` coefficient over
``h`` (``m`` from :func:`studies.waves_branch.mode_height`; independent of the mesh).  At two lambdas ``b`` is
checked against a short trace of the branch (:func:`studies.waves_branch.koiter_check`) and against a finer mesh.

(b) **Knock-down by the critical mode.**  The same cap with the mode of its first bifurcation as a stress-free
imperfection (:func:`contin_models.shell.imperfection3d.mode_imperfection`: the harmonic block's null vector,
:func:`~contin_models.shell.imperfection3d.branch_mode`, scaled so that its largest normal displacement is
``delta``), in the ``D_n`` view with ``K`` harmonics, is traced under pressure from ``p = 0`` to its first fold:
``p_s`` the largest pressure it carries on that path.  Koiter's law for an unstable-symmetric bifurcation follows
from the reduced equation ``(1 - p / p_bif) xi + b xi^2 xi = alpha xi_bar`` (``xi_bar`` the imperfection's
amplitude along ``phi``): ``1 - p_s / p_bif = 3 (-b)^(1/3) (alpha xi_bar / 2)^(2/3)`` to leading order, the
two-thirds-power law.  ``alpha = G / (C1 p_bif)`` is computed independently of the traced paths:
``G = phi^T df/d(reference)[psi]`` (the imperfection's force on the mode at the branch point, a central difference
of the residual in the reference shape, ``psi`` the imperfection per unit ``xi_bar``) and ``C1`` the rate at which the
critical eigenvalue crosses zero (:class:`contin.KoiterCoefficients`).  The measures: ``delta`` (largest normal
displacement of the imperfection over ``h``, the tables' abscissa), ``xi_bar`` (the unit 2-norm of ``phi``, in which
``b`` and ``alpha`` are computed) and ``xi_bar_w = m xi_bar`` (the largest ``Z cos n theta`` coefficient, with
``b_w``); the law is the same in each once ``b`` and ``alpha`` are expressed in it.  With every representation of
``D_n`` watched (``every_mode``; the default run at two amplitudes, ``--full`` at every one) the imperfect path stops
at the first of its fold and a bifurcation out of ``D_n``; there the branch that breaks the symmetry is followed far
enough to see whether the pressure falls on it (the bifurcation is then the largest pressure on the cap's path).
Convergence: a finer meridian and ``K = 3`` (``--full``: and 4) at lambda = 8.

(c) **The complete sphere with a polar dimple** (the sphere of :mod:`studies.imperfection`: ``R/h = 100``,
``nu = 0.5``, Gaussian dimple of width ``lambda_I``, axisymmetric, :func:`studies.imperfection.dimpled_problem`)
traced under pressure with every harmonic block ``n = 1 .. default_harmonics`` watched, to its first fold:
whether the largest pressure is an axisymmetric fold or comes after a bifurcation into ``n`` waves (the
bifurcations before the fold are listed), and the knock-down ``p_max / p_c`` against ``delta / h``.

Units: ``h = 1``, ``R = R/h``, ``E`` such that ``p_c = 1``.  Writes ``koiter.csv``, ``koiter_check.csv``,
``knockdown.csv``, ``convergence.csv``, ``sphere.csv``, ``summary.json`` and the figure ``imperfection_sensitivity``
(PNG and PDF).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin_models.shell.fourier import AngularBasis  # noqa: E402
from contin_models.shell.imperfection3d import branch_mode, meridian_normals, mode_imperfection  # noqa: E402
from contin_models.shell.lift import WavesBranch, follow_waves  # noqa: E402
from contin_models.shell.problem3d import Shell3D  # noqa: E402
from contin_models.shell.structure import ShellOfRevolution, default_harmonics  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.asymmetric import HUANG_1964, NU, R_OVER_H, cap_problem  # noqa: E402
from studies.imperfection import dimpled_problem, knockdown_row  # noqa: E402
from studies.waves_branch import KOITER_STEP, koiter_check, mode_height  # noqa: E402

LAMBDAS = tuple(float(x) for x in range(6, 17))
#: The caps whose knock-down is traced, and where ``b`` is checked against a trace and a finer mesh.
KNOCKDOWN_LAMBDAS = (8.0, 12.0)
#: Largest normal displacement of the mode imperfection over the thickness.
DELTAS = (1e-4, 1e-3, 1e-2, 3e-2, 0.1, 0.2, 0.3)
FULL_DELTAS = (1e-5, 3e-5, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 2e-2, 3e-2, 5e-2, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5)
#: The sphere: dimple widths and depths over the thickness.
SPHERE_WIDTHS, FULL_SPHERE_WIDTHS = (2.0,), (1.0, 2.0, 3.0, 4.0)
SPHERE_DELTAS = (0.1, 0.5, 2.0)
FULL_SPHERE_DELTAS = (0.01, 0.05, 0.1, 0.2, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0)
#: The depths of the axisymmetric curve drawn beside them (:func:`studies.imperfection.knockdown_row`).
SPHERE_CURVE = (0.0, 0.01, 0.05, 0.2, 1.0, 1.5, 3.0, 4.0)
#: The amplitudes (largest normal displacement over h) at which the table gives Koiter's knock-down per lambda.
LAW_DELTAS = (0.01, 0.1)
#: The relative size of the reference's change in the central difference of the imperfection's force.
IMPERFECTION_STEP = 1e-4
#: Steps of the imperfect caps' traces (in the view's unknowns and ``p / p_c``).
TRACE_DS, TRACE_DS_MAX = 0.02, 0.05


# ---- (a) the bifurcation and Koiter's coefficients -------------------------------------------------
def first_bifurcation(lam: float, N: int, r_over_h: float = R_OVER_H) -> tuple[ShellOfRevolution, contin.SpecialPoint]:
    """The cap and the first located bifurcation into waves on its pressure path (an error if a fold comes first)."""
    pr = cap_problem(lam, N, r_over_h, NU)
    path = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(
        ds=0.02, ds_max=0.05, max_steps=4000, stability=True, stop_at=("fold", "bifurcation")), p_max=3.0)
    point = path.special_points[-1] if path.special_points else None
    if point is None or point.kind != "bifurcation" or not point.located:
        raise RuntimeError(f"lambda = {lam:g}, N = {N}: no located bifurcation before the fold ({path.message})")
    return pr, point


def lifted(pr: ShellOfRevolution, point: contin.SpecialPoint, K: int) -> WavesBranch:
    """The branch point re-located in the ``D_n`` view with ``K`` harmonics (and two small steps of its branch)."""
    return follow_waves(pr, point, K, settings=contin.Settings(ds=1e-3, ds_max=1e-3), max_steps=2)


def imperfection_coefficient(wb: WavesBranch, koiter: contin.KoiterCoefficients, psi: np.ndarray) -> float:
    """Koiter's ``alpha`` of the imperfection ``psi`` (a change of the view's reference coefficients per unit
    ``xi_bar``): ``(1 - p / p_bif) xi + b xi^3 = alpha xi_bar``, ``alpha = G / (C1 p_bif)`` with
    ``G = phi^T d f / d(reference)[psi]`` at the branch point (a central difference in the reference shape).

    The states of the view are the rings' coordinates, so the branch point's unknowns describe the same shape
    whatever the reference; only the strains, measured from the reference, change.
    """
    prob, bp = wb.problem, wb.branch_point
    if prob.load != "pressure":
        raise ValueError(f"imperfection_coefficient: the view must be under pressure, got the {prob.load!r} load")
    phi = koiter.null_vector
    c_ref = prob.c_ref
    eps = IMPERFECTION_STEP

    def force(sign: float) -> np.ndarray:
        view = Shell3D(prob.structure, prob.basis, "pressure", "force", p_c=prob.p_c, length=prob.length,
                       reference=c_ref + sign * eps * psi)
        return view.residual(bp.u, bp.p)

    G = float(phi @ (force(1.0) - force(-1.0))) / (2.0 * eps)
    return G / (koiter.C1 * bp.p)


def koiter_row(lam: float, N: int, K: int = 2, r_over_h: float = R_OVER_H) -> dict[str, Any]:
    """Koiter's coefficients at the first bifurcation of the cap ``lam`` and the mode's measures."""
    t0 = time.perf_counter()
    pr, point = first_bifurcation(lam, N, r_over_h)
    wb = lifted(pr, point, K)
    bp = wb.branch_point
    k = contin.koiter_coefficients(wb.problem, bp.u, bp.p, null_vector=bp.bifurcation.null_vector, step=KOITER_STEP)
    m = mode_height(wb, k.null_vector)
    n = int(point.info["key"])
    psi = wb.problem.full_state(k.null_vector, bp.p) - wb.problem.full_state(np.zeros_like(k.null_vector), bp.p)
    alpha = imperfection_coefficient(wb, k, psi)
    # the mode imperfection of unit largest normal displacement along phi, and what of it is not along phi
    view = wb.problem
    shift = view.unknowns(mode_imperfection(view.structure, view.basis, n, branch_mode(
        pr.structure, np.asarray(pr.full_state(point.u, point.p)), n), 1.0)) - view.reference_unknowns()
    xi_per_delta = float(k.null_vector @ shift)
    mismatch = float(np.linalg.norm(shift - xi_per_delta * k.null_vector) / np.linalg.norm(shift))
    pub = HUANG_1964.get(lam) if r_over_h == R_OVER_H else None
    return {"lambda": lam, "N": N, "K": K, "R_over_h": r_over_h, "n": n, "p_bif": float(bp.p),
            "huang_1964": pub[0] if pub else None, "huang_n": pub[1] if pub else None,
            "a": float(k.a), "b": float(k.b), "b_w": float(k.b) / m ** 2, "alpha": alpha, "mode_height": m,
            "C1": float(k.C1), "symmetric": bool(k.symmetric), "xi_per_delta": xi_per_delta, "off_mode": mismatch,
            **{f"koiter_drop_{d:g}": float(koiter_drop(float(k.b), alpha, xi_per_delta * d)) for d in LAW_DELTAS},
            "seconds": time.perf_counter() - t0,
            "_problem": pr, "_point": point, "_waves": wb, "_koiter": k}


def koiter_drop(b: float, alpha: float, xi_bar: np.ndarray | float) -> np.ndarray | float:
    """Koiter's leading-order knock-down ``1 - p_s / p_bif = 3 (-b)^(1/3) (|alpha xi_bar| / 2)^(2/3)`` of an
    unstable-symmetric bifurcation (``b < 0``), in the amplitude measure of ``b``, ``alpha`` and ``xi_bar``."""
    if not b < 0.0:
        raise ValueError(f"koiter_drop: b must be negative (an unstable-symmetric bifurcation), got {b!r}")
    return 3.0 * (-b) ** (1.0 / 3.0) * (np.abs(alpha * np.asarray(xi_bar)) / 2.0) ** (2.0 / 3.0)


# ---- (b) the imperfect caps ----------------------------------------------------------------------
def critical_mode(row: dict[str, Any]) -> np.ndarray:
    """The per-node amplitudes of the cap's critical mode (the harmonic block's null vector at its bifurcation)."""
    pr, point = row["_problem"], row["_point"]
    return branch_mode(pr.structure, np.asarray(pr.full_state(point.u, point.p)), row["n"])


def imperfect_maximum(row: dict[str, Any], mode: np.ndarray, delta: float, K: int,
                      every_mode: bool = False) -> dict[str, Any]:
    """The largest pressure on the path of the cap of ``row`` with ``mode`` as imperfection (largest normal
    displacement ``delta`` h), traced in the ``D_n`` view with ``K`` harmonics under pressure from ``p = 0``.

    Without ``every_mode`` it is the path's first fold.  With ``every_mode`` the path is watched against every
    representation of ``D_n`` and stops at the first of a fold and a bifurcation out of ``D_n``; at such a
    bifurcation the branch that breaks the symmetry is followed
    (:func:`contin_models.shell.lift.follow_symmetry_breaking`, both sides for a two-dimensional representation):
    where the pressure falls along it the bifurcation is the maximum, else the broken branch's first fold.
    """
    from contin_models.shell.lift import follow_symmetry_breaking

    t0 = time.perf_counter()
    st, n = row["_problem"].structure, row["n"]
    basis = AngularBasis(n, K)
    c_bar = mode_imperfection(st, basis, n, mode, delta)
    prob = Shell3D(st, basis, "pressure", "force", p_c=1.0, length=row["R_over_h"], reference=c_bar,
                   every_mode=every_mode)
    perfect = Shell3D(st, basis, "pressure", "force", p_c=1.0, length=row["R_over_h"])
    # the amplitude along the bifurcation's null vector, when the view is the one it was computed in
    xi_bar = None
    if K == row["K"] and st.N == row["N"]:
        xi_bar = float(row["_koiter"].null_vector @ (prob.reference_unknowns() - perfect.reference_unknowns()))
    stops = ("fold", "bifurcation") if every_mode else ("fold",)
    br = contin.continuation(prob, prob.reference_unknowns(), 0.0, contin.Settings(
        ds=TRACE_DS, ds_max=TRACE_DS_MAX, max_steps=4000, stability=every_mode, stop_at=stops), p_max=3.0)
    last = br.special_points[-1] if br.special_points else None
    if last is None or last.kind not in stops or not last.located:
        raise RuntimeError(f"lambda = {row['lambda']:g}, delta/h = {delta:g}: no located {' or '.join(stops)} "
                           f"({br.message})")
    p_max, left_into = float(last.p), None
    kind = "fold, every representation watched before it" if every_mode else "fold (other representations not watched)"
    if last.kind == "bifurcation":
        left_into = str(last.info["key"])
        sides = (1, -1) if left_into.startswith("E") else (1,)
        falls, ends = True, []
        for side in sides:
            # a few steps say whether the pressure falls; only a rising branch is followed to its fold
            for steps in (3, 400):
                broken = follow_symmetry_breaking(prob, last, direction=side, settings=contin.Settings(
                    ds=0.01, ds_max=TRACE_DS_MAX, stability=True, stop_at=("fold", "bifurcation")),
                    max_steps=steps, p_max=3.0).branch
                if float(broken.p[1]) < float(last.p):
                    break
            falls = falls and float(broken.p[1]) < float(last.p)
            ends += [s for s in broken.special_points[1:] if s.kind in ("fold", "bifurcation") and s.located][:1]
        if falls:
            kind = f"bifurcation into {left_into}, the pressure falls on its branch"
        elif ends:
            # the broken branch's own next bifurcation is not followed; of two sides, the weaker
            top = min(ends, key=lambda s: float(s.p))
            p_max = float(top.p)
            kind = (f"fold of the {left_into} branch" if top.kind == "fold"
                    else f"bifurcation ({top.info.get('key')}) on the {left_into} branch, not followed")
        else:
            raise RuntimeError(f"lambda = {row['lambda']:g}, delta/h = {delta:g}: the {left_into} branch rises "
                               "with no located fold or bifurcation")
    out = {"lambda": row["lambda"], "N": st.N, "K": K, "n": n, "delta_over_h": delta, "xi_bar": xi_bar,
           "xi_bar_w": None if xi_bar is None else abs(xi_bar) * row["mode_height"],
           "p_max": p_max, "ratio": p_max / row["p_bif"], "drop": 1.0 - p_max / row["p_bif"],
           "maximum": kind, "left_into": left_into,
           # past a large enough amplitude the D_n path has no fold below the bifurcation: its first fold is another
           "below_bifurcation": bool(p_max < row["p_bif"]),
           "w_at_max": float(prob.observables["w_over_h"](last.u, last.p)),
           "seconds": time.perf_counter() - t0}
    if xi_bar is not None and out["below_bifurcation"]:
        out["koiter_drop"] = float(koiter_drop(row["b"], row["alpha"], xi_bar))
        out["drop_over_koiter"] = out["drop"] / out["koiter_drop"]
    return out


def local_exponents(rows: Sequence[dict[str, Any]]) -> None:
    """The local exponent ``d ln(drop) / d ln(delta)`` between successive rows of one cap (into each row)."""
    for a, b in zip(rows, rows[1:]):
        if a["below_bifurcation"] and b["below_bifurcation"]:
            b["exponent"] = math.log(b["drop"] / a["drop"]) / math.log(b["delta_over_h"] / a["delta_over_h"])


# ---- (c) the complete sphere with a polar dimple ----------------------------------------------------
def sphere_row(N: int, delta: float, width: float) -> dict[str, Any]:
    """The dimpled sphere traced with every harmonic block watched to its first fold: the fold's pressure and the
    bifurcations (into ``n`` waves, or axisymmetric branch points) met before it."""
    t0 = time.perf_counter()
    st = dimpled_problem("sphere", N, delta, width).structure
    pr = ShellOfRevolution(st, "pressure", p_c=1.0, length=float(R_OVER_H), harmonics=default_harmonics(st))
    # steps as the axisymmetric study's near the perfect sphere's clustered singular points
    ds = 0.002 if delta < 0.05 else 0.01
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(
        ds=ds, ds_max=ds, max_steps=4000, stability=True, stop_at=("fold",)), p_max=1.5)
    folds = [s for s in br.special_points if s.kind == "fold" and s.located]
    if not folds:
        raise RuntimeError(f"sphere, delta/h = {delta:g}, lambda_I = {width:g}: no located fold ({br.message})")
    fold = folds[0]
    before = [s for s in br.special_points if s.kind in ("bifurcation", "branch_point") and s.index <= fold.index]
    first = before[0] if before else None
    return {"N": N, "lambda_I": width, "delta_over_h": delta, "harmonics": pr.harmonics, "p_fold": float(fold.p),
            "first_bifurcation": None if first is None else float(first.p),
            "first_kind": None if first is None else (f"n = {first.info['key']}" if first.kind == "bifurcation"
                                                      else "axisymmetric branch point"),
            "bifurcations_before_fold": len(before),
            "maximum": "bifurcation first" if first is not None and first.p < fold.p else "axisymmetric fold",
            "seconds": time.perf_counter() - t0}


# ---- the figure ------------------------------------------------------------------------------------
def plot(koiter: Sequence[dict[str, Any]], knock: Sequence[dict[str, Any]], sphere: Sequence[dict[str, Any]],
         axisymmetric_sphere: Sequence[dict[str, Any]]) -> Any:
    """Three panels: ``b_w`` against lambda; the caps' knock-down against ``delta`` with Koiter's law; the dimpled
    sphere's knock-down against ``delta / h``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.style import COLORS, WIDTH

    fig, axes = plt.subplots(1, 3, figsize=(WIDTH * 2.0, 3.6), layout="constrained")
    ax = axes[0]
    main = [r for r in koiter if r["N"] == koiter[0]["N"]]
    lam = [r["lambda"] for r in main]
    ax.plot(lam, [r["b_w"] for r in main], "o-", color=COLORS[0], ms=4, label=r"$b_w$ (left)")
    twin = ax.twinx()
    twin.plot(lam, [r["b"] for r in main], "s--", color="0.45", ms=3, lw=0.8)
    twin.set_ylabel(f"$b$ (unit 2-norm of the unknowns, $N = {main[0]['N']}$)", color="0.35")
    ax.plot([], [], "s--", color="0.45", ms=3, lw=0.8, label=r"$b$ (right; depends on $N$)")
    ax.legend(fontsize="x-small", loc="lower left")
    for r in main:
        ax.annotate(f"{r['n']}", (r["lambda"], r["b_w"]), textcoords="offset points", xytext=(0, 6), ha="center",
                    fontsize="x-small")
    ax.set_xlabel(r"$\lambda$")
    ax.set_ylabel(r"Koiter's $b_w$ (mode's largest $Z\cos n\theta$ / $h$)")
    ax.set_title(f"clamped caps, $R/h = {R_OVER_H:g}$, $\\nu = 1/3$ (labels: $n$)", fontsize="small")
    ax.margins(y=0.12)
    ax = axes[1]
    for j, lam_k in enumerate(sorted({r["lambda"] for r in knock})):
        rows = sorted((r for r in knock if r["lambda"] == lam_k and r["N"] == knock[0]["N"]
                       and r["K"] == knock[0]["K"] and r["below_bifurcation"]), key=lambda r: r["delta_over_h"])
        if not rows:
            continue
        d = np.array([r["delta_over_h"] for r in rows])
        color = COLORS[(j + 1) % len(COLORS)]
        kr = next(r for r in koiter if r["lambda"] == lam_k and r["N"] == rows[0]["N"])
        ax.plot(d, [r["drop"] for r in rows], "o", color=color, ms=4, mfc="white",
                label=f"$\\lambda = {lam_k:g}$ ($n = {kr['n']}$), traced")
        out_of = [r for r in rows if r["left_into"] is not None]
        ax.plot([r["delta_over_h"] for r in out_of], [r["drop"] for r in out_of], "o", color=color, ms=4,
                label=f"$\\lambda = {lam_k:g}$: maximum where it leaves $D_{{{kr['n']}}}$" if out_of else None)
        per_delta = float(np.mean([abs(r["xi_bar"]) / r["delta_over_h"] for r in rows]))
        dd = np.geomspace(d.min(), d.max(), 100)
        ax.plot(dd, koiter_drop(kr["b"], kr["alpha"], per_delta * dd), "-", color=color, lw=1.0,
                label=f"$\\lambda = {lam_k:g}$, Koiter: $3(-b)^{{1/3}}(\\alpha\\bar\\xi/2)^{{2/3}}$")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"mode imperfection $\delta / h$ (largest normal displacement)")
    ax.set_ylabel(r"knock-down $1 - p_{\max} / p_{bif}$")
    ax.set_title(f"caps with their critical mode ($D_n$ view, $N = {knock[0]['N']}$, $K = {knock[0]['K']}$)",
                 fontsize="small")
    ax.legend(fontsize="x-small", loc="upper left")
    ax = axes[2]
    for j, w in enumerate(sorted({r["lambda_I"] for r in axisymmetric_sphere})):
        rows = sorted((r for r in axisymmetric_sphere if r["lambda_I"] == w), key=lambda r: r["delta_over_h"])
        pts = [r for r in sphere if r["lambda_I"] == w and r["N"] == sphere[0]["N"]]
        ax.plot([r["delta_over_h"] for r in rows], [r["kappa"] for r in rows], "-", color=COLORS[j % len(COLORS)],
                lw=1.0)
        ax.plot([r["delta_over_h"] for r in pts], [r["p_fold"] for r in pts], "o", color=COLORS[j % len(COLORS)],
                ms=4, mfc="white")
        ax.plot([], [], "-o", color=COLORS[j % len(COLORS)], ms=4, mfc="white", lw=1.0,
                label=f"$\\lambda_I = {w:g}$")
    ax.set_xlabel(r"dimple depth $\delta / h$")
    ax.set_ylabel(r"$p_{\max} / p_c$")
    ax.set_ylim(0.0, 1.05)
    ax.set_title(r"complete sphere, polar dimple, $R/h = 100$, $\nu = 0.5$" "\n"
                 "lines: axisymmetric model; circles: every harmonic watched", fontsize="small")
    ax.legend(fontsize="x-small", loc="upper right")
    return fig


# ---- the command line --------------------------------------------------------------------------------
def _public(row: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in row.items() if not k.startswith("_")}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("imperfection_sensitivity", "Koiter's b of Huang's caps, their knock-down by the critical "
                          "mode, the dimpled sphere")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    N, K = (200, 2) if args.full else (100, 2)
    deltas = FULL_DELTAS if args.full else DELTAS
    widths = FULL_SPHERE_WIDTHS if args.full else SPHERE_WIDTHS
    sphere_deltas = FULL_SPHERE_DELTAS if args.full else SPHERE_DELTAS
    # (a)
    koiter = []
    for lam in LAMBDAS:
        say(args.quiet, f"Koiter's b, lambda = {lam:g}, N = {N} ...")
        koiter.append(koiter_row(lam, N, K))
    mesh = [koiter_row(lam, 2 * N, K) for lam in KNOCKDOWN_LAMBDAS]
    checks = []
    for lam in KNOCKDOWN_LAMBDAS:
        say(args.quiet, f"b against a short trace, lambda = {lam:g} ...")
        row = next(r for r in koiter if r["lambda"] == lam)
        checks.append({"lambda": lam, "N": N, "K": K, **koiter_check(row["_waves"], ds=2e-3, window=5e-3)})
    # (b)
    knock, conv = [], []
    for lam in KNOCKDOWN_LAMBDAS:
        row = next(r for r in koiter if r["lambda"] == lam)
        mode = critical_mode(row)
        say(args.quiet, f"imperfect caps, lambda = {lam:g}, n = {row['n']} ...")
        watched = deltas if args.full else (0.1, deltas[-1])
        rows = [imperfect_maximum(row, mode, d, K, every_mode=d in watched) for d in deltas]
        local_exponents(rows)
        knock.extend(rows)
    lam0 = KNOCKDOWN_LAMBDAS[0]
    row0 = next(r for r in koiter if r["lambda"] == lam0)
    fine = next(r for r in mesh if r["lambda"] == lam0)
    conv_deltas = (1e-3, 1e-2, 0.1, 0.2) if args.full else (1e-2, 0.1)
    say(args.quiet, f"convergence in N and K, lambda = {lam0:g} ...")
    for d in conv_deltas:
        base = next(r for r in knock if r["lambda"] == lam0 and r["delta_over_h"] == d)
        # watched alike: where a bifurcation out of D_n comes first, an unwatched trace finds the later fold
        watch = base["left_into"] is not None or base["maximum"].startswith("fold, every")
        variants = [("N", imperfect_maximum(fine, critical_mode(fine), d, K, every_mode=watch))]
        variants += [("K", imperfect_maximum(row0, critical_mode(row0), d, k, every_mode=watch))
                     for k in ((3, 4) if args.full else (3,))]
        for what, v in variants:
            conv.append({"lambda": lam0, "delta_over_h": d, "changed": what, "N": v["N"], "K": v["K"],
                         "maximum": v["maximum"], "base_maximum": base["maximum"],
                         "ratio": v["ratio"], "base_ratio": base["ratio"], "change": v["ratio"] - base["ratio"]})
    # (c)
    sphere, axisym = [], []
    for w in widths:
        say(args.quiet, f"dimpled sphere, lambda_I = {w:g}, every harmonic watched ...")
        sphere.extend(sphere_row(499, d, w) for d in sphere_deltas)
        axisym.extend({"lambda_I": w, "delta_over_h": d,
                       "kappa": knockdown_row("sphere", 499, d, w, locate_mode=False)["kappa"]}
                      for d in sorted(set(sphere_deltas) | set(SPHERE_CURVE)))
    if args.full:  # a finer meridian for the check of the harmonics
        say(args.quiet, "dimpled sphere, lambda_I = 2, N = 997 ...")
        sphere.extend(sphere_row(997, d, 2.0) for d in (0.1, 2.0))
    elapsed = time.perf_counter() - t0
    write_csv(out / "koiter.csv", [_public(r) for r in koiter + mesh])
    write_csv(out / "koiter_check.csv", checks)
    write_csv(out / "knockdown.csv", knock)
    write_csv(out / "convergence.csv", conv)
    write_csv(out / "sphere.csv", sphere)
    write_json(out / "summary.json", {"full": bool(args.full), "seconds": elapsed, "nu": NU, "R_over_h": R_OVER_H,
                                      "koiter": [_public(r) for r in koiter + mesh], "koiter_check": checks,
                                      "knockdown": knock, "convergence": conv, "sphere": sphere,
                                      "sphere_axisymmetric": axisym})
    save_figure(plot(koiter, knock, sphere, axisym), out, "imperfection_sensitivity")
    if not args.quiet:
        print_table([_public(r) for r in koiter + mesh], ["lambda", "N", "K", "n", "p_bif", "huang_1964", "huang_n",
                                                          "a", "b", "b_w", "alpha", "mode_height", "xi_per_delta",
                                                          "off_mode", "koiter_drop_0.01", "koiter_drop_0.1"], digits=6)
        print()
        print_table(checks, ["lambda", "N", "K", "p_c", "b_koiter", "b_traced", "rel_diff", "b_w_koiter",
                             "b_w_traced", "points"], digits=6)
        print()
        print_table(knock, ["lambda", "N", "K", "n", "delta_over_h", "xi_bar_w", "ratio", "drop", "koiter_drop",
                            "drop_over_koiter", "exponent", "maximum", "seconds"], digits=6)
        print()
        print_table(conv, ["lambda", "delta_over_h", "changed", "N", "K", "ratio", "base_ratio", "change", "maximum"],
                    digits=6)
        print()
        print_table(sphere, ["lambda_I", "delta_over_h", "N", "harmonics", "p_fold", "first_bifurcation",
                             "first_kind", "bifurcations_before_fold", "maximum", "seconds"], digits=6)
        print(f"\n{elapsed:.1f} s; written to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
