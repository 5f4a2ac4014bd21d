"""The random-scene study (studies/fuzz.py): reproducible draws, causes, the verdict, and a small run."""

from __future__ import annotations

import json

import pytest

from studies import fuzz


def test_draws_are_reproducible_and_inside_the_stated_ranges() -> None:
    a, b = fuzz.draw_scenes(30, seed=7), fuzz.draw_scenes(30, seed=7)
    assert a == b and a != fuzz.draw_scenes(30, seed=8)
    for s in a:
        assert 40 <= s["shell.N"] <= 200 and 0.3 <= s["shell.phi_hat"] <= 1.5 and -0.5 <= s["shell.nu"] <= 0.5
        assert 1e-3 <= s["shell.h"] / s["shell.R"] <= 0.12 + 1e-12
        assert s["load.kind"] in ("point", "ring", "sphere", "plate", "pressure")
        assert ("load.radius" in s) == (s["load.kind"] == "sphere")
        assert ("load.ring_radius" in s) == (s["load.kind"] == "ring")
    assert {s["load.kind"] for s in fuzz.draw_scenes(60, seed=7)} == set(fuzz.LOAD_KINDS)
    assert min(s["shell.nu"] for s in fuzz.draw_scenes(60, seed=7)) < 0


def test_a_failure_without_an_actionable_cause_misses_the_target() -> None:
    assert fuzz.cause_of("...; advice: the mesh has 3.1 nodes ...; try a finer mesh, shell.N = 94") == "refine the mesh"
    assert fuzz.cause_of("corrector diverging") == "unexplained"
    row = {"shell.N": 60, "outcome": "complete", "cause": ""}
    ok = fuzz.summarize([row] * 99 + [{**row, "outcome": "failed", "cause": "refine the mesh"}])
    assert ok["complete_rate_judged"] == 0.99 and ok["target_met"]
    assert not fuzz.summarize([row] * 98 + [{**row, "outcome": "failed", "cause": "refine the mesh"}] * 2)["target_met"]
    unexplained = fuzz.summarize([row] * 99 + [{**row, "outcome": "failed", "cause": "unexplained"}])
    assert not unexplained["target_met"]
    # refused scenes and coarse meshes are reported, not judged
    judged = fuzz.summarize([row, {**row, "outcome": "refused"}, {**row, "shell.N": 30, "outcome": "failed"}])
    assert judged["n_judged"] == 1 and judged["complete_rate_judged"] == 1.0


@pytest.mark.slow
def test_a_small_seeded_run_writes_its_outputs(tmp_path) -> None:
    status = fuzz.main(["--count", "8", "--seed", "3", "--workers", "1", "--out", str(tmp_path), "-q"])
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["n_scenes"] == 8 and status in (0, 1)
    assert (tmp_path / "fuzz.csv").exists() and (tmp_path / "fuzz.png").exists()
    assert summary["failures_by_cause"].get("unexplained", 0) == 0, summary["failures"]


#: Three random scenes of ``python -m studies.fuzz --count 80 --seed 1`` (indices 56, 44 and 38) that
#: failed before issue 14's B8 contact change: a plate under displacement control whose corrector
#: failed on the dimple branch, a sphere and a plate under force control stopped by the ripple of the
#: contact ring.  In units of R (the scenes are scale-free).
FORMER_FAILURES = {
    "plate, displacement": ["shell.h=0.00982023", "shell.phi_hat=0.600264", "shell.nu=0.0502361", "shell.N=43",
                            "load.kind=plate", "load.control=displacement"],
    "sphere, force": ["shell.h=0.00376889", "shell.phi_hat=0.898784", "shell.nu=0.212232", "shell.N=53",
                      "load.kind=sphere", "load.control=force", "load.radius=2.741"],
    "plate, force": ["shell.h=0.00918671", "shell.phi_hat=0.325757", "shell.nu=0.413112", "shell.N=73",
                     "load.kind=plate", "load.control=force"],
}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(FORMER_FAILURES))
def test_former_failures_run_to_the_end(tmp_path, name) -> None:
    from contin.app.cli import main

    argv = ["trace", "-q", "--set", "output.figure=false", "--out", str(tmp_path / "run")]
    for item in FORMER_FAILURES[name]:
        argv += ["--set", item]
    code = main(argv)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert code == 0 and summary["status"] == "ok", summary["message"]


def test_two_runs_are_compared_scene_by_scene(tmp_path) -> None:
    def run(name: str, outcomes: dict[str, str], points: dict[str, list]) -> None:
        folder = tmp_path / name
        folder.mkdir()
        rows = "\n".join(f"{k},{v}" for k, v in outcomes.items())
        (folder / "fuzz.csv").write_text("index,outcome\n" + rows + "\n")
        (folder / "points.json").write_text(json.dumps(points))

    fold = {"kind": "fold", "label": "max(F)", "p": 0.3, "w_over_R": 0.3, "F_norm": 8.9}
    run("a", {"0": "complete", "1": "complete", "2": "failed", "3": "complete"},
        {"0": [fold], "1": [fold], "2": [], "3": [fold]})
    run("b", {"0": "complete", "1": "failed", "2": "complete", "3": "complete"},
        {"0": [{**fold, "F_norm": 8.9 + 3e-9}], "1": [], "2": [fold], "3": [fold, fold]})
    diff = fuzz.compare_runs(tmp_path / "a", tmp_path / "b")
    assert diff["lost"] == ["1"] and diff["gained"] == ["2"] and diff["mismatched"] == ["3"]
    assert diff["n_complete_in_both"] == 2
    assert diff["max_move"] == pytest.approx(3e-9, rel=1e-3) and diff["max_move_field"] == "F_norm"
