"""A special point whose location failed is reported at its bracket with the observables there."""

import numpy as np
import pytest

import contin
from contin.app.scene import load_scene
from contin.watch.testfunctions import EventTest
from contin_models.benchmarks.bratu import Bratu
from contin_models.shell_scene import SHELL_SCHEMA
from contin_models.shell_scene.point import run_point


def failing_location(self, seg, before, after):
    raise RuntimeError("location failed (made to fail by the test)")


def test_an_unlocated_event_carries_its_observables(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(EventTest, "locate", failing_location)
    pb = Bratu(50)
    br = contin.continuation(pb, np.zeros(50), 0.0, ds=0.1, ds_max=1.0, bounds={"max_u": (None, 3.0)},
                             events=[contin.crossing("max_u", 1.0)])
    (hit,) = br.events()
    assert not hit.located and "made to fail" in hit.info["error"]
    assert set(hit.observables) == set(pb.observables)
    # reported at the bracket's end, a stored point of the branch
    i = int(np.argmin(np.abs(br.p - hit.p)))
    assert hit.observables["max_u"] == pytest.approx(br.observables["max_u"][i], rel=1e-12)


def test_the_point_scene_classifies_a_path_whose_extrema_of_F_were_not_located(monkeypatch: pytest.MonkeyPatch):
    """An extremum of F left bracketed (its location failed) is still a record with F: no KeyError."""
    monkeypatch.setattr(EventTest, "locate", failing_location)
    scene = load_scene(SHELL_SCHEMA, None, ["shell.N=40", "shell.phi_hat=1.2"])
    result = run_point(scene)
    limits = [r for r in result.special_points if r.get("parameter") == "F" and r["kind"] == "fold"]
    assert limits and all(not r["located"] and np.isfinite(r["F"]) for r in limits)
    # this cap's force stays positive along its path (its located F_min R/(2 pi D) is 1.44)
    assert result.summary["classification"] == "monostable"
    assert result.summary["F_max"] == limits[0]["F"]
