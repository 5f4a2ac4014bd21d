"""Benchmark of the phase boundaries (issue 5, Speed): fold continuation against the grid route.

Run ``python -m studies.bench_phase_boundaries [--repeat 3] [--workers 2] [--N 200]``.

(a) Both boundaries over ``phi_hat`` in [0.5, 1.45] by fold continuation
    (:func:`studies.phase_diagram.trace_boundaries`, ``N = 200``), from scratch: median of
    ``--repeat`` in-process runs.  Target <= 60 s.
(b) The grid route at the resolution that places the ``h/R = 0.02`` boundaries to 1e-3 in
    ``phi_hat``: one row of cells at ``h/R = 0.02`` with spacing 2e-3 over [0.5, 1.45] (476 cells,
    each classified by ``contin classify``'s sweep on ``--workers`` processes); each boundary is then
    known to half a spacing.  Run once, after (a), in the same process.  This is the least a grid can
    do: a two-dimensional grid needs such a row for every ``h/R`` it resolves.

Prints both times, the boundaries' ``phi_hat`` at ``h/R = 0.02`` from each route and the ratio
grid / continuation.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from contin.sweep import run_sweep, sweep_scenes  # noqa: E402
from contin_models.shell_scene import SHELL_SCHEMA  # noqa: E402
from studies.phase_diagram import PHI_RANGE, phi_at_mark, trace_boundaries  # noqa: E402

SPACING = 2e-3
H_ROW = 0.02


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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--N", type=int, default=200)
    args = parser.parse_args()
    times, curves = [], None
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        curves = trace_boundaries(args.N)
        times.append(time.perf_counter() - t0)
    t_curve = statistics.median(times)
    phi_curve = {kind: phi_at_mark(c) for kind, c in curves.items()}
    print(f"(a) both boundaries by fold continuation, N = {args.N}: median {t_curve:.2f} s "
          f"(runs: {', '.join(f'{t:.2f}' for t in times)}); phi_hat at h/R = 0.02: "
          + ", ".join(f"{k} {v:.6f}" for k, v in phi_curve.items()))
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
