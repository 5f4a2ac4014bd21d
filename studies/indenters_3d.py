"""Indenters on the paper's cap, on the paths the cap takes: where it snaps, and whether the snap shape is universal.

Run ``python -m studies.indenters_3d [--out DIR] [--full] [--quiet]``.  ``docs/three_d.md`` (section 3) states the
numbers and the conclusions; this docstring says what is computed.

The paper's cap (``phi_hat = 0.8``, ``h/R = 0.02``, ``nu = 0.5``, the sliding edge) pressed at its pole by a point
force, by rigid frictionless spheres of radius ``r/R = 0.3, 0.5, 0.8, 1.1`` and by a rigid plate, each under a
prescribed travel (``w`` of the point, ``w_b`` of the indenter), run as ``contin trace --set load.kind=... --set
stability.harmonics=true --set stability.follow=true`` does, in this process: the axisymmetric path with every
harmonic block watched, then the path the cap takes.  Per indenter:

- the axisymmetric path's snap (``w_b^c``: a fold in the travel, or the release fold after the force has fallen to
  zero) and its first bifurcation into ``n`` waves;
- the followed path: where it parts from the axisymmetric one, its pieces and snaps, and the state from which it
  snaps onto the everted branch;
- the paper's universal snap configuration: the meridian at the axisymmetric snap against the point load's (the
  largest distance between the same nodes, over ``R``), and the same for the state the followed path snaps from
  (its mean meridian over the angle, and how far it stands out of axial symmetry, over ``h``).

The default run uses ``N = 60`` nodes and ``K = 2`` harmonics for the point load, the smallest sphere and the
plate (the sequence of pieces, not its numbers, which need more harmonics); ``--full`` runs every indenter at
``N = 100`` with ``K = 6`` for the point and the spheres of 0.3 and 0.5 (whose paths run through one wave) and 3 for
the others (:data:`FULL_K`), and checks the smallest sphere in ``K`` and ``N`` (:data:`CHECKS`).

Writes ``indenters.csv`` (one row per run), ``pieces.csv``, ``summary.json`` and the figures ``indenters_3d``
(force against travel, both paths, one panel per indenter) and ``snap_shapes`` (the meridians the cap snaps from).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.appendix_b import followed_run, plot_paths, read_plot_data, save_plot_data  # noqa: E402

#: ``(load.kind, r/R)`` of the indenters: the point force, the spheres, the plate.
INDENTERS = (("point", None), ("sphere", 0.3), ("sphere", 0.5), ("sphere", 0.8), ("sphere", 1.1), ("plate", None))
#: The indenters of the default run.
FAST_INDENTERS = (("point", None), ("sphere", 0.3), ("plate", None))
FAST = (60, 2)
#: ``--full``: the nodes (the smallest sphere's snaps move by 3e-5 R from N = 100 to 400), and the harmonics per
#: indenter: the one-wave branches of the point and the small spheres run far from axial symmetry and need many.
FULL_N = 100
FULL_K = {"point": 6, "sphere r/R = 0.3": 6, "sphere r/R = 0.5": 6}
FULL_K_OTHERS = 3
#: The resolution checks of ``--full``: ``(N, K)`` for the smallest sphere.
CHECKS = ((100, 2), (100, 3), (100, 4), (200, 6), (400, 3))


def indenter_name(kind: str, radius: float | None) -> str:
    """``point``, ``sphere r/R = 0.3``, ``plate``."""
    return f"sphere r/R = {radius:g}" if kind == "sphere" else kind


def indenter_scene(kind: str, radius: float | None, N: int, K: int, follow: bool = True) -> dict[str, dict[str, Any]]:
    """The resolved scene: the paper's cap (the shell scene's defaults) under the indenter, the path followed (or,
    with ``follow`` false, the axisymmetric path alone, without the harmonic blocks)."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA

    flag = "true" if follow else "false"
    sets = [f"load.kind={kind}", f"shell.N={N}", f"view.harmonics={K}", f"stability.harmonics={flag}",
            f"stability.follow={flag}", "output.figure=false"]
    if radius is not None:
        sets.append(f"load.radius={radius}")
    return load_scene(SHELL_SCHEMA, None, sets)


def axisymmetric_snap_meridian(kind: str, radius: float | None, N: int, K: int) -> tuple[np.ndarray, np.ndarray]:
    """The meridian ``(r, z)`` of the axisymmetric path's snap, from the axisymmetric run's shapes."""
    from contin_models.shell_scene.scene import run_scene

    result = run_scene(indenter_scene(kind, radius, N, K, follow=False))
    sh = result.shapes
    # the snap of a one-sided contact: the point's or indenter's release (the force has fallen to zero), or a fold;
    # the indentation's first stretch may end at a small snap of the contact ring before it (a later branch's point)
    w_c = float(result.summary["w_c_one_sided"] if kind == "point" else result.summary["w_b_c"])
    # (a landing at the same travel is a jump's point, not the state it left)
    departs = np.isin(np.asarray(sh["special_kind"]).astype(str), ("fold", "event"))
    i = int(np.argmin(np.where(departs, np.abs(np.asarray(sh["special_p"], dtype=float) - w_c), np.inf)))
    return np.asarray(sh["special_r"][i], dtype=float), np.asarray(sh["special_z"][i], dtype=float)


def _snap_state(shapes: dict[str, np.ndarray], at: float) -> tuple[np.ndarray, np.ndarray, float, str]:
    """The followed path's state where it snaps at travel ``at``: its mean meridian over the angle, its largest height
    above or below its ring's mean (absolute), and its symmetry."""
    i = int(np.argmin(np.abs(np.asarray(shapes["state_p"], dtype=float) - at)))
    x, y, z = (np.asarray(shapes[k][i], dtype=float)[:, :-1] for k in ("state_x", "state_y", "state_z"))
    r = np.hypot(x, y)
    z_mean = z.mean(axis=1)
    return r.mean(axis=1), z_mean, float(np.max(np.abs(z - z_mean[:, None]))), str(shapes["state_representation"][i])


def _first_release(pieces: Sequence[dict[str, np.ndarray]]) -> float | None:
    """The travel (over ``R``) where the force along the followed pieces first falls to zero after the start: where a
    one-sided contact lets go (interpolated between stored points; None if it never does)."""
    for c in pieces:
        F, w = c["F"], c["w"]
        for k in range(1, len(F)):
            if F[k - 1] > 0.0 >= F[k] and w[k - 1] > 0.0:
                return float(w[k - 1] + (w[k] - w[k - 1]) * F[k - 1] / (F[k - 1] - F[k]))
    return None


def meridian_distance(a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray]) -> float:
    """The largest distance between the same nodes of two meridians (the same mesh)."""
    return float(np.max(np.hypot(a[0] - b[0], a[1] - b[1])))


def run_indenter(kind: str, radius: float | None, N: int, K: int) -> dict[str, Any]:
    """One indenter's axisymmetric and followed paths, the row of ``indenters.csv``, and the snap meridians."""
    scene = indenter_scene(kind, radius, N, K)
    name = indenter_name(kind, radius)
    run = followed_run(scene, f"indenters_3d: {name} (N = {N}, K = {K})")
    result = run["result"]
    s, f = result.summary, result.summary["followed"]
    R, h = float(scene["shell"]["R"]), float(scene["shell"]["h"])
    first = s.get("first_instability") or {}
    if kind == "point":
        snap_w = s.get("w_c_one_sided")
        snap_kind = s.get("one_sided_snap_kind")
        snap_F = s.get("F_at_one_sided_snap")
    else:
        snap_w, snap_kind, snap_F = s.get("w_b_c"), s.get("snap_kind"), s.get("F_at_snap")
    unit = float(s["F_unit"]) if s.get("F_unit") else 2.0 * np.pi * float(s["D"]) / R
    last_snap = next((p for p in reversed(run["pieces"]) if "snap_at" in p), None)
    row = {"indenter": name, "kind": kind, "r_over_R": radius, "N": N, "K": K, "time_s": run["time_s"],
           "axi_snap_w": None if snap_w is None else float(snap_w) / R, "axi_snap_kind": snap_kind,
           "axi_snap_F": None if snap_F is None else float(snap_F) / unit,
           "first_kind": first.get("kind"), "first_n": first.get("n"),
           "first_w": None if first.get("p") is None else float(first["p"]) / R,
           "first_F": first.get("F_norm"),
           "snaps": len([p for p in run["pieces"] if "snap_at" in p]),
           "snap_to_everted_w": None if last_snap is None else float(last_snap["snap_at"]) / R,
           "snap_to_everted_F": run["snaps"][-1][1] if run["snaps"] else None,
           "followed_release_w": _first_release(run["curves"][1:]),
           "everts": run["everts"], "left": f["left_axisymmetric"], "path": run["path"]}
    axi_meridian = axisymmetric_snap_meridian(kind, radius, N, K)
    followed_meridian = None
    if last_snap is not None:
        r_m, z_m, out_of_round, symmetry = _snap_state(run["shapes"], float(last_snap["snap_at"]))
        followed_meridian = (r_m, z_m)
        row.update({"snap_state_symmetry": symmetry, "snap_state_out_of_round_over_h": out_of_round / h})
    run.update({"row": row, "axi_meridian": axi_meridian, "followed_meridian": followed_meridian, "R": R,
                "pieces": [{"indenter": name, "N": N, "K": K, **p} for p in run["pieces"]]})
    return run


def universality(runs: Sequence[dict[str, Any]]) -> None:
    """Each run's snap meridians against a reference of the same mesh, written into the rows (over ``R``):
    ``axi_snap_distance`` against the point load's axisymmetric snap, ``followed_snap_distance`` against the smallest
    sphere's followed snap (the point load is two-sided: its followed path pulls past the release of a one-sided
    contact, so its snap is not an indenter's)."""
    point = next((r for r in runs if r["row"]["kind"] == "point"), None)
    sphere = next((r for r in runs if r["row"]["kind"] == "sphere"), None)
    for run in runs:
        R = run["R"]
        if point is not None and run["row"]["N"] == point["row"]["N"]:
            run["row"]["axi_snap_distance"] = meridian_distance(run["axi_meridian"], point["axi_meridian"]) / R
        if (sphere is not None and run["row"]["N"] == sphere["row"]["N"] and run["followed_meridian"] is not None
                and sphere["followed_meridian"] is not None):
            run["row"]["followed_snap_distance"] = meridian_distance(run["followed_meridian"],
                                                                     sphere["followed_meridian"]) / R


def plot_snap_shapes(runs: Sequence[dict[str, Any]]) -> Any:
    """The meridians the cap snaps from: on the axisymmetric paths (left) and on the followed paths (right, the mean
    over the angle of the state the cap snaps onto the everted branch from)."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9.0, 3.6), sharey=True)
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.9, len(runs)))
    for run, colour in zip(runs, colours):
        R, name = run["R"], run["row"]["indenter"]
        axes[0].plot(run["axi_meridian"][0] / R, run["axi_meridian"][1] / R, color=colour, lw=1.4, label=name)
        if run["followed_meridian"] is not None:
            sym = run["row"].get("snap_state_symmetry", "")
            axes[1].plot(run["followed_meridian"][0] / R, run["followed_meridian"][1] / R, color=colour, lw=1.4,
                         label=f"{name} ({sym})")
    axes[0].set_title("axisymmetric paths: the snap", fontsize=10)
    axes[1].set_title("followed paths: the state snapping to the everted branch\n(mean over the angle)", fontsize=10)
    for ax in axes:
        ax.set_xlabel(r"$r/R$")
        ax.set_aspect("equal", adjustable="box")
        ax.legend(fontsize=7, frameon=False)
    axes[0].set_ylabel(r"$z/R$")
    fig.tight_layout()
    return fig


#: The columns printed for each run.
COLUMNS = ("indenter", "N", "K", "axi_snap_kind", "axi_snap_w", "axi_snap_distance", "first_n", "first_w", "snaps",
           "snap_to_everted_w", "snap_to_everted_F", "snap_state_symmetry", "snap_state_out_of_round_over_h",
           "followed_snap_distance", "followed_release_w", "everts", "time_s")


def draw(runs: Sequence[dict[str, Any]], out: Any) -> None:
    """The study's figures of its runs."""
    row = runs[0]["row"]
    save_figure(plot_paths(runs, [f"{r['row']['indenter']} ($K = {r['row']['K']}$)" for r in runs],
                           f"the paper's cap (phi_hat = 0.8, h/R = 0.02, nu = 0.5) under indenters (N = {row['N']})",
                           xlabel=r"$w_b/R$", columns=3, clip_after_snaps=True),
                out, "indenters_3d")
    save_figure(plot_snap_shapes(runs), out, "snap_shapes")


def main(argv: Sequence[str] | None = None) -> int:
    parser = study_parser("indenters_3d", __doc__.splitlines()[0])
    parser.add_argument("--replot", action="store_true", help="draw the figures again from DIR/plot_data.json")
    args = parser.parse_args(argv)
    if args.replot:
        runs = read_plot_data(args.out)
        for r in runs:  # the meridians as pairs of arrays again
            r["axi_meridian"] = tuple(np.asarray(a, dtype=float) for a in r["axi_meridian"])
            if r.get("followed_meridian") is not None:
                r["followed_meridian"] = tuple(np.asarray(a, dtype=float) for a in r["followed_meridian"])
        draw(runs, args.out)
        return 0
    out = output_dir(args.out)
    N = FULL_N if args.full else FAST[0]
    runs: list[dict[str, Any]] = []
    checks: list[dict[str, Any]] = []
    failed: list[dict[str, Any]] = []

    def keep() -> list[dict[str, Any]]:  # the table so far: a long --full run that stops keeps what it measured
        rows = [r["row"] for r in runs + checks] + failed
        write_csv(out / "indenters.csv", rows)
        write_csv(out / "pieces.csv", [p for r in runs + checks for p in r["pieces"]])
        return rows

    def attempt(kind: str, radius: float | None, n: int, k: int) -> dict[str, Any] | None:
        try:
            return run_indenter(kind, radius, n, k)
        except RuntimeError as exc:  # reported in the table and below it; the other indenters go on
            failed.append({"indenter": indenter_name(kind, radius), "N": n, "K": k, "failed": str(exc)})
            return None

    for kind, radius in (INDENTERS if args.full else FAST_INDENTERS):
        K = FULL_K.get(indenter_name(kind, radius), FULL_K_OTHERS) if args.full else FAST[1]
        say(args.quiet, f"indenters_3d: {indenter_name(kind, radius)}, N = {N}, K = {K}")
        if (run := attempt(kind, radius, N, K)) is not None:
            runs.append(run)
        keep()
    universality(runs)
    if args.full:
        for n, k in CHECKS:
            say(args.quiet, f"indenters_3d: check sphere r/R = 0.3, N = {n}, K = {k}")
            if (run := attempt("sphere", 0.3, n, k)) is not None:
                checks.append(run)
            keep()
    rows = keep()
    print_table(rows, COLUMNS)
    for row in failed:
        print(f"{row['indenter']} (N = {row['N']}, K = {row['K']}): {row['failed']}")
    for r in runs:
        print(f"{r['row']['indenter']}: {r['row']['left']}\n    {r['row']['path']}")
    save_plot_data(out, runs, extra=("axi_meridian", "followed_meridian", "R"))
    draw(runs, out)
    write_json(out / "summary.json", {"command": "python -m studies.indenters_3d" + (" --full" if args.full else ""),
                                      "N": N, "indenters": [r["row"] for r in runs],
                                      "checks": [r["row"] for r in checks], "failed": failed})
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
