"""The plate's contact ring: is the dimple branch smooth, and does the dimple snap converge with N?

Run ``python -m studies.plate_ring [--out DIR] [--full]``.  The plate indenter of the default cap
(displacement control) first snaps into a dimple held by a ring of contact.  The barrier sees the
meridian between the nodes (:mod:`contin_models.contact.barrier`), so the ring should move continuously:

* **convergence**: the dimple snap (the first fold in the travel ``w_b``) traced on meshes N = 100,
  200, 400 (``--full``: 200, 400, 800); its ``w_b`` and ``F`` and their differences between
  successive meshes, which must shrink;
* **smoothness**: on the N = 200 trace of ``contin trace --set load.kind=plate``, the number of sign
  changes of ``dF/dw_b`` along the dimple branch (the branch after the first snap).  A contact that
  saw only the nodes gave about 150 (the ring hopping from node to node); a smooth branch has only
  its real extrema.

Writes ``convergence.csv``, ``summary.json`` and ``plate_ring.png`` / ``.pdf`` (the dimple branch's
force against travel, and the snap against N).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin.app.scene import load_scene  # noqa: E402
from contin_models.shell_scene import SHELL_SCENE, contact_problem  # noqa: E402
from studies._common import (output_dir, print_table, run_study, save_figure, say, study_parser,  # noqa: E402
                             write_csv, write_json)


def dimple_snap(N: int) -> dict[str, Any]:
    """The first fold in ``w_b`` of the plate on the default cap with ``N`` nodes: ``w_b``, ``F``, ``F_norm``."""
    scene = load_scene(SHELL_SCENE.schema, None, ["load.kind=plate", f"shell.N={N}"])
    problem = contact_problem(scene)
    st = contin.Settings(ds=0.02, ds_max=0.1, tol=1e-10, max_steps=3000)
    br = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, stop_at=("fold",), p_max=0.3)
    fold = br.special_points[-1] if br.special_points else None
    if fold is None or fold.kind != "fold" or not fold.located:
        raise RuntimeError(f"N = {N}: no located dimple snap ({br.message})")
    return {"N": N, "w_b": float(fold.p), "F": float(fold.observables["F"]),
            "F_norm": float(fold.observables["F_norm"]), "steps": len(br.p)}


def dimple_branch(N: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """``w_b`` and ``F`` along the dimple branch (after the first snap) of the plate trace at ``N``."""
    scene = load_scene(SHELL_SCENE.schema, None, ["load.kind=plate", f"shell.N={N}", "output.figure=false"])
    result = SHELL_SCENE.run(scene, False)
    if len(result.branches) < 2:
        raise RuntimeError(f"the plate trace at N = {N} has no branch after its first snap ({result.message})")
    br = result.branches[1]
    return np.asarray(br.observables["w_b"]), np.asarray(br.observables["F"])


def sign_changes(w_b: np.ndarray, F: np.ndarray) -> int:
    """How often ``dF/dw_b`` changes sign between successive stored points."""
    slope = np.sign(np.diff(F) / np.diff(w_b))
    slope = slope[slope != 0]
    return int(np.sum(slope[1:] != slope[:-1]))


def plot(rows: Sequence[dict[str, Any]], w_b: np.ndarray, F: np.ndarray, F_unit: float) -> Any:
    """Left: the dimple branch at N = 200; right: the dimple snap's travel against N."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.plot.style import WIDTH

    fig, (a, b) = plt.subplots(1, 2, figsize=(WIDTH, 3.0), layout="constrained")
    a.plot(w_b, F / F_unit, "-", lw=1.2, color="tab:blue")
    a.set_xlabel(r"$w_b/R$")
    a.set_ylabel(r"$F R / 2\pi D$")
    a.set_title(f"dimple branch, $N = 200$: {sign_changes(w_b, F)} sign changes of $dF/dw_b$", fontsize="small")
    b.plot([r["N"] for r in rows], [r["w_b"] for r in rows], "o-", color="tab:red")
    b.set_xscale("log", base=2)
    b.set_xticks([r["N"] for r in rows], [str(r["N"]) for r in rows])
    b.set_xlabel("$N$ (nodes on the meridian)")
    b.set_ylabel(r"$w_b/R$ at the dimple snap")
    b.set_title("dimple snap against the mesh", fontsize="small")
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    args = study_parser("plate_ring", "the plate's contact ring: smooth dimple branch, snap converged in N").parse_args(argv)
    out = output_dir(args.out)
    sizes = (200, 400, 800) if args.full else (100, 200, 400)
    rows = []
    for N in sizes:
        say(args.quiet, f"dimple snap at N = {N} ...")
        rows.append(dimple_snap(N))
    for prev, row in zip(rows, rows[1:]):
        row["dw_b"], row["dF"] = row["w_b"] - prev["w_b"], row["F"] - prev["F"]
    w_b, F = dimple_branch(200)
    changes = sign_changes(w_b, F)
    F_unit = rows[0]["F"] / rows[0]["F_norm"]
    shrinking = all(abs(b["dw_b"]) < abs(a["dw_b"]) for a, b in zip(rows[1:], rows[2:]))
    write_csv(out / "convergence.csv", rows)
    write_json(out / "summary.json", {"sizes": list(sizes), "snaps": rows, "sign_changes_at_200": changes,
                                      "points_on_dimple_branch": int(w_b.size), "differences_shrink": shrinking})
    save_figure(plot(rows, w_b, F, F_unit), out, "plate_ring")
    print_table(rows, ["N", "w_b", "F", "F_norm", "dw_b", "dF", "steps"], digits=7)
    print(f"dimple branch at N = 200: {changes} sign changes of dF/dw_b over {w_b.size} points; "
          f"differences shrink with N: {'yes' if shrinking else 'no'}")
    return 0 if shrinking else 1


if __name__ == "__main__":
    sys.exit(run_study(main))
