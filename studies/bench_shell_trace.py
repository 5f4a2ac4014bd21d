"""Benchmark: ``contin trace`` of the shell's default scene, in-process and from the command line.

Run ``python -m studies.bench_shell_trace [--repeat 7] [--sizes 200 2000] [--json PATH]``.

What is measured (wall time, BLAS single-threaded, medians of ``--repeat`` runs):

* ``trace``: the model runner alone, in-process with warm imports: the whole connected path from
  w = 0 to eversion, every fold in w and every extremum of F located, the Morse index under both
  controls at every stored point, the classification.  This is the cost the issue's target refers to.
* ``trace + outputs``: :func:`contin.app.cli.main` in-process (adds ``summary.json``, ``branch.csv`` and
  the figure; matplotlib already imported).
* ``start-up``: a fresh ``contin --help`` process (interpreter, imports, argument parsing), and one
  cold ``contin trace`` process for the default scene, reported separately.

It also reports what the run did (steps, rejected steps, factorizations, special points, F_max) so
that a change in speed can be told apart from a change in the work done.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import io  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import shutil  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from typing import Any  # noqa: E402

from contin.app.cli import main as cli_main  # noqa: E402
from contin.app.scene import load_scene  # noqa: E402
from contin_models.shell_scene import SHELL_SCENE  # noqa: E402
from studies._common import write_text  # noqa: E402


def _median_time(fun, repeat: int) -> tuple[float, list[float], Any]:
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fun()
        times.append(time.perf_counter() - t)
    return statistics.median(times), times, out


def bench_size(N: int, repeat: int) -> dict[str, Any]:
    """Time the runner and the full in-process command for one mesh size."""
    scene = load_scene(SHELL_SCENE.schema, None, [f"shell.N={N}"])
    SHELL_SCENE.runner(scene, False)  # warm-up: imports, first-call costs
    t_trace, all_trace, result = _median_time(lambda: SHELL_SCENE.runner(scene, False), repeat)
    br = result.branches[0]
    out_dir = tempfile.mkdtemp(prefix="bench_shell_")
    try:
        args = ["trace", "-q", "--out", out_dir, "--set", f"shell.N={N}"]
        def run_cli() -> int:
            with contextlib.redirect_stdout(io.StringIO()):  # the command prints its table
                return cli_main(args)
        run_cli()  # warm-up (matplotlib import)
        t_cli, all_cli, code = _median_time(run_cli, max(1, repeat // 2))
    finally:
        shutil.rmtree(out_dir, ignore_errors=True)
    return {
        "N": N, "trace_median_s": t_trace, "trace_runs_s": all_trace, "cli_median_s": t_cli, "cli_runs_s": all_cli,
        "cli_exit": code, "status": br.status, "steps": br.meta["n_steps"],
        "rejected_steps": int(sum(br.meta["rejected_steps"].values())),
        "factorizations": br.meta["n_factorizations"], "special_points": len(result.special_points),
        "classification": result.summary.get("classification"), "F_max": result.summary.get("F_max"),
        "w_at_F_max": result.summary.get("w_at_F_max"),
    }


def bench_startup(repeat: int) -> dict[str, Any]:
    """Fresh-process costs: ``contin --help`` and one cold ``contin trace`` of the default scene."""
    exe = shutil.which("contin")
    cmd = [exe] if exe else [sys.executable, "-m", "contin.app.cli"]
    t_help, runs, _ = _median_time(lambda: subprocess.run(cmd + ["--help"], capture_output=True, check=True), repeat)
    out_dir = tempfile.mkdtemp(prefix="bench_shell_cold_")
    try:
        t = time.perf_counter()
        subprocess.run(cmd + ["trace", "-q", "--out", out_dir], capture_output=True, check=True)
        t_cold = time.perf_counter() - t
    finally:
        shutil.rmtree(out_dir, ignore_errors=True)
    return {"help_median_s": t_help, "help_runs_s": runs, "cold_trace_s": t_cold, "command": " ".join(cmd)}


def render(data: dict[str, Any]) -> str:
    """Markdown section for ``docs/benchmarks.md``."""
    lines = [
        "## Shell: `contin trace` of the default scene (point load, phi_hat = 0.8, h/R = 0.02)",
        "",
        f"Produced by `python -m studies.bench_shell_trace --repeat {data['repeat']}` ({data['machine']}; "
        "medians; BLAS single-threaded).  *trace*: the model runner in-process with warm imports (the whole "
        "connected path to eversion, every fold in w and extremum of F located, the Morse index under both "
        "controls at every stored point, the classification).  *trace + outputs*: `contin.app.cli.main` "
        "in-process, adding summary.json, branch.csv and the figure.",
        "",
        "| N | trace (median) | trace + outputs | steps | rejected | factorizations | special points | F_max | class |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in data["sizes"]:
        lines.append(f"| {r['N']} | {r['trace_median_s']:.3f} s | {r['cli_median_s']:.3f} s | {r['steps']} | "
                     f"{r['rejected_steps']} | {r['factorizations']} | {r['special_points']} | {r['F_max']:.8g} | "
                     f"{r['classification']} |")
    s = data.get("startup")
    if s:
        lines += ["", f"Start-up, separately: a fresh `contin --help` process takes {s['help_median_s']:.2f} s "
                  f"(median); one cold `contin trace` process (default scene, with imports and outputs) "
                  f"took {s['cold_trace_s']:.2f} s."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs per size (median reported)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[200, 2000], help="mesh sizes N")
    ap.add_argument("--no-startup", action="store_true", help="skip the fresh-process measurements")
    ap.add_argument("--json", help="write the raw numbers to this JSON file")
    args = ap.parse_args(argv)
    data: dict[str, Any] = {"repeat": args.repeat, "sizes": [],
                            "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"}
    for N in args.sizes:
        reps = args.repeat if N <= 500 else max(3, args.repeat // 2)
        print(f"N = {N}: {reps} runs ...", file=sys.stderr, flush=True)
        data["sizes"].append(bench_size(N, reps))
    if not args.no_startup:
        data["startup"] = bench_startup(args.repeat)
    text = render(data)
    print(text)
    if args.json:
        write_text(args.json, json.dumps(data, indent=2))
    return 0


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
