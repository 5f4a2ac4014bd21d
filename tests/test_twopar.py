"""Fold curves in a second parameter (:class:`contin.analyses.twopar.FoldCurveProblem`), against closed forms.

* Cusp normal form ``f = u^3 - q u - p``: folds at ``u = +-sqrt(q/3)``, ``p = -+2 (q/3)^(3/2)``, meeting
  at the cusp ``q = 0``; the gap between the two fold loads is ``4 (q/3)^(3/2)`` (the 3/2 law).
* Von Mises truss: the limit load ``P_max(b)`` as the height ``b`` changes, from the truss's closed form.
* The shell under a dead point load (issue 5): the force-control fold continued in ``h`` is the fold
  an independent force-controlled trace locates at the same ``h``; near the cusp where the two folds
  meet (the monostable/monotonous boundary), ``F_max - F_min`` vanishes like the 3/2 power of the
  distance in ``h``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import contin
from contin.analyses.twopar import FoldCurveProblem
from contin_models.benchmarks.truss import VonMisesTruss
from contin_models.shell import ShellPointLoad
from tests.cusp_check import assert_three_halves_law


class CuspNormalForm(contin.Problem):
    """``f(u, p; q) = u^3 - q u - p``."""

    def __init__(self, q: float) -> None:
        super().__init__(symmetric=True, name="cusp", parameter_name="p")
        self.q = float(q)
        self._obs = {"u": lambda u, p: float(u[0])}

    @property
    def observables(self):
        return self._obs

    def residual(self, u, p):
        return np.array([u[0] ** 3 - self.q * u[0] - p])

    def jacobian(self, u, p):
        return np.array([[3 * u[0] ** 2 - self.q]])

    def dresidual_dp(self, u, p):
        return np.array([-1.0])


def _cusp_curve(stop: bool) -> tuple[FoldCurveProblem, contin.Branch]:
    u0 = 1 / math.sqrt(3)
    fp = FoldCurveProblem(CuspNormalForm, ([u0], u0 ** 3 - u0), 1.0)
    br = contin.continuation(fp, fp.start, 1.0, ds=0.05, ds_max=0.1, p_min=-0.1, p_max=1.0, direction=-1,
                             max_steps=400, stop_at=("fold",) if stop else (), stability=False)
    return fp, br


def test_cusp_is_located_as_the_fold_of_the_fold_curve():
    _, br = _cusp_curve(stop=True)
    assert br.status == "event"
    (cusp,) = [s for s in br.special_points if s.kind == "fold"]
    assert cusp.located and abs(cusp.p) < 1e-10 and abs(cusp.u[1]) < 1e-12


def test_fold_curve_follows_the_closed_form_through_the_cusp_and_the_three_halves_law():
    fp, br = _cusp_curve(stop=False)
    assert br.status == "bound" and br.p[-1] == pytest.approx(1.0)  # back out to q = 1 on the other fold
    u, p, q = br.u[:, 0], br.u[:, 1], br.p
    assert np.all(q > -1e-12)
    assert np.max(np.abs(np.abs(u) - np.sqrt(np.maximum(q, 0) / 3))) < 1e-8
    assert np.max(np.abs(p + 2 * np.sign(u) * (np.maximum(q, 0) / 3) ** 1.5)) < 1e-10
    # the gap between the two fold loads at the same q, from events located on either side of the cusp
    qs = (0.01, 0.02, 0.04, 0.08)
    br = contin.continuation(fp, fp.start, 1.0, ds=0.05, ds_max=0.1, p_min=-0.1, p_max=1.0, direction=-1,
                             max_steps=400, stability=False, events=[contin.crossing("q", v) for v in qs])
    gap = []
    for v in qs:
        a, b = (fp.split(e.u)[1] for e in br.events(f"q={v:g}"))
        gap.append(abs(a - b))
    slope = np.polyfit(np.log(qs), np.log(gap), 1)[0]
    assert slope == pytest.approx(1.5, abs=1e-6)


def test_truss_limit_load_follows_its_closed_form_in_the_height():
    (y0, P0), _ = VonMisesTruss(1.0, 0.5, 1.0).limit_points()
    fp = FoldCurveProblem(lambda b: VonMisesTruss(1.0, b, 1.0), ([0.0, y0], P0), 0.5, q_name="b")
    for direction, bound in ((1, {"p_max": 1.0}), (-1, {"p_min": 0.2})):
        br = contin.continuation(fp, fp.start, 0.5, ds=0.02, ds_max=0.05, direction=direction, max_steps=200,
                                 stability=False, **bound)
        assert br.status == "bound"
        for U, b in zip(br.u, br.p):
            (y_star, P_max), _ = VonMisesTruss(1.0, b, 1.0).limit_points()
            assert U[1] == pytest.approx(y_star, abs=1e-9) and U[2] == pytest.approx(P_max, abs=1e-9)
        assert br.observables["b"][-1] == pytest.approx(1.0 if direction > 0 else 0.2)


N_SHELL = 40


def _force_fold(h: float) -> contin.SpecialPoint:
    """F_max of the dead-loaded shell at thickness h, from its own force-controlled trace."""
    P = ShellPointLoad(N=N_SHELL, h=h, phi_hat=0.8, control="force")
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.5, ds_max=5.0, stop_at=("fold",), stability=False,
                             max_steps=500, param_weight=1.0 / (10 * 2 * math.pi * P.D))
    assert br.status == "event", br.message
    return br.special_points[-1]


@pytest.fixture(scope="module")
def shell_fold_curve():
    h0 = 0.12
    fold = _force_fold(h0)
    D = ShellPointLoad(N=N_SHELL, h=h0, phi_hat=0.8).D
    fp = FoldCurveProblem(lambda h: ShellPointLoad(N=N_SHELL, h=h, phi_hat=0.8, control="force"), fold, h0,
                          q_name="h", p_scale=100 * 2 * math.pi * D)
    # through the cusp: up in h along the F_max fold, back down along the F_min fold
    br = contin.continuation(fp, fp.start, h0, ds=0.001, ds_max=0.005, p_min=0.1, max_steps=300, stability=False)
    (cusp,) = [s for s in br.special_points if s.kind == "fold"]
    # again, with the loads of both folds located at fixed distances below the cusp
    events = [contin.crossing("h", cusp.p - d, name=f"d={d:g}") for d in CUSP_DISTANCES]
    br2 = contin.continuation(fp, fp.start, h0, ds=0.001, ds_max=0.005, p_min=0.1, max_steps=300, stability=False,
                              events=events)
    return fp, br, cusp, br2


CUSP_DISTANCES = (1e-4, 2e-4, 4e-4, 8e-4)


def test_shell_fold_curve_matches_independent_force_traces(shell_fold_curve):
    fp, br, cusp, _ = shell_fold_curve
    assert cusp.located
    h_cusp = cusp.p
    h = 0.5 * (0.12 + h_cusp)
    k = int(np.argmin(np.abs(br.p[: np.searchsorted(br.p, h_cusp)] - h)))
    ref = _force_fold(float(br.p[k]))
    assert fp.split(br.u[k])[1] == pytest.approx(ref.p, rel=1e-7)


def test_shell_folds_merge_at_a_cusp_with_the_three_halves_law(shell_fold_curve):
    fp, _, cusp, br = shell_fold_curve
    # the cusp lies at lambda ~ 3.7, near the paper's monotonous boundary lambda_d = 3.65 (N = 40 here)
    lam = (12 * (1 - 0.5 ** 2)) ** 0.25 * (math.pi / 2 - 0.8) * math.sqrt(1 / cusp.p)
    assert 3.5 < lam < 3.9
    assert_three_halves_law(fp, br, CUSP_DISTANCES)


class UnfoldedCusp(contin.Problem):
    """``f(u, p; q, r) = u^3 + r u^2 - q u - p``: its cusp in ``(p, q)`` sits at ``q = -r^2 / 3``, ``u = -r / 3``."""

    def __init__(self, q: float, r: float) -> None:
        super().__init__(symmetric=True, name="unfolded_cusp", parameter_name="p")
        self.q, self.r = float(q), float(r)
        self._obs = {"u": lambda u, p: float(u[0])}

    @property
    def observables(self):
        return self._obs

    def residual(self, u, p):
        return np.array([u[0] ** 3 + self.r * u[0] ** 2 - self.q * u[0] - p])

    def jacobian(self, u, p):
        return np.array([[3 * u[0] ** 2 + 2 * self.r * u[0] - self.q]])

    def dresidual_dp(self, u, p):
        return np.array([-1.0])


def test_cusp_curve_problem_follows_the_closed_form():
    r0 = 0.3
    u0 = 1 / math.sqrt(3)  # a fold of the r = r0 member: f_u = 0 there, at q0
    q0 = 3 * u0 ** 2 + 2 * r0 * u0
    fold = ([u0], u0 ** 3 + r0 * u0 ** 2 - q0 * u0)
    fc = FoldCurveProblem(lambda q: UnfoldedCusp(q, r0), fold, q0, q_name="q", q_step=1e-5)
    br = contin.continuation(fc, fc.start, q0, ds=0.05, ds_max=0.1, direction=-1, p_min=-1.0, max_steps=400,
                             stop_at=("fold",), stability=False)
    (cusp,) = [s for s in br.special_points if s.kind == "fold"]
    assert cusp.p == pytest.approx(-r0 ** 2 / 3, abs=1e-8)
    cc = contin.cusp_curve_problem(lambda r, q: UnfoldedCusp(q, r), fc, cusp, r0, r_name="r", r_step=1e-5)
    for direction, end in ((1, 0.8), (-1, -0.5)):
        curve = contin.continuation(cc, cc.start, r0, ds=0.02, ds_max=0.05, p_min=-0.5, p_max=0.8, max_steps=400,
                                    stability=False, direction=direction)
        assert curve.status == "bound" and curve.p[-1] == pytest.approx(end)
        r, U = curve.p, curve.u
        assert np.max(np.abs(U[:, -1] - (-r ** 2 / 3))) < 1e-6  # q on the cusp curve
        assert np.max(np.abs(U[:, 0] + r / 3)) < 1e-5  # u at the cusp


def test_family_problem_given_a_base_builds_only_the_members_it_evaluates():
    """With a member to take its settings from, a family builds nothing when it is made and nothing to
    ask for a domain filter its members do not have; it evaluates as the family that built its own."""
    built = []

    def family(q):
        built.append(q)
        return CuspNormalForm(q)

    base = CuspNormalForm(5.0)
    fam = contin.FamilyProblem(family, 0.25, 2.0, q_name="q", q_step=1e-5, base=base)
    assert built == [] and fam.symmetric and set(fam.observables) == {"u", "q"}
    assert fam.max_step_fraction(np.array([0.3]), 2.1, np.array([1.0]), 0.5) == 1.0 and built == []
    own = contin.FamilyProblem(CuspNormalForm, 0.25, 2.0, q_name="q", q_step=1e-5)
    u = np.array([0.3])
    np.testing.assert_array_equal(fam.residual(u, 2.1), own.residual(u, 2.1))
    np.testing.assert_array_equal(fam.dresidual_dp(u, 2.1), own.dresidual_dp(u, 2.1))
    assert fam.observables["u"](u, 2.1) == own.observables["u"](u, 2.1)
    assert built == [2.1, 2.1 + 1e-5, 2.1 - 1e-5]


def test_family_problem_folds_in_the_second_parameter_at_fixed_load():
    """``u^3 - q u = p0`` at fixed ``p0 > 0`` as a problem in ``q``: its fold is at ``q = 3 (p0/2)^(2/3)``."""
    p0 = 0.25
    q0 = 2.0
    fam = contin.FamilyProblem(CuspNormalForm, p0, q0, q_name="q", q_step=1e-5)
    u_mid = sorted(np.roots([1.0, 0.0, -q0, -p0]).real)[1]  # the middle root: it meets the lowest at the fold
    br = contin.continuation(fam, np.array([u_mid]), q0, ds=0.05, ds_max=0.1, max_steps=400, p_min=-1, p_max=3,
                             direction=-1, stop_at=("fold",), stability=False)
    (fold,) = [s for s in br.special_points if s.kind == "fold"]
    # folds of u^3 - q u - p0 in q: 3u^2 = q and u^3 - q u = p0  =>  u = -(p0/2)^(1/3)
    assert fold.p == pytest.approx(3 * (p0 / 2) ** (2 / 3), abs=1e-8)
    assert fold.u[0] == pytest.approx(-(p0 / 2) ** (1 / 3), abs=1e-7)
