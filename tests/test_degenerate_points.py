"""Multiple branch points of symmetric models with closed forms, with default settings.

Each of these passed unreported before the Morse index was watched: the determinant's sign does not
change where two eigenvalues cross zero together.
"""

from __future__ import annotations

import numpy as np
import pytest

import contin
from contin_models.benchmarks.augusti import AugustiStrut
from contin_models.benchmarks.ring import PressurisedRing
from contin_models.benchmarks.spring_chain import BistableChain
from contin_models.benchmarks.square import D4Square


def _near(branch: contin.Branch, p: float, rtol: float) -> contin.SpecialPoint:
    near = [s for s in branch.branch_points() if abs(s.p - p) <= rtol * max(1.0, abs(p))]
    assert len(near) == 1, (p, [(s.p, s.bifurcation and s.bifurcation.multiplicity) for s in branch.special_points])
    return near[0]


def test_the_square_reports_its_double_point_as_double():
    square = D4Square(30)
    br = contin.continuation(square, np.zeros(square.n ** 2), 0.0, p_max=55.0)
    assert br.success, br.message
    for p, multiplicity, _ in square.branch_points(55.0):  # (1,1) simple, (1,2)/(2,1) double
        bp = _near(br, p, 1e-8)
        assert bp.located and bp.bifurcation.multiplicity == multiplicity


@pytest.mark.parametrize("spring_length", [None, 2.0])
def test_the_augusti_struts_double_point(spring_length):
    strut = AugustiStrut(spring_length=spring_length)
    br = contin.continuation(strut, np.zeros(2), 0.0, p_max=1.5)
    assert br.success, br.message
    bp = _near(br, 1.0, 1e-10)
    assert bp.bifurcation.multiplicity == 2
    assert np.allclose(bp.bifurcation.kernel @ bp.bifurcation.kernel.T, np.eye(2), atol=1e-12)


@pytest.mark.parametrize("coordinates", ["modes", "nodes"])
@pytest.mark.parametrize("stability", [False, True])
def test_three_identical_springs_branch_points_have_multiplicity_two(coordinates, stability):
    # in node coordinates with stability, the bisection of the index told the two eigenvalues apart by
    # 1.5e-11 in the elongation, and each half was taken for a fold
    chain = BistableChain(3, coordinates=coordinates)
    br = contin.continuation(chain, chain.state(np.zeros(3)), 0.0, p_max=4.5, stability=stability)
    assert br.success, br.message
    for Delta, _, multiplicity in chain.homogeneous_branch_points():
        assert _near(br, Delta, 1e-8).bifurcation.multiplicity == multiplicity == 2


def test_the_rings_first_double_points():
    ring = PressurisedRing(N=64)
    br = contin.continuation(ring, np.zeros(2 * ring.N), 0.0, p_max=20.0)
    assert br.success, br.message
    for n in (2, 3, 4):
        bp = _near(br, ring.buckling_load(n), 1e-8)
        assert bp.bifurcation.multiplicity == 2


def test_two_springs_at_their_peak_are_a_pitchfork_not_a_fold():
    # prescribed total elongation, one unknown node: df/dp = -f'(e) vanishes where the springs peak, so
    # the null vector's direction against df/dp (1 in one dimension) says nothing there
    chain = BistableChain(2, coordinates="nodes")
    br = contin.continuation(chain, chain.state(np.zeros(2)), 0.0, p_max=3.0)
    assert br.success, br.message
    for Delta, _, multiplicity in chain.homogeneous_branch_points():
        bp = _near(br, Delta, 1e-9)
        assert bp.located and bp.bifurcation.kind == "pitchfork" and multiplicity == 1


def test_six_springs_fold_together_at_a_point_of_multiplicity_five():
    chain = BistableChain(6, coordinates="nodes")
    br = contin.continuation(chain, chain.state(np.zeros(6)), 0.0, p_max=9.0)
    assert br.success, br.message
    for Delta, _, multiplicity in chain.homogeneous_branch_points():
        assert _near(br, Delta, 1e-8).bifurcation.multiplicity == multiplicity == 5


@pytest.mark.parametrize("k, coordinates", [(2, "nodes"), (2, "modes"), (3, "nodes"), (3, "modes"), (6, "nodes"),
                                            (6, "modes")])
def test_the_chain_snaps_tooth_by_tooth(k, coordinates):
    # six springs in mode coordinates: the homogeneous state is u = 0 and df/dp there is roundoff
    # (1e-33); once the scales or the residual tolerance were taken from it, or the step guard
    # rejected the four-fold point's index jump of four until the steps collapsed, the sweep stopped
    # after the first or second tooth
    chain = BistableChain(k, coordinates=coordinates)
    sweep = contin.quasistatic(chain, chain.state(np.zeros(k)), 0.0, 1.5 * k)
    assert sweep.status == "completed", sweep.message
    teeth = chain.sawtooth()
    assert len(sweep.jumps) == len(teeth)
    for jump, tooth in zip(sweep.jumps, teeth):
        assert jump.p == pytest.approx(tooth.delta, rel=1e-7)
        assert chain.observables["force"](jump.u_to, jump.p) == pytest.approx(tooth.force_after, rel=1e-6)


@pytest.fixture(scope="module")
def square_trace():
    square = D4Square(30)
    return square, contin.continuation(square, np.zeros(square.n ** 2), 0.0, p_max=55.0, stability=True, n_eigs=0)


def _mode_share(square, u):
    """The state's components on the discrete modes (1,2) and (2,1) (grid inner product)."""
    h2 = square.h ** 2
    return h2 * u @ square.mode(1, 2), h2 * u @ square.mode(2, 1)


def test_the_squares_double_point_resolved_by_its_symmetry(square_trace):
    # D4 on the kernel of (1,2)/(2,1): two classes of axial lines, the pure modes and the mixed ones,
    # two lines each; one branch per class is traced, against the cubic bifurcation equation
    square, br = square_trace
    bp = _near(br, square.eigenvalue(1, 2), 1e-8)
    record = bp.bifurcation
    assert record.kind == "symmetric" and len(record.directions) == 2
    assert all("2 copies" in label for label in record.labels)
    kinds, indices = [], []
    for k in range(2):
        post = contin.switch_branch(square, bp, branch=k, p_max=bp.p + 0.05, stability=True, n_eigs=0)
        assert post.success, post.message
        u, p = np.asarray(post.u[-1]), float(post.p[-1])
        a, b = _mode_share(square, u)
        kind = "pure" if min(abs(a), abs(b)) < 1e-6 * max(abs(a), abs(b)) else "mixed"
        assert kind == "pure" or abs(abs(a) - abs(b)) < 1e-8 * abs(a)
        # ||u||_h^2 = (p - lambda) / c to leading order: c = 9/4 (pure), 21/8 (mixed)
        expected = square.branch_amplitude(p, kind) ** 2
        assert square.h ** 2 * u @ u == pytest.approx(expected, rel=2e-3)
        kinds.append(kind)
        indices.append(int(post.n_negative[-1]))
    assert sorted(kinds) == ["mixed", "pure"]
    # above the double point the trivial branch has index 3; the pure branches 1 and the mixed ones 2
    assert dict(zip(kinds, indices)) == {"pure": 1, "mixed": 2}


def test_the_squares_double_point_resolved_by_its_reduced_equation(square_trace):
    # the same model without its symmetry: the four critical lines of the quartic form, 45 degrees apart
    square, _ = square_trace
    plain = D4Square(30)
    plain.symmetry_generators = ()
    br = contin.continuation(plain, np.zeros(plain.n ** 2), 0.0, p_max=55.0)
    record = _near(br, square.eigenvalue(1, 2), 1e-8).bifurcation
    assert record.kind == "reduced" and len(record.directions) == 4
    shares = [_mode_share(square, d[:-1]) for d in record.directions]
    pure = [s for s in shares if min(abs(s[0]), abs(s[1])) < 1e-6]
    mixed = [s for s in shares if abs(abs(s[0]) - abs(s[1])) < 1e-6]
    assert len(pure) == 2 and len(mixed) == 2


def test_the_rings_oval_branch_traced_in_its_fixed_space():
    # EA R^2 / EI = 1e4: at the default 1e6 the corrector's tolerance meets the membrane terms' roundoff
    # once the ring deflects by a tenth of its radius
    from contin.watch.branching import FixedSpaceProblem, isotropy_basis

    ring = PressurisedRing(N=32, membrane_ratio=1e4)
    br = contin.continuation(ring, np.zeros(2 * ring.N), 0.0, p_max=3.5)
    bp = _near(br, ring.buckling_load(2), 1e-8)
    record = bp.bifurcation
    assert record.kind == "symmetric" and record.multiplicity == 2 and len(record.directions) == 2
    for k in range(2):
        d = record.directions[k][:-1]
        B, order = isotropy_basis(ring, bp.u, d)
        assert order == 4 and B.shape == (64, 16)  # fixed by the mirror and the half turn, and their product
        koiter = contin.koiter_coefficients(FixedSpaceProblem(ring, B), B.T @ bp.u, bp.p, null_vector=B.T @ d)
        post = contin.switch_branch(ring, bp, branch=k, p_max=1.02 * bp.p, ds=0.01, known=br.branch_points())
        assert post.success and post.meta["fixed_space"]["unknowns"] == 16, post.message
        U, P = np.asarray(post.u), np.asarray(post.p)
        assert np.allclose(U @ B @ B.T, U, atol=1e-12)  # every state keeps the branch's symmetry
        phi = B @ koiter.null_vector
        xi = np.array([phi @ (u - ring.trivial_state(p)) for u, p in zip(U, P)])
        on = np.abs(xi) > 1e-3
        # p / p_c - 1 = b xi^2 + O(xi^4): the intercept of the ratio against xi^2 is Koiter's b
        fit = np.polyfit(xi[on] ** 2, (P[on] / bp.p - 1.0) / xi[on] ** 2, 1)
        assert fit[1] == pytest.approx(koiter.b, rel=1e-3) and koiter.b > 0


def _radius_spread(ring, u):
    """max - min of the nodes' distances from the centre: the oval's amplitude in either coordinates."""
    X = ring.positions(u)
    return float(np.ptp(np.hypot(X[:, 0], X[:, 1])))


@pytest.mark.slow
def test_the_rings_oval_branch_at_the_stiff_membrane_in_both_coordinates():
    # EA R^2 / EI = 1e6 in displacements: the membrane forces come from differences of lengths, their
    # rounding (about 2e-11 here) lies above the tolerance asked for (1e-11), and the corrector stopped
    # at the first points off the double point ("tolerance below the roundoff floor").  Converged
    # states at residuals that stagnate inside the roundoff floor now raise the run's tolerance to
    # the noise, and say so
    branches = {}
    for coordinates in ("displacements", "positions"):
        ring = PressurisedRing(N=64, coordinates=coordinates)
        br = contin.continuation(ring, ring.trivial_state(0.0), 0.0, p_max=3.5)
        bp = _near(br, ring.buckling_load(2), 1e-8)
        post = contin.switch_branch(ring, bp, p_min=0.0, p_max=2 * bp.p, known=br.branch_points())
        assert post.status == "bound" and post.p[-1] == pytest.approx(2 * bp.p), post.message
        branches[coordinates] = (np.asarray(post.p), np.array([_radius_spread(ring, u) for u in post.u]))
        if coordinates == "displacements":
            raised = post.meta["tol_raised"]
            assert raised and "tolerance was raised" in post.message
            assert raised[-1]["to"] <= 1e4 * raised[0]["from"]
    # the same branch in the other unknowns (its amplitude grows to the radius itself)
    assert all(np.all(np.diff(p) > 0) for p, _ in branches.values())
    for p in (4.0, 5.0):
        amplitudes = [np.interp(p, *branches[c]) for c in branches]
        assert amplitudes[0] == pytest.approx(amplitudes[1], rel=1e-5) and amplitudes[0] > 0.5


def test_a_snap_at_a_five_fold_point_lands_on_the_first_tooth():
    # at a point of multiplicity five any kernel vector is an eigenvector, and along the one the
    # eigensolver picks no kick lowered the energy; the resolved branch directions are kicked too.
    # The homogeneous state is u = 0 in mode coordinates: kicks are sized by the problem's own scale
    chain = BistableChain(6, coordinates="modes")
    first = chain.sawtooth()[0]
    sweep = contin.quasistatic(chain, chain.state(np.zeros(6)), 0.0, first.delta + 0.05)
    assert len(sweep.jumps) >= 1, sweep.message
    jump = sweep.jumps[0]
    assert jump.p == pytest.approx(first.delta, rel=1e-7)
    assert chain.observables["force"](jump.u_to, jump.p) == pytest.approx(first.force_after, rel=1e-6)


def test_a_branch_traced_in_its_fixed_space_counts_the_neutral_tilt_of_the_o2_strut_as_zero():
    # the O(2) strut's tilted branch is a circle of equilibria: the eigenvalue along the circle is
    # zero, its computed sign (+-2e-16) flipped from point to point, and the index flickered between
    # 1 and 2 with no point reported
    strut = AugustiStrut()
    br = contin.continuation(strut, np.zeros(2), 0.0, p_max=1.5, stability=True)
    bp = _near(br, 1.0, 1e-12)
    post = contin.switch_branch(strut, bp, stability=True, p_min=0.5, p_max=1.5, known=br.branch_points())
    assert post.status == "bound" and post.meta["fixed_space"]["unknowns"] == 1, post.message
    assert set(post.n_negative[1:].tolist()) == {1} and post.meta["neutral_modes"] == 1
    assert not [spt for spt in post.special_points if spt.info.get("breaks_symmetry")]


@pytest.mark.parametrize("branch, springs_at_spinodal", [(0, [(5, "valley")]), (1, [(3, "valley"), (3, "peak")]),
                                                         (2, [(2, "valley"), (4, "peak")])])
def test_six_springs_branches_report_the_points_that_break_their_symmetry(branch, springs_at_spinodal):
    # traced in the fixed space of their symmetry, the branches from the five-fold point could not see
    # where m of their identical springs reach a spinodal together (a point of multiplicity m - 1
    # that breaks the branch's symmetry): the index against the other modes changed by m - 1 with
    # nothing reported
    chain = BistableChain(6, coordinates="modes")
    br = contin.continuation(chain, chain.state(np.zeros(6)), 0.0, p_max=9.0, stability=True)
    bp, end = br.branch_points()[0], br.branch_points()[1].p
    post = contin.switch_branch(chain, bp, branch=branch, stability=True, known=br.branch_points(),
                                p_min=0.0, p_max=9.0)
    assert post.meta["fixed_space"]["unknowns"] == 1
    breaking = [spt for spt in post.special_points if spt.info.get("breaks_symmetry")]
    assert breaking and "break its symmetry" in post.message
    F_min, F_max = chain.force_range
    for m, where in springs_at_spinodal:
        # the other 6 - m springs on the branch of the spring law with the same force
        F = F_min if where == "valley" else F_max
        Delta = chain.family_elongation(F, m, 0) if where == "valley" else chain.family_elongation(F, 6 - m, 0)
        (spt,) = [s for s in breaking if min(s.info["bracket_p"]) <= Delta <= max(s.info["bracket_p"])]
        assert abs(spt.info["n_negative_after"] - spt.info["n_negative_before"]) == m - 1
    # any other bracket is the step onto the homogeneous branch's second five-fold point, where the run ends
    spinodal = [chain.family_elongation(F, m, 0) for F in (F_min, F_max) for m in range(7)]
    others = [s for s in breaking if not any(min(s.info["bracket_p"]) <= D <= max(s.info["bracket_p"]) for D in spinodal)]
    assert all(min(abs(b - end) for b in s.info["bracket_p"]) <= 1e-6 * end for s in others)


def test_a_start_on_a_circle_of_equilibria_says_why_it_cannot_be_traced():
    # the O(2) strut's tilted states form circles of equilibria: the Jacobian is singular at every one
    # of them, and a run started there failed with "linear solve produced non-finite values" alone
    strut = AugustiStrut()
    br = contin.continuation(strut, np.zeros(2), 0.0, p_max=1.5)
    post = contin.switch_branch(strut, _near(br, 1.0, 1e-12), p_min=0.5, p_max=1.5)
    k = len(post.p) // 2
    run = contin.continuation(AugustiStrut(), post.u[k], post.p[k], p_min=0.5, p_max=1.5)
    assert run.status == "failed" and "continuous symmetry" in run.message and "switch_branch" in run.message
