"""The paper's phase diagram on the paths the caps take in three dimensions, beside the axisymmetric one.

Run ``python -m studies.phase_diagram_3d [--out DIR] [--full] [--workers N | --scheduler ADDRESS] [--quiet]
[--replot]``.  ``docs/three_d.md`` (section 2) states the numbers and the conclusions; this docstring says what is
computed.

The paper's caps (``nu = 0.5``, the sliding edge, a point force at the pole under displacement control) are classified
monotonous, monostable or bistable (``docs/model.md#classes``) twice from one run each: on the axisymmetric path, and on
the path the cap takes (``stability.follow = true``: it leaves the axisymmetric path at the first bifurcation into the
branch that carries on, snaps where that branch ends and lands on the next stable state, in any symmetry).

1. **The grid.**  Every cell of a grid in ``(phi_hat, h/R)`` is classified both ways by ``contin classify``'s sweep
   (:mod:`contin.app.sweep`: local processes, or a Dask cluster with ``--scheduler``; resumable through ``grid.csv``).
   Per cell: both classes, both force minima, the first bifurcation (its wave number, where it lies, whether before the
   force maximum), the snaps of the followed path.
2. **The boundaries on the followed paths, located.**  At a few ``phi_hat`` the depth ``lambda`` where the followed
   class changes (bistable / monostable, monostable / monotonous) is bisected, each evaluation a run of the cap, and
   compared with the axisymmetric boundaries that :mod:`contin_models.shell.boundaries` traces as curves by fold
   continuation (the route of ``studies.phase_diagram``).  Beside them, by the same bisection, where the first
   bifurcation moves ahead of the force maximum (the boundary that ``studies.asymmetric_boundary`` continues as a
   curve, ``lambda`` about 10.1).
3. **Resolution** (``--full``): the located followed boundary at a finer mesh and with more harmonics, and the
   followed force minimum of two bistable caps against the harmonics ``K`` (one-wave branches need many).

The default run is small (a 3 x 3 grid at ``N = 60``, ``K = 2``, the bistable boundary at one ``phi_hat`` to 1 %);
``--full`` runs a 10 x 7 grid at ``N = 80``, ``K = 3``, the boundaries at four ``phi_hat`` (five for the bifurcation) to
1e-3, and the checks.
Writes ``grid.csv``, ``boundaries.csv``, ``checks.csv``, ``summary.json``, ``plot_data.json`` (``--replot`` draws
the figure again from it) and ``phase_diagram_3d.png`` / ``.pdf``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from studies._common import (executor_from_args, output_dir, print_table, run_study, save_figure, say,  # noqa: E402
                             study_parser, write_csv, write_json)

#: The paper's Poisson ratio.
NU = 0.5
#: The grid of the default run and of ``--full`` (``phi_hat`` values, ``h/R`` values), the mesh ``N`` and the
#: harmonics ``K`` of the views.
FAST = {"phis": (0.7, 1.0, 1.3), "hs": (0.015, 0.03, 0.06), "N": 60, "K": 2}
FULL = {"phis": tuple(np.round(np.linspace(0.5, 1.45, 10), 4)), "hs": tuple(np.round(np.geomspace(0.008, 0.15, 7), 5)),
        "N": 80, "K": 3}
#: Where the boundaries are located, and to what relative width of the bracket in ``lambda``.
FAST_BOUNDARIES = {"phis": {"bistable": (1.0,)}, "tol": 1e-2}
#: (The class boundaries are not located at ``phi_hat = 0.6``: there they lie at ``h/R`` of 0.09 to 0.15, where the
#: followed runs stop at bifurcations of the pole's few nodes under the point force, beyond the model's strains.)
FULL_BOUNDARIES = {"phis": {"bistable": (0.8, 1.0, 1.2, 1.4), "monotonous": (0.8, 1.0, 1.2, 1.4),
                            "bifurcation": (0.6, 0.8, 1.0, 1.2, 1.4)}, "tol": 1e-3}
#: The brackets in ``lambda`` the bisections start from: around this model's axisymmetric boundaries (5.7 and 3.8,
#: ``docs/reproduction.md``) and the bifurcation boundary (10.1, ``docs/model.md``), wide enough to hold the followed
#: ones if they moved.
BRACKETS = {"bistable": (5.0, 6.6), "monotonous": (3.3, 4.4), "bifurcation": (9.0, 11.5)}
#: The resolution checks of ``--full``: the bistable boundary at ``phi_hat = 1`` on ``(N, K)``, and the followed
#: force minimum of two bistable caps (``phi_hat = 1``, ``lambda``) against ``K`` at ``N = 80``.
BOUNDARY_CHECKS = ((160, 3), (80, 6))
MINIMUM_CHECKS = {"lambdas": (8.0, 12.0), "Ks": (3, 6, 10)}

CLASSES = ("monotonous", "monostable", "bistable")


def h_of_lambda(phi_hat: float, lam: float, nu: float = NU) -> float:
    """``h/R`` of the cap of base angle ``phi_hat`` with depth parameter ``lam``
    (``lambda = (12 (1 - nu^2))^(1/4) (pi/2 - phi_hat) / sqrt(h/R)``)."""
    return ((12.0 * (1.0 - nu * nu)) ** 0.25 * (math.pi / 2 - phi_hat) / lam) ** 2


def lambda_of(phi_hat: float, h_over_R: float, nu: float = NU) -> float:
    """The depth parameter of a cap (the inverse of :func:`h_of_lambda`)."""
    return (12.0 * (1.0 - nu * nu)) ** 0.25 * (math.pi / 2 - phi_hat) / math.sqrt(h_over_R)


def scene_sets(N: int, K: int, follow: bool = True) -> list[str]:
    """The scene keys every cap of the study shares (the paper's cap but ``phi_hat`` and ``h``)."""
    return [f"shell.N={N}", f"shell.nu={NU}", "shell.R=1.0", "stability.harmonics=true",
            f"stability.follow={'true' if follow else 'false'}", f"view.harmonics={K}", "output.figure=false"]


def axisymmetric_class(values: dict[str, Any]) -> str | None:
    """The class of the axisymmetric path from its force extrema (``docs/model.md#classes``): no maximum, monotonous;
    a least force below zero after it, bistable; else monostable (None: the path was not complete)."""
    if not values.get("path_complete"):
        return None
    if values.get("F_max_norm") in (None, ""):
        return "monotonous"
    return "bistable" if float(values["F_min_norm"]) < 0.0 else "monostable"


def cell_row(values: dict[str, Any], phi_hat: float, h_over_R: float, label: str | None, failure: str = "") -> dict[str, Any]:
    """One cap's row: both classes, both minima, the first bifurcation and whether it comes before ``F_max``."""
    def num(key: str) -> float | None:
        v = values.get(key)
        return None if v in (None, "") else float(v)

    w_b, w_max = num("first_bifurcation_w_over_R"), num("w_at_F_max_over_R")
    n = num("first_bifurcation_n")
    axi = axisymmetric_class(values)
    return {"phi_hat": phi_hat, "h_over_R": h_over_R, "lambda": lambda_of(phi_hat, h_over_R),
            "axi_class": axi, "followed_class": label or None, "differs": bool(label and axi and label != axi),
            "axi_F_max": num("F_max_norm"), "axi_F_min": num("F_min_norm"),
            "followed_F_max": num("followed_F_max_norm"), "followed_F_min": num("followed_F_min_norm"),
            "first_n": None if n is None else int(n), "first_w": w_b, "first_F": num("first_bifurcation_F_norm"),
            "bifurcates_before_F_max": None if (w_b is None or w_max is None) else bool(w_b < w_max),
            "snaps": num("followed_n_snaps"), "left_axisymmetric": values.get("followed_left_axisymmetric"),
            "failure": failure}


def classify_grid(grid: dict[str, Any], csv_path: Any, executor: Any, progress: bool) -> list[dict[str, Any]]:
    """Classify every cell of ``grid`` on both paths through the sweep (resumable through ``csv_path``)."""
    from contin.app.sweep import run_sweep, sweep_scenes
    from contin_models.shell_scene import SHELL_SCHEMA

    combos = sweep_scenes(SHELL_SCHEMA, [("shell.phi_hat", [float(p) for p in grid["phis"]]),
                                         ("shell.h", [float(h) for h in grid["hs"]])],
                          overrides=scene_sets(grid["N"], grid["K"]))
    raw = run_sweep("shell", combos, csv_path=csv_path, progress=progress, executor=executor)
    return [cell_row(r, float(r["shell.phi_hat"]), float(r["shell.h"]), r.get("label"), r.get("failure") or "")
            for r in raw]


def classify_cap(phi_hat: float, lam: float, N: int, K: int, follow: bool = True) -> dict[str, Any]:
    """Classify one cap of depth ``lam`` on both paths in this process (:func:`cell_row`).

    Raises
    ------
    RuntimeError
        When the run does not decide the class it is asked for (a path cut short).
    """
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import classify_scene

    h = h_of_lambda(phi_hat, lam)
    scene = load_scene(SHELL_SCHEMA, None, [f"shell.phi_hat={phi_hat}", f"shell.h={h!r}", *scene_sets(N, K, follow)])
    c = classify_scene(scene)
    row = cell_row(c.values, phi_hat, h, c.label if follow else None, c.failure)
    if (follow and row["followed_class"] is None) or row["axi_class"] is None:
        raise RuntimeError(f"phase_diagram_3d: the cap phi_hat = {phi_hat}, lambda = {lam:.6g} (N = {N}, K = {K}) "
                           f"was not classified: {c.failure}")
    return row


#: What each located boundary separates, as a test on a cap's row that holds on the deep (large lambda) side.
SIDES: dict[str, tuple[Callable[[dict[str, Any]], bool], bool]] = {
    "bistable": (lambda r: r["followed_class"] == "bistable", True),
    "monotonous": (lambda r: r["followed_class"] != "monotonous", True),
    "bifurcation": (lambda r: bool(r["bifurcates_before_F_max"]), False),
}
#: The same test on the axisymmetric path, where the boundary has one.
AXI_SIDES: dict[str, Callable[[dict[str, Any]], bool]] = {
    "bistable": lambda r: r["axi_class"] == "bistable",
    "monotonous": lambda r: r["axi_class"] != "monotonous",
}


def locate_boundary(kind: str, phi_hat: float, N: int, K: int, tol: float) -> dict[str, Any]:
    """Bisect ``lambda`` at ``phi_hat`` for where the test of ``kind`` (:data:`SIDES`) changes, until the bracket is
    narrower than ``tol`` relative; the axisymmetric test is read from the same runs (its bracket, where it has one).

    Raises
    ------
    RuntimeError
        When the test does not change across :data:`BRACKETS` (the boundary is not where it is looked for).
    """
    test, follow = SIDES[kind]
    lo, hi = BRACKETS[kind]
    runs: list[dict[str, Any]] = []

    def run(lam: float) -> dict[str, Any]:
        row = classify_cap(phi_hat, lam, N, K, follow=follow)
        runs.append(row)
        return row

    r_lo, r_hi = run(lo), run(hi)
    if test(r_lo) or not test(r_hi):
        raise RuntimeError(f"phase_diagram_3d: the {kind} boundary at phi_hat = {phi_hat} is not within lambda = "
                           f"{lo} .. {hi} (N = {N}, K = {K})")
    while (hi - lo) > tol * hi:
        mid = 0.5 * (lo + hi)
        if test(run(mid)):
            hi = mid
        else:
            lo = mid
    out = {"kind": kind, "phi_hat": phi_hat, "N": N, "K": K, "lambda_lo": lo, "lambda_hi": hi,
           "lambda": 0.5 * (lo + hi), "h_over_R": h_of_lambda(phi_hat, 0.5 * (lo + hi)), "runs": len(runs)}
    if kind in AXI_SIDES:  # the axisymmetric class's change within the same runs: its own bracket
        axi = AXI_SIDES[kind]
        below = [r["lambda"] for r in runs if not axi(r)]
        above = [r["lambda"] for r in runs if axi(r)]
        out["axi_lambda_lo"] = max(below) if below else None
        out["axi_lambda_hi"] = min(above) if above else None
    return out


def traced_lambda(curve: Any, phi_hat: float) -> float:
    """``lambda`` on a traced axisymmetric boundary at ``phi_hat`` (linear in ``phi_hat`` between its points)."""
    phi = np.asarray(curve.phi_hat, dtype=float)
    order = np.argsort(phi)
    return float(np.interp(phi_hat, phi[order], np.asarray(curve.lam, dtype=float)[order]))


def minimum_checks(N: int, progress: bool, quiet: bool) -> list[dict[str, Any]]:
    """The followed force minimum of bistable caps at ``phi_hat = 1`` against the harmonics (:data:`MINIMUM_CHECKS`)."""
    rows = []
    for lam in MINIMUM_CHECKS["lambdas"]:
        for K in MINIMUM_CHECKS["Ks"]:
            t0 = time.perf_counter()
            try:
                r = classify_cap(1.0, lam, N, K)
            except RuntimeError as exc:
                rows.append({"check": "F_min", "phi_hat": 1.0, "lambda": lam, "N": N, "K": K, "failure": str(exc)})
                say(quiet, f"  lambda = {lam}, K = {K}: {exc}")
                continue
            rows.append({"check": "F_min", "phi_hat": 1.0, "lambda": lam, "N": N, "K": K,
                         "followed_class": r["followed_class"], "axi_F_min": r["axi_F_min"],
                         "followed_F_min": r["followed_F_min"], "time_s": round(time.perf_counter() - t0, 2)})
            say(quiet, f"  lambda = {lam}, K = {K}: followed F_min = {r['followed_F_min']:.5g} "
                       f"(axisymmetric {r['axi_F_min']:.5g})")
    return rows


CLASS_COLOURS = {"monotonous": "#56B4E9", "monostable": "#E69F00", "bistable": "#009E73", None: "#999999"}


def plot(data: dict[str, Any]) -> Any:
    """Two panels: (a) the plane with the traced axisymmetric boundaries, the grid's followed classes (ringed in red
    where they differ from the axisymmetric class; a cross where the first bifurcation comes before ``F_max``) and
    the located followed boundaries; (b) the followed force minimum over the axisymmetric one against ``lambda``."""
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12.5, 5.6), gridspec_kw={"width_ratios": [1.25, 1]})
    for kind, c in data["curves"].items():
        ax.plot(c["phi_hat"], c["h_over_R"], color="k", lw=1.2, ls="-" if kind == "bistable" else "--",
                label=f"axisymmetric {'bistable / monostable' if kind == 'bistable' else 'monostable / monotonous'}")
    for row in data["grid"]:
        colour = CLASS_COLOURS.get(row["followed_class"], "#999999")
        ax.scatter(row["phi_hat"], row["h_over_R"], s=70, color=colour, zorder=3,
                   edgecolors="#D00000" if row["differs"] else "none", linewidths=2.0)
        if row["bifurcates_before_F_max"] and row["axi_F_max"] is not None:
            ax.scatter(row["phi_hat"], row["h_over_R"], s=22, marker="x", color="k", zorder=4, linewidths=1.0)
    markers = {"bistable": "D", "monotonous": "s", "bifurcation": "^"}
    for kind in markers:
        pts = [b for b in data["boundaries"] if b["kind"] == kind and b["K"] == data["K"] and b["N"] == data["N"]
               and "lambda" in b]
        if pts:
            ax.plot([b["phi_hat"] for b in pts], [b["h_over_R"] for b in pts], markers[kind], color="k", ms=6,
                    mfc="white", mew=1.3, ls=":" if kind == "bifurcation" else "none", zorder=5,
                    label={"bistable": "followed bistable / monostable, located",
                           "monotonous": "followed monostable / monotonous, located",
                           "bifurcation": "first bifurcation before $F_{max}$, located"}[kind])
    for name, colour in CLASS_COLOURS.items():
        ax.scatter([], [], s=50, color=colour, label=f"followed: {name or 'not classified'}")
    ax.scatter([], [], s=50, color="white", edgecolors="#D00000", linewidths=2.0, label="class differs")
    ax.scatter([], [], s=22, marker="x", color="k", label="bifurcates before $F_{max}$")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\hat\phi$")
    ax.set_ylabel(r"$h/R$")
    ax.set_title(f"(a) classes on the followed paths (N = {data['N']}, K = {data['K']})")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.62, -0.13), ncol=3, frameon=False)
    rows = [r for r in data["grid"] if r["axi_class"] == "bistable" and r["followed_F_min"] is not None]
    sc = bx.scatter([r["lambda"] for r in rows], [r["followed_F_min"] / r["axi_F_min"] for r in rows],
                    c=[r["phi_hat"] for r in rows], cmap="viridis", s=30, zorder=3)
    checks = [c for c in data.get("minimum_checks", []) if "followed_F_min" in c]
    for K, marker in zip(sorted({c["K"] for c in checks}), ("_", "x", "+", "1", "2")):
        cs = [c for c in checks if c["K"] == K]
        bx.plot([c["lambda"] for c in cs], [c["followed_F_min"] / c["axi_F_min"] for c in cs], marker, color="k",
                ms=11, mew=1.4, ls="none", label=f"$\\hat\\phi$ = 1, K = {K}")
    if checks:
        bx.legend(fontsize=7, loc="upper right", title="checks in the harmonics", title_fontsize=7)
    fig.colorbar(sc, ax=bx, label=r"$\hat\phi$")
    bx.axhline(1.0, color="0.6", lw=0.8)
    bx.set_ylim(0.0, 1.1)
    bx.set_xlabel(r"$\lambda$")
    bx.set_ylabel(r"$F_{min}$ followed / $F_{min}$ axisymmetric")
    bx.set_title("(b) how much of the pull-back force the real path keeps")
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("phase_diagram_3d", __doc__.splitlines()[0], executor_options=True)
    parser.add_argument("--replot", action="store_true", help="draw the figure again from DIR/plot_data.json")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    if args.replot:
        path = out / "plot_data.json"
        if not path.exists():
            print(f"error: --replot: no {path}: run the study with --out {out} first", file=sys.stderr)
            return 2
        save_figure(plot(json.loads(path.read_text())), out, "phase_diagram_3d")
        return 0
    from studies.phase_diagram import trace_boundaries

    grid = FULL if args.full else FAST
    where = FULL_BOUNDARIES if args.full else FAST_BOUNDARIES
    N, K = grid["N"], grid["K"]
    times: dict[str, float] = {}

    say(args.quiet, f"phase_diagram_3d: the axisymmetric boundaries by fold continuation (N = {N})")
    t0 = time.perf_counter()
    curves = trace_boundaries(N)
    times["axisymmetric_boundaries"] = time.perf_counter() - t0

    say(args.quiet, f"classifying the {len(grid['phis'])} x {len(grid['hs'])} grid on both paths (N = {N}, K = {K})")
    t0 = time.perf_counter()
    with executor_from_args(args) as executor:
        cells = classify_grid(grid, out / "grid.csv", executor, progress=not args.quiet)
    times["grid"] = time.perf_counter() - t0
    write_csv(out / "grid_classes.csv", cells)

    say(args.quiet, "locating the boundaries on the followed paths by bisection in lambda")
    t0 = time.perf_counter()
    boundaries = []
    for kind, phis in where["phis"].items():
        for phi in phis:
            try:
                b = locate_boundary(kind, phi, N, K, where["tol"])
            except RuntimeError as exc:  # a run that decides nothing: the boundary is not located there, and why
                boundaries.append({"kind": kind, "phi_hat": phi, "N": N, "K": K, "failure": str(exc)})
                say(args.quiet, f"  {kind} at phi_hat = {phi}: not located: {exc}")
                continue
            if kind in ("bistable", "monotonous"):
                b["traced_axi_lambda"] = traced_lambda(curves[kind], phi)
            boundaries.append(b)
            say(args.quiet, f"  {kind} at phi_hat = {phi}: lambda = {b['lambda_lo']:.6g} .. {b['lambda_hi']:.6g}"
                            + (f" (axisymmetric, traced: {b['traced_axi_lambda']:.6g})" if "traced_axi_lambda" in b
                               else ""))
    times["boundaries"] = time.perf_counter() - t0

    checks: list[dict[str, Any]] = []
    if args.full:
        say(args.quiet, "resolution checks")
        t0 = time.perf_counter()
        for n_check, k_check in BOUNDARY_CHECKS:
            try:
                b = locate_boundary("bistable", 1.0, n_check, k_check, where["tol"])
            except RuntimeError as exc:
                boundaries.append({"kind": "bistable", "phi_hat": 1.0, "N": n_check, "K": k_check, "failure": str(exc)})
                say(args.quiet, f"  bistable at phi_hat = 1, N = {n_check}, K = {k_check}: not located: {exc}")
                continue
            b["traced_axi_lambda"] = traced_lambda(curves["bistable"], 1.0)
            boundaries.append(b)
            say(args.quiet, f"  bistable at phi_hat = 1, N = {n_check}, K = {k_check}: lambda = "
                            f"{b['lambda_lo']:.6g} .. {b['lambda_hi']:.6g}")
        checks = minimum_checks(N, not args.quiet, args.quiet)
        times["checks"] = time.perf_counter() - t0
    write_csv(out / "boundaries.csv", boundaries)
    write_csv(out / "checks.csv", checks)

    decided = [c for c in cells if c["followed_class"] is not None and c["axi_class"] is not None]
    bistable = [c for c in decided if c["axi_class"] == "bistable"]
    # a followed path cut short after its force fell below zero is bistable with its least force unknown
    ratios = [c["followed_F_min"] / c["axi_F_min"] for c in bistable if c["followed_F_min"] is not None]
    summary = {
        "nu": NU, "N": N, "K": K, "grid": {"phi_hat": list(grid["phis"]), "h_over_R": list(grid["hs"])},
        "cells": len(cells), "classified_both_ways": len(decided),
        "not_classified": [{k: c[k] for k in ("phi_hat", "h_over_R", "lambda", "axi_class", "failure")}
                           for c in cells if c not in decided],
        "class_differs": [{k: c[k] for k in ("phi_hat", "h_over_R", "lambda", "axi_class", "followed_class")}
                          for c in decided if c["differs"]],
        "axisymmetric_bistable_cells": len(bistable),
        "of_them_bistable_followed": sum(c["followed_class"] == "bistable" for c in bistable),
        "left_axisymmetric": sum(bool(c["left_axisymmetric"]) for c in decided),
        "F_min_ratio_range": [min(ratios), max(ratios)] if ratios else None,
        "boundaries": boundaries, "checks": checks, "wall_time_s": times,
    }
    write_json(out / "summary.json", summary)
    print_table(cells, ["phi_hat", "h_over_R", "lambda", "axi_class", "followed_class", "axi_F_min", "followed_F_min",
                        "first_n", "first_w", "bifurcates_before_F_max", "snaps"])
    print_table(boundaries, ["kind", "phi_hat", "N", "K", "lambda_lo", "lambda_hi", "traced_axi_lambda",
                             "axi_lambda_lo", "axi_lambda_hi", "runs", "failure"])
    if checks:
        print_table(checks, ["lambda", "K", "followed_class", "axi_F_min", "followed_F_min", "time_s", "failure"])
    data = {"N": N, "K": K, "grid": cells, "boundaries": boundaries, "minimum_checks": checks,
            "curves": {kind: {"phi_hat": [float(x) for x in c.phi_hat], "h_over_R": [float(x) for x in c.h_over_R]}
                       for kind, c in curves.items()}}
    write_json(out / "plot_data.json", data)
    save_figure(plot(data), out, "phase_diagram_3d")
    say(args.quiet, f"{len(decided)} of {len(cells)} cells classified both ways; the class differs in "
                    f"{len(summary['class_differs'])}; {summary['of_them_bistable_followed']} of "
                    f"{len(bistable)} axisymmetric-bistable cells stay bistable")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
