"""Quasi-static sweeps (``contin.quasistatic``) on the von Mises truss, checked against the closed form.

Two bars of stiffness k from ``(-a, 0)`` and ``(a, 0)`` to the apex ``(0, y)``; a downward dead load P.
On the symmetric path ``P(y) = 2 k y (L0 / L - 1)``, ``L = sqrt(a^2 + y^2)``, with limit points where
``L^3 = L0 a^2``: ``P_max`` at ``y*`` and ``-P_max`` at ``-y*``.  Every reference value below is
computed here from these formulas (roots of ``P(y) = P`` by bracketing on the closed form), never
taken from the code under test.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.optimize import brentq

from contin import JumpError, Problem, QuasiStaticResult, diagram, hysteresis_cycles, quasistatic
from contin.analyses.quasistatic import SnapRules
from contin_models.benchmarks.truss import TrussDisplacementControl, VonMisesTruss

A, B, K = 1.0, 0.5, 1.0
L0 = math.hypot(A, B)
KW = dict(ds=0.02, ds_max=0.05)
#: the engine locates a fold's parameter to p_tol = 1e-10 (absolute for |p| < 1, see contin.locate_fold)
FOLD_TOL = 1e-10


def limit_point() -> tuple[float, float]:
    """``(y*, P_max)`` from ``L*^3 = L0 a^2``."""
    L = (L0 * A * A) ** (1 / 3)
    y = math.sqrt(L * L - A * A)
    return y, 2 * K * y * (L0 / L - 1)


Y_STAR, P_MAX = limit_point()


def P_of_y(y: np.ndarray | float) -> np.ndarray | float:
    return 2 * K * np.asarray(y) * (L0 / np.sqrt(A * A + np.asarray(y) ** 2) - 1)


def energy(y: float, P: float) -> float:
    """Total potential of the symmetric state ``(0, y)``: two bars plus the dead load."""
    return K * (math.hypot(A, y) - L0) ** 2 + P * y


def y_upper(P: float) -> float:
    """The state on the upper stable branch (``y > y*``) at load P (``P < P_max``)."""
    return brentq(lambda y: P_of_y(y) - P, Y_STAR + 1e-12, 50.0, xtol=1e-15)


def y_lower(P: float) -> float:
    """The state on the inverted stable branch (``y < -y*``) at load P (``P > -P_max``)."""
    return brentq(lambda y: P_of_y(y) - P, -50.0, -Y_STAR - 1e-12, xtol=1e-15)


def assert_on_closed_form(res: QuasiStaticResult) -> None:
    for br in res.branches:
        np.testing.assert_allclose(br.u[:, 0], 0.0, atol=1e-10)
        np.testing.assert_allclose(br.p, P_of_y(br.u[:, 1]), atol=1e-10)
        assert np.all(br.n_negative[:-1] == 0)  # all stable (the last point may be the fold)


@pytest.fixture(scope="module")
def loading() -> QuasiStaticResult:
    return quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 1.5 * P_MAX, **KW)


@pytest.fixture(scope="module")
def unloading(loading: QuasiStaticResult) -> QuasiStaticResult:
    return quasistatic(VonMisesTruss(A, B, K), loading.u_final, loading.p_final, -1.5 * P_MAX, **KW)


def test_loading_snaps_at_the_limit_load_onto_the_inverted_branch(loading: QuasiStaticResult) -> None:
    res = loading
    assert res.status == "completed" and res.success and "reached P" in res.message
    assert res.direction == 1 and len(res.branches) == 2 and len(res.jumps) == 1
    (jr,) = res.jumps
    assert res.jump_parameters[0] == pytest.approx(P_MAX, rel=0, abs=FOLD_TOL)
    assert res.folds[0].observables["y"] == pytest.approx(Y_STAR, rel=1e-6)
    # minimised a tiny overshoot past the fold, stated at the fold load
    assert 0 < jr.info["p_minimised"] - P_MAX <= 1e-5 * P_MAX
    assert jr.info["restated"] and jr.p == res.jump_parameters[0] == res.branches[0].p[-1]
    assert jr.success and jr.energy_to < jr.energy_from
    np.testing.assert_array_equal(jr.u_from, res.branches[0].u[-1])
    assert jr.u_to[1] == pytest.approx(y_lower(P_MAX), abs=1e-9) and jr.u_to[0] == pytest.approx(0.0, abs=1e-9)
    assert jr.energy_from - jr.energy_to == pytest.approx(energy(Y_STAR, P_MAX) - energy(y_lower(P_MAX), P_MAX),
                                                          rel=1e-7)
    # the resumed branch starts at the landing and is recorded as coming from the jump
    landing = res.branches[1].special_points[0]
    assert landing.kind == "jump" and landing.label == "jump_to" and landing.p == jr.p
    assert_on_closed_form(res)
    assert res.p_final == pytest.approx(1.5 * P_MAX, rel=1e-12)
    assert res.u_final[1] == pytest.approx(y_lower(1.5 * P_MAX), abs=1e-9)
    # the sweep is monotone in the load
    assert np.all(np.diff(res.p) >= 0) and np.count_nonzero(np.diff(res.p) == 0) == 1  # the snap


def test_unloading_snaps_back_at_the_other_limit_point(unloading: QuasiStaticResult) -> None:
    res = unloading
    assert res.status == "completed" and res.direction == -1 and len(res.jumps) == 1
    (jr,) = res.jumps
    assert res.jump_parameters[0] == pytest.approx(-P_MAX, rel=0, abs=FOLD_TOL)
    assert res.folds[0].observables["y"] == pytest.approx(-Y_STAR, rel=1e-6)
    assert 0 < -P_MAX - jr.info["p_minimised"] <= 1e-5 * P_MAX
    assert jr.p == res.jump_parameters[0]
    assert jr.u_to[1] == pytest.approx(y_upper(-P_MAX), abs=1e-9)
    assert_on_closed_form(res)
    assert res.u_final[1] == pytest.approx(y_upper(-1.5 * P_MAX), abs=1e-9)
    assert np.all(np.diff(res.p) <= 0) and np.count_nonzero(np.diff(res.p) == 0) == 1


def test_loading_and_unloading_form_a_hysteresis_cycle() -> None:
    # pull first (no snap on the upper branch), then load and unload between the same two loads
    truss = VonMisesTruss(A, B, K)
    p_lo, p_hi = -1.5 * P_MAX, 1.5 * P_MAX
    fine = dict(ds=0.002, ds_max=0.005)  # small steps: the loop integral below is a trapezoid rule
    pre = quasistatic(truss, [0.0, B], 0.0, p_lo, **fine)
    assert pre.status == "completed" and pre.jumps == []
    load = quasistatic(truss, pre.u_final, p_lo, p_hi, **fine)
    unload = quasistatic(truss, load.u_final, p_hi, p_lo, **fine)
    assert [len(load.jumps), len(unload.jumps)] == [1, 1]
    G = diagram(load.branches + unload.branches, load.jumps + unload.jumps)
    cycles = hysteresis_cycles(G)
    assert len(cycles) == 1
    cyc = cycles[0]
    pairs = list(zip(cyc, cyc[1:] + cyc[:1]))
    kinds = [next(iter(G.get_edge_data(a, b).values()))["kind"] for a, b in pairs]
    assert kinds.count("jump") == 2
    ps = sorted(G.nodes[n]["p"] for n in cyc)
    assert ps[0] == pytest.approx(p_lo, rel=1e-12) and ps[-1] == pytest.approx(p_hi, rel=1e-12)
    # the two snaps of the loop are at the two limit loads
    jump_ps = sorted(G.nodes[a]["p"] for (a, _), kind in zip(pairs, kinds) if kind == "jump")
    assert jump_ps == [pytest.approx(-P_MAX, rel=0, abs=FOLD_TOL), pytest.approx(P_MAX, rel=0, abs=FOLD_TOL)]
    assert all(d["stable"] for *_, d in G.edges(data=True) if d["kind"] == "branch")
    # one sweep alone is no loop
    assert hysteresis_cycles(diagram(load.branches, load.jumps)) == []
    # the loop integral of y dP equals the energy released by the two snaps (dPi/dP = y at equilibrium)
    loop = np.trapezoid(load.observable("y"), load.p) + np.trapezoid(unload.observable("y"), unload.p)
    released = (energy(Y_STAR, P_MAX) - energy(y_lower(P_MAX), P_MAX)
                + energy(-Y_STAR, -P_MAX) - energy(y_upper(-P_MAX), -P_MAX))
    assert released > 0
    assert loop == pytest.approx(released, rel=1e-3)


def test_no_snap_before_the_limit_load() -> None:
    res = quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 0.9 * P_MAX, **KW)
    assert res.status == "completed" and res.jumps == [] and len(res.branches) == 1
    assert res.u_final[1] == pytest.approx(y_upper(0.9 * P_MAX), abs=1e-9)


def test_displacement_control_of_the_truss_has_no_snap() -> None:
    # with the apex height prescribed the path is single-valued in y (sway stiffness > 0 for b/a < 2.4)
    dc = TrussDisplacementControl(A, B, K)
    res = quasistatic(dc, [0.0], B, -B, **KW)
    assert res.status == "completed" and res.jumps == []
    y = res.p
    assert y[0] == B and y[-1] == pytest.approx(-B, abs=1e-12)
    np.testing.assert_allclose(res.observable("P"), P_of_y(y), atol=1e-10)


def test_max_snaps_stops_at_the_fold() -> None:
    res = quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 1.5 * P_MAX, max_snaps=0, **KW)
    assert res.status == "max_snaps" and not res.success
    assert "max_snaps = 0" in res.message and res.jumps == [] and len(res.branches) == 1
    assert res.p_final == pytest.approx(P_MAX, rel=0, abs=FOLD_TOL)
    assert res.folds[0].p == pytest.approx(P_MAX, rel=0, abs=FOLD_TOL)


def test_a_failed_snap_says_why() -> None:
    truss = VonMisesTruss(A, B, K)
    # the same equations without an energy: continuation works, the snap cannot
    no_energy = Problem(residual=truss.residual, jacobian=truss.jacobian, dresidual_dp=truss.dresidual_dp,
                        observables=truss.observables, symmetric=True, parameter_name="P")
    res = quasistatic(no_energy, [0.0, B], 0.0, 1.5 * P_MAX, **KW)
    assert res.status == "jump_failed"
    fold_p = float(re.search(r"fold P = ([-+0-9.eE]+)", res.message).group(1))
    assert fold_p == pytest.approx(P_MAX, rel=1e-8) and "conservative" in res.message
    assert res.p_final == pytest.approx(P_MAX, rel=0, abs=FOLD_TOL) and res.jumps == []


def test_a_landing_next_to_the_fold_is_rejected() -> None:
    # a separation threshold larger than the real snap (|dy| ~ 0.87, a few times max|u|): minimised at the
    # fold's own load, a landing cannot be told from a stall next to the fold, so every landing is rejected
    # (a hair past the fold it could: tests/test_landing.py)
    attempts = ((0.0, None), (0.0, 1e-4))
    res = quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 1.5 * P_MAX, min_separation=100.0,
                      jump_attempts=attempts, **KW)
    assert res.status == "jump_failed" and "landed back next to the fold" in res.message
    assert len(res.info["jump_attempts"][0]) == len(attempts)  # every attempt was tried


def test_unstable_start_is_refused() -> None:
    # (0, 0) at P = 0 is an equilibrium (bars compressed flat) with one negative eigenvalue
    res = quasistatic(VonMisesTruss(A, B, K), [0.0, 0.0], 0.0, P_MAX, **KW)
    assert res.status == "unstable_start" and res.branches == [] and "unstable" in res.message


def test_a_continuation_that_stops_early_is_reported() -> None:
    res = quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 1.5 * P_MAX, max_steps=3, **KW)
    assert res.status == "stopped" and "max_steps" in res.message and res.jumps == []


def test_bad_arguments() -> None:
    truss = VonMisesTruss(A, B, K)
    with pytest.raises(ValueError, match="p0 != p_end"):
        quasistatic(truss, [0.0, B], 0.0, 0.0)
    with pytest.raises(TypeError, match="not_an_option"):
        quasistatic(truss, [0.0, B], 0.0, 1.0, not_an_option=1)
    with pytest.raises(ValueError, match="jump_attempts"):
        quasistatic(truss, [0.0, B], 0.0, 1.0, jump_attempts=())


# ---- the hooks the models use (contin.quasistatic is the one load-snap loop) -------------------------
def test_an_open_sweep_ends_on_an_observable_bound_or_after_a_chosen_snap() -> None:
    truss = VonMisesTruss(A, B, K)
    # no end load: the sweep goes up until the apex passes y = -1.2 b (a bound of the settings)
    res = quasistatic(truss, [0.0, B], 0.0, None, direction=1, bounds={"y": (-1.2 * B, None)}, **KW)
    assert res.status == "completed" and res.p_end is None and len(res.jumps) == 1
    assert res.u_final[1] == pytest.approx(-1.2 * B, abs=1e-9)
    assert res.p_final == pytest.approx(P_of_y(-1.2 * B), abs=1e-9)
    # stop_after_jump ends the sweep on the landing
    res = quasistatic(truss, [0.0, B], 0.0, None, direction=1, stop_after_jump=lambda jr: "landed", **KW)
    assert res.status == "completed" and res.message.startswith("landed") and len(res.branches) == 1
    np.testing.assert_array_equal(res.u_final, res.jumps[0].u_to)
    with pytest.raises(ValueError, match="direction"):
        quasistatic(truss, [0.0, B], 0.0, None, **KW)
    with pytest.raises(ValueError, match="direction"):
        quasistatic(truss, [0.0, B], 0.0, 1.0, direction=-1, **KW)


def test_a_snap_that_lands_beyond_a_bound_ends_the_sweep_there() -> None:
    """A continuation run from a landing beyond a bound never crosses it: the sweep would go on outside
    the range the caller allowed (a plate that snaps onto the base ring of a cap under a dead load)."""
    truss = VonMisesTruss(A, B, K)
    y_land = y_lower(P_MAX)
    bound = {"y": (0.5 * y_land, None)}  # the loading branch stays above it; the landing lies below
    res = quasistatic(truss, [0.0, B], 0.0, 1.5 * P_MAX, bounds=bound, **KW)
    assert res.status == "stopped" and not res.failed and len(res.branches) == 1 and len(res.jumps) == 1
    assert "landed on or beyond the bound y >=" in res.message
    np.testing.assert_array_equal(res.u_final, res.jumps[0].u_to)
    assert res.u_final[1] == pytest.approx(y_land, abs=1e-9) and res.p_final == pytest.approx(P_MAX, abs=FOLD_TOL)
    # an open sweep ends there as it ends on a bound reached along a branch: completed
    res = quasistatic(truss, [0.0, B], 0.0, None, direction=1, bounds=bound, **KW)
    assert res.status == "completed" and len(res.branches) == 1 and res.u_final[1] == pytest.approx(y_land, abs=1e-9)


def test_snap_rules_measure_the_overshoot_from_the_fold_and_may_keep_the_jump_there() -> None:
    rules = SnapRules(attempts=((1e-6, None),), overshoot_unit="fold", restate=False,
                      separation=lambda uf, pf, ut, pt: abs(ut[1] - uf[1]) / B, min_separation=0.5)
    res = quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 100 * P_MAX, snap=rules, max_snaps=1,
                      stop_after_jump=lambda jr: "done", **KW)
    (jr,) = res.jumps
    # 1e-6 of the fold load past it, not of the sweep's span (100 P_max)
    assert jr.p == pytest.approx(res.folds[0].p * (1 + 1e-6), rel=1e-14)
    assert jr.info["restated"] is False and jr.info["p_minimised"] == jr.p
    assert jr.u_to[1] == pytest.approx(y_lower(jr.p), abs=1e-9)


def test_attempts_stop_on_an_error_the_rules_give_up_on() -> None:
    class Boom(ValueError):
        pass

    def refuse(uf: np.ndarray, pf: float, ut: np.ndarray, pt: float) -> float:
        raise Boom("no distance here")

    rules = SnapRules(separation=refuse, give_up_on=(Boom,))
    with pytest.raises(Boom):  # an error of the separation hook is the caller's own: not swallowed
        quasistatic(VonMisesTruss(A, B, K), [0.0, B], 0.0, 1.5 * P_MAX, snap=rules, **KW)
    truss = VonMisesTruss(A, B, K)
    # without an energy every attempt fails alike (JumpError); giving up on it tries only the first
    no_energy = Problem(residual=truss.residual, jacobian=truss.jacobian, dresidual_dp=truss.dresidual_dp,
                        observables=truss.observables, symmetric=True, parameter_name="P")
    res = quasistatic(no_energy, [0.0, B], 0.0, 1.5 * P_MAX, snap=SnapRules(give_up_on=(JumpError,)), **KW)
    assert res.status == "jump_failed" and len(res.info["jump_attempts"][0]) == 1


def test_a_model_locates_its_own_snap_past_a_terminal_event() -> None:
    # stop on a precursor event just before the limit load and hand the loop the engine's fold there
    from contin import crossing, locate_fold

    truss = VonMisesTruss(A, B, K)
    near = crossing("y", Y_STAR + 0.02, direction=-1, terminal=True, name="near the fold")

    def snap_at(br):
        return locate_fold(truss, br.u[-1], float(br.p[-1]))

    res = quasistatic(truss, [0.0, B], 0.0, 1.5 * P_MAX, events=[near], locate_snap=snap_at, max_snaps=1,
                      stop_after_jump=lambda jr: "done", **KW)
    assert res.status == "completed" and res.folds[0].p == pytest.approx(P_MAX, abs=1e-9)
    assert res.jumps[0].u_to[1] == pytest.approx(y_lower(P_MAX), abs=1e-9)


def test_failed_tells_the_loop_s_failures_from_a_stopped_run() -> None:
    truss = VonMisesTruss(A, B, K)
    assert quasistatic(truss, [0.0, B], 0.0, 1.5 * P_MAX, max_snaps=0, **KW).failed
    assert not quasistatic(truss, [0.0, B], 0.0, 1.5 * P_MAX, max_steps=3, **KW).failed
    assert not quasistatic(truss, [0.0, B], 0.0, 0.5 * P_MAX, **KW).failed


def test_leave_fold_is_one_snap_of_the_loop(loading: QuasiStaticResult) -> None:
    from contin.analyses.quasistatic import leave_fold

    fold = loading.folds[0]
    jr, reasons = leave_fold(VonMisesTruss(A, B, K), fold, +1, u_fold=loading.branches[0].u[-1], p0=0.0,
                             p_end=1.5 * P_MAX)
    assert reasons == [] and jr.info["restated"] and jr.p == fold.p
    np.testing.assert_allclose(jr.u_to, loading.jumps[0].u_to, atol=1e-12)


def test_a_shallow_arch_snaps_at_its_first_branch_point() -> None:
    """The arch's symmetric path bifurcates (unstably) before its limit load: loading snaps there, at the
    located branch point's load, onto the inverted arch (crown deflection beyond twice the rise)."""
    from contin_models.benchmarks.arch import ShallowArch

    arch = ShallowArch()
    res = quasistatic(arch, np.zeros(2 * (arch.n - 1)), 0.0, 20.0)
    assert res.status == "completed" and len(res.jumps) == 1
    bp = res.folds[0]
    assert bp.kind == "branch_point" and bp.located
    assert res.jumps[0].p == pytest.approx(bp.p, rel=1e-12)
    landing = arch.evaluate_observables(res.jumps[0].u_to, res.jumps[0].p)
    assert landing["deflection"] > 2 * arch.rise and abs(landing["asymmetry"]) < 1e-8


def test_a_supercritical_pitchfork_is_not_a_snap() -> None:
    """Past a supercritical pitchfork the stable path goes on, on the bifurcating branch: no jump."""
    from contin_models.benchmarks.pitchfork import Pitchfork

    res = quasistatic(Pitchfork(), np.zeros(2), -1.0, 1.0)
    assert res.status == "branch_point" and res.jumps == []
    assert "stable bifurcating branch" in res.message and "switch_branch" in res.message


def test_a_point_a_hair_before_its_terminal_fold_may_carry_the_folds_eigenvalue() -> None:
    """Next to a stiff contact the fold's eigenvalue at the stored point before the located fold came out
    -1.4e-6 (0.26 the next one) at an arclength of 1.7e-6 from the fold after a step of 2.1e-4: that point
    is the fold, not an instability the sweep missed.  Farther from the fold, or with a second negative
    eigenvalue, it still ends the sweep."""
    from types import SimpleNamespace

    from contin.analyses.quasistatic import _first_unstable

    fold = SimpleNamespace(kind="fold")
    s_fold = 0.0039725
    at_the_fold = SimpleNamespace(n_negative=[0, 0, 1, 1], s=[0.0036, 0.0037603, s_fold - 1.7e-6, s_fold])
    assert _first_unstable(at_the_fold, fold) is None
    before_it = SimpleNamespace(n_negative=[0, 0, 1, 1], s=[0.0036, 0.0037603, s_fold - 1e-5, s_fold])
    assert _first_unstable(before_it, fold) == 2
    two = SimpleNamespace(n_negative=[0, 0, 2, 1], s=[0.0036, 0.0037603, s_fold - 1.7e-6, s_fold])
    assert _first_unstable(two, fold) == 2
    assert _first_unstable(SimpleNamespace(n_negative=[0, 0, 1], s=[0.0, 1.0, 2.0]), None) == 2
