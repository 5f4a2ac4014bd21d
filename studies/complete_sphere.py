"""The complete sphere under external pressure: membrane state and axisymmetric bifurcation (issue 16, study (c)).

Run ``python -m studies.complete_sphere [--out DIR] [--full]`` (20 s; ``--full``: the membrane state up to
N = 3201 and the bifurcation on half and double meshes).

The shell is a complete sphere (two poles on the axis, no edge;
:func:`contin_models.shell.meridian.complete_sphere_meridian`), its rigid translation along the axis
removed by holding the equator's height (:class:`contin_models.shell.structure.ShellStructure`), under
a uniform external pressure ``p`` (:class:`contin_models.shell.structure.ShellOfRevolution`).

(1) **Membrane state.**  Linear theory of a complete sphere: the uniform shrinkage
``dR/R = -p R (1 - nu) / (2 E h)`` (``docs/model.md#classical-values``) of membrane theory, times
``1 / (1 + (h/R)^2 / 12)`` once the bending energy of the uniform curvature change ``-e/R`` is
counted (an ``(h/R)^2`` correction, 8e-6 at ``R/h = 100``).  The linear response ``dx/dp`` at the
reference state is compared with it at the equator and at the poles for three meshes, with the
observed order and a Richardson extrapolation.

(2) **Bifurcation.**  The pressure-controlled path from ``p = 0`` is traced until its first
singular point (a fold or a branch point of the axisymmetric model); its pressure over
``p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2))`` is compared with 1, and the degree ``l`` of the
critical mode (the Legendre polynomial ``P_l(cos beta)`` that carries most of the normal
component of the null vector) with the classical ``l (l + 1) ~ sqrt(12 (1 - nu^2)) R/h``.  Many
modes share almost the same pressure: the axisymmetric modes of degree ``l`` buckle at
``p_l / p_c = (L / L* + L* / L) / 2`` (``L = l (l + 1)``, ``L* = sqrt(12 (1 - nu^2)) R/h``, the
shallow form of the classical result), so every ``l`` with ``p_l`` within a fraction of a per cent
of ``p_c`` is a legitimate critical mode; the study lists that band.

Units: ``R = R/h``, ``h = 1``, ``E`` such that ``p_c = 1``.  Writes ``membrane.csv``,
``bifurcation.csv``, ``summary.json`` and ``complete_sphere.png`` / ``.pdf``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin.numerics.stability import stability_info  # noqa: E402
from contin_models.shell.geometry import POLE_RATIO  # noqa: E402
from contin_models.shell.meridian import complete_sphere_meridian  # noqa: E402
from contin_models.shell.structure import ShellOfRevolution, ShellStructure  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

NU = 0.3
#: Nodes per wavelength of the classical critical mode ``2 pi R / l*`` the bifurcation runs use at least.
NODES_PER_WAVELENGTH = 24
#: Bound on ``(pi q / N)^2 R/h`` for the bifurcation runs, ``q`` the spacing at the poles over the spacing
#: elsewhere (:data:`POLE_RATIO`).  The discrete membrane state errs at the poles by about that much
#: relative (uniform mesh, R/h = 1000: 0.0207, 0.0049, 0.0012 at N = 401, 801, 1601; graded, q = 1/2:
#: 0.0063, 0.0015, 0.00038), an imperfection at the poles that lowers the bifurcation and turns some
#: branch points into folds; the mesh keeps it at 1e-3.
POLE_ERROR = 1e-3


def bifurcation_nodes(r_over_h: float) -> int:
    """Odd ``N`` with :data:`NODES_PER_WAVELENGTH` nodes per critical wavelength and ``(pi q/N)^2 R/h <=`` :data:`POLE_ERROR`."""
    n = max(NODES_PER_WAVELENGTH * classical_degree(r_over_h) / 2.0,
            math.pi * POLE_RATIO * math.sqrt(r_over_h / POLE_ERROR))
    return 2 * math.ceil(n / 2.0) + 1


def sphere_problem(r_over_h: float, N: int, pole_ratio: float = POLE_RATIO) -> ShellOfRevolution:
    """The complete sphere of ``R/h = r_over_h`` under pressure, in the study's units (``h = 1``, ``p_c = 1``)."""
    R, h = float(r_over_h), 1.0
    E = math.sqrt(3.0 * (1.0 - NU * NU)) / (2.0 * (h / R) ** 2)
    structure = ShellStructure(complete_sphere_meridian(R, N, pole_ratio), E, NU, h)
    return ShellOfRevolution(structure, "pressure", p_c=1.0, length=R)


def classical_degree(r_over_h: float) -> float:
    """``l*`` with ``l* (l* + 1) = sqrt(12 (1 - nu^2)) R/h``."""
    L = math.sqrt(12.0 * (1.0 - NU * NU)) * r_over_h
    return (-1.0 + math.sqrt(1.0 + 4.0 * L)) / 2.0


def mode_pressure(l: int, r_over_h: float) -> float:
    """``p_l / p_c = (L / L* + L* / L) / 2`` of the axisymmetric mode of degree ``l`` (module docstring)."""
    L, Ls = l * (l + 1.0), math.sqrt(12.0 * (1.0 - NU * NU)) * r_over_h
    return 0.5 * (L / Ls + Ls / L)


def normal_component(pr: ShellOfRevolution, dx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(mu, w_n)``: ``mu = z/R`` (the cosine of the angle from the north pole) and the outward normal
    component of the full-state field ``dx`` at every node of the reference sphere."""
    x = pr.x_ref
    r, z = x[0::2], x[1::2]
    rad = np.hypot(r, z)
    return z / rad, (r * dx[0::2] + z * dx[1::2]) / rad


def dominant_degree(mu: np.ndarray, w: np.ndarray, l_max: int) -> tuple[int, float]:
    """The degree ``l <= l_max`` whose Legendre polynomial carries most of ``w(mu)``, and its share of the
    fitted field's squared norm (the projection uses the trapezoidal rule on the nodes)."""
    order = np.argsort(mu)
    mu, w = mu[order], w[order]
    shares = []
    for l in range(l_max + 1):
        P = np.polynomial.legendre.Legendre.basis(l)(mu)
        c = (2 * l + 1) / 2.0 * np.trapezoid(w * P, mu)
        shares.append(c * c * 2.0 / (2 * l + 1))  # the squared norm of c P_l on [-1, 1]
    shares = np.array(shares)
    l = int(np.argmax(shares))
    return l, float(shares[l] / shares.sum())


def membrane_rows(r_over_h: float, sizes: Sequence[int]) -> list[dict[str, Any]]:
    """The linear shrinkage per unit pressure at the equator and the north pole against the closed form."""
    rows = []
    for N in sizes:
        pr = sphere_problem(r_over_h, N)
        mu, w = normal_component(pr, pr.linear_response())
        R, h, E = r_over_h, 1.0, pr.structure.E
        exact = -R * R * (1.0 - NU) / (2.0 * E * h) / (1.0 + (h / R) ** 2 / 12.0)
        eq = int(np.argmin(np.abs(mu)))
        rows.append({"R_over_h": r_over_h, "N": N, "equator_error": w[eq] / exact - 1.0,
                     "pole_error": w[-1] / exact - 1.0, "max_error": float(np.max(np.abs(w / exact - 1.0)))})
    for key in ("equator_error", "pole_error"):
        e = [row[key] for row in rows]
        for k in range(2, len(rows)):
            ratio = (e[k - 2] - e[k - 1]) / (e[k - 1] - e[k])
            rows[k][f"{key}_order"] = math.log(abs(ratio), sizes[k] / sizes[k - 1]) if ratio > 0 else None
            rows[k][f"{key}_extrapolated"] = e[k] - (e[k - 1] - e[k]) / (ratio - 1.0) if ratio > 1 else None
    return rows


def bifurcation_row(r_over_h: float, N: int) -> dict[str, Any]:
    """The first singular point of the pressure path and the degree of its mode."""
    pr = sphere_problem(r_over_h, N)
    t0 = time.perf_counter()
    # small steps: many modes go unstable within a fraction of a per cent of p_c, and a step across two
    # of them would see no sign change
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(ds=0.002, ds_max=0.002, max_steps=2000),
                             p_max=1.05)
    seconds = time.perf_counter() - t0
    singular = [s for s in br.special_points if s.kind in ("fold", "branch_point")]
    first = next((s for s in singular if s.located), None)
    ls = classical_degree(r_over_h)
    band = [l for l in range(1, int(3 * ls) + 2) if mode_pressure(l, r_over_h) <= 1.005]
    row: dict[str, Any] = {"R_over_h": r_over_h, "N": N, "l_star": ls, "l_band_0.5%": f"{band[0]}..{band[-1]}",
                           "seconds": seconds, "message": br.message,
                           "unlocated_before": sum(1 for s in singular if not s.located and (first is None or s.p < first.p))}
    if first is None:
        row.update(kind=None, p_over_p_c=None, l=None, share=None)
        return row
    info = stability_info(pr.jacobian(first.u, first.p), k=1, vectors=True)
    dx = np.zeros(pr.structure.n_full)
    dx[pr.idx] = info.eigenvectors[:, 0]
    mu, w = normal_component(pr, dx)
    l, share = dominant_degree(mu, w, int(3 * ls) + 10)
    row.update(kind=first.kind, p_over_p_c=float(first.p), l=l, share=share, l_in_band=band[0] <= l <= band[-1],
               p_l_over_p_c=mode_pressure(l, r_over_h))
    return row


def plot(membrane: Sequence[dict[str, Any]], bifurcation: Sequence[dict[str, Any]]) -> Any:
    """Above: membrane error against N; below: the bifurcation pressure against R/h with the mode degrees."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FixedFormatter, FixedLocator, NullFormatter, NullLocator

    from contin.plot.style import COLORS, GREY, WIDTH, marker_style

    # one above the other at a page's width, each legend right of its panel
    fig, (a, b) = plt.subplots(2, 1, figsize=(WIDTH, 6.2), layout="constrained")
    depths = sorted({r["R_over_h"] for r in membrane})
    equator = {roh: [abs(r["equator_error"]) for r in membrane if r["R_over_h"] == roh] for roh in depths}
    # the equator's error does not depend on R/h (the depths agree to 2e-5 relative): the first depth
    # is a wide solid line under large hollow circles, the others dashed with small dots on top of it
    same = all(np.allclose(e, equator[depths[0]], rtol=1e-3) for e in equator.values())
    for k, roh in enumerate(depths):
        rows = [r for r in membrane if r["R_over_h"] == roh]
        N = [r["N"] for r in rows]
        color = COLORS[k % len(COLORS)]
        solid = k == 0
        note = " (coincides)" if same and not solid else ""
        a.loglog(N, equator[roh], color=color, ls="-" if solid else (0, (3.5, 2.0)), lw=2.2 if solid else 1.1,
                 marker="o", ms=8 if solid else 3.5, mfc="none" if solid else color, mew=1.0, zorder=2 if solid else 3,
                 label=f"equator, $R/h = {roh:g}${note}")
        a.loglog(N, [abs(r["pole_error"]) for r in rows], color=color, ls="-" if solid else (0, (3.5, 2.0)), lw=1.2,
                 marker="s", ms=4.5, label=f"pole, $R/h = {roh:g}$")
    N = np.array(sorted({r["N"] for r in membrane}), dtype=float)
    a.loglog(N, 1e-5 * (N[0] / N) ** 2 * 10, ":", color=GREY, label=r"$\propto N^{-2}$")
    # ticks at the meshes computed, not at the log axis' round numbers
    a.xaxis.set_major_locator(FixedLocator(N))
    a.xaxis.set_major_formatter(FixedFormatter([f"{n:g}" for n in N]))
    a.xaxis.set_minor_locator(NullLocator())
    a.xaxis.set_minor_formatter(NullFormatter())
    a.set_xlim(N[0] / 1.15, N[-1] * 1.15)
    top = max(abs(r["pole_error"]) for r in membrane)
    a.set_ylim(top=4.0 * top)
    a.set_xlabel("nodes on the meridian, $N$")
    a.set_ylabel(r"$|w / w_\mathrm{exact} - 1|$")
    a.set_title("membrane state: relative error of the linear shrinkage $w$ against $N$", fontsize="small")
    a.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    rows = [r for r in bifurcation if r["p_over_p_c"] is not None]
    x = [r["R_over_h"] for r in rows]
    for kind in sorted({r["kind"] for r in rows}):
        sel = [r for r in rows if r["kind"] == kind]
        b.semilogx([r["R_over_h"] for r in sel], [r["p_over_p_c"] for r in sel], ls="none",
                   label=f"first {kind.replace('_', ' ')} (ours)", **marker_style(kind))
    for r in rows:
        b.annotate(f"$l = {r['l']}$, $l^* = {r['l_star']:.1f}$", (r["R_over_h"], r["p_over_p_c"]),
                   textcoords="offset points", xytext=(5, 6), fontsize="small")
    b.axhline(1.0, color=GREY, lw=0.8)
    b.axhspan(0.98, 1.02, color=GREY, alpha=0.15, lw=0, label=r"$p_c \pm 2\,\%$")
    b.set_xlabel("$R/h$")
    b.set_ylabel(r"$p / p_c$")
    b.set_ylim(0.95, 1.05)
    b.set_xlim(min(x) / 1.5, max(x) * 6)
    b.set_title("first singular point of the axisymmetric pressure path", fontsize="small")
    b.text(0.02, 0.97, "$l$: degree of the Legendre polynomial $P_l(\\cos\\beta)$ carrying most of the mode\n"
           "$l^*$: classical degree, $l^*(l^*+1) = \\sqrt{12(1-\\nu^2)}\\,R/h$",
           transform=b.transAxes, va="top", ha="left", fontsize="small")
    b.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("complete_sphere", "complete sphere under pressure: membrane state and bifurcation")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    sizes = (201, 401, 801, 1601, 3201) if args.full else (201, 401, 801)
    membrane = []
    for roh in (100.0, 1000.0):
        say(args.quiet, f"membrane state, R/h = {roh:g}, N = {', '.join(map(str, sizes))} ...")
        membrane.extend(membrane_rows(roh, sizes))
    bif = []
    for roh in (100.0, 300.0, 1000.0):
        N = bifurcation_nodes(roh)
        for n in ((N // 2 + (N // 2 + 1) % 2, N, 2 * N - 1) if args.full else (N,)):
            say(args.quiet, f"bifurcation, R/h = {roh:g}, N = {n} ...")
            bif.append(bifurcation_row(roh, n))
    print_table(membrane, ["R_over_h", "N", "equator_error", "equator_error_order", "equator_error_extrapolated",
                           "pole_error", "pole_error_order"])
    print_table(bif, ["R_over_h", "N", "kind", "p_over_p_c", "l", "share", "l_star", "l_band_0.5%", "unlocated_before",
                      "seconds"])
    write_csv(out / "membrane.csv", membrane)
    write_csv(out / "bifurcation.csv", bif)
    write_json(out / "summary.json", {"membrane": membrane, "bifurcation": bif, "nu": NU})
    save_figure(plot(membrane, bif), out, "complete_sphere")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
