"""The axisymmetric trace's bifurcation into n waves, lifted into the 3-D view and followed onto the n-wave branch."""

import numpy as np
import pytest

import contin
from contin import LiftError
from contin_models.shell.fourier import AngularBasis
from contin_models.shell.lift import follow_waves, rotated_half, shell_lift
from contin_models.shell.problem3d import Shell3D
from contin_models.shell.structure import ShellOfRevolution
from studies.shell3d_convergence import SWITCH_DS, paper_cap, three_wave_branch

N, K, W_END = 30, 2, 0.37
SETTINGS = contin.Settings(ds=SWITCH_DS, ds_max=0.02)


@pytest.fixture(scope="module")
def axisymmetric():
    """The paper's cap (sliding edge) under a prescribed pole deflection, watching the waves 1 .. 4."""
    source = ShellOfRevolution(paper_cap(N), "point", "displacement", harmonics=4)
    trace = contin.continuation(source, source.reference_unknowns(), 0.0, p_max=W_END, ds=0.01, ds_max=0.02,
                                max_steps=2000, stability=True)
    points = {spt.info["key"]: spt for spt in trace.special_points if spt.kind == "bifurcation"}
    return source, trace, points


@pytest.fixture(scope="module")
def three_waves(axisymmetric):
    source, _, points = axisymmetric
    return follow_waves(source, points[3], K, settings=SETTINGS, max_steps=2000, p_max=W_END)


def test_the_lifted_point_is_where_the_harmonic_block_put_it(axisymmetric, three_waves) -> None:
    _, _, points = axisymmetric
    bp = three_waves.branch_point
    assert bp.kind == "branch_point" and bp.located and bp.bifurcation.kind == "pitchfork"
    assert three_waves.problem.basis.n == 3 and three_waves.problem.basis.K == K
    # the view integrates quadratic forms about an axisymmetric state exactly: the same point
    assert bp.p == pytest.approx(points[3].p, rel=1e-9)
    assert abs(bp.info["moved_p"]) < 1e-9 * bp.p
    assert bp.info["mode_angle"] < 1e-6
    assert bp.info["lifted_from"]["key"] == 3


def test_the_branch_from_the_lift_is_the_one_traced_in_3d_from_the_unloaded_cap(three_waves) -> None:
    branch = three_waves.branch
    assert branch.status == "bound" and branch.p[-1] == pytest.approx(W_END, abs=1e-12)
    reference = three_wave_branch(N, K, W_END)          # the whole axisymmetric path again, in 3-D
    force = three_waves.problem.observables["F"](branch.u[-1], branch.p[-1])
    assert force == pytest.approx(reference["F_end"], rel=1e-8)
    assert three_waves.branch_point.p == pytest.approx(reference["w_bp"], rel=1e-9)


def test_the_other_half_is_the_branch_turned_by_pi_over_n(three_waves) -> None:
    prob, bp = three_waves.problem, three_waves.branch_point
    w = 0.355
    halves = [contin.switch_branch(prob, bp, SETTINGS, direction=d, max_steps=200, p_max=w) for d in (1, -1)]
    assert all(h.status == "bound" for h in halves)
    plus, minus = (h.u[-1] for h in halves)
    assert np.max(np.abs(plus - minus)) > 1e-3                      # two different states ...
    np.testing.assert_allclose(rotated_half(prob, plus, w), minus, atol=1e-8)   # ... one turned into the other


def test_a_bad_lift_is_refused(axisymmetric) -> None:
    source, trace, points = axisymmetric
    d4 = Shell3D(paper_cap(N), AngularBasis(4, K), "point", "displacement")
    with pytest.raises(LiftError, match=r"carries the waves \[4, 8\]"):
        shell_lift(source, d4, 3)
    d3 = Shell3D(paper_cap(N), AngularBasis(3, K), "point", "displacement")
    with pytest.raises(LiftError, match="bifurcation into n = 1"):
        contin.lift_branch_point(points[1], source, d3, shell_lift(source, d3, 3))
    force = Shell3D(paper_cap(N), AngularBasis(3, K), "point", "force")
    with pytest.raises(LiftError, match="same load and control"):
        shell_lift(source, force, 3)
    start = contin.SpecialPoint("event", 0.0, trace.u[0], located=True)
    with pytest.raises(LiftError, match="must be a located bifurcation into n waves"):
        follow_waves(source, start, K)


def test_the_papers_point_load_model_through_its_structure() -> None:
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.build import point_problem, point_settings, traced_structure

    scene = load_scene(SHELL_SCHEMA, None, [f"shell.N={N}", "shell.phi_hat=0.6", "stability.harmonics=true",
                                            "stability.n_max=4"])
    source = point_problem(scene)
    trace = contin.continuation(source, source.reference_unknowns(), 0.0, point_settings(scene, source), p_max=0.4,
                                stop_at=("bifurcation",))
    point = trace.special_points[-1]
    assert point.kind == "bifurcation" and point.info["key"] == 3
    waves = follow_waves(source, point, K, structure=traced_structure(scene, source), settings=SETTINGS,
                         max_steps=20, stability=True)
    assert waves.branch_point.p == pytest.approx(point.p, rel=1e-9)
    assert len(waves.branch.p) > 10
    # off the axisymmetric branch: the three-wave coefficients grow
    c = waves.problem.full_state(waves.branch.u[-1], waves.branch.p[-1])
    assert np.max(np.abs(c[waves.problem.view.dofs_of_wave(3)])) > 1e-3


def test_the_branch_counted_against_every_representation(axisymmetric) -> None:
    source, _, points = axisymmetric
    waves = follow_waves(source, points[3], K, settings=SETTINGS, every_mode=True, max_steps=12, stability=True)
    assert [f.name for f in waves.problem.operator_families] == ["representation"]
    modes = waves.branch.meta["modes"]["representation"]
    assert set(modes["keys"]) == {"A2", "E1"}                      # D_3's other classes
    assert len(modes["n_negative"]) == len(waves.branch.p)
    # the total Morse index counts every class: E1 twice (two-dimensional), the traced class A1 besides
    total = waves.branch.n_negative_under("displacement")
    others = np.asarray(modes["n_negative"]) @ np.array([2 if k == "E1" else 1 for k in modes["keys"]])
    assert np.all(total >= others)
