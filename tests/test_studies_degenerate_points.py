"""studies/degenerate_points.py: how it reads a branch against closed-form special points.

The study itself runs the engine on four models for about half a minute; here only its judgement is
checked, on a hand-made branch and on the pitchfork normal form, whose branch point the engine locates.
"""

from __future__ import annotations

import numpy as np

import contin
from contin_models.benchmarks.pitchfork import Pitchfork
from studies.degenerate_points import Expected, index_change_across, judge, unexplained_index_changes


def hand_made_branch(n_negative: list[int], special: list[contin.SpecialPoint] = ()) -> contin.Branch:
    m = len(n_negative)
    p = np.arange(m, dtype=float)
    return contin.Branch(p=p, u=np.zeros((m, 2)), s=p.copy(), tangent_p=np.ones(m), residual=np.zeros(m),
                         newton_iterations=np.ones(m, dtype=int), n_negative=np.array(n_negative),
                         special_points=list(special), status="bound")


def test_a_jump_by_two_with_nothing_reported_is_silent_and_unexplained() -> None:
    br = hand_made_branch([0, 0, 2, 2])
    assert index_change_across(br, 1.5) == (0, 2)
    assert judge(br, Expected("branch_point", 1.5, 2, "double"))["verdict"] == "silent"
    assert judge(br, Expected("branch_point", 7.0, 2, "beyond"))["verdict"] == "not reached"
    (change,) = unexplained_index_changes(br)
    assert (change["p_from"], change["p_to"], change["index_from"], change["index_to"]) == (1.0, 2.0, 0, 2)


def test_a_simple_point_reported_for_a_double_one_accounts_for_one_change() -> None:
    record = contin.Bifurcation(multiplicity=1, kernel=np.array([[1.0, 0.0]]), directions=np.zeros((0, 3)),
                                kind="pitchfork")
    point = contin.SpecialPoint("branch_point", 1.5, np.zeros(2), located=True, index=1, bifurcation=record)
    br = hand_made_branch([0, 0, 2, 2], [point])
    row = judge(br, Expected("branch_point", 1.5, 2, "double"))
    assert row["verdict"] == "as simple" and row["engine"] == "branch_point (pitchfork, multiplicity 1)"
    assert len(unexplained_index_changes(br)) == 1
    assert judge(br, Expected("branch_point", 1.5, 1, "simple"))["verdict"] == "ok"
    assert judge(br, Expected("fold", 1.5, 1, "a fold"))["verdict"] == "misread"


def test_a_double_point_reported_as_double_accounts_for_both_changes() -> None:
    record = contin.Bifurcation(multiplicity=2, kernel=np.eye(2), directions=np.zeros((0, 3)), kind="multiple")
    point = contin.SpecialPoint("branch_point", 1.5, np.zeros(2), located=True, index=1, bifurcation=record)
    br = hand_made_branch([0, 0, 2, 2], [point])
    assert judge(br, Expected("branch_point", 1.5, 2, "double"))["verdict"] == "ok"
    assert unexplained_index_changes(br) == []


def test_the_pitchfork_normal_form_is_ok() -> None:
    br = contin.continuation(Pitchfork(), np.zeros(2), -1.0, p_max=1.0, stability=True)
    row = judge(br, Expected("branch_point", 0.0, 1, "p = 0"))
    assert row["verdict"] == "ok" and row["index_across"] == "0->1"
    assert unexplained_index_changes(br) == []
