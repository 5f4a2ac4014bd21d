"""``stability.follow = true``: the path the shell really takes, as a scene's run.

The scene's axisymmetric path is traced as without ``follow`` (it is drawn faded in the diagram, and its
classification stays in the summary); then :func:`contin_models.shell.followed.follow_path` follows the stable path
from the unloaded shell to the end of the load: along the axisymmetric path to its first loss of stability, onto a
stable emanating branch in the 3-D view of its symmetry (``D_n``, with ``view.harmonics`` harmonics) where one rises,
else snapping to the next stable state, and so on.

Outputs: ``branch.csv`` holds the axisymmetric path (``branch`` 0) and the followed pieces (``branch`` 1, 2, ...)
with the columns ``symmetry`` (``O(2)``, ``D3``, ...) and ``n`` (the waves of the piece's symmetry, 0 for
``O(2)``); ``summary.json`` lists the branches (id, symmetry, parent, the point it came from, how it ended) and the
followed path as a sequence of pieces and snaps; the status line says where the path left the axisymmetric branch
and into how many waves.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import contin
from contin.analyses.conjugate import ConjugateControl
from contin.app.scene import TraceResult, branch_columns, special_point_records, special_point_table

from .build import build, length_unit, loaded_end, traced_structure, travel
from .labels import force_axes, length_symbol, pressure_axes, scene_title
from .pressure import VOLUME_LABELS, volume_problem, volume_settings
from .schema import STABILITY_COLUMNS, Scene
from .view3d import surfaces_drawer

__all__ = ["run_followed", "followed_branches", "classify_followed", "followed_shapes", "point_symmetries"]

_AXI = "axisymmetric path"



def _first(branch: Any, name: str) -> float:
    return float(branch.observables[name][0]) if len(branch) else float("nan")


def _piece_label(piece: Any) -> str:
    return f"piece {piece.index + 1}: {piece.symmetry}"


def followed_branches(fp: Any, pname: str, R: float, unit: str = "R") -> list[dict[str, Any]]:
    """``summary.json``'s ``branches`` of a followed path: per piece its id (the ``branch`` column), symmetry,
    waves, parent, how it started and ended, and where (the parameter at both ends, and over the scene's length
    unit ``R``: ``..._over_R`` whatever the geometry calls its length; a volume change over the unloaded volume,
    ``R`` = V0 with ``unit = "V0"``: ``..._over_V0``)."""
    rows = []
    for pc in fp.pieces:
        br = pc.branch
        rows.append({"id": pc.index + 1, "symmetry": pc.symmetry, "n": pc.waves,
                     "parent": None if pc.parent is None else pc.parent + 1, "from": pc.start,
                     f"{pname}_start": float(pc.start_p), f"{pname}_end": float(br.p[-1]) if len(br) else None,
                     "ended": pc.end, "points": len(br), "relocated": pc.relocated,
                     f"{pname}_start_over_{unit}": float(pc.start_p) / R,
                     f"{pname}_end_over_{unit}": float(br.p[-1]) / R if len(br) else None})
    return rows


def run_followed(scene: Scene, progress: bool = False) -> TraceResult:
    """Trace the scene's axisymmetric path and the path the shell really takes (module docstring).

    Parameters
    ----------
    scene : dict
        A resolved scene with ``stability.follow = true`` (and ``stability.harmonics = true``).
    progress : bool
        Print each step of the followed path to stderr.

    Returns
    -------
    TraceResult
    """
    from contin_models.shell.followed import follow_path

    from .scene import run_scene

    plain = {**scene, "stability": {**scene["stability"], "follow": False}}
    axi = run_scene(plain, progress)
    b = build(scene, progress)
    source, settings, u0, p0, options = _followed_start(scene, b, progress)
    fp = follow_path(source, u0, p0, settings, **options)
    return followed_result(scene, axi, b, source, fp, options)


def resume_followed(scene: Scene, start: Any, progress: bool = False) -> TraceResult:
    """Restart a saved followed path from a point of one of its pieces (``contin trace --from OUT --label K``).

    The piece's view is built again from the scene and the piece's record (``meta["followed"]``, see
    :func:`followed_result`), the path is followed on from the stored point at the label (the stored point before
    it when the label is a located point between two, or the located point that ended the piece), and joined to the
    saved path before it: the saved pieces before, the piece up to that point, and the pieces traced from it.  The
    result describes the whole path, as a fresh run with the new settings would; the axisymmetric path beside it is
    traced again.  Only the continuation and output sections may differ from the saved run's scene.

    Raises
    ------
    contin.app.restart.RestartError
        The saved run holds its points alone or predates these records, the label is on the axisymmetric path
        (branch 0, drawn for comparison) or at a landing after which nothing was traced, the scene changes the
        path, or the saved state is not an equilibrium of the view built again.
    """
    from contin.app.restart import RestartError, SavedPrefix, join_branches, path_changes, saved_scene
    from contin_models.shell.followed import END_TOL, STOPS, FollowedPath, Piece, Snap, follow_path, rebuild_view

    from .scene import SHELL_SCENE, run_scene

    saved = start.saved
    if saved is None:
        raise RestartError("the saved run holds its special points alone (it was traced before whole runs were "
                           "saved): trace the followed path anew")
    records = [br.meta.get("followed") for br in saved.branches[1:]]
    if not records or any(r is None for r in records):
        raise RestartError("the saved run's pieces carry no record of their views (it was traced before followed "
                           "paths could be restarted): trace it anew")
    landing = [i for i, r in enumerate(records) if start.jump is not None and r["jump"] == start.jump]
    if landing:  # a snap's landing: the first stored point of the piece it starts
        start.branch, start.kind, start.special = landing[0] + 1, "landing", None
    if start.branch == 0:
        raise RestartError(f"{start.describe()} lies on branch 0, the axisymmetric path drawn beside the followed one "
                           f"for comparison; restart from a point of the followed path: branches 1 to "
                           f"{len(records)}, its pieces (the 'branch' column of branch.csv)")
    if start.branch > len(records):
        raise RestartError(f"{start.describe()} is a snap's landing after which the saved run traced nothing: restart "
                           "from the point the shell snapped from")
    changed = path_changes(saved_scene(SHELL_SCENE, {"scene": start.saved_scene}), scene)
    if changed:
        raise RestartError(f"a restart of a followed path continues the saved path, and {', '.join(changed)} changed; "
                           "only the continuation and output sections may change: trace the scene anew for another "
                           "structure or load")
    plain = {**scene, "stability": {**scene["stability"], "follow": False}}
    axi = run_scene(plain, progress)
    b = build(scene, progress)
    source, settings, _, _, options = _followed_start(scene, b, progress)
    k = start.branch - 1  # the piece the point lies on
    views = [rebuild_view(r["view"], source, options["structure"]) for r in records[:k + 1]]
    br = saved.branches[k + 1]
    if start.kind == "landing":
        keep = 1
    elif start.kind == "end" or start.special is None:
        keep = len(br)
    else:
        keep = int(br.special_points[start.special].index) + 1
    if keep == len(br) and records[k]["end"] in STOPS:  # the located point that ended the piece is singular
        keep -= 1
    keep = max(keep, 1)
    u0, p0 = np.asarray(br.u[keep - 1], dtype=float), float(br.p[keep - 1])
    end, p_end = options.get("end"), options.get("p_end", math.inf)
    # at the end within the tolerance the path's end is reached with (a bound is located to it, not exactly)
    if p0 >= p_end - END_TOL * max(1.0, abs(p_end)) or (
            end is not None
            and float(views[k].evaluate_observables(u0, p0)[end[0]]) >= end[1] - END_TOL * max(1.0, abs(end[1]))):
        raise RestartError(f"{start.describe()} lies at the end of the load: there is nothing to follow from it")
    residual = float(np.max(np.abs(views[k].residual(u0, p0))))
    scale = float(getattr(views[k], "residual_scale", 1.0) or 1.0)
    if not residual <= 1e-6 * scale:
        raise RestartError(f"the saved state of piece {k + 1} at {source.parameter_name} = {p0:.10g} is not an "
                           f"equilibrium of its view built again from the scene (residual {residual:.3g}, scale "
                           f"{scale:.3g}): trace the followed path anew")
    tail = follow_path(source, u0, p0, settings, start_problem=views[k], **options)
    if not tail.pieces:
        raise RestartError(f"the followed path could not start again from piece {k + 1}: {tail.message}")
    pieces = [Piece(i, views[i], saved.branches[i + 1], r["symmetry"], int(r["waves"]), r["parent"], r["start"],
                    float(r["start_p"]), r["end"], r.get("relocated")) for i, r in enumerate(records[:k])]
    head = br.head(keep)
    first = tail.pieces[0]
    pieces.append(Piece(k, views[k], join_branches(head, first.branch, repeated=True), records[k]["symmetry"],
                        int(records[k]["waves"]), records[k]["parent"], records[k]["start"],
                        float(records[k]["start_p"]), first.end, records[k].get("relocated")))
    for pc in tail.pieces[1:]:
        pieces.append(Piece(pc.index + k, pc.problem, pc.branch, pc.symmetry, pc.waves,
                            None if pc.parent is None else pc.parent + k, pc.start, pc.start_p, pc.end, pc.relocated))
    # the view a saved snap's descent ran in is not saved: its landing piece's stands in (the outputs read the jump
    # and the pieces' branches, not that view)
    snaps = [Snap(int(r["parent"]), i, float(r["start_p"]), views[i], str(r["landing_symmetry"] or r["symmetry"]),
                  saved.jumps[int(r["jump"])]) for i, r in enumerate(records[:k + 1]) if r["jump"] is not None]
    snaps += [Snap(sn.from_piece + k, None if sn.to_piece is None else sn.to_piece + k, sn.p, sn.view, sn.symmetry,
                   sn.jump) for sn in tail.snaps]
    fp = FollowedPath(pieces, snaps, tail.status, tail.message, tail.label)
    # the command line then says that the results describe the whole path
    start.prefix = SavedPrefix([saved.branches[i + 1] for i in range(k)],
                               [sn.jump for sn in snaps[:len(snaps) - len(tail.snaps)]], head, at_stored_point=True,
                               s=float(head.s[-1]))
    return followed_result(scene, axi, b, source, fp, options)


def _followed_start(scene: Scene, b: Any, progress: bool) -> tuple[Any, Any, np.ndarray, float, dict[str, Any]]:
    """Where and how the scene's path is followed (:func:`~contin_models.shell.followed.follow_path`): the traced
    model (under a prescribed volume, the pressure-controlled model under :class:`contin.ConjugateControl`), its
    settings and start, and the keywords: the structure, the control's label, the harmonics, the events (the load's
    extrema; under a prescribed volume the largest volume, which ends a piece), the end of the load and the
    progress lines."""
    import sys

    from contin_models.shell.structure import ShellOfRevolution

    source, settings, u0, p0 = b.problem, b.settings, b.u0, b.p0
    control = scene["load"]["control"]
    pressure = scene["load"]["kind"] == "pressure"
    indenter = scene["load"]["kind"] in ("sphere", "plate")
    volume = pressure and control == "displacement"
    structure = traced_structure(scene, source)
    label = control
    if volume:  # the volume change is the parameter, the pressure its multiplier: the traced model as pressure.py's
        source = volume_problem(b.problem, travel(scene))
        settings = volume_settings(scene, source, progress)
        u0, p0 = source.from_load_state(b.u0, b.p0)
        label = VOLUME_LABELS[0]
    say = (lambda text: print(f"follow: {text}", file=sys.stderr, flush=True)) if progress else None
    # the load's extrema located on every piece, as on the axisymmetric path: the class reads them
    events = [] if pressure else [contin.extremum("F", which, folds="F", stability_label="force")
                                  for which in ("max", "min")]
    if volume:  # where a piece turns back in the volume it leaves it: located even where the turn is a pitchfork too
        events = [contin.extremum("dV", "max", terminal=True, folds="dV", stability_label=VOLUME_LABELS[0])]
    if pressure:  # the scene's end pressure (volume) or eversion, whichever comes first (the settings hold both)
        ends: dict[str, Any] = {"p_end": float(settings.p_max), "end": ("w", float(settings.bounds["w"][1]))}
    elif indenter:  # the indenter's travel to its end
        ends = {"p_end": float(b.w_end)}
        if scene["load"]["kind"] == "plate":
            # the axisymmetric run stops where the plate comes within 2 dhat of the base ring (the bounds of
            # contact.py), beyond which the barrier would press on the support; the pieces in 3-D views have no
            # such observable, but the base ring is held at its height, so the plate's gap falls as it travels
            gap = float(source.evaluate_observables(u0, p0)["base_gap"])
            ends["p_end"] = min(ends["p_end"], p0 + gap - 2.0 * float(source.dhat))
    else:  # a prescribed deflection ends at its end; a dead load goes on until the shell everts
        w_end = loaded_end(scene, source) if isinstance(source, ShellOfRevolution) else b.w_end
        ends = {"p_end": float(w_end)} if control == "displacement" else {"end": ("w", float(w_end))}
    return source, settings, u0, p0, {"structure": structure, "label": label, "K": int(scene["view"]["harmonics"]),
                                      "events": events, "say": say, **ends}


def followed_result(scene: Scene, axi: TraceResult, b: Any, source: Any, fp: Any,
                    options: dict[str, Any]) -> TraceResult:
    """The outputs of a followed path ``fp`` of the scene (module docstring), beside its axisymmetric trace ``axi``:
    the branches (the axisymmetric path, then the pieces, each with ``meta["followed"]``: what a restart rebuilds
    the piece from), the jumps, ``summary.json``'s ``followed``, the table, the columns, the figures.  ``b`` is the
    scene's build, ``source`` and ``options`` what :func:`_followed_start` made of it."""
    from contin_models.shell.followed import view_descriptor

    R = length_unit(scene)  # the sphere's radius, a cone's or plate's base radius, ...
    control = scene["load"]["control"]
    pressure = scene["load"]["kind"] == "pressure"
    indenter = scene["load"]["kind"] in ("sphere", "plate")
    volume = pressure and control == "displacement"
    label, structure = options["label"], options["structure"]
    pname = source.parameter_name
    path = axi.branches[0]
    pieces = [pc.branch for pc in fp.pieces]
    branches = [path] + pieces
    labels = [_AXI] + [_piece_label(pc) for pc in fp.pieces]
    jumps, jump_obs = [], []
    landed_by: dict[int, tuple[int, str]] = {}  # piece -> (its jump in jumps, the landing's symmetry)
    jump_branches: list[tuple[int, int | None]] = []  # per jump: (the branch it leaves, the branch it lands on)
    for sn in fp.snaps:
        before = fp.pieces[sn.from_piece].branch
        after = fp.pieces[sn.to_piece].branch if sn.to_piece is not None and sn.to_piece < len(fp.pieces) else None
        if after is None or not len(after):
            continue
        landed_by[int(sn.to_piece)] = (len(jumps), sn.symmetry)
        jump_branches.append((sn.from_piece + 1, sn.to_piece + 1))  # branch 0 is the axisymmetric path
        jumps.append(sn.jump)
        jump_obs.append(({"p": float(before.p[-1]), **{k: float(v[-1]) for k, v in before.observables.items()}},
                         {"p": float(after.p[0]), **{k: float(v[0]) for k, v in after.observables.items()}}))
    for pc in fp.pieces:
        jump, landing = landed_by.get(pc.index, (None, None))
        pc.branch.meta["followed"] = {"index": pc.index, "symmetry": pc.symmetry, "waves": pc.waves,
                                      "parent": pc.parent, "start": pc.start, "start_p": float(pc.start_p),
                                      "end": pc.end, "view": view_descriptor(pc.problem), "jump": jump,
                                      "landing_symmetry": landing, "relocated": pc.relocated}
    # a pressure has one stability label (the primary one); point and ring loads both controls' columns
    cols = branch_columns(branches, None if pressure else STABILITY_COLUMNS)
    measured = [point_symmetries(pc) for pc in fp.pieces]
    cols["symmetry"] = np.concatenate([np.full(len(path), "O(2)", dtype=object)]
                                      + [np.array(m[0], dtype=object) for m in measured])
    cols["n"] = np.concatenate([np.zeros(len(path), dtype=int)] + [np.array(m[1], dtype=int) for m in measured])
    records = special_point_records(branches, jumps, jump_obs, parameter_name=pname)
    summary = dict(axi.summary)
    summary["followed"] = {"status": fp.status, "message": fp.message, "stability_label": label,
                           "harmonics": int(scene["view"]["harmonics"]),
                           "branches": (followed_branches(fp, pname, float(b.problem.pressure.V0), "V0") if volume
                                        else followed_branches(fp, pname, R)),
                           "path": _path_sequence(fp, pname)}
    left = next((pc for pc in fp.pieces if pc.symmetry != "O(2)"), None)
    if left is None:
        where = f"the followed path stays axisymmetric ({len(fp.snaps)} snap(s))"
    else:
        how = (f"into {left.waves} wave{'s' if left.waves > 1 else ''} ({left.symmetry})" if left.waves
               else f"to a state of symmetry {left.symmetry}")
        verb = "snaps" if left.start == "snap" else "turns"
        unit = length_symbol(scene["shell"])
        at = f"{pname}/{unit} = {left.start_p / R:.4g}" if pname in ("w", "w_b") else f"{pname} = {left.start_p:.6g}"
        if volume:  # the volume it leaves at, and the pressure there (a snap drops it at that volume)
            before = fp.pieces[left.parent].branch if left.parent is not None else left.branch
            at = (f"dV/V0 = {_first(left.branch, 'dV_over_V0'):.4g}, "
                  f"p/p_c = {float(before.observables['p_over_p_c'][-1]):.4g}")
        where = f"the followed path leaves the axisymmetric branch at {at}: it {verb} {how}"
    if control == "displacement" and not pressure and not indenter:  # the classes: the point load's displacement path
        if fp.success:
            summary["followed"].update(classify_followed(fp, float(summary.get("D") or 0.0), R))
        else:  # a class read off part of the path would be a guess (the rest may snap or fall below zero), but for
            # a force below zero on a stable piece, which proves the cap bistable, as on the axisymmetric path
            summary["followed"]["classification"] = "bistable" if negative_on_stable_pieces(fp) else None
    else:  # a dead load, a pressure or an indenter: where it snaps
        summary["followed"]["snap_loads"] = [float(sn.p) for sn in fp.snaps]
        if volume:  # the volume is held through a snap; the pressure drops: before and after, over p_c
            summary["followed"]["snap_pressures_over_p_c"] = [[before["p_over_p_c"], after["p_over_p_c"]]
                                                                  for before, after in jump_obs]
    cls = summary["followed"].get("classification")
    if cls is not None:
        same = cls == summary.get("classification")
        where += (f"; on the followed path the shell is {cls}"
                  + ("" if summary.get("classification") is None else
                     (", as on the axisymmetric path" if same else
                      f", not {summary.get('classification')} as on the axisymmetric path")))
    summary["followed"]["left_axisymmetric"] = where
    message = f"{fp.message}; {where}"
    failure = "" if fp.success else f"the followed path stopped: {fp.message}"
    L = length_symbol(scene["shell"])
    D = summary.get("D")
    if volume:  # the pressure against the volume pushed in, as the traced path under a prescribed volume
        options, x, y = pressure_axes(b.problem.p_c), "dV_over_V0", "p_over_p_c"
        options["axis_labels"]["dV_over_V0"] = r"$\Delta V / V_0$"
    elif pressure:
        options, x, y = pressure_axes(source.p_c), "w_over_h", "p_over_p_c"
    else:
        x, y = ("w_b" if indenter else "w"), "F"
        options = force_axes(x, R, D, length_symbol=L, w_symbol=x,
                             scaled={"w_over_L": x, "F_norm": "F"} if x == "w" else {"F_norm": "F"}) \
            if D is not None else {}
    # the axisymmetric path beneath, faded, without its points: the followed pieces are read against it
    plot_options = {**options, "title": f"followed path: {scene_title(scene)}",
                    "control": "volume" if volume else ("pressure" if pressure else control),
                    "special_kinds": ("fold", "branch_point", "bifurcation"), "faded": [0]}

    shapes = followed_shapes(fp, structure)
    result = TraceResult(branches=branches, jumps=jumps, summary=summary, special_points=records,
                         table=special_point_table(records, pname), csv_columns=cols, x=x, y=y,
                         parameter_name=pname, labels=labels, jump_observables=jump_obs, failure=failure,
                         jump_branches=jump_branches,
                         stability=None if pressure else control, plot_options=plot_options, shapes=shapes,
                         draw_shapes=surfaces_drawer(shapes, R, float(scene["shell"]["h"]), pname,
                                                     length_symbol(scene["shell"])))
    for br in pieces[-1:]:
        br.message = message
    return result


def _surface(problem: Any, u: np.ndarray, p: float, theta: np.ndarray) -> np.ndarray:
    """Cartesian points ``(N, angles, 3)`` of a state of a piece: the 3-D view's own, or the axisymmetric state's
    meridian turned about the axis."""
    from contin_models.shell.lift import is_view

    if is_view(problem):
        return problem.view.points(problem.full_state(u, p), theta)
    x = problem.base.full_state(*problem.split(u)) if isinstance(problem, ConjugateControl) else problem.full_state(u, p)
    return _turned(x[0::2], x[1::2], theta)


def _turned(r: np.ndarray, z: np.ndarray, theta: np.ndarray) -> np.ndarray:
    return np.stack([np.outer(r, np.cos(theta)), np.outer(r, np.sin(theta)), np.outer(z, np.ones_like(theta))], axis=-1)


def followed_shapes(fp: Any, structure: Any) -> dict[str, np.ndarray]:
    """``shapes.npz`` of a followed path: the shell where each piece ends at a located point (where it leaves a
    branch or snaps), then at the path's end, with the arrays of :func:`contin_models.shell_scene.view3d.surface_shapes`
    (``state_representation`` holds the symmetry of the piece the state lies on)."""
    from .view3d import SURFACE_ANGLES

    theta = np.linspace(0.0, 2.0 * np.pi, SURFACE_ANGLES)
    rows = []
    for pc in fp.pieces:
        br = pc.branch
        if not len(br):
            continue
        if pc.end in ("fold", "bifurcation", "branch_point") and br.special_points:
            spt = br.special_points[-1]
            key = spt.info.get("key")
            what = f"{pc.symmetry} -> {key}" if spt.kind == "bifurcation" and key is not None else pc.symmetry
            rows.append((pc.index, spt.kind, spt.label, what, pc.problem, spt.u, spt.p))
    last = fp.pieces[-1] if fp.pieces else None
    if last is not None and len(last.branch):
        rows.append((-1, "end", "end of the followed path", last.symmetry, last.problem, last.branch.u[-1],
                     last.branch.p[-1]))
    if not rows:
        return {}
    X = np.array([_surface(prob, u, p, theta) for *_, prob, u, p in rows])
    x0 = structure.reference_state()
    X0 = _turned(x0[0::2], x0[1::2], theta)
    return {"theta": theta, "reference_x": X0[..., 0], "reference_y": X0[..., 1], "reference_z": X0[..., 2],
            "state_piece": np.array([r[0] for r in rows]), "state_kind": np.array([r[1] for r in rows]),
            "state_label": np.array([str(r[2]) for r in rows]), "state_representation": np.array([r[3] for r in rows]),
            "state_p": np.array([float(r[6]) for r in rows]),
            "state_x": X[..., 0], "state_y": X[..., 1], "state_z": X[..., 2]}


def point_symmetries(piece: Any) -> tuple[list[str], list[int]]:
    """The symmetry of every stored state of a piece (:func:`contin_models.shell.lift.state_symmetry` in its view's
    basis; ``O(2)`` on the axisymmetric trace) and its order (the waves' greatest common divisor, 0 for O(2))."""
    from contin_models.shell.lift import is_view, state_symmetry

    prob, br = piece.problem, piece.branch
    if not is_view(prob):
        return ["O(2)"] * len(br), [0] * len(br)
    syms = [state_symmetry(prob.basis, prob.full_state(u, p)) for u, p in zip(br.u, br.p)]
    return [s.label for s in syms], [s.order for s in syms]


def classify_followed(fp: Any, D: float, R: float) -> dict[str, Any]:
    """The class of the cap on its followed path (``docs/model.md#classes``, measured on the path taken).

    Every stored point of the followed path is stable under the control (the located points where pieces end
    aside), so the path is ``bistable`` where the force is negative somewhere on it, ``monotonous`` where it has no
    snap and no located maximum of the force, else ``monostable``.  ``F_max`` is the first local maximum of the
    force along the path: the first located maximum (``max(F)``) or the start of the first snap, whichever comes
    first; ``F_min`` the least force after it (by stored points and located minima), as on the axisymmetric path
    (None without a maximum: the force then never falls).  Empty when the path's pieces carry no force (a pressure).
    """
    runs = []
    first_max = None
    for pc in fp.pieces:
        F = pc.branch.observables.get("F")
        if F is None:
            return {}
        keep = len(F) - (1 if pc.end in ("fold", "bifurcation", "branch_point") else 0)
        minima = [(float(spt.observables["F"]), float(spt.p)) for spt in pc.branch.special_points
                  if spt.located and spt.label == "min(F)"]
        runs.append((np.concatenate([np.asarray(F[:keep], dtype=float), [m[0] for m in minima]]),
                     np.concatenate([np.asarray(pc.branch.p[:keep], dtype=float), [m[1] for m in minima]])))
        if first_max is None:
            maxima = [spt for spt in pc.branch.special_points if spt.located and spt.label == "max(F)"]
            snapped = any(sn.from_piece == pc.index for sn in fp.snaps)
            if maxima:
                first_max = (float(maxima[0].observables["F"]), float(maxima[0].p), len(runs) - 1)
            elif snapped and keep:
                first_max = (float(F[keep - 1]), float(pc.branch.p[keep - 1]), len(runs) - 1)
    force = np.concatenate([r[0] for r in runs]) if runs else np.zeros(0)
    if not force.size:
        return {}
    after = np.concatenate([_after_maximum(first_max, k, r[1]) for k, r in enumerate(runs)])
    tol = FORCE_ROUNDOFF * float(np.max(np.abs(force)))
    if np.any(force < -tol):
        kind = "bistable"
    elif first_max is None and not fp.snaps:
        kind = "monotonous"
    else:
        kind = "monostable"
    w_all = np.concatenate([r[1] for r in runs])
    i_min = int(np.flatnonzero(after)[np.argmin(force[after])]) if np.any(after) else None
    scale = R / (2.0 * np.pi * D) if D > 0 else float("nan")
    out: dict[str, Any] = {"classification": kind, "n_snaps": len(fp.snaps),
                           "F_max": None if first_max is None else first_max[0],
                           "w_at_F_max": None if first_max is None else first_max[1],
                           "F_min": None if i_min is None else float(force[i_min]),
                           "w_at_F_min": None if i_min is None else float(w_all[i_min])}
    out["F_max_norm"] = None if first_max is None else first_max[0] * scale
    out["F_min_norm"] = None if i_min is None else float(force[i_min]) * scale
    return out


def negative_on_stable_pieces(fp: Any) -> bool:
    """Whether the force falls below zero on a piece of a followed path that ended at a located point or at the end
    of the load: every stored point of such a piece is stable under the control (a piece that stopped for another
    reason may hold points past where it lost stability, and is not counted)."""
    for pc in fp.pieces:
        if pc.end not in ("fold", "bifurcation", "branch_point", "end of load"):
            continue
        F = pc.branch.observables.get("F")
        if F is None:
            return False
        keep = len(F) - (0 if pc.end == "end of load" else 1)
        F = np.asarray(F[:keep], dtype=float)
        if F.size and np.any(F < -FORCE_ROUNDOFF * float(np.max(np.abs(F)))):
            return True
    return False


def _after_maximum(first_max: tuple[float, float, int] | None, piece: int, w: np.ndarray) -> np.ndarray:
    """Which of a piece's points lie past the path's first force maximum ``(F, w, piece)``: a stable piece goes on
    in the deflection (it ends at a fold before it would turn back)."""
    if first_max is None or piece < first_max[2]:
        return np.zeros(len(w), dtype=bool)
    return np.ones(len(w), dtype=bool) if piece > first_max[2] else w >= first_max[1]


#: Relative size of a fall of the force along the followed path below which it is roundoff.
FORCE_ROUNDOFF = 1e-9


def _path_sequence(fp: Any, pname: str) -> list[dict[str, Any]]:
    """The followed path as pieces and snaps in order."""
    seq: list[dict[str, Any]] = []
    snaps = {sn.from_piece: sn for sn in fp.snaps}
    for pc in fp.pieces:
        br = pc.branch
        seq.append({"piece": pc.index + 1, "symmetry": pc.symmetry, f"{pname}_from": float(pc.start_p),
                    f"{pname}_to": float(br.p[-1]) if len(br) else None, "ended": pc.end})
        sn = snaps.get(pc.index)
        if sn is not None:
            seq.append({"snap": {"at": float(sn.p), "landing_symmetry": sn.symmetry,
                                 "energy_released": float(sn.jump.energy_from - sn.jump.energy_to)}})
    return seq
