"""Settings validation: tolerances below the roundoff floor are refused up front (issue 14, B5)."""

from __future__ import annotations

import numpy as np
import pytest

import contin

#: the documented floor (contin.settings.ROUNDOFF_FLOOR)
ROUNDOFF_FLOOR = 1e-14


@pytest.mark.parametrize("name", ["tol", "xtol"])
@pytest.mark.parametrize("value", [1e-15, 1e-16, 0.0])
def test_tolerance_below_roundoff_floor_is_refused(name: str, value: float) -> None:
    with pytest.raises(ValueError) as err:  # contin.SettingsError, a ValueError the command line reports as bad input
        contin.Settings(**{name: value}).validate()
    message = str(err.value)
    assert repr(name) in message and f"{ROUNDOFF_FLOOR:g}" in message


def test_tolerance_at_the_floor_is_accepted() -> None:
    from contin.settings import ROUNDOFF_FLOOR as floor

    assert floor == ROUNDOFF_FLOOR
    contin.Settings(tol=ROUNDOFF_FLOOR, xtol=ROUNDOFF_FLOOR).validate()


def test_continuation_refuses_before_tracing() -> None:
    """``tol = 1e-15`` used to be accepted and then failed at the first point; now it is a ValueError."""
    calls = []

    def residual(u, p):
        calls.append(p)
        return u - p

    problem = contin.Problem(residual=residual, jacobian=lambda u, p: np.eye(1))
    with pytest.raises(ValueError, match="'tol'"):
        contin.continuation(problem, np.zeros(1), 0.0, tol=1e-15)
    assert not calls


def test_max_steps_zero_records_the_corrected_start_point_alone() -> None:
    """``max_steps = 0`` corrects the start point at its parameter and records it with its stability, and takes no
    step: the check of a landing before a path goes on from it.  A negative budget is refused, naming the field."""
    def residual(u, p):
        return np.array([u[0] ** 3 - u[0] - p])

    def jacobian(u, p):
        return np.array([[3.0 * u[0] ** 2 - 1.0]])

    problem = contin.Problem(residual=residual, jacobian=jacobian, symmetric=True)
    # the stable equilibrium near u = 1.1 at p = 0.2 (u^3 - u = 0.2), started 1e-2 off it
    exact = 1.0 + 0.2 / 2.0  # a first guess only: the root is found by the corrector
    branch = contin.continuation(problem, np.array([exact]), 0.2, max_steps=0, stability=True)
    assert len(branch) == 1 and branch.status == "max_steps"
    u = float(branch.u[0][0])
    assert abs(u ** 3 - u - 0.2) <= 1e-10 and float(branch.p[0]) == 0.2
    assert int(branch.n_negative[0]) == 0  # 3 u^2 - 1 > 0 at u = 1.088
    with pytest.raises(ValueError, match="'max_steps'"):
        contin.Settings(max_steps=-1).validate()
