"""Energy core of the discrete axisymmetric shell: generated kernels, reference state, exact
derivatives against finite differences, pure dilation, and no sympy on the import path."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contin_models.shell import HALF_BANDWIDTH, ShellEnergy, spherical_cap, split
from tests.generated_check import assert_reproduced

R, E, H, NU = 1.0, 1.0, 0.02, 0.5
VARIANTS = ("reference", "current")


def shell(N, phi_hat, variant="reference", R=R, pole_ratio=1.0):
    # uniform mesh by default: several checks below use its closed-form reference geometry
    return ShellEnergy(spherical_cap(R, phi_hat, N, pole_ratio), E, H, NU, kappa11_length=variant)


# ---- (a) the committed kernels are what the generator produces -----------------------------------
def test_generated_file_is_reproduced_byte_for_byte(tmp_path):
    assert_reproduced("shell", tmp_path)


def _scaled(function, factor, index=None):
    """``function`` with its result (or its result's entry ``index``) times ``factor``: a wrong density."""
    def wrong(*args, **kwargs):
        out = function(*args, **kwargs)
        if index is None:
            return out * factor
        return tuple(v * factor if i == index else v for i, v in enumerate(out))
    return wrong


def test_elements_are_the_densities_restricted_to_axisymmetric_states():
    from contin_models.shell import codegen

    for el in codegen.build_elements():
        codegen.check_axisymmetric_restriction(el)


@pytest.mark.parametrize("name, attribute, factor, index, message", [
    ("bend", "bend_curvatures", 1.01, 1, "kappa22 of the density"),
    ("bend_cur", "bend_curvatures", 1.01, 0, "kappa11 of the density"),
    ("stretch", "stretch_strains", 1.01, 1, "eps22 of the density"),
    ("bend", "bend_density", 1.01, None, "2 pi times the density"),
    ("stretch", "stretch_density", 2.1 / 2.0, None, "2 pi times the density"),
])
def test_axisymmetric_restriction_check_fails_for_a_wrong_density(monkeypatch, name, attribute, factor, index,
                                                                   message):
    from contin_models.shell import codegen, density

    monkeypatch.setattr(density, attribute, _scaled(getattr(density, attribute), factor, index))
    el = next(e for e in codegen.build_elements() if e.name == name)
    with pytest.raises(AssertionError, match=message):
        codegen.check_axisymmetric_restriction(el)


def test_axisymmetric_restriction_check_fails_for_a_twist_at_axisymmetric_states(monkeypatch):
    from contin_models.shell import codegen, density

    curvatures = density.bend_curvatures
    monkeypatch.setattr(density, "bend_curvatures", lambda *a: curvatures(*a)[:2] + (curvatures(*a)[0] * 0.01,))
    with pytest.raises(AssertionError, match="third strain does not vanish"):
        codegen.generate_source()


# ---- (b) reference state -------------------------------------------------------------------------
@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("N, phi_hat", [(12, 0.6), (40, 1.2), (200, 0.8)])
def test_reference_state_is_stress_free(N, phi_hat, variant):
    s = shell(N, phi_hat, variant)
    x = s.reference_state
    # scales: membrane energy of a unit strain ~ ks R^2, its force ~ ks R
    assert abs(s.energy(x)) <= 1e-24 * s.ks * R**2
    assert np.max(np.abs(s.gradient(x))) <= 1e-13 * s.ks * R
    eps11, eps22 = s.strains(x)
    assert np.max(np.abs(eps11)) < 1e-14 and np.max(np.abs(eps22)) < 1e-14
    k11, k22 = s.curvatures(x)
    np.testing.assert_array_equal(k11, s.kappa11_bar)
    np.testing.assert_array_equal(k22, s.kappa22_bar)


def test_reference_geometry():
    cap = spherical_cap(2.0, 0.7, 25, pole_ratio=1.0)
    assert (cap.r[0], cap.z[0]) == pytest.approx((2.0 * math.cos(0.7), 2.0 * math.sin(0.7)))
    assert (cap.r[-1], cap.z[-1]) == (0.0, 2.0)
    np.testing.assert_allclose(np.hypot(cap.r, cap.z), 2.0, rtol=1e-15)
    chord = 2 * 2.0 * math.sin(cap.dtheta / 2)
    np.testing.assert_allclose(cap.edge_length, chord, rtol=1e-13)
    np.testing.assert_allclose(cap.voronoi_length[1:-1], chord, rtol=1e-13)
    assert cap.voronoi_length[0] == pytest.approx(chord / 2) and cap.voronoi_length[-1] == pytest.approx(chord / 2)
    # kappa22 = 1/R exactly (bisector normal on a uniform mesh); kappa11 = 1/(R cos(dtheta/2))
    # (round-off: z differences near the pole are O(R dtheta^2) out of z = O(R))
    rtol = 1e-15 / cap.dtheta**2
    np.testing.assert_allclose(cap.kappa22[1:-1], 1 / 2.0, rtol=rtol)
    np.testing.assert_allclose(cap.kappa11[1:-1], 1 / (2.0 * math.cos(cap.dtheta / 2)), rtol=rtol)
    assert np.isnan(cap.kappa11[[0, -1]]).all() and np.isnan(cap.kappa22[[0, -1]]).all()
    with pytest.raises(ValueError, match="phi_hat"):
        spherical_cap(1.0, 1.6, 10)
    with pytest.raises(ValueError, match="pole_ratio"):
        spherical_cap(1.0, 1.0, 10, pole_ratio=1.5)
    with pytest.raises(ValueError, match="N"):
        spherical_cap(1.0, 1.0, 2)


# ---- (c) exact derivatives against central finite differences ------------------------------------
def deformed(s, seed, amplitude=1e-2):
    rng = np.random.default_rng(seed)
    x = s.reference_state + amplitude * s.cap.R * rng.uniform(-1.0, 1.0, s.n)
    return x


def fd_gradient(s, x, part, step):
    g = np.empty(s.n)
    for k in range(s.n):
        e = np.zeros(s.n)
        e[k] = step
        g[k] = (s.energy(x + e, part) - s.energy(x - e, part)) / (2 * step)
    return g


def fd_hessian(s, x, part, step):
    Hfd = np.empty((s.n, s.n))
    for k in range(s.n):
        e = np.zeros(s.n)
        e[k] = step
        Hfd[:, k] = (s.gradient(x + e, part) - s.gradient(x - e, part)) / (2 * step)
    return Hfd


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("phi_hat", [0.6, 1.2])
@pytest.mark.parametrize("N", [12, 40])
def test_derivatives_match_finite_differences(N, phi_hat, variant):
    s = shell(N, phi_hat, variant)
    for seed in (1, 2):
        x = deformed(s, seed)
        # At N = 40, phi_hat = 1.2 an edge is ~0.0095 R, so perturbations of 1e-2 R crumple the
        # mesh (edges shortened to ~10 %, turning angles up to ~170 degrees): scale the step by the
        # shortest current edge to stay in the truncation-free range.
        r, z = split(x)
        step = 1e-4 * np.min(np.hypot(np.diff(r), np.diff(z)))
        for part in ("stretch", "bend"):  # separately: bending is ~(h/R)^2 smaller than stretching
            g = s.gradient(x, part)
            g_fd = fd_gradient(s, x, part, step)
            assert np.max(np.abs(g - g_fd)) <= 1e-6 * np.max(np.abs(g)), part
            Hx = s.hessian(x, part).toarray()
            H_fd = fd_hessian(s, x, part, step)
            assert np.max(np.abs(Hx - H_fd)) <= 1e-6 * np.max(np.abs(Hx)), part
            # second difference of the energy itself along a random unit direction (the step is
            # scaled by the shortest edge: the deformed states are strongly distorted at N = 40)
            d = np.random.default_rng(seed + 10).standard_normal(s.n)
            d /= np.linalg.norm(d)
            t = 1e-3 * s.cap.edge_length.min()
            e0, ep, em = s.energy(x, part), s.energy(x + t * d, part), s.energy(x - t * d, part)
            assert (ep - 2 * e0 + em) / t**2 == pytest.approx(d @ Hx @ d, rel=1e-4)
        np.testing.assert_allclose(s.gradient(x), s.gradient(x, "stretch") + s.gradient(x, "bend"))
        assert s.energy(x) == pytest.approx(s.energy(x, "stretch") + s.energy(x, "bend"), rel=1e-14)


# ---- (d) symmetry and band structure -------------------------------------------------------------
@pytest.mark.parametrize("variant", VARIANTS)
def test_hessian_symmetric_and_banded(variant):
    s = shell(40, 0.8, variant)
    Hx = s.hessian(deformed(s, 3))
    A = Hx.toarray()
    np.testing.assert_array_equal(A, A.T)  # the upper triangle is assembled once and mirrored
    rows, cols = Hx.nonzero()
    assert np.max(np.abs(rows - cols)) == HALF_BANDWIDTH
    # the pattern does not depend on the state
    H0 = s.hessian(s.reference_state)
    np.testing.assert_array_equal(H0.indptr, Hx.indptr)
    np.testing.assert_array_equal(H0.indices, Hx.indices)


# ---- (e) pure dilation ---------------------------------------------------------------------------
@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("e", [-0.05, 0.01, 0.2])
@pytest.mark.parametrize("N, phi_hat", [(12, 0.6), (40, 1.2)])
def test_pure_dilation(N, phi_hat, e, variant):
    Rs = 1.7
    s = shell(N, phi_hat, variant, R=Rs)
    cap = s.cap
    x = (1 + e) * s.reference_state
    eps11, eps22 = s.strains(x)
    np.testing.assert_allclose(eps11, e, rtol=0, atol=1e-14)
    np.testing.assert_allclose(eps22, e, rtol=0, atol=1e-14)

    k11, k22 = s.curvatures(x)
    # round-off: z differences near the pole are O(R dtheta^2) out of z = O(R)
    rtol = 1e-15 / cap.dtheta**2
    np.testing.assert_allclose(k22, 1 / ((1 + e) * Rs), rtol=rtol)
    # The chord discretisation gives kappa11 = 1 / (R cos(dtheta/2)) on the reference sphere; a
    # dilation divides it by (1 + e) with the current Voronoi length and leaves it unchanged with
    # the reference one (kappa11 = turning per reference length).
    c = math.cos(cap.dtheta / 2)
    k11_expected = 1 / ((1 + e) * Rs * c) if variant == "current" else 1 / (Rs * c)
    np.testing.assert_allclose(k11, k11_expected, rtol=rtol)
    assert abs(k11_expected * c - (1 / ((1 + e) * Rs) if variant == "current" else 1 / Rs)) < 1e-15

    # analytic energy from the closed-form reference geometry
    theta = cap.theta
    chord = 2 * Rs * math.sin(cap.dtheta / 2)
    rbar_edge = Rs * (np.cos(theta[:-1]) + np.cos(theta[1:])) / 2
    W_stretch = np.sum(math.pi * rbar_edge * chord * s.ks * (2 + 2 * NU) * e**2)
    d22 = 1 / ((1 + e) * Rs) - 1 / Rs
    d11 = (1 / (1 + e) - 1) / (Rs * c) if variant == "current" else 0.0
    rbar_node = Rs * np.cos(theta[1:-1])
    W_bend = np.sum(math.pi * rbar_node * chord * s.kb * (d11**2 + 2 * NU * d11 * d22 + d22**2))
    assert s.energy(x, "stretch") == pytest.approx(W_stretch, rel=1e-12)
    assert s.energy(x, "bend") == pytest.approx(W_bend, rel=1e-10)
    assert s.energy(x) == pytest.approx(W_stretch + W_bend, rel=1e-12)


# ---- (g) the generated kernels against an exact reference, and the blocked assembly ------------
def _element_arguments(name, m, seed):
    """Random moderately distorted elements (node coordinates) and parameters of one kernel family."""
    rng = np.random.default_rng(seed)
    cap = spherical_cap(1.0, 0.7, 30)
    k = rng.integers(1, cap.N - 1, m)
    r = np.stack([cap.r[k - 1], cap.r[k], cap.r[k + 1]]) * (1 + 0.05 * rng.standard_normal((3, m)))
    z = np.stack([cap.z[k - 1], cap.z[k], cap.z[k + 1]]) + 0.3 * cap.edge_length[0] * rng.standard_normal((3, m))
    if name == "stretch":
        return (r[0], z[0], r[1], z[1], cap.edge_length[k], 0.5 * (cap.r[k - 1] + cap.r[k]), 2.0, 0.3)
    return (r[0], z[0], r[1], z[1], r[2], z[2], cap.voronoi_length[k], cap.r[k],
            1.1 * cap.kappa11[k], 0.9 * cap.kappa22[k], 1e-3, 0.3)


@pytest.mark.parametrize("index", [0, pytest.param(1, marks=pytest.mark.slow), pytest.param(2, marks=pytest.mark.slow)])
def test_kernels_match_exact_cartesian_derivatives(index):
    """The chain of polar variables the kernels use reproduces the Cartesian definitions: energy,
    gradient and Hessian against sympy's direct differentiation evaluated in 30-digit arithmetic."""
    sympy = pytest.importorskip("sympy")
    mpmath = pytest.importorskip("mpmath")
    from contin_models.shell import _generated as gen, codegen

    el = codegen.build_elements()[index]
    symbols = el.dofs + el.params
    pairs, h_upper = el.cartesian_hessian_upper()
    f = sympy.lambdify(symbols, [el.energy] + el.cartesian_gradient() + h_upper, "mpmath", cse=True)
    args = _element_arguments(el.name, 8, seed=index)
    energy = getattr(gen, f"{el.name}_energy")(*args)
    grad = getattr(gen, f"{el.name}_gradient")(*args)
    hess = getattr(gen, f"{el.name}_hessian")(*args)
    n = len(el.dofs)
    with mpmath.workdps(30):
        for k in range(len(energy)):
            vals = [mpmath.mpf(float(np.broadcast_to(a, energy.shape)[k])) for a in args]
            exact = np.array([float(v) for v in f(*vals)])
            e_ex, g_ex, h_up = exact[0], exact[1:n + 1], exact[n + 1:]
            h_ex = np.zeros((n, n))
            for (a, b), v in zip(pairs, h_up):
                h_ex[a, b] = h_ex[b, a] = v
            assert energy[k] == pytest.approx(e_ex, rel=1e-13)
            assert np.max(np.abs(grad[k] - g_ex)) <= 1e-12 * np.max(np.abs(g_ex))
            assert np.max(np.abs(hess[k] - h_ex)) <= 1e-12 * np.max(np.abs(h_ex))
            np.testing.assert_array_equal(hess[k], hess[k].T)


@pytest.mark.parametrize("name", ["stretch", "bend", "bend_cur"])
def test_kernels_match_finite_differences(name):
    """Element gradient and Hessian (unpacked convenience functions) against central differences of
    the element energy and gradient."""
    from contin_models.shell import _generated as gen

    args = _element_arguments(name, 6, seed=7)
    n = {"stretch": 4}.get(name, 6)
    energy, gradient, hessian = (getattr(gen, f"{name}_{k}") for k in ("energy", "gradient", "hessian"))
    g, H = gradient(*args), hessian(*args)
    step = 1e-6
    for a in range(n):
        plus, minus = list(args), list(args)
        plus[a] = args[a] + step
        minus[a] = args[a] - step
        g_fd = (energy(*plus) - energy(*minus)) / (2 * step)
        np.testing.assert_allclose(g[:, a], g_fd, rtol=1e-6, atol=1e-6 * np.max(np.abs(g)))
        H_fd = (gradient(*plus) - gradient(*minus)) / (2 * step)
        np.testing.assert_allclose(H[:, :, a], H_fd, rtol=0, atol=1e-6 * np.max(np.abs(H)))


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("N", [12, 13, 14, 40])
def test_blocked_assembly_matches_one_block(N, variant, monkeypatch):
    """Long meshes are evaluated in blocks of elements (``energy._CHUNK``); blocks of 5 elements,
    including ones holding a stretching element only, give the one-block results."""
    import contin_models.shell.energy as energy_module

    s1 = shell(N, 0.8, variant)
    monkeypatch.setattr(energy_module, "_CHUNK", 5)
    s5 = shell(N, 0.8, variant)
    assert len(s5._blocks) > 1 and len(s1._blocks) == 1
    x = deformed(s1, 4)
    for part in (None, "stretch", "bend"):
        assert s5.energy(x, part) == pytest.approx(s1.energy(x, part), rel=1e-14)
        g1 = s1.gradient(x, part)
        np.testing.assert_allclose(s5.gradient(x, part), g1, rtol=0, atol=1e-14 * np.max(np.abs(g1)))
        H1, H5 = s1.hessian(x, part), s5.hessian(x, part)
        np.testing.assert_array_equal(H5.indptr, H1.indptr)
        np.testing.assert_array_equal(H5.indices, H1.indices)
        np.testing.assert_allclose(H5.data, H1.data, rtol=0, atol=1e-14 * np.max(np.abs(H1.data)))
    for part in ("stretch", "bend"):
        np.testing.assert_array_equal(s5.element_energies(x, part), s1.element_energies(x, part))
    with pytest.raises(ValueError, match="part"):
        s1.element_energies(x, None)
    with pytest.raises(ValueError, match="part"):
        s1.hessian(x, "membrane")


# ---- (f) no sympy on the import path -------------------------------------------------------------
def test_import_does_not_load_sympy():
    code = ("import sys, contin_models.shell, contin_models.shell.energy, contin_models.shell.geometry, "
            "contin_models.shell._generated; assert 'sympy' not in sys.modules, 'sympy imported'; print('ok')")
    root = Path(__file__).resolve().parents[1]
    res = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "ok"


@pytest.mark.parametrize("q", [0.5, 1 / 3])
def test_graded_mesh_geometry_and_reference_state(q):
    # nodes on the sphere, monotone, spacing q times the base spacing at the pole and uniform away from it
    from contin_models.shell.geometry import GRADING_WIDTH, theta_nodes

    N, phi_hat, Rs = 201, 0.8, 1.3
    cap = spherical_cap(Rs, phi_hat, N, pole_ratio=q)
    np.testing.assert_allclose(np.hypot(cap.r, cap.z), Rs, rtol=1e-15)
    d = np.diff(cap.theta)
    assert np.all(d > 0) and cap.theta[0] == phi_hat and cap.theta[-1] == math.pi / 2
    assert d[-1] / d[0] == pytest.approx(q, rel=2e-3)
    far = slice(0, int((1 - 5 * GRADING_WIDTH) * (N - 1)))  # sech^2(5) ~ 2e-4: uniform there
    assert np.ptp(d[far]) < 1e-3 * d[0]
    np.testing.assert_array_equal(theta_nodes(phi_hat, N, 1.0), spherical_cap(Rs, phi_hat, N, 1.0).theta)
    # the reference curvatures come from the discrete geometry: the reference state is stress free
    for variant in VARIANTS:
        s = shell(40, phi_hat, variant, R=Rs, pole_ratio=q)
        assert s.energy(s.reference_state) == 0.0
        assert np.max(np.abs(s.gradient(s.reference_state))) == 0.0
    # kappa22 = 1/R only to second order in the spacing on a graded mesh (exactly on the uniform
    # one); the largest error sits next to the pole and falls by ~4 per doubling of N
    err = [np.max(np.abs(spherical_cap(Rs, phi_hat, n, q).kappa22[1:-1] * Rs - 1)) for n in (50, 100, 200)]
    assert err[0] < 0.05 and np.all(np.log2(np.array(err[:-1]) / err[1:]) > 1.9)


@pytest.mark.parametrize("e", [-0.05, 0.2])
def test_pure_dilation_on_the_graded_mesh(e):
    # strains are exactly e and, with the current Voronoi length, every curvature scales by 1/(1 + e)
    s = shell(30, 0.9, "current", R=1.7, pole_ratio=0.5)
    x = (1 + e) * s.reference_state
    eps11, eps22 = s.strains(x)
    np.testing.assert_allclose(eps11, e, rtol=0, atol=1e-14)
    np.testing.assert_allclose(eps22, e, rtol=0, atol=1e-14)
    k11, k22 = s.curvatures(x)
    np.testing.assert_allclose(k11, s.cap.kappa11[1:-1] / (1 + e), rtol=1e-12)
    np.testing.assert_allclose(k22, s.cap.kappa22[1:-1] / (1 + e), rtol=1e-12)


# ---- (e) variable thickness ----------------------------------------------------------------------
def test_scalar_and_uniform_array_thickness_agree():
    # an array of equal thicknesses is the scalar computation up to round-off (the kernels then
    # take per-element stiffnesses instead of one number)
    cap = spherical_cap(1.3, 0.9, 30, pole_ratio=0.5)
    x = cap.x + 1e-2 * np.random.default_rng(3).uniform(-1, 1, 2 * cap.N)
    for variant in VARIANTS:
        a = ShellEnergy(cap, E, H, NU, kappa11_length=variant)
        b = ShellEnergy(cap, E, np.full(cap.N, H), NU, kappa11_length=variant)
        assert b.ks == pytest.approx(a.ks, rel=1e-15) and b.kb == pytest.approx(a.kb, rel=1e-15)
        np.testing.assert_allclose(b.ks_edges, a.ks_edges, rtol=1e-15)
        np.testing.assert_allclose(b.kb_nodes, a.kb_nodes, rtol=1e-15)
        assert b.energy(x) == pytest.approx(a.energy(x), rel=1e-14, abs=0)
        for part in (None, "stretch", "bend"):
            g_a, g_b = a.gradient(x, part), b.gradient(x, part)
            assert np.max(np.abs(g_b - g_a)) <= 1e-14 * np.max(np.abs(g_a))
            H_a, H_b = a.hessian(x, part), b.hessian(x, part)
            assert abs(H_b - H_a).max() <= 1e-14 * abs(H_a).max()
    # the scalar path hands the kernels scalars (bit-identical to the constant-thickness code)
    s = ShellEnergy(cap, E, H, NU)
    assert all(np.ndim(p) == 0 for params in (s.stretch_parameters, s.bend_parameters) for p in params[-2:])
    np.testing.assert_array_equal(s.ks_edges, s.ks)
    np.testing.assert_array_equal(s.kb_nodes, s.kb)


def test_variable_thickness_stiffnesses_and_scaling():
    from contin_models.shell import plate_meridian

    m = plate_meridian(1.0, 21, 1.0, thickness=lambda s: 0.01 * (1 + s))
    s = ShellEnergy(m, 2.0, m.thickness, 0.3)
    h = m.thickness
    np.testing.assert_allclose(s.ks_edges, 2.0 * 0.5 * (h[:-1] + h[1:]) / (1 - 0.09), rtol=1e-15)
    np.testing.assert_allclose(s.kb_nodes, 2.0 * h**3 / (12 * (1 - 0.09)), rtol=1e-15)
    assert s.kb == s.kb_nodes[-1] and s.ks == s.ks_edges[-1]  # the pole end's values
    # energy of each element scales with its own stiffness: doubling every thickness doubles the
    # stretching energy and multiplies the bending energy by 8
    x = m.x + 1e-3 * np.random.default_rng(0).uniform(-1, 1, 2 * m.N)
    s2 = ShellEnergy(m, 2.0, 2 * h, 0.3)
    np.testing.assert_allclose(s2.element_energies(x, "stretch"), 2 * s.element_energies(x, "stretch"), rtol=1e-13)
    np.testing.assert_allclose(s2.element_energies(x, "bend"), 8 * s.element_energies(x, "bend"), rtol=1e-13)
    with pytest.raises(ValueError, match="shape"):
        ShellEnergy(m, 2.0, h[:-1], 0.3)
    with pytest.raises(ValueError, match="positive"):
        ShellEnergy(m, 2.0, -h, 0.3)


@pytest.mark.parametrize("variant", VARIANTS)
def test_variable_thickness_derivatives_match_finite_differences(variant):
    from contin_models.shell import Cone, SphericalArc, meridian

    # a cone on a spherical cap with a corner, thickness varying along the meridian
    Rs, phi = 1.0, 0.7
    cap_start = (Rs * math.cos(phi), Rs * math.sin(phi))
    m = meridian([Cone(1.3, 0.4, *cap_start), SphericalArc(Rs, phi, math.pi / 2)], 16,
                 thickness=lambda t: 0.02 * (1.0 + 0.5 * np.sin(3 * t)))
    s = ShellEnergy(m, E, m.thickness, 0.3, kappa11_length=variant)
    x = m.x + 1e-2 * np.random.default_rng(5).uniform(-1, 1, s.n)
    r, z = split(x)
    step = 1e-4 * np.min(np.hypot(np.diff(r), np.diff(z)))
    for part in ("stretch", "bend"):
        g = s.gradient(x, part)
        assert np.max(np.abs(g - fd_gradient(s, x, part, step))) <= 1e-6 * np.max(np.abs(g)), part
        Hx = s.hessian(x, part).toarray()
        assert np.max(np.abs(Hx - fd_hessian(s, x, part, step))) <= 1e-6 * np.max(np.abs(Hx)), part


@pytest.mark.parametrize("variant", ["reference", "current"])
def test_fused_gradient_and_hessian_equal_the_separate_kernels(variant):
    """The one-pass gradient + Hessian (used once a Hessian follows a gradient) gives the same numbers.

    A fresh energy evaluates every gradient and Hessian with the separate kernels; the same
    sequence on a second energy, after one gradient-then-Hessian pair, runs the fused kernels.  The
    fused rows come from the same chain rule, so they agree to a few ulps, and a gradient-only
    sequence must stop fusing after one unused Hessian.
    """
    rng = np.random.default_rng(3)
    states = [shell(40, 0.8, variant).cap.x + 1e-3 * rng.standard_normal(80) for _ in range(3)]
    separate = shell(40, 0.8, variant)
    fused = shell(40, 0.8, variant)
    fused.gradient(states[0])
    fused.hessian(states[0])  # a Hessian followed the gradient: the next gradient fuses
    for x in states[1:]:
        g_ref = separate.gradient(x, "stretch") + separate.gradient(x, "bend")
        H_ref = (separate.hessian(x, "stretch") + separate.hessian(x, "bend")).toarray()
        g = fused.gradient(x)
        assert fused._pair_upper is not None
        H = fused.hessian(x).toarray()
        assert np.allclose(g, g_ref, rtol=1e-12, atol=1e-12 * np.abs(g_ref).max())
        assert np.allclose(H, H_ref, rtol=1e-12, atol=1e-12 * np.abs(H_ref).max())
    # gradient only: the first gradient still fuses (the previous Hessian was asked for), the second not
    fused.gradient(states[0])
    assert fused._pair_upper is not None
    fused.gradient(states[1])
    assert fused._pair_upper is None
    # a Hessian at another state than the last gradient's is computed afresh, not taken from the pair
    fused.gradient(states[2])
    H_other = fused.hessian(states[0]).toarray()
    assert np.array_equal(H_other, separate.hessian(states[0]).toarray())


def test_shells_of_one_mesh_share_their_pattern_and_assemble_alike():
    """The pattern and scatter slots are built once per mesh size; a shell built later gets the same
    Hessian as one whose pattern was built for it (an energy of another thickness and angle between)."""
    import contin_models.shell.energy as energy_module

    a = shell(23, 0.8)
    b = ShellEnergy(spherical_cap(R, 1.1, 23, 1.0), E, 0.05, NU)
    c = shell(24, 0.8)
    assert a._pattern is b._pattern and a._pattern is not c._pattern
    x = deformed(a, 2)
    H_shared = a.hessian(x).toarray()
    energy_module._PATTERNS.clear()
    fresh = shell(23, 0.8)
    assert fresh._pattern is not a._pattern
    assert np.array_equal(fresh.hessian(x).toarray(), H_shared)
