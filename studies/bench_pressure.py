"""Benchmark: a pressure trace of a clamped cap past its snap against the default point trace, side by side.

Run ``python -m studies.bench_pressure [--repeat 7] [--json PATH]``.

Both are the scene runner in-process with warm imports (``contin trace``'s work without writing
files), N = 200, BLAS single-threaded, run alternately so that the machine's load falls on both:

* ``point``: the default scene (point load at the pole of the sliding cap, the whole path to
  eversion with every fold and extremum located and both controls' stability);
* ``pressure``: the same cap clamped under a prescribed pressure (``load.kind = "pressure"``,
  ``load.control = "force"``, ``shell.boundary = "clamped"``), from ``p = 0`` through its snap and
  every later fold to ``load.p_end_over_p_c = 2``.

Reported: the median of each and the median of the per-pair ratios pressure / point (issue 16's
target: at most 1).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
from typing import Any  # noqa: E402

from contin.app.scene import load_scene  # noqa: E402
from contin_models.shell_scene import SHELL_SCENE  # noqa: E402
from studies._common import alternate_timings, write_text  # noqa: E402

PRESSURE_SCENE = ["load.kind=pressure", "load.control=force", "shell.boundary=clamped"]


def bench(repeat: int) -> dict[str, Any]:
    """Alternate the two runs ``repeat`` times after one warm-up each."""
    point = load_scene(SHELL_SCENE.schema, None, [])
    pressure = load_scene(SHELL_SCENE.schema, None, PRESSURE_SCENE)
    SHELL_SCENE.runner(point, False)
    result = SHELL_SCENE.runner(pressure, False)
    t_point, t_pressure = alternate_timings([lambda: SHELL_SCENE.runner(point, False),
                                             lambda: SHELL_SCENE.runner(pressure, False)], repeat)
    br = result.branches[0]
    return {"repeat": repeat, "point_median_s": statistics.median(t_point),
            "pressure_median_s": statistics.median(t_pressure),
            "ratio_median": statistics.median(b / a for a, b in zip(t_point, t_pressure)),
            "point_runs_s": t_point, "pressure_runs_s": t_pressure, "pressure_scene": PRESSURE_SCENE,
            "pressure_points": len(br.p), "pressure_message": br.message,
            "p_snap_over_p_c": result.summary.get("p_snap_over_p_c"), "n_folds_in_p": result.summary.get("n_folds_in_p")}


def main(argv: list[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = argparse.ArgumentParser(prog="python -m studies.bench_pressure", description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="pairs of runs (default 7)")
    parser.add_argument("--json", default=None, metavar="PATH", help="also write the results as JSON")
    args = parser.parse_args(argv)
    out = bench(args.repeat)
    print(f"point trace (default scene):      {out['point_median_s']:.3f} s median of {args.repeat}")
    print(f"pressure trace (clamped, to 2 p_c): {out['pressure_median_s']:.3f} s median "
          f"({out['pressure_points']} points, {out['n_folds_in_p']} folds in p, snap at p/p_c = "
          f"{out['p_snap_over_p_c']:.4f})")
    print(f"ratio pressure / point (median of pairs): {out['ratio_median']:.3f}")
    if args.json:
        write_text(args.json, json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
