"""Scene runner for indentation by a rigid sphere or plate (``load.kind = "sphere" | "plate"``).

The indenter travel ``w_b`` is prescribed (displacement control of the indenter).  The runner traces
from the first touch of the barrier until the snap, jumps to the stable state at the same ``w_b``
(the shell everts and leaves the indenter) and keeps loading until ``w_b`` reaches the eversion depth
``2 R (1 - sin phi_hat)`` plus ``continuation.overshoot``, or until the indenter comes within
``2 dhat`` of the base ring, which is held vertically: a plate or a large sphere would then press on
the support itself, so the run ends there (status ``bound``).

Where the snap is (``docs/physics.md`` section 4): the path turns back in ``w_b`` as the contact force
falls to zero; the fold is located by the engine's extended system.  When the last contact node is
off the axis (large spheres, after the pole has detached) that fold sits where the node leaves the
barrier's range, where the barrier is only C2, and the continuation can stall within ~1e-7 of it;
the runner therefore also ends a loading stretch when ``F R / (2 pi D)`` falls below
:data:`SNAP_FORCE_NORM` (measured: within 2.4e-7 in ``w_b`` of the end of the branch for r/R = 0.9)
and records that point as the snap (``label`` ``"F -> 0"``).

Special points in ``summary.json``: the snap is ``kind = "fold"`` with ``"parameter": "w_b"`` (or the
``F -> 0`` event, ``kind = "event"``); every record carries ``w`` (= ``w_b``), ``F``, ``w_over_R``,
``F_norm``, ``w_s``, ``Delta_H`` and their normalized forms, ``kappa_p_R``, ``n_contact`` and the range
of nodes in contact (``contact_first``, ``contact_last``; -1 when none).  ``summary.json`` also has
the contact mode on the way to the snap (``contact_mode``: continuous / detach-recontact / detach,
see :func:`contact_mode`; a gap counts once it exceeds ``dhat``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import contin
from contin.branch import Branch
from contin.scene import TraceResult

from .barrier import Plate, Sphere
from .indentation import ShellIndentation

__all__ = ["run_contact", "contact_mode", "SNAP_FORCE_NORM"]

#: ``F R / (2 pi D)`` below which a loading stretch counts as having reached the snap (F -> 0).
SNAP_FORCE_NORM = 1e-6
#: Relative travel past the snap at which the jump minimises, tried in turn (a hair past the snap
#: no equilibrium is near, so the minimisation has to leave for the distant stable state).
_OVERSHOOTS = (1e-6, 1e-5, 1e-4, 1e-3)
_MAX_SNAPS = 4
_OBS = ("w_b", "F", "w_b_over_R", "F_norm", "w_s", "w_s_over_R", "Delta_H", "Delta_H_over_R", "kappa_p_R",
        "n_contact", "contact_first", "contact_last")


def _problem(scene: dict[str, dict[str, Any]]) -> ShellIndentation:
    s, load, c = scene["shell"], scene["load"], scene["contact"]
    indenter = Sphere(load["radius"]) if load["kind"] == "sphere" else Plate()
    return ShellIndentation(R=s["R"], E=s["E"], nu=s["nu"], h=s["h"], phi_hat=s["phi_hat"], N=s["N"],
                            indenter=indenter, K=c["K_c"] or None, dhat=c["dhat"] or None,
                            pole_ratio=s["pole_ratio"])


def _snap(problem: ShellIndentation, u: np.ndarray, w_b: float, tol: float) -> tuple[Any, str]:
    """Jump from the snap point to a distinct stable state at a travel a hair past it."""
    w_s0 = problem.evaluate_one("w_s", u, w_b)
    reasons = []
    for eps in _OVERSHOOTS:
        try:
            jr = contin.jump(problem, u, w_b * (1.0 + eps), tol=tol)
        except contin.JumpError as exc:
            reasons.append(str(exc))
            continue
        moved = abs(problem.evaluate_one("w_s", jr.u_to, jr.p) - w_s0)
        if jr.success and moved > 1e-3 * problem.R:
            # state the snap at the travel where it happens (the detached landing does not depend on w_b)
            return contin.restate_jump(problem, jr, u, w_b), ""
        reasons.append(jr.message if not jr.success else "landed next to the snap point")
    return None, "; ".join(reasons)


def run_contact(scene: dict[str, dict[str, Any]], progress: bool, settings: contin.Settings,
                w_end: float) -> TraceResult:
    """Trace a sphere or plate indentation through its snaps to ``w_b = w_end`` (see the module docstring)."""
    problem = _problem(scene)
    st = settings
    snap_event = contin.crossing("F_norm", SNAP_FORCE_NORM, direction=-1, terminal=True, name="F -> 0")
    branches: list[Branch] = []
    jumps: list[Any] = []
    labels: list[str] = []
    failure = ""
    u, p, origin = problem.reference_unknowns(), 0.0, None
    for k in range(_MAX_SNAPS + 1):
        # the indenter may not reach the base ring: it is held vertically, so the indenter would press
        # on the support itself (a plate or a large sphere gets there before eversion)
        br = contin.continuation(problem, u, p, st, stop_at=("fold",), p_max=w_end, origin=origin,
                                 events=[snap_event], bounds={"base_gap": (2.0 * problem.dhat, None)})
        branches.append(br)
        labels.append("loading" if k == 0 else f"loading after snap {k}")
        if br.status != "event":
            break
        if k == _MAX_SNAPS:
            failure = f"more than {_MAX_SNAPS} snaps before w_b = {w_end:.6g}"
            break
        jr, reason = _snap(problem, br.u[-1], br.p[-1], st.tol)
        if jr is None:
            failure = f"the snap at w_b = {br.p[-1]:.8g} did not land on a stable state ({reason})"
            break
        jumps.append(jr)
        u, p, origin = jr.u_to, jr.p, jr
    return _result(problem, scene, branches, jumps, labels, failure)


def contact_mode(delta_h: np.ndarray, gap_tol: float = 0.0) -> tuple[str, float]:
    """Contact mode of a loading path from its pole gap ``Delta_H`` up to and including the snap.

    ``"continuous"`` (the pole never detaches: ``Delta_H <= gap_tol`` throughout), ``"detach"`` (the
    pole is detached at the snap) or ``"detach-recontact"`` (detached somewhere before the snap,
    touching again at the snap).  Returns the mode and the largest gap before the snap.
    """
    dh = np.asarray(delta_h, dtype=float)
    before = float(dh[:-1].max()) if dh.size > 1 else 0.0
    if dh[-1] > gap_tol:
        return "detach", before
    return ("detach-recontact" if before > gap_tol else "continuous"), before


def _result(problem: ShellIndentation, scene: dict[str, dict[str, Any]], branches: list[Branch], jumps: list,
            labels: list[str], failure: str) -> TraceResult:
    generic = TraceResult.from_branches(branches, jumps, problem=problem, x="w_b", y="F", labels=labels,
                                        failure=failure)
    records = []
    for rec in generic.special_points:
        rec = dict(rec)
        obs = rec.get("observables", {})
        rec["parameter"] = "w_b"
        for name in _OBS:
            if name in obs:
                rec[name] = float(obs[name])
        if "w_b" in obs:
            rec["w"], rec["w_over_R"] = float(obs["w_b"]), float(obs["w_b_over_R"])
        records.append(rec)
    snaps = [r for r in records if r["kind"] == "fold" or r.get("label") == "F -> 0"]
    R = problem.R
    summary: dict[str, Any] = {
        "indenter": scene["load"]["kind"], "radius": scene["load"]["radius"] if scene["load"]["kind"] == "sphere" else None,
        "K_c": problem.K, "dhat": problem.dhat, "D": problem.D, "F_unit": 2.0 * math.pi * problem.D / R,
        "control": "displacement", "classification": None,
        "classification_note": "the classification is defined on the bilateral point load (load.kind = \"point\")",
    }
    if snaps and branches and len(branches[0]):
        # the contact mode on the way to the first snap; a gap counts as a detachment once it exceeds
        # the barrier's own range dhat (below that the pole is within the contact layer's resolution:
        # lifts of 1e-6 .. 1e-4 R occur for r/R = 0.3 .. 0.5, unchanged by dhat and N)
        mode, max_gap = contact_mode(branches[0].observables["Delta_H"], problem.dhat)
        summary.update({"contact_mode": mode, "max_gap_before_snap": max_gap, "contact_mode_gap_tol": problem.dhat})
    if snaps:
        first = snaps[0]
        summary.update({"w_b_c": first["w_b"], "w_b_c_over_R": first["w_b_over_R"], "F_at_snap": first["F"],
                        "Delta_H_at_snap": first["Delta_H"], "Delta_H_at_snap_over_R": first["Delta_H_over_R"],
                        "w_s_at_snap_over_R": first["w_s_over_R"], "kappa_p_R_at_snap": first["kappa_p_R"]})
    cols = dict(generic.csv_columns)
    if all(br.stability_by for br in branches) and branches:
        for label in ("force", "displacement"):
            cols[f"stable_{label}"] = np.concatenate([br.stable_under(label) for br in branches]).astype(int)
        cols["n_negative"] = np.concatenate([br.stability_by["displacement"][0] for br in branches]).astype(int)
        cols["n_negative_force"] = np.concatenate([br.stability_by["force"][0] for br in branches]).astype(int)
    if "w_b" in cols:
        cols = {"w": cols["w_b"], "F": cols.get("F"), "w_over_R": cols["w_b_over_R"], "F_norm": cols.get("F_norm"),
                **{k: v for k, v in cols.items() if k not in ("F", "F_norm")}}
    return TraceResult(branches=generic.branches, jumps=generic.jumps, summary=summary, special_points=records,
                       table=generic.table, csv_columns=cols, x="w_b", y="F", parameter_name="w_b", labels=labels,
                       jump_observables=generic.jump_observables, failure=failure)
