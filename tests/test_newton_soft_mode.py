"""Newton at a fixed parameter from a point next to a soft mode (the start of a branch after a snap).

Near a soft mode a residual within the tolerance can leave the state far from the equilibrium: the
residual ``eps y`` of the soft equation is small while ``y`` is not.  Newton's full step then lands
inside the region of quadratic convergence but raises the residual's max-norm (the stiff equation's
``y**2`` term), so a step length chosen by the residual alone shrinks to nothing and the point was
refused as "within tol but the update does not shrink".  The closed form: the only equilibrium is
``x = y = 0``.
"""

from __future__ import annotations

import numpy as np
import pytest

import contin
from contin.path.curve import CorrectorFailure, Curve

EPS = 1e-6  # stiffness of the soft equation
Y0 = 1e-2  # the start's offset along the soft mode: its residual EPS * Y0 is within tol


def soft_mode_problem() -> contin.Problem:
    return contin.Problem(
        residual=lambda u, p: np.array([u[0] - u[1] ** 2, EPS * u[1]]),
        jacobian=lambda u, p: np.array([[1.0, -2.0 * u[1]], [0.0, EPS]]),
        dresidual_dp=lambda u, p: np.zeros(2),
        name="soft mode", residual_scale=1.0)


def test_newton_converges_through_a_residual_that_first_grows() -> None:
    curve = Curve(soft_mode_problem(), contin.Settings(tol=1e-8))
    u, res, iterations = curve.newton_fixed_p(np.array([Y0 ** 2, Y0]), 0.0)
    assert res <= 1e-8
    assert np.max(np.abs(u)) <= 1e-12  # the equilibrium, not the start that only had a small residual
    assert iterations <= 5


def test_a_start_that_is_not_an_equilibrium_is_still_refused() -> None:
    """The test above must not be passed by accepting small residuals: far-off starts still fail."""
    problem = contin.Problem(residual=lambda u, p: np.array([u[0] ** 2 + 1.0]),
                             jacobian=lambda u, p: np.array([[2.0 * u[0]]]),
                             dresidual_dp=lambda u, p: np.zeros(1), name="no root", residual_scale=1.0)
    with pytest.raises(CorrectorFailure):
        Curve(problem, contin.Settings(tol=1e-8)).newton_fixed_p(np.array([0.5]), 0.0)


def test_a_model_whose_float_arithmetic_overflows_reports_a_non_finite_residual() -> None:
    """``x ** 5`` of a Python float raises OverflowError where numpy gives inf: the same event."""
    from contin.problem import NonFiniteError

    problem = contin.Problem(residual=lambda u, p: np.array([float(u[0]) ** 5 - 1.0]),
                             jacobian=lambda u, p: np.array([[5.0 * float(u[0]) ** 4]]),
                             dresidual_dp=lambda u, p: np.zeros(1), name="quintic", residual_scale=1.0)
    with pytest.raises(NonFiniteError, match="not finite"):
        problem.checked_residual(np.array([1e100]), 0.0)
    with pytest.raises(NonFiniteError, match="not finite"):
        problem.checked_jacobian(np.array([1e100]), 0.0)
