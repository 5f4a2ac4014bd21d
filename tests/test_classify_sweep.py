"""``contin classify --sweep``: axis parsing, the combinations, the CSV written row by row, resume, workers.

The shell runs use N = 30 and phi_hat >= 1 (about 0.1 s each); the classes they expect were checked
against single ``classify`` calls of the same scenes, which every such test also repeats.
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path

import pytest

import contin
from contin.app import cli
from contin.app.scene import Classification, Field, SceneError, SceneModel, Schema, TraceResult, load_scene
from contin.app.sweep import WORKER_DIED, SweepError, parse_sweep, read_sweep_csv, run_sweep, sweep_scenes

SHELL_BASE = ["shell.N=30"]
PHIS = [1.0, 1.2, 1.3]


# ---- a stand-in model (module level, with module-level functions only: worker processes unpickle it) -----
def _a_ok(a):
    return 0 < a <= 10


def _n_ok(n):
    return n >= 1


def _kind_ok(kind):
    return kind in ("x", "y")


TOY_SCHEMA = Schema({"toy": {"a": Field(float, 1.0, _a_ok, "a float in (0, 10]"),
                             "n": Field(int, 3, _n_ok, "an integer >= 1"),
                             "kind": Field(str, "x", _kind_ok, 'one of "x", "y"'), "flag": Field(bool, False)}})


def _toy_run(scene, progress):
    return TraceResult(branches=[])


def _toy_classify(scene, progress):
    a, n = scene["toy"]["a"], scene["toy"]["n"]
    if n == 13:
        os._exit(3)  # the worker dies, as in a crash in compiled code
    if n == 7:
        raise contin.CorrectorFailure("Newton diverged")
    values = {"product": a * n, "twice": 2 * n, "note": "text", "absent": None, "even": n % 2 == 0}
    return Classification("big" if a * n > 5 else "small", values=values)


TOY = SceneModel("toy", "a stand-in", TOY_SCHEMA, _toy_run, classifier=_toy_classify)


class Counting:
    """A runner that counts its classify calls and records how many data rows the CSV had at each call."""

    def __init__(self, runner, csv_path: Path | None = None):
        self.runner, self.csv_path = runner, csv_path
        self.name, self.description, self.schema = runner.name, runner.description, runner.schema
        self.calls: list[dict] = []
        self.rows_at_call: list[int] = []

    def run(self, scene, progress):
        return self.runner.run(scene, progress)

    def classify(self, scene, progress):
        self.calls.append(scene)
        if self.csv_path is not None:
            self.rows_at_call.append(len(data_rows(self.csv_path)))
        return self.runner.classify(scene, progress)


def data_rows(path: Path) -> list[dict[str, str]]:
    if not path.exists() or not path.read_text():
        return []
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def run_cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture(scope="module")
def shell():
    return cli.load_model("shell")


@pytest.fixture(scope="module")
def reference(shell):
    """Independent reference: the shell's classify on each scene, resolved as a single --set run would be."""
    out = {}
    for phi in PHIS:
        scene = load_scene(shell.schema, None, [*SHELL_BASE, f"shell.phi_hat={phi}"])
        out[phi] = shell.classify(scene, False)
    assert [out[phi].label for phi in PHIS] == ["bistable", "monostable", "monotonous"]  # checked at N = 30
    return out


def shell_combos(shell):
    return sweep_scenes(shell.schema, [parse_sweep("shell.phi_hat=1.0,1.2,1.3", shell.schema)], None, SHELL_BASE)


def same_results(rows_a, rows_b):
    strip = [{k: v for k, v in r.items() if k != "wall_time_s"} for r in rows_a]
    return strip == [{k: v for k, v in r.items() if k != "wall_time_s"} for r in rows_b]


# ---- axes ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("spec, name, values", [
    ("shell.phi_hat=0.6,0.8,1.0", "shell.phi_hat", [0.6, 0.8, 1.0]),
    ("shell.N=60,100", "shell.N", [60, 100]),
    ("shell.phi_hat=0.6:1.0:5", "shell.phi_hat", [0.6, 0.7, 0.8, 0.9, 1.0]),  # exactly, not 0.7000000000000001
    ("shell.h = log:0.001:0.1:3", "shell.h", [0.001, 0.01, 0.1]),
    ("shell.N=40:100:4", "shell.N", [40, 60, 80, 100]),
    ("shell.N=log:10:1000:3", "shell.N", [10, 100, 1000]),
    ("shell.phi_hat=1.2:0.8:3", "shell.phi_hat", [1.2, 1.0, 0.8]),  # descending
    ("load.kind=point,sphere", "load.kind", ["point", "sphere"]),
    ("shell.phi_hat=0.8", "shell.phi_hat", [0.8]),
])
def test_parse_sweep(spec, name, values):
    got_name, got = parse_sweep(spec)
    assert got_name == name and got == values
    assert [type(v) for v in got] == [type(v) for v in values]  # integers stay integers


def test_parse_sweep_with_the_schema_types_the_values(shell):
    assert parse_sweep("shell.R=1:3:3") == ("shell.R", [1, 2, 3])
    name, values = parse_sweep("shell.R=1:3:3", shell.schema)  # a float key: floats
    assert values == [1.0, 2.0, 3.0] and all(type(v) is float for v in values)
    assert parse_sweep("shell.N=40:100:4", shell.schema)[1] == [40, 60, 80, 100]


@pytest.mark.parametrize("spec, needles", [
    ("shell.phi_hat", ["'shell.phi_hat'", "section.key=SPEC", "start:stop:count"]),
    ("phi_hat=0.8", ["section.key=SPEC"]),
    ("shell.phi_hat=", ["section.key=SPEC"]),
    ("shell.phi_hat=0.6,,0.8", ["shell.phi_hat", "empty value", "start:stop:count"]),
    ("shell.phi_hat=0.6:1.0", ["shell.phi_hat", "three parts", "log:start:stop:count"]),
    ("shell.phi_hat=0.6:1.0:1", ["shell.phi_hat", "count", ">= 2"]),
    ("shell.phi_hat=0.6:1.0:x", ["shell.phi_hat", "count 'x'"]),
    ("shell.phi_hat=0.6:1.0:2.5", ["shell.phi_hat", "count '2.5'"]),
    ("shell.phi_hat=a:1:3", ["shell.phi_hat", "'a' is not a number"]),
    ("shell.h=log:0:0.1:3", ["shell.h", "start > 0 and stop > 0"]),
    ("shell.phi_hat=0.8,0.8", ["shell.phi_hat", "0.8 is given twice"]),
    ("shell.phi_hat=0.8:0.8:3", ["shell.phi_hat", "repeat"]),
])
def test_bad_specs_name_the_key_and_the_syntax(spec, needles):
    with pytest.raises(SceneError) as info:  # SweepError is the scene's bad-input error
        parse_sweep(spec)
    assert isinstance(info.value, SweepError)
    for needle in needles:
        assert needle in str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("spec, needles", [
    ("shell.N=40:101:3", ["shell.N", "integers", "70.5", "40:100:4"]),
    ("load.kind=1:2:3", ["load.kind", "only a numeric key takes a range"]),
    ("shell.nope=1,2", ["shell.nope", "allows", "phi_hat"]),
    ("nope.x=1,2", ["[nope]", "[shell]"]),
])
def test_bad_specs_against_the_schema(shell, spec, needles):
    with pytest.raises(SweepError) as info:
        parse_sweep(spec, shell.schema)
    for needle in needles:
        assert needle in str(info.value)


# ---- combinations ----------------------------------------------------------------------------------------
def test_sweep_scenes_are_the_product_resolved_like_set():
    axes = [parse_sweep("toy.n=1,2", TOY_SCHEMA), parse_sweep("toy.a=2:4:3", TOY_SCHEMA)]
    combos = sweep_scenes(TOY_SCHEMA, axes, None, ["toy.kind=y"])
    assert [tuple(v.values()) for v, _ in combos] == [(1, 2.0), (1, 3.0), (1, 4.0), (2, 2.0), (2, 3.0), (2, 4.0)]
    for values, scene in combos:  # exactly the scene of a single --set run
        assert scene == load_scene(TOY_SCHEMA, None, ["toy.kind=y", f"toy.n={values['toy.n']}",
                                                      f"toy.a={values['toy.a']}"])
        assert type(values["toy.a"]) is float and type(values["toy.n"]) is int


@pytest.mark.parametrize("axes, overrides, needles", [
    (["toy.a=5:20:4"], [], ["toy.a = 15.0", "--sweep toy.a", "out of range", "a float in (0, 10]",
                            "combination toy.a=15.0"]),
    (["toy.n=1,2.5"], [], ["toy.n = 2.5", "expected an integer"]),
    (["toy.a=1,2", "toy.a=3"], [], ["toy.a is swept twice"]),
    (["toy.a=1,2"], ["toy.a=3"], ["toy.a", "both by --set and by --sweep"]),
    (["toy.n=1,2"], ["toy.a=11"], ["toy.a = 11", "(from --set toy.a=11)"]),  # the fixed part: a plain error
])
def test_bad_combinations_are_reported_before_any_work(axes, overrides, needles):
    with pytest.raises(SceneError) as info:
        sweep_scenes(TOY_SCHEMA, [parse_sweep(a, TOY_SCHEMA) for a in axes], None, overrides)
    for needle in needles:
        assert needle in str(info.value)


# ---- classes, workers -------------------------------------------------------------------------------------
def test_sweep_classes_equal_single_classify_serial_and_parallel(shell, reference, tmp_path):
    combos = shell_combos(shell)
    serial = run_sweep("shell", combos, tmp_path / "serial.csv", workers=1, progress=False)
    parallel = run_sweep("shell", combos, tmp_path / "parallel.csv", workers=2, progress=False)
    assert [r["label"] for r in serial] == ["bistable", "monostable", "monotonous"]
    for row, phi in zip(serial, PHIS):
        ref = reference[phi]
        assert row["shell.phi_hat"] == phi and row["label"] == ref.label and row["failure"] == ""
        for key in ("F_max_norm", "F_min_norm", "w_at_F_max_over_R", "lambda", "n_folds_in_w"):
            assert row[key] == ref.values[key]
        assert row["scene"] == load_scene(shell.schema, None, [*SHELL_BASE, f"shell.phi_hat={phi}"])
    assert same_results(serial, parallel)
    assert "control_traced" not in serial[0]  # strings are not CSV values
    # the CSV holds the same rows, in combination order
    columns, from_csv = read_sweep_csv(tmp_path / "parallel.csv")
    assert columns[:2] == ["shell.phi_hat", "label"] and columns[-3:] == ["wall_time_s", "failure", "scene"]
    assert from_csv == parallel


def test_csv_is_written_row_by_row_and_resume_computes_only_the_missing_row(shell, reference, tmp_path, capsys):
    path = tmp_path / "sweep.csv"
    combos = shell_combos(shell)
    counting = Counting(shell, path)
    first = run_sweep(counting, combos, path, workers=1)
    assert len(counting.calls) == 3 and counting.rows_at_call == [0, 1, 2]  # each row flushed before the next
    err = capsys.readouterr().err
    assert "[1/3] shell.phi_hat=1.0 -> bistable" in err and "[3/3] shell.phi_hat=1.3 -> monotonous" in err
    assert "ETA" in err

    lines = path.read_text().splitlines(keepends=True)
    assert len(lines) == 4
    path.write_text("".join(lines[:-1]))  # an interrupted sweep: the last row is missing
    again = Counting(shell, path)
    second = run_sweep(again, combos, path, workers=1)
    assert [s["shell"]["phi_hat"] for s in again.calls] == [1.3]  # only the missing combination
    err = capsys.readouterr().err
    assert "resumed 2 of 3 combinations" in err and "classifying 1 of 3" in err and "[3/3] shell.phi_hat=1.3" in err
    assert same_results(first, second)
    assert [r["label"] for r in data_rows(path)] == [reference[phi].label for phi in PHIS]

    # complete: nothing is computed; --no-resume computes everything again
    third = Counting(shell, path)
    assert same_results(run_sweep(third, combos, path, workers=1, progress=False), first) and not third.calls
    fourth = Counting(shell, path)
    run_sweep(fourth, combos, path, workers=1, progress=False, resume=False)
    assert len(fourth.calls) == 3 and len(data_rows(path)) == 3


def test_a_row_cut_short_is_recomputed_and_other_values_are_kept(tmp_path):
    path = tmp_path / "toy.csv"
    combos = sweep_scenes(TOY_SCHEMA, [parse_sweep("toy.n=1,2,3", TOY_SCHEMA)])
    run_sweep(TOY, combos, path, workers=1, progress=False)
    text = path.read_text()
    path.write_text(text[:-25])  # killed in the middle of writing the last row
    counting = Counting(TOY, path)
    rows = run_sweep(counting, combos, path, workers=1, progress=False)
    assert [s["toy"]["n"] for s in counting.calls] == [3]
    assert [r["toy.n"] for r in data_rows(path)] == ["1", "2", "3"] and [r["label"] for r in rows] == ["small"] * 3
    # a sweep over other values of the same key reuses what fits and keeps the rest in the file
    wider = sweep_scenes(TOY_SCHEMA, [parse_sweep("toy.n=3,4", TOY_SCHEMA)])
    counting = Counting(TOY, path)
    rows = run_sweep(counting, wider, path, workers=1, progress=False)
    assert [s["toy"]["n"] for s in counting.calls] == [4] and [r["toy.n"] for r in rows] == [3, 4]
    assert [r["toy.n"] for r in data_rows(path)] == ["3", "4", "1", "2"]
    assert rows[1]["product"] == 4.0 and rows[1]["even"] is True and rows[1]["absent"] is None


def test_failures_are_rows_and_a_dead_worker_costs_only_its_combination(tmp_path):
    path = tmp_path / "toy.csv"
    combos = sweep_scenes(TOY_SCHEMA, [parse_sweep("toy.n=1,13,7,2,3", TOY_SCHEMA)])
    rows = run_sweep(TOY, combos, path, workers=2, progress=False)
    assert [r["toy.n"] for r in rows] == [1, 13, 7, 2, 3]
    assert [r["label"] for r in rows] == ["small", None, None, "small", "small"]
    assert rows[1]["failure"].startswith(WORKER_DIED)
    assert rows[2]["failure"] == "run failed: CorrectorFailure: Newton diverged"
    assert [r["failure"] for r in rows[::3]] == ["", ""]
    assert rows[4]["product"] == 3.0 and rows[1]["product"] is None  # the union of the values, None where absent
    assert [r["label"] for r in data_rows(path)] == ["small", "", "", "small", "small"]
    # on resume the engine failure is kept, the dead worker's combination is computed again (here by a
    # stand-in that does not crash, in this process)
    def classify(scene, progress):
        return Classification("fixed") if scene["toy"]["n"] == 13 else _toy_classify(scene, progress)

    counting = Counting(SceneModel("toy", "a stand-in", TOY_SCHEMA, _toy_run, classifier=classify), path)
    rows = run_sweep(counting, combos, path, workers=1, progress=False)
    assert [s["toy"]["n"] for s in counting.calls] == [13]
    assert [r["label"] for r in rows] == ["small", "fixed", None, "small", "small"]
    assert [r["label"] for r in data_rows(path)] == ["small", "fixed", "", "small", "small"]


# ---- the CSV of another sweep -----------------------------------------------------------------------------
def test_a_csv_of_another_sweep_is_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cli, "load_model", lambda name: TOY)
    path = tmp_path / "toy.csv"
    code, _, _ = run_cli(capsys, "classify", "-q", "--workers", "1", "--sweep", "toy.n=1,2", "--csv", str(path))
    assert code == 0
    before = path.read_text()

    code, out, err = run_cli(capsys, "classify", "-q", "-j", "1", "--sweep", "toy.a=1,2", "--csv", str(path))
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert str(path) in err and "sweep over toy.n" in err and "toy.a" in err and "--no-resume" in err
    code, out, err = run_cli(capsys, "classify", "-q", "-j", "1", "--sweep", "toy.n=1,2", "--set", "toy.kind=y",
                             "--csv", str(path))
    assert code == 2 and "another scene" in err and 'toy.kind = "x" there, "y" in this sweep' in err
    assert path.read_text() == before  # never overwritten

    (tmp_path / "other.csv").write_text("w,F\n0.1,2.0\n")
    code, out, err = run_cli(capsys, "classify", "-q", "-j", "1", "--sweep", "toy.n=1,2", "--csv",
                             str(tmp_path / "other.csv"))
    assert code == 2 and "not a sweep CSV" in err and "other.csv" in err
    assert (tmp_path / "other.csv").read_text() == "w,F\n0.1,2.0\n"

    code, _, _ = run_cli(capsys, "classify", "-q", "-j", "1", "--sweep", "toy.a=1,2", "--csv", str(path),
                         "--no-resume")
    assert code == 0 and read_sweep_csv(path)[0][0] == "toy.a"


# ---- the command line ---------------------------------------------------------------------------------------
def test_cli_sweep_of_the_shell(tmp_path, capsys, reference, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the default CSV goes into the current directory
    code, out, err = run_cli(capsys, "classify", "--set", "shell.N=30", "--sweep", "shell.phi_hat=1.0,1.2,1.3",
                             "--workers", "1")
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].startswith("classification sweep (shell): 3 combinations")
    assert lines[1].split() == ["shell.phi_hat", "class", "F_max_norm", "F_min_norm", "time_s"]
    assert lines[2].split()[:3] == ["1.0", "bistable", f"{reference[1.0].values['F_max_norm']:.8g}"]
    assert lines[3].split()[:2] == ["1.2", "monostable"] and lines[4].split()[:2] == ["1.3", "monotonous"]
    assert "classes: bistable 1, monostable 1, monotonous 1" in out and "status: ok" in out
    assert "[2/3] shell.phi_hat=1.2 -> monostable" in err and "Traceback" not in err
    assert [r["label"] for r in data_rows(tmp_path / cli.DEFAULT_SWEEP_CSV)] == ["bistable", "monostable",
                                                                                 "monotonous"]
    # --json: a list of rows; everything is resumed from the CSV
    code, out, err = run_cli(capsys, "classify", "--json", "--set", "shell.N=30", "--sweep",
                             "shell.phi_hat=1.0,1.2,1.3")
    assert code == 0 and "resumed 3 of 3" in err
    rows = json.loads(out)
    assert [r["label"] for r in rows] == ["bistable", "monostable", "monotonous"]
    assert rows[0]["F_max_norm"] == reference[1.0].values["F_max_norm"] and rows[2]["F_max_norm"] is None
    assert rows[1]["scene"]["shell"]["N"] == 30 and rows[1]["shell.phi_hat"] == 1.2


@pytest.mark.parametrize("args, needles", [
    (["--sweep", "shell.phi_hat=0.6:1.0"], ["shell.phi_hat", "three parts"]),
    (["--sweep", "shell.phi_hat=1.2,1.6"], ["shell.phi_hat = 1.6", "a float in (0, 1.5708)", "--sweep"]),
    (["--sweep", "shell.N=5,30"], ["shell.N = 5", "an integer >= 10"]),
    (["--sweep", "model.n=1,2"], ["[model]", "default model 'shell'"]),
    (["--csv", "x.csv"], ["--csv applies only to a sweep", "--sweep"]),
    (["--workers", "2", "--no-resume"], ["--workers, --no-resume apply only to a sweep"]),
    (["--sweep", "shell.phi_hat=1.2", "--workers", "0"], ["--workers 0"]),
    (["--sweep", "shell.phi_hat=1.2", "--workers", "two"], ["--workers", "two"]),
    (["--sweep", "shell.phi_hat=1.2", "--set", "shell.phi_hat=1.3"], ["both by --set and by --sweep"]),
])
def test_cli_bad_sweep_input_exits_2(tmp_path, capsys, monkeypatch, args, needles):
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, "classify", *args)
    assert code == 2 and out == "" and err.startswith("contin: error:") and err.count("\n") == 1
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err
    assert list(tmp_path.iterdir()) == []  # nothing ran, nothing written


def test_cli_failed_combination_exits_1(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cli, "load_model", lambda name: TOY)
    path = tmp_path / "toy.csv"
    code, out, err = run_cli(capsys, "classify", "-q", "-j", "1", "--sweep", "toy.n=2,7", "--csv", str(path))
    assert code == 1 and err == ""
    assert "failed" in out and "Newton diverged" in out and "status: failed - 1 of 2" in out
    code, out, _ = run_cli(capsys, "classify", "-q", "-j", "1", "--json", "--sweep", "toy.n=2,7", "--csv", str(path))
    failures = [r["failure"] for r in json.loads(out)]
    assert code == 1 and failures == ["", "run failed: CorrectorFailure: Newton diverged"]


def test_cli_interrupt_keeps_the_rows_and_exits_130(tmp_path, capsys, monkeypatch):
    def classify(scene, progress):
        if scene["toy"]["n"] == 3:
            raise KeyboardInterrupt
        return _toy_classify(scene, progress)

    model = SceneModel("toy", "a stand-in", TOY_SCHEMA, _toy_run, classifier=classify)
    monkeypatch.setattr(cli, "load_model", lambda name: model)
    path = tmp_path / "toy.csv"
    code, out, err = run_cli(capsys, "classify", "-j", "1", "--sweep", "toy.n=1,2,3,4", "--csv", str(path))
    assert code == 130 and "interrupted" in err and "run the same command again to resume" in err
    assert "Traceback" not in err
    assert [r["toy.n"] for r in data_rows(path)] == ["1", "2"]
    monkeypatch.setattr(cli, "load_model", lambda name: TOY)
    code, out, err = run_cli(capsys, "classify", "-j", "1", "--sweep", "toy.n=1,2,3,4", "--csv", str(path))
    assert code == 0 and "resumed 2 of 4" in err and [r["toy.n"] for r in data_rows(path)] == ["1", "2", "3", "4"]


def _interrupted_classify(scene, progress):
    raise KeyboardInterrupt


def test_cli_interrupt_before_any_row_leaves_no_csv(tmp_path, capsys, monkeypatch):
    model = SceneModel("toy", "a stand-in", TOY_SCHEMA, _toy_run, classifier=_interrupted_classify)
    monkeypatch.setattr(cli, "load_model", lambda name: model)
    path = tmp_path / "sub" / "toy.csv"
    code, out, err = run_cli(capsys, "classify", "-j", "1", "--sweep", "toy.n=1,2", "--csv", str(path))
    assert code == 130 and "Traceback" not in err
    assert not path.exists()  # no empty file in the way of the next run
    assert "no combination finished" in " ".join(err.split())
    # an earlier sweep's file is left as it was, even by --no-resume, until a row replaces it
    monkeypatch.setattr(cli, "load_model", lambda name: TOY)
    assert run_cli(capsys, "classify", "-q", "-j", "1", "--sweep", "toy.n=1,2", "--csv", str(path))[0] == 0
    before = path.read_bytes()
    monkeypatch.setattr(cli, "load_model", lambda name: model)
    code, _, err = run_cli(capsys, "classify", "-j", "1", "--no-resume", "--sweep", "toy.n=1,2", "--csv", str(path))
    assert code == 130 and path.read_bytes() == before
    assert "the finished combinations are in" in " ".join(err.split())


def test_an_unwritable_csv_is_refused_before_any_work(tmp_path, monkeypatch):
    access = os.access
    # as a read-only directory (chmod would not stop root)
    monkeypatch.setattr(os, "access", lambda path, mode: not str(path).startswith(str(tmp_path)) and access(path, mode))
    counting = Counting(TOY)
    with pytest.raises(SweepError, match="cannot write the sweep CSV"):
        run_sweep(counting, sweep_scenes(TOY_SCHEMA, [("toy.n", [1, 2])]), tmp_path / "toy.csv", workers=1,
                  progress=False)
    assert counting.calls == [] and list(tmp_path.iterdir()) == []


def test_classify_help_shows_the_sweep(capsys):
    assert cli.main(["classify", "--help"]) == 0
    text = capsys.readouterr().out
    assert "--sweep" in text and "log:start:stop:count" in text and "--no-resume" in text
    assert "contin classify --sweep shell.phi_hat=" in text
