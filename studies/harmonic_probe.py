"""Probe of the harmonic stability blocks (issue 17): cost per block, ring-mesh limit, sphere under pressure.

Run ``python -m studies.harmonic_probe [--checks] [--cost] [--ring] [--sphere] [--weyl] [--N 200 800 3200]``
(no flag: the first four).

``--checks``
    The ``n = 0`` block on ``(r, z)`` against the traced Hessian (max relative difference) along a
    traced point-load path (sliding cap, ``N = 30``), at a pressurised clamped cap's equilibrium and
    with contact (sphere, point, plate); the smallest eigenvalues (over the largest) of the blocks
    ``n = 0 .. 3`` of a free cap (reference state) and of a pressurised complete sphere
    (equilibrium at ``p_c / 2``), all dofs but the pole's kinematic conditions.

``--cost``
    Wall time (median of 5, one process, BLAS single-threaded) at a stretched state (``1.001``
    times the reference) of the default cap (``R = 1``, ``E = 1e6``, ``nu = 0.5``, ``h = 0.02``,
    ``phi_hat = 0.8``, sliding) for each ``N``: the first block at a new state (local Hessians and the
    band coefficients of their polynomial in ``n``, shared by every ``n``), a further block
    (``n = 5``, state cached), its count and eigenvalue estimate as along a branch
    (:func:`contin.watch.modes.count_and_lowest`) and its two eigenvalues nearest zero as at a located
    bifurcation (:func:`contin.watch.modes.eigenvalues_near_zero`), beside the traced model's Hessian.
``--ring``
    The ring mesh of ``M`` sectors (:func:`ring_mesh_block`) against the blocks, clamped cap
    ``N = 10`` under pressure at a perturbed axisymmetric state: max relative difference per
    ``n`` and ``M``, the observed order and the Richardson-extrapolated difference.
``--sphere``
    Complete sphere, ``R/h = 100``, ``nu = 0.3``, under pressure: per mesh, the critical pressure of
    each block ``n <= 30`` extrapolated linearly from two stable states (0.96 and 0.98 ``p_c``), the
    first ones, and the traced path's first fold (pseudo-arclength).
``--weyl``
    Whether a block's count could be skipped from one point of the default trace with harmonic
    stability to the next (issue 18): by Weyl's inequality the Morse index cannot change while the
    block's change (2-norm) stays below its eigenvalue nearest zero.  For every third point and the
    blocks ``n = 1, 2, 5, 9, 13``, both exactly (dense eigenvalues): the number of pairs where the
    skip would hold, and the quantiles of change over eigenvalue.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
from typing import Any  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

import contin  # noqa: E402
from contin_models.shell.geometry import spherical_cap  # noqa: E402
from contin_models.shell.harmonic import HarmonicShell, block_eigs  # noqa: E402
from contin_models.shell.ring_mesh import ring_mesh_block  # noqa: E402
from contin_models.shell.meridian import complete_sphere_meridian
from contin_models.shell.structure import ShellOfRevolution, ShellStructure  # noqa: E402


def _median_time(f, repeat: int = 5) -> float:
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts)


def indented_state(N: int) -> tuple[ShellStructure, np.ndarray, list[tuple[Any, float]]]:
    """A cap (``phi_hat = 0.8``, h/R = 0.02, ``N`` nodes) whose top is pressed flat by 4e-3 R (a state
    with several contact cells within dhat), and barriers against it: a sphere (rho = 0.5 R), a
    point, a plate, per unit length as in the indentation problem, each with its position."""
    from contin_models.contact.barrier import ContactBarrier, Plate, Sphere, default_barrier, length_weights
    cap = spherical_cap(1.0, 0.8, N)
    st = ShellStructure(cap, 1e6, 0.5, 0.02, boundary="sliding")
    x = cap.x.copy()
    z = x[1::2]
    zt = z.max() - 0.004
    x[1::2] = np.minimum(z, zt + 0.1 * (z - zt))
    K, dh = default_barrier(1e6, 1.0)
    w = length_weights(cap.x)
    contacts = [(ContactBarrier(Sphere(0.5), K, dh, cell_weights=w), zt + 0.5 + 0.6 * dh),
                (ContactBarrier(Sphere(0.0), K, dh, cell_weights=w), zt + 0.5 * dh),
                (ContactBarrier(Plate(), K, dh, cell_weights=w), zt + 0.7 * dh)]
    return st, x, contacts


def checks() -> None:
    from contin_models.shell.harmonic import harmonic_dofs
    from contin_models.shell.volume import volume_hessian

    def n0_error(st, x, p=0.0, contact=None):
        N = st.N
        hs = HarmonicShell(st)
        K = hs.full_block(x, 0, p, contact).toarray()
        H = st.hessian(x).toarray()
        if p:
            H = H + p * volume_hessian(x, hs.z_ref).toarray()
        if contact is not None:
            H = H + contact[0].evaluate(*([x, contact[1]])).hessian_matrix().toarray()
        rz = np.concatenate([[3 * i, 3 * i + 1] for i in range(N)])
        keep = np.array([d for d in range(2 * N) if not (d % 2 == 0 and d // 2 in st.poles)])
        return np.max(np.abs(K[np.ix_(rz, rz)] - H)[np.ix_(keep, keep)]) / np.max(np.abs(H))

    cap = spherical_cap(1.0, 0.8, 30)
    st = ShellStructure(cap, 1e6, 0.5, 0.02, boundary="sliding")
    prob = ShellOfRevolution(st, "point", "displacement")
    br = contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=0.3, ds=0.05, ds_max=0.05, max_steps=12)
    errs = [n0_error(st, prob.full_state(u, p)) for u, p in zip(br.u, br.p)]
    print(f"n = 0 vs traced Hessian, point-load path (w/R up to {br.p[-1]:.3f}, {len(errs)} points): max {max(errs):.1e}")
    h, nu = 0.02, 0.3
    pc = 2.0 * h ** 2 / math.sqrt(3.0 * (1.0 - nu ** 2))
    cl = ShellStructure(spherical_cap(1.0, 0.6, 30), 1.0, nu, h, boundary="clamped")
    pp = ShellOfRevolution(cl, "pressure")
    u = _newton(pp, _newton(pp, pp.reference_unknowns(), 0.25 * pc), 0.5 * pc)
    print(f"n = 0 vs traced Hessian + p d2V, clamped cap at p_c/2: {n0_error(cl, pp.full_state(u, 0.5 * pc), 0.5 * pc):.1e}")
    st, x, contacts = indented_state(30)
    for name, (bar, c) in zip(("sphere 0.5R", "point", "plate"), contacts):
        print(f"n = 0 vs traced Hessian + barrier ({name}, {bar.evaluate(x, c).active.size} active cells): "
              f"{n0_error(st, x, 0.0, (bar, c)):.1e}")
    free = ShellStructure(cap, 1e6, 0.3, 0.02, boundary="free")
    sph = ShellStructure(_Sphere(1.0, 41, h), 1.0, nu, h)
    ps = ShellOfRevolution(sph, "pressure")
    xs = ps.full_state(_newton(ps, ps.reference_unknowns(), 0.5 * pc), 0.5 * pc)
    for label, s_, x_, p_ in (("free cap, reference", free, cap.x, 0.0), ("sphere N=41 at p_c/2", sph, xs, 0.5 * pc)):
        hs = HarmonicShell(s_)
        for n in range(4):
            T = harmonic_dofs(s_, n, remove_rigid=False).T
            ev = np.linalg.eigvalsh((T.T @ hs.full_block(x_, n, p_) @ T).toarray())
            print(f"{label}: n = {n}, smallest eigenvalues / largest: "
                  + " ".join(f"{v:.1e}" for v in ev[:4] / np.max(np.abs(ev))))


def cost(Ns) -> None:
    from contin.watch.modes import count_and_lowest, eigenvalues_near_zero

    print("cost (ms), default cap, sliding: per state (local Hessians and the band coefficients of the polynomial")
    print("in n, shared by every n), per further block (n = 5, state cached), its count and eigenvalue estimate")
    print("(as along a branch), its two eigenvalues nearest zero (as at a located bifurcation), the 1-D Hessian")
    print(f"{'N':>6} {'state':>8} {'block':>8} {'count':>8} {'eig_near0':>10} {'1-D hess':>9}")
    for N in Ns:
        cap = spherical_cap(1.0, 0.8, N)
        st = ShellStructure(cap, 1e6, 0.5, 0.02, boundary="sliding")
        x = cap.x * 1.001  # a state on no branch, but positive definite blocks as along most of one
        hs = HarmonicShell(st)
        hs.band_block(x, 5)  # the reductions and the maps, built once per structure
        states = iter([x + 1e-9 * k for k in range(1, 8)])
        t_state = _median_time(lambda: hs.band_block(next(states), 5))  # a fresh state each call
        t_block = _median_time(lambda: hs.band_block(x, 5))
        K = hs.band_block(x, 5)
        _, _, v = count_and_lowest(K)
        t_count = _median_time(lambda: count_and_lowest(K, v))
        t_eig = _median_time(lambda: eigenvalues_near_zero(K, 2), repeat=3)
        t_1d = _median_time(lambda: st.shell.hessian(x))
        print(f"{N:6d} {1e3 * t_state:8.2f} {1e3 * t_block:8.2f} {1e3 * t_count:8.2f} {1e3 * t_eig:10.2f} "
              f"{1e3 * t_1d:9.2f}")


def ring() -> None:
    cap = spherical_cap(1.0, 0.8, 10)
    st = ShellStructure(cap, 1e6, 0.3, 0.05, boundary="clamped")
    hs = HarmonicShell(st)
    rng = np.random.default_rng(1)
    x = cap.x + 0.02 * rng.standard_normal(2 * cap.N)
    x[-2] = 0.0
    x[0:2] = cap.x[0:2]
    p = 1e3
    Ms = (8, 16, 32, 64, 128)
    print("ring mesh of M sectors against the harmonic blocks (clamped cap, N = 10, p = 1e3, perturbed state)")
    print("max |K_M - K_n| / max |K_n|; order log2(e_M/2 / e_M); Richardson (4 K_2M - K_M)/3")
    for n in range(4):
        K = hs.full_block(x, n, pressure=p).toarray()
        sc = np.max(np.abs(K))
        KM = {M: ring_mesh_block(hs, x, n, M, pressure=p) for M in Ms}
        e = [np.max(np.abs(KM[M] - K)) / sc for M in Ms]
        orders = [math.log2(e[i - 1] / e[i]) for i in range(1, len(Ms))]
        rich = np.max(np.abs((4 * KM[128] - KM[64]) / 3 - K)) / sc
        print(f"n={n}: " + " ".join(f"M={M}: {v:.2e}" for M, v in zip(Ms, e))
              + " | orders " + " ".join(f"{o:.2f}" for o in orders) + f" | Richardson(64,128) {rich:.1e}")


def _Sphere(R: float, N: int, h: float) -> Any:
    """A complete sphere's reference meridian, pole to pole, uniform in the polar angle (the thickness
    is passed to the structure)."""
    return complete_sphere_meridian(R, N, 1.0)


def _newton(prob, u, p):
    for _ in range(30):
        u = u + spla.spsolve(prob.jacobian(u, p).tocsc(), -prob.residual(u, p))
        if np.max(np.abs(prob.residual(u, p))) < 1e-12 * prob.residual_scale:
            return u
    raise RuntimeError("Newton did not converge")


def sphere(Ns=(201, 301, 401), n_max: int = 30) -> None:
    h, nu = 0.01, 0.3
    pc = 2.0 * (h ** 2) / math.sqrt(3.0 * (1.0 - nu ** 2))
    print(f"complete sphere R/h = 100, nu = 0.3, p_c = {pc:.6e}")
    for N in Ns:
        st = ShellStructure(_Sphere(1.0, N, h), 1.0, nu, h)
        prob = ShellOfRevolution(st, "pressure")
        hs = HarmonicShell(st)
        u = prob.reference_unknowns()
        lam = []
        t0 = time.perf_counter()
        u96 = None
        for s in (0.96, 0.98):
            u = _newton(prob, u, s * pc)
            u96 = u if u96 is None else u96
            x = prob.full_state(u, s * pc)
            lam.append(np.array([block_eigs(hs.block(x, n, pressure=s * pc), 1)[0] for n in range(n_max + 1)]))
        t_blocks = time.perf_counter() - t0
        pn = 0.98 + lam[1] * 0.02 / (lam[0] - lam[1])
        order = np.argsort(pn)
        br = contin.continuation(prob, u96, 0.96 * pc, p_max=1.03 * pc, ds=1e-5, ds_max=1e-4, max_steps=60)
        folds = [sp_.p / pc for sp_ in br.special_points if sp_.kind == "fold"]
        print(f"N = {N}: all blocks n <= {n_max} positive definite at 0.96 and 0.98 p_c: "
              f"{bool(np.all(lam[0] > 0) and np.all(lam[1] > 0))} ({t_blocks:.2f} s incl. 2 equilibria)")
        print("   extrapolated p_n/p_c, first 12: " + ", ".join(f"n={n}: {pn[n]:.4f}" for n in order[:12]))
        print(f"   n with p_n within 2 % of p_c: {sorted(int(n) for n in np.flatnonzero(np.abs(pn - 1) < 0.02))}")
        print(f"   traced path (from 0.96 p_c, {len(br.p)} points): first fold at {folds[0]:.4f} p_c"
              if folds else f"   no fold on the traced path ({br.status}, p up to {np.max(br.p) / pc:.4f} p_c)")


def weyl(every: int = 3, keys: tuple[int, ...] = (1, 2, 5, 9, 13)) -> None:
    """``--weyl``: the blocks' change between consecutive points against their eigenvalue nearest zero."""
    from contin.watch import modes
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCENE

    per_point: list[list[Any]] = []
    watch = modes.ModeTest.value

    def value(self: Any, pt: Any) -> Any:  # the blocks each point's counts are made of, as dense arrays
        fresh = pt.modes is None or self.family.name not in pt.modes
        if fresh:
            per_point.append([K.toarray() for K in self.family.operators(pt.u, pt.p)])
        return watch(self, pt)

    modes.ModeTest.value = value
    try:
        SHELL_SCENE.runner(load_scene(SHELL_SCENE.schema, None, ["stability.harmonics=true"]), False)
    finally:
        modes.ModeTest.value = watch
    ratios = []
    for i in range(0, len(per_point) - 1, every):
        for n in keys:
            A, B = per_point[i][n - 1], per_point[i + 1][n - 1]
            if A.shape != B.shape:
                continue
            nearest_zero = float(np.min(np.abs(np.linalg.eigvalsh(A))))
            change = float(np.max(np.abs(np.linalg.eigvalsh(B - A))))
            ratios.append(change / nearest_zero)
    r = np.array(ratios)
    print(f"default trace with harmonic stability: {len(per_point)} points, {r.size} pairs (one point in {every} "
          f"and the next, n = {', '.join(map(str, keys))})")
    print(f"pairs where the block's change is below its eigenvalue nearest zero (a skip Weyl allows): "
          f"{int(np.count_nonzero(r < 1.0))}")
    q = np.percentile(r, [10, 50, 90])
    print(f"change / eigenvalue nearest zero, quantiles 10 / 50 / 90 %: {q[0]:.3g} / {q[1]:.3g} / {q[2]:.3g}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--checks", action="store_true")
    ap.add_argument("--cost", action="store_true")
    ap.add_argument("--ring", action="store_true")
    ap.add_argument("--sphere", action="store_true")
    ap.add_argument("--weyl", action="store_true")
    ap.add_argument("--N", type=int, nargs="+", default=[200, 800, 3200])
    a = ap.parse_args(argv)
    if a.weyl:
        weyl()
    every = not (a.checks or a.cost or a.ring or a.sphere or a.weyl)
    if a.checks or every:
        checks()
    if a.cost or every:
        cost(a.N)
    if a.ring or every:
        ring()
    if a.sphere or every:
        sphere()


if __name__ == "__main__":
    main()
