"""Random scenes: how often does a scene drawn anywhere in the declared ranges run to its end?

``python -m studies.fuzz [--count 40] [--seed 1] [--workers N] [--out DIR]`` draws ``count`` shell
scenes at random (seeded, so a run is reproducible) over the ranges a user may set:

- ``shell.phi_hat`` uniform in [0.3, 1.5] (deep to shallow caps), ``h/R`` log-uniform in [1e-3, 0.12],
  ``nu`` uniform in [-0.5, 0.5] (auxetic to incompressible), ``N`` uniform in [40, 200];
- ``E`` log-uniform in [1e3, 1e11] Pa and ``R`` log-uniform in [1e-3, 1e3] m (the units);
- ``load.kind`` point, ring, sphere, plate or pressure, each equally likely (ring radius uniform in
  [0.1, 0.9] of the edge's radius, sphere radius log-uniform in [0.2, 3] R), ``load.control``
  displacement or force, each equally likely (for a pressure: volume or pressure control).

Each scene runs as ``contin trace`` does (in-process, through :func:`contin.app.cli.main`), with the
figure off.  A scene *completes* when the command exits 0; it is *refused* when the scene lies
outside the declared ranges (exit 2: e.g. a mesh too coarse for the cap's bending length, the rule
``shell.N >= 4 (pi/2 - phi_hat) / sqrt(h/R)``), and a refused scene is not judged; otherwise it
*failed*, and its status line is kept and sorted into a cause.  The study writes ``fuzz.csv`` (one row per scene: the drawn keys, exit
status, time, steps, cause and message), ``summary.json`` (completion rate overall and for
``N >= 40`` among the scenes not refused, counts per cause), ``points.json`` (the special points of
every completed scene, to compare two versions of the code scene by scene) and ``fuzz.png`` / ``fuzz.pdf`` (each
scene placed by ``phi_hat`` and ``h/R``, marked by load kind, coloured by outcome).  It exits with
status 1 when fewer than :data:`TARGET_COMPLETE` of the judged scenes with ``N >= 40`` complete, or
when a failure's message names no cause a user can act on.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import contextlib  # noqa: E402
import io  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import re  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections import Counter  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from studies._common import (executor_from_args, output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

#: Fraction of the judged scenes that must complete.
TARGET_COMPLETE = 0.99
#: Smallest mesh for which the completion target holds; coarser meshes are reported, not judged.
TARGET_MIN_NODES = 40

#: Causes a failure message can name, as (cause, pattern of the status line).  A message that
#: matches none of them is "unexplained": the study then fails, since a user could not act on it.
CAUSES: tuple[tuple[str, str], ...] = (
    ("use displacement control", r"load\.control = \"displacement\""),
    ("use force control", r"load\.control = \"force\""),
    ("refine the mesh", r"refine|finer mesh|too few nodes|increase shell\.N"),
    ("max_steps reached", r"max_steps"),
    ("membrane strain beyond the linear law", r"strain"),
    ("bad input", r"invalid|must be|allowed"),
)


def draw_scenes(count: int, seed: int) -> list[dict[str, Any]]:
    """``count`` random scenes (``--set`` keys and values), reproducible from ``seed``."""
    rng = np.random.default_rng(seed)
    scenes = []
    for index in range(count):
        R = 10.0 ** rng.uniform(-3, 3)
        h_over_R = 10.0 ** rng.uniform(-3, math.log10(0.12))
        kind = str(rng.choice(LOAD_KINDS))
        scene = {
            "index": index,
            "shell.R": R,
            "shell.E": 10.0 ** rng.uniform(3, 11),
            "shell.h": h_over_R * R,
            "shell.phi_hat": rng.uniform(0.3, 1.5),
            "shell.nu": rng.uniform(-0.5, 0.5),
            "shell.N": int(rng.integers(40, 201)),
            "load.kind": kind,
            "load.control": str(rng.choice(["displacement", "force"])),
        }
        if kind == "sphere":
            scene["load.radius"] = 10.0 ** rng.uniform(math.log10(0.2), math.log10(3.0)) * R
        elif kind == "ring":
            scene["load.ring_radius"] = rng.uniform(0.1, 0.9) * R * math.cos(scene["shell.phi_hat"])
        scenes.append(scene)
    return scenes


#: The load kinds drawn (every kind of the scene's ``load.kind``).
LOAD_KINDS = ("point", "ring", "sphere", "plate", "pressure")
#: The summary fields kept of every special point of a completed scene (``points.json``).
POINT_FIELDS = ("kind", "label", "p", "w_over_R", "F_norm", "w_b_over_R", "p_over_p_c")


#: Exit status of ``contin trace`` -> outcome (anything else is a failure).
OUTCOMES = {0: "complete", 2: "refused"}


def cause_of(message: str) -> str:
    """The first of :data:`CAUSES` whose pattern the message matches, else ``"unexplained"``."""
    for cause, pattern in CAUSES:
        if re.search(pattern, message, flags=re.IGNORECASE):
            return cause
    return "unexplained"


def run_scene(scene: dict[str, Any]) -> dict[str, Any]:
    """Trace one drawn scene as ``contin trace`` does and return its row."""
    from contin.app.cli import main as contin_main

    argv = ["trace", "-q", "--set", "output.figure=false"]
    for key, value in scene.items():
        if key != "index":
            argv += ["--set", f"{key}={value!r}" if isinstance(value, str) else f"{key}={value}"]
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            status = contin_main([*argv, "--out", tmp])
        summary_path = Path(tmp) / "summary.json"
        summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    points = [{k: sp[k] for k in POINT_FIELDS if k in sp} for sp in summary.get("special_points", [])]
    err_lines = stderr.getvalue().strip().splitlines()
    message = str(summary.get("message") or (err_lines[-1] if err_lines else ""))
    row = dict(scene)
    row.update({"h_over_R": scene["shell.h"] / scene["shell.R"], "exit_status": status,
                "time_s": round(time.perf_counter() - start, 3), "n_steps": summary.get("n_steps"),
                "outcome": OUTCOMES.get(status, "failed"),
                "cause": "" if status == 0 else cause_of(message), "message": "" if status == 0 else message,
                "special_points": points if status == 0 else []})
    return row


def summarize(rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Completion rates (all scenes, and those with ``N >= TARGET_MIN_NODES``) and failures per cause."""
    judged = [r for r in rows if r["shell.N"] >= TARGET_MIN_NODES and r["outcome"] != "refused"]
    rate = sum(r["outcome"] == "complete" for r in judged) / max(len(judged), 1)
    causes = Counter(r["cause"] for r in rows if r["outcome"] == "failed")
    return {"n_scenes": len(rows), "n_complete": sum(r["outcome"] == "complete" for r in rows),
            "n_refused": sum(r["outcome"] == "refused" for r in rows),
            "n_judged": len(judged), "complete_rate_judged": rate, "target_complete": TARGET_COMPLETE,
            "failures_by_cause": dict(causes),
            "target_met": rate >= TARGET_COMPLETE and causes.get("unexplained", 0) == 0}


def compare_runs(before: Path, after: Path) -> dict[str, Any]:
    """Scene-by-scene comparison of two runs of the study with the same seed and count.

    Reads each run's ``fuzz.csv`` and ``points.json``.  Returns the scenes that completed in
    ``before`` but not in ``after`` (``lost``), those that completed only in ``after`` (``gained``),
    and, over the scenes complete in both, whether their special points agree in number, kind and
    label (``mismatched`` lists those that do not) and the largest move of a numeric field of a
    special point (``max_move``, in the summary's normalized units, with its scene and field).
    """
    import csv

    def load(folder: Path) -> tuple[dict[str, str], dict[str, list[dict[str, Any]]]]:
        with open(folder / "fuzz.csv", newline="") as fh:
            outcomes = {row["index"]: row["outcome"] for row in csv.DictReader(fh)}
        return outcomes, json.loads((folder / "points.json").read_text())

    (out_a, pts_a), (out_b, pts_b) = load(before), load(after)
    both = [k for k in out_a if out_a[k] == "complete" and out_b.get(k) == "complete"]
    mismatched, move = [], (0.0, None, None)
    for k in both:
        a, b = pts_a.get(k, []), pts_b.get(k, [])
        if [(x["kind"], x["label"]) for x in a] != [(x["kind"], x["label"]) for x in b]:
            mismatched.append(k)
            continue
        for x, y in zip(a, b):
            for field in POINT_FIELDS[2:]:
                if isinstance(x.get(field), (int, float)) and isinstance(y.get(field), (int, float)):
                    d = abs(x[field] - y[field])
                    if d > move[0]:
                        move = (d, k, field)
    return {"lost": sorted((k for k in out_a if out_a[k] == "complete" and out_b.get(k) != "complete"), key=int),
            "gained": sorted((k for k in out_b if out_b[k] == "complete" and out_a.get(k) != "complete"), key=int),
            "n_complete_in_both": len(both), "mismatched": sorted(mismatched, key=int),
            "max_move": move[0], "max_move_scene": move[1], "max_move_field": move[2]}


def plot(rows: Sequence[dict[str, Any]]) -> Any:
    """Each scene at (phi_hat, h/R): marker by load kind, filled green if complete, red cross if not."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot import style

    fig, ax = plt.subplots(figsize=(style.WIDTH, 3.7))  # a page's width: printable as saved
    markers = {"point": "o", "ring": "D", "sphere": "s", "plate": "^", "pressure": "P"}
    for kind, marker in markers.items():
        for outcome, colour in (("complete", "tab:green"), ("refused", "0.6"), ("failed", "tab:red")):
            sel = [r for r in rows if r["load.kind"] == kind and r["outcome"] == outcome]
            if sel:
                ax.scatter([r["shell.phi_hat"] for r in sel], [r["h_over_R"] for r in sel], marker=marker,
                           c=colour, s=[12 + r["shell.N"] / 2 for r in sel], alpha=0.8,
                           label=f"{kind}, {outcome} ({len(sel)})")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\hat\phi$ (base angle, rad)")
    ax.set_ylabel(r"$h/R$")
    s = summarize(rows)
    ax.set_title(f"{s['n_complete']} of {s['n_scenes'] - s['n_refused']} accepted random scenes complete "
                 f"({100 * s['complete_rate_judged']:.1f} %); marker size grows with $N$")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Run the study (see the module docstring); exit status 1 when the target is missed."""
    parser = study_parser("fuzz", "random scenes over every declared range: how many complete", executor_options=True)
    parser.add_argument("--count", type=int, default=40, help="number of random scenes (default 40)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    parser.add_argument("--only", metavar="I,J,...", default=None,
                        help="run only these scenes of the draw (comma-separated indices), e.g. the failures of a "
                             "run")
    parser.add_argument("--against", metavar="DIR", default=None,
                        help="compare with an earlier run (same seed and count) in DIR, scene by scene: scenes "
                             "lost or gained, special points that changed (written to comparison.json)")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    scenes = draw_scenes(args.count, args.seed)
    if args.only:
        wanted = {int(i) for i in args.only.split(",")}
        scenes = [s for s in scenes if s["index"] in wanted]
    rows: list[dict[str, Any]] = []
    with executor_from_args(args) as executor:
        for done, (_, row) in enumerate(executor.map_unordered(run_scene, scenes), start=1):
            rows.append(row)
            say(args.quiet, f"[{done}/{len(scenes)}] scene {row['index']}: {row['load.kind']}/{row['load.control']} "
                f"N = {row['shell.N']}: {row['outcome']} {row['cause']} ({row['time_s']:.1f} s)")
    rows.sort(key=lambda r: r["index"])
    summary = summarize(rows)
    summary.update({"seed": args.seed, "count": args.count})
    write_json(out / "points.json", {str(r["index"]): r.pop("special_points") for r in rows})
    write_csv(out / "fuzz.csv", rows)
    write_json(out / "summary.json", {**summary, "failures": [r for r in rows if r["outcome"] == "failed"]})
    save_figure(plot(rows), out, "fuzz")
    print_table(rows, ["index", "load.kind", "load.control", "shell.N", "shell.phi_hat", "h_over_R", "outcome",
                       "cause", "time_s"], digits=3)
    say(args.quiet, f"complete: {summary['n_complete']}/{summary['n_scenes']} ({summary['n_refused']} refused); "
        f"judged (accepted, N >= {TARGET_MIN_NODES}): "
        f"{100 * summary['complete_rate_judged']:.1f} % (target {100 * TARGET_COMPLETE:.0f} %); "
        f"failures by cause: {summary['failures_by_cause']}")
    if args.against:
        diff = compare_runs(Path(args.against), out)
        write_json(out / "comparison.json", diff)
        say(args.quiet, f"against {args.against}: complete in both {diff['n_complete_in_both']}, lost {diff['lost']}, "
            f"gained {diff['gained']}, special points differing in kind or number {diff['mismatched']}, largest "
            f"move {diff['max_move']:.2e} ({diff['max_move_field']} of scene {diff['max_move_scene']})")
    return 0 if summary["target_met"] else 1


if __name__ == "__main__":
    sys.exit(run_study(main))
