"""The shell's 3-D view as a scene (``view.kind = "3d"``): the path traced with states that need not be axisymmetric.

The scene's shell, support, imperfection and load are built as in the axisymmetric view
(:func:`contin_models.shell_scene.build.build`: the same structure, the same steps, weights and ends), and
traced by :class:`contin_models.shell.problem3d.Shell3D` in the basis of ``view.symmetry``
(:func:`angular_basis`): pseudo-arclength continuation from the unloaded shell through every fold, under
the parameter of the scene's control (the loaded node's deflection ``w`` or the load; an indenter's travel
``w_b``; the pressure).  On an axisymmetric scene the traced states stay axisymmetric (the 3-D view then
reproduces the axisymmetric path, to rounding) and the view's use is its stability: a ``Dn`` class judges
every point against every perturbation its angular resolution carries, class by class:

* the traced class (the representation ``A1``: ``R`` and ``Z`` cosine, ``T`` sine series of the waves
  ``0, n, 2n, ...``), whose Hessian is the problem's own; a singular point of it off a fold is a branch
  point (located, recorded, passed);
* every other representation of ``Dn`` (:func:`representations`): ``A2`` (the same waves, mirrored
  parity), ``B1``, ``B2`` (n even: the waves ``n/2 + q n``), ``E1``, ``E2``, ... (two-dimensional: the waves
  ``q n +- j``), by the Bloch blocks of :meth:`contin_models.shell.fourier.FourierShell.bloch_block`; where a
  block becomes singular the path has a bifurcation that breaks its symmetry (located, recorded with its
  ``representation``).

``view.symmetry = "none"`` carries every wave ``0 .. K`` in one class (no Bloch blocks).

Outputs: ``branch.csv`` with the axisymmetric view's columns (``w``, the load, their scaled forms, both
controls' stability) and the Morse index per representation (``n_negative_A1``, ``n_negative_A2``, ...,
under the scene's control; a two-dimensional representation counts each eigenvalue twice, once per
copy); ``summary.json`` with the view (``view``: symmetry, waves, angles, unknowns, the representations), the
limit loads and the first instability; ``shapes.npz`` with the deformed surface at every special point and
at the end of the path (:func:`surface_shapes`), drawn in three dimensions in ``shapes.png``
(:func:`draw_surfaces`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import contin
from contin.app.scene import TraceResult, branch_columns, special_point_records, special_point_table
from contin.results.branch import Branch

from .build import LOWEST_W, build, length_unit, loaded_end, traced_structure
from .labels import force_axes, length_symbol, pressure_axes, scene_title
from .schema import STABILITY_COLUMNS, Scene, record_fields, symmetry_order

__all__ = ["angular_basis", "view_problem", "mode_reference", "representations", "run_view3d", "surface_shapes",
           "draw_surfaces", "MAX_SURFACES"]

#: Observables a special point's record carries at its top level.
_OBS = ("F", "p", "w", "w_b", "w_over_h", "w_over_L", "F_norm", "p_over_p_c")
#: Most deformed surfaces drawn (the first instability and the next special points, then the path's end).
MAX_SURFACES = 4
#: A drawn state counts as axisymmetric (grey, no colour scale) when no point stands above or below its
#: ring's mean height by this many thicknesses.
AXISYMMETRIC_TOLERANCE = 1e-6
#: Angles on the whole circle at which ``shapes.npz`` samples a surface.
SURFACE_ANGLES = 97


def angular_basis(scene: Scene) -> Any:
    """The :class:`contin_models.shell.fourier.AngularBasis` of the scene's ``[view]``: ``Dn`` or no symmetry,
    ``view.harmonics`` harmonics, ``view.angles`` angles (0: the basis's default rule)."""
    from contin_models.shell.fourier import AngularBasis

    view = scene["view"]
    n, mirror = symmetry_order(view["symmetry"])
    return AngularBasis(n, int(view["harmonics"]), mirror=mirror, M=int(view["angles"]) or None)


def representations(problem: Any) -> list[dict[str, Any]]:
    """The irreducible representations of ``Dn`` that the perturbations of a ``Dn`` state fall into.

    One dict per representation (:func:`contin_models.shell.fourier.representation_name`): ``name`` (``A1`` the
    traced class, ``A2`` its mirror parity, ``B1``/``B2`` for ``j = n/2``, ``Ej`` for ``0 < j < n/2``),
    ``dimension`` (1 or 2), the Bloch class ``j`` and ``parity``, and ``waves`` (the wave numbers the class
    carries at the view's resolution).  Empty for a view without a mirror (no Bloch blocks).
    """
    basis = problem.basis
    if not basis.mirror or basis.n < 2:
        return []
    out = []
    for name, (j, parity, copies) in problem.view.representations().items():
        waves = basis.bloch(j, parity).wave_numbers if j else basis.wave_numbers
        out.append({"name": name, "dimension": copies, "j": j, "parity": parity,
                    "waves": sorted({int(w) for w in waves})})
    return out


@dataclasses.dataclass
class ViewBuild:
    """What :func:`view_problem` builds: the 3-D problem, its settings and start, the axisymmetric build beside it."""

    problem: Any
    settings: contin.Settings
    u0: np.ndarray
    p0: float
    axisymmetric: Any


def view_problem(scene: Scene, progress: bool = False) -> ViewBuild:
    """The scene in the 3-D view: :class:`Shell3D` on the structure the axisymmetric view traces, with its settings.

    The settings are the axisymmetric build's (:func:`contin_models.shell_scene.build.build`: steps in the
    scene's length unit, the force weighed by the unloaded shell's stiffness), with the path's end stated on
    the loaded node's deflection ``w`` under a point or ring load (the axisymmetric point-load run states it
    in its own runner).
    """
    axi = build(scene, progress)
    structure = traced_structure(scene, axi.problem)
    basis = angular_basis(scene)
    reference = mode_reference(scene, axi, structure, basis) if scene["imperfection"].get("waves", 0) else None
    problem, settings = _shell3d(scene, axi, structure, basis, basis.mirror and basis.n >= 2, reference)
    return ViewBuild(problem=problem, settings=settings, u0=problem.reference_unknowns(), p0=0.0, axisymmetric=axi)


def _shell3d(scene: Scene, axi: Any, structure: Any, basis: Any, every_mode: bool,
             reference: np.ndarray | None = None) -> tuple[Any, contin.Settings]:
    """:class:`Shell3D` of the scene's load on ``structure`` in ``basis``, and the axisymmetric build's settings
    with the end of the path stated for it."""
    from contin_models.contact.indentation import ShellIndentation
    from contin_models.shell.problem3d import Shell3D

    load = scene["load"]
    kind, control = load["kind"], load["control"]
    L = length_unit(scene)
    settings = axi.settings
    if kind in ("sphere", "plate"):
        if not isinstance(axi.problem, ShellIndentation):
            raise TypeError("view_problem: an indenter scene builds a ShellIndentation")
        problem = Shell3D(structure, basis, kind, "displacement", length=L, every_mode=every_mode,
                          barrier=axi.problem.barrier, reference=reference)
        return problem, dataclasses.replace(settings, p_max=axi.w_end)
    if kind == "pressure":
        problem = Shell3D(structure, basis, "pressure", "force", length=L, every_mode=every_mode,
                          p_c=float(axi.problem.p_c), reference=reference)
        return problem, settings
    node = structure.meridian.ring_node if kind == "ring" else None
    problem = Shell3D(structure, basis, kind, control, length=L, node=node, every_mode=every_mode, reference=reference)
    end = loaded_end(scene, axi.problem)
    ends = {"p_max": end, "p_min": LOWEST_W} if control == "displacement" else {}
    return problem, dataclasses.replace(settings, bounds={"w": (LOWEST_W, end)}, **ends)


def mode_reference(scene: Scene, axi: Any, structure: Any, basis: Any) -> np.ndarray:
    """The stress-free shape of ``imperfection.kind = "mode"`` with ``imperfection.waves = n``: the perfect
    shell's mode of ``n`` waves where its path under the scene's load first bifurcates into it, as an
    imperfection of largest normal displacement ``imperfection.delta_over_h`` times ``h`` (inward for a
    positive amplitude) in ``basis`` (:func:`contin_models.shell.imperfection3d.mode_imperfection`).

    The bifurcation is located as the first branch point of the perfect path in the basis of the waves
    ``0`` and ``n`` (``Dn``, one harmonic), whose quadrature puts it where the harmonic block of ``n`` does.

    Raises
    ------
    contin.app.scene.SceneError
        When the perfect path has no located bifurcation into ``n`` waves up to its end.
    """
    from contin.app.scene import SceneError
    from contin_models.shell.fourier import AngularBasis
    from contin_models.shell.imperfection3d import mode_imperfection

    imp = scene["imperfection"]
    n = int(imp["waves"])
    probe, settings = _shell3d(scene, axi, structure, AngularBasis(n, 1), every_mode=False)
    br = contin.continuation(probe, probe.reference_unknowns(), 0.0, dataclasses.replace(settings, stability=True))
    m, b = probe.view.m, probe.basis
    waves = probe.view.dofs_of_wave(n)
    for bp in br.special_points:
        if bp.kind != "branch_point" or not bp.located or bp.bifurcation is None or bp.bifurcation.null_vector is None:
            continue
        phi = probe.T @ np.asarray(bp.bifurcation.null_vector, dtype=float)
        # a branch point of the axisymmetric waves alone (its mode in wave 0) is not the bifurcation sought
        if np.linalg.norm(phi[waves]) > 0.5 * np.linalg.norm(phi):
            mode = np.stack([phi[b.index("R", "cos", n)::m], phi[b.index("Z", "cos", n)::m],
                             phi[b.index("T", "sin", n)::m]], axis=1)
            return mode_imperfection(structure, basis, n, mode, float(imp["delta_over_h"]) * float(scene["shell"]["h"]))
    raise SceneError(f"imperfection.waves = {n}: the perfect shell's path has no located bifurcation into {n} waves "
                     f"up to its end ({br.message}); choose the waves of one that it has (a run with "
                     "view.kind = \"3d\" lists them)", "constraint")


def _class_columns(br: Branch, label: str) -> dict[str, np.ndarray]:
    """``n_negative_<representation>`` per stored point under the stability ``label``: the other classes' counts
    (each eigenvalue of a two-dimensional class twice) from the family ``"representation"``, the traced class's
    (``A1``) the label's total less theirs."""
    modes = br.meta.get("modes", {}).get("representation")
    if modes is None or label not in br.stability_by:
        return {}
    keys = list(modes["keys"])
    counts = np.asarray(modes["n_negative"], dtype=int).reshape(len(br.p), len(keys))
    copies = np.asarray(modes["multiplicity"], dtype=int)
    out = {"n_negative_A1": br.n_negative_under(label) - counts @ copies}
    for i, key in enumerate(keys):
        out[f"n_negative_{key}"] = copies[i] * counts[:, i]
    return out


def _first_instability(records: list[dict[str, Any]], parameter: str) -> dict[str, Any] | None:
    """The first fold in the control's parameter, branch point or symmetry-breaking bifurcation along the path."""
    for rec in records:
        fold = rec["kind"] == "fold" and rec.get("parameter") == parameter
        if rec.get("located", True) and (fold or rec["kind"] in ("branch_point", "bifurcation")):
            keep = ("kind", "p", "representation", *_OBS)
            return {k: rec[k] for k in keep if k in rec}
    return None


def run_view3d(scene: Scene, progress: bool = False) -> TraceResult:
    """Trace the scene in the 3-D view (see the module docstring).

    Parameters
    ----------
    scene : dict
        A resolved scene with ``view.kind = "3d"``.
    progress : bool
        Print the continuation's progress to stderr.

    Returns
    -------
    TraceResult
        One branch (``"path"``), its special points, the summary, the diagram of the load against the
        deflection styled by the stability under the scene's control, and the 3-D shapes.
    """
    vb = view_problem(scene, progress)
    problem, st = vb.problem, vb.settings
    kind, control = scene["load"]["kind"], scene["load"]["control"]
    load = problem.load_name
    # the limit loads of the load, as the axisymmetric view locates them: extrema declared folds in the load
    if kind == "pressure":
        events = []
        label = "stability"
    elif problem.parameter_name == load:  # the load prescribed: extrema of w are the displacement's folds
        events = [contin.extremum("w", which, folds="w", stability_label="displacement") for which in ("max", "min")]
        label = "force"
    else:
        events = [contin.extremum(load, which, folds=load, stability_label="force") for which in ("max", "min")]
        label = "displacement"
    br: Branch = contin.continuation(problem, vb.u0, vb.p0, st, events=events)
    names = representations(problem)
    records = special_point_records([br], parameter_name=problem.parameter_name, fields=record_fields(_OBS))
    for rec in records:
        if rec["kind"] == "branch_point":  # a singular point of the traced class itself, off a fold
            rec["representation"] = "A1" if names else "the traced class"
    folds = [r for r in records if r["kind"] == "fold" and r.get("parameter") == load]
    maxima = [r for r in folds if control == "force" or kind == "pressure" or str(r.get("label", "")).startswith("max")]
    first_max = maxima[0] if maxima else None
    first_min = next((r for r in folds if first_max is not None and r["index"] > first_max["index"]), None)
    basis = problem.basis
    summary: dict[str, Any] = {
        "view": {"kind": "3d", "symmetry": scene["view"]["symmetry"], "harmonics": basis.K,
                 "waves": [int(w) for w in basis.wave_numbers], "angles": basis.M, "unknowns": problem.n,
                 "representations": names},
        "geometry": scene["shell"]["geometry"], "boundary": scene["shell"]["boundary"], "load": kind,
        "control": control, "length_unit": length_unit(scene),
        f"{load}_max": None if first_max is None else first_max[load],
        f"w_at_{load}_max": None if first_max is None else first_max.get("w"),
        f"{load}_min": None if first_min is None else first_min[load],
        f"w_at_{load}_min": None if first_min is None else first_min.get("w"),
        "n_folds_in_parameter": sum(1 for r in records if r["kind"] == "fold" and r.get("parameter") == problem.parameter_name),
        "n_limit_points": len(folds),
        "n_branch_points": sum(1 for r in records if r["kind"] == "branch_point"),
        "n_symmetry_breaking_bifurcations": sum(1 for r in records if r["kind"] == "bifurcation"),
        "first_instability": _first_instability(records, problem.parameter_name),
    }
    if kind != "pressure":
        summary["D"] = problem.D
    first = summary["first_instability"]
    if first is None:
        said = "first instability: none on the path"
    else:
        what = {"fold": f"the fold in {problem.parameter_name}",
                "branch_point": "a branch point in the traced class",
                "bifurcation": f"a bifurcation that breaks the symmetry into {first.get('representation')}"}[first["kind"]]
        said = f"first instability: {what} at {problem.parameter_name} = {first['p']:.6g}"
    if len(br):
        br.message = f"{br.message}; {said}"
    cols = branch_columns([br], STABILITY_COLUMNS if kind != "pressure" else None)
    cols.update(_class_columns(br, label))
    if kind == "pressure":
        options = pressure_axes(problem.p_c)
        x, y = "w_over_h", "p_over_p_c"
    else:
        L = length_symbol(scene["shell"])
        w = "w_b" if kind in ("sphere", "plate") else "w"
        options = force_axes(w, length_unit(scene), problem.D, length_symbol=L, w_symbol=w,
                             scaled={"w_over_L": w, "F_norm": "F"} if w == "w" else {"F_norm": "F"})
        x, y = w, "F"
    plot_options = {**options, "title": f"3-D view ({scene['view']['symmetry']}, K = {basis.K}): {scene_title(scene)}",
                    "special_kinds": ("fold", "branch_point", "bifurcation"), "control": label}
    shapes = surface_shapes(problem, br)
    return TraceResult(branches=[br], jumps=[], summary=summary, special_points=records,
                       table=special_point_table(records, columns={"folds_in": "parameter", load: load, "w": "w",
                                                                   "w/h": "w_over_h"}), csv_columns=cols, x=x, y=y,
                       parameter_name=problem.parameter_name, labels=["path"], plot_options=plot_options,
                       shapes=shapes, draw_shapes=surfaces_drawer(shapes, length_unit(scene), float(scene["shell"]["h"]),
                                                                  problem.parameter_name, length_symbol(scene["shell"])))


def surface_shapes(problem: Any, branch: Branch, angles: int = SURFACE_ANGLES) -> dict[str, np.ndarray]:
    """``shapes.npz`` of a 3-D run: the deformed surface at every special point and at the path's end.

    Returns
    -------
    dict
        ``theta`` (the sampled angles, the whole circle), ``reference_x``, ``reference_y``, ``reference_z``
        (``(N, angles)``: the unloaded surface), and per drawn state (the special points in the order of
        ``summary.json``'s records, then the path's last point) ``state_kind`` (``"end"`` for the last point),
        ``state_label``, ``state_representation`` (the class a branch point or bifurcation breaks into, else
        empty), ``state_p``, ``state_record`` (-1 for the end), ``state_x``, ``state_y``, ``state_z``
        (``(states, N, angles)``, Cartesian, the axis through the pole) and ``state_coefficients`` (the
        Fourier coefficients of every ring, :meth:`Shell3D.full_state`); ``basis`` (``n``, ``K``, the mirror
        as 0/1, ``M``).  Empty when the branch has no point.
    """
    if not len(branch):
        return {}
    view = problem.view
    theta = np.linspace(0.0, 2.0 * math.pi, angles)
    # an extremum declared a limit point (the load's maximum along a displacement path) is a fold, as in
    # summary.json's records
    rows = [(k, "fold" if spt.kind == "event" and spt.info.get("folds") is not None else spt.kind, spt.label,
             _representation(spt, problem), spt.u, spt.p) for k, spt in enumerate(branch.special_points)]
    rows.append((-1, "end", "end of the path", "", branch.u[-1], branch.p[-1]))
    C = np.array([problem.full_state(u, p) for *_, u, p in rows])
    X = np.array([view.points(c, theta) for c in C])                      # (states, N, angles, 3)
    X0 = view.points(view.reference_state(), theta)
    b = problem.basis
    return {"theta": theta, "reference_x": X0[..., 0], "reference_y": X0[..., 1], "reference_z": X0[..., 2],
            "state_record": np.array([r[0] for r in rows]), "state_kind": np.array([r[1] for r in rows]),
            "state_label": np.array([str(r[2]) for r in rows]), "state_representation": np.array([r[3] for r in rows]),
            "state_p": np.array([float(r[5]) for r in rows]),
            "state_x": X[..., 0], "state_y": X[..., 1], "state_z": X[..., 2], "state_coefficients": C,
            "basis": np.array([b.n, b.K, int(b.mirror), b.M])}


def _representation(spt: Any, problem: Any) -> str:
    """The representation a special point's mode falls into: a bifurcation's family key, ``A1`` for a branch
    point of a ``Dn`` class, else empty."""
    if spt.kind == "bifurcation":
        return str(spt.info.get("key", ""))
    if spt.kind == "branch_point" and problem.basis.mirror and problem.basis.n >= 2:
        return "A1"
    return ""


def _drawn(shapes: dict[str, np.ndarray]) -> list[int]:
    """The states drawn: the first special points (up to :data:`MAX_SURFACES` - 1) and the path's end."""
    kinds = list(shapes["state_kind"])
    special = [i for i, k in enumerate(kinds) if k in ("fold", "branch_point", "bifurcation", "event")]
    return special[:MAX_SURFACES - 1] + [len(kinds) - 1]


def draw_surfaces(fig: Any, shapes: dict[str, np.ndarray], length: float, h: float, parameter: str,
                  length_symbol: str = "R") -> None:
    """Draw the deformed shells of ``shapes`` (:func:`surface_shapes`) in three dimensions on the empty Figure ``fig``.

    One panel per drawn state (:func:`_drawn`), true scale in units of ``length``, shaded, coloured by how far
    each material point stands above or below its ring's mean height in units of the thickness ``h`` (the
    non-axisymmetric part of the deflection: uniform grey on an axisymmetric state), the unloaded rim as a thin line.
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import TwoSlopeNorm

    drawn = _drawn(shapes)
    fig.set_size_inches(2.6 * len(drawn), 2.8)
    # the sampled circle closes on itself: its last angle repeats the first, which the mean must not count twice
    dev = [(shapes["state_z"][i] - shapes["state_z"][i][:, :-1].mean(axis=1, keepdims=True)) / h for i in drawn]
    top = max(float(np.max(np.abs(d))) for d in dev)
    axisymmetric = top < AXISYMMETRIC_TOLERANCE
    norm = TwoSlopeNorm(0.0, -max(top, AXISYMMETRIC_TOLERANCE), max(top, AXISYMMETRIC_TOLERANCE))
    cmap = plt.get_cmap("RdBu_r")
    X0 = np.stack([shapes["reference_x"], shapes["reference_y"], shapes["reference_z"]], axis=-1) / length
    for k, (i, d) in enumerate(zip(drawn, dev)):
        ax = fig.add_subplot(1, len(drawn), k + 1, projection="3d")
        X = np.stack([shapes["state_x"][i], shapes["state_y"][i], shapes["state_z"][i]], axis=-1) / length
        colours = np.broadcast_to(np.array([0.78, 0.78, 0.78, 1.0]), d.shape + (4,)) if axisymmetric else cmap(norm(d))
        ax.plot_surface(X[..., 0], X[..., 1], X[..., 2], facecolors=colours, rstride=1, cstride=1,
                        linewidth=0.0, antialiased=False, shade=True)
        ax.plot(X0[0, :, 0], X0[0, :, 1], X0[0, :, 2], color="0.4", lw=0.6)
        extent = np.ptp(np.concatenate([X.reshape(-1, 3), X0.reshape(-1, 3)]), axis=0)
        ax.set_box_aspect(tuple(np.maximum(extent, 1e-3 * float(extent.max()))))
        ax.view_init(elev=24, azim=-60)
        ax.set_axis_off()
        kind = str(shapes["state_kind"][i]).replace("_", " ")
        if shapes["state_representation"][i]:
            kind += f" ({shapes['state_representation'][i]})"
        ax.set_title(f"{kind}\n${parameter} = {float(shapes['state_p'][i]):.4g}$", fontsize=8)
    # below the panels: the figure's title is the scene's
    if axisymmetric:
        fig.text(0.5, 0.03, f"the deformed shell, true scale in units of ${length_symbol}$; every state drawn is "
                 f"axisymmetric (no point above or below its ring's mean height by {AXISYMMETRIC_TOLERANCE:g} h)",
                 ha="center", fontsize=8)
        return
    mappable = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    bar = fig.colorbar(mappable, ax=fig.axes, shrink=0.6, pad=0.02)
    bar.set_label("height above the ring's mean / h", fontsize=8)
    fig.text(0.5, 0.03, f"the deformed shell, true scale in units of ${length_symbol}$", ha="center", fontsize=8)


def surfaces_drawer(shapes: dict[str, np.ndarray], length: float, h: float, parameter: str,
                    length_symbol: str = "R") -> Callable[[Any], None] | None:
    """:attr:`contin.app.scene.TraceResult.draw_shapes` of a 3-D run: :func:`draw_surfaces` on its arrays."""
    if not shapes:
        return None
    return lambda fig: draw_surfaces(fig, shapes, length, h, parameter, length_symbol)
