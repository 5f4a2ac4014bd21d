"""From point to plate indentation: the two limits bound the finite indenters (paper figure 12).

Run ``python -m studies.point_to_plate [--out DIR] [--full] [--quiet]``.  The cap is the paper's
``phi_hat = 0.8``, ``h/R = 0.02`` (``nu = 0.5``, ``R = 1``).  For each indenter the study finds the
snap of the displacement-controlled indentation (``docs/model.md#snaps``) and records there

- ``w_b^c / R``: the indenter travel at the snap (the paper's critical indentation displacement),
- ``w_s / R``: the pole displacement at the snap,
- ``Delta_H / R``: the gap between the pole and the indenter at the snap.

Indenters:

- the point (``r -> 0``): the bilateral point load's displacement-controlled path (the shell
  scene, ``load.kind = "point"``); a point that can only push loses the shell at the first falling
  zero of F (or an earlier fold in ``w``), the scene's ``w_c_one_sided``.  There ``w_b = w_s = w``
  and ``Delta_H = 0``.
- spheres of radius ``r``: ``r/R`` in 0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5, 2.0 (the paper's range) and,
  with ``--full``, 3, 5 and 10 beyond it (to show the approach to the plate);
- the plate (``r -> inf``, ``load.kind = "plate"``): it first snaps into a dimple held by a ring of
  contact and later everts; its snap is the eversion (the snap after which the shell has left the
  plate).

Sphere and plate runs use :func:`studies.bench_contact.snap_record` (the contact runner's settings,
continuation from the first touch to the located snap, dimple snaps of the plate followed).  The
default (fast) mode uses N = 60 and ``r/R`` in 0.1, 0.5, 0.9, 1.5 (about 11 s of CPU time); N = 60
gives the same answer as N = 200 (every number below to about 1e-4 R).  ``--full`` uses the paper's
N = 200 and every radius (about 40 s of CPU time; the plate alone takes ~8 s there, because its
dimple snap has to be followed).  Coarser meshes are not used: at N = 40 the plate run stops at its
dimple snap (continuation step below ``ds_min``).

It writes into ``DIR`` (default ``out/point_to_plate``): ``fig12.png`` / ``fig12.pdf`` (the three
quantities against ``r/R``, log scale, with the point and plate limits as horizontal lines),
``fig12.csv`` (one row per indenter) and ``summary.json``: the records, and for each quantity
whether every finite-r value lies between the point and plate values (the paper's statement), with
the limits, the extreme finite-r values and the largest excursion beyond the limits.  A value counts
as inside when it is within :data:`BOUND_TOL` ``R`` of the interval: a small sphere's travel differs
from the point's ``w`` by the barrier holding the touching pole a hair off the indenter and by the
offset of the barrier's curve from the pole node (``O(h^2)``: 1.0e-6 R below it at N = 200).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from typing import Any  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contin.app.scene import load_scene  # noqa: E402
from contin_models.shell_scene import SHELL_SCENE, SHELL_SCHEMA  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, shell_lambda, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.bench_contact import snap_record  # noqa: E402

NAME = "point_to_plate"
PHI_HAT, H_OVER_R = 0.8, 0.02
#: Sphere radii r/R: the paper's (figures 6 and 12), the fast subset, and the extension beyond the paper.
RADII_PAPER = (0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5, 2.0)
RADII_FAST = (0.1, 0.5, 0.9, 1.5)
RADII_BEYOND = (3.0, 5.0, 10.0)
N_FAST, N_FULL = 60, 200
#: Tolerance (units of R) of "between the limits": 1e-3 of the barrier range dhat = 1e-3 R, far above the
#: barrier's offset of the touching pole (~5e-9 R) and far below the differences that matter (>= 1e-2 R).
BOUND_TOL = 1e-6
#: The quantities compared, with their axis labels.
QUANTITIES = (("w_b_c_over_R", "w_b^c / R (indenter travel at snap)"),
              ("w_s_over_R", "w_s / R (pole displacement at snap)"),
              ("Delta_H_over_R", "Delta H / R (pole-indenter gap at snap)"))


def _overrides(N: int) -> list[str]:
    return [f"shell.phi_hat={PHI_HAT!r}", f"shell.h={H_OVER_R!r}", f"shell.N={N}", "shell.R=1.0"]


def point_limit(N: int) -> dict[str, Any]:
    """The point indenter's snap: the first falling zero of F on the bilateral path (``w_c_one_sided``).

    Parameters
    ----------
    N : int
        Nodes on the meridian.

    Returns
    -------
    dict
        The row of the point (``indenter = "point"``, ``r_over_R = 0``): ``w_b_c_over_R`` and
        ``w_s_over_R`` both ``w_c_one_sided / R``, ``Delta_H_over_R = 0``, plus what kind of point it
        is (F = 0 or a fold in w), the force there and the run's wall time.
    """
    t0 = time.perf_counter()
    scene = load_scene(SHELL_SCHEMA, None, [*_overrides(N), "output.figure=false"])
    trace = SHELL_SCENE.runner(scene, False)
    s = trace.summary
    if s.get("w_c_one_sided") is None:
        raise RuntimeError(f"point load: no falling zero of F and no fold in w on the path ({trace.branches[0].message})")
    w = float(s["w_c_one_sided_over_R"])
    return {"indenter": "point", "r_over_R": 0.0, "N": N, "w_b_c_over_R": w, "w_s_over_R": w, "Delta_H_over_R": 0.0,
            "F_norm_at_snap": float(s["F_at_one_sided_snap"]) / float(s["F_unit"]), "kappa_p_R": None,
            "snap": f"point: {s['one_sided_snap_kind']}", "contact_mode": "point", "points": len(trace.branches[0]),
            "time_s": time.perf_counter() - t0}


def indenter_snap(r: float | None, N: int) -> dict[str, Any]:
    """The snap of a sphere of radius ``r`` (units of R) or, for ``r = None``, of the plate.

    Parameters
    ----------
    r : float or None
        Sphere radius over R; None for the plate.
    N : int
        Nodes on the meridian.

    Returns
    -------
    dict
        One row: ``w_b_c_over_R``, ``w_s_over_R``, ``Delta_H_over_R``, ``F_norm_at_snap``, ``kappa_p_R``,
        the snap's kind, the contact mode on the way (a gap counts once it exceeds the barrier's
        range ``dhat``, as in ``summary.json`` of ``contin trace``), the number of path points and
        the wall time (:func:`studies.bench_contact.snap_record`).
    """
    # gap_tol: the barrier range dhat = 1e-3 R of the scene's default contact (R = 1)
    extra = (f"shell.phi_hat={PHI_HAT!r}", f"shell.h={H_OVER_R!r}", "shell.R=1.0")
    d = snap_record(r, N, extra=extra, stability=False, gap_tol=1e-3)
    return {"indenter": "plate" if r is None else "sphere", "r_over_R": math.inf if r is None else float(r), "N": N,
            "w_b_c_over_R": d["w_b_c_over_R"], "w_s_over_R": d["w_s_over_R"], "Delta_H_over_R": d["Delta_H_over_R"],
            "F_norm_at_snap": d["F_norm"], "kappa_p_R": d["kappa_p_R"], "snap": d["end"], "contact_mode": d["mode"],
            "points": d["points"], "time_s": d["time"]}


def bounds_check(point: dict[str, Any], plate: dict[str, Any], spheres: list[dict[str, Any]],
                 tol: float = BOUND_TOL) -> dict[str, Any]:
    """Whether every finite-r value lies between the point and plate values, per quantity.

    Parameters
    ----------
    point, plate : dict
        The two limits' rows.
    spheres : list of dict
        The finite indenters' rows.
    tol : float
        Allowed excursion beyond the interval (units of R).

    Returns
    -------
    dict
        Per quantity: the two limits, the interval, the finite-r minimum and maximum (and their radii),
        the largest excursion beyond the interval (0 when inside), ``bounded`` and, when the two limits
        coincide within ``tol``, ``degenerate`` (then "between" means "equal").
    """
    out: dict[str, Any] = {}
    for key, _ in QUANTITIES:
        a, b = float(point[key]), float(plate[key])
        lo, hi = min(a, b), max(a, b)
        vals = np.array([float(s[key]) for s in spheres])
        radii = [s["r_over_R"] for s in spheres]
        excursion = [max(lo - v, v - hi, 0.0) for v in vals]
        i_min, i_max = int(np.argmin(vals)), int(np.argmax(vals))
        out[key] = {"point": a, "plate": b, "interval": [lo, hi],
                    "finite_r_min": float(vals[i_min]), "r_over_R_at_min": radii[i_min],
                    "finite_r_max": float(vals[i_max]), "r_over_R_at_max": radii[i_max],
                    "max_excursion": float(max(excursion)), "tol": tol,
                    "outside": [radii[i] for i, e in enumerate(excursion) if e > tol],
                    "bounded": bool(max(excursion) <= tol), "degenerate": bool(hi - lo <= tol),
                    "monotone_in_r": _monotone(vals)}
    return out


def _monotone(vals: np.ndarray) -> str:
    d = np.diff(vals)
    if d.size == 0:
        return "single value"
    if np.all(d <= BOUND_TOL):
        return "non-increasing" if np.any(d < -BOUND_TOL) else "constant"
    if np.all(d >= -BOUND_TOL):
        return "non-decreasing"
    return "not monotone"


#: Per quantity of :data:`QUANTITIES`: the panel's title and the axis' symbol (mathtext).
PANELS = {"w_b_c_over_R": ("(a) indenter travel at the snap", r"$w_b^c/R$"),
          "w_s_over_R": ("(b) pole displacement at the snap", r"$w_s/R$"),
          "Delta_H_over_R": ("(c) pole-indenter gap at the snap", r"$\Delta H/R$")}


def _sig3(v: float) -> str:
    """Three significant digits (N = 60 and 200 agree to about 1e-4 R: no more is meaningful)."""
    return "0" if v == 0 else f"{v:#.3g}".rstrip(".")


def _times_ten(v: float) -> str:
    r"""``4e-08`` as mathtext ``4 \times 10^{-8}`` (one significant digit)."""
    m, e = f"{v:.0e}".split("e")
    return rf"{m} \times 10^{{{int(e)}}}"


def plot_fig12(point: dict[str, Any], plate: dict[str, Any], spheres: list[dict[str, Any]], N: int) -> Any:
    """Figure 12c: the three snap quantities against r/R with the point and plate limits (a column of three)."""
    from contin.plot import style

    # a page wide: the three panels one above the other, on one r/R axis
    fig, axes = plt.subplots(3, 1, figsize=(style.WIDTH, 7.2), sharex=True, layout="constrained")
    r = np.array([s["r_over_R"] for s in spheres])
    c_point, c_plate = style.COLORS[0], style.COLORS[1]
    for ax, (key, _) in zip(axes, QUANTITIES):
        title, symbol = PANELS[key]
        vals = np.array([s[key] for s in spheres])
        # a sweep over separate runs: markers at the radii, joined by thin straight lines; drawn above the
        # limits, which are wide and pale enough to show on either side where a sphere equals one of them
        ax.plot(r, vals, "-", color="k", lw=0.8, marker="o", ms=5, mfc="w", mec="k", mew=1.0, zorder=4,
                label="sphere of radius $r$")
        ax.axhline(point[key], color=c_point, ls=(0, (5, 3)), lw=2.2, alpha=0.75, zorder=2,
                   label=rf"point ($r \to 0$): {_sig3(point[key])}")
        ax.axhline(plate[key], color=c_plate, ls=(0, (6, 2, 1.5, 2)), lw=1.4, zorder=3,
                   label=rf"plate ($r \to \infty$): {_sig3(plate[key])}")
        ax.set_xscale("log")
        ax.set_ylabel(symbol)
        ax.set_title(title, fontsize="medium")
    a, b, c = axes
    c.set_xlabel("$r/R$")
    # (a) and (b) are the same kind of displacement: on one scale, w_s is seen not to move while w_b^c does
    lo = min(plate["w_b_c_over_R"], *(s["w_b_c_over_R"] for s in spheres))
    hi = max(point["w_b_c_over_R"], point["w_s_over_R"], plate["w_s_over_R"])
    pad = 0.08 * (hi - lo)
    for ax in (a, b):
        ax.set_ylim(lo - pad, hi + 2.5 * pad)
    every = [point["w_s_over_R"], plate["w_s_over_R"], *(s["w_s_over_R"] for s in spheres)]
    spread = max(every) - min(every)
    b.text(0.5, 0.5, f"$w_s/R = {_sig3(point['w_s_over_R'])}$ for the point, the plate and every sphere\n"
                     f"(they agree to within ${_times_ten(max(spread, 1e-16))}$)",
           transform=b.transAxes, ha="center", va="center", fontsize="small",
           bbox={"boxstyle": "square,pad=0.4", "fc": "w", "ec": "0.8", "lw": 0.6})
    a.legend(fontsize="small", loc="center left")
    b.legend(fontsize="small", loc="lower left")
    c.legend(fontsize="small", loc="center left")
    fig.suptitle(rf"Snap of the cap $\hat\phi = {PHI_HAT:g}$, $h/R = {H_OVER_R:g}$ ($N = {N}$): "
                 "point and plate limits", fontsize="medium")
    return fig


def run(full: bool = False, quiet: bool = True) -> dict[str, Any]:
    """Compute the point, sphere and plate snaps and the bounds check (no files written).

    Parameters
    ----------
    full : bool
        N = 200 and every radius (the paper's and beyond) instead of N = 60 and four radii.
    quiet : bool
        No progress lines on stderr.

    Returns
    -------
    dict
        ``N``, ``radii``, ``point``, ``plate``, ``spheres`` (rows), ``bounds`` (:func:`bounds_check`
        over every sphere), ``bounds_paper_range`` (over the radii up to 2.0 only).
    """
    N = N_FULL if full else N_FAST
    radii = RADII_PAPER + RADII_BEYOND if full else RADII_FAST
    say(quiet, f"point (N = {N})")
    point = point_limit(N)
    spheres = []
    for r in radii:
        spheres.append(indenter_snap(r, N))
        s = spheres[-1]
        say(quiet, f"  r/R = {r:g}: w_b^c/R = {s['w_b_c_over_R']:.6f}, Delta_H/R = {s['Delta_H_over_R']:.5f} "
                   f"({s['time_s']:.2f} s)")
    say(quiet, "plate")
    plate = indenter_snap(None, N)
    in_paper = [s for s in spheres if s["r_over_R"] <= max(RADII_PAPER)]
    return {"N": N, "radii": list(radii), "point": point, "plate": plate, "spheres": spheres,
            "bounds": bounds_check(point, plate, spheres), "bounds_paper_range": bounds_check(point, plate, in_paper)}


def _print_report(summary: dict[str, Any], rows: list[dict[str, Any]], out: Any) -> None:
    """Print the snap table, the bounds of each quantity and the paper's statement."""
    print(f"point-to-plate study ({summary['mode']}, N = {summary['N']}), {summary['wall_time_s']:.1f} s; "
          f"files in {out}")
    table = [{"indenter": row["indenter"], "r/R": ("-" if row["indenter"] == "plate" else row["r_over_R"]),
              "w_b^c/R": row["w_b_c_over_R"], "w_s/R": row["w_s_over_R"], "Delta_H/R": row["Delta_H_over_R"],
              "mode": row["contact_mode"], "snap": row["snap"], "time_s": row["time_s"]} for row in rows]
    print_table(table, ["indenter", "r/R", "w_b^c/R", "w_s/R", "Delta_H/R", "mode", "snap", "time_s"], digits=6)
    print()
    for key, label in QUANTITIES:
        q = summary["bounds"][key]
        print(f"{label}: point {q['point']:.6f}, plate {q['plate']:.6f}; finite r in [{q['finite_r_min']:.6f}, "
              f"{q['finite_r_max']:.6f}]; {'bounded' if q['bounded'] else 'NOT bounded'}"
              f"{' (degenerate: the limits coincide)' if q['degenerate'] else ''}, "
              f"largest excursion {q['max_excursion']:.2g}")
    print(f"statement: {'reproduced' if summary['statement']['reproduced'] else 'NOT reproduced'} -- "
          f"{summary['statement']['paper']}")


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m studies.point_to_plate [--out DIR] [--full] [--quiet]``.

    Runs the study and writes ``fig12.png``/``.pdf``, ``fig12.csv`` and ``summary.json``; returns 0
    (a failed run raises).
    """
    args = study_parser(NAME, "Point and plate indentation bound the finite indenters (paper figure 12)"
                        ).parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    res = run(args.full, args.quiet)
    N, point, plate, spheres = res["N"], res["point"], res["plate"], res["spheres"]
    rows = [point, *spheres, plate]
    cols = ["indenter", "r_over_R", "N", "w_b_c_over_R", "w_s_over_R", "Delta_H_over_R", "F_norm_at_snap",
            "kappa_p_R", "snap", "contact_mode", "points", "time_s"]
    write_csv(out / "fig12.csv", rows, cols)
    save_figure(plot_fig12(point, plate, spheres, N), out, "fig12")
    b = res["bounds"]
    ok_wb, ok_dh, ok_ws = (b[k]["bounded"] for k in ("w_b_c_over_R", "Delta_H_over_R", "w_s_over_R"))
    statement = {
        "paper": "point (r -> 0) and plate (r -> inf) indentation bound the finite-r results for the critical "
                 "snapping displacement and for Delta H (figure 12c)",
        "w_b_c_bounded": ok_wb, "Delta_H_bounded": ok_dh, "w_s_bounded": ok_ws,
        "w_s_degenerate": b["w_s_over_R"]["degenerate"],
        "w_s_spread_over_R": max(b["w_s_over_R"]["finite_r_max"], point["w_s_over_R"], plate["w_s_over_R"])
        - min(b["w_s_over_R"]["finite_r_min"], point["w_s_over_R"], plate["w_s_over_R"]),
        "reproduced": ok_wb and ok_dh and ok_ws,
        "note": ("the pole displacement at the snap w_s is the same for every indenter, point and plate included "
                 "(the snap shape is universal), so for w_s the bounds coincide and 'between' means 'equal'; the "
                 "bounds are non-trivial for the indenter travel w_b^c (point above, plate below) and for Delta H "
                 "(point 0 below, plate above), and w_s = w_b^c + Delta H ties the two together"),
    }
    wall = time.perf_counter() - t0
    summary = {
        "study": NAME, "command": f"python -m studies.{NAME}" + (" --full" if args.full else ""),
        "mode": "full" if args.full else "fast", "N": N, "phi_hat": PHI_HAT, "h_over_R": H_OVER_R, "nu": 0.5,
        "lambda": float(shell_lambda(PHI_HAT, H_OVER_R)), "radii_over_R": res["radii"],
        "point": point, "plate": plate, "spheres": spheres,
        "bounds": b, "bounds_paper_range_r_le_2": res["bounds_paper_range"], "statement": statement,
        "wall_time_s": wall,
    }
    write_json(out / "summary.json", summary)

    _print_report(summary, rows, out)
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
