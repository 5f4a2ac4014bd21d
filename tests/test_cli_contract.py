"""Issue 14 on the command line: indenters refused by ``classify`` (B1), incomplete paths reported as such
(B2), interrupts and ``output.figure`` (B4), the tolerance floor of the schemas (B5), and a command
line that names no model (A5)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import contin
from contin.app import cli, registry
from contin.app.scene import SceneModel, Schema, TraceResult, integer, load_scene

ROOT = Path(__file__).resolve().parents[1]


def run_cli(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


# ---- B1: classify refuses an indenter, single and in a sweep, before anything runs -------------------------
@pytest.mark.parametrize("kind", ["sphere", "plate"])
def test_classify_refuses_an_indenter_and_says_what_to_run(capsys: pytest.CaptureFixture, kind: str) -> None:
    code, out, err = run_cli(capsys, "classify", "-q", "--set", f"load.kind={kind}", "--set", "shell.N=40")
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f'contin: error: scene field load.kind = "{kind}" cannot be classified')
    for needle in ('allowed: load.kind = "point"', "docs/model.md#classes", "--set load.kind=point", "contin trace"):
        assert needle in err


def test_classify_sweep_with_an_indenter_is_refused_before_any_work(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture) -> None:
    csv_path = tmp_path / "rows.csv"
    code, out, err = run_cli(capsys, "classify", "-q", "-j", "1", "--set", "shell.N=40", "--sweep",
                             "load.kind=point,sphere", "--csv", str(csv_path))
    assert code == 2 and out == "" and "Traceback" not in err
    assert 'load.kind = "sphere" cannot be classified' in err and "(in the sweep combination load.kind=sphere)" in err
    assert not csv_path.exists()  # refused before the CSV or any combination


def test_run_sweep_refuses_an_indenter(tmp_path: Path) -> None:
    from contin.app.sweep import SweepError, run_sweep, sweep_scenes

    model = registry.load_model("shell")
    combos = sweep_scenes(model.schema, [("load.kind", ["plate"])], None, ["shell.N=40"])
    with pytest.raises(SweepError, match="cannot be classified"):
        run_sweep(model, combos, tmp_path / "rows.csv", workers=1, progress=False)
    assert not (tmp_path / "rows.csv").exists()


def test_the_shell_runner_refuses_an_indenter_to_any_caller() -> None:
    model = registry.load_model("shell")
    scene = load_scene(model.schema, None, ["load.kind=sphere", "shell.N=40"])
    with pytest.raises(contin.app.scene.SceneError, match="cannot be classified"):
        model.classify(scene, False)
    from contin_models.shell_scene import classify_scene

    with pytest.raises(contin.app.scene.SceneError, match="cannot be classified"):
        classify_scene(scene)


# ---- B2: a path cut short by max_steps is incomplete ------------------------------------------------------
def test_a_trace_cut_short_is_incomplete(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "out"
    code, stdout, _ = run_cli(capsys, "trace", "-q", "--set", "continuation.max_steps=5", "--set", "shell.phi_hat=1.2",
                              "--set", "shell.N=40", "--out", str(out))
    assert code == 1
    status = " ".join(stdout[stdout.index("\nstatus: ") + 1:].split())  # the status line, wrapped at 100 columns
    assert status.startswith("status: incomplete - ") and "raise continuation.max_steps (now 5)" in status
    doc = _summary(out)
    assert doc["status"] == "incomplete" and doc["success"] is False and doc["complete"] is False
    assert "before the end of the path" in doc["message"]


@pytest.mark.parametrize("model, sets", [
    ("shell", ["load.control=force", "shell.N=40"]),
    ("shell", ["load.kind=sphere", "shell.N=40"]),
    ("bratu", ["model.n=20"]),
])
def test_every_scene_cut_short_is_incomplete(tmp_path: Path, capsys: pytest.CaptureFixture, model: str,
                                             sets: list[str]) -> None:
    args = ["trace", "-q", "--model", model, "--out", str(tmp_path)]
    for item in [*sets, "continuation.max_steps=3"]:
        args += ["--set", item]
    code, stdout, _ = run_cli(capsys, *args)
    doc = _summary(tmp_path)
    assert code == 1 and doc["status"] == "incomplete" and doc["complete"] is False, stdout


@pytest.mark.parametrize("model, sets", [("bratu", ["model.n=20"]), ("truss", []), ("truss", ["load.cycle=true"])])
def test_a_benchmark_that_reaches_its_end_is_complete(tmp_path: Path, capsys: pytest.CaptureFixture, model: str,
                                                      sets: list[str]) -> None:
    args = ["trace", "-q", "--model", model, "--out", str(tmp_path)]
    for item in sets:
        args += ["--set", item]
    code, _, _ = run_cli(capsys, *args)
    doc = _summary(tmp_path)
    assert code == 0 and doc["status"] == "ok" and doc["complete"] is True


def _branch(status: str) -> contin.Branch:
    return contin.Branch(p=np.array([0.0, 1.0]), u=np.zeros((2, 1)), s=np.array([0.0, 1.0]), tangent_p=np.ones(2),
                         residual=np.zeros(2), newton_iterations=np.zeros(2, dtype=int), status=status, message="m")


@pytest.mark.parametrize("status, complete", [("bound", True), ("event", True), ("closed_loop", True),
                                              ("completed", False), ("max_steps", False)])
def test_a_spent_step_budget_is_the_only_incomplete_planned_end(status: str, complete: bool) -> None:
    result = TraceResult.from_branches([_branch("bound"), _branch(status)], labels=["a", "b"])
    assert result.complete is complete and result.success is complete
    assert result.status == ("ok" if complete else "incomplete")
    assert ("incomplete: b stopped" in result.message) is not complete


# ---- B4: interrupts and output.figure ----------------------------------------------------------------------
def test_figure_false_writes_no_png_and_removes_a_stale_one(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    (tmp_path / "diagram.png").write_bytes(b"an earlier run")
    code, _, _ = run_cli(capsys, "trace", "-q", "--set", "output.figure=false", "--set", "shell.N=40",
                         "--set", "continuation.ds_max=0.05", "--set", "shell.phi_hat=1.3", "--out", str(tmp_path))
    assert code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["branch.csv", "states.npz", "summary.json"]


def test_an_interrupted_trace_leaves_no_directory(tmp_path: Path, capsys: pytest.CaptureFixture,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    def run(scene: dict, progress: bool) -> TraceResult:
        raise KeyboardInterrupt

    fake = SceneModel("fake", "a stand-in", Schema({"model": {"n": integer(3, low=1)}}), run)
    monkeypatch.setattr(cli, "load_model", lambda name: fake)
    code, _, err = run_cli(capsys, "trace", "--model", "fake", "--out", str(tmp_path / "new" / "out"))
    assert code == 130 and err.endswith("contin: interrupted\n") and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_an_output_directory_that_cannot_be_made_exits_2(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    (tmp_path / "file").write_text("")
    code, out, err = run_cli(capsys, "trace", "-q", "--model", "bratu", "--out", str(tmp_path / "file" / "out"))
    assert code == 2 and out == "" and err.startswith("contin: error: --out: cannot create the output directory")


# ---- B5: a tolerance below round-off is refused by every schema ---------------------------------------------
@pytest.mark.parametrize("model", ["shell", "bratu", "truss"])
def test_a_tolerance_below_roundoff_is_refused(capsys: pytest.CaptureFixture, tmp_path: Path, model: str) -> None:
    code, out, err = run_cli(capsys, "trace", "-q", "--model", model, "--set", "continuation.tol=1e-15",
                             "--out", str(tmp_path / "out"))
    field = registry.load_model(model).schema.field("continuation", "tol")
    assert code == 2 and out == "" and "continuation.tol = 1e-15" in err and f"allowed: {field.allowed}" in err
    assert not field.valid(1e-15) and field.valid(field.default)
    assert not (tmp_path / "out").exists()


# ---- A5: the command line names no model ------------------------------------------------------------------
def _model_names() -> list[str]:
    return list(registry.registered_models())


def test_the_command_line_names_no_model() -> None:
    # the engine, the command line and the machinery behind it (scenes, sweeps, executors, files,
    # registry): no model's name anywhere in their source, docstrings and comments included
    names = _model_names()
    assert names
    for path in sorted((ROOT / "contin").glob("*.py")):
        found = sorted({n for n in names if re.search(rf"\b{re.escape(n)}\b", path.read_text(), re.IGNORECASE)})
        assert not found, f"{path.relative_to(ROOT)} names the model(s) {found}"


def test_help_names_the_default_model_from_the_registry(capsys: pytest.CaptureFixture,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    default = registry.default_model()
    assert default is not None
    code, out, _ = run_cli(capsys, "--help")
    assert code == 0 and f"the default model '{default}'" in out
    code, out, _ = run_cli(capsys, "trace", "--help")
    assert code == 0 and f"(default: {default};" in " ".join(out.split())
    # every model's own examples are listed, with --model for all but the default
    for name in _model_names():
        for args, _comment in registry.model_examples(registry.load_model(name), "trace"):
            shown = args if name == default else f"--model {name} {args}"
            assert f"contin trace {shown}" in out
    # without a default, a command asks for --model instead of guessing
    monkeypatch.setattr(registry, "default_model", lambda: None)
    code, out, err = run_cli(capsys, "trace", "-q")
    assert code == 2 and "no default model is registered; choose one with --model NAME" in err


def test_studies_use_the_public_json_conversion() -> None:
    from contin.results.io import json_ready
    from studies import _common

    assert _common.json_ready is json_ready
    assert json_ready({"a": np.float64("nan"), 1: np.arange(2)}) == {"a": None, "1": [0, 1]}


def test_no_private_name_is_imported_from_another_package() -> None:
    # the command line, the engine's scene machinery and the studies' shared helpers use public ways in
    import ast

    paths = [*sorted((ROOT / "contin").glob("*.py")), ROOT / "studies" / "_common.py"]
    offenders = []
    for path in paths:
        package = path.relative_to(ROOT).parts[0]
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                top = node.module.split(".")[0]
                private = [a.name for a in node.names if a.name.startswith("_")]
                if top != package and top in ("contin", "models", "studies") and private:
                    offenders.append(f"{path.relative_to(ROOT)}: from {node.module} import {', '.join(private)}")
    assert not offenders
