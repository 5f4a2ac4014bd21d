"""Leaving a D_n branch where it breaks its symmetry: the bifurcation lifted into its isotropy subgroup's basis,
re-located there and followed; and a snap from the D_n branch's fold with no symmetry imposed."""

import math

import numpy as np
import pytest

import contin
from contin import LiftError
from contin_models.shell.fourier import AngularBasis, transfer_coefficients
from contin_models.shell.lift import (breaking, follow_symmetry_breaking, jump_in_full_space, state_symmetry,
                                      subgroup_basis, subgroup_lift)
from contin_models.shell.problem3d import Shell3D
from studies.shell3d_convergence import SWITCH_DS, paper_cap

N, K = 30, 2
SETTINGS = contin.Settings(ds=SWITCH_DS, ds_max=0.02)


@pytest.mark.parametrize("n, representation, symmetry, sub_n, mirror, K_min, turn", [
    (3, "A2", "C3", 3, False, 2, 0.0),
    (3, "E1", "D1", 1, True, 7, 0.0),     # waves q 3 +- 1 up to 7
    (4, "B1", "D2", 2, True, 5, 0.0),     # waves 2, 6, 10: D_2 carries 0, 2, ..., 10
    (4, "B2", "D2", 2, True, 5, math.pi / 4),
    (6, "E2", "D2", 2, True, 7, 0.0),     # gcd(6, 2) = 2: waves 2, 4, 8, 10, 14
    (6, "E1", "D1", 1, True, 13, 0.0)])
def test_each_representation_breaks_to_its_isotropy_subgroup(n, representation, symmetry, sub_n, mirror, K_min,
                                                             turn) -> None:
    b = breaking(AngularBasis(n, K), representation)
    assert (b.symmetry, b.n, b.mirror, b.K_min) == (symmetry, sub_n, mirror, K_min)
    assert b.turn == pytest.approx(turn, abs=1e-15)
    # the subgroup's basis carries every wave of the D_n states and of the class, on the same angles
    sub = subgroup_basis(AngularBasis(n, K), representation)
    block = AngularBasis(n, K).bloch(b.j, b.parity)
    assert set(AngularBasis(n, K).wave_numbers.tolist()) | set(block.wave_numbers.tolist()) <= \
        set(sub.wave_numbers.tolist())
    assert sub.M == AngularBasis(n, K).M


def test_coefficients_turned_into_another_basis() -> None:
    d4 = AngularBasis(4, 1)
    c = np.zeros(d4.m)
    c[d4.index("R", "cos", 4)] = 1.0          # cos 4 theta, read from theta' = theta - pi / 4: -cos 4 theta'
    c[d4.index("T", "sin", 4)] = 2.0          # sin 4 theta -> -sin 4 theta'
    d2 = AngularBasis(2, 2)
    out = transfer_coefficients(c, d4, d2, math.pi / 4)
    assert out[d2.index("R", "cos", 4)] == pytest.approx(-1.0, abs=1e-15)
    assert out[d2.index("T", "sin", 4)] == pytest.approx(-2.0, abs=1e-15)
    assert np.count_nonzero(out) == 2
    # B2 of D_4: R sin 2 theta is symmetric about theta = pi / 4, where it reads cos 2 theta'
    b2 = d4.bloch(2, "odd")
    m = np.zeros(b2.m)
    m[b2.index("R", "sin", 2)] = 1.0
    out = transfer_coefficients(m, b2, d2, math.pi / 4)
    assert out[d2.index("R", "cos", 2)] == pytest.approx(1.0, abs=1e-15) and np.count_nonzero(out) == 1
    with pytest.raises(ValueError, match=r"R sin\(2 theta\), which"):
        transfer_coefficients(m, b2, d2)              # not turned: antisymmetric, the D_2 basis has no sines of R


def test_the_symmetry_of_a_state_from_its_waves_and_mirror_plane() -> None:
    full = AngularBasis(1, 6, mirror=False)
    nodes = 4
    c = np.zeros((nodes, full.m))
    c[:, full.index("R", "cos", 0)] = 1.0
    assert state_symmetry(full, c.ravel()).label == "O(2)"
    # R = cos 3 (theta - a) + 0.1 cos 6 (theta - a): three mirror planes, one at a
    a = 0.3
    for k, amp in ((3, 1e-2), (6, 1e-3)):
        c[:, full.index("R", "cos", k)] = amp * math.cos(k * a)
        c[:, full.index("R", "sin", k)] = amp * math.sin(k * a)
    sym = state_symmetry(full, c.ravel())
    assert sym.label == "D3" and sym.order == 3 and sym.amplitudes[3] == pytest.approx(1e-2)
    assert math.sin(3 * (sym.mirror - a)) == pytest.approx(0.0, abs=1e-12)
    # Z = sin 3 theta: symmetric about theta = pi / 6, R about theta = a: no common plane
    c[:, full.index("Z", "sin", 3)] = 1e-2
    assert state_symmetry(full, c.ravel()).label == "C3"
    c[:, full.index("Z", "cos", 1)] = 1e-3           # and a tilt: no rotation left
    assert state_symmetry(full, c.ravel()).label == "C1"


@pytest.fixture(scope="module")
def three_waves():
    """The paper's cap (sliding edge) under a prescribed pole deflection in the D_3 view watching every class:
    the axisymmetric path to the three-wave branch point, then the three-wave branch to its fold."""
    prob = Shell3D(paper_cap(N), AngularBasis(3, K), "point", "displacement", every_mode=True)
    first = contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=0.5, ds=0.01, ds_max=0.02,
                                max_steps=300, stability=True, n_eigs=0, stop_at=("branch_point",))
    second = contin.switch_branch(prob, first.special_points[-1], SETTINGS, max_steps=300, p_max=0.5,
                                  stability=True, n_eigs=0, stop_at=("fold",))
    return prob, first, second


def _located(branch, key):
    return [s for s in branch.special_points if s.kind == "bifurcation" and s.info.get("key") == key and s.located]


@pytest.mark.parametrize("on", ["axisymmetric", "three-wave"])
def test_an_e1_bifurcation_relocates_in_d1_and_its_branch_is_d1_not_d3(three_waves, on) -> None:
    prob, first, second = three_waves
    point = _located(first if on == "axisymmetric" else second, "E1")[0]
    if on == "three-wave":
        assert state_symmetry(prob.basis, prob.full_state(point.u, point.p)).label == "D3"
    out = follow_symmetry_breaking(prob, point, settings=SETTINGS, max_steps=6, n_eigs=0)
    assert out.breaking.symmetry == "D1" and out.problem.basis.n == 1 and out.problem.basis.mirror
    bp = out.branch_point
    # the same angles and waves: the D_1 view's Hessian on the E1 waves is the D_3 family's block
    assert abs(bp.p - point.p) < 1e-8 * point.p
    assert bp.info["mode_angle"] < 1e-6
    assert bp.bifurcation.kind == ("pitchfork" if on == "axisymmetric" else "transcritical")
    sym = state_symmetry(out.problem.basis, out.problem.full_state(out.branch.u[-1], out.branch.p[-1]))
    assert sym.label == "D1"
    assert sym.amplitudes[1] > 1e-4 and sym.amplitudes[2] > 1e-6       # waves D_3 does not have


def test_bad_inputs_are_refused(three_waves) -> None:
    prob, first, second = three_waves
    with pytest.raises(LiftError, match=r"representation must be one of .*'A2', 'E1'"):
        breaking(prob.basis, "A1")
    with pytest.raises(LiftError, match="must be a D_n basis"):
        breaking(AngularBasis(3, 2, mirror=False), "A2")
    with pytest.raises(LiftError, match="must be an integer >= 7"):
        subgroup_basis(prob.basis, "E1", 6)
    d3 = Shell3D(paper_cap(N), AngularBasis(3, K), "point", "displacement")
    with pytest.raises(LiftError, match=r"breaks to D1: the target needs AngularBasis\(1, K >= 7"):
        subgroup_lift(prob, d3, "E1")
    force = Shell3D(paper_cap(N), subgroup_basis(prob.basis, "E1"), "point", "force")
    with pytest.raises(LiftError, match="same load and control"):
        subgroup_lift(prob, force, "E1")
    fold = second.special_points[-1]
    with pytest.raises(LiftError, match="must be a located bifurcation of a D_n branch"):
        follow_symmetry_breaking(prob, fold)
    with pytest.raises(LiftError, match="K .* must be an integer >= 6"):
        jump_in_full_space(prob, fold.u, fold.p, K=5)


def test_a_jump_from_the_three_wave_fold_in_the_full_space_lands_stable_and_says_its_symmetry() -> None:
    """From the fold of the three-wave branch (D_3, K = 1) the energy descent with no symmetry imposed (waves
    0 .. 3, both parities) lands on a state stable against all of them, with one wave: D_1, not D_3."""
    from contin.numerics.stability import stability_info

    prob = Shell3D(paper_cap(N), AngularBasis(3, 1), "point", "displacement")
    first = contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=0.5, ds=0.01, ds_max=0.02,
                                max_steps=300, stability=True, n_eigs=0, stop_at=("branch_point",))
    second = contin.switch_branch(prob, first.special_points[-1], SETTINGS, max_steps=300, p_max=0.5,
                                  stability=True, n_eigs=0, stop_at=("fold",))
    fold = second.special_points[-1]
    assert fold.kind == "fold"
    out = jump_in_full_space(prob, fold.u, fold.p)
    full = out.problem
    assert (full.basis.n, full.basis.K, full.basis.mirror) == (1, 3, False)
    assert out.jump.success and out.jump.p == fold.p
    # the fold's D_3 state is unstable against the waves D_3 does not hold; the landing against none of them
    start = full.unknowns(transfer_coefficients(prob.full_state(fold.u, fold.p), prob.basis, full.basis))
    assert stability_info(full.jacobian(start, fold.p), 0).n_negative > 0
    assert stability_info(full.jacobian(out.jump.u_to, out.jump.p), 0).n_negative == 0 == out.n_negative
    assert out.symmetry.label == "D1" and out.symmetry.amplitudes[1] > 10 * out.symmetry.amplitudes[3]
    # a snap: the pole force jumps from the falling branch's negative value to a positive one
    assert prob.observables["F"](fold.u, fold.p) < 0 < full.observables["F"](out.jump.u_to, out.jump.p)


def test_a_b2_bifurcation_relocates_in_d2_turned_by_pi_over_n() -> None:
    """D_4's B2 (the waves 2, 6, antisymmetric about theta = 0) keeps the mirror in theta = pi / 4: the mode, read
    from there, is symmetric and the point a simple branch point of the turned D_2 view (at the axisymmetric
    state it is the harmonic blocks' n = 2 point)."""
    prob = Shell3D(paper_cap(N), AngularBasis(4, 1), "point", "displacement", every_mode=True)
    path = contin.continuation(prob, prob.reference_unknowns(), 0.0, p_max=0.38, ds=0.01, ds_max=0.02,
                               max_steps=300, stability=True, n_eigs=0)
    # at the axisymmetric state B2 (sin 2 theta) and B1 (cos 2 theta) are one pair: they cross at one point,
    # recorded under the first key with the other in "also"
    point = next(s for s in path.special_points if s.kind == "bifurcation" and s.located
                 and "B2" in [s.info["key"], *s.info.get("also", [])])
    with pytest.raises(LiftError, match="did not cross at this point"):
        follow_symmetry_breaking(prob, point, key="A2")
    out = follow_symmetry_breaking(prob, point, settings=SETTINGS, max_steps=5, n_eigs=0, key="B2")
    assert out.breaking.turn == pytest.approx(math.pi / 4) and out.problem.basis.n == 2
    bp = out.branch_point
    assert abs(bp.p - point.p) < 1e-8 * point.p and bp.info["mode_angle"] < 1e-6
    sym = state_symmetry(out.problem.basis, out.problem.full_state(out.branch.u[-1], out.branch.p[-1]))
    assert sym.label == "D2" and sym.amplitudes[2] > 1e-4
