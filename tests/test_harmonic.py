"""Harmonic Hessian blocks of the 2-D shell energy at axisymmetric states (issue 17).

:mod:`contin_models.shell.harmonic`.  What is checked, and why it cannot be tuned:

* the ``n = 0`` block on the ``(r, z)`` dofs is the traced model's Hessian to roundoff (with the
  pressure's ``p d2V``), along a traced path and at pressurised equilibria, for every support; its
  torsion part is uncoupled;
* an unsupported shell has exactly its rigid zero modes: axial translation and torsion at ``n = 0``,
  lateral translation and tilt at ``n = 1``, none at ``n = 2, 3``, at the reference state and at a
  pressurised equilibrium of a complete sphere; the zero modes are the analytic rigid fields;
* an independent check: the same 2-D energy on a ring mesh of ``M`` sectors (central differences
  in ``theta``, Cartesian positions, sums over sectors), its Hessian projected on the Fourier modes
  (:func:`ring_mesh_block`), tends to the blocks at second order in ``1/M``;
* a complete sphere under pressure loses stability within 2 % of the classical ``p_c`` in a
  cluster of wave numbers.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import contin
from contin_models.shell.geometry import spherical_cap
from contin_models.shell.harmonic import (HarmonicShell, Jet, block_eigs, block_inertia, bend_density,
                                          free_edge_density, harmonic_block, harmonic_dofs, mode_maps,
                                          stretch_density, volume_density)
from contin_models.shell.meridian import complete_sphere_meridian
from contin_models.shell.ring_mesh import ring_mesh_block, ring_mesh_energy
from contin_models.shell.structure import ShellOfRevolution, ShellStructure
from contin_models.shell.volume import volume_hessian
from studies.harmonic_probe import indented_state


def Sphere(R: float, N: int, h: float) -> Any:
    """A complete sphere's reference meridian, pole to pole, uniform in the polar angle (the thickness
    is passed to the structure)."""
    return complete_sphere_meridian(R, N, 1.0)


def classical_pc(E: float, h: float, R: float, nu: float) -> float:
    return 2.0 * E * (h / R) ** 2 / math.sqrt(3.0 * (1.0 - nu ** 2))


def newton(prob, u, p, tol=1e-12):
    for _ in range(30):
        u = u + spla.spsolve(prob.jacobian(u, p).tocsc(), -prob.residual(u, p))
        if np.max(np.abs(prob.residual(u, p))) < tol * prob.residual_scale:
            return u
    raise RuntimeError("Newton did not converge")


def rz_dofs(N: int) -> np.ndarray:
    return np.concatenate([[3 * i, 3 * i + 1] for i in range(N)])


def assert_n0_matches(st: ShellStructure, x: np.ndarray, pressure: float = 0.0, z_ref: float | None = None) -> float:
    """The n = 0 block on (r, z) against the traced Hessian (pole radii excluded: fixed in both)."""
    N = st.N
    hs = HarmonicShell(st, z_ref)
    K = hs.full_block(x, 0, pressure).toarray()
    H = st.hessian(x).toarray()
    if pressure:
        H = H + pressure * volume_hessian(x, hs.z_ref).toarray()
    keep = np.array([d for d in range(2 * N) if not (d % 2 == 0 and d // 2 in st.poles)])
    Krz = K[np.ix_(rz_dofs(N), rz_dofs(N))]
    err = np.max(np.abs(Krz - H)[np.ix_(keep, keep)]) / np.max(np.abs(H))
    assert err < 1e-13, err
    t = np.arange(2, 3 * N, 3)
    assert np.max(np.abs(K[np.ix_(rz_dofs(N), t)])) <= 1e-14 * np.max(np.abs(H))  # torsion uncoupled
    return err


# ---- the building blocks -----------------------------------------------------------------------------
def test_jet_matches_finite_differences() -> None:
    """The second-order forward differentiation of a density against central differences."""
    rng = np.random.default_rng(3)
    y0 = [np.array([v]) for v in (0.3, 0.01, 0.2, 0.02, 0.9, -0.05, 0.1, 0.2, -0.1, 0.05, 0.8, 0.02, -0.7, 0.03, 0.01)]
    f = lambda y: bend_density(tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]), tuple(y[12:15]),
                               0.4, 0.8, 1.1, 1.2, 2.0, 0.3)
    J = f(Jet.variables(y0))
    d = rng.standard_normal(15)
    fv = lambda s: float(f([y0[i] + s * d[i] for i in range(15)])[0])
    D1 = lambda e: (fv(e) - fv(-e)) / (2 * e)
    D2 = lambda e: (fv(e) - 2 * fv(0.0) + fv(-e)) / e ** 2
    e = 1e-3  # Richardson-extrapolated central differences, O(e^4)
    assert d @ J.g[:, 0] == pytest.approx((4 * D1(e / 2) - D1(e)) / 3, rel=1e-8)
    assert d @ J.h[:, :, 0] @ d == pytest.approx((4 * D2(e / 2) - D2(e)) / 3, rel=1e-6)
    s = stretch_density(tuple(Jet.variables(y0[:6])[0:3]), tuple(Jet.variables(y0[:6])[3:6]), 0.3, 0.9, 2.0, 0.3)
    assert s.h.shape == (6, 6, 1) and np.allclose(s.h[:, :, 0], s.h[:, :, 0].T)


@pytest.mark.parametrize("compiled", [False, True])
def test_generated_hessian_kernels_are_the_densities_hessians(compiled: bool) -> None:
    """The generated bending and rotating-edge kernels (numpy and, where built, C) against the jets of
    :func:`bend_density` and :func:`free_edge_density` at axisymmetric local variables: the whole
    ``(15, 15)`` and ``(12, 12)`` Hessians, zeros included."""
    from contin_models.shell import _harmonic_generated, harmonic

    if compiled and not harmonic.COMPILED:
        pytest.skip("the C extension contin_models.shell._harmonic_ckernels is not built")
    kernels = harmonic._hgen if compiled else _harmonic_generated
    rng = np.random.default_rng(11)
    m = 7
    r0, r1, r2 = (rng.uniform(0.4, 0.9, m) for _ in range(3))
    z0, z1, z2 = (rng.uniform(-0.2, 0.2, m) for _ in range(3))
    lbar, rbar, k11bar, k22bar, kb = (rng.uniform(0.5, 1.5, m) for _ in range(5))
    nu = 0.3
    zero = np.zeros(m)
    # e1, e2, Dp = P'_2 - P'_0, Pp = P'_1, Ppp = P''_1 of three rings at one theta (module docstring)
    vals = [r1 - r0, zero, z1 - z0, r2 - r1, zero, z2 - z1, zero, r2 - r0, zero, zero, r1, zero, -r1, zero, zero]
    for current, kernel in ((True, kernels.bend_cur_hessian), (False, kernels.bend_ref_hessian)):
        y = Jet.variables(vals)
        H = bend_density(tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]), tuple(y[12:15]),
                         lbar, rbar, k11bar, k22bar, kb, nu, None if current else lbar).h
        G = kernel(vals[0], vals[2], vals[3], vals[5], vals[7], vals[10], lbar, rbar, k11bar, k22bar, kb, nu)
        assert G.shape == (15, 15, m)
        np.testing.assert_allclose(G, H, rtol=1e-11, atol=1e-11 * np.max(np.abs(H)))
    # a rotating edge: e = P_1 - P_0, Dp = P'_1 - P'_0, Pp = P'_0, Ppp = P''_0
    K, kbar = 0.7, 1.3
    for i in range(m):
        v = [r1[i] - r0[i], 0.0, z1[i] - z0[i], 0.0, r1[i] - r0[i], 0.0, 0.0, r0[i], 0.0, -r0[i], 0.0, 0.0]
        y = Jet.variables([np.array([a]) for a in v])
        H = free_edge_density(tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]), K, kbar, nu).h[:, :, 0]
        G = kernels.free_edge_hessian(v[0], v[2], v[4], v[7], v[9], K, kbar, nu)
        np.testing.assert_allclose(G, H, rtol=1e-11, atol=1e-11 * np.max(np.abs(H)))


def test_mode_maps_are_the_fields_derivatives() -> None:
    """``dP'`` and ``dP''`` of the maps are the theta-derivatives of the mode's Cartesian field."""
    rng = np.random.default_rng(0)
    u = rng.standard_normal(3)
    for n in (0, 1, 2, 5):
        maps = mode_maps(n)

        def cart(th):  # Cartesian displacement of the mode at theta
            c, s = (1.0, 1.0) if n == 0 else (math.cos(n * th), math.sin(n * th))
            er, et = np.array([math.cos(th), math.sin(th), 0.0]), np.array([-math.sin(th), math.cos(th), 0.0])
            return u[0] * c * er + u[2] * s * et + u[1] * c * np.array([0.0, 0.0, 1.0])

        th, e = 0.37, 1e-4
        er, et = np.array([math.cos(th), math.sin(th), 0.0]), np.array([-math.sin(th), math.cos(th), 0.0])
        local = lambda v: np.array([v @ er, v @ et, v[2]])
        c, s = (1.0, 1.0) if n == 0 else (math.cos(n * th), math.sin(n * th))
        pred = {k: c * maps[k][0] @ u + s * maps[k][1] @ u for k in maps}
        assert np.allclose(pred["P"], local(cart(th)))
        assert np.allclose(pred["Pp"], local((cart(th + e) - cart(th - e)) / (2 * e)), atol=1e-7)
        assert np.allclose(pred["Ppp"], local((cart(th + e) - 2 * cart(th) + cart(th - e)) / e ** 2), atol=1e-5)
        assert np.allclose(pred["Q"], local(cart(th + math.pi)))
        assert np.allclose(pred["Qp"], local((cart(th + math.pi + e) - cart(th + math.pi - e)) / (2 * e)), atol=1e-7)


def test_dofs_per_wave_number() -> None:
    cap = spherical_cap(1.0, 0.8, 10)
    N = cap.N
    for boundary, edge in (("sliding", {1, 2}), ("pinned", {0, 1, 2}), ("clamped", {0, 1, 2}), ("free", set())):
        st = ShellStructure(cap, 1e6, 0.3, 0.02, boundary=boundary)
        p = 3 * (N - 1)
        d0, d1, d2 = (harmonic_dofs(st, n) for n in (0, 1, 2))
        rig = {}
        if boundary == "free":
            k = st.rigid_fix // 2
            rig = {0: {3 * k + 1, 3 * k + 2}, 1: {3 * k, 3 * k + 1}}
        assert set(d0.fixed) == edge | {p, p + 2} | rig.get(0, set())
        assert set(d1.fixed) == edge | {p + 1} | rig.get(1, set()) and d1.tied == [(p + 2, p, -1.0)]
        assert set(d2.fixed) == edge | {p, p + 1, p + 2}
        # the tied pole: one column carries a and c = -a
        col = list(d1.free).index(p)
        assert d1.T[p, col] == 1.0 and d1.T[p + 2, col] == -1.0


@pytest.mark.parametrize("kappa11_length", ["current", "reference"])
def test_fast_paths_equal_the_direct_ones(kappa11_length: str) -> None:
    """Generated bending kernels against the jets, the polynomial in n against the direct projection,
    the reduction's scatter against T^T K T: closed sphere under pressure, clamped cap with contact,
    a sliding cap with its rotating edge's element under pressure."""
    h = 0.02
    sph = ShellStructure(Sphere(1.0, 15, h), 1.0, 0.3, h, kappa11_length=kappa11_length)
    st, xc, contacts = indented_state(15)
    cl = ShellStructure(st.meridian, 1e6, 0.5, 0.02, boundary="clamped", kappa11_length=kappa11_length)
    sl = ShellStructure(st.meridian, 1e6, 0.3, 0.02, boundary="sliding", kappa11_length=kappa11_length)
    assert sl.edge_element is not None and sl.clamp is None
    rng = np.random.default_rng(4)
    xs = sph.meridian.x * 0.99 + 1e-3 * rng.standard_normal(30)
    xs[0] = xs[-2] = 0.0
    for s_, x, p, contact in ((sph, xs, 1e-4, None), (cl, xc, 0.0, contacts[0]), (sl, xc, 1e3, None)):
        fast, jets = HarmonicShell(s_), HarmonicShell(s_, method="jets")
        for n in (0, 1, 2, 5):
            A = fast.full_block(x, n, p, contact).toarray()
            B = jets.full_block(x, n, p, contact, reference=True).toarray()
            assert np.max(np.abs(A - B)) < 1e-13 * np.max(np.abs(B)), n
            T = harmonic_dofs(s_, n).T
            R = (T.T @ sp.csr_matrix(B) @ T).toarray()
            assert np.max(np.abs(fast.block(x, n, p, contact=contact).toarray() - R)) < 1e-13 * np.max(np.abs(R))


@pytest.mark.slow
def test_generated_module_is_up_to_date() -> None:
    """Regenerating ``_harmonic_generated.py`` (about a minute of sympy) reproduces the committed file."""
    from pathlib import Path

    from contin.modelkit.codegen import check_generated
    from contin_models.shell import harmonic_codegen

    path = Path(__file__).resolve().parents[1] / "models" / "shell" / "_harmonic_generated.py"
    check_generated(harmonic_codegen.generate_source, path, "python -m contin_models.shell.harmonic_codegen")


# ---- acceptance 1: consistency with the traced model ---------------------------------------------------
@pytest.mark.parametrize("kappa11_length", ["current", "reference"])
def test_n0_block_is_the_traced_hessian_along_a_point_load_path(kappa11_length: str) -> None:
    cap = spherical_cap(1.0, 0.8, 30)
    st = ShellStructure(cap, 1e6, 0.5, 0.02, boundary="sliding", kappa11_length=kappa11_length)
    prob = ShellOfRevolution(st, "point", "displacement")
    br = contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=0.3, ds=0.05, ds_max=0.05, max_steps=12)
    assert br.p[-1] > 0.15  # through the nonlinear range (the force maximum is near w/R = 0.1)
    for u, p in list(zip(br.u, br.p))[2::3]:
        x = prob.full_state(u, p)
        assert_n0_matches(st, x)
        # the reduced n = 0 block under the control, on its (r, z) dofs, is the engine's Jacobian
        d = harmonic_dofs(st, 0, control_fixed=[2 * st.N - 1])
        K = harmonic_block(st, x, 0, control_fixed=[2 * st.N - 1]).toarray()
        rz = np.flatnonzero(d.free % 3 != 2)
        assert np.array_equal(d.free[rz], 3 * (prob.idx // 2) + prob.idx % 2)
        J = prob.jacobian(u, p).toarray()
        assert np.max(np.abs(K[np.ix_(rz, rz)] - J)) < 1e-13 * np.max(np.abs(J))


@pytest.mark.parametrize("boundary", ["clamped", "pinned", "sliding"])
def test_n0_block_is_the_traced_hessian_under_pressure(boundary: str) -> None:
    cap = spherical_cap(1.0, 0.6, 30)
    h, nu = 0.02, 0.3
    st = ShellStructure(cap, 1.0, nu, h, boundary=boundary)
    prob = ShellOfRevolution(st, "pressure")
    p = 0.2 * classical_pc(1.0, h, 1.0, nu)  # (the sliding cap spreads: 3 % of R at 0.2 p_c)
    x = prob.full_state(newton(prob, newton(prob, prob.reference_unknowns(), 0.5 * p), p), p)
    assert np.max(np.abs(x - cap.x)) > 1e-3
    assert_n0_matches(st, x, p)
    # off equilibrium, base lifted off the plane: the skirt's terms count too
    rng = np.random.default_rng(2)
    y = x + 1e-3 * rng.standard_normal(x.size)
    y[2 * (cap.N - 1)] = 0.0
    assert_n0_matches(st, y, p)


def test_n0_block_of_a_closed_sphere_under_pressure() -> None:
    sph = Sphere(1.0, 31, 0.02)
    st = ShellStructure(sph, 1.0, 0.3, 0.02)
    prob = ShellOfRevolution(st, "pressure")
    p = 0.5 * classical_pc(1.0, 0.02, 1.0, 0.3)
    assert_n0_matches(st, prob.full_state(newton(prob, prob.reference_unknowns(), p), p), p)


def test_harmonic_block_api() -> None:
    cap = spherical_cap(1.0, 0.8, 20)
    st = ShellStructure(cap, 1e6, 0.3, 0.02, boundary="clamped")
    x = cap.x
    for n in (0, 1, 2, 7):
        K = harmonic_block(st, x, n)
        d = harmonic_dofs(st, n)
        assert K.shape == (d.free.size, d.free.size)
        assert abs(K - K.T).max() <= 1e-14 * abs(K).max()
        Kf = harmonic_block(st, x, n, reduced=False)
        assert Kf.shape == (60, 60)
        coo = Kf.tocoo()
        assert np.max(np.abs(coo.row - coo.col)) <= 8  # half-bandwidth
        assert block_inertia(K) == 0 and block_eigs(K, 2)[0] > 0  # the stress-free clamped cap is stable
    with pytest.raises(ValueError):
        harmonic_block(st, x, -1)


def test_n0_block_is_the_traced_hessian_with_contact() -> None:
    st, x, contacts = indented_state(40)
    hs = HarmonicShell(st)
    N = st.N
    keep = np.array([d for d in range(2 * N) if d != 2 * (N - 1)])
    K0 = hs.full_block(x, 0).toarray()
    for barrier, c in contacts:
        state = barrier.evaluate(x, c)
        assert state.active.size >= 1
        Hc = state.hessian_matrix().toarray()
        Kc = hs.full_block(x, 0, contact=(barrier, c)).toarray() - K0
        err = np.max(np.abs(Kc[np.ix_(rz_dofs(N), rz_dofs(N))] - Hc)[np.ix_(keep, keep)]) / np.max(np.abs(Hc))
        assert err < 1e-13, (barrier.indenter, err)
        Kfull = harmonic_block(st, x, 0, contact=(barrier, c), reduced=False).toarray()
        H = st.hessian(x).toarray() + Hc
        assert np.max(np.abs(Kfull[np.ix_(rz_dofs(N), rz_dofs(N))] - H)[np.ix_(keep, keep)]) < 1e-13 * np.max(np.abs(H))


def test_contact_blocks_equal_the_ring_mesh_barrier() -> None:
    """The barrier has no theta-derivative: its ring-mesh Hessian is exact (trigonometric quadrature)
    for any M > 2n, so the two agree to roundoff, pole cell (mirror) included."""
    st, x, contacts = indented_state(12)
    hs = HarmonicShell(st)
    for barrier, c in contacts:
        for n in range(4):
            Kh = hs.full_block(x, n, contact=(barrier, c)).toarray() - hs.full_block(x, n).toarray()
            Km = ring_mesh_block(hs, x, n, 8, contact=(barrier, c)) - ring_mesh_block(hs, x, n, 8)
            assert np.max(np.abs(Kh - Km)) < 1e-12 * np.max(np.abs(Kh)), (barrier.indenter, n)


# ---- acceptance 2: rigid motions ------------------------------------------------------------------------
def rigid_fields(x: np.ndarray, n: int) -> list[np.ndarray]:
    """The analytic rigid fields of mode n on the full dofs [a, b, c] per node."""
    r, z = x[0::2], x[1::2]
    N = r.size
    out = []
    if n == 0:
        out.append(np.ravel(np.column_stack([0 * r, 1 + 0 * r, 0 * r])))  # axial translation
        out.append(np.ravel(np.column_stack([0 * r, 0 * r, r])))  # torsion: dT = r
    if n == 1:
        out.append(np.ravel(np.column_stack([1 + 0 * r, 0 * r, -1 + 0 * r])))  # translation along e_x
        out.append(np.ravel(np.column_stack([z, -r, -z])))  # rotation about e_y
    return out


def check_rigid_modes(st: ShellStructure, x: np.ndarray, pressure: float = 0.0) -> list:
    hs = HarmonicShell(st)
    ratios = []
    for n in range(4):
        K = hs.full_block(x, n, pressure)
        dofs = harmonic_dofs(st, n, remove_rigid=False)
        T = dofs.T
        Kr = (T.T @ K @ T).toarray()
        w = np.linalg.eigvalsh(Kr)
        scale = np.max(np.abs(w))
        expected = 2 if n <= 1 else 0
        assert np.all(np.abs(w[:expected]) < 1e-12 * scale), (n, w[:3] / scale)
        assert w[expected] > 1e-7 * scale, (n, w[:3] / scale)
        ratios.append(w[expected] / scale)
        for v in rigid_fields(x, n):  # the analytic rigid fields are admissible null vectors
            assert np.max(np.abs(T @ v[dofs.free] - v)) < 1e-15
            assert np.max(np.abs(T.T @ (K @ v))) < 1e-11 * scale * np.max(np.abs(v))
    return ratios


def test_free_cap_has_exactly_the_rigid_zero_modes() -> None:
    cap = spherical_cap(1.0, 0.8, 30)
    st = ShellStructure(cap, 1e6, 0.3, 0.02, boundary="free")
    check_rigid_modes(st, cap.x)
    # and with rigid_fix removal (the default) the blocks are positive definite
    for n in range(4):
        assert block_eigs(harmonic_block(st, cap.x, n), 1)[0] > 0


def test_pressurised_sphere_has_exactly_the_rigid_zero_modes() -> None:
    h, nu = 0.02, 0.3
    st = ShellStructure(Sphere(1.0, 41, h), 1.0, nu, h)
    prob = ShellOfRevolution(st, "pressure")
    p = 0.5 * classical_pc(1.0, h, 1.0, nu)
    u = newton(prob, prob.reference_unknowns(), p)
    x = prob.full_state(u, p)
    assert np.max(np.abs(x - st.meridian.x)) > 1e-4  # a deformed (prestressed) state
    check_rigid_modes(st, x, p)


# ---- acceptance 3: the ring mesh of M sectors -----------------------------------------------------------
def test_ring_mesh_energy_is_the_traced_energy_in_the_limit_and_exact_hessian() -> None:
    """The ring-mesh energy at an axisymmetric state tends to the traced energy (O(M^-2)); its jet
    Hessian along one direction agrees with finite differences of the energy itself."""
    cap = spherical_cap(1.0, 0.8, 8)
    st = ShellStructure(cap, 1.0, 0.3, 0.05, boundary="clamped")
    hs = HarmonicShell(st)
    x = cap.x * 1.01
    x[-2] = 0.0
    x[0:2] = cap.x[0:2]
    r, z = x[0::2], x[1::2]
    E1 = st.energy(x)
    errs = []
    for M in (32, 64, 128):
        th = 2 * math.pi * np.arange(M) / M
        X = (np.repeat(r, M) * np.tile(np.cos(th), cap.N), np.repeat(r, M) * np.tile(np.sin(th), cap.N), np.repeat(z, M))
        errs.append(abs(float(ring_mesh_energy(hs, X, M)) - E1) / E1)
    assert 3.0 < errs[0] / errs[1] < errs[1] / errs[2] < 4.2, errs  # second order, approaching 4
    # finite differences of the plain-float energy along the mode-2 field against the jet Hessian
    M, n = 16, 2
    KM = ring_mesh_block(hs, x, n, M, pressure=0.0)
    u = np.random.default_rng(5).standard_normal(3 * cap.N)
    th = 2 * math.pi * np.arange(M) / M
    c, s = np.cos(n * th), np.sin(n * th)
    a, b, cc = u[0::3], u[1::3], u[2::3]
    dX = (np.outer(a, c * np.cos(th)) - np.outer(cc, s * np.sin(th)), np.outer(a, c * np.sin(th)) + np.outer(cc, s * np.cos(th)),
          np.outer(b, c))
    th_all = np.tile(th, cap.N)
    X0 = (np.repeat(r, M) * np.cos(th_all), np.repeat(r, M) * np.sin(th_all), np.repeat(z, M))
    f = lambda e: float(ring_mesh_energy(hs, tuple(X0[k] + e * dX[k].ravel() for k in range(3)), M))
    eps = 1e-4
    fd = (f(eps) - 2 * f(0.0) + f(-eps)) / eps ** 2
    assert u @ KM @ u == pytest.approx(fd, rel=1e-5)


@pytest.mark.parametrize("boundary", ["clamped", "free"])
def test_blocks_are_the_limit_of_the_ring_mesh(boundary: str) -> None:
    """Second-order convergence of the ring-mesh blocks to the harmonic blocks (n = 0..3), at a
    non-trivial axisymmetric state with pressure; Richardson extrapolation closes the gap further."""
    cap = spherical_cap(1.0, 0.8, 8)
    st = ShellStructure(cap, 1e6, 0.3, 0.05, boundary=boundary)
    hs = HarmonicShell(st)
    rng = np.random.default_rng(1)
    x = cap.x + 0.02 * rng.standard_normal(2 * cap.N)
    x[-2] = 0.0
    x[0:2] = cap.x[0:2]
    p = 1e3 if boundary == "clamped" else 0.0
    for n in range(4):
        K = hs.full_block(x, n, pressure=p).toarray()
        scale = np.max(np.abs(K))
        K32, K64 = (ring_mesh_block(hs, x, n, M, pressure=p) for M in (32, 64))
        e32, e64 = np.max(np.abs(K32 - K)) / scale, np.max(np.abs(K64 - K)) / scale
        assert 3.2 < e32 / e64 < 4.4, (n, e32, e64)
        rich = np.max(np.abs((4 * K64 - K32) / 3 - K)) / scale
        assert rich < 0.1 * e64, (n, rich, e64)


# ---- acceptance 4: the complete sphere under pressure ----------------------------------------------------
R_OVER_H = 100.0
N_MAX = 30


def sphere_problem(N: int = 301):
    h, nu = 1.0 / R_OVER_H, 0.3
    st = ShellStructure(Sphere(1.0, N, h), 1.0, nu, h)
    return st, ShellOfRevolution(st, "pressure"), classical_pc(1.0, h, 1.0, nu)


def smallest_per_n(hs: HarmonicShell, x: np.ndarray, p: float) -> np.ndarray:
    return np.array([block_eigs(hs.block(x, n, pressure=p), 1)[0] for n in range(N_MAX + 1)])


def critical_pressures(N: int = 301, s=(0.96, 0.98)) -> np.ndarray:
    """``p_n / p_c`` per n: the smallest eigenvalue of block n, linear in p through two stable
    states of the membrane path, extrapolated to zero."""
    st, prob, pc = sphere_problem(N)
    hs = HarmonicShell(st)
    u = prob.reference_unknowns()
    lam = []
    for si in s:
        u = newton(prob, u, si * pc)
        lam.append(smallest_per_n(hs, prob.full_state(u, si * pc), si * pc))
        assert np.all(lam[-1] > 0)  # stable against every n <= N_MAX on the way
    return s[1] + lam[1] * (s[1] - s[0]) / (lam[0] - lam[1])


def test_sphere_under_pressure_loses_stability_at_p_c_in_a_cluster() -> None:
    """R/h = 100, nu = 0.3: every block n <= 30 is positive definite at 0.96 and 0.98 p_c; the
    first block to lose it does so within 2 % of p_c, and at least 10 wave numbers follow within
    1 % of it (the classical degeneracy: l(l+1) ~ sqrt(12 (1 - nu^2)) R/h, l ~ 18, every n <= l)."""
    pn = critical_pressures()
    first = float(np.min(pn))
    assert abs(first - 1.0) < 0.02, pn
    cluster = np.flatnonzero(pn < first + 0.01)
    assert cluster.size >= 10, (cluster, pn)
    assert pn[N_MAX] > first + 0.2  # n_max lies beyond the critical band


def test_sphere_first_instability_along_the_traced_path() -> None:
    """The traced membrane path (pseudo-arclength, N = 301): every block n <= 30 is positive definite
    up to the path's first special point, an axisymmetric fold (the discrete poles make the membrane
    state slightly non-uniform, an imperfection of the n = 0 problem) within 2 % of p_c; there the
    n >= 1 blocks are still positive definite, and their extrapolated critical pressures form a
    cluster within 2 % of p_c."""
    st, prob, pc = sphere_problem()
    hs = HarmonicShell(st)
    u = newton(prob, newton(prob, prob.reference_unknowns(), 0.96 * pc), 0.99 * pc)
    br = contin.continuation(prob, u, 0.99 * pc, p_max=1.03 * pc, ds=1e-5, ds_max=1e-4, max_steps=12)
    folds = [sp_ for sp_ in br.special_points if sp_.kind == "fold"]
    assert folds, [sp_.kind for sp_ in br.special_points]
    s_fold = folds[0].p / pc
    assert abs(s_fold - 1.0) < 0.02
    before = [k for k in range(len(br.p)) if br.p[k] < folds[0].p and (k == 0 or br.p[k] > br.p[k - 1])]
    for k in before:
        x = prob.full_state(br.u[k], br.p[k])
        assert all(block_inertia(hs.block(x, n, pressure=br.p[k])) == 0 for n in range(N_MAX + 1))
    pn = critical_pressures(s=(0.97, 0.99))
    assert np.sum(np.abs(pn[1:] - 1.0) < 0.02) >= 10, pn


@pytest.mark.parametrize("lam, asymmetric", [(5.0, False), (7.0, True)])
def test_clamped_cap_under_pressure_bifurcates_asymmetrically_only_when_deep(lam: float, asymmetric: bool) -> None:
    """Along the traced path, with the harmonic blocks watched (``ShellOfRevolution(harmonics=...)``, engine's
    ``contin.watch.modes``): a clamped cap with lambda = 5 reaches its axisymmetric snap first, one with lambda = 7
    bifurcates into a low wave number before it (Huang 1964: asymmetric buckling from lambda ~ 5.5 on).
    Measured (R/h = 400, N = 120): lambda = 5 fold at 0.618 p_c; lambda = 7 bifurcation into n = 3 at
    0.753 p_c, before the fold at 1.053."""
    import contin
    from contin_models.shell.meridian import spherical_cap_meridian
    from contin_models.shell.pressure import phi_hat_for_lambda
    from contin_models.shell.structure import ShellOfRevolution, ShellStructure, default_harmonics

    nu, R, h = 0.3, 400.0, 1.0
    E = math.sqrt(3 * (1 - nu * nu)) / (2 * (h / R) ** 2)  # p_c = 1
    st = ShellStructure(spherical_cap_meridian(R, phi_hat_for_lambda(lam, R, h, nu), 80, 1.0), E, nu, h, "clamped")
    pr = ShellOfRevolution(st, "pressure", p_c=1.0, length=R, harmonics=default_harmonics(st))
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0,
                             contin.Settings(ds=0.02, ds_max=0.05, max_steps=400, stability=True), p_max=2.0,
                             stop_at=("fold", "bifurcation"))
    first = br.special_points[-1]
    assert first.located
    if asymmetric:
        assert first.kind == "bifurcation" and first.info["key"] in (2, 3, 4) and 0.6 < first.p < 1.0
        assert abs(first.info["eigenvalue"]) < 1e-8 * abs(first.info["next_eigenvalue"])
    else:
        assert first.kind == "fold" and first.p == pytest.approx(0.618, abs=0.01)
    counts = br.meta["modes"]["n"]["n_negative"]
    assert all(c == 0 for c in counts[0])


def test_a_held_pole_has_no_lateral_translation_at_n_1() -> None:
    """``pole_held``: the n = 1 block loses exactly the pole's lateral dof; the other blocks are unchanged."""
    from contin_models.shell.geometry import spherical_cap
    from contin_models.shell.harmonic import harmonic_dofs, harmonic_family
    from contin_models.shell.structure import ShellStructure

    st = ShellStructure(spherical_cap(1.0, 0.8, 30, 0.5), 1e6, 0.5, 0.02, "sliding", edge_bending="none")
    x = st.meridian.x
    free = harmonic_family(st, lambda u, p: x, 3)
    held = harmonic_family(st, lambda u, p: x, 3, pole_held=True)
    K1, K1h = free.operator(1, None, 0.0), held.operator(1, None, 0.0)
    assert K1h.shape[0] == K1.shape[0] - 1
    keep = harmonic_dofs(st, 1).free != 3 * (st.N - 1)
    assert np.array_equal(K1h.toarray(), K1.toarray()[np.ix_(keep, keep)])
    assert np.array_equal(held.operator(2, None, 0.0).toarray(), free.operator(2, None, 0.0).toarray())


def test_blocks_of_several_wave_numbers_at_once_equal_the_single_ones() -> None:
    """:meth:`HarmonicShell.band_blocks` (the per-point route) against :meth:`band_block` and the CSR
    :meth:`block`, with a pressure, for a cap with a pole and a complete sphere."""
    from contin_models.shell.geometry import spherical_cap
    from contin_models.shell.harmonic import HarmonicShell
    from contin_models.shell.meridian import complete_sphere_meridian
    from contin_models.shell.structure import ShellStructure

    for st in (ShellStructure(spherical_cap(1.0, 0.8, 40, 0.5), 1e6, 0.5, 0.02, "sliding", edge_bending="none"),
               ShellStructure(complete_sphere_meridian(1.0, 31), 1e6, 0.3, 0.02, "free")):
        hs = HarmonicShell(st)
        x = st.meridian.x * (1.0 + 1e-3 * np.cos(np.arange(st.meridian.x.size)))
        for hold in (False, True):
            many = hs.band_blocks(x, range(1, 7), pressure=0.3, hold_pole=hold)
            for n, K in zip(range(1, 7), many):
                one = hs.band_block(x, n, pressure=0.3, hold_pole=hold).toarray()
                assert np.abs(K.toarray() - one).max() <= 1e-13 * np.abs(one).max()
                if not hold:
                    assert np.abs(hs.block(x, n, 0.3).toarray() - one).max() <= 1e-13 * np.abs(one).max()


def test_a_sphere_on_a_point_support_has_no_rigid_mode_when_both_poles_are_held() -> None:
    """A complete sphere pinned at its south pole: ``n = 0`` positive definite (the support holds the axial
    translation, the spin is removed); ``n = 1`` keeps exactly one zero mode (the tilt about the support) while
    the north pole may slide, none when the probe holds it (``pole_held``); every block as in 3-D (the ring mesh's
    rigid-mode count is :func:`test_pressurised_sphere_has_exactly_the_rigid_zero_modes`)."""
    from contin_models.shell.harmonic import harmonic_family

    st = ShellStructure(complete_sphere_meridian(1.0, 61), 1.0, 0.3, 0.01, boundary="pinned")
    x = st.meridian.x
    scale = abs(harmonic_block(st, x, 1)).max()
    assert block_eigs(harmonic_block(st, x, 0), 1)[0] > 1e-8 * scale
    free = block_eigs(harmonic_family(st, lambda u, p: x, 2).operator(1, None, 0.0).tocsr(), 2)
    held = block_eigs(harmonic_family(st, lambda u, p: x, 2, pole_held=True).operator(1, None, 0.0).tocsr(), 1)
    assert abs(free[0]) < 1e-12 * scale and free[1] > 1e-8 * scale
    assert held[0] > 1e-8 * scale
