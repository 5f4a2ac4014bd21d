"""With ``stability.harmonics = true`` the terminal and the diagram name the modes and the first instability.

Before: every bifurcation row of the table was labelled literally ``bifurcation(n)``, the long label pushed
the force column out of the 100-column table, and neither the status line nor the diagram's title said
that the path first loses stability to a bifurcation into ``n`` waves (the default cap: ``n = 1`` at
w/R = 0.32, before its first fold in w at 0.40; the clamped cap under pressure: ``n = 5`` before its
pressure maximum).  Now each row names its mode (``n = 3``), the load columns stay, and wherever the
snap is named the first instability is named beside it.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from contin.app import cli

HARMONICS = ["--set", "stability.harmonics=true", "--set", "shell.N=60"]


def trace(capsys: pytest.CaptureFixture, out: Path, *argv: str) -> tuple[int, str]:
    code = cli.main(["trace", "-q", "--out", str(out), *argv])
    return code, capsys.readouterr().out


def table_rows(out: str) -> list[list[str]]:
    lines = out.split("special points (shell):\n")[1].split("\n(not shown")[0].split("\nstatus:")[0].splitlines()
    return [line.split() for line in lines]


@pytest.mark.slow
def test_bifurcation_rows_name_their_mode_and_keep_the_force(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    code, out = trace(capsys, tmp_path / "point", *HARMONICS)
    assert code == 0
    rows = table_rows(out)
    header = rows[0]
    assert header[:4] == ["#", "kind", "label", "folds_in"] and "w" in header and "F" in header
    doc = json.loads((tmp_path / "point" / "summary.json").read_text())
    bifurcations = [r for r in doc["special_points"] if r["kind"] == "bifurcation"]
    assert bifurcations and all(r["label"] == f"n = {r['n']}" for r in bifurcations)
    printed = [row for row in rows[1:] if row[1] == "bifurcation"]
    assert len(printed) == len(bifurcations)
    for row, rec in zip(printed, bifurcations):
        assert row[2:5] == ["n", "=", str(rec["n"])]
        assert float(row[header.index("F") + 2]) == pytest.approx(rec["F"], rel=1e-7)  # "n = 3" is three words


@pytest.mark.slow
def test_status_line_and_title_name_the_first_instability(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    code, out = trace(capsys, tmp_path / "point", *HARMONICS)
    doc = json.loads((tmp_path / "point" / "summary.json").read_text())
    first = doc["first_instability"]
    assert first["kind"] == "bifurcation" and first["n"] == 1 and 0.3 < first["w_over_R"] < 0.35
    status = " ".join(out.split("status:")[1].split())
    assert "classification: bistable (F_max =" in status
    assert (f"first instability: a bifurcation into 1 circumferential wave (n = 1) at w/R = {first['w_over_R']:.4g}"
            in status)
    assert f"first instability: $n = 1$ at $w/R = {first['w_over_R']:.4g}$" in doc["diagram"]["note"]


@pytest.mark.slow
def test_pressure_status_names_the_first_instability_in_p_over_p_c(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture) -> None:
    code, out = trace(capsys, tmp_path / "pressure", *HARMONICS, "--set", "load.kind=pressure",
                      "--set", "shell.boundary=clamped", "--set", "load.control=force")
    doc = json.loads((tmp_path / "pressure" / "summary.json").read_text())
    first = doc["first_instability"]
    assert first["kind"] == "bifurcation" and first["n"] >= 4 and first["p_over_p_c"] < doc["p_snap_over_p_c"]
    status = " ".join(out.split("status:")[1].split())
    assert "first fold (snap under pressure) at p/p_c =" in status
    assert f"(n = {first['n']}) at p/p_c = {first['p_over_p_c']:.4g}" in status


def test_without_harmonics_nothing_is_added(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    code, out = trace(capsys, tmp_path / "plain", "--set", "shell.N=60")
    assert code == 0 and "first instability" not in out
