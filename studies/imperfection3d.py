"""A cap with its three-wave mode as imperfection, in the 3-D view: the force maximum against the depth.

Run ``python -m studies.imperfection3d [--out DIR] [--quiet]`` (about half a minute).

For each of two sliding caps (``phi_hat = 0.8``, ``nu = 0.5``, E = 1e6, R = 1) in the ``D_3`` basis with
``K = 2`` harmonics: the perfect cap is traced under the pole's deflection to its three-wave branch point,
whose harmonic block gives the mode (:func:`contin_models.shell.imperfection3d.branch_mode`); the perfect
force maximum is located (the axisymmetric fold where it comes before the branch point, else the fold of
the three-wave branch, switched onto under force control); then the cap with the mode as imperfection
(:func:`~contin_models.shell.imperfection3d.mode_imperfection`, largest normal displacement ``delta``) is
traced under the pole force to its fold, for ``delta = 1e-1 .. 1e-3 h``.

* the paper's cap, h/R = 0.02, N = 40: the axisymmetric fold comes first;
* a thinner cap, h/R = 0.01, N = 50: the three-wave bifurcation comes first.

Outputs in ``--out`` (default ``out/imperfection3d``): ``summary.json`` and the tables on stdout.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from studies._common import output_dir, print_table, run_study, say, study_parser, write_json  # noqa: E402

#: ``(label, N, h/R)`` of the caps.
CAPS = (("paper cap", 40, 0.02), ("thinner cap", 50, 0.01))
#: The imperfection's depths over the thickness.
DEPTHS = (1e-1, 3e-2, 1e-2, 3e-3, 1e-3)


def _fold(prob: Any, u0: np.ndarray, p0: float = 0.0) -> Any:
    br = contin.continuation(prob, u0, p0, p_max=1e9, ds=0.01, ds_max=0.05, max_steps=4000, stop_at=("fold",))
    folds = [s for s in br.special_points if s.kind == "fold" and s.located]
    if not folds:
        raise RuntimeError(f"imperfection3d: no located fold ({br.message})")
    return folds[0]


def cap_table(N: int, h: float) -> dict[str, Any]:
    """The perfect cap's branch point and force maximum, and the imperfect caps' force maxima."""
    from contin_models.shell.fourier import AngularBasis
    from contin_models.shell.geometry import spherical_cap
    from contin_models.shell.imperfection3d import branch_mode, mode_imperfection
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellStructure

    st = ShellStructure(spherical_cap(1.0, 0.8, N), 1e6, 0.5, h, boundary="sliding")
    basis = AngularBasis(3, 2)
    disp = Shell3D(st, basis, "point", "displacement")
    first = contin.continuation(disp, disp.reference_unknowns(), 0.0, p_max=0.6, ds=0.01, ds_max=0.02,
                                max_steps=2000, stability=True, n_eigs=0, stop_at=("branch_point",))
    bp = first.special_points[-1] if first.special_points else None
    if bp is None or bp.kind != "branch_point" or not bp.located:
        raise RuntimeError(f"imperfection3d: no located branch point before w = 0.6 ({first.message})")
    mode = branch_mode(st, disp.full_state(bp.u, bp.p)[disp.view.axisymmetric_dofs()], 3)
    force = Shell3D(st, basis, "point", "force")
    fold = _fold(force, force.reference_unknowns())
    F = force.observables["F_norm"]
    w = force.observables["w"]
    if w(fold.u, fold.p) < bp.p:
        perfect, what = fold, "axisymmetric fold"
    else:
        path = contin.continuation(force, force.reference_unknowns(), 0.0, p_max=1e9, ds=0.01, ds_max=0.05,
                                   max_steps=4000, stability=True, n_eigs=0, stop_at=("branch_point",))
        branch = contin.switch_branch(force, path.special_points[-1], settings=contin.Settings(ds=0.005, ds_max=0.05),
                                      max_steps=4000, p_max=1e9, stop_at=("fold",))
        folds = [s for s in branch.special_points if s.kind == "fold" and s.located]
        if not folds:
            raise RuntimeError(f"imperfection3d: the three-wave branch has no located fold ({branch.message})")
        perfect, what = folds[0], "fold of the three-wave branch"
    F_perfect = F(perfect.u, perfect.p)
    rows = []
    for depth in DEPTHS:
        c_bar = mode_imperfection(st, basis, 3, mode, depth * h)
        prob = Shell3D(st, basis, "point", "force", reference=c_bar)
        top = _fold(prob, prob.reference_unknowns())
        c = prob.full_state(top.u, top.p)
        waves = float(np.max(np.abs(np.delete(c - c_bar, prob.view.axisymmetric_dofs()))))
        Fmax = prob.observables["F_norm"](top.u, top.p)
        rows.append({"delta_over_h": depth, "F_max": Fmax, "F_max_over_perfect": Fmax / F_perfect,
                     "w_at_F_max": prob.observables["w"](top.u, top.p), "waves_over_h": waves / h})
    return {"N": N, "h": h, "w_bp": float(bp.p), "F_bp": float(disp.observables["F_norm"](bp.u, bp.p)), "perfect": what,
            "F_perfect": F_perfect, "w_perfect": w(perfect.u, perfect.p), "rows": rows}


def main(argv: Sequence[str] | None = None) -> int:
    args = study_parser("imperfection3d", __doc__.splitlines()[0]).parse_args(argv)
    out = output_dir(args.out)
    doc: dict[str, Any] = {"command": "python -m studies.imperfection3d"}
    for label, N, h in CAPS:
        say(args.quiet, f"{label}: N = {N}, h/R = {h}")
        t = cap_table(N, h)
        doc[label] = t
        print(f"{label} (h/R = {h}, N = {N}, D_3, K = 2): branch point w/R = {t['w_bp']:.5f} (F_norm "
              f"{t['F_bp']:.5f}); perfect maximum, the {t['perfect']}: F_norm = {t['F_perfect']:.5f} at "
              f"w/R = {t['w_perfect']:.5f}")
        print_table(t["rows"], ["delta_over_h", "F_max", "F_max_over_perfect", "w_at_F_max", "waves_over_h"])
    write_json(out / "summary.json", doc)
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
