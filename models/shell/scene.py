"""Command-line scene of the point-indented shell (``contin trace --model shell``).

The scene traces the whole connected equilibrium path of a spherical cap loaded by a point at its
pole, from the reference state until the shell is everted (the pole past the mirror image of its
start, ``w = 2 R (1 - sin phi_hat)``, by ``continuation.overshoot``), locates every fold in ``w``
and every extremum of ``F`` (the limit points under force control), labels every point's stability
under both controls and classifies the response (``docs/physics.md`` sections 4 and 5).

Scene keys (public contract, ``--set section.key=value``)::

    [shell]         R, E, nu, h, phi_hat, N, pole_ratio (node spacing at the pole / elsewhere; 1 = uniform)
    [load]          kind = "point" | "sphere" | "plate", radius (sphere), control = "displacement" | "force"
    [contact]       K_c, dhat (0: the paper's values scaled with E and R; sphere and plate only)
    [continuation]  ds, ds_max (units of R), tol, max_steps, overshoot
    [output]        figure

A sphere or plate indenter is run by :mod:`models.contact.runner` (its docstring describes that
``summary.json``); what follows is the point load's.

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

Classification (``docs/physics.md`` section 5)
----------------------------------------------
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
questionable without failing: a strain beyond :data:`models.shell.strain.STRAIN_LIMIT`, which under
a point load means the pole's singular strain has left the material law's range and results near
there can change with N (:mod:`models.shell.strain`).  The status line repeats the warnings.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import contin
from contin.branch import Branch
from contin.scene import (Classification, Constraint, Field, SceneModel, Schema, TraceResult, boolean,
                          check_classifiable, choice, integer, real)

from .problem import ShellPointLoad
from .strain import strain_peak, strain_warning

__all__ = ["SHELL_SCENE", "SHELL_SCHEMA", "classify", "classify_scene", "eversion_displacement"]

Scene = dict[str, dict[str, Any]]

#: Observables of :class:`ShellPointLoad` reported at every special point.
_OBS = ("w", "F", "w_over_R", "F_norm")
#: Minimum number of steps over the eversion depth: ``ds`` and ``ds_max`` are capped at this
#: fraction of ``2 R (1 - sin phi_hat)``, so shallow caps (short paths) are still resolved.
_MIN_STEPS_PER_PATH = 20
#: Relative size (of ``max |F|`` on the path) below which a negative force counts as round-off.
_F_ROUNDOFF = 1e-8

#: Largest ``shell.N``: 125 times the finest mesh of the studies (N = 800).  The cost is linear in N, but
#: a mistyped huge N would otherwise run for hours or fail allocating instead of being rejected.
MAX_NODES = 100_000


def _nodes_ok(n: int) -> bool:
    return 10 <= n <= MAX_NODES


SHELL_SCHEMA = Schema(
    sections={
        "shell": {
            "R": real(1.0, gt=0, help="sphere radius [m]"),
            "E": real(1e6, gt=0, help="Young's modulus [Pa]"),
            "nu": real(0.5, gt=-1, le=0.5, help="Poisson's ratio"),
            "h": real(0.02, gt=0, help="thickness [m]"),
            "phi_hat": real(0.8, gt=0, lt=math.pi / 2,
                            help="base angle from the horizontal [rad] (small = deep cap)"),
            "N": Field(int, 200, _nodes_ok, f"an integer >= 10 and <= {MAX_NODES}", "number of nodes on the meridian"),
            "pole_ratio": real(0.5, gt=0, le=1, help="node spacing at the pole / elsewhere (1 = uniform mesh; "
                                                    "graded towards the point load by default)"),
        },
        "load": {
            "kind": choice("point", ("point", "sphere", "plate"),
                           help="indenter: a point at the pole (bilateral), or a rigid sphere or plate through the "
                                "log-barrier contact"),
            "radius": real(0.5, gt=0, help="sphere radius [m] (load.kind = sphere)"),
            "control": choice("displacement", ("displacement", "force"),
                              help="displacement: the pole displacement w (point) or the indenter travel w_b "
                                   "(sphere, plate) is prescribed; force: a dead load F on the pole or the indenter"),
        },
        "continuation": {
            "ds": real(0.02, gt=0, help="initial arclength step in units of R"),
            "ds_max": real(0.1, gt=0, help="largest step in units of R (also capped at 1/20 of the eversion depth)"),
            # the floor is measured: at tol = 1e-12 the default scene (N = 200 and 800) stops at its first
            # points with Newton stalled at round-off; 5e-12 and 1e-11 run every load kind and control
            "tol": real(1e-10, ge=1e-11, lt=1, help="relative residual tolerance (below 1e-11 round-off in the "
                                                     "shell's residual keeps Newton from converging)"),
            "max_steps": integer(3000, low=1, high=1_000_000, help="maximum number of steps per branch"),
            "overshoot": real(0.05, ge=0, le=1,
                              help="stop this fraction past eversion, w = 2 R (1 - sin phi_hat) (1 + overshoot)"),
        },
        "contact": {
            "K_c": real(0.0, ge=0, help="barrier stiffness [N/m]; 0 = 100 E R (the paper's 1e8 for E = 1 MPa, R = 1 m)"),
            "dhat": real(0.0, ge=0, help="barrier range [m]; 0 = 1e-3 R (the paper's 1e-3 for R = 1 m)"),
        },
        "output": {
            "figure": boolean(True, help="draw the force-displacement diagram (false: an empty placeholder)"),
        },
    },
    constraints=[
        Constraint(("continuation.ds", "continuation.ds_max"),
                   lambda s: s["continuation"]["ds"] <= s["continuation"]["ds_max"],
                   "continuation.ds <= continuation.ds_max"),
        Constraint(("shell.h", "shell.R"), lambda s: s["shell"]["h"] < s["shell"]["R"],
                   "shell.h < shell.R", "the shell model is thin: its thickness must be below its radius"),
    ],
)


def eversion_displacement(R: float, phi_hat: float) -> float:
    """Pole displacement ``2 R (1 - sin phi_hat)`` at which the pole reaches the mirror image of its start."""
    return 2.0 * R * (1.0 - math.sin(phi_hat))


# ---------------------------------------------------------------------------------------------------
# special points and classification
# ---------------------------------------------------------------------------------------------------
def _stability_pair(br: Branch, label: str, index: int) -> tuple[bool | None, bool | None, int | None, int | None]:
    """Stability (and negative-eigenvalue counts) under ``label`` at stored points ``index`` and ``index + 1``."""
    if label not in br.stability_by or index < 0:
        return None, None, None, None
    nneg = br.stability_by[label][0]
    before = int(nneg[index]) if index < len(nneg) else None
    after = int(nneg[index + 1]) if index + 1 < len(nneg) else None
    return (None if before is None else before == 0, None if after is None else after == 0, before, after)


def _shell_records(branches: list[Branch], base: list[dict[str, Any]], R: float) -> list[dict[str, Any]]:
    """Rewrite the generic special-point records for the shell (parameter, observables, stability).

    ``base`` is :attr:`TraceResult.special_points` as built by :meth:`TraceResult.from_branches`, in
    the same order as the branches' special points followed by the jumps.
    """
    out: list[dict[str, Any]] = []
    k = 0
    for bi, br in enumerate(branches):
        pname = br.meta.get("parameter_name", "w")
        for spt in br.special_points:
            rec = dict(base[k])
            k += 1
            obs = rec.get("observables", {})
            extremum_of_F = spt.kind == "event" and spt.label in ("max(F)", "min(F)")
            if spt.kind == "fold" or extremum_of_F:
                # which quantity folds: the traced parameter for a PALC fold, F for an F extremum
                folds_in = "F" if extremum_of_F else pname
                rec["kind"] = "fold"
                rec["parameter"] = folds_in
                if extremum_of_F:
                    rec["label"] = spt.label
                label = "force" if folds_in == "F" else "displacement"
                # a point that ends the branch is stored last: the side it came from is the point before
                ends = bool(spt.info.get("ends_branch"))
                sb, sa, nb, na = _stability_pair(br, label, spt.index - 1 if ends else spt.index)
                rec.pop("stable_before", None)
                rec.pop("stable_after", None)
                if sb is not None:
                    rec["stable_before"] = sb
                    rec["n_negative_before"] = nb
                if sa is not None and not spt.info.get("ends_branch"):
                    rec["stable_after"] = sa
                    rec["n_negative_after"] = na
                rec["stability_control"] = label
            else:
                rec["parameter"] = pname
            for name in _OBS:
                if name in obs:
                    rec[name] = float(obs[name])
            out.append(rec)
    for rec in base[k:]:  # jumps: F is the fixed parameter
        rec = dict(rec)
        obs = rec.get("observables", {})
        rec["parameter"] = "F"
        for name in _OBS:
            if name in obs:
                rec[name] = float(obs[name])
        out.append(rec)
    return out


def classify(branch: Branch, records: list[dict[str, Any]], D: float, R: float) -> dict[str, Any]:
    """Classify a displacement-controlled path (``docs/physics.md`` section 5).

    Parameters
    ----------
    branch : Branch
        The traced path with stability data (label ``"displacement"``).
    records : list of dict
        Its special-point records as produced by :func:`_shell_records`.
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


def _path_complete(br: Branch) -> bool:
    """Whether a displacement-controlled path reached eversion (its ``p_max`` bound)."""
    return br.status == "bound" and len(br) > 0


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


def _classification_line(c: dict[str, Any]) -> str:
    if c["classification"] is None:
        return (f"classification: undecided (the path did not reach eversion; on the part traced it looks "
                f"{c.get('classification_on_partial_path')})")
    if c["F_max"] is None and c["F_min"] is None:
        return f"classification: {c['classification']} (no extremum of F)"

    def fmt(v: Any) -> str:
        return "-" if v is None else f"{v:.6g}"
    return (f"classification: {c['classification']} (F_max = {fmt(c['F_max'])} at w = {fmt(c['w_at_F_max'])}, "
            f"F_min = {fmt(c['F_min'])} at w = {fmt(c['w_at_F_min'])}; normalized F_max R/(2 pi D) = "
            f"{fmt(c['F_max_norm'])} at w/R = {fmt(c['w_at_F_max_over_R'])}, F_min R/(2 pi D) = "
            f"{fmt(c['F_min_norm'])} at w/R = {fmt(c['w_at_F_min_over_R'])})")


def _table(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    word = {True: "stable", False: "unstable", None: "?"}
    rows = []
    for rec in records:
        if rec["kind"] == "jump":
            stab = word[rec.get("stable")] if "stable" in rec else ""
            what = rec.get("label", "")
        else:
            b, a = rec.get("stable_before"), rec.get("stable_after")
            stab = "" if b is None and a is None else f"{word[b]} -> {word[a]}"
            if rec.get("stability_control"):
                stab += f" ({rec['stability_control']})"
            what = rec.get("label", "")
        rows.append({"kind": rec["kind"], "folds_in": rec["parameter"], "label": what,
                     "w": rec.get("w"), "F": rec.get("F"), "w/R": rec.get("w_over_R"),
                     "F_norm": rec.get("F_norm"), "residual": rec.get("residual"), "stability": stab})
    return rows


def _csv(branches: list[Branch], base: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """branch.csv: the generic columns plus both stability labels (``n_negative`` is the displacement one)."""
    cols = dict(base)
    cols.pop("stable", None)
    cols.pop("n_negative", None)
    if all(br.stability_by for br in branches) and branches:
        for label in ("force", "displacement"):
            cols[f"stable_{label}"] = np.concatenate([br.stable_under(label) for br in branches]).astype(int)
        cols["n_negative"] = np.concatenate([br.stability_by["displacement"][0] for br in branches]).astype(int)
        cols["n_negative_force"] = np.concatenate([br.stability_by["force"][0] for br in branches]).astype(int)
    return cols


# ---------------------------------------------------------------------------------------------------
# the runner
# ---------------------------------------------------------------------------------------------------
def _settings(scene: Scene, problem: ShellPointLoad, w_end: float, progress: bool) -> contin.Settings:
    s, c = scene["shell"], scene["continuation"]
    R = s["R"]
    cap = eversion_displacement(R, s["phi_hat"]) / _MIN_STEPS_PER_PATH / R
    ds_max = min(c["ds_max"], cap)
    ds = min(c["ds"], ds_max)
    # weights make ds dimensionless in units of R: positions and w are lengths; F is measured in
    # units of 2 pi D / R times the Reissner-type scale of the path (F_norm ~ 1..10 over the path)
    f_unit = 2.0 * math.pi * problem.D / R
    param_weight = 1.0 / R if problem.control == "displacement" else 1.0 / (10.0 * f_unit)
    return contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, tol=c["tol"], max_steps=c["max_steps"],
                           stability=True, n_eigs=0, state_weight=1.0 / R, param_weight=param_weight, progress=progress)


def _problem(scene: Scene, control: str) -> ShellPointLoad:
    s = scene["shell"]
    return ShellPointLoad(R=s["R"], E=s["E"], nu=s["nu"], h=s["h"], phi_hat=s["phi_hat"], N=s["N"], control=control,
                          pole_ratio=s["pole_ratio"])


def _run_shell(scene: Scene, progress: bool) -> TraceResult:
    s, c, load = scene["shell"], scene["continuation"], scene["load"]
    if load["kind"] in ("sphere", "plate"):
        return _run_contact(scene, progress)
    if load["control"] == "force":
        return _run_force(scene, progress)
    R = s["R"]
    w_end = eversion_displacement(R, s["phi_hat"]) * (1.0 + c["overshoot"])
    problem = _problem(scene, "displacement")
    st = _settings(scene, problem, w_end, progress)
    # F = 0 (falling): where a one-sided point indenter, which can only push, would lose the shell
    br = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, p_max=w_end,
                             events=[contin.extremum("F", "max"), contin.extremum("F", "min"),
                                     contin.crossing("F", 0.0, direction=-1, name=_F_ZERO)])
    if _path_complete(br) or not len(br):
        return _result([br], [], problem, scene, ["path"], "")
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
                               stop_at=("fold",), events=[contin.extremum("F", "min")])


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


def contact_settings(scene: Scene, progress: bool = False, stability: bool = True) -> tuple[contin.Settings, float]:
    """Continuation settings and the end of travel ``w_end`` of a sphere or plate scene."""
    s, c = scene["shell"], scene["continuation"]
    R = s["R"]
    w_end = eversion_displacement(R, s["phi_hat"]) * (1.0 + c["overshoot"])
    # lengths in units of R, as for the point load; the first contact is a sharp corner of the path
    # (the barrier switches on), so the first step is a quarter of the scene's
    ds_max = min(c["ds_max"], eversion_displacement(R, s["phi_hat"]) / _MIN_STEPS_PER_PATH / R)
    ds = 0.25 * min(c["ds"], ds_max)
    st = contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, tol=c["tol"], max_steps=c["max_steps"],
                         stability=stability, n_eigs=0, state_weight=1.0 / R, param_weight=1.0 / R, progress=progress)
    return st, w_end


def _run_contact(scene: Scene, progress: bool) -> TraceResult:
    """Sphere or plate indentation (see :mod:`models.contact.runner`): travel or dead load on the indenter."""
    from models.contact.runner import run_contact, run_contact_force  # only a contact scene builds these

    st, w_end = contact_settings(scene, progress)
    if scene["load"]["control"] == "force":
        return run_contact_force(scene, progress, st, w_end)
    return run_contact(scene, progress, st, w_end)


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


def _result(branches: list[Branch], jumps: list, problem: ShellPointLoad, scene: Scene, labels: list[str],
            failure: str) -> TraceResult:
    R = scene["shell"]["R"]
    generic = TraceResult.from_branches(branches, jumps, problem=problem, x="w", y="F", labels=labels,
                                        failure=failure)
    records = _shell_records(branches, generic.special_points, R)
    # the index of each special point is needed by classify (located minima between stored points)
    k = 0
    for br in branches:
        for spt in br.special_points:
            records[k]["index"] = int(spt.index)
            k += 1
    # a branch resumed after a snap repeats the jump's landing as its first special point
    records = [r for r in records if not (r["kind"] == "jump" and "branch" in r)]
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
    if scene["load"]["control"] == "displacement" and branches and len(branches[0]):
        cls = classify(branches[0], [r for r in records if r.get("branch", 0) == 0], problem.D, R)
        complete = _path_complete(branches[0])
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
        line = _classification_line(cls)
        branches[0].message = f"{branches[0].message}; {line}"
    elif scene["load"]["control"] == "displacement":
        summary["classification"] = None
        summary["classification_note"] = "nothing was traced on the displacement-controlled path"
    else:
        summary["classification"] = None
        summary["classification_note"] = ("the classification is defined on the displacement-controlled path; "
                                          "'contin classify' traces it whatever load.control says")
    result = TraceResult(branches=generic.branches, jumps=generic.jumps, summary=summary, special_points=records,
                         table=_table(records), csv_columns=_csv(branches, generic.csv_columns), x="w", y="F",
                         parameter_name=generic.parameter_name, labels=labels,
                         jump_observables=generic.jump_observables, failure=failure)
    if not scene["output"]["figure"]:
        result.plot = lambda ax: ax.text(0.5, 0.5, "figure disabled (output.figure = false)", ha="center",
                                         va="center", transform=ax.transAxes)
    else:
        result.plot = lambda ax: _plot(ax, result)
    return result


def _plot(ax: Any, result: TraceResult) -> None:
    """Force-displacement diagram: stable (under the scene's control) solid, unstable dashed."""
    control = result.summary.get("control", "displacement")
    for i, br in enumerate(result.branches):
        if not len(br):
            continue
        w, F = br.observables["w"], br.observables["F"]
        ok = br.stable_under(control) if br.stability_by else np.ones(len(br), bool)
        color = f"C{i}"
        for lo in range(len(br) - 1):
            style = "-" if ok[lo] and ok[lo + 1] else "--"
            ax.plot(w[lo:lo + 2], F[lo:lo + 2], style, color=color, lw=1.4 if style == "-" else 1.0)
        ax.plot([], [], "-", color=color, label=(result.labels[i] if i < len(result.labels) else f"branch {i}"))
    for rec in result.special_points:
        if rec["kind"] == "fold":
            marker = "o" if rec["parameter"] == "w" else "^"
            ax.plot(rec["w"], rec["F"], marker, color="k", ms=5, mfc="none" if rec["parameter"] == "w" else "k")
    for a, b in result.jump_observables:
        if "w" in a and "w" in b:
            ax.annotate("", xy=(b["w"], b["F"]), xytext=(a["w"], a["F"]),
                        arrowprops={"arrowstyle": "->", "ls": ":", "color": "k"})
    ax.plot([], [], "ko", mfc="none", ms=5, label="fold in w")
    ax.plot([], [], "k^", ms=5, label="limit point in F")
    ax.axhline(0.0, color="0.7", lw=0.6)
    ax.set_xlabel("w (pole displacement)")
    ax.set_ylabel("F (point force)")
    ax.legend(fontsize="small")
    cls = result.summary.get("classification")
    if cls:
        ax.text(0.02, 0.02, f"{cls}, stability under {control} control", transform=ax.transAxes, fontsize="small")


#: Attempts to leave a force limit point: (relative load increment past the fold, kick in units of R
#: or None for the engine's default).  Exactly at the fold the energy is flat to third order along
#: the null vector; a load a hair above the limit load has no equilibrium nearby, so the
#: minimisation has to leave for the distant stable state.
_JUMP_ATTEMPTS = ((1e-6, 1e-4), (1e-4, None), (1e-4, 1e-4))
_MAX_SNAPS = 4


def _snap(problem: ShellPointLoad, u: np.ndarray, F: float, tol: float) -> tuple[Any, str]:
    """Jump from a force limit point to a distinct stable state; ``(JumpResult or None, reason)``."""
    w_fold = problem.evaluate_observables(u, F)["w"]
    reasons = []
    for eps, kick in _JUMP_ATTEMPTS:
        try:
            jr = contin.jump(problem, u, F * (1.0 + eps), tol=tol,
                             perturbation=None if kick is None else kick * problem.R)
        except contin.JumpError as exc:
            reasons.append(str(exc))
            continue
        w_to = problem.evaluate_observables(jr.u_to, jr.p)["w"]
        if jr.success and abs(w_to - w_fold) > 1e-3 * problem.R:
            return jr, ""
        reasons.append(jr.message if not jr.success else "landed back at the limit point")
    return None, "; ".join(reasons)


def _run_force(scene: Scene, progress: bool) -> TraceResult:
    """Dead load at the pole: load to each force limit point, snap, keep loading until eversion."""
    s, c = scene["shell"], scene["continuation"]
    R = s["R"]
    w_end = eversion_displacement(R, s["phi_hat"]) * (1.0 + c["overshoot"])
    problem = _problem(scene, "force")
    st = _settings(scene, problem, w_end, progress)
    branches: list[Branch] = []
    jumps: list[Any] = []
    labels: list[str] = []
    failure = ""
    u, F, origin = problem.reference_unknowns(), 0.0, None
    for k in range(_MAX_SNAPS + 1):
        br = contin.continuation(problem, u, F, st, stop_at=("fold",), bounds={"w": (None, w_end)}, origin=origin)
        branches.append(br)
        labels.append("loading" if k == 0 else f"loading after snap {k}")
        if br.status != "event":  # reached eversion (w bound), max_steps, or failed
            break
        if k == _MAX_SNAPS:
            failure = f"more than {_MAX_SNAPS} snaps under force control before eversion"
            break
        jr, reason = _snap(problem, br.u[-1], br.p[-1], c["tol"])
        if jr is None:
            failure = f"the snap at the force limit point F = {br.p[-1]:.8g} did not land on a stable state ({reason})"
            break
        jumps.append(jr)
        u, F, origin = jr.u_to, jr.p, jr
        if problem.evaluate_observables(u, F)["w"] >= w_end:
            break  # landed beyond eversion: nothing left to load
    return _result(branches, jumps, problem, scene, labels, failure)


#: Fields of :func:`classify` copied into a :class:`~contin.scene.Classification` (``contin classify --json``).
_CLASSIFY_FIELDS = ("F_max", "w_at_F_max", "F_min", "w_at_F_min", "F_max_norm", "w_at_F_max_over_R", "F_min_norm",
                    "w_at_F_min_over_R", "n_folds_in_w", "n_limit_points_in_F", "F_negative_on_stable_path",
                    "classification_on_partial_path", "max_strain", "w_at_max_strain_over_R")


def classify_scene(scene: Scene, progress: bool = False) -> Classification:
    """Classify a shell scene (``contin classify --model shell``).

    The class is defined on the displacement-controlled path to eversion (``docs/physics.md``
    section 5), so that path is traced whatever ``load.control`` says; every other key of the scene
    is used as given.

    Parameters
    ----------
    scene : dict
        A resolved scene of :data:`SHELL_SCHEMA`.
    progress : bool
        Print the continuation's progress to stderr.

    Returns
    -------
    Classification
        ``label`` is ``"monotonous"``, ``"monostable"`` or ``"bistable"``, or None when the path
        did not reach eversion and F < 0 was not yet seen on a displacement-stable part of it.
        ``values`` holds ``F_max``, ``w_at_F_max``, ``F_min``, ``w_at_F_min`` and their normalized
        forms (``F R / (2 pi D)``, ``w / R``), the fold counts, ``lambda``, ``D``, ``F_unit`` and
        ``eversion_w``; ``trace`` is the displacement-controlled run.

    Raises
    ------
    contin.scene.SceneError
        For a sphere or plate indenter: the class is defined on the point-load path.
    """
    check_classifiable(SHELL_SCENE, scene)  # an indenter has no class: refused, also when called directly
    path_scene = {section: dict(keys) for section, keys in scene.items()}
    path_scene["load"]["control"] = "displacement"
    path_scene["output"]["figure"] = False
    trace = _run_shell(path_scene, progress)
    summ = trace.summary
    label = summ.get("classification")
    values: dict[str, Any] = {"control_traced": "displacement"}
    values.update({k: summ[k] for k in _CLASSIFY_FIELDS if k in summ})
    values.update({k: summ[k] for k in ("lambda", "D", "F_unit", "eversion_w") if k in summ})
    s = scene["shell"]
    lines = [f"scene: R = {s['R']:g}, h/R = {s['h'] / s['R']:g}, phi_hat = {s['phi_hat']:g}, nu = {s['nu']:g}, "
             f"N = {s['N']}; lambda = {summ['lambda']:.4g}"]
    rows = [("", "F", "w", "F R/(2 pi D)", "w/R", "")]
    for tag, what in (("max", "first local maximum of F: the snap load under force control"),
                      ("min", "last local minimum of F: the snap-back load on unloading")):
        F = summ.get(f"F_{tag}")
        if F is None:
            rows.append((f"F_{tag}", "-", "-", "-", "-", "none on the path"))
        else:
            rows.append((f"F_{tag}", f"{F:.6g}", f"{summ[f'w_at_F_{tag}']:.6g}", f"{summ[f'F_{tag}_norm']:.6g}",
                         f"{summ[f'w_at_F_{tag}_over_R']:.6g}", what))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    for r in rows:
        lines.append("  ".join(c.rjust(w) if 0 < i < 5 else c.ljust(w) for i, (c, w) in enumerate(zip(r, widths)))
                     .rstrip())
    if "n_folds_in_w" in summ:
        lines.append(f"path: {summ['n_limit_points_in_F']} limit points in F, {summ['n_folds_in_w']} folds in w; "
                     f"F < 0 on a displacement-stable part: {'yes' if summ['F_negative_on_stable_path'] else 'no'}")
    if "max_strain" in summ:
        lines.append(f"largest membrane strain: {summ['max_strain']:.3g} ({summ['max_strain_at']}, "
                     f"w/R = {summ['w_at_max_strain_over_R']:.4g})")
    lines += [f"warning: {w}" for w in summ.get("warnings", [])]
    values["path_complete"] = bool(trace.branches) and _path_complete(trace.branches[0])
    failure = "" if label is not None else summ.get("classification_note", "the path could not be traced")
    return Classification(label=label, values=values, lines=lines, trace=trace, failure=failure)


#: The class is defined on the point-load path (``docs/physics.md`` section 5): ``contin classify``
#: refuses an indenter and says what to run instead.
_CLASSIFY_REQUIRES = (
    Constraint(("load.kind",), lambda s: s["load"]["kind"] == "point", 'load.kind = "point"',
               "the classes monotonous, monostable and bistable are defined on the displacement path of the point "
               "load at the pole, docs/physics.md section 5; an indenter can only push, so its path has no F < 0 to "
               "classify. The class of this cap: the same command with --set load.kind=point. The indenter's own "
               "snap (w_b_c, F at the snaps): 'contin trace' with this scene, in summary.json"),
)

SHELL_SCENE = SceneModel(
    name="shell",
    description="spherical cap under a point load at the pole: the whole path to eversion, folds in w and F, "
                "stability under both controls, classification",
    schema=SHELL_SCHEMA,
    runner=_run_shell,
    classifier=classify_scene,
    classify_requires=_CLASSIFY_REQUIRES,
    default=True,
    examples={
        "trace": (("--set shell.phi_hat=1.2 --set shell.N=100 --out /tmp/run", "a monostable cap"),
                  ("--set load.control=force", "dead load: snaps at the limit points of F"),
                  ("--set load.kind=sphere --set load.radius=0.5", "a rigid sphere through the barrier contact")),
        "classify": (("--set shell.phi_hat=1.2 --set shell.N=100", "monostable"),
                     ("scene.toml --json", ""),
                     ("--sweep shell.phi_hat=0.6:1.4:9 --sweep shell.h=0.01,0.02 --csv phi_h.csv", ""),
                     ("--set shell.N=100 --sweep shell.h=log:0.005:0.05:7 --workers 4 --json", ""),
                     ("--sweep shell.phi_hat=0.6:1.4:9 --scheduler tcp://127.0.0.1:8786", "on a Dask cluster")),
    },
    help={
        "trace": "branch.csv has w, F, w_over_R, F_norm, stable_force, stable_displacement and n_negative; the path "
                 "ends at eversion, w = 2 R (1 - sin phi_hat) (1 + continuation.overshoot).",
        "classify": "the class (monotonous, monostable or bistable) is defined on the displacement-controlled path "
                    "of the point load to eversion, which is traced whatever load.control says; a sphere or plate "
                    "indenter is refused. Printed: the class, F_max and F_min with the displacements where they "
                    "occur, raw and normalized (w/R, F R/(2 pi D)); the sweep CSV adds F_max, F_min, F_max_norm, "
                    "w_at_F_max_over_R, ..., lambda.",
    },
)
