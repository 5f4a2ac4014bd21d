"""Step limits that follow the path: ``Settings.stall_steps`` and the shell scene's ``continuation.max_steps = "auto"``."""

import numpy as np
import pytest

import contin
from contin.app.scene import SceneError, load_scene
from contin_models.shell_scene import SHELL_SCHEMA
from contin_models.shell_scene.build import point_problem, point_settings


def line() -> contin.Problem:
    """u - p = 0: a straight path with no feature, unbounded both ways."""
    return contin.Problem(residual=lambda u, p: u - p, jacobian=lambda u, p: np.eye(u.size),
                          dresidual_dp=lambda u, p: -np.ones_like(u), name="line")


def decaying_wave() -> contin.Problem:
    """2 exp(-u/20) sin(u) + u/20 - p = 0: a path that folds every half period while its first crest,
    p ~ 1.9, stays the largest p it reaches until u ~ 38 (many folds later)."""
    def residual(u, p):
        return 2.0 * np.exp(-u / 20.0) * np.sin(u) + u / 20.0 - p

    def jacobian(u, p):
        return np.diag(2.0 * np.exp(-u / 20.0) * (np.cos(u) - np.sin(u) / 20.0) + 1.0 / 20.0)

    return contin.Problem(residual=residual, jacobian=jacobian, dresidual_dp=lambda u, p: -np.ones_like(u),
                          name="decaying wave")


KW = {"ds": 0.1, "ds_max": 0.1, "state_weight": 1.0, "param_weight": 1.0, "check_model": False}


def test_a_path_running_away_from_its_only_bound_stalls():
    """Going down from p = 0 with p_max = 1 the only bound: nothing is found and the bound recedes."""
    br = contin.continuation(line(), [0.0], 0.0, p_max=1.0, direction=-1, max_steps=1000, stall_steps=40, **KW)
    assert br.status == "stalled" and not br.success
    assert len(br.p) == 41  # the start and the 40 steps without progress
    assert "40 steps without progress" in br.message and "p_max" in br.message


def test_the_same_path_with_an_explicit_limit_alone_obeys_it():
    br = contin.continuation(line(), [0.0], 0.0, p_max=1.0, direction=-1, max_steps=60, **KW)
    assert br.status == "max_steps" and len(br.p) == 61


def test_a_winding_path_that_keeps_folding_is_not_stalled():
    """The parameter's record stands for longer than ``stall_steps``, but the folds on the way count as progress."""
    stall = 60
    br = contin.continuation(decaying_wave(), [0.0], 0.0, p_max=2.5, max_steps=5000, stall_steps=stall, **KW)
    assert br.status == "bound" and br.p[-1] == pytest.approx(2.5)
    record = np.maximum.accumulate(br.p)
    news = np.flatnonzero(np.diff(record) > 0) + 1
    assert np.diff(news).max() > 3 * stall  # judged by the parameter alone, the path would have stalled
    assert len(br.folds()) >= 10


def test_stall_steps_is_validated():
    with pytest.raises(contin.SettingsError, match="stall_steps"):
        contin.Settings(stall_steps=-1).validate()


def test_the_shell_scene_limit_is_automatic_unless_a_number_is_given():
    auto = load_scene(SHELL_SCHEMA, None, [])
    assert auto["continuation"]["max_steps"] == "auto"
    st = point_settings(auto, point_problem(auto, "displacement"))
    assert st.stall_steps > 0 and st.max_steps > 10 * st.stall_steps
    fixed = load_scene(SHELL_SCHEMA, None, ["continuation.max_steps=5000"])
    st = point_settings(fixed, point_problem(fixed, "displacement"))
    assert (st.max_steps, st.stall_steps) == (5000, 0)
    with pytest.raises(SceneError, match='an integer in \\[1, 1000000\\] or "auto"'):
        load_scene(SHELL_SCHEMA, None, ["continuation.max_steps=many"])


def test_a_run_cut_short_by_the_automatic_limit_asks_for_a_number() -> None:
    from types import SimpleNamespace

    from contin.app.cli import _status_message

    model = SimpleNamespace(schema=SimpleNamespace(sections={"continuation": {"max_steps": None}}))
    result = SimpleNamespace(message="path: reached max_steps = 200000", complete=False)
    auto = _status_message(model, {"continuation": {"max_steps": "auto"}}, result)
    assert "give a number of steps above the automatic limit" in auto and "(now auto)" not in auto
    fixed = _status_message(model, {"continuation": {"max_steps": 3000}}, result)
    assert fixed.endswith("raise continuation.max_steps (now 3000)")


def turn_and_climb() -> contin.Problem:
    """p = sin(u) up to u = 3 pi / 2, then p = -1 + ((u - 3 pi / 2) / 20)^2 / 2: a path that comes up to p = 1,
    turns back at a fold to p = -1 and then climbs slowly, without another fold, past its first crest."""
    turn = 1.5 * np.pi

    def f(u):
        return np.where(u <= turn, np.sin(u), -1.0 + 0.5 * ((u - turn) / 20.0) ** 2)

    def df(u):
        return np.where(u <= turn, np.cos(u), (u - turn) / 400.0)

    return contin.Problem(residual=lambda u, p: f(u) - p, jacobian=lambda u, p: np.diag(df(u)),
                          dresidual_dp=lambda u, p: -np.ones_like(u), name="turn and climb")


def test_a_path_climbing_back_towards_its_bound_after_a_fold_is_not_stalled():
    """After the fold at p = -1 the path needs hundreds of steps to pass its first crest, p = 1, the closest it
    had come to p_max: every step nearer the bound since the fold is progress."""
    stall = 40
    br = contin.continuation(turn_and_climb(), [0.0], 0.0, p_max=1.5, max_steps=5000, stall_steps=stall, **KW)
    assert br.status == "bound" and br.p[-1] == pytest.approx(1.5)
    assert len(br.folds()) == 2
    record = np.maximum.accumulate(br.p)
    news = np.flatnonzero(np.diff(record) > 0) + 1
    assert np.diff(news).max() > 3 * stall  # judged by the closest approach since the start, it would have stalled
