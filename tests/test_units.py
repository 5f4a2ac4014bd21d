"""A scene gives the same dimensionless answer in any units (metres or millimetres, any E)."""

import json

import pytest

from contin.app.cli import main


def _special_points(tmp_path, R: float) -> list[tuple[float, float]]:
    out = tmp_path / f"R{R}"
    status = main(["trace", "-q", "--set", "load.kind=sphere", "--set", f"load.radius={0.5 * R}",
                   "--set", "load.control=force", "--set", "shell.N=80", "--set", f"shell.R={R}",
                   "--set", f"shell.h={0.01 * R}", "--set", "output.figure=false", "--out", str(out)])
    assert status == 0
    summary = json.loads((out / "summary.json").read_text())
    return [(p["F_norm"], p["w_over_R"]) for p in summary["special_points"]]


@pytest.mark.slow
def test_force_controlled_sphere_snaps_alike_in_any_units(tmp_path):
    """The snap's kick and its landing test are lengths of the shell (units of R), not of the state
    vector's numbers: at R = 1 m and R = 1 cm the same snap is found (issue 14, B8)."""
    metres, centimetres = _special_points(tmp_path, 1.0), _special_points(tmp_path, 0.01)
    assert len(metres) == len(centimetres) == 4  # fold, landing, and the jump's two ends
    for (F_a, w_a), (F_b, w_b) in zip(metres, centimetres):
        assert F_a == pytest.approx(F_b, rel=1e-5)
        assert w_a == pytest.approx(w_b, abs=1e-5)
