"""The path a shell really takes: the turning of a wavy state is not an instability, and the followed path."""

import math
import numpy as np
import pytest

import contin
from contin.numerics.stability import stability_info
from contin_models.shell.fourier import AngularBasis, transfer_coefficients
from contin_models.shell.followed import follow_path
from contin_models.shell_scene.follow import classify_followed
from contin_models.shell.lift import follow_waves
from contin_models.shell.problem3d import Shell3D
from contin_models.shell.structure import ShellOfRevolution
from contin_models.shell.geometry import spherical_cap
from contin_models.shell.structure import ShellStructure
from studies.shell3d_convergence import E, H_OVER_R, NU, PHI_HAT, SWITCH_DS, paper_cap

N, K, W_END = 30, 2, 0.37


@pytest.fixture(scope="module")
def three_waves():
    """The paper's cap's three-wave branch at N = 30, followed from its bifurcation with every class watched."""
    source = ShellOfRevolution(paper_cap(N), "point", "displacement", harmonics=4)
    trace = contin.continuation(source, source.reference_unknowns(), 0.0, p_max=W_END, ds=0.01, ds_max=0.02,
                                max_steps=2000, stability=True)
    point = next(s for s in trace.special_points if s.kind == "bifurcation" and s.info["key"] == 3)
    return follow_waves(source, point, K, settings=contin.Settings(ds=SWITCH_DS, ds_max=0.02), max_steps=2000,
                        p_max=W_END, every_mode=True, stability=True)


def test_the_turning_of_a_wavy_state_is_a_null_vector_not_an_instability(three_waves) -> None:
    prob, branch = three_waves.problem, three_waves.branch
    assert branch.status == "bound" and len(branch) > 10
    modes = branch.meta["modes"]["representation"]
    a2 = list(modes["keys"]).index("A2")
    counts = np.asarray(modes["n_negative"]).reshape(len(branch), -1)[:, a2]
    for i in range(1, len(branch), 4):
        c = prob.full_state(branch.u[i], branch.p[i])
        H = prob.view.bloch_block(c, 0, "odd")
        g = prob.view.turning_direction(c)[prob.view.bloch_unknowns(0, "odd")]
        top = abs(H).max()
        # the state turned about the axis has the same energy: its direction is a null vector up to aliasing,
        # while the block's next eigenvalue stays far from zero
        assert abs(g @ (H @ g)) / (g @ g) / top < 1e-9
        assert stability_info(H, 2).eigenvalues[1] / top > 1e-6
    # the turning's sign is noise (negative here): the stability of the circle of turned states ignores it
    assert np.all(counts[1:] == 0)


def test_a_pieces_view_is_built_again_from_its_record(three_waves) -> None:
    """What a restart of a followed path rebuilds a piece's view from: the basis and the gauge.  The three-wave
    view, a one-wave view with a mirror and one without under a gauge come back with the same unknowns, and a state of
    the three-wave branch is an equilibrium of its rebuilt view (an independent check: the residual)."""
    from contin_models.shell.followed import rebuild_view, view_descriptor
    from contin_models.shell.lift import same_load

    prob, branch = three_waves.problem, three_waves.branch
    source = ShellOfRevolution(paper_cap(N), "point", "displacement", harmonics=4)
    assert view_descriptor(source) is None and rebuild_view(None, source, source.structure) is source
    u, p = np.asarray(branch.u[-1]), float(branch.p[-1])
    scale = float(prob.residual_scale)
    assert np.max(np.abs(prob.residual(u, p))) <= 1e-8 * scale
    again = rebuild_view(view_descriptor(prob), source, source.structure)
    assert again.basis.n == 3 and again.basis.M == prob.basis.M and np.max(np.abs(again.residual(u, p))) <= 1e-8 * scale
    for view in (same_load(prob, AngularBasis(1, 6), every_mode=True),
                 same_load(prob, AngularBasis(1, 6, mirror=False), gauge=(N // 2, 1))):
        rebuilt = rebuild_view(view_descriptor(view), source, source.structure)
        assert (rebuilt.basis.n, rebuilt.basis.K, rebuilt.basis.mirror, rebuilt.basis.M, rebuilt.gauge) == \
            (view.basis.n, view.basis.K, view.basis.mirror, view.basis.M, view.gauge)
        c = transfer_coefficients(prob.full_state(u, p), prob.basis, view.basis)  # the three waves, one basis lower
        assert rebuilt.T.shape == view.T.shape
        assert np.array_equal(rebuilt.residual(rebuilt.unknowns(c), p), view.residual(view.unknowns(c), p))


def test_an_axisymmetric_state_keeps_its_whole_a2_block() -> None:
    prob = Shell3D(paper_cap(N), AngularBasis(3, K), "point", "displacement", every_mode=True)
    u = prob.reference_unknowns()
    block = prob.operator_families[0].operator("A2", u, 0.0)
    whole = prob.view.bloch_block(prob.full_state(u, 0.0), 0, "odd")
    assert abs(block - whole).max() == 0.0


def _cap(phi_hat: float) -> ShellOfRevolution:
    """A cap of the paper's thickness and material under a prescribed pole deflection, watching waves 1 .. 5."""
    structure = ShellStructure(spherical_cap(1.0, phi_hat, N), E, NU, H_OVER_R, boundary="sliding")
    return ShellOfRevolution(structure, "point", "displacement", harmonics=5)


LIMIT_LOADS = [contin.extremum("F", which, folds="F", stability_label="force") for which in ("max", "min")]


def _followed(phi_hat: float, w_end: float):
    source = _cap(phi_hat)
    fp = follow_path(source, source.reference_unknowns(), 0.0, contin.Settings(ds=0.01, ds_max=0.02, max_steps=2000),
                     structure=source.structure, label="displacement", p_end=w_end, K=K, events=LIMIT_LOADS)
    assert fp.success, fp.message
    for piece in fp.pieces:  # every stored point stable under the control (a located end is singular)
        counts = piece.branch.n_negative_under("displacement")
        assert np.all(counts[: len(counts) - (piece.end != "end of load")] == 0)
    for before, after in zip(fp.pieces, fp.pieces[1:]):  # one path: each piece starts where the last ended
        assert after.start_p == pytest.approx(float(before.branch.p[-1]), rel=1e-5)
    assert fp.pieces[-1].branch.p[-1] == pytest.approx(w_end, rel=1e-12)
    return fp


def test_the_followed_path_turns_onto_the_stable_three_wave_branch() -> None:
    fp = _followed(0.6, 0.45)
    first, second = fp.pieces
    assert (first.symmetry, first.end) == ("O(2)", "bifurcation") and first.branch.special_points[-1].info["key"] == 3
    assert (second.symmetry, second.start, second.end) == ("D3", "bifurcation", "end of load")
    assert not fp.snaps


@pytest.mark.slow
def test_the_deeper_cap_snaps_from_its_one_wave_bifurcation_and_goes_on_without_axial_symmetry() -> None:
    fp = _followed(PHI_HAT, 0.6)
    first = fp.pieces[0]
    assert first.end == "bifurcation" and first.branch.special_points[-1].info["key"] == 1
    # the one-wave branch falls back: the cap snaps sideways onto a state with one mirror plane, which it
    # leaves at a fold in w for the everted, axisymmetric cap
    assert [(pc.symmetry, pc.start, pc.end) for pc in fp.pieces] == [
        ("O(2)", "load", "bifurcation"), ("D1", "snap", "fold"), ("O(2)", "snap", "end of load")]
    for snap in fp.snaps:
        assert snap.jump.success and snap.jump.energy_to < snap.jump.energy_from
    assert [snap.symmetry for snap in fp.snaps] == ["D1", "O(2)"]
    # the class on the followed path: its first maximum of F is the axisymmetric path's, located alike
    source = _cap(PHI_HAT)
    axisymmetric = contin.continuation(source, source.reference_unknowns(), 0.0, p_max=0.6, ds=0.01, ds_max=0.02,
                                       max_steps=2000, events=LIMIT_LOADS)
    first_max = next(s for s in axisymmetric.special_points if s.label == "max(F)")
    cls = classify_followed(fp, 1.0, 1.0)
    assert cls["F_max"] == pytest.approx(first_max.observables["F"], rel=1e-9)
    assert cls["w_at_F_max"] == pytest.approx(first_max.p, rel=1e-9)
    landing = fp.pieces[2].branch.observables["F"]
    assert cls["classification"] == ("bistable" if np.min(landing) < 0 else "monostable") and cls["n_snaps"] == 2


def test_the_end_of_the_load_must_lie_ahead() -> None:
    source = ShellOfRevolution(paper_cap(N), "point", "displacement", harmonics=4)
    with pytest.raises(ValueError, match="p_end"):
        follow_path(source, source.reference_unknowns(), 0.0, contin.Settings(), structure=source.structure,
                    label="displacement", p_end=0.0)


FOLLOW_REFUSED = [
    (["stability.follow=true"], ["stability.follow", "stability.harmonics = true"]),
    (["stability.follow=true", "stability.harmonics=true", "load.kind=plate", "load.control=force"],
     ["stability.follow", "load.kind", "dead load on an indenter"]),
]


@pytest.mark.parametrize("keys, needles", FOLLOW_REFUSED)
def test_a_path_that_cannot_be_followed_is_refused_with_one_paragraph(tmp_path, capsys, keys, needles) -> None:
    from contin.app import cli

    out = tmp_path / "out"
    code = cli.main(["trace", *[a for k in keys for a in ("--set", k)], "--out", str(out)])
    stderr = capsys.readouterr().err
    assert code == 2 and stderr.startswith("contin: error:") and stderr.count("\n") == 1
    for needle in needles:
        assert needle in stderr
    assert not out.exists() or not any(out.iterdir())


def test_csv_columns_of_branches_with_and_without_a_tangent() -> None:
    from contin.app.scene import branch_columns

    problem = contin.Problem(lambda u, p: u - p, jacobian=lambda u, p: np.eye(1),
                             observables={"x": lambda u, p: float(u[0])},
                             observable_derivatives={"x": lambda u, p: (np.ones(1), 0.0)})
    a = contin.continuation(problem, np.zeros(1), 0.0, p_max=0.1, ds=0.05)
    b = contin.continuation(problem, np.zeros(1), 0.0, p_max=0.1, ds=0.05)
    b.tangents.pop("x", None)
    cols = branch_columns([a, b])
    assert np.all(np.isnan(cols["tangent_x"][len(a):])) and not np.any(np.isnan(cols["tangent_x"][: len(a)]))


@pytest.mark.slow
def test_the_followed_run_writes_its_pieces_replots_and_restarts(tmp_path, capsys) -> None:
    import csv
    import json

    from contin.app import cli

    out = tmp_path / "run"
    keys = ["shell.phi_hat=0.6", "shell.N=40", "view.harmonics=2", "stability.harmonics=true", "stability.follow=true"]
    sets = [a for k in keys for a in ("--set", k)]
    assert cli.main(["trace", "-q", *sets, "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    followed = summary["followed"]
    assert followed["status"] == "completed" and followed["classification"] == "bistable"
    assert [b["symmetry"] for b in followed["branches"]][:2] == ["O(2)", "D3"]
    assert [b["parent"] for b in followed["branches"]] == [None] + [b["id"] - 1 for b in followed["branches"][1:]]
    assert "leaves the axisymmetric branch" in followed["left_axisymmetric"] and "3 waves (D3)" in followed["left_axisymmetric"]
    rows = list(csv.DictReader(open(out / "branch.csv")))
    pieces = {}
    for row in rows:
        pieces.setdefault(int(row["branch"]), []).append(row)
    assert len(pieces) == 1 + len(followed["branches"])
    assert {r["symmetry"] for r in pieces[2][1:]} == {"D3"} and {r["n"] for r in pieces[2][1:]} == {"3"}
    for b, rs in pieces.items():  # every stored point of the followed path stable (the located ends aside)
        if b > 0:
            ended = followed["branches"][b - 1]["ended"]
            kept = rs[:-1] if ended in ("fold", "bifurcation", "branch_point") else rs
            assert all(r["stable_displacement"] == "1" for r in kept)
    (out / "diagram.png").unlink()
    assert cli.main(["plot", str(out)]) == 0 and (out / "diagram.png").is_file()
    capsys.readouterr()
    # a restart from a point of the three-wave piece, with a smaller largest step, joins the saved path: the same
    # pieces, the same located points to the corrector's tolerance, the same class
    records = summary["special_points"]
    label = next(r["number"] for r in records if r.get("branch") == 2 and r.get("label") == "max(F)")
    again = tmp_path / "again"
    assert cli.main(["trace", "-q", "--from", str(out), "--label", str(label), "--set", "continuation.ds_max=0.05",
                     "--out", str(again)]) == 0
    redo = json.loads((again / "summary.json").read_text())
    assert redo["restart"]["joined"] and redo["followed"]["classification"] == "bistable"
    assert [(b["symmetry"], b["ended"]) for b in redo["followed"]["branches"]] == \
        [(b["symmetry"], b["ended"]) for b in followed["branches"]]
    located = [(r["branch"], r["label"], r["p"]) for r in records if r.get("branch") and r["kind"] != "jump"]
    relocated = [(r["branch"], r["label"], r["p"]) for r in redo["special_points"] if r.get("branch") and r["kind"] != "jump"]
    assert [x[:2] for x in located] == [x[:2] for x in relocated]
    assert max(abs(a[2] - b[2]) for a, b in zip(located, relocated)) < 1e-8
    # the point a snap leaves from is named: the bifurcation it left, not a fold of another branch
    jump_from = next(r["number"] for r in records if r.get("label") == "jump_from")
    bifurcation = next(r["number"] for r in records if r.get("branch") == 2 and r["kind"] == "bifurcation")
    assert cli.main(["trace", "--from", str(out), "--label", str(jump_from), "--out", str(tmp_path / "x")]) == 2
    assert f"(point {bifurcation})" in capsys.readouterr().err
    # refused with one paragraph: a point of the axisymmetric path drawn beside, another structure, the end of load
    assert cli.main(["trace", "--from", str(out), "--label", "1", "--out", str(tmp_path / "y")]) == 2
    assert "branch 0, the axisymmetric path" in capsys.readouterr().err
    assert cli.main(["trace", "--from", str(out), "--label", str(label), "--set", "shell.h=0.019",
                     "--out", str(tmp_path / "z")]) == 2
    assert "shell.h changed" in capsys.readouterr().err
    last = len(followed["branches"])
    assert cli.main(["trace", "--from", str(out), "--label", f"end:{last}", "--out", str(tmp_path / "w")]) == 2
    assert "nothing to follow" in capsys.readouterr().err


def test_a_gauge_holds_the_turning_of_a_state_without_a_mirror() -> None:
    """A one-wave state in the basis without a mirror: singular along its turning, regular under the gauge, and
    as stable there as in its D_1 view."""
    from contin_models.shell.lift import same_load
    from contin_models.shell.problem3d import gauge_for
    from contin_models.shell.fourier import transfer_coefficients

    fp = _followed(PHI_HAT, 0.6)
    piece = fp.pieces[1]
    view, br = piece.problem, piece.branch
    i = len(br) // 2
    c = view.full_state(br.u[i], br.p[i])
    free = AngularBasis(1, view.basis.K, mirror=False, M=view.basis.M)
    loose = same_load(view, free)
    H = loose.jacobian(loose.unknowns(transfer_coefficients(c, view.basis, free)), br.p[i])
    low = stability_info(H, 2, vectors=True)
    # the lowest eigenvector is the turning, its eigenvalue the quadrature's aliasing (M = 8 angles here),
    # two orders below the next
    turning = loose.unknowns(_turned_derivative(free, transfer_coefficients(c, view.basis, free)))
    assert abs(low.eigenvectors[:, 0] @ turning) / np.linalg.norm(turning) > 0.9999
    assert abs(low.eigenvalues[0]) < 2e-2 * low.eigenvalues[1]
    gauge, turn = gauge_for(free, transfer_coefficients(c, view.basis, free))
    held = same_load(view, free, gauge=gauge)
    u = held.unknowns(transfer_coefficients(c, view.basis, free, turn))
    Hg = held.jacobian(u, br.p[i])
    assert stability_info(Hg, 1).eigenvalues[0] / abs(Hg).max() > 1e-9
    assert np.max(np.abs(held.residual(u, br.p[i]))) < 1e-8 * held.residual_scale
    assert stability_info(Hg, 0).n_negative == 0 == view.stability(br.u[i], br.p[i], 0)["displacement"].n_negative
    with pytest.raises(ValueError, match="gauge"):
        same_load(view, view.basis, gauge=gauge)


def _turned_derivative(basis: AngularBasis, c: np.ndarray, step: float = 1e-6) -> np.ndarray:
    """d/d(angle) of the state turned about the axis, by central differences of the exact turn of its series."""
    from contin_models.shell.fourier import transfer_coefficients

    return (transfer_coefficients(c, basis, basis, step) - transfer_coefficients(c, basis, basis, -step)) / (2 * step)


@pytest.mark.slow
def test_under_a_dead_load_the_three_wave_branch_carries_the_load_to_its_own_limit_point() -> None:
    """The cap phi_hat = 0.6 under a dead load: the three-wave branch is stable and rises to a limit point below
    the axisymmetric one, where the cap snaps to the everted state, beyond the end of the load (w = 0.9 R)."""
    structure = ShellStructure(spherical_cap(1.0, 0.6, N), E, NU, H_OVER_R, boundary="sliding")
    source = ShellOfRevolution(structure, "point", "force", harmonics=5)
    settings = contin.Settings(ds=0.01, ds_max=0.02, max_steps=2000, param_weight=1e-2)
    fp = follow_path(source, source.reference_unknowns(), 0.0, settings, structure=structure, label="force",
                     end=("w", 0.9), K=K)
    assert fp.success, fp.message
    assert [(pc.symmetry, pc.end) for pc in fp.pieces] == [("O(2)", "bifurcation"), ("D3", "fold"),
                                                           ("O(2)", "end of load")]
    for piece in fp.pieces[:2]:
        assert np.all(piece.branch.n_negative_under("force")[:-1] == 0)
    assert fp.pieces[2].branch.observables["w"][0] >= 0.9 and fp.snaps[0].jump.success
    plain = ShellOfRevolution(structure, "point", "force")
    axisymmetric = contin.continuation(plain, plain.reference_unknowns(), 0.0, settings, stop_at=("fold",))
    limit = axisymmetric.special_points[-1]
    assert limit.kind == "fold"
    assert 0.9 * limit.p < fp.pieces[1].branch.p[-1] < limit.p  # the three-wave branch's limit load is lower


@pytest.mark.slow
def test_a_clamped_cap_under_pressure_snaps_from_its_five_wave_bifurcation() -> None:
    """The clamped default cap under pressure (N = 60): its five-wave branch falls back (subcritical), so the cap
    snaps there, at the bifurcation's pressure, and lands on the inverted axisymmetric cap."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene.build import build, traced_structure
    from contin_models.shell_scene.scene import SHELL_SCENE

    scene = load_scene(SHELL_SCENE.schema, None, ["load.kind=pressure", "load.control=force", "shell.boundary=clamped",
                                                  "stability.harmonics=true", "shell.N=60", "stability.n_max=8"])
    b = build(scene)
    fp = follow_path(b.problem, b.u0, 0.0, b.settings, structure=traced_structure(scene, b.problem), label="force",
                     p_end=b.settings.p_max, end=("w", b.settings.bounds["w"][1]), K=1)
    assert fp.success, fp.message
    first, second = fp.pieces
    stop = first.branch.special_points[-1]
    assert (first.end, stop.info["key"], second.symmetry, second.start) == ("bifurcation", 5, "O(2)", "snap")
    assert fp.snaps[0].p == pytest.approx(stop.p, rel=1e-5) and fp.snaps[0].jump.energy_to < fp.snaps[0].jump.energy_from
    assert np.all(second.branch.n_negative[: len(second.branch)] == 0)


@pytest.mark.slow
def test_a_sphere_pressing_the_cap_sideways_snaps_from_its_one_wave_bifurcation() -> None:
    """The default cap under a rigid sphere of radius R / 2 (N = 60, K = 2): past its maximum force the sphere's
    one-wave bifurcation falls back, the cap snaps sideways onto a state with one mirror plane, leaves it at a
    fold of the travel and lands on the everted cap, which the sphere then presses to the end of its travel."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene.build import build, traced_structure
    from contin_models.shell_scene.scene import SHELL_SCENE

    scene = load_scene(SHELL_SCENE.schema, None, ["load.kind=sphere", "load.radius=0.5", "stability.harmonics=true",
                                                  "shell.N=60", "stability.n_max=4"])
    b = build(scene)
    fp = follow_path(b.problem, b.u0, 0.0, b.settings, structure=traced_structure(scene, b.problem),
                     label="displacement", p_end=b.w_end, K=2)
    assert fp.success, fp.message
    assert [(pc.symmetry, pc.start, pc.end) for pc in fp.pieces] == [
        ("O(2)", "load", "bifurcation"), ("D1", "snap", "fold"), ("O(2)", "snap", "end of load")]
    assert fp.pieces[0].branch.special_points[-1].info["key"] == 1
    assert [sn.symmetry for sn in fp.snaps] == ["D1", "O(2)"]
    for piece in fp.pieces:
        counts = piece.branch.n_negative_under("displacement")
        assert np.all(counts[: len(counts) - (piece.end != "end of load")] == 0)


def test_a_piece_that_turns_back_at_a_fold_it_did_not_locate_stops_there() -> None:
    """A piece of the followed path goes on in the direction of loading; one that passes a fold of the load without
    locating it (a fold and a branch point next to each other leave every stored point's count at zero, as on the
    ring-loaded cap's four-wave piece) must not be followed backwards.  Here the fold of ``u^3 - 3 u = p`` at
    ``p = 2`` is only bracketed (``locate = False``) and the stability operator is positive throughout, so the
    counts do not catch it: the piece is cut at the last point before the load falls and the path stops, saying so.
    """
    problem = contin.Problem(residual=lambda u, p: np.array([u[0] ** 3 - 3.0 * u[0] - p]),
                             jacobian=lambda u, p: np.array([[3.0 * u[0] ** 2 - 3.0]]),
                             energy=lambda u, p: u[0] ** 4 / 4 - 1.5 * u[0] ** 2 - p * u[0],
                             stability_operator=lambda u, p: np.eye(1))
    settings = contin.Settings(ds=0.05, ds_max=0.1, max_steps=200, locate=False)
    out = follow_path(problem, np.array([-2.0]), -2.0, settings, structure=None, label="primary", p_end=5.0)
    assert out.status == "stopped" and "turns back in the load" in out.message
    p = np.asarray(out.pieces[0].branch.p)
    assert np.all(np.diff(p) >= 0.0) and 1.9 < p[-1] <= 2.0 + 1e-12


def test_a_monostable_cap_that_stays_axisymmetric_has_the_axisymmetric_paths_force_minimum() -> None:
    """The shallow cap of the paper's appendix B (phi_hat = 1.2) never leaves the axisymmetric path, so its
    followed path's class, force maximum and the force minimum after it are the axisymmetric path's.  The minimum
    was the least force on the whole path, the unloaded start's zero, beside the axisymmetric path's 1.44."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import run_scene

    scene = load_scene(SHELL_SCHEMA, None, ["shell.phi_hat=1.2", "shell.N=40", "view.harmonics=2",
                                            "stability.harmonics=true", "stability.follow=true",
                                            "output.figure=false"])
    result = run_scene(scene)
    s, f = result.summary, result.summary["followed"]
    assert result.success and f["path"][0]["ended"] == "end of load" and len(f["path"]) == 1
    assert s["classification"] == f["classification"] == "monostable"
    assert s["F_min_norm"] > 1.0  # a monostable cap's force stays positive after its maximum
    assert f["F_max_norm"] == pytest.approx(s["F_max_norm"], rel=1e-9)
    assert f["F_min_norm"] == pytest.approx(s["F_min_norm"], rel=1e-9)


@pytest.mark.slow
def test_a_followed_plate_ends_where_it_reaches_the_base_ring_as_the_axisymmetric_run_does() -> None:
    """The plate's travel ends where the plate comes within 2 dhat of the base ring (the axisymmetric run's bound
    on the base gap); the followed path's pieces went on past it until a step left the model's domain and
    reported a complete path as stopped."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import run_scene

    keys = ["load.kind=plate", "shell.N=40", "view.harmonics=2", "stability.harmonics=true", "output.figure=false"]
    plain = run_scene(load_scene(SHELL_SCHEMA, None, keys))
    followed = run_scene(load_scene(SHELL_SCHEMA, None, keys + ["stability.follow=true"]))
    assert plain.success and plain.branches[-1].status == "bound"
    assert followed.success and followed.summary["followed"]["path"][-1]["ended"] == "end of load"
    assert followed.branches[-1].p[-1] == pytest.approx(plain.branches[-1].p[-1], rel=1e-9)


def test_a_path_that_cannot_leave_its_stop_ends_there_and_says_why(monkeypatch) -> None:
    """A snap whose energy descent cannot start (no perturbation along the unstable mode lowers the energy) ends the
    followed path with the reason, as the lift's and the corrector's failures do; it escaped as an exception."""
    import contin_models.shell.followed as followed
    from contin.analyses.jump import JumpError

    def refuse(*args, **kwargs):
        raise JumpError("no perturbation along the unstable eigenvector lowers the energy")

    monkeypatch.setattr(followed, "_leave", refuse)
    source = _cap(0.6)
    fp = follow_path(source, source.reference_unknowns(), 0.0, contin.Settings(ds=0.01, ds_max=0.02, max_steps=2000),
                     structure=source.structure, label="displacement", p_end=0.45, K=K, events=LIMIT_LOADS)
    assert not fp.success and len(fp.pieces) == 1 and fp.pieces[0].end == "bifurcation"
    assert "could not leave the bifurcation" in fp.message and "lowers the energy" in fp.message


def test_a_followed_path_cut_short_has_no_class(monkeypatch) -> None:
    """A followed path that stops before its end (here: it cannot leave its first bifurcation) gets no class: the
    class of its first piece alone was reported as the shell's ("on the followed path the shell is monotonous")."""
    import contin_models.shell.followed as followed
    from contin.analyses.jump import JumpError
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import run_scene

    def refuse(*args, **kwargs):
        raise JumpError("no perturbation along the unstable eigenvector lowers the energy")

    monkeypatch.setattr(followed, "_leave", refuse)
    scene = load_scene(SHELL_SCHEMA, None, ["shell.phi_hat=0.9", "shell.N=40", "view.harmonics=2",
                                            "stability.harmonics=true", "stability.follow=true", "output.figure=false"])
    result = run_scene(scene)
    assert not result.success and result.summary["followed"]["status"] == "stopped"
    assert result.summary["followed"]["classification"] is None
    assert "on the followed path the shell is" not in result.message


def test_a_one_wave_bubble_that_rejoins_the_axisymmetric_path_is_followed_back_onto_it() -> None:
    """A monostable cap (lambda = 5.5) bifurcates into one wave and the one-wave branch rejoins the axisymmetric path
    at its second n = 1 bifurcation.  Where it rejoins, the piece's fold in the load is a pitchfork, and with K = 3
    neither the fold nor the branch point could be located: the path stopped there.  It now goes on from the last
    point before the junction, which lies where the axisymmetric trace locates that second bifurcation."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import run_scene

    scene = load_scene(SHELL_SCHEMA, None, ["shell.phi_hat=1.0", "shell.h=0.03231", "shell.N=80", "view.harmonics=3",
                                            "stability.harmonics=true", "stability.follow=true", "output.figure=false"])
    result = run_scene(scene)
    assert result.success, result.message
    f = result.summary["followed"]
    assert [item.get("symmetry") for item in f["path"] if "snap" not in item] == ["O(2)", "D1", "O(2)"]
    junction = [spt.p for spt in result.branches[0].special_points
                if spt.kind == "bifurcation" and spt.info.get("key") == 1 and spt.located][1]
    assert f["path"][1]["w_to"] == pytest.approx(junction, rel=1e-5)
    assert f["classification"] == result.summary["classification"] == "monostable"
    assert f["F_min_norm"] == pytest.approx(result.summary["F_min_norm"], rel=1e-6)


def test_a_followed_path_cut_short_after_its_force_fell_below_zero_is_bistable(monkeypatch) -> None:
    """The cap of 0.9 (N = 40, K = 2) pulls back (F < 0) on its one-wave piece, which ends at a located fold.  When
    the path cannot go on from there, that part of it still proves the cap bistable, as a force below zero on a stable
    part proves it on the axisymmetric path; ``contin classify`` gave it no class."""
    import contin_models.shell.followed as followed
    from contin.analyses.jump import JumpError
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import classify_scene

    leave = followed._leave
    calls = []

    def refuse_the_second(*args, **kwargs):
        calls.append(args[1])
        if len(calls) == 2:
            raise JumpError("no perturbation along the unstable eigenvector lowers the energy")
        return leave(*args, **kwargs)

    monkeypatch.setattr(followed, "_leave", refuse_the_second)
    scene = load_scene(SHELL_SCHEMA, None, ["shell.phi_hat=0.9", "shell.N=40", "view.harmonics=2",
                                            "stability.harmonics=true", "stability.follow=true", "output.figure=false"])
    c = classify_scene(scene)
    f = c.trace.summary["followed"]
    assert f["status"] == "stopped" and calls[1].kind == "fold"
    D1 = c.trace.branches[2]  # the axisymmetric trace, its followed piece, then the one-wave piece
    assert float(min(D1.observables["F"])) < 0.0
    assert c.label == f["classification"] == "bistable"


@pytest.mark.slow
def test_a_snap_from_the_end_of_a_one_wave_bubble_that_finds_nothing_lower_lands_where_it_is() -> None:
    """The cap of lambda = 5.4 at N = 160, K = 3: its one-wave branch rejoins the axisymmetric path at a pitchfork, and
    the descent from the fold there stalls at once ("line search failed to lower the energy"): the state past the
    junction is next to the stable axisymmetric one, with nothing lower to find.  The path stopped there; it now takes
    that state, made an equilibrium by Newton's method and checked stable, and goes on to the end of the load with the
    axisymmetric path's force minimum (the two are the same states past the junction)."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import run_scene

    h = (3 ** 0.5 * (math.pi / 2 - 1.0) / 5.4) ** 2  # lambda = 5.4 at nu = 0.5
    scene = load_scene(SHELL_SCHEMA, None, ["shell.phi_hat=1.0", f"shell.h={h!r}", "shell.N=160", "view.harmonics=3",
                                            "stability.harmonics=true", "stability.follow=true", "output.figure=false"])
    result = run_scene(scene)
    assert result.success, result.message
    f = result.summary["followed"]
    assert f["path"][-1]["symmetry"] == "O(2)" and f["path"][-1]["ended"] == "end of load"
    assert f["classification"] == result.summary["classification"] == "monostable"
    assert f["F_min_norm"] == pytest.approx(result.summary["F_min_norm"], rel=1e-6)
