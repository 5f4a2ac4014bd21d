"""Force-displacement curves of the point-indented cap and its hysteresis (paper figures 3 and 4).

Run ``python -m studies.force_displacement [--out DIR] [--full] [--quiet]``.  The default (fast) mode
uses a coarse mesh (N = 60, continuation steps of 1/40 of the eversion depth) and every case;
``--full`` uses the paper's N = 200 (steps of 1/100 of the eversion depth).  CPU time on one core:
about 10 s fast, 25 s with ``--full``.  Both write into
``DIR`` (default ``out/force_displacement``):

``fig3.png`` / ``fig3.pdf`` and ``fig3.csv``
    Paper figure 3: the normalized force ``F R / (2 pi D)`` against ``w / R`` along the whole
    displacement-controlled path of the bilateral point load (the path the classification is
    defined on, ``docs/model.md#classes``), from the reference state to 5 % past
    eversion.  (a) ``h/R = 0.02``, ``phi_hat`` = 0.6, 0.7, ..., 1.3; (b) ``phi_hat = 1.0``,
    ``h/R`` = 0.01, 0.02, ..., 0.08.  Parts stable under displacement control are solid, unstable
    parts dashed; each curve is labelled with the class of that same run
    (:func:`contin_models.shell_scene.classify` through the scene runner).  The located first maximum and
    last minimum of F (the force-control snap loads) are marked.  The paper's axis label reads
    ``F h / (2 pi D)``; its figure 6 and the text of section 4b use ``F R / (2 pi D)``, which is what
    is plotted (``R = 1`` in the paper, so the two differ only by the extraction).
``fig4.png`` / ``fig4.pdf`` and ``fig4.csv``
    Paper figure 4: quasi-static loading and unloading (:func:`contin.quasistatic`) of the caps
    ``phi_hat = 1.2`` (column a) and ``0.8`` (column b), ``h/R = 0.02``.  Row 1: displacement
    control of the pole (the paper's control: "the pole is manually moved"); loading to 5 % past
    eversion and back to ``w = 0``.  Row 2: force control (a dead load on the pole).  Loading goes
    to ``1.2 F_max`` (beyond the snap); unloading goes to ``F = 0`` for a monostable cap, and for
    a bistable cap to ``1.2 F_min`` (``F_min < 0``: the everted cap is stable without load and
    only a pull past ``F_min`` snaps it back), followed by a return to ``F = 0``.  Snaps are
    dotted arrows; the whole displacement-controlled path is drawn in grey underneath.  Row 3:
    meridian shapes ``(r, z)`` (mirrored about the axis) at the numbered points of row 1.
``summary.json``
    Per case of figure 3 the class, ``lambda``, ``F_max_norm``, ``F_min_norm`` (and where they
    occur), the folds in ``w`` and the scene overrides that rebuild the case.  Per cap of figure 4
    and per control the snaps (where, from which force to which), whether the loading and unloading
    sweeps form a hysteresis loop (:func:`contin.hysteresis_cycles` of their diagram), the loop's
    width and area, and the elastic energy the snaps release (equal to the area up to the trapezoid
    rule).  Then the three statements of the paper these figures carry (``docs/model.md#what-the-paper-reports``),
    each with the numbers that decide it and ``"reproduced"`` true or false.

Forces are ``F_norm = F R / (2 pi D)`` and displacements ``w / R`` throughout; loop areas are in
units of ``2 pi D`` (``oint F_norm d(w/R)``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin.app.scene import TraceResult, load_scene  # noqa: E402
from contin.plot import style  # noqa: E402
from contin.plot.branches import smooth_path, stability_pieces  # noqa: E402
from contin_models.shell.problem import ShellPointLoad  # noqa: E402
from contin_models.shell_scene import SHELL_SCENE, SHELL_SCHEMA, eversion_displacement, point_problem, point_settings  # noqa: E402
from studies._common import (clearest_offset, output_dir, print_table, save_figure, say, shell_lambda,  # noqa: E402
                             study_parser, write_csv, write_json)

NAME = "force_displacement"
#: Figure 3a: base angles at h/R = 0.02 (the paper's range [0.6, 1.3]).
PHI_3A = (0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3)
H_3A = 0.02
#: Figure 3b: thicknesses at phi_hat = 1.0 (the paper's range [0.01, 0.08]).
H_3B = (0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08)
PHI_3B = 1.0
#: Figure 4: the monostable (a) and bistable (b) caps at h/R = 0.02.
PHI_4 = (1.2, 0.8)
H_4 = 0.02
N_FAST, N_FULL = 60, 200
#: Steps per eversion depth on the paths (the scene's default is 20): fast and full mode (smooth curves).
STEPS_FAST, STEPS_FULL = 40, 100
#: Force-control sweeps: load to this multiple of F_max; a bistable cap is pulled to this multiple of F_min.
FORCE_MARGIN = 1.2
_RANK = {"bistable": 0, "monostable": 1, "monotonous": 2}


# ---------------------------------------------------------------------------------------------------
# scenes and runs
# ---------------------------------------------------------------------------------------------------
def case_overrides(phi_hat: float, h_over_R: float, N: int, steps: int = STEPS_FULL) -> list[str]:
    """The ``--set`` overrides of one case (``R = 1``, the other keys at the scene defaults).

    Parameters
    ----------
    phi_hat, h_over_R : float
        Base angle and relative thickness.
    N : int
        Nodes on the meridian.
    steps : int
        The continuation step is capped at ``1 / steps`` of the eversion depth (smooth curves).

    Returns
    -------
    list of str
        ``section.key=value`` strings for :func:`contin.app.scene.load_scene`.
    """
    ds = eversion_displacement(1.0, phi_hat) / steps
    return [f"shell.phi_hat={phi_hat!r}", f"shell.h={h_over_R!r}", f"shell.N={N}", "shell.R=1.0",
            f"continuation.ds={ds!r}", f"continuation.ds_max={ds!r}", "output.figure=false"]


def case_scene(phi_hat: float, h_over_R: float, N: int, steps: int = STEPS_FULL) -> dict[str, dict[str, Any]]:
    """The resolved shell scene of one case (see :func:`case_overrides`)."""
    return load_scene(SHELL_SCHEMA, None, case_overrides(phi_hat, h_over_R, N, steps))


def _stability_pieces(br: contin.Branch) -> list[tuple[np.ndarray, np.ndarray, bool | None]]:
    """``w/R`` and ``F_norm`` of a path drawn smooth, in runs of equal displacement stability that change at
    the located special points (:func:`contin.plot.branches.stability_pieces`)."""
    return stability_pieces(br.observables["w_over_R"], br.observables["F_norm"], br.tangent("w_over_R"),
                            br.tangent("F_norm"), br.s, br.stable_under("displacement"),
                            [sp.s for sp in br.special_points if sp.located])


def _smooth(br: contin.Branch) -> tuple[np.ndarray, np.ndarray]:
    """``w/R`` and ``F_norm`` of a branch, smooth between its stored points (their tangents)."""
    return smooth_path(br.observables["w_over_R"], br.observables["F_norm"], br.tangent("w_over_R"),
                       br.tangent("F_norm"), br.s)


def trace_case(phi_hat: float, h_over_R: float, N: int, steps: int = STEPS_FULL
               ) -> tuple[dict[str, Any], TraceResult]:
    """Trace the displacement-controlled path of one case with the shell scene's runner.

    Parameters
    ----------
    phi_hat, h_over_R, N, steps
        The case, as in :func:`case_overrides`.

    Returns
    -------
    record : dict
        The class of this run and the quantities that decide it (normalized), the path's size and
        status, the run's wall time and the scene overrides.
    trace : TraceResult
        The run itself (its first branch is the path).
    """
    over = case_overrides(phi_hat, h_over_R, N, steps)
    t0 = time.perf_counter()
    trace = SHELL_SCENE.runner(load_scene(SHELL_SCHEMA, None, over), False)
    dt = time.perf_counter() - t0
    s = trace.summary
    br = trace.branches[0]
    rec = {"phi_hat": phi_hat, "h_over_R": h_over_R, "N": N, "lambda": float(shell_lambda(phi_hat, h_over_R)),
           "classification": s.get("classification"), "F_max_norm": s.get("F_max_norm"),
           "w_at_F_max_over_R": s.get("w_at_F_max_over_R"), "F_min_norm": s.get("F_min_norm"),
           "w_at_F_min_over_R": s.get("w_at_F_min_over_R"), "n_folds_in_w": s.get("n_folds_in_w"),
           "n_limit_points_in_F": s.get("n_limit_points_in_F"),
           "F_negative_on_stable_path": s.get("F_negative_on_stable_path"),
           "w_c_one_sided_over_R": s.get("w_c_one_sided_over_R"), "path_status": br.status, "path_points": len(br),
           "eversion_w_over_R": eversion_displacement(1.0, phi_hat), "wall_time_s": dt, "scene_overrides": over}
    return rec, trace


def _curve_rows(case: str, rec: dict[str, Any], br: contin.Branch) -> list[dict[str, Any]]:
    stab_d = br.stable_under("displacement")
    stab_f = br.stable_under("force")
    nneg = br.stability_by["displacement"][0]
    return [{"case": case, "phi_hat": rec["phi_hat"], "h_over_R": rec["h_over_R"], "class": rec["classification"],
             "w_over_R": float(br.observables["w_over_R"][i]), "F_norm": float(br.observables["F_norm"][i]),
             "stable": int(stab_d[i]), "stable_force": int(stab_f[i]), "n_negative": int(nneg[i])}
            for i in range(len(br))]


# ---------------------------------------------------------------------------------------------------
# figure 4: quasi-static loading and unloading
# ---------------------------------------------------------------------------------------------------
def _obs(problem: ShellPointLoad, u: np.ndarray, p: float) -> dict[str, float]:
    o = problem.evaluate_observables(u, p)
    return {"w_over_R": float(o["w_over_R"]), "F_norm": float(o["F_norm"])}


def _snap_records(problem: ShellPointLoad, sweep: contin.QuasiStaticResult) -> list[dict[str, Any]]:
    out = []
    for jr in sweep.jumps:
        a, b = _obs(problem, jr.u_from, jr.p), _obs(problem, jr.u_to, jr.p)
        out.append({"parameter": problem.parameter_name, "w_over_R_from": a["w_over_R"], "F_norm_from": a["F_norm"],
                    "w_over_R_to": b["w_over_R"], "F_norm_to": b["F_norm"],
                    "energy_released_norm": (jr.energy_from - jr.energy_to) / (2.0 * math.pi * problem.D)})
    return out


def _sweep_curve(sweep: contin.QuasiStaticResult) -> tuple[np.ndarray, np.ndarray]:
    return sweep.observable("w_over_R"), sweep.observable("F_norm")


def _loop(problem: ShellPointLoad, sweeps: Sequence[contin.QuasiStaticResult], control: str) -> dict[str, Any]:
    """Hysteresis of a closed set of sweeps: cycles of their diagram, the loop's area and released energy."""
    branches = [br for s in sweeps for br in s.branches]
    jumps = [j for s in sweeps for j in s.jumps]
    cycles = contin.hysteresis_cycles(contin.diagram(branches, jumps))
    # the area enclosed: oint F dw under displacement control (the snaps are at fixed w), -oint w dF under
    # force control (the snaps are at fixed F); both in units of 2 pi D (F_norm times w/R)
    area = 0.0
    for s in sweeps:
        w, F = _sweep_curve(s)
        area += float(np.trapezoid(F, w)) if control == "displacement" else -float(np.trapezoid(w, F))
    released = sum(j.energy_from - j.energy_to for j in jumps) / (2.0 * math.pi * problem.D)
    return {"n_cycles": len(cycles), "hysteresis": bool(cycles), "loop_area_norm": area if jumps else 0.0,
            "energy_released_norm": released}


def hysteresis_case(phi_hat: float, h_over_R: float, N: int, F_max: float | None, F_min: float | None,
                    steps: int = STEPS_FULL) -> dict[str, Any]:
    """Quasi-static loading and unloading of one cap under displacement and under force control.

    Parameters
    ----------
    phi_hat, h_over_R : float
        The cap.
    N : int
        Nodes on the meridian.
    F_max, F_min : float or None
        First maximum and last minimum of F on the displacement-controlled path (raw, not
        normalized); they set the targets of the force-controlled sweeps (None: no extremum; the
        force sweeps then go to twice the load at ``w`` = eversion depth and back).
    steps : int
        Continuation steps per eversion depth (:func:`case_overrides`).

    Returns
    -------
    dict
        ``"displacement"`` and ``"force"``: the sweeps (``sweeps``, a list of ``(name,
        QuasiStaticResult)``), the problem, their snaps, the loop record (:func:`_loop`) and the
        targets; ``"shapes"``: numbered states of the displacement sweeps for the configuration panel.
    """
    scene = case_scene(phi_hat, h_over_R, N, steps)
    R = 1.0
    w_end = eversion_displacement(R, phi_hat) * (1.0 + scene["continuation"]["overshoot"])
    out: dict[str, Any] = {}
    # ---- displacement control: load to past eversion and back
    P = point_problem(scene, "displacement")
    st = point_settings(scene, P)
    load = contin.quasistatic(P, P.reference_unknowns(), 0.0, w_end, st)
    unload = contin.quasistatic(P, load.u_final, load.p_final, 0.0, st)
    sweeps = [("loading", load), ("unloading", unload)]
    out["displacement"] = {"problem": P, "sweeps": sweeps, "targets": {"w_end_over_R": w_end / R},
                           "status": [s.status for _, s in sweeps], "messages": [s.message for _, s in sweeps]}
    # ---- force control
    Pf = point_problem(scene, "force")
    stf = point_settings(scene, Pf)
    F_unit = 2.0 * math.pi * Pf.D / R
    if F_max is None:
        F_end = 2.0 * float(np.interp(w_end, load.observable("w"), load.observable("F")))
    else:
        F_end = FORCE_MARGIN * F_max
    fload = contin.quasistatic(Pf, Pf.reference_unknowns(), 0.0, F_end, stf)
    fsweeps = [("loading", fload)]
    if F_min is not None and F_min < 0:
        F_low = FORCE_MARGIN * F_min
        funload = contin.quasistatic(Pf, fload.u_final, fload.p_final, F_low, stf)
        back = contin.quasistatic(Pf, funload.u_final, funload.p_final, 0.0, stf)
        fsweeps += [("unloading", funload), ("back to F = 0", back)]
    else:
        F_low = 0.0
        funload = contin.quasistatic(Pf, fload.u_final, fload.p_final, 0.0, stf)
        fsweeps += [("unloading", funload)]
    out["force"] = {"problem": Pf, "sweeps": fsweeps,
                    "targets": {"F_end_norm": F_end / F_unit, "F_low_norm": F_low / F_unit},
                    "status": [s.status for _, s in fsweeps], "messages": [s.message for _, s in fsweeps]}
    for ctl in ("displacement", "force"):
        d = out[ctl]
        d["loop"] = _loop(d["problem"], [s for _, s in d["sweeps"]], ctl)
        d["snaps"] = {name: _snap_records(d["problem"], s) for name, s in d["sweeps"]}
    # ---- shapes along the displacement sweeps: the jumps' ends and a few points of the loading sweep
    shapes: list[tuple[str, np.ndarray, float, dict[str, float]]] = []

    def add(label: str, u: np.ndarray, p: float) -> None:
        shapes.append((label, P.full_state(u, p), p, _obs(P, u, p)))

    ws = load.observable("w")
    us = np.concatenate([br.u for br in load.branches])
    add("reference", P.reference_unknowns(), 0.0)
    if not load.jumps:
        for frac in (0.35, 0.7):
            k = int(np.argmin(np.abs(ws - frac * w_end)))
            add("loading", us[k], float(ws[k]))
    for jr in load.jumps:
        add("loading: before snap", jr.u_from, jr.p)
        add("loading: after snap", jr.u_to, jr.p)
    add("end of loading", load.u_final, load.p_final)
    for jr in unload.jumps:
        add("unloading: before snap", jr.u_from, jr.p)
        add("unloading: after snap", jr.u_to, jr.p)
    out["shapes"] = shapes
    return out


# ---------------------------------------------------------------------------------------------------
# statements of the paper (docs/model.md#what-the-paper-reports)
# ---------------------------------------------------------------------------------------------------
def _boundary_estimate(recs: list[dict[str, Any]], key: str) -> float | None:
    """Where F_min crosses zero between the last bistable and the first monostable case (linear in ``key``)."""
    for a, b in zip(recs, recs[1:]):
        if a["classification"] == "bistable" and b["classification"] == "monostable":
            fa, fb = a["F_min_norm"], b["F_min_norm"]
            if fa is not None and fb is not None and fa < 0 < fb:
                return a[key] + (b[key] - a[key]) * (-fa) / (fb - fa)
    return None


def check_statements(fig3a: list[dict[str, Any]], fig3b: list[dict[str, Any]], fig4: dict[str, Any]
                     ) -> dict[str, Any]:
    """The paper's statements on figures 3 and 4, each with the numbers that decide it.

    Parameters
    ----------
    fig3a, fig3b : list of dict
        Case records (:func:`trace_case`) in increasing ``phi_hat`` and increasing ``h/R``.
    fig4 : dict
        Per cap (key ``"phi_hat=..."``) the summary of :func:`hysteresis_case`.

    Returns
    -------
    dict
        One entry per statement: ``paper`` (the statement), the deciding numbers, ``reproduced``.
    """
    out: dict[str, Any] = {}
    # 1. h/R = 0.02: bistable below 1.1, monostable above, monotonous at 1.3
    cls = {r["phi_hat"]: r["classification"] for r in fig3a}
    below = [p for p in cls if p < 1.1 - 1e-9]
    above = [p for p in cls if 1.1 + 1e-9 < p < 1.3 - 1e-9]
    at_11 = next((r for r in fig3a if abs(r["phi_hat"] - 1.1) < 1e-9), None)
    ok1 = all(cls[p] == "bistable" for p in below) and all(cls[p] == "monostable" for p in above)
    ok1 = ok1 and cls.get(1.3) == "monotonous" and bool(below) and bool(above)
    out["h0.02_phi_sweep"] = {
        "paper": "h/R = 0.02: bistable for phi_hat < 1.1, monostable above, monotonous at phi_hat = 1.3",
        "classes": {f"{p:g}": c for p, c in cls.items()},
        "F_min_norm": {f"{r['phi_hat']:g}": r["F_min_norm"] for r in fig3a},
        "bistable_below_1.1": all(cls[p] == "bistable" for p in below),
        "monostable_between_1.1_and_1.3": all(cls[p] == "monostable" for p in above),
        "monotonous_at_1.3": cls.get(1.3) == "monotonous",
        "at_phi_hat_1.1": None if at_11 is None else {"class": at_11["classification"],
                                                      "F_min_norm": at_11["F_min_norm"]},
        "bistable_monostable_boundary_phi_hat_estimate": _boundary_estimate(fig3a, "phi_hat"),
        "boundary_note": "linear interpolation of F_min_norm between the grid's last bistable and first "
                         "monostable case (the phase-diagram study locates it precisely)",
        "reproduced": ok1,
    }
    # 2. phi_hat = 1.0: h/R from 0.01 to 0.08 goes bistable -> monostable -> monotonous
    seq = [r["classification"] for r in fig3b]
    ranks = [_RANK.get(c, -1) for c in seq]
    ok2 = all(r >= 0 for r in ranks) and ranks == sorted(ranks) and set(seq) == set(_RANK)

    def last(c: str) -> float | None:
        hs = [r["h_over_R"] for r in fig3b if r["classification"] == c]
        return max(hs) if hs else None

    def first(c: str) -> float | None:
        hs = [r["h_over_R"] for r in fig3b if r["classification"] == c]
        return min(hs) if hs else None
    out["phi1.0_h_sweep"] = {
        "paper": "phi_hat = 1.0: h/R from 0.01 to 0.08 goes bistable -> monostable -> monotonous",
        "classes": {f"{r['h_over_R']:g}": r["classification"] for r in fig3b},
        "F_min_norm": {f"{r['h_over_R']:g}": r["F_min_norm"] for r in fig3b},
        "last_bistable_h_over_R": last("bistable"), "first_monostable_h_over_R": first("monostable"),
        "last_monostable_h_over_R": last("monostable"), "first_monotonous_h_over_R": first("monotonous"),
        "bistable_monostable_boundary_h_over_R_estimate": _boundary_estimate(fig3b, "h_over_R"),
        "reproduced": ok2,
    }
    # 3. hysteresis for 0.8, none for 1.2
    k08, k12 = "phi_hat=0.8", "phi_hat=1.2"
    if k08 in fig4 and k12 in fig4:
        d08, d12 = fig4[k08]["displacement_control"], fig4[k12]["displacement_control"]
        f08, f12 = fig4[k08]["force_control"], fig4[k12]["force_control"]
        ok_d = d08["hysteresis"] and not d12["hysteresis"]
        out["hysteresis_0.8_not_1.2"] = {
            "paper": "phi_hat = 0.8 loading and unloading curves show hysteresis; phi_hat = 1.2 does not (figure 4)",
            "displacement_control": {"phi_hat=0.8": d08["hysteresis"], "phi_hat=1.2": d12["hysteresis"],
                                     "loop_width_w_over_R_0.8": d08["loop_width_w_over_R"],
                                     "loop_area_norm_0.8": d08["loop_area_norm"]},
            "force_control": {"phi_hat=0.8": f08["hysteresis"], "phi_hat=1.2": f12["hysteresis"],
                              "loop_width_F_norm_0.8": f08["loop_width_F_norm"],
                              "loop_width_F_norm_1.2": f12["loop_width_F_norm"]},
            "reproduced_under_displacement_control": ok_d,
            "reproduced_under_force_control": f08["hysteresis"] and not f12["hysteresis"],
            "reproduced": ok_d,
            "note": ("the paper moves the pole (displacement control; section 4a), under which the monostable "
                     "cap 1.2 has no fold in w and its loading and unloading curves coincide. Under a dead load "
                     "(force control) every cap with a maximum of F snaps: the monostable cap 1.2 snaps at F_max "
                     "and back at F_min > 0, a loop too, while the bistable cap 0.8 snaps back only when pulled "
                     "past F_min < 0."),
        }
    return out


# ---------------------------------------------------------------------------------------------------
# figures
# ---------------------------------------------------------------------------------------------------
#: Symbols of the swept quantities of figure 3 (mathtext), by record key.
_SYMBOL = {"phi_hat": r"\hat\phi", "h_over_R": "h/R"}
F_LABEL, W_LABEL = r"$F R / 2\pi D$", r"$w/R$"
#: The first maximum and last minimum of F: filled triangles in the curve's colour, a black edge so that
#: one on top of another curve or of a neighbouring mark still shows, drawn above every curve.
_EXTREMUM = {"ms": 5.5, "mec": "k", "mew": 0.6, "ls": "none", "zorder": 5}


def _plot_fig3_panel(ax: Any, runs: list[tuple[str, dict[str, Any], TraceResult]], title: str, key: str) -> None:
    from matplotlib.lines import Line2D

    cmap = plt.get_cmap("viridis")
    case_handles, has_max, has_min = [], False, False
    for k, (_, rec, trace) in enumerate(runs):
        color = cmap(k / max(1, len(runs) - 1) * 0.9)
        for x, y, ok in _stability_pieces(trace.branches[0]):
            if ok:
                ax.plot(x, y, color=color, zorder=2, **style.STABLE)
            else:
                # thinner and faded: the unstable loops of the thin caps would otherwise bury the stable parts
                ax.plot(x, y, color=color, ls=style.UNSTABLE["ls"], lw=0.7, alpha=0.5, zorder=1)
        case_handles.append(Line2D([], [], color=color, **style.STABLE,
                                   label=f"${_SYMBOL[key]} = {rec[key]:g}$: {rec['classification'] or 'undecided'}"))
        if rec["F_max_norm"] is not None:
            ax.plot(rec["w_at_F_max_over_R"], rec["F_max_norm"], "^", mfc=color, **_EXTREMUM)
            has_max = True
        if rec["F_min_norm"] is not None:
            ax.plot(rec["w_at_F_min_over_R"], rec["F_min_norm"], "v", mfc=color, **_EXTREMUM)
            has_min = True
    ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
    extra = [Line2D([], [], color="0.15", **style.STABLE, label="stable (displacement control)"),
             Line2D([], [], color="0.15", ls=style.UNSTABLE["ls"], lw=0.7, alpha=0.5, label="unstable")]
    if has_max:
        extra.append(Line2D([], [], marker="^", mfc="0.6", **_EXTREMUM, label=r"first maximum of $F$"))
    if has_min:
        extra.append(Line2D([], [], marker="v", mfc="0.6", **_EXTREMUM, label=r"last minimum of $F$"))
    ax.set_xlabel(W_LABEL)
    ax.set_ylabel(F_LABEL)
    ax.set_title(title, fontsize="medium")
    # beside the axes: the curves fill the whole panel (the style's legend size, readable at page width)
    ax.legend(handles=case_handles + extra, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)


def plot_fig3(runs_a: list, runs_b: list, N: int) -> Any:
    """Figure 3: (a) the phi_hat sweep at h/R = 0.02 above (b) the h/R sweep at phi_hat = 1.0 (a page wide)."""
    fig, axes = plt.subplots(2, 1, figsize=(style.WIDTH, 7.4), layout="constrained")
    _plot_fig3_panel(axes[0], runs_a, f"(a) $h/R = {H_3A:g}$, $N = {N}$", "phi_hat")
    _plot_fig3_panel(axes[1], runs_b, rf"(b) $\hat\phi = {PHI_3B:g}$, $N = {N}$", "h_over_R")
    fig.suptitle("Point indentation, displacement-controlled path (class of each run in the legend)",
                 fontsize="medium")
    return fig


def plot_fig4(cases: dict[float, dict[str, Any]], paths: dict[float, TraceResult], N: int) -> Any:
    """Figure 4: loading/unloading under both controls (rows 1, 2) and the shapes (row 3), a column per cap.

    A page wide: the curves' legend is the figure's (above the panels), each column's shapes have theirs
    below them; the columns share one grid, so that their rows line up.
    """
    from matplotlib.lines import Line2D

    fig = plt.figure(figsize=(style.WIDTH, 8.4), layout="constrained")
    # the figure's legend belongs to a subfigure holding the panels: a figure's own "outside" legend would
    # lie on its suptitle
    body = fig.subfigures(1, 1)
    axes = body.subplots(3, len(cases), squeeze=False, height_ratios=(1.0, 1.0, 0.72))
    # "back to F = 0" dash-dotted: dotted is the snaps' style
    styles = {"loading": ("-", "tab:red"), "unloading": ("--", "tab:blue"), "back to F = 0": ("-.", "tab:green")}
    names = {"back to F = 0": "back to $F = 0$"}
    # the legend of rows 1 and 2, one for the figure: every curve style of any panel, then every snap style
    curve_handles: dict[str, Any] = {}
    snap_handles: dict[str, Any] = {}
    for col, (phi, case) in enumerate(cases.items()):
        tag = "ab"[col] if col < 2 else str(col)
        for row, ctl in enumerate(("displacement", "force")):
            ax = axes[row, col]
            ax.plot(*_smooth(paths[phi].branches[0]), "-", color="0.8", lw=3,
                    label="whole path (displacement control)", zorder=0)
            d = case[ctl]
            snaps = []
            for name, sw in d["sweeps"]:
                ls, color = styles.get(name, ("-", "k"))
                for b in sw.branches:
                    if len(b):
                        ax.plot(*_smooth(b), ls, color=color, lw=1.5)
                ax.plot([], [], ls, color=color, label=names.get(name, name))
                for jr in sw.jumps:
                    a, z = _obs(d["problem"], jr.u_from, jr.p), _obs(d["problem"], jr.u_to, jr.p)
                    ax.annotate("", xy=(z["w_over_R"], z["F_norm"]), xytext=(a["w_over_R"], a["F_norm"]),
                                arrowprops={"arrowstyle": "->", "ls": ":", "color": color, "lw": 1.3})
                if sw.jumps:
                    snaps.append((name, color))
            # the snap arrows take their sweep's colour: one entry per sweep that snaps, none without a snap
            handles, labels = ax.get_legend_handles_labels()
            for h, lab in zip(handles, labels):
                curve_handles.setdefault(lab, h)
            for name, color in snaps:
                label = f"snap on {names.get(name, name)}"
                snap_handles.setdefault(label, Line2D([], [], ls=":", color=color, lw=1.3, label=label))
            if ctl == "displacement":
                for k, (_, _, _, o) in enumerate(case["shapes"]):
                    ax.plot(o["w_over_R"], o["F_norm"], "o", color=f"C{k}", ms=6, mec="k", zorder=5)
            lp = d["loop"]
            ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
            # the column's cap heads its first panel
            head = rf"({tag}) $\hat\phi = {phi:g}$" + "\n" if row == 0 else ""
            ax.set_title(f"{head}({tag}{row + 1}) {ctl} control: {'hysteresis' if lp['hysteresis'] else 'no hysteresis'}",
                         fontsize="medium")
            ax.set_xlabel(W_LABEL)
            ax.set_ylabel(F_LABEL)
        ax = axes[2, col]
        for k, (label, x, _, o) in enumerate(case["shapes"]):
            r, z = x[0::2], x[1::2]
            # the meridian runs from the base (node 0) to the pole: mirror it about the axis
            ax.plot(np.concatenate([-r, r[::-1]]), np.concatenate([z, z[::-1]]), "-", color=f"C{k}", lw=1.2,
                    label=f"{k + 1}: {label} ($w/R = {o['w_over_R']:.3f}$)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(r"$r/R$")
        ax.set_ylabel(r"$z/R$")
        ax.set_title(f"({tag}3) meridian at the numbered points", fontsize="medium")
        # below the panel (placed under its axis label once the layout is known): the labels are too long
        # for the narrow panel
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=1, handlelength=2.0)
    body.legend(handles=[*curve_handles.values(), *snap_handles.values()], loc="outside upper center", ncol=3,
               handlelength=2.4)
    fig.suptitle(f"Loading and unloading, $h/R = {H_4:g}$, $N = {N}$", fontsize="medium")
    # the shapes' legends just under their axis labels, then the numbers where the curves are not: both are
    # known once the layout has fixed the axes; lay the figure out again with the legends moved and keep it
    fig.draw_without_rendering()
    for ax in axes[2]:
        label = ax.xaxis.label.get_window_extent()
        y = ax.transAxes.inverted().transform((0.0, label.y0))[1]
        ax.get_legend().set_bbox_to_anchor((0.5, y - 0.02), transform=ax.transAxes)
    fig.draw_without_rendering()
    fig.set_layout_engine("none")
    for col, case in enumerate(cases.values()):
        ax = axes[0, col]
        placed: list[np.ndarray] = []
        for k, (_, _, _, o) in enumerate(case["shapes"]):
            xy = (o["w_over_R"], o["F_norm"])
            best, place = clearest_offset(ax, xy, _OFFSETS, placed)
            ax.annotate(str(k + 1), xy, textcoords="offset points", xytext=_OFFSETS[best], fontsize="small",
                        ha="center", va="center")
            placed.append(place)
    return fig


#: Where a point's number may go, in points from the point (its centre).
_OFFSETS = ((8, 8), (8, -8), (-8, 8), (-8, -8), (10, 0), (-10, 0), (0, 10), (0, -10))


# ---------------------------------------------------------------------------------------------------
# main
# ---------------------------------------------------------------------------------------------------
def _fig4_summary(phi: float, rec: dict[str, Any], case: dict[str, Any]) -> dict[str, Any]:
    d, f = case["displacement"], case["force"]
    dl, du = d["snaps"]["loading"], d["snaps"]["unloading"]
    fl = f["snaps"]["loading"]
    fu = f["snaps"]["unloading"]
    disp = {"status": d["status"], "targets": d["targets"], "snaps": d["snaps"], **d["loop"],
            "snap_loading_w_over_R": dl[0]["w_over_R_from"] if dl else None,
            "snap_unloading_w_over_R": du[0]["w_over_R_from"] if du else None,
            "loop_width_w_over_R": (dl[0]["w_over_R_from"] - du[0]["w_over_R_from"]) if dl and du else None}
    force = {"status": f["status"], "targets": f["targets"], "snaps": f["snaps"], **f["loop"],
             "snap_loading_F_norm": fl[0]["F_norm_from"] if fl else None,
             "snap_unloading_F_norm": fu[0]["F_norm_from"] if fu else None,
             "loop_width_F_norm": (fl[0]["F_norm_from"] - fu[0]["F_norm_from"]) if fl and fu else None}
    return {"phi_hat": phi, "h_over_R": H_4, "classification": rec["classification"],
            "F_max_norm": rec["F_max_norm"], "F_min_norm": rec["F_min_norm"],
            "w_at_F_max_over_R": rec["w_at_F_max_over_R"], "w_at_F_min_over_R": rec["w_at_F_min_over_R"],
            "scene_overrides": rec["scene_overrides"], "displacement_control": disp, "force_control": force}


def run(full: bool = False, quiet: bool = True) -> dict[str, Any]:
    """Compute everything of the study (no files written).

    Parameters
    ----------
    full : bool
        The paper's resolution (N = 200) instead of the fast coarse mesh (N = 60).
    quiet : bool
        No progress lines on stderr.

    Returns
    -------
    dict
        ``N``, ``steps_per_eversion``, ``fig3a``/``fig3b`` (lists of ``(label, record, trace)``), ``fig4`` (per phi_hat the
        :func:`hysteresis_case` output), ``fig4_summary``, ``statements``, ``paths`` (trace per
        figure-4 cap).
    """
    N, steps = (N_FULL, STEPS_FULL) if full else (N_FAST, STEPS_FAST)
    traces: dict[tuple[float, float], tuple[dict[str, Any], TraceResult]] = {}

    def get(phi: float, h: float) -> tuple[dict[str, Any], TraceResult]:
        if (phi, h) not in traces:
            traces[(phi, h)] = trace_case(phi, h, N, steps)
            rec = traces[(phi, h)][0]
            say(quiet, f"  phi_hat = {phi:g}, h/R = {h:g}: {rec['classification']} "
                       f"({rec['path_points']} points, {rec['wall_time_s']:.2f} s)")
        return traces[(phi, h)]

    say(quiet, f"figure 3 (N = {N})")
    fig3a = [(f"phi_hat = {p:g}", *get(p, H_3A)) for p in PHI_3A]
    fig3b = [(f"h/R = {h:g}", *get(PHI_3B, h)) for h in H_3B]
    say(quiet, "figure 4")
    fig4: dict[float, dict[str, Any]] = {}
    fig4_summary: dict[str, Any] = {}
    paths: dict[float, TraceResult] = {}
    for phi in PHI_4:
        rec, trace = get(phi, H_4)
        paths[phi] = trace
        F_unit = trace.summary["F_unit"]
        F_max = None if rec["F_max_norm"] is None else rec["F_max_norm"] * F_unit
        F_min = None if rec["F_min_norm"] is None else rec["F_min_norm"] * F_unit
        t0 = time.perf_counter()
        fig4[phi] = hysteresis_case(phi, H_4, N, F_max, F_min, steps)
        fig4_summary[f"phi_hat={phi:g}"] = _fig4_summary(phi, rec, fig4[phi])
        say(quiet, f"  phi_hat = {phi:g}: sweeps {time.perf_counter() - t0:.2f} s")
    statements = check_statements([r for _, r, _ in fig3a], [r for _, r, _ in fig3b], fig4_summary)
    return {"N": N, "steps_per_eversion": steps, "fig3a": fig3a, "fig3b": fig3b, "fig4": fig4, "fig4_summary": fig4_summary,
            "statements": statements, "paths": paths}


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m studies.force_displacement [--out DIR] [--full] [--quiet]``.

    Runs the study and writes its figures, CSV files and ``summary.json`` (see the module docstring);
    returns 0 when every run finished and every statement was decided, 1 otherwise.
    """
    args = study_parser(NAME, "Force-displacement curves and hysteresis of the point-indented cap "
                              "(paper figures 3 and 4)").parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    res = run(args.full, args.quiet)
    N = res["N"]

    rows3 = []
    for fig, runs in (("3a", res["fig3a"]), ("3b", res["fig3b"])):
        for label, rec, trace in runs:
            rows3 += [{"figure": fig, **r} for r in _curve_rows(label, rec, trace.branches[0])]
    write_csv(out / "fig3.csv", rows3, ["figure", "case", "phi_hat", "h_over_R", "class", "w_over_R", "F_norm",
                                         "stable", "stable_force", "n_negative"])
    rows4 = []
    for phi, case in res["fig4"].items():
        for ctl in ("displacement", "force"):
            for name, sw in case[ctl]["sweeps"]:
                for bi, br in enumerate(sw.branches):
                    stab = br.stable_under(ctl)
                    for i in range(len(br)):
                        rows4.append({"case": f"phi_hat = {phi:g}", "phi_hat": phi, "control": ctl, "sweep": name,
                                      "branch": bi, "w_over_R": float(br.observables["w_over_R"][i]),
                                      "F_norm": float(br.observables["F_norm"][i]), "stable": int(stab[i])})
    write_csv(out / "fig4.csv", rows4, ["case", "phi_hat", "control", "sweep", "branch", "w_over_R", "F_norm",
                                         "stable"])
    shape_rows = []
    for phi, case in res["fig4"].items():
        for k, (label, x, _, o) in enumerate(case["shapes"]):
            shape_rows += [{"phi_hat": phi, "point": k + 1, "label": label, "w_over_R_point": o["w_over_R"],
                            "F_norm_point": o["F_norm"], "node": i, "r_over_R": float(x[2 * i]),
                            "z_over_R": float(x[2 * i + 1])} for i in range(len(x) // 2)]
    write_csv(out / "fig4_shapes.csv", shape_rows)
    save_figure(plot_fig3(res["fig3a"], res["fig3b"], N), out, "fig3")
    save_figure(plot_fig4(res["fig4"], res["paths"], N), out, "fig4")

    all_ok = all(rec["path_status"] == "bound" and rec["classification"] is not None
                 for runs in (res["fig3a"], res["fig3b"]) for _, rec, _ in runs)
    all_ok = all_ok and all(st == "completed" for c in res["fig4"].values() for ctl in ("displacement", "force")
                            for st in c[ctl]["status"])
    wall = time.perf_counter() - t0
    summary = {
        "study": NAME, "command": f"python -m studies.{NAME}" + (" --full" if args.full else ""),
        "mode": "full" if args.full else "fast", "N": N, "steps_per_eversion": res["steps_per_eversion"], "R": 1.0, "E": 1e6, "nu": 0.5,
        "force_unit": "F_norm = F R / (2 pi D)", "loop_area_unit": "2 pi D (oint F_norm d(w/R))",
        "fig3a": {"h_over_R": H_3A, "cases": [dict(r) for _, r, _ in res["fig3a"]]},
        "fig3b": {"phi_hat": PHI_3B, "cases": [dict(r) for _, r, _ in res["fig3b"]]},
        "fig4": res["fig4_summary"],
        "statements": res["statements"],
        "all_runs_ok": all_ok, "wall_time_s": wall,
    }
    write_json(out / "summary.json", summary)

    print(f"force-displacement study ({summary['mode']}, N = {N}), {wall:.1f} s; files in {out}")
    rows = [{"fig": fig, "phi_hat": r["phi_hat"], "h/R": r["h_over_R"], "lambda": r["lambda"],
             "class": r["classification"], "F_max_norm": r["F_max_norm"], "F_min_norm": r["F_min_norm"],
             "folds_in_w": r["n_folds_in_w"]}
            for fig, runs in (("3a", res["fig3a"]), ("3b", res["fig3b"])) for _, r, _ in runs]
    print_table(rows, ["fig", "phi_hat", "h/R", "lambda", "class", "F_max_norm", "F_min_norm", "folds_in_w"],
                digits=5)
    print()
    rows = []
    for key, s in res["fig4_summary"].items():
        d, f = s["displacement_control"], s["force_control"]
        rows.append({"cap": key, "control": "displacement", "snap_load": d["snap_loading_w_over_R"],
                     "snap_unload": d["snap_unloading_w_over_R"], "at": "w/R",
                     "hysteresis": "yes" if d["hysteresis"] else "no", "width": d["loop_width_w_over_R"],
                     "area_norm": d["loop_area_norm"]})
        rows.append({"cap": key, "control": "force", "snap_load": f["snap_loading_F_norm"],
                     "snap_unload": f["snap_unloading_F_norm"], "at": "F_norm",
                     "hysteresis": "yes" if f["hysteresis"] else "no", "width": f["loop_width_F_norm"],
                     "area_norm": f["loop_area_norm"]})
    print_table(rows, ["cap", "control", "at", "snap_load", "snap_unload", "hysteresis", "width", "area_norm"],
                digits=5)
    print()
    for key, st in res["statements"].items():
        print(f"{key}: {'reproduced' if st['reproduced'] else 'NOT reproduced'} -- {st['paper']}")
    return 0 if all_ok else 1


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
