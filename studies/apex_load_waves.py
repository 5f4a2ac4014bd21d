"""The clamped cap under an apex load for lambda = 8 .. 14: where it leaves the axisymmetric path, into how many
waves, and how far its ``n``-wave branch carries load (the question of Fitch 1968).

Run ``python -m studies.apex_load_waves [--out DIR] [--full]``.  ``docs/three_d.md`` (section 4) states the numbers
and the conclusions; this docstring says what is computed.

The cap is :func:`studies.waves_branch.point_cap`: clamped, ``nu = 0.3``, ``lambda = 2 (3 (1 - nu^2))^(1/4)
sqrt(H/t)`` with the exact rise ``H``, ``t = 1``, ``R = R/t``, a point force at the apex under displacement control
(the apex deflection ``w`` prescribed), the harmonic blocks ``n = 1 .. default_harmonics`` watched.  For each lambda
and depth ``R/t``:

1. the axisymmetric path from the unloaded cap to ``w = 2 H`` (the inverted cap), every bifurcation into waves
   located (:func:`studies.waves_branch.axisymmetric_path`); its **limit load** is the first maximum of the load
   along it (the snap under a dead load), read off the stored points and a parabola through the largest one and
   its neighbours (:func:`load_maximum`);
2. its first bifurcation into ``n`` waves, and whether it comes before the limit load;
3. where it does, the ``n``-wave branch in the ``D_n`` view with ``K`` harmonics, counted against every
   representation of ``D_n`` (:func:`studies.waves_branch.n_wave_branch`), to ``w = 2 H`` or back to the
   axisymmetric path.  Read off it (:func:`branch_end`):

   * its **end** under displacement control: a fold in ``w`` (the cap snaps there under a prescribed deflection),
     its return to the axisymmetric path (a branch point where the waves vanish), or the end of the travel;
   * its largest load before that end: the **maximum under force control** (the fold of the load, where a dead
     load snaps), or the load at the end if the load rises all the way;
   * where it first loses stability under displacement control (a negative eigenvalue of any representation: a
     secondary bifurcation into a class it does not carry) and under force control.

``--full`` also asks where the cap goes where the branch loses stability (:func:`descent_past_loss`: the branch
that breaks the symmetry there, and an energy descent just past the point) and brackets the range of lambda where
the axisymmetric snap comes before any bifurcation (:func:`snap_range`).  The engine's followed path
(:func:`contin_models.shell.followed.follow_path`) is not used: on these caps it stops at the loss of stability of
the ``n``-wave branch, where its snap finds no descent along the mode (``docs/three_d.md``, section 4).

The loads are ``P R / (E t^3)`` (shallow-shell theory's parameter; divided by Reissner's linear stiffness
``4 / sqrt(3 (1 - nu^2)) = 2.42`` they are the apex deflection over the thickness that the linear shallow sphere
would have under them).  The shallow limit is ``R/t = 10^4``; the deep cap ``R/t = 100`` (``H / R`` = 0.10 at
lambda = 8, 0.30 at 14).  ``--full`` adds the harmonics ``K + 1`` and a finer meridian at two lambdas in the
shallow limit, and the first bifurcation of the independent shallow-shell model (:mod:`studies.shallow_cap_waves`)
at every lambda.

Writes ``cases.csv`` (one row per lambda, depth, ``N`` and ``K``), ``paths.csv`` (the axisymmetric paths and the
branches of the main runs), ``shallow_model.csv`` and ``descents.csv`` (``--full``), ``summary.json`` (with the
range of the axisymmetric snap under ``--full``) and the figure ``apex_load_waves`` (PNG and PDF).
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
from contin.analyses.jump import jump  # noqa: E402
from contin_models.shell.lift import follow_symmetry_breaking, state_symmetry  # noqa: E402
from contin_models.benchmarks.shallow_cap import load_factor, point_load_stiffness  # noqa: E402
from studies import shallow_cap_waves  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.waves_branch import (Curve, axisymmetric_path, draw_path, extrema, first_half,  # noqa: E402
                                  load_scale, loss_of_stability, n_wave_branch, physical_stability, point_cap,
                                  return_point, wave_amplitude)

NU = 0.3
#: Fitch's range of the depth parameter.
LAMBDAS = (8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0)
#: The shallow limit and the deep cap, ``R/t``.
SHALLOW, DEEP = 1e4, 100.0
#: A branch point met on the branch is its return to the axisymmetric path when the waves' largest amplitude there
#: is below this fraction of their largest along the branch.
RETURN_AMPLITUDE = 1e-2
#: The largest arclength steps of the branch's trace, tried in turn: the switch onto the branch can fail at its
#: first steps with one and not with another (the corrector lands on the axisymmetric path).
DS_MAX_TRIES = (0.25, 0.1, 0.4)
#: Brackets of lambda for :func:`snap_range`: the snap appears within the first, the bifurcation overtakes it within
#: the second; the bisection's width.
SNAP_BRACKET, BIFURCATION_BRACKET, LAMBDA_TOL = (4.0, 8.0), (9.0, 10.0), 0.01
#: How far past the loss of stability of the branch (in ``w/t``) the energy is descended.
DESCENT_DW = 0.05
#: The waves of a landing listed with their amplitude: those above this (over the thickness).
WAVE_SHOWN = 1e-2


def rise_over_thickness(lam: float, nu: float = NU) -> float:
    """``H / t`` of the cap of depth parameter ``lam``: ``lambda^2 / (4 sqrt(3 (1 - nu^2)))``."""
    return lam ** 2 / (4.0 * math.sqrt(3.0 * (1.0 - nu ** 2)))


def load_maximum(w: np.ndarray, P: np.ndarray) -> tuple[float, float] | None:
    """The first interior maximum of ``P`` along a path (``w`` rising there): the vertex of the parabola in ``w``
    through the largest stored point and its two neighbours; None where the load does not turn down."""
    w, P = np.asarray(w, dtype=float), np.asarray(P, dtype=float)
    for i in extrema(P):
        if P[i] > P[i - 1] and P[i] > P[i + 1]:
            c2, c1, c0 = np.polyfit(w[i - 1:i + 2], P[i - 1:i + 2], 2)
            if c2 < 0.0:
                wv = -c1 / (2.0 * c2)
                return float(wv), float(c0 + c1 * wv + c2 * wv ** 2)
            return float(w[i]), float(P[i])
    return None


def branch_end(wb: Any, w: np.ndarray, P: np.ndarray, stop: int) -> dict[str, Any]:
    """How the ``n``-wave branch (its first ``stop`` stored points, deflections ``w`` and loads ``P``) ends under
    displacement control, whichever comes first along it: ``"fold in w"`` (the branch turns back in the prescribed
    deflection), ``"returns"`` (to the axisymmetric path), ``"meets another branch"`` (a branch point where the
    waves do not vanish), ``"end of travel"`` or ``"trace stopped"`` (the trace failed: its message is the case's
    ``status``); with the deflection and the load there, and the deflection where
    it returns to the axisymmetric path (``w_return``, None if it does not)."""
    b = wb.branch
    back = return_point(b)
    met = next((s for s in b.special_points[1:] if s.kind == "branch_point"), None)
    kind = None
    if met is not None:
        largest = max(wave_amplitude(wb, u, q) for u, q in zip(b.u[:stop], b.p[:stop]))
        kind = "returns" if wave_amplitude(wb, met.u, met.p) < RETURN_AMPLITUDE * largest else "meets another branch"
    # the branch meets the path with w turning back there: that is its return, not a fold
    folds = [s for s in b.special_points if s.kind == "fold" and s.index < stop - 1
             and (back is None or abs(float(s.p) - back) > 1e-6 * back)]
    w_return = back if kind == "returns" else None
    if folds:
        return {"end": "fold in w", "w_end": float(folds[0].p), "P_end": float(folds[0].observables["F"])
                * load_scale(wb.problem), "w_return": w_return}
    if met is not None:
        return {"end": kind, "w_end": back, "P_end": float(P[stop - 1]), "w_return": w_return}
    if not b.success:
        return {"end": "trace stopped", "w_end": float(w[stop - 1]), "P_end": float(P[stop - 1]), "w_return": None}
    return {"end": "end of travel", "w_end": float(w[stop - 1]), "P_end": float(P[stop - 1]), "w_return": None}


def first_unstable(branch: contin.Branch, label: str, stop: int) -> int | None:
    """The first stored point of the branch (of its first ``stop``) with a negative eigenvalue under ``label``."""
    bad = np.flatnonzero(np.asarray(branch.n_negative_under(label))[:stop] > 0)
    return int(bad[0]) if bad.size else None


def branch_with_retries(problem: Any, point: contin.SpecialPoint, K: int, w_end: float) -> tuple[Any, float]:
    """The ``n``-wave branch (:func:`studies.waves_branch.n_wave_branch`) with the largest steps of
    :data:`DS_MAX_TRIES` in turn, until one traces it; and that step.  If none does, the failed trace that went
    farthest along the branch (``branch.success`` False, its message saying where it stopped)."""
    failed = []
    for ds_max in DS_MAX_TRIES:
        wb = n_wave_branch(problem, point, K, w_end, ds_max=ds_max, strict=False)
        if wb.branch.success:
            return wb, ds_max
        failed.append((len(wb.branch.p), ds_max, wb))
    _, ds_max, wb = max(failed, key=lambda f: f[0])
    return wb, ds_max


def apex_case(lam: float, r_over_t: float, N: int, K: int, branch: bool = True) -> dict[str, Any]:
    """One cap: the axisymmetric path to ``w = 2 H``, its limit load, its first bifurcation into waves and (when it
    comes before the limit load and ``branch``) the ``n``-wave branch with ``K`` harmonics, read as in the module
    docstring."""
    t0 = time.perf_counter()
    H = rise_over_thickness(lam)
    pr = point_cap(lam, N, r_over_t, NU)
    scale = load_scale(pr)
    path = axisymmetric_path(pr, 2.0 * H)
    w0, P0 = np.asarray(path.observable("w")), np.asarray(path.observable("F")) * scale
    limit = load_maximum(w0, P0)
    bifs = [s for s in path.special_points if s.kind == "bifurcation" and s.info.get("family") == "n" and s.located]
    out: dict[str, Any] = {"lambda": lam, "R_over_t": r_over_t, "H_over_t": H, "N": N, "K": K,
                           "w_limit": limit[0] if limit else None, "P_limit": limit[1] if limit else None,
                           "n": None, "w_bif": None, "P_bif": None, "bifurcation_first": False,
                           "_problem": pr, "_path": path, "_waves": None}
    if bifs:
        first = bifs[0]
        out.update(n=int(first.info["key"]), w_bif=float(first.p), P_bif=float(first.observables["F"]) * scale,
                   bifurcation_first=limit is None or float(first.p) < limit[0])
        if out["bifurcation_first"]:
            out["P_bif_over_P_limit"] = out["P_bif"] / limit[1] if limit else None
    if out["bifurcation_first"] and branch:
        wb, ds_max = branch_with_retries(pr, first, K, 2.0 * H)
        b = wb.branch
        stop = first_half(b)
        w, P = np.asarray(b.observable("w"))[:stop], np.asarray(b.observable("F"))[:stop] * scale
        end = branch_end(wb, w, P, stop)
        top = load_maximum(w, P)
        w_max, P_max = top if top is not None else (end["w_end"], end["P_end"])
        lost = loss_of_stability(wb, w, stop)
        i_force = first_unstable(b, "force", stop)
        out.update(end, w_Pmax=w_max, P_max=P_max, load_falls=top is not None,
                   P_max_over_P_limit=P_max / limit[1] if limit else None,
                   stable_to_w=lost["w_from"] if lost else None,
                   unstable_from_w=lost["w_to"] if lost else None,
                   lost_to=" ".join(lost["representations"]) if lost else None,
                   P_at_loss=float(P[np.flatnonzero(w == lost["w_from"])[0]]) if lost else None,
                   force_stable_to_w=float(w[i_force - 1]) if i_force else None,
                   ds_max=ds_max, status=b.status if b.success else f"{b.status}: {b.message}", _waves=wb)
    out["seconds"] = time.perf_counter() - t0
    return out


def descent_past_loss(case: dict[str, Any], dw: float = DESCENT_DW) -> dict[str, Any]:
    """Where the cap goes where its ``n``-wave branch loses stability under displacement control.

    The located bifurcation into the class that turns first is lifted into the view of the subgroup it leaves into
    (:func:`contin_models.shell.lift.follow_symmetry_breaking`, a few steps of that branch both ways: its Morse
    index under displacement control at its third point says whether it could carry the cap), and the energy is
    descended (:func:`contin.analyses.jump.jump`) at the deflection ``dw`` past the point from the branch point's
    state, kicked along the bifurcation's mode: the landing's symmetry (its waves present above 1e-6 of the shell's
    size), the amplitudes of its waves above :data:`WAVE_SHOWN` ``t``, its load and its Morse index in the descent's
    view.
    """
    wb = case["_waves"]
    b = wb.branch
    stop = first_half(b)
    point = next((s for s in b.special_points if s.kind == "bifurcation" and s.located and s.index < stop), None)
    if point is None:
        return {"lambda": case["lambda"], "R_over_t": case["R_over_t"], "message": "no located loss of stability"}
    scale = load_scale(case["_problem"])
    row: dict[str, Any] = {"lambda": case["lambda"], "R_over_t": case["R_over_t"], "N": case["N"], "K": case["K"],
                           "class": point.info.get("key"), "w_loss": float(point.p),
                           "P_loss": float(point.observables["F"]) * scale}
    settings = contin.Settings(ds=0.01, ds_max=0.05, stability=True)
    for side in (1, -1):
        bb = follow_symmetry_breaking(wb.problem, point, settings=settings, direction=side, max_steps=3)
        counts = np.asarray(bb.branch.n_negative_under("displacement"))
        row[f"secondary_{'plus' if side > 0 else 'minus'}_negative"] = int(counts[min(2, len(counts) - 1)])
        row[f"secondary_{'plus' if side > 0 else 'minus'}_dw"] = float(bb.branch.p[-1]) - float(point.p)
    view, bp = bb.problem, bb.branch_point
    jr = jump(view, bp.u, float(bp.p) + dw, direction=np.asarray(bp.bifurcation.null_vector))
    sym = state_symmetry(view.basis, view.full_state(jr.u_to, jr.p))
    obs = view.evaluate_observables(jr.u_to, jr.p)
    row.update(w_landing=float(obs["w"]), P_landing=float(obs["F"]) * scale, landing=sym.label,
               waves=" ".join(f"{k}:{a:.3g}" for k, a in sorted(sym.amplitudes.items()) if k > 0 and a > WAVE_SHOWN),
               landing_negative=int(jr.n_negative), landed=bool(jr.success), message=jr.message)
    return row


def bisect_lambda(test: Any, low: float, high: float, tol: float = LAMBDA_TOL) -> tuple[float, float]:
    """The interval of width ``tol`` in lambda where ``test`` (False at ``low``, True at ``high``) turns True."""
    if test(low) or not test(high):
        raise ValueError(f"bisect_lambda: the test must be False at lambda = {low:g} and True at {high:g}")
    while high - low > tol:
        mid = 0.5 * (low + high)
        low, high = (low, mid) if test(mid) else (mid, high)
    return low, high


def snap_range(r_over_t: float, N: int, tol: float = LAMBDA_TOL) -> dict[str, Any]:
    """The range of lambda where the cap snaps axisymmetrically before any bifurcation into waves: from the lambda
    where its axisymmetric path first has a limit load (below it the load rises all the way to ``w = 2 H``) to the
    lambda where the first bifurcation comes before that limit load; each bracketed to ``tol``."""
    def has_limit(lam: float) -> bool:
        return apex_case(lam, r_over_t, N, 1, branch=False)["P_limit"] is not None

    def bifurcates_first(lam: float) -> bool:
        return apex_case(lam, r_over_t, N, 1, branch=False)["bifurcation_first"]

    lo = bisect_lambda(has_limit, SNAP_BRACKET[0], SNAP_BRACKET[1], tol)
    hi = bisect_lambda(bifurcates_first, BIFURCATION_BRACKET[0], BIFURCATION_BRACKET[1], tol)
    first = apex_case(hi[1], r_over_t, N, 1, branch=False)
    return {"R_over_t": r_over_t, "N": N, "limit_load_from": lo, "bifurcation_first_from": hi,
            "n_there": first["n"], "w_bif_there": first["w_bif"], "w_limit_there": first["w_limit"]}


def shallow_model_bifurcation(lam: float, N: int) -> dict[str, Any]:
    """The independent shallow-shell model's first bifurcation into waves and limit load (``K = 0``, its wave
    numbers watched; :func:`studies.shallow_cap_waves.axisymmetric_path`), to ``w = 2 H``."""
    cap, path = shallow_cap_waves.axisymmetric_path(lam, N, 2.0 * rise_over_thickness(lam))
    scale = load_factor(lam, NU)
    P = np.asarray(path.observable("q")) * scale
    limit = load_maximum(np.asarray(path.p), P)
    bifs = [s for s in path.special_points if s.kind == "bifurcation" and s.located]
    first = bifs[0] if bifs else None
    return {"lambda": lam, "N": N, "n": int(first.info["key"]) if first else None,
            "w_bif": float(first.p) if first else None,
            "P_bif": float(first.observables["q"]) * scale if first else None,
            "w_limit": limit[0] if limit else None, "P_limit": limit[1] if limit else None}


# ---- the figure ----------------------------------------------------------------------------------
def plot(cases: Sequence[dict[str, Any]]) -> Any:
    """Load against apex deflection per lambda at both depths (axisymmetric light, the branch strong; solid stable
    and dashed unstable under displacement control), and against lambda the axisymmetric limit load, the load at the
    first bifurcation and the load where the branch loses stability."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.style import COLORS, WIDTH

    depths = sorted({c["R_over_t"] for c in cases}, reverse=True)
    lams = sorted({c["lambda"] for c in cases})
    fig, axes = plt.subplots(1, len(depths) + 1, figsize=(WIDTH * 2.0, 3.9), layout="constrained", squeeze=False)
    for ax, rt in zip(axes[0], depths):
        top = 0.0
        for case in (c for c in cases if c["R_over_t"] == rt):
            color = COLORS[lams.index(case["lambda"]) % len(COLORS)]
            s = load_scale(case["_problem"])
            path = case["_path"]
            w0, P0 = np.asarray(path.observable("w")), np.asarray(path.observable("F")) * s
            light = matplotlib.colors.to_hex(0.45 * np.asarray(matplotlib.colors.to_rgb(color)) + 0.55)
            draw_path(ax, Curve(w0, P0, np.asarray(path.stable_under("displacement"))), light,
                      f"$\\lambda = {case['lambda']:g}$")
            top = max(top, case["P_limit"] or 0.0)
            if case["P_limit"] is not None:
                ax.plot([case["w_limit"]], [case["P_limit"]], "^", color=color, ms=4)
            wb = case["_waves"]
            if wb is None:
                continue
            b = wb.branch
            stop = first_half(b)
            draw_path(ax, Curve(np.asarray(b.observable("w"))[:stop], np.asarray(b.observable("F"))[:stop] * s,
                                physical_stability(wb)[:stop]), color, None)
            ax.plot([case["w_bif"]], [case["P_bif"]], "o", color=color, mfc="white", ms=4.5)
            ax.plot([case["w_Pmax"]], [case["P_max"]], "s", color=color, ms=3.5)
            if case["stable_to_w"] is not None:
                ax.plot([case["stable_to_w"]], [case["P_at_loss"]], "x", color=color, ms=5)
        ax.set_xlim(0.0, max(c["w_limit"] or 0.0 for c in cases if c["R_over_t"] == rt) * 1.25)
        ax.set_ylim(0.0, 1.25 * top)
        ax.set_xlabel(r"apex deflection $w/t$")
        ax.set_ylabel(r"apex load $P R / (E t^3)$")
        ax.set_title(f"$R/t = {rt:g}$", fontsize="small")
        ax.legend(loc="upper left", fontsize="x-small", ncol=2)
    ax = axes[0, -1]
    for rt, ls in zip(depths, ("-", "--")):
        sel = sorted((c for c in cases if c["R_over_t"] == rt), key=lambda c: c["lambda"])
        lam = [c["lambda"] for c in sel]
        ax.plot(lam, [c["P_limit"] for c in sel], ls, color="0.4", marker="^", ms=4,
                label=f"axisymmetric limit, $R/t = {rt:g}$")
        bif = [c for c in sel if c["bifurcation_first"]]
        ax.plot([c["lambda"] for c in bif], [c["P_bif"] for c in bif], ls, color=COLORS[0], marker="o", mfc="white",
                ms=4, label=f"bifurcation, $R/t = {rt:g}$")
        lost = [c for c in bif if c.get("P_at_loss") is not None]
        ax.plot([c["lambda"] for c in lost], [c["P_at_loss"] for c in lost], ls, color=COLORS[2], marker="x", ms=5,
                label=f"the branch loses stability, $R/t = {rt:g}$")
    ax.set_xlabel(r"$\lambda$")
    ax.set_ylabel(r"$P R / (E t^3)$")
    ax.set_title("loads against $\\lambda$", fontsize="small")
    ax.legend(loc="upper left", fontsize="x-small")
    fig.suptitle(r"clamped caps under an apex load, $\nu = 0.3$: axisymmetric path (light), $n$-wave branch (strong), "
                 "solid stable and dashed unstable under displacement control; open circle: bifurcation, triangle: "
                 "axisymmetric limit load, square: largest load on the branch, cross: the branch loses stability",
                 fontsize="x-small")
    return fig


# ---- the command line ----------------------------------------------------------------------------
def _public(case: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in case.items() if not k.startswith("_")}


COLUMNS = ["lambda", "R_over_t", "N", "K", "n", "w_bif", "P_bif", "w_limit", "P_limit", "bifurcation_first",
           "end", "w_end", "P_end", "w_return", "w_Pmax", "P_max", "P_max_over_P_limit", "stable_to_w", "P_at_loss",
           "lost_to", "force_stable_to_w", "ds_max", "status", "seconds"]


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("apex_load_waves", "clamped caps under an apex load, lambda = 8 .. 14: the n-wave "
                                             "branches against the axisymmetric limit load (Fitch 1968)")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    if args.full:
        main_runs = [(lam, rt, 120, 3) for rt in (SHALLOW, DEEP) for lam in LAMBDAS]
        checks = [(lam, SHALLOW, 120, 4) for lam in (10.0, 14.0)] + [(lam, SHALLOW, 200, 3) for lam in (10.0, 14.0)]
        shallow = [(lam, 60) for lam in LAMBDAS] + [(lam, 100) for lam in (10.0, 14.0)]
    else:
        main_runs = [(lam, rt, 60, 2) for rt in (SHALLOW, DEEP) for lam in (8.0, 11.0, 14.0)]
        checks, shallow = [], []
    cases = []
    for lam, rt, N, K in main_runs + checks:
        say(args.quiet, f"apex load, lambda = {lam:g}, R/t = {rt:g}, N = {N}, K = {K} ...")
        cases.append(apex_case(lam, rt, N, K))
    main_cases = cases[:len(main_runs)]
    descents = []
    for c in (main_cases if args.full else []):
        if c["_waves"] is not None and c.get("stable_to_w") is not None:
            say(args.quiet, f"descent past the loss of stability, lambda = {c['lambda']:g}, "
                            f"R/t = {c['R_over_t']:g} ...")
            try:
                descents.append(descent_past_loss(c))
            except (RuntimeError, ValueError, ArithmeticError) as exc:
                descents.append({"lambda": c["lambda"], "R_over_t": c["R_over_t"], "message": str(exc)})
    ranges = []
    for rt in ((SHALLOW, DEEP) if args.full else ()):
        say(args.quiet, f"the range of the axisymmetric snap, R/t = {rt:g} ...")
        ranges.append(snap_range(rt, 120))
    shallow_rows = []
    for lam, N in shallow:
        say(args.quiet, f"shallow-shell model, lambda = {lam:g}, N = {N} ...")
        shallow_rows.append(shallow_model_bifurcation(lam, N))
    elapsed = time.perf_counter() - t0
    rows = [_public(c) for c in cases]
    write_csv(out / "cases.csv", [{k: r.get(k) for k in COLUMNS} for r in rows])
    paths = []
    for c in main_cases:
        s = load_scale(c["_problem"])
        for w, P, ok in zip(c["_path"].observable("w"), np.asarray(c["_path"].observable("F")) * s,
                            c["_path"].stable_under("displacement")):
            paths.append({"lambda": c["lambda"], "R_over_t": c["R_over_t"], "branch": "axisymmetric", "w_over_t": w,
                          "P": P, "stable_displacement": int(ok)})
        if c["_waves"] is not None:
            b = c["_waves"].branch
            stop = first_half(b)
            for w, P, ok in zip(np.asarray(b.observable("w"))[:stop], (np.asarray(b.observable("F")) * s)[:stop],
                                physical_stability(c["_waves"])[:stop]):
                paths.append({"lambda": c["lambda"], "R_over_t": c["R_over_t"], "branch": f"{c['n']} waves",
                              "w_over_t": w, "P": P, "stable_displacement": int(ok)})
    write_csv(out / "paths.csv", paths)
    if shallow_rows:
        write_csv(out / "shallow_model.csv", shallow_rows)
    if descents:
        write_csv(out / "descents.csv", descents)
    write_json(out / "summary.json", {"full": bool(args.full), "seconds": elapsed, "nu": NU,
                                      "load": "P R / (E t^3)", "linear_stiffness": point_load_stiffness(NU),
                                      "cases": rows, "shallow_model": shallow_rows, "descents": descents,
                                      "snap_range": ranges})
    save_figure(plot(main_cases), out, "apex_load_waves")
    if not args.quiet:
        print_table(rows, COLUMNS, digits=5)
        if shallow_rows:
            print()
            print_table(shallow_rows, ["lambda", "N", "n", "w_bif", "P_bif", "w_limit", "P_limit"], digits=6)
        if ranges:
            print()
            print_table(ranges, ["R_over_t", "N", "limit_load_from", "bifurcation_first_from", "n_there",
                                 "w_bif_there", "w_limit_there"], digits=6)
        if descents:
            print()
            print_table(descents, ["lambda", "R_over_t", "class", "w_loss", "P_loss", "secondary_plus_negative",
                                   "secondary_minus_negative", "landing", "waves", "w_landing", "P_landing",
                                   "landing_negative", "landed"], digits=6)
        print(f"\n{elapsed:.1f} s; written to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
