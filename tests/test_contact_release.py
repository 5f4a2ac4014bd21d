"""The release fold: the snap of a large sphere or a plate, where the last (off-axis) contact node leaves.

Independent checks of :func:`contin_models.contact.release.locate_release_fold` (which finds the root of
``dw_b/dx`` on the curve of equilibria with the node's gap ``x`` prescribed):

* at the located point the displacement-control Hessian is singular: its smallest eigenvalue from a
  dense symmetric eigensolver is zero to rounding, against a positive one on the stable side;
* the gap agrees with the leading-order closed form of the barrier: ``W = K x^3 / dhat + O(x^4)``
  gives a node stiffness ``6 K x / dhat``, and ``H + k n n^T`` turns singular at
  ``k = -1 / (n^T H^{-1} n)``, so ``x_f = dhat / (6 K |n^T H^{-1} n|)`` with ``H`` the shell's own
  Hessian (a dense solve) and ``n`` the contact normal of the node;
* the fold lies beyond the ``F -> 0`` event along the path, within ``x_f`` of where the node leaves.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.linalg as sl

import contin
from contin.cli import main as cli_main
from contin_models.contact import Plate, Sphere
from contin_models.contact.indentation import ShellIndentation
from contin_models.contact.release import ReleaseFoldError, locate_release_fold
from contin_models.shell_scene.contact import SNAP_FORCE_NORM


@pytest.fixture(scope="module")
def large_sphere():
    P = ShellIndentation(N=60, indenter=Sphere(0.9))
    event = contin.crossing("F_norm", SNAP_FORCE_NORM, direction=-1, terminal=True, name="F -> 0")
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=0.7, events=[event],
                             stop_at=("fold",), bounds={"base_gap": (2 * P.dhat, None)})
    assert br.status == "event" and br.special_points[-1].label == "F -> 0", br.message
    return P, br, locate_release_fold(P, br.u[-1], br.p[-1])


def test_release_fold_is_a_singular_point_of_the_displacement_control_hessian(large_sphere):
    P, br, rf = large_sphere
    before = sl.eigvalsh(P.jacobian(br.u[-1], br.p[-1]).toarray())
    at = sl.eigvalsh(P.jacobian(rf.u, rf.w_b).toarray())
    assert before[0] > 1e-3 * before[1]  # stable before it
    assert abs(at[0]) < 1e-8 * at[1]
    assert rf.residual <= 1e-10 * P.residual_scale
    # an off-axis node (the pole has detached) and a positive, tiny force
    assert 0 < rf.node < P.N - 1
    assert 0 < P.evaluate_one("F", rf.u, rf.w_b) < P.evaluate_one("F", br.u[-1], br.p[-1])


def test_release_gap_matches_the_barrier_closed_form(large_sphere):
    P, _, rf = large_sphere
    H = P.elastic.free_block(P.elastic.elastic_hessian(P.full_state(rf.u)), "force").toarray()  # shell alone
    # the last point of the meridian in contact: the barrier's sample point nearest to the sphere,
    # its contact normal on the unknowns (d(d_s)/du) and its share of the barrier (quadrature weight)
    x, c = P.full_state(rf.u), P.position(rf.w_b)
    sample, d = P.barrier.nearest_sample(x, c)
    assert P.dhat - d == pytest.approx(rf.gap, rel=1e-6)
    _, n_full, _ = P.barrier.sample_gap(x, c, sample)
    n = n_full[P.idx]
    weight = P.barrier.cells(P.N).weight[sample]
    compliance = float(n @ np.linalg.solve(H, n))
    assert compliance < 0  # the free shell at the snap is a saddle that pulls the point away
    x_closed = P.dhat / (6.0 * P.K * weight * abs(compliance))
    assert rf.gap == pytest.approx(x_closed, rel=1e-3)
    assert rf.gap < 1e-4 * P.dhat  # why the continuation cannot turn round it


def test_release_fold_lies_just_beyond_the_force_event(large_sphere):
    P, br, rf = large_sphere
    assert 0 < rf.w_b - br.p[-1] < 1e-8 * P.R


def test_release_fold_needs_a_node_in_contact_and_the_stable_side():
    P = ShellIndentation(N=40, indenter=Sphere(0.9))
    with pytest.raises(ReleaseFoldError, match="no node is in contact"):
        locate_release_fold(P, P.reference_unknowns(), -0.01)  # indenter held off the cap
    # first touch of the pole: the path goes on into contact, there is no release fold to find
    with pytest.raises(ReleaseFoldError, match="not on the stable side"):
        locate_release_fold(P, P.reference_unknowns(), 0.0)


def test_plate_scene_reports_the_dimple_snaps_and_the_eversion_release_fold(tmp_path, large_sphere):
    out = tmp_path / "plate"
    code = cli_main(["trace", "-q", "--set", "load.kind=plate", "--set", "shell.N=60", "--out", str(out)])
    summary = json.loads((out / "summary.json").read_text())
    assert code == 0 and summary["status"] == "ok"
    snaps = summary["snaps"]
    # the flattened contact region buckles into a dimple held by a ring (snaps at a finite force that
    # stay in contact), then the shell everts off the plate at the release fold
    assert all(s["kind"] == "fold" for s in snaps)
    assert snaps[0]["F"] > 10.0 and snaps[0]["nodes_in_contact_after"] > 0
    # (the contact cells make the eversion fold wide enough for the engine to go round it; otherwise
    # the release search locates it)
    assert snaps[-1]["label"] in ("", "release") and snaps[-1]["nodes_in_contact_after"] == 0
    assert summary["snap_label"] == snaps[-1]["label"] and summary["w_b_c"] == pytest.approx(snaps[-1]["w_b"])
    assert summary["contact_mode"] == "detach" and summary["Delta_H_at_snap_over_R"] > 0.1
    # the snap shape is universal (paper figure 8): the plate's pole curvature at its release fold is
    # the large sphere's on the same mesh
    P, _, rf = large_sphere
    assert summary["kappa_p_R_at_snap"] == pytest.approx(P.evaluate_one("kappa_p_R", rf.u, rf.w_b), rel=1e-3)


def test_plate_is_not_a_sphere_of_radius_zero():
    with pytest.raises(ValueError, match="radius must be > 0"):
        ShellIndentation(N=20, indenter=Sphere(0.0))
    assert ShellIndentation(N=20, indenter=Plate()).indenter.name == "plate"
