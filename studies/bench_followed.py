"""Benchmark: the followed path of a cap (``stability.follow = true``) against its axisymmetric trace, side by side.

Run ``python -m studies.bench_followed [--repeat 3] [--set KEY=VALUE ...]`` (default: the paper's cap at
``shell.phi_hat = 0.6``, its default mesh, ``view.harmonics`` at its default).  Each repetition runs, in this order
and in one process (warm imports, BLAS single-threaded): the axisymmetric trace (``stability.harmonics = false``),
the same with the harmonic blocks watched, and the followed path (which traces the axisymmetric path too, for
its figure, and then follows the stable path through the 3-D views).  It prints the median wall time and the median
processor time of this process (single-threaded BLAS: the work done, less disturbed by other work on the machine) of each,
the ratios of the followed path to both axisymmetric traces, and the followed path's pieces and snaps, so that a
change of speed can be told apart from a change of work.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from typing import Any  # noqa: E402

from studies._common import run_study  # noqa: E402

#: The scene of the acceptance: the paper's cap at phi_hat = 0.6 under the point load (displacement control).
DEFAULT_SETS = ("shell.phi_hat=0.6",)


def _timed(sets: list[str]) -> tuple[float, float, Any]:
    """Wall time, processor time of this process and the result of one run of the scene."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene.scene import SHELL_SCENE

    scene = load_scene(SHELL_SCENE.schema, None, ["output.figure=false", *sets])
    start, cpu = time.perf_counter(), time.process_time()
    result = SHELL_SCENE.run(scene, False)
    return time.perf_counter() - start, time.process_time() - cpu, result


def main(argv: list[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = argparse.ArgumentParser(prog="python -m studies.bench_followed", description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="repetitions (medians are quoted); default 3")
    parser.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                        help="scene keys as contin trace --set takes them (default shell.phi_hat=0.6)")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error(f"--repeat must be >= 1, got {args.repeat}")
    sets = list(args.sets) or list(DEFAULT_SETS)
    cases = {"axisymmetric": [*sets, "stability.harmonics=false"],
             "axisymmetric with harmonics": [*sets, "stability.harmonics=true"],
             "followed path": [*sets, "stability.harmonics=true", "stability.follow=true"]}
    _timed(cases["axisymmetric"])  # the imports a runner defers to its first call
    times: dict[str, list[float]] = {name: [] for name in cases}
    cpus: dict[str, list[float]] = {name: [] for name in cases}
    last: dict[str, Any] = {}
    for r in range(args.repeat):
        for name, keys in cases.items():
            wall, cpu, result = _timed(keys)
            times[name].append(wall)
            cpus[name].append(cpu)
            last[name] = result
            print(f"repeat {r + 1}: {name}: {wall:.2f} s wall, {cpu:.2f} s processor ({result.status})", flush=True)
    print(f"\nscene: {' '.join(sets)}; medians of {args.repeat} (wall, and this process's processor time, which "
          "other work on the machine disturbs less):")
    for kind, table in (("wall", times), ("processor", cpus)):
        med = {name: statistics.median(t) for name, t in table.items()}
        for name in cases:
            print(f"  {name:30s} {med[name]:8.2f} s {kind}")
        follow = med["followed path"]
        print(f"  {kind}: followed / axisymmetric: {follow / med['axisymmetric']:.1f}x; followed / axisymmetric with "
              f"harmonics: {follow / med['axisymmetric with harmonics']:.1f}x")
    followed = last["followed path"].summary.get("followed", {})
    for row in followed.get("branches", []):
        print(f"  piece {row['id']}: {row['symmetry']}, from {row['from']}, ended {row['ended']}, {row['points']} points")
    print(f"  {followed.get('message', '')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
