"""Key numbers of ``studies.phase_diagram_3d``: the paper's classes on the paths the caps take."""

from __future__ import annotations

import json

import pytest

from studies import phase_diagram_3d as pd3


def test_depth_parameter_and_its_inverse() -> None:
    """``lambda`` of the paper's cap (phi_hat = 1.2, h/R = 0.02, nu = 0.5) by hand: 12 (1 - 1/4) = 9, 9^(1/4) =
    sqrt(3), (pi/2 - 1.2) / sqrt(0.02) = 2.62191..., lambda = 4.54131..."""
    assert pd3.lambda_of(1.2, 0.02) == pytest.approx(3 ** 0.5 * (3.141592653589793 / 2 - 1.2) / 0.02 ** 0.5, rel=1e-14)
    assert pd3.lambda_of(1.2, 0.02) == pytest.approx(4.54131, abs=1e-5)
    assert pd3.h_of_lambda(0.8, pd3.lambda_of(0.8, 0.0123)) == pytest.approx(0.0123, rel=1e-13)


def test_the_class_read_from_the_axisymmetric_extrema_is_contin_classify_s() -> None:
    """The study reads the axisymmetric class from the force extrema a followed run reports; on three caps, one of each
    class (N = 40), it must be the class ``contin classify`` gives without the followed path."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCHEMA
    from contin_models.shell_scene.scene import classify_scene

    for phi_hat, h, expected in ((1.3, 0.03, "monotonous"), (1.0, 0.06, "monostable"), (1.0, 0.02, "bistable")):
        scene = load_scene(SHELL_SCHEMA, None, [f"shell.phi_hat={phi_hat}", f"shell.h={h}", "shell.N=40",
                                                f"shell.nu={pd3.NU}", "output.figure=false"])
        c = classify_scene(scene)
        assert c.label == expected
        assert pd3.axisymmetric_class(c.values) == expected


@pytest.mark.slow
def test_the_followed_bistable_boundary_is_the_traced_axisymmetric_one(tmp_path) -> None:
    """The study's default run (N = 60, K = 2): every cell classified both ways, the located followed bistable
    boundary at phi_hat = 1 brackets the axisymmetric boundary traced by fold continuation (an independent route:
    the fold of the unloaded cap continued in phi_hat), and the followed force minimum of a cap deeper than
    lambda = 8 is less deep than the axisymmetric one, while near the boundary it is the same (the one-wave piece
    lands back on the axisymmetric path before its minimum)."""
    assert pd3.main(["--out", str(tmp_path), "--quiet", "--workers", "1"]) == 0
    S = json.loads((tmp_path / "summary.json").read_text())
    assert S["classified_both_ways"] == S["cells"] == 9
    b = next(b for b in S["boundaries"] if b["kind"] == "bistable")
    assert b["lambda_lo"] <= b["traced_axi_lambda"] <= b["lambda_hi"]
    data = json.loads((tmp_path / "plot_data.json").read_text())
    for cell in data["grid"]:
        if cell["axi_class"] == "bistable" and cell["lambda"] > 8.0:
            assert cell["axi_F_min"] < cell["followed_F_min"] < 0.0
        if cell["axi_class"] == "bistable" and cell["lambda"] < 6.2:
            assert cell["followed_F_min"] == pytest.approx(cell["axi_F_min"], rel=1e-6)
