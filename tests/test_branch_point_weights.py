"""Branch points located and followed whatever the arclength weights (issue 15, item 4).

Symmetric problems locate a branch point on the Hessian's own test function, so the located load
must not depend on ``state_weight`` / ``param_weight``; ``switch_branch`` must work from it with
settings other than those of the locating run; a switched branch that meets a branch point again
must stop there and say so.
"""

import numpy as np
import pytest
from scipy.special import ellipk

from contin import Problem, continuation, switch_branch
from contin_models.benchmarks.elastica import EulerColumn

from contin_models.benchmarks.arch import ShallowArch

#: weight settings of the arclength norm
WEIGHTS = {
    "unit": {},
    "param_1e3": {"param_weight": 1e3},
    "param_1e-3": {"param_weight": 1e-3},
    "state_1e3": {"state_weight": 1e3},
    "state_1e-3": {"state_weight": 1e-3},
}


def scaled(weights, ds, ds_max):
    """The weights with the steps scaled by the largest weight, so each run takes about as many steps."""
    kw = dict(WEIGHTS[weights])
    f = max(kw.get("param_weight", 1.0), kw.get("state_weight", 1.0))
    return {**kw, "ds": ds * f, "ds_max": ds_max * f, "ds_min": 1e-9 * f}


def column_branch(n, weights):
    col = EulerColumn(n)
    # the straight branch moves in the load only: its arclength is param_weight times the load
    kw = dict(WEIGHTS[weights])
    f = kw.get("param_weight", 1.0)
    return col, continuation(col, np.zeros(n), 0.0, p_max=15.0, ds=0.5 * f, ds_max=2.0 * f, **kw)


@pytest.mark.parametrize("n", [20, 40, 80])
@pytest.mark.parametrize("weights", sorted(WEIGHTS))
def test_column_branch_point_matches_closed_form_with_any_weights(n, weights):
    # the half-column of inextensible links: P_1 = 4 EI / h^2 sin^2(pi / (4 n)) (model docstring)
    col, br = column_branch(n, weights)
    (bp,) = br.branch_points()
    assert bp.located
    P1 = col.buckling_load_closed_form()
    assert abs(bp.p - P1) <= 1e-10 * P1
    assert bp.bifurcation.kind == "pitchfork"
    lam = np.linalg.eigvalsh(col.jacobian(bp.u, bp.p).toarray())
    assert np.min(np.abs(lam)) <= 1e-12 * np.max(np.abs(lam))


@pytest.mark.parametrize("locating, switching", [("unit", "param_1e3"), ("param_1e3", "param_1e-3"),
                                                 ("state_1e3", "unit")])
def test_column_switch_with_other_weights_follows_the_elastica(locating, switching):
    n = 80
    col, br = column_branch(n, locating)
    bp = br.branch_points()[0]
    buckled = switch_branch(col, bp, p_max=14.0, max_steps=400, **scaled(switching, 0.05, 0.2))
    assert buckled.status == "bound"
    rot = buckled.observables["end_rotation"]
    assert np.all(np.abs(rot[1:]) > 0) and np.all(buckled.p > bp.p)
    # elastica: sqrt(P / EI) l = K(m = sin^2(alpha / 2)), l = L / 2, alpha the end rotation
    predicted = ellipk(np.sin(rot / 2) ** 2) ** 2 / 0.5 ** 2
    big = np.abs(rot) > 0.3
    assert big.sum() >= 3
    np.testing.assert_allclose(buckled.p[big], predicted[big], rtol=3e-3)


def transcritical() -> Problem:
    """``f = p u - u^2``: the trivial branch and ``u = p`` cross transcritically at the origin."""
    return Problem(residual=lambda u, p: np.array([p * u[0] - u[0] ** 2]),
                   jacobian=lambda u, p: np.array([[p - 2 * u[0]]]),
                   dresidual_dp=lambda u, p: np.array([u[0]]), symmetric=True, name="transcritical")


@pytest.mark.parametrize("weights", ["unit", "param_1e-3", "state_1e3"])
def test_transcritical_second_branch_from_the_bifurcation_equation(weights):
    prob = transcritical()
    br = continuation(prob, [0.0], -1.0, p_max=1.0, **scaled(weights, 0.1, 0.2))
    (bp,) = br.branch_points()
    assert bp.located and abs(bp.p) < 1e-12
    assert bp.bifurcation.kind == "transcritical"
    d = bp.bifurcation.directions[0]
    assert abs(abs(d[0] / d[1]) - 1.0) < 1e-6  # the branch u = p
    for direction in (1, -1):
        nb = switch_branch(prob, bp, direction=direction, ds=0.05, p_min=-1.0, p_max=1.0, param_weight=3.0)
        assert nb.status == "bound"
        np.testing.assert_allclose(nb.u[:, 0], nb.p, atol=1e-9)
        assert np.all(np.abs(nb.u[1:, 0]) > 1e-3)


# ---- the shallow arch ------------------------------------------------------------------------------

ARCH_RUN = {"ds": 0.1, "ds_max": 0.5, "bounds": {"deflection": (None, 0.1)}, "max_steps": 3000}


def arch_branch(**kw):
    arch = ShallowArch()
    return arch, continuation(arch, np.zeros(2 * (arch.n - 1)), 0.0, **{**ARCH_RUN, **kw})


def antisymmetric_part(arch, u):
    """Norm of the part of the nodal displacements antisymmetric about the crown (independent of the model)."""
    X = np.zeros((arch.n + 1, 2))
    X[1:-1] = u.reshape(-1, 2)
    mirror = X[::-1] * np.array([-1.0, 1.0])  # reflect x -> -x
    return np.linalg.norm(X - mirror) / 2


def check_branch_point(arch, bp):
    """Independent dense check: an eigenvalue at roundoff, its eigenvector antisymmetric, equilibrium."""
    H = arch.jacobian(bp.u, bp.p).toarray()
    w, V = np.linalg.eigh(H)
    k = np.argmin(np.abs(w))
    assert abs(w[k]) <= 1e-13 * np.max(np.abs(w))
    assert antisymmetric_part(arch, V[:, k]) == pytest.approx(1.0, abs=1e-8)
    assert np.max(np.abs(arch.residual(bp.u, bp.p))) <= 1e-10 * arch.residual_scale


@pytest.fixture(scope="module")
def arch_unit():
    return arch_branch()


def test_arch_four_branch_points_located_with_unit_weights(arch_unit):
    arch, br = arch_unit
    bps = br.branch_points()
    assert len(bps) == 4 and all(bp.located for bp in bps)
    for bp in bps:
        check_branch_point(arch, bp)
        assert bp.bifurcation.kind == "pitchfork"


#: the arch traced in metrics scaled by 10^-3 and 10^3 (steps scaled with the largest weight); the
#: load-dominated and state-blind metrics make every fold of the path sharper than the smallest step,
#: so each is crossed from the located fold along its null vector, two of them (P = -17.40, 12.73)
#: within noise of a branch point or of a retrograde step; ds_max = 5e2 was the fragile case
ARCH_SCALED = {
    "param_1e-3": WEIGHTS["param_1e-3"],
    "param_1e3": scaled("param_1e3", 0.1, 1.0),
    "param_1e3, ds_max 5e2": {**scaled("param_1e3", 0.1, 1.0), "ds_max": 5e2},
    "state_1e-3": scaled("state_1e-3", 0.1, 1.0),
}


@pytest.mark.slow
@pytest.mark.parametrize("weights", sorted(ARCH_SCALED))
def test_arch_branch_points_and_folds_are_the_same_with_scaled_weights(arch_unit, weights):
    arch, br = arch_unit
    _, other = arch_branch(**ARCH_SCALED[weights])
    assert other.status == "bound", other.message
    located = [bp.p for bp in other.branch_points() if bp.located]
    np.testing.assert_allclose(located, [bp.p for bp in br.branch_points()], rtol=1e-8)
    # every limit load of the unit-weight run is found (the finer runs also resolve the close pair at
    # P = 12.73, 7.74 that the unit run's steps of 0.5 pass over)
    folds = np.array([f.p for f in other.folds()])
    assert all(np.min(np.abs(folds - f.p)) <= 1e-8 * abs(f.p) for f in br.folds())


@pytest.mark.slow
@pytest.mark.parametrize("weights", ["state_1e3"])
def test_arch_branch_points_same_loads_slow(arch_unit, weights):
    arch, br = arch_unit
    _, other = arch_branch(**WEIGHTS[weights])
    bps = other.branch_points()
    assert all(bp.located for bp in bps)
    np.testing.assert_allclose([bp.p for bp in bps], [bp.p for bp in br.branch_points()], rtol=1e-8)
    for bp in bps:
        check_branch_point(arch, bp)


def test_arch_switching_reaches_the_known_branch_points(arch_unit):
    arch, br = arch_unit
    bps = br.branch_points()
    # the asymmetric branches join the branch points in pairs: 0 with 3, 1 with 2
    partner = {0: 3, 3: 0, 1: 2, 2: 1}
    for k, bp in enumerate(bps):
        settings = {"ds": 0.02} if k % 2 else {"state_weight": 1e3, "ds": 20.0, "ds_max": 200.0}
        nb = switch_branch(arch, bp, known=bps, max_steps=1000, **settings)
        assert nb.status == "reached_branch_point", nb.message
        assert f"branch point {partner[k]}" in nb.message
        assert nb.p[-1] == bps[partner[k]].p
        assert max(antisymmetric_part(arch, u) for u in nb.u) > 1e-3
        assert max(np.max(np.abs(arch.residual(u, p))) for u, p in zip(nb.u, nb.p)) <= 1e-10 * arch.residual_scale


def test_arch_switched_branch_closes_its_loop():
    arch = ShallowArch()
    br = continuation(arch, np.zeros(2 * (arch.n - 1)), 0.0, ds=0.1, ds_max=0.5, p_max=30.0, stop_at=("branch_point",))
    bp = br.branch_points()[0]
    loop = switch_branch(arch, bp, ds=0.02, max_steps=1000)
    assert loop.status == "closed_loop", loop.message
    assert "returned to the branch point it started from" in loop.message
    assert loop.p[-1] == bp.p and loop.success
    # it went round: through both asymmetric halves (opposite signs of the antisymmetric part)
    asym = loop.observables["asymmetry"]
    assert asym.max() > 1e-3 and asym.min() < -1e-3


@pytest.mark.slow
def test_a_root_of_the_hessian_test_at_a_fold_is_not_a_branch_point():
    """The arch's first limit load under a load-dominated norm (state_weight 1e-3): the run ends on the
    fold, the determinant sign flips there by roundoff, and the Hessian's eigenvalue does cross zero;
    with df/dp far from orthogonal to the null vector it is reported unlocated, not as a branch point."""
    arch = ShallowArch()
    # the roundoff sign flip depends on the exact points taken: Newton's method throughout (no chord
    # updates) reproduces the path on which it was seen
    br = continuation(arch, np.zeros(2 * (arch.n - 1)), 0.0, p_max=20.0, p_min=-20.0, state_weight=1e-3,
                      max_chord_rate=0.0)
    at_fold = [s for s in br.branch_points() if abs(s.p - 9.3610946) < 1e-5]
    assert at_fold and not at_fold[0].located and "fold" in at_fold[0].info["error"]
    assert all(s.info["null_vector_cosine_to_dfdp"] < 1e-6 for s in br.branch_points() if s.located)


def coupled_transcritical(n: int = 30, c: float = 0.7, seed: int = 3) -> tuple[Problem, np.ndarray, float]:
    """``E = u^T K u / 2 - p (a.u)^2 / 2 + c (a.u)^3 / 3`` in ``n`` coupled unknowns (``K`` a random SPD matrix).

    The trivial branch ``u = 0`` loses stability at ``p* = 1 / (a^T K^-1 a)``, where the second branch
    ``u = s p* K^-1 a``, ``s = a.u = (p - p*) / c``, crosses it transcritically (no symmetry: the energy is
    cubic along the null vector ``K^-1 a``).  Returns the problem, ``K^-1 a`` and ``p*``.
    """
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((n, n))
    K = B @ B.T / n + np.eye(n)
    a = rng.standard_normal(n)
    Kia = np.linalg.solve(K, a)
    p_star = 1.0 / float(a @ Kia)
    aa = np.outer(a, a)
    prob = Problem(residual=lambda u, p: K @ u - p * (a @ u) * a + c * (a @ u) ** 2 * a,
                   jacobian=lambda u, p: K - p * aa + 2 * c * (a @ u) * aa,
                   dresidual_dp=lambda u, p: -(a @ u) * a,
                   energy=lambda u, p: float(0.5 * u @ K @ u - 0.5 * p * (a @ u) ** 2 + c / 3 * (a @ u) ** 3),
                   symmetric=True, name="coupled_transcritical")
    return prob, Kia, p_star


@pytest.mark.parametrize("weights", ["unit", "param_1e3", "state_1e-3"])
def test_transcritical_crossing_in_many_unknowns(weights):
    c = 0.7
    prob, Kia, p_star = coupled_transcritical(c=c)
    n = Kia.size
    br = continuation(prob, np.zeros(n), 0.0, p_max=2.0 * p_star, **scaled(weights, 0.05, 0.2))
    assert br.status == "bound", br.message
    (bp,) = br.branch_points()
    assert bp.located and abs(bp.p - p_star) <= 1e-10 * p_star
    assert bp.bifurcation.kind == "transcritical"
    # the crossing branch's direction, in the stored (weight-free) form: du/dp = p* K^-1 a / c
    d = bp.bifurcation.directions[0]
    np.testing.assert_allclose(d[:n] / d[n], p_star * Kia / c, rtol=1e-6, atol=1e-9 * np.max(np.abs(Kia)))
    for direction in (1, -1):
        nb = switch_branch(prob, bp, direction=direction, ds=0.02, p_min=0.2 * p_star, p_max=1.8 * p_star,
                           max_steps=500)
        assert nb.status == "bound", nb.message
        s = (nb.p - p_star) / c  # the closed-form branch at the traced loads
        np.testing.assert_allclose(nb.u, np.outer(s * p_star, Kia), atol=1e-9 * np.max(np.abs(Kia)))
        # it left the crossing the way it was sent (along direction * d) and stayed on that side
        assert np.all(np.sign(nb.p[1:] - p_star) == direction * np.sign(d[n]))
        # its first step is a fraction of the branch point's own scales (p* and |u| ~ p*^2 |K^-1 a| / c),
        # not of the units: the first point lies within 5 % of p* from it
        assert abs(nb.p[1] - p_star) < 0.05 * p_star
