"""Issue 18: ``contin trace --from OUT --label K`` restarts from a saved point (``states.npz``, :mod:`contin.app.restart`).

A path cut short by its step limit and resumed from its end, and a path restarted from a special point, find
the same special points as the uncut run (to 1e-8 relative, module notes below); the point load's state
saved under displacement control is loaded on by a dead load (another continuation parameter); the engine's
resume follows the other branch at a branch point; bad input is one line and exit status 2.

Precision: folds in the continuation parameter, crossings and the values at every special point agree to
1e-8.  The *location* of an extremum of an observable (the point load's ``max(F)`` / ``min(F)``, folds in F
along the displacement path) is found as a root of a derivative along the curve whose noise floor is the
corrector tolerance (contin.watch.testfunctions, EventTest.locate): it moves by up to ~1e-6 relative with the
steps that bracket it, in an uncut run too (another first step moves it by 7e-7 at N = 60), so it is compared
to 2e-6 - the engine's own repeatability, not the restart's.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from contin.app import cli
from contin.app.restart import RestartError, find_point, read_start, restart_states, resume

RTOL = 1e-8
#: Relative agreement of an extremum's location (module docstring).
EXTREMUM_LOCATION_RTOL = 2e-6


def trace(capsys: pytest.CaptureFixture, out: Path, *argv: str) -> tuple[int, str, str]:
    code = cli.main(["trace", "-q", "--out", str(out), *argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def points(out: Path, branch: int = 0) -> list[dict]:
    doc = json.loads((out / "summary.json").read_text())
    return [r for r in doc["special_points"] if r.get("branch") == branch]


def close(a: float, b: float, rtol: float, scale: float = 0.0) -> bool:
    return abs(a - b) <= rtol * max(abs(a), abs(b)) + RTOL * scale


def assert_same_points(reference: list[dict], restarted: list[dict], observables: tuple[str, ...] = ()) -> None:
    """Same kinds and labels in order; locations and values to 1e-8 (an extremum's location to its own accuracy)."""
    assert [(r["kind"], r["label"], r["parameter"]) for r in reference] == \
           [(r["kind"], r["label"], r["parameter"]) for r in restarted]
    scales = {name: max(abs(r["observables"][name]) for r in reference) for name in observables}
    for a, b in zip(reference, restarted):
        extremum = a["label"] in ("max(F)", "min(F)")
        assert close(a["p"], b["p"], EXTREMUM_LOCATION_RTOL if extremum else RTOL), (a, b)
        for name in observables:
            # a crossing of F = 0 has F ~ 1e-11: its value is compared on the scale of F along the path
            located_by = a["parameter"] if extremum else None
            rtol = EXTREMUM_LOCATION_RTOL if extremum and name != located_by else RTOL
            assert close(a["observables"][name], b["observables"][name], rtol, scales[name]), (name, a, b)


# ---- the 1-D Bratu benchmark: fast, one fold -----------------------------------------------------------------
@pytest.fixture(scope="module")
def bratu_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("bratu")
    runs = {name: root / name for name in ("full", "cut", "resumed", "from_fold")}
    for name, argv in (("full", ["--model", "bratu", "--set", "model.n=50"]),
                       ("cut", ["--model", "bratu", "--set", "model.n=50", "--set", "continuation.max_steps=10"])):
        cli.main(["trace", "-q", "--out", str(runs[name]), *argv])
    cli.main(["trace", "-q", "--out", str(runs["resumed"]), "--from", str(runs["cut"]), "--label", "end",
              "--set", "continuation.max_steps=1000"])
    cli.main(["trace", "-q", "--out", str(runs["from_fold"]), "--from", str(runs["full"]), "--label", "1"])
    return runs


def test_a_cut_bratu_path_resumed_from_its_end_finds_the_fold_of_the_uncut_run(bratu_runs: dict[str, Path]) -> None:
    full, cut, resumed = (json.loads((bratu_runs[n] / "summary.json").read_text()) for n in ("full", "cut", "resumed"))
    assert cut["status"] == "incomplete" and not cut["special_points"]
    assert resumed["status"] == "ok" and resumed["complete"]
    assert resumed["restart"]["label"] == "end" and resumed["restart"]["kind"] == "end"
    assert_same_points(full["special_points"], resumed["special_points"], ("max_u", "u_mid"))
    assert full["fold_lam"] == pytest.approx(resumed["fold_lam"], rel=RTOL)


def test_a_bratu_restart_from_the_fold_is_joined_to_the_path_before_it(bratu_runs: dict[str, Path]) -> None:
    full = np.genfromtxt(bratu_runs["full"] / "branch.csv", delimiter=",", names=True)
    after = np.genfromtxt(bratu_runs["from_fold"] / "branch.csv", delimiter=",", names=True)
    doc = json.loads((bratu_runs["from_fold"] / "summary.json").read_text())
    full_doc = json.loads((bratu_runs["full"] / "summary.json").read_text())
    # the same path as the uncut run: its fold once (not found again at the start), and on to the same bound
    assert doc["status"] == "ok" and doc["restart"]["joined"]
    assert_same_points(full_doc["special_points"], doc["special_points"], ("max_u", "u_mid"))
    assert doc["fold_lam"] == full_doc["fold_lam"]
    assert after["p"][0] == 0.0 and after["p"][-1] == pytest.approx(full["p"][-1], rel=RTOL)
    assert after["max_u"][-1] == pytest.approx(full["max_u"][-1], rel=RTOL)
    assert np.all(np.diff(after["max_u"]) > 0)  # on along the upper branch, not back down the lower one


def test_states_file_holds_every_special_point_and_the_end(bratu_runs: dict[str, Path]) -> None:
    data = np.load(bratu_runs["full"] / "states.npz")
    index = json.loads(str(data["index"][()]))
    assert [(p["key"], p["kind"]) for p in index["points"]] == [("1", "fold"), ("end0", "end")]
    assert data["u_1"].shape == (50,) and data["pd_1"].shape == (3,)
    _, start = read_start(bratu_runs["full"], "1")
    assert start.kind == "fold" and start.number == 1 and start.record["kind"] == "fold"
    summary = json.loads((bratu_runs["full"] / "summary.json").read_text())
    assert summary["special_points"][0]["number"] == 1


# ---- bad input: one line, exit status 2 ------------------------------------------------------------------------
@pytest.mark.parametrize("argv, needle", [
    (["--from", "{missing}", "--label", "1"], "no such directory"),
    (["--from", "{nostates}", "--label", "1"], "no states.npz there"),
    (["--from", "{full}", "--label", "7"], "--label '7': no such saved point; saved: special points 1; branch ends end"),
    (["--from", "{full}", "--label", "end:2"], "no such saved point"),
    (["--from", "{full}", "--label", "1", "--set", "model.n=60"], "--set model.n=60: model.n fixes the structure"),
    (["--from", "{full}"], "--from OUT and --label K go together"),
    (["--label", "1"], "--from OUT and --label K go together"),
    (["--from", "{full}", "--label", "1", "--model", "truss"], "was traced with the model 'bratu'"),
    (["--from", "{full}", "--label", "end"], "lies at the end of this scene's path or beyond it"),
    (["--from", "{full}", "--label", "end", "--set", "continuation.max_steps=3000"], "there is nothing to trace"),
])
def test_bad_restarts_are_one_line_and_exit_2(bratu_runs: dict[str, Path], tmp_path: Path,
                                              capsys: pytest.CaptureFixture, argv: list[str], needle: str) -> None:
    nostates = tmp_path / "nostates"
    nostates.mkdir()
    (nostates / "summary.json").write_text((bratu_runs["full"] / "summary.json").read_text())
    paths = {"missing": str(tmp_path / "missing"), "nostates": str(nostates), "full": str(bratu_runs["full"])}
    argv = [a.format(**paths) for a in argv]
    code, out, err = trace(capsys, tmp_path / "out", *argv)
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith("contin: error: ") and needle in err, err
    assert not (tmp_path / "out").exists()


def test_labels_name_numbers_ends_and_unique_labels() -> None:
    pts = [{"key": "1", "kind": "fold", "label": "max(F)", "branch": 0, "number": 1},
           {"key": "2", "kind": "fold", "label": "max(F)", "branch": 0, "number": 2},
           {"key": "3", "kind": "event", "label": "F = 0", "branch": 0, "number": 3},
           {"key": "end0", "kind": "end", "label": "end", "branch": 0, "number": None},
           {"key": "end1", "kind": "end", "label": "end", "branch": 1, "number": None}]
    assert find_point(pts, "2")["key"] == "2"
    assert find_point(pts, "F = 0")["key"] == "3"
    assert find_point(pts, "end")["key"] == "end0" and find_point(pts, "end:1")["key"] == "end1"
    with pytest.raises(RestartError, match="names 2 special points"):
        find_point(pts, "max(F)")


# ---- the engine's resume at a branch point: the other branch ---------------------------------------------------
def test_resume_follows_the_other_branch_at_a_branch_point(tmp_path: Path) -> None:
    from contin import continuation
    from contin.app.scene import TraceResult
    from contin_models.benchmarks.pitchfork import Pitchfork

    pf = Pitchfork()
    trivial = continuation(pf, [0.0, 0.0], -1.0, ds=0.1, p_max=1.0, stability=True)
    result = TraceResult.from_branches([trivial], problem=pf)
    states = restart_states(result)
    np.savez(tmp_path / "states.npz", **states)
    (tmp_path / "summary.json").write_text(json.dumps({"model": "none", "scene": {},
                                                       "special_points": result.special_points}))
    number = next(k + 1 for k, r in enumerate(result.special_points) if r["kind"] == "branch_point")
    _, start = read_start(tmp_path, str(number))
    assert start.kind == "branch_point" and "bifurcation_direction" in start.extra
    same = resume(pf, start, ds=0.1, p_max=1.0, stability=True)  # on along the trivial branch
    assert same.status == "bound" and np.all(np.abs(same.u[:, 0]) < 1e-12) and not same.branch_points()
    other = resume(pf, start, switch=True, ds=0.1, p_max=1.0, stability=True)
    assert other.status == "bound" and other.p[-1] == pytest.approx(1.0)
    np.testing.assert_allclose(other.u[:, 0] ** 2, other.p, atol=1e-9)  # u1 = +-sqrt(p)
    assert other.special_points[0].kind == "branch_point"
    _, end = read_start(tmp_path, "end")
    with pytest.raises(RestartError, match="no other branch to follow"):
        resume(pf, end, switch=True)


# ---- the point-loaded cap (N = 60): the whole winding path -----------------------------------------------------
SHELL = ["--set", "shell.N=60", "--set", "output.figure=false"]  # (no test here looks at the figures)
_OBS = ("w", "F")


@pytest.fixture(scope="module")
def shell_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("shell")
    runs = {name: root / name for name in ("full", "cut", "resumed")}
    cli.main(["trace", "-q", "--out", str(runs["full"]), *SHELL])
    cli.main(["trace", "-q", "--out", str(runs["cut"]), *SHELL, "--set", "continuation.max_steps=40"])
    cli.main(["trace", "-q", "--out", str(runs["resumed"]), "--from", str(runs["cut"]), "--label", "end",
              "--set", "continuation.max_steps=3000"])
    return runs


def test_a_cut_shell_path_resumed_from_its_end_reproduces_the_uncut_run(shell_runs: dict) -> None:
    full, resumed = points(shell_runs["full"]), points(shell_runs["resumed"])
    cut = json.loads((shell_runs["cut"] / "summary.json").read_text())
    assert cut["status"] == "incomplete"
    assert len(full) > len(points(shell_runs["cut"])) + 10
    # joined to the saved path: every special point of the uncut run, numbered as it numbers them
    assert_same_points(full, resumed, _OBS)
    assert [r["number"] for r in resumed] == [r["number"] for r in full]
    doc = json.loads((shell_runs["resumed"] / "summary.json").read_text())
    reference = json.loads((shell_runs["full"] / "summary.json").read_text())
    assert doc["status"] == "ok" and doc["complete"] and doc["restart"]["kind"] == "end" and doc["restart"]["joined"]
    assert doc["classification"] == reference["classification"] == "bistable"
    for key in ("F_max", "F_min"):  # the snap loads of the whole path, not of the part traced after the cut
        assert doc[key] == pytest.approx(reference[key], rel=EXTREMUM_LOCATION_RTOL)
    assert doc["classification_note"] == reference["classification_note"]
    rows = np.genfromtxt(shell_runs["resumed"] / "branch.csv", delimiter=",", names=True)
    assert rows["w"][0] == 0.0 and rows["w"][-1] == pytest.approx(reference["w_end"], rel=1e-9)


def test_a_shell_restart_from_its_first_fold_describes_the_whole_path(shell_runs: dict, tmp_path: Path) -> None:
    full = points(shell_runs["full"])
    k = next(r["number"] for r in full if r["kind"] == "fold" and r["parameter"] == "w")  # the first fold in w
    cli.main(["trace", "-q", "--out", str(tmp_path / "after"), "--from", str(shell_runs["full"]), "--label", str(k)])
    assert_same_points(full, points(tmp_path / "after"), _OBS)  # the points before it kept, it once, those after found


def test_a_shell_restart_refuses_another_mesh(shell_runs: dict, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    code, out, err = trace(capsys, tmp_path / "out", "--from", str(shell_runs["full"]), "--label", "1",
                           "--set", "shell.N=80")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "--set shell.N=80: shell.N fixes the structure of the problem" in err and "shell.N = 60" in err


def test_a_displacement_state_loaded_on_under_force_control(tmp_path: Path) -> None:
    """Another continuation parameter: a state of the displacement path, continued in the force (a dead load)."""
    force, cut, switched = tmp_path / "force", tmp_path / "cut", tmp_path / "switched"
    cli.main(["trace", "-q", "--out", str(force), *SHELL, "--set", "load.control=force"])
    cli.main(["trace", "-q", "--out", str(cut), *SHELL, "--set", "continuation.max_steps=6"])
    code = cli.main(["trace", "-q", "--out", str(switched), "--from", str(cut), "--label", "end",
                     "--set", "load.control=force", "--set", "continuation.max_steps=3000"])
    assert code == 0
    a, b = (json.loads((d / "summary.json").read_text())["special_points"] for d in (force, switched))
    assert [(r["kind"], r["label"]) for r in a] == [(r["kind"], r["label"]) for r in b]
    limit_a, limit_b = a[0], b[0]
    assert limit_a["kind"] == "fold" and limit_a["parameter"] == "F"
    assert close(limit_a["p"], limit_b["p"], RTOL)  # the limit load: a fold in the continuation parameter F
    assert close(limit_a["observables"]["w"], limit_b["observables"]["w"], RTOL)
