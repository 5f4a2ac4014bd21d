"""Issue 17 study (b): the boundary where the paper's caps bifurcate before their limit load (``studies/asymmetric_boundary.py``)."""

from __future__ import annotations

import math

import pytest

from studies.asymmetric_boundary import BoundaryFunction, depth_parameter, root_in_h, trace_curve
from studies.asymmetric_point import cap_row


@pytest.mark.slow
def test_the_root_of_the_boundary_function_separates_the_classified_caps() -> None:
    """The root of ``B`` (one block watched, N = 60) against the classification with every block watched
    (``contin classify``, pole held): 3 % thinner the first bifurcation comes before ``F_max``, 3 % thicker
    after it."""
    B = BoundaryFunction(3, 60)
    h = root_in_h(B, 0.8, 0.015, 0.02, xtol=1e-6)
    assert 10.0 < depth_parameter(0.8, h) < 10.2
    thinner, thicker = cap_row((0.8, 0.97 * h, 60, True)), cap_row((0.8, 1.03 * h, 60, True))
    assert thinner["before_F_max"] and thinner["first_n"] == 3
    assert not thicker["before_F_max"]


@pytest.mark.slow
def test_the_continued_boundary_keeps_its_depth_parameter() -> None:
    """Continued from phi_hat = 0.8 to 0.7 and 0.9, the curve stays on lambda = 10.1 within 0.5 % and every
    point solves B = 0."""
    B = BoundaryFunction(3, 60)
    h0 = root_in_h(B, 0.8, 0.015, 0.02)
    curve = trace_curve(B, 0.8, h0, (0.7, 0.9), ds=0.05)
    assert curve[0]["phi_hat"] == pytest.approx(0.7, abs=1e-9) and curve[-1]["phi_hat"] == pytest.approx(0.9, abs=1e-9)
    lam = [r["lambda"] for r in curve]
    assert max(lam) - min(lam) < 0.005 * min(lam)  # 0.23 % here: lambda grows slowly with phi_hat
    for r in curve:
        assert abs(B(r["phi_hat"], r["h_over_R"])) < 1e-7
        assert r["lambda"] == pytest.approx(depth_parameter(r["phi_hat"], r["h_over_R"]))
    assert all(math.isfinite(v) for v in lam)
