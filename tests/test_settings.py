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
