"""The scene schema of the shell with its loads (``contin trace --model shell``) and its geometry helpers.

Scene keys (public contract, ``--set section.key=value``)::

    [shell]         R, E, nu, h, phi_hat, N, pole_ratio (node spacing at the pole / elsewhere; 1 = uniform),
                    boundary = "sliding" | "pinned" | "clamped" (pinned and clamped: pressure scenes only)
    [load]          kind = "point" | "sphere" | "plate" | "pressure", radius (sphere),
                    control = "displacement" | "force" (pressure: the volume change dV = V0 - V | the pressure),
                    p_end_over_p_c (pressure, force control), dV_end_over_V0 (pressure, displacement control)
    [contact]       K_c, dhat (0: the paper's values scaled with E and R; sphere and plate only)
    [continuation]  ds, ds_max (units of R), tol, max_steps, overshoot
    [output]        figure
"""

from __future__ import annotations

import math
from typing import Any

from contin.scene import Constraint, Field, Schema, boolean, choice, integer, real
from contin_models.shell.pressure import BOUNDARIES

__all__ = ["SHELL_SCHEMA", "MAX_NODES", "MIN_NODES_PER_BENDING_LENGTH", "STABILITY_COLUMNS", "Scene", "eversion_displacement",
           "minimum_nodes", "nodes_per_bending_length"]

Scene = dict[str, dict[str, Any]]

#: Largest ``shell.N``: 125 times the finest mesh of the studies (N = 800).  The cost is linear in N, but
#: a mistyped huge N would otherwise run for hours or fail allocating instead of being rejected.
MAX_NODES = 100_000


def _nodes_ok(n: int) -> bool:
    return 10 <= n <= MAX_NODES


#: Nodes per bending length ``sqrt(R h)`` below which a scene is refused (``shell.N``).
MIN_NODES_PER_BENDING_LENGTH = 4

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
            "boundary": choice("sliding", BOUNDARIES,
                               help="support of the base edge: sliding (z fixed, r free: the paper's base), pinned "
                                    "(r and z fixed) or clamped (r, z and the edge rotation fixed); pinned and "
                                    "clamped only under load.kind = pressure"),
        },
        "load": {
            "kind": choice("point", ("point", "sphere", "plate", "pressure"),
                           help="indenter: a point at the pole (bilateral), or a rigid sphere or plate through the "
                                "log-barrier contact; or a uniform external pressure p on the cap"),
            "radius": real(0.5, gt=0, help="sphere radius [m] (load.kind = sphere)"),
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
        Constraint(("shell.N", "shell.h", "shell.R", "shell.phi_hat"),
                   lambda s: s["shell"]["h"] >= s["shell"]["R"] or s["shell"]["N"] >= minimum_nodes(s["shell"]),
                   f"shell.N >= {MIN_NODES_PER_BENDING_LENGTH} (pi/2 - phi_hat) / sqrt(h/R)",
                   f"a snapping cap bends over the length sqrt(R h); with fewer than {MIN_NODES_PER_BENDING_LENGTH} "
                   "nodes over it the discrete path winds through spurious folds and snaps (random scenes below "
                   "the rule failed 12 times in 15, studies/fuzz.py); refine the mesh"),
        Constraint(("shell.boundary", "load.kind"),
                   lambda s: s["shell"]["boundary"] == "sliding" or s["load"]["kind"] == "pressure",
                   'shell.boundary = "sliding" unless load.kind = "pressure" (pressure scenes take "sliding", '
                   '"pinned" or "clamped")',
                   "the point, sphere and plate scenes are built on the paper's sliding base (z fixed, r free); "
                   "a pinned or clamped edge exists so far only for the pressure-loaded cap. Drop shell.boundary "
                   "or set shell.boundary=sliding"),
    ],
)


def nodes_per_bending_length(shell: dict[str, Any], N: int | None = None) -> float:
    """How many nodes the meridian's mean spacing puts over the bending length ``sqrt(R h)``.

    Parameters
    ----------
    shell : dict
        The scene's ``[shell]`` section (``R``, ``h``, ``phi_hat`` and, unless ``N`` is given, ``N``).
    N : int, optional
        A number of nodes other than the scene's.
    """
    arc = shell["R"] * (math.pi / 2 - shell["phi_hat"])  # the meridian's length
    return (shell["N"] if N is None else N) * math.sqrt(shell["R"] * shell["h"]) / arc


def minimum_nodes(shell: dict[str, Any]) -> int:
    """Fewest nodes that put :data:`MIN_NODES_PER_BENDING_LENGTH` nodes over the bending length ``sqrt(R h)``.

    Parameters
    ----------
    shell : dict
        The scene's ``[shell]`` section (``R``, ``h``, ``phi_hat``).
    """
    return math.ceil(MIN_NODES_PER_BENDING_LENGTH / nodes_per_bending_length(shell, N=1) - 1e-9)


def eversion_displacement(R: float, phi_hat: float) -> float:
    """Pole displacement ``2 R (1 - sin phi_hat)`` at which the pole reaches the mirror image of its start."""
    return 2.0 * R * (1.0 - math.sin(phi_hat))


#: ``branch.csv``'s stability columns (name -> the engine's :meth:`contin.Branch.columns` name): stability
#: under both controls, ``n_negative`` being the displacement control's Morse index.
STABILITY_COLUMNS = {"stable_force": "stable_force", "stable_displacement": "stable_displacement",
                     "n_negative": "n_negative_displacement", "n_negative_force": "n_negative_force"}
