"""The contact ring's ripple: how the force along an indentation path depends on where the ring sits.

Run ``python -m studies.contact_ripple [--out DIR]``.  A sphere of radius ``2.741 R`` indents a thin
cap (``phi_hat = 0.8988``, ``h/R = 3.769e-3``, ``nu = 0.2122``: the random scene 44 of
``python -m studies.fuzz --count 80 --seed 1``, in units of R).  Its pole detaches early and the
sphere then touches the cap along a ring that moves outwards.  Under displacement control the path
is traced up to its force maximum (the snap under force control) on several meshes and contact
integration rules, and the study counts how the force ripples there:

* ``sign_changes``: sign changes of ``dF/dw_b`` before the force maximum (a smooth path has none);
* ``drops_over_F_max``: the sum of the force decreases before the maximum over ``F_max``;
* ``largest_drop_over_F_max``: the largest single decrease over ``F_max``.

Under force control every ripple is a limit load (docs/robustness.md, random scenes).  The variants
compare the barrier integrated over its support (the default since issue 14, B8) with the earlier
rule, fixed Gauss points per contact cell (``support_points = 0``), on meshes N = 53 (the fuzz
scene's), 106 and 212.  Writes ``ripple.csv`` and ``summary.json``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin_models.contact import Sphere  # noqa: E402
from contin_models.contact.indentation import ShellIndentation  # noqa: E402
from studies._common import output_dir, print_table, run_study, say, study_parser, write_csv, write_json  # noqa: E402

#: The cap and sphere (units of R), from the random scene 44 of the fuzz study.
CAP = {"R": 1.0, "E": 1e6, "h": 3.7689e-3, "phi_hat": 0.89878, "nu": 0.21223}
SPHERE_RADIUS = 2.741
#: (label, N, fixed Gauss points per cell, Gauss points per support piece (0: integrate at the fixed ones))
VARIANTS: tuple[tuple[str, int, int, int], ...] = (
    ("support rule", 53, 15, 12),
    ("support rule", 106, 15, 12),
    ("support rule", 212, 15, 12),
    ("15 fixed Gauss points", 53, 15, 0),
    ("15 fixed Gauss points", 106, 15, 0),
    ("45 fixed Gauss points", 106, 45, 0),
    ("15 fixed Gauss points", 212, 15, 0),
)


def ripple(N: int, quadrature: int, support_points: int) -> dict[str, Any]:
    """Trace the indentation to its force maximum and measure the ripple before it."""
    problem = ShellIndentation(**CAP, N=N, indenter=Sphere(SPHERE_RADIUS), quadrature=quadrature,
                               support_points=support_points)
    depth = 2.0 * (1.0 - np.sin(CAP["phi_hat"]))
    st = contin.Settings(ds=depth / 20, ds_max=depth / 20, tol=1e-10, max_steps=20000)
    start = time.perf_counter()
    br = contin.continuation(problem, problem.reference_unknowns(), 0.0, st, p_max=depth,
                             events=[contin.crossing("F_norm", 1e-6, direction=-1, terminal=True)])
    F = np.asarray(br.observables["F"])
    k = int(np.argmax(F))
    dF = np.diff(F[:k + 1])
    slope = np.sign(dF[dF != 0])
    return {"N": N, "quadrature": quadrature, "support_points": support_points, "points": k + 1,
            "sign_changes": int(np.sum(slope[1:] != slope[:-1])),
            "drops_over_F_max": float(abs(dF[dF < 0].sum()) / F[k]),
            "largest_drop_over_F_max": float(max(0.0, -dF.min()) / F[k]) if dF.size else 0.0,
            "F_max_norm": float(br.observables["F_norm"][k]), "w_b_at_F_max": float(br.p[k]),
            "status": br.status, "time_s": round(time.perf_counter() - start, 2)}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    args = study_parser("contact_ripple", "ripple of the force where a contact ring moves over the nodes").parse_args(argv)
    out = output_dir(args.out)
    rows = []
    for label, N, q, support in VARIANTS:
        say(args.quiet, f"{label}, N = {N} ...")
        rows.append({"variant": label, **ripple(N, q, support)})
    write_csv(out / "ripple.csv", rows)
    write_json(out / "summary.json", {"cap": CAP, "sphere_radius": SPHERE_RADIUS, "rows": rows})
    print_table(rows, ["variant", "N", "sign_changes", "drops_over_F_max", "largest_drop_over_F_max", "F_max_norm",
                       "w_b_at_F_max", "time_s"], digits=4)
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))
