"""``python -m studies.indenter_size`` (paper figures 6-8), run end to end in its default (fast) mode.

The study's numbers are checked against runs made here through other entry points
(:func:`studies.bench_contact.run_to_snap` with :func:`studies.bench_contact.snap_settings`, the point
scene's ``w_c_one_sided``), against the paper's statements (docs/model.md#what-the-paper-reports: ``w_b^c`` flat below
``r_c`` and decreasing above, ``r_c/R`` near 0.8-0.9, the contact modes, one pole curvature at the snap)
and, for the resting-sphere helper, against closed forms.

The default run checks a small run of the study (``small``: :data:`SMALL_RADII`, one bisection round
between them, then stopped by :data:`SMALL_TOL`): the same code from the contact runs to the figures,
on two radii, one on each side of the transition.  The study's whole fast mode (``fast``: seven radii,
``r_c`` to 0.025; about 20 s) runs under ``-m slow``, with the statements that need its seven radii.
"""

from __future__ import annotations

import csv
import functools
import json
import math

import numpy as np
import pytest

from contin.app.scene import load_scene
from contin_models.shell.problem import ShellPointLoad
from contin_models.shell_scene import SHELL_SCENE, SHELL_SCHEMA
from studies import indenter_size
from studies.bench_contact import run_to_snap, snap_settings
from tests.figure_check import assert_figure

FIGURES = ("fig6_snap_vs_radius", "fig7_snap_configurations", "fig8_pole_curvature")
#: The small run: the smallest sphere (continuous contact) and one past the transition (detached).
SMALL_RADII = (0.1, 0.9)
#: Its bisection stops after one round (at r/R = 0.5), with the bracket [0.5, 0.9].
SMALL_TOL = 0.4


def _run_study(out, radii: tuple[float, ...], tol: float) -> dict:
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(indenter_size, "RADII_FAST", radii)
        mp.setattr(indenter_size, "TOL_FAST", tol)
        assert indenter_size.main(["--out", str(out), "--quiet"]) == 0
    return json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def small_study(tmp_path_factory) -> tuple:
    out = tmp_path_factory.mktemp("indenter_size_small")
    return out, _run_study(out, SMALL_RADII, SMALL_TOL), SMALL_RADII, SMALL_TOL


@pytest.fixture(scope="module")
def fast_study(tmp_path_factory) -> tuple:
    out = tmp_path_factory.mktemp("indenter_size")
    return out, _run_study(out, indenter_size.RADII_FAST, indenter_size.TOL_FAST), indenter_size.RADII_FAST, \
        indenter_size.TOL_FAST


# the study's run takes seconds: behind ``slow`` (the default test run's time)
@pytest.fixture(scope="module", params=[pytest.param("small", marks=pytest.mark.slow),
                                        pytest.param("fast", marks=pytest.mark.slow)])
def study(request) -> tuple:
    """The study's outputs, its summary, its radii and the resolution of its ``r_c`` bisection."""
    return request.getfixturevalue(f"{request.param}_study")


@functools.lru_cache(maxsize=None)
def _snap(r: float) -> tuple:
    P, st, w_end = snap_settings(r, 200, stability=False)
    br, sp = run_to_snap(P, st, w_end)
    assert sp is not None and sp.kind == "fold", (r, br.message)
    return P, br, sp


def test_writes_figures_tables_and_summary(study):
    out, S, radii, _ = study
    for stem in FIGURES:
        for ext in ("png", "pdf"):
            f = out / f"{stem}.{ext}"
            assert f.is_file() and f.stat().st_size > 1000, f
        assert_figure(out, stem)
    assert isinstance(S["r_c_over_R"], float)
    assert S["mode"] == "fast" and S["scene"]["N"] == 200
    required = {"r_over_R", "w_b_c_over_R", "Delta_H_over_R", "contact_mode"}
    for c in S["cases"]:
        assert required <= set(c), c
        assert c["contact_mode"] in ("continuous", "detach-recontact", "detach")
    assert [c["r_over_R"] for c in S["cases"]] == pytest.approx(sorted(radii))
    radii = [c["r_over_R"] for c in S["cases"]]
    with open(out / "cases.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["r_over_R"]) for r in rows] == radii
    assert [float(r["w_b_c_over_R"]) for r in rows] == [c["w_b_c_over_R"] for c in S["cases"]]
    with open(out / "paths.csv", newline="") as fh:
        paths = list(csv.DictReader(fh))
    assert {float(r["r_over_R"]) for r in paths} == {0.0, *radii}  # every case's path and the point load's
    assert (out / "bisection.csv").is_file()


@pytest.mark.slow
def test_small_run_bisects_once(small_study):
    """The small run's bisection: one round, at the bracket's midpoint, in this process's table."""
    out, S, _, _ = small_study
    assert S["r_c_bracket"] == pytest.approx([0.5, 0.9]) and S["r_c_runs"] == 1
    with open(out / "bisection.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["r_over_R"]) for r in rows] == pytest.approx([0.1, 0.5, 0.9])
    assert [r["contact_mode"] for r in rows] == ["continuous", "continuous", "detach"]


def test_snap_of_a_case_equals_a_separate_contact_run(study):
    """r/R = 0.9 (detached at the snap): the study's numbers against a run made here."""
    _, S, _, _ = study
    case = next(c for c in S["cases"] if c["r_over_R"] == pytest.approx(0.9))
    P, br, sp = _snap(0.9)
    assert case["w_b_c_over_R"] == pytest.approx(sp.p / P.R, rel=1e-9)
    assert case["Delta_H_over_R"] == pytest.approx(sp.observables["Delta_H"] / P.R, rel=1e-7)
    assert case["kappa_p_R_at_snap"] == pytest.approx(sp.observables["kappa_p_R"], rel=1e-7)
    # the mode read off that run: the pole is detached beyond the barrier's range at the snap
    assert sp.observables["Delta_H"] > P.dhat and case["contact_mode"] == "detach"


def test_transition_bracket_holds_in_separate_runs(study):
    """Independent runs at the ends of the reported r_c bracket fall on either side of the gap tolerance."""
    _, S, _, width = study
    lo, hi = S["r_c_bracket"]
    assert lo < S["r_c_over_R"] < hi and hi - lo <= width + 1e-12
    tol = S["r_c_gap_tol_over_R"]
    P, _, sp_lo = _snap(lo)
    assert 0.0 < tol <= 0.01 * P.dhat / P.R  # tied to the barrier range, well below it
    assert sp_lo.observables["Delta_H"] / P.R <= tol
    _, _, sp_hi = _snap(hi)
    assert sp_hi.observables["Delta_H"] / P.R > tol


def test_paper_statements(study):
    """docs/model.md#what-the-paper-reports (paper figures 6-8): the transition, the modes, one pole curvature."""
    _, S, _, _ = study
    cases = S["cases"]
    # (the bracket's ends are on either side: the small run's radii are its ends)
    below = [c for c in cases if c["r_over_R"] <= S["r_c_bracket"][0]]
    above = [c for c in cases if c["r_over_R"] >= S["r_c_bracket"][1]]
    assert below and above
    w_below = [c["w_b_c_over_R"] for c in below]
    assert max(w_below) - min(w_below) < 1e-6  # constant below r_c
    assert all(c["Delta_H_over_R"] == 0.0 for c in below)
    w_above = [c["w_b_c_over_R"] for c in above]
    assert all(b < a for a, b in zip(w_above, w_above[1:])) and w_above[0] < min(w_below) - 1e-3
    gaps = [c["Delta_H_over_R"] for c in above]
    assert all(g > 1e-3 for g in gaps) and all(b > a for a, b in zip(gaps, gaps[1:]))
    modes = {c["r_over_R"]: c["contact_mode"] for c in cases}
    for r, m in modes.items():
        if r <= 0.5:
            assert m == "continuous", (r, m)
        elif r >= 0.9:
            assert m == "detach", (r, m)
    # with the strict criterion (any gap) no sphere below the transition counts as "detach" either
    assert all(c["contact_mode_strict"] != "detach" for c in cases if c["r_over_R"] <= 0.7)
    # every snap was located: a fold in w_b (by the engine, or the release fold beyond F -> 0) at a
    # vanishing force (these runs are also tests/test_contact_paper.py's radii sweep, under -m slow)
    for c in cases:
        # (1e-4 as tests/test_contact_paper.py: a fold the engine locates on the cell barrier keeps
        # F R/(2 pi D) ~ 2.5e-5 of the barrier's force at its last contact point)
        assert c["snap_label"] in ("", "release") and 0 < c["F_norm_at_snap"] < 1e-4, c
    kap = [c["kappa_p_R_at_snap"] for c in cases]
    assert max(kap) - min(kap) < 1e-3 * abs(np.mean(kap))


@pytest.mark.slow
def test_paper_statements_on_the_seven_radii(fast_study):
    """What needs the fast mode's seven radii: r_c near 0.8-0.9, three radii either side, the middle mode."""
    _, S, _, _ = fast_study
    assert 0.7 < S["r_c_over_R"] < 0.9  # "near 0.8-0.9"; the radii 0.7 and 0.9 straddle it
    below = [c for c in S["cases"] if c["r_over_R"] < S["r_c_bracket"][0]]
    above = [c for c in S["cases"] if c["r_over_R"] > S["r_c_bracket"][1]]
    assert len(below) >= 3 and len(above) >= 3
    modes = {c["r_over_R"]: c["contact_mode"] for c in S["cases"]}
    assert modes[0.7] == "detach-recontact"


def test_universal_snap_state_is_the_point_scene_one_sided_snap(study):
    """Every snap is the free shell at F = 0: its pole travel is the point scene's w_c_one_sided."""
    _, S, _, _ = study
    scene = load_scene(SHELL_SCHEMA, None, [])
    w_c = SHELL_SCENE.runner(scene, False).summary["w_c_one_sided"]
    assert S["free_snap_state"]["w_s_over_R"] == pytest.approx(w_c, rel=1e-9)
    for c in S["cases"]:
        assert c["w_s_over_R"] == pytest.approx(w_c, abs=1e-7), c
        assert c["shape_deviation_over_R"] < 1e-6
        # the sphere lowered onto the free snap shape (the meridian as the barrier sees it) gives the gap
        # and the snap travel
        assert c["Delta_H_over_R"] == pytest.approx(c["Delta_H_predicted_over_R"], abs=5e-6)
        # (the travel counts from the first touch of the barrier's curve, which crosses the axis a
        # quarter of the pole node's height above its neighbour: below the node on the convex cap,
        # above it once the pole has inverted, O(h^2) in all)
        cap = ShellPointLoad(N=S["scene"]["N"]).cap.x
        assert c["w_b_c_over_R"] == pytest.approx(w_c - c["Delta_H_over_R"], abs=3 * (cap[-1] - cap[-3]) / 4)


def test_resting_sphere_closed_forms():
    # the pole at z = 0 and one node at (a, b): a sphere through both has radius (a^2 + b^2) / (2 b)
    a, b = 0.4, 0.1
    r = np.array([a, 0.0])
    z = np.array([b, 0.0])
    rc = (a * a + b * b) / (2 * b)
    small = indenter_size.resting_sphere(r, z, 0.9 * rc)
    assert small["gap"] == 0.0 and small["node"] == 1 and small["centre"] == pytest.approx(0.9 * rc)
    big = indenter_size.resting_sphere(r, z, 1.5 * rc)
    R_ = 1.5 * rc
    assert big["node"] == 0
    assert big["gap"] == pytest.approx(b + math.sqrt(R_ * R_ - a * a) - R_, rel=1e-12)
    # a node outside the sphere's radius never carries it
    far = indenter_size.resting_sphere(np.array([2.0, 0.0]), np.array([5.0, 0.0]), 1.0)
    assert far["gap"] == 0.0 and far["node"] == 1
