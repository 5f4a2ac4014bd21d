"""The cost of the shell's 3-D view (:mod:`contin_models.shell.fourier`): Newton steps, symmetry, a traced branch.

Run ``python -m studies.bench_shell3d [--out DIR] [--full] [--quiet] [--repeat R] [--only PART ...]``.

Four measurements (``--only``: some of them), each the median of ``--repeat`` runs in this process:

* **A Newton step against N** (``steps``): the paper's cap (``phi_hat = 0.8``, h/R = 0.02, nu = 0.5,
  sliding edge) in the ``D_3`` basis with ``K`` harmonics, at a state on the way down under the pole's
  deflection: assembling the Jacobian, factoring it (banded Cholesky, the banded LU where it is not positive
  definite) and solving, for N = 100, 200, 400, 800.
  At a fixed angular resolution the step should grow as O(N): the time per node is reported.
* **The symmetry's gain** (``symmetry``): the pinched open hemisphere of :mod:`studies.pinched_hemisphere`
  at P = 200 solved in its ``D_2`` basis and, from that state perturbed off the symmetry, by Newton's
  method in the basis without any symmetry (the same waves, the same angles): the largest difference of
  the two states and the time of a Newton step in each.
* **A traced branch** (``branch``): the paper's cap at N = 200 in the ``D_3`` basis, traced from the
  unloaded cap (displacement control, stability watched) to its first branch point, then along the
  three-wave branch to ``w = 0.37 R`` (:func:`studies.shell3d_convergence.three_wave_branch`); beside it
  the axisymmetric trace of the same cap (the traced 1-D model, the same settings) to the same
  deflection.  Both count the Morse index at every point and store no eigenvalues (``n_eigs = 0``: the
  three smallest of a banded matrix cost a reduction to tridiagonal form, 8 Newton steps of the 3-D view
  at N = 100).  The ratio of their times is the cost of the 3-D view on this path; beside it the
  factorizations each run took, and the floor: one Newton step of each model at the end of its path,
  and their ratio (``floor``), which a 3-D trace with as many Newton steps as the axisymmetric one
  would cost.

* **Stability against every class** (``every_mode``): the paper's cap in the ``D_3`` basis traced from the
  unloaded cap to ``w = 0.37 R`` (the axisymmetric path, displacement control, no branch switch) with and
  without ``every_mode`` (:class:`contin_models.shell.problem3d.Shell3D`: the Bloch blocks of the classes
  ``A2`` and ``E1`` counted at every point, a change of a count located); beside the two times, the
  family's own cost per point, at up to 10 points of the plain trace (each point once per repeat, so that
  no cache of the last state answers): building both blocks (:meth:`~contin.OperatorFamily.operators`),
  and counting them with the eigenvalue estimate the engine makes per point
  (:func:`contin.watch.modes.count_and_lowest`).

Outputs in ``--out`` (default ``out/bench_shell3d``): ``summary.json``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from studies._common import output_dir, print_table, run_study, say, study_parser, write_json  # noqa: E402

#: The three-wave basis of the paper's cap: harmonics of ``D_3`` (waves ``0, 3, ..., 3 K``); ``K = 3`` puts the
#: load on the branch within 1e-5 of its angular limit (:mod:`studies.shell3d_convergence`).
WAVES, HARMONICS = 3, 3
#: Where the traced branch stops.
W_END = 0.37


def median_time(call: Callable[[], Any], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        call()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def cap(N: int) -> Any:
    from studies.shell3d_convergence import paper_cap

    return paper_cap(N)


def newton_step(prob: Any, u: np.ndarray, p: float) -> np.ndarray:
    """One Newton step of the problem at ``(u, p)``: residual, Jacobian, its factorization, solve."""
    r = prob.residual(u, p)
    return prob.factorize(prob.jacobian(u, p)).solve(-r)


def steps(meshes: Sequence[int], repeat: int) -> list[dict[str, Any]]:
    from contin_models.shell.fourier import AngularBasis
    from contin_models.shell.problem3d import Shell3D

    rows = []
    for N in meshes:
        prob = Shell3D(cap(N), AngularBasis(WAVES, HARMONICS), "point", "displacement")
        rng = np.random.default_rng(0)
        u = prob.reference_unknowns() + 1e-4 * rng.standard_normal(prob.n)  # not axisymmetric: every term works
        newton_step(prob, u, 0.1)  # the first call builds the caches (maps, pattern, slots)
        seconds = median_time(lambda: newton_step(prob, u + 1e-12 * rng.standard_normal(prob.n), 0.1), repeat)
        rows.append({"N": N, "unknowns": prob.n, "band": prob.kl, "step_ms": 1e3 * seconds,
                     "per_node_us": 1e6 * seconds / N})
    return rows


def symmetry(repeat: int, N: int = 24, K: int = 8) -> dict[str, Any]:
    from contin_models.shell.fourier import AngularBasis
    from contin_models.shell.problem3d import Shell3D
    from studies.pinched_hemisphere import hemisphere

    sym = hemisphere(N, K)
    load = 200.0
    br = contin.continuation(sym, sym.reference_unknowns(), 0.0, p_max=load, ds=5.0, ds_max=40.0, max_steps=500)
    if br.status != "bound":
        raise RuntimeError(f"bench_shell3d: the D_2 trace stopped before P = {load:g}: {br.message}")
    c_sym = sym.full_state(br.u[-1], load)
    basis = AngularBasis(1, 2 * K, mirror=False, M=sym.basis.M)
    full = Shell3D(sym.structure, basis, "forces", forces=[(f[0], f[1], f[2]) for f in sym.forces])
    lift = np.zeros(full.view.size)
    for j, term in enumerate(sym.basis.terms):
        lift[full.basis.index(*term)::full.view.m] = c_sym[j::sym.view.m]
    u = full.unknowns(lift) + 1e-6 * np.random.default_rng(1).standard_normal(full.n)
    iterations = 0
    for iterations in range(1, 31):
        du = newton_step(full, u, load)
        u = u + du
        if np.max(np.abs(du)) < 1e-12 * sym.structure.meridian.length_scale:
            break
    difference = float(np.max(np.abs(full.full_state(u, load) - lift)))
    u_sym = br.u[-1]
    t_sym = median_time(lambda: newton_step(sym, u_sym, load), repeat)
    t_full = median_time(lambda: newton_step(full, u, load), repeat)
    return {"N": N, "K": K, "M": sym.basis.M, "unknowns_D2": sym.n, "unknowns_none": full.n,
            "newton_iterations": iterations, "largest_difference": difference, "step_ms_D2": 1e3 * t_sym,
            "step_ms_none": 1e3 * t_full, "ratio": t_full / t_sym}


def branch(N: int, repeat: int) -> dict[str, Any]:
    from contin_models.shell.structure import ShellOfRevolution
    from studies.shell3d_convergence import three_wave_branch

    st = cap(N)

    def axisymmetric() -> Any:
        prob = ShellOfRevolution(st, "point", "displacement")
        return contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=W_END, ds=0.01, ds_max=0.02,
                                   max_steps=2000, stability=True, n_eigs=0)

    t_axi = median_time(axisymmetric, repeat)
    t_3d = median_time(lambda: three_wave_branch(N, HARMONICS, W_END, n_eigs=0), max(1, repeat // 2))
    run = three_wave_branch(N, HARMONICS, W_END, n_eigs=0)
    ax = axisymmetric()
    # the floor: one Newton step of each at the end of its path (a fresh state each time, so that no
    # cache of the last state answers)
    rng = np.random.default_rng(2)
    prob3, prob1 = run["problem"], ShellOfRevolution(st, "point", "displacement")
    states = [(prob3, run["second"].u[-1], float(run["second"].p[-1])), (prob1, ax.u[-1], float(ax.p[-1]))]
    step_3d, step_1d = (median_time(lambda: newton_step(prob, u + 1e-13 * rng.standard_normal(u.size), w),
                                    10 * repeat) for prob, u, w in states)
    n_3d = run["first"].meta["n_factorizations"] + run["second"].meta["n_factorizations"]
    return {"N": N, "K": HARMONICS, "w_branch_point": run["w_bp"], "w_end": W_END, "points_3d": run["points"],
            "points_axisymmetric": len(ax.p), "factorizations_3d": n_3d,
            "factorizations_axisymmetric": ax.meta["n_factorizations"], "seconds_3d": t_3d,
            "seconds_axisymmetric": t_axi, "ratio": t_3d / t_axi,
            "ratio_per_point": (t_3d / run["points"]) / (t_axi / len(ax.p)),
            "newton_step_ms_3d": 1e3 * step_3d, "newton_step_ms_axisymmetric": 1e3 * step_1d,
            "floor": step_3d / step_1d}


def every_mode(N: int, repeat: int) -> dict[str, Any]:
    from contin.watch.modes import count_and_lowest
    from contin_models.shell.fourier import AngularBasis
    from contin_models.shell.problem3d import Shell3D

    st = cap(N)
    problems = {flag: Shell3D(st, AngularBasis(WAVES, HARMONICS), "point", "displacement", every_mode=flag)
                for flag in (False, True)}

    def trace(flag: bool) -> Any:
        prob = problems[flag]
        return contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=W_END, ds=0.01, ds_max=0.02,
                                   max_steps=2000, stability=True, n_eigs=0)

    runs = {flag: trace(flag) for flag in (False, True)}
    for flag, run in runs.items():
        if run.status != "bound":
            raise RuntimeError(f"bench_shell3d: the D_3 trace (every_mode={flag}) stopped before w = {W_END}: "
                               f"{run.message}")
    seconds = {flag: median_time(lambda flag=flag: trace(flag), max(1, repeat // 2)) for flag in (False, True)}
    family = problems[True].operator_families[0]
    plain = runs[False]
    points = [(plain.u[i], float(plain.p[i])) for i in np.unique(np.linspace(0, len(plain.p) - 1, 10).astype(int))]
    build, count = [], []
    for _ in range(repeat):
        for u, p in points:
            t0 = time.perf_counter()
            operators = family.operators(u, p)
            t1 = time.perf_counter()
            for K in operators:
                count_and_lowest(K)
            build.append(t1 - t0)
            count.append(time.perf_counter() - t1)
    located = [s for s in runs[True].special_points if s.kind == "bifurcation"]
    return {"N": N, "K": HARMONICS, "w_end": W_END, "keys": list(family.keys),
            "block_sizes": [int(K.shape[0]) for K in family.operators(*points[-1])],
            "points_plain": len(plain.p), "points_every_mode": len(runs[True].p),
            "bifurcations": len(located), "unlocated": sum(not s.located for s in located),
            "seconds_plain": seconds[False], "seconds_every_mode": seconds[True],
            "ratio": seconds[True] / seconds[False],
            "family_build_ms": 1e3 * float(np.median(build)), "family_count_ms": 1e3 * float(np.median(count))}


#: The measurements by name, in the order they run (``--only`` picks some).
PARTS = ("steps", "symmetry", "branch", "every_mode")


def main(argv: Sequence[str] | None = None) -> int:
    parser = study_parser("bench_shell3d", "the cost of the shell's 3-D view")
    parser.add_argument("--repeat", type=int, default=5, help="runs per timing (the median is reported)")
    parser.add_argument("--only", nargs="+", choices=PARTS, default=PARTS, metavar="PART",
                        help=f"run only these measurements (of {', '.join(PARTS)})")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    summary: dict[str, Any] = {}
    if "steps" in args.only:
        say(args.quiet, "Newton steps against N")
        summary["steps"] = rows = steps((100, 200, 400, 800) if args.full else (100, 200, 400), args.repeat)
        print_table(rows, ["N", "unknowns", "band", "step_ms", "per_node_us"], digits=4)
    if "symmetry" in args.only:
        say(args.quiet, "the symmetry's gain (pinched hemisphere, D_2 against no symmetry)")
        summary["symmetry"] = sym = symmetry(args.repeat)
        print_table([sym], list(sym), digits=4)
    if "branch" in args.only:
        say(args.quiet, "a traced branch of the paper's cap against its axisymmetric trace")
        summary["branch"] = br = branch(200 if args.full else 100, args.repeat)
        print_table([br], list(br), digits=4)
    if "every_mode" in args.only:
        say(args.quiet, "stability against every class: the D_3 trace with every_mode against without")
        summary["every_mode"] = every = every_mode(200 if args.full else 100, args.repeat)
        print_table([every], [k for k in every if k not in ("keys", "block_sizes")], digits=4)
    command = "python -m studies.bench_shell3d" + (" --full" if args.full else "")
    if tuple(args.only) != PARTS:
        command += " --only " + " ".join(args.only)
    write_json(out / "summary.json", {**summary, "repeat": args.repeat, "wall_time_s": time.perf_counter() - t0,
                                      "command": command})
    say(args.quiet, f"{time.perf_counter() - t0:.1f} s; outputs in {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
