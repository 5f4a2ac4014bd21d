"""Point load at the pole of the discrete shell: derivatives, reference equilibrium, both controls."""

from __future__ import annotations

import numpy as np
import pytest

from contin import continuation
from contin.linalg import bandwidths
from models.shell import HALF_BANDWIDTH, ShellPointLoad

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
        np.testing.assert_array_equal(P.unknowns(x), u)
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


def _observed_orders(values) -> np.ndarray:
    d = np.diff(np.asarray(values, dtype=float))
    return np.log2(np.abs(d[:-1] / d[1:]))


def test_mirror_pole_converges_at_second_order_linear_stiffness():
    ks = [ShellPointLoad(N=N).linear_stiffness() for N in (100, 200, 400, 800)]
    orders = _observed_orders(ks)
    # error ~ N^-2 log N (point-load singularity): the observed order approaches 2 from below
    assert np.all(orders > 1.7) and np.all(np.diff(orders) > 0)


def test_reissner_limit_thin_shell():
    P = ShellPointLoad(h=0.001, N=6400)
    ratio = P.linear_stiffness() / P.reissner_stiffness()
    # deep-cap shortfall 1 - k/kR ~ 0.87 sqrt(h/R) (measured over h/R = 0.001 .. 0.02)
    assert 1 - ratio == pytest.approx(0.87 * np.sqrt(0.001), rel=0.05)


def test_force_at_tenth_radius_converges_at_second_order():
    Fs = []
    for N in (50, 100, 200, 400, 800):
        P = ShellPointLoad(N=N)
        br = continuation(P, P.reference_unknowns(), 0.0, p_max=0.1 * P.R, ds=0.01, ds_max=0.05,
                          detect_branch_points=False)
        assert br.status == "bound"
        Fs.append(br.observables["F"][-1])
    assert np.all(_observed_orders(Fs) > 1.75)


def test_normalized_force_maximum_is_scale_invariant():
    # E x 1e3 and R x 10 (h scaled with R): w/R and F R / (2 pi D) at the force maximum must not move
    from contin import continuation, extremum

    found = []
    for E, R in [(1e6, 1.0), (1e9, 10.0)]:
        pb = ShellPointLoad(N=40, E=E, R=R, h=0.02 * R, control="displacement")
        br = continuation(pb, pb.reference_unknowns(), 0.0, ds=0.02 * R, ds_max=0.05 * R, p_max=0.32 * R,
                          events=[extremum("F", "max")])
        (ev,) = br.events("max(F)")
        found.append((ev.observables["w_over_R"], ev.observables["F_norm"]))
    assert found[1][0] == pytest.approx(found[0][0], rel=1e-8)
    assert found[1][1] == pytest.approx(found[0][1], rel=1e-8)
