"""The scene schema of the shell with its loads (``contin trace --model shell``) and its geometry helpers.

Scene keys (public contract, ``--set section.key=value``)::

    [shell]         geometry = "sphere" | "cone" | "plate" | "torus" | "ellipse" | "table" (shape.py),
                    R, phi_hat (sphere; R also the torispherical crown), a (base radius: cone, plate, torus;
                    radial semi-axis: ellipse), H (cone's rise), b, t_edge (ellipse), knuckle (torus),
                    table (CSV profile), E, nu, h, N, pole_ratio (node spacing at the pole / elsewhere),
                    boundary = "sliding" | "pinned" | "clamped" | "free" (the indenters: sliding only)
    [imperfection]  kind = "none" | "dimple" | "mode", delta_over_h, lambda_I (dimple width), waves (mode: 0 axisymmetric,
                    n >= 1 waves in the 3-D view)
    [view]          kind = "axisymmetric" | "3d", symmetry = "Dn" | "none", harmonics (K), angles (M, 0: the rule)
    [stability]     harmonics (watch non-axisymmetric modes n = 1 .. n_max), n_max (0: the default rule)
    [load]          kind = "point" | "ring" | "sphere" | "plate" | "pressure", radius (sphere),
                    ring_radius (ring), pole_held (point, with harmonics), control = "displacement" | "force" (pressure: the volume change
                    dV = V0 - V | the pressure), p_end_over_p_c (pressure, force control), dV_end_over_V0
                    (pressure, displacement control)
    [contact]       K_c, dhat (0: the paper's values scaled with E and R; sphere and plate only)
    [continuation]  ds, ds_max (units of R), tol, max_steps, overshoot
    [output]        figure, pdf, shapes
"""

from __future__ import annotations

import math
from typing import Any

from contin.app.scene import Constraint, Field, Schema, boolean, choice, integer, real, text
from contin_models.shell.supports import SUPPORTS

from .shape import GEOMETRIES, base_radius, bending_radius, meridian_length

__all__ = ["SHELL_SCHEMA", "shell_first_instability", "instability_text", "harmonic_summary", "record_fields",
           "record_instability", "MAX_NODES", "LARGE_MESH", "MIN_NODES_PER_BENDING_LENGTH", "STABILITY_COLUMNS", "Scene",
           "eversion_displacement", "minimum_nodes", "WRINKLE_NODES", "MIN_WRINKLE_NODES", "WRINKLE_DEPTH", "POINT_LIKE_RING",
           "crosses_wrinkled_middle", "wrinkle_nodes", "symmetry_order", "nodes_per_bending_length", "run_time_forecast", "STALL_STEPS",
           "AUTO_MAX_STEPS"]

Scene = dict[str, dict[str, Any]]

#: Largest ``shell.N``.  Rounding grows with the mesh (the bending stiffness is a discrete fourth
#: derivative): past a few thousand nodes it outweighs the discretization error, and on finer meshes
#: it breaks the trace itself (the default path at N = 50000 scatters into spurious extrema and never
#: reaches eversion); docs/scenes.md has the measurements.
MAX_NODES = 20_000
#: ``shell.N`` above which the command line warns, before the run, roughly how long it takes
#: (:func:`run_time_forecast`).
LARGE_MESH = 8000
# The default path's cost on a fine mesh, for the forecast (docs/scenes.md): seconds per step at
# N = 3200 on one core, the exponent of its growth with N from 3200 to 20000 nodes (faster than N:
# the band matrices outgrow the processor's cache, and rounding costs Newton iterations), and its steps.
_STEP_SECONDS_AT_3200 = 0.027
_STEP_GROWTH = 1.25
_PATH_STEPS = 230


def _nodes_ok(n: int) -> bool:
    return 10 <= n <= MAX_NODES


#: ``continuation.max_steps = "auto"``: a branch stops once this many steps in a row made no progress (no
#: fold, branch point or event found, and its end approached no closer): a thin deep cap winds through a
#: fold every few dozen steps on its way to eversion, however many folds its path has.
STALL_STEPS = 3000
#: ``continuation.max_steps = "auto"``: the most steps a branch that keeps progressing may take.
AUTO_MAX_STEPS = 200_000

#: Nodes per bending length ``sqrt(R h)`` below which a scene is refused (``shell.N``).
MIN_NODES_PER_BENDING_LENGTH = 4

#: Nodes over the bending length ``sqrt(R h)`` at which every measured path through a deep cap's wrinkled middle
#: ended: there a train of meridional wrinkles, each about 0.4 ``sqrt(R h)`` long, runs from the edge to the
#: pole, and on a coarser mesh the train can break up into a path that folds back and forth without reaching
#: its end (``docs/robustness.md``).  What the advice after such a path asks for.
WRINKLE_NODES = 8.5
#: Nodes over ``sqrt(R h)`` below which every measured path through that middle wound (up to 7.13; they
#: ended from 7.24 on): what the validation rule asks for.
MIN_WRINKLE_NODES = 7.2
#: The cap's depth ``lambda`` (:func:`contin_models.shell.boundaries.depth_parameter`, the paper's) beyond which
#: a connected path through the middle wrinkles so (the caps measured: winding from 30.0 on, none up to 27.8).
WRINKLE_DEPTH = 30.0
#: A ring closer to the pole than this many bending lengths ``sqrt(R h)`` loads the cap as a point does: its
#: path crosses the wrinkled middle (measured: rings at 1.8 to 3.6 wound, from 4.6 on none did).
POINT_LIKE_RING = 4.0


def crosses_wrinkled_middle(scene: dict[str, dict[str, Any]]) -> bool:
    """Whether the scene traces a deep spherical cap's connected path through its wrinkled middle.

    That path is traced for a point load under displacement control, a point load on a cap other than the
    paper's (another support or an imperfection) under either control, and a ring within
    :data:`POINT_LIKE_RING` bending lengths of the pole under either control; a point force on the paper's cap
    snaps over the middle (its energy descent lands beyond it), and a wider ring's path ends at the ring's
    own eversion first.  The cap is deep when its ``lambda`` exceeds :data:`WRINKLE_DEPTH`.  The measurements
    behind the rule are on the axisymmetric trace, so the 3-D view and the followed path are not covered.
    """
    shell, load = scene["shell"], scene["load"]
    if (shell.get("geometry", "sphere") != "sphere" or load["kind"] not in ("point", "ring")
            or scene["view"]["kind"] != "axisymmetric" or scene["stability"]["follow"] or not _thin(scene)):
        return False
    if load["kind"] == "ring" and load["ring_radius"] >= POINT_LIKE_RING * math.sqrt(shell["R"] * shell["h"]):
        return False
    papers_cap = shell["boundary"] == "sliding" and scene["imperfection"]["kind"] == "none"
    if load["kind"] == "point" and load["control"] == "force" and papers_cap:
        return False
    return _depth(shell) > WRINKLE_DEPTH


def _depth(shell: dict[str, Any]) -> float:
    """The spherical cap's ``lambda`` (:func:`contin_models.shell.boundaries.depth_parameter`)."""
    from contin_models.shell.boundaries import depth_parameter  # the shell's modules load only for a cap that may need it

    return float(depth_parameter(shell["phi_hat"], shell["h"] / shell["R"], shell["nu"]))


def wrinkle_nodes(shell: dict[str, Any], per_length: float = MIN_WRINKLE_NODES) -> int:
    """Fewest nodes that put ``per_length`` nodes over the bending length ``sqrt(R h)`` (by default what the
    validation rule asks, :data:`MIN_WRINKLE_NODES`)."""
    return minimum_nodes(shell, per_length)


def _wrinkle_mesh_ok(scene: dict[str, dict[str, Any]]) -> bool:
    """The mesh rule of a path through a deep cap's wrinkled middle (:func:`crosses_wrinkled_middle`)."""
    return not crosses_wrinkled_middle(scene) or scene["shell"]["N"] >= wrinkle_nodes(scene["shell"])


def _wrinkle_mesh_needs(scene: dict[str, dict[str, Any]]) -> str:
    """What the wrinkle rule asks of this scene's ``shell.N``, as numbers."""
    shell = scene["shell"]
    return (f"this cap (lambda = {_depth(shell):.1f}) needs shell.N >= {wrinkle_nodes(shell)} for its path's middle "
            f"(shell.N = {shell['N']} puts {nodes_per_bending_length(shell):.2g} nodes over the bending length)")


def _shape_error(scene: dict[str, dict[str, Any]]) -> str:
    """Why the scene's shape cannot be built (the torispherical head's proportions, the table's file), or ``""``."""
    from .shape import reference_meridian

    shell = scene["shell"]
    if shell.get("geometry", "sphere") == "sphere":
        return ""
    try:
        reference_meridian(shell, N=16)
    except ValueError as exc:
        return str(exc)
    return ""


def _geometry_ok(scene: dict[str, dict[str, Any]]) -> bool:
    """Whether the scene's shape can be built."""
    return not _shape_error(scene)


def _shape_ok(geometry: str) -> Any:
    """The check of one geometry's shape: other geometries pass it."""
    return lambda scene: scene["shell"]["geometry"] != geometry or _geometry_ok(scene)


def _mesh_ok(scene: dict[str, dict[str, Any]]) -> bool:
    """The mesh rule: at least :data:`MIN_NODES_PER_BENDING_LENGTH` nodes over the bending length."""
    return not _geometry_ok(scene) or not _thin(scene) or scene["shell"]["N"] >= minimum_nodes(scene["shell"])


def _mesh_needs(scene: dict[str, dict[str, Any]]) -> str:
    """What the mesh rule asks of this scene's ``shell.N``, as a number."""
    shell = scene["shell"]
    needed = minimum_nodes(shell)
    out = (f"this shell needs shell.N >= {needed} (shell.N = {shell['N']} puts {nodes_per_bending_length(shell):.2g} "
           f"nodes over the bending length)")
    if needed > MAX_NODES:
        out += f", more than the largest shell.N = {MAX_NODES}: the shell is too thin for the model's meshes"
    return out


def _thin(scene: dict[str, dict[str, Any]]) -> bool:
    """Whether the thickness is below the meridian's smallest radius of curvature (the sphere's ``R``)."""
    shell = scene["shell"]
    if shell.get("geometry", "sphere") == "sphere":
        return shell["h"] < shell["R"]
    return not _geometry_ok(scene) or shell["h"] < bending_radius(shell)


def symmetry_order(symmetry: str) -> tuple[int, bool]:
    """``(n, mirror)`` of ``view.symmetry``: ``"Dn"`` is ``(n, True)``, ``"none"`` ``(1, False)``.

    Raises
    ------
    ValueError
        For any other text, and for ``"Dn"`` with ``n < 2``.
    """
    text = str(symmetry).strip()
    if text == "none":
        return 1, False
    if len(text) > 1 and text[0] in "dD" and text[1:].isdigit() and int(text[1:]) >= 2:
        return int(text[1:]), True
    raise ValueError(f'view.symmetry must be "Dn" with an integer n >= 2 (e.g. "D3") or "none", got {symmetry!r}')


def _symmetry_ok(symmetry: str) -> bool:
    try:
        symmetry_order(symmetry)
    except ValueError:
        return False
    return True


def _angles_ok(scene: dict[str, dict[str, Any]]) -> bool:
    view = scene["view"]
    if view["kind"] != "3d" or view["angles"] == 0 or not _symmetry_ok(view["symmetry"]):
        return True
    n, mirror = symmetry_order(view["symmetry"])
    M = view["angles"]
    return M > 2 * view["harmonics"] * n and (M % (2 * n) == 0 if mirror else True)


def _angles_need(scene: dict[str, dict[str, Any]]) -> str:
    view = scene["view"]
    n, mirror = symmetry_order(view["symmetry"])
    step = 2 * n if mirror else 1
    least = (2 * view["harmonics"] * n // step + 1) * step
    return (f"view.symmetry = {view['symmetry']!r} and view.harmonics = {view['harmonics']} need view.angles >= {least}"
            + (f" and a multiple of {step}" if mirror else "") + f" (view.angles = {view['angles']})")


def _waves_ok(scene: dict[str, dict[str, Any]]) -> bool:
    waves, view = scene["imperfection"]["waves"], scene["view"]
    if waves == 0 or view["kind"] != "3d" or not _symmetry_ok(view["symmetry"]):
        return True
    n, _ = symmetry_order(view["symmetry"])
    return waves % n == 0 and waves <= view["harmonics"] * n


def _view_load_ok(scene: dict[str, dict[str, Any]]) -> bool:
    if scene["view"]["kind"] != "3d":
        return True
    kind, control = scene["load"]["kind"], scene["load"]["control"]
    return (kind in ("point", "ring") or (kind == "pressure" and control == "force")
            or (kind in ("sphere", "plate") and control == "displacement"))


SHELL_SCHEMA = Schema(
    sections={
        "shell": {
            "R": real(1.0, gt=0, help="sphere radius [m] (geometry sphere; the crown radius of the torus geometry)"),
            "E": real(1e6, gt=0, help="Young's modulus [Pa]"),
            "nu": real(0.5, gt=-1, le=0.5, help="Poisson's ratio"),
            "h": real(0.02, gt=0, help="thickness [m]"),
            "phi_hat": real(0.8, gt=0, lt=math.pi / 2,
                            help="base angle from the horizontal [rad] (small = deep cap)"),
            "N": Field(int, 200, _nodes_ok, f"an integer >= 10 and <= {MAX_NODES} (on finer meshes rounding breaks "
                                            "the trace, docs/scenes.md)",
                       f"number of nodes on the meridian (above {LARGE_MESH} a run is announced with an estimate of "
                       "its time)"),
            "pole_ratio": real(0.5, gt=0, le=1, help="node spacing at the pole / elsewhere (1 = uniform mesh; "
                                                    "graded towards the point load by default)"),
            "boundary": choice("sliding", SUPPORTS,
                               help="support of the base edge: sliding (z fixed, r free: the paper's base), pinned "
                                    "(r and z fixed), clamped (r, z and the edge rotation fixed) or free (nothing; "
                                    "pressure on a closed shell only); the indenters take sliding only"),
            "geometry": choice("sphere", GEOMETRIES,
                               help="meridian: the spherical cap (R, phi_hat), a cone (a, H), a flat plate (a), a "
                                    "torispherical head (crown R, base a, knuckle), a spheroidal cap (a, b, t_edge) or a "
                                    "tabulated profile (table); point, ring and pressure loads only, except the sphere"),
            "a": real(0.8, gt=0, help="base radius [m] (cone, plate, torus); the radial semi-axis (ellipse)"),
            "H": real(0.2, gt=0, help="rise of the cone's apex above its base [m] (geometry cone)"),
            "b": real(0.5, gt=0, help="axial semi-axis of the spheroid [m] (geometry ellipse)"),
            "t_edge": real(0.5, ge=0, lt=math.pi / 2, help="parametric angle of the spheroidal cap's edge [rad], 0 = "
                                                             "its equator (geometry ellipse)"),
            "knuckle": real(0.1, gt=0, help="radius of the torispherical head's knuckle [m] (geometry torus)"),
            "table": text("", help="CSV file of the profile's points r, z from the edge to the pole on the axis "
                                   "(geometry table)"),
        },
        "load": {
            "kind": choice("point", ("point", "ring", "sphere", "plate", "pressure"),
                           help="a point force at the pole (bilateral), a ring force on the circle of radius "
                                "load.ring_radius, a rigid sphere or plate through the log-barrier contact, or a "
                                "uniform external pressure p"),
            "radius": real(0.5, gt=0, help="sphere radius [m] (load.kind = sphere)"),
            "pole_held": boolean(False, help="with stability.harmonics: the point load holds the pole laterally (no "
                                             "n = 1 translation of the pole); false: a frictionless point, which lets "
                                             "the pole slide sideways under the force"),
            "ring_radius": real(0.5, gt=0, help="radius of the ring load's circle [m] (load.kind = ring), inside the "
                                                "edge's radius"),
            "control": choice("displacement", ("displacement", "force"),
                              help="displacement: the pole displacement w (point), the indenter travel w_b "
                                   "(sphere, plate) or the volume change dV = V0 - V (pressure: the volume the "
                                   "pressure pushes in, positive inwards, length^3; p is its Lagrange multiplier) is "
                                   "prescribed; force: a dead load F on the pole or the indenter, or the pressure p"),
            "p_end_over_p_c": real(2.0, gt=0, help="pressure scenes under force control: stop at this pressure over the "
                                                   "classical p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2)), unless eversion "
                                                   "comes first"),
            "dV_end_over_V0": real(2.1, gt=0, help="pressure scenes under displacement (volume) control: stop at the "
                                                   "volume change dV = V0 - V equal to this times the unloaded cap's "
                                                   "volume V0 over its base plane (2: the cap's mirror image, everted), "
                                                   "unless the pole passes eversion first"),
        },
        "continuation": {
            "ds": real(0.02, gt=0, help="initial arclength step in units of R"),
            "ds_max": real(0.1, gt=0, help="largest step in units of R (also capped at 1/20 of the eversion depth)"),
            # the floor is measured: at tol = 1e-12 the default scene (N = 200 and 800) stops at its first
            # points with Newton stalled at round-off; 5e-12 and 1e-11 run every load kind and control
            "tol": real(1e-10, ge=1e-11, lt=1, help="relative residual tolerance (below 1e-11 round-off in the "
                                                     "shell's residual keeps Newton from converging)"),
            "max_steps": integer("auto", low=1, high=1_000_000, words=("auto",),
                                 help=f"steps per branch: \"auto\" goes on while the branch progresses (a fold, branch "
                                      f"point or event found, or its end approached, within the last {STALL_STEPS} "
                                      f"steps) up to {AUTO_MAX_STEPS} steps; a number is obeyed exactly"),
            "overshoot": real(0.05, ge=0, le=1,
                              help="stop this fraction past eversion, w = 2 R (1 - sin phi_hat) (1 + overshoot)"),
        },
        "contact": {
            "K_c": real(0.0, ge=0, help="barrier stiffness [N/m]; 0 = 100 E R (the paper's 1e8 for E = 1 MPa, R = 1 m)"),
            "dhat": real(0.0, ge=0, help="barrier range [m]; 0 = 1e-3 R (the paper's 1e-3 for R = 1 m)"),
        },
        "output": {
            "figure": boolean(True, help="draw the diagram and the shapes figure (false: no figure file is written)"),
            "pdf": boolean(False, help="also write the figures as PDF (diagram.pdf, shapes.pdf) beside the PNGs "
                                       "(as 'contin trace --pdf' does)"),
            "shapes": choice("special", ("special", "path"),
                             help="what shapes.npz holds: the deformed meridian at every special point (special), or "
                                  "also at every stored point of the path (path: its path_* arrays, one row per row "
                                  "of branch.csv)"),
        },
        "imperfection": {
            "kind": choice("none", ("none", "dimple", "mode"),
                           help="stress-free shape: perfect, a Gaussian dimple at the pole, or the perfect shell's "
                                "buckling mode (the null vector at the first fold or branch point of its path)"),
            "delta_over_h": real(0.0, help="amplitude over the thickness: the dimple's depth at the pole, or the "
                                           "mode's largest inward normal displacement (positive pushes inwards)"),
            "waves": integer(0, low=0, high=1000,
                             help="kind = \"mode\": 0, the perfect shell's axisymmetric buckling mode; n >= 1 (view.kind "
                                  "= \"3d\"), its mode of n waves where its path first bifurcates into n waves"),
            "lambda_I": real(2.0, gt=0, help="dimple width lambda_I = (12 (1 - nu^2))^(1/4) sqrt(R/h) beta_0, "
                                             "beta_0 its angular width (R: the geometry's length scale)"),
        },

        "view": {
            "kind": choice("axisymmetric", ("axisymmetric", "3d"),
                           help="axisymmetric: the meridian's states (r, z per node), the traced model; 3d: states "
                                "that need not be axisymmetric, each node a ring of material points moving in three "
                                "directions as Fourier series in the angle, in the symmetry class view.symmetry "
                                "(docs/model.md, the 3-D view)"),
            "symmetry": Field(str, "D3", _symmetry_ok, 'a dihedral class "D2", "D3", ... ("Dn", n >= 2) or "none"',
                              "symmetry of the traced states in the 3-D view: Dn, n-fold rotation about the axis and "
                              "the mirror in a meridional plane (waves 0, n, 2n, ...; the other classes of Dn are "
                              "watched by their Bloch blocks), or none (every wave 0 .. view.harmonics)"),
            "harmonics": integer(3, low=1, high=64, help="harmonics K of the 3-D view: the waves 0, n, ..., K n (Dn) "
                                                        "or 0 .. K (none)"),
            "angles": integer(0, low=0, high=100_000,
                              help="angles M of the 3-D view's trapezoidal rule on the whole circle, a multiple of 2n "
                                   "(Dn) above 2 K n; 0: the smallest multiple of 2 n above 3 K n"),
        },
        "stability": {
            "harmonics": boolean(False, help="also judge stability against non-axisymmetric modes: the Hessian blocks of "
                                             "wave numbers n = 1 .. n_max at every point, a bifurcation into mode n "
                                             "located and recorded (off by default: it costs about 3 times the trace and "
                                             "changes what the paper's classification means, README)"),
            "n_max": integer(0, low=0, high=1000, help="largest wave number watched; 0 = 1.25 times the classical critical "
                                                       "number plus 2 (contin_models.shell.structure.default_harmonics)"),
            "follow": boolean(False, help="follow the path the shell really takes (needs stability.harmonics): where the "
                                          "followed branch loses stability, the stable branch that rises there (an n-wave "
                                          "branch in the 3-D view of its symmetry, with view.harmonics harmonics) or "
                                          "else a snap to the next stable state, to the end of the load"),
        },    },
    constraints=[
        Constraint(("view.kind", "view.symmetry", "view.harmonics", "view.angles"), _angles_ok,
                   "view.angles = 0 or a multiple of 2 n above 2 K n (view.symmetry = \"Dn\"; above 2 K for "
                   "\"none\"), K = view.harmonics",
                   "the trapezoidal rule in the angle integrates the second variation about an axisymmetric state "
                   "exactly only with more than 2 K n angles, and a Dn-symmetric state is evaluated on one half "
                   "period, which needs a multiple of 2 n", detail=_angles_need),
        Constraint(("view.kind", "load.kind", "load.control"), _view_load_ok,
                   'with view.kind = "3d": load.kind = "point" or "ring" (either control), "pressure" under '
                   'load.control = "force", or "sphere" or "plate" under load.control = "displacement"',
                   "the 3-D view traces the equilibrium path through its folds under the parameter of the scene's "
                   "control; a prescribed volume and a dead load on an indenter are traced in the axisymmetric view "
                   "(view.kind = \"axisymmetric\")"),
        Constraint(("imperfection.waves", "imperfection.kind", "view.kind"),
                   lambda s: s["imperfection"]["waves"] == 0 or (s["imperfection"]["kind"] == "mode"
                                                                and s["view"]["kind"] == "3d"),
                   'imperfection.waves = 0, or imperfection.kind = "mode" with view.kind = "3d"',
                   "a mode of n >= 1 waves is not axisymmetric: only the 3-D view carries it"),
        Constraint(("imperfection.waves", "view.symmetry", "view.harmonics"), _waves_ok,
                   "imperfection.waves a wave of the view: a multiple of n up to K n (view.symmetry = \"Dn\"), up "
                   "to K (\"none\"), K = view.harmonics",
                   "an imperfection that breaks the declared symmetry would be cut to the part the traced class "
                   "carries; declare a symmetry the imperfection has (e.g. view.symmetry = \"D3\" for 3 or 6 waves)"),
        Constraint(("view.kind", "stability.harmonics"),
                   lambda s: s["view"]["kind"] != "3d" or not s["stability"]["harmonics"],
                   'stability.harmonics = false with view.kind = "3d"',
                   "stability.harmonics watches the axisymmetric view's harmonic blocks; the 3-D view judges "
                   "stability against every class of perturbation of its symmetry itself (the Bloch blocks of Dn, or "
                   "every wave of view.harmonics without symmetry)"),
        Constraint(("stability.follow", "stability.harmonics", "view.kind"),
                   lambda s: not s["stability"]["follow"] or (s["stability"]["harmonics"]
                                                             and s["view"]["kind"] == "axisymmetric"),
                   'stability.harmonics = true and view.kind = "axisymmetric" with stability.follow = true',
                   "the followed path starts on the axisymmetric path and leaves it where a harmonic block shows a "
                   "bifurcation into waves, so it needs the blocks watched; the 3-D views it goes on in are chosen "
                   "by the symmetry of each branch (view.harmonics sets their harmonics)"),
        Constraint(("stability.follow", "load.kind", "load.control", "load.pole_held"),
                   lambda s: not s["stability"]["follow"] or (
                       (s["load"]["kind"] in ("point", "ring") and not s["load"]["pole_held"])
                       or s["load"]["kind"] == "pressure"
                       or (s["load"]["kind"] in ("sphere", "plate") and s["load"]["control"] == "displacement")),
                   'load.kind = "point" or "ring" (the pole free), "pressure", or "sphere" or "plate" under '
                   'load.control = "displacement", with stability.follow = true',
                   "the followed path is built for a point or ring load and a pressure under either control and an "
                   "indenter driven by its travel; a dead load on an indenter is not followed yet (trace it with "
                   "stability.harmonics to see where it leaves the axisymmetric path)"),
        Constraint(("view.kind", "view.symmetry", "load.pole_held"),
                   lambda s: not (s["view"]["kind"] == "3d" and s["view"]["symmetry"] == "none"
                                  and s["load"]["kind"] == "point" and s["load"]["pole_held"]),
                   'load.pole_held = false with view.kind = "3d" and view.symmetry = "none"',
                   "in the 3-D view the point force at the pole is frictionless: without symmetry the pole may move "
                   "sideways (in a Dn class with n >= 2 it stays on the axis by symmetry)"),
        Constraint(("continuation.ds", "continuation.ds_max"),
                   lambda s: s["continuation"]["ds"] <= s["continuation"]["ds_max"],
                   "continuation.ds <= continuation.ds_max"),
        Constraint(("shell.h", "shell.R"), _thin,
                   "shell.h < shell.R (other geometries: below the meridian's smallest radius of curvature, "
                   "shell.a for the cone and the plate, shell.knuckle for the torus)",
                   "the shell model is thin: its thickness must be below its radius"),
        Constraint(("shell.N", "shell.h", "shell.R", "shell.phi_hat"), _mesh_ok,
                   f"shell.N >= {MIN_NODES_PER_BENDING_LENGTH} L / sqrt(rho h), L the meridian's length and rho its "
                   "smallest radius of curvature (the sphere: (pi/2 - phi_hat) / sqrt(h/R))",
                   f"a snapping cap bends over the length sqrt(R h); with fewer than {MIN_NODES_PER_BENDING_LENGTH} "
                   "nodes over it the discrete path winds through spurious folds and snaps (random scenes below "
                   "the rule failed 12 times in 15, studies/fuzz.py); refine the mesh",
                   detail=_mesh_needs),
        Constraint(("shell.N", "shell.h", "shell.R", "shell.phi_hat", "shell.nu", "load.kind", "load.control"),
                   _wrinkle_mesh_ok,
                   f"shell.N >= {MIN_WRINKLE_NODES:g} (pi/2 - phi_hat) / sqrt(h/R) on a spherical cap deeper than lambda = "
                   f"{WRINKLE_DEPTH:g} (lambda = (12 (1 - nu^2))^(1/4) (pi/2 - phi_hat) / sqrt(h/R)) whose path crosses its "
                   f"middle: a point load under displacement control (on "
                   f"another support or an imperfect cap also under force control), or a ring within "
                   f"{POINT_LIKE_RING:g} sqrt(R h) of the pole",
                   "in the middle of such a path, between the cap and its mirror image, a train of meridional "
                   "wrinkles about 0.4 sqrt(R h) long runs from the edge to the pole; with fewer than "
                   f"{MIN_WRINKLE_NODES:g} nodes over sqrt(R h) the train breaks up and the discrete path folds back and "
                   "forth for hundreds of thousands of steps without reaching its end (docs/robustness.md); refine "
                   "the mesh, or trace a point load under force control, which snaps over the middle",
                   detail=_wrinkle_mesh_needs),
        Constraint(("shell.geometry", "shell.a", "shell.R", "shell.knuckle"), _shape_ok("torus"),
                   "a buildable shape: torus 0 < shell.knuckle < shell.a < shell.R",
                   "the torispherical head's knuckle joins its crown inside the base radius"),
        Constraint(("shell.geometry", "shell.table"), _shape_ok("table"),
                   "a buildable shape: shell.table names an existing CSV file of at least 4 points r, z from the "
                   "edge to the pole on the axis",
                   "the file of a table geometry is read when the scene is checked; a relative path is taken from "
                   "the current directory",
                   detail=_shape_error),
        Constraint(("shell.boundary", "shell.geometry", "imperfection.kind", "load.kind"),
                   lambda s: s["load"]["kind"] not in ("sphere", "plate")
                   or (s["shell"]["boundary"] == "sliding" and s["shell"]["geometry"] == "sphere"
                       and s["imperfection"]["kind"] == "none"),
                   'the indenters (load.kind = "sphere" or "plate") on the paper\'s cap: shell.geometry = "sphere", '
                   'shell.boundary = "sliding", imperfection.kind = "none"',
                   "the log-barrier contact is built on the paper's sliding spherical cap; a point, ring or pressure "
                   "load takes every geometry, support and imperfection"),
        Constraint(("shell.boundary", "load.kind"),
                   lambda s: s["shell"]["boundary"] != "free",
                   'shell.boundary in ("sliding", "pinned", "clamped")',
                   "a free edge leaves the shell unsupported: a point or ring force has nothing to push against, and "
                   "a pressure on an open shell has no closed volume (a complete sphere, closed at both poles, is in "
                   "the Python API: contin_models.shell.meridian.complete_sphere_meridian)"),
        Constraint(("load.ring_radius", "shell.geometry"),
                   lambda s: s["load"]["kind"] != "ring" or not _geometry_ok(s)
                   or s["load"]["ring_radius"] < base_radius(s["shell"]),
                   "load.ring_radius < the edge's radius (shell.R cos(shell.phi_hat) for the sphere, shell.a for the "
                   "cone, plate and torus, shell.a cos(shell.t_edge) for the ellipse)",
                   "the ring load acts on a circle of the shell between its edge and its pole"),
        Constraint(("imperfection.kind", "imperfection.delta_over_h"),
                   lambda s: s["imperfection"]["kind"] == "none" or s["imperfection"]["delta_over_h"] != 0.0,
                   "imperfection.delta_over_h != 0 when imperfection.kind is not \"none\"",
                   "an imperfection of zero amplitude is the perfect shell: set imperfection.kind = \"none\" or give "
                   "its amplitude"),
        Constraint(("shell.geometry", "load.kind", "load.control"),
                   lambda s: not (s["shell"]["geometry"] == "plate" and s["load"]["kind"] == "pressure"
                                  and s["load"]["control"] == "displacement"),
                   'load.control = "force" for a pressure on shell.geometry = "plate"',
                   "volume control prescribes the enclosed volume's change relative to the reference volume V0 "
                   "(load.dV_end_over_V0), and a flat plate encloses none; trace the plate under its pressure"),
    ],
)


def nodes_per_bending_length(shell: dict[str, Any], N: int | None = None) -> float:
    """How many nodes the meridian's mean spacing puts over the bending length ``sqrt(rho h)``.

    ``rho`` is the meridian's smallest radius of curvature (:func:`contin_models.shell_scene.shape.bending_radius`;
    the sphere's ``R``).

    Parameters
    ----------
    shell : dict
        The scene's ``[shell]`` section (the geometry's keys, ``h`` and, unless ``N`` is given, ``N``).
    N : int, optional
        A number of nodes other than the scene's.
    """
    if shell.get("geometry", "sphere") == "sphere":
        arc, rho = shell["R"] * (math.pi / 2 - shell["phi_hat"]), shell["R"]  # the meridian's length
    else:
        arc, rho = meridian_length(shell), bending_radius(shell)
    return (shell["N"] if N is None else N) * math.sqrt(rho * shell["h"]) / arc


def minimum_nodes(shell: dict[str, Any], per_length: float = MIN_NODES_PER_BENDING_LENGTH) -> int:
    """Fewest nodes that put ``per_length`` nodes over the bending length ``sqrt(R h)`` (by default what the
    mesh rule asks, :data:`MIN_NODES_PER_BENDING_LENGTH`).

    Parameters
    ----------
    shell : dict
        The scene's ``[shell]`` section (``R``, ``h``, ``phi_hat``).
    per_length : float
        Nodes wanted over the bending length.
    """
    return math.ceil(per_length / nodes_per_bending_length(shell, N=1) - 1e-9)


def run_time_forecast(scene: Scene) -> str | None:
    """The warning said before a scene on a very fine mesh runs: roughly how long, and why; None below
    :data:`LARGE_MESH` nodes.

    The estimate is the default path's (the point load on the paper's cap) measured on one core of a
    2-core machine; the other loads take more steps, and ``stability.harmonics`` about 3 times longer.

    Parameters
    ----------
    scene : dict
        The resolved scene.
    """
    N = scene["shell"]["N"]
    if N <= LARGE_MESH:
        return None
    per_step = _STEP_SECONDS_AT_3200 * (N / 3200) ** _STEP_GROWTH
    total = per_step * _PATH_STEPS
    duration = f"{total:.0f} s" if total < 90 else f"{total / 60:.0f} minutes"
    return (f"shell.N = {N} is a very fine mesh: expect roughly {duration} for the default point load's path "
            f"({_PATH_STEPS} steps of about {per_step:.2g} s on one core; other loads differ, stability.harmonics "
            f"takes about 3 times as long); a step costs more than N times a coarse mesh's, and on the default cap, "
            f"beyond N = 3200, rounding, which grows with N, moves the located points (w at F_max) more than the "
            f"finer mesh corrects them (docs/scenes.md)")


def shell_first_instability(records: list[dict[str, Any]], parameter: str, fields: tuple[str, ...]) -> dict[str, Any] | None:
    """``summary.json``'s ``first_instability``: the first fold in the control's ``parameter`` or the first
    bifurcation into a wave number ``n`` along the path (:func:`contin.app.scene.first_instability`), with
    ``kind``, ``n`` (None for a fold) and the load ``fields``; None when the path has neither."""
    from contin.app.scene import first_instability

    out = first_instability(records, parameter, fields)
    if out is not None:
        out.setdefault("n", None)
        out.pop("family", None)
    return out


def instability_text(summary: dict[str, Any], shown: tuple[tuple[str, str, str], ...], tex: bool = False) -> str:
    """What the status line (``tex`` false) or the diagram's title (``tex`` true) says of the path's first
    instability when the run watches the harmonics (empty when it does not).

    Parameters
    ----------
    summary : dict
        The run's summary, with ``first_instability`` and ``harmonics`` (:func:`record_instability`).
    shown : tuple of (field, plain name, TeX name)
        The loads to name it by, in the diagram's units, e.g. ``("w_over_R", "w/R", "w/R")``.
    tex : bool
        Write it for a matplotlib title (mathtext), shorter.
    """
    if "harmonics" not in summary:
        return ""
    first = summary.get("first_instability")
    if first is None:
        return ("no fold and no bifurcation into $n$ waves on the path" if tex else
                "first instability: none on the path (no fold under this control, no bifurcation into n waves)")

    def at(names: int) -> str:
        parts = [f"{tex_name if tex else plain} = {first[field]:.4g}" for field, plain, tex_name in shown[:names]
                 if first.get(field) is not None]
        return (" at $" + "$, $".join(parts) + "$") if tex and parts else (" at " + ", ".join(parts) if parts else "")
    if first["kind"] == "bifurcation":
        if tex:
            return f"first instability: $n = {first['n']}${at(1)}"
        waves = "1 circumferential wave" if first["n"] == 1 else f"{first['n']} circumferential waves"
        return (f"first instability: a bifurcation into {waves} (n = {first['n']}){at(len(shown))}, where the shell "
                f"leaves the axisymmetric path traced here")
    if tex:
        return f"first instability: the fold{at(1)}"
    return f"first instability: the fold{at(len(shown))} (no bifurcation into n waves before it)"


def record_instability(summary: dict[str, Any], records: list[dict[str, Any]], parameter: str,
                       fields: tuple[str, ...], problem: Any) -> None:
    """Put ``first_instability`` (:func:`shell_first_instability`) and, when the problem watches harmonics,
    ``harmonics`` (:func:`harmonic_summary`, its warning added to ``warnings``) into ``summary``."""
    summary["first_instability"] = shell_first_instability(records, parameter, fields)
    harmonics = harmonic_summary(problem, records)
    if harmonics is not None:
        summary["harmonics"] = harmonics
        if "warning" in harmonics:
            summary.setdefault("warnings", []).append(harmonics["warning"])


def record_fields(names: tuple[str, ...]) -> Any:
    """The scene's own fields of a special point's record (for :func:`contin.app.scene.special_point_records`):
    the observables ``names`` it has, its ``index`` and, when it declares one, the control it folds under
    (``stability_control``)."""
    def fields(spt: Any) -> dict[str, Any]:
        out: dict[str, Any] = {name: float(spt.observables[name]) for name in names if name in spt.observables}
        out["index"] = int(spt.index)
        if spt.info.get("stability_label") is not None:
            out["stability_control"] = spt.info["stability_label"]
        return out
    return fields


def harmonic_summary(problem: Any, records: list[dict[str, Any]]) -> dict[str, Any] | None:
    """``summary.json``'s ``harmonics``: ``n_max``, the number of bifurcations located, and a warning when one
    comes within 1 of ``n_max`` (the critical wave number must lie well inside the watched range; raise
    ``stability.n_max``).  None when the problem watches no harmonics."""
    families = getattr(problem, "operator_families", ())
    if not families:
        return None
    n_max = int(max(families[0].keys))
    ns = [r["n"] for r in records if r["kind"] == "bifurcation" and r.get("n") is not None]
    out: dict[str, Any] = {"n_max": n_max, "bifurcations": len(ns)}
    if ns and max(ns) >= n_max - 1:
        out["warning"] = (f"a bifurcation into n = {max(ns)} is at the edge of the watched range n <= {n_max}: "
                          f"modes beyond it may come first; raise stability.n_max")
    return out


def eversion_displacement(R: float, phi_hat: float) -> float:
    """Pole displacement ``2 R (1 - sin phi_hat)`` at which the pole reaches the mirror image of its start."""
    return 2.0 * R * (1.0 - math.sin(phi_hat))


#: ``branch.csv``'s stability columns (name -> the engine's :meth:`contin.Branch.columns` name): stability
#: under both controls, ``n_negative`` being the displacement control's Morse index.
STABILITY_COLUMNS = {"stable_force": "stable_force", "stable_displacement": "stable_displacement",
                     "n_negative": "n_negative_displacement", "n_negative_force": "n_negative_force"}
