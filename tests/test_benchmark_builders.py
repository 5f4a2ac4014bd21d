"""The benchmark scenes' public builders: scene -> problem, settings, start (as ``contin trace`` uses them)."""

from __future__ import annotations

import numpy as np

import contin
from contin.app.scene import load_scene
from contin_models.benchmarks.bratu import Bratu
from contin_models.benchmarks.scenes import BRATU_SCHEMA, TRUSS_SCHEMA, build_bratu, build_truss
from contin_models.benchmarks.truss import VonMisesTruss


def test_bratu_builder_gives_the_scene_s_problem_and_bounds() -> None:
    problem, st, u0, p0 = build_bratu(load_scene(BRATU_SCHEMA, None, ["model.n=20", "continuation.max_u=2"]))
    assert isinstance(problem, Bratu) and problem.n == 20 and u0.shape == (20,) and not u0.any() and p0 == 0.0
    assert st.bounds == {"max_u": (None, 2.0)}
    br = contin.continuation(problem, u0, p0, st)
    assert br.status == "bound" and len(br.folds()) == 1


def test_truss_builder_weights_the_arclength_by_the_truss_scales() -> None:
    problem, st, u0, p0 = build_truss(load_scene(TRUSS_SCHEMA, None, ["model.b=0.4"]))
    assert isinstance(problem, VonMisesTruss) and p0 == 0.0
    np.testing.assert_array_equal(u0, [0.0, 0.4])
    (_, p_max), _ = problem.limit_points()
    assert st.param_weight == 1.0 / p_max and st.state_weight == np.sqrt(2) / 0.4 and st.stability
