"""``contin trace`` with a sphere or plate indenter (issue 4): the snap and the jump, both controls."""

from __future__ import annotations

import contextlib
import csv
import io
import json
from pathlib import Path

import pytest

import contin
from contin.app.cli import main
from contin_models.contact import Sphere
from contin_models.contact.indentation import ShellIndentation
from contin_models.shell_scene.contact import SNAP_FORCE_NORM


def _trace(out: Path, *sets: str) -> tuple[int, dict, list[dict]]:
    args = ["trace", "-q", "--out", str(out), "--set", "shell.N=60", "--set", "output.figure=false"]
    for s in sets:
        args += ["--set", s]
    with contextlib.redirect_stdout(io.StringIO()):
        code = main(args)
    summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else {}
    rows = list(csv.DictReader(open(out / "branch.csv"))) if (out / "branch.csv").exists() else []
    return code, summary, rows


@pytest.fixture(scope="module")
def sphere_runs(tmp_path_factory) -> dict[float, tuple[int, dict, list[dict]]]:
    return {r: _trace(tmp_path_factory.mktemp(f"r{r}"), "load.kind=sphere", f"load.radius={r}") for r in (0.5, 0.9)}


def test_sphere_trace_snaps_and_jumps_to_the_everted_state(sphere_runs):
    code, summary, rows = sphere_runs[0.5]
    assert code == 0 and summary["status"] == "ok"
    # the snap against an independent continuation of the same problem to its fold in w_b
    P = ShellIndentation(N=60, indenter=Sphere(0.5))
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, stop_at=("fold",), p_max=0.7)
    (fold,) = [s for s in br.special_points if s.kind == "fold"]
    assert summary["w_b_c"] == pytest.approx(fold.p, rel=1e-7)
    snaps = [r for r in summary["special_points"] if r["kind"] in ("fold", "event")]
    assert snaps[0]["parameter"] == "w_b" and snaps[0]["F_norm"] <= 1.000001 * SNAP_FORCE_NORM and snaps[0]["Delta_H"] == 0.0
    (jump,) = summary["jumps"]
    assert jump["success"]
    landing = [r for r in summary["special_points"] if r.get("label") == "jump_to"][0]
    assert landing["w_b"] == pytest.approx(summary["w_b_c"], rel=1e-12)  # stated at the snap's travel
    assert landing["n_contact"] == 0 and landing["Delta_H"] > 0.1 and landing["w_s"] > 0.5
    for col in ("w", "F", "w_over_R", "F_norm", "w_s", "Delta_H", "kappa_p_R", "n_contact", "stable_force",
                "stable_displacement", "n_negative"):
        assert col in rows[0]


def test_large_sphere_detaches_before_the_snap_with_the_same_pole_shape(sphere_runs):
    # paper figures 6-8: above the transition the pole leaves the indenter before the snap, the snap
    # comes earlier in w_b, and the shape at the snap (pole displacement, pole curvature) is universal
    _, small, _ = sphere_runs[0.5]
    code, large, _ = sphere_runs[0.9]
    assert code == 0
    assert large["Delta_H_at_snap"] > 0.005 and small["Delta_H_at_snap"] == 0.0
    assert large["w_b_c"] < small["w_b_c"] - 0.005
    assert large["kappa_p_R_at_snap"] == pytest.approx(small["kappa_p_R_at_snap"], rel=0.01)
    assert large["w_s_at_snap_over_R"] == pytest.approx(small["w_s_at_snap_over_R"], rel=0.01)
    # contact modes (gap beyond dhat): the small sphere keeps the pole, the large one loses it
    assert small["contact_mode"] == "continuous" and large["contact_mode"] == "detach"
    snap = [r for r in large["special_points"] if r["kind"] in ("fold", "event")][0]
    assert 0 < snap["contact_first"] <= snap["contact_last"] < 59  # a ring off the pole (N = 60)


def test_force_control_of_an_indenter_snaps_at_the_limit_load(tmp_path):
    code, summary, rows = _trace(tmp_path, "load.kind=sphere", "load.control=force")
    assert code == 0 and summary["status"] == "ok" and summary["control"] == "force", summary.get("message")
    # reference: the maximum of the force along the displacement-controlled path, located as an
    # extremum event by an independent continuation of the displacement problem
    P = ShellIndentation(N=60, indenter=Sphere(0.5))
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=0.4,
                             events=[contin.extremum("F", "max")], stability=False)
    (fmax,) = br.events("max(F)")
    assert summary["F_snap"] == pytest.approx(fmax.observables["F"], rel=1e-8)
    assert summary["w_b_at_snap"] == pytest.approx(fmax.p, abs=1e-6)
    # the shell everts under the load and the indenter follows it down, still in contact
    (jump,) = summary["jumps"]
    landing = [r for r in summary["special_points"] if r.get("label") == "jump_to"][0]
    assert jump["success"] and landing["parameter"] == "F" and landing["n_contact"] > 0
    assert summary["w_b_after_snap"] > summary["w_b_at_snap"] + 0.2
    assert summary["snaps"][0]["nodes_in_contact_after"] > 0
    # the snap list gives the travel where the shell snapped, not the load (the parameter under force control)
    assert summary["snaps"][0]["w_b"] == summary["w_b_at_snap"] and summary["snaps"][0]["F"] == summary["F_snap"]
    # loading goes on until the indenter reaches the end of its travel or the base ring
    assert float(rows[-1]["F"]) > summary["F_snap"] and float(rows[-1]["w"]) > summary["w_b_after_snap"]
