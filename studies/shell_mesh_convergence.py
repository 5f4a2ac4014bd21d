"""Mesh convergence and closed-form limits of the point-indented shell.

Default scene: ``phi_hat = 0.8``, ``h/R = 0.02``, ``nu = 0.5``, ``E = 1e6``, ``R = 1``.  Run
``python -m studies.shell_mesh_convergence`` (about 20 s with single-threaded BLAS on the
development machine; ``--quick`` skips the meshes above N = 800 and the pole-variant survey, about
10 s).  It prints the numbers
asserted in ``tests/test_shell_convergence.py`` and quoted in ``models/shell/problem.py`` and
``models/shell/energy.py``:

Every section uses the default mesh, graded towards the pole (``pole_ratio = 0.5``, see
:func:`contin_models.shell.geometry.theta_nodes`); sections 1 and 2 also show the uniform mesh
(``pole_ratio = 1``) beside it.

1. Variants.  For each mesh, curvature length (``kappa11_length``) and pole treatment, over
   N = 50 .. 800: F at ``w/R = 0.1`` (displacement-controlled trace), the linear stiffness over
   Reissner's ``8 sqrt(D E h) / R``, and successive-difference orders.
2. Observed order of ``F(w/R = 0.1)`` and ``F_max`` (first maximum of F on the
   displacement-controlled path = force-control limit load) for the default scene, under three
   definitions: (a) successive differences ``log2(|F_N - F_{N/2}| / |F_{2N} - F_N|)``, (b) the
   error against a Richardson reference from the finest meshes, ``log2(e_N / e_{2N})``, (c) the
   least-squares fit ``F_N = F_inf + alpha N^-p`` over N = 50 .. 800 (Eca & Hoekstra).  ``F_max``
   is also located as a fold under force control, as a cross-check.
3. Pole variants (not in the model; a survey of what the pole element controls): the pole's area
   weight scaled by a factor, and the pole curvature with the reference instead of the current
   last-edge length.
4. Reissner's limit: ``k / k_R`` for ``h/R`` in {0.001, 0.002, 0.005, 0.02} at ``N_0 =
   100 / sqrt(h/R)``, ``2 N_0``, ``4 N_0``; the fitted shortfall law in ``sqrt(h/R)`` and its
   extrapolation to ``h/R = 0``; the part of the shortfall due to the sliding base (stiffness with
   the base pinned, ``r_0`` fixed too) against Geckeler's edge-layer compliance, at
   ``N = 50 / sqrt(h/R)`` and ``100 / sqrt(h/R)``.
5. Scale invariance: largest relative change of ``w/R`` and ``F_norm`` over every special point of
   the default-scene trace (``contin trace --model shell``, N = 40) when ``E -> 1e3 E`` and
   ``(R, h) -> 10 (R, h)``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import io  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import least_squares  # noqa: E402

from contin import continuation, extremum  # noqa: E402
from contin.numerics.linalg import BandedLU  # noqa: E402
from contin_models.shell import HALF_BANDWIDTH, PoleMirror, ShellPointLoad  # noqa: E402
from contin_models.shell.geometry import POLE_RATIO  # noqa: E402

NS = (50, 100, 200, 400, 800)
#: node gradings compared: the default (graded towards the pole) and the paper's uniform mesh
MESHES = (POLE_RATIO, 1.0)
H_OVER_R = (0.001, 0.002, 0.005, 0.02)
#: thinner shells for the edge-compliance check (the sliding-minus-pinned compliance is
#: mesh-independent to 1e-4, so these are cheap)
H_OVER_R_THIN = (1e-4, 2e-4, 5e-4, 1e-3)


# ---- convergence bookkeeping ---------------------------------------------------------------------
def observed_orders(values: Sequence[float]) -> list[float]:
    """Orders ``log2(|d_i / d_{i+1}|)`` from successive differences of a sequence over halved meshes."""
    d = np.diff(np.asarray(values, dtype=float))
    return [math.log2(abs(d[i] / d[i + 1])) for i in range(len(d) - 1)]


def richardson(values: Sequence[float]) -> tuple[float, float]:
    """Richardson limit from the last three values of a sequence over halved meshes.

    Returns ``(limit, p)`` with ``p`` the order observed on those three meshes.
    """
    f0, f1, f2 = (float(v) for v in values[-3:])
    p = math.log2(abs((f1 - f0) / (f2 - f1)))
    return f2 + (f2 - f1) / (2.0**p - 1.0), p


def orders_against(values: Sequence[float], reference: float) -> list[float]:
    """Orders ``log2(e_N / e_{2N})`` of the errors ``e_N = |F_N - reference|``."""
    e = np.abs(np.asarray(values, dtype=float) - reference)
    return [math.log2(e[i] / e[i + 1]) for i in range(len(e) - 1)]


def least_squares_order(ns: Sequence[int], values: Sequence[float]) -> tuple[float, float, float]:
    """Fit ``F_N = F_inf + alpha N^-p`` to all meshes (Eca & Hoekstra); returns ``(F_inf, alpha, p)``."""
    ns_a = np.asarray(ns, dtype=float)
    f = np.asarray(values, dtype=float)
    # residuals scaled by the spread of the data so the fit is well conditioned for any F scale
    scale = float(np.ptp(f))

    def residual(c: np.ndarray) -> np.ndarray:
        return (c[0] + c[1] * ns_a ** -c[2] - f) / scale

    start = np.array([f[-1], (f[0] - f[-1]) * ns_a[0] ** 2, 2.0])
    sol = least_squares(residual, start, x_scale=np.array([scale, abs(start[1]), 1.0]))
    return float(sol.x[0]), float(sol.x[1]), float(sol.x[2])


# ---- traces ----------------------------------------------------------------------------------------
def force_at(shell: ShellPointLoad, w_over_R: float = 0.1) -> float:
    """Pole force F at ``w = w_over_R R`` on the displacement-controlled path from the reference state."""
    br = continuation(shell, shell.reference_unknowns(), 0.0, p_max=w_over_R * shell.R, ds=0.01 * shell.R,
                      ds_max=0.05 * shell.R, detect_branch_points=False)
    if br.status != "bound":
        raise RuntimeError(f"{shell!r}: the trace to w/R = {w_over_R} stopped early ({br.message})")
    return float(br.observables["F"][-1])


def first_force_maximum(shell: ShellPointLoad, **overrides: Any) -> tuple[float, float]:
    """``(F_max, w/R)`` at the first maximum of F on the displacement-controlled path.

    Parameters
    ----------
    shell : ShellPointLoad
        The displacement-controlled problem, traced from its reference state.
    **overrides
        :class:`contin.Settings` fields that replace the defaults of this trace (up to ``w = R/2``,
        ``ds = 0.02 R``, ``ds_max = 0.05 R``, no branch-point detection).

    Returns
    -------
    tuple of float
        ``F`` and ``w/R`` at the located maximum.

    Raises
    ------
    RuntimeError
        If no maximum is found before ``w = R/2``, or it is only bracketed between stored points.
    """
    opts: dict[str, Any] = {"p_max": 0.5 * shell.R, "ds": 0.02 * shell.R, "ds_max": 0.05 * shell.R,
                            "detect_branch_points": False, **overrides}
    br = continuation(shell, shell.reference_unknowns(), 0.0, events=[extremum("F", "max", terminal=True)], **opts)
    where = f"{shell!r}" + (f", {overrides}" if overrides else "")
    found = br.events("max(F)")
    if not found:
        raise RuntimeError(f"{where}: no maximum of F before w/R = 0.5 ({br.status}: {br.message})")
    if not found[0].located:
        # a bracketed maximum is a stored point near it, not the maximum: never report it as converged
        raise RuntimeError(f"{where}: the maximum of F was bracketed but not located "
                           f"({found[0].info.get('error', '')}; {br.message})")
    return float(found[0].observables["F"]), float(found[0].observables["w_over_R"])


def force_limit_load(N: int, pole_ratio: float = POLE_RATIO) -> float:
    """First limit point of F under force control (dead load), located as a fold."""
    shell = ShellPointLoad(N=N, control="force", pole_ratio=pole_ratio)
    # F is measured in units of 10 * 2 pi D / R in the arclength norm (as in the shell scene)
    f_unit = 2.0 * math.pi * shell.D / shell.R
    br = continuation(shell, shell.reference_unknowns(), 0.0, ds=0.02, ds_max=0.05, param_weight=1.0 / (10.0 * f_unit),
                      stop_at=("fold",), detect_branch_points=False)
    folds = [sp for sp in br.special_points if sp.kind == "fold"]
    if not folds:
        raise RuntimeError(f"N = {N}: no force limit point ({br.message})")
    return float(folds[0].p)


# ---- linear stiffness with a choice of fixed dofs --------------------------------------------------
def condensed_stiffness(shell: ShellPointLoad, pinned_base: bool = False) -> float:
    """``dF/dw`` at the reference state by static condensation of the full elastic Hessian.

    ``pinned_base=False`` reproduces :meth:`ShellPointLoad.linear_stiffness` (sliding base: only
    ``z_0`` fixed); ``True`` fixes ``r_0`` as well (a hinged edge, free to rotate), which removes
    the compliance of the edge bending layer that a sliding base needs (see :func:`geckeler_coefficient`).
    """
    H = shell.elastic_hessian(shell.cap.x).tocsr()
    free = shell.idx_displacement[1:] if pinned_base else shell.idx_displacement
    pole = shell.n_full - 1
    Huu = H[free][:, free].tocsr()
    Hup = H[free][:, [pole]].toarray().ravel()
    y = BandedLU(Huu, HALF_BANDWIDTH, HALF_BANDWIDTH).solve(Hup)
    return float(H[pole, pole] - Hup @ y)


def geckeler_coefficient(phi_hat: float, nu: float) -> float:
    """Leading coefficient ``c`` of the sliding-base compliance ``k_R / k - 1 ~ c sqrt(h/R)``.

    The membrane state of a cap under an apex load ``F`` has the meridional force
    ``N = F / (2 pi R cos^2 phi_hat)`` at the base, tangent to the meridian; a sliding base (z
    fixed, r free) cannot take its horizontal part ``H = N sin phi_hat``, which an edge bending
    layer must carry instead.  Geckeler's approximation gives the edge's horizontal displacement
    ``delta = 2 R lambda cos^2 phi_hat H / (E h)``, ``lambda = (3 (1 - nu^2))^(1/4) sqrt(R / h)``
    (Timoshenko & Woinowsky-Krieger, spherical shells under edge forces).  By Clapeyron the extra
    compliance is ``2 pi R cos phi_hat H delta / F^2 = lambda sin^2 phi_hat / (pi E h cos phi_hat)``,
    and divided by Reissner's ``R / (8 sqrt(D E h))``:
    ``c = 4 sin^2 phi_hat / (pi cos phi_hat (3 (1 - nu^2))^(1/4))``.
    """
    return 4.0 * math.sin(phi_hat) ** 2 / (math.pi * math.cos(phi_hat) * (3.0 * (1.0 - nu**2)) ** 0.25)


def reissner_meshes(h_over_R: float) -> tuple[int, int, int]:
    """Meshes ``N_0, 2 N_0, 4 N_0`` with ``N_0 = 100 / sqrt(h/R)``: a fixed number of nodes per bending length."""
    n0 = int(round(100.0 / math.sqrt(h_over_R)))
    return n0, 2 * n0, 4 * n0


def _edge_meshes(h_over_R: float) -> tuple[int, int]:
    """Meshes of the edge-compliance check: the difference of compliances is mesh-independent to 1e-4."""
    return int(round(50.0 / math.sqrt(h_over_R))), int(round(100.0 / math.sqrt(h_over_R)))


# ---- pole variants (study only) ----------------------------------------------------------------------
def with_pole_variant(shell: ShellPointLoad, area_factor: float = 1.0,
                      current_length: bool | None = None) -> ShellPointLoad:
    """Replace the pole element of ``shell`` by a modified :class:`PoleMirror` (in place).

    A survey tool, not a model option (:meth:`ShellPointLoad.use_pole_element`).
    """
    old = shell.pole_element
    cap = shell.cap
    pole = PoleMirror(cap.edge_length[-1], shell.shell.kb, shell.shell.nu,
                      old.current_length if current_length is None else current_length,
                      float(cap.r[-2]), float(cap.z[-1] - cap.z[-2]))
    pole.K *= area_factor
    shell.use_pole_element(pole)
    return shell


# ---- sections -------------------------------------------------------------------------------------
def _fmt(values: Sequence[float], digits: int = 4) -> str:
    return "[" + ", ".join(f"{v:.{digits}f}" for v in values) + "]"


def section_variants() -> dict[tuple[str, str, float], list[float]]:
    """Section 1; returns ``F(w/R = 0.1)`` over :data:`NS` for each ``(kappa11_length, pole, pole_ratio)``."""
    print("1. Variants: F(w/R=0.1) and k/k_Reissner over N =", NS)
    out = {}
    for q in MESHES:
        for length in ("reference", "current"):
            for pole in ("mirror", "skip"):
                forces, stiffness = [], []
                for N in NS:
                    shell = ShellPointLoad(N=N, kappa11_length=length, pole=pole, pole_ratio=q)
                    forces.append(force_at(shell))
                    stiffness.append(shell.linear_stiffness() / shell.reissner_stiffness())
                out[(length, pole, q)] = forces
                print(f"  pole_ratio={q:<4g} kappa11_length={length:9s} pole={pole:6s}")
                print(f"    F(w/R=0.1)     = {np.array2string(np.array(forces), precision=8)}")
                print(f"    orders of F    = {_fmt(observed_orders(forces), 3)}")
                print(f"    k / k_Reissner = {np.array2string(np.array(stiffness), precision=7)}, "
                      f"orders {_fmt(observed_orders(stiffness), 3)}", flush=True)
    return out


def section_orders(quick: bool, variants: dict[tuple[str, str, float], list[float]]) -> None:
    fine_F = (1600, 3200, 6400) if not quick else ()
    fine_max = (1600, 3200) if not quick else ()
    references: dict[str, float] = {}
    errors: dict[tuple[str, float], list[float]] = {}
    for q in MESHES:
        mesh = "graded (default)" if q == POLE_RATIO else "uniform"
        print(f"\n2. Observed orders, default scene (kappa11_length='current', pole='mirror'), {mesh} mesh, "
              f"pole_ratio = {q:g}")
        ns_F = NS + fine_F
        F = [force_at(ShellPointLoad(N=N, pole_ratio=q)) for N in ns_F]
        ns_M = NS + fine_max
        maxima = [first_force_maximum(ShellPointLoad(N=N, pole_ratio=q)) for N in ns_M]
        Fmax = [m[0] for m in maxima]
        for name, ns, vals in (("F(w/R=0.1)", ns_F, F), ("F_max", ns_M, Fmax)):
            print(f"  {name}: N = {ns}")
            print(f"    values = {np.array2string(np.array(vals), precision=10)}")
            print(f"    (a) successive-difference orders = {_fmt(observed_orders(vals))}")
            if len(ns) > len(NS):
                ref, p = richardson(vals)
                references.setdefault(name, ref)  # the first mesh's reference serves both meshes
                print(f"    (b) Richardson reference from N = {ns[-3:]}: {ref:.10f} (order {p:.4f} there); "
                      f"orders of |F_N - ref| over N = {NS}: {_fmt(orders_against(vals[:len(NS)], ref))}")
                print(f"        relative errors at N = {NS}: "
                      + ", ".join(f"{abs(v - ref) / abs(ref):.2e}" for v in vals[:len(NS)]))
                errors[(name, q)] = [abs(v - references[name]) for v in vals[:len(NS)]]
                if name.startswith("F(w/R") and ("current", "skip", q) in variants:
                    ratios = [abs(v - ref) / abs(v0 - ref) for v, v0 in zip(variants[("current", "skip", q)], vals)]
                    print(f"        pole='skip': errors {_fmt(ratios, 1)} times those of 'mirror'")
            f_inf, alpha, p = least_squares_order(NS, vals[:len(NS)])
            print(f"    (c) least-squares F_inf + alpha N^-p over N = {NS}: p = {p:.4f} (F_inf = {f_inf:.8f})")
            f_inf, alpha, p = least_squares_order(NS[1:], vals[1:len(NS)])
            print(f"        same over N = {NS[1:]}: p = {p:.4f}")
        print(f"  w/R at F_max: {_fmt([m[1] for m in maxima], 6)}")
        ns_fold = NS if not quick else NS[:3]
        folds = [force_limit_load(N, q) for N in ns_fold]
        dev = max(abs(a - b) / abs(b) for a, b in zip(folds, Fmax))
        print(f"  F_max as a force-control fold over N = {ns_fold}: {np.array2string(np.array(folds), precision=10)}; "
              f"largest relative difference from the extremum under displacement control {dev:.1e}", flush=True)
    if len(MESHES) == 2 and errors:
        graded, uniform = POLE_RATIO, 1.0
        print("\n  error of the graded mesh / error of the uniform mesh at N =", NS, "(common reference)")
        for name in references:
            ratio = [a / b for a, b in zip(errors[(name, graded)], errors[(name, uniform)])]
            print(f"    {name}: {_fmt(ratio, 2)}")


def section_pole_variants() -> None:
    print("\n3. Pole variants (survey only): successive-difference orders of F(w/R=0.1) over N =", NS)
    cases = [("area x 0 (no pole bending)", dict(area_factor=0.0)),
             ("area x 0.5", dict(area_factor=0.5)),
             ("area x 1 (the model: the pole's Voronoi disc)", dict(area_factor=1.0)),
             ("area x 1.25", dict(area_factor=1.25)),
             ("area x 2", dict(area_factor=2.0)),
             ("pole length = reference lbar", dict(current_length=False))]
    for label, kw in cases:
        forces = [force_at(with_pole_variant(ShellPointLoad(N=N), **kw)) for N in NS]
        ks = [with_pole_variant(ShellPointLoad(N=N), **kw).linear_stiffness() for N in NS]
        print(f"  {label:46s} F(800) = {forces[-1]:.8f}  orders of F {_fmt(observed_orders(forces), 3)}"
              f"  orders of k {_fmt(observed_orders(ks), 3)}", flush=True)


def section_reissner() -> None:
    print("\n4. Reissner limit, phi_hat = 0.8, nu = 0.5: k/k_R at N_0 = 100/sqrt(h/R), 2 N_0, 4 N_0")
    shortfall = []
    for hr in H_OVER_R:
        ns = reissner_meshes(hr)
        ratios = []
        for N in ns:
            shell = ShellPointLoad(h=hr, N=N)
            ratios.append(shell.linear_stiffness() / shell.reissner_stiffness())
        d1, d2 = ratios[1] - ratios[0], ratios[2] - ratios[1]
        p = math.log2(abs(d1 / d2))
        err = abs(d2) / (2.0**p - 1.0) / ratios[2]
        shortfall.append(1.0 - ratios[2])
        print(f"  h/R = {hr:<6g} N = {ns}: k/k_R = {_fmt(ratios, 7)}; relative changes "
              f"{abs(d1) / ratios[1]:.1e}, {abs(d2) / ratios[2]:.1e}; order {p:.3f}; "
              f"estimated error at 4 N_0 {err:.1e}; shortfall 1 - k/k_R = {shortfall[-1]:.5f} "
              f"= {shortfall[-1] / math.sqrt(hr):.4f} sqrt(h/R)")
    x = np.sqrt(np.array(H_OVER_R))
    s = np.array(shortfall)
    c3 = np.linalg.lstsq(np.vstack([np.ones_like(x), x, x * x]).T, s, rcond=None)[0]
    c2 = np.linalg.lstsq(np.vstack([np.ones_like(x), x]).T, s, rcond=None)[0]
    slope = np.polyfit(np.log(np.array(H_OVER_R)), np.log(s), 1)[0]
    res3 = np.max(np.abs(np.vstack([np.ones_like(x), x, x * x]).T @ c3 - s))
    print(f"  shortfall fit  s = {c3[0]:+.5f} {c3[1]:+.4f} sqrt(h/R) {c3[2]:+.4f} h/R  (max residual {res3:.1e})"
          f" -> k/k_R at h/R = 0: {1 - c3[0]:.5f}")
    print(f"  shortfall fit  s = {c2[0]:+.5f} {c2[1]:+.4f} sqrt(h/R)  -> k/k_R at h/R = 0: {1 - c2[0]:.5f}")
    print(f"  log-log slope of s against h/R: {slope:.4f}")

    c_g = geckeler_coefficient(0.8, 0.5)
    print(f"  sliding-base edge compliance: (k_R/k_sliding - k_R/k_pinned) / sqrt(h/R), Geckeler c = {c_g:.4f}")
    rows = []
    for hr in H_OVER_R_THIN + H_OVER_R[1:]:
        vals = []
        for N in _edge_meshes(hr):
            shell = ShellPointLoad(h=hr, N=N)
            kR = shell.reissner_stiffness()
            k_s, k_p = condensed_stiffness(shell) / kR, condensed_stiffness(shell, pinned_base=True) / kR
            vals.append(((1 / k_s - 1 / k_p) / math.sqrt(hr), k_s, k_p))
        rows.append((hr, vals))
        print(f"    h/R = {hr:<6g} N = {_edge_meshes(hr)}: coefficient {vals[0][0]:.5f}, {vals[1][0]:.5f}; "
              f"k/k_R sliding {vals[1][1]:.6f}, pinned {vals[1][2]:.6f}")
    xt = np.sqrt(np.array(H_OVER_R_THIN))
    ct = np.array([r[1][1][0] for r in rows[:len(H_OVER_R_THIN)]])
    lin = np.polyfit(xt, ct, 1)
    print(f"    linear extrapolation to h/R = 0 over h/R = {H_OVER_R_THIN}: {lin[1]:.5f} "
          f"({(lin[1] / c_g - 1) * 100:+.2f} % from Geckeler)", flush=True)


def _special_points(sets: Sequence[str], out: Path) -> list[dict]:
    """Special points of ``contin trace --model shell`` at N = 40 with extra ``--set`` options."""
    from contin.app.cli import main as cli_main

    args = ["trace", "--model", "shell", "-q", "--out", str(out), "--set", "shell.N=40", "--set", "output.figure=false"]
    for s in sets:
        args += ["--set", s]
    with contextlib.redirect_stdout(io.StringIO()):  # the runner prints its table even with -q
        status = cli_main(args)
    if status != 0:
        raise RuntimeError(f"contin {' '.join(args)} failed with status {status}")
    return json.loads((out / "summary.json").read_text())["special_points"]


def section_scale_invariance() -> None:
    print("\n5. Scale invariance (contin trace --model shell, N = 40): E x 1e3, R and h x 10")
    scaled = ["shell.E=1e9", "shell.R=10", "shell.h=0.2"]
    with tempfile.TemporaryDirectory() as tmp:
        for tol in ("1e-10", "1e-11"):  # the scene's default tolerance, and a tighter one
            a = _special_points([f"continuation.tol={tol}"], Path(tmp) / f"base{tol}")
            b = _special_points(scaled + [f"continuation.tol={tol}"], Path(tmp) / f"scaled{tol}")
            worst = max(abs(q[k] - p[k]) / abs(p[k]) for p, q in zip(a, b) for k in ("w_over_R", "F_norm"))
            same = ([(p["kind"], p["parameter"], p["label"]) for p in a]
                    == [(q["kind"], q["parameter"], q["label"]) for q in b])
            print(f"  tol = {tol}: {len(a)} and {len(b)} special points (same kinds and order: {same}); "
                  f"largest relative change of w/R and F_norm: {worst:.1e}", flush=True)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N <= 800 only, no pole-variant survey")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    variants = section_variants()
    section_orders(args.quick, variants)
    if not args.quick:
        section_pole_variants()
    section_reissner()
    section_scale_invariance()
    print(f"\nwall time {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
