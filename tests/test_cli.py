"""The ``contin`` command line: outputs, the special-point summary, and the error contract."""

from __future__ import annotations

import csv
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import contin
from contin.app import cli, registry
from contin.app.scene import (Classification, SceneError, SceneModel, Schema, TraceResult, can_classify, integer,
                          load_scene, real)

OUTPUTS = {"summary.json", "branch.csv", "diagram.png", "states.npz"}


def run_cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def read_summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


def read_csv(out: Path) -> list[dict[str, str]]:
    with open(out / "branch.csv", newline="") as fh:
        return list(csv.DictReader(fh))


# ---- successful runs ----------------------------------------------------------------------------------
def test_trace_bratu_writes_outputs_and_locates_the_fold(tmp_path, capsys):
    out = tmp_path / "out"
    code, stdout, stderr = run_cli(capsys, "trace", "--model", "bratu", "--out", str(out), "--quiet")
    assert code == 0, stderr
    assert {p.name for p in out.iterdir()} == OUTPUTS  # no temporary files left behind
    assert stderr == ""  # --quiet
    summary = read_summary(out)
    assert summary["model"] == "bratu" and summary["status"] == "ok" and summary["success"] is True
    assert summary["scene"]["model"]["n"] == 200  # the fully resolved scene
    assert summary["scene"]["continuation"]["stability"] is True
    assert summary["n_steps"] > 0 and summary["wall_time_s"] > 0
    folds = [sp for sp in summary["special_points"] if sp["kind"] == "fold"]
    assert len(folds) == 1
    fold = folds[0]
    # n = 200 discretises the continuum fold 3.513830719
    assert abs(fold["p"] - 3.51) < 0.01
    assert fold["parameter"] == "lam" and fold["located"] and fold["residual"] < 1e-8
    assert "max_u" in fold["observables"]
    rows = read_csv(out)
    assert len(rows) == summary["n_steps"] + 1
    assert {"p", "max_u", "u_mid", "residual"} <= set(rows[0])
    assert max(float(r["max_u"]) for r in rows) == pytest.approx(4.0)  # stopped on the max_u bound
    assert (out / "diagram.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "fold" in stdout and "status: ok" in stdout


def test_trace_with_stability_reports_it(tmp_path, capsys):
    out = tmp_path / "o"
    code, stdout, _ = run_cli(capsys, "trace", "-m", "bratu", "-q", "-o", str(out), "--set", "model.n=20",
                              "--set", "continuation.stability=true")
    assert code == 0
    fold = read_summary(out)["special_points"][0]
    assert fold["stable_before"] is True and fold["stable_after"] is False
    rows = read_csv(out)
    assert rows[0]["stable"] == "1" and rows[-1]["stable"] == "0" and rows[-1]["n_negative"] == "1"
    assert "stable -> unstable" in stdout


def test_scene_file_and_overrides(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text("[model]\nn = 10\n\n[continuation]\nmax_u = 2\n")
    out = tmp_path / "o"
    code, _, err = run_cli(capsys, "trace", str(scene), "--model", "bratu", "-q", "-o", str(out),
                           "--set", "model.n=12")
    assert code == 0, err
    resolved = read_summary(out)["scene"]
    assert resolved["model"]["n"] == 12  # --set wins over the file
    assert resolved["continuation"]["max_u"] == 2.0  # an integer where a float is expected
    assert resolved["continuation"]["ds"] == 0.1  # default filled in


def test_truss_hysteresis_cycle(tmp_path, capsys):
    out = tmp_path / "o"
    code, stdout, err = run_cli(capsys, "trace", "--model", "truss", "-q", "-o", str(out), "--set", "load.cycle=true")
    assert code == 0, err
    summary = read_summary(out)
    assert summary["hysteresis_loops"] == 1
    assert [b["label"] for b in summary["branches"]] == ["loading", "unloading", "reloading"]
    assert len(summary["jumps"]) == 2 and all(j["success"] for j in summary["jumps"])
    p_max = summary["P_max_closed_form"]
    folds = [sp["p"] for sp in summary["special_points"] if sp["kind"] == "fold"]
    assert folds == pytest.approx([p_max, -p_max, p_max], rel=1e-9)
    assert {r["branch"] for r in read_csv(out)} == {"0", "1", "2"}
    assert "jump_to" in stdout


def test_truss_s_curve_stability(tmp_path, capsys):
    out = tmp_path / "o"
    code, _, _ = run_cli(capsys, "trace", "--model", "truss", "-q", "-o", str(out))
    assert code == 0
    folds = [sp for sp in read_summary(out)["special_points"] if sp["kind"] == "fold"]
    assert [(f["stable_before"], f["stable_after"]) for f in folds] == [(True, False), (False, True)]


def test_console_script(tmp_path):
    exe = Path(sys.executable).parent / "contin"
    if not exe.exists():
        exe = Path(shutil.which("contin") or "contin")
    out = tmp_path / "o"
    proc = subprocess.run([str(exe), "trace", "--model", "bratu", "--set", "model.n=20", "--out", str(out)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert {p.name for p in out.iterdir()} == OUTPUTS
    assert "Traceback" not in proc.stderr
    assert "contin: tracing" in proc.stderr  # progress goes to stderr
    assert "status: ok" in proc.stdout


def test_models_lists_bratu_and_truss(capsys):
    code, stdout, _ = run_cli(capsys, "models")
    assert code == 0
    assert "bratu (trace):" in stdout and "truss (trace):" in stdout
    assert "shell (default, trace, classify):" in stdout
    assert "n = 200" in stdout and "cycle = false" in stdout
    assert "phi_hat = 0.8" in stdout and "a float in (0, 1.5708)" in stdout  # the shell's keys with ranges


def test_models_toml_is_a_scene_file_of_the_defaults(tmp_path, capsys):
    code, stdout, _ = run_cli(capsys, "models", "--toml")  # the default model
    assert code == 0
    scene = tmp_path / "scene.toml"
    scene.write_text(stdout)
    schema = cli.load_model("shell").schema
    assert load_scene(schema, scene) == load_scene(schema)
    code, stdout, _ = run_cli(capsys, "models", "bratu", "--toml")
    assert code == 0 and stdout.count("[model]") == 1 and "[shell]" not in stdout
    code, _, stderr = run_cli(capsys, "models", "bratu", "truss", "--toml")
    assert code == 2 and "one model" in stderr


def test_default_model_is_the_papers_shell_scene():
    # the registry names the default (the shell's runner says default = True); the command line names none
    assert registry.default_model() == "shell"
    scene = load_scene(cli.load_model(registry.default_model()).schema)
    shell = scene["shell"]
    assert (shell["phi_hat"], shell["h"] / shell["R"], shell["N"]) == (0.8, 0.02, 200)
    assert scene["load"]["kind"] == "point" and scene["load"]["control"] == "displacement"


def test_trace_without_model_traces_the_shell(tmp_path, capsys):
    out = tmp_path / "o"
    code, stdout, stderr = run_cli(capsys, "trace", "-q", "--set", "shell.N=40", "--out", str(out))
    assert code == 0, stderr
    summary = read_summary(out)
    assert summary["model"] == "shell" and summary["scene"]["shell"]["phi_hat"] == 0.8
    assert summary["classification"] == "bistable"
    assert "max(F)" in stdout and "status: ok" in stdout
    # issue 18: the table and the status line fit 100 columns; what the table leaves out is named
    assert max(len(line) for line in stdout.splitlines()) <= 100
    assert "(not shown: residual" in stdout and "summary.json has every column" in stdout


def test_help_exits_zero(capsys):
    assert cli.main(["--help"]) == 0
    text = capsys.readouterr().out
    assert all(cmd in text for cmd in ("trace", "classify", "models")) and "default model 'shell'" in text
    assert cli.main(["trace", "--help"]) == 0
    text = capsys.readouterr().out
    assert "summary.json" in text and "stable_displacement" in text
    assert "[shell]" in text and "phi_hat = 0.8" in text and "contin models shell" in text  # keys discoverable
    assert cli.main(["classify", "--help"]) == 0
    text = capsys.readouterr().out
    assert "--json" in text and "F R/(2 pi D)" in text and "phi_hat = 0.8" in text
    assert cli.main(["models", "--help"]) == 0
    assert "--toml" in capsys.readouterr().out


# ---- the error contract --------------------------------------------------------------------------------
def _assert_input_error(code: int, stdout: str, stderr: str, out: Path, *needles: str) -> None:
    assert code == 2
    assert stderr.startswith("contin: error:")
    assert stderr.count("\n") == 1 and stderr.endswith("\n")  # one paragraph
    assert "Traceback" not in stderr
    for needle in needles:
        assert needle in stderr
    assert not out.exists() or not any(out.iterdir())  # nothing written, not even temporaries


BAD_INPUT = [
    (["-m", "bratu", "--set", "model.n=1"], ["model.n", "1", "an integer >= 2"]),
    (["-m", "bratu", "--set", "model.nn=3"], ["model.nn", "allows: n"]),
    (["-m", "bratu", "--set", "model.n=abc"], ["model.n", "abc", "expected an integer"]),
    (["-m", "bratu", "--set", "model.n=true"], ["model.n", "expected an integer"]),  # a bool is not an int
    (["-m", "bratu", "--set", "model.n"], ["model.n", "section.key=value"]),
    (["-m", "bratu", "--set", "plot.x=1"], ["[plot]", "[model]"]),
    (["-m", "bratu", "--set", "continuation.ds=0.5", "--set", "continuation.ds_max=0.1"], ["continuation.ds", "ds_max"]),
    (["--model", "nope"], ["nope", "bratu", "truss", "shell"]),
    (["--model", "truss", "--set", "model.b=2.5"], ["model.b", "2.4", "branch points"]),
    (["--no-such-option"], ["--no-such-option"]),
    # the default model is the shell: its keys, and a hint when another model's key is given
    (["--set", "model.n=5"], ["[model]", "[shell]", "default model 'shell'", "--model"]),
    (["--set", "shell.N=5"], ["shell.N", "5", "an integer >= 10"]),
    (["--set", "shell.phi_hat=1.6"], ["shell.phi_hat", "1.6", "a float in (0, 1.5708)"]),
    (["--set", "load.control=pressure"], ["load.control", "pressure", '"displacement", "force"']),
    (["--set", "shell.h=2"], ["shell.h", "shell.R", "thin"]),
]


@pytest.mark.parametrize("args, needles", BAD_INPUT)
def test_bad_input_exits_2(tmp_path, capsys, args, needles):
    out = tmp_path / "out"
    code, stdout, stderr = run_cli(capsys, "trace", *args, "--out", str(out))
    _assert_input_error(code, stdout, stderr, out, *needles)


@pytest.mark.parametrize("args, needles", BAD_INPUT)
def test_classify_bad_input_exits_2(tmp_path, capsys, args, needles):
    if args[:2] in (["-m", "bratu"], ["--model", "truss"]):
        needles = ["cannot classify"]  # checked before the scene: these models have no classification
    code, stdout, stderr = run_cli(capsys, "classify", *args)
    _assert_input_error(code, stdout, stderr, tmp_path / "nothing", *needles)
    assert stdout == ""


def test_truncated_scene_file(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text("[model]\nn = 20\n[continuation\nds = ")
    out = tmp_path / "out"
    code, stdout, stderr = run_cli(capsys, "trace", str(scene), "--out", str(out))
    _assert_input_error(code, stdout, stderr, out, "scene.toml", "not valid TOML", "line 3")


def test_missing_scene_file(tmp_path, capsys):
    out = tmp_path / "out"
    code, stdout, stderr = run_cli(capsys, "trace", str(tmp_path / "none.toml"), "--out", str(out))
    _assert_input_error(code, stdout, stderr, out, "none.toml")


def test_unwritable_out(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    for out in (blocker, blocker / "sub"):
        code, stdout, stderr = run_cli(capsys, "trace", "--model", "bratu", "--set", "model.n=10", "--out", str(out))
        assert code == 2 and stderr.startswith("contin: error:") and str(blocker) in stderr
        assert "Traceback" not in stderr
    assert blocker.read_text() == "x"


def test_numerical_failure_still_writes_outputs(tmp_path, capsys):
    out = tmp_path / "out"
    big = ["--set", "continuation.ds_min=0.5", "--set", "continuation.ds=0.5", "--set", "continuation.ds_max=0.5"]
    code, stdout, stderr = run_cli(capsys, "trace", "-q", "--model", "bratu", "--set", "model.n=20", *big,
                                   "--out", str(out))
    assert code == 1
    assert {p.name for p in out.iterdir()} == OUTPUTS
    summary = read_summary(out)
    assert summary["success"] is False and summary["status"] == "min_step"
    assert "ds_min" in summary["message"] and "status: min_step" in stdout


# ---- interrupts, with a stand-in model ---------------------------------------------------------------------
def _fake_model(run) -> SceneModel:
    return SceneModel("fake", "a stand-in", Schema({"model": {"n": integer(3, low=1)}}), run)


def _tiny_branch() -> contin.Branch:
    return contin.Branch(p=np.array([0.0, 1.0]), u=np.zeros((2, 1)), s=np.array([0.0, 1.0]),
                         tangent_p=np.ones(2), residual=np.zeros(2), newton_iterations=np.zeros(2, dtype=int),
                         observables={"a": np.array([0.0, 2.0])}, status="bound", message="done",
                         meta={"parameter_name": "q", "n_steps": 1})


def test_ctrl_c_during_run_exits_130(tmp_path, capsys, monkeypatch):
    def run(scene, progress):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "load_model", lambda name: _fake_model(run))
    out = tmp_path / "out"
    code, _, stderr = run_cli(capsys, "trace", "--out", str(out))
    assert code == 130 and "Traceback" not in stderr and "interrupted" in stderr
    assert not out.exists()  # the run made it and wrote nothing: it is removed again (issue 14, B4)
    # a directory that was there before the run stays, with what it held
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    code, _, _ = run_cli(capsys, "trace", "-q", "--out", str(out / "a" / "b"))
    assert code == 130 and [p.name for p in out.iterdir()] == ["notes.txt"]
    out.joinpath("empty").mkdir()
    code, _, _ = run_cli(capsys, "trace", "-q", "--out", str(out / "empty"))
    assert code == 130 and (out / "empty").is_dir()


def test_ctrl_c_while_writing_leaves_no_partial_files(tmp_path, capsys, monkeypatch):
    def plot(ax):
        raise KeyboardInterrupt  # the figure is written last: summary and CSV are already in temp files

    def run(scene, progress):
        res = TraceResult.from_branches([_tiny_branch()], x="p", y="a")
        res.plot = plot
        return res

    monkeypatch.setattr(cli, "load_model", lambda name: _fake_model(run))
    out = tmp_path / "out"
    code, _, _ = run_cli(capsys, "trace", "-q", "--out", str(out))
    assert code == 130
    assert not out.exists()  # no partial file, and not the empty directory the run made


def test_runner_protocol_with_stand_in(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cli, "load_model", lambda name: _fake_model(
        lambda scene, progress: TraceResult.from_branches([_tiny_branch()], x="p", y="a", summary={"extra": scene})))
    out = tmp_path / "out"
    code, _, _ = run_cli(capsys, "trace", "-q", "--out", str(out), "--set", "model.n=5")
    assert code == 0
    summary = read_summary(out)
    assert summary["extra"] == {"model": {"n": 5}} and summary["parameter"] == "q"
    assert [r["a"] for r in read_csv(out)] == ["0.0", "2.0"]


# ---- the scene loader ------------------------------------------------------------------------------------
SCHEMA = Schema({"m": {"x": real(1.0, gt=0), "k": integer(5, low=1, high=10)}})


def test_load_scene_types_and_defaults():
    assert load_scene(SCHEMA) == {"m": {"x": 1.0, "k": 5}}
    scene = load_scene(SCHEMA, overrides=["m.x=2", "m.k=7"])
    assert scene == {"m": {"x": 2.0, "k": 7}} and isinstance(scene["m"]["x"], float)
    with pytest.raises(SceneError, match=r"m\.x = true .*expected a number"):
        load_scene(SCHEMA, overrides=["m.x=true"])
    with pytest.raises(SceneError, match=r"m\.k = 11 .*an integer in \[1, 10\]"):
        load_scene(SCHEMA, overrides=["m.k=11"])


def test_scene_error_is_one_paragraph(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[m]\nx = "a\nb"\n')
    with pytest.raises(SceneError) as info:
        load_scene(SCHEMA, bad)
    assert "\n" not in str(info.value) and "bad.toml" in str(info.value)


def test_scene_error_raised_inside_a_runner_is_bad_input(monkeypatch, capsys, tmp_path):
    from contin.app import cli
    from contin.app.scene import SceneError

    import dataclasses

    def failing_run(scene, progress):
        raise SceneError("scene field model.n = 7 cannot be combined with this run; allowed: anything else")

    runner = dataclasses.replace(cli.load_model("bratu"), runner=failing_run)
    monkeypatch.setattr(cli, "load_model", lambda name: runner)
    code = cli.main(["trace", "--out", str(tmp_path / "o"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("contin: error:") and "model.n" in err and "Traceback" not in err
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").iterdir())


# ---- classify, with stand-in models ------------------------------------------------------------------------
def _classifying_model(classify) -> SceneModel:
    return SceneModel("fake", "a stand-in", Schema({"model": {"n": integer(3, low=1)}}),
                      lambda scene, progress: TraceResult.from_branches([_tiny_branch()]), classifier=classify)


def test_classify_prints_the_models_class_and_json(capsys, monkeypatch):
    def classify(scene, progress):
        trace = TraceResult.from_branches([_tiny_branch()])
        return Classification("wobbly", values={"peak": 2.5, "n": scene["model"]["n"]}, lines=["peak = 2.5"],
                              trace=trace)

    monkeypatch.setattr(cli, "load_model", lambda name: _classifying_model(classify))
    code, stdout, stderr = run_cli(capsys, "classify", "--set", "model.n=7")
    assert code == 0
    assert stdout.splitlines() == ["classification (shell): wobbly", "  peak = 2.5", "status: ok"]
    assert "contin: classifying model 'shell'" in stderr  # progress on stderr, like trace
    code, stdout, stderr = run_cli(capsys, "classify", "-q", "--json", "--set", "model.n=7")
    assert code == 0 and stderr == ""
    doc = json.loads(stdout)
    assert doc["classification"] == "wobbly" and doc["success"] is True and doc["status"] == "ok"
    assert doc["peak"] == 2.5 and doc["n"] == 7 and doc["scene"] == {"model": {"n": 7}}
    assert doc["n_steps"] == 1 and doc["wall_time_s"] >= 0 and doc["model"] == "shell"


def test_classify_undecided_exits_1(capsys, monkeypatch):
    monkeypatch.setattr(cli, "load_model", lambda name: _classifying_model(
        lambda scene, progress: Classification(None, failure="the path stopped early")))
    code, stdout, stderr = run_cli(capsys, "classify", "-q")
    assert code == 1 and "undecided" in stdout and "the path stopped early" in stdout and stderr == ""
    code, stdout, _ = run_cli(capsys, "classify", "-q", "--json")
    doc = json.loads(stdout)
    assert code == 1 and doc["classification"] is None and doc["success"] is False


def test_classify_engine_failure_exits_1_without_traceback(capsys, monkeypatch):
    def classify(scene, progress):
        raise contin.CorrectorFailure("Newton diverged")

    monkeypatch.setattr(cli, "load_model", lambda name: _classifying_model(classify))
    code, stdout, stderr = run_cli(capsys, "classify", "-q")
    assert code == 1 and "Newton diverged" in stdout and "Traceback" not in stderr


def test_classify_scene_error_inside_the_classifier_is_bad_input(capsys, monkeypatch):
    def classify(scene, progress):
        raise SceneError("scene field model.n = 3 cannot be classified; allowed: n > 3")

    monkeypatch.setattr(cli, "load_model", lambda name: _classifying_model(classify))
    code, stdout, stderr = run_cli(capsys, "classify", "-q")
    _assert_input_error(code, stdout, stderr, Path("/nonexistent/contin-test"), "model.n", "allowed")


def test_model_without_classifier_cannot_classify(capsys, monkeypatch):
    monkeypatch.setattr(cli, "load_model", lambda name: _fake_model(lambda scene, progress: None))
    code, stdout, stderr = run_cli(capsys, "classify", "--model", "fake")
    assert code == 2 and "'fake' cannot classify" in stderr and stdout == ""
    assert not can_classify(_fake_model(lambda scene, progress: None))
    assert can_classify(_classifying_model(lambda scene, progress: None))


def test_internal_error_is_one_paragraph_without_traceback(tmp_path, capsys, monkeypatch):
    def run(scene, progress):
        raise RuntimeError("a bug\nover two lines")

    monkeypatch.setattr(cli, "load_model", lambda name: _fake_model(run))
    monkeypatch.delenv("CONTIN_TRACEBACK", raising=False)
    code, _, stderr = run_cli(capsys, "trace", "-q", "--out", str(tmp_path / "o"))
    assert code == 1 and stderr.startswith("contin: internal error: RuntimeError: a bug over two lines")
    assert stderr.count("\n") == 1 and "Traceback" not in stderr


def test_tables_print_no_negative_zero():
    """A coordinate that is exactly zero but negative (a jump's unchanged travel, say) prints as 0."""
    table = cli.format_table([{"kind": "jump", "w": -0.0, "F": np.float64(-0.0), "residual": 0.0}])
    assert "-0" not in table and table.splitlines()[1].split()[1:3] == ["0", "0"]


# ---- contin plot: saved runs drawn again ------------------------------------------------------------------
def test_plot_redraws_and_overlays_saved_runs(tmp_path, capsys):
    """Two saved runs of the bratu model: one re-drawn (PNG, and PDF by the suffix), both overlaid; the branches
    read back are those of branch.csv, with the special points of summary.json."""
    from contin.app.saved import load_run

    runs = []
    for n in (20, 40):
        out = tmp_path / f"run{n}"
        code, _, err = run_cli(capsys, "trace", "-m", "bratu", "-q", "-o", str(out), "--set", f"model.n={n}",
                               "--set", "continuation.stability=true")
        assert code == 0, err
        runs.append(out)
    saved = load_run(runs[0])
    rows = read_csv(runs[0])
    assert [float(r["p"]) for r in rows] == list(saved.branches[0].p)
    assert len(saved.branches[0].special_points) == len(read_summary(runs[0])["special_points"])
    assert list(saved.branches[0].stable) == [r["stable"] == "1" for r in rows] and saved.x == "p"
    (runs[0] / "diagram.png").unlink()
    code, out, err = run_cli(capsys, "plot", str(runs[0]))
    assert code == 0, err
    assert (runs[0] / "diagram.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, _, err = run_cli(capsys, "plot", str(runs[0]), str(runs[1]), "-o", str(tmp_path / "both.pdf"))
    assert code == 0, err
    assert (tmp_path / "both.pdf").read_bytes()[:5] == b"%PDF-"


@pytest.mark.parametrize("case, needles", [
    ("missing", ["summary.json", "not found", "is not an output directory"]),
    ("axis", ["has no quantity 'nosuch'", "'max_u'"]),
    ("suffix", ["must end in .png or .pdf"]),
])
def test_plot_refuses_what_it_cannot_draw(tmp_path, capsys, case, needles):
    out = tmp_path / "run"
    if case != "missing":
        assert run_cli(capsys, "trace", "-m", "bratu", "-q", "-o", str(out), "--set", "model.n=20")[0] == 0
    args = {"missing": ["plot", str(tmp_path / "none")], "axis": ["plot", str(out), "-x", "nosuch"],
            "suffix": ["plot", str(out), "-o", str(tmp_path / "a.svg")]}[case]
    code, _, err = run_cli(capsys, *args)
    assert code == 2 and all(n in err for n in needles), err


def test_an_overlay_names_its_runs_by_the_scene_keys_that_differ(tmp_path):
    from contin.app.saved import SavedRun, overlay_labels

    def run(name, model, phi, N=200, figure=True):
        scene = {"shell": {"phi_hat": phi, "N": N}, "output": {"figure": figure}}
        return SavedRun(path=tmp_path / name, summary={"model": model, "scene": scene}, branches=[])

    title, labels = overlay_labels([run("a", "shell", 0.8), run("b", "shell", 1.2, figure=False)])
    assert title == "shell: runs that differ in shell.phi_hat"  # the output section changes no result
    assert labels == ["shell.phi_hat = 0.8", "shell.phi_hat = 1.2"]
    _, labels = overlay_labels([run("a", "shell", 0.8), run("b", "shell", 1.2, N=400)])
    assert labels == ["shell.N = 200, shell.phi_hat = 0.8", "shell.N = 400, shell.phi_hat = 1.2"]
    _, labels = overlay_labels([run("a", "shell", 0.8), run("b", "shell", 0.8), run("c", "shell", 1.2)])
    assert labels == ["shell.phi_hat = 0.8 (a)", "shell.phi_hat = 0.8 (b)", "shell.phi_hat = 1.2 (c)"]
    assert overlay_labels([run("a", "shell", 0.8), run("b", "shell", 0.8)]) == ("a / b", ["a", "b"])
    assert overlay_labels([run("a", "shell", 0.8), run("b", "bratu", 0.8)]) == ("a / b", ["a", "b"])
