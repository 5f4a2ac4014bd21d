"""Classical checks of the shell under pressure (issue 16): clamped caps, (a) the axisymmetric snap, (b) curves.

Run ``python -m studies.classical [--out DIR] [--full]``.  ``docs/validation.md`` sections 3 and 4
state the comparisons, their sources and the verdicts; this docstring says what is computed.

(a) **Axisymmetric snap pressure of clamped shallow caps against lambda.**  For each
``lambda = 2 (3 (1 - nu^2))^(1/4) sqrt(H/h)`` (:func:`contin_models.shell.pressure.cap_lambda`, ``H`` the
exact rise ``R (1 - cos phi_0)``) a cap of given ``R/h`` (``nu = 0.3``) with a clamped edge
(:class:`contin_models.shell.ShellPressure`) is traced under pressure control from ``p = 0`` with
:func:`contin.continuation`, stopping at the first fold in ``p``; its pressure over the classical
``p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2))`` is compared with Budiansky (1959) and the two later
computations that Teng & Rotter (1989a, Table 1) list with it (Dumir & Nath 1984; Teng & Rotter's own).
A cap with no fold up to ``P_MAX`` ``p_c`` is reported as monotonic.

- Mesh convergence: three meshes per cap (default N = 100, 200, 400 at ``R/h = 400``; ``--full``:
  N = 100, 200, 400, 800 at every ``R/h``), with the observed order and a Richardson estimate.
- Depth: ``R/h`` = 100, 400, 1000, 10000 at fixed ``lambda``.  In shallow-shell theory the result
  depends on ``lambda`` only; the deep-geometry correction is linear in ``h/R`` at fixed ``lambda``
  (the cap's ``H/R = (H/h)(h/R)``), so ``p(h/R) = p_0 + c h/R`` fitted on the two thinnest caps gives
  the shallow limit ``p_0`` and the size ``p(100) - p_0`` of the deep-geometry effect at ``R/h = 100``.
- The clamped edge's boundary layer (decay length ``ell = sqrt(R h) / (3 (1 - nu^2))^(1/4)``) spans
  ``a / ell = lambda / sqrt(2)`` of the base radius ``a = sqrt(2 R H)`` whatever ``R/h``: a uniform
  mesh of N nodes puts ``sqrt(2) N / lambda`` nodes in it at every ``R/h`` (35 at ``lambda = 8``,
  N = 200), so the thin caps need no edge grading (the model grades only towards the pole).
- Candidate causes of the offset to Budiansky (``--full`` adds them, the default keeps one each):
  Poisson's ratio, the lambda definition (exact rise against the base-radius form
  ``(12 (1 - nu^2))^(1/4) a / sqrt(R h)``), ``kappa11_length`` reference against current, pinned
  against clamped, and the clamp itself (rotation of the edge tangent at the fold, extrapolated from
  the first two chords, against the pinned edge's).
- The steep part near ``lambda = 5.5``: a fine scan of ``lambda`` (5.3 to 5.9) with small steps, the
  number of maxima of ``p`` before the snap, and the pole deflection at the fold.

(b) **Pressure-deflection curves of clamped caps.**  ``p / p_c`` against the pole deflection
``w / h`` and the average deflection ``(V_0 - V) / (pi a^2 h)`` for ``lambda`` = 4 to 8, and the
deflected shape at the first fold for ``lambda`` = 5, 5.5, 6: the mechanism that changes near 5.5.
The published curve we can compare with is the clamped cap ``R = 100 in``, ``h = 0.5 in``,
``phi_0 = 7.1 deg`` (``lambda = 3.18``, no snap) of Bathe et al. (1975) and Teng & Rotter (1989a,
Fig. 13), load ``q (a/h)^4 / E`` against ``w / h``, as digitised in AQUINAS's Example GNA03
(Filippidis & Sadowski, github.com/AchilleasF/AQUINAS-FE, ``src/Examples/input_Example_GNA03.csv``).

Findings (``docs/validation.md`` sections 3 and 4 for the tables)
-----------------------------------------------------------------
Mesh-converged (order 2, finest mesh within 1.4e-5 ``p_c`` of Richardson), the snap pressures at
``R/h = 400`` are 1.1 to 2.2 % below Budiansky's at lambda = 4, 5, 6, 7, 8 and 5.2 % at 5.5; the
shallow limit is 1.9 to 2.5 % (5.6 %) below, and within 0.16 % of Teng & Rotter's own values at all
six lambdas.  The deep-geometry effect at ``R/h = 100`` raises the snap pressure by 1.2 % (lambda 4)
to 3.2 % (lambda 8), linearly in ``h/R``.  Neither the mesh, the step, ``kappa11_length``, the clamp
(edge tangent rotation 5e-7 rad at N = 800) nor the lambda definition explains the offset to
Budiansky; ``nu = 1/3`` would bring it under 0.8 % (3.5 % at 5.5), a hypothesis we could not check
against the 1959 paper.  Near lambda = 5.5 the deflection maximum at the fold leaves the pole for
a ring (r/a = 0 at 5.5, 0.32 at 5.6, 0.46 at 6): the snap pressure rises by up to 1.3 ``p_c`` per
unit lambda there, one maximum of ``p`` throughout; from lambda = 6.2 the path has a second, higher
maximum after the first fold.  The Bathe cap's curve lies within 1.4 % of the plotted ranges of
both published curves.

Units: ``h = 1``, ``R = R/h``, and ``E`` such that ``p_c = 1``, so the parameter is ``p / p_c`` and
the state is in units of the thickness (both of order one along the trace).

Writes ``snap.csv`` (every lambda, N, R/h and variant), ``convergence.csv``, ``shallow_limit.csv``,
``curves.csv``, ``bathe.csv``, ``summary.json`` and the figures ``classical_snap``,
``classical_shallow``, ``classical_curves`` and ``classical_bathe`` (PNG and PDF).
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
from contin.plot.branches import smooth_path  # noqa: E402
from contin_models.shell.pressure import ShellPressure, cap_lambda, phi_hat_for_lambda  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

NU = 0.3
R_OVER_H = 400.0
#: The depths of the R/h sweep (the shallow limit is fitted on the two largest).
DEPTHS = (100.0, 400.0, 1000.0, 10000.0)
#: The trace stops here if no fold came first (a monotonic cap).
P_MAX = 3.0

#: Axisymmetric snap pressure over p_c of clamped shallow caps, nu = 0.3: Budiansky (1959), as
#: tabulated by Teng & Rotter (1989a, Table 1); quoted in docs/model.md#classical-values.
BUDIANSKY = {4.0: 0.578, 5.0: 0.629, 5.5: 0.789, 6.0: 0.995, 7.0: 1.068, 8.0: 1.13}
#: The same table's other two columns: Dumir & Nath (1984) and Teng & Rotter's own finite elements
#: (1989a).  Read from AQUINAS's reproduction of that table (github.com/AchilleasF/AQUINAS-FE,
#: src/Examples/input_Example_GNA05.csv, whose Example_GNA05.m uses R/t = 100, nu = 0.3, the exact rise).
DUMIR_NATH = {4.0: 0.58, 5.0: 0.63, 5.5: 0.785, 6.0: 0.986, 7.0: 1.042, 8.0: 1.115}
TENG_ROTTER = {4.0: 0.563, 5.0: 0.615, 5.5: 0.746, 6.0: 0.972, 7.0: 1.046, 8.0: 1.109}

LAMBDAS = (3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5, 7.0, 8.0)
#: The fine scan of the steep part (``--full``; the default keeps every second value).
FINE_LAMBDAS = tuple(round(5.3 + 0.05 * i, 2) for i in range(13))

#: Bathe et al. (1975) / Teng & Rotter (1989a, Fig. 13): clamped cap R = 100 in, t = 0.5 in,
#: phi_0 = 7.1 deg, nu = 0.3, uniform pressure q; load q (a/t)^4 / E against the apex deflection w_c/t.
#: Points digitised by AQUINAS (input_Example_GNA03.csv): (w_c/t, q (a/t)^4/E).
BATHE_CAP = dict(R=100.0, h=0.5, phi_0_deg=7.1, nu=0.3)
BATHE_TR_POINTS = ((0.111477, 1.972274), (0.213981, 3.278777), (0.444883, 5.430852), (0.602395, 6.350361),
                   (0.794673, 7.069568), (0.998353, 7.399261), (1.126323, 7.507814), (1.545236, 8.037809),
                   (1.804251, 8.544110), (2.051739, 9.223156), (2.425155, 11.499076), (2.545009, 12.647622),
                   (2.653235, 13.795497))
BATHE_B_POINTS = ((0.067526, 1.377248), (0.152521, 2.567132), (0.263720, 3.830785), (0.389397, 4.994119),
                  (0.468199, 5.533356), (0.552831, 6.101832), (0.649051, 6.598723), (0.882020, 7.305831),
                  (1.015913, 7.602588), (1.318400, 7.880188), (1.452218, 8.046883), (1.719854, 8.380272),
                  (1.859578, 8.706268), (2.133389, 9.661401), (2.378491, 11.236263), (2.583129, 13.213410),
                  (2.720954, 15.273399))

#: Point (apex) and ring load on the clamped cap of Mescall (1965): R = 4.758 in, t = 0.01576 in,
#: base radius a = 0.9 in (lambda = 6.0, R/t = 302), E = 1e7 psi, nu = 0.3; total load P (lb) against
#: the apex deflection w_c (in).  Teng & Rotter (1989a, Fig. 12) and Wood & Zienkiewicz (1977), as
#: digitised in AQUINAS (input_Example_GNA04.csv; its column names swap P and w_c, its plotting script
#: plots column 1 as w_c and column 2 as P).  Not computed here: the loads are being built.
MESCALL_CAP = {
    "geometry": {"R_in": 4.758, "t_in": 0.01576, "a_in": 0.9, "E_psi": 1e7, "nu": 0.3, "clamped": True},
    "ring_load_r_over_a_0.42": {
        "teng_rotter_1989a": {"peak_P_lb": 74.52, "peak_w_c_in": 0.01463, "valley_P_lb": 37.44,
                              "valley_w_c_in": 0.0689},
        "wood_zienkiewicz_1977": {"peak_P_lb": 74.85, "peak_w_c_in": 0.0117, "valley_P_lb": 37.65,
                                  "valley_w_c_in": 0.065}},
    "apex_load": {
        "teng_rotter_1989a": {"w_c_in": [0.0102, 0.0632, 0.1220, 0.1607], "P_lb": [9.79, 25.67, 40.46, 64.90]},
        "wood_zienkiewicz_1977": {"w_c_in": [0.00885, 0.0698, 0.1204, 0.1607], "P_lb": [9.68, 27.99, 41.34, 70.29]},
        "note": "no limit point up to w_c = 0.16 in in either source"},
    "source": "github.com/AchilleasF/AQUINAS-FE src/Examples/input_Example_GNA04.csv and Example_GNA04.m",
}


# ---- the caps -----------------------------------------------------------------------------------
def lambda_base_radius(pr: ShellPressure) -> float:
    """The base-radius form of lambda, ``(12 (1 - nu^2))^(1/4) a / sqrt(R h)`` (shallow-shell theory's ``a^2 = 2 R H``)."""
    a = pr.R * math.cos(pr.phi_hat)
    return (12.0 * (1.0 - pr.nu ** 2)) ** 0.25 * a / math.sqrt(pr.R * pr.h)


def clamped_cap(lam: float, N: int, r_over_h: float = R_OVER_H, *, nu: float = NU, boundary: str = "clamped",
                kappa11_length: str = "current", lambda_def: str = "rise") -> ShellPressure:
    """The cap of depth parameter ``lam`` in the study's units (``h = 1``, ``p_c = 1``).

    ``lambda_def = "rise"`` sets the exact rise ``H = R (1 - cos phi_0)`` from ``lam``
    (:func:`phi_hat_for_lambda`); ``"base"`` sets the base radius ``a`` from the base-radius form
    (:func:`lambda_base_radius`), which is the same in the shallow limit.
    """
    R, h = float(r_over_h), 1.0
    E = math.sqrt(3.0 * (1.0 - nu * nu)) / (2.0 * (h / R) ** 2)
    if lambda_def == "rise":
        phi_hat = phi_hat_for_lambda(lam, R, h, nu)
    elif lambda_def == "base":
        a = lam * math.sqrt(R * h) / (12.0 * (1.0 - nu * nu)) ** 0.25
        phi_hat = math.acos(a / R)
    else:
        raise ValueError(f"lambda_def must be 'rise' or 'base', got {lambda_def!r}")
    return ShellPressure(R=R, E=E, nu=nu, h=h, phi_hat=phi_hat, N=N, boundary=boundary,
                         kappa11_length=kappa11_length)


def edge_tangent_rotation(pr: ShellPressure, x: np.ndarray) -> float:
    """Rotation (rad) of the meridian's tangent at the edge, extrapolated from the first two chords.

    The chord of edge ``i`` has the direction of the tangent at its midpoint to second order; the
    tangent angle at the base node is ``1.5 a_0 - 0.5 a_1`` (``a_i`` the chord angles), second-order
    accurate on a uniform mesh.  Its change from the reference state is what a clamp must hold at
    zero (to the discretisation error ``O(l^2)``); the first chord alone turns by ``O(l)``
    (:meth:`ShellPressure.edge_rotation`).
    """
    def angle(y: np.ndarray) -> float:
        a0 = math.atan2(y[3] - y[1], y[2] - y[0])
        a1 = math.atan2(y[5] - y[3], y[4] - y[2])
        return 1.5 * a0 - 0.5 * a1
    return angle(x) - angle(pr.cap.x)


def _settings(ds_max: float) -> contin.Settings:
    return contin.Settings(ds=min(0.02, ds_max), ds_max=ds_max, max_steps=20000)


def snap_pressure(lam: float, N: int, r_over_h: float = R_OVER_H, *, ds_max: float = 0.1,
                  variant: str = "clamped", **cap_options: Any) -> dict[str, Any]:
    """The first fold in ``p`` of a cap: ``p_snap / p_c``, the pole deflection and the edge rotations there.

    Returns a row with ``p_snap_over_p_c`` and ``w_over_h`` None when the trace reaches ``P_MAX``
    without a fold (monotonic).  ``variant`` labels the row; ``cap_options`` go to :func:`clamped_cap`.
    """
    pr = clamped_cap(lam, N, r_over_h, **cap_options)
    t0 = time.perf_counter()
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, _settings(ds_max), stop_at=("fold",), p_max=P_MAX)
    folds = [s for s in br.special_points if s.kind == "fold"]
    row: dict[str, Any] = {"variant": variant, "lambda": lam, "N": N, "R_over_h": r_over_h, "nu": pr.nu,
                           "lambda_rise": cap_lambda(pr.R, pr.h, pr.phi_hat, pr.nu),
                           "lambda_base": lambda_base_radius(pr), "H_over_R": 1.0 - math.sin(pr.phi_hat),
                           "steps": len(br.p)}
    if folds and folds[0].located:
        x = pr.full_state(folds[0].u)
        row["p_snap_over_p_c"] = float(folds[0].p) / pr.p_c
        row["w_over_h"] = float(folds[0].observables["w_over_h"])
        row["edge_chord_rotation"] = pr.edge_rotation(x)
        row["edge_tangent_rotation"] = edge_tangent_rotation(pr, x)
    elif folds:
        raise RuntimeError(f"lambda = {lam}, N = {N}: fold detected but not located ({br.message})")
    else:
        row["p_snap_over_p_c"] = None
        row["w_over_h"] = None
        row["note"] = f"no fold up to p = {P_MAX} p_c ({br.message})"
    for name, table in (("budiansky", BUDIANSKY), ("dumir_nath", DUMIR_NATH), ("teng_rotter", TENG_ROTTER)):
        row[name] = table.get(lam)
    if row["budiansky"] is not None and row["p_snap_over_p_c"] is not None:
        row["rel_diff"] = row["p_snap_over_p_c"] / row["budiansky"] - 1.0
        row["rel_diff_teng_rotter"] = row["p_snap_over_p_c"] / row["teng_rotter"] - 1.0
    row["seconds"] = time.perf_counter() - t0
    return row


# ---- convergence and the shallow limit ----------------------------------------------------------
def convergence(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per (lambda, R/h): the three finest meshes (doubling N), observed order and Richardson estimate.

    ``order = log2((p_1 - p_2) / (p_2 - p_3))`` when the two changes have the same sign (else None:
    the changes are at the level of the fold's location tolerance or oscillate); ``p_rich`` is the
    Richardson estimate ``p_3 + (p_3 - p_2) / (2^q - 1)`` with the observed order ``q`` when it lies
    in [1, 4], else with ``q = 2`` (the discretisation's order for smooth solutions).
    """
    out = []
    keys = sorted({(r["lambda"], r["R_over_h"]) for r in rows if r["variant"] == "clamped"})
    for lam, rh in keys:
        sel = sorted((r for r in rows if r["variant"] == "clamped" and r["lambda"] == lam and r["R_over_h"] == rh
                      and r["p_snap_over_p_c"] is not None), key=lambda r: r["N"])
        if len(sel) < 3:
            continue
        (n1, p1), (n2, p2), (n3, p3) = [(r["N"], r["p_snap_over_p_c"]) for r in sel[-3:]]
        d12, d23 = p1 - p2, p2 - p3
        order = math.log2(d12 / d23) if d12 * d23 > 0 else None
        q = order if order is not None and 1.0 <= order <= 4.0 else 2.0
        rich = p3 + (p3 - p2) / (2.0 ** q - 1.0)
        out.append({"lambda": lam, "R_over_h": rh, "N": f"{n1}/{n2}/{n3}", "p_1": p1, "p_2": p2, "p_3": p3,
                    "change_12": p2 - p1, "change_23": p3 - p2, "order": order, "p_rich": rich,
                    "rich_minus_finest": rich - p3})
    return out


def shallow_limit(rows: Sequence[dict[str, Any]], finest: int) -> list[dict[str, Any]]:
    """Per lambda: ``p(h/R) = p_0 + c h/R`` through the two thinnest caps, and the deep effect at R/h = 100."""
    out = []
    for lam in sorted({r["lambda"] for r in rows}):
        pts = {r["R_over_h"]: r["p_snap_over_p_c"] for r in rows if r["variant"] == "clamped"
               and r["lambda"] == lam and r["N"] == finest and r["p_snap_over_p_c"] is not None}
        if not all(d in pts for d in DEPTHS):
            continue
        (ra, pa), (rb, pb) = sorted(pts.items())[-2:]
        c = (pa - pb) / (1.0 / ra - 1.0 / rb)
        p0 = pb - c / rb
        row: dict[str, Any] = {"lambda": lam, "p_shallow": p0, "slope_c": c}
        for d in DEPTHS:
            row[f"p_{d:g}"] = pts[d]
        # the linear fit's prediction at the two other depths, as a check of the linear form
        row["fit_error_400"] = pts[400.0] - (p0 + c / 400.0)
        row["fit_error_100"] = pts[100.0] - (p0 + c / 100.0)
        row["deep_effect_100"] = pts[100.0] - p0
        row["deep_effect_100_rel"] = pts[100.0] / p0 - 1.0
        ref = BUDIANSKY.get(lam)
        row["budiansky"] = ref
        row["shallow_vs_budiansky"] = p0 / ref - 1.0 if ref else None
        row["shallow_vs_teng_rotter"] = p0 / TENG_ROTTER[lam] - 1.0 if ref else None
        row["r100_vs_teng_rotter"] = pts[100.0] / TENG_ROTTER[lam] - 1.0 if ref else None
        out.append(row)
    return out


# ---- pressure-deflection curves ------------------------------------------------------------------
def pressure_curve(pr: ShellPressure, *, ds_max: float = 0.02, w_max: float | None = None,
                   p_max: float = 1.4) -> dict[str, Any]:
    """The branch from ``p = 0``: ``p/p_c``, pole and average deflection over ``h``, its folds and fold shapes."""
    bounds = {"w_over_h": (None, w_max)} if w_max is not None else {}
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, _settings(ds_max), p_max=p_max * pr.p_c,
                             bounds=bounds)
    a = pr.R * math.cos(pr.phi_hat)
    V = br.observable("V")
    V0 = pr.pressure.volume(pr.cap.x)
    folds = []
    for s in br.special_points:
        if s.kind != "fold":
            continue
        x = pr.full_state(s.u)
        folds.append({"p_over_p_c": float(s.p) / pr.p_c, "w_over_h": float(s.observables["w_over_h"]),
                      "w_avg_over_h": (V0 - float(s.observables["V"])) / (math.pi * a * a * pr.h),
                      "r_over_a": (pr.cap.x[0::2] / a).tolist(),
                      "deflection_over_h": ((pr.cap.x[1::2] - x[1::2]) / pr.h).tolist()})
    # the tangents along the arclength let the figures draw the path smooth between the stored points
    return {"p_over_p_c": br.p / pr.p_c, "w_over_h": br.observable("w_over_h"),
            "w_avg_over_h": (V0 - V) / (math.pi * a * a * pr.h), "folds": folds, "message": br.message,
            "a": a, "s": br.s, "dp_over_p_c": _tangent(br, "p", 1.0 / pr.p_c),
            "dw_over_h": _tangent(br, "w_over_h", 1.0),
            "dw_avg_over_h": _tangent(br, "V", -1.0 / (math.pi * a * a * pr.h))}


def _tangent(br: contin.Branch, name: str, factor: float) -> np.ndarray | None:
    t = br.tangent(name)
    return None if t is None else t * factor


def bathe_cap(N: int) -> ShellPressure:
    """The clamped cap of Bathe et al. (1975) / Teng & Rotter (1989a, Fig. 13), E = 1 (the load is normalised)."""
    c = BATHE_CAP
    return ShellPressure(R=c["R"], E=1.0, nu=c["nu"], h=c["h"], phi_hat=0.5 * math.pi - math.radians(c["phi_0_deg"]),
                         N=N, boundary="clamped")


def bathe_comparison(N: int) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """Our ``q (a/h)^4 / E`` against ``w / h`` for the Bathe cap, and the published points against it."""
    pr = bathe_cap(N)
    a = pr.R * math.cos(pr.phi_hat)
    scale = (a / pr.h) ** 4 / pr.E
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, _settings(0.01), p_max=16.0 / scale,
                             bounds={"w_over_h": (None, 3.0)})
    w = br.observable("w_over_h")
    q = br.p * scale
    curve = {"w_over_h": w, "q_norm": q, "s": br.s, "dw_over_h": _tangent(br, "w_over_h", 1.0),
             "dq_norm": _tangent(br, "p", scale), "lambda": pr.lam(), "R_over_h": pr.R / pr.h, "a_over_h": a / pr.h,
             "folds": len([s for s in br.special_points if s.kind == "fold"]), "message": br.message,
             "monotonic": bool(np.all(np.diff(w) > 0) and np.all(np.diff(q) > 0))}
    # a dense copy of our curve (piecewise linear between converged points) for the distances
    wd = np.interp(np.linspace(0.0, len(w) - 1.0, 20 * len(w)), np.arange(len(w)), w)
    qd = np.interp(np.linspace(0.0, len(q) - 1.0, 20 * len(q)), np.arange(len(q)), q)
    rows = []
    for source, pts in (("Teng & Rotter 1989a Fig. 13", BATHE_TR_POINTS), ("Bathe et al. 1975", BATHE_B_POINTS)):
        for wp, qp in pts:
            ours = float(np.interp(wp, w, q))  # w and q both increase along this branch (no fold)
            rows.append({"source": source, "w_over_h": wp, "q_published": qp, "q_ours": ours,
                         "rel_diff": ours / qp - 1.0, "w_ours_at_q": float(np.interp(qp, q, w)),
                         "dw_at_q": float(np.interp(qp, q, w)) - wp,
                         # distance to our curve in fractions of the plotted ranges (w/h 0-3, load 0-16)
                         "distance": float(np.min(np.hypot((wd - wp) / 3.0, (qd - qp) / 16.0)))})
    return curve, rows


# ---- figures --------------------------------------------------------------------------------------
def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_snap(rows: Sequence[dict[str, Any]], finest: int, fine: Sequence[dict[str, Any]]) -> Any:
    """``p_snap / p_c`` against ``lambda`` at each R/h (finest mesh), the fine scan and the published values."""
    from contin.plot.style import COLORS, GREY, WIDTH

    plt = _plt()
    fig, ax = plt.subplots(figsize=(WIDTH, 4.4), layout="constrained")
    # up to eight values lie within 0.02 p_c at each published lambda: the published ones are drawn
    # first and thin (their arms and outlines show around ours), ours above them, nested from the large
    # hollow circle (R/h = 400) to the small dot (R/h = 10000) inside the triangle (R/h = 1000); the
    # square (R/h = 100), 0.005 p_c higher, is hollow so that it hides neither
    styles = {100.0: dict(color=COLORS[1], marker="s", ms=5.5, mfc="none", mew=1.0, zorder=4.5),
              400.0: dict(color=COLORS[0], marker="o", ms=8.0, mfc="none", mew=1.0, zorder=4),
              1000.0: dict(color=COLORS[2], marker="^", ms=4.4, zorder=5),
              10000.0: dict(color=COLORS[6], marker="o", ms=2.2, zorder=6)}
    for rh, st in styles.items():
        pts = sorted((r["lambda"], r["p_snap_over_p_c"]) for r in rows if r["variant"] == "clamped"
                     and r["R_over_h"] == rh and r["N"] == finest and r["p_snap_over_p_c"] is not None)
        if not pts:
            continue
        label = f"$R/h = {rh:g}$, $N = {finest}$"
        if rh != R_OVER_H:
            ax.plot(*zip(*pts), ls="none", label=label, **st)
            continue
        # a sweep, one run per lambda, joined only through the fine scan's samples too: a chord from
        # lambda = 5 to 6 would pass 0.06 p_c below them; the circles mark this mesh's own samples
        on_line = dict(pts)
        on_line.update({r["lambda"]: r["p_snap_over_p_c"] for r in fine
                        if r["p_snap_over_p_c"] is not None and r["lambda"] not in on_line})
        xs = sorted(on_line)
        ax.plot(xs, [on_line[x] for x in xs], ls="-", lw=0.8, markevery=[i for i, x in enumerate(xs) if x in dict(pts)],
                label=label, **st)
    if fine:
        pts = sorted((r["lambda"], r["p_snap_over_p_c"]) for r in fine
                     if r["p_snap_over_p_c"] is not None and r["lambda"] not in BUDIANSKY)
        ax.plot(*zip(*pts), "o", color=COLORS[0], ms=3.0, zorder=4,
                label=f"fine scan, $R/h = {fine[0]['R_over_h']:g}$, $N = {fine[0]['N']}$")
    nu13 = sorted((r["lambda"], r["p_snap_over_p_c"]) for r in rows if r["variant"].startswith("nu=1/3, shallow"))
    if nu13:
        ax.plot(*zip(*nu13), "*", color="k", mfc="none", ms=8.5, mew=0.8, zorder=3.5,
                label=r"$\nu = 1/3$, $R/h = 10000$, $N = 400$")
    ax.plot(list(BUDIANSKY), list(BUDIANSKY.values()), "D", color="k", mfc="none", ms=8.5, mew=0.8, zorder=3,
            label="Budiansky (1959)")
    ax.plot(list(DUMIR_NATH), list(DUMIR_NATH.values()), "x", color=GREY, ms=7, mew=0.9, zorder=3,
            label="Dumir & Nath (1984)")
    ax.plot(list(TENG_ROTTER), list(TENG_ROTTER.values()), "+", color=COLORS[4], ms=10, mew=1.0, zorder=3,
            label="Teng & Rotter (1989a)")
    mono = sorted({r["lambda"] for r in rows if r["p_snap_over_p_c"] is None})
    for lam in mono:
        ax.axvline(lam, color=GREY, lw=0.6, ls=":")
    ax.set_xlabel(r"$\lambda = 2\,[3(1-\nu^2)]^{1/4}\sqrt{H/h}$")
    ax.set_ylabel(r"axisymmetric snap pressure $p_\mathrm{snap} / p_c$")
    title = ("clamped spherical caps under uniform pressure, $\\nu = 0.3$ unless stated\n"
             "(published values: Teng & Rotter 1989a, Table 1)")
    if mono:
        title += f"; dotted: no fold up to ${P_MAX:g}\\,p_c$"
    ax.set_title(title, fontsize="small")
    ax.grid(alpha=0.3)
    # lower right: below the curves once they have risen past lambda = 6
    ax.legend(loc="lower right", title="this model unless a source is named")
    return fig


def plot_shallow(limit: Sequence[dict[str, Any]]) -> Any:
    """``p_snap / p_c`` relative to Budiansky against ``h/R``: the approach to the shallow limit.

    Above all depths; below the detail near ``h/R = 0``, where the thinnest cap (``h/R = 1e-4``) and the
    extrapolated limit lie a marker's width apart on the upper panel's scale.
    """
    from contin.plot.framing import show_detail
    from contin.plot.style import WIDTH

    plt = _plt()
    # a column: side by side at a page's width the detail would be 2.2 in wide
    fig, (ax, zoom) = plt.subplots(2, 1, figsize=(WIDTH, 6.6), gridspec_kw={"height_ratios": [1.35, 1.0]},
                                   layout="constrained")
    hr = np.array([1.0 / d for d in DEPTHS])
    # sizes nest where two lambdas meet (5 and 6 at h/R = 0.0025, 5 and 7 at the limit): the smaller
    # mark is drawn above the larger, so both outlines show
    markers = "osD^v<>"
    sizes = (5.5, 7.0, 5.5, 4.5, 5.0, 5.5, 5.5)
    x_box, y_box = (-1.2e-4, 1.12e-3), (-2.6, -1.5)
    off_box = []
    for k, row in enumerate(r for r in limit if r["budiansky"]):
        ref = row["budiansky"]
        vals = 100 * (np.array([row[f"p_{d:g}"] for d in DEPTHS]) / ref - 1.0)
        xs = np.linspace(0.0, 0.0105, 20)
        fit = 100 * ((row["p_shallow"] + row["slope_c"] * xs) / ref - 1.0)
        p0 = 100 * row["shallow_vs_budiansky"]
        ms, marker = sizes[k % len(sizes)], markers[k % len(markers)]
        z = 4.0 + (8.0 - ms) / 10.0
        # the detail's abscissa in units of 1e-3 (tick labels without an offset factor)
        for a, f in ((ax, 1.0), (zoom, 1e3)):
            line, = a.plot(f * hr, vals, ls="none", marker=marker, ms=ms, zorder=z, label=f"$\\lambda = {row['lambda']:g}$")
            a.plot(f * xs, fit, color=line.get_color(), lw=0.8, zorder=2)
            # the extrapolated limit, the figure's point: hollow and above the computed ones, which show
            # through it where they are a marker's width away
            a.plot([0.0], [p0], marker=marker, color=line.get_color(), mfc="none", mew=1.1, ms=ms + 1.5,
                   zorder=z + 2.0)
        if not y_box[0] <= p0 <= y_box[1]:
            off_box.append(f"{row['lambda']:g}")
    ax.axhline(0.0, color="k", lw=0.8, zorder=1)
    for a in (ax, zoom):
        a.grid(alpha=0.3)
    ax.set_xlabel(r"$h/R$ (at fixed $\lambda$)")
    zoom.set_xlabel(r"$10^3\,h/R$")
    for a in (ax, zoom):  # one above the other: each its own label
        a.set_ylabel(r"$p_\mathrm{snap}/p_\mathrm{Budiansky} - 1$  [%]")
    ax.set_xlim(-0.0005, 0.0105)
    ax.set_title("finest mesh, $R/h$ = 100, 400, 1000, 10000 (filled);\n"
                 "open: shallow limit $h/R \\to 0$ of the lines $p_0 + c\\,h/R$ through $R/h$ = 1000, 10000",
                 fontsize="small", loc="left")
    show_detail(ax, zoom, (x_box, y_box), scale=(1e3, 1.0),
                title="detail of the grey box" + (f" ($\\lambda = {', '.join(off_box)}$ below)" if off_box else ""))
    ax.legend(ncol=2, loc="upper left")
    return fig


def _smooth(c: dict[str, Any], x: str, y: str) -> tuple[np.ndarray, np.ndarray]:
    """The branch ``c`` (a :func:`pressure_curve` or the Bathe curve) smooth between its stored points."""
    return smooth_path(c[x], c[y], c.get("d" + x), c.get("d" + y), c["s"])


def plot_curves(curves: dict[float, dict[str, Any]], shapes: Sequence[float]) -> Any:
    """``p/p_c`` against pole and average deflection, and the deflected shape at the first fold."""
    from contin.plot.style import WIDTH

    plt = _plt()
    # the two load-deflection panels side by side (one ordinate), the shapes at the snap below them
    # at the page's width; the curves' legend is the upper row's own, under its panels
    fig = plt.figure(figsize=(WIDTH, 6.4), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.25, 1.0])
    axes = [*top.subplots(1, 2, sharey=True), bottom.subplots()]
    for lam, c in curves.items():
        line, = axes[0].plot(*_smooth(c, "w_over_h", "p_over_p_c"), lw=1.1, label=f"$\\lambda = {lam:g}$")
        axes[1].plot(*_smooth(c, "w_avg_over_h", "p_over_p_c"), lw=1.1, color=line.get_color())
        if c["folds"]:
            f = c["folds"][0]
            axes[0].plot(f["w_over_h"], f["p_over_p_c"], "o", color=line.get_color(), ms=5)
            axes[1].plot(f["w_avg_over_h"], f["p_over_p_c"], "o", color=line.get_color(), ms=5)
            if lam in shapes:
                axes[2].plot(f["r_over_a"], f["deflection_over_h"], color=line.get_color(), lw=1.2,
                             label=f"$\\lambda = {lam:g}$: $p = {f['p_over_p_c']:.3f}\\,p_c$")
    axes[0].set_xlabel("pole deflection $w/h$")
    axes[1].set_xlabel(r"average deflection $(V_0 - V)/(\pi a^2 h)$")
    axes[0].set_ylabel("$p/p_c$")
    for ax in axes[:2]:
        ax.set_ylim(0.0, 1.3)
        ax.grid(alpha=0.3)
    axes[0].set_xlim(0.0, 8.0)
    axes[1].set_xlim(0.0, 3.0)
    top.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncol=len(curves))
    top.suptitle(f"clamped caps, $R/h = {R_OVER_H:g}$, $N = 200$, $\\nu = 0.3$ (dots: first fold; traced up to "
                 "$1.4\\,p_c$);\nthe same curves against the pole (left) and the average deflection (right)",
                 fontsize="small")
    axes[2].set_xlabel("reference radius $r/a$ (0: pole, 1: clamped edge)")
    axes[2].set_ylabel("downward deflection\n" r"$(z_\mathrm{ref} - z)/h$ at the first fold")
    axes[2].set_title("deflected shape at the snap: the mechanism changes near $\\lambda = 5.5$", fontsize="small")
    axes[2].axhline(0.0, color="k", lw=0.6)
    axes[2].grid(alpha=0.3)
    axes[2].legend()
    return fig


def plot_bathe(curve: dict[str, Any]) -> Any:
    """The Bathe cap: our load-deflection curve against the two published ones."""
    from contin.plot.style import COLORS, RED, WIDTH

    plt = _plt()
    fig, ax = plt.subplots(figsize=(WIDTH, 4.2), layout="constrained")
    ax.plot(*_smooth(curve, "w_over_h", "q_norm"), "-", color="k", lw=1.2, zorder=2,
            label=f"this model, $N = {curve['N']}$ ($\\lambda = {curve['lambda']:.2f}$)")
    # the two sources' points lie a marker's width apart at w/h = 0.45 and 1.0: small filled triangles
    # above large hollow circles keep both visible
    ax.plot(*zip(*BATHE_B_POINTS), "o", color=COLORS[0], mfc="none", ms=7.5, mew=1.0, zorder=3,
            label="Bathe et al. (1975)")
    ax.plot(*zip(*BATHE_TR_POINTS), "^", color=RED, ms=4.5, zorder=4, label="Teng & Rotter (1989a), Fig. 13")
    ax.set_xlabel("apex deflection $w_c / h$")
    ax.set_ylabel("load $q\\,(a/h)^4 / E$")
    ax.set_title("clamped cap $R = 100$ in, $h = 0.5$ in, $\\phi_0 = 7.1°$, $\\nu = 0.3$\n"
                 "(published points as digitised in AQUINAS Example GNA03)", fontsize="small")
    ax.set_xlim(0.0, 3.0)
    ax.set_ylim(0.0, 16.0)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left")
    return fig


# ---- the study ------------------------------------------------------------------------------------
def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("classical", "clamped caps under pressure: axisymmetric snap and pressure-deflection curves")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    t_start = time.perf_counter()
    sizes = (100, 200, 400, 800) if args.full else (100, 200, 400)
    finest = sizes[-1]
    rows: list[dict[str, Any]] = []

    # (a) three meshes (four with --full) at every depth; the default refines only R/h = 400
    for rh in DEPTHS:
        meshes = sizes if (args.full or rh == R_OVER_H) else (finest,)
        lams = LAMBDAS if rh == R_OVER_H else tuple(BUDIANSKY)
        say(args.quiet, f"snap pressures at R/h = {rh:g}, N = {', '.join(map(str, meshes))} ...")
        for N in meshes:
            rows.extend(snap_pressure(lam, N, rh) for lam in lams)

    # candidate causes of the offset (one cap each by default, every Budiansky lambda with --full)
    lams = tuple(BUDIANSKY) if args.full else (5.0, 8.0)
    say(args.quiet, "variants: nu, lambda definition, kappa11 length, pinned edge ...")
    for lam in lams:
        rows.append(snap_pressure(lam, 200, 1000.0, variant="nu=0.25", nu=0.25))
        rows.append(snap_pressure(lam, 200, 1000.0, variant="nu=1/3", nu=1.0 / 3.0))
        rows.append(snap_pressure(lam, 200, 1000.0, variant="reference (nu=0.3, N=200, R/h=1000)"))
        rows.append(snap_pressure(lam, 200, 100.0, variant="lambda from base radius", lambda_def="base"))
        rows.append(snap_pressure(lam, 200, 1000.0, variant="kappa11_length=reference", kappa11_length="reference"))
        rows.append(snap_pressure(lam, 200, 1000.0, variant="pinned", boundary="pinned"))
        rows.append(snap_pressure(lam, 200, 1000.0, variant="ds_max=0.01", ds_max=0.01))
    # Poisson's ratio in the shallow limit, at every Budiansky lambda
    for lam in BUDIANSKY:
        rows.append(snap_pressure(lam, 400, 10000.0, variant="nu=1/3, shallow (R/h=10000, N=400)", nu=1.0 / 3.0))
    # the clamp: edge rotation at the fold against N
    for N in sizes:
        rows.append(snap_pressure(6.0, N, 1000.0, variant="clamp check"))

    # the steep part: fine lambda scan with small steps, counting the maxima of p before the snap
    say(args.quiet, "fine scan of the steep part ...")
    fine_lams = FINE_LAMBDAS if args.full else FINE_LAMBDAS[::2]
    fine = []
    for lam in fine_lams:
        pr = clamped_cap(lam, 200, R_OVER_H)
        c = pressure_curve(pr, ds_max=0.01 if args.full else 0.02, w_max=3.0, p_max=1.3)
        maxima = [f for f in c["folds"] if f["w_over_h"] < 3.0]
        # a maximum of p: p decreases after it (the local maxima among the folds before w = 3 h)
        p = c["p_over_p_c"]
        n_max = int(np.sum((p[1:-1] > p[:-2]) & (p[1:-1] >= p[2:])))
        first = maxima[0] if maxima else None
        fine.append({"lambda": lam, "R_over_h": R_OVER_H, "N": 200,
                     "p_snap_over_p_c": first["p_over_p_c"] if first else None,
                     "w_over_h": first["w_over_h"] if first else None,
                     "max_deflection_over_h": max(first["deflection_over_h"]) if first else None,
                     "r_over_a_of_max": first["r_over_a"][int(np.argmax(first["deflection_over_h"]))] if first else None,
                     "folds_before_3h": len(maxima), "maxima_of_p": n_max})

    conv = convergence(rows)
    limit = shallow_limit(rows, finest)

    # (b) pressure-deflection curves
    say(args.quiet, "pressure-deflection curves ...")
    curve_lams = (4.0, 5.0, 5.5, 6.0, 7.0, 8.0)
    curves = {lam: pressure_curve(clamped_cap(lam, 200, R_OVER_H), ds_max=0.02 if args.full else 0.04)
              for lam in curve_lams}
    curve_rows = [{"lambda": lam, "R_over_h": R_OVER_H, "N": 200, "p_over_p_c": float(p), "w_over_h": float(w),
                   "w_avg_over_h": float(wa)}
                  for lam, c in curves.items() for p, w, wa in zip(c["p_over_p_c"], c["w_over_h"], c["w_avg_over_h"])]
    fold_rows = [{"lambda": lam, "fold": i, "p_over_p_c": f["p_over_p_c"], "w_over_h": f["w_over_h"],
                  "w_avg_over_h": f["w_avg_over_h"],
                  "max_deflection_over_h": max(f["deflection_over_h"]),
                  "r_over_a_of_max": f["r_over_a"][int(np.argmax(f["deflection_over_h"]))]}
                 for lam, c in curves.items() for i, f in enumerate(c["folds"])]
    say(args.quiet, "the Bathe cap ...")
    bathe_N = 400 if args.full else 200
    bathe_curve, bathe_rows = bathe_comparison(bathe_N)
    bathe_curve["N"] = bathe_N
    elapsed = time.perf_counter() - t_start

    # ---- output
    write_csv(out / "snap.csv", rows)
    write_csv(out / "convergence.csv", conv)
    write_csv(out / "shallow_limit.csv", limit)
    write_csv(out / "fine_scan.csv", fine)
    write_csv(out / "curves.csv", curve_rows)
    write_csv(out / "bathe.csv", bathe_rows)
    ref_rows = {r["lambda"]: r for r in rows if r["variant"] == "clamped" and r["R_over_h"] == R_OVER_H
                and r["N"] == finest}
    write_json(out / "summary.json", {
        "nu": NU, "R_over_h": R_OVER_H, "sizes": list(sizes), "depths": list(DEPTHS), "full": bool(args.full),
        "published": {"budiansky_1959": BUDIANSKY, "dumir_nath_1984": DUMIR_NATH, "teng_rotter_1989a": TENG_ROTTER,
                      "source": "Teng & Rotter (1989a), Computers & Structures 31(2) 211-233, Table 1, as "
                                "reproduced in AQUINAS (github.com/AchilleasF/AQUINAS-FE, "
                                "src/Examples/input_Example_GNA05.csv)"},
        "rel_diff_budiansky_R400": {str(k): r.get("rel_diff") for k, r in ref_rows.items() if r.get("budiansky")},
        "convergence": conv, "shallow_limit": limit, "fine_scan": fine, "curve_folds": fold_rows,
        "bathe": {"lambda": bathe_curve["lambda"], "R_over_h": bathe_curve["R_over_h"], "N": bathe_N,
                  "folds": bathe_curve["folds"], "monotonic": bathe_curve["monotonic"], "points": bathe_rows},
        "to_compare_once_the_loads_exist": MESCALL_CAP,
        "seconds": elapsed, "rows": rows})
    save_figure(plot_snap(rows, finest, fine), out, "classical_snap")
    save_figure(plot_shallow(limit), out, "classical_shallow")
    save_figure(plot_curves(curves, (5.0, 5.5, 6.0)), out, "classical_curves")
    save_figure(plot_bathe(bathe_curve), out, "classical_bathe")

    # ---- tables
    print(f"(a) snap pressure, clamped, R/h = {R_OVER_H:g}, nu = {NU}:")
    print_table([r for r in rows if r["variant"] == "clamped" and r["R_over_h"] == R_OVER_H],
                ["lambda", "N", "p_snap_over_p_c", "budiansky", "rel_diff", "teng_rotter", "rel_diff_teng_rotter",
                 "w_over_h", "steps"], digits=5)
    print("\nmesh convergence (three finest meshes):")
    print_table(conv, ["lambda", "R_over_h", "N", "p_1", "p_2", "p_3", "change_12", "change_23", "order", "p_rich"],
                digits=7)
    print(f"\nshallow limit (N = {finest}): p = p_0 + c h/R through R/h = {DEPTHS[-2]:g} and {DEPTHS[-1]:g}:")
    print_table(limit, ["lambda", "p_100", "p_400", "p_1000", "p_10000", "p_shallow", "slope_c", "fit_error_100",
                        "deep_effect_100", "deep_effect_100_rel", "shallow_vs_budiansky", "shallow_vs_teng_rotter",
                        "r100_vs_teng_rotter"], digits=5)
    print("\ncandidate causes of the offset:")
    print_table([r for r in rows if r["variant"] != "clamped"],
                ["variant", "lambda", "N", "R_over_h", "lambda_rise", "lambda_base", "p_snap_over_p_c", "rel_diff",
                 "edge_chord_rotation", "edge_tangent_rotation"], digits=5)
    print("\nsteep part (fine scan, R/h = 400, N = 200):")
    print_table(fine, ["lambda", "p_snap_over_p_c", "w_over_h", "max_deflection_over_h", "r_over_a_of_max",
                       "folds_before_3h", "maxima_of_p"], digits=5)
    print("\n(b) folds of the pressure-deflection curves (R/h = 400, N = 200):")
    print_table(fold_rows, ["lambda", "fold", "p_over_p_c", "w_over_h", "w_avg_over_h", "max_deflection_over_h",
                            "r_over_a_of_max"], digits=5)
    print(f"\nBathe cap (lambda = {bathe_curve['lambda']:.3f}, R/h = {bathe_curve['R_over_h']:g}, N = {bathe_N}, "
          f"folds: {bathe_curve['folds']}):")
    print_table(bathe_rows, ["source", "w_over_h", "q_published", "q_ours", "rel_diff", "dw_at_q", "distance"],
                digits=4)
    print(f"\nrelative difference to Budiansky at R/h = {R_OVER_H:g}, N = {finest}: " + ", ".join(
        f"lambda {k:g}: {r['rel_diff']:+.2%}" for k, r in ref_rows.items() if r.get("rel_diff") is not None))
    print(f"computed in {elapsed:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))
