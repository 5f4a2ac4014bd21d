"""Classification of the point-indented shell and its stability labels (acceptance points 4 and 5).

Point 4: at h/R = 0.02, phi_hat in {0.6, 0.8, 1.0} is bistable, 1.2 monostable, 1.35 monotonous; at
phi_hat = 1.0, h/R = 0.01 is bistable, 0.05 monostable, 0.09 monotonous -- each at two meshes.  The
cases 0.8, 1.2 and 1.35 at N = 60 are in ``test_shell_scene.py``; here are the others and the
refined meshes.  Besides the scene's own ``classification``, every case is checked against the
definitions (``docs/model.md#classes``) applied directly to the stored points of ``branch.csv``.

Point 5: the stability labels change exactly at located folds -- the displacement-control count of
negative eigenvalues only across a fold in w, the force-control count only across an extremum of F
(a fold in F), and by exactly one there.
"""

from __future__ import annotations

import copy
import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

import contin
from contin.app.cli import main
from contin_models.shell.problem import ShellPointLoad


_TRACES: dict[tuple[int, float, float], tuple[dict, dict[str, np.ndarray]]] = {}


def trace(tmp_path: Path, N: int, phi_hat: float, h: float = 0.02) -> tuple[dict, dict[str, np.ndarray]]:
    """Run the shell scene; return ``summary.json`` and the columns of ``branch.csv``.

    Several tests check the same scene (a class, then its labels): each scene is traced once per
    session and every caller gets its own copy of the result.
    """
    key = (N, float(phi_hat), float(h))
    if key not in _TRACES:
        _TRACES[key] = _trace(tmp_path, N, phi_hat, h)
    return copy.deepcopy(_TRACES[key])


def _trace(tmp_path: Path, N: int, phi_hat: float, h: float) -> tuple[dict, dict[str, np.ndarray]]:
    code = main(["trace", "--model", "shell", "-q", "--out", str(tmp_path), "--set", f"shell.N={N}",
                 "--set", f"shell.phi_hat={phi_hat}", "--set", f"shell.h={h}", "--set", "output.figure=false"])
    assert code == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    with open(tmp_path / "branch.csv") as fh:
        rows = list(csv.DictReader(fh))
    cols = {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}
    return summary, cols


def class_from_definitions(cols: dict[str, np.ndarray]) -> str:
    """The class from the stored points alone (docs/model.md#classes), without the located special points.

    monotonous: F increases with w along the whole path (which then never folds in w); bistable: some
    point stable under displacement control carries F < 0; monostable otherwise.
    """
    F, w = cols["F"], cols["w"]
    if np.all(np.diff(w) > 0) and np.all(np.diff(F) > 0):
        return "monotonous"
    stable = cols["stable_displacement"] == 1
    if np.any(stable & (F < -1e-8 * np.max(np.abs(F)))):
        return "bistable"
    return "monostable"


def check(summary: dict, cols: dict[str, np.ndarray], expected: str) -> None:
    assert summary["classification"] == expected
    assert class_from_definitions(cols) == expected
    if expected == "monotonous":
        assert summary["F_max"] is None and summary["n_folds_in_w"] == 0
    elif expected == "monostable":
        assert 0 < summary["F_min"] < summary["F_max"] and summary["w_at_F_max"] < summary["w_at_F_min"]
        assert np.all(cols["F"][1:] > 0)
    else:
        assert summary["F_min"] < 0 < summary["F_max"]


# ---------------------------------------------------------------------------------------------------
# acceptance point 4
# ---------------------------------------------------------------------------------------------------
FAST = [  # (phi_hat, h/R, expected): each trace takes well under a second at N = 60 and 120
    (1.0, 0.02, "bistable"), (1.0, 0.05, "monostable"), (1.0, 0.09, "monotonous"),
]


@pytest.mark.parametrize("N", [60, 120])
@pytest.mark.parametrize("phi_hat, h, expected", FAST)
def test_classification(tmp_path: Path, N: int, phi_hat: float, h: float, expected: str) -> None:
    check(*trace(tmp_path, N, phi_hat, h), expected)


@pytest.mark.parametrize("phi_hat, expected", [(1.2, "monostable"), (1.35, "monotonous")])
def test_classification_at_h_over_R_0_02_refined_mesh(tmp_path: Path, phi_hat: float, expected: str) -> None:
    check(*trace(tmp_path, 120, phi_hat), expected)


@pytest.mark.parametrize("N, phi_hat, h", [(60, 1.0, 0.01), (120, 1.0, 0.01), (120, 0.8, 0.02)])
def test_bistable_classification_winding_paths(tmp_path: Path, N: int, phi_hat: float, h: float) -> None:
    # thin or deep caps: the connected path winds through 8 folds in w before eversion (under 1 s each)
    check(*trace(tmp_path, N, phi_hat, h), "bistable")


@pytest.mark.parametrize("N", [60, 120])
def test_phi_0_6_classification_whole_path(tmp_path: Path, N: int) -> None:
    # the deepest cap: 14 folds in w on the connected path (about 1.3 s each)
    check(*trace(tmp_path, N, 0.6), "bistable")


@pytest.mark.parametrize("N", [60, 120])
def test_phi_0_6_bistable_quick(N: int) -> None:
    """phi_hat = 0.6 by a second route: the everted state is stable under displacement control and pulls.

    The scene traces the whole connected path, which at phi_hat = 0.6 winds through 14 folds in w
    (``test_phi_0_6_classification_whole_path``).  Bistability only needs the stable
    parts: load quasi-statically past eversion (one snap, from the unbuckled onto the everted
    branch) and unload; the everted branch, followed back until it snaps, carries F < 0 at stable
    states.  (The unbuckled branch does not: at this depth it folds in w while still pushing.)
    """
    pr = ShellPointLoad(phi_hat=0.6, h=0.02, N=N)
    w_ev = 2 * (1 - math.sin(0.6))
    st = contin.Settings(ds=w_ev / 20, ds_max=w_ev / 20, ds_min=1e-9 * w_ev / 20)
    load = contin.quasistatic(pr, pr.reference_unknowns(), 0.0, 1.05 * w_ev, st)
    unload = contin.quasistatic(pr, load.u_final, load.p_final, 0.0, st)
    assert load.status == unload.status == "completed"
    assert len(load.jumps) == len(unload.jumps) == 1
    unbuckled, everted = load.branches[0], unload.branches[0]
    assert np.all(unbuckled.observables["F"] > -1e-8 * unbuckled.observables["F"].max())
    assert np.all(everted.stable_under("displacement")[:-1])
    F = everted.observables["F"][:-1]
    assert F.min() < -0.5 * unbuckled.observables["F"].max()  # a pull comparable to the snap-through push


# ---------------------------------------------------------------------------------------------------
# acceptance point 5: labels change exactly at located folds
# ---------------------------------------------------------------------------------------------------
def check_labels_change_only_at_folds(summary: dict, cols: dict[str, np.ndarray]) -> tuple[int, int]:
    n_d = cols["n_negative"].astype(int)
    n_f = cols["n_negative_force"].astype(int)
    spts = summary["special_points"]
    w_folds = [r["index"] for r in spts if r["kind"] == "fold" and r["parameter"] == "w"]
    F_folds = [r["index"] for r in spts if r["kind"] == "fold" and r["parameter"] == "F"]
    for label, n, folds in (("displacement", n_d, w_folds), ("force", n_f, F_folds)):
        # at most one fold of each kind between two stored points (else the count could change by 0 or 2)
        assert len(set(folds)) == len(folds), (label, folds)
        changes = np.flatnonzero(np.diff(n) != 0)
        assert sorted(changes.tolist()) == sorted(folds), (label, changes, folds)
        assert np.all(np.abs(np.diff(n)[changes]) == 1), label
    return len(w_folds), len(F_folds)


def test_labels_change_exactly_at_folds_default_scene(tmp_path: Path) -> None:
    summary, cols = trace(tmp_path, 40, 0.8)
    n_w, n_F = check_labels_change_only_at_folds(summary, cols)
    assert (n_w, n_F) == (summary["n_folds_in_w"], summary["n_limit_points_in_F"])
    assert n_w > 0 and n_F > 0  # the default scene has both kinds: the check is not vacuous
    # the path starts and ends stable under both controls (unbuckled, everted)
    for key in ("n_negative", "n_negative_force"):
        assert cols[key][0] == 0 and cols[key][-1] == 0


@pytest.mark.parametrize("phi_hat, h", [(1.2, 0.02), (1.0, 0.02)])
def test_labels_change_exactly_at_folds_no_snap_back(tmp_path: Path, phi_hat: float, h: float) -> None:
    # single-valued in w: the displacement label never changes; the force label changes at F_max and F_min
    summary, cols = trace(tmp_path, 60, phi_hat, h)
    n_w, n_F = check_labels_change_only_at_folds(summary, cols)
    assert n_w == 0 and n_F == 2
    assert np.all(cols["n_negative"] == 0)
    assert sorted(set(cols["n_negative_force"].astype(int).tolist())) == [0, 1]


@pytest.mark.parametrize("N, phi_hat, h", [(60, 0.8, 0.02), (120, 0.8, 0.02), (60, 0.6, 0.02), (60, 1.0, 0.01)])
def test_labels_change_exactly_at_folds_long_paths(tmp_path: Path, N: int, phi_hat: float, h: float) -> None:
    summary, cols = trace(tmp_path, N, phi_hat, h)
    n_w, n_F = check_labels_change_only_at_folds(summary, cols)
    assert n_w > 0 and n_F > 0
