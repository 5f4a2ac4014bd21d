"""Command-line scenes of the benchmark models (``contin trace --model bratu|truss``).

Each scene is a :class:`contin.app.scene.SceneModel` registered in the ``contin.models`` entry-point
group (see ``pyproject.toml``); the engine finds it only through that registry.  Importing this module
loads the schemas only (no numpy): the command line loads every registered model to print its help or
to refuse a scene; the models themselves are imported by the builders.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple

import contin
from contin.app.scene import Constraint, Field, SceneError, SceneModel, Schema, TraceResult, boolean, integer, real

if TYPE_CHECKING:
    import numpy as np

    from contin.app.restart import Start as SavedPoint

    from .bratu import Bratu
    from .truss import VonMisesTruss

__all__ = ["BRATU_SCENE", "TRUSS_SCENE", "Start", "build_bratu", "build_truss"]

Scene = dict[str, dict[str, Any]]


class Start(NamedTuple):
    """What a benchmark scene builds: the problem, its continuation settings and the starting point."""

    problem: contin.Problem
    settings: contin.Settings
    u0: np.ndarray
    p0: float


def _step_order(section: str = "continuation") -> Constraint:
    return Constraint((f"{section}.ds", f"{section}.ds_max"), lambda s: s[section]["ds"] <= s[section]["ds_max"],
                      f"{section}.ds <= {section}.ds_max")


#: Smallest ``continuation.tol``: a relative residual within a few round-offs of double precision
#: (2.2e-16) is no target a converged point can be held to (both benchmarks still converge at 1e-15 on
#: the grids tried, n = 200 and 20000, by luck of their conditioning; the shell stops at 1e-12).
TOL_FLOOR = 1e-14
_TOL_HELP = "relative residual tolerance (at least 1e-14: below that it is round-off of double precision)"


# ---- Bratu -----------------------------------------------------------------------------------------
#: Largest ``model.n``: five times the largest benchmarked grid (``studies.bench_bratu``, n = 200000); a
#: mistyped huge n would otherwise run for hours or fail allocating instead of being rejected.
MAX_GRID = 1_000_000


def _grid_ok(n: int) -> bool:
    return 2 <= n <= MAX_GRID


BRATU_SCHEMA = Schema(
    sections={
        "model": {"n": Field(int, 200, _grid_ok, f"an integer >= 2 and <= {MAX_GRID}", "interior grid points")},
        "continuation": {
            "ds": real(0.1, gt=0, help="initial arclength step"),
            "ds_max": real(0.2, gt=0, help="largest step"),
            "ds_min": real(1e-9, gt=0, help="smallest step before the run gives up"),
            "tol": real(1e-10, ge=TOL_FLOOR, lt=1, help=_TOL_HELP),
            "max_steps": integer(1000, low=1, high=100000, help="maximum number of steps"),
            "max_u": real(4.0, gt=0, help="stop when max(u) reaches this value"),
            "stability": boolean(True, help="count negative Hessian eigenvalues at every point"),
        },
    },
    constraints=[
        _step_order(),
        Constraint(("continuation.ds_min", "continuation.ds"),
                   lambda s: s["continuation"]["ds_min"] <= s["continuation"]["ds"],
                   "continuation.ds_min <= continuation.ds"),
    ],
)


def build_bratu(scene: Scene, progress: bool = False) -> Start:
    """The Bratu problem of a resolved :data:`BRATU_SCHEMA` scene, its settings and the trivial start."""
    import numpy as np

    from .bratu import Bratu

    c = scene["continuation"]
    problem = Bratu(scene["model"]["n"])
    st = contin.Settings(ds=c["ds"], ds_max=c["ds_max"], ds_min=c["ds_min"], tol=c["tol"], max_steps=c["max_steps"],
                         bounds={"max_u": (None, c["max_u"])}, stability=c["stability"], progress=progress)
    return Start(problem, st, np.zeros(problem.n), 0.0)


def _run_bratu(scene: Scene, progress: bool) -> TraceResult:
    problem, st, u0, p0 = build_bratu(scene, progress)
    return _bratu_result(problem, contin.continuation(problem, u0, p0, st))


def _resume_bratu(scene: Scene, start: SavedPoint, progress: bool) -> TraceResult:
    """The branch on from a saved point (``contin trace --from OUT --label K``), along its saved direction."""
    from contin.app.restart import continue_saved, resume

    problem, st, _, _ = build_bratu(scene, progress)
    (br,), _ = continue_saved(start, [resume(problem, start, st)])
    return _bratu_result(problem, br)


def _bratu_result(problem: Bratu, br: contin.Branch) -> TraceResult:
    from .bratu import LAMBDA_CRITICAL

    folds = br.folds()
    summary: dict[str, Any] = {"lambda_critical_continuum": LAMBDA_CRITICAL}
    if folds:
        summary["fold_lam"] = folds[0].p
        summary["fold_relative_error_vs_continuum"] = abs(folds[0].p - LAMBDA_CRITICAL) / LAMBDA_CRITICAL
    return TraceResult.from_branches([br], problem=problem, x="p", y="max_u", summary=summary)


BRATU_SCENE = SceneModel(
    name="bratu",
    description="1-D Bratu problem u'' + lam exp(u) = 0 on (0, 1): the branch from lam = 0 around its fold",
    schema=BRATU_SCHEMA,
    runner=_run_bratu,
    examples={"trace": (("--set model.n=50", "the fold at lam = 3.51 on a coarse grid"),)},
    resumer=_resume_bratu,
    restart_fixed=("model.n",),
)


# ---- von Mises truss ---------------------------------------------------------------------------------
TRUSS_SCHEMA = Schema(
    sections={
        "model": {
            "a": real(1.0, gt=0, help="half span"),
            "b": real(0.5, gt=0, help="initial apex height"),
            "k": real(1.0, gt=0, help="axial bar stiffness"),
        },
        "continuation": {
            "ds": real(0.05, gt=0, help="initial step, in units of b and the limit load"),
            "ds_max": real(0.2, gt=0, help="largest step (same units)"),
            "tol": real(1e-10, ge=TOL_FLOOR, lt=1, help=_TOL_HELP),
        },
        "load": {"cycle": boolean(False, help="load to the snap, unload to the snap back, reload (hysteresis "
                                              "loop) instead of tracing the whole S-curve")},
    },
    constraints=[
        _step_order(),
        Constraint(("model.a", "model.b"), lambda s: s["model"]["b"] / s["model"]["a"] < 2.4,
                   "model.b / model.a < 2.4",
                   "for steeper trusses the symmetric path has branch points where the truss sways sideways, which this "
                   "scene does not follow"),
    ],
)


def build_truss(scene: Scene, progress: bool = False) -> Start:
    """The truss of a resolved :data:`TRUSS_SCHEMA` scene, its settings and the unloaded start."""
    import numpy as np

    from .truss import VonMisesTruss

    m, c = scene["model"], scene["continuation"]
    problem = VonMisesTruss(m["a"], m["b"], m["k"])
    (_, p_max), _ = problem.limit_points()
    # weights make ds dimensionless: the apex moves by ~b and the load by ~P_max along the curve
    st = contin.Settings(ds=c["ds"], ds_max=c["ds_max"], tol=c["tol"], stability=True,
                         state_weight=np.sqrt(2) / m["b"], param_weight=1.0 / p_max, progress=progress,
                         bounds={"y": (-1.6 * m["b"], None)})
    return Start(problem, st, np.array([0.0, m["b"]]), 0.0)


def _run_truss(scene: Scene, progress: bool) -> TraceResult:
    problem, st, u0, _ = build_truss(scene, progress)
    (_, p_max), _ = problem.limit_points()
    summary = {"P_max_closed_form": p_max, "P_min_closed_form": -p_max}
    if not scene["load"]["cycle"]:
        br = contin.continuation(problem, u0, 0.0, st)
        return _s_curve(problem, br, summary)

    # load to the snap, unload to the snap back, reload to the first fold again: three sweeps of the
    # one load-snap loop, each without an end load (the folds end them)
    names = ["loading", "unloading", "reloading"]
    branches, jumps, failure = [], [], ""
    u, p = u0, 0.0
    for i, name in enumerate(names):
        last = i == len(names) - 1
        qs = contin.quasistatic(problem, u, p, None, st, direction=1 if i % 2 == 0 else -1,
                                max_snaps=0 if last else 1, stop_after_jump=lambda jr: "snapped")
        branches += qs.branches
        jumps += qs.jumps
        if qs.status != ("max_snaps" if last else "completed"):
            failure = f"{name} did not end at a fold and snap ({qs.message})"
            break
        u, p = qs.u_final, qs.p_final
    if not failure:
        G = contin.diagram(branches, jumps)
        summary["hysteresis_loops"] = len(contin.hysteresis_cycles(G))
    return TraceResult.from_branches(branches, jumps, problem=problem, x="deflection", y="p", summary=summary,
                                     labels=names[:len(branches)], failure=failure,
                                     table_observables=["y", "deflection"])


def _s_curve(problem: VonMisesTruss, br: contin.Branch, summary: dict[str, Any]) -> TraceResult:
    return TraceResult.from_branches([br], problem=problem, x="deflection", y="p", summary=summary,
                                     labels=["S-curve"], table_observables=["y", "deflection"])


def _resume_truss(scene: Scene, start: SavedPoint, progress: bool) -> TraceResult:
    """The S-curve on from a saved point (``contin trace --from OUT --label K``); the hysteresis loop is not resumed."""
    if scene["load"]["cycle"]:
        raise SceneError("load.cycle = true cannot be restarted from a saved point: the loop's three sweeps start "
                         "from the unloaded truss; restart the S-curve (load.cycle = false) or trace the loop anew",
                         "constraint")
    from contin.app.restart import continue_saved, resume

    problem, st, _, _ = build_truss(scene, progress)
    (_, p_max), _ = problem.limit_points()
    (br,), _ = continue_saved(start, [resume(problem, start, st)])
    return _s_curve(problem, br, {"P_max_closed_form": p_max, "P_min_closed_form": -p_max})


TRUSS_SCENE = SceneModel(
    name="truss",
    description="von Mises two-bar truss under a dead load: the S-curve with its two limit points, "
                "or the snap-through hysteresis loop",
    schema=TRUSS_SCHEMA,
    runner=_run_truss,
    examples={"trace": (("--set load.cycle=true", "the snap-through hysteresis loop"),)},
    resumer=_resume_truss,
)
