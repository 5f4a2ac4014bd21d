"""The pressure-loaded cap's run of the scene (``contin trace --model shell``, ``load.kind = "pressure"``).

The scene traces the connected equilibrium path of a spherical cap under a uniform external
pressure ``p`` (:class:`contin_models.shell.ShellPressure`, on the support ``shell.boundary``) by
pseudo-arclength continuation from the unloaded cap at ``p = 0``, until the pressure reaches
``load.p_end_over_p_c`` times the classical pressure ``p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2))`` or the
pole has moved past eversion, ``w = 2 H (1 + continuation.overshoot)`` with the rise
``H = R (1 - sin phi_hat)``, whichever comes first.

Why the whole path and not the quasistatic loading with its jumps: continuation goes around every
fold in ``p``, so the diagram shows the snap-through pressure (the first fold, where the loaded cap
jumps under a prescribed pressure), the unstable part between and the snap-back pressure on
unloading, each point labelled stable or unstable under pressure control (the engine's stability,
the Morse index of the Hessian at fixed ``p``).  Under a prescribed pressure the cap snaps at the
first fold: its pressure is ``p_snap`` in ``summary.json``.

``summary.json``
----------------
``p_c``, ``lambda`` (:func:`contin_models.shell.pressure.cap_lambda`,
``2 (3 (1 - nu^2))^(1/4) sqrt(H / h)``), ``H``, ``eversion_w``, ``w_end``, ``p_end``, ``boundary``,
``control`` (``"force"``: the pressure is prescribed), ``n_folds_in_p`` and the first fold as
``p_snap``, ``p_snap_over_p_c``, ``w_at_p_snap``, ``w_at_p_snap_over_h`` (None without a fold: a
monotonic cap).  Every special point (``"kind": "fold"`` with ``"parameter": "p"``, and the end of
the path) carries ``p``, ``p_over_p_c``, ``w``, ``w_over_h``, ``V`` and ``stable_before`` /
``stable_after`` under pressure control.  ``branch.csv`` has ``p``, ``w``, ``w_over_h``,
``p_over_p_c``, ``V``, ``stable`` and ``n_negative`` per stored point.
"""

from __future__ import annotations

from typing import Any

import contin
from contin.branch import Branch, SpecialPoint
from contin.scene import TraceResult, branch_columns, special_point_records, special_point_table
from contin_models.shell.pressure import cap_lambda

from .build import end_of_path, pressure_problem, pressure_settings
from .schema import Scene, eversion_displacement

__all__ = ["run_pressure"]

#: Observables of :class:`ShellPressure` every special-point record carries at its top level (``p`` is
#: the record's parameter already).
_OBS = ("p_over_p_c", "w", "w_over_h", "V")
#: Columns of the printed special-point table (header -> record field).
_TABLE_COLUMNS = {"p": "p", "p/p_c": "p_over_p_c", "w": "w", "w/h": "w_over_h"}
#: What the diagram's axes show.
_AXIS_LABELS = {"w_over_h": "pole deflection / thickness", "p_over_p_c": "pressure / classical p_c"}


def _pressure_fields(spt: SpecialPoint) -> dict[str, Any]:
    """The pressure scene's own fields of a special point's record: its observables and ``index``."""
    out: dict[str, Any] = {name: float(spt.observables[name]) for name in _OBS if name in spt.observables}
    out["index"] = int(spt.index)
    return out


def _snap(records: list[dict[str, Any]], p_c: float) -> dict[str, Any]:
    """The first fold in ``p`` along the path: where the cap snaps under a prescribed pressure."""
    folds = [r for r in records if r["kind"] == "fold" and r.get("parameter") == "p"]
    first = folds[0] if folds else None
    return {"n_folds_in_p": len(folds),
            "p_snap": None if first is None else first["p"],
            "p_snap_over_p_c": None if first is None else first["p"] / p_c,
            "w_at_p_snap": None if first is None else first["w"],
            "w_at_p_snap_over_h": None if first is None else first["w_over_h"]}


def run_pressure(scene: Scene, progress: bool = False) -> TraceResult:
    """Trace the pressure-controlled path of the scene's cap from ``p = 0`` (see the module docstring).

    Parameters
    ----------
    scene : dict
        A resolved scene of :data:`contin_models.shell_scene.schema.SHELL_SCHEMA` with
        ``load.kind = "pressure"`` (and ``load.control = "force"``, which the schema enforces).
    progress : bool
        Print the continuation's progress to stderr.

    Returns
    -------
    TraceResult
        One branch (``"path"``), its special points, the summary above and the diagram ``p/p_c``
        against ``w/h`` styled by the stability under pressure control.
    """
    s = scene["shell"]
    problem = pressure_problem(scene)
    st = pressure_settings(scene, problem, progress)
    br: Branch = contin.continuation(problem, problem.reference_unknowns(), 0.0, st)
    labels = ["path"]
    records = special_point_records([br], parameter_name=problem.parameter_name, fields=_pressure_fields)
    summary: dict[str, Any] = {
        "p_c": problem.p_c,
        "lambda": cap_lambda(s["R"], s["h"], s["phi_hat"], s["nu"]),
        "H": eversion_displacement(s["R"], s["phi_hat"]) / 2.0,  # the rise R (1 - sin phi_hat)
        "eversion_w": eversion_displacement(s["R"], s["phi_hat"]),
        "w_end": end_of_path(scene),
        "p_end": st.p_max,
        "boundary": s["boundary"],
        "control": scene["load"]["control"],
    }
    summary.update(_snap(records, problem.p_c))
    snap = summary["p_snap_over_p_c"]
    note = (f"{s['boundary']} edge, lambda = {summary['lambda']:.3g}; stability under pressure control"
            + (f"; snaps at p/p_c = {snap:.4g}" if snap is not None else "; no fold"))
    if len(br):
        br.message = f"{br.message}; " + (f"first fold (snap under pressure) at p/p_c = {snap:.6g}, w/h = "
                                          f"{summary['w_at_p_snap_over_h']:.6g}" if snap is not None else
                                          "no fold in p on the path (no snap)")
    plot_options = {"axis_labels": _AXIS_LABELS, "special_kinds": ("fold",), "note": note}
    # output.figure = false is the command line's to honour (contin.scene.wants_figure)
    return TraceResult(branches=[br], jumps=[], summary=summary, special_points=records,
                       table=special_point_table(records, columns=_TABLE_COLUMNS),
                       csv_columns=branch_columns([br]), x="w_over_h", y="p_over_p_c",
                       parameter_name=problem.parameter_name, labels=labels, plot_options=plot_options)
