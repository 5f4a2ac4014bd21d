"""A pressurised complete sphere probed at its poles: the largest probe force and where the dimple breaks symmetry.

Run ``python -m studies.sphere_probe [--out DIR] [--full]``.  ``docs/three_d.md`` (section 6) states the numbers
and the conclusions; this docstring says what is computed.

The shell is a complete sphere, ``R/h = 100``, ``nu = 0.3``
(:func:`contin_models.shell.meridian.complete_sphere_meridian`), its south pole on a point support
(``boundary="pinned"``: the pole held at its point) and a probe at its north pole prescribing the pole's travel
``w`` (:class:`contin_models.shell.structure.ShellOfRevolution`, a point load under displacement control).  Both
poles are held laterally (the probe and the support grip their poles): the harmonic blocks ``n = 1`` then have no
rigid zero mode.  ``w`` is the approach of probe and support; by the symmetry about the equator each pole's
dimple is ``w / 2`` deep while that symmetry holds.

Each case is first pressurised at ``p`` (``p > 0`` external, ``p < 0`` internal; the uniform state of
pressure control, solved by Newton's method), then probed under one of two controls:

``"pressure"``
    a gas: ``p`` fixed while probing (the probe problem with the fixed pressure ``p``);
``"volume"``
    an incompressible fill: the enclosed volume held at its pressurised value, ``p`` the multiplier that
    changes (:class:`contin_models.shell.probe.ProbeAtFixedVolume`).

Along the axisymmetric path from ``w`` at the pressurised state (``F = 0``) the study locates

1. the **largest probe force** ``F_max``: the first maximum of ``F`` along the path (a located extremum event);
   the path is traced until ``F`` falls back below zero (the snap) or to the travel :data:`W_END`;
2. the **first bifurcation into n waves** (``n >= 2``), from the blocks ``n = 1 .. default_harmonics``: the
   engine's located bifurcations of the family ``"n"`` (as :func:`studies.waves_branch.first_bifurcation` reads
   them, here without ``n = 1`` and the pole's modes below), with its ``w``, ``F`` and ``n``; whether it comes
   before ``F_max``; the first ``n = 1`` bifurcation is listed apart;
3. the **initial stiffness** ``dF/dw`` at the pressurised state, times 2 (a pole's stiffness), against Reissner's
   ``k_R = 4 E h^2 / (R sqrt(3 (1 - nu^2)))`` and its pressurised form (:func:`pressurised_stiffness`); and the
   unpressurised sphere's at ``R/h`` = 100 and 1000 on three meshes each (:func:`reissner_rows`, ``stiffness.csv``).

Units: ``h = 1``, ``R = 100``, ``E`` such that ``p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2)) = 1``; forces over
``F_unit = E h^3 / R``.  Fast default: ``N = 201`` nodes pole to pole, three pressures.  ``--full``: eight
pressures from ``-2 p_c`` to ``0.9 p_c`` at ``N = 401`` (the figure's) and ``N = 201``, and ``N = 801`` at three of
them (mesh check).  The harmonic blocks are exact per wave number (no truncation in ``n``): the range watched,
``n <= default_harmonics`` (25 here), only has to contain the critical ``n``.

A bifurcation whose mode is largest within :data:`POLE_SCALE` thicknesses of the axis is reported apart
(``n_pole``, ``w_pole``): it lives on the first rings round a pole (``r < h`` on the finest mesh), where the point
force's hoop stress is singular and thin-shell theory does not hold; it is not the dimple's loss of symmetry.
``r_mode`` is the radius where the reported mode is largest.

Along the path the first branch point (the symmetry about the equator breaks: one dimple deepens, the other
recovers) is reported too: under pressure control it is where ``F`` is largest (two equal dimples in series), under
volume control just before.

Writes ``cases.csv``, ``paths.csv``, ``stiffness.csv``, ``summary.json`` and the figure ``sphere_probe`` (PNG, PDF).
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
from contin_models.shell.harmonic import harmonic_mode  # noqa: E402
from contin_models.shell.meridian import complete_sphere_meridian  # noqa: E402
from contin_models.shell.probe import ProbeAtFixedVolume  # noqa: E402
from contin_models.shell.structure import ShellOfRevolution, ShellStructure, default_harmonics  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)

NU = 0.3
R_OVER_H = 100.0
#: The probe's largest travel (the approach of the two poles), in thicknesses.
W_END = 60.0
#: Pressures over p_c: the fast default's and the full sweep's; the full sweep's mesh check.
PRESSURES_FAST = (-1.0, 0.0, 0.5)
PRESSURES_FULL = (-2.0, -1.0, -0.5, 0.0, 0.25, 0.5, 0.75, 0.9)
MESH_CHECK = (-1.0, 0.0, 0.5)
#: Nodes pole to pole: the fast default's; the full sweep's (which also runs the fast one's); the finest check.
N_FAST, N_FULL, N_CHECK = 201, 401, 801
CONTROLS = ("pressure", "volume")
#: Newton's iteration for the pressurised state: steps and tolerance (relative to the shell's size).
NEWTON_STEPS, NEWTON_TOL = 40, 1e-13
#: A located bifurcation whose mode is largest within this many thicknesses of the axis is a pole's, not the
#: dimple's (module docstring).
POLE_SCALE = 2.0


def sphere_units() -> tuple[float, float, float]:
    """``(R, h, E)`` of the study's units: ``h = 1``, ``R = R/h``, ``p_c = 1``."""
    R, h = R_OVER_H, 1.0
    return R, h, math.sqrt(3.0 * (1.0 - NU * NU)) / (2.0 * (h / R) ** 2)


def reissner_stiffness(E: float, h: float, R: float, nu: float = NU) -> float:
    """Reissner's linear stiffness of a shallow sphere under a point force: ``4 E h^2 / (R sqrt(3 (1 - nu^2)))``."""
    return 4.0 * E * h * h / (R * math.sqrt(3.0 * (1.0 - nu * nu)))


def pressurised_stiffness(tau: float) -> float:
    """The linear point-load stiffness of a pressurised shallow sphere over Reissner's, ``k(tau) / k_R``.

    ``tau = p_int R^2 / (4 sqrt(E h D))`` (``D`` the bending stiffness) is ``-p / p_c`` for the external pressure
    ``p`` of this study.  The linear shallow-shell equation with the membrane tension ``p_int R / 2``,
    ``D lap^2 w - (p_int R / 2) lap w + (E h / R^2) w = F delta``, gives by a Hankel transform
    ``w(0) = F / (2 pi) int_0^inf k dk / (D k^4 + (p_int R / 2) k^2 + E h / R^2)``, whence
    ``k / k_R = (pi / 2) sqrt(1 - tau^2) / arccos(tau)`` for ``|tau| < 1`` and
    ``(pi / 2) sqrt(tau^2 - 1) / artanh(sqrt(1 - tau^-2))`` for ``tau > 1`` (Vella, Ajdari, Vaziri and Boudaoud
    2012, J. R. Soc. Interface 9, 448); 1 at ``tau = 0`` (Reissner), 0 at ``tau = -1`` (the classical buckling
    pressure), ``pi / 2`` at ``tau = 1``.
    """
    tau = float(tau)
    if tau <= -1.0:
        return 0.0
    if abs(tau - 1.0) < 1e-12:
        return math.pi / 2.0
    if tau < 1.0:
        return math.pi / 2.0 * math.sqrt(1.0 - tau * tau) / math.acos(tau)
    return math.pi / 2.0 * math.sqrt(tau * tau - 1.0) / math.atanh(math.sqrt(1.0 - 1.0 / (tau * tau)))


def reissner_rows() -> list[dict[str, Any]]:
    """The unpressurised sphere's pole stiffness (twice ``dF/dw``) over Reissner's at ``R/h`` = 100 and 1000 on three
    meshes each: the mesh's share and the thickness's share of the offset."""
    rows = []
    for r_over_h, sizes in ((R_OVER_H, (201, 401, 801)), (1000.0, (801, 1601, 3201))):
        for N in sizes:
            R, h, E = r_over_h, 1.0, 1.0
            st = ShellStructure(complete_sphere_meridian(R, N), E, NU, h, boundary="pinned")
            k_pole = 2.0 * ShellOfRevolution(st, "point", "displacement").linear_stiffness()
            rows.append({"R_over_h": r_over_h, "N": N, "k_pole_over_k_R": k_pole / reissner_stiffness(E, h, R)})
    return rows


def probed_sphere(N: int) -> ShellStructure:
    """The complete sphere of the study on its point support (south pole pinned)."""
    R, h, E = sphere_units()
    return ShellStructure(complete_sphere_meridian(R, N), E, NU, h, boundary="pinned")


def pressurised_state(structure: ShellStructure, p: float) -> np.ndarray:
    """The full state of the sphere under the pressure ``p`` alone (Newton's method from the reference)."""
    pr = ShellOfRevolution(structure, "pressure", p_c=1.0)
    u = pr.reference_unknowns()
    scale = float(structure.meridian.length_scale)
    for _ in range(NEWTON_STEPS):
        du = pr.factorize(pr.jacobian(u, p)).solve(-pr.residual(u, p))
        u = u + du
        if not np.all(np.isfinite(u)):
            raise ArithmeticError(f"pressurised state at p = {p:g}: Newton's iteration diverged")
        if np.max(np.abs(du)) < NEWTON_TOL * scale:
            return pr.full_state(u, p)
    raise ArithmeticError(f"pressurised state at p = {p:g}: Newton's iteration did not converge")


def probe_problem(structure: ShellStructure, p: float, control: str, x: np.ndarray,
                  harmonics: int = -1) -> tuple[Any, np.ndarray, float]:
    """The probe under ``control`` from the pressurised state ``x``: ``(problem, U0, w0)``."""
    if control not in CONTROLS:
        raise ValueError(f"control must be one of {CONTROLS}, got {control!r}")
    R = float(structure.meridian.length_scale)
    # a (tiny) pressure builds the volume term that with_pressure() then sets
    probe = ShellOfRevolution(structure, "point", "displacement", length=R, pressure=p if p else 1e-300,
                              harmonics=harmonics, pole_held=True).with_pressure(p)
    w0 = float(probe.x_ref[probe.z_node] - x[probe.z_node])
    u0 = probe.unknowns(x)
    if control == "pressure":
        return probe, u0, w0
    h = float(np.max(structure.h_nodes))
    volume = ProbeAtFixedVolume(probe, probe.pressure.volume(x), 1.0 / h, harmonics=harmonics, pole_held=True,
                                p_c=1.0)
    return volume, volume.join(u0, p), w0


def initial_stiffness(problem: Any, U: np.ndarray, w: float) -> float:
    """``dF/dw`` along the equilibrium path at ``(U, w)``: the tangent ``J dU/dw = -dR/dw`` and ``F``'s derivatives."""
    dU = problem.factorize(problem.jacobian(U, w)).solve(-problem.dresidual_dp(U, w))
    dFdU, dFdw = problem.observable_derivatives["F"](U, w)
    return float(np.dot(dFdU, dU) + dFdw)


def probe_case(p: float, control: str, N: int, w_end: float = W_END) -> dict[str, Any]:
    """One pressure and control: the path from the pressurised state, ``F_max``, the first bifurcations, the
    initial stiffness (module docstring)."""
    t0 = time.perf_counter()
    R, h, E = sphere_units()
    st = probed_sphere(N)
    K = default_harmonics(st)
    x = pressurised_state(st, p)
    problem, U0, w0 = probe_problem(st, p, control, x, K)
    k_R = reissner_stiffness(E, h, R)
    k_pole = 2.0 * initial_stiffness(problem, U0, w0)
    f_unit = E * h ** 3 / R
    br = contin.continuation(problem, U0, w0, contin.Settings(ds=0.05, ds_max=0.5, max_steps=4000, stability=True),
                             p_max=w0 + w_end, bounds={"F": (-1e-3 * f_unit, None)},
                             events=[contin.extremum("F", "max", name="F_max")])
    if br.status not in ("bound", "event"):
        raise RuntimeError(f"p = {p:g} p_c, {control} control, N = {N}: {br.message}")
    peaks = [s for s in br.special_points if s.label == "F_max" and s.located]
    waves = [s for s in br.special_points if s.kind == "bifurcation" and s.info.get("family") == "n" and s.located]
    # a mode that peaks within POLE_SCALE of the axis lives on the few rings next to a pole, where the point force's
    # hoop stress is singular and thin-shell theory does not hold: reported apart from the dimple's
    at_pole = [s for s in waves if int(s.info["key"]) >= 2 and mode_radius(st, s) < POLE_SCALE * h]
    first = next((s for s in waves if int(s.info["key"]) >= 2 and s not in at_pole), None)
    first_pole = at_pole[0] if at_pole else None
    lateral = next((s for s in waves if int(s.info["key"]) == 1), None)
    out: dict[str, Any] = {
        "p_over_p_c": p, "control": control, "N": N, "K": K, "w0": w0,
        "k_pole_over_k_R": k_pole / k_R, "k_closed_form": pressurised_stiffness(-p),
        "w_Fmax": float(peaks[0].p) - w0 if peaks else None,
        "F_max": float(peaks[0].observables["F"]) / f_unit if peaks else None,
        "n": int(first.info["key"]) if first else None,
        "w_bif": float(first.p) - w0 if first else None,
        "F_bif": float(first.observables["F"]) / f_unit if first else None,
        "p_bif": float(first.observables["p"]) if first and control == "volume" else (p if first else None),
        "n1_w": float(lateral.p) - w0 if lateral else None, "end": br.status,
        "n_pole": int(first_pole.info["key"]) if first_pole else None,
        "w_pole": float(first_pole.p) - w0 if first_pole else None,
        "r_mode": mode_radius(st, first) / h if first else None,
        "w_end": float(br.p[-1]) - w0}
    out["bifurcation_first"] = first is not None and (not peaks or out["w_bif"] < out["w_Fmax"])
    # blocks that lost stability in the same step as the located one (the engine's "also"), and every block's
    # own first crossing of zero, interpolated in w between the stored points' lowest eigenvalues: an independent
    # reading of how close the next wave numbers come
    out["n_also"] = " ".join(str(k) for k in first.info.get("also", ())) if first else ""
    out["crossings"] = " ".join(f"{n}:{wc:.4g}" for wc, n in block_crossings(br, w0)[:3])
    split = next((s for s in br.special_points if s.kind == "branch_point" and s.located), None)
    out["w_branch_point"] = float(split.p) - w0 if split else None
    out["F_branch_point"] = float(split.observables["F"]) / f_unit if split else None
    out["_w"] = (np.asarray(br.p) - w0) / R
    out["_F"] = np.asarray(br.observable("F")) / f_unit
    out["_stable"] = np.asarray(br.stable_under())  # under the control, every watched block counted
    out["_waves"] = [(float(s.p) - w0, float(s.observables["F"]) / f_unit, int(s.info["key"])) for s in waves]
    out["seconds"] = time.perf_counter() - t0
    return out


def mode_radius(structure: ShellStructure, point: contin.SpecialPoint) -> float:
    """The reference radius (distance from the axis) of the node where the located bifurcation's mode is largest."""
    n = int(point.info["key"])
    amplitude = np.linalg.norm(harmonic_mode(structure, n, np.asarray(point.info["mode"]), hold_pole=True), axis=1)
    return float(structure.meridian.r[int(np.argmax(amplitude))])


def block_crossings(branch: contin.Branch, w0: float) -> list[tuple[float, int]]:
    """Each watched block's first crossing of zero along the branch, ``(w - w0, n)`` sorted by ``w``: linear
    interpolation of its lowest eigenvalue (the estimate stored at every point) between the last point where it is
    positive and the first where it is negative."""
    modes = branch.meta["modes"]["n"]
    lowest = np.asarray(modes["lowest"], dtype=float)
    w = np.asarray(branch.p, dtype=float) - w0
    out = []
    for j, n in enumerate(modes["keys"]):
        neg = np.flatnonzero(lowest[:, j] < 0.0)
        if neg.size and neg[0] > 0:
            i = neg[0]
            a, b = lowest[i - 1, j], lowest[i, j]
            out.append((float(w[i - 1] + (w[i] - w[i - 1]) * a / (a - b)), int(n)))
    return sorted(out)


def mesh_rows(cases: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Every key number of each pressure and control at every ``N`` run, with its relative change from the next
    coarser ``N`` (``d_<key>``)."""
    keys = ("k_pole_over_k_R", "F_max", "w_Fmax", "F_bif", "w_bif")
    rows = []
    for (p, control) in sorted({(c["p_over_p_c"], c["control"]) for c in cases}):
        same = sorted((c for c in cases if c["p_over_p_c"] == p and c["control"] == control), key=lambda c: c["N"])
        if len(same) < 2:
            continue
        for prev, c in zip([None] + same[:-1], same):
            row: dict[str, Any] = {"p_over_p_c": p, "control": control, "N": c["N"], "n": c["n"]}
            for key in keys:
                row[key] = c[key]
                ok = prev is not None and prev[key] and c[key] is not None
                row[f"d_{key}"] = c[key] / prev[key] - 1.0 if ok else None
            rows.append(row)
    return rows


# ---- the figure ----------------------------------------------------------------------------------
def plot(cases: Sequence[dict[str, Any]], shown: Sequence[float]) -> Any:
    """The cases of one mesh: (a) ``F_max`` and the force at the first n-wave bifurcation against ``p / p_c`` for
    both controls, ``n`` written beside each bifurcation; (b) ``F`` against ``w / R`` at the pressures ``shown`` (solid: stable under
    the control against every watched mode, dotted: not), ``F_max`` and the first bifurcation into waves marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.style import COLORS, WIDTH

    N = cases[0]["N"]
    main = cases
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(WIDTH * 2.0, 4.2), layout="constrained")
    for control, color in zip(CONTROLS, COLORS):
        sel = sorted((c for c in main if c["control"] == control), key=lambda c: c["p_over_p_c"])
        peak = [c for c in sel if c["F_max"] is not None]
        ax.plot([c["p_over_p_c"] for c in peak], [c["F_max"] for c in peak], "-^" if control == "pressure" else "--v",
                color=color, ms=5, label=f"$F_{{max}}$, {control} control")
        bif = [c for c in sel if c["F_bif"] is not None]
        ax.plot([c["p_over_p_c"] for c in bif], [c["F_bif"] for c in bif], "--o", color=color, mfc="white", ms=5,
                label=f"first $n$-wave bifurcation, {control} control")
        for c in bif:
            ax.annotate(f"n={c['n']}" + ("" if c["bifurcation_first"] else "*"), (c["p_over_p_c"], c["F_bif"]),
                        textcoords="offset points", xytext=(4, 4 if control == "pressure" else -10),
                        fontsize="x-small", color=color)
    ax.set_yscale("log")
    ax.set_xlabel(r"pressure $p / p_c$ (external $> 0$, internal $< 0$)")
    ax.set_ylabel(r"probe force $F R / (E h^3)$")
    ax.set_title("largest force and the first bifurcation into waves\n(*: after $F_{max}$)",
                 fontsize="small")
    ax.legend(loc="upper right", fontsize="x-small")
    styles = {"pressure": "-", "volume": "--"}
    for k, p in enumerate(shown):
        color = COLORS[(k + 2) % len(COLORS)]
        for control in CONTROLS:
            c = next((c for c in main if c["p_over_p_c"] == p and c["control"] == control), None)
            if c is None:
                continue
            w, F, ok = c["_w"], c["_F"], c["_stable"]
            # the located points join both the stable and the unstable part (the stored points skip them)
            marks = [(c[a] / R_OVER_H, c[b]) for a, b in (("w_Fmax", "F_max"), ("w_bif", "F_bif")) if c[b] is not None]
            if marks:
                order = np.argsort(np.concatenate([w, [m[0] for m in marks]]), kind="stable")
                w = np.concatenate([w, [m[0] for m in marks]])[order]
                F = np.concatenate([F, [m[1] for m in marks]])[order]
                ok = np.concatenate([ok, np.ones(len(marks), dtype=bool)])[order]
                edge = np.concatenate([np.zeros(len(c["_w"]), dtype=bool), np.ones(len(marks), dtype=bool)])[order]
            else:
                edge = np.zeros(len(w), dtype=bool)
            bx.plot(np.where(ok, w, np.nan), np.where(ok, F, np.nan), styles[control], color=color, lw=1.2,
                    label=f"$p = {p:g}\\,p_c$, {control}")
            bx.plot(np.where(ok & ~edge, np.nan, w), np.where(ok & ~edge, np.nan, F), ":", color=color, lw=0.9)
            if c["F_max"] is not None:
                bx.plot([c["w_Fmax"] / R_OVER_H], [c["F_max"]], "^", color=color, ms=5)
            if c["n"] is not None:
                bx.plot([c["w_bif"] / R_OVER_H], [c["F_bif"]], "o", color=color, mfc="white", ms=5)
                bx.annotate(f"n={c['n']}", (c["w_bif"] / R_OVER_H, c["F_bif"]), textcoords="offset points",
                            xytext=(-24, 4) if control == "pressure" else (6, -10), fontsize="x-small", color=color)
    bx.set_xscale("log")
    bx.set_yscale("log")
    bx.set_xlim(1e-3, 1.0)
    bx.set_ylim(1e-2, None)
    bx.set_xlabel(r"probe travel $w / R$ (approach of the poles)")
    bx.set_ylabel(r"probe force $F R / (E h^3)$")
    bx.set_title("force against travel (solid, dashed: stable against every watched mode; dotted: not;\n"
                 "triangle: $F_{max}$; circle: first bifurcation into $n \\geq 2$ waves)", fontsize="small")
    bx.legend(loc="upper left", fontsize="x-small")
    fig.suptitle(f"complete sphere $R/h = {R_OVER_H:g}$, $\\nu = {NU:g}$, probed at its poles (N = {N})",
                 fontsize="small")
    return fig


# ---- the command line ----------------------------------------------------------------------------
COLUMNS = ["p_over_p_c", "control", "N", "K", "k_pole_over_k_R", "k_closed_form", "w_Fmax", "F_max", "w_branch_point",
           "F_branch_point", "n", "n_also", "crossings", "w_bif", "F_bif", "p_bif", "r_mode", "bifurcation_first",
           "n1_w", "n_pole", "w_pole", "end", "w_end", "seconds"]


def _public(case: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in case.items() if not k.startswith("_")}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("sphere_probe", "a pressurised complete sphere probed at its poles: the largest probe "
                                          "force and the first bifurcation into waves, pressure and volume control")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    t0 = time.perf_counter()
    if args.full:
        main_N = N_FULL
        runs = [(p, c, N) for N in (N_FAST, N_FULL) for p in PRESSURES_FULL for c in CONTROLS]
        runs += [(p, c, N_CHECK) for p in MESH_CHECK for c in CONTROLS]
        shown = (-1.0, 0.0, 0.5)
    else:
        main_N = N_FAST
        runs = [(p, c, N_FAST) for p in PRESSURES_FAST for c in CONTROLS]
        shown = PRESSURES_FAST
    cases = []
    for p, control, N in runs:
        say(args.quiet, f"p = {p:g} p_c, {control} control, N = {N} ...")
        cases.append(probe_case(p, control, N))
    reissner = reissner_rows()
    elapsed = time.perf_counter() - t0
    rows = [_public(c) for c in cases]
    write_csv(out / "stiffness.csv", reissner)
    mesh = mesh_rows(cases)
    write_csv(out / "cases.csv", [{k: r.get(k) for k in COLUMNS} for r in rows])
    write_csv(out / "paths.csv", [{"p_over_p_c": c["p_over_p_c"], "control": c["control"], "N": c["N"],
                                   "w_over_R": w, "F": F, "stable": int(ok)}
                                  for c in cases for w, F, ok in zip(c["_w"], c["_F"], c["_stable"])])
    write_json(out / "summary.json", {"full": bool(args.full), "seconds": elapsed, "nu": NU, "R_over_h": R_OVER_H,
                                      "force_unit": "E h^3 / R", "w": "approach of the poles", "cases": rows,
                                      "mesh": mesh, "reissner": reissner})
    save_figure(plot([c for c in cases if c["N"] == main_N], shown), out, "sphere_probe")
    if not args.quiet:
        print_table(rows, COLUMNS, digits=5)
        print()
        print_table(reissner, ["R_over_h", "N", "k_pole_over_k_R"], digits=5)
        if mesh:
            print()
            print_table(mesh, ["p_over_p_c", "control", "N", "n", "k_pole_over_k_R", "d_k_pole_over_k_R", "F_max",
                               "d_F_max", "w_Fmax", "d_w_Fmax", "F_bif", "d_F_bif", "w_bif", "d_w_bif"], digits=5)
        print(f"\n{elapsed:.1f} s; written to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
