"""Issue 14, B3: the plate's contact ring moves over the meridian smoothly (the barrier's contact cells).

With the paper's nodal barrier the ring that holds the plate's dimple could only sit on a node: it
hopped from node to node, ``dF/dw_b`` changed sign about 150 times along the dimple branch at
``N = 200`` (all stable), displacement control snapped again and again on coarser meshes and force
control gave up after four spurious snaps.  With the barrier integrated over quadratic cells
between the nodes (:mod:`contin_models.contact.barrier`) the branch is smooth, the dimple snap converges
with the mesh and force control reaches eversion.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import contin
from contin.app.cli import main as cli_main
from contin_models.contact import Plate
from contin_models.contact.indentation import ShellIndentation


def _dimple_snap(P: ShellIndentation) -> contin.Branch:
    """Displacement control from the first touch to the first fold (the dimple snap)."""
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.02, ds_max=0.1, tol=1e-10,
                             stop_at=("fold",), p_max=0.3)
    assert br.status == "event" and br.special_points[-1].kind == "fold", br.message
    return br


def _sign_changes(w: np.ndarray, F: np.ndarray) -> int:
    slope = np.sign(np.diff(F) / np.diff(w))
    slope = slope[slope != 0]
    return int(np.count_nonzero(slope[1:] != slope[:-1]))


def test_dimple_branch_is_smooth():
    """After the dimple snap the ring moves outwards: a smooth force, no further snap (nodal: a snap)."""
    P = ShellIndentation(N=120, indenter=Plate())
    fold = _dimple_snap(P).special_points[-1]
    for eps in (1e-6, 1e-5, 1e-4, 1e-3):  # jump to the dimpled state a hair past the fold
        jr = contin.jump(P, fold.u, fold.p * (1.0 + eps))
        if jr.success and P.evaluate_one("w_s", jr.u_to, jr.p) > P.evaluate_one("w_s", fold.u, fold.p) + 1e-3:
            break
    else:
        pytest.fail("the dimple snap did not land on a dimpled state")
    assert P.evaluate_one("n_contact", jr.u_to, jr.p) > 0  # the dimple is held by a ring of contact
    # small steps (a node spacing is ~0.006 R of travel here), so that a hop cannot hide between them
    br = contin.continuation(P, jr.u_to, jr.p, ds=5e-4, ds_max=5e-4, p_max=jr.p + 0.02, max_steps=2000,
                             stop_at=("fold",))
    # the nodal barrier folds again after 7 steps here (the ring leaves its node)
    assert br.status == "bound", br.message
    # F first falls a little after the landing, then rises: measured 2 sign changes
    assert _sign_changes(np.asarray(br.p), np.asarray(br.observables["F"])) <= 2
    ring = np.asarray(br.observables["contact_last"])
    assert ring[-1] < ring[0]  # the ring has moved outwards (towards the base, node 0)


@pytest.mark.slow
def test_dimple_snap_converges_with_the_mesh():
    """The dimple snap's travel and force at N = 200, 400, 800: differences shrinking (second order)."""
    snaps = []
    for N in (200, 400, 800):
        fold = _dimple_snap(ShellIndentation(N=N, indenter=Plate())).special_points[-1]
        snaps.append((fold.p, fold.observables["F"]))
    (w1, F1), (w2, F2), (w3, F3) = snaps
    # measured: w_b 0.0595861, 0.0594903, 0.0594676; F 71.025, 70.872, 70.836 (ratios ~4.2)
    assert abs(w3 - w2) < 0.5 * abs(w2 - w1) and abs(F3 - F2) < 0.5 * abs(F2 - F1)
    assert abs(w3 - w2) < 5e-5 and abs(F3 - F2) < 0.1


@pytest.mark.slow
def test_force_controlled_plate_reaches_eversion(tmp_path):
    """``contin trace --set load.kind=plate --set load.control=force``: the dimple snap, then eversion."""
    out = tmp_path / "plate_force"
    code = cli_main(["trace", "-q", "--set", "load.kind=plate", "--set", "load.control=force",
                     "--set", "output.figure=false", "--out", str(out)])
    summary = json.loads((out / "summary.json").read_text())
    assert code == 0 and summary["status"] == "ok", summary["message"]
    loads = [s["F"] for s in summary["snaps"]]
    # measured: the dimple at F = 71.03, eversion at F = 91.59 (no spurious snaps in between)
    assert len(loads) == 2 and 70 < loads[0] < 72 and 91 < loads[1] < 92.5


def test_stability_counts_at_the_dimple_fold_of_a_fine_mesh(monkeypatch):
    """At the located dimple fold of N = 400 the bordered matrix has a vanishing pivot.  The
    pivot-free L D L^T of the bordered matrix either counts it or declines (its growth check; with the
    contact at the nodes it declined here); the engine then counts the banded leading block and adds
    the sign of the Schur complement (:func:`contin.numerics.stability.nested_inertias`), which is what the
    declared ``LeadingBlock`` gives anywhere else.  Both ways must give the same counts."""
    import contin.numerics.stability
    from contin.numerics.stability import leading_inertias

    P = ShellIndentation(N=400, indenter=Plate())
    assert isinstance(P._stability_operators["displacement"], contin.LeadingBlock)
    br = _dimple_snap(P)
    fold = br.special_points[-1]
    n = P.idx.size
    direct = leading_inertias(P._op_force(fold.u, fold.p), (n, n + 1))
    counts = {label: info.n_negative for label, info in P.stability(fold.u, fold.p).items()}
    assert list(counts) == ["displacement", "force"]
    assert counts["displacement"] in (0, 1) and counts["force"] >= counts["displacement"]
    if direct is not None:
        assert direct == [counts["displacement"], counts["force"]]
    # away from the fold both ways count the same (stable under both controls on the way up)
    k = len(br.p) // 2
    expected = leading_inertias(P._op_force(br.u[k], br.p[k]), (n, n + 1))
    monkeypatch.setattr(contin.numerics.stability, "leading_inertias", lambda H, sizes: None)
    by_schur = {label: info.n_negative for label, info in P.stability(br.u[k], br.p[k]).items()}
    assert by_schur == {"displacement": expected[0], "force": expected[1]}
