"""Stability against every mode on the command line (issue 17, item 3): ``[stability] harmonics``.

The mechanism's numbers are checked in ``tests/test_harmonic.py`` and ``tests/test_modes.py``; here the
contract: the keys, ``first_instability``, the bifurcation records with ``n``, the CSV columns and the
note of ``contin classify``.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from contin.app import cli


def run_cli(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


PRESSURE = ["load.kind=pressure", "load.control=force", "shell.boundary=clamped", "shell.N=60", "shell.nu=0.3",
            "load.p_end_over_p_c=0.95", "stability.harmonics=true", "stability.n_max=10"]


def test_pressure_scene_reports_its_first_instability(capsys: pytest.CaptureFixture, tmp_path: Path) -> None:
    """The default cap clamped (lambda = 9.2) bifurcates into a few waves before its pressure maximum."""
    args = ["trace", "-q", "--out", str(tmp_path), "--set", "output.figure=false"]
    for s in PRESSURE:
        args += ["--set", s]
    code, _, err = run_cli(capsys, *args)
    assert code == 0, err
    summary = json.loads((tmp_path / "summary.json").read_text())
    first = summary["first_instability"]
    assert first["kind"] == "bifurcation" and isinstance(first["n"], int) and 2 <= first["n"] <= 8
    assert first["p_over_p_c"] < summary["p_snap_over_p_c"]
    assert {"p", "p_over_p_c", "w", "w_over_h"} <= set(first)
    bif = [r for r in summary["special_points"] if r["kind"] == "bifurcation"]
    assert bif and all("n" in r for r in bif)
    with open(tmp_path / "branch.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert {"n_negative_n", "critical_n", "lowest_n"} <= set(rows[0])
    assert float(rows[0]["n_negative_n"]) == 0.0
    assert any(float(r["n_negative_n"]) > 0 for r in rows)
    # the points name their critical n and that block's eigenvalue nearest zero, which
    # changes sign where the path bifurcates
    later = [r for r in rows[1:] if r["critical_n"] not in ("", "nan")]
    assert len(later) >= len(rows) - 3  # all but the start and the end points placed on a bound
    signs = [float(r["lowest_n"]) > 0 for r in later]
    assert signs[0] and not all(signs)
    # shapes.npz: every special point's deformed meridian, and each located mode, which the block of its
    # n, rebuilt from the saved shape and pressure, maps to (nearly) zero
    import numpy as np

    from contin_models.shell.harmonic import HarmonicShell, harmonic_dofs
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.build import pressure_problem
    from contin.app.scene import load_scene

    shapes = np.load(tmp_path / "shapes.npz")
    assert [str(k) for k in shapes["special_kind"]] == [r["kind"] for r in summary["special_points"]][:len(shapes["special_kind"])]
    problem = pressure_problem(load_scene(SHELL_SCHEMA, None, PRESSURE))
    hs = HarmonicShell(problem.structure)
    for k, n, a, b, c in zip(shapes["mode_record"], shapes["mode_n"], shapes["mode_a"], shapes["mode_b"], shapes["mode_c"]):
        x = np.column_stack([shapes["special_r"][k], shapes["special_z"][k]]).ravel()
        K = hs.full_block(x, int(n), pressure=float(shapes["special_p"][k]))
        v = np.column_stack([a, b, c]).ravel()
        T = harmonic_dofs(problem.structure, int(n)).T  # the admissible fields; the rest are the supports' reactions
        assert np.linalg.norm(T.T @ (K @ v)) < 1e-9 * abs(K).max() * np.linalg.norm(v)


def test_without_harmonics_the_first_instability_is_a_fold(capsys: pytest.CaptureFixture, tmp_path: Path) -> None:
    args = ["trace", "-q", "--out", str(tmp_path), "--set", "output.figure=false"]
    for s in PRESSURE[:-2]:
        args += ["--set", s]
    code, _, err = run_cli(capsys, *args)
    assert code == 0, err
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["first_instability"]["kind"] == "fold" and summary["first_instability"]["n"] is None
    assert summary["first_instability"]["p_over_p_c"] == pytest.approx(summary["p_snap_over_p_c"])


@pytest.mark.slow
def test_classify_says_when_an_asymmetric_bifurcation_comes_first(capsys: pytest.CaptureFixture) -> None:
    code, out, err = run_cli(capsys, "classify", "--set", "stability.harmonics=true", "--set", "shell.N=60",
                             "--set", "stability.n_max=6")
    assert code == 0, err
    assert "asymmetric: before its first fold in w the path bifurcates into the mode of" in out


def test_n_max_range_is_checked(capsys: pytest.CaptureFixture) -> None:
    code, _, err = run_cli(capsys, "trace", "-q", "--set", "stability.n_max=-1")
    assert code == 2 and "stability.n_max" in err


@pytest.mark.parametrize("control", ["displacement", "force"])
def test_an_indented_cap_is_watched_under_both_controls(capsys: pytest.CaptureFixture, tmp_path: Path,
                                                        control: str) -> None:
    """A rigid sphere (r/R = 0.5) on the default cap, every mode watched: under its travel the frictionless
    contact lets the cap slide sideways (n = 1) before the snap; under a dead load it snaps at the limit
    load first (the n = 1 crossing lies beyond it)."""
    args = ["trace", "-q", "--out", str(tmp_path), "--set", "output.figure=false", "--set", "load.kind=sphere",
            "--set", "load.radius=0.5", "--set", f"load.control={control}", "--set", "shell.N=60",
            "--set", "stability.harmonics=true", "--set", "stability.n_max=2"]
    code, _, err = run_cli(capsys, *args)
    assert code == 0, err
    summary = json.loads((tmp_path / "summary.json").read_text())
    with open(tmp_path / "branch.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert "n_negative_n" in rows[0] and summary["harmonics"]["n_max"] == 2
    first = summary["first_instability"]
    if control == "displacement":
        assert first["kind"] == "bifurcation" and first["n"] == 1 and first["w_over_R"] < summary["w_b_c_over_R"]
    else:
        assert first["kind"] == "fold" and first["F"] == pytest.approx(summary["F_snap"])
