"""studies/waves_branch.py: the n-wave branches of clamped caps against the axisymmetric trace and Koiter's b."""

import numpy as np
import pytest

import contin
from contin.numerics.stability import stability_info
from studies import waves_branch as wv

N = 40          # coarse meridian: the checks compare two computations on the same mesh
LAM = 12.0


@pytest.fixture(scope="module")
def apex():
    """The lambda = 12 cap (R/t = 1000) under the apex load to its first bifurcation, and the lifted point."""
    pr = wv.point_cap(LAM, N)
    path = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(
        ds=0.05, ds_max=0.25, max_steps=2000, stability=True, stop_at=("bifurcation",)), p_max=wv.W_END)
    point = wv.first_bifurcation(path)
    waves = wv.follow_waves(pr, point, 2, every_mode=True, settings=contin.Settings(ds=0.02, ds_max=0.1,
                            stability=True), max_steps=25)
    return pr, path, point, waves


def test_the_first_bifurcation_is_where_the_block_of_its_waves_goes_indefinite(apex) -> None:
    pr, path, point, _ = apex
    n = int(point.info["key"])
    assert n == 4
    # the stored points on either side: every block definite before, block n alone indefinite after
    before = path.u[-2], path.p[-2]
    step = contin.continuation(pr, path.u[-2], path.p[-2], contin.Settings(ds=0.05, ds_max=0.05),
                               p_max=point.p + 0.05)
    after = step.u[-1], step.p[-1]
    for k in range(1, pr.harmonics + 1):
        assert stability_info(pr.harmonic_block(k, *before), 0).n_negative == 0
        assert stability_info(pr.harmonic_block(k, *after), 0).n_negative == (1 if k == n else 0)


def test_the_n_wave_branch_starts_at_the_bifurcation_and_leaves_in_its_waves(apex) -> None:
    _, _, point, waves = apex
    assert waves.branch_point.p == pytest.approx(point.p, rel=1e-9)
    prob, branch = waves.problem, waves.branch
    assert prob.basis.n == 4 and 0.0 < branch.p[0] - point.p < 0.02     # the first step off it
    amplitude = [np.max(np.abs(prob.full_state(u, p)[prob.view.dofs_of_wave(4)])) for u, p in zip(branch.u, branch.p)]
    assert amplitude[-1] > 10 * amplitude[1] > 0.0
    assert np.all(np.diff(branch.p) > 0)                               # the deflection grows along it


def test_koiters_b_is_the_traced_branchs_curvature(apex) -> None:
    # b from differences of the Hessian at the branch point against the intercept of (p/p_c - 1)/xi^2 on
    # points of the branch traced again: two independent readings of the same coefficient.  The traced
    # one carries the fit's O(xi^4) remainder (the points reach xi ~ 0.1, where b_abs xi^2 is ~ 1e-3 of
    # p_c), the differenced one the Richardson remainder of its step; both below 1e-4 relative here, so
    # 1e-3 leaves room for the machine without admitting a wrong second-order field (K = 1, which has none
    # of the waves 2n, gives a b_w ten times larger).
    _, _, _, waves = apex
    k = wv.koiter_check(waves, ds=0.02)
    assert k["symmetric"] and k["a"] == 0.0
    assert k["b_traced"] == pytest.approx(k["b_koiter"], rel=1e-3)
    # the engine's default step, a fraction of the problem's difference scale (the thickness here, where the
    # unknowns are coordinates of size R = 1000 t), gives it too
    assert k["b_traced"] == pytest.approx(k["b_koiter_default_step"], rel=1e-3)
    assert k["b_w_koiter"] > 0      # the deflection rises along the branch on both of its halves


def test_rotation_of_the_pattern_is_left_out_of_the_a2_count(apex) -> None:
    # turning the four-wave pattern about the axis costs no energy: one eigenvalue of the A2 block is zero up to
    # the quadrature, of either sign; the view's A2 count leaves it out, so the branch near its start is stable
    _, _, _, waves = apex
    engine = waves.branch.meta["modes"]["representation"]
    a2 = np.asarray(engine["n_negative"])[:, list(engine["keys"]).index("A2")]
    assert np.all(a2[1:6] == 0)
    counts = wv.morse_counts(waves, 3)
    assert counts["total"] == 0 and counts["A2"] == 0


@pytest.mark.slow
def test_huangs_cap_falls_off_its_bifurcation() -> None:
    pc = wv.pressure_case(40, 2)
    assert pc["n"] == 4
    assert pc["koiter"]["b_koiter"] < 0 and pc["koiter"]["b_traced"] == pytest.approx(pc["koiter"]["b_koiter"],
                                                                                     rel=1e-3)
    p = pc["_waves"].branch.p
    assert p[0] < pc["p_bif"] and p[1] < p[0] and pc["p_min"] < 0.97 * pc["p_bif"]
    assert pc["counts"][2]["A1"] == 1     # unstable in its own class under pressure control


def test_first_pass_and_extrema() -> None:
    w = np.array([0.0, 1.0, 2.0, 1.5, 2.5])
    y = np.array([0.0, 10.0, 20.0, 15.0, 25.0])
    assert wv.first_pass(w, y, 1.75) == (17.5, 1)
    assert wv.first_pass(w, y, 3.0) is None
    assert wv.extrema(w) == [2, 3]
