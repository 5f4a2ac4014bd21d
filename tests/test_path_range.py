"""The point scene's displacement path stays within the scene: from the unloaded pole's height, w = 0, to eversion.

A thin deep cap on a coarse mesh (``shell.phi_hat=0.4193 shell.h=5.13e-3 shell.N=80``) winds for some
36000 steps and passes a point where the Morse index changes by more than the determinant's sign shows.
Before the index was watched, the path turned back there, retraced its own way to the unloaded cap and
went on, with nothing to stop it, into the pole pulled upwards (w = -7473 after 200000 steps); once that
was bounded, the scene ended "back at w = 0" with a warning, reported as a success.  It now passes the
point and ends at the end of its travel.  ``data/deep_cap_n80_way_back.npz`` is a state of the old path
on its way back (a maximum of F at w = 0.829, with the direction it went through it), saved from that
run: a path that does come back must still end at the unloaded pole's height.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from contin.app import cli
from contin.app.restart import Start
from contin.app.scene import load_scene
from contin_models.shell_scene import SHELL_SCHEMA
from contin_models.shell_scene.point import LOWEST_W, came_back, path_complete, run_point

SCENE = ["shell.phi_hat=0.4193", "shell.h=5.13e-3", "shell.N=80", "load.control=displacement"]
WAY_BACK = Path(__file__).parent / "data" / "deep_cap_n80_way_back.npz"


def test_a_path_coming_back_ends_at_the_unloaded_pole_height():
    saved = np.load(WAY_BACK)
    start = Start(u=saved["u"], p=float(saved["p"]), du=saved["du"], dp=float(saved["dp"]), name="way back",
                  kind="fold", saved_scene={"load": {"control": "displacement"}})
    result = run_point(load_scene(SHELL_SCHEMA, None, SCENE), start=start)
    path = result.branches[0]
    assert path.status == "bound" and came_back(path) and not path_complete(path)
    assert path.p[-1] == pytest.approx(LOWEST_W, abs=1e-12) and path.p.min() >= LOWEST_W - 1e-12
    assert len(path.p) < 500  # it went straight down, no step budget spent
    assert any("came back to the unloaded pole's height" in w for w in result.summary["warnings"])
    path.p[-1] = 3e-19  # where the whole scene's path located its bound: still back at w = 0, not at eversion
    assert came_back(path) and not path_complete(path)


@pytest.mark.slow
def test_the_coarse_deep_cap_ends(tmp_path):
    """The whole scene (some 45000 steps): it reaches the end of its travel, not the unloaded cap again."""
    code = cli.main(["trace", "-q", "--out", str(tmp_path), *[a for s in SCENE for a in ("--set", s)]])
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert code == 0 and summary["status"] == "ok" and summary["complete"]
    assert summary["w_end"] >= summary["eversion_w"]
    assert not any("came back to the unloaded pole's height" in w for w in summary["warnings"])


def test_a_ring_near_the_edge_of_a_deep_cap_is_sized_by_its_own_eversion(tmp_path) -> None:
    """A ring's circle is everted at its mirror image in the edge's plane, far short of the pole's ``2 H``.

    Sized by the pole's travel, the path of a ring at 0.82 of the edge's radius folded back at the
    ring's eversion and ran on into the ring pulled up (``w`` = -31 R after 3000 steps).  The
    travel is now the closed form ``2 (sqrt(R^2 - r^2) - R sin phi_hat)`` of the ring node's radius
    ``r``, and the path ends once the ring is everted (within ``RING_EVERSION_FRACTION`` of it).
    """
    from contin_models.shell_scene.build import RING_EVERSION_FRACTION

    import json
    import math

    from contin.app.cli import main

    phi_hat = 0.34514270096738314
    code = main(["trace", "-q", "--set", "output.figure=false", "--out", str(tmp_path),
                 "--set", f"shell.phi_hat={phi_hat}", "--set", "shell.h=0.012394", "--set", "shell.nu=-0.0576",
                 "--set", "shell.N=62", "--set", "load.kind=ring", "--set", "load.ring_radius=0.77521"])
    summary = json.loads((tmp_path / "summary.json").read_text())
    r = summary["ring_node_radius"]
    assert summary["travel"] == pytest.approx(2.0 * (math.sqrt(1.0 - r * r) - math.sin(phi_hat)), rel=1e-12)
    assert summary["w_end"] == pytest.approx(RING_EVERSION_FRACTION * summary["travel"], rel=1e-12)
    assert code == 0 and summary["status"] == "ok", summary["message"]
    assert summary["n_steps"] < 3000 and "stopped at p_max" in summary["message"]  # w prescribed: its bound
