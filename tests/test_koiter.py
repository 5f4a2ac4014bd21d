"""Koiter's coefficients at simple branch points against closed forms and traced branches."""

from __future__ import annotations

import numpy as np
import pytest

import contin
from contin import koiter_coefficients
from contin_models.benchmarks.elastica import EulerColumn
from contin_models.benchmarks.pitchfork import Pitchfork
from contin_models.benchmarks.truss import VonMisesTruss


def test_pitchfork_normal_form():
    # f = (-p u1 + u1^3, u2): the branch u1^2 = p, so p = xi^2 exactly (a = 0, b = 1 without p_c)
    k = koiter_coefficients(Pitchfork(), np.zeros(2), 0.0)
    assert k.symmetric
    assert k.a_abs == 0.0
    assert k.b_abs == pytest.approx(1.0, rel=1e-8)
    assert k.C1 == pytest.approx(-1.0, rel=1e-10)
    assert np.isnan(k.b)  # p_c = 0: no normalised coefficient


@pytest.mark.parametrize("n", [10, 50])
def test_euler_column_against_the_discrete_closed_form(n):
    # On theta = 0 the Hessian is (EI/h) K - P h I; with phi the unit eigenvector of K of the
    # smallest eigenvalue, C1 = -h, C2 = 0, C3 = P_c h sum(phi^4), so b = sum(phi^4) / 6.
    col = EulerColumn(n)
    Pc = col.buckling_load_closed_form()
    _, V = np.linalg.eigh(col._stiffness().toarray())
    b_exact = np.sum(V[:, 0] ** 4) / 6.0
    k = koiter_coefficients(col, np.zeros(n), Pc)
    assert k.symmetric and k.a == 0.0
    assert k.b == pytest.approx(b_exact, rel=1e-7)
    # the continuum elastica: P / P_c = 1 + alpha^2 / 8 in the end rotation alpha = theta_n
    alpha_per_xi = abs(k.null_vector[-1])
    assert k.b / alpha_per_xi ** 2 == pytest.approx(1.0 / 8.0, rel=2.0 / n)


def test_euler_column_against_the_traced_branch():
    col = EulerColumn(50)
    Pc = col.buckling_load_closed_form()
    st = contin.Settings(ds=0.05 * Pc, ds_max=0.1 * Pc)
    bp = contin.continuation(col, np.zeros(50), 0.0, st, p_max=1.5 * Pc).branch_points()[0]
    k = koiter_coefficients(col, bp.u, bp.p, bp.bifurcation.null_vector)
    # the located point carries the same coefficients in its record
    assert bp.bifurcation.koiter["b"] == pytest.approx(k.b, rel=1e-9)
    assert bp.bifurcation.koiter["a"] == 0.0
    post = contin.switch_branch(col, bp, contin.Settings(ds=0.004, ds_max=0.004), p_max=1.02 * Pc)
    xi = np.asarray(post.u) @ k.null_vector
    ratio = (np.asarray(post.p) / bp.p - 1.0) / np.where(xi == 0, np.nan, xi) ** 2
    small = (np.abs(xi) > 0.01) & (np.abs(xi) < 0.5)
    assert small.sum() >= 10
    # ratio = b + O(xi^2): fit both and compare the intercept
    fit = np.linalg.lstsq(np.vstack([np.ones(small.sum()), xi[small] ** 2]).T, ratio[small], rcond=None)[0]
    assert fit[0] == pytest.approx(k.b, rel=1e-6)


def test_refuses_what_it_cannot_answer():
    with pytest.raises(ValueError, match="symmetric"):
        koiter_coefficients(contin.Problem.__new__(_Unsymmetric), np.zeros(2), 0.0)
    # the truss's limit point (closed form L^3 = L0 a^2 on x = 0) is a fold, not a branch point
    truss = VonMisesTruss()
    L = (truss.L0 * truss.a ** 2) ** (1.0 / 3.0)
    y = np.sqrt(L ** 2 - truss.a ** 2)
    P = 2.0 * truss.k * y * (truss.L0 / L - 1.0)
    with pytest.raises(ValueError, match="fold"):
        koiter_coefficients(truss, np.array([0.0, y]), P)


class _Unsymmetric(contin.Problem):
    symmetric = False


class _CoupledModes(contin.Problem):
    """E = (1 - p) x^2 / 2 + y^2 / 2 + c x^2 y + e x^3 + d x^4 / 4: a mode ``x`` that drives ``y``.

    On y = -c x^2 (the second-order field) the energy is (1 - p) x^2 / 2 + e x^3 + (d - 2 c^2) x^4 / 4,
    so the branch leaving (0, 0) at p = 1 is p = 1 + 3 e x + (d - 2 c^2) x^2 + ... (for e = 0 exactly
    to this order).
    """

    def __init__(self, c: float, d: float, e: float = 0.0) -> None:
        super().__init__(symmetric=True, name="coupled_modes", parameter_name="p")
        self.c, self.d, self.e = c, d, e

    def residual(self, u, p):
        x, y = u
        return np.array([(1 - p) * x + 2 * self.c * x * y + 3 * self.e * x ** 2 + self.d * x ** 3, y + self.c * x ** 2])

    def jacobian(self, u, p):
        x, y = u
        return np.array([[1 - p + 2 * self.c * y + 6 * self.e * x + 3 * self.d * x ** 2, 2 * self.c * x],
                         [2 * self.c * x, 1.0]])

    def dresidual_dp(self, u, p):
        return np.array([-u[0], 0.0])


def test_the_second_order_field_enters_b():
    # without the field chi the coefficient would be d = 1, not d - 2 c^2 = 0.5
    k = koiter_coefficients(_CoupledModes(c=0.5, d=1.0), np.zeros(2), 1.0)
    assert k.symmetric
    assert k.b == pytest.approx(0.5, rel=1e-8)


def test_an_asymmetric_point_has_a():
    k = koiter_coefficients(_CoupledModes(c=0.5, d=1.0, e=0.2), np.zeros(2), 1.0)
    assert not k.symmetric
    assert k.a == pytest.approx(0.6, rel=1e-8)
    assert np.isnan(k.b)


class FarFundamentalPath(contin.Problem):
    """``E = k (x - X)^2 / 2 + mu(p) y^2 / 2 + y^4 / 4`` with ``X = 1000`` and ``mu(p) = sin(1 - p)``: the
    fundamental path ``y = 0``, ``x = X`` far from the origin, the branch point at ``p_c = 1`` (``C1 = mu'
    = -1``) and the branch ``y^2 = -mu(p)``, so ``p - p_c = xi^2`` to second order (``b_abs = 1``)."""

    X = 1000.0

    def __init__(self) -> None:
        super().__init__(symmetric=True)

    def residual(self, u, p):
        x, y = u
        return np.array([x - self.X, np.sin(1.0 - p) * y + y ** 3])

    def jacobian(self, u, p):
        x, y = u
        return np.array([[1.0, 0.0], [0.0, np.sin(1.0 - p) + 3.0 * y ** 2]])

    def dresidual_dp(self, u, p):
        return np.array([0.0, -np.cos(1.0 - p) * u[1]])


def test_the_traced_tangent_is_differenced_on_the_parameters_scale():
    """A state far from zero (max|u| = 1000) must not make the difference step along the traced tangent
    move the parameter by the state's scale: C1 is the critical eigenvalue's rate along the path."""
    k = koiter_coefficients(FarFundamentalPath(), np.array([1000.0, 0.0]), 1.0)
    assert k.C1 == pytest.approx(-1.0, rel=1e-8)
    assert k.b_abs == pytest.approx(1.0, rel=1e-6)
