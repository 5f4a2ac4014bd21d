"""The von Mises truss: S-curve, limit loads, stability labels, jump, hysteresis (all closed form)."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from contin import continuation, diagram, extremum, hysteresis_cycles, jump
from contin_models.benchmarks.truss import TrussDisplacementControl, VonMisesTruss

A, B, K = 1.0, 0.5, 1.0


def closed_form():
    """Limit points from L^3 = L0 a^2, written here from the energy, not taken from the model."""
    L0 = math.hypot(A, B)
    L = (L0 * A * A) ** (1 / 3)
    y = math.sqrt(L * L - A * A)
    return y, 2 * K * y * (L0 / L - 1)


def P_of_y(y):
    L0 = math.hypot(A, B)
    return 2 * K * y * (L0 / np.sqrt(A * A + y * y) - 1)


def hessian_eigs(y):
    L0 = math.hypot(A, B)
    L2 = A * A + y * y
    c = 1 - L0 / math.sqrt(L2)
    return np.sort(2 * K * np.array([(A * A + c * y * y) / L2, (y * y + c * A * A) / L2]))


@pytest.fixture(scope="module")
def s_curve():
    tr = VonMisesTruss(A, B, K)
    return tr, continuation(tr, [0.0, B], 0.0, ds=0.02, ds_max=0.05, stability=True, n_eigs=2,
                            bounds={"y": (-1.6 * B, None)})


def test_s_curve_passes_both_limit_points(s_curve):
    tr, br = s_curve
    y_star, P_max = closed_form()
    folds = br.folds()
    assert [f.located for f in folds] == [True, True]
    assert folds[0].p == pytest.approx(P_max, rel=1e-10, abs=0)
    assert folds[1].p == pytest.approx(-P_max, rel=1e-10, abs=0)
    assert folds[0].observables["y"] == pytest.approx(y_star, rel=1e-6)
    # the unstable segment between the folds is traced, and the run ends on the inverted side
    ys = br.observables["y"]
    assert np.any((ys < y_star) & (ys > -y_star))
    assert br.status == "bound" and ys[-1] == pytest.approx(-1.6 * B, abs=1e-12)


def test_points_lie_on_the_closed_form_path(s_curve):
    _, br = s_curve
    np.testing.assert_allclose(br.u[:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(br.p, P_of_y(br.u[:, 1]), atol=1e-12)


def test_every_stability_label(s_curve):
    tr, br = s_curve
    for u, P, n_neg, eigs in zip(br.u, br.p, br.n_negative, br.eigenvalues):
        exact = hessian_eigs(u[1])
        assert n_neg == np.count_nonzero(exact < 0)
        np.testing.assert_allclose(eigs, exact, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(eigs, np.linalg.eigvalsh(tr.jacobian(u, P)), rtol=1e-12, atol=1e-14)
    y_star, _ = closed_form()
    ys = br.u[:, 1]
    assert np.all(br.n_negative[np.abs(ys) < y_star - 1e-9] == 1)
    assert np.all(br.n_negative[np.abs(ys) > y_star + 1e-9] == 0)
    assert br.folds()[0].info["stable_before"] and not br.folds()[0].info["stable_after"]


def test_jump_from_upper_limit_point_lands_on_inverted_state():
    tr = VonMisesTruss(A, B, K)
    load = continuation(tr, [0.0, B], 0.0, ds=0.02, ds_max=0.05, stop_at=("fold",))
    fold = load.folds()[0]
    assert load.status == "event" and load.p[-1] == fold.p
    jr = jump(tr, fold.u, fold.p)
    assert jr.success and jr.n_negative == 0 and jr.energy_to < jr.energy_from
    y_inv = brentq(lambda y: P_of_y(y) - fold.p, -3 * B, -closed_form()[0] - 1e-9, xtol=1e-15)
    assert jr.u_to[1] == pytest.approx(y_inv, abs=1e-10)
    assert jr.u_to[0] == pytest.approx(0.0, abs=1e-10)
    resumed = continuation(tr, jr.u_to, fold.p, ds=0.02, ds_max=0.05, p_max=2 * fold.p, stability=True,
                           origin=jr)
    assert resumed.status == "bound" and np.all(resumed.n_negative == 0)
    landing = resumed.special_points[0]
    assert landing.kind == "jump" and landing.label == "jump_to" and landing.index == 0
    assert landing.p == fold.p and landing.info["energy_released"] > 0
    np.testing.assert_allclose(resumed.p, P_of_y(resumed.u[:, 1]), atol=1e-12)


def test_jump_refuses_a_stable_start():
    tr = VonMisesTruss(A, B, K)
    from contin import JumpError
    with pytest.raises(JumpError, match="stable"):
        jump(tr, np.array([0.0, B]), 0.0)


def test_hysteresis_loop_is_a_cycle_of_the_diagram():
    tr = VonMisesTruss(A, B, K)
    kw = dict(ds=0.02, ds_max=0.05, stability=True, stop_at=("fold",))
    load = continuation(tr, [0.0, B], 0.0, **kw)
    j1 = jump(tr, load.u[-1], load.p[-1])
    unload = continuation(tr, j1.u_to, j1.p, direction=-1, **kw)
    j2 = jump(tr, unload.u[-1], unload.p[-1])
    reload = continuation(tr, j2.u_to, j2.p, direction=1, **kw)
    G = diagram([load, unload, reload], [j1, j2])
    cycles = hysteresis_cycles(G)
    assert len(cycles) == 1 and len(cycles[0]) == 4
    kinds = [e["kind"] for *_, e in G.edges(data=True)]
    assert kinds.count("jump") == 2
    stable = {e["stable"] for *_, e in G.edges(data=True) if e["kind"] == "branch"}
    assert stable == {True}
    # without the second jump there is no loop
    assert hysteresis_cycles(diagram([load, unload], [j1])) == []


def test_force_maximum_under_displacement_control_equals_force_control_fold():
    dc = TrussDisplacementControl(A, B, K)
    br = continuation(dc, [0.0], B, direction=-1, ds=0.02, ds_max=0.05, p_min=-B,
                      events=[extremum("P", "max")])
    (ev,) = br.events("max(P)")
    _, P_max = closed_form()
    assert ev.located and ev.info["extremum_value"] == pytest.approx(P_max, rel=1e-12, abs=0)
    assert ev.p == pytest.approx(closed_form()[0], rel=1e-7)


def test_fold_that_ends_a_run_reports_the_side_it_came_from():
    tr = VonMisesTruss(A, B, K)
    load = continuation(tr, [0.0, B], 0.0, ds=0.02, ds_max=0.05, stop_at=("fold",), stability=True)
    (fold,) = load.folds()
    assert fold.info["ends_branch"] and fold.info["n_negative_before"] == 0
    assert fold.info["stable_before"] is True and "stable_after" not in fold.info


def test_a_step_along_a_tiny_negative_curvature_is_found_at_a_small_size(monkeypatch):
    """E = -eps u0^2 / 2 + K u0^4 + u1^2 / 2 near its saddle: with eps = 1e-6 and K = 1e3 the quartic
    outweighs the negative curvature at 1e-4 of the scale and beyond, so only the smaller sizes lower
    the energy; without them the descent would crawl off the saddle by shifted-Newton steps."""
    import importlib

    import contin

    jump_module = importlib.import_module("contin.analyses.jump")
    eps, K = 1e-6, 1e3

    def energy(u, p):
        return -0.5 * eps * u[0] ** 2 + K * u[0] ** 4 + 0.5 * u[1] ** 2

    def gradient(u, p):
        return np.array([-eps * u[0] + 4 * K * u[0] ** 3, u[1]])

    problem = contin.GradientProblem(energy, gradient)
    x = np.array([1e-9, 0.0])
    g, E = gradient(x, 0.0), energy(x, 0.0)
    step = jump_module._negative_curvature_step(problem, x, 0.0, g, E, 1.0)
    assert step is not None and step[2] < E
    assert 0 < abs(step[1][0]) <= 1.1e-5 and step[1][0] > 0  # downhill: the side the gradient points away from
    monkeypatch.setattr(jump_module, "SMALL_CURVATURE_STEPS", ())
    assert jump_module._negative_curvature_step(problem, x, 0.0, g, E, 1.0) is None
