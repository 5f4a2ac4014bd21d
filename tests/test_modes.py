"""Operator families watched along a branch (:mod:`contin.watch.modes`): bifurcations into other modes.

A problem with the trivial path ``u = p`` and, per key ``k``, the operator ``diag(k^2 - u, 2 k^2 - u)``:
key ``k`` gains a negative eigenvalue at ``p = k^2`` and another at ``p = 2 k^2``, known exactly.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp

import contin


def family_problem(keys=(1, 2, 3), sparse: bool = False) -> contin.Problem:
    def op(k, u, p):
        H = np.diag([k * k - u[0], 2.0 * k * k - u[0]])
        return sp.csr_matrix(H) if sparse else H

    family = contin.OperatorFamily("k", keys, op, multiplicity=lambda k: 2)
    return contin.Problem(residual=lambda u, p: np.array([u[0] - p]), jacobian=lambda u, p: np.eye(1),
                          dresidual_dp=lambda u, p: np.array([-1.0]), symmetric=True, operator_families=[family],
                          name="family")


@pytest.mark.parametrize("sparse", [False, True])
def test_every_crossing_is_detected_and_located(sparse: bool) -> None:
    br = contin.continuation(family_problem(sparse=sparse), np.zeros(1), 0.0, ds=0.37, ds_max=0.37, p_max=10.0, stability=True,
                             max_steps=100)
    bif = [s for s in br.special_points if s.kind == "bifurcation"]
    expected = [(1.0, 1), (2.0, 1), (4.0, 2), (8.0, 2), (9.0, 3)]
    assert [(round(s.p, 9), s.info["key"]) for s in bif] == [(p, k) for p, k in expected]
    for s in bif:
        assert s.located and s.info["family"] == "k"
        assert abs(s.info["eigenvalue"]) < 1e-8 * abs(s.info["next_eigenvalue"])
    counts = br.meta["modes"]["k"]
    # each key's eigenvalue nearest zero, estimated per point (diag(k^2 - p, 2 k^2 - p)), while one is
    # clearly nearest (past a crossing the warm start tracks the crossed one for a while)
    for p, lows in zip(br.p[1:], counts["lowest"][1:]):
        if p > 0.9:
            break
        exact = [min((k * k - p, 2 * k * k - p), key=abs) for k in (1, 2, 3)]
        assert lows == pytest.approx(exact, rel=1e-3)  # an estimate: 3 warm-started inverse-iteration steps
    assert counts["keys"] == [1, 2, 3] and counts["n_negative"][0] == [0, 0, 0]
    assert counts["n_negative"][-1] == [2, 2, 1] and len(counts["n_negative"]) == len(br.p)


def test_two_keys_changing_on_one_step_report_the_first_crossing() -> None:
    # one step of 1.5 from p = 7.6 crosses p = 8 (key 2) and p = 9 (key 3)
    br = contin.continuation(family_problem(), np.array([7.6]), 7.6, ds=1.5, ds_max=1.5, p_max=9.5, max_steps=5,
                             stability=True)
    bif = [s for s in br.special_points if s.kind == "bifurcation"]
    assert len(bif) == 1
    assert bif[0].info["key"] == 2 and bif[0].p == pytest.approx(8.0, abs=1e-9)
    assert bif[0].info["also"] == [3] and sorted(bif[0].info["changed_keys"]) == [2, 3]


def test_stop_at_the_first_bifurcation_and_the_mode() -> None:
    br = contin.continuation(family_problem(), np.zeros(1), 0.0, ds=0.3, ds_max=0.3, p_max=10.0, stability=True,
                             stop_at=("bifurcation",))
    assert br.status == "event" and br.p[-1] == pytest.approx(1.0, abs=1e-9)
    mode = br.special_points[-1].info["mode"]
    assert abs(mode[0]) == pytest.approx(1.0) and mode[1] == pytest.approx(0.0, abs=1e-12)


def test_without_stability_nothing_is_watched() -> None:
    br = contin.continuation(family_problem(), np.zeros(1), 0.0, ds=0.3, ds_max=0.3, p_max=3.0, stability=False)
    assert not [s for s in br.special_points if s.kind == "bifurcation"] and "modes" not in br.meta


def test_banded_operators_are_counted_estimated_and_located_like_dense_ones() -> None:
    """A family whose operators are :class:`contin.numerics.linalg.SymmetricBand` (tridiagonal, 80 rows, one
    eigenvalue k^2 - u below the rest): the same crossings, located as sharply."""
    from contin.numerics.linalg import SymmetricBand
    from contin.watch.modes import count_and_lowest, eigenvalues_near_zero

    n = 80
    base = np.linspace(30.0, 60.0, n)

    def op(k, u, p):
        d = base.copy()
        d[n // 2] = k * k - u[0]
        ab = np.zeros((2, n))
        ab[1] = d + 2.0
        ab[0, 1:] = -1.0 * (np.arange(1, n) != n // 2) * (np.arange(1, n) != n // 2 + 1)  # keep the soft row decoupled
        return SymmetricBand(ab)

    K = op(2, np.array([7.0]), 7.0)  # 4 + 2 - 7 = -1
    dense = K.toarray()
    w = np.linalg.eigvalsh(dense)
    count, lowest, _ = count_and_lowest(K, None)
    assert count == int(np.count_nonzero(w < 0)) == 1 and lowest == pytest.approx(w[np.argmin(abs(w))], rel=1e-6)
    near, V = eigenvalues_near_zero(K, 2, vectors=True)
    ref = sorted(w, key=abs)[:2]
    assert near[0] == pytest.approx(ref[0], rel=1e-9)
    assert near[1] == pytest.approx(ref[1], rel=1e-3)  # the next one's own cluster (30.8, 31.7, ...) converges slowly
    assert np.linalg.norm(dense @ V[:, 0] - near[0] * V[:, 0]) < 1e-10
    family = contin.OperatorFamily("k", (1, 2, 3), op)
    prob = contin.Problem(residual=lambda u, p: np.array([u[0] - p]), jacobian=lambda u, p: np.eye(1),
                          dresidual_dp=lambda u, p: np.array([-1.0]), symmetric=True, operator_families=[family],
                          name="band family")
    br = contin.continuation(prob, np.zeros(1), 0.0, ds=0.37, ds_max=0.37, p_max=10.0, stability=True, max_steps=100)
    bif = [s for s in br.special_points if s.kind == "bifurcation"]
    assert [(s.info["key"], round(s.p, 8)) for s in bif] == [(1, 3.0), (2, 6.0)]  # k^2 + 2 - u = 0 below p = 10
    for s in bif:
        assert abs(s.info["eigenvalue"]) < 1e-8 * abs(s.info["next_eigenvalue"])


def test_the_stored_mode_is_the_null_vector_of_the_operator_itself() -> None:
    """``info["mode"]`` is K's own null vector at the located point, not the Jacobi-scaled operator's: on a
    badly scaled operator the two differ."""
    scales = np.array([1.0, 1e4, 1e-3])

    def op(k, u, p):
        A = np.array([[2.0 - u[0], 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 4.0]])
        return A * scales[:, None] * scales[None, :]

    family = contin.OperatorFamily("k", (1,), op)
    prob = contin.Problem(residual=lambda u, p: np.array([u[0] - p]), jacobian=lambda u, p: np.eye(1),
                          dresidual_dp=lambda u, p: np.array([-1.0]), symmetric=True, operator_families=[family],
                          name="scaled")
    br = contin.continuation(prob, np.zeros(1), 0.0, ds=0.3, ds_max=0.3, p_max=3.0, stability=True, max_steps=50)
    bif = [s for s in br.special_points if s.kind == "bifurcation"]
    assert len(bif) == 1
    K = op(1, bif[0].u, bif[0].p)
    mode = bif[0].info["mode"]
    assert np.linalg.norm(mode) == pytest.approx(1.0)
    assert np.linalg.norm(K @ mode) < 1e-9 * np.linalg.norm(K)


def _operators_built_while(monkeypatch: pytest.MonkeyPatch, method: str, second: float) -> tuple[Any, list, set]:
    """Trace the family ``diag(k^2 - u, second k^2 - u)`` (keys 1, 2) to ``p = 5``, recording the keys and states
    at which its operator is built while :class:`contin.watch.modes.ModeTest`'s ``method`` runs: the branch,
    those ``(key, u)`` and the stored parameters."""
    from contin.watch import modes

    calls: list[tuple[int, float, bool]] = []
    locating = [False]

    def op(k, u, p):
        calls.append((k, float(u[0]), locating[0]))
        return np.diag([k * k - u[0], second * k * k - u[0]])

    original = getattr(modes.ModeTest, method)

    def watched(self, *args):
        locating[0] = True
        try:
            return original(self, *args)
        finally:
            locating[0] = False

    monkeypatch.setattr(modes.ModeTest, method, watched)
    family = contin.OperatorFamily("k", (1, 2), op, multiplicity=lambda k: 2)
    prob = contin.Problem(residual=lambda u, p: np.array([u[0] - p]), jacobian=lambda u, p: np.eye(1),
                          dresidual_dp=lambda u, p: np.array([-1.0]), symmetric=True, operator_families=[family],
                          name="family")
    br = contin.continuation(prob, np.zeros(1), 0.0, ds=0.37, ds_max=0.37, p_max=5.0, stability=True, max_steps=100)
    return br, [(k, u) for k, u, during in calls if during], set(float(p) for p in br.p)


def test_the_location_reuses_the_bracket_ends_operators_and_factorizations(monkeypatch: pytest.MonkeyPatch) -> None:
    """The root of the bordered function evaluates the key's operator only at new points on the curve: the
    bracket ends' operators and factorizations are those the counts at those points made."""
    br, in_location, stored = _operators_built_while(monkeypatch, "_bordered_root", 2.0)
    bif = [s for s in br.special_points if s.kind == "bifurcation"]
    assert [(round(s.p, 9), s.info["key"]) for s in bif] == [(1.0, 1), (2.0, 1), (4.0, 2)]
    assert in_location, "the bordered roots evaluated no operator"
    assert not [(k, u) for k, u in in_location if u in stored], "a bracket end's operator was evaluated again"


def test_the_eigenvalues_near_zero_do_not_depend_on_what_the_process_computed_before() -> None:
    # ARPACK draws its start vector from a generator whose state runs on between calls: the same
    # matrix gave eigenvectors that differed in their last digits, and a branch point located with
    # them moved by 1e-9 between a run alone and the same run after others
    from scipy.sparse.linalg import eigsh

    from contin.watch.modes import eigenvalues_near_zero

    rng = np.random.default_rng(7)
    n = 400
    A = sp.random(n, n, density=0.02, random_state=rng)
    H = (A + A.T + sp.diags(np.linspace(-1.0, 3.0, n))).tocsc()
    first = eigenvalues_near_zero(H, k=2, vectors=True)
    eigsh(H, k=3, which="LA")  # anything else the process asks of ARPACK in between
    second = eigenvalues_near_zero(H, k=2, vectors=True)
    assert np.array_equal(first[0], second[0]) and np.array_equal(first[1], second[1])


def _record_bisections(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The indices of the eigenvalues :mod:`contin.watch.modes` bisects from now on (one per evaluation)."""
    from contin.watch import modes

    bisected: list[int] = []
    original = modes.ordered_eigenvalue

    def ordered_eigenvalue(H, index):
        bisected.append(index)
        return original(H, index)

    monkeypatch.setattr(modes, "ordered_eigenvalue", ordered_eigenvalue)
    return bisected


def test_the_eigenvalue_bisection_reuses_the_bracket_ends_operators(monkeypatch: pytest.MonkeyPatch) -> None:
    """A double eigenvalue of a key crosses zero: no bordered function singles out one of the two, and the
    location bisects each on the eigenvalue itself, from the bracket ends' operators as the counts at those
    points built them, not built again."""
    bisected = _record_bisections(monkeypatch)
    br, in_location, stored = _operators_built_while(monkeypatch, "locate", 1.0)
    assert bisected
    bif = [s for s in br.special_points if s.kind == "bifurcation"]
    assert [(round(s.p, 9), s.info["key"], s.info["counts_after"]) for s in bif] == [(1.0, 1, [2, 0]), (4.0, 2, [2, 2])]
    assert in_location, "the location evaluated no operator"
    assert not [(k, u) for k, u in in_location if u in stored], "a bracket end's operator was evaluated again"


def test_a_second_crossing_of_a_key_is_located_by_the_bordered_function(monkeypatch: pytest.MonkeyPatch) -> None:
    """Key ``k``'s second eigenvalue crosses at ``2 k^2`` while the eigenvector estimate still follows the first
    (on a diagonal operator inverse iteration never leaves it): the bordered function of that estimate keeps its
    sign, and the location takes the crossing eigenvalue's own vector instead of bisecting the eigenvalue
    (a banded eigensolve per evaluation)."""
    bisected = _record_bisections(monkeypatch)
    br = contin.continuation(family_problem(), np.zeros(1), 0.0, ds=0.37, ds_max=0.37, p_max=10.0, stability=True,
                             max_steps=100)
    bif = sorted((s.p, s.info["key"]) for s in br.special_points if s.kind == "bifurcation")
    assert [k for _, k in bif] == [1, 1, 2, 2, 3]
    np.testing.assert_allclose([p for p, _ in bif], [1.0, 2.0, 4.0, 8.0, 9.0], rtol=0, atol=1e-9)
    assert all(s.located for s in br.special_points if s.kind == "bifurcation")
    assert not bisected, f"eigenvalues bisected: indices {bisected}"


def test_two_crossings_on_one_step_are_located_by_the_bordered_function(monkeypatch: pytest.MonkeyPatch) -> None:
    """Key ``k``'s two eigenvalues cross at ``k^2`` and ``1.01 k^2``, on one step: each is located by the bordered
    function of its own vector, and the first is reported, without bisecting an eigenvalue."""
    bisected = _record_bisections(monkeypatch)
    br, _, _ = _operators_built_while(monkeypatch, "locate", 1.01)
    bif = [s for s in br.special_points if s.kind == "bifurcation"]
    assert [(s.info["key"], s.info["counts_after"]) for s in bif] == [(1, [2, 0]), (2, [2, 2])]
    np.testing.assert_allclose([s.p for s in bif], [1.0, 4.0], rtol=0, atol=1e-9)
    assert all(s.located for s in bif)
    assert not bisected, f"eigenvalues bisected: indices {bisected}"
