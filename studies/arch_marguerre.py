"""The bar-hinge shallow arch against Marguerre's shallow-arch theory: do its loads converge to it?

Run ``python -m studies.arch_marguerre [--out DIR] [--full]``.  The pinned arch of ``n`` bars and
hinge springs (:class:`contin_models.benchmarks.arch.ShallowArch`, nodes on a circular arc) is
traced along its symmetric path by :func:`contin.continuation` with default settings; its first
branch point (asymmetric bifurcation) and its first fold (symmetric limit point) are compared with
the same loads of the shallow-arch theory solved in ``K`` sine modes
(:class:`contin_models.benchmarks.marguerre.MarguerreArch`, traced the same way).

Loads are given as ``Q = 4 P L^3 / (pi^4 EI r)`` (``L`` the span, ``r = sqrt(EI / EA)``), the form in
which the modal energy has unit coefficients; in it the Marguerre loads depend on ``h / r`` only
for the parabolic (shallow circular) arch, not on ``h / L``.  Sections:

* **K convergence** of the Marguerre loads (parabolic arch, ``h / r`` = 10 and 5), and the check of
  the modal model with ``K = 2`` against the two-mode closed form of the half-sine arch;
* **comparison**: for ``h / r`` = 10 (branch point first) and 5 (limit point first), ``h / L`` = 0.1,
  0.05, 0.02, 0.01 and ``n`` = 20, 40, 80 (``--full``: also 160) the loads of the bar-hinge arch, the
  Marguerre values of the parabolic arch (the shallow theory proper) and of the exact circular shape,
  and the relative differences; ``n_inf`` rows extrapolate the two finest ``n`` assuming an ``n^-2``
  error (checked by the printed ratio of successive differences), leaving the shallowness error;
* the **half-sine** bar-hinge arch (``shape="sine"``) at ``h / r = 10`` against the Marguerre
  half-sine arch.

Writes ``k_convergence.csv``, ``comparison.csv``, ``summary.json`` and ``arch_marguerre.png`` / ``.pdf``.
Exit status 1 if the differences do not shrink as ``n`` grows and ``h / L`` shrinks.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin_models.benchmarks import arch as arch_model  # noqa: E402
from contin_models.benchmarks import marguerre  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)



#: sine modes of the Marguerre reference values (converged to 6 digits, see the K table)
K_REF = 33
#: the trace stops past the first fold and branch point (both lie below 0.6 h for h / r in [5, 10])
BOUND = 0.9


def special_loads(problem: Any, n_unknowns: int, unit: float, rise: float) -> dict[str, float]:
    """``Q`` at the first located branch point and the first located fold of the symmetric path."""
    br = contin.continuation(problem, np.zeros(n_unknowns), 0.0, bounds={"deflection": (None, BOUND * rise)})
    out = {}
    for kind in ("branch_point", "fold"):
        pts = [s for s in br.special_points if s.kind == kind and s.located]
        if not pts:
            raise RuntimeError(f"{problem.name}: no located {kind} below deflection {BOUND} h ({br.message})")
        out[kind] = float(pts[0].p / unit)
        out[kind + "_w"] = float(pts[0].observables["deflection"] / rise)
    return out


def marguerre_loads(rg: float, K: int, shape: str, h_over_L: float = 0.01) -> dict[str, float]:
    """Marguerre loads ``Q`` for ``h / r = rg`` with ``K`` modes (span 1, ``EI = 1``)."""
    m = marguerre.MarguerreArch(K=K, rise=h_over_L, rise_over_gyration=rg, shape=shape)
    return special_loads(m, K, m.load_unit(), m.rise)


def arch_loads(rg: float, h_over_L: float, n: int, shape: str = "circle") -> dict[str, float]:
    """Bar-hinge loads ``Q`` (span 1, ``EI = 1``)."""
    a = arch_model.ShallowArch(n=n, rise=h_over_L, rise_over_gyration=rg, shape=shape)
    return special_loads(a, 2 * (n - 1), marguerre.load_unit(1.0, 1.0, h_over_L / rg), a.rise)


def path(problem: Any, n_unknowns: int, unit: float, rise: float) -> tuple[np.ndarray, np.ndarray]:
    """Deflection / h and Q along the symmetric path up to a deflection of 2.2 h."""
    br = contin.continuation(problem, np.zeros(n_unknowns), 0.0, bounds={"deflection": (None, 2.2 * rise)})
    return np.asarray(br.observables["deflection"]) / rise, np.asarray(br.p) / unit


def k_convergence(quiet: bool) -> list[dict[str, Any]]:
    """Marguerre loads against ``K``: parabolic arch at ``h / r`` = 10 and 5, half-sine arch at 10 (with ``K = 2``
    beside the two-mode closed form)."""
    rows = []
    for rg in (10.0, 5.0):
        for K in (3, 5, 9, 17, 33, 65):
            say(quiet, f"Marguerre parabola h/r = {rg}, K = {K} ...")
            q = marguerre_loads(rg, K, "parabola")
            rows.append({"shape": "parabola", "h/r": rg, "K": K, "Q_bp": q["branch_point"], "Q_fold": q["fold"]})
    for K in (2, 3, 5, 9, 17, 33):
        q = marguerre_loads(10.0, K, "sine")
        closed = marguerre.two_mode_half_sine(10.0) if K == 2 else {}
        rows.append({"shape": "sine", "h/r": 10.0, "K": K, "Q_bp": q["branch_point"], "Q_fold": q["fold"],
                     "closed_bp": closed.get("branch_point"), "closed_fold": closed.get("fold")})
    return rows


def compare(quiet: bool, sizes: Sequence[int]) -> list[dict[str, Any]]:
    """Bar-hinge loads for every case and mesh beside the Marguerre values, with relative differences
    ``err_* = Q(bars) / Q(Marguerre) - 1`` and a Richardson row ``n = "inf"`` per case."""
    rows = []
    cases = [("circle", 10.0, (0.1, 0.05, 0.02, 0.01)), ("circle", 5.0, (0.1, 0.05, 0.02, 0.01)),
             ("sine", 10.0, (0.05, 0.01))]
    for shape, rg, ratios in cases:
        ref_shape = "parabola" if shape == "circle" else "sine"
        ref = marguerre_loads(rg, K_REF, ref_shape)
        for hL in ratios:
            exact = marguerre_loads(rg, K_REF, "circle", hL) if shape == "circle" else ref
            group = []
            for n in sizes:
                say(quiet, f"bar-hinge {shape} h/r = {rg}, h/L = {hL}, n = {n} ...")
                q = arch_loads(rg, hL, n, shape)
                group.append({"shape": shape, "h/r": rg, "h/L": hL, "n": n, "Q_bp": q["branch_point"],
                              "Q_fold": q["fold"], "w_bp": q["branch_point_w"], "w_fold": q["fold_w"]})
            # Richardson with an n^-2 error from the two finest meshes
            a, b = group[-2], group[-1]
            f = (b["n"] / a["n"]) ** 2
            group.append({"shape": shape, "h/r": rg, "h/L": hL, "n": "inf",
                          "Q_bp": (f * b["Q_bp"] - a["Q_bp"]) / (f - 1),
                          "Q_fold": (f * b["Q_fold"] - a["Q_fold"]) / (f - 1)})
            if len(group) >= 4:
                d = [group[i + 1]["Q_bp"] - group[i]["Q_bp"] for i in range(len(sizes) - 1)]
                group[-1]["ratio"] = d[-2] / d[-1]  # 4 for an n^-2 error and doubling n
            for row in group:
                row["M_bp"], row["M_fold"] = ref["branch_point"], ref["fold"]
                row["err_bp"] = row["Q_bp"] / ref["branch_point"] - 1
                row["err_fold"] = row["Q_fold"] / ref["fold"] - 1
                if shape == "circle":
                    row["Mc_bp"], row["Mc_fold"] = exact["branch_point"], exact["fold"]
            rows.extend(group)
    return rows


def shrinking(rows: Sequence[dict[str, Any]]) -> bool:
    """Do |err| shrink with n at every h / L, and (at the finest n) with h / L?"""
    ok = True
    keys = sorted({(r["shape"], r["h/r"]) for r in rows})
    for shape, rg in keys:
        sel = [r for r in rows if r["shape"] == shape and r["h/r"] == rg]
        ratios = sorted({r["h/L"] for r in sel}, reverse=True)
        finest = []
        for hL in ratios:
            by_n = [r for r in sel if r["h/L"] == hL and r["n"] != "inf"]
            for err in ("err_bp", "err_fold"):
                ok &= all(abs(y[err]) < abs(x[err]) for x, y in zip(by_n, by_n[1:]))
            finest.append(by_n[-1])
        for err in ("err_bp", "err_fold"):
            ok &= all(abs(y[err]) < abs(x[err]) for x, y in zip(finest, finest[1:]))
    return bool(ok)


def plot(rows: Sequence[dict[str, Any]], krows: Sequence[dict[str, Any]], paths: dict[str, Any]) -> Any:
    """(a) load-deflection paths; (b) relative differences against h / L; (c) K convergence."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.style import WIDTH

    # a column of three at a page's width; a row each, so that (b)'s legend beside it narrows no other panel
    fig = plt.figure(figsize=(WIDTH, 8.4), layout="constrained")
    a, b, c = (sf.subplots() for sf in fig.subfigures(3, 1, height_ratios=[1.0, 1.0, 0.9]))
    for (rg, color) in ((10.0, "tab:blue"), (5.0, "tab:red")):
        w, q = paths[("arch", rg)]
        a.plot(w, q, "-", color=color, lw=1.2, label=f"bars+hinges, $n = 80$, $h/r = {rg:g}$")
        w, q = paths[("marguerre", rg)]
        a.plot(w, q, "--", color="k", lw=0.8, label="Marguerre ($K = 33$)" if rg == 10.0 else None)
        for r in rows:
            if r["shape"] == "circle" and r["h/r"] == rg and r["h/L"] == 0.01 and r["n"] == 80:
                a.plot(r["w_bp"], r["Q_bp"], "o", mfc="none", color=color)
                a.plot(r["w_fold"], r["Q_fold"], "s", mfc="none", color=color)
    a.plot([], [], "ko", mfc="none", label="first branch point")
    a.plot([], [], "ks", mfc="none", label="first limit point")
    a.axhline(0, color="0.7", lw=0.5)
    # the loop is still the symmetric path (asymmetry zero throughout): the third mode takes over and
    # the crown rises again while the quarter points go down; right of the loop's tip, on no line
    a.annotate("loop: still symmetric,\nhigher symmetric modes", xy=(0.9, 105), fontsize="small")
    a.set_xlabel("crown deflection / rise")
    a.set_ylabel(r"$Q = 4PL^3/(\pi^4 EI\, r)$")
    a.set_title("symmetric path, circular arch, $h/L = 0.01$", fontsize="small")
    a.legend()
    marks = {20: "v", 40: "^", 80: "o", 160: "D", "inf": "*"}
    for rg, color in ((10.0, "tab:blue"), (5.0, "tab:red")):
        for n, mk in marks.items():
            sel = [r for r in rows if r["shape"] == "circle" and r["h/r"] == rg and r["n"] == n]
            if sel:
                b.loglog([r["h/L"] for r in sel], [abs(r["err_bp"]) for r in sel], marker=mk, color=color,
                         ls="-" if n == "inf" else ":", lw=0.9,
                         label=f"$h/r = {rg:g}$, $n = {chr(92) + 'infty' if n == 'inf' else n}$")
    x = np.array([0.01, 0.1])
    b.loglog(x, 2.0 * x ** 2, "k-", lw=0.6, label=r"slope 2: $2\,(h/L)^2$")
    b.set_xlabel("rise / span  $h/L$")
    b.set_ylabel(r"$|Q_\mathrm{bp}(\mathrm{bars})\,/\,Q_\mathrm{bp}(\mathrm{Marguerre}) - 1|$")
    b.set_title("first branch point against shallow theory ($n = \\infty$: Richardson from $n$ = 40, 80)",
                fontsize="small")
    b.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    for rg, color in ((10.0, "tab:blue"), (5.0, "tab:red")):
        sel = [r for r in krows if r["shape"] == "parabola" and r["h/r"] == rg]
        last = sel[-1]
        for key, ls in (("Q_bp", "o-"), ("Q_fold", "s--")):
            c.semilogy([r["K"] for r in sel[:-1]], [abs(r[key] / last[key] - 1) for r in sel[:-1]], ls, color=color,
                       mfc="none", label=f"$h/r = {rg:g}$, {'branch point' if key == 'Q_bp' else 'limit point'}")
    c.set_xscale("log", base=2)
    c.set_xlabel("$K$ (sine modes)")
    c.set_ylabel(f"relative change from $K = {sel[-1]['K']}$")
    c.set_title("Marguerre loads against $K$ (parabolic arch)", fontsize="small")
    c.legend()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("arch_marguerre", "bar-hinge shallow arch against Marguerre shallow-arch theory")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    sizes = (20, 40, 80, 160) if args.full else (20, 40, 80)
    krows = k_convergence(args.quiet)
    rows = compare(args.quiet, sizes)
    paths = {}
    for rg in (10.0, 5.0):
        say(args.quiet, f"paths at h/r = {rg} ...")
        a = arch_model.ShallowArch(n=80, rise=0.01, rise_over_gyration=rg)
        paths[("arch", rg)] = path(a, 2 * 79, marguerre.load_unit(1.0, 1.0, 0.01 / rg), a.rise)
        m = marguerre.MarguerreArch(K=K_REF, rise=0.01, rise_over_gyration=rg, shape="parabola")
        paths[("marguerre", rg)] = path(m, K_REF, m.load_unit(), m.rise)
    ok = shrinking(rows)
    write_csv(out / "k_convergence.csv", krows)
    write_csv(out / "comparison.csv", rows)
    write_json(out / "summary.json", {
        "load": "Q = 4 P L^3 / (pi^4 EI r), r = sqrt(EI / EA)", "K_ref": K_REF, "sizes": list(sizes),
        "two_mode_half_sine_closed_form": marguerre.two_mode_half_sine(10.0), "k_convergence": krows,
        "comparison": rows, "differences_shrink": ok})
    save_figure(plot(rows, krows, paths), out, "arch_marguerre")
    print("Marguerre loads against K (Q = 4 P L^3 / (pi^4 EI r)):")
    print_table(krows, ["shape", "h/r", "K", "Q_bp", "Q_fold", "closed_bp", "closed_fold"], digits=8)
    print("\nbar-hinge arch (Q) against Marguerre (M: parabola or half-sine, Mc: Marguerre on the exact circle):")
    print_table(rows, ["shape", "h/r", "h/L", "n", "Q_bp", "M_bp", "Mc_bp", "err_bp", "Q_fold", "M_fold", "Mc_fold",
                       "err_fold", "ratio"], digits=6)
    print(f"differences shrink with n and with h/L: {'yes' if ok else 'no'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(run_study(main))
