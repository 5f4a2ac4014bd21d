"""The shell with its loads as one command-line scene (``contin trace --model shell``).

This is the one place that combines the shell (:mod:`contin_models.shell`) with its loads: the point load
(:mod:`contin_models.shell_scene.point`) and the rigid indenters through the contact
(:mod:`contin_models.contact`, run by :mod:`contin_models.shell_scene.contact`), and a uniform pressure
(:mod:`contin_models.shell_scene.pressure`).  Knowledge flows one way:
``contin_models.shell`` <- ``contin_models.contact`` <- ``contin_models.shell_scene``.
"""

from __future__ import annotations

from typing import Any

from contin.app.scene import Classification, Constraint, SceneError, SceneModel, TraceResult, check_classifiable

# the runners (and with them the shell, numpy and the engine) are imported when a scene runs: loading
# SHELL_SCENE, as the command line does for its help and to check a scene, reads the schema only
from .schema import (MIN_NODES_PER_BENDING_LENGTH, SHELL_SCHEMA, WRINKLE_NODES, Scene, nodes_per_bending_length,
                     run_time_forecast, wrinkle_nodes)

__all__ = ["SHELL_SCENE", "RESTART_FIXED", "classify_scene", "resume_scene", "run_scene"]


def run_scene(scene: Scene, progress: bool = False) -> TraceResult:
    """Trace a resolved shell scene: the point load or an indenter, under displacement or force control, or a
    uniform pressure under volume control (displacement) or pressure control (force)."""
    from .build import contact_settings, is_papers_cap
    from .point import run_point, run_point_force

    kind, control = scene["load"]["kind"], scene["load"]["control"]
    if scene.get("stability", {}).get("follow"):
        from .follow import run_followed

        result = run_followed(scene, progress)
    elif scene.get("view", {}).get("kind") == "3d":
        from .view3d import run_view3d

        result = run_view3d(scene, progress)
    elif kind in ("sphere", "plate"):
        # imported here: a point-load trace never loads the contact runner (nor scipy.optimize)
        from .contact import run_contact, run_contact_force

        st, w_end = contact_settings(scene, progress)
        run = run_contact_force if control == "force" else run_contact
        result = run(scene, progress, st, w_end)
    elif kind == "pressure":
        from .pressure import run_pressure  # either control: load.control = displacement prescribes the volume

        result = run_pressure(scene, progress)
    elif not is_papers_cap(scene) or kind == "ring":
        from .revolution import run_revolution  # any other shell, or a ring load

        result = run_revolution(scene, progress)
    else:
        result = run_point_force(scene, progress) if control == "force" else run_point(scene, progress)
    if not result.success and result.status != "incomplete":
        advice = result.summary.setdefault("advice", [])
        if kind in ("sphere", "plate") and control == "force" and _stopped_on_contact_steps(result.message):
            advice.append(CONTACT_STEPS_ADVICE)
        advice.append(mesh_advice(scene))
    elif result.status == "incomplete" and (winding := winding_advice(scene)):
        result.summary.setdefault("advice", []).append(winding)
    return result


def resume_scene(scene: Scene, start: Any, progress: bool = False) -> TraceResult:
    """Restart a shell scene from a saved point (``contin trace --from OUT --label K``, :mod:`contin.app.restart`).

    Supported: the point load on the paper's cap (:func:`contin_models.shell_scene.point.resume_point`), under
    either control whatever control saved the point (the state is carried over, so a point of the
    displacement path can be loaded on by a dead load and back), and a followed path of any scene from a point of
    one of its pieces (:func:`contin_models.shell_scene.follow.resume_followed`).  The other loads and shells are
    refused.
    """
    from .build import is_papers_cap
    from .point import resume_point

    if scene.get("stability", {}).get("follow"):
        from .follow import resume_followed

        return resume_followed(scene, start, progress)
    if scene.get("view", {}).get("kind") == "3d":
        raise SceneError("a restart from a saved point is supported in the axisymmetric view (view.kind = "
                         "\"axisymmetric\"); this scene has view.kind = \"3d\": trace it anew", "constraint")
    if scene["load"]["kind"] != "point" or not is_papers_cap(scene):
        raise SceneError(f"a restart from a saved point is supported for the point load on the paper's cap "
                         f"(load.kind = \"point\", shell.geometry = \"sphere\", shell.boundary = \"sliding\", no "
                         f"imperfection); this scene has load.kind = \"{scene['load']['kind']}\", shell.geometry = "
                         f"\"{scene['shell']['geometry']}\", shell.boundary = \"{scene['shell']['boundary']}\": trace it "
                         f"anew", "constraint")
    return resume_point(scene, start, progress)


#: Scene keys a restart keeps: they fix the mesh, the support or the load, i.e. the unknowns of the saved state.
RESTART_FIXED = ("shell.N", "shell.pole_ratio", "shell.geometry", "shell.boundary", "shell.table", "load.kind",
                 "imperfection.kind", "imperfection.delta_over_h", "imperfection.lambda_I", "imperfection.waves", "view.kind", "view.symmetry",
                 "view.harmonics", "view.angles")


#: What a force-controlled indentation that stops on the contact ring's steps should try.
CONTACT_STEPS_ADVICE = (
    "under force control the indentation stopped at a limit load that the shell barely leaves, or at "
    "more of them than a snap has: where the indenter touches the cap along a ring on a coarse mesh, "
    "the force along the path keeps a small wave at the node spacing (docs/robustness.md), and each "
    "wave is a small limit load; trace the scene under displacement control "
    "(load.control = \"displacement\"), which passes them")


def _stopped_on_contact_steps(message: str) -> bool:
    """Whether a force-controlled indentation failed on a landing next to its fold or on too many snaps."""
    return "landed back next to the fold" in message or "max_snaps" in message


#: Nodes over the bending length beyond which a finer mesh is no longer the first thing to try.
WELL_RESOLVED_NODES = 16


def mesh_advice(scene: Scene) -> str:
    """What to try first when a run fails numerically, with how well the mesh resolves the cap.

    In the random scenes of ``studies/fuzz.py`` most numerical failures came from meshes too coarse
    for the bending length ``sqrt(R h)`` (those are now refused), so on a coarse mesh the advice is a
    finer one.  On a mesh with :data:`WELL_RESOLVED_NODES` or more nodes over that length a finer mesh
    is unlikely to help (the default cap at N = 800 has 147 there, and its failures were in the
    solver, e.g. a snap's energy descent): the advice is then the other control, or a smaller step.
    This is advice, not a diagnosis.
    """
    s = scene["shell"]
    per_length = nodes_per_bending_length(s)
    head = (f"the mesh has {per_length:.1f} nodes over the bending length sqrt(R h) (at least "
            f"{MIN_NODES_PER_BENDING_LENGTH} are required)")
    if per_length < WELL_RESOLVED_NODES:
        return f"{head}; the first thing to try is a finer mesh, shell.N = {2 * s['N']}"
    other = "displacement" if scene["load"]["control"] == "force" else "force"
    return (f"{head}, so a finer mesh is unlikely to help; try the other control (load.control = \"{other}\") "
            f"or a smaller continuation.ds_max")


def winding_advice(scene: Scene) -> str | None:
    """What to try when the automatic step limit cut a path short on a mesh too coarse for its middle, or None.

    A path that runs out of the automatic limit (``continuation.max_steps = "auto"``) kept finding folds
    to the end: it wound.  On a mesh below :data:`WRINKLE_NODES` nodes over the bending length that is
    the broken-up wrinkle train of the path's middle, which more steps do not end and a finer mesh does.
    On a finer mesh, or under a step limit the user chose, there is nothing to add to raising the limit.
    """
    s = scene["shell"]
    if scene["continuation"]["max_steps"] != "auto" or s.get("geometry", "sphere") != "sphere":
        return None
    per_length = nodes_per_bending_length(s)
    if per_length >= WRINKLE_NODES:
        return None
    needed = wrinkle_nodes(s, WRINKLE_NODES)
    return (f"the path wound through folds until the automatic step limit, on a mesh with {per_length:.1f} nodes "
            f"over the bending length sqrt(R h); in the middle of a thin deep cap's path a train of wrinkles "
            f"about 0.4 sqrt(R h) long forms, and with fewer than {WRINKLE_NODES:g} nodes over that length the "
            f"train breaks up into a path that folds back and forth without end, which more steps do not "
            f"change: the first thing to try is a finer mesh, shell.N = {needed}")


#: Fields of :func:`classify` copied into a :class:`~contin.app.scene.Classification` (``contin classify --json``).
_CLASSIFY_FIELDS = ("F_max", "w_at_F_max", "F_min", "w_at_F_min", "F_max_norm", "w_at_F_max_over_R", "F_min_norm",
                    "w_at_F_min_over_R", "n_folds_in_w", "n_limit_points_in_F", "F_negative_on_stable_path",
                    "classification_on_partial_path", "max_strain", "w_at_max_strain_over_R")


def classify_scene(scene: Scene, progress: bool = False) -> Classification:
    """Classify a shell scene (``contin classify --model shell``).

    The class is defined on the displacement-controlled path to eversion (``docs/model.md#classes``),
    so that path is traced whatever ``load.control`` says; every other key of the scene
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
    contin.app.scene.SceneError
        For a sphere or plate indenter: the class is defined on the point-load path.
    """
    from .point import path_complete

    check_classifiable(SHELL_SCENE, scene)  # an indenter has no class: refused, also when called directly
    path_scene = {section: dict(keys) for section, keys in scene.items()}
    path_scene["load"]["control"] = "displacement"
    path_scene["output"]["figure"] = False
    trace = run_scene(path_scene, progress)
    summ = trace.summary
    label = summ.get("classification")
    followed = summ.get("followed")
    if followed is not None:  # the class on the path the cap really takes (bistable can be proven by part of it)
        label = (followed.get("classification")
                 if followed.get("status") == "completed" or followed.get("classification") == "bistable" else None)
    values: dict[str, Any] = {"control_traced": "displacement"}
    values.update({k: summ[k] for k in _CLASSIFY_FIELDS if k in summ})
    values.update({k: summ[k] for k in ("lambda", "D", "F_unit", "eversion_w") if k in summ})
    s = scene["shell"]
    lines = [f"scene: R = {s['R']:g}, h/R = {s['h'] / s['R']:g}, phi_hat = {s['phi_hat']:g}, nu = {s['nu']:g}, "
             f"N = {s['N']}; lambda = {summ['lambda']:.4g}"]
    complete = trace.complete and bool(trace.branches) and path_complete(trace.branches[0])
    rows = [("", "F", "w", "F R/(2 pi D)", "w/R", "")]
    for tag, what in (("max", "first local maximum of F: the snap load under force control"),
                      ("min", "last local minimum of F: the snap-back load on unloading")):
        F = summ.get(f"F_{tag}")
        if F is None:
            rows.append((f"F_{tag}", "-", "-", "-", "-", "none on the path" if complete else
                         "not found on the part traced: the path stopped before eversion"))
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
    first = summ.get("first_instability")
    if first is not None:
        values["first_instability"] = first
        if first["kind"] == "bifurcation":
            values.update({"first_bifurcation_n": first["n"], "first_bifurcation_w_over_R": first.get("w_over_R"),
                           "first_bifurcation_F_norm": first.get("F_norm")})
            waves = "1 circumferential wave" if first["n"] == 1 else f"{first['n']} circumferential waves"
            whose = ("the class above is the followed path's (below)" if followed is not None else
                     "the class is that of the axisymmetric path, which the shell leaves there (stability.follow = "
                     "true classifies the path it takes)")
            lines.append(f"asymmetric: before its first fold in w the path bifurcates into the mode of {waves} "
                         f"(n = {first['n']}) at w = {first['w']:.6g} (F = {first['F']:.6g}); {whose}")
    elif scene.get("stability", {}).get("harmonics"):
        lines.append("asymmetric: no bifurcation into a non-axisymmetric mode along the path")
    if followed is not None:
        values["followed"] = {k: followed.get(k) for k in ("classification", "F_max", "w_at_F_max", "F_min",
                                                           "w_at_F_min", "n_snaps", "status", "message")}
        values["axisymmetric_classification"] = summ.get("classification")
        # flat copies for a sweep's table, which keeps numbers and flags only
        values.update({f"followed_{k}": followed.get(k) for k in ("F_max_norm", "w_at_F_max", "F_min_norm",
                                                                  "w_at_F_min", "n_snaps")})
        values["followed_left_axisymmetric"] = any(item.get("symmetry") not in (None, "O(2)")
                                                   for item in followed.get("path", ()))
        lines.append(f"followed path: {followed.get('message')}; {followed.get('left_axisymmetric')}")
        if followed.get("F_max") is not None:
            lines.append(f"followed path: first local maximum of F = {followed['F_max']:.6g} at w = "
                         f"{followed['w_at_F_max']:.6g}, least F = {followed['F_min']:.6g} at w = "
                         f"{followed['w_at_F_min']:.6g}, {followed['n_snaps']} snap(s); the "
                         "table above is the axisymmetric path's")
    lines += [f"warning: {w}" for w in summ.get("warnings", [])]
    values["path_complete"] = complete
    failure = "" if label is not None else summ.get("classification_note", "the path could not be traced")
    return Classification(label=label, values=values, lines=lines, trace=trace, failure=failure)


#: The class is defined on the point-load path (``docs/model.md#classes``): ``contin classify``
#: refuses an indenter and says what to run instead.
_CLASSIFY_REQUIRES = (
    Constraint(("load.kind",), lambda s: s["load"]["kind"] == "point", 'load.kind = "point"',
               "the classes monotonous, monostable and bistable are defined on the displacement path of the point "
               "load at the pole, docs/model.md#classes; an indenter can only push, so its path has no F < 0 to "
               "classify. The class of this cap: the same command with --set load.kind=point. The indenter's own "
               "snap (w_b_c, F at the snaps): 'contin trace' with this scene, in summary.json"),
    Constraint(("view.kind",), lambda s: s["view"]["kind"] == "axisymmetric", 'view.kind = "axisymmetric"',
               "the classes are defined on the axisymmetric path of the point load (docs/model.md#classes); "
               "'contin trace' with view.kind = \"3d\" traces the path in the 3-D view and locates where it breaks "
               "its symmetry"),
    Constraint(("shell.geometry", "shell.boundary", "imperfection.kind"),
               lambda s: s["shell"]["geometry"] == "sphere" and s["shell"]["boundary"] == "sliding"
               and s["imperfection"]["kind"] == "none",
               'shell.geometry = "sphere", shell.boundary = "sliding", imperfection.kind = "none"',
               "the classes are the paper's, defined for its perfect spherical cap on the sliding base "
               "(docs/model.md#classes); for another shell 'contin trace' reports the limit loads F_max, F_min and the "
               "folds in w in summary.json"),
)

SHELL_SCENE = SceneModel(
    name="shell",
    description="spherical cap under a point load at the pole: the whole path to eversion, folds in w and F, "
                "stability under both controls, classification",
    schema=SHELL_SCHEMA,
    runner=run_scene,
    classifier=classify_scene,
    classify_requires=_CLASSIFY_REQUIRES,
    resumer=resume_scene,
    restart_fixed=RESTART_FIXED,
    forecast=run_time_forecast,
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
