"""``python -m studies.force_displacement`` (paper figures 3 and 4), fast mode, end to end.

The study runs once (module fixture) into a temporary directory.  Its summary is then checked
against runs made here, independently of the study: the class and the force extrema of a case
against :func:`contin_models.shell_scene.classify_scene` on the scene with the default continuation steps
(the study uses finer steps), the snaps of the loading/unloading sweeps against the folds and force
extrema of that separate path, and the curves of ``fig3.csv`` against the definitions of the classes
(``docs/model.md#classes``) applied directly to the data.

The default run runs the study on the cases these checks name (``checked``: four base angles of
figure 3a, three thicknesses of figure 3b, both caps of figure 4); the whole fast mode (``fast``: the
eight and eight curves of figure 3) runs under ``-m slow``.
"""

from __future__ import annotations

import csv
import functools
import json
import math
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from contin.app.scene import load_scene
from contin_models.shell_scene import SHELL_SCHEMA, classify_scene
from studies import force_displacement as study
from tests.figure_check import assert_figure


#: Figure 3's cases by run: those checked against a separate classification below (the figure-4 caps,
#: 0.8 and 1.2, among them; each class in each sweep), and the fast mode's whole sweeps.
CASES = {"checked": ((0.8, 1.1, 1.2, 1.3), (0.03, 0.04, 0.07)), "fast": (study.PHI_3A, study.H_3B)}


# the study's run takes seconds: behind ``slow`` (the default test run's time)
@pytest.fixture(scope="module", params=[pytest.param("checked", marks=pytest.mark.slow),
                                        pytest.param("fast", marks=pytest.mark.slow)])
def result(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int, dict[str, Any], tuple]:
    out = tmp_path_factory.mktemp(f"force_displacement_{request.param}")
    phis, hs = CASES[request.param]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(study, "PHI_3A", phis)
        mp.setattr(study, "H_3B", hs)
        rc = study.main(["--out", str(out), "--quiet"])
    return out, rc, json.loads((out / "summary.json").read_text()), (phis, hs)


@functools.lru_cache(maxsize=None)
def _separate(phi_hat: float, h_over_R: float, N: int) -> Any:
    """An independent classification: the scene with only the cap and the mesh set (default steps)."""
    scene = load_scene(SHELL_SCHEMA, None, [f"shell.phi_hat={phi_hat}", f"shell.h={h_over_R}", f"shell.N={N}",
                                            "output.figure=false"])
    return classify_scene(scene)


def _case(summary: dict[str, Any], phi_hat: float, h_over_R: float) -> dict[str, Any]:
    for fig in ("fig3a", "fig3b"):
        for rec in summary[fig]["cases"]:
            if math.isclose(rec["phi_hat"], phi_hat) and math.isclose(rec["h_over_R"], h_over_R):
                return rec
    raise KeyError((phi_hat, h_over_R))


def _curves(path: Path) -> dict[tuple[str, str], dict[str, np.ndarray]]:
    cols: dict[tuple[str, str], dict[str, list]] = defaultdict(lambda: defaultdict(list))
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            c = cols[(row["figure"], row["case"])]
            c["class"].append(row["class"])
            for k in ("phi_hat", "w_over_R", "F_norm", "stable"):
                c[k].append(float(row[k]))
    return {key: {k: (np.array(v) if k != "class" else v) for k, v in c.items()} for key, c in cols.items()}


def test_writes_every_file_and_succeeds(result) -> None:
    out, rc, summary, (phis, hs) = result
    assert rc == 0
    for stem in ("fig3", "fig4"):
        assert_figure(out, stem, min_png_bytes=10_000)
        assert (out / f"{stem}.csv").stat().st_size > 1_000
    assert summary["mode"] == "fast" and summary["N"] == study.N_FAST
    assert summary["all_runs_ok"] is True
    assert [r["phi_hat"] for r in summary["fig3a"]["cases"]] == list(phis)
    assert [r["h_over_R"] for r in summary["fig3b"]["cases"]] == list(hs)


@pytest.mark.parametrize("phi_hat,h_over_R", [(0.8, 0.02), (1.1, 0.02), (1.2, 0.02), (1.3, 0.02),
                                              (1.0, 0.03), (1.0, 0.04), (1.0, 0.07)])
def test_class_and_extrema_agree_with_a_separate_classification(result, phi_hat, h_over_R) -> None:
    _, _, summary, _ = result
    rec = _case(summary, phi_hat, h_over_R)
    sep = _separate(phi_hat, h_over_R, summary["N"])
    assert sep.label is not None
    assert rec["classification"] == sep.label
    for key in ("F_max_norm", "F_min_norm"):
        if sep.values[key] is None:
            assert rec[key] is None
        else:  # located extrema: independent of the continuation steps up to the solver tolerance
            assert rec[key] == pytest.approx(sep.values[key], rel=1e-6, abs=1e-8)


def test_fig3_curves_satisfy_the_definition_of_their_class(result) -> None:
    out, _, summary, (phis, hs) = result
    curves = _curves(out / "fig3.csv")
    assert len(curves) == len(phis) + len(hs)
    for (fig, case), c in curves.items():
        cls = set(c["class"])
        assert len(cls) == 1, (fig, case)
        (cls,) = cls
        F, w, stable = c["F_norm"], c["w_over_R"], c["stable"].astype(bool)
        # every path runs from the reference state to 5 % past eversion, w = 2 R (1 - sin phi_hat)
        assert F[0] == pytest.approx(0.0, abs=1e-9) and w[0] == 0.0
        assert w[-1] == pytest.approx(1.05 * 2 * (1 - math.sin(c["phi_hat"][0])), rel=1e-9)
        if cls == "monotonous":
            assert np.all(np.diff(F) > 0) and np.all(np.diff(w) > 0) and stable.all(), case
        elif cls == "monostable":
            assert np.all(F[1:] > 0), case
            assert np.any(np.diff(F) < 0), case
        else:
            assert cls == "bistable"
            assert np.any((F < 0) & stable), case


def test_force_control_loop_snaps_at_the_path_extrema(result) -> None:
    _, _, summary, _ = result
    for phi in study.PHI_4:
        s = summary["fig4"][f"phi_hat={phi:g}"]
        sep = _separate(phi, study.H_4, summary["N"])
        f = s["force_control"]
        assert f["status"] and all(st == "completed" for st in f["status"])
        # loading snaps at the first maximum of F, unloading (pulling, for a bistable cap) at the last minimum
        assert f["snap_loading_F_norm"] == pytest.approx(sep.values["F_max_norm"], rel=1e-6)
        assert f["snap_unloading_F_norm"] == pytest.approx(sep.values["F_min_norm"], rel=1e-6)
        assert f["loop_width_F_norm"] == pytest.approx(sep.values["F_max_norm"] - sep.values["F_min_norm"], rel=1e-6)
        assert f["hysteresis"] is True and f["n_cycles"] == 1
        # the loop's area is the energy the two snaps release (the work done around a closed cycle)
        assert f["loop_area_norm"] > 0
        assert f["loop_area_norm"] == pytest.approx(f["energy_released_norm"], rel=2e-2)
        if sep.values["F_min"] < 0:  # bistable: the snap back needs a pull, and lands on a pulled-up cap
            (back,) = f["snaps"]["unloading"]
            assert back["F_norm_from"] < 0 and back["w_over_R_to"] < 0


def test_displacement_control_snaps_at_the_folds_in_w(result) -> None:
    _, _, summary, _ = result
    for phi in study.PHI_4:
        s = summary["fig4"][f"phi_hat={phi:g}"]
        sep = _separate(phi, study.H_4, summary["N"])
        folds = [r for r in sep.trace.special_points if r["kind"] == "fold" and r["parameter"] == "w"]
        d = s["displacement_control"]
        assert all(st == "completed" for st in d["status"])
        if not folds:  # single-valued in w: loading and unloading coincide
            assert d["hysteresis"] is False and d["n_cycles"] == 0
            assert d["snaps"] == {"loading": [], "unloading": []}
            continue
        # loading leaves the unbuckled branch at its first fold in w, unloading leaves the everted branch at
        # the path's last fold in w
        assert d["snap_loading_w_over_R"] == pytest.approx(folds[0]["w_over_R"], abs=1e-7)
        assert d["snap_unloading_w_over_R"] == pytest.approx(folds[-1]["w_over_R"], abs=1e-7)
        assert d["hysteresis"] is True and d["n_cycles"] == 1
        assert d["loop_area_norm"] == pytest.approx(d["energy_released_norm"], rel=2e-2)
    st = summary["statements"]["hysteresis_0.8_not_1.2"]
    assert st["displacement_control"]["phi_hat=0.8"] is True and st["displacement_control"]["phi_hat=1.2"] is False


def test_statements_follow_from_the_classes_in_the_summary(result) -> None:
    _, _, summary, _ = result
    st = summary["statements"]
    a = {r["phi_hat"]: r["classification"] for r in summary["fig3a"]["cases"]}
    expect_a = (all(c == "bistable" for p, c in a.items() if p < 1.1 - 1e-9)
                and all(c == "monostable" for p, c in a.items() if 1.1 + 1e-9 < p < 1.3 - 1e-9)
                and a[1.3] == "monotonous")
    assert st["h0.02_phi_sweep"]["reproduced"] is expect_a
    order = {"bistable": 0, "monostable": 1, "monotonous": 2}
    ranks = [order[r["classification"]] for r in summary["fig3b"]["cases"]]
    assert st["phi1.0_h_sweep"]["reproduced"] is (ranks == sorted(ranks) and set(ranks) == {0, 1, 2})
    # the interpolated boundary lies between the grid points it was interpolated from
    phi_b = st["h0.02_phi_sweep"]["bistable_monostable_boundary_phi_hat_estimate"]
    last_bi = max(p for p, c in a.items() if c == "bistable")
    assert last_bi < phi_b < min(p for p, c in a.items() if c == "monostable")
