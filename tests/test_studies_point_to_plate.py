"""``python -m studies.point_to_plate`` (paper figure 12), fast mode, end to end.

The study runs once (module fixture) into a temporary directory.  Its point limit is checked against
the falling zero of F traced here directly on :class:`contin_models.shell.problem.ShellPointLoad` (no scene
code) and against the point scene's ``w_c_one_sided``; its finite indenters against what holds
without the paper: a small sphere touches the pole at the snap, so it snaps where the point does;
the pole sits where the indenter is plus the gap; and the bounds verdict in ``summary.json`` against
the numbers of ``fig12.csv``.

The default run runs the study with the smallest and the largest of its fast radii (``ends``: the one
that snaps where the point does, and the one farthest towards the plate); the whole fast mode
(``fast``: four radii) runs under ``-m slow``.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any

import pytest

import contin
from contin.app.scene import load_scene
from contin_models.shell.problem import ShellPointLoad
from contin_models.shell_scene import SHELL_SCENE, SHELL_SCHEMA
from studies import point_to_plate as study
from tests.figure_check import assert_figure


#: The sphere radii of each run.
RADII = {"ends": (min(study.RADII_FAST), max(study.RADII_FAST)), "fast": study.RADII_FAST}


# the study's run takes seconds: behind ``slow`` (the default test run's time)
@pytest.fixture(scope="module", params=[pytest.param("ends", marks=pytest.mark.slow),
                                        pytest.param("fast", marks=pytest.mark.slow)])
def result(request: pytest.FixtureRequest,
           tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int, dict[str, Any], list[dict[str, Any]], tuple]:
    out = tmp_path_factory.mktemp(f"point_to_plate_{request.param}")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(study, "RADII_FAST", RADII[request.param])
        rc = study.main(["--out", str(out), "--quiet"])
    with open(out / "fig12.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    return out, rc, json.loads((out / "summary.json").read_text()), rows, RADII[request.param]


def _num(row: dict[str, str], key: str) -> float:
    return float(row[key])


def test_writes_every_file(result) -> None:
    out, rc, summary, rows, radii = result
    assert rc == 0
    assert_figure(out, "fig12", min_png_bytes=10_000)
    assert summary["mode"] == "fast" and summary["N"] == study.N_FAST
    assert [r["indenter"] for r in rows] == ["point"] + ["sphere"] * len(radii) + ["plate"]
    assert [_num(r, "r_over_R") for r in rows[1:-1]] == list(radii)


def test_point_limit_is_the_first_falling_zero_of_the_point_force(result) -> None:
    _, _, summary, rows, _ = result
    N = summary["N"]
    # directly on the problem: displacement control from the reference state to the first F = 0 going down
    P = ShellPointLoad(R=1.0, phi_hat=study.PHI_HAT, h=study.H_OVER_R, N=N)
    st = contin.Settings(ds=0.005, ds_max=0.01, ds_min=1e-12, state_weight=1.0, param_weight=1.0, max_steps=2000,
                         stability=False)
    br = contin.continuation(P, P.reference_unknowns(), 0.0, st, p_max=1.0,
                             events=[contin.crossing("F", 0.0, direction=-1, terminal=True, name="F = 0")])
    assert br.status == "event", br.message
    zero = br.special_points[-1]
    assert zero.label == "F = 0" and zero.located
    # no fold in w before it (the one-sided point would otherwise snap there)
    assert not br.folds()
    point = rows[0]
    assert _num(point, "w_b_c_over_R") == pytest.approx(zero.p, abs=1e-9)
    assert _num(point, "w_s_over_R") == _num(point, "w_b_c_over_R") and _num(point, "Delta_H_over_R") == 0.0
    # and the point scene's own field
    scene = load_scene(SHELL_SCHEMA, None, [f"shell.phi_hat={study.PHI_HAT}", f"shell.h={study.H_OVER_R}",
                                            f"shell.N={N}", "output.figure=false"])
    w_c = SHELL_SCENE.runner(scene, False).summary["w_c_one_sided"]
    assert summary["point"]["w_b_c_over_R"] == pytest.approx(w_c, abs=1e-12)


def test_a_small_sphere_snaps_where_the_point_does(result) -> None:
    _, _, _, rows, radii = result
    point, small = rows[0], rows[1]
    assert _num(small, "r_over_R") == min(radii) <= 0.1
    # the pole touches the small sphere at the snap (no gap beyond the barrier range)
    assert _num(small, "Delta_H_over_R") == 0.0
    # so the indenter travel there is the point's, up to the barrier holding the pole a hair off the
    # sphere and the barrier's curve crossing the axis a quarter of the pole node's height above its
    # neighbour: below the node on the convex cap, above it once the pole has inverted (about twice
    # that offset in all, O(h^2); 1.2e-5 R at N = 60)
    assert _num(small, "w_b_c_over_R") == pytest.approx(_num(point, "w_b_c_over_R"), abs=3 * _pole_offset())


def _pole_offset() -> float:
    """``(z_pole - z_neighbour) / 4`` of the undeformed cap on the study's fast mesh, in units of R."""
    x = ShellPointLoad(phi_hat=study.PHI_HAT, h=study.H_OVER_R, N=study.N_FAST).cap.x
    return float(x[-1] - x[-3]) / 4.0


def test_pole_is_where_the_indenter_is_plus_the_gap(result) -> None:
    _, _, _, rows, _ = result
    for r in rows:
        # w_s = w_b + Delta H: the gap is measured from the pole to the indenter beyond the barrier range,
        # and w_b is counted from the first touch of that range
        # (up to the offset between the pole node and the barrier's curve, see above)
        assert _num(r, "w_s_over_R") == pytest.approx(_num(r, "w_b_c_over_R") + _num(r, "Delta_H_over_R"),
                                                      abs=3 * _pole_offset())
    plate = rows[-1]
    assert plate["indenter"] == "plate" and plate["r_over_R"] == ""  # infinite radius: empty cell
    assert _num(plate, "Delta_H_over_R") > 0.05  # the plate has lost the pole well before the snap


def test_bounds_verdict_matches_the_numbers(result) -> None:
    _, _, summary, rows, _ = result
    point, plate, spheres = rows[0], rows[-1], rows[1:-1]
    tol = summary["bounds"]["w_b_c_over_R"]["tol"]
    assert tol <= 1e-5  # well below the spread of w_b^c and Delta H over the radii (>= 1e-2)
    verdicts = {}
    for key in ("w_b_c_over_R", "w_s_over_R", "Delta_H_over_R"):
        lo, hi = sorted((_num(point, key), _num(plate, key)))
        inside = all(lo - tol <= _num(s, key) <= hi + tol for s in spheres)
        assert summary["bounds"][key]["bounded"] is inside, key
        verdicts[key] = inside
    assert summary["statement"]["reproduced"] is all(verdicts.values())
    # the non-trivial bounds: the point limit is the largest travel and the smallest gap, the plate the reverse
    assert _num(point, "w_b_c_over_R") > _num(plate, "w_b_c_over_R") + 0.1
    assert _num(point, "Delta_H_over_R") == 0.0 < _num(plate, "Delta_H_over_R")
    assert math.isclose(summary["bounds"]["w_b_c_over_R"]["point"], _num(point, "w_b_c_over_R"))
