"""The symmetric benchmark models: derivatives, closed forms at their symmetric states, symmetry generators.

Models: :mod:`contin_models.benchmarks.square` (D4), :mod:`contin_models.benchmarks.ring` (the dihedral
group of the polygon), :mod:`contin_models.benchmarks.spring_chain` (S_k), :mod:`contin_models.benchmarks.augusti`
(D4 and O(2)).  The closed forms are written out here where they are short; where a model's method
gives one (the ring's Fourier symbols, the chain's sawtooth), it is checked against the model's own
residual and Hessian, two derivations that share no code.  What the engine does at these models'
degenerate points is measured by ``studies/degenerate_points.py``; nothing here runs the engine.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

import contin
from contin_models.benchmarks.augusti import AugustiStrut
from contin_models.benchmarks.ring import PressurisedRing
from contin_models.benchmarks.spring_chain import BistableChain
from contin_models.benchmarks.square import D4Square
from contin_models.benchmarks.symmetry import group_closure_size, signed_permutation


def dense(matrix) -> np.ndarray:
    return matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix)


def newton(problem: contin.Problem, u: np.ndarray, p: float, steps: int = 30) -> np.ndarray:
    """An equilibrium at fixed ``p`` from ``u`` (plain Newton, for a start already close to one)."""
    for _ in range(steps):
        du = np.linalg.solve(dense(problem.jacobian(u, p)), -problem.residual(u, p))
        u = u + du
        if np.max(np.abs(du)) <= 1e-14 * max(1.0, np.max(np.abs(u))):
            break
    return u


def assert_symmetry(problem: contin.Problem, states: list[np.ndarray], p: float, order: int) -> None:
    """The generators are orthogonal, generate a group of ``order`` elements, keep the energy and are equivariant."""
    generators = problem.symmetry_generators
    assert group_closure_size(generators) == order
    for g in generators:
        G = dense(g)
        np.testing.assert_allclose(G @ G.T, np.eye(G.shape[0]), atol=1e-14)
        for u in states:
            assert problem.energy(G @ u, p) == pytest.approx(problem.energy(u, p), rel=1e-12, abs=1e-14)
            scale = np.max(np.abs(problem.residual(u, p))) + 1.0
            np.testing.assert_allclose(G.T @ problem.residual(G @ u, p), problem.residual(u, p), atol=1e-11 * scale)


def assert_commutes(problem: contin.Problem, u: np.ndarray, p: float) -> None:
    """At a state every generator fixes, the generators commute with the Hessian."""
    H = dense(problem.jacobian(u, p))
    for g in problem.symmetry_generators:
        G = dense(g)
        np.testing.assert_allclose(G @ u, u, atol=1e-14)
        np.testing.assert_allclose(G @ H, H @ G, atol=1e-12 * np.max(np.abs(H)))


# ---- the D4 square ----------------------------------------------------------------------------------
def test_square_derivatives() -> None:
    m = D4Square(8)
    u = 0.3 * np.random.default_rng(0).standard_normal(64)
    assert contin.check_problem(m, u, 25.0).ok


def test_square_trivial_branch_eigenvalues_are_those_of_the_discrete_laplacian() -> None:
    n, p = 30, 40.0
    m = D4Square(n)
    h = 1.0 / (n + 1)
    s = np.sin(np.arange(1, n + 1) * np.pi * h / 2) ** 2
    closed = np.sort((4 / h ** 2 * (s[:, None] + s[None, :]) - p).ravel() * h ** 2)
    found = np.linalg.eigvalsh(dense(m.jacobian(np.zeros(n * n), p)))
    np.testing.assert_allclose(found, closed, rtol=1e-10)
    # the double point (1,2)/(2,1): two eigenvalues h^2 (lambda_12 - p) and the model's list says so
    lam12 = 4 / h ** 2 * (s[0] + s[1])
    assert np.sum(np.abs(found - h ** 2 * (lam12 - p)) < 1e-10) == 2
    assert (lam12, 2, (1, 2)) in [(pytest.approx(q, rel=1e-14), mult, jk) for q, mult, jk in m.branch_points(60.0)]


def test_square_quartic_coefficients_are_the_exact_grid_sums() -> None:
    # sum sin^4 = 3 (n+1)/8 and sum sin^2(pi x) sin^2(2 pi x) = (n+1)/4 on the grid: alpha = 9/4, beta = 1
    for n in (6, 30, 41):
        alpha, beta = D4Square(n).quartic_coefficients(1, 2)
        assert alpha == pytest.approx(9 / 4, rel=1e-13) and beta == pytest.approx(1.0, rel=1e-13)


@pytest.mark.parametrize("mixed", [False, True])
def test_square_cubic_bifurcation_equation_gives_the_branch_amplitudes(mixed: bool) -> None:
    # an equilibrium near lambda_12 along a pure or a mixed kernel direction, against (p - lambda)/alpha
    # and 2 (p - lambda)/(alpha + 3 beta), to leading order: the error is O(p - lambda)
    m = D4Square(12)
    lam = m.eigenvalue(1, 2)
    direction = m.mode(1, 2) + (m.mode(2, 1) if mixed else 0.0)
    for dp in (0.4, 0.2):
        p = lam + dp
        closed = math.sqrt(2 * dp / (9 / 4 + 3) if mixed else dp / (9 / 4))
        guess = closed * direction / math.sqrt(m.h ** 2 * np.dot(direction, direction))
        u = newton(m, guess, p)
        assert np.max(np.abs(m.residual(u, p))) < 1e-14
        norm = math.sqrt(m.h ** 2 * np.dot(u, u))
        assert abs(norm / closed - 1) < 0.02 * dp
        assert m.branch_amplitude(p, "mixed" if mixed else "pure") == pytest.approx(closed, rel=1e-12)


def test_square_symmetry_is_d4_and_maps_equilibria_to_equilibria() -> None:
    m = D4Square(10)
    rng = np.random.default_rng(1)
    assert_symmetry(m, [rng.standard_normal(100) for _ in range(2)], 30.0, 8)
    assert_commutes(m, np.zeros(100), 30.0)
    p = m.eigenvalue(1, 2) + 2.0
    u = newton(m, 0.9 * m.mode(1, 2), p)
    assert np.max(np.abs(m.residual(u, p))) < 1e-13 and np.max(np.abs(u)) > 0.1
    for g in m.symmetry_generators:
        assert np.max(np.abs(m.residual(g @ u, p))) < 1e-13


# ---- the ring ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("coordinates", ["displacements", "positions"])
def test_ring_derivatives(coordinates: str) -> None:
    m = PressurisedRing(16, membrane_ratio=1e3, coordinates=coordinates)
    u = m.trivial_state(0.0) + 0.05 * np.random.default_rng(2).standard_normal(32)
    assert contin.check_problem(m, u, 2.0).ok


@pytest.mark.parametrize("coordinates", ["displacements", "positions"])
def test_ring_trivial_branch_is_an_equilibrium_with_the_symbols_eigenvalues(coordinates: str) -> None:
    # a moderate membrane penalty: with EA R^2 / EI = 1e6 the Hessian's norm puts eigh's rounding at
    # 1e-9 of the bending eigenvalues
    m = PressurisedRing(32, membrane_ratio=1e3, coordinates=coordinates)
    for p in (0.0, 1.0, 2.5, 5.0):
        u = m.trivial_state(p)
        assert np.max(np.abs(m.residual(u, p))) < 1e-12
        found = np.linalg.eigvalsh(dense(m.jacobian(u, p)))
        np.testing.assert_allclose(found, m.trivial_hessian_eigenvalues(p), rtol=1e-10)


def test_ring_radius_of_the_compressed_ring() -> None:
    m = PressurisedRing(16, membrane_ratio=1e3)
    p = 4.0
    # the hoop force -p r cos(theta/2) stretches the segments by N l0 / EA
    r = m.trivial_radius(p)
    hoop = m.EA * (r / m.R - 1.0)
    assert hoop == pytest.approx(-p * r * math.cos(math.pi / 16), rel=1e-12)


def test_ring_buckling_loads_tend_to_the_classical_ones() -> None:
    # inextensible limit: p_n^(N) -> (n^2 - 1) EI / R^3 at second order in 1/N
    errors = [abs(PressurisedRing(N).inextensible_buckling_load(2) - 3.0) for N in (32, 64, 128)]
    assert errors[0] < 0.03 and 3.9 < errors[0] / errors[1] < 4.1 and 3.9 < errors[1] / errors[2] < 4.1
    assert abs(PressurisedRing(128).inextensible_buckling_load(3) - 8.0) < 0.02
    # the membrane penalty's effect on p_2 shrinks with it, like 1 / (EA R^2 / EI)
    limit = PressurisedRing(32).inextensible_buckling_load(2)
    gaps = [abs(PressurisedRing(32, membrane_ratio=ratio).buckling_load(2) - limit) for ratio in (1e4, 1e5)]
    assert 9 < gaps[0] / gaps[1] < 11


def test_ring_buckling_loads_are_double_zeros_of_the_hessian() -> None:
    m = PressurisedRing(16, membrane_ratio=1e3)
    for n in (2, 3, 4):
        p = m.buckling_load(n)
        found = np.linalg.eigvalsh(dense(m.jacobian(m.trivial_state(p), p)))
        assert np.sum(np.abs(found) < 1e-9) == 2


@pytest.mark.parametrize("coordinates", ["displacements", "positions"])
def test_ring_symmetry_is_the_polygons_dihedral_group(coordinates: str) -> None:
    m = PressurisedRing(12, membrane_ratio=1e3, coordinates=coordinates)
    rng = np.random.default_rng(3)
    states = [m.trivial_state(0.0) + 0.05 * rng.standard_normal(24) for _ in range(2)]
    assert_symmetry(m, states, 2.0, 24)
    assert_commutes(m, m.trivial_state(3.0), 3.0)


# ---- the chain --------------------------------------------------------------------------------------
@pytest.mark.parametrize("k", [2, 3, 6])
@pytest.mark.parametrize("coordinates", ["nodes", "modes"])
def test_chain_derivatives(k: int, coordinates: str) -> None:
    m = BistableChain(k, coordinates=coordinates)
    rng = np.random.default_rng(k)
    e = 1.0 + 0.2 * rng.standard_normal(k)
    assert contin.check_problem(m, m.state(e), float(e.sum())).ok


@pytest.mark.parametrize("k", [2, 3, 6])
@pytest.mark.parametrize("coordinates", ["nodes", "modes"])
def test_chain_homogeneous_branch_eigenvalues(k: int, coordinates: str) -> None:
    m = BistableChain(k, coordinates=coordinates)
    s, w = 3.0, 0.1
    e_a = 1 - w * math.acosh(math.sqrt(s))
    for Delta in (0.5 * k, k * e_a, 1.02 * k, 1.5 * k):
        stiffness = 1 - s / math.cosh((Delta / k - 1) / w) ** 2
        weights = np.ones(k - 1) if coordinates == "modes" else 4 * np.sin(np.arange(1, k) * np.pi / (2 * k)) ** 2
        u = m.state(np.full(k, Delta / k))
        assert np.max(np.abs(m.residual(u, Delta))) < 1e-14
        np.testing.assert_allclose(np.linalg.eigvalsh(dense(m.jacobian(u, Delta))), np.sort(stiffness * weights),
                                   rtol=1e-10, atol=1e-12)  # at the spinodal: f(e) rounded
    # the two branch points, of multiplicity k - 1, where f'(e) = 0
    (D_a, F_a, mult_a), (D_b, _, mult_b) = m.homogeneous_branch_points()
    assert D_a == pytest.approx(k * e_a, rel=1e-14) and D_b == pytest.approx(k * (2 - e_a), rel=1e-14)
    assert mult_a == mult_b == k - 1
    H = dense(m.jacobian(m.state(np.full(k, D_a / k)), D_a))
    assert np.max(np.abs(H)) < 1e-12  # f'(e_a) = 0 up to the rounding of e_a
    assert F_a == pytest.approx(e_a - s * w * (math.tanh((e_a - 1) / w) + math.tanh(1 / w)), rel=1e-14)


def test_chain_phases_and_the_pitchfork_limit() -> None:
    m = BistableChain(2)
    F_min, F_max = m.force_range
    for F in np.linspace(F_min, F_max, 7)[1:-1]:
        e = m.phase_elongations(F)
        assert e[0] < m.spinodals[0] < e[1] < m.spinodals[1] < e[2]
        np.testing.assert_allclose(m.spring_force(np.array(e)), F, atol=1e-14)
    # 1/f'(e1) + 1/f'(e2) at equal forces near the peak tends to -(2/3) f''' / f''^2
    f2, f3 = m.spring_derivatives_at_peak()
    e1, e2, _ = m.phase_elongations(F_max - 1e-8)
    assert 1 / m.spring_stiffness(e1) + 1 / m.spring_stiffness(e2) == pytest.approx(-2 / 3 * f3 / f2 ** 2, rel=1e-3)


@pytest.mark.parametrize("k", [2, 3, 6])
def test_chain_sawtooth_snaps_from_a_critical_state_to_a_stable_one(k: int) -> None:
    # each tooth, checked on the model itself: before the snap an equilibrium with a singular Hessian
    # (k - j - 1 zero eigenvalues at a spinodal, one at a fold) and otherwise stable; after it a stable
    # equilibrium at the same total elongation with one more spring on its outer branches
    m = BistableChain(k, coordinates="modes")
    teeth = m.sawtooth()
    assert [t.springs_out for t in teeth] == list(range(k))
    for t in teeth:
        e1, e2, e3 = m.phase_elongations(t.force_before)
        j = t.springs_out
        before = [e1] * (k - j - (t.at == "fold")) + [e2] * (t.at == "fold") + [e3] * j
        assert sum(before) == pytest.approx(t.delta, rel=1e-13)
        u = m.state(before)
        assert np.max(np.abs(m.residual(u, t.delta))) < 1e-12
        eig = np.linalg.eigvalsh(dense(m.jacobian(u, t.delta)))
        zeros = int(np.sum(np.abs(eig) < 1e-7))
        assert zeros == (t.multiplicity if t.at == "spinodal" else 1) and np.all(eig > -1e-7)
        a1, a2, a3 = m.phase_elongations(t.force_after)
        candidates = [[a1] * (k - j - 1) + [a3] * (j + 1), [a1] * (k - j - 1) + [a2] + [a3] * j]
        after = min(candidates, key=lambda e: abs(sum(e) - t.delta))
        assert sum(after) == pytest.approx(t.delta, rel=1e-12)
        v = m.state(after)
        assert np.max(np.abs(m.residual(v, t.delta))) < 1e-12
        assert np.all(np.linalg.eigvalsh(dense(m.jacobian(v, t.delta))) > 0)
    assert all(a.delta < b.delta for a, b in zip(teeth, teeth[1:]))


@pytest.mark.parametrize("k, order", [(2, 2), (3, 6), (6, 720)])
def test_chain_symmetry_is_the_permutations_of_the_springs(k: int, order: int) -> None:
    m = BistableChain(k, coordinates="modes")
    rng = np.random.default_rng(k)
    assert_symmetry(m, [m.state(1 + 0.2 * rng.standard_normal(k)) for _ in range(2)], 1.1 * k, order)
    assert_commutes(m, np.zeros(k - 1), 0.9 * k)
    # an equilibrium with one spring on its outer branch, and its images: the same spring law at each
    e1, _, e3 = m.phase_elongations(0.7)
    e = np.array([e3] + [e1] * (k - 1))
    u, Delta = m.state(e), float(e.sum())
    for g in m.symmetry_generators:
        assert np.max(np.abs(m.residual(g @ u, Delta))) < 1e-13
        assert sorted(m.elongations(g @ u, Delta)) == pytest.approx(sorted(e), abs=1e-13)
    assert BistableChain(3, coordinates="nodes").symmetry_generators == ()


# ---- the Augusti struts -----------------------------------------------------------------------------
@pytest.mark.parametrize("spring_length", [None, 2.0])
@pytest.mark.parametrize("epsilon, omega", [(0.0, 0.0), (1e-3, 0.0), (1e-3, math.pi / 4), (1e-3, 0.3)])
def test_augusti_derivatives(spring_length, epsilon: float, omega: float) -> None:
    m = AugustiStrut(spring_length, epsilon, omega)
    assert contin.check_problem(m, np.array([0.1, -0.05]), 0.9).ok


@pytest.mark.parametrize("spring_length", [None, 2.0, 4.0])
def test_augusti_double_point_and_its_quartic_terms(spring_length) -> None:
    m = AugustiStrut(spring_length)
    for lam in (0.0, 0.7, 1.0, 1.3):
        np.testing.assert_allclose(np.linalg.eigvalsh(dense(m.jacobian(np.zeros(2), lam))), [1 - lam, 1 - lam],
                                   atol=1e-14)
    # V(t d, 1) = c4(d) t^4 + O(t^6): the closed-form quartic coefficient against the energy itself
    b2 = 0.0 if spring_length is None else spring_length ** -2
    for angle in (0.0, math.pi / 4, 0.3):
        c, s = math.cos(angle), math.sin(angle)
        c4 = (b2 - 1) / 8 * (c ** 4 + s ** 4) - (b2 + 0.25) * c ** 2 * s ** 2
        assert m.quartic_coefficient(angle) == pytest.approx(c4, rel=1e-14)
        d = np.array([c, s])
        quotient = lambda t: m.energy(t * d, 1.0) / t ** 4  # c4 + c6 t^2 + ...
        t1, t2 = 2e-2, 1e-2
        estimate = (t1 ** 2 * quotient(t2) - t2 ** 2 * quotient(t1)) / (t1 ** 2 - t2 ** 2)  # the t^2 term removed
        assert estimate == pytest.approx(c4, rel=1e-6)


def test_augusti_o2_limit_load_is_koiters_law_in_closed_form() -> None:
    for epsilon in (1e-5, 1e-6):
        m = AugustiStrut(None, epsilon)
        xi, lam = m.limit_load()
        assert xi == pytest.approx(epsilon ** (1 / 3), rel=1e-14)
        assert lam == pytest.approx((1 - epsilon ** (2 / 3)) ** 1.5, rel=1e-14)
        assert np.max(np.abs(m.residual(m.path_state(xi), lam))) < 1e-15
        # the path's maximum: lambda(xi) = (1 - eps/xi) sqrt(1 - xi^2) is lower on both sides
        assert m.path_load(0.99 * xi) < lam and m.path_load(1.01 * xi) < lam
        assert m.koiter_limit_load() == pytest.approx(1 - 1.5 * epsilon ** (2 / 3), rel=1e-14)


@pytest.mark.parametrize("omega", [0.0, math.pi / 4])
def test_augusti_two_mode_limit_load_and_its_leading_order(omega: float) -> None:
    for epsilon in (1e-5, 1e-6):
        m = AugustiStrut(2.0, epsilon, omega)
        xi, lam = m.limit_load()
        assert np.max(np.abs(m.residual(m.path_state(xi), lam))) < 1e-15
        # the limit point is where the path's tangent is horizontal: the Hessian is singular along the line
        eig = np.linalg.eigvalsh(dense(m.jacobian(m.path_state(xi), lam)))
        assert np.min(np.abs(eig)) < 1e-7
        A = (1 - 0.25) / 2 if omega == 0.0 else (3 * 0.25 + 2) / 4
        koiter = 1 - 3 * A ** (1 / 3) * (epsilon / 2) ** (2 / 3)
        assert m.koiter_limit_load() == pytest.approx(koiter, rel=1e-14)
        # Koiter's law is the leading order: the remainder is O(epsilon^(4/3)) in 1 - lambda_s
        assert abs(lam - koiter) < 5 * epsilon ** (4 / 3)
        assert m.secondary_branch_point() is None


def test_augusti_secondary_branch_point_on_a_soft_axis_path() -> None:
    # springs nearly as short as the strut: along an axis the path loses its stability across the
    # axis before its limit point; there the transverse stiffness, from the model's Hessian, vanishes
    m = AugustiStrut(1.2, 1e-5, 0.0)
    xi_b, lam_b = m.secondary_branch_point()
    assert lam_b < m.limit_load()[1]
    H = dense(m.jacobian(m.path_state(xi_b), lam_b))
    assert abs(H[1, 1]) < 1e-12 and abs(H[0, 1]) < 1e-15


@pytest.mark.parametrize("spring_length", [None, 2.0])
def test_augusti_symmetry(spring_length) -> None:
    rng = np.random.default_rng(4)
    states = [0.2 * rng.standard_normal(2) for _ in range(3)]
    perfect = AugustiStrut(spring_length)
    assert_symmetry(perfect, states, 0.8, 8)
    assert_commutes(perfect, np.zeros(2), 0.8)
    xi = 0.1
    lam = perfect.path_load(xi)
    for g in perfect.symmetry_generators:
        assert np.max(np.abs(perfect.residual(dense(g) @ perfect.path_state(xi), lam))) < 1e-15
    imperfect = AugustiStrut(spring_length, 1e-3, math.pi / 4)
    assert_symmetry(imperfect, states, 0.8, 2)
    assert AugustiStrut(2.0, 1e-3, 0.3).symmetry_generators == ()
    assert len(AugustiStrut(None, 1e-3, 0.3).symmetry_generators) == 1


def test_signed_permutation_refuses_what_is_not_one() -> None:
    np.testing.assert_array_equal(dense(signed_permutation([1, 0], [1, -1])), [[0, 1], [-1, 0]])
    with pytest.raises(ValueError, match="permutation"):
        signed_permutation([0, 0])
    with pytest.raises(ValueError, match="signs"):
        signed_permutation([1, 0], [1, 2])
