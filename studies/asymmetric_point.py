"""Issue 17, study (b), first pass: where the paper's point-loaded caps leave the axisymmetric path.

Run ``python -m studies.asymmetric_point [--out DIR] [--full] [--workers N]``.

Over a grid of ``(phi_hat, h/R)`` (``nu = 0.5``, the paper's), each cap is classified by
``contin classify`` (the displacement-controlled path of the point load to eversion) with
``stability.harmonics = true``: the blocks of wave numbers ``n = 1 .. n_max`` are watched along the path
and the first bifurcation into a mode is located.  For each cap: the paper's class (from the
axisymmetric path), the limit load ``F_max`` and where it is, the first fold in ``w`` (the snap under
displacement control), and the first bifurcation (its ``n`` and ``w``), with the pole free laterally
(a frictionless point) and held (``load.pole_held = true``).  Reported per cap:

* ``before_fold_in_w``: the bifurcation comes before the snap under displacement control;
* ``before_F_max``: it comes before the limit load, the snap under force control.

``--indenters`` instead traces the cap ``phi_hat = 0.8`` (``h/R`` = 0.02 and 0.01) under rigid spheres of
radii ``r/R`` = 0.1 .. 2 and the plate (displacement control, every mode watched, the barrier's block in
each), and reports whether the first instability is a bifurcation before the snap (the located fold in
the travel ``w_b``); writes ``indenters.csv`` / ``.json``.

``--boundary`` also locates, for a few ``phi_hat``, the thickness at which the first bifurcation
reaches the limit load (``before_F_max`` changes), by bisection in ``ln(h/R)`` on that test, each
evaluation a classification (pole held laterally): points on the boundary, to 1 % in ``h``; the
boundary continued as a curve, and its mesh convergence, are ``studies/asymmetric_boundary.py``.  Mesh: N = 100 (``--full``: 200), ``n_max`` = 12.  Writes ``asymmetric_point.csv``,
``boundary.csv``, ``summary.json`` and ``asymmetric_point.png`` / ``.pdf``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from contin.app.scene import load_scene  # noqa: E402
from contin_models.shell_scene import SHELL_SCHEMA  # noqa: E402
from contin_models.shell_scene.scene import classify_scene  # noqa: E402
from contin_models.shell_scene.schema import minimum_nodes  # noqa: E402
from studies._common import (executor_from_args, output_dir, print_table, run_study, save_figure, say,  # noqa: E402
                             study_parser, write_csv, write_json)

N_MAX = 12


def cap_row(args: tuple[float, float, int, bool]) -> dict[str, Any]:
    """Classify one cap with harmonics on; the row of the study's table."""
    phi_hat, h, N, held = args
    sets = [f"shell.phi_hat={phi_hat!r}", f"shell.h={h!r}", f"shell.N={N}", "stability.harmonics=true",
            f"stability.n_max={N_MAX}", f"load.pole_held={'true' if held else 'false'}", "output.figure=false"]
    scene = load_scene(SHELL_SCHEMA, None, sets)
    cls = classify_scene(scene)
    v = cls.values
    first = v.get("first_instability") or {}
    bif = first.get("kind") == "bifurcation"
    w_fmax = v.get("w_at_F_max")
    return {"phi_hat": phi_hat, "h_over_R": h, "N": N, "pole_held": held, "class": cls.label,
            "F_max_norm": v.get("F_max_norm"), "w_at_F_max_over_R": v.get("w_at_F_max_over_R"),
            "first_kind": first.get("kind"), "first_n": first.get("n"), "first_w_over_R": first.get("w_over_R"),
            "before_fold_in_w": bool(bif),
            "before_F_max": bool(bif and w_fmax is not None and first.get("w") is not None and first["w"] < w_fmax)}


def boundary_point(phi_hat: float, h_lo: float, h_hi: float, N: int, rtol: float = 0.01) -> dict[str, Any]:
    """The ``h/R`` in ``[h_lo, h_hi]`` where the first bifurcation (pole held) reaches ``F_max``: bisection in
    ``ln h`` on ``before_F_max`` (true at ``h_lo``, false at ``h_hi``); None when the bracket does not."""
    lo, hi = cap_row((phi_hat, h_lo, N, True)), cap_row((phi_hat, h_hi, N, True))
    out: dict[str, Any] = {"phi_hat": phi_hat, "N": N, "h_lo": h_lo, "h_hi": h_hi, "evaluations": 2}
    if not (lo["before_F_max"] and not hi["before_F_max"]):
        out["h_over_R"] = None
        out["note"] = f"no change on the bracket (before F_max: {lo['before_F_max']} at {h_lo}, {hi['before_F_max']} at {h_hi})"
        return out
    a, b = math.log(h_lo), math.log(h_hi)
    n_lo = lo["first_n"]
    while b - a > rtol:
        m = 0.5 * (a + b)
        row = cap_row((phi_hat, math.exp(m), N, True))
        out["evaluations"] += 1
        if row["before_F_max"]:
            a, n_lo = m, row["first_n"]
        else:
            b = m
    out["h_over_R"] = math.exp(0.5 * (a + b))
    out["n_at_boundary"] = n_lo
    return out


def plot(rows: Sequence[dict[str, Any]], boundary: Sequence[dict[str, Any]] = ()) -> Any:
    """The grid in ``(phi_hat, h/R)``: marker by class, colour by where the first bifurcation comes, its n;
    the located boundary points (pole held) on the right."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from matplotlib.ticker import FixedFormatter, FixedLocator, NullLocator

    from contin.plot import style

    before_f, before_w, none = style.RED, style.COLORS[4], style.COLORS[0]

    # a page's width (contin.plot.style.WIDTH), two panels of about 2.8 in: printable as saved
    fig, axes = plt.subplots(1, 2, figsize=(style.WIDTH, 3.7), sharey=True, layout="constrained")
    markers = {"monotonous": "o", "monostable": "s", "bistable": "D", None: "x"}
    h_values = sorted({r["h_over_R"] for r in rows})
    for ax, held in zip(axes, (False, True)):
        for r in (r for r in rows if r["pole_held"] == held):
            color = before_f if r["before_F_max"] else before_w if r["before_fold_in_w"] else none
            ax.semilogy(r["phi_hat"], r["h_over_R"], markers.get(r["class"], "x"), color=color, ms=8, mfc="none")
            if r["first_n"] is not None:
                ax.annotate(str(r["first_n"]), (r["phi_hat"], r["h_over_R"]), textcoords="offset points",
                            xytext=(7, 0), ha="left", va="center", fontsize="small")
        pts = [(b["phi_hat"], b["h_over_R"]) for b in boundary if b.get("h_over_R")]
        if held and pts:
            ax.semilogy(*zip(*pts), "k+-", lw=0.8, ms=9, label=r"bifurcation reaches $F_\mathrm{max}$")
            lam = float(np.mean([(12 * 0.75) ** 0.25 * (math.pi / 2 - f) / math.sqrt(hh) for f, hh in pts]))
            ff = np.linspace(0.55, 1.45, 50)
            ax.semilogy(ff, ((12 * 0.75) ** 0.25 * (math.pi / 2 - ff) / lam) ** 2, ":", color="gray", lw=0.8)
            # beside the dotted line (not on it), between the lowest row and the located points above it
            h_text = 1.15 * min(h_values)
            ax.annotate(f"$\\lambda$ = {lam:.3g}", (math.pi / 2 - lam * math.sqrt(h_text) / (12 * 0.75) ** 0.25, h_text),
                        textcoords="offset points", xytext=(5, 0), ha="left", va="center", fontsize="small",
                        color="gray")
        ax.set_xlabel(r"$\hat\phi$ (base angle) [rad]")
        # the sampled thicknesses as plain decimals: log-axis ticks such as 3x10^-2 fall between the data
        ax.yaxis.set_major_locator(FixedLocator(h_values))
        ax.yaxis.set_major_formatter(FixedFormatter([f"{v:g}" for v in h_values]))
        ax.yaxis.set_minor_locator(NullLocator())
        # room above and below the outer rows: the inward ticks of the frame cut into their markers
        ax.set_ylim(min(h_values) / 1.25, max(h_values) * 1.25)
        ax.set_title("pole held laterally" if held else "frictionless point (pole free)", fontsize="small")
    axes[0].set_ylabel("$h/R$")
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], ls="", marker=m, color="k", mfc="none", label=str(c)) for c, m in markers.items() if c]
    # the located boundary is drawn (with --boundary): its line belongs in the legend as well, in the first
    # column (what a mark or line is), the colours in the second
    handles += [ln for ln in axes[1].get_lines() if not ln.get_label().startswith("_")]
    colours = [Line2D([], [], ls="", marker="o", color=c, mfc="none", label=t) for c, t in (
        (before_f, r"bifurcation before $F_\mathrm{max}$"), (before_w, r"bifurcation before the fold in $w$"),
        (none, r"no bifurcation before the fold in $w$ (or no fold)"))]
    # two columns below the panels (one row of them would be wider than the page)
    fig.legend(handles=handles + colours, loc="outside lower center", ncol=2, frameon=False,
               columnspacing=2.0, handletextpad=0.4)
    fig.suptitle(r"point-loaded caps ($\nu = 0.5$): first non-axisymmetric bifurcation ($n$ beside the marker)",
                 fontsize="small")
    return fig


def _boundary_task(args: tuple[float, float, float, int]) -> dict[str, Any]:
    return boundary_point(*args)


#: Indenters of ``--indenters``: sphere radii over R, and the plate (None).
INDENTERS = (0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5, 2.0, None)
#: A bifurcation this close to the snap (in w_b / R) is reported at it, not before it.
SAME_POINT = 1e-6


def indenter_row(args: tuple[float, float, int, float | None]) -> dict[str, Any]:
    """Trace one cap under a rigid sphere of radius ``r`` (or the plate, ``r = None``) to its first snap, every
    mode watched; where it first loses stability against the snap (the located fold in the travel)."""
    from contin_models.shell_scene.scene import run_scene

    phi_hat, h, N, r = args
    sets = [f"shell.phi_hat={phi_hat!r}", f"shell.h={h!r}", f"shell.N={N}", "stability.harmonics=true",
            f"stability.n_max={N_MAX}", "output.figure=false"]
    sets += ["load.kind=plate"] if r is None else ["load.kind=sphere", f"load.radius={r!r}"]
    result = run_scene(load_scene(SHELL_SCHEMA, None, sets))
    summ = result.summary
    first = summ.get("first_instability") or {}
    snap = summ.get("w_b_c_over_R")
    bif = first.get("kind") == "bifurcation"
    lead = None if not (bif and snap is not None and first.get("w_over_R") is not None) else snap - first["w_over_R"]
    return {"phi_hat": phi_hat, "h_over_R": h, "N": N, "indenter": "plate" if r is None else f"sphere {r:g}",
            "snap_w_b_over_R": snap, "first_kind": first.get("kind"), "first_n": first.get("n"),
            "first_w_b_over_R": first.get("w_over_R"), "first_F_norm": first.get("F_norm"),
            "snap_minus_first_over_R": lead,
            # a bifurcation within 1e-6 R of the snap is at it: where a large indenter releases the cap
            # (F -> 0), the n = 1 or 6 block becomes singular at the release fold itself
            "before_snap": bool(lead is not None and lead > SAME_POINT),
            "at_snap": bool(lead is not None and abs(lead) <= SAME_POINT)}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("asymmetric_point", "point-loaded caps: where they leave the axisymmetric path",
                          executor_options=True)
    parser.add_argument("--boundary", action="store_true",
                        help="also locate where the first bifurcation reaches F_max, for a few phi_hat")
    parser.add_argument("--indenters", action="store_true",
                        help="only the rigid spheres of several radii and the plate on two caps")
    args = parser.parse_args(argv)
    if args.indenters:
        out = output_dir(args.out)
        N = 200 if args.full else 100
        cases = [(0.8, h, N, r) for h in (0.02, 0.01) for r in INDENTERS]
        say(args.quiet, f"{len(cases)} indentations with harmonics (N = {N}, n_max = {N_MAX}) ...")
        with executor_from_args(args) as ex:
            rows = list(ex.map(indenter_row, cases))
        print_table(rows, ["phi_hat", "h_over_R", "indenter", "snap_w_b_over_R", "first_kind", "first_n",
                           "first_w_b_over_R", "first_F_norm", "snap_minus_first_over_R", "before_snap", "at_snap"])
        write_csv(out / "indenters.csv", rows)
        write_json(out / "indenters.json", {"rows": rows, "N": N, "n_max": N_MAX, "nu": 0.5})
        return 0
    out = output_dir(args.out)
    N = 200 if args.full else 100
    phis = np.linspace(0.6, 1.4, 9 if args.full else 5)
    hs = (0.005, 0.01, 0.02, 0.04) if args.full else (0.01, 0.02, 0.04)
    cases = []
    for phi in phis:
        for h in hs:
            shell = {"R": 1.0, "h": h, "phi_hat": float(phi), "geometry": "sphere"}
            if N < minimum_nodes(shell):
                continue
            cases += [(float(phi), h, N, held) for held in (False, True)]
    say(args.quiet, f"{len(cases)} caps with harmonics (N = {N}, n_max = {N_MAX}) ...")
    with executor_from_args(args) as ex:
        rows = list(ex.map(cap_row, cases))
    print_table(rows, ["phi_hat", "h_over_R", "pole_held", "class", "F_max_norm", "w_at_F_max_over_R", "first_kind",
                       "first_n", "first_w_over_R", "before_fold_in_w", "before_F_max"])
    write_csv(out / "asymmetric_point.csv", rows)
    boundary: list[dict[str, Any]] = []
    if args.boundary:
        brackets = ((0.6, 0.02, 0.04), (0.7, 0.01, 0.04), (0.8, 0.01, 0.02), (0.9, 0.005, 0.02))
        say(args.quiet, f"boundary: the first bifurcation at F_max, {len(brackets)} base angles ...")
        with executor_from_args(args) as ex:
            boundary = list(ex.map(_boundary_task, [(phi, lo, hi, N) for phi, lo, hi in brackets]))
        print_table(boundary, ["phi_hat", "h_over_R", "n_at_boundary", "evaluations", "h_lo", "h_hi"])
        write_csv(out / "boundary.csv", boundary)
    write_json(out / "summary.json", {"rows": rows, "boundary": boundary, "N": N, "n_max": N_MAX, "nu": 0.5})
    save_figure(plot(rows, boundary), out, "asymmetric_point")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
