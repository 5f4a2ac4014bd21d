"""Benchmark: the default trace with harmonic stability on against the axisymmetric trace, side by side.

Run ``python -m studies.bench_harmonics [--repeat 5] [--n-max K]``.

Both are the scene runner in-process with warm imports, N = 200, BLAS single-threaded, run
alternately: the default scene (point load at the pole of the paper's cap, the whole path to
eversion) without and with ``stability.harmonics = true`` (the blocks n = 1 .. n_max watched at every
point, every bifurcation into a mode located; ``n_max`` 0 = the default rule).  Reported: the medians,
the median ratio of the pairs and its spread (the lowest and highest pair: the machine may be shared),
the points traced and the bifurcations located.  The target is a ratio of at most 3.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import statistics  # noqa: E402

from contin.app.scene import load_scene  # noqa: E402
from contin_models.shell_scene import SHELL_SCENE  # noqa: E402
from studies._common import alternate_timings  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = argparse.ArgumentParser(prog="python -m studies.bench_harmonics", description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="pairs of runs (default 5)")
    parser.add_argument("--n-max", type=int, default=0, help="stability.n_max (0: the default rule)")
    args = parser.parse_args(argv)
    plain = load_scene(SHELL_SCENE.schema, None, [])
    watched = load_scene(SHELL_SCENE.schema, None, ["stability.harmonics=true", f"stability.n_max={args.n_max}"])
    SHELL_SCENE.runner(plain, False)
    result = SHELL_SCENE.runner(watched, False)
    t_plain, t_watched = alternate_timings([lambda: SHELL_SCENE.runner(plain, False),
                                            lambda: SHELL_SCENE.runner(watched, False)], args.repeat)
    br = result.branches[0]
    modes = br.meta.get("modes", {}).get("n", {})
    n_bif = sum(1 for b in result.branches for s in b.special_points if s.kind == "bifurcation")
    print(f"axisymmetric trace: {statistics.median(t_plain):.3f} s median of {args.repeat}")
    print(f"with harmonics (n = 1..{len(modes.get('keys', []))}): {statistics.median(t_watched):.3f} s median "
          f"({len(br.p)} points, {n_bif} bifurcations located)")
    ratios = [b / a for a, b in zip(t_plain, t_watched)]
    print(f"ratio (median of pairs): {statistics.median(ratios):.2f} (pairs {min(ratios):.2f} .. {max(ratios):.2f})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
