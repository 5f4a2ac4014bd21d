"""Scene runner for indentation by a rigid sphere or plate (``load.kind = "sphere" | "plate"``).

The indenter travel ``w_b`` is prescribed (displacement control of the indenter).  The runner traces
from the first touch of the barrier until the snap, jumps to the stable state at the same ``w_b``
(the shell everts and leaves the indenter) and keeps loading until ``w_b`` reaches the eversion depth
``2 R (1 - sin phi_hat)`` plus ``continuation.overshoot``, or until the indenter comes within
``2 dhat`` of the base ring, which is held vertically: a plate or a large sphere would then press on
the support itself, so the run ends there (status ``bound``).  The loading, snapping and resuming
is :func:`contin.quasistatic`'s; this module gives it the contact's rules (:func:`snap_rules`,
:func:`snap_point`) and reports the result.

Where the snap is (``docs/model.md#snaps``): the path turns back in ``w_b`` as the contact force
falls to zero.  While the pole is the last point in contact the fold is a sizeable fraction of ``dhat``
inside the barrier and the engine's extended system locates it.  When the last contact point is off
the axis (large spheres and the plate, after the pole has detached) the fold lies a few 1e-8 R before
the meridian leaves the barrier, where the force changes too fast along the path for the engine to
fix it precisely: a loading stretch ends on the event ``F R / (2 pi D) <`` :data:`SNAP_FORCE_NORM`
(or on the engine's fold, at a force below :data:`RELEASE_FORCE_NORM`) and the fold is located from
there with the gap of the meridian's nearest point as the parameter
(:func:`contin_models.contact.release.locate_release_fold`, label ``"release"``).

A plate (and a large sphere) may snap earlier at a finite force: the flattened contact region
buckles inwards into a dimple held by a ring of contact.  Those snaps are jumped like the others;
``summary.json`` lists every snap under ``"snaps"`` and reports as ``w_b_c`` the one after which the
shell has left the indenter (eversion), the snap of the paper.

Special points in ``summary.json``: a snap is ``kind = "fold"`` with ``"parameter": "w_b"`` (the
``F -> 0`` event only if the release fold could not be located; its ``error`` says why); every record
carries ``w`` (= ``w_b``), ``F``, ``w_over_R``,
``F_norm``, ``w_s``, ``Delta_H`` and their normalized forms, ``kappa_p_R``, ``n_contact`` and the range
of nodes in contact (``contact_first``, ``contact_last``; -1 when none).  ``summary.json`` also has
the contact mode on the way to the snap (``contact_mode``: continuous / detach-recontact / detach,
see :func:`contact_mode`; a gap counts once it exceeds ``dhat``), the largest membrane strain over
every stored point (``max_strain``, ``max_strain_at``, ``w_b_at_max_strain_over_R``) and
``warnings``: a strain beyond :data:`contin_models.shell.strain.STRAIN_LIMIT` is reported there and on the
status line.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import contin
from contin.app.scene import TraceResult, branch_columns, special_point_records
from contin.results.branch import Branch, SpecialPoint

from contin.analyses.quasistatic import DEFAULT_JUMP_ATTEMPTS, QuasiStaticResult, SnapRules, bound_passed
from contin_models.contact.indentation import ShellIndentation, ShellIndentationForce
from contin_models.contact.release import ReleaseFoldError, locate_release_fold
from contin_models.shell.strain import strain_peak, strain_warning

from .build import contact_problem, point_problem, pole_moved, rest_stiffness, watch_harmonics
from .deformed import LoadSketch, shapes_drawer, shell_shapes
from .labels import force_axes, scene_title
from .schema import STABILITY_COLUMNS, Scene, instability_text, record_instability

__all__ = ["run_contact", "run_contact_force", "contact_mode", "snap_point", "snap_rules", "snap_event",
           "SNAP_FORCE_NORM", "SNAP_ARMED_NORM", "FORCE_START_NORM", "MAX_SNAPS", "CONTACT_STEPS_PER_NODE"]

#: ``F R / (2 pi D)`` below which a loading stretch counts as having reached the snap (F -> 0).
SNAP_FORCE_NORM = 1e-4
#: ``F R / (2 pi D)`` the force must have reached before its fall to :data:`SNAP_FORCE_NORM` counts as the snap: in the
#: first steps after the first touch the force is of the order of the corrector's tolerance and may rise above
#: SNAP_FORCE_NORM and dip below it again.
SNAP_ARMED_NORM = 1e-3
#: A fold of the travel at a force below this (``F R / (2 pi D)``) is the release of the last contact
#: point, located again in that point's gap (:func:`snap_point`).
RELEASE_FORCE_NORM = 1e-3
#: ``F R / (2 pi D)`` at which a force-controlled trace takes over from displacement control.
FORCE_START_NORM = 0.05
#: Target load of a force-controlled trace in the same unit (beyond any limit point; the indenter's
#: travel bounds end the trace first).
FORCE_END_NORM = 100.0
#: Relative travel past the snap at which the jump minimises, tried in turn (a hair past the snap
#: no equilibrium is near, so the minimisation has to leave for the distant stable state).
_OVERSHOOTS = (1e-6, 1e-5, 1e-4, 1e-3)
#: Snaps a trace may make before eversion (a plate dimples, then everts; more means the trace is lost); a
#: force-controlled trace may also make the contact steps of :data:`CONTACT_STEPS_PER_NODE`.
MAX_SNAPS = 4
#: Snaps a force-controlled trace may make besides those, per node of the meridian: under a dead load the
#: contact ring of a wide indenter (``r/R`` about 1 or more) can widen node by node, each node a small snap
#: of the discrete shell (a jump of less than a node spacing in travel) before the cap's own snap.
CONTACT_STEPS_PER_NODE = 1
#: What the diagram's axes show.
def _plot_options(scene: Scene, D: float) -> dict[str, Any]:
    """The diagram in the cap's reference units (indenter travel w_b/R, force F R/(2 pi D)), titled by the scene.

    ``branch.csv`` repeats the travel as ``w`` and ``w_over_R`` (the point load's columns): labelled and
    scaled as ``w_b``, and so are the shell's own lengths over ``R``.
    """
    R = scene["shell"]["R"]
    options = force_axes("w_b", R, D, w_symbol="w_b", scaled={"w_b_over_R": "w_b", "w_over_R": "w_b", "F_norm": "F"})
    options["axis_labels"].update(w=options["axis_labels"]["w_b"], Delta_H_over_R=r"$\Delta H/R$")
    options["scale"]["w"] = 1.0 / R
    options["same_as"]["w"] = "w_b"
    return {**options, "title": scene_title(scene), "zero_line": True}
_OBS = ("w_b", "F", "w_b_over_R", "F_norm", "w_s", "w_s_over_R", "Delta_H", "Delta_H_over_R", "kappa_p_R",
        "n_contact", "contact_first", "contact_last")


def snap_rules(problem: ShellIndentation) -> SnapRules:
    """How a displacement-controlled indentation leaves its snap (for :func:`contin.quasistatic`).

    The jump minimises at a travel ``w_b (1 + eps)`` for each ``eps`` of ``_OVERSHOOTS`` with the
    engine's default kicks in units of R; a landing is a snap when the pole has moved by more than
    1e-3 R.  An overshoot that pushes the indenter through a node (a short-range barrier leaves less
    room than ``eps w_b``) ends the attempts: larger ones only go further.  The landing is stated at the
    snap's own travel (the detached landing does not depend on ``w_b``).
    """
    return SnapRules(attempts=tuple((eps, None) for eps in _OVERSHOOTS), overshoot_unit="fold",
                     perturbation_unit=problem.R, separation=pole_moved(problem, "w_s", problem.R),
                     min_separation=1e-3, give_up_on=(contin.NonFiniteError,))


#: The overshoot of the last snap attempt of a force-controlled indentation, after the engine's: where a wide
#: indenter's contact ring moves node by node, the force along the path ripples at each node by a fraction of
#: a percent; a smaller overshoot lands back next to the limit load, or lands a hair short of the separation
#: that makes it a snap and cannot be carried back to the limit load by Newton's method.
FORCE_LAST_OVERSHOOT = 1e-3


def indentation_force_snap_rules(forced: ShellIndentationForce, R: float) -> SnapRules:
    """How a force-controlled indentation leaves a limit load: the engine's attempts and overshoot, then
    :data:`FORCE_LAST_OVERSHOOT`; the landing restated at the limit load, with the kicks in units of R and the
    landing measured by the pole's movement over R (:func:`contin_models.shell_scene.build.pole_moved`), so
    that a scene snaps alike in any units."""
    return SnapRules(attempts=DEFAULT_JUMP_ATTEMPTS + ((FORCE_LAST_OVERSHOOT, None),), perturbation_unit=R,
                     separation=pole_moved(forced, "w_s", R), min_separation=1e-3)


class _ArmedForce:
    """``F R / (2 pi D)`` once it has reached :data:`SNAP_ARMED_NORM` at some point the trace evaluated, infinite
    before: the test function of :func:`snap_event`, which a non-finite value never triggers."""

    def __init__(self, problem: contin.Problem) -> None:
        self.force = problem.observables["F_norm"]
        self.armed = False

    def __call__(self, u: np.ndarray, p: float) -> float:
        value = float(self.force(u, p))
        self.armed = self.armed or value >= SNAP_ARMED_NORM
        return value if self.armed else math.inf


def snap_event(problem: contin.Problem) -> contin.Event:
    """The terminal event on which a loading stretch has reached its snap: ``F R / (2 pi D)`` of ``problem`` falls
    to :data:`SNAP_FORCE_NORM` after it has reached :data:`SNAP_ARMED_NORM` (the release fold beyond it is located
    by :func:`snap_point`).  One event per trace: it keeps whether the force has been armed."""
    return contin.crossing(_ArmedForce(problem), SNAP_FORCE_NORM, direction=-1, terminal=True, name="F -> 0")


def _snaps(problem: contin.Problem, qs: QuasiStaticResult) -> list[dict[str, Any]]:
    """Each snap's point, the branch it ends and the nodes in contact after it."""
    return [{"point": fold, "branch": k, "contact_after": int(problem.evaluate_one("n_contact", j.u_to, j.p))}
            for k, (fold, j) in enumerate(zip(qs.folds, qs.jumps))]


def _labels(n: int) -> list[str]:
    return ["loading" if k == 0 else f"loading after snap {k}" for k in range(n)]


def run_contact(scene: Scene, progress: bool, settings: contin.Settings, w_end: float) -> TraceResult:
    """Trace a sphere or plate indentation through its snaps to ``w_b = w_end`` (see the module docstring)."""
    problem = contact_problem(scene)
    # the indenter may not reach the base ring: it is held vertically, so the indenter would press
    # on the support itself (a plate or a large sphere gets there before eversion); the located
    # snaps alone end a stretch (the plate's dimple branch flickers in stability between nodes, B3)
    qs = contin.quasistatic(problem, problem.reference_unknowns(), 0.0, w_end, settings, max_snaps=MAX_SNAPS,
                            snap=snap_rules(problem), locate_snap=lambda br: snap_point(problem, br, settings.tol),
                            stop_at_branch_points=False, check_stability=False, events=[snap_event(problem)],
                            bounds={"base_gap": (2.0 * problem.dhat, None)})
    return _result(problem, scene, qs.branches, qs.jumps, _labels(len(qs.branches)), qs.message if qs.failed else "",
                   _snaps(problem, qs))


def run_contact_force(scene: Scene, progress: bool, settings: contin.Settings, w_end: float) -> TraceResult:
    """Trace a sphere or plate indentation under a dead load on the indenter (``load.control = "force"``).

    Without contact the indenter floats (its travel is undetermined), so displacement control first
    brings it from the first touch to the small load ``F R / (2 pi D)`` = :data:`FORCE_START_NORM`;
    from that contact state :func:`contin.quasistatic` raises the load on
    :class:`contin_models.contact.indentation.ShellIndentationForce`.  At each limit point of the load (a fold
    in ``F``: the maximum of the force along the displacement path) the shell snaps, at that load, to
    the everted shell still pressed by the indenter, and loading goes on until the indenter travel
    reaches ``w_end`` or the indenter comes within ``2 dhat`` of the base ring, along a branch or by a
    snap's landing (a plate usually snaps down onto the base ring at its last limit load).
    """
    problem = contact_problem(scene)
    forced = watch_harmonics(scene, ShellIndentationForce.from_displacement(problem))
    f_unit = 2.0 * math.pi * problem.D / problem.R
    start = contin.crossing("F_norm", FORCE_START_NORM, direction=+1, terminal=True, name="start of force control")
    lead = contin.continuation(problem, problem.reference_unknowns(), 0.0, settings, p_max=w_end, events=[start],
                               bounds={"base_gap": (2.0 * problem.dhat, None)})
    if lead.status != "event":
        return _result(forced, scene, [], [], [], f"displacement control did not reach the start load of force "
                       f"control ({lead.message})", [], control="force")
    U, F = forced.from_displacement_state(lead.u[-1], lead.p[-1])
    stiffness = rest_stiffness(point_problem(scene, "force"), problem.R)
    # the load weighed as on the point-loaded cap (rest_stiffness: a force k R counts as R); the
    # target load is never reached: the travel bounds end the sweep
    max_snaps = MAX_SNAPS + CONTACT_STEPS_PER_NODE * scene["shell"]["N"]
    base_ring = {"base_gap": (2.0 * problem.dhat, None)}
    qs = contin.quasistatic(forced, U, F, FORCE_END_NORM * f_unit, settings, max_snaps=max_snaps,
                            param_weight=1.0 / (stiffness * problem.R), snap=indentation_force_snap_rules(forced, problem.R),
                            bounds={"w_b": (None, w_end), **base_ring})
    failure = "" if qs.status in ("completed", "stopped") and all(
        br.status in ("bound", "event") for br in qs.branches) else qs.message
    if not failure and qs.jumps and len(qs.jumps) == len(qs.branches):
        # the sweep ended on a landing beyond a travel bound: most often a plate that snaps down
        # onto the base ring, which then carries any further load
        last = qs.jumps[-1]
        support = "; the indenter has come down to the base ring, which carries any further load" \
            if bound_passed(forced, base_ring, last.u_to, last.p) else ""
        last.message = f"{last.message}; {qs.message}{support}"
    return _result(forced, scene, qs.branches, qs.jumps, _labels(len(qs.branches)), failure, _snaps(forced, qs),
                   control="force")


def snap_point(problem: ShellIndentation, br: Branch, tol: float) -> SpecialPoint | None:
    """Where a loading stretch snaps: its located fold in ``w_b``, or the release fold beyond ``F -> 0``.

    On the ``F -> 0`` event the release fold is located with the last contact point's gap as the
    parameter (:mod:`contin_models.contact.release`) and added to the branch's special points; if that
    fails, the event itself is the snap and the reason is kept in its ``info``.  A fold the engine
    located at a force below :data:`RELEASE_FORCE_NORM` is that release fold too: it is located again
    in the gap, from the last stored point before it, so that its force is as precise as its travel.
    """
    if br.status != "event" or not br.special_points:
        return None
    last = br.special_points[-1]
    if last.kind == "fold" and abs(last.observables.get("F_norm", math.inf)) < RELEASE_FORCE_NORM and len(br.p) >= 2:
        # the engine turned round a release fold (the barrier over its support makes it wide enough),
        # but there the force changes so fast along the path that the fold's F is fixed to a few
        # digits only; the gap of the last contact point resolves it: start on the stable side
        try:
            rf = locate_release_fold(problem, br.u[-2], br.p[-2], tol=tol)
        except ReleaseFoldError as exc:
            last.info["release"] = f"not refined: {exc}"
            return last
        last.p, last.u = rf.w_b, rf.u
        last.observables = problem.evaluate_observables(rf.u, rf.w_b)
        last.residual = rf.residual
        last.info.update({"node": rf.node, "gap": rf.gap, "dw_b_dgap": rf.dw_dx,
                          "located_by": "the gap of the last contact point as parameter"})
        return last
    if last.kind == "fold" or last.label != "F -> 0":
        return last
    try:
        rf = locate_release_fold(problem, br.u[-1], br.p[-1], tol=tol)
    except ReleaseFoldError as exc:
        last.info["error"] = f"release fold not located: {exc}"
        return last
    fold = SpecialPoint(kind="fold", p=rf.w_b, u=rf.u, observables=problem.evaluate_observables(rf.u, rf.w_b),
                        residual=rf.residual, located=True, s=float(br.s[-1]), index=len(br.p) - 1,
                        label="release",
                        info={"stable_before": True, "stable_after": False, "node": rf.node, "gap": rf.gap,
                              "dw_b_dgap": rf.dw_dx, "located_by": "the gap of the last contact node as parameter"})
    br.special_points.append(fold)
    br.message += f"; release fold located at w_b = {rf.w_b:.10g} (node {rf.node}, gap {rf.gap:.3g})"
    return fold


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


def _flat(observables: dict[str, float]) -> dict[str, float]:
    """The observables every record carries at its top level (``w``, ``w_over_R``: the indenter travel)."""
    out = {name: float(observables[name]) for name in _OBS if name in observables}
    if "w_b" in observables:
        out["w"], out["w_over_R"] = float(observables["w_b"]), float(observables["w_b_over_R"])
    return out


def _result(problem: ShellIndentation | ShellIndentationForce, scene: Scene,
            branches: list[Branch], jumps: list, labels: list[str], failure: str, snaps: list[dict[str, Any]],
            control: str = "displacement") -> TraceResult:
    generic = TraceResult.from_branches(branches, jumps, problem=problem, x="w_b", y="F", labels=labels,
                                        failure=failure)
    records = special_point_records(branches, jumps, generic.jump_observables, generic.parameter_name,
                                    fields=lambda spt: _flat(spt.observables))
    for rec in records[len(records) - 2 * len(jumps):]:
        rec.update(_flat(rec["observables"]))
    R = problem.R
    summary: dict[str, Any] = {
        "indenter": scene["load"]["kind"], "radius": scene["load"]["radius"] if scene["load"]["kind"] == "sphere" else None,
        "K_c": problem.K, "dhat": problem.dhat, "D": problem.D, "F_unit": 2.0 * math.pi * problem.D / R,
        "control": control, "classification": None,
        "classification_note": "the classification is defined on the bilateral point load (load.kind = \"point\")",
    }
    # the travel from the observables: under force control the parameter p is the load, not w_b
    observed = [sn["point"].observables or problem.evaluate_observables(sn["point"].u, sn["point"].p) for sn in snaps]
    summary["snaps"] = [{"w_b": float(obs["w_b"]), "kind": sn["point"].kind, "label": sn["point"].label,
                         "F": float(obs["F"]), "Delta_H": float(obs["Delta_H"]),
                         "nodes_in_contact_after": sn["contact_after"]} for sn, obs in zip(snaps, observed)]
    # the snap of the paper is the one after which the shell has left the indenter (eversion); a plate
    # or a large sphere may snap before it into a dimpled shape that stays in contact
    main = next((sn for sn in snaps if sn["contact_after"] == 0), snaps[-1] if snaps else None)
    if control == "force" and snaps:
        # under a dead load the snap is at the limit load; the everted shell stays under the indenter
        first = snaps[0]["point"]
        landing = jumps[0]
        summary.update({"snap_kind": "fold", "snap_label": "max(F)", "F_snap": float(first.p),
                        "F_snap_norm": float(first.observables["F_norm"]), "w_b_at_snap": float(first.observables["w_b"]),
                        "w_b_at_snap_over_R": float(first.observables["w_b"]) / R,
                        "w_b_after_snap": float(landing.u_to[-1]), "w_b_after_snap_over_R": float(landing.u_to[-1]) / R})
    elif main is not None:
        obs = main["point"].observables
        # the contact mode on the way to that snap; a gap counts as a detachment once it exceeds the
        # barrier's own range dhat (below that the pole is within the contact layer's resolution:
        # lifts of 1e-6 .. 1e-4 R occur for r/R = 0.3 .. 0.5, unchanged by dhat and N)
        gaps = np.concatenate([br.observables["Delta_H"] for br in branches[:main["branch"] + 1]] + [[obs["Delta_H"]]])
        mode, max_gap = contact_mode(gaps, problem.dhat)
        summary.update({"contact_mode": mode, "max_gap_before_snap": max_gap, "contact_mode_gap_tol": problem.dhat})
        summary.update({"snap_kind": main["point"].kind, "snap_label": main["point"].label,
                        "w_b_c": float(main["point"].p), "w_b_c_over_R": float(main["point"].p) / R,
                        "F_at_snap": obs["F"], "Delta_H_at_snap": obs["Delta_H"],
                        "Delta_H_at_snap_over_R": obs["Delta_H_over_R"], "w_s_at_snap_over_R": obs["w_s_over_R"],
                        "kappa_p_R_at_snap": obs["kappa_p_R"]})
    peak = strain_peak(problem, branches, "w_b")
    warning = strain_warning(peak, R, point_load=False, load_label="w_b")
    if peak is not None:
        summary.update(max_strain=peak.value, w_b_at_max_strain_over_R=peak.load / R, max_strain_at=peak.where)
    summary["warnings"] = [warning] if warning else []
    record_instability(summary, records, generic.parameter_name, ("F", "F_norm", "w", "w_over_R"), problem)
    # branch.csv keeps the primary label's "stable" (the traced control's) before the shell's columns
    stability = {"stable": f"stable_{control}", "n_negative": STABILITY_COLUMNS["n_negative"], **STABILITY_COLUMNS}
    cols = branch_columns(branches, stability)
    if "w_b" in cols:
        cols = {"w": cols["w_b"], "F": cols.get("F"), "w_over_R": cols["w_b_over_R"], "F_norm": cols.get("F_norm"),
                **{k: v for k, v in cols.items() if k not in ("F", "F_norm")}}
    shapes = shell_shapes(branches, problem.full_state, getattr(problem, "operator_families", ()), problem.elastic.cap.x,
                          path=scene["output"]["shapes"] == "path",
                          fields={"indenter": lambda spt: problem.c0 - spt.observables.get("w_b", math.nan)})
    plot_options = _plot_options(scene, problem.D)
    shown = (("w_over_R", "w_b/R", "w_b/R"), ("F_norm", "F R/(2 pi D)", r"F R/2\pi D"))
    instability = instability_text(summary, shown)
    if instability and branches and len(branches[0]):
        branches[0].message = f"{branches[0].message}; {instability}"
        plot_options["note"] = instability_text(summary, shown, tex=True)
    sketch = LoadSketch(scene["load"]["kind"], radius=float(scene["load"]["radius"]))
    return TraceResult(branches=generic.branches, jumps=generic.jumps, summary=summary, special_points=records,
                       table=generic.table, csv_columns=cols, x="w_b", y="F", parameter_name=problem.parameter_name,
                       labels=labels, jump_observables=generic.jump_observables, failure=failure,
                       stability=control, plot_options=plot_options,
                       shapes=shapes, draw_shapes=shapes_drawer(shapes, R, problem.parameter_name, plot_options, load=sketch))
