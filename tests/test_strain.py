"""The largest membrane strain of a run, and the warning beyond the material law's range."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import contin
from contin.app.scene import load_scene
from contin.results.branch import Branch
from contin_models.shell.problem import ShellPointLoad
from contin_models.shell_scene import SHELL_SCENE, eversion_displacement
from contin_models.shell.strain import STRAIN_LIMIT, StrainPeak, strain_peak, strain_warning


def _branch(states: list[np.ndarray], loads: list[float]) -> Branch:
    m = len(states)
    return Branch(p=np.array(loads, dtype=float), u=np.array(states), s=np.arange(m, dtype=float),
                  tangent_p=np.ones(m), residual=np.zeros(m), newton_iterations=np.zeros(m, dtype=int),
                  observables={"w": np.array(loads, dtype=float)})


def test_dilations_give_their_own_strain_as_the_peak() -> None:
    # x -> (1 + e) x strains every edge by exactly e in both directions (docs/model.md#checks)
    P = ShellPointLoad(N=40)
    x0 = P.cap.x.copy()
    identity = SimpleNamespace(shell=P.shell, full_state=lambda u, p: u)
    states = [x0, (1 + 0.05) * x0, (1 - 0.3) * x0, (1 + 0.2) * x0]
    peak = strain_peak(identity, [_branch(states, [0.0, 1.0, 2.0, 3.0])], "w")
    assert peak is not None
    assert peak.value == pytest.approx(0.3, rel=1e-12)
    assert peak.load == 2.0
    assert peak.n_edges == 39


def test_the_peak_is_located_on_the_edge_that_carries_it() -> None:
    P = ShellPointLoad(N=40)
    x = P.cap.x.copy()
    x[-4] *= 1.5  # the node next to the pole moves out: its two edges stretch, the pole edge most in r
    identity = SimpleNamespace(shell=P.shell, full_state=lambda u, p: u)
    peak = strain_peak(identity, [_branch([x], [0.7])], "w")
    eps11, eps22 = P.shell.strains(x)
    assert peak.value == pytest.approx(max(np.abs(eps11).max(), np.abs(eps22).max()))
    assert peak.where == "pole"
    assert StrainPeak(0.2, 0.0, 0, 39).where == "base"
    assert StrainPeak(0.2, 0.0, 20, 39).where == "interior"


def test_a_non_finite_strain_is_refused() -> None:
    P = ShellPointLoad(N=20)
    x = P.cap.x.copy()
    x[10] = np.nan
    identity = SimpleNamespace(shell=P.shell, full_state=lambda u, p: u)
    with pytest.raises(FloatingPointError, match="non-finite"):
        strain_peak(identity, [_branch([x], [0.0])], "w")


def test_no_branch_point_gives_no_peak_and_no_warning() -> None:
    P = ShellPointLoad(N=20)
    assert strain_peak(P, [], "w") is None
    assert strain_warning(None, 1.0, point_load=True) == ""


def test_the_warning_names_the_strain_the_place_and_for_a_point_load_the_remedy() -> None:
    assert strain_warning(StrainPeak(STRAIN_LIMIT, 0.3, 38, 39), 1.0, point_load=True) == ""
    pole = strain_warning(StrainPeak(0.35, 0.3, 38, 39), 2.0, point_load=True)
    assert "0.35" in pole and "pole" in pole and "w/R = 0.15" in pole and "sphere" in pole
    inside = strain_warning(StrainPeak(0.35, 0.3, 20, 39), 1.0, point_load=True)
    assert "edge 20 of 39" in inside and "sphere" not in inside
    contact = strain_warning(StrainPeak(0.35, 0.3, 38, 39), 1.0, point_load=False, load_label="w_b")
    assert "w_b/R" in contact and "singular" not in contact


def _fixed_w_state(h: float, N: int, fraction: float) -> tuple[ShellPointLoad, np.ndarray]:
    P = ShellPointLoad(h=h, N=N, phi_hat=0.8)
    w = fraction * eversion_displacement(1.0, 0.8)
    st = contin.Settings(ds=w / 50, ds_max=w / 50, tol=1e-10, max_steps=500, stability=False)
    br = contin.continuation(P, P.reference_unknowns(), 0.0, st, p_max=w)
    assert br.status == "bound" and br.p[-1] == pytest.approx(w)
    return P, P.full_state(br.u[-1], br.p[-1]).copy()


def test_under_a_point_load_the_pole_strain_grows_with_N_while_the_strain_off_the_axis_converges() -> None:
    # the claim behind the warning's advice (models/shell/strain.py): h/R = 0.15 at half the eversion travel
    pole, off_axis = [], []
    for N in (100, 200, 400, 800):
        P, x = _fixed_w_state(0.15, N, 0.5)
        eps11, eps22 = P.shell.strains(x)
        pole.append(eps22[-1])
        off_axis.append(float(np.interp(0.03, P.cap.edge_radius[::-1], eps22[::-1])))
    assert all(b > a * 1.15 for a, b in zip(pole, pole[1:])), pole
    changes = np.abs(np.diff(off_axis))
    assert changes[-1] < 0.02 * abs(off_axis[-1]), off_axis
    assert changes[-1] < changes[0], off_axis


def test_the_scene_reports_the_peak_and_warns_only_beyond_the_limit() -> None:
    thin = SHELL_SCENE.runner(load_scene(SHELL_SCENE.schema, None, ["shell.N=60", "output.figure=false"]), False)
    assert thin.summary["max_strain"] < STRAIN_LIMIT and thin.summary["warnings"] == []
    assert "warning" not in thin.message
    thick = SHELL_SCENE.runner(load_scene(SHELL_SCENE.schema, None,
                                          ["shell.N=60", "shell.h=0.2", "output.figure=false"]), False)
    assert thick.summary["max_strain"] > STRAIN_LIMIT and thick.summary["max_strain_at"] == "pole"
    assert len(thick.summary["warnings"]) == 1 and "warning: the membrane strain" in thick.message
    assert math.isfinite(thick.summary["w_at_max_strain_over_R"])


def test_the_pole_strain_study_writes_its_table(tmp_path) -> None:
    import csv

    from studies import pole_strain

    assert pole_strain.main(["--out", str(tmp_path), "--quiet"]) == 0
    with open(tmp_path / "pole_strain.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [int(r["N"]) for r in rows] == [100, 200, 400]
    strains = [float(r["pole_strain"]) for r in rows]
    assert strains[0] < strains[1] < strains[2]
    assert (tmp_path / "summary.json").exists()


@pytest.mark.slow
def test_a_path_that_is_lost_is_reported_not_recorded() -> None:
    from studies.pole_strain import stops

    # h/R = 0.2 at N = 1600 loses the path before 0.9 w_ev (docs/robustness.md)
    rows = stops(0.2, 1600, (0.25, 0.9))
    assert rows[0]["reached"] and not rows[1]["reached"]
    assert "pole_strain" not in rows[1] and rows[1]["message"]
