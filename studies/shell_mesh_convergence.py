"""Mesh convergence of the point-indented shell (default scene: phi_hat = 0.8, h/R = 0.02).

Run ``python -m studies.shell_mesh_convergence`` (about 10 s).  For each curvature-length variant
(``kappa11_length``) and pole treatment it prints, over N = 50, 100, 200, 400, 800: the force F at
``w/R = 0.1`` (traced by continuation under displacement control), the linear stiffness divided by
Reissner's ``8 sqrt(D E h) / R``, and the observed orders ``log2(d_i / d_{i+1})`` of successive
differences.  The numbers quoted in ``models/shell/problem.py`` and ``models/shell/energy.py`` come
from this script.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402

import numpy as np  # noqa: E402

from contin import continuation  # noqa: E402
from models.shell import ShellPointLoad  # noqa: E402

NS = (50, 100, 200, 400, 800)


def observed_orders(values: list[float]) -> list[float]:
    """Orders ``log2(|d_i / d_{i+1}|)`` from successive differences of a sequence over halved meshes."""
    d = np.diff(values)
    return [math.log2(abs(d[i] / d[i + 1])) for i in range(len(d) - 1)]


def main() -> None:
    for length in ("reference", "current"):
        for pole in ("mirror", "skip"):
            forces, stiffness = [], []
            for N in NS:
                shell = ShellPointLoad(N=N, kappa11_length=length, pole=pole)
                br = continuation(shell, shell.reference_unknowns(), 0.0, p_max=0.1 * shell.R, ds=0.01,
                                  ds_max=0.05, detect_branch_points=False)
                if br.status != "bound":
                    raise SystemExit(f"N = {N}, {length}/{pole}: the trace stopped early ({br.message})")
                forces.append(br.observables["F"][-1])
                stiffness.append(shell.linear_stiffness() / shell.reissner_stiffness())
            print(f"kappa11_length={length:9s} pole={pole:6s}")
            print(f"  F(w/R=0.1)  = {np.array2string(np.array(forces), precision=8)}")
            print(f"  orders of F = {np.round(observed_orders(forces), 3)}")
            print(f"  k / k_Reissner = {np.array2string(np.array(stiffness), precision=7)}, "
                  f"orders {np.round(observed_orders(stiffness), 3)}", flush=True)


if __name__ == "__main__":
    main()
