"""Contact barrier (docs/model.md#contact, eq. 3.16): generated kernels, exact derivatives against
finite differences and 30-digit sympy, the contact cells (the barrier integrated over quadratic
cells between the nodes: an independent quadrature, derivatives, the band, the paper's nodal
barrier as one point per cell), C2 continuity at dhat, blow-up at contact, the IPC step filter on
cases with known answers, clear errors instead of NaN, and the E/R scaling rule."""

import math
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from contin_models.contact import ContactBarrier, Plate, Sphere, barrier_value, default_barrier
from contin_models.contact import _generated as gen
from contin_models.contact.barrier import length_weights
from tests.generated_check import assert_reproduced

K, DHAT = 1e8, 1e-3  # the paper's values (E = 1 MPa, R = 1 m)
RHO = 0.5
FRACTIONS = (1e-3, 0.05, 0.3, 0.7, 0.97)  # d / dhat


# ---- closed forms (independent of the code under test) -------------------------------------------
def W(d):
    return -K * (d - DHAT) ** 2 * math.log(d / DHAT)


def W1(d):
    return -K * (2 * (d - DHAT) * math.log(d / DHAT) + (d - DHAT) ** 2 / d)


def W2(d):
    return -K * (2 * math.log(d / DHAT) + 4 * (d - DHAT) / d - (d - DHAT) ** 2 / d**2)


def kernels(shape):
    params = (RHO,) if shape == "sphere" else ()

    def call(kind, r, z, c):
        return getattr(gen, f"{shape}_{kind}")(np.atleast_1d(r), np.atleast_1d(z), c, *params, K, DHAT)

    return call


def node_at(shape, d, angle=0.7, c=1.2):
    """A node at distance ``d`` from the indenter at position ``c``: (r, z)."""
    if shape == "sphere":  # below the centre, at polar angle `angle` from the downward axis
        return (RHO + d) * math.sin(angle), c - (RHO + d) * math.cos(angle)
    return 0.3, c - d


def fd5(f, v, h):
    """Five-point central difference of ``f`` at ``v`` (error O(h^4))."""
    return (-f(v + 2 * h) + 8 * f(v + h) - 8 * f(v - h) + f(v - 2 * h)) / (12 * h)


# ---- (a) the committed kernels are what the generator produces -----------------------------------
@pytest.mark.slow
def test_generated_file_is_reproduced_byte_for_byte(tmp_path):
    assert_reproduced("contact", tmp_path)


def test_no_sympy_on_the_import_path():
    import subprocess
    import sys

    code = "import sys, contin_models.contact; assert 'sympy' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True, cwd=Path(__file__).resolve().parents[1])


# ---- (b) kernel derivatives ------------------------------------------------------------------------
@pytest.mark.parametrize("shape", ["sphere", "plate"])
@pytest.mark.parametrize("frac", FRACTIONS)
@pytest.mark.parametrize("angle", [0.0, 0.7, 1.3])
def test_kernel_derivatives_match_finite_differences(shape, frac, angle):
    call = kernels(shape)
    d = frac * DHAT
    r, z = node_at(shape, d, angle)
    c = 1.2
    v0 = np.array([r, z, c])
    # the energy and the distance against the closed forms
    assert call("distance", r, z, c)[0] == pytest.approx(d, rel=1e-9, abs=1e-15)
    assert call("energy", r, z, c)[0] == pytest.approx(W(d), rel=1e-8)
    e, g, hp = call("derivatives", r, z, c)
    assert e[0] == pytest.approx(W(d), rel=1e-8)
    np.testing.assert_allclose(g[:, 0], call("gradient", r, z, c)[:, 0], rtol=1e-14)
    np.testing.assert_allclose(hp[:, 0], call("hessian", r, z, c)[:, 0], rtol=1e-14)
    H = np.empty((3, 3))
    for k, (a, b) in enumerate(gen.PAIRS):
        H[a, b] = H[b, a] = hp[k, 0]
    step = 1e-2 * min(d, DHAT - d)  # small against both ends of (0, dhat)
    for a in range(3):
        unit = np.eye(3)[a]
        fe = fd5(lambda t: call("energy", *(v0 + t * unit))[0], 0.0, step)
        fg = fd5(lambda t: call("gradient", *(v0 + t * unit))[:, 0], 0.0, step)
        scale_g = abs(W1(d))
        assert abs(g[a, 0] - fe) <= 1e-7 * scale_g, (a, g[a, 0], fe)
        np.testing.assert_allclose(H[:, a], fg, rtol=0, atol=1e-7 * abs(W2(d)) + 1e-7 * scale_g / RHO)


@pytest.mark.parametrize("shape", ["sphere", "plate"])
@pytest.mark.parametrize("frac", [0.01, 0.5, 0.9])
def test_kernel_chain_rule_closed_form(shape, frac):
    """grad W = W'(d) grad d, hess W = W'' grad d grad d^T + W' hess d, with grad d by hand."""
    call = kernels(shape)
    d = frac * DHAT
    angle = 0.6
    r, z = node_at(shape, d, angle)
    _, g, hp = call("derivatives", r, z, 1.2)
    if shape == "plate":
        gd, Hd = np.array([0.0, -1.0, 1.0]), np.zeros((3, 3))
    else:
        nr, nz = math.sin(angle), -math.cos(angle)
        q = RHO + d
        gd = np.array([nr, nz, -nz])
        P = np.array([[nz * nz, -nr * nz], [-nr * nz, nr * nr]]) / q
        Hd = np.block([[P, -P[:, 1:]], [-P[1:, :], P[1:, 1:]]])
    np.testing.assert_allclose(g[:, 0], W1(d) * gd, rtol=1e-9, atol=1e-12 * abs(W1(d)))
    H = W2(d) * np.outer(gd, gd) + W1(d) * Hd
    for k, (a, b) in enumerate(gen.PAIRS):
        assert hp[k, 0] == pytest.approx(H[a, b], rel=1e-9, abs=1e-12 * abs(W2(d)))


@pytest.mark.parametrize("index", [0, 1])
def test_kernels_match_30_digit_sympy(index):
    sympy = pytest.importorskip("sympy")
    from contin_models.contact import codegen

    ind = codegen.build_indenters()[index]
    args = ind.arguments
    vars3 = ind.variables
    grad = [sympy.diff(ind.energy, v) for v in vars3]
    hess = [sympy.diff(ind.energy, vars3[a], vars3[b]) for a, b in codegen.PAIRS]
    fn = getattr(gen, f"{ind.name}_derivatives")
    for frac, angle in [(0.02, 0.3), (0.4, 1.1), (0.95, 0.0)]:
        r, z = node_at(ind.name, frac * DHAT, angle, c=1.3)
        values = [r, z, 1.3] + ([RHO] if ind.name == "sphere" else []) + [K, DHAT]
        subs = {s: sympy.Float(repr(v), 30) for s, v in zip(args, values)}
        e, g, h = fn(np.array([r]), np.array([z]), 1.3, *values[3:])
        ref_e = float(ind.energy.evalf(30, subs=subs))
        ref_g = [float(x.evalf(30, subs=subs)) for x in grad]
        ref_h = [float(x.evalf(30, subs=subs)) for x in hess]
        assert e[0] == pytest.approx(ref_e, rel=1e-10)
        np.testing.assert_allclose(g[:, 0], ref_g, rtol=1e-9, atol=1e-12 * max(map(abs, ref_g)))
        np.testing.assert_allclose(h[:, 0], ref_h, rtol=1e-9, atol=1e-12 * max(map(abs, ref_h)))


# ---- (c) the class: a multi-node state, derivatives w.r.t. x and c --------------------------------
def cap_state(N=9, R=1.0, phi_hat=0.8):
    theta = np.linspace(phi_hat, math.pi / 2, N)
    r, z = R * np.cos(theta), R * np.sin(theta)
    r[-1] = 0.0
    x = np.empty(2 * N)
    x[0::2], x[1::2] = r, z
    return x


def contact_setup(shape, gap=0.4 * DHAT, N=41, R=1.0, rho=RHO, E=1e6, quadrature=None, weighted=False):
    """Undeformed cap with the indenter ``gap`` above the pole; barrier from the default rule."""
    x = cap_state(N, R)
    Kc, dhat = default_barrier(E, R)
    opts = {} if quadrature is None else {"quadrature": quadrature}
    if weighted:
        opts["cell_weights"] = length_weights(x)
    if shape == "sphere":
        return ContactBarrier(Sphere(rho), Kc, dhat, **opts), x, R + rho + gap
    return ContactBarrier(Plate(), Kc, dhat, **opts), x, R + gap


def cell_energy_reference(x, c, shape, rho, q, weights=None):
    """The barrier integrated over the cells, built independently of the code under test.

    ``q = 1``: the paper's nodal sum ``sum_i W(d_i)``.  Otherwise cell i >= 1 is the quadratic
    B-spline piece ``x(t) = (1/2 - t)^2 / 2 x_{i-1} + (3/4 - t^2) x_i + (1/2 + t)^2 / 2 x_{i+1}``
    (the pole's third node mirrored across the axis) on t in [-1/2, 1/2], integrated by adaptive
    quadrature (scipy's QUADPACK) to 1e-13; the base node: W(d_0).
    """
    from scipy.integrate import quad

    r, z = x[0::2], x[1::2]
    N = r.size
    weights = np.ones(N) if weights is None else weights

    def dist(rr, zz):
        return np.hypot(rr, zz - c) - rho if shape == "sphere" else c - zz

    def Wsum(d):
        return sum(W(v) for v in np.atleast_1d(d) if v < DHAT)

    total = weights[0] * Wsum(dist(r[0], z[0]))
    for i in range(1, N):
        if q == 1:
            total += weights[i] * Wsum(dist(r[i], z[i]))
            continue
        ra, za = r[i - 1], z[i - 1]
        rb, zb = (r[i + 1], z[i + 1]) if i < N - 1 else (-r[i - 1], z[i - 1])

        def integrand(t, i=i, ra=ra, za=za, rb=rb, zb=zb):
            B = ((0.5 - t) ** 2 / 2, 0.75 - t * t, (0.5 + t) ** 2 / 2)
            return Wsum(dist(B[0] * ra + B[1] * r[i] + B[2] * rb, B[0] * za + B[1] * z[i] + B[2] * zb))

        value, _ = quad(integrand, -0.5, 0.5, epsabs=0.0, epsrel=1e-13, limit=500)
        total += weights[i] * value
    return total


@pytest.mark.parametrize("q", [1, 15])
@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_class_derivatives_match_finite_differences(shape, q):
    rng = np.random.default_rng(3)
    cb, x, c = contact_setup(shape, gap=0.3 * DHAT, N=61, rho=2.0, quadrature=q, weighted=True)
    x = x + 2e-5 * rng.standard_normal(x.size) * (np.arange(x.size) % 2)  # jiggle the heights a little
    x[-2] = 0.0
    st = cb.evaluate(x, c)
    assert st.n_active >= 3 and st.n_active < x.size // 2  # several cells in contact, not all
    assert np.all(st.gaps > 0)
    np.testing.assert_array_equal(st.active, np.flatnonzero(st.gaps < DHAT))
    # the energy is the quadrature over the cells, computed independently
    ref = cell_energy_reference(x, c, "sphere" if shape == "sphere" else "plate", 2.0, q, cb.cell_weights)
    assert st.energy == pytest.approx(ref, rel=1e-12)
    # outside the active cells' nodes the gradient is exactly zero
    touched = np.unique(st.stencils)
    inactive = np.setdiff1d(np.arange(x.size // 2), touched)
    assert np.all(st.gradient[2 * inactive] == 0) and np.all(st.gradient[2 * inactive + 1] == 0)
    step = 1e-8
    y0 = np.append(x, c)

    def grad_all(y):
        s = cb.evaluate(y[:-1], y[-1], hessian=False)
        return np.append(s.gradient, s.dE_dc)

    full_H = np.zeros((y0.size, y0.size))
    full_H[:-1, :-1] = st.hessian_matrix().toarray()
    full_H[:-1, -1] = full_H[-1, :-1] = st.hess_xc
    full_H[-1, -1] = st.hess_cc
    g0 = grad_all(y0)
    gscale = np.max(np.abs(g0))
    hscale = np.max(np.abs(full_H))
    for a in np.append(np.concatenate([2 * touched, 2 * touched + 1]), y0.size - 1):
        unit = np.zeros(y0.size)
        unit[a] = 1.0
        fe = fd5(lambda t: cb.energy(y0[:-1] + t * unit[:-1], y0[-1] + t * unit[-1]), 0.0, step)
        assert abs(g0[a] - fe) <= 1e-6 * gscale, (a, g0[a], fe)
        fg = fd5(lambda t: grad_all(y0 + t * unit), 0.0, step)
        np.testing.assert_allclose(full_H[:, a], fg, rtol=0, atol=1e-6 * hscale)
    # the force on the indenter: F = -dE/dc > 0 while pushing, the sum of the cells' shares
    assert st.force > 0 and st.force == pytest.approx(np.sum(st.node_force), rel=1e-13)
    assert np.all(st.node_force > 0)
    assert st.energy == pytest.approx(np.sum(st.node_energy), rel=1e-13)
    # translation along the axis (node heights and the indenter together) leaves E unchanged:
    # dE/dc = -sum_i dE/dz_i, i.e. the indenter's reaction balances the forces on the nodes
    assert st.dE_dc == pytest.approx(-np.sum(st.gradient[1::2]), rel=1e-12)
    # same for the Hessian: the z-translation is in its null space
    tz = np.append(np.tile([0.0, 1.0], x.size // 2), 1.0)
    assert np.max(np.abs(full_H @ tz)) <= 1e-9 * hscale
    dF_dx, dF_dc = st.force_gradient()
    np.testing.assert_array_equal(dF_dx, -st.hess_xc)
    assert dF_dc == -st.hess_cc


@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_hessian_fits_the_shells_band(shape):
    cb, x, c = contact_setup(shape, gap=0.2 * DHAT, rho=3.0)
    st = cb.evaluate(x, c)
    assert st.n_active >= 2
    rows, cols, vals = st.hessian_triplets()
    assert rows.size == 36 * st.n_active
    # a cell couples the nodes i-1, i, i+1: within the shell's half-bandwidth 5 (interleaved dofs)
    assert np.max(np.abs(rows - cols)) <= 5
    H = st.hessian_matrix()
    np.testing.assert_allclose(H.toarray(), H.toarray().T, rtol=0, atol=1e-9 * abs(H).max())
    np.testing.assert_allclose(st.hess_blocks, np.swapaxes(st.hess_blocks, 1, 2), rtol=0,
                               atol=1e-9 * np.max(np.abs(st.hess_blocks)))
    # the slots of the blocks in a banded pattern add up to the same matrix
    n = x.size
    pattern = sp.diags([np.ones(n - abs(k)) for k in range(-5, 6)], list(range(-5, 6)), format="csr")
    pattern.data[:] = 0.0
    slots = cb.hessian_slots(pattern)
    np.add.at(pattern.data, slots[st.active].ravel(), st.hess_blocks.ravel())
    np.testing.assert_allclose(pattern.toarray(), H.toarray(), rtol=0, atol=1e-12 * abs(H).max())
    with pytest.raises(ValueError, match="not in the pattern"):
        cb.hessian_slots(sp.identity(n, format="csr"))


@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_one_point_per_cell_is_the_papers_nodal_barrier(shape):
    """quadrature = 1: the energy is sum_i W(d_i) over the nodes, the Hessian node-block diagonal."""
    cb, x, c = contact_setup(shape, gap=0.2 * DHAT, rho=3.0, quadrature=1)
    st = cb.evaluate(x, c)
    assert st.n_active >= 2
    assert st.energy == pytest.approx(sum(W(d) for d in st.distances if d < DHAT), rel=1e-12)
    np.testing.assert_array_equal(st.gaps, st.distances)
    H = st.hessian_matrix().tocoo()
    nz = H.data != 0
    assert np.all(H.row[nz] // 2 == H.col[nz] // 2)  # each node couples only its own (r, z)
    # the pole on the axis: its r-z coupling vanishes and W_zz = W''(d) (plate and sphere alike)
    pole = x.size // 2 - 1
    Hd = st.hessian_matrix().toarray()
    assert Hd[2 * pole, 2 * pole + 1] == 0.0
    assert Hd[2 * pole + 1, 2 * pole + 1] == pytest.approx(W2(0.2 * DHAT), rel=1e-6)


def test_uniform_gap_counts_one_node_per_cell():
    """A flat meridian parallel to the plate: every cell at the same gap gives W(d), as a node does."""
    N, d = 21, 0.4 * DHAT
    x = np.zeros(2 * N)
    x[0::2] = np.linspace(1.0, 0.0, N)
    cb = ContactBarrier(Plate(), K, DHAT)
    st = cb.evaluate(x, d)
    assert st.n_active == N
    assert st.energy == pytest.approx(N * W(d), rel=1e-12)
    # with the length weights of a uniform mesh of n_paper = N nodes: the base and pole cells are
    # half and whole edges, the interior cells one spacing each
    w = length_weights(x, n_paper=N)
    np.testing.assert_allclose(w, np.r_[0.5, np.ones(N - 2), 1.0], rtol=1e-12)
    st_w = ContactBarrier(Plate(), K, DHAT, cell_weights=w).evaluate(x, d)
    assert st_w.energy == pytest.approx((N - 0.5) * W(d), rel=1e-12)
    # refining the mesh keeps the barrier per unit length: twice the nodes, half the weights
    x2 = np.zeros(4 * N - 2)
    x2[0::2] = np.linspace(1.0, 0.0, 2 * N - 1)
    w2 = length_weights(x2, n_paper=N)
    np.testing.assert_allclose(w2[1:-1], 0.5, rtol=1e-12)
    # the meridian's length (without the pole cell's mirrored half) is N - 1 spacings at any mesh
    assert np.sum(w2) - w2[-1] / 2 == pytest.approx(N - 1, rel=1e-12)
    assert np.sum(w) - w[-1] / 2 == pytest.approx(N - 1, rel=1e-12)
    with pytest.raises(ValueError, match="cell weights are for"):
        ContactBarrier(Plate(), K, DHAT, cell_weights=w).evaluate(x2, d)


def test_a_ring_is_seen_between_the_nodes():
    """A bump of the meridian sliding under the plate: the force at a fixed plate height.

    The meridian is ``z = -a (r - s0)^2`` on fixed nodes; as the top ``s0`` moves across one node
    spacing, the nodal barrier's force swings (the top is felt only at the nodes), the cells'
    force hardly moves: the ring is felt where it is.
    """
    l, a, d0 = 0.004, 2.0, 0.985 * DHAT  # about the spacing and curvature of the plate's ring at N = 200
    nodes = np.arange(1, 60) * l
    forces = {1: [], 15: []}
    for s0 in np.linspace(30 * l, 31 * l, 21):
        x = np.zeros(2 * nodes.size)
        x[0::2] = nodes[::-1]
        x[1::2] = -a * (nodes[::-1] - s0) ** 2
        for q in forces:
            forces[q].append(ContactBarrier(Plate(), K, DHAT, quadrature=q).force(x, d0))
    swing = {q: np.ptp(f) / np.mean(f) for q, f in forces.items()}
    assert swing[1] > 0.5  # the nodal barrier: 76 % over one spacing
    assert swing[15] < 1e-3  # the cells: 0.05 %


def test_no_contact_gives_zeros():
    cb, x, c = contact_setup("sphere", gap=2 * DHAT)
    st = cb.evaluate(x, c)
    assert st.n_active == 0 and st.energy == 0.0 and st.force == 0.0 and st.hess_cc == 0.0
    assert not np.any(st.gradient) and not np.any(st.hess_xc) and st.hessian_matrix().nnz == 0
    assert cb.energy(x, c) == 0.0


# ---- (d) C2 continuity at dhat and blow-up at contact ----------------------------------------------
@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_c2_continuity_at_dhat(shape):
    """Below dhat: W ~ K dhat^2 eps^3, W' ~ -3 K dhat eps^2, W'' ~ 6 K eps (d = dhat (1 - eps))."""
    call = kernels(shape)
    for eps in (1e-2, 1e-3, 1e-4):
        d = DHAT * (1 - eps)
        r, z = node_at(shape, d, 0.0)
        e, g, h = call("derivatives", r, z, 1.2)
        assert e[0] / (K * DHAT**2 * eps**3) == pytest.approx(1.0, abs=2 * eps)
        # on the axis the node's z derivative is -W' for both shapes (d decreases as z grows)
        assert -g[1, 0] / (-3 * K * DHAT * eps**2) == pytest.approx(1.0, abs=2 * eps)
        assert h[3, 0] / (6 * K * eps) == pytest.approx(1.0, abs=2 * eps)
    # the class: exactly zero at and above dhat, and continuous (value, gradient, Hessian) across it
    cb = ContactBarrier(Sphere(RHO) if shape == "sphere" else Plate(), K, DHAT)
    c = 1.2
    for d in (DHAT, DHAT * (1 + 1e-12), DHAT * (1 - 1e-12), DHAT * (1 - 1e-6), DHAT * 1.1):
        x = np.array(node_at(shape, d, 0.0, c))
        st = cb.evaluate(x, c)
        assert st.distances[0] == pytest.approx(d, rel=1e-11)
        assert st.n_active == int(st.distances[0] < DHAT)
        if st.n_active == 0:
            assert st.energy == 0.0 and st.force == 0.0 and not np.any(st.gradient)
        assert abs(st.energy) <= K * DHAT**2 * 1e-17
        assert np.max(np.abs(st.gradient)) <= K * DHAT * 1e-11
        assert abs(st.hess_cc) <= K * 1e-5 and np.max(np.abs(st.hess_blocks), initial=0.0) <= K * 1e-5


def test_barrier_blows_up_at_contact():
    cb = ContactBarrier(Plate(), K, DHAT)
    c = 0.0  # the node at z = -d: the distance is exact
    energies, forces = [], []
    for k in range(1, 13):
        d = DHAT * 10.0**-k
        st = cb.evaluate(np.array([0.2, c - d]), c)
        assert math.isfinite(st.energy) and np.all(np.isfinite(st.gradient)) and math.isfinite(st.hess_cc)
        assert st.energy == pytest.approx(W(d), rel=1e-9)
        # d -> 0+: W -> K dhat^2 log(dhat / d), F = -W' -> K dhat^2 / d (relative corrections
        # 2 (d / dhat) log(dhat / d) and d / dhat)
        assert st.energy == pytest.approx(K * DHAT**2 * k * math.log(10), rel=3 * 10.0**-k + 1e-6)
        assert st.force == pytest.approx(-W1(d), rel=1e-9)
        assert st.force == pytest.approx(K * DHAT**2 / d, rel=(2 * k * math.log(10) + 1) * 10.0**-k)
        energies.append(st.energy)
        forces.append(st.force)
    assert np.all(np.diff(energies) > 0) and np.all(np.diff(forces) > 0)
    assert energies[-1] > 25 * K * DHAT**2
    np.testing.assert_allclose(barrier_value([DHAT * 1e-6, DHAT, 2 * DHAT], K, DHAT),
                               [W(DHAT * 1e-6), 0.0, 0.0])


# ---- (e) errors instead of NaN -----------------------------------------------------------------------
@pytest.mark.parametrize("shape", ["sphere", "plate"])
@pytest.mark.parametrize("depth", [0.0, 1e-9, 0.05])
def test_penetrating_state_is_rejected(shape, depth):
    cb, x, c = contact_setup(shape, gap=0.0)
    pole = x.size // 2 - 1
    # the barrier sees the B-spline of the nodes, whose top is the pole cell's middle point
    # 3/4 z_pole + 1/4 z_neighbour (the neighbour mirrored across the axis counts twice)
    top = 0.75 * x[-1] + 0.25 * x[-3]
    c = c - (x[-1] - top) - depth  # the indenter at (depth 0) or overlapping that point
    for call in (lambda: cb.evaluate(x, c), lambda: cb.energy(x, c), lambda: cb.force(x, c),
                 lambda: cb.check(x, c), lambda: cb.max_safe_fraction(x, c, np.zeros_like(x))):
        with pytest.raises(ValueError, match=rf"node {pole} .*distance d = [-0-9.e]+ <= 0"):
            call()
    assert cb.sample_distances(x, c).min() == pytest.approx(-depth, abs=1e-15)


def test_non_finite_input_is_rejected():
    cb, x, c = contact_setup("sphere")
    bad = x.copy()
    bad[5] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        cb.evaluate(bad, c)
    with pytest.raises(ValueError, match="not finite"):
        cb.evaluate(x, math.inf)
    with pytest.raises(ValueError, match="not finite"):
        cb.max_safe_fraction(x, c, bad)
    with pytest.raises(ValueError, match="even length"):
        cb.evaluate(x[:-1], c)
    with pytest.raises(ValueError, match="safety"):
        cb.max_safe_fraction(x, c, np.zeros_like(x), safety=1.0)


# ---- (f) the step filter -----------------------------------------------------------------------------
def test_safe_fraction_plate_is_linear():
    cb = ContactBarrier(Plate(), K, DHAT)
    x = np.array([0.5, 0.0, 0.2, -0.3])
    # plate 0.01 above the first node, moving down by 0.02: contact at s = 0.5
    assert cb.max_safe_fraction(x, 0.01, np.zeros(4), -0.02) == pytest.approx(0.45, rel=1e-14)
    # the node moving up instead: the same
    assert cb.max_safe_fraction(x, 0.01, np.array([0.0, 0.02, 0.0, 0.0]), 0.0) == pytest.approx(0.45, rel=1e-14)
    # both, and another safety factor: closing rate 0.04 -> s = 0.25
    dx = np.array([0.3, 0.02, 0.0, 0.0])
    assert cb.max_safe_fraction(x, 0.01, dx, -0.02, safety=0.5) == pytest.approx(0.125, rel=1e-14)
    # exactly reaching the plate at s = 1 is not safe; stopping just short of it is
    assert cb.max_safe_fraction(x, 0.01, np.zeros(4), -0.01) == pytest.approx(0.9, rel=1e-14)
    assert cb.max_safe_fraction(x, 0.01, np.zeros(4), -0.0099) == 1.0
    # moving apart, or sideways: the whole step is safe
    assert cb.max_safe_fraction(x, 0.01, np.zeros(4), +0.5) == 1.0
    assert cb.max_safe_fraction(x, 0.01, np.array([5.0, 0.0, -1.0, 0.0]), 0.0) == 1.0


def test_safe_fraction_sphere_known_roots():
    rho, zc = 0.5, 1.0
    cb = ContactBarrier(Sphere(rho), K, DHAT)
    # node on the axis at z = 0 (d = 0.5) moving straight up to the centre: surface at s = 0.5
    x = np.array([0.0, 0.0])
    assert cb.max_safe_fraction(x, zc, np.array([0.0, 1.0])) == pytest.approx(0.45, rel=1e-14)
    # the sphere moving down instead
    assert cb.max_safe_fraction(x, zc, np.zeros(2), -1.0) == pytest.approx(0.45, rel=1e-14)
    # off the axis, straight toward the centre: (0.6, 0.2) is at distance 1 from (0, 1): s = 0.5
    x = np.array([0.6, 0.2])
    assert cb.max_safe_fraction(x, zc, np.array([-0.6, 0.8])) == pytest.approx(0.45, rel=1e-14)
    # split between node and sphere: node (-0.6, 0.4), sphere -0.4 -> relative motion (-0.6, 0.8)
    assert cb.max_safe_fraction(x, zc, np.array([-0.6, 0.4]), -0.4) == pytest.approx(0.45, rel=1e-14)
    # a chord: (0.3, 0) moving up by 2 enters the ball at s = 0.3 (and leaves at 0.7): first root
    x = np.array([0.3, 0.0])
    assert cb.max_safe_fraction(x, zc, np.array([0.0, 2.0])) == pytest.approx(0.27, rel=1e-13)
    # a step that passes beside the sphere: (0.6, 0) to (0.6, 2) never comes closer than 0.1
    assert cb.max_safe_fraction(np.array([0.6, 0.0]), zc, np.array([0.0, 2.0])) == 1.0
    # a step that stops short of the surface: safe
    assert cb.max_safe_fraction(np.array([0.0, 0.0]), zc, np.array([0.0, 0.49])) == 1.0
    # point indenter (rho = 0): the node must not reach the centre
    cp = ContactBarrier(Sphere(0.0), K, DHAT)
    assert cp.max_safe_fraction(np.array([0.0, 0.0]), 1.0, np.array([0.0, 4.0])) == pytest.approx(0.225)


@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_far_node_crossing_mid_step_limits_the_step(shape):
    """An active node moving away cannot hide a far node that a large step drives through the surface."""
    cb, x, c = contact_setup(shape, gap=0.5 * DHAT, N=41)
    st = cb.evaluate(x, c)
    far = 20
    assert far not in st.active and st.distances[far] > 50 * DHAT
    dx = np.zeros_like(x)
    dx[1::2] = -0.01  # every node moves down, away from the indenter, except the far node, which
    # moves 4 times its distance towards the indenter (straight at the sphere's centre, or up to
    # the plate): it reaches the surface at s = 0.25
    if shape == "sphere":
        rc = np.array([x[2 * far], x[2 * far + 1] - c])
        dx[2 * far:2 * far + 2] = -4 * st.distances[far] * rc / np.linalg.norm(rc)
    else:
        dx[2 * far + 1] = 4 * st.distances[far]
    t = cb.max_safe_fraction(x, c, dx)
    # the filter watches the cells' sample points, which are blends of three nodes (the B-spline):
    # the far cell's middle point, 3/4 of the far node and 1/8 of each neighbour, reaches the
    # surface a little after the node would, where the dense curve of the step crosses it
    first = np.inf
    for s in np.linspace(0.2, 0.5, 3001):
        y = x + s * dx
        for t_cell in np.linspace(-0.5, 0.5, 101):
            B = ((0.5 - t_cell) ** 2 / 2, 0.75 - t_cell ** 2, (0.5 + t_cell) ** 2 / 2)
            pr = sum(B[j] * y[2 * (far - 1 + j)] for j in range(3))
            pz = sum(B[j] * y[2 * (far - 1 + j) + 1] for j in range(3))
            d = math.hypot(pr, pz - c) - RHO if shape == "sphere" else c - pz
            if d <= 0:
                first = min(first, s)
        if first < np.inf:
            break
    assert 0.25 < first < 0.35
    assert t == pytest.approx(0.9 * first, rel=2e-3)
    # the shortened step is safe all the way (checked on a fine sampling), the full one is not
    for s in np.linspace(0, t, 50):
        cb.check(x + s * dx, c)
    with pytest.raises(ValueError, match=f"node {far} "):
        cb.check(x + 0.4 * dx, c)
    assert cb.max_safe_fraction(x, c, 0.2 * dx) == 1.0  # the first fifth of it is safe


@pytest.mark.parametrize("q", [1, 15])
@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_safe_fraction_against_sampling(shape, q):
    """Random steps: the fraction is safety times the first crossing of a sample point found by dense sampling."""
    rng = np.random.default_rng(11)
    cb = ContactBarrier(Sphere(0.4) if shape == "sphere" else Plate(), K, DHAT, quadrature=q)
    s = np.linspace(0.0, 1.0, 20001 if q == 1 else 4001)
    limited = 0
    for _ in range(200):
        c = 1.0
        n = 5
        theta = rng.uniform(0.2, math.pi / 2, n)
        x = np.empty(2 * n)
        rad = 0.4 + rng.uniform(0.01, 0.3, n) if shape == "sphere" else 1.0
        x[0::2] = rad * np.cos(theta) if shape == "sphere" else rng.uniform(0, 1, n)
        x[1::2] = c - (rad * np.sin(theta) if shape == "sphere" else rng.uniform(0.01, 0.3, n))
        dx = rng.normal(0, 0.2, 2 * n)
        dc = rng.normal(0, 0.1)
        if np.min(cb.sample_distances(x, c)) <= 0:  # a cell between the random nodes cuts the indenter
            continue
        t = cb.max_safe_fraction(x, c, dx, dc)
        if q == 1:  # the sample points are the nodes
            np.testing.assert_array_equal(cb.sample_distances(x, c), cb.distances(x, c))
        # every sample point is linear in the nodes: its path is that of its start plus s times its step
        p0, p1 = np.array(cb.cells(n).points(x[0::2], x[1::2])), np.array(cb.cells(n).points(dx[0::2], dx[1::2]))
        pr, pz = p0[0] + s[:, None] * p1[0], p0[1] + s[:, None] * p1[1]
        if shape == "sphere":
            dist = np.hypot(pr, pz - (c + s[:, None] * dc)) - 0.4
        else:
            dist = (c + s[:, None] * dc) - pz
        bad = np.flatnonzero(np.any(dist <= 0, axis=1))
        if bad.size == 0:
            assert t == 1.0 or t / 0.9 >= 1.0 - 1e-3  # grazing crossings the sampling may miss
        else:
            limited += 1
            assert t / 0.9 == pytest.approx(s[bad[0]], abs=2 / (s.size - 1))
    assert limited > 20


# ---- (g) the scaling rule for K_c and dhat -----------------------------------------------------------
def test_default_barrier_rule():
    assert default_barrier(1e6, 1.0) == (1e8, 1e-3)  # the paper's values
    K2, d2 = default_barrier(1e9, 10.0)
    assert K2 == pytest.approx(1e8 * 1e3 * 10) and d2 == pytest.approx(1e-2)
    # refining dhat keeps K_c dhat fixed
    K3, d3 = default_barrier(1e6, 1.0, dhat_over_R=1e-4)
    assert d3 == pytest.approx(1e-4) and K3 * d3 == pytest.approx(1e8 * 1e-3)
    with pytest.raises(ValueError):
        default_barrier(-1.0, 1.0)


def normalized(shape, E, R, rule=default_barrier, h_over_R=0.02, nu=0.5, quadrature=15):
    """Barrier energy / (E R^3) and F R / (2 pi D) of a fixed normalized configuration."""
    x = cap_state(41, R)
    Kc, dhat = rule(E, R)
    gap = 0.4e-3 * R  # the indenter 0.4e-3 R above the pole (inside dhat = 1e-3 R)
    indenter = Sphere(0.5 * R) if shape == "sphere" else Plate()
    cb = ContactBarrier(indenter, Kc, dhat, quadrature=quadrature)
    c = R + 0.5 * R + gap if shape == "sphere" else R + gap
    st = cb.evaluate(x, c)
    h = h_over_R * R
    D = E * h**3 / (12 * (1 - nu**2))
    return st.energy / (E * R**3), st.force * R / (2 * math.pi * D), st.n_active


@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_scale_invariance_of_the_default_rule(shape):
    e0, f0, n0 = normalized(shape, 1e6, 1.0)
    e1, f1, n1 = normalized(shape, 1e9, 10.0)
    assert n0 == n1 and n0 >= 2
    assert e1 == pytest.approx(e0, rel=1e-9) and f1 == pytest.approx(f0, rel=1e-9)
    # the reference numbers from the closed form with the paper's K_c, dhat (E = 1 MPa, R = 1), for
    # the nodal barrier (one point per cell)
    e0, f0, n0 = normalized(shape, 1e6, 1.0, quadrature=1)
    x = cap_state(41, 1.0)
    r, z = x[0::2], x[1::2]
    if shape == "sphere":
        d = np.hypot(r, z - 1.5004) - 0.5
    else:
        d = 1.0004 - z
    act = d < DHAT
    D = 1e6 * 0.02**3 / (12 * 0.75)
    assert e0 == pytest.approx(sum(W(v) for v in d[act]) / 1e6, rel=1e-9)
    if shape == "plate":  # F = -sum W'(d) (dd/dc = 1)
        assert f0 == pytest.approx(-sum(W1(v) for v in d[act]) / (2 * math.pi * D), rel=1e-9)
    # a rule that forgets the R in K_c (K_c proportional to E only) is not invariant
    def e_only(E, R):
        return 1e8 * E / 1e6, 1e-3 * R

    _, f2, _ = normalized(shape, 1e9, 10.0, rule=e_only, quadrature=1)
    assert f2 == pytest.approx(f0 / 10, rel=1e-9)


# ---- (g) a ring that slides over the mesh: the contact of issue 14, B8 ----------------------------
def _bump_state(r0, N=41, h=0.025, rho_b=0.5):
    """A meridian with its highest point, of radius of curvature ``rho_b``, at ``r = r0``, nodes at fixed ``r``."""
    r = np.arange(N)[::-1] * h  # the base at r = 1, the pole on the axis
    x = np.empty(2 * N)
    x[0::2], x[1::2] = r, -(r - r0) ** 2 / (2 * rho_b)
    return x


@pytest.mark.parametrize("support_points, smooth", [(None, True), (0, False)])
def test_a_light_ring_contact_does_not_feel_the_nodes(support_points, smooth):
    """A plate pressing lightly on a ring (0.6 % of dhat, where the thin caps of the fuzz study
    carried their load) while the ring slides by one node spacing: the meridian is the same shape
    translated, so the energy and the force must not change.  The B-spline of a parabola's nodes is
    the parabola lowered by ``h^2 / (8 rho_b)`` wherever its top sits, so the exact integral is
    constant; integrated over its support the barrier keeps it to rounding, whereas the fixed Gauss
    points of the cells (``support_points = 0``) see the narrow contact come and go."""
    h, rho_b = 0.025, 0.5
    opts = {} if support_points is None else {"support_points": support_points}
    cb = ContactBarrier(Plate(), K, DHAT, **opts)
    c = -h * h / (8 * rho_b) + 0.994 * DHAT
    r0s = 0.5 + np.linspace(0.0, h, 41)
    energy = np.array([cb.energy(_bump_state(r0), c) for r0 in r0s])
    force = np.array([cb.force(_bump_state(r0), c) for r0 in r0s])
    assert np.all(force > 0)
    spread_e, spread_f = np.ptp(energy) / energy.mean(), np.ptp(force) / force.mean()
    if smooth:
        assert spread_e < 1e-10 and spread_f < 1e-10
        # and it is the integral itself, not only constant
        ref = cell_energy_reference(_bump_state(0.51), c, "plate", 0.0, 15)
        assert cb.energy(_bump_state(0.51), c) == pytest.approx(ref, rel=1e-10)
    else:
        assert spread_e > 0.05 and spread_f > 0.05


@pytest.mark.parametrize("shape", ["sphere", "plate"])
@pytest.mark.parametrize("depth", [0.006, 0.3, 0.9])
def test_support_rule_against_adaptive_quadrature(shape, depth):
    """From a light touch to deep contact, the barrier integrated over its support is the integral."""
    cb, x, c = contact_setup(shape, gap=0.0, N=41)
    top = 0.75 * x[-1] + 0.25 * x[-3]  # the pole cell's middle point, the curve's highest
    c = c - (x[-1] - top) + (1.0 - depth) * DHAT
    st = cb.evaluate(x, c)
    assert st.n_active >= 1
    ref = cell_energy_reference(x, c, shape, RHO, 15)
    assert st.energy == pytest.approx(ref, rel=1e-10)
