"""Deflation (contin.deflate, contin.deflated_branches): solutions at one parameter that no traced branch
reaches, against closed forms and against Newton on the same equations written here.

* Bratu (1-D, finite differences) below its fold: from the lower solution alone deflation finds the
  upper one; both agree with Newton on the discrete equations written here, and converge to the
  continuum closed form at second order.
* The deflated step is Newton's step for ``M f`` (a dense finite-difference Jacobian of ``M f`` here).
* An isola (contin_models.benchmarks.isola): found from the trivial solution, traced once round to a
  closed loop, the second point where it crosses ``p`` recognised, a cycle of its own in the diagram.
* The pitchfork normal form at ``p > 0``: its three solutions.
* Failures are reported, never raised, and no NaN is returned; bad settings and states are refused.
"""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest
import scipy.linalg as sla

import contin
from contin.analyses.deflation import DeflationOperator
from contin.path.curve import Curve
from contin_models.benchmarks.bratu import Bratu
from contin_models.benchmarks.isola import Isola
from contin_models.benchmarks.pitchfork import Pitchfork

LAM = 1.0


def bratu_newton(n: int, lam: float, u: np.ndarray) -> np.ndarray:
    """Newton on ``-(u_{i-1} - 2 u_i + u_{i+1}) / h - lam h exp(u_i) = 0`` (zero ends), written here."""
    h = 1.0 / (n + 1)
    u = np.array(u, dtype=float)
    for _ in range(50):
        padded = np.concatenate([[0.0], u, [0.0]])
        f = -(padded[:-2] - 2 * u + padded[2:]) / h - lam * h * np.exp(u)
        band = np.zeros((3, n))
        band[0, 1:] = band[2, :-1] = -1.0 / h
        band[1] = 2.0 / h - lam * h * np.exp(u)
        du = sla.solve_banded((1, 1), band, -f)
        u += du
        if np.max(np.abs(du)) <= 1e-14 * (1.0 + np.max(np.abs(u))):
            return u
    raise AssertionError("the test's Newton did not converge")


def continuum_thetas(lam: float) -> tuple[float, float]:
    """The two roots of ``theta = sqrt(2 lam) cosh(theta / 4)`` below the fold, by bisection."""
    def g(t: float) -> float:
        return t - math.sqrt(2 * lam) * math.cosh(t / 4)
    # g > 0 between the roots; its maximum is where sinh(theta / 4) = 4 / sqrt(2 lam)
    peak = 4 * math.asinh(4 / math.sqrt(2 * lam))
    roots = []
    for lo, hi in ((0.0, peak), (peak, 100.0)):
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if (g(mid) < 0) == (g(lo) < 0) else (lo, mid)
        roots.append(0.5 * (lo + hi))
    return roots[0], roots[1]


def continuum_bratu(x: np.ndarray, theta: float) -> np.ndarray:
    return -2.0 * np.log(np.cosh((x - 0.5) * theta / 2) / np.cosh(theta / 4))


def bratu_pair(n: int) -> tuple[Bratu, np.ndarray, np.ndarray, contin.DeflationResult]:
    """The model, the lower solution (the test's Newton), the upper one of the test's Newton, and deflation's result."""
    model = Bratu(n)
    lower_theta, upper_theta = continuum_thetas(LAM)
    lower = bratu_newton(n, LAM, continuum_bratu(model.x, lower_theta))
    upper = bratu_newton(n, LAM, continuum_bratu(model.x, upper_theta))
    return model, lower, upper, contin.deflate(model, LAM, [lower])


def test_bratu_upper_solution_from_the_lower_one_alone():
    model, lower, upper, found = bratu_pair(200)
    assert max(np.abs(lower - upper)) > 1.0  # two distinct solutions below the fold
    assert len(found.solutions) == 1, found.summary()
    assert np.max(np.abs(found.solutions[0] - upper)) <= 1e-9 * np.max(np.abs(upper))
    first = found.attempts[0]
    assert first.status == "converged" and first.factorizations == first.iterations
    assert first.residual <= 1e-10 * model.residual_scale


def test_bratu_solutions_converge_to_the_continuum_closed_form():
    errors = {}
    for n in (100, 200):
        model, lower, _, found = bratu_pair(n)
        thetas = continuum_thetas(LAM)
        errors[n] = [float(np.max(np.abs(u - continuum_bratu(model.x, theta))))
                     for u, theta in zip((lower, found.solutions[0]), thetas)]
    for coarse, fine in zip(errors[100], errors[200]):
        # the scheme's error is c h^2: halving h (n + 1 = 101 -> 201) divides it by (201/101)^2
        assert coarse / fine == pytest.approx((201 / 101) ** 2, rel=0.02)
    assert max(errors[200]) < 1e-3  # the other root is O(1) away


def test_the_deflated_step_is_newtons_step_for_the_deflated_residual():
    model = Bratu(8)
    rng = np.random.default_rng(3)
    known = [rng.normal(size=8), rng.normal(size=8)]
    u = rng.normal(size=8)
    curve = Curve(model, contin.Settings(state_weight=3.0))
    q, sigma = 2.0, 1.0

    def deflated(v: np.ndarray) -> np.ndarray:
        factor = np.prod([1.0 / (3.0 * np.linalg.norm(v - r) / math.sqrt(8)) ** q + sigma for r in known])
        return factor * model.residual(v, LAM)

    h = 1e-6
    jac = np.column_stack([(deflated(u + h * e) - deflated(u - h * e)) / (2 * h) for e in np.eye(8)])
    newton = -np.linalg.solve(jac, deflated(u))
    op = DeflationOperator(curve, known, q, sigma)
    step = op.step(u, model.residual(u, LAM), model.factorize(model.jacobian(u, LAM)))
    assert np.max(np.abs(step - newton)) <= 1e-6 * np.max(np.abs(newton))


@pytest.mark.parametrize("p", [0.25, 2.0])
def test_pitchfork_three_solutions_all_found(p):
    found = contin.deflate(Pitchfork(), p, [np.zeros(2)])
    states = sorted(found.solutions, key=lambda u: u[0])
    assert len(states) == 2, found.summary()
    root = math.sqrt(p)
    for u, expected in zip(states, ([-root, 0.0], [root, 0.0])):
        assert u == pytest.approx(expected, abs=1e-12)


def test_pitchfork_halves_are_one_branch():
    result = contin.deflated_branches(Pitchfork(), 0.25, known_states=[np.zeros(2)], p_min=-0.5, p_max=1.0)
    assert len(result.deflation.solutions) == 2
    assert result.traced == [0] and result.same_as == {1: 0}
    assert [br.status for br in result.branches] == ["bound", "bound"]
    for br in result.branches:
        assert np.max(np.abs(br.p - br.u[:, 0] ** 2)) <= 1e-9  # the parabola p = u1^2
    folds = [spt for br in result.branches for spt in br.special_points if spt.kind == "fold"]
    assert len(folds) == 1 and abs(folds[0].p) <= 1e-8


def isola_setup():
    model = Isola()
    trivial = [contin.continuation(model, np.zeros(2), 0.0, p_min=-2.0, p_max=3.0, direction=d) for d in (1, -1)]
    return model, trivial, contin.deflated_branches(model, 0.0, trivial)


def test_isola_found_from_the_trivial_solution_and_traced_round_once():
    model, trivial, result = isola_setup()
    assert all(br.status == "bound" and not br.branch_points() for br in trivial)  # nothing leads off it
    assert len(result.deflation.known) == 1 and np.all(result.deflation.known[0] == 0.0)
    xis = sorted(model.xi(u) for u in result.deflation.solutions)
    assert xis == pytest.approx(sorted(model.isola_amplitudes(0.0)), abs=1e-12)
    assert all(abs(-model.s * u[0] + model.c * u[1]) <= 1e-12 for u in result.deflation.solutions)
    assert len(result.traced) == 1 and len(result.same_as) == 1
    (loop,) = result.branches
    assert loop.status == "closed_loop" and loop.success, loop.message
    circle = [(model.xi(u) - model.a) ** 2 + (p - model.b) ** 2 - model.rho ** 2 for u, p in zip(loop.u, loop.p)]
    assert np.max(np.abs(circle)) <= 1e-9
    folds = sorted(spt.p for spt in loop.special_points if spt.kind == "fold")
    assert folds == pytest.approx([model.b - model.rho, model.b + model.rho], abs=1e-8)
    assert np.max(np.abs(loop.u[-1] - loop.u[0])) <= 1e-9 and abs(loop.p[-1] - loop.p[0]) <= 1e-9
    assert loop.p.min() >= model.b - model.rho - 1e-9 and loop.p.max() <= model.b + model.rho + 1e-9


def test_isola_is_a_cycle_of_its_own_in_the_diagram():
    _, trivial, result = isola_setup()
    G = contin.diagram([*trivial, *result.branches])
    cycles = list(nx.simple_cycles(nx.DiGraph(G)))
    assert len(cycles) == 1
    assert sorted(G.nodes[node]["kind"] for node in cycles[0]) == ["fold", "fold", "start"]
    assert not nx.is_weakly_connected(G)  # the isola meets no other branch


class InMillimetres(Isola):
    """The isola with its state in units a thousand times smaller."""

    K = 1000.0

    def residual(self, u, p):
        return super().residual(u / self.K, p)

    def jacobian(self, u, p):
        return super().jacobian(u / self.K, p) / self.K

    def dresidual_dp(self, u, p):
        return super().dresidual_dp(u / self.K, p)

    def energy(self, u, p):
        return super().energy(u / self.K, p)


def test_a_model_in_other_units_deflates_alike():
    outer = Isola().state(max(Isola().isola_amplitudes(0.0)))
    runs = [contin.deflate(model, 0.0, [scale * outer]) for model, scale in ((Isola(), 1.0), (InMillimetres(), 1e3))]
    assert [(a.status, a.iterations) for a in runs[0].attempts] == [(a.status, a.iterations) for a in runs[1].attempts]
    # from the isola's outer point: its inner point and the trivial solution
    xis = sorted(Isola().xi(u) for u in runs[0].solutions)
    assert xis == pytest.approx([0.0, min(Isola().isola_amplitudes(0.0))], abs=1e-12)
    for mine, theirs in zip(runs[0].solutions, runs[1].solutions):
        assert np.max(np.abs(theirs / 1e3 - mine)) <= 1e-12


def test_known_states_come_from_the_given_branches():
    model = Bratu(100)
    lower = contin.continuation(model, np.zeros(100), 0.0, p_max=2.0)
    result = contin.deflated_branches(model, LAM, [lower], p_min=0.5, p_max=3.6)
    expected = bratu_newton(100, LAM, continuum_bratu(model.x, continuum_thetas(LAM)[0]))
    (known,) = result.deflation.known
    assert np.max(np.abs(known - expected)) <= 1e-9
    assert len(result.deflation.solutions) == 1 and result.traced == [0]
    assert len(result.branches) == 2 and all(br.success for br in result.branches)
    assert all(br.meta["deflation"] == {"p": LAM, "solution": 0} for br in result.branches)


# ---- failures: reported, never raised, never a NaN --------------------------------------------------------

def assert_no_nan(found: contin.DeflationResult) -> None:
    assert all(np.isfinite(u).all() for u in found.solutions)
    assert all(a.u is None or np.isfinite(a.u).all() for a in found.attempts)
    assert all(a.message for a in found.attempts)


def test_a_start_with_no_solution_ahead_is_reported_diverged():
    found = contin.deflate(Pitchfork(), 0.25, [np.zeros(2)], starts=[[0.0, 0.1]])
    assert found.solutions == [] and [a.status for a in found.attempts] == ["diverged"]
    assert_no_nan(found)


def test_a_start_where_the_model_overflows_is_reported():
    found = contin.deflate(Bratu(50), LAM, [np.zeros(50)], starts=[np.full(50, 800.0)])
    (attempt,) = found.attempts
    assert attempt.status == "diverged" and "not finite" in attempt.message
    assert_no_nan(found)


def test_a_singular_jacobian_is_reported():
    found = contin.deflate(Pitchfork(), 0.0, [], starts=[[0.0, 0.1]])
    (attempt,) = found.attempts
    assert attempt.status == "diverged" and "no Newton step" in attempt.message
    assert_no_nan(found)


def test_a_start_on_a_known_solution_is_reported():
    found = contin.deflate(Pitchfork(), 0.25, [np.zeros(2)], starts=[np.zeros(2)])
    assert [a.status for a in found.attempts] == ["known"] and found.solutions == []


class NotFiniteBeyond(contin.Problem):
    """``f = u (u - 1) (u - 2)``, NaN for ``u > 1.5``: the root at 2 lies where the model is not finite."""

    def __init__(self) -> None:
        super().__init__(name="not finite beyond 1.5", residual_scale=1.0)

    def residual(self, u, p):
        return np.where(u > 1.5, np.nan, u * (u - 1) * (u - 2))

    def jacobian(self, u, p):
        return np.atleast_2d(np.where(u > 1.5, np.nan, 3 * u ** 2 - 6 * u + 2))

    def dresidual_dp(self, u, p):
        return np.zeros(1)


def test_iterates_where_the_model_is_not_finite_return_no_nan():
    found = contin.deflate(NotFiniteBeyond(), 0.0, [np.zeros(1)], starts=[[0.1]])
    assert len(found.solutions) == 1 and found.solutions[0] == pytest.approx([1.0], abs=1e-12)
    assert [a.status for a in found.attempts] == ["converged", "diverged"]
    assert_no_nan(found)


def test_bad_settings_and_states_are_refused():
    with pytest.raises(contin.SettingsError, match="'power'"):
        contin.deflate(Pitchfork(), 0.25, [np.zeros(2)], deflation=contin.DeflationSettings(power=1.0))
    with pytest.raises(ValueError, match=r"starts\[0\] has 3 entries"):
        contin.deflate(Pitchfork(), 0.25, [np.zeros(2)], starts=[np.zeros(3)])
    with pytest.raises(ValueError, match=r"known_states\[0\] is not finite"):
        contin.deflate(Pitchfork(), 0.25, [np.array([np.nan, 0.0])])
    with pytest.raises(ValueError, match="nothing to start from"):
        contin.deflate(Pitchfork(), 0.25, [])
    away = contin.continuation(Pitchfork(), np.zeros(2), -1.0, p_max=-0.5)  # never reaches p = 0.25
    with pytest.raises(ValueError, match="no known state at this parameter"):
        contin.deflated_branches(Pitchfork(), 0.25, [away])
