"""Point (apex) and ring loads on a clamped cap against the published curves (issue 16, study (b), loads).

Run ``python -m studies.clamped_cap_loads [--out DIR] [--full]``.

The cap is Mescall's (1965) clamped spherical cap, ``R = 4.758 in``, ``t = 0.01576 in``, base
radius ``a = 0.9 in`` (``lambda = 6``, ``R/t = 302``), ``E = 1e7 psi``, ``nu = 0.3``, loaded either by
a point force at the apex or by a ring force at radius ``0.42 a``.  Both are traced under
displacement control (the apex's or the ring's deflection prescribed;
:class:`contin_models.shell.structure.ShellOfRevolution`), by continuation through every fold, and
the total load ``P`` is read against the apex deflection ``w_c``.  The published values, Teng &
Rotter (1989a, Fig. 12) and Wood & Zienkiewicz (1977), are those digitised in AQUINAS that
``studies.classical.MESCALL_CAP`` records (source and caveats there and in ``docs/validation.md``
section 4).

The ring sits on the node nearest ``0.42 a``: ``N`` is chosen (from the requested value upwards)
so that the node is within 0.02 % of ``a`` of it, and its radius is reported.

Writes ``loads.csv`` (our curves), ``summary.json`` and ``clamped_cap_loads.png`` / ``.pdf``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin_models.shell.geometry import spherical_cap  # noqa: E402
from contin_models.shell.structure import ShellOfRevolution, ShellStructure  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)
from studies.classical import MESCALL_CAP  # noqa: E402

GEOMETRY = MESCALL_CAP["geometry"]
RING_AT = 0.42
#: Apex deflections at which the published apex-load curves are compared (inches).
W_C_END = {"point": 0.2, "ring": 0.12}


def ring_mesh(N: int) -> tuple[int, int]:
    """``(N', k)``: the first ``N' >= N`` whose node ``k`` lies within 2e-4 ``a`` of ``0.42 a``."""
    R, a = GEOMETRY["R_in"], GEOMETRY["a_in"]
    phi_hat = math.pi / 2 - math.asin(a / R)
    for n in range(N, N + 200):
        r = spherical_cap(R, phi_hat, n, 1.0).r
        k = int(np.argmin(np.abs(r - RING_AT * a)))
        if abs(r[k] - RING_AT * a) <= 2e-4 * a:
            return n, k
    raise RuntimeError(f"no mesh from N = {N} puts a node within 2e-4 a of {RING_AT} a")


def trace(load: str, N: int) -> dict[str, Any]:
    """The clamped cap's displacement-controlled path under the apex or the ring load."""
    R, t, a, E, nu = (GEOMETRY[k] for k in ("R_in", "t_in", "a_in", "E_psi", "nu"))
    phi_hat = math.pi / 2 - math.asin(a / R)
    N, k = ring_mesh(N) if load == "ring" else (N, None)
    cap = spherical_cap(R, phi_hat, N, 1.0)
    pr = ShellOfRevolution(ShellStructure(cap, E, nu, t, "clamped"), load, "displacement", node=k)
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(ds=0.002, ds_max=0.005, max_steps=3000),
                             p_max=W_C_END[load])
    if br.status != "ok" and not br.message.startswith("stopped at p_max"):
        raise RuntimeError(f"{load} load, N = {N}: {br.message}")
    w_name = "w" if load == "point" else "w_pole"
    # the tangents along the arclength s let the figure draw the path smooth between the stored points
    return {"load": load, "N": N, "ring_r_over_a": None if k is None else float(cap.r[k] / a),
            "w_c": np.asarray(br.observable(w_name)), "P": np.asarray(br.observable("F")), "message": br.message,
            "s": np.asarray(br.s), "dw_c": br.tangent(w_name), "dP": br.tangent("F")}


def compare(curves: dict[str, dict[str, Any]]) -> list[dict[str, Any]]:
    """Our values beside the published ones at the published points."""
    rows = []
    point = curves["point"]
    for src, key in (("Teng & Rotter 1989a", "teng_rotter_1989a"), ("Wood & Zienkiewicz 1977", "wood_zienkiewicz_1977")):
        pub = MESCALL_CAP["apex_load"][key]
        for w, P in zip(pub["w_c_in"], pub["P_lb"]):
            ours = float(np.interp(w, point["w_c"], point["P"]))
            rows.append({"load": "apex", "quantity": f"P at w_c = {w:g} in", "source": src, "published": P,
                         "ours": ours, "rel_diff": ours / P - 1.0})
    ring = curves["ring"]
    w, P = ring["w_c"], ring["P"]
    i = int(np.argmax(np.where(w < 0.04, P, -np.inf)))  # the first maximum, then the following minimum
    j = i + int(np.argmin(np.where(w[i:] < 0.1, P[i:], np.inf)))
    for src, key in (("Teng & Rotter 1989a", "teng_rotter_1989a"), ("Wood & Zienkiewicz 1977", "wood_zienkiewicz_1977")):
        pub = MESCALL_CAP["ring_load_r_over_a_0.42"][key]
        for name, idx, pk, wk in (("first maximum", i, "peak_P_lb", "peak_w_c_in"),
                                  ("following minimum", j, "valley_P_lb", "valley_w_c_in")):
            rows.append({"load": "ring 0.42 a", "quantity": f"{name} P", "source": src, "published": pub[pk],
                         "ours": float(P[idx]), "rel_diff": float(P[idx]) / pub[pk] - 1.0,
                         "w_c_published": pub[wk], "w_c_ours": float(w[idx])})
    return rows


def plot(curves: dict[str, dict[str, Any]]) -> Any:
    """``P`` against ``w_c``: our two paths and the published points."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.branches import smooth_path
    from contin.plot.style import COLORS, WIDTH

    colors = {"point": COLORS[0], "ring": COLORS[1]}
    fig, ax = plt.subplots(figsize=(WIDTH, 4.0), layout="constrained")
    for load in ("point", "ring"):
        c = curves[load]
        # the ring's node is within 2e-4 a of 0.42 a: three digits say where it is, more would claim more
        label = "apex load (ours)" if load == "point" else f"ring load at $r = {c['ring_r_over_a']:.3g}\\,a$ (ours)"
        ax.plot(*smooth_path(c["w_c"], c["P"], c.get("dw_c"), c.get("dP"), c["s"]), color=colors[load], lw=1.2,
                label=label)
    for key, marker, src in (("teng_rotter_1989a", "o", "Teng & Rotter 1989a"),
                             ("wood_zienkiewicz_1977", "s", "Wood & Zienkiewicz 1977")):
        apex = MESCALL_CAP["apex_load"][key]
        ax.plot(apex["w_c_in"], apex["P_lb"], marker, color=colors["point"], mfc="none", label=f"apex, {src}")
        ring = MESCALL_CAP["ring_load_r_over_a_0.42"][key]
        ax.plot([ring["peak_w_c_in"], ring["valley_w_c_in"]], [ring["peak_P_lb"], ring["valley_P_lb"]], marker,
                color=colors["ring"], mfc="none", label=f"ring extrema, {src}")
    ax.set_xlabel(r"apex deflection $w_c$ [in]")
    ax.set_ylabel(r"total load $P$ [lb]")
    ax.set_xlim(0, 0.2)
    ax.set_ylim(0, 120)
    ax.set_title("clamped cap (Mescall 1965), $\\lambda = 6$, $R/t = 302$: apex and ring loads", fontsize="small")
    # right of the ring load's peak, above both curves' middle parts: nothing drawn there
    ax.legend(loc="upper left", bbox_to_anchor=(0.13, 1.0))
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("clamped_cap_loads", "apex and ring loads on a clamped cap against published curves")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    sizes = (200, 400, 800) if args.full else (200, 400)
    runs: dict[int, dict[str, dict[str, Any]]] = {}
    for N in sizes:
        say(args.quiet, f"apex and ring loads, N = {N} ...")
        runs[N] = {load: trace(load, N) for load in ("point", "ring")}
    finest = runs[sizes[-1]]
    rows = compare(finest)
    coarse = compare(runs[sizes[-2]])
    for row, c in zip(rows, coarse):
        row["ours_coarser_mesh"] = c["ours"]
    print_table(rows, ["load", "quantity", "source", "published", "ours", "rel_diff", "ours_coarser_mesh"])
    curve_rows = [{"load": load, "N": c["N"], "w_c_in": w, "P_lb": P}
                  for load, c in finest.items() for w, P in zip(c["w_c"], c["P"])]
    write_csv(out / "loads.csv", curve_rows)
    write_json(out / "summary.json", {"comparison": rows, "meshes": list(sizes),
                                      "ring_r_over_a": finest["ring"]["ring_r_over_a"], "cap": GEOMETRY})
    save_figure(plot(finest), out, "clamped_cap_loads")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
