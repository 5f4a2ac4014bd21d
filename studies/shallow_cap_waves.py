"""The n-wave branch of the apex-loaded clamped cap by shallow-shell theory, against the shell model's.

Run ``python -m studies.shallow_cap_waves [--out DIR] [--full]``.  ``docs/asymmetric.md`` (last section) states
the numbers and what they show; this docstring says what is computed.

The model is :class:`contin_models.benchmarks.shallow_cap.ShallowCap`: the Marguerre / Donnell-Mushtari-Vlasov
equations of a shallow spherical cap, clamped, the apex deflection ``w`` prescribed, Fourier in the angle and
finite elements in the radius, written without anything from ``models/shell/``.  Its answers depend on
``lambda`` and ``nu`` only; the load is ``P R / (E t^3)``.

For lambda = 10 and 12 (``nu = 0.3``):

1. the axisymmetric path (``K = 0``) from the unloaded cap to ``w/t = W_END``, the Hessians of the wave numbers
   ``WATCH`` watched (at an axisymmetric state the Hessian splits by harmonic), every bifurcation into waves
   located by the engine;
2. from the first one (``n`` waves) the ``n``-wave branch in the ``D_n``-fixed space with the harmonics
   ``0, n, .., K n``: the located point lifted into it (:func:`contin.lift_branch_point`, which locates it again
   there) and the branch traced with :func:`contin.switch_branch` (the ``+1`` half; the other is its image under
   the turn by ``pi / n``), to ``w/t = W_END`` or the first branch point it meets (the axisymmetric path again, or
   another branch of the same symmetry);
3. its stability at fixed apex deflection at every stored point, against every class of perturbations of
   ``D_n`` (:func:`contin_models.benchmarks.shallow_cap.representation_harmonics`: ``A1`` the branch's own space,
   ``A2``, ``B1``, ``B2``, ``E_j``): the negative eigenvalues of each class's Hessian (the ``E`` classes count
   twice in the total); the turn of the pattern about the axis, an exact zero eigenvalue of ``A2``, is left out:
   ``A2`` is counted shifted by ``max(100 |t.H t| / t.t, 1e3 eps ||H||)``, ``t`` the turning mode.  Where the
   branch first loses stability, the class's smallest eigenvalue is interpolated linearly to zero between the two
   stored points;
4. ``P R / (E t^3)`` at ``w/t`` = 20, 25, 30, 35 on both branches (the state corrected by Newton at that apex
   deflection from the interpolated neighbours; on the first pass of the branch), the smallest eigenvalue of each
   class there and the counts of the same state turned by ``pi / n`` (the other half of the branch), against the
   shell model's numbers (``PROJECT``, from ``docs/asymmetric.md``);
5. convergence in the radial mesh ``N`` and the harmonics ``K``, and the error against the run time (the
   difference from the finest run);
6. Koiter's ``b`` at the bifurcation against the traced branch (:func:`koiter_check`), in the amplitude of the
   mode's largest ``w cos n t`` as well, beside the shell model's;
7. (``--full``) the shell model's axisymmetric path (:func:`studies.waves_branch.axisymmetric_path`, N = 200) at
   ``R/t`` = 10^3, 10^4, 10^5 (and N = 800 at 10^5) and the same lambda, and its ``n``-wave branch at
   ``R/t = 10^5`` (``K = 4``): towards the shallow limit its loads and special points should tend to this
   theory's (:func:`shell_limit`, :func:`shell_branch_limit`).

Units: ``t`` the thickness; ``P R / (E t^3)`` from the apex force ``q = P a^2 / (D t)``
(:func:`~contin_models.benchmarks.shallow_cap.load_factor`).  Writes ``table.csv``, ``bifurcations.csv``, ``koiter.csv``,
``convergence.csv``, ``shell_limit.csv`` and ``shell_branch_limit.csv`` (``--full``), ``axisymmetric.csv``,
``waves.csv``, ``summary.json`` and the figure ``shallow_cap_waves`` (PNG and PDF).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from scipy.sparse.linalg import spsolve  # noqa: E402

import contin  # noqa: E402
from contin_models.benchmarks.shallow_cap import ShallowCap, load_factor  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

NU = 0.3
LAMBDAS = (10.0, 12.0)
#: The traces stop at this apex deflection over the thickness (beyond the axisymmetric limit point at lambda = 12).
W_END = 40.0
W_TABLE = (20.0, 25.0, 30.0, 35.0)
#: ``R/t`` of the shell model's runs towards the shallow limit (``--full``), and its meridian's elements; the last
#: ``R/t`` again with ``SHELL_N_FINE`` elements (the shell model's own mesh error is of the order of the differences).
SHELL_DEPTHS = (1e3, 1e4, 1e5)
SHELL_N = 200
SHELL_N_FINE = 800
#: The harmonics of the runs of the mesh convergence (``--full``).
K_MESH = 4
#: The wave numbers watched on the axisymmetric path.
WATCH = tuple(range(2, 9))
#: The waves' largest amplitude, relative to its largest on the branch, below which the branch is back on the
#: axisymmetric path.
RETURN_AMPLITUDE = 1e-2
#: Mesh grading towards the pole (the point load's ``r^2 log r``): ``rho_i = (i / N)^GRADING``.
GRADING = 1.5
#: The shell model's numbers (``docs/asymmetric.md``, "The n-wave branches of clamped caps": N = 200, ``R/t = 1000``,
#: the branch at ``K = 6`` for lambda = 12 and ``K = 4`` for lambda = 10): first bifurcation, loads at W_TABLE on the
#: axisymmetric path and on the branch, where the branch loses stability, where it returns to the axisymmetric path.
PROJECT: dict[float, dict[str, Any]] = {
    12.0: {"n": 4, "w_bif": 17.989, "P_bif": 6.9984,
           "P_axisymmetric": {20.0: 7.5914, 25.0: 9.8494, 30.0: 13.352, 35.0: 15.350},
           "P_waves": {20.0: 7.4914, 25.0: 9.6094, 30.0: 13.090, 35.0: 14.595},
           "stable_to": "29.6-29.8", "returns_at": None, "b_w": 0.17788},
    10.0: {"n": 4, "w_bif": 18.602, "P_bif": 9.3618,
           "P_axisymmetric": {20.0: 10.289, 25.0: 11.235, 30.0: 22.334, 35.0: 97.98},
           "P_waves": {20.0: 10.278},
           "stable_to": "21.5-21.8", "returns_at": 20.5125, "b_w": 0.17507},
}


# ---- the two branches ------------------------------------------------------------------------------
def axisymmetric_path(lam: float, N: int, w_end: float = W_END) -> tuple[ShallowCap, contin.Branch]:
    """The axisymmetric cap (``K = 0``) traced to ``w/t = w_end`` with the wave numbers :data:`WATCH` watched."""
    cap = ShallowCap(lam, NU, N=N, grading=GRADING, watch=WATCH)
    br = contin.continuation(cap, cap.reference_unknowns(), 0.0, contin.Settings(
        ds=0.05, ds_max=0.5, max_steps=4000, stability=True), p_max=w_end)
    if br.status != "bound":
        raise RuntimeError(f"axisymmetric path, lambda = {lam:g}, N = {N}: {br.message}")
    return cap, br


def first_bifurcation(branch: contin.Branch) -> contin.SpecialPoint:
    """The first located bifurcation into waves on the axisymmetric path."""
    for spt in branch.special_points:
        if spt.kind == "bifurcation" and spt.info.get("family") == "n" and spt.located:
            return spt
    raise RuntimeError("no located bifurcation into waves on the axisymmetric path")


def lifted_point(axi: ShallowCap, point: contin.SpecialPoint, K: int) -> tuple[ShallowCap, contin.SpecialPoint]:
    """The ``D_n``-fixed cap with ``K`` harmonics and the bifurcation ``point`` of the axisymmetric cap lifted into it
    and located again there (:func:`contin.lift_branch_point`)."""
    n = int(point.info["key"])
    cap = ShallowCap(axi.lam, axi.nu, n=n, K=K, N=axi.N, grading=axi.grading)
    lift = contin.Lift(state=lambda x, p: cap.embed(axi, x), mode=lambda v: cap.embed_mode(n, v), family="n", key=n,
                       name="axisymmetric cap -> D_n")
    # the residual's terms are the axisymmetric cap's: its calibrated scale sets the tolerance from the first step
    # (the switch would otherwise keep the uncalibrated scale 1, below the roundoff floor of these terms)
    cap.calibrate_residual_scale(axi.residual_scale)
    return cap, contin.lift_branch_point(point, axi, cap, lift)


def wave_branch(axi: ShallowCap, point: contin.SpecialPoint, K: int, w_end: float = W_END,
                ds_max: float = 0.5) -> tuple[ShallowCap, contin.SpecialPoint, contin.Branch]:
    """The ``n``-wave branch from ``point`` in the ``D_n``-fixed space with ``K`` harmonics: the lifted and
    re-located branch point and the branch, to ``w_end`` or the first branch point it meets."""
    cap, bp = lifted_point(axi, point, K)
    br = contin.switch_branch(cap, bp, contin.Settings(ds=0.02, ds_max=ds_max, max_steps=4000, stability=True,
                                                       stop_at=("branch_point",)), p_max=w_end, direction=1)
    if not br.success:
        raise RuntimeError(f"{cap.n}-wave branch, lambda = {axi.lam:g}, N = {axi.N}, K = {K}: {br.message}")
    return cap, bp, br


def koiter_check(axi: ShallowCap, point: contin.SpecialPoint, ds: float = 0.002, steps: int = 40,
                 window: float = 2e-3) -> dict[str, Any]:
    """Koiter's ``b`` at the bifurcation (``w / w_c = 1 + b xi^2``, :func:`contin.koiter_coefficients` on the
    ``D_n`` cap with ``K = 2``, which holds the mode and its second-order field, the waves 0 and ``2 n``) against
    the intercept of ``(w / w_c - 1) / xi^2``, fitted linearly in ``xi^2`` on a short trace with steps ``ds`` (the
    points within ``window`` of ``w_c``); ``xi = phi^T x`` along the unit null vector ``phi``.  ``b_w``: the same in
    the amplitude of the mode's largest ``w cos n t`` nodal value over the thickness, ``b / height^2``."""
    cap, bp = lifted_point(axi, point, 2)
    k = contin.koiter_coefficients(cap, bp.u, bp.p, null_vector=bp.bifurcation.null_vector)
    short = contin.switch_branch(cap, bp, contin.Settings(ds=ds, ds_max=ds), direction=1, max_steps=steps)
    xi = np.asarray(short.u) @ k.null_vector
    rel = np.asarray(short.p) / bp.p - 1.0
    use = (rel != 0.0) & (np.abs(rel) <= window) & (xi != 0.0)
    if use.sum() < 4:
        raise RuntimeError(f"koiter_check: {int(use.sum())} points within {window} of w_c; take a smaller ds")
    traced = float(np.polyfit(xi[use] ** 2, rel[use] / xi[use] ** 2, 1)[1])
    values = [i for i, lab in enumerate(cap.space.labels) if lab[0] == cap.n and lab[2] == "w" and lab[4] == 0]
    height = float(np.max(np.abs(k.null_vector[values])))
    return {"lambda": axi.lam, "N": axi.N, "w_c": float(bp.p), "a": float(k.a), "b_koiter": float(k.b),
            "b_traced": traced, "rel_diff": traced / float(k.b) - 1.0, "b_w_koiter": float(k.b) / height ** 2,
            "b_w_traced": traced / height ** 2, "points": int(use.sum())}


# ---- stability against every class ---------------------------------------------------------------
def class_stability(cap: ShallowCap, x: np.ndarray, p: float, eigenvalues: bool = False) -> dict[str, Any]:
    """Negative eigenvalues per class of ``D_n`` at ``(x, p)`` (the turning mode left out of ``A2``), their total
    (``E`` classes twice) and, with ``eigenvalues``, each class's smallest eigenvalue (``A2``: without the turn)."""
    counts: dict[str, Any] = {}
    lowest: dict[str, float] = {}
    total = 0
    for label, (H, space) in cap.representation_hessians(x, p).items():
        if label == "A2":
            t = cap.turning_mode(x, space)
            turn = float(t @ (H @ t)) / float(t @ t)
            shift = max(100.0 * abs(turn), 1e3 * np.finfo(float).eps * float(abs(H).sum(axis=1).max()))
            H = H + shift * sp.identity(H.shape[0], format="csr")
        if eigenvalues:
            info = contin.stability_info(H, 3 if label == "A2" else 1, vectors=label == "A2")
            vals = info.eigenvalues
            if label == "A2":
                overlap = np.abs(info.eigenvectors.T @ (t / np.linalg.norm(t)))
                vals = np.delete(vals, int(np.argmax(overlap)))
            count, lowest[label] = info.n_negative, float(vals[0])
        else:
            count = contin.stability_info(H, 0).n_negative
        counts[label] = int(count)
        total += (2 if label.startswith("E") else 1) * int(count)
    counts["total"] = total
    return {"counts": counts, "lowest": lowest}


def loss_of_stability(cap: ShallowCap, branch: contin.Branch, counts: Sequence[dict[str, int]],
                      bisections: int = 8) -> dict[str, Any] | None:
    """Where the branch first loses stability: the two stored points around it, the classes that turn there, and
    the apex deflection where it happens, bisected on the chord between the two points (each trial state corrected
    by Newton at its deflection) to ``1 / 2^bisections`` of the step."""
    for i in range(1, len(counts)):
        if counts[i]["total"] > counts[i - 1]["total"]:
            turned = [k for k in counts[i] if k != "total" and counts[i][k] > counts[i - 1][k]]
            x0, x1 = np.asarray(branch.u[i - 1]), np.asarray(branch.u[i])
            w0, w1 = float(branch.p[i - 1]), float(branch.p[i])
            lo, hi, before = 0.0, 1.0, counts[i - 1]["total"]
            for _ in range(bisections):
                s = 0.5 * (lo + hi)
                w = w0 + s * (w1 - w0)
                x = newton_at(cap, (1 - s) * x0 + s * x1, w)
                if x is None:
                    break
                if class_stability(cap, x, w)["counts"]["total"] > before:
                    hi = s
                else:
                    lo = s
            return {"w_from": w0, "w_to": w1, "classes": turned,
                    "w_stable": w0 + lo * (w1 - w0), "w_unstable": w0 + hi * (w1 - w0)}
    return None


def newton_at(cap: ShallowCap, x: np.ndarray, w: float, max_steps: int = 30) -> np.ndarray | None:
    """The equilibrium at apex deflection ``w`` by Newton's method from ``x`` (None if it does not converge)."""
    scale = max(1.0, abs(cap.apex_force(x, w)))
    for _ in range(max_steps):
        f = cap.residual(x, w)
        if not np.all(np.isfinite(f)):
            return None
        if np.max(np.abs(f)) <= 1e-9 * scale:
            return x
        x = x - spsolve(cap.jacobian(x, w).tocsc(), f)
    return None


# ---- reading the branches ------------------------------------------------------------------------
def state_at(cap: ShallowCap, branch: contin.Branch, target: float, stop: int | None = None
             ) -> tuple[np.ndarray, int] | None:
    """The equilibrium at apex deflection ``target`` on the first segment of the branch that crosses it: the
    interpolated neighbours corrected by Newton at that deflection, and the segment's first index (None where the
    branch does not reach it)."""
    w = np.asarray(branch.p[:stop], dtype=float)
    for i in range(len(w) - 1):
        if (w[i] - target) * (w[i + 1] - target) <= 0.0 and w[i] != w[i + 1]:
            s = (target - w[i]) / (w[i + 1] - w[i])
            x = newton_at(cap, (1 - s) * np.asarray(branch.u[i]) + s * np.asarray(branch.u[i + 1]), target)
            if x is None:
                raise RuntimeError(f"state_at: Newton did not converge at w/t = {target} (lambda = {cap.lam:g})")
            return x, i
    return None


def branch_end(branch: contin.Branch) -> int:
    """The stored points up to the first branch point after the one the branch left (all of them if none)."""
    met = [s for s in branch.special_points[1:] if s.kind == "branch_point"]
    return min(len(branch.p), met[0].index + 1) if met else len(branch.p)


def case(lam: float, N: int, K: int, stability: bool = True, w_end: float = W_END) -> dict[str, Any]:
    """One cap: the axisymmetric path, its first bifurcation, the ``n``-wave branch, the table rows."""
    t0 = time.perf_counter()
    axi, path = axisymmetric_path(lam, N, w_end)
    t_path = time.perf_counter() - t0
    point = first_bifurcation(path)
    cap, bp, br = wave_branch(axi, point, K, w_end)
    stop = branch_end(br)
    counts = ([class_stability(cap, br.u[i], br.p[i])["counts"] for i in range(stop)] if stability else [])
    seconds = time.perf_counter() - t0
    koiter = koiter_check(axi, point) if stability else None
    scale = load_factor(lam, NU)
    rows = []
    for target in W_TABLE:
        row: dict[str, Any] = {"lambda": lam, "N": N, "K": K, "w_over_t": target}
        got = state_at(axi, path, target)
        row["P_axisymmetric"] = axi.apex_force(got[0], target) * scale if got else None
        got = state_at(cap, br, target, stop)
        if got is not None:
            row["P_waves"] = cap.apex_force(got[0], target) * scale
            row["ratio"] = row["P_waves"] / row["P_axisymmetric"]
            if stability:
                st = class_stability(cap, got[0], target, eigenvalues=True)
                row.update({f"n_{k}": v for k, v in st["counts"].items()})
                row.update({f"lowest_{k}": v for k, v in st["lowest"].items()})
                # the same state turned by pi / n, on the other half of the branch: B1 and B2 change places
                turned = class_stability(cap, cap.symmetry_generators[0] @ got[0], target)["counts"]
                row["turned_counts"] = " ".join(f"{k} {v}" for k, v in turned.items())
        ref = PROJECT.get(lam, {})
        for key in ("P_axisymmetric", "P_waves"):
            theirs = ref.get(key, {}).get(target)
            row[f"shell_{key}"] = theirs
            row[f"diff_{key}"] = (row[key] / theirs - 1.0) if (theirs and row.get(key) is not None) else None
        rows.append(row)
    met = [s for s in br.special_points[1:] if s.kind == "branch_point"]
    ret = float(met[0].p) if met else None
    w = np.asarray(br.p[:stop])
    largest = max(float(np.max(np.abs(u[cap.wave_unknowns]))) for u in br.u[:stop])
    later = [s for s in br.special_points[1:] if s.index < stop]
    # back on the axisymmetric path where the waves vanish (the branch turns back in w there: a fold of w)
    back = [s for s in later if float(np.max(np.abs(np.asarray(s.u)[cap.wave_unknowns]))) < RETURN_AMPLITUDE * largest]
    returns = float(back[0].p) if back else None
    axis_max = _path_maximum(path, scale)
    return {"lambda": lam, "N": N, "K": K, "n": int(point.info["key"]), "w_bif": float(point.p),
            "P_bif": float(point.observables["P"]), "w_bif_lifted": float(bp.p), "moved_w": float(bp.info["moved_p"]),
            "path_bifurcations": [(int(s.info["key"]), float(s.p)) for s in path.special_points
                                  if s.kind == "bifurcation" and s.located],
            "axisymmetric_limit_w": axis_max[0], "axisymmetric_limit_P": axis_max[1],
            "waves_status": br.status, "w_max": float(np.max(w)),
            "folds_in_w": [float(s.p) for s in later if s.kind == "fold" and s not in back],
            "meets_branch_point_at": ret, "returns_to_axisymmetric_at": returns,
            "loses_stability": loss_of_stability(cap, br, counts) if stability else None,
            "seconds_path": t_path, "seconds": seconds, "rows": rows, "koiter": koiter,
            "_axi": axi, "_path": path, "_cap": cap, "_branch": br, "_stop": stop, "_counts": counts}


def _path_maximum(path: contin.Branch, scale: float) -> tuple[float | None, float | None]:
    """The first located extremum of the load on the axisymmetric path (a fold in ``w`` does not enter: the
    control is ``w``), as the largest stored load before it falls."""
    P = np.asarray(path.observable("q")) * scale
    d = np.diff(P)
    for i in range(len(d) - 1):
        if d[i] > 0.0 >= d[i + 1]:
            return float(path.p[i + 1]), float(P[i + 1])
    return None, None


# ---- the shell model towards the shallow limit -----------------------------------------------------
def shell_limit(lam: float, r_over_t: float, N: int = SHELL_N) -> dict[str, Any]:
    """The shell model's axisymmetric path (``studies.waves_branch``: the exact spherical cap, ``lambda`` from its
    exact rise) at ``R/t = r_over_t``: its bifurcations into ``n = 4`` waves (leaving and meeting again) and
    ``P R / (E t^3)`` at :data:`W_TABLE` (linear between its stored points, as that study reads them)."""
    from studies.waves_branch import axisymmetric_path as shell_path
    from studies.waves_branch import load_scale, point_cap

    t0 = time.perf_counter()
    problem = point_cap(lam, N, r_over_t)
    path = shell_path(problem, W_TABLE[-1] + 1.0)
    w, P = np.asarray(path.observable("w")), np.asarray(path.observable("F")) * load_scale(problem)
    crossings = [float(s.p) for s in path.special_points if s.kind == "bifurcation" and s.located
                 and s.info.get("key") == 4]
    return {"lambda": lam, "R_over_t": r_over_t, "N": N, "w_bif_4": crossings[0] if crossings else None,
            "w_back_4": crossings[1] if len(crossings) > 1 else None,
            **{f"P_{int(t)}": float(np.interp(t, w, P)) for t in W_TABLE}, "seconds": time.perf_counter() - t0}


def shell_branch_limit(lam: float, r_over_t: float = SHELL_DEPTHS[-1], N: int = SHELL_N, K: int = K_MESH
                       ) -> dict[str, Any]:
    """The shell model's ``n``-wave branch (:func:`studies.waves_branch.point_load_case`) at ``R/t = r_over_t``
    with ``K`` harmonics: its loads at :data:`W_TABLE`, where it loses stability, folds and meets a branch point."""
    from studies.waves_branch import point_load_case

    c = point_load_case(lam, N, K, r_over_t)
    return {"lambda": lam, "R_over_t": r_over_t, "N": N, "K": K, "w_bif": c["w_bif"],
            **{f"P_waves_{int(r['w_over_t'])}": r.get("P_waves") for r in c["rows"]},
            "loses_stability": c["loses_stability"], "folds_in_w": c["folds_in_w"], "returns_at_w": c["returns_at_w"],
            "meets_branch_point_at": next((float(s.p) for s in c["_waves"].branch.special_points[1:]
                                           if s.kind == "branch_point"), None),
            "seconds": c["seconds"]}


# ---- the figure --------------------------------------------------------------------------------
def plot(cases: Sequence[dict[str, Any]]) -> Any:
    """Left: ``P R / (E t^3)`` against ``w/t``, the axisymmetric paths (light) and the ``n``-wave branches (solid
    stable, dashed unstable), with the shell model's loads at the table's deflections as crosses.  Right: the
    branches' load over the axisymmetric path's at the same deflection, where the bubble of lambda = 10 shows."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.branches import stability_pieces
    from contin.plot.style import COLORS, WIDTH

    fig, (ax, rel) = plt.subplots(1, 2, figsize=(1.7 * WIDTH, 3.9), layout="constrained")
    for k, c in enumerate(cases):
        color = COLORS[k % len(COLORS)]
        light = matplotlib.colors.to_hex(0.4 * np.asarray(matplotlib.colors.to_rgb(color)) + 0.6)
        scale = load_factor(c["lambda"], NU)
        path, br, stop = c["_path"], c["_branch"], c["_stop"]
        P_axis = np.asarray(path.observable("q")) * scale
        ax.plot(path.p, P_axis, color=light, lw=1.2, label=f"$\\lambda = {c['lambda']:g}$: axisymmetric")
        w, P = np.asarray(br.p[:stop]), np.asarray(br.observable("q")[:stop]) * scale
        ratio = P / np.interp(w, np.asarray(path.p), P_axis) - 1.0
        stable = [cnt["total"] == 0 for cnt in c["_counts"]] if c["_counts"] else [True] * len(w)
        label = f"$\\lambda = {c['lambda']:g}$: {c['n']} waves"
        for panel, y in ((ax, P), (rel, ratio)):
            first = True
            for X, Y, st in stability_pieces(w, y, None, None, np.arange(len(w), dtype=float), stable):
                panel.plot(X, Y, color=color, lw=1.4, ls="-" if st else "--", label=label if first else None)
                first = False
        ax.plot([c["w_bif"]], [c["P_bif"]], "o", color=color, mfc="white", ms=5)
        rel.plot([c["w_bif"]], [0.0], "o", color=color, mfc="white", ms=5)
        ref = PROJECT.get(c["lambda"], {})
        for key, marker in (("P_axisymmetric", "+"), ("P_waves", "x")):
            pts = [(a, b) for a, b in sorted(ref.get(key, {}).items()) if b < 30.0]
            if pts:
                ax.plot(*zip(*pts), marker, color="k" if key == "P_waves" else "0.45", ms=6, mew=1.0,
                        label=(f"shell model: {'branch' if key == 'P_waves' else 'axisymmetric'}" if k == 0 else None))
        mine = [(a, b / ref["P_axisymmetric"][a] - 1.0) for a, b in sorted(ref.get("P_waves", {}).items())]
        if mine:
            rel.plot(*zip(*mine), "x", color="k", ms=6, mew=1.0, label="shell model" if k == len(cases) - 1 else None)
    ax.set_xlabel(r"apex deflection $w/t$")
    ax.set_ylabel(r"apex load $P R / (E t^3)$")
    ax.set_xlim(0, W_END)
    ax.set_ylim(0, 25)
    ax.legend(loc="upper left", fontsize="x-small")
    rel.axhline(0.0, color="0.6", lw=0.8)
    rel.set_xlabel(r"apex deflection $w/t$")
    rel.set_ylabel(r"$P / P_{\mathrm{axisymmetric}} - 1$ at the same $w$")
    rel.set_xlim(16, W_END)
    # K = 2 puts the branch far above the path past w/t = 28; the converged branches stay within a few per cent
    rel.set_ylim(-0.08, 0.04)
    rel.legend(loc="upper left", fontsize="x-small")
    fig.suptitle(f"shallow-shell theory, clamped cap under an apex load, $\\nu = {NU:g}$ "
                 "(solid stable, dashed unstable at fixed $w$; open circles: bifurcation)", fontsize="small")
    return fig


# ---- the command line ----------------------------------------------------------------------------
def _public(c: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in c.items() if not k.startswith("_") and k != "rows"}


def convergence_rows(cases: Sequence[dict[str, Any]], K_mesh: int) -> list[dict[str, Any]]:
    """Per lambda and table deflection, the runs' loads and their differences from a reference, with the run
    times: ``in K``, the runs on the first run's mesh against the one with the most harmonics there; ``in N``, the
    runs with ``K_mesh`` harmonics against the finest mesh among them."""
    out = []
    for lam in sorted({c["lambda"] for c in cases}):
        mine = [c for c in cases if c["lambda"] == lam]
        N_main = mine[0]["N"]
        groups = {"in K": [c for c in mine if c["N"] == N_main], "in N": [c for c in mine if c["K"] == K_mesh]}
        for study, group in groups.items():
            if len(group) < 2:
                continue
            ref = max(group, key=lambda m: (m["K"], m["N"]))
            for c in group:
                for row, other in zip(c["rows"], ref["rows"]):
                    def diff(key: str) -> float | None:
                        a, b = row.get(key), other.get(key)
                        return None if a is None or b is None else a - b
                    out.append({"lambda": lam, "study": study, "N": c["N"], "K": c["K"], "w_over_t": row["w_over_t"],
                                "P_axisymmetric": row["P_axisymmetric"], "P_waves": row.get("P_waves"),
                                "error_axisymmetric": diff("P_axisymmetric"), "error_waves": diff("P_waves"),
                                "w_bif": c["w_bif"], "seconds": c["seconds"],
                                "reference": f"N = {ref['N']}, K = {ref['K']}"})
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("shallow_cap_waves", "the n-wave branch of the apex-loaded clamped cap by shallow-shell "
                                               "theory, against the shell model")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    if args.full:
        main_runs = [(lam, 100, 6) for lam in LAMBDAS]
        checks = ([(lam, 100, K) for lam in LAMBDAS for K in (2, 3, K_MESH)]
                  + [(lam, N, K_MESH) for lam in LAMBDAS for N in (50, 150)])
    else:
        main_runs, checks = [(lam, 40, 3) for lam in LAMBDAS], []
    cases = []
    for lam, N, K in main_runs + checks:
        say(args.quiet, f"lambda = {lam:g}, N = {N}, K = {K} ...")
        cases.append(case(lam, N, K, stability=(lam, N, K) in main_runs))
    main_cases = cases[:len(main_runs)]
    shells: list[dict[str, Any]] = []
    shell_branches: list[dict[str, Any]] = []
    if args.full:
        for lam in LAMBDAS:
            for rt, N in [(rt, SHELL_N) for rt in SHELL_DEPTHS] + [(SHELL_DEPTHS[-1], SHELL_N_FINE)]:
                say(args.quiet, f"shell model, lambda = {lam:g}, R/t = {rt:g}, N = {N} ...")
                shells.append(shell_limit(lam, rt, N))
        for lam in LAMBDAS:
            say(args.quiet, f"shell model's branch, lambda = {lam:g}, R/t = {SHELL_DEPTHS[-1]:g} ...")
            shell_branches.append(shell_branch_limit(lam))
        for c in main_cases:
            # the shallow theory's own crossings of n = 4 and loads, in the same columns
            n4 = [p for k, p in c["path_bifurcations"] if k == 4]
            shells.append({"lambda": c["lambda"], "R_over_t": "shallow", "N": c["N"],
                           "w_bif_4": n4[0] if n4 else None, "w_back_4": n4[1] if len(n4) > 1 else None,
                           **{f"P_{int(r['w_over_t'])}": r["P_axisymmetric"] for r in c["rows"]},
                           "seconds": c["seconds_path"]})
    elapsed = time.perf_counter() - t0
    table = [r for c in main_cases for r in c["rows"]]
    convergence = convergence_rows(cases, K_MESH)
    write_csv(out / "table.csv", table)
    write_csv(out / "bifurcations.csv", [_public(c) for c in cases])
    koiter_rows = [{**c["koiter"], "shell_b_w": PROJECT[c["lambda"]]["b_w"]} for c in main_cases]
    write_csv(out / "koiter.csv", koiter_rows)
    write_csv(out / "convergence.csv", convergence)
    if shells:
        write_csv(out / "shell_limit.csv", shells)
        write_csv(out / "shell_branch_limit.csv", shell_branches)
    write_csv(out / "axisymmetric.csv", [
        {"lambda": c["lambda"], "N": c["N"], "w_over_t": w, "P": q * load_factor(c["lambda"], NU), "stable": int(s)}
        for c in main_cases for w, q, s in zip(c["_path"].p, c["_path"].observable("q"), c["_path"].stable)])
    write_csv(out / "waves.csv", [
        {"lambda": c["lambda"], "N": c["N"], "K": c["K"], "n": c["n"], "w_over_t": c["_branch"].p[i],
         "P": c["_branch"].observable("q")[i] * load_factor(c["lambda"], NU),
         **{f"n_{k}": v for k, v in c["_counts"][i].items()}}
        for c in main_cases for i in range(c["_stop"])])
    write_json(out / "summary.json", {"full": bool(args.full), "seconds": elapsed, "nu": NU, "grading": GRADING,
                                      "load": "P R / (E t^3)", "shell_model": {str(k): v for k, v in PROJECT.items()},
                                      "cases": [_public(c) for c in cases], "table": table,
                                      "convergence": convergence, "shell_limit": shells,
                                      "shell_branch_limit": shell_branches})
    save_figure(plot(main_cases), out, "shallow_cap_waves")
    if not args.quiet:
        print_table(table, ["lambda", "N", "K", "w_over_t", "P_axisymmetric", "shell_P_axisymmetric",
                            "diff_P_axisymmetric", "P_waves", "shell_P_waves", "diff_P_waves", "n_A1", "n_A2", "n_B1",
                            "n_B2", "n_E1", "n_total", "turned_counts"], digits=5)
        print()
        print_table([_public(c) for c in cases], ["lambda", "N", "K", "n", "w_bif", "P_bif", "moved_w",
                                                  "axisymmetric_limit_w", "axisymmetric_limit_P", "w_max", "folds_in_w",
                                                  "meets_branch_point_at", "returns_to_axisymmetric_at",
                                                  "loses_stability", "seconds"], digits=6)
        print()
        print_table(koiter_rows, ["lambda", "N", "w_c", "a", "b_koiter", "b_traced", "rel_diff", "b_w_koiter",
                                  "b_w_traced", "shell_b_w", "points"], digits=6)
        if convergence:
            print()
            print_table(convergence, ["lambda", "study", "N", "K", "w_over_t", "P_axisymmetric", "error_axisymmetric",
                                      "P_waves", "error_waves", "seconds"], digits=5)
        if shells:
            print()
            print_table(shells, ["lambda", "R_over_t", "N", "w_bif_4", "w_back_4", *[f"P_{int(t)}" for t in W_TABLE],
                                 "seconds"], digits=6)
            print()
            print_table(shell_branches, ["lambda", "R_over_t", "N", "K", "w_bif",
                                         *[f"P_waves_{int(t)}" for t in W_TABLE], "loses_stability", "folds_in_w",
                                         "returns_at_w", "meets_branch_point_at", "seconds"], digits=6)
        print(f"\n{elapsed:.1f} s; written to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
