"""Key numbers of ``studies.appendix_b``: the paper's appendix B caps on the paths they take."""

from __future__ import annotations

import pytest

from studies.appendix_b import run_cap


def test_the_cap_of_09_leaves_its_axisymmetric_path_after_the_force_maximum_and_still_everts() -> None:
    """phi_hat = 0.9 (N = 40, K = 2): past its force maximum the cap snaps sideways into one wave (the pole slides),
    the one-wave branch ends at a fold in the deflection, and the cap snaps onto the axisymmetric everted branch.  The
    maximum is the axisymmetric one; the minimum is not reached by the path taken, so the force falls less deep.
    Each snap releases energy (the jump's two energies, each of the shell at its state)."""
    run = run_cap(0.9, 40, 2)
    row, pieces = run["row"], run["pieces"]
    order = [p["symmetry"] if "symmetry" in p else f"snap to {p['landing']}" for p in pieces]
    # with more harmonics the one-wave branch has more folds, each a snap within D1: the ends are what it does
    assert order[:3] == ["O(2)", "snap to D1", "D1"] and order[-2:] == ["snap to O(2)", "O(2)"]
    assert set(order[2:-2]) <= {"D1", "snap to D1"}
    assert pieces[0]["ended"] == "bifurcation" and pieces[-3]["ended"] == "fold" and pieces[-1]["ended"] == "end of load"
    assert row["first_n"] == 1 and row["axi_w_F_max"] < row["first_w"] < row["axi_snap_w"]
    assert row["followed_F_max"] == pytest.approx(row["axi_F_max"], rel=1e-12)
    assert row["axi_class"] == row["followed_class"] == "bistable"
    assert row["axi_F_min"] < row["followed_F_min"] < 0.0
    assert all(p["energy_released"] > 0.0 for p in pieces if "energy_released" in p)
    assert row["everts"]


@pytest.mark.slow
def test_the_cap_of_06_turns_into_three_waves_then_snaps_through_one_wave() -> None:
    """phi_hat = 0.6 (N = 80, K = 2): the cap turns into three waves before its force maximum (which it then never
    reaches), snaps from that branch into one wave and from there onto the everted branch."""
    run = run_cap(0.6, 80, 2)
    row, pieces = run["row"], run["pieces"]
    order = [p["symmetry"] if "symmetry" in p else f"snap to {p['landing']}" for p in pieces]
    assert order == ["O(2)", "D3", "snap to D1", "D1", "snap to O(2)", "O(2)"]
    assert row["first_n"] == 3 and row["first_w"] < row["axi_w_F_max"]
    assert row["followed_F_max"] < row["axi_F_max"]
    assert row["followed_class"] == "bistable" and row["everts"]
