"""Failure behaviour: step shrinking, minimum step, no unconverged or non-finite point stored."""

import numpy as np
import pytest

from contin import Problem, continuation


def wall_problem(p_wall=1.0):
    """u^3 + u - p = 0, whose residual is NaN beyond p = p_wall (a model that breaks down)."""
    def residual(u, p):
        r = u ** 3 + u - p
        return r if p < p_wall else np.full_like(r, np.nan)
    return Problem(residual=residual, jacobian=lambda u, p: np.diag(3 * u ** 2 + 1),
                   dresidual_dp=lambda u, p: -np.ones_like(u), name="wall")


def test_nan_is_a_failure_and_the_run_stops_with_a_reason():
    br = continuation(wall_problem(), [0.0], 0.0, ds=0.1, ds_max=0.3, ds_min=1e-6, max_steps=500)
    assert br.status == "min_step"
    assert "ds_min" in br.message and "not finite" in br.message
    assert np.all(br.p < 1.0)
    assert br.p[-1] > 1.0 - 1e-5  # it shrank the step down to the wall before giving up
    assert np.all(np.isfinite(br.u)) and np.all(br.residual <= br.meta["abs_tol"])


def test_thin_constructor_with_finite_difference_fallbacks():
    # only the residual: Jacobian and df/dp come from finite differences
    pb = Problem(residual=lambda u, p: u ** 3 - u + p)
    br = continuation(pb, [-1.2], -0.5, ds=0.05, ds_max=0.1, p_max=0.6, tol=1e-9)
    folds = br.folds()
    # folds of p = u - u^3 at u = +-1/sqrt(3): p = -+2 / (3 sqrt(3))
    assert len(folds) == 2
    assert sorted(f.p for f in folds) == pytest.approx([-2 / (3 * np.sqrt(3)), 2 / (3 * np.sqrt(3))], rel=1e-8)


def test_unconvergeable_start_fails_cleanly():
    pb = Problem(residual=lambda u, p: np.exp(u) + 1.0 + 0 * p, jacobian=lambda u, p: np.diag(np.exp(u)))
    br = continuation(pb, [0.0], 0.0)
    assert br.status == "failed" and "could not start" in br.message
    assert len(br) == 0 and not br.success


def test_invalid_settings_name_the_field():
    pb = Problem(residual=lambda u, p: u - p)
    with pytest.raises(ValueError, match="'ds_min'"):
        continuation(pb, [0.0], 0.0, ds_min=-1.0)
    with pytest.raises(TypeError, match="unknown continuation option"):
        continuation(pb, [0.0], 0.0, step=0.1)


def test_corrector_never_stores_a_point_above_tolerance():
    # a stiff cubic: many corrector failures and retries; every stored point still converged
    pb = Problem(residual=lambda u, p: 1e3 * (u ** 3 - u) + p,
                 jacobian=lambda u, p: np.diag(1e3 * (3 * u ** 2 - 1)), dresidual_dp=lambda u, p: np.ones(1),
                 residual_scale=1e3)
    br = continuation(pb, [1.2], 0.0, ds=1.0, ds_max=5.0, p_min=-500, p_max=500, max_newton=4)
    for u, p, r in zip(br.u, br.p, br.residual):
        assert abs(pb.residual(u, p)[0]) == pytest.approx(r, abs=1e-12) and r <= br.meta["abs_tol"]


def test_large_steps_do_not_jump_to_a_neighbouring_branch():
    # two disjoint branches u = sin p and u = sin p + 0.05; big steps must stay on the first one
    gap = 0.05
    pb = Problem(residual=lambda u, p: (u - np.sin(p)) * (u - np.sin(p) - gap),
                 jacobian=lambda u, p: np.diag(2 * u - 2 * np.sin(p) - gap),
                 dresidual_dp=lambda u, p: -np.cos(p) * (2 * u - 2 * np.sin(p) - gap))
    br = continuation(pb, [0.0], 0.0, ds=0.5, ds_max=2.0, p_max=12.0, max_steps=2000)
    assert br.status == "bound"
    np.testing.assert_allclose(br.u[:, 0], np.sin(br.p), atol=1e-8)


def test_model_supplied_stability_operator_is_used():
    # the Jacobian is the identity, but the model says stability is decided by diag(p - 1, 1)
    pb = Problem(residual=lambda u, p: u - p, jacobian=lambda u, p: np.eye(2),
                 dresidual_dp=lambda u, p: -np.ones(2),
                 stability_operator=lambda u, p: np.diag([p - 1.0, 1.0]))
    br = continuation(pb, [0.0, 0.0], 0.0, ds=0.1, ds_max=0.3, p_max=2.0, stability=True)
    np.testing.assert_array_equal(br.n_negative, (br.p < 1.0).astype(int))
    np.testing.assert_allclose(br.eigenvalues[:, 0], np.minimum(br.p - 1.0, 1.0), atol=1e-14)


def test_fold_of_a_non_symmetric_system():
    # u2 = u1^2 and 2 u2 - u1 + p = 0 give p = u1 - 2 u1^2: a fold at u1 = 1/4, p = 1/8
    pb = Problem(residual=lambda u, p: np.array([u[1] - u[0] ** 2, 2 * u[1] - u[0] + p]),
                 jacobian=lambda u, p: np.array([[-2 * u[0], 1.0], [-1.0, 2.0]]),
                 dresidual_dp=lambda u, p: np.array([0.0, 1.0]))
    br = continuation(pb, [0.0, 0.0], 0.0, ds=0.05, ds_max=0.1, p_min=-0.5, max_steps=200)
    (fold,) = br.folds()
    assert fold.located and fold.info["method"] == "minimally augmented Newton"
    assert fold.p == pytest.approx(0.125, rel=1e-12)
    assert fold.u[0] == pytest.approx(0.25, rel=1e-6)


def test_several_labelled_stability_operators(tmp_path):
    # one branch, two notions of stability (as a structure under force and under displacement control)
    from contin import Branch

    pb = Problem(residual=lambda u, p: u - p, jacobian=lambda u, p: np.eye(2),
                 dresidual_dp=lambda u, p: -np.ones(2),
                 stability_operators={"force": lambda u, p: np.diag([p - 1.0, 1.0]),
                                      "displacement": lambda u, p: np.diag([2.0 - p, 3.0])})
    br = continuation(pb, [0.0, 0.0], 0.0, ds=0.1, ds_max=0.3, p_max=3.0, stability=True)
    np.testing.assert_array_equal(br.n_negative, (br.p < 1.0).astype(int))  # primary = first label
    np.testing.assert_array_equal(br.stable_under("force"), br.p >= 1.0)
    np.testing.assert_array_equal(br.stable_under("displacement"), br.p <= 2.0)
    back = Branch.load(br.save(tmp_path / "b.npz"))
    assert list(back.stability_by) == ["force", "displacement"]
    for label in back.stability_by:
        for a, b in zip(back.stability_by[label], br.stability_by[label]):
            np.testing.assert_array_equal(a, b)


def bend_problem(width: float = 1e-9, slope: float = 3.0) -> Problem:
    """u = slope * width * log(1 + exp(p / width)): a path that turns from u = 0 onto u = slope * p over a
    length ``width`` of p, without a fold (the Jacobian is 1 everywhere)."""
    def sigmoid(x):
        return 0.5 * (1.0 + np.tanh(0.5 * x))

    return Problem(residual=lambda u, p: u - slope * width * np.logaddexp(0.0, p / width),
                   jacobian=lambda u, p: np.eye(u.size),
                   dresidual_dp=lambda u, p: -slope * sigmoid(p / width) * np.ones_like(u), name="bend")


def test_a_bend_sharper_than_the_smallest_step_is_crossed_at_a_fixed_parameter():
    """Every arclength step into the bend lands farther from its predictor than the step is long, down to
    ds_min; away from a fold the path is a graph over p, and Newton at a fixed p beyond the bend finds it."""
    br = continuation(bend_problem(), [0.0], -1.0, ds=0.05, ds_max=0.1, ds_min=1e-6, p_max=1.0, max_steps=500)
    assert br.status == "bound" and br.p[-1] == pytest.approx(1.0)
    np.testing.assert_allclose(br.u[:, 0], 3e-9 * np.logaddexp(0.0, br.p / 1e-9), rtol=1e-9, atol=1e-12)
    assert not br.folds() and np.all(np.diff(br.p) > 0)
    assert len(br.meta["bridged"]) == 1 and abs(br.meta["bridged"][0]) < 1e-5 and "crossed 1 bend" in br.message
    # near a fold the path is no graph over p: there the bridge is not tried, and the step still collapses
    pb = Problem(residual=lambda u, p: u ** 3 - u + p, jacobian=lambda u, p: np.diag(3 * u ** 2 - 1),
                 dresidual_dp=lambda u, p: np.ones_like(u))
    br = continuation(pb, [-1.2], -0.5, ds=0.05, ds_max=0.1, p_max=0.6, tol=1e-9, stop_at=("fold",))
    assert br.status == "event" and len(br.folds()) == 1
