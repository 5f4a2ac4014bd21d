"""Benchmark: the default shell trace (or Bratu) of this tree against another checkout, side by side in one run.

Run ``python -m studies.bench_side_by_side --baseline DIR [--repeat 7] [--case shell|bratu] [--set KEY=VALUE ...]``
where DIR is a checkout of the baseline (e.g. ``git worktree add /tmp/base 57912bb``).  Each repetition traces the default
scene (the model's runner in-process, no output files, BLAS single-threaded) in a fresh
process of each tree, alternating, so that both see the same load of a shared machine.  Inside the
process the trace runs twice and the second run is timed, with warm imports: since issue 18 the
command line defers the engine's heavy imports (scipy.sparse, the generated kernels) to the first
trace, while the baseline imports them with the runner's module, so a first run would charge this tree
alone for them (about 0.3 s).  The first run's wall time is printed too.  It prints
the median wall and CPU time of each and their ratio, and the work done (steps, special points),
so that a change of speed can be told apart from a change of work.  ``--set`` traces another scene
than the default (scene keys as ``contin trace --set`` takes them, e.g. ``--set load.kind=plate --set
load.control=force``); the run's status is printed beside its work.

``--case bratu`` times the engine alone instead: the 1-D Bratu problem with n = 2000 from ``lam = 0``
through its located fold to ``max(u) = 4`` (as ``studies.bench_bratu``), the median of 9 runs inside
each fresh process.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

from studies._common import run_study  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

#: Run in a child process with the tree first on sys.path: the scene runner is found under the name
#: the tree uses (before issue 14 the package was ``models`` and the scene ``contin_models.shell.scene``).
CHILD = r"""
import importlib, json, time
from contin.app.scene import load_scene
for name in ("models.shell.scene", "contin_models.shell_scene"):  # the baseline tree first: its own copy
    try:
        module = importlib.import_module(name)
        break
    except ImportError:
        continue
model = module.SHELL_SCENE
scene = load_scene(model.schema, None, ["output.figure=false"] + SETS)
def timed():
    wall, cpu = time.perf_counter(), time.process_time()
    result = model.run(scene, False)
    return time.perf_counter() - wall, time.process_time() - cpu, result
first, _, _ = timed()  # pays for the imports a runner defers to its first call
wall, cpu, result = timed()
print(json.dumps({"wall": wall, "cpu": cpu, "first": first,
                  "n_steps": sum(max(len(b.p) - 1, 0) for b in result.branches),
                  "n_special": sum(len(b.special_points) for b in result.branches), "module": name,
                  "status": result.status}))
"""


#: The Bratu case: the engine through a fold on a tridiagonal problem (each tree's own Bratu model).
BRATU_CHILD = r"""
import importlib, json, statistics, time
import numpy as np
from contin import continuation
for name in ("models.benchmarks.bratu", "contin_models.benchmarks.bratu"):
    try:
        module = importlib.import_module(name)
        break
    except ImportError:
        continue
def run():
    pb = module.Bratu(2000)
    wall, cpu = time.perf_counter(), time.process_time()
    br = continuation(pb, np.zeros(2000), 0.0, ds=0.1, ds_max=1.0, bounds={"max_u": (None, 4.0)}, store_states=False)
    return time.perf_counter() - wall, time.process_time() - cpu, br
run()
runs = [run() for _ in range(9)]
br = runs[-1][2]
assert br.folds() and br.folds()[0].located
print(json.dumps({"wall": statistics.median(r[0] for r in runs), "cpu": statistics.median(r[1] for r in runs),
                  "n_steps": len(br.p) - 1, "n_special": len(br.special_points), "module": name,
                  "fold": br.folds()[0].p}))
"""


def _import_path(tree: Path, shims: Path) -> str:
    """``PYTHONPATH`` that imports ``tree``'s own engine and models.

    The installed project maps the import name ``contin_models`` to one checkout's ``models``
    folder; a shim directory holding ``contin_models`` as a link to ``tree/models`` comes first so
    that the other checkout's models are found instead.
    """
    shim = shims / str(abs(hash(str(tree))))
    shim.mkdir(exist_ok=True)
    link = shim / "contin_models"
    if not link.exists() and (tree / "models").is_dir():
        link.symlink_to(tree / "models", target_is_directory=True)
    return os.pathsep.join([str(shim), str(tree)])


def one_run(tree: Path, shims: Path, case: str = "shell", sets: list[str] | None = None) -> dict:
    """Trace the default scene, or the scene of ``sets`` (or Bratu), once in a fresh process importing ``tree``;
    its times and work."""
    env = dict(os.environ, PYTHONPATH=_import_path(tree, shims))
    child = f"SETS = {list(sets or [])!r}\n" + CHILD if case == "shell" else BRATU_CHILD
    out = subprocess.run([sys.executable, "-c", child], cwd="/", env=env, capture_output=True, text=True)
    if out.returncode:
        raise RuntimeError(f"the default trace of {tree} failed:\n{out.stderr.strip()}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = argparse.ArgumentParser(prog="python -m studies.bench_side_by_side", description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", required=True, type=Path, help="checkout of the baseline")
    parser.add_argument("--repeat", type=int, default=7, help="repetitions per tree (default 7)")
    parser.add_argument("--case", choices=("shell", "bratu"), default="shell",
                        help="the default shell trace (default) or the engine on Bratu n = 2000")
    parser.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene key of the shell case (repeatable); default the default scene")
    args = parser.parse_args(argv)
    if args.sets and args.case != "shell":
        parser.error("--set applies to --case shell only")
    runs: dict[str, list[dict]] = {"this": [], "baseline": []}
    shims = Path(tempfile.mkdtemp(prefix="contin_bench_"))
    try:
        for i in range(args.repeat):
            for label, tree in (("this", ROOT), ("baseline", args.baseline.resolve())):
                runs[label].append(one_run(tree, shims, args.case, args.sets))
            print(f"[{i + 1}/{args.repeat}] this {runs['this'][-1]['wall']:.3f} s, "
                  f"baseline {runs['baseline'][-1]['wall']:.3f} s", file=sys.stderr)
    finally:
        shutil.rmtree(shims, ignore_errors=True)
    keys = ("wall", "cpu", "first") if args.case == "shell" else ("wall", "cpu")
    med = {label: {k: statistics.median(r[k] for r in rs) for k in keys} for label, rs in runs.items()}
    for label, rs in runs.items():
        first = f" (first run {med[label]['first']:.3f} s)" if "first" in med[label] else ""
        print(f"{label:9s} median wall {med[label]['wall']:.3f} s{first}, cpu {med[label]['cpu']:.3f} s; "
              f"{rs[0]['n_steps']} steps, {rs[0]['n_special']} special points"
              f"{', status ' + rs[0]['status'] if 'status' in rs[0] else ''} ({rs[0]['module']})")
    print(f"ratio this/baseline: wall {med['this']['wall'] / med['baseline']['wall']:.3f}, "
          f"cpu {med['this']['cpu'] / med['baseline']['cpu']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))
