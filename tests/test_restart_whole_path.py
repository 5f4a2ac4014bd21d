"""What a restarted run reports: the whole path when it continues the saved one, else plainly the part it traced.

``contin trace --from OUT --label K`` used to summarise only the part it traced as if it were the whole
run: from the default cap's third special point it called ``F_max`` the first maximum after that point
(58.95 instead of the cap's snap load 49.86), and a run resumed after its step limit did the same.
Now a restart that continues the saved path is joined to it (``contin.app.restart.continue_saved``): its
summary, table, classification and status line are those of the whole path.  A restart on another
path (another control, another shell) reports no class and no snap load, and says it describes only
the part it traced.  A point at or past the end of the scene's path is refused, whatever keys are set;
every numbered point of the table is restartable or refused with the reason.

The cap is the default one at N = 60 (fast; the same sequence of special points as N = 200).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from contin.app import cli

SHELL = ["--set", "shell.N=60", "--set", "output.figure=false"]
#: Relative agreement of the located extrema of F between runs stepped differently (tests/test_restart.py).
EXTREMUM_RTOL = 2e-6


def trace(capsys: pytest.CaptureFixture, out: Path, *argv: str) -> tuple[int, str, str]:
    code = cli.main(["trace", "-q", "--out", str(out), *argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("whole")
    runs = {name: root / name for name in ("full", "force")}
    cli.main(["trace", "-q", "--out", str(runs["full"]), *SHELL])
    cli.main(["trace", "-q", "--out", str(runs["force"]), *SHELL, "--set", "load.control=force"])
    return runs


def test_a_restart_from_a_later_point_reports_the_snap_load_of_the_whole_path(runs: dict[str, Path], tmp_path: Path,
                                                                               capsys: pytest.CaptureFixture) -> None:
    full = summary(runs["full"])
    later = next(r for r in full["special_points"] if r["kind"] == "fold" and r["parameter"] == "w")
    assert later["number"] > 1 and later["w"] > full["w_at_F_max"]  # past the snap load
    code, out, _ = trace(capsys, tmp_path / "after", "--from", str(runs["full"]), "--label", str(later["number"]))
    doc = summary(tmp_path / "after")
    assert code == 0 and doc["status"] == "ok" and doc["restart"]["joined"]
    assert doc["classification"] == full["classification"] == "bistable"
    assert doc["F_max"] == pytest.approx(full["F_max"], rel=EXTREMUM_RTOL)
    assert doc["w_at_F_max"] == pytest.approx(full["w_at_F_max"], rel=EXTREMUM_RTOL)
    assert doc["F_min"] == pytest.approx(full["F_min"], rel=EXTREMUM_RTOL)
    assert len(doc["special_points"]) == len(full["special_points"])
    status = " ".join(out.split("status:")[1].split())
    assert "the results describe the whole path" in status and f"F_max = {full['F_max']:.6g}" in status


def test_a_restart_on_another_path_claims_no_class_or_snap_load(runs: dict[str, Path], tmp_path: Path,
                                                               capsys: pytest.CaptureFixture) -> None:
    """Another Poisson ratio: the state is carried over, but the path traced is not the one from the unloaded cap."""
    code, out, _ = trace(capsys, tmp_path / "nu", "--from", str(runs["full"]), "--label", "3", "--set", "shell.nu=0.45")
    doc = summary(tmp_path / "nu")
    assert code == 0 and not doc["restart"]["joined"] and "shell.nu changed" in doc["restart"]["describes"]
    assert doc["classification"] is None and doc["F_max"] is None and doc["F_min"] is None
    assert doc["classification_on_traced_part"] in ("bistable", "monostable", "monotonous")
    assert "first_instability" not in doc
    status = " ".join(out.split("status:")[1].split())
    assert "the results describe only the part traced from there" in status and "F_max =" not in status
    rows = np.genfromtxt(tmp_path / "nu" / "branch.csv", delimiter=",", names=True)
    assert rows["w"][0] > 0.3  # the part traced from point 3 on, not the path from the unloaded cap


@pytest.mark.parametrize("keys", [[], ["--set", "continuation.max_steps=3000"], ["--set", "load.control=force"]])
def test_a_restart_at_the_end_of_the_path_is_refused_whatever_keys_are_set(runs: dict[str, Path], tmp_path: Path,
                                                                           capsys: pytest.CaptureFixture,
                                                                           keys: list[str]) -> None:
    # (before: under force control the dead load ran on past eversion until its step limit)
    code, out, err = trace(capsys, tmp_path / "end", "--from", str(runs["full"]), "--label", "end",
                           "--set", "continuation.max_steps=60", *keys)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "lies at" in err and "end of this scene's path or beyond it" in err and "nothing to trace" in err
    assert not (tmp_path / "end").exists()


def test_an_unloading_dead_load_stops_at_the_unloaded_pole(runs: dict[str, Path], tmp_path: Path,
                                                           capsys: pytest.CaptureFixture) -> None:
    """From the snap load, the saved path's force falls: a dead load unloads back to w = 0 and stops there
    (before: it pulled the pole on through w < 0 until its step limit)."""
    code, _, _ = trace(capsys, tmp_path / "unload", "--from", str(runs["full"]), "--label", "1",
                       "--set", "load.control=force", "--set", "continuation.max_steps=300")
    doc = summary(tmp_path / "unload")
    assert code == 0 and doc["status"] == "ok", doc["message"]
    rows = np.genfromtxt(tmp_path / "unload" / "branch.csv", delimiter=",", names=True)
    assert rows["w"][-1] == pytest.approx(0.0, abs=1e-9) and np.all(rows["w"] >= -1e-9)
    assert abs(rows["F"][-1]) < 1e-6 * abs(rows["F"][0])


def test_every_numbered_point_of_a_force_run_restarts_or_says_why(runs: dict[str, Path], tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture) -> None:
    force = summary(runs["force"])
    kinds = [(r["number"], r["kind"], r["label"]) for r in force["special_points"]]
    assert [k[1:] for k in kinds] == [("fold", ""), ("jump", "jump_from"), ("jump", "jump_to")]
    code, _, err = trace(capsys, tmp_path / "from", "--from", str(runs["force"]), "--label", "2")
    assert code == 2 and "where a jump leaves its limit point" in err and "point 1" in err and "point 3" in err
    code, _, _ = trace(capsys, tmp_path / "to", "--from", str(runs["force"]), "--label", "3")
    doc = summary(tmp_path / "to")
    assert code == 0 and doc["status"] == "ok" and doc["restart"]["joined"]
    # from the landing on, joined to the loading before the snap: the whole force path again
    assert [(r["kind"], r["label"]) for r in doc["special_points"]] == [k[1:] for k in kinds]
    for a, b in zip(force["special_points"], doc["special_points"]):
        assert b["p"] == pytest.approx(a["p"], rel=1e-8)
    assert [b["label"] for b in doc["branches"]] == [b["label"] for b in force["branches"]]


def test_every_numbered_point_of_a_pressure_run_is_saved_and_its_refusal_names_the_load(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "pressure"
    cli.main(["trace", "-q", "--out", str(out), "--set", "load.kind=pressure", "--set", "shell.boundary=clamped",
              "--set", "shell.N=60", "--set", "output.figure=false"])
    capsys.readouterr()
    numbers = [r["number"] for r in summary(out)["special_points"]]
    index = json.loads(str(np.load(out / "states.npz")["index"][()]))
    assert numbers and [p["number"] for p in index["points"] if p.get("number")] == numbers
    code, _, err = trace(capsys, tmp_path / "again", "--from", str(out), "--label", str(numbers[1]))
    assert code == 2 and "supported for the point load" in err and "load.kind = \"pressure\"" in err


@pytest.mark.slow
def test_a_joined_restart_keeps_the_per_mode_columns(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """With harmonic stability the joined branch keeps each stored point's counts per wave number n."""
    full, after = tmp_path / "full", tmp_path / "after"
    cli.main(["trace", "-q", "--out", str(full), *SHELL, "--set", "stability.harmonics=true"])
    code, _, _ = trace(capsys, after, "--from", str(full), "--label", "10")
    assert code == 0 and summary(after)["restart"]["joined"]
    a = np.genfromtxt(full / "branch.csv", delimiter=",", names=True)
    b = np.genfromtxt(after / "branch.csv", delimiter=",", names=True)
    assert np.all(np.isfinite(b["n_negative_n"]))
    head = int(summary(full)["special_points"][9]["index"]) + 1  # the saved rows before point 10
    np.testing.assert_array_equal(a["n_negative_n"][:head], b["n_negative_n"][:head])
    assert b["n_negative_n"].max() == a["n_negative_n"].max()
