"""The shell's command-line scene: outputs, special points, bad input, classification."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest

from contin.app.cli import main
from contin.app.scene import defaults
from contin.results.branch import SPECIAL_KINDS
from contin_models.shell_scene import SHELL_SCHEMA

FIELDS = ("kind", "parameter", "w", "F", "w_over_R", "F_norm", "residual")


def _trace(tmp_path: Path, *sets: str) -> tuple[int, dict]:
    args = ["trace", "--model", "shell", "-q", "--out", str(tmp_path)]
    for item in sets:
        args += ["--set", item]
    code = main(args)
    summary = json.loads((tmp_path / "summary.json").read_text()) if (tmp_path / "summary.json").exists() else {}
    return code, summary


def _rows(out: Path) -> list[dict[str, str]]:
    with open(out / "branch.csv", newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Path, int, dict]]:
    """The default scene at N = 40 under both controls, traced once for the tests of this module."""
    out: dict[str, tuple[Path, int, dict]] = {}
    for control in ("displacement", "force"):
        path = tmp_path_factory.mktemp(control)
        code, summary = _trace(path, "shell.N=40", f"load.control={control}")
        out[control] = (path, code, summary)
    return out


def test_default_scene_writes_outputs_and_special_points(runs: dict) -> None:
    tmp_path, code, summary = runs["displacement"]
    assert code == 0
    for name in ("summary.json", "branch.csv", "diagram.png"):
        assert (tmp_path / name).stat().st_size > 0
    assert summary["classification"] == "bistable"
    for key in ("F_max", "w_at_F_max", "F_min", "w_at_F_min", "F_max_norm", "w_at_F_max_over_R"):
        assert summary[key] is not None
    spts = summary["special_points"]
    params = {r["parameter"] for r in spts}
    assert params == {"w", "F"}
    zeros = [r for r in spts if r["kind"] == "event"]
    # falling zeros of F: where a one-sided point indenter would let go of the shell
    assert zeros and all(r["label"] == "F = 0" and abs(r["F"]) < 1e-8 * summary["F_max"] for r in zeros)
    assert summary["w_c_one_sided"] == zeros[0]["w"] and summary["one_sided_snap_kind"] == "F = 0"
    # the first zero comes after the force maximum, on the way down
    assert summary["w_at_F_max"] < summary["w_c_one_sided"]
    spts = [r for r in spts if r["kind"] != "event"]
    for rec in spts:
        for key in FIELDS:
            assert key in rec, (key, rec)
        assert rec["kind"] == "fold"
        assert "stable_before" in rec and "stable_after" in rec
        # the label changes exactly at the fold, by one negative eigenvalue
        assert abs(rec["n_negative_after"] - rec["n_negative_before"]) == 1
    # the first special point is the force maximum: force-stable before, unstable after
    assert spts[0]["parameter"] == "F" and spts[0]["label"] == "max(F)"
    assert spts[0]["stable_before"] and not spts[0]["stable_after"]
    # path order: the arclength index never decreases
    assert [r["index"] for r in spts] == sorted(r["index"] for r in spts)
    with open(tmp_path / "branch.csv") as fh:
        header = next(csv.reader(fh))
    for col in ("w", "F", "w_over_R", "F_norm", "stable_force", "stable_displacement", "n_negative"):
        assert col in header


@pytest.mark.parametrize("item, field", [
    ("shell.h=-1", "shell.h"), ("shell.phi_hat=2", "shell.phi_hat"), ("shell.N=5", "shell.N"),
    ("shell.nu=0.7", "shell.nu"), ('load.kind="cylinder"', "load.kind"), ("shell.h=1.5", "shell.h"),
])
def test_bad_input_is_one_paragraph_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture, item: str,
                                            field: str) -> None:
    code, _ = _trace(tmp_path, item)
    err = capsys.readouterr().err
    assert code == 2
    assert field in err
    assert "Traceback" not in err
    assert err.strip().count("\n") == 0


@pytest.mark.parametrize("phi_hat, expected", [(0.8, "bistable"), (1.2, "monostable"), (1.35, "monotonous")])
def test_classification_at_h_over_R_0_02(tmp_path: Path, phi_hat: float, expected: str) -> None:
    code, summary = _trace(tmp_path, "shell.N=60", f"shell.phi_hat={phi_hat}", "output.figure=false")
    assert code == 0
    assert summary["classification"] == expected
    if expected == "monostable":
        assert 0 < summary["F_min"] < summary["F_max"]
        assert summary["w_at_F_max"] < summary["w_at_F_min"]


def test_monostable_middle_part_unstable_under_force_stable_under_displacement(tmp_path: Path) -> None:
    code, summary = _trace(tmp_path, "shell.N=40", "shell.phi_hat=1.2", "output.figure=false")
    assert code == 0
    with open(tmp_path / "branch.csv") as fh:
        rows = list(csv.DictReader(fh))
    lo, hi = summary["w_at_F_max"], summary["w_at_F_min"]
    inside = [r for r in rows if lo < float(r["w"]) < hi]
    assert inside
    assert all(r["stable_force"] == "0" and r["stable_displacement"] == "1" for r in inside)
    assert all(r["stable_displacement"] == "1" for r in rows)  # single-valued in w: no snap-back


def test_force_control_snaps_to_the_everted_state(runs: dict) -> None:
    _, code, summary = runs["force"]
    assert code == 0
    assert len(summary["jumps"]) == 1 and summary["jumps"][0]["success"]
    first = summary["special_points"][0]
    assert first["parameter"] == "F" and first["stable_before"]
    landing = [r for r in summary["special_points"] if r.get("label") == "jump_to"][0]
    assert landing["w"] > summary["eversion_w"] * 0.9


@pytest.mark.parametrize("control", ["displacement", "force"])
def test_summary_and_csv_follow_the_command_line_contract(runs: dict, control: str) -> None:
    """The command line's contract (``docs/cli.md``): the fields of summary.json and the columns of branch.csv."""
    out, code, summary = runs[control]
    assert code == 0
    # the fully resolved scene: every key of the schema, the overrides applied
    expected = defaults(SHELL_SCHEMA)
    expected["shell"]["N"] = 40
    expected["load"]["control"] = control
    assert summary["scene"] == expected
    assert summary["wall_time_s"] > 0
    assert summary["n_steps"] == sum(b["n_steps"] for b in summary["branches"]) > 0
    # classification: defined on the displacement-controlled path only
    assert "classification" in summary and summary["classification_note"]
    assert summary["classification"] == ("bistable" if control == "displacement" else None)
    R, D = summary["scene"]["shell"]["R"], summary["D"]
    spts = summary["special_points"]
    assert spts
    for rec in spts:
        assert rec["kind"] in SPECIAL_KINDS
        for key in FIELDS:
            assert key in rec, (key, rec)
        # which quantity folds: F at a limit point under force control, w at a fold of the controlled w
        if rec["kind"] == "fold":
            assert rec["parameter"] == ("F" if rec.get("label") in ("max(F)", "min(F)") or control == "force"
                                        else "w")
        if rec["kind"] == "jump":
            assert rec["parameter"] == "F"  # the load is held fixed during a snap
        assert rec["w_over_R"] == pytest.approx(rec["w"] / R, rel=1e-12)
        assert rec["F_norm"] == pytest.approx(rec["F"] * R / (2 * math.pi * D), rel=1e-12)
        # every point states its own residual (its size is the engine's business, tested there)
        assert isinstance(rec["residual"], float) and math.isfinite(rec["residual"]) and rec["residual"] >= 0
        for key in ("stable_before", "stable_after"):
            assert rec.get(key) in (None, True, False)
    if control == "force":
        kinds = [(r["kind"], r.get("label")) for r in spts]
        assert kinds[:3] == [("fold", ""), ("jump", "jump_from"), ("jump", "jump_to")]
        fold, start, landing = spts[:3]
        assert fold["stable_before"] is True and start["stable_before"] is True
        assert start["residual"] == fold["residual"] and start["w"] == fold["w"]
        assert landing["stable_after"] is True
    rows = _rows(out)
    assert len(rows) == sum(b["n_points"] for b in summary["branches"])
    for col in ("w", "F", "w_over_R", "F_norm", "stable_force", "stable_displacement", "n_negative"):
        assert col in rows[0], col
    for r in rows:
        assert r["stable_displacement"] == ("1" if r["n_negative"] == "0" else "0")
        assert r["stable_force"] in ("0", "1")
        assert float(r["w_over_R"]) == pytest.approx(float(r["w"]) / R, rel=1e-12, abs=1e-300)


def _classify(capsys: pytest.CaptureFixture, *args: str) -> tuple[int, str, str]:
    code = main(["classify", "-q", *args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_classify_traces_the_displacement_path_whatever_the_control(runs: dict,
                                                                     capsys: pytest.CaptureFixture) -> None:
    _, _, traced = runs["displacement"]
    code, stdout, stderr = _classify(capsys, "--json", "--set", "shell.N=40", "--set", "load.control=force")
    assert code == 0 and stderr == ""
    doc = json.loads(stdout)
    assert doc["classification"] == "bistable" and doc["success"] is True and doc["status"] == "ok"
    assert doc["control_traced"] == "displacement" and doc["path_complete"] is True
    assert doc["scene"]["load"]["control"] == "force"  # the scene as given
    for key in ("F_max", "w_at_F_max", "F_min", "w_at_F_min", "F_max_norm", "w_at_F_max_over_R", "F_min_norm",
                "w_at_F_min_over_R"):
        assert doc[key] == pytest.approx(traced[key], rel=1e-9), key
    assert doc["F_max"] > 0 > doc["F_min"]
    assert doc["n_steps"] == traced["n_steps"] and doc["wall_time_s"] > 0


def test_classify_prints_the_class_and_the_extrema(capsys: pytest.CaptureFixture) -> None:
    code, stdout, _ = _classify(capsys, "--set", "shell.N=40", "--set", "shell.phi_hat=1.2")
    assert code == 0
    lines = stdout.splitlines()
    assert lines[0] == "classification (shell): monostable" and lines[-1] == "status: ok"
    assert "F R/(2 pi D)" in stdout and "w/R" in stdout
    assert any(line.split()[0] == "F_max" for line in lines[1:]) and any(line.split()[0] == "F_min" for line in lines[1:])


def test_classify_undecided_when_the_path_stops_early(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    # a monostable cap: its everted branch carries no stable F < 0, so nothing but the whole path decides
    code, stdout, stderr = _classify(capsys, "--json", "--set", "shell.N=40", "--set", "shell.phi_hat=1.2",
                                     "--set", "continuation.max_steps=5")
    assert code == 1 and "Traceback" not in stderr
    doc = json.loads(stdout)
    assert doc["classification"] is None and doc["success"] is False and doc["path_complete"] is False
    assert "did not reach eversion" in doc["message"]
    # trace says the same in summary.json, with what the traced part looks like
    code, summary = _trace(tmp_path, "shell.N=40", "shell.phi_hat=1.2", "continuation.max_steps=5")
    assert summary["classification"] is None and summary["classification_on_partial_path"] == "monotonous"


def test_the_shapes_at_the_special_points_are_saved_and_drawn(runs: dict, tmp_path: Path) -> None:
    """``shapes.npz``: one deformed meridian per special point of ``summary.json``, whose pole sits the
    point's ``w`` below the reference pole; ``shapes.png`` beside it, and neither figure with
    ``output.figure = false`` (a figure left by an earlier run is removed)."""
    import numpy as np

    out, code, summary = runs["displacement"]
    assert code == 0 and (out / "shapes.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    shapes = np.load(out / "shapes.npz")
    branch_records = [r for r in summary["special_points"] if r["kind"] not in ("jump_from", "jump_to")]
    assert len(shapes["special_kind"]) == len(branch_records) and shapes["special_r"].shape == (len(branch_records), 40)
    for k, rec in enumerate(branch_records):
        assert str(shapes["special_kind"][k]) == rec["kind"]
        assert shapes["reference_z"][-1] - shapes["special_z"][k][-1] == pytest.approx(rec["w"], abs=1e-12)
    assert "path_r" not in shapes  # the path's shapes only on request
    (tmp_path / "shapes.png").write_bytes(b"old")
    code, _ = _trace(tmp_path, "shell.N=40", "output.figure=false", "continuation.max_steps=20", "output.shapes=path")
    assert not (tmp_path / "shapes.png").exists() and (tmp_path / "shapes.npz").exists()
    # on request, the meridian at every row of branch.csv: its pole w below the reference pole
    shapes = np.load(tmp_path / "shapes.npz")
    with open(tmp_path / "branch.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert shapes["path_r"].shape == shapes["path_z"].shape == (len(rows), 40) and len(rows) > 10
    np.testing.assert_array_equal(shapes["path_p"], [float(r["p"]) for r in rows])
    np.testing.assert_array_equal(shapes["path_branch"], [int(float(r["branch"])) for r in rows])
    np.testing.assert_allclose(shapes["reference_z"][-1] - shapes["path_z"][:, -1], [float(r["w"]) for r in rows],
                               atol=1e-12)


@pytest.mark.parametrize("N, control, expected", [(40, "force", "finer mesh, shell.N = 80"),
                                                   (800, "force", 'load.control = "displacement"'),
                                                   (800, "displacement", 'load.control = "force"')])
def test_mesh_advice_fits_the_mesh(N: int, control: str, expected: str) -> None:
    """A finer mesh is the advice on a coarse mesh only: at N = 800 the default cap has 147 nodes over
    its bending length, where a failure is the solver's, not the mesh's."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene.scene import mesh_advice

    scene = load_scene(SHELL_SCHEMA, None, [f"shell.N={N}", f"load.control={control}"])
    advice = mesh_advice(scene)
    assert expected in advice
    assert ("unlikely to help" in advice) == (N == 800)


#: Scene 179 of ``python -m studies.fuzz --count 300 --seed 33``: a thin deep cap under a point load and
#: displacement control whose path winds on its own mesh (4.1 nodes over sqrt(R h)) and ends at N = 150.
WINDING_CAP = ["shell.R=404.6728351562885", "shell.E=87152877039.92862", "shell.h=1.5456817528166313",
               "shell.phi_hat=0.42974739211929047", "shell.nu=-0.31562760121326794", "shell.N=75"]


def test_a_path_cut_by_the_automatic_step_limit_on_a_coarse_mesh_is_told_to_refine(monkeypatch) -> None:
    """Running out of the automatic step limit on a mesh too coarse for the wrinkles in the middle of the
    path: the advice is the mesh that ends such paths, not more steps; with a step limit of the user's
    own, or on a mesh fine enough for the middle, there is no such advice."""
    import importlib

    from contin.app.scene import load_scene
    from contin_models.shell_scene import schema
    from contin_models.shell_scene.scene import WRINKLE_NODES, run_scene, winding_advice
    from contin_models.shell_scene.schema import nodes_per_bending_length

    build = importlib.import_module("contin_models.shell_scene.build")  # the package's name 'build' is a function
    monkeypatch.setattr(build, "AUTO_MAX_STEPS", 40)  # the limit itself is 200000 steps: minutes of winding
    # the wrinkle rule refuses this cap at validation; the advice is for the paths it does not cover
    monkeypatch.setattr(schema, "WRINKLE_DEPTH", math.inf)
    scene = load_scene(SHELL_SCHEMA, None, WINDING_CAP + ["output.figure=false"])
    result = run_scene(scene)
    assert result.status == "incomplete"
    needed = math.ceil(WRINKLE_NODES / nodes_per_bending_length(scene["shell"], N=1))
    assert needed == 157  # 8.5 nodes over sqrt(R h); measured: this cap winds at N = 110 and ends at N = 150
    assert "advice: the path wound through folds" in result.message and f"shell.N = {needed}" in result.message

    chosen = load_scene(SHELL_SCHEMA, None, WINDING_CAP + ["continuation.max_steps=40"])
    assert winding_advice(chosen) is None
    fine = load_scene(SHELL_SCHEMA, None, WINDING_CAP[:-1] + [f"shell.N={needed}"])
    assert winding_advice(fine) is None


def test_a_deep_cap_whose_path_crosses_its_wrinkled_middle_is_refused_below_the_wrinkle_mesh() -> None:
    """The cap of WINDING_CAP winds for 200000 steps on its own mesh: validation refuses it with the number of
    nodes its middle needs, while the scenes whose path does not cross that middle on the same mesh pass."""
    from contin.app.scene import SceneError, load_scene
    from contin_models.shell.boundaries import depth_parameter
    from contin_models.shell_scene.schema import WRINKLE_DEPTH, wrinkle_nodes

    with pytest.raises(SceneError, match=r"lambda = 33\.5\) needs shell\.N >= 133 for its path's middle"):
        load_scene(SHELL_SCHEMA, None, WINDING_CAP)
    scene = load_scene(SHELL_SCHEMA, None, WINDING_CAP[:-1] + ["shell.N=133"])
    assert wrinkle_nodes(scene["shell"]) == 133  # 7.2 nodes over sqrt(R h); measured: winds at 6.0, ends at 8.1
    # the point force on the paper's cap snaps over the middle; on a pinned edge it traces it
    load_scene(SHELL_SCHEMA, None, WINDING_CAP + ["load.control=force"])
    with pytest.raises(SceneError, match="path's middle"):
        load_scene(SHELL_SCHEMA, None, WINDING_CAP + ["load.control=force", "shell.boundary=pinned"])
    # a ring within four bending lengths of the pole loads the cap as a point does; a wider one ends at its own
    # eversion first
    bending_length = math.sqrt(404.6728351562885 * 1.5456817528166313)
    with pytest.raises(SceneError, match="path's middle"):
        load_scene(SHELL_SCHEMA, None, WINDING_CAP + ["load.kind=ring", f"load.ring_radius={3.9 * bending_length}"])
    load_scene(SHELL_SCHEMA, None, WINDING_CAP + ["load.kind=ring", f"load.ring_radius={4.1 * bending_length}"])
    # a shallower cap on as coarse a mesh: below the depth at which the middle wrinkles so
    shallower = [k for k in WINDING_CAP if not k.startswith("shell.h=")] + [f"shell.h={1.5456817528166313 * 1.3}"]
    shell = load_scene(SHELL_SCHEMA, None, shallower)["shell"]
    assert depth_parameter(shell["phi_hat"], shell["h"] / shell["R"], shell["nu"]) < WRINKLE_DEPTH


@pytest.mark.slow
def test_force_control_snaps_on_a_fine_mesh(tmp_path: Path) -> None:
    """At N = 800 the snap's energy descent met a ridge whose negative curvature was far below the
    Levenberg shift and crawled along it for 500 iterations; a step along the negative curvature
    (contin.jump) leaves it: the default cap snaps to the everted state (measured 59 iterations)."""
    out = tmp_path / "fine"
    code = main(["trace", "-q", "--set", "shell.N=800", "--set", "load.control=force", "--set", "output.figure=false",
                 "--out", str(out)])
    summary = json.loads((out / "summary.json").read_text())
    assert code == 0 and summary["status"] == "ok", summary["message"]
    (jump,) = summary["jumps"]
    assert jump["success"]
