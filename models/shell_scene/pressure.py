"""The pressure-loaded shell's runs of the scene (``contin trace --model shell``, ``load.kind = "pressure"``).

The scene traces the connected equilibrium path of its shell (any ``shell.geometry``, on the support
``shell.boundary``, with its ``[imperfection]``: :func:`contin_models.shell_scene.build.pressure_problem`,
a :class:`contin_models.shell.structure.ShellOfRevolution`; on the perfect spherical cap the problem
of :class:`contin_models.shell.ShellPressure`) under a uniform external pressure ``p`` by
pseudo-arclength continuation from the unloaded shell, under one of two controls (``load.control``):

``"displacement"`` (the default, as for every load): volume control
    The volume change ``dV = V0 - V`` is prescribed and ``p`` is its Lagrange multiplier
    (:class:`contin.analyses.conjugate.ConjugateControl`, :func:`volume_problem`), as in experiments that pump
    fluid out of (or a piston into) the space the cap closes.  ``V`` is the volume between the cap
    and its base plane, ``V0`` the unloaded cap's; ``dV`` is positive as the pressure pushes the
    cap in (the volume it displaces, the work-conjugate of ``p``: ``p dV`` is the work the pressure
    does), in the scene's length unit cubed.  The path runs from ``dV = 0`` until
    ``dV = load.dV_end_over_V0 V0`` (``2 V0`` is the mirror image of the cap: everted) or until the
    pole has moved past eversion, whichever comes first.
``"force"``: pressure control
    ``p`` is the parameter; the path runs from ``p = 0`` until the pressure reaches
    ``load.p_end_over_p_c`` times the classical pressure ``p_c = 2 E (h/L)^2 / sqrt(3 (1 - nu^2))``
    (``L`` the geometry's length scale: ``R`` for the sphere) or the pole has moved past eversion,
    ``w = 2 H (1 + continuation.overshoot)`` with the rise ``H`` (``R (1 - sin phi_hat)`` for the
    sphere; a plate's path ends at ``10 h (1 + continuation.overshoot)``), whichever comes first.

Why the whole path and not the quasistatic loading with its jumps: continuation goes around every
fold, so the diagram shows the snap-through pressure (the first limit point in ``p``, where the
cap jumps under a prescribed pressure), the unstable part between and the snap-back pressure on
unloading.  Under pressure control each point is labelled stable or unstable under pressure control
(the Morse index of the Hessian at fixed ``p``).  Under volume control it is labelled under both:
``"volume"`` (the primary label: the Hessian on the tangent space of the volume constraint) and
``"pressure"``.  A prescribed volume carries the cap stably past the pressure maximum; it snaps only
at a fold in ``dV`` (where the path turns back in the volume), which shallow clamped caps
(``lambda`` up to about 5) do not have and deeper ones have a little past the pressure maximum
(``docs/validation.md`` section 7).

Where the whole path does not end: past its first fold a deep thin cap's connected path turns back through
unstable axisymmetric states between the cap and its mirror image, and the number of them grows steeply with
``lambda`` (under volume control hundreds of folds in ``dV`` at ``lambda`` 30; on deeper caps, under either
control, a path that may not end at all).  Under the automatic step limit
(``continuation.max_steps = "auto"``) a connected path that runs out of steps (under volume control after
:data:`VOLUME_PATH_STEPS`) or stalls is cut at its first fold in the control: the cap snaps there at the prescribed
volume or pressure (a descent in the energy: on the volume constraint,
:func:`contin_models.shell.constrained_snap.jump_on_constraint`, or at the pressure, :func:`contin.jump`) and the
trace goes on from the landing as the load grows, the path the cap takes as fluid is pumped out or the pressure
raised.  The status line says so, and ``summary.json``'s ``connected_path`` records how the connected path ended,
its steps, its folds and the range of the control it went through before it was cut.  A number for
``continuation.max_steps`` traces the connected path only, as far as it goes.

``summary.json``
----------------
``p_c``, ``lambda`` (``2 (3 (1 - nu^2))^(1/4) sqrt(H / h)`` with the rise ``H``; for the sphere
:func:`contin_models.shell.pressure.cap_lambda`), ``H``, ``eversion_w``, ``geometry``, ``length_unit``,
``imperfection``, ``w_end``, ``boundary``, ``control``
(``"force"``: the pressure is prescribed; ``"displacement"``: the volume), ``n_folds_in_p`` and the
first limit point in ``p`` as ``p_snap``, ``p_snap_over_p_c``, ``w_at_p_snap``, ``w_at_p_snap_over_h``
(None without one: a monotonic cap): the snap under pressure control, under either control.  Under
pressure control also ``p_end``; under volume control ``V0``, ``dV_end``, ``n_folds_in_dV`` and the
first fold in ``dV`` (the snap under volume control) as ``dV_snap``, ``dV_snap_over_V0``,
``p_at_dV_snap``, ``p_at_dV_snap_over_p_c``, ``w_at_dV_snap_over_h`` (None without one).  Where the connected
path was cut (above), ``connected_path``: how it ended (``status``), its ``steps``, its ``folds`` in the control,
the ``range`` of the control it went through (in the unit ``range_of``), whether the loading path replaced it
(``replaced``: "yes: ..." or "no: " and why) and the load of the snap (``snap_at``, in the same unit).

Every special point carries ``p`` (under volume control: the multiplier, not the parameter),
``p_over_p_c``, ``w``, ``w_over_h``, ``V`` and ``stable_before`` / ``stable_after`` under the control
in which it is a fold (``"parameter"``: ``"p"`` for a limit point in the pressure, ``"dV"`` for a
fold in the volume; ``stability_control`` names the label).  Under volume control a limit point in
``p`` is an extremum of ``p`` along the path (``label`` ``max(p)`` or ``min(p)``), and every record
also has ``dV`` and ``dV_over_V0``.  ``branch.csv`` has ``p``, ``w``, ``w_over_h``, ``p_over_p_c``,
``V``, ``stable`` and ``n_negative`` (under the scene's control) per stored point; under volume
control also ``dV``, ``dV_over_V0``, ``stable_pressure`` and ``n_negative_pressure``.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

import contin
from contin.analyses.conjugate import ConjugateControl
from contin.app.scene import TraceResult, branch_columns, special_point_records, special_point_table
from contin.numerics.linalg import Factorization
from contin.analyses.jump import JumpError, JumpResult, jump
from contin.results.branch import Branch, SpecialPoint
from contin_models.contact.indentation import BorderedBandedLU
from contin_models.shell.energy import HALF_BANDWIDTH
from contin_models.shell.constrained_snap import jump_on_constraint
from contin_models.shell.lift import controlled_families
from contin_models.shell.structure import ShellOfRevolution

from .build import (MIN_STEPS_PER_PATH, end_of_path, length_unit, pressure_problem, pressure_settings, step_limits,
                    travel)
from .deformed import shapes_drawer, shell_shapes
from .labels import length_symbol, pressure_axes, scene_title
from .schema import Scene, instability_text, record_fields, record_instability

#: The load fields of ``summary.json``'s ``first_instability`` for a pressure.
_INSTABILITY_FIELDS = ("p", "p_over_p_c", "w", "w_over_h")
from .shape import rise

__all__ = ["run_pressure", "volume_problem", "volume_settings", "VOLUME_LABELS", "VOLUME_PATH_STEPS",
           "PRESSURE_SNAP_ITERATIONS"]

#: Stability labels under volume control: the prescribed volume (primary), then pressure control.
VOLUME_LABELS = ("volume", "pressure")
#: Steps the connected path under a prescribed volume takes under the automatic step limit before the loading path
#: (:func:`_reported_path`) replaces what lies past its first fold in the volume.  Past that fold a deep thin cap's
#: connected path turns back through the unstable axisymmetric states between the cap and its mirror image, and
#: their number grows steeply with the cap's depth: hundreds of folds in the volume, or a path that does not end.
#: (Under a prescribed pressure the connected path keeps the whole automatic limit: its longest paths that end are
#: longer, and one that does not end stalls.)
VOLUME_PATH_STEPS = 50_000

#: Observables of :class:`ShellPressure` every special-point record carries at its top level (``p`` is
#: the record's parameter already).
_OBS = ("p_over_p_c", "w", "w_over_h", "V")
#: Columns of the printed special-point table (header -> record field).
_TABLE_COLUMNS = {"p": "p", "p/p_c": "p_over_p_c", "w": "w", "w/h": "w_over_h"}


def _lift_jump_records(records: list[dict[str, Any]], names: tuple[str, ...]) -> None:
    """Give a snap's two records (``jump_from``, ``jump_to``) the observables ``names`` at their top level, as
    :func:`~contin_models.shell_scene.schema.record_fields` gives every special point's."""
    for rec in records:
        if rec["kind"] == "jump" and "jump" in rec:
            rec.update({name: rec["observables"][name] for name in names if name in rec["observables"]})


def _snap(records: list[dict[str, Any]], p_c: float) -> dict[str, Any]:
    """The first limit point in ``p`` along the path: where the cap snaps under a prescribed pressure.

    Under volume control it is the first maximum of the multiplier ``p``, an extremum event declared
    as a fold in ``p`` (the same record fields).
    """
    folds = [r for r in records if r["kind"] == "fold" and r.get("parameter") == "p"]
    first = folds[0] if folds else None
    return {"n_folds_in_p": len(folds),
            "p_snap": None if first is None else first["p"],
            "p_snap_over_p_c": None if first is None else first["p"] / p_c,
            "w_at_p_snap": None if first is None else first["w"],
            "w_at_p_snap_over_h": None if first is None else first["w_over_h"]}


def _shape_fields(scene: Scene) -> dict[str, Any]:
    """The summary's shape fields: ``lambda`` (from the rise), ``H``, ``eversion_w``, ``geometry``, ``length_unit``."""
    s = scene["shell"]
    H = rise(s)
    return {"lambda": 2.0 * (3.0 * (1.0 - s["nu"] ** 2)) ** 0.25 * math.sqrt(H / s["h"]), "H": H,
            "eversion_w": 2.0 * H, "geometry": s["geometry"], "length_unit": length_unit(scene),
            "imperfection": dict(scene["imperfection"])}


def run_pressure(scene: Scene, progress: bool = False) -> TraceResult:
    """Trace the path of the scene's cap under its ``load.control`` (see the module docstring).

    Parameters
    ----------
    scene : dict
        A resolved scene of :data:`contin_models.shell_scene.schema.SHELL_SCHEMA` with
        ``load.kind = "pressure"``.
    progress : bool
        Print the continuation's progress to stderr.

    Returns
    -------
    TraceResult
        One branch (``"path"``), its special points, the summary above and the diagram: ``p/p_c``
        against ``w/h`` styled by the stability under pressure control (``load.control = "force"``),
        or ``p/p_c`` against ``dV`` styled by the stability under volume control.
    """
    if scene["load"]["control"] == "force":
        return _run_pressure_control(scene, progress)
    return _run_volume_control(scene, progress)


#: How the status line and the diagram name the first instability (:func:`instability_text`), in their units.
_SHOWN_PRESSURE = (("p_over_p_c", "p/p_c", "p/p_c"), ("w_over_h", "w/h", "w/h"))
_SHOWN_VOLUME = (("dV_over_V0", "dV/V0", r"\Delta V/V_0"), ("p_over_p_c", "p/p_c", "p/p_c"))


def _plain_instability(summary: dict[str, Any], shown: tuple[tuple[str, str, str], ...]) -> str:
    text = instability_text(summary, shown)
    return f"; {text}" if text else ""


def _tex_instability(summary: dict[str, Any], shown: tuple[tuple[str, str, str], ...]) -> str:
    text = instability_text(summary, shown, tex=True)
    return f"; {text}" if text else ""


def _run_pressure_control(scene: Scene, progress: bool) -> TraceResult:
    """The path under a prescribed pressure, from ``p = 0``."""
    s = scene["shell"]
    problem = pressure_problem(scene)
    st = pressure_settings(scene, problem, progress)
    br: Branch = contin.continuation(problem, problem.reference_unknowns(), 0.0, st)
    path = _reported_path(problem, br, st, [], lambda u, p: jump(problem, u, p, max_iter=PRESSURE_SNAP_ITERATIONS),
                          (problem.p_c, "p/p_c"), "pressure", scene["continuation"]["max_steps"] == "auto")
    branches = path.branches
    records = special_point_records(branches, path.jumps, path.jump_observables, parameter_name=problem.parameter_name,
                                    fields=record_fields(_OBS))
    _lift_jump_records(records, _OBS)
    summary: dict[str, Any] = {
        "p_c": problem.p_c,
        **_shape_fields(scene),
        "w_end": end_of_path(scene),
        "p_end": st.p_max,
        "boundary": s["boundary"],
        "control": scene["load"]["control"],
    }
    summary.update(_snap(records, problem.p_c))
    record_instability(summary, records, "p", _INSTABILITY_FIELDS, problem)
    snap = summary["p_snap_over_p_c"]
    note = (rf"$\lambda = {summary['lambda']:.3g}$"
            + (f"; snaps at $p/p_c = {snap:.4g}$" if snap is not None else "; no fold")
            + _tex_instability(summary, _SHOWN_PRESSURE))
    if len(br):
        first = branches[0]
        first.message = f"{first.message}; " + (f"first fold (snap under pressure) at p/p_c = {snap:.6g}, w/h = "
                                                f"{summary['w_at_p_snap_over_h']:.6g}" if snap is not None else
                                                "no fold in p on the path (no snap)")
        first.message += _plain_instability(summary, _SHOWN_PRESSURE) + path.note
    if path.connected is not None:
        summary["connected_path"] = path.connected
    plot_options = {**pressure_axes(problem.p_c), "special_kinds": ("fold", "bifurcation"), "note": note,
                    "title": scene_title(scene), "control": "pressure"}
    # output.figure = false is the command line's to honour (contin.app.scene.wants_figure)
    shapes = shell_shapes(branches, problem.full_state, problem.operator_families, problem.x_ref,
                          path=scene["output"]["shapes"] == "path")
    return TraceResult(branches=branches, jumps=path.jumps, summary=summary, special_points=records,
                       table=special_point_table(records, columns=_TABLE_COLUMNS),
                       csv_columns=branch_columns(branches), x="w_over_h", y="p_over_p_c",
                       parameter_name=problem.parameter_name, labels=path.labels,
                       jump_observables=path.jump_observables,
                       plot_options=plot_options,
                       shapes=shapes, draw_shapes=shapes_drawer(shapes, length_unit(scene), problem.parameter_name, plot_options,
                                                                length_symbol=length_symbol(s)))


# ---------------------------------------------------------------------------------------------------
# volume control
# ---------------------------------------------------------------------------------------------------
def volume_problem(pressure: ShellOfRevolution, depth: float | None = None) -> ConjugateControl:
    """The cap ``pressure`` with its volume change ``dV = V0 - V`` prescribed and ``p`` its multiplier.

    :class:`contin.analyses.conjugate.ConjugateControl` of the pressure-controlled cap: the pressure enters
    the energy linearly (``p (V - V0)``), so ``dV = -dE/dp`` and the Jacobian is the cap's Hessian
    bordered by ``dV/dx`` (dense: every node moves the volume).  The bordered matrix is factorized
    by block elimination on the banded LU of the Hessian (:class:`BorderedBandedLU`, as the force-
    controlled indenter does), so a solve stays O(N).  The multiplier is stored in units of
    ``p_c / (2 H)`` (the classical pressure per eversion depth), so that it weighs in the arclength
    like a length of the shell.

    Observables: the cap's (``p`` is the multiplier), ``dV`` (the parameter) and ``dV_over_V0``,
    ``V0`` the unloaded cap's volume over its base plane.  Stability labels: :data:`VOLUME_LABELS`.
    ``depth`` is the deflection the path is sized by (the scene's
    :func:`contin_models.shell_scene.build.travel`); default the eversion depth ``2 H`` of the
    reference shape, ``H`` the pole's height above the edge.
    """
    V0 = float(pressure.pressure.V0)
    if not V0 > 0.0:
        raise ValueError(f"volume_problem: the reference shell encloses no volume (V0 = {V0:g}, a flat plate?): "
                         "volume control measures dV against V0; trace it under its pressure instead")
    if depth is None:
        depth = 2.0 * float(pressure.x_ref[-1] - pressure.x_ref[1])
        if not depth > 0.0:
            raise ValueError("volume_problem: a flat shell has no eversion depth; give depth")
    volume = ConjugateControl(pressure, displacement="dV", scaled={"dV_over_V0": ("dV", 1.0 / V0)},
                              labels=VOLUME_LABELS, linear=True, multiplier_unit=pressure.p_c / depth,
                              factorize=_bordered_band)
    # the n >= 1 blocks are shared by both controls: the same family, on the multiplier's pressure
    volume.operator_families = controlled_families(volume, getattr(pressure, "operator_families", ()))
    return volume


def _bordered_band(J: Any) -> Factorization:
    """Block elimination of the multiplier on the cap's banded LU (O(N) solves)."""
    return BorderedBandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH)


def volume_settings(scene: Scene, problem: ConjugateControl, progress: bool = False) -> contin.Settings:
    """Continuation settings of a volume-controlled trace: steps in units of R, stability under both controls.

    The path ends at ``dV = load.dV_end_over_V0 V0`` or at the pole deflection of
    :func:`contin_models.shell_scene.build.end_of_path` (eversion plus the overshoot), whichever comes
    first.
    """
    c = scene["continuation"]
    L, depth = length_unit(scene), travel(scene)
    ds_max = min(c["ds_max"], depth / MIN_STEPS_PER_PATH / L)
    ds = min(c["ds"], ds_max)
    # positions and w are lengths in units of L (the multiplier too, see volume_problem); the volume
    # change to eversion, 2 V0, weighs as much as the pole moving through the eversion depth
    V0 = float(problem.base.pressure.V0)
    return contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, tol=c["tol"], **step_limits(scene),
                           stability=True, n_eigs=0, state_weight=1.0 / L,
                           param_weight=depth / (L * 2.0 * V0), progress=progress,
                           p_max=scene["load"]["dV_end_over_V0"] * V0, bounds={"w": (None, end_of_path(scene))})


#: Observables every special-point record carries at its top level under volume control (``p`` too:
#: it overrides the record's parameter value, which is ``dV`` there).
_VOLUME_OBS = ("p", "p_over_p_c", "w", "w_over_h", "V", "dV", "dV_over_V0")
#: Columns of the printed special-point table under volume control.
_VOLUME_TABLE_COLUMNS = {"folds_in": "parameter", "dV/V0": "dV_over_V0", "p": "p", "p/p_c": "p_over_p_c", "w": "w",
                         "w/h": "w_over_h"}
#: ``branch.csv``'s stability columns under volume control (name -> :meth:`contin.Branch.columns` name).
_VOLUME_STABILITY_COLUMNS = {"stable": "stable_volume", "n_negative": "n_negative_volume",
                             "stable_pressure": "stable_pressure", "n_negative_pressure": "n_negative_pressure"}


def _volume_snap(records: list[dict[str, Any]], V0: float, p_c: float) -> dict[str, Any]:
    """The first fold in ``dV`` along the path: where the cap snaps under a prescribed volume."""
    folds = [r for r in records if r["kind"] == "fold" and r.get("parameter") == "dV"]
    first = folds[0] if folds else None
    return {"n_folds_in_dV": len(folds),
            "dV_snap": None if first is None else first["dV"],
            "dV_snap_over_V0": None if first is None else first["dV"] / V0,
            "p_at_dV_snap": None if first is None else first["p"],
            "p_at_dV_snap_over_p_c": None if first is None else first["p"] / p_c,
            "w_at_dV_snap_over_h": None if first is None else first["w_over_h"]}


def _run_volume_control(scene: Scene, progress: bool) -> TraceResult:
    """The path under a prescribed volume change, from ``dV = 0``."""
    s = scene["shell"]
    pressure = pressure_problem(scene)
    problem = volume_problem(pressure, travel(scene))
    st = volume_settings(scene, problem, progress)
    U0, q0 = problem.from_load_state(pressure.reference_unknowns(), 0.0)
    # a limit point of the pressure is an extremum of the multiplier along the path: located as an
    # event and recorded as a fold in p, stable before and after under pressure control
    events = [contin.extremum("p", which, folds="p", stability_label=VOLUME_LABELS[1]) for which in ("max", "min")]
    auto = scene["continuation"]["max_steps"] == "auto"
    connected = dataclasses.replace(st, max_steps=min(st.max_steps, VOLUME_PATH_STEPS)) if auto else st
    br: Branch = contin.continuation(problem, U0, q0, connected, events=events)
    V0 = float(pressure.pressure.V0)
    path = _reported_path(problem, br, st, events, lambda U, q: jump_on_constraint(problem, U, q), (V0, "dV/V0"),
                          "volume", auto)
    branches, jumps, jump_obs = path.branches, path.jumps, path.jump_observables
    records = special_point_records(branches, jumps, jump_obs, parameter_name=problem.parameter_name,
                                    fields=record_fields(_VOLUME_OBS))
    _lift_jump_records(records, _VOLUME_OBS)  # p: the pressure, as on every other record
    summary: dict[str, Any] = {
        "p_c": pressure.p_c,
        **_shape_fields(scene),
        "w_end": end_of_path(scene),
        "V0": V0,
        "dV_end": st.p_max,
        "boundary": s["boundary"],
        "control": scene["load"]["control"],
    }
    summary.update(_snap(records, pressure.p_c))
    summary.update(_volume_snap(records, V0, pressure.p_c))
    record_instability(summary, records, "dV", _INSTABILITY_FIELDS + ("dV", "dV_over_V0"), problem)
    p_snap, dV_snap = summary["p_snap_over_p_c"], summary["dV_snap_over_V0"]
    seen = (f"pressure maximum p/p_c = {p_snap:.6g} at w/h = {summary['w_at_p_snap_over_h']:.6g} (the snap under "
            "pressure control)" if p_snap is not None else "no limit point in p")
    seen += (f"; first fold in the volume (snap under volume control) at dV/V0 = {dV_snap:.6g}, p/p_c = "
             f"{summary['p_at_dV_snap_over_p_c']:.6g}" if dV_snap is not None else "; no fold in the volume (no snap)")
    seen += path.note
    if path.connected is not None:
        summary["connected_path"] = path.connected
    if len(br):
        first = branches[0]
        first.message = f"{first.message}; {seen}{_plain_instability(summary, _SHOWN_VOLUME)}"
    note = (rf"$\lambda = {summary['lambda']:.3g}$"
            + (f"; $p_{{max}}/p_c = {p_snap:.4g}$" if p_snap is not None else "")
            + (rf"; snaps at $\Delta V/V_0 = {dV_snap:.4g}$" if dV_snap is not None else r"; no fold in $\Delta V$")
            + _tex_instability(summary, _SHOWN_VOLUME))
    csv = branch_columns(branches, _VOLUME_STABILITY_COLUMNS)
    # the branch's parameter is dV (an observable column too); the pressure scene's "p" is the pressure
    csv["p"] = np.concatenate([b.observables["p"] for b in branches])
    # the volume pushed in as a fraction of the cap's enclosed volume V0
    options = pressure_axes(pressure.p_c)
    options["axis_labels"].update(dV=r"$\Delta V / V_0$", dV_over_V0=r"$\Delta V / V_0$")
    options["scale"]["dV"] = 1.0 / V0
    options["same_as"]["dV_over_V0"] = "dV"
    plot_options = {**options, "symbols": {"dV": r"$\Delta V$"}, "special_kinds": ("fold", "bifurcation"), "note": note,
                    "title": scene_title(scene), "control": "volume"}

    def plot(ax: Any) -> Any:
        return contin.plot_branches(branches, x="p", y="p_over_p_c", ax=ax,
                                    jumps=[(j, a, b) for j, (a, b) in zip(jumps, jump_obs)], **plot_options)

    shapes = shell_shapes(branches, lambda U, q: pressure.full_state(*problem.split(U)), problem.operator_families,
                          pressure.x_ref, path=scene["output"]["shapes"] == "path")
    return TraceResult(branches=branches, jumps=jumps, summary=summary, special_points=records,
                       table=special_point_table(records, columns=_VOLUME_TABLE_COLUMNS),
                       csv_columns=csv, x="dV", y="p_over_p_c", parameter_name=problem.parameter_name,
                       labels=path.labels, jump_observables=jump_obs, plot=plot, plot_options=plot_options,
                       shapes=shapes, draw_shapes=shapes_drawer(shapes, length_unit(scene), problem.parameter_name, plot_options,
                                                                length_symbol=length_symbol(s)))


@dataclasses.dataclass
class _ReportedPath:
    """What a pressure run reports (:func:`_reported_path`): its branches with their labels (the connected path,
    or the connected path up to its first fold and the path from the snap's landing), the snap and the observables
    at its ends, and ``summary.json``'s ``connected_path`` (None where the connected path is reported whole)."""

    branches: list[Branch]
    labels: list[str]
    jumps: list[JumpResult]
    jump_observables: list[tuple[dict[str, float], dict[str, float]]]
    connected: dict[str, Any] | None

    @property
    def note(self) -> str:
        """The status line's words where the connected path did not end and the snap did not replace it."""
        if self.connected is None or self.connected["replaced"].startswith("yes"):
            return ""
        return f"; the connected path was not replaced by the loading path: {self.connected['replaced'][4:]}"


#: Iterations of the descent of a snap under a prescribed pressure (:func:`contin.jump`): from the pressure maximum a
#: deep thin cap descends all the way to its everted state.
PRESSURE_SNAP_ITERATIONS = 5000

#: Where a connected path that did not end is replaced by the loading path (:func:`_reported_path`): under the automatic step limit, when it
#: ran out of steps (:data:`VOLUME_PATH_STEPS` under a prescribed volume) or stalled.
_NOT_ENDED = ("max_steps", "stalled")


def _reported_path(problem: Any, br: Branch, st: contin.Settings, events: list[Any], snap: Any,
                   unit: tuple[float, str], held: str, automatic: bool) -> _ReportedPath:
    """The connected path ``br``, or, where it did not end under the automatic step limit (``automatic``), the path a
    cap takes as its load grows: the connected path to its first fold in the control, the snap there at the
    prescribed load (``snap(U, q)``: a descent in the energy, on the volume constraint under a prescribed volume) and
    the path on from the landing as the load grows, under the step limits of ``st``.  ``unit`` is the control's
    unit and how the messages name the ratio (``(V0, "dV/V0")``), ``held`` what the snap holds (``"volume"``)."""
    from contin_models.shell.followed import SNAP_OVERSHOOT

    if not (automatic and br.status in _NOT_ENDED):
        return _ReportedPath([br], ["path"], [], [], None)
    scale, ratio = unit
    folds = [spt for spt in br.special_points if spt.kind == "fold"]
    steps = len(br) - 1
    record: dict[str, Any] = {"status": br.status, "steps": steps, "folds": len(folds),
                              "range": [float(np.min(br.p)) / scale, float(np.max(br.p)) / scale], "range_of": ratio}
    if not folds:
        record["replaced"] = f"no: no fold in the {held} in its {steps} steps to snap from"
        return _ReportedPath([br], ["path"], [], [], record)
    fold: SpecialPoint = folds[0]
    where = f"the first fold in the {held} ({ratio} = {fold.p / scale:.6g})"
    q = float(fold.p) * (1.0 + SNAP_OVERSHOOT)
    try:
        jr = snap(np.asarray(fold.u), q)
    except (JumpError, ArithmeticError, ValueError) as exc:
        record["replaced"] = f"no: the snap from {where} failed: {exc}"
        return _ReportedPath([br], ["path"], [], [], record)
    if not jr.success:
        record["replaced"] = f"no: the snap from {where} did not land on a stable state: {jr.message}"
        return _ReportedPath([br], ["path"], [], [], record)
    # the stored point after the fold closes the head's line at the turn
    head = br.head(min(fold.index + 2, len(br)), [spt for spt in br.special_points if spt.index <= fold.index])
    head.status = "event"
    ended = "ran out of its steps" if br.status == "max_steps" else "stalled"
    more = len(folds) - 1
    head.message = (f"stopped at {where}: the connected path on from it wound through {more} more fold"
                    f"{'' if more == 1 else 's'} in the {held} and {ended} after {steps} steps ({ratio} between "
                    f"{record['range'][0]:.3g} and {record['range'][1]:.3g}) without reaching the end, so the cap "
                    f"snaps there at the prescribed {held}")
    landing = contin.continuation(problem, jr.u_to, q, dataclasses.replace(st, direction=1), events=events, origin=jr)
    record["replaced"] = f"yes: by the snap at its first fold in the {held} and the path from the landing"
    record["snap_at"] = q / scale
    ends = (problem.evaluate_observables(jr.u_from, jr.p), problem.evaluate_observables(jr.u_to, jr.p))
    return _ReportedPath([head, landing], ["path", "after the snap"], [jr], [ends], record)
