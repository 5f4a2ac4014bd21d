"""Benchmark: how much of the default trace is kernels and LAPACK, the floor with today's work (issue 18).

Run ``python -m studies.bench_floor [--repeat 3]``.

The default scene is traced in-process with warm imports (one untimed run first).  During the timed
runs every call of the shell's generated element kernels (:mod:`contin_models.shell._generated`) and of
the LAPACK routines the trace uses (``dgbtrf``, ``dgbtrs``, ``dpbtrf``, ``dgttrf``, ``dgttrs``) is
counted and timed by a wrapper, and so is every call of the engine's C banded factorizations
(``contin.numerics._banded``: the stability counts' pivot-free ``L D L^T``, the tridiagonal LU) where
built.  Their sum is the time the trace would take if everything around them cost nothing: the floor for
this work with these kernels.  The table gives, per routine, the calls and the time of the median run,
and the trace's wall time beside the floor.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import collections  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

from studies._common import run_study  # noqa: E402

#: the LAPACK routines of a shell trace (banded LU, its solves, the stability counts' Cholesky pieces)
LAPACK = ("dgbtrf", "dgbtrs", "dpbtrf", "dgttrf", "dgttrs")


def _timed(fn: Callable, key: str, calls: collections.Counter, seconds: collections.Counter) -> Callable:
    def wrapper(*args, **kwargs):
        start = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            seconds[key] += time.perf_counter() - start
            calls[key] += 1
    return wrapper


def main(argv: list[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = argparse.ArgumentParser(prog="python -m studies.bench_floor", description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed runs (default 3; the median is shown)")
    args = parser.parse_args(argv)

    from scipy.linalg import lapack

    from contin.app.scene import load_scene
    from contin_models import shell_scene
    from contin_models.shell.energy import kernels as gen

    calls: collections.Counter = collections.Counter()
    seconds: collections.Counter = collections.Counter()
    # the shell energy looks its kernels up when it is built, so wrapping them before the runs is enough
    for name in [n for n in dir(gen) if "_fast_" in n and ("gradient" in n or "hessian" in n)]:
        setattr(gen, name, _timed(getattr(gen, name), name, calls, seconds))
    for name in LAPACK:
        setattr(lapack, name, _timed(getattr(lapack, name), name, calls, seconds))
    from contin.numerics.linalg import banded_extension

    banded = banded_extension()
    if banded is not None:  # looked up on the module at each call, like the LAPACK routines
        for name in ("factor", "solve", "ldlt_negative"):
            setattr(banded, name, _timed(getattr(banded, name), f"_banded.{name}", calls, seconds))
    model = shell_scene.SHELL_SCENE
    scene = load_scene(model.schema, None, ["output.figure=false"])
    model.run(scene, False)
    runs = []
    for _ in range(args.repeat):
        calls.clear()
        seconds.clear()
        start = time.perf_counter()
        model.run(scene, False)
        runs.append((time.perf_counter() - start, dict(calls), dict(seconds)))
    wall, calls_m, seconds_m = sorted(runs, key=lambda r: r[0])[len(runs) // 2]
    floor = sum(seconds_m.values())
    print(f"default trace, N = 200, median of {args.repeat} warm runs: {wall:.3f} s "
          f"(all runs {', '.join(f'{r[0]:.3f}' for r in runs)})")
    print(f"{'routine':36s} {'calls':>7s} {'time':>9s} {'per call':>10s}")
    for key in sorted(seconds_m, key=seconds_m.get, reverse=True):
        print(f"{key:36s} {calls_m[key]:7d} {seconds_m[key]:8.3f}s {1e6 * seconds_m[key] / calls_m[key]:8.1f}us")
    print(f"kernels, LAPACK and C factorizations: {floor:.3f} s of {wall:.3f} s ({100 * floor / wall:.0f} %); "
          f"the rest, {wall - floor:.3f} s, is Python and numpy around them")
    print(f"the floor's median over the runs: {statistics.median(sum(r[2].values()) for r in runs):.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))
