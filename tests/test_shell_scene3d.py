"""The shell's 3-D view as a scene (``view.kind = "3d"``): its keys, its runs against the axisymmetric view's,
its outputs."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import contin
from contin.app import cli
from contin.app.scene import load_scene
from contin_models.shell_scene import SHELL_SCHEMA, build
from contin_models.shell_scene.view3d import draw_surfaces, run_view3d, surface_shapes, view_problem

#: A coarse cap that the mesh rule accepts, in the D3 class with one harmonic (waves 0 and 3): seconds per run.
SMALL = ["shell.N=30", "view.harmonics=1"]


def scene3d(*keys: str) -> dict:
    return load_scene(SHELL_SCHEMA, None, ["view.kind=3d", *SMALL, *keys])


def run_cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


BAD_VIEWS = [
    (["view.symmetry=D1"], ["view.symmetry", "D1", "n >= 2"]),
    (["view.symmetry=C3"], ["view.symmetry", "C3"]),
    (["view.angles=10"], ["view.angles", "need view.angles >= 12 and a multiple of 6"]),
    (["view.angles=15"], ["view.angles", "multiple of 6"]),
    (["load.kind=pressure", "load.control=displacement"], ["view.kind", "load.control", "axisymmetric view"]),
    (["load.kind=plate", "load.control=force"], ["view.kind", "load.kind", "displacement"]),
    (["stability.harmonics=true"], ["stability.harmonics", "Bloch"]),
    (["view.symmetry=none", "load.pole_held=true"], ["load.pole_held", "frictionless"]),
    (["imperfection.kind=mode", "imperfection.delta_over_h=0.1", "imperfection.waves=2"],
     ["imperfection.waves", "breaks the declared symmetry"]),
    (["imperfection.kind=mode", "imperfection.delta_over_h=0.1", "imperfection.waves=6"],
     ["imperfection.waves", "up to K n"]),
    (["view.kind=axisymmetric", "imperfection.kind=mode", "imperfection.delta_over_h=0.1", "imperfection.waves=3"],
     ["imperfection.waves", "only the 3-D view"]),
]


@pytest.mark.parametrize("keys, needles", BAD_VIEWS)
def test_a_view_that_cannot_be_traced_is_refused_with_one_paragraph(tmp_path, capsys, keys, needles):
    out = tmp_path / "out"
    args = [a for k in ["view.kind=3d", "view.harmonics=1", *keys] for a in ("--set", k)]
    code, _, stderr = run_cli(capsys, "trace", *args, "--out", str(out))
    assert code == 2 and stderr.startswith("contin: error:") and stderr.count("\n") == 1
    assert "Traceback" not in stderr
    for needle in needles:
        assert needle in stderr
    assert not out.exists() or not any(out.iterdir())


def test_classify_and_restart_refuse_the_3d_view(tmp_path, capsys):
    code, _, stderr = run_cli(capsys, "classify", "--set", "view.kind=3d")
    assert code == 2 and 'view.kind = "axisymmetric"' in stderr


def test_the_axisymmetric_path_of_the_3d_view_is_the_traced_models():
    """On the perfect cap the D3 states stay axisymmetric: the limit load is the axisymmetric view's to rounding,
    and its first symmetry-breaking bifurcation is where the harmonic blocks put their first (n = 1 or 2)."""
    keys = ["continuation.max_steps=20"]
    result = run_view3d(scene3d(*keys))
    axi_scene = load_scene(SHELL_SCHEMA, None, [*SMALL[:1], *keys, "stability.harmonics=true", "stability.n_max=4"])
    axi = build(axi_scene)
    br = contin.continuation(axi.problem, axi.u0, axi.p0, axi.settings, p_max=axi.w_end,
                             events=[contin.extremum("F", "max", folds="F", stability_label="force")])
    F_max = next(s for s in br.special_points if s.kind == "event")
    assert result.summary["F_max"] == pytest.approx(F_max.observables["F"], rel=1e-9)
    assert result.summary["w_at_F_max"] == pytest.approx(F_max.p, rel=1e-8)
    first = result.summary["first_instability"]
    assert first["kind"] == "bifurcation" and first["representation"] == "E1"   # waves 1, 2, 4
    harmonic = [s for s in br.special_points if s.kind == "bifurcation" and s.info["key"] in (1, 2, 4)]
    assert harmonic and first["p"] == pytest.approx(harmonic[0].p, rel=1e-7)


def test_branch_csv_counts_the_morse_index_per_representation(tmp_path, capsys):
    out = tmp_path / "out"
    code, stdout, _ = run_cli(capsys, "trace", "--set", "view.kind=3d", *[a for k in SMALL for a in ("--set", k)],
                              "--set", "continuation.max_steps=25", "--out", str(out))
    assert code == 1 and "incomplete" in stdout and "max_steps" in stdout  # cut short on purpose, and said so
    with open(out / "branch.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    total = np.array([int(r["n_negative"]) for r in rows])
    per = {name: np.array([int(r[f"n_negative_{name}"]) for r in rows]) for name in ("A1", "A2", "E1")}
    assert np.array_equal(per["A1"] + per["A2"] + per["E1"], total) and total.max() > 0
    assert np.all(per["E1"] % 2 == 0)  # a two-dimensional representation: both copies counted
    summary = json.loads((out / "summary.json").read_text())
    names = [r["name"] for r in summary["view"]["representations"]]
    assert names == ["A1", "A2", "E1"] and summary["view"]["waves"] == [0, 3]
    assert {r["representation"] for r in summary["special_points"] if r["kind"] == "bifurcation"} <= {"A2", "E1"}
    shapes = np.load(out / "shapes.npz")
    assert shapes["state_x"].shape == (len(summary["special_points"]) + 1, 30, 97)
    assert (out / "shapes.png").stat().st_size > 0


#: The default cap's units: the force 2 pi D / R (D = E h^3 / (12 (1 - nu^2))), the classical pressure, R.
F_UNIT, P_UNIT, W_UNIT = 2 * np.pi * 1e6 * 0.02**3 / 9.0, 2e6 * 0.02**2 / 1.5, 1.0


@pytest.mark.parametrize("keys, load, unit", [(["load.kind=ring", "load.ring_radius=0.3"], "F", F_UNIT),
                                              (["load.kind=pressure", "load.control=force"], "p", P_UNIT),
                                              (["load.kind=sphere", "load.radius=0.5"], "F", F_UNIT),
                                              (["load.kind=point", "load.control=force"], "w", W_UNIT)])
def test_every_load_of_the_3d_view_is_the_axisymmetric_views_on_the_way_up(keys, load, unit):
    """A few steps in the 3-D view, then the axisymmetric view's problem solved at the same parameter: the
    same state (its load or deflection to 1e-8, or 1e-10 of the scene's unit where it is still near zero)."""
    scene = scene3d(*keys, "continuation.max_steps=6")
    vb = view_problem(scene)
    br = contin.continuation(vb.problem, vb.u0, vb.p0, vb.settings)
    axi = vb.axisymmetric
    ref = contin.continuation(axi.problem, axi.u0, axi.p0, axi.settings, p_max=float(br.p[-1]),
                              max_steps=200)
    assert ref.status == "bound" and ref.p[-1] == pytest.approx(br.p[-1], rel=1e-12)
    assert br.observables[load][-1] == pytest.approx(ref.observables[load][-1], rel=1e-8, abs=1e-10 * unit)


def test_a_surface_that_is_not_axisymmetric_is_drawn_in_colour_and_an_axisymmetric_one_in_grey():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    vb = view_problem(scene3d("continuation.max_steps=3"))
    br = contin.continuation(vb.problem, vb.u0, vb.p0, vb.settings)
    shapes = surface_shapes(vb.problem, br)
    assert list(shapes["state_kind"]) == ["end"]
    panels = []
    for amplitude in (0.0, 1e-3):
        drawn = {k: v.copy() for k, v in shapes.items()}
        drawn["state_z"][-1] += amplitude * np.cos(3 * drawn["theta"])[None, :]
        fig = plt.figure()
        draw_surfaces(fig, drawn, 1.0, 0.02, "w")
        panels.append(len(fig.axes))  # the surface, and a colour bar when there is colour
        plt.close(fig)
    assert panels == [1, 2]


@pytest.mark.slow
def test_a_mode_of_n_waves_is_the_stress_free_shape():
    """``imperfection.waves = 3``: the reference is the perfect cap's plus its three-wave mode at the first
    bifurcation into three waves, of largest normal displacement delta; the traced class carries it."""
    from contin_models.shell.fourier import FourierShell
    from contin_models.shell.imperfection3d import meridian_normals

    delta_over_h = 0.1
    vb = view_problem(scene3d("imperfection.kind=mode", f"imperfection.delta_over_h={delta_over_h}",
                              "imperfection.waves=3"))
    view, st = vb.problem.view, vb.problem.structure
    perfect = FourierShell(st, vb.problem.basis).reference_state()
    imperfect = vb.problem.c_ref
    assert np.array_equal(imperfect, view.reference_state())
    b, m = vb.problem.basis, view.m
    waves = imperfect - perfect
    assert np.max(np.abs(np.delete(waves, view.dofs_of_wave(3)))) == 0.0  # three waves, nothing else
    nr, nz = meridian_normals(st)
    normal = waves[b.index("R", "cos", 3)::m] * nr + waves[b.index("Z", "cos", 3)::m] * nz
    assert np.max(np.abs(normal)) == pytest.approx(delta_over_h * 0.02, rel=1e-12)
    assert np.linalg.norm(vb.problem.residual(vb.u0, 0.0)) < 1e-8  # at rest in its own shape
