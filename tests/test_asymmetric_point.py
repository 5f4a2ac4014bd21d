"""The paper's point-loaded caps with every mode watched (``studies/asymmetric_point.py``, issue 17 study (b)).

Shallow-shell theory makes a boundary between behaviours of a point-loaded shallow cap a curve of
constant depth parameter ``lambda = (12 (1 - nu^2))^(1/4) (pi/2 - phi_hat) / sqrt(h/R)``: the located
boundary where the first bifurcation reaches the limit load must lie at one ``lambda`` for different
base angles (measured 10.07 to 10.11 for phi_hat = 0.6 to 0.9 at N = 100).
"""

from __future__ import annotations

import math

import pytest

from studies.asymmetric_point import boundary_point, cap_row


def _lambda(phi_hat: float, h: float) -> float:
    return (12 * 0.75) ** 0.25 * (math.pi / 2 - phi_hat) / math.sqrt(h)


@pytest.mark.slow
def test_the_bifurcation_reaches_the_limit_load_at_one_depth_parameter() -> None:
    a = boundary_point(0.7, 0.01, 0.04, 100)
    b = boundary_point(0.9, 0.005, 0.02, 100)
    assert a["n_at_boundary"] == b["n_at_boundary"] == 3
    assert _lambda(0.7, a["h_over_R"]) == pytest.approx(_lambda(0.9, b["h_over_R"]), rel=0.01)


@pytest.mark.slow
def test_a_thin_deep_cap_bifurcates_before_its_limit_load() -> None:
    row = cap_row((0.6, 0.01, 60, True))
    assert row["class"] == "bistable" and row["before_F_max"] and row["first_n"] == 3
