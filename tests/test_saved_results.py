"""Quasi-static sweeps, jumps and diagrams save to one file each and load back identical (issue 15, item 7)."""

import networkx as nx
import numpy as np
import pytest

import contin
from contin import BranchFileError, JumpResult, QuasiStaticResult
from contin_models.benchmarks.truss import VonMisesTruss


@pytest.fixture(scope="module")
def sweep() -> QuasiStaticResult:
    """The von Mises truss loaded through its limit point and its snap, and unloaded."""
    truss = VonMisesTruss(a=1.0, b=0.5, k=1.0)
    st = contin.Settings(ds=0.02, ds_max=0.05, tol=1e-10)
    res = contin.quasistatic(truss, np.array([0.0, 0.5]), 0.0, 0.3, st)
    assert res.success and len(res.jumps) == 1
    return res


def _same_branch(a: contin.Branch, b: contin.Branch) -> None:
    np.testing.assert_array_equal(a.p, b.p)
    np.testing.assert_array_equal(a.u, b.u)
    assert list(a.observables) == list(b.observables)
    assert [(s.kind, s.p, s.label) for s in a.special_points] == [(s.kind, s.p, s.label) for s in b.special_points]
    assert (a.status, a.message) == (b.status, b.message)


def test_a_quasistatic_sweep_loads_back_identical(sweep, tmp_path):
    path = sweep.save(tmp_path / "sweep")
    assert path.suffix == ".npz"
    back = QuasiStaticResult.load(path)
    assert (back.p0, back.p_end, back.direction, back.status, back.message, back.p_final) == \
        (sweep.p0, sweep.p_end, sweep.direction, sweep.status, sweep.message, sweep.p_final)
    np.testing.assert_array_equal(back.u_final, sweep.u_final)
    assert len(back.branches) == len(sweep.branches)
    for a, b in zip(sweep.branches, back.branches):
        _same_branch(a, b)
    assert [f.p for f in back.folds] == [f.p for f in sweep.folds]
    np.testing.assert_array_equal(back.jump_parameters, sweep.jump_parameters)
    j0, k0 = sweep.jumps[0], back.jumps[0]
    np.testing.assert_array_equal(j0.u_to, k0.u_to)
    assert (j0.p, j0.energy_to, j0.success, j0.info["fold_p"]) == (k0.p, k0.energy_to, k0.success, k0.info["fold_p"])


def test_a_jump_loads_back_identical(sweep, tmp_path):
    jr = sweep.jumps[0]
    back = JumpResult.load(jr.save(tmp_path / "jump.npz"))
    np.testing.assert_array_equal(back.u_from, jr.u_from)
    np.testing.assert_array_equal(back.u_to, jr.u_to)
    assert (back.p, back.energy_from, back.n_negative, back.message) == (jr.p, jr.energy_from, jr.n_negative, jr.message)


def test_a_diagram_loads_back_with_every_attribute(sweep, tmp_path):
    G = contin.diagram(sweep.branches, sweep.jumps)
    H = contin.load_diagram(contin.save_diagram(G, tmp_path / "diagram"))
    assert nx.utils.graphs_equal(G, H)
    assert sorted(G.edges(keys=True, data=True), key=str) == sorted(H.edges(keys=True, data=True), key=str)


def test_a_file_of_another_kind_is_refused_by_name(sweep, tmp_path):
    path = sweep.branches[0].save(tmp_path / "branch.npz")
    with pytest.raises(BranchFileError, match="not a contin-quasistatic file"):
        QuasiStaticResult.load(path)
    with pytest.raises(BranchFileError, match="no such file"):
        JumpResult.load(tmp_path / "missing.npz")
