"""The paper's appendix B on the paths the caps take: deep caps under a point load, followed in three dimensions.

Run ``python -m studies.appendix_b [--out DIR] [--full] [--quiet]``.  ``docs/three_d.md`` (section 1) states the
numbers and the conclusions; this docstring says what is computed.

The caps of the paper's appendix B: ``phi_hat = 0.6, 0.9, 1.2``, ``h/R = 0.02``, ``nu = 0.5``, the sliding edge, a
point force at the pole under displacement control (the scene's defaults but ``phi_hat``).  Each cap is run as
``contin trace --set shell.phi_hat=X --set stability.harmonics=true --set stability.follow=true`` does, in this
process: the axisymmetric path to eversion with every harmonic block watched, then the path the shell takes (it
leaves the axisymmetric path at the first bifurcation into the branch that carries on, snaps where a branch ends
under the prescribed deflection and lands on the next stable state, in any symmetry).  Per cap:

- the axisymmetric path's class, force maximum and minimum, and its first fold in ``w`` (its snap);
- where the followed path parts from it (the first bifurcation: ``w/R``, the force, the number of waves), the
  sequence of pieces and snaps, the followed path's class, force maximum and minimum, and whether it reaches the
  end of the travel axisymmetric again (the cap everts);
- the shell in three dimensions where each piece ends and at the end (``appendix_b_shapes_<phi_hat>.png``).

The default run uses ``N = 80`` nodes and ``K = 2`` harmonics of the view (about 20 s: the sequence of pieces, not
its numbers, which need more harmonics); ``--full`` runs ``N = 200`` with ``K`` = 5, 10 and 3 (:data:`FULL_K`) and the
resolution checks on the two deep caps (:data:`CHECKS`: the harmonics at ``N = 100``, and ``N = 400`` for the cap of
0.9); and, with the pole held laterally (``load.pole_held = true``: the
point load as a pin through the pole instead of a frictionless tip, which the followed path does not take), where the
axisymmetric path first bifurcates.

Writes ``caps.csv`` (one row per run, rewritten after each), ``pieces.csv`` (the followed paths' pieces),
``held_pole.csv``, ``summary.json`` and the figures
``appendix_b`` (force against deflection, both paths, one panel per cap) and ``appendix_b_shapes_<phi_hat>``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import time  # noqa: E402
from pathlib import Path  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

#: The caps of the paper's appendix B (base angle from the horizontal; small is deep).
CAPS = (0.6, 0.9, 1.2)
#: Nodes and harmonics of the default run, and the nodes of ``--full``.
FAST, FULL_N = (80, 2), 200
#: The harmonics of ``--full`` per cap: where the followed path's snaps have converged in ``K`` (the checks).  The
#: one-wave branch of the cap of 0.9 runs far from axial symmetry (its pole slides off the axis) and needs many.
FULL_K = {0.6: 5, 0.9: 10, 1.2: 3}
#: The resolution checks of ``--full`` on the deep caps, ``(phi_hat, N, K)``: the harmonics at ``N = 100`` (within 0.2 %
#: of ``N = 200`` in where the path parts and 1e-4 in its snaps), and a finer mesh for the cap of 0.9.
CHECKS = (tuple((0.6, 100, k) for k in (2, 3, 4, 5, 6)) + tuple((0.9, 100, k) for k in (2, 3, 4, 5, 6, 8, 10, 12))
          + ((0.9, 400, 10),))


def cap_scene(phi_hat: float, N: int, K: int, pole_held: bool = False) -> dict[str, dict[str, Any]]:
    """The resolved scene of one cap: the shell scene's defaults (the paper's cap) with ``phi_hat``, the mesh, the
    view's harmonics, and the followed path on."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA

    sets = [f"shell.phi_hat={phi_hat}", f"shell.N={N}", f"view.harmonics={K}", "stability.harmonics=true",
            "stability.follow=true", f"load.pole_held={'true' if pole_held else 'false'}", "output.figure=false"]
    return load_scene(SHELL_SCHEMA, None, sets)


def _first_fold_in_w(records: Sequence[dict[str, Any]]) -> dict[str, Any] | None:
    """The axisymmetric path's first located fold in the prescribed deflection (its snap under that control)."""
    for r in records:
        if r.get("branch", 0) == 0 and r["kind"] == "fold" and r.get("parameter") == "w" and r.get("located", True):
            return r
    return None


def _path_text(path: Sequence[dict[str, Any]], parameter: str) -> str:
    """The followed path as one line: each piece's symmetry and how it ends, each snap's landing."""
    parts = []
    for item in path:
        if "snap" in item:
            parts.append(f"snap at {item['snap']['at']:.5f}")
        else:
            parts.append(f"{item['symmetry']} to {item[parameter + '_to']:.5f} ({item['ended']})")
    return " -> ".join(parts)


def followed_run(scene: dict[str, dict[str, Any]], what: str) -> dict[str, Any]:
    """Run a scene with ``stability.follow = true`` (the path the shell takes beside the axisymmetric one) and
    collect what the studies of the followed paths report: the result, the run time, each branch's curve (the
    deflection or travel over ``R``, ``F R / (2 pi D)``, the stability under the prescribed displacement), the
    snaps, the pieces and snaps in order (rows of ``pieces.csv``) and the path as one line.

    Raises
    ------
    RuntimeError
        When the run does not complete (the followed path stopped short), naming ``what`` was run: a study's
        numbers come from complete paths only.
    """
    from contin_models.shell_scene.scene import run_scene

    start = time.perf_counter()
    result = run_scene(scene)
    seconds = time.perf_counter() - start
    if not result.success:
        raise RuntimeError(f"{what} did not complete: {result.message}")
    f = result.summary["followed"]
    R = float(scene["shell"]["R"])  # the 3-D pieces name the deflection over R w_over_L
    cols = result.csv_columns
    which = np.asarray(cols["branch"], dtype=int)
    curves = [{"symmetry": str(cols["symmetry"][which == k][0]) if k else "axisymmetric",
               "w": np.asarray(cols["p"], dtype=float)[which == k] / R,
               "F": np.asarray(cols["F_norm"], dtype=float)[which == k],
               "stable": np.asarray(cols["stable_displacement"], dtype=bool)[which == k]}
              for k in range(len(result.branches))]
    snaps = [(float(before["p"]) / R, float(before["F_norm"]), float(after["F_norm"]))
             for before, after in result.jump_observables]
    pieces = [{k: v for k, v in item.items() if k != "snap"}
              | ({"snap_at": item["snap"]["at"], "landing": item["snap"]["landing_symmetry"],
                  "energy_released": item["snap"]["energy_released"]} if "snap" in item else {})
              for item in f["path"]]
    everts = (f["status"] == "completed" and f["path"][-1].get("symmetry") == "O(2)"
              and f["path"][-1].get("ended") == "end of load")
    return {"result": result, "time_s": round(seconds, 2), "curves": curves, "snaps": snaps, "pieces": pieces,
            "everts": everts, "path": _path_text(f["path"], result.parameter_name), "shapes": result.shapes,
            "h": float(scene["shell"]["h"])}


def run_cap(phi_hat: float, N: int, K: int, pole_held: bool = False) -> dict[str, Any]:
    """Trace one cap's axisymmetric and followed paths (:func:`followed_run`), with the row of ``caps.csv``.

    Raises
    ------
    RuntimeError
        When the run does not complete.
    """
    scene = cap_scene(phi_hat, N, K, pole_held)
    run = followed_run(scene, f"appendix_b: the cap phi_hat = {phi_hat} (N = {N}, K = {K})")
    result = run["result"]
    s = result.summary
    f = s["followed"]
    first = s.get("first_instability") or {}
    fold = _first_fold_in_w(result.special_points)
    R = float(scene["shell"]["R"])
    run["row"] = {"phi_hat": phi_hat, "N": N, "K": K, "pole_held": pole_held, "lambda": s["lambda"],
                  "time_s": run["time_s"],
                  "axi_class": s["classification"], "axi_F_max": s["F_max_norm"],
                  "axi_w_F_max": s["w_at_F_max_over_R"], "axi_F_min": s["F_min_norm"],
                  "axi_w_F_min": s["w_at_F_min_over_R"],
                  "axi_snap_w": None if fold is None else float(fold["p"]) / R,
                  "axi_snap_F": None if fold is None else float(fold["observables"]["F_norm"]),
                  "first_kind": first.get("kind"), "first_n": first.get("n"), "first_w": first.get("w_over_R"),
                  "first_F": first.get("F_norm"),
                  "followed_class": f.get("classification"), "followed_F_max": f.get("F_max_norm"),
                  "followed_F_min": f.get("F_min_norm"), "snaps": f.get("n_snaps"), "everts": run["everts"],
                  "left": f["left_axisymmetric"], "path": run["path"]}
    run["pieces"] = [{"phi_hat": phi_hat, "N": N, "K": K, "pole_held": pole_held, **piece} for piece in run["pieces"]]
    return run


#: Colours of the followed pieces by their symmetry (the axisymmetric path beneath in grey).
SYMMETRY_COLOURS = {"O(2)": "#0072B2", "D1": "#009E73", "D2": "#CC79A7", "D3": "#D55E00", "D4": "#E69F00",
                    "D5": "#56B4E9"}


def _runs(mask: np.ndarray) -> list[slice]:
    """The stretches of equal ``mask``, each one point longer so that neighbouring stretches meet."""
    edges = [0] + [i + 1 for i in range(len(mask) - 1) if mask[i] != mask[i + 1]] + [len(mask)]
    return [slice(a, min(b + 1, len(mask))) for a, b in zip(edges[:-1], edges[1:])]


def plot_paths(runs: Sequence[dict[str, Any]], titles: Sequence[str], suptitle: str, xlabel: str = r"$w/R$",
               columns: int | None = None, clip_after_snaps: bool = False) -> Any:
    """Force against deflection, one panel per run: the axisymmetric path (grey; dashed where unstable against some
    mode) and the followed path (coloured by its symmetry), its snaps, where it parts (the row's ``first_w``,
    ``first_F``) and where the axisymmetric path would snap (``axi_snap_w``, ``axi_snap_F``).  With
    ``clip_after_snaps`` the force axis ends a little above the largest force before the last snap (an indenter
    pressing the everted cap against its support drives the force far beyond it)."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    columns = columns or len(runs)
    rows = -(-len(runs) // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.0 * columns, 3.4 * rows), squeeze=False)
    seen: dict[str, Any] = {}
    for ax, run, title in zip(axes.flat, runs, titles):
        row, curves = run["row"], run["curves"]
        axi = curves[0]
        for sl in _runs(axi["stable"]):
            ax.plot(axi["w"][sl], axi["F"][sl], color="0.72", lw=1.4, ls="-" if axi["stable"][sl][0] else "--")
        for c in curves[1:]:
            colour = SYMMETRY_COLOURS.get(c["symmetry"], "k")
            ax.plot(c["w"], c["F"], color=colour, lw=1.8)
            seen.setdefault(c["symmetry"], colour)
        for w, F0, F1 in run["snaps"]:
            ax.annotate("", xy=(w, F1), xytext=(w, F0),
                        arrowprops={"arrowstyle": "->", "color": "0.3", "lw": 0.9, "ls": ":"})
        if row.get("first_w") is not None:
            ax.plot(row["first_w"], row["first_F"], marker="*", ms=11, color="#C21E56", ls="none")
        if row.get("axi_snap_w") is not None:
            ax.plot(row["axi_snap_w"], row["axi_snap_F"], marker="o", mfc="white", mec="0.45", ls="none", ms=6)
        ax.axhline(0.0, color="0.85", lw=0.6, zorder=0)
        if clip_after_snaps and run["snaps"]:
            last = run["snaps"][-1][0]
            before = np.concatenate([c["F"][c["w"] <= last] for c in curves])
            top, low = float(np.max(before)), float(np.min(before))
            ax.set_ylim(low - 0.1 * (top - low), top + 0.4 * (top - low))
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(xlabel)
    for ax in axes.flat[len(runs):]:
        ax.set_axis_off()
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$F R / 2\pi D$")
    handles = [Line2D([], [], color="0.72", lw=1.4, label="axisymmetric path, stable"),
               Line2D([], [], color="0.72", lw=1.4, ls="--", label="axisymmetric path, unstable"),
               *[Line2D([], [], color=c, lw=1.8, label=f"followed path: {s}") for s, c in seen.items()],
               Line2D([], [], color="0.3", lw=0.9, ls=":", label="snap"),
               Line2D([], [], marker="*", ms=11, color="#C21E56", ls="none", label="first bifurcation"),
               Line2D([], [], marker="o", mfc="white", mec="0.45", ls="none", label="axisymmetric snap")]
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, -0.12 / rows))
    fig.suptitle(suptitle, fontsize=10)
    fig.tight_layout()
    return fig


def plot_shapes(run: dict[str, Any]) -> Any:
    """The shell in three dimensions where each piece of the followed path ends and at its end."""
    import matplotlib.pyplot as plt
    from contin_models.shell_scene.view3d import draw_surfaces

    fig = plt.figure()
    draw_surfaces(fig, run["shapes"], 1.0, run["h"], "w")
    row = run["row"]
    fig.suptitle(rf"followed path, $\hat\phi = {row['phi_hat']:g}$ (N = {row['N']}, K = {row['K']})", fontsize=10,
                 y=1.02)
    return fig


def save_plot_data(out: Any, runs: Sequence[dict[str, Any]], extra: Sequence[str] = ()) -> None:
    """What the figures of ``runs`` need: ``plot_data.json`` (rows, curves, snaps and the keys ``extra``) and each
    run's 3-D states in ``shapes_<k>.npz``; ``--replot`` draws the figures again from them."""
    def listed(v: Any) -> Any:
        if isinstance(v, np.ndarray):
            return v.tolist()
        if isinstance(v, dict):
            return {k: listed(x) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [listed(x) for x in v]
        return v

    keep = ("row", "curves", "snaps", "h", *extra)
    write_json(Path(out) / "plot_data.json", {"runs": [{k: listed(r[k]) for k in keep if k in r} for r in runs]})
    for k, r in enumerate(runs):
        if r.get("shapes"):
            np.savez_compressed(Path(out) / f"shapes_{k}.npz", **r["shapes"])


def read_plot_data(out: Any) -> list[dict[str, Any]]:
    """The runs saved by :func:`save_plot_data` in ``out``, with their arrays again."""
    import json
    import sys

    path = Path(out) / "plot_data.json"
    if not path.exists():
        print(f"error: --replot: no {path}: run the study with --out {out} first", file=sys.stderr)
        raise SystemExit(2)
    runs = json.loads(path.read_text())["runs"]
    for k, r in enumerate(runs):
        r["curves"] = [{key: (np.asarray(v, dtype=bool) if key == "stable" else
                              np.asarray(v, dtype=float) if isinstance(v, list) else v)
                        for key, v in c.items()} for c in r["curves"]]
        shapes = Path(out) / f"shapes_{k}.npz"
        if shapes.exists():
            with np.load(shapes) as z:
                r["shapes"] = {name: z[name] for name in z.files}
    return runs


#: The columns printed for each run.
COLUMNS = ("phi_hat", "N", "K", "pole_held", "axi_class", "axi_F_max", "axi_F_min", "axi_snap_w", "first_n", "first_w",
           "followed_class", "followed_F_max", "followed_F_min", "snaps", "everts", "time_s")


def _check(phi_hat: float, N: int, K: int) -> dict[str, Any]:
    """A resolution check: its run, or the reason it did not complete (a check reports, it does not stop the study)."""
    try:
        return run_cap(phi_hat, N, K)
    except RuntimeError as exc:
        return {"row": {"phi_hat": phi_hat, "N": N, "K": K, "pole_held": False, "failed": str(exc)}, "pieces": []}


def held_pole_bifurcation(phi_hat: float, N: int) -> dict[str, Any]:
    """Where the axisymmetric path of a cap whose pole is held laterally first leaves it (its harmonic blocks watched;
    the followed path is built for the frictionless tip only)."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import run_scene

    scene = load_scene(SHELL_SCHEMA, None, [f"shell.phi_hat={phi_hat}", f"shell.N={N}", "stability.harmonics=true",
                                            "load.pole_held=true", "output.figure=false"])
    result = run_scene(scene)
    first = result.summary.get("first_instability") or {}
    return {"phi_hat": phi_hat, "N": N, "complete": result.success, "first_kind": first.get("kind"),
            "first_n": first.get("n"), "first_w": first.get("w_over_R"), "first_F": first.get("F_norm"),
            "axi_w_F_max": result.summary.get("w_at_F_max_over_R")}


def draw(runs: Sequence[dict[str, Any]], out: Any) -> None:
    """The study's figures of its runs."""
    row = runs[0]["row"]
    titles = [rf"$\hat\phi = {r['row']['phi_hat']:g}$, $\lambda = {r['row']['lambda']:.1f}$ ($K = {r['row']['K']}$)"
              for r in runs]
    save_figure(plot_paths(runs, titles, f"point load at the pole, h/R = 0.02, nu = 0.5, sliding edge "
                                         f"(N = {row['N']})"), out, "appendix_b")
    for r in runs:
        save_figure(plot_shapes(r), out, f"appendix_b_shapes_{r['row']['phi_hat']:g}")


def main(argv: Sequence[str] | None = None) -> int:
    parser = study_parser("appendix_b", __doc__.splitlines()[0])
    parser.add_argument("--replot", action="store_true", help="draw the figures again from DIR/plot_data.json")
    args = parser.parse_args(argv)
    if args.replot:
        draw(read_plot_data(args.out), args.out)
        return 0
    out = output_dir(args.out)
    N = FULL_N if args.full else FAST[0]
    runs: list[dict[str, Any]] = []
    checks: list[dict[str, Any]] = []

    def keep() -> list[dict[str, Any]]:  # the table so far: a long --full run that stops keeps what it measured
        rows = [r["row"] for r in runs + checks]
        write_csv(out / "caps.csv", rows)
        write_csv(out / "pieces.csv", [p for r in runs + checks for p in r["pieces"]])
        return rows

    for phi_hat in CAPS:
        K = FULL_K[phi_hat] if args.full else FAST[1]
        say(args.quiet, f"appendix_b: phi_hat = {phi_hat}, N = {N}, K = {K}")
        runs.append(run_cap(phi_hat, N, K))
        keep()
    held = []
    if args.full:
        say(args.quiet, "appendix_b: the pole held laterally")
        held = [held_pole_bifurcation(phi_hat, N) for phi_hat in CAPS]
        write_csv(out / "held_pole.csv", held)
        for phi_hat, n, k in CHECKS:
            say(args.quiet, f"appendix_b: check phi_hat = {phi_hat}, N = {n}, K = {k}")
            checks.append(_check(phi_hat, n, k))
            keep()
    rows = keep()
    print_table(rows, COLUMNS)
    if held:
        print("pole held laterally: the axisymmetric path's first bifurcation")
        print_table(held, ["phi_hat", "N", "first_kind", "first_n", "first_w", "first_F", "axi_w_F_max"])
    for r in runs:
        print(f"phi_hat = {r['row']['phi_hat']:g}: {r['row']['left']}\n    {r['row']['path']}")
    for r in checks:
        if "failed" in r["row"]:
            print(f"check phi_hat = {r['row']['phi_hat']:g}, N = {r['row']['N']}, K = {r['row']['K']}: "
                  f"{r['row']['failed']}")
    save_plot_data(out, runs)
    draw(runs, out)
    write_json(out / "summary.json", {"command": "python -m studies.appendix_b" + (" --full" if args.full else ""),
                                      "N": N, "caps": [r["row"] for r in runs],
                                      "checks": [r["row"] for r in checks], "held_pole": held})
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
