"""Point and ring loads on any shell of revolution: the scene's run (``load.kind = "point"`` or ``"ring"``).

The paper's cap (a perfect spherical cap on the sliding base) under a point load keeps its own run
(:mod:`contin_models.shell_scene.point`: quasistatic snaps under force control, the classification).
Every other point- or ring-loaded scene -- another ``shell.geometry``, a pinned, clamped support, an
``[imperfection]``, a ring load -- is traced here: the connected equilibrium path of
:class:`contin_models.shell.structure.ShellOfRevolution` from the unloaded shell by pseudo-arclength
continuation through every fold, under the scene's control:

``"displacement"`` (default)
    the loaded node's deflection ``w`` (the pole's, or the ring's; positive down) is prescribed and
    the load ``F`` is its reaction; a maximum or minimum of ``F`` is located as a limit load (a fold
    under force control).
``"force"``
    the total load ``F`` (positive pushing down) is the parameter; an extremum of ``w`` is located
    as a fold under displacement control.

The path ends at the deflection ``w = 2 H (1 + continuation.overshoot)``, ``H`` the shell's rise (a
plate: ``10 h (1 + overshoot)``); a ring's at its own circle's eversion, ``2 (z_ring - z_edge) (1 +
overshoot)``; and a path that comes back to the unloaded height ``w = 0`` ends there (with a warning).  Every point is labelled under both controls (``"force"``: the
Hessian on all unknowns; ``"displacement"``: without the loaded node's height).

``summary.json``: ``geometry``, ``boundary``, ``load`` (``"point"`` or ``"ring"``), ``ring_radius`` and
``ring_node_radius`` (ring), ``control``, ``H``, ``eversion_w``, ``w_end``, ``length_unit``, ``D`` (the
bending stiffness at the loaded node), ``F_unit = 2 pi D / L``, ``imperfection``, ``n_folds_in_w``,
``n_limit_points_in_F``, the first maximum of ``F`` along the path (``F_max``, ``w_at_F_max``, the snap
load under force control) and the next minimum (``F_min``, ``w_at_F_min``), and the first fold in
``w`` (``w_fold``, ``F_at_w_fold``: the snap under displacement control); None where there is none.
Special points carry ``F``, ``w``, ``w_over_h``, ``w_over_L``, ``F_norm`` (and ``w_pole`` for a ring).
``branch.csv`` has those columns and both labels' stability.
"""

from __future__ import annotations

import math
from typing import Any

import contin
from contin.app.scene import TraceResult, branch_columns, special_point_records, special_point_table
from contin.results.branch import Branch

from .build import LOWEST_W, length_unit, loaded_end, loaded_travel, revolution_problem, revolution_settings
from .deformed import LoadSketch, observed, shapes_drawer, shell_shapes
from .schema import STABILITY_COLUMNS, Scene, instability_text, record_fields, record_instability
from .labels import force_axes, length_symbol, scene_title
from .shape import rise

__all__ = ["run_revolution"]

_OBS = ("F", "w", "w_over_h", "w_over_L", "F_norm", "w_pole")
_TABLE_COLUMNS = {"folds_in": "parameter", "F": "F", "w": "w", "w/h": "w_over_h", "F L/(2 pi D)": "F_norm"}


def _first(records: list[dict[str, Any]], test) -> dict[str, Any] | None:
    hits = sorted((r for r in records if test(r)), key=lambda r: r["index"])
    return hits[0] if hits else None


def run_revolution(scene: Scene, progress: bool = False) -> TraceResult:
    """Trace a point- or ring-loaded scene's path from the unloaded shell (see the module docstring).

    Parameters
    ----------
    scene : dict
        A resolved scene with ``load.kind`` ``"point"`` or ``"ring"``.
    progress : bool
        Print the continuation's progress to stderr.

    Returns
    -------
    TraceResult
        One branch (``"path"``), its special points, the summary above and the diagram ``F``
        against ``w`` styled by the stability under the scene's control.
    """
    s, load = scene["shell"], scene["load"]
    control = load["control"]
    problem = revolution_problem(scene)
    st = revolution_settings(scene, problem, progress)
    if control == "displacement":
        events = [contin.extremum("F", which, folds="F", stability_label="force") for which in ("max", "min")]
    else:
        events = [contin.extremum("w", which, folds="w", stability_label="displacement") for which in ("max", "min")]
    br: Branch = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, events=events)
    records = special_point_records([br], parameter_name=problem.parameter_name, fields=record_fields(_OBS))

    def is_F_fold(r: dict[str, Any]) -> bool:
        return r["kind"] == "fold" and r.get("parameter") == "F"

    def is_w_fold(r: dict[str, Any]) -> bool:
        return r["kind"] == "fold" and r.get("parameter") == "w"

    # the first limit load from the unloaded shell is a maximum of F (under displacement control the
    # extremum event says which; under force control it is the path's first fold in F)
    F_max = _first(records, lambda r: is_F_fold(r) and (control == "force" or str(r.get("label", "")).startswith("max")))
    F_min = _first(records, lambda r: is_F_fold(r) and F_max is not None and r["index"] > F_max["index"])
    w_fold = _first(records, is_w_fold)
    H = rise(s)
    summary: dict[str, Any] = {
        "geometry": s["geometry"], "boundary": s["boundary"], "load": load["kind"], "control": control,
        "H": H, "eversion_w": 2.0 * H, "w_end": loaded_end(scene, problem), "travel": loaded_travel(scene, problem),
        "length_unit": length_unit(scene), "D": problem.D, "F_unit": 2.0 * math.pi * problem.D / length_unit(scene),
        "imperfection": dict(scene["imperfection"]),
        "n_folds_in_w": sum(1 for r in records if is_w_fold(r)),
        "n_limit_points_in_F": sum(1 for r in records if is_F_fold(r)),
        "F_max": None if F_max is None else F_max["F"], "w_at_F_max": None if F_max is None else F_max["w"],
        "F_min": None if F_min is None else F_min["F"], "w_at_F_min": None if F_min is None else F_min["w"],
        "w_fold": None if w_fold is None else w_fold["w"], "F_at_w_fold": None if w_fold is None else w_fold["F"],
    }
    record_instability(summary, records, problem.parameter_name, ("F", "F_norm", "w", "w_over_h", "w_over_L"),
                       problem)
    if load["kind"] == "ring":
        node = problem.node
        summary.update(ring_radius=load["ring_radius"], ring_node_radius=float(problem.x_ref[2 * node]))
    snap = (f"first limit load F = {summary['F_max']:.6g} at w = {summary['w_at_F_max']:.6g}"
            if F_max is not None else "no limit load")
    L = length_symbol(s)  # the shape's length unit, named as the diagram's axes name it
    shown = (("w_over_L", f"w/{L}", f"w/{L}"), ("F_norm", f"F {L}/(2 pi D)", rf"F {L}/2\pi D"))
    instability = instability_text(summary, shown)
    # a bound reached far below the end of travel is the lower one
    came_back = (len(br) > 1 and br.status == "bound"
                 and float(problem.observables["w"](br.u[-1], br.p[-1])) < 0.5 * (LOWEST_W + summary["w_end"]))
    if came_back:
        summary["warnings"] = [f"the path came back to the loaded {'ring' if load['kind'] == 'ring' else 'pole'}'s "
                               "unloaded height, w = 0, without reaching the end of its travel (below it the load "
                               "would pull the shell up without end)"]
    if len(br):
        br.message = (f"{br.message}" + (": back at the unloaded height" if came_back else "") + f"; {snap}"
                      + (f"; {instability}" if instability else ""))
    # w of the loaded node and the total load F, in the shape's length L and the bending unit 2 pi D / L
    options = force_axes("w", length_unit(scene), problem.D, length_symbol=L,
                         scaled={"w_over_L": "w", "F_norm": "F", "w_over_h": "w"})
    options["axis_labels"]["w_over_h"] = "$w/h$"
    plot_options = {**options, "title": scene_title(scene), "special_kinds": ("fold", "bifurcation"), "control": control,
                    "note": instability_text(summary, shown, tex=True)}
    sketch = LoadSketch(load["kind"], node=problem.node if load["kind"] == "ring" else -1)
    shapes = shell_shapes([br], problem.full_state, problem.operator_families, problem.x_ref,
                          path=scene["output"]["shapes"] == "path",
                          fields={"F": observed("F")})
    return TraceResult(branches=[br], jumps=[], summary=summary, special_points=records,
                       table=special_point_table(records, columns=_TABLE_COLUMNS),
                       csv_columns=branch_columns([br], STABILITY_COLUMNS), x="w", y="F",
                       parameter_name=problem.parameter_name, labels=["path"], plot_options=plot_options,
                       shapes=shapes, draw_shapes=shapes_drawer(shapes, length_unit(scene), problem.parameter_name, plot_options,
                                                                 length_symbol=L, load=sketch))
