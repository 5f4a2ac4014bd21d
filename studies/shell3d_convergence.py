"""Mesh convergence of the shell's 3-D view on a state that is not axisymmetric: the paper's cap on its three-wave branch.

Run ``python -m studies.shell3d_convergence [--out DIR] [--full] [--quiet]``.

The paper's default cap (``phi_hat = 0.8``, h/R = 0.02, nu = 0.5, sliding edge), pushed at its pole by a
prescribed deflection ``w``, meets a bifurcation into three circumferential waves at ``w`` near 0.35 R
(the harmonic blocks locate it; ``docs/validation.md`` section 9).  In the 3-D view with the ``D_3`` basis
(waves ``0, 3, ..., 3 K``) the engine finds it as a simple branch point, switches onto the three-wave
branch and follows it to ``w = 0.37 R``, where the force has fallen by a fifth.  The study records the
branch point's deflection ``w_bp`` (an axisymmetric quantity) and the force ``F`` at ``w = 0.37 R`` on the
branch (a quantity of a state that is not axisymmetric), refining

* the meridian: N = 50, 100, 200 (``--full``: 25 .. 800) at a fixed angular resolution;
* the angle: K = 1 .. 4 (``--full``: 1 .. 6) at a fixed N;

``--boundary clamped`` does the same for the clamped cap, whose edge has no rotating half cell: its
first bifurcation that keeps ``D_3`` is into six waves near ``w = 0.44 R``, so it is followed in the ``D_6``
basis (waves ``0, 6, ..., 6 K``) and the force read at ``0.45 R``;

and reports the differences between successive refinements and the observed orders (in N:
``log2`` of the ratio of successive differences).  Outputs in ``--out`` (default
``out/shell3d_convergence``): ``shell3d_convergence.csv``, ``summary.json`` and the figure
``convergence`` (differences against N and against K).
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

#: The paper's default cap.
PHI_HAT, H_OVER_R, NU, E = 0.8, 0.02, 0.5, 1e6
#: The symmetry of the branch followed, and where on it the force is read; per edge support: the clamped
#: cap's first bifurcation in ``D_3`` comes later (near 0.44 R) and into six waves, so it is followed in ``D_6``.
WAVES, W_END = 3, 0.37
BRANCHES = {"sliding": (WAVES, W_END), "clamped": (6, 0.45)}
#: The first step onto the bifurcating branch (in the arclength metric).  The branch leaves the branch point
#: as a parabola in the load, ``w - w_bp`` about four times the square of the wave amplitude, which in the
#: metric's root-mean-square of the state turns within about 1e-4 of the point: a longer first step is
#: halved until it is that short, and each halving costs a failed correction.
SWITCH_DS = 1e-4
FAST = {"meridian": ((50, 100, 200), 3), "angle": (50, (1, 2, 3, 4))}
FULL = {"meridian": ((25, 50, 100, 200, 400, 800), 4), "angle": (100, (1, 2, 3, 4, 6))}


def paper_cap(N: int, boundary: str = "sliding") -> Any:
    """The paper's default cap on ``N`` nodes (R = 1, E = 1e6)."""
    from contin_models.shell.geometry import spherical_cap
    from contin_models.shell.structure import ShellStructure

    return ShellStructure(spherical_cap(1.0, PHI_HAT, N), E, NU, H_OVER_R, boundary=boundary)


def three_wave_branch(N: int, K: int, w_end: float = W_END, boundary: str = "sliding",
                      n_eigs: int = 0, waves: int = WAVES) -> dict[str, Any]:
    """Trace the cap in the ``D_waves`` basis to its first branch point, switch onto the bifurcating branch
    and follow it to ``w_end``: the branch point's deflection, the force there and at ``w_end``, the traces
    (``n_eigs``: the smallest eigenvalues stored per point, :class:`contin.Settings`; by default none, the
    Morse index only: a banded eigensolve costs O(n^2 b) per point, which dominates from N = 400 on)."""
    from contin_models.shell.fourier import AngularBasis
    from contin_models.shell.problem3d import Shell3D

    prob = Shell3D(paper_cap(N, boundary), AngularBasis(waves, K), "point", "displacement")
    t0 = time.perf_counter()
    first = contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=w_end, ds=0.01, ds_max=0.02,
                               max_steps=2000, stability=True, n_eigs=n_eigs, stop_at=("branch_point",))
    bp = first.special_points[-1] if first.special_points else None
    if bp is None or bp.kind != "branch_point" or not bp.located:
        raise RuntimeError(f"shell3d_convergence: no located branch point before w = {w_end} at N = {N}, K = {K}: "
                           f"{first.message}")
    second = contin.switch_branch(prob, bp, settings=contin.Settings(ds=SWITCH_DS, ds_max=0.02), max_steps=2000,
                                  p_max=w_end, stability=True, n_eigs=n_eigs)
    if second.status != "bound":
        raise RuntimeError(f"shell3d_convergence: the three-wave branch stopped before w = {w_end} at N = {N}, "
                           f"K = {K}: {second.message}")
    seconds = time.perf_counter() - t0
    u, w = second.u[-1], float(second.p[-1])
    c = prob.full_state(u, w)
    waves = float(np.max(np.abs(np.delete(c, prob.view.axisymmetric_dofs()))))
    return {"N": N, "K": K, "w_bp": float(bp.p), "F_end": float(prob.observables["F"](u, w)), "w_end": w,
            "wave_amplitude": waves, "points": len(first.p) + len(second.p), "seconds": seconds,
            "problem": prob, "first": first, "second": second}


def differences(values: Sequence[float]) -> list[float]:
    return [abs(b - a) for a, b in zip(values, values[1:])]


def orders(diffs: Sequence[float], ratio: float = 2.0) -> list[float]:
    return [math.log(a / b) / math.log(ratio) if a > 0 and b > 0 else math.nan for a, b in zip(diffs, diffs[1:])]


def figure(meridian: Sequence[dict[str, Any]], angle: Sequence[dict[str, Any]]) -> Any:
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(8.4, 3.6))
    Ns = np.array([r["N"] for r in meridian[1:]], dtype=float)
    w_end = meridian[0]["w_end"]
    for key, label, mark in (("F_end", f"force on the branch at w = {w_end:.2f} R", "o"),
                             ("w_bp", "branch point w / R", "s")):
        d = np.array(differences([r[key] for r in meridian]))
        scale = abs(meridian[-1][key])
        a.loglog(Ns, d / scale, mark + "-", color="k" if key == "F_end" else "0.5", ms=4, label=label)
    a.loglog(Ns, (Ns / Ns[0]) ** -2.0 * 0.5 * float(np.max(np.array(differences([r["w_bp"] for r in meridian])))
                                                       / abs(meridian[-1]["w_bp"])), ":", color="0.6",
             label="slope -2")
    a.set_xlabel("N (finer of the two meshes)")
    a.set_ylabel("change from the coarser mesh (relative)")
    a.legend(fontsize=7)
    a.set_title(f"(a) the meridian, K = {meridian[0]['K']}", fontsize=10)
    Ks = np.array([r["K"] for r in angle[1:]])
    d = np.array(differences([r["F_end"] for r in angle])) / abs(angle[-1]["F_end"])
    b.semilogy(Ks, d, "o-", color="k", ms=4)
    b.set_xticks(Ks)
    b.set_xlabel(f"K (finer of the two; waves to {angle[0]['problem'].basis.n} K)")
    b.set_ylabel("change of the force (relative)")
    b.set_title(f"(b) the angle, N = {angle[0]['N']}", fontsize=10)
    n = angle[0]["problem"].basis.n
    fig.suptitle(f"Paper's cap on its {n}-wave branch: convergence of the 3-D view", fontsize=10)
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    parser = study_parser("shell3d_convergence", "mesh convergence of the 3-D view on the paper's three-wave branch")
    parser.add_argument("--boundary", choices=tuple(BRANCHES), default="sliding",
                        help="the cap's edge: the paper's sliding edge (default) or clamped")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    plan = FULL if args.full else FAST
    waves, w_end = BRANCHES[args.boundary]
    t0 = time.perf_counter()
    meshes, K = plan["meridian"]
    meridian = []
    for N in meshes:
        say(args.quiet, f"meridian: N = {N}, K = {K}")
        meridian.append(three_wave_branch(N, K, w_end, args.boundary, waves=waves))
    N_angle, harmonics = plan["angle"]
    angle = []
    for k in harmonics:
        say(args.quiet, f"angle: N = {N_angle}, K = {k}")
        angle.append(three_wave_branch(N_angle, k, w_end, args.boundary, waves=waves))
    columns = ["N", "K", "w_bp", "F_end", "wave_amplitude", "points", "seconds"]
    rows = [{c: r[c] for c in columns} for r in meridian + angle]
    print_table(rows, columns, digits=9)
    write_csv(out / "shell3d_convergence.csv", rows, columns)
    dF, dw = differences([r["F_end"] for r in meridian]), differences([r["w_bp"] for r in meridian])
    dK = differences([r["F_end"] for r in angle])
    summary = {"boundary": args.boundary, "waves": waves, "w_end": w_end,
               "meridian": {"N": list(meshes), "K": K, "F_differences": dF, "F_orders": orders(dF),
                            "w_bp_differences": dw, "w_bp_orders": orders(dw)},
               "angle": {"N": N_angle, "K": list(harmonics), "F_differences": dK},
               "rows": rows, "wall_time_s": time.perf_counter() - t0,
               "command": "python -m studies.shell3d_convergence" + (" --full" if args.full else "")
               + (f" --boundary {args.boundary}" if args.boundary != "sliding" else "")}
    write_json(out / "summary.json", summary)
    save_figure(figure(meridian, angle), out, "convergence")
    say(args.quiet, "meridian: F differences " + ", ".join(f"{x:.3g}" for x in dF) + "; orders "
        + ", ".join(f"{x:.2f}" for x in orders(dF)) + "; w_bp orders " + ", ".join(f"{x:.2f}" for x in orders(dw)))
    say(args.quiet, "angle: F differences " + ", ".join(f"{x:.3g}" for x in dK))
    say(args.quiet, f"{time.perf_counter() - t0:.1f} s; outputs in {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
