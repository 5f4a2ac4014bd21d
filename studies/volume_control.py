"""Study (e) of issue 16: a clamped cap under volume control against pressure control.

Run ``python -m studies.volume_control [--out DIR] [--full]``.

A clamped shallow cap (``R/h = 400``, ``nu = 0.3``; ``lambda = 7`` and, for contrast, ``lambda = 5``;
:class:`contin_models.shell.ShellPressure`) is traced twice from the unloaded state:

* under **pressure control** (the pressure ``p`` prescribed, :func:`contin.continuation` on the cap),
  past its first limit point in ``p`` (until the pole has moved ``W_PAST`` thicknesses);
* under **volume control** (the volume change ``dV = V0 - V`` prescribed and ``p`` its Lagrange
  multiplier: :class:`contin.analyses.conjugate.ConjugateControl` through
  :func:`contin_models.shell_scene.pressure.volume_problem`, the construction ``contin trace`` uses for
  ``load.kind = pressure``) until the cap is everted (``dV = 2 V0``) or the pole has moved past eversion.

Both controls have the same equilibria; what differs is where each path can be followed and which
states are stable.  The study reports

* the snaps each control sees: the limit point ``p_max`` of the pressure-controlled path (where a
  prescribed pressure jumps: its landing is found by :func:`contin.jump`, energy minimisation at
  fixed ``p``) and the folds in ``dV`` of the volume-controlled path (where a prescribed volume
  snaps; the stable state at the same ``dV`` on the traced path is reported as its landing);
* the agreement of the multiplier ``p`` with the pressure-controlled branch: every stored point of
  the pressure-controlled branch is located on the volume-controlled one as a crossing event of its
  ``dV`` (not interpolated) and the pressures compared;
* the stability labels along the volume-controlled path under both controls (``"volume"``: the
  Hessian restricted to the volume constraint's tangent, the bordered count minus one;
  ``"pressure"``: the Hessian's own count).

With every mode watched (issue 17, study (c), :func:`every_mode`, ``every_mode.csv``): the first
instability of each cap under each control, through the scene runner with ``stability.harmonics``.

Units: ``h = 1``, ``R = R/h``, and ``E`` such that ``p_c = 1`` (as :mod:`studies.classical`).  Mesh
``N = 100`` (``--full``: 200 and 400 as well, for the mesh convergence of the snap points).

A scan over ``lambda`` (:data:`SCAN`, N = 100) gives, from one volume-controlled trace per cap, the
first limit point in ``p`` and the first fold in ``dV``: which caps snap under a prescribed volume.

Writes ``special_points.csv`` (every limit point and fold with its stability under both controls),
``paths.csv`` (both paths of every cap), ``scan.csv``, ``summary.json`` and ``volume_control.png`` /
``.pdf``.
Findings: ``docs/validation.md`` section 7.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin.results.branch import Branch  # noqa: E402
from contin_models.shell.pressure import ShellPressure, phi_hat_for_lambda  # noqa: E402
from contin_models.shell_scene.pressure import VOLUME_LABELS, volume_problem  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

NU = 0.3
R_OVER_H = 400.0
#: The main cap (Budiansky's snap pressure 1.068 p_c) and a shallower one whose volume path has no fold.
LAMBDAS = (7.0, 5.0)
#: The pressure-controlled trace stops when the pole has moved this many thicknesses (past the first fold).
W_PAST = 1.5
#: The volume-controlled trace stops at this volume change over V0 (2: the mirror image, everted).
DV_END_OVER_V0 = 2.0
#: Caps scanned for the first snap of each control (volume-controlled traces only, to the first fold in dV).
SCAN = (4.0, 5.0, 5.5, 6.0, 6.5, 7.0, 8.0)
#: Largest arclength step of both traces over the eversion depth (finer than the scene's 1/20, so that the
#: figure's paths are smooth through the snaps).
STEP = 0.015
#: At most this many stored points of the pressure-controlled branch are located on the volume-controlled
#: one (evenly spread; each is a located crossing event, about 50 ms).
N_COMPARED = 24


def clamped_cap(lam: float, N: int) -> ShellPressure:
    """The clamped cap of depth parameter ``lam`` in the study's units (``h = 1``, ``p_c = 1``)."""
    R, h = R_OVER_H, 1.0
    E = math.sqrt(3.0 * (1.0 - NU * NU)) / (2.0 * (h / R) ** 2)
    return ShellPressure(R=R, E=E, nu=NU, h=h, phi_hat=phi_hat_for_lambda(lam, R, h, NU), N=N, boundary="clamped")


def depth(cap: ShellPressure) -> float:
    """The eversion depth ``2 H = 2 R (1 - sin phi_hat)``."""
    return 2.0 * cap.R * (1.0 - math.sin(cap.phi_hat))


def trace_pressure(cap: ShellPressure) -> Branch:
    """Pressure control from ``p = 0`` past the first limit point, to ``w = W_PAST h``.

    Weights as the pressure scene's (a change of ``p_c`` weighs as the eversion depth); steps :data:`STEP`.
    """
    d = depth(cap)
    st = contin.Settings(ds=0.01 * d, ds_max=STEP * d, max_steps=2000, stability=True, n_eigs=0,
                         state_weight=1.0 / cap.h, param_weight=d / (cap.h * cap.p_c))
    return contin.continuation(cap, cap.reference_unknowns(), 0.0, st, p_max=3.0 * cap.p_c,
                               bounds={"w_over_h": (None, W_PAST)})


def trace_volume(cap: ShellPressure, crossings: dict[int, float] | None = None
                 ) -> tuple[contin.analyses.conjugate.ConjugateControl, Branch]:
    """Volume control from ``dV = 0`` to ``DV_END_OVER_V0 V0`` (or the pole past eversion).

    Extrema of the multiplier are located as limit points in ``p``; ``crossings`` are volume changes
    at which the path's states are located exactly (crossing events named ``at<key>``).
    """
    problem = volume_problem(cap)
    d, V0 = depth(cap), cap.pressure.V0
    st = contin.Settings(ds=0.01 * d, ds_max=STEP * d, max_steps=3000, stability=True, n_eigs=0,
                         state_weight=1.0 / cap.h, param_weight=d / (cap.h * 2.0 * V0))
    events = [contin.extremum("p", which, folds="p", stability_label=VOLUME_LABELS[1]) for which in ("max", "min")]
    events += [contin.crossing("dV", float(v), name=f"at{i}") for i, v in (crossings or {}).items()]
    U0, q0 = problem.from_load_state(cap.reference_unknowns(), 0.0)
    br = contin.continuation(problem, U0, q0, st, p_max=DV_END_OVER_V0 * V0,
                             bounds={"w": (None, 1.05 * d)}, events=events)
    return problem, br


def _limit_points(br: Branch) -> list[Any]:
    """Folds in ``dV`` and extrema of ``p`` (limit points in p) along a volume-controlled branch, in path order."""
    return [s for s in br.special_points if s.kind == "fold" or s.info.get("folds") == "p"]


def _stability_word(spt: Any, label: str) -> str:
    entry = spt.info.get("stability", {}).get(label, {})
    word = {True: "stable", False: "unstable", None: "?"}
    return f"{word[entry.get('stable_before')]} -> {word[entry.get('stable_after')]}"


def pressure_landing(cap: ShellPressure, pressure: Branch) -> dict[str, Any]:
    """Where a prescribed pressure jumps at its limit point: :func:`contin.jump` at ``p_max``."""
    fold = next(s for s in pressure.special_points if s.kind == "fold")
    j = contin.jump(cap, fold.u, fold.p)
    obs = cap.evaluate_observables(j.u_to, j.p)
    return {"p_max_over_p_c": fold.p / cap.p_c, "w_at_p_max_over_h": fold.observables["w_over_h"],
            "dV_at_p_max_over_V0": (cap.pressure.V0 - fold.observables["V"]) / cap.pressure.V0,
            "landing_success": bool(j.success), "landing_w_over_h": obs["w_over_h"],
            "landing_dV_over_V0": (cap.pressure.V0 - obs["V"]) / cap.pressure.V0,
            "landing_energy_drop": float(j.energy_from - j.energy_to)}


def volume_landing(problem: Any, volume: Branch, spt: Any) -> dict[str, Any]:
    """The stable state (under volume control) at a fold's ``dV`` elsewhere on the traced path.

    Between stored points of the path whose ``dV`` brackets the fold's, stable at both ends, the state
    is interpolated linearly in ``dV`` (the nearest such stretch after the fold); None when there is none.
    """
    dV, stable = volume.p, volume.stable_under(VOLUME_LABELS[0])
    for i in range(spt.index + 1, len(volume) - 1):
        if stable[i] and stable[i + 1] and (dV[i] - spt.p) * (dV[i + 1] - spt.p) <= 0.0:
            t = (spt.p - dV[i]) / (dV[i + 1] - dV[i])
            p = (1 - t) * volume.observables["p"][i] + t * volume.observables["p"][i + 1]
            w = (1 - t) * volume.observables["w_over_h"][i] + t * volume.observables["w_over_h"][i + 1]
            return {"landing_p_over_p_c": p / problem.base.p_c, "landing_w_over_h": w}
    return {"landing_p_over_p_c": None, "landing_w_over_h": None}


def compared_points(pressure: Branch) -> list[int]:
    """Indices of the pressure-controlled branch's stored points compared (at most :data:`N_COMPARED`, not the start)."""
    return sorted({int(i) for i in np.linspace(1, len(pressure) - 1, min(N_COMPARED, len(pressure) - 1))})


def compare_pressure(cap: ShellPressure, pressure: Branch, volume: Branch) -> dict[str, Any]:
    """The multiplier ``p`` against the pressure-controlled branch at the same ``dV`` (and nearest ``w``)."""
    V0 = cap.pressure.V0
    located: dict[int, list[Any]] = {}
    for s in volume.special_points:
        if s.kind == "event" and s.label.startswith("at") and s.located:
            located.setdefault(int(s.label[2:]), []).append(s)
    rel, dw = [], []
    wanted = compared_points(pressure)
    for i in wanted:
        if i not in located:
            continue
        w_i = pressure.observables["w"][i]
        s = min(located[i], key=lambda s: abs(s.observables["w"] - w_i))  # the same state among the crossings
        rel.append(abs(s.observables["p"] / pressure.p[i] - 1.0))
        dw.append(abs(s.observables["w"] - w_i) / cap.h)
    return {"n_compared": len(rel), "n_wanted": len(wanted), "n_pressure_points": len(pressure) - 1,
            "max_rel_diff_p": max(rel) if rel else None, "max_diff_w_over_h": max(dw) if dw else None,
            "dV_range_over_V0": [float(np.min(V0 - pressure.observables["V"]) / V0),
                                 float(np.max(V0 - pressure.observables["V"]) / V0)]}


def run_cap(lam: float, N: int, compare: bool = True) -> dict[str, Any]:
    """Both traces of one cap and everything the study reports about them (``compare``: the multiplier too)."""
    cap = clamped_cap(lam, N)
    V0 = cap.pressure.V0
    t0 = time.perf_counter()
    pressure = trace_pressure(cap)
    t1 = time.perf_counter()
    crossings = {i: V0 - pressure.observables["V"][i] for i in compared_points(pressure)} if compare else None
    problem, volume = trace_volume(cap, crossings)
    t2 = time.perf_counter()
    points = []
    for s in _limit_points(volume):
        folds = s.info.get("folds", "dV")
        row = {"lambda": lam, "N": N, "folds_in": folds, "label": s.label,
               "dV_over_V0": s.p / V0, "p_over_p_c": s.observables["p_over_p_c"], "w_over_h": s.observables["w_over_h"],
               "volume": _stability_word(s, VOLUME_LABELS[0]), "pressure": _stability_word(s, VOLUME_LABELS[1]),
               "located": bool(s.located)}
        if folds == "dV" and s.info.get("stability", {}).get(VOLUME_LABELS[0], {}).get("stable_before"):
            row.update(volume_landing(problem, volume, s))
        points.append(row)
    folds_in_dV = [r for r in points if r["folds_in"] == "dV"]
    p_limits = [r for r in points if r["folds_in"] == "p"]
    nv, npr = volume.stability_by[VOLUME_LABELS[0]][0], volume.stability_by[VOLUME_LABELS[1]][0]
    first_max = next((r for r in p_limits if r["label"] == "max(p)"), None)
    # stretch of the path, from the start, that is stable under the prescribed volume
    unstable_v = np.flatnonzero(nv > 0)
    stable_upto = volume.p[unstable_v[0] - 1] / V0 if unstable_v.size else volume.p[-1] / V0
    landing = pressure_landing(cap, pressure)
    # cross-check of the jump: the volume-controlled path's pressure at the landing's volume, on its last
    # stretch (after the last fold in dV, where dV grows monotonically to the end)
    last = max((s.index for s in volume.special_points if s.kind == "fold"), default=0) + 1
    landing["p_on_volume_path_at_landing_over_p_c"] = float(
        np.interp(landing["landing_dV_over_V0"] * V0, volume.p[last:], volume.observables["p"][last:]) / cap.p_c)
    result = {
        "lambda": lam, "N": N, "V0": V0, "p_c": cap.p_c, "H": depth(cap) / 2,
        "pressure_control": {"status": pressure.status, "message": pressure.message, "steps": len(pressure) - 1,
                             **landing},
        "volume_control": {"status": volume.status, "message": volume.message, "steps": len(volume) - 1,
                           "n_limit_points_in_p": len(p_limits), "n_folds_in_dV": len(folds_in_dV),
                           "first_p_max_over_p_c": None if first_max is None else first_max["p_over_p_c"],
                           "first_fold_in_dV": folds_in_dV[0] if folds_in_dV else None,
                           "stable_from_start_to_dV_over_V0": stable_upto,
                           "max_n_negative_volume": int(nv.max()), "max_n_negative_pressure": int(npr.max()),
                           "end_dV_over_V0": volume.p[-1] / V0, "end_w_over_h": volume.observables["w_over_h"][-1]},
        "agreement": compare_pressure(cap, pressure, volume) if compare else None,
        "wall_time_s": {"pressure": t1 - t0, "volume": t2 - t1},
    }
    return {"result": result, "points": points, "pressure": pressure, "volume": volume, "cap": cap}


def scan(lam: float, N: int) -> dict[str, Any]:
    """The first limit point in ``p`` and the first fold in ``dV`` of a cap, from one volume-controlled trace.

    The trace stops at the first fold in ``dV`` (or at the end of :func:`trace_volume`'s path).
    """
    cap = clamped_cap(lam, N)
    problem = volume_problem(cap)
    d, V0 = depth(cap), cap.pressure.V0
    st = contin.Settings(ds=0.01 * d, ds_max=STEP * d, max_steps=3000, stability=True, n_eigs=0,
                         state_weight=1.0 / cap.h, param_weight=d / (cap.h * 2.0 * V0))
    U0, q0 = problem.from_load_state(cap.reference_unknowns(), 0.0)
    br = contin.continuation(problem, U0, q0, st, p_max=DV_END_OVER_V0 * V0, bounds={"w": (None, 1.05 * d)},
                             events=[contin.extremum("p", "max", folds="p", stability_label=VOLUME_LABELS[1])],
                             stop_at=("fold",))
    p_max = next((s for s in br.special_points if s.info.get("folds") == "p"), None)
    fold = next((s for s in br.special_points if s.kind == "fold"), None)
    row: dict[str, Any] = {"lambda": lam, "N": N,
                           "p_max_over_p_c": None if p_max is None else p_max.observables["p_over_p_c"],
                           "dV_at_p_max_over_V0": None if p_max is None else p_max.p / V0,
                           "dV_fold_over_V0": None if fold is None else fold.p / V0,
                           "p_at_dV_fold_over_p_c": None if fold is None else fold.observables["p_over_p_c"],
                           "w_at_dV_fold_over_h": None if fold is None else fold.observables["w_over_h"]}
    if fold is not None and p_max is not None and fold.p > p_max.p:
        row["dV_fold_past_p_max"] = fold.p / p_max.p - 1.0  # how far the volume carries the cap past p_max
    return row


def _path_rows(run: dict[str, Any]) -> list[dict[str, Any]]:
    cap, V0 = run["cap"], run["cap"].pressure.V0
    rows = []
    for control, br in (("pressure", run["pressure"]), ("volume", run["volume"])):
        for i in range(len(br)):
            p = br.p[i] if control == "pressure" else br.observables["p"][i]
            dV = V0 - br.observables["V"][i]
            row = {"lambda": run["result"]["lambda"], "N": run["result"]["N"], "control": control,
                   "dV_over_V0": dV / V0, "p_over_p_c": p / cap.p_c, "w_over_h": br.observables["w_over_h"][i]}
            for label, (nneg, _) in br.stability_by.items():
                row[f"n_negative_{'pressure' if label == 'stability' else label}"] = int(nneg[i])
            rows.append(row)
    return rows


def _located(br: Branch) -> list[float]:
    """Arclengths of a branch's located special points."""
    return [sp.s for sp in br.special_points if sp.located]


def _curve(br: Branch, V0: float, p_c: float, pressure_controlled: bool) -> tuple[np.ndarray, ...]:
    """``dV/V0``, ``p/p_c``, their derivatives along the arclength and the arclength of a stored branch.

    Read by observable name, not through ``Branch.tangent``: on the volume-controlled branch ``tangent("p")``
    is the parameter's (``dV``), not the pressure's."""
    if pressure_controlled:
        x = 1.0 - br.observables["V"] / V0
        dV = br.tangents.get("V")
        dx = None if dV is None else -dV / V0
    else:
        x, dx = br.p / V0, br.tangent_p / V0
    y = br.observables["p_over_p_c"]
    dy = br.tangents.get("p_over_p_c")
    if dy is None and pressure_controlled:
        dy = br.tangent_p / p_c
    return x, y, dx, dy, br.s


def plot(runs: Sequence[dict[str, Any]]) -> Any:
    """``p / p_c`` against ``dV / V0`` for each cap: both paths, each styled by its own control's stability.

    One column per cap, page-wide in all: the whole path on top, the snaps below (the range of ``dV``
    where the path turns), the cap's legend under both.  The pressure-controlled path is drawn thick and
    light underneath the volume-controlled one
    (they are the same equilibria up to where the pressure trace stops); dotted arrows are the jump of
    each control at its first snap.  Both paths are drawn smooth between their stored points from the
    stored tangents (:func:`contin.plot.branches.smooth_path`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    from contin.plot import style
    from contin.plot.branches import stability_pieces
    from contin.plot.framing import show_detail

    c_pressure, c_volume = style.COLORS[4], style.COLORS[0]
    # a page's width (contin.plot.style.WIDTH) split into one column per cap, printable as saved
    fig, grid = plt.subplots(3, len(runs), figsize=(style.WIDTH, 7.6), squeeze=False, layout="constrained",
                             gridspec_kw={"height_ratios": [1.0, 1.0, 0.26]})
    axes, below = grid[:2], grid[2]  # the bottom row holds the legends: the panels of both columns aligned
    for ax in below:
        ax.set_axis_off()
    for col, run in enumerate(runs):
        cap, res = run["cap"], run["result"]
        V0 = cap.pressure.V0
        vol, pr = run["volume"], run["pressure"]
        pc = res["pressure_control"]
        folds = [r for r in run["points"] if r["folds_in"] == "dV"]
        turns = [r["dV_over_V0"] for r in run["points"] if r["dV_over_V0"] < 0.6]
        zoom_x = max(2.0 * pc["dV_at_p_max_over_V0"], 1.1 * max(turns, default=0.0))
        # each control's style changes at its located points (folds, extrema) between stored points
        paths = [(_curve(pr, V0, cap.p_c, True), pr.stable, _located(pr), c_pressure, 5.0, 2, "pressure"),
                 (_curve(vol, V0, cap.p_c, False), vol.stable_under(VOLUME_LABELS[0]), _located(vol), c_volume, None,
                  3, "volume")]
        inside = vol.p / V0 <= zoom_x
        snaps = ((0.0, zoom_x), (0.0, 1.12 * float(np.max(vol.observables["p"][inside])) / cap.p_c))
        for row, ax in enumerate(axes[:, col]):
            if row == 1:  # the snaps: the detail of a grey box on the whole path above
                show_detail(axes[0, col], ax, snaps, title="the snaps (detail of the grey box)")
            entries = []
            for (x, y, dx, dy, s), stable, cuts, color, lw, z, control in paths:
                kinds = set()
                for X, Y, st in stability_pieces(x, y, dx, dy, s, stable, cuts):
                    line = dict(style.STABLE if st else style.UNSTABLE)
                    if lw is not None:
                        line["lw"] = lw
                    ax.plot(X, Y, color=color, zorder=z, solid_capstyle="round", dash_capstyle="butt", **line)
                    kinds.add("stable" if st else "unstable")
                # the legend names only the line styles drawn (the shallower cap is stable throughout under volume)
                words = [w for k, w in (("stable", "stable solid"), ("unstable", "unstable dashed")) if k in kinds]
                entries.append(Line2D([], [], color=color, lw=lw or style.STABLE["lw"],
                                      label=f"{control} control: {', '.join(words)}"))
            limit, = ax.plot([pc["dV_at_p_max_over_V0"]], [pc["p_max_over_p_c"]], ls="none",
                             label="limit point in $p$ (pressure control snaps)", **style.marker_style("limit point"))
            entries.append(limit)
            arrow = dict(arrowstyle="->", ls=":", lw=1.4, shrinkA=0, shrinkB=0)
            if pc["landing_success"]:
                x0, x1, y0 = pc["dV_at_p_max_over_V0"], pc["landing_dV_over_V0"], pc["p_max_over_p_c"]
                right = ax.get_xlim()[1] if row == 1 else math.inf
                if x1 <= right:
                    ax.annotate("", xy=(x1, y0), xytext=(x0, y0), zorder=4,
                                arrowprops=dict(arrow, color=c_pressure, shrinkB=3))
                else:
                    # the landing is beyond the detail's range: the arrow runs to the panel's edge and says where
                    # it lands (an annotation whose end lies outside the axes is not drawn at all)
                    edge = x0 + 0.985 * (right - x0)
                    ax.annotate("", xy=(edge, y0), xytext=(x0, y0), zorder=4, arrowprops=dict(arrow, color=c_pressure))
                    ax.annotate(f"snap to $\\Delta V/V_0$ = {x1:.3g}", (edge, y0), textcoords="offset points",
                                xytext=(-8, -5), ha="right", va="top", fontsize="small", color=c_pressure)
            if folds:
                fold, = ax.plot([r["dV_over_V0"] for r in folds], [r["p_over_p_c"] for r in folds], ls="none",
                                label="fold in $\\Delta V$ (volume control snaps at the first)",
                                **style.marker_style("fold"))
                entries.append(fold)
                first = folds[0]
                if first.get("landing_p_over_p_c") is not None:
                    ax.annotate("", xy=(first["dV_over_V0"], first["landing_p_over_p_c"]),
                                xytext=(first["dV_over_V0"], first["p_over_p_c"]), zorder=4,
                                arrowprops=dict(arrow, color=c_volume, shrinkA=4))
            ax.set_xlabel(r"$\Delta V / V_0 = (V_0 - V) / V_0$ (volume pushed in)")
            ax.set_ylabel(r"$p / p_c$")
            ax.grid(alpha=0.3, lw=0.5)
            if row == 0:
                ax.set_title(f"clamped cap, $\\lambda$ = {res['lambda']:g}, $R/h$ = {R_OVER_H:g}, $N$ = {res['N']}",
                             fontsize="small")
                ax.set_xlim(0.0, None)
                ax.set_ylim(0.0, None)
                # below the column's panels: inside, at a half page's width, it would cover the paths
                below[col].legend(handles=entries, loc="upper center", borderaxespad=0.0)
    return fig


def every_mode(lam: float, N: int) -> list[dict[str, Any]]:
    """Issue 17, study (c): the first instability of the same cap under both controls with every mode watched.

    The scene runner (``contin trace``'s work) with ``stability.harmonics = true``: the first fold under
    the control or the first bifurcation into a wave number ``n``, whichever comes first.  An ``n >= 1``
    field changes neither the pressure's work nor the volume to first order, so both controls share
    those blocks and must meet the same bifurcation at the same state.
    """
    from contin.app.scene import load_scene
    from contin_models.shell.pressure import phi_hat_for_lambda
    from contin_models.shell_scene import SHELL_SCENE

    h = 1.0 / R_OVER_H
    rows = []
    for control in ("force", "displacement"):
        scene = load_scene(SHELL_SCENE.schema, None, [
            "load.kind=pressure", f"load.control={control}", "shell.boundary=clamped", f"shell.h={h!r}",
            f"shell.nu={NU}", f"shell.phi_hat={phi_hat_for_lambda(lam, 1.0, h, NU)!r}", f"shell.N={N}",
            "stability.harmonics=true", "output.figure=false"])
        result = SHELL_SCENE.runner(scene, False)
        first = result.summary.get("first_instability") or {}
        rows.append({"lambda": lam, "N": N, "control": "pressure" if control == "force" else "volume",
                     "first_kind": first.get("kind"), "n": first.get("n"), "p_over_p_c": first.get("p_over_p_c"),
                     "w_over_h": first.get("w_over_h"), "axisymmetric_p_max_over_p_c": result.summary.get("p_snap_over_p_c"),
                     "axisymmetric_dV_fold_over_V0": result.summary.get("dV_snap_over_V0")})
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("volume_control", "a clamped cap under volume control against pressure control")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    runs = []
    for lam in LAMBDAS:
        say(args.quiet, f"lambda = {lam:g}, N = 100: pressure and volume control ...")
        runs.append(run_cap(lam, 100))
    mesh = []
    for N in ((200, 400) if args.full else (200,)):
        say(args.quiet, f"lambda = {LAMBDAS[0]:g}, N = {N} (mesh check) ...")
        mesh.append(run_cap(LAMBDAS[0], N, compare=False))
    say(args.quiet, f"first snaps of both controls, lambda = {', '.join(f'{x:g}' for x in SCAN)}, N = 100 ...")
    scanned = [scan(lam, 100) for lam in SCAN]
    points = [r for run in runs + mesh for r in run["points"]]
    write_csv(out / "special_points.csv", points)
    write_csv(out / "paths.csv", [row for run in runs for row in _path_rows(run)])
    write_json(out / "summary.json", {
        "nu": NU, "R_over_h": R_OVER_H, "W_PAST": W_PAST, "DV_END_OVER_V0": DV_END_OVER_V0,
        "caps": [run["result"] for run in runs], "mesh": [run["result"] for run in mesh], "special_points": points,
        "scan": scanned})
    write_csv(out / "scan.csv", scanned)
    say(args.quiet, f"every mode (issue 17, study (c)): lambda = {', '.join(f'{x:g}' for x in LAMBDAS)}, N = 120, "
                    "both controls ...")
    modes = [row for lam in LAMBDAS for row in every_mode(lam, 120)]
    write_csv(out / "every_mode.csv", modes)
    save_figure(plot(runs), out, "volume_control")
    print_table(points, ["lambda", "N", "folds_in", "label", "dV_over_V0", "p_over_p_c", "w_over_h", "volume",
                         "pressure", "landing_p_over_p_c", "landing_w_over_h"], digits=6)
    print()
    print_table(scanned, ["lambda", "N", "p_max_over_p_c", "dV_at_p_max_over_V0", "dV_fold_over_V0",
                          "p_at_dV_fold_over_p_c", "w_at_dV_fold_over_h", "dV_fold_past_p_max"], digits=6)
    print()
    print_table(modes, ["lambda", "N", "control", "first_kind", "n", "p_over_p_c", "w_over_h",
                        "axisymmetric_p_max_over_p_c", "axisymmetric_dV_fold_over_V0"], digits=6)
    print()
    for run in runs + mesh:
        res = run["result"]
        pc, vc, ag = res["pressure_control"], res["volume_control"], res["agreement"]
        first = vc["first_fold_in_dV"]
        print(f"lambda = {res['lambda']:g}, N = {res['N']}: pressure control snaps at p_max/p_c = "
              f"{pc['p_max_over_p_c']:.6g} (w/h = {pc['w_at_p_max_over_h']:.4g}, dV/V0 = {pc['dV_at_p_max_over_V0']:.4g})"
              f" and lands at w/h = {pc['landing_w_over_h']:.4g} (dV/V0 = {pc['landing_dV_over_V0']:.4g}, where the volume "
              f"path has p/p_c = {pc['p_on_volume_path_at_landing_over_p_c']:.4g}); "
              f"volume control: {vc['n_limit_points_in_p']} limit points in p, {vc['n_folds_in_dV']} folds in dV"
              + (f", first at dV/V0 = {first['dV_over_V0']:.6g}, p/p_c = {first['p_over_p_c']:.6g}" if first else "")
              + f"; stable from the start to dV/V0 = {vc['stable_from_start_to_dV_over_V0']:.4g}"
              + (f"; p agrees with pressure control at {ag['n_compared']}/{ag['n_wanted']} points to "
                 f"{ag['max_rel_diff_p']:.2g} (relative)" if ag else "")
              + f"; {res['wall_time_s']['pressure'] + res['wall_time_s']['volume']:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))
