"""Probe of the contact snap against the indenter size (issue 4, work in progress; not the figure-6 study).

Run ``python -m studies.contact_snap_probe [--N 200]`` (about 15 s).  For a sphere of radius r
(r/R in 0.1 .. 2.0) and a plate pressing on the default cap (phi_hat = 0.8, h/R = 0.02), it traces
:class:`models.contact.indentation.ShellIndentation` from the first touch of the barrier to the snap
(detected as in :mod:`models.contact.runner`) and prints there: the indenter travel ``w_b/R``, the force, the
pole-indenter gap ``Delta_H/R``, the pole displacement ``w_s/R``, the pole curvature ``kappa_p R``, the
number of nodes in contact and how the snap was found (the fold in w_b, or the force falling below
``SNAP_FORCE_NORM``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import time  # noqa: E402

import contin  # noqa: E402
from models.contact import Plate, Sphere  # noqa: E402
from models.contact.indentation import ShellIndentation  # noqa: E402
from models.contact.runner import SNAP_FORCE_NORM  # noqa: E402

RADII = (0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5, 2.0, None)  # None: the plate


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--N", type=int, default=200, help="nodes on the meridian")
    args = ap.parse_args(argv)
    print(f"{'indenter':>10} {'w_b/R':>9} {'F':>9} {'Delta_H/R':>9} {'w_s/R':>8} {'kappa_p R':>9} {'contact':>7} "
          f"{'time':>6}  end")
    for r in RADII:
        P = ShellIndentation(N=args.N, indenter=Sphere(r) if r else Plate())
        t = time.perf_counter()
        # as the scene runner does: the snap is the fold in w_b, or where F R/(2 pi D) has fallen
        # below SNAP_FORCE_NORM; folds at a finite force are contact kinks, traced through here
        snap_event = contin.crossing("F_norm", SNAP_FORCE_NORM, direction=-1, terminal=True, name="F -> 0")
        br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=0.7, max_steps=3000,
                                 events=[snap_event], bounds={"base_gap": (2 * P.dhat, None)})
        dt = time.perf_counter() - t
        folds = [s for s in br.special_points if s.kind == "fold" or s.label == "F -> 0"]
        snap = next((s for s in folds if abs(s.observables["F_norm"]) < 1e-3), None)
        kinks = sum(1 for s in folds if abs(s.observables["F_norm"]) >= 1e-3)
        obs = snap.observables if snap is not None else P.evaluate_observables(br.u[-1], br.p[-1])
        end = (f"{snap.label or snap.kind} located" if snap is not None else f"{br.status}: {br.message[:60]}")
        if kinks:
            end += f" ({kinks} fold(s) at finite force before it)"
        name = f"r/R={r:g}" if r else "plate"
        print(f"{name:>10} {obs['w_b_over_R']:9.5f} {obs['F']:9.2e} {obs['Delta_H_over_R']:9.5f} "
              f"{obs['w_s_over_R']:8.5f} {obs['kappa_p_R']:9.4f} {int(obs['n_contact']):7d} {dt:6.2f}  {end}",
              flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
