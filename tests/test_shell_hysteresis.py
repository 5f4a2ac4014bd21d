"""Hysteresis of the point-loaded shell (issue acceptance point 6, figure 4 of the paper).

Quasi-static loading and unloading sweeps (``contin.quasistatic``) are checked against an
independent trace of the whole connected displacement-controlled path (``contin.continuation``
from the reference state to past eversion, as the shell scene does): the snaps must happen at the
path's folds in w (displacement control) or at its extrema of F (force control), and every landing
must be a state of the stretch of that path it is claimed to be on (Newton from the path,
interpolated at the landing's w, converges to the landing).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import contin
from contin.palc import Curve
from contin_models.shell.problem import ShellPointLoad

N = 40
R = 1.0


def eversion(phi_hat: float) -> float:
    return 2.0 * R * (1.0 - math.sin(phi_hat))


def settings(problem: ShellPointLoad) -> contin.Settings:
    """The shell scene's continuation settings (lengths in units of R, F in units of 20 pi D / R)."""
    cap = eversion(problem.phi_hat) / 20
    ds, ds_max = min(0.02, cap), min(0.1, cap)
    pw = 1.0 / R if problem.control == "displacement" else 1.0 / (10.0 * 2.0 * math.pi * problem.D / R)
    return contin.Settings(ds=ds, ds_max=ds_max, ds_min=1e-9 * ds, state_weight=1.0 / R, param_weight=pw,
                           max_steps=3000)


def full_path(phi_hat: float) -> tuple[ShellPointLoad, contin.Branch]:
    """The whole connected displacement-controlled path to 5 % past eversion, with F extrema located."""
    pr = ShellPointLoad(R=R, phi_hat=phi_hat, N=N)
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, settings(pr), p_max=1.05 * eversion(phi_hat),
                             events=[contin.extremum("F", "max"), contin.extremum("F", "min")])
    assert br.status == "bound"
    return pr, br


def state_on_stretch(problem: ShellPointLoad, path: contin.Branch, lo: int, hi: int, w: float) -> np.ndarray:
    """The equilibrium at ``w`` on the stretch ``path[lo..hi]`` (monotone in w): Newton from the interpolant."""
    ws = path.p[lo:hi + 1]
    k = next(i for i in range(len(ws) - 1) if (ws[i] - w) * (ws[i + 1] - w) <= 0)
    t = (w - ws[k]) / (ws[k + 1] - ws[k])
    u = (1 - t) * path.u[lo + k] + t * path.u[lo + k + 1]
    u, _, _ = Curve(problem, settings(problem)).newton_fixed_p(u, w)
    return u


def w_folds(path: contin.Branch) -> list[contin.SpecialPoint]:
    return path.folds()


def F_extrema(path: contin.Branch, which: str) -> list[contin.SpecialPoint]:
    return path.events(f"{which}(F)")


def loop_integral(*sweeps: contin.QuasiStaticResult) -> float:
    """``sum of the integral of F dw`` over the sweeps (trapezoid rule on the stored points)."""
    return float(sum(np.trapezoid(s.observable("F"), s.observable("w")) for s in sweeps))


# ---------------------------------------------------------------------------------------------------
# fixtures (module scope: each trace is shared by the tests that read it)
# ---------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def path08() -> tuple[ShellPointLoad, contin.Branch]:
    return full_path(0.8)


@pytest.fixture(scope="module")
def path12() -> tuple[ShellPointLoad, contin.Branch]:
    return full_path(1.2)


@pytest.fixture(scope="module")
def disp08() -> tuple[contin.QuasiStaticResult, contin.QuasiStaticResult]:
    pr = ShellPointLoad(R=R, phi_hat=0.8, N=N)
    w_end = 1.05 * eversion(0.8)
    load = contin.quasistatic(pr, pr.reference_unknowns(), 0.0, w_end, settings(pr))
    unload = contin.quasistatic(pr, load.u_final, load.p_final, 0.0, settings(pr))
    return load, unload


# ---------------------------------------------------------------------------------------------------
# displacement control (the paper's figure 4)
# ---------------------------------------------------------------------------------------------------
def test_phi_0_8_loading_snaps_at_the_first_fold_in_w_onto_the_everted_branch(path08, disp08) -> None:
    pr, path = path08
    load, _ = disp08
    assert load.status == "completed", load.message
    assert len(load.jumps) == 1
    first_fold = w_folds(path)[0]
    assert first_fold.located
    # the snap is at the first fold in w of the connected path (both located to solver tolerance)
    assert load.jump_parameters[0] == pytest.approx(first_fold.p, rel=1e-8, abs=0)
    (jr,) = load.jumps
    assert jr.info["restated"] and jr.p == load.jump_parameters[0]
    assert 0 < jr.info["p_minimised"] - first_fold.p < 1e-5 * R
    # the landing lies on the everted branch: the stretch after the path's last fold in w
    last_fold = w_folds(path)[-1]
    assert last_fold.p < jr.p  # that stretch reaches back below the snap displacement
    u_ref = state_on_stretch(pr, path, last_fold.index + 1, len(path) - 1, jr.p)
    np.testing.assert_allclose(jr.u_to, u_ref, atol=1e-7 * R)
    F_from, F_to = (pr.evaluate_observables(u, jr.p)["F"] for u in (jr.u_from, jr.u_to))
    assert F_to < F_from  # the everted branch carries a lower (pulling) force at the same w
    # the sweep reached eversion on that branch and was stable all the way
    assert load.p_final == pytest.approx(1.05 * eversion(0.8), rel=1e-12)
    for br in load.branches:
        assert np.all(br.stability_by["displacement"][0][:-1] == 0)


def test_phi_0_8_unloading_snaps_back_at_the_everted_branch_own_fold(path08, disp08) -> None:
    pr, path = path08
    load, unload = disp08
    assert unload.status == "completed", unload.message
    assert len(unload.jumps) == 1
    folds = w_folds(path)
    # the everted branch's own fold is the path's last fold in w (after it the path runs to eversion)
    assert unload.jump_parameters[0] == pytest.approx(folds[-1].p, rel=1e-8, abs=0)
    assert unload.jump_parameters[0] < load.jump_parameters[0]
    (jr,) = unload.jumps
    assert jr.info["restated"] and jr.p == unload.jump_parameters[0]
    assert 0 < folds[-1].p - jr.info["p_minimised"] < 1e-5 * R
    # it lands on the unbuckled branch: the stretch from the reference state to the first fold
    u_ref = state_on_stretch(pr, path, 0, folds[0].index, jr.p)
    np.testing.assert_allclose(jr.u_to, u_ref, atol=1e-7 * R)
    # and unloading ends in the stress-free reference state
    assert unload.p_final == 0.0 or unload.p_final == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(unload.u_final, pr.reference_unknowns(), atol=1e-8 * R)


def test_phi_0_8_loop_has_positive_area_equal_to_the_energy_released(disp08) -> None:
    load, unload = disp08
    area = loop_integral(load, unload)
    F = np.concatenate([load.observable("F"), unload.observable("F")])
    # "clearly positive": a sizeable fraction of the box spanned by the loop
    assert area > 0.05 * (F.max() - F.min()) * (load.jump_parameters[0] - unload.jump_parameters[0])
    # the work done around a closed cycle is the elastic energy released by the snaps
    released = sum(jr.energy_from - jr.energy_to for jr in load.jumps + unload.jumps)
    assert area == pytest.approx(released, rel=2e-2)
    G = contin.diagram(load.branches + unload.branches, load.jumps + unload.jumps)
    cycles = contin.hysteresis_cycles(G)
    assert len(cycles) == 1


def test_phi_1_2_loading_and_unloading_coincide(path12) -> None:
    pr, path = path12
    assert path.folds() == []  # the path is single-valued in w: no snap under displacement control
    w_end = 1.05 * eversion(1.2)
    marks = [contin.crossing("w", f * w_end, name=f"w{k}") for k, f in enumerate(np.linspace(0.1, 0.9, 9))]
    load = contin.quasistatic(pr, pr.reference_unknowns(), 0.0, w_end, settings(pr), events=marks)
    unload = contin.quasistatic(pr, load.u_final, w_end, 0.0, settings(pr), events=marks)
    assert load.status == unload.status == "completed"
    assert load.jumps == [] and unload.jumps == []
    # at the same nine displacements (located exactly) the loading and unloading states agree
    at_load = {s.label: s for s in load.branches[0].events()}
    at_unload = {s.label: s for s in unload.branches[0].events()}
    assert set(at_load) == set(at_unload) == {ev.name for ev in marks}
    F_scale = float(np.max(np.abs(load.observable("F"))))
    for name, a in at_load.items():
        b = at_unload[name]
        assert a.p == pytest.approx(b.p, abs=1e-12 * R)
        assert a.observables["F"] == pytest.approx(b.observables["F"], abs=1e-7 * F_scale)
        np.testing.assert_allclose(a.u, b.u, atol=1e-8 * R)
    np.testing.assert_allclose(unload.u_final, pr.reference_unknowns(), atol=1e-8 * R)
    assert abs(loop_integral(load, unload)) < 1e-3 * F_scale * w_end


# ---------------------------------------------------------------------------------------------------
# force control: the loop jumps at the force limit points
# ---------------------------------------------------------------------------------------------------
def _force_state_on_path(pr_d: ShellPointLoad, path: contin.Branch, lo: int, hi: int, pr_f: ShellPointLoad,
                         u_f: np.ndarray, F: float) -> tuple[float, np.ndarray, np.ndarray]:
    """``(w, displacement unknowns of u_f, path state at that w on path[lo..hi])``."""
    w = pr_f.evaluate_observables(u_f, F)["w"]
    u_d = pr_d.unknowns(pr_f.full_state(u_f, F))
    return w, u_d, state_on_stretch(pr_d, path, lo, hi, w)


def test_phi_1_2_force_control_loop_jumps_at_the_force_limit_points(path12) -> None:
    pr_d, path = path12
    (fmax,), (fmin,) = F_extrema(path, "max"), F_extrema(path, "min")
    F_max, F_min = fmax.info["extremum_value"], fmin.info["extremum_value"]
    assert 0 < F_min < F_max  # monostable
    pr = ShellPointLoad(R=R, phi_hat=1.2, N=N, control="force")
    F_end = 1.5 * F_max
    load = contin.quasistatic(pr, pr.reference_unknowns(), 0.0, F_end, settings(pr))
    unload = contin.quasistatic(pr, load.u_final, F_end, 0.0, settings(pr))
    assert load.status == unload.status == "completed", (load.message, unload.message)
    assert len(load.jumps) == len(unload.jumps) == 1
    assert load.jump_parameters[0] == pytest.approx(F_max, rel=1e-6, abs=0)
    assert unload.jump_parameters[0] == pytest.approx(F_min, rel=1e-6, abs=0)
    # loading lands beyond the force minimum, unloading lands before the force maximum
    jr = load.jumps[0]
    w, u_d, u_ref = _force_state_on_path(pr_d, path, fmin.index + 1, len(path) - 1, pr, jr.u_to, jr.p)
    assert w > fmin.observables["w"]
    np.testing.assert_allclose(u_d, u_ref, atol=1e-7 * R)
    jr = unload.jumps[0]
    w, u_d, u_ref = _force_state_on_path(pr_d, path, 0, fmax.index, pr, jr.u_to, jr.p)
    assert 0 < w < fmax.observables["w"]
    np.testing.assert_allclose(u_d, u_ref, atol=1e-7 * R)
    np.testing.assert_allclose(unload.u_final, pr.reference_unknowns(), atol=1e-8 * R)
    assert len(contin.hysteresis_cycles(contin.diagram(load.branches + unload.branches,
                                                       load.jumps + unload.jumps))) == 1
    # the loop integral of w dF is the energy released by the two snaps (dPi/dF = -w at equilibrium)
    loop = sum(np.trapezoid(s.observable("w"), s.p) for s in (load, unload))
    released = sum(j.energy_from - j.energy_to for j in load.jumps + unload.jumps)
    assert -loop == pytest.approx(released, rel=1e-2)


def test_phi_0_8_force_control_snaps_at_F_max_and_back_only_when_pulled_past_F_min(path08) -> None:
    pr_d, path = path08
    F_max = F_extrema(path, "max")[0].info["extremum_value"]   # the first local maximum: the snap load
    last_min = F_extrema(path, "min")[-1]                        # the everted branch's force minimum
    F_min = last_min.info["extremum_value"]
    assert F_min < 0 < F_max  # bistable: the everted state needs a pull to snap back
    pr = ShellPointLoad(R=R, phi_hat=0.8, N=N, control="force")
    F_end = 1.2 * F_max
    load = contin.quasistatic(pr, pr.reference_unknowns(), 0.0, F_end, settings(pr))
    assert load.status == "completed" and len(load.jumps) == 1, load.message
    assert load.jump_parameters[0] == pytest.approx(F_max, rel=1e-6, abs=0)
    jr = load.jumps[0]
    w, u_d, u_ref = _force_state_on_path(pr_d, path, last_min.index + 1, len(path) - 1, pr, jr.u_to, jr.p)
    assert w > last_min.observables["w"]
    np.testing.assert_allclose(u_d, u_ref, atol=1e-7 * R)
    # unloading to F = 0 does not snap back: the everted state is stable without load
    unload = contin.quasistatic(pr, load.u_final, F_end, 0.0, settings(pr))
    assert unload.status == "completed" and unload.jumps == []
    w0, u_d, u_ref = _force_state_on_path(pr_d, path, last_min.index + 1, len(path) - 1, pr, unload.u_final, 0.0)
    np.testing.assert_allclose(u_d, u_ref, atol=1e-7 * R)
    assert w0 > last_min.observables["w"] > 0
    # pulling past the everted branch's force minimum snaps it back, to the pulled-up unbuckled cap
    pull = contin.quasistatic(pr, unload.u_final, 0.0, 1.2 * F_min, settings(pr))
    assert pull.status == "completed" and len(pull.jumps) == 1, pull.message
    assert pull.jump_parameters[0] == pytest.approx(F_min, rel=1e-6, abs=0)
    landing_w = pr.evaluate_observables(pull.jumps[0].u_to, pull.jumps[0].p)["w"]
    assert landing_w < 0
