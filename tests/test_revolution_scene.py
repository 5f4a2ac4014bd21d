"""Scenes of any shell of revolution on the command line (issue 16, item 5): geometry, support, ring load, imperfection.

Independent checks where a scene has one: the clamped plate's initial stiffness against the linear
plate solution ``F = 16 pi D w / a^2``; a tabulated circle against the analytic spherical cap; the
ring node on the requested circle.  The rest are the contract's keys, refusals and fields.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from contin.app import cli
from contin.app.scene import load_scene
from contin_models.shell_scene import SHELL_SCHEMA
from contin_models.shell_scene.build import scene_meridian


def run_cli(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def trace(capsys: pytest.CaptureFixture, out: Path, *sets: str) -> tuple[dict, list[dict]]:
    args = ["trace", "-q", "--out", str(out), "--set", "output.figure=false"]
    for s in sets:
        args += ["--set", s]
    code, _, err = run_cli(capsys, *args)
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "branch.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    return summary, rows


def test_clamped_plate_starts_with_the_linear_plate_stiffness(capsys: pytest.CaptureFixture, tmp_path: Path) -> None:
    """Clamped disc, central point load: ``F = 16 pi D w / a^2`` while ``w << h`` (Timoshenko's plate)."""
    a, h, E, nu = 0.8, 0.01, 1e6, 0.3
    summary, rows = trace(capsys, tmp_path, "shell.geometry=plate", "shell.boundary=clamped", f"shell.h={h}",
                          f"shell.nu={nu}", "shell.N=100", "continuation.ds=1e-4")
    D = E * h**3 / (12 * (1 - nu**2))
    w, F = float(rows[1]["w"]), float(rows[1]["F"])
    assert 0 < w < 0.05 * h
    assert F / w == pytest.approx(16 * math.pi * D / a**2, rel=5e-3)
    assert summary["geometry"] == "plate" and summary["F_max"] is None  # a plate stiffens


def test_ring_load_acts_on_the_requested_circle(capsys: pytest.CaptureFixture, tmp_path: Path) -> None:
    summary, rows = trace(capsys, tmp_path, "load.kind=ring", "load.ring_radius=0.3", "shell.boundary=clamped",
                          "shell.N=80")
    s = summary
    assert s["load"] == "ring" and s["ring_node_radius"] == pytest.approx(0.3, abs=1e-12)
    assert {"F", "w", "w_pole", "stable_force", "stable_displacement"} <= set(rows[0])
    assert s["F_max"] is not None and s["n_limit_points_in_F"] >= 1


def test_tabulated_circle_is_the_spherical_cap(capsys: pytest.CaptureFixture, tmp_path: Path) -> None:
    """The same clamped cap given as a table of 40 points and analytically: the same snap pressure (the spline of
    a circle through 40 points is the circle to about 1e-9)."""
    phi = 1.2
    t = np.linspace(phi, math.pi / 2, 40)
    table = tmp_path / "cap.csv"
    np.savetxt(table, np.c_[np.cos(t), np.sin(t)], delimiter=",", header="r,z", comments="")
    common = ["load.kind=pressure", "load.control=force", "shell.boundary=clamped", "shell.h=0.005", "shell.N=80",
              "shell.pole_ratio=1"]
    sphere, _ = trace(capsys, tmp_path / "sphere", *common, f"shell.phi_hat={phi}")
    tabled, _ = trace(capsys, tmp_path / "table", *common, "shell.geometry=table", f"shell.table={table}")
    p_sphere = sphere["p_snap"]  # the pressure itself: p_c is normalised by each geometry's own length scale
    assert p_sphere is not None
    assert tabled["p_snap"] == pytest.approx(p_sphere, rel=1e-6)  # measured 2e-9


def test_a_dimple_knocks_the_snap_pressure_down(capsys: pytest.CaptureFixture, tmp_path: Path) -> None:
    common = ["load.kind=pressure", "load.control=force", "shell.boundary=clamped", "shell.N=80"]
    perfect, _ = trace(capsys, tmp_path / "perfect", *common)
    dimpled, _ = trace(capsys, tmp_path / "dimpled", *common, "imperfection.kind=dimple",
                       "imperfection.delta_over_h=0.5")
    p0, p1 = perfect["p_snap_over_p_c"], dimpled["p_snap_over_p_c"]
    assert p1 < 0.8 * p0
    assert dimpled["imperfection"]["kind"] == "dimple"


@pytest.mark.parametrize("geometry", ["cone", "ellipse", "torus"])
def test_other_geometries_trace_under_pressure(capsys: pytest.CaptureFixture, tmp_path: Path, geometry: str) -> None:
    summary, rows = trace(capsys, tmp_path, f"shell.geometry={geometry}", "load.kind=pressure", "load.control=force",
                          "shell.boundary=clamped", "shell.h=0.02", "shell.N=100", "load.p_end_over_p_c=0.3")
    s = summary
    assert s["geometry"] == geometry and s["H"] > 0 and s["p_c"] > 0
    assert {"p", "p_over_p_c", "w", "w_over_h"} <= set(rows[0])


def test_mode_imperfection_has_the_requested_amplitude() -> None:
    scene = load_scene(SHELL_SCHEMA, None, ["load.kind=pressure", "shell.boundary=clamped", "shell.N=60",
                                            "imperfection.kind=mode", "imperfection.delta_over_h=0.3"])
    perfect = scene_meridian(scene, perfect=True)
    imperfect = scene_meridian(scene)
    nr, nz = perfect.normals()
    normal = (imperfect.r - perfect.r) * nr + (imperfect.z - perfect.z) * nz
    assert np.min(normal) == pytest.approx(-0.3 * scene["shell"]["h"], rel=1e-9)  # inwards by delta
    assert imperfect.r[-1] == 0.0 and imperfect.z[0] == perfect.z[0]


@pytest.mark.parametrize("sets, needle", [
    (["shell.boundary=free"], "a free edge leaves the shell unsupported"),
    (["load.kind=ring", "load.ring_radius=0.9"], "load.ring_radius < the edge's radius"),
    (["imperfection.kind=dimple"], "imperfection.delta_over_h != 0"),
    (["shell.geometry=torus", "shell.knuckle=0.9"], "0 < shell.knuckle < shell.a < shell.R"),
    (["shell.geometry=table", "shell.table=/nonexistent.csv"], "a buildable shape"),
    (["load.kind=sphere", "shell.geometry=cone"], "the log-barrier contact is built on the paper's"),
])
def test_scenes_that_cannot_be_built_are_refused(capsys: pytest.CaptureFixture, tmp_path: Path, sets: list[str],
                                                  needle: str) -> None:
    args = ["trace", "-q", "--out", str(tmp_path / "out")]
    for s in sets:
        args += ["--set", s]
    code, out, err = run_cli(capsys, *args)
    assert code == 2 and out == ""
    assert err.startswith("contin: error:") and err.count("\n") == 1 and needle in err, err


def test_classify_is_the_papers_cap_only(capsys: pytest.CaptureFixture) -> None:
    code, _, err = run_cli(capsys, "classify", "-q", "--set", "shell.geometry=cone")
    assert code == 2 and "the classes are the paper's" in err


@pytest.mark.parametrize("sets, closed_form", [
    # Reissner's point stiffness of a sphere, 16 sqrt(3 (1 - nu^2)) D / (h R), far from the support
    (["shell.boundary=pinned", "shell.R=1", "shell.h=0.02", "shell.nu=0.5"],
     lambda D, s: 16 * math.sqrt(3 * (1 - 0.5**2)) * D / (0.02 * 1.0)),
    # Timoshenko's clamped plate, 16 pi D / a^2
    (["shell.geometry=plate", "shell.boundary=clamped", "shell.nu=0.3"],
     lambda D, s: 16 * math.pi * D / s["shell"]["a"] ** 2),
])
def test_rest_stiffness_is_the_linear_shells(sets: list[str], closed_form) -> None:
    from contin_models.shell_scene.build import length_unit, rest_stiffness, revolution_problem

    scene = load_scene(SHELL_SCHEMA, None, sets + ["load.control=force"])
    problem = revolution_problem(scene)
    assert rest_stiffness(problem, length_unit(scene)) == pytest.approx(closed_form(problem.D, scene), rel=1e-3)


def test_force_control_traces_the_displacement_path_through_every_fold(capsys: pytest.CaptureFixture,
                                                                       tmp_path: Path) -> None:
    """A clamped cap under a ring force winds through 16 folds and then stiffens steeply (F R/(2 pi D)
    up to 1e4 at the end of travel); with the load weighed by the rest stiffness, force control
    follows the same path (before: max_steps after 3000 steps, F R/(2 pi D) = 410)."""
    sets = ["load.kind=ring", "shell.boundary=clamped"]
    by_travel, _ = trace(capsys, tmp_path / "w", *sets)
    by_force, rows = trace(capsys, tmp_path / "F", *sets, "load.control=force")
    assert by_force["status"] == "ok" and len(rows) < 1000
    points = [(p["F"], p["w"]) for p in by_force["special_points"]]
    reference = [(p["F"], p["w"]) for p in by_travel["special_points"]]
    assert len(points) == len(reference) == 16
    for F, w in points:
        nearest = min(reference, key=lambda q: abs(q[0] - F) / max(abs(F), 1.0) + abs(q[1] - w))
        assert nearest == pytest.approx((F, w), rel=1e-7, abs=1e-8)
