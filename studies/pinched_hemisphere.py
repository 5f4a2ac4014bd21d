"""The pinched open hemisphere (Sze, Liu & Lo 2004) in the shell's 3-D view.

Run ``python -m studies.pinched_hemisphere [--out DIR] [--full] [--quiet]``.

The benchmark (K. Y. Sze, X. H. Liu, S. H. Lo, "Popular benchmark problems for geometric nonlinear
analysis of shells", *Finite Elements in Analysis and Design* 40 (2004) 1551-1569): a hemisphere of
radius 10 with an 18 degree hole at its top, thickness 0.04, E = 6.825e7, nu = 0.3, every edge free,
pinched by four radial point forces on its equator, outward at 0 and 180 degrees and inward at 90 and
270 degrees, each of magnitude P up to 400.  The paper tabulates the radial displacement of an
outward-loaded point and of an inward-loaded point along the load (:data:`REFERENCE`).

The load pattern has the symmetry ``D_2`` (half-turns and the mirrors through the loaded points), so
the 3-D view runs in the ``D_2`` basis: waves ``0, 2, ..., 2 K`` in the angle, ``N`` rings along the
meridian from the equator (node 0) to the hole.  Each mesh traces P from 0 to 400 with the four forces
as dead loads; the study interpolates both displacements at the tabulated loads and reports their
differences from the paper, and, to show that the meshes converge, the change from one mesh to the
next.  Outputs in ``--out`` (default ``out/pinched_hemisphere``): ``pinched_hemisphere.csv`` (every
mesh at every tabulated load), ``summary.json``, and the figures ``curves`` (load against both
displacements, each mesh and the paper's points) and ``shape`` (the finest mesh's shell at P = 400).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

#: Radius, hole (degrees from the axis), thickness, Young's modulus, Poisson's ratio, largest load.
RADIUS, HOLE_DEG, THICKNESS, E, NU, P_MAX = 10.0, 18.0, 0.04, 6.825e7, 0.3, 400.0

#: Sze, Liu & Lo (2004), the open hemisphere's table: ``P / P_max``, the outward radial displacement of
#: a point pulled outward, the inward radial displacement of a point pushed inward.
REFERENCE = np.array([
    [0.05, 0.855, 0.955], [0.10, 1.499, 1.840], [0.15, 1.969, 2.604], [0.20, 2.321, 3.261],
    [0.25, 2.596, 3.833], [0.30, 2.819, 4.339], [0.35, 3.002, 4.790], [0.40, 3.158, 5.196],
    [0.45, 3.291, 5.565], [0.50, 3.406, 5.902], [0.55, 3.508, 6.212], [0.60, 3.598, 6.497],
    [0.65, 3.678, 6.761], [0.70, 3.750, 7.006], [0.75, 3.816, 7.234], [0.80, 3.875, 7.448],
    [0.85, 3.929, 7.647], [0.90, 3.979, 7.835], [0.95, 4.025, 8.011], [1.00, 4.067, 8.178]])

#: ``(N, K)``: rings along the meridian and harmonics of the ``D_2`` basis (waves up to ``2 K``), both
#: refined together (``N = 16 f``, ``K = 6 f``); the full run refines by a constant ratio (1.5), so that
#: the three meshes give an observed order of convergence.
FAST_MESHES = ((32, 12), (40, 15), (48, 18))
FULL_MESHES = ((32, 12), (48, 18), (72, 27))


def hemisphere(N: int, K: int) -> Any:
    """The benchmark as a :class:`contin_models.shell.problem3d.Shell3D` on ``N`` rings and ``K`` harmonics."""
    from contin_models.shell.fourier import AngularBasis
    from contin_models.shell.meridian import SphericalArc, meridian
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellStructure

    arc = SphericalArc(RADIUS, 0.0, math.radians(90.0 - HOLE_DEG))  # equator (node 0) to the hole
    st = ShellStructure(meridian([arc], N, 1.0), E, NU, THICKNESS, boundary="free")
    half = 0.5 * math.pi
    forces = [(0, 0.0, (1.0, 0.0, 0.0)), (0, math.pi, (-1.0, 0.0, 0.0)),
              (0, half, (0.0, -1.0, 0.0)), (0, 3.0 * half, (0.0, 1.0, 0.0))]
    return Shell3D(st, AngularBasis(2, K), "forces", forces=forces)


def trace(N: int, K: int) -> dict[str, Any]:
    """Trace ``P`` from 0 to :data:`P_MAX` on one mesh; the displacements at the tabulated loads."""
    prob = hemisphere(N, K)
    t0 = time.perf_counter()
    br = contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=P_MAX, ds=5.0, ds_max=40.0,
                             max_steps=2000)
    seconds = time.perf_counter() - t0
    if br.status != "bound":
        raise RuntimeError(f"pinched hemisphere N = {N}, K = {K}: the trace stopped before P = {P_MAX:g}: "
                           f"{br.message}")
    P = np.asarray(br.p, dtype=float)
    u_out, u_in = np.asarray(br.observable("u0")), np.asarray(br.observable("u2"))
    loads = REFERENCE[:, 0] * P_MAX
    return {"N": N, "K": K, "unknowns": prob.n, "seconds": seconds, "points": len(P), "P": P, "u_out": u_out,
            "u_in": u_in, "at_out": np.interp(loads, P, u_out), "at_in": np.interp(loads, P, u_in), "problem": prob,
            "state": prob.full_state(br.u[-1], float(P[-1]))}


def rows_of(runs: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per mesh and tabulated load: both displacements, their differences from the paper (%)."""
    rows = []
    for r in runs:
        for k, (frac, ref_out, ref_in) in enumerate(REFERENCE):
            rows.append({"N": r["N"], "K": r["K"], "P": frac * P_MAX, "u_out": float(r["at_out"][k]),
                         "u_out_ref": ref_out, "err_out_pct": 100.0 * (r["at_out"][k] - ref_out) / ref_out,
                         "u_in": float(r["at_in"][k]), "u_in_ref": ref_in,
                         "err_in_pct": 100.0 * (r["at_in"][k] - ref_in) / ref_in})
    return rows


def curves_figure(runs: Sequence[dict[str, Any]]) -> Any:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.2, 4.4))
    shades = np.linspace(0.75, 0.0, len(runs))
    for r, g in zip(runs, shades):
        c = (g, g, g)
        ax.plot(r["u_out"], r["P"], color=c, lw=1.4, label=f"N = {r['N']}, waves to {2 * r['K']}")
        ax.plot(r["u_in"], r["P"], color=c, lw=1.4, ls="--")
    ax.plot(REFERENCE[:, 1], REFERENCE[:, 0] * P_MAX, "o", mfc="none", mec="C3", ms=5,
            label="Sze, Liu & Lo (2004)")
    ax.plot(REFERENCE[:, 2], REFERENCE[:, 0] * P_MAX, "s", mfc="none", mec="C0", ms=5)
    ax.set_xlabel("radial displacement of the loaded point")
    ax.set_ylabel("P")
    ax.text(2.3, 260, "pulled outward\n(solid, circles)", ha="center", fontsize=8)
    ax.text(6.9, 150, "pushed inward\n(dashed, squares)", ha="center", fontsize=8)
    ax.set_xlim(0.0, None)
    ax.set_ylim(0.0, P_MAX * 1.02)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("Pinched open hemisphere: the 3-D view (D$_2$ basis)", fontsize=10)
    fig.tight_layout()
    return fig


def shape_figure(run: dict[str, Any]) -> Any:
    import matplotlib.pyplot as plt

    view, c = run["problem"].view, run["state"]
    theta = np.linspace(0.0, 2.0 * math.pi, 145)
    X = view.points(c, theta)                    # (N, angles, 3)
    X0 = view.points(view.reference_state(), theta)
    loaded = view.points(c, np.array([0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi]))[0]
    fig = plt.figure(figsize=(9.0, 4.4))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ax.plot_surface(X[..., 0], X[..., 1], X[..., 2], color="0.8", edgecolor="0.35", lw=0.2, rstride=2, cstride=4,
                    shade=True)
    ax.set_box_aspect(tuple(np.ptp(X.reshape(-1, 3), axis=0)))  # one scale on every axis
    ax.view_init(elev=22, azim=-58)
    ax.set_axis_off()
    ax.set_title("(a) the shell at P = 400", fontsize=10)
    top = fig.add_subplot(1, 2, 2)
    top.plot(X0[0, :, 0], X0[0, :, 1], color="C0", lw=0.9, ls="--", label="equator, unloaded")
    top.plot(X0[-1, :, 0], X0[-1, :, 1], color="C0", lw=0.9, ls=":", label="hole, unloaded")
    for i in range(0, X.shape[0], 4):
        top.plot(X[i, :, 0], X[i, :, 1], color="0.6", lw=0.5)
    for j in range(0, theta.size - 1, 12):
        top.plot(X[:, j, 0], X[:, j, 1], color="0.6", lw=0.5)
    top.plot(X[0, :, 0], X[0, :, 1], color="k", lw=1.3, label="equator, P = 400")
    top.plot(X[-1, :, 0], X[-1, :, 1], color="k", lw=1.0, ls="-.", label="hole, P = 400")
    top.plot(loaded[:, 0], loaded[:, 1], "o", color="C3", ms=4, label="loaded points")
    top.set_aspect("equal")
    top.set_xlabel("x")
    top.set_ylabel("y")
    top.legend(fontsize=7, loc="upper right", framealpha=0.95)
    top.set_title("(b) seen from above", fontsize=10)
    fig.suptitle(f"Pinched open hemisphere, true scale (N = {run['N']}, waves to {2 * run['K']})", fontsize=10)
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    parser = study_parser("pinched_hemisphere", "the pinched open hemisphere of Sze, Liu & Lo (2004) in 3-D")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    meshes = FULL_MESHES if args.full else FAST_MESHES
    t0 = time.perf_counter()
    runs = []
    for N, K in meshes:
        say(args.quiet, f"pinched hemisphere: N = {N}, waves 0 .. {2 * K}")
        runs.append(trace(N, K))
    rows = rows_of(runs)
    columns = ["N", "K", "P", "u_out", "u_out_ref", "err_out_pct", "u_in", "u_in_ref", "err_in_pct"]
    shown = [r for r in rows if round(r["P"]) % 80 == 0]
    print_table(shown, columns, digits=5)
    write_csv(out / "pinched_hemisphere.csv", rows, columns)
    worst = {(r["N"], r["K"]): max(max(abs(x["err_out_pct"]), abs(x["err_in_pct"])) for x in rows
                                        if x["N"] == r["N"] and x["K"] == r["K"]) for r in runs}
    change = [float(max(np.max(np.abs(b["at_out"] - a["at_out"])), np.max(np.abs(b["at_in"] - a["at_in"]))))
              for a, b in zip(runs, runs[1:])]
    order = None
    if len(change) == 2 and change[1] > 0 and len({b[0] / a[0] for a, b in zip(meshes, meshes[1:])}) == 1:
        order = math.log(change[0] / change[1]) / math.log(meshes[1][0] / meshes[0][0])
    summary = {"meshes": [{k: r[k] for k in ("N", "K", "unknowns", "seconds", "points")} for r in runs],
               "observed_order": order,
               "largest_difference_from_paper_pct": {f"N={n},K={k}": v for (n, k), v in worst.items()}, "largest_change_between_meshes": change,
               "wall_time_s": time.perf_counter() - t0,
               "command": "python -m studies.pinched_hemisphere" + (" --full" if args.full else "")}
    write_json(out / "summary.json", summary)
    save_figure(curves_figure(runs), out, "curves")
    save_figure(shape_figure(runs[-1]), out, "shape")
    for r in runs:
        say(args.quiet, f"N = {r['N']}, waves to {2 * r['K']}: {r['unknowns']} unknowns, {r['points']} points, "
                        f"{r['seconds']:.1f} s, largest difference from the paper {worst[r['N'], r['K']]:.2f} %")
    say(args.quiet, f"largest change between successive meshes: {', '.join(f'{x:.4f}' for x in change)}"
                    + (f" (observed order {order:.2f})" if order is not None else "") + "; "
                    f"{time.perf_counter() - t0:.1f} s; outputs in {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
