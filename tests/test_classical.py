"""Clamped shallow caps under pressure against the classical literature (``studies/classical.py``, issue 16).

The expected values are published ones, never our own: Budiansky (1959) and Teng & Rotter (1989a),
both from Teng & Rotter's Table 1 (``docs/validation.md`` section 3).  Our shallow-limit values sit
about 2 % below Budiansky's and within 0.2 % of Teng & Rotter's; the tolerances below say which.
The clamp test is a consistency check (the edge tangent's rotation vanishes with the mesh), stated as such.
"""

from __future__ import annotations

import pytest

from studies.classical import BUDIANSKY, TENG_ROTTER, snap_pressure


@pytest.mark.parametrize("lam", [4.0, 5.0, 6.0, 7.0, 8.0])
def test_snap_pressure_within_3_percent_of_budiansky(lam):
    """R/h = 400, N = 100: within 3 % of Budiansky (the issue's criterion) and 1 % of Teng & Rotter.

    lambda = 5.5 is left out on purpose: there the curve rises by about 0.7 p_c per unit lambda and
    Budiansky's 0.789 is 5 % above ours (Teng & Rotter's 0.746 is within 0.3 %).
    """
    row = snap_pressure(lam, 100, 400.0)
    p = row["p_snap_over_p_c"]
    assert p == pytest.approx(BUDIANSKY[lam], rel=0.03)
    assert p == pytest.approx(TENG_ROTTER[lam], rel=0.01)


def test_steep_lambda_5_5_matches_teng_rotter():
    """lambda = 5.5 at R/h = 1000: within 0.5 % of Teng & Rotter (1989a), 5 % below Budiansky (1959)."""
    p = snap_pressure(5.5, 100, 1000.0)["p_snap_over_p_c"]
    assert p == pytest.approx(TENG_ROTTER[5.5], rel=0.005)
    assert 0.93 < p / BUDIANSKY[5.5] < 0.97


def test_clamp_holds_the_edge_tangent():
    """Consistency check: at the fold the edge tangent's rotation is a discretisation error (O(N^-2)).

    Halving the spacing divides it by about 4 and it stays below 1e-4 rad, while the pinned edge of
    the same cap turns by 0.04 rad.
    """
    coarse = snap_pressure(6.0, 100, 1000.0)["edge_tangent_rotation"]
    fine = snap_pressure(6.0, 200, 1000.0)["edge_tangent_rotation"]
    pinned = snap_pressure(6.0, 100, 1000.0, boundary="pinned")["edge_tangent_rotation"]
    assert abs(coarse) < 1e-4 and abs(fine) < 0.4 * abs(coarse)
    assert abs(pinned) > 1e-2
