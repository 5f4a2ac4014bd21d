"""The strain at the pole under a point load, against the mesh: why thick caps are not mesh-converged.

Run ``python -m studies.pole_strain [--out DIR] [--full] [--quiet]``.

The cap (``phi_hat = 0.8``, ``nu = 0.5``) is pushed at its pole by a prescribed displacement ``w``
(the point load of ``contin trace``), and the path is stopped at fixed fractions of the eversion
travel ``w_ev = 2 R (1 - sin phi_hat)``.  At each stop it records, for several N:

* ``pole_strain``: the largest ``|eps11|``, ``|eps22|`` of the edge at the pole;
* ``eps22_r03``: the hoop strain at the distance ``0.03 R`` from the axis (interpolated in the
  reference radius): a strain at a fixed material point, away from the pole;
* ``kappa11_pole_R``: the meridional curvature at the node next to the pole, times R;
* ``F_norm``: the pole force ``F R / (2 pi D)``.

A quantity of a converged solution settles as N grows; one that keeps growing by a similar step per
doubling of N belongs to a singular point.  The default run is h/R = 0.15 at ``w = w_ev / 2``; with
``--full``, h/R in {0.02, 0.1, 0.15, 0.2} at ``w / w_ev`` in {0.25, 0.5, 0.75, 0.9} and N up to 1600.
``docs/robustness.md`` quotes the ``--full`` run.  Outputs in ``--out`` (default ``out/pole_strain``):
``pole_strain.csv`` and ``summary.json``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin_models.shell.problem import ShellPointLoad  # noqa: E402
from contin_models.shell_scene import eversion_displacement  # noqa: E402
from studies._common import output_dir, print_table, say, study_parser, write_csv, write_json  # noqa: E402

#: Cap depth of every run.
PHI_HAT = 0.8
#: Distance from the axis (units of R) of the off-pole strain.
OFF_AXIS_RADIUS = 0.03


def stops(h: float, N: int, fractions: Sequence[float]) -> list[dict[str, Any]]:
    """Trace the point-load path of one cap and record the pole quantities at each ``w / w_ev``.

    Parameters
    ----------
    h : float
        Thickness (R = 1).
    N : int
        Number of nodes.
    fractions : sequence of float
        Increasing fractions of the eversion travel at which to stop.

    Returns
    -------
    list of dict
        One row per fraction; a fraction the path did not reach has ``reached = False`` and the
        continuation's reason in ``message``.
    """
    P = ShellPointLoad(h=h, N=N, phi_hat=PHI_HAT)
    w_ev = eversion_displacement(1.0, PHI_HAT)
    st = contin.Settings(ds=0.01, ds_max=0.01, ds_min=1e-10, tol=1e-10, max_steps=5000, stability=False)
    u, p = P.reference_unknowns(), 0.0
    rows: list[dict[str, Any]] = []
    lost = ""
    for frac in fractions:
        row: dict[str, Any] = {"h_over_R": h, "N": N, "w_over_w_ev": frac}
        if not lost:
            br = contin.continuation(P, u, p, st, p_max=frac * w_ev)
            if br.status != "bound" or not math.isclose(float(br.p[-1]), frac * w_ev, rel_tol=1e-9):
                lost = f"{br.status}: {br.message}"
            else:
                u, p = br.u[-1].copy(), float(br.p[-1])
        if lost:
            rows.append({**row, "reached": False, "message": lost})
            continue
        x = P.full_state(u, p).copy()
        eps11, eps22 = P.shell.strains(x)
        kappa11, _ = P.shell.curvatures(x)
        rbar = P.cap.edge_radius
        rows.append({**row, "reached": True,
                     "pole_strain": float(max(abs(eps11[-1]), abs(eps22[-1]))),
                     "eps22_r03": float(np.interp(OFF_AXIS_RADIUS, rbar[::-1], eps22[::-1])),
                     "kappa11_pole_R": float(kappa11[-1]),
                     "F_norm": float(P.reaction_force(x)) / (2.0 * math.pi * P.D),
                     "message": ""})
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    parser = study_parser("pole_strain", "the strain at the pole under a point load, against the mesh")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    if args.full:
        thicknesses, fractions, meshes = (0.02, 0.1, 0.15, 0.2), (0.25, 0.5, 0.75, 0.9), (200, 400, 800, 1600)
    else:
        thicknesses, fractions, meshes = (0.15,), (0.5,), (100, 200, 400)
    t0 = time.perf_counter()
    rows: list[dict[str, Any]] = []
    for h in thicknesses:
        for N in meshes:
            say(args.quiet, f"pole strain: h/R = {h:g}, N = {N}")
            rows.extend(stops(h, N, fractions))
    columns = ["h_over_R", "w_over_w_ev", "N", "pole_strain", "eps22_r03", "kappa11_pole_R", "F_norm", "message"]
    ordered = sorted(rows, key=lambda r: (r["h_over_R"], r["w_over_w_ev"], r["N"]))
    print_table(ordered, columns)
    write_csv(out / "pole_strain.csv", ordered, columns + ["reached"])
    write_json(out / "summary.json", {"rows": ordered, "phi_hat": PHI_HAT, "wall_time_s": time.perf_counter() - t0,
                                      "command": "python -m studies.pole_strain" + (" --full" if args.full else "")})
    say(args.quiet, f"{len(rows)} stops in {time.perf_counter() - t0:.1f} s; outputs in {out}")
    return 0


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
