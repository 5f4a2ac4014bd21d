"""Benchmark of the phase boundaries (issue 5, Speed): fold continuation against the grid route.

Run ``python -m studies.bench_phase_boundaries [--repeat 3] [--workers 2] [--N 200] [--baseline DIR] [--no-grid]``.

(a) Both boundaries over ``phi_hat`` in [0.5, 1.45] by fold continuation
    (:func:`studies.phase_diagram.trace_boundaries`, ``N = 200``), from scratch: median of
    ``--repeat`` in-process runs.  Target <= 60 s.  Also counted: the shell problems built on the way
    (:func:`contin_models.shell.boundaries.thickness_member`: a member of the families in ``ln h`` and
    ``phi_hat`` for every state and finite-difference neighbour the continuation evaluates).
    With ``--baseline DIR`` (a checkout of another version, e.g. ``git worktree add /tmp/base REV``)
    each repetition runs (a) in a fresh process of each tree, alternating, so that both see the same
    load of a shared machine, and the medians and their ratio are printed.
(b) The grid route at the resolution that places the ``h/R = 0.02`` boundaries to 1e-3 in
    ``phi_hat``: one row of cells at ``h/R = 0.02`` with spacing 2e-3 over [0.5, 1.45] (476 cells,
    each classified by ``contin classify``'s sweep on ``--workers`` processes); each boundary is then
    known to half a spacing.  Run once, after (a), in the same process (not with ``--no-grid``).  This
    is the least a grid can do: a two-dimensional grid needs such a row for every ``h/R`` it resolves.

Prints both times, the boundaries' ``phi_hat`` at ``h/R = 0.02`` from each route and the ratio
grid / continuation.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import inspect  # noqa: E402
import json  # noqa: E402
import shutil  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from contin.app.sweep import run_sweep, sweep_scenes  # noqa: E402
from contin_models.shell_scene import SHELL_SCHEMA  # noqa: E402
from studies.bench_side_by_side import ROOT, _import_path  # noqa: E402
from studies.phase_diagram import PHI_RANGE  # noqa: E402

SPACING = 2e-3
H_ROW = 0.02

def counted_trace(N: int) -> dict:
    """Part (a) once: its wall and CPU time, the shell problems built, ``phi_hat`` at ``h/R = 0.02`` of each boundary.

    Self-contained (its source runs in a fresh process of another checkout as well, :func:`trace_once`).
    """
    import time

    import contin_models.shell.boundaries as boundaries
    from studies.phase_diagram import phi_at_mark, trace_boundaries

    built = [0]
    member = boundaries.thickness_member

    def counted(*args, **kwargs):
        built[0] += 1
        return member(*args, **kwargs)

    boundaries.thickness_member = counted
    try:
        wall, cpu = time.perf_counter(), time.process_time()
        curves = trace_boundaries(N)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    finally:
        boundaries.thickness_member = member
    return {"wall": wall, "cpu": cpu, "built": built[0], "phi": {kind: phi_at_mark(c) for kind, c in curves.items()}}


def trace_once(N: int, tree: Path, shims: Path) -> dict:
    """:func:`counted_trace` in a fresh process importing ``tree`` (its engine, models and studies)."""
    code = f"import json\n{inspect.getsource(counted_trace)}\nprint(json.dumps(counted_trace({int(N)})))\n"
    env = dict(os.environ, PYTHONPATH=_import_path(tree, shims))
    done = subprocess.run([sys.executable, "-c", code], cwd="/", env=env, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"the boundaries of {tree} failed:\n{done.stderr.strip()}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def grid_row(N: int, workers: int) -> tuple[float, dict[str, float]]:
    """Classify the ``h/R = 0.02`` row; return its time and each boundary from adjacent cells."""
    phis = np.round(np.arange(PHI_RANGE[0], PHI_RANGE[1] + SPACING / 2, SPACING), 10)
    combos = sweep_scenes(SHELL_SCHEMA, [("shell.phi_hat", [float(p) for p in phis])],
                          overrides=[f"shell.N={N}", f"shell.h={H_ROW}"])
    t0 = time.perf_counter()
    rows = run_sweep("shell", combos, csv_path=None, workers=workers, progress=False)
    wall = time.perf_counter() - t0
    labels = [r.get("label") for r in rows]
    found: dict[str, float] = {}
    for a, b, pa, pb in zip(labels, labels[1:], phis, phis[1:]):
        if a == "bistable" and b == "monostable":
            found["bistable"] = 0.5 * (pa + pb)
        if a == "monostable" and b == "monotonous":
            found["monotonous"] = 0.5 * (pa + pb)
    found["unclassified"] = float(sum(lab is None for lab in labels))
    return wall, found


def side_by_side(N: int, repeat: int, baseline: Path) -> dict:
    """Part (a) in fresh processes of this tree and of ``baseline``, alternating; prints their medians."""
    runs: dict[str, list[dict]] = {"this": [], "baseline": []}
    shims = Path(tempfile.mkdtemp(prefix="contin_bench_"))
    try:
        for i in range(repeat):
            for label, tree in (("this", ROOT), ("baseline", baseline.resolve())):
                runs[label].append(trace_once(N, tree, shims))
            print(f"[{i + 1}/{repeat}] this {runs['this'][-1]['wall']:.2f} s, "
                  f"baseline {runs['baseline'][-1]['wall']:.2f} s", file=sys.stderr)
    finally:
        shutil.rmtree(shims, ignore_errors=True)
    med = {label: {k: statistics.median(r[k] for r in rs) for k in ("wall", "cpu")} for label, rs in runs.items()}
    for label, rs in runs.items():
        print(f"(a) {label:9s} N = {N}: median wall {med[label]['wall']:.2f} s, cpu {med[label]['cpu']:.2f} s; "
              f"{rs[0]['built']} shell problems built; phi_hat at h/R = 0.02: "
              + ", ".join(f"{k} {v:.9f}" for k, v in rs[0]["phi"].items()))
    print(f"    ratio this/baseline: wall {med['this']['wall'] / med['baseline']['wall']:.3f}, "
          f"cpu {med['this']['cpu'] / med['baseline']['cpu']:.3f}")
    return runs["this"][0]["phi"] | {"wall": med["this"]["wall"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--N", type=int, default=200)
    parser.add_argument("--baseline", type=Path, default=None,
                        help="checkout to time part (a) against, side by side in fresh processes")
    parser.add_argument("--no-grid", action="store_true", help="skip part (b), the grid row")
    args = parser.parse_args()
    if args.baseline is not None:
        found = side_by_side(args.N, args.repeat, args.baseline)
        t_curve, phi_curve = found.pop("wall"), found
    else:
        runs = [counted_trace(args.N) for _ in range(args.repeat)]
        t_curve = statistics.median(r["wall"] for r in runs)
        phi_curve = runs[-1]["phi"]
        times = ", ".join(f"{r['wall']:.2f}" for r in runs)
        print(f"(a) both boundaries by fold continuation, N = {args.N}: median {t_curve:.2f} s (runs: {times}); "
              f"{runs[-1]['built']} shell problems built; phi_hat at h/R = 0.02: "
              + ", ".join(f"{k} {v:.6f}" for k, v in phi_curve.items()))
    if args.no_grid:
        return
    t_grid, found = grid_row(args.N, args.workers)
    n_cells = int(round((PHI_RANGE[1] - PHI_RANGE[0]) / SPACING)) + 1
    print(f"(b) grid row h/R = 0.02, {n_cells} cells at spacing {SPACING}, {args.workers} workers: {t_grid:.1f} s; "
          + ", ".join(f"{k} {v:.4f}" for k, v in found.items()))
    for kind in ("bistable", "monotonous"):
        if kind in found:
            print(f"    {kind}: grid {found[kind]:.4f} vs traced {phi_curve[kind]:.6f} "
                  f"(difference {abs(found[kind] - phi_curve[kind]):.1e}, half spacing {SPACING / 2:.0e})")
    print(f"ratio grid row / continuation: {t_grid / t_curve:.1f}")


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
