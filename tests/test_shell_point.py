"""Point load at the pole of the discrete shell: derivatives, reference equilibrium, both controls."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from contin import continuation
from contin.numerics.linalg import bandwidths
from contin_models.shell import HALF_BANDWIDTH, ShellPointLoad

VARIANTS = [(kl, pole) for kl in ("reference", "current") for pole in ("mirror", "skip")]


def _perturbed(P: ShellPointLoad, seed: int) -> tuple[np.ndarray, float]:
    rng = np.random.default_rng(seed)
    u = P.reference_unknowns() + 0.01 * P.R * rng.standard_normal(P.n)
    p = 0.03 * P.R if P.control == "displacement" else 0.5 * P.reissner_stiffness() * 0.03 * P.R
    return u, p


def _central(f, u: np.ndarray, step: float) -> np.ndarray:
    cols = []
    for j in range(u.size):
        e = np.zeros(u.size)
        e[j] = step
        cols.append((f(u + e) - f(u - e)) / (2 * step))
    return np.array(cols).T


@pytest.mark.parametrize("control", ["displacement", "force"])
@pytest.mark.parametrize("kappa11_length,pole", VARIANTS)
def test_derivatives_match_central_differences(control, kappa11_length, pole):
    P = ShellPointLoad(N=20, h=0.05, control=control, kappa11_length=kappa11_length, pole=pole)
    for seed in (0, 1):
        u, p = _perturbed(P, seed)
        g = P.residual(u, p)
        g_fd = _central(lambda v: np.array([P.energy(v, p)]), u, 1e-6).ravel()
        assert np.max(np.abs(g - g_fd)) <= 1e-6 * np.max(np.abs(g))
        J = P.jacobian(u, p).toarray()
        J_fd = _central(lambda v: P.residual(v, p), u, 1e-6)
        assert np.max(np.abs(J - J_fd)) <= 1e-6 * np.max(np.abs(J))
        np.testing.assert_array_equal(J, J.T)
        dp = P.dresidual_dp(u, p)
        dp_fd = (P.residual(u, p + 1e-6) - P.residual(u, p - 1e-6)) / 2e-6
        assert np.max(np.abs(dp - dp_fd)) <= 1e-6 * np.max(np.abs(dp))


@pytest.mark.parametrize("control", ["displacement", "force"])
def test_jacobian_banded_and_stability_operators(control):
    P = ShellPointLoad(N=30, control=control)
    u, p = _perturbed(P, 3)
    J = P.jacobian(u, p)
    kl, ku = bandwidths(J)
    assert max(kl, ku) <= HALF_BANDWIDTH
    ops = P.stability_operators(u, p)
    assert sorted(ops) == ["displacement", "force"]
    assert list(ops)[0] == control  # the control's own stability is the primary label (used by jump)
    assert ops["displacement"].shape == (2 * P.N - 3,) * 2
    assert ops["force"].shape == (2 * P.N - 2,) * 2
    for op in ops.values():
        assert max(bandwidths(op)) <= HALF_BANDWIDTH
    # the operator of the problem's own control is its Jacobian
    np.testing.assert_array_equal(ops[control].toarray(), J.toarray())
    # the displacement operator is the force operator without the pole row and column
    np.testing.assert_array_equal(ops["force"].toarray()[:-1, :-1], ops["displacement"].toarray())
    # the banded factorization solves the system
    b = np.arange(P.n, dtype=float)
    np.testing.assert_allclose(J @ P.factorize(J).solve(b), b, rtol=0, atol=1e-8 * np.max(np.abs(b)))


@pytest.mark.parametrize("kappa11_length,pole", VARIANTS)
def test_reference_state_is_equilibrium(kappa11_length, pole):
    for control in ("displacement", "force"):
        P = ShellPointLoad(N=50, control=control, kappa11_length=kappa11_length, pole=pole)
        u0 = P.reference_unknowns()
        assert P.energy(u0, 0.0) == pytest.approx(0.0, abs=1e-20 * P.residual_scale * P.R)
        assert np.max(np.abs(P.residual(u0, 0.0))) <= 1e-12 * P.residual_scale
        obs = P.evaluate_observables(u0, 0.0)
        assert obs["w"] == 0.0 and abs(obs["F"]) <= 1e-12 * P.residual_scale
        # the reference state is stable under both controls
        for op in P.stability_operators(u0, 0.0).values():
            assert np.linalg.eigvalsh(op.toarray()).min() > 0


def test_state_maps_round_trip():
    for control in ("displacement", "force"):
        P = ShellPointLoad(N=12, control=control)
        u, p = _perturbed(P, 5)
        x = P.full_state(u, p)
        assert x[1] == P.cap.z[0] and x[-2] == 0.0
        back = P.unknowns(x)
        if control == "force":
            # the last unknown is the pole displacement w = zbar - z_pole (the dead load's generic
            # unknown): its round trip through z_pole is exact up to the rounding of that subtraction
            assert abs(back[-1] - u[-1]) <= 2 * np.finfo(float).eps * abs(P.z_pole_ref)
            back, u = back[:-1], u[:-1]
        np.testing.assert_array_equal(back, u)
    P = ShellPointLoad(N=12)
    assert P.pole_displacement(P.full_state(P.reference_unknowns(), 0.25)) == pytest.approx(0.25)


def test_linear_stiffness_is_the_initial_slope():
    P = ShellPointLoad(N=60)
    br = continuation(P, P.reference_unknowns(), 0.0, ds=1e-6, ds_max=1e-6, p_max=1e-6 * P.R,
                      detect_branch_points=False)
    assert br.status == "bound"
    F = br.observables["F"]
    w = br.observables["w"]
    k_secant = F[-1] / w[-1]
    assert k_secant == pytest.approx(P.linear_stiffness(), rel=1e-4)


def test_force_and_displacement_control_agree():
    N = 40
    Pd = ShellPointLoad(N=N, control="displacement")
    Pf = ShellPointLoad(N=N, control="force")
    br = continuation(Pd, Pd.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=0.02 * Pd.R,
                      stability=True)
    assert br.status == "bound" and br.p[-1] == pytest.approx(0.02 * Pd.R, rel=1e-12)
    assert len(br) >= 3
    labels = br.stable_under("force")
    assert np.all(labels) and np.all(br.stable_under("displacement"))
    picks = np.unique(np.linspace(1, len(br) - 1, 3).astype(int))
    for k in picks:
        u_d, w = br.u[k], br.p[k]
        F = br.observables["F"][k]
        x_d = Pd.full_state(u_d, w)
        # Newton on force control at F, started from the reference state
        u = Pf.reference_unknowns()
        for _ in range(30):
            r = Pf.residual(u, F)
            if np.max(np.abs(r)) <= 1e-11 * Pf.residual_scale:
                break
            u = u - Pf.factorize(Pf.jacobian(u, F)).solve(r)
        x_f = Pf.full_state(u, F)
        np.testing.assert_allclose(x_f, x_d, rtol=0, atol=1e-9 * Pd.R)
        assert Pf.evaluate_observables(u, F)["w"] == pytest.approx(w, rel=1e-8)
        assert Pf.evaluate_observables(u, F)["F_norm"] == pytest.approx(br.observables["F_norm"][k], rel=1e-12)


@pytest.mark.parametrize("control", ["displacement", "force"])
def test_exact_observable_derivatives_match_central_differences(control):
    P = ShellPointLoad(N=30, control=control)
    rng = np.random.default_rng(8)
    u = P.reference_unknowns() + 1e-3 * rng.standard_normal(P.n)
    p = 0.05 if control == "displacement" else 2.0
    for name, deriv in P.observable_derivatives.items():
        fun = P.observables[name]
        d_u, d_p = deriv(u, p)
        v = rng.standard_normal(P.n)
        h = 1e-6
        fd_u = (fun(u + h * v, p) - fun(u - h * v, p)) / (2 * h)
        fd_p = (fun(u, p + h) - fun(u, p - h)) / (2 * h)
        scale = max(abs(fd_u), abs(d_u @ v), 1e-8 * abs(fun(u, p)), 1e-12)
        assert d_u @ v == pytest.approx(fd_u, abs=1e-6 * scale), name
        assert d_p == pytest.approx(fd_p, rel=1e-6, abs=1e-9 * max(1.0, abs(fd_p))), name


@pytest.mark.parametrize("control", ["displacement", "force"])
def test_stability_counts_from_one_factorization_match_eigenvalues(control):
    # the nested-block Morse indices against dense eigenvalues of each operator, on buckled states
    P = ShellPointLoad(N=40, phi_hat=0.8, control="displacement")
    br = continuation(P, P.reference_unknowns(), 0.0, ds=0.02, ds_max=0.05, p_max=0.45, max_steps=200)
    Q = ShellPointLoad(N=40, phi_hat=0.8, control=control)
    seen = set()
    for u, w in zip(br.u[::3], br.p[::3]):
        x = P.full_state(u, w)
        uq, pq = (Q.unknowns(x), w) if control == "displacement" else (Q.unknowns(x), P.reaction_force(x))
        counts = {label: info.n_negative for label, info in Q.stability(uq, pq).items()}
        assert list(counts) == list(Q.stability_operators(uq, pq))
        for label, op in Q.stability_operators(uq, pq).items():
            expected = int(np.count_nonzero(np.linalg.eigvalsh(op.toarray()) < 0))
            assert counts[label] == expected, (label, w)
            seen.add(expected)
    assert len(seen) >= 2  # the path visits unstable states


def test_a_replaced_pole_element_acts_under_both_controls():
    from contin_models.shell import PoleMirror

    for control in ("displacement", "force"):
        P = ShellPointLoad(N=20, control=control)
        u = P.reference_unknowns()
        u[-1] += 0.01 * P.R  # displace the pole (force control) or a node next to it
        e0 = P.energy(u, 0.0)
        old = P.pole_element
        stiffer = PoleMirror(old.lbar, P.shell.kb, P.shell.nu, old.current_length, float(P.cap.r[-2]),
                             float(P.cap.z[-1] - P.cap.z[-2]))
        stiffer.K *= 2.0
        P.use_pole_element(stiffer)
        assert P.pole_element is stiffer
        x = P.full_state(u, 0.0)
        expected = P.shell.energy(x) + stiffer.energy(*(float(x[-4]), float(x[-1] - x[-3])))
        assert P.energy(u, 0.0) == pytest.approx(expected, rel=1e-12) and P.energy(u, 0.0) > e0


def test_csr_slots_finds_stored_entries_and_refuses_missing_ones() -> None:
    from contin_models.shell.problem import csr_slots

    A = sp.csr_matrix(np.array([[1.0, 0, 2.0], [0, 3.0, 0], [4.0, 5.0, 6.0]]))
    slots = csr_slots(A, [2, 0, 1, 2], [1, 2, 1, 0])
    np.testing.assert_array_equal(A.data[slots], [5.0, 2.0, 3.0, 4.0])
    with pytest.raises(KeyError, match=r"entry \(1, 2\)"):
        csr_slots(A, [0, 1], [0, 2])
