"""Automatic diagrams: every branch once, copies under the declared symmetry recognised, loops as cycles.

* The square of D4 symmetry (contin_models.benchmarks.square, 30 x 30): depth 2 from ``u = 0`` to
  ``p = 55``, past the simple point (1,1) and the double point (1,2)/(2,1): the trivial branch, the
  (1,1) branch (both halves: ``-phi_11`` is no image of ``phi_11`` under D4), one pure and one mixed
  branch; the other half of each of those is the image of the traced half under a reflection and is
  recognised as a copy, not traced.
* The pitchfork normal form: both halves of the bifurcating branch are one curve meeting at the branch
  point; with ``u1 -> -u1`` declared, the second half is a copy of the first.
* A parabola ``u1 = 1 - p^2`` crossing the trivial branch at p = -1, 1: its arc between them, reached
  from its other end, is recognised, not traced again, and the arc and the trivial branch are a cycle.
* The isola (contin_models.benchmarks.isola) found by deflation: a cycle of its own.
* ``contin.diagram(..., merge=True)``: a branch given twice is one set of edges; a branch point of one
  branch inside another (which did not locate it) splits that one.
"""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest
import scipy.sparse as sp

import contin
from contin import Problem
from contin_models.benchmarks.isola import Isola
from contin_models.benchmarks.pitchfork import Pitchfork
from contin_models.benchmarks.square import D4Square


def _mode_share(square, u):
    h2 = square.h ** 2
    return h2 * u @ square.mode(1, 2), h2 * u @ square.mode(2, 1)


def _curve_edges(G):
    """Curve id -> the edges of that curve."""
    out: dict[int, list] = {}
    for a, b, data in G.edges(data=True):
        if data["kind"] == "branch":
            out.setdefault(data["curve"], []).append((a, b, data))
    return out


@pytest.fixture(scope="module")
def square_diagram():
    square = D4Square(30)
    return square, contin.auto_diagram(square, np.zeros(square.n ** 2), 0.0, depth=2, p_max=55.0)


@pytest.mark.slow
def test_the_squares_diagram_has_every_branch_once(square_diagram):
    square, result = square_diagram
    assert result.success, [a.message for a in result.failures]
    assert [a.status for a in result.attempts].count("traced") == 4
    # trivial | (1,1) both halves | pure | mixed
    assert [len(c) for c in result.curves] == [1, 2, 1, 1]
    kinds = []
    for curve in result.curves[2:]:
        (bi,) = curve
        a, b = _mode_share(square, np.asarray(result.branches[bi].u[-1]))
        kinds.append("pure" if min(abs(a), abs(b)) < 1e-6 * max(abs(a), abs(b)) else
                     "mixed" if abs(abs(a) - abs(b)) < 1e-8 * abs(a) else "other")
    assert sorted(kinds) == ["mixed", "pure"]
    (one_one,) = [c for c in result.curves if len(c) == 2]
    ends = [np.asarray(result.branches[bi].u[-1]) for bi in one_one]
    assert np.allclose(ends[0], -ends[1], atol=1e-8)  # the two halves of the (1,1) pitchfork
    # no branch twice: no probe landed on a traced branch, and no two branches share a point off the nodes
    assert not [a for a in result.attempts if a.status == "same"]
    for i, bi in enumerate(result.branches):
        for bj in result.branches[i + 1:]:
            mid = len(bj) // 2
            assert contin.analyses.diagram.position_on(bi, bj.u[mid], bj.p[mid]) is None


@pytest.mark.slow
def test_the_squares_copies_are_recognised_not_traced(square_diagram):
    square, result = square_diagram
    copies = result.copies
    assert len(copies) == 2 and {a.half for a in copies} == {-1}
    group = contin.watch.branching.group_elements(square.symmetry_generators, square.n ** 2)
    for attempt in copies:
        traced = result.branches[attempt.branch]
        g = group[attempt.element]
        # g maps the traced half onto the other: g u is a solution at the same p, -u up to roundoff
        u, p = np.asarray(traced.u[-1]), float(traced.p[-1])
        assert np.max(np.abs(square.residual(g @ u, p))) <= 1e-12
        assert np.allclose(g @ u, -u, atol=1e-10)
    (node,) = [n for n, d in result.graph.nodes(data=True) if d.get("copies")]
    assert result.graph.nodes[node]["p"] == pytest.approx(square.eigenvalue(1, 2), abs=1e-8)
    assert sorted(c["copy_of"] for c in result.graph.nodes[node]["copies"]) == sorted(a.branch for a in copies)


@pytest.mark.slow
def test_the_squares_graph_has_each_branch_once(square_diagram):
    square, result = square_diagram
    G = result.graph
    edges = _curve_edges(G)
    assert sorted(edges) == [0, 1, 2, 3]
    assert len(edges[0]) == 3  # the trivial branch: start, (1,1), (1,2)/(2,1), end
    bps = sorted(d["p"] for _, d in G.nodes(data=True) if "branch_point" in d["kinds"])
    assert bps == pytest.approx([square.eigenvalue(1, 1), square.eigenvalue(1, 2)], abs=1e-8)
    for curve in (1, 2, 3):  # every other curve leaves from a branch point of the trivial branch
        assert all(G.nodes[a]["kind"] == "branch_point" for a, _, _ in edges[curve])
    assert not any("merged" in d for *_, d in G.edges(data=True))


def test_both_halves_of_a_pitchfork_are_one_curve():
    result = contin.auto_diagram(Pitchfork(), np.zeros(2), -0.5, depth=2, p_max=0.5, ds=0.05,
                                 state_weight=1.0, param_weight=1.0)
    assert result.success and [len(c) for c in result.curves] == [1, 2]
    halves = [result.branches[bi] for bi in result.curves[1]]
    assert sorted(np.sign(br.u[-1][0]) for br in halves) == [-1, 1]
    (bp,) = [n for n, d in result.graph.nodes(data=True) if "branch_point" in d["kinds"]]
    assert result.graph.nodes[bp]["p"] == pytest.approx(0.0, abs=1e-10)
    out = [d for _, _, d in result.graph.out_edges(bp, data=True) if d["curve"] == 1]
    assert len(out) == 2  # both halves leave the one branch point node


class SymmetricPitchfork(Pitchfork):
    """The pitchfork with its symmetry ``u1 -> -u1`` declared."""

    def __init__(self) -> None:
        super().__init__()
        self.symmetry_generators = (sp.diags([-1.0, 1.0]).tocsr(),)


def test_the_second_half_of_a_symmetric_pitchfork_is_a_copy():
    result = contin.auto_diagram(SymmetricPitchfork(), np.zeros(2), -0.5, depth=1, p_max=0.5, ds=0.05,
                                 state_weight=1.0, param_weight=1.0)
    assert result.success and [len(c) for c in result.curves] == [1, 1]
    (copy,) = result.copies
    assert copy.half == -1 and copy.branch == result.curves[1][0]


class Arch(Problem):
    """``f = (u1 (u1 - (1 - p^2)), u2)``: the trivial branch, and the parabola ``u1 = 1 - p^2`` crossing it at p = -1, 1."""

    def __init__(self) -> None:
        super().__init__(symmetric=False, name="arch", parameter_name="p")

    def residual(self, u, p):
        return np.array([u[0] * (u[0] - 1.0 + p ** 2), u[1]])

    def jacobian(self, u, p):
        return np.array([[2 * u[0] - 1.0 + p ** 2, 0.0], [0.0, 1.0]])

    def dresidual_dp(self, u, p):
        return np.array([2 * p * u[0], 0.0])


def test_a_branch_reached_from_its_other_end_is_not_traced_again():
    result = contin.auto_diagram(Arch(), np.zeros(2), -2.0, depth=2, p_max=2.0, p_min=-2.0, ds=0.05, ds_max=0.1,
                                 state_weight=1.0, param_weight=1.0)
    assert result.success, [a.message for a in result.failures]
    (same,) = [a for a in result.attempts if a.status == "same"]
    assert same.p == pytest.approx(1.0, abs=1e-9)
    arc = result.branches[same.branch]  # the half from p = -1 that reached p = 1 along the parabola
    assert arc.status == "reached_branch_point" and arc.p[-1] == pytest.approx(1.0, abs=1e-9)
    assert np.max(np.abs(arc.u[:, 0] - (1.0 - arc.p ** 2))) <= 1e-7  # the corrector's tolerance
    assert [a.status for a in result.attempts].count("traced") == 3  # the arc, and the parabola outside each end
    G = result.graph
    bps = [n for n, d in G.nodes(data=True) if "branch_point" in d["kinds"]]
    between = [d for a, b, d in G.edges(data=True) if {a, b} == set(bps)]
    assert sorted(d["curve"] for d in between) == [0, 1]  # the trivial branch and the arc, once each
    cycle = nx.find_cycle(nx.MultiGraph(G))  # the arc and the trivial branch between the two points
    assert len(cycle) == 2 and {a for a, *_ in cycle} == set(bps)


def test_the_isola_found_by_deflation_is_a_cycle():
    model = Isola()
    result = contin.auto_diagram(model, np.zeros(2), -2.0, depth=2, p_max=3.0, deflate_at=[0.0])
    assert result.success
    (found,) = result.deflations
    assert len(found.branches) == 1 and found.branches[0].status == "closed_loop"
    assert [len(c) for c in result.curves] == [1, 1]
    cycles = list(nx.simple_cycles(nx.DiGraph(result.graph)))
    assert len(cycles) == 1
    assert sorted(result.graph.nodes[n]["kind"] for n in cycles[0]) == ["fold", "fold", "start"]
    assert all(result.graph.edges[e]["curve"] == 1 for e in result.graph.edges(keys=True) if e[0] in cycles[0])


def test_a_branch_given_twice_is_merged():
    model = Pitchfork()
    kw = dict(p_max=0.5, ds=0.05, state_weight=1.0, param_weight=1.0)
    trivial = contin.continuation(model, np.zeros(2), -0.5, **kw)
    bp = trivial.branch_points()[0]
    half = contin.switch_branch(model, bp, **kw)
    again = contin.continuation(model, np.array([np.sqrt(0.5), 0.0]), 0.5, direction=-1, p_min=0.01,
                                **{**kw, "p_max": 0.6})  # the same half, from its other end, short of the bp
    plain = contin.diagram([trivial, half, trivial, again])
    merged = contin.diagram([trivial, half, trivial, again], merge=True)
    assert plain.number_of_edges() > merged.number_of_edges()
    branch_of = sorted(d["branch"] for *_, d in merged.edges(data=True))
    assert 2 not in branch_of  # the trivial branch a second time: nothing of its own
    notes = [m for *_, d in merged.edges(data=True) for m in d.get("merged", ())]
    assert {m["branch"] for m in notes} == {2, 3}
    assert any(m["branch"] == 3 and m["reverse"] for m in notes)


def test_a_branch_point_inside_another_branch_splits_it():
    # the trivial branch traced blind to branch points, the pitchfork's half switched from a run that saw it
    model = Pitchfork()
    kw = dict(p_max=0.5, ds=0.05, state_weight=1.0, param_weight=1.0)
    seen = contin.continuation(model, np.zeros(2), -0.5, **kw)
    blind = contin.continuation(model, np.zeros(2), -0.5, detect_branch_points=False, **kw)
    assert not blind.branch_points()
    half = contin.switch_branch(model, seen.branch_points()[0], **kw)
    plain = contin.diagram([blind, half])
    G = contin.diagram([blind, half], merge=True)
    assert plain.number_of_edges() == 2 and G.number_of_edges() == 3
    (split,) = [n for n, d in G.nodes(data=True) if "split" in d["kinds"]]
    assert G.nodes[split]["p"] == pytest.approx(0.0, abs=1e-10)
    assert sorted(d["branch"] for _, _, d in G.edges(split, data=True)) == [0, 1]  # out: the trivial's second half and the new one
    assert [d["branch"] for _, _, d in G.in_edges(split, data=True)] == [0]
