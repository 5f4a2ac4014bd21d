"""Benchmark of the contact snap (issue 4, Speed): one sphere indentation and the eight-radius sweep.

Run ``python -m studies.bench_contact [--repeat 5] [--workers 2]``.  Medians of in-process wall times
(imports warm, one untimed warm-up run first):

(a) one sphere indentation, ``N = 200``, ``r/R = 0.5``: continuation from the first touch of the barrier
    through the located snap (the fold in ``w_b``, located by the engine or, beyond the ``F -> 0``
    event, as a release fold, exactly as :func:`contin_models.shell_scene.contact.run_contact`) and the jump to the everted state; it stops right after
    the jump.  Target <= 1 s.
(b) the eight-radius sweep of issue 4 test 4 (``r/R`` in :data:`RADII`), each radius continued to its
    snap (no jump), spread over ``--workers`` processes.  Target <= 10 s.

Both use the settings the CLI builds for a sphere scene (:func:`snap_settings`, the scene defaults with
``shell.N`` and ``load.radius`` set); ``--no-stability`` drops the stability counts along the path (the
snap location does not depend on them).  The helpers :func:`run_to_snap` and :func:`snap_record` are
also used by ``tests/test_contact_paper.py``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from concurrent.futures import ProcessPoolExecutor  # noqa: E402
from typing import Any  # noqa: E402

import contin  # noqa: E402
from contin.app.scene import load_scene  # noqa: E402
from contin_models.contact.indentation import ShellIndentation  # noqa: E402
from contin.analyses.quasistatic import leave_fold  # noqa: E402
from contin_models.shell_scene import SHELL_SCHEMA, contact_problem, contact_settings  # noqa: E402
from contin_models.shell_scene.contact import MAX_SNAPS, contact_mode, snap_event, snap_point, snap_rules  # noqa: E402

#: r/R of issue 4 test 4 (paper figures 6, 7)
RADII = (0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5, 2.0)


def snap_settings(r: float, N: int, extra: tuple[str, ...] = (), stability: bool = True
                  ) -> tuple[ShellIndentation, contin.Settings, float]:
    """The problem, the continuation settings and ``w_end`` that ``contin trace`` builds for a sphere scene.

    The settings are :func:`contin_models.shell_scene.contact_settings`, as ``contin trace`` uses; ``extra`` are further ``--set`` overrides such as ``"contact.dhat=1e-4"``.
    """
    load = ["load.kind=plate"] if r is None else ["load.kind=sphere", f"load.radius={r}"]
    scene = load_scene(SHELL_SCHEMA, None, [*load, f"shell.N={N}", *extra])
    st, w_end = contact_settings(scene, stability=stability)
    return contact_problem(scene), st, w_end


def run_to_snap(problem: ShellIndentation, st: contin.Settings, w_end: float
                ) -> tuple[contin.Branch, contin.SpecialPoint | None]:
    """The runner's first loading stretch, from the first touch to its snap (:func:`snap_point`)."""
    br = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, stop_at=("fold",), p_max=w_end,
                             events=[snap_event(problem)], bounds={"base_gap": (2.0 * problem.dhat, None)})
    return br, snap_point(problem, br, st.tol)


def _snap_to_eversion(P: ShellIndentation, st: contin.Settings, w_end: float
                      ) -> tuple[contin.Branch, contin.SpecialPoint]:
    """The plate's path through its dimple snaps (at a finite force) to the eversion snap (F -> 0).

    The runner's load-snap loop (:func:`contin.quasistatic` with the contact's snap rules), stopped
    after the snap whose force had fallen to ~0; the last stretch and that snap are returned.
    """
    def everted(jr: contin.JumpResult) -> str | None:
        return "everted" if P.evaluate_one("F_norm", jr.u_from, jr.info["fold_p"]) <= 1e-3 else None

    qs = contin.quasistatic(P, P.reference_unknowns(), 0.0, w_end, st, max_snaps=MAX_SNAPS, snap=snap_rules(P),
                            locate_snap=lambda br: snap_point(P, br, st.tol), stop_after_jump=everted,
                            stop_at_branch_points=False, check_stability=False, events=[snap_event(P)],
                            bounds={"base_gap": (2.0 * P.dhat, None)})
    if qs.status != "completed" or not qs.folds:
        raise RuntimeError(f"plate: no eversion snap ({qs.status}: {qs.message})")
    return qs.branches[-1], qs.folds[-1]


def snap_record(r: float | None, N: int = 200, extra: tuple[str, ...] = (), stability: bool = False,
                gap_tol: float = 0.0) -> dict[str, Any]:
    """Run one radius to its snap; the snap's observables, the contact mode and the wall time."""
    t0 = time.perf_counter()
    P, st, w_end = snap_settings(r, N, extra, stability)
    br, sp = run_to_snap(P, st, w_end)
    dt = time.perf_counter() - t0
    if sp is None:
        raise RuntimeError(f"r/R = {r}: no snap ({br.status}: {br.message})")
    if r is None and sp.kind == "fold" and sp.observables["F_norm"] > 1e-3:
        # the plate's first snaps are dimple snaps at a finite force: follow them to eversion
        br, sp = _snap_to_eversion(P, st, w_end)
        dt = time.perf_counter() - t0
    obs = sp.observables
    mode, max_gap = contact_mode(list(br.observable("Delta_H")) + [obs["Delta_H"]], gap_tol)
    return {"r": r, "N": N, "status": br.status, "snap_kind": sp.kind, "end": sp.kind + (f" {sp.label}" if sp.label else ""),
            "w_b_c": float(sp.p), "w_b_c_over_R": float(obs["w_b_over_R"]), "F_norm": float(obs["F_norm"]),
            "Delta_H_over_R": float(obs["Delta_H_over_R"]), "kappa_p_R": float(obs["kappa_p_R"]),
            "w_s_over_R": float(obs["w_s_over_R"]), "n_contact": int(obs["n_contact"]), "mode": mode,
            "max_gap_before_over_R": max_gap / P.R, "dhat": P.dhat, "K": P.K, "points": len(br.p),
            "time": dt}


def _sweep_one(args: tuple[float, int, bool]) -> dict[str, Any]:
    r, N, stability = args
    return snap_record(r, N, stability=stability)


def sweep(N: int = 200, radii: tuple[float, ...] = RADII, workers: int = 2, stability: bool = False,
          pool: ProcessPoolExecutor | None = None) -> list[dict[str, Any]]:
    """Snap records for every radius, over ``workers`` processes (largest radii, the slowest, first)."""
    order = sorted(radii, reverse=True)
    jobs = [(r, N, stability) for r in order]
    if workers <= 1:
        recs = [_sweep_one(j) for j in jobs]
    elif pool is not None:
        recs = list(pool.map(_sweep_one, jobs))
    else:
        with ProcessPoolExecutor(max_workers=workers) as ex:
            recs = list(ex.map(_sweep_one, jobs))
    return sorted(recs, key=lambda d: d["r"])


def one_indentation(N: int = 200, r: float = 0.5, stability: bool = True) -> dict[str, Any]:
    """(a): first touch -> located snap -> jump to the everted state; stops right after the jump."""
    P, st, w_end = snap_settings(r, N, stability=stability)
    br, sp = run_to_snap(P, st, w_end)
    if sp is None:
        raise RuntimeError(f"r/R = {r}: no snap ({br.status}: {br.message})")
    jr, reasons = leave_fold(P, sp, +1, st, snap_rules(P))
    if jr is None:
        raise RuntimeError(f"r/R = {r}: the jump failed ({'; '.join(reasons)})")
    return {"w_b_c_over_R": float(sp.p) / P.R,
            "w_s_after_over_R": P.evaluate_one("w_s", jr.u_to, jr.p) / P.R}


def _median_time(fn, repeat: int) -> tuple[float, list[float]]:
    fn()  # warm-up (imports, generated code, caches)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5, help="timed repetitions (median reported)")
    ap.add_argument("--N", type=int, default=200, help="nodes on the meridian")
    ap.add_argument("--workers", type=int, default=2, help="processes for the sweep")
    ap.add_argument("--no-stability", action="store_true", help="no stability counts along the paths")
    args = ap.parse_args(argv)
    stab = not args.no_stability
    cmd = "python -m studies.bench_contact " + " ".join(argv if argv is not None else sys.argv[1:])
    info = one_indentation(args.N, stability=stab)
    ta, _ = _median_time(lambda: one_indentation(args.N, stability=stab), args.repeat)
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        recs = sweep(args.N, workers=args.workers, stability=stab, pool=pool)  # also warms the workers
        tb, _ = _median_time(lambda: sweep(args.N, workers=args.workers, stability=stab, pool=pool), args.repeat)
    serial = sum(d["time"] for d in recs)
    print(f"`{cmd.strip()}` (N = {args.N}, stability {'on' if stab else 'off'}, median of {args.repeat}, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')})\n")
    print("| case | median wall time [s] | target [s] |")
    print("|---|---:|---:|")
    print(f"| (a) sphere r/R = 0.5: first touch -> snap (w_b^c/R = {info['w_b_c_over_R']:.6f}) -> jump "
          f"(w_s/R = {info['w_s_after_over_R']:.4f}) | {ta:.3f} | 1 |")
    print(f"| (b) eight-radius sweep to the snap, {args.workers} processes | {tb:.3f} | 10 |")
    print(f"\nsweep per radius (one run, serial sum {serial:.2f} s; the plate, not in the sweep, follows its dimple "
          "snaps to the eversion snap):\n")
    print("| r/R | w_b^c/R | Delta_H/R at snap | kappa_p R | mode | max gap before snap / R | end | time [s] |")
    print("|---:|---:|---:|---:|---|---:|---|---:|")
    recs.append(snap_record(None, args.N, stability=stab))
    for d in recs:
        print(f"| {d['r'] or 'plate'} | {d['w_b_c_over_R']:.6f} | {d['Delta_H_over_R']:.4e} | {d['kappa_p_R']:.5f} | "
              f"{d['mode']} | {d['max_gap_before_over_R']:.2e} | {d['end']} | {d['time']:.2f} |")
    return 0


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
