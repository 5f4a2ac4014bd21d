"""The shell's command-line scene: outputs, special points, bad input, classification."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from contin.cli import main

FIELDS = ("kind", "parameter", "w", "F", "w_over_R", "F_norm", "residual")


def _trace(tmp_path: Path, *sets: str) -> tuple[int, dict]:
    args = ["trace", "--model", "shell", "-q", "--out", str(tmp_path)]
    for item in sets:
        args += ["--set", item]
    code = main(args)
    summary = json.loads((tmp_path / "summary.json").read_text()) if (tmp_path / "summary.json").exists() else {}
    return code, summary


def test_default_scene_writes_outputs_and_special_points(tmp_path: Path) -> None:
    code, summary = _trace(tmp_path, "shell.N=40")
    assert code == 0
    for name in ("summary.json", "branch.csv", "diagram.png"):
        assert (tmp_path / name).stat().st_size > 0
    assert summary["classification"] == "bistable"
    for key in ("F_max", "w_at_F_max", "F_min", "w_at_F_min", "F_max_norm", "w_at_F_max_over_R"):
        assert summary[key] is not None
    spts = summary["special_points"]
    params = {r["parameter"] for r in spts}
    assert params == {"w", "F"}
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
    ("shell.nu=0.7", "shell.nu"), ('load.kind="ring"', "load.kind"), ("shell.h=1.5", "shell.h"),
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
    code, summary = _trace(tmp_path, "shell.N=60", f"shell.phi_hat={phi_hat}")
    assert code == 0
    assert summary["classification"] == expected
    if expected == "monostable":
        assert 0 < summary["F_min"] < summary["F_max"]
        assert summary["w_at_F_max"] < summary["w_at_F_min"]


def test_monostable_middle_part_unstable_under_force_stable_under_displacement(tmp_path: Path) -> None:
    code, summary = _trace(tmp_path, "shell.N=40", "shell.phi_hat=1.2")
    assert code == 0
    with open(tmp_path / "branch.csv") as fh:
        rows = list(csv.DictReader(fh))
    lo, hi = summary["w_at_F_max"], summary["w_at_F_min"]
    inside = [r for r in rows if lo < float(r["w"]) < hi]
    assert inside
    assert all(r["stable_force"] == "0" and r["stable_displacement"] == "1" for r in inside)
    assert all(r["stable_displacement"] == "1" for r in rows)  # single-valued in w: no snap-back


def test_force_control_snaps_to_the_everted_state(tmp_path: Path) -> None:
    code, summary = _trace(tmp_path, "shell.N=40", "load.control=force")
    assert code == 0
    assert len(summary["jumps"]) == 1 and summary["jumps"][0]["success"]
    first = summary["special_points"][0]
    assert first["parameter"] == "F" and first["stable_before"]
    landing = [r for r in summary["special_points"] if r.get("label") == "jump_to"][0]
    assert landing["w"] > summary["eversion_w"] * 0.9
