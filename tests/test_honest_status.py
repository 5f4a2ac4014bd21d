"""A path cut short is reported as incomplete wherever its result is shown: terminal, JSON, sweep rows.

``contin classify -q --set continuation.max_steps=5`` used to say ``status: ok``, exit 0 and "F_max none on
the path", and ``--json`` had ``"path_complete": false`` beside ``"status": "ok"``: the class (bistable,
proved on the everted branch) was right, but the snap loads were missing because the path stopped, not
because the cap has none.  The class proved on the part traced is still given; the status is
``incomplete``, the exit status 1, and the missing loads say why they are missing.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from contin.app import cli
from contin.app.sweep import read_sweep_csv

CUT = ["--set", "shell.N=60", "--set", "continuation.max_steps=5"]


def run(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_classify_of_a_cut_path_is_incomplete_and_exits_1(capsys: pytest.CaptureFixture) -> None:
    code, out, _ = run(capsys, "classify", "-q", *CUT)
    assert code == 1
    assert out.splitlines()[0] == "classification (shell): bistable"  # proved on the everted branch
    status = " ".join(out.split("status:")[1].split())
    assert status.startswith("incomplete - ") and "raise continuation.max_steps (now 5)" in status
    assert "none on the path" not in out and "not found on the part traced: the path stopped before eversion" in out


def test_classify_json_of_a_cut_path_is_incomplete(capsys: pytest.CaptureFixture) -> None:
    code, out, _ = run(capsys, "classify", "-q", "--json", *CUT)
    doc = json.loads(out)
    assert code == 1
    assert doc["status"] == "incomplete" and doc["success"] is False and doc["complete"] is False
    assert doc["path_complete"] is False and doc["classification"] == "bistable" and doc["F_max"] is None
    assert "continuation.max_steps" in doc["message"]


def test_a_complete_path_stays_ok(capsys: pytest.CaptureFixture) -> None:
    code, out, _ = run(capsys, "classify", "-q", "--json", "--set", "shell.N=60")
    doc = json.loads(out)
    assert code == 0 and doc["status"] == "ok" and doc["success"] and doc["complete"] and doc["path_complete"]


def test_sweep_rows_of_cut_paths_say_incomplete(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "cut.csv"
    code, out, _ = run(capsys, "classify", "-q", "--workers", "1", "--sweep", "shell.phi_hat=0.8,1.2", *CUT,
                       "--csv", str(path))
    assert code == 1
    columns, rows = read_sweep_csv(path)
    assert columns[:3] == ["shell.phi_hat", "label", "status"]
    assert [(r["label"], r["status"]) for r in rows] == [("bistable", "incomplete"), (None, "incomplete")]
    assert all(r["failure"] for r in rows)
    lines = out.splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("shell.phi_hat"))  # under the wrapped title
    assert lines[head].split()[:3] == ["shell.phi_hat", "class", "status"]
    assert lines[head + 1].split()[:3] == ["0.8", "bistable", "incomplete"]
    assert lines[head + 2].split()[:3] == ["1.2", "undecided", "incomplete"]
    assert "status: incomplete - 2 of 2 combinations stopped before the end of their path" in " ".join(out.split())


def test_a_sweep_csv_without_status_is_resumed(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """Rows of a CSV written before rows had a status are read (ok unless failed) and reused, not recomputed."""
    path = tmp_path / "sweep.csv"
    args = ("classify", "-q", "--workers", "1", "--sweep", "shell.phi_hat=1.2,1.3", "--set", "shell.N=30",
            "--csv", str(path))
    assert run(capsys, *args)[0] == 0
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    header = [c for c in rows[0] if c != "status"]
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, header, extrasaction="ignore", lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    code, out, err = run(capsys, *args)
    assert code == 0, err
    assert [r["status"] for r in read_sweep_csv(path)[1]] == ["ok", "ok"]
    assert "status: ok - all 2 combinations classified" in out
