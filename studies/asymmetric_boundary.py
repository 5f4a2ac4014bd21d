"""Issue 17, study (b): where the paper's point-loaded caps bifurcate before their limit load, as a curve.

Run ``python -m studies.asymmetric_boundary [--out DIR] [--full] [--n 3]``.

With the pole held laterally (``load.pole_held = true``), a thin deep cap of the paper (``nu = 0.5``)
leaves the axisymmetric path into ``n`` waves before the limit load ``F_max`` (the snap under force
control), a shallower or thicker one after it (``studies/asymmetric_point.py``, whose ``--boundary``
bisects for a few points).  Here the boundary is traced as a curve in the paper's plane
``(phi_hat, h/R)``:

* the **boundary function** of a cap is ``B = (w_n - w_Fmax) / R``: ``w_n`` the pole deflection at which
  the block of wave number ``n`` first becomes singular along the displacement-controlled path (located
  by the engine, :mod:`contin.watch.modes`, watching that block only), ``w_Fmax`` where the force is largest
  (a located extremum).  Both are smooth functions of the cap's parameters, so the boundary ``B = 0`` is
  a smooth curve;
* it is **continued** by the engine itself: :func:`contin.continuation` on the scalar problem
  ``B(phi_hat, y) = 0`` with the unknown ``y = ln(h/R)`` and the parameter ``phi_hat`` (pseudo-arclength,
  so the curve may turn), its derivatives by central differences of ``B`` (each evaluation a trace of
  the cap to its limit load and its bifurcation);
* its **first point** is the root in ``y`` at ``phi_hat = 0.8`` (Brent on ``h/R`` in ``[0.015, 0.02]``:
  on thicker caps the first ``n = 3`` crossing along the path lies beyond its first fold in ``w``, a
  different branch of ``B``), and the same root on meshes
  ``N = 100, 200, 400`` (``--full``: 800) gives the **mesh convergence** of the boundary's
  ``lambda = (12 (1 - nu^2))^(1/4) (pi/2 - phi_hat) / sqrt(h/R)``;
* the curve is drawn on the paper's phase diagram beside this model's traced bistable and monotonous
  boundaries (``lambda`` = 5.727 and 3.807, ``docs/reproduction.md``).

Writes ``boundary_curve.csv`` (the continued points: ``phi_hat``, ``h_over_R``, ``lambda``, ``B`` and
the two deflections), ``boundary_mesh.csv``, ``summary.json`` and ``asymmetric_boundary.png`` / ``.pdf``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin.app.scene import load_scene  # noqa: E402
from contin_models.shell_scene import SHELL_SCHEMA  # noqa: E402
from contin_models.shell_scene.build import end_of_path, point_problem, point_settings  # noqa: E402
from studies._common import output_dir, print_table, run_study, save_figure, say, study_parser, write_csv, write_json  # noqa: E402

NU = 0.5
LAMBDA_BISTABLE = 5.727  # this model's traced bistable / monostable boundary (docs/reproduction.md)
LAMBDA_MONOTONOUS = 3.807  # and its monostable / monotonous boundary
#: Step of the central differences of B in ln(h/R) and in phi_hat.
DIFF_STEP = 2e-4
#: The base angles the curve is continued over.
PHI_RANGE = (0.5, 1.2)


def depth_parameter(phi_hat: float, h_over_R: float, nu: float = NU) -> float:
    """The paper's ``lambda = (12 (1 - nu^2))^(1/4) (pi/2 - phi_hat) / sqrt(h/R)``."""
    return (12.0 * (1.0 - nu * nu)) ** 0.25 * (0.5 * math.pi - phi_hat) / math.sqrt(h_over_R)


class BoundaryFunction:
    """``B(phi_hat, h/R) = (w_n - w_Fmax) / R`` of the paper's point-loaded cap, pole held, on a mesh of N nodes.

    Every evaluation is kept (``calls``) with its two deflections, so that the study can report them.
    """

    def __init__(self, n: int, N: int) -> None:
        self.n, self.N = int(n), int(N)
        self.calls: list[dict[str, Any]] = []
        self._memo: dict[tuple[float, float], float] = {}

    def __call__(self, phi_hat: float, h: float) -> float:
        key = (float(phi_hat), float(h))
        if key not in self._memo:
            self._memo[key] = self._evaluate(*key)
        return self._memo[key]

    def _evaluate(self, phi_hat: float, h: float) -> float:
        sets = [f"shell.phi_hat={phi_hat!r}", f"shell.h={h!r}", f"shell.N={self.N}", "stability.harmonics=true",
                f"stability.n_max={self.n}", "load.pole_held=true", "load.control=displacement", "output.figure=false"]
        scene = load_scene(SHELL_SCHEMA, None, sets)
        problem = point_problem(scene, "displacement")
        family = problem.operator_families[0]
        problem.operator_families = (contin.OperatorFamily(family.name, (self.n,), family.operator,
                                                           family.multiplicity, vectors=False),)
        st = point_settings(scene, problem)
        R = scene["shell"]["R"]
        f_max = contin.extremum("F", "max", terminal=True, folds="F", stability_label="force")
        br = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, p_max=end_of_path(scene),
                                 events=[f_max])
        top = [s for s in br.special_points if s.kind == "event" and s.label == f_max.name]
        if not top:
            raise RuntimeError(f"B({phi_hat}, {h}): no maximum of F on the path ({br.message})")
        w_top = top[0].p
        bif = [s for s in br.special_points if s.kind == "bifurcation" and s.p <= w_top]
        if bif:
            w_n = bif[0].p
        else:  # on from the limit load to the bifurcation
            more = contin.continuation(problem, top[0].u, w_top, st, p_max=end_of_path(scene), stop_at=("bifurcation",))
            if more.meta["modes"]["n"]["n_negative"][0][0] > 0:
                # already unstable at the limit load: the crossing lay within the location tolerance of it,
                # on the far side of the terminal event of the first run
                w_n = w_top
            else:
                bif = [s for s in more.special_points if s.kind == "bifurcation"]
                if not bif:
                    raise RuntimeError(f"B({phi_hat}, {h}): no bifurcation into n = {self.n} on the path ({more.message})")
                w_n = bif[0].p
        value = (w_n - w_top) / R
        self.calls.append({"phi_hat": phi_hat, "h_over_R": h / R, "w_n_over_R": w_n / R, "w_Fmax_over_R": w_top / R,
                           "B": value})
        return value


def boundary_problem(B: BoundaryFunction) -> contin.Problem:
    """``B(phi_hat, exp(y)) = 0`` as a one-unknown problem (``u = [y]``, ``p = phi_hat``), derivatives by
    central differences of :data:`DIFF_STEP`."""

    def residual(u: np.ndarray, p: float) -> np.ndarray:
        return np.array([B(p, math.exp(u[0]))])

    def jacobian(u: np.ndarray, p: float) -> np.ndarray:
        d = DIFF_STEP
        return np.array([[(B(p, math.exp(u[0] + d)) - B(p, math.exp(u[0] - d))) / (2.0 * d)]])

    def dresidual_dp(u: np.ndarray, p: float) -> np.ndarray:
        d = DIFF_STEP
        return np.array([(B(p + d, math.exp(u[0])) - B(p - d, math.exp(u[0]))) / (2.0 * d)])

    return contin.Problem(residual=residual, jacobian=jacobian, dresidual_dp=dresidual_dp,
                          observables={"h_over_R": lambda u, p: math.exp(u[0]),
                                       "lambda": lambda u, p: depth_parameter(p, math.exp(u[0]))},
                          parameter_name="phi_hat", name=f"boundary n = {B.n}")


def root_in_h(B: BoundaryFunction, phi_hat: float, h_lo: float, h_hi: float, xtol: float = 1e-9) -> float:
    """The ``h/R`` in ``[h_lo, h_hi]`` where ``B = 0`` at ``phi_hat`` (Brent in ``ln h``)."""
    from scipy.optimize import brentq

    return math.exp(brentq(lambda y: B(phi_hat, math.exp(y)), math.log(h_lo), math.log(h_hi), xtol=xtol))


def trace_curve(B: BoundaryFunction, phi_0: float, h_0: float, phi_range: tuple[float, float],
                ds: float) -> list[dict[str, Any]]:
    """The boundary continued both ways from ``(phi_0, h_0)`` within ``phi_range``: one row per point."""
    problem = boundary_problem(B)
    st = contin.Settings(ds=ds, ds_max=ds, ds_min=1e-4 * ds, tol=1e-8, max_steps=60)
    rows: list[dict[str, Any]] = []
    for direction in (-1, +1):
        br = contin.continuation(problem, np.array([math.log(h_0)]), phi_0, st, direction=direction,
                                 p_min=phi_range[0], p_max=phi_range[1])
        for k in range(len(br)):
            rows.append({"phi_hat": float(br.p[k]), "h_over_R": float(br.observables["h_over_R"][k]),
                         "lambda": float(br.observables["lambda"][k]), "residual": float(br.residual[k]),
                         "direction": direction})
    rows.sort(key=lambda r: r["phi_hat"])
    unique: list[dict[str, Any]] = []
    for r in rows:  # the start point is in both directions' branches
        if not unique or abs(r["phi_hat"] - unique[-1]["phi_hat"]) > 1e-12:
            unique.append(r)
    return unique


def plot(curve: Sequence[dict[str, Any]], mesh: Sequence[dict[str, Any]], n: int) -> Any:
    """The continued curve on the paper's phase diagram (``h/R`` against ``phi_hat``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot import style as look

    fig, ax = plt.subplots(figsize=(look.WIDTH, 4.8))  # a page's width: printable as saved
    ff = np.linspace(0.45, 1.5, 200)
    for lam, label, style in ((LAMBDA_MONOTONOUS, r"monostable / monotonous ($\lambda$ = 3.81)", "--"),
                              (LAMBDA_BISTABLE, r"bistable / monostable ($\lambda$ = 5.73)", "-.")):
        ax.semilogy(ff, (depth_parameter(ff, 1.0) / lam) ** 2, style, color="gray", lw=1.0, label=label)
    ax.semilogy([r["phi_hat"] for r in curve], [r["h_over_R"] for r in curve], "-", color="tab:red", lw=1.6,
                label=f"bifurcation into $n$ = {n} at $F_\\mathrm{{max}}$ (continued, $N$ = {curve[0]['N'] if curve else '?'})")
    ax.semilogy([r["phi_hat"] for r in curve], [r["h_over_R"] for r in curve], ".", color="tab:red", ms=4)
    for r in mesh:
        ax.semilogy([r["phi_hat"]], [r["h_over_R"]], "o", mfc="none", color="k", ms=4 + 2 * math.log2(r["N"] / 100))
    if mesh:
        ax.plot([], [], "o", mfc="none", color="k", label="its point at $N$ = " + ", ".join(str(r["N"]) for r in mesh))
    ax.text(0.52, 0.0035, "bistable, bifurcates into\n$n$ = 3 before $F_\\mathrm{max}$", fontsize="small", color="tab:red")
    ax.text(0.55, 0.05, "bistable,\n$F_\\mathrm{max}$ first", fontsize="small", color="gray")
    ax.text(1.13, 0.021, "monostable", fontsize="small", color="gray")
    ax.text(1.3, 0.07, "monotonous", fontsize="small", color="gray")
    ax.set_xlabel(r"$\hat\phi$ (base angle) [rad]")
    ax.set_ylabel("$h/R$")
    ax.set_xlim(0.45, 1.5)
    ax.set_ylim(1e-3, 0.2)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    ax.set_title(r"point-loaded caps, $\nu = 0.5$, pole held: where the cap leaves the axisymmetric path"
                 "\nbefore its limit load", fontsize="small")
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("asymmetric_boundary", "the bifurcation-at-F_max boundary continued as a curve")
    parser.add_argument("--n", type=int, default=3, help="wave number whose boundary is traced (default 3)")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    n = args.n
    meshes = (100, 200, 400, 800) if args.full else (100, 200, 400)
    say(args.quiet, f"first point and mesh convergence at phi_hat = 0.8, N = {meshes} ...")
    mesh: list[dict[str, Any]] = []
    functions: dict[int, BoundaryFunction] = {}
    for N in meshes:
        B = functions[N] = BoundaryFunction(n, N)
        h = root_in_h(B, 0.8, 0.015, 0.02)
        mesh.append({"N": N, "phi_hat": 0.8, "h_over_R": h, "lambda": depth_parameter(0.8, h),
                     "evaluations": len(B.calls)})
    if len(mesh) >= 3:
        l1, l2, l3 = (m["lambda"] for m in mesh[-3:])
        if (l2 - l1) * (l3 - l2) > 0 and l3 != l2:
            order = math.log(abs(l2 - l1) / abs(l3 - l2), 2)
            for m in mesh:
                m["order"] = order
            mesh[-1]["richardson"] = l3 + (l3 - l2) / (2.0 ** order - 1.0)
    print_table(mesh, ["N", "phi_hat", "h_over_R", "lambda", "evaluations", "order", "richardson"])
    write_csv(out / "boundary_mesh.csv", mesh)
    N_curve = 200 if args.full else 100
    B = functions[N_curve]
    h0 = next(m["h_over_R"] for m in mesh if m["N"] == N_curve)
    say(args.quiet, f"continuing the boundary in phi_hat from (0.8, {h0:.5g}), N = {N_curve} ...")
    curve = trace_curve(B, 0.8, h0, PHI_RANGE, ds=0.08)
    for r in curve:
        r["N"] = N_curve
    print_table(curve, ["phi_hat", "h_over_R", "lambda", "residual", "direction"])
    write_csv(out / "boundary_curve.csv", curve)
    lams = [r["lambda"] for r in curve]
    summary = {"n": n, "nu": NU, "N_curve": N_curve, "points": len(curve), "evaluations_of_B": len(B.calls),
               "lambda_range": [min(lams), max(lams)], "phi_range": [curve[0]["phi_hat"], curve[-1]["phi_hat"]],
               "mesh": mesh}
    write_json(out / "summary.json", summary)
    say(args.quiet, f"lambda on the curve: {min(lams):.4f} .. {max(lams):.4f} ({len(curve)} points, "
                    f"{len(B.calls)} evaluations of B)")
    save_figure(plot(curve, mesh, n), out, "asymmetric_boundary")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
