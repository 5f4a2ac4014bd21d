"""Extreme scenes that used to fail: a short-range contact barrier and a thin cap's long path.

References are independent runs: the whole connected path traced with enough steps, and the
barrier's own distances.
"""

from __future__ import annotations

import numpy as np
import pytest

from contin.app.cli import load_model
from contin.app.scene import load_scene


def _scene(*overrides: str) -> dict:
    return load_scene(load_model("shell").schema, None, [*overrides, "output.figure=false"])


def test_short_range_barrier_snaps_and_completes() -> None:
    """dhat = 1e-5 R: the snap's jump must start inside the barrier's narrow domain (it raised before)."""
    scene = _scene("load.kind=sphere", "load.radius=0.5", "contact.dhat=1e-5", "shell.N=60")
    result = load_model("shell").run(scene, False)
    assert result.success, result.message
    assert len(result.jumps) >= 1
    from contin_models.shell_scene import contact_problem
    problem = contact_problem(scene)
    gaps = [float(np.min(problem.contact(u, float(p), hessian=False).distances))
            for br in result.branches for u, p in zip(br.u, br.p)]
    assert min(gaps) > 0.0


def test_everted_branch_decides_a_path_cut_short() -> None:
    """A path stopped by max_steps is still shown bistable from the everted branch, with the same F_min."""
    model = load_model("shell")
    whole = model.classify(_scene("shell.N=60"), False)
    assert whole.label == "bistable" and whole.values["path_complete"]
    cut = model.classify(_scene("shell.N=60", "continuation.max_steps=60"), False)
    assert not cut.values["path_complete"]
    assert cut.label == "bistable", cut.message
    assert cut.values["F_min"] == pytest.approx(whole.values["F_min"], rel=1e-8)
    assert cut.values["w_at_F_min"] == pytest.approx(whole.values["w_at_F_min"], rel=1e-8)
    assert cut.values["F_max"] == pytest.approx(whole.values["F_max"], rel=1e-8)
    assert "everted branch" in cut.trace.summary["classification_note"]


def test_monostable_cap_cut_short_stays_undecided() -> None:
    """The everted branch of a monostable cap carries no stable F < 0: the class stays undecided."""
    cut = load_model("shell").classify(_scene("shell.N=60", "shell.phi_hat=1.2", "continuation.max_steps=5"), False)
    assert cut.label is None
    assert not cut.success
