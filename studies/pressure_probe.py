"""A pressurised cap probed by a point force at its pole: the limit load's fold curve in ``(p, F)`` (issue 16, item 3).

Run ``python -m studies.pressure_probe [--out DIR] [--full]``.

A clamped spherical cap under a fixed uniform pressure ``p`` and a dead point force ``F`` at the pole
is a two-parameter problem: :class:`contin_models.shell.structure.ShellOfRevolution` with the force as
the parameter and the pressure fixed (``pressure=``, :meth:`~ShellOfRevolution.with_pressure` gives
the family).  Its limit load ``F_max`` (the first fold in ``F``) moves with ``p`` along a fold curve,
which :class:`contin.FoldCurveProblem` traces from the unpressurised cap's limit load.

Checks that need nothing from this study's own code:

* at ``p = 0`` the curve starts at the force-controlled cap's limit load (located by
  :func:`contin.continuation` on the cap alone);
* where the curve crosses ``F = 0`` the cap carries the pressure alone at a singular point, so that
  pressure is a fold of the pressure-controlled path (:class:`contin_models.shell.ShellPressure`,
  traced on its own): the two must agree to the location tolerance.

The curve is followed until it turns back in ``p`` (a cusp, where the limit load meets the next fold in
``F``) or reaches ``0.6 p_c``.

Cap: ``R = 1``, ``h/R = 0.01``, ``phi_hat = 0.9`` (``lambda = 12``), ``nu = 0.3``, clamped, ``N = 200``
(``--full``: also 400).  Writes ``fold_curve.csv``, ``summary.json`` and ``pressure_probe.png`` / ``.pdf``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import contin  # noqa: E402
from contin_models.shell.geometry import spherical_cap  # noqa: E402
from contin_models.shell.pressure import ShellPressure, classical_pressure  # noqa: E402
from contin_models.shell.structure import ShellOfRevolution, ShellStructure  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

CAP = {"R": 1.0, "E": 1e6, "nu": 0.3, "h": 0.01, "phi_hat": 0.9}


def probe_problem(N: int) -> ShellOfRevolution:
    """The clamped cap with a point force at the pole (the parameter) and room for a fixed pressure."""
    c = CAP
    structure = ShellStructure(spherical_cap(c["R"], c["phi_hat"], N, 1.0), c["E"], c["nu"], c["h"], "clamped")
    # a (tiny) pressure builds the volume term that with_pressure() then sets
    return ShellOfRevolution(structure, "point", "force", pressure=1e-300)


def fold_curve(N: int, p_max_over_p_c: float = 0.6) -> dict[str, Any]:
    """The limit load's fold curve from ``p = 0`` until ``F`` has crossed 0 (or ``p`` reaches the bound)."""
    c = CAP
    p_c = classical_pressure(c["E"], c["h"], c["R"], c["nu"])
    base = probe_problem(N).with_pressure(0.0)
    D = float(base.D)
    f_unit = 2.0 * math.pi * D / c["R"]
    br = contin.continuation(base, base.reference_unknowns(), 0.0,
                             contin.Settings(ds=0.01, ds_max=0.5, max_steps=3000, param_weight=1.0 / (10 * f_unit)),
                             stop_at=("fold",), p_max=100.0 * f_unit)
    fold = next((s for s in br.special_points if s.kind == "fold" and s.located), None)
    if fold is None:
        raise RuntimeError(f"N = {N}: the cap under a point force has no located limit load ({br.message})")
    curve = contin.FoldCurveProblem(lambda q: base.with_pressure(q * p_c), fold, 0.0, q_name="p_over_p_c",
                                    p_scale=10.0 * f_unit)
    # the curve ends where it turns back in p (a cusp: two limit loads meet) or at the bound
    fc = contin.continuation(curve, curve.start, 0.0, ds=0.01, ds_max=0.05, stability=False, max_steps=400,
                             p_max=p_max_over_p_c, stop_at=("fold",), events=[contin.crossing("F", 0.0, name="F = 0")])
    cusp = next((s for s in fc.special_points if s.kind == "fold" and s.located), None)
    rows = [{"N": N, "p_over_p_c": float(q), "F": float(curve.split(U)[1]), "F_norm": float(curve.split(U)[1]) / f_unit,
             "w": float(curve.observables["w"](U, q))} for U, q in zip(fc.u, fc.p)]
    hits = fc.events("F = 0")
    return {"N": N, "F_max_at_p0": float(fold.p), "F_max_at_p0_norm": float(fold.p) / f_unit, "rows": rows,
            "p_at_F_zero_over_p_c": float(hits[0].p) if hits else None, "message": fc.message, "p_c": p_c,
            "cusp_p_over_p_c": None if cusp is None else float(cusp.p),
            "cusp_F_norm": None if cusp is None else float(curve.split(cusp.u)[1]) / f_unit}


def pressure_folds(N: int) -> list[float]:
    """The folds in ``p`` of the pressure-controlled cap alone, over ``p_c`` (independent of the fold curve)."""
    c = CAP
    pr = ShellPressure(c["R"], c["E"], c["nu"], c["h"], c["phi_hat"], N, "clamped")
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(ds=0.01, ds_max=0.5, max_steps=3000),
                             p_max=2.0 * pr.p_c)
    return [float(s.p) / pr.p_c for s in br.special_points if s.kind == "fold" and s.located]


def plot(curves: Sequence[dict[str, Any]], folds: Sequence[float]) -> Any:
    """``F_max`` against ``p``: the fold curve, its cusp, and the pressure-path folds on ``F = 0``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot import style

    fig, ax = plt.subplots(figsize=(style.WIDTH, 3.8))  # a page's width: printable as saved
    # straight between stored points: the fold curve's branch stores no tangent of F (FoldCurveProblem
    # gives no observable derivatives); its stored points are close enough that no corner shows
    for c in curves:
        ax.plot([r["p_over_p_c"] for r in c["rows"]], [r["F_norm"] for r in c["rows"]], lw=1.2,
                label=f"limit load of the point force, $N$ = {c['N']}")
    ax.axhline(0.0, color="gray", lw=0.7, zorder=0)
    p_end = max(r["p_over_p_c"] for r in curves[0]["rows"])
    xs = [f for f in folds if f <= p_end * 1.05]
    off = [f for f in folds if f > p_end * 1.05]
    label = r"folds in $p$ of the pressure path alone ($F = 0$, traced apart)"
    if off:
        # the pressure path's first folds (near p_c) are far right of the fold curve: named, not drawn
        label += f"\n({len(off)} more at {min(off):.3g}\u2013{max(off):.3g} $p_c$, beyond the axes)"
    ax.plot(xs, [0.0] * len(xs), ls="none", label=label, **style.marker_style("fold"))
    for c in curves:
        if c.get("cusp_p_over_p_c") is not None and c.get("cusp_F_norm") is not None:
            ax.plot([c["cusp_p_over_p_c"]], [c["cusp_F_norm"]], ls="none", marker="o", ms=5.0, mfc="k", mec="k",
                    zorder=7, label=(f"cusp at $p$ = {c['cusp_p_over_p_c']:.3g} $p_c$ (the curve turns back; "
                                     "tracing stops)") if c is curves[0] else None)
    ax.set_xlabel(r"fixed pressure $p / p_c$")
    ax.set_ylabel(r"limit load $F_\mathrm{max} R / 2\pi D$")
    ax.set_title("clamped cap ($\\lambda = 12$, $R/h = 100$) probed at its pole under pressure", fontsize="small")
    ax.legend(loc="upper right")
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("pressure_probe", "a pressurised cap probed at its pole: the limit load's fold curve in (p, F)")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    curves = []
    for N in ((200, 400) if args.full else (200,)):
        say(args.quiet, f"fold curve, N = {N} ...")
        curves.append(fold_curve(N))
    say(args.quiet, "pressure-controlled path alone ...")
    folds = pressure_folds(curves[-1]["N"])
    summary = []
    for c in curves:
        p0 = c["p_at_F_zero_over_p_c"]
        nearest = min(folds, key=lambda f: abs(f - p0)) if (p0 is not None and folds) else None
        summary.append({"N": c["N"], "F_max_at_p0_norm": c["F_max_at_p0_norm"], "p_at_F_zero_over_p_c": p0,
                        "nearest_pressure_fold": nearest, "difference": None if nearest is None else p0 - nearest,
                        "cusp_p_over_p_c": c["cusp_p_over_p_c"], "cusp_F_norm": c["cusp_F_norm"], "points": len(c["rows"])})
    print_table(summary, ["N", "F_max_at_p0_norm", "p_at_F_zero_over_p_c", "nearest_pressure_fold", "difference",
                          "cusp_p_over_p_c", "cusp_F_norm", "points"])
    write_csv(out / "fold_curve.csv", [r for c in curves for r in c["rows"]])
    write_json(out / "summary.json", {"cap": CAP, "curves": summary, "pressure_folds_over_p_c": folds})
    save_figure(plot(curves, folds), out, "pressure_probe")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
