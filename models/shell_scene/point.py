"""The point-indented shell's runs of the scene (``contin trace --model shell``, ``load.kind = "point"``).

The scene traces the whole connected equilibrium path of a spherical cap loaded by a point at its
pole, from the reference state until the shell is everted (the pole past the mirror image of its
start, ``w = 2 R (1 - sin phi_hat)``, by ``continuation.overshoot``), locates every fold in ``w``
and every extremum of ``F`` (the limit points under force control), labels every point's stability
under both controls and classifies the response (``docs/model.md#snaps``,
``docs/model.md#classes``).

The scene keys are :data:`contin_models.shell_scene.schema.SHELL_SCHEMA`'s.  A sphere or plate indenter is
run by :mod:`contin_models.shell_scene.contact` (its docstring describes that ``summary.json``); what
follows is the point load's.

Special points in ``summary.json``
----------------------------------
``"parameter"`` names the quantity that folds: ``"w"`` for a fold of the path in the prescribed
pole displacement (a snap-back under displacement control), ``"F"`` for a local extremum of the
force along the path (a limit point under force control, ``kind = "fold"`` with ``label`` ``max(F)``
or ``min(F)``).  ``"stable_before"`` / ``"stable_after"`` give the stability, under the control in
which the point is a fold (displacement for ``w``, force for ``F``), at the stored points on either
side.  Every record also carries ``w``, ``F``, ``w_over_R``, ``F_norm = F R / (2 pi D)`` and the
residual of its defining system.  Under force control each snap adds two ``"kind": "jump"`` records
(``parameter`` ``"F"``, the load held fixed): ``jump_from`` (the limit point it leaves, with that
point's residual and ``stable_before``) and ``jump_to`` (the stable landing state, ``stable_after``).

Classification (``docs/model.md#classes``)
---------------------------------------------------------------
``monotonous``: no extremum of F and no fold in w on the path.  Otherwise ``bistable`` when F < 0
(below round-off) at some point of the path that is stable under displacement control, else
``monostable``.  ``F_max`` is the first local maximum of F along the path (the force-control snap
load); ``F_min`` is the last local minimum of F along the path, i.e. the minimum on the branch that
reaches eversion (the force-control snap-back load on unloading).

A path cut short (``continuation.max_steps``; thin deep caps wind through many folds: h/R = 0.002,
``phi_hat`` = 0.8 needs 8341 steps to eversion) is completed from the other end: the everted branch
is traced back in ``w`` from the cap's mirror image to its first fold.  Its first minimum of F is
``F_min`` (at h/R = 0.002 it agrees with the whole path's to 1e-11), and a stable stretch of it with
F < 0 shows the cap bistable.  Monotonous and monostable still need the whole path.

``summary.json`` always has ``"classification"``: the class under displacement control; None under
force control (the force path skips the parts between the limit points, so the class is not
defined on it; ``contin classify`` traces the displacement path whatever ``load.control`` says), and
None when the path stopped before eversion without having shown the bistable signature (then
``classification_on_partial_path`` says what the traced part looks like).  ``classification_note``
says which case applies.  :func:`classify_scene` is the model's classifier (``contin classify``).

``max_strain`` is the largest membrane strain over every stored point (``max_strain_at``: ``pole``,
``base`` or ``interior``; ``w_at_max_strain_over_R``).  ``warnings`` lists what the run found
questionable without failing: a strain beyond :data:`contin_models.shell.strain.STRAIN_LIMIT`, which under
a point load means the pole's singular strain has left the material law's range and results near
there can change with N (:mod:`contin_models.shell.strain`).  The status line repeats the warnings.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import contin
from contin.app.restart import RestartError, Start, beyond_end, continue_saved, resume
from contin.app.scene import SceneError, TraceResult, branch_columns, special_point_records, special_point_table
from contin.results.branch import Branch, SpecialPoint
from contin_models.shell import ShellPointLoad
from contin_models.shell.strain import strain_peak, strain_warning

from .build import LOWEST_W, end_of_path, force_snap_rules, point_problem, point_settings
from .deformed import LoadSketch, observed, shapes_drawer, shell_shapes
from .labels import force_axes, scene_title
from .schema import STABILITY_COLUMNS, Scene, eversion_displacement, instability_text, record_instability

#: The load fields of ``summary.json``'s ``first_instability`` for a point load.
_INSTABILITY_FIELDS = ("F", "F_norm", "w", "w_over_R")
#: How the status line and the diagram name the first instability (:func:`instability_text`): in the diagram's units.
_SHOWN = (("w_over_R", "w/R", "w/R"), ("F_norm", "F R/(2 pi D)", r"F R/2\pi D"))

__all__ = ["classify", "path_complete", "came_back", "LOWEST_W", "run_point", "run_point_force", "resume_point", "MAX_SNAPS"]

#: Observables of :class:`ShellPointLoad` reported at every special point.
_OBS = ("w", "F", "w_over_R", "F_norm")
#: Columns of the printed special-point table (header -> record field): which quantity folds and the
#: observables in both units.
_TABLE_COLUMNS = {"folds_in": "parameter", "w": "w", "F": "F", "w/R": "w_over_R", "F_norm": "F_norm"}
#: Relative size (of ``max |F|`` on the path) below which a negative force counts as round-off.
_F_ROUNDOFF = 1e-8

# ---------------------------------------------------------------------------------------------------
# special points and classification
# ---------------------------------------------------------------------------------------------------
def _flat(observables: dict[str, float]) -> dict[str, float]:
    """The observables every record carries at its top level."""
    return {name: float(observables[name]) for name in _OBS if name in observables}


def _point_fields(spt: SpecialPoint) -> dict[str, Any]:
    """The shell's own fields of a special point's record (:func:`contin.app.scene.special_point_records`).

    A limit point (a fold in ``w``, or an extremum of ``F`` declared as a fold in ``F``) carries
    the Morse index on either side and, as ``stability_control``, the control under which it is
    one (the engine's stability label); every point its observables and ``index``.
    """
    out: dict[str, Any] = {}
    if spt.kind == "fold" or spt.info.get("folds") is not None:
        out.update(spt.stability_under())
        if spt.info.get("stability_label") is not None:
            out["stability_control"] = spt.info["stability_label"]
    out.update(_flat(spt.observables))
    out["index"] = int(spt.index)
    return out


def classify(branch: Branch, records: list[dict[str, Any]], D: float, R: float) -> dict[str, Any]:
    """Classify a displacement-controlled path (``docs/model.md#classes``).

    Parameters
    ----------
    branch : Branch
        The traced path with stability data (label ``"displacement"``).
    records : list of dict
        Its special-point records (see :func:`_records`).
    D, R : float
        Bending stiffness and sphere radius (for the normalized force).

    Returns
    -------
    dict
        ``classification``, ``F_max``, ``w_at_F_max``, ``F_min``, ``w_at_F_min`` (None when absent),
        their normalized forms ``F_max_norm``, ``w_at_F_max_over_R``, ... and the counts of folds.
    """
    F = branch.observables["F"]
    stable_d = branch.stable_under("displacement")
    maxima = [r for r in records if r.get("parameter") == "F" and r.get("label") == "max(F)"]
    minima = [r for r in records if r.get("parameter") == "F" and r.get("label") == "min(F)"]
    w_folds = [r for r in records if r.get("kind") == "fold" and r.get("parameter") == "w"]
    threshold = -_F_ROUNDOFF * float(np.max(np.abs(F), initial=0.0))
    negative_stable = bool(np.any((F < threshold) & stable_d))
    # a located F minimum on a displacement-stable stretch also counts (it lies between stored points)
    for r in minima:
        i = int(r.get("index", -1)) if "index" in r else -1
        if r["F"] < threshold and 0 <= i < len(stable_d) - 1 and stable_d[i] and stable_d[i + 1]:
            negative_stable = True
    if not maxima and not minima and not w_folds:
        kind = "monotonous"
    elif negative_stable:
        kind = "bistable"
    else:
        kind = "monostable"
    scale = R / (2.0 * math.pi * D)
    out: dict[str, Any] = {"classification": kind}
    first_max = maxima[0] if maxima else None
    last_min = minima[-1] if minima else None
    for tag, rec in (("max", first_max), ("min", last_min)):
        out[f"F_{tag}"] = None if rec is None else rec["F"]
        out[f"w_at_F_{tag}"] = None if rec is None else rec["w"]
        out[f"F_{tag}_norm"] = None if rec is None else rec["F"] * scale
        out[f"w_at_F_{tag}_over_R"] = None if rec is None else rec["w"] / R
    out["n_folds_in_w"] = len(w_folds)
    out["n_limit_points_in_F"] = len(maxima) + len(minima)
    out["F_negative_on_stable_path"] = negative_stable
    return out


#: What a path that came back to :data:`LOWEST_W` says (its message and ``summary.json``'s ``warnings``).
_CAME_BACK = ("the path came back to the unloaded pole's height, w = 0, without reaching eversion (beyond it the pole "
              "would be pulled up without end); thin deep caps under a point load do so on meshes too coarse for "
              "their wrinkles: compare with a finer mesh (shell.N)")


def path_complete(br: Branch) -> bool:
    """Whether a displacement-controlled path reached eversion (its ``p_max`` bound, not :data:`LOWEST_W`)."""
    return br.status == "bound" and len(br) > 0 and not came_back(br)


def came_back(br: Branch) -> bool:
    """Whether a displacement-controlled path ended back at the unloaded pole's height (:data:`LOWEST_W`).

    The bound is located to the corrector's precision, a round-off of the path's largest ``w`` either side of it.
    """
    if br.status != "bound" or not len(br):
        return False
    return abs(float(br.p[-1]) - LOWEST_W) <= 1e-9 * float(np.max(np.abs(br.p)))


def _jump_fields(records: list[dict[str, Any]], branches: list[Branch]) -> None:
    """Complete the jump records in place with what is known about their two ends.

    Jump ``j`` leaves the force limit point that ends branch ``j`` (the same state, at a load a hair
    above the limit load, where no equilibrium is near): ``jump_from`` takes that fold's residual and
    ``stable_before``.  ``jump_to`` is a minimum of the energy at fixed load: ``stable_after`` is its
    stability under force control.
    """
    for rec in records:
        if rec["kind"] != "jump" or "jump" not in rec:
            continue
        if rec.get("label") == "jump_from":
            folds = [r for r in records if r["kind"] == "fold" and r.get("branch") == rec["jump"]]
            if folds:
                fold = folds[-1]
                rec["residual"] = fold.get("residual")
                rec["residual_of"] = "the force limit point the jump leaves"
                if "stable_before" in fold:
                    rec["stable_before"] = fold["stable_before"]
        elif rec.get("label") == "jump_to" and "stable" in rec:
            rec["stable_after"] = rec["stable"]


#: Why a run restarted from a saved point and not joined to the saved path has no class (:func:`_traced_part_only`).
_TRACED_PART_NOTE = ("this run traced the path from a saved point on, not joined to the path from the unloaded cap: "
                     "the class and the snap loads F_max, F_min belong to that whole path ('contin classify' traces "
                     "it); the special points of the part traced are in the table")


def _traced_part_only(cls: dict[str, Any]) -> dict[str, Any]:
    """The classification fields of a restarted run that describes only the part it traced: no class and no
    snap loads (they belong to the whole path), what the traced part shows kept apart."""
    out = {key: None for key in cls if key.startswith(("F_max", "F_min", "w_at_F_"))}
    out.update(classification=None, classification_on_traced_part=cls["classification"],
               classification_note=_TRACED_PART_NOTE)
    return out


def _classification_line(c: dict[str, Any], complete: bool = True) -> str:
    if c["classification"] is None and "classification_on_traced_part" in c:
        return "classification: none (the run describes only the part traced from the saved point)"
    if c["classification"] is None:
        return (f"classification: undecided (the path did not reach eversion; on the part traced it looks "
                f"{c.get('classification_on_partial_path')})")
    if c["F_max"] is None and c["F_min"] is None:
        return f"classification: {c['classification']} (no extremum of F{'' if complete else ' on the part traced'})"

    def fmt(v: Any) -> str:
        return "-" if v is None else f"{v:.6g}"
    return (f"classification: {c['classification']} (F_max = {fmt(c['F_max'])} at w = {fmt(c['w_at_F_max'])}, "
            f"F_min = {fmt(c['F_min'])} at w = {fmt(c['w_at_F_min'])}; normalized F_max R/(2 pi D) = "
            f"{fmt(c['F_max_norm'])} at w/R = {fmt(c['w_at_F_max_over_R'])}, F_min R/(2 pi D) = "
            f"{fmt(c['F_min_norm'])} at w/R = {fmt(c['w_at_F_min_over_R'])})")


# ---------------------------------------------------------------------------------------------------
# the runner
# ---------------------------------------------------------------------------------------------------
def run_point(scene: Scene, progress: bool = False, start: Start | None = None) -> TraceResult:
    """Trace the point-loaded cap's displacement-controlled path to eversion (see the module docstring), from the
    unloaded cap or, given ``start`` (a saved point in these unknowns), on from there along its direction."""
    s = scene["shell"]
    w_end = end_of_path(scene)
    problem = point_problem(scene, "displacement")
    st = point_settings(scene, problem, progress)
    # F = 0 (falling): where a one-sided point indenter, which can only push, would lose the shell
    events = [_limit_load("max"), _limit_load("min"), contin.crossing("F", 0.0, direction=-1, name=_F_ZERO)]
    if start is None:
        br = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, p_min=LOWEST_W, p_max=w_end,
                                 events=events)
    else:
        (br,), _ = continue_saved(start, [resume(problem, start, st, p_min=LOWEST_W, p_max=w_end, events=events)])
    if came_back(br):
        br.message = f"{br.message}: back at the unloaded pole's height without reaching eversion"
    partial = start is not None and not start.continues_saved_path
    if path_complete(br) or not len(br) or partial:
        return _result([br], [], problem, scene, ["path"], "", partial=partial)
    return _result([br, _everted_branch(problem, st, s["phi_hat"])], [], problem, scene, ["path", _EVERTED], "")


#: Label of the branch traced back from the mirror image of the cap when the path stops before eversion.
_EVERTED = "everted branch"


def _everted_branch(problem: ShellPointLoad, st: contin.Settings, phi_hat: float) -> Branch:
    """The everted cap's branch, traced back in ``w`` from the cap's mirror image to its first fold in w.

    Thin deep caps (lambda above ~20) have a connected path that winds through many folds before it
    reaches eversion (h/R = 0.002, phi_hat = 0.8: 8341 steps).  The everted state at the end of that
    path is the mirror image of the cap at ``w = 2 R (1 - sin phi_hat)`` (stretch-free, with the
    bending reversed), so its branch can be reached directly: a stable stretch of it carrying F < 0
    shows the cap bistable without tracing the winding middle of the path.
    """
    x = problem.cap.x.copy()
    x[1::2] = 2.0 * x[1] - x[1::2]  # reflect every node in the base plane (z_0 is held)
    w_mirror = eversion_displacement(problem.R, phi_hat)
    return contin.continuation(problem, problem.unknowns(x), w_mirror, st, direction=-1, p_min=0.0,
                               stop_at=("fold",), events=[_limit_load("min")])


#: Label of the falling zero of the point force on the displacement path.
_F_ZERO = "F = 0"


def _one_sided_snap(records: list[dict[str, Any]]) -> dict[str, Any] | None:
    """Where a point indenter that can only push would snap: the first of the first falling zero of F
    and the first fold in ``w`` along the path (the bilateral path is the same up to there)."""
    first = [r for r in records if r.get("branch", 0) == 0 and (
        r.get("label") == _F_ZERO or (r["kind"] == "fold" and r.get("parameter") == "w"))]
    if not first:
        return None
    rec = min(first, key=lambda r: r["index"] + (0.5 if r["kind"] == "fold" else 0.0))
    return {"w_c_one_sided": rec["w"], "w_c_one_sided_over_R": rec["w_over_R"], "F_at_one_sided_snap": rec["F"],
            "one_sided_snap_kind": "F = 0" if rec.get("label") == _F_ZERO else "fold in w"}


def _use_everted_branch(cls: dict[str, Any], branches: list[Branch], records: list[dict[str, Any]],
                        labels: list[str], D: float, R: float) -> str:
    """Complete the class of a path cut short from the everted branch; returns a note for the summary.

    ``F_min`` is the path's last minimum of F, on the branch that reaches eversion: the part traced
    may have passed other minima, so it is taken from the everted branch (the first minimum met
    going back from the mirror image) or left unknown.  A stable stretch of the everted branch with
    F < 0 shows the cap bistable.
    """
    if labels[1:2] != [_EVERTED] or not len(branches[1]):
        found = ("no everted branch" if labels[1:2] != [_EVERTED] else
                 f"the everted branch could not be traced: {branches[1].message}")
        for key in ("F_min", "w_at_F_min", "F_min_norm", "w_at_F_min_over_R"):
            cls[key] = None
        return f"; F_min is unknown ({found})"
    everted = branches[1]
    minima = sorted((r for r in records if r.get("branch") == 1 and r.get("label") == "min(F)"),
                    key=lambda r: r["index"])
    first = minima[0] if minima else None
    cls["F_min"] = None if first is None else first["F"]
    cls["w_at_F_min"] = None if first is None else first["w"]
    cls["F_min_norm"] = None if first is None else first["F"] * R / (2.0 * math.pi * D)
    cls["w_at_F_min_over_R"] = None if first is None else first["w"] / R
    shown = classify(everted, [r for r in records if r.get("branch") == 1], D, R)["F_negative_on_stable_path"]
    note = "; F_min is taken from the everted branch, traced back from the cap's mirror image"
    if shown and not cls["F_negative_on_stable_path"]:
        cls["classification"], cls["F_negative_on_stable_path"] = "bistable", True
        note += ", which is stable with F < 0: the cap is bistable"
    return note


def _limit_load(which: str) -> contin.Event:
    """An extremum of ``F`` along the displacement path: a limit point under force control."""
    return contin.extremum("F", which, folds="F", stability_label="force")


def _records(branches: list[Branch], generic: TraceResult) -> list[dict[str, Any]]:
    """The engine's special-point records with the shell's fields (:func:`_point_fields`).

    A branch resumed after a snap repeats the jump's landing as its first special point: that
    record is left out (the jump's own ``jump_to`` states it).
    """
    records = special_point_records(branches, generic.jumps, generic.jump_observables, generic.parameter_name,
                                    fields=_point_fields)
    for rec in records:
        if rec["kind"] == "jump" and "jump" in rec:
            rec.update(_flat(rec["observables"]))
    return [r for r in records if not (r["kind"] == "jump" and "branch" in r)]


def _result(branches: list[Branch], jumps: list, problem: ShellPointLoad, scene: Scene, labels: list[str],
            failure: str, partial: bool = False) -> TraceResult:
    R = scene["shell"]["R"]
    generic = TraceResult.from_branches(branches, jumps, problem=problem, x="w", y="F", labels=labels,
                                        failure=failure)
    records = _records(branches, generic)
    summary: dict[str, Any] = {
        "eversion_w": eversion_displacement(R, scene["shell"]["phi_hat"]),
        "w_end": eversion_displacement(R, scene["shell"]["phi_hat"]) * (1.0 + scene["continuation"]["overshoot"]),
        "D": problem.D,
        "F_unit": 2.0 * math.pi * problem.D / R,
        "lambda": (12 * (1 - problem.nu ** 2)) ** 0.25 * (math.pi / 2 - problem.phi_hat) * math.sqrt(R / problem.h),
        "control": scene["load"]["control"],
    }
    _jump_fields(records, branches)
    peak = strain_peak(problem, branches, "w")
    warning = strain_warning(peak, R, point_load=True)
    if peak is not None:
        summary.update(max_strain=peak.value, w_at_max_strain_over_R=peak.load / R, max_strain_at=peak.where)
    summary["warnings"] = [warning] if warning else []
    if scene["load"]["control"] == "displacement" and branches and came_back(branches[0]):
        summary["warnings"].append(_CAME_BACK)
    record_instability(summary, records, problem.parameter_name, _INSTABILITY_FIELDS, problem)
    if partial:  # the traced part's first loss of stability, not the path's from the unloaded cap
        summary["first_instability_on_traced_part"] = summary.pop("first_instability")
    if scene["load"]["control"] == "displacement" and branches and len(branches[0]) and partial:
        # the class and the snap loads belong to the path from the unloaded cap, which this run did not trace
        summary.update(_traced_part_only(classify(branches[0], [r for r in records if r.get("branch", 0) == 0],
                                                  problem.D, R)))
        branches[0].message = f"{branches[0].message}; {_classification_line(summary)}"
    elif scene["load"]["control"] == "displacement" and branches and len(branches[0]):
        cls = classify(branches[0], [r for r in records if r.get("branch", 0) == 0], problem.D, R)
        complete = path_complete(branches[0])
        everted_note = ""
        if not complete:
            everted_note = _use_everted_branch(cls, branches, records, labels, problem.D, R)
        if not complete and not cls["F_negative_on_stable_path"]:
            # monotonous and monostable need the whole path: an unfinished one cannot rule out F < 0 later
            cls["classification_on_partial_path"] = cls["classification"]
            cls["classification"] = None
        summary.update(cls)
        summary.update(_one_sided_snap(records) or {})
        summary["classification_note"] = (
            "from the displacement-controlled path to eversion" if complete else
            f"the path did not reach eversion ({branches[0].message}); a class other than bistable needs the "
            f"whole path{everted_note}")
        line = _classification_line(cls, complete)
        branches[0].message = f"{branches[0].message}; {line}"
    elif scene["load"]["control"] == "displacement":
        summary["classification"] = None
        summary["classification_note"] = "nothing was traced on the displacement-controlled path"
    else:
        summary["classification"] = None
        summary["classification_note"] = ("the classification is defined on the displacement-controlled path; "
                                          "'contin classify' traces it whatever load.control says")
    # the first instability is named wherever the snap is: the status line and the diagram
    instability = instability_text(summary, _SHOWN)
    if instability and branches and len(branches[0]):
        branches[0].message = f"{branches[0].message}; {instability}"
    # the diagram styles by the scene's control; an "F = 0" event is in the table, not on the figure
    cls = summary.get("classification")
    # the axes in the cap's reference units: w/R and F R/(2 pi D)
    note = "; ".join(t for t in (str(cls) if cls else "", instability_text(summary, _SHOWN, tex=True)) if t)
    plot_options = {**force_axes("w", R, problem.D, scaled={"w_over_R": "w", "F_norm": "F"}), "title": scene_title(scene),
                    "zero_line": True, "special_kinds": ("fold", "bifurcation"), "note": note}
    shapes = shell_shapes(branches, problem.full_state, getattr(problem, "operator_families", ()), problem.cap.x,
                          path=scene["output"]["shapes"] == "path", fields={"F": observed("F")})
    result = TraceResult(branches=generic.branches, jumps=generic.jumps, summary=summary, special_points=records,
                         table=special_point_table(records, branch_labels=labels if len(branches) > 1 else None,
                                                   columns=_TABLE_COLUMNS),
                         csv_columns=branch_columns(branches, STABILITY_COLUMNS), x="w", y="F",
                         parameter_name=generic.parameter_name, labels=labels,
                         jump_observables=generic.jump_observables, failure=failure,
                         stability=summary["control"], plot_options=plot_options,
                         shapes=shapes, draw_shapes=shapes_drawer(shapes, problem.R, generic.parameter_name, plot_options,
                                                                 load=LoadSketch("point")))
    if not scene["output"]["figure"]:
        result.plot = lambda ax: ax.text(0.5, 0.5, "figure disabled (output.figure = false)", ha="center",
                                         va="center", transform=ax.transAxes)
    return result


#: Snaps a force-controlled trace may make before eversion.
MAX_SNAPS = 4


def run_point_force(scene: Scene, progress: bool = False, start: Start | None = None) -> TraceResult:
    """Dead load at the pole: load to each force limit point, snap, keep loading until eversion; given ``start`` (a
    saved point in the force control's unknowns), from there, loading or unloading as the saved path went.

    The scene's path lies between the unloaded pole and eversion: a sweep ends where the pole passes
    ``w_end`` (eversion and ``continuation.overshoot`` past it) or, unloading, falls back to ``w = 0``,
    whether it gets there along a branch or by a snap.
    """
    w_end = end_of_path(scene)
    problem = point_problem(scene, "force")
    st = point_settings(scene, problem, progress)
    u0, F0, direction = problem.reference_unknowns(), 0.0, 1
    if start is not None:
        u0, F0, direction = start.u, start.p, start.direction or 1
    # loading from the unloaded cap starts on w = 0 itself: that end only bounds an unloading sweep
    w_range = (0.0 if direction < 0 else None, w_end)
    if start is not None:
        past = beyond_end(problem, start, bounds={"w": w_range})
        if past:
            raise RestartError(f"{start.describe()} lies at an end of this scene's path or beyond it ({past}; the "
                               f"path runs from the unloaded pole, w = 0, to eversion and continuation.overshoot "
                               f"past it) and the pole moved on outwards there: there is nothing to trace under "
                               f"force control; restart from a point inside the path")
        nneg = problem.stability(u0, F0, 0)["force"].n_negative
        if nneg:
            raise SceneError(f"{start.describe()} is unstable under force control ({nneg} negative eigenvalue"
                             f"{'s' if nneg > 1 else ''}): a dead load cannot hold the cap there; restart under "
                             f"force control from a point stable under it (stable_force = 1 in branch.csv)",
                             "constraint")

    # no end load: the pole displacement's bounds end the sweep, reached along a branch or by a snap's
    # landing; the located limit points alone end a stretch, as they always did for this scene
    qs = contin.quasistatic(problem, u0, F0, None, st, direction=direction, max_snaps=MAX_SNAPS,
                            snap=force_snap_rules(problem, "w", problem.R),
                            stop_at_branch_points=False, check_stability=False, bounds={"w": w_range})
    branches, jumps = (qs.branches, qs.jumps) if start is None else continue_saved(start, qs.branches, qs.jumps)
    word = "loading" if direction > 0 else "unloading"
    labels = [word if k == 0 else f"{word} after snap {k}" for k in range(len(branches))]
    return _result(branches, jumps, problem, scene, labels, qs.message if qs.failed else "",
                   partial=start is not None and not start.continues_saved_path)


def resume_point(scene: Scene, start: Start, progress: bool = False) -> TraceResult:
    """Restart the point load from a saved point (``contin trace --from OUT --label K``).

    The saved run's control (``start.saved_scene``) says what the state is; ``load.control`` of ``scene``
    which quantity is continued from there: the pole displacement ``w`` (the path on to eversion, along
    the saved direction) or the force ``F`` (the dead load's quasi-static sweep, loading when the force
    rose along the saved path through the point, else unloading).  A state saved under one control is
    carried over to the other through the cap's node positions (:meth:`ShellPointLoad.full_state`).
    """
    saved = (start.saved_scene.get("load") or {}).get("control", "displacement")
    control = scene["load"]["control"]
    if saved != control:
        start = _other_control(scene, start, saved, control)
    return run_point_force(scene, progress, start) if control == "force" else run_point(scene, progress, start)


def _other_control(scene: Scene, start: Start, saved: str, control: str) -> Start:
    """``start`` (a point in the unknowns of the control ``saved``) in the unknowns and parameter of ``control``."""
    old, new = point_problem(scene, saved), point_problem(scene, control)
    if start.u.size != old.n:
        raise SceneError(f"the saved state has {start.u.size} unknowns, the cap under {saved} control "
                         f"{old.n}: it was not saved by this scene", "constraint")
    x = old.full_state(start.u, start.p)
    eps = 1e-7 / max(float(np.max(np.abs(start.du), initial=0.0)), abs(start.dp), 1e-300)
    x1 = old.full_state(start.u + eps * start.du, start.p + eps * start.dp)
    u, u1 = new.unknowns(x), new.unknowns(x1)
    # the new parameter: F (the pole's reaction) or w (the pole's position), and its change along the direction
    name = "F" if control == "force" else "w"
    p = old.evaluate_observables(start.u, start.p)[name]
    p1 = old.evaluate_observables(start.u + eps * start.du, start.p + eps * start.dp)[name]
    return Start(u=u, p=p, du=(u1 - u) / eps, dp=(p1 - p) / eps, ds=None, name=start.name, kind=start.kind,
                 label=start.label, branch=start.branch, number=start.number, record=start.record,
                 complete=start.complete, saved_scene=start.saved_scene)
