"""The release fold: the snap of a large sphere or a plate, where the last (off-axis) contact leaves.

Independent checks of :func:`contin_models.contact.release.locate_release_fold` (which finds the root of
``dw_b/dx`` on the curve of equilibria with the gap ``x = dhat - d`` of the meridian's point nearest
to the indenter prescribed):

* at the located point the displacement-control Hessian is singular: its smallest eigenvalue from a
  dense symmetric eigensolver is zero to rounding, against a positive one on the stable side;
* the gap agrees with the leading-order closed form of the barrier integrated over its support:
  near the last contact point the distance along the meridian's curve is ``d = dhat - x + alpha
  tau^2`` (``tau`` the cell's coordinate) and ``W ~ K (dhat - d)^3 / dhat``, so a cell of weight
  ``w`` stores ``w K / dhat (32/35) x^(7/2) / sqrt(alpha)``, with stiffness ``8 w K x^(3/2) /
  (dhat sqrt(alpha))`` along the contact normal ``n``; ``H + k n n^T`` turns singular at
  ``k = -1 / (n^T H^{-1} n)``, so ``x_f = (dhat sqrt(alpha) / (8 w K |n^T H^{-1} n|))^(2/3)`` with
  ``H`` the shell's own Hessian (a dense solve);
* the engine's own fold of the travel, found by the continuation, is the same point.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.linalg as sl

import contin
from contin.app.cli import main as cli_main
from contin_models.contact import Plate, Sphere
from contin_models.contact.indentation import ShellIndentation
from contin_models.contact.release import ReleaseFoldError, locate_release_fold
from contin_models.shell_scene.contact import SNAP_FORCE_NORM


@pytest.fixture(scope="module")
def large_sphere():
    P = ShellIndentation(N=60, indenter=Sphere(0.9))
    # an event far closer to F = 0 than the scene's (SNAP_FORCE_NORM), so that the engine meets the fold
    event = contin.crossing("F_norm", 1e-2 * SNAP_FORCE_NORM, direction=-1, terminal=True, name="F -> 0")
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=0.7, events=[event],
                             stop_at=("fold",), bounds={"base_gap": (2 * P.dhat, None)})
    # the barrier integrated over its support makes the release fold wide enough for the engine to
    # turn round it (before the force has fallen to the event's level); start the search on its
    # stable side, one stored point back
    assert br.status == "event" and br.special_points[-1].kind in ("fold", "event"), br.message
    return P, br, locate_release_fold(P, br.u[-2], br.p[-2])


def test_release_fold_is_a_singular_point_of_the_displacement_control_hessian(large_sphere):
    P, br, rf = large_sphere
    before = sl.eigvalsh(P.jacobian(br.u[-2], br.p[-2]).toarray())
    at = sl.eigvalsh(P.jacobian(rf.u, rf.w_b).toarray())
    assert before[0] > 1e-3 * before[1]  # stable before it
    assert abs(at[0]) < 1e-8 * at[1]
    assert rf.residual <= 1e-10 * P.residual_scale
    # an off-axis point (the pole has detached) and a positive, tiny force
    assert 0 < rf.node < P.N - 1
    assert 0 < P.evaluate_one("F", rf.u, rf.w_b) < P.evaluate_one("F", br.u[-2], br.p[-2])


def test_release_gap_matches_the_barrier_closed_form(large_sphere):
    P, _, rf = large_sphere
    H = P.elastic.free_block(P.elastic.elastic_hessian(P.full_state(rf.u)), "force").toarray()  # shell alone
    x, c = P.full_state(rf.u), P.position(rf.w_b)
    d, n_full, _, cell, t = P.barrier.closest_point(x, c)
    assert P.dhat - d == pytest.approx(rf.gap, rel=1e-6)
    # the cell's curve, x(t) = a + b t + e t^2 from its three nodes (quadratic B-spline), and the
    # curvature of the distance to the sphere's centre along it at the nearest point
    nodes = x.reshape(-1, 2)[[cell - 1, cell, cell + 1]]
    a = (nodes[0] + 6 * nodes[1] + nodes[2]) / 8
    b, e = (nodes[2] - nodes[0]) / 2, (nodes[0] - 2 * nodes[1] + nodes[2]) / 2
    point, slope, bend = a + b * t + e * t * t, b + 2 * e * t, 2 * e
    rel = point - np.array([0.0, c])
    q = np.linalg.norm(rel)
    assert abs(rel @ slope) < 1e-9 * q * np.linalg.norm(slope)  # the nearest point: d is stationary in t
    alpha = 0.5 * (slope @ slope + rel @ bend) / q
    n = n_full[P.idx]
    weight = P.barrier.cells(P.N).cell_weight[cell]
    compliance = float(n @ np.linalg.solve(H, n))
    assert compliance < 0  # the free shell at the snap is a saddle that pulls the point away
    x_closed = (P.dhat * np.sqrt(alpha) / (8.0 * weight * P.K * abs(compliance))) ** (2.0 / 3.0)
    assert rf.gap == pytest.approx(x_closed, rel=1e-3)  # measured 1.7e-5
    assert rf.gap < 1e-4 * P.dhat  # a sharp fold in w_b


def test_release_fold_is_the_engines_fold_of_the_travel(large_sphere):
    P, br, rf = large_sphere
    fold = br.special_points[-1]
    assert fold.kind == "fold" and fold.located
    assert abs(rf.w_b - fold.p) < 1e-8 * P.R  # measured 2.5e-10


def test_release_fold_needs_a_node_in_contact_and_the_stable_side():
    P = ShellIndentation(N=40, indenter=Sphere(0.9))
    with pytest.raises(ReleaseFoldError, match="no node is in contact"):
        locate_release_fold(P, P.reference_unknowns(), -0.01)  # indenter held off the cap
    # first touch of the pole: the path goes on into contact, there is no release fold to find
    with pytest.raises(ReleaseFoldError, match="not on the stable side"):
        locate_release_fold(P, P.reference_unknowns(), 0.0)


def test_plate_scene_reports_the_dimple_snaps_and_the_eversion_release_fold(tmp_path, large_sphere):
    out = tmp_path / "plate"
    code = cli_main(["trace", "-q", "--set", "load.kind=plate", "--set", "shell.N=60", "--set", "output.figure=false",
                     "--out", str(out)])
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


def _force_path() -> contin.Problem:
    """u - p = 0 with ``F_norm`` rising to 1.4e-4 and back to 2e-5 in the first hundredth (noise at the first touch,
    as a tiny sphere of the fuzz draws showed), then from p = 0.02 up to 1 and down to 2e-5 at p = 1 (the release)."""
    def force(u: np.ndarray, p: float) -> float:
        x = float(u[0])
        rise = np.sin(np.pi * (x - 0.02) / 0.98) if x > 0.02 else 0.0
        return 1.2e-4 * np.exp(-((x - 0.005) / 0.002) ** 2) + 2e-5 + rise
    return contin.Problem(residual=lambda u, p: u - p, jacobian=lambda u, p: np.eye(1),
                          dresidual_dp=lambda u, p: -np.ones(1), observables={"F_norm": force}, name="force path")


def test_the_snap_event_waits_for_the_force_to_rise_before_its_fall_counts():
    """The force dips below SNAP_FORCE_NORM right after the first touch; the snap is its fall at the release."""
    from contin_models.shell_scene.contact import SNAP_ARMED_NORM, snap_event

    problem = _force_path()
    kw = {"ds": 1e-3, "ds_max": 1e-2, "p_max": 2.0, "state_weight": 1.0, "param_weight": 1.0, "check_model": False}
    br = contin.continuation(problem, np.zeros(1), 0.0, events=[snap_event(problem)], **kw)
    assert br.status == "event" and br.special_points[-1].label == "F -> 0"
    assert br.special_points[-1].p == pytest.approx(1.0 - 0.98 * (SNAP_FORCE_NORM - 2e-5) / np.pi, abs=1e-6)
    assert SNAP_ARMED_NORM > 1.2e-4 + 2e-5  # the dip's peak does not arm it
    # the plain crossing stops at the dip
    plain = contin.crossing("F_norm", SNAP_FORCE_NORM, direction=-1, terminal=True, name="F -> 0")
    early = contin.continuation(problem, np.zeros(1), 0.0, events=[plain], **kw)
    assert early.status == "event" and early.special_points[-1].p < 0.01
