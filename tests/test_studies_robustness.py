"""The robustness study: its fast matrix completes, and its checks catch what they are meant to."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from studies import robustness


@pytest.mark.slow
def test_fast_matrix_completes(tmp_path: Path) -> None:
    code = robustness.main(["--out", str(tmp_path), "--workers", "1", "-q"])
    assert code == 0
    rows = list(csv.DictReader((tmp_path / "matrix.csv").open()))
    assert [r["scene"] for r in rows] == [c.name for c in robustness.CASES if c.fast]
    assert all(r["outcome"] == "completed" for r in rows)
    doc = json.loads((tmp_path / "summary.json").read_text())
    units = [s for s in doc["scenes"] if s["group"] == "units"]
    assert units and all(s["units_change"] <= robustness.UNITS_TOLERANCE for s in units)
    assert "| default |" in (tmp_path / "matrix.md").read_text()


def test_checks_catch_an_unconverged_point_and_a_wrong_force() -> None:
    scene, result, _ = robustness._trace(["shell.N=20", "shell.phi_hat=1.5"])
    problem = robustness._problem_of(scene)
    good = robustness.check_branches(problem, result.branches, scene)
    assert good["worst_residual"] <= 1.0 and good["energy_deviation"] <= robustness.ENERGY_TOLERANCE
    br = result.branches[0]
    br.residual[3] = 10.0 * scene["continuation"]["tol"] * problem.residual_scale
    br.observables["F"][::2] *= 1.01  # sampled points include index 0
    bad = robustness.check_branches(problem, result.branches, scene)
    assert bad["worst_residual"] > 1.0
    assert bad["energy_deviation"] > 100 * robustness.ENERGY_TOLERANCE
    br.observables["w"][5] = np.nan
    assert not robustness.check_branches(problem, result.branches, scene)["finite"]
    row = {"status": "ok", "message": "", **bad, "finite": True, "class": "monotonous"}
    outcome, why = robustness.verdict(row, robustness.CASES[0], None)
    assert outcome == "FAILED" and "not converged" in why and "dE/dw" in why
