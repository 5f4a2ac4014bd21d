"""Public ways in: a resolved shell scene -> the problem, its continuation settings and its start.

The command line (:data:`contin_models.shell_scene.SHELL_SCENE`), the studies, the tests and users build
the shell's problems here, so that a scene means the same thing everywhere::

    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA, build

    scene = load_scene(SHELL_SCHEMA, None, ["shell.phi_hat=1.2"])
    b = build(scene)
    branch = contin.continuation(b.problem, b.u0, b.p0, b.settings, p_max=b.w_end)

:func:`point_problem` / :func:`point_settings` and :func:`contact_problem` / :func:`contact_settings`
are the pieces :func:`build` is made of, for callers that want one of them alone.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

import contin
from contin.problem import Problem
from contin_models.contact import Plate, Sphere
from contin_models.contact.indentation import ShellIndentation, ShellIndentationForce
from contin.analyses.quasistatic import SnapRules
from contin.app.scene import SceneError
from contin_models.shell import ShellPointLoad
from contin_models.shell.meridian import ReferenceMeridian, with_mode
from contin_models.shell.pressure import classical_pressure
from contin_models.shell.structure import ShellOfRevolution, ShellStructure, default_harmonics

from .schema import AUTO_MAX_STEPS, STALL_STEPS, Scene, eversion_displacement
from .shape import length_scale, reference_meridian, rise

__all__ = ["Build", "build", "contact_problem", "contact_settings", "end_of_path", "point_problem",
           "point_settings", "pressure_problem", "pressure_settings", "force_snap_rules", "pole_moved", "MIN_STEPS_PER_PATH",
           "FORCE_JUMP_ATTEMPTS", "is_papers_cap", "length_unit", "travel", "scene_meridian", "scene_structure",
           "revolution_problem", "revolution_settings", "rest_stiffness", "buckling_mode", "FLAT_TRAVEL_OVER_H", "harmonics_of",
           "loaded_travel", "loaded_end", "LOWEST_W", "RING_EVERSION_FRACTION",
           "watch_harmonics", "step_limits", "traced_structure"]

#: Minimum number of steps over the eversion depth: ``ds`` and ``ds_max`` are capped at this
#: fraction of ``2 R (1 - sin phi_hat)``, so shallow caps (short paths) are still resolved.
MIN_STEPS_PER_PATH = 20


def step_limits(scene: Scene) -> dict[str, int]:
    """The :class:`contin.Settings` fields ``max_steps`` and ``stall_steps`` of the scene's ``continuation.max_steps``.

    ``"auto"``: a branch goes on while it progresses (:data:`STALL_STEPS`), up to :data:`AUTO_MAX_STEPS`
    steps; a number: exactly that many steps at most, whether or not the branch progresses.
    """
    chosen = scene["continuation"]["max_steps"]
    if chosen == "auto":
        return {"max_steps": AUTO_MAX_STEPS, "stall_steps": STALL_STEPS}
    return {"max_steps": int(chosen), "stall_steps": 0}


#: ``(overshoot, kick)`` attempts of a force-controlled snap: the load is raised by ``overshoot F``
#: past the limit load and the state kicked by ``kick R`` along the null vector (None: the engine's
#: default kick); a load a hair above the limit load has no equilibrium nearby, so the minimisation
#: has to leave for the distant stable state.
FORCE_JUMP_ATTEMPTS = ((1e-6, 1e-4), (1e-4, None), (1e-4, 1e-4))


def pole_moved(problem: Problem, pole: str, R: float) -> Callable[[np.ndarray, float, np.ndarray, float], float]:
    """How far a snap moved the pole, in units of ``R``: the landing distance of :class:`SnapRules`.

    ``pole`` names the observable of the pole's displacement.  A length of the shell, so that a scene
    snaps alike in any units (the state vector's own numbers are metres or millimetres).
    """
    def moved(u_fold: np.ndarray, p_fold: float, u_to: np.ndarray, p_to: float) -> float:
        observe = problem.observables[pole]
        return abs(float(observe(u_to, p_to)) - float(observe(u_fold, p_fold))) / R

    return moved


def force_snap_rules(problem: Problem, pole: str, R: float) -> SnapRules:
    """How the force-controlled point load leaves a limit load (for :func:`contin.quasistatic`).

    The attempts are :data:`FORCE_JUMP_ATTEMPTS` with the kick measured in units of ``R``; a landing
    is a snap when the pole has moved by more than 1e-3 R (:func:`pole_moved`).  The jump stays at
    the load it was minimised at: the snap's ``jump_from`` and ``jump_to`` records are stated there.
    """
    return SnapRules(attempts=FORCE_JUMP_ATTEMPTS, overshoot_unit="fold", perturbation_unit=R,
                     separation=pole_moved(problem, pole, R), min_separation=1e-3, restate=False)


@dataclass
class Build:
    """What a scene builds: the problem the trace starts on, its settings and its start.

    Attributes
    ----------
    problem : Problem
        :class:`contin_models.shell.ShellPointLoad` (point load on the paper's cap, either control),
        :class:`contin_models.shell.structure.ShellOfRevolution` (a point or ring load on any other
        shell, either control; pressure, pressure prescribed) or
        :class:`contin_models.contact.indentation.ShellIndentation` (sphere or plate, indenter travel
        prescribed).
    settings : contin.Settings
        The continuation settings ``contin trace`` uses for it.
    u0 : ndarray
        The starting state: the undeformed cap (an equilibrium at ``p0``).
    p0 : float
        The starting parameter (0: no load, or the first touch of the indenter's barrier).
    w_end : float
        End of the loading path in pole displacement or indenter travel: the eversion depth
        ``2 R (1 - sin phi_hat)`` plus ``continuation.overshoot``.
    """

    problem: Problem
    settings: contin.Settings
    u0: np.ndarray
    p0: float
    w_end: float


#: A flat shell (a plate) has no eversion: its paths run to a deflection of this many thicknesses.
FLAT_TRAVEL_OVER_H = 10.0


def is_papers_cap(scene: Scene) -> bool:
    """Whether the scene's shell is the paper's: a perfect spherical cap on the sliding base."""
    s = scene["shell"]
    return (s.get("geometry", "sphere") == "sphere" and s["boundary"] == "sliding"
            and scene.get("imperfection", {}).get("kind", "none") == "none")


def length_unit(scene: Scene) -> float:
    """The scene's length unit: ``R`` for the sphere, the geometry's length scale otherwise
    (:func:`contin_models.shell_scene.shape.length_scale`)."""
    s = scene["shell"]
    return float(s["R"]) if s.get("geometry", "sphere") == "sphere" else length_scale(s)


def travel(scene: Scene) -> float:
    """The deflection a path is sized by: the eversion depth ``2 H``, or :data:`FLAT_TRAVEL_OVER_H` ``h`` for a plate."""
    s = scene["shell"]
    if s.get("geometry", "sphere") == "sphere":
        return eversion_displacement(s["R"], s["phi_hat"])
    H = rise(s)
    return 2.0 * H if H > 0.0 else FLAT_TRAVEL_OVER_H * s["h"]


#: The lowest deflection of a point or ring path: a path back at the loaded node's unloaded height has left
#: the scene (below it the node is pulled up, along a stable branch that has no end and no fold to find).
LOWEST_W = 0.0


def end_of_path(scene: Scene) -> float:
    """Pole displacement (or indenter travel) that ends a loading path: eversion (:func:`travel`) plus the overshoot."""
    return travel(scene) * (1.0 + scene["continuation"]["overshoot"])


def loaded_travel(scene: Scene, problem: ShellOfRevolution) -> float:
    """The deflection the loaded node can make before its circle is everted: :func:`travel` for a point.

    A ring's circle is everted when it reaches its mirror image in the edge's plane, ``2 (z_ring -
    z_edge)`` below its reference, less than the pole's ``2 H``; pushed further it can only stretch
    the shell, so a path sized by the pole's travel never ends (the path folds back at the ring's
    eversion).  A ring on a flat shell is sized as the flat shell is (:data:`FLAT_TRAVEL_OVER_H` ``h``).
    """
    if scene["load"]["kind"] != "ring":
        return travel(scene)
    height = _ring_height(problem)
    return 2.0 * height if height > 0.0 else FLAT_TRAVEL_OVER_H * scene["shell"]["h"]


def _ring_height(problem: ShellOfRevolution) -> float:
    """Height of the loaded node's reference circle above the edge's plane."""
    return problem.z_ref_node - float(problem.x_ref[1])


#: How far a ring's path goes towards its circle's mirror image (:func:`loaded_travel`).  The pole under a
#: point force can pass its mirror image (the force pulls a spike), but a ring's circle reaches its mirror
#: only in the limit, with the annulus between ring and edge stretched flat: the path folds back short of it
#: (docs/robustness.md has where, on random scenes), so the ring counts as everted within this fraction of it.
RING_EVERSION_FRACTION = 0.9


def loaded_end(scene: Scene, problem: ShellOfRevolution) -> float:
    """The deflection of the loaded node that ends a point or ring path.

    A point's: :func:`loaded_travel` plus the overshoot; a ring's: :data:`RING_EVERSION_FRACTION` of it.
    """
    full = loaded_travel(scene, problem)
    if scene["load"]["kind"] == "ring" and _ring_height(problem) > 0.0:
        return RING_EVERSION_FRACTION * full
    return full * (1.0 + scene["continuation"]["overshoot"])


def _step_cap(scene: Scene) -> float:
    """Largest step in the scene's length unit: ``continuation.ds_max``, at most 1/20 of :func:`travel`."""
    return min(scene["continuation"]["ds_max"], travel(scene) / MIN_STEPS_PER_PATH / length_unit(scene))


def scene_meridian(scene: Scene, perfect: bool = False) -> ReferenceMeridian:
    """The scene's reference meridian: its geometry, a node on the ring of a ring load, its imperfection.

    Parameters
    ----------
    scene : dict
        A resolved scene.
    perfect : bool
        Leave the imperfection out.  (A mode of ``imperfection.waves >= 1`` is not axisymmetric: the meridian
        is then the perfect one, and the 3-D view carries the mode.)

    Raises
    ------
    contin.app.scene.SceneError
        When the shape cannot be built (the message says why).
    """
    s, load = scene["shell"], scene["load"]
    imperfection = None if perfect else scene.get("imperfection")
    ring = load["ring_radius"] if load["kind"] == "ring" else None
    try:
        m = reference_meridian(s, imperfection, ring_radius=ring)
    except ValueError as exc:
        raise SceneError(str(exc), "constraint") from None
    # a mode of n >= 1 waves is the 3-D view's reference (contin_models.shell_scene.view3d.mode_reference)
    if imperfection and imperfection.get("kind") == "mode" and not imperfection.get("waves", 0):
        mode = buckling_mode(scene)
        m = with_mode(m, mode, imperfection["delta_over_h"] * s["h"], normalize="normal")
    return m


def scene_structure(scene: Scene, perfect: bool = False) -> ShellStructure:
    """The scene's shell with its support (:class:`contin_models.shell.structure.ShellStructure`)."""
    s = scene["shell"]
    return ShellStructure(scene_meridian(scene, perfect), s["E"], s["nu"], s["h"], s["boundary"])


def harmonics_of(scene: Scene, structure: ShellStructure) -> int:
    """The largest wave number the scene watches: 0 (``stability.harmonics = false``), ``stability.n_max``, or
    :func:`contin_models.shell.structure.default_harmonics` of the structure when ``n_max = 0``."""
    stab = scene.get("stability", {})
    if not stab.get("harmonics", False):
        return 0
    return int(stab.get("n_max", 0)) or default_harmonics(structure)


def watch_harmonics(scene: Scene, problem: Problem) -> Problem:
    """Give a problem of the paper's cap (the point load or an indenter, under either control) the harmonic
    blocks of its shell as an operator family, when the scene asks for them; returns the problem.

    The blocks are those of the 2-D energy of the paper's model: the sliding cap without an edge
    element (:class:`ShellStructure` with ``edge_bending="none"``), whose energy is
    :class:`contin_models.shell.ShellPointLoad`'s; an indenter adds its barrier's block.
    """
    from contin_models.shell.harmonic import harmonic_family

    structure = traced_structure(scene, problem)
    n_max = harmonics_of(scene, structure)
    if n_max:
        contact = None
        if isinstance(problem, ShellIndentation):  # the indenter's travel is the parameter
            contact = (lambda u, p: (problem.barrier, problem.position(p)))
        elif isinstance(problem, ShellIndentationForce):  # the load is the parameter, the travel an unknown
            contact = (lambda u, p: (problem.barrier, problem.position(u)))
        held = scene["load"]["kind"] == "point" and scene["load"].get("pole_held", False)
        problem.operator_families = (harmonic_family(structure, problem.full_state, n_max, contact=contact,
                                                     pole_held=held),)
    return problem


def traced_structure(scene: Scene, problem: Problem) -> ShellStructure:
    """The :class:`ShellStructure` whose energy is the elastic energy of a problem :func:`build` made of ``scene``.

    A shell of revolution's own structure; for the paper's cap (the point load, the indenters) the sliding cap
    without an edge element (``edge_bending="none"``), whose energy is :class:`ShellPointLoad`'s: what the
    harmonic blocks and the 3-D view of such a scene are built on.
    """
    if isinstance(problem, ShellOfRevolution):
        return problem.structure
    shell = problem.elastic if isinstance(problem, (ShellIndentation, ShellIndentationForce)) else problem
    s = scene["shell"]
    return ShellStructure(shell.cap, s["E"], s["nu"], s["h"], "sliding", shell.shell.kappa11_length,
                          edge_bending="none")


def revolution_problem(scene: Scene, control: str | None = None, perfect: bool = False) -> ShellOfRevolution:
    """The scene's shell under its point, ring or pressure load (:class:`ShellOfRevolution`).

    Pressure is built with the pressure as the parameter whatever ``control`` says (the volume as the
    parameter is :func:`contin_models.shell_scene.pressure.volume_problem` of it).
    """
    s, load = scene["shell"], scene["load"]
    structure = scene_structure(scene, perfect)
    L = length_unit(scene)
    harmonics = harmonics_of(scene, structure)
    if load["kind"] == "pressure":
        return ShellOfRevolution(structure, "pressure", "force", length=L,
                                 p_c=classical_pressure(s["E"], s["h"], L, s["nu"]), harmonics=harmonics)
    if load["kind"] not in ("point", "ring"):
        raise ValueError(f"revolution_problem: load.kind must be point, ring or pressure, got {load['kind']!r}")
    node = structure.meridian.ring_node if load["kind"] == "ring" else None
    return ShellOfRevolution(structure, load["kind"], control or load["control"], node=node, length=L,
                             harmonics=harmonics, pole_held=load["kind"] == "point" and load.get("pole_held", False))


def rest_stiffness(problem: ShellOfRevolution | ShellPointLoad, length: float) -> float:
    """The unloaded shell's stiffness ``dF/dw`` at ``F = 0`` under its load (one linear solve).

    ``length`` is the scene's length unit (:func:`length_unit`), the scale of the difference step.
    ``w`` is the load's deflection (the pole's, or the ring's).  On a sphere under a point load at
    the pole, away from its support, this is Reissner's ``16 sqrt(3 (1 - nu^2)) D / (h R)``; on a
    clamped plate of radius ``a``, ``16 pi D / a^2``.

    Raises
    ------
    ValueError
        When the unloaded shell has no finite positive stiffness (a mechanism).
    """
    if problem.control == "displacement":
        raise ValueError("rest_stiffness: the problem is under displacement control; build it under force control")
    u0 = problem.reference_unknowns()
    p0 = 0.0
    du_dp = -problem.factorize(problem.jacobian(u0, p0)).solve(problem.dresidual_dp(u0, p0))
    w = problem.observables["w"]
    # a central difference over a step that moves the state by 1e-6 of the length unit
    step = 1e-6 * length / max(float(np.max(np.abs(du_dp))), 1e-300)
    dw_dp = float(w(u0 + step * du_dp, p0) - w(u0 - step * du_dp, p0)) / (2.0 * step)
    if not (math.isfinite(dw_dp) and dw_dp > 0.0):
        raise ValueError(f"rest_stiffness: the unloaded shell has no finite positive stiffness (dw/dF = {dw_dp!r})")
    return 1.0 / dw_dp


def revolution_settings(scene: Scene, problem: ShellOfRevolution, progress: bool = False) -> contin.Settings:
    """Continuation settings of a point or ring load on any shell: steps in the scene's length unit, both labels' stability.

    Under force control the load is weighed by :func:`rest_stiffness` ``k``: a change ``k L`` of the
    force counts as much as one length unit ``L`` of the state, so that the force and the deflection
    weigh alike while the shell is linear, and a path winding through many folds takes about the
    steps it takes under displacement control.  The path ends at the deflection :func:`loaded_end`, or
    where the loaded node comes back to its unloaded height (:data:`LOWEST_W`).
    """
    c = scene["continuation"]
    L = length_unit(scene)
    ds_max = _step_cap(scene)
    ds = min(c["ds"], ds_max)
    param_weight = 1.0 / L if problem.control == "displacement" else 1.0 / (rest_stiffness(problem, L) * L)
    # the path has left the scene where the loaded node comes back to its unloaded height: below it the
    # node is pulled up along a stable branch with no end
    end = loaded_end(scene, problem)
    bounds = {"w": (LOWEST_W, end)}
    ends = {"p_max": end, "p_min": LOWEST_W} if problem.control == "displacement" else {}
    return contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, tol=c["tol"], **step_limits(scene),
                           stability=True, n_eigs=0, state_weight=1.0 / L, param_weight=param_weight,
                           progress=progress, bounds=bounds, **ends)


def buckling_mode(scene: Scene) -> np.ndarray:
    """The perfect shell's buckling mode under the scene's load: the null vector at the first fold or
    branch point of its path with the load as the parameter (the first limit load or bifurcation under
    force or pressure control, whatever ``load.control`` says), as a full state, zero on the fixed dofs.

    Raises :class:`contin.app.scene.SceneError` when the path has no located fold or branch point up to
    its end.
    """
    from contin.numerics.stability import stability_info

    load = scene["load"]
    problem = revolution_problem(scene, control="force", perfect=True)
    st = pressure_settings(scene, problem) if load["kind"] == "pressure" else revolution_settings(scene, problem)
    br = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, stop_at=("fold", "branch_point"))
    first = next((p for p in br.special_points if p.kind in ("fold", "branch_point") and p.located), None)
    if first is None:
        raise SceneError("imperfection.kind = \"mode\": the perfect shell's path has no located fold or branch point "
                         f"up to its end ({br.message}); give a dimple instead", "constraint")
    info = stability_info(problem.jacobian(first.u, first.p), k=1, vectors=True)
    mode = np.zeros(problem.structure.n_full)
    mode[problem.idx] = info.eigenvectors[:, 0]
    return mode


def point_problem(scene: Scene, control: str | None = None) -> ShellPointLoad:
    """The point-loaded cap of the scene, under ``control`` (default: the scene's ``load.control``)."""
    s = scene["shell"]
    problem = ShellPointLoad(R=s["R"], E=s["E"], nu=s["nu"], h=s["h"], phi_hat=s["phi_hat"], N=s["N"],
                             control=control or scene["load"]["control"], pole_ratio=s["pole_ratio"])
    return watch_harmonics(scene, problem)


def point_settings(scene: Scene, problem: ShellPointLoad, progress: bool = False) -> contin.Settings:
    """Continuation settings of a point-load trace (steps in units of R, both labels' stability)."""
    c, R = scene["continuation"], scene["shell"]["R"]
    ds_max = _step_cap(scene)
    ds = min(c["ds"], ds_max)
    # weights make ds dimensionless in units of R: positions and w are lengths; a force is measured by
    # the deflection it gives the unloaded cap (rest_stiffness), as on any shell of revolution
    param_weight = 1.0 / R if problem.control == "displacement" else 1.0 / (rest_stiffness(problem, R) * R)
    return contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, tol=c["tol"], **step_limits(scene),
                           stability=True, n_eigs=0, state_weight=1.0 / R, param_weight=param_weight, progress=progress)


def pressure_problem(scene: Scene) -> ShellOfRevolution:
    """The scene's shell under a uniform external pressure (the parameter), on ``shell.boundary``.

    On the perfect spherical cap this is :class:`contin_models.shell.ShellPressure`'s problem (the
    same meridian, unknowns and residual).
    """
    if scene["load"]["kind"] != "pressure":
        raise ValueError(f"pressure_problem: load.kind must be 'pressure', got {scene['load']['kind']!r}")
    return revolution_problem(scene)


def pressure_settings(scene: Scene, problem: ShellOfRevolution, progress: bool = False) -> contin.Settings:
    """Continuation settings of a pressure trace: steps in the scene's length unit, stability under pressure control.

    The path ends at ``load.p_end_over_p_c`` times the classical pressure or at the pole deflection of
    :func:`end_of_path` (eversion plus the overshoot), whichever comes first.
    """
    c = scene["continuation"]
    ds_max = _step_cap(scene)
    ds = min(c["ds"], ds_max)
    L = length_unit(scene)
    # positions and w are lengths in units of L; a pressure change of p_c weighs as much as the pole
    # moving through the eversion depth, so both halves of the path (the pressure rising to the snap,
    # the pole travelling to eversion) are resolved by the same steps
    return contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, tol=c["tol"], **step_limits(scene),
                           stability=True, n_eigs=0, state_weight=1.0 / L,
                           param_weight=travel(scene) / (L * problem.p_c), progress=progress,
                           p_max=scene["load"]["p_end_over_p_c"] * problem.p_c, bounds={"w": (None, end_of_path(scene))})


def contact_problem(scene: Scene) -> ShellIndentation:
    """The cap under the scene's rigid sphere or plate, indenter travel ``w_b`` prescribed."""
    s, load, c = scene["shell"], scene["load"], scene["contact"]
    if load["kind"] not in ("sphere", "plate"):
        raise ValueError(f"contact_problem: load.kind must be 'sphere' or 'plate', got {load['kind']!r}")
    indenter = Sphere(load["radius"]) if load["kind"] == "sphere" else Plate()
    problem = ShellIndentation(R=s["R"], E=s["E"], nu=s["nu"], h=s["h"], phi_hat=s["phi_hat"], N=s["N"],
                               indenter=indenter, K=c["K_c"] or None, dhat=c["dhat"] or None,
                               pole_ratio=s["pole_ratio"])
    return watch_harmonics(scene, problem)


def contact_settings(scene: Scene, progress: bool = False, stability: bool = True) -> tuple[contin.Settings, float]:
    """Continuation settings and the end of travel ``w_end`` of a sphere or plate scene."""
    c, R = scene["continuation"], scene["shell"]["R"]
    # lengths in units of R, as for the point load; the first contact is a sharp corner of the path
    # (the barrier switches on), so the first step is a quarter of the scene's
    ds_max = _step_cap(scene)
    ds = 0.25 * min(c["ds"], ds_max)
    st = contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, tol=c["tol"], **step_limits(scene),
                         stability=stability, n_eigs=0, state_weight=1.0 / R, param_weight=1.0 / R, progress=progress)
    return st, end_of_path(scene)


def build(scene: Scene, progress: bool = False) -> Build:
    """The problem, settings and start of a scene, as ``contin trace`` starts it.

    A point load on the paper's cap is built under the scene's ``load.control``
    (:class:`ShellPointLoad`); a point or ring load on any other shell too
    (:class:`contin_models.shell.structure.ShellOfRevolution`); a pressure under pressure control, with
    the trace's end (pressure and eversion) in its settings.  A sphere or plate is built under
    displacement control of the indenter whatever ``load.control`` says: force control of an
    indenter starts from a contact state that displacement control reaches first
    (:func:`contin_models.shell_scene.contact.run_contact_force`).
    """
    problem: Problem
    if scene["load"]["kind"] == "point" and is_papers_cap(scene):
        problem = point_problem(scene)
        settings = point_settings(scene, problem, progress)
    elif scene["load"]["kind"] in ("point", "ring"):
        problem = revolution_problem(scene)
        settings = revolution_settings(scene, problem, progress)
    elif scene["load"]["kind"] == "pressure":
        problem = pressure_problem(scene)
        settings = pressure_settings(scene, problem, progress)
    else:
        problem = contact_problem(scene)
        settings, _ = contact_settings(scene, progress)
    return Build(problem=problem, settings=settings, u0=problem.reference_unknowns(), p0=0.0,
                 w_end=end_of_path(scene))
