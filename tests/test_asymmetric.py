"""Clamped shallow caps under pressure bifurcate asymmetrically (``studies/asymmetric.py``, issue 17 study (a)).

Expected values are published ones, never our own: Huang (1964) and Teng & Rotter (1989b, Table 3),
``nu = 1/3`` (``docs/asymmetric.md``).  Huang's theory is shallow-shell theory: the apples-to-apples
comparison is our cap near the shallow limit (``R/h = 10000``), which lands within 0.31 % of Huang at
every tabulated lambda.  At the table's ``R/h = 100`` ours is 0.6 to 1.3 % above Teng & Rotter (a
deep-geometry effect, linear in ``h/R``); that test states the offset as a band, not as agreement.
The location checks compare the engine's located bifurcation with an independent bisection in ``p``
on the block's ``L D L^T`` inertia (:func:`studies.asymmetric.bisect_first`).
"""

from __future__ import annotations

import pytest

from studies.asymmetric import HUANG_1964, TENG_ROTTER_1989B, bisect_first, first_instability


@pytest.mark.parametrize("lam", [8.0, 12.0])
def test_shallow_cap_matches_huang(lam):
    """R/h = 10000 (shallow), N = 100: Huang's wave number, and his pressure within 0.5 % (measured 0.02, 0.08 %)."""
    row = first_instability(lam, 100, 10000.0)
    p_h, n_h = HUANG_1964[lam]
    assert row["kind"] == "bifurcation" and row["n"] == n_h
    assert row["p_cr_over_p_c"] == pytest.approx(p_h, rel=0.005)


def test_published_cap_offset_to_teng_rotter():
    """R/h = 100 (the table's cap), lambda = 8, N = 100: n = 4 as published; p_cr 0.86 % above Teng & Rotter.

    The band (0.3 % to 1.5 % above) is the deep-geometry offset of docs/asymmetric.md, not an agreement criterion.
    """
    row = first_instability(8.0, 100)
    p_tr, n_tr = TENG_ROTTER_1989B[8.0]
    assert row["kind"] == "bifurcation" and row["n"] == n_tr
    assert 1.003 < row["p_cr_over_p_c"] / p_tr < 1.015


def test_lambda_5_snaps_axisymmetrically_lambda_6_bifurcates():
    """The change of mechanism between lambda = 5 and 6 (Huang: asymmetric from about 5.5 on).

    lambda = 5: the axisymmetric fold first (0.635 p_c, no block indefinite before it); lambda = 6:
    a bifurcation into n = 2 near Huang's 0.775, well below the axisymmetric snap (1.02 p_c).
    """
    five = first_instability(5.0, 100)
    assert five["kind"] == "fold" and five["p_cr_over_p_c"] == pytest.approx(0.635, abs=0.01)
    counts = five["_branch"].meta["modes"]["n"]["n_negative"]
    assert all(c == 0 for point in counts for c in point)
    six = first_instability(6.0, 100)
    assert six["kind"] == "bifurcation" and six["n"] == 2
    assert six["p_cr_over_p_c"] == pytest.approx(HUANG_1964[6.0][0], rel=0.015)


@pytest.mark.parametrize("lam", [7.0, 16.0])
def test_located_bifurcation_agrees_with_bisection_on_inertia(lam):
    """N = 100: the located pressure within 1e-8 (relative) of the bisection on the block's inertia, and the
    block's smallest eigenvalue below 1e-8 of the next at the located point (measured 2e-10 / 4e-12 and
    4e-11 / 3e-12).  At N = 400 both floors rise to ~1e-8 (the block's norm grows as N^3: eps ||H|| / the next
    eigenvalue is 6e-8 there; docs/asymmetric.md)."""
    row = first_instability(lam, 100)
    assert row["kind"] == "bifurcation"
    bis = bisect_first(row)
    assert bis["n"] == row["n"]
    assert bis["rel_diff"] < 1e-8
    assert bis["eig_ratio"] < 1e-8


@pytest.mark.slow
@pytest.mark.parametrize("lam", [6.0, 16.0])
def test_mesh_converged_and_n_kept(lam):
    """N = 100, 200, 400 at R/h = 100: the same n, and the last refinement changes p_cr by less than 1e-5 p_c."""
    rows = [first_instability(lam, N) for N in (100, 200, 400)]
    assert len({r["n"] for r in rows}) == 1
    assert abs(rows[2]["p_cr_over_p_c"] - rows[1]["p_cr_over_p_c"]) < 1e-5
